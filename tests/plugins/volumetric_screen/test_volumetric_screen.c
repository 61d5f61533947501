/*
 * The volumetric_screen node through the host, on scenes and lit images with known values
 * made in memory by the test plugin testvsinputs, on gl and cpu (a missing GL device is a
 * failure). The test camera looks down -Z from the origin (60 degrees, 32 x 24 pixels), so
 * a light travelling along +Z sits at the image centre (16, 12).
 *
 *   series     Mitchell's constant-input geometric series: sky everywhere, thesis model,
 *              normalize = false: inscatter = exposure weight L_c decay (1 - decay^N) /
 *              (1 - decay) / N on every pixel (N = 1, 7, 64); out = base + inscatter
 *   normalize  normalize = true on the same input: exposure weight L_c for N = 8, 64, 256
 *   behind     a light behind the camera (w < 0), in the image plane (w = 0), just in front
 *              of it (w = 1e-7): no contribution, out = base (both models); w = 0.05 (far
 *              off-screen, some samples inside): finite, > 0 near the side it lies on
 *   outside    the light off-screen: samples outside the image count as not visible; the
 *              series counts only the samples inside (a double reference, within one
 *              sample's weight per pixel)
 *   occluder   a surface (depth 0.5) between a pixel and the light gives less; a pixel
 *              whose samples miss it is unchanged
 *   lights32   32 lights = the sum of the 32 single-light renders (with an occluder)
 *   physical   unoccluded, physical model: L_c sigma_s p_HG(g, cos) d seg(sigma_t d) with d
 *              = z_limit / cos (and = zfar with z_limit = 0); out = base e^(-sigma_t d) + L_v
 *   example    gl and cpu agree on examples/volumetric_scene.lgraph (64 x 36); the shafts
 *              are there (inscatter > 0 somewhere, not everywhere the same)
 *   gating     a medium of density 0: the node does not run, out = base, inscatter black,
 *              --explain says why
 *   errors     absurd and NaN parameters, a base without depth, 33 lights: a clear error
 *              naming the value, no output file
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/medium.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#define W 32
#define H 24

static const char *const BACKENDS[] = { "gl", "cpu" };

/* Writes graph `g`, renders it at W x H and reads `out` (when given) into *img. Returns
 * the exit status (-2: the output could not be read). */
static int render(lg_test *t, const char *g, const char *size, const char *out, lg_image *img,
                  char **text)
{
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", size ? size : "32x24", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0 || !img)
        return rc;
    return lg_test_read(t, out, img, NULL) ? 0 : -2;
}

/* One vol node on `backend` with extra parameters `vol` over scene parameters `scene` and
 * base parameters `base`; reads inscatter into *ins and out into *out (may be NULL). */
static bool run_vol(lg_test *t, const char *backend, const char *scene, const char *base,
                    const char *vol, lg_image *ins, lg_image *out)
{
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_vs_scene { %s }\n"
             "b = test_vs_base { %s }\n"
             "vol = volumetric_screen { scene = s, base = b, backend = %s, %s }\n"
             "output vol.inscatter \"ins.exr\" float\n"
             "output vol \"out.exr\" float\n",
             scene, base, backend, vol);
    int rc = render(t, g, NULL, "ins.exr", ins, NULL);
    if (rc == 0 && out && !lg_test_read(t, "out.exr", out, NULL))
        rc = -2;
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d): scene {%s} base {%s} vol {%s}", backend, rc,
                  scene, base, vol);
    return rc == 0;
}

static const float *px(const lg_image *img, uint32_t x, uint32_t y)
{
    return img->pixels + 4 * ((size_t)y * img->width + x);
}

/* Every channel of every pixel finite. */
static bool all_finite(const lg_image *img)
{
    for (size_t i = 0; i < 4 * (size_t)img->width * img->height; i++)
        if (!isfinite(img->pixels[i]))
            return false;
    return true;
}

/* ---- series, normalize ----------------------------------------------------------------------- */

static void case_series(lg_test *t)
{
    static const int Ns[] = { 1, 7, 64 };
    const double exposure = 2.0, weight = 0.05, decay = 0.9, Lc = 10.0;
    const double base[3] = { 0.2, 0.3, 0.4 };
    for (size_t b = 0; b < 2; b++)
        for (size_t k = 0; k < 3; k++) {
            int N = Ns[k];
            char vol[256];
            snprintf(vol, sizeof vol,
                     "model = thesis, normalize = false, samples = %d, exposure = %g, "
                     "weight = %g, decay = %g",
                     N, exposure, weight, decay);
            lg_image ins = { 0 }, out = { 0 };
            if (!run_vol(t, BACKENDS[b], "", "", vol, &ins, &out))
                continue;
            double want = exposure * weight * Lc * decay * (1 - pow(decay, N)) / (1 - decay) / N;
            lg_image ref = { 0 }, refo = { 0 };
            lg_image_alloc(&ref, W, H);
            lg_image_alloc(&refo, W, H);
            for (size_t i = 0; i < (size_t)W * H; i++)
                for (int c = 0; c < 4; c++) {
                    ref.pixels[4 * i + c] = c < 3 ? (float)want : 1.0f;
                    refo.pixels[4 * i + c] = c < 3 ? (float)(base[c] + want) : 1.0f;
                }
            lg_test_tol tol = { .max_abs = 1e-7, .rel = 1e-5 };
            char what[64];
            snprintf(what, sizeof what, "%s N=%d inscatter", BACKENDS[b], N);
            lg_test_check_image(t, &ins, &ref, 32, &tol, what);
            snprintf(what, sizeof what, "%s N=%d out", BACKENDS[b], N);
            lg_test_check_image(t, &out, &refo, 32, &tol, what);
            lg_image_free(&ins);
            lg_image_free(&out);
            lg_image_free(&ref);
            lg_image_free(&refo);
        }
}

static void case_normalize(lg_test *t)
{
    static const int Ns[] = { 8, 64, 256 };
    const double exposure = 1.5, weight = 0.02, Lc = 10.0;
    for (size_t b = 0; b < 2; b++)
        for (size_t k = 0; k < 3; k++) {
            char vol[256];
            snprintf(vol, sizeof vol,
                     "model = thesis, normalize = true, samples = %d, exposure = %g, "
                     "weight = %g, decay = 0.94",
                     Ns[k], exposure, weight);
            lg_image ins = { 0 };
            if (!run_vol(t, BACKENDS[b], "", "", vol, &ins, NULL))
                continue;
            double want = exposure * weight * Lc;
            for (uint32_t y = 0; y < H; y++)
                for (uint32_t x = 0; x < W; x++) {
                    const float *p = px(&ins, x, y);
                    for (int c = 0; c < 3; c++)
                        if (fabs(p[c] - want) > 2e-6 * want) {
                            LG_TEST_FAILF(t,
                                          "%s N=%d: pixel (%u, %u) channel %d is %.9g, not "
                                          "%.9g",
                                          BACKENDS[b], Ns[k], x, y, c, p[c], want);
                            x = W, y = H;
                            break;
                        }
                }
            lg_image_free(&ins);
        }
}

/* ---- behind, outside, occluder --------------------------------------------------------------- */

static void case_behind(lg_test *t)
{
    static const struct {
        const char *dir, *what;
    } zero[] = {
        { "direction = [0, 0, -1]", "behind the camera (w < 0)" },
        { "direction = [1, 0, 0]", "in the image plane (w = 0)" },
        { "direction = [0, 1, 0]", "in the image plane, vertical (w = 0)" },
        { "direction = [1, 0, 1e-7]", "just in front of the image plane (w = 1e-7)" },
    };
    static const char *const models[] = { "model = thesis", "model = physical" };
    const size_t nz = sizeof zero / sizeof zero[0];
    for (size_t b = 0; b < 2; b++)
        for (size_t m = 0; m < 2; m++) {
            /* one render: a scene and a node per direction */
            char g[4096];
            int len = snprintf(g, sizeof g,
                               "lightgraph 1\n"
                               "b = test_vs_base { box_x1 = 8, box_y1 = 8 }\n");
            for (size_t k = 0; k < nz; k++)
                len += snprintf(g + len, sizeof g - (size_t)len,
                                "s%zu = test_vs_scene { %s }\n"
                                "v%zu = volumetric_screen { scene = s%zu, base = b, "
                                "backend = %s, %s }\n"
                                "output v%zu.inscatter \"ins%zu.exr\" float\n"
                                "output v%zu \"out%zu.exr\" float\n",
                                k, zero[k].dir, k, k, BACKENDS[b], models[m], k, k, k, k);
            int rc = render(t, g, NULL, NULL, NULL, NULL);
            LG_TEST_CHECK(t, rc == 0, "%s %s: render failed (%d)", BACKENDS[b], models[m], rc);
            for (size_t k = 0; k < nz && rc == 0; k++) {
                char ni[32], no[32];
                snprintf(ni, sizeof ni, "ins%zu.exr", k);
                snprintf(no, sizeof no, "out%zu.exr", k);
                lg_image ins = { 0 }, out = { 0 };
                if (!lg_test_read(t, ni, &ins, NULL) || !lg_test_read(t, no, &out, NULL))
                    continue;
                bool ok = true;
                for (uint32_t y = 0; y < H && ok; y++)
                    for (uint32_t x = 0; x < W && ok; x++) {
                        const float *a = px(&ins, x, y), *o = px(&out, x, y);
                        ok = a[0] == 0.0f && a[1] == 0.0f && a[2] == 0.0f && a[3] == 1.0f;
                        /* physical: base attenuated, never brighter */
                        ok = ok && isfinite(o[0]) && o[0] <= 0.2f && o[3] == 1.0f;
                        if (m == 0)
                            ok = ok && o[0] == 0.2f && o[1] == 0.3f && o[2] == 0.4f;
                        if (!ok)
                            LG_TEST_FAILF(t,
                                          "%s %s, %s: pixel (%u, %u) inscatter (%g, %g, %g, "
                                          "%g), out (%g, %g, %g)",
                                          BACKENDS[b], models[m], zero[k].what, x, y, a[0], a[1],
                                          a[2], a[3], o[0], o[1], o[2]);
                    }
                lg_image_free(&ins);
                lg_image_free(&out);
            }
            /* w = 0.05: p_l some 400 pixels left of the image; the first samples of pixels on
             * the right stay inside, those of the left edge leave at once */
            lg_image ins = { 0 };
            if (!run_vol(t, BACKENDS[b], "direction = [1, 0, 0.05]", "", models[m], &ins, NULL))
                continue;
            LG_TEST_CHECK(t, all_finite(&ins), "%s %s, w = 0.05: a value is not finite",
                          BACKENDS[b], models[m]);
            LG_TEST_CHECK(t, px(&ins, 31, 12)[0] > 0.0f && px(&ins, 31, 12)[0] > px(&ins, 0, 12)[0],
                          "%s %s, w = 0.05: pixel (31, 12) has %g, (0, 12) %g: the far right "
                          "should see samples inside the image, more than the far left",
                          BACKENDS[b], models[m], px(&ins, 31, 12)[0], px(&ins, 0, 12)[0]);
            lg_image_free(&ins);
        }
}

/* The test camera's projection of a direction towards the light, (dx, dy, dz) with
 * dz < 0 (in front): its pixel position (x to the right, y as the image's rows go; dy = 0
 * only here, so the vertical flip does not matter). */
static void light_pixel(double dx, double dz, double *lx, double *ly)
{
    double f = 1.0 / tan(LG_PI / 6.0), aspect = (double)W / H;
    double ndc = f / aspect * dx / -dz;
    *lx = (ndc + 1.0) * 0.5 * W;
    *ly = 0.5 * H;
}

static void case_outside(lg_test *t)
{
    const int N = 32;
    const double decay = 0.95, scale = 1.0 * 0.01 * 10.0 / N;
    double lx, ly;
    /* the light travels along (1.5, 0, 1): towards it (-1.5, 0, -1), left of the image */
    light_pixel(-1.5, -1.0, &lx, &ly);
    LG_TEST_CHECK(t, lx < -10.0, "the test light should lie left of the image (x = %g)", lx);
    for (size_t b = 0; b < 2; b++) {
        char vol[160];
        snprintf(vol, sizeof vol, "model = thesis, normalize = false, samples = %d, decay = %g", N,
                 decay);
        lg_image ins = { 0 };
        if (!run_vol(t, BACKENDS[b], "direction = [1.5, 0, 1]", "", vol, &ins, NULL))
            continue;
        uint32_t bad = 0, partial = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                double p[2] = { x + 0.5, y + 0.5 }, s = 0.0;
                int inside = 0;
                for (int i = 1; i <= N; i++) {
                    double qx = p[0] + i * (lx - p[0]) / N, qy = p[1] + i * (ly - p[1]) / N;
                    if (qx >= 0 && qx < W && qy >= 0 && qy < H) {
                        s += pow(decay, i);
                        inside++;
                    }
                }
                partial += inside > 0 && inside < N;
                double want = scale * s, got = px(&ins, x, y)[0];
                /* one sample's weight: a sample on the image's edge may fall either way in
                 * float */
                if (fabs(got - want) > 1e-6 + scale * decay && bad++ < 5)
                    LG_TEST_FAILF(t,
                                  "%s: pixel (%u, %u) has %.9g, want %.9g (samples "
                                  "inside %d of %d)",
                                  BACKENDS[b], x, y, got, want, inside, N);
            }
        LG_TEST_CHECK(t, partial > W * H / 2,
                      "only %u pixels have samples both inside and "
                      "outside the image: the case tests little",
                      partial);
        lg_image_free(&ins);
    }
}

static void case_occluder(lg_test *t)
{
    /* light at the centre (16, 12); the box covers x 20..25, y 8..15 */
    const char *box = "box_x0 = 20, box_x1 = 26, box_y0 = 8, box_y1 = 16";
    static const char *const models[] = { "model = thesis, normalize = false", "model = physical" };
    for (size_t b = 0; b < 2; b++)
        for (size_t m = 0; m < 2; m++) {
            lg_image open = { 0 }, shut = { 0 };
            if (!run_vol(t, BACKENDS[b], "", "", models[m], &open, NULL) ||
                !run_vol(t, BACKENDS[b], "", box, models[m], &shut, NULL)) {
                lg_image_free(&open);
                continue;
            }
            /* right of the box, its samples cross it */
            for (uint32_t x = 27; x < W; x++)
                LG_TEST_CHECK(t, px(&shut, x, 12)[0] < 0.9f * px(&open, x, 12)[0],
                              "%s %s: pixel (%u, 12) behind the box: %g, without it %g",
                              BACKENDS[b], models[m], x, px(&shut, x, 12)[0], px(&open, x, 12)[0]);
            /* left of the light, the box is never between */
            for (uint32_t x = 0; x < 15; x++)
                for (uint32_t y = 0; y < H; y++)
                    if (px(&shut, x, y)[0] != px(&open, x, y)[0]) {
                        LG_TEST_FAILF(t,
                                      "%s %s: pixel (%u, %u) is %g with the box, %g "
                                      "without: the box is not between it and the light",
                                      BACKENDS[b], models[m], x, y, px(&shut, x, y)[0],
                                      px(&open, x, y)[0]);
                        x = W, y = H;
                    }
            lg_image_free(&open);
            lg_image_free(&shut);
        }
}

/* ---- lights32 -------------------------------------------------------------------------------- */

static void case_lights32(lg_test *t)
{
    for (size_t b = 0; b < 2; b++) {
        /* one graph: the 32-light scene and the 32 single-light scenes, 33 vol nodes */
        size_t cap = 64 * 1024;
        char *g = malloc(cap);
        if (!g) {
            LG_TEST_FAILF(t, "out of memory");
            return;
        }
        const char *scene = "direction = [0.1, 0.05, 1], intensity = 3";
        int len = snprintf(g, cap,
                           "lightgraph 1\n"
                           "b = test_vs_base { box_x0 = 12, box_x1 = 20, box_y0 = 4, "
                           "box_y1 = 10 }\n"
                           "all = test_vs_scene { lights = 32, %s }\n"
                           "vall = volumetric_screen { scene = all, base = b, backend = %s }\n"
                           "output vall.inscatter \"all.exr\" float\n",
                           scene, BACKENDS[b]);
        for (int k = 0; k < 32; k++)
            len += snprintf(g + len, cap - (size_t)len,
                            "s%d = test_vs_scene { lights = 32, only = %d, %s }\n"
                            "v%d = volumetric_screen { scene = s%d, base = b, backend = %s }\n"
                            "output v%d.inscatter \"one%d.exr\" float\n",
                            k, k, scene, k, k, BACKENDS[b], k, k);
        int rc = render(t, g, NULL, NULL, NULL, NULL);
        free(g);
        LG_TEST_CHECK(t, rc == 0, "%s: the 33-node render failed (%d)", BACKENDS[b], rc);
        if (rc)
            continue;
        lg_image all = { 0 }, sum = { 0 };
        if (!lg_test_read(t, "all.exr", &all, NULL) || lg_image_alloc(&sum, W, H))
            continue;
        double peak = 0;
        for (int k = 0; k < 32; k++) {
            char name[32];
            snprintf(name, sizeof name, "one%d.exr", k);
            lg_image one = { 0 };
            if (!lg_test_read(t, name, &one, NULL))
                continue;
            for (size_t i = 0; i < 4 * (size_t)W * H; i++)
                sum.pixels[i] += (i & 3) == 3 ? 0.0f : one.pixels[i];
            lg_image_free(&one);
        }
        for (size_t i = 0; i < (size_t)W * H; i++) {
            sum.pixels[4 * i + 3] = 1.0f;
            peak = fmax(peak, sum.pixels[4 * i]);
        }
        LG_TEST_CHECK(t, peak > 1e-4, "%s: the lights give nothing (peak %g)", BACKENDS[b], peak);
        lg_test_tol tol = { .max_abs = 1e-6 * peak, .rel = 1e-5 };
        char what[64];
        snprintf(what, sizeof what, "%s: 32 lights vs the sum of single lights", BACKENDS[b]);
        lg_test_check_image(t, &all, &sum, 32, &tol, what);
        lg_image_free(&all);
        lg_image_free(&sum);
    }
}

/* ---- physical -------------------------------------------------------------------------------- */

static void case_physical(lg_test *t)
{
    const double ss = 0.1, sa = 0.05, st = ss + sa, g = 0.4, Lc = 10.0;
    const double base[3] = { 0.2, 0.3, 0.4 };
    static const double limits[] = { 5.0, 0.0 };
    for (size_t b = 0; b < 2; b++)
        for (size_t k = 0; k < 2; k++) {
            char vol[160];
            snprintf(vol, sizeof vol, "model = physical, samples = 16, z_limit = %g", limits[k]);
            lg_image ins = { 0 }, out = { 0 };
            if (!run_vol(t, BACKENDS[b], "absorption = 0.05", "", vol, &ins, &out))
                continue;
            double zl = limits[k] > 0 ? limits[k] : 20.0; /* the camera's zfar */
            double f = tan(LG_PI / 6.0), aspect = (double)W / H;
            lg_image ref = { 0 }, refo = { 0 };
            lg_image_alloc(&ref, W, H);
            lg_image_alloc(&refo, W, H);
            for (uint32_t y = 0; y < H; y++)
                for (uint32_t x = 0; x < W; x++) {
                    double vx = (2.0 * (x + 0.5) / W - 1.0) * f * aspect;
                    double vy = (2.0 * (y + 0.5) / H - 1.0) * f;
                    double len = sqrt(vx * vx + vy * vy + 1.0);
                    double cosv = 1.0 / len; /* with the forward axis and with -L */
                    double d = zl / cosv;
                    double lv = lg_medium_inscatter(Lc, ss, st, lg_hg_phase(g, cosv), d);
                    size_t i = (size_t)y * W + x;
                    for (int c = 0; c < 3; c++) {
                        ref.pixels[4 * i + c] = (float)lv;
                        refo.pixels[4 * i + c] = (float)(base[c] * exp(-st * d) + lv);
                    }
                    ref.pixels[4 * i + 3] = refo.pixels[4 * i + 3] = 1.0f;
                }
            lg_test_tol tol = { .max_abs = 1e-7, .rel = 2e-5 };
            char what[80];
            snprintf(what, sizeof what, "%s z_limit %g: inscatter vs the closed form", BACKENDS[b],
                     limits[k]);
            lg_test_check_image(t, &ins, &ref, 32, &tol, what);
            snprintf(what, sizeof what, "%s z_limit %g: out", BACKENDS[b], limits[k]);
            lg_test_check_image(t, &out, &refo, 32, &tol, what);
            lg_image_free(&ins);
            lg_image_free(&out);
            lg_image_free(&ref);
            lg_image_free(&refo);
        }
}

/* ---- the example, gl against cpu ------------------------------------------------------------- */

static void case_example(lg_test *t)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "include \"%s/examples/volumetric_scene.lgraph\"\n"
             "vgl = volumetric_screen { scene = fog, base = lit, backend = gl }\n"
             "vcpu = volumetric_screen { scene = fog, base = lit, backend = cpu }\n"
             "output vgl.inscatter \"gl.exr\" float\n"
             "output vcpu.inscatter \"cpu.exr\" float\n"
             "output vgl \"glo.exr\" float\n"
             "output vcpu \"cpuo.exr\" float\n",
             VS_SOURCE_ROOT);
    int rc = render(t, g, "64x36", NULL, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "the example failed to render (%d)", rc);
    if (rc)
        return;
    lg_image a = { 0 }, c = { 0 }, ao = { 0 }, co = { 0 };
    if (!lg_test_read(t, "gl.exr", &a, NULL) || !lg_test_read(t, "cpu.exr", &c, NULL) ||
        !lg_test_read(t, "glo.exr", &ao, NULL) || !lg_test_read(t, "cpuo.exr", &co, NULL))
        return;
    double lo = INFINITY, hi = 0;
    for (size_t i = 0; i < (size_t)a.width * a.height; i++) {
        lo = fmin(lo, c.pixels[4 * i]);
        hi = fmax(hi, c.pixels[4 * i]);
    }
    LG_TEST_CHECK(t, hi > 0 && hi > 2 * lo, "no shafts: inscatter spans %g .. %g", lo, hi);
    /* gl and cpu: the same float arithmetic, the view rays float on gl and double on the
     * cpu (measured here: max 2e-5, RMSE 3e-6); max_abs leaves room for one sample on a
     * texel's edge falling the other way (1/64 of a pixel's value) */
    lg_test_tol tol = { .max_abs = 0.02 * hi, .rel = 1e-4, .rmse = 2e-4 * hi };
    lg_test_check_image(t, &a, &c, 32, &tol, "example inscatter, gl vs cpu");
    lg_test_check_image(t, &ao, &co, 32, &tol, "example out, gl vs cpu");
    lg_image_free(&a);
    lg_image_free(&c);
    lg_image_free(&ao);
    lg_image_free(&co);
}

/* ---- errors ---------------------------------------------------------------------------------- */

static void case_errors(lg_test *t)
{
    static const struct {
        const char *scene, *base, *vol, *says;
    } cases[] = {
        { "", "", "samples = 0", "samples" },
        { "", "", "samples = 2000", "samples" },
        { "", "", "decay = 0", "decay = 0" },
        { "", "", "decay = 1.5", "decay" },
        { "", "", "decay = nan", "decay" },
        { "", "", "exposure = -1", "exposure" },
        { "", "", "exposure = nan", "exposure" },
        { "", "", "exposure = inf", "exposure" },
        { "", "", "weight = nan", "weight" },
        { "", "", "z_limit = -1", "z_limit" },
        { "", "", "z_limit = nan", "z_limit" },
        { "", "", "z_limit = 0.05", "z_limit 0.05 must lie beyond the camera's near plane" },
        { "", "", "model = mitchell", "mitchell" },
        { "", "depth_plane = false", "", "has no depth plane" },
        { "lights = 33", "", "", "more than 32 directional lights" },
    };
    const size_t n = sizeof cases / sizeof cases[0];
    for (size_t b = 0; b < 2; b++)
        /* the parameters are checked before any device is used: their errors once (cpu);
         * the base and the scene on both backends */
        for (size_t k = b == 0 ? n - 2 : 0; k < n; k++) {
            char g[1024];
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_vs_scene { %s }\n"
                     "b = test_vs_base { %s }\n"
                     "vol = volumetric_screen { scene = s, base = b, backend = %s, %s }\n"
                     "output vol \"o.exr\" float\n",
                     cases[k].scene, cases[k].base, BACKENDS[b], cases[k].vol);
            char *text = NULL;
            int rc = render(t, g, NULL, NULL, NULL, &text);
            const char *what = cases[k].vol[0]    ? cases[k].vol
                               : cases[k].base[0] ? cases[k].base
                                                  : cases[k].scene;
            LG_TEST_CHECK(t, rc == 1 || rc == 2, "%s %s: exit status %d, not 1 or 2", BACKENDS[b],
                          what, rc);
            LG_TEST_CHECK(t, text && strstr(text, cases[k].says) && strstr(text, "vol"),
                          "%s %s: the message does not name the node and say '%s':\n%s",
                          BACKENDS[b], what, cases[k].says, text ? text : "");
            FILE *f = fopen(lg_test_path(t, "o.exr"), "rb");
            LG_TEST_CHECK(t, !f, "%s %s: an output file was written", BACKENDS[b], what);
            if (f)
                fclose(f);
            free(text);
        }
}

/* ---- gating ---------------------------------------------------------------------------------- */

static void case_gating(lg_test *t)
{
    /* the medium removed downstream of the test scene: the node must not run */
    const char *g = "lightgraph 1\n"
                    "s = test_vs_scene { }\n"
                    "clear = medium { scene = s, density = 0 }\n"
                    "b = test_vs_base { }\n"
                    "vol = volumetric_screen { scene = clear, base = b }\n"
                    "output vol.inscatter \"ins.exr\" float\n"
                    "output vol \"out.exr\" float\n";
    lg_image ins = { 0 }, out = { 0 };
    char *text = NULL;
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "32x24", "--explain", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 0, "the gated render failed (%d)", rc);
    LG_TEST_CHECK(t, text && strstr(text, "vol") && strstr(text, "medium"),
                  "--explain does not say why vol is gated:\n%s", text ? text : "");
    free(text);
    if (rc || !lg_test_read(t, "ins.exr", &ins, NULL) || !lg_test_read(t, "out.exr", &out, NULL))
        return;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        const float *a = ins.pixels + 4 * i, *o = out.pixels + 4 * i;
        if (a[0] != 0 || a[1] != 0 || a[2] != 0 || o[0] != 0.2f || o[1] != 0.3f || o[2] != 0.4f) {
            LG_TEST_FAILF(t,
                          "gated: pixel %zu inscatter (%g, %g, %g), out (%g, %g, %g): want "
                          "black and base",
                          i, a[0], a[1], a[2], o[0], o[1], o[2]);
            break;
        }
    }
    lg_image_free(&ins);
    lg_image_free(&out);
}

/* testvsinputs's folder, and an empty cache per case */
static void setup(lg_test *t)
{
    lg_test_use_plugins(t, VS_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "series", case_series },     { "normalize", case_normalize },
        { "behind", case_behind },     { "outside", case_outside },
        { "occluder", case_occluder }, { "lights32", case_lights32 },
        { "physical", case_physical }, { "example", case_example },
        { "errors", case_errors },     { "gating", case_gating },
    };
    lg_test_main_opts o = { .prefix = "volumetric_screen", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
