/*
 * plugins/volumetric_reference/vr_estimators.h: the sampling and tracking routines of
 * volumetric_reference (README.md beside this file, "Estimators"), header-only so that
 * tests/plugins/volumetric_reference/test_vr_estimators.c checks each one directly against
 * its distribution or its closed form.
 *
 *   vr_rng              a counter-based stream (splitmix64): the same numbers on any thread
 *   vr_hg_sample_cos    the Henyey-Greenstein phase function sampled by its inverse CDF
 *   vr_hg_sample_dir    a direction about an axis with that cosine
 *   vr_equi_*           equiangular sampling of a point light along a ray (Kulla & Fajardo
 *                       2012): pdf proportional to 1 / (H^2 + (t - t_c)^2)
 *   vr_medium           the medium as the estimators see it (coefficients, field, box)
 *   vr_transmittance    ratio tracking (unbiased, weights) or delta tracking (unbiased,
 *                       0 or 1) of e^(-integral sigma_t) along a segment
 *   vr_free_flight      the next real collision along a segment by delta tracking with
 *                       per-channel weights (spectral tracking, Kutz et al. 2017)
 *
 * Majorants: a heterogeneous segment is cut into VR_MAJORANT_PIECES equal pieces, each
 * with its own majorant mu = max_c sigma_t[c] x lg_medium_field_max over the piece's box
 * (a piecewise constant majorant keeps both trackings unbiased and spends fewer tentative
 * collisions where height fog thins out). A homogeneous segment has mu = max_c sigma_t[c]
 * and m = 1 (no field evaluation).
 */
#ifndef VR_ESTIMATORS_H
#define VR_ESTIMATORS_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "lightgraph/medium.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#define VR_MAJORANT_PIECES 16
/* tentative collisions one tracking may take before it stops (a majorant so large that
 * the run would not end; lg_medium_field_max bounds every field, so only absurd fields
 * reach it): the estimate is then cut there (biased low, counted in *capped) */
#define VR_MAX_COLLISIONS 1000000

/* ---- random numbers -------------------------------------------------------------------------- */

/* splitmix64's finaliser: a counter-based generator (a pure function of its input). */
static inline uint64_t vr_mix(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* A uniform double in [0, 1) from the 53 high bits. */
static inline double vr_unit(uint64_t h)
{
    return (double)(h >> 11) * 0x1.0p-53;
}

typedef struct vr_rng {
    uint64_t s;
} vr_rng;

/* A stream seeded by a key (a hash of seed, pixel, ray, ...). */
static inline vr_rng vr_rng_make(uint64_t key)
{
    return (vr_rng){ vr_mix(key ^ 0xd1b54a32d192ed03ull) };
}

/* The next uniform double in [0, 1). */
static inline double vr_next(vr_rng *r)
{
    r->s += 0x9e3779b97f4a7c15ull;
    return vr_unit(vr_mix(r->s));
}

/* ---- the phase function ---------------------------------------------------------------------- */

/* cos(theta) distributed as p_HG(g, cos) (lg_hg_phase, with its clamp of g) from a uniform
 * xi in [0, 1): the inverse of the CDF
 *     P(cos) = (1 - g^2) / (2g) ((1 + g^2 - 2g cos)^(-1/2) - (1 + g)^(-1)),
 * cos = (1 + g^2 - ((1 - g^2) / (1 - g + 2g xi))^2) / (2g); 2 xi - 1 for |g| < 1e-4 (the
 * formula's cancellation; the phase there differs from isotropic by under 3e-4). */
static inline double vr_hg_sample_cos(double g, double xi)
{
    if (!(g == g))
        g = 0.0;
    g = g < -LG_HG_G_MAX ? -LG_HG_G_MAX : g > LG_HG_G_MAX ? LG_HG_G_MAX : g;
    double c;
    if (fabs(g) < 1e-4) {
        c = 2.0 * xi - 1.0;
    } else {
        double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
        c = (1.0 + g * g - s * s) / (2.0 * g);
    }
    return c < -1.0 ? -1.0 : c > 1.0 ? 1.0 : c;
}

/* A unit direction at cos(theta) = c from unit `axis`, at azimuth 2 pi u (an orthonormal
 * basis by Duff et al. 2017: no branch on the axis but its sign). */
static inline void vr_hg_sample_dir(const double axis[3], double c, double u, double out[3])
{
    double sign = axis[2] >= 0.0 ? 1.0 : -1.0;
    double a = -1.0 / (sign + axis[2]);
    double b = axis[0] * axis[1] * a;
    double t1[3] = { 1.0 + sign * axis[0] * axis[0] * a, sign * b, -sign * axis[0] };
    double t2[3] = { b, sign + axis[1] * axis[1] * a, -axis[1] };
    double s = sqrt(fmax(0.0, 1.0 - c * c)), phi = 2.0 * LG_PI * u;
    double x = s * cos(phi), y = s * sin(phi);
    for (int k = 0; k < 3; k++)
        out[k] = c * axis[k] + x * t1[k] + y * t2[k];
    double l = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
    for (int k = 0; k < 3; k++)
        out[k] /= l;
}

/* ---- equiangular sampling -------------------------------------------------------------------- */

/* A point light q seen from the ray o + t w (w unit), t in [ta, tb]: t = t_c + H tan(xi),
 * xi uniform in [xi0, xi1], H = sqrt(h^2 + LG_LIGHT_EPSILON^2) with h the distance from q
 * to the line. Then pdf(t) = H / ((xi1 - xi0) (H^2 + (t - t_c)^2)) and H^2 + (t - t_c)^2 =
 * d^2 + eps^2: F(x(t)) / pdf(t) = W C (xi1 - xi0) / H, the light's own 1 / (d^2 + eps^2)
 * cancelled (no noise from it, however close the ray passes). */
typedef struct vr_equi {
    double tc, H, xi0, xi1;
} vr_equi;

static inline void vr_equi_init(vr_equi *e, const double o[3], const double w[3], const double q[3],
                                double ta, double tb)
{
    double qo[3], tc = 0.0, qq = 0.0;
    for (int k = 0; k < 3; k++) {
        qo[k] = q[k] - o[k];
        tc += qo[k] * w[k];
        qq += qo[k] * qo[k];
    }
    double h2 = qq - tc * tc;
    e->tc = tc;
    e->H = sqrt((h2 > 0.0 ? h2 : 0.0) + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
    e->xi0 = atan((ta - tc) / e->H);
    e->xi1 = atan((tb - tc) / e->H);
}

/* The point for uniform u in [0, 1) and 1 / pdf there. */
static inline double vr_equi_sample(const vr_equi *e, double u, double *inv_pdf)
{
    double xi = e->xi0 + u * (e->xi1 - e->xi0);
    double s = e->H * tan(xi);
    *inv_pdf = (e->xi1 - e->xi0) * (e->H * e->H + s * s) / e->H;
    return e->tc + s;
}

/* ---- the medium ------------------------------------------------------------------------------ */

typedef struct vr_medium {
    const lg_medium *m; /* its field (m->field NULL: homogeneous) */
    bool hetero;
    double sigma_s[3], sigma_t[3];
    double mu_max; /* max_c sigma_t[c] */
} vr_medium;

static inline void vr_medium_make(vr_medium *md, const lg_medium *m, const float sigma_s[3],
                                  const float sigma_t[3])
{
    md->m = m;
    md->hetero = lg_medium_is_heterogeneous(m);
    md->mu_max = 0.0;
    for (int c = 0; c < 3; c++) {
        md->sigma_s[c] = sigma_s[c];
        md->sigma_t[c] = sigma_t[c];
        md->mu_max = fmax(md->mu_max, (double)sigma_t[c]);
    }
}

/* The density multiplier at p (1 homogeneous). */
static inline double vr_density(const vr_medium *md, const double p[3])
{
    return md->hetero ? lg_medium_field_at(md->m, p) : 1.0;
}

/* The clip of [*a, *b] on the ray o + t w to the box [lo, hi]; false when nothing is left. */
static inline bool vr_clip_box(const double o[3], const double w[3], const double lo[3],
                               const double hi[3], double *a, double *b)
{
    double t0 = *a, t1 = *b;
    for (int k = 0; k < 3; k++) {
        if (w[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k])
                return false;
            continue;
        }
        double u = (lo[k] - o[k]) / w[k], v = (hi[k] - o[k]) / w[k];
        if (u > v) {
            double s = u;
            u = v;
            v = s;
        }
        t0 = u > t0 ? u : t0;
        t1 = v < t1 ? v : t1;
    }
    if (!(t1 > t0))
        return false;
    *a = t0;
    *b = t1;
    return true;
}

/* The field's box (float bounds in double; -/+FLT_MAX when unbounded). */
static inline void vr_field_box(const vr_medium *md, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = md->hetero ? (double)md->m->field->bounds_min[k] : -HUGE_VAL;
        hi[k] = md->hetero ? (double)md->m->field->bounds_max[k] : HUGE_VAL;
    }
}

/* The majorant of sigma_t over the piece [t0, t1] of the ray. */
static inline double vr_piece_majorant(const vr_medium *md, const double o[3], const double w[3],
                                       double t0, double t1)
{
    if (!md->hetero)
        return md->mu_max;
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        double p = o[k] + t0 * w[k], q = o[k] + t1 * w[k];
        lo[k] = p < q ? p : q;
        hi[k] = p < q ? q : p;
    }
    return md->mu_max * lg_medium_field_max(md->m, lo, hi);
}

/* An unbiased estimate of the transmittance e^(-integral_0^len sigma_t) along o + t w
 * (w unit), per channel: homogeneous e^(-sigma_t len) exactly; heterogeneous by ratio
 * tracking (ratio = true: T = prod (1 - sigma_t(x_j) / mu) over the tentative collisions
 * x_j) or delta tracking (ratio = false: 1 until a channel's first real collision, then 0;
 * one uniform decides every channel, so each channel's marginal is exact). The segment is
 * clipped to the field's box first (m = 0 outside). `capped` (may be NULL) counts the
 * trackings cut at VR_MAX_COLLISIONS. */
static inline void vr_transmittance(const vr_medium *md, const double o[3], const double w[3],
                                    double len, bool ratio, vr_rng *r, double T[3],
                                    uint32_t *capped)
{
    T[0] = T[1] = T[2] = 1.0;
    if (!(len > 0.0))
        return;
    if (!md->hetero) {
        for (int c = 0; c < 3; c++)
            T[c] = exp(-md->sigma_t[c] * len);
        return;
    }
    double lo[3], hi[3], a = 0.0, b = len;
    vr_field_box(md, lo, hi);
    if (!vr_clip_box(o, w, lo, hi, &a, &b))
        return;
    double piece = (b - a) / VR_MAJORANT_PIECES;
    uint32_t n = 0;
    for (int pc = 0; pc < VR_MAJORANT_PIECES; pc++) {
        double p0 = pc == 0 ? a : a + piece * pc,
               p1 = pc + 1 == VR_MAJORANT_PIECES ? b : p0 + piece;
        double mu = vr_piece_majorant(md, o, w, p0, p1);
        if (!(mu > 0.0))
            continue;
        double t = p0;
        for (;;) {
            t -= log(1.0 - vr_next(r)) / mu;
            if (!(t < p1))
                break;
            if (++n > VR_MAX_COLLISIONS) {
                if (capped)
                    (*capped)++;
                return;
            }
            double x[3] = { o[0] + t * w[0], o[1] + t * w[1], o[2] + t * w[2] };
            double m = lg_medium_field_at(md->m, x);
            if (ratio) {
                for (int c = 0; c < 3; c++) {
                    double f = md->sigma_t[c] * m / mu;
                    T[c] *= f < 1.0 ? 1.0 - f : 0.0;
                }
                if (T[0] == 0.0 && T[1] == 0.0 && T[2] == 0.0)
                    return;
            } else {
                double u = vr_next(r);
                for (int c = 0; c < 3; c++)
                    if (u < md->sigma_t[c] * m / mu)
                        T[c] = 0.0;
                if (T[0] == 0.0 && T[1] == 0.0 && T[2] == 0.0)
                    return;
            }
        }
    }
}

/* The first scattering event along o + t w, t in [ta, tb], by delta tracking against the
 * piecewise majorant mu with per-channel weights: at each tentative collision x, a real
 * collision with probability P = mean_c sigma_t(x) / mu (then beta *= sigma_s(x) / (mu P):
 * scattering, absorption folded into the weight), else a null one (beta *= (mu -
 * sigma_t(x)) / (mu (1 - P))). Grey media: P = sigma_t(x) / mu, beta *= the albedo at
 * the event, the classic delta tracking. Returns t, or INFINITY when the path leaves
 * [ta, tb] without one (it then ends: a surface absorbs, the sky is empty). */
static inline double vr_free_flight(const vr_medium *md, const double o[3], const double w[3],
                                    double ta, double tb, vr_rng *r, double beta[3],
                                    uint32_t *capped)
{
    if (!(tb > ta))
        return INFINITY;
    double lo[3], hi[3], a = ta, b = tb;
    vr_field_box(md, lo, hi);
    if (md->hetero && !vr_clip_box(o, w, lo, hi, &a, &b))
        return INFINITY;
    int pieces = md->hetero && isfinite(b) ? VR_MAJORANT_PIECES : 1;
    double piece = (b - a) / pieces;
    uint32_t n = 0;
    for (int pc = 0; pc < pieces; pc++) {
        /* (one piece: [a, b] as it is; a + INFINITY x 0 would be NaN) */
        double p0 = pc == 0 ? a : a + piece * pc, p1 = pc + 1 == pieces ? b : p0 + piece;
        double mu = vr_piece_majorant(md, o, w, p0, p1);
        if (!(mu > 0.0) || !isfinite(mu))
            continue;
        double t = p0;
        for (;;) {
            t -= log(1.0 - vr_next(r)) / mu;
            if (!(t < p1))
                break;
            if (++n > VR_MAX_COLLISIONS) {
                if (capped)
                    (*capped)++;
                return INFINITY;
            }
            double x[3] = { o[0] + t * w[0], o[1] + t * w[1], o[2] + t * w[2] };
            double m = vr_density(md, x);
            double st[3], mean = 0.0;
            for (int c = 0; c < 3; c++) {
                st[c] = md->sigma_t[c] * m;
                mean += st[c] / 3.0;
            }
            double P = mean / mu;
            if (vr_next(r) < P) {
                for (int c = 0; c < 3; c++)
                    beta[c] *= md->sigma_s[c] * m / (mu * P);
                return t;
            }
            for (int c = 0; c < 3; c++)
                beta[c] *= (mu - st[c]) / (mu * (1.0 - P));
        }
    }
    return INFINITY;
}

#endif
