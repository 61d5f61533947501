/*
 * Reinhard tone mapping on the CPU: the code the `cpu` backend runs. Private to the
 * plugin (and its tests, which compile reinhard_cpu.c themselves and compare it with the
 * double-precision oracle, tests/plugins/reinhard/reinhard_oracle.c).
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
 *
 * Speed: the two passes are written for the compiler's vectoriser: fixed-size blocks of
 * pixels, no branch per pixel (the bad-pixel policy is selects), a float logarithm of our
 * own (libm's logf does not vectorise without -ffast-math, which this code must not use:
 * it would drop the NaN and Inf checks). The per-pixel logs are float; they are summed in
 * float over 8 lanes of at most LG_RH_BLOCK / 8 pixels, then in double, so a sum over
 * millions of pixels keeps about 1e-9 relative accuracy. The plugin threads them through
 * the host's pool (lg_parallel_for), one chunk of rows at a time.
 */
#ifndef LG_REINHARD_CPU_H
#define LG_REINHARD_CPU_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum lg_rh_mode { LG_RH_LUMINANCE = 0, LG_RH_RGB = 1 } lg_rh_mode;

typedef struct lg_rh_params {
    lg_rh_mode mode;
    float w[3];   /* luminance weights */
    double delta; /* log offset */
    double white; /* Lwhite in the scaled domain; 0 = off */
} lg_rh_params;

/* What the reduction finds. */
typedef struct lg_rh_stats {
    double log_sum;     /* sum of log(delta + L) over the valid pixels */
    uint64_t valid;     /* pixels in the average */
    uint64_t nonfinite; /* left out: an R, G or B channel NaN or Inf, or L not finite */
    uint64_t negative;  /* left out: finite, L < 0 */
} lg_rh_stats;

/* Pixels per block of the vectorised loops (a multiple of 8). */
#define LG_RH_BLOCK 64

/* Luminance of a pixel as every backend computes it: in float, in this order. */
static inline float lg_rh_luma(const float *px, const float w[3])
{
    return w[0] * px[0] + w[1] * px[1] + w[2] * px[2];
}

/* Adds `n` rgba32f pixels to `st` (which the caller zeroes first). The result depends on
 * the pixels and n only (no threads inside), so chunks reduced separately and added in a
 * fixed order give the same sum every time. */
void lg_rh_reduce(const float *rgba, size_t n, const lg_rh_params *p, lg_rh_stats *st);

/* Adds b to a (a += b), the sum first. */
void lg_rh_stats_add(lg_rh_stats *a, const lg_rh_stats *b);

/* Lavg from the stats; false (and *lavg untouched) when no pixel was valid. */
bool lg_rh_log_average(const lg_rh_stats *st, double *lavg);

/* One adaptation step (seed 0, 5.2): La + (Lavg - La) (1 - rate^(60 dt)). */
double lg_rh_adapt(double la, double lavg, double rate, double dt);

/* Maps `n` rgba32f pixels with scale s = a / Lavg, in float; in and out do not overlap. */
void lg_rh_map(const float *restrict in, float *restrict out, size_t n, float scale,
               const lg_rh_params *p);

/* The natural logarithm of a float x > 0 (finite, normal), to about 1 ulp; the form the
 * vectoriser accepts. Exposed for its test. */
float lg_rh_logf(float x);

/* ---- the passes over a whole image, threaded ------------------------------------------------- */

/* A parallel-for with lg_parallel_for's contract (lightgraph/host.h): the plugin passes
 * the host's; the tests and the benchmark pass pools of their own sizes. */
typedef int (*lg_rh_pfor)(void *pctx, size_t count, size_t grain,
                          void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk),
                          void *ctx);

/* An input image: rows of `width` pixels, `row_pixels` apart, rgba32f, rgba16f or rgbe8
 * (decoded into float blocks as the passes read them). */
typedef struct lg_rh_image {
    const void *pixels;
    size_t row_pixels;
    uint32_t width, height;
    bool half; /* rgba16f */
    bool rgbe; /* rgbe8 (lg_rgbe_decode; alpha 1) */
} lg_rh_image;

/* Pixels per chunk: enough work to be worth a hand-off to a thread, and hundreds of
 * chunks for a large image so that the threads finish together. Chunks are whole rows. */
#define LG_RH_CHUNK_PIXELS 16384u

/* Rows per chunk, and the chunks (= reduction slots) of an image: functions of the image
 * size only, so the log-average's rounding is the same whatever the thread count. */
size_t lg_rh_cpu_rows_per_chunk(uint32_t width);
size_t lg_rh_cpu_chunks(uint32_t width, uint32_t height);

/* Pass 1: the stats of the whole image into *total, through `slots`
 * (lg_rh_cpu_chunks() of them, scratch), combined in chunk order. Returns pfor's error. */
int lg_rh_cpu_reduce(const lg_rh_image *in, const lg_rh_params *p, lg_rh_stats *slots,
                     lg_rh_pfor pfor, void *pctx, lg_rh_stats *total);

/* Pass 2: maps the image into `out` (rgba32f rows `out_row_pixels` apart). */
int lg_rh_cpu_map(const lg_rh_image *in, float *out, size_t out_row_pixels, float scale,
                  const lg_rh_params *p, lg_rh_pfor pfor, void *pctx);

#endif
