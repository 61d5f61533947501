/*
 * Ward's RGBE (shared exponent) and the sRGB transfer function.
 *
 * Convention: a channel c with shared exponent byte E decodes to m * 2^(E - 136), with no
 * half-step offset, and encodes to round(c * 2^(136 - E)). Rounding to nearest keeps the
 * reconstruction unbiased (Radiance instead truncates on encode and adds 0.5 on decode);
 * dropping the +0.5 is what makes exact powers of two round trip exactly (mantissa 128).
 * The seed's exponent, ceil(log2(max)), gave a mantissa of exactly 1.0 (256) for powers of
 * two; frexp's mantissa is in [0.5, 1), and the one rounding case that reaches 256 bumps
 * the exponent instead.
 */
#include <float.h>
#include <math.h>
#include <string.h>

#include "lightgraph/image.h"

/* NaN and negative channels carry no light that RGBE can store. */
static double rgbe_sanitize(float c)
{
    return (c > 0.0f) ? (double)c : 0.0;
}

void lg_rgbe_encode(const float rgb[3], uint8_t rgbe[4])
{
    double c[3] = { rgbe_sanitize(rgb[0]), rgbe_sanitize(rgb[1]), rgbe_sanitize(rgb[2]) };
    double max = c[0] > c[1] ? c[0] : c[1];
    if (c[2] > max)
        max = c[2];

    /* Below FLT_MIN (a float denormal) is black: a GPU flushes denormals to zero, and with
     * this rule the twins in shaders/common/rgbe.glsl and rgbe.cl give the same bytes
     * (tests/unit/formats/test_rgbe_devices.c). */
    if (!(max >= FLT_MIN)) {
        rgbe[0] = rgbe[1] = rgbe[2] = rgbe[3] = 0;
        return;
    }

    int e = 0;
    int saturate = isinf(max);
    if (!saturate) {
        double mant = frexp(max, &e); /* max = mant * 2^e, mant in [0.5, 1) */
        if (floor(mant * 256.0 + 0.5) >= 256.0)
            e++;            /* rounds up to the next power of two: mantissa 128 there */
        saturate = e > 127; /* exponent byte e + 128 must fit in 255 */
    }
    if (saturate) {
        /* The largest value RGBE holds is 255 * 2^(255-136), about 1.7e38: the largest
         * channel gets it, the others keep their ratio to it (0 beside an infinity).
         * In float, step by step as the GPU twins compute it, so that the bytes agree
         * (in double, 0.7 * 2^127 / 2^127 * 255 rounds to 178, in float to 179). */
        for (int i = 0; i < 3; i++) {
            float ratio = isinf(max) ? (isinf(c[i]) ? 1.0f : 0.0f) : (float)c[i] / (float)max;
            float scaled = ratio * 255.0f;
            rgbe[i] = (uint8_t)floorf(scaled + 0.5f);
        }
        rgbe[3] = 255;
        return;
    }

    double scale = ldexp(1.0, 8 - e); /* exact: a power of two */
    for (int i = 0; i < 3; i++) {
        double m = floor(c[i] * scale + 0.5);
        rgbe[i] = (uint8_t)(m > 255.0 ? 255.0 : m);
    }
    rgbe[3] = (uint8_t)(e + 128);
}

void lg_rgbe_decode(const uint8_t rgbe[4], float rgb[3])
{
    if (rgbe[3] == 0) {
        rgb[0] = rgb[1] = rgb[2] = 0.0f;
        return;
    }
    /* 2^(E-136) ranges over 2^-135 .. 2^119, every one a float (below 2^-126 a denormal),
     * made from its bits (ldexp in double cost 4x more in a decode loop); every
     * m * 2^(E-136) is then exact in float (at most 8 significant bits, none below 2^-149). */
    int k = (int)rgbe[3] - 136;
    uint32_t bits = k >= -126 ? (uint32_t)(k + 127) << 23 : 1u << (k + 149);
    float f;
    memcpy(&f, &bits, sizeof f);
    for (int i = 0; i < 3; i++)
        rgb[i] = (float)rgbe[i] * f;
}

float lg_srgb_encode(float linear)
{
    if (!(linear > 0.0f))
        return 0.0f; /* also NaN */
    if (linear >= 1.0f)
        return 1.0f;
    if (linear <= 0.0031308f)
        return 12.92f * linear;
    return 1.055f * powf(linear, 1.0f / 2.4f) - 0.055f;
}

float lg_srgb_decode(float encoded)
{
    if (!(encoded > 0.0f))
        return 0.0f;
    if (encoded >= 1.0f)
        return 1.0f;
    if (encoded <= 0.04045f)
        return encoded / 12.92f;
    return powf((encoded + 0.055f) / 1.055f, 2.4f);
}
