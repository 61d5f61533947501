/* The error metrics that diff, sweep and tune share (metric.h). */
#include "cli/metric.h"

#include <math.h>
#include <stdio.h>
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
    out->ssim = NAN; /* metric.c's SSIM: issue 23, part "metric" */
    return 0;
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
