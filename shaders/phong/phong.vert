#version 450 core
// The phong node's vertex stage (plugins/phong). One instance of one mesh per draw
// instance, the instances' matrices from a storage buffer (as plugins/preview does).
// Compiled once per shading mode with
//   LG_SHADING        0 flat, 1 gouraud, 2 phong, 3 mixed, 4 phong_half
//   LG_SV, LG_SV_ARR  shadowed lights carried as separate colours (LG_SV_ARR = max(LG_SV, 1))
// Gouraud and mixed light every vertex here (seed 1, 1.3.2): for a double-sided material
// both sides, the fragment stage picks by gl_FrontFacing (two-sided lighting).
// Varyings are matched by location: 0 position, 1 normal, 2 surface id, 3 mixed: the vertex's
// largest cos(V, R) (to the geometry stage) and the highlight flag (to the fragment stage),
// 4 front colour, 5 back colour, 6.. front shadowed colours, then back ones; then (ABI 3.1)
// LG_UV_LOC: TEXCOORD_0 and TEXCOORD_1 in one vec4, LG_UV_LOC + 1: the world tangent.

#include "phong.glsl"
#include "phong_scene.glsl"

#define LG_UV_LOC (6 + 2 * LG_SV_ARR)

layout(location = 0) in vec3 a_position; // object space
layout(location = 1) in vec3 a_normal;   // object space (the scene's, or eq. 1-13's)
layout(location = 2) in vec2 a_uv0;      // TEXCOORD_0 ((0, 0) for a mesh without)
layout(location = 3) in vec2 a_uv1;      // TEXCOORD_1
layout(location = 4) in vec4 a_tangent;  // object space, w the bitangent's sign

struct LgInstance {
    mat4 model;  // object to world
    mat4 normal; // inverse transpose of model's 3x3 (upper-left)
};
layout(std430, binding = 0) readonly buffer LgInstances {
    LgInstance lg_inst[];
};

uniform int u_first;      // this draw's first entry in the bound range of LgInstances
uniform int u_id_base;    // surface id of the draw's first instance (ids start at 1)

layout(location = 0) out vec3 v_pos; // world
layout(location = 1) out vec3 v_nrm; // world, not normalised
layout(location = 2) flat out uint v_id;
layout(location = LG_UV_LOC) out vec4 v_uv;      // TEXCOORD_0, TEXCOORD_1
layout(location = LG_UV_LOC + 1) out vec4 v_tan; // world tangent, w its sign
#if LG_SHADING == 3
// mixed: the largest cos(angle(V, R)) over the lights here, for the normal and its reverse
layout(location = 3) out vec2 v_max_cos;
#endif
#if LG_SHADING == 1 || LG_SHADING == 3
layout(location = 4) out vec3 v_c0;
layout(location = 5) out vec3 v_c0b;
layout(location = 6) out vec3 v_cs[LG_SV_ARR];
layout(location = 6 + LG_SV_ARR) out vec3 v_csb[LG_SV_ARR];
#endif

void main()
{
    LgInstance I = lg_inst[u_first + gl_InstanceID];
    vec4 world = I.model * vec4(a_position, 1.0);
    v_pos = world.xyz;
    v_nrm = mat3(I.normal) * a_normal;
    v_id = uint(u_id_base + gl_InstanceID);
    v_uv = vec4(a_uv0, a_uv1);
    v_tan = lg_mat_world_tangent(I.model, a_tangent);
    gl_Position = u_view_proj * world;
#if LG_SHADING == 1 || LG_SHADING == 3
    LgPhongMaterial m = lg_material();
    vec3 N = lg_safe_normalize(v_nrm, lg_view_vector(v_pos));
    vec3 cs[LG_SV_ARR];
    lg_shade_split(v_pos, N, m, v_c0, cs);
    v_cs = cs;
    if (u_double_sided != 0) {
        lg_shade_split(v_pos, -N, m, v_c0b, cs);
        v_csb = cs;
    } else {
        v_c0b = v_c0;
        v_csb = v_cs;
    }
#endif
#if LG_SHADING == 3
    v_max_cos = vec2(-2.0);
    if (u_ks > 0.0 && any(greaterThan(u_os, vec3(0.0))))
        v_max_cos = vec2(lg_max_cos_vr(v_pos, N), lg_max_cos_vr(v_pos, -N));
#endif
}
