// acme_blur's bad-pixel policy on CL: the twin of acme_blur.glsl and of acme_sanitize in
// blur_cpu.c; keep the three alike. OpenCL C has no #include of embedded text: blur_cl.c
// gives this file to lg_cl_pass before blur.cl (lg_cl_pass_desc.sources, in order).
// NaN reads as 0, +-Inf as +-FLT_MAX, and a sum beyond FLT_MAX is FLT_MAX.
inline float4 acme_sanitize(float4 v)
{
    int4 nan = (as_int4(v) & 0x7fffffff) > 0x7f800000; // from the bits: -1 where NaN
    v = select(v, (float4)(0.0f), nan);
    return clamp(v, (float4)(-FLT_MAX), (float4)(FLT_MAX));
}
