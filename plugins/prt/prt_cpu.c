/*
 * The prt node's CPU dot products (prt_launch.h). Built at -O3 (plugins/prt/meson.build),
 * plain SSE2 (no -march: the plugin runs on any x86-64), and measured with
 * tools/bench_prt_roofline.c; what made it fast, in order of effect:
 *
 *   - software prefetch PRT_PREFETCH vertices ahead: one thread reads one stream, and the
 *     hardware prefetcher alone left it at ~35% of the triad (which has three streams per
 *     thread in flight); with it, ~50-60%;
 *   - the whole record at once: a vertex's 3 x stride floats are contiguous, so they are
 *     multiplied in 4-float blocks by the lighting laid out like the record (plane c's
 *     coefficients at [c stride, c stride + n), zero elsewhere): 3 x ceil-ish(stride / 4)
 *     blocks, no scalar tails, one 4-to-1 sum per channel;
 *   - a compile-time coefficient count for the usual band counts (2 .. 8), so that GCC
 *     unrolls the blocks completely.
 *
 * Independent partial sums (no reassociation of a float sum: no -ffast-math) keep the
 * result within a few ulps of sum_i |l_i t_i| of the exact dot product
 * (tests/plugins/prt `exact` bounds it by 1e-5 relative).
 */
#include "prt_launch.h"

#define PRT_W 4 /* PRT_RECORD_PAD rounds to it */
/* vertices to prefetch ahead (~10 KB at 5 bands) */
#define PRT_PREFETCH 32
/* the record path's largest stride (16 bands: a 9 KB lighting record on the stack);
 * beyond it, prt_dot1 per channel */
#define PRT_RECORD_MAX 256u

/* sum_{i < n} l[i] t[i] in PRT_W partial sums (the generic path) */
static inline __attribute__((always_inline)) float
prt_dot1(const float *restrict l, const float *restrict t, const uint32_t n)
{
    float acc[PRT_W] = { 0 };
    uint32_t i = 0;
    for (; i + PRT_W <= n; i += PRT_W)
        for (int k = 0; k < PRT_W; k++)
            acc[k] += l[i + k] * t[i + k];
    for (int k = 0; i < n; i++, k++)
        acc[k] += l[i] * t[i];
    return (acc[0] + acc[1]) + (acc[2] + acc[3]);
}

static inline __attribute__((always_inline)) void prt_prefetch(const float *t, uint32_t stride)
{
    const char *ahead = (const char *)(t + (size_t)PRT_PREFETCH * 3u * stride);
    for (uint32_t b = 0; b < 3u * stride * sizeof(float); b += 64)
        __builtin_prefetch(ahead + b, 0, 0);
}

/* Vertices [v, last) by the record path: `lr` is the lighting laid out like a record,
 * one padded row per channel. Reads up to PRT_W - 1 floats past a record: never call it
 * for the buffer's last vertex. */
static inline __attribute__((always_inline)) void prt_records(const float *restrict transfer,
                                                              const float *restrict lr,
                                                              const uint32_t stride, size_t v,
                                                              size_t last, float *restrict out)
{
    const uint32_t pad = PRT_RECORD_PAD(stride);
    for (; v < last; v++) {
        const float *restrict t = transfer + v * 3u * stride;
        prt_prefetch(t, stride);
        for (uint32_t c = 0; c < 3; c++) {
            const uint32_t j0 = c * stride / PRT_W * PRT_W;
            const uint32_t j1 = ((c + 1) * stride + PRT_W - 1) / PRT_W * PRT_W;
            float acc[PRT_W] = { 0 };
            for (uint32_t j = j0; j < j1; j += PRT_W)
                for (int k = 0; k < PRT_W; k++)
                    acc[k] += lr[c * pad + j + k] * t[j + k];
            out[4 * v + c] = (acc[0] + acc[1]) + (acc[2] + acc[3]);
        }
        out[4 * v + 3] = 1.0f;
    }
}

/* Vertices [v, last) per channel (any n <= stride). */
static void prt_generic(const prt_cpu_job *job, size_t v, size_t last)
{
    const float *restrict l = job->lighting;
    const uint32_t n = job->n, stride = job->stride;
    float *restrict out = job->out;
    for (; v < last; v++) {
        const float *restrict t = job->transfer + v * 3u * stride;
        prt_prefetch(t, stride);
        out[4 * v + 0] = prt_dot1(l, t, n);
        out[4 * v + 1] = prt_dot1(l + n, t + stride, n);
        out[4 * v + 2] = prt_dot1(l + 2u * n, t + 2u * stride, n);
        out[4 * v + 3] = 1.0f;
    }
}

void lg_prt_cpu_range(const prt_cpu_job *job, size_t begin, size_t end)
{
    const uint32_t n = job->n, stride = job->stride;
    size_t last = end < job->vertices ? end : job->vertices;
    size_t v = begin < last ? begin : last;
    /* the record path stops before the buffer's last vertex (it reads past a record) */
    size_t rec_end = last < job->vertices ? last : job->vertices - 1;
    if (stride <= PRT_RECORD_MAX && v < rec_end) {
        float lr[3 * PRT_RECORD_PAD(PRT_RECORD_MAX)];
        prt_record_lighting(job->lighting, n, stride, lr);
        switch (stride) {
#define PRT_CASE(s)                                                                                \
    case s: prt_records(job->transfer, lr, s, v, rec_end, job->out); break;
            PRT_CASE(4)
            PRT_CASE(9)
            PRT_CASE(16)
            PRT_CASE(25)
            PRT_CASE(36)
            PRT_CASE(49)
            PRT_CASE(64)
#undef PRT_CASE
        default: prt_records(job->transfer, lr, stride, v, rec_end, job->out);
        }
        v = rec_end;
    }
    prt_generic(job, v, last);
    float *out = job->out;
    for (v = last > begin ? last : begin; v < end; v++)
        out[4 * v + 0] = out[4 * v + 1] = out[4 * v + 2] = out[4 * v + 3] = 0.0f;
}
