#version 450 core
// The ibl plugin's shading pass on GL (plugins/ibl/README.md gives the equations): one
// fragment per output pixel reads the G-buffer, the optional base image and the probe, and
// writes the output's colour (rgba32f, rgba16f or rgbe8 on an RGBA8 target) and depth. The
// C twin is ibl_shade_pixel() in plugins/ibl/ibl.c, the CL twin shaders/ibl/ibl.cl.
#include "probe.glsl"
#include "rgbe.glsl"

#define IBL_REFLECT 0
#define IBL_ENVMAP 1
#define IBL_BACKGROUND 2
#define IBL_RGBA32F 0
#define IBL_RGBA16F 1
#define IBL_RGBE8 2

layout(binding = 0) uniform sampler2D u_gbuf;       // world normal, material + 1
layout(binding = 7) uniform sampler2D u_gbuf2;      // the pixel's F0 (rgb), roughness
layout(binding = 1) uniform sampler2D u_gdepth;     // window depth, 1 = nothing
layout(binding = 2) uniform sampler2D u_base;       // the base image (rgba32f, or rgbe8)
layout(binding = 3) uniform sampler2D u_base_depth; // its depth plane
layout(binding = 4) uniform sampler2D u_probe2d;    // lat-long or angular radiance
layout(binding = 5) uniform samplerCube u_probecube;
layout(binding = 6) uniform samplerCube u_chain;    // the GGX chain (GL_LINEAR_MIPMAP_LINEAR)

// two vec4 per material: (F0 rgb, roughness), (double-sided, 0, 0, 0); the pixel's own F0
// and roughness (the factors times the material's textures) come from u_gbuf2
layout(std430, binding = 1) readonly buffer Materials { vec4 mats[]; };
// pixels whose colour an rgba16f store clamped
layout(std430, binding = 2) buffer Clamped { uint clamped; };
// the split-sum DFG table (plugins/ibl/ggx_prefilter.h, lg_ggx_dfg_shared): (A, B) on end
// points, entry (i, j) at n.v = i / (N - 1), roughness = j / (N - 1)
layout(std430, binding = 3) readonly buffer Dfg { vec2 dfg[]; };

// The pass's values, uploaded in one call from the C struct that mirrors the block
// (ibl_gpu_shade in plugins/ibl/ibl.c, std140, 160 bytes). No instance name: the members
// read as plain uniforms.
layout(std140, binding = 0) uniform IblShade {
    mat4 u_inv_view_proj;
    mat3 u_rotation;        // probe -> world (std140: three vec4 columns)
    ivec2 u_size;
    int u_mode;
    int u_layout;
    int u_bilinear;
    int u_fresnel;
    int u_has_base;         // 0: none; 1: rgba32f; 2: rgbe8 (RGBA8 bytes, decoded, alpha 1)
    int u_has_base_depth;
    int u_format;
    int u_chain_levels;     // 0: no chain (every material a mirror)
    int u_dfg_size;
};

layout(location = 0) out vec4 o_color;

vec3 ibl_lookup(vec3 dir)
{
    vec3 d = lg_probe_from_world(u_rotation, dir);
    if (u_layout == LG_PROBE_CUBE)
        return lg_probe_cube(u_probecube, 0.0, d).rgb;
    if (u_bilinear != 0)
        return lg_probe_2d_bilinear(u_probe2d, u_layout, 0, d).rgb;
    return lg_probe_2d_nearest(u_probe2d, u_layout, 0, d).rgb;
}

// lg_ggx_dfg: bilinear in the table, exactly the CPU's arithmetic
vec2 ibl_dfg(float ndv, float r)
{
    float last = float(u_dfg_size - 1);
    float x = clamp(ndv, 0.0, 1.0) * last, y = clamp(r, 0.0, 1.0) * last;
    int i0 = min(int(x), u_dfg_size - 2), j0 = min(int(y), u_dfg_size - 2);
    float fx = x - float(i0), fy = y - float(j0);
    vec2 t00 = dfg[j0 * u_dfg_size + i0], t10 = dfg[j0 * u_dfg_size + i0 + 1];
    vec2 t01 = dfg[(j0 + 1) * u_dfg_size + i0], t11 = dfg[(j0 + 1) * u_dfg_size + i0 + 1];
    vec2 a = t00 + (t10 - t00) * fx, b = t01 + (t11 - t01) * fx;
    return a + (b - a) * fy;
}

// The radiance along dir for a perceptual roughness: the probe itself at 0; the GGX chain
// at lod = roughness (L - 1), trilinear; below lod 1, the probe blended with level 1 (so
// that roughness 0+ continues roughness 0).
vec3 ibl_radiance(vec3 dir, float rough)
{
    if (!(rough > 0.0) || u_chain_levels < 2)
        return ibl_lookup(dir);
    float lod = rough * float(u_chain_levels - 1);
    vec3 d = lg_probe_safe_dir(lg_probe_from_world(u_rotation, dir));
    if (lod < 1.0) {
        vec3 a = ibl_lookup(dir), b = textureLod(u_chain, d, 1.0).rgb;
        return a + (b - a) * lod;
    }
    return textureLod(u_chain, d, lod).rgb;
}

// The shading normal facing the viewer (V from the eye to the point): a normal facing away
// is flipped for a double-sided material, and for a single-sided one turned into the plane
// perpendicular to V (N.V = 0: R = V, continuous with the front side's grazing limit).
vec3 ibl_normal(vec3 n, vec3 V, bool double_sided)
{
    float m = max(abs(n.x), max(abs(n.y), abs(n.z)));
    if (!(m > 1e-30) || lg_probe_nonfinite(m))
        return -V;
    vec3 N = normalize(n / m);
    float d = dot(N, V);
    if (d > 0.0) {
        if (double_sided)
            return -N;
        vec3 t = N - d * V;
        float l = length(t);
        return l > 1e-6 ? t / l : -V;
    }
    return N;
}

float ibl_clean(float x)
{
    return (floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u ? 0.0 : x; // NaN -> 0
}

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec2 ndc = (vec2(p) + 0.5) / vec2(u_size) * 2.0 - 1.0;
    vec4 a = u_inv_view_proj * vec4(ndc, -1.0, 1.0);
    vec4 b = u_inv_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 V = lg_probe_safe_dir(b.xyz / b.w - a.xyz / a.w);

    vec4 g = texelFetch(u_gbuf, p, 0);
    float gd = texelFetch(u_gdepth, p, 0).r;
    vec4 base = vec4(0.0, 0.0, 0.0, 1.0);
    if (u_has_base == 1)
        base = texelFetch(u_base, p, 0);
    else if (u_has_base == 2)
        base = vec4(lg_rgbe_decode_unorm(texelFetch(u_base, p, 0)), 1.0);
    float bd = u_has_base_depth != 0 ? texelFetch(u_base_depth, p, 0).r : 1.0;
    int mat = int(g.a + 0.5) - 1;

    vec4 c;
    float depth;
    if (u_mode == IBL_BACKGROUND) {
        bool covered = gd < 1.0 || bd < 1.0;
        c = covered ? base : vec4(ibl_lookup(V), 1.0);
        depth = min(gd, bd);
    } else if (mat < 0) {
        c = base;
        depth = bd;
    } else {
        vec4 m1 = mats[2 * mat + 1], m0 = texelFetch(u_gbuf2, p, 0);
        vec3 N = ibl_normal(g.xyz, V, m1.x != 0.0);
        float ndv = dot(N, V);
        float cosv = clamp(-ndv, 0.0, 1.0);
        vec3 L = u_mode == IBL_REFLECT ? V - 2.0 * ndv * N : N;
        float rough = u_chain_levels >= 2 ? m0.a : 0.0;
        vec3 F = m0.rgb;
        if (u_fresnel != 0) {
            if (rough > 0.0) {
                vec2 ab = ibl_dfg(cosv, rough);
                F = F * ab.x + ab.y;
            } else {
                float k = 1.0 - cosv, k2 = k * k;
                F = F + (vec3(1.0) - F) * (k2 * k2 * k);
            }
        }
        c = vec4(base.rgb + F * ibl_radiance(L, rough), base.a);
        depth = gd;
    }
    c = vec4(ibl_clean(c.r), ibl_clean(c.g), ibl_clean(c.b), ibl_clean(c.a));
    if (u_format == IBL_RGBA16F) {
        if (c.r > 65504.0 || c.g > 65504.0 || c.b > 65504.0)
            atomicAdd(clamped, 1u);
        c = lg_half_range(c);
    } else if (u_format == IBL_RGBE8) {
        c = lg_rgbe_encode(c.rgb) / 255.0;
    }
    o_color = c;
    gl_FragDepth = depth;
}
