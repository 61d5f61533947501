/*
 * volumetric_reference through the host, on the scene of the test plugin testvolscene (a
 * square of half-edge 1 in z = 0 seen from (0, 0, 5), 40 degrees, znear 0.1, zfar 50) with
 * scene_tools' light and medium, base = phong. The test knows every ray (pixel centres:
 * subpixel = centre) and every distance, so it computes the single-scattering integral in
 * closed form (lightgraph/medium.h, in double) and compares.
 *
 *   closed_form  one light travelling -Z (from behind the camera: nothing in the fog is
 *                shadowed): inscatter = L_c sigma_s p d seg(sigma_t d) within 1e-5
 *                relative on square pixels (d to the square) and sky pixels (d to z_limit,
 *                given, and the camera's zfar by default); steps 1 and 64 agree (the
 *                segment integral is exact); out = base e^(-sigma_t d) + inscatter
 *   tau0         sigma_t = 1e-7: inscatter = L_c sigma_s p d within 1e-5 (thin fog does
 *                not vanish)
 *   occluder     the light travels +Z (from behind the square): every square pixel gets
 *                exactly 0; a sky pixel's ray starts inside the square's shadow (the prism
 *                |x|, |y| < 1, z > 0) and leaves it at t_exit: inscatter = L_c sigma_s p
 *                (e^(-sigma_t t_exit) - e^(-sigma_t d)) / sigma_t within one segment's
 *                share, and below the unshadowed value
 *   lights32     32 unshadowed lights (fog cut at z_limit 4, in front of the square) equal
 *                the sum of their 32 closed forms within 1e-5; two lights (one shadowed) =
 *                the sum of the two single renders within 1e-5; 33 lights: a clear error
 *   threads      LIGHTGRAPH_THREADS 1, 2 and 3 give the same bits (jittered, spp 3: the
 *                Latin hypercube; and spp 4: the square grid)
 *   masked       the square as a venetian blind (testvolscene slats = 4: alpha-masked
 *                horizontal bands, plugins/embree_common's filter): a view ray through a
 *                clear band passes the blind and its fog runs to z_limit, through an opaque
 *                band it stops; the fog on the far side of the blind from the light (in
 *                front of it for a light behind, behind it for a light in front) is lit
 *                through the clear bands only. Against a fine midpoint sum of the analytic
 *                visibility, within one segment's share per change of visibility; rays
 *                without a change: the closed form within 1e-5
 *   gated        fog density 0: out is base bit for bit, inscatter black (the planner
 *                gates the node; its plugin is not loaded)
 *   bad_params   steps 0, spp 0 and 5000, z_limit -1, NaN and inside the near plane, a
 *                base without depth, order 0 and 65, paths 0: non-zero exit, the node and
 *                the value named, no file
 *
 * Since issue 25 (point and spot lights, density fields, multiple scattering; the
 * statistical checks take two seeds, stat_check says why its bound holds):
 *   point_closed   a point light, g = 0, sigma_t -> 0, no occluder (fog to view depth 4):
 *                  the closed form L_c sigma_s (xi1 - xi0) / (4 pi H) within 1e-5,
 *                  homogeneous and through a uniform field (equiangular: no variance)
 *   point_medium   extinction, g 0.4: a point light, a spot (15/30 degrees, range 3), and
 *                  the point through a uniform field (ratio and delta tracking) against
 *                  L_c sigma_s lg_point_inscatter (64 nodes), within 2 standard deviations
 *   field_box      a box of fog under a directional light: the chord's closed form with the
 *                  box's own shadow on itself (light transmittance to the box's top)
 *   orders         a furnace-like box of fog (sigma_t 2) around a point light: orders 1..5,
 *                  each adds light, the change per order decreases (n = 1..4); order 2 over
 *                  order 1 at albedo 0.9 and 0.5 in the ratio 1.8 (same paths)
 *   hard_local     the camera at a spot light inside its cone; a light exactly on a view
 *                  ray (finite, the closed form); range 0 = range 1e6 bit for bit; a light
 *                  inside a closed box: exactly 0 at orders 1 and 2
 *   threads_local  point + spot in height fog at order 3: 1 and 2 threads, the same bits
 *
 * Since issue 26 (the pixels as lg_shard items, spans of at most 64 pixels of a row;
 * README.md, "Over MPI ranks"), at 130x6 (three spans a row, the last one shorter):
 *   shard_threads  LIGHTGRAPH_THREADS 1, 2 and 3 give the same bits of out and inscatter:
 *                  a point light at order 1 (homogeneous), and a point and a directional
 *                  light in height fog at order 3 (tracked transmittances, base's too);
 *                  the spans in their places: an unshadowed light on the mirror-symmetric
 *                  scene gives mirrored pixels equal within 1e-5, none black
 *   mpirun_single  (suite dist, builds with MPI) tests/dist/mpirun.sh 2 and 3 (one thread
 *                  a rank), and 2 ranks of 2 threads, give the bits of one process: a
 *                  point light at order 1
 *   mpirun_order3  2 and 3 ranks of one thread for the height fog at order 3
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "lightgraph/image.h"
#include "lightgraph/medium.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#define W 24
#define H 16
#define EYE_Z 5.0
#define TAN_HALF 0.36397023426620234 /* tan(20 degrees) */

/* the medium of most cases: sigma_s = (0.1, 0.2, 0.05), sigma_t = (0.15, 0.2, 0.15) */
static const double SIG_S[3] = { 0.1, 0.2, 0.05 }, SIG_T[3] = { 0.15, 0.2, 0.15 };
#define MEDIUM                                                                                     \
    "fog = medium { scene = %s, density = 1, scattering = [0.1, 0.2, 0.05], "                      \
    "absorption = [0.05, 0, 0.1], g = %s }\n"

/* The unit view ray through the centre of pixel (x, y) (row 0 at the top). */
static void ray(int x, int y, double w[3])
{
    double a = (2.0 * (x + 0.5) / W - 1.0) * TAN_HALF * ((double)W / H);
    double b = -(2.0 * (y + 0.5) / H - 1.0) * TAN_HALF;
    double l = sqrt(a * a + b * b + 1.0);
    w[0] = a / l, w[1] = b / l, w[2] = -1.0 / l;
}

/* The fog length of pixel (x, y): to the square (half-edge 1) or to view depth z_limit;
 * *square says which. Pixels within 1e-3 of the square's edge: *edge. */
static double fog_length(int x, int y, double z_limit, bool *square, bool *edge)
{
    double w[3];
    ray(x, y, w);
    double cf = -w[2], t = EYE_Z / cf;
    double px = fabs(t * w[0]), py = fabs(t * w[1]);
    *square = z_limit > EYE_Z && px < 1.0 && py < 1.0;
    *edge = fabs(px - 1.0) < 1e-3 || fabs(py - 1.0) < 1e-3;
    return *square ? t : z_limit / cf;
}

static double closed(double lc, double ss, double st, double g, const double w[3],
                     const double L[3], double d)
{
    double c = -(w[0] * L[0] + w[1] * L[1] + w[2] * L[2]);
    return lg_medium_inscatter(lc, ss, st, lg_hg_phase(g, c), d);
}

/* Writes and renders graph text; reads `file` (if given) into *img. Returns the status. */
static int render(lg_test *t, const char *g, const char *file, lg_image *img, char **text)
{
    static const char *const args[] = { "--size", "24x16", NULL };
    lg_test_write_text(t, "g.lgraph", g);
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0 || !file)
        return rc;
    return lg_test_read(t, file, img, NULL) ? 0 : -2;
}

/* The graph: the square, lights (text of `light` nodes chained from `cam`, the last one
 * named `lights`), the medium, phong, the node with `params` (subpixel = centre unless
 * they say otherwise); writes the inscatter to
 * i.exr, out to o.exr and base to b.exr. */
static const char *graph(char *buf, size_t size, const char *lights, const char *g,
                         const char *params)
{
    char med[512];
    snprintf(med, sizeof med, MEDIUM, "lights", g);
    snprintf(buf, size,
             "lightgraph 1\n"
             "cam = test_vol_scene { }\n"
             "%s"
             "%s"
             "lit = phong { scene = fog, background = [0.6, 0.7, 0.9] }\n"
             "vol = volumetric_reference { scene = fog, base = lit%s%s }\n"
             "output vol.inscatter \"i.exr\" float\n"
             "output vol.out \"o.exr\" float\n"
             "output lit.out \"b.exr\" float\n",
             lights, med, strstr(params, "subpixel") ? "" : ", subpixel = centre", params);
    return buf;
}

static const char *one_light(char *buf, size_t size, const double L[3], double intensity)
{
    snprintf(buf, size,
             "lights = light { scene = cam, direction = [%.17g, %.17g, %.17g], "
             "intensity = %.17g }\n",
             L[0], L[1], L[2], intensity);
    return buf;
}

static double rel(double got, double want)
{
    return fabs(got - want) / fmax(fabs(want), 1e-30);
}

/* ---- cases ----------------------------------------------------------------------------------- */

static void case_closed_form(lg_test *t)
{
    static const double L[3] = { 0, 0, -1 };
    char lights[256], g[2048];
    one_light(lights, sizeof lights, L, 10.0);
    static const struct {
        const char *params;
        double z_limit;
    } runs[] = {
        { ", steps = 1, spp = 1, z_limit = 20", 20.0 },
        { ", steps = 64, spp = 2, z_limit = 20", 20.0 },
        { ", steps = 3", 50.0 },             /* z_limit 0: the camera's zfar */
        { ", steps = 8, z_limit = 4", 4.0 }, /* the fog ends before the square */
    };
    for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
        lg_image in = { 0 }, out = { 0 }, base = { 0 };
        int rc = render(t, graph(g, sizeof g, lights, "0.4", runs[r].params), "i.exr", &in, NULL);
        LG_TEST_CHECK(t, rc == 0, "render %s: %d", runs[r].params, rc);
        if (rc != 0)
            continue;
        LG_TEST_CHECK(t,
                      lg_test_read(t, "o.exr", &out, NULL) && lg_test_read(t, "b.exr", &base, NULL),
                      "outputs");
        double worst = 0, worst_out = 0;
        int squares = 0, skies = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                bool sq, edge;
                double d = fog_length(x, y, runs[r].z_limit, &sq, &edge);
                if (edge)
                    continue;
                squares += sq, skies += !sq;
                double w[3];
                ray(x, y, w);
                const float *pi = in.pixels + ((size_t)y * W + x) * 4;
                const float *po = out.pixels + ((size_t)y * W + x) * 4;
                const float *pb = base.pixels + ((size_t)y * W + x) * 4;
                for (int c = 0; c < 3; c++) {
                    double want = closed(10.0, SIG_S[c], SIG_T[c], 0.4, w, L, d);
                    double e = rel(pi[c], want);
                    if (e > worst)
                        worst = e;
                    LG_TEST_CHECK(t, e < 1e-5,
                                  "%s: pixel (%d, %d) %s channel %d: %.9g, want "
                                  "%.9g (d %.6g)",
                                  runs[r].params, x, y, sq ? "square" : "sky", c, (double)pi[c],
                                  want, d);
                    double wo = pb[c] * exp(-SIG_T[c] * d) + want;
                    double eo = fabs(po[c] - wo) / (fabs(wo) + 1e-6);
                    worst_out = fmax(worst_out, eo);
                    LG_TEST_CHECK(t, eo < 1e-4,
                                  "%s: pixel (%d, %d) out channel %d: %.9g, want "
                                  "%.9g",
                                  runs[r].params, x, y, c, (double)po[c], wo);
                }
                LG_TEST_CHECK(t, pi[3] == 1.0f && po[3] == pb[3], "alpha");
            }
        LG_TEST_CHECK(t, skies > 0 && (runs[r].z_limit < EYE_Z || squares > 0),
                      "%d square, %d sky pixels", squares, skies);
        lg_test_note_("closed_form %s: %d square and %d sky pixels, worst relative error "
                      "%.2g (out %.2g)\n",
                      runs[r].params, squares, skies, worst, worst_out);
        lg_image_free(&in);
        lg_image_free(&out);
        lg_image_free(&base);
    }
}

static void case_tau0(lg_test *t)
{
    static const double L[3] = { 0, 0, -1 };
    char lights[256], g[2048];
    one_light(lights, sizeof lights, L, 3.0);
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "cam = test_vol_scene { }\n"
             "%s"
             "fog = medium { scene = lights, density = 1, scattering = [1e-7, 1e-7, 1e-7], "
             "absorption = [0, 0, 0], g = -0.3 }\n"
             "lit = phong { scene = fog }\n"
             "vol = volumetric_reference { scene = fog, base = lit, subpixel = centre, "
             "steps = 5, z_limit = 30 }\n"
             "output vol.inscatter \"i.exr\" float\n",
             lights);
    lg_image in = { 0 };
    int rr = render(t, g, "i.exr", &in, NULL);
    LG_TEST_CHECK(t, rr == 0, "render: %d", rr);
    if (rr != 0)
        return;
    double worst = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool sq, edge;
            double d = fog_length(x, y, 30.0, &sq, &edge);
            if (edge)
                continue;
            double w[3];
            ray(x, y, w);
            double p = lg_hg_phase(-0.3, -(w[0] * L[0] + w[1] * L[1] + w[2] * L[2]));
            double want = 3.0 * 1e-7 * p * d; /* sigma_t -> 0: no extinction */
            for (int c = 0; c < 3; c++) {
                double e = rel(in.pixels[((size_t)y * W + x) * 4 + c], want);
                worst = fmax(worst, e);
                LG_TEST_CHECK(t, e < 1e-5, "pixel (%d, %d): %.9g, want %.9g", x, y,
                              (double)in.pixels[((size_t)y * W + x) * 4 + c], want);
            }
        }
    lg_test_note_("tau0: worst relative error %.2g against L_c sigma_s p d\n", worst);
    lg_image_free(&in);
}

static void case_occluder(lg_test *t)
{
    static const double L[3] = { 0, 0, 1 };
    const int steps = 256;
    char lights[256], g[2048];
    one_light(lights, sizeof lights, L, 10.0);
    lg_image in = { 0 };
    int rc = render(t, graph(g, sizeof g, lights, "0.4", ", steps = 256, z_limit = 20"), "i.exr",
                    &in, NULL);
    LG_TEST_CHECK(t, rc == 0, "render: %d", rc);
    if (rc != 0)
        return;
    int zero = 0, partial = 0;
    double worst = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool sq, edge;
            double d = fog_length(x, y, 20.0, &sq, &edge);
            if (edge)
                continue;
            const float *pi = in.pixels + ((size_t)y * W + x) * 4;
            double w[3];
            ray(x, y, w);
            if (sq) {
                /* the whole ray lies in the square's shadow */
                LG_TEST_CHECK(t, pi[0] == 0.0f && pi[1] == 0.0f && pi[2] == 0.0f,
                              "square pixel (%d, %d): %g %g %g, want exactly 0", x, y,
                              (double)pi[0], (double)pi[1], (double)pi[2]);
                zero++;
                continue;
            }
            double t_exit = 1.0 / fmax(fabs(w[0]), fabs(w[1]));
            double c = -(w[0] * L[0] + w[1] * L[1] + w[2] * L[2]), p = lg_hg_phase(0.4, c);
            for (int ch = 0; ch < 3; ch++) {
                double lit = 10.0 * SIG_S[ch] * p;
                double want = lit * (exp(-SIG_T[ch] * t_exit) - exp(-SIG_T[ch] * d)) / SIG_T[ch];
                double share = lit * d / steps; /* one segment, unattenuated */
                double full = closed(10.0, SIG_S[ch], SIG_T[ch], 0.4, w, L, d);
                worst = fmax(worst, fabs(pi[ch] - want) / share);
                LG_TEST_CHECK(t, fabs(pi[ch] - want) <= share,
                              "sky pixel (%d, %d) channel %d: "
                              "%.9g, want %.9g (one segment %.3g)",
                              x, y, ch, (double)pi[ch], want, share);
                LG_TEST_CHECK(t, pi[ch] < full,
                              "sky pixel (%d, %d): %.9g, not below the "
                              "unshadowed %.9g",
                              x, y, (double)pi[ch], full);
            }
            partial++;
        }
    LG_TEST_CHECK(t, zero > 0 && partial > 0, "%d square, %d sky pixels", zero, partial);
    lg_test_note_("occluder: %d square pixels exactly 0; %d sky pixels within %.2f of a "
                  "segment's share of the analytic value\n",
                  zero, partial, worst);
    lg_image_free(&in);
}

/* The blind (slats bands, half-edge 1): whether (x, y) in z = 0 is on an opaque band: 1,
 * clear or outside: 0, within 1e-3 of an edge: -1. */
static int blind_at(double x, double y, int slats)
{
    if (fabs(fabs(x) - 1.0) < 1e-3 || fabs(fabs(y) - 1.0) < 1e-3)
        return -1;
    if (fabs(x) > 1.0 || fabs(y) > 1.0)
        return 0;
    double v = (1.0 - y) / 2.0 * slats, f = v - floor(v);
    if (f < 1e-3 * slats || f > 1.0 - 1e-3 * slats)
        return -1;
    return ((long)floor(v)) % 2 == 0 ? 1 : 0;
}

static void case_masked(lg_test *t)
{
    const int slats = 4, steps = 64;
    char lights[256], g[2048], g2[2100];
    for (int back = 0; back < 2; back++) {
        const double L[3] = { 0, 0, back ? 1.0 : -1.0 };
        one_light(lights, sizeof lights, L, 10.0);
        graph(g, sizeof g, lights, "0.4", ", steps = 64, z_limit = 20");
        /* the same graph on the blind */
        const char *at = strstr(g, "test_vol_scene { }");
        LG_TEST_CHECK(t, at != NULL, "graph text");
        if (!at)
            return;
        snprintf(g2, sizeof g2, "%.*stest_vol_scene { slats = %d }%s", (int)(at - g), g, slats,
                 at + strlen("test_vol_scene { }"));
        lg_image in = { 0 };
        int rc = render(t, g2, "i.exr", &in, NULL);
        LG_TEST_CHECK(t, rc == 0, "render (light from the %s): %d", back ? "back" : "front", rc);
        if (rc != 0)
            return;
        int through = 0, stopped = 0, mixed = 0;
        double worst = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double w[3];
                ray(x, y, w);
                double cf = -w[2], ts = EYE_Z / cf;
                int hit = blind_at(ts * w[0], ts * w[1], slats);
                if (hit < 0)
                    continue;
                double d = hit ? ts : 20.0 / cf;
                through += !hit && fabs(ts * w[0]) < 1 && fabs(ts * w[1]) < 1;
                stopped += hit;
                const float *pi = in.pixels + ((size_t)y * W + x) * 4;
                /* the point at t is shadowed when its shadow ray (along -L) crosses the
                 * blind's plane on an opaque band: in front of the blind (z > 0) for the
                 * light behind, behind it (z < 0) for the light in front */
                const int fine = 20000;
                double c = -(w[0] * L[0] + w[1] * L[1] + w[2] * L[2]), p = lg_hg_phase(0.4, c);
                double sum[3] = { 0, 0, 0 }, hf = d / fine;
                int changes = 0, prev = -2, amb = 0;
                for (int k = 0; k < fine; k++) {
                    double tt = (k + 0.5) * hf, z = EYE_Z + tt * w[2];
                    bool crosses = back ? z > 0 : z < 0;
                    int b = crosses ? blind_at(tt * w[0], tt * w[1], slats) : 0;
                    if (b < 0) {
                        amb++;
                        continue;
                    }
                    changes += prev >= 0 && b != prev;
                    prev = b;
                    for (int ch = 0; ch < 3; ch++)
                        sum[ch] += b ? 0.0 : exp(-SIG_T[ch] * tt) * hf;
                }
                mixed += changes > 0;
                for (int ch = 0; ch < 3; ch++) {
                    double lit = 10.0 * SIG_S[ch] * p, want = lit * sum[ch];
                    /* without a change of visibility the estimator is exact (the segment
                     * integral): the closed form; else one segment's share per change */
                    if (changes == 0 && amb == 0)
                        want = hit ? closed(10.0, SIG_S[ch], SIG_T[ch], 0.4, w, L, d) : want;
                    double share = changes == 0 && amb == 0
                                       ? 1e-5 * fabs(want) + (hit ? 0.0 : lit * hf)
                                       : lit * d / steps * (changes + 1) + lit * hf * (amb + 2);
                    worst = fmax(worst, fabs(pi[ch] - want) / share);
                    LG_TEST_CHECK(t, fabs(pi[ch] - want) <= share,
                                  "light from the %s, pixel (%d, %d) (%s) channel %d: %.9g, "
                                  "want %.9g (%d changes of visibility, tolerance %.3g)",
                                  back ? "back" : "front", x, y, hit ? "opaque band" : "clear", ch,
                                  (double)pi[ch], want, changes, share);
                }
            }
        LG_TEST_CHECK(t, through >= 4 && stopped >= 4 && (!back || mixed >= 4),
                      "light from the %s: %d pixels through clear bands, %d on opaque ones, %d "
                      "with light and shadow along the ray",
                      back ? "back" : "front", through, stopped, mixed);
        lg_test_note_("masked, light from the %s: %d pixels see through the blind, %d stop on "
                      "it, %d cross light and shadow; worst %.3g of the tolerance\n",
                      back ? "back" : "front", through, stopped, mixed, worst);
        lg_image_free(&in);
    }
}

static void case_lights32(lg_test *t)
{
    /* 32 directions travelling away from +Z's fog side: (-L).z > 0, so the rays towards
     * the lights leave the square behind them; the fog ends at view depth 4 (z >= 1) */
    char g[8192];
    double Ls[33][3];
    size_t len = 0;
    for (int l = 0; l < 33; l++) {
        double a = l * 2.399963, z = -0.2 - 0.75 * (l % 11) / 10.0;
        double r = sqrt(1.0 - z * z);
        Ls[l][0] = r * cos(a), Ls[l][1] = r * sin(a), Ls[l][2] = z;
    }
    /* the names: l0 .. l30, then lights */
    char text[32 * 200];
    len = 0;
    for (int l = 0; l < 32; l++) {
        char name[16], prev[16];
        snprintf(name, sizeof name, l == 31 ? "lights" : "l%d", l);
        snprintf(prev, sizeof prev, l == 0 ? "cam" : "l%d", l - 1);
        len += (size_t)snprintf(text + len, sizeof text - len,
                                "%s = light { scene = %s, direction = [%.17g, %.17g, %.17g], "
                                "intensity = %d }\n",
                                name, prev, Ls[l][0], Ls[l][1], Ls[l][2], 1 + l % 5);
    }
    lg_image in = { 0 };
    int rc = render(t, graph(g, sizeof g, text, "0.6", ", steps = 2, z_limit = 4"), "i.exr", &in,
                    NULL);
    LG_TEST_CHECK(t, rc == 0, "render 32 lights: %d", rc);
    if (rc == 0) {
        double worst = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                bool sq, edge;
                double d = fog_length(x, y, 4.0, &sq, &edge), w[3];
                ray(x, y, w);
                for (int c = 0; c < 3; c++) {
                    double want = 0;
                    for (int l = 0; l < 32; l++)
                        want += closed(1 + l % 5, SIG_S[c], SIG_T[c], 0.6, w, Ls[l], d);
                    double e = rel(in.pixels[((size_t)y * W + x) * 4 + c], want);
                    worst = fmax(worst, e);
                    LG_TEST_CHECK(t, e < 1e-5, "pixel (%d, %d) channel %d: %.9g, want %.9g", x, y,
                                  c, (double)in.pixels[((size_t)y * W + x) * 4 + c], want);
                }
            }
        lg_test_note_("lights32: worst relative error %.2g against the sum of 32 closed "
                      "forms\n",
                      worst);
    }
    lg_image_free(&in);

    /* linearity with shadows: A (shadowed by the square) + B = A, B rendered alone */
    static const double A[3] = { 0.2, 0.1, 1 }, B[3] = { -0.3, -0.5, -1 };
    lg_image ia = { 0 }, ib = { 0 }, iab = { 0 };
    char la[256], lb[256], lab[512];
    const char *params = ", steps = 16, spp = 3, subpixel = jittered, z_limit = 20";
    one_light(la, sizeof la, A, 7.0);
    one_light(lb, sizeof lb, B, 2.0);
    snprintf(lab, sizeof lab,
             "la = light { scene = cam, direction = [0.2, 0.1, 1], intensity = 7 }\n"
             "lights = light { scene = la, direction = [-0.3, -0.5, -1], intensity = 2 }\n");
    int r1 = render(t, graph(g, sizeof g, la, "0.4", params), "i.exr", &ia, NULL);
    int r2 = render(t, graph(g, sizeof g, lb, "0.4", params), "i.exr", &ib, NULL);
    int r3 = render(t, graph(g, sizeof g, lab, "0.4", params), "i.exr", &iab, NULL);
    LG_TEST_CHECK(t, r1 == 0 && r2 == 0 && r3 == 0, "renders %d %d %d", r1, r2, r3);
    if (r1 == 0 && r2 == 0 && r3 == 0) {
        int shadowed = 0;
        for (size_t i = 0; i < (size_t)W * H * 4; i++) {
            if (i % 4 == 3)
                continue;
            double want = (double)ia.pixels[i] + ib.pixels[i];
            LG_TEST_CHECK(t, fabs(iab.pixels[i] - want) <= 1e-5 * want,
                          "value %zu: %.9g, want "
                          "%.9g",
                          i, (double)iab.pixels[i], want);
            shadowed += ia.pixels[i] == 0.0f;
        }
        LG_TEST_CHECK(t, shadowed > 0, "light A shadows no pixel entirely");
    }
    lg_image_free(&ia);
    lg_image_free(&ib);
    lg_image_free(&iab);

    /* 33 lights */
    len = strlen(text);
    char *p = strstr(text, "lights = light");
    memcpy(p, "l31   ", 6);
    snprintf(text + len, sizeof text - len,
             "lights = light { scene = l31, direction = [0, 0, -1] }\n");
    char *msg = NULL;
    rc = render(t, graph(g, sizeof g, text, "0.6", ""), NULL, NULL, &msg);
    LG_TEST_CHECK(t, rc != 0 && msg && strstr(msg, "node 'vol'") && strstr(msg, "more than 32"),
                  "33 lights: status %d, %s", rc, msg ? msg : "");
    free(msg);
}

static void case_threads(lg_test *t)
{
    static const double L[3] = { 0.3, -0.2, 1 };
    char lights[256], g[2048];
    one_light(lights, sizeof lights, L, 10.0);
    const char *params[] = { ", subpixel = jittered, spp = 3, steps = 24, seed = 7",
                             ", subpixel = jittered, spp = 4, steps = 24" };
    for (int k = 0; k < 2; k++) {
        lg_image img[3] = { { 0 } };
        for (int th = 0; th < 3; th++) {
            char v[8];
            snprintf(v, sizeof v, "%d", th + 1);
            setenv("LIGHTGRAPH_THREADS", v, 1);
            int rc = render(t, graph(g, sizeof g, lights, "0.4", params[k]), "i.exr", &img[th],
                            NULL);
            LG_TEST_CHECK(t, rc == 0, "render with %d threads", th + 1);
        }
        unsetenv("LIGHTGRAPH_THREADS");
        for (int th = 1; th < 3; th++)
            LG_TEST_CHECK(t,
                          img[0].pixels && img[th].pixels &&
                              memcmp(img[0].pixels, img[th].pixels, (size_t)W * H * 16) == 0,
                          "%s: %d threads differ from 1", params[k], th + 1);
        double sum = 0;
        for (size_t i = 0; img[0].pixels && i < (size_t)W * H * 4; i++)
            sum += img[0].pixels[i];
        LG_TEST_CHECK(t, sum > W * H, "an image with fog: %g", sum);
        for (int th = 0; th < 3; th++)
            lg_image_free(&img[th]);
    }
}

static void expect_error(lg_test *t, const char *g, const char *want)
{
    char *msg = NULL;
    remove(lg_test_path(t, "i.exr"));
    remove(lg_test_path(t, "o.exr"));
    int rc = render(t, g, NULL, NULL, &msg);
    LG_TEST_CHECK(t, rc != 0 && rc != -1, "status %d for %s", rc, want);
    /* the node by name, or the place of its line in the graph (the parser's range errors) */
    LG_TEST_CHECK(t,
                  msg && (strstr(msg, "node 'vol'") || strstr(msg, "g.lgraph:6:")) &&
                      strstr(msg, want),
                  "the message does not "
                  "say '%s': %s",
                  want, msg ? msg : "");
    FILE *f = fopen(lg_test_path(t, "i.exr"), "rb");
    LG_TEST_CHECK(t, f == NULL, "i.exr written despite the error (%s)", want);
    if (f)
        fclose(f);
    free(msg);
}

static void case_bad_params(lg_test *t)
{
    static const double L[3] = { 0, 0, -1 };
    char lights[256], g[2048];
    one_light(lights, sizeof lights, L, 10.0);
    static const struct {
        const char *p, *want;
    } bad[] = {
        { ", steps = 0", "steps" },       { ", spp = 0", "spp" },
        { ", spp = 5000", "spp" },        { ", z_limit = -1", "z_limit" },
        { ", z_limit = nan", "z_limit" }, { ", z_limit = 0.01", "z_limit" },
        { ", seed = -3", "seed" },        { ", order = 0", "order" },
        { ", order = 65", "order" },      { ", paths = 0", "paths" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        expect_error(t, graph(g, sizeof g, lights, "0.4", bad[i].p), bad[i].want);
    /* a base without depth: an image read from a file */
    lg_image img = { 0 };
    LG_TEST_CHECK(t, lg_image_alloc(&img, W, H) == 0, "alloc");
    lg_test_write_exr(t, "flat.exr", &img);
    lg_image_free(&img);
    char med[512];
    snprintf(med, sizeof med, MEDIUM, "lights", "0.4");
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "cam = test_vol_scene { }\n%s%s"
             "flat = image { file = \"flat.exr\" }\n"
             "vol = volumetric_reference { scene = fog, base = flat }\n"
             "output vol.inscatter \"i.exr\" float\n",
             lights, med);
    expect_error(t, g, "depth");
}

static void case_gated(lg_test *t)
{
    /* density 0: no medium, the node is gated (out = base, inscatter black) */
    static const double L[3] = { 0, 0, -1 };
    char lights[256], g[2048];
    one_light(lights, sizeof lights, L, 10.0);
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "cam = test_vol_scene { }\n"
             "%s"
             "fog = medium { scene = lights, density = 0 }\n"
             "lit = phong { scene = fog, background = [0.6, 0.7, 0.9] }\n"
             "vol = volumetric_reference { scene = fog, base = lit }\n"
             "output vol.inscatter \"i.exr\" float\n"
             "output vol.out \"o.exr\" float\n"
             "output lit.out \"b.exr\" float\n",
             lights);
    lg_image in = { 0 }, out = { 0 }, base = { 0 };
    int rc = render(t, g, "i.exr", &in, NULL);
    LG_TEST_CHECK(t, rc == 0, "render: %d", rc);
    if (rc == 0 && lg_test_read(t, "o.exr", &out, NULL) && lg_test_read(t, "b.exr", &base, NULL)) {
        LG_TEST_CHECK(t, memcmp(out.pixels, base.pixels, (size_t)W * H * 16) == 0,
                      "gated: out differs from base");
        for (size_t i = 0; i < (size_t)W * H * 4; i++)
            if (i % 4 != 3)
                LG_TEST_CHECK(t, in.pixels[i] == 0.0f, "gated: inscatter value %zu is %g", i,
                              (double)in.pixels[i]);
    }
    lg_image_free(&in);
    lg_image_free(&out);
    lg_image_free(&base);
}

/* ---- point and spot lights, density fields, multiple scattering (issue 25) ------------------- */

static const double EYE[3] = { 0, 0, EYE_Z };

/* A graph: test_vol_scene with `scene` parameters, `lights` (light nodes chained from cam,
 * the last named lights), scene_tools' medium (MEDIUM with g) unless g is NULL (then the
 * scene carries its own medium and field: testvolscene's medium = true), phong, the node
 * with `params` (subpixel = centre unless they say otherwise). */
static const char *graph2(char *buf, size_t size, const char *scene, const char *lights,
                          const char *g, const char *params)
{
    char med[512] = "";
    if (g)
        snprintf(med, sizeof med, MEDIUM, "lights", g);
    const char *s = g ? "fog" : "lights";
    snprintf(buf, size,
             "lightgraph 1\n"
             "cam = test_vol_scene { %s }\n"
             "%s"
             "%s"
             "lit = phong { scene = %s, background = [0.6, 0.7, 0.9] }\n"
             "vol = volumetric_reference { scene = %s, base = lit%s%s }\n"
             "output vol.inscatter \"i.exr\" float\n"
             "output vol.out \"o.exr\" float\n",
             scene, lights, med, s, s, strstr(params, "subpixel") ? "" : ", subpixel = centre",
             params);
    return buf;
}

static const char *point_light(char *buf, size_t size, const double q[3], double intensity,
                               double range)
{
    snprintf(buf, size,
             "lights = light { scene = cam, type = point, position = [%.17g, %.17g, %.17g], "
             "intensity = %.17g, range = %.17g }\n",
             q[0], q[1], q[2], intensity, range);
    return buf;
}

/* A spot light travelling along -Z. */
static const char *spot_light(char *buf, size_t size, const double q[3], double inner_deg,
                              double outer_deg, double intensity, double range)
{
    snprintf(buf, size,
             "lights = light { scene = cam, type = spot, position = [%.17g, %.17g, %.17g], "
             "direction = [0, 0, -1], inner_cone_deg = %.17g, outer_cone_deg = %.17g, "
             "intensity = %.17g, range = %.17g }\n",
             q[0], q[1], q[2], inner_deg, outer_deg, intensity, range);
    return buf;
}

/* lg_point_inscatter's spot array for spot_light's cone (the angles as the light node
 * stores them: float radians). */
static void spot_array(double inner_deg, double outer_deg, double spot[5])
{
    spot[0] = 0, spot[1] = 0, spot[2] = -1;
    spot[3] = (double)(float)cos((double)(float)(inner_deg * LG_PI / 180.0));
    spot[4] = (double)(float)cos((double)(float)(outer_deg * LG_PI / 180.0));
}

/* Two renders of a graph made by `make(seed)` and the check of the estimate `a` against
 * want (per pixel and channel, `use`d pixels only): with a and b independent unbiased
 * estimates of standard deviation s per value, E[(a - want)^2] = s^2 and E[(a - b)^2] =
 * 2 s^2, so over n >= 300 values RMS(a - want) / (RMS(a - b) / sqrt 2) is 1 within about
 * 0.1 (a chi-square ratio); a bias shows as a ratio far above it. Allowed: 2, plus
 * `floor_rel` of the RMS of want (float rounding of the output, the reference's quadrature)
 * for estimators with no noise at all. Returns the RMS relative error. */
static double stat_check(lg_test *t, const char *what, const lg_image *a, const lg_image *b,
                         const double *want, const bool *use, double floor_rel)
{
    double se2 = 0, sd2 = 0, sw2 = 0, worst = 0;
    int n = 0, bad = 0;
    for (int i = 0; i < W * H; i++) {
        if (!use[i])
            continue;
        for (int c = 0; c < 3; c++) {
            double va = a->pixels[(size_t)i * 4 + c], vb = b->pixels[(size_t)i * 4 + c];
            double wa = want[(size_t)i * 3 + c];
            bad += !isfinite(va) || !isfinite(vb) || va < 0.0;
            se2 += (va - wa) * (va - wa);
            sd2 += (va - vb) * (va - vb);
            sw2 += wa * wa;
            worst = fmax(worst, fabs(va - wa) / fmax(wa, 1e-30));
            n++;
        }
    }
    double rms_e = sqrt(se2 / n), rms_s = sqrt(sd2 / n / 2.0), rms_w = sqrt(sw2 / n);
    LG_TEST_CHECK(t, bad == 0, "%s: %d values not finite or negative", what, bad);
    LG_TEST_CHECK(t, n >= 300 && rms_w > 0, "%s: %d values, RMS %g", what, n, rms_w);
    LG_TEST_CHECK(t, rms_e <= 2.0 * rms_s + floor_rel * rms_w,
                  "%s: RMS error %.3g against a standard deviation %.3g (RMS value %.3g): "
                  "biased",
                  what, rms_e, rms_s, rms_w);
    lg_test_note_("%s: RMS error %.3g = %.2g sd (sd %.3g), relative %.2g, worst pixel %.2g\n", what,
                  rms_e, rms_e / fmax(rms_s, 1e-300), rms_s, rms_e / rms_w, worst);
    return rms_e / rms_w;
}

/* want[] for one local light: L_c sigma_s lg_point_inscatter along each pixel-centre ray
 * to its fog length at z_limit (every pixel: the fog ends before the square). */
static void want_local(const double q[3], double lc, double range, const double *spot, double g,
                       const double ss[3], const double st[3], double z_limit, double *want,
                       bool *use)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool sq, edge;
            double d = fog_length(x, y, z_limit, &sq, &edge), w[3];
            ray(x, y, w);
            use[y * W + x] = true;
            for (int c = 0; c < 3; c++)
                want[(size_t)(y * W + x) * 3 + c] =
                    lc * ss[c] * lg_point_inscatter(EYE, w, 0.0, d, q, range, spot, g, st[c], 64);
        }
}

static void case_point_closed(lg_test *t)
{
    /* g = 0, sigma_t -> 0, no occluder (the fog ends at view depth 4, in front of the
     * square): every equiangular sample is L_c sigma_s (xi1 - xi0) / (4 pi H): the closed
     * form, to float rounding, homogeneous and through a uniform field */
    static const double q[3] = { 0.3, 0.2, 2.5 };
    static const double tiny[3] = { 1e-7, 1e-7, 1e-7 };
    char lights[512], g[4096];
    point_light(lights, sizeof lights, q, 5.0, 0.0);
    static double want[W * H * 3];
    static bool use[W * H];
    want_local(q, 5.0, 0.0, NULL, 0.0, tiny, (const double[3]){ 0, 0, 0 }, 4.0, want, use);
    static const char *const scenes[] = { "", "medium = true, field = uniform, scattering = "
                                              "[1e-7, 1e-7, 1e-7], absorption = [0, 0, 0]" };
    for (int k = 0; k < 2; k++) {
        if (k == 0)
            snprintf(g, sizeof g,
                     "lightgraph 1\ncam = test_vol_scene { }\n%s"
                     "fog = medium { scene = lights, density = 1, scattering = [1e-7, 1e-7, "
                     "1e-7], absorption = [0, 0, 0], g = 0 }\n"
                     "lit = phong { scene = fog }\n"
                     "vol = volumetric_reference { scene = fog, base = lit, subpixel = centre, "
                     "steps = 4, z_limit = 4 }\n"
                     "output vol.inscatter \"i.exr\" float\n",
                     lights);
        else
            graph2(g, sizeof g, scenes[1], lights, NULL, ", steps = 4, z_limit = 4");
        lg_image in = { 0 };
        int rc = render(t, g, "i.exr", &in, NULL);
        LG_TEST_CHECK(t, rc == 0, "render %d: %d", k, rc);
        if (rc)
            continue;
        double worst = 0;
        for (int i = 0; i < W * H; i++)
            for (int c = 0; c < 3; c++) {
                double e = rel(in.pixels[(size_t)i * 4 + c], want[(size_t)i * 3 + c]);
                worst = fmax(worst, e);
                LG_TEST_CHECK(t, e < 1e-5, "%s: pixel %d channel %d: %.9g, want %.9g",
                              k ? "uniform field" : "homogeneous", i, c,
                              (double)in.pixels[(size_t)i * 4 + c], want[(size_t)i * 3 + c]);
            }
        lg_test_note_("point_closed %s: worst relative error %.2g against (xi1 - xi0) / (4 pi H)\n",
                      k ? "uniform field" : "homogeneous", worst);
        lg_image_free(&in);
    }
}

/* Renders graph text g with seeds 1 and 2 (appended to params by the caller's %s). */
static bool render_pair(lg_test *t, const char *scene, const char *lights, const char *gg,
                        const char *params, lg_image img[2])
{
    char g[4096], p[512];
    for (int s = 0; s < 2; s++) {
        snprintf(p, sizeof p, "%s, seed = %d", params, s + 1);
        int rc = render(t, graph2(g, sizeof g, scene, lights, gg, p), "i.exr", &img[s], NULL);
        LG_TEST_CHECK(t, rc == 0, "render %s %s seed %d: %d", scene, params, s + 1, rc);
        if (rc)
            return false;
    }
    return true;
}

static void case_point_medium(lg_test *t)
{
    /* extinction and g != 0: against lg_point_inscatter with 64 nodes, statistically */
    static const double q[3] = { 0.3, 0.2, 2.5 }, qs[3] = { 0.3, 0.2, 4.5 };
    static double want[W * H * 3], want_s[W * H * 3];
    static bool use[W * H];
    double spot[5];
    spot_array(15.0, 30.0, spot);
    want_local(q, 5.0, 0.0, NULL, 0.4, SIG_S, SIG_T, 4.0, want, use);
    want_local(qs, 5.0, 3.0, spot, 0.4, SIG_S, SIG_T, 4.0, want_s, use);
    char pl[512], sl[512];
    point_light(pl, sizeof pl, q, 5.0, 0.0);
    spot_light(sl, sizeof sl, qs, 15.0, 30.0, 5.0, 3.0);
    static const char *const own =
        "medium = true, field = uniform, scattering = [0.1, 0.2, 0.05], absorption = [0.05, 0, "
        "0.1], g = 0.4";
    const struct {
        const char *what, *scene, *lights, *g, *params;
        bool spot;
    } runs[] = {
        { "point, homogeneous", "", pl, "0.4", ", steps = 16, z_limit = 4", false },
        { "spot (range 3), homogeneous", "", sl, "0.4", ", steps = 16, z_limit = 4", true },
        { "point, uniform field, ratio", own, pl, NULL, ", steps = 16, z_limit = 4", false },
        { "point, uniform field, delta", own, pl, NULL,
          ", steps = 16, z_limit = 4, transmittance = delta", false },
    };
    for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++) {
        lg_image img[2] = { { 0 }, { 0 } };
        if (render_pair(t, runs[r].scene, runs[r].lights, runs[r].g, runs[r].params, img))
            stat_check(t, runs[r].what, &img[0], &img[1], runs[r].spot ? want_s : want, use, 1e-5);
        lg_image_free(&img[0]);
        lg_image_free(&img[1]);
    }
}

static void case_field_box(lg_test *t)
{
    /* a box of fog [-0.6, 0.6]^2 x [1, 3] lit by a directional light travelling -Z: a view
     * ray crosses it on its chord [ta, tb]; the light reaches x(t) through the box above it
     * (3 - z(t)): the medium shadows itself. L_v = L_c sigma_s p integral_ta^tb
     * e^(-sigma_t (t - ta)) e^(-sigma_t (3 - z(t))) dt, in closed form */
    static const double L[3] = { 0, 0, -1 };
    static const double ss[3] = { 0.3, 0.5, 0.2 }, st[3] = { 0.4, 0.5, 0.4 };
    char lights[256];
    one_light(lights, sizeof lights, L, 10.0);
    static const char *const scene = "medium = true, field = box, lo = [-0.6, -0.6, 1], hi = "
                                     "[0.6, 0.6, 3], scattering = [0.3, 0.5, 0.2], absorption = "
                                     "[0.1, 0, 0.2], g = 0.3";
    static double want[W * H * 3];
    static bool use[W * H];
    int inside = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double w[3];
            ray(x, y, w);
            /* the slab test in double */
            double lo[3] = { -0.6, -0.6, 1 }, hi[3] = { 0.6, 0.6, 3 }, ta = 0, tb = 1e30;
            for (int c = 0; c < 3; c++) {
                if (w[c] == 0.0)
                    continue;
                double u = (lo[c] - EYE[c]) / w[c], v = (hi[c] - EYE[c]) / w[c];
                ta = fmax(ta, fmin(u, v));
                tb = fmin(tb, fmax(u, v));
            }
            double p = lg_hg_phase(0.3, w[2]); /* dot(w, to the light) */
            use[y * W + x] = true;
            inside += tb > ta;
            for (int c = 0; c < 3; c++) {
                double v = 0.0;
                if (tb > ta) {
                    double k = st[c] * (1.0 - w[2]);
                    v = 10.0 * ss[c] * p * exp(st[c] * (ta + EYE_Z - 3.0)) *
                        (exp(-k * ta) - exp(-k * tb)) / k;
                }
                want[(size_t)(y * W + x) * 3 + c] = v;
            }
        }
    LG_TEST_CHECK(t, inside > 50 && inside < W * H - 50, "%d of %d rays cross the box", inside,
                  W * H);
    lg_image img[2] = { { 0 }, { 0 } };
    if (render_pair(t, scene, lights, NULL, ", steps = 16", img))
        stat_check(t, "box of fog, directional, self-shadowed", &img[0], &img[1], want, use, 1e-5);
    lg_image_free(&img[0]);
    lg_image_free(&img[1]);
}

/* Sum over the inscatter image (channel c, or all for c < 0). */
static double image_sum(const lg_image *img)
{
    double s = 0;
    for (size_t i = 0; i < (size_t)W * H * 4; i++)
        if (i % 4 != 3)
            s += img->pixels[i];
    return s;
}

static void case_orders(lg_test *t)
{
    /* a furnace-like closed case: a box of fog [-1, 1]^2 x [1, 3], sigma_t 2 (optical
     * half-width 2), a point light at its centre, nothing else inside (the square is
     * outside it and absorbs). The order-n + 1 render continues the order-n render's paths
     * with the same random numbers, so I_{n+1} - I_n is exactly order n + 1's estimate */
    static const double q[3] = { 0, 0, 2 };
    static const double albedo[2] = { 0.9, 0.5 };
    char lights[512], scene[512], g[4096], p[256];
    point_light(lights, sizeof lights, q, 1.0, 0.0);
    double E[2][6] = { { 0 } };
    for (int a = 0; a < 2; a++) {
        snprintf(scene, sizeof scene,
                 "medium = true, field = box, lo = [-1, -1, 1], hi = [1, 1, 3], scattering = "
                 "[%g, %g, %g], absorption = [%g, %g, %g], g = 0.3",
                 2 * albedo[a], 2 * albedo[a], 2 * albedo[a], 2 * (1 - albedo[a]),
                 2 * (1 - albedo[a]), 2 * (1 - albedo[a]));
        lg_image img[6] = { { 0 } };
        double change[5] = { 0 };
        bool ok = true;
        for (int n = 1; n <= (a == 0 ? 5 : 2) && ok; n++) {
            snprintf(p, sizeof p, ", steps = 8, order = %d, paths = 4, seed = 3", n);
            int rc = render(t, graph2(g, sizeof g, scene, lights, NULL, p), "i.exr", &img[n], NULL);
            LG_TEST_CHECK(t, rc == 0, "albedo %g order %d: %d", albedo[a], n, rc);
            ok = rc == 0;
            if (!ok)
                break;
            E[a][n] = image_sum(&img[n]);
            if (n > 1) {
                for (size_t i = 0; i < (size_t)W * H * 4; i++)
                    if (i % 4 != 3)
                        change[n - 1] += fabs(img[n].pixels[i] - img[n - 1].pixels[i]);
                LG_TEST_CHECK(t, E[a][n] > E[a][n - 1],
                              "albedo %g: order %d adds nothing (%g after %g)", albedo[a], n,
                              E[a][n], E[a][n - 1]);
            }
        }
        if (ok && a == 0) {
            for (int n = 2; n <= 4; n++)
                LG_TEST_CHECK(t, change[n] < change[n - 1],
                              "albedo 0.9: the change from order %d to %d (%g) is not below "
                              "the one from %d to %d (%g)",
                              n, n + 1, change[n], n - 1, n, change[n - 1]);
            lg_test_note_("orders (albedo 0.9): sum of inscatter %.4g %.4g %.4g %.4g %.4g for "
                          "orders 1..5; changes %.4g %.4g %.4g %.4g (ratios %.2f %.2f %.2f)\n",
                          E[0][1], E[0][2], E[0][3], E[0][4], E[0][5], change[1], change[2],
                          change[3], change[4], change[2] / change[1], change[3] / change[2],
                          change[4] / change[3]);
        }
        for (int n = 0; n < 6; n++)
            lg_image_free(&img[n]);
    }
    /* order 2 against order 1 scales like the albedo: sigma_t is the same, so both
     * albedos draw the same paths and (E2 - E1) / E1 = a x (the same geometry) */
    if (E[0][1] > 0 && E[1][1] > 0) {
        double r9 = (E[0][2] - E[0][1]) / E[0][1], r5 = (E[1][2] - E[1][1]) / E[1][1];
        LG_TEST_CHECK(t, fabs(r9 / r5 - 0.9 / 0.5) < 1e-3 * 1.8,
                      "order 2 / order 1: %.5g at albedo 0.9, %.5g at 0.5: ratio %.5f, want 1.8",
                      r9, r5, r9 / r5);
        lg_test_note_("orders: order 2 adds %.1f%% at albedo 0.9, %.1f%% at 0.5 (ratio %.4f, "
                      "want 1.8); orders 2..5 add %.1f%% at 0.9\n",
                      100 * r9, 100 * r5, r9 / r5, 100 * (E[0][5] - E[0][1]) / E[0][1]);
    }
}

static void case_hard_local(lg_test *t)
{
    char lights[512], g[4096];
    static double want[W * H * 3];
    static bool use[W * H];
    /* the camera at the light and inside its cone: a spot at the eye aimed down -Z */
    {
        double spot[5];
        spot_array(10.0, 20.0, spot);
        want_local(EYE, 5.0, 0.0, spot, 0.4, SIG_S, SIG_T, 4.0, want, use);
        spot_light(lights, sizeof lights, EYE, 10.0, 20.0, 5.0, 0.0);
        lg_image img[2] = { { 0 }, { 0 } };
        if (render_pair(t, "", lights, "0.4", ", steps = 16, z_limit = 4", img))
            stat_check(t, "camera at the spot, inside its cone", &img[0], &img[1], want, use, 1e-5);
        lg_image_free(&img[0]);
        lg_image_free(&img[1]);
    }
    /* a light exactly on a view ray (pixel (12, 8)'s centre ray, 2 units out): finite
     * thanks to LG_LIGHT_EPSILON, and the closed form's value */
    {
        double w[3];
        ray(12, 8, w);
        double q[3] = { EYE[0] + 2 * w[0], EYE[1] + 2 * w[1], EYE[2] + 2 * w[2] };
        want_local(q, 5.0, 0.0, NULL, 0.4, SIG_S, SIG_T, 4.0, want, use);
        point_light(lights, sizeof lights, q, 5.0, 0.0);
        lg_image img[2] = { { 0 }, { 0 } };
        if (render_pair(t, "", lights, "0.4", ", steps = 16, z_limit = 4", img)) {
            stat_check(t, "light on a view ray", &img[0], &img[1], want, use, 1e-5);
            double v = img[0].pixels[(size_t)(8 * W + 12) * 4 + 1];
            double wv = want[(size_t)(8 * W + 12) * 3 + 1];
            LG_TEST_CHECK(t, isfinite(v) && rel(v, wv) < 1e-3,
                          "the ray through the light: %g, want %g", v, wv);
            lg_test_note_("light on the ray: %.6g (closed form %.6g)\n", v, wv);
        }
        lg_image_free(&img[0]);
        lg_image_free(&img[1]);
    }
    /* range 0 is infinite: the same as a range far beyond the scene (W = 1 - 1e-24) */
    {
        static const double q[3] = { 0.3, 0.2, 2.5 };
        lg_image a = { 0 }, b = { 0 };
        int rc = render(t,
                        graph2(g, sizeof g, "", point_light(lights, sizeof lights, q, 5, 0), "0.4",
                               ", steps = 8, z_limit = 4"),
                        "i.exr", &a, NULL);
        rc |= render(t,
                     graph2(g, sizeof g, "", point_light(lights, sizeof lights, q, 5, 1e6), "0.4",
                            ", steps = 8, z_limit = 4"),
                     "i.exr", &b, NULL);
        LG_TEST_CHECK(t, rc == 0, "range renders: %d", rc);
        if (rc == 0)
            LG_TEST_CHECK(t,
                          memcmp(a.pixels, b.pixels, (size_t)W * H * 16) == 0 && image_sum(&a) > 0,
                          "range 0 differs from range 1e6 (sum %g vs %g)", image_sum(&a),
                          image_sum(&b));
        lg_image_free(&a);
        lg_image_free(&b);
    }
    /* the light inside closed geometry (a box of half-edge 0.3 around it): 0 everywhere,
     * single and multiple scattering */
    for (int order = 1; order <= 2; order++) {
        static const double q[3] = { 0, 0, 2.5 };
        char p[256];
        snprintf(p, sizeof p, ", steps = 8, z_limit = 20, order = %d, paths = 2", order);
        lg_image a = { 0 };
        int rc = render(t,
                        graph2(g, sizeof g, "cube = 0.3, cube_centre = [0, 0, 2.5]",
                               point_light(lights, sizeof lights, q, 50, 0), "0.4", p),
                        "i.exr", &a, NULL);
        LG_TEST_CHECK(t, rc == 0, "cube render: %d", rc);
        if (rc == 0)
            LG_TEST_CHECK(t, image_sum(&a) == 0.0, "order %d: light inside the box: sum %g", order,
                          image_sum(&a));
        lg_image_free(&a);
    }
}

static void case_threads_local(lg_test *t)
{
    /* point + spot in height fog, order 3: the same bits for 1 and 2 threads */
    char g[4096];
    static const char *const lights =
        "pt = light { scene = cam, type = point, position = [0.3, 0.2, 2.5], intensity = 5 }\n"
        "lights = light { scene = pt, type = spot, position = [-0.3, 0.4, 4], direction = [0, "
        "0, -1], inner_cone_deg = 15, outer_cone_deg = 30, intensity = 5 }\n";
    const char *scene = "medium = true, field = height, falloff = 0.8, base_y = 0, scattering = "
                        "[0.3, 0.3, 0.3], absorption = [0.1, 0.1, 0.1], g = 0.2";
    lg_image img[2] = { { 0 }, { 0 } };
    for (int th = 0; th < 2; th++) {
        setenv("LIGHTGRAPH_THREADS", th ? "2" : "1", 1);
        int rc = render(t,
                        graph2(g, sizeof g, scene, lights, NULL,
                               ", subpixel = jittered, spp = 2, steps = 8, order = 3, paths = 2"),
                        "i.exr", &img[th], NULL);
        LG_TEST_CHECK(t, rc == 0, "render with %d threads: %d", th + 1, rc);
    }
    unsetenv("LIGHTGRAPH_THREADS");
    LG_TEST_CHECK(t,
                  img[0].pixels && img[1].pixels &&
                      memcmp(img[0].pixels, img[1].pixels, (size_t)W * H * 16) == 0,
                  "2 threads differ from 1");
    LG_TEST_CHECK(t, img[0].pixels && image_sum(&img[0]) > 0, "no fog");
    lg_image_free(&img[0]);
    lg_image_free(&img[1]);
}

/* ---- the pixels as lg_shard items (issue 26) ------------------------------------------------- */

/* 130 pixels wide: three spans of 44, 44 and 42 pixels a row (VR_SPAN 64) */
#define SW 130
#define SH 6
#define SHARD_SIZE "130x6"

/* The two graphs of the shard cases: a point light in homogeneous fog at order 1, and a
 * point and a directional light in height fog at order 3 (every transmittance tracked,
 * base's extinction too). Jittered sub-pixels: every random stream is used. */
static const char *shard_graph(char *buf, size_t size, bool order3)
{
    static const char *const point =
        "lights = light { scene = cam, type = point, position = [0.3, 0.2, 2.5], intensity = 5 "
        "}\n";
    static const char *const two =
        "pt = light { scene = cam, type = point, position = [0.3, 0.2, 2.5], intensity = 5 }\n"
        "lights = light { scene = pt, direction = [0.3, -0.4, -1], intensity = 4 }\n";
    if (!order3)
        return graph2(buf, size, "", point, "0.4",
                      ", subpixel = jittered, spp = 2, steps = 16, z_limit = 20, seed = 5");
    return graph2(buf, size,
                  "medium = true, field = height, falloff = 0.8, base_y = 0, scattering = "
                  "[0.3, 0.3, 0.3], absorption = [0.1, 0.1, 0.1], g = 0.2",
                  two, NULL,
                  ", subpixel = jittered, spp = 2, steps = 8, order = 3, paths = 2, seed = 5");
}

/* Reads i.exr and o.exr of the last render into img[0], img[1]. */
static bool read_pair(lg_test *t, lg_image img[2])
{
    return lg_test_read(t, "i.exr", &img[0], NULL) && lg_test_read(t, "o.exr", &img[1], NULL) &&
           img[0].width == SW && img[0].height == SH && img[1].width == SW && img[1].height == SH;
}

/* Whether a and b (i.exr, o.exr each) have the same bits; says where they first differ. */
static bool same_bits(lg_test *t, const char *what, const lg_image a[2], const lg_image b[2])
{
    static const char *const names[2] = { "inscatter", "out" };
    bool same = true;
    for (int k = 0; k < 2; k++) {
        if (!a[k].pixels || !b[k].pixels) {
            LG_TEST_FAILF(t, "%s: %s missing", what, names[k]);
            same = false;
            continue;
        }
        size_t n = (size_t)SW * SH * 4, diff = 0, first = 0;
        for (size_t i = n; i-- > 0;)
            if (memcmp(&a[k].pixels[i], &b[k].pixels[i], sizeof(float)) != 0)
                diff++, first = i;
        LG_TEST_CHECK(t, diff == 0,
                      "%s: %s differs in %zu of %zu values, first pixel (%zu, %zu) channel %zu: "
                      "%.9g against %.9g",
                      what, names[k], diff, n, first / 4 % SW, first / 4 / SW, first % 4,
                      (double)b[k].pixels[first], (double)a[k].pixels[first]);
        same = same && diff == 0;
    }
    return same;
}

/* The sum of inscatter (a picture with fog in it, not a black one). */
static double pair_sum(const lg_image img[2])
{
    double s = 0;
    for (size_t i = 0; img[0].pixels && i < (size_t)SW * SH * 4; i++)
        if (i % 4 != 3)
            s += img[0].pixels[i];
    return s;
}

static void case_shard_threads(lg_test *t)
{
    static const char *const args[] = { "--size", SHARD_SIZE, NULL };
    char g[4096];
    for (int k = 0; k < 2; k++) {
        lg_test_write_text(t, "g.lgraph", shard_graph(g, sizeof g, k == 1));
        lg_image img[3][2] = { { { 0 } } };
        for (int th = 0; th < 3; th++) {
            char v[8];
            snprintf(v, sizeof v, "%d", th + 1);
            setenv("LIGHTGRAPH_THREADS", v, 1);
            int rc = lg_test_render(t, "g.lgraph", args, NULL);
            LG_TEST_CHECK(t, rc == 0 && read_pair(t, img[th]), "%s, %d threads: render %d",
                          k ? "order 3" : "order 1", th + 1, rc);
        }
        unsetenv("LIGHTGRAPH_THREADS");
        for (int th = 1; th < 3; th++) {
            char what[64];
            snprintf(what, sizeof what, "%s, %d threads against 1", k ? "order 3" : "order 1",
                     th + 1);
            same_bits(t, what, img[0], img[th]);
        }
        LG_TEST_CHECK(t, pair_sum(img[0]) > 1e-3 * SW * SH, "%s: no fog (sum %g)",
                      k ? "order 3" : "order 1", pair_sum(img[0]));
        for (int th = 0; th < 3; th++)
            lg_image_free(&img[th][0]), lg_image_free(&img[th][1]);
    }
    /* the spans in their places: the scene is mirror-symmetric about x = 0 and a light
     * travelling -Z from behind the camera shadows no fog, so at pixel centres the
     * inscatter of (x, y) and (129 - x, y) is the same closed form (to float rounding);
     * a span computed for the wrong pixels or left out breaks the symmetry */
    static const double L[3] = { 0, 0, -1 };
    char lights[256];
    lg_test_write_text(t, "g.lgraph",
                       graph2(g, sizeof g, "", one_light(lights, sizeof lights, L, 3.0), "0.4",
                              ", steps = 4, z_limit = 30"));
    lg_image m[2] = { { 0 } };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0 && read_pair(t, m), "mirror render: %d", rc);
    double worst = 0;
    int dark = 0;
    for (int y = 0; m[0].pixels && y < SH; y++)
        for (int x = 0; x < SW; x++)
            for (int c = 0; c < 3; c++) {
                double a = m[0].pixels[((size_t)y * SW + x) * 4 + c];
                double b = m[0].pixels[((size_t)y * SW + (SW - 1 - x)) * 4 + c];
                dark += !(a > 0.0);
                worst = fmax(worst, rel(a, b));
            }
    LG_TEST_CHECK(t, m[0].pixels && dark == 0 && worst < 1e-5,
                  "mirror: %d values not > 0, worst relative difference of mirrored pixels %.3g",
                  dark, worst);
    lg_test_note_("shard_threads mirror: worst relative difference of mirrored pixels %.2g\n",
                  worst);
    lg_image_free(&m[0]);
    lg_image_free(&m[1]);
}

static double mono_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Runs `tests/dist/mpirun.sh np lightgraph render g.lgraph --size SHARD_SIZE` in the
 * scratch folder, `threads` threads a rank. Returns the exit status, -1 on a signal. */
static int render_mpirun(lg_test *t, int np, int threads)
{
    const char *src = getenv("LG_SOURCE_ROOT");
    if (!src || !*src)
        LG_TEST_FAILF(t, "LG_SOURCE_ROOT is not set: cannot find tests/dist/mpirun.sh");
    char script[4096], nps[16], ths[16], log[4096];
    snprintf(script, sizeof script, "%s/tests/dist/mpirun.sh", src ? src : "");
    snprintf(nps, sizeof nps, "%d", np);
    snprintf(ths, sizeof ths, "%d", threads);
    snprintf(log, sizeof log, "%s", lg_test_path(t, "mpirun.log"));
    const char *argv[] = { "/bin/sh",  script,   nps,        lg_test_exe(), "render",
                           "g.lgraph", "--size", SHARD_SIZE, NULL };
    pid_t pid = fork();
    if (pid == 0) {
        /* the child: the scratch folder, output to mpirun.log */
        FILE *f = freopen(log, "w", stdout);
        if (!f || dup2(fileno(stdout), 2) < 0 || chdir(lg_test_dir(t)) != 0)
            _exit(126);
        setenv("LIGHTGRAPH_THREADS", ths, 1);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    while (pid > 0 && waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    int rc = pid < 0 ? -2 : WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (rc != 0) {
        /* what mpirun and the ranks said */
        FILE *f = fopen(log, "r");
        char line[1024];
        fprintf(stderr, "$ %s %s lightgraph render g.lgraph --size %s -> %d\n", script, nps,
                SHARD_SIZE, rc);
        while (f && fgets(line, sizeof line, f))
            fputs(line, stderr);
        if (f)
            fclose(f);
    }
    return rc;
}

/* One process, then mpirun.sh 2 and 3 with one thread a rank (and, order 1, 2 ranks of
 * two threads: a rank's chunk is then two spans, split over its threads): the same bits of
 * out and inscatter. */
static void mpirun_case(lg_test *t, bool order3)
{
    static const char *const args[] = { "--size", SHARD_SIZE, NULL };
    const char *name = order3 ? "order 3, height fog" : "order 1, point light";
    char g[4096];
    lg_test_write_text(t, "g.lgraph", shard_graph(g, sizeof g, order3));
    lg_image one[2] = { { 0 } };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    if (!(rc == 0 && read_pair(t, one))) {
        LG_TEST_FAILF(t, "%s: one process: render %d", name, rc);
        return;
    }
    LG_TEST_CHECK(t, pair_sum(one) > 1e-3 * SW * SH, "%s: no fog (sum %g)", name, pair_sum(one));
    static const int runs[3][2] = { { 2, 1 }, { 3, 1 }, { 2, 2 } };
    for (int k = 0; k < (order3 ? 2 : 3); k++) {
        int np = runs[k][0], threads = runs[k][1];
        remove(lg_test_path(t, "i.exr"));
        remove(lg_test_path(t, "o.exr"));
        lg_image got[2] = { { 0 } };
        double t0 = mono_now();
        rc = render_mpirun(t, np, threads);
        double secs = mono_now() - t0;
        char what[96];
        snprintf(what, sizeof what, "%s, mpirun -np %d (%d thread%s a rank) against one process",
                 name, np, threads, threads > 1 ? "s" : "");
        if (rc == 0 && read_pair(t, got))
            same_bits(t, what, one, got);
        else
            LG_TEST_FAILF(t, "%s: exit %d, or no 130x6 i.exr and o.exr", what, rc);
        lg_test_note_("%s: %.1f s\n", what, secs);
        lg_image_free(&got[0]);
        lg_image_free(&got[1]);
    }
    lg_image_free(&one[0]);
    lg_image_free(&one[1]);
}

static void case_mpirun_single(lg_test *t)
{
    mpirun_case(t, false);
}

static void case_mpirun_order3(lg_test *t)
{
    mpirun_case(t, true);
}

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, VR_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "closed_form", case_closed_form },
        { "tau0", case_tau0 },
        { "occluder", case_occluder },
        { "lights32", case_lights32 },
        { "threads", case_threads },
        { "bad_params", case_bad_params },
        { "gated", case_gated },
        { "masked", case_masked },
        { "point_closed", case_point_closed },
        { "point_medium", case_point_medium },
        { "field_box", case_field_box },
        { "orders", case_orders },
        { "hard_local", case_hard_local },
        { "threads_local", case_threads_local },
        { "shard_threads", case_shard_threads },
        { "mpirun_single", case_mpirun_single },
        { "mpirun_order3", case_mpirun_order3 },
    };
    lg_test_main_opts o = { .prefix = "volumetric_reference", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
