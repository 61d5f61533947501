/*
 * volumetric_froxel's cl backend (plugins/volumetric_froxel/froxel_cl.c) with point and
 * spot lights, their shadows and a heterogeneous medium (froxel.h 4.), through the host, in
 * the bunny box at a small size, against froxel.h's grid computed in double by the test
 * plugin testfroxellocal (froxel_spec_grid; it shares only vol_common, lightgraph/medium.h
 * and lg_shadowmap_visibility with the node). A missing CL device fails.
 *
 *   point      a point light of 3 cd with a range, unshadowed
 *   spot       a spot light (cone 20 / 35 degrees) aimed at the floor, unshadowed
 *   shadows    both, shadowed through test_local_shadows' hand-made maps (six cube faces for
 *              the point light, one perspective map for the spot, PCF radius 1): agrees,
 *              and the shadows take at least 5 % of the in-scattering away (so the test sees
 *              them)
 *   field      both shadowed plus a directional sun, in an fBm x height-fog density field
 *              (test_field): agrees, and differs from the homogeneous medium by at least
 *              5 %
 *   pcf_absurd a PCF radius of 4000 texels on 16-texel tiles: refused (exit 1, a message
 *              naming the node, the radius and the tile size, no output file)
 * Every case also checks the lookup: z_limit = 0.5 ends the fog before every surface (the
 * lights stand within it), so each pixel's fog ends in the last slice, and at the grid's
 * own size (pixel centre = column centre) inscatter is the grid's last slice and out = base
 * x alpha + inscatter (sigma_t grey: the grid's alpha is the column's transmittance
 * e^(-sigma_t P)).
 *
 * Agreement as test_froxel_gl.c's (the existing tolerance): values whose error exceeds 1e-4
 * of their channel's largest value at most 0.5 % of all values (a sample within rounding of
 * a shadow texel's edge may land on the other side in float), RMSE at most 5e-4.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/test.h"

#define GW 24
#define GH 16
#define GD 40

#define note(...) (fprintf(stderr, __VA_ARGS__), fputc('\n', stderr))

static const char *root(void)
{
    const char *r = getenv("LG_SOURCE_ROOT");
    return r ? r : ".";
}

/* got against want (see the head comment); returns the RMSE. */
static double agree(lg_test *t, const lg_image *got, const lg_image *want, double tol,
                    const char *what)
{
    LG_TEST_CHECK(t, got->width == want->width && got->height == want->height, "%s: %ux%u vs %ux%u",
                  what, got->width, got->height, want->width, want->height);
    if (got->width != want->width || got->height != want->height)
        return INFINITY;
    const float *a = got->pixels, *b = want->pixels;
    size_t n = (size_t)got->width * got->height * 4;
    double sc[4] = { 0, 0, 0, 0 };
    for (size_t i = 0; i < n; i++)
        if (isfinite(b[i]) && fabs(b[i]) > sc[i % 4])
            sc[i % 4] = fabs(b[i]);
    double sq = 0, worst = 0;
    size_t over = 0, bad = 0, at = 0;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(a[i]) || !isfinite(b[i])) {
            bad++;
            continue;
        }
        double e = fabs((double)a[i] - b[i]) / (sc[i % 4] > 0 ? sc[i % 4] : 1.0);
        sq += e * e;
        over += e > tol;
        if (e > worst) {
            worst = e;
            at = i;
        }
    }
    double rmse = sqrt(sq / n);
    note("%s: rgb scale %.4g, max error %.3g at value %zu (got %.6g, want %.6g), rmse %.3g, "
         "%zu of %zu beyond %g",
         what, fmax(fmax(sc[0], sc[1]), sc[2]), worst, at, (double)a[at], (double)b[at], rmse, over,
         n, tol);
    LG_TEST_CHECK(t, sc[0] > 0 || sc[1] > 0 || sc[2] > 0, "%s: the reference is black", what);
    LG_TEST_CHECK(t, bad == 0, "%s: %zu values are not finite", what, bad);
    LG_TEST_CHECK(t, over <= n / 200, "%s: %zu values (of %zu) differ by more than %g", what, over,
                  n, tol);
    LG_TEST_CHECK(t, rmse <= 5 * tol, "%s: rmse %g > %g", what, rmse, 5 * tol);
    return rmse;
}

/* The mean of an image's rgb. */
static double mean_rgb(const lg_image *im)
{
    const float *p = im->pixels;
    double s = 0;
    size_t n = (size_t)im->width * im->height;
    for (size_t i = 0; i < n; i++)
        s += p[4 * i] + p[4 * i + 1] + p[4 * i + 2];
    return s / (3.0 * (double)n);
}

/* The graph: the bunny box lit by `lights` (light nodes chained from `cam`, the last named
 * `lights`), fog (through test_field when `field`), the froxel node on cl with `shadows`
 * ("" = none; else the node that `shadow_node` defines), its grid, the spec grid, base and
 * the outputs. */
static void graph(char *g, size_t size, const char *lights, bool field, const char *shadows,
                  const char *shadow_node)
{
    char sh[64] = "";
    if (shadows[0])
        snprintf(sh, sizeof sh, ", shadows = %s", shadows);
    snprintf(
        g, size,
        "lightgraph 1\n"
        "scene = gltf { file = \"%s/assets/meshes/bunny_cornell_box.glb\" }\n"
        "cam = camera { scene = scene, mode = look_at, position = [0, 0.9, 0.6], "
        "target = [0, 1.5, -1.5], fov_deg = 60 }\n"
        "%s"
        "%s = medium { scene = lights, density = 1, scattering = [0.3, 0.3, 0.3], "
        "absorption = [0.1, 0.1, 0.1], g = 0.3 }\n"
        "%s"
        "%s"
        "lit = phong { scene = fog, ambient = [0.05, 0.05, 0.05] }\n"
        "vol = volumetric_froxel { scene = fog, base = lit%s, width = %d, height = %d, "
        "depth = %d, z_limit = 0.5, accumulation = energy_conserving, backend = cl, "
        "point_integration = sample }\n"
        "grid = froxel_grid_image { froxel = vol.grid, width = %d, height = %d, depth = %d }\n"
        "spec = froxel_spec_grid { scene = fog, base = lit, froxel = vol.grid%s, "
        "width = %d, height = %d, depth = %d }\n"
        "output lit \"base.exr\"\n"
        "output vol \"out.exr\"\n"
        "output vol.inscatter \"ins.exr\"\n"
        "output grid \"grid.exr\"\n"
        "output spec \"spec.exr\"\n",
        root(), lights, field ? "fog0" : "fog",
        field
            ? "fog = test_field { scene = fog0, frequency = 4, octaves = 1, scale = 2, "
              "offset = -0.3, height_falloff = 1.5, height_base = 0.8, box_min = [-0.7, 0.5, -0.4], "
              "box_max = [0.7, 1.5, 0.7] }\n"
            : "",
        shadow_node, sh, GW, GH, GD, GW, GH, GD, sh, GW, GH, GD);
}

/* Renders g; reads grid, spec, base, out, ins. */
static bool run(lg_test *t, const char *g, lg_image im[5], const char *what)
{
    static const char *const files[5] = { "grid.exr", "spec.exr", "base.exr", "out.exr",
                                          "ins.exr" };
    memset(im, 0, 5 * sizeof *im);
    char size[32];
    snprintf(size, sizeof size, "%dx%d", GW, GH);
    const char *args[] = { "--size", size, NULL };
    lg_test_write_text(t, "g.lgraph", g);
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 0, "%s: the render failed (%d): %s", what, rc, text ? text : "");
    free(text);
    bool ok = rc == 0;
    for (int i = 0; ok && i < 5; i++)
        ok = lg_test_read(t, files[i], &im[i], NULL);
    LG_TEST_CHECK(t, ok, "%s: an output is missing", what);
    return ok;
}

static void free5(lg_image im[5])
{
    for (int i = 0; i < 5; i++)
        lg_image_free(&im[i]);
}

/* The lookup against the grid's last slice (see the head comment). */
static void check_lookup(lg_test *t, lg_image im[5], const char *what)
{
    const float *grid = im[0].pixels, *base = im[2].pixels, *out = im[3].pixels,
                *ins = im[4].pixels;
    double scale = 0, e_ins = 0, e_out = 0;
    for (size_t i = 0; i < (size_t)GW * GH * 4; i++)
        if (i % 4 < 3)
            scale = fmax(scale, fabs(ins[i]));
    for (int y = 0; y < GH; y++)
        for (int x = 0; x < GW; x++) {
            const float *gl = grid + 4 * ((size_t)((GD - 1) * GH + y) * GW + x);
            size_t p = 4 * ((size_t)y * GW + x);
            for (int c = 0; c < 3; c++) {
                e_ins = fmax(e_ins, fabs(ins[p + c] - gl[c]) / scale);
                /* out's error in units of its own size (base is up to about 1) */
                e_out = fmax(e_out, fabs(out[p + c] - (base[p + c] * gl[3] + ins[p + c])) /
                                        fmax(scale, fabs(out[p + c])));
            }
        }
    note("%s: lookup: inscatter vs the grid's last slice %.3g, out vs base T + L_v %.3g "
         "(scale %.4g)",
         what, e_ins, e_out, scale);
    LG_TEST_CHECK(t, scale > 0, "%s: inscatter is black", what);
    LG_TEST_CHECK(t, e_ins <= 1e-4, "%s: inscatter differs from the grid's last slice by %g", what,
                  e_ins);
    LG_TEST_CHECK(t, e_out <= 1e-4, "%s: out differs from base x T + inscatter by %g", what, e_out);
}

static const char point_light[] =
    "lights = light { scene = cam, mode = replace, type = point, position = [-0.15, 0.95, 0.25], "
    "color = [1, 0.8, 0.6], intensity = 3, range = 4 }\n";
static const char spot_light[] =
    "lights = light { scene = cam, mode = replace, type = spot, position = [0.15, 1.25, 0.3], "
    "direction = [-0.2, -1, -0.1], inner_cone_deg = 20, outer_cone_deg = 35, "
    "color = [0.6, 0.8, 1], intensity = 4 }\n";
static const char both_lights[] =
    "l0 = light { scene = cam, mode = replace, type = point, position = [-0.15, 0.95, 0.25], "
    "color = [1, 0.8, 0.6], intensity = 3, range = 4 }\n"
    "lights = light { scene = l0, type = spot, position = [0.15, 1.25, 0.3], "
    "direction = [-0.2, -1, -0.1], inner_cone_deg = 20, outer_cone_deg = 35, "
    "color = [0.6, 0.8, 1], intensity = 4 }\n";
static const char three_lights[] =
    "l0 = light { scene = cam, mode = replace, type = point, position = [-0.15, 0.95, 0.25], "
    "color = [1, 0.8, 0.6], intensity = 3, range = 4 }\n"
    "l1 = light { scene = l0, type = spot, position = [0.15, 1.25, 0.3], "
    "direction = [-0.2, -1, -0.1], inner_cone_deg = 20, outer_cone_deg = 35, "
    "color = [0.6, 0.8, 1], intensity = 4 }\n"
    "lights = light { scene = l1, direction = [0.4, -0.25, 1], intensity = 2 }\n";
static const char local_shadows[] =
    "sm = test_local_shadows { scene = fog, resolution = 64, wall = 0.2, pcf_radius = 1 }\n";

/* One light set: the grid and the lookup agree; returns the spec grid's mean (or -1). */
static double light_case(lg_test *t, const char *lights, bool field, bool shadowed,
                         const char *what)
{
    static char g[8192];
    graph(g, sizeof g, lights, field, shadowed ? "sm" : "", shadowed ? local_shadows : "");
    lg_image im[5];
    double mean = -1;
    if (run(t, g, im, what)) {
        char w[96];
        snprintf(w, sizeof w, "%s: cl grid vs froxel.h's", what);
        agree(t, &im[0], &im[1], 1e-4, w);
        check_lookup(t, im, what);
        mean = mean_rgb(&im[1]);
    }
    free5(im);
    return mean;
}

static void case_point(lg_test *t)
{
    light_case(t, point_light, false, false, "point");
}

static void case_spot(lg_test *t)
{
    light_case(t, spot_light, false, false, "spot");
}

static void case_shadows(lg_test *t)
{
    double lit = light_case(t, both_lights, false, false, "point + spot unshadowed");
    double sh = light_case(t, both_lights, false, true, "point + spot shadowed");
    note("mean in-scattering: unshadowed %.5g, shadowed %.5g", lit, sh);
    LG_TEST_CHECK(t, lit > 0 && sh >= 0 && sh < 0.95 * lit,
                  "the shadows take %.3g %% of the in-scattering away (at least 5 %% expected)",
                  100.0 * (1.0 - sh / lit));
}

static void case_field(lg_test *t)
{
    double hom = light_case(t, three_lights, false, true, "three lights homogeneous");
    double het = light_case(t, three_lights, true, true, "three lights in a field");
    note("mean in-scattering: homogeneous %.5g, field %.5g", hom, het);
    LG_TEST_CHECK(t, hom > 0 && het >= 0 && fabs(het - hom) > 0.05 * hom,
                  "the field changes the in-scattering by %.3g %% only", 100.0 * (het / hom - 1));
}

/* A PCF radius larger than the map's tiles is refused with a message naming it (the
 * kernel would take (2 r + 1)^2 taps per sample), exit status 1, no output file. */
static void case_pcf_absurd(lg_test *t)
{
    static char g[8192];
    graph(g, sizeof g, point_light, false, "sm",
          "sm = test_local_shadows { scene = fog, resolution = 16, wall = 0.2, "
          "pcf_radius = 4000 }\n");
    lg_test_write_text(t, "g.lgraph", g);
    char size[32];
    snprintf(size, sizeof size, "%dx%d", GW, GH);
    const char *args[] = { "--size", size, NULL };
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    note("pcf_radius 4000: exit %d: %s", rc, text ? text : "");
    LG_TEST_CHECK(t, rc == 1, "pcf_radius 4000 on 16-texel tiles: exit status %d, not 1", rc);
    LG_TEST_CHECK(t,
                  text && strstr(text, "vol") && strstr(text, "pcf_radius 4000") &&
                      strstr(text, "16"),
                  "the error names neither the node, the radius nor the tile: %s",
                  text ? text : "");
    FILE *f = fopen(lg_test_path(t, "out.exr"), "rb");
    LG_TEST_CHECK(t, f == NULL, "out.exr was written");
    if (f)
        fclose(f);
    free(text);
}

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, FX_CL_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "point", case_point },           { "spot", case_spot },
        { "shadows", case_shadows },       { "field", case_field },
        { "pcf_absurd", case_pcf_absurd },
    };
    lg_test_main_opts o = { .prefix = "froxel_cl", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
