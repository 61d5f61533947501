#version 450
// Reinhard log-average luminance: a two-stage parallel reduction (lightgraph, reinhard).
//
// Stage 1 (LG_STAGE == 1): a 2D dispatch (plugins/reinhard/reinhard_launch.h): work-group
// (gx, gy) of 256 invocations along x covers columns gx * 256 .. + 255; each invocation
// walks its column over the rows gy, gy + rows, gy + 2 rows, ... (rows = the dispatch's
// height), summing log(delta + L) over the valid pixels and counting the ones left out
// with selects, not branches. No integer division per pixel; neighbouring invocations
// load neighbouring pixels. Each work-group reduces in shared memory and writes one
// Partial. Stage 2 (LG_STAGE == 2): one work-group reduces the partials; then invocation
// 0 computes Lavg, the adaptation step and the scale a / L into the Result block, where
// the map reads it: the host does not read anything between the reduction and the map.
//
// Seed 0 (5.2) reduced with log2(N) render-to-texture passes of 2x2 averages; compute
// shaders reduce in two dispatches whatever the size, and count the bad pixels.
//
// Defines set by the plugin: LG_STAGE (1 or 2), LG_IN_FORMAT (rgba32f, rgba16f, or rgba8 with LG_IN_RGBE for rgbe8 input, stage 1).
// Bad pixels, as on the CPU (plugins/reinhard/reinhard_cpu.h): an R, G or B channel that
// is NaN or Inf, or a luminance that is not finite, counts as nonfinite; L < 0 as negative.
#include "rgbe.glsl"

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
#ifdef LG_IN_RGBE
// rgbe8: the RGBA8 texel's bytes decoded (shaders/common/rgbe.glsl); alpha 1
#define rh_in(p) vec4(lg_rgbe_decode_unorm(imageLoad(u_in, p)), 1.0)
#else
#define rh_in(p) imageLoad(u_in, p)
#endif
layout(location = 0) uniform ivec2 u_size;
layout(location = 1) uniform float u_delta;
layout(location = 2) uniform vec3 u_w;
#else
// plugins/reinhard/reinhard_launch.h, rh_result; la and have_la persist across frames
layout(std430, binding = 1) buffer Result {
    Partial total;
    float lavg;      // exp(sum / valid), 1 when no pixel is valid
    float la;        // adapted luminance
    float scale;     // a / Lavg or a / La: what the map uses
    uint have_la;
} result;
layout(location = 0) uniform uint u_count;
layout(location = 1) uniform float u_key;
layout(location = 2) uniform int u_adapt;       // 0 off, 1 on
layout(location = 3) uniform float u_adapt_k;   // 1 - rate^(60 dt)
layout(location = 4) uniform float u_adapt_from;// La before the first frame; 0: first Lavg
layout(location = 5) uniform int u_reset;       // 1: forget La (first frame since prepare)
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
    int x = int(gl_GlobalInvocationID.x);
    int rows = int(gl_NumWorkGroups.y);
    // invocations right of the image run no iteration (only in the last column group)
    int yend = x < u_size.x ? u_size.y : 0;
    for (int y = int(gl_WorkGroupID.y); y < yend; y += rows) {
        vec3 c = rh_in( ivec2(x, y)).rgb;
        float l = u_w.r * c.r + u_w.g * c.g + u_w.b * c.b;
        bool fin = lg_finite(c.r) && lg_finite(c.g) && lg_finite(c.b) && lg_finite(l);
        bool neg = fin && l < 0.0;
        bool ok = fin && !neg;
        sum += log(ok ? u_delta + l : 1.0); // log(1) = 0 for the pixels left out
        valid += uint(ok);
        nonfinite += uint(!fin);
        negative += uint(neg);
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
        part[gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x] = p;
#else
        result.total = p;
        bool ok = p.valid > 0u;
        float lavg = ok ? exp(p.sum / float(p.valid)) : 1.0;
        result.lavg = lavg;
        float l = lavg;
        if (u_adapt != 0) {
            float la = result.la;
            if (u_reset != 0 || result.have_la == 0u) {
                la = u_adapt_from > 0.0 ? u_adapt_from : lavg;
                result.have_la = 1u;
            }
            if (ok)
                la = la + (lavg - la) * u_adapt_k;
            result.la = la;
            l = la;
        }
        result.scale = u_key / l;
#endif
    }
}
