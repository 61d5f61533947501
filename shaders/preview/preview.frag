#version 450 core
// The preview's fragment stage (plugins/preview): unlit base colour (the material's factor
// times its base colour texture), world normal or linearised depth; alpha-masked texels
// (MASK below the cutoff, BLEND below one half) are no surface in every mode. With
// LG_WIREFRAME, lines of u_wire.x pixels in colour u_wire_color over the surface.

#include "material.glsl"

#ifdef LG_WIREFRAME
in vec3 g_normal;
in float g_view_depth;
in vec2 g_uv0, g_uv1;
noperspective in vec3 g_edge;
#define v_normal g_normal
#define v_view_depth g_view_depth
#define v_uv0 g_uv0
#define v_uv1 g_uv1
layout(location = 7) uniform float u_wire_width; // line width in pixels
layout(location = 8) uniform vec3 u_wire_color;  // linear RGB
#else
in vec3 v_normal;
in float v_view_depth;
in vec2 v_uv0, v_uv1;
#endif

layout(location = 3) uniform int u_mode;      // 0 base_color, 1 normals, 2 depth
layout(location = 5) uniform vec2 u_near_far; // znear, zfar of the projection

layout(location = 0) out vec4 o_color;

void main()
{
    vec4 base = lg_mat_base_color(v_uv0, v_uv1);
    if (lg_mat_cut(base.a))
        discard;
    if (u_mode == 0) {
        o_color = vec4(base.rgb, 1.0);
    } else if (u_mode == 1) {
        // a degenerate normal (zero after interpolation) shows as mid grey, not NaN
        float l = length(v_normal);
        vec3 n = l > 0.0 ? v_normal / l : vec3(0.0);
        o_color = vec4(n * 0.5 + 0.5, 1.0);
    } else {
        float t = (v_view_depth - u_near_far.x) / (u_near_far.y - u_near_far.x);
        o_color = vec4(vec3(clamp(t, 0.0, 1.0)), 1.0);
    }
#ifdef LG_WIREFRAME
    // coverage of a line of width w centred on the nearest edge, over one pixel's width
    float d = min(g_edge.x, min(g_edge.y, g_edge.z));
    float cover = clamp(0.5 * u_wire_width - d + 0.5, 0.0, 1.0);
    o_color.rgb = mix(o_color.rgb, u_wire_color, cover);
#endif
}
