/*
 * The estimators of volumetric_reference (plugins/volumetric_reference/vr_estimators.h)
 * against their distributions and closed forms, in process (no render). Every bound is a
 * multiple of the estimator's own standard error (stated per case), so a correct estimator
 * fails with probability below about 1e-4 per check and the random numbers are fixed
 * (counter-based): the outcome is the same on every run.
 *
 *   hg_sample      histogram of vr_hg_sample_cos (2e5 draws, 20 bins in cos) against the
 *                  integral of lg_hg_phase over each bin (Simpson), for g = 0, 0.5, -0.7,
 *                  0.9: chi-square below 60 (19 degrees of freedom: p < 1e-5); the mean
 *                  cosine equals g within 5 standard errors; sampled directions are unit
 *                  and at that cosine from the axis
 *   equiangular    1 / pdf times 1 / (d^2 + eps^2) is the constant (xi1 - xi0) / H
 *                  (= 4 pi lg_point_inscatter at g = 0, sigma_t = 0) within 1e-6; the
 *                  estimate of integral e^(-0.3 t) / (d^2 + eps^2) dt by 4096 stratified
 *                  samples matches a 20000-panel Simpson sum within 1e-4 relative; a ray
 *                  through the light (h = 0) and from the light (t_c = 0) stay finite
 *   uniform        a uniform field (kind UNIFORM, no height, unbounded): ratio and delta
 *                  tracking's mean over 20000 estimates of e^(-sigma_t L) per channel
 *                  (sigma_t 0.3, 0.7, 1.1; L 1.7) within 5 standard errors
 *   box            a box of fog [-1, 1]^3 crossed obliquely: e^(-sigma_t chord) (the slab
 *                  test's chord) within 5 standard errors, and 1 exactly for a ray that
 *                  misses it
 *   height         height fog (falloff k 1.5, base 0.5) along vertical rays up and down:
 *                  tau = sigma_t / k |e^(-k (y0 - b)) - e^(-k (y1 - b))|, within 5 standard
 *                  errors
 *   sqrt_n         unbiasedness: for the height fog, the RMS error over 64 batch means of N
 *                  ratio-tracking estimates falls as 1/sqrt(N): RMS(N=64) / RMS(N=1024) in
 *                  [2.6, 6.2] (4 expected; the RMS of 64 batches is within about +-9%, the
 *                  ratio +-13%: 3 standard deviations), and the mean of all 64 x 1024 is
 *                  within 5 standard errors
 *   free_flight    E[beta_c 1(a scattering event before L)] = albedo_c (1 - T_c(L)) for a
 *                  constant albedo, per channel, homogeneous grey, chromatic, and in the
 *                  height fog (the weights of spectral tracking), within 5 standard errors
 *   free_flight_unbounded  an infinite homogeneous segment: every path scatters,
 *                  E[beta; event] = the albedo (within 5 standard errors)
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "lightgraph/medium.h"
#include "lightgraph/test.h"

#include "vr_estimators.h"

/* mean and standard error of n samples with sums s1, s2 */
static double std_err(double s1, double s2, double n)
{
    double m = s1 / n, var = s2 / n - m * m;
    return sqrt(fmax(var, 0.0) / n);
}

static void case_hg_sample(lg_test *t)
{
    static const double gs[] = { 0.0, 0.5, -0.7, 0.9 };
    enum { NB = 20, N = 200000 };
    for (size_t gi = 0; gi < sizeof gs / sizeof gs[0]; gi++) {
        double g = gs[gi];
        double hist[NB] = { 0 }, s1 = 0, s2 = 0;
        vr_rng r = vr_rng_make(1234 + gi);
        double axis[3] = { 0.36, -0.48, 0.8 }, worst_dir = 0;
        for (int i = 0; i < N; i++) {
            double c = vr_hg_sample_cos(g, vr_next(&r));
            int b = (int)((c + 1.0) * 0.5 * NB);
            hist[b < 0 ? 0 : b >= NB ? NB - 1 : b] += 1;
            s1 += c;
            s2 += c * c;
            if (i < 1000) {
                double d[3];
                vr_hg_sample_dir(axis, c, vr_next(&r), d);
                double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
                double dc = d[0] * axis[0] + d[1] * axis[1] + d[2] * axis[2];
                worst_dir = fmax(worst_dir, fmax(fabs(len - 1.0), fabs(dc - c)));
            }
        }
        double chi2 = 0;
        for (int b = 0; b < NB; b++) {
            /* the bin's probability: 2 pi integral of p_HG over its cosines (Simpson) */
            double a = -1.0 + 2.0 * b / NB, h = 2.0 / NB / 200, p = 0;
            for (int k = 0; k <= 200; k++) {
                double wk = k == 0 || k == 200 ? 1 : k % 2 ? 4 : 2;
                p += wk * lg_hg_phase(g, a + k * h);
            }
            p *= 2.0 * LG_PI * h / 3.0;
            double e = p * N;
            chi2 += (hist[b] - e) * (hist[b] - e) / e;
        }
        double mean = s1 / N, se = std_err(s1, s2, N);
        LG_TEST_CHECK(t, chi2 < 60.0, "g = %g: chi-square %.1f over %d bins", g, chi2, NB);
        LG_TEST_CHECK(t, fabs(mean - g) < 5 * se, "g = %g: mean cosine %.5f (se %.2g)", g, mean,
                      se);
        LG_TEST_CHECK(t, worst_dir < 1e-12, "g = %g: directions off by %.2g", g, worst_dir);
        lg_test_note_("hg_sample g = %4.1f: chi-square %.1f (19 dof), mean cos %.4f +- %.4f\n", g,
                      chi2, mean, se);
    }
}

static void case_equiangular(lg_test *t)
{
    const double o[3] = { 0, 0, 5 }, w[3] = { 0.6, 0, -0.8 }, q[3] = { 0.3, 0.4, 2.5 };
    vr_equi e;
    vr_equi_init(&e, o, w, q, 0.5, 7.0);
    double want = 4.0 * LG_PI * lg_point_inscatter(o, w, 0.5, 7.0, q, 0.0, NULL, 0.0, 0.0, 8);
    double worst = 0, sum = 0;
    vr_rng r = vr_rng_make(9);
    enum { N = 4096 };
    for (int i = 0; i < N; i++) {
        double ip;
        double tt = vr_equi_sample(&e, (i + vr_next(&r)) / N, &ip);
        double d2 = 0;
        for (int c = 0; c < 3; c++)
            d2 += (o[c] + tt * w[c] - q[c]) * (o[c] + tt * w[c] - q[c]);
        double f = 1.0 / (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
        worst = fmax(worst, fabs(f * ip - want) / want);
        sum += exp(-0.3 * tt) * f * ip;
    }
    /* 1e-6: the rounding of h^2 = |q - o|^2 - t_c^2 (a cancellation), not the sampling */
    LG_TEST_CHECK(t, worst < 1e-6, "f / pdf varies: %.2g relative", worst);
    double simpson = 0, h = 6.5 / 20000;
    for (int k = 0; k <= 20000; k++) {
        double tt = 0.5 + k * h, d2 = 0;
        for (int c = 0; c < 3; c++)
            d2 += (o[c] + tt * w[c] - q[c]) * (o[c] + tt * w[c] - q[c]);
        double wk = k == 0 || k == 20000 ? 1 : k % 2 ? 4 : 2;
        simpson += wk * exp(-0.3 * tt) / (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
    }
    simpson *= h / 3.0;
    double est = sum / N;
    LG_TEST_CHECK(t, fabs(est - simpson) / simpson < 1e-4, "estimate %.9g, Simpson %.9g", est,
                  simpson);
    lg_test_note_("equiangular: f/pdf constant within %.2g; e^(-0.3t) integral %.9g vs %.9g\n",
                  worst, est, simpson);
    /* a ray through the light, and a ray starting at it: finite */
    const double q2[3] = { 0.6 * 2.0, 0, 5 - 0.8 * 2.0 };
    const double *qs[2] = { q2, o };
    for (int k = 0; k < 2; k++) {
        vr_equi_init(&e, o, w, qs[k], 0.0, 7.0);
        double s = 0;
        for (int i = 0; i < 64; i++) {
            double ip;
            double tt = vr_equi_sample(&e, (i + 0.5) / 64, &ip);
            s += ip / (LG_LIGHT_EPSILON * LG_LIGHT_EPSILON + (tt - e.tc) * (tt - e.tc));
        }
        LG_TEST_CHECK(t, isfinite(s) && s > 0, "light %s the ray: %g", k ? "at the start of" : "on",
                      s);
    }
}

/* Mean and standard error of n transmittance estimates along (o, w, len). */
static void t_mean(const vr_medium *md, const double o[3], const double w[3], double len,
                   bool ratio, int n, uint64_t seed, double mean[3], double se[3])
{
    double s1[3] = { 0 }, s2[3] = { 0 };
    vr_rng r = vr_rng_make(seed);
    for (int i = 0; i < n; i++) {
        double T[3];
        vr_transmittance(md, o, w, len, ratio, &r, T, NULL);
        for (int c = 0; c < 3; c++) {
            s1[c] += T[c];
            s2[c] += T[c] * T[c];
        }
    }
    for (int c = 0; c < 3; c++) {
        mean[c] = s1[c] / n;
        se[c] = std_err(s1[c], s2[c], n);
    }
}

static void field_medium(lg_medium *m, lg_density_field *f, vr_medium *md, const float st[3])
{
    memset(m, 0, sizeof *m);
    m->present = true;
    m->density = 1.0f;
    m->field = f;
    float ss[3] = { 0.8f * st[0], 0.8f * st[1], 0.8f * st[2] };
    vr_medium_make(md, m, ss, st);
}

static void unbounded(lg_density_field *f)
{
    memset(f, 0, sizeof *f);
    f->kind = LG_FIELD_UNIFORM;
    for (int c = 0; c < 3; c++) {
        f->bounds_min[c] = -FLT_MAX;
        f->bounds_max[c] = FLT_MAX;
    }
}

/* Checks the mean of ratio and delta tracking against want[c] = e^(-tau[c]). */
static void check_T(lg_test *t, const char *what, const vr_medium *md, const double o[3],
                    const double w[3], double len, const double tau[3])
{
    for (int ratio = 0; ratio < 2; ratio++) {
        double mean[3], se[3];
        t_mean(md, o, w, len, ratio, 20000, 77 + ratio, mean, se);
        for (int c = 0; c < 3; c++) {
            double want = exp(-tau[c]);
            LG_TEST_CHECK(t, fabs(mean[c] - want) <= 5 * se[c] + 1e-12,
                          "%s, %s tracking, channel %d: %.5f, want %.5f (se %.2g)", what,
                          ratio ? "ratio" : "delta", c, mean[c], want, se[c]);
        }
        lg_test_note_("%s %s: T = %.4f %.4f %.4f (want %.4f %.4f %.4f, se %.1e)\n", what,
                      ratio ? "ratio" : "delta", mean[0], mean[1], mean[2], exp(-tau[0]),
                      exp(-tau[1]), exp(-tau[2]), se[1]);
    }
}

static const float ST[3] = { 0.3f, 0.7f, 1.1f };

static void case_uniform(lg_test *t)
{
    lg_density_field f;
    lg_medium m;
    vr_medium md;
    unbounded(&f);
    field_medium(&m, &f, &md, ST);
    const double o[3] = { 0.1, 0.2, 0.3 }, w[3] = { 0, 0.6, 0.8 };
    double tau[3];
    for (int c = 0; c < 3; c++)
        tau[c] = ST[c] * 1.7;
    check_T(t, "uniform", &md, o, w, 1.7, tau);
}

static void case_box(lg_test *t)
{
    lg_density_field f;
    lg_medium m;
    vr_medium md;
    unbounded(&f);
    for (int c = 0; c < 3; c++) {
        f.bounds_min[c] = -1.0f;
        f.bounds_max[c] = 1.0f;
    }
    field_medium(&m, &f, &md, ST);
    double w[3] = { 1.0, 0.1, 0.05 }, l = sqrt(1.0 + 0.01 + 0.0025);
    for (int c = 0; c < 3; c++)
        w[c] /= l;
    const double o[3] = { -3, 0.2, 0.1 };
    /* the chord: enters at x = -1, leaves at x = 1 (|y|, |z| stay below 1 on the way) */
    double chord = 2.0 / w[0], tau[3];
    for (int c = 0; c < 3; c++)
        tau[c] = ST[c] * chord;
    check_T(t, "box chord", &md, o, w, 10.0, tau);
    /* a ray that misses the box: exactly 1 */
    const double o2[3] = { -3, 1.5, 0 };
    double T[3];
    vr_rng r = vr_rng_make(3);
    vr_transmittance(&md, o2, w, 10.0, true, &r, T, NULL);
    LG_TEST_CHECK(t, T[0] == 1.0 && T[1] == 1.0 && T[2] == 1.0, "a miss: %g %g %g", T[0], T[1],
                  T[2]);
}

static void height_field(lg_density_field *f)
{
    unbounded(f);
    f->height_falloff = 1.5f;
    f->height_base = 0.5f;
}

/* tau of the height fog between y0 and y1 (vertical), per unit sigma_t */
static double height_tau(double y0, double y1)
{
    const double k = 1.5, b = 0.5;
    return fabs(exp(-k * (y0 - b)) - exp(-k * (y1 - b))) / k;
}

static void case_height(lg_test *t)
{
    lg_density_field f;
    lg_medium m;
    vr_medium md;
    height_field(&f);
    field_medium(&m, &f, &md, ST);
    const double up[3] = { 0, 1, 0 }, down[3] = { 0, -1, 0 };
    const double o1[3] = { 0.3, -0.5, 0.2 }, o2[3] = { 0.3, 2.0, 0.2 };
    double tau[3];
    for (int c = 0; c < 3; c++)
        tau[c] = ST[c] * height_tau(-0.5, 2.0);
    check_T(t, "height up", &md, o1, up, 2.5, tau);
    check_T(t, "height down", &md, o2, down, 2.5, tau);
}

static void case_sqrt_n(lg_test *t)
{
    lg_density_field f;
    lg_medium m;
    vr_medium md;
    height_field(&f);
    field_medium(&m, &f, &md, ST);
    const double o[3] = { 0.3, -0.5, 0.2 }, up[3] = { 0, 1, 0 };
    double want = exp(-ST[1] * height_tau(-0.5, 2.0));
    const int ns[2] = { 64, 1024 };
    double rms[2], all = 0, all2 = 0;
    for (int k = 0; k < 2; k++) {
        double e2 = 0;
        for (int b = 0; b < 64; b++) {
            double mean[3], se[3];
            t_mean(&md, o, up, 2.5, true, ns[k], 1000 * (k + 1) + b, mean, se);
            e2 += (mean[1] - want) * (mean[1] - want);
            if (k == 1) {
                all += mean[1];
                all2 += mean[1] * mean[1];
            }
        }
        rms[k] = sqrt(e2 / 64);
    }
    double ratio = rms[0] / rms[1];
    LG_TEST_CHECK(t, ratio > 2.6 && ratio < 6.2,
                  "RMS error %.3g at N = 64, %.3g at 1024: ratio %.2f", rms[0], rms[1], ratio);
    double mean = all / 64, se = std_err(all, all2, 64);
    LG_TEST_CHECK(t, fabs(mean - want) < 5 * se,
                  "mean of 65536 estimates %.6f, want %.6f (se %.2g)", mean, want, se);
    lg_test_note_("sqrt_n: RMS error %.3g (N = 64), %.3g (N = 1024), ratio %.2f (4 expected); "
                  "mean %.6f vs %.6f\n",
                  rms[0], rms[1], ratio, mean, want);
}

static void case_free_flight(lg_test *t)
{
    lg_density_field f;
    lg_medium m, hm = { 0 };
    vr_medium md[3];
    static const float grey[3] = { 0.9f, 0.9f, 0.9f };
    hm.present = true;
    float ss[3] = { 0.8f * grey[0], 0.8f * grey[1], 0.8f * grey[2] };
    vr_medium_make(&md[0], &hm, ss, grey);
    float ss2[3] = { 0.8f * ST[0], 0.8f * ST[1], 0.8f * ST[2] };
    vr_medium_make(&md[1], &hm, ss2, ST);
    height_field(&f);
    field_medium(&m, &f, &md[2], ST);
    static const char *const names[3] = { "homogeneous grey", "homogeneous chromatic",
                                          "height fog" };
    const double o[3] = { 0.3, -0.5, 0.2 }, up[3] = { 0, 1, 0 };
    const double L = 2.5;
    for (int k = 0; k < 3; k++) {
        double s1[3] = { 0 }, s2[3] = { 0 };
        vr_rng r = vr_rng_make(500 + k);
        enum { N = 40000 };
        for (int i = 0; i < N; i++) {
            double beta[3] = { 1, 1, 1 };
            double tt = vr_free_flight(&md[k], o, up, 0.0, L, &r, beta, NULL);
            for (int c = 0; c < 3; c++) {
                double v = isfinite(tt) ? beta[c] : 0.0;
                s1[c] += v;
                s2[c] += v * v;
            }
        }
        for (int c = 0; c < 3; c++) {
            double tau = md[k].sigma_t[c] * (k == 2 ? height_tau(-0.5, 2.0) : L);
            double want = 0.8 * (1.0 - exp(-tau));
            double mean = s1[c] / N, se = std_err(s1[c], s2[c], N);
            LG_TEST_CHECK(t, fabs(mean - want) < 5 * se + 1e-12,
                          "%s channel %d: E[beta; event] %.5f, want %.5f (se %.2g)", names[k], c,
                          mean, want, se);
            if (c == 2)
                lg_test_note_("free_flight %s: %.5f, want %.5f (se %.1e)\n", names[k], mean, want,
                              se);
        }
    }
}

/* An unbounded homogeneous segment (a path leaving through an opening: no surface ahead):
 * every path scatters somewhere, E[beta; event] = the albedo. Caught a NaN: a + INFINITY x 0
 * as the first piece's start made every such free flight escape. */
static void case_free_flight_unbounded(lg_test *t)
{
    lg_medium hm = { 0 };
    vr_medium md;
    static const float grey[3] = { 0.9f, 0.9f, 0.9f };
    const float ss[3] = { 0.8f * grey[0], 0.8f * grey[1], 0.8f * grey[2] };
    hm.present = true;
    vr_medium_make(&md, &hm, ss, grey);
    const double o[3] = { 0, 0, 0 }, w[3] = { 0, 0, 1 };
    double s1 = 0, s2 = 0;
    vr_rng r = vr_rng_make(77);
    enum { N = 20000 };
    for (int i = 0; i < N; i++) {
        double beta[3] = { 1, 1, 1 };
        double tt = vr_free_flight(&md, o, w, 0.0, INFINITY, &r, beta, NULL);
        double v = isfinite(tt) ? beta[1] : 0.0;
        s1 += v;
        s2 += v * v;
    }
    double mean = s1 / N, se = std_err(s1, s2, N);
    LG_TEST_CHECK(t, fabs(mean - 0.8) < 5 * se + 1e-6, "unbounded: E[beta; event] %.5f, want 0.8",
                  mean);
    lg_test_note_("free_flight unbounded: %.5f, want 0.8\n", mean);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "hg_sample", case_hg_sample },
        { "equiangular", case_equiangular },
        { "uniform", case_uniform },
        { "box", case_box },
        { "height", case_height },
        { "sqrt_n", case_sqrt_n },
        { "free_flight", case_free_flight },
        { "free_flight_unbounded", case_free_flight_unbounded },
    };
    lg_test_main_opts o = { .prefix = "vr_estimators" };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
