#version 450
// volumetric_froxel, pass 3 of 3: the lookup and composite (plugins/volumetric_froxel/
// froxel.h, step 3). One invocation per pixel (x, y) of base:
//
//   d     = the fog length along the pixel's ray (vol_fog_length: the surface or z_limit)
//   t_end = d cos; k = the slice t_end falls in; t_s = its start (0 for slice 0);
//   delta = (t_end - t_s) / cos, the part of slice k in front of the surface
//   A     = grid at slice k - 1 (0 for k = 0), S = S at slice k, both bilinear in (x, y)
//   thesis:            L_v = A + S delta                      out = base + L_v
//   energy_conserving: L_v = A + e^(-sigma_t t_s / cos) S delta seg(sigma_t delta)
//                      out = base e^(-sigma_t d) + L_v
//
// inscatter = (L_v, 1), out's alpha = base's. out's depth is copied by froxel_gl.c (a
// depth texture cannot be an image).
#include "froxel_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(binding = 0) uniform sampler2D u_base;                        // colour, texelFetch
layout(binding = 1) uniform sampler2D u_depth;                       // window depth
layout(binding = 0, rgba32f) uniform readonly image3D u_acc;         // the grid (A, Tr)
layout(binding = 1, rgba32f) uniform readonly image3D u_s;           // this frame's S
layout(binding = 2, rgba32f) uniform writeonly image2D u_out;
layout(binding = 3, rgba32f) uniform writeonly image2D u_inscatter;

uniform ivec2 u_size;        // the image, w x h
uniform ivec3 u_grid;
uniform mat4 u_inv_vp;
uniform mat4 u_ray_vp;      // vol_ray_matrix: the view rays
uniform vec3 u_eye;
uniform vec3 u_fwd;
uniform float u_z_limit;
uniform int u_slicing;
uniform vec4 u_map;
uniform vec3 u_sigma_t;
uniform int u_energy;
#ifdef FX_HETERO
// froxel.h 4.: the optical path P_k (froxel_column.comp); rho_k is S's alpha
layout(binding = 4, r32f) uniform readonly image3D u_path;

// P at slice k, bilinear like A
float fx_bilerp_path(vec2 uv, int k)
{
    ivec2 a = ivec2(uv);
    ivec2 b = min(a + 1, u_grid.xy - 1);
    vec2 f = uv - vec2(a);
    float r0 = mix(imageLoad(u_path, ivec3(a.x, a.y, k)).r, imageLoad(u_path, ivec3(b.x, a.y, k)).r, f.x);
    float r1 = mix(imageLoad(u_path, ivec3(a.x, b.y, k)).r, imageLoad(u_path, ivec3(b.x, b.y, k)).r, f.x);
    return mix(r0, r1, f.y);
}
#endif
// The frame's slice table (froxel_column.comp's): T(k) at fx_slices[D + k]
layout(std430, binding = 1) readonly buffer FxSlices {
    float fx_slices[];
};

// Bilinear in cell coordinates uv (already clamped to [0, W-1] x [0, H-1]) of slice k.
vec3 fx_bilerp_acc(vec2 uv, int k)
{
    ivec2 a = ivec2(uv);
    ivec2 b = min(a + 1, u_grid.xy - 1);
    vec2 f = uv - vec2(a);
    vec3 r0 = mix(imageLoad(u_acc, ivec3(a.x, a.y, k)).rgb, imageLoad(u_acc, ivec3(b.x, a.y, k)).rgb, f.x);
    vec3 r1 = mix(imageLoad(u_acc, ivec3(a.x, b.y, k)).rgb, imageLoad(u_acc, ivec3(b.x, b.y, k)).rgb, f.x);
    return mix(r0, r1, f.y);
}
vec3 fx_bilerp_s(vec2 uv, int k)
{
    ivec2 a = ivec2(uv);
    ivec2 b = min(a + 1, u_grid.xy - 1);
    vec2 f = uv - vec2(a);
    vec3 r0 = mix(imageLoad(u_s, ivec3(a.x, a.y, k)).rgb, imageLoad(u_s, ivec3(b.x, a.y, k)).rgb, f.x);
    vec3 r1 = mix(imageLoad(u_s, ivec3(a.x, b.y, k)).rgb, imageLoad(u_s, ivec3(b.x, b.y, k)).rgb, f.x);
    return mix(r0, r1, f.y);
}
#ifdef FX_HETERO
// S and rho (its alpha) at slice k, bilinear
vec4 fx_bilerp_s4(vec2 uv, int k)
{
    ivec2 a = ivec2(uv);
    ivec2 b = min(a + 1, u_grid.xy - 1);
    vec2 f = uv - vec2(a);
    vec4 r0 = mix(imageLoad(u_s, ivec3(a.x, a.y, k)), imageLoad(u_s, ivec3(b.x, a.y, k)), f.x);
    vec4 r1 = mix(imageLoad(u_s, ivec3(a.x, b.y, k)), imageLoad(u_s, ivec3(b.x, b.y, k)), f.x);
    return mix(r0, r1, f.y);
}
#endif

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, u_size)))
        return;
    vec2 ndc = fx_ndc(px, u_size);
    vec3 w = fx_ray(u_ray_vp, ndc);
    float cs = dot(w, u_fwd);
    float depth = texelFetch(u_depth, px, 0).r;
    // vol_fog_length: the surface (none for sky or a depth that is not finite), cut at
    // z_limit
    float surf = FX_INF;
    if (depth < 1.0 && !isinf(depth))
        surf = length(fx_unproject(u_inv_vp, ndc, 2.0 * depth - 1.0) - u_eye);
    float d = min(surf, cs > 0.0 ? u_z_limit / cs : FX_INF);

    float t_end = d * cs;
    int D = u_grid.z;
    float zc = clamp(lg_depth_to_slice(u_slicing, u_map, t_end), 0.0, float(D));
    int k = min(int(floor(zc)), D - 1);
    float t_s = k == 0 ? 0.0 : fx_slices[D + k];
    float delta = max(t_end - t_s, 0.0) / cs;

    vec2 uv = (vec2(px) + 0.5) * vec2(u_grid.xy) / vec2(u_size) - 0.5;
    uv = clamp(uv, vec2(0.0), vec2(u_grid.xy - 1));
    vec3 A = k > 0 ? fx_bilerp_acc(uv, k - 1) : vec3(0.0);
    vec4 base = texelFetch(u_base, px, 0);
    vec3 L, o;
#ifdef FX_HETERO
    // froxel.h 4.: each slice's own extinction, the optical path to the slice's start
    vec4 S4 = fx_bilerp_s4(uv, k);
    vec3 S = S4.rgb;
    float rho = S4.a;
    float P = k > 0 ? fx_bilerp_path(uv, k - 1) : 0.0;
    if (u_energy != 0) {
        L = A + exp(-u_sigma_t * P) * S * delta * lg_medium_segment3(u_sigma_t * (rho * delta));
        o = base.rgb * exp(-u_sigma_t * (P + rho * delta)) + L;
    } else {
        L = A + S * delta;
        o = base.rgb + L;
    }
#else
    vec3 S = fx_bilerp_s(uv, k);
    if (u_energy != 0 && u_sigma_t.x == u_sigma_t.y && u_sigma_t.y == u_sigma_t.z) {
        // grey: one exp per factor (the same values)
        float st = u_sigma_t.x;
        L = A + exp(-st * (t_s / cs)) * S * (delta * lg_medium_segment(st * delta));
        o = base.rgb * exp(-st * d) + L;
    } else if (u_energy != 0) {
        L = A + exp(-u_sigma_t * (t_s / cs)) * S * delta * lg_medium_segment3(u_sigma_t * delta);
        o = base.rgb * exp(-u_sigma_t * d) + L;
    } else {
        L = A + S * delta;
        o = base.rgb + L;
    }
#endif
    imageStore(u_inscatter, px, vec4(L, 1.0));
    imageStore(u_out, px, vec4(o, base.a));
}
