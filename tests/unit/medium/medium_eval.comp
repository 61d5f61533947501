#version 450
// Evaluates shaders/common/medium.glsl on a table of inputs for tests/unit/medium
// (test_medium_devices.c). Per record: args = (op, slicing, x, unused), map = the slice
// map (near, far, near_offset, depth); op 0 lg_hg_phase(g = map.x, c = x), 1
// lg_medium_segment(x), 2 lg_slice_to_depth(x), 3 lg_depth_to_slice(x), 4 the round trip
// lg_depth_to_slice(lg_slice_to_depth(x)); since ABI 3.2, with four vec4 of ext per record
// (test_medium_devices.c's layout): 5 lg_light_window(x, map.x), 6 lg_spot_cone(x, map.x,
// map.y), 7 lg_local_falloff (ext0 = q, range; ext1 = axis, is_spot; ext2 = p; map.xy =
// cone), 8 lg_point_inscatter (ext0 = o, t0; ext1 = w, t1; ext2 = q, range; ext3 = axis,
// is_spot; map = cos_inner, cos_outer, g, sigma_t; x = nodes).
#include "medium.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Args { vec4 args[]; };
layout(std430, binding = 1) readonly buffer Maps { vec4 maps[]; };
layout(std430, binding = 2) writeonly buffer Results { float results[]; };
layout(std430, binding = 3) readonly buffer Ext { vec4 ext[]; };
layout(location = 0) uniform uint u_count;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count)
        return;
    int op = int(args[i].x), slicing = int(args[i].y);
    float x = args[i].z;
    vec4 m = maps[i];
    float r = 0.0;
    if (op == 0)
        r = lg_hg_phase(m.x, x);
    else if (op == 1)
        r = lg_medium_segment(x);
    else if (op == 2)
        r = lg_slice_to_depth(slicing, m, x);
    else if (op == 3)
        r = lg_depth_to_slice(slicing, m, x);
    else if (op == 4)
        r = lg_depth_to_slice(slicing, m, lg_slice_to_depth(slicing, m, x));
    else if (op == 5)
        r = lg_light_window(x, m.x);
    else if (op == 6)
        r = lg_spot_cone(x, m.x, m.y);
    else if (op == 7) {
        vec4 e0 = ext[4 * i], e1 = ext[4 * i + 1], e2 = ext[4 * i + 2];
        vec3 tl;
        float d;
        r = lg_local_falloff(e0.xyz, e0.w, e1.w != 0.0, e1.xyz, m.xy, e2.xyz, tl, d);
    } else {
        vec4 e0 = ext[4 * i], e1 = ext[4 * i + 1], e2 = ext[4 * i + 2], e3 = ext[4 * i + 3];
        r = lg_point_inscatter(e0.xyz, e1.xyz, e0.w, e1.w, e2.xyz, e2.w, e3.w != 0.0, e3.xyz,
                               m.xy, m.z, m.w, int(x));
    }
    results[i] = r;
}
