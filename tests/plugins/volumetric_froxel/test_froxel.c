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

/* One froxel node against the closed form, in a batch rendered as one graph. */
typedef struct fx_item {
    const char *params; /* the froxel node's parameters (without scene, base, backend) */
    const char *mode;   /* froxel_closed_form's mode */
    const char *zl;     /* its z_limit (the froxel node's) */
} fx_item;

/* Renders every item of `items` (froxel nodes v<i> reading scene `scene`, each beside its
 * closed form r<i>) in one graph at `size` with `extra` graph text, and writes the largest
 * relative error of each v<i>.inscatter into err[i] (-1 when the render failed). */
static void vs_closed_form_batch(lg_test *t, const char *backend, const char *extra,
                                 const char *scene, const fx_item *items, size_t n,
                                 const char *size, double *err)
{
    size_t cap = 16384 + strlen(extra), len = 0;
    char *g = malloc(cap);
    if (!g) {
        LG_TEST_FAILF(t, "out of memory");
        return;
    }
    len += (size_t)snprintf(g + len, cap - len, SCENE "%s\n", extra);
    for (size_t i = 0; i < n; i++)
        len += (size_t)snprintf(g + len, cap - len,
                                "v%zu = volumetric_froxel { scene = %s, base = lit, backend = "
                                "%s, %s }\n"
                                "r%zu = froxel_closed_form { scene = %s, base = lit, mode = %s, "
                                "z_limit = %s }\n"
                                "output v%zu.inscatter \"v%zu.exr\" float\n"
                                "output r%zu \"r%zu.exr\" float\n",
                                i, scene, backend, items[i].params, i, scene, items[i].mode,
                                items[i].zl, i, i, i, i);
    const char *args[] = { "--size", size, NULL };
    int rc = render(t, g, args, NULL, NULL, NULL);
    free(g);
    for (size_t i = 0; i < n; i++) {
        err[i] = -1;
        if (rc != 0) {
            LG_TEST_FAILF(t, "%s %s: the render failed", backend, items[i].params);
            continue;
        }
        char vn[32], rn[32];
        snprintf(vn, sizeof vn, "v%zu.exr", i);
        snprintf(rn, sizeof rn, "r%zu.exr", i);
        lg_image ins = { 0 }, ref = { 0 };
        if (lg_test_read(t, vn, &ins, NULL) && lg_test_read(t, rn, &ref, NULL)) {
            bool finite;
            err[i] = max_rel(&ins, &ref, 1e-6, &finite);
            LG_TEST_CHECK(t, finite, "%s %s: a value is not finite", backend, items[i].params);
        }
        lg_image_free(&ins);
        lg_image_free(&ref);
    }
}

/* ---- closed form: unshadowed, energy_conserving, both slicings, several grids ---------------- */

static void closed_form(lg_test *t, const char *backend)
{
    static const struct {
        const char *grid, *size;
    } grids[] = {
        { "width = 16, height = 8, depth = 24", "16x8" },
        { "width = 1, height = 1, depth = 1", "1x1" },
        { "width = 12, height = 6, depth = 1", "12x6" },
    };
    static const char *const slicings[] = { "uniform_clip", "exponential" };
    /* z_limit 0: the camera's zfar (2.64) behind every surface but the opening's sky;
     * 1.2: most walls behind it; z_near 0.9: the near walls in front of the grid */
    static const struct {
        const char *zl, *extra;
    } ranges[] = {
        { "0", "" },
        { "1.2", "" },
        { "1.2", ", z_near = 0.9" },
        { "2", ", z_near = 0.5, near_offset = 0.6" },
    };
    for (size_t gi = 0; gi < sizeof grids / sizeof grids[0]; gi++) {
        char p[8][256];
        fx_item it[8];
        size_t n = 0;
        for (int si = 0; si < 2; si++)
            for (size_t ri = 0; ri < sizeof ranges / sizeof ranges[0]; ri++) {
                if (ri == 3 && si == 0)
                    continue; /* near_offset: exponential only */
                snprintf(p[n], sizeof p[n], "%s, slicing = %s, z_limit = %s%s", grids[gi].grid,
                         slicings[si], ranges[ri].zl, ranges[ri].extra);
                it[n] = (fx_item){ p[n], "energy_conserving", ranges[ri].zl };
                n++;
            }
        double err[8];
        vs_closed_form_batch(t, backend, "", "fog", it, n, grids[gi].size, err);
        for (size_t i = 0; i < n; i++) {
            lg_test_note_("%s %s: max relative error %.3g", backend, p[i], err[i]);
            LG_TEST_CHECK(t, err[i] >= 0 && err[i] < 1e-4, "%s %s: %.3g against the closed form",
                          backend, p[i], err[i]);
        }
    }
}

/* ---- thesis accumulation --------------------------------------------------------------------- */

/* Unshadowed, the thesis's plain sum S x length gives L_c sigma_s p d at a column's centre
 * for any slicing (S is constant along the column), i.e. the closed form times
 * tau / (1 - e^-tau): exactly what a one-slice grid gives too. */
static void thesis(lg_test *t, const char *backend)
{
    static const char *const p[] = {
        "width = 1, height = 1, depth = 1, accumulation = thesis, z_limit = 2",
        "width = 16, height = 8, depth = 24, accumulation = thesis, z_limit = 2",
        "width = 16, height = 8, depth = 24, slicing = exponential, accumulation = thesis, "
        "z_limit = 2",
    };
    static const char *const size[] = { "1x1", "16x8", "16x8" };
    for (size_t i = 0; i < 3; i++) {
        /* against the thesis sum, and against the closed form, which it must exceed by
         * tau / (1 - e^-tau) */
        fx_item it[2] = { { p[i], "thesis_one_slice", "2" }, { p[i], "energy_conserving", "2" } };
        double err[2];
        vs_closed_form_batch(t, backend, "", "fog", it, 2, size[i], err);
        lg_test_note_("%s %s: %.3g vs the thesis sum, %.3g vs the closed form", backend, p[i],
                      err[0], err[1]);
        LG_TEST_CHECK(t, err[0] >= 0 && err[0] < 1e-4, "%s %s: %.3g against the thesis sum",
                      backend, p[i], err[0]);
        LG_TEST_CHECK(t, err[1] > 1e-2,
                      "%s %s: the thesis sum should exceed the closed form "
                      "(%.3g)",
                      backend, p[i], err[1]);
    }
}

/* ---- 32 lights, a light behind the camera ---------------------------------------------------- */

static void lights(lg_test *t, const char *backend)
{
    /* 31 more suns of varied directions and colours: the closed form sums them */
    char extra[8192] = "", *e = extra;
    for (int i = 0; i < 31; i++) {
        double a = 0.7 * i, y = -0.2 - 0.02 * i;
        char prev[16];
        snprintf(prev, sizeof prev, i ? "l%d" : "fog", i - 1);
        e += sprintf(e,
                     "l%d = light { scene = %s, direction = [%g, %g, %g], intensity = %g, "
                     "color = [1, %g, %g] }\n",
                     i, prev, cos(a), y, sin(a), 0.5 + 0.1 * i, 0.3 + 0.02 * i, 1 - 0.02 * i);
    }
    const char *params = "width = 16, height = 8, depth = 24, z_limit = 2";
    fx_item it = { params, "energy_conserving", "2" };
    double err;
    vs_closed_form_batch(t, backend, extra, "l30", &it, 1, "16x8", &err);
    lg_test_note_("%s, 32 lights: max relative error %.3g", backend, err);
    LG_TEST_CHECK(t, err >= 0 && err < 1e-4, "%s, 32 lights: %.3g against the closed form", backend,
                  err);
    /* 33 lights: a clear error */
    char gg[16384];
    snprintf(gg, sizeof gg,
             SCENE "%s\nl31 = light { scene = l30, direction = [0, -1, 0] }\n"
                   "vol = volumetric_froxel { scene = l31, base = lit, backend = %s, %s }\n"
                   "output vol.inscatter \"ins.exr\" float\n",
             extra, backend, params);
    const char *args[] = { "--size", "16x8", NULL };
    char *text = NULL;
    int rc = render(t, gg, args, NULL, NULL, &text);
    LG_TEST_CHECK(t, rc == 1 && text && strstr(text, "32"),
                  "33 lights: status %d, want 1 and a message naming the limit", rc);
    free(text);
    /* the sun behind the camera, travelling along its view (phase at cos = -1) */
    vs_closed_form_batch(t, backend,
                         "behind = light { scene = fog, mode = replace, direction = "
                         "[-0.224, -0.336, -0.915], intensity = 10 }",
                         "behind", &it, 1, "16x8", &err);
    LG_TEST_CHECK(
        t, err >= 0 && err < 1e-4,
        "%s, sun behind the camera: %.3g against the "
        "closed form",
        backend,
        err); /* thin fog (tau ~ 1e-7 per slice): the segment factor's series, no cancellation; the
               * in-scatter is L_c sigma_s p d to float precision, not zero */
    vs_closed_form_batch(t, backend,
                         "thin = medium { scene = fog, density = 1e-6, scattering = "
                         "[0.1, 0.1, 0.1], g = 0.4 }",
                         "thin", &it, 1, "16x8", &err);
    LG_TEST_CHECK(t, err >= 0 && err < 1e-4,
                  "%s, thin fog (tau -> 0): %.3g against the "
                  "closed form",
                  backend, err);
    /* a coloured medium (sigma_t 0.4, 0.2, 0.15): the backends take a shortcut when sigma_t
     * is grey (one exp per froxel and per factor), this is the per-channel path; every
     * other case here is grey */
    vs_closed_form_batch(t, backend,
                         "tinted = medium { scene = fog, density = 1, scattering = "
                         "[0.1, 0.2, 0.05], absorption = [0.3, 0, 0.1], g = 0.4 }",
                         "tinted", &it, 1, "16x8", &err);
    lg_test_note_("%s, coloured sigma_t: max relative error %.3g", backend, err);
    LG_TEST_CHECK(t, err >= 0 && err < 1e-4,
                  "%s, coloured sigma_t (0.4, 0.2, 0.15): %.3g "
                  "against the closed form",
                  backend, err);
}

/* ---- shadows --------------------------------------------------------------------------------- */

static void shadows(lg_test *t, const char *backend)
{
    char g[4096];
    snprintf(g, sizeof g,
             SCENE "sh = volumetric_froxel { scene = fog, base = lit, shadows = shadow, "
                   "backend = %s, width = 32, height = 18, depth = 32, z_near = 0.2 }\n"
                   "un = volumetric_froxel { scene = fog, base = lit, backend = %s, "
                   "width = 32, height = 18, depth = 32, z_near = 0.2 }\n"
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
    lg_test_note_("%s: %zu of %zu pixels at least 10%% darker with shadows, %zu brighter", backend,
                  less, n, more);
    LG_TEST_CHECK(t, more == 0, "%s: %zu pixels brighter with shadows than without", backend, more);
    LG_TEST_CHECK(t, less > n / 4,
                  "%s: only %zu of %zu pixels darkened by the shadows "
                  "(the bunny box's walls shadow most of the fog)",
                  backend, less, n);
done:
    lg_image_free(&sh);
    lg_image_free(&un);
}

/* ---- backends agree -------------------------------------------------------------------------- */

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

/* ---- temporal -------------------------------------------------------------------------------- */

static double rmse(const lg_image *a, const lg_image *b)
{
    double s = 0;
    size_t n = (size_t)a->width * a->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double e = a->pixels[4 * i + c] - b->pixels[4 * i + c];
            s += e * e;
        }
    return sqrt(s / (3.0 * (double)n));
}

/* Shadowed, so that S varies along a column and the jitter matters: a 24x12x6 grid with
 * and without temporal over 8 frames of a static camera, against 24x12x512. */
static void temporal(lg_test *t, const char *backend)
{
    static const char *const names[] = { "off", "on", "h0", "hi" };
    static const char *const params[] = { "depth = 6", "depth = 6, temporal = true, history = 0.7",
                                          "depth = 6, temporal = true, history = 0",
                                          "depth = 512" };
    char g[4096];
    size_t len = (size_t)snprintf(g, sizeof g, SCENE);
    for (int i = 0; i < 4; i++)
        len += (size_t)snprintf(g + len, sizeof g - len,
                                "%s = volumetric_froxel { scene = fog, base = lit, shadows = "
                                "shadow, backend = %s, width = 24, height = 12, "
                                "slicing = exponential, %s }\n"
                                "output %s.inscatter \"%s.exr\" float\n",
                                names[i], backend, params[i], names[i], names[i]);
    const char *args[] = { "--size", "48x24", "--frames", "8", NULL };
    lg_image im[4] = { { 0 } };
    if (render(t, g, args, NULL, NULL, NULL) != 0) {
        LG_TEST_FAILF(t, "%s: the render failed", backend);
        return;
    }
    bool ok = true;
    for (int i = 0; i < 4; i++) {
        char f[16];
        snprintf(f, sizeof f, "%s.exr", names[i]);
        ok &= lg_test_read(t, f, &im[i], NULL);
    }
    if (ok) {
        double off = rmse(&im[0], &im[3]), on = rmse(&im[1], &im[3]);
        lg_test_note_("%s: 24x12x6 against 24x12x512, RMSE %.4g without temporal, %.4g with "
                      "(8 frames, history 0.7)",
                      backend, off, on);
        LG_TEST_CHECK(t, off > 0 && on < 0.8 * off,
                      "%s: temporal should lower the error (%.4g -> %.4g)", backend, off, on);
        /* history 0 is temporal off, bit for bit */
        LG_TEST_CHECK(t,
                      !memcmp(im[0].pixels, im[2].pixels, (size_t)im[0].width * im[0].height * 16),
                      "%s: history 0 differs from temporal off", backend);
    }
    for (int i = 0; i < 4; i++)
        lg_image_free(&im[i]);
}

/* ---- errors ---------------------------------------------------------------------------------- */

static void errors(lg_test *t)
{
    static const struct {
        const char *set, *want;
        int status;
    } c[] = {
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
        LG_TEST_CHECK(t,
                      rc != 0 && rc != -1 && text && strstr(text, c[i].want) && strstr(text, "vol"),
                      "--set %s: status %d (want a clean failure naming %s and the node)", c[i].set,
                      rc, c[i].want);
        free(text);
    }
    /* a grid above 1 GiB */
    {
        const char *args[] = { "--size",         "8x4",           "--set",
                               "vol.width=1024", "--set",         "vol.height=1024",
                               "--set",          "vol.depth=512", NULL };
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

#define BACKEND_CASES(fn)                                                                          \
    static void fn##_cpu(lg_test *t)                                                               \
    {                                                                                              \
        fn(t, "cpu");                                                                              \
    }                                                                                              \
    static void fn##_cl(lg_test *t)                                                                \
    {                                                                                              \
        fn(t, "cl");                                                                               \
    }                                                                                              \
    static void fn##_gl(lg_test *t)                                                                \
    {                                                                                              \
        fn(t, "gl");                                                                               \
    }
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
        { "closed_form_cpu", closed_form_cpu },
        { "closed_form_cl", closed_form_cl },
        { "closed_form_gl", closed_form_gl },
        { "thesis_cpu", thesis_cpu },
        { "thesis_cl", thesis_cl },
        { "thesis_gl", thesis_gl },
        { "lights_cpu", lights_cpu },
        { "lights_cl", lights_cl },
        { "lights_gl", lights_gl },
        { "shadows_cpu", shadows_cpu },
        { "shadows_cl", shadows_cl },
        { "shadows_gl", shadows_gl },
        { "temporal_cpu", temporal_cpu },
        { "temporal_cl", temporal_cl },
        { "temporal_gl", temporal_gl },
        { "backends", backends },
        { "errors", errors },
    };
    lg_test_main_opts o = { .prefix = "froxel", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
