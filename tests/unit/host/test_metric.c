/* host/cli/metric.h's SSIM (lg_metric_ssim, through lg_metrics_compute), in process:
 *
 *   test_metric identical     an image against itself: SSIM exactly 1, DSSIM exactly 0
 *   test_metric constant      a constant against a constant: the paper's closed form
 *                             (2 mu_a mu_b + C1) / (mu_a^2 + mu_b^2 + C1), a black reference
 *   test_metric noise         SSIM falls strictly as the noise's amplitude grows
 *   test_metric blur          a blur and a uniform offset of the same RMSE: the blur's SSIM
 *                             is far lower (what a perceptual metric is for)
 *   test_metric nonfinite     windows with a NaN or Inf skipped and counted; all skipped: NaN
 *   test_metric small         images smaller than the window: NaN, no window
 *   test_metric speed         a 1920x1080 pair within a second of CPU time
 *   test_metric ssim_of A B   prints the SSIM of the text images A against B (the format of
 *                             test_metric_ssim.py, which checks it against its own SSIM)
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/check.h"
#include "cli/metric.h"
#include "lightgraph/vecmath.h"

/* ---- images ---------------------------------------------------------------------------------- */

static lg_image new_image(uint32_t w, uint32_t h)
{
    lg_image img;
    if (lg_image_alloc(&img, w, h) != 0) {
        fprintf(stderr, "test_metric: no memory for %ux%u\n", w, h);
        exit(1);
    }
    return img;
}

static void set_rgb(lg_image *img, uint32_t x, uint32_t y, double r, double g, double b)
{
    float *p = img->pixels + 4 * ((size_t)y * img->width + x);
    p[0] = (float)r;
    p[1] = (float)g;
    p[2] = (float)b;
    p[3] = 1.0f;
}

static void fill(lg_image *img, double r, double g, double b)
{
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++)
            set_rgb(img, x, y, r, g, b);
}

/* A scene-like linear image: a gradient, fine stripes and a bright disc, RGB apart. */
static lg_image textured(uint32_t w, uint32_t h)
{
    lg_image img = new_image(w, h);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double u = (double)x / w, v = (double)y / h;
            double stripes = 0.5 + 0.5 * sin(LG_PI * 0.5 * x) * cos(LG_PI * 0.3 * y);
            double dx = u - 0.6, dy = v - 0.4;
            double disc = dx * dx + dy * dy < 0.04 ? 2.0 : 0.0;
            set_rgb(&img, x, y, 0.2 + 0.6 * u * stripes + disc, 0.1 + 0.5 * v * stripes + disc,
                    0.3 * stripes + 0.2 * u * v + disc);
        }
    return img;
}

/* A deterministic uniform number in [-1, 1) (an LCG: the same on every machine). */
static double noise(uint64_t *state)
{
    *state = *state * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*state >> 11) / 4503599627370496.0 - 1.0;
}

static lg_metric_set compare(const lg_image *a, const lg_image *ref)
{
    lg_metric_set m;
    char err[256] = "";
    int rc = lg_metrics_compute(a, ref, &m, NULL, 0, err, sizeof err);
    CHECKF(rc == 0, "lg_metrics_compute: %s", err);
    return m;
}

/* ---- identical ------------------------------------------------------------------------------- */

static void test_identical(void)
{
    lg_image a = textured(64, 48), b = textured(64, 48);
    lg_metric_set m = compare(&a, &b);
    CHECKF(m.ssim == 1.0, "SSIM of an image against itself: %.17g, not exactly 1", m.ssim);
    CHECKF(lg_metric_value(&m, LG_METRIC_DSSIM) == 0.0, "DSSIM %.17g",
           lg_metric_value(&m, LG_METRIC_DSSIM));
    CHECKF(m.ssim_windows == 54 * 38 && m.ssim_skipped == 0, "windows %llu, skipped %llu",
           (unsigned long long)m.ssim_windows, (unsigned long long)m.ssim_skipped);
    CHECKF(m.base.rmse == 0.0 && m.rel_rmse == 0.0, "rmse %g, rel_rmse %g", m.base.rmse,
           m.rel_rmse);
    lg_image_free(&a);
    lg_image_free(&b);
}

/* ---- constant -------------------------------------------------------------------------------- */

static void expect_constant(double ca, double cb)
{
    lg_image a = new_image(20, 16), b = new_image(20, 16);
    fill(&a, ca, ca, ca);
    fill(&b, cb, cb, cb);
    /* grey: the luminance is the value (the weights sum to 1) */
    double ma = (float)ca, mb = (float)cb;
    double l = mb > LG_SSIM_MIN_RANGE ? mb : LG_SSIM_MIN_RANGE;
    double c1 = (0.01 * l) * (0.01 * l);
    double want = (2 * ma * mb + c1) / (ma * ma + mb * mb + c1);
    lg_metric_set m = compare(&a, &b);
    /* the variance E[a^2] - mu^2 of a constant is rounding, about 1e-16 mu_a^2, next to C2 */
    CHECKF(fabs(m.ssim - want) <= 1e-9 * fabs(want) + 1e-15,
           "constant %g against %g: SSIM %.17g, the closed form %.17g", ca, cb, m.ssim, want);
    CHECKF(fabs(m.ssim_range - l) <= 1e-7 * l, "constant %g: L %.17g, not %.17g", cb, m.ssim_range,
           l);
    CHECKF(m.ssim_windows == 10 * 6, "windows %llu", (unsigned long long)m.ssim_windows);
    lg_image_free(&a);
    lg_image_free(&b);
}

static void test_constant(void)
{
    expect_constant(0.2, 0.5);
    expect_constant(0.5, 0.2);
    expect_constant(3.0, 0.25);
    expect_constant(0.0, 1.0);
    expect_constant(0.999, 1.0);
    expect_constant(40.0, 38.0);
    /* a black reference: L is the floor, C1 > 0, and black against it is 1 */
    expect_constant(0.0, 0.0);
    expect_constant(1e-4, 0.0);
    expect_constant(1.0, 0.0);
    /* a coloured pair, the luminance weights checked */
    lg_image a = new_image(12, 12), b = new_image(12, 12);
    fill(&a, 1.0, 0.0, 0.0);
    fill(&b, 0.0, 0.0, 1.0);
    double ya = 0.2126, yb = 0.0722, c1 = (0.01 * yb) * (0.01 * yb);
    double want = (2 * ya * yb + c1) / (ya * ya + yb * yb + c1);
    lg_metric_set m = compare(&a, &b);
    CHECKF(fabs(m.ssim - want) <= 1e-6, "red against blue: SSIM %.17g, not %.17g (Y weights)",
           m.ssim, want);
    lg_image_free(&a);
    lg_image_free(&b);
}

/* ---- noise ----------------------------------------------------------------------------------- */

static void test_noise(void)
{
    lg_image ref = textured(96, 64), a = new_image(96, 64);
    const double amp[] = { 0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0 };
    double prev = 1.0;
    for (size_t i = 0; i < sizeof amp / sizeof amp[0]; i++) {
        uint64_t st = 42; /* the same noise pattern, scaled */
        for (size_t p = 0; p < (size_t)96 * 64 * 4; p++)
            a.pixels[p] = ref.pixels[p] + (p % 4 == 3 ? 0.0f : (float)(amp[i] * noise(&st)));
        lg_metric_set m = compare(&a, &ref);
        printf("noise %-6g rmse %-10.4g ssim %.6f\n", amp[i], m.base.rmse, m.ssim);
        CHECKF(m.ssim < prev, "noise %g: SSIM %.9g, not below %.9g (the smaller noise's)", amp[i],
               m.ssim, prev);
        prev = m.ssim;
    }
    CHECKF(prev < 0.5, "noise of amplitude 1 left SSIM at %g", prev);
    lg_image_free(&ref);
    lg_image_free(&a);
}

/* ---- blur ------------------------------------------------------------------------------------ */

/* Grey 0.5 with a gentle gradient and fine stripes of 5% (a fabric, a brick wall at a
 * distance): detail that a blur removes at little cost in RMSE. */
static lg_image fine_texture(uint32_t w, uint32_t h)
{
    lg_image img = new_image(w, h);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            double v = 0.4 + 0.2 * x / w + 0.05 * sin(LG_PI * 0.5 * x) * sin(LG_PI * 0.4 * y);
            set_rgb(&img, x, y, v, 0.9 * v, 0.8 * v);
        }
    return img;
}

/* A 3x3 box blur of ref (clamped at the borders). */
static lg_image blurred(const lg_image *ref)
{
    int w = (int)ref->width, h = (int)ref->height;
    lg_image out = new_image(ref->width, ref->height);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < 4; c++) {
                double s = 0;
                for (int j = -1; j <= 1; j++)
                    for (int i = -1; i <= 1; i++) {
                        int xx = x + i < 0 ? 0 : x + i >= w ? w - 1 : x + i;
                        int yy = y + j < 0 ? 0 : y + j >= h ? h - 1 : y + j;
                        s += ref->pixels[4 * ((size_t)yy * w + xx) + c];
                    }
                out.pixels[4 * ((size_t)y * w + x) + c] = (float)(s / 9.0);
            }
    return out;
}

static void test_blur(void)
{
    lg_image ref = fine_texture(96, 64), blur = blurred(&ref), off = new_image(96, 64);
    lg_metric_set mb = compare(&blur, &ref);
    /* a uniform offset on R, G and B has exactly its size as RMSE */
    double d = mb.base.rmse;
    for (size_t p = 0; p < (size_t)96 * 64 * 4; p++)
        off.pixels[p] = ref.pixels[p] + (p % 4 == 3 ? 0.0f : (float)d);
    lg_metric_set mo = compare(&off, &ref);
    printf("blur    rmse %.6g  rel_rmse %.6g  ssim %.6f  dssim %.6f\n", mb.base.rmse, mb.rel_rmse,
           mb.ssim, 1 - mb.ssim);
    printf("offset  rmse %.6g  rel_rmse %.6g  ssim %.6f  dssim %.6f\n", mo.base.rmse, mo.rel_rmse,
           mo.ssim, 1 - mo.ssim);
    CHECKF(fabs(mo.base.rmse - mb.base.rmse) <= 1e-3 * mb.base.rmse, "offset RMSE %g, blur %g",
           mo.base.rmse, mb.base.rmse);
    /* the blur is "visibly wrong": the stripes are gone; the offset "numerically off"; both
     * are a few percent of the reference in RMSE */
    CHECKF(mb.rel_rmse < 0.1, "the blur's relative RMSE %g is not small", mb.rel_rmse);
    CHECKF(mb.ssim < 0.8, "the blur's SSIM %g is not visibly low", mb.ssim);
    CHECKF(mo.ssim > 0.99, "the offset's SSIM %g is not near 1", mo.ssim);
    CHECKF(1 - mb.ssim > 20 * (1 - mo.ssim), "DSSIM blur %g, offset %g: not 20 times apart",
           1 - mb.ssim, 1 - mo.ssim);
    lg_image_free(&ref);
    lg_image_free(&blur);
    lg_image_free(&off);
}

/* ---- nonfinite ------------------------------------------------------------------------------- */

static void test_nonfinite(void)
{
    lg_image a = textured(32, 30), b = textured(32, 30);
    /* one NaN in A at (15, 12): the 11 x 11 windows holding it are skipped, the rest are 1 */
    set_rgb(&a, 15, 12, 0.5, NAN, 0.5);
    lg_metric_set m = compare(&a, &b);
    CHECKF(m.ssim_skipped == 11 * 11 && m.ssim_windows == 22 * 20 - 121 && m.ssim == 1.0,
           "a NaN in A: windows %llu, skipped %llu, SSIM %.17g", (unsigned long long)m.ssim_windows,
           (unsigned long long)m.ssim_skipped, m.ssim);
    /* an Inf in the reference near a corner: fewer windows hold it; L ignores it */
    set_rgb(&b, 2, 1, INFINITY, 0, 0);
    m = compare(&a, &b);
    CHECKF(m.ssim_skipped == 121 + 3 * 2 && isfinite(m.ssim_range),
           "an Inf in B at (2, 1): skipped %llu, L %g", (unsigned long long)m.ssim_skipped,
           m.ssim_range);
    /* every window skipped: NaN, and DSSIM NaN for the caller to refuse */
    for (uint32_t y = 0; y < 30; y += 5)
        for (uint32_t x = 0; x < 32; x += 5)
            set_rgb(&a, x, y, NAN, 0, 0);
    m = compare(&a, &b);
    CHECKF(m.ssim_windows == 0 && m.ssim_skipped == 22 * 20 && isnan(m.ssim) &&
               isnan(lg_metric_value(&m, LG_METRIC_DSSIM)),
           "NaN everywhere: windows %llu, skipped %llu, SSIM %g",
           (unsigned long long)m.ssim_windows, (unsigned long long)m.ssim_skipped, m.ssim);
    lg_image_free(&a);
    lg_image_free(&b);
}

/* ---- small ----------------------------------------------------------------------------------- */

static void expect_size(uint32_t w, uint32_t h, uint64_t windows)
{
    lg_image a = textured(w, h), b = textured(w, h);
    lg_metric_set m = compare(&a, &b);
    CHECKF(m.ssim_windows == windows && m.ssim_skipped == 0, "%ux%u: windows %llu, not %llu", w, h,
           (unsigned long long)m.ssim_windows, (unsigned long long)windows);
    CHECKF(windows ? m.ssim == 1.0 : isnan(m.ssim), "%ux%u: SSIM %g", w, h, m.ssim);
    CHECKF(m.base.rmse == 0.0, "%ux%u: the other metrics are still computed", w, h);
    lg_image_free(&a);
    lg_image_free(&b);
}

static void test_small(void)
{
    expect_size(1, 1, 0);
    expect_size(10, 40, 0);
    expect_size(40, 10, 0);
    expect_size(11, 11, 1);
    expect_size(12, 11, 2);
    expect_size(11, 14, 4);
    /* sizes that differ: an error, not a number */
    lg_image a = textured(12, 12), b = textured(12, 13);
    lg_metric_set m;
    char err[256] = "";
    CHECK(lg_metrics_compute(&a, &b, &m, NULL, 0, err, sizeof err) != 0);
    CHECK(lg_metric_ssim(&a, &b, &m, err, sizeof err) != 0 && strstr(err, "12x12 against 12x13"));
    lg_image_free(&a);
    lg_image_free(&b);
}

/* ---- speed ----------------------------------------------------------------------------------- */

static void test_speed(void)
{
    lg_image a = textured(1920, 1080), b = textured(1920, 1080);
    uint64_t st = 7;
    for (size_t p = 0; p < (size_t)1920 * 1080 * 4; p++)
        a.pixels[p] += (float)(0.05 * noise(&st));
    lg_metric_set m;
    char err[256] = "";
    clock_t t0 = clock();
    int rc = lg_metric_ssim(&a, &b, &m, err, sizeof err);
    double s = (double)(clock() - t0) / CLOCKS_PER_SEC;
    printf("SSIM of 1920x1080: %.3f s of CPU time, SSIM %.6f over %llu windows\n", s, m.ssim,
           (unsigned long long)m.ssim_windows);
    CHECKF(rc == 0, "%s", err);
#if defined(__SANITIZE_ADDRESS__) || !defined(__OPTIMIZE__)
    /* `make test-sanitize` (ASan + UBSan at -O0) measures the instrumentation, not the code */
    printf("an unoptimised or sanitized build: the time is not checked\n");
#else
    /* CPU time, not wall time: the machine's other load does not count */
    CHECKF(s < 1.0, "SSIM of 1920x1080 took %.3f s of CPU time", s);
#endif
    lg_image_free(&a);
    lg_image_free(&b);
}

/* ---- ssim_of --------------------------------------------------------------------------------- */

/* A text image: "W H" then W*H pixels "R G B" (nan and inf allowed), row by row. */
static int read_text(const char *path, lg_image *img)
{
    FILE *f = fopen(path, "r");
    unsigned w, h;
    if (!f || fscanf(f, "%u %u", &w, &h) != 2 || lg_image_alloc(img, w, h) != 0) {
        fprintf(stderr, "test_metric: cannot read '%s'\n", path);
        if (f)
            fclose(f);
        return -1;
    }
    for (size_t i = 0; i < (size_t)w * h; i++) {
        char c[3][64];
        if (fscanf(f, "%63s %63s %63s", c[0], c[1], c[2]) != 3) {
            fprintf(stderr, "test_metric: '%s' ends at pixel %zu\n", path, i);
            fclose(f);
            return -1;
        }
        for (int k = 0; k < 3; k++)
            img->pixels[4 * i + k] = strtof(c[k], NULL);
        img->pixels[4 * i + 3] = 1.0f;
    }
    fclose(f);
    return 0;
}

static int ssim_of(const char *pa, const char *pb)
{
    lg_image a = { 0 }, b = { 0 };
    if (read_text(pa, &a) || read_text(pb, &b))
        return 1;
    lg_metric_set m = compare(&a, &b);
    printf("ssim %.17g windows %llu skipped %llu range %.17g\n", m.ssim,
           (unsigned long long)m.ssim_windows, (unsigned long long)m.ssim_skipped, m.ssim_range);
    lg_image_free(&a);
    lg_image_free(&b);
    return check_failures ? 1 : 0;
}

int main(int argc, char **argv)
{
    const char *t = argc > 1 ? argv[1] : "";
    if (strcmp(t, "ssim_of") == 0 && argc == 4)
        return ssim_of(argv[2], argv[3]);
    if (strcmp(t, "identical") == 0)
        test_identical();
    else if (strcmp(t, "constant") == 0)
        test_constant();
    else if (strcmp(t, "noise") == 0)
        test_noise();
    else if (strcmp(t, "blur") == 0)
        test_blur();
    else if (strcmp(t, "nonfinite") == 0)
        test_nonfinite();
    else if (strcmp(t, "small") == 0)
        test_small();
    else if (strcmp(t, "speed") == 0)
        test_speed();
    else {
        fprintf(stderr, "usage: test_metric identical|constant|noise|blur|nonfinite|small|"
                        "speed | ssim_of A.txt B.txt\n");
        return 2;
    }
    return check_report(t);
}
