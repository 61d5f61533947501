// The prt node's dot products on OpenCL (plugins/prt): one work-item per texel of the
// `vertices` image (lightgraph/transfer.h, "Per-vertex values as an image"), i.e. per
// vertex; texels past the last vertex get (0, 0, 0, 0).
//
//   radiance_c(v) = sum_{i < LG_N} lighting[c][i] * transfer[v][c][i]
//
// Built per coefficient count (plugins/prt/prt_launch.h, prt_cl_options): LG_N (the common
// prefix's n^2), LG_STRIDE (the transfer's n^2) and LG_PAD (a record of 3 LG_STRIDE floats
// rounded up to 4), so that the loops below are unrolled completely.
//
// transfer: float[V][3][LG_STRIDE] (LG_KIND_TRANSFER); record: the lighting laid out like
// a vertex's record, one LG_PAD row per channel (channel c's coefficients at
// [c LG_STRIDE, c LG_STRIDE + LG_N), zero elsewhere: prt_record_lighting); lighting: the
// plain float[3][LG_N], for the last vertex; out: float4 per texel (rgba32f, tightly
// packed, as the host's CL images are).
//
// A vertex's record is read in float4 blocks that straddle the channels' boundaries
// (each block times the record-shaped lighting of one channel): no scalar tails, one
// 4-to-1 sum per channel, the same scheme as prt_cpu.c. A block may reach 3 floats past
// the record, so the buffer's last vertex takes the scalar path.

#if !defined(LG_N) || !defined(LG_STRIDE) || !defined(LG_PAD)
#error "prt.cl is built with -DLG_N, -DLG_STRIDE and -DLG_PAD (prt_cl_options)"
#endif

__kernel void prt_dot(__global const float *restrict transfer,
                      __global const float *restrict record,
                      __global const float *restrict lighting, uint vertices, uint texels,
                      __global float4 *restrict out)
{
    uint v = (uint)get_global_id(0);
    if (v >= texels)
        return;
    if (v >= vertices) {
        out[v] = (float4)(0.0f);
        return;
    }
    __global const float *t = transfer + (size_t)v * (3u * LG_STRIDE);
    float res[3];
    if (v + 1u < vertices) {
        for (uint c = 0; c < 3u; c++) {
            float4 a = (float4)(0.0f);
            for (uint j = c * LG_STRIDE / 4u * 4u; j < ((c + 1u) * LG_STRIDE + 3u) / 4u * 4u;
                 j += 4u)
                a = fma(vload4(0, t + j), vload4(0, record + c * LG_PAD + j), a);
            res[c] = (a.x + a.y) + (a.z + a.w);
        }
    } else {
        for (uint c = 0; c < 3u; c++) {
            float s = 0.0f;
            for (uint i = 0; i < LG_N; i++)
                s = fma(lighting[c * LG_N + i], t[c * LG_STRIDE + i], s);
            res[c] = s;
        }
    }
    out[v] = (float4)(res[0], res[1], res[2], 1.0f);
}
