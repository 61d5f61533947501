/*
 * lightgraph/color.h: luminance weights and small colour helpers, header-only.
 *
 * The project's luminance is Rec.709 (0.2126, 0.7152, 0.0722). Seed 0 uses
 * (0.2125, 0.7154, 0.0721); nodes that compute luminance offer both as an enum
 * parameter `luminance = rec709 | seed`.
 */
#ifndef LIGHTGRAPH_COLOR_H
#define LIGHTGRAPH_COLOR_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lg_luma_weights { LG_LUMA_REC709 = 0, LG_LUMA_SEED0 = 1 } lg_luma_weights;

static inline void lg_luma_coeffs(lg_luma_weights w, float out[3])
{
    if (w == LG_LUMA_SEED0) {
        out[0] = 0.2125f;
        out[1] = 0.7154f;
        out[2] = 0.0721f;
    } else {
        out[0] = 0.2126f;
        out[1] = 0.7152f;
        out[2] = 0.0722f;
    }
}

static inline float lg_luma(const float rgb[3], const float w[3])
{
    return w[0] * rgb[0] + w[1] * rgb[1] + w[2] * rgb[2];
}

#ifdef __cplusplus
}
#endif
#endif
