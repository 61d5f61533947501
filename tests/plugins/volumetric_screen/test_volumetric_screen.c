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
 *   errors     absurd and NaN parameters, a base without depth, 33 lights, a heterogeneous
 *              medium: a clear error naming the value, no output file
 *
 * Point and spot lights (issue 25):
 *   point      a point light on screen, unoccluded, physical: inscatter = L_c sigma_s times
 *              the airlight integral (lg_point_inscatter at 64 nodes, double) on every
 *              pixel, the glow's brightest pixel at the light's; out = base e^(-sigma_t d)
 *              + L_v
 *   point_occluder  a surface in front of the light's depth darkens the pixels whose samples
 *              cross it; a surface behind the light changes nothing (bit-identical)
 *   point_behind    the light behind the camera, at the camera, in its plane: exactly 0 in
 *              both models (the documented fade-out); the airlight the method leaves out
 *              there is printed
 *   point_offscreen the light left of the image, thesis model: exposure weight L_c F_e
 *              times the series over the samples inside the image (F_e the falloff at the
 *              camera); physical: finite and below the unshadowed airlight
 *   spot       a spot crossing the view: inscatter = the airlight with the cone (a brute-
 *              force sum), rows whose rays miss the cone exactly 0; thesis: the camera
 *              outside the cone gives 0; the camera inside a cone: the same oracle, and
 *              the thesis model's falloff at the camera
 *   range0     range 0 (infinite) = range 1e6; a range shorter than every ray's distance to
 *              the light: exactly 0 everywhere; finite always
 *   (lights32 also sums 32 point lights.)
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

/* The light settings `set[k]` (k < n, on top of `type`: "" or "type = point, "), each
 * described by what[k], give no in-scattering anywhere: one render of a test_vs_scene and a
 * volumetric_screen node per setting on `backend` with `model`; every inscatter pixel must be
 * (0, 0, 0, 1) and every output pixel finite, opaque and no brighter than the base (equal to
 * it under the thesis's model, which has no extinction). */
static void check_no_light(lg_test *t, const char *backend, const char *model, const char *type,
                           const char *const *set, const char *const *what, size_t n)
{
    char g[4096];
    int len = snprintf(g, sizeof g,
                       "lightgraph 1\n"
                       "b = test_vs_base { box_x1 = 8, box_y1 = 8 }\n");
    for (size_t k = 0; k < n; k++)
        len += snprintf(g + len, sizeof g - (size_t)len,
                        "s%zu = test_vs_scene { %s%s }\n"
                        "v%zu = volumetric_screen { scene = s%zu, base = b, "
                        "backend = %s, %s }\n"
                        "output v%zu.inscatter \"ins%zu.exr\" float\n"
                        "output v%zu \"out%zu.exr\" float\n",
                        k, type, set[k], k, k, backend, model, k, k, k, k);
    int rc = render(t, g, NULL, NULL, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "%s %s: render failed (%d)", backend, model, rc);
    bool thesis = strcmp(model, "model = thesis") == 0;
    for (size_t k = 0; k < n && rc == 0; k++) {
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
                if (thesis)
                    ok = ok && o[0] == 0.2f && o[1] == 0.3f && o[2] == 0.4f;
                if (!ok)
                    LG_TEST_FAILF(t,
                                  "%s %s, %s: pixel (%u, %u) inscatter (%g, %g, %g, %g), out "
                                  "(%g, %g, %g)",
                                  backend, model, what[k], x, y, a[0], a[1], a[2], a[3], o[0], o[1],
                                  o[2]);
            }
        lg_image_free(&ins);
        lg_image_free(&out);
    }
}

static void case_behind(lg_test *t)
{
    static const char *const dirs[] = { "direction = [0, 0, -1]", "direction = [1, 0, 0]",
                                        "direction = [0, 1, 0]", "direction = [1, 0, 1e-7]" };
    static const char *const whats[] = { "behind the camera (w < 0)", "in the image plane (w = 0)",
                                         "in the image plane, vertical (w = 0)",
                                         "just in front of the image plane (w = 1e-7)" };
    static const char *const models[] = { "model = thesis", "model = physical" };
    for (size_t b = 0; b < 2; b++)
        for (size_t m = 0; m < 2; m++) {
            check_no_light(t, BACKENDS[b], models[m], "", dirs, whats, 4);
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
    static const char *const scenes[] = {
        "direction = [0.1, 0.05, 1], intensity = 3",
        "type = point, position = [0.5, 0.2, -4], intensity = 30",
    };
    for (size_t b = 0; b < 4; b++) {
        const char *scene = scenes[b / 2];
        /* one graph: the 32-light scene and the 32 single-light scenes, 33 vol nodes */
        size_t cap = 64 * 1024;
        char *g = malloc(cap);
        if (!g) {
            LG_TEST_FAILF(t, "out of memory");
            return;
        }
        int len = snprintf(g, cap,
                           "lightgraph 1\n"
                           "b = test_vs_base { box_x0 = 12, box_x1 = 20, box_y0 = 4, "
                           "box_y1 = 10 }\n"
                           "all = test_vs_scene { lights = 32, %s }\n"
                           "vall = volumetric_screen { scene = all, base = b, backend = %s }\n"
                           "output vall.inscatter \"all.exr\" float\n",
                           scene, BACKENDS[b % 2]);
        for (int k = 0; k < 32; k++)
            len += snprintf(g + len, cap - (size_t)len,
                            "s%d = test_vs_scene { lights = 32, only = %d, %s }\n"
                            "v%d = volumetric_screen { scene = s%d, base = b, backend = %s }\n"
                            "output v%d.inscatter \"one%d.exr\" float\n",
                            k, k, scene, k, k, BACKENDS[b % 2], k, k);
        int rc = render(t, g, NULL, NULL, NULL, NULL);
        free(g);
        LG_TEST_CHECK(t, rc == 0, "%s: the 33-node render failed (%d)", BACKENDS[b % 2], rc);
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
        LG_TEST_CHECK(t, peak > 1e-4, "%s: the lights give nothing (peak %g)", BACKENDS[b % 2],
                      peak);
        lg_test_tol tol = { .max_abs = 1e-6 * peak, .rel = 1e-5 };
        char what[64];
        snprintf(what, sizeof what, "%s %s: 32 lights vs the sum of single lights", BACKENDS[b % 2],
                 b < 2 ? "directional" : "point");
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

/* ---- point and spot lights (issue 25) -------------------------------------------------------- */

/* The test camera's view ray through pixel (x, y) (its centre; row 0 at the top), unit,
 * world = view. */
static void test_ray(uint32_t x, uint32_t y, double w[3])
{
    double f = tan(LG_PI / 6.0), aspect = (double)W / H;
    w[0] = (2.0 * (x + 0.5) / W - 1.0) * f * aspect;
    w[1] = (1.0 - 2.0 * (y + 0.5) / H) * f;
    w[2] = -1.0;
    double len = sqrt(w[0] * w[0] + w[1] * w[1] + 1.0);
    for (int c = 0; c < 3; c++)
        w[c] /= len;
}

/* A point in front of the test camera (z < 0): its position in pixels (row 0 at the top:
 * world +y is up the image). */
static void test_pixel(const double q[3], double *px_, double *py_)
{
    double f = 1.0 / tan(LG_PI / 6.0), aspect = (double)W / H;
    *px_ = (f / aspect * q[0] / -q[2] + 1.0) * 0.5 * W;
    *py_ = (1.0 - f * q[1] / -q[2]) * 0.5 * H;
}

/* The same in-scattering by brute force: the integrand of lightgraph/medium.h's airlight
 * (phase, window, cone, inverse square with eps, extinction both ways) by the midpoint rule
 * in t with `steps` steps: an oracle that shares no quadrature with the node. */
static double airlight_brute(const double w[3], double d, const double q[3], double range,
                             const double *spot, double g, double st, int steps)
{
    double h = d / steps, sum = 0.0;
    for (int i = 0; i < steps; i++) {
        double t = (i + 0.5) * h, l[3], dd = 0.0;
        for (int c = 0; c < 3; c++) {
            l[c] = q[c] - t * w[c];
            dd += l[c] * l[c];
        }
        double dist = sqrt(dd);
        double cw = (l[0] * w[0] + l[1] * w[1] + l[2] * w[2]) / dist;
        double f = lg_hg_phase(g, cw) * lg_light_window(dist, range) /
                   (dd + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
        if (spot)
            f *= lg_spot_cone(-(l[0] * spot[0] + l[1] * spot[1] + l[2] * spot[2]) / dist, spot[3],
                              spot[4]);
        sum += f * exp(-st * (t + dist)) * h;
    }
    return sum;
}

/* The unshadowed physical in-scattering of one point or spot light at q on every pixel of
 * the sky-only test image (d = zfar / cos, zfar 20), with 64 nodes in double: the
 * reference of `point` and `spot`. */
static void airlight_image(lg_image *ref, const double q[3], double range, const double *spot,
                           double Lc, double ss, double st, double g)
{
    lg_image_alloc(ref, W, H);
    const double o[3] = { 0, 0, 0 };
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double w[3];
            test_ray(x, y, w);
            double d = 20.0 / -w[2];
            double a = Lc * ss * lg_point_inscatter(o, w, 0.0, d, q, range, spot, g, st, 64);
            float *p = ref->pixels + 4 * ((size_t)y * W + x);
            p[0] = p[1] = p[2] = (float)a;
            p[3] = 1.0f;
        }
}

static void case_point(lg_test *t)
{
    const double q[3] = { 0.6, 0.4, -5.0 }, ss = 0.1, sa = 0.05, g = 0.4, Lc = 10.0;
    double lx, ly;
    test_pixel(q, &lx, &ly);
    lg_image ref = { 0 };
    airlight_image(&ref, q, 0.0, NULL, Lc, ss, ss + sa, g);
    for (size_t b = 0; b < 2; b++) {
        lg_image ins = { 0 }, out = { 0 };
        if (!run_vol(t, BACKENDS[b], "type = point, position = [0.6, 0.4, -5], absorption = 0.05",
                     "", "model = physical", &ins, &out))
            continue;
        lg_test_diff dd;
        /* 8 nodes against 64 in double: the integrand in the angle is smooth (the phase,
         * the extinction); the largest error is where the ray passes nearest the light and
         * the phase sweeps through 180 degrees (measured: relative 6.8e-4 cpu, 1.2e-3 gl at
         * the light's pixel; rmse 2e-5 of the peak) */
        lg_test_tol tol = { .max_abs = 1e-9, .rel = 2.5e-3 };
        char what[64];
        snprintf(what, sizeof what, "%s: point light inscatter vs the airlight", BACKENDS[b]);
        lg_test_diff_images(&ins, &ref, 32, &tol, &dd);
        lg_test_note_("%s: point light, max |got - want| %.3g, rmse %.3g (peak %.4g)", BACKENDS[b],
                      dd.max_abs, dd.rmse, px(&ref, (uint32_t)lx, (uint32_t)ly)[0]);
        lg_test_check_image(t, &ins, &ref, 32, &tol, what);
        /* the glow is centred on the light: its brightest pixel holds the light */
        uint32_t bx = 0, by = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++)
                if (px(&ins, x, y)[0] > px(&ins, bx, by)[0])
                    bx = x, by = y;
        LG_TEST_CHECK(t, bx == (uint32_t)lx && by == (uint32_t)ly,
                      "%s: the brightest pixel is (%u, %u), the light is at (%.2f, %.2f)",
                      BACKENDS[b], bx, by, lx, ly);
        LG_TEST_CHECK(t, px(&ins, bx, by)[0] > 4.0f * px(&ins, 0, 0)[0],
                      "%s: no glow: %g at the light, %g in the corner", BACKENDS[b],
                      px(&ins, bx, by)[0], px(&ins, 0, 0)[0]);
        /* out = base e^(-sigma_t d) + L_v */
        bool ok = true;
        for (uint32_t y = 0; y < H && ok; y++)
            for (uint32_t x = 0; x < W && ok; x++) {
                double w[3];
                test_ray(x, y, w);
                double want = 0.2 * exp(-(ss + sa) * 20.0 / -w[2]) + px(&ins, x, y)[0];
                ok = fabs(px(&out, x, y)[0] - want) <= 1e-6 + 2e-5 * want;
                if (!ok)
                    LG_TEST_FAILF(t, "%s: out (%u, %u) = %.7g, want %.7g", BACKENDS[b], x, y,
                                  px(&out, x, y)[0], want);
            }
        lg_image_free(&ins);
        lg_image_free(&out);
    }
    lg_image_free(&ref);
}

static void case_point_occluder(lg_test *t)
{
    /* the light at (0.6, 0.4, -5), pixel (18.5, 10.3), window depth 0.965; a box right of
     * it at depth 0.5 (in front of the light, view distance 0.2) and the same box at 0.99
     * (behind it); decay 1: every sample weighs the same */
    const double q[3] = { 0.6, 0.4, -5.0 };
    double lx, ly;
    test_pixel(q, &lx, &ly);
    const char *scene = "type = point, position = [0.6, 0.4, -5]";
    static const char *const models[] = { "model = thesis, normalize = false, decay = 1",
                                          "model = physical, decay = 1" };
    for (size_t b = 0; b < 2; b++)
        for (size_t m = 0; m < 2; m++) {
            lg_image open = { 0 }, front = { 0 }, back = { 0 };
            bool ok = run_vol(t, BACKENDS[b], scene, "", models[m], &open, NULL) &&
                      run_vol(t, BACKENDS[b], scene,
                              "box_x0 = 20, box_x1 = 26, box_y0 = 6, box_y1 = 15", models[m],
                              &front, NULL) &&
                      run_vol(t, BACKENDS[b], scene,
                              "box_x0 = 20, box_x1 = 26, box_y0 = 6, box_y1 = 15, "
                              "box_depth = 0.99",
                              models[m], &back, NULL);
            if (ok) {
                uint32_t y = (uint32_t)ly;
                for (uint32_t x = 27; x < W; x++)
                    LG_TEST_CHECK(t, px(&front, x, y)[0] < 0.9f * px(&open, x, y)[0],
                                  "%s %s: pixel (%u, %u) behind the box in front of the light: "
                                  "%g, without it %g",
                                  BACKENDS[b], models[m], x, y, px(&front, x, y)[0],
                                  px(&open, x, y)[0]);
                /* outside the box (inside it the surface shortens the pixel's own ray) */
                for (size_t i = 0; i < 4 * (size_t)W * H; i++) {
                    uint32_t x = (uint32_t)(i / 4 % W), yy = (uint32_t)(i / 4 / W);
                    if (x >= 20 && x < 26 && yy >= 6 && yy < 15)
                        continue;
                    if (back.pixels[i] != open.pixels[i]) {
                        LG_TEST_FAILF(t,
                                      "%s %s: a box behind the light changed value %zu: %g, "
                                      "without it %g",
                                      BACKENDS[b], models[m], i, back.pixels[i], open.pixels[i]);
                        break;
                    }
                }
            }
            lg_image_free(&open);
            lg_image_free(&front);
            lg_image_free(&back);
        }
}

static void case_point_behind(lg_test *t)
{
    static const char *const pos[] = { "position = [0.3, 0.2, 3]", "position = [0, 0, 0]",
                                       "position = [2, 0, 0]", "position = [2, 0, 1e-6]" };
    static const char *const whats[] = { "behind the camera", "at the camera",
                                         "in the camera's plane",
                                         "just behind the camera's plane" };
    static const char *const models[] = { "model = thesis", "model = physical" };
    for (size_t b = 0; b < 2; b++)
        for (size_t m = 0; m < 2; m++)
            check_no_light(t, BACKENDS[b], models[m], "type = point, ", pos, whats, 4);
    /* what the fade-out leaves out: the unshadowed airlight of the light behind the camera */
    const double q[3] = { 0.3, 0.2, 3.0 };
    lg_image ref = { 0 }, front = { 0 };
    airlight_image(&ref, q, 0.0, NULL, 10.0, 0.1, 0.1, 0.4);
    const double qf[3] = { 0.3, 0.2, -3.0 };
    airlight_image(&front, qf, 0.0, NULL, 10.0, 0.1, 0.1, 0.4);
    double sb = 0, sf = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        sb += ref.pixels[4 * i];
        sf += front.pixels[4 * i];
    }
    lg_test_note_("behind: the unshadowed airlight left out averages %.4g per pixel, %.1f %% of "
                  "the same light's mirrored in front of the camera (%.4g)",
                  sb / (W * H), 100.0 * sb / sf, sf / (W * H));
    lg_image_free(&ref);
    lg_image_free(&front);
}

static void case_point_offscreen(lg_test *t)
{
    const int N = 32;
    const double q[3] = { -6.0, 0.0, -4.0 }, decay = 0.95, Lc = 10.0;
    double lx, ly;
    test_pixel(q, &lx, &ly);
    LG_TEST_CHECK(t, lx < -10.0, "the test light should lie left of the image (x = %g)", lx);
    const double d2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    const double fe = 1.0 / (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
    const double scale = 1.0 * 0.01 * Lc * fe / N;
    const char *scene = "type = point, position = [-6, 0, -4]";
    for (size_t b = 0; b < 2; b++) {
        char vol[160];
        snprintf(vol, sizeof vol, "model = thesis, normalize = false, samples = %d, decay = %g", N,
                 decay);
        lg_image ins = { 0 };
        if (!run_vol(t, BACKENDS[b], scene, "", vol, &ins, NULL))
            continue;
        uint32_t partial = 0;
        int bad = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                double p[2] = { x + 0.5, y + 0.5 }, sum = 0.0;
                int inside = 0;
                for (int i = 1; i <= N; i++) {
                    double qx = p[0] + i * (lx - p[0]) / N, qy = p[1] + i * (ly - p[1]) / N;
                    if (qx >= 0 && qx < W && qy >= 0 && qy < H) {
                        sum += pow(decay, i);
                        inside++;
                    }
                }
                partial += inside > 0 && inside < N;
                double want = scale * sum, got = px(&ins, x, y)[0];
                if (fabs(got - want) > 1e-9 + 1e-5 * want + scale * decay && bad++ < 5)
                    LG_TEST_FAILF(t,
                                  "%s: pixel (%u, %u) has %.9g, want %.9g (samples inside "
                                  "%d of %d)",
                                  BACKENDS[b], x, y, got, want, inside, N);
            }
        LG_TEST_CHECK(t, partial > W * H / 2,
                      "only %u pixels have samples both inside and outside the image", partial);
        lg_image_free(&ins);
        /* physical: finite, at most the unshadowed airlight (M <= 1), not all 0 */
        lg_image phy = { 0 }, ref = { 0 };
        if (!run_vol(t, BACKENDS[b], scene, "", "model = physical", &phy, NULL))
            continue;
        airlight_image(&ref, q, 0.0, NULL, Lc, 0.1, 0.1, 0.4);
        double hi = 0;
        for (size_t i = 0; i < (size_t)W * H; i++) {
            float g = phy.pixels[4 * i], r = ref.pixels[4 * i];
            hi = fmax(hi, g);
            if (!(isfinite(g) && g >= 0.0f && g <= r * (1.0f + 1e-4f))) {
                LG_TEST_FAILF(t, "%s physical: pixel %zu has %g, the unshadowed airlight %g",
                              BACKENDS[b], i, g, r);
                break;
            }
        }
        LG_TEST_CHECK(t, hi > 0, "%s physical: nothing from the light off screen", BACKENDS[b]);
        lg_image_free(&phy);
        lg_image_free(&ref);
    }
}

/* *ref (allocated here, W x H, the caller frees it) = the spot light's in-scattering through
 * every pixel of the test camera by brute force (test_vs_scene's medium: sigma_s = sigma_t =
 * 0.1, g 0.4, the sky at 20 m; 20000 midpoint steps); returns its peak. */
static double spot_brute_image(lg_image *ref, const double q[3], const double spot[5], double Lc)
{
    lg_image_alloc(ref, W, H);
    double peak = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            double w[3];
            test_ray(x, y, w);
            float *p = ref->pixels + 4 * ((size_t)y * W + x);
            p[0] = p[1] = p[2] =
                (float)(Lc * 0.1 * airlight_brute(w, 20.0 / -w[2], q, 0.0, spot, 0.4, 0.1, 20000));
            p[3] = 1.0f;
            peak = fmax(peak, p[0]);
        }
    return peak;
}

/* The camera inside the cone: a spot 5 m ahead shining back at it (cones 20 and 30
 * degrees; the image's corners lie outside the cone, its centre inside): physical against
 * brute force as in `spot`; thesis: the falloff at the camera, C = 1 there, gives
 * exposure weight L_c / 25 on the pixels whose samples all see the sky. */
static void spot_inside(lg_test *t)
{
    const double q[3] = { 0.0, 0.0, -5.0 }, Lc = 10.0;
    const double spot[5] = { 0, 0, 1, cos(20.0 * LG_PI / 180.0), cos(30.0 * LG_PI / 180.0) };
    const char *scene = "type = spot, position = [0, 0, -5], direction = [0, 0, 1], "
                        "inner_cone = 20, outer_cone = 30, intensity = 10";
    lg_image ref = { 0 };
    double peak = spot_brute_image(&ref, q, spot, Lc);
    for (size_t b = 0; b < 2; b++) {
        lg_image ins = { 0 }, th = { 0 };
        if (!run_vol(t, BACKENDS[b], scene, "", "model = physical", &ins, NULL) ||
            !run_vol(t, BACKENDS[b], scene, "", "model = thesis, normalize = false", &th, NULL)) {
            lg_image_free(&ins);
            continue;
        }
        lg_test_diff dd;
        lg_test_tol tol = { .max_abs = 0.02 * peak, .rmse = 0.002 * peak };
        lg_test_diff_images(&ins, &ref, 32, &tol, &dd);
        lg_test_note_("%s: camera inside the spot's cone, vs brute force: max %.3g %% of the "
                      "peak, rmse %.3g %%",
                      BACKENDS[b], 100.0 * dd.max_abs / peak, 100.0 * dd.rmse / peak);
        char what[64];
        snprintf(what, sizeof what, "%s: camera inside the cone", BACKENDS[b]);
        lg_test_check_image(t, &ins, &ref, 32, &tol, what);
        /* thesis, sky everywhere: exposure 1 x weight 0.01 x L_c x F_e x the series */
        double fe = 1.0 / (25.0 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON), series = 0.0;
        for (int i = 1; i <= 64; i++)
            series += pow(0.94, i);
        double want = 0.01 * Lc * fe * series / 64.0, got = px(&th, 16, 12)[0];
        LG_TEST_CHECK(t, fabs(got - want) <= 1e-5 * want,
                      "%s thesis: the centre has %.9g, want %.9g (L_c F_e at the camera)",
                      BACKENDS[b], got, want);
        lg_image_free(&ins);
        lg_image_free(&th);
    }
    lg_image_free(&ref);
}

static void case_spot(lg_test *t)
{
    /* at (-3, 0, -6) along +x, cones 5 and 10 degrees: the beam crosses the view */
    const double q[3] = { -3.0, 0.0, -6.0 }, Lc = 10.0;
    const double spot[5] = { 1, 0, 0, cos(5.0 * LG_PI / 180.0), cos(10.0 * LG_PI / 180.0) };
    const char *scene =
        "type = spot, position = [-3, 0, -6], direction = [1, 0, 0], inner_cone = 5, "
        "outer_cone = 10, intensity = 10";
    lg_image ref = { 0 };
    double peak = spot_brute_image(&ref, q, spot, Lc);
    for (size_t b = 0; b < 2; b++) {
        lg_image ins = { 0 }, th = { 0 };
        if (!run_vol(t, BACKENDS[b], scene, "", "model = physical", &ins, NULL) ||
            !run_vol(t, BACKENDS[b], scene, "", "model = thesis", &th, NULL)) {
            lg_image_free(&ins);
            continue;
        }
        /* 8 nodes on the ray's piece inside the cone against 20000 midpoint steps (the
         * inner cone's edge is still a kink inside the piece) */
        lg_test_diff dd;
        /* measured: max 1.1 %, rmse 0.08 % of the peak, gl and cpu alike */
        lg_test_tol tol = { .max_abs = 0.02 * peak, .rmse = 0.002 * peak };
        lg_test_diff_images(&ins, &ref, 32, &tol, &dd);
        lg_test_note_("%s: spot light, 8 nodes vs brute force: max %.3g %% of the peak, rmse "
                      "%.3g %%",
                      BACKENDS[b], 100.0 * dd.max_abs / peak, 100.0 * dd.rmse / peak);
        char what[64];
        snprintf(what, sizeof what, "%s: spot inscatter vs the airlight", BACKENDS[b]);
        lg_test_check_image(t, &ins, &ref, 32, &tol, what);
        /* rows whose rays miss the cone: exactly 0; the beam's row: lit */
        for (uint32_t y = 0; y < H; y++)
            if (y < 3 || y >= H - 3)
                for (uint32_t x = 0; x < W; x++)
                    if (px(&ins, x, y)[0] != 0.0f) {
                        LG_TEST_FAILF(t, "%s: pixel (%u, %u) outside the beam has %g", BACKENDS[b],
                                      x, y, px(&ins, x, y)[0]);
                        y = H, x = W;
                    }
        LG_TEST_CHECK(t, px(&ins, 16, 12)[0] > 0.1f * peak, "%s: the beam's centre has %g",
                      BACKENDS[b], px(&ins, 16, 12)[0]);
        /* thesis: F_e is the falloff at the camera, outside the cone: 0 */
        float hi = 0;
        for (size_t i = 0; i < 4 * (size_t)W * H; i++)
            hi = fmaxf(hi, (i & 3) == 3 ? 0.0f : th.pixels[i]);
        LG_TEST_CHECK(t, hi == 0.0f, "%s thesis: the camera is outside the cone, yet %g",
                      BACKENDS[b], hi);
        lg_image_free(&ins);
        lg_image_free(&th);
    }
    lg_image_free(&ref);
    spot_inside(t);
}

static void case_range0(lg_test *t)
{
    const char *scene = "type = point, position = [0.6, 0.4, -5]";
    for (size_t b = 0; b < 2; b++) {
        lg_image inf = { 0 }, big = { 0 }, tiny = { 0 }, zero = { 0 };
        char s1[128], s2[128], s3[128];
        snprintf(s1, sizeof s1, "%s, range = 1e6", scene);
        snprintf(s2, sizeof s2, "%s, range = 1e-6", scene);
        /* the light's distance to every ray: at least 5 sin(angle to the nearest ray) */
        snprintf(s3, sizeof s3, "%s, range = 0.001", scene);
        bool ok = run_vol(t, BACKENDS[b], scene, "", "model = physical", &inf, NULL) &&
                  run_vol(t, BACKENDS[b], s1, "", "model = physical", &big, NULL) &&
                  run_vol(t, BACKENDS[b], s2, "", "model = physical", &tiny, NULL) &&
                  run_vol(t, BACKENDS[b], s3, "", "model = thesis", &zero, NULL);
        if (ok) {
            lg_test_tol tol = { .max_abs = 1e-9, .rel = 1e-6 };
            char what[64];
            snprintf(what, sizeof what, "%s: range 0 vs range 1e6", BACKENDS[b]);
            lg_test_check_image(t, &inf, &big, 32, &tol, what);
            LG_TEST_CHECK(t, all_finite(&tiny) && all_finite(&zero), "%s: a value not finite",
                          BACKENDS[b]);
            double hi = 0, hz = 0;
            for (size_t i = 0; i < (size_t)W * H; i++) {
                hi = fmax(hi, tiny.pixels[4 * i]);
                hz = fmax(hz, zero.pixels[4 * i]);
            }
            LG_TEST_CHECK(t, hi == 0.0, "%s: range 1e-6, no ray comes that close, yet inscatter %g",
                          BACKENDS[b], hi);
            LG_TEST_CHECK(t, hz == 0.0,
                          "%s thesis: the camera is beyond the range 0.001, yet inscatter %g",
                          BACKENDS[b], hz);
        }
        lg_image_free(&inf);
        lg_image_free(&big);
        lg_image_free(&tiny);
        lg_image_free(&zero);
    }
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
        { "lights = 33", "", "", "more than 32 lights" },
        { "field = true", "", "", "density field" },
    };
    const size_t n = sizeof cases / sizeof cases[0];
    for (size_t b = 0; b < 2; b++)
        /* the parameters are checked before any device is used: their errors once (cpu);
         * the base and the scene on both backends */
        for (size_t k = b == 0 ? n - 3 : 0; k < n; k++) {
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
        { "series", case_series },
        { "normalize", case_normalize },
        { "behind", case_behind },
        { "outside", case_outside },
        { "occluder", case_occluder },
        { "lights32", case_lights32 },
        { "physical", case_physical },
        { "example", case_example },
        { "errors", case_errors },
        { "gating", case_gating },
        { "point", case_point },
        { "point_occluder", case_point_occluder },
        { "point_behind", case_point_behind },
        { "point_offscreen", case_point_offscreen },
        { "spot", case_spot },
        { "range0", case_range0 },
    };
    lg_test_main_opts o = { .prefix = "volumetric_screen", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
