#version 450
// Evaluates shaders/common/medium.glsl on a table of inputs for tests/unit/medium
// (test_medium_devices.c). Per record: args = (op, slicing, x, unused), map = the slice
// map (near, far, near_offset, depth); op 0 lg_hg_phase(g = map.x, c = x), 1
// lg_medium_segment(x), 2 lg_slice_to_depth(x), 3 lg_depth_to_slice(x), 4 the round trip
// lg_depth_to_slice(lg_slice_to_depth(x)).
#include "medium.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Args { vec4 args[]; };
layout(std430, binding = 1) readonly buffer Maps { vec4 maps[]; };
layout(std430, binding = 2) writeonly buffer Results { float results[]; };
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
    else
        r = lg_depth_to_slice(slicing, m, lg_slice_to_depth(slicing, m, x));
    results[i] = r;
}
