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
    fprintf(stderr, "usage: test_medium phase|segment|slices|inscatter\n");
    return 2;
}
