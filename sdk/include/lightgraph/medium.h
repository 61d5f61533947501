/*
 * lightgraph/medium.h: the maths of a participating medium, since ABI 2.4 (density fields,
 * point and spot lights since 3.2)
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

/* ---- Density fields (since ABI 3.2; lightgraph/scene.h, "Density fields") -------------------- */

/* Improved Perlin gradient noise (Perlin 2002: quintic fade, the 12 edge-midpoint
 * gradients), each lattice point's gradient picked by an integer hash of (i, j, k, seed)
 * instead of a permutation table (no table to keep; any seed). In [-1, 1] (the largest
 * magnitude of this gradient set is below 1), 0 at integer points. */
LG_API double lg_noise3(double x, double y, double z, uint32_t seed);
/* sum_{o < octaves} gain^o lg_noise3(frequency lacunarity^o p, seed + o) (the fBm sum of
 * lightgraph/scene.h before offset and scale). */
LG_API double lg_fbm3(const lg_density_fbm *f, const double p[3]);

/* The density multiplier m(p) of the medium at world point p: 1 for a homogeneous medium
 * (field NULL), else inside(p) f(p) h(p). Never negative; 0 for a point that is not
 * finite. */
LG_API double lg_medium_field_at(const lg_medium *m, const double p[3]);
/* An upper bound of m over the box [lo, hi] (a majorant for delta tracking): 1 without a
 * field; the grid's max_value or the fBm's scale (sum gain^o - offset) times h's largest
 * value over the box (at its lowest y), 0 when the box misses bounds. */
LG_API double lg_medium_field_max(const lg_medium *m, const double lo[3], const double hi[3]);
/* True when the medium has a density field (m is not 1 everywhere). */
LG_API bool lg_medium_is_heterogeneous(const lg_medium *m);

/* ---- Point and spot lights in a medium (since ABI 3.2) --------------------------------------- */
/*
 * A point or spot light of intensity I (candela, glTF) at position q lights a point p at
 * distance d = |q - p| with irradiance-like factor
 *
 *     E(p) = L_c F(p),   F(p) = W(d) C(p) / (d^2 + LG_LIGHT_EPSILON^2)
 *
 *   W(d) = clamp(1 - (d / range)^4, 0, 1)   the range window KHR_lights_punctual
 *                                            recommends; 1 for range 0 (infinite)
 *   C(p) = 1 (point); for a spot travelling along s with cone angles inner <= outer,
 *          t = clamp((dot(-l, s) - cos(outer)) / max(cos(inner) - cos(outer), 1e-4), 0, 1),
 *          C = t^2 (KHR_lights_punctual's smooth falloff), l the unit vector from p to q.
 *
 * LG_LIGHT_EPSILON (1 mm in metre scenes) keeps F finite at the light itself (a point light
 * is a bulb of that size as seen from the medium; 1e-6 relative change at 1 m): the camera
 * at the light, or a ray through it, gives large finite values, never inf or NaN. In a
 * medium, the light reaching p is further attenuated by e^(-sigma_t d) (homogeneous) or
 * e^(-integral sigma_t) along p -> q (heterogeneous); a directional light is not (the
 * medium's boundary towards an infinitely distant light is not modelled).
 */
#define LG_LIGHT_EPSILON 1e-3

/* W(d) above. */
LG_API double lg_light_window(double d, double range);
/* C above from cos_angle = dot(-l, s) (the angle between the spot's axis and the direction
 * from the light to p) and the cone's cosines. cos_inner < cos_outer is treated as equal
 * (a hard edge). */
LG_API double lg_spot_cone(double cos_angle, double cos_inner, double cos_outer);
/* F(p) of light `l` (any type): directional 1 with to_light = -direction, *dist = INFINITY;
 * point and spot: W C / (d^2 + eps^2), to_light = unit vector p -> q (the spot's axis
 * reversed when p = q), *dist = d. to_light and dist may be NULL. */
LG_API double lg_light_falloff(const lg_light *l, const double p[3], double to_light[3],
                               double *dist);

/* The in-scattering of one point or spot light along a view-ray segment, per unit L_c and
 * unit sigma_s, unshadowed, in a homogeneous medium (the airlight integral, Sun et al.
 * 2005):
 *
 *     A = integral_{t0}^{t1} p_HG(g, dot(w, l(t))) F(x(t)) e^(-sigma_t (t - t0)) e^(-sigma_t d(t)) dt
 *
 * x(t) = o + t w (w unit), d(t) = |q - x(t)|. With t = t_c + H tan(xi) (t_c = dot(q - o, w),
 * h the distance from q to the ray's line, H = sqrt(h^2 + eps^2)), dt / (d^2 + eps^2) =
 * dxi / H and the integrand in xi is smooth and bounded: A is evaluated by Gauss-Legendre
 * quadrature with `nodes` points (1 .. 64, in panels of at most 8) over [xi(ta), xi(tb)],
 * [ta, tb] the part of [t0, t1] the light reaches (within `range` of q, inside a spot's
 * outer cone when cos_outer >= 0), where the integrand has no kink but the inner cone's.
 * For an isotropic phase (g = 0), sigma_t = 0, a point light and an infinite range the
 * integrand is constant and A = (xi1 - xi0) / (4 pi H) exactly at any node count: Sun et
 * al.'s closed form without extinction. t1 <= t0 gives 0. `spot` NULL for a point light,
 * else {axis x, y, z, cos_inner, cos_outer} (the axis unit, the direction light travels). */
LG_API double lg_point_inscatter(const double o[3], const double w[3], double t0, double t1,
                                 const double q[3], double range, const double *spot, double g,
                                 double sigma_t, int nodes);

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
