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
    const char *ref;    /* more parameters of froxel_closed_form (NULL: none); "%G" in it
                         * stands for the froxel node's grid (v<i>.grid) */
} fx_item;

/* Relative RMSE of rgb: sqrt(sum (got - want)^2 / sum want^2). */
static double rel_rmse(const lg_image *got, const lg_image *want)
{
    double e = 0, r = 0;
    size_t n = (size_t)got->width * got->height;
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++) {
            double g = got->pixels[4 * p + c], w = want->pixels[4 * p + c];
            e += (g - w) * (g - w);
            r += w * w;
        }
    return r > 0 ? sqrt(e / r) : sqrt(e);
}

/* Renders every item of `items` (froxel nodes v<i> reading scene `scene`, each beside its
 * closed form r<i>) in one graph at `size` with `extra` graph text, and writes the largest
 * relative error of each v<i>.inscatter into err[i] (-1 when the render failed). */
static void vs_closed_form_batch2(lg_test *t, const char *backend, const char *extra,
                                  const char *scene, const fx_item *items, size_t n,
                                  const char *size, double *err, double *rr)
{
    size_t cap = 16384 + strlen(extra), len = 0;
    char *g = malloc(cap);
    if (!g) {
        LG_TEST_FAILF(t, "out of memory");
        return;
    }
    len += (size_t)snprintf(g + len, cap - len, SCENE "%s\n", extra);
    for (size_t i = 0; i < n; i++) {
        /* the reference's extra parameters, "%G" -> v<i>.grid */
        char ref[512] = "", gname[32];
        snprintf(gname, sizeof gname, "v%zu.grid", i);
        for (const char *r = items[i].ref; r && *r && strlen(ref) + 40 < sizeof ref; r++) {
            if (r[0] == '%' && r[1] == 'G') {
                strcat(ref, gname);
                r++;
            } else {
                strncat(ref, r, 1);
            }
        }
        len += (size_t)snprintf(g + len, cap - len,
                                "v%zu = volumetric_froxel { scene = %s, base = lit, backend = "
                                "%s, %s }\n"
                                "r%zu = froxel_closed_form { scene = %s, base = lit, mode = %s, "
                                "z_limit = %s%s%s }\n"
                                "output v%zu.inscatter \"v%zu.exr\" float\n"
                                "output r%zu \"r%zu.exr\" float\n",
                                i, scene, backend, items[i].params, i, scene, items[i].mode,
                                items[i].zl, *ref ? ", " : "", ref, i, i, i, i);
    }
    const char *args[] = { "--size", size, NULL };
    int rc = render(t, g, args, NULL, NULL, NULL);
    free(g);
    for (size_t i = 0; i < n; i++) {
        err[i] = -1;
        if (rr)
            rr[i] = -1;
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
            if (rr)
                rr[i] = rel_rmse(&ins, &ref);
            LG_TEST_CHECK(t, finite, "%s %s: a value is not finite", backend, items[i].params);
        }
        lg_image_free(&ins);
        lg_image_free(&ref);
    }
}

static void vs_closed_form_batch(lg_test *t, const char *backend, const char *extra,
                                 const char *scene, const fx_item *items, size_t n,
                                 const char *size, double *err)
{
    vs_closed_form_batch2(t, backend, extra, scene, items, n, size, err, NULL);
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

/* ---- point and spot lights (issue 25, froxel.h 4.) ------------------------------------------- */

/* A bulb (the issue's: the sun turned into a point light at [0, 0.9, 0]) and a spot aimed
 * down and away from the camera, whose cone edge crosses the image. */
#define FX_BULB                                                                                    \
    "bulb = light { scene = fog, mode = replace, type = point, position = [0, 0.9, 0], "           \
    "intensity = 2 }\n"
#define FX_SPOT                                                                                    \
    "spot = light { scene = fog, mode = replace, type = spot, position = [0.1, 1.1, -0.2], "       \
    "aim = target, target = [-0.3, 0.5, -1.3], inner_cone_deg = 20, outer_cone_deg = 40, "         \
    "intensity = 4 }\n"

/* Analytic point and spot lights equal froxel.h 4. written out (froxel_closed_form
 * point_slices, every double) at column centres, to float rounding: the bulb and the spot,
 * both slicings, 1, 2 and 8 nodes, and the sample mode (nodes 0) too.
 * Measured (gl / cl, after the rays from vol_ray_matrix): bulb <= 2.6e-5 / 2.3e-5, spot
 * <= 7.1e-5 / 2.1e-5. The spot's largest is column (10, 5), which grazes the outer cone: its
 * value is 1.9e-4 of the image's peak (t ~ 0.01 in C = t^2, relative error 2 dt / t with
 * dt ~ ulp / (cos_inner - cos_outer) ~ 4e-7); against the peak it is 2e-8. The rays were
 * the error before (normalize(unproject(ndc, 0) - eye) in float, 5 mm from the eye: up to
 * 7.8e-6 rad, which made 5e-4 .. 9e-4 of the spot and 1e-4 of the bulb).
 * uniform_clip slices are uniform in 1 / t from the camera's znear (2.6 mm here): every
 * sample point of a 24-slice grid lies within 0.12 m of the eye, where the spot (and a
 * range-0.8 light) give exactly 0, so the sample mode's uniform case takes z_near 0.3. */
static void point_analytic(lg_test *t, const char *backend)
{
    static const struct {
        const char *params, *ref;
    } c[] = {
        { "point_nodes = 2", "nodes = 2" },
        { "point_nodes = 1, slicing = exponential, z_near = 0.3", "nodes = 1" },
        { "point_nodes = 8, slicing = exponential", "nodes = 8" },
        { "point_integration = sample, z_near = 0.3", "nodes = 0" },
        { "point_integration = sample, slicing = exponential", "nodes = 0" },
    };
    const size_t nc = sizeof c / sizeof c[0];
    static const char *const scenes[] = { "bulb", "spot" };
    for (int sc = 0; sc < 2; sc++) {
        char p[8][256], r[8][64];
        fx_item it[8];
        for (size_t i = 0; i < nc; i++) {
            snprintf(p[i], sizeof p[i], "width = 16, height = 8, depth = 24, z_limit = 2, %s",
                     c[i].params);
            snprintf(r[i], sizeof r[i], "grid = %%G, %s", c[i].ref);
            it[i] = (fx_item){ p[i], "point_slices", "2", r[i] };
        }
        double err[8];
        vs_closed_form_batch(t, backend, FX_BULB FX_SPOT, scenes[sc], it, nc, "16x8", err);
        for (size_t i = 0; i < nc; i++) {
            lg_test_note_("%s %s %s: max relative error %.3g against froxel.h 4. in double",
                          backend, scenes[sc], p[i], err[i]);
            LG_TEST_CHECK(t, err[i] >= 0 && err[i] < 1e-4, "%s %s %s: %.3g against point_slices",
                          backend, scenes[sc], p[i], err[i]);
        }
    }
}

/* Both modes converge to the continuous airlight integral (point_exact) as the slices
 * shrink; the analytic one is nearer at every depth. Relative RMSE over the 16x8 column
 * centres, exponential slices from z_near 0.01 to 2 (slice 0 spans the eye to T(1): a
 * z_near far from the eye would leave one long slice at every depth). */
static void point_converge(lg_test *t, const char *backend)
{
    static const int depths[] = { 64, 128, 256 };
    char p[6][256];
    fx_item it[6];
    for (int m = 0; m < 2; m++)
        for (int d = 0; d < 3; d++) {
            snprintf(p[3 * m + d], sizeof p[0],
                     "width = 16, height = 8, depth = %d, slicing = exponential, z_near = 0.01, "
                     "z_limit = 2, point_integration = %s",
                     depths[d], m ? "analytic" : "sample");
            it[3 * m + d] = (fx_item){ p[3 * m + d], "point_exact", "2", NULL };
        }
    double err[6], rr[6];
    vs_closed_form_batch2(t, backend, FX_BULB, "bulb", it, 6, "16x8", err, rr);
    for (int m = 0; m < 2; m++) {
        lg_test_note_("%s bulb, %s: relative RMSE against the airlight integral at 64 / 128 / "
                      "256 slices: %.3g / %.3g / %.3g (max relative %.3g / %.3g / %.3g)",
                      backend, m ? "analytic" : "sample", rr[3 * m], rr[3 * m + 1], rr[3 * m + 2],
                      err[3 * m], err[3 * m + 1], err[3 * m + 2]);
        LG_TEST_CHECK(t,
                      rr[3 * m] > 0 && rr[3 * m + 1] < rr[3 * m] && rr[3 * m + 2] < rr[3 * m + 1],
                      "%s %s: the error should fall with depth (%.3g, %.3g, %.3g)", backend,
                      m ? "analytic" : "sample", rr[3 * m], rr[3 * m + 1], rr[3 * m + 2]);
        LG_TEST_CHECK(t, rr[3 * m + 2] < 0.01, "%s %s: %.3g at 256 slices", backend,
                      m ? "analytic" : "sample", rr[3 * m + 2]);
    }
    /* Where the analytic mode matters: a light on the rays (at the eye) and a coarse grid.
     * The sample misses the 1 / d^2 peak inside slice 0; the analytic slice integral has
     * it, up to X_l and the extinction taken at the sample point. */
    fx_item near[2] = {
        { "width = 16, height = 8, depth = 16, slicing = exponential, z_near = 0.01, "
          "z_limit = 2, point_integration = sample",
          "point_exact", "2", NULL },
        { "width = 16, height = 8, depth = 16, slicing = exponential, z_near = 0.01, "
          "z_limit = 2, point_integration = analytic",
          "point_exact", "2", NULL },
    };
    vs_closed_form_batch2(t, backend,
                          "atcam = light { scene = fog, mode = replace, type = point, position = "
                          "[0.7, 0.6, 0.9], intensity = 2 }\n",
                          "atcam", near, 2, "16x8", err, rr);
    lg_test_note_("%s, the bulb at the eye, 16 slices: relative RMSE sample %.3g, analytic %.3g",
                  backend, rr[0], rr[1]);
    LG_TEST_CHECK(t, rr[1] >= 0 && rr[1] < 0.01 && rr[1] < 0.1 * rr[0],
                  "%s, the bulb at the eye: analytic %.3g, sample %.3g", backend, rr[1], rr[0]);
}

/* Hard cases: the spot's cone edge (lit and dark columns, both to rounding), the camera
 * inside the cone and at the light (finite, to rounding), a light at the camera with a
 * window (range) that ends inside the image, range 0 (infinite). */
static void point_hard(lg_test *t, const char *backend)
{
    const char *extra = FX_SPOT
        /* the camera inside the spot's cone: the spot behind it, aimed along its view */
        "spotcam = light { scene = fog, mode = replace, type = spot, position = [0.9, 0.62, "
        "1.2], aim = target, target = [-0.5, 0.7, -1.5], outer_cone_deg = 30, intensity = 4 }\n"
        /* the bulb at the camera (the eye at the light: finite, the largest values) */
        "atcam = light { scene = fog, mode = replace, type = point, position = [0.7, 0.6, 0.9], "
        "intensity = 2 }\n"
        /* a range that ends inside the fog, and range 0 = infinite */
        "ranged = light { scene = fog, mode = replace, type = point, position = [0, 0.9, 0], "
        "range = 0.8, intensity = 2 }\n";
    static const char *const scenes[] = { "spot", "spotcam", "atcam", "ranged" };
    for (int sc = 0; sc < 4; sc++) {
        fx_item it[2] = {
            { "width = 16, height = 8, depth = 32, z_limit = 2", "point_slices", "2",
              "grid = %G, nodes = 2" },
            /* z_near 0.3: from the camera's znear every sample lies within 0.12 m of the
             * eye, where the spot and the ranged light are 0 (point_analytic) */
            { "width = 16, height = 8, depth = 32, z_limit = 2, point_integration = sample, "
              "z_near = 0.3",
              "point_slices", "2", "grid = %G, nodes = 0" },
        };
        double err[2];
        vs_closed_form_batch(t, backend, extra, scenes[sc], it, 2, "16x8", err);
        for (int i = 0; i < 2; i++) {
            lg_test_note_("%s %s %s: %.3g against point_slices", backend, scenes[sc],
                          i ? "sample" : "analytic", err[i]);
            LG_TEST_CHECK(t, err[i] >= 0 && err[i] < 1e-4, "%s %s %s: %.3g against point_slices",
                          backend, scenes[sc], i ? "sample" : "analytic", err[i]);
        }
    }
    /* the cone edge cuts the image: some columns dark, some lit; a range that ends in the
     * fog darkens what lies beyond it */
    char g[4096];
    snprintf(g, sizeof g,
             SCENE "%s" FX_BULB
                   "s = volumetric_froxel { scene = spot, base = lit, backend = %s, width = 16, "
                   "height = 8, depth = 32, slicing = exponential, z_near = 0.05 }\n"
                   "r = volumetric_froxel { scene = ranged, base = lit, backend = %s, width = 16, "
                   "height = 8, depth = 32, z_limit = 2 }\n"
                   "u = volumetric_froxel { scene = bulb, base = lit, backend = %s, width = 16, "
                   "height = 8, depth = 32, z_limit = 2 }\n"
                   "output s.inscatter \"s.exr\" float\noutput r.inscatter \"r.exr\" float\n"
                   "output u.inscatter \"u.exr\" float\n",
             extra, backend, backend, backend);
    {
        const char *args[] = { "--size", "16x8", NULL };
        lg_image si = { 0 }, ri = { 0 }, ui = { 0 };
        if (render(t, g, args, "s.exr", &si, NULL) == 0 && lg_test_read(t, "r.exr", &ri, NULL) &&
            lg_test_read(t, "u.exr", &ui, NULL)) {
            size_t n = (size_t)si.width * si.height, dark = 0, lit = 0, cut = 0;
            double smax = 0;
            for (size_t q = 0; q < n; q++)
                smax = fmax(smax, si.pixels[4 * q]);
            for (size_t q = 0; q < n; q++) {
                dark += si.pixels[4 * q] == 0.0f; /* a ray that misses the cone: C = 0 */
                lit += si.pixels[4 * q] > 1e-2 * smax;
                cut += ri.pixels[4 * q] < 0.999 * ui.pixels[4 * q];
                LG_TEST_CHECK(t, ri.pixels[4 * q] <= ui.pixels[4 * q] * (1 + 1e-5) + 1e-9,
                              "%s: range 0.8 brighter than range 0 at pixel %zu", backend, q);
            }
            lg_test_note_("%s: spot: %zu dark and %zu lit of %zu columns; range 0.8 darker "
                          "than infinite in %zu",
                          backend, dark, lit, n, cut);
            LG_TEST_CHECK(t, dark > n / 10 && lit >= 4,
                          "%s: the spot's cone edge should cross the image (%zu dark, %zu lit)",
                          backend, dark, lit);
            LG_TEST_CHECK(t, cut > n / 2, "%s: range 0.8 darkens only %zu of %zu columns", backend,
                          cut, n);
        } else {
            LG_TEST_FAILF(t, "%s: the render failed", backend);
        }
        lg_image_free(&si);
        lg_image_free(&ri);
        lg_image_free(&ui);
    }
}

/* ---- heterogeneous media (froxel.h 4.) ------------------------------------------------------- */

/* A uniform field over everything is the homogeneous medium: for a point light the only
 * difference is X_l read from the optical-depth volume (trilinear between exact cell
 * values) instead of e^(-sigma_t d): small, and smaller with tau_res. */
static void field_uniform(lg_test *t, const char *backend)
{
    char g[4096];
    snprintf(g, sizeof g,
             SCENE FX_BULB "uf = froxel_test_field { scene = bulb }\n"
                           "h = volumetric_froxel { scene = bulb, base = lit, backend = %s, "
                           "width = 16, height = 8, depth = 32, z_limit = 2 }\n"
                           "u32 = volumetric_froxel { scene = uf, base = lit, backend = %s, "
                           "width = 16, height = 8, depth = 32, z_limit = 2, tau_res = 32 }\n"
                           "u128 = volumetric_froxel { scene = uf, base = lit, backend = %s, "
                           "width = 16, height = 8, depth = 32, z_limit = 2, tau_res = 128 }\n"
                           "output h \"h.exr\" float\noutput u32 \"u32.exr\" float\n"
                           "output u128 \"u128.exr\" float\n",
             backend, backend, backend);
    const char *args[] = { "--size", "16x8", NULL };
    lg_image h = { 0 }, a = { 0 }, b = { 0 };
    if (render(t, g, args, "h.exr", &h, NULL) != 0 || !lg_test_read(t, "u32.exr", &a, NULL) ||
        !lg_test_read(t, "u128.exr", &b, NULL)) {
        LG_TEST_FAILF(t, "%s: the render failed", backend);
    } else {
        bool fa, fb;
        double ea = max_rel(&a, &h, 1e-6, &fa), eb = max_rel(&b, &h, 1e-6, &fb);
        lg_test_note_("%s: uniform field against the homogeneous medium (out): max relative "
                      "%.3g at tau_res 32, %.3g at 128",
                      backend, ea, eb);
        LG_TEST_CHECK(t, fa && fb, "%s: a value is not finite", backend);
        LG_TEST_CHECK(t, eb < 2e-3 && eb < ea, "%s: uniform field %.3g (tau_res 128), %.3g (32)",
                      backend, eb, ea);
    }
    lg_image_free(&h);
    lg_image_free(&a);
    lg_image_free(&b);
}

/* A fog box and height fog against the single-scattering integral marched finely
 * (froxel_closed_form field_exact) at column centres, a sun and the bulb, relative RMSE
 * over the columns (the grid's error: a slice's density is its sample point's, the
 * optical-depth volume is trilinear). Columns that miss the box are 0 on both sides. */
static void field_exact(lg_test *t, const char *backend)
{
    const char *extra = FX_BULB
        "sunb = light { scene = bulb, direction = [0.4, -0.25, 1], intensity = 3 }\n"
        "box = froxel_test_field { scene = sunb, bounds_min = [-0.6, 0.3, -1.4], "
        "bounds_max = [0.3, 1.1, -0.2] }\n"
        "hf = froxel_test_field { scene = sunb, height_falloff = 3, height_base = 0.5 }\n";
    static const char *const scenes[] = { "box", "hf" };
    for (int sc = 0; sc < 2; sc++) {
        fx_item it[2] = {
            { "width = 16, height = 8, depth = 64, slicing = exponential, z_near = 0.01, "
              "z_limit = 2",
              "field_exact", "2", "steps = 200" },
            { "width = 16, height = 8, depth = 256, slicing = exponential, z_near = 0.01, "
              "z_limit = 2",
              "field_exact", "2", "steps = 200" },
        };
        double err[2], rr[2];
        vs_closed_form_batch2(t, backend, extra, scenes[sc], it, 2, "16x8", err, rr);
        lg_test_note_("%s %s: relative RMSE against the marched integral %.3g (64 slices), "
                      "%.3g (256)",
                      backend, scenes[sc], rr[0], rr[1]);
        /* measured (cpu): box 0.074 -> 0.024, height fog 1.1e-3 -> 9e-5; the box's edges
         * cut slices (all or nothing: first order in the slice length) */
        LG_TEST_CHECK(t, rr[1] >= 0 && rr[1] < 0.03 && rr[1] < 0.5 * rr[0],
                      "%s %s: %.3g at 256 slices, %.3g at 64", backend, scenes[sc], rr[1], rr[0]);
    }
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
        { "vol.point_nodes=9", "point_nodes", 2 },
        { "vol.tau_res=1", "tau_res", 2 },
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
BACKEND_CASES(point_analytic)
BACKEND_CASES(point_converge)
BACKEND_CASES(point_hard)
BACKEND_CASES(field_uniform)
BACKEND_CASES(field_exact)

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
        { "point_analytic_cpu", point_analytic_cpu },
        { "point_analytic_cl", point_analytic_cl },
        { "point_analytic_gl", point_analytic_gl },
        { "point_converge_cpu", point_converge_cpu },
        { "point_converge_cl", point_converge_cl },
        { "point_converge_gl", point_converge_gl },
        { "point_hard_cpu", point_hard_cpu },
        { "point_hard_cl", point_hard_cl },
        { "point_hard_gl", point_hard_gl },
        { "field_uniform_cpu", field_uniform_cpu },
        { "field_uniform_cl", field_uniform_cl },
        { "field_uniform_gl", field_uniform_gl },
        { "field_exact_cpu", field_exact_cpu },
        { "field_exact_cl", field_exact_cl },
        { "field_exact_gl", field_exact_gl },
    };
    lg_test_main_opts o = { .prefix = "froxel", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
