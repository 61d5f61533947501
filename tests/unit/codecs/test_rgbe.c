/*
 * Ward's RGBE encoding at its edges (image.h lists them), and the sRGB transfer function.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>

#include "codectest.h"
#include "lightgraph/image.h"

static void roundtrip(float r, float g, float b, float out[3], uint8_t e[4])
{
    float in[3] = { r, g, b };
    lg_rgbe_encode(in, e);
    lg_rgbe_decode(e, out);
}

int main(void)
{
    float o[3];
    uint8_t e[4];

    /* zero and tiny values: (0,0,0,0), decoding to exactly 0 */
    roundtrip(0.0f, 0.0f, 0.0f, o, e);
    CHECK(e[0] == 0 && e[1] == 0 && e[2] == 0 && e[3] == 0);
    CHECK(o[0] == 0.0f && o[1] == 0.0f && o[2] == 0.0f);
    roundtrip(1e-39f, 1e-38f, 0.0f, o, e);
    CHECK(e[3] == 0 && o[0] == 0.0f && o[1] == 0.0f);
    roundtrip(0x1p-126f, 0.0f, 0.0f, o, e); /* FLT_MIN, the smallest normal float: kept, exactly */
    CHECK(e[3] != 0 && o[0] == 0x1p-126f);

    /* negatives and NaN encode as 0; the other channels are unaffected */
    roundtrip(-1.0f, 0.5f, 0.25f, o, e);
    CHECK(o[0] == 0.0f && o[1] == 0.5f && o[2] == 0.25f);
    roundtrip(NAN, 2.0f, -INFINITY, o, e);
    CHECK(o[0] == 0.0f && o[1] == 2.0f && o[2] == 0.0f);
    roundtrip(-5.0f, -1.0f, NAN, o, e);
    CHECK(e[3] == 0 && o[0] == 0.0f && o[1] == 0.0f && o[2] == 0.0f);

    /* exact powers of two round trip exactly, alone or with smaller powers beside them */
    for (int k = -126; k <= 126; k++) {
        float v = ldexpf(1.0f, k);
        for (int c = 0; c < 3; c++) {
            float in[3] = { 0, 0, 0 };
            in[c] = v;
            lg_rgbe_encode(in, e);
            lg_rgbe_decode(e, o);
            CHECKF(o[c] == v && e[c] == 128, "2^%d in channel %d -> %a (m=%d)", k, c, (double)o[c],
                   e[c]);
        }
        if (k >= -119) {
            roundtrip(v, v / 2, v / 128, o, e);
            CHECKF(o[0] == v && o[1] == v / 2 && o[2] == v / 128, "2^%d mixed", k);
        }
    }

    /* the mantissa never overflows: a value that rounds up to the next power of two gets
     * that power's exponent (the seed's ceil(log2) made it 256) */
    for (int k = -100; k <= 100; k += 7) {
        float v = ldexpf(255.75f / 256.0f, k + 1); /* just below 2^(k+1) */
        roundtrip(v, 0, 0, o, e);
        CHECKF(e[0] == 128 && o[0] == ldexpf(1.0f, k + 1), "near 2^%d: m=%d", k + 1, e[0]);
    }

    /* at and beyond 2^127: saturation to 255 * 2^119 (about 1.7e38), ratios kept */
    const float top = 255.0f * 0x1p119f;
    roundtrip(0x1p127f, 0.0f, 0.0f, o, e);
    CHECK(e[0] == 255 && e[3] == 255 && o[0] == top && isfinite(o[0]));
    roundtrip(FLT_MAX, FLT_MAX / 2, 0.0f, o, e);
    CHECK(e[0] == 255 && e[1] == 128 && e[3] == 255 && o[0] == top);
    roundtrip(INFINITY, 1.0f, INFINITY, o, e);
    CHECK(e[0] == 255 && e[1] == 0 && e[2] == 255 && e[3] == 255 && o[0] == top && o[2] == top);
    roundtrip(nextafterf(0x1p127f, 0.0f), 0.0f, 0.0f, o, e); /* rounds up to 2^127 */
    CHECK(e[3] == 255 && o[0] == top);
    roundtrip(0x1.8p126f, 0x1p126f, 0.0f, o, e); /* largest binade, exact */
    CHECK(e[3] == 255 && o[0] == 0x1.8p126f && o[1] == 0x1p126f);
    uint8_t maxe[4] = { 255, 255, 255, 255 };
    lg_rgbe_decode(maxe, o);
    CHECK(o[0] == top && o[1] == top && o[2] == top);

    /* every normalised code (max mantissa >= 128) survives decode -> encode */
    for (int ex = 1; ex <= 255; ex++) {
        for (int m = 128; m <= 255; m++) {
            uint8_t in[4] = { (uint8_t)m, (uint8_t)(m / 3), (uint8_t)(255 - m), (uint8_t)ex },
                    out[4];
            float f[3];
            lg_rgbe_decode(in, f);
            if (f[0] < FLT_MIN)
                continue; /* the documented zero threshold (denormals are black) */
            lg_rgbe_encode(f, out);
            CHECKF(out[0] == in[0] && out[1] == in[1] && out[2] == in[2] && out[3] == in[3],
                   "code (%d,%d,%d,%d) -> (%d,%d,%d,%d)", in[0], in[1], in[2], in[3], out[0],
                   out[1], out[2], out[3]);
        }
        if (check_failures > 20)
            break;
    }

    /* precision: error at most half a step of the shared exponent */
    uint32_t s = 12345;
    for (int i = 0; i < 100000; i++) {
        float in[3];
        for (int c = 0; c < 3; c++) {
            s = s * 1664525u + 1013904223u;
            in[c] = ldexpf((float)(s >> 8) / 16777216.0f, (int)(s % 60) - 30);
        }
        lg_rgbe_encode(in, e);
        lg_rgbe_decode(e, o);
        double step = ldexp(1.0, e[3] - 136);
        for (int c = 0; c < 3; c++)
            CHECKF(fabs((double)o[c] - in[c]) <= 0.5 * step, "%g -> %g (step %g)", (double)in[c],
                   (double)o[c], step);
        if (check_failures > 20)
            break;
    }

    /* sRGB */
    CHECK(lg_srgb_encode(0.0f) == 0.0f && lg_srgb_encode(1.0f) == 1.0f);
    CHECK(lg_srgb_encode(-1.0f) == 0.0f && lg_srgb_encode(7.0f) == 1.0f);
    CHECK(lg_srgb_encode(NAN) == 0.0f && lg_srgb_decode(NAN) == 0.0f);
    CHECK(fabsf(lg_srgb_encode(0.0031308f) - 0.04045f) < 1e-5f);
    CHECK(fabsf(lg_srgb_encode(0.18f) - 0.46135613f) < 1e-5f); /* 1.055*0.18^(1/2.4)-0.055 */
    CHECK(fabsf(lg_srgb_decode(0.5f) - 0.21404114f) < 1e-6f);
    float prev = -1.0f;
    for (int i = 0; i <= 1000; i++) {
        float x = (float)i / 1000.0f, y = lg_srgb_encode(x);
        CHECKF(y >= prev, "encode not monotonic at %g", (double)x);
        CHECKF(fabsf(lg_srgb_decode(y) - x) <= 1e-5f + 1e-4f * x, "decode(encode(%g)) = %g",
               (double)x, (double)lg_srgb_decode(y));
        prev = y;
    }
    for (int i = 0; i < 256; i++) {
        float lin = lg_srgb_decode((float)i / 255.0f);
        int back = (int)lrintf(lg_srgb_encode(lin) * 255.0f);
        CHECKF(back == i, "8-bit code %d -> %d", i, back);
    }
    return check_report("rgbe");
}
