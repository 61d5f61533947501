/*
 * The reinhard plugin's CPU code alone. The double-precision oracle
 * (reinhard_oracle.c) against closed forms of the log-average, the curve, the white
 * point, adaptation and the bad-pixel policy; then the plugin's fast float passes
 * (plugins/reinhard/reinhard_cpu.c) against the oracle, its logarithm against libm's, and
 * its threaded passes for bit-identical results with pools of 1, 2 and 7 threads
 * (host/base/pool.c, the pool behind lg_parallel_for) and for rgba16f input. test_reinhard.c
 * then checks every backend through the host.
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>

#include "common/check.h"
#include "reinhard_cpu.h"
#include "reinhard_oracle.h"
#include "base/pool.h"

#include "lightgraph/image.h"

static lg_rh_params params(lg_rh_mode mode, double white, double delta)
{
    lg_rh_params p = {
        .mode = mode, .w = { 0.2126f, 0.7152f, 0.0722f }, .delta = delta, .white = white
    };
    return p;
}

static double scale_of(const float *px, size_t n, const lg_rh_params *p, double key,
                       lg_rh_stats *st)
{
    memset(st, 0, sizeof *st);
    lg_rh_ref_reduce(px, n, p, st);
    double lavg = 0;
    if (!lg_rh_log_average(st, &lavg))
        return NAN;
    return key / lavg;
}

/* A constant image: Lavg = delta + L, every pixel maps to m / (1 + m) with m = a L / (L +
 * delta) (a / (1 + a) when delta << L), in both modes for a grey pixel. */
static void test_constant(void)
{
    const double key = 0.18, delta = 1e-4;
    float px[4 * 6];
    for (int i = 0; i < 6; i++) {
        px[i * 4 + 0] = px[i * 4 + 1] = px[i * 4 + 2] = 2.5f;
        px[i * 4 + 3] = 0.25f;
    }
    for (int mode = 0; mode < 2; mode++) {
        lg_rh_params p = params((lg_rh_mode)mode, 0, delta);
        lg_rh_stats st;
        double s = scale_of(px, 6, &p, key, &st);
        float l = 0.2126f * 2.5f + 0.7152f * 2.5f + 0.0722f * 2.5f;
        CHECKF(fabs(s - key / (delta + l)) < 1e-12, "scale %.17g", s);
        float out[4 * 6];
        lg_rh_ref_map(px, out, 6, s, &p);
        double m = key * 2.5 / (2.5 + delta);
        for (int i = 0; i < 6; i++) {
            CHECKF(fabs(out[i * 4] - m / (1 + m)) < 1e-6, "mode %d: %.9g vs %.9g", mode, out[i * 4],
                   m / (1 + m));
            CHECKF(fabs(out[i * 4] - key / (1 + key)) < 2e-5, "near a/(1+a)");
            CHECKF(out[i * 4 + 3] == 0.25f, "alpha passes through");
        }
    }
}

/* A saturated colour in luminance mode keeps its chromaticity: out = c Ld / L. */
static void test_luminance_colour(void)
{
    float px[4] = { 4.0f, 1.0f, 0.25f, 1.0f };
    lg_rh_params p = params(LG_RH_LUMINANCE, 0, 1e-4);
    float out[4];
    double s = 0.5;
    lg_rh_ref_map(px, out, 1, s, &p);
    double l = 0.2126 * 4 + 0.7152 * 1 + 0.0722 * 0.25;
    double ld = s * l / (1 + s * l);
    for (int k = 0; k < 3; k++)
        CHECKF(fabs(out[k] - px[k] * ld / l) < 1e-6, "channel %d: %.9g", k, out[k]);
    CHECKF(fabs(out[0] / out[1] - 4.0) < 1e-5, "ratio r/g kept");

    lg_rh_params q = params(LG_RH_RGB, 0, 1e-4);
    lg_rh_ref_map(px, out, 1, s, &q);
    for (int k = 0; k < 3; k++)
        CHECKF(fabs(out[k] - s * px[k] / (1 + s * px[k])) < 1e-6, "rgb channel %d", k);
}

/* White point: Ld(Lwhite) = 1, below it Lm (1 + Lm/Lw^2) / (1 + Lm), above it 1. */
static void test_white(void)
{
    const double lw = 3.0;
    lg_rh_params p = params(LG_RH_LUMINANCE, lw, 1e-4);
    double inv = 1.0 / (lw * lw);
    CHECKF(fabs(lg_rh_ref_curve(lw, inv) - 1.0) < 1e-15, "Ld(Lwhite) = %.17g",
           lg_rh_ref_curve(lw, inv));
    CHECKF(lg_rh_ref_curve(10 * lw, inv) == 1.0, "above white clamps to 1");
    CHECKF(fabs(lg_rh_ref_curve(1.0, inv) - (1.0 + 1.0 / 9.0) / 2.0) < 1e-15, "Ld(1)");
    CHECKF(lg_rh_ref_curve(1.0, 0) == 0.5, "no white: Ld(1) = 1/2");
    /* through the map, grey pixels: x = s L with s = 1 */
    float px[8] = { 3, 3, 3, 1, 1, 1, 1, 1 };
    float out[8];
    lg_rh_ref_map(px, out, 2, 1.0, &p);
    CHECKF(fabs(out[0] - 1.0) < 1e-6, "grey at white -> 1: %.9g", out[0]);
    CHECKF(fabs(out[4] - (1.0 + 1.0 / 9.0) / 2.0) < 1e-6, "grey 1 -> %.9g", out[4]);
}

/* Monotone in L, in [0, 1), over 12 decades. */
static void test_monotone(void)
{
    enum { N = 1200 };
    float *px = malloc(sizeof(float) * 4 * N), *out = malloc(sizeof(float) * 4 * N);
    for (int i = 0; i < N; i++) {
        float v = (float)pow(10.0, -6.0 + 12.0 * i / (N - 1));
        px[i * 4 + 0] = v;
        px[i * 4 + 1] = 0.5f * v;
        px[i * 4 + 2] = 2.0f * v;
        px[i * 4 + 3] = 1;
    }
    for (int mode = 0; mode < 2; mode++) {
        lg_rh_params p = params((lg_rh_mode)mode, 0, 1e-4);
        lg_rh_stats st;
        double s = scale_of(px, N, &p, 0.18, &st);
        lg_rh_ref_map(px, out, N, s, &p);
        for (int i = 0; i < N; i++) {
            for (int k = 0; k < 3; k++) {
                CHECKF(out[i * 4 + k] >= 0 && out[i * 4 + k] < (mode ? 1.0f : 14.0f), "range at %d",
                       i);
                if (i)
                    CHECKF(out[i * 4 + k] >= out[(i - 1) * 4 + k],
                           "mode %d: not monotone at %d ch %d", mode, i, k);
            }
        }
        CHECKF(out[(N - 1) * 4 + 1] > out[0 * 4 + 1], "not constant");
    }
    free(px);
    free(out);
}

/* Multiplying the exposure by 10 changes nothing but through delta. */
static void test_exposure(void)
{
    enum { N = 500 };
    float *a = malloc(sizeof(float) * 4 * N), *b = malloc(sizeof(float) * 4 * N);
    float *oa = malloc(sizeof(float) * 4 * N), *ob = malloc(sizeof(float) * 4 * N);
    srand(7);
    for (int i = 0; i < N * 4; i++) {
        a[i] = (float)(exp(8.0 * rand() / RAND_MAX - 4.0));
        b[i] = a[i] * 10.0f;
    }
    for (int mode = 0; mode < 2; mode++) {
        lg_rh_params p = params((lg_rh_mode)mode, 0, 1e-12);
        lg_rh_stats st;
        lg_rh_ref_map(a, oa, N, scale_of(a, N, &p, 0.18, &st), &p);
        lg_rh_ref_map(b, ob, N, scale_of(b, N, &p, 0.18, &st), &p);
        double md = 0;
        for (int i = 0; i < N * 4; i++)
            md = fmax(md, fabs(oa[i] - ob[i]) * (i % 4 != 3));
        CHECKF(md < 2e-6, "mode %d: x10 exposure changed the output by %.3g", mode, md);
    }
    free(a);
    free(b);
    free(oa);
    free(ob);
}

/* 60 steps of 1/60 s equal one step of 1 s; the closed form La = Lavg + (La0 - Lavg) r^60t. */
static void test_adapt(void)
{
    double la = 5.0, lavg = 0.3, rate = 0.98;
    for (int i = 0; i < 60; i++)
        la = lg_rh_adapt(la, lavg, rate, 1.0 / 60.0);
    double one = lg_rh_adapt(5.0, lavg, rate, 1.0);
    double closed = lavg + (5.0 - lavg) * pow(rate, 60.0);
    CHECKF(fabs(la - one) < 1e-12, "60 x 1/60 = %.17g, 1 x 1 = %.17g", la, one);
    CHECKF(fabs(one - closed) < 1e-12, "closed form %.17g", closed);
    CHECKF(fabs(lg_rh_adapt(5.0, lavg, 0.0, 1.0 / 60) - lavg) < 1e-15, "rate 0 adapts at once");
    CHECKF(lg_rh_adapt(5.0, lavg, 1.0, 1.0 / 60) == 5.0, "rate 1 never adapts");
}

/* Zero, NaN, Inf and negative pixels: counted, left out of Lavg (zero counts as log
 * delta), and mapped by the policy without touching their neighbours. */
static void test_bad_pixels(void)
{
    const float inf = INFINITY, qnan = NAN;
    float px[] = {
        1,       1,
        1,       1, /* 0 good */
        4,       2,
        1,       1, /* 1 good */
        0,       0,
        0,       1, /* 2 zero: log(delta) */
        qnan,    1,
        1,       1, /* 3 nan */
        inf,     1,
        1,       1, /* 4 +inf */
        -inf,    1,
        1,       1, /* 5 -inf */
        -10,     1,
        1,       1, /* 6 negative luminance */
        -0.1f,   1,
        1,       0.5f, /* 7 negative channel, positive luminance: counted as valid */
        1e30f,   1e30f,
        1e30f,   1, /* 8 huge but valid */
        FLT_MAX, FLT_MAX,
        FLT_MAX, 1, /* 9 the largest float */
    };
    size_t n = sizeof px / sizeof px[0] / 4;
    const double delta = 1e-4;
    for (int mode = 0; mode < 2; mode++) {
        lg_rh_params p = params((lg_rh_mode)mode, 0, delta);
        lg_rh_stats st;
        memset(&st, 0, sizeof st);
        lg_rh_ref_reduce(px, n, &p, &st);
        float lmax = lg_rh_luma(&px[9 * 4], p.w);
        uint64_t over = isinf(lmax) ? 1 : 0;
        CHECKF(st.valid == 6 - over, "valid %llu", (unsigned long long)st.valid);
        CHECKF(st.nonfinite == 3 + over, "nonfinite %llu", (unsigned long long)st.nonfinite);
        CHECKF(st.negative == 1, "negative %llu", (unsigned long long)st.negative);
        double l1 = 0.2126f * 4 + 0.7152f * 2 + 0.0722f * 1;
        double l7 = (double)(0.2126f * -0.1f + 0.7152f * 1 + 0.0722f * 1);
        double l8 = lg_rh_luma(&px[8 * 4], p.w);
        double want = log(delta + 1.0) + log(delta + l1) + log(delta) + log(delta + l7) +
                      log(delta + l8) + (over ? 0.0 : log(delta + lmax));
        CHECKF(fabs(st.log_sum - want) < 1e-6, "log sum %.9g vs %.9g", st.log_sum, want);

        float out[sizeof px / sizeof px[0]];
        lg_rh_ref_map(px, out, n, 0.7, &p);
        for (size_t i = 0; i < n * 4; i++)
            CHECKF(!isnan(out[i]) && out[i] >= 0 && out[i] <= 14, "out[%zu] = %g", i, out[i]);
        CHECKF(out[2 * 4] == 0 && out[2 * 4 + 1] == 0, "zero -> 0");
        CHECKF(out[3 * 4] == 0, "NaN channel -> 0");
        CHECKF(out[4 * 4] == 1, "+Inf channel -> 1");
        CHECKF(out[5 * 4] == 0, "-Inf channel -> 0");
        CHECKF(out[7 * 4] == 0 && out[7 * 4 + 3] == 0.5f, "negative channel -> 0, alpha kept");
        if (mode == 0) {
            CHECKF(out[4 * 4 + 1] == 0, "luminance: finite channels of a +Inf pixel -> 0");
            /* NaN read as 0, then mapped like (0, 1, 1) */
            float ref[4] = { 0, 1, 1, 1 }, o[4];
            lg_rh_ref_map(ref, o, 1, 0.7, &p);
            CHECKF(out[3 * 4 + 1] == o[1], "NaN pixel's other channels as if it were 0");
            /* huge grey: Ld/L c = Ld -> 1, with or without float overflow of L */
            CHECKF(fabs(out[8 * 4] - 1.0) < 1e-6, "huge grey -> %.9g", out[8 * 4]);
            CHECKF(fabs(out[9 * 4] - 1.0) < 1e-6, "FLT_MAX grey -> %.9g", out[9 * 4]);
        } else {
            CHECKF(fabs(out[4 * 4 + 1] - 0.7 / 1.7) < 1e-6, "rgb: channels independent");
            CHECKF(fabs(out[8 * 4] - 1.0) < 1e-6, "huge -> 1");
            CHECKF(fabs(out[9 * 4] - 1.0) < 1e-6, "FLT_MAX -> 1");
        }
        /* good pixels as if the bad ones were absent */
        float good[] = { 1, 1, 1, 1, 4, 2, 1, 1 }, og[8];
        lg_rh_ref_map(good, og, 2, 0.7, &p);
        CHECKF(memcmp(og, out, sizeof og) == 0, "neighbours untouched");
    }
    /* no valid pixel at all */
    float allbad[] = { qnan, qnan, qnan, 1, -1, -1, -1, 1 };
    lg_rh_params p = params(LG_RH_LUMINANCE, 0, 1e-4);
    lg_rh_stats st;
    memset(&st, 0, sizeof st);
    lg_rh_ref_reduce(allbad, 2, &p, &st);
    double lavg = 42;
    CHECKF(!lg_rh_log_average(&st, &lavg) && lavg == 42, "no valid pixel: no average");
}

/* ---- the fast passes against the oracle ------------------------------------------------------ */

/* A test image: log-uniform colours over ten decades, exact zeros, and every kind of bad
 * pixel, spread so that blocks of LG_RH_BLOCK and their tails both see some. */
static float *test_image(size_t n, uint32_t seed)
{
    float *px = malloc(n * 16);
    for (size_t i = 0; i < n; i++) {
        float *p = px + i * 4;
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            p[k] = (float)pow(10.0, -5.0 + 10.0 * (seed >> 8) / 16777216.0);
        }
        p[3] = (float)(i % 7) / 7.0f;
        switch (i % 97) {
        case 5: p[0] = NAN; break;
        case 17: p[1] = INFINITY; break;
        case 29: p[0] = p[1] = p[2] = INFINITY; break;
        case 41: p[2] = -INFINITY; break;
        case 53:
            p[0] = -10.0f;
            p[1] = p[2] = 0.1f;
            break;                     /* negative luminance */
        case 61: p[0] = -0.01f; break; /* negative channel, L > 0 */
        case 73: p[0] = p[1] = p[2] = 0.0f; break;
        case 89: p[0] = p[1] = p[2] = 3e38f; break; /* L overflows */
        default: break;
        }
    }
    return px;
}

static void test_fast_against_oracle(void)
{
    const size_t n = 10007; /* not a multiple of the block */
    float *px = test_image(n, 7);
    float *got = malloc(n * 16), *want = malloc(n * 16);
    for (int mode = 0; mode < 2; mode++) {
        for (int white = 0; white < 2; white++) {
            lg_rh_params p = params((lg_rh_mode)mode, white ? 40.0 : 0.0, 1e-4);
            lg_rh_stats a, b;
            memset(&a, 0, sizeof a);
            memset(&b, 0, sizeof b);
            lg_rh_reduce(px, n, &p, &a);
            lg_rh_ref_reduce(px, n, &p, &b);
            CHECKF(a.valid == b.valid && a.nonfinite == b.nonfinite && a.negative == b.negative,
                   "counts %llu/%llu/%llu, oracle %llu/%llu/%llu", (unsigned long long)a.valid,
                   (unsigned long long)a.nonfinite, (unsigned long long)a.negative,
                   (unsigned long long)b.valid, (unsigned long long)b.nonfinite,
                   (unsigned long long)b.negative);
            /* float logs (about 1 ulp each) of values whose logs average about -4 */
            CHECKF(fabs(a.log_sum - b.log_sum) <= 2e-7 * 12.0 * (double)b.valid,
                   "log sum %.12g, oracle %.12g", a.log_sum, b.log_sum);
            double lavg = 0;
            CHECK(lg_rh_log_average(&b, &lavg));
            double scale = 0.18 / lavg;
            lg_rh_map(px, got, n, (float)scale, &p);
            lg_rh_ref_map(px, want, n, scale, &p);
            int bad = 0;
            double md = 0;
            for (size_t i = 0; i < n * 4; i++) {
                double d = fabs((double)got[i] - want[i]);
                md = d > md ? d : md;
                /* float against double: a few ulps of values up to 1 / 0.0722 */
                if (!(d <= 1e-6 * fmax(1.0, fabs(want[i]))) && bad++ < 5)
                    fprintf(stderr, "mode %d white %d: pixel %zu channel %zu: %.9g, oracle %.9g\n",
                            mode, white, i / 4, i % 4, got[i], want[i]);
            }
            CHECKF(bad == 0, "mode %d white %d: %d values differ from the oracle (max %.3g)", mode,
                   white, bad, md);
        }
    }
    free(px);
    free(got);
    free(want);
}

static void test_logf(void)
{
    double worst = 0;
    float worst_x = 0;
    for (float x = 1e-12f; x < 3e38f; x *= 1.0009765625f) {
        double want = log((double)x), got = lg_rh_logf(x);
        /* relative to the result, or absolute near log(1) = 0 */
        double err = fabs(got - want) / fmax(fabs(want), 1.0);
        if (err > worst) {
            worst = err;
            worst_x = x;
        }
    }
    CHECKF(worst < 3e-7, "lg_rh_logf: worst error %.3g at x = %.9g", worst, worst_x);
    CHECK(lg_rh_logf(1.0f) == 0.0f);
}

/* ---- the threaded passes --------------------------------------------------------------------- */

static int pool_for(void *pctx, size_t count, size_t grain,
                    void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk), void *ctx)
{
    return lg_pool_run(pctx, count, grain, fn, ctx);
}

static void test_threads(void)
{
    /* wide enough for several chunks per row band, tall enough for many chunks */
    const uint32_t w = 1111, h = 523;
    const size_t n = (size_t)w * h;
    float *px = test_image(n, 11);
    float *out[3];
    lg_rh_stats total[3];
    lg_rh_stats *slots = calloc(lg_rh_cpu_chunks(w, h), sizeof *slots);
    CHECK(lg_rh_cpu_chunks(w, h) > 7);
    lg_rh_params p = params(LG_RH_LUMINANCE, 0.0, 1e-4);
    lg_rh_image in = { px, w, w, h, false };
    static const uint32_t sizes[] = { 1, 2, 7 };
    for (int k = 0; k < 3; k++) {
        lg_pool *pool = lg_pool_new(sizes[k], NULL);
        out[k] = malloc(n * 16);
        CHECK(lg_rh_cpu_reduce(&in, &p, slots, pool_for, pool, &total[k]) == 0);
        double lavg = 1;
        lg_rh_log_average(&total[k], &lavg);
        CHECK(lg_rh_cpu_map(&in, out[k], w, (float)(0.18 / lavg), &p, pool_for, pool) == 0);
        lg_pool_free(pool);
        if (k) {
            CHECKF(memcmp(&total[k], &total[0], sizeof total[0]) == 0,
                   "pool of %u: log sum %.17g, pool of 1: %.17g", sizes[k], total[k].log_sum,
                   total[0].log_sum);
            CHECKF(memcmp(out[k], out[0], n * 16) == 0, "pool of %u: another output", sizes[k]);
        }
    }
    /* the same stats as one pass over the whole image, within float rounding */
    lg_rh_stats ref;
    memset(&ref, 0, sizeof ref);
    lg_rh_ref_reduce(px, n, &p, &ref);
    CHECK(total[0].valid == ref.valid && total[0].nonfinite == ref.nonfinite &&
          total[0].negative == ref.negative);
    CHECKF(fabs(total[0].log_sum - ref.log_sum) <= 2e-7 * 12.0 * (double)ref.valid,
           "threaded log sum %.12g, oracle %.12g", total[0].log_sum, ref.log_sum);

    /* rgba16f: the same image through half gives the result of its widened floats */
    uint16_t *half = malloc(n * 8);
    for (size_t i = 0; i < n * 4; i++) {
        half[i] = lg_half_from_float(px[i]);
        px[i] = lg_float_from_half(half[i]);
    }
    lg_rh_image hin = { half, w, w, h, true };
    lg_rh_stats th, tf;
    float *oh = malloc(n * 16), *of = malloc(n * 16);
    lg_pool *pool = lg_pool_new(2, NULL);
    CHECK(lg_rh_cpu_reduce(&hin, &p, slots, pool_for, pool, &th) == 0);
    CHECK(lg_rh_cpu_reduce(&in, &p, slots, pool_for, pool, &tf) == 0);
    CHECK(memcmp(&th, &tf, sizeof th) == 0);
    CHECK(lg_rh_cpu_map(&hin, oh, w, 0.5f, &p, pool_for, pool) == 0);
    CHECK(lg_rh_cpu_map(&in, of, w, 0.5f, &p, pool_for, pool) == 0);
    CHECKF(memcmp(oh, of, n * 16) == 0, "rgba16f input maps differently from its floats");
    lg_pool_free(pool);
    free(oh);
    free(of);
    free(half);
    for (int k = 0; k < 3; k++)
        free(out[k]);
    free(slots);
    free(px);
}

int main(void)
{
    test_constant();
    test_luminance_colour();
    test_white();
    test_monotone();
    test_exposure();
    test_adapt();
    test_bad_pixels();
    test_fast_against_oracle();
    test_logf();
    test_threads();
    return check_report("reinhard math");
}
