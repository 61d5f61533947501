/* The error metrics that diff, sweep and tune share: one definition of each, so a number in a
 * sweep's CSV, in diff's JSON and in tune's answer means the same thing.
 *
 * All of them compare an image A with a reference B of the same size, over R, G and B, on the
 * pixels finite in both (lg_image_compare's rule; the count of the others is `nonfinite`):
 *
 *   rmse      sqrt(mean (a - b)^2)
 *   rel_rmse  rmse / sqrt(mean b^2): the error as a fraction of the reference's RMS; 0 when A
 *             equals B, +Inf when B is black and A is not
 *   mean_abs  mean |a - b|          max_abs   max |a - b|
 *   rel_mse   mean (a - b)^2 / (b^2 + 1e-4)
 *   dssim     1 - SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) on luminance: see metric.c
 *
 * "Error" in sweep and tune is one of these, chosen by name (--metric). */
#ifndef LG_CLI_METRIC_H
#define LG_CLI_METRIC_H

#include <stddef.h>

#include "lightgraph/image.h"

typedef enum lg_metric_id {
    LG_METRIC_RMSE = 0,
    LG_METRIC_REL_RMSE,
    LG_METRIC_MEAN_ABS,
    LG_METRIC_MAX_ABS,
    LG_METRIC_REL_MSE,
    LG_METRIC_DSSIM,
    LG_METRIC_COUNT
} lg_metric_id;

typedef struct lg_metric_set {
    lg_image_metrics
        base;        /* lg_image_compare's: rmse, psnr, mean_abs, max_abs, rel_mse, nonfinite */
    double ref_rms;  /* sqrt(mean b^2) over the compared pixels and RGB */
    double rel_rmse; /* base.rmse / ref_rms (0 / 0 = 0, x / 0 = +Inf) */
    double ssim;     /* mean SSIM of the luminance, in [-1, 1]; 1 for identical images */
} lg_metric_set;

/* The metric called `name` ("rmse", "rel_rmse", ...). Returns 0, or -1 for an unknown name. */
int lg_metric_parse(const char *name, lg_metric_id *out);
/* The name of a metric; "?" for an id out of range. */
const char *lg_metric_name(lg_metric_id id);
/* Every metric's name, comma separated, for usage and error messages (a static string). */
const char *lg_metric_names(void);

/* Computes every metric of A against the reference REF. With `heat` not NULL it is filled
 * (allocated; the caller frees it with lg_image_free) as lg_image_compare's heat map with
 * white at heat_max (<= 0: the largest error). Returns 0, or -1 with the reason in err
 * (sizes that differ, no memory). */
int lg_metrics_compute(const lg_image *a, const lg_image *ref, lg_metric_set *out, lg_image *heat,
                       double heat_max, char *err, size_t errlen);

/* The value of one metric in a computed set (an error: smaller is better, dssim included). */
double lg_metric_value(const lg_metric_set *m, lg_metric_id id);

#endif
