/*
 * tests/unit/medium: the density fields of lightgraph/medium.h and lightgraph/scene.h (ABI
 * 3.2) and vol_common's optical-depth volumes. One command per meson test:
 *
 *   noise      lg_noise3 stays in [-1, 1] over 2e5 random points (and reaches past 0.5),
 *              is 0 at every lattice point (negative ones too), continuous (a step of
 *              1e-7 changes it by less than 1e-6, across cell faces too), the same for the
 *              same seed, different for another (mean |difference| > 0.1), 0 for a point
 *              that is not finite
 *   fbm        lg_fbm3 is the sum of its octaves, gain^o lg_noise3(frequency lacunarity^o
 *              p, seed + o), summed here independently
 *   field      lg_medium_field_at for each kind: no field = 1; uniform = 1 inside its
 *              closed box and 0 outside; height fog e^(-k (y - base)); fBm = scale max(0,
 *              sum - offset) h; a one-voxel grid's trilinear tent (2 at the centre, 1 half a
 *              voxel away, 0.25 at (0.75, 0.5, 0) voxels, 0 a voxel away); a 2x1x1 grid
 *              rotated and scaled read through world_to_index (1, 2, 3 at index 0, 0.5, 1);
 *              0 for points that are not finite
 *   field_max  lg_medium_field_max is a true bound: 4e4 random points of random sub-boxes
 *              never exceed it, for fBm with and without height fog and offset, a grid and a
 *              uniform box; 0 for a box that misses the field's bounds, 1 without a field
 *   tau        vol_tau_build against closed forms on a 2 x 2 x 2 box of fog: a directional
 *              light straight down gives the chord to the top face (1 - y); a point light
 *              inside gives the distance to it, one outside above the box the chord to the
 *              top face along the way to it; height fog e^(-k y) under a light straight down
 *              gives (e^(-k y) - e^(-k)) / k within 1e-3 relative; vol_tau_sample reads the
 *              cells back and clamps outside the box; the memory is counted and released
 */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "lightgraph/medium.h"
#include "lightgraph/vecmath.h"
#include "vol_common.h"

/* xorshift64*: reproducible random numbers in [0, 1) */
static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (double)((rng_state * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

static double rnd_in(double a, double b)
{
    return a + (b - a) * rnd();
}

/* ---- noise ----------------------------------------------------------------------------------- */

static int cmd_noise(void)
{
    const uint32_t seeds[] = { 0, 1, 12345, 0xffffffffu };
    double amax = 0.0;
    for (size_t s = 0; s < sizeof seeds / sizeof seeds[0]; s++)
        for (int i = 0; i < 50000; i++) {
            double x = rnd_in(-50, 50), y = rnd_in(-50, 50), z = rnd_in(-50, 50);
            double v = lg_noise3(x, y, z, seeds[s]);
            CHECKF(v >= -1.0 && v <= 1.0, "noise(%g, %g, %g, %u) = %g", x, y, z, seeds[s], v);
            amax = fmax(amax, fabs(v));
        }
    CHECKF(amax > 0.5, "the largest |noise| over 2e5 points is %g: a flat field", amax);
    for (int i = -3; i <= 3; i++)
        for (int j = -3; j <= 3; j++)
            for (int k = -3; k <= 3; k++)
                for (uint32_t s = 0; s < 3; s++) {
                    double v = lg_noise3(i * 7.0, j * 5.0 - 1.0, k * 3.0 + 100.0, s);
                    CHECKF(v == 0.0, "noise at lattice point (%d, %d, %d) seed %u = %g", i * 7,
                           j * 5 - 1, k * 3 + 100, s, v);
                }
    /* continuity: a Lipschitz bound (the gradient of this noise is a few units at most) */
    for (int i = 0; i < 20000; i++) {
        double p[3] = { rnd_in(-10, 10), rnd_in(-10, 10), rnd_in(-10, 10) };
        int axis = i % 3;
        if (i % 2)
            p[axis] = round(p[axis]) - 5e-8; /* straddle a cell face */
        double q[3] = { p[0], p[1], p[2] };
        q[axis] += 1e-7;
        double a = lg_noise3(p[0], p[1], p[2], 7), b = lg_noise3(q[0], q[1], q[2], 7);
        CHECKF(fabs(a - b) < 1e-6, "noise jumps by %g over 1e-7 at (%.9g, %.9g, %.9g) axis %d",
               fabs(a - b), p[0], p[1], p[2], axis);
    }
    double diff = 0.0, same = 0.0;
    for (int i = 0; i < 10000; i++) {
        double x = rnd_in(-20, 20), y = rnd_in(-20, 20), z = rnd_in(-20, 20);
        diff += fabs(lg_noise3(x, y, z, 3) - lg_noise3(x, y, z, 4));
        same += fabs(lg_noise3(x, y, z, 3) - lg_noise3(x, y, z, 3));
    }
    CHECKF(diff / 10000 > 0.1, "seeds 3 and 4 differ by %g on average: the seed changes nothing",
           diff / 10000);
    CHECKF(same == 0.0, "the same seed gives different values (%g)", same);
    CHECK(lg_noise3(NAN, 0, 0, 0) == 0.0);
    CHECK(lg_noise3(0.5, INFINITY, 0, 0) == 0.0);
    CHECK(lg_noise3(0.5, 0.5, -INFINITY, 0) == 0.0);
    return check_report("field noise");
}

/* ---- fbm ------------------------------------------------------------------------------------- */

static int cmd_fbm(void)
{
    const lg_density_fbm cases[] = {
        { .octaves = 1, .seed = 0, .frequency = 1, .lacunarity = 2, .gain = 0.5f },
        { .octaves = 5, .seed = 9, .frequency = 0.7f, .lacunarity = 2, .gain = 0.5f },
        { .octaves = 8, .seed = 123, .frequency = 3, .lacunarity = 1.9f, .gain = 0.65f },
        { .octaves = 16, .seed = 1, .frequency = 0.1f, .lacunarity = 1, .gain = 0.9f },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        const lg_density_fbm *f = &cases[c];
        for (int i = 0; i < 2000; i++) {
            double p[3] = { rnd_in(-30, 30), rnd_in(-30, 30), rnd_in(-30, 30) };
            double want = 0.0;
            for (uint32_t o = 0; o < f->octaves; o++) {
                double fr = (double)f->frequency * pow((double)f->lacunarity, (double)o);
                want += pow((double)f->gain, (double)o) *
                        lg_noise3(fr * p[0], fr * p[1], fr * p[2], f->seed + o);
            }
            double got = lg_fbm3(f, p);
            CHECKF(fabs(got - want) < 1e-9, "case %zu at (%g, %g, %g): fbm %.12g, sum %.12g", c,
                   p[0], p[1], p[2], got, want);
        }
    }
    return check_report("field fbm");
}

/* ---- field ----------------------------------------------------------------------------------- */

static lg_density_field everywhere(lg_field_kind kind)
{
    lg_density_field f;
    memset(&f, 0, sizeof f);
    f.kind = kind;
    for (int c = 0; c < 3; c++) {
        f.bounds_min[c] = -FLT_MAX;
        f.bounds_max[c] = FLT_MAX;
    }
    return f;
}

static double at(const lg_medium *m, double x, double y, double z)
{
    double p[3] = { x, y, z };
    return lg_medium_field_at(m, p);
}

static bool near(double a, double b, double tol)
{
    return fabs(a - b) <= tol;
}

/* grid->index_to_world = translate(t) rotate_y(angle) scale(s); world_to_index its inverse,
 * written out (the inverse of each factor in reverse order). */
static void grid_xform(lg_density_grid *g, const double s[3], double angle, const double t[3])
{
    double c = cos(angle), sn = sin(angle);
    /* R = rotation about +Y: x' = c x + sn z, z' = -sn x + c z */
    double R[9] = { c, 0, sn, 0, 1, 0, -sn, 0, c }; /* row-major */
    memset(g->index_to_world, 0, sizeof g->index_to_world);
    memset(g->world_to_index, 0, sizeof g->world_to_index);
    for (int row = 0; row < 3; row++) {
        for (int col = 0; col < 3; col++) {
            g->index_to_world[col * 4 + row] = R[row * 3 + col] * s[col];
            g->world_to_index[col * 4 + row] = R[col * 3 + row] / s[row]; /* S^-1 R^T */
        }
        g->index_to_world[12 + row] = t[row];
    }
    for (int row = 0; row < 3; row++) {
        double v = 0.0;
        for (int col = 0; col < 3; col++)
            v += g->world_to_index[col * 4 + row] * t[col];
        g->world_to_index[12 + row] = -v;
    }
    g->index_to_world[15] = g->world_to_index[15] = 1.0;
}

static void to_world(const lg_density_grid *g, const double q[3], double w[3])
{
    const double *m = g->index_to_world;
    for (int r = 0; r < 3; r++)
        w[r] = m[r] * q[0] + m[4 + r] * q[1] + m[8 + r] * q[2] + m[12 + r];
}

static int cmd_field(void)
{
    lg_medium m;
    memset(&m, 0, sizeof m);
    m.present = true;
    m.density = 1;
    CHECK(at(&m, 1, 2, 3) == 1.0 && !lg_medium_is_heterogeneous(&m));

    /* uniform in a closed box */
    lg_density_field f = everywhere(LG_FIELD_UNIFORM);
    float lo[3] = { -1, 0, 2 }, hi[3] = { 1, 3, 4 };
    memcpy(f.bounds_min, lo, sizeof lo);
    memcpy(f.bounds_max, hi, sizeof hi);
    m.field = &f;
    CHECK(lg_medium_is_heterogeneous(&m));
    CHECK(at(&m, 0, 1, 3) == 1.0);
    CHECK(at(&m, -1, 0, 2) == 1.0 && at(&m, 1, 3, 4) == 1.0); /* closed */
    CHECK(at(&m, -1.0001, 1, 3) == 0.0 && at(&m, 0, 3.0001, 3) == 0.0 && at(&m, 0, 1, 1.99) == 0.0);
    CHECK(at(&m, NAN, 1, 3) == 0.0 && at(&m, 0, INFINITY, 3) == 0.0);

    /* height fog */
    f = everywhere(LG_FIELD_UNIFORM);
    f.height_falloff = 0.5f;
    f.height_base = 2.0f;
    for (double y = -3; y <= 6; y += 0.75)
        CHECKF(near(at(&m, 0.3, y, -7), exp(-0.5 * (y - 2.0)), 1e-12 * exp(-0.5 * (y - 2.0))),
               "height fog at y %g: %g, want %g", y, at(&m, 0.3, y, -7), exp(-0.5 * (y - 2.0)));

    /* fBm with offset, scale and height fog */
    f = everywhere(LG_FIELD_FBM);
    f.fbm = (lg_density_fbm){ .octaves = 4,
                              .seed = 5,
                              .frequency = 1.3f,
                              .lacunarity = 2,
                              .gain = 0.5f,
                              .offset = 0.1f,
                              .scale = 3 };
    f.height_falloff = 0.2f;
    int zeros = 0;
    for (int i = 0; i < 2000; i++) {
        double p[3] = { rnd_in(-5, 5), rnd_in(-5, 5), rnd_in(-5, 5) };
        double want = 3.0 * fmax(0.0, lg_fbm3(&f.fbm, p) - (double)0.1f) *
                      exp(-(double)0.2f * p[1]);
        double got = lg_medium_field_at(&m, p);
        CHECKF(near(got, want, 1e-9), "fbm field at (%g, %g, %g): %g, want %g", p[0], p[1], p[2],
               got, want);
        zeros += got == 0.0;
    }
    CHECKF(zeros > 100 && zeros < 1900, "the offset left %d of 2000 points at 0", zeros);

    /* a one-voxel grid: value 2 centred at world (2.5, 1, 5.5), voxel 0.5 (OpenVDB's
     * convention: the centre at the index point; make_vdb_cloud's one_voxel.vdb) */
    float one = 2.0f;
    lg_density_grid g = { .nx = 1, .ny = 1, .nz = 1, .values = &one, .max_value = 2 };
    grid_xform(&g, (const double[3]){ 0.5, 0.5, 0.5 }, 0.0, (const double[3]){ 2.5, 1, 5.5 });
    f = everywhere(LG_FIELD_GRID);
    f.grid = &g;
    CHECK(near(at(&m, 2.5, 1, 5.5), 2.0, 1e-12));
    CHECK(near(at(&m, 2.75, 1, 5.5), 1.0, 1e-12));   /* half a voxel along x */
    CHECK(near(at(&m, 2.5, 0.75, 5.5), 1.0, 1e-12)); /* along -y */
    CHECKF(near(at(&m, 2.5 - 0.375, 1.25, 5.5), 0.25, 1e-12), "(0.75, 0.5, 0) voxels: %g",
           at(&m, 2.5 - 0.375, 1.25, 5.5));
    CHECK(at(&m, 3.0, 1, 5.5) == 0.0 && at(&m, 2.5, 1, 6.0) == 0.0 &&
          at(&m, 2.5, 0.49, 5.5) == 0.0);

    /* a 2 x 1 x 1 grid (1, 3), scaled (0.5, 1, 2), rotated 60 degrees about +Y, moved */
    float two[2] = { 1.0f, 3.0f };
    lg_density_grid g2 = { .nx = 2, .ny = 1, .nz = 1, .values = two, .max_value = 3 };
    grid_xform(&g2, (const double[3]){ 0.5, 1, 2 }, LG_PI / 3, (const double[3]){ 10, -1, 4 });
    f.grid = &g2;
    const double qs[3][4] = { { 0, 0, 0, 1 }, { 0.5, 0, 0, 2 }, { 1, 0, 0, 3 } };
    for (int i = 0; i < 3; i++) {
        double w[3];
        to_world(&g2, qs[i], w);
        CHECKF(near(lg_medium_field_at(&m, w), qs[i][3], 1e-9),
               "rotated grid at index (%g, 0, 0) = world (%g, %g, %g): %g, want %g", qs[i][0], w[0],
               w[1], w[2], lg_medium_field_at(&m, w), qs[i][3]);
    }
    double w[3];
    to_world(&g2, (const double[3]){ 0.5, 0.5, 0.25 }, w); /* (2 (1 - 0.5) (1 - 0.25)) */
    CHECKF(near(lg_medium_field_at(&m, w), 2.0 * 0.5 * 0.75, 1e-9), "off-axis: %g",
           lg_medium_field_at(&m, w));
    to_world(&g2, (const double[3]){ 2.0, 0, 0 }, w); /* a voxel beyond the last centre */
    CHECKF(lg_medium_field_at(&m, w) < 1e-9, "index (2, 0, 0): %g", lg_medium_field_at(&m, w));
    to_world(&g2, (const double[3]){ 1.5, 0, 0 }, w);
    CHECKF(near(lg_medium_field_at(&m, w), 1.5, 1e-9), "index (1.5, 0, 0): %g",
           lg_medium_field_at(&m, w));
    to_world(&g2, (const double[3]){ 0.5, 0, -1.25 }, w);
    CHECK(lg_medium_field_at(&m, w) == 0.0);
    return check_report("field field");
}

/* ---- field_max ------------------------------------------------------------------------------- */

static void check_bound(const lg_medium *m, const char *what, double span)
{
    for (int b = 0; b < 20; b++) {
        double lo[3], hi[3];
        for (int c = 0; c < 3; c++) {
            double a = rnd_in(-span, span), d = rnd_in(-span, span);
            lo[c] = fmin(a, d);
            hi[c] = fmax(a, d);
        }
        double mx = lg_medium_field_max(m, lo, hi), seen = 0.0;
        for (int i = 0; i < 2000; i++) {
            double p[3] = { rnd_in(lo[0], hi[0]), rnd_in(lo[1], hi[1]), rnd_in(lo[2], hi[2]) };
            double v = lg_medium_field_at(m, p);
            seen = fmax(seen, v);
            CHECKF(v <= mx, "%s: m(%g, %g, %g) = %.9g over the box's bound %.9g", what, p[0], p[1],
                   p[2], v, mx);
        }
        CHECKF(seen <= mx, "%s: %g > %g", what, seen, mx);
    }
}

static int cmd_field_max(void)
{
    lg_medium m;
    memset(&m, 0, sizeof m);
    double lo[3] = { -1, -1, -1 }, hi[3] = { 1, 1, 1 };
    CHECK(lg_medium_field_max(&m, lo, hi) == 1.0);
    lg_density_field f = everywhere(LG_FIELD_FBM);
    m.field = &f;
    f.fbm = (lg_density_fbm){ .octaves = 6,
                              .seed = 2,
                              .frequency = 2,
                              .lacunarity = 2,
                              .gain = 0.5f,
                              .offset = 0,
                              .scale = 1 };
    check_bound(&m, "fbm", 10);
    f.fbm.offset = 0.4f;
    f.fbm.scale = 5;
    check_bound(&m, "fbm offset", 10);
    f.height_falloff = 0.3f;
    f.height_base = 1;
    check_bound(&m, "fbm height", 10);
    f = everywhere(LG_FIELD_UNIFORM);
    f.height_falloff = 2;
    for (int c = 0; c < 3; c++) {
        f.bounds_min[c] = -2;
        f.bounds_max[c] = 3;
    }
    check_bound(&m, "uniform box height", 5);
    double far_lo[3] = { 4, 4, 4 }, far_hi[3] = { 5, 5, 5 };
    CHECK(lg_medium_field_max(&m, far_lo, far_hi) == 0.0);
    float vals[27];
    for (int i = 0; i < 27; i++)
        vals[i] = (float)(i % 7);
    lg_density_grid g = { .nx = 3, .ny = 3, .nz = 3, .values = vals, .max_value = 6 };
    grid_xform(&g, (const double[3]){ 0.4, 0.4, 0.4 }, 0.3, (const double[3]){ 0, 0, 0 });
    f = everywhere(LG_FIELD_GRID);
    f.grid = &g;
    check_bound(&m, "grid", 2);
    return check_report("field field_max");
}

/* ---- tau ------------------------------------------------------------------------------------- */

static uint64_t live_bytes, peak_bytes;
static void t_log(lg_node *n, lg_log_level l, const char *fmt, va_list ap)
{
    (void)n;
    (void)l;
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}
static void t_error(lg_node *n, const char *fmt, va_list ap)
{
    (void)n;
    fprintf(stderr, "error: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}
static void t_alloc(lg_node *n, uint64_t b)
{
    (void)n;
    live_bytes += b;
    peak_bytes = live_bytes > peak_bytes ? live_bytes : peak_bytes;
}
static void t_free(lg_node *n, uint64_t b)
{
    (void)n;
    live_bytes -= b;
}

/* vol_tau_build marches its layers through lg_parallel_for: here in chunk order on this
 * thread, as the host does for a nested call. */
static int t_parallel_for(lg_node *n, size_t count, size_t grain,
                          void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk),
                          void *ctx)
{
    (void)n;
    for (size_t b = 0, c = 0; b < count; b += grain, c++)
        fn(ctx, b, b + grain < count ? b + grain : count, (uint32_t)c);
    return 0;
}

/* The centre of cell (x, y, z) as vol_common.h documents it. */
static void cell(const vol_tau_volume *t, uint32_t x, uint32_t y, uint32_t z, double p[3])
{
    uint32_t idx[3] = { x, y, z };
    for (int c = 0; c < 3; c++)
        p[c] = t->lo[c] + (t->hi[c] - t->lo[c]) * (double)idx[c] / (double)(t->n[c] - 1);
}

static float cell_tau(const vol_tau_volume *t, uint32_t x, uint32_t y, uint32_t z)
{
    return t->tau[(size_t)x + (size_t)t->n[0] * ((size_t)y + (size_t)t->n[1] * z)];
}

/* Distance from p (inside the box) along unit d to the box [-1, 1]^3's boundary. */
static double exit_unit_box(const double p[3], const double d[3])
{
    double t = INFINITY;
    for (int c = 0; c < 3; c++) {
        if (d[c] > 0)
            t = fmin(t, (1.0 - p[c]) / d[c]);
        else if (d[c] < 0)
            t = fmin(t, (-1.0 - p[c]) / d[c]);
    }
    return t;
}

typedef double (*tau_fn)(const double p[3], const vol_light *l);

static double tau_dir(const double p[3], const vol_light *l)
{
    (void)l;
    return 1.0 - p[1]; /* straight down: the chord to the top face */
}
static double tau_point(const double p[3], const vol_light *l)
{
    double d[3], len = 0.0;
    for (int c = 0; c < 3; c++) {
        d[c] = l->pos[c] - p[c];
        len += d[c] * d[c];
    }
    len = sqrt(len);
    if (len == 0.0)
        return 0.0;
    for (int c = 0; c < 3; c++)
        d[c] /= len;
    return fmin(len, exit_unit_box(p, d));
}
static double k_height = 1.5;
static double tau_height(const double p[3], const vol_light *l)
{
    (void)l;
    return (exp(-k_height * p[1]) - exp(-k_height)) / k_height;
}

static void check_tau(lg_node *n, vol_setup *v, const char *what, tau_fn want, double rel,
                      double abs_tol)
{
    vol_tau_volume t;
    live_bytes = peak_bytes = 0;
    int rc = vol_tau_build(n, v, 0, 24, &t);
    CHECKF(rc == 0, "%s: vol_tau_build returned %d", what, rc);
    if (rc)
        return;
    CHECKF(t.n[0] == 24 && t.n[1] == 24 && t.n[2] == 24, "%s: %ux%ux%u cells", what, t.n[0], t.n[1],
           t.n[2]);
    CHECKF(peak_bytes == (uint64_t)t.n[0] * t.n[1] * t.n[2] * sizeof(float),
           "%s: %llu bytes counted", what, (unsigned long long)peak_bytes);
    double worst = 0.0;
    for (uint32_t z = 0; z < t.n[2]; z++)
        for (uint32_t y = 0; y < t.n[1]; y++)
            for (uint32_t x = 0; x < t.n[0]; x++) {
                double p[3];
                cell(&t, x, y, z, p);
                double w = want(p, &v->lights[0]), got = cell_tau(&t, x, y, z);
                double err = fabs(got - w);
                worst = fmax(worst, err - rel * fabs(w));
                CHECKF(err <= rel * fabs(w) + abs_tol,
                       "%s: cell (%u, %u, %u) at (%g, %g, %g): tau %.7g, want %.7g", what, x, y, z,
                       p[0], p[1], p[2], got, w);
                CHECKF(near(vol_tau_sample(&t, p), got, 1e-6 * (1 + fabs(got))),
                       "%s: vol_tau_sample at cell (%u, %u, %u): %g, stored %g", what, x, y, z,
                       vol_tau_sample(&t, p), got);
            }
    /* clamped: a point beyond the box reads its nearest cell */
    double out[3] = { 0.0, 50.0, 0.0 }, top[3] = { 0.0, t.hi[1], 0.0 };
    CHECKF(near(vol_tau_sample(&t, out), vol_tau_sample(&t, top), 1e-9), "%s: clamping", what);
    vol_tau_free(n, &t);
    CHECKF(live_bytes == 0 && t.tau == NULL, "%s: %llu bytes still counted", what,
           (unsigned long long)live_bytes);
}

static int cmd_tau(void)
{
    lg_host_api api;
    memset(&api, 0, sizeof api);
    api.struct_size = sizeof api;
    api.log = t_log;
    api.error = t_error;
    api.account_alloc = t_alloc;
    api.account_free = t_free;
    api.parallel_for = t_parallel_for;
    lg_node node = { .host = &api, .name = "tau" };

    lg_density_field f = everywhere(LG_FIELD_UNIFORM);
    for (int c = 0; c < 3; c++) {
        f.bounds_min[c] = -1;
        f.bounds_max[c] = 1;
    }
    vol_setup v;
    memset(&v, 0, sizeof v);
    v.medium.present = true;
    v.medium.density = 1;
    v.medium.field = &f;
    v.heterogeneous = true;
    for (int c = 0; c < 3; c++) {
        v.scene_min[c] = -3; /* the scene is larger than the fog: the box is the field's */
        v.scene_max[c] = 3;
    }
    v.n_lights = 1;
    v.lights[0] = (vol_light){ .dir = { 0, -1, 0 }, .type = LG_LIGHT_DIRECTIONAL, .shadow = -1 };
    /* a constant integrand: the midpoint rule is exact but for float rounding */
    check_tau(&node, &v, "uniform, directional down", tau_dir, 1e-5, 1e-5);
    v.lights[0] = (vol_light){ .type = LG_LIGHT_POINT, .pos = { 0.2f, 0.5f, -0.1f }, .shadow = -1 };
    check_tau(&node, &v, "uniform, point inside", tau_point, 1e-5, 1e-5);
    v.lights[0].pos[1] = 2.5f;
    check_tau(&node, &v, "uniform, point above", tau_point, 1e-5, 1e-5);
    f.height_falloff = (float)k_height;
    v.lights[0] = (vol_light){ .dir = { 0, -1, 0 }, .type = LG_LIGHT_DIRECTIONAL, .shadow = -1 };
    check_tau(&node, &v, "height fog, directional down", tau_height, 1e-3, 1e-6);
    return check_report("field tau");
}

int main(int argc, char **argv)
{
    const char *c = argc > 1 ? argv[1] : "";
    if (strcmp(c, "noise") == 0)
        return cmd_noise();
    if (strcmp(c, "fbm") == 0)
        return cmd_fbm();
    if (strcmp(c, "field") == 0)
        return cmd_field();
    if (strcmp(c, "field_max") == 0)
        return cmd_field_max();
    if (strcmp(c, "tau") == 0)
        return cmd_tau();
    fprintf(stderr, "usage: test_field noise|fbm|field|field_max|tau\n");
    return 2;
}
