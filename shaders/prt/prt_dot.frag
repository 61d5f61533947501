#version 450 core
// The prt node's dot products on GL (plugins/prt): one fragment per texel of the
// `vertices` image (lightgraph/transfer.h, "Per-vertex values as an image"), drawn as a
// full-screen triangle into that image; texel (x, y) is vertex v = y * u_width + x, and
// texels past the last vertex get (0, 0, 0, 0).
//
//   radiance_c(v) = sum_{i < LG_N} lighting[c][i] * transfer[v][c][i]
//
// A fragment, not a compute shader: llvmpipe runs fragments with far less set-up per
// invocation than its compute path (plugins/prt/README.md, Roofline). Built per
// coefficient count (defines LG_N, the common prefix's n^2, and LG_STRIDE, the transfer's
// n^2: prt_launch.h, prt_gl_frag_defines), so that the loops unroll, every record offset
// and lighting index is a constant, and each float of a record meets one multiply-add.
// transfer is the LG_KIND_TRANSFER buffer as the host holds it (float[V][3][LG_STRIDE]);
// lighting the rotated coefficients truncated to the common prefix (float[3][LG_N]), as
// uniforms (the same for every lane).
//
// u_transfer views the transfer as an RGB32F buffer texture: a record of 3 LG_STRIDE floats
// is exactly LG_STRIDE texels starting at texel v LG_STRIDE, so it takes LG_STRIDE fetches
// of 3 floats. llvmpipe's cost is per fetch, not per byte: this is 1.8x faster than 4-float
// RGBA32F fetches (a record starts at any float modulo 4, so those need a shift) and 2x
// faster than 1-float R32F fetches (README.md). LG_R32F: the R32F view instead (kept for
// the benchmark's comparison, tools/bench_prt_roofline.c).

layout(binding = 0) uniform samplerBuffer u_transfer; // RGB32F (LG_R32F: R32F)
uniform float u_lighting[3 * LG_N];
uniform uint u_vertices; // vertices in the transfer
uniform uint u_width;    // the image's width (LG_VERTEX_IMAGE_WIDTH)
// rigid motion (ABI 3.1): only vertices [u_first, u_end) are written by this draw (one run
// of meshes whose lighting is turned alike); 0 and u_vertices for a static scene
uniform uint u_first;
uniform uint u_end;

layout(location = 0) out vec4 o_radiance;

// Adds record float j (a constant after unrolling) times its lighting coefficient: float j
// is coefficient j % LG_STRIDE of channel j / LG_STRIDE, past the common prefix unused.
#define LG_ACC(j, value)                                                                  \
    if ((j) % LG_STRIDE < LG_N)                                                           \
        acc[(j) / LG_STRIDE] += u_lighting[(j) / LG_STRIDE * LG_N + (j) % LG_STRIDE] * (value)

void main()
{
    uint v = uint(gl_FragCoord.y) * u_width + uint(gl_FragCoord.x);
    if (v >= u_vertices) {
        o_radiance = vec4(0.0);
        return;
    }
    if (v < u_first || v >= u_end)
        discard;
    vec3 acc = vec3(0.0);
#ifdef LG_R32F
    // channel by channel: a loop of 3 LG_STRIDE iterations would pass the compiler's
    // unroll limit at 5 bands and index the lighting at run time (measured slower)
    int t = int(v * 3u * LG_STRIDE);
    for (uint c = 0u; c < 3u; c++)
        for (uint i = 0u; i < LG_N; i++)
            acc[c] += u_lighting[c * LG_N + i] *
                      texelFetch(u_transfer, t + int(c * LG_STRIDE + i)).r;
#else
    int t = int(v * LG_STRIDE);
    for (uint k = 0u; k < LG_STRIDE; k++) {
        vec3 r = texelFetch(u_transfer, t + int(k)).rgb;
        LG_ACC(3u * k, r.x);
        LG_ACC(3u * k + 1u, r.y);
        LG_ACC(3u * k + 2u, r.z);
    }
#endif
    o_radiance = vec4(acc, 1.0);
}
