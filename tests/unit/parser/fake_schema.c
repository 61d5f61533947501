#include "fake_schema.h"

#include <string.h>

static const lg_param_desc image_params[] = {
    { .key = "file", .type = LG_PARAM_PATH, .def.s = "", .doc = "image file" },
};
static const lg_port_desc out_image[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static const char *const mode_values[] = { "rgb", "luminance", NULL };
static const char *const backend_values[] = { "cpu", "gl", "cl", NULL };
static const char *const exposure_old[] = { "gain", NULL };
static const lg_param_desc reinhard_params[] = {
    { .key = "key",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.18,
      .min = 0.001,
      .max = 100,
      .doc = "middle grey" },
    { .key = "white",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 1e6,
      .doc = "burn-out luminance" },
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.s = "luminance",
      .enum_values = mode_values,
      .doc = "per channel or on luminance" },
    { .key = "backend",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = backend_values,
      .doc = "where it runs" },
    { .key = "exposure",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -20,
      .max = 20,
      .renamed_from = exposure_old,
      .doc = "stops" },
};
static const lg_port_desc in_image[] = { { .name = "image", .kind = LG_KIND_IMAGE } };

static const lg_port_desc add_inputs[] = {
    { .name = "a", .kind = LG_KIND_IMAGE },
    { .name = "b", .kind = LG_KIND_IMAGE },
};

static const lg_port_desc out_scene[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc in_scene[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc gbuffer_outputs[] = {
    { .name = "color", .kind = LG_KIND_IMAGE },
    { .name = "depth", .kind = LG_KIND_IMAGE },
};

static const lg_param_desc blur_params[] = {
    { .key = "radius", .type = LG_PARAM_INT, .def.i = 4, .min = 0, .max = 64 },
    { .key = "offset", .type = LG_PARAM_VEC2, .min = -10, .max = 10 },
    { .key = "tint", .type = LG_PARAM_COLOR, .def.v = { 1, 1, 1 }, .min = 0, .max = 1 },
    { .key = "grid", .type = LG_PARAM_INT3, .def.i3 = { 8, 8, 8 }, .min = 1, .max = 512 },
    { .key = "enabled", .type = LG_PARAM_BOOL, .def.b = true },
    { .key = "label", .type = LG_PARAM_STRING, .def.s = "blur" },
};
static const lg_port_desc blur_inputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE },
    { .name = "mask", .kind = LG_KIND_ANY, .optional = true },
};
static const lg_port_desc sink_inputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE, .optional = true },
};

/* An image made at a size its parameters give (core's constant): check refuses sizes over
 * the schema's pixel limit. */
static const lg_param_desc solid_params[] = {
    { .key = "w",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1 << 20,
      .role = LG_ROLE_IMAGE_WIDTH },
    { .key = "h",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1 << 20,
      .role = LG_ROLE_IMAGE_HEIGHT },
};

/* Colours that also take keywords (ABI 2.3): `albedo = material | [r, g, b]` defaulting
 * to the keyword, `tint` to a colour. */
static const char *const albedo_words[] = { "material", "vertex", NULL };
static const lg_param_desc bake_params[] = {
    { .key = "albedo",
      .type = LG_PARAM_COLOR,
      .def.e = 1,
      .enum_values = albedo_words,
      .min = 0,
      .max = 1,
      .doc = "material | vertex | [r, g, b]" },
    { .key = "tint",
      .type = LG_PARAM_COLOR,
      .def = { .e = -1, .v = { 0.25, 0.5, 1 } },
      .enum_values = albedo_words,
      .min = 0,
      .max = 1 },
};

static const lg_node_type types[] = {
    { .struct_size = sizeof(lg_node_type),
      .name = "image",
      LG_PARAMS(image_params),
      LG_OUTPUTS(out_image) },
    { .struct_size = sizeof(lg_node_type),
      .name = "reinhard",
      LG_PARAMS(reinhard_params),
      LG_INPUTS(in_image),
      LG_OUTPUTS(out_image) },
    { .struct_size = sizeof(lg_node_type),
      .name = "add",
      LG_INPUTS(add_inputs),
      LG_OUTPUTS(out_image) },
    { .struct_size = sizeof(lg_node_type),
      .name = "scene",
      LG_PARAMS(image_params),
      LG_OUTPUTS(out_scene) },
    { .struct_size = sizeof(lg_node_type),
      .name = "gbuffer",
      LG_INPUTS(in_scene),
      LG_OUTPUTS(gbuffer_outputs) },
    { .struct_size = sizeof(lg_node_type),
      .name = "blur",
      LG_PARAMS(blur_params),
      LG_INPUTS(blur_inputs),
      LG_OUTPUTS(out_image) },
    { .struct_size = sizeof(lg_node_type), .name = "sink", LG_INPUTS(sink_inputs) },
    { .struct_size = sizeof(lg_node_type),
      .name = "solid",
      LG_PARAMS(solid_params),
      LG_OUTPUTS(out_image) },
    { .struct_size = sizeof(lg_node_type),
      .name = "bake",
      LG_PARAMS(bake_params),
      LG_OUTPUTS(out_image) },
};
#define N_TYPES (sizeof types / sizeof types[0])

static const char *const type_names[] = { "image", "reinhard", "add",   "scene", "gbuffer",
                                          "blur",  "sink",     "solid", "bake" };

static const lg_node_type *lookup(void *ctx, const char *name)
{
    (void)ctx;
    for (size_t i = 0; i < N_TYPES; i++)
        if (strcmp(types[i].name, name) == 0)
            return &types[i];
    return NULL;
}

static const lg_schema schema = {
    .lookup = lookup,
    .n_names = N_TYPES,
    .names = type_names,
    .max_pixels = 1u << 27, /* LG_IMAGE_MAX_PIXELS_DEFAULT */
};

const lg_schema *lg_fake_schema(void)
{
    return &schema;
}
