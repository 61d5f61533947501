#version 450 core
// The prt node's dot products on GL (plugins/prt): one invocation per texel of the
// `vertices` image (lightgraph/transfer.h, "Per-vertex values as an image"), i.e. per
// vertex; texels past the last vertex get (0, 0, 0, 0).
//
//   radiance_c(v) = sum_{i < LG_N} lighting[c][i] * transfer[v][c][i]
//
// Built per coefficient count (defines LG_N, the common prefix's n^2, and LG_STRIDE, the
// transfer's n^2: plugins/prt/prt_launch.h, prt_gl_defines), so that the loops unroll and
// the lighting's indices are constants: llvmpipe then loads each coefficient once for
// all the lanes of a SIMD batch. transfer is the LG_KIND_TRANSFER buffer as the host holds
// it (float[V][3][LG_STRIDE]), lighting the rotated coefficients truncated to the common
// prefix (float[3][LG_N]). Groups of PRT_GL_GROUP invocations along x (prt_launch.h), in a
// 2D grid of groups when one row would pass GL's group-count limit; texel = x + y *
// (groups along x) * PRT_GL_GROUP.

layout(local_size_x = 64, local_size_y = 1) in;

// LG_TBO (prt_gl_defines, when the transfer's floats fit GL_MAX_TEXTURE_BUFFER_SIZE): the
// transfer read through an R32F buffer texture over the same buffer. llvmpipe fetches
// texels for a SIMD batch of lanes at once, where it loads an SSBO element lane by lane:
// 3.3x faster at 5 bands (README.md, Roofline).
#ifdef LG_TBO
uniform samplerBuffer u_transfer;
#define transfer_at(k) texelFetch(u_transfer, int(k)).r
#else
layout(std430, binding = 0) readonly buffer Transfer {
    float transfer[];
};
#define transfer_at(k) transfer[k]
#endif
layout(std430, binding = 1) readonly buffer Lighting {
    float lighting[3 * LG_N];
};
layout(binding = 0, rgba32f) uniform writeonly image2D u_out;

uniform uint u_vertices; // vertices in the transfer
uniform uint u_width;    // the image's width (LG_VERTEX_IMAGE_WIDTH)
uniform uint u_texels;   // width * height

void main()
{
    uint v = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (v >= u_texels)
        return;
    ivec2 p = ivec2(int(v % u_width), int(v / u_width));
    if (v >= u_vertices) {
        imageStore(u_out, p, vec4(0.0));
        return;
    }
    uint base = v * (3u * LG_STRIDE);
    vec3 acc = vec3(0.0);
    for (uint i = 0u; i < LG_N; i++) {
        acc.r += lighting[i] * transfer_at(base + i);
        acc.g += lighting[LG_N + i] * transfer_at(base + LG_STRIDE + i);
        acc.b += lighting[2u * LG_N + i] * transfer_at(base + 2u * LG_STRIDE + i);
    }
    imageStore(u_out, p, vec4(acc, 1.0));
}
