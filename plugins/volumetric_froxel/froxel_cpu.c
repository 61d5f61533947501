/*
 * The cpu backend of volumetric_froxel: froxel.h's three passes over the host's thread
 * pool. It is the reference of the spec: the light pass and the accumulation run fused,
 * one column per index (the accumulation needs the whole column of S, which the same
 * index has just computed), then the lookup one image row per index. Every index writes
 * only its own column or row, so the result is the same bits for any thread count.
 *
 * Arithmetic in double where it costs nothing (rays, depths, the per-light sum); stored
 * values are float, as the GPU backends store them.
 *
 * froxel.h 4. (point and spot lights, density fields) is a second path behind per-frame
 * flags: the lights it takes (every point and spot light; with a density field every light,
 * since each then has its own transmittance X_l) leave the directional fast path, and a
 * frame with only directional lights in a homogeneous medium runs the loop of 1-3 alone.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/vecmath.h"

#include "froxel.h"

typedef struct fx_cpu {
    uint32_t w, h, d;
    float *s;    /* S of this frame, rgba, [k][j][i] */
    float *hist; /* the previous frame's blended S (valid when hist_valid) */
    bool hist_valid;
    float *tj;        /* the frame's T(k + jitter) in float (columns' inner loop) */
    uint64_t counted; /* bytes counted with lg_account_alloc (S and its history) */
    /* heterogeneous medium: each column's optical path P_k (froxel.h 4.), [k][j][i]; made
     * on the first such frame */
    float *path;
    /* the orthographic records' depth bounds per FX_MM_BLOCK^2 texels (fx_minmax), made
     * each frame: mm_cap floats */
    float *mm;
    size_t mm_cap;
} fx_cpu;

/* Texels per side of a block of the depth bounds: a 256^2 tile's bounds take 8 KiB and
 * stay in the L1 cache while its 256 KiB of depths do not. */
#define FX_MM_BLOCK 8

/* A light of the froxel.h 4. path, with what the frame knows of it. */
typedef struct fx_cpu_light {
    const vol_light *L;
    double q[3];    /* point, spot: position */
    double axis[3]; /* spot: the axis (direction light travels) */
    double cos_in, cos_out;
    double range; /* 0: infinite */
    double lc[3]; /* sigma_s C_l */
    bool dir, spot;
    int32_t rec;               /* its first shadow record, or -1 */
    const vol_tau_volume *tau; /* heterogeneous: its optical-depth volume */
} fx_cpu_light;

typedef struct fx_cpu_ctx {
    const fx_frame *f;
    fx_cpu *c;
    const float *atlas; /* shadow atlas depth plane, or NULL */
    float *grid;        /* rgba32f W x H x D */
    const float *base, *base_depth;
    float *out, *out_depth, *ins;
    float prev_vp[16]; /* the previous camera's view_proj (temporal) */
    bool blend;
    bool grey;          /* sigma_t the same in r, g, b: one exp per froxel */
    double inv_sigma_t; /* grey: 1 / sigma_t (0 when sigma_t = 0) */
    /* per frame: the slice tables (D entries each; tk D + 1) */
    const float *tj;    /* T(k + jitter) */
    const double *tlen; /* t_{k+1} - t_k (t_0 = 0) */
    const double *tq;   /* T(k + 0.5) (temporal) */
    const double *tk;   /* T(k), k = 0 .. D (the lookup's slice start) */
    /* per light: its shadow record or -1; the shadowed lights in order: */
    int32_t rec[VOL_MAX_LIGHTS];
    uint32_t n_sh;
    float ca[VOL_MAX_LIGHTS][4]; /* a_l = VP_l e */
    uint32_t tile[VOL_MAX_LIGHTS][2];
    /* an orthographic record (w = 1) whose tile lies inside the atlas: the fast form, with
     * a_l in texel units (u, v: (a 0.5 + 0.5) res; z: a 0.5 + 0.5) and tscale the factor of
     * b_l (0.5 res, 0.5 res, 0.5) */
    bool ortho[VOL_MAX_LIGHTS];
    uint32_t n_ortho;
    const float *mm[VOL_MAX_LIGHTS]; /* ortho: (min, max) per block, mm_n blocks a row */
    uint32_t mm_n;
    uint32_t mm_shift; /* the bounds' rows lie 2^mm_shift blocks apart (>= mm_n: a shift, not
                        * a multiply, in the vector loop) */
    float ta[VOL_MAX_LIGHTS][3];
    float tscale[3];
    /* froxel.h 4.: the lights of the second path (n_gen 0: it does not run) */
    fx_cpu_light gen[VOL_MAX_LIGHTS];
    uint32_t n_gen;
    bool het;             /* f->density: rho multiplies S, per-slice extinction */
    int nodes;            /* analytic point and spot lights: Gauss-Legendre nodes, 0 = sample */
    double gx[8], gw[8];  /* the rule's nodes on [-1, 1] and weights */
    double hg_a, hg_k;    /* Henyey-Greenstein: see hg() */
    const float *density; /* f->density */
} fx_cpu_ctx;

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Gauss-Legendre nodes and weights on [-1, 1], 1 .. 8 points, in increasing order (the
 * rule lg_point_inscatter uses, lightgraph/medium.h). */
static const double fx_gl_x[8][8] = {
    { 0.0 },
    { -0.5773502691896257645, 0.5773502691896257645 },
    { -0.7745966692414833770, 0.0, 0.7745966692414833770 },
    { -0.8611363115940525752, -0.3399810435848562648, 0.3399810435848562648,
      0.8611363115940525752 },
    { -0.9061798459386639928, -0.5384693101056830910, 0.0, 0.5384693101056830910,
      0.9061798459386639928 },
    { -0.9324695142031520279, -0.6612093864662645137, -0.2386191860831969086, 0.2386191860831969086,
      0.6612093864662645137, 0.9324695142031520279 },
    { -0.9491079123427585245, -0.7415311855993944399, -0.4058451513773971669, 0.0,
      0.4058451513773971669, 0.7415311855993944399, 0.9491079123427585245 },
    { -0.9602898564975362317, -0.7966664774136267396, -0.5255324099163289858,
      -0.1834346424956498049, 0.1834346424956498049, 0.5255324099163289858, 0.7966664774136267396,
      0.9602898564975362317 },
};
static const double fx_gl_w[8][8] = {
    { 2.0 },
    { 1.0, 1.0 },
    { 0.5555555555555555556, 0.8888888888888888889, 0.5555555555555555556 },
    { 0.3478548451374538574, 0.6521451548625461427, 0.6521451548625461427, 0.3478548451374538574 },
    { 0.2369268850561890875, 0.4786286704993664680, 0.5688888888888888889, 0.4786286704993664680,
      0.2369268850561890875 },
    { 0.1713244923791703450, 0.3607615730481386076, 0.4679139345726910473, 0.4679139345726910473,
      0.3607615730481386076, 0.1713244923791703450 },
    { 0.1294849661688696933, 0.2797053914892766679, 0.3818300505051189449, 0.4179591836734693878,
      0.3818300505051189449, 0.2797053914892766679, 0.1294849661688696933 },
    { 0.1012285362903762592, 0.2223810344533744706, 0.3137066458778872873, 0.3626837833783619830,
      0.3626837833783619830, 0.3137066458778872873, 0.2223810344533744706, 0.1012285362903762592 },
};

/* lg_hg_phase(g, c) with the frame's constants: (1 - g^2) / (4 pi den^1.5), den in the
 * form without cancellation near the forward (g >= 0) or backward (g < 0) peak. */
static double hg(const fx_cpu_ctx *x, double g, double c)
{
    c = c < -1.0 ? -1.0 : c > 1.0 ? 1.0 : c;
    double den = g >= 0.0 ? x->hg_a + 2.0 * g * (1.0 - c) : x->hg_a - 2.0 * g * (1.0 + c);
    return x->hg_k / (den * sqrt(den));
}

/* The range window W(d) (lg_light_window). */
static double window(double d, double range)
{
    if (!(range > 0.0))
        return 1.0;
    double r = d / range, r2 = r * r, w = 1.0 - r2 * r2;
    return w < 0.0 ? 0.0 : w > 1.0 ? 1.0 : w;
}

/* The spot's smooth cone C (lg_spot_cone). */
static double cone(const fx_cpu_light *g, double ca)
{
    double span = g->cos_in - g->cos_out;
    if (span < 1e-4)
        span = 1e-4;
    double t = (ca - g->cos_out) / span;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return t * t;
}

/* A column's constants of the froxel.h 4. path for one local light (analytic mode): the
 * airlight substitution t = tc + H tan(xi) along the column's ray, and xi at the start of
 * the next slice (the end of one slice is the start of the next: one atan per slice). */
typedef struct fx_col_light {
    double tc, h2, H; /* dot(q - e, w), squared distance of q to the ray's line, sqrt(h2 + eps^2) */
    double qa, wa;    /* spot: dot(q - e, axis), dot(w, axis) */
    double xi;        /* xi at the current slice's start */
    double dp;        /* directional (heterogeneous medium): p_HG(g, dot(w, -L)) */
} fx_col_light;

/* The column constants of fx_col_light for every light of the second path. */
static void gen_column(const fx_cpu_ctx *x, const double w[3], fx_col_light *cl)
{
    const vol_setup *v = x->f->v;
    for (uint32_t l = 0; l < x->n_gen; l++) {
        const fx_cpu_light *g = &x->gen[l];
        fx_col_light *c = &cl[l];
        if (g->dir) {
            c->dp = hg(x, v->g, -dot3(w, g->axis));
            continue;
        }
        double qo[3] = { g->q[0] - v->eye[0], g->q[1] - v->eye[1], g->q[2] - v->eye[2] };
        c->tc = dot3(qo, w);
        c->h2 = dot3(qo, qo) - c->tc * c->tc;
        if (c->h2 < 0.0)
            c->h2 = 0.0;
        c->H = sqrt(c->h2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
        c->qa = dot3(qo, g->axis);
        c->wa = dot3(w, g->axis);
        c->xi = atan((0.0 - c->tc) / c->H); /* slice 0 starts at the eye */
    }
}

/* froxel.h 4.: the in-scattering of the second path's lights at froxel (column ray w, slice
 * k) per unit length, before rho, added to s. Sample: F and the phase at the sample point
 * p; analytic: the slice's airlight integral over its length (lg_point_inscatter with
 * sigma_t = 0, evaluated with the column's constants); both times the shadow and X_l at p. */
static void gen_terms(const fx_cpu_ctx *x, const double w[3], double inv_cos, uint32_t k,
                      fx_col_light *cl, double s[3])
{
    const fx_frame *f = x->f;
    const vol_setup *v = f->v;
    const double ts = f->slices->tj[k] * inv_cos;
    const double p[3] = { v->eye[0] + w[0] * ts, v->eye[1] + w[1] * ts, v->eye[2] + w[2] * ts };
    for (uint32_t l = 0; l < x->n_gen; l++) {
        const fx_cpu_light *g = &x->gen[l];
        fx_col_light *c = &cl[l];
        double a, dist = 0.0;
        if (g->dir) {
            a = c->dp;
        } else {
            double vq[3] = { g->q[0] - p[0], g->q[1] - p[1], g->q[2] - p[2] };
            double d2 = dot3(vq, vq), d = sqrt(d2);
            dist = d;
            if (x->nodes && (g->spot || g->range > 0.0)) {
                /* a cone or a range: lg_point_inscatter itself, whose nodes cover only the
                 * part of the slice the light reaches (the column's xi carried as below) */
                double b0 = k == 0 ? 0.0 : f->slices->tk[k] * inv_cos;
                double b1 = f->slices->tk[k + 1] * inv_cos;
                c->xi = atan((b1 - c->tc) / c->H);
                double sp[5] = { g->axis[0], g->axis[1], g->axis[2], g->cos_in, g->cos_out };
                a = lg_point_inscatter(v->eye, w, b0, b1, g->q, g->range, g->spot ? sp : NULL, v->g,
                                       0.0, x->nodes) /
                    (f->slices->tlen[k] * inv_cos);
            } else if (x->nodes) {
                /* the slice [b_k, b_{k+1}] along the ray, t = tc + H tan(xi) */
                double b1 = f->slices->tk[k + 1] * inv_cos;
                double xi1 = atan((b1 - c->tc) / c->H), xi0 = c->xi;
                c->xi = xi1;
                double half = 0.5 * (xi1 - xi0), mid = 0.5 * (xi1 + xi0), sum = 0.0;
                for (int i = 0; i < x->nodes; i++) {
                    double tt = c->H * tan(mid + half * x->gx[i]); /* t - tc */
                    double dd = sqrt(c->h2 + tt * tt);
                    double fv = hg(x, v->g, dd > 0.0 ? -tt / dd : 0.0) * window(dd, g->range);
                    if (g->spot)
                        fv *= cone(g, dd > 0.0 ? -(c->qa - (c->tc + tt) * c->wa) / dd : 1.0);
                    sum += x->gw[i] * fv;
                }
                a = half * sum / c->H / (f->slices->tlen[k] * inv_cos);
            } else {
                double lu[3];
                for (int ch = 0; ch < 3; ch++)
                    lu[ch] = d > 0.0 ? vq[ch] / d : -g->axis[ch];
                a = window(d, g->range) / (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
                if (g->spot)
                    a *= cone(g, -dot3(lu, g->axis));
                a *= hg(x, v->g, dot3(w, lu));
            }
        }
        if (a == 0.0)
            continue; /* outside the cone or the range: no shadow lookup */
        if (g->rec >= 0) {
            a *= vol_shadow_cpu(f->sm, x->atlas, g->rec, p);
            if (a == 0.0)
                continue;
        }
        if (x->het) {
            double tau = vol_tau_sample(g->tau, p);
            if (x->grey) {
                double e = a * exp(-v->sigma_t[0] * tau);
                for (int ch = 0; ch < 3; ch++)
                    s[ch] += e * g->lc[ch];
            } else {
                for (int ch = 0; ch < 3; ch++)
                    s[ch] += a * exp(-v->sigma_t[ch] * tau) * g->lc[ch];
            }
        } else if (g->dir) {
            for (int ch = 0; ch < 3; ch++)
                s[ch] += a * g->lc[ch];
        } else if (x->grey) {
            double e = a * exp(-v->sigma_t[0] * dist);
            for (int ch = 0; ch < 3; ch++)
                s[ch] += e * g->lc[ch];
        } else {
            for (int ch = 0; ch < 3; ch++)
                s[ch] += a * exp(-v->sigma_t[ch] * dist) * g->lc[ch];
        }
    }
}

/* Column (i, j)'s ray and its cos to the forward axis (froxel.h). */
static void column_ray(const fx_frame *f, uint32_t i, uint32_t j, double w[3], double *cosv)
{
    const vol_setup *v = f->v;
    vol_ray(v, (i + 0.5) * v->width / f->w, (j + 0.5) * v->height / f->h, w);
    *cosv = dot3(w, v->forward);
}

/* Trilinear read of an rgba [k][j][i] volume at continuous texel coordinates (texel centres
 * at integers), clamped to the edge. */
static void trilinear(const float *vol, uint32_t W, uint32_t H, uint32_t D, double x, double y,
                      double z, double out[3])
{
    double c[3] = { x, y, z };
    double lim[3] = { W - 1.0, H - 1.0, D - 1.0 };
    uint32_t i0[3], i1[3];
    double fr[3];
    for (int a = 0; a < 3; a++) {
        double t = c[a] < 0 ? 0 : c[a] > lim[a] ? lim[a] : c[a];
        double fl = floor(t);
        i0[a] = (uint32_t)fl;
        i1[a] = i0[a] + 1 > (uint32_t)lim[a] ? (uint32_t)lim[a] : i0[a] + 1;
        fr[a] = t - fl;
    }
    out[0] = out[1] = out[2] = 0;
    for (int corner = 0; corner < 8; corner++) {
        uint32_t ii = corner & 1 ? i1[0] : i0[0];
        uint32_t jj = corner & 2 ? i1[1] : i0[1];
        uint32_t kk = corner & 4 ? i1[2] : i0[2];
        double wt = (corner & 1 ? fr[0] : 1 - fr[0]) * (corner & 2 ? fr[1] : 1 - fr[1]) *
                    (corner & 4 ? fr[2] : 1 - fr[2]);
        const float *p = vol + 4 * (((size_t)kk * H + jj) * W + ii);
        for (int ch = 0; ch < 3; ch++)
            out[ch] += wt * p[ch];
    }
}

/* Temporal: the history at world point q seen by the previous camera; false outside its
 * grid. */
static bool history_at(const fx_cpu_ctx *x, const double q[3], double out[3])
{
    const fx_frame *f = x->f;
    const float *m = x->prev_vp;
    double c[4];
    for (int r = 0; r < 4; r++)
        c[r] = m[r] * q[0] + m[4 + r] * q[1] + m[8 + r] * q[2] + m[12 + r];
    if (!(c[3] > 0))
        return false;
    double u = (c[0] / c[3] + 1.0) * f->w / 2.0, v = (c[1] / c[3] + 1.0) * f->h / 2.0;
    double rel[3] = { q[0] - f->prev->eye[0], q[1] - f->prev->eye[1], q[2] - f->prev->eye[2] };
    double z = lg_depth_to_slice(&f->prev_map, dot3(rel, f->prev->forward));
    if (!(u >= 0 && u <= f->w && v >= 0 && v <= f->h && z >= 0 && z <= f->d))
        return false;
    trilinear(x->c->hist, f->w, f->h, f->d, u - 0.5, v - 0.5, z - 0.5, out);
    return true;
}

/* rec[] of a light that takes froxel.h 4.'s path (not the directional fast path) */
#define FX_REC_GEN (-2)

/* Columns per chunk of the fused pass: the per-column constants of a chunk live on the
 * stack (FX_CPU_GRAIN x 32 lights x 7 floats = 28 KiB at most). */
#define FX_CPU_GRAIN 32

/* Slices per block of the orthographic records' pass: the block's sums (3 x FX_KB x
 * FX_CPU_GRAIN floats, 6 KiB) stay in the L1 cache while every light adds to them, and a
 * block's footprint in a light's depth bounds is a few cache lines. */
#define FX_KB 16

/* Lanes of the vector loop: gcc's vector extensions, one SSE2 register on x86-64 (gcc 12
 * turns 8-lane compares into scalar code there) and one NEON register on aarch64; no
 * intrinsics. The chunk's columns are FX_CPU_GRAIN lanes. */
#define FX_VW 4
typedef float fx_vf __attribute__((vector_size(4 * FX_VW)));
typedef int32_t fx_vi __attribute__((vector_size(4 * FX_VW)));
typedef uint32_t fx_vu __attribute__((vector_size(4 * FX_VW)));
typedef double fx_v2d __attribute__((vector_size(16)));
/* lanes i0 .. i3 of the 8 of a and b (gcc and clang name it differently) */
#if defined(__clang__)
#define FX_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shufflevector(a, b, i0, i1, i2, i3)
#else
#define FX_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shuffle(a, b, (fx_vi){ i0, i1, i2, i3 })
#endif
_Static_assert(FX_CPU_GRAIN % FX_VW == 0, "a chunk is a whole number of vectors");
_Static_assert(FX_VW == 4, "fx_ortho_slices loads the bounds of 4 lanes as 2 x 2 pairs");
_Static_assert(FX_MM_BLOCK % FX_VW == 0, "fx_minmax reads a block row as whole vectors");

/* The orthographic records' shadowed lights (every directional light's) over slices
 * [k0, k0 + kn) of a chunk's FX_CPU_GRAIN columns: sacc[ch][k - k0][c] = unsh + the sum, in
 * light order, of sigma_s C_l p_HG over the lights that see the froxel's sample point.
 *
 * The texel and the depth are affine in view depth (u = ta_l + tb_l t: three multiply-adds,
 * no division); the test is the block bounds' (fx_minmax: the depth test is monotonic in
 * the stored depth, so the bounds decide most froxels without reading their texel) and,
 * in a block that holds the froxel's depth between its bounds, the texel's own: the same
 * decisions, the same bits, as one froxel at a time. A vector loop (README.md, "The
 * directional pass as a vector loop"): FX_VW columns at once with masks instead of
 * branches, so that the loads of the bounds are independent of each other and of any
 * branch, in three passes per light and slice block: (1) the decisions, and a list of the
 * froxels whose texel decides (the one branch per vector, rarely taken), their texels
 * prefetched; (2) those texels, independent loads; (3) the masked sums. The lanes past a
 * short chunk's end compute on zeros (tb, lp = 0: they add 0) and are never read. */
__attribute__((noinline)) static void
fx_ortho_slices(const fx_cpu_ctx *x, uint32_t k0, uint32_t kn, const float unsh[FX_CPU_GRAIN][3],
                const float tb[VOL_MAX_LIGHTS][3][FX_CPU_GRAIN],
                const float lp[VOL_MAX_LIGHTS][3][FX_CPU_GRAIN], float sacc[3][FX_KB][FX_CPU_GRAIN])
{
    const lg_shadowmap *sm = x->f->sm;
    const float res = (float)sm->resolution, bias = sm->bias_constant;
    const uint32_t aw = sm->atlas_width, rs = x->mm_shift + 1; /* a row of (min, max) */
    /* one light's decisions over the block, and the froxels its texels decide (at most all:
     * the list's last entry may be written past its count, never read) */
    int32_t shm[FX_KB * FX_CPU_GRAIN];
    uint16_t o_idx[FX_KB * FX_CPU_GRAIN + FX_VW];
    uint32_t o_off[FX_KB * FX_CPU_GRAIN + FX_VW];
    float o_z[FX_KB * FX_CPU_GRAIN + FX_VW];
    for (uint32_t kk = 0; kk < kn; kk++)
        for (uint32_t c = 0; c < FX_CPU_GRAIN; c++)
            for (int ch = 0; ch < 3; ch++)
                sacc[ch][kk][c] = unsh[c][ch];
    for (uint32_t l = 0; l < x->n_sh; l++) {
        if (!x->ortho[l])
            continue;
        const float au = x->ta[l][0], av = x->ta[l][1], az = x->ta[l][2];
        const float *atl = x->atlas + (size_t)x->tile[l][1] * aw + x->tile[l][0];
        const float *mml = x->mm[l];
        /* 1. the bounds' decision per froxel (shadowed: all ones), and the froxels whose
         * texel decides, listed: (sh index, texel offset, depth) */
        uint32_t n_open = 0;
        for (uint32_t kk = 0; kk < kn; kk++) {
            const float t = x->tj[k0 + kk];
            for (uint32_t c = 0; c < FX_CPU_GRAIN; c += FX_VW) {
                fx_vf bu, bv, bz;
                memcpy(&bu, tb[l][0] + c, sizeof bu);
                memcpy(&bv, tb[l][1] + c, sizeof bv);
                memcpy(&bz, tb[l][2] + c, sizeof bz);
                const fx_vf u = au + bu * t, vv = av + bv * t, z = az + bz * t;
                const fx_vi in = (u >= 0.0f) & (u < res) & (vv >= 0.0f) & (vv < res) & (z >= 0.0f);
                /* outside the tile (or NaN) the lane reads block 0, and is lit whatever it
                 * reads */
                const fx_vu iu = (fx_vu) __builtin_convertvector((fx_vf)((fx_vi)u & in), fx_vi);
                const fx_vu iv = (fx_vu) __builtin_convertvector((fx_vf)((fx_vi)vv & in), fx_vi);
                const fx_vu bi = ((iv / FX_MM_BLOCK) << rs) + 2 * (iu / FX_MM_BLOCK);
                /* each lane's (min, max) pair in one 8-byte load, then split */
                double p0, p1, p2, p3;
                memcpy(&p0, mml + bi[0], sizeof p0);
                memcpy(&p1, mml + bi[1], sizeof p1);
                memcpy(&p2, mml + bi[2], sizeof p2);
                memcpy(&p3, mml + bi[3], sizeof p3);
                const fx_vf q01 = (fx_vf)(fx_v2d){ p0, p1 }, q23 = (fx_vf)(fx_v2d){ p2, p3 };
                const fx_vf lo = FX_SHUFFLE(q01, q23, 0, 2, 4, 6);
                const fx_vf hi = FX_SHUFFLE(q01, q23, 1, 3, 5, 7);
                const fx_vi past_lo = in & (z > lo + bias), past_hi = z > hi + bias;
                const fx_vi sh = past_lo & past_hi, open = past_lo & ~past_hi;
                memcpy(&shm[kk * FX_CPU_GRAIN + c], &sh, sizeof sh);
                /* about 1 froxel in 16 needs its texel (the bench at 32 lights): a branch
                 * per vector, taken rarely, is cheaper than listing every lane */
                uint64_t any[2];
                memcpy(any, &open, sizeof any);
                if (any[0] | any[1]) {
                    for (int e = 0; e < FX_VW; e++) {
                        o_idx[n_open] = (uint16_t)(kk * FX_CPU_GRAIN + c + (uint32_t)e);
                        o_off[n_open] = iv[e] * aw + iu[e];
                        o_z[n_open] = z[e];
                        /* read in pass 2, a block later: started now */
                        __builtin_prefetch(atl + o_off[n_open]);
                        n_open += (uint32_t)open[e] & 1u;
                    }
                }
            }
        }
        /* 2. their texels: independent loads in a loop of their own (they miss the cache:
         * 32 lights' tiles are 8 MiB), so that many are in flight at once */
        for (uint32_t i = 0; i < n_open; i++)
            shm[o_idx[i]] = o_z[i] > atl[o_off[i]] + bias ? -1 : 0;
        /* 3. lit: + sigma_s C_l p_HG (the bits of + 1 x it); shadowed: + 0 */
        for (uint32_t kk = 0; kk < kn; kk++) {
            for (uint32_t c = 0; c < FX_CPU_GRAIN; c += FX_VW) {
                fx_vi sh;
                fx_vf a0, a1, a2, w0, w1, w2;
                memcpy(&sh, &shm[kk * FX_CPU_GRAIN + c], sizeof sh);
                memcpy(&a0, &sacc[0][kk][c], sizeof a0);
                memcpy(&a1, &sacc[1][kk][c], sizeof a1);
                memcpy(&a2, &sacc[2][kk][c], sizeof a2);
                memcpy(&w0, lp[l][0] + c, sizeof w0);
                memcpy(&w1, lp[l][1] + c, sizeof w1);
                memcpy(&w2, lp[l][2] + c, sizeof w2);
                a0 += (fx_vf)((fx_vi)w0 & ~sh);
                a1 += (fx_vf)((fx_vi)w1 & ~sh);
                a2 += (fx_vf)((fx_vi)w2 & ~sh);
                memcpy(&sacc[0][kk][c], &a0, sizeof a0);
                memcpy(&sacc[1][kk][c], &a1, sizeof a1);
                memcpy(&sacc[2][kk][c], &a2, sizeof a2);
            }
        }
    }
}

/* Light pass and accumulation of columns [begin, end) (at most FX_CPU_GRAIN, consecutive
 * in memory). Everything that depends only on the column is computed once per column:
 * 1 / cos, the sum over unshadowed lights sigma_s C_l p_HG (a column constant), per
 * shadowed light sigma_s C_l p_HG and the light-clip position as an affine function of
 * view depth, clip(t) = a_l + b_l t (a_l = VP_l e, b_l = VP_l w / cos). Everything that
 * depends only on the slice comes from the frame's tables (x->tj, x->tlen, x->tq). The
 * loop then walks k outside and the chunk's columns inside, so that S and the grid are
 * written in runs of consecutive texels and the inner loop has no per-column set-up. */
static void columns(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const fx_cpu_ctx *x = ctx;
    const fx_frame *f = x->f;
    const vol_setup *v = f->v;
    const size_t plane = (size_t)f->w * f->h;
    const uint32_t nc = (uint32_t)(end - begin), nsh = x->n_sh, nsp = nsh - x->n_ortho;
    float inv_cos[FX_CPU_GRAIN], unsh[FX_CPU_GRAIN][3];
    /* sigma_s C_l p_HG per shadowed light, [light][channel][column]: the vector loop's rows */
    float lp[VOL_MAX_LIGHTS][3][FX_CPU_GRAIN];
    float cb[VOL_MAX_LIGHTS][FX_CPU_GRAIN][4];
    /* orthographic records (every directional light's): the texel coordinates and the window
     * depth as affine functions of view depth, u = ta_l + tb_l t (x->ta: the light's part,
     * tb: the column's), [light][u, v, z][column] so that the loop over columns is a run */
    float tb[VOL_MAX_LIGHTS][3][FX_CPU_GRAIN];
    double wv[FX_CPU_GRAIN][3], acc[FX_CPU_GRAIN][3], tr[FX_CPU_GRAIN][3];
    /* froxel.h 4. (only touched when the frame has lights of the second path or a field) */
    fx_col_light cl[FX_CPU_GRAIN][VOL_MAX_LIGHTS];
    double icd[FX_CPU_GRAIN], path[FX_CPU_GRAIN];
    /* the orthographic records' sum over FX_KB slices (fx_ortho_slices) */
    float sacc[3][FX_KB][FX_CPU_GRAIN];
    for (uint32_t c = 0; c < nc; c++) {
        size_t col = begin + c;
        uint32_t i = (uint32_t)(col % f->w), j = (uint32_t)(col / f->w);
        double cosv;
        column_ray(f, i, j, wv[c], &cosv);
        inv_cos[c] = (float)(1.0 / cosv);
        double u[3] = { 0, 0, 0 };
        uint32_t s = 0;
        for (uint32_t l = 0; l < v->n_lights; l++) {
            const vol_light *L = &v->lights[l];
            if (x->rec[l] == FX_REC_GEN)
                continue; /* froxel.h 4.'s path */
            double cth = -(wv[c][0] * L->dir[0] + wv[c][1] * L->dir[1] + wv[c][2] * L->dir[2]);
            double p = lg_hg_phasef(v->g, (float)cth);
            if (x->rec[l] < 0) {
                for (int ch = 0; ch < 3; ch++)
                    u[ch] += v->sigma_s[ch] * L->l_c[ch] * p;
                continue;
            }
            for (int ch = 0; ch < 3; ch++)
                lp[s][ch][c] = (float)(v->sigma_s[ch] * L->l_c[ch] * p);
            const float *m = f->sm->lights[x->rec[l]].view_proj;
            for (int r = 0; r < 4; r++)
                cb[s][c][r] =
                    (float)((m[r] * wv[c][0] + m[4 + r] * wv[c][1] + m[8 + r] * wv[c][2]) / cosv);
            for (int r = 0; r < 3; r++)
                tb[s][r][c] =
                    (float)((m[r] * wv[c][0] + m[4 + r] * wv[c][1] + m[8 + r] * wv[c][2]) / cosv *
                            x->tscale[r]);
            s++;
        }
        for (int ch = 0; ch < 3; ch++) {
            unsh[c][ch] = (float)u[ch];
            acc[c][ch] = 0;
            tr[c][ch] = 1;
        }
        if (x->n_gen || x->het) {
            icd[c] = 1.0 / cosv;
            path[c] = 0.0;
            gen_column(x, wv[c], cl[c]);
        }
    }
    const float res = f->sm ? (float)f->sm->resolution : 0;
    const float bias = f->sm ? f->sm->bias_constant : 0;
    const uint32_t aw = f->sm ? f->sm->atlas_width : 0, ah = f->sm ? f->sm->atlas_height : 0;
    const bool thesis = f->accum == FX_ACC_THESIS;
    /* 1a. The shadowed lights of orthographic records (every directional light's) go into
     * sacc, FX_KB slices at a time (fx_ortho_slices); the loop below starts each froxel's S
     * from there. */
    if (x->n_ortho) {
        for (uint32_t c = nc; c < FX_CPU_GRAIN; c++) {
            /* the vector loop runs every lane of the chunk: lanes past its end add 0 */
            unsh[c][0] = unsh[c][1] = unsh[c][2] = 0.0f;
            for (uint32_t l = 0; l < nsh; l++)
                for (int r = 0; r < 3; r++)
                    tb[l][r][c] = 0.0f, lp[l][r][c] = 0.0f;
        }
    }
    for (uint32_t k = 0; k < f->d; k++) {
        const float t = x->tj[k];
        const double len = x->tlen[k];
        float *sk = x->c->s + 4 * (k * plane + begin);
        float *gk = x->grid + 4 * (k * plane + begin);
        if (x->n_ortho && k % FX_KB == 0)
            fx_ortho_slices(x, k, f->d - k < FX_KB ? f->d - k : FX_KB, unsh, tb, lp, sacc);
        for (uint32_t c = 0; c < nc; c++) {
            /* 1. light pass (the orthographic records' sum is in sacc already) */
            float s[3] = { unsh[c][0], unsh[c][1], unsh[c][2] };
            if (x->n_ortho)
                for (int ch = 0; ch < 3; ch++)
                    s[ch] = sacc[ch][k % FX_KB][c];
            /* perspective records (none from today's shadowmap for a directional light): the
             * divided form, in light order after the orthographic ones (nsp = 0: no loop over
             * the orthographic ones to skip them, which was a tenth of the pass at 32) */
            for (uint32_t l = 0; nsp && l < nsh; l++) {
                if (x->ortho[l])
                    continue;
                const float *a = x->ca[l], *b = cb[l][c];
                float cx = a[0] + b[0] * t, cy = a[1] + b[1] * t, cz = a[2] + b[2] * t;
                float iw = 1.0f / (a[3] + b[3] * t);
                float u = cx * iw * 0.5f + 0.5f, vv = cy * iw * 0.5f + 0.5f;
                float z = cz * iw * 0.5f + 0.5f;
                bool lit = true;
                if (u >= 0.0f && u < 1.0f && vv >= 0.0f && vv < 1.0f && z >= 0.0f) {
                    uint32_t tx = x->tile[l][0] + (uint32_t)(u * res);
                    uint32_t ty = x->tile[l][1] + (uint32_t)(vv * res);
                    if (tx < aw && ty < ah)
                        lit = !(z > x->atlas[(size_t)ty * aw + tx] + bias);
                }
                float m = lit ? 1.0f : 0.0f;
                s[0] += m * lp[l][0][c];
                s[1] += m * lp[l][1][c];
                s[2] += m * lp[l][2][c];
            }
            double rho = 1.0;
            if (x->n_gen || x->het) {
                double sg[3] = { s[0], s[1], s[2] };
                gen_terms(x, wv[c], icd[c], k, cl[c], sg);
                if (x->het)
                    rho = x->density[k * plane + begin + c];
                for (int ch = 0; ch < 3; ch++)
                    s[ch] = (float)(sg[ch] * rho);
            }
            if (x->blend) {
                double tq = x->tq[k], q[3], hv[3];
                for (int a = 0; a < 3; a++)
                    q[a] = v->eye[a] + wv[c][a] * tq * inv_cos[c];
                if (history_at(x, q, hv))
                    for (int ch = 0; ch < 3; ch++)
                        s[ch] = (float)(s[ch] + (hv[ch] - s[ch]) * f->history);
            }
            float *sp = sk + 4 * c;
            sp[0] = s[0], sp[1] = s[1], sp[2] = s[2], sp[3] = 1.0f;

            /* 2. accumulation */
            double delta = len * inv_cos[c];
            double *ac = acc[c], *trc = tr[c];
            if (x->het) {
                /* each slice's own extinction sigma_t rho_k, the optical path P_k */
                path[c] += rho * delta;
                x->c->path[k * plane + begin + c] = (float)path[c];
                if (thesis) {
                    for (int ch = 0; ch < 3; ch++)
                        ac[ch] += s[ch] * delta;
                } else {
                    for (int ch = 0; ch < 3; ch++) {
                        double tau = v->sigma_t[ch] * rho * delta;
                        ac[ch] += trc[ch] * s[ch] * delta * lg_medium_segment(tau);
                        trc[ch] *= exp(-tau);
                    }
                }
            } else if (thesis) {
                for (int ch = 0; ch < 3; ch++)
                    ac[ch] += s[ch] * delta;
            } else if (x->grey) {
                /* Delta seg(tau) = (1 - e^-tau) / sigma_t: no division per froxel (the
                 * series below 1e-4, where 1 - e^-tau would cancel) */
                double tau = v->sigma_t[0] * delta, e = exp(-tau);
                double wseg = tau < 1e-4 ? delta * (1.0 - 0.5 * tau + tau * tau / 6.0)
                                         : (1.0 - e) * x->inv_sigma_t;
                for (int ch = 0; ch < 3; ch++) {
                    ac[ch] += trc[ch] * s[ch] * wseg;
                    trc[ch] *= e;
                }
            } else {
                for (int ch = 0; ch < 3; ch++) {
                    double tau = v->sigma_t[ch] * delta;
                    ac[ch] += trc[ch] * s[ch] * delta * lg_medium_segment(tau);
                    trc[ch] *= exp(-tau);
                }
            }
            float *g = gk + 4 * c;
            g[0] = (float)ac[0], g[1] = (float)ac[1], g[2] = (float)ac[2];
            /* the mean of Tr's channels: Tr itself when sigma_t is grey (the division by 3
             * was a fifth of the pass's time at one light: its latency is on every froxel) */
            g[3] = x->grey ? (float)trc[0] : (float)((trc[0] + trc[1] + trc[2]) * (1.0 / 3.0));
        }
    }
}

/* The depth bounds of block rows [begin, end) (index = light x block rows + row) of the
 * orthographic records' tiles: min and max of the stored depths per FX_MM_BLOCK^2 texels. */
static void fx_minmax(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const fx_cpu_ctx *x = ctx;
    const lg_shadowmap *sm = x->f->sm;
    const uint32_t res = sm->resolution, nb = x->mm_n, aw = sm->atlas_width;
    for (size_t idx = begin; idx < end; idx++) {
        uint32_t l = (uint32_t)(idx / nb), by = (uint32_t)(idx % nb);
        if (!x->ortho[l])
            continue;
        float *out = (float *)x->mm[l] + ((size_t)by << (x->mm_shift + 1));
        const float *atl = x->atlas + (size_t)x->tile[l][1] * aw + x->tile[l][0];
        for (uint32_t bx = 0; bx < nb; bx++)
            out[2 * bx] = INFINITY, out[2 * bx + 1] = -INFINITY;
        uint32_t y1 = (by + 1) * FX_MM_BLOCK < res ? (by + 1) * FX_MM_BLOCK : res;
        /* whole blocks FX_VW texels at a time (made per frame and light: at 32 lights the
         * scalar loop was a tenth of the light pass), the partial block of a res that is
         * not a multiple of FX_MM_BLOCK texel by texel; the same bounds either way */
        const uint32_t whole = res / FX_MM_BLOCK;
        const fx_vf pinf = { INFINITY, INFINITY, INFINITY, INFINITY }, ninf = -pinf;
        for (uint32_t bx = 0; bx < whole; bx++) {
            fx_vf lo = pinf, hi = ninf;
            for (uint32_t y = by * FX_MM_BLOCK; y < y1; y++) {
                const float *row = atl + (size_t)y * aw + bx * FX_MM_BLOCK;
                for (uint32_t q = 0; q < FX_MM_BLOCK; q += FX_VW) {
                    fx_vf d;
                    memcpy(&d, row + q, sizeof d);
                    /* NaN depths: neither bound decides, the texel's own test does */
                    const fx_vi nan = d != d;
                    const fx_vf dl = (fx_vf)(((fx_vi)d & ~nan) | ((fx_vi)ninf & nan));
                    const fx_vf dh = (fx_vf)(((fx_vi)d & ~nan) | ((fx_vi)pinf & nan));
                    const fx_vi lt = dl<lo, gt = dh> hi;
                    lo = (fx_vf)(((fx_vi)dl & lt) | ((fx_vi)lo & ~lt));
                    hi = (fx_vf)(((fx_vi)dh & gt) | ((fx_vi)hi & ~gt));
                }
            }
            float *o = out + 2 * bx;
            for (int e = 0; e < FX_VW; e++) {
                o[0] = lo[e] < o[0] ? lo[e] : o[0];
                o[1] = hi[e] > o[1] ? hi[e] : o[1];
            }
        }
        for (uint32_t y = by * FX_MM_BLOCK; y < y1; y++) {
            const float *row = atl + (size_t)y * aw;
            for (uint32_t tx = whole * FX_MM_BLOCK; tx < res; tx++) {
                float d = row[tx];
                float *o = out + 2 * (tx / FX_MM_BLOCK);
                if (!(d >= o[0]))
                    o[0] = d != d ? -INFINITY : d;
                if (!(d <= o[1]))
                    o[1] = d != d ? INFINITY : d;
            }
        }
    }
}

/* Bilinear read of slice k of an rgba [k][j][i] volume at (u, v) (clamped). */
static void bilinear(const float *vol, uint32_t W, uint32_t H, uint32_t k, double u, double v,
                     double out[3])
{
    u = u < 0 ? 0 : u > W - 1.0 ? W - 1.0 : u;
    v = v < 0 ? 0 : v > H - 1.0 ? H - 1.0 : v;
    uint32_t i0 = (uint32_t)u, j0 = (uint32_t)v;
    uint32_t i1 = i0 + 1 < W ? i0 + 1 : i0, j1 = j0 + 1 < H ? j0 + 1 : j0;
    double fu = u - i0, fv = v - j0;
    const float *s = vol + 4 * (size_t)k * W * H;
    for (int ch = 0; ch < 3; ch++) {
        double a = s[4 * ((size_t)j0 * W + i0) + ch] * (1 - fu) +
                   s[4 * ((size_t)j0 * W + i1) + ch] * fu;
        double b = s[4 * ((size_t)j1 * W + i0) + ch] * (1 - fu) +
                   s[4 * ((size_t)j1 * W + i1) + ch] * fu;
        out[ch] = a * (1 - fv) + b * fv;
    }
}

/* Bilinear read of slice k of a one-channel [k][j][i] volume at (u, v) (clamped). */
static double bilinear1(const float *vol, uint32_t W, uint32_t H, uint32_t k, double u, double v)
{
    u = u < 0 ? 0 : u > W - 1.0 ? W - 1.0 : u;
    v = v < 0 ? 0 : v > H - 1.0 ? H - 1.0 : v;
    uint32_t i0 = (uint32_t)u, j0 = (uint32_t)v;
    uint32_t i1 = i0 + 1 < W ? i0 + 1 : i0, j1 = j0 + 1 < H ? j0 + 1 : j0;
    double fu = u - i0, fv = v - j0;
    const float *s = vol + (size_t)k * W * H;
    double a = s[(size_t)j0 * W + i0] * (1 - fu) + s[(size_t)j0 * W + i1] * fu;
    double b = s[(size_t)j1 * W + i0] * (1 - fu) + s[(size_t)j1 * W + i1] * fu;
    return a * (1 - fv) + b * fv;
}

/* 3. Lookup of image rows [begin, end). vol_fog_length's rule with the pixel's ray computed
 * once (vol_fog_length makes its own), T(k) from the frame's table instead of a pow per
 * pixel, and for a grey sigma_t one exp per factor instead of one per channel: the same
 * values as the per-channel form, a third of the transcendental calls. */
static void rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const fx_cpu_ctx *x = ctx;
    const fx_frame *f = x->f;
    const vol_setup *v = f->v;
    const bool thesis = f->accum == FX_ACC_THESIS;
    for (size_t y = begin; y < end; y++) {
        for (uint32_t px = 0; px < v->width; px++) {
            size_t p = y * v->width + px;
            double xc = px + 0.5, yc = y + 0.5;
            float depth = x->base_depth[p];
            double w[3];
            vol_ray(v, xc, yc, w);
            double cosv = dot3(w, v->forward);
            /* vol_fog_length: to the surface or to z_limit, whichever is nearer */
            double limit = cosv > 0.0 ? (double)v->z_limit / cosv : INFINITY;
            double surf = vol_surface_distance(v, xc, yc, depth);
            double d = surf < limit ? surf : limit;
            double t_end = d * cosv;
            double zc = lg_depth_to_slice(&f->map, t_end);
            zc = zc < 0 ? 0 : zc > f->d ? f->d : zc;
            uint32_t k = (uint32_t)floor(zc);
            if (k > f->d - 1)
                k = f->d - 1;
            double t_s = k == 0 ? 0.0 : x->tk[k];
            double delta = t_end > t_s ? (t_end - t_s) / cosv : 0.0;
            double u = xc * f->w / v->width - 0.5, vv = yc * f->h / v->height - 0.5;
            double a[3] = { 0, 0, 0 }, s[3];
            if (k > 0)
                bilinear(x->grid, f->w, f->h, k - 1, u, vv, a);
            bilinear(x->c->s, f->w, f->h, k, u, vv, s);
            const float *b = x->base + 4 * p;
            float *o = x->out + 4 * p, *in = x->ins + 4 * p;
            double tr_s = 1.0, seg = 1.0, tv = 1.0;
            if (x->het) {
                /* froxel.h 4.: the optical path to slice k's start and slice k's density */
                double pk = k > 0 ? bilinear1(x->c->path, f->w, f->h, k - 1, u, vv) : 0.0;
                double rho = bilinear1(x->density, f->w, f->h, k, u, vv);
                for (int ch = 0; ch < 3; ch++) {
                    double st = v->sigma_t[ch];
                    double lv = thesis ? a[ch] + s[ch] * delta
                                       : a[ch] + exp(-st * pk) * s[ch] * delta *
                                                     lg_medium_segment(st * rho * delta);
                    tv = thesis ? 1.0 : exp(-st * (pk + rho * delta));
                    in[ch] = (float)lv;
                    o[ch] = (float)(b[ch] * tv + lv);
                }
                in[3] = 1.0f;
                o[3] = b[3];
                x->out_depth[p] = depth;
                continue;
            }
            if (!thesis && x->grey) {
                double st = v->sigma_t[0];
                tr_s = exp(-st * t_s / cosv);
                seg = lg_medium_segment(st * delta);
                tv = exp(-st * d);
            }
            for (int ch = 0; ch < 3; ch++) {
                double lv;
                if (thesis) {
                    lv = a[ch] + s[ch] * delta;
                } else if (x->grey) {
                    lv = a[ch] + tr_s * s[ch] * delta * seg;
                } else {
                    double st = v->sigma_t[ch];
                    lv = a[ch] +
                         exp(-st * t_s / cosv) * s[ch] * delta * lg_medium_segment(st * delta);
                    tv = exp(-st * d);
                }
                in[ch] = (float)lv;
                o[ch] = (float)(b[ch] * tv + lv);
            }
            in[3] = 1.0f;
            o[3] = b[3];
            x->out_depth[p] = depth;
        }
    }
}

int fx_cpu_execute(lg_node *n, void **state, const fx_frame *f)
{
    fx_cpu *c = *state;
    size_t vox = (size_t)f->w * f->h * f->d;
    if (c && (c->w != f->w || c->h != f->h || c->d != f->d)) {
        fx_cpu_destroy(n, c);
        *state = c = NULL;
    }
    if (!c) {
        c = calloc(1, sizeof *c);
        if (c) {
            c->s = malloc(vox * 16);
            c->hist = malloc(vox * 16);
            c->tj = malloc(f->d * sizeof *c->tj);
        }
        if (!c || !c->s || !c->hist || !c->tj) {
            fx_cpu_destroy(n, c);
            return lg_error_code(n, LG_ERR_NOMEM,
                                 "out of memory (two %ux%ux%u rgba32f "
                                 "volumes, S and its history)",
                                 f->w, f->h, f->d);
        }
        c->w = f->w;
        c->h = f->h;
        c->d = f->d;
        c->counted = 2 * (uint64_t)vox * 16;
        lg_account_alloc(n, c->counted);
        *state = c;
    }
    fx_cpu_ctx x = { .f = f, .c = c };
    /* the blend needs a previous frame that this backend has computed */
    x.blend = f->history > 0 && f->prev && c->hist_valid;
    if (x.blend)
        memcpy(x.prev_vp, f->prev->view.view_proj, sizeof x.prev_vp);

    lg_cpu_view bv, ov, iv, gv, av;
    int rc = lg_map_cpu(n, lg_input(n, VOL_IN_BASE), LG_READ, &bv);
    if (!rc && !bv.depth)
        rc = lg_error(n, "input 'base' has no depth plane");
    if (!rc && f->sm) {
        rc = lg_map_cpu(n, f->sm->atlas, LG_READ, &av);
        if (!rc)
            x.atlas = av.depth ? av.depth : av.pixels;
    }
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, VOL_OUT_OUT), LG_WRITE, &ov);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, VOL_OUT_INSCATTER), LG_WRITE, &iv);
    if (!rc)
        rc = lg_map_cpu(n, lg_part(n, lg_output(n, FX_OUT_GRID), "grid"), LG_WRITE, &gv);
    if (rc)
        return rc;
    x.base = bv.pixels;
    x.base_depth = bv.depth;
    x.out = ov.pixels;
    x.out_depth = ov.depth;
    x.ins = iv.pixels;
    x.grid = gv.pixels;
    if (!x.base || !x.out || !x.out_depth || !x.ins || !x.grid)
        return lg_error(n, "a mapping of base, out, inscatter or grid gave no pixels");

    /* the slice tables (froxel.c's, T(k + jitter) in float for the columns) */
    for (uint32_t k = 0; k < f->d; k++)
        c->tj[k] = (float)f->slices->tj[k];
    x.tj = c->tj;
    x.tlen = f->slices->tlen;
    x.tq = f->slices->tq;
    x.tk = f->slices->tk;
    /* the lights: shadowed ones get a_l and their tile */
    const vol_setup *v = f->v;
    x.grey = v->sigma_t[0] == v->sigma_t[1] && v->sigma_t[1] == v->sigma_t[2];
    x.inv_sigma_t = x.grey && v->sigma_t[0] > 0 ? 1.0 / v->sigma_t[0] : 0.0;
    if (f->sm) {
        x.tscale[0] = x.tscale[1] = 0.5f * (float)f->sm->resolution;
        x.tscale[2] = 0.5f;
    }
    /* froxel.h 4.: a density field or a point or spot light turns on the second path */
    x.het = f->density != NULL;
    x.density = f->density;
    if (x.het && !c->path) {
        c->path = malloc(vox * sizeof(float));
        if (!c->path)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (a %ux%ux%u optical-path volume)",
                                 f->w, f->h, f->d);
        c->counted += (uint64_t)vox * sizeof(float);
        lg_account_alloc(n, (uint64_t)vox * sizeof(float));
    }
    x.nodes = f->point_nodes < 0 ? 0 : f->point_nodes > 8 ? 8 : f->point_nodes;
    for (int i = 0; i < x.nodes; i++) {
        x.gx[i] = fx_gl_x[x.nodes - 1][i];
        x.gw[i] = fx_gl_w[x.nodes - 1][i];
    }
    {
        double g = v->g;
        g = !(g == g) ? 0.0 : g < -LG_HG_G_MAX ? -LG_HG_G_MAX : g > LG_HG_G_MAX ? LG_HG_G_MAX : g;
        x.hg_a = g >= 0.0 ? (1.0 - g) * (1.0 - g) : (1.0 + g) * (1.0 + g);
        x.hg_k = (1.0 - g) * (1.0 + g) / (4.0 * LG_PI);
    }
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_light *L = &v->lights[l];
        int32_t r = L->shadow;
        bool sh = x.atlas && f->sm && r >= 0 && (uint32_t)r < f->sm->n_lights;
        /* the second path also takes a shadowed directional light when the map filters
         * (pcf_radius > 0: vol_shadow_cpu's taps; the fast path reads one texel) */
        if (x.het || L->type != LG_LIGHT_DIRECTIONAL || (sh && f->sm->pcf_radius > 0)) {
            fx_cpu_light *g = &x.gen[x.n_gen++];
            g->L = L;
            g->dir = L->type == LG_LIGHT_DIRECTIONAL;
            g->spot = L->type == LG_LIGHT_SPOT;
            for (int a = 0; a < 3; a++) {
                g->q[a] = L->pos[a];
                g->axis[a] = L->dir[a];
                g->lc[a] = (double)v->sigma_s[a] * L->l_c[a];
            }
            g->cos_in = L->cos_inner;
            g->cos_out = L->cos_outer;
            g->range = L->range;
            g->rec = sh ? r : -1;
            g->tau = x.het && f->tau ? &f->tau[l] : NULL;
            x.rec[l] = FX_REC_GEN;
            continue;
        }
        x.rec[l] = sh ? r : -1;
        if (!sh)
            continue;
        const lg_shadow_light *R = &f->sm->lights[r];
        const float *m = R->view_proj;
        for (int row = 0; row < 4; row++)
            x.ca[x.n_sh][row] = (float)(m[row] * v->eye[0] + m[4 + row] * v->eye[1] +
                                        m[8 + row] * v->eye[2] + m[12 + row]);
        x.tile[x.n_sh][0] = R->tile_x;
        x.tile[x.n_sh][1] = R->tile_y;
        uint32_t res = f->sm->resolution;
        x.ortho[x.n_sh] = m[3] == 0.0f && m[7] == 0.0f && m[11] == 0.0f && m[15] == 1.0f &&
                          (uint64_t)R->tile_x + res <= f->sm->atlas_width &&
                          (uint64_t)R->tile_y + res <= f->sm->atlas_height &&
                          (uint64_t)res * f->sm->atlas_width <= UINT32_MAX; /* texel offsets */
        x.n_ortho += x.ortho[x.n_sh];
        for (int row = 0; row < 3; row++) {
            double a = (double)m[row] * v->eye[0] + (double)m[4 + row] * v->eye[1] +
                       (double)m[8 + row] * v->eye[2] + m[12 + row];
            x.ta[x.n_sh][row] = (float)(row < 2 ? (a * 0.5 + 0.5) * res : a * 0.5 + 0.5);
        }
        x.n_sh++;
    }
    if (x.n_ortho) {
        /* each orthographic record's depth bounds per block (fx_minmax) */
        uint32_t res = f->sm->resolution, nb = (res + FX_MM_BLOCK - 1) / FX_MM_BLOCK;
        while ((1u << x.mm_shift) < nb)
            x.mm_shift++;
        size_t need = ((size_t)x.n_sh * nb * 2) << x.mm_shift;
        if (need > c->mm_cap) {
            float *mm = realloc(c->mm, need * sizeof(float));
            if (!mm)
                return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu shadow depth bounds)",
                                     need);
            lg_account_alloc(n, (need - c->mm_cap) * sizeof(float));
            c->counted += (need - c->mm_cap) * sizeof(float);
            c->mm = mm;
            c->mm_cap = need;
        }
        x.mm_n = nb;
        for (uint32_t l = 0; l < x.n_sh; l++)
            x.mm[l] = c->mm + (((size_t)l * nb * 2) << x.mm_shift);
        rc = lg_parallel_for(n, (size_t)x.n_sh * nb, 1, fx_minmax, &x);
        if (rc)
            return rc;
    }
    rc = lg_parallel_for(n, (size_t)f->w * f->h, FX_CPU_GRAIN, columns, &x);
    if (!rc)
        rc = lg_parallel_for(n, f->v->height, 4, rows, &x);
    if (rc)
        return rc;
    /* this frame's blended S is the next frame's history */
    float *t = c->s;
    c->s = c->hist;
    c->hist = t;
    c->hist_valid = true;
    return 0;
}

void fx_cpu_destroy(lg_node *n, void *state)
{
    fx_cpu *c = state;
    if (!c)
        return;
    if (c->counted)
        lg_account_free(n, c->counted);
    free(c->s);
    free(c->hist);
    free(c->tj);
    free(c->path);
    free(c->mm);
    free(c);
}
