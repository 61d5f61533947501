/*
 * volumetric_froxel's cpu backend with many shadowed directional lights (the vector loop of
 * froxel_cpu.c's fx_ortho_slices: the orthographic records, their depth bounds per 8 x 8
 * texels, FX_KB slices at a time) against froxel.h computed on the CPU in double by the
 * test plugin testfroxelspec (froxel_spec, shadows by lg_shadowmap_visibility), in one
 * render: the bunny box at the grid's size (each pixel's centre is a column's, so the
 * lookup is compared exactly, froxel.h 3.), energy_conserving, uniform clip slicing from
 * 0.3 to 4 m (the fog beyond the box lies outside every light's tile: lit), the shadowmap
 * node's maps.
 *
 *   dir12    12 lights fanned around the sun, 64^2 tiles; a 31 x 18 x 40 grid: 558 columns
 *            end in a chunk of 14 of its 32 lanes, 40 slices in a block of 8 of its 16
 *   odd_res  hard case: 5 lights, 100^2 tiles (not a whole number of 8 x 8 blocks: the
 *            last row and column of blocks are partial), a 37 x 11 x 23 grid (every chunk
 *            and slice block boundary falls mid-row)
 *
 * Agreement: as test_froxel_gl_lights.c (tol 1e-4 of each channel's largest value, at
 * most 0.5 % of the values beyond it, rmse at most 5 tol): a froxel whose sample point lies
 * within float rounding of a texel's depth or edge may go the other way in float.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/test.h"

#include "froxel_agree.h"
#include "lightgraph/vecmath.h"

static const char *root(void)
{
    const char *r = getenv("LG_SOURCE_ROOT");
    return r ? r : ".";
}

/* n directional lights (the first the sun, the rest fanned around it, as the bench's),
 * every one shadowed with res^2 tiles, on a W x H x D grid rendered at W x H on cpu with the
 * reference beside it; each output pair compared. */
static void run(lg_test *t, int n, int res, int W, int H, int D, const char *what)
{
    char g[8192];
    size_t len = (size_t)
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "scene = gltf { file = \"%s/assets/meshes/bunny_cornell_box.glb\" }\n"
                 "cam = camera { scene = scene, mode = look_at, position = [0.7, 0.6, 0.9], "
                 "target = [-0.5, 0.7, -1.5], fov_deg = 70 }\n"
                 "l0 = light { scene = cam, direction = [0.3, -0.35, 1], intensity = 3 }\n",
                 root());
    for (int l = 1; l < n; l++) {
        /* fanned around the sun, all shining into the box through its opening */
        double a = 2.0 * LG_PI * l / (n - 1);
        len += (size_t)snprintf(g + len, sizeof g - len,
                                "l%d = light { scene = l%d, direction = [%.4f, %.4f, 1], "
                                "intensity = 1 }\n",
                                l, l - 1, 0.3 + 0.25 * cos(a), -0.35 + 0.2 * sin(a));
    }
    len += (size_t)snprintf(
        g + len, sizeof g - len,
        "fog = medium { scene = l%d, density = 1, scattering = [0.3, 0.25, 0.2], "
        "absorption = [0.05, 0.1, 0.2], g = 0.4 }\n"
        "sm = shadowmap { scene = fog, resolution = %d }\n"
        "lit = phong { scene = fog, ambient = [0.05, 0.05, 0.05] }\n"
        "vol = volumetric_froxel { scene = fog, base = lit, shadows = sm, width = %d, "
        "height = %d, depth = %d, backend = cpu, accumulation = energy_conserving, "
        "z_near = 0.3, z_limit = 4 }\n"
        "grid = froxel_grid_image { froxel = vol.grid, width = %d, height = %d, depth = %d }\n"
        "ref = froxel_spec { scene = fog, base = lit, shadows = sm, width = %d, height = %d, "
        "depth = %d, z_near = 0.3, z_limit = 4 }\n"
        "a_out = froxel_agree { got = vol, want = ref.out }\n"
        "a_ins = froxel_agree { got = vol.inscatter, want = ref.inscatter }\n"
        "a_grid = froxel_agree { got = grid, want = ref.grid }\n"
        "output a_out \"a_out.exr\"\n"
        "output a_ins \"a_ins.exr\"\n"
        "output a_grid \"a_grid.exr\"\n",
        n - 1, res, W, H, D, W, H, D, W, H, D);
    LG_TEST_CHECK(t, len < sizeof g, "%s: the graph does not fit", what);
    lg_test_write_text(t, "g.lgraph", g);
    char size[32];
    snprintf(size, sizeof size, "%dx%d", W, H);
    const char *const args[] = { "--size", size, NULL };
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 0, "%s: the render failed (%d): %s", what, rc, text ? text : "");
    free(text);
    if (rc)
        return;
    static const char *const files[] = { "a_out.exr", "a_ins.exr", "a_grid.exr" };
    static const char *const names[] = { "out", "inscatter", "grid" };
    for (int i = 0; i < 3; i++) {
        lg_image m;
        memset(&m, 0, sizeof m);
        bool ok = lg_test_read(t, files[i], &m, NULL);
        LG_TEST_CHECK(t, ok, "%s: no %s", what, files[i]);
        if (!ok)
            continue;
        char w[96];
        snprintf(w, sizeof w, "%s %s cpu vs froxel_spec", what, names[i]);
        froxel_agree_check(t, &m, 1e-4, w);
        lg_image_free(&m);
    }
}

static void case_dir12(lg_test *t)
{
    run(t, 12, 64, 31, 18, 40, "12 lights");
}

static void case_odd_res(lg_test *t)
{
    run(t, 5, 100, 37, 11, 23, "100^2 tiles");
}

/* each case: the test plugins' folder */
static void setup(lg_test *t)
{
    lg_test_use_plugins(t, FX_CPU_DIR_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "dir12", case_dir12 },
        { "odd_res", case_odd_res },
    };
    lg_test_main_opts o = { .prefix = "froxel_cpu_dir", .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
