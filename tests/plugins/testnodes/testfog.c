/* Test plugin "testfog": nodes that need scene features, to test gating. If gating works,
 * a graph whose scene lacks a medium never loads this plugin at all.
 *
 *   test_fog         needs a medium and a light
 *   test_specular    needs a specular material
 *   test_reflective  needs a reflective material (lg_material.reflectivity), nothing else
 *   test_mirror      needs a reflective material and a probe, as `reflect` and `envmap` do
 *
 * Each writes `value` into every channel of an image the size of `image` or the render. */
#include <string.h>

#include "lightgraph/lightgraph.h"

static const lg_param_desc fog_params[] = {
    { .key = "value",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.5,
      .min = 0,
      .max = 1e6,
      .doc = "the value written to every channel" },
};
static const lg_port_desc fog_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" },
    { .name = "image", .kind = LG_KIND_IMAGE, .optional = true, .doc = "size reference" },
};
static const lg_port_desc fog_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int fog_prepare(lg_node *n)
{
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    const lg_resource *img = lg_input(n, 1);
    lg_resource_info info;
    if (img && lg_describe(img, &info, n) == 0) {
        d.width = info.image.width;
        d.height = info.image.height;
    } else {
        lg_render_size(n, &d.width, &d.height);
    }
    return lg_declare_image(n, 0, &d);
}

static int fog_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    lg_resource_info info;
    lg_describe(lg_output(n, 0), &info, n);
    float *p = v.pixels;
    float val = (float)lg_param_float(n, "value");
    for (size_t i = 0; i < (size_t)info.image.width * info.image.height; i++) {
        p[4 * i + 0] = p[4 * i + 1] = p[4 * i + 2] = val;
        p[4 * i + 3] = 1;
    }
    return 0;
}

static const lg_port_desc spec_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE },
    { .name = "image", .kind = LG_KIND_IMAGE },
};

static int spec_prepare(lg_node *n)
{
    return lg_declare_alias(n, 0, 1);
}

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_fog",
        .doc = "Needs a medium and a light; writes a constant image (test)",
        LG_PARAMS(fog_params),
        LG_INPUTS(fog_in),
        LG_OUTPUTS(fog_out),
        .needs = LG_NEEDS_MEDIUM | LG_NEEDS_LIGHT,
        .neutral = LG_NEUTRAL_ZERO,
        .prepare = fog_prepare,
        .execute = fog_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_specular",
        .doc = "Needs a specular material; passes its image through (test)",
        LG_INPUTS(spec_in),
        LG_OUTPUTS(fog_out),
        .needs = LG_NEEDS_SPECULAR,
        .neutral = LG_NEUTRAL_PASSTHROUGH,
        .neutral_input = 1,
        .prepare = spec_prepare,
        .execute = fog_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_reflective",
        .doc = "Needs a reflective material; writes a constant image (test)",
        LG_PARAMS(fog_params),
        LG_INPUTS(fog_in),
        LG_OUTPUTS(fog_out),
        .needs = LG_NEEDS_REFLECTIVE,
        .neutral = LG_NEUTRAL_ZERO,
        .prepare = fog_prepare,
        .execute = fog_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_mirror",
        .doc = "Needs a reflective material and a light probe, like reflect; writes a constant "
               "image (test)",
        LG_PARAMS(fog_params),
        LG_INPUTS(fog_in),
        LG_OUTPUTS(fog_out),
        .needs = LG_NEEDS_REFLECTIVE | LG_NEEDS_PROBE,
        .neutral = LG_NEUTRAL_ZERO,
        .prepare = fog_prepare,
        .execute = fog_execute,
    },
};

LG_PLUGIN_DEFINE("testfog", "1.0.0", "Gated nodes for planner tests", types)
