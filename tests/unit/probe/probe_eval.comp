#version 450
// Evaluates shaders/common/probe.glsl on an array of directions for tests/unit/probe/
// (test_probe_devices.c): per direction, the lookup (nearest or bilinear) and the
// coordinates of the direction.
#include "probe.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Dirs { vec4 dirs[]; };
layout(std430, binding = 1) writeonly buffer Results { vec4 results[]; }; // value, coord

layout(binding = 0) uniform sampler2D u_tex2d;
layout(binding = 1) uniform samplerCube u_cube;
layout(location = 0) uniform uint u_count;
layout(location = 1) uniform int u_layout;
layout(location = 2) uniform int u_bilinear;
layout(location = 3) uniform mat3 u_rotation; // probe -> world

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count)
        return;
    vec3 d = lg_probe_from_world(u_rotation, dirs[i].xyz);
    vec4 v;
    if (u_layout == LG_PROBE_CUBE)
        v = lg_probe_cube(u_cube, 0.0, d);
    else if (u_bilinear != 0)
        v = lg_probe_2d_bilinear(u_tex2d, u_layout, 0, d);
    else
        v = lg_probe_2d_nearest(u_tex2d, u_layout, 0, d);
    results[2 * i] = v;
    results[2 * i + 1] = vec4(lg_probe_dir_to_coord(u_layout, d), 0.0);
}
