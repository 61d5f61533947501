/* A plugin built in several variants of one file name (lg_reloadable.so), each into its own
 * directory, for the viewer's reload tests (tests/unit/viewer): the test copies one variant
 * over the file the viewer loaded and checks what the window shows.
 *
 *   RELOADABLE_VARIANT 1, 2: an image of one colour (variant 1 red, 2 green), scaled by the
 *                           parameter `gain`, so that a reload shows;
 *   RELOADABLE_VARIANT 3:   crashes in create() (a store through a null pointer), as a
 *                           broken rebuild would;
 *   RELOADABLE_ABI1:        declares plugin ABI 1.0, which the host refuses.
 */
#include <lightgraph/lightgraph.h>

#ifndef RELOADABLE_VARIANT
#define RELOADABLE_VARIANT 1
#endif

static const lg_param_desc params[] = {
    { .key = "gain",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 100,
      .doc = "scales the colour" },
};

static const lg_port_desc outputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE, .doc = "one colour, the render size" },
};

static int rl_create(lg_node *n)
{
    (void)n;
#if RELOADABLE_VARIANT == 3
    /* what a broken rebuild does: a store through a null pointer (SIGSEGV) */
    volatile int *volatile nowhere = NULL;
    *nowhere = 1;
#endif
    return 0;
}

static int rl_prepare(lg_node *n)
{
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    lg_render_size(n, &d.width, &d.height);
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int rl_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    int rc = lg_describe(lg_output(n, 0), &info, n);
    lg_cpu_view v;
    if (rc || (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v)))
        return rc;
    float g = (float)lg_param_float(n, "gain");
    float c[3] = { RELOADABLE_VARIANT == 1 ? 0.5f * g : 0, RELOADABLE_VARIANT == 2 ? 0.5f * g : 0,
                   0.1f };
    for (uint32_t y = 0; y < info.image.height; y++) {
        float *row = (float *)v.pixels + (size_t)y * v.row_pixels * 4;
        for (uint32_t x = 0; x < info.image.width; x++) {
            row[4 * x] = c[0];
            row[4 * x + 1] = c[1];
            row[4 * x + 2] = c[2];
            row[4 * x + 3] = 1;
        }
    }
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "reloadable",
    .doc = "An image of one colour that tells which build of the plugin made it (test)",
    LG_PARAMS(params),
    LG_OUTPUTS(outputs),
    .create = rl_create,
    .prepare = rl_prepare,
    .execute = rl_execute,
} };

#ifdef RELOADABLE_ABI1
#undef LG_ABI_MAJOR
#define LG_ABI_MAJOR 1
#undef LG_ABI_MINOR
#define LG_ABI_MINOR 0
#endif
LG_PLUGIN_DEFINE("reloadable", "1.0.0", "A plugin the viewer's tests rebuild (tests)", types)
