// acme_blur's bad-pixel policy on GL, included by blur.comp (`#include "acme_blur.glsl"`:
// embed.py searches the including shader's folder, then each -I folder, here
// shaders/common). Twins: acme_blur.cl (cl) and acme_sanitize in blur_cpu.c (cpu); keep
// the three alike. NaN reads as 0, +-Inf as +-FLT_MAX, and a sum beyond FLT_MAX is FLT_MAX,
// so that the output is finite. NaN is found from the bits, which no compiler may
// optimise away as it may isnan() under relaxed float rules.
const float ACME_FLT_MAX = 3.402823466e38;

vec4 acme_sanitize(vec4 v)
{
    bvec4 nan = greaterThan(floatBitsToUint(v) & 0x7fffffffu, uvec4(0x7f800000u));
    return clamp(mix(v, vec4(0.0), nan), vec4(-ACME_FLT_MAX), vec4(ACME_FLT_MAX));
}
