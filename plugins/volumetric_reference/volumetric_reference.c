/*
 * The volumetric_reference plugin (README.md beside this file; TECHNIQUES.md §6, seed 2
 * chapter 3): single scattering in a homogeneous medium lit by directional lights, ray
 * marched on the CPU with exact visibility (Embree occlusion rays). The oracle the four
 * volumetric methods are measured against.
 *
 *   scene, base -> out (base e^(-sigma_t d) + L_v, base's depth), inscatter (L_v)
 *
 * Estimator, per pixel: `spp` sub-pixel rays (stratified: jittered cells of a square grid
 * when spp is a square, else a jittered Latin hypercube), each from the eye along w to its
 * own fog length d = min(first surface (an Embree ray cast), z_limit / dot(w, forward)),
 * cut into `steps` equal segments [a, b]; in each one point x at a jittered place and, per
 * light l,
 *
 *   L_v += L_c sigma_s p_HG(g, dot(w, -L)) V_l(x) e^(-sigma_t a) (b - a) seg(sigma_t (b - a))
 *
 * (lightgraph/medium.h: the transmittance inside the segment is integrated exactly, so
 * only the visibility V_l is sampled). The pixel's L_v is the mean over its rays. Every
 * random number is a hash of (seed, pixel, ray, segment): the same bits for any thread
 * count and any order.
 *
 * Since issue 25 (README.md, "Point and spot lights", "Heterogeneous media", "Multiple
 * scattering"; the estimators in vr_estimators.h): point and spot lights by equiangular
 * sampling along the ray with Embree visibility of the finite segment to the light; a
 * density field by ratio or delta tracking of every transmittance (view ray and towards
 * each light: the medium shadows itself); orders 2 .. `order` by path tracing with
 * next-event estimation. Directional lights in a homogeneous medium at order 1 keep the
 * estimator above, bit for bit.
 *
 * Since issue 26 (README.md, "Over MPI ranks"): the pixels are lg_shard items (spans of at
 * most VR_SPAN pixels of a row), spread over the host's threads and, under mpirun, over
 * every rank; each rank builds the Embree scene itself. The same bits for any count of
 * either, and the same bits as before.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <embree3/rtcore.h>

#include "lg_embree.h"

#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/scene.h"

#include "vol_common.h"
#include "vr_estimators.h"

#define VR_MAX_STEPS 65536
#define VR_MAX_SPP 4096
#define VR_MAX_ORDER 64
#define VR_MAX_PATHS 4096
/* the most pixels of one lg_shard item (a span of a row; vr_execute says why) */
#define VR_SPAN 64
/* Seconds one thread takes per occlusion ray, the march's step around it included.
 * Measured here (2-core VM shared with compiles, LIGHTGRAPH_THREADS=1):
 * examples/volumetric_reference.lgraph at 160x90, spp 4, steps 256, one light: 1.47e7
 * rays in 4.2 s, 2.9e-7 s each (the bunny box: a small BVH; a large scene costs more per
 * ray). What `render` warns with (above a minute) and --explain shows. */
#define VR_SECONDS_PER_RAY 2.9e-7

typedef struct vr_state {
    uint32_t steps, spp;
    uint32_t order, paths; /* scattering order (1 = single), paths per ray for orders >= 2 */
    bool ratio;            /* transmittance = ratio (else delta) in a heterogeneous medium */
    uint64_t seed;
    bool centre; /* subpixel = centre: every ray through the pixel centre */
    float z_limit;
    bool per_frame;
    uint32_t width, height;
    bool reported_nonfinite; /* base's NaN/Inf pixels said (lg_check_input_finite) */
} vr_state;

/* ---- the march ------------------------------------------------------------------------------- */

typedef struct vr_run {
    const vr_state *st;
    const vol_setup *v;
    const lg_embree *e;
    const float *base, *depth; /* rgba32f and window depth, row_pixels apart */
    size_t base_row;
    uint32_t side;      /* spp = side^2, or 0: Latin hypercube */
    double tnear_light; /* occlusion rays start this far from the medium point */
    /* the lg_shard items: spans of `span` pixels, spans_per_row of them per row */
    uint32_t span, spans_per_row;
    uint64_t *computed; /* items this process computed (atomic; the others came from ranks) */
    vr_medium md;
    /* the medium's box for the rays that leave the view: secondary rays (any medium) and,
     * in a field, rays towards a directional light: the field's bounds, the scene's (with
     * the eye) on the axes where the field has none or the medium is homogeneous */
    double box_lo[3], box_hi[3];
    bool any_local, any_dir; /* point or spot lights; directional lights */
} vr_run;

/* Sub-pixel position k of pixel `pix`: stratified in [0, 1)^2. `perm` (Latin hypercube
 * only): the pixel's permutation of 0 .. spp-1 (vr_perm). */
static void vr_subpixel(const vr_run *r, uint64_t pix, uint32_t k, const uint32_t *perm,
                        double uv[2])
{
    uint64_t h = vr_mix(r->st->seed * 0x2545f4914f6cdd1dull ^ vr_mix(pix * 8192u + k));
    double xi0 = vr_unit(h), xi1 = vr_unit(vr_mix(h));
    if (r->st->centre) {
        uv[0] = uv[1] = 0.5;
        return;
    }
    if (r->side) {
        uv[0] = ((k % r->side) + xi0) / r->side;
        uv[1] = ((k / r->side) + xi1) / r->side;
        return;
    }
    /* a Latin hypercube: u stratified by k, v by the pixel's permutation of k */
    uint32_t spp = r->st->spp;
    uv[0] = (k + xi0) / spp;
    uv[1] = (perm[k] + xi1) / spp;
}

/* A Fisher-Yates shuffle of 0 .. spp-1 seeded by (seed, pixel). */
static void vr_perm(const vr_run *r, uint64_t pix, uint32_t *perm)
{
    uint32_t spp = r->st->spp;
    for (uint32_t i = 0; i < spp; i++)
        perm[i] = i;
    uint64_t s = vr_mix(r->st->seed ^ vr_mix(pix ^ 0x5bd1e995ull));
    for (uint32_t i = spp - 1; i > 0; i--) {
        s = vr_mix(s);
        uint32_t j = (uint32_t)(s % (i + 1));
        uint32_t t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
}

/* Whether the segment from x along unit dir, up to tfar (INFINITY: the whole ray), is free
 * of geometry (an Embree occlusion ray from tnear_light: x is in the medium, not on a
 * surface). */
static bool vr_visible(const vr_run *r, struct RTCIntersectContext *ctx, const double x[3],
                       const double dir[3], double tfar)
{
    if (tfar <= r->tnear_light)
        return true;
    struct RTCRay ray = { .org_x = (float)x[0],
                          .org_y = (float)x[1],
                          .org_z = (float)x[2],
                          .tnear = (float)r->tnear_light,
                          .dir_x = (float)dir[0],
                          .dir_y = (float)dir[1],
                          .dir_z = (float)dir[2],
                          .tfar = (float)tfar,
                          .mask = ~0u };
    rtcOccluded1(r->e->scene, ctx, &ray);
    return !(ray.tfar < 0.0f); /* -inf: occluded */
}

/* The distance along unit dir from x to where a heterogeneous medium's box ends (r->box_*),
 * 0 when x is outside it. */
static double vr_box_exit(const vr_run *r, const double x[3], const double dir[3])
{
    double a = 0.0, b = HUGE_VAL;
    return vr_clip_box(x, dir, r->box_lo, r->box_hi, &a, &b) && a <= 0.0 ? b : 0.0;
}

/* The medium's transmittance from x towards light l at distance dist along to_light:
 * homogeneous e^(-sigma_t d) (1 for a directional light, vol_light_transmittance); in a
 * field, tracked (ratio or delta) to the light, or to the box's end for a directional one:
 * the medium shadows itself. */
static void vr_light_T(const vr_run *r, const vol_light *l, const double x[3],
                       const double to_light[3], double dist, vr_rng *rng, double T[3])
{
    if (!r->md.hetero) {
        for (int c = 0; c < 3; c++)
            T[c] = vol_light_transmittance(r->v, l, dist, c);
        return;
    }
    double len = l->type == LG_LIGHT_DIRECTIONAL ? vr_box_exit(r, x, to_light) : dist;
    vr_transmittance(&r->md, x, to_light, len, r->st->ratio, rng, T, NULL);
}

/* Next-event estimation to the directional lights at a scattering point x reached
 * travelling along unit din: acc += sum over them of L_c V(x) T(x) p_HG(g, dot(l, din))
 * (sigma_s is the caller's). Point and spot lights are sampled along the path's segments
 * instead (vr_local_segment): at a point reached by free flight their 1 / d^2 would make
 * the estimate's variance unbounded near the light. */
static void vr_nee(const vr_run *r, struct RTCIntersectContext *ctx, const double x[3],
                   const double din[3], vr_rng *rng, double acc[3])
{
    const vol_setup *v = r->v;
    for (uint32_t li = 0; li < v->n_lights; li++) {
        const vol_light *l = &v->lights[li];
        if (l->type != LG_LIGHT_DIRECTIONAL)
            continue;
        double tl[3], dist;
        double f = vol_light_falloff(l, x, tl, &dist);
        if (!(f > 0.0) || !vr_visible(r, ctx, x, tl, dist))
            continue;
        double T[3];
        vr_light_T(r, l, x, tl, dist, rng, T);
        double p = lg_hg_phase(v->g, tl[0] * din[0] + tl[1] * din[1] + tl[2] * din[2]);
        for (int c = 0; c < 3; c++)
            acc[c] += (double)l->l_c[c] * f * p * T[c];
    }
}

/* The view transmittance from the eye to t along w: exact (homogeneous) or tracked. */
static void vr_view_T(const vr_run *r, const double w[3], double t, vr_rng *rng, double T[3])
{
    vr_transmittance(&r->md, r->v->eye, w, t, r->st->ratio, rng, T, NULL);
}

/* The in-scattering of point or spot light l along the ray o + t w, t in [0, d] (d may be
 * INFINITY in a homogeneous medium: xi1 = pi/2), by equiangular sampling: n stratified
 * samples of xi, the mean added to lv (README.md, "Point and spot lights"). The interval is
 * first cut to the range's sphere (W = 0 beyond) and to the field's box. Used for the view
 * ray (order 1) and for every segment of a path (orders >= 2, n = 1). */
static void vr_local_segment(const vr_run *r, struct RTCIntersectContext *ctx, const vol_light *l,
                             const double o[3], const double w[3], double d, uint32_t n,
                             vr_rng *rng, double lv[3])
{
    const vol_setup *v = r->v;
    double q[3] = { l->pos[0], l->pos[1], l->pos[2] };
    double ta = 0.0, tb = d;
    if (r->md.hetero) {
        double lo[3], hi[3];
        vr_field_box(&r->md, lo, hi);
        if (!vr_clip_box(o, w, lo, hi, &ta, &tb))
            return;
    }
    if (l->range > 0.0f) {
        double tc = 0.0, qq = 0.0;
        for (int c = 0; c < 3; c++) {
            tc += (q[c] - o[c]) * w[c];
            qq += (q[c] - o[c]) * (q[c] - o[c]);
        }
        double R = l->range, h2 = qq - tc * tc;
        if (!(h2 < R * R))
            return;
        double half = sqrt(R * R - (h2 > 0.0 ? h2 : 0.0));
        ta = fmax(ta, tc - half);
        tb = fmin(tb, tc + half);
    }
    if (!(tb > ta))
        return;
    vr_equi e;
    vr_equi_init(&e, o, w, q, ta, tb);
    double acc[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < n; i++) {
        double ip, tl[3], dist;
        double t = vr_equi_sample(&e, ((double)i + vr_next(rng)) / n, &ip);
        double x[3] = { o[0] + t * w[0], o[1] + t * w[1], o[2] + t * w[2] };
        double f = vol_light_falloff(l, x, tl, &dist);
        double m = vr_density(&r->md, x);
        if (!(f > 0.0) || !(m > 0.0) || !isfinite(ip) || !vr_visible(r, ctx, x, tl, dist))
            continue;
        double Tl[3], Tv[3];
        vr_light_T(r, l, x, tl, dist, rng, Tl);
        vr_transmittance(&r->md, o, w, t, r->st->ratio, rng, Tv, NULL);
        double p = lg_hg_phase(v->g, tl[0] * w[0] + tl[1] * w[1] + tl[2] * w[2]);
        for (int c = 0; c < 3; c++)
            acc[c] += (double)l->l_c[c] * v->sigma_s[c] * m * f * ip * p * Tl[c] * Tv[c];
    }
    for (int c = 0; c < 3; c++)
        lv[c] += acc[c] / n;
}

/* Single scattering of point or spot light l along the view ray [0, d]: `steps` samples. */
static void vr_local_single(const vr_run *r, struct RTCIntersectContext *ctx, const vol_light *l,
                            const double w[3], double d, uint64_t key, double lv[3])
{
    vr_rng rng = vr_rng_make(key);
    vr_local_segment(r, ctx, l, r->v->eye, w, d, r->st->steps, &rng, lv);
}

/* Single scattering of the directional lights in a heterogeneous medium: `steps` jittered
 * strata of the view ray's part inside the field's box, the view and light transmittances
 * tracked. */
static void vr_dir_field_single(const vr_run *r, struct RTCIntersectContext *ctx, const double w[3],
                                double d, uint64_t key, double lv[3])
{
    const vol_setup *v = r->v;
    double lo[3], hi[3], ta = 0.0, tb = d;
    vr_field_box(&r->md, lo, hi);
    if (!vr_clip_box(v->eye, w, lo, hi, &ta, &tb))
        return;
    vr_rng rng = vr_rng_make(key);
    uint32_t steps = r->st->steps;
    double h = (tb - ta) / steps, acc[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < steps; i++) {
        double t = ta + h * ((double)i + vr_next(&rng));
        double x[3] = { v->eye[0] + t * w[0], v->eye[1] + t * w[1], v->eye[2] + t * w[2] };
        double m = vr_density(&r->md, x);
        if (!(m > 0.0))
            continue;
        double sum[3] = { 0, 0, 0 }, Tv[3];
        for (uint32_t li = 0; li < v->n_lights; li++) {
            const vol_light *l = &v->lights[li];
            if (l->type != LG_LIGHT_DIRECTIONAL)
                continue;
            double tl[3] = { -l->dir[0], -l->dir[1], -l->dir[2] }, Tl[3];
            if (!vr_visible(r, ctx, x, tl, INFINITY))
                continue;
            vr_light_T(r, l, x, tl, INFINITY, &rng, Tl);
            double p = lg_hg_phase(v->g, tl[0] * w[0] + tl[1] * w[1] + tl[2] * w[2]);
            for (int c = 0; c < 3; c++)
                sum[c] += (double)l->l_c[c] * p * Tl[c];
        }
        if (sum[0] == 0.0 && sum[1] == 0.0 && sum[2] == 0.0)
            continue;
        vr_view_T(r, w, t, &rng, Tv);
        for (int c = 0; c < 3; c++)
            acc[c] += sum[c] * v->sigma_s[c] * m * Tv[c];
    }
    for (int c = 0; c < 3; c++)
        lv[c] += acc[c] * h;
}

/* Orders 2 .. order by path tracing (README.md, "Multiple scattering"): `paths` paths per
 * view ray, each: the first scattering point x1 on [0, d] by free flight (delta tracking),
 * then per order k a direction from the phase function (its inverse CDF) and the segment
 * along it up to the first surface (which absorbs: the path ends there, as it does when it
 * leaves the medium); order k's light is the point and spot lights' in-scattering along
 * that segment (equiangular) and, at the next point drawn by free flight on it,
 * next-event estimation to the directional lights. Order 1 is the single-scattering
 * estimate and is not added again. */
static void vr_paths(const vr_run *r, struct RTCIntersectContext *ctx, const double w[3], double d,
                     uint64_t key, double lv[3])
{
    const vol_setup *v = r->v;
    const vr_state *st = r->st;
    double sum[3] = { 0, 0, 0 };
    for (uint32_t j = 0; j < st->paths; j++) {
        vr_rng rng = vr_rng_make(key ^ vr_mix(j + 0x3c6ef372fe94f82bull));
        double beta[3] = { 1, 1, 1 }, dir[3] = { w[0], w[1], w[2] };
        double t = vr_free_flight(&r->md, v->eye, w, 0.0, d, &rng, beta, NULL);
        if (!isfinite(t))
            continue;
        double x[3] = { v->eye[0] + t * w[0], v->eye[1] + t * w[1], v->eye[2] + t * w[2] };
        for (uint32_t k = 2; k <= st->order; k++) {
            double nd[3];
            double c = vr_hg_sample_cos(v->g, vr_next(&rng));
            vr_hg_sample_dir(dir, c, vr_next(&rng), nd);
            struct RTCRayHit rh;
            memset(&rh, 0, sizeof rh);
            rh.ray.org_x = (float)x[0], rh.ray.org_y = (float)x[1], rh.ray.org_z = (float)x[2];
            rh.ray.dir_x = (float)nd[0], rh.ray.dir_y = (float)nd[1], rh.ray.dir_z = (float)nd[2];
            rh.ray.tnear = (float)r->tnear_light;
            rh.ray.tfar = INFINITY;
            rh.ray.mask = ~0u;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(r->e->scene, ctx, &rh);
            double s = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? (double)rh.ray.tfar : INFINITY;
            /* the medium's box ends every secondary ray, homogeneous too: an unbounded fog
             * lit by a directional light it does not attenuate would send each order back
             * with about the albedo's share, the series growing towards 1 / (1 - a) */
            s = fmin(s, vr_box_exit(r, x, nd));
            /* order k from point and spot lights: their in-scattering along this segment
             * (one equiangular sample each), seen from x */
            double acc[3] = { 0, 0, 0 };
            if (r->any_local)
                for (uint32_t li = 0; li < v->n_lights; li++)
                    if (v->lights[li].type != LG_LIGHT_DIRECTIONAL)
                        vr_local_segment(r, ctx, &v->lights[li], x, nd, s, 1, &rng, acc);
            for (int c2 = 0; c2 < 3; c2++)
                sum[c2] += beta[c2] * acc[c2];
            double tt = vr_free_flight(&r->md, x, nd, 0.0, s, &rng, beta, NULL);
            if (!isfinite(tt))
                break;
            for (int c2 = 0; c2 < 3; c2++) {
                x[c2] += tt * nd[c2];
                dir[c2] = nd[c2];
            }
            /* order k from directional lights: next-event estimation at the new point */
            if (!r->any_dir)
                continue;
            acc[0] = acc[1] = acc[2] = 0.0;
            vr_nee(r, ctx, x, dir, &rng, acc);
            for (int c2 = 0; c2 < 3; c2++)
                sum[c2] += beta[c2] * acc[c2];
            if (beta[0] == 0.0 && beta[1] == 0.0 && beta[2] == 0.0)
                break;
        }
    }
    for (int c = 0; c < 3; c++)
        lv[c] += sum[c] / st->paths;
}

/* One pixel's in-scattered radiance (mean over its rays). */
static void vr_pixel(const vr_run *r, uint32_t x, uint32_t y, double lv[3])
{
    const vol_setup *v = r->v;
    const vr_state *st = r->st;
    uint64_t pix = (uint64_t)y * v->width + x;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    lv[0] = lv[1] = lv[2] = 0.0;
    uint32_t perm[VR_MAX_SPP];
    if (!r->side && !st->centre)
        vr_perm(r, pix, perm);
    for (uint32_t k = 0; k < st->spp; k++) {
        double uv[2], w[3];
        vr_subpixel(r, pix, k, perm, uv);
        vol_ray(v, x + uv[0], y + uv[1], w);
        double cf = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
        if (!(cf > 0.0))
            continue; /* cannot happen for a ray inside the view: no fog behind the eye */
        /* the surface: the first hit past the near plane (what the raster clipped is not
         * there), the fog ends at z_limit */
        double limit = (double)v->z_limit / cf;
        struct RTCRayHit rh;
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = (float)v->eye[0], rh.ray.org_y = (float)v->eye[1];
        rh.ray.org_z = (float)v->eye[2];
        rh.ray.dir_x = (float)w[0], rh.ray.dir_y = (float)w[1], rh.ray.dir_z = (float)w[2];
        rh.ray.tnear = (float)(v->view.znear / cf);
        rh.ray.tfar = (float)limit;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(r->e->scene, &ctx, &rh);
        double d = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? (double)rh.ray.tfar : limit;
        if (!(d > 0.0) || !isfinite(d))
            continue;
        uint64_t key = vr_mix(st->seed ^ 0x7f4a7c159e3779b9ull) ^ vr_mix(pix * 8192u + k);
        double ray_lv[3] = { 0, 0, 0 };
        if (r->any_local)
            for (uint32_t li = 0; li < v->n_lights; li++)
                if (v->lights[li].type != LG_LIGHT_DIRECTIONAL)
                    vr_local_single(r, &ctx, &v->lights[li], w, d, key ^ vr_mix(li + 1), ray_lv);
        if (r->any_dir && r->md.hetero)
            vr_dir_field_single(r, &ctx, w, d, key ^ 0x94d049bb133111ebull, ray_lv);
        if (st->order > 1)
            vr_paths(r, &ctx, w, d, key ^ 0xbf58476d1ce4e5b9ull, ray_lv);
        for (int ch = 0; ch < 3; ch++)
            lv[ch] += ray_lv[ch];
        if (!r->any_dir || r->md.hetero)
            continue;
        /* directional lights in a homogeneous medium: stratified steps, each segment's
         * transmittance integrated exactly (the estimator of ABI 2.x, the same bits) */
        double h = d / st->steps;
        /* per light: L_c sigma_s p; per channel: the segment's own integral (b - a) seg */
        double lit[VOL_MAX_LIGHTS][3], segi[3];
        for (uint32_t l = 0; l < v->n_lights; l++) {
            const float *L = v->lights[l].dir;
            double c = -(w[0] * L[0] + w[1] * L[1] + w[2] * L[2]);
            double p = lg_hg_phase(v->g, c);
            for (int ch = 0; ch < 3; ch++)
                lit[l][ch] = (double)v->lights[l].l_c[ch] * v->sigma_s[ch] * p;
        }
        for (int ch = 0; ch < 3; ch++)
            segi[ch] = h * lg_medium_segment((double)v->sigma_t[ch] * h);
        uint64_t rs = vr_mix(vr_mix(st->seed + 0x632be59bd9b4e019ull) ^ vr_mix(pix * 8192u + k));
        double acc[3] = { 0, 0, 0 };
        for (uint32_t i = 0; i < st->steps; i++) {
            double a = h * i;
            double t = a + h * vr_unit(vr_mix(rs + i));
            double xs[3] = { v->eye[0] + t * w[0], v->eye[1] + t * w[1], v->eye[2] + t * w[2] };
            double vis[3] = { 0, 0, 0 };
            for (uint32_t l = 0; l < v->n_lights; l++) {
                const float *L = v->lights[l].dir;
                if (v->lights[l].type != LG_LIGHT_DIRECTIONAL)
                    continue;
                struct RTCRay ray = { .org_x = (float)xs[0],
                                      .org_y = (float)xs[1],
                                      .org_z = (float)xs[2],
                                      .tnear = (float)r->tnear_light,
                                      .dir_x = -L[0],
                                      .dir_y = -L[1],
                                      .dir_z = -L[2],
                                      .tfar = INFINITY,
                                      .mask = ~0u };
                rtcOccluded1(r->e->scene, &ctx, &ray);
                if (ray.tfar < 0.0f) /* -inf: occluded */
                    continue;
                for (int ch = 0; ch < 3; ch++)
                    vis[ch] += lit[l][ch];
            }
            for (int ch = 0; ch < 3; ch++)
                if (vis[ch] != 0.0)
                    acc[ch] += vis[ch] * exp(-(double)v->sigma_t[ch] * a);
        }
        for (int ch = 0; ch < 3; ch++)
            lv[ch] += acc[ch] * segi[ch];
    }
    for (int ch = 0; ch < 3; ch++)
        lv[ch] /= st->spp;
}

/* A heterogeneous medium's transmittance to the surface behind pixel (x, y) (the centre
 * ray to the stored depth, as the homogeneous e^(-sigma_t d)): the mean of spp tracked
 * estimates (unbiased; noise on `out` only, inscatter does not use it). */
static void vr_base_T(const vr_run *r, uint32_t x, uint32_t y, double d, double T[3])
{
    const vol_setup *v = r->v;
    double w[3];
    vol_ray(v, x + 0.5, y + 0.5, w);
    uint64_t pix = (uint64_t)y * v->width + x;
    vr_rng rng = vr_rng_make(vr_mix(r->st->seed ^ 0x2545f4914f6cdd1dull) ^ vr_mix(pix));
    T[0] = T[1] = T[2] = 0.0;
    for (uint32_t k = 0; k < r->st->spp; k++) {
        double t1[3];
        vr_view_T(r, w, d, &rng, t1);
        for (int c = 0; c < 3; c++)
            T[c] += t1[c] / r->st->spp;
    }
}

/* One pixel's result, an lg_shard item's element: out's and inscatter's colour (alpha and
 * depth come from base, which every rank has). */
typedef struct vr_px {
    float out[3], insc[3];
} vr_px;

/* Pixel (x, y)'s in-scattering and the extinction of the surface behind it into *px. */
static void vr_pixel_px(const vr_run *r, uint32_t x, uint32_t y, vr_px *px)
{
    const vol_setup *v = r->v;
    double lv[3];
    vr_pixel(r, x, y, lv);
    const float *b = r->base + ((size_t)y * r->base_row + x) * 4;
    float dz = r->depth[(size_t)y * r->base_row + x];
    /* extinction of the surface behind the fog: the pixel-centre ray to the depth the
     * raster stored (what base shows) */
    double d = vol_fog_length(v, x + 0.5, y + 0.5, dz);
    double Tf[3] = { 0, 0, 0 };
    if (r->md.hetero && isfinite(d))
        vr_base_T(r, x, y, d, Tf);
    for (int ch = 0; ch < 3; ch++) {
        double T = !isfinite(d) ? 0.0 : r->md.hetero ? Tf[ch] : exp(-(double)v->sigma_t[ch] * d);
        px->out[ch] = (float)((double)b[ch] * T + lv[ch]);
        px->insc[ch] = (float)lv[ch];
    }
}

/* lg_shard's run: items [begin, end), each a span of r->span pixels of one row (item i:
 * row i / spans_per_row, pixels from (i % spans_per_row) x span; the row's last span may
 * be shorter, its tail zeros). Every random number is a hash of (seed, pixel, ray, ...):
 * an item's bytes depend on its index alone, whichever thread or rank computes it. */
static int vr_spans(void *ctx, uint64_t begin, uint64_t end, void *items, char *err,
                    size_t err_size)
{
    (void)err;
    (void)err_size;
    const vr_run *r = ctx;
    vr_px *px = items;
    for (uint64_t i = begin; i < end; i++, px += r->span) {
        uint32_t y = (uint32_t)(i / r->spans_per_row);
        uint32_t x0 = (uint32_t)(i % r->spans_per_row) * r->span;
        uint32_t x1 = x0 + r->span < r->v->width ? x0 + r->span : r->v->width;
        memset(px + (x1 - x0), 0, (size_t)(r->span - (x1 - x0)) * sizeof *px);
        for (uint32_t x = x0; x < x1; x++)
            vr_pixel_px(r, x, y, &px[x - x0]);
    }
    __atomic_fetch_add(r->computed, end - begin, __ATOMIC_RELAXED);
    return 0;
}

/* The CPU seconds of every thread of this process (the debug line's measure of the
 * per-pixel cost: unlike wall time it holds on a machine shared with other work). */
static double vr_cpu_seconds(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- the node -------------------------------------------------------------------------------- */

static int vr_create(lg_node *n)
{
    vr_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    return 0;
}

static void vr_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static int vr_prepare(lg_node *n)
{
    vr_state *st = n->user;
    int64_t steps = lg_param_int(n, "steps"), spp = lg_param_int(n, "spp");
    int64_t seed = lg_param_int(n, "seed");
    double z_limit = lg_param_float(n, "z_limit");
    if (steps < 1 || steps > VR_MAX_STEPS)
        return lg_error(n, "steps = %lld: must be in [1, %d]", (long long)steps, VR_MAX_STEPS);
    if (spp < 1 || spp > VR_MAX_SPP)
        return lg_error(n, "spp = %lld: must be in [1, %d]", (long long)spp, VR_MAX_SPP);
    if (seed < 0)
        return lg_error(n, "seed = %lld: must be >= 0", (long long)seed);
    if (!isfinite(z_limit) || z_limit < 0.0 || z_limit > 1e30)
        return lg_error(n, "z_limit = %g: must be a view depth >= 0 (0 = the camera's zfar)",
                        z_limit);
    int64_t order = lg_param_int(n, "order"), paths = lg_param_int(n, "paths");
    if (order < 1 || order > VR_MAX_ORDER)
        return lg_error(n, "order = %lld: must be in [1, %d] (1 = single scattering)",
                        (long long)order, VR_MAX_ORDER);
    if (paths < 1 || paths > VR_MAX_PATHS)
        return lg_error(n, "paths = %lld: must be in [1, %d]", (long long)paths, VR_MAX_PATHS);
    st->order = (uint32_t)order;
    st->paths = (uint32_t)paths;
    st->ratio = lg_param_enum(n, "transmittance") == 0;
    st->steps = (uint32_t)steps;
    st->spp = (uint32_t)spp;
    st->seed = (uint64_t)seed;
    st->z_limit = (float)z_limit;
    st->centre = lg_param_enum(n, "subpixel") == 1;
    st->per_frame = lg_param_bool(n, "per_frame");
    int rc = vol_declare_outputs(n, &st->width, &st->height);
    if (rc)
        return rc;
    lg_resource_info info;
    if (lg_describe(lg_input(n, VOL_IN_BASE), &info, n) == 0 &&
        info.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n,
                        "input 'base' is not rgba32f (format %d): connect a linear lit "
                        "image (phong's out)",
                        (int)info.image.format);
    if (st->per_frame)
        lg_set_per_frame(n, true);
    /* the estimate: one occlusion ray per pixel, sub-pixel ray, step and light; orders
     * >= 2: per path and order one ray to the next point and one per light */
    double lights = vol_scene_lights(n, VOL_ACCEPT_LIGHTS);
    double rays = (double)st->width * st->height * st->spp *
                  (st->steps * lights + (double)(st->order - 1) * st->paths * (lights + 1.0));
    lg_declare_work(n, rays, rays * VR_SECONDS_PER_RAY / lg_cpu_workers(n), "occlusion rays");
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int vr_execute(lg_node *n, const lg_frame *frame)
{
    vr_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, VOL_IN_SCENE));
    if (!s)
        return lg_error(n, "input 'scene' holds no scene");
    /* base passes into `out`: its NaN and Inf are said once, as `image` says a file's */
    int rc = lg_check_input_finite(n, frame, VOL_IN_BASE, "base", NULL, &st->reported_nonfinite);
    if (rc)
        return rc;
    vol_setup v;
    rc = vol_setup_make(n, s, st->width, st->height, st->z_limit, NULL,
                        VOL_ACCEPT_LIGHTS | VOL_ACCEPT_FIELD, &v);
    if (rc)
        return rc;
    for (int ch = 0; ch < 3; ch++)
        if (!isfinite(v.sigma_s[ch]) || !isfinite(v.sigma_t[ch]) || v.sigma_s[ch] < 0.0f ||
            v.sigma_t[ch] < v.sigma_s[ch])
            return lg_error(n,
                            "the scene's medium has sigma_s %g, sigma_t %g (channel %d): "
                            "need finite 0 <= sigma_s <= sigma_t",
                            (double)v.sigma_s[ch], (double)v.sigma_t[ch], ch);
    if (!isfinite(v.g))
        return lg_error(n, "the scene's medium has g = %g", (double)v.g);
    for (uint32_t l = 0; l < v.n_lights; l++)
        for (int ch = 0; ch < 3; ch++)
            if (!isfinite(v.lights[l].l_c[ch]) || v.lights[l].l_c[ch] < 0.0f)
                return lg_error(n,
                                "light %u: colour x intensity %g (channel %d) is not a "
                                "finite value >= 0",
                                v.lights[l].scene_index, (double)v.lights[l].l_c[ch], ch);

    lg_cpu_view bv, ov, iv;
    if (lg_map_cpu(n, lg_input(n, VOL_IN_BASE), LG_READ, &bv) || !bv.pixels || !bv.depth)
        return lg_error(n, "input 'base' cannot be read on the CPU");
    if (lg_map_cpu(n, lg_output(n, VOL_OUT_OUT), LG_WRITE, &ov) || !ov.pixels || !ov.depth)
        return lg_error(n, "output 'out' cannot be written");
    if (lg_map_cpu(n, lg_output(n, VOL_OUT_INSCATTER), LG_WRITE, &iv) || !iv.pixels)
        return lg_error(n, "output 'inscatter' cannot be written");

    /* every instance in world space, as prt_bake builds it (plugins/embree_common), at
     * this frame's pose when the scene is animated (ABI 3.1) */
    double t_setup = lg_now(n);
    lg_embree e;
    rc = lg_embree_make_at(n, s, frame->time, &e);
    if (rc) {
        lg_embree_free(&e);
        return rc;
    }
    /* buffers + about 1.5x for the BVH; made and released in every execute */
    const uint64_t counted = (uint64_t)e.bytes * 5 / 2;
    lg_account_alloc(n, counted);
    uint32_t side = (uint32_t)lround(sqrt((double)st->spp));
    vr_run r = {
        .st = st,
        .v = &v,
        .e = &e,
        .base = bv.pixels,
        .depth = bv.depth,
        .base_row = bv.row_pixels,
        .side = side * side == st->spp ? side : 0,
        /* occlusion rays start in the medium, not on a surface: a small fraction of the
         * scene's size clears float rounding at the origin without skipping geometry */
        .tnear_light = 1e-5 * (e.extent > 0.0 ? e.extent : 1.0),
    };
    vr_medium_make(&r.md, &v.medium, v.sigma_s, v.sigma_t);
    for (uint32_t l = 0; l < v.n_lights; l++) {
        r.any_local |= v.lights[l].type != LG_LIGHT_DIRECTIONAL;
        r.any_dir |= v.lights[l].type == LG_LIGHT_DIRECTIONAL;
    }
    /* per axis, the field's bound where it has one; where it is unbounded (-/+FLT_MAX) the
     * scene's bounds with the eye, grown by 1% (a directional light's and a secondary
     * ray's way out of an unbounded fog must end somewhere) */
    for (int c = 0; c < 3; c++) {
        double lo = fmin(v.scene_min[c], v.eye[c]), hi = fmax(v.scene_max[c], v.eye[c]);
        double pad = 0.01 * (hi - lo) + 1e-6;
        r.box_lo[c] = lo - pad;
        r.box_hi[c] = hi + pad;
        if (r.md.hetero && v.medium.field->bounds_min[c] > -FLT_MAX)
            r.box_lo[c] = v.medium.field->bounds_min[c];
        if (r.md.hetero && v.medium.field->bounds_max[c] < FLT_MAX)
            r.box_hi[c] = v.medium.field->bounds_max[c];
    }
    /* The pixels as lg_shard items (host.h: over the pool's threads, and under mpirun over
     * every rank; the same bits for any count of either): spans of at most VR_SPAN pixels
     * of one row, a row cut into equal spans. A row of a film-sized image is too coarse a
     * unit for many ranks (the host hands a rank `grain` x its threads items at a time:
     * 1080 rows over 64 ranks of 16 threads would leave half of them idle), and pixels
     * through the bunny or a cloud cost more than the sky beside them, so a small grain of
     * one span balances the load; a span still makes thousands of rays, beside which
     * handing it out costs nothing. */
    uint32_t W = st->width, H = st->height;
    uint32_t nspan = (W + VR_SPAN - 1) / VR_SPAN;
    r.span = (W + nspan - 1) / nspan;
    r.spans_per_row = (W + r.span - 1) / r.span;
    uint64_t count = (uint64_t)r.spans_per_row * H, item_bytes = (uint64_t)r.span * sizeof(vr_px);
    /* every item on every rank: out and inscatter below are filled from it everywhere */
    vr_px *px = malloc((size_t)(count * item_bytes));
    if (!px) {
        lg_embree_free(&e);
        lg_account_free(n, counted);
        return lg_error(n, "out of memory for %ux%u pixels' results (%.1f MiB)", W, H,
                        (double)(count * item_bytes) / 1048576.0);
    }
    lg_account_alloc(n, count * item_bytes);
    uint64_t computed = 0;
    r.computed = &computed;
    double t_shard = lg_now(n), c_shard = vr_cpu_seconds();
    lg_progress(n, 0.0, "ray marching");
    lg_shard_job job = { .count = count,
                         .grain = 1,
                         .item_bytes = item_bytes,
                         .out = px,
                         .run = vr_spans,
                         .ctx = &r,
                         .what = "pixel spans" };
    rc = lg_shard(n, &job);
    double t_done = lg_now(n), c_done = vr_cpu_seconds();
    if (rc == 0) {
        lg_progress(n, 1.0, "ray marching");
        /* the items into the images; alpha and depth from base */
        const float *bp = bv.pixels;
        float *op = ov.pixels, *ip = iv.pixels;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                const vr_px *q = &px[(size_t)y * r.spans_per_row * r.span + x];
                const float *b = bp + ((size_t)y * bv.row_pixels + x) * 4;
                float *o = op + ((size_t)y * ov.row_pixels + x) * 4;
                float *i = ip + ((size_t)y * iv.row_pixels + x) * 4;
                for (int ch = 0; ch < 3; ch++) {
                    o[ch] = q->out[ch];
                    i[ch] = q->insc[ch];
                }
                o[3] = b[3];
                i[3] = 1.0f;
                ov.depth[(size_t)y * ov.row_pixels + x] = bv.depth[(size_t)y * bv.row_pixels + x];
            }
        lg_log(n, LG_LOG_DEBUG,
               "%ux%u, %u lights, spp %u, steps %u, order %u, paths %u, %s medium (%s); "
               "Embree scene and set-up %.3f s; %llu spans of %u pixels (%llu bytes), %llu of "
               "them computed by this process, %.3f s (%.3f s of CPU)",
               st->width, st->height, v.n_lights, st->spp, st->steps, st->order, st->paths,
               r.md.hetero ? "heterogeneous" : "homogeneous",
               st->ratio ? "ratio tracking" : "delta tracking", t_shard - t_setup,
               (unsigned long long)count, r.span, (unsigned long long)(count * item_bytes),
               (unsigned long long)__atomic_load_n(&computed, __ATOMIC_RELAXED), t_done - t_shard,
               c_done - c_shard);
    }
    free(px);
    lg_account_free(n, count * item_bytes);
    lg_embree_free(&e);
    lg_account_free(n, counted);
    return rc;
}

static const char *const vr_subpixels[] = { "jittered", "centre", NULL };
static const char *const vr_transmittances[] = { "ratio", "delta", NULL };

static const lg_param_desc vr_params[] = {
    { .key = "steps",
      .type = LG_PARAM_INT,
      .def.i = 256,
      .min = 1,
      .max = VR_MAX_STEPS,
      .doc = "segments per ray (one jittered visibility sample each; the transmittance "
             "inside a segment is integrated exactly)" },
    { .key = "spp",
      .type = LG_PARAM_INT,
      .def.i = 4,
      .min = 1,
      .max = VR_MAX_SPP,
      .doc = "rays per pixel, stratified within the pixel (a square count: a jittered grid; "
             "any other: a jittered Latin hypercube)" },
    { .key = "seed",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 0x7fffffff,
      .doc = "the jitter's seed (every random number is a hash of seed, pixel, ray, step)" },
    { .key = "subpixel",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = vr_subpixels,
      .doc = "jittered (the rays cover the pixel: antialiased) or centre (every ray through "
             "the pixel centre, as the screen-space methods sample; spp then averages the "
             "visibility samples only)" },
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth (scene units) where the fog ends; 0 = the camera's zfar" },
    { .key = "order",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 1,
      .max = VR_MAX_ORDER,
      .doc = "scattering events per path: 1 = single scattering (as before); n > 1 adds "
             "orders 2 .. n by path tracing (phase-function sampling, free flight, "
             "next-event estimation to every light; surfaces absorb)" },
    { .key = "paths",
      .type = LG_PARAM_INT,
      .def.i = 4,
      .min = 1,
      .max = VR_MAX_PATHS,
      .doc = "order > 1: paths per sub-pixel ray for the orders >= 2" },
    { .key = "transmittance",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = vr_transmittances,
      .doc = "a heterogeneous medium's transmittance estimator (view ray, towards each "
             "light): ratio tracking (weights, lower noise) or delta tracking (0 or 1); "
             "both unbiased against a majorant from lg_medium_field_max per 1/16 of the "
             "segment. A homogeneous medium uses e^(-sigma_t d) exactly" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "run again on every frame (--frames), for timing; the result is the same" },
};

static const lg_port_desc vr_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene: its lights (directional, point, spot), medium (homogeneous or a "
             "density field), active camera; every instance occludes" },
    { .name = "base",
      .kind = LG_KIND_IMAGE,
      .doc = "the lit image with depth (phong's out), rgba32f" },
};
static const lg_port_desc vr_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f + depth: base e^(-sigma_t d) + inscatter, base's depth" },
    { .name = "inscatter",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: the in-scattered radiance L_v alone, alpha 1" },
};

static const lg_node_type vr_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "volumetric_reference",
        .doc = "Single (or multiple, `order`) scattering in the scene's medium, homogeneous or "
               "heterogeneous, from directional, point and spot lights with Embree "
               "visibility (CPU): the oracle of the volumetric methods",
        LG_PARAMS(vr_params),
        LG_INPUTS(vr_inputs),
        LG_OUTPUTS(vr_outputs),
        .needs = LG_NEEDS_MEDIUM | LG_NEEDS_LIGHT,
        .neutral = LG_NEUTRAL_PASSTHROUGH_FIRST,
        .neutral_input = 1,
        .create = vr_create,
        .prepare = vr_prepare,
        .execute = vr_execute,
        .destroy = vr_destroy,
    },
};

LG_PLUGIN_DEFINE("volumetric_reference", "1.0.0",
                 "Ray-marched single scattering with Embree visibility: the reference of "
                 "the volumetric methods",
                 vr_types)
