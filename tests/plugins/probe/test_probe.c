/* The probe plugin (`probe` node) and scene_tools' `environment` node through the host.
 * The test plugin testprobe (probe_tap) reads the published probe back through
 * lg_probe_get and lg_probe_lookup, as a consumer would.
 *
 *   latlong_asset     assets/probes/forest_1024x512_zip.exr: layout, size, texels (negatives
 *                     zeroed), solid angles sum to 4 pi, identity rotation, scale 1
 *   angular_asset     assets/probes/forest_angular_1024.hdr: the same checks, and its lookups
 *                     agree with the lat-long forest's best unturned (the derived file
 *                     follows probe.h's conventions)
 *   cross_h, cross_v, strip_h, strip_v, faces
 *                     synthetic cubes (a colour per face, an off-centre marker texel): the
 *                     GL cube equals the faces, and looking up each face's centre and its
 *                     marker's direction gives the face's colour and the marker's
 *   cross_seams       in both crosses, pixels adjacent in the file across a face edge are
 *                     adjacent on the sphere (the crosses are unfoldings of the GL cube)
 *   auto_errors       impossible and ambiguous sizes, explicit layouts that do not fit,
 *                     faces of unequal size or not square, a missing file, file + faces,
 *                     `faces` with 0, 5 or 7 items, an item not a string or empty
 *   latlong_not_2to1  layout = latlong accepts 7x3 with a note; auto refuses it
 *   one_by_one        a 1x1 file: angular (auto) and lat-long; lookups give its texel
 *   rotate_360        rotate_deg = [360, 360, 360] equals none bit for bit; yaw 90 moves
 *   exposure_scale    texels times 2^exposure * scale; info.scale says it
 *   bad_texels        NaN, Inf and negative channels set to 0, one warning with the counts
 *   png               a PNG probe: texels are the file's 8-bit sRGB codes decoded to linear
 *                     (lg_srgb_decode(code / 255), exactly; alpha ignored), at most 1, times
 *                     the exposure; a cross PNG is a cube like an EXR one
 *   environment       the scene feature `probe` and gating on it
 *   content_key       a downstream cache entry is invalidated by changed pixels (same file
 *                     size), exposure and rotation, and reused otherwise
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/test.h"

#ifndef PR_TESTPROBE_DIR
#define PR_TESTPROBE_DIR ""
#endif
#ifndef PR_TESTNODES_DIR
#define PR_TESTNODES_DIR ""
#endif
#ifndef PR_TESTCUBE_DIR
#define PR_TESTCUBE_DIR ""
#endif

static void setup(lg_test *t)
{
    static char path[8300];
    snprintf(path, sizeof path, "%s:%s:%s", PR_TESTPROBE_DIR, PR_TESTCUBE_DIR, PR_TESTNODES_DIR);
    lg_test_use_plugins(t, path);
}

static lg_image alloc_image(uint32_t w, uint32_t h)
{
    lg_image img;
    if (lg_image_alloc(&img, w, h)) {
        fprintf(stderr, "lg_image_alloc failed\n");
        exit(99);
    }
    return img;
}

static float *pix(const lg_image *img, uint32_t x, uint32_t y)
{
    return img->pixels + 4 * ((size_t)y * img->width + x);
}

/* Renders graph text; returns the exit status, *out what the program printed. */
static int render(lg_test *t, const char *graph, char **out)
{
    lg_test_write_text(t, "g.lgraph", graph);
    const char *args[] = { "--explain", "-v", NULL };
    return lg_test_render(t, "g.lgraph", args, out);
}

/* Renders `probe_def` ("sky = probe { ... }\n") with a probe_tap in `mode` into tap.exr
 * (and dirs.exr as its directions when `dirs`), reads it. */
static bool tap(lg_test *t, const char *probe_def, const char *mode, const lg_image *dirs,
                lg_image *got, char **log)
{
    char g[4096];
    if (dirs)
        lg_test_write_exr(t, "dirs.exr", dirs);
    snprintf(g, sizeof g,
             "lightgraph 1\n%s%s"
             "tap = probe_tap { probe = sky, mode = %s%s }\n"
             "output tap \"tap.exr\"\n",
             probe_def, dirs ? "d = image { file = \"dirs.exr\", radiance = false }\n" : "", mode,
             dirs ? ", dirs = d" : "");
    char *out = NULL;
    int rc = render(t, g, &out);
    LG_TEST_CHECK(t, rc == 0, "render failed (exit %d):\n%s", rc, out ? out : "");
    if (log)
        *log = out;
    else
        free(out);
    memset(got, 0, sizeof *got);
    if (rc)
        return false;
    unsigned bits = 0;
    if (!lg_test_read(t, "tap.exr", got, &bits))
        return false;
    LG_TEST_CHECK(t, bits == 32, "tap.exr has %u bits", bits);
    return true;
}

/* The info tap: checks the layout, size, solid-angle sum, scale; returns the info pixels. */
static void check_info(lg_test *t, const char *probe_def, int layout, uint32_t w, uint32_t h,
                       float scale, const char *what)
{
    lg_image info;
    if (!tap(t, probe_def, "info", NULL, &info, NULL))
        return;
    const float *p = info.pixels;
    LG_TEST_CHECK(t, p[1] == (float)layout && p[2] == (float)w && p[3] == (float)h,
                  "%s: layout %g %gx%g, want %d %ux%u", what, (double)p[1], (double)p[2],
                  (double)p[3], layout, w, h);
    LG_TEST_CHECK(t, fabs(p[0] - (4.0 * LG_PI)) <= 1e-6 * (4.0 * LG_PI),
                  "%s: the solid angles sum to %.9g, want 4 pi (rel. error %.3g)", what,
                  (double)p[0], (p[0] - (4.0 * LG_PI)) / (4.0 * LG_PI));
    LG_TEST_CHECK(t, p[4] == scale, "%s: info.scale %.9g, want %.9g", what, (double)p[4],
                  (double)scale);
    LG_TEST_CHECK(t, p[5] == 1 && p[6] == (layout == LG_PROBE_CUBE ? 6 : 1) && p[7] == 1,
                  "%s: levels %g faces %g solid angles %g", what, (double)p[5], (double)p[6],
                  (double)p[7]);
    static const float id[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    for (int k = 0; k < 9; k++)
        LG_TEST_CHECK(t, p[8 + 4 * (k / 3) + k % 3] == id[k], "%s: rotation[%d] = %g", what, k,
                      (double)p[8 + 4 * (k / 3) + k % 3]);
    lg_image_free(&info);
}

/* ---- synthetic cubes ------------------------------------------------------------------------- */

#define CN 8u
/* The marker: off-centre and off both diagonals, so that any flip, turn or transpose of a
 * face moves it. */
#define MARK_I 5u
#define MARK_J 1u

static void face_color(uint32_t f, float c[4])
{
    c[0] = (float)(f + 1);
    c[1] = 0.25f * (float)(f + 1);
    c[2] = 10.0f + (float)f;
    c[3] = 1.0f;
}
static void mark_color(uint32_t f, float c[4])
{
    c[0] = 100.0f + (float)f;
    c[1] = 0.5f;
    c[2] = 7.0f;
    c[3] = 1.0f;
}

/* The six GL faces, N x N each, one under the other (6N rows). */
static lg_image make_faces(void)
{
    lg_image c = alloc_image(CN, 6 * CN);
    for (uint32_t f = 0; f < 6; f++)
        for (uint32_t j = 0; j < CN; j++)
            for (uint32_t i = 0; i < CN; i++) {
                float *p = pix(&c, i, f * CN + j);
                if (i == MARK_I && j == MARK_J)
                    mark_color(f, p);
                else
                    face_color(f, p);
            }
    return c;
}

/* The documented layouts (docs/probes.md): cell (column, row) of each GL face and whether
 * it is turned by 180 degrees. */
static const int cells_h[6][3] = { { 2, 1, 0 }, { 0, 1, 0 }, { 1, 0, 0 },
                                   { 1, 2, 0 }, { 1, 1, 0 }, { 3, 1, 0 } };
static const int cells_v[6][3] = { { 2, 1, 0 }, { 0, 1, 0 }, { 1, 0, 0 },
                                   { 1, 2, 0 }, { 1, 1, 0 }, { 1, 3, 1 } };

/* A file image of `cols` x `rows` cells holding the GL faces `faces` where `cells` says;
 * unused cells hold -1 (zeroed by the node, so a misplaced read shows). */
static lg_image make_layout(const lg_image *faces, uint32_t cols, uint32_t rows,
                            const int cells[6][3])
{
    lg_image img = alloc_image(cols * CN, rows * CN);
    for (size_t k = 0; k < (size_t)img.width * img.height * 4; k++)
        img.pixels[k] = -1.0f;
    for (uint32_t f = 0; f < 6; f++)
        for (uint32_t y = 0; y < CN; y++)
            for (uint32_t x = 0; x < CN; x++) {
                uint32_t sx = cells[f][2] ? CN - 1 - x : x, sy = cells[f][2] ? CN - 1 - y : y;
                memcpy(pix(&img, (uint32_t)cells[f][0] * CN + x, (uint32_t)cells[f][1] * CN + y),
                       pix(faces, sx, f * CN + sy), 16);
            }
    return img;
}

/* Checks a loaded cube: the GL faces equal `faces`, and the lookups of each face's centre
 * and marker direction give the face's colours. */
static void check_cube(lg_test *t, const char *probe_def, const lg_image *faces, const char *what)
{
    check_info(t, probe_def, LG_PROBE_CUBE, CN, CN, 1.0f, what);
    lg_image raw;
    if (tap(t, probe_def, "raw", NULL, &raw, NULL)) {
        char label[128];
        snprintf(label, sizeof label, "%s: the GL cube's faces", what);
        lg_test_tol tol = { 0 };
        lg_test_check_image(t, &raw, faces, 32, &tol, label);
        lg_image_free(&raw);
    }
    lg_image dirs = alloc_image(12, 1);
    for (uint32_t f = 0; f < 6; f++) {
        lg_vec3 c = lg_probe_texel_dir(LG_PROBE_CUBE, CN, CN, f, CN / 2, CN / 2);
        lg_vec3 m = lg_probe_texel_dir(LG_PROBE_CUBE, CN, CN, f, MARK_I, MARK_J);
        float *pc = pix(&dirs, 2 * f, 0), *pm = pix(&dirs, 2 * f + 1, 0);
        pc[0] = c.x, pc[1] = c.y, pc[2] = c.z;
        pm[0] = m.x, pm[1] = m.y, pm[2] = m.z;
    }
    lg_image got;
    if (tap(t, probe_def, "lookup", &dirs, &got, NULL)) {
        static const char *names[6] = { "+X", "-X", "+Y", "-Y", "+Z", "-Z" };
        for (uint32_t f = 0; f < 6; f++) {
            float wc[4], wm[4];
            face_color(f, wc);
            mark_color(f, wm);
            const float *gc = pix(&got, 2 * f, 0), *gm = pix(&got, 2 * f + 1, 0);
            LG_TEST_CHECK(t, memcmp(gc, wc, 12) == 0,
                          "%s: face %s centre reads (%g, %g, %g), want (%g, %g, %g)", what,
                          names[f], (double)gc[0], (double)gc[1], (double)gc[2], (double)wc[0],
                          (double)wc[1], (double)wc[2]);
            LG_TEST_CHECK(t, memcmp(gm, wm, 12) == 0,
                          "%s: face %s marker reads (%g, %g, %g), want the marker (%g, ...)", what,
                          names[f], (double)gm[0], (double)gm[1], (double)gm[2], (double)wm[0]);
        }
        lg_image_free(&got);
    }
    lg_image_free(&dirs);
}

static void case_cross_h(lg_test *t)
{
    lg_image faces = make_faces();
    lg_image img = make_layout(&faces, 4, 3, cells_h);
    lg_test_write_exr(t, "c.exr", &img);
    check_cube(t, "sky = probe { file = \"c.exr\" }\n", &faces, "horizontal cross (auto)");
    check_cube(t, "sky = probe { file = \"c.exr\", layout = cross }\n", &faces, "horizontal cross");
    lg_image_free(&img);
    lg_image_free(&faces);
}

static void case_cross_v(lg_test *t)
{
    lg_image faces = make_faces();
    lg_image img = make_layout(&faces, 3, 4, cells_v);
    lg_test_write_exr(t, "c.exr", &img);
    check_cube(t, "sky = probe { file = \"c.exr\" }\n", &faces, "vertical cross (auto)");
    check_cube(t, "sky = probe { file = \"c.exr\", layout = cross }\n", &faces, "vertical cross");
    lg_image_free(&img);
    lg_image_free(&faces);
}

static void case_strip_h(lg_test *t)
{
    static const int cells[6][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 2, 0, 0 },
                                     { 3, 0, 0 }, { 4, 0, 0 }, { 5, 0, 0 } };
    lg_image faces = make_faces();
    lg_image img = make_layout(&faces, 6, 1, cells);
    lg_test_write_exr(t, "s.exr", &img);
    check_cube(t, "sky = probe { file = \"s.exr\" }\n", &faces, "6x1 strip (auto)");
    check_cube(t, "sky = probe { file = \"s.exr\", layout = strip }\n", &faces, "6x1 strip");
    lg_image_free(&img);
    lg_image_free(&faces);
}

static void case_strip_v(lg_test *t)
{
    lg_image faces = make_faces(); /* already the 1x6 strip */
    lg_test_write_exr(t, "s.exr", &faces);
    check_cube(t, "sky = probe { file = \"s.exr\" }\n", &faces, "1x6 strip (auto)");
    check_cube(t, "sky = probe { file = \"s.exr\", layout = strip }\n", &faces, "1x6 strip");
    lg_image_free(&faces);
}

static void write_faces(lg_test *t, const lg_image *faces)
{
    static const char *files[6] = { "px.exr", "nx.exr", "py.exr", "ny.exr", "pz.exr", "nz.exr" };
    for (uint32_t f = 0; f < 6; f++) {
        lg_image one = { CN, CN, faces->pixels + (size_t)4 * f * CN * CN };
        lg_test_write_exr(t, files[f], &one);
    }
}

#define FACES_PARAMS                                                                               \
    "faces = [\"px.exr\", \"nx.exr\", \"py.exr\", \"ny.exr\", \"pz.exr\", \"nz.exr\"]"

static void case_faces(lg_test *t)
{
    lg_image faces = make_faces();
    write_faces(t, &faces);
    check_cube(t, "sky = probe { " FACES_PARAMS " }\n", &faces, "six faces (auto)");
    check_cube(t, "sky = probe { layout = faces, " FACES_PARAMS " }\n", &faces, "six faces");
    lg_image_free(&faces);
}

/* Each file pixel holds its own coordinates; after loading, every GL texel says which file
 * pixel it came from, so each file pixel gets a direction. Neighbours in the file (both in
 * faces) must be neighbours on the sphere: at most ~1.5 texels apart, never a seam away. */
static void seams(lg_test *t, uint32_t cols, uint32_t rows, const char *what)
{
    uint32_t W = cols * CN, H = rows * CN;
    lg_image img = alloc_image(W, H);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            float *p = pix(&img, x, y);
            p[0] = (float)x + 1, p[1] = (float)y + 1, p[2] = 0, p[3] = 1;
        }
    lg_test_write_exr(t, "c.exr", &img);
    lg_image raw;
    if (!tap(t, "sky = probe { file = \"c.exr\" }\n", "raw", NULL, &raw, NULL)) {
        lg_image_free(&img);
        return;
    }
    lg_vec3 *dir = calloc((size_t)W * H, sizeof *dir);
    bool *has = calloc((size_t)W * H, 1);
    for (uint32_t f = 0; f < 6; f++)
        for (uint32_t j = 0; j < CN; j++)
            for (uint32_t i = 0; i < CN; i++) {
                const float *p = pix(&raw, i, f * CN + j);
                uint32_t x = (uint32_t)p[0] - 1, y = (uint32_t)p[1] - 1;
                dir[(size_t)y * W + x] = lg_probe_texel_dir(LG_PROBE_CUBE, CN, CN, f, i, j);
                has[(size_t)y * W + x] = true;
            }
    /* a texel spans at most 2/N rad (at a face centre, seen from 1); diagonal neighbours
     * across an edge fold ~1.5 texels */
    double lim = 3.0 / CN;
    uint64_t pairs = 0, crossing = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            if (!has[(size_t)y * W + x])
                continue;
            for (int k = 0; k < 2; k++) {
                uint32_t x2 = x + (k == 0), y2 = y + (k == 1);
                if (x2 >= W || y2 >= H || !has[(size_t)y2 * W + x2])
                    continue;
                lg_vec3 a = dir[(size_t)y * W + x], b = dir[(size_t)y2 * W + x2];
                double c = a.x * b.x + a.y * b.y + a.z * b.z;
                double ang = acos(c > 1 ? 1 : c);
                pairs++;
                crossing += (x / CN != x2 / CN) || (y / CN != y2 / CN);
                LG_TEST_CHECK(t, ang < lim,
                              "%s: file pixels (%u, %u) and (%u, %u) are %.3f rad apart on the "
                              "sphere (limit %.3f): the faces do not meet there",
                              what, x, y, x2, y2, ang, lim);
            }
        }
    LG_TEST_CHECK(t, crossing == 5 * CN, "%s: %llu neighbour pairs cross a face edge, want %u",
                  what, (unsigned long long)crossing, 5 * CN);
    LG_TEST_CHECK(t, pairs > 0, "%s: no pairs", what);
    free(dir);
    free(has);
    lg_image_free(&raw);
    lg_image_free(&img);
}

static void case_cross_seams(lg_test *t)
{
    seams(t, 4, 3, "horizontal cross");
    seams(t, 3, 4, "vertical cross");
}

/* ---- real assets ----------------------------------------------------------------------------- */

static void case_latlong_asset(lg_test *t)
{
    char def[1024];
    snprintf(def, sizeof def, "sky = probe { file = \"%s\" }\n",
             lg_test_asset("probes/forest_1024x512_zip.exr"));
    check_info(t, def, LG_PROBE_LATLONG, 1024, 512, 1.0f, "lat-long forest");
    lg_image raw, file;
    char err[256];
    if (lg_image_read(lg_test_asset("probes/forest_1024x512_zip.exr"), 0, &file, NULL, err,
                      sizeof err)) {
        LG_TEST_FAILF(t, "%s", err);
        return;
    }
    if (tap(t, def, "raw", NULL, &raw, NULL)) {
        for (size_t k = 0; k < (size_t)file.width * file.height; k++) {
            float *p = file.pixels + 4 * k;
            for (int c = 0; c < 3; c++)
                p[c] = p[c] > 0 ? p[c] : 0.0f;
            p[3] = 1;
        }
        lg_test_tol tol = { 0 };
        lg_test_check_image(t, &raw, &file, 32, &tol, "lat-long forest texels");
        lg_image_free(&raw);
    }
    lg_image_free(&file);
}

static void case_angular_asset(lg_test *t)
{
    char ang[1024], ll[1024];
    snprintf(ang, sizeof ang, "sky = probe { file = \"%s\" }\n",
             lg_test_asset("probes/forest_angular_1024.hdr"));
    snprintf(ll, sizeof ll, "sky = probe { file = \"%s\" }\n",
             lg_test_asset("probes/forest_1024x512_zip.exr"));
    check_info(t, ang, LG_PROBE_ANGULAR, 1024, 1024, 1.0f, "angular forest");
    /* the same scene in two layouts: lookups along 4096 directions (away from the rim,
     * where the angular map has little resolution) agree on average */
    uint32_t nd = 4096;
    lg_image dirs = alloc_image(nd, 1);
    uint32_t s = 12345;
    for (uint32_t i = 0; i < nd; i++) {
        float v[3];
        for (;;) {
            for (int c = 0; c < 3; c++) {
                s = s * 1664525u + 1013904223u;
                v[c] = (float)(s >> 8) / 8388608.0f - 1.0f;
            }
            float l = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if (l > 0.01f && l <= 1 && v[2] / sqrtf(l) < 0.7f)
                break;
        }
        float *p = pix(&dirs, i, 0);
        p[0] = v[0], p[1] = v[1], p[2] = v[2];
    }
    /* mean |angular - lat-long| over the mean lat-long radiance, for the lat-long forest
     * turned by `yaw` degrees: the same convention gives a sharp minimum at 0 (measured
     * 0.19: RGBE rounding and the resampling that made the angular file; 0.75 at +-2
     * degrees, 1.4 to 2.2 for any mirrored axis) */
    lg_image a;
    if (tap(t, ang, "bilinear", &dirs, &a, NULL)) {
        static const float yaws[3] = { 0, 2, -2 };
        double rel[3] = { 0, 0, 0 };
        for (int k = 0; k < 3; k++) {
            char def[1200];
            snprintf(def, sizeof def, "sky = probe { file = \"%s\", rotate_deg = [%g, 0, 0] }\n",
                     lg_test_asset("probes/forest_1024x512_zip.exr"), (double)yaws[k]);
            lg_image b;
            if (!tap(t, def, "bilinear", &dirs, &b, NULL))
                continue;
            double sb = 0, sd = 0;
            for (uint32_t i = 0; i < nd; i++)
                for (int c = 0; c < 3; c++) {
                    double x = pix(&a, i, 0)[c], y = pix(&b, i, 0)[c];
                    sb += y, sd += fabs(x - y);
                }
            rel[k] = sd / sb;
            fprintf(stderr,
                    "angular vs lat-long forest turned by %g degrees: mean |difference| "
                    "%.3f of the mean\n",
                    (double)yaws[k], rel[k]);
            lg_image_free(&b);
        }
        LG_TEST_CHECK(t, rel[0] < 0.3, "the angular and lat-long forests disagree: %.3f", rel[0]);
        LG_TEST_CHECK(t, rel[1] > 2 * rel[0] && rel[2] > 2 * rel[0],
                      "no sharp minimum at 0 degrees: %.3f, +2: %.3f, -2: %.3f", rel[0], rel[1],
                      rel[2]);
        lg_image_free(&a);
    }
    lg_image_free(&dirs);
}

/* ---- errors ---------------------------------------------------------------------------------- */

/* Renders `def` with a tap and expects exit `want_rc` (1: the node failed; 2: the graph
 * was refused before anything ran) with a message containing want1 (and want2). */
static void expect_exit(lg_test *t, int want_rc, const char *def, const char *want1,
                        const char *want2);

static void expect_error(lg_test *t, const char *def, const char *want1, const char *want2)
{
    expect_exit(t, 1, def, want1, want2);
}

static void expect_exit(lg_test *t, int want_rc, const char *def, const char *want1,
                        const char *want2)
{
    char g[4096];
    snprintf(g, sizeof g,
             "lightgraph 1\n%stap = probe_tap { probe = sky, mode = info }\n"
             "output tap \"tap.exr\"\n",
             def);
    char *out = NULL;
    int rc = render(t, g, &out);
    const char *o = out ? out : "";
    LG_TEST_CHECK(t, rc == want_rc, "%s: exit %d, want %d (a failure naming the problem):\n%s", def,
                  rc, want_rc, o);
    LG_TEST_CHECK(t, strstr(o, want1) && (!want2 || strstr(o, want2)),
                  "%s: the message does not say '%s'%s%s:\n%s", def, want1, want2 ? " and " : "",
                  want2 ? want2 : "", o);
    free(out);
}

static void write_sized(lg_test *t, const char *name, uint32_t w, uint32_t h)
{
    lg_image img = alloc_image(w, h);
    for (size_t k = 0; k < (size_t)w * h * 4; k++)
        img.pixels[k] = 0.5f;
    lg_test_write_exr(t, name, &img);
    lg_image_free(&img);
}

static void case_auto_errors(lg_test *t)
{
    write_sized(t, "wide.exr", 30, 10);     /* 3:1: nothing */
    write_sized(t, "near2.exr", 201, 100);  /* nearly 2:1 */
    write_sized(t, "near43.exr", 401, 300); /* nearly 4:3 */
    write_sized(t, "cross_odd.exr", 10, 10);
    write_sized(t, "sq8.exr", 8, 8);
    write_sized(t, "sq4.exr", 4, 4);
    write_sized(t, "rect.exr", 8, 6);
    expect_error(t, "sky = probe { file = \"wide.exr\" }\n", "wide.exr' is 30x10",
                 "no probe layout has this shape");
    expect_error(t, "sky = probe { file = \"near2.exr\" }\n", "near2.exr' is 201x100: ambiguous",
                 "lat-long");
    expect_error(t, "sky = probe { file = \"near43.exr\" }\n", "near43.exr' is 401x300: ambiguous",
                 "horizontal cross");
    expect_error(t, "sky = probe { file = \"cross_odd.exr\", layout = cross }\n",
                 "cross_odd.exr' is 10x10", "4N x 3N");
    expect_error(t, "sky = probe { file = \"rect.exr\", layout = angular }\n", "rect.exr' is 8x6",
                 "square");
    expect_error(t, "sky = probe { file = \"sq8.exr\", layout = strip }\n", "sq8.exr' is 8x8",
                 "6N x N");
    expect_error(t, "sky = probe { file = \"missing.exr\" }\n", "missing.exr", NULL);
    expect_error(t, "sky = probe { file = \"\" }\n", "'file' is empty", NULL);
    /* faces */
    const char *base = "\"sq8.exr\", \"sq8.exr\", \"sq8.exr\", \"sq8.exr\", \"sq8.exr\"";
    char def[1024];
    snprintf(def, sizeof def, "sky = probe { faces = [%s, \"sq4.exr\"] }\n", base);
    expect_error(t, def, "sq4.exr' (faces[5], the -Z face) is 4x4", "one size");
    snprintf(def, sizeof def, "sky = probe { faces = [%s, \"rect.exr\"] }\n", base);
    expect_error(t, def, "rect.exr' (faces[5], the -Z face) is 8x6", "square");
    snprintf(def, sizeof def, "sky = probe { faces = [\"rect.exr\", %s] }\n", base);
    expect_error(t, def, "rect.exr' (faces[0], the +X face) is 8x6", "square");
    snprintf(def, sizeof def, "sky = probe { faces = [%s] }\n", base);
    expect_error(t, def, "needs six files in 'faces' (+X, -X, +Y, -Y, +Z, -Z), found 5", NULL);
    snprintf(def, sizeof def, "sky = probe { faces = [%s, \"sq8.exr\", \"sq8.exr\"] }\n", base);
    expect_error(t, def, "needs six files in 'faces' (+X, -X, +Y, -Y, +Z, -Z), found 7", NULL);
    expect_error(t, "sky = probe { layout = faces }\n", "needs six files in 'faces'", "found 0");
    snprintf(def, sizeof def, "sky = probe { faces = [%s, \"nope.exr\"] }\n", base);
    expect_error(t, def, "nope.exr", NULL);
    snprintf(def, sizeof def, "sky = probe { file = \"sq8.exr\", faces = [%s, \"sq8.exr\"] }\n",
             base);
    expect_error(t, def, "'faces' is for layout = faces", NULL);
    snprintf(def, sizeof def,
             "sky = probe { layout = faces, file = \"sq8.exr\", faces = [%s, \"sq8.exr\"] }\n",
             base);
    expect_error(t, def, "'file' ('", "leave it empty");
    /* the list's type, checked before anything runs */
    expect_exit(t, 2, "sky = probe { faces = [\"a.exr\", 3] }\n",
                "expected a file path (a string), found an integer (item 1 of parameter 'faces'",
                NULL);
    expect_exit(t, 2, "sky = probe { faces = \"a.exr\" }\n",
                "expected a list of file paths (strings), found a string", NULL);
    expect_exit(t, 2, "sky = probe { faces = [\"a.exr\", \"\"] }\n",
                "item 1 of parameter 'faces' of node 'sky' is an empty path", NULL);
}

static void case_latlong_not_2to1(lg_test *t)
{
    write_sized(t, "l73.exr", 7, 3);
    char *log = NULL;
    lg_image info;
    if (tap(t, "sky = probe { file = \"l73.exr\", layout = latlong }\n", "info", NULL, &info,
            &log)) {
        LG_TEST_CHECK(t,
                      info.pixels[1] == LG_PROBE_LATLONG && info.pixels[2] == 7 &&
                          info.pixels[3] == 3,
                      "7x3 lat-long: layout %g, %gx%g", (double)info.pixels[1],
                      (double)info.pixels[2], (double)info.pixels[3]);
        LG_TEST_CHECK(t, fabs(info.pixels[0] - (4.0 * LG_PI)) <= 1e-6 * (4.0 * LG_PI), "sum %.9g",
                      (double)info.pixels[0]);
        LG_TEST_CHECK(t, log && strstr(log, "is 7x3, not 2:1: read as a lat-long"),
                      "no note about the 7x3 lat-long:\n%s", log ? log : "");
        lg_image_free(&info);
    }
    free(log);
    expect_error(t, "sky = probe { file = \"l73.exr\" }\n", "l73.exr' is 7x3",
                 "latlong reads any size");
}

static void case_one_by_one(lg_test *t)
{
    lg_image one = alloc_image(1, 1);
    one.pixels[0] = 0.25f, one.pixels[1] = 3.5f, one.pixels[2] = 12345.678f, one.pixels[3] = 1;
    lg_test_write_exr(t, "one.exr", &one);
    check_info(t, "sky = probe { file = \"one.exr\" }\n", LG_PROBE_ANGULAR, 1, 1, 1.0f,
               "1x1 (auto: angular)");
    check_info(t, "sky = probe { file = \"one.exr\", layout = latlong }\n", LG_PROBE_LATLONG, 1, 1,
               1.0f, "1x1 lat-long");
    lg_image dirs = alloc_image(8, 1);
    static const float d[8][3] = { { 0, 0, -1 }, { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 },
                                   { 0, -1, 0 }, { 0, 0, 0 }, { 1, 1, 1 }, { -0.3f, 0.2f, 0.9f } };
    for (uint32_t i = 0; i < 8; i++)
        memcpy(pix(&dirs, i, 0), d[i], 12);
    static const char *layouts[2] = { "angular", "latlong" };
    for (int l = 0; l < 2; l++)
        for (int m = 0; m < 2; m++) {
            char def[256];
            snprintf(def, sizeof def, "sky = probe { file = \"one.exr\", layout = %s }\n",
                     layouts[l]);
            lg_image got;
            if (!tap(t, def, m ? "bilinear" : "lookup", &dirs, &got, NULL))
                continue;
            for (uint32_t i = 0; i < 8; i++)
                LG_TEST_CHECK(t, memcmp(pix(&got, i, 0), one.pixels, 12) == 0,
                              "1x1 %s %s: direction %u reads (%g, %g, %g)", layouts[l],
                              m ? "bilinear" : "nearest", i, (double)pix(&got, i, 0)[0],
                              (double)pix(&got, i, 0)[1], (double)pix(&got, i, 0)[2]);
            lg_image_free(&got);
        }
    lg_image_free(&dirs);
    lg_image_free(&one);
}

/* ---- parameters ------------------------------------------------------------------------------ */

static lg_image random_dirs(uint32_t n, uint32_t seed)
{
    lg_image dirs = alloc_image(n, 1);
    for (uint32_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            seed = seed * 1664525u + 1013904223u;
            pix(&dirs, i, 0)[c] = (float)(seed >> 8) / 8388608.0f - 1.0f;
        }
    return dirs;
}

static void case_rotate_360(lg_test *t)
{
    char def[1024];
    const char *file = lg_test_asset("probes/forest_1024x512_zip.exr");
    lg_image dirs = random_dirs(2048, 7);
    lg_image a, b, c;
    snprintf(def, sizeof def, "sky = probe { file = \"%s\" }\n", file);
    bool ok = tap(t, def, "bilinear", &dirs, &a, NULL);
    snprintf(def, sizeof def, "sky = probe { file = \"%s\", rotate_deg = [360, -360, 720] }\n",
             file);
    ok = tap(t, def, "bilinear", &dirs, &b, NULL) && ok;
    check_info(t, def, LG_PROBE_LATLONG, 1024, 512, 1.0f, "rotated by 360 degrees");
    snprintf(def, sizeof def, "sky = probe { file = \"%s\", rotate_deg = [90, 0, 0] }\n", file);
    ok = tap(t, def, "bilinear", &dirs, &c, NULL) && ok;
    if (ok) {
        LG_TEST_CHECK(t, memcmp(a.pixels, b.pixels, (size_t)2048 * 16) == 0,
                      "rotate_deg = [360, -360, 720] differs from no rotation");
        LG_TEST_CHECK(t, memcmp(a.pixels, c.pixels, (size_t)2048 * 16) != 0,
                      "rotate_deg = [90, 0, 0] changes nothing");
        /* yaw 90: the probe's centre (-Z) turns to -X (probe.h) */
        lg_image d1 = alloc_image(1, 1), r1, r2;
        d1.pixels[0] = -1;
        d1.pixels[1] = d1.pixels[2] = 0;
        lg_image d0 = alloc_image(1, 1);
        d0.pixels[2] = -1;
        snprintf(def, sizeof def, "sky = probe { file = \"%s\", rotate_deg = [90, 0, 0] }\n", file);
        bool ok1 = tap(t, def, "lookup", &d1, &r1, NULL);
        snprintf(def, sizeof def, "sky = probe { file = \"%s\" }\n", file);
        bool ok2 = tap(t, def, "lookup", &d0, &r2, NULL);
        if (ok1 && ok2)
            LG_TEST_CHECK(t, memcmp(r1.pixels, r2.pixels, 12) == 0,
                          "yaw 90: world -X reads (%g, %g, %g), the unrotated -Z (%g, %g, %g)",
                          (double)r1.pixels[0], (double)r1.pixels[1], (double)r1.pixels[2],
                          (double)r2.pixels[0], (double)r2.pixels[1], (double)r2.pixels[2]);
        if (ok1)
            lg_image_free(&r1);
        if (ok2)
            lg_image_free(&r2);
        lg_image_free(&d0);
        lg_image_free(&d1);
    }
    if (a.pixels)
        lg_image_free(&a);
    if (b.pixels)
        lg_image_free(&b);
    if (c.pixels)
        lg_image_free(&c);
    lg_image_free(&dirs);
}

static void case_exposure_scale(lg_test *t)
{
    lg_image img = alloc_image(8, 4);
    for (uint32_t k = 0; k < 32; k++) {
        img.pixels[4 * k] = 0.1f * (float)k;
        img.pixels[4 * k + 1] = 1.0f + (float)k;
        img.pixels[4 * k + 2] = 1e-3f;
        img.pixels[4 * k + 3] = 0.5f; /* alpha becomes 1 */
    }
    lg_test_write_exr(t, "e.exr", &img);
    const char *def = "sky = probe { file = \"e.exr\", exposure = 2, scale = 0.75 }\n";
    check_info(t, def, LG_PROBE_LATLONG, 8, 4, 3.0f, "exposure 2, scale 0.75");
    lg_image raw;
    if (tap(t, def, "raw", NULL, &raw, NULL)) {
        for (uint32_t k = 0; k < 32; k++)
            for (int c = 0; c < 4; c++) {
                float want = c == 3 ? 1.0f : (float)((double)img.pixels[4 * k + c] * 3.0);
                LG_TEST_CHECK(t, raw.pixels[4 * k + c] == want,
                              "texel %u channel %d: %.9g, want %.9g", k, c,
                              (double)raw.pixels[4 * k + c], (double)want);
            }
        lg_image_free(&raw);
    }
    check_info(t, "sky = probe { file = \"e.exr\", exposure = -1 }\n", LG_PROBE_LATLONG, 8, 4, 0.5f,
               "exposure -1");
    lg_image_free(&img);
}

static void case_bad_texels(lg_test *t)
{
    lg_image img = alloc_image(8, 4);
    for (uint32_t k = 0; k < 32; k++) {
        img.pixels[4 * k] = 1.0f + (float)k;
        img.pixels[4 * k + 1] = 2.0f;
        img.pixels[4 * k + 2] = 3.0f;
        img.pixels[4 * k + 3] = 1.0f;
    }
    img.pixels[4 * 3 + 0] = NAN;
    img.pixels[4 * 5 + 1] = INFINITY;
    img.pixels[4 * 6 + 2] = -INFINITY; /* infinite, not counted as negative */
    img.pixels[4 * 9 + 0] = -0.5f;
    img.pixels[4 * 9 + 2] = -2.0f; /* one pixel, two negative channels */
    img.pixels[4 * 11 + 1] = -1e-3f;
    img.pixels[4 * 12 + 3] = NAN; /* alpha: ignored, set to 1 */
    lg_test_write_exr(t, "bad.exr", &img);
    char *log = NULL;
    lg_image raw;
    if (tap(t, "sky = probe { file = \"bad.exr\" }\n", "raw", NULL, &raw, &log)) {
        for (uint32_t k = 0; k < 32; k++)
            for (int c = 0; c < 4; c++) {
                float in = img.pixels[4 * k + c];
                float want = c == 3 ? 1.0f : (isfinite(in) && in >= 0 ? in : 0.0f);
                LG_TEST_CHECK(t, raw.pixels[4 * k + c] == want && !signbit(raw.pixels[4 * k + c]),
                              "texel %u channel %d: %g, want %g", k, c,
                              (double)raw.pixels[4 * k + c], (double)want);
            }
        lg_image_free(&raw);
    }
    const char *o = log ? log : "";
    const char *w = strstr(o, "bad.exr' (8x4): set to 0 the colour channels of 5 pixels");
    LG_TEST_CHECK(t, w != NULL, "no warning with the count 5:\n%s", o);
    LG_TEST_CHECK(t, strstr(o, "2 negative, 1 NaN, 2 infinite"), "counts by kind:\n%s", o);
    const char *first = strstr(o, "set to 0 the colour channels");
    LG_TEST_CHECK(t, !first || !strstr(first + 1, "set to 0 the colour channels"),
                  "warned more than once:\n%s", o);
    free(log);
    lg_image_free(&img);
}

/* ---- PNG files ------------------------------------------------------------------------------- */

/* An 8-bit code per channel, decoded as the SDK's PNG reader does. */
static float code_lin(unsigned code)
{
    return lg_srgb_decode((float)code / 255.0f);
}

/* Writes `img` (linear values whose sRGB encodings are whole 8-bit codes) as an RGBA PNG
 * and checks that reading it back gives the same values: the codes are in the file. */
static void write_png(lg_test *t, const char *name, const lg_image *img)
{
    char err[512];
    lg_image_write_opts wo;
    memset(&wo, 0, sizeof wo);
    if (lg_image_write(lg_test_path(t, name), img, &wo, err, sizeof err)) {
        fprintf(stderr, "writing %s: %s\n", name, err);
        exit(99);
    }
    lg_image back;
    if (lg_test_read(t, name, &back, NULL)) {
        size_t bad = 0;
        for (size_t i = 0; i < (size_t)img->width * img->height * 4; i++)
            bad += i % 4 != 3 && back.pixels[i] != img->pixels[i];
        LG_TEST_CHECK(t, bad == 0, "%s: %zu channels did not survive the PNG round trip", name,
                      bad);
        lg_image_free(&back);
    }
}

static void case_png(lg_test *t)
{
    /* a 16 x 8 lat-long whose codes cover 0 .. 255, with an alpha the probe ignores */
    lg_image img = alloc_image(16, 8);
    for (uint32_t k = 0; k < 128; k++) {
        float *p = img.pixels + 4 * k;
        p[0] = code_lin(2 * k);
        p[1] = code_lin(255 - 2 * k);
        p[2] = code_lin((k * 37 + 1) % 256);
        p[3] = 0.5f;
    }
    write_png(t, "sky.png", &img);
    check_info(t, "sky = probe { file = \"sky.png\" }\n", LG_PROBE_LATLONG, 16, 8, 1.0f,
               "PNG lat-long (auto)");
    for (int e = 0; e < 2; e++) {
        lg_image raw;
        const char *def = e ? "sky = probe { file = \"sky.png\", exposure = 2 }\n"
                            : "sky = probe { file = \"sky.png\" }\n";
        if (!tap(t, def, "raw", NULL, &raw, NULL))
            continue;
        float peak = 0.0f;
        for (uint32_t k = 0; k < 128; k++)
            for (int c = 0; c < 4; c++) {
                float want = c == 3 ? 1.0f : img.pixels[4 * k + c] * (e ? 4.0f : 1.0f);
                float got = raw.pixels[4 * k + c];
                peak = c < 3 && got > peak ? got : peak;
                LG_TEST_CHECK(t, got == want, "%s texel %u channel %d: %.9g, want %.9g",
                              e ? "exposure 2:" : "PNG:", k, c, (double)got, (double)want);
            }
        LG_TEST_CHECK(t, peak == (e ? 4.0f : 1.0f), "the brightest texel is %g: code 255 is 1",
                      (double)peak);
        lg_image_free(&raw);
    }
    lg_image_free(&img);

    /* a horizontal cross PNG: a cube, its faces the decoded codes */
    lg_image faces = alloc_image(CN, 6 * CN);
    for (uint32_t f = 0; f < 6; f++)
        for (uint32_t j = 0; j < CN; j++)
            for (uint32_t i = 0; i < CN; i++) {
                float *p = pix(&faces, i, f * CN + j);
                p[0] = code_lin(20 + 40 * f + (i == MARK_I && j == MARK_J ? 3 : 0));
                p[1] = code_lin(200 - 30 * f);
                p[2] = code_lin(5 + 10 * f + j);
                p[3] = 1.0f;
            }
    lg_image cross = make_layout(&faces, 4, 3, cells_h);
    for (size_t k = 0; k < (size_t)cross.width * cross.height * 4; k++)
        if (cross.pixels[k] < 0.0f)
            cross.pixels[k] = 0.0f; /* unused cells: black (a PNG holds no negatives) */
    write_png(t, "cross.png", &cross);
    const char *def = "sky = probe { file = \"cross.png\" }\n";
    check_info(t, def, LG_PROBE_CUBE, CN, CN, 1.0f, "PNG cross (auto)");
    lg_image raw;
    if (tap(t, def, "raw", NULL, &raw, NULL)) {
        lg_test_tol tol = { 0 };
        lg_test_check_image(t, &raw, &faces, 32, &tol, "PNG cross: the GL cube's faces");
        lg_image_free(&raw);
    }
    lg_image_free(&cross);
    lg_image_free(&faces);
}

/* ---- environment ----------------------------------------------------------------------------- */

static bool line_has(const char *text, const char *prefix, const char *what)
{
    const char *l = strstr(text, prefix);
    if (!l)
        return false;
    const char *e = strchr(l, '\n');
    size_t len = e ? (size_t)(e - l) : strlen(l);
    char *s = malloc(len + 1);
    memcpy(s, l, len);
    s[len] = 0;
    bool ok = strstr(s, what) != NULL;
    free(s);
    return ok;
}

static void case_environment(lg_test *t)
{
    write_sized(t, "sky.exr", 16, 8);
    const char *g = "lightgraph 1\n"
                    "cube = test_cube {}\n"
                    "sky = probe { file = \"sky.exr\" }\n"
                    "env = environment { scene = cube, probe = sky }\n"
                    "a = test_needs_probe { scene = env }\n"
                    "b = test_needs_probe { scene = cube }\n"
                    "output a \"a.exr\"\n"
                    "output b \"b.exr\"\n";
    char *out = NULL;
    int rc = render(t, g, &out);
    const char *o = out ? out : "";
    LG_TEST_CHECK(t, rc == 0, "render failed:\n%s", o);
    LG_TEST_CHECK(t, line_has(o, "scene features (env):", "probe yes"), "env: no probe:\n%s", o);
    LG_TEST_CHECK(t, line_has(o, "scene features (cube):", "probe no"), "cube: a probe?\n%s", o);
    LG_TEST_CHECK(t, line_has(o, "  a ", "kept"), "a (scene with a probe) not kept:\n%s", o);
    LG_TEST_CHECK(t, line_has(o, "  b ", "gated"), "b (scene without a probe) not gated:\n%s", o);
    free(out);
    lg_image img;
    if (lg_test_read(t, "a.exr", &img, NULL)) {
        LG_TEST_CHECK(t, img.pixels[0] == 1, "a: %g, want 1 (ran)", (double)img.pixels[0]);
        lg_image_free(&img);
    }
    if (lg_test_read(t, "b.exr", &img, NULL)) {
        LG_TEST_CHECK(t, img.pixels[0] == 0, "b: %g, want 0 (gated)", (double)img.pixels[0]);
        lg_image_free(&img);
    }
}

/* ---- cache identity -------------------------------------------------------------------------- */

/* Renders probe -> raw tap -> test_cached; true when the cached node computed (a miss). */
static bool cache_computed(lg_test *t, const char *probe_def)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\n%s"
             "tap = probe_tap { probe = sky, mode = raw }\n"
             "m = test_cached { image = tap }\n"
             "output m \"m.exr\"\n",
             probe_def);
    lg_test_write_text(t, "c.lgraph", g);
    char *out = NULL;
    int rc = lg_test_render(t, "c.lgraph", NULL, &out);
    LG_TEST_CHECK(t, rc == 0, "render failed:\n%s", out ? out : "");
    bool computed = out && strstr(out, "computed");
    LG_TEST_CHECK(t, out && (computed || strstr(out, "reused")), "neither computed nor reused:\n%s",
                  out ? out : "");
    free(out);
    return computed;
}

static void case_content_key(lg_test *t)
{
    lg_image a = alloc_image(8, 4), b = alloc_image(8, 4);
    for (size_t k = 0; k < 32 * 4; k++) {
        a.pixels[k] = 0.5f + (float)k;
        b.pixels[k] = 0.5f + (float)k;
    }
    b.pixels[4 * 17 + 1] = 99.0f; /* one channel differs; same size, uncompressed */
    lg_test_write_exr(t, "p.exr", &a);
    const char *def = "sky = probe { file = \"p.exr\" }\n";
    LG_TEST_CHECK(t, cache_computed(t, def), "first render: not computed");
    LG_TEST_CHECK(t, !cache_computed(t, def), "same file: the cache was not used");
    lg_test_write_exr(t, "p.exr", &b);
    LG_TEST_CHECK(t, cache_computed(t, def), "changed pixels: stale cache entry used");
    LG_TEST_CHECK(t, !cache_computed(t, def), "same changed file: the cache was not used");
    LG_TEST_CHECK(t, cache_computed(t, "sky = probe { file = \"p.exr\", exposure = 1 }\n"),
                  "exposure changed: stale cache entry used");
    LG_TEST_CHECK(t,
                  cache_computed(t, "sky = probe { file = \"p.exr\", rotate_deg = [0, 0, 1] }\n"),
                  "rotation changed: stale cache entry used");
    lg_image_free(&a);
    lg_image_free(&b);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "latlong_asset", case_latlong_asset },
        { "angular_asset", case_angular_asset },
        { "cross_h", case_cross_h },
        { "cross_v", case_cross_v },
        { "strip_h", case_strip_h },
        { "strip_v", case_strip_v },
        { "faces", case_faces },
        { "cross_seams", case_cross_seams },
        { "auto_errors", case_auto_errors },
        { "latlong_not_2to1", case_latlong_not_2to1 },
        { "one_by_one", case_one_by_one },
        { "rotate_360", case_rotate_360 },
        { "exposure_scale", case_exposure_scale },
        { "bad_texels", case_bad_texels },
        { "png", case_png },
        { "environment", case_environment },
        { "content_key", case_content_key },
    };
    lg_test_main_opts opts = { .prefix = "probe", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &opts);
}
