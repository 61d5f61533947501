// The Phong lighting equation in GLSL 4.50 (lightgraph): seed 1 eq. 1-4, 1-8, 1-9..1-12.
//
// Included with `#include "phong.glsl"` (tools/embed.py resolves it at build time: no
// #version line here). The C twin is plugins/phong/phong_model.h: same names, same
// policies, documented there; tests/unit/phong/ holds the two against each other. Change
// one, change the other.
//
//     I_c = Ia_c ka Od_c + sum over lights of att * shadow * lg_phong_direct(...)_c
//     lg_phong_direct = Ii_c [ kd Od_c (N.L) + ks Os_c spec ]
//     spec = (R.V)^n (LG_SPEC_PHONG, R = reflect(-L, N)) or (N.H)^n' (LG_SPEC_BLINN)
//     att  = lg_depth_cue(r, K) = 1 / max(r + K, 1)
//
// N, V, L unit; V from the point to the viewer, L from the point to the light.
// Every function returns finite values for every input (non-finite ones included).

#ifndef LG_PHONG_GLSL
#define LG_PHONG_GLSL

struct LgPhongMaterial {
    float ka;
    float kd;
    float ks;
    float n;   // shininess
    vec3 od;   // object (diffuse) colour Od
    vec3 os;   // specular colour Os
};

const int LG_SPEC_PHONG = 0;
const int LG_SPEC_BLINN = 1;

// Blinn's exponent correction: n' = LG_BLINN_CORRECTION * n matches Phong's highlight.
const float LG_BLINN_CORRECTION = 4.0;
// Below this |L + V|^2 the halfway vector does not exist (L = -V): no highlight.
const float LG_BLINN_MIN_HALFWAY2 = 1e-6;

const float LG_PHONG_FLT_MIN = 1.17549435e-38;  // smallest normal float
const float LG_PHONG_FLT_MAX = 3.40282347e38;

// Not NaN and not infinite: tests the exponent bits, which no fast-math rewrite removes.
bool lg_phong_isfinite(float x)
{
    return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

float lg_phong_finite_or_zero(float x)
{
    return lg_phong_isfinite(x) ? x : 0.0;
}

vec3 lg_phong_finite_or_zero(vec3 v)
{
    return vec3(lg_phong_finite_or_zero(v.x), lg_phong_finite_or_zero(v.y),
                lg_phong_finite_or_zero(v.z));
}

// Unit vector along v. Zero, denormal-only, NaN or Inf v -> fallback (unchanged; a
// non-finite fallback -> 0); huge or tiny finite v rescaled by 2^-100 / 2^100 first.
vec3 lg_safe_normalize(vec3 v, vec3 fallback)
{
    if (!lg_phong_isfinite(fallback.x) || !lg_phong_isfinite(fallback.y) ||
        !lg_phong_isfinite(fallback.z))
        fallback = vec3(0.0);
    if (!lg_phong_isfinite(v.x) || !lg_phong_isfinite(v.y) || !lg_phong_isfinite(v.z))
        return fallback;
    float m = max(abs(v.x), max(abs(v.y), abs(v.z)));
    if (!(m >= LG_PHONG_FLT_MIN))
        return fallback;
    if (m > 1.152921504606846976e18)        // 2^60
        v *= 7.8886090522101181e-31;        // 2^-100
    else if (m < 8.6736173798840355e-19)    // 2^-60
        v *= 1.2676506002282294e30;         // 2^100
    return v * inversesqrt(dot(v, v));
}

// x^n for a cosine x and shininess n. x <= 0, denormal or NaN -> 0 (so pow(0, 0) = 0);
// x >= 1 -> 1 exactly; n clamped to [0, FLT_MAX], NaN n -> 0; n = 0 -> 1 for x > 0. In [0, 1].
float lg_spec_pow(float x, float n)
{
    if (!(x >= LG_PHONG_FLT_MIN))
        return 0.0;
    if (x >= 1.0)
        return 1.0;   // exactly: pow(1, n) = exp2(n log2(1)) need not be
    if (!(n > 0.0))
        return 1.0;
    n = min(n, LG_PHONG_FLT_MAX);
    // pow = exp2(n log2 x), and log2 may be off by 2^-21 near 1: keep x < 1 below 1
    return min(pow(x, n), 1.0);
}

// Ia ka Od; non-finite channels -> 0.
vec3 lg_phong_ambient(vec3 Ia, LgPhongMaterial m)
{
    return lg_phong_finite_or_zero(Ia * m.ka * m.od);
}

// One light: Ii [kd Od (N.L) + ks Os spec], no ambient, attenuation or shadow; n_eff is
// the exponent used (m.n is not read). N.L <= 0 -> 0 (no specular either); R.V, N.H
// clamped at 0; Blinn with L = -V -> no highlight; back-facing N lit as given (never
// flipped); non-finite channels -> 0.
vec3 lg_phong_direct(vec3 N, vec3 V, vec3 L, vec3 Ii, LgPhongMaterial m, int spec_model,
                     float n_eff)
{
    float ndl = dot(N, L);
    if (!(ndl > 0.0))
        return vec3(0.0);
    float cosine;
    if (spec_model == LG_SPEC_BLINN) {
        vec3 h = L + V;
        float h2 = dot(h, h);
        cosine = h2 >= LG_BLINN_MIN_HALFWAY2 ? dot(N, h * inversesqrt(h2)) : 0.0;
    } else {
        vec3 r = N * (2.0 * ndl) - L;   // reflect(-L, N)
        cosine = dot(r, V);
    }
    float spec = lg_spec_pow(cosine, n_eff);
    ndl = min(ndl, 1.0);
    return lg_phong_finite_or_zero(Ii * (m.kd * ndl * m.od + m.ks * spec * m.os));
}

// Depth cueing, eq. 1-12: 1 / (r + K), never above 1 (r + K <= 1 -> 1, r = K = 0 -> 1);
// +Inf -> 0, NaN -> 1.
float lg_depth_cue(float r, float K)
{
    float d = r + K;
    return d > 1.0 ? 1.0 / d : 1.0;
}

#endif
