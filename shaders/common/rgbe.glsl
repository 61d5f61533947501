// shaders/common/rgbe.glsl: Ward's RGBE (LG_FORMAT_RGBE8) and the rgba16f range in GLSL
// 4.50, the twins of lg_rgbe_encode / lg_rgbe_decode (sdk/src/rgbe.c, lightgraph/image.h)
// and of shaders/common/rgbe.cl. #include "rgbe.glsl".
//
// An rgbe8 image is an RGBA8 (unorm) texture: store lg_rgbe_encode(rgb) / 255.0 with
// imageStore into a layout(rgba8) image, read texelFetch(...) and decode with
// lg_rgbe_decode_unorm. The byte values are those of the C encoder (round to nearest, no
// half-step offset, NaN and negative channels 0, +Inf and values at or above 2^127
// saturated, a largest channel below FLT_MIN black); tests/unit/formats/ checks it byte
// for byte. Intended difference: a GPU that flushes denormals (llvmpipe does) reads a
// denormal channel beside a normal largest one as 0, where the C encoder may give it a
// small mantissa, and lg_rgbe_decode of exponent bytes below 10 (values below FLT_MIN)
// gives 0 where the C decoder gives the denormal.
//
// lg_half_range(v): what an rgba16f target can hold. Values above 65504 (the largest
// half) would become +Inf on the store; they are clamped to 65504 instead (and below
// -65504 to -65504), NaN to 0 (lightgraph/image.h, "Pixel formats"; the C twin is
// lg_pixels_from_rgba32f). A producer counts the values it changes and reports them once.
#ifndef LG_RGBE_GLSL
#define LG_RGBE_GLSL

// NaN and negative channels: 0 (a NaN fails every comparison).
float lg_rgbe_channel(float c)
{
    return c > 0.0 ? c : 0.0;
}

// The four bytes (as floats 0..255) of rgb. ldexp's exponent is at most 8 - (-125) = 133
// here, beyond GLSL's guaranteed +128: split in two so that no step is undefined.
vec4 lg_rgbe_encode(vec3 rgb)
{
    vec3 c = vec3(lg_rgbe_channel(rgb.r), lg_rgbe_channel(rgb.g), lg_rgbe_channel(rgb.b));
    float m = max(c.r, max(c.g, c.b));
    // below FLT_MIN (denormals, which a GPU may flush) is black, as in the C encoder
    if (!(m >= 1.17549435e-38))
        return vec4(0.0);
    int e = 0;
    bool saturate = isinf(m);
    if (!saturate) {
        float mant = frexp(m, e); // m = mant 2^e, mant in [0.5, 1)
        if (floor(mant * 256.0 + 0.5) >= 256.0)
            e++;
        saturate = e > 127;
    }
    if (saturate) {
        // float steps without fused multiply-add, as the C encoder computes them
        precise vec3 ratio = isinf(m) ? vec3(isinf(c.r) ? 1.0 : 0.0, isinf(c.g) ? 1.0 : 0.0,
                                             isinf(c.b) ? 1.0 : 0.0)
                                      : c / m;
        precise vec3 scaled = ratio * 255.0;
        return vec4(floor(scaled + 0.5), 255.0);
    }
    // ldexp per channel: c 2^(8-e) <= 256, while 2^(8-e) alone may overflow a float
    int e1 = (8 - e) / 2, e2 = (8 - e) - e1;
    vec3 q = vec3(floor(ldexp(ldexp(c.r, e1), e2) + 0.5), floor(ldexp(ldexp(c.g, e1), e2) + 0.5),
                  floor(ldexp(ldexp(c.b, e1), e2) + 0.5));
    return vec4(min(q, vec3(255.0)), float(e + 128));
}

// rgb from the four bytes (as floats 0..255).
vec3 lg_rgbe_decode(vec4 bytes)
{
    int e = int(bytes.a + 0.5);
    if (e == 0)
        return vec3(0.0);
    vec3 m = floor(bytes.rgb + 0.5);
    return vec3(ldexp(m.r, e - 136), ldexp(m.g, e - 136), ldexp(m.b, e - 136));
}

// rgb from an RGBA8 unorm texel as texelFetch returns it (each byte / 255).
vec3 lg_rgbe_decode_unorm(vec4 texel)
{
    return lg_rgbe_decode(texel * 255.0);
}

// What an rgba16f store keeps: finite, within +-65504; NaN 0 (it fails every comparison).
float lg_half_range1(float v)
{
    return v <= 65504.0 ? (v >= -65504.0 ? v : (v < -65504.0 ? -65504.0 : 0.0))
                        : (v > 65504.0 ? 65504.0 : 0.0);
}

vec4 lg_half_range(vec4 v)
{
    return vec4(lg_half_range1(v.r), lg_half_range1(v.g), lg_half_range1(v.b),
                lg_half_range1(v.a));
}

// How many channels of v lg_half_range changes (NaN, beyond +-65504): what a producer
// adds to its count (e.g. atomicAdd on a buffer) to report once, as lg_pixels_from_rgba32f
// counts on the CPU.
uint lg_half_range_count(vec4 v)
{
    bvec4 kept = bvec4(v.r >= -65504.0 && v.r <= 65504.0, v.g >= -65504.0 && v.g <= 65504.0,
                       v.b >= -65504.0 && v.b <= 65504.0, v.a >= -65504.0 && v.a <= 65504.0);
    return 4u - uint(kept.r) - uint(kept.g) - uint(kept.b) - uint(kept.a);
}

#endif
