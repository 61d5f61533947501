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
    float *s;        /* S of this frame, rgba, [k][j][i] */
    float *hist;     /* the previous frame's blended S (valid when hist_valid) */
    bool hist_valid;
} fx_cpu;

typedef struct fx_cpu_ctx {
    const fx_frame *f;
    fx_cpu *c;
    const float *atlas;        /* shadow atlas depth plane, or NULL */
    float *grid;               /* rgba32f W x H x D */
    const float *base, *base_depth;
    float *out, *out_depth, *ins;
    float prev_vp[16];         /* the previous camera's view_proj (temporal) */
    bool blend;
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
static void trilinear(const float *vol, uint32_t W, uint32_t H, uint32_t D, double x,
                      double y, double z, double out[3])
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

/* Light pass and accumulation of columns [begin, end). */
static void columns(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const fx_cpu_ctx *x = ctx;
    const fx_frame *f = x->f;
    const vol_setup *v = f->v;
    size_t plane = (size_t)f->w * f->h;
    for (size_t col = begin; col < end; col++) {
        uint32_t i = (uint32_t)(col % f->w), j = (uint32_t)(col / f->w);
        double w[3], cosv;
        column_ray(f, i, j, w, &cosv);
        /* the per-light factor C_l p_HG of this column, and the shadowed lights */
        double lp[VOL_MAX_LIGHTS][3];
        for (uint32_t l = 0; l < v->n_lights; l++) {
            const vol_light *L = &v->lights[l];
            double c = -(w[0] * L->dir[0] + w[1] * L->dir[1] + w[2] * L->dir[2]);
            double p = lg_hg_phasef(v->g, (float)c);
            for (int ch = 0; ch < 3; ch++)
                lp[l][ch] = L->l_c[ch] * p;
        }
        double acc[3] = { 0, 0, 0 }, tr[3] = { 1, 1, 1 };
        double t_prev = 0; /* t_0 = 0: slice 0 starts at the eye */
        for (uint32_t k = 0; k < f->d; k++) {
            /* 1. light pass */
            double t = lg_slice_to_depth(&f->map, k + (double)f->jitter);
            double pt[3];
            for (int a = 0; a < 3; a++)
                pt[a] = v->eye[a] + w[a] * t / cosv;
            double sum[3] = { 0, 0, 0 };
            for (uint32_t l = 0; l < v->n_lights; l++) {
                float vis = x->atlas ? vol_shadow_cpu(f->sm, x->atlas, v->lights[l].shadow, pt)
                                     : 1.0f;
                if (vis > 0)
                    for (int ch = 0; ch < 3; ch++)
                        sum[ch] += lp[l][ch];
            }
            double s[3];
            for (int ch = 0; ch < 3; ch++)
                s[ch] = (float)(v->sigma_s[ch] * sum[ch]);
            if (x->blend) {
                double tq = lg_slice_to_depth(&f->map, k + 0.5), q[3], hv[3];
                for (int a = 0; a < 3; a++)
                    q[a] = v->eye[a] + w[a] * tq / cosv;
                if (history_at(x, q, hv))
                    for (int ch = 0; ch < 3; ch++)
                        s[ch] = (float)(s[ch] + (hv[ch] - s[ch]) * f->history);
            }
            size_t idx = 4 * (k * plane + col);
            float *sp = x->c->s + idx;
            for (int ch = 0; ch < 3; ch++)
                sp[ch] = (float)s[ch];
            sp[3] = 1.0f;

            /* 2. accumulation */
            double t_next = lg_slice_to_depth(&f->map, k + 1.0);
            double delta = (t_next - t_prev) / cosv;
            t_prev = t_next;
            for (int ch = 0; ch < 3; ch++) {
                double sv = sp[ch];
                if (f->accum == FX_ACC_THESIS) {
                    acc[ch] += sv * delta;
                } else {
                    double tau = v->sigma_t[ch] * delta;
                    acc[ch] += tr[ch] * sv * delta * lg_medium_segment(tau);
                    tr[ch] *= exp(-tau);
                }
            }
            float *g = x->grid + idx;
            for (int ch = 0; ch < 3; ch++)
                g[ch] = (float)acc[ch];
            g[3] = (float)((tr[0] + tr[1] + tr[2]) / 3.0);
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

/* 3. Lookup of image rows [begin, end). */
static void rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const fx_cpu_ctx *x = ctx;
    const fx_frame *f = x->f;
    const vol_setup *v = f->v;
    for (size_t y = begin; y < end; y++) {
        for (uint32_t px = 0; px < v->width; px++) {
            size_t p = y * v->width + px;
            double xc = px + 0.5, yc = y + 0.5;
            float depth = x->base_depth[p];
            double d = vol_fog_length(v, xc, yc, depth);
            double w[3];
            vol_ray(v, xc, yc, w);
            double cosv = dot3(w, v->forward);
            double t_end = d * cosv;
            double zc = lg_depth_to_slice(&f->map, t_end);
            zc = zc < 0 ? 0 : zc > f->d ? f->d : zc;
            uint32_t k = (uint32_t)floor(zc);
            if (k > f->d - 1)
                k = f->d - 1;
            double t_s = k == 0 ? 0.0 : lg_slice_to_depth(&f->map, k);
            double delta = t_end > t_s ? (t_end - t_s) / cosv : 0.0;
            double u = xc * f->w / v->width - 0.5, vv = yc * f->h / v->height - 0.5;
            double a[3] = { 0, 0, 0 }, s[3];
            if (k > 0)
                bilinear(x->grid, f->w, f->h, k - 1, u, vv, a);
            bilinear(x->c->s, f->w, f->h, k, u, vv, s);
            const float *b = x->base + 4 * p;
            float *o = x->out + 4 * p, *in = x->ins + 4 * p;
            for (int ch = 0; ch < 3; ch++) {
                double lv, tv = 1.0;
                if (f->accum == FX_ACC_THESIS) {
                    lv = a[ch] + s[ch] * delta;
                } else {
                    double st = v->sigma_t[ch];
                    lv = a[ch] + exp(-st * t_s / cosv) * s[ch] * delta *
                                     lg_medium_segment(st * delta);
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
        }
        if (!c || !c->s || !c->hist) {
            fx_cpu_destroy(n, c);
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (two %ux%ux%u rgba32f "
                                                  "volumes, S and its history)",
                                 f->w, f->h, f->d);
        }
        c->w = f->w;
        c->h = f->h;
        c->d = f->d;
        lg_account_alloc(n, 2 * (uint64_t)vox * 16);
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

    /* columns: a chunk of 64 columns is D x 64 light evaluations */
    rc = lg_parallel_for(n, (size_t)f->w * f->h, 64, columns, &x);
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
    (void)n;
    fx_cpu *c = state;
    if (!c)
        return;
    free(c->s);
    free(c->hist);
    free(c);
}
