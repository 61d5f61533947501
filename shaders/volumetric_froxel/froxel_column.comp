#version 450
// volumetric_froxel, passes 1 and 2 of 3 fused: the light pass and the accumulation
// (plugins/volumetric_froxel/froxel.h, steps 1 and 2; seed 2, eqs. 11 and 12). One
// invocation per column (i, j), walking k = 0 .. D-1 front to back:
//
//   p     = e + w_ij T(k + jitter) / cos_ij
//   S_ijk = sigma_s sum_l C_l Shadow_l(p) p_HG(g, dot(w_ij, -L_l))
//
// then, with a history, the blend with the previous frame's S read trilinearly where the
// slice's centre falls in the previous grid. S goes to u_s (rgba32f, alpha 1: this frame's
// S, the lookup's partial slice and the next frame's history), and the running sum to the
// grid u_out:
//
//   thesis:            A_k = A_{k-1} + S_k Delta_k                              Tr_k = 1
//   energy_conserving: A_k = A_{k-1} + Tr_{k-1} S_k Delta_k seg(sigma_t Delta_k)
//                      Tr_k = Tr_{k-1} exp(-sigma_t Delta_k)
//
// What depends only on the column is computed once, before the walk: 1 / cos, the sum of
// sigma_s C_l p_HG over the unshadowed lights, and per shadowed light sigma_s C_l p_HG and
// its clip position as an affine function of view depth, clip(t) = a_l + b_l t (a_l = VP_l
// e, b_l = VP_l w / cos): a shadow test per froxel is 4 multiply-adds, a reciprocal and a
// fetch. (Measured on llvmpipe: the per-froxel light pass followed by a per-column
// accumulation, each froxel doing all of this work, was 305 ms at the thesis grid with
// one light; this pass, README's table.)
//
// Work-groups of 8x8 columns: each step k touches one 8x8 tile of a slice, so neighbouring
// invocations write neighbouring texels and their shadow fetches land near each other.
#include "froxel_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#define FX_MAX_LIGHTS 32

// One light with its shadow record folded in (froxel_gl.c, fx_gl_light). The plain variant
// reads the directional fields (view_proj .. tile); FX_GENERAL reads the rest.
struct FxLight {
    mat4 view_proj;    // world -> the shadow record's clip space (shadow >= 0)
    vec3 dir;          // unit, the direction the light travels (a spot's axis)
    int shadow;        // >= 0: shadowed through the atlas tile at `tile`; -1: unshadowed
    vec3 l_c;          // colour x intensity
    int type;          // 0 directional, 1 point, 2 spot (lg_light_type)
    ivec2 tile;        // the tile's top-left texel
    int rec;           // FX_GENERAL: the light's first record in FxRecords, or -1
    int n_rec;         // its records: 1, 2 (dual paraboloid) or 6 (cube)
    vec3 pos;          // point, spot: world position
    float range;       // 0 = infinite
    vec3 sq;           // the light's position from its first record's view (the face choice)
    float cos_inner;
    float cos_outer;
    float pad2;
    vec2 pad3;
};
layout(std430, binding = 0) readonly buffer FxLights {
    FxLight fx_lights[];
};
// The frame's slice table (froxel_gl.c, fx_gl_slices): D floats T(k + jitter), D + 1
// floats T(k) (k = 0 .. D), D floats T(k + 0.5), D floats tlen_k = t_{k+1} - t_k (t_0 = 0,
// in double on the CPU, as the cpu backend's step). Before it, each froxel evaluated the slice
// map two or three times (a pow each, exponential slicing).
layout(std430, binding = 1) readonly buffer FxSlices {
    float fx_slices[];
};

#ifdef FX_GENERAL
// Point and spot lights, PCF or a heterogeneous medium (froxel.h 4.): every shadow record
// of the map (lg_shadow_light, its matrix and tile; froxel_gl.c, fx_gl_record).
struct FxRecord {
    mat4 m;            // view_proj; a paraboloid record's view
    ivec2 tile;
    int face;          // LG_SHADOW_FACE_*
    int projection;
    float znear;
    float depth_range;
    vec2 pad;
};
layout(std430, binding = 2) readonly buffer FxRecords {
    FxRecord fx_recs[];
};
uniform int u_pcf;           // PCF radius, texels (0: one texel)
uniform int u_point_nodes;   // 0: point and spot lights sampled at p; 1 .. 8: analytic
#endif
#ifdef FX_HETERO
layout(binding = 1) uniform sampler3D u_density;               // rho_ijk, texelFetch
layout(binding = 2) uniform sampler3D u_tau;                   // lights' tau, stacked in z, linear
layout(binding = 3, r32f) uniform writeonly image3D u_path;    // P_k
uniform vec3 u_tau_lo;       // the tau volumes' box
uniform vec3 u_tau_hi;
uniform ivec3 u_tau_n;       // cells of one light's volume
#endif

layout(binding = 0) uniform sampler2D u_atlas;                 // depth-only, texelFetch
layout(binding = 0, rgba32f) uniform writeonly image3D u_s;    // this frame's S
layout(binding = 1, rgba32f) uniform readonly image3D u_hist;  // the previous frame's S
layout(binding = 2, rgba32f) uniform writeonly image3D u_out;  // the grid

uniform ivec3 u_grid;        // W, H, D
uniform mat4 u_ray_vp;       // this frame's camera: vol_ray_matrix, the view rays
uniform vec3 u_eye;
uniform vec3 u_fwd;
uniform vec3 u_sigma_s;
uniform float u_g;
uniform int u_n_lights;      // 1 .. 32
uniform int u_shadow_res;    // tile side, texels
uniform float u_bias;        // bias_constant, depth units
uniform float u_history;     // weight of the history; 0: none (or no previous frame)
uniform mat4 u_prev_vp;      // the previous frame's view-projection
uniform vec3 u_prev_eye;
uniform vec3 u_prev_fwd;
uniform int u_prev_slicing;
uniform vec4 u_prev_map;
uniform vec3 u_sigma_t;
uniform int u_energy;        // 1: energy_conserving, 0: thesis

// The history at continuous cell coordinates x (cell centres at integers), trilinear,
// clamped to the edge.
vec3 fx_history(vec3 x)
{
    ivec3 hi = u_grid - 1;
    vec3 x0 = floor(x);
    vec3 f = x - x0;
    ivec3 a = clamp(ivec3(x0), ivec3(0), hi);
    ivec3 b = clamp(ivec3(x0) + 1, ivec3(0), hi);
    vec3 c00 = mix(imageLoad(u_hist, ivec3(a.x, a.y, a.z)).rgb,
                   imageLoad(u_hist, ivec3(b.x, a.y, a.z)).rgb, f.x);
    vec3 c10 = mix(imageLoad(u_hist, ivec3(a.x, b.y, a.z)).rgb,
                   imageLoad(u_hist, ivec3(b.x, b.y, a.z)).rgb, f.x);
    vec3 c01 = mix(imageLoad(u_hist, ivec3(a.x, a.y, b.z)).rgb,
                   imageLoad(u_hist, ivec3(b.x, a.y, b.z)).rgb, f.x);
    vec3 c11 = mix(imageLoad(u_hist, ivec3(a.x, b.y, b.z)).rgb,
                   imageLoad(u_hist, ivec3(b.x, b.y, b.z)).rgb, f.x);
    return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

#ifdef FX_GENERAL
// lg_shadowmap_visibility on the GPU: the record of light l that holds p (lg_shadowmap_record_at:
// a cube's face by the major axis of p - sq, ties to the lower axis; a paraboloid pair by the
// side of the front record's view), its projection (perspective divide; a paraboloid's
// mapping), then the fraction of the (2 r + 1)^2 PCF taps, each clamped to the tile, in
// which p is lit. 1 outside the tile, behind the near plane or without a record.
float fx_visibility(int r, int nr, vec3 sq, vec3 p, ivec2 atlas_size, int res)
{
    // one exit (structured control flow for llvmpipe's SIMD lanes)
    if (nr == 6) {
        vec3 d = p - sq;
        vec3 a = abs(d);
        // the major axis, ties to the lower one, without indexing d by a variable
        int axis = 0;
        float m = a.x, da = d.x;
        if (a.y > m) {
            axis = 1;
            m = a.y;
            da = d.y;
        }
        if (a.z > m) {
            axis = 2;
            da = d.z;
        }
        r += 2 * axis + (da < 0.0 ? 1 : 0);
    } else if (nr == 2) {
        vec4 v = fx_recs[r].m * vec4(p, 1.0);
        r += v.z > 0.0 ? 1 : 0;
    }
    int face = fx_recs[r].face;
    vec4 q = fx_recs[r].m * vec4(p, 1.0);
    bool front = q.w > 0.0;
    vec3 ndc = q.xyz / q.w;
    if (face >= 16) {
        // dual paraboloid: the view-space direction maps to d.xy / (1 + z'), depth is the
        // distance past znear over depth_range (lg_shadowmap_visibility)
        float len = length(q.xyz);
        front = len > 0.0;
        float zf = (face == 16 ? -q.z : q.z) / len;
        ndc = vec3(q.xy / len / (1.0 + zf),
                   2.0 * (len - fx_recs[r].znear) / fx_recs[r].depth_range - 1.0);
        ndc.x = face == 17 ? -ndc.x : ndc.x;
    }
    vec2 uv = ndc.xy * 0.5 + 0.5;
    float z = min(ndc.z * 0.5 + 0.5, 1.0);
    bool inside = front && uv.x >= 0.0 && uv.x < 1.0 && uv.y >= 0.0 && uv.y < 1.0 && z >= 0.0;
    float vis = 1.0;
    if (inside) {
        ivec2 cxy = min(ivec2(uv * float(res)), ivec2(res - 1));
        ivec2 tile = fx_recs[r].tile;
        int side = 2 * u_pcf + 1, taps = side * side, lit = 0;
        for (int i = 0; i < taps; i++) {
            ivec2 o = ivec2(i % side, i / side) - u_pcf;
            ivec2 texel = tile + clamp(cxy + o, ivec2(0), ivec2(res - 1));
            bool beyond = any(greaterThanEqual(texel, atlas_size));
            float stored = texelFetch(u_atlas, min(texel, atlas_size - 1), 0).r;
            lit += beyond || !(z > stored + u_bias) ? 1 : 0;
        }
        vis = float(lit) / float(taps);
    }
    return vis;
}
#endif

#ifdef FX_HETERO
// tau_l(p): light l's optical-depth volume (vol_tau_volume) read with linear filtering at
// froxel.h's coordinates, clamped to the box (cell centres), the lights stacked along z.
float fx_tau(int l, vec3 p)
{
    vec3 n1 = vec3(u_tau_n - 1);
    vec3 x = clamp((p - u_tau_lo) / (u_tau_hi - u_tau_lo) * n1, vec3(0.0), n1);
    vec3 uvw = (x + 0.5) / vec3(u_tau_n);
    uvw.z = (x.z + 0.5 + float(l * u_tau_n.z)) / float(u_tau_n.z * u_n_lights);
    return textureLod(u_tau, uvw, 0.0).r;
}
#endif

#ifdef FX_GENERAL
// froxel.h 1, 2 and 4 for point and spot lights, PCF and heterogeneous media: per froxel
// and light the falloff (or the slice's analytic average), the shadow through the record
// that holds p, the transmittance towards the light; rho multiplies S and the extinction.
void fx_column_general(ivec2 c, vec3 w, float ic)
{
    // each light's record read once per column into locals (read per froxel from the
    // FxLights buffer it cost 1.6 .. 2.3x on llvmpipe: README, "The light pass's floor: gl")
    vec4 l0[FX_MAX_LIGHTS], l1[FX_MAX_LIGHTS], l2[FX_MAX_LIGHTS], l3[FX_MAX_LIGHTS];
    ivec2 lr[FX_MAX_LIGHTS];
    for (int l = 0; l < u_n_lights; l++) {
        int type = fx_lights[l].type;
        vec3 term = u_sigma_s * fx_lights[l].l_c;
        if (type == 0)
            term *= lg_hg_phase(u_g, dot(w, -fx_lights[l].dir));
        l0[l] = vec4(fx_lights[l].pos, fx_lights[l].range);
        l1[l] = vec4(fx_lights[l].dir, float(type));
        l2[l] = vec4(term, fx_lights[l].cos_inner);
        l3[l] = vec4(fx_lights[l].sq, fx_lights[l].cos_outer);
        lr[l] = ivec2(fx_lights[l].rec, fx_lights[l].n_rec);
    }
    ivec2 atlas_size = textureSize(u_atlas, 0);
    int res = u_shadow_res;
    vec3 A = vec3(0.0), Tr = vec3(1.0);
    float P = 0.0;
    float t0 = 0.0;
    int D = u_grid.z;
    for (int k = 0; k < D; k++) {
        float t = fx_slices[k];
        float t1 = fx_slices[D + k + 1];
        float delta = fx_slices[3 * D + 1 + k] * ic;
        vec3 p = u_eye + w * (t * ic);
        vec3 S = vec3(0.0);
        for (int l = 0; l < u_n_lights; l++) {
            int type = int(l1[l].w);
            vec3 term = l2[l].rgb;
            float dist = 0.0;
            if (type != 0) {
                bool spot = type == 2;
                vec3 q = l0[l].xyz, ax = l1[l].xyz;
                vec2 cone = vec2(l2[l].w, l3[l].w);
                float range = l0[l].w;
                vec3 tl;
                float f = lg_local_falloff(q, range, spot, ax, cone, p, tl, dist);
                if (u_point_nodes > 0)
                    f = lg_point_inscatter(u_eye, w, t0 * ic, t1 * ic, q, range, spot, ax, cone,
                                           u_g, 0.0, u_point_nodes) / delta;
                else
                    f *= lg_hg_phase(u_g, dot(w, tl));
                term *= f;
            }
            if (lr[l].x >= 0)
                term *= fx_visibility(lr[l].x, lr[l].y, l3[l].xyz, p, atlas_size, res);
#ifdef FX_HETERO
            term *= exp(-u_sigma_t * fx_tau(l, p));
#else
            if (type != 0)
                term *= exp(-u_sigma_t * dist);
#endif
            S += term;
        }
#ifdef FX_HETERO
        float rho = texelFetch(u_density, ivec3(c, k), 0).r;
        S *= rho;
#else
        const float rho = 1.0;
#endif
        if (u_history > 0.0) {
            float tc = fx_slices[2 * D + 1 + k];
            vec3 q = u_eye + w * (tc * ic);
            vec4 pc = u_prev_vp * vec4(q, 1.0);
            vec2 uv = (pc.xy / pc.w + 1.0) * vec2(u_grid.xy) * 0.5;
            float z = lg_depth_to_slice(u_prev_slicing, u_prev_map,
                                        dot(q - u_prev_eye, u_prev_fwd));
            if (pc.w > 0.0 && uv.x >= 0.0 && uv.x <= float(u_grid.x) && uv.y >= 0.0 &&
                uv.y <= float(u_grid.y) && z >= 0.0 && z <= float(u_grid.z))
                S = mix(S, fx_history(vec3(uv, z) - 0.5), u_history);
        }
        // alpha: rho at the sample point (the lookup's rho_k; 1 homogeneous)
        imageStore(u_s, ivec3(c, k), vec4(S, rho));

        if (u_energy != 0) {
            vec3 tau = u_sigma_t * (rho * delta);
            A += Tr * S * delta * lg_medium_segment3(tau);
            Tr *= exp(-tau);
        } else {
            A += S * delta;
        }
#ifdef FX_HETERO
        P += rho * delta;
        imageStore(u_path, ivec3(c, k), vec4(P, 0.0, 0.0, 0.0));
#endif
        imageStore(u_out, ivec3(c, k), vec4(A, (Tr.x + Tr.y + Tr.z) / 3.0));
        t0 = t1;
    }
}
#endif

void main()
{
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(c, u_grid.xy)))
        return;
    vec3 w = fx_ray(u_ray_vp, fx_ndc(c, u_grid.xy));
    float ic = 1.0 / dot(w, u_fwd);
#ifdef FX_GENERAL
    fx_column_general(c, w, ic);
#else

    // the column's constants
    vec3 unsh = vec3(0.0);
    vec3 lp[FX_MAX_LIGHTS];
    vec4 la[FX_MAX_LIGHTS], lb[FX_MAX_LIGHTS];
    ivec2 tile[FX_MAX_LIGHTS];
    int nsh = 0;
    for (int l = 0; l < u_n_lights; l++) {
        vec3 cl = u_sigma_s * fx_lights[l].l_c * lg_hg_phase(u_g, dot(w, -fx_lights[l].dir));
        if (fx_lights[l].shadow < 0) {
            unsh += cl;
            continue;
        }
        mat4 m = fx_lights[l].view_proj;
        la[nsh] = m * vec4(u_eye, 1.0);
        lb[nsh] = m * vec4(w * ic, 0.0);
        lp[nsh] = cl;
        tile[nsh] = fx_lights[l].tile;
        nsh++;
    }
    ivec2 atlas_size = textureSize(u_atlas, 0);
    float res = float(u_shadow_res);

    vec3 A = vec3(0.0), Tr = vec3(1.0);
    float t0 = 0.0;
    int D = u_grid.z;
    // sigma_t the same in r, g, b: one exp and one segment factor per froxel (same values)
    bool grey = u_sigma_t.x == u_sigma_t.y && u_sigma_t.y == u_sigma_t.z;
    for (int k = 0; k < D; k++) {
        float t = fx_slices[k];
        vec3 S = unsh;
        for (int l = 0; l < nsh; l++) {
            // vol_shadow_cpu's rule: nearest texel of the light's tile; lit outside the
            // tile, in front of the light's near plane, or beyond the atlas
            vec4 q = la[l] + lb[l] * t;
            vec3 n = q.xyz * (1.0 / q.w);
            vec2 uv = n.xy * 0.5 + 0.5;
            float z = n.z * 0.5 + 0.5;
            bool lit = true;
            if (uv.x >= 0.0 && uv.x < 1.0 && uv.y >= 0.0 && uv.y < 1.0 && z >= 0.0) {
                // uv < 1, but uv * res may round up to res in float: the last texel then
                ivec2 texel = tile[l] + min(ivec2(uv * res), ivec2(u_shadow_res - 1));
                if (all(lessThan(texel, atlas_size)))
                    lit = !(z > texelFetch(u_atlas, texel, 0).r + u_bias);
            }
            S += lit ? lp[l] : vec3(0.0);
        }
        if (u_history > 0.0) {
            // the slice's centre, projected into the previous grid
            float tc = fx_slices[2 * D + 1 + k];
            vec3 q = u_eye + w * (tc * ic);
            vec4 pc = u_prev_vp * vec4(q, 1.0);
            vec2 uv = (pc.xy / pc.w + 1.0) * vec2(u_grid.xy) * 0.5;
            float z = lg_depth_to_slice(u_prev_slicing, u_prev_map,
                                        dot(q - u_prev_eye, u_prev_fwd));
            if (pc.w > 0.0 && uv.x >= 0.0 && uv.x <= float(u_grid.x) && uv.y >= 0.0 &&
                uv.y <= float(u_grid.y) && z >= 0.0 && z <= float(u_grid.z))
                S = mix(S, fx_history(vec3(uv, z) - 0.5), u_history);
        }
        imageStore(u_s, ivec3(c, k), vec4(S, 1.0));

        float t1 = fx_slices[D + k + 1];
        float delta = fx_slices[3 * D + 1 + k] * ic;
        if (u_energy != 0 && grey) {
            float tau = u_sigma_t.x * delta;
            A += Tr * S * (delta * lg_medium_segment(tau));
            Tr *= exp(-tau);
        } else if (u_energy != 0) {
            vec3 tau = u_sigma_t * delta;
            A += Tr * S * delta * lg_medium_segment3(tau);
            Tr *= exp(-tau);
        } else {
            A += S * delta;
        }
        imageStore(u_out, ivec3(c, k), vec4(A, (Tr.x + Tr.y + Tr.z) / 3.0));
        t0 = t1;
    }
#endif
}
