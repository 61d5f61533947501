/*
 * Image comparison: error metrics over RGB and a heat map of the per-pixel error.
 */
#include <math.h>
#include <string.h>

#include "image_alloc.h"

/* Heat ramp stops, in display (sRGB-encoded) values: black, blue, red, yellow, white. The
 * ramp is interpolated in display space, where it looks even, then decoded to linear so
 * that a PNG of the heat map shows exactly these colours. */
static const float heat_stops[5][3] = {
    { 0, 0, 0 }, { 0, 0, 1 }, { 1, 0, 0 }, { 1, 1, 0 }, { 1, 1, 1 },
};

static void heat_colour(double t, float out[3])
{
    if (!(t > 0.0))
        t = 0.0;
    if (t > 1.0)
        t = 1.0;
    double s = t * 4.0;
    int i = (int)s;
    if (i > 3)
        i = 3;
    float f = (float)(s - i);
    for (int c = 0; c < 3; c++) {
        float v = heat_stops[i][c] + (heat_stops[i + 1][c] - heat_stops[i][c]) * f;
        out[c] = lg_srgb_decode(v);
    }
}

static int px_finite(const float *p)
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

int lg_image_compare(const lg_image *a, const lg_image *b, lg_image_metrics *out, lg_image *heatmap,
                     double heat_max, char *err, size_t errlen)
{
    if (err && errlen)
        err[0] = 0;
    if (!a || !b || !out || !a->pixels || !b->pixels)
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "lg_image_compare: missing image");
    memset(out, 0, sizeof *out);
    if (a->width != b->width || a->height != b->height)
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "images differ in size: %ux%u and %ux%u",
                             a->width, a->height, b->width, b->height);
    if (heatmap) {
        int rc = lg_image_alloc(heatmap, a->width, a->height);
        if (rc)
            return lg_image_fail(err, errlen, rc, "cannot allocate a %ux%u heat map", a->width,
                                 a->height);
    }

    size_t n = (size_t)a->width * a->height;
    double sum_sq = 0.0, sum_abs = 0.0, sum_rel = 0.0, max_abs = 0.0;
    uint64_t finite = 0;
    for (size_t i = 0; i < n; i++) {
        const float *pa = a->pixels + i * 4, *pb = b->pixels + i * 4;
        if (!px_finite(pa) || !px_finite(pb)) {
            out->nonfinite++;
            continue;
        }
        finite++;
        for (int c = 0; c < 3; c++) {
            double d = (double)pa[c] - (double)pb[c];
            double ad = fabs(d);
            sum_sq += d * d;
            sum_abs += ad;
            sum_rel += d * d / ((double)pb[c] * pb[c] + 1e-4);
            if (ad > max_abs)
                max_abs = ad;
        }
    }
    if (finite) {
        double cnt = 3.0 * (double)finite;
        double mse = sum_sq / cnt;
        out->rmse = sqrt(mse);
        out->psnr = mse > 0.0 ? 10.0 * log10(1.0 / mse) : INFINITY;
        out->mean_abs = sum_abs / cnt;
        out->max_abs = max_abs;
        out->rel_mse = sum_rel / cnt;
    } else {
        /* nothing comparable: no error measured, and nothing to vouch for either */
        out->psnr = INFINITY;
    }

    if (heatmap) {
        double scale = heat_max > 0.0 ? heat_max : max_abs;
        for (size_t i = 0; i < n; i++) {
            const float *pa = a->pixels + i * 4, *pb = b->pixels + i * 4;
            float *h = heatmap->pixels + i * 4;
            h[3] = 1.0f;
            if (!px_finite(pa) || !px_finite(pb)) {
                h[0] = 1.0f; /* magenta */
                h[1] = 0.0f;
                h[2] = 1.0f;
                continue;
            }
            double e = 0.0;
            for (int c = 0; c < 3; c++) {
                double d = fabs((double)pa[c] - (double)pb[c]);
                if (d > e)
                    e = d;
            }
            heat_colour(scale > 0.0 ? e / scale : 0.0, h);
        }
    }
    return LG_OK;
}
