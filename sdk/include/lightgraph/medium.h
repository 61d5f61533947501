/*
 * lightgraph/medium.h: the maths of a homogeneous participating medium, since ABI 2.4
 * (TECHNIQUES.md §6; seed 2, chapter 3). Every volumetric plugin and its GPU kernels use
 * these definitions; shaders/common/medium.glsl and shaders/common/medium.cl are their
 * line-by-line twins, and tests/unit/medium checks all three against each other.
 *
 * Units (the only ones in lightgraph):
 *   L_c      = light colour x intensity (glTF: lux for a directional light)
 *   sigma_s  = medium density x scattering   (1 / scene unit)       lg_medium_coeffs
 *   sigma_t  = sigma_s + density x absorption (1 / scene unit)
 *   L_v      = in-scattered radiance: L_c sigma_s p (length) for an unshadowed segment
 *              of the given length in a medium without extinction; nothing else scaled.
 *
 * Phase angle. For a view ray travelling along w (from the eye into the scene) and a light
 * whose light travels along l, the scattering angle theta has cos theta = dot(w, -l) =
 * dot(w, direction towards the light). g > 0 (forward scattering) therefore brightens the
 * view towards the light. (The thesis's engine uses dot(w, l) for directional lights:
 * that bug darkens the sun's halo and is not reproduced.)
 *
 * Henyey-Greenstein in the stable form:
 *
 *     p(g, c) = (1 - g)(1 + g) / (4 pi ((1 - g)^2 + 2 g (1 - c))^(3/2))
 *
 * which loses no digits as |g| -> 1 or c -> 1 (the textbook 1 + g^2 - 2gc cancels there).
 * p integrates to 1 over the sphere and its mean cosine is g. g is clamped to
 * [-LG_HG_G_MAX, LG_HG_G_MAX] so that |g| = 1 (a delta) gives large finite values, never
 * inf or NaN; c is clamped to [-1, 1].
 *
 * Segment factor. Along a segment of optical depth tau = sigma_t length, the scattering
 * integrated with the transmittance from the segment's start is
 *
 *     integral_0^length e^(-sigma_t s) ds = length (1 - e^(-tau)) / tau
 *
 * lg_medium_segment(tau) = (1 - e^(-tau)) / tau = -expm1(-tau) / tau, exactly 1 at tau = 0
 * and without cancellation for small tau (thin fog does not vanish). Negative tau is
 * treated as 0.
 *
 * Slice maps (froxel grids, lightgraph/froxel.h): slice coordinate z in [0, depth] <-> view
 * depth t in [near, far], monotonic, with exact inverses (round trips to a few ulp):
 *
 *   LG_FROXEL_UNIFORM_CLIP (the thesis, eq. 10): uniform in the clip depth of a perspective
 *     projection whose near and far planes are the grid's, i.e. 1/t is linear in z:
 *         t(z) = 1 / (1/near + (z / depth) (1/far - 1/near))
 *   LG_FROXEL_EXPONENTIAL (production engines): the first slice is linear from near to
 *     near_offset, the others exponential from near_offset to far:
 *         t(z) = near + z (near_offset - near)                       0 <= z <= 1
 *         t(z) = near_offset (far / near_offset)^((z - 1) / (depth - 1))   1 <= z <= depth
 *     (depth = 1: one linear slice from near to far.) near < near_offset < far.
 *
 * z outside [0, depth] and t outside [near, far] are extrapolated by the same formula
 * (callers clamp where they need); t <= 0 maps to z = 0 for uniform_clip.
 */
#ifndef LIGHTGRAPH_MEDIUM_H
#define LIGHTGRAPH_MEDIUM_H

#include <stdbool.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/froxel.h"
#include "lightgraph/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define LG_HG_G_MAX 0.999999

/* Henyey-Greenstein phase, 1/sr. cos_theta = dot(view ray direction, direction towards
 * the light). */
LG_API double lg_hg_phase(double g, double cos_theta);
/* The same in float, as the kernels compute it. */
LG_API float lg_hg_phasef(float g, float cos_theta);

/* (1 - e^(-tau)) / tau, 1 at tau <= 0. */
LG_API double lg_medium_segment(double tau);
LG_API float lg_medium_segmentf(float tau);

/* In-scattered radiance of an unshadowed homogeneous segment of `length` lit by a
 * directional light (one channel): L_c sigma_s p length segment(sigma_t length). The
 * closed form the reference and the energy-conserving froxel grid meet. */
LG_API double lg_medium_inscatter(double l_c, double sigma_s, double sigma_t, double phase,
                                  double length);

/* The medium's coefficients per channel (density applied). present false or density <= 0
 * gives zeros. */
LG_API void lg_medium_coeffs(const lg_medium *m, float sigma_s[3], float sigma_t[3]);

/* L_c of a light: colour x intensity. */
LG_API void lg_light_color(const lg_light *light, float l_c[3]);

/* A slice map. */
typedef struct lg_slice_map {
    lg_froxel_slicing slicing;
    uint32_t depth;     /* slices, >= 1 */
    double near, far;   /* 0 < near < far */
    double near_offset; /* exponential: near < near_offset < far */
} lg_slice_map;

/* Fills *map; returns 0, or -1 (map untouched) when the values break the rules above.
 * near_offset is ignored for uniform_clip. */
LG_API int lg_slice_map_init(lg_slice_map *map, lg_froxel_slicing slicing, uint32_t depth,
                             double near, double far, double near_offset);
/* Slice coordinate z (a real number; slice k spans [k, k+1]) -> view depth t. */
LG_API double lg_slice_to_depth(const lg_slice_map *map, double z);
/* View depth t -> slice coordinate z. */
LG_API double lg_depth_to_slice(const lg_slice_map *map, double t);
/* The map of a froxel info part. */
LG_API int lg_slice_map_from_info(lg_slice_map *map, const lg_froxel_info *info);

#ifdef __cplusplus
}
#endif
#endif
