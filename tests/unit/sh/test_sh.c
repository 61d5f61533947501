/*
 * tests/unit/sh: lightgraph/sh.h. One command per meson test:
 *
 *   eval         lg_sh_eval_d to band 64 against an independent long double reference
 *                (unnormalised P_l^m recurrence, K_l^m by lgammal, azimuth by atan2),
 *                within 1e-10 of each band's scale sqrt((2l+1)/4pi); lg_sh_eval_f to band
 *                16 within 2e-5 of it; non-unit, zero, tiny, NaN and infinite directions
 *   addition     sum_m Y_lm^2 = (2l+1)/(4 pi) at 2000 random directions and exactly at
 *                +-x, +-y, +-z: float to band 16 within 1e-4 relative, double to band 64
 *                within 1e-10
 *   orthonormal  Gauss-Legendre (in z) x uniform phi quadrature, exact for the products
 *                of band 8 functions: the Gram matrix is the identity within 1e-12
 *   band1        Y_1,-1 = +0.488603 y, Y_1,0 = +0.488603 z, Y_1,1 = +0.488603 x (no
 *                Condon-Shortley phase); Y_2,* against the closed forms of docs/sh.md
 *   zonal        A_l: pi, 2pi/3, pi/4, 0, -pi/24, 0, pi/64, and any l (to 1000) against a
 *                quadrature of the clamped cosine 2 pi int_0^1 z P_l(z) dz (l <= 40), finite
 *   irradiance   a constant environment c projected by quadrature gives irradiance pi c at
 *                every normal; a light at +x gives more irradiance at +x than at -x; an
 *                upper-hemisphere sky gives (pi/2)(1 + n_y) with 9 coefficients (exact:
 *                the truncation error is zero, closed-form coefficients rotated to +y;
 *                by quadrature of the discontinuous sky within 1e-3)
 *   rotation     identity; per-band energy preserved to band 20; rotate(project(f)) equals
 *                project(f o R^T) (a sum of clamped-cosine lobes, band 8, quadrature),
 *                1e-10; R1 R2 composition; the float planes version
 *   drift        10^4 composed small rotations: the SH matrices multiplied step by step
 *                drift (printed), rebuilding from the accumulated 3x3 re-orthonormalised
 *                each step stays orthogonal within 1e-12
 *   window       a delta light truncated to 3 bands: its radiance has the known negative
 *                lobe (closed form -1.8/(4 pi) at cos theta = -0.2); Hanning of width 3
 *                shrinks it (closed form -0.3/(4 pi)), the Gaussian window of width 1
 *                removes it (closed form) and the irradiance's too; the irradiance's lobe
 *                (closed form) and what each window does are printed
 *   cost         ns per evaluation for n = 3, 5, 8, 16 (float and double), printed only
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/check.h"
#include "lightgraph/sh.h"
#include "lightgraph/vecmath.h"

#define NMAX 64
#define NC (NMAX * NMAX)

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}
static void rnd_dir(double d[3])
{
    double z = 2.0 * rnd() - 1.0, phi = 2.0 * LG_PI * rnd(), r = sqrt(fmax(0.0, 1.0 - z * z));
    d[0] = r * cos(phi), d[1] = r * sin(phi), d[2] = z;
}

/* Independent reference: textbook formula in long double, with trigonometry. */
static void ref_eval(int n, const double d[3], long double *out)
{
    long double x = d[0], y = d[1], z = d[2];
    long double len = sqrtl(x * x + y * y + z * z);
    x /= len, y /= len, z /= len;
    long double phi = atan2l(y, x), st = sqrtl(fmaxl(0.0L, 1.0L - z * z));
    for (int m = 0; m < n; m++) {
        /* P_m^m = (2m-1)!! st^m (no CS phase), then the three-term recurrence. */
        long double pmm = 1.0L;
        for (int k = 1; k <= m; k++)
            pmm *= (2.0L * k - 1.0L) * st;
        long double p2 = 0, p1 = pmm;
        for (int l = m; l < n; l++) {
            long double p;
            if (l == m)
                p = pmm;
            else if (l == m + 1)
                p = (2.0L * m + 1.0L) * z * pmm;
            else
                p = ((2.0L * l - 1.0L) * z * p1 - (l + m - 1.0L) * p2) / (long double)(l - m);
            if (l > m)
                p2 = p1, p1 = p;
            long double k = sqrtl((2.0L * l + 1.0L) / (4.0L * (long double)LG_PI) *
                                  expl(lgammal(l - m + 1.0L) - lgammal(l + m + 1.0L)));
            if (m == 0) {
                out[l * (l + 1)] = k * p;
            } else {
                out[l * (l + 1) + m] = sqrtl(2.0L) * k * p * cosl(m * phi);
                out[l * (l + 1) - m] = sqrtl(2.0L) * k * p * sinl(m * phi);
            }
        }
    }
}

static const double axes[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                   { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };

static int cmd_eval(void)
{
    static double yd[NC];
    static float yf[NC];
    static long double yr[NC];
    double worst_d = 0.0, worst_f = 0.0;
    for (int t = 0; t < 300; t++) {
        double d[3];
        if (t < 6)
            memcpy(d, axes[t], sizeof d);
        else
            rnd_dir(d);
        /* Not unit: scaled. */
        double s = t % 3 == 0 ? 1e-20 : (t % 3 == 1 ? 7.5 : 1.0);
        double ds[3] = { d[0] * s, d[1] * s, d[2] * s };
        float fs[3] = { (float)d[0], (float)d[1], (float)d[2] };
        lg_sh_eval_d(NMAX, ds, yd);
        lg_sh_eval_f(16, fs, yf);
        ref_eval(NMAX, d, yr);
        for (int l = 0; l < NMAX; l++) {
            double scale = sqrt((2.0 * l + 1.0) / (4.0 * LG_PI));
            for (int m = -l; m <= l; m++) {
                int i = l * (l + 1) + m;
                double e = fabs(yd[i] - (double)yr[i]) / scale;
                if (e > worst_d)
                    worst_d = e;
                if (l < 16) {
                    /* The float version at float's own input direction, against the
                     * reference at the double one: input rounding is part of the error. */
                    double ef = fabs((double)yf[i] - (double)yr[i]) / scale;
                    if (ef > worst_f)
                        worst_f = ef;
                }
            }
        }
    }
    printf("eval: worst |error| / band scale: double (band 64) %.3g, float (band 16) %.3g\n",
           worst_d, worst_f);
    CHECKF(worst_d < 1e-10, "%g", worst_d);
    CHECKF(worst_f < 2e-5, "%g", worst_f);

    /* Degenerate directions: -Z, finite. */
    double ref[NC];
    const double mz[3] = { 0, 0, -1 };
    lg_sh_eval_d(NMAX, mz, ref);
    const double bad[5][3] = {
        { 0, 0, 0 }, { 1e-31, -1e-31, 0 }, { NAN, 0, 1 }, { INFINITY, 0, 0 }, { 0, -INFINITY, NAN }
    };
    for (int b = 0; b < 5; b++) {
        lg_sh_eval_d(NMAX, bad[b], yd);
        int same = 1;
        for (int i = 0; i < NC; i++)
            same &= isfinite(yd[i]) && yd[i] == ref[i];
        CHECKF(same, "degenerate direction %d is not -Z", b);
        float fb[3] = { (float)bad[b][0], (float)bad[b][1], (float)bad[b][2] };
        lg_sh_eval_f(NMAX, fb, yf);
        int ok = 1;
        for (int i = 0; i < NC; i++)
            ok &= isfinite(yf[i]) && fabs(yf[i] - ref[i]) < 1e-3;
        CHECKF(ok, "float degenerate direction %d is not -Z", b);
    }
    /* Huge components: no overflow. */
    const double huge[3] = { 1e300, 1e300, -1e300 };
    const double unit[3] = { 1, 1, -1 };
    double yu[NC];
    lg_sh_eval_d(NMAX, huge, yd);
    lg_sh_eval_d(NMAX, unit, yu);
    double e = 0;
    for (int i = 0; i < NC; i++)
        e = fmax(e, fabs(yd[i] - yu[i]));
    CHECKF(e < 1e-14, "huge direction: %g", e);
    /* float at band 64 stays finite everywhere. */
    for (int t = 0; t < 200; t++) {
        double d[3];
        rnd_dir(d);
        float f[3] = { (float)d[0], (float)d[1], (float)d[2] };
        lg_sh_eval_f(NMAX, f, yf);
        int ok = 1;
        for (int i = 0; i < NC; i++)
            ok &= isfinite(yf[i]) && fabsf(yf[i]) < 10.0f;
        CHECK(ok);
    }
    return check_report("sh_eval");
}

static int cmd_addition(void)
{
    static double yd[NC];
    static float yf[NC];
    double worst_d = 0.0, worst_f = 0.0;
    for (int t = 0; t < 2006; t++) {
        double d[3];
        if (t < 6)
            memcpy(d, axes[t], sizeof d);
        else
            rnd_dir(d);
        float f[3] = { (float)d[0], (float)d[1], (float)d[2] };
        lg_sh_eval_d(NMAX, d, yd);
        lg_sh_eval_f(16, f, yf);
        for (int l = 0; l < NMAX; l++) {
            double want = (2.0 * l + 1.0) / (4.0 * LG_PI), sd = 0.0, sf = 0.0;
            for (int m = -l; m <= l; m++) {
                sd += yd[l * (l + 1) + m] * yd[l * (l + 1) + m];
                if (l < 16)
                    sf += (double)yf[l * (l + 1) + m] * yf[l * (l + 1) + m];
            }
            worst_d = fmax(worst_d, fabs(sd / want - 1.0));
            if (l < 16)
                worst_f = fmax(worst_f, fabs(sf / want - 1.0));
        }
        if (t == 5) {
            printf("addition at +-x, +-y, +-z: worst relative error double %.3g, float %.3g\n",
                   worst_d, worst_f);
            CHECKF(worst_d < 1e-10 && worst_f < 1e-4, "%g %g", worst_d, worst_f);
        }
    }
    printf("addition, 2000 random directions as well: double (band 64) %.3g, float (band "
           "16) %.3g\n",
           worst_d, worst_f);
    CHECKF(worst_d < 1e-10, "%g", worst_d);
    CHECKF(worst_f < 1e-4, "%g", worst_f);
    return check_report("sh_addition");
}

/* Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_k). */
static void gauss_legendre(int k, double *x, double *w)
{
    for (int i = 0; i < k; i++) {
        double z = cos(LG_PI * (i + 0.75) / (k + 0.5)), pp = 0.0;
        for (int it = 0; it < 100; it++) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= k; j++) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = k * (z * p1 - p2) / (z * z - 1.0);
            double dz = p1 / pp;
            z -= dz;
            if (fabs(dz) < 1e-16)
                break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * pp * pp);
    }
}

/* Quadrature on the sphere: nz Gauss-Legendre nodes in z x nphi uniform azimuths; exact
 * for polynomials of degree < min(2 nz, nphi). Calls f(dir, weight, ctx). */
typedef void (*quad_fn)(const double d[3], double w, void *ctx);
static void sphere_quad(int nz, int nphi, quad_fn f, void *ctx)
{
    double *x = malloc(sizeof(double) * (size_t)nz), *w = malloc(sizeof(double) * (size_t)nz);
    gauss_legendre(nz, x, w);
    for (int i = 0; i < nz; i++) {
        double r = sqrt(fmax(0.0, 1.0 - x[i] * x[i]));
        for (int j = 0; j < nphi; j++) {
            double phi = 2.0 * LG_PI * (j + 0.5) / nphi;
            double d[3] = { r * cos(phi), r * sin(phi), x[i] };
            f(d, w[i] * 2.0 * LG_PI / nphi, ctx);
        }
    }
    free(x);
    free(w);
}

struct gram {
    int n;
    double g[64 * 64];
};
static void gram_acc(const double d[3], double w, void *ctx)
{
    struct gram *g = ctx;
    double y[64];
    int nc = g->n * g->n;
    lg_sh_eval_d((uint32_t)g->n, d, y);
    for (int i = 0; i < nc; i++)
        for (int j = 0; j < nc; j++)
            g->g[i * nc + j] += w * y[i] * y[j];
}

static int cmd_orthonormal(void)
{
    static struct gram g;
    g.n = 8;
    sphere_quad(10, 20, gram_acc, &g);
    double worst = 0.0;
    for (int i = 0; i < 64; i++)
        for (int j = 0; j < 64; j++)
            worst = fmax(worst, fabs(g.g[i * 64 + j] - (i == j)));
    printf("orthonormality, band 8, Gauss-Legendre 10 x 20: worst |G - I| %.3g\n", worst);
    CHECKF(worst < 1e-12, "%g", worst);
    return check_report("sh_orthonormal");
}

static int cmd_band1(void)
{
    double y[9];
    const double d[3] = { 0.3, -0.5, 0.8124038404635961 };
    lg_sh_eval_d(3, d, y);
    double x = d[0], yy = d[1], z = d[2];
    double c1 = sqrt(3.0 / (4.0 * LG_PI));
    CHECK(fabs(c1 - 0.488603) < 1e-6);
    CHECKF(fabs(y[1] - c1 * yy) < 1e-15, "Y_1,-1 %g", y[1]);
    CHECKF(fabs(y[2] - c1 * z) < 1e-15, "Y_1,0 %g", y[2]);
    CHECKF(fabs(y[3] - c1 * x) < 1e-15, "Y_1,1 %g", y[3]);
    /* Signs at the axes: +0.488603 at +y for Y_1,-1 etc. */
    double t[9];
    lg_sh_eval_d(2, axes[2], t);
    CHECK(fabs(t[1] - 0.488603) < 1e-6);
    lg_sh_eval_d(2, axes[4], t);
    CHECK(fabs(t[2] - 0.488603) < 1e-6);
    lg_sh_eval_d(2, axes[0], t);
    CHECK(fabs(t[3] - 0.488603) < 1e-6);
    /* Band 2 closed forms (docs/sh.md table). */
    double c2 = 0.5 * sqrt(15.0 / LG_PI), c20 = 0.25 * sqrt(5.0 / LG_PI);
    double want[5] = { c2 * x * yy, c2 * yy * z, c20 * (3.0 * z * z - 1.0), c2 * x * z,
                       0.5 * c2 * (x * x - yy * yy) };
    for (int m = 0; m < 5; m++)
        CHECKF(fabs(y[4 + m] - want[m]) < 1e-15, "Y_2,%d", m - 2);
    double c00 = 0.5 / sqrt(LG_PI);
    CHECK(fabs(y[0] - c00) < 1e-16);
    float f[9];
    const float df[3] = { 0.3f, -0.5f, 0.8124038f };
    lg_sh_eval_f(3, df, f);
    for (int i = 0; i < 9; i++)
        CHECKF(fabs(f[i] - y[i]) < 1e-6, "float %d", i);
    return check_report("sh_band1");
}

struct zq {
    int l;
    double s;
};
static int cmd_zonal(void)
{
    const double want[7] = { LG_PI, 2 * LG_PI / 3, LG_PI / 4, 0, -LG_PI / 24, 0, LG_PI / 64 };
    for (uint32_t l = 0; l < 7; l++)
        CHECKF(fabs(lg_sh_clamped_cosine(l) - want[l]) < 1e-15, "A_%u = %.17g", l,
               lg_sh_clamped_cosine(l));
    /* Independent: A_l = sqrt(4pi/(2l+1)) * (coefficient of max(cos, 0) on Y_l0)
     *             = 2 pi int_0^1 z P_l(z) dz, by Gauss-Legendre on [0, 1] (exact: the
     * integrand is a polynomial of degree l + 1). */
    double x[32], w[32];
    gauss_legendre(32, x, w);
    double worst = 0.0;
    for (int l = 0; l <= 40; l++) {
        double s = 0.0;
        for (int i = 0; i < 32; i++) {
            double z = 0.5 * (x[i] + 1.0), p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= l; j++) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            s += 0.5 * w[i] * z * p1;
        }
        s *= 2.0 * LG_PI;
        worst = fmax(worst, fabs(s - lg_sh_clamped_cosine((uint32_t)l)));
    }
    printf("A_l against quadrature, l <= 40: worst %.3g\n", worst);
    CHECKF(worst < 1e-13, "%g", worst);
    for (uint32_t l = 0; l <= 100000; l += 1 + l / 10) {
        double a = lg_sh_clamped_cosine(l);
        CHECKF(isfinite(a) && fabs(a) <= LG_PI, "A_%u = %g", l, a);
    }
    printf("A_1000 = %.6g, A_100000 = %.6g\n", lg_sh_clamped_cosine(1000),
           lg_sh_clamped_cosine(100000));
    return check_report("sh_zonal");
}

/* Projection by quadrature of f given as a callback. */
typedef double (*sph_fn)(const double d[3], const void *ctx);
struct proj {
    int n;
    sph_fn f;
    const void *fctx;
    double c[NC];
};
static void proj_acc(const double d[3], double w, void *ctx)
{
    struct proj *p = ctx;
    static double y[NC];
    lg_sh_eval_d((uint32_t)p->n, d, y);
    double v = p->f(d, p->fctx) * w;
    for (int i = 0; i < p->n * p->n; i++)
        p->c[i] += v * y[i];
}
static void project(int n, sph_fn f, const void *fctx, int nz, int nphi, double *out)
{
    static struct proj p;
    memset(&p, 0, sizeof p);
    p.n = n, p.f = f, p.fctx = fctx;
    sphere_quad(nz, nphi, proj_acc, &p);
    memcpy(out, p.c, sizeof(double) * (size_t)(n * n));
}
static double f_const(const double d[3], const void *ctx)
{
    (void)d;
    return *(const double *)ctx;
}
/* Irradiance at normal nrm from radiance coefficients. */
static double irradiance(int n, const double *c, const double nrm[3])
{
    double y[NC], e = 0.0;
    lg_sh_eval_d((uint32_t)n, nrm, y);
    for (int l = 0; l < n; l++)
        for (int m = -l; m <= l; m++)
            e += lg_sh_clamped_cosine((uint32_t)l) * c[l * (l + 1) + m] * y[l * (l + 1) + m];
    return e;
}

static void axis_angle(const double ax[3], double ang, double *R);
static double f_sky(const double d[3], const void *ctx)
{
    (void)ctx;
    return d[1] > 0.0 ? 1.0 : 0.0;
}

static int cmd_irradiance(void)
{
    double c = 2.5, co[NC];
    project(8, f_const, &c, 16, 32, co);
    double worst = 0.0;
    for (int t = 0; t < 200; t++) {
        double d[3];
        rnd_dir(d);
        worst = fmax(worst, fabs(irradiance(8, co, d) - LG_PI * c));
    }
    printf("constant environment 2.5: worst |E - 2.5 pi| %.3g\n", worst);
    CHECKF(worst < 1e-12, "%g", worst);
    /* A delta light at +x (coefficients Y(+x)): more irradiance at +x than at -x. */
    double yl[9];
    lg_sh_eval_d(3, axes[0], yl);
    double ep = irradiance(3, yl, axes[0]), em = irradiance(3, yl, axes[1]);
    printf("delta light at +x, 9 coefficients: E(+x) %.6f, E(-x) %.6f\n", ep, em);
    CHECK(ep > em && ep > 0.0);

    /* An upper-hemisphere sky (radiance 1 for w.y > 0): its irradiance is exactly
     * (pi/2)(1 + n_y), and so is its 9-coefficient one: about +z the sky is zonal with
     * L_00 = sqrt(pi), L_10 = pi sqrt(3 / (4 pi)), L_20 = 0 (2 pi K_l int_0^1 P_l), and
     * A_l = 0 for odd l > 1, so no band beyond 1 contributes. Built about +z, turned to +y
     * by lg_sh_rotation_build (rotation about x by -90 degrees: +z -> +y). */
    double sky[9] = { 0 }, skyy[9], Rx[9], Msky[35];
    sky[0] = sqrt(LG_PI);
    sky[2] = LG_PI * sqrt(3.0 / (4.0 * LG_PI));
    axis_angle((const double[3]){ 1, 0, 0 }, -0.5 * LG_PI, Rx);
    CHECK(fabs(Rx[5] + 1.0) < 1e-15 || fabs(Rx[5] - 1.0) < 1e-15);
    lg_sh_rotation_build(3, Rx, Msky);
    lg_sh_rotate(3, Msky, sky, skyy);
    /* And by quadrature of the discontinuous sky (not exact: printed, loose bound). */
    static double skyq[NC];
    project(3, f_sky, NULL, 200, 400, skyq);
    double worst_sky = 0.0, worst_q = 0.0;
    for (int t = 0; t < 200; t++) {
        double d[3];
        if (t < 6)
            memcpy(d, axes[t], sizeof d);
        else
            rnd_dir(d);
        double want = 0.5 * LG_PI * (1.0 + d[1]);
        worst_sky = fmax(worst_sky, fabs(irradiance(3, skyy, d) - want));
        worst_q = fmax(worst_q, fabs(irradiance(3, skyq, d) - want));
    }
    printf("upper-hemisphere sky, 9 coefficients: worst |E - (pi/2)(1 + n_y)| %.3g (closed "
           "form coefficients, rotated), %.3g (projected by 200 x 400 quadrature)\n",
           worst_sky, worst_q);
    CHECKF(worst_sky < 1e-12, "%g", worst_sky);
    CHECKF(worst_q < 1e-3, "%g", worst_q);
    return check_report("sh_irradiance");
}

static void mat_mul(const double *a, const double *b, double *o)
{
    double t[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            t[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
    memcpy(o, t, sizeof t);
}
/* Rotation by angle about unit axis (Rodrigues). */
static void axis_angle(const double ax[3], double ang, double *R)
{
    double c = cos(ang), s = sin(ang), t = 1.0 - c, x = ax[0], y = ax[1], z = ax[2];
    double l = sqrt(x * x + y * y + z * z);
    x /= l, y /= l, z /= l;
    double m[9] = { t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
                    t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
                    t * x * z - s * y, t * y * z + s * x, t * z * z + c };
    memcpy(R, m, sizeof m);
}
static void random_rotation(double *R)
{
    double ax[3];
    rnd_dir(ax);
    axis_angle(ax, 2.0 * LG_PI * rnd(), R);
}

/* f = sum of clamped-cosine lobes around fixed axes, with weights. */
struct lobes {
    double R[9];
    int rotated;
};
static double f_lobes(const double d[3], const void *ctx)
{
    const struct lobes *L = ctx;
    double q[3] = { d[0], d[1], d[2] };
    if (L->rotated) { /* f(R^T d) */
        const double *R = L->R;
        q[0] = R[0] * d[0] + R[3] * d[1] + R[6] * d[2];
        q[1] = R[1] * d[0] + R[4] * d[1] + R[7] * d[2];
        q[2] = R[2] * d[0] + R[5] * d[1] + R[8] * d[2];
    }
    /* A polynomial (exact under the quadrature) of degree up to 4, no symmetry. */
    double x = q[0], y = q[1], z = q[2];
    return 1.0 + 0.7 * x - 0.3 * y + 0.2 * z + 1.5 * x * y - 0.8 * z * z + 0.4 * y * z * x +
           0.9 * x * x * x * z - 0.5 * y * y * y * y;
}

static double max_diff(const double *a, const double *b, int n)
{
    double e = 0.0;
    for (int i = 0; i < n; i++)
        e = fmax(e, fabs(a[i] - b[i]));
    return e;
}

static int cmd_rotation(void)
{
    static double M[349504], M2[349504], M12[349504];
    static double c[NC], r[NC], r2[NC], q[NC];
    const double I[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    /* Identity. */
    CHECK(lg_sh_rotation_build(20, I, M) == 0);
    for (int l = 0; l < 20; l++) {
        int w = 2 * l + 1;
        const double *b = M + lg_sh_rotation_size((uint32_t)l);
        double e = 0.0;
        for (int i = 0; i < w; i++)
            for (int j = 0; j < w; j++)
                e = fmax(e, fabs(b[i * w + j] - (i == j)));
        CHECKF(e < 1e-14, "identity band %d: %g", l, e);
    }
    CHECK(lg_sh_rotation_size(64) == 349504);
    /* Energy per band, random coefficients, random rotations, 20 bands. */
    double worst_e = 0.0;
    for (int t = 0; t < 10; t++) {
        double R[9];
        random_rotation(R);
        lg_sh_rotation_build(20, R, M);
        for (int i = 0; i < 400; i++)
            c[i] = 2.0 * rnd() - 1.0;
        lg_sh_rotate(20, M, c, r);
        for (int l = 0; l < 20; l++) {
            double e0 = 0, e1 = 0;
            for (int i = l * l; i < (l + 1) * (l + 1); i++)
                e0 += c[i] * c[i], e1 += r[i] * r[i];
            worst_e = fmax(worst_e, fabs(e1 / e0 - 1.0));
        }
    }
    printf("rotation: per-band energy, 20 bands: worst relative change %.3g\n", worst_e);
    CHECKF(worst_e < 1e-12, "%g", worst_e);
    /* Against re-projection: band 8 holds the degree-4 test function exactly. */
    double worst_p = 0.0;
    for (int t = 0; t < 5; t++) {
        struct lobes L = { .rotated = 0 };
        random_rotation(L.R);
        if (t == 0)
            axis_angle((const double[3]){ 0, 1, 0 }, 0.5 * LG_PI, L.R); /* about up */
        project(8, f_lobes, &L, 12, 24, c);
        L.rotated = 1;
        project(8, f_lobes, &L, 12, 24, q);
        lg_sh_rotation_build(8, L.R, M);
        lg_sh_rotate(8, M, c, r);
        worst_p = fmax(worst_p, max_diff(r, q, 64));
        /* In place gives the same. */
        memcpy(r2, c, sizeof(double) * 64);
        lg_sh_rotate(8, M, r2, r2);
        CHECK(max_diff(r, r2, 64) == 0.0);
    }
    printf("rotation: rotate(project(f)) vs project(f o R^T), band 8: worst %.3g\n", worst_p);
    CHECKF(worst_p < 1e-10, "%g", worst_p);
    /* And for a high band count, by point evaluation: sum c_i Y_i(R^T d)... equivalently
     * the rotated coefficients evaluated at R d equal the original at d. */
    double worst_h = 0.0;
    {
        double R[9], y0[NC], y1[NC], d[3], rd[3];
        random_rotation(R);
        lg_sh_rotation_build(NMAX, R, M);
        for (int i = 0; i < NC; i++)
            c[i] = (2.0 * rnd() - 1.0) / (1.0 + i / 64.0);
        lg_sh_rotate(NMAX, M, c, r);
        for (int t = 0; t < 20; t++) {
            rnd_dir(d);
            for (int k = 0; k < 3; k++)
                rd[k] = R[k * 3] * d[0] + R[k * 3 + 1] * d[1] + R[k * 3 + 2] * d[2];
            lg_sh_eval_d(NMAX, d, y0);
            lg_sh_eval_d(NMAX, rd, y1);
            double f0 = 0, f1 = 0;
            for (int i = 0; i < NC; i++)
                f0 += c[i] * y0[i], f1 += r[i] * y1[i];
            worst_h = fmax(worst_h, fabs(f1 - f0));
        }
    }
    printf("rotation: band 64, g(R d) = f(d) at 20 points: worst %.3g\n", worst_h);
    CHECKF(worst_h < 1e-9, "%g", worst_h);
    /* Composition: M(R1 R2) = M(R1) M(R2) (apply R2 then R1). */
    {
        double R1[9], R2[9], R12[9];
        random_rotation(R1);
        random_rotation(R2);
        mat_mul(R1, R2, R12);
        lg_sh_rotation_build(16, R1, M);
        lg_sh_rotation_build(16, R2, M2);
        lg_sh_rotation_build(16, R12, M12);
        for (int i = 0; i < 256; i++)
            c[i] = 2.0 * rnd() - 1.0;
        lg_sh_rotate(16, M2, c, r);
        lg_sh_rotate(16, M, r, r);
        lg_sh_rotate(16, M12, c, r2);
        double e = max_diff(r, r2, 256);
        printf("rotation: composition, 16 bands: %.3g\n", e);
        CHECKF(e < 1e-12, "%g", e);
        /* Float planes (RGB) against double. */
        static float fin[3 * 256], fout[3 * 256];
        for (int p = 0; p < 3; p++)
            for (int i = 0; i < 256; i++)
                fin[p * 256 + i] = (float)c[i] * (float)(p + 1);
        lg_sh_rotate_planes_f(16, M12, 3, fin, fout);
        double ef = 0.0;
        for (int p = 0; p < 3; p++)
            for (int i = 0; i < 256; i++)
                ef = fmax(ef, fabs(fout[p * 256 + i] - r2[i] * (p + 1)));
        CHECKF(ef < 1e-5, "float planes %g", ef);
    }
    double nanR[9] = { NAN, 0, 0, 0, 1, 0, 0, 0, 1 };
    CHECK(lg_sh_rotation_build(4, nanR, M) == -1);
    return check_report("sh_rotation");
}

/* Worst deviation from orthogonality of the block-diagonal SH matrices. */
static double orth_error(int n, const double *M)
{
    double e = 0.0;
    for (int l = 0; l < n; l++) {
        int w = 2 * l + 1;
        const double *b = M + lg_sh_rotation_size((uint32_t)l);
        for (int i = 0; i < w; i++)
            for (int j = 0; j < w; j++) {
                double s = 0.0;
                for (int k = 0; k < w; k++)
                    s += b[i * w + k] * b[j * w + k];
                e = fmax(e, fabs(s - (i == j)));
            }
    }
    return e;
}

static int cmd_drift(void)
{
    enum { N = 8, STEPS = 10000 };
    static double step_m[1000], acc_m[1000], tmp[1000], abs_m[1000];
    double Rs[9], Racc[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    axis_angle((const double[3]){ 0.3, 1.0, -0.2 }, 0.0123, Rs);
    lg_sh_rotation_build(N, Rs, step_m);
    lg_sh_rotation_build(N, Racc, acc_m);
    double worst_abs = 0.0;
    for (int s = 0; s < STEPS; s++) {
        /* The wrong way: multiply SH matrices step after step. */
        for (int l = 0; l < N; l++) {
            int w = 2 * l + 1;
            size_t o = lg_sh_rotation_size((uint32_t)l);
            for (int i = 0; i < w; i++)
                for (int j = 0; j < w; j++) {
                    double v = 0.0;
                    for (int k = 0; k < w; k++)
                        v += step_m[o + i * w + k] * acc_m[o + k * w + j];
                    tmp[o + i * w + j] = v;
                }
        }
        memcpy(acc_m, tmp, sizeof(double) * lg_sh_rotation_size(N));
        /* The right way: accumulate the 3x3, re-orthonormalise, rebuild. */
        mat_mul(Rs, Racc, Racc);
        lg_sh_orthonormalize(Racc);
        if (s % 1000 == 999 || s == STEPS - 1) {
            lg_sh_rotation_build(N, Racc, abs_m);
            worst_abs = fmax(worst_abs, orth_error(N, abs_m));
        }
    }
    double drift = orth_error(N, acc_m);
    printf("drift after %d steps: SH matrices multiplied %.3g, rebuilt from the 3x3 %.3g\n", STEPS,
           drift, worst_abs);
    CHECKF(worst_abs < 1e-12, "%g", worst_abs);
    /* The rebuilt orientation is still the true one: 10^4 steps of angle a about a fixed
     * axis is one rotation of 10^4 a. */
    double Rtrue[9];
    axis_angle((const double[3]){ 0.3, 1.0, -0.2 }, 0.0123 * STEPS, Rtrue);
    CHECKF(max_diff(Racc, Rtrue, 9) < 1e-9, "%g", max_diff(Racc, Rtrue, 9));
    return check_report("sh_drift");
}

/* Radiance reconstructed from coefficients c (n bands) at direction d. */
static double reconstruct(int n, const double *c, const double d[3])
{
    double y[NC], v = 0.0;
    lg_sh_eval_d((uint32_t)n, d, y);
    for (int i = 0; i < n * n; i++)
        v += c[i] * y[i];
    return v;
}
/* Minimum over theta in [0, pi] (azimuth 0) of f(c, dir(theta)), light at +z. */
static double min_over_theta(double (*f)(int, const double *, const double *), const double *c,
                             double *t_at)
{
    double mn = 1e9;
    for (int k = 0; k <= 4000; k++) {
        double t = -1.0 + k / 2000.0, s = sqrt(fmax(0.0, 1.0 - t * t));
        double d[3] = { s, 0.0, t };
        double v = f(3, c, d);
        if (v < mn)
            mn = v, *t_at = t;
    }
    return mn;
}

static int cmd_window(void)
{
    /* A unit delta light at +z: coefficients Y_lm(+z). By the addition theorem its 3-band
     * radiance is L(t) = (1 + 3 w1 t + 5 w2 P_2(t)) / (4 pi), t = cos theta, w_l the
     * window factors (1 unwindowed): 4 pi L = (1 - 5 w2 / 2) + 3 w1 t + 7.5 w2 t^2.
     * Unwindowed: minimum at t = -0.2, -1.8 / (4 pi) = -0.14324, the negative lobe.
     * Hanning of width 3 (w1 = 3/4, w2 = 1/4): minimum at t = -0.6, -0.3 / (4 pi): smaller
     * but there. Gaussian of width 1 (w1 = e^-1, w2 = e^-3): the vertex t = -w1/(15 w2 / 3)
     * is below -1, the minimum is at t = -1: (1 - 3 e^-1 + 5 e^-3) / (4 pi) > 0: gone. */
    double c[9], cw[9], t;
    lg_sh_eval_d(3, axes[4], c);
    double lmin = min_over_theta(reconstruct, c, &t);
    printf("delta light, 3 bands, radiance: min %.6f at cos theta %.4f (closed form %.6f at "
           "-0.2)\n",
           lmin, t, -1.8 / (4.0 * LG_PI));
    CHECKF(fabs(lmin + 1.8 / (4.0 * LG_PI)) < 1e-6, "%g", lmin);
    memcpy(cw, c, sizeof c);
    lg_sh_window(3, LG_SH_WINDOW_HANNING, 3.0, cw);
    double wmin = min_over_theta(reconstruct, cw, &t);
    printf("  hanning width 3: radiance min %.6f at %.4f (closed form %.6f at -0.6), peak "
           "%.6f (unwindowed %.6f)\n",
           wmin, t, -0.3 / (4.0 * LG_PI), reconstruct(3, cw, axes[4]), reconstruct(3, c, axes[4]));
    CHECKF(fabs(wmin + 0.3 / (4.0 * LG_PI)) < 1e-6, "%g", wmin);
    CHECKF(fabs(cw[2] - 0.75 * c[2]) < 1e-15 && fabs(cw[6] - 0.25 * c[6]) < 1e-15, "factors");
    memcpy(cw, c, sizeof c);
    lg_sh_window(3, LG_SH_WINDOW_GAUSSIAN, 1.0, cw);
    double gmin = min_over_theta(reconstruct, cw, &t);
    double gclosed = (1.0 - 3.0 * exp(-1.0) + 5.0 * exp(-3.0)) / (4.0 * LG_PI);
    double gemin = min_over_theta(irradiance, cw, &t);
    printf("  gaussian width 1: radiance min %.6f (closed form %.6f at -1), peak %.6f; "
           "irradiance min %.6f, peak %.6f\n",
           gmin, gclosed, reconstruct(3, cw, axes[4]), gemin, irradiance(3, cw, axes[4]));
    CHECKF(gmin > 0.0 && fabs(gmin - gclosed) < 1e-12, "%g", gmin);
    CHECKF(gemin > 0.0, "%g", gemin);

    /* Irradiance of the same light: E(t) = 1/4 + t/2 + (5/16) P_2(t), minimum at
     * t = -8/15: -0.039583 (exact: max(t, 0)). Printed with the windows: windowing the
     * radiance does not make this one non-negative (at t = -1 it needs w1 <= 1/2 + 5 w2 / 8,
     * which no Hanning or Lanczos width above 2 gives); docs/sh.md says so. */
    double tmin = -8.0 / 15.0;
    double Emin_closed = 0.25 + 0.5 * tmin + (5.0 / 16.0) * 0.5 * (3.0 * tmin * tmin - 1.0);
    double emin = min_over_theta(irradiance, c, &t);
    printf("delta light, 3 bands, irradiance: min %.6f at cos theta %.4f (closed form %.6f "
           "at %.4f), peak %.6f (exact 1)\n",
           emin, t, Emin_closed, tmin, irradiance(3, c, axes[4]));
    CHECKF(fabs(emin - Emin_closed) < 1e-6, "%g", emin);
    CHECKF(fabs(irradiance(3, c, axes[5]) - 1.0 / 16.0) < 1e-14, "antipode");
    const double widths[2] = { 3.0, 4.0 };
    for (int wk = 0; wk < 2; wk++)
        for (int kind = 0; kind < 3; kind++) {
            memcpy(cw, c, sizeof c);
            lg_sh_window(3, (lg_sh_window_kind)kind, widths[wk], cw);
            printf("  %s width %.0f: radiance min %.6f; irradiance min %.6f, peak %.6f\n",
                   kind == 2 ? "gaussian"
                   : kind    ? "lanczos"
                             : "hanning",
                   widths[wk], min_over_theta(reconstruct, cw, &t),
                   min_over_theta(irradiance, cw, &t), irradiance(3, cw, axes[4]));
        }
    /* Band 0 untouched, nothing at and beyond width, no-op for width <= 0. */
    CHECK(lg_sh_window_factor(LG_SH_WINDOW_HANNING, 3.0, 0) == 1.0);
    CHECK(lg_sh_window_factor(LG_SH_WINDOW_LANCZOS, 3.0, 3) == 0.0);
    CHECK(lg_sh_window_factor(LG_SH_WINDOW_HANNING, 0.0, 5) == 1.0);
    CHECK(fabs(lg_sh_window_factor(LG_SH_WINDOW_HANNING, 4.0, 2) - 0.5) < 1e-15);
    CHECK(fabs(lg_sh_window_factor(LG_SH_WINDOW_LANCZOS, 2.0, 1) - 2.0 / LG_PI) < 1e-15);
    return check_report("sh_window");
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int cmd_cost(void)
{
    static double yd[NC];
    static float yf[NC];
    const uint32_t ns[4] = { 3, 5, 8, 16 };
    enum { K = 256 };
    static double dirs[K][3];
    static float fdirs[K][3];
    for (int i = 0; i < K; i++) {
        rnd_dir(dirs[i]);
        for (int k = 0; k < 3; k++)
            fdirs[i][k] = (float)dirs[i][k];
    }
    volatile double sink = 0.0;
    for (int b = 0; b < 4; b++) {
        uint32_t n = ns[b];
        long reps = 200000 / (long)(n * n) + 1000;
        double t0 = now_s();
        for (long r = 0; r < reps; r++) {
            lg_sh_eval_f(n, fdirs[r % K], yf);
            sink += yf[n * n - 1];
        }
        double t1 = now_s();
        for (long r = 0; r < reps; r++) {
            lg_sh_eval_d(n, dirs[r % K], yd);
            sink += yd[n * n - 1];
        }
        double t2 = now_s();
        printf("cost n = %2u (%3u values): float %.1f ns, double %.1f ns per evaluation\n", n,
               n * n, (t1 - t0) / reps * 1e9, (t2 - t1) / reps * 1e9);
    }
    (void)sink;
    return check_report("sh_cost");
}

int main(int argc, char **argv)
{
    const char *c = argc > 1 ? argv[1] : "";
    if (!strcmp(c, "eval"))
        return cmd_eval();
    if (!strcmp(c, "addition"))
        return cmd_addition();
    if (!strcmp(c, "orthonormal"))
        return cmd_orthonormal();
    if (!strcmp(c, "band1"))
        return cmd_band1();
    if (!strcmp(c, "zonal"))
        return cmd_zonal();
    if (!strcmp(c, "irradiance"))
        return cmd_irradiance();
    if (!strcmp(c, "rotation"))
        return cmd_rotation();
    if (!strcmp(c, "drift"))
        return cmd_drift();
    if (!strcmp(c, "window"))
        return cmd_window();
    if (!strcmp(c, "cost"))
        return cmd_cost();
    fprintf(stderr, "usage: test_sh eval|addition|orthonormal|band1|zonal|irradiance|"
                    "rotation|drift|window|cost\n");
    return 2;
}
