// shaders/ibl/ibl.cl: the ibl plugin's shading pass on CL, the twin of ibl_shade.frag and
// of ibl_shade_pixel() in plugins/ibl/ibl.c (plugins/ibl/README.md gives the equations).
// Built after shaders/common/probe.cl and rgbe.cl (the plugin concatenates the three).
// One work item per output pixel; every image is a tightly packed buffer, row 0 first.

#define IBL_REFLECT 0
#define IBL_ENVMAP 1
#define IBL_BACKGROUND 2
#define IBL_RGBA32F 0
#define IBL_RGBA16F 1
#define IBL_RGBE8 2

inline float3 ibl_lookup(global const float4 *probe, int layout, int pw, int ph, int bilinear,
                         float4 r0, float4 r1, float4 r2, float3 dir)
{
    float3 d = lg_probe_from_world(r0.xyz, r1.xyz, r2.xyz, dir);
    return lg_probe_lookup(probe, layout, pw, ph, d, bilinear).xyz;
}

// As ibl_dfg in ibl_shade.frag (lg_ggx_dfg).
inline float2 ibl_dfg(global const float2 *t, int n, float ndv, float r)
{
    float last = (float)(n - 1);
    float x = clamp(ndv, 0.0f, 1.0f) * last, y = clamp(r, 0.0f, 1.0f) * last;
    int i0 = min((int)x, n - 2), j0 = min((int)y, n - 2);
    float fx = x - (float)i0, fy = y - (float)j0;
    float2 t00 = t[j0 * n + i0], t10 = t[j0 * n + i0 + 1];
    float2 t01 = t[(j0 + 1) * n + i0], t11 = t[(j0 + 1) * n + i0 + 1];
    float2 a = t00 + (t10 - t00) * fx, b = t01 + (t11 - t01) * fx;
    return a + (b - a) * fy;
}

// Level l of the chain (a cube of face `size`, levels packed as lg_image_offset says),
// bilinear.
inline float3 ibl_chain_level(global const float4 *chain, int size, int l, float3 d)
{
    size_t off = 0;
    for (int k = 0; k < l; k++) {
        size_t s = (size_t)max(size >> k, 1);
        off += 6 * s * s;
    }
    int s = max(size >> l, 1);
    return lg_probe_lookup(chain + off, LG_PROBE_CUBE, s, s, d, 1).xyz;
}

// As ibl_radiance in ibl_shade.frag (lg_probe_lookup_rough above lod 1).
inline float3 ibl_radiance(global const float4 *probe, int layout, int pw, int ph,
                           int bilinear, float4 r0, float4 r1, float4 r2,
                           global const float4 *chain, int size, int levels, float3 dir,
                           float rough)
{
    if (!(rough > 0.0f) || levels < 2)
        return ibl_lookup(probe, layout, pw, ph, bilinear, r0, r1, r2, dir);
    float lod = rough * (float)(levels - 1);
    float3 d = lg_probe_from_world(r0.xyz, r1.xyz, r2.xyz, dir);
    if (lod < 1.0f) {
        float3 a = ibl_lookup(probe, layout, pw, ph, bilinear, r0, r1, r2, dir);
        float3 b = ibl_chain_level(chain, size, 1, d);
        return a + (b - a) * lod;
    }
    int lo = (int)floor(lod);
    float f = lod - (float)lo;
    int hi = min(lo + 1, levels - 1);
    float3 a = ibl_chain_level(chain, size, lo, d), b = ibl_chain_level(chain, size, hi, d);
    return a + (b - a) * f;
}

// As ibl_normal in ibl_shade.frag.
inline float3 ibl_normal(float3 n, float3 V, int double_sided)
{
    float m = fmax(fabs(n.x), fmax(fabs(n.y), fabs(n.z)));
    if (!(m > 1e-30f) || lg_probe_nonfinite(m))
        return -V;
    float3 N = n / m;
    N = N * (1.0f / sqrt(dot(N, N)));
    float d = dot(N, V);
    if (d > 0.0f) {
        if (double_sided)
            return -N;
        float3 t = N - d * V;
        float l = sqrt(dot(t, t));
        return l > 1e-6f ? t / l : -V;
    }
    return N;
}

inline float ibl_clean(float x)
{
    return (as_uint(x) & 0x7fffffffu) > 0x7f800000u ? 0.0f : x;
}

inline float4 ibl_mul(const float16 m, float4 v)
{
    return m.s0123 * v.x + m.s4567 * v.y + m.s89ab * v.z + m.scdef * v.w;
}

kernel void ibl_shade(int mode, int width, int height, float16 inv_view_proj,
                      global const float4 *gbuf, global const float4 *gbuf2,
                      global const float *gdepth,
                      int has_base, global const float4 *base, int has_base_depth,
                      global const float *base_depth, global const float4 *mats,
                      global const float4 *probe, int layout, int pw, int ph, int bilinear,
                      float4 r0, float4 r1, float4 r2, int fresnel, int format,
                      global void *out, global float *out_depth, global uint *clamped,
                      global const float4 *chain, int chain_size, int chain_levels,
                      global const float2 *dfg, int dfg_size)
{
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height)
        return;
    size_t i = (size_t)y * width + x;
    float2 ndc = ((float2)((float)x, (float)y) + 0.5f) / (float2)((float)width, (float)height)
                 * 2.0f - 1.0f;
    float4 a = ibl_mul(inv_view_proj, (float4)(ndc.x, ndc.y, -1.0f, 1.0f));
    float4 b = ibl_mul(inv_view_proj, (float4)(ndc.x, ndc.y, 1.0f, 1.0f));
    float3 V = lg_probe_safe_dir(b.xyz / b.w - a.xyz / a.w);

    float4 g = gbuf ? gbuf[i] : (float4)(0.0f);
    float4 g2 = gbuf2 ? gbuf2[i] : (float4)(0.0f); // the pixel's F0 and roughness
    float gd = gdepth ? gdepth[i] : 1.0f;
    // has_base 2: an rgbe8 base, four bytes a pixel (decoded, alpha 1)
    float4 bc = has_base == 1   ? base[i]
                : has_base == 2 ? (float4)(lg_rgbe_decode(((global const uchar4 *)base)[i]), 1.0f)
                                : (float4)(0.0f, 0.0f, 0.0f, 1.0f);
    float bd = has_base_depth ? base_depth[i] : 1.0f;
    int mat = (int)(g.w + 0.5f) - 1;

    float4 c;
    float depth;
    if (mode == IBL_BACKGROUND) {
        int covered = gd < 1.0f || bd < 1.0f;
        c = covered ? bc
                    : (float4)(ibl_lookup(probe, layout, pw, ph, bilinear, r0, r1, r2, V), 1.0f);
        depth = fmin(gd, bd);
    } else if (mat < 0) {
        c = bc;
        depth = bd;
    } else {
        float4 m1 = mats[2 * mat + 1];
        float3 N = ibl_normal(g.xyz, V, m1.x != 0.0f);
        float ndv = dot(N, V);
        float cosv = clamp(-ndv, 0.0f, 1.0f);
        float3 L = mode == IBL_REFLECT ? V - 2.0f * ndv * N : N;
        float rough = chain_levels >= 2 ? g2.w : 0.0f;
        float3 F = g2.xyz;
        if (fresnel) {
            if (rough > 0.0f) {
                float2 ab = ibl_dfg(dfg, dfg_size, cosv, rough);
                F = F * ab.x + ab.y;
            } else {
                float k = 1.0f - cosv, k2 = k * k;
                F = F + ((float3)(1.0f) - F) * (k2 * k2 * k);
            }
        }
        float3 rad = ibl_radiance(probe, layout, pw, ph, bilinear, r0, r1, r2, chain,
                                  chain_size, chain_levels, L, rough);
        c = (float4)(bc.xyz + F * rad, bc.w);
        depth = gd;
    }
    c = (float4)(ibl_clean(c.x), ibl_clean(c.y), ibl_clean(c.z), ibl_clean(c.w));
    if (format == IBL_RGBA16F) {
        if (c.x > 65504.0f || c.y > 65504.0f || c.z > 65504.0f)
            atomic_inc(clamped);
        vstore_half4_rte(lg_half_range(c), i, (global half *)out);
    } else if (format == IBL_RGBE8) {
        ((global uchar4 *)out)[i] = lg_rgbe_encode(c.xyz);
    } else {
        ((global float4 *)out)[i] = c;
    }
    if (out_depth)
        out_depth[i] = depth;
}
