/*
 * The test oracle of the reinhard plugin (reinhard_oracle.h): plain C, one pixel at a
 * time, double precision for the sum and the curve. This was the plugin's `cpu` backend
 * until the float, vectorised, threaded one (plugins/reinhard/reinhard_cpu.c) replaced it.
 */
#include "reinhard_oracle.h"

#include <math.h>
#include <string.h>

void lg_rh_ref_reduce(const float *rgba, size_t n, const lg_rh_params *p, lg_rh_stats *st)
{
    double sum = 0.0;
    uint64_t valid = 0, nonfinite = 0, negative = 0;
    for (size_t i = 0; i < n; i++) {
        const float *px = rgba + i * 4;
        if (!isfinite(px[0]) || !isfinite(px[1]) || !isfinite(px[2])) {
            nonfinite++;
            continue;
        }
        float l = lg_rh_luma(px, p->w);
        if (!isfinite(l)) { /* finite channels whose weighted sum overflows */
            nonfinite++;
            continue;
        }
        if (l < 0.0f) {
            negative++;
            continue;
        }
        sum += log(p->delta + (double)l);
        valid++;
    }
    st->log_sum += sum;
    st->valid += valid;
    st->nonfinite += nonfinite;
    st->negative += negative;
}

double lg_rh_ref_curve(double x, double inv_white2)
{
    if (isinf(x))
        return 1.0;
    double g = x / (1.0 + x);
    if (inv_white2 > 0.0) {
        g *= 1.0 + x * inv_white2;
        if (g > 1.0)
            g = 1.0;
    }
    return g;
}

void lg_rh_ref_map(const float *in, float *out, size_t n, double scale, const lg_rh_params *p)
{
    double inv_w2 = p->white > 0.0 ? 1.0 / (p->white * p->white) : 0.0;
    for (size_t i = 0; i < n; i++) {
        const float *src = in + i * 4;
        float *dst = out + i * 4;
        float c[3];
        bool inf[3], any_inf = false;
        for (int k = 0; k < 3; k++) {
            float v = src[k];
            inf[k] = isinf(v) && v > 0.0f;
            any_inf |= inf[k];
            /* NaN and negative (-Inf included) read as 0; +Inf is handled below */
            c[k] = (isnan(v) || v < 0.0f || inf[k]) ? 0.0f : v;
        }
        float alpha = src[3];

        if (p->mode == LG_RH_RGB) {
            for (int k = 0; k < 3; k++)
                dst[k] = inf[k] ? 1.0f : (float)lg_rh_ref_curve(scale * (double)c[k], inv_w2);
        } else if (any_inf) {
            /* lim c Ld / L as L -> Inf: 1 for the infinite channels, 0 for the others */
            for (int k = 0; k < 3; k++)
                dst[k] = inf[k] ? 1.0f : 0.0f;
        } else {
            /* both weight sets sum to at most 1 in float: L <= max(c), never Inf */
            float l = lg_rh_luma(c, p->w);
            float r[3] = { 0.0f, 0.0f, 0.0f }; /* black: all channels 0 */
            if (l > 0.0f)
                for (int k = 0; k < 3; k++)
                    r[k] = c[k] / l;
            double ld = lg_rh_ref_curve(scale * (double)l, inv_w2);
            for (int k = 0; k < 3; k++)
                dst[k] = (float)((double)r[k] * ld);
        }
        dst[3] = alpha;
    }
}
