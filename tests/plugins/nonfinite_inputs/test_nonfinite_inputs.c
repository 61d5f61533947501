/*
 * NaN and Inf in an image a node passes on are reported, with their count, by that node
 * (lightgraph/image.h, lg_check_input_finite): a base image of known non-finite pixels
 * (test_vs_base of tests/plugins/volumetric_screen/testvsinputs.c: `nan_pixels` with a NaN
 * red, `inf_pixels` with +Inf green and -Inf blue, so a pixel with two bad channels counts
 * once) through every node that takes a `base`:
 *
 *   background   ibl, on cpu, gl and cl (the probe is a constant written here)
 *   screen       volumetric_screen, on cpu and gl
 *   polygonal    volumetric_polygonal (gl)
 *   froxel       volumetric_froxel, on cpu, gl and cl
 *   reference    volumetric_reference (cpu)
 *   core         core's scale (port 'image') and add (ports 'a' and 'b'), on the cpu
 *
 * Each case renders two frames with the node run in both (--every-frame): the warning
 * "input 'base' (frame 0): N pixels with a NaN or Inf channel" must appear exactly once,
 * with N = nan_pixels + inf_pixels; a clean base gives no such warning. The volumetric
 * nodes run on the bunny box of examples/volumetric_scene.lgraph (sun, fog, shadow map),
 * with the base in place of phong's image. A missing device is a failure.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/test.h"

#define W 32
#define H 24

/* Counts the occurrences of `needle` in `text`. */
static int count_of(const char *text, const char *needle)
{
    int k = 0;
    for (const char *p = text ? strstr(text, needle) : NULL; p; p = strstr(p + 1, needle))
        k++;
    return k;
}

/* Renders `node` (a node text with `base` as its base input, named n) over a base of
 * nan + inf bad pixels, two frames, and checks the warning. */
static void check_node(lg_test *t, const char *scene_text, const char *node, const char *port,
                       int nan, int inf)
{
    char g[4096];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "%s"
             "base = test_vs_base { width = %d, height = %d, depth = 1, nan_pixels = %d, "
             "inf_pixels = %d }\n"
             "n = %s\n"
             "output n \"n.exr\"\n",
             scene_text, W, H, nan, inf, node);
    lg_test_write_text(t, "g.lgraph", g);
    char size[32];
    snprintf(size, sizeof size, "%dx%d", W, H);
    const char *args[] = { "--size", size, "--frames", "2", "--every-frame", NULL };
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    if (rc != 0 && lg_test_output_says_no_device(text ? text : ""))
        LG_TEST_CHECK(t, 0, "%s: no device (a missing device is a failure):\n%s", node,
                      text ? text : "");
    else
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d):\n%s", node, rc, text ? text : "");
    if (rc == 0) {
        char want[160];
        snprintf(want, sizeof want, "input '%s' (frame 0): %d pixel%s with a NaN or Inf channel",
                 port, nan + inf, nan + inf == 1 ? "" : "s");
        int said = count_of(text, "with a NaN or Inf channel");
        if (nan + inf == 0)
            LG_TEST_CHECK(t, said == 0, "%s: a clean base was reported:\n%s", node, text);
        else
            LG_TEST_CHECK(t, said == 1 && count_of(text, want) == 1,
                          "%s: want \"%s\" once (over two frames), got:\n%s", node, want,
                          text ? text : "");
    }
    free(text);
}

static const char *vol_scene(void)
{
    static char s[1024];
    snprintf(s, sizeof s, "include \"%s/examples/volumetric_scene.lgraph\"\n", LG_SOURCE_DIR);
    return s;
}

static void run_port(lg_test *t, const char *scene, const char *const *nodes, size_t n_nodes,
                     const char *port)
{
    static const int cases[][2] = { { 5, 2 }, { 0, 1 }, { 0, 0 } };
    for (size_t k = 0; k < n_nodes; k++)
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++)
            check_node(t, scene, nodes[k], port, cases[c][0], cases[c][1]);
}

static void run_all(lg_test *t, const char *scene, const char *const *nodes, size_t n_nodes)
{
    run_port(t, scene, nodes, n_nodes, "base");
}

static void case_background(lg_test *t)
{
    lg_image p = { 0 };
    lg_image_alloc(&p, 8, 4);
    for (size_t i = 0; i < 32; i++)
        for (int c = 0; c < 4; c++)
            p.pixels[4 * i + c] = 1.0f;
    lg_test_write_exr(t, "probe.exr", &p);
    lg_image_free(&p);
    const char *scene = "s = test_vs_scene { }\n"
                        "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                        "env = environment { scene = s, probe = sky }\n";
    static const char *const nodes[] = {
        "background { scene = env, probe = sky, base = base, backend = cpu }",
        "background { scene = env, probe = sky, base = base, backend = gl }",
        "background { scene = env, probe = sky, base = base, backend = cl }",
    };
    run_all(t, scene, nodes, 3);
}

static void case_screen(lg_test *t)
{
    static const char *const nodes[] = {
        "volumetric_screen { scene = fog, base = base, backend = cpu, samples = 8 }",
        "volumetric_screen { scene = fog, base = base, backend = gl, samples = 8 }",
    };
    run_all(t, vol_scene(), nodes, 2);
}

static void case_polygonal(lg_test *t)
{
    static const char *const nodes[] = {
        "volumetric_polygonal { scene = fog, base = base, shadows = shadow, resolution = 16 }",
    };
    run_all(t, vol_scene(), nodes, 1);
}

static void case_froxel(lg_test *t)
{
    static const char *const nodes[] = {
        "volumetric_froxel { scene = fog, base = base, shadows = shadow, backend = cpu, "
        "width = 16, height = 12, depth = 16 }",
        "volumetric_froxel { scene = fog, base = base, shadows = shadow, backend = gl, "
        "width = 16, height = 12, depth = 16 }",
        "volumetric_froxel { scene = fog, base = base, shadows = shadow, backend = cl, "
        "width = 16, height = 12, depth = 16 }",
    };
    run_all(t, vol_scene(), nodes, 3);
}

static void case_reference(lg_test *t)
{
    static const char *const nodes[] = {
        "volumetric_reference { scene = fog, base = base, steps = 8, spp = 1 }",
    };
    run_all(t, vol_scene(), nodes, 1);
}

/* core's add and scale (cpu), each input by its port's name; add's other input is a clean
 * constant of the same size */
static void case_core(lg_test *t)
{
    static const char *const scale[] = { "scale { image = base, factor = 2 }" };
    run_port(t, "", scale, 1, "image");
    static const char *const add_a[] = { "add { a = base, b = k }" };
    run_port(t, "k = constant { width = 32, height = 24 }\n", add_a, 1, "a");
    static const char *const add_b[] = { "add { a = k, b = base }" };
    run_port(t, "k = constant { width = 32, height = 24 }\n", add_b, 1, "b");
}

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, NF_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "background", case_background }, { "screen", case_screen },
        { "polygonal", case_polygonal },   { "froxel", case_froxel },
        { "reference", case_reference },   { "core", case_core },
    };
    lg_test_main_opts o = { .setup = setup, .prefix = "nonfinite" };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
