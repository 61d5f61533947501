#version 450 core
// The preview's fragment stage (plugins/preview): unlit base colour, world normal or
// linearised depth.

in vec3 v_normal;
in float v_view_depth;

layout(location = 3) uniform int u_mode;        // 0 base_color, 1 normals, 2 depth
layout(location = 4) uniform vec3 u_base_color; // the material's, linear RGB
layout(location = 5) uniform vec2 u_near_far;   // znear, zfar of the projection

layout(location = 0) out vec4 o_color;

void main()
{
    if (u_mode == 0) {
        o_color = vec4(u_base_color, 1.0);
    } else if (u_mode == 1) {
        // a degenerate normal (zero after interpolation) shows as mid grey, not NaN
        float l = length(v_normal);
        vec3 n = l > 0.0 ? v_normal / l : vec3(0.0);
        o_color = vec4(n * 0.5 + 0.5, 1.0);
    } else {
        float t = (v_view_depth - u_near_far.x) / (u_near_far.y - u_near_far.x);
        o_color = vec4(vec3(clamp(t, 0.0, 1.0)), 1.0);
    }
}
