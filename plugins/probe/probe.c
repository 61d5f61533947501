/*
 * The probe plugin: the `probe` node reads a light probe from image files in any of the
 * layouts lightgraph knows (lat-long, Debevec's angular map, a cube as a horizontal or
 * vertical cross, a 6x1 or 1x6 strip, or six face files) and outputs the probe resource
 * (lightgraph/probe.h) on the CPU: the radiance (2D for lat-long and angular, an
 * LG_IMAGE_CUBE in OpenGL's face order for the others), its exact solid angles and its
 * info (layout, rotation, the scale applied).
 *
 * All file work happens in prepare() (the size decides the declared resource), in
 * probe_load.c (apart so that tests/fuzz/fuzz_probe.c runs it alone); execute() copies
 * the texels and fills the solid angles. README.md has the conventions, the
 * cross diagrams, the errors and the measured cost; docs/probes.md the same conventions
 * next to the rest of the probe maths.
 */
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"
#include "probe_load.h"

typedef struct pr_state {
    pr_file f; /* the texels as read (probe_load.h) */
    float rotation[9];
    float scale;
} pr_state;

/* Fills st from the files the parameters name (probe_load.c reads them). */
static int pr_load(lg_node *n, pr_state *st, uint64_t *key)
{
    const char *faces[6] = { NULL };
    uint32_t n_faces = lg_param_list_count(n, "faces");
    for (uint32_t f = 0; f < 6 && f < n_faces; f++)
        faces[f] = lg_param_list_item(n, "faces", f);
    return pr_load_file(n, lg_param_enum(n, "layout"), lg_param_string(n, "file"), faces, n_faces,
                        &st->f, key);
}

/* exposure and scale: one factor on every colour channel. A product beyond the float
 * range is clamped to FLT_MAX (a sun stays the brightest thing, not black) and said. */
static int pr_apply_scale(lg_node *n, pr_state *st)
{
    double exposure = lg_param_float(n, "exposure"), scale = lg_param_float(n, "scale");
    double f = exp2(exposure) * scale;
    if (!isfinite(f) || f < 0 || f > FLT_MAX)
        return lg_error(n,
                        "exposure = %g and scale = %g give a factor %g that a float cannot "
                        "hold",
                        exposure, scale, f);
    st->scale = (float)f;
    if (f == 1.0)
        return 0;
    size_t texels = (size_t)st->f.width * st->f.height * (st->f.layout == LG_PROBE_CUBE ? 6 : 1);
    uint64_t over = 0;
    for (size_t i = 0; i < texels; i++)
        for (int c = 0; c < 3; c++) {
            float *p = st->f.texels + 4 * i + c;
            double v = (double)*p * f;
            if (v > FLT_MAX) {
                v = FLT_MAX;
                over++;
            }
            *p = (float)v;
        }
    if (over)
        lg_log(n, LG_LOG_WARN,
               "exposure = %g, scale = %g: %" PRIu64 " channel value%s beyond "
               "the float range clamped to %g",
               exposure, scale, over, over == 1 ? "" : "s", (double)FLT_MAX);
    return 0;
}

static int probe_prepare(lg_node *n)
{
    pr_state *st = n->user;
    if (!st) {
        st = lg_create_state(n, sizeof *st);
        if (!st)
            return LG_ERR_NOMEM;
    }
    pr_file_clear(&st->f);
    uint64_t key = 0;
    int rc = pr_load(n, st, &key);
    if (!rc)
        rc = pr_apply_scale(n, st);
    if (rc) {
        pr_file_clear(&st->f);
        return rc;
    }
    lg_add_content_key(n, &key, sizeof key);

    const lg_value *r = lg_param(n, "rotate_deg");
    lg_probe_rotation_from_euler((float)r->v[0], (float)r->v[1], (float)r->v[2], st->rotation);

    lg_image_desc d = { .width = st->f.width,
                        .height = st->f.height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = st->f.layout == LG_PROBE_CUBE ? LG_IMAGE_CUBE : 0u };
    if ((rc = lg_probe_declare(n, 0, st->f.layout, &d, true)))
        return rc;
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int probe_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    pr_state *st = n->user;
    const lg_resource *out = lg_output(n, 0);
    const lg_resource *rad = out ? lg_part(n, out, "radiance") : NULL;
    const lg_resource *sa = out ? lg_part(n, out, "solid_angle") : NULL;
    if (!st || !st->f.texels || !rad || !sa)
        return lg_error(n, "the probe's parts were not declared (prepare failed?)");
    lg_cpu_view v, sv;
    int rc;
    if ((rc = lg_map_cpu(n, rad, LG_WRITE, &v)) || (rc = lg_map_cpu(n, sa, LG_WRITE, &sv)))
        return rc;
    uint32_t faces = st->f.layout == LG_PROBE_CUBE ? 6 : 1;
    /* rows row_pixels apart (== width today); a cube's faces follow each other */
    for (uint32_t f = 0; f < faces; f++)
        for (uint32_t y = 0; y < st->f.height; y++) {
            size_t row = (size_t)f * st->f.height + y;
            memcpy((float *)v.pixels + row * v.row_pixels * 4, st->f.texels + row * st->f.width * 4,
                   (size_t)st->f.width * 16);
        }
    if ((rc = lg_probe_solid_angles(st->f.layout, st->f.width, st->f.height, sv.pixels)))
        return lg_error_code(n, rc, "solid angles of a %ux%u probe", st->f.width, st->f.height);
    lg_probe_info info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    info.layout = st->f.layout;
    memcpy(info.rotation, st->rotation, sizeof info.rotation);
    info.scale = st->scale;
    info.filter = LG_PROBE_FILTER_NONE;
    info.file_layout = st->f.file_layout;
    return lg_probe_publish(n, 0, &info);
}

static void probe_destroy(lg_node *n)
{
    pr_state *st = n->user;
    if (!st)
        return;
    pr_file_clear(&st->f);
    free(st);
    n->user = NULL;
}

/* ---- probe_convert --------------------------------------------------------------------------- */

/* The `layout` parameter of probe_convert, in the enum's order. */
enum { PC_LATLONG = 0, PC_ANGULAR, PC_CROSS, PC_VCROSS, PC_STRIP, PC_VSTRIP };

typedef struct pc_state {
    lg_probe_layout layout;
    lg_probe_file_layout file_layout;
    uint32_t width, height; /* the output's radiance size (a cube's face size) */
} pc_state;

/* The output size for `size` = 0: the destination whose texel count over the sphere is
 * nearest the source image's (W x H for a 2D image, 6 N^2 for a cube): lat-long 2H x H
 * with 2 H^2 texels, a cube 6 N^2, an angular map's disc pi S^2 / 4. The source's layout
 * is not needed (its info is written in execute, after this prepare): only the number of
 * texels it holds. */
#define PC_SECONDS_PER_TEXEL 4e-5

static void pc_auto_size(double texels, lg_probe_layout l, uint32_t *w, uint32_t *h)
{
    double s = l == LG_PROBE_LATLONG ? sqrt(texels / 2)
               : l == LG_PROBE_CUBE  ? sqrt(texels / 6)
                                     : sqrt(texels * 4 / LG_PROBE_PI_F);
    uint32_t n = s < 1 ? 1 : s > 8192 ? 8192 : (uint32_t)lround(s);
    *h = n;
    *w = l == LG_PROBE_LATLONG ? 2 * n : n;
}

static int convert_prepare(lg_node *n)
{
    pc_state *st = n->user;
    if (!st) {
        st = lg_create_state(n, sizeof *st);
        if (!st)
            return LG_ERR_NOMEM;
    }
    const lg_resource *in = lg_input(n, 0);
    lg_resource_info ri, rad;
    if (!in || lg_describe(in, &ri, n) != 0 || ri.kind != LG_KIND_PROBE)
        return lg_error(n, "input 'probe' is not a probe (a `probe` node makes one)");
    const lg_resource *r = ri.neutral ? NULL : lg_part(n, in, "radiance");
    if (!r || lg_describe(r, &rad, n) != 0)
        return lg_error(n, "input 'probe' has no radiance (is its producer gated?)");
    int layout = lg_param_enum(n, "layout");
    static const lg_probe_layout layouts[] = { LG_PROBE_LATLONG, LG_PROBE_ANGULAR, LG_PROBE_CUBE,
                                               LG_PROBE_CUBE,    LG_PROBE_CUBE,    LG_PROBE_CUBE };
    static const lg_probe_file_layout files[] = { LG_PROBE_FILE_DEFAULT, LG_PROBE_FILE_DEFAULT,
                                                  LG_PROBE_FILE_CROSS,   LG_PROBE_FILE_VCROSS,
                                                  LG_PROBE_FILE_STRIP,   LG_PROBE_FILE_VSTRIP };
    if (layout < 0 || layout > PC_VSTRIP)
        return lg_error(n, "unknown layout %d", layout);
    st->layout = layouts[layout];
    st->file_layout = files[layout];
    int64_t size = lg_param_int(n, "size");
    if (size > 0) {
        st->height = (uint32_t)size;
        st->width = st->layout == LG_PROBE_LATLONG ? 2 * (uint32_t)size : (uint32_t)size;
    } else {
        double texels = (double)rad.image.width * rad.image.height *
                        ((rad.image.flags & LG_IMAGE_CUBE) ? 6 : 1);
        pc_auto_size(texels, st->layout, &st->width, &st->height);
    }
    lg_log(n, LG_LOG_DEBUG, "%ux%u%s -> %s %ux%u", rad.image.width, rad.image.height,
           (rad.image.flags & LG_IMAGE_CUBE) ? " cube" : "",
           st->layout == LG_PROBE_LATLONG   ? "lat-long"
           : st->layout == LG_PROBE_ANGULAR ? "angular map"
                                            : "cube",
           st->width, st->height);
    lg_image_desc d = { .width = st->width,
                        .height = st->height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = st->layout == LG_PROBE_CUBE ? LG_IMAGE_CUBE : 0u };
    int rc = lg_probe_declare(n, 0, st->layout, &d, true);
    if (rc)
        return rc; /* the host refused a size over the pixel limit or the machine's memory */
    /* the resampling's working memory (the overlap matrix and its balancing), which the
     * declared output does not include, before anything runs */
    uint64_t src_n = (uint64_t)rad.image.width * rad.image.height *
                     ((rad.image.flags & LG_IMAGE_CUBE) ? 6 : 1);
    uint64_t dst_n = (uint64_t)st->width * st->height * (st->layout == LG_PROBE_CUBE ? 6 : 1);
    uint64_t need = lg_probe_resample_bytes(src_n, dst_n);
    const char *bound;
    uint64_t avail = lg_memory_available(&bound);
    if (need > avail) {
        char a[32], b[32];
        lg_bytes_text(a, sizeof a, need);
        lg_bytes_text(b, sizeof b, avail);
        return lg_error_code(n, LG_ERR_NOMEM,
                             "size = %lld: resampling the %ux%u%s probe (%llu texels) into "
                             "%ux%u%s (%llu texels) needs %s (%llu bytes) of working memory, "
                             "more than the %s (%llu bytes) of %s; lower size (0 keeps the "
                             "probe's texel count)",
                             (long long)size, rad.image.width, rad.image.height,
                             (rad.image.flags & LG_IMAGE_CUBE) ? " cube" : "",
                             (unsigned long long)src_n, st->width, st->height,
                             st->layout == LG_PROBE_CUBE ? " x 6 faces" : "",
                             (unsigned long long)dst_n, a, (unsigned long long)need, b,
                             (unsigned long long)avail, bound);
    }
    /* the estimate: the area-weighted resampling costs about PC_SECONDS_PER_TEXEL per
     * texel of the source and of the result together, on one thread; measured here
     * (2-core VM shared with compiles, LIGHTGRAPH_THREADS=1): the 1024x512 forest into
     * crosses of 64, 128 and 256 in 17.6, 19.6 and 35 s, 3.2e-5 to 3.8e-5 s per texel;
     * part of it runs on the host's threads */
    double texels = (double)rad.image.width * rad.image.height *
                        ((rad.image.flags & LG_IMAGE_CUBE) ? 6 : 1) +
                    (double)st->width * st->height * (st->layout == LG_PROBE_CUBE ? 6 : 1);
    lg_declare_work(n, texels, texels * PC_SECONDS_PER_TEXEL / lg_cpu_workers(n),
                    "texels resampled (source and result)");
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int convert_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    pc_state *st = n->user;
    lg_probe src;
    if (!st || !lg_probe_get(n, lg_input(n, 0), &src))
        return lg_error(n, "input 'probe' is not a probe");
    const lg_resource *out = lg_output(n, 0);
    const lg_resource *rad = out ? lg_part(n, out, "radiance") : NULL;
    const lg_resource *sa = out ? lg_part(n, out, "solid_angle") : NULL;
    if (!rad || !sa)
        return lg_error(n, "the probe's parts were not declared (prepare failed?)");
    lg_cpu_view in, v, sv;
    int rc;
    if ((rc = lg_map_cpu(n, src.radiance, LG_READ, &in)) ||
        (rc = lg_map_cpu(n, rad, LG_WRITE, &v)) || (rc = lg_map_cpu(n, sa, LG_WRITE, &sv)))
        return rc;
    /* level 0 of the source (a prefiltered chain's other levels are not converted), read
     * with its rotation: resampling into the identity bakes it in */
    lg_probe_image img = lg_probe_image_at(src.info.layout, &src.radiance_desc, in.pixels, 0,
                                           src.info.rotation);
    uint32_t faces = st->layout == LG_PROBE_CUBE ? 6 : 1;
    size_t texels = (size_t)st->width * st->height * faces;
    float *buf = v.row_pixels == st->width ? v.pixels : malloc(texels * 16);
    if (!buf)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu texels)", texels);
    lg_probe_resample_stats stats;
    rc = lg_probe_resample_pool(n, &img, st->layout, st->width, st->height, NULL, NULL, buf,
                                &stats);
    /* alpha 1 everywhere, as the probe node makes it (a probe's alpha has no meaning; the
     * resampler leaves 0 outside the angular disc), so that a written probe read back is
     * the same probe */
    for (size_t k = 0; !rc && k < texels; k++)
        buf[4 * k + 3] = 1.0f;
    if (buf != v.pixels) {
        for (size_t row = 0; !rc && row < (size_t)faces * st->height; row++)
            memcpy((float *)v.pixels + row * v.row_pixels * 4, buf + row * st->width * 4,
                   (size_t)st->width * 16);
        free(buf);
    }
    if (rc) {
        char a[32] = "";
        lg_bytes_text(a, sizeof a,
                      lg_probe_resample_bytes((uint64_t)img.width * img.height *
                                                  (img.layout == LG_PROBE_CUBE ? 6 : 1),
                                              (uint64_t)texels));
        return lg_error_code(n, rc, "resampling the %ux%u probe into %ux%u failed%s%s%s", img.width,
                             img.height, st->width, st->height,
                             rc == LG_ERR_NOMEM ? ": out of memory (its working memory, at "
                                                  "least "
                                                : "",
                             rc == LG_ERR_NOMEM ? a : "", rc == LG_ERR_NOMEM ? ")" : "");
    }
    lg_log(n, LG_LOG_DEBUG,
           "%llu sub-rectangles, %llu texel pairs, %u balancing rounds; "
           "integral error %.2e before balancing, %.2e after",
           (unsigned long long)stats.samples, (unsigned long long)stats.entries, stats.iterations,
           stats.raw_total_error, stats.total_error);
    if ((rc = lg_probe_solid_angles(st->layout, st->width, st->height, sv.pixels)))
        return lg_error_code(n, rc, "solid angles of a %ux%u probe", st->width, st->height);
    lg_probe_info info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    info.layout = st->layout;
    lg_probe_rotation_from_euler(0, 0, 0, info.rotation); /* baked in */
    info.scale = src.info.scale;
    info.filter = LG_PROBE_FILTER_NONE;
    info.file_layout = st->file_layout;
    return lg_probe_publish(n, 0, &info);
}

static void convert_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static const char *const pr_layouts[] = { "auto",  "latlong", "angular", "cross",
                                          "strip", "faces",   NULL };
static const lg_param_desc probe_params[] = {
    { .key = "file",
      .type = LG_PARAM_PATH,
      .def.s = "",
      .doc = "probe image: .exr (any compression), .hdr, or .png (sRGB decoded to linear, "
             "at most 1: low dynamic range); empty with layout = faces" },
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = PR_LAYOUT_AUTO,
      .enum_values = pr_layouts,
      .doc = "auto (from the size: 2:1 latlong, 1:1 angular, 4:3 / 3:4 cross, 6:1 / 1:6 "
             "strip), or say which; faces reads the list `faces`" },
    { .key = "faces",
      .type = LG_PARAM_PATH_LIST,
      .doc = "layout = faces: six files, [+X, -X, +Y, -Y, +Z, -Z], square, one size" },
    { .key = "rotate_deg",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .min = -1e6,
      .max = 1e6,
      .doc = "[yaw, pitch, roll], degrees: probe -> world, R = Ry(yaw) Rx(pitch) Rz(roll)" },
    { .key = "exposure",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -64,
      .max = 64,
      .doc = "stops: the texels are multiplied by 2^exposure" },
    { .key = "scale",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e9,
      .doc = "linear multiplier of the texels (with 2^exposure: info.scale)" },
};
static const lg_port_desc probe_outputs[] = {
    { .name = "probe",
      .kind = LG_KIND_PROBE,
      .doc = "radiance (rgba32f; 2D or GL cube), solid_angle, info; on the CPU" },
};

static const char *const pc_layouts[] = { "latlong", "angular", "cross", "vcross",
                                          "strip",   "vstrip",  NULL };
static const lg_param_desc convert_params[] = {
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = PC_LATLONG,
      .enum_values = pc_layouts,
      .doc = "latlong, angular, or a cube written (by an output) as a horizontal cross, a "
             "vertical cross, a 6x1 strip or a 1x6 strip" },
    { .key = "size",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 8192,
      .doc = "cube face size, lat-long height (width 2x), angular side; 0 = as many texels "
             "on the sphere as the source image has" },
};
static const lg_port_desc convert_inputs[] = {
    { .name = "probe", .kind = LG_KIND_PROBE, .doc = "the probe to convert (any layout)" },
};
static const lg_port_desc convert_outputs[] = {
    { .name = "probe",
      .kind = LG_KIND_PROBE,
      .doc = "the probe area-resampled into `layout`, its rotation baked in; on the CPU" },
};

static const lg_node_type probe_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "probe",
        .doc = "reads a light probe: lat-long, angular map, cross, strip or six faces",
        LG_PARAMS(probe_params),
        LG_OUTPUTS(probe_outputs),
        .prepare = probe_prepare,
        .execute = probe_execute,
        .destroy = probe_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "probe_convert",
        .doc = "area-weighted resampling of a probe into another layout and size (its "
               "integral over any region kept); an output writes it as EXR or HDR",
        LG_PARAMS(convert_params),
        LG_INPUTS(convert_inputs),
        LG_OUTPUTS(convert_outputs),
        .prepare = convert_prepare,
        .execute = convert_execute,
        .destroy = convert_destroy,
    },
};

LG_PLUGIN_DEFINE("probe", "1.0.0", "Light probes from files in every layout", probe_types)
