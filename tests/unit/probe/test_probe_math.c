/*
 * The probe conventions of lightgraph/probe.h on the CPU (issue 9, deliverable 1 and the
 * maths of 4 and 5):
 *
 *   test_probe_math solid_angles   every layout at several sizes sums to 4 pi (1e-6
 *                                  relative); the angular map's texels against an
 *                                  independent polar-integral oracle, rim texels included
 *   test_probe_math conventions    lat-long, angular and cube spot directions
 *   test_probe_math roundtrip      texel -> direction -> texel for every texel
 *   test_probe_math hard_dirs      axes, poles, seam, centre, rim; zero, denormal,
 *                                  non-unit, NaN and Inf directions
 *   test_probe_math continuity     bilinear lookups across cube edges and corners, the
 *                                  lat-long seam and poles; 1x1 and constant images
 *   test_probe_math rotation       yaw/pitch/roll conventions, 360 = identity, lookups
 *                                  with a rotation
 *   test_probe_math cost           ns per call of the maps and lookups (printed)
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/check.h"
#include "lightgraph/probe.h"

static const char *layout_name(lg_probe_layout l)
{
    return l == LG_PROBE_LATLONG ? "latlong" : l == LG_PROBE_ANGULAR ? "angular" : "cube";
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static lg_vec3 rnd_dir(void)
{
    double z = 2 * rnd() - 1, a = 2 * LG_PI * rnd(), s = sqrt(1 - z * z);
    return lg_v3((float)(s * cos(a)), (float)(s * sin(a)), (float)z);
}

static size_t texel_count(lg_probe_layout l, uint32_t w, uint32_t h)
{
    return (size_t)w * h * (l == LG_PROBE_CUBE ? 6 : 1);
}

/* An image of random RGBA in [0, 1) (alpha too). */
static float *rnd_image(lg_probe_layout l, uint32_t w, uint32_t h)
{
    size_t n = texel_count(l, w, h) * 4;
    float *p = malloc(n * sizeof *p);
    for (size_t k = 0; k < n; k++)
        p[k] = (float)rnd();
    return p;
}

static void lookup(lg_probe_layout l, uint32_t w, uint32_t h, const float *rgba, const float *rot,
                   lg_vec3 d, lg_probe_sampling s, float out[4])
{
    lg_probe_image img = { l, w, h, rgba, rot, { 0 } };
    lg_probe_lookup(&img, d, s, out);
}

static double diff4(const float *a, const float *b)
{
    double m = 0;
    for (int k = 0; k < 4; k++)
        m = fmax(m, fabs((double)a[k] - b[k]));
    return m;
}

static int finite4(const float *a)
{
    return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]) && isfinite(a[3]);
}

/* ---- solid angles ---------------------------------------------------------------------------- */

/* Oracle for one angular texel, written independently of probe.c: in polar coordinates
 * about the disc's centre, sum over rays phi of the integral of pi sin(pi r) dr over the
 * part of the ray inside the texel and the disc, i.e. cos(pi r_in) - cos(pi r_out) with
 * both clipped to 1; integrated over phi by Gauss-Legendre between the breakpoints
 * (corners, where the circle crosses an edge), where the integrand is smooth. */
static double ray_part(double x0, double x1, double y0, double y1, double c, double s)
{
    double tin = 0, tout = 1e300;
    double lo[2] = { x0, y0 }, hi[2] = { x1, y1 }, dd[2] = { c, s };
    for (int k = 0; k < 2; k++) {
        if (fabs(dd[k]) < 1e-300) {
            if (0 < lo[k] || 0 > hi[k])
                return 0;
            continue;
        }
        double t1 = lo[k] / dd[k], t2 = hi[k] / dd[k];
        if (t1 > t2) {
            double t = t1;
            t1 = t2;
            t2 = t;
        }
        tin = fmax(tin, t1);
        tout = fmin(tout, t2);
    }
    if (!(tout > tin) || tin >= 1)
        return 0;
    return cos(LG_PI * tin) - cos(LG_PI * fmin(tout, 1));
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double angular_oracle(uint32_t n, uint32_t i, uint32_t j)
{
    double x0 = 2.0 * i / n - 1, x1 = 2.0 * (i + 1) / n - 1;
    double y1 = 1 - 2.0 * j / n, y0 = 1 - 2.0 * (j + 1) / n;
    double bp[32];
    int nb = 0;
    int origin_inside = x0 < 0 && x1 > 0 && y0 < 0 && y1 > 0;
    double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    double base = origin_inside ? 0 : atan2(cy, cx);
    double xs[2] = { x0, x1 }, ys[2] = { y0, y1 };
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) {
            if (xs[a] == 0 && ys[b] == 0)
                continue;
            double d = atan2(ys[b], xs[a]) - base;
            while (d > LG_PI)
                d -= 2 * LG_PI;
            while (d <= -LG_PI)
                d += 2 * LG_PI;
            bp[nb++] = d;
        }
    /* where the unit circle crosses the edges */
    for (int a = 0; a < 2; a++) {
        double x = xs[a];
        if (fabs(x) < 1)
            for (int sg = -1; sg <= 1; sg += 2) {
                double y = sg * sqrt(1 - x * x);
                if (y > y0 && y < y1) {
                    double d = atan2(y, x) - base;
                    while (d > LG_PI)
                        d -= 2 * LG_PI;
                    while (d <= -LG_PI)
                        d += 2 * LG_PI;
                    bp[nb++] = d;
                }
            }
        double y = ys[a];
        if (fabs(y) < 1)
            for (int sg = -1; sg <= 1; sg += 2) {
                double xx = sg * sqrt(1 - y * y);
                if (xx > x0 && xx < x1) {
                    double d = atan2(y, xx) - base;
                    while (d > LG_PI)
                        d -= 2 * LG_PI;
                    while (d <= -LG_PI)
                        d += 2 * LG_PI;
                    bp[nb++] = d;
                }
            }
    }
    if (origin_inside) {
        bp[nb++] = -LG_PI;
        bp[nb++] = LG_PI;
    }
    qsort(bp, (size_t)nb, sizeof *bp, cmpd);
    static const double gx[8] = { 0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                                  0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                                  0.9445750230732326, 0.9894009349916499 };
    static const double gw[8] = { 0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                                  0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                                  0.0622535239386479, 0.0271524594117541 };
    double sum = 0;
    for (int k = 0; k + 1 < nb; k++) {
        double a = bp[k], b = bp[k + 1];
        if (!(b > a))
            continue;
        int pieces = 8;
        double hstep = (b - a) / pieces;
        for (int p = 0; p < pieces; p++) {
            double mid = a + (p + 0.5) * hstep, half = 0.5 * hstep;
            for (int g = 0; g < 8; g++)
                for (int sg = -1; sg <= 1; sg += 2) {
                    double phi = base + mid + sg * gx[g] * half;
                    sum += gw[g] * half * ray_part(x0, x1, y0, y1, cos(phi), sin(phi));
                }
        }
    }
    return sum;
}

static void check_sum(lg_probe_layout l, uint32_t w, uint32_t h)
{
    size_t n = texel_count(l, w, h);
    float *t = malloc(n * sizeof *t);
    double t0 = now();
    int rc = lg_probe_solid_angles(l, w, h, t);
    double t1 = now();
    CHECKF(rc == 0, "%s %ux%u: lg_probe_solid_angles returned %d", layout_name(l), w, h, rc);
    double sum = 0, sumd = 0, worst = 0;
    int negative = 0;
    for (size_t k = 0; k < n; k++) {
        sum += t[k];
        if (!(t[k] >= 0))
            negative++;
    }
    /* the per-texel function in double, against the float table */
    uint32_t faces = l == LG_PROBE_CUBE ? 6 : 1;
    for (uint32_t f = 0; f < faces; f++)
        for (uint32_t j = 0; j < h; j++)
            for (uint32_t i = 0; i < w; i++) {
                double s = lg_probe_texel_solid_angle(l, w, h, f, i, j);
                sumd += s;
                float tv = t[((size_t)f * h + j) * w + i];
                /* relative, except for slivers of the angular rim far below a mean texel,
                 * where 1e-9 of a mean texel is the measure (their edge integrals cancel
                 * to ~1e-17 sr whichever way round they are summed) */
                double mean = 4 * LG_PI / (double)n;
                double e = fabs(s - tv) / fmax(s, 1e-2 * mean);
                if (s > 0 && e > worst)
                    worst = e;
            }
    double rel = fabs(sum - 4 * LG_PI) / (4 * LG_PI), reld = fabs(sumd - 4 * LG_PI) / (4 * LG_PI);
    printf("solid angles %-7s %5ux%-5u sum(float table) - 4pi: %.2e rel, sum(double) %.2e rel, "
           "table %.1f ms\n",
           layout_name(l), w, h, rel, reld, (t1 - t0) * 1e3);
    CHECKF(rel <= 1e-6, "%s %ux%u: the table sums to %.12g, 4 pi = %.12g (%.3g relative)",
           layout_name(l), w, h, sum, 4 * LG_PI, rel);
    CHECKF(reld <= 1e-9, "%s %ux%u: the texels sum to %.15g in double (%.3g relative)",
           layout_name(l), w, h, sumd, reld);
    CHECKF(negative == 0, "%s %ux%u: %d negative or NaN solid angles", layout_name(l), w, h,
           negative);
    CHECKF(worst <= 1e-7, "%s %ux%u: table vs lg_probe_texel_solid_angle %.3g relative",
           layout_name(l), w, h, worst);
    free(t);
}

static int cmd_solid_angles(void)
{
    uint32_t ll[][2] = {
        { 1, 1 }, { 2, 1 }, { 4, 2 }, { 64, 32 }, { 1000, 500 }, { 7, 3 }, { 3, 7 }
    };
    for (size_t k = 0; k < sizeof ll / sizeof ll[0]; k++)
        check_sum(LG_PROBE_LATLONG, ll[k][0], ll[k][1]);
    uint32_t cube[] = { 1, 2, 3, 64, 255 };
    for (size_t k = 0; k < sizeof cube / sizeof cube[0]; k++)
        check_sum(LG_PROBE_CUBE, cube[k], cube[k]);
    uint32_t ang[] = { 1, 2, 3, 4, 64, 513 };
    for (size_t k = 0; k < sizeof ang / sizeof ang[0]; k++)
        check_sum(LG_PROBE_ANGULAR, ang[k], ang[k]);

    /* lat-long rows: the closed form */
    CHECK(fabs(lg_probe_texel_solid_angle(LG_PROBE_LATLONG, 2, 1, 0, 1, 0) - 2 * LG_PI) < 1e-12);
    CHECK(fabs(lg_probe_texel_solid_angle(LG_PROBE_LATLONG, 1, 1, 0, 0, 0) - 4 * LG_PI) < 1e-12);
    /* a cube face is 4 pi / 6; a 1x1 angular map's texel is the sphere */
    CHECK(fabs(lg_probe_texel_solid_angle(LG_PROBE_CUBE, 1, 1, 3, 0, 0) - 4 * LG_PI / 6) < 1e-12);
    CHECK(fabs(lg_probe_texel_solid_angle(LG_PROBE_ANGULAR, 1, 1, 0, 0, 0) - 4 * LG_PI) < 1e-12);
    /* a cube 2x2 face: each texel a quarter of the face */
    CHECK(fabs(lg_probe_texel_solid_angle(LG_PROBE_CUBE, 2, 2, 0, 1, 0) - LG_PI / 6) < 1e-12);

    /* the angular map against the polar oracle, every texel of small maps (rim texels are
     * partly covered; corner texels are outside: 0) */
    uint32_t sizes[] = { 1, 2, 3, 5, 8, 33 };
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        uint32_t n = sizes[s];
        double worst = 0, worst_rim = 0;
        int zeros = 0;
        for (uint32_t j = 0; j < n; j++)
            for (uint32_t i = 0; i < n; i++) {
                double got = lg_probe_texel_solid_angle(LG_PROBE_ANGULAR, n, n, 0, i, j);
                double want = angular_oracle(n, i, j);
                double e = fabs(got - want) / fmax(want, 1e-300);
                if (want == 0) {
                    CHECKF(got == 0, "angular %u: texel (%u, %u) outside the disc has %.3g sr", n,
                           i, j, got);
                    zeros++;
                    continue;
                }
                /* rim texels: the circle passes through them */
                double x0 = 2.0 * i / n - 1, x1 = 2.0 * (i + 1) / n - 1;
                double y1 = 1 - 2.0 * j / n, y0 = 1 - 2.0 * (j + 1) / n;
                double fx = fmax(fabs(x0), fabs(x1)), fy = fmax(fabs(y0), fabs(y1));
                int rim = fx * fx + fy * fy > 1;
                if (rim && e > worst_rim)
                    worst_rim = e;
                if (!rim && e > worst)
                    worst = e;
                CHECKF(e <= (rim ? 1e-8 : 1e-12),
                       "angular %u: texel (%u, %u)%s: %.15g sr, oracle %.15g (%.3g)", n, i, j,
                       rim ? " (on the rim)" : "", got, want, e);
            }
        printf("angular %3u vs polar oracle: interior %.2e, rim %.2e relative, %d texels outside\n",
               n, worst, worst_rim, zeros);
    }
    /* symmetry of a 64 map: mirrored texels agree */
    for (uint32_t j = 0; j < 64; j += 7)
        for (uint32_t i = 0; i < 64; i += 5) {
            double a = lg_probe_texel_solid_angle(LG_PROBE_ANGULAR, 64, 64, 0, i, j);
            double b = lg_probe_texel_solid_angle(LG_PROBE_ANGULAR, 64, 64, 0, 63 - i, j);
            double c = lg_probe_texel_solid_angle(LG_PROBE_ANGULAR, 64, 64, 0, j, i);
            CHECKF(fabs(a - b) <= 1e-9 * fmax(a, 1e-30) + 1e-300 &&
                       fabs(a - c) <= 1e-9 * fmax(a, 1e-30) + 1e-300,
                   "angular 64 texel (%u, %u): %.17g, mirrored %.17g, transposed %.17g", i, j, a, b,
                   c);
        }
    /* invalid sizes */
    float dummy[6];
    CHECK(lg_probe_solid_angles(LG_PROBE_CUBE, 2, 1, dummy) == LG_ERR_INVALID);
    CHECK(lg_probe_solid_angles(LG_PROBE_LATLONG, 0, 1, dummy) == LG_ERR_INVALID);
    CHECK(lg_probe_solid_angles((lg_probe_layout)7, 1, 1, dummy) == LG_ERR_INVALID);
    CHECK(lg_probe_texel_solid_angle(LG_PROBE_LATLONG, 4, 2, 0, 4, 0) == 0);
    return check_report("probe_solid_angles");
}

/* ---- conventions ----------------------------------------------------------------------------- */

static void expect_dir(const char *what, lg_vec3 got, double x, double y, double z, double tol)
{
    CHECKF(fabs(got.x - x) <= tol && fabs(got.y - y) <= tol && fabs(got.z - z) <= tol,
           "%s: (%.9g, %.9g, %.9g), expected (%g, %g, %g)", what, got.x, got.y, got.z, x, y, z);
}

static void expect_coord(const char *what, lg_probe_coord c, uint32_t face, double u, double v,
                         double tol)
{
    CHECKF(c.face == face && fabs(c.u - u) <= tol && fabs(c.v - v) <= tol,
           "%s: face %u (%.9g, %.9g), expected face %u (%g, %g)", what, c.face, c.u, c.v, face, u,
           v);
}

static lg_probe_coord C2(uint32_t f, float u, float v)
{
    lg_probe_coord c = { f, u, v };
    return c;
}

static int cmd_conventions(void)
{
    const double t = 2e-7;
    /* lat-long: the centre looks along -Z, u = 0.75 along +X, 0.25 along -X, the top +Y,
     * the seam +Z */
    expect_dir("latlong centre", lg_probe_coord_to_dir(LG_PROBE_LATLONG, C2(0, 0.5f, 0.5f)), 0, 0,
               -1, t);
    expect_dir("latlong u=0.75", lg_probe_coord_to_dir(LG_PROBE_LATLONG, C2(0, 0.75f, 0.5f)), 1, 0,
               0, t);
    expect_dir("latlong u=0.25", lg_probe_coord_to_dir(LG_PROBE_LATLONG, C2(0, 0.25f, 0.5f)), -1, 0,
               0, t);
    expect_dir("latlong u=0 (seam)", lg_probe_coord_to_dir(LG_PROBE_LATLONG, C2(0, 0.0f, 0.5f)), 0,
               0, 1, t);
    expect_dir("latlong top", lg_probe_coord_to_dir(LG_PROBE_LATLONG, C2(0, 0.3f, 0.0f)), 0, 1, 0,
               t);
    expect_dir("latlong bottom", lg_probe_coord_to_dir(LG_PROBE_LATLONG, C2(0, 0.3f, 1.0f)), 0, -1,
               0, t);
    /* the panorama is not mirrored seen from inside: looking at -Z with +Y up, +X is to
     * the right, and u grows to the right */
    lg_probe_coord a = lg_probe_dir_to_coord(LG_PROBE_LATLONG, lg_v3(0.1f, 0, -1));
    CHECKF(a.u > 0.5f, "a direction right of -Z has u = %g <= 0.5", a.u);
    /* texel (W/2, H/2) of 64 x 32: just right of and below the centre */
    lg_vec3 d = lg_probe_texel_dir(LG_PROBE_LATLONG, 64, 32, 0, 32, 16);
    CHECKF(d.z < -0.99f && d.x > 0 && d.y < 0, "latlong texel (32, 16): (%g, %g, %g)", d.x, d.y,
           d.z);
    d = lg_probe_texel_dir(LG_PROBE_LATLONG, 64, 32, 0, 0, 0);
    CHECKF(fabs(d.y - cos(LG_PI / 64)) < 1e-6, "latlong row 0 centre: y = %.9g, cos(pi/64) = %.9g",
           d.y, cos(LG_PI / 64));
    expect_coord("latlong +X", lg_probe_dir_to_coord(LG_PROBE_LATLONG, lg_v3(1, 0, 0)), 0, 0.75,
                 0.5, t);
    expect_coord("latlong -Z", lg_probe_dir_to_coord(LG_PROBE_LATLONG, lg_v3(0, 0, -1)), 0, 0.5,
                 0.5, t);
    expect_coord("latlong +Y", lg_probe_dir_to_coord(LG_PROBE_LATLONG, lg_v3(0, 1, 0)), 0, 0.5, 0,
                 t);
    expect_coord("latlong -Y", lg_probe_dir_to_coord(LG_PROBE_LATLONG, lg_v3(0, -1, 0)), 0, 0.5, 1,
                 t);

    /* angular: centre -Z, right +X, up +Y, rim +Z; r = theta / pi */
    expect_dir("angular centre", lg_probe_coord_to_dir(LG_PROBE_ANGULAR, C2(0, 0.5f, 0.5f)), 0, 0,
               -1, t);
    expect_dir("angular r=0.5 right", lg_probe_coord_to_dir(LG_PROBE_ANGULAR, C2(0, 0.75f, 0.5f)),
               1, 0, 0, t);
    expect_dir("angular r=0.5 up", lg_probe_coord_to_dir(LG_PROBE_ANGULAR, C2(0, 0.5f, 0.25f)), 0,
               1, 0, t);
    expect_dir("angular rim", lg_probe_coord_to_dir(LG_PROBE_ANGULAR, C2(0, 1.0f, 0.5f)), 0, 0, 1,
               t);
    expect_dir("angular corner (outside)", lg_probe_coord_to_dir(LG_PROBE_ANGULAR, C2(0, 0, 0)), 0,
               0, 1, 0);
    expect_coord("angular -Z", lg_probe_dir_to_coord(LG_PROBE_ANGULAR, lg_v3(0, 0, -1)), 0, 0.5,
                 0.5, t);
    expect_coord("angular +X", lg_probe_dir_to_coord(LG_PROBE_ANGULAR, lg_v3(1, 0, 0)), 0, 0.75,
                 0.5, t);
    expect_coord("angular -Y", lg_probe_dir_to_coord(LG_PROBE_ANGULAR, lg_v3(0, -1, 0)), 0, 0.5,
                 0.75, t);
    expect_coord("angular +Z", lg_probe_dir_to_coord(LG_PROBE_ANGULAR, lg_v3(0, 0, 1)), 0, 0.5, 1.0,
                 t);
    /* 45 degrees from -Z toward +X: r = 1/4 */
    expect_coord("angular 45", lg_probe_dir_to_coord(LG_PROBE_ANGULAR, lg_v3(1, 0, -1)), 0, 0.625,
                 0.5, t);

    /* cube: GL's table */
    expect_coord("cube +X", lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(1, 0.5f, 0.25f)), 0, 0.375,
                 0.25, t);
    expect_coord("cube -X", lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(-1, 0.5f, 0.25f)), 1, 0.625,
                 0.25, t);
    expect_coord("cube +Y", lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(0.5f, 1, 0.25f)), 2, 0.75,
                 0.625, t);
    expect_coord("cube -Y", lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(0.5f, -1, 0.25f)), 3, 0.75,
                 0.375, t);
    expect_coord("cube +Z", lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(0.5f, 0.25f, 1)), 4, 0.75,
                 0.375, t);
    expect_coord("cube -Z", lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(0.5f, 0.25f, -1)), 5, 0.25,
                 0.375, t);
    static const float axes[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                      { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
    for (uint32_t f = 0; f < 6; f++) {
        expect_dir("cube face centre", lg_probe_coord_to_dir(LG_PROBE_CUBE, C2(f, 0.5f, 0.5f)),
                   axes[f][0], axes[f][1], axes[f][2], 0);
        expect_coord("cube axis",
                     lg_probe_dir_to_coord(LG_PROBE_CUBE,
                                           lg_v3(axes[f][0], axes[f][1], axes[f][2])),
                     f, 0.5, 0.5, 0);
    }
    /* ties: X before Y before Z */
    CHECK(lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(1, 1, 1)).face == 0);
    CHECK(lg_probe_dir_to_coord(LG_PROBE_CUBE, lg_v3(0, -1, 1)).face == 3);
    return check_report("probe_conventions");
}

/* ---- round trip ------------------------------------------------------------------------------ */

static void roundtrip(lg_probe_layout l, uint32_t w, uint32_t h)
{
    uint32_t faces = l == LG_PROBE_CUBE ? 6 : 1;
    int bad = 0;
    double worst = 0;
    for (uint32_t f = 0; f < faces; f++)
        for (uint32_t j = 0; j < h; j++)
            for (uint32_t i = 0; i < w; i++) {
                double cu = (i + 0.5) / w, cv = (j + 0.5) / h;
                if (l == LG_PROBE_ANGULAR) {
                    double a = 2 * cu - 1, b = 1 - 2 * cv;
                    if (a * a + b * b >= 0.999999)
                        continue; /* the centre is outside the disc (or on the rim) */
                }
                lg_vec3 d = lg_probe_texel_dir(l, w, h, f, i, j);
                lg_probe_coord c = lg_probe_dir_to_coord(l, d);
                double du = fabs(c.u - cu);
                if (l == LG_PROBE_LATLONG)
                    du = fmin(du, 1 - du);
                /* at a lat-long pole row of height 1 every u is the same point */
                if (l == LG_PROBE_LATLONG && h == 1)
                    du = 0;
                double e = fmax(du * w, fabs(c.v - cv) * h); /* in texels */
                if (e > worst)
                    worst = e;
                if (c.face != f || e > 1e-3) {
                    if (bad++ < 5)
                        CHECKF(
                            0,
                            "%s %ux%u texel (%u, %u) face %u -> (%.9g %.9g %.9g) -> face %u (%.9g, %.9g)",
                            layout_name(l), w, h, i, j, f, d.x, d.y, d.z, c.face, c.u, c.v);
                }
            }
    printf("round trip %-7s %5ux%-5u worst %.2e texel\n", layout_name(l), w, h, worst);
}

static int cmd_roundtrip(void)
{
    roundtrip(LG_PROBE_LATLONG, 1, 1);
    roundtrip(LG_PROBE_LATLONG, 2, 1);
    roundtrip(LG_PROBE_LATLONG, 64, 32);
    roundtrip(LG_PROBE_LATLONG, 2048, 1024);
    roundtrip(LG_PROBE_LATLONG, 5, 9);
    roundtrip(LG_PROBE_ANGULAR, 1, 1);
    roundtrip(LG_PROBE_ANGULAR, 3, 3);
    roundtrip(LG_PROBE_ANGULAR, 64, 64);
    roundtrip(LG_PROBE_ANGULAR, 1025, 1025);
    roundtrip(LG_PROBE_CUBE, 1, 1);
    roundtrip(LG_PROBE_CUBE, 2, 2);
    roundtrip(LG_PROBE_CUBE, 64, 64);
    roundtrip(LG_PROBE_CUBE, 512, 512);
    return check_report("probe_roundtrip");
}

/* ---- hard directions ------------------------------------------------------------------------- */

static int cmd_hard_dirs(void)
{
    const lg_probe_layout layouts[3] = { LG_PROBE_LATLONG, LG_PROBE_ANGULAR, LG_PROBE_CUBE };
    const uint32_t sizes[3][2] = { { 16, 8 }, { 17, 17 }, { 8, 8 } };
    const float dn = 1e-40f; /* a denormal */
    const lg_vec3 fallback_like[] = {
        lg_v3(0, 0, 0),        lg_v3(-0.0f, -0.0f, -0.0f), lg_v3(dn, -dn, dn),
        lg_v3(1e-31f, 0, 0),   lg_v3(NAN, 0, 0),           lg_v3(0, NAN, 1),
        lg_v3(INFINITY, 0, 0), lg_v3(1, -INFINITY, 1),     lg_v3(NAN, NAN, NAN),
    };
    const lg_vec3 hard[] = {
        lg_v3(1, 0, 0),
        lg_v3(-1, 0, 0),
        lg_v3(0, 1, 0),
        lg_v3(0, -1, 0),
        lg_v3(0, 0, 1),
        lg_v3(0, 0, -1),
        lg_v3(-0.0f, 1, -0.0f),
        lg_v3(0, -1, -0.0f),
        lg_v3(1e-7f, 0, 1),
        lg_v3(-1e-7f, 0, 1),
        lg_v3(-0.0f, 0.3f, 1),
        lg_v3(0, 0.3f, 1),
        lg_v3(1e-7f, 1e-7f, -1),
        lg_v3(1e-20f, 0, -1),
        lg_v3(1e-7f, 0, 1),
        lg_v3(1e-30f, 0, 1),
        lg_v3(1, 1, 0),
        lg_v3(1, 1, 1),
        lg_v3(-1, 1, -1),
        lg_v3(1, -1, 1),
        lg_v3(3e38f, 3e38f, 3e38f),
        lg_v3(1e-30f, 2e-30f, -2e-30f),
        lg_v3(dn, 0, 1),
    };
    for (int li = 0; li < 3; li++) {
        lg_probe_layout l = layouts[li];
        uint32_t w = sizes[li][0], h = sizes[li][1];
        float *img = rnd_image(l, w, h);
        for (int s = 0; s < 2; s++) {
            float ref[4], got[4];
            lookup(l, w, h, img, NULL, lg_v3(0, 0, -1), (lg_probe_sampling)s, ref);
            for (size_t k = 0; k < sizeof fallback_like / sizeof fallback_like[0]; k++) {
                lookup(l, w, h, img, NULL, fallback_like[k], (lg_probe_sampling)s, got);
                CHECKF(diff4(got, ref) == 0, "%s %s: (%g, %g, %g) does not read as -Z",
                       layout_name(l), s ? "bilinear" : "nearest", fallback_like[k].x,
                       fallback_like[k].y, fallback_like[k].z);
            }
            for (size_t k = 0; k < sizeof hard / sizeof hard[0]; k++) {
                lg_vec3 d = hard[k];
                lg_probe_coord c = lg_probe_dir_to_coord(l, d);
                CHECKF(isfinite(c.u) && isfinite(c.v) && c.u >= 0 && c.u <= 1 && c.v >= 0 &&
                           c.v <= 1 && c.face < 6,
                       "%s: (%g, %g, %g) -> face %u (%g, %g)", layout_name(l), d.x, d.y, d.z,
                       c.face, c.u, c.v);
                lookup(l, w, h, img, NULL, d, (lg_probe_sampling)s, got);
                CHECKF(finite4(got), "%s: (%g, %g, %g) looks up a non-finite value", layout_name(l),
                       d.x, d.y, d.z);
                /* scale invariance: non-unit directions read the same */
                const float ks[] = { 1e-20f, 1e-3f, 7.0f, 1e20f };
                for (int q = 0; q < 4; q++) {
                    lg_vec3 e = lg_v3_scale(d, ks[q]);
                    if (!isfinite(e.x) || !isfinite(e.y) || !isfinite(e.z))
                        continue;
                    float m = fmaxf(fabsf(e.x), fmaxf(fabsf(e.y), fabsf(e.z)));
                    if (!(m > 1e-30f))
                        continue;
                    /* below ~1e-19 a component's square is denormal: normalisation loses
                     * bits but stays within a few ulp */
                    float g2[4];
                    lookup(l, w, h, img, NULL, e, (lg_probe_sampling)s, g2);
                    CHECKF(diff4(g2, got) <= 1e-4, "%s %s: (%g, %g, %g) * %g reads %g, unscaled %g",
                           layout_name(l), s ? "bilinear" : "nearest", d.x, d.y, d.z, ks[q], g2[0],
                           got[0]);
                }
            }
        }
        free(img);
    }
    /* the angular centre: no division by zero, the centre texel's value exactly */
    {
        float img[9 * 4];
        for (int k = 0; k < 36; k++)
            img[k] = (float)k;
        float got[4];
        lookup(LG_PROBE_ANGULAR, 3, 3, img, NULL, lg_v3(0, 0, -5), LG_PROBE_BILINEAR, got);
        CHECKF(got[0] == 16 && got[3] == 19, "angular 3x3 centre reads %g, not texel 4", got[0]);
        lookup(LG_PROBE_ANGULAR, 3, 3, img, NULL, lg_v3(1e-20f, -1e-20f, -1), LG_PROBE_NEAREST,
               got);
        CHECKF(got[0] == 16, "angular 3x3 near the centre reads %g, not texel 4", got[0]);
        /* the rim: +Z reads the bottom middle texel (the documented point of the rim) */
        lookup(LG_PROBE_ANGULAR, 3, 3, img, NULL, lg_v3(0, 0, 1), LG_PROBE_NEAREST, got);
        CHECKF(got[0] == 28, "angular 3x3 +Z reads %g, not texel 7", got[0]);
        /* just inside the rim, along +X: the right middle texel */
        lookup(LG_PROBE_ANGULAR, 3, 3, img, NULL, lg_v3(1e-3f, 0, 1), LG_PROBE_NEAREST, got);
        CHECKF(got[0] == 20, "angular 3x3 near the rim at +X reads %g, not texel 5", got[0]);
    }
    /* a lat-long image that is not 2:1, and the seam: both sides of +Z read column 0 /
     * column W-1 in nearest mode */
    {
        float img[5 * 3 * 4];
        for (int k = 0; k < 60; k++)
            img[k] = (float)k;
        float a[4], b[4];
        lookup(LG_PROBE_LATLONG, 5, 3, img, NULL, lg_v3(1e-6f, 0, 1), LG_PROBE_NEAREST, a);
        lookup(LG_PROBE_LATLONG, 5, 3, img, NULL, lg_v3(-1e-6f, 0, 1), LG_PROBE_NEAREST, b);
        CHECKF(a[0] == 4 * 9 && b[0] == 4 * 5,
               "5x3 seam: %g and %g, expected row 1 columns 4 and 0", a[0], b[0]);
        lookup(LG_PROBE_LATLONG, 5, 3, img, NULL, lg_v3(0, 0, 1), LG_PROBE_NEAREST, a);
        lookup(LG_PROBE_LATLONG, 5, 3, img, NULL, lg_v3(-0.0f, 0, 1), LG_PROBE_NEAREST, b);
        CHECKF(a[0] == b[0], "+Z and (-0, 0, 1) read %g and %g", a[0], b[0]);
    }
    /* a 1x1 cube with six different faces: each axis reads its face exactly (bilinear
     * and nearest); a corner direction the mean of its three faces */
    {
        float img[6 * 4];
        for (int k = 0; k < 24; k++)
            img[k] = (float)(k / 4 + 1);
        static const float axes[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                          { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
        for (int f = 0; f < 6; f++)
            for (int sm = 0; sm < 2; sm++) {
                float got[4];
                lookup(LG_PROBE_CUBE, 1, 1, img, NULL, lg_v3(axes[f][0], axes[f][1], axes[f][2]),
                       (lg_probe_sampling)sm, got);
                CHECKF(got[0] == (float)(f + 1), "1x1 cube: axis of face %d reads %g", f, got[0]);
            }
        float got[4];
        lookup(LG_PROBE_CUBE, 1, 1, img, NULL, lg_v3(1, 1, 1), LG_PROBE_BILINEAR, got);
        CHECKF(fabsf(got[0] - (1 + 3 + 5) / 3.0f) < 1e-6f,
               "1x1 cube: corner (+X +Y +Z) reads %g, not 3", got[0]);
    }
    /* lg_probe_image_at: level 1 of a 2-level cube (4 then 2 texels a side) */
    {
        lg_image_desc desc;
        memset(&desc, 0, sizeof desc);
        desc.width = desc.height = 4;
        desc.flags = LG_IMAGE_CUBE;
        desc.levels = 2;
        float data[(6 * 16 + 6 * 4) * 4];
        for (int k = 0; k < (int)(sizeof data / sizeof data[0]); k++)
            data[k] = (float)(k / 4);
        lg_probe_image im = lg_probe_image_at(LG_PROBE_CUBE, &desc, data, 1, NULL);
        CHECK(im.width == 2 && im.height == 2 && im.rgba == data + 4 * 96);
        float got[4];
        lg_probe_lookup(&im, lg_v3(0, 0, -1), LG_PROBE_NEAREST, got); /* face 5, (1, 1) */
        CHECKF(got[0] == 96 + 5 * 4 + 3, "level 1, -Z: texel %g", got[0]);
        im = lg_probe_image_at(LG_PROBE_CUBE, &desc, data, 2, NULL);
        CHECK(im.width == 0 && im.rgba == NULL);
    }
    /* empty images */
    {
        float got[4] = { 1, 1, 1, 1 };
        lg_probe_image img = { LG_PROBE_LATLONG, 0, 0, NULL, NULL, { 0 } };
        lg_probe_lookup(&img, lg_v3(0, 1, 0), LG_PROBE_BILINEAR, got);
        CHECK(got[0] == 0 && got[3] == 0);
    }
    return check_report("probe_hard_dirs");
}

/* ---- continuity ------------------------------------------------------------------------------ */

static lg_vec3 nrm(double x, double y, double z)
{
    double l = sqrt(x * x + y * y + z * z);
    return lg_v3((float)(x / l), (float)(y / l), (float)(z / l));
}

static int cmd_continuity(void)
{
    /* cube: approach each of the 12 edges and 8 corners from every adjacent face; the
     * values converge to one value */
    for (uint32_t n = 1; n <= 8; n *= 2) {
        float *img = rnd_image(LG_PROBE_CUBE, n, n);
        double worst = 0;
        for (int a = 0; a < 3; a++)
            for (int sa = -1; sa <= 1; sa += 2)
                for (int b = a + 1; b < 3; b++)
                    for (int sb = -1; sb <= 1; sb += 2)
                        for (int k = 0; k < 5; k++) {
                            /* a point on the edge (axes a and b at +-1, the third free) */
                            double p[3], q[3];
                            int c = 3 - a - b;
                            p[a] = sa;
                            p[b] = sb;
                            p[c] = -0.9 + 0.45 * k;
                            float v[2][4];
                            const double eps = 1e-6;
                            for (int side = 0; side < 2; side++) {
                                memcpy(q, p, sizeof q);
                                /* into the face of axis a (shrink b) or of axis b */
                                if (side == 0)
                                    q[b] *= 1 - eps;
                                else
                                    q[a] *= 1 - eps;
                                lookup(LG_PROBE_CUBE, n, n, img, NULL, nrm(q[0], q[1], q[2]),
                                       LG_PROBE_BILINEAR, v[side]);
                            }
                            double e = diff4(v[0], v[1]);
                            worst = fmax(worst, e);
                            CHECKF(e<1e-4, "cube %u: edge %c%c %c%c at %g: %g vs %g", n, sa> 0
                                       ? '+'
                                       : '-',
                                   "xyz"[a], sb > 0 ? '+' : '-', "xyz"[b], p[c], v[0][0], v[1][0]);
                        }
        /* corners: from each of the three faces */
        for (int corner = 0; corner < 8; corner++) {
            double s[3] = { corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1 };
            float v[3][4];
            for (int f = 0; f < 3; f++) {
                double q[3] = { s[0] * (1 - 1e-6), s[1] * (1 - 1e-6), s[2] * (1 - 1e-6) };
                q[f] = s[f];
                lookup(LG_PROBE_CUBE, n, n, img, NULL, nrm(q[0], q[1], q[2]), LG_PROBE_BILINEAR,
                       v[f]);
            }
            double e = fmax(diff4(v[0], v[1]), diff4(v[0], v[2]));
            worst = fmax(worst, e);
            CHECKF(e < 1e-4, "cube %u: corner %d from three faces: %g %g %g", n, corner, v[0][0],
                   v[1][0], v[2][0]);
        }
        printf("cube %u: edges and corners, worst jump %.2e (directions 1e-6 apart)\n", n, worst);
        free(img);
    }
    /* every layout: random pairs of directions 1e-5 rad apart differ by at most the
     * image's gradient times the step (values in [0, 1], a gradient of ~texels per radian),
     * seams, poles and edges included */
    const lg_probe_layout layouts[3] = { LG_PROBE_LATLONG, LG_PROBE_ANGULAR, LG_PROBE_CUBE };
    const uint32_t sizes[3][2] = { { 32, 16 }, { 33, 33 }, { 12, 12 } };
    for (int li = 0; li < 3; li++) {
        lg_probe_layout l = layouts[li];
        uint32_t w = sizes[li][0], h = sizes[li][1];
        float *img = rnd_image(l, w, h);
        double worst = 0;
        int jumps = 0;
        for (int k = 0; k < 20000; k++) {
            lg_vec3 d = rnd_dir();
            /* every fourth direction: near a seam, pole or edge */
            if (k % 4 == 1)
                d = nrm(d.x * 1e-3, d.y, fabs(d.z) + 0.1); /* lat-long seam, cube edges near +Z */
            else if (k % 4 == 2)
                d = nrm(d.x * 1e-3, 1, d.z * 1e-3); /* the +Y pole */
            else if (k % 4 == 3)
                d = nrm(d.x, d.y, d.x >= 0 ? fabs(d.x) : -fabs(d.x)); /* cube edges x = +-z */
            lg_vec3 e = rnd_dir();
            lg_vec3 dd = nrm(d.x + 1e-5 * e.x, d.y + 1e-5 * e.y, d.z + 1e-5 * e.z);
            float a[4], b[4];
            lookup(l, w, h, img, NULL, d, LG_PROBE_BILINEAR, a);
            lookup(l, w, h, img, NULL, dd, LG_PROBE_BILINEAR, b);
            /* the angular map is discontinuous only at its rim (+Z, one point) */
            if (l == LG_PROBE_ANGULAR && d.z > 0.999f)
                continue;
            double jump = diff4(a, b);
            /* bilinear filtering of values in [0, 1) is Lipschitz with constant 1 per texel
             * along each axis: within a face, the jump is bounded by the distance of the
             * two coordinates in texels (lat-long: across the seam the short way; near a
             * pole the coordinates move fast, the values no faster than they do) */
            double allowed = 2e-3;
            lg_probe_coord ca = lg_probe_dir_to_coord(l, d), cb = lg_probe_dir_to_coord(l, dd);
            if (l != LG_PROBE_CUBE && ca.face == cb.face) {
                double du = fabs(ca.u - cb.u);
                if (l == LG_PROBE_LATLONG)
                    du = fmin(du, 1 - du);
                allowed = fmax(allowed, 1.01 * (du * w + fabs(ca.v - cb.v) * h) + 1e-5);
            }
            worst = fmax(worst, jump / allowed);
            if (jump > allowed && jumps++ < 5)
                CHECKF(0, "%s: a jump of %g (allowed %g) between (%g %g %g) and (%g %g %g)",
                       layout_name(l), jump, allowed, d.x, d.y, d.z, dd.x, dd.y, dd.z);
        }
        printf("%s %ux%u: worst change over 1e-5 rad: %.2f of its bound (20000 pairs)\n",
               layout_name(l), w, h, worst);
        free(img);
    }
    /* the lat-long seam and the poles, explicitly */
    {
        float *img = rnd_image(LG_PROBE_LATLONG, 7, 4);
        float a[4], b[4];
        for (int k = -3; k <= 3; k++) {
            double y = 0.3 * k;
            lookup(LG_PROBE_LATLONG, 7, 4, img, NULL, nrm(1e-7, y, 1), LG_PROBE_BILINEAR, a);
            lookup(LG_PROBE_LATLONG, 7, 4, img, NULL, nrm(-1e-7, y, 1), LG_PROBE_BILINEAR, b);
            CHECKF(diff4(a, b) < 1e-5, "seam at y %g: %g vs %g", y, a[0], b[0]);
        }
        /* along each meridian through a pole: both sides converge */
        for (int k = 0; k < 16; k++) {
            double phi = 2 * LG_PI * k / 16 + 0.1, t = 1e-6;
            for (int pole = -1; pole <= 1; pole += 2) {
                lookup(LG_PROBE_LATLONG, 7, 4, img, NULL,
                       nrm(sin(t) * sin(phi), pole * cos(t), -sin(t) * cos(phi)), LG_PROBE_BILINEAR,
                       a);
                lookup(LG_PROBE_LATLONG, 7, 4, img, NULL,
                       nrm(-sin(t) * sin(phi), pole * cos(t), sin(t) * cos(phi)), LG_PROBE_BILINEAR,
                       b);
                CHECKF(diff4(a, b) < 1e-4, "pole %+d meridian %g: %g vs %g", pole, phi, a[0], b[0]);
            }
        }
        free(img);
    }
    /* 1x1 images of every layout: the value everywhere; constant images: exactly the
     * constant (interpolation as a + (b - a) f), for a few awkward constants */
    for (int li = 0; li < 3; li++) {
        lg_probe_layout l = layouts[li];
        float one[6 * 4];
        for (int k = 0; k < 24; k++)
            one[k] = 0.25f + (k % 4) * 0.5f;
        const float cs[] = { 0.1f, 3.5f, 12345.678f, 1e-30f, 65504.0f * 4 };
        size_t nt = texel_count(l, 9, 9) * 4;
        float *cst = malloc(nt * sizeof(float));
        double worst = 0;
        int inexact = 0;
        for (size_t q = 0; q < sizeof cs / sizeof cs[0]; q++) {
            for (size_t k = 0; k < nt; k++)
                cst[k] = cs[q];
            for (int k = 0; k < 4000; k++) {
                lg_vec3 d = rnd_dir();
                if (k & 1)
                    d = nrm(d.x > 0 ? 1 : -1, d.y > 0 ? 1 : -1, d.z * 1e-3 + (d.z > 0 ? 1 : -1));
                for (int s2 = 0; s2 < 2; s2++) {
                    float got[4];
                    if (q == 0) {
                        lookup(l, 1, 1, one, NULL, d, (lg_probe_sampling)s2, got);
                        worst = fmax(worst, diff4(got, one));
                    }
                    lookup(l, 9, 9, cst, NULL, d, (lg_probe_sampling)s2, got);
                    for (int c = 0; c < 4; c++)
                        if (got[c] != cs[q] && inexact++ < 5)
                            CHECKF(0, "%s: constant %.9g reads %.9g along (%g %g %g)",
                                   layout_name(l), cs[q], got[c], d.x, d.y, d.z);
                }
            }
        }
        CHECKF(worst == 0, "%s: 1x1 image reads %g off", layout_name(l), worst);
        printf("%s: 1x1 images read their texel, constant images exactly their constant\n",
               layout_name(l));
        free(cst);
    }
    return check_report("probe_continuity");
}

/* ---- rotation -------------------------------------------------------------------------------- */

static int cmd_rotation(void)
{
    float r[9], id[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    lg_probe_rotation_from_euler(360, -360, 720, r);
    CHECKF(memcmp(r, id, sizeof r) == 0, "360 degrees is not the identity bit for bit");
    lg_probe_rotation_from_euler(0, 0, 0, r);
    CHECK(memcmp(r, id, sizeof r) == 0);
    lg_probe_rotation_from_euler(NAN, INFINITY, 0, r);
    CHECK(memcmp(r, id, sizeof r) == 0);
    /* yaw 90: the probe's centre (-Z) turns to -X; pitch 90: to +Y; roll 90: +Y to -X */
    lg_probe_rotation_from_euler(90, 0, 0, r);
    expect_dir("yaw 90 of -Z", lg_probe_to_world(r, lg_v3(0, 0, -1)), -1, 0, 0, 0);
    lg_probe_rotation_from_euler(0, 90, 0, r);
    expect_dir("pitch 90 of -Z", lg_probe_to_world(r, lg_v3(0, 0, -1)), 0, 1, 0, 0);
    lg_probe_rotation_from_euler(0, 0, 90, r);
    expect_dir("roll 90 of +Y", lg_probe_to_world(r, lg_v3(0, 1, 0)), -1, 0, 0, 0);
    /* the order: roll, then pitch, then yaw */
    lg_probe_rotation_from_euler(90, 90, 0, r);
    expect_dir("pitch 90 then yaw 90 of -Z", lg_probe_to_world(r, lg_v3(0, 0, -1)), 0, 1, 0, 1e-7);
    expect_dir("pitch 90 then yaw 90 of +Y", lg_probe_to_world(r, lg_v3(0, 1, 0)), 1, 0, 0, 1e-7);
    lg_probe_rotation_from_euler(30, 0, 0, r);
    float r2[9];
    lg_probe_rotation_from_euler(390, 0, 0, r2);
    CHECK(memcmp(r, r2, sizeof r) == 0);
    /* random angles: orthonormal; from_world inverts to_world; lookups in the world */
    float *img = rnd_image(LG_PROBE_LATLONG, 32, 16);
    double worst = 0;
    for (int k = 0; k < 1000; k++) {
        lg_probe_rotation_from_euler((float)(720 * rnd() - 360), (float)(180 * rnd() - 90),
                                     (float)(360 * rnd() - 180), r);
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                double dot = r[a * 3] * r[b * 3] + r[a * 3 + 1] * r[b * 3 + 1] +
                             r[a * 3 + 2] * r[b * 3 + 2];
                worst = fmax(worst, fabs(dot - (a == b)));
            }
        lg_vec3 d = rnd_dir(), w = lg_probe_to_world(r, d), back = lg_probe_from_world(r, w);
        worst = fmax(worst, fabs(back.x - d.x) + fabs(back.y - d.y) + fabs(back.z - d.z));
        float a4[4], b4[4];
        lookup(LG_PROBE_LATLONG, 32, 16, img, r, w, LG_PROBE_BILINEAR, a4);
        lookup(LG_PROBE_LATLONG, 32, 16, img, NULL, d, LG_PROBE_BILINEAR, b4);
        CHECKF(diff4(a4, b4) < 1e-3, "rotated lookup %g vs %g", a4[0], b4[0]);
    }
    CHECKF(worst < 1e-6, "rotations: orthonormality / inverse off by %g", worst);
    free(img);
    return check_report("probe_rotation");
}

/* ---- cost ------------------------------------------------------------------------------------ */

static volatile float sink;

/* CPU time of this thread: the machine may be shared, and wall time would count the
 * time other processes hold the core. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static int cmd_cost(void)
{
    enum { N = 1 << 20 };
    lg_vec3 *dirs = malloc(N * sizeof *dirs);
    for (int k = 0; k < N; k++)
        dirs[k] = rnd_dir();
    const lg_probe_layout layouts[3] = { LG_PROBE_LATLONG, LG_PROBE_ANGULAR, LG_PROBE_CUBE };
    const uint32_t sizes[3][2] = { { 1024, 512 }, { 1024, 1024 }, { 256, 256 } };
    for (int li = 0; li < 3; li++) {
        lg_probe_layout l = layouts[li];
        uint32_t w = sizes[li][0], h = sizes[li][1];
        float *img = rnd_image(l, w, h);
        float acc = 0;
        double t0 = cpu_now();
        for (int k = 0; k < N; k++) {
            lg_vec3 d = lg_probe_texel_dir(l, w, h, (uint32_t)k % (l == LG_PROBE_CUBE ? 6u : 1u),
                                           (uint32_t)k % w, ((uint32_t)k / w) % h);
            acc += d.x;
        }
        double t1 = cpu_now();
        for (int k = 0; k < N; k++) {
            lg_probe_coord c = lg_probe_dir_to_coord(l, dirs[k]);
            acc += c.u;
        }
        double t2 = cpu_now();
        float o[4];
        for (int k = 0; k < N; k++) {
            lookup(l, w, h, img, NULL, dirs[k], LG_PROBE_NEAREST, o);
            acc += o[0];
        }
        double t3 = cpu_now();
        for (int k = 0; k < N; k++) {
            lookup(l, w, h, img, NULL, dirs[k], LG_PROBE_BILINEAR, o);
            acc += o[0];
        }
        double t4 = cpu_now();
        size_t n = texel_count(l, w, h);
        float *sa = malloc(n * sizeof *sa);
        double t5 = cpu_now();
        lg_probe_solid_angles(l, w, h, sa);
        double t6 = cpu_now();
        /* what an SH projection does per texel: its direction, its radiance times its
         * solid angle (here the first moment, sum L(w) w dw) */
        double m[3] = { 0, 0, 0 };
        uint32_t faces = l == LG_PROBE_CUBE ? 6 : 1;
        for (uint32_t f = 0; f < faces; f++)
            for (uint32_t j = 0; j < h; j++)
                for (uint32_t i = 0; i < w; i++) {
                    size_t k = ((size_t)f * h + j) * w + i;
                    lg_vec3 d = lg_probe_texel_dir(l, w, h, f, i, j);
                    float wgt = img[4 * k] * sa[k];
                    m[0] += wgt * d.x;
                    m[1] += wgt * d.y;
                    m[2] += wgt * d.z;
                }
        double t7 = cpu_now();
        sink = acc + (float)(m[0] + m[1] + m[2]);
        printf("cost %-7s %4ux%-4u: texel->dir %.1f ns, dir->coord %.1f ns, nearest %.1f ns, "
               "bilinear %.1f ns (random directions), solid-angle table %.1f ms (%.1f ns/texel), "
               "projection loop %.1f ns/texel (CPU time of one thread)\n",
               layout_name(l), w, h, (t1 - t0) * 1e9 / N, (t2 - t1) * 1e9 / N, (t3 - t2) * 1e9 / N,
               (t4 - t3) * 1e9 / N, (t6 - t5) * 1e3, (t6 - t5) * 1e9 / (double)n,
               (t7 - t6) * 1e9 / (double)n);
        free(sa);
        free(img);
    }
    free(dirs);
    return check_report("probe_cost");
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        int (*fn)(void);
    } cmds[] = {
        { "solid_angles", cmd_solid_angles },
        { "conventions", cmd_conventions },
        { "roundtrip", cmd_roundtrip },
        { "hard_dirs", cmd_hard_dirs },
        { "continuity", cmd_continuity },
        { "rotation", cmd_rotation },
        { "cost", cmd_cost },
    };
    if (argc == 2)
        for (size_t k = 0; k < sizeof cmds / sizeof cmds[0]; k++)
            if (strcmp(argv[1], cmds[k].name) == 0)
                return cmds[k].fn();
    fprintf(stderr, "usage: test_probe_math solid_angles|conventions|roundtrip|hard_dirs|"
                    "continuity|rotation|cost\n");
    return 2;
}
