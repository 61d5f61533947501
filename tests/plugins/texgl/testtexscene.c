/*
 * Test plugin "testtexscene": the textured quads of texscene.h as a scene node, so that
 * the raster nodes can be tested on textures before (and apart from) the glTF loader.
 *
 *   test_tex_scene   -> scene (parameters layout, wrap)
 */
#include "lightgraph/lightgraph.h"

#include "texscene.h"

static const char *const tx_layouts[] = {
    "checker", "random", "wrap", "mip", "mask", "normal", NULL
};

static int tx_prepare(lg_node *n)
{
    tx_scene *t = tx_make(lg_param_enum(n, "layout"), (int)lg_param_int(n, "wrap"));
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &t->s.features, &t->s, tx_free);
}

static int tx_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const lg_param_desc tx_params[] = {
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = tx_layouts,
      .doc = "which textured quad (texscene.h)" },
    { .key = "wrap",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 2,
      .doc = "layout wrap: 0 repeat, 1 clamp to edge, 2 mirrored repeat" },
};
static const lg_port_desc tx_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_tex_scene",
    .doc = "A textured quad built in memory for the texture tests",
    LG_PARAMS(tx_params),
    LG_OUTPUTS(tx_out),
    .prepare = tx_prepare,
    .execute = tx_nothing,
} };

LG_PLUGIN_DEFINE("testtexscene", "1.0.0", "In-memory textured scenes for the texture tests", types)
