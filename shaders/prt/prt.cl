// The prt node's dot products on OpenCL (plugins/prt): one work-item per texel of the
// `vertices` image (lightgraph/transfer.h, "Per-vertex values as an image"), i.e. per
// vertex; texels past the last vertex get (0, 0, 0, 0).
//
//   radiance_c(v) = sum_{i < n} lighting[c][i] * transfer[v][c][i]
//
// transfer: float[V][3][stride] (LG_KIND_TRANSFER); lighting: the rotated coefficients
// truncated to the common prefix, float[3][n]; out: float4 per texel (rgba32f, tightly
// packed, as the host's CL images are). The lighting is tiny and read by every item: it
// stays in the cache. Consecutive items read consecutive records, so a work-group streams
// one contiguous stretch of the transfer buffer (PoCL packs work-items into SIMD lanes;
// the record loads become gathers that hit lines the neighbouring lanes bring in).

__kernel void prt_dot(__global const float *restrict transfer,
                      __global const float *restrict lighting, uint n, uint stride,
                      uint vertices, uint texels, __global float4 *restrict out)
{
    uint v = (uint)get_global_id(0);
    if (v >= texels)
        return;
    if (v >= vertices) {
        out[v] = (float4)(0.0f);
        return;
    }
    __global const float *t = transfer + (size_t)v * 3u * stride;
    float r = 0.0f, g = 0.0f, b = 0.0f;
    for (uint i = 0; i < n; i++) {
        r = fma(lighting[i], t[i], r);
        g = fma(lighting[n + i], t[stride + i], g);
        b = fma(lighting[2u * n + i], t[2u * stride + i], b);
    }
    out[v] = (float4)(r, g, b, 1.0f);
}
