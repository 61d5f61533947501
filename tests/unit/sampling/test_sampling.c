/*
 * tests/unit/sampling: lightgraph/sampling.h. One command per meson test:
 *
 *   square   every sampler's points lie in [0, 1)^2 and are pure functions of (side, seed,
 *            k); jittered: exactly one point per cell, two seeds differ; Hammersley and
 *            Sobol with side 16: one point in every elementary interval of area 1/256
 *            (the (0, 8, 2)-net property; Hammersley's u strata and v's radical inverse);
 *            a digital shift keeps the net property; names
 *   sphere   unit directions; the estimate (4 pi / T) sum f of the integrals of 1, z, z^2,
 *            x y and y^2 over the sphere (4 pi, 0, 4 pi / 3, 0, 4 pi / 3) within what the
 *            sampler promises at side 256; the seed's theta = 2 acos(sqrt(1 - u)) gives
 *            the same directions; the poles are exact
 *   sum      10^8 float terms: ones sum to exactly 10^8 through lg_sum (a float sum stops
 *            at 2^24), 0.1f summed 10^8 times within 1e-12 relative of 10^8 * 0.1f, a
 *            cancelling sequence (1e16, 1, -1e16) exact; lg_sum_f over 2^22 floats
 *            against an exact integer sum; merge of partial sums
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "lightgraph/sampling.h"
#include "lightgraph/vecmath.h"

static const lg_sampler samplers[] = { LG_SAMPLER_JITTERED, LG_SAMPLER_HAMMERSLEY,
                                       LG_SAMPLER_SOBOL };

/* one point in each of the side*side elementary intervals of shape (2^a x 2^b), a + b =
 * log2(side^2), for every split: the (0, m, 2)-net property */
static int net_ok(lg_sampler s, uint32_t side, uint64_t seed)
{
    uint32_t total = side * side, m = 0;
    while ((1u << m) < total)
        m++;
    int ok = 1;
    unsigned char *hit = calloc(total, 1);
    for (uint32_t a = 0; a <= m; a++) {
        uint32_t nu = 1u << a, nv = 1u << (m - a);
        memset(hit, 0, total);
        for (uint32_t k = 0; k < total; k++) {
            double uv[2];
            lg_sample_square(s, side, seed, k, uv);
            uint32_t cu = (uint32_t)(uv[0] * nu), cv = (uint32_t)(uv[1] * nv);
            hit[cv * nu + cu]++;
        }
        for (uint32_t i = 0; i < total; i++)
            if (hit[i] != 1) {
                ok = 0;
                fprintf(stderr,
                        "%s side %u seed %llu: interval shape %ux%u, cell %u has %u "
                        "points\n",
                        lg_sampler_name(s), side, (unsigned long long)seed, nu, nv, i, hit[i]);
                break;
            }
    }
    free(hit);
    return ok;
}

static int cmd_square(void)
{
    for (unsigned si = 0; si < 3; si++) {
        lg_sampler s = samplers[si];
        for (uint32_t side = 1; side <= 64; side = side * 2 + 1) {
            for (uint64_t k = 0; k < (uint64_t)side * side; k++) {
                double a[2], b[2];
                lg_sample_square(s, side, 7, k, a);
                lg_sample_square(s, side, 7, k, b);
                CHECK(a[0] >= 0 && a[0] < 1 && a[1] >= 0 && a[1] < 1);
                CHECK(a[0] == b[0] && a[1] == b[1]);
            }
        }
    }
    /* jittered: one point per cell, whatever the seed; seeds differ */
    uint32_t side = 37;
    for (uint64_t seed = 0; seed < 3; seed++) {
        for (uint64_t k = 0; k < (uint64_t)side * side; k++) {
            double uv[2];
            lg_sample_square(LG_SAMPLER_JITTERED, side, seed, k, uv);
            CHECKF((uint32_t)(uv[0] * side) == k % side && (uint32_t)(uv[1] * side) == k / side,
                   "jittered point %llu outside its cell", (unsigned long long)k);
        }
    }
    double p0[2], p1[2];
    lg_sample_square(LG_SAMPLER_JITTERED, side, 1, 5, p0);
    lg_sample_square(LG_SAMPLER_JITTERED, side, 2, 5, p1);
    CHECK(p0[0] != p1[0] || p0[1] != p1[1]);
    /* the nets */
    CHECK(net_ok(LG_SAMPLER_SOBOL, 16, 0));
    CHECK(net_ok(LG_SAMPLER_SOBOL, 16, 12345));
    CHECK(net_ok(LG_SAMPLER_SOBOL, 64, 0));
    CHECK(net_ok(LG_SAMPLER_HAMMERSLEY, 16, 0));
    CHECK(net_ok(LG_SAMPLER_HAMMERSLEY, 16, 99));
    CHECK(!strcmp(lg_sampler_name(LG_SAMPLER_SOBOL), "sobol"));
    CHECK(!strcmp(lg_sampler_name(LG_SAMPLER_JITTERED), "jittered"));
    CHECK(!strcmp(lg_sampler_name(LG_SAMPLER_HAMMERSLEY), "hammersley"));
    CHECK(lg_sampler_name((lg_sampler)17) == NULL);
    return check_report("sampling square");
}

static int cmd_sphere(void)
{
    /* the seed's map: theta = 2 acos(sqrt(1 - u)) */
    for (int i = 0; i <= 1000; i++) {
        double uv[2] = { i / 1000.0, (i * 7 % 1000) / 1000.0 }, d[3];
        lg_sample_sphere(uv, d);
        double th = 2.0 * acos(sqrt(1.0 - uv[0])), ph = 2.0 * LG_PI * uv[1];
        double e[3] = { sin(th) * cos(ph), sin(th) * sin(ph), cos(th) };
        CHECKF(fabs(d[0] - e[0]) < 1e-7 && fabs(d[1] - e[1]) < 1e-7 && fabs(d[2] - e[2]) < 1e-12,
               "u %g: (%g %g %g) against the seed's (%g %g %g)", uv[0], d[0], d[1], d[2], e[0],
               e[1], e[2]);
        CHECK(fabs(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] - 1.0) < 1e-14);
    }
    double np[2] = { 0, 0.3 }, d[3];
    lg_sample_sphere(np, d);
    CHECK(d[2] == 1.0 && d[0] == 0.0 && d[1] == 0.0);
    /* integrals; tolerances: Monte Carlo (jittered) vs quasi-Monte Carlo */
    for (unsigned si = 0; si < 3; si++) {
        lg_sampler s = samplers[si];
        uint32_t side = 256;
        double sum[5] = { 0 };
        for (uint64_t k = 0; k < (uint64_t)side * side; k++) {
            double uv[2], w[3];
            lg_sample_square(s, side, 3, k, uv);
            lg_sample_sphere(uv, w);
            sum[0] += 1, sum[1] += w[2], sum[2] += w[2] * w[2], sum[3] += w[0] * w[1];
            sum[4] += w[1] * w[1];
        }
        double scale = 4.0 * LG_PI / ((double)side * side);
        double want[5] = { 4 * LG_PI, 0, 4 * LG_PI / 3, 0, 4 * LG_PI / 3 };
        for (int i = 0; i < 5; i++) {
            double got = sum[i] * scale;
            CHECKF(fabs(got - want[i]) < 2e-3, "%s integral %d: %.8f, want %.8f",
                   lg_sampler_name(s), i, got, want[i]);
        }
    }
    return check_report("sampling sphere");
}

static int cmd_sum(void)
{
    const uint64_t n = 100000000ull;
    lg_sum ones = { 0, 0 }, tenth = { 0, 0 };
    float naive = 0.0f;
    const float t = 0.1f;
    for (uint64_t i = 0; i < n; i++) {
        float one = 1.0f;
        lg_sum_add(&ones, one);
        lg_sum_add(&tenth, t);
        naive += one;
    }
    CHECKF(lg_sum_value(&ones) == 1e8, "10^8 ones: %.17g", lg_sum_value(&ones));
    double want = 1e8 * (double)t;
    CHECKF(fabs(lg_sum_value(&tenth) - want) <= 1e-12 * want, "10^8 x 0.1f: %.17g, want %.17g",
           lg_sum_value(&tenth), want);
    /* the failure lg_sum exists for (kept so that a change of flags shows) */
    printf("a float sum of 10^8 ones: %.0f\n", naive);
    CHECK(naive == 16777216.0f);
    lg_sum c = { 0, 0 };
    lg_sum_add(&c, 1e16);
    lg_sum_add(&c, 1.0);
    lg_sum_add(&c, -1e16);
    CHECKF(lg_sum_value(&c) == 1.0, "cancelling sum: %g", lg_sum_value(&c));
    /* merge: two halves of the tenths */
    lg_sum a = { 0, 0 }, b = { 0, 0 };
    for (int i = 0; i < 1000000; i++)
        lg_sum_add(i & 1 ? &a : &b, t);
    lg_sum_merge(&a, &b);
    CHECK(fabs(lg_sum_value(&a) - 1e6 * (double)t) <= 1e-12 * 1e6 * (double)t);
    /* pairwise over an array of integers (exact in double) */
    size_t m = (size_t)1 << 22;
    float *x = malloc(m * sizeof *x);
    double exact = 0;
    for (size_t i = 0; i < m; i++) {
        x[i] = (float)(i % 1000);
        exact += x[i];
    }
    CHECK(lg_sum_f(x, m) == exact);
    CHECK(lg_sum_f(x, 0) == 0.0 && lg_sum_f(NULL, 5) == 0.0);
    free(x);
    return check_report("sampling sum");
}

int main(int argc, char **argv)
{
    const char *c = argc > 1 ? argv[1] : "";
    if (!strcmp(c, "square"))
        return cmd_square();
    if (!strcmp(c, "sphere"))
        return cmd_sphere();
    if (!strcmp(c, "sum"))
        return cmd_sum();
    fprintf(stderr, "usage: test_sampling square|sphere|sum\n");
    return 2;
}
