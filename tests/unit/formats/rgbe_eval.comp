#version 450
// Evaluates shaders/common/rgbe.glsl for tests/unit/formats/test_rgbe_devices.c: per
// input, the encoded bytes (through the SSBO as numbers and through an RGBA8 image store,
// the way an rgbe8 target is written), the decode of the given bytes (as numbers and as an
// RGBA8 texel read back with texelFetch) and lg_half_range of the input.
#include "rgbe.glsl"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 1) readonly buffer Bytes { uvec4 bytes_in[]; };
layout(std430, binding = 2) writeonly buffer Encoded { uvec4 encoded[]; };
layout(std430, binding = 3) writeonly buffer Decoded { vec4 decoded[]; }; // 2 per item
layout(std430, binding = 4) writeonly buffer HalfRange { vec4 half_range[]; };

layout(binding = 0, rgba8) uniform writeonly image2D u_target; // u_count x 1
layout(binding = 0) uniform sampler2D u_bytes_tex;            // the bytes as RGBA8, n x 1
layout(location = 0) uniform uint u_count;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_count)
        return;
    vec4 b = lg_rgbe_encode(inputs[i].rgb);
    encoded[i] = uvec4(b);
    imageStore(u_target, ivec2(int(i), 0), b / 255.0);
    // .w: lg_half_range_count of the input
    decoded[2 * i] = vec4(lg_rgbe_decode(vec4(bytes_in[i])), float(lg_half_range_count(inputs[i])));
    decoded[2 * i + 1] = vec4(lg_rgbe_decode_unorm(texelFetch(u_bytes_tex, ivec2(int(i), 0), 0)), 0.0);
    half_range[i] = lg_half_range(inputs[i]);
}
