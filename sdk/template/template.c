/* template: a minimal lightgraph plugin with one node, `template_invert`, which computes
 * out = max(0, white - image) per RGB channel on the CPU. Start a plugin from here. */
#include <stddef.h>

#include "lightgraph/lightgraph.h"

static const lg_param_desc params[] = {
    {.key = "white", .type = LG_PARAM_FLOAT, .def.f = 1.0, .min = 0, .max = 1e6,
     .doc = "the value that inverts to black"},
};
static const lg_port_desc inputs[] = {{.name = "image", .kind = LG_KIND_IMAGE, .doc = "input"}};
static const lg_port_desc outputs[] = {{.name = "out", .kind = LG_KIND_IMAGE, .doc = "result"}};

static int invert_prepare(lg_node *n)
{
    lg_resource_info info;
    int rc = lg_describe(lg_input(n, 0), &info, n);
    if (rc)
        return rc;
    lg_image_desc d = {.width = info.image.width, .height = info.image.height,
                       .format = LG_FORMAT_RGBA32F};
    return lg_declare_image(n, 0, &d);
}

static int invert_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    lg_cpu_view in, out;
    int rc = lg_describe(lg_input(n, 0), &info, n);
    if (rc || (rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &in)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &out)))
        return rc;
    if (info.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n, "expects an rgba32f image");
    const float *a = in.pixels;
    float *b = out.pixels;
    float white = (float)lg_param_float(n, "white");
    for (size_t i = 0; i < (size_t)info.image.width * info.image.height; i++) {
        for (int c = 0; c < 3; c++) {
            float v = white - a[4 * i + c];
            b[4 * i + c] = v > 0 ? v : 0;
        }
        b[4 * i + 3] = a[4 * i + 3];
    }
    return 0;
}

static const lg_node_type types[] = {{
    .struct_size = sizeof(lg_node_type),
    .name = "template_invert",
    .doc = "white - image, per RGB channel (the SDK template)",
    LG_PARAMS(params),
    LG_INPUTS(inputs),
    LG_OUTPUTS(outputs),
    .prepare = invert_prepare,
    .execute = invert_execute,
}};

LG_PLUGIN_DEFINE("template", "1.0.0", "The SDK's template plugin", types)
