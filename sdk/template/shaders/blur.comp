#version 450
// acme_blur on GL (backend = gl): one direction of the separable Gaussian per dispatch,
// one invocation per pixel. blur_gl.c runs it twice: dir (1, 0) from the input into the
// scratch image, dir (0, 1) from the scratch image into the output.
//   dst(p) = sum_{i=-r..r} w[|i|] src(clamp(p + i dir, 0, size - 1))
// in float, taps in the order i = -r .. r (as blur_cpu.c sums them).

layout(local_size_x = 16, local_size_y = 16) in;

#include "acme_blur.glsl"

layout(binding = 0, rgba32f) uniform readonly image2D u_src;
layout(binding = 1, rgba32f) uniform writeonly image2D u_dst;
// the normalised weights, w[0] the centre: an lg_gl_buffer
layout(std430, binding = 0) readonly buffer AcmeWeights { float acme_w[]; };
// mirrored by acme_blur_params in blur_gl.c (LG_GL_BLOCK_SIZE 32), uploaded whole
layout(std140, binding = 1) uniform AcmeBlur {
    ivec2 size;
    ivec2 dir;
    int radius;
    int pad0, pad1, pad2;
};

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= size.x || p.y >= size.y)
        return;
    vec4 acc = vec4(0.0);
    for (int i = -radius; i <= radius; i++) {
        ivec2 q = clamp(p + i * dir, ivec2(0), size - 1);
        acc += acme_w[abs(i)] * acme_sanitize(imageLoad(u_src, q));
    }
    imageStore(u_dst, p, acme_sanitize(acc));
}
