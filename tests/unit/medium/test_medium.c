/*
 * tests/unit/medium: lightgraph/medium.h. One command per meson test:
 *
 *   phase     p integrates to 1 over the sphere and its mean cosine is g, for g in
 *             {0, +-0.4, +-0.9, +-0.99, +-0.999} (quadrature on logarithmic grids towards
 *             the peak, so that the sharp lobes are resolved); g = 0 is 1/(4 pi); cos = 1
 *             exactly gives (1 + g)/(4 pi (1 - g)^2); the stable form agrees with long
 *             double at g = 0.9999, cos = 1 - 1e-9 where the textbook form in double
 *             loses digits; the float version within 1e-5 of the double one; g = +-1, NaN
 *             and cos outside [-1, 1] give finite, non-negative values; g > 0 is brighter
 *             towards the light (cos = 1) than away from it
 *   segment   (1 - e^-tau)/tau: 1 at tau = 0, at 1e-30 and at negative or NaN tau; the
 *             float version within 1e-6 relative of the double one (and of expm1) over
 *             tau in [1e-12, 80]; large tau finite and positive
 *   slices    both slicings: t(0) = near, t(depth) = far, strictly increasing, z(t(z)) = z
 *             within 1e-9 for depth 1, 2, 7, 128; uniform_clip is uniform in the NDC
 *             depth of the [near, far] projection; exponential's first slice ends at
 *             near_offset; invalid maps refused
 *   inscatter lg_medium_inscatter equals the integral of L_c sigma_s p e^(-sigma_t s) over
 *             [0, d] (Simpson, 10^5 steps), tends to L_c sigma_s p d as sigma_t -> 0 and is
 *             exact there; a slice sum without transmittance (the thesis's eq. 12) errs by
 *             tau / (1 - e^-tau)
 *   lights    (ABI 3.2) lg_light_window, lg_spot_cone and lg_light_falloff at known points
 *             (the window's 1 - 1/16 at half the range, no window for range 0, negative,
 *             inf or NaN; the cone's t^2; F finite at the light); lg_point_inscatter
 *             against its definition integrated by Simpson in double (64 nodes within 1e-3,
 *             8 within 3e-2: rays through the light; the worst printed), Sun et al.'s closed
 *             form exact at 1 .. 64 nodes (it caught the 8-point rule's second weight,
 *             wrong in the 7th digit), the split A(0, t2) = A(0, t1) + e^(-sigma_t t1) A(t1, t2) that
 *             volumetric_polygonal's signed sum relies on, empty segments, the ray from
 *             the light
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "lightgraph/medium.h"
#include "lightgraph/vecmath.h"

/* integral over c in [-1, 1] of 2 pi c^k p(g, c): substitution s = 1 -+ c on each half,
 * Simpson in log s from 1e-14 to 1, plus the tiny [0, 1e-14] piece as a rectangle */
static double half_integral(double g, int k, double sign)
{
    const int n = 200000; /* even */
    double a = log(1e-14), b = 0.0, h = (b - a) / n, sum = 0.0;
    for (int i = 0; i <= n; i++) {
        double s = exp(a + i * h);
        double c = sign * (1.0 - s);
        double f = 2.0 * LG_PI * (k ? c : 1.0) * lg_hg_phase(g, c) * s; /* ds = s dlog s */
        double w = (i == 0 || i == n) ? 1.0 : (i & 1) ? 4.0 : 2.0;
        sum += w * f;
    }
    double c0 = sign;
    return sum * h / 3.0 + 1e-14 * 2.0 * LG_PI * (k ? c0 : 1.0) * lg_hg_phase(g, c0);
}

static int cmd_phase(void)
{
    const double gs[] = { 0.0, 0.4, -0.4, 0.9, -0.9, 0.99, -0.99, 0.999, -0.999 };
    for (size_t i = 0; i < sizeof gs / sizeof gs[0]; i++) {
        double g = gs[i];
        double norm = half_integral(g, 0, 1.0) + half_integral(g, 0, -1.0);
        double mean = half_integral(g, 1, 1.0) + half_integral(g, 1, -1.0);
        CHECKF(fabs(norm - 1.0) < 1e-6, "g %g: integral %.12f", g, norm);
        CHECKF(fabs(mean - g) < 1e-6, "g %g: mean cosine %.12f", g, mean);
    }
    for (double c = -1.0; c <= 1.0; c += 0.125)
        CHECK(fabs(lg_hg_phase(0.0, c) - 1.0 / (4.0 * LG_PI)) < 1e-17);
    for (size_t i = 0; i < sizeof gs / sizeof gs[0]; i++) {
        double g = gs[i];
        double want = (1.0 + g) / (4.0 * LG_PI * (1.0 - g) * (1.0 - g));
        CHECKF(fabs(lg_hg_phase(g, 1.0) / want - 1.0) < 1e-12, "g %g at cos 1", g);
    }
    {
        long double g = 0.9999, c = 1.0 - 1e-9; /* the doubles, exactly */
        long double den = 1.0L + g * g - 2.0L * g * c;
        long double want = (1.0L - g * g) / (4.0L * (long double)LG_PI * den * sqrtl(den));
        double got = lg_hg_phase((double)g, (double)c);
        CHECKF(fabsl((long double)got / want - 1.0L) < 1e-9L, "stable form %.17g vs %.17Lg", got,
               want);
        CHECK(lg_hg_phase(-0.9999, -1.0 + 1e-9) == lg_hg_phase(0.9999, 1.0 - 1e-9));
    }
    for (size_t i = 0; i < sizeof gs / sizeof gs[0]; i++)
        for (double c = -1.0; c <= 1.0; c += 1.0 / 64.0) {
            float gf = (float)gs[i], cf = (float)c;
            double d = lg_hg_phase(gf, cf);
            float f = lg_hg_phasef(gf, cf);
            CHECKF(fabs(f / d - 1.0) < 1e-5, "float g %g cos %g: %g vs %g", gs[i], c, f, d);
        }
    const double odd[] = { 1.0, -1.0, 2.0, -5.0, NAN, INFINITY };
    for (size_t i = 0; i < sizeof odd / sizeof odd[0]; i++)
        for (double c = -1.5; c <= 1.5; c += 0.25) {
            double p = lg_hg_phase(odd[i], c), q = lg_hg_phase(0.3, odd[i]);
            float pf = lg_hg_phasef((float)odd[i], (float)c);
            CHECKF(isfinite(p) && p >= 0.0 && isfinite(q) && q >= 0.0 && isfinite(pf) && pf >= 0.0f,
                   "g %g cos %g", odd[i], c);
        }
    CHECK(lg_hg_phase(0.4, 1.0) > lg_hg_phase(0.4, -1.0));
    CHECK(lg_hg_phase(-0.4, 1.0) < lg_hg_phase(-0.4, -1.0));
    return check_report("medium_phase");
}

static int cmd_segment(void)
{
    CHECK(lg_medium_segment(0.0) == 1.0);
    CHECK(lg_medium_segment(1e-30) == 1.0);
    CHECK(lg_medium_segment(-1.0) == 1.0);
    CHECK(lg_medium_segment(NAN) == 1.0);
    CHECK(lg_medium_segmentf(0.0f) == 1.0f);
    CHECK(lg_medium_segmentf(1e-30f) == 1.0f);
    CHECK(lg_medium_segmentf(-1.0f) == 1.0f);
    CHECK(lg_medium_segmentf(NAN) == 1.0f);
    for (double lt = -12.0; lt <= log10(80.0); lt += 0.01) {
        double tau = pow(10.0, lt);
        double want = -expm1(-tau) / tau;
        double d = lg_medium_segment(tau);
        float f = lg_medium_segmentf((float)tau);
        double wantf = -expm1(-(double)(float)tau) / (double)(float)tau;
        CHECKF(fabs(d / want - 1.0) < 1e-15, "tau %g", tau);
        CHECKF(fabs(f / wantf - 1.0) < 1e-6, "float tau %g: %.9g vs %.9g", tau, f, wantf);
        CHECK(d > 0.0 && d <= 1.0);
    }
    CHECK(isfinite(lg_medium_segment(1e30)) && lg_medium_segment(1e30) > 0.0);
    CHECK(isfinite(lg_medium_segmentf(1e30f)) && lg_medium_segmentf(1e30f) > 0.0f);
    CHECK(lg_medium_segment(INFINITY) == 0.0);
    return check_report("medium_segment");
}

static int cmd_slices(void)
{
    const uint32_t depths[] = { 1, 2, 7, 128 };
    const lg_froxel_slicing sl[] = { LG_FROXEL_UNIFORM_CLIP, LG_FROXEL_EXPONENTIAL };
    for (int s = 0; s < 2; s++)
        for (int i = 0; i < 4; i++) {
            lg_slice_map m;
            uint32_t D = depths[i];
            CHECK(lg_slice_map_init(&m, sl[s], D, 0.1, 17.6, 0.5) == 0);
            CHECKF(fabs(lg_slice_to_depth(&m, 0.0) / 0.1 - 1.0) < 1e-12, "s %d D %u", s, D);
            CHECKF(fabs(lg_slice_to_depth(&m, D) / 17.6 - 1.0) < 1e-12, "s %d D %u", s, D);
            double prev = -1.0;
            for (int k = 0; k <= 1000; k++) {
                double z = D * k / 1000.0;
                double t = lg_slice_to_depth(&m, z);
                CHECKF(t > prev, "not increasing: s %d D %u z %g", s, D, z);
                prev = t;
                double back = lg_depth_to_slice(&m, t);
                CHECKF(fabs(back - z) < 1e-9 * (D > 1 ? D : 1), "round trip s %d D %u z %g: %g", s,
                       D, z, back);
            }
            if (sl[s] == LG_FROXEL_EXPONENTIAL && D > 1)
                CHECK(fabs(lg_slice_to_depth(&m, 1.0) - 0.5) < 1e-15);
            if (sl[s] == LG_FROXEL_UNIFORM_CLIP) {
                /* NDC depth of a GL projection with near n, far f */
                double n = 0.1, f = 17.6;
                for (int k = 0; k <= (int)D; k++) {
                    double t = lg_slice_to_depth(&m, k);
                    double ndc = (f + n) / (f - n) - 2.0 * f * n / ((f - n) * t);
                    CHECKF(fabs(ndc - (-1.0 + 2.0 * k / D)) < 1e-9, "ndc D %u k %d: %g", D, k, ndc);
                }
            }
        }
    lg_slice_map m;
    CHECK(lg_slice_map_init(&m, LG_FROXEL_UNIFORM_CLIP, 0, 0.1, 10, 0) != 0);
    CHECK(lg_slice_map_init(&m, LG_FROXEL_UNIFORM_CLIP, 4, 0.0, 10, 0) != 0);
    CHECK(lg_slice_map_init(&m, LG_FROXEL_UNIFORM_CLIP, 4, 1.0, 1.0, 0) != 0);
    CHECK(lg_slice_map_init(&m, LG_FROXEL_UNIFORM_CLIP, 4, 1.0, INFINITY, 0) != 0);
    CHECK(lg_slice_map_init(&m, LG_FROXEL_UNIFORM_CLIP, 4, NAN, 10, 0) != 0);
    CHECK(lg_slice_map_init(&m, LG_FROXEL_EXPONENTIAL, 4, 0.1, 10, 0.05) != 0);
    CHECK(lg_slice_map_init(&m, LG_FROXEL_EXPONENTIAL, 4, 0.1, 10, 10) != 0);
    CHECK(lg_slice_map_init(&m, (lg_froxel_slicing)9, 4, 0.1, 10, 1) != 0);
    CHECK(lg_slice_map_init(&m, LG_FROXEL_EXPONENTIAL, 1, 0.1, 10, 0) == 0);
    lg_froxel_info info = { .struct_size = sizeof info,
                            .width = 4,
                            .height = 4,
                            .depth = 8,
                            .slicing = LG_FROXEL_EXPONENTIAL,
                            .near = 0.1f,
                            .far = 20.0f,
                            .near_offset = 1.0f };
    CHECK(lg_slice_map_from_info(&m, &info) == 0 && m.depth == 8);
    return check_report("medium_slices");
}

static int cmd_inscatter(void)
{
    const double lc = 10.0, ss = 0.1, p = lg_hg_phase(0.4, 0.3);
    const double sts[] = { 0.0, 1e-9, 0.1, 0.3, 2.0, 50.0 };
    for (size_t i = 0; i < sizeof sts / sizeof sts[0]; i++) {
        double st = sts[i], d = 7.5;
        int n = 100000;
        double h = d / n, sum = 0.0;
        for (int k = 0; k <= n; k++) {
            double w = (k == 0 || k == n) ? 1.0 : (k & 1) ? 4.0 : 2.0;
            sum += w * exp(-st * k * h);
        }
        double want = lc * ss * p * sum * h / 3.0;
        double got = lg_medium_inscatter(lc, ss, st, p, d);
        CHECKF(fabs(got / want - 1.0) < 1e-9, "sigma_t %g: %.12g vs %.12g", st, got, want);
    }
    CHECK(lg_medium_inscatter(lc, ss, 0.0, p, 3.0) == lc * ss * p * 3.0);
    CHECK(lg_medium_inscatter(lc, ss, 0.5, p, 0.0) == 0.0);
    /* the thesis's per-slice sum against the exact slice integral */
    for (double tau = 1e-6; tau < 20.0; tau *= 3.0) {
        double exact = lg_medium_inscatter(1.0, 1.0, tau, 1.0, 1.0);
        CHECKF(fabs(1.0 / exact / (tau / -expm1(-tau)) - 1.0) < 1e-12, "tau %g", tau);
    }
    lg_medium m = { .present = true,
                    .density = 2.0f,
                    .scattering = { 0.1f, 0.2f, 0.3f },
                    .absorption = { 0.05f, 0.0f, 1.0f },
                    .g = 0.4f };
    float s[3], t[3];
    lg_medium_coeffs(&m, s, t);
    CHECK(s[0] == 0.2f && s[1] == 0.4f && s[2] == 0.6f);
    CHECK(fabsf(t[0] - 0.3f) < 1e-7f && t[1] == 0.4f && fabsf(t[2] - 2.6f) < 1e-6f);
    m.density = 0.0f;
    lg_medium_coeffs(&m, s, t);
    CHECK(s[0] == 0.0f && t[2] == 0.0f);
    lg_light l = { .color = { 1.0f, 0.5f, 0.25f }, .intensity = 10.0f };
    float c[3];
    lg_light_color(&l, c);
    CHECK(c[0] == 10.0f && c[1] == 5.0f && c[2] == 2.5f);
    return check_report("medium_inscatter");
}

/* ---- point and spot lights (ABI 3.2) --------------------------------------------------------- */

/* The airlight integral's definition (lightgraph/medium.h), integrated in t by Simpson's
 * rule on a grid refined towards the light's closest point: n steps on each side of t_c
 * clipped to [t0, t1], in the variable u = asinh((t - t_c) / s) (s the ray's distance from
 * the light plus 1e-3: dense where the integrand peaks). */
static double airlight_brute(const double o[3], const double w[3], double t0, double t1,
                             const double q[3], double range, const double *spot, double g,
                             double sigma_t)
{
    double qo[3], tc = 0.0, qq = 0.0;
    for (int c = 0; c < 3; c++) {
        qo[c] = q[c] - o[c];
        tc += qo[c] * w[c];
        qq += qo[c] * qo[c];
    }
    double s = sqrt(fmax(qq - tc * tc, 0.0)) + 1e-3;
    double u0 = asinh((t0 - tc) / s), u1 = asinh((t1 - tc) / s);
    const int n = 40000; /* even */
    double h = (u1 - u0) / n, sum = 0.0;
    for (int k = 0; k <= n; k++) {
        double u = u0 + k * h, t = tc + s * sinh(u), dt = s * cosh(u);
        double p[3], l[3], d2 = 0.0;
        for (int c = 0; c < 3; c++) {
            p[c] = o[c] + t * w[c];
            l[c] = q[c] - p[c];
            d2 += l[c] * l[c];
        }
        double d = sqrt(d2);
        if (!(d > 0.0))
            continue; /* the light itself: a point of measure 0 (its direction undefined) */
        double cw = (l[0] * w[0] + l[1] * w[1] + l[2] * w[2]) / d;
        double f = lg_hg_phase(g, cw) * lg_light_window(d, range) /
                   (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
        if (spot)
            f *= lg_spot_cone(-(l[0] * spot[0] + l[1] * spot[1] + l[2] * spot[2]) / d, spot[3],
                              spot[4]);
        f *= exp(-sigma_t * ((t - t0) + d));
        double wt = (k == 0 || k == n) ? 1.0 : (k & 1) ? 4.0 : 2.0;
        sum += wt * f * dt;
    }
    return sum * h / 3.0;
}

/* The airlight's quadrature against its definition: the integrand in the angle is smooth
 * on the clipped segment but where the ray passes within ~LG_LIGHT_EPSILON of the light
 * (the phase's cosine and d turn there: a kink inside the segment unless it starts at the
 * light) and at the inner cone's edge (t^2's derivative jumps): measured worst 5.5e-4 at
 * 64 nodes and 1.8e-2 at 8, both on rays through the light. The split identity at 64
 * nodes: the inner cone's kink, measured 5e-5. */
#define AIR64_TOL 1e-3
#define AIR8_TOL 3e-2
#define SPLIT_TOL 1e-4

static int cmd_lights(void)
{
    /* the range window: 1 at the light, 1 - 1/16 at half the range, 0 from the range on;
     * range 0, negative, infinite or NaN: no window */
    CHECK(lg_light_window(0.0, 2.0) == 1.0);
    CHECK(fabs(lg_light_window(1.0, 2.0) - (1.0 - 1.0 / 16.0)) < 1e-15);
    CHECK(lg_light_window(2.0, 2.0) == 0.0 && lg_light_window(7.0, 2.0) == 0.0);
    CHECK(lg_light_window(1e9, 0.0) == 1.0 && lg_light_window(3.0, -1.0) == 1.0);
    CHECK(lg_light_window(3.0, INFINITY) == 1.0 && lg_light_window(3.0, NAN) == 1.0);
    /* the cone: 1 inside the inner angle, 0 beyond the outer, t^2 between; a reversed pair
     * is a hard edge at the outer */
    double ci = cos(0.2), co = cos(0.4);
    CHECK(lg_spot_cone(1.0, ci, co) == 1.0 && lg_spot_cone(ci, ci, co) == 1.0);
    CHECK(lg_spot_cone(co, ci, co) == 0.0 && lg_spot_cone(-1.0, ci, co) == 0.0);
    CHECKF(fabs(lg_spot_cone(0.5 * (ci + co), ci, co) - 0.25) < 1e-12, "half way: %.17g",
           lg_spot_cone(0.5 * (ci + co), ci, co));
    CHECK(lg_spot_cone(ci + 1e-3, co, ci) == 1.0 && lg_spot_cone(ci - 1e-3, co, ci) == 0.0);
    /* F of each type */
    lg_light dl = { .type = LG_LIGHT_DIRECTIONAL, .direction = { 0.0f, -2.0f, 0.0f } };
    double p[3] = { 1, 2, 3 }, tl[3], dist;
    CHECK(lg_light_falloff(&dl, p, tl, &dist) == 1.0 && isinf(dist));
    CHECK(tl[0] == 0.0 && tl[1] == 1.0 && tl[2] == 0.0);
    lg_light pl = { .type = LG_LIGHT_POINT, .position = { 1, 2, 5 } };
    double f = lg_light_falloff(&pl, p, tl, &dist);
    CHECKF(fabs(f * (4.0 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON) - 1.0) < 1e-15 && dist == 2.0 &&
               tl[2] == 1.0,
           "point: %.17g at %g", f, dist);
    /* at the light: finite, 1 / eps^2, towards the light = the (default) axis reversed */
    f = lg_light_falloff(&pl, (double[3]){ 1, 2, 5 }, tl, &dist);
    CHECKF(isfinite(f) && fabs(f * LG_LIGHT_EPSILON * LG_LIGHT_EPSILON - 1.0) < 1e-12 &&
               dist == 0.0 && tl[1] == 1.0,
           "at the light: %g", f);
    pl.range = 4.0f;
    f = lg_light_falloff(&pl, p, NULL, NULL);
    CHECK(fabs(f * (4.0 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON) - (1.0 - 1.0 / 16.0)) < 1e-12);
    lg_light sl = { .type = LG_LIGHT_SPOT,
                    .position = { 0, 3, 0 },
                    .direction = { 0, -1, 0 },
                    .inner_cone = 0.2f,
                    .outer_cone = 0.4f };
    double below[3] = { 0, 1, 0 }, side[3] = { 2, 3, 0 };
    f = lg_light_falloff(&sl, below, NULL, NULL);
    CHECK(fabs(f * (4.0 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON) - 1.0) < 1e-12);
    CHECK(lg_light_falloff(&sl, side, NULL, NULL) == 0.0);

    /* the airlight integral against its definition, on rays passing the light at h = 1,
     * 0.1, 1e-3 and through it, segments before, across and after it, g in {0, 0.6, -0.3},
     * sigma_t in {0, 0.2, 2}, range 0 or 3, point and spot: 64 nodes and 8 nodes (the
     * shaders' rule) within AIR64_TOL and AIR8_TOL relative (the worst printed) */
    const double o[3] = { 0, 0, 0 }, w[3] = { 0, 0, 1 };
    const double hs[] = { 1.0, 0.1, 1e-3, 0.0 };
    const double segs[][2] = { { 0.0, 1.5 }, { 0.0, 6.0 }, { 2.5, 3.5 }, { 3.2, 9.0 } };
    const double gs[] = { 0.0, 0.6, -0.3 }, sts[] = { 0.0, 0.2, 2.0 }, ranges[] = { 0.0, 3.0 };
    /* the spot at (h, 0, 3) leans back over the ray: its cone holds the ray beyond t ~ 3 */
    double spot[5] = { -0.3, 0.0, sqrt(0.91), cos(0.3), cos(0.6) };
    double worst64 = 0.0, worst8 = 0.0;
    for (size_t ih = 0; ih < 4; ih++)
        for (size_t is = 0; is < 4; is++)
            for (size_t ig = 0; ig < 3; ig++)
                for (size_t it = 0; it < 3; it++)
                    for (size_t ir = 0; ir < 2; ir++)
                        for (int sp = 0; sp < 2; sp++) {
                            if ((ig + it + ir + (size_t)sp) % 2)
                                continue; /* half the grid: enough, and fast */
                            double q[3] = { hs[ih], 0.0, 3.0 };
                            const double *spp = sp ? spot : NULL;
                            double t0 = segs[is][0], t1 = segs[is][1];
                            double want = airlight_brute(o, w, t0, t1, q, ranges[ir], spp, gs[ig],
                                                         sts[it]);
                            double a64 = lg_point_inscatter(o, w, t0, t1, q, ranges[ir], spp,
                                                            gs[ig], sts[it], 64);
                            double a8 = lg_point_inscatter(o, w, t0, t1, q, ranges[ir], spp, gs[ig],
                                                           sts[it], 8);
                            double scale = fmax(fabs(want), 1e-12);
                            double e64 = fabs(a64 - want) / scale, e8 = fabs(a8 - want) / scale;
                            CHECKF(e64 < AIR64_TOL,
                                   "h %g, [%g, %g], g %g, sigma_t %g, range %g, spot %d: 64 "
                                   "nodes %.12g, definition %.12g",
                                   hs[ih], t0, t1, gs[ig], sts[it], ranges[ir], sp, a64, want);
                            CHECKF(e8 < AIR8_TOL,
                                   "h %g, [%g, %g], g %g, sigma_t %g, range %g, spot %d: 8 "
                                   "nodes %.12g, definition %.12g",
                                   hs[ih], t0, t1, gs[ig], sts[it], ranges[ir], sp, a8, want);
                            worst64 = fmax(worst64, e64);
                            worst8 = fmax(worst8, e8);
                        }
    printf("airlight against its definition: worst relative error 64 nodes %.2g, 8 nodes "
           "%.2g\n",
           worst64, worst8);
    /* Sun et al.'s closed form (g = 0, sigma_t = 0, no range, a point light): exact at any
     * node count */
    for (size_t ih = 0; ih < 4; ih++) {
        double q[3] = { hs[ih], 0.0, 3.0 };
        double H = sqrt(hs[ih] * hs[ih] + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
        double want = (atan((6.0 - 3.0) / H) - atan((0.0 - 3.0) / H)) / (4.0 * LG_PI * H);
        for (int nodes = 1; nodes <= 64; nodes *= 2) {
            double a = lg_point_inscatter(o, w, 0.0, 6.0, q, 0.0, NULL, 0.0, 0.0, nodes);
            CHECKF(fabs(a / want - 1.0) < 1e-12, "closed form, h %g, %d nodes: %.17g vs %.17g",
                   hs[ih], nodes, a, want);
        }
    }
    /* what volumetric_polygonal's signed sum relies on: A from the eye splits at any t,
     * A(0, t2) = A(0, t1) + e^(-sigma_t t1) A(t1, t2) */
    double q[3] = { 0.3, 0.1, 2.0 };
    double along[5] = { 0.0, 0.0, 1.0, cos(0.5), cos(1.2) };
    for (size_t it = 0; it < 3; it++)
        for (int sp = 0; sp < 2; sp++) {
            const double *spp = sp ? along : NULL;
            double a02 = lg_point_inscatter(o, w, 0.0, 5.0, q, 0.0, spp, 0.5, sts[it], 64);
            double a01 = lg_point_inscatter(o, w, 0.0, 2.3, q, 0.0, spp, 0.5, sts[it], 64);
            double a12 = lg_point_inscatter(o, w, 2.3, 5.0, q, 0.0, spp, 0.5, sts[it], 64);
            CHECKF(a01 > 0.0 && a12 > 0.0 &&
                       fabs((a01 + exp(-sts[it] * 2.3) * a12) / a02 - 1.0) < SPLIT_TOL,
                   "sigma_t %g, spot %d: %.12g + %.12g vs %.12g", sts[it], sp, a01, a12, a02);
        }
    /* empty and reversed segments; the camera at the light: large and finite */
    CHECK(lg_point_inscatter(o, w, 2.0, 2.0, q, 0.0, NULL, 0.0, 0.1, 8) == 0.0);
    CHECK(lg_point_inscatter(o, w, 3.0, 2.0, q, 0.0, NULL, 0.0, 0.1, 8) == 0.0);
    double at = lg_point_inscatter(o, w, 0.0, 4.0, o, 0.0, NULL, 0.3, 0.1, 8);
    CHECKF(isfinite(at) && at > 1.0 / (4.0 * LG_PI * LG_LIGHT_EPSILON) * 0.5 * 0.5,
           "the ray from the light: %g", at);
    /* node counts out of range are clamped, not refused */
    CHECK(isfinite(lg_point_inscatter(o, w, 0.0, 4.0, q, 0.0, NULL, 0.3, 0.1, 0)));
    CHECK(lg_point_inscatter(o, w, 0.0, 4.0, q, 0.0, NULL, 0.3, 0.1, 1000) ==
          lg_point_inscatter(o, w, 0.0, 4.0, q, 0.0, NULL, 0.3, 0.1, 64));
    return check_report("medium_lights");
}

int main(int argc, char **argv)
{
    const char *c = argc > 1 ? argv[1] : "";
    if (!strcmp(c, "phase"))
        return cmd_phase();
    if (!strcmp(c, "segment"))
        return cmd_segment();
    if (!strcmp(c, "slices"))
        return cmd_slices();
    if (!strcmp(c, "inscatter"))
        return cmd_inscatter();
    if (!strcmp(c, "lights"))
        return cmd_lights();
    fprintf(stderr, "usage: test_medium phase|segment|slices|inscatter|lights\n");
    return 2;
}
