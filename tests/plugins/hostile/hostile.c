/* Plugins that attack the scanner rather than break its rules: each must be refused within
 * a bounded time and a bounded read, and the other plugins must still work.
 *
 *   -DHOSTILE_BLOCK: a constructor that never returns (the scan must time out);
 *   -DHOSTILE_HUGE:  a descriptor whose documentation is 8 MiB (the scan result is capped).
 *
 * Built into their own directory, which no other test puts on LIGHTGRAPH_PLUGIN_PATH. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lightgraph/lightgraph.h"

#ifdef HOSTILE_BLOCK
__attribute__((constructor)) static void never_returns(void)
{
    for (;;)
        pause();
}
#endif

static int execute(lg_node *n, const lg_frame *f)
{
    (void)n;
    (void)f;
    return 0;
}

static lg_node_type types[] = {{
    .struct_size = sizeof(lg_node_type),
    .name = HOSTILE_TYPE_NAME,
    .doc = "a node in a hostile plugin",
    .execute = execute,
}};

static lg_plugin_desc desc = {
    .struct_size = sizeof(lg_plugin_desc),
    .abi_major = LG_ABI_MAJOR,
    .abi_minor = LG_ABI_MINOR,
    .name = HOSTILE_PLUGIN_NAME,
    .version = "0.0.1",
    .doc = "a hostile plugin (test)",
    .types = types,
    .n_types = 1,
};

LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void);
LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void)
{
#ifdef HOSTILE_HUGE
    /* made at run time, so the .so stays small */
    size_t n = (size_t)8 << 20;
    char *doc = malloc(n + 1);
    if (doc) {
        memset(doc, 'a', n);
        doc[n] = 0;
        types[0].doc = doc;
    }
#endif
    return &desc;
}
