/*
 * The probe plugin: the `probe` node reads a light probe from image files in any of the
 * layouts lightgraph knows (lat-long, Debevec's angular map, a cube as a horizontal or
 * vertical cross, a 6x1 or 1x6 strip, or six face files) and outputs the probe resource
 * (lightgraph/probe.h) on the CPU: the radiance (2D for lat-long and angular, an
 * LG_IMAGE_CUBE in OpenGL's face order for the others), its exact solid angles and its
 * info (layout, rotation, the scale applied).
 *
 * All file work happens in prepare() (the size decides the declared resource); execute()
 * copies the texels and fills the solid angles. README.md has the conventions, the
 * cross diagrams, the errors and the measured cost; docs/probes.md the same conventions
 * next to the rest of the probe maths.
 */
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"

/* What a file holds, more precisely than lg_probe_layout: where the cube's faces sit. */
typedef enum pr_source {
    PR_NONE = 0,
    PR_LATLONG,
    PR_ANGULAR,
    PR_CROSS_H, /* 4:3 */
    PR_CROSS_V, /* 3:4 */
    PR_STRIP_H, /* 6:1 */
    PR_STRIP_V, /* 1:6 */
    PR_FACES,   /* six files */
} pr_source;

static const char *const pr_source_names[] = {
    "none", "lat-long", "angular map", "horizontal cross", "vertical cross",
    "6x1 strip", "1x6 strip", "six face files",
};

/* The `layout` parameter's values, in the enum's order. */
enum { PR_LAYOUT_AUTO = 0, PR_LAYOUT_LATLONG, PR_LAYOUT_ANGULAR, PR_LAYOUT_CROSS,
       PR_LAYOUT_STRIP, PR_LAYOUT_FACES };

static const char *const pr_face_names[6] = { "+X", "-X", "+Y", "-Y", "+Z", "-Z" };

/* Where the faces sit in a cross or a strip: lg_probe_file_cell (lightgraph/probe.h), the
 * table lg_probe_pack writes with, so that reading and writing are inverses. The
 * horizontal cross holds every face as OpenGL orients it; the vertical one turns -Z
 * (below -Y) by 180 degrees, as cmft and HDRShop do, so that its edges meet -Y's.
 * docs/probes.md draws both. */
static lg_probe_file_layout pr_file_layout(pr_source src)
{
    return src == PR_CROSS_H ? LG_PROBE_FILE_CROSS : src == PR_CROSS_V ? LG_PROBE_FILE_VCROSS
         : src == PR_STRIP_H ? LG_PROBE_FILE_STRIP : src == PR_STRIP_V ? LG_PROBE_FILE_VSTRIP
         : LG_PROBE_FILE_DEFAULT;
}

typedef struct pr_state {
    lg_probe_layout layout;
    uint32_t width, height; /* the radiance image's size (a cube's face size) */
    float *texels;          /* level 0, RGBA, packed as the CPU copy (faces, rows) */
    lg_image decoded;       /* 2D layouts: the decoded file, whose pixels are `texels`
                             * (freed by the SDK that allocated them) */
    float rotation[9];
    float scale;
    lg_probe_file_layout file_layout; /* how the cube was stored: an output writes it so */
} pr_state;

static void pr_state_clear(pr_state *st)
{
    if (st->decoded.pixels)
        lg_image_free(&st->decoded);
    else
        free(st->texels);
    st->texels = NULL;
    memset(&st->decoded, 0, sizeof st->decoded);
    st->file_layout = LG_PROBE_FILE_DEFAULT;
}

/* Reads one file as stored (no clamping: pr_sanitize counts and zeroes what a probe
 * cannot hold, with one warning per file). */
static int pr_read(lg_node *n, const char *path, const char *what, lg_image *img)
{
    if (!path || !*path)
        return lg_error(n, "parameter '%s' is empty: name an .exr or .hdr file", what);
    char err[512];
    int rc = lg_image_read(path, 0, img, NULL, err, sizeof err);
    if (rc)
        return lg_error_code(n, rc, "%s", err); /* names the file and the reason */
    return 0;
}

/* Zeroes negative, NaN and infinite colour channels, sets alpha to 1 (a probe's alpha has
 * no meaning), and warns once for the file with the counts of pixels affected. */
static void pr_sanitize(lg_node *n, const char *path, lg_image *img)
{
    uint64_t neg = 0, nan = 0, inf = 0;
    size_t px = (size_t)img->width * img->height;
    for (size_t i = 0; i < px; i++) {
        float *p = img->pixels + 4 * i;
        bool has_neg = false, has_nan = false, has_inf = false;
        for (int c = 0; c < 3; c++) {
            if (isnan(p[c])) {
                has_nan = true;
                p[c] = 0.0f;
            } else if (isinf(p[c])) {
                has_inf = true;
                p[c] = 0.0f;
            } else if (p[c] < 0.0f) {
                has_neg = true;
                p[c] = 0.0f;
            } else if (p[c] == 0.0f) {
                p[c] = 0.0f; /* -0 becomes +0: the same bits for the same light */
            }
        }
        p[3] = 1.0f;
        neg += has_neg;
        nan += has_nan;
        inf += has_inf;
    }
    if (neg + nan + inf)
        lg_log(n, LG_LOG_WARN,
               "file '%s' (%ux%u): set to 0 the colour channels of %" PRIu64 " pixel%s "
               "that a probe cannot hold: %" PRIu64 " negative, %" PRIu64 " NaN, %" PRIu64
               " infinite",
               path, img->width, img->height, neg + nan + inf, neg + nan + inf == 1 ? "" : "s",
               neg, nan, inf);
}

/* w/h within 1% of num/den. */
static bool pr_near_ratio(uint32_t w, uint32_t h, uint32_t num, uint32_t den)
{
    double r = ((double)w * den) / ((double)h * num);
    return r > 0.99 && r < 1.0101;
}

/* The source layout an image's size means, or PR_NONE after an error that names the
 * file, its size and what it could be. `want` is the `layout` parameter. */
static pr_source pr_detect(lg_node *n, const char *path, uint32_t w, uint32_t h, int want)
{
    bool ll = w == 2 * h, ang = w == h;
    bool ch = w % 4 == 0 && h % 3 == 0 && w / 4 == h / 3;
    bool cv = w % 3 == 0 && h % 4 == 0 && w / 3 == h / 4;
    bool sh = w == 6 * h, sv = h == 6 * w;
    switch (want) {
    case PR_LAYOUT_LATLONG:
        if (!ll)
            lg_log(n, LG_LOG_INFO,
                   "file '%s' is %ux%u, not 2:1: read as a lat-long all the same (layout = "
                   "latlong; every row spans 360 degrees and the rows 180, whatever the size)",
                   path, w, h);
        return PR_LATLONG;
    case PR_LAYOUT_ANGULAR:
        if (ang)
            return PR_ANGULAR;
        lg_error(n, "file '%s' is %ux%u: an angular map (layout = angular) is square", path,
                 w, h);
        return PR_NONE;
    case PR_LAYOUT_CROSS:
        if (ch)
            return PR_CROSS_H;
        if (cv)
            return PR_CROSS_V;
        lg_error(n, "file '%s' is %ux%u: a cross (layout = cross) is 4N x 3N (horizontal) or "
                    "3N x 4N (vertical) with N the face size",
                 path, w, h);
        return PR_NONE;
    case PR_LAYOUT_STRIP:
        if (sh)
            return PR_STRIP_H;
        if (sv)
            return PR_STRIP_V;
        lg_error(n, "file '%s' is %ux%u: a strip (layout = strip) is 6N x N or N x 6N with N "
                    "the face size",
                 path, w, h);
        return PR_NONE;
    default:
        break;
    }
    /* auto: exactly one exact match (the ratios 2:1, 1:1, 4:3, 3:4, 6:1 and 1:6 exclude
     * each other, so an exact size is never ambiguous) */
    if (ll)
        return PR_LATLONG;
    if (ang)
        return PR_ANGULAR;
    if (ch)
        return PR_CROSS_H;
    if (cv)
        return PR_CROSS_V;
    if (sh)
        return PR_STRIP_H;
    if (sv)
        return PR_STRIP_V;
    /* not exact: name the layouts whose ratio it nearly has */
    char near[256] = "";
    static const struct { uint32_t num, den; const char *name; } ratios[] = {
        { 2, 1, "lat-long (2:1; layout = latlong reads any size)" },
        { 1, 1, "angular map (1:1)" },
        { 4, 3, "horizontal cross (4N x 3N)" },
        { 3, 4, "vertical cross (3N x 4N)" },
        { 6, 1, "6x1 strip (6N x N)" },
        { 1, 6, "1x6 strip (N x 6N)" },
    };
    for (size_t i = 0; i < sizeof ratios / sizeof ratios[0]; i++)
        if (pr_near_ratio(w, h, ratios[i].num, ratios[i].den)) {
            size_t len = strlen(near);
            snprintf(near + len, sizeof near - len, "%s%s", len ? ", " : "", ratios[i].name);
        }
    if (*near)
        lg_error(n, "file '%s' is %ux%u: ambiguous; its shape is near %s but not exactly: "
                    "set `layout` to say which",
                 path, w, h, near);
    else
        lg_error(n, "file '%s' is %ux%u: no probe layout has this shape (auto recognises "
                    "2:1 lat-long, 1:1 angular, 4:3 and 3:4 crosses, 6:1 and 1:6 strips); "
                    "set `layout` (latlong reads any size)",
                 path, w, h);
    return PR_NONE;
}

/* Copies face f of a cube from its cell (cx, cy) of a larger image, turned by 180 degrees
 * when `turn`. */
static void pr_copy_face(float *dst, const lg_image *src, uint32_t N, int cx, int cy, int turn)
{
    for (uint32_t y = 0; y < N; y++)
        for (uint32_t x = 0; x < N; x++) {
            uint32_t sx = turn ? N - 1 - x : x, sy = turn ? N - 1 - y : y;
            const float *s = src->pixels +
                             4 * ((size_t)((uint32_t)cy * N + sy) * src->width +
                                  (uint32_t)cx * N + sx);
            memcpy(dst + 4 * ((size_t)y * N + x), s, 16);
        }
}

/* Fills st from the files. */
static int pr_load(lg_node *n, pr_state *st, uint64_t *key)
{
    int want = lg_param_enum(n, "layout");
    const char *file = lg_param_string(n, "file");
    bool have_file = file && *file;
    uint32_t have_faces = lg_param_list_count(n, "faces");
    if (want == PR_LAYOUT_AUTO && !have_file && have_faces)
        want = PR_LAYOUT_FACES;
    uint64_t h = LG_IMAGE_HASH_SEED;

    if (want == PR_LAYOUT_FACES) {
        if (have_file)
            return lg_error(n, "layout = faces reads the six files of 'faces'; 'file' ('%s') "
                               "is set too: leave it empty",
                            file);
        if (have_faces != 6)
            return lg_error(n, "layout = faces needs six files in 'faces' (+X, -X, +Y, -Y, +Z, "
                               "-Z), found %u",
                            have_faces);
        lg_image img[6];
        memset(img, 0, sizeof img);
        int rc = 0;
        uint32_t N = 0;
        const char *first = lg_param_list_item(n, "faces", 0);
        for (uint32_t f = 0; f < 6 && !rc; f++) {
            const char *p = lg_param_list_item(n, "faces", f);
            char what[64];
            snprintf(what, sizeof what, "faces[%u]", f);
            if ((rc = pr_read(n, p, what, &img[f])))
                break;
            if (img[f].width != img[f].height)
                rc = lg_error(n, "face file '%s' (faces[%u], the %s face) is %ux%u: faces are "
                                 "square",
                              p, f, pr_face_names[f], img[f].width, img[f].height);
            else if (f > 0 && img[f].width != N)
                rc = lg_error(n, "face file '%s' (faces[%u], the %s face) is %ux%u but '%s' "
                                 "(faces[0]) is %ux%u: the six faces have one size",
                              p, f, pr_face_names[f], img[f].width, img[f].height, first, N, N);
            N = img[f].width;
        }
        if (!rc) {
            st->texels = malloc((size_t)6 * N * N * 16);
            if (!st->texels)
                rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory (a cube of 6 x %ux%u)", N, N);
        }
        for (uint32_t f = 0; f < 6 && !rc; f++) {
            pr_sanitize(n, lg_param_list_item(n, "faces", f), &img[f]);
            h = lg_image_hash(&img[f], h);
            memcpy(st->texels + (size_t)4 * f * N * N, img[f].pixels, (size_t)N * N * 16);
        }
        for (int f = 0; f < 6; f++)
            lg_image_free(&img[f]);
        if (rc)
            return rc;
        st->layout = LG_PROBE_CUBE;
        st->width = st->height = N;
        h = (h ^ PR_FACES) * 0x100000001b3ull;
        *key = h;
        return 0;
    }

    if (have_faces)
        return lg_error(n, "'faces' is for layout = faces; this probe reads 'file' (layout = %s): "
                           "leave 'faces' empty",
                        want == PR_LAYOUT_AUTO ? "auto" : "a single-file layout");
    lg_image img;
    memset(&img, 0, sizeof img);
    int rc = pr_read(n, file, "file", &img);
    if (rc)
        return rc;
    pr_source src = pr_detect(n, file, img.width, img.height, want);
    if (src == PR_NONE) {
        lg_image_free(&img);
        return LG_ERR_INVALID;
    }
    pr_sanitize(n, file, &img);
    h = lg_image_hash(&img, h);
    h = (h ^ (uint64_t)src) * 0x100000001b3ull;
    *key = h;
    lg_log(n, LG_LOG_DEBUG, "file '%s' (%ux%u): %s", file, img.width, img.height,
           pr_source_names[src]);

    if (src == PR_LATLONG || src == PR_ANGULAR) {
        st->layout = src == PR_LATLONG ? LG_PROBE_LATLONG : LG_PROBE_ANGULAR;
        st->width = img.width;
        st->height = img.height;
        st->decoded = img; /* kept: texels are its pixels */
        st->texels = img.pixels;
        return 0;
    }
    uint32_t N = src == PR_CROSS_H ? img.width / 4 : src == PR_CROSS_V ? img.width / 3
               : src == PR_STRIP_H ? img.height : img.width;
    st->texels = malloc((size_t)6 * N * N * 16);
    if (!st->texels) {
        lg_image_free(&img);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (a cube of 6 x %ux%u)", N, N);
    }
    st->file_layout = pr_file_layout(src);
    for (uint32_t f = 0; f < 6; f++) {
        uint32_t cx, cy;
        bool turn;
        lg_probe_file_cell(st->file_layout, f, &cx, &cy, &turn);
        pr_copy_face(st->texels + (size_t)4 * f * N * N, &img, N, (int)cx, (int)cy, turn);
    }
    lg_image_free(&img);
    st->layout = LG_PROBE_CUBE;
    st->width = st->height = N;
    return 0;
}

/* exposure and scale: one factor on every colour channel. A product beyond the float
 * range is clamped to FLT_MAX (a sun stays the brightest thing, not black) and said. */
static int pr_apply_scale(lg_node *n, pr_state *st)
{
    double exposure = lg_param_float(n, "exposure"), scale = lg_param_float(n, "scale");
    double f = exp2(exposure) * scale;
    if (!isfinite(f) || f < 0 || f > FLT_MAX)
        return lg_error(n, "exposure = %g and scale = %g give a factor %g that a float cannot "
                           "hold",
                        exposure, scale, f);
    st->scale = (float)f;
    if (f == 1.0)
        return 0;
    size_t texels = (size_t)st->width * st->height * (st->layout == LG_PROBE_CUBE ? 6 : 1);
    uint64_t over = 0;
    for (size_t i = 0; i < texels; i++)
        for (int c = 0; c < 3; c++) {
            float *p = st->texels + 4 * i + c;
            double v = (double)*p * f;
            if (v > FLT_MAX) {
                v = FLT_MAX;
                over++;
            }
            *p = (float)v;
        }
    if (over)
        lg_log(n, LG_LOG_WARN, "exposure = %g, scale = %g: %" PRIu64 " channel value%s beyond "
                               "the float range clamped to %g",
               exposure, scale, over, over == 1 ? "" : "s", (double)FLT_MAX);
    return 0;
}

static int probe_prepare(lg_node *n)
{
    pr_state *st = n->user;
    if (!st) {
        st = calloc(1, sizeof *st);
        if (!st)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
        n->user = st;
    }
    pr_state_clear(st);
    uint64_t key = 0;
    int rc = pr_load(n, st, &key);
    if (!rc)
        rc = pr_apply_scale(n, st);
    if (rc) {
        pr_state_clear(st);
        return rc;
    }
    n->host->add_content_key(n, &key, sizeof key);

    const lg_value *r = lg_param(n, "rotate_deg");
    lg_probe_rotation_from_euler((float)r->v[0], (float)r->v[1], (float)r->v[2], st->rotation);

    lg_image_desc d = { .width = st->width, .height = st->height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = st->layout == LG_PROBE_CUBE ? LG_IMAGE_CUBE : 0u };
    if ((rc = lg_probe_declare(n, 0, st->layout, &d, true)))
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
    if (!st || !st->texels || !rad || !sa)
        return lg_error(n, "the probe's parts were not declared (prepare failed?)");
    lg_cpu_view v, sv;
    int rc;
    if ((rc = lg_map_cpu(n, rad, LG_WRITE, &v)) || (rc = lg_map_cpu(n, sa, LG_WRITE, &sv)))
        return rc;
    uint32_t faces = st->layout == LG_PROBE_CUBE ? 6 : 1;
    /* rows row_pixels apart (== width today); a cube's faces follow each other */
    for (uint32_t f = 0; f < faces; f++)
        for (uint32_t y = 0; y < st->height; y++) {
            size_t row = (size_t)f * st->height + y;
            memcpy((float *)v.pixels + row * v.row_pixels * 4,
                   st->texels + row * st->width * 4, (size_t)st->width * 16);
        }
    if ((rc = lg_probe_solid_angles(st->layout, st->width, st->height, sv.pixels)))
        return lg_error_code(n, rc, "solid angles of a %ux%u probe", st->width, st->height);
    lg_probe_info info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    info.layout = st->layout;
    memcpy(info.rotation, st->rotation, sizeof info.rotation);
    info.scale = st->scale;
    info.filter = LG_PROBE_FILTER_NONE;
    info.file_layout = st->file_layout;
    return lg_probe_publish(n, 0, &info);
}

static void probe_destroy(lg_node *n)
{
    pr_state *st = n->user;
    if (!st)
        return;
    pr_state_clear(st);
    free(st);
    n->user = NULL;
}

/* ---- probe_convert ------------------------------------------------------------------------ */

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
    double s = l == LG_PROBE_LATLONG ? sqrt(texels / 2) : l == LG_PROBE_CUBE
             ? sqrt(texels / 6) : sqrt(texels * 4 / LG_PROBE_PI_F);
    uint32_t n = s < 1 ? 1 : s > 8192 ? 8192 : (uint32_t)lround(s);
    *h = n;
    *w = l == LG_PROBE_LATLONG ? 2 * n : n;
}

static int convert_prepare(lg_node *n)
{
    pc_state *st = n->user;
    if (!st) {
        st = calloc(1, sizeof *st);
        if (!st)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
        n->user = st;
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
                                               LG_PROBE_CUBE, LG_PROBE_CUBE, LG_PROBE_CUBE };
    static const lg_probe_file_layout files[] = {
        LG_PROBE_FILE_DEFAULT, LG_PROBE_FILE_DEFAULT, LG_PROBE_FILE_CROSS,
        LG_PROBE_FILE_VCROSS, LG_PROBE_FILE_STRIP, LG_PROBE_FILE_VSTRIP };
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
           st->layout == LG_PROBE_LATLONG ? "lat-long" : st->layout == LG_PROBE_ANGULAR
           ? "angular map" : "cube", st->width, st->height);
    lg_image_desc d = { .width = st->width, .height = st->height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = st->layout == LG_PROBE_CUBE ? LG_IMAGE_CUBE : 0u };
    int rc = lg_probe_declare(n, 0, st->layout, &d, true);
    if (rc)
        return rc;
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
    if (rc)
        return lg_error_code(n, rc, "resampling the %ux%u probe into %ux%u failed%s",
                             img.width, img.height, st->width, st->height,
                             rc == LG_ERR_NOMEM ? ": out of memory" : "");
    lg_log(n, LG_LOG_DEBUG, "%llu sub-rectangles, %llu texel pairs, %u balancing rounds; "
           "integral error %.2e before balancing, %.2e after",
           (unsigned long long)stats.samples, (unsigned long long)stats.entries,
           stats.iterations, stats.raw_total_error, stats.total_error);
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

static const char *const pr_layouts[] = { "auto", "latlong", "angular", "cross", "strip",
                                          "faces", NULL };
static const lg_param_desc probe_params[] = {
    { .key = "file", .type = LG_PARAM_PATH, .def.s = "",
      .doc = "probe image: .exr (any compression) or .hdr; empty with layout = faces" },
    { .key = "layout", .type = LG_PARAM_ENUM, .def.e = PR_LAYOUT_AUTO, .enum_values = pr_layouts,
      .doc = "auto (from the size: 2:1 latlong, 1:1 angular, 4:3 / 3:4 cross, 6:1 / 1:6 "
             "strip), or say which; faces reads the list `faces`" },
    { .key = "faces", .type = LG_PARAM_PATH_LIST,
      .doc = "layout = faces: six files, [+X, -X, +Y, -Y, +Z, -Z], square, one size" },
    { .key = "rotate_deg", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 0 }, .min = -1e6, .max = 1e6,
      .doc = "[yaw, pitch, roll], degrees: probe -> world, R = Ry(yaw) Rx(pitch) Rz(roll)" },
    { .key = "exposure", .type = LG_PARAM_FLOAT, .def.f = 0, .min = -64, .max = 64,
      .doc = "stops: the texels are multiplied by 2^exposure" },
    { .key = "scale", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0, .max = 1e9,
      .doc = "linear multiplier of the texels (with 2^exposure: info.scale)" },
};
static const lg_port_desc probe_outputs[] = {
    { .name = "probe", .kind = LG_KIND_PROBE,
      .doc = "radiance (rgba32f; 2D or GL cube), solid_angle, info; on the CPU" },
};

static const char *const pc_layouts[] = { "latlong", "angular", "cross", "vcross", "strip",
                                          "vstrip", NULL };
static const lg_param_desc convert_params[] = {
    { .key = "layout", .type = LG_PARAM_ENUM, .def.e = PC_LATLONG, .enum_values = pc_layouts,
      .doc = "latlong, angular, or a cube written (by an output) as a horizontal cross, a "
             "vertical cross, a 6x1 strip or a 1x6 strip" },
    { .key = "size", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 8192,
      .doc = "cube face size, lat-long height (width 2x), angular side; 0 = as many texels "
             "on the sphere as the source image has" },
};
static const lg_port_desc convert_inputs[] = {
    { .name = "probe", .kind = LG_KIND_PROBE, .doc = "the probe to convert (any layout)" },
};
static const lg_port_desc convert_outputs[] = {
    { .name = "probe", .kind = LG_KIND_PROBE,
      .doc = "the probe area-resampled into `layout`, its rotation baked in; on the CPU" },
};

static const lg_node_type probe_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "probe",
        .doc = "reads a light probe: lat-long, angular map, cross, strip or six faces",
        LG_PARAMS(probe_params), LG_OUTPUTS(probe_outputs),
        .prepare = probe_prepare, .execute = probe_execute, .destroy = probe_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "probe_convert",
        .doc = "area-weighted resampling of a probe into another layout and size (its "
               "integral over any region kept); an output writes it as EXR or HDR",
        LG_PARAMS(convert_params), LG_INPUTS(convert_inputs), LG_OUTPUTS(convert_outputs),
        .prepare = convert_prepare, .execute = convert_execute, .destroy = convert_destroy,
    },
};

LG_PLUGIN_DEFINE("probe", "1.0.0", "Light probes from files in every layout", probe_types)
