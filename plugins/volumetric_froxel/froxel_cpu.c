/*
 * The cpu backend of volumetric_froxel: froxel.h's three passes over the host's thread
 * pool. It is the reference of the spec: the light pass and the accumulation run fused,
 * one column per index (the accumulation needs the whole column of S, which the same
 * index has just computed), then the lookup one image row per index. Every index writes
 * only its own column or row, so the result is the same bits for any thread count.
 *
 * Arithmetic in double where it costs nothing (rays, depths, the per-light sum); stored
 * values are float, as the GPU backends store them.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"

#include "froxel.h"

typedef struct fx_cpu {
    uint32_t w, h, d;
    float *s;    /* S of this frame, rgba, [k][j][i] */
    float *hist; /* the previous frame's blended S (valid when hist_valid) */
    bool hist_valid;
    float *tj;        /* the frame's T(k + jitter) in float (columns' inner loop) */
    uint64_t counted; /* bytes counted with lg_account_alloc (S and its history) */
} fx_cpu;

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
} fx_cpu_ctx;

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
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

/* Columns per chunk of the fused pass: the per-column constants of a chunk live on the
 * stack (FX_CPU_GRAIN x 32 lights x 7 floats = 28 KiB at most). */
#define FX_CPU_GRAIN 32

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
    const uint32_t nc = (uint32_t)(end - begin), nsh = x->n_sh;
    float inv_cos[FX_CPU_GRAIN], unsh[FX_CPU_GRAIN][3];
    float lp[VOL_MAX_LIGHTS][FX_CPU_GRAIN][3];
    float cb[VOL_MAX_LIGHTS][FX_CPU_GRAIN][4];
    double wv[FX_CPU_GRAIN][3], acc[FX_CPU_GRAIN][3], tr[FX_CPU_GRAIN][3];
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
            double cth = -(wv[c][0] * L->dir[0] + wv[c][1] * L->dir[1] + wv[c][2] * L->dir[2]);
            double p = lg_hg_phasef(v->g, (float)cth);
            if (x->rec[l] < 0) {
                for (int ch = 0; ch < 3; ch++)
                    u[ch] += v->sigma_s[ch] * L->l_c[ch] * p;
                continue;
            }
            for (int ch = 0; ch < 3; ch++)
                lp[s][c][ch] = (float)(v->sigma_s[ch] * L->l_c[ch] * p);
            const float *m = f->sm->lights[x->rec[l]].view_proj;
            for (int r = 0; r < 4; r++)
                cb[s][c][r] =
                    (float)((m[r] * wv[c][0] + m[4 + r] * wv[c][1] + m[8 + r] * wv[c][2]) / cosv);
            s++;
        }
        for (int ch = 0; ch < 3; ch++) {
            unsh[c][ch] = (float)u[ch];
            acc[c][ch] = 0;
            tr[c][ch] = 1;
        }
    }
    const float res = f->sm ? (float)f->sm->resolution : 0;
    const float bias = f->sm ? f->sm->bias_constant : 0;
    const uint32_t aw = f->sm ? f->sm->atlas_width : 0, ah = f->sm ? f->sm->atlas_height : 0;
    const bool thesis = f->accum == FX_ACC_THESIS;
    for (uint32_t k = 0; k < f->d; k++) {
        const float t = x->tj[k];
        const double len = x->tlen[k];
        float *sk = x->c->s + 4 * (k * plane + begin);
        float *gk = x->grid + 4 * (k * plane + begin);
        for (uint32_t c = 0; c < nc; c++) {
            /* 1. light pass */
            float s[3] = { unsh[c][0], unsh[c][1], unsh[c][2] };
            for (uint32_t l = 0; l < nsh; l++) {
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
                s[0] += m * lp[l][c][0];
                s[1] += m * lp[l][c][1];
                s[2] += m * lp[l][c][2];
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
            if (thesis) {
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
            g[3] = (float)((trc[0] + trc[1] + trc[2]) / 3.0);
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
    for (uint32_t l = 0; l < v->n_lights; l++) {
        int32_t r = v->lights[l].shadow;
        bool sh = x.atlas && f->sm && r >= 0 && (uint32_t)r < f->sm->n_lights;
        x.rec[l] = sh ? r : -1;
        if (!sh)
            continue;
        const lg_shadow_light *L = &f->sm->lights[r];
        const float *m = L->view_proj;
        for (int row = 0; row < 4; row++)
            x.ca[x.n_sh][row] = (float)(m[row] * v->eye[0] + m[4 + row] * v->eye[1] +
                                        m[8 + row] * v->eye[2] + m[12 + row]);
        x.tile[x.n_sh][0] = L->tile_x;
        x.tile[x.n_sh][1] = L->tile_y;
        x.n_sh++;
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
    free(c);
}
