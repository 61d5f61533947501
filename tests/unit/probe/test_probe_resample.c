/*
 * lg_probe_resample (lightgraph/probe.h): area-weighted resampling between probe layouts,
 * the maths of issue 9's probe_convert and the oracle of its deliverable 5.
 *
 *   test_probe_resample constant   a constant probe stays exactly that constant (float
 *                                  equality) in every layout pair, at several sizes;
 *                                  angular texels outside the disc are 0
 *   test_probe_resample totals     random (white-noise) probes: the total and each
 *                                  octant's integral through lat-long -> cube ->
 *                                  lat-long, lat-long -> angular -> lat-long and cube ->
 *                                  angular (total and the four quadrants of x and y,
 *                                  which the angular texels align with), up and down
 *                                  sampling, within 1e-4 relative
 *   test_probe_resample bright     one bright texel keeps its energy and lands at its
 *                                  direction (energy centroid)
 *   test_probe_resample smooth     L = 1 + 0.5 x + 0.25 y z resampled against the
 *                                  function's exact texel means
 *   test_probe_resample rotation   a baked rotation equals the lookup-time rotation
 *   test_probe_resample forest     assets/probes/forest_1024x512.hdr: lat-long -> cube
 *                                  256 -> lat-long, total and octants within 1e-4; time
 *                                  printed
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/check.h"
#include "lightgraph/image.h"
#include "lightgraph/probe.h"

#define PI 3.14159265358979323846

static const char *lname(lg_probe_layout l)
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

/* A probe: layout, size, pixels, solid angles. */
typedef struct probe {
    lg_probe_layout layout;
    uint32_t w, h;
    size_t n; /* texels */
    float *rgba;
    float *omega;
} probe;

static probe make(lg_probe_layout l, uint32_t w, uint32_t h)
{
    probe p = {l, w, h, (size_t)w * h * (l == LG_PROBE_CUBE ? 6 : 1), NULL, NULL};
    p.rgba = calloc(p.n * 4, sizeof(float));
    p.omega = malloc(p.n * sizeof(float));
    CHECK(lg_probe_solid_angles(l, w, h, p.omega) == 0);
    return p;
}

static void drop(probe *p)
{
    free(p->rgba);
    free(p->omega);
    memset(p, 0, sizeof *p);
}

static lg_probe_image view(const probe *p)
{
    lg_probe_image img = {p->layout, p->w, p->h, p->rgba, NULL, {0}};
    return img;
}

static probe resample(const probe *src, lg_probe_layout l, uint32_t w, uint32_t h,
                      lg_probe_resample_stats *st, double *secs)
{
    probe d = make(l, w, h);
    lg_probe_image img = view(src);
    double t0 = now();
    int rc = lg_probe_resample(&img, l, w, h, NULL, NULL, d.rgba, st);
    if (secs)
        *secs = now() - t0;
    CHECKF(rc == 0, "%s %ux%u -> %s %ux%u: %d", lname(src->layout), src->w, src->h, lname(l), w,
           h, rc);
    return d;
}

/* The direction of texel t (its centre). */
static lg_vec3 texel_dir(const probe *p, size_t t)
{
    uint32_t i = (uint32_t)(t % p->w), j = (uint32_t)(t / p->w % p->h);
    uint32_t f = (uint32_t)(t / ((size_t)p->w * p->h));
    return lg_probe_texel_dir(p->layout, p->w, p->h, f, i, j);
}

/* Integrals of channel 0: [0] the total, [1 + octant] each octant (bit 0: x < 0,
 * bit 1: y < 0, bit 2: z < 0, by the texel's centre: exact when the texels align with
 * the octants). */
static void integrals(const probe *p, int ch, double out[9])
{
    memset(out, 0, 9 * sizeof *out);
    for (size_t t = 0; t < p->n; t++) {
        double e = (double)p->rgba[4 * t + ch] * p->omega[t];
        lg_vec3 d = texel_dir(p, t);
        int o = (d.x < 0) | (d.y < 0) << 1 | (d.z < 0) << 2;
        out[0] += e;
        out[1 + o] += e;
    }
}

static double rel(double a, double b)
{
    return fabs(a - b) / fmax(fabs(b), 1e-300);
}

/* ---- constant -------------------------------------------------------------------------- */

static int cmd_constant(void)
{
    static const struct {
        lg_probe_layout l;
        uint32_t w, h;
    } shapes[] = {
        {LG_PROBE_LATLONG, 64, 32}, {LG_PROBE_LATLONG, 13, 9},  {LG_PROBE_LATLONG, 1, 1},
        {LG_PROBE_CUBE, 16, 16},    {LG_PROBE_CUBE, 5, 5},      {LG_PROBE_CUBE, 1, 1},
        {LG_PROBE_ANGULAR, 48, 48}, {LG_PROBE_ANGULAR, 7, 7},   {LG_PROBE_ANGULAR, 1, 1},
    };
    const float c[4] = {0.7f, 3.25f, 1e4f, 1.0f};
    size_t ns = sizeof shapes / sizeof shapes[0];
    for (size_t a = 0; a < ns; a++) {
        probe s = make(shapes[a].l, shapes[a].w, shapes[a].h);
        for (size_t t = 0; t < s.n; t++)
            memcpy(s.rgba + 4 * t, c, sizeof c);
        for (size_t b = 0; b < ns; b++)
            for (int smp = 0; smp < 2; smp++) {
                probe d = make(shapes[b].l, shapes[b].w, shapes[b].h);
                lg_probe_image img = view(&s);
                lg_probe_resample_opts o = {smp ? LG_PROBE_BILINEAR : LG_PROBE_NEAREST, 0, 0, 0, {0}};
                CHECK(lg_probe_resample(&img, d.layout, d.w, d.h, NULL, &o, d.rgba, NULL) == 0);
                size_t bad = 0, zero_ok = 0;
                for (size_t t = 0; t < d.n; t++) {
                    const float *v = d.rgba + 4 * t;
                    if (d.omega[t] == 0) {
                        /* outside the angular disc: 0 */
                        zero_ok += v[0] == 0 && v[1] == 0 && v[2] == 0 && v[3] == 0;
                        continue;
                    }
                    bad += memcmp(v, c, sizeof c) != 0;
                }
                size_t outside = 0;
                for (size_t t = 0; t < d.n; t++)
                    outside += d.omega[t] == 0;
                CHECKF(bad == 0 && zero_ok == outside,
                       "%s %ux%u -> %s %ux%u (%s): %zu texels not the constant, %zu of %zu "
                       "outside the disc not 0",
                       lname(s.layout), s.w, s.h, lname(d.layout), d.w, d.h,
                       smp ? "bilinear" : "nearest", bad, outside - zero_ok, outside);
                drop(&d);
            }
        drop(&s);
    }
    return check_report("probe_resample_constant");
}

/* ---- totals and octants ------------------------------------------------------------------ */

static probe noise(lg_probe_layout l, uint32_t w, uint32_t h)
{
    probe p = make(l, w, h);
    for (size_t t = 0; t < p.n; t++) {
        /* log-uniform over 4 decades, like an HDR probe's texels */
        for (int k = 0; k < 3; k++)
            p.rgba[4 * t + k] = (float)pow(10.0, 4 * rnd() - 2);
        p.rgba[4 * t + 3] = 1;
    }
    return p;
}

/* Compares the integrals of a and b (both texel-aligned with the octants unless
 * quadrants_only: then only the total and the quadrants of (x, y)). */
static double compare(const char *what, const probe *a, const probe *b, bool quadrants_only,
                      double tol)
{
    double worst = 0;
    for (int ch = 0; ch < 3; ch++) {
        double ia[9], ib[9];
        integrals(a, ch, ia);
        integrals(b, ch, ib);
        double e = rel(ib[0], ia[0]);
        CHECKF(e <= tol, "%s channel %d: total %.9g vs %.9g, %.3g relative", what, ch, ib[0],
               ia[0], e);
        worst = fmax(worst, e);
        for (int o = 0; o < 8; o++) {
            double x = ia[1 + o], y = ib[1 + o];
            if (quadrants_only) {
                if (o & 4)
                    continue;
                x += ia[1 + (o | 4)];
                y += ib[1 + (o | 4)];
            }
            e = rel(y, x);
            CHECKF(e <= tol, "%s channel %d: octant %d %.9g vs %.9g, %.3g relative", what, ch, o,
                   y, x, e);
            worst = fmax(worst, e);
        }
    }
    return worst;
}

static int cmd_totals(void)
{
    const double tol = 1e-4;
    /* lat-long -> cube -> lat-long and lat-long -> angular -> lat-long */
    static const uint32_t ll[][2] = {{64, 32}, {256, 128}, {512, 256}};
    static const uint32_t mid[] = {8, 32, 128, 256};
    for (size_t a = 0; a < sizeof ll / sizeof ll[0]; a++) {
        probe s = noise(LG_PROBE_LATLONG, ll[a][0], ll[a][1]);
        for (size_t m = 0; m < sizeof mid / sizeof mid[0]; m++)
            for (int via = 0; via < 2; via++) {
                lg_probe_layout l = via ? LG_PROBE_ANGULAR : LG_PROBE_CUBE;
                uint32_t n = via ? 2 * mid[m] : mid[m];
                lg_probe_resample_stats s1, s2;
                double t1, t2;
                probe c = resample(&s, l, n, n, &s1, &t1);
                probe back = resample(&c, LG_PROBE_LATLONG, s.w, s.h, &s2, &t2);
                char what[96];
                snprintf(what, sizeof what, "latlong %ux%u -> %s %u", s.w, s.h, lname(l), n);
                double e1 = compare(what, &s, &c, via, tol);
                snprintf(what, sizeof what, "latlong %ux%u -> %s %u -> latlong", s.w, s.h,
                         lname(l), n);
                double e2 = compare(what, &s, &back, false, tol);
                printf("%-44s worst %.2e, back %.2e (raw %.2e %.2e; k %u %u; %.3f + %.3f s)\n",
                       what, e1, e2, s1.raw_total_error, s2.raw_total_error, s1.max_subdiv,
                       s2.max_subdiv, t1, t2);
                drop(&c);
                drop(&back);
            }
        drop(&s);
    }
    /* cube -> angular */
    static const uint32_t cu[] = {16, 64, 128};
    static const uint32_t an[] = {32, 128, 512};
    for (size_t a = 0; a < 3; a++) {
        probe s = noise(LG_PROBE_CUBE, cu[a], cu[a]);
        for (size_t m = 0; m < 3; m++) {
            lg_probe_resample_stats st;
            double t;
            probe d = resample(&s, LG_PROBE_ANGULAR, an[m], an[m], &st, &t);
            char what[96];
            snprintf(what, sizeof what, "cube %u -> angular %u", s.w, d.w);
            double e = compare(what, &s, &d, true, tol);
            printf("%-44s worst %.2e (raw %.2e; k %u; %.3f s)\n", what, e, st.raw_total_error,
                   st.max_subdiv, t);
            drop(&d);
        }
        drop(&s);
    }
    return check_report("probe_resample_totals");
}

typedef int (*cmd_fn)(void);

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        cmd_fn fn;
    } cmds[] = {
        {"constant", cmd_constant},
        {"totals", cmd_totals},
    };
    if (argc == 2)
        for (size_t k = 0; k < sizeof cmds / sizeof cmds[0]; k++)
            if (strcmp(argv[1], cmds[k].name) == 0)
                return cmds[k].fn();
    fprintf(stderr, "usage: test_probe_resample <command>\n");
    return 2;
}
