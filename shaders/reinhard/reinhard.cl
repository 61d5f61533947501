// Reinhard tone mapping in OpenCL C 1.2 (lightgraph, reinhard).
//
//   rh_reduce        stage 1: each work-item sums log(delta + L) over LG_PPI pixels (blocks
//                    of 8, as float8 vectors), counts the pixels left out and writes one
//                    partial
//   rh_reduce_final  stage 2: one work-group reduces the partials; then item 0 computes
//                    Lavg, the adaptation step and the scale into the result block
//   rh_map           the tone curve, eight pixels per work-item (float8 vectors), reading the
//                    scale from the result block (no host round trip between the reduction
//                    and the map)
//
// The same arithmetic and the same bad-pixel policy as the GL shaders and the CPU code
// (plugins/reinhard/reinhard_cpu.h); launch geometry in plugins/reinhard/reinhard_launch.h.
// Build options: -DLG_LOCAL=<work-group size of the reductions, a power of two>,
// -DLG_MAP_LOCAL=<work-group size of the map>, -DLG_PPI=<pixels per stage-1 item, a multiple
// of 8> and, for
// rgba16f input, -DLG_IN_HALF=1, for rgbe8 input -DLG_IN_RGBE=1 (shaders/common/rgbe.cl
// precedes this file then). Images are buffers of tightly packed pixels (4 floats, 4
// halves, or 4 RGBE bytes decoded as they are loaded, alpha 1).
//
// Speed (PoCL on CPUs, and GPUs alike): no branch per pixel (the policy is select()s),
// eight pixels per work-item as float8 vectors (two 64-byte loads and stores), consecutive
// work-items touch consecutive blocks, no barrier in the pixel kernels, and a logarithm of
// our own (rh_log, rh_log8). Measurements on PoCL 3.1, 2
// CPUs, 2048x1396, are in plugins/reinhard/README.md ("Speed").

#ifndef LG_LOCAL
#define LG_LOCAL 256
#endif
#ifndef LG_MAP_LOCAL
#define LG_MAP_LOCAL 256
#endif
#ifndef LG_PPI
#define LG_PPI 16
#endif
#if LG_PPI % 8
#error "LG_PPI must be a multiple of 8 (stage 1 reads blocks of 8 pixels)"
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
// The polynomial part on f = m - 1, z = f^2 and the exponent fe, for float and float8 alike
// (the same operations in the same order): y, with log(x) = f + y + ln2_hi fe.
#define RH_LOG_POLY(y, f, z, fe)                                                          \
    do {                                                                                  \
        (y) = 7.0376836292e-2f;                                                           \
        (y) = (y) * (f) - 1.1514610310e-1f;                                               \
        (y) = (y) * (f) + 1.1676998740e-1f;                                               \
        (y) = (y) * (f) - 1.2420140846e-1f;                                               \
        (y) = (y) * (f) + 1.4249322787e-1f;                                               \
        (y) = (y) * (f) - 1.6668057665e-1f;                                               \
        (y) = (y) * (f) + 2.0000714765e-1f;                                               \
        (y) = (y) * (f) - 2.4999993993e-1f;                                               \
        (y) = (y) * (f) + 3.3333331174e-1f;                                               \
        (y) = (y) * (f) * (z);                                                            \
        (y) += -2.12194440e-4f * (fe);                                                    \
        (y) += -0.5f * (z);                                                               \
    } while (0)

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
    float fe = (float)e, y;
    RH_LOG_POLY(y, f, z, fe);
    return f + y + 0.693359375f * fe;
}

inline float4 rh_load(const __global float *in, uint i)
{
#if defined(LG_IN_HALF)
    return vload_half4(i, (const __global half *)in);
#elif defined(LG_IN_RGBE)
    return (float4)(lg_rgbe_decode(vload4(i, (const __global uchar *)in)), 1.0f);
#else
    return vload4(i, in);
#endif
}

// Eight pixels at a time, as explicit vectors: r, g, b and alpha of pixels 8j .. 8j + 7.
// Why not one pixel per work-item and PoCL's vectorisation across work-items: clang's SLP
// vectoriser first packs a pixel's channels into <2 x float> / <4 x float> values, and
// LLVM's loop vectoriser, which PoCL relies on to vectorise its work-item loops, cannot
// widen vector-typed instructions ("instruction return type cannot be vectorized" with
// POCL_VECTORIZER_REMARKS=1), so each work-item ran as scalar code. Explicit float8 code
// is SIMD whatever the work-group method does.
#if defined(LG_IN_HALF)
#define RH_LOAD16(j, p) vload_half16((j), (const __global half *)(p))
#elif defined(LG_IN_RGBE)
// four pixels 4j .. 4j + 3, decoded one by one
inline float16 rh_load16_rgbe(uint j, const __global float *p)
{
    return (float16)(rh_load(p, 4 * j), rh_load(p, 4 * j + 1), rh_load(p, 4 * j + 2),
                     rh_load(p, 4 * j + 3));
}
#define RH_LOAD16(j, p) rh_load16_rgbe((j), (p))
#else
#define RH_LOAD16(j, p) vload16((j), (p))
#endif

inline void rh_load8(const __global float *in, uint j, float8 *r, float8 *g, float8 *b,
                     float8 *a)
{
    float16 p = RH_LOAD16(2 * j, in), q = RH_LOAD16(2 * j + 1, in);
    *r = (float8)(p.s048c, q.s048c);
    *g = (float8)(p.s159d, q.s159d);
    *b = (float8)(p.s26ae, q.s26ae);
    *a = (float8)(p.s37bf, q.s37bf);
}

inline int8 rh_finite8(float8 v)
{
    return (as_int8(v) & (int8)0x7f800000) != (int8)0x7f800000; // -1 where finite
}

// rh_log on eight values, the same operations in the same order.
inline float8 rh_log8(float8 x)
{
    int8 b = as_int8(x);
    int8 e = ((b >> 23) & 0xff) - 126;
    float8 m = as_float8((b & 0x007fffff) | 0x3f000000);
    int8 small = m < 0.70710678118654752f;             // -1 where true
    e += small;
    m = select(m, m + m, small);
    float8 f = m - 1.0f;
    float8 z = f * f;
    float8 fe = convert_float8(e), y;
    RH_LOG_POLY(y, f, z, fe);
    return f + y + 0.693359375f * fe;
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

// Each work-item sums LG_PPI pixels in blocks of 8, LG_LOCAL blocks apart (neighbouring
// items read neighbouring blocks), as float8 vectors with no branch per pixel; only the
// image's last, partial block (n not a multiple of 8) takes the per-pixel path. Each item
// writes its own partial: no local memory, no barrier (on PoCL a barrier splits the kernel
// into work-item loops that keep every private value in memory between them; the
// local-memory tree this replaced took 40-56 ms, a per-item partial 12 ms). Stage 2 then
// reduces one partial per work-item (1/LG_PPI of a 16-byte value per pixel: 3% more
// traffic with LG_PPI = 32).
__kernel void rh_reduce(const __global float *in, uint n, float delta, float4 w,
               __global rh_partial *part)
{
    uint first = get_group_id(0) * (LG_LOCAL * LG_PPI / 8) + get_local_id(0);
    float8 sum8 = 0.0f;
    int8 nonfinite8 = 0, negative8 = 0;
    float sum = 0.0f;
    uint nonfinite = 0, negative = 0;   // valid: the pixels looked at, less these
    for (uint k = 0; k < LG_PPI / 8; k++) {
        uint j = first + k * LG_LOCAL;                 // block of pixels 8j .. 8j + 7
        if (8 * j + 8 <= n) {
            float8 r, g, b, a;
            rh_load8(in, j, &r, &g, &b, &a);
            float8 l = w.x * r + w.y * g + w.z * b;
            int8 fin = rh_finite8(r) & rh_finite8(g) & rh_finite8(b) & rh_finite8(l);
            int8 neg = fin & (l < 0.0f);
            int8 ok = fin & ~neg;
            sum8 += rh_log8(select((float8)1.0f, delta + l, ok));
            nonfinite8 += ~fin & 1;
            negative8 += neg & 1;
        } else {                                       // the image's last, partial block
            for (uint i = 8 * j; i < n; i++) {
                float4 c = rh_load(in, i);
                float l = w.x * c.x + w.y * c.y + w.z * c.z;
                int fin = rh_finite(c.x) & rh_finite(c.y) & rh_finite(c.z) & rh_finite(l);
                int neg = fin & (l < 0.0f);
                int ok = fin & !neg;
                sum += rh_log(ok ? delta + l : 1.0f);
                nonfinite += !fin;
                negative += neg;
            }
        }
    }
    float4 s4 = sum8.lo + sum8.hi;
    sum += (s4.x + s4.y) + (s4.z + s4.w);
    int4 f4 = nonfinite8.lo + nonfinite8.hi, n4 = negative8.lo + negative8.hi;
    nonfinite += (uint)((f4.x + f4.y) + (f4.z + f4.w));
    negative += (uint)((n4.x + n4.y) + (n4.z + n4.w));
    uint mine = 0;                                     // pixels this item looked at
    for (uint k = 0; k < LG_PPI / 8; k++) {
        uint p0 = 8 * (first + k * LG_LOCAL);
        mine += p0 < n ? min(8u, n - p0) : 0u;
    }
    rh_partial p = { sum, mine - nonfinite - negative, nonfinite, negative };
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

inline float8 rh_curve8(float8 x, float inv_white2)
{
    float8 g = x / (1.0f + x);
    g = fmin(1.0f, g * (1.0f + x * inv_white2));
    return select(g, (float8)1.0f, as_int8(x) == (int8)0x7f800000);
}

// NaN, negative and +-Inf read as 0
inline float8 rh_clean8(float8 v)
{
    return select((float8)0.0f, v, rh_finite8(v) & (v >= 0.0f));
}

// One pixel, as rh_map did it before it took eight (the image's last, partial block).
inline void rh_map1(const __global float *in, __global float4 *out, uint i, float scale,
                    float inv_white2, int mode, float4 w)
{
    float4 src = rh_load(in, i);
    int4 bits = as_int4(src);
    int4 pinf = bits == (int4)0x7f800000;                    // +Inf channels
    float4 c = select((float4)0.0f, src, rh_finite4(src) & (src >= 0.0f));
    float4 o;
    if (mode == 1) {
        o = rh_curve4(scale * c, inv_white2);
    } else {
        float l = w.x * c.x + w.y * c.y + w.z * c.z;
        float ld = rh_curve4((float4)(scale * l), inv_white2).x;
        o = l > 0.0f ? c / l * ld : (float4)0.0f;
        // grey: Ld itself (c / L is 1, but L's rounding can make it 1 + 1 ulp)
        o = (c.x == c.y && c.y == c.z) ? (float4)ld : o;
        o = any(pinf.xyz) ? (float4)0.0f : o;
    }
    o = select(o, (float4)1.0f, pinf);
    o.w = src.w;
    out[i] = o;
}

// mode: 0 luminance, 1 rgb (uniform: one branch per work-item, the same for all)
// Each work-item maps pixels 8j .. 8j + 7 (j = get_global_id(0)) as float8 vectors.
// No reqd_work_group_size: with it, PoCL 3.1 ran the map at half the speed (measured).
__kernel void rh_map(const __global float *in, __global float4 *out, uint n,
            const __global rh_result *result, float inv_white2, int mode, float4 w)
{
    uint j = get_global_id(0);
    float scale = result->scale;
    if (8 * j + 8 > n) {
        for (uint i = 8 * j; i < n; i++)
            rh_map1(in, out, i, scale, inv_white2, mode, w);
        return;
    }
    float8 r, g, b, a;
    rh_load8(in, j, &r, &g, &b, &a);
    int8 ir = as_int8(r) == (int8)0x7f800000, ig = as_int8(g) == (int8)0x7f800000,
         ib = as_int8(b) == (int8)0x7f800000;            // +Inf channels
    float8 cr = rh_clean8(r), cg = rh_clean8(g), cb = rh_clean8(b);
    float8 orr, og, ob;
    if (mode == 1) {
        orr = rh_curve8(scale * cr, inv_white2);
        og = rh_curve8(scale * cg, inv_white2);
        ob = rh_curve8(scale * cb, inv_white2);
    } else {
        float8 l = w.x * cr + w.y * cg + w.z * cb;
        float8 ld = rh_curve8(scale * l, inv_white2);
        int8 z = !(l > 0.0f) | ir | ig | ib;   // black, or a +Inf channel: 0
        int8 grey = (cr == cg) & (cg == cb);   // Ld itself (c / L is 1 but for rounding)
        orr = select(select(cr / l * ld, ld, grey), (float8)0.0f, z);
        og = select(select(cg / l * ld, ld, grey), (float8)0.0f, z);
        ob = select(select(cb / l * ld, ld, grey), (float8)0.0f, z);
    }
    orr = select(orr, (float8)1.0f, ir);
    og = select(og, (float8)1.0f, ig);
    ob = select(ob, (float8)1.0f, ib);
    float16 p, q;
    p.s048c = orr.lo; p.s159d = og.lo; p.s26ae = ob.lo; p.s37bf = a.lo;
    q.s048c = orr.hi; q.s159d = og.hi; q.s26ae = ob.hi; q.s37bf = a.hi;
    vstore16(p, 2 * j, (__global float *)out);
    vstore16(q, 2 * j + 1, (__global float *)out);
}
