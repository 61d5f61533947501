/* Deliberately broken plugins: each variant (chosen by -DBROKEN_*) must be refused by the
 * host with a message naming the file and the problem, never loaded and never crash it. */
#include <stddef.h>

#include "lightgraph/lightgraph.h"

static int execute(lg_node *n, const lg_frame *f)
{
    (void)n;
    (void)f;
    return 0;
}

#ifdef BROKEN_BAD_KEYWORD
static const char *const keywords[] = { "material", NULL };
#endif

static const lg_param_desc params[] = {
#ifdef BROKEN_BAD_DEFAULT
    { .key = "x", .type = LG_PARAM_FLOAT, .def.f = 5, .min = 0, .max = 1, .doc = "out of range" },
#elif defined(BROKEN_BAD_KEYWORD)
    /* a colour with keywords (ABI 2.3) whose default index names no keyword */
    { .key = "x",
      .type = LG_PARAM_COLOR,
      .def.e = 2,
      .enum_values = keywords,
      .min = 0,
      .max = 1,
      .doc = "default keyword 2 of 1" },
#elif defined(BROKEN_OUTPUT_DEFAULT)
    /* an output file (ABI 2.7) with a default: it would be written on every render */
    { .key = "x",
      .type = LG_PARAM_PATH,
      .def.s = "dump.ply",
      .role = LG_ROLE_OUTPUT_FILE,
      .doc = "an output file that is not \"\" by default" },
#else
    { .key = "x", .type = LG_PARAM_FLOAT, .def.f = 0.5, .min = 0, .max = 1, .doc = "fine" },
#endif
};

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = BROKEN_TYPE_NAME,
    .doc = "a node in a broken plugin",
    LG_PARAMS(params),
    .execute = execute,
} };

#ifndef BROKEN_NO_ENTRY
static const lg_plugin_desc desc = {
#ifdef BROKEN_SHORT_STRUCT
    .struct_size = 8,
#else
    .struct_size = sizeof(lg_plugin_desc),
#endif
#ifdef BROKEN_MAJOR
    .abi_major = LG_ABI_MAJOR + 1,
#elif defined(BROKEN_ABI1)
    .abi_major = 1, /* a plugin built against the ABI 1 SDK */
#else
    .abi_major = LG_ABI_MAJOR,
#endif
#ifdef BROKEN_MINOR
    .abi_minor = LG_ABI_MINOR + 1,
#elif defined(BROKEN_ABI1)
    .abi_minor = 1,
#else
    .abi_minor = LG_ABI_MINOR,
#endif
#ifdef BROKEN_NO_NAME
    .name = NULL,
#else
    .name = BROKEN_PLUGIN_NAME,
#endif
    .version = "0.0.1",
    .doc = "a broken plugin (test)",
    .types = types,
    .n_types = 1,
};

LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void);
LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void)
{
#ifdef BROKEN_CRASH
    volatile int *p = NULL;
    *p = 1; /* a plugin that crashes while being scanned */
#endif
    return &desc;
}
#else
/* exports something, but not the entry symbol */
LG_PLUGIN_EXPORT const lg_node_type *not_a_plugin(void);
LG_PLUGIN_EXPORT const lg_node_type *not_a_plugin(void)
{
    return types;
}
#endif
