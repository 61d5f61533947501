/*
 * ggx_prefilter.h: the ibl plugin's glossy prefiltering of light probes (GGX), the
 * split-sum DFG table, and a Monte Carlo oracle of the glossy integral.
 *
 * Technique code, not the SDK's: it was lightgraph/probe_filter.h from ABI 2.2 to 2.5 and
 * left the installed SDK in 2.6 (docs/sdk.md changelog), as the Phong equation left it in
 * 2.0. It is built into a static library (plugins/ibl/meson.build) that the plugin, its
 * tests and tools/prefilter_study link, so that they all check the code the plugin runs.
 * The contract a consumer of a chain needs (LG_PROBE_FILTER_GGX, level l of L is
 * roughness l / (L - 1)) stays in lightgraph/probe.h.
 *
 * A rough surface reflects the environment convolved with its BRDF lobe. Doing that
 * integral per pixel is too slow; the split-sum approximation (Karis 2013, "Real Shading
 * in Unreal Engine 4"; Filament's cmgen and its DFG LUT) splits it into
 *   (1) the probe prefiltered once per roughness (a chain of levels, this header's
 *       lg_probe_prefilter_ggx), read along the mirror direction r = reflect(-v, n), and
 *   (2) a 2D table (n.v, roughness) -> (A, B) of the BRDF's directional albedo with
 *       Fresnel factored out (lg_ggx_dfg_table / lg_ggx_dfg),
 * so that the reflected radiance is  prefiltered(r, roughness) * (F0 A + B).
 * docs/probes.md "Glossy prefiltering" has the maths, the measured error against the
 * oracle below and the cost (the prefilter study, docs/accuracy.md#probe).
 *
 * Conventions (the only ones in lightgraph; the ibl plugin's GLSL and CL follow them):
 *   - Microfacet distribution: GGX / Trowbridge-Reitz,
 *       D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2),
 *     with alpha = roughness^2, roughness being glTF's perceptual roughness in [0, 1].
 *   - Visibility: Smith height-correlated (Heitz 2014; Filament's V_SmithGGXCorrelated),
 *       Vis = G / (4 (n.l)(n.v))
 *           = 0.5 / ((n.l) sqrt((n.v)^2 (1 - alpha^2) + alpha^2)
 *                    + (n.v) sqrt((n.l)^2 (1 - alpha^2) + alpha^2)).
 *   - Fresnel: Schlick, F = F0 + (1 - F0)(1 - v.h)^5, F0 per RGB channel
 *     (lg_material.reflectivity).
 *   - f_spec(l, v) = D(h) Vis(l, v) F(v.h), h = normalize(l + v).
 *   - A GGX chain of L levels (lg_probe_info.filter = LG_PROBE_FILTER_GGX): level l holds
 *     the probe prefiltered for perceptual roughness l / (L - 1) (lg_probe_level_roughness;
 *     level 0 is the probe itself, roughness 0; the last level roughness 1; a chain of
 *     one level is the probe alone). Level l's size is the level-0 size >> l (min 1), as
 *     the mip levels of lightgraph/host.h (lg_image_offset packs them; a GL texture with
 *     that many mip levels holds them), so a GL cube texture sampled with
 *     GL_LINEAR_MIPMAP_LINEAR and textureLod(dir, lg_probe_roughness_lod(roughness, L))
 *     reads what lg_probe_lookup_rough reads.
 *
 * Frames. The chain lg_probe_prefilter_ggx makes is in the source's own probe frame: the
 * GGX lobe with n = v = r is symmetric about r, so prefiltering commutes with rotation, and
 * the chain takes the source's rotation (lg_probe_info.rotation; set lg_probe_image.rotation
 * of every level to it for lookups). That is also why level 0 can be the source bit for
 * bit.
 *
 * Thread safety: every function is re-entrant. lg_ggx_dfg builds its table once per
 * process on first use (thread-safe; concurrent first callers wait for it).
 */
#ifndef LG_IBL_GGX_PREFILTER_H
#define LG_IBL_GGX_PREFILTER_H

#include <math.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"
#include "lightgraph/probe.h"
#include "lightgraph/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The most levels a GGX chain has (a 65536 face has 17 mip levels; 16 is plenty). */
#define LG_PROBE_FILTER_MAX_LEVELS 16u

/* Perceptual roughness of level `level` of a chain of `levels`: level / (levels - 1);
 * 0 for a chain of one level (or none), and for level 0. */
static inline float lg_probe_level_roughness(uint32_t level, uint32_t levels)
{
    if (levels <= 1)
        return 0.0f;
    if (level >= levels)
        level = levels - 1;
    return (float)level / (float)(levels - 1);
}

/* The (fractional) level to read for a perceptual roughness: roughness * (levels - 1),
 * roughness clamped to [0, 1] first (NaN counts as 0); 0 for a chain of one level. The
 * inverse of lg_probe_level_roughness. */
static inline float lg_probe_roughness_lod(float roughness, uint32_t levels)
{
    if (!(roughness > 0.0f) || levels <= 1) /* NaN, negative, zero */
        return 0.0f;
    if (roughness > 1.0f)
        roughness = 1.0f;
    return roughness * (float)(levels - 1);
}

/* How lg_probe_prefilter_ggx weights its samples (lg_probe_prefilter_opts.weighting). */
typedef enum lg_probe_prefilter_weighting {
    LG_PROBE_WEIGHT_NOL = 0, /* n.l: Karis 2013 and Filament's cmgen (the default). Better
                              * for views away from the normal, but biased even at
                              * n = v, where the true lobe also carries Vis(l, v): about
                              * 10% relative RMS on the sunlit forest probe at roughness
                              * 0.5 .. 1 (docs/probes.md "Glossy prefiltering") */
    LG_PROBE_WEIGHT_NOL_VIS, /* n.l Vis(n.l, n.v = 1): the integrand's own lobe for
                              * n = v, so that the split sum converges to the oracle
                              * there; worse than n.l at 45 degrees and beyond */
} lg_probe_prefilter_weighting;

/* How lg_probe_prefilter_ggx samples. Zeroed (or a NULL pointer) means the defaults. */
typedef struct lg_probe_prefilter_opts {
    uint32_t samples;       /* GGX samples per texel (a Hammersley set), 0 = 256 */
    uint32_t no_source_lod; /* nonzero: read level 0 of the source for every sample
                             * (plain importance sampling: noisy, aliased bright spots
                             * at low sample counts); default 0: filtered importance
                             * sampling (Krivanek & Colbert 2008, as Filament's cmgen and
                             * Karis 2013): each sample reads a box-filtered mip of the
                             * source chosen from its pdf, lod = log4(omega_s / omega_p)
                             * + 1 with omega_s = 1 / (samples pdf) the sample's solid
                             * angle and omega_p a level-0 texel's (trilinear between
                             * mips) */
    uint32_t weighting;     /* an lg_probe_prefilter_weighting (since this header's first
                             * version; 0 = n.l) */
    uint32_t reserved[5];
} lg_probe_prefilter_opts;

/* What a prefiltering measured. */
typedef struct lg_probe_prefilter_stats {
    double seconds;   /* wall time of the whole call (level 0 and the mips included) */
    uint64_t samples; /* GGX samples taken (texels of levels >= 1 times samples; those
                       * below the horizon count too) */
    uint32_t threads; /* participants of the pool used (1 without one) */
    uint32_t reserved_u[3];
    double reserved[4];
} lg_probe_prefilter_stats;

/* Prefilters `src` (one level, any layout; see "Frames" above for its rotation) into a
 * GGX chain of `levels` levels of layout `layout`, level-0 size width x height (cube: the
 * face size, width == height), written to `out`: RGBA floats, every level packed as
 * lg_image_offset says for that description (lg_image_offset(&desc, levels, 0) texels in
 * all; a cube's six faces per level); `out` is the caller's.
 *
 * Level 0 is src copied when layout and size match (bit for bit), else area-resampled
 * into the layout (lg_probe_resample, its default options); a resampled angular map's
 * texels outside the disc (solid angle 0) then hold the radiance along +Z, the
 * direction of every point outside the disc, instead of 0, so that bilinear lookups at
 * the rim do not darken (a constant probe stays constant). Level l > 0, of perceptual
 * roughness r = l / (levels - 1), is at every texel of direction n
 *     sum_k L(l_k) (n.l_k) / sum_k (n.l_k)     over k with n.l_k > 0,
 * l_k = reflect(-n, h_k), h_k the GGX (alpha = r^2) importance samples about n of a
 * Hammersley set (the same set for every texel, turned into the texel's frame): the
 * split-sum assumption n = v = r of Karis 2013. (With opts->weighting =
 * LG_PROBE_WEIGHT_NOL_VIS the weight is (n.l_k) Vis(n.l_k, 1) instead.) L reads level 0 (no_source_lod) or the
 * source's box-filtered mip chain (the default; see lg_probe_prefilter_opts). The sum is
 * formed as L(l_0) + sum_k w_k (L(l_k) - L(l_0)) / sum_k w_k, so that a constant probe
 * stays exactly constant at every level and in every layout.
 *
 * The source's texels must be finite (the probe node sets NaN, Inf and negative texels to
 * 0): one non-finite texel spreads over every texel whose lobe reaches it.
 *
 * Cost (docs/probes.md "Glossy prefiltering"): (texels of levels 1 .. L-1, about a third
 * of level 0's) x samples x 2 bilinear lookups (one without source lod); a cube of face 128, 5 levels, 256 samples per texel: 0.3 .. 0.5 s on two
 * threads of a loaded VM. Memory beyond `out`: the source's mip chain (a third of level
 * 0) and 20 bytes per sample per level.
 *
 * pool: a node whose host thread pool runs the work (lg_parallel_for; call from the
 * node's prepare() or execute()), or NULL for the calling thread alone. The result is the
 * same bit for bit either way. stats and opts may be NULL.
 * Returns 0, or LG_ERR_INVALID (src NULL or empty, unknown layout, a zero size or a side
 * above 65536, a cube that is not square, levels outside 1..16, out NULL, an unknown
 * weighting) or LG_ERR_NOMEM. Nothing is reported through the host (the caller does, with its
 * context). */
int lg_probe_prefilter_ggx(lg_node *pool, const lg_probe_image *src, lg_probe_layout layout,
                           uint32_t width, uint32_t height, uint32_t levels,
                           const lg_probe_prefilter_opts *opts, float *out,
                           lg_probe_prefilter_stats *stats);

/* Rough lookup into a chain: levels[0 .. n_levels - 1], each an lg_probe_image of the same
 * layout and rotation, level l of size >> l (lg_probe_image_at makes them from a mapped
 * radiance image). lod = lg_probe_roughness_lod(roughness, n_levels), lo = floor(lod),
 * f = lod - lo, and the result is a + (b - a) f with a and b the bilinear lg_probe_lookup
 * of levels lo and min(lo + 1, n_levels - 1): what a GL cube texture with
 * GL_LINEAR_MIPMAP_LINEAR and textureLod(dir, lod) does, and what the GLSL and CL code of
 * the ibl plugin reproduce. Roughness 0 is lg_probe_lookup of level 0 exactly. n_levels 0
 * or levels NULL gives 0. Writes RGBA to out. */
void lg_probe_lookup_rough(const lg_probe_image *levels, uint32_t n_levels, lg_vec3 dir,
                           float roughness, float out[4]);

/* The split-sum DFG table (Karis 2013; Filament's DFG LUT): for n.v and perceptual
 * roughness, the scale A and bias B with
 *     integral over the hemisphere of f_spec(l, v) (n.l) dl  =  F0 A + B
 * (the directional albedo under a white environment; Schlick Fresnel, GGX,
 * Smith height-correlated), i.e. A = integral (1 - Fc) D Vis (n.l),
 * B = integral Fc D Vis (n.l), Fc = (1 - v.h)^5. Table of size x size entries, entry
 * (i, j) at n.v = (i + 0.5) / size and roughness = (j + 0.5) / size, two floats (A, B) at
 * out[2 (j size + i) + 0..1] (2 size^2 floats, the caller's), each estimated from
 * `samples` GGX importance samples of a Hammersley set (0 = 1024). size 0 or out NULL
 * does nothing. At roughness 0, A + B = 1 exactly. */
void lg_ggx_dfg_table(uint32_t size, uint32_t samples, float *out);

/* (A, B) at any n.v and roughness (both clamped to [0, 1]; NaN counts as 0): bilinear in
 * the process's table (lg_ggx_dfg_shared), made once on first use (some 0.1 s). */
#define LG_GGX_DFG_SIZE 32u
#define LG_GGX_DFG_SAMPLES 1024u
void lg_ggx_dfg(float n_dot_v, float roughness, float out[2]);

/* The process's table: LG_GGX_DFG_SIZE^2 entries of LG_GGX_DFG_SAMPLES samples, two
 * floats (A, B) each, entry (i, j) at out[2 (j N + i)] -- but on the END POINTS, n.v =
 * i / (N - 1) and roughness = j / (N - 1), not on texel centres as lg_ggx_dfg_table: the
 * albedo falls steeply with roughness near 1 (d(A + B)/dr about -1.2), and a table of
 * centres clamped at its edge read n.v = 1, roughness 1 half an entry inside, 6% high
 * (measured). lg_ggx_dfg reads it at x = n.v (N - 1), y = roughness (N - 1). A GL
 * texture of it (GL_LINEAR, clamp to edge) gives the same with texture coordinates
 * lg_ggx_dfg_uv (GLSL: uv = (vec2(n_dot_v, roughness) * (N - 1) + 0.5) / N). Owned by
 * the library, valid until the process ends. Accuracy (tests/unit/probe_filter `dfg`):
 * within 1e-2 absolute of the converged integral (the worst near grazing n.v, where
 * GGX samples fall below the horizon), bilinear included. */
const float *lg_ggx_dfg_shared(void);
static inline void lg_ggx_dfg_uv(float n_dot_v, float roughness, float uv[2])
{
    const float n = (float)LG_GGX_DFG_SIZE;
    n_dot_v = n_dot_v > 0.0f ? (n_dot_v < 1.0f ? n_dot_v : 1.0f) : 0.0f;
    roughness = roughness > 0.0f ? (roughness < 1.0f ? roughness : 1.0f) : 0.0f;
    uv[0] = (n_dot_v * (n - 1.0f) + 0.5f) / n;
    uv[1] = (roughness * (n - 1.0f) + 0.5f) / n;
}

/* The oracle: a Monte Carlo estimate (accumulated in double) of
 *     integral over the hemisphere of n of  L(l) f_spec(l, v) (n.l) dl
 * with f_spec as above (f0: Schlick's F0 per channel; NULL means no Fresnel, F = 1),
 * L the bilinear lg_probe_lookup of `src` (its rotation applies: n and v are world
 * directions), importance sampled by D (h from D(h)(n.h), l = reflect(-v, h)) with
 * `samples` samples (0 = 65536) of a Hammersley set given a Cranley-Patterson rotation
 * drawn from `seed` (PCG32), so different seeds give independent estimates. n and v are
 * normalised first (lg_probe_safe_dir); v points toward the viewer. Roughness is clamped
 * to [0, 1] (NaN: 0); roughness 0 gives F(n.v) L(reflect(-v, n)) exactly (one lookup).
 * A viewer behind the surface (n.v <= 0) gives 0. Writes RGB to out[0..2].
 * Returns 0, or LG_ERR_INVALID (src, its texels or out NULL, or a zero size). */
int lg_probe_ggx_reference(const lg_probe_image *src, lg_vec3 n, lg_vec3 v, float roughness,
                           const float f0[3], uint64_t samples, uint32_t seed, double out[3]);

/* The split-sum estimate of the same integral from a chain:
 *     lg_probe_lookup_rough(levels, n_levels, reflect(-v, n), roughness) * (f0 A + B)
 * (f0 NULL: A + B), (A, B) = lg_ggx_dfg(n.v, roughness), n and v normalised first, n.v
 * clamped to [0, 1]: the formula `reflect` uses on every backend. Writes RGB to out. */
void lg_probe_ggx_split_sum(const lg_probe_image *levels, uint32_t n_levels, lg_vec3 n, lg_vec3 v,
                            float roughness, const float f0[3], float out[3]);

#ifdef __cplusplus
}
#endif
#endif
