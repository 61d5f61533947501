// Reinhard tone mapping in OpenCL C 1.2 (lightgraph, reinhard).
//
//   rh_reduce        stage 1: each work-group sums log(delta + L) over a grid-stride share of
//                    the pixels, counts the pixels left out, reduces in local memory and
//                    writes one partial
//   rh_reduce_final  stage 2: one work-group reduces the partials
//   rh_map           the tone curve, one work-item per pixel
//
// The same arithmetic and the same bad-pixel policy as the GL shaders and the CPU oracle
// (plugins/reinhard/reinhard_cpu.h). Build options: -DLG_LOCAL=<work-group size, a power
// of two> and, for rgba16f input, -DLG_IN_HALF=1. Images are buffers of tightly packed
// pixels (4 floats, or 4 halves).

#ifndef LG_LOCAL
#define LG_LOCAL 256
#endif

typedef struct rh_partial {
    float sum;
    uint valid;
    uint nonfinite;
    uint negative;
} rh_partial;

// By the bits, so that no option may assume finite floats.
inline int rh_finite(float v)
{
    return (as_uint(v) & 0x7f800000u) != 0x7f800000u;
}

inline int rh_is_nan(float v)
{
    uint b = as_uint(v);
    return (b & 0x7f800000u) == 0x7f800000u && (b & 0x007fffffu) != 0u;
}

inline int rh_is_pinf(float v)
{
    return as_uint(v) == 0x7f800000u;
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

__kernel __attribute__((reqd_work_group_size(LG_LOCAL, 1, 1)))
void rh_reduce(const __global float *in, uint n, float delta, float4 w,
               __global rh_partial *part)
{
    __local float s_sum[LG_LOCAL];
    __local uint s_valid[LG_LOCAL], s_nonfinite[LG_LOCAL], s_negative[LG_LOCAL];
    uint lid = get_local_id(0);
    uint stride = get_global_size(0);
    float sum = 0.0f;
    uint valid = 0, nonfinite = 0, negative = 0;
    for (uint i = get_global_id(0); i < n; i += stride) {
        float4 c = rh_load(in, i);
        if (!rh_finite(c.x) || !rh_finite(c.y) || !rh_finite(c.z)) {
            nonfinite++;
            continue;
        }
        float l = w.x * c.x + w.y * c.y + w.z * c.z;
        if (!rh_finite(l)) {
            nonfinite++;
        } else if (l < 0.0f) {
            negative++;
        } else {
            sum += log(delta + l);
            valid++;
        }
    }
    s_sum[lid] = sum;
    s_valid[lid] = valid;
    s_nonfinite[lid] = nonfinite;
    s_negative[lid] = negative;
    rh_local_reduce(s_sum, s_valid, s_nonfinite, s_negative, lid);
    if (lid == 0) {
        rh_partial p = { s_sum[0], s_valid[0], s_nonfinite[0], s_negative[0] };
        part[get_group_id(0)] = p;
    }
}

__kernel __attribute__((reqd_work_group_size(LG_LOCAL, 1, 1)))
void rh_reduce_final(const __global rh_partial *part, uint count, __global rh_partial *result)
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
        rh_partial p = { s_sum[0], s_valid[0], s_nonfinite[0], s_negative[0] };
        *result = p;
    }
}

inline float rh_curve(float x, float inv_white2)
{
    if (rh_is_pinf(x))
        return 1.0f;
    float g = x / (1.0f + x);
    if (inv_white2 > 0.0f)
        g = fmin(1.0f, g * (1.0f + x * inv_white2));
    return g;
}

__kernel void rh_map(const __global float *in, __global float4 *out, uint n, float scale,
                     float inv_white2, int mode, float4 w)
{
    uint i = get_global_id(0);
    if (i >= n)
        return;
    float4 src = rh_load(in, i);
    float c[3] = { src.x, src.y, src.z };
    int inf[3];
    int any_inf = 0;
    for (int k = 0; k < 3; k++) {
        float v = c[k];
        inf[k] = rh_is_pinf(v);
        any_inf |= inf[k];
        c[k] = (rh_is_nan(v) || v < 0.0f || inf[k]) ? 0.0f : v;
    }
    float o[3];
    if (mode == 1) {
        for (int k = 0; k < 3; k++)
            o[k] = inf[k] ? 1.0f : rh_curve(scale * c[k], inv_white2);
    } else if (any_inf) {
        for (int k = 0; k < 3; k++)
            o[k] = inf[k] ? 1.0f : 0.0f;
    } else {
        float l = w.x * c[0] + w.y * c[1] + w.z * c[2];
        // both weight sets sum to at most 1 in float: L <= max(c), never Inf
        float r[3] = { 0.0f, 0.0f, 0.0f };
        if (l > 0.0f)
            for (int k = 0; k < 3; k++)
                r[k] = c[k] / l;
        float ld = rh_curve(scale * l, inv_white2);
        for (int k = 0; k < 3; k++)
            o[k] = r[k] * ld;
    }
    out[i] = (float4)(o[0], o[1], o[2], src.w);
}
