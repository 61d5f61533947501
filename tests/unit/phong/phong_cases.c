/* The C and GLSL evaluation of test cases, and the tolerance between them (phong_cases.h). */
#include "phong_cases.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exec/device.h"
#include "devtest.h"
#include "lightgraph/gl.h"
#include "phong_eval.comp.h"

static lg_vec3 v3(const float *a)
{
    return lg_v3(a[0], a[1], a[2]);
}

static void put3(float *o, lg_vec3 v)
{
    o[0] = v.x;
    o[1] = v.y;
    o[2] = v.z;
    o[3] = 0.0f;
}

static lg_phong_material material(const phong_case *c)
{
    lg_phong_material m = { c->mat[0],
                            c->mat[1],
                            c->mat[2],
                            c->mat[3],
                            { c->od[0], c->od[1], c->od[2] },
                            { c->os[0], c->os[1], c->os[2] } };
    return m;
}

void phong_eval_c(const phong_case *c, phong_result *r)
{
    lg_phong_material m = material(c);
    put3(r->direct,
         lg_phong_direct(v3(c->N), v3(c->V), v3(c->L), v3(c->Ii), &m, c->model[0], c->nrm[3]));
    put3(r->ambient, lg_phong_ambient(v3(c->Ii), &m));
    put3(r->normalized, lg_safe_normalize(v3(c->nrm), v3(c->fb)));
    r->scalars[0] = lg_depth_cue(c->s[0], c->s[1]);
    r->scalars[1] = lg_spec_pow(c->s[2], c->s[3]);
    r->scalars[2] = r->scalars[3] = 0.0f;
}

phong_case phong_case_default(void)
{
    phong_case c;
    memset(&c, 0, sizeof c);
    c.N[2] = c.V[2] = c.L[2] = 1.0f;
    c.Ii[0] = c.Ii[1] = c.Ii[2] = 1.0f;
    c.mat[0] = 0.1f;
    c.mat[1] = 0.6f;
    c.mat[2] = 0.4f;
    c.mat[3] = 10.0f;
    for (int i = 0; i < 3; i++) {
        c.od[i] = 0.5f;
        c.os[i] = 1.0f;
        c.nrm[i] = 1.0f;
    }
    c.nrm[3] = 10.0f;
    c.fb[2] = 1.0f;
    c.s[0] = 1.0f;
    c.s[1] = 1.0f;
    c.s[2] = 0.5f;
    c.s[3] = 10.0f;
    c.model[0] = LG_SPEC_PHONG;
    return c;
}

/* ---- tolerance ------------------------------------------------------------------------------- */

#define ULP 1.1920928955078125e-07 /* 2^-23 */

double phong_spec_pow_tol(double x, double n)
{
    if (!(x > 0) || !(n > 0) || x >= 1)
        return 2 * ULP; /* 0 or 1 exactly on both sides */
    if (n > FLT_MAX)
        n = FLT_MAX;
    double l2 = log2(x), y = fabs(n * l2);
    double dlog2 = (x >= 0.5 && x <= 2.0) ? 0x1p-21 : 3 * ULP * fabs(l2);
    return log(2.0) * (n * dlog2 + ULP * y) + (3 + 2 * y) * ULP + 2 * ULP;
}

/* lg_spec_pow's policy in double. */
static double spec_pow_d(double x, double n)
{
    if (!(x >= FLT_MIN))
        return 0;
    if (x >= 1)
        return 1;
    if (!(n > 0))
        return 1;
    if (n > FLT_MAX)
        n = FLT_MAX;
    return pow(x, n);
}

static int finite4(const float *a)
{
    return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]) && isfinite(a[3]);
}

static double dot_d(const float *a, const float *b)
{
    return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
}

static double rel(double g, double c)
{
    double d = fabs(g - c), m = fabs(c);
    return m > 1e-6 ? d / m : 0.0;
}

/* |g - c| <= allowed, recording the ratio. */
static int within(double g, double c, double allowed, phong_stats *st, const char *what,
                  uint32_t case_no)
{
    double d = fabs(g - c);
    if (d == 0)
        return 1; /* also when the allowance is not a number (0 x an infinite tolerance) */
    double ratio = d / (allowed > 0 ? allowed : FLT_MIN);
    /* the worst ratio is about precision: leave out denormal flushes (both below 2 FLT_MIN) */
    if (ratio > st->worst_ratio && fmax(fabs(g), fabs(c)) >= 2 * FLT_MIN) {
        st->worst_ratio = ratio;
        snprintf(st->worst_what, sizeof st->worst_what,
                 "case %u %s: C %.9g GLSL %.9g allowed +-%.3g", (unsigned)case_no, what, c, g,
                 allowed);
    }
    return d <= allowed;
}

/* Is the case's lg_phong_direct input unit and finite (the interval check applies)? */
static int plain_direct(const phong_case *k)
{
    const float *vs[] = { k->N, k->V, k->L };
    for (int i = 0; i < 3; i++) {
        double l = sqrt(dot_d(vs[i], vs[i]));
        if (!(fabs(l - 1) < 1e-5))
            return 0;
    }
    for (int i = 0; i < 3; i++)
        if (!isfinite(k->Ii[i]) || !isfinite(k->od[i]) || !isfinite(k->os[i]))
            return 0;
    for (int i = 0; i < 4; i++)
        if (!isfinite(k->mat[i]))
            return 0;
    /* results beyond FLT_MAX are 0 by policy: compared exactly */
    for (int i = 0; i < 3; i++)
        if (!(fabs((double)k->Ii[i]) *
                  (fabs((double)k->mat[1] * k->od[i]) + fabs((double)k->mat[2] * k->os[i])) <
              0.5 * FLT_MAX))
            return 0;
    return isfinite(k->nrm[3]);
}

int phong_compare(const phong_case *k, const phong_result *c, const phong_result *g,
                  phong_stats *st, char *why, size_t whylen)
{
    st->cases++;
    why[0] = '\0';
    if (!finite4(c->direct) || !finite4(c->ambient) || !finite4(c->normalized) ||
        !finite4(c->scalars)) {
        snprintf(why, whylen, "C result not finite");
        st->mismatches++;
        return 1;
    }
    if (!finite4(g->direct) || !finite4(g->ambient) || !finite4(g->normalized) ||
        !finite4(g->scalars)) {
        snprintf(why, whylen, "GLSL result not finite");
        st->mismatches++;
        return 1;
    }
    int bad = 0;
    /* lg_phong_direct */
    int knife = 0;
    double ndl = dot_d(k->N, k->L);
    double n_eff = k->nrm[3];
    double x = 0;
    if (k->model[0] == LG_SPEC_BLINN) {
        float h[3] = { k->L[0] + k->V[0], k->L[1] + k->V[1], k->L[2] + k->V[2] };
        double h2 = dot_d(h, h);
        if (fabs(h2 - LG_BLINN_MIN_HALFWAY2) < 1e-3 * LG_BLINN_MIN_HALFWAY2)
            knife = 1;
        x = h2 >= LG_BLINN_MIN_HALFWAY2 ? dot_d(k->N, h) / sqrt(h2) : 0.0;
    } else {
        float r[3];
        for (int i = 0; i < 3; i++)
            r[i] = (float)(2 * ndl * k->N[i] - k->L[i]);
        x = dot_d(r, k->V);
    }
    int no_halfway = k->model[0] == LG_SPEC_BLINN && !knife && x == 0.0; /* x = 0 by policy */
    if (fabs(ndl) < 1e-6 || (!(n_eff > 0) && fabs(x) < 1e-6 && !no_halfway))
        knife = 1;
    if (plain_direct(k) && knife) {
        st->knife_edge++;
        if (getenv("LG_PHONG_VERBOSE"))
            fprintf(stderr, "knife edge: case %u N.L %.9g cos %.9g n %g\n",
                    (unsigned)(st->cases - 1), ndl, x, n_eff);
    } else if (plain_direct(k)) {
        double d = 1e-6;
        double tol = fmax(phong_spec_pow_tol(x - d, n_eff), phong_spec_pow_tol(x + d, n_eff));
        double s0 = spec_pow_d(x - d, n_eff), s1 = spec_pow_d(x + d, n_eff);
        double smin = fmin(s0, s1) * (1 - tol), smax = fmax(s0, s1) * (1 + tol);
        /* N.L too is a float dot product on each side: moved by +-1e-6 */
        double nl0 = fmin(fmax(ndl - d, 0), 1), nl1 = fmin(ndl + d, 1);
        double spec_c = spec_pow_d(x, n_eff);
        for (int i = 0; i < 3 && ndl > 0; i++) {
            double D0 = (double)k->Ii[i] * k->mat[1] * nl0 * k->od[i];
            double D1 = (double)k->Ii[i] * k->mat[1] * nl1 * k->od[i];
            double Dlo = fmin(D0, D1), Dhi = fmax(D0, D1);
            Dlo = fmin(Dlo * (1 - 1e-5), Dlo * (1 + 1e-5));
            Dhi = fmax(Dhi * (1 - 1e-5), Dhi * (1 + 1e-5));
            double sk = (double)k->Ii[i] * k->mat[2] * k->os[i];
            double lo = Dlo + fmin(sk * smin, sk * smax) - FLT_MIN;
            double hi = Dhi + fmax(sk * smin, sk * smax) + FLT_MIN;
            double gv = g->direct[i], cv = c->direct[i];
            double allowed = fmax(hi - cv, cv - lo);
            int ok_g = gv >= lo && gv <= hi, ok_c = cv >= lo && cv <= hi;
            within(gv, cv, allowed, st, "direct", st->cases - 1);
            if (!ok_g || !ok_c) {
                bad = 1;
                snprintf(
                    why, whylen,
                    "direct[%d]: C %.9g GLSL %.9g, allowed [%.9g, %.9g] (N.L %.9g, cos %.9g, n %g)",
                    i, cv, gv, lo, hi, ndl, x, n_eff);
            }
            double r = rel(gv, cv);
            if (r > st->max_rel_direct)
                st->max_rel_direct = r;
            if (spec_c == 0 || k->mat[2] == 0) {
                if (r > st->max_rel_diffuse_only)
                    st->max_rel_diffuse_only = r;
            }
        }
        if (!(ndl > 0))
            for (int i = 0; i < 3; i++)
                if (!within(g->direct[i], c->direct[i], FLT_MIN, st, "direct (N.L <= 0)",
                            st->cases - 1)) {
                    bad = 1;
                    snprintf(why, whylen, "direct[%d] with N.L %.9g <= 0: C %.9g GLSL %.9g", i, ndl,
                             c->direct[i], g->direct[i]);
                }
    } else {
        for (int i = 0; i < 3; i++)
            if (!within(g->direct[i], c->direct[i], 1e-5 * fabs(c->direct[i]) + FLT_MIN, st,
                        "direct (exceptional)", st->cases - 1)) {
                bad = 1;
                snprintf(why, whylen, "direct[%d] (exceptional input): C %.9g GLSL %.9g", i,
                         c->direct[i], g->direct[i]);
            }
    }
    /* lg_phong_ambient */
    for (int i = 0; i < 3; i++) {
        double r = rel(g->ambient[i], c->ambient[i]);
        if (r > st->max_rel_ambient)
            st->max_rel_ambient = r;
        if (!within(g->ambient[i], c->ambient[i], 1e-6 * fabs(c->ambient[i]) + FLT_MIN, st,
                    "ambient", st->cases - 1)) {
            bad = 1;
            snprintf(why, whylen, "ambient[%d]: C %.9g GLSL %.9g", i, c->ambient[i], g->ambient[i]);
        }
    }
    /* lg_safe_normalize: a fallback must be bit-identical (it is returned unchanged) */
    int c_fb = memcmp(c->normalized, k->fb, 3 * sizeof(float)) == 0;
    for (int i = 0; i < 3; i++) {
        double d = fabs((double)g->normalized[i] - c->normalized[i]);
        if (d > st->max_abs_normalize)
            st->max_abs_normalize = d;
        if (!within(g->normalized[i], c->normalized[i], c_fb ? 0.0 : 1e-6, st, "normalize",
                    st->cases - 1)) {
            bad = 1;
            snprintf(why, whylen, "normalize[%d] of (%.9g %.9g %.9g): C %.9g GLSL %.9g", i,
                     k->nrm[0], k->nrm[1], k->nrm[2], c->normalized[i], g->normalized[i]);
        }
    }
    /* lg_depth_cue */
    double r = rel(g->scalars[0], c->scalars[0]);
    if (r > st->max_rel_depth_cue)
        st->max_rel_depth_cue = r;
    if (!within(g->scalars[0], c->scalars[0], 1e-6 * fabs(c->scalars[0]) + FLT_MIN, st, "depth_cue",
                st->cases - 1)) {
        bad = 1;
        snprintf(why, whylen, "depth_cue(%.9g, %.9g): C %.9g GLSL %.9g", k->s[0], k->s[1],
                 c->scalars[0], g->scalars[0]);
    }
    /* lg_spec_pow */
    double tol = phong_spec_pow_tol(k->s[2], k->s[3]);
    r = rel(g->scalars[1], c->scalars[1]);
    if (r > st->max_rel_spec_pow)
        st->max_rel_spec_pow = r;
    if (k->s[3] <= 128 && r > st->max_rel_spec_pow_n128)
        st->max_rel_spec_pow_n128 = r;
    char label[96];
    snprintf(label, sizeof label, "spec_pow(%.9g, %.6g)", k->s[2], k->s[3]);
    if (!within(g->scalars[1], c->scalars[1], tol * fabs(c->scalars[1]) + FLT_MIN, st, label,
                st->cases - 1)) {
        bad = 1;
        snprintf(why, whylen, "spec_pow(%.9g, %.9g): C %.9g GLSL %.9g, tolerance %.3g relative",
                 k->s[2], k->s[3], c->scalars[1], g->scalars[1], tol);
    }
    st->mismatches += (uint32_t)bad;
    return bad;
}

/* ---- GL -------------------------------------------------------------------------------------- */

struct phong_gl {
    lg_gl_device *dev;
    const lg_gl *gl;
    GLuint prog;
};

int phong_gl_open(phong_gl **out, char *err, size_t errlen)
{
    *out = NULL;
    phong_gl *g = calloc(1, sizeof *g);
    if (!g) {
        snprintf(err, errlen, "out of memory");
        return LG_ERR_NOMEM;
    }
    char e1[512] = "", e2[512] = "";
    if (lg_gl_device_create(&g->dev, "osmesa", e1, sizeof e1) &&
        lg_gl_device_create(&g->dev, "egl", e2, sizeof e2)) {
        snprintf(err, errlen, "no GL device: %s; %s", e1, e2);
        free(g);
        return LG_ERR_DEVICE;
    }
    g->gl = lg_gl_device_table(g->dev);
    devtest_clear();
    lg_gl_shader_src src = { GL_COMPUTE_SHADER, lg_src_phong_eval_comp_file,
                             lg_src_phong_eval_comp };
    g->prog = lg_gl_program(devtest_node(), g->gl, &src, 1, NULL);
    if (!g->prog) {
        snprintf(err, errlen, "phong_eval.comp: %s", devtest_errors);
        phong_gl_close(&g);
        return LG_ERR_INVALID;
    }
    *out = g;
    return 0;
}

int phong_gl_eval(phong_gl *g, const phong_case *cases, phong_result *results, uint32_t n,
                  char *err, size_t errlen)
{
    const lg_gl *gl = g->gl;
    GLuint buf[2];
    gl->CreateBuffers(2, buf);
    gl->NamedBufferData(buf[0], (GLsizeiptr)(n ? n : 1) * (GLsizeiptr)sizeof *cases, cases,
                        GL_STATIC_DRAW);
    gl->NamedBufferData(buf[1], (GLsizeiptr)(n ? n : 1) * (GLsizeiptr)sizeof *results, NULL,
                        GL_STATIC_READ);
    gl->UseProgram(g->prog);
    gl->Uniform1ui(0, n);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf[0]);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buf[1]);
    gl->DispatchCompute((n + 63) / 64, 1, 1);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl->GetNamedBufferSubData(buf[1], 0, (GLsizeiptr)n * (GLsizeiptr)sizeof *results, results);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    gl->UseProgram(0);
    gl->DeleteBuffers(2, buf);
    GLenum e = gl->GetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, errlen, "GL error %s", lg_gl_strerror(e));
        return LG_ERR_DEVICE;
    }
    return 0;
}

void phong_gl_close(phong_gl **pg)
{
    phong_gl *g = *pg;
    if (!g)
        return;
    if (g->prog)
        g->gl->DeleteProgram(g->prog);
    lg_gl_device_destroy(&g->dev);
    free(g);
    *pg = NULL;
}
