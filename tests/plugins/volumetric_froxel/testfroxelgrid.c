/*
 * Test plugin "testfroxelgrid": a froxel volume's grid as an image, so that a graph can
 * write it to a file (output statements write images only) and a test can read it back
 * (tests/plugins/volumetric_froxel/test_froxel_gl.c).
 *
 *   froxel_grid_image  froxel -> out: rgba32f, W x (H D); cell (i, j, k) of the grid at
 *                      pixel (i, k H + j): slice 0 on top, each slice H rows. Read on the
 *                      CPU (lg_map_cpu: the host moves a GL or CL grid there). The grid's
 *                      size is given as parameters (prepare cannot see it) and checked
 *                      against the info part: a mismatch is an error naming both.
 */
#include <string.h>

#include "lightgraph/froxel.h"
#include "lightgraph/lightgraph.h"

static const lg_param_desc fg_params[] = {
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 1,
      .max = 4096,
      .doc = "the grid's width W" },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 1,
      .max = 4096,
      .doc = "the grid's height H" },
    { .key = "depth",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 1,
      .max = 4096,
      .doc = "the grid's depth D" },
};
static const lg_port_desc fg_in[] = { { .name = "froxel", .kind = LG_KIND_FROXEL } };
static const lg_port_desc fg_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int fg_prepare(lg_node *n)
{
    uint64_t w = (uint64_t)lg_param_int(n, "width"), h = (uint64_t)lg_param_int(n, "height"),
             d = (uint64_t)lg_param_int(n, "depth");
    if (h * d > 65536)
        return lg_error(n, "height x depth = %llu: more rows than an image may have",
                        (unsigned long long)(h * d));
    lg_image_desc desc = { .width = (uint32_t)w,
                           .height = (uint32_t)(h * d),
                           .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &desc);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int fg_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_froxel fv;
    const lg_froxel *fx = lg_froxel_get(n, lg_input(n, 0), &fv);
    if (!fx)
        return lg_error(n, "input 'froxel': no froxel volume (a gated producer?)");
    uint32_t w = (uint32_t)lg_param_int(n, "width"), h = (uint32_t)lg_param_int(n, "height"),
             d = (uint32_t)lg_param_int(n, "depth");
    if (fx->info.width != w || fx->info.height != h || fx->info.depth != d)
        return lg_error(n, "the grid is %ux%ux%u, the parameters say %ux%ux%u", fx->info.width,
                        fx->info.height, fx->info.depth, w, h, d);
    lg_resource_info info;
    int rc = lg_describe(fx->grid, &info, n);
    if (rc)
        return rc;
    if (info.volume.format != LG_FORMAT_RGBA32F)
        return lg_error(n, "the grid's format is %d, not rgba32f", (int)info.volume.format);
    lg_cpu_view in, out;
    if ((rc = lg_map_cpu(n, fx->grid, LG_READ, &in)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &out)))
        return rc;
    /* the volume is [k][j][i] rgba, tightly packed: slice k is rows k H .. k H + H - 1 */
    const float *src = in.pixels;
    float *dst = out.pixels;
    for (size_t row = 0; row < (size_t)h * d; row++)
        memcpy(dst + row * out.row_pixels * 4, src + row * (size_t)w * 4, (size_t)w * 16);
    return 0;
}

static const lg_node_type fg_types[] = {
    { .struct_size = sizeof(lg_node_type),
      .name = "froxel_grid_image",
      .doc = "a froxel grid as a W x (H D) image, slice 0 on top (test)",
      LG_PARAMS(fg_params),
      LG_INPUTS(fg_in),
      LG_OUTPUTS(fg_out),
      .prepare = fg_prepare,
      .execute = fg_execute },
};

LG_PLUGIN_DEFINE("testfroxelgrid", "1.0.0", "Froxel grids as images (test)", fg_types)
