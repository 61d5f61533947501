// shaders/common/medium.cl: lightgraph/medium.h in OpenCL C 1.2, concatenated before a
// plugin's kernels. The C float functions (sdk/src/medium.c) and shaders/common/
// medium.glsl are its twins; tests/unit/medium holds them together. Conventions and units
// in medium.h.
#ifndef LG_MEDIUM_CL
#define LG_MEDIUM_CL

#define LG_MEDIUM_PI 3.14159265358979323846f
#define LG_HG_G_MAX 0.999999f
#define LG_SLICING_UNIFORM_CLIP 1
#define LG_SLICING_EXPONENTIAL 2

float lg_hg_phase(float g, float c)
{
    g = clamp(g, -LG_HG_G_MAX, LG_HG_G_MAX);
    c = clamp(c, -1.0f, 1.0f);
    float den = g >= 0.0f ? (1.0f - g) * (1.0f - g) + 2.0f * g * (1.0f - c)
                          : (1.0f + g) * (1.0f + g) - 2.0f * g * (1.0f + c);
    return (1.0f - g) * (1.0f + g) / (4.0f * LG_MEDIUM_PI * den * sqrt(den));
}

float lg_medium_segment(float tau)
{
    if (!(tau > 0.0f))
        return 1.0f;
    if (tau < 0.25f)
        return 1.0f - tau * (0.5f - tau * (1.0f / 6.0f - tau * (
               1.0f / 24.0f - tau * (1.0f / 120.0f - tau * (1.0f / 720.0f)))));
    return (1.0f - exp(-tau)) / tau;
}

// map = (near, far, near_offset, depth)
float lg_slice_to_depth(int slicing, float4 map, float z)
{
    float near = map.x, far = map.y, off = map.z, D = map.w;
    if (slicing == LG_SLICING_EXPONENTIAL) {
        if (D <= 1.0f)
            return near + z * (far - near);
        if (z <= 1.0f)
            return near + z * (off - near);
        return off * pow(far / off, (z - 1.0f) / (D - 1.0f));
    }
    return 1.0f / (1.0f / near + (z / D) * (1.0f / far - 1.0f / near));
}

float lg_depth_to_slice(int slicing, float4 map, float t)
{
    float near = map.x, far = map.y, off = map.z, D = map.w;
    if (slicing == LG_SLICING_EXPONENTIAL) {
        if (D <= 1.0f)
            return (t - near) / (far - near);
        if (t <= off)
            return (t - near) / (off - near);
        return 1.0f + (D - 1.0f) * log(t / off) / log(far / off);
    }
    if (!(t > 0.0f))
        return 0.0f;
    return D * (1.0f / t - 1.0f / near) / (1.0f / far - 1.0f / near);
}

#endif
