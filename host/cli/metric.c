/* The error metrics that diff, sweep and tune share (metric.h). */
#include "cli/metric.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const names[LG_METRIC_COUNT] = {
    [LG_METRIC_RMSE] = "rmse",         [LG_METRIC_REL_RMSE] = "rel_rmse",
    [LG_METRIC_MEAN_ABS] = "mean_abs", [LG_METRIC_MAX_ABS] = "max_abs",
    [LG_METRIC_REL_MSE] = "rel_mse",   [LG_METRIC_DSSIM] = "dssim",
};

int lg_metric_parse(const char *name, lg_metric_id *out)
{
    for (int i = 0; i < LG_METRIC_COUNT; i++)
        if (strcmp(name, names[i]) == 0) {
            *out = (lg_metric_id)i;
            return 0;
        }
    return -1;
}

const char *lg_metric_name(lg_metric_id id)
{
    return (unsigned)id < LG_METRIC_COUNT ? names[id] : "?";
}

const char *lg_metric_names(void)
{
    return "rmse, rel_rmse, mean_abs, max_abs, rel_mse, dssim";
}

/* sqrt(mean b^2) over RGB of the pixels finite in both images (lg_image_compare's set). */
static double reference_rms(const lg_image *a, const lg_image *ref)
{
    size_t n = (size_t)ref->width * ref->height;
    double sum = 0;
    size_t count = 0;
    for (size_t i = 0; i < n; i++) {
        const float *p = a->pixels + 4 * i, *q = ref->pixels + 4 * i;
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || !isfinite(q[0]) ||
            !isfinite(q[1]) || !isfinite(q[2]))
            continue;
        sum += (double)q[0] * q[0] + (double)q[1] * q[1] + (double)q[2] * q[2];
        count += 3;
    }
    return count ? sqrt(sum / (double)count) : 0.0;
}

/* ---- SSIM ------------------------------------------------------------------------------------ */

#define SSIM_R (LG_SSIM_WINDOW / 2) /* the window's radius: 5 */

/* The moments a window weighs: E[a], E[b], E[a^2], E[b^2], E[ab] of the luminances. */
enum { M_A, M_B, M_AA, M_BB, M_AB, N_MOMENTS };

/* The SSIM's state while it walks down the image. The 2-D Gaussian is the product of two
 * 1-D ones, so each row is filtered along x once, when it is read, into a ring of the last
 * LG_SSIM_WINDOW filtered rows; each output row of windows then filters the ring along y.
 * Memory: a few rows, whatever the image's height. */
typedef struct ssim_walk {
    int w, ow;                 /* image width; windows per row (w - 10) */
    double wt[LG_SSIM_WINDOW]; /* the 1-D Gaussian, sum 1 */
    double *row[N_MOMENTS];    /* one image row's per-pixel moments (w each) */
    int *bad_prefix;           /* w + 1: non-finite pixels of the row before x */
    double *ring[N_MOMENTS];   /* LG_SSIM_WINDOW rows of ow horizontal sums */
    int *bad_ring;             /* LG_SSIM_WINDOW rows of ow non-finite counts */
    double *acc[N_MOMENTS];    /* one output row's weighted moments (ow each) */
    void *block;               /* the one allocation all of the above point into */
} ssim_walk;

static int ssim_walk_init(ssim_walk *s, int w)
{
    s->w = w;
    s->ow = w - 2 * SSIM_R;
    size_t ow = (size_t)s->ow, n = (size_t)w;
    size_t doubles = N_MOMENTS * (n + ow * (LG_SSIM_WINDOW + 1));
    size_t ints = n + 1 + ow * LG_SSIM_WINDOW;
    s->block = malloc(doubles * sizeof(double) + ints * sizeof(int));
    if (!s->block)
        return -1;
    double *d = s->block;
    for (int m = 0; m < N_MOMENTS; m++) {
        s->row[m] = d, d += n;
        s->ring[m] = d, d += ow * LG_SSIM_WINDOW;
        s->acc[m] = d, d += ow;
    }
    s->bad_prefix = (int *)d;
    s->bad_ring = s->bad_prefix + n + 1;
    double sum = 0;
    for (int i = 0; i < LG_SSIM_WINDOW; i++) {
        double t = (double)(i - SSIM_R) / LG_SSIM_SIGMA;
        s->wt[i] = exp(-0.5 * t * t);
        sum += s->wt[i];
    }
    for (int i = 0; i < LG_SSIM_WINDOW; i++)
        s->wt[i] /= sum;
    return 0;
}

static double luminance(const float *p)
{
    return 0.2126 * (double)p[0] + 0.7152 * (double)p[1] + 0.0722 * (double)p[2];
}

static bool finite_rgb(const float *p)
{
    return isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]);
}

/* Image row y of A and B: its per-pixel moments (0 where a pixel is not finite in both, so
 * that no NaN spreads into the sums; such windows are skipped anyway), filtered along x into
 * ring slot y % LG_SSIM_WINDOW, with each horizontal window's count of non-finite pixels. */
static void ssim_row(ssim_walk *s, const lg_image *a, const lg_image *b, int y)
{
    const float *pa = a->pixels + (size_t)4 * s->w * y, *pb = b->pixels + (size_t)4 * s->w * y;
    s->bad_prefix[0] = 0;
    for (int x = 0; x < s->w; x++) {
        bool ok = finite_rgb(pa + 4 * x) && finite_rgb(pb + 4 * x);
        double ya = ok ? luminance(pa + 4 * x) : 0.0, yb = ok ? luminance(pb + 4 * x) : 0.0;
        s->row[M_A][x] = ya;
        s->row[M_B][x] = yb;
        s->row[M_AA][x] = ya * ya;
        s->row[M_BB][x] = yb * yb;
        s->row[M_AB][x] = ya * yb;
        s->bad_prefix[x + 1] = s->bad_prefix[x] + !ok;
    }
    size_t slot = (size_t)(y % LG_SSIM_WINDOW) * s->ow;
    for (int m = 0; m < N_MOMENTS; m++) {
        const double *in = s->row[m];
        double *out = s->ring[m] + slot;
        for (int x = 0; x < s->ow; x++) {
            double t = 0;
            for (int i = 0; i < LG_SSIM_WINDOW; i++)
                t += s->wt[i] * in[x + i];
            out[x] = t;
        }
    }
    for (int x = 0; x < s->ow; x++)
        s->bad_ring[slot + x] = s->bad_prefix[x + LG_SSIM_WINDOW] - s->bad_prefix[x];
}

/* The row of windows whose top row is image row oy (the ring holds rows oy .. oy + 10): adds
 * each window's SSIM to *sum, and counts it in *n or, holding a non-finite pixel, *skipped. */
static void ssim_windows(ssim_walk *s, int oy, double c1, double c2, double *sum, uint64_t *n,
                         uint64_t *skipped)
{
    for (int m = 0; m < N_MOMENTS; m++) {
        double *acc = s->acc[m];
        for (int x = 0; x < s->ow; x++)
            acc[x] = 0;
        for (int k = 0; k < LG_SSIM_WINDOW; k++) {
            const double *in = s->ring[m] + (size_t)((oy + k) % LG_SSIM_WINDOW) * s->ow;
            double wk = s->wt[k];
            for (int x = 0; x < s->ow; x++)
                acc[x] += wk * in[x];
        }
    }
    for (int x = 0; x < s->ow; x++) {
        int bad = 0;
        for (int k = 0; k < LG_SSIM_WINDOW; k++)
            bad += s->bad_ring[(size_t)k * s->ow + x];
        if (bad) {
            (*skipped)++;
            continue;
        }
        double ma = s->acc[M_A][x], mb = s->acc[M_B][x];
        /* the same operations on a and b, so that identical images give exactly 1 */
        double va = s->acc[M_AA][x] - ma * ma, vb = s->acc[M_BB][x] - mb * mb;
        double cov = s->acc[M_AB][x] - ma * mb;
        double num = (2.0 * ma * mb + c1) * (2.0 * cov + c2);
        double den = (ma * ma + mb * mb + c1) * (va + vb + c2);
        *sum += num / den;
        (*n)++;
    }
}

/* L: the reference's largest finite luminance, at least LG_SSIM_MIN_RANGE (metric.h). */
static double ssim_range(const lg_image *ref)
{
    double l = LG_SSIM_MIN_RANGE;
    size_t n = (size_t)ref->width * ref->height;
    for (size_t i = 0; i < n; i++) {
        const float *q = ref->pixels + 4 * i;
        if (finite_rgb(q) && luminance(q) > l)
            l = luminance(q);
    }
    return l;
}

int lg_metric_ssim(const lg_image *a, const lg_image *ref, lg_metric_set *out, char *err,
                   size_t errlen)
{
    if (a->width != ref->width || a->height != ref->height) {
        snprintf(err, errlen, "SSIM: the images differ in size (%ux%u against %ux%u)", a->width,
                 a->height, ref->width, ref->height);
        return -1;
    }
    out->ssim = NAN;
    out->ssim_windows = out->ssim_skipped = 0;
    out->ssim_range = ssim_range(ref);
    if (a->width < LG_SSIM_WINDOW || a->height < LG_SSIM_WINDOW)
        return 0; /* no window fits: NaN, as metric.h says */
    ssim_walk s;
    if (ssim_walk_init(&s, (int)a->width)) {
        snprintf(err, errlen, "SSIM: no memory for the rows of a %ux%u image", a->width, a->height);
        return -1;
    }
    double c1 = 0.01 * out->ssim_range, c2 = 0.03 * out->ssim_range;
    c1 *= c1;
    c2 *= c2;
    double sum = 0;
    for (int y = 0; y < (int)a->height; y++) {
        ssim_row(&s, a, ref, y);
        if (y >= LG_SSIM_WINDOW - 1)
            ssim_windows(&s, y - (LG_SSIM_WINDOW - 1), c1, c2, &sum, &out->ssim_windows,
                         &out->ssim_skipped);
    }
    free(s.block);
    if (out->ssim_windows)
        out->ssim = sum / (double)out->ssim_windows;
    return 0;
}

int lg_metrics_compute(const lg_image *a, const lg_image *ref, lg_metric_set *out, lg_image *heat,
                       double heat_max, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (lg_image_compare(a, ref, &out->base, heat, heat_max, err, errlen))
        return -1;
    out->ref_rms = reference_rms(a, ref);
    if (out->base.rmse == 0)
        out->rel_rmse = 0;
    else
        out->rel_rmse = out->ref_rms > 0 ? out->base.rmse / out->ref_rms : INFINITY;
    return lg_metric_ssim(a, ref, out, err, errlen);
}

double lg_metric_value(const lg_metric_set *m, lg_metric_id id)
{
    switch (id) {
    case LG_METRIC_RMSE: return m->base.rmse;
    case LG_METRIC_REL_RMSE: return m->rel_rmse;
    case LG_METRIC_MEAN_ABS: return m->base.mean_abs;
    case LG_METRIC_MAX_ABS: return m->base.max_abs;
    case LG_METRIC_REL_MSE: return m->base.rel_mse;
    case LG_METRIC_DSSIM: return 1.0 - m->ssim;
    default: return NAN;
    }
}
