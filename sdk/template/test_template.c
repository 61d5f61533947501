/* The template plugin's test, on the SDK's harness (lightgraph/test.h): acme_blur on
 * every backend its `backend` parameter declares (cpu, gl and cl; the harness reads them
 * from `lightgraph inspect acme_blur --json`), each compared with the others and with a
 * reference computed here in double precision as the 2D sum of the Gaussian (not
 * separably, not in the node's float order: an independent oracle); then the parameter
 * checks of the host. A backend whose device is missing here makes its case a skip (77).
 *
 *     test_template CASE          one case (meson runs each)
 *     test_template --bench=N     the benchmark: N frames of 1920x1080 per backend
 *
 * LIGHTGRAPH_PLUGIN_PATH must name the folder of lg_acme_blur.so (meson.build sets it). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/test.h"

/* ---- the reference --------------------------------------------------------------------------- */

/* The node's bad-pixel policy (README "Bad pixels"): NaN reads as 0, +-Inf as +-FLT_MAX
 * (3.4028234663852886e38), and a result beyond it is that. */
static double sanitize(double v)
{
    const double fmax = 3.4028234663852886e38;
    return isnan(v) ? 0 : v > fmax ? fmax : v < -fmax ? -fmax : v;
}

/* out(x, y) = sum_i sum_j w_i w_j in(clamp(x + i), clamp(y + j)) in double, where
 * w_i = g(i) / sum_k g(k), g(i) = exp(-i^2 / (2 sigma^2)), i, j, k in [-r, r], r the radius
 * (0: ceil(3 sigma)); sigma 0 is the identity. */
static void reference(const lg_image *in, lg_image *out, double sigma, int radius)
{
    int r = sigma == 0 ? 0 : radius > 0 ? radius : (int)ceil(3 * sigma);
    double *w = calloc((size_t)2 * r + 1, sizeof *w), sum = 0;
    for (int i = -r; i <= r; i++)
        sum += w[i + r] = sigma == 0 ? 1 : exp(-(double)i * i / (2 * sigma * sigma));
    int wd = (int)in->width, ht = (int)in->height;
    for (int y = 0; y < ht; y++)
        for (int x = 0; x < wd; x++)
            for (int c = 0; c < 4; c++) {
                double acc = 0;
                for (int j = -r; j <= r; j++)
                    for (int i = -r; i <= r; i++) {
                        int xi = x + i < 0 ? 0 : x + i >= wd ? wd - 1 : x + i;
                        int yj = y + j < 0 ? 0 : y + j >= ht ? ht - 1 : y + j;
                        acc += w[i + r] / sum * w[j + r] / sum *
                               sanitize(in->pixels[4 * ((size_t)yj * wd + xi) + c]);
                    }
                out->pixels[4 * ((size_t)y * wd + x) + c] = (float)sanitize(acc);
            }
    free(w);
}

/* A test image: smooth and sharp features, values in [-0.5, 2], alpha varying. */
static void fill(lg_image *img)
{
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++) {
            float *p = img->pixels + 4 * ((size_t)y * img->width + x);
            p[0] = (float)(1 + sin(0.7 * x) * cos(0.3 * y));
            p[1] = (x / 4 + y / 3) % 2 ? 2.0f : -0.5f; /* a checkerboard: sharp edges */
            p[2] = (float)((x * 7 + y * 13) % 17) / 8.0f;
            p[3] = (float)x / (float)(img->width > 1 ? img->width - 1 : 1);
        }
}

/* Runs acme_blur { image = in.exr, <params> } on every backend against the reference. */
static void blur_backends(lg_test *t, const lg_image *in, double sigma, int radius,
                          const char *params, const lg_test_tol *tol, const char *what)
{
    lg_image want;
    if (lg_image_alloc(&want, in->width, in->height)) {
        LG_TEST_FAILF(t, "cannot allocate %ux%u", in->width, in->height);
        return;
    }
    reference(in, &want, sigma, radius);
    lg_test_write_exr(t, "in.exr", in);
    char graph[512], size[32];
    snprintf(graph, sizeof graph,
             "lightgraph 1\n"
             "src = image { file = \"in.exr\", radiance = false }\n"
             "blur = acme_blur { image = src, %s }\n",
             params);
    snprintf(size, sizeof size, "%ux%u", in->width, in->height);
    const char *args[] = { "--size", size, NULL };
    lg_test_backends_desc d = {
        .graph = graph,
        .node = "blur",
        .args = args,
        .reference = &want,
        .tol_reference = *tol,
        .tol_backends = *tol,
        .what = what,
        /* per pixel: the input and the scratch image read 2r + 1 times (mostly from the
         * caches), written once; count the memory traffic: 4 reads and writes of 16 bytes */
        .bytes_per_frame = 64.0 * in->width * in->height,
    };
    lg_test_backends(t, &d, NULL);
    lg_image_free(&want);
}

/* Float sums of 2r + 1 taps in two passes on values up to 2: measured at most 4.8e-7 from
 * the double reference and between backends (README "Accuracy"); five times that here. */
static const lg_test_tol tol_float = { .max_abs = 2.5e-6, .rmse = 5e-7 };

static void case_backends(lg_test *t)
{
    bool bench = lg_test_bench_frames(t) > 0;
    lg_image in;
    if (lg_image_alloc(&in, bench ? 1920 : 37, bench ? 1080 : 23)) {
        LG_TEST_FAILF(t, "cannot allocate the input");
        return;
    }
    fill(&in);
    blur_backends(t, &in, 2.5, 0, "sigma = 2.5", &tol_float, "sigma 2.5 (radius 8)");
    lg_image_free(&in);
}

/* Images smaller than the kernel (clamp to edge on every side) and thin ones. */
static void case_sizes(lg_test *t)
{
    static const uint32_t sizes[][2] = { { 1, 1 }, { 7, 5 }, { 3, 40 }, { 40, 2 } };
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        lg_image in;
        if (lg_image_alloc(&in, sizes[k][0], sizes[k][1])) {
            LG_TEST_FAILF(t, "cannot allocate %ux%u", sizes[k][0], sizes[k][1]);
            return;
        }
        fill(&in);
        char what[64];
        snprintf(what, sizeof what, "%ux%u, sigma 3 (radius 9)", sizes[k][0], sizes[k][1]);
        blur_backends(t, &in, 3, 0, "sigma = 3", &tol_float, what);
        lg_image_free(&in);
    }
}

/* sigma = 0 copies the image exactly; an explicit radius truncates the kernel. */
static void case_params(lg_test *t)
{
    lg_image in;
    if (lg_image_alloc(&in, 19, 11)) {
        LG_TEST_FAILF(t, "cannot allocate the input");
        return;
    }
    fill(&in);
    static const lg_test_tol exact = { .max_abs = 0 };
    blur_backends(t, &in, 0, 5, "sigma = 0, radius = 5", &exact, "sigma 0: a copy");
    blur_backends(t, &in, 4, 2, "sigma = 4, radius = 2", &tol_float, "sigma 4, radius 2");
    lg_image_free(&in);
}

/* NaN, +-Inf and the largest floats: finite output, as the policy says, and one warning. */
static void case_badpixels(lg_test *t)
{
    lg_image in;
    if (lg_image_alloc(&in, 9, 7)) {
        LG_TEST_FAILF(t, "cannot allocate the input");
        return;
    }
    fill(&in);
    in.pixels[4 * (3 * 9 + 4) + 0] = NAN;
    in.pixels[4 * (3 * 9 + 4) + 1] = INFINITY;
    in.pixels[4 * (1 * 9 + 1) + 2] = -INFINITY;
    in.pixels[4 * (5 * 9 + 7) + 0] = 3.4e38f; /* with its neighbours' sums: beyond FLT_MAX */
    in.pixels[4 * (5 * 9 + 8) + 0] = 3.4e38f;
    /* relative: the values near the huge pixels are ~1e37 */
    static const lg_test_tol tol = { .max_abs = 2.5e-6, .rel = 1e-6 };
    blur_backends(t, &in, 1.5, 0, "sigma = 1.5", &tol, "NaN, Inf, 3.4e38 pixels");

    /* the warning, once (on the default backend) */
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nsrc = image { file = \"in.exr\", radiance = false }\n"
                       "blur = acme_blur { image = src }\noutput blur \"o.exr\"\n");
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", NULL, &out);
    LG_TEST_CHECK(t, rc == 0, "exit %d, want 0", rc);
    const char *want = "input 'image' (frame 0): 2 pixels with a NaN or Inf channel, read as 0";
    LG_TEST_CHECK(t, out && strstr(out, want), "no warning '%s...' in: %s", want, out ? out : "");
    free(out);
    lg_image_free(&in);
}

static void case_range(lg_test *t)
{
    /* sigma is declared in [0, 64]: the host refuses -1 with exit status 2, naming it */
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nc = constant { color = [1, 1, 1] }\n"
                       "blur = acme_blur { image = c, sigma = -1 }\noutput blur \"o.exr\"\n");
    char *out = NULL;
    const char *args[] = { "--size", "4x4", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    LG_TEST_CHECK(t, rc == 2, "exit %d, want 2", rc);
    LG_TEST_CHECK(t, out && strstr(out, "sigma"), "the message does not name the parameter: %s",
                  out ? out : "");
    free(out);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "backends", case_backends },   { "sizes", case_sizes }, { "params", case_params },
        { "badpixels", case_badpixels }, { "range", case_range },
    };
    lg_test_main_opts o = { .prefix = "acme_blur" };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
