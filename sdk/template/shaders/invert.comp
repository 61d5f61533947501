#version 450
// template_invert on GL (backend = gl): one invocation per pixel,
// out.rgb = max(0, white - in.rgb), out.a = in.a. The formula is in common/invert.glsl,
// which embed.py pastes here at build time (meson.build passes -I shaders/common).

layout(local_size_x = 16, local_size_y = 16) in;

#include "invert.glsl"

layout(binding = 0, rgba32f) uniform readonly image2D u_in;
layout(binding = 1, rgba32f) uniform writeonly image2D u_out;
layout(location = 0) uniform ivec2 u_size;
layout(location = 1) uniform float u_white;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    vec4 c = imageLoad(u_in, p);
    imageStore(u_out, p, vec4(template_invert(c.rgb, u_white), c.a));
}
