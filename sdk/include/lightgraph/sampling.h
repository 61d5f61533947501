/*
 * lightgraph/sampling.h: point sets on the unit square and the sphere, and sums that stay
 * accurate over 10^8 terms (since ABI 2.3). The SH projection (`sh_project`), the PRT bake
 * (`prt_bake`) and their studies draw their directions here, so that "sampler = sobol"
 * means the same points everywhere.
 *
 * Point sets. A set of T = side * side points in [0, 1)^2, indexed k = 0 .. T-1. Every
 * point is a pure function of (sampler, side, seed, k): no state, no allocation, the same
 * bits on any thread count and in any order.
 *
 *   LG_SAMPLER_JITTERED    seed 0 §5.6: the square cut into side x side cells, one uniform
 *                          point in each. Point k lies in cell (k mod side, k / side):
 *                          u = (k mod side + xi_1) / side, v = (k / side + xi_2) / side,
 *                          with (xi_1, xi_2) from a counter-based hash of (seed, k). (The
 *                          seed's listing reuses its loop variable `i` in the inner loop and
 *                          indexes the sample array with the coefficient index: here the
 *                          sample index is k alone and the coefficients are another loop.)
 *   LG_SAMPLER_HAMMERSLEY  u = (k + 1/2) / T, v = the base-2 radical inverse of k. seed != 0
 *                          adds a random digital shift (an XOR of v's bits), which keeps the
 *                          set's structure and decorrelates two sets.
 *   LG_SAMPLER_SOBOL       the first two dimensions of Sobol's sequence (u = the radical
 *                          inverse of k, v from the direction numbers of the primitive
 *                          polynomial x + 1), 32-bit; the first 4^m points form a
 *                          (0, 2m, 2)-net, so side a power of two is the best case. seed != 0
 *                          adds a random digital shift to both dimensions.
 *
 * Sphere. lg_sample_sphere maps (u, v) to a direction uniformly (equal area, pdf 1 / (4 pi)):
 * z = cos theta = 1 - 2u, phi = 2 pi v; the seed's theta = 2 acos(sqrt(1 - u)) is the same
 * map (cos(2 acos s) = 2 s^2 - 1 = 1 - 2u), computed here without the acos so that the poles
 * lose no digits. A Monte Carlo estimate of the integral of f over the sphere is then
 * (4 pi / T) sum_k f(w_k).
 *
 * Sums. Adding 10^8 float terms in float loses everything past 2^24 (a float sum of ones
 * stops at 16777216). lg_sum accumulates in double with Neumaier's compensation (a
 * running correction for the digits each addition drops), so that the error does not
 * grow with the count; lg_sum_f sums an array of floats pairwise in double. Both depend
 * on IEEE evaluation order: never compile them with -ffast-math or -fassociative-math,
 * which remove the compensation (tests/unit/sampling `sum` would fail).
 */
#ifndef LIGHTGRAPH_SAMPLING_H
#define LIGHTGRAPH_SAMPLING_H

#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lg_sampler {
    LG_SAMPLER_JITTERED = 0,
    LG_SAMPLER_HAMMERSLEY = 1,
    LG_SAMPLER_SOBOL = 2,
} lg_sampler;

/* "jittered", "hammersley", "sobol"; NULL for another value. */
LG_API const char *lg_sampler_name(lg_sampler s);

/* Point k (0 <= k < side^2) of the set, into uv[2], both in [0, 1). side >= 1; k and
 * side outside the range are taken modulo (never out of bounds). */
LG_API void lg_sample_square(lg_sampler s, uint32_t side, uint64_t seed, uint64_t k, double uv[2]);

/* The uniform direction of (u, v) (see "Sphere"), unit length. */
LG_API void lg_sample_sphere(const double uv[2], double dir[3]);

/* A compensated sum: start from {0, 0}, add terms, read the total with lg_sum_value. */
typedef struct lg_sum {
    double s; /* running sum */
    double c; /* the low-order digits the additions to s dropped */
} lg_sum;

static inline void lg_sum_add(lg_sum *a, double x)
{
    double t = a->s + x;
    /* Neumaier: whichever operand is larger keeps its digits in t; recover the other's */
    if ((a->s < 0 ? -a->s : a->s) >= (x < 0 ? -x : x))
        a->c += (a->s - t) + x;
    else
        a->c += (x - t) + a->s;
    a->s = t;
}

/* Merges b into a (partial sums of two threads). */
static inline void lg_sum_merge(lg_sum *a, const lg_sum *b)
{
    lg_sum_add(a, b->s);
    a->c += b->c;
}

static inline double lg_sum_value(const lg_sum *a)
{
    return a->s + a->c;
}

/* The sum of x[0 .. n-1] in double, pairwise (blocks of 64 summed in order, then halves
 * added recursively): error O(log n) roundings of double. n = 0 gives 0. */
LG_API double lg_sum_f(const float *x, size_t n);

#ifdef __cplusplus
}
#endif
#endif
