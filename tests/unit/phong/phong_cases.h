/*
 * tests/unit/phong/phong_cases.h: one layout of test cases for the lighting functions,
 * evaluated by the C twin (plugins/phong/phong_model.h) and by the GLSL one
 * (shaders/common/phong.glsl, through phong_eval.comp on a GL device), and the tolerance that holds the
 * two together.
 *
 * Tolerance (phong_compare). Both sides compute in binary32. The C side is IEEE with
 * correctly rounded sqrt and a powf within 1 ULP; GLSL 4.50 (§4.7.1) allows inversesqrt
 * 2 ULP, division 2.5 ULP, log2 3 ULP (absolute 2^-21 for x in [0.5, 2]), exp2 3 + 2|y| ULP,
 * and pow(x, n) = exp2(n log2 x). So:
 *   lg_safe_normalize  each component within 1e-6 (unit results); fallbacks bit-identical
 *   lg_depth_cue       relative 1e-6
 *   lg_phong_ambient   relative 1e-6
 *   lg_spec_pow        relative phong_spec_pow_tol(x, n): the GLSL bound above propagated,
 *                      ln2 (n dlog2(x) + 2^-23 |y|) + (3 + 2|y|) 2^-23 with y = n log2 x,
 *                      plus 2 ULP for the C side; the bound grows with n (about 3.3e-7 n
 *                      near x = 1): "pow with large n amplifies"
 *   lg_phong_direct    the diffuse part D relative 1e-5; the specular part S between the
 *                      values for the cosine moved by +-1e-6 (the two sides' dot products
 *                      and normalisations differ by a few ULP) widened by the spec_pow
 *                      tolerance
 * and every value on both sides must be finite. All limits add FLT_MIN absolute (GPUs flush
 * denormal results to zero).
 */
#ifndef LG_TEST_PHONG_CASES_H
#define LG_TEST_PHONG_CASES_H

#include <stddef.h>
#include <stdint.h>

#include "phong_model.h"

/* std430 layout of phong_eval.comp's Case and Result: vec4 and ivec4 only. */
typedef struct phong_case {
    float N[4], V[4], L[4]; /* xyz */
    float Ii[4];            /* xyz; also Ia for lg_phong_ambient */
    float mat[4];           /* ka, kd, ks, n */
    float od[4], os[4];     /* xyz */
    float nrm[4];           /* xyz: lg_safe_normalize input; w: n_eff */
    float fb[4];            /* xyz: fallback */
    float s[4];             /* r, K, x, n */
    int32_t model[4];       /* x: spec_model */
} phong_case;

typedef struct phong_result {
    float direct[4], ambient[4], normalized[4];
    float scalars[4]; /* lg_depth_cue, lg_spec_pow */
} phong_result;

/* The C side. */
void phong_eval_c(const phong_case *c, phong_result *r);

/* A case with neutral values for everything (unit vectors N = V = L = +Z, white unit
 * light and a grey material, n = 10, r = 1, K = 1, x = 0.5): hard cases change a field. */
phong_case phong_case_default(void);

/* Agreement statistics over many phong_compare calls. */
typedef struct phong_stats {
    uint32_t cases, mismatches, knife_edge;
    double worst_ratio;          /* max |glsl - c| / allowed, over everything */
    char worst_what[256];        /* which value that was */
    double max_rel_direct;       /* max relative difference of lg_phong_direct (|c| > 1e-6) */
    double max_rel_diffuse_only; /* the same over cases whose specular term is 0 */
    double max_rel_ambient, max_rel_depth_cue;
    double max_abs_normalize;
    double max_rel_spec_pow, max_rel_spec_pow_n128; /* lg_spec_pow; the second for n <= 128 */
} phong_stats;

/* The relative tolerance of lg_spec_pow(x, n) between C and GLSL (see above). */
double phong_spec_pow_tol(double x, double n);

/* Compares the GLSL result g with the C result c of case k; returns 0 when every value is
 * finite and within tolerance, else 1 with the reason in why. Updates st. Cases on a
 * knife edge of a documented discontinuity (N.L, R.V or N.H within 1e-6 of 0 where it
 * decides, |L + V|^2 within 1e-6 relative of LG_BLINN_MIN_HALFWAY2) are only held to
 * finiteness, and counted. */
int phong_compare(const phong_case *k, const phong_result *c, const phong_result *g,
                  phong_stats *st, char *why, size_t whylen);

/* The GL side: a device (OSMesa, else EGL) and phong_eval.comp compiled. open returns 0,
 * or LG_ERR_DEVICE (skip) / another code with the reason in err. */
typedef struct phong_gl phong_gl;
int phong_gl_open(phong_gl **out, char *err, size_t errlen);
int phong_gl_eval(phong_gl *g, const phong_case *cases, phong_result *results, uint32_t n,
                  char *err, size_t errlen);
void phong_gl_close(phong_gl **g);

#endif
