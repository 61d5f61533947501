/*
 * lg_half_from_float / lg_float_from_half against the binary16 rules, checked three ways:
 * named edge cases, an independent rounding oracle written with double arithmetic, and
 * (when the compiler has _Float16) the compiler's own conversion.
 */
#include <fenv.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "codectest.h"
#include "lightgraph/image.h"

static float f_of_bits(uint32_t b)
{
    float f;
    memcpy(&f, &b, sizeof f);
    return f;
}

static int half_is_nan(uint16_t h)
{
    return (h & 0x7c00u) == 0x7c00u && (h & 0x3ffu) != 0;
}

/* The nearest binary16 by arithmetic: scale into an integer grid and let rint (ties to
 * even under the default rounding mode) pick. */
static uint16_t oracle_half(float f)
{
    uint16_t sign = signbit(f) ? 0x8000u : 0;
    double a = fabs((double)f);
    if (isnan(f))
        return 0x7e00u; /* any NaN; compared by class */
    if (a >= 65520.0)
        return sign | 0x7c00u;
    if (a < ldexp(1.0, -14)) {
        double n = rint(a / ldexp(1.0, -24));  /* denormal grid, exact scaling */
        return (uint16_t)(sign | (uint16_t)n); /* n == 1024 is the smallest normal */
    }
    int e2;
    frexp(a, &e2);
    int E = e2 - 1; /* a in [2^E, 2^(E+1)) */
    double n = rint(a / ldexp(1.0, E - 10));
    if (n >= 2048.0) {
        n = 1024.0;
        E++;
    }
    if (E + 15 >= 31)
        return sign | 0x7c00u;
    return (uint16_t)(sign | (uint16_t)((E + 15) << 10) | (uint16_t)(n - 1024.0));
}

static void check_one(float f)
{
    uint16_t got = lg_half_from_float(f), want = oracle_half(f);
    if (isnan(f)) {
        CHECKF(half_is_nan(got), "NaN %08x -> %04x", 0u, got);
        return;
    }
    uint32_t b;
    memcpy(&b, &f, sizeof b);
    CHECKF(got == want, "float %a (0x%08x): got 0x%04x want 0x%04x", (double)f, b, got, want);
#ifdef LG_HAVE_FLOAT16
    _Float16 h = (_Float16)f;
    uint16_t hb;
    memcpy(&hb, &h, sizeof hb);
    CHECKF(got == hb, "float %a: got 0x%04x, _Float16 gives 0x%04x", (double)f, got, hb);
#endif
}

int main(void)
{
    if (fegetround() != FE_TONEAREST)
        fesetround(FE_TONEAREST);

    /* named cases */
    CHECK(lg_half_from_float(0.0f) == 0x0000);
    CHECK(lg_half_from_float(-0.0f) == 0x8000);
    CHECK(lg_half_from_float(1.0f) == 0x3c00);
    CHECK(lg_half_from_float(-2.0f) == 0xc000);
    CHECK(lg_half_from_float(65504.0f) == 0x7bff);
    CHECK(lg_half_from_float(65519.996f) == 0x7bff);
    CHECK(lg_half_from_float(65520.0f) == 0x7c00);
    CHECK(lg_half_from_float(-65520.0f) == 0xfc00);
    CHECK(lg_half_from_float(1e10f) == 0x7c00);
    CHECK(lg_half_from_float(INFINITY) == 0x7c00);
    CHECK(lg_half_from_float(-INFINITY) == 0xfc00);
    CHECK(half_is_nan(lg_half_from_float(NAN)));
    CHECK(half_is_nan(lg_half_from_float(-NAN)) && (lg_half_from_float(-NAN) & 0x8000));
    CHECK(half_is_nan(lg_half_from_float(f_of_bits(0x7f800001u)))); /* payload only in low bits */
    CHECK(lg_half_from_float(0x1p-14f) == 0x0400);                  /* smallest normal */
    CHECK(lg_half_from_float(0x1p-24f) == 0x0001);                  /* smallest denormal */
    CHECK(lg_half_from_float(0x1p-25f) == 0x0000);                  /* tie -> even (0) */
    CHECK(lg_half_from_float(-0x1p-25f) == 0x8000);
    CHECK(lg_half_from_float(nextafterf(0x1p-25f, 1.0f)) == 0x0001);
    CHECK(lg_half_from_float(0x1.8p-24f) == 0x0002);          /* 1.5 units: tie -> 2 */
    CHECK(lg_half_from_float(0x1.4p-23f) == 0x0002);          /* 2.5 units: tie -> 2 */
    CHECK(lg_half_from_float(0x1p-14f - 0x1p-25f) == 0x0400); /* tie 0x3ff/0x400 -> even */
    CHECK(lg_half_from_float(0x1p-26f) == 0x0000);
    CHECK(lg_half_from_float(1.0f + 0x1p-11f) == 0x3c00);   /* tie -> even */
    CHECK(lg_half_from_float(1.0f + 0x1.8p-10f) == 0x3c02); /* 1.5 ulp: tie -> even */

    CHECK(lg_float_from_half(0x7bff) == 65504.0f);
    CHECK(lg_float_from_half(0x0001) == 0x1p-24f);
    CHECK(lg_float_from_half(0x03ff) == 0x3ffp-24f);
    CHECK(lg_float_from_half(0x0400) == 0x1p-14f);
    CHECK(lg_float_from_half(0x7c00) == INFINITY);
    CHECK(lg_float_from_half(0xfc00) == -INFINITY);
    CHECK(isnan(lg_float_from_half(0x7e00)));
    CHECK(signbit(lg_float_from_half(0x8000)) && lg_float_from_half(0x8000) == 0.0f);

    /* every half survives half -> float -> half; NaNs stay NaN */
    for (uint32_t h = 0; h <= 0xffffu; h++) {
        float f = lg_float_from_half((uint16_t)h);
        uint16_t back = lg_half_from_float(f);
        if (half_is_nan((uint16_t)h))
            CHECKF(isnan(f) && half_is_nan(back), "NaN half 0x%04x", h);
        else
            CHECKF(back == h, "half 0x%04x -> %a -> 0x%04x", h, (double)f, back);
        if (check_failures > 20)
            return check_report("half");
    }

    /* sweep the whole float range, and densely the denormal and overflow boundaries */
    for (uint64_t b = 0; b <= 0xffffffffu; b += 4099)
        check_one(f_of_bits((uint32_t)b));
    for (uint32_t b = 0x32800000u; b <= 0x38800000u; b += 61) /* 2^-26 .. 2^-14 */
        check_one(f_of_bits(b));
    for (uint32_t b = 0x477f0000u; b <= 0x47800000u; b++) /* 65280 .. 65536 */
        check_one(f_of_bits(b));
    for (int i = -40; i <= 40; i++) { /* halfway points around every denormal step near 0 */
        check_one(ldexpf(1.0f, -24) * (1.0f + (float)i / 8.0f));
        check_one(-ldexpf(1.0f, -24) * (1.0f + (float)i / 8.0f));
    }
    return check_report("half");
}
