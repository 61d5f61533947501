#version 450 core
// The prt node's dot products on GL (plugins/prt): one invocation per texel of the
// `vertices` image (lightgraph/transfer.h, "Per-vertex values as an image"), i.e. per
// vertex; texels past the last vertex get (0, 0, 0, 0).
//
//   radiance_c(v) = sum_{i < u_n} lighting[c][i] * transfer[v][c][i]
//
// transfer is the LG_KIND_TRANSFER buffer as the host holds it (float[V][3][u_stride]),
// lighting the already rotated coefficients truncated to the common prefix (float[3][u_n]).
// Groups of PRT_GL_GROUP invocations along x (plugins/prt/prt_launch.h), in a 2D grid of
// groups when one row of groups would pass GL's group-count limit; texel = x + y * (groups
// along x) * PRT_GL_GROUP. A group's vertices are consecutive, so its reads are one
// contiguous stretch of the transfer buffer.

layout(local_size_x = 64, local_size_y = 1) in;

layout(std430, binding = 0) readonly buffer Transfer {
    float transfer[];
};
layout(std430, binding = 1) readonly buffer Lighting {
    float lighting[];
};
layout(binding = 0, rgba32f) uniform writeonly image2D u_out;

uniform uint u_n;        // coefficients per channel used (common prefix)
uniform uint u_stride;   // coefficients per channel in the transfer (its n^2)
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
    uint base = v * 3u * u_stride;
    vec3 acc = vec3(0.0);
    for (uint i = 0u; i < u_n; i++) {
        acc.r += lighting[i] * transfer[base + i];
        acc.g += lighting[u_n + i] * transfer[base + u_stride + i];
        acc.b += lighting[2u * u_n + i] * transfer[base + 2u * u_stride + i];
    }
    imageStore(u_out, p, vec4(acc, 1.0));
}
