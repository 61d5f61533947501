/*
 * The prt node through the host, on scenes, SH lighting and transfer with known values
 * built in memory by the test plugin testprtinputs (prt_testdata.h holds the values), on
 * cpu, gl and cl. A missing device is a failure (llvmpipe and PoCL are dependencies).
 *
 *   exact        the `vertices` output (EXR) against a C double reference of the dot
 *                products (5 bands, 172 vertices, two meshes, three instances): relative
 *                error <= 1e-5 of sum_i |l_i t_i| on every vertex and channel, alpha 1,
 *                padding 0, LG_VERTEX_IMAGE_WIDTH wide; the three backends agree likewise
 *   bands        lighting 6 bands with transfer 3, 2 with 4, 12 with 12, 10 with 17: the
 *                common prefix is used (reference with min(bands)), the debug log says so
 *   vertex_count a transfer of 100 vertices on the 172-vertex scene: a clear error
 *   rotation     a band-1 delta light at +X turned by rotate_deg = [90, 0, 0] equals the
 *                light made at R(+X) = -Z (lg_probe_rotation_from_euler's convention), and
 *                a 4-band delta light turned by [30, -20, 10] equals the light made at
 *                R d: rotation is exact, not a re-projection
 *   spin         spin 40 deg/s over --frames 3 --dt 0.5 (the outputs are written after
 *                the last frame, t = 1 s) equals a static rotate_deg with yaw + 40
 *   raster       `out` on a flat quad facing the camera: a constant transfer gives the
 *                constant on every covered pixel (alpha 1) and 0 with alpha 0 elsewhere;
 *                random per-vertex values are interpolated across the two triangles as
 *                the analytic camera predicts; `reflect` adds its RGB
 *   instances    the two instances of one mesh share its values: mirrored points of the
 *                two spheres (unshadowed diffuse transfer from the normals, light from +Y)
 *                agree with each other and with the analytic 3-band value
 *   bad_params   NaN and absurd rotate_deg / spin_deg_per_s, and a reflect image of another
 *                size: clear errors naming the parameter, no output file
 *   texture      the quad with a base colour texture: each pixel the untextured radiance
 *                times the sRGB-decoded texel (not the factor again); an alpha mask's hole
 *                not drawn
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/probe.h"
#include "lightgraph/sh.h"
#include "lightgraph/test.h"
#include "lightgraph/transfer.h"
#include "lightgraph/vecmath.h"

#include "prt_testdata.h"

#define MIXED_VERTICES 172u

static const char *const BACKENDS[] = { "cpu", "gl", "cl" };

/* Renders graph text `g` with `args`; reads `out` into *img (when img is given). Returns
 * the exit status; *text (optional) gets what the program printed. */
static int render(lg_test *t, const char *g, const char *const *args, const char *out,
                  lg_image *img, char **text)
{
    lg_test_write_text(t, "g.lgraph", g);
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0 || !img)
        return rc;
    return lg_test_read(t, out, img, NULL) ? 0 : -2;
}

/* The C reference: radiance of vertex v, channel c with `lb` lighting bands (seed ls) and
 * `tb` transfer bands (seed ts), in double, over the common prefix. *scale gets
 * sum |l t| (the size of the rounding a float sum may make). */
static double reference(uint32_t ls, uint32_t lb, uint32_t ts, uint32_t tb, uint32_t v, uint32_t c,
                        double *scale)
{
    uint32_t b = lb < tb ? lb : tb;
    double s = 0, a = 0;
    for (uint32_t i = 0; i < b * b; i++) {
        double p = (double)prt_test_light(ls, c, i) * (double)prt_test_transfer(ts, v, c, i);
        s += p;
        a += fabs(p);
    }
    *scale = a;
    return s;
}

/* Checks a `vertices` image against the reference; returns the largest error / scale. */
static double check_vertices(lg_test *t, const lg_image *img, const char *what, uint32_t lb,
                             uint32_t tb)
{
    uint32_t w = 0, h = 0;
    lg_vertex_image_size(MIXED_VERTICES, &w, &h);
    LG_TEST_CHECK(t, img->width == w && img->height == h, "%s: vertices image %ux%u, not %ux%u",
                  what, img->width, img->height, w, h);
    if (img->width != w || img->height != h)
        return INFINITY;
    double worst = 0;
    int bad = 0;
    for (uint32_t i = 0; i < w * h; i++) {
        const float *p = img->pixels + 4 * (size_t)i;
        if (i >= MIXED_VERTICES) {
            if ((p[0] != 0 || p[1] != 0 || p[2] != 0 || p[3] != 0) && bad++ < 5)
                LG_TEST_FAILF(t, "%s: padding texel %u is (%g, %g, %g, %g), not 0", what, i, p[0],
                              p[1], p[2], p[3]);
            continue;
        }
        if (p[3] != 1.0f && bad++ < 5)
            LG_TEST_FAILF(t, "%s: vertex %u alpha %g, not 1", what, i, p[3]);
        for (uint32_t c = 0; c < 3; c++) {
            double scale, want = reference(1, lb, 2, tb, i, c, &scale);
            double e = fabs(p[c] - want) / (scale > 1e-30 ? scale : 1e-30);
            worst = e > worst ? e : worst;
            if (!(e <= 1e-5) && bad++ < 5)
                LG_TEST_FAILF(t,
                              "%s: vertex %u channel %u is %.9g, the reference %.9g "
                              "(error %.3g of sum|l t| = %.3g)",
                              what, i, c, p[c], want, e, scale);
        }
    }
    return worst;
}

static const char *graph_vertices(char *g, size_t n, const char *backend, uint32_t lb, uint32_t tb,
                                  const char *extra)
{
    snprintf(g, n,
             "lightgraph 1\n"
             "s = test_prt_inputs_scene { }\n"
             "l = test_prt_sh { bands = %u, seed = 1 }\n"
             "tr = test_prt_transfer { bands = %u, seed = 2 }\n"
             "p = prt { scene = s, lighting = l, transfer = tr, backend = %s%s }\n"
             "output p.vertices \"v.exr\" float\n",
             lb, tb, backend, extra ? extra : "");
    return g;
}

/* ---- cases ----------------------------------------------------------------------------------- */

static void case_exact(lg_test *t)
{
    lg_image img[3] = { { 0 } };
    const char *args[] = { "--size", "64x48", NULL };
    for (int b = 0; b < 3; b++) {
        char g[1024];
        int rc = render(t, graph_vertices(g, sizeof g, BACKENDS[b], 5, 5, NULL), args, "v.exr",
                        &img[b], NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc)
            continue;
        double worst = check_vertices(t, &img[b], BACKENDS[b], 5, 5);
        lg_test_note_("%s: worst error %.3g of sum|l t|", BACKENDS[b], worst);
    }
    /* the backends against each other (the same bound, as all are within it of the
     * reference; here directly) */
    for (int b = 1; b < 3; b++) {
        if (!img[0].pixels || !img[b].pixels || img[0].width != img[b].width ||
            img[0].height != img[b].height)
            continue;
        for (uint32_t i = 0; i < MIXED_VERTICES; i++)
            for (uint32_t c = 0; c < 3; c++) {
                double scale;
                reference(1, 5, 2, 5, i, c, &scale);
                double d = fabs(img[0].pixels[4 * i + c] - img[b].pixels[4 * i + c]);
                LG_TEST_CHECK(t, d <= 2e-5 * scale,
                              "cpu and %s differ at vertex %u channel "
                              "%u: %g",
                              BACKENDS[b], i, c, d);
            }
    }
    for (int b = 0; b < 3; b++)
        lg_image_free(&img[b]);
}

static void case_bands(lg_test *t)
{
    /* {12, 12} and {17, 10}: the cpu loop's record path at a run-time stride and its
     * per-channel path (stride 289 > PRT_RECORD_MAX) */
    static const uint32_t pairs[4][2] = { { 6, 3 }, { 2, 4 }, { 12, 12 }, { 10, 17 } };
    const char *args[] = { "--size", "32x24", "-v", "-v", NULL };
    for (int b = 0; b < 3; b++)
        for (int k = 0; k < 4; k++) {
            char g[1024], what[64];
            snprintf(what, sizeof what, "%s, lighting %u bands, transfer %u", BACKENDS[b],
                     pairs[k][0], pairs[k][1]);
            lg_image img = { 0 };
            char *text = NULL;
            int rc =
                render(t, graph_vertices(g, sizeof g, BACKENDS[b], pairs[k][0], pairs[k][1], NULL),
                       args, "v.exr", &img, &text);
            LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", what, rc);
            if (!rc) {
                check_vertices(t, &img, what, pairs[k][0], pairs[k][1]);
                char want[64];
                uint32_t m = pairs[k][0] < pairs[k][1] ? pairs[k][0] : pairs[k][1];
                snprintf(want, sizeof want, "using the first %u", m);
                bool differ = pairs[k][0] != pairs[k][1], said = text && strstr(text, want);
                LG_TEST_CHECK(t, said == differ, "%s: the debug log %s '%s':\n%s", what,
                              differ ? "does not say" : "says", want, text ? text : "");
            }
            free(text);
            lg_image_free(&img);
        }
}

static void case_vertex_count(lg_test *t)
{
    for (int b = 0; b < 3; b++) {
        char g[1024];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_prt_inputs_scene { }\n"
                 "l = test_prt_sh { bands = 3 }\n"
                 "tr = test_prt_transfer { bands = 3, vertices = 100 }\n"
                 "p = prt { scene = s, lighting = l, transfer = tr, backend = %s }\n"
                 "output p.vertices \"v.exr\" float\n",
                 BACKENDS[b]);
        char *text = NULL;
        const char *args[] = { "--size", "32x24", NULL };
        int rc = render(t, g, args, NULL, NULL, &text);
        LG_TEST_CHECK(t, rc != 0, "%s: a 100-vertex transfer on a 172-vertex scene rendered",
                      BACKENDS[b]);
        LG_TEST_CHECK(t,
                      text && strstr(text, "input 'transfer' has 100 vertices but the "
                                           "scene has 172"),
                      "%s: the message does not name the counts:\n%s", BACKENDS[b],
                      text ? text : "");
        LG_TEST_CHECK(t, text && strstr(text, "p"), "%s: no node named", BACKENDS[b]);
        FILE *f = fopen(lg_test_path(t, "v.exr"), "rb");
        LG_TEST_CHECK(t, !f, "%s: an output file was written after the error", BACKENDS[b]);
        if (f)
            fclose(f);
        free(text);
    }
}

/* The vertices image of a delta light along d (bands, colour 1) with rotate_deg. */
static int delta_render(lg_test *t, const char *backend, uint32_t bands, const double d[3],
                        const double rot[3], lg_image *img)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_prt_inputs_scene { }\n"
             "l = test_prt_sh { bands = %u, mode = delta, dir = [%.17g, %.17g, %.17g] }\n"
             "tr = test_prt_transfer { bands = %u }\n"
             "p = prt { scene = s, lighting = l, transfer = tr, backend = %s, "
             "rotate_deg = [%.17g, %.17g, %.17g] }\n"
             "output p.vertices \"v.exr\" float\n",
             bands, d[0], d[1], d[2], bands, backend, rot[0], rot[1], rot[2]);
    const char *args[] = { "--size", "32x24", NULL };
    return render(t, g, args, "v.exr", img, NULL);
}

static void compare_vertex_images(lg_test *t, const lg_image *a, const lg_image *b, double tol,
                                  const char *what)
{
    if (!a->pixels || !b->pixels || a->width != b->width || a->height != b->height) {
        LG_TEST_FAILF(t, "%s: images missing or of different sizes", what);
        return;
    }
    double worst = 0;
    for (uint32_t i = 0; i < MIXED_VERTICES; i++)
        for (int c = 0; c < 3; c++) {
            double d = fabs(a->pixels[4 * i + c] - b->pixels[4 * i + c]);
            worst = d > worst ? d : worst;
        }
    LG_TEST_CHECK(t, worst <= tol, "%s: largest difference %.3g > %.3g", what, worst, tol);
    lg_test_note_("%s: largest difference %.3g", what, worst);
}

static void case_rotation(lg_test *t)
{
    /* the convention: yaw 90 takes +X to -Z (R = Ry(90), counter-clockwise about +Y) */
    float R[9];
    lg_probe_rotation_from_euler(90, 0, 0, R);
    double rx[3] = { R[0], R[1], R[2] }; /* column 0 = R (+X) */
    LG_TEST_CHECK(t, fabs(rx[0]) < 1e-6 && fabs(rx[1]) < 1e-6 && fabs(rx[2] + 1) < 1e-6,
                  "yaw 90 takes +X to (%g, %g, %g), not -Z", rx[0], rx[1], rx[2]);
    static const double px[3] = { 1, 0, 0 }, zero[3] = { 0, 0, 0 }, yaw90[3] = { 90, 0, 0 };
    static const double rot[3] = { 30, -20, 10 }, d0[3] = { 0.48, 0.6, -0.64 };
    float R2[9];
    lg_probe_rotation_from_euler((float)rot[0], (float)rot[1], (float)rot[2], R2);
    double rd[3];
    for (int r = 0; r < 3; r++)
        rd[r] = R2[r] * d0[0] + R2[3 + r] * d0[1] + R2[6 + r] * d0[2];
    for (int b = 0; b < 3; b++) {
        char what[96];
        lg_image a = { 0 }, c = { 0 };
        int rc = delta_render(t, BACKENDS[b], 2, px, yaw90, &a);
        rc |= delta_render(t, BACKENDS[b], 2, rx, zero, &c);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed", BACKENDS[b]);
        snprintf(what, sizeof what, "%s: band-1 light at +X turned by yaw 90 vs made at -Z",
                 BACKENDS[b]);
        if (!rc)
            compare_vertex_images(t, &a, &c, 2e-6, what);
        lg_image_free(&a);
        lg_image_free(&c);
        rc = delta_render(t, BACKENDS[b], 4, d0, rot, &a);
        rc |= delta_render(t, BACKENDS[b], 4, rd, zero, &c);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed", BACKENDS[b]);
        snprintf(what, sizeof what, "%s: 4-band light turned by [30, -20, 10] vs made at R d",
                 BACKENDS[b]);
        if (!rc)
            compare_vertex_images(t, &a, &c, 2e-5, what);
        lg_image_free(&a);
        lg_image_free(&c);
    }
}

static void case_spin(lg_test *t)
{
    for (int b = 0; b < 3; b++) {
        char g[1024];
        lg_image a = { 0 }, c = { 0 };
        graph_vertices(g, sizeof g, BACKENDS[b], 4, 4,
                       ", rotate_deg = [10, 20, 0], spin_deg_per_s = 40");
        const char *args[] = { "--size", "32x24", "--frames", "3", "--dt", "0.5", NULL };
        int rc = render(t, g, args, "v.exr", &a, NULL);
        graph_vertices(g, sizeof g, BACKENDS[b], 4, 4, ", rotate_deg = [50, 20, 0]");
        const char *args1[] = { "--size", "32x24", NULL };
        rc |= render(t, g, args1, "v.exr", &c, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed", BACKENDS[b]);
        char what[96];
        snprintf(what, sizeof what, "%s: frame 2 of spin 40 deg/s vs rotate_deg yaw 50",
                 BACKENDS[b]);
        if (!rc)
            compare_vertex_images(t, &a, &c, 1e-6, what);
        /* and the spin did turn something: frame 2 differs from no spin */
        lg_image s = { 0 };
        graph_vertices(g, sizeof g, BACKENDS[b], 4, 4, ", rotate_deg = [10, 20, 0]");
        if (!rc && render(t, g, args1, "v.exr", &s, NULL) == 0) {
            double d = 0;
            for (uint32_t i = 0; i < 4 * MIXED_VERTICES; i++)
                d = fmax(d, fabs(a.pixels[i] - s.pixels[i]));
            LG_TEST_CHECK(t, d > 1e-3, "%s: the spin changed nothing (%g)", BACKENDS[b], d);
        }
        lg_image_free(&s);
        lg_image_free(&a);
        lg_image_free(&c);
    }
}

/* The quad layout seen by its camera: the world point (x, y) on z = 0 through pixel centre
 * (px, py) of a w x h image (as lg_scene_view_make builds the camera: eye (0, 0, 5)
 * looking along -Z, 40 degrees vertical). */
static void quad_point(uint32_t w, uint32_t h, uint32_t px, uint32_t py, double *x, double *y)
{
    double tn = tan(0.5 * 40.0 * LG_PI / 180.0), a = (double)w / h;
    double sx = (2.0 * (px + 0.5) / w - 1.0) * tn * a, sy = (1.0 - 2.0 * (py + 0.5) / h) * tn;
    *x = 5.0 * sx;
    *y = 5.0 * sy;
}

static void case_raster(lg_test *t)
{
    const uint32_t W = 64, H = 48;
    const char *args[] = { "--size", "64x48", NULL };
    for (int b = 0; b < 3; b++) {
        for (int mode = 0; mode < 2; mode++) {
            /* mode 0: constant transfer (+ reflect); mode 1: random per-vertex values */
            char g[1024];
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_prt_inputs_scene { layout = quad }\n"
                     "l = test_prt_sh { bands = 3, seed = 1 }\n"
                     "tr = test_prt_transfer { bands = 3, seed = 2, vertices = 4, mode = %s }\n"
                     "%s"
                     "p = prt { scene = s, lighting = l, transfer = tr, backend = %s%s }\n"
                     "output p \"o.exr\" float\n",
                     mode ? "random" : "constant",
                     mode ? "" : "r = constant { color = [0.25, 0.5, 2] }\n", BACKENDS[b],
                     mode ? "" : ", reflect = r");
            lg_image img = { 0 };
            int rc = render(t, g, args, "o.exr", &img, NULL);
            LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
            if (rc)
                continue;
            double V[4][3], scale = 0;
            for (uint32_t v = 0; v < 4; v++)
                for (uint32_t c = 0; c < 3; c++) {
                    double s;
                    V[v][c] = reference(1, 3, 2, 3, mode ? v : 0, c, &s);
                    scale = fmax(scale, s);
                }
            static const double refl[3] = { 0.25, 0.5, 2 };
            uint32_t covered = 0, checked = 0;
            int bad = 0;
            for (uint32_t py = 0; py < H; py++)
                for (uint32_t px = 0; px < W; px++) {
                    const float *p = img.pixels + 4 * ((size_t)py * W + px);
                    double x, y;
                    quad_point(W, H, px, py, &x, &y);
                    double u = (x + 1) / 2, w = (y + 1) / 2;
                    bool inside = u > 0.01 && u < 0.99 && w > 0.01 && w < 0.99;
                    bool outside = u < -0.01 || u > 1.01 || w < -0.01 || w > 1.01;
                    if (p[3] == 1.0f)
                        covered++;
                    double want[3];
                    for (int c = 0; c < 3; c++) {
                        /* the grid's triangles (a, b, d) and (a, d, c) of corners a (-1,-1),
                         * b (1,-1), c (-1,1), d (1,1): vertices 0, 1, 2, 3 = a, b, c, d */
                        double val = u >= w ? V[0][c] * (1 - u) + V[1][c] * (u - w) + V[3][c] * w
                                            : V[0][c] * (1 - w) + V[2][c] * (w - u) + V[3][c] * u;
                        want[c] = (outside ? 0.0 : val) + (mode ? 0.0 : refl[c]);
                    }
                    if (inside && fabs(u - w) > 0.02) {
                        checked++;
                        double tol = mode ? 2e-3 * scale : 1e-5 * (scale + 2);
                        for (int c = 0; c < 3; c++)
                            if (!(fabs(p[c] - want[c]) <= tol) && bad++ < 5)
                                LG_TEST_FAILF(t,
                                              "%s mode %d: pixel (%u, %u) channel %d is %.7g, "
                                              "expected %.7g",
                                              BACKENDS[b], mode, px, py, c, p[c], want[c]);
                        if (p[3] != 1.0f && bad++ < 5)
                            LG_TEST_FAILF(t, "%s: covered pixel (%u, %u) alpha %g", BACKENDS[b], px,
                                          py, p[3]);
                    } else if (outside) {
                        for (int c = 0; c < 3; c++)
                            if (p[c] != (float)want[c] && bad++ < 5)
                                LG_TEST_FAILF(t,
                                              "%s mode %d: background (%u, %u) channel %d is "
                                              "%g, expected %g",
                                              BACKENDS[b], mode, px, py, c, p[c], want[c]);
                        if (p[3] != 0.0f && bad++ < 5)
                            LG_TEST_FAILF(t, "%s: background pixel (%u, %u) alpha %g", BACKENDS[b],
                                          px, py, p[3]);
                    }
                }
            LG_TEST_CHECK(t, checked > 300 && covered > 300 && covered < W * H / 2,
                          "%s: %u pixels covered, %u checked", BACKENDS[b], covered, checked);
            lg_image_free(&img);
        }
    }
}

/* Textures (README "Textures"): the quad with constant transfer, untextured and with a base
 * colour texture, on every backend. (a) halves: every covered pixel is the untextured one
 * times the texel, sRGB-decoded (left (255, 255, 255): equal bit for bit; right (255, 128,
 * 32): within llvmpipe's sRGB decode of lg_srgb_decode, 2e-3 of the texel, the ratio
 * re-encoding to the texel's byte) and not the factor again;
 * (b) mask: the top-left quarter (alpha 0 texel, MASK) is not drawn (RGB 0, alpha 0) and the
 * rest is the untextured image. */
static void case_texture(lg_test *t)
{
    const uint32_t W = 64, H = 48;
    const char *args[] = { "--size", "64x48", NULL };
    static const char *const tex[] = { "none", "halves", "mask" };
    for (int b = 0; b < 3; b++) {
        lg_image img[3] = { { 0 } };
        bool ok = true;
        for (int k = 0; k < 3; k++) {
            char g[1024];
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_prt_inputs_scene { layout = quad, texture = %s }\n"
                     "l = test_prt_sh { bands = 3, seed = 1 }\n"
                     "tr = test_prt_transfer { bands = 3, seed = 2, vertices = 4, "
                     "mode = constant }\n"
                     "p = prt { scene = s, lighting = l, transfer = tr, backend = %s }\n"
                     "output p \"o.exr\" float\n",
                     tex[k], BACKENDS[b]);
            int rc = render(t, g, args, "o.exr", &img[k], NULL);
            LG_TEST_CHECK(t, rc == 0, "%s texture %s: render failed (%d)", BACKENDS[b], tex[k], rc);
            ok &= rc == 0;
        }
        if (ok) {
            const float right[3] = { 1.0f, lg_srgb_decode(128.0f / 255.0f),
                                     lg_srgb_decode(32.0f / 255.0f) };
            uint32_t covered = 0, left_n = 0, right_n = 0, hole = 0;
            int bad = 0;
            for (uint32_t py = 0; py < H; py++)
                for (uint32_t px = 0; px < W; px++) {
                    const float *p0 = img[0].pixels + 4 * ((size_t)py * W + px);
                    const float *p1 = img[1].pixels + 4 * ((size_t)py * W + px);
                    const float *p2 = img[2].pixels + 4 * ((size_t)py * W + px);
                    double x, y;
                    quad_point(W, H, px, py, &x, &y);
                    double u = (x + 1) / 2, v = (1 - y) / 2; /* the texture's (u, v) */
                    bool inside = u > 0.02 && u < 0.98 && v > 0.02 && v < 0.98;
                    if (!inside || fabs(u - 0.5) < 0.03 || fabs(v - 0.5) < 0.03) {
                        /* edges: only agreement on what is drawn */
                        if ((p0[3] == 0.0f) != (p1[3] == 0.0f) && bad++ < 5)
                            LG_TEST_FAILF(t, "%s: (%u, %u) drawn in one image only", BACKENDS[b],
                                          px, py);
                        continue;
                    }
                    covered++;
                    for (int c = 0; c < 3; c++) {
                        /* llvmpipe decodes sRGB with an approximation (texgl's tests: 1.2e-3
                         * of the texel measured): 2e-3 of the texel, and the texel the ratio
                         * gives re-encodes to its byte exactly */
                        double want = u < 0.5 ? p0[c] : (double)p0[c] * right[c];
                        double tol = u < 0.5 ? 0.0 : 2e-3 * fabs(p0[c]) + 1e-7;
                        int byte = (int)lroundf(lg_srgb_encode(p1[c] / p0[c]) * 255.0f);
                        int want_byte = u < 0.5 ? 255
                                                : (int)lroundf(lg_srgb_encode(right[c]) * 255.0f);
                        if ((!(fabs(p1[c] - want) <= tol) || byte != want_byte) && bad++ < 5)
                            LG_TEST_FAILF(t,
                                          "%s halves: (%u, %u) channel %d is %.7g, the "
                                          "untextured %.7g times the texel: %.7g (texel byte "
                                          "%d, not %d)",
                                          BACKENDS[b], px, py, c, p1[c], p0[c], want, byte,
                                          want_byte);
                    }
                    left_n += u < 0.5, right_n += u >= 0.5;
                    bool in_hole = u < 0.5 && v < 0.5;
                    hole += in_hole;
                    for (int c = 0; c < 4; c++) {
                        float want = in_hole ? 0.0f : p0[c];
                        if (p2[c] != want && bad++ < 5)
                            LG_TEST_FAILF(t, "%s mask: (%u, %u) channel %d is %g, expected %g",
                                          BACKENDS[b], px, py, c, p2[c], want);
                    }
                }
            LG_TEST_CHECK(t, covered > 300 && left_n > 100 && right_n > 100 && hole > 50,
                          "%s: %u pixels checked (%u left, %u right, %u in the hole)", BACKENDS[b],
                          covered, left_n, right_n, hole);
        }
        for (int k = 0; k < 3; k++)
            lg_image_free(&img[k]);
    }
}

/* The pixel where world point p lands (the quad_point camera). */
static void project(uint32_t w, uint32_t h, const double p[3], uint32_t *px, uint32_t *py)
{
    double tn = tan(0.5 * 40.0 * LG_PI / 180.0), a = (double)w / h;
    double sx = p[0] / (5.0 - p[2]), sy = p[1] / (5.0 - p[2]);
    *px = (uint32_t)lround((sx / (tn * a) + 1.0) / 2.0 * w - 0.5);
    *py = (uint32_t)lround((1.0 - sy / tn) / 2.0 * h - 0.5);
}

/* Instances share their mesh's values: the mixed scene's sphere, drawn at x = -1 and +1,
 * lit from +Y with the unshadowed diffuse transfer of its normals, looks the same at the
 * mirrored points (-1, 0.42, 0.42) and (1, 0.42, 0.42) (normal (0, 0.7, 0.7)), and
 * brighter than the grid behind (normal +Z, n.l = 0). */
static void case_instances(lg_test *t)
{
    const uint32_t W = 64, H = 48;
    const char *args[] = { "--size", "64x48", NULL };
    for (int b = 0; b < 3; b++) {
        char g[1024];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_prt_inputs_scene { }\n"
                 "l = test_prt_sh { bands = 3, mode = delta, dir = [0, 1, 0] }\n"
                 "tr = test_prt_transfer { bands = 3, mode = normal, scene = s }\n"
                 "p = prt { scene = s, lighting = l, transfer = tr, backend = %s }\n"
                 "output p \"o.exr\" float\n",
                 BACKENDS[b]);
        lg_image img = { 0 };
        int rc = render(t, g, args, "o.exr", &img, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc)
            continue;
        const double pl[3] = { -1, 0.42, 0.42 }, pr[3] = { 1, 0.42, 0.42 }, pg[3] = { 0, -1.5, -1 };
        uint32_t x[3], y[3];
        project(W, H, pl, &x[0], &y[0]);
        project(W, H, pr, &x[1], &y[1]);
        project(W, H, pg, &x[2], &y[2]);
        const float *v[3];
        for (int k = 0; k < 3; k++)
            v[k] = img.pixels + 4 * ((size_t)y[k] * W + x[k]);
        /* analytic, 3 bands, at the normal where the pixel's ray meets the sphere:
         * (0.8 / pi) (1/4 + (1/2) n.l + (5/16) P2(n.l)), l = +Y; the mesh is 12 x 6 quads,
         * so the interpolated value is within 15% of it */
        double want[2];
        for (int k = 0; k < 2; k++) {
            double xw, yw;
            quad_point(W, H, x[k], y[k], &xw, &yw); /* the ray through (xw, yw, 0) */
            double d[3] = { xw, yw, -5.0 }, o[3] = { 0, 0, 5 }, cx = k ? 1.0 : -1.0;
            double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int i = 0; i < 3; i++)
                d[i] /= len;
            double oc[3] = { o[0] - cx, o[1], o[2] };
            double bq = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
            double cq = oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - 0.36;
            double tq = -bq - sqrt(fmax(bq * bq - cq, 0.0));
            double ny = (o[1] + tq * d[1]) / 0.6;
            want[k] = 0.8 / LG_PI * (0.25 + 0.5 * ny + 5.0 / 16.0 * 0.5 * (3 * ny * ny - 1));
        }
        double grid = 0.8 / LG_PI * (0.25 - 5.0 / 32.0);
        for (int c = 0; c < 3; c++) {
            LG_TEST_CHECK(t, fabs(v[0][c] - v[1][c]) <= 0.02 * want[0],
                          "%s: the two instances differ at mirrored points (%u, %u) and (%u, "
                          "%u): %g and %g",
                          BACKENDS[b], x[0], y[0], x[1], y[1], v[0][c], v[1][c]);
            for (int k = 0; k < 2; k++)
                LG_TEST_CHECK(t, fabs(v[k][c] - want[k]) <= 0.15 * want[k],
                              "%s: instance %d at (%u, %u) is %g, the analytic %g", BACKENDS[b], k,
                              x[k], y[k], v[k][c], want[k]);
            LG_TEST_CHECK(t, fabs(v[2][c] - grid) <= 1e-4,
                          "%s: the grid at (%u, %u) is %g, the analytic %g", BACKENDS[b], x[2],
                          y[2], v[2][c], grid);
        }
        lg_image_free(&img);
    }
}

static void case_bad_params(lg_test *t)
{
    static const struct {
        const char *set, *says;
    } cases[] = {
        { "rotate_deg = [nan, 0, 0]", "rotate_deg" },
        { "rotate_deg = [0, 1e9, 0]", "rotate_deg" },
        { "spin_deg_per_s = inf", "spin_deg_per_s" },
        { "spin_deg_per_s = -1e12", "spin_deg_per_s" },
        { "reflect = r", "input 'reflect' is 7x5 but the output is 32x24" },
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char g[1024];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_prt_inputs_scene { }\n"
                 "l = test_prt_sh { bands = 3 }\n"
                 "tr = test_prt_transfer { bands = 3 }\n"
                 "r = constant { width = 7, height = 5 }\n"
                 "p = prt { scene = s, lighting = l, transfer = tr, backend = cpu, %s }\n"
                 "output p \"o.exr\" float\n",
                 cases[k].set);
        char *text = NULL;
        const char *args[] = { "--size", "32x24", NULL };
        int rc = render(t, g, args, NULL, NULL, &text);
        LG_TEST_CHECK(t, rc == 1 || rc == 2, "%s: exit status %d, not 1 or 2", cases[k].set, rc);
        LG_TEST_CHECK(t, text && strstr(text, cases[k].says),
                      "%s: the message does not say '%s':\n%s", cases[k].set, cases[k].says,
                      text ? text : "");
        FILE *f = fopen(lg_test_path(t, "o.exr"), "rb");
        LG_TEST_CHECK(t, !f, "%s: an output file was written", cases[k].set);
        if (f)
            fclose(f);
        free(text);
    }
}

/* testprtinputs's folder, and an empty cache per case */
static void setup(lg_test *t)
{
    lg_test_use_plugins(t, PRT_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "exact", case_exact },
        { "bands", case_bands },
        { "vertex_count", case_vertex_count },
        { "rotation", case_rotation },
        { "spin", case_spin },
        { "raster", case_raster },
        { "texture", case_texture },
        { "instances", case_instances },
        { "bad_params", case_bad_params },
    };
    lg_test_main_opts o = { .prefix = "prt", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
