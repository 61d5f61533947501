#version 450
// Reinhard log-average luminance: a two-stage parallel reduction (lightgraph, reinhard).
//
// Stage 1 (LG_STAGE == 1): every workgroup walks the image with a grid stride, sums
// log(delta + L) over its valid pixels and counts the pixels left out, then reduces in
// shared memory and writes one Partial per workgroup.
// Stage 2 (LG_STAGE == 2): one workgroup reduces the partials to one Partial.
//
// Seed 0 (5.2) reduced with log2(N) render-to-texture passes of 2x2 averages; compute
// shaders reduce in two dispatches whatever the size, and count the bad pixels.
//
// Defines set by the plugin: LG_STAGE (1 or 2), LG_IN_FORMAT (rgba32f or rgba16f, stage 1).
// Bad pixels, as on the CPU (plugins/reinhard/reinhard_cpu.h): an R, G or B channel that
// is NaN or Inf, or a luminance that is not finite, counts as nonfinite; L < 0 as negative.

#define LG_GROUP 256u
layout(local_size_x = 256) in;

struct Partial {
    float sum;       // sum of log(delta + L)
    uint valid;      // pixels in the sum
    uint nonfinite;  // left out: NaN or Inf
    uint negative;   // left out: L < 0
};

layout(std430, binding = 0) buffer Partials { Partial part[]; };

#if LG_STAGE == 1
layout(binding = 0, LG_IN_FORMAT) uniform readonly image2D u_in;
layout(location = 0) uniform ivec2 u_size;
layout(location = 1) uniform float u_delta;
layout(location = 2) uniform vec3 u_w;
#else
layout(std430, binding = 1) buffer Result { Partial result; };
layout(location = 0) uniform uint u_count;
#endif

shared float s_sum[LG_GROUP];
shared uint s_valid[LG_GROUP];
shared uint s_nonfinite[LG_GROUP];
shared uint s_negative[LG_GROUP];

// By the bits, so that no compiler may assume finite floats.
bool lg_finite(float v)
{
    return (floatBitsToUint(v) & 0x7f800000u) != 0x7f800000u;
}

void main()
{
    uint lid = gl_LocalInvocationID.x;
    float sum = 0.0;
    uint valid = 0u, nonfinite = 0u, negative = 0u;

#if LG_STAGE == 1
    uint w = uint(u_size.x);
    uint n = w * uint(u_size.y);
    uint stride = gl_NumWorkGroups.x * LG_GROUP;
    for (uint i = gl_GlobalInvocationID.x; i < n; i += stride) {
        vec3 c = imageLoad(u_in, ivec2(int(i % w), int(i / w))).rgb;
        if (!lg_finite(c.r) || !lg_finite(c.g) || !lg_finite(c.b)) {
            nonfinite++;
            continue;
        }
        float l = u_w.r * c.r + u_w.g * c.g + u_w.b * c.b;
        if (!lg_finite(l)) {
            nonfinite++;
        } else if (l < 0.0) {
            negative++;
        } else {
            sum += log(u_delta + l);
            valid++;
        }
    }
#else
    for (uint i = lid; i < u_count; i += LG_GROUP) {
        sum += part[i].sum;
        valid += part[i].valid;
        nonfinite += part[i].nonfinite;
        negative += part[i].negative;
    }
#endif

    s_sum[lid] = sum;
    s_valid[lid] = valid;
    s_nonfinite[lid] = nonfinite;
    s_negative[lid] = negative;
    barrier();
    for (uint s = LG_GROUP / 2u; s > 0u; s >>= 1) {
        if (lid < s) {
            s_sum[lid] += s_sum[lid + s];
            s_valid[lid] += s_valid[lid + s];
            s_nonfinite[lid] += s_nonfinite[lid + s];
            s_negative[lid] += s_negative[lid + s];
        }
        barrier();
    }
    if (lid == 0u) {
        Partial p = Partial(s_sum[0], s_valid[0], s_nonfinite[0], s_negative[0]);
#if LG_STAGE == 1
        part[gl_WorkGroupID.x] = p;
#else
        result = p;
#endif
    }
}
