/*
 * lg_image_compare: metrics on images with known differences, NaN/Inf handling, the heat
 * map's colours, and size mismatches.
 */
#include <math.h>
#include <string.h>

#include "codectest.h"
#include "lightgraph/image.h"

static void fill(lg_image *img, float r, float g, float b)
{
    for (size_t i = 0; i < (size_t)img->width * img->height; i++) {
        img->pixels[i * 4] = r;
        img->pixels[i * 4 + 1] = g;
        img->pixels[i * 4 + 2] = b;
        img->pixels[i * 4 + 3] = 1.0f;
    }
}

static int near(double a, double b, double tol)
{
    return fabs(a - b) <= tol * (fabs(b) + 1e-12);
}

int main(void)
{
    lg_image a, b, heat;
    lg_image_metrics m;
    char err[256];
    CHECK(lg_image_alloc(&a, 8, 4) == LG_OK && lg_image_alloc(&b, 8, 4) == LG_OK);

    /* identical */
    fill(&a, 0.25f, 0.5f, 2.0f);
    fill(&b, 0.25f, 0.5f, 2.0f);
    CHECK(lg_image_compare(&a, &b, &m, &heat, 0.0, err, sizeof err) == LG_OK);
    CHECK(m.rmse == 0.0 && isinf(m.psnr) && m.psnr > 0 && m.max_abs == 0.0 && m.mean_abs == 0.0);
    CHECK(m.rel_mse == 0.0 && m.nonfinite == 0);
    CHECK(heat.width == 8 && heat.pixels[0] == 0.0f && heat.pixels[1] == 0.0f &&
          heat.pixels[3] == 1.0f);
    lg_image_free(&heat);

    /* a uniform difference of 0.25 in every channel */
    fill(&a, 0.5f, 0.5f, 0.5f);
    fill(&b, 0.25f, 0.25f, 0.25f);
    CHECK(lg_image_compare(&a, &b, &m, NULL, 0.0, err, sizeof err) == LG_OK);
    CHECK(near(m.rmse, 0.25, 1e-12) && near(m.mean_abs, 0.25, 1e-12) &&
          near(m.max_abs, 0.25, 1e-12));
    CHECK(near(m.psnr, 10.0 * log10(1.0 / 0.0625), 1e-12));
    CHECK(near(m.rel_mse, 0.0625 / (0.0625 + 1e-4), 1e-12));

    /* one channel of one pixel differs: the metrics average over 3 channels of all pixels */
    fill(&a, 1.0f, 1.0f, 1.0f);
    fill(&b, 1.0f, 1.0f, 1.0f);
    a.pixels[5 * 4 + 1] = 3.0f; /* pixel 5, green: error 2 */
    a.pixels[6 * 4 + 3] = 0.0f; /* alpha is not compared */
    CHECK(lg_image_compare(&a, &b, &m, &heat, 0.0, err, sizeof err) == LG_OK);
    CHECK(near(m.mean_abs, 2.0 / 96.0, 1e-12) && near(m.rmse, sqrt(4.0 / 96.0), 1e-12));
    CHECK(m.max_abs == 2.0 && near(m.rel_mse, 4.0 / 1.0001 / 96.0, 1e-12));
    /* heat: the largest error is white, no error black */
    CHECK(heat.pixels[5 * 4] == 1.0f && heat.pixels[5 * 4 + 1] == 1.0f &&
          heat.pixels[5 * 4 + 2] == 1.0f);
    CHECK(heat.pixels[0] == 0.0f && heat.pixels[6 * 4] == 0.0f);
    lg_image_free(&heat);

    /* the ramp with a fixed heat_max: 1/4 blue, 1/2 red, 3/4 yellow, beyond white */
    fill(&b, 0.0f, 0.0f, 0.0f);
    fill(&a, 0.0f, 0.0f, 0.0f);
    float errs[5] = { 0.25f, 0.5f, 0.75f, 1.0f, 7.0f };
    float want[5][3] = { { 0, 0, 1 }, { 1, 0, 0 }, { 1, 1, 0 }, { 1, 1, 1 }, { 1, 1, 1 } };
    for (int i = 0; i < 5; i++)
        a.pixels[i * 4 + 2] = -errs[i]; /* the error is absolute */
    a.pixels[7 * 4] = 0.125f;           /* between black and blue: dark blue, in display space */
    CHECK(lg_image_compare(&a, &b, &m, &heat, 1.0, err, sizeof err) == LG_OK);
    for (int i = 0; i < 5; i++)
        for (int c = 0; c < 3; c++)
            CHECKF(fabsf(heat.pixels[i * 4 + c] - want[i][c]) < 1e-6f, "heat %d channel %d: %g", i,
                   c, (double)heat.pixels[i * 4 + c]);
    CHECK(heat.pixels[7 * 4] == 0.0f && heat.pixels[7 * 4 + 1] == 0.0f);
    CHECK(fabsf(heat.pixels[7 * 4 + 2] - lg_srgb_decode(0.5f)) < 1e-6f);
    lg_image_free(&heat);

    /* NaN and Inf: counted, left out of the metrics, magenta in the heat map */
    fill(&a, 0.5f, 0.5f, 0.5f);
    fill(&b, 0.5f, 0.5f, 0.5f);
    a.pixels[0] = NAN;
    b.pixels[4 * 4 + 2] = INFINITY;
    a.pixels[9 * 4 + 1] = 0.75f;
    CHECK(lg_image_compare(&a, &b, &m, &heat, 0.0, err, sizeof err) == LG_OK);
    CHECK(m.nonfinite == 2);
    CHECK(isfinite(m.rmse) && near(m.max_abs, 0.25, 1e-12) && near(m.mean_abs, 0.25 / 90.0, 1e-9));
    CHECK(heat.pixels[0] == 1.0f && heat.pixels[1] == 0.0f && heat.pixels[2] == 1.0f);
    CHECK(heat.pixels[16] == 1.0f && heat.pixels[17] == 0.0f && heat.pixels[18] == 1.0f);
    lg_image_free(&heat);

    /* sizes differ: an error that gives both sizes */
    lg_image c;
    CHECK(lg_image_alloc(&c, 3, 5) == LG_OK);
    int rc = lg_image_compare(&a, &c, &m, &heat, 0.0, err, sizeof err);
    CHECKF(rc == LG_ERR_INVALID && strstr(err, "8x4") && strstr(err, "3x5"), "%d %s", rc, err);
    CHECK(heat.pixels == NULL);
    lg_image_free(&c);

    lg_image_free(&a);
    lg_image_free(&b);
    return check_report("compare");
}
