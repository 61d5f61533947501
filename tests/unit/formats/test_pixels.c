/*
 * lg_pixels_from_rgba32f / lg_pixels_to_rgba32f / lg_format_name (sdk/src/formats.c) and
 * the policy of lightgraph/image.h "Pixel formats", against independent oracles:
 *   rgba16f: a value v in range converts like lg_half_from_float(v) (itself tested bit by
 *            bit in tests/unit/codecs/test_half.c); above 65504 (and +Inf) it is 65504,
 *            never Inf; NaN is 0; each of those is counted once;
 *   rgba8:   round(clamp(v) * 255) computed here in double;
 *   rgbe8:   the bytes of lg_rgbe_encode; the decoded value within half a mantissa step of
 *            the largest channel (2^(E-137)) of the input, alpha 1;
 *   the round trip to float and back of every half, every rgba8 byte and every RGBE quad
 *   of a sweep returns the same bits.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/check.h"
#include "lightgraph/host.h"
#include "lightgraph/image.h"

static void names(void)
{
    const lg_format all[] = { LG_FORMAT_RGBA32F, LG_FORMAT_RGBA16F, LG_FORMAT_RGBA8,
                              LG_FORMAT_RGBE8 };
    const char *want[] = { "rgba32f", "rgba16f", "rgba8", "rgbe8" };
    for (int i = 0; i < 4; i++) {
        CHECK(strcmp(lg_format_name(all[i]), want[i]) == 0);
        lg_format f = 0;
        CHECK(lg_format_from_name(want[i], &f) == 0 && f == all[i]);
    }
    lg_format f = LG_FORMAT_RGBA8;
    CHECK(lg_format_from_name("rgbe", &f) == LG_ERR_NOTFOUND && f == LG_FORMAT_RGBA8);
    CHECK(lg_format_from_name(NULL, &f) == LG_ERR_NOTFOUND);
    CHECK(strcmp(lg_format_name((lg_format)99), "unknown") == 0);
    float px[4] = { 0 };
    unsigned char out[16];
    CHECK(lg_pixels_from_rgba32f((lg_format)99, px, 1, out, NULL) == LG_ERR_INVALID);
    CHECK(lg_pixels_to_rgba32f((lg_format)0, out, 1, px) == LG_ERR_INVALID);
}

static void half_policy(void)
{
    const float v[] = { 0.0f,     -0.0f,    1.0f,  0.1f,   -2.5f,    65504.0f, 65505.0f,
                        65519.0f, 65520.0f, 1e5f,  1e9f,   INFINITY, -1e6f,    -INFINITY,
                        NAN,      -NAN,     6e-8f, 1e-30f, -65504.0f };
    /* replaced (counted): everything beyond +-65504, Inf and NaN */
    const int counted[] = { 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0 };
    size_t n = sizeof v / sizeof v[0];
    size_t px = (n + 3) / 4;
    float *src = calloc(px * 4, sizeof(float));
    memcpy(src, v, sizeof v);
    uint16_t *h = calloc(px * 4, 2);
    uint64_t clamped = 7; /* adds to what is there */
    CHECK(lg_pixels_from_rgba32f(LG_FORMAT_RGBA16F, src, px, h, &clamped) == 0);
    uint64_t want_count = 7;
    for (size_t i = 0; i < n; i++) {
        want_count += (uint64_t)counted[i];
        float x = v[i];
        float expect = x != x ? 0.0f : x > 65504.0f ? 65504.0f : x < -65504.0f ? -65504.0f : x;
        uint16_t want = lg_half_from_float(expect);
        CHECKF(h[i] == want, "rgba16f of %g: 0x%04x, want 0x%04x", (double)x, h[i], want);
        float back = lg_float_from_half(h[i]);
        CHECKF(isfinite(back), "rgba16f of %g reads back %g: never Inf or NaN", (double)x,
               (double)back);
    }
    CHECKF(clamped == want_count, "clamped count %llu, want %llu", (unsigned long long)clamped,
           (unsigned long long)want_count);
    /* every finite half round trips through float bit for bit, and is never counted */
    uint16_t *all = malloc(65536 * 2), *again = malloc(65536 * 2);
    float *f = malloc(65536 * 4);
    int finite = 0;
    for (uint32_t i = 0; i < 65536; i++) {
        uint16_t q = (uint16_t)i;
        if (((q >> 10) & 0x1f) == 0x1f)
            q = 0x3c00; /* Inf and NaN are not what a policy-following image holds */
        all[finite++] = q;
    }
    CHECK(lg_pixels_to_rgba32f(LG_FORMAT_RGBA16F, all, 65536 / 4, f) == 0);
    uint64_t c2 = 0;
    CHECK(lg_pixels_from_rgba32f(LG_FORMAT_RGBA16F, f, 65536 / 4, again, &c2) == 0);
    CHECK(c2 == 0);
    int same = 1;
    for (uint32_t i = 0; i < 65536; i++)
        same &= (all[i] == again[i]) || ((all[i] & 0x7fff) == 0 && (again[i] & 0x7fff) == 0);
    CHECKF(same, "a half -> float -> half round trip changed bits");
    free(all);
    free(again);
    free(f);
    free(src);
    free(h);
    printf(
        "rgba16f: above 65504 and Inf -> 65504, NaN -> 0, counted; every finite half round trips\n");
}

static void rgba8_policy(void)
{
    const float v[] = { 0,   1,        0.5f,       0.2f,       -0.1f,  1.5f,
                        NAN, INFINITY, 1.0f / 255, 0.5f / 255, 0.999f, 254.5f / 255 };
    size_t n = sizeof v / sizeof v[0], px = n / 4;
    uint8_t b[12];
    uint64_t c = 0;
    CHECK(lg_pixels_from_rgba32f(LG_FORMAT_RGBA8, v, px, b, &c) == 0);
    CHECKF(c == 4, "rgba8: %llu values counted, want 4 (-0.1, 1.5, NaN, Inf)",
           (unsigned long long)c);
    for (size_t i = 0; i < n; i++) {
        double x = v[i] != v[i] ? 0 : v[i] < 0 ? 0 : v[i] > 1 ? 1 : v[i];
        uint8_t want = (uint8_t)floor(x * 255 + 0.5);
        CHECKF(b[i] == want, "rgba8 of %g: %u, want %u", (double)v[i], b[i], want);
    }
    uint8_t all[256], again[256];
    float f[256];
    for (int i = 0; i < 256; i++)
        all[i] = (uint8_t)i;
    CHECK(lg_pixels_to_rgba32f(LG_FORMAT_RGBA8, all, 64, f) == 0);
    c = 0;
    CHECK(lg_pixels_from_rgba32f(LG_FORMAT_RGBA8, f, 64, again, &c) == 0);
    CHECK(c == 0 && memcmp(all, again, 256) == 0);
    CHECK(f[255] == 1.0f && f[0] == 0.0f);
    printf("rgba8: clamp to [0, 1], NaN 0, round(v 255); every byte round trips\n");
}

static uint64_t rng = 0x1234567887654321ull;
static double rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) * (1.0 / 9007199254740992.0);
}

static void rgbe_policy(void)
{
    enum { N = 20000 };
    float *src = malloc(N * 16), *back = malloc(N * 16);
    uint8_t *b = malloc(N * 4);
    uint64_t want_count = 0;
    for (int i = 0; i < N; i++) {
        double base = ldexp(1.0, (int)(rnd() * 240) - 120);
        for (int c = 0; c < 3; c++)
            src[4 * i + c] = (float)(base * exp2((rnd() - 0.5) * 12));
        src[4 * i + 3] = (float)rnd();
    }
    const float special[][3] = { { NAN, 1, 2 },   { -1, 2, 3 },       { INFINITY, 0, 0 },
                                 { 3e38f, 1, 1 }, { 0x1p127f, 0, 0 }, { 0, 0, 0 },
                                 { -0.0f, 0, 0 } };
    const int counted[] = { 1, 1, 1, 1, 1, 0, 0 };
    for (int k = 0; k < 7; k++) {
        memcpy(src + 4 * k, special[k], 12);
        src[4 * k + 3] = 1;
    }
    for (int k = 0; k < 7; k++)
        want_count += (uint64_t)counted[k];
    uint64_t c = 0;
    CHECK(lg_pixels_from_rgba32f(LG_FORMAT_RGBE8, src, N, b, &c) == 0);
    CHECKF(c == want_count, "rgbe8: %llu counted, want %llu", (unsigned long long)c,
           (unsigned long long)want_count);
    CHECK(lg_pixels_to_rgba32f(LG_FORMAT_RGBE8, b, N, back) == 0);
    double worst = 0;
    for (int i = 0; i < N; i++) {
        uint8_t want[4];
        lg_rgbe_encode(src + 4 * i, want);
        CHECKF(memcmp(want, b + 4 * i, 4) == 0, "rgbe8 pixel %d: bytes differ from lg_rgbe_encode",
               i);
        CHECK(back[4 * i + 3] == 1.0f);
        if (i < 7)
            continue;
        /* half a mantissa step of the pixel's exponent: 2^(E - 137) */
        double step = ldexp(1.0, (int)b[4 * i + 3] - 137);
        double m = fmax(src[4 * i], fmax(src[4 * i + 1], src[4 * i + 2]));
        for (int ch = 0; ch < 3; ch++) {
            double e = fabs((double)back[4 * i + ch] - src[4 * i + ch]);
            CHECKF(e <= step, "rgbe8 pixel %d channel %d: %g reads %g (step %g)", i, ch,
                   (double)src[4 * i + ch], (double)back[4 * i + ch], step);
            if (ch == 0 || src[4 * i + ch] == m)
                worst = fmax(worst, e / m);
        }
    }
    /* every exponent byte with every mantissa of R: decode then encode gives the bytes back
     * (for canonical quads: the largest mantissa at least 128, or all zero) */
    int bad = 0;
    for (int e = 1; e < 256; e++)
        for (int m = 128; m < 256; m++) {
            uint8_t q[4] = { (uint8_t)m, (uint8_t)(m / 2), (uint8_t)(m / 3), (uint8_t)e }, r[4];
            float f[4];
            CHECK(lg_pixels_to_rgba32f(LG_FORMAT_RGBE8, q, 1, f) == 0);
            CHECK(lg_pixels_from_rgba32f(LG_FORMAT_RGBE8, f, 1, r, NULL) == 0);
            /* the exponent bytes whose values are float denormals (below 2^-126) are
             * black by the encoder's rule (lightgraph/image.h) */
            int below = f[0] < FLT_MIN;
            if (!below && memcmp(q, r, 4) && bad++ < 5)
                CHECKF(0, "RGBE quad %u %u %u %u -> %a -> %u %u %u %u", q[0], q[1], q[2], q[3],
                       (double)f[0], r[0], r[1], r[2], r[3]);
        }
    CHECK(bad == 0);
    /* the decode (inlined in formats.c) is lg_rgbe_decode's, bit for bit, for every
     * exponent byte and mantissa */
    {
        uint8_t q[256 * 4];
        float f[256 * 4];
        for (int e = 0; e < 256; e++) {
            for (int m = 0; m < 256; m++) {
                q[4 * m] = (uint8_t)m;
                q[4 * m + 1] = (uint8_t)(255 - m);
                q[4 * m + 2] = (uint8_t)(m * 7);
                q[4 * m + 3] = (uint8_t)e;
            }
            CHECK(lg_pixels_to_rgba32f(LG_FORMAT_RGBE8, q, 256, f) == 0);
            for (int m = 0; m < 256; m++) {
                float want[3];
                lg_rgbe_decode(q + 4 * m, want);
                CHECKF(memcmp(want, f + 4 * m, 12) == 0 && f[4 * m + 3] == 1.0f,
                       "decode of %d %d %d %d differs from lg_rgbe_decode", q[4 * m], q[4 * m + 1],
                       q[4 * m + 2], e);
            }
        }
    }
    printf("rgbe8: bytes of lg_rgbe_encode, %d random pixels within half a step (largest "
           "channel relative error %.3g <= 2^-8 = %.3g), every canonical quad round trips\n",
           N, worst, 1.0 / 256);
    CHECK(worst <= 1.0 / 256);
    free(src);
    free(back);
    free(b);
}

static void in_place(void)
{
    /* dst == src, growing (to_rgba32f) and shrinking (from_rgba32f) */
    float buf[64];
    for (int i = 0; i < 64; i++)
        buf[i] = (float)i * 0.25f;
    float ref[64];
    memcpy(ref, buf, sizeof ref);
    const lg_format fs[] = { LG_FORMAT_RGBA32F, LG_FORMAT_RGBA16F, LG_FORMAT_RGBE8 };
    for (int k = 0; k < 3; k++) {
        float tmp[64];
        memcpy(tmp, ref, sizeof tmp);
        CHECK(lg_pixels_from_rgba32f(fs[k], tmp, 16, tmp, NULL) == 0);
        CHECK(lg_pixels_to_rgba32f(fs[k], tmp, 16, tmp) == 0);
        for (int i = 0; i < 64; i++) {
            float want = (fs[k] == LG_FORMAT_RGBE8 && i % 4 == 3) ? 1.0f : ref[i];
            /* 0.25 steps below 16 are exact in half and in RGBE when the pixel's largest
             * channel is below 64 (mantissa step 0.25 at exponent 6) */
            CHECKF(tmp[i] == want, "%s in place: value %d is %g, want %g", lg_format_name(fs[k]), i,
                   (double)tmp[i], (double)want);
        }
    }
}

/* The cost of the conversions, printed (docs/images.md quotes it), not checked: ns per pixel
 * over 1M pixels, the least of 5 runs. */
static void cost(void)
{
    enum { N = 1 << 20 };
    float *src = malloc((size_t)N * 16), *back = malloc((size_t)N * 16);
    void *dst = malloc((size_t)N * 16);
    for (size_t i = 0; i < (size_t)N * 4; i++)
        src[i] = (float)exp2((double)(i % 1000) / 50.0 - 8.0);
    const lg_format fs[] = { LG_FORMAT_RGBA32F, LG_FORMAT_RGBA16F, LG_FORMAT_RGBE8,
                             LG_FORMAT_RGBA8 };
    for (int k = 0; k < 4; k++) {
        double best_from = 1e30, best_to = 1e30;
        for (int r = 0; r < 5; r++) {
            struct timespec t0, t1, t2;
            clock_gettime(CLOCK_MONOTONIC, &t0);
            lg_pixels_from_rgba32f(fs[k], src, N, dst, NULL);
            clock_gettime(CLOCK_MONOTONIC, &t1);
            lg_pixels_to_rgba32f(fs[k], dst, N, back);
            clock_gettime(CLOCK_MONOTONIC, &t2);
            double a = (t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec);
            double b = (t2.tv_sec - t1.tv_sec) * 1e9 + (t2.tv_nsec - t1.tv_nsec);
            best_from = a < best_from ? a : best_from;
            best_to = b < best_to ? b : best_to;
        }
        printf("cost %-7s: from rgba32f %.2f ns/px, to rgba32f %.2f ns/px (one thread)\n",
               lg_format_name(fs[k]), best_from / N, best_to / N);
    }
    free(src);
    free(back);
    free(dst);
}

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    cost();
    names();
    half_policy();
    rgba8_policy();
    rgbe_policy();
    in_place();
    return check_report("formats_pixels");
}
