#version 450
// volumetric_froxel, pass 1 of 3: the light pass (plugins/volumetric_froxel/froxel.h, step
// 1; seed 2, eq. 11). One invocation per froxel (i, j, k):
//
//   p     = e + w_ij T(k + jitter) / cos_ij
//   S_ijk = sigma_s sum_l C_l Shadow_l(p) p_HG(g, dot(w_ij, -L_l))
//
// then, with a history, the blend with the previous frame's S read trilinearly where the
// slice's centre falls in the previous grid. The result goes to u_s (rgba32f, alpha 1):
// this frame's S, and the next frame's history.
//
// Work-groups of 8x8x1 along x, y: neighbouring invocations share a slice, so their
// shadow-map fetches land near each other in the atlas, and the light loop (u_n_lights is
// uniform) never diverges; only the shadow test's outcome does, and it is a select.
#include "froxel_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// One directional light with its shadow record folded in (froxel_gl.c, fx_gl_light).
struct FxLight {
    mat4 view_proj;    // world -> the shadow record's clip space (shadow >= 0)
    vec3 dir;          // unit, the direction the light travels
    int shadow;        // >= 0: shadowed through the atlas tile at `tile`; -1: unshadowed
    vec3 l_c;          // colour x intensity
    float pad0;
    ivec2 tile;        // the tile's top-left texel
    ivec2 pad1;
};
layout(std430, binding = 0) readonly buffer FxLights {
    FxLight fx_lights[];
};

layout(binding = 0) uniform sampler2D u_atlas;                 // depth-only, texelFetch
layout(binding = 0, rgba32f) uniform writeonly image3D u_s;    // this frame's S
layout(binding = 1, rgba32f) uniform readonly image3D u_hist;  // the previous frame's S

uniform ivec3 u_grid;        // W, H, D
uniform mat4 u_inv_vp;       // this frame's camera
uniform vec3 u_eye;
uniform vec3 u_fwd;
uniform int u_slicing;       // LG_SLICING_*
uniform vec4 u_map;          // near, far, near_offset, D
uniform vec3 u_sigma_s;
uniform float u_g;
uniform int u_n_lights;      // 1 .. 32
uniform int u_shadow_res;    // tile side, texels
uniform float u_bias;        // bias_constant, depth units
uniform float u_jitter;      // [0, 1)
uniform float u_history;     // weight of the history; 0: none (or no previous frame)
uniform mat4 u_prev_vp;      // the previous frame's view-projection
uniform vec3 u_prev_eye;
uniform vec3 u_prev_fwd;
uniform int u_prev_slicing;
uniform vec4 u_prev_map;

// Light l's shadow test (shadow >= 0), vol_shadow_cpu's rule: nearest texel of the light's tile; lit outside the tile, in front
// of the light's near plane, or beyond the atlas.
float fx_shadow(int l, vec3 p)
{
    vec4 c = fx_lights[l].view_proj * vec4(p, 1.0);
    vec3 q = c.xyz / c.w;
    vec2 t = q.xy * 0.5 + 0.5;
    float z = q.z * 0.5 + 0.5;
    if (!(t.x >= 0.0 && t.x < 1.0 && t.y >= 0.0 && t.y < 1.0) || !(z >= 0.0))
        return 1.0;
    // t < 1, but t * res may round up to res in float: the last texel then
    ivec2 texel = fx_lights[l].tile + min(ivec2(t * float(u_shadow_res)), ivec2(u_shadow_res - 1));
    if (any(greaterThanEqual(texel, textureSize(u_atlas, 0))))
        return 1.0;
    float stored = texelFetch(u_atlas, texel, 0).r;
    return z > stored + u_bias ? 0.0 : 1.0;
}

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

void main()
{
    ivec3 c = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(c, u_grid)))
        return;
    vec3 w = fx_ray(u_inv_vp, u_eye, fx_ndc(c.xy, u_grid.xy));
    float cs = dot(w, u_fwd);
    float t = lg_slice_to_depth(u_slicing, u_map, float(c.z) + u_jitter);
    vec3 p = u_eye + w * (t / cs);
    vec3 sum = vec3(0.0);
    // fields read in place: a copy of the whole record (112 bytes, the matrix even for an
    // unshadowed light) per light and froxel is what llvmpipe would otherwise load
    for (int l = 0; l < u_n_lights; l++) {
        float vis = fx_lights[l].shadow < 0 ? 1.0 : fx_shadow(l, p);
        sum += fx_lights[l].l_c * (vis * lg_hg_phase(u_g, dot(w, -fx_lights[l].dir)));
    }
    vec3 S = u_sigma_s * sum;
    if (u_history > 0.0) {
        // the slice's centre, projected into the previous grid
        float tc = lg_slice_to_depth(u_slicing, u_map, float(c.z) + 0.5);
        vec3 q = u_eye + w * (tc / cs);
        vec4 pc = u_prev_vp * vec4(q, 1.0);
        vec2 uv = (pc.xy / pc.w + 1.0) * vec2(u_grid.xy) * 0.5;
        float z = lg_depth_to_slice(u_prev_slicing, u_prev_map, dot(q - u_prev_eye, u_prev_fwd));
        if (pc.w > 0.0 && uv.x >= 0.0 && uv.x <= float(u_grid.x) && uv.y >= 0.0 &&
            uv.y <= float(u_grid.y) && z >= 0.0 && z <= float(u_grid.z))
            S = mix(S, fx_history(vec3(uv, z) - 0.5), u_history);
    }
    imageStore(u_s, c, vec4(S, 1.0));
}
