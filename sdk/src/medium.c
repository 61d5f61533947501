/* lightgraph/medium.h: Henyey-Greenstein, the segment factor, slice maps, density fields,
 * point and spot lights. */
#include "lightgraph/medium.h"

#include <float.h>
#include <math.h>
#include <stdint.h>

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

/* ---- density fields -------------------------------------------------------------------------- */

/* A 32-bit integer hash (the finaliser of MurmurHash3) of a lattice point and a seed. */
static uint32_t lattice_hash(int32_t i, int32_t j, int32_t k, uint32_t seed)
{
    uint32_t h = seed * 0x9e3779b9u;
    h ^= (uint32_t)i * 0x85ebca6bu;
    h = (h << 13) | (h >> 19);
    h ^= (uint32_t)j * 0xc2b2ae35u;
    h = (h << 13) | (h >> 19);
    h ^= (uint32_t)k * 0x27d4eb2fu;
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

/* dot(gradient h % 12, (x, y, z)) over Perlin's 12 edge-midpoint gradients. */
static double grad_dot(uint32_t h, double x, double y, double z)
{
    switch (h % 12u) {
    case 0: return x + y;
    case 1: return -x + y;
    case 2: return x - y;
    case 3: return -x - y;
    case 4: return x + z;
    case 5: return -x + z;
    case 6: return x - z;
    case 7: return -x - z;
    case 8: return y + z;
    case 9: return -y + z;
    case 10: return y - z;
    default: return -y - z;
    }
}

static double fade(double t)
{
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

double lg_noise3(double x, double y, double z, uint32_t seed)
{
    if (!isfinite(x) || !isfinite(y) || !isfinite(z))
        return 0.0;
    double fx = floor(x), fy = floor(y), fz = floor(z);
    /* far from the origin the lattice wraps (the hash sees 32-bit coordinates) */
    int32_t i = (int32_t)(int64_t)fmod(fx, 2147483648.0);
    int32_t j = (int32_t)(int64_t)fmod(fy, 2147483648.0);
    int32_t k = (int32_t)(int64_t)fmod(fz, 2147483648.0);
    double x0 = x - fx, y0 = y - fy, z0 = z - fz;
    double u = fade(x0), v = fade(y0), w = fade(z0);
    double n[8];
    for (int c = 0; c < 8; c++) {
        int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
        n[c] = grad_dot(lattice_hash(i + dx, j + dy, k + dz, seed), x0 - dx, y0 - dy, z0 - dz);
    }
    double a = n[0] + u * (n[1] - n[0]), b = n[2] + u * (n[3] - n[2]);
    double c0 = n[4] + u * (n[5] - n[4]), d0 = n[6] + u * (n[7] - n[6]);
    double e = a + v * (b - a), f = c0 + v * (d0 - c0);
    double r = e + w * (f - e);
    return r < -1.0 ? -1.0 : r > 1.0 ? 1.0 : r;
}

double lg_fbm3(const lg_density_fbm *f, const double p[3])
{
    double sum = 0.0, amp = 1.0, freq = f->frequency;
    uint32_t oct = f->octaves > 16 ? 16 : f->octaves;
    for (uint32_t o = 0; o < oct; o++) {
        sum += amp * lg_noise3(freq * p[0], freq * p[1], freq * p[2], f->seed + o);
        amp *= f->gain;
        freq *= f->lacunarity;
    }
    return sum;
}

/* The trilinear blend of a grid at index point q, voxels outside counting 0. */
static double grid_at(const lg_density_grid *g, const double p[3])
{
    const double *m = g->world_to_index;
    double q[3];
    for (int r = 0; r < 3; r++)
        q[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    if (!(q[0] > -1.0 && q[1] > -1.0 && q[2] > -1.0 && q[0] < (double)g->nx &&
          q[1] < (double)g->ny && q[2] < (double)g->nz))
        return 0.0;
    double fq[3];
    int64_t i0[3];
    for (int r = 0; r < 3; r++) {
        double fl = floor(q[r]);
        i0[r] = (int64_t)fl;
        fq[r] = q[r] - fl;
    }
    int64_t n[3] = { g->nx, g->ny, g->nz };
    double sum = 0.0;
    for (int c = 0; c < 8; c++) {
        int64_t ix = i0[0] + (c & 1), iy = i0[1] + ((c >> 1) & 1), iz = i0[2] + ((c >> 2) & 1);
        if (ix < 0 || iy < 0 || iz < 0 || ix >= n[0] || iy >= n[1] || iz >= n[2])
            continue;
        double wgt = ((c & 1) ? fq[0] : 1.0 - fq[0]) * (((c >> 1) & 1) ? fq[1] : 1.0 - fq[1]) *
                     (((c >> 2) & 1) ? fq[2] : 1.0 - fq[2]);
        sum +=
            wgt *
            (double)g->values[(size_t)ix + (size_t)n[0] * ((size_t)iy + (size_t)n[1] * (size_t)iz)];
    }
    return sum;
}

bool lg_medium_is_heterogeneous(const lg_medium *m)
{
    return m && m->field != NULL;
}

double lg_medium_field_at(const lg_medium *m, const double p[3])
{
    const lg_density_field *f = m ? m->field : NULL;
    if (!f)
        return 1.0;
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
        return 0.0;
    for (int c = 0; c < 3; c++)
        if (!(p[c] >= (double)f->bounds_min[c] && p[c] <= (double)f->bounds_max[c]))
            return 0.0;
    double v = 1.0;
    if (f->kind == LG_FIELD_GRID)
        v = f->grid ? grid_at(f->grid, p) : 0.0;
    else if (f->kind == LG_FIELD_FBM)
        v = (double)f->fbm.scale * fmax(0.0, lg_fbm3(&f->fbm, p) - (double)f->fbm.offset);
    if (f->height_falloff > 0.0f && v > 0.0)
        v *= exp(-(double)f->height_falloff * (p[1] - (double)f->height_base));
    return v > 0.0 && isfinite(v) ? v : 0.0;
}

double lg_medium_field_max(const lg_medium *m, const double lo[3], const double hi[3])
{
    const lg_density_field *f = m ? m->field : NULL;
    if (!f)
        return 1.0;
    double blo[3], bhi[3];
    for (int c = 0; c < 3; c++) {
        blo[c] = fmax(lo[c], (double)f->bounds_min[c]);
        bhi[c] = fmin(hi[c], (double)f->bounds_max[c]);
        if (!(blo[c] <= bhi[c]))
            return 0.0;
    }
    double v = 1.0;
    if (f->kind == LG_FIELD_GRID) {
        v = f->grid ? (double)f->grid->max_value : 0.0;
    } else if (f->kind == LG_FIELD_FBM) {
        double sum = 0.0, amp = 1.0;
        for (uint32_t o = 0; o < f->fbm.octaves && o < 16; o++, amp *= f->fbm.gain)
            sum += amp;
        v = (double)f->fbm.scale * fmax(0.0, sum - (double)f->fbm.offset);
    }
    if (f->height_falloff > 0.0f)
        v *= exp(-(double)f->height_falloff * (blo[1] - (double)f->height_base));
    return isfinite(v) ? v : DBL_MAX;
}

/* ---- point and spot lights ------------------------------------------------------------------- */

double lg_light_window(double d, double range)
{
    if (!(range > 0.0) || !isfinite(range))
        return 1.0;
    double r = d / range;
    double r2 = r * r;
    return clampd(1.0 - r2 * r2, 0.0, 1.0);
}

double lg_spot_cone(double cos_angle, double cos_inner, double cos_outer)
{
    double span = cos_inner - cos_outer;
    if (span < 1e-4)
        span = 1e-4;
    double t = clampd((cos_angle - cos_outer) / span, 0.0, 1.0);
    return t * t;
}

double lg_light_falloff(const lg_light *l, const double p[3], double to_light[3], double *dist)
{
    if (l->type == LG_LIGHT_DIRECTIONAL) {
        double dl = sqrt((double)l->direction[0] * l->direction[0] +
                         (double)l->direction[1] * l->direction[1] +
                         (double)l->direction[2] * l->direction[2]);
        if (to_light)
            for (int c = 0; c < 3; c++)
                to_light[c] = dl > 0.0 ? -(double)l->direction[c] / dl : 0.0;
        if (dist)
            *dist = INFINITY;
        return 1.0;
    }
    double v[3], d2 = 0.0;
    for (int c = 0; c < 3; c++) {
        v[c] = (double)l->position[c] - p[c];
        d2 += v[c] * v[c];
    }
    double d = sqrt(d2);
    double axis[3] = { l->direction[0], l->direction[1], l->direction[2] };
    double al = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (int c = 0; c < 3; c++)
        axis[c] = al > 0.0 ? axis[c] / al : (c == 1 ? -1.0 : 0.0);
    double lu[3];
    for (int c = 0; c < 3; c++)
        lu[c] = d > 0.0 ? v[c] / d : -axis[c];
    if (to_light)
        for (int c = 0; c < 3; c++)
            to_light[c] = lu[c];
    if (dist)
        *dist = d;
    double f = lg_light_window(d, l->range) / (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
    if (l->type == LG_LIGHT_SPOT) {
        double ca = -(lu[0] * axis[0] + lu[1] * axis[1] + lu[2] * axis[2]);
        f *= lg_spot_cone(ca, cos(l->inner_cone), cos(l->outer_cone));
    }
    return f;
}

/* Gauss-Legendre nodes and weights on [-1, 1] for 1 .. 8 points (positive half; the rule is
 * symmetric). */
static const double gl_x[8][4] = {
    { 0.0 },
    { 0.5773502691896257645 },
    { 0.0, 0.7745966692414833770 },
    { 0.3399810435848562648, 0.8611363115940525752 },
    { 0.0, 0.5384693101056830910, 0.9061798459386639928 },
    { 0.2386191860831969086, 0.6612093864662645137, 0.9324695142031520279 },
    { 0.0, 0.4058451513773971669, 0.7415311855993944399, 0.9491079123427585245 },
    { 0.1834346424956498049, 0.5255324099163289858, 0.7966664774136267396, 0.9602898564975362317 },
};
static const double gl_w[8][4] = {
    { 2.0 },
    { 1.0 },
    { 0.8888888888888888889, 0.5555555555555555556 },
    { 0.6521451548625461427, 0.3478548451374538574 },
    { 0.5688888888888888889, 0.4786286704993664680, 0.2369268850561890875 },
    { 0.4679139345726910473, 0.3607615730481386076, 0.1713244923791703450 },
    { 0.4179591836734693878, 0.3818300505051189449, 0.2797053914892766679, 0.1294849661688696933 },
    { 0.3626837833783619830, 0.3137066458778872873, 0.2223810344533744706, 0.1012285362903762592 },
};

/* The rule's i-th node (0 .. n-1) on [-1, 1] and its weight. */
static void gl_node(int n, int i, double *x, double *w)
{
    int half = n / 2;
    const double *xs = gl_x[n - 1], *ws = gl_w[n - 1];
    if (n % 2 == 1) {
        /* odd: entry 0 is the centre */
        int k = i - half;
        int a = k < 0 ? -k : k;
        *x = k < 0 ? -xs[a] : xs[a];
        *w = ws[a];
    } else {
        int k = i < half ? half - 1 - i : i - half;
        *x = i < half ? -xs[k] : xs[k];
        *w = ws[k];
    }
}

/* Clips [*a, *b] along the ray to where the light can reach: within `range` of the light
 * (range > 0) and inside a spot's outer cone (convex for cos_outer >= 0: one interval; a
 * wider cone is not clipped). The integrand is 0 outside, and its kinks there (the
 * window's and the cone's edges) cost a Gauss-Legendre rule over the whole segment most of
 * its accuracy (up to tens of percent at 8 nodes on a narrow cone). Worked in s = t - tc
 * from the ray's closest point to the light, y0 = that point - q (|y0|^2 = h2, y0 . w =
 * 0): the cone's quadratic (y.a)^2 - cos_outer^2 |y|^2 in s then has coefficients of the
 * size of h, not of |o - q| (whose cancellation moved the roots near the apex by 1e-3 in
 * float, where the integrand is largest). Its roots within the segment, s = 0 (a line
 * through the apex has a double root there) and the ends split the segment; the pieces
 * whose middle is inside (y.a >= cos_outer |y|) are kept, one interval since the cone is
 * convex. False when nothing is left. */
/* light_clip's test of the piece [p0, p1]: inside the cone at its middle widens [lo, hi]. */
static void clip_piece(const double y0[3], const double w[3], const double *spot, double p0,
                       double p1, double *lo, double *hi)
{
    double m = 0.5 * (p0 + p1), y[3];
    for (int c = 0; c < 3; c++)
        y[c] = y0[c] + m * w[c];
    double yax = y[0] * spot[0] + y[1] * spot[1] + y[2] * spot[2];
    if (yax >= spot[4] * sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])) {
        *lo = fmin(*lo, p0);
        *hi = fmax(*hi, p1);
    }
}

static bool light_clip(const double y0[3], const double w[3], double tc, double h2, double range,
                       const double *spot, double *a, double *b)
{
    double sa = *a - tc, sb = *b - tc;
    if (range > 0.0 && isfinite(range)) {
        double r2 = range * range - h2;
        if (!(r2 > 0.0))
            return false;
        double r = sqrt(r2);
        sa = fmax(sa, -r);
        sb = fmin(sb, r);
    }
    if (spot && spot[4] >= 0.0 && sb > sa) {
        double co2 = spot[4] * spot[4];
        double ya = y0[0] * spot[0] + y0[1] * spot[1] + y0[2] * spot[2];
        double wa = w[0] * spot[0] + w[1] * spot[1] + w[2] * spot[2];
        double A = wa * wa - co2, B = 2.0 * ya * wa, C = ya * ya - co2 * h2;
        /* the breakpoints: the ends, the roots (a negative discriminant from rounding at a
         * tangent line taken as 0: a spare breakpoint costs nothing) and s = 0 (a line
         * through the apex has a double root there, which rounding may lose), each set to
         * sb when outside (sa, sb); sorted by a fixed network (no indexed array: the
         * shaders' twins stay plain) */
        double b1 = 0.0 > sa && 0.0 < sb ? 0.0 : sb, b2 = sb, b3 = sb;
        double disc = fmax(B * B - 4.0 * A * C, 0.0);
        if (A != 0.0) {
            double qq = -0.5 * (B + (B >= 0.0 ? sqrt(disc) : -sqrt(disc)));
            double r0 = qq / A, r1 = qq != 0.0 ? C / qq : r0;
            b2 = r0 > sa && r0 < sb ? r0 : sb;
            b3 = r1 > sa && r1 < sb ? r1 : sb;
        } else if (B != 0.0) {
            double r = -C / B;
            b2 = r > sa && r < sb ? r : sb;
        }
        double tmp;
        if (b2 < b1)
            tmp = b1, b1 = b2, b2 = tmp;
        if (b3 < b2)
            tmp = b2, b2 = b3, b3 = tmp;
        if (b2 < b1)
            tmp = b1, b1 = b2, b2 = tmp;
        double lo = INFINITY, hi = -INFINITY;
        clip_piece(y0, w, spot, sa, b1, &lo, &hi);
        clip_piece(y0, w, spot, b1, b2, &lo, &hi);
        clip_piece(y0, w, spot, b2, b3, &lo, &hi);
        clip_piece(y0, w, spot, b3, sb, &lo, &hi);
        sa = lo;
        sb = hi;
    }
    *a = tc + sa;
    *b = tc + sb;
    return sb > sa;
}

double lg_point_inscatter(const double o[3], const double w[3], double t0, double t1,
                          const double q[3], double range, const double *spot, double g,
                          double sigma_t, int nodes)
{
    if (!(t1 > t0))
        return 0.0;
    if (nodes < 1)
        nodes = 1;
    if (nodes > 64)
        nodes = 64;
    double qo[3], tc = 0.0;
    for (int c = 0; c < 3; c++) {
        qo[c] = q[c] - o[c];
        tc += qo[c] * w[c];
    }
    /* h from the light's offset perpendicular to the ray, not as |qo|^2 - tc^2: that
     * difference cancels when the ray passes close to the light (in float, to nothing at
     * h ~ 1e-3 |qo|, the glow's brightest pixels); the point at t is then perp - s w,
     * s = t - tc, without the cancellation of qo - t w near t = tc either */
    double perp[3], h2 = 0.0;
    for (int c = 0; c < 3; c++) {
        perp[c] = qo[c] - tc * w[c];
        h2 += perp[c] * perp[c];
    }
    double H = sqrt(h2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
    /* the nodes go where the light reaches; the extinction still counts from t0 */
    double ta = t0, tb = t1, y0[3] = { -perp[0], -perp[1], -perp[2] };
    if (!light_clip(y0, w, tc, h2, range, spot, &ta, &tb))
        return 0.0;
    double xi0 = atan((ta - tc) / H), xi1 = atan((tb - tc) / H);
    int panels = (nodes + 7) / 8, per = (nodes + panels - 1) / panels;
    double sum = 0.0, width = (xi1 - xi0) / panels;
    double cos_inner = spot ? spot[3] : 1.0, cos_outer = spot ? spot[4] : -1.0;
    for (int pn = 0; pn < panels; pn++) {
        double a = xi0 + pn * width;
        for (int i = 0; i < per; i++) {
            double x, wt;
            gl_node(per, i, &x, &wt);
            double xi = a + 0.5 * width * (x + 1.0);
            double sx = H * tan(xi), t = tc + sx;
            double l[3], d2 = 0.0;
            for (int c = 0; c < 3; c++) {
                l[c] = perp[c] - sx * w[c];
                d2 += l[c] * l[c];
            }
            double d = sqrt(d2);
            double cw = d > 0.0 ? (l[0] * w[0] + l[1] * w[1] + l[2] * w[2]) / d : 0.0;
            double f = lg_hg_phase(g, cw) * lg_light_window(d, range);
            if (spot) {
                double ca = d > 0.0 ? -(l[0] * spot[0] + l[1] * spot[1] + l[2] * spot[2]) / d : 1.0;
                f *= lg_spot_cone(ca, cos_inner, cos_outer);
            }
            if (sigma_t > 0.0)
                f *= exp(-sigma_t * ((t - t0) + d));
            sum += 0.5 * width * wt * f;
        }
    }
    return sum / H;
}
