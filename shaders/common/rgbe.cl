// shaders/common/rgbe.cl: Ward's RGBE (LG_FORMAT_RGBE8) and the rgba16f range in OpenCL C
// 1.2, the twins of lg_rgbe_encode / lg_rgbe_decode (sdk/src/rgbe.c) and of
// shaders/common/rgbe.glsl. Embedded byte for byte (lg_src_rgbe_cl); a kernel is built
// from this text followed by its own (lg_cl_source_join, lightgraph/cl.h).
//
// An rgbe8 image on CL is a buffer of uchar4 (the CPU's bytes): store
// lg_rgbe_encode(rgb), read with lg_rgbe_decode. lg_half_range clamps what an rgba16f
// store would turn into +Inf (above 65504) to 65504 (below -65504 to -65504), and NaN to 0,
// as lg_pixels_from_rgba32f does on the CPU. Byte for byte the C encoder's results
// (tests/unit/formats/), denormals included on PoCL; a device that flushes denormals
// differs as rgbe.glsl says.
#ifndef LG_RGBE_CL
#define LG_RGBE_CL

inline float lg_rgbe_channel(float c)
{
    return c > 0.0f ? c : 0.0f;
}

inline uchar4 lg_rgbe_encode(float3 rgb)
{
    float3 c = (float3)(lg_rgbe_channel(rgb.x), lg_rgbe_channel(rgb.y), lg_rgbe_channel(rgb.z));
    float m = fmax(c.x, fmax(c.y, c.z));
    // below FLT_MIN (denormals, which a device may flush) is black, as in the C encoder
    if (!(m >= FLT_MIN))
        return (uchar4)(0, 0, 0, 0);
    int e = 0;
    int saturate = isinf(m);
    if (!saturate) {
        float mant = frexp(m, &e);
        if (floor(mant * 256.0f + 0.5f) >= 256.0f)
            e++;
        saturate = e > 127;
    }
    if (saturate) {
        // float steps without contraction into a fused multiply-add, as the C encoder
#pragma OPENCL FP_CONTRACT OFF
        float3 ratio = isinf(m) ? (float3)(isinf(c.x) ? 1.0f : 0.0f, isinf(c.y) ? 1.0f : 0.0f,
                                           isinf(c.z) ? 1.0f : 0.0f)
                                : c / m;
        float3 scaled = ratio * 255.0f;
        float3 q = floor(scaled + 0.5f);
        return (uchar4)((uchar)q.x, (uchar)q.y, (uchar)q.z, (uchar)255);
    }
    float3 q = (float3)(floor(ldexp(c.x, 8 - e) + 0.5f), floor(ldexp(c.y, 8 - e) + 0.5f),
                        floor(ldexp(c.z, 8 - e) + 0.5f));
    q = fmin(q, (float3)(255.0f));
    return (uchar4)((uchar)q.x, (uchar)q.y, (uchar)q.z, (uchar)(e + 128));
}

inline float3 lg_rgbe_decode(uchar4 b)
{
    int e = (int)b.w;
    if (e == 0)
        return (float3)(0.0f);
    return (float3)(ldexp((float)b.x, e - 136), ldexp((float)b.y, e - 136),
                    ldexp((float)b.z, e - 136));
}

// Finite, within +-65504; NaN 0 (it fails every comparison).
inline float lg_half_range1(float v)
{
    return v <= 65504.0f ? (v >= -65504.0f ? v : (v < -65504.0f ? -65504.0f : 0.0f))
                         : (v > 65504.0f ? 65504.0f : 0.0f);
}

inline float4 lg_half_range(float4 v)
{
    return (float4)(lg_half_range1(v.x), lg_half_range1(v.y), lg_half_range1(v.z),
                    lg_half_range1(v.w));
}

// How many channels of v lg_half_range changes (NaN, beyond +-65504): what a producer
// adds to its count (atomic_add) to report once, as lg_pixels_from_rgba32f counts.
inline uint lg_half_range_count(float4 v)
{
    return (uint)(!(v.x >= -65504.0f && v.x <= 65504.0f)) +
           (uint)(!(v.y >= -65504.0f && v.y <= 65504.0f)) +
           (uint)(!(v.z >= -65504.0f && v.z <= 65504.0f)) +
           (uint)(!(v.w >= -65504.0f && v.w <= 65504.0f));
}

#endif
