/*
 * The prt node's CPU dot products (prt_launch.h). Built at -O3 (plugins/prt/meson.build):
 * the per-vertex products run in PRT_LANES independent accumulators, so GCC vectorises
 * them without reassociating a float sum (no -ffast-math), and the record of a vertex
 * (3 x stride floats, contiguous) streams through once.
 */
#include "prt_launch.h"

#define PRT_LANES 8

/* sum_{i < n} l[i] t[i], in PRT_LANES partial sums added at the end. */
static inline float prt_dot1(const float *restrict l, const float *restrict t, uint32_t n)
{
    float acc[PRT_LANES] = { 0 };
    uint32_t i = 0;
    for (; i + PRT_LANES <= n; i += PRT_LANES)
        for (int k = 0; k < PRT_LANES; k++)
            acc[k] += l[i + k] * t[i + k];
    for (int k = 0; i < n; i++, k++)
        acc[k] += l[i] * t[i];
    float s = 0.0f;
    for (int k = 0; k < PRT_LANES; k++)
        s += acc[k];
    return s;
}

void lg_prt_cpu_range(const prt_cpu_job *job, size_t begin, size_t end)
{
    const float *restrict l = job->lighting;
    const uint32_t n = job->n, stride = job->stride;
    float *restrict out = job->out;
    size_t last = end < job->vertices ? end : job->vertices;
    size_t v = begin;
    for (; v < last; v++) {
        const float *restrict t = job->transfer + v * 3u * stride;
        out[4 * v + 0] = prt_dot1(l, t, n);
        out[4 * v + 1] = prt_dot1(l + n, t + stride, n);
        out[4 * v + 2] = prt_dot1(l + 2u * n, t + 2u * stride, n);
        out[4 * v + 3] = 1.0f;
    }
    for (; v < end; v++)
        out[4 * v + 0] = out[4 * v + 1] = out[4 * v + 2] = out[4 * v + 3] = 0.0f;
}
