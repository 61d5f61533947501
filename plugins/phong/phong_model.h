/*
 * phong_model.h: the Phong lighting equation in C, and vertex normals (the phong plugin's;
 * not part of the installed SDK, which keeps contracts and general helpers only).
 *
 * Built into the static library lg_phong_model (plugins/phong/meson.build), which the
 * plugin and its tests (tests/unit/phong, tests/plugins/phong) link: the tests hold the
 * plugin's own code to the GLSL twin, not a copy of it.
 *
 * The equation (seed 1 eq. 1-4, 1-8, 1-9..1-12; TECHNIQUES.md §1), per colour channel c:
 *
 *     I_c = Ia_c ka Od_c + sum over lights of att * shadow * Ii_c [ kd Od_c (N.L) + ks Os_c spec ]
 *
 *     spec = (R.V)^n          Phong, R = reflect(-L, N) = 2 (N.L) N - L
 *     spec = (N.H)^n'         Blinn, H = (L + V) / |L + V|, n' = n or LG_BLINN_CORRECTION * n
 *     att  = lg_depth_cue(r, K) = 1 / (r + K) (eq. 1-12) when depth cueing is on, else 1
 *
 * N is the unit surface normal, V the unit vector from the point to the viewer, L the unit
 * vector from the point to the light, r the distance from the point to the viewer.
 *
 * The same functions, with the same names and the same policies, exist in GLSL 4.50 in
 * shaders/common/phong.glsl (`#include "phong.glsl"`, resolved by tools/embed.py at build
 * time); tests/unit/phong/ evaluates both on the same inputs and holds them to within a
 * stated tolerance. Change one, change the other.
 *
 * Every lighting function here is total: it returns finite values for every input, finite
 * or not. The policy for each degenerate input is written next to the function and tested
 * by name in tests/unit/phong/ (docs/phong-hard-cases.md collects them):
 *
 *   zero, denormal, NaN or Inf vector   lg_safe_normalize returns the caller's fallback
 *   huge finite vector                  rescaled by a power of two before squaring
 *   pow(0, 0), shininess 0              lg_spec_pow(x <= 0, n) = 0; lg_spec_pow(x > 0, 0) = 1
 *   R.V < 0, N.H < 0                    clamped to 0: no highlight
 *   N.L <= 0                            no diffuse and no specular
 *   L = -V with Blinn                   H does not exist: no highlight (spec = 0)
 *   back-facing N (N.V < 0)             lit as given, never flipped (see lg_phong_direct)
 *   r + K <= 1 in depth cueing          att = 1 (depth cueing only attenuates)
 *   non-finite intensity or material    the channel that comes out non-finite is 0
 *
 * Vertex normals: lg_vertex_normals_eq13() is seed 1 eq. 1-13 (the normalised sum of the
 * adjacent facets' unit normals) and lg_vertex_normals_crease() the remedy for its false
 * smoothing (seed 1 fig. 1.27): facets meeting at a crease sharper than a given angle do not
 * share a normal.
 */
#ifndef LG_PHONG_MODEL_H
#define LG_PHONG_MODEL_H

#include <float.h>
#include <stdint.h>
#include <string.h>

#include "lightgraph/vecmath.h"
#include "lightgraph/types.h"

/* A material of the reflection model. Coefficients are scalars, colours RGB in linear
 * radiance units; n is the shininess (1 .. several hundred; larger is a smaller highlight). */
typedef struct lg_phong_material {
    float ka, kd, ks, n;
    float od[3]; /* object (diffuse) colour Od */
    float os[3]; /* specular colour Os */
} lg_phong_material;

/* The specular model of lg_phong_direct(); any other value counts as LG_SPEC_PHONG. */
enum { LG_SPEC_PHONG = 0, LG_SPEC_BLINN = 1 };

/* Blinn's exponent correction: with H halfway between L and V, the angle between N and H
 * is half the angle between R and V (seed 1, fig. 1.14: theta = 2 psi), and
 * cos^n'(theta/2) ~ cos^n(theta) near the highlight for n' = 4 n. Pass
 * n_eff = LG_BLINN_CORRECTION * n to lg_phong_direct() to make Blinn's highlight match
 * Phong's; pass n_eff = n for the uncorrected model (a larger highlight). */
#define LG_BLINN_CORRECTION 4.0f

/* Blinn: below this |L + V|^2 (the angle between L and -V under ~1e-3 rad) the halfway
 * vector is not defined to float precision and the highlight is 0. */
#define LG_BLINN_MIN_HALFWAY2 1e-6f

/* The normal lg_vertex_normals_eq13() gives a vertex without any usable facet: +Z, as the
 * scene loader's computed normals (plugins/scene_gltf). */
#define LG_PHONG_NORMAL_FALLBACK_X 0.0f
#define LG_PHONG_NORMAL_FALLBACK_Y 0.0f
#define LG_PHONG_NORMAL_FALLBACK_Z 1.0f

/* True when x is neither NaN nor infinite. Tests the exponent bits, as the GLSL does, so
 * that a compiler's fast-math assumptions cannot remove it. */
static inline int lg_phong_isfinite(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return (u & 0x7f800000u) != 0x7f800000u;
}

/* x, or 0 when x is NaN or infinite. */
static inline float lg_phong_finite_or_zero(float x)
{
    return lg_phong_isfinite(x) ? x : 0.0f;
}

/*
 * The unit vector along v, or `fallback` when v has no direction.
 *
 * Policy:
 * - v with a NaN or infinite component, or with every component below FLT_MIN in magnitude
 *   (zero and denormal vectors: GPUs flush denormals to zero, so they have no direction
 *   there either), returns `fallback` unchanged (not normalised); a fallback with a NaN or
 *   infinite component is replaced by (0, 0, 0).
 * - Huge finite v (largest component above 2^60) is scaled by 2^-100, and tiny v (largest
 *   component below 2^-60) by 2^100, before its length is taken: exact scalings that keep
 *   the squared length away from overflow and underflow. Any other v is normalised as is.
 * The result of a non-fallback path is unit to float precision.
 */
static inline lg_vec3 lg_safe_normalize(lg_vec3 v, lg_vec3 fallback)
{
    if (!lg_phong_isfinite(fallback.x) || !lg_phong_isfinite(fallback.y) ||
        !lg_phong_isfinite(fallback.z))
        fallback = lg_v3(0.0f, 0.0f, 0.0f);
    if (!lg_phong_isfinite(v.x) || !lg_phong_isfinite(v.y) || !lg_phong_isfinite(v.z))
        return fallback;
    float m = fmaxf(fabsf(v.x), fmaxf(fabsf(v.y), fabsf(v.z)));
    if (!(m >= FLT_MIN))
        return fallback;
    if (m > 1.152921504606846976e18f)                /* 2^60 */
        v = lg_v3_scale(v, 7.8886090522101181e-31f); /* 2^-100 */
    else if (m < 8.6736173798840355e-19f)            /* 2^-60 */
        v = lg_v3_scale(v, 1.2676506002282294e30f);  /* 2^100 */
    return lg_v3_scale(v, 1.0f / sqrtf(lg_v3_dot(v, v)));
}

/*
 * The specular power x^n for x a cosine (R.V or N.H) and n the shininess.
 *
 * Policy:
 * - x <= 0, x below FLT_MIN (a denormal: zero on GPUs) and NaN x give 0: no highlight,
 *   whatever n. In particular pow(0, 0) = 0, so that "R.V <= 0 means no specular" holds
 *   for every n.
 * - x >= 1 (x > 1: rounding, or non-unit vectors; +Inf) gives 1 for every n, exactly
 *   (GLSL's pow(1, n) = exp2(n log2 1) may be off by 2^-21 n, since log2 may be off by
 *   2^-21 near 1).
 * - n is clamped to [0, FLT_MAX]; NaN and negative n count as 0, +Inf as FLT_MAX.
 * - n = 0 gives 1 for every x > 0 (the limit of x^n as n -> 0): a constant highlight over
 *   the hemisphere where the cosine is positive.
 * - n = FLT_MAX is a mirror: 1 for x = 1, 0 for x < 1.
 * The result is in [0, 1].
 */
static inline float lg_spec_pow(float x, float n)
{
    if (!(x >= FLT_MIN))
        return 0.0f;
    if (x >= 1.0f)
        return 1.0f;
    if (!(n > 0.0f))
        return 1.0f;
    if (n > FLT_MAX)
        n = FLT_MAX;
    return fminf(powf(x, n), 1.0f); /* as the GLSL, whose pow may round above 1 */
}

/* The ambient term Ia ka Od (eq. 1-4); a channel that comes out NaN or infinite is 0. */
static inline lg_vec3 lg_phong_ambient(lg_vec3 Ia, const lg_phong_material *m)
{
    return lg_v3(lg_phong_finite_or_zero(Ia.x * m->ka * m->od[0]),
                 lg_phong_finite_or_zero(Ia.y * m->ka * m->od[1]),
                 lg_phong_finite_or_zero(Ia.z * m->ka * m->od[2]));
}

/*
 * One light's diffuse and specular terms, Ii [ kd Od (N.L) + ks Os spec ]: no ambient, no
 * attenuation, no shadow (the caller multiplies by lg_depth_cue() and its shadow test).
 *
 * N, V, L are unit vectors (lg_safe_normalize); V points from the point to the viewer, L
 * from the point to the light. spec_model is LG_SPEC_PHONG or LG_SPEC_BLINN; n_eff is the
 * exponent used: m->n is not read, so that the caller chooses Blinn's correction
 * (LG_BLINN_CORRECTION).
 *
 * Policy:
 * - N.L <= 0 or NaN: the light is behind the surface; the result is 0, specular included.
 *   N.L is clamped to at most 1.
 * - Phong: R = 2 (N.L) N - L; R.V < 0 gives no highlight (lg_spec_pow of a clamped cosine).
 * - Blinn: when |L + V|^2 < LG_BLINN_MIN_HALFWAY2 (L = -V: the light straight behind the
 *   point as seen from the viewer) H does not exist; the limit of N.H depends on the
 *   direction L approaches -V from, so no value is right, and the highlight is 0 (H is taken
 *   as the zero vector, and lg_spec_pow(0, n) = 0 even for n = 0).
 * - Back-facing N (N.V < 0) is lit as given, never flipped: interpolated normals
 *   legitimately face away from the viewer near silhouettes, and flipping them there would
 *   light the rim from the wrong side. A double-sided surface seen from behind is the
 *   caller's business: flip N by the facet's orientation (gl_FrontFacing), not by N.V.
 * - Vectors that are not unit give the formula's value for them with the cosines clamped
 *   to [0, 1]; NaN cosines count as 0.
 * - A channel of the result that is NaN or infinite (non-finite or overflowing Ii, kd, ks,
 *   Od, Os) is 0.
 */
static inline lg_vec3 lg_phong_direct(lg_vec3 N, lg_vec3 V, lg_vec3 L, lg_vec3 Ii,
                                      const lg_phong_material *m, int spec_model, float n_eff)
{
    float ndl = lg_v3_dot(N, L);
    if (!(ndl > 0.0f))
        return lg_v3(0.0f, 0.0f, 0.0f);
    float cosine;
    if (spec_model == LG_SPEC_BLINN) {
        lg_vec3 h = lg_v3_add(L, V);
        float h2 = lg_v3_dot(h, h);
        cosine = h2 >= LG_BLINN_MIN_HALFWAY2 ? lg_v3_dot(N, lg_v3_scale(h, 1.0f / sqrtf(h2)))
                                             : 0.0f;
    } else {
        lg_vec3 r = lg_v3_sub(lg_v3_scale(N, 2.0f * ndl), L);
        cosine = lg_v3_dot(r, V);
    }
    float spec = lg_spec_pow(cosine, n_eff);
    if (ndl > 1.0f)
        ndl = 1.0f;
    float d = m->kd * ndl, s = m->ks * spec;
    return lg_v3(lg_phong_finite_or_zero(Ii.x * (d * m->od[0] + s * m->os[0])),
                 lg_phong_finite_or_zero(Ii.y * (d * m->od[1] + s * m->os[1])),
                 lg_phong_finite_or_zero(Ii.z * (d * m->od[2] + s * m->os[2])));
}

/*
 * Depth cueing (eq. 1-12): the factor 1 / (r + K) for the light terms, r the distance from
 * the point to the viewer and K the user's constant.
 *
 * Policy: depth cueing attenuates, it never amplifies: when r + K <= 1 (including r = 0
 * with K = 0, where 1 / (r + K) does not exist) the factor is 1, so the result is
 * 1 / max(r + K, 1), continuous, in [0, 1]. r + K = +Inf gives 0; NaN r + K gives 1 (no
 * attenuation). Choose K >= 1 to have eq. 1-12 exactly at every distance.
 */
static inline float lg_depth_cue(float r, float K)
{
    float d = r + K;
    return d > 1.0f ? 1.0f / d : 1.0f;
}

/*
 * Vertex normals by seed 1 eq. 1-13: each vertex's normal is the normalised sum of the
 * unit normals of the triangles that use it (not weighted by area or angle).
 *
 *   pos          nv vertex positions, xyz
 *   idx, ni      ni indices, three per counter-clockwise triangle (front face: the normal
 *                is (p1 - p0) x (p2 - p0)); trailing indices beyond a multiple of 3 are
 *                ignored
 *   out_normals  nv normals, xyz, written for every vertex
 *
 * Policy:
 * - A triangle contributes nothing when it is degenerate: twice its area below 1e-6 times
 *   its longest edge squared (zero area, a repeated vertex, collinear corners, angles under
 *   about 1e-6 rad), a non-finite position, or an index >= nv.
 * - A vertex whose usable facets' normals cancel (|sum| < 1e-4, e.g. the two sides of a
 *   sheet) takes the normal of its first usable facet in index order.
 * - A vertex with no usable facet (unreferenced, or only degenerate triangles) takes
 *   (LG_PHONG_NORMAL_FALLBACK_X, _Y, _Z) = +Z. No output is ever NaN or zero.
 * Returns LG_OK, or LG_ERR_INVALID when an index is >= nv or ni is not a multiple of 3
 * (out_normals is still written, without those triangles), or when a pointer is NULL
 * with a non-zero count (nothing written).
 *
 * False smoothing (seed 1 fig. 1.27): on a corrugated surface whose facets alternate
 * symmetrically (a zigzag), the facet normals around every vertex cancel in pairs and all
 * vertex normals come out parallel, so Gouraud and Phong shading draw the corrugation as
 * a flat plane. lg_vertex_normals_crease() is the remedy.
 */
int lg_vertex_normals_eq13(const float *pos, uint32_t nv, const uint32_t *idx, uint32_t ni,
                           float *out_normals);

/*
 * Vertex normals with creases: eq. 1-13 restricted, per triangle corner, to the facets
 * around the vertex whose normal is within `crease_angle` (radians) of the corner's own
 * facet normal; a vertex whose corners get different normals is split into one output
 * vertex per distinct normal. This is the remedy for the false smoothing of seed 1
 * fig. 1.27: across a crease sharper than crease_angle the facets keep their own
 * normals, and the shading shows the crease. crease_angle >= pi gives eq. 1-13 (no split);
 * crease_angle = 0 gives flat shading (every facet its own normal); NaN counts as 0.
 * Facets count as within the angle when cos(angle between them) >= cos(crease_angle) - 1e-6.
 *
 *   pos, nv, idx, ni  as lg_vertex_normals_eq13() (ni a multiple of 3)
 *   out_idx           ni indices into the output vertices, the triangles of idx in order
 *   out_src           per output vertex, the input vertex it copies (at most ni entries):
 *                     copy positions and other attributes through it
 *   out_normals       per output vertex, its unit normal (at most 3 * ni floats)
 *   *out_nv           the number of output vertices (<= ni); input vertices that no
 *                     triangle uses are dropped
 *
 * Vertices are matched by index, not by position: weld vertices that repeat a position
 * first. A degenerate triangle's corners (see lg_vertex_normals_eq13) take their vertex's
 * eq. 1-13 normal. Output vertices are numbered in the order of input vertex, then of
 * first corner, so the result is deterministic. Around a vertex used by more than 128
 * triangles, corners are grouped (each joins the first of at most 64 groups whose first
 * facet is within the angle, or the closest group) and take their group's normalised sum,
 * which keeps the cost linear.
 *
 * Returns LG_OK; LG_ERR_INVALID (with *out_nv = 0) for an index >= nv, ni not a multiple
 * of 3 or a NULL pointer; LG_ERR_NOMEM when temporary memory cannot be allocated.
 */
int lg_vertex_normals_crease(const float *pos, uint32_t nv, const uint32_t *idx, uint32_t ni,
                             float crease_angle, uint32_t *out_idx, uint32_t *out_src,
                             float *out_normals, uint32_t *out_nv);

#endif
