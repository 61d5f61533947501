// acme_blur on CL (backend = cl): one direction of the separable Gaussian per run, one
// work-item per pixel; images are float4 buffers, rows top first (lg_map_cl). blur_cl.c
// runs it twice: (dx, dy) = (1, 0) from the input into the scratch buffer, (0, 1) from it
// into the output. acme_sanitize comes from common/acme_blur.cl, given first.
//   dst(p) = sum_{i=-r..r} w[|i|] src(clamp(p + i (dx, dy), 0, size - 1))
// in float, taps in the order i = -r .. r (as blur_cpu.c sums them).
__kernel void acme_blur_1d(__global const float4 *src, __global float4 *dst, int width,
                           int height, int dx, int dy, __global const float *w, int radius)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height)
        return;
    float4 acc = (float4)(0.0f);
    for (int i = -radius; i <= radius; i++) {
        int xi = clamp(x + i * dx, 0, width - 1), yi = clamp(y + i * dy, 0, height - 1);
        acc += w[abs(i)] * acme_sanitize(src[(size_t)yi * width + xi]);
    }
    dst[(size_t)y * width + x] = acme_sanitize(acc);
}
