/* Test plugin "testclock": a node that shows the frame's time, so that the viewer's play,
 * pause and scrub (docs/viewer.md, "Animation") can be read back from a screenshot without
 * an animated scene:
 *
 *   test_clock { image = lit }   every frame (lg_set_per_frame): the input's pixels with
 *                                frame->time added to red and frame->index to green (mod
 *                                1000), blue and alpha as they are; without an input a
 *                                render-size image of (time, index, 0, 1)
 *
 * It runs on the CPU. The nodes upstream of it stay static: a test counts their runs. */
#include <string.h>

#include "lightgraph/lightgraph.h"

static const lg_port_desc in[] = { { .name = "image", .kind = LG_KIND_IMAGE, .optional = true } };
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int clock_prepare(lg_node *n)
{
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    const lg_resource *src = lg_input(n, 0);
    if (src) {
        lg_resource_info info;
        int rc = lg_describe(src, &info, n);
        if (rc)
            return rc;
        if (info.kind != LG_KIND_IMAGE || info.image.format != LG_FORMAT_RGBA32F)
            return lg_error(n, "input 'image' is not an rgba32f image");
        d.width = info.image.width;
        d.height = info.image.height;
    } else {
        lg_render_size(n, &d.width, &d.height);
    }
    int rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    lg_set_per_frame(n, true);
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int clock_execute(lg_node *n, const lg_frame *frame)
{
    lg_resource_info info;
    int rc = lg_describe(lg_output(n, 0), &info, n);
    if (rc)
        return rc;
    lg_cpu_view a = { 0 }, b;
    const lg_resource *src = lg_input(n, 0);
    if (src && (rc = lg_map_cpu(n, src, LG_READ, &a)))
        return rc;
    if ((rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &b)))
        return rc;
    for (uint32_t y = 0; y < info.image.height; y++) {
        float *o = (float *)b.pixels + (size_t)y * b.row_pixels * 4;
        const float *i = src ? (const float *)a.pixels + (size_t)y * a.row_pixels * 4 : NULL;
        for (uint32_t x = 0; x < info.image.width; x++) {
            float base[4] = { 0, 0, 0, 1 };
            if (i)
                memcpy(base, i + 4 * x, sizeof base);
            o[4 * x + 0] = base[0] + (float)frame->time;
            o[4 * x + 1] = base[1] + (float)(frame->index % 1000);
            o[4 * x + 2] = base[2];
            o[4 * x + 3] = base[3];
        }
    }
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_clock",
    .doc = "The frame's time added to red, its index to green, every frame (test)",
    LG_INPUTS(in),
    LG_OUTPUTS(out),
    .prepare = clock_prepare,
    .execute = clock_execute,
} };

LG_PLUGIN_DEFINE("testclock", "1.0.0", "The frame's time as an image (tests)", types)
