/* Test plugin "testformats": the HDR precision formats (lightgraph/image.h "Pixel formats")
 * through the host.
 *
 *   test_hdr  { format, width, height, peak, nan }   a CPU producer of a known HDR pattern
 *             in any format, through lg_pixels_from_rgba32f (the rgba16f clamp policy: the
 *             values it clamped are reported once, with their count)
 *   test_copy { backend = cpu | gl | cl }           copies its input's bytes, whatever the
 *             format, on the device named (glCopyImageSubData, clEnqueueCopyBuffer,
 *             memcpy): a chain of copies moves an image through every transfer of the host
 *   test_fill { color = checker | [r, g, b] }        a colour parameter that also takes a
 *             keyword (ABI 2.3): the image filled with the colour, or with a checker of
 *             (1, 1, 1) and (0, 0, 0) pixels (pixel (x, y) white when x + y is even)
 *
 * The pattern, pixel (x, y) of W x H, u = (x + 0.5) / W, v = (y + 0.5) / H:
 *   L = 2^(20 u - 8) (2^-8 .. 2^12 across the image), RGB = L (1, 0.5 + 0.5 v, 1 - 0.75 v),
 *   alpha 1; pixel (0, 0) is (peak, peak / 2, peak / 4) when peak > 0 (a sun), and with
 *   nan = true pixel (1, 0) is (NaN, 1, 1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/gl.h"
#include "lightgraph/image.h"
#include "lightgraph/lightgraph.h"

static const char *const fmt_names[] = { "rgba32f", "rgba16f", "rgbe8", "rgba8", NULL };
static const lg_format fmt_values[] = { LG_FORMAT_RGBA32F, LG_FORMAT_RGBA16F, LG_FORMAT_RGBE8,
                                        LG_FORMAT_RGBA8 };

typedef struct hdr_state {
    bool warned;
} hdr_state;

static const lg_param_desc hdr_params[] = {
    { .key = "format",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = fmt_names,
      .doc = "the output's pixel format" },
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 65536,
      .doc = "pixels; 0 = the render width",
      .role = LG_ROLE_IMAGE_WIDTH },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 65536,
      .doc = "pixels; 0 = the render height",
      .role = LG_ROLE_IMAGE_HEIGHT },
    { .key = "peak",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "pixel (0, 0) is (peak, peak/2, peak/4) when > 0" },
    { .key = "nan", .type = LG_PARAM_BOOL, .def.b = false, .doc = "pixel (1, 0) gets a NaN" },
};
static const lg_port_desc hdr_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int hdr_create(lg_node *n)
{
    n->user = calloc(1, sizeof(hdr_state));
    return n->user ? 0 : LG_ERR_NOMEM;
}

static void hdr_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static int hdr_prepare(lg_node *n)
{
    lg_image_desc d = { .format = fmt_values[lg_param_enum(n, "format")] };
    d.width = (uint32_t)lg_param_int(n, "width");
    d.height = (uint32_t)lg_param_int(n, "height");
    if (!d.width || !d.height)
        lg_render_size(n, &d.width, &d.height);
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int hdr_execute(lg_node *n, const lg_frame *frame)
{
    hdr_state *st = n->user;
    lg_resource_info info;
    int rc = lg_describe(lg_output(n, 0), &info, n);
    if (rc)
        return rc;
    lg_cpu_view v;
    if ((rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v)))
        return rc;
    uint32_t w = info.image.width, h = info.image.height;
    lg_format f = info.image.format;
    float *row = malloc((size_t)w * 16);
    if (!row)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    float peak = (float)lg_param_float(n, "peak");
    bool nan = lg_param_bool(n, "nan");
    uint64_t clamped = 0;
    for (uint32_t y = 0; y < h; y++) {
        double vv = (y + 0.5) / h;
        for (uint32_t x = 0; x < w; x++) {
            double u = (x + 0.5) / w, l = exp2(20 * u - 8);
            float *p = row + 4 * x;
            p[0] = (float)l;
            p[1] = (float)(l * (0.5 + 0.5 * vv));
            p[2] = (float)(l * (1 - 0.75 * vv));
            p[3] = 1;
        }
        if (y == 0 && peak > 0) {
            row[0] = peak;
            row[1] = peak / 2;
            row[2] = peak / 4;
        }
        if (y == 0 && nan && w > 1)
            row[4] = NAN;
        lg_pixels_from_rgba32f(f, row, w,
                               (char *)v.pixels + (size_t)y * v.row_pixels * lg_format_size(f),
                               &clamped);
    }
    free(row);
    /* the policy: reported once per node, with the count */
    if (clamped && !st->warned) {
        st->warned = true;
        lg_log(n, LG_LOG_WARN, "%s output, frame %u: %llu values it cannot hold replaced (%s)",
               lg_format_name(f), frame->index, (unsigned long long)clamped,
               f == LG_FORMAT_RGBA16F ? "beyond 65504 clamped to 65504, NaN set to 0"
               : f == LG_FORMAT_RGBE8 ? "NaN and negatives set to 0, 2^127 and above saturated"
                                      : "NaN set to 0, clamped to [0, 1]");
    }
    return 0;
}

static const char *const backends[] = { "cpu", "gl", "cl", NULL };
static const lg_param_desc copy_params[] = {
    { .key = "backend",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = backends,
      .doc = "where the copy runs" },
};
static const lg_port_desc copy_in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };

static int copy_prepare(lg_node *n)
{
    lg_resource_info info;
    const lg_resource *in = lg_input(n, 0);
    if (!in)
        return lg_error(n, "input 'image' is not connected");
    int rc = lg_describe(in, &info, n);
    if (rc)
        return rc;
    if (info.kind != LG_KIND_IMAGE)
        return lg_error(n, "input 'image' is not an image");
    lg_image_desc d = { .width = info.image.width,
                        .height = info.image.height,
                        .format = info.image.format };
    if ((rc = lg_declare_image(n, 0, &d)))
        return rc;
    static const lg_device devs[] = { LG_DEVICE_CPU, LG_DEVICE_GL, LG_DEVICE_CL };
    return lg_set_device(n, devs[lg_param_enum(n, "backend")]);
}

static int copy_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    int rc = lg_describe(lg_input(n, 0), &info, n);
    if (rc)
        return rc;
    size_t bytes = (size_t)info.image.width * info.image.height * lg_format_size(info.image.format);
    switch (lg_param_enum(n, "backend")) {
    case 0: {
        lg_cpu_view a, b;
        if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &a)) ||
            (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &b)))
            return rc;
        memcpy(b.pixels, a.pixels, bytes);
        return 0;
    }
    case 1: {
        const lg_gl *gl = lg_gl_get(n);
        if (!gl)
            return LG_ERR_DEVICE;
        uint32_t ta = 0, tb = 0, dummy;
        if ((rc = lg_map_gl(n, lg_input(n, 0), LG_READ, &ta, &dummy)) ||
            (rc = lg_map_gl(n, lg_output(n, 0), LG_WRITE, &tb, &dummy)))
            return rc;
        gl->CopyImageSubData(ta, GL_TEXTURE_2D, 0, 0, 0, 0, tb, GL_TEXTURE_2D, 0, 0, 0, 0,
                             (GLsizei)info.image.width, (GLsizei)info.image.height, 1);
        return lg_gl_check(n, "glCopyImageSubData");
    }
    default: {
        cl_command_queue q = lg_cl_queue(n);
        if (!q)
            return LG_ERR_DEVICE;
        void *a = NULL, *b = NULL, *dummy = NULL;
        if ((rc = lg_map_cl(n, lg_input(n, 0), LG_READ, &a, &dummy)) ||
            (rc = lg_map_cl(n, lg_output(n, 0), LG_WRITE, &b, &dummy)))
            return rc;
        cl_int e = clEnqueueCopyBuffer(q, (cl_mem)a, (cl_mem)b, 0, 0, bytes, 0, NULL, NULL);
        if (e != CL_SUCCESS)
            return lg_cl_fail(n, e, "clEnqueueCopyBuffer");
        return 0;
    }
    }
}

static const char *const fill_words[] = { "checker", NULL };
static const lg_param_desc fill_params[] = {
    { .key = "color",
      .type = LG_PARAM_COLOR,
      .def.e = 0,
      .enum_values = fill_words,
      .min = 0,
      .max = 100,
      .doc = "the fill colour, or checker" },
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 4,
      .min = 1,
      .max = 64,
      .doc = "pixels",
      .role = LG_ROLE_IMAGE_WIDTH },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 4,
      .min = 1,
      .max = 64,
      .doc = "pixels",
      .role = LG_ROLE_IMAGE_HEIGHT },
};

static int fill_prepare(lg_node *n)
{
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    d.width = (uint32_t)lg_param_int(n, "width");
    d.height = (uint32_t)lg_param_int(n, "height");
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int fill_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    int rc = lg_describe(lg_output(n, 0), &info, n);
    if (rc)
        return rc;
    lg_cpu_view v;
    if ((rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v)))
        return rc;
    const lg_value *c = lg_param(n, "color");
    for (uint32_t y = 0; y < info.image.height; y++) {
        float *row = (float *)v.pixels + (size_t)y * v.row_pixels * 4;
        for (uint32_t x = 0; x < info.image.width; x++) {
            for (int k = 0; k < 3; k++)
                row[4 * x + k] = c->e < 0 ? (float)c->v[k] : (float)((x + y + 1) % 2);
            row[4 * x + 3] = 1;
        }
    }
    return 0;
}

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_hdr",
        .doc = "A known HDR pattern in any pixel format (test)",
        LG_PARAMS(hdr_params),
        LG_OUTPUTS(hdr_out),
        .create = hdr_create,
        .destroy = hdr_destroy,
        .prepare = hdr_prepare,
        .execute = hdr_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_copy",
        .doc = "Copies an image's bytes on cpu, gl or cl (test)",
        LG_PARAMS(copy_params),
        LG_INPUTS(copy_in),
        LG_OUTPUTS(hdr_out),
        .prepare = copy_prepare,
        .execute = copy_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_fill",
        .doc = "An image of one colour, or a checker (test)",
        LG_PARAMS(fill_params),
        LG_OUTPUTS(hdr_out),
        .prepare = fill_prepare,
        .execute = fill_execute,
    },
};

LG_PLUGIN_DEFINE("testformats", "1.0.0", "Pixel formats through the host (tests)", types)
