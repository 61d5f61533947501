#version 450 core
// The prt node's `reflect` pass (plugins/prt): the reflect image's RGB added to the output
// (additive blending) texel for texel; alpha 0 is added, so the output's coverage stays.

uniform sampler2D u_reflect;
layout(location = 0) out vec4 o_color;

void main()
{
    o_color = vec4(texelFetch(u_reflect, ivec2(gl_FragCoord.xy), 0).rgb, 0.0);
}
