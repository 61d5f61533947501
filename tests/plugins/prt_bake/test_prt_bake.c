/*
 * The prt_bake plugin's nodes (prt_bake, prt_reference) through the host, on scenes built
 * in memory by the test plugin testprtscene. The transfer is read back as an image
 * (test_transfer_image: every coefficient) and dotted here with lighting computed here
 * (lightgraph/sh.h), so every oracle is independent of the plugin:
 *
 *   unshadowed    transfer . L = (rho / pi) E_n on a sphere, L = 1 + 0.5 x + 0.3 z^2 (its
 *                 coefficients by quadrature here, E in closed form), bands 3 and 5
 *   cone          the apex of a conical pit of half-angle alpha under a constant sky 1:
 *                 rho sin^2(alpha), alpha = 20, 45, 70 degrees
 *   furnace       an open white box under a constant sky 1: interreflected radiance rises
 *                 with the bounces toward 1 (error printed per bounce count); shadowed < 1
 *   backface      a square above a floor point blocks 1 - F (F: the form factor of the
 *                 square) whether the point sees its front or its back (Embree's backface
 *                 culling off)
 *   large_coords  the quad scene translated by 1e5 gives the transfer of the untranslated
 *                 one; a plane at 1e6 (and 0) has no self-shadowing: shadowed == unshadowed
 *   brute         visibility = brute and = embree agree (same rays; a handful of ties)
 *   params        albedo material == [r, g, b] of the same colour; albedo scales; bands;
 *                 bad parameters fail with a message naming the node and value
 *   memory        under an address-space limit of 2 GiB (RLIMIT_AS, set in this process and
 *                 so in the host it runs): interreflected with samples = 2048 and
 *                 hit_memory_mib = 1048576 on the box (hits up to 40 MiB per vertex) is
 *                 refused in prepare, naming hit_memory_mib, its value, the bytes needed and
 *                 the bytes available; samples = 2048 with bands = 12 (a 2.3 GiB direction
 *                 table) likewise names samples; the same box at samples = 32 bakes
 *   few_samples   samples 1..5 (fewer rays than a packet holds) bake, finite
 *   cache         a second render loads the bake; a corrupt entry is reported and baked
 *                 again, equal; changed parameters make a new entry
 *   cache_said    "cached" only when the host stored the entry: a disabled cache (a
 *                 world-writable cache folder) and an entry that cannot be stored (a folder
 *                 with a file in its place) say "not cached" and why
 *   forged        entries of the bake and of the reference with a valid checksum but values
 *                 the node cannot make (NaN, Inf, 3e38, and a finite value just beyond the
 *                 bound of the computation) at the first, a middle and the last float:
 *                 each is reported once ("is corrupt (float N ..."), removed and made again,
 *                 equal bit for bit to a cold run; the remade entry then loads
 *   nonfinite     prt_reference under a probe with one NaN, +Inf or -Inf texel (lat-long
 *                 and cube, the test plugin's test_raw_probe, never cleaned): every float
 *                 finite and equal bit for bit to the same probe with the texel 0, computed
 *                 and from the cache; one warning naming the count and the texel
 *   reference     prt_reference: unshadowed = (rho / pi) E of a smooth probe; the cone's
 *                 shadowed value rho sin^2(alpha); the bake approaches it as samples grow
 *   masked        alpha masks (plugins/embree_common's filter): a square at y = 1 over the
 *                 floor with a checker alpha texture (test_prt_scene layout = masked); each
 *                 floor vertex's shadowed t_0 lies between the bounds an analytic trace of
 *                 the same directions gives (the ray's crossing of y = 1 in an opaque cell
 *                 blocks, in a transparent one passes; crossings within 1e-4 of a cell edge
 *                 may go either way), for Embree and brute-force visibility, both checker
 *                 phases, and BLEND (treated as a mask at its cutoff); the two phases add up
 *                 to the plane plus the opaque square; a square without texture coordinates
 *                 is opaque (bit for bit the unmasked square's bake); a factor alpha below
 *                 the cutoff removes the square (bit for bit the plane's bake);
 *                 prt_reference's shadow rays against the same analytic bounds; a white and
 *                 black checker texture on the square turned to the floor bounces about half
 *                 of the white square's light onto it, no vertex more; the cache
 *                 key: the texture's RGB changed loads the shadowed bake, the mask changed
 *                 bakes again, interreflected bakes again on either
 *   chain         the oracles through the whole chain users run, on every backend of the
 *                 `prt` node (cpu, gl, cl): a probe written here -> sh_project (quadrature)
 *                 -> prt_bake -> prt, its `vertices` output read back: the cone's apex
 *                 rho sin^2(alpha) (a constant probe has only L_0: no truncation), the open
 *                 white box's interreflected radiance -> 1, and unshadowed = (rho / pi) E_n
 *                 on the sphere under the smooth probe; the three backends agree
 *   threads       the bunny in the Cornell box baked interreflected and shadowed, and
 *                 prt_reference, with the pool at 1 and at 2 threads (LIGHTGRAPH_THREADS),
 *                 each from a cold cache: every output and every cache entry the same
 *                 bytes (lg_shard's chunks differ with the pool's size); the interreflected
 *                 bake whose hits pass a 1 MiB budget equals the one that keeps them, bit
 *                 for bit
 *   dist2, dist3  the same graphs and examples/prt.lgraph's chain on the bake (sh_project,
 *                 prt on the cpu, reinhard) under tests/dist/mpirun.sh 2 and 3 (one thread
 *                 per rank, 3 oversubscribed on this 2-core machine) against one process:
 *                 the same output bytes and cache entry bytes, each result said once (rank
 *                 0); on the warm cache the ranks load every entry and draw the same
 *                 picture (meson tests `prt_bake dist np2`, `np3`, suite dist, with MPI)
 */
#include <dirent.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "lightgraph/image.h"
#include "lightgraph/probe.h"
#include "lightgraph/sampling.h"
#include "lightgraph/sh.h"
#include "lightgraph/test.h"
#include "lightgraph/transfer.h"
#include "lightgraph/vecmath.h"

#include "common/cache_forge.h"

/* ---- helpers --------------------------------------------------------------------------------- */

/* Renders graph text `g` with `extra` args (NULL-terminated, may be NULL); returns the exit
 * status; *text (may be NULL) gets the output. */
static int run(lg_test *t, const char *g, char **text)
{
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "-v", NULL };
    return lg_test_render(t, "g.lgraph", args, text);
}

/* A transfer read back: nv vertices, n2 coefficients, [i][c][k]. */
typedef struct tr {
    uint32_t nv, n2;
    float *t;
} tr;

static void tr_free(tr *x)
{
    free(x->t);
    memset(x, 0, sizeof *x);
}

/* Bakes `scene` (a test_prt_scene parameter list) with prt_bake parameters `bake` and reads
 * the transfer; false after a failed check. */
static bool bake(lg_test *t, const char *scene, const char *bakep, uint32_t bands, tr *out,
                 char **text)
{
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_prt_scene { %s }\n"
             "b = prt_bake { scene = s, bands = %u, %s }\n"
             "v = test_transfer_image { transfer = b, bands = %u }\n"
             "output v \"t.exr\"\n",
             scene, bands, bakep, bands);
    memset(out, 0, sizeof *out);
    char *txt = NULL;
    int rc = run(t, g, &txt);
    LG_TEST_CHECK(t, rc == 0, "bake of { %s } with { %s } failed (%d):\n%s", scene, bakep, rc,
                  txt ? txt : "");
    if (text)
        *text = txt;
    else
        free(txt);
    if (rc != 0)
        return false;
    lg_image img;
    if (!lg_test_read(t, "t.exr", &img, NULL))
        return false;
    /* testprtscene.c: V vertices per row, n^2 texels each; alpha 1 marks a vertex */
    out->n2 = bands * bands;
    uint32_t V = out->n2 >= 1024 ? 1 : 1024 / out->n2;
    LG_TEST_CHECK(t, img.width == V * out->n2, "transfer image %u wide, want %u", img.width,
                  V * out->n2);
    out->nv = 0;
    while (
        out->nv < V * img.height &&
        img.pixels[4 * ((size_t)(out->nv / V) * img.width + (size_t)(out->nv % V) * out->n2) + 3] ==
            1.0f)
        out->nv++;
    out->t = malloc(((size_t)out->nv * 3 * out->n2 + 1) * sizeof(float));
    for (uint32_t i = 0; i < out->nv; i++)
        for (uint32_t k = 0; k < out->n2; k++)
            for (int c = 0; c < 3; c++)
                out->t[(size_t)i * 3 * out->n2 + (size_t)c * out->n2 + k] =
                    img.pixels[4 * ((size_t)(i / V) * img.width + (size_t)(i % V) * out->n2 + k) +
                               c];
    lg_image_free(&img);
    return true;
}

/* The radiance of vertex i, channel c, under lighting coefficients L[n2] (same for RGB). */
static double radiance(const tr *x, uint32_t i, int c, const double *L)
{
    double s = 0;
    for (uint32_t k = 0; k < x->n2; k++)
        s += (double)x->t[(size_t)i * 3 * x->n2 + (size_t)c * x->n2 + k] * L[k];
    return s;
}

/* The constant sky 1: only L_0 = sqrt(4 pi). */
static void sky_const(double *L, uint32_t n2)
{
    memset(L, 0, n2 * sizeof *L);
    L[0] = sqrt(4 * LG_PI);
}

/* The smooth environment of the tests and its irradiance (Funk-Hecke, closed form):
 *   L(w) = 1 + 0.5 x + 0.3 z^2,
 *   E(N) = pi + 0.5 (2 pi / 3) N_x + 0.3 [pi / 3 + (pi / 4)(N_z^2 - 1/3)]
 * (1 -> pi; x -> A_1 x; z^2 = 1/3 + (z^2 - 1/3), a band-2 function -> A_2 (z^2 - 1/3)). */
static double env_L(const double d[3])
{
    return 1 + 0.5 * d[0] + 0.3 * d[2] * d[2];
}
static double env_E(const double N[3])
{
    return LG_PI + 0.5 * (2 * LG_PI / 3) * N[0] +
           0.3 * (LG_PI / 3 + (LG_PI / 4) * (N[2] * N[2] - 1.0 / 3));
}

/* Its SH coefficients by a product rule exact for polynomials of degree <= 2 + 2 (bands
 * up to 3 matter; higher ones are 0 and come out 0 to rounding): Gauss-Legendre in
 * cos theta (8 points) times 16 equal steps in phi. */
static void env_coeffs(uint32_t bands, double *L)
{
    static const double gx[8] = { -0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                  -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                  0.7966664774136267,  0.9602898564975363 };
    static const double gw[8] = { 0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                  0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                  0.2223810344533745, 0.1012285362903763 };
    uint32_t n2 = bands * bands;
    double *y = malloc(n2 * sizeof *y);
    memset(L, 0, n2 * sizeof *L);
    for (int a = 0; a < 8; a++)
        for (int b = 0; b < 16; b++) {
            double ct = gx[a], st = sqrt(1 - ct * ct), ph = 2 * LG_PI * (b + 0.5) / 16;
            double d[3] = { st * cos(ph), ct, st * sin(ph) };
            lg_sh_eval_d(bands, d, y);
            double w = gw[a] * (2 * LG_PI / 16) * env_L(d);
            for (uint32_t k = 0; k < n2; k++)
                L[k] += w * y[k];
        }
    free(y);
}

/* The form factor from a point to a parallel square [-a, a]^2 at height h above it (four
 * corner rectangles of the classic formula). */
static double square_ff(double a, double h)
{
    double X = a / h, Y = a / h;
    double f = (X / sqrt(1 + X * X) * atan(Y / sqrt(1 + X * X)) +
                Y / sqrt(1 + Y * Y) * atan(X / sqrt(1 + Y * Y))) /
               (2 * LG_PI);
    return 4 * f;
}

/* ---- cases ----------------------------------------------------------------------------------- */

static void case_unshadowed(lg_test *t)
{
    const double rho[3] = { 0.8, 0.5, 0.2 };
    const uint32_t seg = 24, cols = seg, rows = seg / 2;
    for (uint32_t bands = 3; bands <= 5; bands += 2) {
        tr x;
        if (!bake(t, "layout = sphere, segments = 24, base_color = [0.8, 0.5, 0.2]",
                  "mode = unshadowed, samples = 64", bands, &x, NULL))
            return;
        double L[25];
        env_coeffs(bands, L);
        LG_TEST_CHECK(t, x.nv == (cols + 1) * (rows + 1), "%u vertices", x.nv);
        double worst = 0;
        for (uint32_t j = 0, v = 0; j <= rows; j++)
            for (uint32_t i = 0; i <= cols && v < x.nv; i++, v++) {
                double th = LG_PI * j / rows, ph = 2 * LG_PI * i / cols;
                double N[3] = { sin(th) * cos(ph), cos(th), -sin(th) * sin(ph) };
                for (int c = 0; c < 3; c++) {
                    double want = rho[c] / LG_PI * env_E(N), got = radiance(&x, v, c, L);
                    worst = fmax(worst, fabs(got - want));
                }
            }
        /* 4096 Sobol directions: the cosine lobe's quadrature error is about 1e-3 */
        fprintf(stderr, "unshadowed, %u bands: worst |t.L - (rho/pi) E| = %.2e\n", bands, worst);
        LG_TEST_CHECK(t, worst < 4e-3, "%u bands: worst error %.3g", bands, worst);
        tr_free(&x);
    }
    /* the other samplers, same oracle (jittered converges more slowly: a looser bound) */
    static const char *const samplers[] = { "jittered", "hammersley" };
    for (int k = 0; k < 2; k++) {
        char p[128];
        snprintf(p, sizeof p, "mode = unshadowed, samples = 64, sampler = %s, seed = 7",
                 samplers[k]);
        tr x;
        if (!bake(t, "layout = sphere, segments = 24", p, 3, &x, NULL))
            return;
        double L[9], worst = 0;
        env_coeffs(3, L);
        for (uint32_t j = 0, v = 0; j <= rows; j++)
            for (uint32_t i = 0; i <= cols; i++, v++) {
                double th = LG_PI * j / rows, ph = 2 * LG_PI * i / cols;
                double N[3] = { sin(th) * cos(ph), cos(th), -sin(th) * sin(ph) };
                worst = fmax(worst, fabs(radiance(&x, v, 1, L) - env_E(N) / LG_PI));
            }
        fprintf(stderr, "unshadowed, %s: worst error %.2e\n", samplers[k], worst);
        LG_TEST_CHECK(t, worst < (k == 0 ? 1e-2 : 4e-3), "%s: worst error %.3g", samplers[k],
                      worst);
        tr_free(&x);
    }
}

static void case_cone(lg_test *t)
{
    static const double alphas[] = { 20, 45, 70 };
    double L[9];
    sky_const(L, 9);
    for (int a = 0; a < 3; a++) {
        char scene[256];
        snprintf(scene, sizeof scene,
                 "layout = cone, alpha_deg = %g, segments = 128, base_color = [0.9, 0.6, 0.3]",
                 alphas[a]);
        tr x;
        if (!bake(t, scene, "mode = shadowed, samples = 128", 3, &x, NULL))
            return;
        double s = sin(alphas[a] * LG_PI / 180), rho[3] = { 0.9, 0.6, 0.3 };
        for (int c = 0; c < 3; c++) {
            double got = radiance(&x, 0, c, L), want = rho[c] * s * s;
            if (c == 0)
                fprintf(stderr, "cone alpha %g: apex radiance %.5f, rho sin^2 alpha %.5f\n",
                        alphas[a], got, want);
            LG_TEST_CHECK(t, fabs(got - want) < 0.005, "alpha %g channel %d: %.5f, want %.5f",
                          alphas[a], c, got, want);
        }
        tr_free(&x);
    }
}

static void case_furnace(lg_test *t)
{
    double L[9];
    sky_const(L, 9);
    /* the opening is a sixth of the box: light stays for many bounces (each keeps about
     * 0.83 of the last one's error here), so the count goes to 32 */
    static const int bounces[] = { 0, 1, 2, 4, 8, 16, 32 };
    double prev = 0;
    for (int b = 0; b < 7; b++) {
        char p[256];
        if (bounces[b] == 0)
            snprintf(p, sizeof p, "mode = shadowed, samples = 32");
        else
            snprintf(p, sizeof p,
                     "mode = interreflected, samples = 32, bounces = %d, bounce_threshold = 0",
                     bounces[b]);
        tr x;
        if (!bake(t, "layout = box, grid = 6", p, 3, &x, NULL))
            return;
        double sum = 0, lo = 1e9, hi = -1e9;
        for (uint32_t i = 0; i < x.nv; i++) {
            double r = radiance(&x, i, 1, L);
            sum += r;
            lo = fmin(lo, r);
            hi = fmax(hi, r);
        }
        double mean = sum / x.nv;
        fprintf(stderr,
                "furnace, %2d bounces: mean radiance %.4f (error %.4f), min %.4f, max "
                "%.4f\n",
                bounces[b], mean, 1 - mean, lo, hi);
        if (bounces[b] == 0)
            LG_TEST_CHECK(t, mean < 0.9 && hi < 1.0, "shadowed: mean %.4f, max %.4f (want < 1)",
                          mean, hi);
        else
            LG_TEST_CHECK(t, mean > prev, "%d bounces: mean %.4f not above %.4f", bounces[b], mean,
                          prev);
        LG_TEST_CHECK(t, hi < 1.01, "%d bounces: a vertex at %.4f, above 1", bounces[b], hi);
        if (bounces[b] == 32)
            LG_TEST_CHECK(t, fabs(1 - mean) < 0.01, "32 bounces: mean %.4f, want 1 within 0.01",
                          mean);
        prev = mean;
        if (bounces[b] == 4) {
            /* hits not kept (hit_memory_mib = 0): every bounce casts its rays again, and
             * finds the same hits */
            tr y;
            char q[300];
            snprintf(q, sizeof q, "%s, hit_memory_mib = 0", p);
            if (bake(t, "layout = box, grid = 6", q, 3, &y, NULL)) {
                double worst = 0;
                for (size_t k = 0; k < (size_t)x.nv * 3 * x.n2; k++)
                    worst = fmax(worst, fabs(x.t[k] - y.t[k]));
                fprintf(stderr, "furnace, 4 bounces, hits cast again: worst difference %.2e\n",
                        worst);
                LG_TEST_CHECK(t, worst < 1e-5, "hits kept or cast again differ by %.3g", worst);
                tr_free(&y);
            }
            /* a budget the hits pass (1 MiB; about 2 MiB of hits here): the ones kept are
             * dropped and the bounces cast again, the same result, and the log says so */
            char *txt = NULL;
            snprintf(q, sizeof q, "%s, hit_memory_mib = 1", p);
            if (bake(t, "layout = box, grid = 6", q, 3, &y, &txt)) {
                double worst = 0;
                for (size_t k = 0; k < (size_t)x.nv * 3 * x.n2; k++)
                    worst = fmax(worst, fabs(x.t[k] - y.t[k]));
                fprintf(stderr, "furnace, 4 bounces, hits over a 1 MiB budget: worst %.2e\n",
                        worst);
                LG_TEST_CHECK(t, worst < 1e-5, "hits over the budget: differ by %.3g", worst);
                LG_TEST_CHECK(t, txt && strstr(txt, "passed their budget of 1.0 MiB"),
                              "hit_memory_mib = 1: no word of the budget passed:\n%s",
                              txt ? txt : "");
                tr_free(&y);
            }
            free(txt);
        }
        if (bounces[b] == 1) {
            /* the default (auto) keeps this box's hits, and says how many and why */
            char *txt = NULL;
            tr y;
            if (bake(t, "layout = box, grid = 6", "mode = interreflected, samples = 16", 3, &y,
                     &txt)) {
                LG_TEST_CHECK(t, txt && strstr(txt, "kept ") && strstr(txt, "(auto)"),
                              "the default hit_memory_mib: hits not kept, or not said:\n%s",
                              txt ? txt : "");
                tr_free(&y);
            }
            free(txt);
        }
        tr_free(&x);
    }
}

static void case_backface(lg_test *t)
{
    double L[9];
    sky_const(L, 9);
    double want = 1 - square_ff(0.5, 1.0);
    for (int f = 0; f < 2; f++) {
        char scene[256];
        snprintf(scene, sizeof scene, "layout = quad, grid = 4, quad_size = 0.5, quad_flip = %s",
                 f ? "true" : "false");
        tr x;
        if (!bake(t, scene, "mode = shadowed, samples = 128", 3, &x, NULL))
            return;
        /* the floor's centre vertex: grid 4, row 2, column 2 */
        double got = radiance(&x, 2 * 5 + 2, 1, L);
        fprintf(stderr, "square seen from its %s: %.5f, 1 - F = %.5f\n", f ? "front" : "back", got,
                want);
        LG_TEST_CHECK(t, fabs(got - want) < 0.005, "square seen from its %s: %.5f, want %.5f",
                      f ? "front" : "back", got, want);
        tr_free(&x);
    }
}

/* Very few directions (samples 1..5: 1 to 25 directions, fewer than a 16-ray packet per
 * vertex): the bake runs (Embree's assertion on the packet's unused lanes aborted the process
 * for samples 2..4, issue 20) and every coefficient is finite; the constant sky's radiance
 * at the open floor's centre stays within [0, 2] however crude the estimate. */
static void case_few_samples(lg_test *t)
{
    double L[9];
    sky_const(L, 9);
    for (int n = 1; n <= 5; n++) {
        char bp[128];
        snprintf(bp, sizeof bp, "mode = shadowed, samples = %d", n);
        tr x;
        if (!bake(t, "layout = quad, grid = 4, quad_size = 0.5", bp, 3, &x, NULL))
            return;
        size_t bad = 0;
        for (size_t i = 0; i < (size_t)x.nv * 3 * x.n2; i++)
            bad += !isfinite(x.t[i]);
        double got = radiance(&x, 2 * 5 + 2, 1, L);
        LG_TEST_CHECK(t, bad == 0 && got >= 0 && got <= 2,
                      "samples = %d: %zu non-finite coefficients, centre radiance %g", n, bad, got);
        tr_free(&x);
    }
}

static void case_large_coords(lg_test *t)
{
    double L[9];
    sky_const(L, 9);
    tr a, b;
    if (!bake(t, "layout = quad, grid = 8", "samples = 32", 3, &a, NULL) ||
        !bake(t, "layout = quad, grid = 8, translate = [1e5, -1e5, 1e5]", "samples = 32", 3, &b,
              NULL))
        return;
    double worst = 0;
    for (uint32_t i = 0; i < 81; i++)
        worst = fmax(worst, fabs(radiance(&a, i, 1, L) - radiance(&b, i, 1, L)));
    /* at 1e5 float coordinates are 0.0078 apart (the square's corners move by that) and
     * the rays' origins rise by 4 ulps (0.03, pb_offset): the square, 1 above the floor,
     * then blocks about 0.01 more of the sky */
    fprintf(stderr, "quad scene at 0 and at 1e5: worst floor radiance difference %.2e\n", worst);
    LG_TEST_CHECK(t, worst < 0.02, "translated by 1e5: the floor's radiance moves by %.3g", worst);
    tr_free(&a);
    tr_free(&b);
    /* no acne: a lone plane is unoccluded everywhere, at any distance from the origin */
    static const char *const where[] = { "[0, 0, 0]", "[1e5, 1e5, 1e5]", "[-1e6, 1e6, 3e5]" };
    for (int w = 0; w < 3; w++) {
        char scene[256];
        snprintf(scene, sizeof scene, "layout = plane, grid = 16, translate = %s", where[w]);
        tr s, u;
        if (!bake(t, scene, "mode = shadowed, samples = 32", 3, &s, NULL) ||
            !bake(t, scene, "mode = unshadowed, samples = 32", 3, &u, NULL))
            return;
        uint32_t acne = 0;
        for (size_t q = 0; q < (size_t)s.nv * 3 * s.n2; q++)
            acne += s.t[q] != u.t[q];
        LG_TEST_CHECK(t, acne == 0,
                      "plane at %s: %u coefficients differ between shadowed and "
                      "unshadowed (self-shadowing)",
                      where[w], acne);
        tr_free(&s);
        tr_free(&u);
    }
}

static void case_brute(lg_test *t)
{
    tr e, b;
    if (!bake(t, "layout = quad, grid = 4", "samples = 16, visibility = embree", 3, &e, NULL) ||
        !bake(t, "layout = quad, grid = 4", "samples = 16, visibility = brute", 3, &b, NULL))
        return;
    /* one ray more or less moves a coefficient by at most 4 rho |Y| / T <= 4 (0.55) / 256 */
    double one = 4 * 0.55 / 256, worst = 0;
    uint32_t differ = 0;
    for (uint32_t i = 0; i < e.nv; i++) {
        bool d = false;
        for (uint32_t q = 0; q < 3 * e.n2; q++) {
            double diff = fabs(e.t[(size_t)i * 3 * e.n2 + q] - b.t[(size_t)i * 3 * e.n2 + q]);
            worst = fmax(worst, diff);
            d |= diff > 1e-6;
        }
        differ += d;
    }
    fprintf(stderr, "brute vs embree: %u of %u vertices differ, worst %.2e (one ray %.2e)\n",
            differ, e.nv, worst, one);
    LG_TEST_CHECK(t, worst <= 3 * one, "brute and embree differ by %.3g (%.1f rays)", worst,
                  worst / one);
    LG_TEST_CHECK(t, differ <= 3, "%u vertices differ between brute and embree", differ);
    tr_free(&e);
    tr_free(&b);
}

static void case_params(lg_test *t)
{
    tr m, c, h;
    if (!bake(t, "layout = quad, grid = 2, base_color = [0.8, 0.5, 0.2]", "albedo = material", 3,
              &m, NULL) ||
        !bake(t, "layout = quad, grid = 2", "albedo = [0.8, 0.5, 0.2]", 3, &c, NULL) ||
        !bake(t, "layout = quad, grid = 2", "albedo = [0.4, 0.25, 0.1]", 3, &h, NULL))
        return;
    uint32_t diff = 0, half = 0;
    for (size_t q = 0; q < (size_t)m.nv * 3 * m.n2; q++) {
        diff += m.t[q] != c.t[q];
        half += fabs(h.t[q] - 0.5 * c.t[q]) > 1e-7 * (1 + fabs(c.t[q]));
    }
    LG_TEST_CHECK(t, diff == 0, "albedo material and the same [r, g, b]: %u values differ", diff);
    LG_TEST_CHECK(t, half == 0, "half the albedo: %u values are not half", half);
    /* the planes are R, G, B: ratios 0.8 : 0.5 : 0.2 on a lit coefficient */
    double cr = c.t[0], cg = c.t[c.n2], cb = c.t[2 * c.n2];
    LG_TEST_CHECK(t, cr > 0 && fabs(cg / cr - 0.625) < 1e-5 && fabs(cb / cr - 0.25) < 1e-5,
                  "channel planes %g %g %g, not in the ratio 0.8 : 0.5 : 0.2", cr, cg, cb);
    tr_free(&m);
    tr_free(&c);
    tr_free(&h);
    tr x;
    if (bake(t, "layout = quad, grid = 2", "samples = 8", 6, &x, NULL)) {
        LG_TEST_CHECK(t, x.nv == 9 + 4 && x.n2 == 36, "bands 6: %u vertices x %u", x.nv, x.n2);
        tr_free(&x);
    }
    /* bad input: an error naming node and value, non-zero exit */
    static const struct {
        const char *bake, *says;
    } bad[] = {
        { "albedo = [2, 0.5, 0.5]", "albedo" },
        { "samples = 0", "samples" },
        { "bands = 65", "bands" },
        { "bounce_threshold = nan", "bounce_threshold" },
        { "mode = glossy", "mode" },
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char g[1024];
        snprintf(g, sizeof g,
                 "lightgraph 1\ns = test_prt_scene { layout = plane, grid = 2 }\n"
                 "b = prt_bake { scene = s, %s }\n"
                 "v = test_transfer_image { transfer = b }\noutput v \"bad.exr\"\n",
                 bad[k].bake);
        char *text = NULL;
        int rc = run(t, g, &text);
        LG_TEST_CHECK(t, rc != 0 && text && strstr(text, bad[k].says) && strstr(text, "b"),
                      "{ %s }: exit %d, output:\n%s", bad[k].bake, rc, text ? text : "");
        free(text);
    }
    char g[512];
    snprintf(g, sizeof g,
             "lightgraph 1\ns = test_prt_scene { layout = plane, grid = 2 }\n"
             "sky = probe { file = \"none.exr\" }\n"
             "r = prt_reference { scene = s, probe = sky, mode = interreflected }\n"
             "output r \"bad.exr\"\n");
    lg_image one = { 0 };
    lg_image_alloc(&one, 2, 1);
    for (int q = 0; q < 8; q++)
        one.pixels[q] = 1;
    lg_test_write_exr(t, "none.exr", &one);
    lg_image_free(&one);
    char *text = NULL;
    int rc = run(t, g, &text);
    LG_TEST_CHECK(t, rc != 0 && text && strstr(text, "interreflected"),
                  "prt_reference, mode = interreflected: exit %d, output:\n%s", rc,
                  text ? text : "");
    free(text);
}

/* The prt_bake entries in the case's cache folder: how many, and the first one's path. */
static void case_memory(lg_test *t)
{
#ifdef __SANITIZE_ADDRESS__
    /* AddressSanitizer reserves terabytes of address space for its shadow at start-up: the
     * host cannot start under a 2 GiB RLIMIT_AS. The normal build runs this case. */
    printf("AddressSanitizer build: the RLIMIT_AS case is not run\n");
    (void)t;
    return;
#endif
    struct rlimit rl = { 2ull << 30, 2ull << 30 };
    LG_TEST_CHECK(t, setrlimit(RLIMIT_AS, &rl) == 0, "setrlimit(RLIMIT_AS, 2 GiB) failed");
    char *out = NULL;
    int rc = run(t,
                 "lightgraph 1\nscene = test_prt_scene { layout = box, grid = 6 }\n"
                 "bake = prt_bake { scene = scene, mode = interreflected, samples = 2048, "
                 "hit_memory_mib = 1048576 }\nimg = test_transfer_image { transfer = bake }\n"
                 "output img \"t.exr\"\n",
                 &out);
    LG_TEST_CHECK(t,
                  rc == 1 && out &&
                      strstr(out, "node 'bake' (prt_bake): hit_memory_mib = "
                                  "1048576 keeps the shadowed pass's ray hits") &&
                      strstr(out, "x 2097153 directions x 20 bytes)") &&
                      strstr(out, "of address space that the process's limit (RLIMIT_AS, "
                                  "ulimit -v) leaves; lower hit_memory_mib below"),
                  "hits beyond the limit: exit %d\n%s", rc, out ? out : "");
    free(out);
    struct stat sb;
    LG_TEST_CHECK(t, stat(lg_test_path(t, "t.exr"), &sb) != 0, "t.exr was written");
    out = NULL;
    rc = run(t,
             "lightgraph 1\nscene = test_prt_scene { layout = box, grid = 6 }\n"
             "bake = prt_bake { scene = scene, samples = 2048, bands = 12 }\n"
             "img = test_transfer_image { transfer = bake, bands = 12 }\n"
             "output img \"t.exr\"\n",
             &out);
    LG_TEST_CHECK(t,
                  rc == 1 && out &&
                      strstr(out, "node 'bake' (prt_bake): samples = 2048 with "
                                  "bands = 12: the bake needs 2.3 GiB") &&
                      strstr(out, "lower samples or bands"),
                  "a direction table beyond the limit: exit %d\n%s", rc, out ? out : "");
    free(out);
    LG_TEST_CHECK(t, stat(lg_test_path(t, "t.exr"), &sb) != 0, "t.exr was written");
    tr x;
    if (bake(t, "layout = box, grid = 6", "mode = interreflected, samples = 32", 3, &x, NULL))
        tr_free(&x);
}

static int cache_entries(char *first, size_t n)
{
    const char *dir = getenv("LIGHTGRAPH_CACHE_DIR");
    DIR *d = dir ? opendir(dir) : NULL;
    int count = 0;
    if (!d)
        return 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (!strncmp(e->d_name, "prt_bake-", 9)) {
            if (count++ == 0)
                snprintf(first, n, "%s/%s", dir, e->d_name);
        }
    closedir(d);
    return count;
}

static void case_cache(lg_test *t)
{
    const char *scene = "layout = quad, grid = 4";
    const char *p = "mode = interreflected, samples = 16, bounces = 2";
    tr r[3];
    char *text[3] = { NULL, NULL, NULL };
    for (int k = 0; k < 2; k++)
        if (!bake(t, scene, p, 3, &r[k], &text[k]))
            return;
    LG_TEST_CHECK(t, strstr(text[0], "transfer baked") && !strstr(text[0], "from the cache"),
                  "first render did not bake:\n%s", text[0]);
    LG_TEST_CHECK(t,
                  strstr(text[1], "transfer loaded from the cache") &&
                      !strstr(text[1], "transfer baked"),
                  "second render did not load the cache:\n%s", text[1]);
    LG_TEST_CHECK(t, memcmp(r[0].t, r[1].t, (size_t)r[0].nv * 3 * r[0].n2 * 4) == 0,
                  "the cached transfer differs from the baked one");
    char path[1024] = "";
    int n0 = cache_entries(path, sizeof path);
    LG_TEST_CHECK(t, n0 == 1, "%d prt_bake cache entries, want 1", n0);
    /* corrupt one byte in the middle of the payload */
    FILE *f = fopen(path, "r+b");
    LG_TEST_CHECK(t, f != NULL, "cannot open the cache entry %s", path);
    if (f) {
        fseek(f, 0, SEEK_END);
        long size = ftell(f);
        fseek(f, size / 2, SEEK_SET);
        int ch = fgetc(f);
        fseek(f, size / 2, SEEK_SET);
        fputc(ch ^ 0x5a, f);
        fclose(f);
    }
    if (bake(t, scene, p, 3, &r[2], &text[2])) {
        LG_TEST_CHECK(t, strstr(text[2], "corrupt") && strstr(text[2], "transfer baked"),
                      "a corrupt entry was not reported and baked again:\n%s", text[2]);
        LG_TEST_CHECK(t, memcmp(r[0].t, r[2].t, (size_t)r[0].nv * 3 * r[0].n2 * 4) == 0,
                      "the transfer baked again differs");
        tr_free(&r[2]);
    }
    tr x;
    char *tx = NULL;
    if (bake(t, scene, "mode = interreflected, samples = 16, bounces = 3", 3, &x, &tx)) {
        LG_TEST_CHECK(t, strstr(tx, "transfer baked"), "changed bounces did not bake:\n%s", tx);
        int n1 = cache_entries(path, sizeof path);
        LG_TEST_CHECK(t, n1 == 2, "%d prt_bake cache entries after a parameter change, want 2", n1);
        tr_free(&x);
    }
    free(tx);
    for (int k = 0; k < 3; k++)
        free(text[k]);
    tr_free(&r[0]);
    tr_free(&r[1]);
}

/* The bake's log line ends in what became of the entry: "; cached" only when it was stored. */
static void case_cache_said(lg_test *t)
{
    const char *scene = "layout = quad, grid = 2";
    const char *p = "mode = unshadowed, samples = 8";
    const char *dir = getenv("LIGHTGRAPH_CACHE_DIR"); /* the case's own (lg_test_use_plugins) */
    LG_TEST_CHECK(t, dir && *dir, "LIGHTGRAPH_CACHE_DIR is not set");
    if (!dir || !*dir)
        return;
    tr r;
    char *text = NULL;
    /* a cache folder every user may write to is refused: the cache is off for the render */
    LG_TEST_CHECK(t, mkdir(dir, 0700) == 0 && chmod(dir, 0777) == 0, "cannot make %s 0777", dir);
    if (bake(t, scene, p, 3, &r, &text)) {
        LG_TEST_CHECK(t,
                      strstr(text, "cache disabled for this run") &&
                          strstr(text, "not cached: the cache is disabled for this render") &&
                          !strstr(text, "; cached"),
                      "a disabled cache:\n%s", text);
        tr_free(&r);
    }
    free(text);
    text = NULL;
    char path[1024] = "";
    LG_TEST_CHECK(t, cache_entries(path, sizeof path) == 0, "an entry was written: %s", path);
    /* a usable cache: stored, and said so */
    LG_TEST_CHECK(t, chmod(dir, 0700) == 0, "chmod %s", dir);
    if (bake(t, scene, p, 3, &r, &text)) {
        LG_TEST_CHECK(t, strstr(text, "transfer baked") && strstr(text, "; cached"),
                      "a stored entry:\n%s", text);
        tr_free(&r);
    }
    free(text);
    text = NULL;
    LG_TEST_CHECK(t, cache_entries(path, sizeof path) == 1, "no entry written");
    /* a folder with a file in the entry's place: it cannot be removed, nothing is stored */
    char keep[1100];
    snprintf(keep, sizeof keep, "%s/keep", path);
    FILE *f = NULL;
    LG_TEST_CHECK(t, remove(path) == 0 && mkdir(path, 0700) == 0 && (f = fopen(keep, "w")),
                  "cannot put a folder at %s", path);
    if (f)
        fclose(f);
    if (bake(t, scene, p, 3, &r, &text)) {
        LG_TEST_CHECK(t,
                      strstr(text, "cannot be removed") && strstr(text, "transfer baked") &&
                          strstr(text, "not cached: the host could not store it") &&
                          !strstr(text, "; cached"),
                      "an entry that cannot be stored:\n%s", text);
        tr_free(&r);
    }
    free(text);
    struct stat st;
    LG_TEST_CHECK(t, stat(keep, &st) == 0, "the folder's file is gone");
    remove(keep);
    remove(path);
}

/* Counts the occurrences of `needle` in `text`. */
static int occurrences(const char *text, const char *needle)
{
    int k = 0;
    for (const char *p = text ? strstr(text, needle) : NULL; p; p = strstr(p + 1, needle))
        k++;
    return k;
}

static void write_probe(lg_test *t, bool smooth);

/* The forged values of case_forged: what a writer of the cache could plant. */
typedef struct forgery {
    float v;
    const char *what;
} forgery;

static const forgery forgeries[] = {
    { NAN, "NaN" },
    { INFINITY, "Inf" },
    { 3e38f, "3e38" },
    /* finite, and beyond the bound: a bake's DC coefficient is at most rho Y_0 W (1 + ...)
     * (about 1.14 with 2 bounces), a reference's radiance rho L_max 2 / sqrt(3) */
    { 2.5f, "2.5" },
};

static void case_forged(lg_test *t)
{
    /* the bake: interreflected (two bounces: the widest bound) on the quad scene */
    const char *scene = "layout = quad, grid = 4";
    const char *p = "mode = interreflected, samples = 16, bounces = 2";
    tr cold;
    char *text = NULL;
    if (!bake(t, scene, p, 3, &cold, &text))
        return;
    LG_TEST_CHECK(t, strstr(text, "transfer baked") != NULL, "the cold run did not bake:\n%s",
                  text);
    free(text);
    const char *dir = getenv("LIGHTGRAPH_CACHE_DIR");
    char path[1024] = "";
    LG_TEST_CHECK(t, cache_forge_find(dir, "prt_bake-", path, sizeof path) == 1,
                  "want one prt_bake entry in %s", dir ? dir : "(unset)");
    long nf = cache_forge_floats(path, 40); /* sizeof(pb_cache_header) */
    LG_TEST_CHECK(t, nf == (long)cold.nv * 3 * 9, "entry of %ld floats, want %u", nf,
                  cold.nv * 3 * 9);
    size_t at[3] = { 0, (size_t)nf / 2, (size_t)nf - 1 };
    for (size_t f = 0; f < sizeof forgeries / sizeof forgeries[0]; f++)
        for (int a = 0; a < 3; a++) {
            /* a finite value just beyond the bound is meaningful for the DC term only */
            if (f == 3 && at[a] % 9 != 0)
                continue;
            LG_TEST_CHECK(t, cache_forge_float(path, 40, at[a], forgeries[f].v) == 0,
                          "cannot forge %s", path);
            tr again;
            if (!bake(t, scene, p, 3, &again, &text))
                return;
            char want[64];
            snprintf(want, sizeof want, "is corrupt (float %zu ", at[a]);
            LG_TEST_CHECK(t,
                          occurrences(text, "is corrupt") == 1 && strstr(text, want) &&
                              strstr(text, "transfer baked"),
                          "%s at float %zu: not reported once and baked again:\n%s",
                          forgeries[f].what, at[a], text);
            LG_TEST_CHECK(t,
                          again.nv == cold.nv &&
                              memcmp(again.t, cold.t, (size_t)cold.nv * 3 * 9 * 4) == 0,
                          "%s at float %zu: the transfer baked again differs from the cold "
                          "run",
                          forgeries[f].what, at[a]);
            free(text);
            tr_free(&again);
        }
    /* the entry made again is a good one */
    tr last;
    if (bake(t, scene, p, 3, &last, &text)) {
        LG_TEST_CHECK(t, strstr(text, "transfer loaded from the cache") && !strstr(text, "corrupt"),
                      "the remade entry was not loaded:\n%s", text);
        tr_free(&last);
    }
    free(text);
    tr_free(&cold);

    /* the reference: unshadowed sphere under the smooth probe */
    write_probe(t, true);
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\ns = test_prt_scene { layout = sphere, segments = 12, "
             "base_color = [0.8, 0.5, 0.2] }\n"
             "sky = probe { file = \"probe.exr\", layout = latlong }\n"
             "r = prt_reference { scene = s, probe = sky, mode = unshadowed, "
             "resolution = 16 }\noutput r \"ref.exr\"\n");
    int rc = run(t, g, &text);
    lg_image ref;
    LG_TEST_CHECK(t, rc == 0 && strstr(text, "reference computed"),
                  "the cold reference failed (%d):\n%s", rc, text ? text : "");
    free(text);
    if (rc != 0 || !lg_test_read(t, "ref.exr", &ref, NULL))
        return;
    LG_TEST_CHECK(t, cache_forge_find(dir, "prt_reference-", path, sizeof path) == 1,
                  "want one prt_reference entry in %s", dir);
    nf = cache_forge_floats(path, 40);
    size_t rat[3] = { 0, 4 * (size_t)(nf / 8) + 1, (size_t)nf - 2 }; /* R, G, B of three vertices */
    for (size_t f = 0; f < sizeof forgeries / sizeof forgeries[0]; f++)
        for (int a = 0; a < 3; a++) {
            LG_TEST_CHECK(t, cache_forge_float(path, 40, rat[a], forgeries[f].v) == 0,
                          "cannot forge %s", path);
            rc = run(t, g, &text);
            char want[64];
            snprintf(want, sizeof want, "is corrupt (float %zu ", rat[a]);
            LG_TEST_CHECK(t,
                          rc == 0 && occurrences(text, "is corrupt") == 1 && strstr(text, want) &&
                              strstr(text, "reference computed"),
                          "reference, %s at float %zu: not reported once and computed again "
                          "(%d):\n%s",
                          forgeries[f].what, rat[a], rc, text ? text : "");
            free(text);
            lg_image img;
            if (rc == 0 && lg_test_read(t, "ref.exr", &img, NULL)) {
                LG_TEST_CHECK(t,
                              memcmp(img.pixels, ref.pixels, (size_t)ref.width * ref.height * 16) ==
                                  0,
                              "reference, %s at float %zu: differs from the cold run",
                              forgeries[f].what, rat[a]);
                lg_image_free(&img);
            }
        }
    lg_image_free(&ref);
}

/* Writes a lat-long probe of env_L (or a constant 1). */
static void write_probe(lg_test *t, bool smooth)
{
    lg_image img = { 0 };
    uint32_t W = 128, H = 64;
    lg_image_alloc(&img, W, H);
    for (uint32_t j = 0; j < H; j++)
        for (uint32_t i = 0; i < W; i++) {
            /* lat-long convention of probe.h: phi = 2 pi (u - 1/2), theta = pi v,
             * d = (sin th sin phi, cos th, -sin th cos phi) */
            double u = (i + 0.5) / W, v = (j + 0.5) / H;
            double ph = 2 * LG_PI * (u - 0.5), th = LG_PI * v;
            double d[3] = { sin(th) * sin(ph), cos(th), -sin(th) * cos(ph) };
            double L = smooth ? env_L(d) : 1.0;
            float *p = img.pixels + 4 * ((size_t)j * W + i);
            p[0] = p[1] = p[2] = (float)L;
            p[3] = 1;
        }
    lg_test_write_exr(t, "probe.exr", &img);
    lg_image_free(&img);
}

static bool reference(lg_test *t, const char *scene, const char *params, lg_image *img)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\ns = test_prt_scene { %s }\n"
             "sky = probe { file = \"probe.exr\", layout = latlong }\n"
             "r = prt_reference { scene = s, probe = sky, %s }\n"
             "output r \"ref.exr\"\n",
             scene, params);
    char *text = NULL;
    int rc = run(t, g, &text);
    LG_TEST_CHECK(t, rc == 0, "prt_reference { %s } failed (%d):\n%s", params, rc,
                  text ? text : "");
    free(text);
    return rc == 0 && lg_test_read(t, "ref.exr", img, NULL);
}

static void case_reference(lg_test *t)
{
    /* unshadowed, smooth probe: (rho / pi) E on the sphere's vertices */
    write_probe(t, true);
    lg_image img;
    const uint32_t cols = 24, rows = 12;
    if (reference(t, "layout = sphere, segments = 24, base_color = [0.8, 0.5, 0.2]",
                  "mode = unshadowed, resolution = 32", &img)) {
        const double rho[3] = { 0.8, 0.5, 0.2 };
        double worst = 0;
        LG_TEST_CHECK(t, img.width == 1024 && img.height == 1, "vertex image %ux%u", img.width,
                      img.height);
        for (uint32_t j = 0, v = 0; j <= rows; j++)
            for (uint32_t i = 0; i <= cols; i++, v++) {
                double th = LG_PI * j / rows, ph = 2 * LG_PI * i / cols;
                double N[3] = { sin(th) * cos(ph), cos(th), -sin(th) * sin(ph) };
                for (int c = 0; c < 3; c++)
                    worst = fmax(worst, fabs(img.pixels[4 * v + c] - rho[c] / LG_PI * env_E(N)));
                LG_TEST_CHECK(t, img.pixels[4 * v + 3] == 1.0f, "vertex %u: alpha %g", v,
                              (double)img.pixels[4 * v + 3]);
            }
        uint32_t nv = (cols + 1) * (rows + 1);
        LG_TEST_CHECK(t, img.pixels[4 * nv + 3] == 0.0f, "padding texel %u not 0", nv);
        fprintf(stderr, "reference, unshadowed: worst |r - (rho/pi) E| = %.2e\n", worst);
        LG_TEST_CHECK(t, worst < 3e-3, "unshadowed reference off by %.3g", worst);
        /* cached like the bake: the same graph again loads it, bit for bit */
        char g[1024];
        snprintf(g, sizeof g,
                 "lightgraph 1\ns = test_prt_scene { layout = sphere, segments = 24, "
                 "base_color = [0.8, 0.5, 0.2] }\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "r = prt_reference { scene = s, probe = sky, mode = unshadowed, "
                 "resolution = 32 }\noutput r \"ref2.exr\"\n");
        char *text = NULL;
        int rc = run(t, g, &text);
        lg_image again;
        LG_TEST_CHECK(t, rc == 0 && text && strstr(text, "reference loaded from the cache"),
                      "second reference render did not load the cache (%d):\n%s", rc,
                      text ? text : "");
        if (rc == 0 && lg_test_read(t, "ref2.exr", &again, NULL)) {
            LG_TEST_CHECK(t,
                          memcmp(again.pixels, img.pixels, (size_t)img.width * img.height * 16) ==
                              0,
                          "the cached reference differs");
            lg_image_free(&again);
        }
        free(text);
        lg_image_free(&img);
    }

    /* shadowed cone under a constant probe */
    write_probe(t, false);
    if (reference(t, "layout = cone, alpha_deg = 45, segments = 256",
                  "mode = shadowed, resolution = 64", &img)) {
        double got = img.pixels[1], want = 0.5;
        fprintf(stderr, "reference, cone 45 degrees: %.5f, sin^2 alpha %.5f\n", got, want);
        LG_TEST_CHECK(t, fabs(got - want) < 0.01, "cone reference %.5f, want %.5f", got, want);
        lg_image_free(&img);
    }

    /* the bake approaches the reference as samples grow (L has bands <= 2 only, so the
     * transfer's truncation costs nothing: only the sampling error is left) */
    write_probe(t, true);
    const char *scene = "layout = quad, grid = 6, quad_size = 0.7";
    if (!reference(t, scene, "mode = shadowed, resolution = 64", &img))
        return;
    double L[9];
    env_coeffs(3, L);
    double prev = INFINITY;
    static const int samples[] = { 8, 32, 128 };
    for (int s = 0; s < 3; s++) {
        char p[128];
        snprintf(p, sizeof p, "mode = shadowed, samples = %d", samples[s]);
        tr x;
        if (!bake(t, scene, p, 3, &x, NULL))
            break;
        double se = 0, sr = 0;
        for (uint32_t i = 0; i < x.nv; i++) {
            double r = img.pixels[4 * i + 1], b = radiance(&x, i, 1, L);
            se += (b - r) * (b - r);
            sr += r * r;
        }
        double rel = sqrt(se / sr);
        fprintf(stderr, "bake (%d^2 sobol directions) vs reference: relative RMSE %.2e\n",
                samples[s], rel);
        LG_TEST_CHECK(t, rel < prev * 1.05, "samples %d: RMSE %.3g did not fall (%.3g)", samples[s],
                      rel, prev);
        if (samples[s] == 128)
            LG_TEST_CHECK(t, rel < 0.01, "samples 128: relative RMSE %.3g", rel);
        prev = rel;
        tr_free(&x);
    }
    lg_image_free(&img);
}

/* prt_reference of `scene` under a test_raw_probe { probe } into `file`: the exit status,
 * the output in *text (the caller frees it) and the image in *img when it rendered. */
static int raw_reference(lg_test *t, const char *scene, const char *probe, const char *params,
                         const char *file, lg_image *img, char **text)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\ns = test_prt_scene { %s }\n"
             "sky = test_raw_probe { %s }\n"
             "r = prt_reference { scene = s, probe = sky, %s }\n"
             "output r \"%s\"\n",
             scene, probe, params, file);
    int rc = run(t, g, text);
    LG_TEST_CHECK(t, rc == 0, "prt_reference under test_raw_probe { %s } failed (%d):\n%s", probe,
                  rc, *text ? *text : "");
    if (rc == 0 && !lg_test_read(t, file, img, NULL))
        rc = -1;
    return rc;
}

/* The vertices' floats of img (nv vertices) that are NaN or infinite. */
static uint32_t nonfinite_floats(const lg_image *img, uint32_t nv)
{
    uint32_t bad = 0;
    for (size_t i = 0; i < (size_t)nv * 4; i++)
        bad += !isfinite(img->pixels[i]);
    return bad;
}

static void case_nonfinite(lg_test *t)
{
    /* one texel of a constant probe set to NaN, +Inf or -Inf (the producer test_raw_probe
     * does not clean it, as `probe` would): the integral leaves it out, so the result is
     * the one of the same probe with that texel 0, bit for bit, every float finite, and
     * the node says it once, naming the count and the texel. Before: every vertex that
     * saw the texel was NaN (Inf). A lat-long probe (unshadowed sphere: every direction
     * is seen by some vertex) and a cube (shadowed quad scene, the texel on face 2, +Y,
     * above the floor). */
    static const struct {
        const char *scene, *probe, *params, *where;
        uint32_t nv;
    } setups[] = {
        { "layout = sphere, segments = 12", "width = 32, bad_x = 10, bad_y = 5",
          "mode = unshadowed, resolution = 16",
          "input 'probe' (32x16): 1 pixel with a NaN or Inf channel, left out of the "
          "integral (those channels count as radiance 0); the first at texel (10, 5) "
          "(reported once)",
          13 * 7 },
        { "layout = quad, grid = 4", "width = 8, cube = true, bad_face = 2, bad_x = 3, bad_y = 4",
          "mode = shadowed, resolution = 8",
          "input 'probe' (8x8 per cube face): 1 pixel with a NaN or Inf channel, left out "
          "of the integral (those channels count as radiance 0); the first at texel (3, 4) "
          "of face 2 (reported once)",
          25 + 4 },
    };
    static const char *const bad[] = { "nan", "inf", "neg_inf" };
    for (size_t k = 0; k < sizeof setups / sizeof setups[0]; k++) {
        char probe[256];
        char *text = NULL;
        lg_image zero, none;
        snprintf(probe, sizeof probe, "%s, bad = zero", setups[k].probe);
        if (raw_reference(t, setups[k].scene, probe, setups[k].params, "zero.exr", &zero, &text) !=
            0) {
            free(text);
            continue;
        }
        LG_TEST_CHECK(t, !strstr(text, "NaN or Inf"), "a finite probe was said to hold NaN:\n%s",
                      text);
        free(text);
        text = NULL;
        /* the texel matters: without it (the constant everywhere) some vertex differs */
        snprintf(probe, sizeof probe, "%s, bad = none", setups[k].probe);
        if (raw_reference(t, setups[k].scene, probe, setups[k].params, "none.exr", &none, &text) ==
            0) {
            uint32_t differ = 0;
            for (uint32_t i = 0; i < setups[k].nv * 4; i++)
                differ += none.pixels[i] != zero.pixels[i];
            LG_TEST_CHECK(t, differ > 0,
                          "%s: zeroing the texel changed no vertex (a test "
                          "that cannot see the texel)",
                          setups[k].probe);
            lg_image_free(&none);
        }
        free(text);
        for (int b = 0; b < 3; b++) {
            snprintf(probe, sizeof probe, "%s, bad = %s", setups[k].probe, bad[b]);
            /* twice: computed, then loaded from the cache (said the same way) */
            for (int pass = 0; pass < 2; pass++) {
                lg_image img;
                text = NULL;
                if (raw_reference(t, setups[k].scene, probe, setups[k].params, "bad.exr", &img,
                                  &text) != 0) {
                    free(text);
                    break;
                }
                const char *how = pass ? "reference loaded from the cache" : "reference computed";
                LG_TEST_CHECK(t, strstr(text, how) != NULL, "%s (run %d): '%s' not said:\n%s",
                              probe, pass + 1, how, text);
                LG_TEST_CHECK(t, occurrences(text, setups[k].where) == 1,
                              "%s (run %d): want the warning once:\n  %s\noutput:\n%s", probe,
                              pass + 1, setups[k].where, text);
                uint32_t nf = nonfinite_floats(&img, setups[k].nv);
                LG_TEST_CHECK(t, nf == 0,
                              "%s (run %d): %u of the %u vertices' floats are NaN "
                              "or infinite",
                              probe, pass + 1, nf, setups[k].nv * 4);
                LG_TEST_CHECK(t,
                              img.width == zero.width && img.height == zero.height &&
                                  memcmp(img.pixels, zero.pixels,
                                         (size_t)img.width * img.height * 16) == 0,
                              "%s (run %d): not the result of the texel set to 0 (vertex 0 "
                              "R %g, want %g)",
                              probe, pass + 1, (double)img.pixels[0], (double)zero.pixels[0]);
                lg_image_free(&img);
                free(text);
            }
        }
        lg_image_free(&zero);
    }
}

/* The radiance of vertex i, channel c, from a per-vertex image (transfer.h's layout). */
static double vertex_value(const lg_image *img, uint32_t i, int c)
{
    return img->pixels[4 * ((size_t)(i / LG_VERTEX_IMAGE_WIDTH) * img->width +
                            i % LG_VERTEX_IMAGE_WIDTH) +
                       c];
}

/* sh_project -> prt_bake -> prt on `backend`, the `vertices` output read into *img. */
static bool chain(lg_test *t, const char *scene, const char *bakep, uint32_t bands,
                  const char *backend, lg_image *img)
{
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_prt_scene { %s }\n"
             "sky = probe { file = \"probe.exr\", layout = latlong }\n"
             "light = sh_project { probe = sky, bands = %u }\n"
             "b = prt_bake { scene = s, bands = %u, %s }\n"
             "lit = prt { scene = s, lighting = light, transfer = b, backend = %s }\n"
             "output lit.vertices \"v.exr\"\n",
             scene, bands, bands, bakep, backend);
    char *text = NULL;
    int rc = run(t, g, &text);
    if (rc != 0 && lg_test_output_says_no_device(text ? text : ""))
        LG_TEST_CHECK(t, 0, "backend %s: no device (a missing device is a failure):\n%s", backend,
                      text ? text : "");
    else
        LG_TEST_CHECK(t, rc == 0, "chain { %s } { %s } on %s failed (%d):\n%s", scene, bakep,
                      backend, rc, text ? text : "");
    free(text);
    return rc == 0 && lg_test_read(t, "v.exr", img, NULL);
}

static void case_chain(lg_test *t)
{
    static const char *const backends[] = { "cpu", "gl", "cl" };
    /* constant sky 1: the cone's apex and the furnace */
    write_probe(t, false);
    for (int b = 0; b < 3; b++) {
        lg_image img;
        if (!chain(t, "layout = cone, alpha_deg = 45, segments = 128, base_color = [0.9, 0.6, 0.3]",
                   "mode = shadowed, samples = 128", 3, backends[b], &img))
            return;
        double rho[3] = { 0.9, 0.6, 0.3 };
        for (int c = 0; c < 3; c++) {
            double got = vertex_value(&img, 0, c), want = rho[c] * 0.5;
            if (c == 0)
                fprintf(stderr, "chain %s: cone apex %.5f, rho sin^2 45 = %.5f\n", backends[b], got,
                        want);
            LG_TEST_CHECK(t, fabs(got - want) < 0.006, "%s: cone apex channel %d %.5f, want %.5f",
                          backends[b], c, got, want);
        }
        lg_image_free(&img);
        if (!chain(t, "layout = box, grid = 6",
                   "mode = interreflected, samples = 32, bounces = 32, bounce_threshold = 0", 3,
                   backends[b], &img))
            return;
        uint32_t nv = 5 * 7 * 7; /* five walls of (grid + 1)^2 vertices */
        double sum = 0;
        for (uint32_t i = 0; i < nv; i++)
            sum += vertex_value(&img, i, 1);
        LG_TEST_CHECK(t, img.pixels[4 * nv + 3] == 0.0f && img.pixels[4 * (nv - 1) + 3] == 1.0f,
                      "%s: the box should have %u vertices", backends[b], nv);
        fprintf(stderr, "chain %s: furnace, 32 bounces: mean radiance %.4f\n", backends[b],
                sum / nv);
        LG_TEST_CHECK(t, fabs(1 - sum / nv) < 0.01, "%s: furnace mean %.4f, want 1 within 0.01",
                      backends[b], sum / nv);
        lg_image_free(&img);
    }
    /* the smooth probe, unshadowed sphere: (rho / pi) E(N), 3 bands hold it exactly */
    write_probe(t, true);
    lg_image ref = { 0 };
    for (int b = 0; b < 3; b++) {
        lg_image img;
        if (!chain(t, "layout = sphere, segments = 16, base_color = [0.8, 0.8, 0.8]",
                   "mode = unshadowed, samples = 64", 3, backends[b], &img))
            return;
        uint32_t seg = 16, rows = seg / 2, nv = (seg + 1) * (rows + 1);
        double worst = 0;
        for (uint32_t j = 0; j <= rows; j++)
            for (uint32_t i = 0; i <= seg; i++) {
                double th = LG_PI * j / rows, ph = 2 * LG_PI * i / seg;
                double N[3] = { sin(th) * cos(ph), cos(th), -sin(th) * sin(ph) };
                double want = 0.8 / LG_PI * env_E(N);
                worst = fmax(worst, fabs(vertex_value(&img, j * (seg + 1) + i, 0) - want));
            }
        fprintf(stderr, "chain %s: unshadowed sphere, worst |radiance - (rho/pi) E| %.2e\n",
                backends[b], worst);
        LG_TEST_CHECK(t, worst < 3e-3, "%s: unshadowed sphere off by %.3g", backends[b], worst);
        if (b == 0) {
            ref = img;
            continue;
        }
        double diff = 0;
        for (uint32_t i = 0; i < nv; i++)
            for (int c = 0; c < 3; c++)
                diff = fmax(diff, fabs(vertex_value(&img, i, c) - vertex_value(&ref, i, c)));
        LG_TEST_CHECK(t, diff < 1e-5, "%s against cpu: %.3g", backends[b], diff);
        lg_image_free(&img);
    }
    lg_image_free(&ref);
}

/* ---- alpha masks ----------------------------------------------------------------------------- */

/* The analytic visibility of the masked layout (testprtscene.c) from floor vertex p along
 * d (d[1] > 0): 1 clear, 0 blocked, -1 within `margin` of a cell edge or the square's edge
 * (either answer is right for a float ray). `phase` < 0: an opaque square; `cells` 0: no
 * square. */
static int masked_vis(const double p[3], const double d[3], double a, uint32_t cells, int phase)
{
    const double margin = 1e-4;
    double t = (1.0 - p[1]) / d[1], x = p[0] + t * d[0], z = p[2] + t * d[2];
    if (cells == 0)
        return 1;
    double ex = a - fabs(x), ez = a - fabs(z);
    if (fabs(ex) < margin || fabs(ez) < margin)
        return -1;
    if (ex < 0 || ez < 0)
        return 1;
    if (phase < 0)
        return 0;
    double u = (x + a) / (2 * a) * cells, v = (a - z) / (2 * a) * cells;
    double fu = u - floor(u), fv = v - floor(v), m = margin * cells / (2 * a);
    if (fu < m || fu > 1 - m || fv < m || fv > 1 - m)
        return -1;
    long cell = (long)floor(u) + (long)floor(v) + phase;
    return cell % 2 == 0 ? 0 : 1;
}

/* Every floor vertex's t_0 (channel R) of `x` held to the analytic bounds of masked_vis
 * over the bake's directions (sobol, `samples`, seed 0) on a g x g floor; returns how many
 * vertices lie under the square and saw both clear and blocked directions (the test's
 * teeth: the pattern is really probed). */
static uint32_t masked_check(lg_test *t, const tr *x, uint32_t g, uint32_t samples, double a,
                             uint32_t cells, int phase, const char *what)
{
    uint32_t T = samples * samples, mixed = 0;
    double y00 = 0.5 / sqrt(LG_PI);
    for (uint32_t j = 0; j <= g; j++)
        for (uint32_t i = 0; i <= g; i++) {
            uint32_t vi = j * (g + 1) + i;
            double p[3] = { -2 + 4.0 * i / g, 0, 2 - 4.0 * j / g }, lo = 0, amb = 0;
            uint32_t clear = 0, blocked = 0;
            for (uint32_t k = 0; k < T; k++) {
                double uv[2], d[3];
                lg_sample_square(LG_SAMPLER_SOBOL, samples, 0, k, uv);
                lg_sample_sphere(uv, d);
                if (!(d[1] > 0))
                    continue;
                int v = masked_vis(p, d, a, cells, phase);
                if (v == 1)
                    lo += d[1], clear++;
                else if (v < 0)
                    amb += d[1];
                else
                    blocked++;
            }
            double f = 4.0 / T * y00, got = x->t[(size_t)vi * 3 * x->n2];
            double lo_t = f * lo, hi_t = f * (lo + amb), tol = 1e-5 * f * T;
            LG_TEST_CHECK(t, got >= lo_t - tol && got <= hi_t + tol,
                          "%s: floor vertex %u (%g, 0, %g): t_0 = %.7g, the analytic mask gives "
                          "[%.7g, %.7g]",
                          what, vi, p[0], p[2], got, lo_t, hi_t);
            mixed += clear > 0 && blocked > 0 && fabs(p[0]) < a && fabs(p[2]) < a;
        }
    return mixed;
}

/* prt_reference shadowed on the masked layout under a constant cube probe (radiance 1):
 * each floor vertex's exit radiance within the analytic quadrature's bounds over the same
 * cube texels (lg_probe_texel_dir, lg_probe_solid_angles): r = (1 / pi) sum_t V sa_t
 * max(N.w_t, 0), white albedo. */
static void masked_reference(lg_test *t, uint32_t g, double a, uint32_t cells, int phase,
                             const char *scene)
{
    const uint32_t R = 16;
    lg_image img;
    char *txt = NULL, params[64];
    snprintf(params, sizeof params, "mode = shadowed, resolution = %u", R);
    int rc = raw_reference(t, scene, "width = 16, cube = true, value = 1", params, "r.exr", &img,
                           &txt);
    free(txt);
    if (rc != 0)
        return;
    float *sa = malloc((size_t)6 * R * R * sizeof(float));
    if (!sa || lg_probe_solid_angles(LG_PROBE_CUBE, R, R, sa) != 0) {
        LG_TEST_CHECK(t, false, "solid angles of a cube of face %u", R);
        free(sa);
        lg_image_free(&img);
        return;
    }
    uint32_t mixed = 0;
    for (uint32_t j = 0; j <= g; j++)
        for (uint32_t i = 0; i <= g; i++) {
            uint32_t vi = j * (g + 1) + i, clear = 0, blocked = 0;
            double p[3] = { -2 + 4.0 * i / g, 0, 2 - 4.0 * j / g }, lo = 0, amb = 0;
            for (uint32_t f = 0, k = 0; f < 6; f++)
                for (uint32_t y = 0; y < R; y++)
                    for (uint32_t x = 0; x < R; x++, k++) {
                        lg_vec3 dv = lg_probe_texel_dir(LG_PROBE_CUBE, R, R, f, x, y);
                        double l =
                            sqrt((double)dv.x * dv.x + (double)dv.y * dv.y + (double)dv.z * dv.z);
                        double d[3] = { dv.x / l, dv.y / l, dv.z / l };
                        if (!(d[1] > 0))
                            continue;
                        int v = masked_vis(p, d, a, cells, phase);
                        double wgt = d[1] * sa[k] / LG_PI;
                        if (v == 1)
                            lo += wgt, clear++;
                        else if (v < 0)
                            amb += wgt;
                        else
                            blocked++;
                    }
            double got = img.pixels[4 * (size_t)vi], tol = 1e-4;
            LG_TEST_CHECK(t, got >= lo - tol && got <= lo + amb + tol,
                          "prt_reference, %s: floor vertex %u (%g, 0, %g): %.6g, the analytic "
                          "mask gives [%.6g, %.6g]",
                          scene, vi, p[0], p[2], got, lo, lo + amb);
            mixed += clear > 0 && blocked > 0 && fabs(p[0]) < a && fabs(p[2]) < a;
        }
    LG_TEST_CHECK(t, cells == 0 || mixed >= 9,
                  "prt_reference, %s: only %u vertices under the square saw both opaque and "
                  "clear texels",
                  scene, mixed);
    free(sa);
    lg_image_free(&img);
}

static void case_masked(lg_test *t)
{
    const uint32_t g = 8, samples = 32, bands = 2, cells = 4;
    const double a = 1.0;
    char sc[256];
    tr m[2], bl, br, op, pl, nt, gone;
    for (int ph = 0; ph < 2; ph++) {
        snprintf(sc, sizeof sc,
                 "layout = masked, grid = %u, quad_size = %g, mask = checker, mask_cells = %u, "
                 "mask_phase = %d",
                 g, a, cells, ph);
        if (!bake(t, sc, "mode = shadowed, samples = 32", bands, &m[ph], NULL))
            return;
        uint32_t mixed = masked_check(t, &m[ph], g, samples, a, cells, ph, "checker (embree)");
        LG_TEST_CHECK(t, mixed >= 9,
                      "phase %d: only %u vertices under the square saw both "
                      "opaque and clear directions",
                      ph, mixed);
    }
    snprintf(sc, sizeof sc,
             "layout = masked, grid = %u, quad_size = %g, mask = checker, mask_cells = %u", g, a,
             cells);
    if (bake(t, sc, "mode = shadowed, samples = 32, visibility = brute", bands, &br, NULL)) {
        masked_check(t, &br, g, samples, a, cells, 0, "checker (brute)");
        tr_free(&br);
    }
    snprintf(sc, sizeof sc,
             "layout = masked, grid = %u, quad_size = %g, mask = blend, mask_cells = %u", g, a,
             cells);
    if (bake(t, sc, "mode = shadowed, samples = 32", bands, &bl, NULL)) {
        masked_check(t, &bl, g, samples, a, cells, 0, "blend (a mask at its cutoff)");
        tr_free(&bl);
    }
    snprintf(sc, sizeof sc, "layout = masked, grid = %u, quad_size = %g, mask = none", g, a);
    bool ok = bake(t, sc, "mode = shadowed, samples = 32", bands, &op, NULL);
    if (ok)
        masked_check(t, &op, g, samples, a, cells, -1, "opaque square");
    snprintf(sc, sizeof sc, "layout = masked, grid = %u, quad_size = %g, mask = no_texcoords", g,
             a);
    if (ok && bake(t, sc, "mode = shadowed, samples = 32", bands, &nt, NULL)) {
        /* the mask cannot be read: opaque, the unmasked square's bits */
        LG_TEST_CHECK(t, nt.nv == op.nv && memcmp(nt.t, op.t, (size_t)op.nv * 3 * op.n2 * 4) == 0,
                      "a mask without texture coordinates: not the opaque square's bake");
        tr_free(&nt);
    }
    snprintf(sc, sizeof sc,
             "layout = masked, grid = %u, quad_size = %g, mask = checker, quad_alpha = 0.4", g, a);
    bool ok2 = bake(t, sc, "mode = shadowed, samples = 32", bands, &gone, NULL);
    snprintf(sc, sizeof sc, "layout = plane, grid = %u", g);
    if (ok2 && bake(t, sc, "mode = shadowed, samples = 32", bands, &pl, NULL)) {
        /* alpha 0.4 x texel alpha <= 0.4 < 0.5 everywhere: no square at all; the floor's
         * vertices come first in both scenes */
        uint32_t nf = (g + 1) * (g + 1);
        LG_TEST_CHECK(t, memcmp(gone.t, pl.t, (size_t)nf * 3 * pl.n2 * 4) == 0,
                      "a square whose factor alpha is below the cutoff still shadows the floor");
        masked_check(t, &pl, g, samples, a, 0, 0, "plane");
        /* complementary checkers: clear(0) + clear(1) = clear(plane) + clear(opaque) */
        double worst = 0;
        for (uint32_t v = 0; ok && v < nf; v++) {
            size_t q = (size_t)v * 3 * pl.n2;
            double d = (double)m[0].t[q] + m[1].t[q] - pl.t[q] - op.t[q];
            worst = fmax(worst, fabs(d));
        }
        fprintf(stderr, "masked: |t0(phase 0) + t0(phase 1) - t0(plane) - t0(opaque)| <= %.3g\n",
                worst);
        LG_TEST_CHECK(t, worst < 0.02 * pl.t[0],
                      "the two checker phases do not add up to the plane and the opaque "
                      "square (%.3g)",
                      worst);
        tr_free(&pl);
    }
    if (ok2)
        tr_free(&gone);
    if (ok)
        tr_free(&op);
    tr_free(&m[0]);
    tr_free(&m[1]);

    /* bounces off a textured surface: the square turned to face the floor, opaque, a
     * checker of white and black texels; the light it bounces onto the floor is the white
     * square's on the white cells only: about half, never more (the texture sampled at each
     * hit; a bake that ignored the texture would bounce all of it) */
    {
        tr sh, wh, ck;
        const char *bp = "mode = interreflected, samples = 32, bounces = 1";
        snprintf(sc, sizeof sc, "layout = masked, grid = %u, quad_flip = true, mask = none", g);
        bool ok3 = bake(t, sc, "mode = shadowed, samples = 32", bands, &sh, NULL);
        bool ok4 = ok3 && bake(t, sc, bp, bands, &wh, NULL);
        snprintf(sc, sizeof sc,
                 "layout = masked, grid = %u, quad_flip = true, mask = colour, mask_cells = %u", g,
                 cells);
        bool ok5 = ok4 && bake(t, sc, bp, bands, &ck, NULL);
        if (ok5) {
            double sw = 0, sk = 0;
            uint32_t nf = (g + 1) * (g + 1);
            for (uint32_t v = 0; v < nf; v++) {
                size_t q = (size_t)v * 3 * sh.n2;
                double iw = (double)wh.t[q] - sh.t[q], ik = (double)ck.t[q] - sh.t[q];
                LG_TEST_CHECK(t, ik <= iw + 1e-6 && ik >= -1e-6,
                              "floor vertex %u: the checker square bounces %.6g, the white one "
                              "%.6g",
                              v, ik, iw);
                sw += iw, sk += ik;
            }
            fprintf(stderr,
                    "masked: a white/black checker bounces %.4f of the white square's "
                    "light onto the floor\n",
                    sk / sw);
            LG_TEST_CHECK(
                t,
                sw > 0 && sk / sw > 0.35 &&
                        sk /
                            sw<0.65,
                               "the checker bounces %.4f of the white square's light, want about 0.5",
                               sw> 0
                    ? sk / sw
                    : -1.0);
        }
        if (ok5)
            tr_free(&ck);
        if (ok4)
            tr_free(&wh);
        if (ok3)
            tr_free(&sh);
    }

    /* prt_reference: the same mask through its shadow rays (both phases, the blinds-like
     * 8-cell checker) */
    for (int ph = 0; ph < 2; ph++) {
        snprintf(sc, sizeof sc,
                 "layout = masked, grid = %u, quad_size = %g, mask = checker, mask_cells = 8, "
                 "mask_phase = %d",
                 g, a, ph);
        masked_reference(t, g, a, 8, ph, sc);
    }

    /* the cache key (prt_bake is LG_NODE_CACHE_BY_CONTENT): the checker's RGB changed (the
     * scene node's identity changes with its parameters) loads the shadowed bake; the mask
     * changed (its phase) bakes again; interreflected reads the texture at its bounces, so
     * an RGB change bakes it again */
    static const struct {
        const char *scene, *bake, *want;
    } steps[] = {
        { "mask_phase = 0, texture_rgb = [1, 1, 1]", "mode = shadowed", "transfer baked" },
        { "mask_phase = 0, texture_rgb = [0.2, 0.5, 0.9]", "mode = shadowed",
          "transfer loaded from the cache" },
        { "mask_phase = 1, texture_rgb = [0.2, 0.5, 0.9]", "mode = shadowed", "transfer baked" },
        { "mask_phase = 0, texture_rgb = [1, 1, 1]", "mode = interreflected", "transfer baked" },
        { "mask_phase = 0, texture_rgb = [0.2, 0.5, 0.9]", "mode = interreflected",
          "transfer baked" },
        { "mask_phase = 0, texture_rgb = [0.2, 0.5, 0.9]", "mode = interreflected",
          "transfer loaded from the cache" },
    };
    for (size_t k = 0; k < sizeof steps / sizeof steps[0]; k++) {
        char bp[128], *txt = NULL;
        tr y;
        snprintf(sc, sizeof sc, "layout = masked, grid = 4, mask = checker, %s", steps[k].scene);
        snprintf(bp, sizeof bp, "%s, samples = 8", steps[k].bake);
        if (bake(t, sc, bp, bands, &y, &txt)) {
            LG_TEST_CHECK(t, txt && strstr(txt, steps[k].want),
                          "step %zu: { %s } with { %s }: want '%s' in:\n%s", k, sc, bp,
                          steps[k].want, txt ? txt : "");
            tr_free(&y);
        }
        free(txt);
    }
}

/* ---- threads and ranks: the same bits -------------------------------------------------------- */

/* A whole file, malloc'd (*size its bytes), or NULL. */
static char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = NULL;
    size_t n = 0, cap = 0;
    for (;;) {
        if (n == cap) {
            cap = cap ? 2 * cap : 65536;
            char *g = realloc(buf, cap);
            if (!g)
                break;
            buf = g;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    fclose(f);
    *size = n;
    return buf;
}

/* Files `a` and `b` (paths) hold the same bytes; a failed check naming `what` otherwise. */
static bool same_file(lg_test *t, const char *a, const char *b, const char *what)
{
    size_t na = 0, nb = 0;
    char *x = read_all(a, &na), *y = read_all(b, &nb);
    bool ok = x && y && na == nb && memcmp(x, y, na) == 0;
    size_t at = 0;
    while (x && y && at < na && at < nb && x[at] == y[at])
        at++;
    LG_TEST_CHECK(t, ok, "%s: %s (%zu bytes) and %s (%zu bytes) differ%s%zu", what, a, na, b, nb,
                  x && y ? " from byte " : ": missing, at ", at);
    free(x);
    free(y);
    return ok;
}

static int name_cmp(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The cache entries of the prt_bake plugin (files "prt_bake-*", "prt_reference-*") in folder `dir`, sorted;
 * returns their count (at most `max`), names malloc'd into names[]. */
static int entries_in(const char *dir, char **names, int max)
{
    DIR *d = opendir(dir);
    int count = 0;
    if (!d)
        return 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if ((!strncmp(e->d_name, "prt_bake-", 9) || !strncmp(e->d_name, "prt_reference-", 14)) &&
            count < max)
            names[count++] = strdup(e->d_name);
    closedir(d);
    qsort(names, (size_t)count, sizeof *names, name_cmp);
    return count;
}

/* The two cache folders hold the same prt_bake entries (names and bytes), `want` of them. */
static void same_entries(lg_test *t, const char *da, const char *db, int want, const char *what)
{
    char *a[8], *b[8];
    int na = entries_in(da, a, 8), nb = entries_in(db, b, 8);
    LG_TEST_CHECK(t, na == want && nb == want, "%s: %d and %d cache entries, want %d each", what,
                  na, nb, want);
    for (int k = 0; k < na && k < nb; k++) {
        LG_TEST_CHECK(t, strcmp(a[k], b[k]) == 0, "%s: entry %s against %s", what, a[k], b[k]);
        char pa[1024], pb[1024], w[256];
        snprintf(pa, sizeof pa, "%s/%s", da, a[k]);
        snprintf(pb, sizeof pb, "%s/%s", db, b[k]);
        snprintf(w, sizeof w, "%s: cache entry %s", what, a[k]);
        same_file(t, pa, pb, w);
    }
    for (int k = 0; k < na; k++)
        free(a[k]);
    for (int k = 0; k < nb; k++)
        free(b[k]);
}

/* The graphs whose bits must not depend on threads or ranks: the bunny in the Cornell box
 * (2628 vertices, the bunny's costlier rays next to the walls' cheap ones) baked
 * interreflected (the direct pass and each bounce are jobs of their own) and shadowed, the
 * bake's transfer written whole (test_transfer_image); prt_reference shadowed under a
 * smooth probe (write_probe); and, with `chain`, the chain of examples/prt.lgraph on the bake (sh_project,
 * prt on the cpu, reinhard) to a picture. `extra` is appended to the bake's parameters. */
static void same_bits_graph(lg_test *t, bool chain, const char *extra)
{
    char g[4096], mesh[1024];
    snprintf(mesh, sizeof mesh, "%s", lg_test_asset("meshes/bunny_cornell_box.glb"));
    int k = snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "scene = gltf { file = \"%s\" }\n"
                     "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                     "bake = prt_bake { scene = scene, mode = interreflected, bands = 3, "
                     "samples = 16, bounces = 2, bounce_threshold = 0%s }\n"
                     "shad = prt_bake { scene = scene, mode = shadowed, bands = 2, "
                     "samples = 12 }\n"
                     "tb = test_transfer_image { transfer = bake, bands = 3 }\n"
                     "ts = test_transfer_image { transfer = shad, bands = 2 }\n"
                     "ref = prt_reference { scene = scene, probe = sky, mode = shadowed, "
                     "resolution = 8 }\n"
                     "output tb \"bake.exr\"\noutput ts \"shad.exr\"\noutput ref \"ref.exr\"\n",
                     mesh, extra);
    write_probe(t, true);
    if (chain)
        snprintf(g + k, sizeof g - (size_t)k,
                 "cam = camera { scene = scene, mode = look_at, position = [0.0, 1.0, -3.4], "
                 "target = [0.0, 0.9, 0.0], fov_deg = 45 }\n"
                 "light = sh_project { probe = sky, bands = 3 }\n"
                 "lit = prt { scene = cam, lighting = light, transfer = bake, backend = cpu }\n"
                 "tone = reinhard { image = lit }\n"
                 "output tone \"prt.png\"\n");
    lg_test_write_text(t, "g.lgraph", g);
}

/* Runs g.lgraph (render -v, --size 96x72) with the cache in <scratch>/<cache> (emptied
 * first when `cold`) and LIGHTGRAPH_THREADS = threads, as `np` MPI ranks through
 * tests/dist/mpirun.sh when np > 0 (else one plain process), then moves every output to
 * <name>.<output>. Returns the exit status; *text gets what it printed. */
static int same_bits_run(lg_test *t, int np, int threads, const char *cache, bool cold,
                         const char *name, char **text)
{
    char dir[1024], cmd[4096], th[16];
    snprintf(dir, sizeof dir, "%s", lg_test_path(t, cache));
    snprintf(cmd, sizeof cmd, cold ? "rm -rf '%s' && mkdir -p '%s'" : "mkdir -p '%s'", dir, dir);
    if (system(cmd) != 0)
        return -1;
    setenv("LIGHTGRAPH_CACHE_DIR", dir, 1);
    snprintf(th, sizeof th, "%d", threads);
    setenv("LIGHTGRAPH_THREADS", th, 1);
    int rc = -1;
    if (np == 0) {
        const char *args[] = { "-v", "--size", "96x72", NULL };
        rc = lg_test_render(t, "g.lgraph", args, text);
    } else {
        snprintf(cmd, sizeof cmd,
                 "cd '%s' && sh '%s' %d '%s' render g.lgraph -v --size 96x72 2>&1 </dev/null",
                 lg_test_dir(t), PRT_MPIRUN, np, lg_test_exe());
        FILE *p = popen(cmd, "r");
        size_t n = 0, cap = 4096, got;
        char *out = malloc(cap);
        while (out && p && (got = fread(out + n, 1, cap - n - 1, p)) > 0)
            if ((n += got) + 1 == cap) {
                char *g = realloc(out, cap *= 2);
                if (!g)
                    break;
                out = g;
            }
        if (out)
            out[n] = 0;
        int st = p ? pclose(p) : -1;
        if (st != -1 && WIFEXITED(st))
            rc = WEXITSTATUS(st);
        if (rc != 0)
            fprintf(stderr, "$ %s\nexit %d\n%s\n", cmd, rc, out ? out : "");
        if (text)
            *text = out;
        else
            free(out);
    }
    unsetenv("LIGHTGRAPH_THREADS");
    static const char *const outs[] = { "bake.exr", "shad.exr", "ref.exr", "prt.png" };
    for (int k = 0; k < 4; k++) {
        char to[64], from[1024];
        snprintf(to, sizeof to, "%s.%s", name, outs[k]);
        snprintf(from, sizeof from, "%s", lg_test_path(t, outs[k]));
        rename(from, lg_test_path(t, to));
    }
    return rc;
}

/* The outputs of runs `a` and `b` (same_bits_run's names) and, with `caches`, their cache
 * folders (of the same names) agree byte for byte. */
static void same_bits_compare(lg_test *t, const char *a, const char *b, bool chain, bool caches,
                              const char *what)
{
    static const char *const outs[] = { "bake.exr", "shad.exr", "ref.exr", "prt.png" };
    for (int k = 0; k < (chain ? 4 : 3); k++) {
        char fa[64], fb[64], pa[1024], w[256];
        snprintf(fa, sizeof fa, "%s.%s", a, outs[k]);
        snprintf(fb, sizeof fb, "%s.%s", b, outs[k]);
        snprintf(pa, sizeof pa, "%s", lg_test_path(t, fa));
        snprintf(w, sizeof w, "%s: %s", what, outs[k]);
        same_file(t, pa, lg_test_path(t, fb), w);
    }
    if (!caches)
        return;
    char ca[1024];
    snprintf(ca, sizeof ca, "%s", lg_test_path(t, a));
    same_entries(t, ca, lg_test_path(t, b), 3, what);
}

/* One process, the pool at 1 and at 2 threads: the same bits in every output and in
 * every cache entry (the bake's chunks, each rank's share under MPI, differ with the pool's
 * size); and the interreflected bake whose hits pass a 1 MiB budget (some vertices' hits
 * kept until then, the others' rays cast again in every bounce) equals the one that keeps
 * them all, bit for bit. */
static void case_threads(lg_test *t)
{
    same_bits_graph(t, false, "");
    char *text = NULL;
    int rc = same_bits_run(t, 0, 1, "c1", true, "c1", &text);
    LG_TEST_CHECK(t, rc == 0 && text && strstr(text, "kept "),
                  "1 thread: exit %d, or the hits were not kept:\n%s", rc, text ? text : "");
    free(text);
    rc = same_bits_run(t, 0, 2, "c2", true, "c2", NULL);
    LG_TEST_CHECK(t, rc == 0, "2 threads: exit %d", rc);
    same_bits_compare(t, "c1", "c2", false, true, "LIGHTGRAPH_THREADS 1 and 2");
    same_bits_graph(t, false, ", hit_memory_mib = 1");
    text = NULL;
    rc = same_bits_run(t, 0, 2, "c3", true, "c3", &text);
    LG_TEST_CHECK(t, rc == 0 && text && strstr(text, "passed their budget of 1.0 MiB"),
                  "hit_memory_mib = 1: exit %d, or the budget was not passed:\n%s", rc,
                  text ? text : "");
    free(text);
    char c1[1024];
    snprintf(c1, sizeof c1, "%s", lg_test_path(t, "c1.bake.exr"));
    same_file(t, c1, lg_test_path(t, "c3.bake.exr"),
              "interreflected, hits kept and past a 1 MiB budget");
}

/* `mpirun -np np` (tests/dist/mpirun.sh, one thread per rank) against one process with 2
 * threads, each with a cold cache: the same bits in every output (the transfers, the
 * reference, the picture of examples/prt.lgraph's chain) and in every cache entry, each
 * made and said once; then the ranks again on the warm cache load the entries (rank 0
 * says so) and make the same picture, the entries untouched. */
static void case_dist(lg_test *t, int np)
{
    same_bits_graph(t, true, "");
    int rc = same_bits_run(t, 0, 2, "one", true, "one", NULL);
    LG_TEST_CHECK(t, rc == 0, "one process: exit %d", rc);
    char *text = NULL;
    rc = same_bits_run(t, np, 1, "ranks", true, "ranks", &text);
    LG_TEST_CHECK(t, rc == 0, "%d ranks: exit %d", np, rc);
    LG_TEST_CHECK(t,
                  text && occurrences(text, "transfer baked") == 2 &&
                      occurrences(text, "reference computed") == 1,
                  "%d ranks: want each result made and said once (by rank 0):\n%s", np,
                  text ? text : "");
    free(text);
    char what[64];
    snprintf(what, sizeof what, "one process and %d ranks", np);
    same_bits_compare(t, "one", "ranks", true, true, what);
    text = NULL;
    rc = same_bits_run(t, np, 1, "ranks", false, "warm", &text);
    LG_TEST_CHECK(t,
                  rc == 0 && text && occurrences(text, "transfer loaded from the cache") == 2 &&
                      occurrences(text, "reference loaded from the cache") == 1 &&
                      !strstr(text, "transfer baked"),
                  "%d ranks, warm cache: exit %d, or not every result loaded once:\n%s", np, rc,
                  text ? text : "");
    free(text);
    snprintf(what, sizeof what, "one process and %d ranks on a warm cache", np);
    same_bits_compare(t, "one", "warm", true, false, what);
    char one[1024];
    snprintf(one, sizeof one, "%s", lg_test_path(t, "one"));
    same_entries(t, one, lg_test_path(t, "ranks"), 3, what);
}

static void case_dist2(lg_test *t)
{
    case_dist(t, 2);
}

static void case_dist3(lg_test *t)
{
    case_dist(t, 3);
}

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, PRT_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "unshadowed", case_unshadowed },
        { "cone", case_cone },
        { "furnace", case_furnace },
        { "backface", case_backface },
        { "large_coords", case_large_coords },
        { "few_samples", case_few_samples },
        { "brute", case_brute },
        { "params", case_params },
        { "cache", case_cache },
        { "cache_said", case_cache_said },
        { "memory", case_memory },
        { "reference", case_reference },
        { "chain", case_chain },
        { "forged", case_forged },
        { "nonfinite", case_nonfinite },
        { "masked", case_masked },
        { "threads", case_threads },
        { "dist2", case_dist2 },
        { "dist3", case_dist3 },
    };
    lg_test_main_opts o = { .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
