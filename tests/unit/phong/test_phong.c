/*
 * The lighting equation's two twins, C (plugins/phong/phong_model.h) and GLSL
 * (shaders/common/phong.glsl, compiled into phong_eval.comp), held against each other and against the
 * documented policy of every hard case.
 *
 *   test_phong agree        a few thousand random cases from a fixed seed plus every hard
 *                           case's inputs: C and GLSL agree within phong_cases.h's
 *                           tolerance; prints the measured agreement
 *   test_phong <hard case>  one hard case (the list: test_phong list): its inputs through
 *                           both twins, each result finite and equal to the documented
 *                           value, and the twins in agreement
 *
 * Exits 77 (skip) when no GL device can be made, after the C half has been checked (a C
 * failure is still reported as a failure).
 */
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "phong_cases.h"

#define MAX_CASES 64

static const float NaN_ = NAN;
static const float INF_ = INFINITY;

/* ---- an oracle in double: the documented formula and policy, written independently ----------- */

static double spec_ref(double x, double n)
{
    if (!(x >= FLT_MIN))
        return 0;
    if (x > 1)
        x = 1;
    if (!(n > 0))
        return 1;
    return pow(x, fmin(n, FLT_MAX));
}

/* lg_phong_direct for unit, finite input, channel i */
static double direct_ref(const phong_case *c, int i)
{
    const float *N = c->N, *V = c->V, *L = c->L;
    double ndl = (double)N[0] * L[0] + (double)N[1] * L[1] + (double)N[2] * L[2];
    if (!(ndl > 0))
        return 0;
    double x;
    if (c->model[0] == LG_SPEC_BLINN) {
        double h[3] = { (double)L[0] + V[0], (double)L[1] + V[1], (double)L[2] + V[2] };
        double h2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
        x = h2 >= LG_BLINN_MIN_HALFWAY2 ? (N[0] * h[0] + N[1] * h[1] + N[2] * h[2]) / sqrt(h2) : 0;
    } else {
        double r[3];
        for (int k = 0; k < 3; k++)
            r[k] = 2 * ndl * N[k] - L[k];
        x = r[0] * V[0] + r[1] * V[1] + r[2] * V[2];
    }
    return (double)c->Ii[i] *
           (c->mat[1] * fmin(ndl, 1) * c->od[i] + c->mat[2] * spec_ref(x, c->nrm[3]) * c->os[i]);
}

/* ---- checks shared by the cases -------------------------------------------------------------- */

static int all_finite(const phong_result *r)
{
    const float *a = r->direct;
    for (int i = 0; i < 16; i++)
        if (!isfinite(a[i]))
            return 0;
    return 1;
}

static void expect3(const char *side, const char *what, uint32_t k, const float *got, double x,
                    double y, double z, double tol)
{
    double want[3] = { x, y, z };
    for (int i = 0; i < 3; i++)
        CHECKF(fabs(got[i] - want[i]) <= tol * fmax(1.0, fabs(want[i])),
               "%s case %" PRIu32 ": %s[%d] = %.9g, documented %.9g", side, k, what, i, got[i],
               want[i]);
}

static void expect1(const char *side, const char *what, uint32_t k, double got, double want,
                    double tol)
{
    CHECKF(fabs(got - want) <= tol * fmax(1e-30, fabs(want)) || got == want,
           "%s case %" PRIu32 ": %s = %.9g, documented %.9g", side, k, what, got, want);
}

static void unit3(float *o, double x, double y, double z)
{
    double l = sqrt(x * x + y * y + z * z);
    o[0] = (float)(x / l);
    o[1] = (float)(y / l);
    o[2] = (float)(z / l);
    o[3] = 0;
}

/* ---- hard cases ------------------------------------------------------------------------------ */

/* zero vectors (+0 and -0) through lg_safe_normalize: the fallback, unchanged; a
 * non-finite fallback becomes 0 */
static uint32_t build_normalize_zero(phong_case *c)
{
    float in[][3] = { { 0, 0, 0 }, { -0.0f, 0, -0.0f } };
    uint32_t n = 0;
    for (int i = 0; i < 2; i++) {
        c[n] = phong_case_default();
        memcpy(c[n].nrm, in[i], sizeof in[i]);
        c[n].fb[0] = 0.25f; /* not unit: returned as is */
        c[n].fb[1] = -2.0f;
        c[n].fb[2] = 0;
        n++;
    }
    c[n] = phong_case_default();
    c[n].nrm[0] = c[n].nrm[1] = c[n].nrm[2] = 0;
    c[n].fb[0] = NaN_;
    n++;
    return n;
}

static void check_normalize_zero(const phong_case *c, const phong_result *r, uint32_t n,
                                 const char *side)
{
    expect3(side, "normalize", 0, r[0].normalized, 0.25, -2.0, 0, 0);
    expect3(side, "normalize", 1, r[1].normalized, 0.25, -2.0, 0, 0);
    expect3(side, "normalize (NaN fallback)", 2, r[2].normalized, 0, 0, 0, 0);
}

/* denormal-only vectors -> fallback; the smallest normal and tiny normal vectors normalise */
static uint32_t build_normalize_denormal(phong_case *c)
{
    float in[][3] = { { 1e-40f, -1e-41f, 0 },
                      { FLT_MIN / 2, FLT_MIN / 2, FLT_MIN / 2 },
                      { FLT_MIN, 0, 0 },
                      { 1e-30f, 2e-30f, -2e-30f },
                      { -3e-20f, 4e-20f, 0 } };
    for (int i = 0; i < 5; i++) {
        c[i] = phong_case_default();
        memcpy(c[i].nrm, in[i], sizeof in[i]);
        c[i].fb[0] = 0;
        c[i].fb[1] = 1;
        c[i].fb[2] = 0;
    }
    return 5;
}

static void check_normalize_denormal(const phong_case *c, const phong_result *r, uint32_t n,
                                     const char *side)
{
    expect3(side, "normalize", 0, r[0].normalized, 0, 1, 0, 0);
    expect3(side, "normalize", 1, r[1].normalized, 0, 1, 0, 0);
    expect3(side, "normalize", 2, r[2].normalized, 1, 0, 0, 1e-6);
    expect3(side, "normalize", 3, r[3].normalized, 1.0 / 3, 2.0 / 3, -2.0 / 3, 1e-6);
    expect3(side, "normalize", 4, r[4].normalized, -0.6, 0.8, 0, 1e-6);
}

/* huge finite vectors: rescaled, no overflow */
static uint32_t build_normalize_huge(phong_case *c)
{
    float in[][3] = { { FLT_MAX, FLT_MAX, FLT_MAX },
                      { FLT_MAX, 0, 0 },
                      { 1e30f, -1e30f, 0 },
                      { 3e38f, -3e38f, 1e20f },
                      { 2e19f, 0, -2e19f } };
    for (int i = 0; i < 5; i++) {
        c[i] = phong_case_default();
        memcpy(c[i].nrm, in[i], sizeof in[i]);
    }
    return 5;
}

static void check_normalize_huge(const phong_case *c, const phong_result *r, uint32_t n,
                                 const char *side)
{
    double s = 1 / sqrt(3.0), h = 1 / sqrt(2.0);
    expect3(side, "normalize", 0, r[0].normalized, s, s, s, 1e-6);
    expect3(side, "normalize", 1, r[1].normalized, 1, 0, 0, 1e-6);
    expect3(side, "normalize", 2, r[2].normalized, h, -h, 0, 1e-6);
    expect3(side, "normalize", 3, r[3].normalized, h, -h, 0, 1e-6);
    expect3(side, "normalize", 4, r[4].normalized, h, 0, -h, 1e-6);
}

/* NaN and infinite components: the fallback */
static uint32_t build_normalize_nonfinite(phong_case *c)
{
    float in[][3] = {
        { NaN_, 0, 0 }, { NaN_, 1, 0 }, { INF_, 0, 0 }, { 1, -INF_, 1 }, { INF_, INF_, INF_ }
    };
    for (int i = 0; i < 5; i++) {
        c[i] = phong_case_default();
        memcpy(c[i].nrm, in[i], sizeof in[i]);
        c[i].fb[0] = 0;
        c[i].fb[1] = 0;
        c[i].fb[2] = -1;
    }
    return 5;
}

static void check_normalize_nonfinite(const phong_case *c, const phong_result *r, uint32_t n,
                                      const char *side)
{
    for (uint32_t k = 0; k < n; k++)
        expect3(side, "normalize", k, r[k].normalized, 0, 0, -1, 0);
}

/* L = -V: Blinn's H does not exist -> no highlight (diffuse only), for n > 0 and n = 0;
 * Phong's R.V there is 1 - 2 (N.L)^2 */
static uint32_t build_halfway_undefined(phong_case *c)
{
    uint32_t n = 0;
    double ls[][3] = { { 0.3, 0.1, 1 }, { 1, 0, 0.2 }, { 0, 0, 1 } };
    for (int i = 0; i < 3; i++)
        for (int model = 0; model < 2; model++)
            for (int zero_n = 0; zero_n < 2; zero_n++) {
                c[n] = phong_case_default();
                unit3(c[n].L, ls[i][0], ls[i][1], ls[i][2]);
                for (int k = 0; k < 3; k++)
                    c[n].V[k] = -c[n].L[k];
                c[n].model[0] = model;
                c[n].nrm[3] = zero_n ? 0.0f : 20.0f;
                n++;
            }
    /* L within 1e-4 rad of -V (|L + V| < 1e-3): H is rounding noise, so the same policy;
     * here L + V points along N, and a computed H would give the full highlight */
    for (int model = 0; model < 2; model++) {
        c[n] = phong_case_default();
        unit3(c[n].L, 1, 0, 0.05);
        double v[3] = { -c[n].L[0], -c[n].L[1], -c[n].L[2] + 1e-4 };
        unit3(c[n].V, v[0], v[1], v[2]);
        c[n].model[0] = model;
        c[n].nrm[3] = 1;
        n++;
    }
    return n;
}

static void check_halfway_undefined(const phong_case *c, const phong_result *r, uint32_t n,
                                    const char *side)
{
    for (uint32_t k = 0; k < n; k++) {
        double ndl = c[k].L[2]; /* N = +Z */
        for (int i = 0; i < 3; i++) {
            double diffuse = c[k].Ii[i] * c[k].mat[1] * ndl * c[k].od[i];
            if (c[k].model[0] == LG_SPEC_BLINN) {
                expect1(side, "Blinn, L = -V: diffuse only", k, r[k].direct[i], diffuse, 1e-6);
            } else {
                /* the oracle, and for exact L = -V the closed form R.V = 1 - 2 (N.L)^2 */
                expect1(side, "Phong, L = -V", k, r[k].direct[i], direct_ref(&c[k], i), 1e-5);
                if (k < 12) {
                    double rv = 1 - 2 * ndl * ndl;
                    double want = diffuse +
                                  c[k].Ii[i] * c[k].mat[2] * c[k].os[i] * spec_ref(rv, c[k].nrm[3]);
                    expect1(side, "Phong, L = -V", k, r[k].direct[i], want, 1e-5);
                }
            }
        }
    }
}

/* R.V < 0 (and N.H < 0): no highlight, even with n = 0 */
static uint32_t build_rv_negative(phong_case *c)
{
    uint32_t n = 0;
    for (int zero_n = 0; zero_n < 2; zero_n++) {
        /* Phong: L at 45 degrees, V at 60 degrees on L's side: R is on the other side */
        c[n] = phong_case_default();
        unit3(c[n].L, 1, 0, 1);
        unit3(c[n].V, sqrt(3.0), 0, 1);
        c[n].nrm[3] = zero_n ? 0.0f : 10.0f;
        n++;
        /* Blinn with N.H < 0: the light at grazing incidence, the viewer below the horizon */
        c[n] = phong_case_default();
        unit3(c[n].L, 1, 0, 0.05);
        unit3(c[n].V, 0.2, 0, -1);
        c[n].model[0] = LG_SPEC_BLINN;
        c[n].nrm[3] = zero_n ? 0.0f : 10.0f;
        n++;
    }
    return n;
}

static void check_rv_negative(const phong_case *c, const phong_result *r, uint32_t n,
                              const char *side)
{
    for (uint32_t k = 0; k < n; k++)
        for (int i = 0; i < 3; i++) {
            double diffuse = c[k].Ii[i] * c[k].mat[1] * c[k].L[2] * c[k].od[i];
            expect1(side, "cosine < 0: diffuse only", k, r[k].direct[i], diffuse, 1e-6);
        }
}

/* shininess 0 and pow(0, 0): lg_spec_pow's table, and lg_phong_direct with n = 0 */
static const float spow_in[][3] = {
    /* x, n, documented */
    { 0, 0, 0 },                                                   /* pow(0, 0) = 0 */
    { -0.0f, 0, 0 },      { 0.5f, 0, 1 },                          /* n = 0: 1 for x > 0 */
    { 1, 0, 1 },          { 1e-30f, 0, 1 },      { 1e-40f, 0, 0 }, /* denormal x counts as 0 */
    { 1e-40f, 0.01f, 0 }, { -0.5f, 0, 0 },       { 0.5f, -3, 1 },  /* negative n counts as 0 */
    { 0.5f, NAN, 1 },                                              /* NaN n counts as 0 */
    { NAN, 5, 0 },                                                 /* NaN x: no highlight */
    { 2, 5, 1 },                                                   /* x > 1 counts as 1 */
    { INFINITY, 5, 1 },   { 0.5f, INFINITY, 0 },                   /* a mirror */
    { 1, INFINITY, 1 },   { 1, FLT_MAX, 1 },     { 0.5f, 2, 0.25f },
};
#define N_SPOW (sizeof spow_in / sizeof spow_in[0])

static uint32_t build_shininess_zero(phong_case *c)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < N_SPOW; i++) {
        c[n] = phong_case_default();
        c[n].s[2] = spow_in[i][0];
        c[n].s[3] = spow_in[i][1];
        n++;
    }
    /* lg_phong_direct, n = 0: R.V > 0 gives the full ks Os; R = V exactly gives it too */
    c[n] = phong_case_default();
    unit3(c[n].L, 1, 0, 1);
    unit3(c[n].V, -1, 0, 2);
    c[n].nrm[3] = 0;
    n++;
    c[n] = phong_case_default();
    c[n].nrm[3] = 0;
    c[n].model[0] = LG_SPEC_BLINN;
    n++;
    return n;
}

static void check_shininess_zero(const phong_case *c, const phong_result *r, uint32_t n,
                                 const char *side)
{
    for (uint32_t k = 0; k < N_SPOW; k++)
        expect1(side, "spec_pow", k, r[k].scalars[1], spow_in[k][2], 1e-6);
    for (uint32_t k = N_SPOW; k < n; k++)
        for (int i = 0; i < 3; i++) {
            double want = c[k].Ii[i] *
                          (c[k].mat[1] * c[k].L[2] * c[k].od[i] + c[k].mat[2] * c[k].os[i]);
            expect1(side, "direct, n = 0, cosine > 0", k, r[k].direct[i], want, 1e-6);
        }
}

/* back-facing N (N.V < 0): lit as given, not flipped; N.L <= 0 gives 0 */
static uint32_t build_back_facing(phong_case *c)
{
    uint32_t n = 0;
    for (int model = 0; model < 2; model++) {
        c[n] = phong_case_default(); /* N.L > 0, N.V < 0 */
        unit3(c[n].L, 1, 0, 1);
        unit3(c[n].V, -1, 0, -0.2);
        c[n].model[0] = model;
        c[n].nrm[3] = 2;
        n++;
        c[n] = phong_case_default(); /* N.L < 0, N.V < 0: the flipped normal would be lit */
        unit3(c[n].L, 0.3, 0, -1);
        unit3(c[n].V, -0.3, 0, -1);
        c[n].model[0] = model;
        n++;
        c[n] = phong_case_default(); /* N.L = 0 exactly */
        unit3(c[n].L, 1, 0, 0);
        c[n].model[0] = model;
        c[n].nrm[3] = 0;
        n++;
    }
    return n;
}

static void check_back_facing(const phong_case *c, const phong_result *r, uint32_t n,
                              const char *side)
{
    for (uint32_t k = 0; k < n; k++)
        for (int i = 0; i < 3; i++) {
            double want = direct_ref(&c[k], i);
            expect1(side, "back-facing N, as given", k, r[k].direct[i], want, 1e-5);
            if (k % 3 == 0)
                CHECKF(r[k].direct[i] > c[k].Ii[i] * c[k].mat[1] * c[k].od[i] * 0.5,
                       "%s case %" PRIu32 ": N.V < 0 but N.L > 0 must be lit", side, k);
            else
                CHECKF(r[k].direct[i] == 0, "%s case %" PRIu32 ": N.L <= 0 must give 0", side, k);
        }
}

/* depth cueing: r = 0 with K = 0 and the other edges of 1 / max(r + K, 1) */
static const float cue_in[][3] = {
    /* r, K, documented */
    { 0, 0, 1 },
    { 0.5f, 0, 1 },
    { 0, 1, 1 },
    { 1, 0, 1 },
    { 3, 1, 0.25f },
    { 9, 1, 0.1f },
    { INFINITY, 0, 0 },
    { NAN, 1, 1 },
    { 1, NAN, 1 },
    { -5, 0, 1 },
    { 5, -2, 1.0f / 3 },
    { FLT_MAX, FLT_MAX, 0 },
    { -INFINITY, INFINITY, 1 },
};
#define N_CUE (sizeof cue_in / sizeof cue_in[0])

static uint32_t build_depth_cue_zero(phong_case *c)
{
    for (uint32_t i = 0; i < N_CUE; i++) {
        c[i] = phong_case_default();
        c[i].s[0] = cue_in[i][0];
        c[i].s[1] = cue_in[i][1];
    }
    return N_CUE;
}

static void check_depth_cue_zero(const phong_case *c, const phong_result *r, uint32_t n,
                                 const char *side)
{
    for (uint32_t k = 0; k < n; k++)
        expect1(side, "depth_cue", k, r[k].scalars[0], cue_in[k][2], 1e-6);
}

/* NaN and Inf in every input of lg_phong_direct and lg_phong_ambient: finite results;
 * a channel that would be non-finite is 0 */
static uint32_t build_nonfinite_inputs(phong_case *c)
{
    uint32_t n = 0;
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (int b = 0; b < 3; b++) {
        float v = bad[b];
        c[n] = phong_case_default();
        c[n].N[0] = v;
        n++; /* 0 */
        c[n] = phong_case_default();
        c[n].V[1] = v;
        n++; /* 1 */
        c[n] = phong_case_default();
        c[n].L[2] = v;
        n++; /* 2 */
        c[n] = phong_case_default();
        c[n].Ii[0] = v;
        n++; /* 3 */
        c[n] = phong_case_default();
        c[n].mat[1] = v;
        n++; /* 4 kd */
        c[n] = phong_case_default();
        c[n].mat[2] = v;
        n++; /* 5 ks */
        c[n] = phong_case_default();
        c[n].od[1] = v;
        n++; /* 6 */
        c[n] = phong_case_default();
        c[n].os[2] = v;
        n++; /* 7 */
        c[n] = phong_case_default();
        c[n].nrm[3] = v;
        n++; /* 8 n_eff */
        c[n] = phong_case_default();
        c[n].mat[0] = v;
        n++; /* 9 ka */
        c[n] = phong_case_default();
        c[n].model[0] = LG_SPEC_BLINN;
        c[n].V[0] = v;
        n++; /* 10 */
    }
    /* overflow from finite input: Ii * kd * Od beyond FLT_MAX */
    c[n] = phong_case_default();
    c[n].Ii[0] = c[n].Ii[1] = c[n].Ii[2] = 3e38f;
    c[n].mat[1] = 4;
    c[n].od[0] = c[n].od[1] = c[n].od[2] = 1;
    n++;
    return n;
}

static void check_nonfinite_inputs(const phong_case *c, const phong_result *r, uint32_t n,
                                   const char *side)
{
    for (uint32_t k = 0; k < n; k++)
        CHECKF(all_finite(&r[k]), "%s case %" PRIu32 ": a result is not finite", side, k);
    /* documented values for a few: NaN N -> no light; NaN Ii[0] -> channel 0 is 0, others
     * lit; NaN kd -> 0 on every channel; NaN n_eff counts as 0 (R = V: spec 1) */
    double full = 0.6 * 0.5 + 0.4 * 1.0; /* kd Od + ks Os with N = V = L */
    expect3(side, "direct, NaN N", 0, r[0].direct, 0, 0, 0, 0);
    expect3(side, "direct, NaN Ii.x", 3, r[3].direct, 0, full, full, 1e-6);
    expect3(side, "direct, NaN kd", 4, r[4].direct, 0, 0, 0, 0);
    expect3(side, "direct, NaN n_eff", 8, r[8].direct, full, full, full, 1e-6);
    expect3(side, "ambient, NaN ka", 9, r[9].ambient, 0, 0, 0, 0);
    expect3(side, "ambient, NaN Ii.x", 3, r[3].ambient, 0, 0.05, 0.05, 1e-6);
    /* +Inf Ii: the channel is 0 */
    expect3(side, "direct, +Inf Ii.x", 14, r[14].direct, 0, full, full, 1e-6);
    /* overflow */
    expect3(side, "direct, overflow", n - 1, r[n - 1].direct, 0, 0, 0, 0);
}

typedef struct hard_case {
    const char *name;
    const char *policy;
    uint32_t (*build)(phong_case *c);
    void (*check)(const phong_case *c, const phong_result *r, uint32_t n, const char *side);
} hard_case;

static const hard_case hard_cases[] = {
    { "normalize_zero", "zero vector -> the fallback, unchanged; non-finite fallback -> 0",
      build_normalize_zero, check_normalize_zero },
    { "normalize_denormal",
      "all components below FLT_MIN -> fallback; tiny normal vectors normalise",
      build_normalize_denormal, check_normalize_denormal },
    { "normalize_huge", "huge finite vectors rescaled by 2^-100 before squaring",
      build_normalize_huge, check_normalize_huge },
    { "normalize_nonfinite", "NaN or Inf component -> fallback", build_normalize_nonfinite,
      check_normalize_nonfinite },
    { "halfway_undefined", "L = -V: Blinn gives no highlight; Phong's R.V = 1 - 2 (N.L)^2",
      build_halfway_undefined, check_halfway_undefined },
    { "rv_negative", "R.V < 0 or N.H < 0: no highlight, also for n = 0", build_rv_negative,
      check_rv_negative },
    { "shininess_zero", "pow(0, 0) = 0; n = 0 -> 1 for x > 0; n clamped to [0, FLT_MAX]",
      build_shininess_zero, check_shininess_zero },
    { "back_facing", "N.V < 0 lit as given, never flipped; N.L <= 0 -> 0", build_back_facing,
      check_back_facing },
    { "depth_cue_zero", "1 / max(r + K, 1): r = K = 0 -> 1; +Inf -> 0; NaN -> 1",
      build_depth_cue_zero, check_depth_cue_zero },
    { "nonfinite_inputs", "NaN/Inf anywhere: finite results, a non-finite channel is 0",
      build_nonfinite_inputs, check_nonfinite_inputs },
};
#define N_HARD (sizeof hard_cases / sizeof hard_cases[0])

/* ---- the GL device, shared by the commands --------------------------------------------------- */

static phong_gl *gl_dev;
static int gl_state; /* 0 not tried, 1 open, -1 unavailable */

static phong_gl *gl_get(void)
{
    if (gl_state == 0) {
        char err[1024];
        int rc = phong_gl_open(&gl_dev, err, sizeof err);
        if (rc == LG_ERR_DEVICE)
            fprintf(stderr, "no GL device, the GLSL half is skipped: %s\n", err);
        else
            CHECKF(rc == 0, "GL: %s", err);
        gl_state = rc == 0 ? 1 : -1;
    }
    return gl_state == 1 ? gl_dev : NULL;
}

/* Both twins on n cases: check_fn on each, then agreement. Returns 0, or 1 without GL. */
static int run_cases(const char *name, const phong_case *c, uint32_t n,
                     void (*check_fn)(const phong_case *, const phong_result *, uint32_t,
                                      const char *),
                     phong_stats *st, int verbose)
{
    phong_result *rc = calloc(n, sizeof *rc), *rg = calloc(n, sizeof *rg);
    if (!rc || !rg) {
        CHECKF(0, "out of memory");
        free(rc);
        free(rg);
        return 0;
    }
    for (uint32_t k = 0; k < n; k++) {
        phong_eval_c(&c[k], &rc[k]);
        CHECKF(all_finite(&rc[k]), "%s: C case %" PRIu32 " not finite", name, k);
    }
    if (check_fn)
        check_fn(c, rc, n, "C");
    phong_gl *g = gl_get();
    int no_gl = g == NULL;
    if (g) {
        char err[512];
        int e = phong_gl_eval(g, c, rg, n, err, sizeof err);
        CHECKF(e == 0, "%s: GL: %s", name, err);
        if (e == 0) {
            if (check_fn)
                check_fn(c, rg, n, "GLSL");
            int shown = 0;
            for (uint32_t k = 0; k < n; k++) {
                char why[512];
                int bad = phong_compare(&c[k], &rc[k], &rg[k], st, why, sizeof why);
                if (bad && shown++ < 20)
                    CHECKF(!bad, "%s: case %" PRIu32 ": C and GLSL disagree: %s", name, k, why);
                else if (bad)
                    check_failures++;
                if (verbose)
                    printf(
                        "%s %3" PRIu32
                        ": C (%.9g %.9g %.9g) GLSL (%.9g %.9g %.9g) | norm C (%.9g %.9g %.9g) GLSL (%.9g %.9g %.9g) | cue %.9g %.9g | spow %.9g %.9g\n",
                        name, k, rc[k].direct[0], rc[k].direct[1], rc[k].direct[2], rg[k].direct[0],
                        rg[k].direct[1], rg[k].direct[2], rc[k].normalized[0], rc[k].normalized[1],
                        rc[k].normalized[2], rg[k].normalized[0], rg[k].normalized[1],
                        rg[k].normalized[2], rc[k].scalars[0], rg[k].scalars[0], rc[k].scalars[1],
                        rg[k].scalars[1]);
            }
        }
    }
    free(rc);
    free(rg);
    return no_gl;
}

/* ---- random cases ---------------------------------------------------------------------------- */

static uint64_t rng_state = 0x9a8b87588077b958ull; /* fixed: seed 1's id */

static double rnd(void) /* [0, 1) */
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1p-53;
}

static double rnd_in(double a, double b)
{
    return a + (b - a) * rnd();
}

static void rnd_unit(double v[3])
{
    double l2;
    do {
        for (int i = 0; i < 3; i++)
            v[i] = rnd_in(-1, 1);
        l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    } while (l2 > 1 || l2 < 1e-6);
    for (int i = 0; i < 3; i++)
        v[i] /= sqrt(l2);
}

static double dot3d(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static phong_case random_case(void)
{
    phong_case c = phong_case_default();
    double N[3], L[3], V[3];
    rnd_unit(N);
    rnd_unit(L);
    if (dot3d(N, L) < 0 && rnd() < 0.8)
        for (int i = 0; i < 3; i++)
            L[i] = -L[i];
    if (rnd() < 0.3) { /* near the mirror direction: highlights */
        double ndl = dot3d(N, L), p[3];
        rnd_unit(p);
        double s = rnd_in(0, 0.3);
        for (int i = 0; i < 3; i++)
            V[i] = 2 * ndl * N[i] - L[i] + s * p[i];
        double l = sqrt(dot3d(V, V));
        for (int i = 0; i < 3; i++)
            V[i] /= l;
    } else {
        rnd_unit(V);
        if (dot3d(N, V) < 0 && rnd() < 0.8)
            for (int i = 0; i < 3; i++)
                V[i] = -V[i];
    }
    unit3(c.N, N[0], N[1], N[2]);
    unit3(c.L, L[0], L[1], L[2]);
    unit3(c.V, V[0], V[1], V[2]);
    for (int i = 0; i < 3; i++) {
        c.Ii[i] = (float)rnd_in(0, 4);
        c.od[i] = (float)rnd();
        c.os[i] = (float)rnd();
    }
    c.mat[0] = (float)rnd();
    c.mat[1] = (float)rnd();
    c.mat[2] = (float)rnd();
    c.mat[3] = (float)pow(10, rnd_in(0, 3));
    c.model[0] = rnd() < 0.5 ? LG_SPEC_PHONG : LG_SPEC_BLINN;
    c.nrm[3] = c.model[0] == LG_SPEC_BLINN && rnd() < 0.5 ? LG_BLINN_CORRECTION * c.mat[3]
                                                          : c.mat[3];
    double d[3], mag = pow(10, rnd_in(-44, 38.5));
    rnd_unit(d);
    for (int i = 0; i < 3; i++)
        c.nrm[i] = (float)(d[i] * mag);
    c.fb[0] = c.fb[1] = 0;
    c.fb[2] = 1;
    c.s[0] = (float)rnd_in(0, 50);
    c.s[1] = (float)rnd_in(0, 5);
    c.s[2] = rnd() < 0.3 ? (float)(1 - pow(10, rnd_in(-7, -1))) : (float)rnd_in(-0.2, 1.2);
    c.s[3] = (float)pow(10, rnd_in(-2, 4));
    return c;
}

enum { N_RANDOM = 4000 };

static int cmd_agree(void)
{
    uint32_t cap = N_RANDOM + N_HARD * MAX_CASES, n = 0;
    phong_case *c = calloc(cap, sizeof *c);
    if (!c) {
        CHECKF(0, "out of memory");
        return check_report("phong agree");
    }
    for (uint32_t i = 0; i < N_RANDOM; i++)
        c[n++] = random_case();
    for (uint32_t h = 0; h < N_HARD; h++)
        n += hard_cases[h].build(c + n);
    phong_stats st;
    memset(&st, 0, sizeof st);
    int no_gl = run_cases("agree", c, n, NULL, &st, 0);
    free(c);
    if (no_gl)
        return check_skip("phong agree");
    printf("C vs GLSL over %" PRIu32 " cases (%d random, seed 0x9a8b87588077b958, + hard cases):\n",
           st.cases, N_RANDOM);
    printf("  mismatches %" PRIu32 ", knife-edge cases (finiteness only) %" PRIu32 "\n",
           st.mismatches, st.knife_edge);
    printf("  worst |GLSL - C| / tolerance   %.3g (%s)\n", st.worst_ratio, st.worst_what);
    printf("  lg_phong_direct   max rel %.3g (diffuse only %.3g)\n", st.max_rel_direct,
           st.max_rel_diffuse_only);
    printf("  lg_phong_ambient  max rel %.3g\n", st.max_rel_ambient);
    printf("  lg_safe_normalize max abs %.3g\n", st.max_abs_normalize);
    printf("  lg_depth_cue      max rel %.3g\n", st.max_rel_depth_cue);
    printf("  lg_spec_pow       max rel %.3g (n <= 128: %.3g)\n", st.max_rel_spec_pow,
           st.max_rel_spec_pow_n128);
    CHECKF(st.knife_edge < 10, "%" PRIu32 " knife-edge cases: the random set is not testing much",
           st.knife_edge);
    return check_report("phong agree");
}

static int cmd_hard(const hard_case *h)
{
    phong_case c[MAX_CASES];
    uint32_t n = h->build(c);
    printf("%s: %s (%" PRIu32 " inputs)\n", h->name, h->policy, n);
    phong_stats st;
    memset(&st, 0, sizeof st);
    int no_gl = run_cases(h->name, c, n, h->check, &st, 1);
    if (no_gl)
        return check_skip(h->name);
    return check_report(h->name);
}

int main(int argc, char **argv)
{
    const char *cmd = argc > 1 ? argv[1] : "agree";
    int rc = -1;
    if (strcmp(cmd, "agree") == 0) {
        rc = cmd_agree();
    } else if (strcmp(cmd, "list") == 0) {
        for (uint32_t h = 0; h < N_HARD; h++)
            printf("%s\t%s\n", hard_cases[h].name, hard_cases[h].policy);
        rc = 0;
    } else {
        for (uint32_t h = 0; h < N_HARD; h++)
            if (strcmp(cmd, hard_cases[h].name) == 0)
                rc = cmd_hard(&hard_cases[h]);
        if (rc < 0) {
            fprintf(stderr, "test_phong: unknown command '%s' (agree, list, or a hard case)\n",
                    cmd);
            rc = 2;
        }
    }
    phong_gl_close(&gl_dev);
    return rc;
}
