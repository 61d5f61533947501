/*
 * Reinhard tone mapping on the CPU: the reference the GL and CL backends are tested
 * against, and the code the `cpu` backend runs. Private to the plugin (and its tests,
 * which compile reinhard_cpu.c themselves).
 *
 * The equations (README.md has their sources):
 *   Lavg = exp( (1/N) sum log(delta + L) )           over the valid pixels
 *   s    = a / Lavg    (or a / La with adaptation)
 *   x    = s L          (mode luminance)   or   s c per channel (mode rgb)
 *   Ld   = x / (1 + x)                                     white off
 *   Ld   = min(1, x (1 + x / Lwhite^2) / (1 + x))          white on
 *   out  = c Ld / L     (mode luminance)   or   Ld per channel (mode rgb)
 *
 * Bad pixels: a pixel whose R, G or B is NaN or +-Inf, or whose luminance is negative or
 * not finite, is left out of Lavg and counted. On output every channel is sanitised first:
 * NaN -> 0, negative (and -Inf) -> 0; a +Inf channel maps to 1 (the limit of x/(1+x)) and,
 * in luminance mode, the finite channels of such a pixel map to 0 (the limit of c Ld / L
 * as L -> Inf). Alpha passes through untouched.
 */
#ifndef LG_REINHARD_CPU_H
#define LG_REINHARD_CPU_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum lg_rh_mode { LG_RH_LUMINANCE = 0, LG_RH_RGB = 1 } lg_rh_mode;

typedef struct lg_rh_params {
    lg_rh_mode mode;
    float w[3];     /* luminance weights */
    double delta;   /* log offset */
    double white;   /* Lwhite in the scaled domain; 0 = off */
} lg_rh_params;

/* What the reduction finds. */
typedef struct lg_rh_stats {
    double log_sum;      /* sum of log(delta + L) over the valid pixels */
    uint64_t valid;      /* pixels in the average */
    uint64_t nonfinite;  /* left out: an R, G or B channel NaN or Inf, or L not finite */
    uint64_t negative;   /* left out: finite, L < 0 */
} lg_rh_stats;

/* Luminance of a pixel as every backend computes it: in float, in this order. */
static inline float lg_rh_luma(const float *px, const float w[3])
{
    return w[0] * px[0] + w[1] * px[1] + w[2] * px[2];
}

/* Adds `n` rgba32f pixels to `st` (which the caller zeroes first). */
void lg_rh_reduce(const float *rgba, size_t n, const lg_rh_params *p, lg_rh_stats *st);

/* Lavg from the stats; false (and *lavg untouched) when no pixel was valid. */
bool lg_rh_log_average(const lg_rh_stats *st, double *lavg);

/* One adaptation step (seed 0, 5.2): La + (Lavg - La) (1 - rate^(60 dt)). */
double lg_rh_adapt(double la, double lavg, double rate, double dt);

/* Maps `n` rgba32f pixels with scale s = a / Lavg (in may equal out). */
void lg_rh_map(const float *in, float *out, size_t n, double scale, const lg_rh_params *p);

/* The tone curve on a scaled value x >= 0 (+Inf allowed): x/(1+x), or the white-point
 * variant clamped to 1. inv_white2 = 1/Lwhite^2, 0 when white is off. */
double lg_rh_curve(double x, double inv_white2);

#endif
