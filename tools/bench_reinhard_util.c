/*
 * lg_bench_reinhard: the two image chores of tools/bench_reinhard.py, through the SDK.
 *
 *   lg_bench_reinhard prep IN WIDTH OUT KEY DELTA
 *       Resamples IN to WIDTH pixels wide (the height keeps the aspect ratio) with
 *       bilinear filtering, writes OUT as a float EXR, and prints as JSON the figures a
 *       matching pfstmo_reinhard02 run needs: the log-average luminance (Rec.709 weights,
 *       log(DELTA + L)), the maximum luminance and the white point pfstmo_reinhard02 uses,
 *       Lwhite = KEY Lmax / Lavg (the largest scaled luminance).
 *   lg_bench_reinhard diff A B
 *       Prints the mean and maximum absolute RGB differences of two images of one size
 *       as JSON.
 *   lg_bench_reinhard absstats FILE GAIN
 *       The same for an image that already holds a difference multiplied by GAIN (a
 *       graph computed it in float; the output file may be half): mean and maximum of
 *       |v| / GAIN over RGB.
 *
 * Exit status 0, or 1 with a message on stderr.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"

static int usage(void)
{
    fprintf(stderr, "usage: lg_bench_reinhard prep IN WIDTH OUT KEY DELTA\n"
                    "       lg_bench_reinhard diff A B\n"
                    "       lg_bench_reinhard absstats FILE GAIN\n");
    return 2;
}

/* Bilinear, pixel centres aligned ((x + 0.5) s - 0.5), edges clamped. */
static float sample(const lg_image *in, double fx, double fy, int c)
{
    double x = fx < 0 ? 0 : fx, y = fy < 0 ? 0 : fy;
    uint32_t x0 = (uint32_t)x, y0 = (uint32_t)y;
    if (x0 >= in->width - 1)
        x0 = in->width - 1;
    if (y0 >= in->height - 1)
        y0 = in->height - 1;
    uint32_t x1 = x0 + 1 < in->width ? x0 + 1 : x0, y1 = y0 + 1 < in->height ? y0 + 1 : y0;
    double tx = x - x0, ty = y - y0;
    if (tx > 1)
        tx = 1;
    if (ty > 1)
        ty = 1;
    const float *p = in->pixels;
    double a = p[((size_t)y0 * in->width + x0) * 4 + c],
           b = p[((size_t)y0 * in->width + x1) * 4 + c];
    double d = p[((size_t)y1 * in->width + x0) * 4 + c],
           e = p[((size_t)y1 * in->width + x1) * 4 + c];
    return (float)((a * (1 - tx) + b * tx) * (1 - ty) + (d * (1 - tx) + e * tx) * ty);
}

static int prep(const char *inpath, const char *wtext, const char *outpath, const char *ktext,
                const char *dtext)
{
    char err[1024];
    lg_image in, out;
    int width = atoi(wtext);
    double key = atof(ktext), delta = atof(dtext);
    if (width <= 0 || key <= 0 || delta <= 0) {
        fprintf(stderr, "lg_bench_reinhard: WIDTH, KEY and DELTA must be positive\n");
        return 1;
    }
    if (lg_image_read(inpath, LG_READ_RADIANCE, &in, NULL, err, sizeof err)) {
        fprintf(stderr, "lg_bench_reinhard: %s\n", err);
        return 1;
    }
    uint32_t w = (uint32_t)width;
    uint32_t h = (uint32_t)((double)in.height * w / in.width + 0.5);
    if (lg_image_alloc(&out, w, h)) {
        fprintf(stderr, "lg_bench_reinhard: cannot allocate %ux%u\n", w, h);
        return 1;
    }
    double sx = (double)in.width / w, sy = (double)in.height / h;
    double sum = 0, lmax = 0;
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            float *q = out.pixels + ((size_t)y * w + x) * 4;
            for (int c = 0; c < 4; c++)
                q[c] = sample(&in, (x + 0.5) * sx - 0.5, (y + 0.5) * sy - 0.5, c);
            double l = 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
            sum += log(delta + l);
            lmax = l > lmax ? l : lmax;
        }
    }
    lg_image_write_opts o = { .exr_pixel = LG_EXR_FLOAT, .exr_compression = LG_EXR_ZIP };
    if (lg_image_write(outpath, &out, &o, err, sizeof err)) {
        fprintf(stderr, "lg_bench_reinhard: %s\n", err);
        return 1;
    }
    double lavg = exp(sum / ((double)w * h));
    printf("{\"width\": %u, \"height\": %u, \"lavg\": %.17g, \"lmax\": %.17g, \"white\": %.17g}\n",
           w, h, lavg, lmax, key * lmax / lavg);
    lg_image_free(&in);
    lg_image_free(&out);
    return 0;
}

static int diff(const char *a, const char *b)
{
    char err[1024];
    lg_image ia, ib;
    if (lg_image_read(a, 0, &ia, NULL, err, sizeof err) ||
        lg_image_read(b, 0, &ib, NULL, err, sizeof err)) {
        fprintf(stderr, "lg_bench_reinhard: %s\n", err);
        return 1;
    }
    lg_image_metrics m;
    if (lg_image_compare(&ia, &ib, &m, NULL, 0, err, sizeof err)) {
        fprintf(stderr, "lg_bench_reinhard: %s\n", err);
        return 1;
    }
    printf("{\"mean_abs\": %.9g, \"max_abs\": %.9g, \"rmse\": %.9g, \"nonfinite\": %llu}\n",
           m.mean_abs, m.max_abs, m.rmse, (unsigned long long)m.nonfinite);
    lg_image_free(&ia);
    lg_image_free(&ib);
    return 0;
}

static int absstats(const char *path, const char *gtext)
{
    char err[1024];
    lg_image img;
    double gain = atof(gtext);
    if (!(gain > 0)) {
        fprintf(stderr, "lg_bench_reinhard: GAIN must be positive\n");
        return 1;
    }
    if (lg_image_read(path, 0, &img, NULL, err, sizeof err)) {
        fprintf(stderr, "lg_bench_reinhard: %s\n", err);
        return 1;
    }
    double sum = 0, mx = 0;
    unsigned long long nonfinite = 0;
    size_t n = (size_t)img.width * img.height;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            double v = fabs(img.pixels[i * 4 + c]) / gain;
            if (!isfinite(v)) {
                nonfinite++;
                continue;
            }
            sum += v;
            mx = v > mx ? v : mx;
        }
    }
    printf("{\"mean_abs\": %.9g, \"max_abs\": %.9g, \"nonfinite\": %llu}\n", sum / (3.0 * n), mx,
           nonfinite);
    lg_image_free(&img);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 7 && strcmp(argv[1], "prep") == 0)
        return prep(argv[2], argv[3], argv[4], argv[5], argv[6]);
    if (argc == 4 && strcmp(argv[1], "diff") == 0)
        return diff(argv[2], argv[3]);
    if (argc == 4 && strcmp(argv[1], "absstats") == 0)
        return absstats(argv[2], argv[3]);
    return usage();
}
