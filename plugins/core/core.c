/*
 * The core plugin: nodes every graph needs.
 *
 *   image     reads an HDR (or PNG) file into an rgba32f image
 *   constant  a uniform colour image
 *   add       a + b
 *   scale     image * factor * tint
 *
 * All of them run on the CPU; README.md describes ports, parameters and policies.
 */
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"

/* ---- shared helpers -------------------------------------------------------------------------- */

/* Reads one row of an image mapped on the CPU as rgba32f floats, whatever its declared
 * linear format (rgba32f, rgba16f, rgbe8 decoded with alpha 1: lg_pixels_to_rgba32f).
 * rgba8 is refused in prepare (its encoding is not known). */
static void core_row_to_float(const lg_cpu_view *v, lg_format fmt, uint32_t y, uint32_t w,
                              float *dst)
{
    size_t ps = lg_format_size(fmt);
    const unsigned char *row = (const unsigned char *)v->pixels + (size_t)y * v->row_pixels * ps;
    lg_pixels_to_rgba32f(fmt, row, w, dst);
}

static float *core_row_out(const lg_cpu_view *v, uint32_t y)
{
    return (float *)v->pixels + (size_t)y * v->row_pixels * 4;
}

static const char *core_format_name(lg_format f)
{
    return lg_format_name(f);
}

/* Describes image input `port` (required: add's a and b, scale's image); refuses formats
 * the CPU nodes cannot read as linear values. */
static int core_image_input(lg_node *n, uint32_t port, const char *what, lg_resource_info *info)
{
    lg_assert_input(n, port);
    const lg_resource *r = lg_input(n, port);
    int rc = lg_describe(r, info, n);
    if (rc)
        return lg_error_code(n, rc, "input '%s': cannot describe the resource", what);
    if (info->kind != LG_KIND_IMAGE)
        return lg_error(n, "input '%s' is not an image", what);
    if (!info->neutral && info->image.format != LG_FORMAT_RGBA32F &&
        info->image.format != LG_FORMAT_RGBA16F && info->image.format != LG_FORMAT_RGBE8)
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "input '%s' is %s (display-encoded); this node adds and scales "
                             "linear light and takes rgba32f, rgba16f or rgbe8",
                             what, core_format_name(info->image.format));
    return 0;
}

static int core_declare_rgba32f(lg_node *n, uint32_t port, uint32_t w, uint32_t h)
{
    lg_image_desc d = { .width = w, .height = h, .format = LG_FORMAT_RGBA32F };
    return lg_declare_image(n, port, &d);
}

/* ---- image ----------------------------------------------------------------------------------- */

typedef struct core_image_state {
    lg_image img;
} core_image_state;

/* 64-bit FNV-1a over the file's bytes: the whole content, so that a file rewritten within
 * the same second and with the same size still changes the cache key. A 4 MB EXR takes a
 * few milliseconds, next to the tens the decoder needs. */
static int image_prepare(lg_node *n)
{
    const char *path = lg_param_string(n, "file");
    bool radiance = lg_param_bool(n, "radiance");
    if (!path || !*path)
        return lg_error(n, "parameter 'file' is empty: name an .exr, .hdr or .png file");

    core_image_state *st = n->user;
    if (!st) {
        st = lg_create_state(n, sizeof *st);
        if (!st)
            return LG_ERR_NOMEM;
    }
    lg_image_free(&st->img);

    char err[512];
    lg_image_read_info info;
    memset(&info, 0, sizeof info);
    int rc = lg_image_read(path, radiance ? LG_READ_RADIANCE : 0, &st->img, &info, err, sizeof err);
    if (rc)
        /* the SDK's message names the file and the reason */
        return lg_error_code(n, rc, "%s", err);
    if (info.negatives_clamped)
        lg_log(n, LG_LOG_WARN,
               "file '%s': %" PRIu64 " pixel%s with a negative channel clamped to 0 "
               "(radiance = true; lossy compression makes them)",
               path, info.negatives_clamped, info.negatives_clamped == 1 ? "" : "s");
    char what[600];
    snprintf(what, sizeof what, "file '%s'", path);
    lg_warn_nonfinite(n, what, info.nonfinite, "kept as found");

    /* the decoded pixels, not the file's bytes: no second open of the path (the file could
     * change between the two), and the same key for the same pixels in any encoding */
    uint64_t h = lg_image_hash(&st->img, LG_IMAGE_HASH_SEED);
    lg_add_content_key(n, &h, sizeof h);

    rc = core_declare_rgba32f(n, 0, st->img.width, st->img.height);
    if (rc)
        return rc;
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int image_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    core_image_state *st = n->user;
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    for (uint32_t y = 0; y < st->img.height; y++)
        memcpy(core_row_out(&v, y), st->img.pixels + (size_t)y * st->img.width * 4,
               (size_t)st->img.width * 16);
    return 0;
}

static void image_destroy(lg_node *n)
{
    core_image_state *st = n->user;
    if (!st)
        return;
    lg_image_free(&st->img);
    free(st);
    n->user = NULL;
}

/* ---- constant -------------------------------------------------------------------------------- */

static int constant_prepare(lg_node *n)
{
    uint32_t w, h;
    lg_output_size(n, "width", "height", &w, &h);
    if (w == 0 || h == 0)
        return lg_error(n,
                        "size %ux%u is empty (width and height 0 take the render size, "
                        "--size)",
                        w, h);
    int rc = core_declare_rgba32f(n, 0, w, h);
    if (rc)
        return rc;
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int constant_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    const lg_value *c = lg_param(n, "color");
    float px[4] = { (float)c->v[0], (float)c->v[1], (float)c->v[2],
                    (float)lg_param_float(n, "alpha") };
    lg_resource_info info;
    int rc = lg_describe(lg_output(n, 0), &info, n);
    if (rc)
        return rc;
    lg_cpu_view v;
    rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    for (uint32_t y = 0; y < info.image.height; y++) {
        float *row = core_row_out(&v, y);
        for (uint32_t x = 0; x < info.image.width; x++)
            memcpy(row + (size_t)x * 4, px, sizeof px);
    }
    return 0;
}

/* ---- add ------------------------------------------------------------------------------------- */

/* node->user of add and scale: whether the output aliases an input (add with a gated
 * input), and which inputs' NaN/Inf pixels were reported (lg_check_input_finite: once per
 * render; a node that passes a non-finite input on says so, issue 20). */
typedef struct core_pass {
    bool aliased;
    bool reported[2];
} core_pass;

static core_pass *core_pass_get(lg_node *n)
{
    if (!n->user)
        n->user = calloc(1, sizeof(core_pass));
    if (!n->user)
        lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu bytes of node state)",
                      sizeof(core_pass));
    return n->user;
}

static void core_pass_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static int add_prepare(lg_node *n)
{
    core_pass *st = core_pass_get(n);
    if (!st)
        return LG_ERR_NOMEM;
    lg_resource_info a, b;
    int rc = core_image_input(n, 0, "a", &a);
    if (rc)
        return rc;
    rc = core_image_input(n, 1, "b", &b);
    if (rc)
        return rc;
    /* A gated input (zero): the sum is the other input, with no copy; execute then has
     * nothing to do (the output is the input, so it must not write). */
    st->aliased = a.neutral || b.neutral;
    if (st->aliased) {
        rc = lg_declare_alias(n, 0, b.neutral ? 0 : 1);
        return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
    }
    if (a.image.width != b.image.width || a.image.height != b.image.height)
        return lg_error(n, "input sizes differ: a is %ux%u, b is %ux%u", a.image.width,
                        a.image.height, b.image.width, b.image.height);
    rc = core_declare_rgba32f(n, 0, a.image.width, a.image.height);
    if (rc)
        return rc;
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int add_execute(lg_node *n, const lg_frame *frame)
{
    core_pass *st = n->user;
    if (st->aliased)
        return 0; /* the aliased input reports its own NaN/Inf, if its producer does */
    int rc = lg_check_input_finite(n, frame, 0, "a", NULL, &st->reported[0]);
    if (!rc)
        rc = lg_check_input_finite(n, frame, 1, "b", NULL, &st->reported[1]);
    if (rc)
        return rc;
    lg_resource_info a, b;
    rc = lg_describe(lg_input(n, 0), &a, n);
    if (!rc)
        rc = lg_describe(lg_input(n, 1), &b, n);
    if (rc)
        return rc;
    lg_cpu_view va, vb, vo;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &va)) ||
        (rc = lg_map_cpu(n, lg_input(n, 1), LG_READ, &vb)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &vo)))
        return rc;
    uint32_t w = a.image.width, h = a.image.height;
    float *rb = malloc((size_t)w * 16);
    if (!rb)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (row of %u pixels)", w);
    for (uint32_t y = 0; y < h; y++) {
        float *o = core_row_out(&vo, y);
        core_row_to_float(&va, a.image.format, y, w, o);
        core_row_to_float(&vb, b.image.format, y, w, rb);
        for (size_t x = 0; x < w; x++) {
            float *p = o + x * 4;
            const float *q = rb + x * 4;
            p[0] += q[0];
            p[1] += q[1];
            p[2] += q[2];
            /* coverage: the union of two additive layers, kept in [0, 1] */
            float al = p[3] + q[3];
            p[3] = al > 1.0f ? 1.0f : al;
        }
    }
    free(rb);
    return 0;
}

/* ---- scale ----------------------------------------------------------------------------------- */

static int scale_prepare(lg_node *n)
{
    if (!core_pass_get(n))
        return LG_ERR_NOMEM;
    lg_resource_info in;
    int rc = core_image_input(n, 0, "image", &in);
    if (rc)
        return rc;
    rc = core_declare_rgba32f(n, 0, in.image.width, in.image.height);
    if (rc)
        return rc;
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int scale_execute(lg_node *n, const lg_frame *frame)
{
    core_pass *st = n->user;
    int rc = lg_check_input_finite(n, frame, 0, "image", NULL, &st->reported[0]);
    if (rc)
        return rc;
    lg_resource_info in;
    rc = lg_describe(lg_input(n, 0), &in, n);
    if (rc)
        return rc;
    double f = lg_param_float(n, "factor");
    const lg_value *t = lg_param(n, "tint");
    float m[3] = { (float)(f * t->v[0]), (float)(f * t->v[1]), (float)(f * t->v[2]) };
    lg_cpu_view vi, vo;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &vi)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &vo)))
        return rc;
    for (uint32_t y = 0; y < in.image.height; y++) {
        float *o = core_row_out(&vo, y);
        core_row_to_float(&vi, in.image.format, y, in.image.width, o);
        for (size_t x = 0; x < in.image.width; x++) {
            o[x * 4 + 0] *= m[0];
            o[x * 4 + 1] *= m[1];
            o[x * 4 + 2] *= m[2];
        }
    }
    return 0;
}

/* ---- descriptors ----------------------------------------------------------------------------- */

static const lg_param_desc image_params[] = {
    { .key = "file",
      .type = LG_PARAM_PATH,
      .def.s = "",
      .doc =
          "image file: .exr (any compression), .hdr/.pic (RGBE) or .png (sRGB, decoded to linear)" },
    { .key = "radiance",
      .type = LG_PARAM_BOOL,
      .def.b = true,
      .doc = "the file holds radiance: negative values (from lossy compression) are clamped to 0" },
};
static const lg_port_desc image_outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "the file's pixels, rgba32f, linear" },
};

static const lg_param_desc constant_params[] = {
    { .key = "color",
      .type = LG_PARAM_COLOR,
      .def.v = { 0.18, 0.18, 0.18 },
      .doc = "linear RGB of every pixel" },
    { .key = "alpha", .type = LG_PARAM_FLOAT, .def.f = 1.0, .doc = "alpha of every pixel" },
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 65536,
      .doc = "pixels; 0 = the render width (--size)",
      .role = LG_ROLE_IMAGE_WIDTH },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 65536,
      .doc = "pixels; 0 = the render height (--size)",
      .role = LG_ROLE_IMAGE_HEIGHT },
};
static const lg_port_desc constant_outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "rgba32f" },
};

static const lg_port_desc add_inputs[] = {
    { .name = "a", .kind = LG_KIND_IMAGE, .doc = "linear image" },
    { .name = "b", .kind = LG_KIND_IMAGE, .doc = "linear image of the same size" },
};
static const lg_port_desc add_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: RGB a + b, alpha min(1, a + b); the other input itself if one is gated" },
};

static const lg_param_desc scale_params[] = {
    { .key = "factor",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 1e9,
      .doc = "multiplier of every colour channel (exposure, linear)" },
    { .key = "tint",
      .type = LG_PARAM_COLOR,
      .def.v = { 1, 1, 1 },
      .doc = "per-channel multiplier, linear RGB" },
};
static const lg_port_desc scale_inputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE, .doc = "linear image (rgba32f, rgba16f or rgbe8)" },
};
static const lg_port_desc scale_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: RGB * factor * tint, alpha unchanged" },
};

static const lg_node_type core_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "image",
        .doc = "reads an image file (EXR, HDR, PNG) as linear rgba32f",
        LG_PARAMS(image_params),
        LG_OUTPUTS(image_outputs),
        .prepare = image_prepare,
        .execute = image_execute,
        .destroy = image_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "constant",
        .doc = "an image of one colour",
        LG_PARAMS(constant_params),
        LG_OUTPUTS(constant_outputs),
        .prepare = constant_prepare,
        .execute = constant_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "add",
        .doc = "sum of two images of the same size",
        LG_INPUTS(add_inputs),
        LG_OUTPUTS(add_outputs),
        .prepare = add_prepare,
        .execute = add_execute,
        .destroy = core_pass_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "scale",
        .doc = "image times a factor and a tint",
        LG_PARAMS(scale_params),
        LG_INPUTS(scale_inputs),
        LG_OUTPUTS(scale_outputs),
        .prepare = scale_prepare,
        .execute = scale_execute,
        .destroy = core_pass_destroy,
    },
};

LG_PLUGIN_DEFINE("core", "1.0.0", "Basic image nodes: image, constant, add, scale", core_types)
