// Reinhard tone mapping in OpenCL C 1.2 (lightgraph, reinhard).
//
//   rh_reduce        stage 1: each work-item sums log(delta + L) over LG_PPI pixels,
//                    counts the pixels left out and writes one partial
//   rh_reduce_final  stage 2: one work-group reduces the partials; then item 0 computes
//                    Lavg, the adaptation step and the scale into the result block
//   rh_map           the tone curve, one work-item per pixel, reading the scale from the
//                    result block (no host round trip between the reduction and the map)
//
// The same arithmetic and the same bad-pixel policy as the GL shaders and the CPU code
// (plugins/reinhard/reinhard_cpu.h); launch geometry in plugins/reinhard/reinhard_launch.h.
// Build options: -DLG_LOCAL=<work-group size of the reductions, a power of two>,
// -DLG_MAP_LOCAL=<work-group size of the map>, -DLG_PPI=<pixels per stage-1 item> and, for
// rgba16f input, -DLG_IN_HALF=1. Images are buffers of tightly packed pixels (4 floats, or
// 4 halves).
//
// Speed (PoCL on CPUs, and GPUs alike): no branch per pixel (the policy is select()s),
// float4 loads and stores, consecutive work-items touch consecutive pixels, no barrier in
// the pixel kernels, and a logarithm of our own (rh_log). Measurements on PoCL 3.1, 2
// CPUs, 2048x1396, are in plugins/reinhard/README.md ("Speed").

#ifndef LG_LOCAL
#define LG_LOCAL 256
#endif
#ifndef LG_MAP_LOCAL
#define LG_MAP_LOCAL 256
#endif
#ifndef LG_PPI
#define LG_PPI 1
#endif

typedef struct rh_partial {
    float sum;
    uint valid;
    uint nonfinite;
    uint negative;
} rh_partial;

// plugins/reinhard/reinhard_launch.h, rh_result
typedef struct rh_result {
    float sum;
    uint valid;
    uint nonfinite;
    uint negative;
    float lavg;
    float la;
    float scale;
    uint have_la;
} rh_result;

// By the bits, so that no option may assume finite floats: 1 or 0.
inline int rh_finite(float v)
{
    return (as_uint(v) & 0x7f800000u) != 0x7f800000u;
}

inline int4 rh_finite4(float4 v)
{
    return (as_int4(v) & (int4)0x7f800000) != (int4)0x7f800000; // -1 where finite
}

// The natural logarithm of x > 0 (finite, normal): Cephes' logf (S. L. Moshier), as in
// plugins/reinhard/reinhard_cpu.c, about 1 ulp. Ours, not log(): PoCL 3.1's log() is not
// vectorised and cost ~100 ns a call, which made stage 1 take 130-200 ms on 2.86
// Mpixels; this one is plain arithmetic that vectorises with the work-item loop.
inline float rh_log(float x)
{
    uint b = as_uint(x);
    int e = (int)((b >> 23) & 0xffu) - 126;            // x = m 2^e, m in [0.5, 1)
    float m = as_float((b & 0x007fffffu) | 0x3f000000u);
    int small = m < 0.70710678118654752f;              // then use 2m in [sqrt(1/2), 1)
    e -= small;
    m = small ? m + m : m;
    float f = m - 1.0f;
    float z = f * f;
    float y = 7.0376836292e-2f;
    y = y * f - 1.1514610310e-1f;
    y = y * f + 1.1676998740e-1f;
    y = y * f - 1.2420140846e-1f;
    y = y * f + 1.4249322787e-1f;
    y = y * f - 1.6668057665e-1f;
    y = y * f + 2.0000714765e-1f;
    y = y * f - 2.4999993993e-1f;
    y = y * f + 3.3333331174e-1f;
    y = y * f * z;
    float fe = (float)e;
    y += -2.12194440e-4f * fe;
    y += -0.5f * z;
    return f + y + 0.693359375f * fe;
}

inline float4 rh_load(const __global float *in, uint i)
{
#ifdef LG_IN_HALF
    return vload_half4(i, (const __global half *)in);
#else
    return vload4(i, in);
#endif
}

inline void rh_local_reduce(__local float *s_sum, __local uint *s_valid,
                            __local uint *s_nonfinite, __local uint *s_negative, uint lid)
{
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint s = LG_LOCAL / 2; s > 0; s >>= 1) {
        if (lid < s) {
            s_sum[lid] += s_sum[lid + s];
            s_valid[lid] += s_valid[lid + s];
            s_nonfinite[lid] += s_nonfinite[lid + s];
            s_negative[lid] += s_negative[lid + s];
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
}

// Each work-item sums LG_PPI pixels LG_LOCAL apart (neighbouring items read neighbouring
// pixels) in an unrolled loop, with no branch per pixel (the tail of the image is masked:
// clamped index, ok = 0), and writes its own partial: no local memory, no barrier (on
// PoCL a barrier splits the kernel into work-item loops that keep every private value in
// memory between them; the local-memory tree this replaced took 40-56 ms, this 12 ms).
// Stage 2 then reduces one partial per work-item (1/LG_PPI of a 16-byte value per pixel:
// 6% more traffic with LG_PPI = 16).
__kernel void rh_reduce(const __global float *in, uint n, float delta, float4 w,
               __global rh_partial *part)
{
    uint base = get_group_id(0) * (LG_LOCAL * LG_PPI) + get_local_id(0);
    float sum = 0.0f;
    uint valid = 0, nonfinite = 0, negative = 0;
    #pragma unroll
    for (uint k = 0; k < LG_PPI; k++) {
        uint i = base + k * LG_LOCAL;
        int inside = i < n;
        float4 c = rh_load(in, inside ? i : n - 1);
        float l = w.x * c.x + w.y * c.y + w.z * c.z;
        int fin = rh_finite(c.x) & rh_finite(c.y) & rh_finite(c.z) & rh_finite(l);
        int neg = fin & (l < 0.0f);
        int ok = fin & !neg & inside;
        sum += rh_log(ok ? delta + l : 1.0f); // log(1) = 0 for the pixels left out
        valid += ok;
        nonfinite += (!fin) & inside;
        negative += neg & inside;
    }
    rh_partial p = { sum, valid, nonfinite, negative };
    part[get_global_id(0)] = p;
}

// adapt: 0 off, 1 on; adapt_k = 1 - rate^(60 dt) (computed on the host in double);
// adapt_from: La before the first frame (0: the first Lavg); reset: forget La (the host
// sets it on the first frame after prepare).
__kernel __attribute__((reqd_work_group_size(LG_LOCAL, 1, 1)))
void rh_reduce_final(const __global rh_partial *part, uint count, __global rh_result *result,
                     float key, int adapt, float adapt_k, float adapt_from, int reset)
{
    __local float s_sum[LG_LOCAL];
    __local uint s_valid[LG_LOCAL], s_nonfinite[LG_LOCAL], s_negative[LG_LOCAL];
    uint lid = get_local_id(0);
    float sum = 0.0f;
    uint valid = 0, nonfinite = 0, negative = 0;
    for (uint i = lid; i < count; i += LG_LOCAL) {
        sum += part[i].sum;
        valid += part[i].valid;
        nonfinite += part[i].nonfinite;
        negative += part[i].negative;
    }
    s_sum[lid] = sum;
    s_valid[lid] = valid;
    s_nonfinite[lid] = nonfinite;
    s_negative[lid] = negative;
    rh_local_reduce(s_sum, s_valid, s_nonfinite, s_negative, lid);
    if (lid == 0) {
        rh_result r = *result;
        r.sum = s_sum[0];
        r.valid = s_valid[0];
        r.nonfinite = s_nonfinite[0];
        r.negative = s_negative[0];
        int ok = r.valid > 0;
        r.lavg = ok ? exp(r.sum / (float)r.valid) : 1.0f;
        float l = r.lavg;
        if (adapt) {
            if (reset || !r.have_la) {
                r.la = adapt_from > 0.0f ? adapt_from : r.lavg;
                r.have_la = 1;
            }
            if (ok)
                r.la = r.la + (r.lavg - r.la) * adapt_k;
            l = r.la;
        }
        r.scale = key / l;
        *result = r;
    }
}

inline float4 rh_curve4(float4 x, float inv_white2)
{
    float4 g = x / (1.0f + x);
    g = fmin(1.0f, g * (1.0f + x * inv_white2)); // inv_white2 = 0: g <= 1 stays
    return select(g, (float4)1.0f, as_int4(x) == (int4)0x7f800000); // x = +Inf -> 1
}

// mode: 0 luminance, 1 rgb (uniform: one branch per work-item, the same for all)
// No reqd_work_group_size: with it, PoCL 3.1 ran this kernel at half the speed (16 ms
// against 7.1-7.4 ms for groups of 64 to 4096 items on 2048x1396, measured).
__kernel void rh_map(const __global float *in, __global float4 *out, uint n,
            const __global rh_result *result, float inv_white2, int mode, float4 w)
{
    uint i = get_global_id(0);
    if (i >= n)
        return;
    float scale = result->scale;
    float4 src = rh_load(in, i);
    int4 bits = as_int4(src);
    int4 pinf = bits == (int4)0x7f800000;                    // +Inf channels
    // NaN, negative and +-Inf read as 0
    float4 c = select((float4)0.0f, src, rh_finite4(src) & (src >= 0.0f));
    float4 o;
    if (mode == 1) {
        o = rh_curve4(scale * c, inv_white2);
    } else {
        // both weight sets sum to at most 1 in float: L <= max(c), never Inf
        float l = w.x * c.x + w.y * c.y + w.z * c.z;
        float ld = rh_curve4((float4)(scale * l), inv_white2).x;
        o = l > 0.0f ? c / l * ld : (float4)0.0f;
        // a +Inf channel: 1 there, 0 for the others (the limit of c Ld / L)
        o = any(pinf.xyz) ? (float4)0.0f : o;
    }
    o = select(o, (float4)1.0f, pinf);
    o.w = src.w;
    out[i] = o;
}
