/*
 * The pixel formats of images (lg_format, lightgraph/types.h) to and from float RGBA, for
 * CPU producers and consumers: the policy of lightgraph/image.h ("Pixel formats").
 *
 * The clamps are written as comparisons that a NaN fails (so NaN lands on 0) rather than
 * with isnan, the same way shaders/common/rgbe.glsl and rgbe.cl write lg_half_range, so
 * that the three give the same values.
 */
#include <math.h>
#include <string.h>

#include "lightgraph/image.h"

#define HALF_MAX 65504.0f

const char *lg_format_name(lg_format f)
{
    switch (f) {
    case LG_FORMAT_RGBA32F: return "rgba32f";
    case LG_FORMAT_RGBA16F: return "rgba16f";
    case LG_FORMAT_RGBA8: return "rgba8";
    case LG_FORMAT_RGBE8: return "rgbe8";
    }
    return "unknown";
}

int lg_format_from_name(const char *name, lg_format *out)
{
    static const lg_format all[] = { LG_FORMAT_RGBA32F, LG_FORMAT_RGBA16F, LG_FORMAT_RGBA8,
                                     LG_FORMAT_RGBE8 };
    for (size_t i = 0; name && i < sizeof all / sizeof all[0]; i++)
        if (strcmp(name, lg_format_name(all[i])) == 0) {
            *out = all[i];
            return 0;
        }
    return LG_ERR_NOTFOUND;
}

/* What an rgba16f store keeps: NaN -> 0, beyond +-65504 -> +-65504 (never Inf). */
static float half_range(float v, uint64_t *n)
{
    if (v <= HALF_MAX) {
        if (v >= -HALF_MAX)
            return v;
        (*n)++;
        return v < -HALF_MAX ? -HALF_MAX : 0.0f;
    }
    (*n)++;
    return v > HALF_MAX ? HALF_MAX : 0.0f;
}

/* A display value: NaN -> 0, clamped to [0, 1]; counts values that were outside. */
static uint8_t unorm8(float v, uint64_t *n)
{
    if (!(v >= 0.0f && v <= 1.0f)) {
        (*n)++;
        v = v > 1.0f ? 1.0f : 0.0f; /* NaN and negatives: 0 */
    }
    return (uint8_t)floor((double)v * 255.0 + 0.5); /* in double: 254.5/255 stays 254 */
}

/* A channel RGBE cannot hold as it is: NaN, negative, +Inf, 2^127 and above (saturated). */
static int rgbe_replaced(float v)
{
    return !(v >= 0.0f && v < 0x1p127f);
}

int lg_pixels_from_rgba32f(lg_format f, const float *src, size_t n, void *dst, uint64_t *clamped)
{
    uint64_t count = 0;
    switch (f) {
    case LG_FORMAT_RGBA32F: memmove(dst, src, n * 16); break;
    case LG_FORMAT_RGBA16F: {
        uint16_t *h = dst;
        for (size_t i = 0; i < 4 * n; i++)
            h[i] = lg_half_from_float(half_range(src[i], &count));
        break;
    }
    case LG_FORMAT_RGBA8: {
        uint8_t *b = dst;
        for (size_t i = 0; i < 4 * n; i++)
            b[i] = unorm8(src[i], &count);
        break;
    }
    case LG_FORMAT_RGBE8: {
        uint8_t *b = dst;
        for (size_t i = 0; i < n; i++) {
            const float *p = src + 4 * i;
            count += (uint64_t)(rgbe_replaced(p[0]) + rgbe_replaced(p[1]) + rgbe_replaced(p[2]));
            lg_rgbe_encode(p, b + 4 * i);
        }
        break;
    }
    default: return LG_ERR_INVALID;
    }
    if (clamped)
        *clamped += count;
    return 0;
}

int lg_pixels_to_rgba32f(lg_format f, const void *src, size_t n, float *dst)
{
    switch (f) {
    case LG_FORMAT_RGBA32F: memmove(dst, src, n * 16); return 0;
    case LG_FORMAT_RGBA16F: {
        const uint16_t *h = src;
        /* from the end: dst may be src (a 16-byte pixel grows from an 8-byte one) */
        for (size_t i = 4 * n; i-- > 0;)
            dst[i] = lg_float_from_half(h[i]);
        return 0;
    }
    case LG_FORMAT_RGBA8: {
        const uint8_t *b = src;
        for (size_t i = 4 * n; i-- > 0;)
            dst[i] = (float)b[i] / 255.0f;
        return 0;
    }
    case LG_FORMAT_RGBE8: {
        /* lg_rgbe_decode inlined (the same bits: m * 2^(E-136), exact in float): the call
         * per pixel cost as much as the decode */
        const uint8_t *b = src;
        for (size_t i = n; i-- > 0;) {
            uint8_t q[4];
            memcpy(q, b + 4 * i, 4);
            int k = (int)q[3] - 136;
            uint32_t bits = q[3] == 0   ? 0u
                            : k >= -126 ? (uint32_t)(k + 127) << 23
                                        : 1u << (k + 149);
            float scale;
            memcpy(&scale, &bits, sizeof scale);
            dst[4 * i] = (float)q[0] * scale;
            dst[4 * i + 1] = (float)q[1] * scale;
            dst[4 * i + 2] = (float)q[2] * scale;
            dst[4 * i + 3] = 1.0f;
        }
        return 0;
    }
    }
    return LG_ERR_INVALID;
}
