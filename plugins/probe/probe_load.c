/*
 * plugins/probe/probe_load.c: the `probe` node's files (probe_load.h): read, their layout
 * recognised from the size or the `layout` parameter, the values a probe cannot hold
 * zeroed, a cube's faces cut out of its cross or strip. No parameter is read here: probe.c
 * passes them, and tests/fuzz/fuzz_probe.c calls this on arbitrary files.
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "probe_load.h"

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
    "none",           "lat-long",  "angular map", "horizontal cross",
    "vertical cross", "6x1 strip", "1x6 strip",   "six face files",
};

static const char *const pr_face_names[6] = { "+X", "-X", "+Y", "-Y", "+Z", "-Z" };

/* Where the faces sit in a cross or a strip: lg_probe_file_cell (lightgraph/probe.h), the
 * table lg_probe_pack writes with, so that reading and writing are inverses. The
 * horizontal cross holds every face as OpenGL orients it; the vertical one turns -Z
 * (below -Y) by 180 degrees, as cmft and HDRShop do, so that its edges meet -Y's.
 * docs/probes.md draws both. */
static lg_probe_file_layout pr_file_layout(pr_source src)
{
    return src == PR_CROSS_H   ? LG_PROBE_FILE_CROSS
           : src == PR_CROSS_V ? LG_PROBE_FILE_VCROSS
           : src == PR_STRIP_H ? LG_PROBE_FILE_STRIP
           : src == PR_STRIP_V ? LG_PROBE_FILE_VSTRIP
                               : LG_PROBE_FILE_DEFAULT;
}

/* Reads one file as stored (no clamping: pr_sanitize counts and zeroes what a probe
 * cannot hold, with one warning per file). A PNG arrives decoded from sRGB to linear by
 * the SDK's reader, in [0, 1]: a valid probe, of low dynamic range (README, "Files"). */
static int pr_read(lg_node *n, const char *path, const char *what, lg_image *img)
{
    if (!path || !*path)
        return lg_error(n, "parameter '%s' is empty: name an .exr, .hdr or .png file", what);
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
               path, img->width, img->height, neg + nan + inf, neg + nan + inf == 1 ? "" : "s", neg,
               nan, inf);
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
        lg_error(n, "file '%s' is %ux%u: an angular map (layout = angular) is square", path, w, h);
        return PR_NONE;
    case PR_LAYOUT_CROSS:
        if (ch)
            return PR_CROSS_H;
        if (cv)
            return PR_CROSS_V;
        lg_error(n,
                 "file '%s' is %ux%u: a cross (layout = cross) is 4N x 3N (horizontal) or "
                 "3N x 4N (vertical) with N the face size",
                 path, w, h);
        return PR_NONE;
    case PR_LAYOUT_STRIP:
        if (sh)
            return PR_STRIP_H;
        if (sv)
            return PR_STRIP_V;
        lg_error(n,
                 "file '%s' is %ux%u: a strip (layout = strip) is 6N x N or N x 6N with N "
                 "the face size",
                 path, w, h);
        return PR_NONE;
    default: break;
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
    static const struct {
        uint32_t num, den;
        const char *name;
    } ratios[] = {
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
        lg_error(n,
                 "file '%s' is %ux%u: ambiguous; its shape is near %s but not exactly: "
                 "set `layout` to say which",
                 path, w, h, near);
    else
        lg_error(n,
                 "file '%s' is %ux%u: no probe layout has this shape (auto recognises "
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
            const float *s = src->pixels + 4 * ((size_t)((uint32_t)cy * N + sy) * src->width +
                                                (uint32_t)cx * N + sx);
            memcpy(dst + 4 * ((size_t)y * N + x), s, 16);
        }
}

void pr_file_clear(pr_file *st)
{
    if (st->decoded.pixels)
        lg_image_free(&st->decoded);
    else
        free(st->texels);
    memset(st, 0, sizeof *st);
    st->file_layout = LG_PROBE_FILE_DEFAULT;
}

/* Fills st from the files. */
int pr_load_file(lg_node *n, int want, const char *file, const char *const *faces,
                 uint32_t have_faces, pr_file *st, uint64_t *key)
{
    memset(st, 0, sizeof *st);
    bool have_file = file && *file;
    if (want == PR_LAYOUT_AUTO && !have_file && have_faces)
        want = PR_LAYOUT_FACES;
    uint64_t h = LG_IMAGE_HASH_SEED;

    if (want == PR_LAYOUT_FACES) {
        if (have_file)
            return lg_error(n,
                            "layout = faces reads the six files of 'faces'; 'file' ('%s') "
                            "is set too: leave it empty",
                            file);
        if (have_faces != 6)
            return lg_error(n,
                            "layout = faces needs six files in 'faces' (+X, -X, +Y, -Y, +Z, "
                            "-Z), found %u",
                            have_faces);
        lg_image img[6];
        memset(img, 0, sizeof img);
        int rc = 0;
        uint32_t N = 0;
        const char *first = faces[0];
        for (uint32_t f = 0; f < 6 && !rc; f++) {
            const char *p = faces[f];
            char what[64];
            snprintf(what, sizeof what, "faces[%u]", f);
            if ((rc = pr_read(n, p, what, &img[f])))
                break;
            if (img[f].width != img[f].height)
                rc = lg_error(n,
                              "face file '%s' (faces[%u], the %s face) is %ux%u: faces are "
                              "square",
                              p, f, pr_face_names[f], img[f].width, img[f].height);
            else if (f > 0 && img[f].width != N)
                rc = lg_error(n,
                              "face file '%s' (faces[%u], the %s face) is %ux%u but '%s' "
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
            pr_sanitize(n, faces[f], &img[f]);
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
        return lg_error(n,
                        "'faces' is for layout = faces; this probe reads 'file' (layout = %s): "
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
    uint32_t N = src == PR_CROSS_H   ? img.width / 4
                 : src == PR_CROSS_V ? img.width / 3
                 : src == PR_STRIP_H ? img.height
                                     : img.width;
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
