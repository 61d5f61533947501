/* Plugins that attack the scanner rather than break its rules: each must be refused within
 * a bounded time and a bounded read, and the other plugins must still work.
 *
 *   -DHOSTILE_BLOCK: a constructor that never returns (the scan must time out);
 *   -DHOSTILE_HUGE:  a descriptor of 8 node types each documented by 1 MiB of text, 8 MiB
 *                    serialised (each string is cut at 1 MiB; the whole result is capped).
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

#ifdef HOSTILE_HUGE
#define N_TYPES 8
#else
#define N_TYPES 1
#endif
static const char *const names[8] = {
    HOSTILE_TYPE_NAME "0", HOSTILE_TYPE_NAME "1", HOSTILE_TYPE_NAME "2", HOSTILE_TYPE_NAME "3",
    HOSTILE_TYPE_NAME "4", HOSTILE_TYPE_NAME "5", HOSTILE_TYPE_NAME "6", HOSTILE_TYPE_NAME "7",
};
static lg_node_type types[N_TYPES];

static lg_plugin_desc desc = {
    .struct_size = sizeof(lg_plugin_desc),
    .abi_major = LG_ABI_MAJOR,
    .abi_minor = LG_ABI_MINOR,
    .name = HOSTILE_PLUGIN_NAME,
    .version = "0.0.1",
    .doc = "a hostile plugin (test)",
    .types = types,
    .n_types = N_TYPES,
};

LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void);
LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void)
{
    const char *doc = "a node in a hostile plugin";
#ifdef HOSTILE_HUGE
    /* made at run time, so the .so stays small */
    size_t n = (size_t)1 << 20;
    char *big = malloc(n + 1);
    if (big) {
        memset(big, 'a', n);
        big[n] = 0;
        doc = big;
    }
#endif
    for (int i = 0; i < N_TYPES; i++) {
        types[i].struct_size = sizeof(lg_node_type);
        types[i].name = names[i];
        types[i].doc = doc;
        types[i].execute = execute;
    }
    return &desc;
}
