/*
 * tests/plugins/volumetric_froxel: the volumetric_froxel node through the host, on the
 * bunny-box scene of examples/volumetric_scene.lgraph at tiny sizes, on every backend
 * (cases named CASE_BACKEND; a missing device fails).
 *
 * The closed form comes from the test plugin testfroxelcheck (froxel_closed_form, built
 * here), computed from vol_common.h and lightgraph/medium.h without the node's code. The
 * closed form holds exactly where a pixel's centre is a column's centre (froxel.h), so
 * those cases render at an image size equal to the grid's W x H.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/test.h"

/* The scene: the example's nodes (scene, cam, sun, fog, shadow, lit). */
#define SCENE "lightgraph 1\ninclude \"" FX_SOURCE_ROOT "/examples/volumetric_scene.lgraph\"\n"

/* Writes graph text `g`, renders it with `args`, reads `out` into *img (when img). */
static int render(lg_test *t, const char *g, const char *const *args, const char *out,
                  lg_image *img, char **text)
{
    lg_test_write_text(t, "g.lgraph", g);
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0 || !img)
        return rc;
    return lg_test_read(t, out, img, NULL) ? 0 : -2;
}

/* Largest |got - want| / (|want| + floor) over rgb, and whether everything is finite. */
static double max_rel(const lg_image *got, const lg_image *want, double floor_, bool *finite)
{
    double m = 0;
    *finite = true;
    size_t n = (size_t)got->width * got->height;
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            double g = got->pixels[4 * p + c], w = want->pixels[4 * p + c];
            if (!isfinite(g)) {
                *finite = false;
                continue;
            }
            double r = fabs(g - w) / (fabs(w) + floor_);
            if (r > m)
                m = r;
        }
    return m;
}

/* One render of `vol` (froxel parameters `params`, extra graph text `extra`) and the
 * closed form (`mode`, z_limit of `zl`) at `size`; returns the largest relative error of
 * vol.inscatter, -1 when a render failed. */
static double vs_closed_form(lg_test *t, const char *backend, const char *params,
                             const char *extra, const char *mode, const char *zl,
                             const char *size)
{
    char g[4096];
    snprintf(g, sizeof g,
             SCENE "%s\n"
                   "vol = volumetric_froxel { scene = fog, base = lit, backend = %s, %s }\n"
                   "ref = froxel_closed_form { scene = fog, base = lit, mode = %s, "
                   "z_limit = %s }\n"
                   "output vol.inscatter \"ins.exr\" float\noutput ref \"ref.exr\" float\n",
             extra, backend, params, mode, zl);
    const char *args[] = { "--size", size, NULL };
    lg_image ins = { 0 }, ref = { 0 };
    double r = -1;
    if (render(t, g, args, "ins.exr", &ins, NULL) == 0 && lg_test_read(t, "ref.exr", &ref, NULL)) {
        bool finite;
        r = max_rel(&ins, &ref, 1e-6, &finite);
        LG_TEST_CHECK(t, finite, "%s %s: a value is not finite", backend, params);
    } else {
        LG_TEST_FAILF(t, "%s %s: the render failed", backend, params);
    }
    lg_image_free(&ins);
    lg_image_free(&ref);
    return r;
}

/* ---- closed form: unshadowed, energy_conserving, both slicings, several grids ---------- */

static void closed_form(lg_test *t, const char *backend)
{
    static const struct { const char *grid, *size; } grids[] = {
        { "width = 16, height = 8, depth = 24", "16x8" },
        { "width = 1, height = 1, depth = 1", "1x1" },
        { "width = 12, height = 6, depth = 1", "12x6" },
        { "width = 10, height = 7, depth = 96", "10x7" },
    };
    static const char *const slicings[] = { "uniform_clip", "exponential" };
    /* z_limit 0: the camera's zfar (2.64) behind every surface but the opening's sky;
     * 1.2: most walls behind it; z_near 0.9: the near walls in front of the grid */
    static const struct { const char *zl, *extra; } ranges[] = {
        { "0", "" }, { "1.2", "" }, { "1.2", ", z_near = 0.9" },
        { "2", ", z_near = 0.5, near_offset = 0.6" },
    };
    for (size_t gi = 0; gi < sizeof grids / sizeof grids[0]; gi++)
        for (int si = 0; si < 2; si++)
            for (size_t ri = 0; ri < sizeof ranges / sizeof ranges[0]; ri++) {
                if (ri == 3 && si == 0)
                    continue; /* near_offset: exponential only */
                char p[256];
                snprintf(p, sizeof p, "%s, slicing = %s, z_limit = %s%s", grids[gi].grid,
                         slicings[si], ranges[ri].zl, ranges[ri].extra);
                double r = vs_closed_form(t, backend, p, "", "energy_conserving",
                                          ranges[ri].zl, grids[gi].size);
                lg_test_note_("%s %s: max relative error %.3g", backend, p, r);
                LG_TEST_CHECK(t, r >= 0 && r < 1e-4, "%s %s: %.3g against the closed form",
                              backend, p, r);
            }
}

/* ---- thesis accumulation --------------------------------------------------------------- */

/* Unshadowed, the thesis's plain sum S x length gives L_c sigma_s p d at a column's centre
 * for any slicing (S is constant along the column), i.e. the closed form times
 * tau / (1 - e^-tau): exactly what a one-slice grid gives too. */
static void thesis(lg_test *t, const char *backend)
{
    static const struct { const char *p, *size; } c[] = {
        { "width = 1, height = 1, depth = 1", "1x1" },
        { "width = 16, height = 8, depth = 24", "16x8" },
        { "width = 16, height = 8, depth = 24, slicing = exponential", "16x8" },
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        char p[256];
        snprintf(p, sizeof p, "%s, accumulation = thesis, z_limit = 2", c[i].p);
        double r = vs_closed_form(t, backend, p, "", "thesis_one_slice", "2", c[i].size);
        LG_TEST_CHECK(t, r >= 0 && r < 1e-4, "%s %s: %.3g against the thesis sum", backend,
                      p, r);
        /* and it is the closed form's tau / (1 - e^-tau) times: not the closed form */
        double e = vs_closed_form(t, backend, p, "", "energy_conserving", "2", c[i].size);
        lg_test_note_("%s %s: %.3g vs the thesis sum, %.3g vs the closed form", backend, p,
                      r, e);
        LG_TEST_CHECK(t, e > 1e-2, "%s %s: the thesis sum should exceed the closed form "
                      "(%.3g)", backend, p, e);
    }
}

/* ---- 32 lights, a light behind the camera ---------------------------------------------- */

static void lights(lg_test *t, const char *backend)
{
    /* 31 more suns of varied directions and colours: the closed form sums them */
    char extra[8192] = "", *e = extra;
    for (int i = 0; i < 31; i++) {
        double a = 0.7 * i, y = -0.2 - 0.02 * i;
        char prev[16];
        snprintf(prev, sizeof prev, i ? "l%d" : "fog", i - 1);
        e += sprintf(e, "l%d = light { scene = %s, direction = [%g, %g, %g], intensity = %g, "
                        "color = [1, %g, %g] }\n",
                     i, prev, cos(a), y, sin(a), 0.5 + 0.1 * i, 0.3 + 0.02 * i, 1 - 0.02 * i);
    }
    const char *params = "width = 16, height = 8, depth = 24, z_limit = 2";
    {
        char gg[16384];
        snprintf(gg, sizeof gg,
                 SCENE "%s\n"
                       "vol = volumetric_froxel { scene = l30, base = lit, backend = %s, %s }\n"
                       "ref = froxel_closed_form { scene = l30, base = lit, z_limit = 2 }\n"
                       "output vol.inscatter \"ins.exr\" float\noutput ref \"ref.exr\" float\n",
                 extra, backend, params);
        const char *args[] = { "--size", "16x8", NULL };
        lg_image ins = { 0 }, ref = { 0 };
        if (render(t, gg, args, "ins.exr", &ins, NULL) == 0 &&
            lg_test_read(t, "ref.exr", &ref, NULL)) {
            bool finite;
            double r = max_rel(&ins, &ref, 1e-6, &finite);
            lg_test_note_("%s, 32 lights: max relative error %.3g", backend, r);
            LG_TEST_CHECK(t, finite && r < 1e-4, "%s, 32 lights: %.3g against the closed "
                          "form", backend, r);
        } else {
            LG_TEST_FAILF(t, "%s: the 32-light render failed", backend);
        }
        lg_image_free(&ins);
        lg_image_free(&ref);
        /* 33 lights: a clear error */
        snprintf(gg, sizeof gg,
                 SCENE "%s\nl31 = light { scene = l30, direction = [0, -1, 0] }\n"
                       "vol = volumetric_froxel { scene = l31, base = lit, backend = %s, %s }\n"
                       "output vol.inscatter \"ins.exr\" float\n",
                 extra, backend, params);
        char *text = NULL;
        int rc = render(t, gg, args, NULL, NULL, &text);
        LG_TEST_CHECK(t, rc == 1 && text && strstr(text, "32"),
                      "33 lights: status %d, want 1 and a message naming the limit", rc);
        free(text);
    }
    /* the sun behind the camera, travelling along its view (phase at cos = -1) */
    double r = vs_closed_form(t, backend, "width = 16, height = 8, depth = 24, z_limit = 2",
                              "behind = light { scene = fog, mode = replace, direction = "
                              "[-0.224, -0.336, -0.915], intensity = 10 }",
                              "energy_conserving", "2", "16x8");
    LG_TEST_CHECK(t, r >= 0 && r < 1e-4, "%s, sun behind the camera: %.3g against the closed "
                  "form", backend, r);
}

/* ---- shadows --------------------------------------------------------------------------- */

static void shadows(lg_test *t, const char *backend)
{
    char g[4096];
    snprintf(g, sizeof g,
             SCENE "sh = volumetric_froxel { scene = fog, base = lit, shadows = shadow, "
                   "backend = %s, width = 32, height = 18, depth = 32 }\n"
                   "un = volumetric_froxel { scene = fog, base = lit, backend = %s, "
                   "width = 32, height = 18, depth = 32 }\n"
                   "output sh.inscatter \"sh.exr\" float\noutput un.inscatter \"un.exr\" float\n",
             backend, backend);
    const char *args[] = { "--size", "64x36", NULL };
    lg_image sh = { 0 }, un = { 0 };
    if (render(t, g, args, "sh.exr", &sh, NULL) != 0 || !lg_test_read(t, "un.exr", &un, NULL)) {
        LG_TEST_FAILF(t, "%s: the render failed", backend);
        goto done;
    }
    size_t n = (size_t)sh.width * sh.height, less = 0, more = 0;
    for (size_t p = 0; p < n; p++) {
        double a = sh.pixels[4 * p], b = un.pixels[4 * p];
        if (a > b * (1 + 1e-5) + 1e-7)
            more++;
        if (a < b * 0.9)
            less++;
    }
    lg_test_note_("%s: %zu of %zu pixels at least 10%% darker with shadows, %zu brighter",
                  backend, less, n, more);
    LG_TEST_CHECK(t, more == 0, "%s: %zu pixels brighter with shadows than without",
                  backend, more);
    LG_TEST_CHECK(t, less > n / 4, "%s: only %zu of %zu pixels darkened by the shadows "
                  "(the bunny box's walls shadow most of the fog)", backend, less, n);
done:
    lg_image_free(&sh);
    lg_image_free(&un);
}

/* ---- backends agree ---------------------------------------------------------------------- */

static void backends(lg_test *t)
{
    static const char *const be[] = { "cpu", "cl", "gl", NULL };
    static const char *const args[] = { "--size", "64x36", NULL };
    lg_test_backends_desc d = {
        .graph = SCENE "vol = volumetric_froxel { scene = fog, base = lit, shadows = shadow, "
                       "width = 24, height = 12, depth = 40 }\n",
        .node = "vol",
        .backends = be,
        .args = args,
        /* float vs double arithmetic; a sample point on a shadow edge may flip */
        .tol_backends = { .max_abs = 0.05, .rel = 1e-3, .rmse = 2e-3 },
    };
    lg_test_backends(t, &d, NULL);
}

/* ---- temporal ------------------------------------------------------------------------------ */

/* RMSE of vol.inscatter (grid 24x12xD, temporal or not, over `frames`) against a grid of
 * 512 slices. */
static double temporal_rmse(lg_test *t, const char *backend, const char *p, const char *frames,
                            lg_image *keep)
{
    char g[4096];
    snprintf(g, sizeof g,
             SCENE "vol = volumetric_froxel { scene = fog, base = lit, shadows = shadow, "
                   "backend = %s, width = 24, height = 12, %s }\n"
                   "hi = volumetric_froxel { scene = fog, base = lit, shadows = shadow, "
                   "backend = %s, width = 24, height = 12, depth = 512 }\n"
                   "output vol.inscatter \"ins.exr\" float\noutput hi.inscatter \"hi.exr\" float\n",
             backend, p, backend);
    const char *args[] = { "--size", "48x24", "--frames", frames, NULL };
    lg_image a = { 0 }, b = { 0 };
    double r = -1;
    if (render(t, g, args, "ins.exr", &a, NULL) == 0 && lg_test_read(t, "hi.exr", &b, NULL)) {
        double s = 0;
        size_t n = (size_t)a.width * a.height;
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++) {
                double e = a.pixels[4 * i + c] - b.pixels[4 * i + c];
                s += e * e;
            }
        r = sqrt(s / (3.0 * n));
    } else {
        LG_TEST_FAILF(t, "%s %s: the render failed", backend, p);
    }
    if (keep)
        *keep = a;
    else
        lg_image_free(&a);
    lg_image_free(&b);
    return r;
}

static void temporal(lg_test *t, const char *backend)
{
    double off = temporal_rmse(t, backend, "depth = 6", "8", NULL);
    double on = temporal_rmse(t, backend, "depth = 6, temporal = true, history = 0.9", "8",
                              NULL);
    lg_test_note_("%s: 24x12x6 against 24x12x512, RMSE %.4g without temporal, %.4g with "
                  "(8 frames, history 0.9)",
                  backend, off, on);
    LG_TEST_CHECK(t, off > 0 && on >= 0 && on < 0.8 * off,
                  "%s: temporal should lower the error (%.4g -> %.4g)", backend, off, on);
    /* history 0 is temporal off, bit for bit */
    lg_image a = { 0 }, b = { 0 };
    temporal_rmse(t, backend, "depth = 6", "8", &a);
    temporal_rmse(t, backend, "depth = 6, temporal = true, history = 0", "8", &b);
    if (a.pixels && b.pixels)
        LG_TEST_CHECK(t, !memcmp(a.pixels, b.pixels, (size_t)a.width * a.height * 16),
                      "%s: history 0 differs from temporal off", backend);
    lg_image_free(&a);
    lg_image_free(&b);
}

/* ---- errors -------------------------------------------------------------------------------- */

static void errors(lg_test *t)
{
    static const struct { const char *set, *want; int status; } c[] = {
        { "vol.width=0", "width", 2 },
        { "vol.depth=100000", "depth", 2 },
        { "vol.history=1.5", "history", 2 },
        { "vol.z_limit=nan", "z_limit", 2 },
        { "vol.z_near=-1", "z_near", 2 },
        { "vol.z_near=3", "z_near", 1 },
        { "vol.near_offset=5", "near_offset", 1 },
    };
    const char *g = SCENE "vol = volumetric_froxel { scene = fog, base = lit, backend = cpu, "
                          "slicing = exponential, z_limit = 2 }\n"
                          "output vol \"out.exr\" float\n";
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        const char *args[] = { "--size", "8x4", "--set", c[i].set, NULL };
        char *text = NULL;
        int rc = render(t, g, args, NULL, NULL, &text);
        LG_TEST_CHECK(t, rc != 0 && rc != -1 && text && strstr(text, c[i].want) &&
                             strstr(text, "vol"),
                      "--set %s: status %d (want a clean failure naming %s and the node)",
                      c[i].set, rc, c[i].want);
        free(text);
    }
    /* a grid above 1 GiB */
    {
        const char *args[] = { "--size", "8x4", "--set", "vol.width=1024", "--set",
                               "vol.height=1024", "--set", "vol.depth=512", NULL };
        char *text = NULL;
        int rc = render(t, g, args, NULL, NULL, &text);
        LG_TEST_CHECK(t, rc != 0 && rc != -1 && text && strstr(text, "GiB"),
                      "a 8 GiB grid: status %d, want a clean failure", rc);
        free(text);
    }
    /* base without depth: a tone-mapped image */
    {
        const char *g2 = SCENE "tm = reinhard { image = lit }\n"
                               "vol = volumetric_froxel { scene = fog, base = tm, backend = cpu }\n"
                               "output vol \"out.exr\" float\n";
        const char *args[] = { "--size", "8x4", NULL };
        char *text = NULL;
        int rc = render(t, g2, args, NULL, NULL, &text);
        LG_TEST_CHECK(t, rc != 0 && rc != -1 && text && strstr(text, "depth"),
                      "base without depth: status %d, want a clean failure", rc);
        free(text);
    }
}

#define BACKEND_CASES(fn)                                                                  \
    static void fn##_cpu(lg_test *t) { fn(t, "cpu"); }                                     \
    static void fn##_cl(lg_test *t) { fn(t, "cl"); }                                       \
    static void fn##_gl(lg_test *t) { fn(t, "gl"); }
BACKEND_CASES(closed_form)
BACKEND_CASES(thesis)
BACKEND_CASES(lights)
BACKEND_CASES(shadows)
BACKEND_CASES(temporal)

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, FX_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "closed_form_cpu", closed_form_cpu }, { "closed_form_cl", closed_form_cl },
        { "closed_form_gl", closed_form_gl },   { "thesis_cpu", thesis_cpu },
        { "thesis_cl", thesis_cl },             { "thesis_gl", thesis_gl },
        { "lights_cpu", lights_cpu },           { "lights_cl", lights_cl },
        { "lights_gl", lights_gl },             { "shadows_cpu", shadows_cpu },
        { "shadows_cl", shadows_cl },           { "shadows_gl", shadows_gl },
        { "temporal_cpu", temporal_cpu },       { "temporal_cl", temporal_cl },
        { "temporal_gl", temporal_gl },         { "backends", backends },
        { "errors", errors },
    };
    lg_test_main_opts o = { .prefix = "froxel", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
