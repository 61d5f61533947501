#version 450 core
// The prt node's dot products on GL (plugins/prt): one fragment per texel of the
// `vertices` image (lightgraph/transfer.h, "Per-vertex values as an image"), drawn as a
// full-screen triangle into that image; texel (x, y) is vertex v = y * u_width + x, and
// texels past the last vertex get (0, 0, 0, 0).
//
//   radiance_c(v) = sum_{i < LG_N} lighting[c][i] * transfer[v][c][i]
//
// A fragment, not a compute shader: llvmpipe runs fragments in SIMD batches of whole quads
// with far less set-up per invocation than its compute path (plugins/prt/README.md,
// Roofline). Built per coefficient count (defines LG_N, the common prefix's n^2, and
// LG_STRIDE, the transfer's n^2: prt_launch.h, prt_gl_defines), so that the loops unroll,
// every record offset and lighting index is a constant, and each float of a record meets
// exactly one multiply-add. transfer is the LG_KIND_TRANSFER buffer as the host holds it
// (float[V][3][LG_STRIDE]); lighting the rotated coefficients truncated to the common
// prefix (float[3][LG_N]), as uniforms (the same for every lane).
//
// LG_VEC4: the record is read 4 floats per fetch, through an RGBA32F buffer texture over
// the transfer (u_transfer4): a record of 3 LG_STRIDE floats starts at any float, so the
// fragment fetches the ceil(3 LG_STRIDE / 4) + 1 texels that cover it and shifts each pair
// by the record's start modulo 4 (selects, no memory). The last vertex reads through the
// R32F view (u_transfer) instead: its record may end inside a texel the RGBA32F view does
// not have (a buffer texture holds floor(bytes / 16) texels). Without LG_VEC4 every float
// is a fetch of the R32F view.

layout(binding = 0) uniform samplerBuffer u_transfer; // R32F
#ifdef LG_VEC4
layout(binding = 1) uniform samplerBuffer u_transfer4; // RGBA32F, the same buffer
#endif
uniform float u_lighting[3 * LG_N];
uniform uint u_vertices; // vertices in the transfer
uniform uint u_width;    // the image's width (LG_VERTEX_IMAGE_WIDTH)

layout(location = 0) out vec4 o_radiance;

#define LG_RECORD (3u * LG_STRIDE)

// Adds record float j (a constant after unrolling) times its lighting coefficient.
#define LG_ACC(j, value)                                                                  \
    if ((j) < LG_RECORD && (j) % LG_STRIDE < LG_N)                                        \
        acc[(j) / LG_STRIDE] += u_lighting[(j) / LG_STRIDE * LG_N + (j) % LG_STRIDE] * (value)

vec3 dot_scalar(uint base)
{
    vec3 acc = vec3(0.0);
    for (uint c = 0u; c < 3u; c++)
        for (uint i = 0u; i < LG_N; i++)
            acc[c] += u_lighting[c * LG_N + i] *
                      texelFetch(u_transfer, int(base + c * LG_STRIDE + i)).r;
    return acc;
}

#ifdef LG_VEC4
vec3 dot_vec4(uint base)
{
    int t = int(base >> 2u);
    uint s = base & 3u;
    bvec4 s1 = bvec4(s == 1u), s2 = bvec4(s == 2u), s3 = bvec4(s == 3u);
    vec3 acc = vec3(0.0);
    vec4 a = texelFetch(u_transfer4, t);
    for (uint k = 0u; k < (LG_RECORD + 3u) / 4u; k++) {
        vec4 b = texelFetch(u_transfer4, t + int(k) + 1);
        // record floats 4k .. 4k + 3: texel k shifted by s, continued from texel k + 1
        vec4 r = a;
        r = mix(r, vec4(a.yzw, b.x), s1);
        r = mix(r, vec4(a.zw, b.xy), s2);
        r = mix(r, vec4(a.w, b.xyz), s3);
        LG_ACC(4u * k, r.x);
        LG_ACC(4u * k + 1u, r.y);
        LG_ACC(4u * k + 2u, r.z);
        LG_ACC(4u * k + 3u, r.w);
        a = b;
    }
    return acc;
}
#endif

void main()
{
    uint v = uint(gl_FragCoord.y) * u_width + uint(gl_FragCoord.x);
    if (v >= u_vertices) {
        o_radiance = vec4(0.0);
        return;
    }
    uint base = v * LG_RECORD;
#ifdef LG_VEC4
    vec3 acc = v + 1u < u_vertices ? dot_vec4(base) : dot_scalar(base);
#else
    vec3 acc = dot_scalar(base);
#endif
    o_radiance = vec4(acc, 1.0);
}
