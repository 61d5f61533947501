/*
 * The known values of the prt tests: shared by the test plugin (testprtinputs.c, which
 * publishes them as LG_KIND_SH and LG_KIND_TRANSFER) and the test (test_prt.c, whose C
 * reference recomputes them), so that both sides see the same numbers without files.
 */
#ifndef LG_PRT_TESTDATA_H
#define LG_PRT_TESTDATA_H

#include <stdint.h>

/* A value in [-1, 1) from (seed, a, b, c): a 64-bit mix (splitmix64's finaliser), exactly
 * representable in float (24 bits). */
static inline float prt_test_value(uint32_t seed, uint32_t a, uint32_t b, uint32_t c)
{
    uint64_t x = ((uint64_t)seed << 48) ^ ((uint64_t)a << 20) ^ ((uint64_t)b << 10) ^ c;
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
    return (float)((double)(x >> 40) / (double)(1u << 23) - 1.0);
}

/* SH lighting, mode random: coefficient i of channel c (in [-1, 1), band l scaled by
 * 1 / (1 + l) so that the sums stay well conditioned). */
static inline float prt_test_light(uint32_t seed, uint32_t c, uint32_t i)
{
    uint32_t l = 0;
    while ((l + 1) * (l + 1) <= i)
        l++;
    return prt_test_value(seed, 0xfffffu, c, i) / (float)(1 + l);
}

/* Transfer, mode random: vertex v, channel c, coefficient i. */
static inline float prt_test_transfer(uint32_t seed, uint32_t v, uint32_t c, uint32_t i)
{
    return prt_test_value(seed, v, c, i);
}

#endif
