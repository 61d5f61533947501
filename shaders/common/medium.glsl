// shaders/common/medium.glsl: lightgraph/medium.h in GLSL 4.50. #include "medium.glsl".
// The C functions (sdk/src/medium.c, float versions) and shaders/common/medium.cl are its
// twins; tests/unit/medium holds them together. Conventions and units in medium.h:
// cos theta = dot(view ray direction, direction towards the light); slice maps z in
// [0, depth] <-> view depth t.
#ifndef LG_MEDIUM_GLSL
#define LG_MEDIUM_GLSL

const float LG_MEDIUM_PI = 3.14159265358979323846;
const float LG_HG_G_MAX = 0.999999;
#define LG_SLICING_UNIFORM_CLIP 1
#define LG_SLICING_EXPONENTIAL 2

// Henyey-Greenstein, 1/sr, the stable form (lightgraph/medium.h).
float lg_hg_phase(float g, float c)
{
    g = clamp(g, -LG_HG_G_MAX, LG_HG_G_MAX);
    c = clamp(c, -1.0, 1.0);
    float den = g >= 0.0 ? (1.0 - g) * (1.0 - g) + 2.0 * g * (1.0 - c)
                         : (1.0 + g) * (1.0 + g) - 2.0 * g * (1.0 + c);
    return (1.0 - g) * (1.0 + g) / (4.0 * LG_MEDIUM_PI * den * sqrt(den));
}

// (1 - e^-tau) / tau, 1 at tau <= 0; a series below 1/4 (no expm1 in GLSL).
float lg_medium_segment(float tau)
{
    if (!(tau > 0.0))
        return 1.0;
    if (tau < 0.25)
        return 1.0 - tau * (0.5 - tau * (1.0 / 6.0 - tau * (
               1.0 / 24.0 - tau * (1.0 / 120.0 - tau * (1.0 / 720.0)))));
    return (1.0 - exp(-tau)) / tau;
}
vec3 lg_medium_segment3(vec3 tau)
{
    return vec3(lg_medium_segment(tau.x), lg_medium_segment(tau.y), lg_medium_segment(tau.z));
}

// Slice maps: map = (near, far, near_offset, depth), slicing = LG_SLICING_*.
float lg_slice_to_depth(int slicing, vec4 map, float z)
{
    float near = map.x, far = map.y, off = map.z, D = map.w;
    if (slicing == LG_SLICING_EXPONENTIAL) {
        if (D <= 1.0)
            return near + z * (far - near);
        if (z <= 1.0)
            return near + z * (off - near);
        return off * pow(far / off, (z - 1.0) / (D - 1.0));
    }
    return 1.0 / (1.0 / near + (z / D) * (1.0 / far - 1.0 / near));
}

float lg_depth_to_slice(int slicing, vec4 map, float t)
{
    float near = map.x, far = map.y, off = map.z, D = map.w;
    if (slicing == LG_SLICING_EXPONENTIAL) {
        if (D <= 1.0)
            return (t - near) / (far - near);
        if (t <= off)
            return (t - near) / (off - near);
        return 1.0 + (D - 1.0) * log(t / off) / log(far / off);
    }
    if (!(t > 0.0))
        return 0.0;
    return D * (1.0 / t - 1.0 / near) / (1.0 / far - 1.0 / near);
}

#endif
