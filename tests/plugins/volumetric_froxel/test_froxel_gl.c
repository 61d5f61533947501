/*
 * volumetric_froxel's gl backend (three compute passes, plugins/volumetric_froxel/
 * froxel_gl.c) against its cpu backend, through the host, on the bunny box of
 * examples/volumetric_scene.lgraph at a small size. A missing GL device fails.
 *
 *   example_energy   energy_conserving, uniform_clip: `out`, `inscatter` and the grid part
 *                    (read back through testfroxelgrid's froxel_grid_image) agree with
 *                    cpu; a second froxel node whose base is the first's `out` integrates
 *                    the same fog (so out's depth is base's depth) on gl
 *   example_thesis   the thesis's accumulation with exponential slicing, likewise
 *   lights32         32 directional lights, each shadow-mapped (the lights buffer full):
 *                    gl agrees with cpu; a 33rd light is a clear error naming the limit
 *   temporal         temporal = true, history 0.6 over --frames 3 (jittered slices, the
 *                    history volume swapped every frame): gl agrees with cpu
 *   frames           per_frame over --frames 4: the node runs 4 times and allocates no
 *                    more than over 1 frame (the volumes and passes are made once)
 *
 * Agreement. Both compute froxel.h in float, but the cpu backend's geometry is double: a
 * sample point that lies within rounding of a shadow-map texel edge or depth may fall on
 * the other side of it, and that whole froxel (and the rest of its column in the grid)
 * then differs. So a comparison allows a small share of outliers: values whose error
 * exceeds `tol` (1e-4; temporal 1e-3) of their channel's largest value must be at most
 * 0.5 % of all values, and the RMSE (errors in those units) at most 2 tol. Measured: no outlier at all, errors below
 * 1e-5 of the scale (rmse ~1e-6).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#include "froxel_agree.h"

#define GW 32
#define GH 18
#define GD 48

/* a line of information on stderr (measured errors, profile numbers) */
#define note(...) (fprintf(stderr, __VA_ARGS__), fputc('\n', stderr))

static const char *root(void)
{
    const char *r = getenv("LG_SOURCE_ROOT");
    return r ? r : ".";
}

/* Renders graph text g with --set vol.backend=B plus `extra` (NULL-terminated, may be
 * NULL). Returns the exit status; *text (optional) gets the output. */
static int render(lg_test *t, const char *g, const char *backend, const char *const *extra,
                  char **text)
{
    char set[64];
    snprintf(set, sizeof set, "vol.backend=%s", backend);
    const char *args[16] = { "--size", "128x72", "--set", set };
    size_t n = 4;
    for (size_t i = 0; extra && extra[i] && n < 15; i++)
        args[n++] = extra[i];
    args[n] = NULL;
    lg_test_write_text(t, "g.lgraph", g);
    return lg_test_render(t, "g.lgraph", args, text);
}

/* got against want: see "Agreement" above. */
static void agree(lg_test *t, const lg_image *got, const lg_image *want, double tol,
                  const char *what)
{
    LG_TEST_CHECK(t, got->width == want->width && got->height == want->height, "%s: %ux%u vs %ux%u",
                  what, got->width, got->height, want->width, want->height);
    if (got->width != want->width || got->height != want->height)
        return;
    const float *a = got->pixels, *b = want->pixels;
    size_t n = (size_t)got->width * got->height * 4;
    /* a scale per channel: the alpha of inscatter (1) must not hide errors in its rgb */
    double sc[4] = { 0, 0, 0, 0 };
    for (size_t i = 0; i < n; i++)
        if (isfinite(b[i]) && fabs(b[i]) > sc[i % 4])
            sc[i % 4] = fabs(b[i]);
    double scale = fmax(fmax(sc[0], sc[1]), sc[2]);
    double sq = 0, worst = 0;
    size_t over = 0, bad = 0, at = 0;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(a[i]) || !isfinite(b[i])) {
            bad++;
            continue;
        }
        double e = fabs((double)a[i] - b[i]) / (sc[i % 4] > 0 ? sc[i % 4] : 1.0);
        sq += e * e;
        if (e > tol)
            over++;
        if (e > worst) {
            worst = e;
            at = i;
        }
    }
    double rmse = sqrt(sq / n);
    size_t px = at / 4;
    note("%s: rgb scale %.4g, max error %.3g of its channel's scale at (%zu, %zu) c%zu "
         "(got %.6g, want %.6g), rmse %.3g, %zu of %zu beyond %g",
         what, scale, worst, px % got->width, px / got->width, at % 4, (double)a[at], (double)b[at],
         rmse, over, n, tol);
    froxel_agree_verdict(t, scale, rmse, over, bad, n, tol, what);
}

static bool read(lg_test *t, const char *file, lg_image *img)
{
    memset(img, 0, sizeof *img);
    return lg_test_read(t, file, img, NULL);
}

/* The example with node `vol` (parameters `params`), its grid as an image, and outputs
 * out.exr, ins.exr, grid.exr. `lights` replaces the example's sun when not NULL. */
static void graph(char *g, size_t size, const char *params)
{
    snprintf(g, size,
             "lightgraph 1\n"
             "include \"%s/examples/volumetric_scene.lgraph\"\n"
             "vol = volumetric_froxel { scene = fog, base = lit, shadows = shadow, width = %d,"
             " height = %d, depth = %d, %s }\n"
             "grid = froxel_grid_image { froxel = vol.grid, width = %d, height = %d,"
             " depth = %d }\n"
             "output vol \"out.exr\"\n"
             "output vol.inscatter \"ins.exr\"\n"
             "output grid \"grid.exr\"\n",
             root(), GW, GH, GD, params, GW, GH, GD);
}

/* Renders g on cpu and gl and compares the three outputs. */
static void gl_vs_cpu(lg_test *t, const char *g, const char *const *extra, double tol,
                      const char *what)
{
    static const char *const files[] = { "out.exr", "ins.exr", "grid.exr" };
    lg_image ref[3], got[3];
    memset(ref, 0, sizeof ref);
    memset(got, 0, sizeof got);
    int rc = render(t, g, "cpu", extra, NULL);
    LG_TEST_CHECK(t, rc == 0, "%s: the cpu render failed (%d)", what, rc);
    for (int i = 0; rc == 0 && i < 3; i++)
        read(t, files[i], &ref[i]);
    int rg = render(t, g, "gl", extra, NULL);
    LG_TEST_CHECK(t, rg == 0, "%s: the gl render failed (%d)", what, rg);
    for (int i = 0; rg == 0 && i < 3; i++)
        read(t, files[i], &got[i]);
    if (rc == 0 && rg == 0)
        for (int i = 0; i < 3; i++) {
            char w[96];
            snprintf(w, sizeof w, "%s %s gl vs cpu", what, files[i]);
            agree(t, &got[i], &ref[i], tol, w);
        }
    for (int i = 0; i < 3; i++) {
        lg_image_free(&ref[i]);
        lg_image_free(&got[i]);
    }
}

static void case_example_energy(lg_test *t)
{
    char g[2048];
    graph(g, sizeof g, "accumulation = energy_conserving");
    gl_vs_cpu(t, g, NULL, 1e-4, "energy_conserving");

    /* out carries base's depth: a second node on `out` sees the same surfaces */
    char g2[2600];
    snprintf(g2, sizeof g2,
             "%svol2 = volumetric_froxel { scene = fog, base = vol, shadows = shadow, "
             "width = %d, height = %d, depth = %d, backend = gl }\n"
             "output vol2.inscatter \"ins2.exr\"\n",
             g, GW, GH, GD);
    int rc = render(t, g2, "gl", NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "the chained render failed (%d)", rc);
    lg_image a, b;
    if (rc == 0 && read(t, "ins.exr", &a) && read(t, "ins2.exr", &b)) {
        lg_test_tol tol = { .max_abs = 1e-6, .rel = 1e-6 };
        lg_test_check_image(t, &b, &a, 32, &tol, "inscatter of a froxel node on vol's out");
        lg_image_free(&a);
        lg_image_free(&b);
    }
}

static void case_example_thesis(lg_test *t)
{
    char g[2048];
    graph(g, sizeof g, "accumulation = thesis, slicing = exponential, near_offset = 0.5");
    gl_vs_cpu(t, g, NULL, 1e-4, "thesis exponential");
}

/* The example's scene with n directional lights (the sun's chain replaced). */
static void lights_graph(char *g, size_t size, int n)
{
    int k = snprintf(g, size,
                     "lightgraph 1\n"
                     "scene = gltf { file = \"%s/assets/meshes/bunny_cornell_box.glb\" }\n"
                     "cam = camera { scene = scene, mode = look_at, position = [0.55, 1.45, "
                     "0.95], target = [-0.05, 0.55, -1.5], fov_deg = 70 }\n",
                     root());
    for (int i = 0; i < n; i++) {
        /* directions spread over a cone around the sun's, colours varied; each light
         * node adds one to the scene of the one before */
        double a = LG_TWO_PI * i / n, r = 0.25 + 0.02 * (i % 5);
        char prev[16];
        if (i)
            snprintf(prev, sizeof prev, "l%d", i - 1);
        else
            strcpy(prev, "cam");
        k += snprintf(g + k, size - (size_t)k,
                      "l%d = light { scene = %s, direction = [%.4f, %.4f, 1], "
                      "color = [%.3f, %.3f, %.3f], intensity = 0.4 }\n",
                      i, prev, 0.3 + r * cos(a), -0.35 + r * sin(a), 0.5 + 0.5 * (i % 3 == 0),
                      0.5 + 0.5 * (i % 3 == 1), 0.5 + 0.5 * (i % 3 == 2));
    }
    snprintf(g + k, size - (size_t)k,
             "fog = medium { scene = l%d, density = 1, scattering = [0.1, 0.1, 0.1], "
             "absorption = [0.05, 0.05, 0.05], g = 0.4 }\n"
             "shadow = shadowmap { scene = fog, resolution = 128 }\n"
             "lit = phong { scene = fog, shadows = shadow, ambient = [0.05, 0.05, 0.05] }\n"
             "vol = volumetric_froxel { scene = fog, base = lit, shadows = shadow, width = %d,"
             " height = %d, depth = %d }\n"
             "grid = froxel_grid_image { froxel = vol.grid, width = %d, height = %d,"
             " depth = %d }\n"
             "output vol \"out.exr\"\n"
             "output vol.inscatter \"ins.exr\"\n"
             "output grid \"grid.exr\"\n",
             n - 1, GW, GH, GD, GW, GH, GD);
}

static void case_lights32(lg_test *t)
{
    static char g[16384];
    lights_graph(g, sizeof g, 32);
    gl_vs_cpu(t, g, NULL, 1e-4, "32 lights");

    lights_graph(g, sizeof g, 33);
    char *text = NULL;
    int rc = render(t, g, "gl", NULL, &text);
    LG_TEST_CHECK(t, rc != 0, "33 directional lights were accepted");
    LG_TEST_CHECK(t, text && strstr(text, "vol") && strstr(text, "32"),
                  "the error names neither the node nor the limit: %s", text ? text : "");
    free(text);
}

static void case_temporal(lg_test *t)
{
    char g[2048];
    graph(g, sizeof g, "temporal = true, history = 0.6");
    static const char *const frames[] = { "--frames", "3", NULL };
    /* the reprojection lands on cell centres only up to rounding: float puts the previous
     * slice coordinate ~1e-4 slices off where double does not, and S jumps between slices
     * at shadow edges (measured: 1 % of inscatter's values beyond 1e-4, none beyond 3e-4) */
    gl_vs_cpu(t, g, frames, 1e-3, "temporal, 3 frames");
}

/* "bytes_allocated" and "runs" of node `vol` in a --profile-json file. */
static bool profile_of(lg_test *t, const char *file, unsigned long long *alloc,
                       unsigned long long *runs)
{
    FILE *f = fopen(lg_test_path(t, file), "rb");
    if (!f)
        return false;
    static char buf[1 << 16];
    size_t len = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[len] = 0;
    char *p = strstr(buf, "\"name\": \"vol\"");
    char *a = p ? strstr(p, "\"bytes_allocated\": ") : NULL;
    char *r = p ? strstr(p, "\"runs\": ") : NULL;
    if (!a || !r)
        return false;
    *alloc = strtoull(a + 19, NULL, 10);
    *runs = strtoull(r + 8, NULL, 10);
    return true;
}

static void case_frames(lg_test *t)
{
    char g[2048];
    graph(g, sizeof g, "per_frame = true");
    static const char *const one[] = { "--frames", "1", "--profile-json", "p1.json", NULL };
    static const char *const four[] = { "--frames", "4", "--profile-json", "p4.json", NULL };
    int rc1 = render(t, g, "gl", one, NULL), rc4 = render(t, g, "gl", four, NULL);
    LG_TEST_CHECK(t, rc1 == 0 && rc4 == 0, "renders failed (%d, %d)", rc1, rc4);
    unsigned long long a1 = 0, r1 = 0, a4 = 0, r4 = 0;
    bool ok = profile_of(t, "p1.json", &a1, &r1) && profile_of(t, "p4.json", &a4, &r4);
    LG_TEST_CHECK(t, ok, "no profile of node vol");
    note("vol: 1 frame %llu runs, %llu bytes; 4 frames %llu runs, %llu bytes", r1, a1, r4, a4);
    LG_TEST_CHECK(t, r4 == 4, "vol ran %llu times over 4 frames", r4);
    /* the two S volumes (2 x 16 bytes a cell) at least */
    LG_TEST_CHECK(t, a1 >= 2ull * GW * GH * GD * 16, "vol allocated %llu bytes", a1);
    LG_TEST_CHECK(t, a4 == a1, "vol allocated %llu bytes over 4 frames, %llu over 1", a4, a1);
}

/* each case: the test plugin's folder, an empty cache */
static void setup(lg_test *t)
{
    lg_test_use_plugins(t, FX_GL_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "example_energy", case_example_energy },
        { "example_thesis", case_example_thesis },
        { "lights32", case_lights32 },
        { "temporal", case_temporal },
        { "frames", case_frames },
    };
    lg_test_main_opts o = { .prefix = "froxel_gl", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
