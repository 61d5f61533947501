#version 450
// Reinhard tone curve (lightgraph, reinhard): one invocation per pixel.
//
//   x  = s L (u_mode 0, luminance)  or  s c per channel (u_mode 1, rgb)
//   Ld = x / (1 + x), or min(1, x (1 + x / Lwhite^2) / (1 + x)) with a white point
//   out = (c / L) Ld (luminance)    or  Ld per channel (rgb)
//
// s is read from the Result block that reinhard_reduce.comp's stage 2 wrote: no host
// round trip between the reduction and the map. Bad pixels follow
// plugins/reinhard/reinhard_cpu.h: NaN and negative channels read as 0; a +Inf channel
// gives 1, and in luminance mode the other channels of that pixel 0. Alpha passes
// through. The policy is selects (mix with a bvec), not branches, so llvmpipe's SIMD
// lanes stay together; u_mode is uniform. Work-groups of 64x1 along rows
// (plugins/reinhard/reinhard_launch.h): contiguous loads and stores.
// Defines: LG_IN_FORMAT (rgba32f, rgba16f, or rgba8 with LG_IN_RGBE for rgbe8 input).
#include "rgbe.glsl"

layout(local_size_x = 64, local_size_y = 1) in;

layout(binding = 0, LG_IN_FORMAT) uniform readonly image2D u_in;
#ifdef LG_IN_RGBE
// rgbe8: the RGBA8 texel's bytes decoded (shaders/common/rgbe.glsl); alpha 1
#define rh_in(p) vec4(lg_rgbe_decode_unorm(imageLoad(u_in, p)), 1.0)
#else
#define rh_in(p) imageLoad(u_in, p)
#endif
layout(binding = 1, rgba32f) uniform writeonly image2D u_out;
layout(std430, binding = 1) readonly buffer Result {
    float sum;
    uint valid, nonfinite, negative;
    float lavg, la;
    float scale;     // a / Lavg (or a / La)
    uint have_la;
} result;
layout(location = 0) uniform ivec2 u_size;
layout(location = 2) uniform float u_inv_white2; // 1 / Lwhite^2, 0 = no white point
layout(location = 3) uniform int u_mode;         // 0 luminance, 1 rgb
layout(location = 4) uniform vec3 u_w;           // luminance weights

// x >= 0; +Inf -> 1
vec3 lg_curve(vec3 x)
{
    vec3 g = x / (1.0 + x);
    g = min(vec3(1.0), g * (1.0 + x * u_inv_white2)); // u_inv_white2 = 0: g <= 1 stays
    return mix(g, vec3(1.0), equal(floatBitsToUint(x), uvec3(0x7f800000u)));
}

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= u_size.x || p.y >= u_size.y)
        return;
    float s = result.scale;
    vec4 src = rh_in( p);
    uvec3 b = floatBitsToUint(src.rgb);
    bvec3 pinf = equal(b, uvec3(0x7f800000u));
    // NaN, negative and +-Inf read as 0 (finite by the bits)
    bvec3 fin = notEqual(b & uvec3(0x7f800000u), uvec3(0x7f800000u));
    vec3 c = mix(vec3(0.0), src.rgb, bvec3(uvec3(fin) & uvec3(greaterThanEqual(src.rgb, vec3(0.0)))));
    vec3 o;
    if (u_mode == 1) {
        o = lg_curve(s * c);
    } else {
        // both weight sets sum to at most 1 in float: L <= max(c), never Inf
        float l = u_w.r * c.r + u_w.g * c.g + u_w.b * c.b;
        float ld = lg_curve(vec3(s * l)).x;
        o = l > 0.0 ? c / l * ld : vec3(0.0);
        // grey: c / L is 1 exactly, but not in float (L's rounding makes it 1 + 1 ulp, so a
        // bright grey would map to 1.0000001): Ld itself
        o = (c.r == c.g && c.g == c.b) ? vec3(ld) : o;
        o = any(pinf) ? vec3(0.0) : o; // lim c Ld / L as L -> Inf: 0 but the Inf channels
    }
    o = mix(o, vec3(1.0), pinf);
    imageStore(u_out, p, vec4(o, src.a));
}
