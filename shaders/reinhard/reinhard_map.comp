#version 450
// Reinhard tone curve (lightgraph, reinhard): one invocation per pixel.
//
//   x  = s L (u_mode 0, luminance)  or  s c per channel (u_mode 1, rgb)
//   Ld = x / (1 + x), or min(1, x (1 + x / Lwhite^2) / (1 + x)) with a white point
//   out = (c / L) Ld (luminance)    or  Ld per channel (rgb)
//
// Bad pixels follow plugins/reinhard/reinhard_cpu.h: NaN and negative channels read as
// 0; a +Inf channel gives 1, and in luminance mode the other channels of that pixel 0.
// Alpha passes through. Defines: LG_IN_FORMAT (rgba32f or rgba16f).

layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = 0, LG_IN_FORMAT) uniform readonly image2D u_in;
layout(binding = 1, rgba32f) uniform writeonly image2D u_out;
layout(location = 0) uniform ivec2 u_size;
layout(location = 1) uniform float u_scale;      // a / Lavg (or a / La)
layout(location = 2) uniform float u_inv_white2; // 1 / Lwhite^2, 0 = no white point
layout(location = 3) uniform int u_mode;         // 0 luminance, 1 rgb
layout(location = 4) uniform vec3 u_w;           // luminance weights

bool lg_is_nan(float v)
{
    uint b = floatBitsToUint(v);
    return (b & 0x7f800000u) == 0x7f800000u && (b & 0x007fffffu) != 0u;
}

bool lg_is_pinf(float v)
{
    return floatBitsToUint(v) == 0x7f800000u;
}

float lg_curve(float x)
{
    if (lg_is_pinf(x))
        return 1.0;
    float g = x / (1.0 + x);
    if (u_inv_white2 > 0.0)
        g = min(1.0, g * (1.0 + x * u_inv_white2));
    return g;
}

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    vec4 src = imageLoad(u_in, p);
    vec3 c;
    bvec3 inf;
    for (int k = 0; k < 3; k++) {
        float v = src[k];
        inf[k] = lg_is_pinf(v);
        c[k] = (lg_is_nan(v) || v < 0.0 || inf[k]) ? 0.0 : v;
    }
    vec3 o;
    if (u_mode == 1) {
        for (int k = 0; k < 3; k++)
            o[k] = inf[k] ? 1.0 : lg_curve(u_scale * c[k]);
    } else if (any(inf)) {
        o = vec3(inf);
    } else {
        float l = u_w.r * c.r + u_w.g * c.g + u_w.b * c.b;
        // both weight sets sum to at most 1 in float: L <= max(c), never Inf
        vec3 r = l > 0.0 ? c / l : vec3(0.0);
        o = r * lg_curve(u_scale * l);
    }
    imageStore(u_out, p, vec4(o, src.a));
}
