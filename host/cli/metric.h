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
 *   dssim     1 - ssim, where ssim is the mean SSIM (below)
 *
 * SSIM: Wang, Bovik, Sheikh, Simoncelli, "Image quality assessment: from error visibility to
 * structural similarity", IEEE Transactions on Image Processing 13(4), 2004, as the paper
 * defines it (its equation 13 with the Gaussian window of its section III-B):
 *
 *   - on the luminance Y = 0.2126 R + 0.7152 G + 0.0722 B of the linear values (BT.709);
 *   - in 11x11 windows weighted by a circular-symmetric Gaussian of sigma 1.5 pixels,
 *     normalised to sum 1 (separable: an 11-tap 1-D Gaussian along x, then along y);
 *   - SSIM(x, y) = (2 mu_a mu_b + C1)(2 sigma_ab + C2) / ((mu_a^2 + mu_b^2 + C1)
 *     (sigma_a^2 + sigma_b^2 + C2)), the moments weighted by the window (the sigmas are the
 *     population ones, no n / (n - 1)), C1 = (0.01 L)^2, C2 = (0.03 L)^2;
 *   - the mean over every window that lies fully inside the image ("valid": (W - 10) x
 *     (H - 10) windows, no padding at the borders).
 *
 * L, the dynamic range, is the paper's "range of the pixel values" (255 for 8-bit images).
 * Our images are linear HDR with no fixed range, so L is the reference's: its largest finite
 * luminance, at least LG_SSIM_MIN_RANGE. From the reference alone, so that every run of a
 * sweep is judged on the same scale whatever it renders; the floor keeps C1 and C2 above 0,
 * so that a black reference against a black image gives 1 rather than 0 / 0, and against a
 * flat image of luminance y gives C1 / (y^2 + C1): 0.5 at y = 1e-5, 0.01 at 1e-4. The cost
 * of the choice: one very bright pixel (a sun in a probe) raises C1 and C2 for the whole
 * image, and differences in the dark parts then weigh less; compare with a reference cropped
 * or scaled to what matters when that hurts.
 *
 * Non-finite pixels (NaN or Inf in R, G or B of either image) are left out by leaving out
 * every window that holds one; those windows are counted in ssim_skipped. Images smaller
 * than the window (width or height under 11) have no window, and when every window is
 * skipped there is none either: then ssim is NaN, ssim_windows 0, and a caller that needs
 * the SSIM reports it as an error (the other metrics are still computed).
 *
 * "Error" in sweep and tune is one of these, chosen by name (--metric). */
#ifndef LG_CLI_METRIC_H
#define LG_CLI_METRIC_H

#include <stddef.h>
#include <stdint.h>

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
        base;          /* lg_image_compare's: rmse, psnr, mean_abs, max_abs, rel_mse, nonfinite */
    double ref_rms;    /* sqrt(mean b^2) over the compared pixels and RGB */
    double rel_rmse;   /* base.rmse / ref_rms (0 / 0 = 0, x / 0 = +Inf) */
    double ssim;       /* mean SSIM of the luminance, in [-1, 1]; 1 for identical images; NaN
                        when no window was compared (ssim_windows 0) */
    double ssim_range; /* L: the reference's largest finite luminance, floored */
    uint64_t ssim_windows; /* the windows averaged into ssim */
    uint64_t ssim_skipped; /* the windows left out for holding a non-finite pixel */
} lg_metric_set;

/* The SSIM's window: LG_SSIM_WINDOW x LG_SSIM_WINDOW pixels, Gaussian of sigma LG_SSIM_SIGMA. */
#define LG_SSIM_WINDOW 11
#define LG_SSIM_SIGMA 1.5
/* The least dynamic range L (a black reference's), in the images' linear units. */
#define LG_SSIM_MIN_RANGE 1e-3

/* The metric called `name` ("rmse", "rel_rmse", ...). Returns 0, or -1 for an unknown name. */
int lg_metric_parse(const char *name, lg_metric_id *out);
/* The name of a metric; "?" for an id out of range. */
const char *lg_metric_name(lg_metric_id id);
/* Every metric's name, comma separated, for usage and error messages (a static string). */
const char *lg_metric_names(void);

/* The mean SSIM of A against the reference REF (same size), as described above, into
 * out->ssim, ssim_range, ssim_windows and ssim_skipped; the other fields are left alone.
 * Returns 0, or -1 with the reason in err (sizes that differ, no memory). */
int lg_metric_ssim(const lg_image *a, const lg_image *ref, lg_metric_set *out, char *err,
                   size_t errlen);

/* Computes every metric of A against the reference REF. With `heat` not NULL it is filled
 * (allocated; the caller frees it with lg_image_free) as lg_image_compare's heat map with
 * white at heat_max (<= 0: the largest error). Returns 0, or -1 with the reason in err
 * (sizes that differ, no memory). */
int lg_metrics_compute(const lg_image *a, const lg_image *ref, lg_metric_set *out, lg_image *heat,
                       double heat_max, char *err, size_t errlen);

/* The value of one metric in a computed set (an error: smaller is better, dssim included). */
double lg_metric_value(const lg_metric_set *m, lg_metric_id id);

#endif
