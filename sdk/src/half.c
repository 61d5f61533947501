/*
 * IEEE 754 binary16 <-> binary32 conversions, bit by bit so that the rounding (to nearest,
 * ties to even) does not depend on the compiler or the FPU.
 */
#include <string.h>

#include "lightgraph/image.h"

uint16_t lg_half_from_float(float f)
{
    uint32_t x;
    memcpy(&x, &f, sizeof x);
    uint16_t sign = (uint16_t)((x >> 16) & 0x8000u);
    uint32_t a = x & 0x7fffffffu;

    if (a >= 0x7f800000u) {
        if (a == 0x7f800000u)
            return sign | 0x7c00u;
        /* NaN: keep the top payload bits and force the quiet bit, so that a payload which
         * lives only in the dropped low bits cannot turn the NaN into an infinity. */
        return (uint16_t)(sign | 0x7e00u | ((a >> 13) & 0x3ffu));
    }
    /* 65520 is halfway between 65504 (the largest half, odd mantissa) and 65536: the tie
     * goes to the even neighbour, which is infinity. */
    if (a >= 0x477ff000u)
        return sign | 0x7c00u;
    if (a >= 0x38800000u) {
        /* Normal half: rebias the exponent (127 -> 15) and round the 13 dropped bits. A
         * carry out of the mantissa correctly bumps the exponent. */
        uint32_t v = a - 0x38000000u;
        v += 0x0fffu + ((v >> 13) & 1u);
        return (uint16_t)(sign | (v >> 13));
    }
    /* Below 2^-25 everything rounds to zero; 2^-25 itself is a tie that goes to 0 (even). */
    if (a < 0x33000000u)
        return sign;
    /* Denormal half, in units of 2^-24: the float's significand m * 2^(e-150) is
     * m >> (126 - e), e in [102, 112]. A result of 0x400 is the smallest normal half,
     * which is also the right encoding. */
    uint32_t e = a >> 23;
    uint32_t m = (a & 0x7fffffu) | 0x800000u;
    uint32_t shift = 126u - e;
    uint32_t r = m >> shift;
    uint32_t rem = m & ((1u << shift) - 1u);
    uint32_t halfway = 1u << (shift - 1u);
    if (rem > halfway || (rem == halfway && (r & 1u)))
        r++;
    return (uint16_t)(sign | r);
}

float lg_float_from_half(uint16_t h)
{
    uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
    uint32_t e = (h >> 10) & 0x1fu;
    uint32_t m = h & 0x3ffu;
    uint32_t x;

    if (e == 0) {
        /* zero or denormal: m * 2^-24, exact in float */
        float f = (float)m * 0x1p-24f;
        memcpy(&x, &f, sizeof x);
        x |= sign;
    } else if (e == 31) {
        x = sign | 0x7f800000u | (m << 13);
    } else {
        x = sign | ((e + 112u) << 23) | (m << 13);
    }
    float out;
    memcpy(&out, &x, sizeof out);
    return out;
}
