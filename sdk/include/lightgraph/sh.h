/*
 * lightgraph/sh.h: real spherical harmonics (SH), since ABI 2.2: evaluation of any band
 * count, the clamped-cosine zonal coefficients, exact rotation of coefficient vectors and
 * windowing against ringing. docs/sh.md has the derivations, the measured accuracy and
 * cost. The SH coefficient resource (lightgraph/shcoeffs.h) and the per-vertex transfer
 * (lightgraph/transfer.h) use this basis.
 *
 * Conventions (the only ones in lightgraph):
 *   - n bands: l = 0 .. n-1, n^2 functions; function i = l (l + 1) + m, m in [-l, l].
 *   - World directions, y the world up axis as in every other file. The basis is the
 *     textbook real basis written in world x, y, z with its polar axis along +Z (the m = 0
 *     functions are symmetric about +Z), so that band 1 is exactly
 *       Y_1,-1 = +0.488603 y,   Y_1,0 = +0.488603 z,   Y_1,1 = +0.488603 x.
 *   - No Condon-Shortley phase: with rho^m (cos m phi, sin m phi) = (Re, Im) (x + i y)^m,
 *       Y_l,m  = sqrt(2) K_l^m P_l^m(z) cos(m phi)     m > 0
 *       Y_l,0  =         K_l^0 P_l^0(z)
 *       Y_l,-m = sqrt(2) K_l^m P_l^m(z) sin(m phi)     m > 0
 *     K_l^m = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!), P_l^m without the (-1)^m factor. Every
 *     Y is a polynomial in x, y, z: evaluation needs no trigonometry, poles included.
 *   - Orthonormal: the integral over the sphere of Y_i Y_j is 1 for i = j, 0 otherwise, so
 *     the coefficient of f is c_i = integral f Y_i, and f ~ sum_i c_i Y_i.
 *   - Irradiance from radiance coefficients L_lm: E(nrm) = sum A_l L_lm Y_lm(nrm)
 *     (Ramamoorthi and Hanrahan 2001), A_l from lg_sh_clamped_cosine.
 *
 * All functions are pure (no allocation, thread-safe) and take any n in 1 .. LG_SH_MAX_BANDS
 * (lightgraph/shcoeffs.h); out-of-range n is clamped to that range so that nothing is read
 * or written past n^2 values: callers pass valid counts.
 */
#ifndef LIGHTGRAPH_SH_H
#define LIGHTGRAPH_SH_H

#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/shcoeffs.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Index of Y_l,m: l (l + 1) + m. */
static inline uint32_t lg_sh_index(int l, int m)
{
    return (uint32_t)(l * (l + 1) + m);
}

/*
 * Evaluates Y_0 .. Y_{n^2-1} at direction dir into out[n^2]. dir need not be unit (it is
 * normalised); a zero vector, one with all components below 1e-30 in magnitude, or one
 * with a NaN or infinite component means -Z, the fallback of lightgraph/probe.h
 * (lg_probe_safe_dir). The values are always finite.
 *
 * By the normalised associated-Legendre recurrences (docs/sh.md): no factorial, no
 * trigonometry. Accuracy (tests/unit/sh, docs/sh.md): against a long double reference,
 * the double version to band 64 within 2e-14 of each band's scale sqrt((2l+1)/(4 pi)),
 * the float one to band 16 within 5e-6; the addition theorem holds to 1.1e-13 (double,
 * band 64) and 1.6e-5 (float, band 16) relative. The float version stays finite and
 * bounded at every band.
 */
LG_API void lg_sh_eval_f(uint32_t n, const float dir[3], float *out);
LG_API void lg_sh_eval_d(uint32_t n, const double dir[3], double *out);

/*
 * The clamped-cosine zonal coefficient A_l: the factor band l of a radiance expansion
 * takes in the irradiance, A_l = sqrt(4 pi / (2l + 1)) times the coefficient on Y_l,0 of
 * max(cos theta, 0) = 2 pi int_0^1 t P_l(t) dt (docs/sh.md):
 * A_0 = pi, A_1 = 2 pi / 3, A_l = 0 for odd l > 1, and for even l
 *   A_l = 2 pi (-1)^(l/2 - 1) / ((l + 2)(l - 1)) * l! / (2^l ((l/2)!)^2),
 * the last factor by its ratio recurrence (l+1)/(l+2), so any l is finite (it decays as
 * l^-2.5). pi, 2pi/3, pi/4, 0, -pi/24, 0, pi/64, ...
 */
LG_API double lg_sh_clamped_cosine(uint32_t l);

/*
 * Rotation. A rotation of n bands is a block-diagonal matrix: one (2l+1) x (2l+1) block
 * per band, stored one after the other, each row-major (rows and columns m = -l .. l);
 * lg_sh_rotation_size(n) doubles in all (n (2n - 1)(2n + 1) / 3: 10 for n = 2, 349,504
 * for 64). Caller-owned.
 *
 * R is a 3x3 rotation, row-major, acting on column vectors (world' = R world). The built
 * matrices rotate the function: the coefficients out of lg_sh_rotate(in) describe
 * g(w) = f(R^T w), i.e. a light at direction v moves to R v.
 *
 * Built by the Ivanic-Ruedenberg recurrences (J. Phys. Chem. 1996, 100, 6342, with the
 * erratum J. Phys. Chem. A 1998, 102, 9099), which are exact for any band count (to
 * rounding; the band-1 block is R itself in this basis's (y, z, x) order). R should be
 * orthonormal: a matrix accumulated from many small rotations drifts; re-orthonormalise
 * it (lg_sh_orthonormalize) and rebuild from the absolute orientation rather than
 * multiply SH matrices (tests/unit/sh `rotation_drift` shows both).
 * Returns 0, or -1 (nothing written) when R has a NaN or infinite element.
 */
static inline size_t lg_sh_rotation_size(uint32_t n)
{
    return (size_t)n * (2u * n - 1u) * (2u * n + 1u) / 3u;
}
LG_API int lg_sh_rotation_build(uint32_t n, const double R[9], double *matrices);
/* out = rotation applied to in, one channel of n^2 values; out may be in. */
LG_API void lg_sh_rotate(uint32_t n, const double *matrices, const double *in, double *out);
/* The same on `planes` planes of n^2 floats each (the layout of lightgraph/shcoeffs.h,
 * planes = 3 for RGB), accumulated in double; out may be in. */
LG_API void lg_sh_rotate_planes_f(uint32_t n, const double *matrices, uint32_t planes,
                                  const float *in, float *out);
/* Gram-Schmidt on R's rows (row 0, then 1, then 2 = 0 x 1): the nearest-in-practice
 * rotation to a drifted product of rotations. In place. */
LG_API void lg_sh_orthonormalize(double R[9]);

/*
 * Windowing against ringing (Sloan 2008, "Stupid Spherical Harmonics (SH) Tricks"): band l
 * multiplied by a factor w_l that falls with l, trading sharpness for less overshoot.
 *   LG_SH_WINDOW_HANNING   (1 + cos(pi l / width)) / 2 for l < width, else 0
 *   LG_SH_WINDOW_LANCZOS   sin(pi l / width) / (pi l / width) for l < width, else 0
 *   LG_SH_WINDOW_GAUSSIAN  exp(-l (l + 1) / (width (width + 1))): the spherical heat
 *                          kernel (diffusion on the sphere), e^-1 at l = width
 * width > 0 (width <= 0, NaN or infinite means no windowing: factor 1). Band 0 is never
 * changed. Measured on a delta light truncated to 3 bands (docs/sh.md, tests/unit/sh
 * `window`): its radiance's negative lobe (-0.1432 at cos theta = -0.2) shrinks to
 * -0.0239 with Hanning of width 3 and is gone with the Gaussian of width 1 (both the
 * radiance and the irradiance become non-negative).
 */
typedef enum lg_sh_window_kind {
    LG_SH_WINDOW_HANNING = 0,
    LG_SH_WINDOW_LANCZOS = 1,
    LG_SH_WINDOW_GAUSSIAN = 2,
} lg_sh_window_kind;
LG_API double lg_sh_window_factor(lg_sh_window_kind kind, double width, uint32_t l);
/* Multiplies band l of coeffs[n^2] (one channel) by lg_sh_window_factor(kind, width, l). */
LG_API void lg_sh_window(uint32_t n, lg_sh_window_kind kind, double width, double *coeffs);

#ifdef __cplusplus
}
#endif
#endif
