#version 450
// Evaluates the lighting functions of shaders/common/phong.glsl on an array of cases, for
// tests/unit/phong/ to compare with the C twin (plugins/phong/phong_model.h). Layout:
// phong_cases.h.
#include "phong.glsl"

layout(local_size_x = 64) in;

struct Case {
    vec4 N, V, L;   // xyz: lg_phong_direct's vectors
    vec4 Ii;        // xyz: light intensity
    vec4 mat;       // ka, kd, ks, n
    vec4 od, os;    // xyz: colours
    vec4 nrm;       // xyz: lg_safe_normalize's input; w: n_eff for lg_phong_direct
    vec4 fb;        // xyz: lg_safe_normalize's fallback
    vec4 s;         // r, K (lg_depth_cue), x, n (lg_spec_pow)
    ivec4 model;    // x: spec_model
};

struct Result {
    vec4 direct;     // xyz
    vec4 ambient;    // xyz (Ia = Ii)
    vec4 normalized; // xyz
    vec4 scalars;    // lg_depth_cue, lg_spec_pow
};

layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
layout(location = 0) uniform uint u_count;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count)
        return;
    Case c = cases[i];
    LgPhongMaterial m = LgPhongMaterial(c.mat.x, c.mat.y, c.mat.z, c.mat.w, c.od.xyz, c.os.xyz);
    Result r;
    r.direct = vec4(lg_phong_direct(c.N.xyz, c.V.xyz, c.L.xyz, c.Ii.xyz, m, c.model.x, c.nrm.w), 0.0);
    r.ambient = vec4(lg_phong_ambient(c.Ii.xyz, m), 0.0);
    r.normalized = vec4(lg_safe_normalize(c.nrm.xyz, c.fb.xyz), 0.0);
    r.scalars = vec4(lg_depth_cue(c.s.x, c.s.y), lg_spec_pow(c.s.z, c.s.w), 0.0, 0.0);
    results[i] = r;
}
