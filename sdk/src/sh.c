/*
 * sh.c: lightgraph/sh.h, real spherical harmonics (conventions and sources in the header
 * and docs/sh.md).
 */
#include "lightgraph/sh.h"

#include <math.h>
#include <string.h>

#include "lightgraph/vecmath.h"

static uint32_t clamp_bands(uint32_t n)
{
    if (n < 1u)
        return 1u;
    return n > LG_SH_MAX_BANDS ? LG_SH_MAX_BANDS : n;
}

/* The normalised recurrences, written once for both precisions. With
 *   Q_l^m(z) = K_l^m P_l^m(z) / sin^m(theta)  (a polynomial in z; K and P as in sh.h),
 *   Q_0^0 = 1 / sqrt(4 pi),
 *   Q_m^m = sqrt((2m + 1) / (2m)) Q_{m-1}^{m-1},
 *   Q_{m+1}^m = sqrt(2m + 3) z Q_m^m,
 *   Q_l^m = a (z Q_{l-1}^m - b Q_{l-2}^m),
 *     a = sqrt((4l^2 - 1) / (l^2 - m^2)), b = sqrt(((l-1)^2 - m^2) / (4 (l-1)^2 - 1)),
 * and sin^m(theta) (cos m phi, sin m phi) = (C_m, S_m) = (Re, Im) (x + i y)^m by
 *   C_m = x C_{m-1} - y S_{m-1},  S_m = x S_{m-1} + y C_{m-1}.
 * The ratio factors are computed in double in both versions (they are constants; the
 * float version rounds them once). */
#define LG_SH_EVAL_BODY(T, SQRT)                                                                   \
    do {                                                                                           \
        T cm = (T)1, sm = (T)0;         /* C_m, S_m */                                             \
        T qmm = (T)(0.5 / sqrt(LG_PI)); /* Q_m^m */                                                \
        for (int m = 0; m < (int)n; m++) {                                                         \
            if (m > 0) {                                                                           \
                T c2 = x * cm - y * sm;                                                            \
                sm = x * sm + y * cm;                                                              \
                cm = c2;                                                                           \
                qmm *= (T)sqrt((2.0 * m + 1.0) / (2.0 * m));                                       \
            }                                                                                      \
            T s2 = m > 0 ? (T)SQRT((T)2) : (T)1;                                                   \
            T q2 = 0, q1 = qmm; /* Q_{l-2}^m, Q_{l-1}^m */                                         \
            for (int l = m; l < (int)n; l++) {                                                     \
                T q;                                                                               \
                if (l == m) {                                                                      \
                    q = qmm;                                                                       \
                } else if (l == m + 1) {                                                           \
                    q = (T)sqrt(2.0 * m + 3.0) * z * qmm;                                          \
                } else {                                                                           \
                    double ll = l, mm = m, l1 = l - 1;                                             \
                    T a = (T)sqrt((4.0 * ll * ll - 1.0) / (ll * ll - mm * mm));                    \
                    T b = (T)sqrt((l1 * l1 - mm * mm) / (4.0 * l1 * l1 - 1.0));                    \
                    q = a * (z * q1 - b * q2);                                                     \
                }                                                                                  \
                if (l > m) {                                                                       \
                    q2 = q1;                                                                       \
                    q1 = q;                                                                        \
                }                                                                                  \
                if (m == 0) {                                                                      \
                    out[l * (l + 1)] = q;                                                          \
                } else {                                                                           \
                    out[l * (l + 1) + m] = s2 * q * cm;                                            \
                    out[l * (l + 1) - m] = s2 * q * sm;                                            \
                }                                                                                  \
            }                                                                                      \
        }                                                                                          \
    } while (0)

void lg_sh_eval_d(uint32_t n, const double dir[3], double *out)
{
    n = clamp_bands(n);
    double x = dir[0], y = dir[1], z = dir[2];
    double ax = fabs(x), ay = fabs(y), az = fabs(z);
    double mx = fmax(ax, fmax(ay, az));
    if (!isfinite(x) || !isfinite(y) || !isfinite(z) || !(mx >= 1e-30)) {
        x = 0.0, y = 0.0, z = -1.0;
    } else {
        /* Scale first: no overflow or underflow in the squares. */
        x /= mx, y /= mx, z /= mx;
        double len = sqrt(x * x + y * y + z * z);
        x /= len, y /= len, z /= len;
    }
    LG_SH_EVAL_BODY(double, sqrt);
}

void lg_sh_eval_f(uint32_t n, const float dir[3], float *out)
{
    n = clamp_bands(n);
    float x = dir[0], y = dir[1], z = dir[2];
    float mx = fmaxf(fabsf(x), fmaxf(fabsf(y), fabsf(z)));
    if (!isfinite(x) || !isfinite(y) || !isfinite(z) || !(mx >= 1e-30f)) {
        x = 0.0f, y = 0.0f, z = -1.0f;
    } else {
        x /= mx, y /= mx, z /= mx;
        float len = sqrtf(x * x + y * y + z * z);
        x /= len, y /= len, z /= len;
    }
    LG_SH_EVAL_BODY(float, sqrtf);
}

double lg_sh_clamped_cosine(uint32_t l)
{
    if (l == 0)
        return LG_PI;
    if (l == 1)
        return 2.0 * LG_PI / 3.0;
    if (l & 1u)
        return 0.0;
    /* c_l = l! / (2^l ((l/2)!)^2) = C(l, l/2) / 2^l: c_0 = 1, c_{k+2} = c_k (k+1)/(k+2). */
    double c = 1.0;
    for (uint32_t k = 0; k < l; k += 2)
        c *= (k + 1.0) / (k + 2.0);
    double sign = ((l / 2u) & 1u) ? 1.0 : -1.0; /* (-1)^(l/2 - 1) */
    return 2.0 * LG_PI * sign / ((l + 2.0) * (l - 1.0)) * c;
}

/* ---- rotation (Ivanic and Ruedenberg 1996, erratum 1998) ------------------------------------- */

/* Offset of band l's block in the packed matrices: sum_{k<l} (2k+1)^2. */
static size_t block_offset(int l)
{
    return lg_sh_rotation_size((uint32_t)l);
}

/* Element (m, n) of band l's block, m and n in [-l, l]. */
#define BLK(base, l, m, n) ((base)[((m) + (l)) * (2 * (l) + 1) + ((n) + (l))])

/* The recurrences' P function: r1 the band-1 block, prev band l-1's block. */
static double ir_p(const double *r1, const double *prev, int i, int l, int a, int b)
{
    int lp = l - 1;
    if (b == l)
        return BLK(r1, 1, i, 1) * BLK(prev, lp, a, lp) - BLK(r1, 1, i, -1) * BLK(prev, lp, a, -lp);
    if (b == -l)
        return BLK(r1, 1, i, 1) * BLK(prev, lp, a, -lp) + BLK(r1, 1, i, -1) * BLK(prev, lp, a, lp);
    return BLK(r1, 1, i, 0) * BLK(prev, lp, a, b);
}

int lg_sh_rotation_build(uint32_t n, const double R[9], double *matrices)
{
    n = clamp_bands(n);
    for (int k = 0; k < 9; k++)
        if (!isfinite(R[k]))
            return -1;
    matrices[0] = 1.0;
    if (n < 2)
        return 0;
    /* Band 1: the basis is (y, z, x) up to one common factor, and (as coordinates of
     * g(w) = f(R^T w)) a linear function's coefficients transform by R. */
    double *r1 = matrices + block_offset(1);
    static const int perm[3] = { 1, 2, 0 }; /* m = -1, 0, 1 -> y, z, x */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r1[i * 3 + j] = R[perm[i] * 3 + perm[j]];
    for (int l = 2; l < (int)n; l++) {
        const double *prev = matrices + block_offset(l - 1);
        double *cur = matrices + block_offset(l);
        for (int m = -l; m <= l; m++) {
            int am = m < 0 ? -m : m;
            double d0 = m == 0 ? 1.0 : 0.0;
            for (int k = -l; k <= l; k++) {
                double denom = (k == l || k == -l) ? (2.0 * l) * (2.0 * l - 1.0)
                                                   : (double)(l + k) * (double)(l - k);
                double u = sqrt((double)(l + m) * (double)(l - m) / denom);
                double v = 0.5 * sqrt((1.0 + d0) * (l + am - 1.0) * (l + am) / denom) *
                           (1.0 - 2.0 * d0);
                double w = -0.5 * sqrt((l - am - 1.0) * (l - am) / denom) * (1.0 - d0);
                double val = 0.0;
                if (u != 0.0)
                    val += u * ir_p(r1, prev, 0, l, m, k);
                if (v != 0.0) {
                    double V;
                    if (m == 0) {
                        V = ir_p(r1, prev, 1, l, 1, k) + ir_p(r1, prev, -1, l, -1, k);
                    } else if (m > 0) {
                        double d1 = m == 1 ? 1.0 : 0.0;
                        V = ir_p(r1, prev, 1, l, m - 1, k) * sqrt(1.0 + d1) -
                            ir_p(r1, prev, -1, l, -m + 1, k) * (1.0 - d1);
                    } else {
                        double d1 = m == -1 ? 1.0 : 0.0;
                        V = ir_p(r1, prev, 1, l, m + 1, k) * (1.0 - d1) +
                            ir_p(r1, prev, -1, l, -m - 1, k) * sqrt(1.0 + d1);
                    }
                    val += v * V;
                }
                if (w != 0.0) {
                    double W;
                    if (m > 0)
                        W = ir_p(r1, prev, 1, l, m + 1, k) + ir_p(r1, prev, -1, l, -m - 1, k);
                    else
                        W = ir_p(r1, prev, 1, l, m - 1, k) - ir_p(r1, prev, -1, l, -m + 1, k);
                    val += w * W;
                }
                BLK(cur, l, m, k) = val;
            }
        }
    }
    return 0;
}

void lg_sh_rotate(uint32_t n, const double *matrices, const double *in, double *out)
{
    n = clamp_bands(n);
    double tmp[2 * LG_SH_MAX_BANDS - 1];
    for (int l = 0; l < (int)n; l++) {
        const double *blk = matrices + block_offset(l);
        int w = 2 * l + 1, base = l * l;
        for (int i = 0; i < w; i++) {
            double s = 0.0;
            for (int j = 0; j < w; j++)
                s += blk[i * w + j] * in[base + j];
            tmp[i] = s;
        }
        memcpy(out + base, tmp, (size_t)w * sizeof tmp[0]);
    }
}

void lg_sh_rotate_planes_f(uint32_t n, const double *matrices, uint32_t planes, const float *in,
                           float *out)
{
    n = clamp_bands(n);
    size_t nc = (size_t)n * n;
    double tmp[2 * LG_SH_MAX_BANDS - 1];
    for (uint32_t p = 0; p < planes; p++) {
        const float *src = in + p * nc;
        float *dst = out + p * nc;
        for (int l = 0; l < (int)n; l++) {
            const double *blk = matrices + block_offset(l);
            int w = 2 * l + 1, base = l * l;
            for (int i = 0; i < w; i++) {
                double s = 0.0;
                for (int j = 0; j < w; j++)
                    s += blk[i * w + j] * (double)src[base + j];
                tmp[i] = s;
            }
            for (int i = 0; i < w; i++)
                dst[base + i] = (float)tmp[i];
        }
    }
}

void lg_sh_orthonormalize(double R[9])
{
    double *a = R, *b = R + 3, *c = R + 6;
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; k++)
        a[k] /= la;
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for (int k = 0; k < 3; k++)
        b[k] -= d * a[k];
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    for (int k = 0; k < 3; k++)
        b[k] /= lb;
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* ---- windowing (Sloan 2008) ------------------------------------------------------------------ */

double lg_sh_window_factor(lg_sh_window_kind kind, double width, uint32_t l)
{
    if (!(width > 0.0) || !isfinite(width) || l == 0)
        return 1.0;
    if (kind == LG_SH_WINDOW_GAUSSIAN)
        return exp(-(double)l * (l + 1.0) / (width * (width + 1.0)));
    double t = (double)l / width;
    if (t >= 1.0)
        return 0.0;
    if (kind == LG_SH_WINDOW_LANCZOS)
        return sin(LG_PI * t) / (LG_PI * t);
    return 0.5 * (1.0 + cos(LG_PI * t));
}

void lg_sh_window(uint32_t n, lg_sh_window_kind kind, double width, double *coeffs)
{
    n = clamp_bands(n);
    for (uint32_t l = 0; l < n; l++) {
        double f = lg_sh_window_factor(kind, width, l);
        for (uint32_t i = l * l; i < (l + 1) * (l + 1); i++)
            coeffs[i] *= f;
    }
}
