#version 450
// volumetric_froxel, pass 2 of 3: the accumulation (plugins/volumetric_froxel/froxel.h,
// step 2; seed 2, eq. 12). One invocation per column (i, j), front to back over the D
// slices; slice k spans view depths [t_k, t_{k+1}] with t_0 = 0 (the eye) and t_k = T(k):
//
//   thesis:            A_k = A_{k-1} + S_k Delta_k                              Tr_k = 1
//   energy_conserving: A_k = A_{k-1} + Tr_{k-1} S_k Delta_k seg(sigma_t Delta_k)
//                      Tr_k = Tr_{k-1} exp(-sigma_t Delta_k)
//
// Delta_k = (t_{k+1} - t_k) / cos_ij. The grid gets (A_k, mean of Tr_k) at (i, j, k).
// Work-groups of 8x8 columns: each step k reads and writes one 8x8 tile of a slice, so
// neighbouring invocations touch neighbouring texels.
#include "froxel_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(binding = 0, rgba32f) uniform readonly image3D u_s;      // this frame's S
layout(binding = 1, rgba32f) uniform writeonly image3D u_out;   // the grid

uniform ivec3 u_grid;
uniform mat4 u_inv_vp;
uniform vec3 u_eye;
uniform vec3 u_fwd;
uniform int u_slicing;
uniform vec4 u_map;
uniform vec3 u_sigma_t;
uniform int u_energy;        // 1: energy_conserving, 0: thesis

void main()
{
    ivec2 c = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(c, u_grid.xy)))
        return;
    vec3 w = fx_ray(u_inv_vp, u_eye, fx_ndc(c, u_grid.xy));
    float cs = dot(w, u_fwd);
    vec3 A = vec3(0.0), Tr = vec3(1.0);
    float t0 = 0.0;
    for (int k = 0; k < u_grid.z; k++) {
        float t1 = lg_slice_to_depth(u_slicing, u_map, float(k + 1));
        float delta = (t1 - t0) / cs;
        vec3 S = imageLoad(u_s, ivec3(c, k)).rgb;
        if (u_energy != 0) {
            vec3 tau = u_sigma_t * delta;
            A += Tr * S * delta * lg_medium_segment3(tau);
            Tr *= exp(-tau);
        } else {
            A += S * delta;
        }
        imageStore(u_out, ivec3(c, k), vec4(A, (Tr.x + Tr.y + Tr.z) / 3.0));
        t0 = t1;
    }
}
