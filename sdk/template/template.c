/* template: a minimal lightgraph plugin with one node, `template_invert`, which computes
 * out = max(0, white - image) per RGB channel on the CPU or, with backend = gl, in a GL
 * compute shader (shaders/invert.comp, embedded at build time by the SDK's embed.py).
 * Start a plugin from here. */
#include <stdlib.h>
#include <stddef.h>

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"

#include "invert.comp.h" /* lg_src_invert_comp, lg_src_invert_comp_file (meson.build) */

enum { TPL_BACKEND_CPU = 0, TPL_BACKEND_GL = 1 };

typedef struct tpl_state {
    int backend;
    /* backend gl: a compute pass (lightgraph/gl_pass.h), made on the first execute and
     * destroyed in destroy; its names are looked up once */
    lg_gl_pass *pass;
    lg_gl_binding b_in, b_out;
    lg_gl_uniform u_size, u_white;
} tpl_state;

static const char *const backends[] = {"cpu", "gl", NULL};
static const lg_param_desc params[] = {
    {.key = "white", .type = LG_PARAM_FLOAT, .def.f = 1.0, .min = 0, .max = 1e6,
     .doc = "the value that inverts to black"},
    {.key = "backend", .type = LG_PARAM_ENUM, .def.e = TPL_BACKEND_CPU, .enum_values = backends,
     .doc = "where it runs: cpu, or gl (a compute shader)"},
};
static const lg_port_desc inputs[] = {
    {.name = "image", .kind = LG_KIND_IMAGE, .doc = "input, rgba32f"},
};
static const lg_port_desc outputs[] = {
    {.name = "out", .kind = LG_KIND_IMAGE, .doc = "result, rgba32f"},
};

static int invert_create(lg_node *n)
{
    tpl_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    st->backend = lg_param_enum(n, "backend");
    n->user = st;
    return 0;
}

static int invert_prepare(lg_node *n)
{
    tpl_state *st = n->user;
    lg_resource_info info;
    int rc = lg_describe(lg_input(n, 0), &info, n);
    if (rc)
        return rc;
    if (info.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n, "expects an rgba32f image");
    lg_image_desc d = {.width = info.image.width, .height = info.image.height,
                       .format = LG_FORMAT_RGBA32F};
    if ((rc = lg_declare_image(n, 0, &d)))
        return rc;
    /* the device the node runs on; the host moves the input there when it is elsewhere */
    return lg_set_device(n, st->backend == TPL_BACKEND_GL ? LG_DEVICE_GL : LG_DEVICE_CPU);
}

static int invert_execute_gl(lg_node *n, const lg_resource_info *info)
{
    tpl_state *st = n->user;
    int rc;
    if (!st->pass) {
        static const lg_gl_shader_src cs = {GL_COMPUTE_SHADER, lg_src_invert_comp_file,
                                            lg_src_invert_comp};
        lg_gl_pass_desc d = {.name = "template_invert", .stages = &cs, .n_stages = 1};
        if ((rc = lg_gl_pass_create(n, &d, &st->pass)))
            return rc;
        st->b_in = lg_gl_pass_image(st->pass, "u_in");
        st->b_out = lg_gl_pass_image(st->pass, "u_out");
        st->u_size = lg_gl_pass_uniform(st->pass, "u_size");
        st->u_white = lg_gl_pass_uniform(st->pass, "u_white");
    }
    GLuint tin, tout;
    if ((rc = lg_map_gl(n, lg_input(n, 0), LG_READ, &tin, NULL)) ||
        (rc = lg_map_gl(n, lg_output(n, 0), LG_WRITE, &tout, NULL)) ||
        (rc = lg_gl_pass_begin(st->pass, NULL))) /* a failed name look-up fails here */
        return rc;
    lg_gl_pass_bind_image(st->pass, st->b_in, tin, GL_READ_ONLY, GL_RGBA32F);
    lg_gl_pass_bind_image(st->pass, st->b_out, tout, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_set_ivec2(st->pass, st->u_size, (int32_t)info->image.width,
                    (int32_t)info->image.height);
    lg_gl_set_float(st->pass, st->u_white, (float)lg_param_float(n, "white"));
    rc = lg_gl_pass_dispatch(st->pass, info->image.width, info->image.height, 1);
    /* end: the barrier for whoever reads the output next, and the host's GL state back */
    return lg_gl_pass_end(st->pass, rc);
}

static int invert_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    tpl_state *st = n->user;
    lg_resource_info info;
    lg_cpu_view in, out;
    int rc = lg_describe(lg_input(n, 0), &info, n);
    if (rc)
        return rc;
    if (st->backend == TPL_BACKEND_GL)
        return invert_execute_gl(n, &info);
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &in)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &out)))
        return rc;
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

static void invert_destroy(lg_node *n)
{
    tpl_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->pass);
    free(st);
    n->user = NULL;
}

static const lg_node_type types[] = {{
    .struct_size = sizeof(lg_node_type),
    .name = "template_invert",
    .doc = "white - image, per RGB channel (the SDK template)",
    LG_PARAMS(params),
    LG_INPUTS(inputs),
    LG_OUTPUTS(outputs),
    .create = invert_create,
    .prepare = invert_prepare,
    .execute = invert_execute,
    .destroy = invert_destroy,
}};

LG_PLUGIN_DEFINE("template", "1.0.0", "The SDK's template plugin", types)
