/* Test plugin "testparts": composite resources (ABI 2.0) end to end.
 *
 *   partmaker  -> probe: a cube probe (size x size faces, `levels` mip levels, a solid-angle
 *                 table, the info part) written on `device` (cpu, gl or cl). Texel values
 *                 are constant per (level, face): R = 1000 l + 100 f + 1, G = 1, B = 2, A = 3.
 *   partcheck  probe -> out: reads the probe on `device` and fails, naming the first wrong
 *                 texel, unless every level and face holds the pattern above and the solid
 *                 angles sum to 4 pi. out is a 1x1 image holding 1.
 *   partsteal  image -> out: maps the last probe a partmaker made, which it did not receive
 *                 through an input (`what` = part: lg_part on it; texture: maps its radiance
 *                 part); the host must refuse both.
 *   badparam   -> out: reads a parameter its type does not declare.
 *   kindmaker  -> sh, transfer, froxel: one of each of the other composite kinds, through
 *                 their headers' declare / publish; element i of each big part holds i.
 *   kindcheck  sh, transfer, froxel -> out: reads them back through the kinds' get
 *                 accessors and fails unless the info and every element arrived.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "lightgraph/cl.h"
#include "lightgraph/gl.h"
#include "lightgraph/lightgraph.h"

/* partsteal's loot, shared within the plugin: the last probe and its radiance part */
static const lg_resource *g_last_probe, *g_last_radiance;

static const char *const devices[] = { "cpu", "gl", "cl", NULL };

static float pattern(uint32_t level, uint32_t face)
{
    return 1000.0f * (float)level + 100.0f * (float)face + 1.0f;
}

static int out_1x1(lg_node *n)
{
    lg_image_desc d = { .width = 1, .height = 1, .format = LG_FORMAT_RGBA32F };
    return lg_declare_image(n, 0, &d);
}

static int write_1x1(lg_node *n, float v)
{
    lg_cpu_view o;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &o);
    if (rc)
        return rc;
    float *p = o.pixels;
    p[0] = p[1] = p[2] = v;
    p[3] = 1;
    return 0;
}

/* ---- partmaker ------------------------------------------------------------------------------- */

static const lg_param_desc maker_params[] = {
    { .key = "device", .type = LG_PARAM_ENUM, .enum_values = devices, .doc = "where to write" },
    { .key = "size", .type = LG_PARAM_INT, .def.i = 8, .min = 1, .max = 256, .doc = "face side" },
    { .key = "levels", .type = LG_PARAM_INT, .def.i = 4, .min = 1, .max = 9, .doc = "mip levels" },
};
static const lg_port_desc maker_out[] = { { .name = "probe", .kind = LG_KIND_PROBE } };

static int maker_prepare(lg_node *n)
{
    uint32_t size = (uint32_t)lg_param_int(n, "size");
    lg_image_desc d = { .width = size,
                        .height = size,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = LG_IMAGE_CUBE,
                        .levels = (uint32_t)lg_param_int(n, "levels") };
    int rc = lg_probe_declare(n, 0, LG_PROBE_CUBE, &d, true);
    if (rc)
        return rc;
    int dev = lg_param_enum(n, "device");
    return lg_set_device(n, dev == 1 ? LG_DEVICE_GL : dev == 2 ? LG_DEVICE_CL : LG_DEVICE_CPU);
}

static int maker_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    const lg_resource *out = lg_output(n, 0);
    const lg_resource *rad = lg_part(n, out, "radiance");
    const lg_resource *sa = lg_part(n, out, "solid_angle");
    if (!rad || !sa)
        return lg_error(n, "the declared parts are missing");
    lg_resource_info ri;
    lg_describe(rad, &ri, n);
    const lg_image_desc *d = &ri.image;
    int dev = lg_param_enum(n, "device");
    int rc = 0;
    if (dev == 0) {
        lg_cpu_view v;
        if ((rc = lg_map_cpu(n, rad, LG_WRITE, &v)))
            return rc;
        float *p = v.pixels;
        for (uint32_t l = 0; l < lg_image_levels(d); l++)
            for (uint32_t f = 0; f < 6; f++) {
                size_t a = lg_image_offset(d, l, f);
                size_t b = a + (size_t)lg_image_level_width(d, l) * lg_image_level_height(d, l);
                for (size_t i = a; i < b; i++) {
                    p[4 * i] = pattern(l, f);
                    p[4 * i + 1] = 1, p[4 * i + 2] = 2, p[4 * i + 3] = 3;
                }
            }
    } else if (dev == 1) {
        const lg_gl *gl = lg_gl_get(n);
        uint32_t tex = 0;
        if (!gl || (rc = lg_map_gl(n, rad, LG_WRITE, &tex, NULL)))
            return rc ? rc : LG_ERR_DEVICE;
        for (uint32_t l = 0; l < lg_image_levels(d); l++)
            for (uint32_t f = 0; f < 6; f++) {
                float c[4] = { pattern(l, f), 1, 2, 3 };
                gl->ClearTexSubImage(tex, (GLint)l, 0, 0, (GLint)f,
                                     (GLsizei)lg_image_level_width(d, l),
                                     (GLsizei)lg_image_level_height(d, l), 1, GL_RGBA, GL_FLOAT, c);
            }
        if ((rc = lg_gl_check(n, "clearing the cube's faces")))
            return rc;
    } else {
        void *mem = NULL;
        if ((rc = lg_map_cl(n, rad, LG_WRITE, &mem, NULL)))
            return rc;
        cl_command_queue q = lg_cl_queue(n);
        for (uint32_t l = 0; l < lg_image_levels(d); l++)
            for (uint32_t f = 0; f < 6; f++) {
                cl_float4 c = { { pattern(l, f), 1, 2, 3 } };
                size_t px = (size_t)lg_image_level_width(d, l) * lg_image_level_height(d, l);
                cl_int e = clEnqueueFillBuffer(q, (cl_mem)mem, &c, sizeof c,
                                               lg_image_offset(d, l, f) * 16, px * 16, 0, NULL,
                                               NULL);
                if (e != CL_SUCCESS)
                    return lg_error(n, "clEnqueueFillBuffer: %d", e);
            }
        clFinish(q);
    }
    /* the solid angles, on the CPU whatever the device: parts have their own residency */
    lg_cpu_view sv;
    if ((rc = lg_map_cpu(n, sa, LG_WRITE, &sv)))
        return rc;
    float *w = sv.pixels;
    size_t texels = (size_t)6 * d->width * d->height;
    for (size_t i = 0; i < texels; i++)
        w[i] = (float)(4.0 * LG_PI / (double)texels);
    lg_probe_info info = { .layout = LG_PROBE_CUBE,
                           .scale = 1,
                           .rotation = { 1, 0, 0, 0, 1, 0, 0, 0, 1 } };
    if ((rc = lg_probe_publish(n, 0, &info)))
        return rc;
    g_last_probe = out;
    g_last_radiance = rad;
    return 0;
}

/* ---- partcheck ------------------------------------------------------------------------------- */

static const lg_param_desc check_params[] = {
    { .key = "device", .type = LG_PARAM_ENUM, .enum_values = devices, .doc = "where to read" },
};
static const lg_port_desc check_in[] = { { .name = "probe", .kind = LG_KIND_PROBE } };
static const lg_port_desc img_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int check_prepare(lg_node *n)
{
    int dev = lg_param_enum(n, "device");
    int rc = out_1x1(n);
    return rc ? rc
              : lg_set_device(n, dev == 1   ? LG_DEVICE_GL
                                 : dev == 2 ? LG_DEVICE_CL
                                            : LG_DEVICE_CPU);
}

static int check_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_probe pv;
    const lg_probe *p = lg_probe_get(n, lg_input(n, 0), &pv);
    if (!p)
        return lg_error(n, "no probe");
    if (p->info.layout != LG_PROBE_CUBE || !p->solid_angle)
        return lg_error(n, "the probe's info or solid angles did not arrive");
    const lg_image_desc *d = &p->radiance_desc;
    size_t total = lg_image_offset(d, lg_image_levels(d), 0);
    float *px = malloc(total * 16);
    if (!px)
        return LG_ERR_NOMEM;
    int dev = lg_param_enum(n, "device"), rc = 0;
    if (dev == 0) {
        lg_cpu_view v;
        if (!(rc = lg_map_cpu(n, p->radiance, LG_READ, &v)))
            memcpy(px, v.pixels, total * 16);
    } else if (dev == 1) {
        const lg_gl *gl = lg_gl_get(n);
        uint32_t tex = 0;
        if (!gl || (rc = lg_map_gl(n, p->radiance, LG_READ, &tex, NULL))) {
            free(px);
            return rc ? rc : LG_ERR_DEVICE;
        }
        GLint target = 0;
        gl->GetTextureParameteriv(tex, GL_TEXTURE_TARGET, &target);
        if (target != GL_TEXTURE_CUBE_MAP)
            rc = lg_error(n, "the radiance part is not a GL cube map (target 0x%x)", target);
        for (uint32_t l = 0; !rc && l < lg_image_levels(d); l++) {
            size_t off = lg_image_offset(d, l, 0), len = lg_image_offset(d, l + 1, 0) - off;
            gl->GetTextureImage(tex, (GLint)l, GL_RGBA, GL_FLOAT, (GLsizei)(len * 16),
                                px + 4 * off);
        }
        if (!rc)
            rc = lg_gl_check(n, "reading the cube back");
    } else {
        void *mem = NULL;
        if (!(rc = lg_map_cl(n, p->radiance, LG_READ, &mem, NULL))) {
            cl_int e = clEnqueueReadBuffer(lg_cl_queue(n), (cl_mem)mem, CL_TRUE, 0, total * 16, px,
                                           0, NULL, NULL);
            if (e != CL_SUCCESS)
                rc = lg_error(n, "clEnqueueReadBuffer: %d", e);
        }
    }
    for (uint32_t l = 0; !rc && l < lg_image_levels(d); l++)
        for (uint32_t f = 0; !rc && f < 6; f++) {
            size_t a = lg_image_offset(d, l, f);
            size_t b = a + (size_t)lg_image_level_width(d, l) * lg_image_level_height(d, l);
            for (size_t i = a; i < b; i++)
                if (px[4 * i] != pattern(l, f) || px[4 * i + 1] != 1 || px[4 * i + 3] != 3) {
                    rc = lg_error(n, "level %u face %u texel %zu: %g, expected %g", l, f, i - a,
                                  (double)px[4 * i], (double)pattern(l, f));
                    break;
                }
        }
    free(px);
    if (rc)
        return rc;
    lg_cpu_view sv;
    if ((rc = lg_map_cpu(n, p->solid_angle, LG_READ, &sv)))
        return rc;
    double sum = 0;
    for (size_t i = 0; i < (size_t)6 * d->width * d->height; i++)
        sum += ((const float *)sv.pixels)[i];
    if (fabs(sum - 4.0 * LG_PI) > 1e-4)
        return lg_error(n, "solid angles sum to %g, not 4 pi", sum);
    return write_1x1(n, 1.0f);
}

/* ---- partsteal, badparam --------------------------------------------------------------------- */

static const char *const steal_what[] = { "part", "texture", NULL };
static const lg_param_desc steal_params[] = {
    { .key = "what", .type = LG_PARAM_ENUM, .enum_values = steal_what, .doc = "how to steal" },
};
static const lg_port_desc steal_in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };

static int steal_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    if (!g_last_probe)
        return lg_error(n, "no probe was made before this node");
    if (lg_param_enum(n, "what") == 0)
        return lg_part(n, g_last_probe, "radiance") ? write_1x1(n, 1.0f) : LG_ERR_INVALID;
    /* the part handle as its producer saw it, mapped by a node that never received it */
    lg_cpu_view v;
    return lg_map_cpu(n, g_last_radiance, LG_READ, &v) ? LG_ERR_INVALID : write_1x1(n, 1.0f);
}

static int bad_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    double v = lg_param_float(n, "no_such_key");
    return write_1x1(n, (float)v);
}

/* ---- kindmaker, kindcheck -------------------------------------------------------------------- */

static const lg_param_desc kind_params[] = {
    { .key = "bands", .type = LG_PARAM_INT, .def.i = 3, .min = 1, .max = 64, .doc = "SH bands" },
    { .key = "vertices",
      .type = LG_PARAM_INT,
      .def.i = 5,
      .min = 1,
      .max = 1000,
      .doc = "vertices" },
};
static const lg_port_desc kind_ports[] = {
    { .name = "sh", .kind = LG_KIND_SH, .optional = true },
    { .name = "transfer", .kind = LG_KIND_TRANSFER, .optional = true },
    { .name = "froxel", .kind = LG_KIND_FROXEL, .optional = true },
};
enum { FX_W = 4, FX_H = 3, FX_D = 5 };

static int kmake_prepare(lg_node *n)
{
    uint32_t bands = (uint32_t)lg_param_int(n, "bands");
    int rc = lg_sh_declare(n, 0, bands);
    if (!rc)
        rc = lg_transfer_declare(n, 1, bands, (uint32_t)lg_param_int(n, "vertices"));
    if (!rc)
        rc = lg_froxel_declare(n, 2, FX_W, FX_H, FX_D, LG_FORMAT_RGBA32F);
    return rc;
}

/* element i of part `name` of output `port` holds i */
static int fill(lg_node *n, uint32_t port, const char *name)
{
    const lg_resource *p = lg_part(n, lg_output(n, port), name);
    lg_resource_info info;
    lg_cpu_view v;
    if (!p || lg_describe(p, &info, n) || lg_map_cpu(n, p, LG_WRITE, &v))
        return lg_error(n, "part '%s' cannot be written", name);
    size_t count = info.kind == LG_KIND_VOLUME ? (size_t)FX_W * FX_H * FX_D * 4
                                               : info.buffer.size / sizeof(float);
    for (size_t i = 0; i < count; i++)
        ((float *)v.pixels)[i] = (float)i;
    return 0;
}

static int kmake_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    uint32_t bands = (uint32_t)lg_param_int(n, "bands");
    lg_sh_info si = { .bands = bands, .flags = LG_SH_WINDOWED };
    lg_transfer_info ti = { .bands = bands,
                            .vertices = (uint32_t)lg_param_int(n, "vertices"),
                            .mode = LG_TRANSFER_SHADOWED };
    lg_froxel_info fi = { .width = FX_W,
                          .height = FX_H,
                          .depth = FX_D,
                          .slicing = LG_FROXEL_EXPONENTIAL,
                          .near = 0.1f,
                          .far = 50.0f };
    int rc = fill(n, 0, "coeffs");
    if (!rc)
        rc = fill(n, 1, "transfer");
    if (!rc)
        rc = fill(n, 2, "grid");
    if (!rc)
        rc = lg_sh_publish(n, 0, &si);
    if (!rc)
        rc = lg_transfer_publish(n, 1, &ti);
    return rc ? rc : lg_froxel_publish(n, 2, &fi);
}

static int counts_up(lg_node *n, const lg_resource *p, size_t count, const char *what)
{
    lg_cpu_view v;
    if (lg_map_cpu(n, p, LG_READ, &v))
        return LG_ERR_INVALID;
    for (size_t i = 0; i < count; i++)
        if (((const float *)v.pixels)[i] != (float)i)
            return lg_error(n, "%s: element %zu is %g", what, i,
                            (double)((const float *)v.pixels)[i]);
    return 0;
}

static int kcheck_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_sh sv;
    lg_transfer tv;
    lg_froxel fv;
    const lg_sh *sh = lg_sh_get(n, lg_input(n, 0), &sv);
    const lg_transfer *tr = lg_transfer_get(n, lg_input(n, 1), &tv);
    const lg_froxel *fx = lg_froxel_get(n, lg_input(n, 2), &fv);
    if (!sh || !tr || !fx)
        return lg_error(n, "a kind's accessor gave nothing");
    uint32_t b = (uint32_t)lg_param_int(n, "bands"), nv = (uint32_t)lg_param_int(n, "vertices");
    if (sh->info.bands != b || sh->n_coeffs != b * b || !(sh->info.flags & LG_SH_WINDOWED) ||
        tr->info.bands != b || tr->info.vertices != nv || tr->info.mode != LG_TRANSFER_SHADOWED ||
        fx->info.slicing != LG_FROXEL_EXPONENTIAL || fx->info.far != 50.0f ||
        fx->info.depth != FX_D)
        return lg_error(n, "an info struct did not arrive as written");
    int rc = counts_up(n, sh->coeffs, (size_t)3 * b * b, "sh coeffs");
    if (!rc)
        rc = counts_up(n, tr->transfer, (size_t)nv * 3 * b * b, "transfer");
    if (!rc)
        rc = counts_up(n, fx->grid, (size_t)FX_W * FX_H * FX_D * 4, "froxel grid");
    return rc ? rc : write_1x1(n, 1.0f);
}

static const lg_node_type types[] = {
    { .struct_size = sizeof(lg_node_type),
      .name = "partmaker",
      .doc = "a cube probe (test)",
      LG_PARAMS(maker_params),
      LG_OUTPUTS(maker_out),
      .prepare = maker_prepare,
      .execute = maker_execute },
    { .struct_size = sizeof(lg_node_type),
      .name = "partcheck",
      .doc = "checks a probe (test)",
      LG_PARAMS(check_params),
      LG_INPUTS(check_in),
      LG_OUTPUTS(img_out),
      .prepare = check_prepare,
      .execute = check_execute },
    { .struct_size = sizeof(lg_node_type),
      .name = "partsteal",
      .doc = "maps what it did not receive (test)",
      LG_PARAMS(steal_params),
      LG_INPUTS(steal_in),
      LG_OUTPUTS(img_out),
      .prepare = out_1x1,
      .execute = steal_execute },
    { .struct_size = sizeof(lg_node_type),
      .name = "badparam",
      .doc = "reads an undeclared parameter (test)",
      LG_OUTPUTS(img_out),
      .prepare = out_1x1,
      .execute = bad_execute },
    { .struct_size = sizeof(lg_node_type),
      .name = "kindmaker",
      .doc = "an SH, a transfer and a froxel resource (test)",
      LG_PARAMS(kind_params),
      LG_OUTPUTS(kind_ports),
      .prepare = kmake_prepare,
      .execute = kmake_execute },
    { .struct_size = sizeof(lg_node_type),
      .name = "kindcheck",
      .doc = "reads them back (test)",
      LG_PARAMS(kind_params),
      LG_INPUTS(kind_ports),
      LG_OUTPUTS(img_out),
      .prepare = out_1x1,
      .execute = kcheck_execute },
};

LG_PLUGIN_DEFINE("testparts", "1.0.0", "Composite resources (test)", types)
