// shaders/volumetric_froxel/froxel.cl: the cl backend of volumetric_froxel, built after
// shaders/common/medium.cl. plugins/volumetric_froxel/froxel.h is the spec; froxel_cpu.c
// computes the same in C. Volumes are rgba float4 arrays [k][j][i].
//
// Per directional light l, `lights` holds 8 floats: dir.xyz (travels), shadow record (as a
// float, -1 = unshadowed), l_c.rgb, its index among the frame's lights (the optical-depth
// volume's). Per shadow record, `shadows` holds FX_REC floats: view_proj (column-major; a
// paraboloid record's view), tile_x, tile_y, face (LG_SHADOW_FACE_*), znear, depth_range,
// 0, 0, 0. Point and spot lights: `locals`, FX_LOCAL floats each (fx_local_sum).
#define FX_REC 24
#define FX_LOCAL 20

// FX_FULL (a build option, froxel_cl.c): 1 for the program that handles point and spot
// lights and heterogeneous media (then per-frame kernel arguments say which); 0 (the
// default) compiles those branches away, so that directional lights in a homogeneous
// medium run exactly the code they ran before issue 25.
#ifndef FX_FULL
#define FX_FULL 0
#endif

// The unit view ray through image point (x, y) (vol_ray), from vol_ray_matrix's rvp: the
// offset from the eye made in double on the host (not r.xyz / r.w - eye in float: NDC z 0
// lies millimetres from the eye, and that difference cost the ray up to 8e-6 rad).
float3 fx_ray(float16 rvp, float x, float y, float W, float H)
{
    float4 ndc = (float4)(2.0f * x / W - 1.0f, 2.0f * y / H - 1.0f, 0.0f, 1.0f);
    float4 r = rvp.s0123 * ndc.x + rvp.s4567 * ndc.y + rvp.scdef;
    return normalize(r.xyz / r.w);
}

// vol_shadow_cpu: 1 lit, 0 shadowed.
float fx_shadow(__global const float *shadows, int rec, __global const float *atlas,
                int aw, int ah, int res, float bias, float3 p)
{
    if (rec < 0)
        return 1.0f;
    __global const float *m = shadows + FX_REC * rec;
    float4 c = (float4)(m[0], m[1], m[2], m[3]) * p.x + (float4)(m[4], m[5], m[6], m[7]) * p.y +
               (float4)(m[8], m[9], m[10], m[11]) * p.z + (float4)(m[12], m[13], m[14], m[15]);
    float u = c.x / c.w * 0.5f + 0.5f, v = c.y / c.w * 0.5f + 0.5f, z = c.z / c.w * 0.5f + 0.5f;
    if (!(u >= 0.0f && u < 1.0f && v >= 0.0f && v < 1.0f) || !(z >= 0.0f))
        return 1.0f;
    int tx = (int)m[16] + (int)(u * res), ty = (int)m[17] + (int)(v * res);
    if (tx >= aw || ty >= ah)
        return 1.0f;
    return z > atlas[ty * aw + tx] + bias ? 0.0f : 1.0f;
}

float3 fx_trilinear(__global const float4 *vol, int W, int H, int D, float3 c)
{
    float3 lim = (float3)(W - 1, H - 1, D - 1);
    c = clamp(c, (float3)(0.0f), lim);
    float3 fl = floor(c), fr = c - fl;
    int3 i0 = convert_int3(fl);
    int3 i1 = min(i0 + 1, convert_int3(lim));
    float3 r = (float3)(0.0f);
    for (int corner = 0; corner < 8; corner++) {
        int ii = (corner & 1) ? i1.x : i0.x, jj = (corner & 2) ? i1.y : i0.y,
            kk = (corner & 4) ? i1.z : i0.z;
        float w = ((corner & 1) ? fr.x : 1.0f - fr.x) * ((corner & 2) ? fr.y : 1.0f - fr.y) *
                  ((corner & 4) ? fr.z : 1.0f - fr.z);
        r += w * vol[(kk * H + jj) * W + ii].xyz;
    }
    return r;
}

// ---- point and spot lights, heterogeneous media (froxel.h 4.) --------------------------------

// lg_shadowmap_visibility for record rec (the one that holds p): the fraction of the
// (2 pcf + 1)^2 taps around p's texel in which p is lit, each tap clamped to the tile; lit
// outside the tile, behind a perspective record's near plane or without a record.
float fx_visibility(__global const float *shadows, int rec, __global const float *atlas,
                    int aw, int ah, int res, float bias, int pcf, float3 p)
{
    if (rec < 0)
        return 1.0f;
    __global const float *m = shadows + FX_REC * rec;
    int face = (int)m[18];
    float3 ndc;
    if (face >= 16) {
        // dual paraboloid: m is the record's view; depth is the distance past znear over
        // depth_range (plugins/shadowmap/README.md)
        float3 v = (float3)(m[0], m[1], m[2]) * p.x + (float3)(m[4], m[5], m[6]) * p.y +
                   (float3)(m[8], m[9], m[10]) * p.z + (float3)(m[12], m[13], m[14]);
        float len = length(v);
        if (!(len > 0.0f))
            return 1.0f;
        float zf = face == 16 ? -v.z / len : v.z / len;
        ndc = (float3)(v.x / len / (1.0f + zf), v.y / len / (1.0f + zf),
                       2.0f * (len - m[19]) / m[20] - 1.0f);
        if (face == 17)
            ndc.x = -ndc.x;
    } else {
        float4 c = (float4)(m[0], m[1], m[2], m[3]) * p.x + (float4)(m[4], m[5], m[6], m[7]) * p.y +
                   (float4)(m[8], m[9], m[10], m[11]) * p.z +
                   (float4)(m[12], m[13], m[14], m[15]);
        if (!(c.w > 0.0f))
            return 1.0f;
        ndc = c.xyz / c.w;
    }
    float u = ndc.x * 0.5f + 0.5f, v = ndc.y * 0.5f + 0.5f, z = ndc.z * 0.5f + 0.5f;
    if (!(u >= 0.0f && u < 1.0f && v >= 0.0f && v < 1.0f) || !(z >= 0.0f))
        return 1.0f;
    z = fmin(z, 1.0f);
    int cx = (int)(u * res), cy = (int)(v * res), tx0 = (int)m[16], ty0 = (int)m[17];
    int lit = 0;
    for (int dy = -pcf; dy <= pcf; dy++) {
        int ty = ty0 + clamp(cy + dy, 0, res - 1);
        for (int dx = -pcf; dx <= pcf; dx++) {
            int tx = tx0 + clamp(cx + dx, 0, res - 1);
            lit += tx >= aw || ty >= ah || !(z > atlas[ty * aw + tx] + bias);
        }
    }
    return (float)lit / (float)((2 * pcf + 1) * (2 * pcf + 1));
}

// vol_tau_sample: light l's optical depth at p, trilinear between the cell centres of its
// volume, clamped to the box. taud holds 12 floats per light: lo.xyz, hi.xyz, n.xyz, the
// volume's offset in `tau` (its bits, as_int), 0, 0.
float fx_tau(__global const float *tau, __global const float *taud, int l, float3 p)
{
    __global const float *d = taud + 12 * l;
    float3 lo = (float3)(d[0], d[1], d[2]), hi = (float3)(d[3], d[4], d[5]);
    int3 n = (int3)((int)d[6], (int)d[7], (int)d[8]);
    float3 nm1 = convert_float3(n - 1);
    float3 u = clamp((p - lo) / (hi - lo) * nm1, (float3)(0.0f), nm1);
    int3 i0 = min(convert_int3(floor(u)), n - 2);
    float3 f = u - convert_float3(i0);
    __global const float *t = tau + as_int(d[9]) + (i0.z * n.y + i0.y) * n.x + i0.x;
    int sy = n.x, sz = n.x * n.y;
    float a = mix(t[0], t[1], f.x), b = mix(t[sy], t[sy + 1], f.x);
    float c = mix(t[sz], t[sz + 1], f.x), e = mix(t[sz + sy], t[sz + sy + 1], f.x);
    return mix(mix(a, b, f.y), mix(c, e, f.y), f.z);
}

// The point and spot lights' share of S at sample point p of a froxel whose slice spans
// distances [r0, r1] along the column's ray w from the eye (froxel.h 4.), without rho.
// Per light, `locals` holds FX_LOCAL floats: pos.xyz, range, axis.xyz (a spot's; travels),
// is_spot, l_c.rgb, its first shadow record (-1: unshadowed), cos_inner, cos_outer, records
// (6 a cube, 2 dual paraboloid, else 1), its index among the frame's lights, the light's
// position as its first record's view matrix gives it (the cube's face choice, as
// lg_shadowmap_record_at), 0. nodes 0: the point sample; 1 .. 8: the segment average of
// lg_point_inscatter with that many nodes. grey: one exp for the transmittance, not three.
float3 fx_local_sum(int n_loc, __global const float *locals, float3 eye, float3 w, float3 p,
                    float r0, float r1, int nodes, float g, float3 sigma_t, int grey, int het,
                    __global const float *tau, __global const float *taud,
                    __global const float *shadows, __global const float *atlas, int aw, int ah,
                    int res, float bias, int pcf)
{
    float3 s = (float3)(0.0f);
    float inv_len = 1.0f / (r1 - r0);
    for (int l = 0; l < n_loc; l++) {
        __global const float *L = locals + FX_LOCAL * l;
        float3 q = (float3)(L[0], L[1], L[2]), axis = (float3)(L[4], L[5], L[6]);
        float range = L[3];
        int is_spot = L[7] != 0.0f;
        float2 cone = (float2)(L[12], L[13]);
        float3 tl;
        float dist;
        float f = lg_local_falloff(q, range, is_spot, axis, cone, p, &tl, &dist);
        if (nodes > 0)
            f = lg_point_inscatter(eye, w, r0, r1, q, range, is_spot, axis, cone, g, 0.0f,
                                   nodes) * inv_len;
        else
            f *= lg_hg_phase(g, dot(w, tl));
        int rec = (int)L[11];
        if (rec >= 0) {
            int faces = (int)L[14];
            if (faces == 6) {
                float3 dv = p - (float3)(L[16], L[17], L[18]), a = fabs(dv);
                int ax = a.y > a.x ? (a.z > a.y ? 2 : 1) : (a.z > a.x ? 2 : 0);
                float comp = ax == 0 ? dv.x : ax == 1 ? dv.y : dv.z;
                rec += 2 * ax + (comp < 0.0f ? 1 : 0);
            } else if (faces == 2) {
                __global const float *m = shadows + FX_REC * rec;
                float vz = m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14];
                rec += vz > 0.0f ? 1 : 0;
            }
            f *= fx_visibility(shadows, rec, atlas, aw, ah, res, bias, pcf, p);
        }
        float od = het ? fx_tau(tau, taud, (int)L[15], p) : dist;
        float3 x = grey ? (float3)(exp(-sigma_t.x * od)) : exp(-sigma_t * od);
        s += (float3)(L[8], L[9], L[10]) * f * x;
    }
    return s;
}

// Light pass (eq. 11) and accumulation (eq. 12): one work-item per column. What depends
// only on the column is computed once: 1 / cos, the sum over unshadowed lights of
// sigma_s C_l p_HG, and per shadowed light sigma_s C_l p_HG and the light-clip position
// as an affine function of view depth, clip(t) = a_l + b_l t (a_l = VP_l e, b_l = VP_l w /
// cos), so that a shadow test is 4 multiply-adds, a reciprocal and one fetch. What depends
// only on the slice comes from `slices` (4 D + 1 floats): T(k + jitter), t_{k+1} - t_k (t_0
// = 0), T(k + 0.5), and T(k) for k = 0 .. D (the lookup's). grey (sigma_t the same in r, g,
// b): one exp and one segment factor per froxel instead of three; the same values.
#define FX_MAX_LIGHTS 32
__kernel void fx_columns(int W, int H, int D, float16 ivp, float16 rvp, float4 eye, float4 fwd, float4 img,
                         __global const float *slices, int accum, int grey,
                         float4 sigma_s, float4 sigma_t, float g,
                         int n_lights, __global const float *lights,
                         __global const float *shadows, __global const float *atlas,
                         int aw, int ah, int res, float bias,
                         int blend, float history, float16 prev_vp, float4 prev_eye,
                         float4 prev_fwd, int prev_slicing, float4 prev_map,
                         __global const float4 *hist, __global float4 *S,
                         __global float4 *grid, int n_loc, __global const float *locals,
                         int nodes, int pcf, int het, __global const float *density,
                         __global const float *tau, __global const float *taud,
                         __global float *path)
{
    het = FX_FULL && het;
    n_loc = FX_FULL ? n_loc : 0;
    int col = get_global_id(0);
    if (col >= W * H)
        return;
    int i = col % W, j = col / W;
    float3 w = fx_ray(rvp, (i + 0.5f) * img.x / W, (j + 0.5f) * img.y / H, img.x,
                      img.y);
    float cosv = dot(w, fwd.xyz);
    float inv_cos = 1.0f / cosv;
    float3 unsh = (float3)(0.0f);
    float4 la[FX_MAX_LIGHTS], lb[FX_MAX_LIGHTS];
    float3 lp[FX_MAX_LIGHTS];
    int2 tile[FX_MAX_LIGHTS];
    int nsh = 0;
    // heterogeneous: every light's term has its own transmittance, so the unshadowed
    // directional ones are summed per froxel (un, with their light indices ui; li for the
    // shadowed ones) instead of into the column constant
    float3 un[FX_MAX_LIGHTS];
    int li[FX_MAX_LIGHTS], ui[FX_MAX_LIGHTS];
    int nun = 0;
    for (int l = 0; l < n_lights; l++) {
        __global const float *L = lights + 8 * l;
        float3 c = sigma_s.xyz * (float3)(L[4], L[5], L[6]) *
                   lg_hg_phase(g, -dot(w, (float3)(L[0], L[1], L[2])));
        int rec = (int)L[3];
        if (rec < 0 && het) {
            un[nun] = c;
            ui[nun++] = (int)L[7];
            continue;
        }
        if (rec < 0) {
            unsh += c;
            continue;
        }
        li[nsh] = (int)L[7];
        __global const float *m = shadows + FX_REC * rec;
        float4 c0 = (float4)(m[0], m[1], m[2], m[3]), c1 = (float4)(m[4], m[5], m[6], m[7]),
               c2 = (float4)(m[8], m[9], m[10], m[11]), c3 = (float4)(m[12], m[13], m[14], m[15]);
        la[nsh] = c0 * eye.x + c1 * eye.y + c2 * eye.z + c3;
        lb[nsh] = (c0 * w.x + c1 * w.y + c2 * w.z) * inv_cos;
        lp[nsh] = c;
        tile[nsh] = (int2)((int)m[16], (int)m[17]);
        nsh++;
    }
    float fres = (float)res;
    float3 acc = (float3)(0.0f), tr = (float3)(1.0f);
    float opt = 0.0f; // heterogeneous: the optical path P_k (froxel.h 4.)
    for (int k = 0; k < D; k++) {
        float t = slices[k];
        float3 s = unsh;
        float3 p = eye.xyz + w * (t * inv_cos); // the sample point (local lights, fields)
        for (int l = 0; l < nsh; l++) {
            float4 c = la[l] + lb[l] * t;
            float iw = 1.0f / c.w;
            float u = c.x * iw * 0.5f + 0.5f, v = c.y * iw * 0.5f + 0.5f, z = c.z * iw * 0.5f + 0.5f;
            bool lit = true;
            if (u >= 0.0f && u < 1.0f && v >= 0.0f && v < 1.0f && z >= 0.0f) {
                int tx = tile[l].x + (int)(u * fres), ty = tile[l].y + (int)(v * fres);
                if (tx < aw && ty < ah)
                    lit = !(z > atlas[ty * aw + tx] + bias);
            }
            float3 term = lit ? lp[l] : (float3)(0.0f);
            if (het)
                term *= exp(-sigma_t.xyz * fx_tau(tau, taud, li[l], p));
            s += term;
        }
        for (int l = 0; l < nun; l++)
            s += un[l] * exp(-sigma_t.xyz * fx_tau(tau, taud, ui[l], p));
        if (n_loc > 0) {
            float r0 = (k == 0 ? 0.0f : slices[3 * D + k]) * inv_cos;
            float r1 = slices[3 * D + k + 1] * inv_cos;
            s += sigma_s.xyz * fx_local_sum(n_loc, locals, eye.xyz, w, p, r0, r1, nodes, g,
                                            sigma_t.xyz, grey, het, tau, taud, shadows, atlas,
                                            aw, ah, res, bias, pcf);
        }
        float rho = het ? density[k * W * H + col] : 1.0f;
        s *= rho;
        if (blend) {
            float3 q = eye.xyz + w * (slices[2 * D + k] * inv_cos);
            float4 c = prev_vp.s0123 * q.x + prev_vp.s4567 * q.y + prev_vp.s89ab * q.z +
                       prev_vp.scdef;
            if (c.w > 0.0f) {
                float u = (c.x / c.w + 1.0f) * W * 0.5f, v = (c.y / c.w + 1.0f) * H * 0.5f;
                float z = lg_depth_to_slice(prev_slicing, prev_map, dot(q - prev_eye.xyz,
                                                                        prev_fwd.xyz));
                if (u >= 0.0f && u <= W && v >= 0.0f && v <= H && z >= 0.0f && z <= D)
                    s = mix(s, fx_trilinear(hist, W, H, D, (float3)(u, v, z) - 0.5f),
                            history);
            }
        }
        int idx = k * W * H + col;
        S[idx] = (float4)(s, 1.0f);
        float delta = slices[D + k] * inv_cos;
        // the slice's optical length: rho Delta (heterogeneous), Delta (homogeneous)
        float od = het ? rho * delta : delta;
        if (het) {
            opt += od;
            path[idx] = opt;
        }
        if (accum == 0) {
            acc += s * delta;
        } else if (grey) {
            float tau = sigma_t.x * od;
            acc += tr * s * (delta * lg_medium_segment(tau));
            tr *= exp(-tau);
        } else {
            float3 tau = sigma_t.xyz * od;
            float3 seg = (float3)(lg_medium_segment(tau.x), lg_medium_segment(tau.y),
                                  lg_medium_segment(tau.z));
            acc += tr * s * delta * seg;
            tr *= exp(-tau);
        }
        grid[idx] = (float4)(acc, (tr.x + tr.y + tr.z) / 3.0f);
    }
}

float3 fx_bilinear(__global const float4 *vol, int W, int H, int k, float u, float v)
{
    u = clamp(u, 0.0f, (float)(W - 1));
    v = clamp(v, 0.0f, (float)(H - 1));
    int i0 = (int)u, j0 = (int)v;
    int i1 = min(i0 + 1, W - 1), j1 = min(j0 + 1, H - 1);
    float fu = u - i0, fv = v - j0;
    __global const float4 *s = vol + k * W * H;
    float3 a = mix(s[j0 * W + i0].xyz, s[j0 * W + i1].xyz, fu);
    float3 b = mix(s[j1 * W + i0].xyz, s[j1 * W + i1].xyz, fu);
    return mix(a, b, fv);
}

// fx_bilinear of a one-float-per-cell volume (rho, the optical path).
float fx_bilinear1(__global const float *vol, int W, int H, int k, float u, float v)
{
    u = clamp(u, 0.0f, (float)(W - 1));
    v = clamp(v, 0.0f, (float)(H - 1));
    int i0 = (int)u, j0 = (int)v;
    int i1 = min(i0 + 1, W - 1), j1 = min(j0 + 1, H - 1);
    float fu = u - i0, fv = v - j0;
    __global const float *s = vol + k * W * H;
    return mix(mix(s[j0 * W + i0], s[j0 * W + i1], fu), mix(s[j1 * W + i0], s[j1 * W + i1], fu),
               fv);
}

// Lookup: one work-item per pixel. The slice start T(k) comes from `slices` (fx_columns'
// table; a pow per pixel otherwise); grey: one exp per factor, as fx_columns.
__kernel void fx_lookup(int W, int H, int D, float16 ivp, float16 rvp, float4 eye, float4 fwd, float4 img,
                        int slicing, float4 map, __global const float *slices,
                        float z_limit, int accum, int grey, float4 sigma_t,
                        __global const float4 *grid, __global const float4 *S,
                        __global const float4 *base, __global const float *base_depth,
                        __global float4 *out, __global float *out_depth,
                        __global float4 *ins, int het, __global const float *density,
                        __global const float *path)
{
    het = FX_FULL && het;
    int p = get_global_id(0);
    int iw = (int)img.x, ih = (int)img.y;
    if (p >= iw * ih)
        return;
    float x = (p % iw) + 0.5f, y = (p / iw) + 0.5f;
    float depth = base_depth[p];
    float3 w = fx_ray(rvp, x, y, img.x, img.y);
    float cosv = dot(w, fwd.xyz);
    // vol_fog_length
    float d = cosv > 0.0f ? z_limit / cosv : INFINITY;
    if (depth < 1.0f && isfinite(depth)) {
        float4 ndc = (float4)(2.0f * x / img.x - 1.0f, 2.0f * y / img.y - 1.0f,
                              2.0f * depth - 1.0f, 1.0f);
        float4 r = ivp.s0123 * ndc.x + ivp.s4567 * ndc.y + ivp.s89ab * ndc.z + ivp.scdef;
        d = fmin(d, length(r.xyz / r.w - eye.xyz));
    }
    float t_end = d * cosv;
    float zc = clamp(lg_depth_to_slice(slicing, map, t_end), 0.0f, (float)D);
    int k = min((int)floor(zc), D - 1);
    float t_s = k == 0 ? 0.0f : slices[3 * D + k];
    float delta = fmax(t_end - t_s, 0.0f) / cosv;
    float u = x * W / img.x - 0.5f, v = y * H / img.y - 0.5f;
    float3 a = k > 0 ? fx_bilinear(grid, W, H, k - 1, u, v) : (float3)(0.0f);
    float3 s = fx_bilinear(S, W, H, k, u, v);
    float4 b = base[p];
    float3 lv, tv = (float3)(1.0f);
    if (het && accum != 0) {
        // froxel.h 4.: the optical path to the slice's start P_{k-1} and the slice's rho
        float pk = k > 0 ? fx_bilinear1(path, W, H, k - 1, u, v) : 0.0f;
        float rk = fx_bilinear1(density, W, H, k, u, v);
        float3 tau = sigma_t.xyz * (rk * delta);
        float3 seg = (float3)(lg_medium_segment(tau.x), lg_medium_segment(tau.y),
                              lg_medium_segment(tau.z));
        lv = a + exp(-sigma_t.xyz * pk) * s * delta * seg;
        tv = exp(-sigma_t.xyz * (pk + rk * delta));
    } else if (accum == 0) {
        lv = a + s * delta;
    } else if (grey) {
        float st = sigma_t.x;
        lv = a + exp(-st * (t_s / cosv)) * s * (delta * lg_medium_segment(st * delta));
        tv = (float3)(exp(-st * d));
    } else {
        float3 tau = sigma_t.xyz * delta;
        float3 seg = (float3)(lg_medium_segment(tau.x), lg_medium_segment(tau.y),
                              lg_medium_segment(tau.z));
        lv = a + exp(-sigma_t.xyz * (t_s / cosv)) * s * delta * seg;
        tv = exp(-sigma_t.xyz * d);
    }
    ins[p] = (float4)(lv, 1.0f);
    out[p] = (float4)(b.xyz * tv + lv, b.w);
    out_depth[p] = depth;
}
