/*
 * plugins/volumetric_froxel/froxel.h: the contract between the volumetric_froxel node
 * (froxel.c: parameters, prepare, the frame's set-up, temporal state) and its three
 * backends (froxel_cpu.c, froxel_cl.c + shaders/volumetric_froxel/froxel.cl, froxel_gl.c +
 * shaders/volumetric_froxel/froxel_*.comp). All three compute exactly what this comment says, in
 * float, so that they agree to rounding (tests/plugins/volumetric_froxel).
 *
 * Notation (vol_common.h for the view ray, lightgraph/medium.h for p, seg and the slice
 * map T(z) -> view depth, with T^-1 its inverse):
 *   grid W x H x D; image w x h; eye e, forward f; sigma_s, sigma_t (rgb), g; lights l with
 *   direction L_l (travels), colour C_l, shadow record.
 *
 * Column (i, j): the ray w_ij through NDC (2 (i + 0.5) / W - 1, 2 (j + 0.5) / H - 1) (row 0
 * at the top, as the image), cos_ij = dot(w_ij, f) (> 0). View depth t lies at distance
 * t / cos_ij along it.
 *
 * Slices: boundary t_k = T(k) for k = 1 .. D; t_0 = 0: slice 0 starts at the eye, so the fog
 * between the eye and z_near is counted with slice 0's scattering (the grid covers the whole
 * ray up to z_limit; T(0) = z_near is only where the slice map starts). Length of slice k
 * along the ray: Delta_ijk = (t_{k+1} - t_k) / cos_ij.
 *
 * 1. Light pass (eq. 11, per unit length): sample point at slice coordinate k + jitter,
 *        p = e + w_ij T(k + jitter) / cos_ij
 *        S_ijk = sigma_s * sum_l C_l Shadow_l(p) p_HG(g, dot(w_ij, -L_l))        (rgb)
 *    Shadow_l: vol_shadow_cpu's rule (nearest texel of the light's tile, bias_constant, lit
 *    outside the tile or in front of the light's near plane; no shadow map: 1).
 *    Temporal (history > 0 and a previous frame exists): the point at the slice's centre,
 *    q = e + w_ij T(k + 0.5) / cos_ij, projected by the previous frame's camera to the
 *    previous grid's continuous coordinates (u', v', z') = ((ndc'.x + 1) W / 2,
 *    (ndc'.y + 1) H / 2, T'^-1(dot(q - e', f'))); inside [0, W] x [0, H] x [0, D] the
 *    history H (the previous frame's blended S) is read trilinearly at (u' - 0.5, v' - 0.5,
 *    z' - 0.5) with clamp to edge, and S_ijk = lerp(S_ijk, H, history); outside, S_ijk is
 *    kept. The blended S becomes the next frame's history.
 *    alpha of S = 1 (unused).
 *
 * 2. Accumulation (eq. 12), one thread per column, k = 0 .. D-1, front to back:
 *    thesis:            A_k = A_{k-1} + S_k Delta_k;                     Tr_k = 1
 *    energy_conserving: A_k = A_{k-1} + Tr_{k-1} S_k Delta_k seg(sigma_t Delta_k);
 *                       Tr_k = Tr_{k-1} exp(-sigma_t Delta_k)            (rgb; Tr_{-1} = 1)
 *    A_{-1} = 0. The grid (the LG_KIND_FROXEL output, part `grid`) stores at (i, j, k):
 *    rgb = A_k (in-scattered radiance from the eye to the far boundary of slice k), alpha =
 *    the mean of Tr_k's three channels (informative: consumers of a homogeneous medium use
 *    exp(-sigma_t d) per channel).
 *
 * 3. Lookup, per pixel (x, y) of base, with its depth: the fog length d along the pixel's
 *    ray w (vol_fog_length), t_end = d cos (cos = dot(w, f)); zc = clamp(T^-1(t_end), 0, D);
 *    k = min(floor(zc), D - 1); slice start t_s = (k == 0 ? 0 : T(k)); delta = max(t_end -
 *    t_s, 0) / cos. Bilinear in (u, v) = ((x + 0.5) W / w - 0.5, (y + 0.5) H / h - 0.5),
 *    clamped to [0, W-1] x [0, H-1], of the grid at k - 1 (0 when k = 0) -> A and of S at k
 *    -> S:
 *      thesis:            L_v = A + S delta
 *      energy_conserving: L_v = A + exp(-sigma_t t_s / cos) S delta seg(sigma_t delta)
 *    inscatter = (L_v, 1); out = (base.rgb exp(-sigma_t d) + L_v, base.a) for
 *    energy_conserving, (base.rgb + L_v, base.a) for thesis; out's depth = base's depth.
 *    (For an unshadowed homogeneous medium S is constant along a column, and the energy-
 *    conserving lookup is the closed form L_c sigma_s p d seg(sigma_t d) at any slicing,
 *    exactly where the pixel's centre is a column's centre (image size = W x H, or a 1 x 1
 *    image on a 1 x 1 grid). Between columns the bilinear blend of A and S (whose phase and
 *    1 / cos belong to the columns, not the pixel) is an interpolation error of the
 *    method, not of a backend; tests compare at column centres.)
 *
 * 4. Point and spot lights, heterogeneous media (issue 25; homogeneous media with only
 *    directional lights compute exactly 1-3 above, at the same cost: the added terms are
 *    behind per-frame flags, not per-froxel branches on data).
 *    Light l of type point or spot at q_l contributes to S_ijk (per unit length, rgb):
 *        C_l Shadow_l(p) F_l(p) X_l(p) p_HG(g, dot(w_ij, l_l(p)))
 *    F_l = vol_light_falloff (lightgraph/medium.h: window W(d) and cone C over d^2 + eps^2),
 *    l_l = unit vector p -> q_l, d = |q_l - p|; Shadow_l: the map's record that holds p
 *    (lg_shadowmap_record_at: a point light's cube face) with lg_shadowmap_visibility's
 *    rule and PCF; X_l = e^(-sigma_t d) per channel (homogeneous) or the light's optical-
 *    depth volume (below). Directional lights keep their term of 1 (X = 1 homogeneous).
 *    Analytic point and spot lights (f->point_nodes = n in 1 .. 8): the sample at p is
 *    replaced by the slice's segment average along the column's ray,
 *        (1 / Delta_ijk) lg_point_inscatter(e, w_ij, t_k / cos_ij, t_{k+1} / cos_ij, q_l,
 *                                           range, spot, g, 0, n)
 *    (sigma_t = 0: the accumulation applies the extinction along the ray), times C_l,
 *    Shadow_l(p) and X_l(p) at the sample point p as above (t_0 = 0: slice 0 from the eye).
 *    This is what makes a coarse grid right near a light: the integral of 1 / d^2 over the
 *    slice, not its value at one point. n = 0: the point sample.
 *
 *    Heterogeneous medium (f->density != NULL): rho_ijk = f->density[i + W (j + H k)], the
 *    density multiplier m (lg_medium_field_at) at the light pass's sample point p, made on
 *    the CPU by froxel.c for the frame (the field itself never reaches a device: the
 *    light pass's cost does not depend on the field). Then
 *        S_ijk = rho_ijk sigma_s sum_l C_l Shadow_l F_l X_l p_HG        (rho multiplies S)
 *        X_l(p) = e^(-sigma_t tau_l(p)),  tau_l = f->tau[l] sampled trilinearly at p
 *    for every light type (the medium's shadow on itself; vol_tau_volume: cell centre
 *    (a, b, c) at lo + (hi - lo) (a, b, c) / (n - 1), clamped to the box; as a GL texture
 *    with linear filtering, u = ((p - lo) / (hi - lo) (n - 1) + 0.5) / n). The
 *    accumulation takes each slice's own extinction, sigma_t rho_k:
 *        A_k = A_{k-1} + Tr_{k-1} S_k Delta_k seg(sigma_t rho_k Delta_k)
 *        Tr_k = Tr_{k-1} exp(-sigma_t rho_k Delta_k)
 *    (thesis accumulation: unchanged, Tr = 1) and keeps the optical path P_k = sum_{m <= k}
 *    rho_m Delta_m per column (P_{-1} = 0) in memory of the backend's choice. The lookup
 *    reads P at k - 1 and rho at k bilinearly like A and S:
 *        L_v = A + exp(-sigma_t P_{k-1}) S delta seg(sigma_t rho_k delta)
 *        out = base.rgb exp(-sigma_t (P_{k-1} + rho_k delta)) + L_v
 *    The grid's alpha stays the mean of Tr_k's channels.
 *    All three backends implement 4.; the cpu backend's second path (froxel_cpu.c) is the
 *    reference.
 *
 * Every backend maps its inputs and outputs itself on its device (lg_map_cpu / _gl / _cl):
 * base = lg_input(VOL_IN_BASE) (colour + depth), the shadow atlas = f->sm->atlas, outputs
 * VOL_OUT_OUT, VOL_OUT_INSCATTER, and FX_OUT_GRID's part "grid" (rgba32f volume W x H x D).
 * The scattering volume S and its history are the backend's own (memory it makes once,
 * keeps across frames and frees in destroy, counted in the profile when made and when
 * freed: lg_gl_texture on gl, lg_account_alloc / lg_account_free on cpu). froxel.c
 * publishes the grid's info part after the backend returns.
 */
#ifndef LG_VOLUMETRIC_FROXEL_H
#define LG_VOLUMETRIC_FROXEL_H

#include <stdbool.h>
#include <stdint.h>

#include "vol_common.h"

enum { FX_OUT_GRID = 2 };

typedef enum fx_accum { FX_ACC_THESIS = 0, FX_ACC_ENERGY = 1 } fx_accum;

/* The most slices a grid has (the `depth` parameter's maximum). */
#define FX_MAX_D 512

/* The frame's slice tables: view depths from the slice map, in double, made once per frame
 * by froxel.c (fx_slice_tables) for whichever backend runs; each copies them to its device
 * in its own layout. Entries past D are unused. */
typedef struct fx_slices {
    double tj[FX_MAX_D];     /* T(k + jitter), k < D: the light pass's sample depth */
    double tk[FX_MAX_D + 1]; /* T(k), k <= D: slice k's start (the lookup) */
    double tq[FX_MAX_D];     /* T(k + 0.5), k < D: the history's reprojected point */
    double tlen[FX_MAX_D];   /* T(k + 1) - T(k), with slice 0 starting at the eye (T = 0):
                              * the accumulation's step */
} fx_slices;

typedef struct fx_frame {
    const vol_setup *v; /* this frame's camera, lights, medium, z_limit, image size */
    uint32_t w, h, d;   /* grid W x H x D */
    lg_slice_map map;   /* near = z_near, far = v->z_limit */
    fx_accum accum;
    float jitter;            /* sample offset in each slice, [0, 1); 0.5 without temporal */
    float history;           /* weight of the history in the blend, [0, 1); 0 = none */
    const vol_setup *prev;   /* the previous frame's set-up, or NULL (no history yet) */
    lg_slice_map prev_map;   /* the previous frame's slice map (valid when prev) */
    const lg_shadowmap *sm;  /* NULL: unshadowed */
    uint32_t frame;          /* frame index */
    const fx_slices *slices; /* this frame's slice tables */
    /* issue 25 (4. above) */
    int point_nodes; /* point and spot lights: 0 = sample at p; 1 .. 8 = analytic */
    /* heterogeneous medium: W x H x D multipliers at the light pass's sample points (x
     * fastest), and v->n_lights optical-depth volumes in light order; both NULL for a
     * homogeneous medium. Owned by froxel.c (valid during the execute). */
    const float *density;
    const vol_tau_volume *tau;
} fx_frame;

/* A backend's state, made on the first execute (state NULL), kept across frames; the
 * volumes are remade when the grid size changes. Each returns 0 or an LG_ERR_* after
 * lg_error. destroy runs with the node's device current (GL context for gl). */
int fx_cpu_execute(lg_node *node, void **state, const fx_frame *f);
void fx_cpu_destroy(lg_node *node, void *state);
int fx_cl_execute(lg_node *node, void **state, const fx_frame *f);
void fx_cl_destroy(lg_node *node, void *state);
int fx_gl_execute(lg_node *node, void **state, const fx_frame *f);
void fx_gl_destroy(lg_node *node, void *state);

#endif
