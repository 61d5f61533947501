/*
 * lightgraph/vecmath.h: pi and its kin, small vector and matrix helpers, header-only.
 *
 * Conventions (the project's, see TECHNIQUES.md): right-handed, Y-up world as glTF;
 * angles in radians; matrices are 4x4 floats in column-major order (OpenGL's and glTF's:
 * element (row r, column c) is m[c * 4 + r]), acting on column vectors: p' = M p.
 */
#ifndef LIGHTGRAPH_VECMATH_H
#define LIGHTGRAPH_VECMATH_H

#include <math.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Pi and the multiples a renderer keeps dividing by, as double constants (macros, usable
 * in constant expressions and in C++), each written to more digits than a double holds so
 * that it is the double nearest the exact value. Use these rather than M_PI (not in C11:
 * <math.h> defines it only with POSIX or GNU extensions) or a value typed out by hand.
 *
 *   LG_PI           pi                     3.14159...   half a turn, in radians
 *   LG_TWO_PI       2 pi                   6.28318...   a full turn
 *   LG_HALF_PI      pi / 2                 1.57079...   a quarter turn
 *   LG_INV_PI       1 / pi                 0.31830...   Lambert's BRDF is albedo * LG_INV_PI
 *   LG_INV_TWO_PI   1 / (2 pi)             0.15915...   the density of a uniform angle
 *   LG_INV_FOUR_PI  1 / (4 pi)             0.07957...   the density of a uniform direction
 *                                                       (an isotropic phase function)
 *
 * LG_PI * x / 180.0 turns degrees into radians. LG_TWO_PI and LG_HALF_PI equal
 * 2.0 * LG_PI and 0.5 * LG_PI to the bit (scaling by two is exact); the reciprocals are
 * rounded once from the exact value, so LG_INV_PI may differ from 1.0 / LG_PI in the last
 * bit. LG_PIF is the float nearest pi, for float code; any other float constant is the
 * double one cast, e.g. (float)LG_TWO_PI. GLSL and OpenCL shaders cannot include this header
 * and keep their own. */
#define LG_PI 3.14159265358979323846264338327950288
#define LG_TWO_PI 6.28318530717958647692528676655900577
#define LG_HALF_PI 1.57079632679489661923132169163975144
#define LG_INV_PI 0.318309886183790671537767526745028724
#define LG_INV_TWO_PI 0.159154943091895335768883763372514362
#define LG_INV_FOUR_PI 0.0795774715459476678844418816862571810
#define LG_PIF 3.14159265358979323846f

typedef struct lg_vec3 {
    float x, y, z;
} lg_vec3;

static inline lg_vec3 lg_v3(float x, float y, float z)
{
    lg_vec3 v = { x, y, z };
    return v;
}
static inline lg_vec3 lg_v3_add(lg_vec3 a, lg_vec3 b)
{
    return lg_v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline lg_vec3 lg_v3_sub(lg_vec3 a, lg_vec3 b)
{
    return lg_v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline lg_vec3 lg_v3_scale(lg_vec3 a, float s)
{
    return lg_v3(a.x * s, a.y * s, a.z * s);
}
static inline float lg_v3_dot(lg_vec3 a, lg_vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline lg_vec3 lg_v3_cross(lg_vec3 a, lg_vec3 b)
{
    return lg_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float lg_v3_length(lg_vec3 a)
{
    return sqrtf(lg_v3_dot(a, a));
}

/* Unit vector along `a`. Zero, denormal-only, NaN or infinite input returns `fallback`
 * (the caller says what a direction-less vector means); huge finite input is rescaled
 * before squaring so that it does not overflow. */
static inline lg_vec3 lg_v3_normalize_or(lg_vec3 a, lg_vec3 fallback)
{
    /* fmaxf ignores NaN, so each component is checked on its own */
    if (!isfinite(a.x) || !isfinite(a.y) || !isfinite(a.z))
        return fallback;
    float m = fmaxf(fabsf(a.x), fmaxf(fabsf(a.y), fabsf(a.z)));
    if (!(m > 1e-30f))
        return fallback;
    a = lg_v3_scale(a, 1.0f / m);
    float l = lg_v3_length(a);
    return lg_v3_scale(a, 1.0f / l);
}

/* out = a * b */
static inline void lg_m4_mul(float out[16], const float a[16], const float b[16])
{
    float r[16];
    for (int c = 0; c < 4; c++)
        for (int rr = 0; rr < 4; rr++) {
            float s = 0;
            for (int k = 0; k < 4; k++)
                s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    memcpy(out, r, sizeof r);
}

static inline void lg_m4_identity(float m[16])
{
    memset(m, 0, 16 * sizeof(float));
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

/* p' = M p for a point (w = 1), divided by w when w != 0 and != 1. */
static inline lg_vec3 lg_m4_point(const float m[16], lg_vec3 p)
{
    float x = m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12];
    float y = m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13];
    float z = m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14];
    float w = m[3] * p.x + m[7] * p.y + m[11] * p.z + m[15];
    if (w != 0.0f && w != 1.0f) {
        x /= w;
        y /= w;
        z /= w;
    }
    return lg_v3(x, y, z);
}

/* d' = M d for a direction (w = 0). */
static inline lg_vec3 lg_m4_dir(const float m[16], lg_vec3 d)
{
    return lg_v3(m[0] * d.x + m[4] * d.y + m[8] * d.z, m[1] * d.x + m[5] * d.y + m[9] * d.z,
                 m[2] * d.x + m[6] * d.y + m[10] * d.z);
}

/* A view matrix looking from `eye` at `target` with `up` (gluLookAt). A degenerate `up`
 * (parallel to the view direction) is replaced by another axis. */
static inline void lg_m4_look_at(float m[16], lg_vec3 eye, lg_vec3 target, lg_vec3 up)
{
    lg_vec3 f = lg_v3_normalize_or(lg_v3_sub(target, eye), lg_v3(0, 0, -1));
    lg_vec3 s = lg_v3_cross(f, up);
    if (lg_v3_length(s) < 1e-6f * (lg_v3_length(up) + 1e-30f))
        s = lg_v3_cross(f, fabsf(f.y) < 0.9f ? lg_v3(0, 1, 0) : lg_v3(1, 0, 0));
    s = lg_v3_normalize_or(s, lg_v3(1, 0, 0));
    lg_vec3 u = lg_v3_cross(s, f);
    lg_m4_identity(m);
    m[0] = s.x;
    m[4] = s.y;
    m[8] = s.z;
    m[1] = u.x;
    m[5] = u.y;
    m[9] = u.z;
    m[2] = -f.x;
    m[6] = -f.y;
    m[10] = -f.z;
    m[12] = -lg_v3_dot(s, eye);
    m[13] = -lg_v3_dot(u, eye);
    m[14] = lg_v3_dot(f, eye);
}

/* OpenGL perspective projection (clip z in [-w, w]); yfov in radians. */
static inline void lg_m4_perspective(float m[16], float yfov, float aspect, float znear, float zfar)
{
    float f = 1.0f / tanf(yfov * 0.5f);
    memset(m, 0, 16 * sizeof(float));
    m[0] = f / aspect;
    m[5] = f;
    m[10] = (zfar + znear) / (znear - zfar);
    m[11] = -1.0f;
    m[14] = 2.0f * zfar * znear / (znear - zfar);
}

/* OpenGL orthographic projection. */
static inline void lg_m4_ortho(float m[16], float l, float r, float b, float t, float n, float f)
{
    memset(m, 0, 16 * sizeof(float));
    m[0] = 2.0f / (r - l);
    m[5] = 2.0f / (t - b);
    m[10] = -2.0f / (f - n);
    m[12] = -(r + l) / (r - l);
    m[13] = -(t + b) / (t - b);
    m[14] = -(f + n) / (f - n);
    m[15] = 1.0f;
}

/* General inverse (cofactors, in double). Returns 0, or -1 (out untouched) when singular. */
static inline int lg_m4_invert(float out[16], const float m[16])
{
    double a[16], inv[16];
    for (int i = 0; i < 16; i++)
        a[i] = m[i];
    inv[0] = a[5] * a[10] * a[15] - a[5] * a[11] * a[14] - a[9] * a[6] * a[15] +
             a[9] * a[7] * a[14] + a[13] * a[6] * a[11] - a[13] * a[7] * a[10];
    inv[4] = -a[4] * a[10] * a[15] + a[4] * a[11] * a[14] + a[8] * a[6] * a[15] -
             a[8] * a[7] * a[14] - a[12] * a[6] * a[11] + a[12] * a[7] * a[10];
    inv[8] = a[4] * a[9] * a[15] - a[4] * a[11] * a[13] - a[8] * a[5] * a[15] +
             a[8] * a[7] * a[13] + a[12] * a[5] * a[11] - a[12] * a[7] * a[9];
    inv[12] = -a[4] * a[9] * a[14] + a[4] * a[10] * a[13] + a[8] * a[5] * a[14] -
              a[8] * a[6] * a[13] - a[12] * a[5] * a[10] + a[12] * a[6] * a[9];
    inv[1] = -a[1] * a[10] * a[15] + a[1] * a[11] * a[14] + a[9] * a[2] * a[15] -
             a[9] * a[3] * a[14] - a[13] * a[2] * a[11] + a[13] * a[3] * a[10];
    inv[5] = a[0] * a[10] * a[15] - a[0] * a[11] * a[14] - a[8] * a[2] * a[15] +
             a[8] * a[3] * a[14] + a[12] * a[2] * a[11] - a[12] * a[3] * a[10];
    inv[9] = -a[0] * a[9] * a[15] + a[0] * a[11] * a[13] + a[8] * a[1] * a[15] -
             a[8] * a[3] * a[13] - a[12] * a[1] * a[11] + a[12] * a[3] * a[9];
    inv[13] = a[0] * a[9] * a[14] - a[0] * a[10] * a[13] - a[8] * a[1] * a[14] +
              a[8] * a[2] * a[13] + a[12] * a[1] * a[10] - a[12] * a[2] * a[9];
    inv[2] = a[1] * a[6] * a[15] - a[1] * a[7] * a[14] - a[5] * a[2] * a[15] + a[5] * a[3] * a[14] +
             a[13] * a[2] * a[7] - a[13] * a[3] * a[6];
    inv[6] = -a[0] * a[6] * a[15] + a[0] * a[7] * a[14] + a[4] * a[2] * a[15] -
             a[4] * a[3] * a[14] - a[12] * a[2] * a[7] + a[12] * a[3] * a[6];
    inv[10] = a[0] * a[5] * a[15] - a[0] * a[7] * a[13] - a[4] * a[1] * a[15] +
              a[4] * a[3] * a[13] + a[12] * a[1] * a[7] - a[12] * a[3] * a[5];
    inv[14] = -a[0] * a[5] * a[14] + a[0] * a[6] * a[13] + a[4] * a[1] * a[14] -
              a[4] * a[2] * a[13] - a[12] * a[1] * a[6] + a[12] * a[2] * a[5];
    inv[3] = -a[1] * a[6] * a[11] + a[1] * a[7] * a[10] + a[5] * a[2] * a[11] -
             a[5] * a[3] * a[10] - a[9] * a[2] * a[7] + a[9] * a[3] * a[6];
    inv[7] = a[0] * a[6] * a[11] - a[0] * a[7] * a[10] - a[4] * a[2] * a[11] + a[4] * a[3] * a[10] +
             a[8] * a[2] * a[7] - a[8] * a[3] * a[6];
    inv[11] = -a[0] * a[5] * a[11] + a[0] * a[7] * a[9] + a[4] * a[1] * a[11] - a[4] * a[3] * a[9] -
              a[8] * a[1] * a[7] + a[8] * a[3] * a[5];
    inv[15] = a[0] * a[5] * a[10] - a[0] * a[6] * a[9] - a[4] * a[1] * a[10] + a[4] * a[2] * a[9] +
              a[8] * a[1] * a[6] - a[8] * a[2] * a[5];
    double det = a[0] * inv[0] + a[1] * inv[4] + a[2] * inv[8] + a[3] * inv[12];
    if (det == 0.0 || !isfinite(det))
        return -1;
    for (int i = 0; i < 16; i++)
        out[i] = (float)(inv[i] / det);
    return 0;
}

/* The normal matrix (inverse transpose of the upper 3x3), column-major 3x3. Returns -1 for
 * a singular matrix (out untouched). */
static inline int lg_m4_normal_matrix(float out[9], const float m[16])
{
    float inv[16];
    if (lg_m4_invert(inv, m))
        return -1;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            out[c * 3 + r] = inv[r * 4 + c];
    return 0;
}

#ifdef __cplusplus
}
#endif
#endif
