/* lightgraph/medium.h: Henyey-Greenstein, the segment factor, slice maps. */
#include "lightgraph/medium.h"

#include <math.h>

#include "lightgraph/vecmath.h"

static double clampd(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

double lg_hg_phase(double g, double c)
{
    if (!(g == g))
        g = 0.0;
    if (!(c == c))
        c = 1.0;
    g = clampd(g, -LG_HG_G_MAX, LG_HG_G_MAX);
    c = clampd(c, -1.0, 1.0);
    /* (1 - g)^2 + 2g(1 - c) = 1 + g^2 - 2gc without the cancellation at g -> 1, c -> 1;
     * for g < 0 the same holds at c -> -1 with (1 + g)^2 - 2g(1 + c). */
    double den = g >= 0.0 ? (1.0 - g) * (1.0 - g) + 2.0 * g * (1.0 - c)
                          : (1.0 + g) * (1.0 + g) - 2.0 * g * (1.0 + c);
    return (1.0 - g) * (1.0 + g) / (4.0 * LG_PI * den * sqrt(den));
}

float lg_hg_phasef(float g, float c)
{
    if (!(g == g))
        g = 0.0f;
    if (!(c == c))
        c = 1.0f;
    const float gmax = (float)LG_HG_G_MAX;
    g = g < -gmax ? -gmax : g > gmax ? gmax : g;
    c = c < -1.0f ? -1.0f : c > 1.0f ? 1.0f : c;
    float den = g >= 0.0f ? (1.0f - g) * (1.0f - g) + 2.0f * g * (1.0f - c)
                          : (1.0f + g) * (1.0f + g) - 2.0f * g * (1.0f + c);
    return (1.0f - g) * (1.0f + g) / (4.0f * (float)LG_PI * den * sqrtf(den));
}

double lg_medium_segment(double tau)
{
    if (!(tau > 0.0))
        return 1.0;
    if (tau < 1e-8)
        return 1.0 - 0.5 * tau;
    return -expm1(-tau) / tau;
}

float lg_medium_segmentf(float tau)
{
    /* The kernels have no expm1: below 1/4 the series to tau^5 (truncation < tau^6/5040 <
     * 5e-8), above it the quotient, whose cancellation costs about 2^-24 / tau < 3e-7
     * relative. The C float version follows the kernels so that the three agree. */
    if (!(tau > 0.0f))
        return 1.0f;
    if (tau < 0.25f)
        return 1.0f - tau * (0.5f - tau * (1.0f / 6.0f -
                                           tau * (1.0f / 24.0f -
                                                  tau * (1.0f / 120.0f - tau * (1.0f / 720.0f)))));
    return (1.0f - expf(-tau)) / tau;
}

double lg_medium_inscatter(double l_c, double sigma_s, double sigma_t, double phase, double length)
{
    if (!(length > 0.0))
        return 0.0;
    return l_c * sigma_s * phase * length * lg_medium_segment(sigma_t * length);
}

void lg_medium_coeffs(const lg_medium *m, float sigma_s[3], float sigma_t[3])
{
    for (int c = 0; c < 3; c++) {
        sigma_s[c] = sigma_t[c] = 0.0f;
        if (m && m->present && m->density > 0.0f) {
            sigma_s[c] = m->density * m->scattering[c];
            sigma_t[c] = sigma_s[c] + m->density * m->absorption[c];
        }
    }
}

void lg_light_color(const lg_light *light, float l_c[3])
{
    for (int c = 0; c < 3; c++)
        l_c[c] = light ? light->color[c] * light->intensity : 0.0f;
}

int lg_slice_map_init(lg_slice_map *map, lg_froxel_slicing slicing, uint32_t depth, double near,
                      double far, double near_offset)
{
    if (!map || depth < 1 || !(near > 0.0) || !(far > near) || !isfinite(far))
        return -1;
    if (slicing == LG_FROXEL_EXPONENTIAL) {
        if (depth > 1 && !(near_offset > near && near_offset < far))
            return -1;
    } else if (slicing != LG_FROXEL_UNIFORM_CLIP) {
        return -1;
    }
    map->slicing = slicing;
    map->depth = depth;
    map->near = near;
    map->far = far;
    map->near_offset = slicing == LG_FROXEL_EXPONENTIAL ? near_offset : 0.0;
    return 0;
}

double lg_slice_to_depth(const lg_slice_map *m, double z)
{
    double D = (double)m->depth;
    if (m->slicing == LG_FROXEL_EXPONENTIAL) {
        if (m->depth == 1)
            return m->near + z * (m->far - m->near);
        if (z <= 1.0)
            return m->near + z * (m->near_offset - m->near);
        return m->near_offset * pow(m->far / m->near_offset, (z - 1.0) / (D - 1.0));
    }
    return 1.0 / (1.0 / m->near + (z / D) * (1.0 / m->far - 1.0 / m->near));
}

double lg_depth_to_slice(const lg_slice_map *m, double t)
{
    double D = (double)m->depth;
    if (m->slicing == LG_FROXEL_EXPONENTIAL) {
        if (m->depth == 1)
            return (t - m->near) / (m->far - m->near);
        if (t <= m->near_offset)
            return (t - m->near) / (m->near_offset - m->near);
        return 1.0 + (D - 1.0) * log(t / m->near_offset) / log(m->far / m->near_offset);
    }
    if (!(t > 0.0))
        return 0.0;
    return D * (1.0 / t - 1.0 / m->near) / (1.0 / m->far - 1.0 / m->near);
}

int lg_slice_map_from_info(lg_slice_map *map, const lg_froxel_info *info)
{
    if (!info)
        return -1;
    return lg_slice_map_init(map, info->slicing, info->depth, info->near, info->far,
                             info->near_offset);
}
