/*
 * The reinhard node through the host, per backend: `test_reinhard CASE BACKEND` with
 * BACKEND cpu, gl or cl (exit 77 when that device cannot be made here).
 *
 *   constant      a constant image maps to m / (1 + m), m = a L / (L + delta), in both
 *                 modes and both luminance weights; alpha passes through
 *   white         three grey levels; white = the scaled top-but-one level: that level
 *                 maps to 1, the one above is clamped to 1, the one below follows
 *                 Lm (1 + Lm / Lw^2) / (1 + Lm)
 *   monotone      a ramp over ten decades maps to a non-decreasing ramp in [0, 1)
 *   exposure      the image x10 (through core's scale node) maps to the same output
 *   adapt         60 frames of 1/60 s = 1 frame of 1 s = the closed form
 *                 La = Lavg + (La0 - Lavg) rate^60; the node's dt overrides --dt
 *   badpixels     NaN, +-Inf, negative and zero pixels: counted in one warning, mapped by
 *                 the policy, and the other pixels as the closed form over the valid ones
 *   bright        greys so bright that s L is +Inf (and +Inf pixels) map to exactly 1 in
 *                 both modes, with and without a white point; no grey maps above 1
 *   sizes         1x1, 17x3, 3x257, 300x1 and 1100x700 (several grid-stride rounds):
 *                 every pixel of a constant image is mapped
 *   backends      (no BACKEND: all of them) every backend the node declares against the
 *                 double-precision oracle (reinhard_oracle.c) and against cpu, through the
 *                 SDK harness, on a photograph and a synthetic image, in four parameter
 *                 sets; `test_reinhard --bench[=N] backends` is the benchmark
 *   threads       (cpu) the same output, to the bit, with LIGHTGRAPH_THREADS = 1, 2 and 7:
 *                 the log-average is reduced per chunk and added in chunk order
 *
 * Values come back through the output file; when the host writes half EXR the checks add
 * half's rounding (2^-11 relative) to their tolerance (lightgraph/test.h, lg_test_tol_of).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/test.h"
#include "reinhard_cpu.h"
#include "reinhard_oracle.h"

static const char *backend;

/* Tolerance of a GPU float result against the closed form (computed in double): the map
 * runs in float, the log-average is a float sum of logs. */
#define TOL 2e-6

static const double W709[3] = { 0.2126f, 0.7152f, 0.0722f };
static const double WSEED[3] = { 0.2125f, 0.7154f, 0.0721f };

static lg_image alloc_image(uint32_t w, uint32_t h)
{
    lg_image img;
    if (lg_image_alloc(&img, w, h)) {
        fprintf(stderr, "lg_image_alloc(%u, %u) failed\n", w, h);
        exit(99);
    }
    return img;
}

static void fill(lg_image *img, const float px[4])
{
    for (size_t i = 0; i < (size_t)img->width * img->height; i++)
        memcpy(img->pixels + i * 4, px, 16);
}

static double luma(const float *c, const double w[3])
{
    /* as the node does: float products and sums */
    return (float)((float)((float)w[0] * c[0]) + (float)((float)w[1] * c[1])) +
           (float)((float)w[2] * c[2]);
}

/* Writes g.lgraph: image in.exr -> reinhard { backend, extra } -> out. The image node
 * keeps negative values (radiance = false): what reinhard does with them is under test. */
static void write_graph(lg_test *t, const char *graph, const char *in, const char *extra,
                        const char *out)
{
    char text[2048];
    snprintf(text, sizeof text,
             "lightgraph 1\nsrc = image { file = \"%s\", radiance = false }\n"
             "tone = reinhard { image = src, backend = %s%s%s }\noutput tone \"%s\"\n",
             in, backend, *extra ? ", " : "", extra, out);
    lg_test_write_text(t, graph, text);
}

static bool render_read(lg_test *t, const char *graph, const char *const *args, const char *out,
                        lg_image *img, unsigned *bits, char **err)
{
    int rc = lg_test_render(t, graph, args, err);
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (exit %d)", graph, rc);
    if (rc)
        return false;
    return lg_test_read(t, out, img, bits);
}

/* Compares every pixel of `got` with `want` (within tol plus the file's rounding);
 * reports up to 5 differences. Returns the largest difference. `want` is a closed form,
 * or (files > 1) another output file, rounded on its own. */
static double compare_n(lg_test *t, const lg_image *got, const lg_image *want, unsigned bits,
                        double tol, int files, const char *what)
{
    if (got->width != want->width || got->height != want->height) {
        LG_TEST_CHECK(t, 0, "%s: size %ux%u, want %ux%u", what, got->width, got->height,
                      want->width, want->height);
        return INFINITY;
    }
    double md = 0;
    int bad = 0;
    for (size_t i = 0; i < (size_t)want->width * want->height * 4; i++) {
        double g = got->pixels[i], e = want->pixels[i], d = fabs(g - e);
        md = fmax(md, d);
        if (!(d <= files * lg_test_tol_of(e, bits, tol / files)) && bad++ < 5)
            fprintf(stderr, "%s: pixel %zu (%zu, %zu) channel %zu: %.9g, want %.9g\n", what, i / 4,
                    i / 4 % want->width, i / 4 / want->width, i % 4, g, e);
    }
    LG_TEST_CHECK(t, bad == 0, "%s: %d values beyond tolerance (max diff %.3g)", what, bad, md);
    return md;
}

static double compare(lg_test *t, const lg_image *got, const lg_image *want, unsigned bits,
                      double tol, const char *what)
{
    return compare_n(t, got, want, bits, tol, 1, what);
}

/* The host may write outputs as half EXR (11 significant bits), which hides float-level
 * differences. diff_nodes() appends nodes that compute (a - b) * 1e4 in float with core's
 * scale and add, and an output of it: amplified, a difference of 1e-7 survives a half file
 * with three significant digits. */
#define DIFF_GAIN 1e4

static void diff_nodes(char *text, size_t cap, const char *a, const char *b, const char *file)
{
    size_t len = strlen(text);
    snprintf(text + len, cap - len,
             "neg_%s = scale { image = %s, tint = [-1, -1, -1] }\n"
             "d_%s = add { a = %s, b = neg_%s }\n"
             "amp_%s = scale { image = d_%s, factor = %g }\n"
             "output amp_%s \"%s\"\n",
             b, b, a, a, b, a, a, DIFF_GAIN, a, file);
}

/* Max and mean absolute RGB difference from a diff_nodes() file. */
static bool diff_stats(lg_test *t, const char *file, double *max, double *mean)
{
    lg_image d;
    if (!lg_test_read(t, file, &d, NULL))
        return false;
    double mx = 0, sum = 0;
    size_t n = (size_t)d.width * d.height;
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            double v = fabs(d.pixels[i * 4 + k]) / DIFF_GAIN;
            mx = v > mx || isnan(v) ? v : mx;
            sum += v;
        }
    }
    *max = mx;
    *mean = sum / (3.0 * (double)n);
    lg_image_free(&d);
    return true;
}

/* ---- constant -------------------------------------------------------------------------------- */

static void expect_constant(lg_image *want, const float c[4], double key, double delta, bool rgb,
                            const double w[3])
{
    double l = luma(c, w);
    double s = key / (l + delta); /* Lavg of a constant image: exp(log(delta + L)) */
    float o[4];
    for (int k = 0; k < 3; k++) {
        if (rgb)
            o[k] = (float)(s * c[k] / (1 + s * c[k]));
        else
            o[k] = (float)(c[k] / l * (s * l / (1 + s * l)));
    }
    o[3] = c[3];
    fill(want, o);
}

static void case_constant(lg_test *t)
{
    const float c[4] = { 0.5f, 1.0f, 2.0f, 0.3f };
    lg_image in = alloc_image(9, 7), want = alloc_image(9, 7), out;
    fill(&in, c);
    lg_test_write_exr(t, "in.exr", &in);
    static const struct {
        const char *params;
        double key, delta;
        bool rgb, seed;
    } v[] = {
        { "", 0.18, 1e-4, false, false },
        { "mode = rgb", 0.18, 1e-4, true, false },
        { "key = 0.72, luminance = seed, mode = rgb", 0.72, 1e-4, true, true },
        { "key = 0.05, delta = 0.01, luminance = seed", 0.05, 0.01, false, true },
    };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        write_graph(t, "g.lgraph", "in.exr", v[i].params, "out.exr");
        unsigned bits;
        if (!render_read(t, "g.lgraph", NULL, "out.exr", &out, &bits, NULL))
            continue;
        expect_constant(&want, c, v[i].key, v[i].delta, v[i].rgb, v[i].seed ? WSEED : W709);
        char what[128];
        snprintf(what, sizeof what, "constant {%s}", v[i].params);
        compare(t, &out, &want, bits, TOL, what);
        if (i == 0) {
            /* the textbook value, delta aside: a grey pixel of the mean maps to a/(1+a) */
            double g = out.pixels[0] * luma(c, W709) / c[0];
            LG_TEST_CHECK(t, fabs(g - 0.18 / 1.18) < 1e-4 + lg_test_tol_of(g, bits, 0),
                          "Ld = %.6g, a/(1+a) = %.6g", g, 0.18 / 1.18);
        }
        lg_image_free(&out);
    }
    lg_image_free(&in);
    lg_image_free(&want);
}

/* ---- white ----------------------------------------------------------------------------------- */

static void case_white(lg_test *t)
{
    const float lv[3] = { 0.5f, 8.0f, 20.0f };
    const double key = 0.18, delta = 1e-4;
    lg_image in = alloc_image(6, 5), out;
    for (size_t i = 0; i < 30; i++) {
        float v = lv[i % 3];
        float px[4] = { v, v, v, 1.0f };
        memcpy(in.pixels + i * 4, px, 16);
    }
    lg_test_write_exr(t, "in.exr", &in);
    double ls[3], sum = 0;
    for (int k = 0; k < 3; k++) {
        float px[3] = { lv[k], lv[k], lv[k] };
        ls[k] = luma(px, W709);
        sum += log(delta + ls[k]);
    }
    double s = key / exp(sum / 3);
    double lw = s * ls[1];
    for (int rgb = 0; rgb < 2; rgb++) {
        char params[256];
        snprintf(params, sizeof params, "white = %.17g%s", lw, rgb ? ", mode = rgb" : "");
        write_graph(t, "g.lgraph", "in.exr", params, "out.exr");
        unsigned bits;
        if (!render_read(t, "g.lgraph", NULL, "out.exr", &out, &bits, NULL))
            continue;
        double m = s * ls[0];
        double e0 = m * (1 + m / (lw * lw)) / (1 + m);
        for (size_t i = 0; i < 30; i++) {
            double g = out.pixels[i * 4 + 1];
            double e = i % 3 == 0 ? e0 : 1.0;
            LG_TEST_CHECK(t, fabs(g - e) <= lg_test_tol_of(e, bits, TOL),
                          "%s pixel %zu (level %g): %.9g, want %.9g", rgb ? "rgb" : "luminance", i,
                          lv[i % 3], g, e);
        }
        lg_image_free(&out);
    }
    /* without the white point the same levels stay below 1 */
    write_graph(t, "g.lgraph", "in.exr", "", "out.exr");
    unsigned bits;
    if (render_read(t, "g.lgraph", NULL, "out.exr", &out, &bits, NULL)) {
        double m = s * ls[1];
        LG_TEST_CHECK(t,
                      fabs(out.pixels[1 * 4 + 1] - m / (1 + m)) <=
                          lg_test_tol_of(m / (1 + m), bits, TOL),
                      "no white: %.9g, want %.9g", out.pixels[5], m / (1 + m));
        lg_image_free(&out);
    }
    lg_image_free(&in);
}

/* ---- monotone -------------------------------------------------------------------------------- */

static void case_monotone(lg_test *t)
{
    const uint32_t w = 200, h = 3;
    lg_image in = alloc_image(w, h), out;
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            float v = (float)pow(10.0, -5.0 + 10.0 * x / (w - 1));
            /* row 0 grey, row 1 warm, row 2 cold */
            float px[4] = { v * (y == 1 ? 3.0f : 1.0f), v, v * (y == 2 ? 3.0f : 1.0f), 1.0f };
            memcpy(in.pixels + ((size_t)y * w + x) * 4, px, 16);
        }
    }
    lg_test_write_exr(t, "in.exr", &in);
    for (int rgb = 0; rgb < 2; rgb++) {
        write_graph(t, "g.lgraph", "in.exr", rgb ? "mode = rgb" : "", "out.exr");
        unsigned bits;
        if (!render_read(t, "g.lgraph", NULL, "out.exr", &out, &bits, NULL))
            continue;
        int bad = 0;
        for (uint32_t y = 0; y < h; y++) {
            for (uint32_t x = 0; x < w; x++) {
                const float *p = out.pixels + ((size_t)y * w + x) * 4;
                for (int k = 0; k < 3; k++) {
                    /* luminance mode: a saturated channel may exceed 1 (c Ld / L) */
                    float hi = rgb || y == 0 ? 1.0f : 3.0f;
                    if (!(p[k] >= 0 && p[k] <= hi) && bad++ < 5)
                        fprintf(stderr, "pixel (%u,%u) ch %d = %g out of range\n", x, y, k, p[k]);
                    if (x && !(p[k] >= p[k - 4]) && bad++ < 5)
                        fprintf(stderr, "pixel (%u,%u) ch %d: %.9g < %.9g before it\n", x, y, k,
                                p[k], p[k - 4]);
                }
            }
        }
        LG_TEST_CHECK(t, bad == 0, "%s: %d violations", rgb ? "rgb" : "luminance", bad);
        LG_TEST_CHECK(t, out.pixels[1] < 0.01f && out.pixels[(w - 1) * 4 + 1] > 0.99f,
                      "the ramp does not span the range: %g .. %g", out.pixels[1],
                      out.pixels[(w - 1) * 4 + 1]);
        lg_image_free(&out);
    }
    lg_image_free(&in);
}

/* ---- exposure -------------------------------------------------------------------------------- */

static void case_exposure(lg_test *t)
{
    /* a real photograph (no zero pixels, Lmin ~ 1e-3), a repository file: missing fails
     * the test (lg_test_asset); delta small so that only the exposure differs */
    char src[4200];
    snprintf(src, sizeof src, "%s", lg_test_asset("images/GoldenGate.exr"));
    for (int rgb = 0; rgb < 2; rgb++) {
        char text[8192];
        const char *mode = rgb ? ", mode = rgb" : "";
        snprintf(text, sizeof text,
                 "lightgraph 1\nsrc = image { file = \"%s\" }\n"
                 "up = scale { image = src, factor = 10 }\n"
                 "t1 = reinhard { image = src, delta = 1e-9, backend = %s%s }\n"
                 "t10 = reinhard { image = up, delta = 1e-9, backend = %s%s }\n"
                 "output t1 \"o1.exr\"\noutput t10 \"o10.exr\"\n",
                 src, backend, mode, backend, mode);
        diff_nodes(text, sizeof text, "t10", "t1", "diff.exr");
        lg_test_write_text(t, "g.lgraph", text);
        LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, NULL) == 0, "render failed");
        lg_image a, b;
        unsigned bits;
        if (lg_test_read(t, "o1.exr", &a, &bits)) {
            if (lg_test_read(t, "o10.exr", &b, NULL)) {
                compare_n(t, &b, &a, bits, 1e-5, 2, rgb ? "x10 rgb" : "x10");
                lg_image_free(&b);
            }
            lg_image_free(&a);
        }
        double mx, mean;
        if (diff_stats(t, "diff.exr", &mx, &mean)) {
            fprintf(stderr, "exposure x10 (%s): max abs diff %.3g, mean %.3g (float)\n",
                    rgb ? "rgb" : "luminance", mx, mean);
            LG_TEST_CHECK(t, mx <= 1e-5, "x10 changed the output by %.3g in float", mx);
        }
    }
}

/* ---- adapt ----------------------------------------------------------------------------------- */

static void case_adapt(lg_test *t)
{
    const float c[4] = { 0.4f, 0.4f, 0.4f, 1.0f };
    const double key = 0.18, delta = 1e-4, la0 = 5.0, rate = 0.98;
    lg_image in = alloc_image(16, 16), want = alloc_image(16, 16), a, b, d, e;
    fill(&in, c);
    lg_test_write_exr(t, "in.exr", &in);
    write_graph(t, "g.lgraph", "in.exr", "adapt = true, adapt_from = 5", "out.exr");
    const char *sixty[] = { "--frames", "60", "--dt", "0.016666666666666666", "-o", "a.exr", NULL };
    const char *one[] = { "--frames", "1", "--dt", "1", "-o", "b.exr", NULL };
    unsigned bits = 32;
    bool ok = render_read(t, "g.lgraph", sixty, "a.exr", &a, &bits, NULL);
    ok &= render_read(t, "g.lgraph", one, "b.exr", &b, NULL, NULL);
    /* the node's dt wins over --dt */
    write_graph(t, "g2.lgraph", "in.exr", "adapt = true, adapt_from = 5, dt = 0.016666666666666666",
                "out.exr");
    const char *sixty_slow[] = { "--frames", "60", "--dt", "1", "-o", "d.exr", NULL };
    ok &= render_read(t, "g2.lgraph", sixty_slow, "d.exr", &d, NULL, NULL);
    /* adaptation off: the frame's own Lavg */
    write_graph(t, "g3.lgraph", "in.exr", "adapt_from = 5", "out.exr");
    ok &= render_read(t, "g3.lgraph", one, "b.exr", &e, NULL, NULL);
    if (!ok)
        return;

    double l = luma(c, W709), lavg = l + delta;
    double la = lavg + (la0 - lavg) * pow(rate, 60.0);
    double s = key / la;
    float o = (float)(s * l / (1 + s * l));
    fill(&want, (const float[4]){ o, o, o, 1.0f });
    compare(t, &a, &want, bits, TOL, "60 frames of 1/60 s");
    compare(t, &b, &want, bits, TOL, "1 frame of 1 s");
    compare(t, &d, &want, bits, TOL, "node dt 1/60, --dt 1");
    compare_n(t, &a, &b, bits, 1e-6, 2, "60 x 1/60 against 1 x 1");
    double s0 = key / lavg, o0 = s0 * l / (1 + s0 * l);
    LG_TEST_CHECK(t, fabs(e.pixels[0] - o0) <= lg_test_tol_of(o0, bits, TOL),
                  "adapt off: %.9g, want %.9g", e.pixels[0], o0);
    LG_TEST_CHECK(t, fabs(a.pixels[0] - e.pixels[0]) > 1e-3,
                  "adaptation had no effect (%.9g vs %.9g)", a.pixels[0], e.pixels[0]);
    lg_image_free(&a);
    lg_image_free(&b);
    lg_image_free(&d);
    lg_image_free(&e);
    lg_image_free(&in);
    lg_image_free(&want);
}

/* ---- bad pixels ------------------------------------------------------------------------------ */

static void case_badpixels(lg_test *t)
{
    const uint32_t w = 16, h = 8;
    const double key = 0.18, delta = 1e-4;
    lg_image in = alloc_image(w, h), out;
    srand(11);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        float *p = in.pixels + i * 4;
        for (int k = 0; k < 3; k++)
            p[k] = (float)exp(6.0 * rand() / RAND_MAX - 3.0);
        p[3] = 0.75f;
    }
    /* the bad ones, spread over rows */
    const float inf = INFINITY;
    struct {
        size_t at;
        float px[3];
    } bad[] = {
        { 3, { NAN, 1, 1 } },        { 20, { 1, NAN, NAN } }, { 37, { inf, 1, 1 } },
        { 50, { inf, inf, inf } },   { 64, { -inf, 1, 1 } },  { 77, { 1, 1, -inf } },
        { 90, { -10, 0.5f, 0.5f } }, { 101, { 0, 0, 0 } },    { 115, { 0, 0, 0 } },
        { 127, { -0.01f, 1, 1 } }, /* negative channel, positive luminance: valid */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        memcpy(in.pixels + bad[i].at * 4, bad[i].px, 12);
    lg_test_write_exr(t, "in.exr", &in);

    /* closed form over the valid pixels: all but 6 nonfinite and 1 negative */
    double sum = 0;
    size_t valid = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const float *p = in.pixels + i * 4;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            continue;
        double l = luma(p, W709);
        if (l < 0)
            continue;
        sum += log(delta + l);
        valid++;
    }
    double s = key / exp(sum / (double)valid);
    for (int rgb = 0; rgb < 2; rgb++) {
        write_graph(t, "g.lgraph", "in.exr", rgb ? "mode = rgb" : "", "out.exr");
        unsigned bits;
        char *err = NULL;
        if (!render_read(t, "g.lgraph", NULL, "out.exr", &out, &bits, &err))
            continue;
        LG_TEST_CHECK(t,
                      err && strstr(err, "7 of 128 pixels") && strstr(err, "6 with NaN or Inf") &&
                          strstr(err, "1 with negative luminance"),
                      "no warning with the counts (7 of 128; 6 NaN or Inf; 1 negative): %s",
                      err ? err : "");
        free(err);
        lg_image want = alloc_image(w, h);
        for (size_t i = 0; i < (size_t)w * h; i++) {
            const float *p = in.pixels + i * 4;
            float *q = want.pixels + i * 4;
            float c[3];
            bool pinf[3], any = false;
            for (int k = 0; k < 3; k++) {
                pinf[k] = isinf(p[k]) && p[k] > 0;
                any |= pinf[k];
                c[k] = isnan(p[k]) || p[k] < 0 || pinf[k] ? 0.0f : p[k];
            }
            double l = luma(c, W709);
            for (int k = 0; k < 3; k++) {
                if (pinf[k])
                    q[k] = 1.0f;
                else if (rgb)
                    q[k] = (float)(s * c[k] / (1 + s * c[k]));
                else if (any || l <= 0)
                    q[k] = 0.0f;
                else
                    q[k] = (float)(c[k] / l * (s * l / (1 + s * l)));
            }
            q[3] = p[3];
        }
        compare(t, &out, &want, bits, TOL, rgb ? "bad pixels, rgb" : "bad pixels, luminance");
        lg_image_free(&want);
        lg_image_free(&out);
    }
    lg_image_free(&in);
}

/* ---- bright ---------------------------------------------------------------------------------- */

/* Greys so bright that the scaled luminance s L is +Inf or Ld rounds to 1 (and +Inf pixels):
 * exactly 1, as the README promises (x / (1 + x) is 1 for x = +Inf), never 1 + 1 ulp, in both
 * modes and with a white point; and every grey pixel maps to at most 1. 20 pixels wide, so
 * that the cl backend's float8 blocks and its last, partial block both see them. */
static void case_bright(lg_test *t)
{
    const uint32_t w = 20, h = 2;
    lg_image in = alloc_image(w, h), out;
    const float inf = INFINITY;
    const float greys[] = { 1e30f, 3.4028235e38f, 3e38f, 1e20f, inf, 1e9f, 0.5f, 2.0f, 1e30f };
    const size_t at[] = { 0, 3, 7, 9, 13, 17, 19, 22, 38 };
    for (size_t i = 0; i < (size_t)w * h; i++) {
        float *p = in.pixels + i * 4;
        p[0] = 0.1f + 0.01f * (float)i;
        p[1] = 0.2f;
        p[2] = 0.05f + 0.02f * (float)(i % 7);
        p[3] = 1.0f;
    }
    for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
        float *p = in.pixels + at[i] * 4;
        p[0] = p[1] = p[2] = greys[i];
    }
    lg_test_write_exr(t, "in.exr", &in);
    const char *extras[] = { "", "mode = rgb", "white = 2", "mode = rgb, white = 2" };
    for (size_t e = 0; e < sizeof extras / sizeof extras[0]; e++) {
        write_graph(t, "g.lgraph", "in.exr", extras[e], "out.exr");
        unsigned bits;
        if (!render_read(t, "g.lgraph", NULL, "out.exr", &out, &bits, NULL))
            continue;
        LG_TEST_CHECK(t, bits == 32, "the output should be float EXR (got %u bits)", bits);
        for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
            const float *q = out.pixels + at[i] * 4;
            for (int k = 0; k < 3; k++) {
                if (greys[i] >= 1e20f)
                    LG_TEST_CHECK(t, q[k] == 1.0f,
                                  "%s: grey %g (pixel %zu) channel %d maps to "
                                  "%.9g, not exactly 1",
                                  *extras[e] ? extras[e] : "defaults", (double)greys[i], at[i], k,
                                  (double)q[k]);
                else
                    LG_TEST_CHECK(t, q[k] <= 1.0f && q[k] == q[0],
                                  "%s: grey %g (pixel %zu) "
                                  "channel %d maps to %.9g (channel 0: %.9g)",
                                  *extras[e] ? extras[e] : "defaults", (double)greys[i], at[i], k,
                                  (double)q[k], (double)q[0]);
            }
        }
        lg_image_free(&out);
    }
    lg_image_free(&in);
}

/* ---- sizes ----------------------------------------------------------------------------------- */

static void case_sizes(lg_test *t)
{
    static const uint32_t sz[][2] = { { 1, 1 }, { 17, 3 }, { 3, 257 }, { 300, 1 }, { 1100, 700 } };
    const float c[4] = { 3.0f, 0.25f, 1.0f, 0.5f };
    for (size_t i = 0; i < sizeof sz / sizeof sz[0]; i++) {
        lg_image in = alloc_image(sz[i][0], sz[i][1]), want = alloc_image(sz[i][0], sz[i][1]), out;
        fill(&in, c);
        lg_test_write_exr(t, "in.exr", &in);
        write_graph(t, "g.lgraph", "in.exr", "", "out.exr");
        unsigned bits;
        if (render_read(t, "g.lgraph", NULL, "out.exr", &out, &bits, NULL)) {
            expect_constant(&want, c, 0.18, 1e-4, false, W709);
            char what[64];
            snprintf(what, sizeof what, "%ux%u", sz[i][0], sz[i][1]);
            /* 770,000 float logs summed: a little more rounding in the average */
            compare(t, &out, &want, bits, i == 4 ? 1e-5 : TOL, what);
            lg_image_free(&out);
        }
        lg_image_free(&in);
        lg_image_free(&want);
    }
}

/* ---- every backend --------------------------------------------------------------------------- */

/* The reference: the plain double-precision oracle (reinhard_oracle.c: log sum in double,
 * the curve in double, one pixel at a time) on the input as the node reads it. */
static void reference(const lg_image *in, lg_image *out, lg_rh_mode mode, const double w[3],
                      double key, double delta, double white)
{
    lg_rh_params p = {
        .mode = mode, .w = { (float)w[0], (float)w[1], (float)w[2] }, .delta = delta, .white = white
    };
    size_t n = (size_t)in->width * in->height;
    lg_rh_stats st;
    memset(&st, 0, sizeof st);
    lg_rh_ref_reduce(in->pixels, n, &p, &st);
    double lavg = 1;
    if (!lg_rh_log_average(&st, &lavg)) {
        fprintf(stderr, "reference: no valid pixel\n");
        exit(99);
    }
    *out = alloc_image(in->width, in->height);
    lg_rh_ref_map(in->pixels, out->pixels, n, key / lavg, &p);
}

/* An HDR test image: log-uniform values over 8 decades per channel, a few exact zeros, a
 * smooth gradient in one corner (so the worst pixel's place means something). */
static lg_image synthetic(uint32_t w, uint32_t h)
{
    lg_image img = alloc_image(w, h);
    uint64_t r = 0x9E3779B97F4A7C15ull;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        for (int k = 0; k < 3; k++) {
            r ^= r << 13, r ^= r >> 7, r ^= r << 17; /* xorshift64 */
            double u = (double)(r >> 11) * 0x1.0p-53;
            img.pixels[i * 4 + k] = i % 97 == 0 ? 0.0f : (float)pow(10.0, 8.0 * u - 4.0);
        }
        img.pixels[i * 4 + 3] = 1.0f;
    }
    return img;
}

/* Every backend of the node (cpu, gl, cl: what `inspect reinhard --json` lists) through the
 * harness: each against the double-precision reference and against the cpu backend, in
 * four parameter sets, on a photograph and on a synthetic image. Under --bench, a
 * 2048x1396 image and N frames per backend (the bench table). */
static void case_backends(lg_test *t)
{
    static const struct {
        const char *params;
        lg_rh_mode mode;
        bool seed;
        double key, white;
    } v[] = {
        { "", LG_RH_LUMINANCE, false, 0.18, 0 },
        { "mode = rgb", LG_RH_RGB, false, 0.18, 0 },
        { "white = 40", LG_RH_LUMINANCE, false, 0.18, 40 },
        { "key = 0.72, luminance = seed, mode = rgb", LG_RH_RGB, true, 0.72, 0 },
    };
    bool bench = lg_test_bench_frames(t) > 0;
    char missing[32] = "";
    const char *photo = lg_test_asset("images/GoldenGate.exr"); /* fails when missing */
    struct {
        const char *name, *file;
        lg_image img;
    } inputs[2];
    size_t n_inputs = 0;
    {
        inputs[n_inputs].name = "photo";
        inputs[n_inputs].file = photo;
        char err[512];
        lg_image_read_info info;
        memset(&info, 0, sizeof info);
        if (lg_image_read(photo, 0, &inputs[n_inputs].img, &info, err, sizeof err)) {
            LG_TEST_FAILF(t, "%s", err);
            return;
        }
        n_inputs++;
    }
    if (!bench) {
        inputs[n_inputs].name = "synthetic";
        inputs[n_inputs].file = "synthetic.exr";
        inputs[n_inputs].img = bench ? synthetic(2048, 1396) : synthetic(203, 77);
        lg_test_write_exr(t, "synthetic.exr", &inputs[n_inputs].img);
        n_inputs++;
    }
    for (size_t in = 0; in < n_inputs; in++) {
        for (size_t i = 0; i < (bench ? 1 : sizeof v / sizeof v[0]); i++) {
            lg_image want;
            reference(&inputs[in].img, &want, v[i].mode, v[i].seed ? WSEED : W709, v[i].key, 1e-4,
                      v[i].white);
            char graph[8192], what[256];
            /* radiance = false: the node sees the file's values as they are */
            snprintf(graph, sizeof graph,
                     "lightgraph 1\nsrc = image { file = \"%s\", radiance = false }\n"
                     "tone = reinhard { image = src%s%s }\n",
                     inputs[in].file, *v[i].params ? ", " : "", v[i].params);
            snprintf(what, sizeof what, "reinhard {%s} on %s", v[i].params, inputs[in].name);
            /* float map and a float log sum on gl and cl against the double reference:
             * a few float ulps of the scale, a few of the curve */
            lg_test_backends_desc d = {
                .graph = graph,
                .node = "tone",
                .reference = &want,
                .tol_reference = { .max_abs = 1e-5, .rmse = 1e-6 },
                .tol_backends = { .max_abs = 1e-5, .rmse = 1e-6 },
                .what = what,
                /* a reduction pass and a map pass over rgba32f: 16 B read twice, 16 B written */
                .bytes_per_frame = 48.0 * inputs[in].img.width * inputs[in].img.height,
                /* a missing device: a skip at the end, once the images are freed */
                .allow_missing = true,
            };
            lg_test_backends_result res;
            size_t ran = lg_test_backends(t, &d, &res);
            for (size_t k = 0; k < res.n; k++)
                if (res.run[k].status == LG_TEST_RUN_NO_DEVICE)
                    snprintf(missing, sizeof missing, "%s", res.run[k].backend);
            LG_TEST_CHECK(t,
                          ran >= 1 && strcmp(res.run[0].backend, "cpu") == 0 &&
                              res.run[0].status == LG_TEST_RUN_OK,
                          "%s: the cpu backend did not run", what);
            lg_test_backends_free(&res);
            lg_image_free(&want);
        }
        lg_image_free(&inputs[in].img);
    }
    if (*missing)
        lg_test_skip(t, "no %s device here (the other backends were compared)", missing);
}

/* The per-backend cases read their backend (cpu, gl or cl) from the argument after the
 * case's name; it defaults to cpu (e.g. under --all or --bench). */
static void setup(lg_test *t)
{
    backend = lg_test_arg(t, 0) ? lg_test_arg(t, 0) : "cpu";
    lg_test_require_backend(t, backend);
}

/* ---- threads --------------------------------------------------------------------------------- */

static void case_threads(lg_test *t)
{
    if (strcmp(backend, "cpu") != 0) {
        LG_TEST_FAILF(t, "threads is a cpu case (the host's pool), not %s", backend);
        return;
    }
    /* a few hundred chunks of rows, bad pixels and ten decades of values */
    const uint32_t w = 1031, h = 677;
    lg_image in = alloc_image(w, h);
    uint32_t seed = 5;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        float *p = in.pixels + i * 4;
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            p[k] = (float)pow(10.0, -5.0 + 10.0 * (seed >> 8) / 16777216.0);
        }
        p[3] = 1.0f;
        if (i % 1013 == 7)
            p[1] = NAN;
    }
    lg_test_write_exr(t, "in.exr", &in);
    write_graph(t, "g.lgraph", "in.exr", "", "out.exr");
    static const char *const threads[] = { "1", "2", "7" };
    lg_image out[3];
    bool ok = true;
    for (int k = 0; k < 3; k++) {
        setenv("LIGHTGRAPH_THREADS", threads[k], 1);
        const char *args[] = { "-o", k == 0 ? "t1.exr" : k == 1 ? "t2.exr" : "t7.exr", NULL };
        ok &= render_read(t, "g.lgraph", args, args[1], &out[k], NULL, NULL);
    }
    unsetenv("LIGHTGRAPH_THREADS");
    if (ok) {
        for (int k = 1; k < 3; k++)
            LG_TEST_CHECK(t, memcmp(out[k].pixels, out[0].pixels, (size_t)w * h * 16) == 0,
                          "LIGHTGRAPH_THREADS=%s maps differently from LIGHTGRAPH_THREADS=1",
                          threads[k]);
        for (int k = 0; k < 3; k++)
            lg_image_free(&out[k]);
    }
    lg_image_free(&in);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "constant", case_constant }, { "white", case_white },
        { "monotone", case_monotone }, { "exposure", case_exposure },
        { "adapt", case_adapt },       { "badpixels", case_badpixels },
        { "sizes", case_sizes },       { "backends", case_backends },
        { "threads", case_threads },   { "bright", case_bright },
    };
    lg_test_main_opts o = { .prefix = "reinhard", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
