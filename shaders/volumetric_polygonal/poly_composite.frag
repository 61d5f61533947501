#version 450
// volumetric_polygonal, step 3: out = base e^(-sigma_t d) + L_v, depth = base's.
// d as in poly_volume.frag (the fog's length along the pixel's ray).
#include "medium.glsl"

layout(binding = 0) uniform sampler2D u_base;
layout(binding = 1) uniform sampler2D u_base_depth;
layout(binding = 2) uniform sampler2D u_inscatter;
#include "poly_view.glsl"

layout(location = 0) out vec4 o_color;

vec3 unproject(vec2 xy, float z)
{
    vec4 p = u_inv_view_proj * vec4(2.0 * xy / u_size - 1.0, z, 1.0);
    return p.xyz / p.w;
}

void main()
{
    vec2 xy = gl_FragCoord.xy;
    ivec2 px = ivec2(xy);
    vec3 w = normalize(unproject(xy, 0.0) - u_eye);
    float depth = texelFetch(u_base_depth, px, 0).r;
    float d = 3.0e38;
    if (depth < 1.0)
        d = length(unproject(xy, 2.0 * depth - 1.0) - u_eye);
    float c = dot(w, u_forward);
    if (c > 0.0)
        d = min(d, u_z_limit / c);
    vec4 base = texelFetch(u_base, px, 0);
    vec3 T = exp(-u_sigma_t * d); // 0 where d is infinite and sigma_t > 0, 1 at sigma_t 0
    T = mix(T, vec3(1.0), equal(u_sigma_t, vec3(0.0)));
    o_color = vec4(base.rgb * T + texelFetch(u_inscatter, px, 0).rgb, base.a);
    gl_FragDepth = depth;
}
