/* Test plugins for unique names (host/exec/names.h, tests/unit/host/test_names.py): one source,
 * built once per variant into a folder of its own, so that each test puts exactly the
 * plugins it needs on LIGHTGRAPH_PLUGIN_PATH.
 *
 *   dup_a/lg_names_dup.so    plugin names_dup, type names_dup_a
 *   dup_b/lg_names_dup.so    plugin names_dup (the same name), type names_dup_b
 *   other/lg_names_other.so  plugin names_other, types names_other and names_dup_a (the
 *                            type of dup_a)
 *   scale/lg_names_scale.so  plugin names_scale, types names_scale_ok and scale (core's)
 *   twice/lg_names_twice.so  plugin names_twice, type names_twice declared twice
 *
 * Each node passes its image through (an alias); its one parameter is `gain`, so that a
 * graph that sets core's `scale.factor` fails on this `scale` and works on core's. */
#include "lightgraph/lightgraph.h"

static const lg_param_desc params[] = {
    { .key = "gain",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 100,
      .doc = "does nothing" },
};
static const lg_port_desc in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int prepare(lg_node *n)
{
    return lg_declare_alias(n, 0, 0);
}

static int execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

#define TYPE(name_)                                                                                \
    {                                                                                              \
        .struct_size = sizeof(lg_node_type), .name = (name_),                                      \
        .doc = "Its input, unchanged (a names test plugin)", LG_PARAMS(params), LG_INPUTS(in),     \
        LG_OUTPUTS(out), .prepare = prepare, .execute = execute,                                   \
    }

static const lg_node_type types[] = {
#if defined(NAMES_DUP_A)
    TYPE("names_dup_a"),
#elif defined(NAMES_DUP_B)
    TYPE("names_dup_b"),
#elif defined(NAMES_OTHER)
    TYPE("names_other"),
    TYPE("names_dup_a"),
#elif defined(NAMES_SCALE)
    TYPE("names_scale_ok"),
    TYPE("scale"),
#elif defined(NAMES_TWICE)
    TYPE("names_twice"),
    TYPE("names_twice"),
#else
#error "a variant: -DNAMES_DUP_A, ..."
#endif
};

LG_PLUGIN_DEFINE(NAMES_PLUGIN, "1.0.0", "A names test plugin", types)
