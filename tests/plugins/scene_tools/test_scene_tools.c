/*
 * The scene_tools plugin (camera, light, medium, environment) through the host: `test_scene_tools CASE`.
 * Scenes come from the test plugin `testcube` (this folder): `test_cube` makes a real
 * lg_scene in memory, `test_scene_probe` writes what a scene holds into a 1-row EXR
 * (layout in testcube.c). `test_fog` (tests/plugins/testnodes) needs a medium and a light.
 *
 *   features      --explain prints each derived scene's features: lights by type, medium
 *                 yes/no and density, triangles unchanged
 *   gating        test_fog gated on the plain cube, kept after light + medium, gated again
 *                 by medium { density = 0 } after a foggy scene and without a light; its
 *                 plugin is loaded only when kept
 *   environment   `environment` attaches a probe: features say "probe yes"; test_mirror
 *                 (tests/plugins/testnodes: needs a reflective material and a probe, as
 *                 reflect does) is gated with "no light probe" without it and "no reflective
 *                 material" on a cube of reflectivity 0, kept and run with both; the count of
 *                 reflective materials is of materials, not instances, and 0 when no
 *                 instance draws the material
 *   look_at       position, target, fov, aspect as given; up unit and orthogonal; clip
 *                 planes from the bounds hold every corner, explicit ones are kept; the
 *                 active camera is replaced, or added to a scene without one
 *   orbit         for several azimuths, elevations (the poles included) and aspects, every
 *                 corner of the bounds projects inside the frustum; the distance follows the
 *                 documented formula; an explicit distance is in bounding radii
 *   lights        three chained `light` nodes give 3 lights (add) in order, normalised, with
 *                 colour, intensity, point position and range; a last `replace` leaves 1
 *   medium        coefficients and g reach the scene; density 0 removes it
 *   sharing       a chain of derived scenes points `geometry` at the source's resource and
 *                 shares its meshes, instances and materials; the source's own is NULL
 *   sharing_gl    the GL buffers of a derived scene's mesh are the source's (skips without GL)
 *   sharing_cl    the same for CL buffers, which hold the mesh's own data (skips without CL)
 *   errors        bad parameters and inputs exit 1 with a message naming the node and why
 *   field         the medium's density field (ABI 3.2) through test_field_probe: field =
 *                 none keeps the homogeneous medium (no field, m = 1, features.medium_field
 *                 0) and warns about height fog or a box it ignores; uniform with height fog
 *                 and a box is e^(-k (y - base)) inside the closed box and 0 outside; fbm
 *                 carries every parameter and equals scale max(0, lg_fbm3 - offset); another
 *                 seed gives another field; density 0 leaves no medium, so no field feature
 *   field_errors each refusal of the medium node exits 1 (2 for a declared range) and
 *                 names the parameter, the file, the grid or the voxel: a flat or inside-out
 *                 box, frequency 0, gain 1, a height fog that overflows the scene, an empty
 *                 vdb path, a missing file, a folder, a (sparse) file over the 1 GiB cap;
 *                 with OpenVDB also vdb_scale 0, a text
 *                 file, a truncated file, a file without a float grid, an unknown grid name
 *                 (the file's grids listed), a level set, an empty grid, 2^30 voxels made
 *                 dense, a frustum transform, a negative or NaN voxel; without OpenVDB,
 *                 field = vdb itself, with a message saying what to install
 *   vdb           (with OpenVDB) the files make_vdb_cloud writes at build time read back:
 *                 one_voxel.vdb's first float grid (a vec3 grid before it is skipped), its
 *                 size, value and transform, and the field at world points equal to
 *                 OpenVDB's own trilinear sample there (tools::BoxSampler, written by the
 *                 tool); grid = other picks the other grid; vdb_scale and vdb_translate move
 *                 it; rotated.vdb (scaled, rotated, moved) and a 16^3 cloud agree with
 *                 OpenVDB's samples within 1e-5
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "lightgraph/medium.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/test.h"

#ifndef PT_TESTNODES_DIR
#define PT_TESTNODES_DIR ""
#endif
#ifndef ST_TESTCUBE_DIR
#define ST_TESTCUBE_DIR ""
#endif
/* the build folder holding make_vdb_cloud's fixtures ("" without OpenVDB) */
#ifndef ST_VDB_DIR
#define ST_VDB_DIR ""
#endif

#define DEG (LG_PI / 180.0)

static void use_test_plugins(lg_test *t)
{
    static char path[8300];
    if (*PT_TESTNODES_DIR && *ST_TESTCUBE_DIR)
        snprintf(path, sizeof path, "%s:%s", ST_TESTCUBE_DIR, PT_TESTNODES_DIR);
    lg_test_use_plugins(t, path);
}

/* Renders `graph` (text) and returns the exit status; *out gets what the program printed. */
static int render_text(lg_test *t, const char *graph, const char *const *args, char **out)
{
    lg_test_write_text(t, "g.lgraph", graph);
    return lg_test_render(t, "g.lgraph", args, out);
}

/* The probe image written to probe.exr by a graph ending in `output probe "probe.exr"`. */
static bool run_probe(lg_test *t, const char *graph, const char *const *args, lg_image *img)
{
    char *out = NULL;
    int rc = render_text(t, graph, args, &out);
    free(out);
    LG_TEST_CHECK(t, rc == 0, "render failed (exit %d)", rc);
    if (rc)
        return false;
    unsigned bits = 0;
    if (!lg_test_read(t, "probe.exr", img, &bits))
        return false;
    LG_TEST_CHECK(t, bits == 32, "probe.exr has %u bits per channel, want 32", bits);
    return true;
}

static const float *px(const lg_image *img, uint32_t x)
{
    static const float none[4] = { NAN, NAN, NAN, NAN };
    return x < img->width ? img->pixels + (size_t)x * 4 : none;
}

static lg_vec3 px3(const lg_image *img, uint32_t x)
{
    const float *p = px(img, x);
    return lg_v3(p[0], p[1], p[2]);
}

static bool near3(lg_vec3 a, lg_vec3 b, float tol)
{
    return fabsf(a.x - b.x) <= tol && fabsf(a.y - b.y) <= tol && fabsf(a.z - b.z) <= tol;
}

/* The line of `text` that starts with `prefix` (after leading spaces), copied, or NULL. */
static char *line_with(const char *text, const char *prefix)
{
    for (const char *l = text; l && *l;) {
        const char *e = strchr(l, '\n');
        size_t len = e ? (size_t)(e - l) : strlen(l);
        const char *s = l;
        while (s < l + len && *s == ' ')
            s++;
        if (strncmp(s, prefix, strlen(prefix)) == 0) {
            char *r = malloc(len + 1);
            memcpy(r, l, len);
            r[len] = 0;
            return r;
        }
        l = e ? e + 1 : NULL;
    }
    return NULL;
}

/* The explain table's state column ("kept", "gated", "culled") of node `name`. */
static const char *state_of(const char *text, const char *name)
{
    static char state[16];
    char prefix[128];
    snprintf(prefix, sizeof prefix, "%s ", name);
    char *l = line_with(text, prefix);
    state[0] = 0;
    if (l) {
        char node[64], type[64];
        if (sscanf(l, "%63s %63s %15s", node, type, state) != 3)
            state[0] = 0;
        free(l);
    }
    return state;
}

/* True if the "scene features (name): ..." line contains `what`. */
static bool features_say(const char *text, const char *name, const char *what)
{
    char prefix[128];
    snprintf(prefix, sizeof prefix, "scene features (%s):", name);
    char *l = line_with(text, prefix);
    bool ok = l && strstr(l, what);
    free(l);
    return ok;
}

static bool plugin_loaded(const char *text, const char *plugin)
{
    char *l = line_with(text, "plugins loaded:");
    bool ok = false;
    if (l) {
        char word[64];
        snprintf(word, sizeof word, " %s", plugin);
        char *p = strstr(l, word);
        ok = p && (p[strlen(word)] == ' ' || p[strlen(word)] == 0);
        free(l);
    }
    return ok;
}

/* ---- cases ----------------------------------------------------------------------------------- */

static void case_features(lg_test *t)
{
    const char *g = "lightgraph 1\n"
                    "cube = test_cube { instances = 2 }\n"
                    "sun  = light { scene = cube, direction = [1, -1, 0] }\n"
                    "lamp = light { scene = sun, type = point, position = [0, 3, 0] }\n"
                    "fog  = medium { scene = lamp, density = 0.5 }\n"
                    "off  = medium { scene = fog, density = 0 }\n"
                    "p1 = test_scene_probe { scene = fog }\n"
                    "p2 = test_scene_probe { scene = off }\n"
                    "output p1 \"p1.exr\"\n"
                    "output p2 \"p2.exr\"\n";
    const char *args[] = { "--explain", NULL };
    char *out = NULL;
    int rc = render_text(t, g, args, &out);
    LG_TEST_CHECK(t, rc == 0, "render failed: %s", out ? out : "");
    const char *o = out ? out : "";
    LG_TEST_CHECK(t,
                  features_say(o, "cube",
                               "triangles 24, vertices 48, lights: 0 directional, 0 point"),
                  "cube features: %s", o);
    LG_TEST_CHECK(t, features_say(o, "cube", "medium no (density 0)"), "cube medium: %s", o);
    LG_TEST_CHECK(t,
                  features_say(o, "sun",
                               "triangles 24, vertices 48, lights: 1 directional, 0 point"),
                  "sun features: %s", o);
    LG_TEST_CHECK(t, features_say(o, "lamp", "lights: 1 directional, 1 point"), "lamp features: %s",
                  o);
    LG_TEST_CHECK(t, features_say(o, "lamp", "medium no"), "lamp medium: %s", o);
    LG_TEST_CHECK(t, features_say(o, "fog", "lights: 1 directional, 1 point"), "fog lights: %s", o);
    LG_TEST_CHECK(t, features_say(o, "fog", "medium yes (density 0.5)"), "fog medium: %s", o);
    LG_TEST_CHECK(t, features_say(o, "off", "medium no (density 0)"), "off medium: %s", o);
    LG_TEST_CHECK(t, features_say(o, "off", "triangles 24,"), "off triangles: %s", o);
    LG_TEST_CHECK(t, plugin_loaded(o, "scene_tools"), "scene_tools not loaded: %s", o);
    LG_TEST_CHECK(t, strcmp(state_of(o, "sun"), "kept") == 0, "sun is %s", state_of(o, "sun"));
    LG_TEST_CHECK(t, strcmp(state_of(o, "off"), "kept") == 0, "off is %s", state_of(o, "off"));
    free(out);

    lg_image img;
    unsigned bits;
    if (lg_test_read(t, "p1.exr", &img, &bits)) {
        LG_TEST_CHECK(t,
                      px(&img, 5)[3] == 1 && px(&img, 6)[3] == 1 && px(&img, 7)[3] == 1 &&
                          px(&img, 8)[3] == 24,
                      "p1: lg_scene.features medium %g dir %g point %g triangles %g",
                      (double)px(&img, 5)[3], (double)px(&img, 6)[3], (double)px(&img, 7)[3],
                      (double)px(&img, 8)[3]);
        lg_image_free(&img);
    }
    if (lg_test_read(t, "p2.exr", &img, &bits)) {
        LG_TEST_CHECK(t, px(&img, 5)[3] == 0 && px(&img, 5)[0] == 0,
                      "p2: medium present %g, features.medium %g", (double)px(&img, 5)[0],
                      (double)px(&img, 5)[3]);
        lg_image_free(&img);
    }
}

static void gating_case(lg_test *t, const char *what, const char *chain, const char *scene,
                        bool kept, const char *reason)
{
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "cube = test_cube {}\n"
             "%s"
             "fogfx = test_fog { scene = %s, value = 0.5 }\n"
             "output fogfx \"fog.exr\"\n",
             chain, scene);
    const char *args[] = { "--explain", "--size", "4x2", NULL };
    char *out = NULL;
    int rc = render_text(t, g, args, &out);
    const char *o = out ? out : "";
    LG_TEST_CHECK(t, rc == 0, "%s: render failed: %s", what, o);
    const char *st = state_of(o, "fogfx");
    LG_TEST_CHECK(t, strcmp(st, kept ? "kept" : "gated") == 0, "%s: test_fog is '%s', want %s:\n%s",
                  what, st, kept ? "kept" : "gated", o);
    if (!kept) {
        char *l = line_with(o, "fogfx ");
        LG_TEST_CHECK(t, l && strstr(l, reason), "%s: the reason is not '%s': %s", what, reason,
                      l ? l : "");
        free(l);
    }
    LG_TEST_CHECK(t, plugin_loaded(o, "testfog") == kept, "%s: testfog %s:\n%s", what,
                  kept ? "not loaded though kept" : "loaded though gated", o);
    free(out);
    lg_image img;
    if (lg_test_read(t, "fog.exr", &img, NULL)) {
        float want = kept ? 0.5f : 0.0f;
        LG_TEST_CHECK(t,
                      img.width == 4 && img.height == 2 && img.pixels[0] == want &&
                          img.pixels[4 * 7 + 1] == want,
                      "%s: fog image %ux%u, value %g, want %g", what, img.width, img.height,
                      (double)img.pixels[0], (double)want);
        lg_image_free(&img);
    }
}

static void case_gating(lg_test *t)
{
    gating_case(t, "plain cube", "", "cube", false, "no participating medium");
    gating_case(t, "light only", "sun = light { scene = cube }\n", "sun", false,
                "no participating medium");
    gating_case(t, "medium only", "m = medium { scene = cube, density = 0.3 }\n", "m", false,
                "no light");
    gating_case(t, "light + medium",
                "sun = light { scene = cube }\nm = medium { scene = sun, density = 0.3 }\n", "m",
                true, NULL);
    gating_case(t, "medium + light",
                "m = medium { scene = cube, density = 0.3 }\nsun = light { scene = m }\n", "sun",
                true, NULL);
    gating_case(t, "density 0 after a medium",
                "sun = light { scene = cube }\nm = medium { scene = sun, density = 0.3 }\n"
                "off = medium { scene = m, density = 0 }\n",
                "off", false, "no participating medium");
    gating_case(t, "density 0 alone",
                "sun = light { scene = cube }\noff = medium { scene = sun, density = 0 }\n", "off",
                false, "no participating medium");
    gating_case(t, "a camera keeps what it gets",
                "sun = light { scene = cube }\nm = medium { scene = sun, density = 0.3 }\n"
                "cam = camera { scene = m }\n",
                "cam", true, NULL);
}

/* One graph: `chain` derives scene `scene` from `cube` (test_cube with `cube_params`),
 * test_mirror reads it. Checks the features line of `scene`, test_mirror's state and reason,
 * whether testfog was loaded, and the image it wrote (0.25 when kept, 0 when gated). */
static void mirror_case(lg_test *t, const char *what, const char *cube_params, const char *chain,
                        const char *scene, const char *features, bool kept, const char *reason)
{
    const char *probe_file = lg_test_asset("probes/studio_512x256_half_dwab.exr");
    LG_TEST_CHECK(t, probe_file != NULL, "assets/probes/studio_512x256_half_dwab.exr is missing");
    if (!probe_file)
        return;
    char g[4096];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "cube = test_cube { %s }\n"
             "sky = probe { file = \"%s\" }\n"
             "%s"
             "mirror = test_mirror { scene = %s, value = 0.25 }\n"
             "output mirror \"mirror.exr\"\n",
             cube_params, probe_file, chain, scene);
    const char *args[] = { "--explain", "--size", "4x2", NULL };
    char *out = NULL;
    int rc = render_text(t, g, args, &out);
    const char *o = out ? out : "";
    LG_TEST_CHECK(t, rc == 0, "%s: render failed: %s", what, o);
    LG_TEST_CHECK(t, features_say(o, scene, features),
                  "%s: the features of '%s' do not say '%s':\n%s", what, scene, features, o);
    const char *st = state_of(o, "mirror");
    LG_TEST_CHECK(t, strcmp(st, kept ? "kept" : "gated") == 0,
                  "%s: test_mirror is '%s', want %s:\n%s", what, st, kept ? "kept" : "gated", o);
    if (!kept) {
        char *l = line_with(o, "mirror ");
        LG_TEST_CHECK(t, l && strstr(l, reason), "%s: the reason is not '%s': %s", what, reason,
                      l ? l : "");
        free(l);
    }
    LG_TEST_CHECK(t, plugin_loaded(o, "testfog") == kept, "%s: testfog %s:\n%s", what,
                  kept ? "not loaded though kept" : "loaded though gated", o);
    free(out);
    lg_image img;
    if (lg_test_read(t, "mirror.exr", &img, NULL)) {
        float want = kept ? 0.25f : 0.0f;
        LG_TEST_CHECK(t,
                      img.width == 4 && img.height == 2 && img.pixels[0] == want &&
                          img.pixels[4 * 7 + 2] == want,
                      "%s: mirror image %ux%u, value %g, want %g", what, img.width, img.height,
                      (double)img.pixels[0], (double)want);
        lg_image_free(&img);
    }
}

static void case_environment(lg_test *t)
{
    const char *env = "env = environment { scene = cube, probe = sky }\n";
    mirror_case(t, "reflective cube, no probe", "reflectivity = 0.5", "", "cube",
                "probe no; specular material no; reflective materials 1", false, "no light probe");
    mirror_case(t, "probe, cube of reflectivity 0", "", env, "env",
                "probe yes; specular material no; reflective materials 0", false,
                "no reflective material");
    mirror_case(t, "probe and a reflective cube", "reflectivity = 0.5", env, "env",
                "probe yes; specular material no; reflective materials 1", true, NULL);
    /* three instances of the one reflective material: one reflective material */
    mirror_case(t, "three instances", "reflectivity = 0.04, instances = 3", env, "env",
                "triangles 36, vertices 72,", true, NULL);
    mirror_case(t, "three instances count one material", "reflectivity = 0.04, instances = 3", env,
                "env", "reflective materials 1", true, NULL);
    /* no instance draws the material: it does not count, the node is gated */
    mirror_case(t, "a material nobody draws", "reflectivity = 1, instances = 0", env, "env",
                "triangles 0, vertices 0,", false, "no reflective material");
    /* the environment keeps through a derived scene downstream, and the camera keeps it */
    mirror_case(t, "camera after environment", "reflectivity = 1",
                "env = environment { scene = cube, probe = sky }\ncam = camera { scene = env }\n",
                "cam", "probe yes; specular material no; reflective materials 1", true, NULL);
    mirror_case(t, "environment after camera", "reflectivity = 1",
                "cam = camera { scene = cube }\nenv = environment { scene = cam, probe = sky }\n",
                "env", "probe yes; specular material no; reflective materials 1", true, NULL);
}

/* Depths of the bounds' corners along the view direction lie within [znear, zfar]. */
static void check_clip(lg_test *t, const char *what, const lg_image *img)
{
    lg_vec3 eye = px3(img, 0), target = px3(img, 1);
    lg_vec3 f = lg_v3_normalize_or(lg_v3_sub(target, eye), lg_v3(0, 0, 0));
    lg_vec3 lo = px3(img, 8), hi = px3(img, 9);
    float zn = px(img, 1)[3], zf = px(img, 2)[3];
    LG_TEST_CHECK(t, zn > 0 && zf > zn, "%s: znear %g zfar %g", what, (double)zn, (double)zf);
    for (int k = 0; k < 8; k++) {
        lg_vec3 c = lg_v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
        float d = lg_v3_dot(lg_v3_sub(c, eye), f);
        LG_TEST_CHECK(t, d >= zn && d <= zf, "%s: corner %d at depth %g outside [%g, %g]", what, k,
                      (double)d, (double)zn, (double)zf);
    }
}

static void check_up(lg_test *t, const char *what, const lg_image *img)
{
    lg_vec3 eye = px3(img, 0), target = px3(img, 1), up = px3(img, 2);
    lg_vec3 f = lg_v3_normalize_or(lg_v3_sub(target, eye), lg_v3(0, 0, 0));
    LG_TEST_CHECK(t, fabsf(lg_v3_length(up) - 1) < 1e-5f, "%s: |up| = %g", what,
                  (double)lg_v3_length(up));
    LG_TEST_CHECK(t, fabsf(lg_v3_dot(up, f)) < 1e-5f, "%s: up . view = %g", what,
                  (double)lg_v3_dot(up, f));
}

static void case_look_at(lg_test *t)
{
    const char *g =
        "lightgraph 1\n"
        "cube = test_cube { half_size = [1, 0.5, 2] }\n"
        "cam = camera { scene = cube, mode = look_at, position = [1, 2, 6], target = [0.5, 0, 0],\n"
        "               fov_deg = 60, aspect = 2 }\n"
        "probe = test_scene_probe { scene = cam }\n"
        "output probe \"probe.exr\"\n";
    lg_image img;
    if (!run_probe(t, g, NULL, &img))
        return;
    LG_TEST_CHECK(t, near3(px3(&img, 0), lg_v3(1, 2, 6), 0), "position");
    LG_TEST_CHECK(t, near3(px3(&img, 1), lg_v3(0.5f, 0, 0), 0), "target");
    LG_TEST_CHECK(t, fabs(px(&img, 0)[3] - 60 * DEG) < 1e-6, "yfov %g", (double)px(&img, 0)[3]);
    LG_TEST_CHECK(t, px(&img, 3)[3] == 2, "aspect %g", (double)px(&img, 3)[3]);
    LG_TEST_CHECK(t, px(&img, 3)[1] == 1 && px(&img, 3)[2] == 0,
                  "the active camera is replaced: %g cameras, active %g", (double)px(&img, 3)[1],
                  (double)px(&img, 3)[2]);
    check_up(t, "look_at", &img);
    /* up stays in the plane of the view direction and world up, on world up's side */
    lg_vec3 f = lg_v3_normalize_or(lg_v3_sub(px3(&img, 1), px3(&img, 0)), lg_v3(0, 0, 0));
    lg_vec3 side = lg_v3_cross(f, lg_v3(0, 1, 0));
    LG_TEST_CHECK(t, fabsf(lg_v3_dot(px3(&img, 2), side)) < 1e-5f && px(&img, 2)[1] > 0,
                  "up leaves the plane of view and world up");
    check_clip(t, "look_at", &img);
    lg_image_free(&img);

    /* a scene without a camera gets one */
    const char *g1 = "lightgraph 1\n"
                     "cube = test_cube { camera = false }\n"
                     "cam = camera { scene = cube, mode = look_at, position = [0, 0, 7] }\n"
                     "probe = test_scene_probe { scene = cam }\n"
                     "output probe \"probe.exr\"\n";
    if (run_probe(t, g1, NULL, &img)) {
        LG_TEST_CHECK(t,
                      px(&img, 3)[1] == 1 && px(&img, 3)[2] == 0 &&
                          near3(px3(&img, 0), lg_v3(0, 0, 7), 0),
                      "no camera: %g cameras, active %g", (double)px(&img, 3)[1],
                      (double)px(&img, 3)[2]);
        lg_image_free(&img);
    }

    /* explicit planes are kept; a camera inside the box gets a usable near plane */
    const char *g2 =
        "lightgraph 1\n"
        "cube = test_cube { half_size = [3, 3, 3] }\n"
        "cam = camera { scene = cube, mode = look_at, position = [0, 0, 1], target = [0, 0, 0],\n"
        "               znear = 0.25, zfar = 40 }\n"
        "cam2 = camera { scene = cube, mode = look_at, position = [0, 0, 1], target = [0, 0, 0] }\n"
        "probe = test_scene_probe { scene = cam }\n"
        "probe2 = test_scene_probe { scene = cam2 }\n"
        "output probe \"probe.exr\"\n"
        "output probe2 \"probe2.exr\"\n";
    if (!run_probe(t, g2, NULL, &img))
        return;
    LG_TEST_CHECK(t, px(&img, 1)[3] == 0.25f && px(&img, 2)[3] == 40, "explicit planes %g %g",
                  (double)px(&img, 1)[3], (double)px(&img, 2)[3]);
    lg_image_free(&img);
    if (lg_test_read(t, "probe2.exr", &img, NULL)) {
        float zn = px(&img, 1)[3], zf = px(&img, 2)[3];
        /* farthest corner: 3 + 1 = 4 along -Z, plus the 1 % margin */
        LG_TEST_CHECK(t, fabsf(zf - 4.04f) < 1e-4f && zn > 0 && fabsf(zn - zf * 1e-3f) < 1e-6f,
                      "inside the box: znear %g zfar %g", (double)zn, (double)zf);
        lg_image_free(&img);
    }
}

/* Projects the bounds' corners with the probe's camera at `aspect`: all inside clip space. */
static void check_framed(lg_test *t, const char *what, const lg_image *img, float aspect)
{
    float view[16], proj[16], vp[16];
    lg_m4_look_at(view, px3(img, 0), px3(img, 1), px3(img, 2));
    lg_m4_perspective(proj, px(img, 0)[3], aspect, px(img, 1)[3], px(img, 2)[3]);
    lg_m4_mul(vp, proj, view);
    lg_vec3 lo = px3(img, 8), hi = px3(img, 9);
    float maxabs = 0;
    for (int k = 0; k < 8; k++) {
        float p[4] = { k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z, 1 }, c[4];
        for (int r = 0; r < 4; r++)
            c[r] = vp[r] * p[0] + vp[4 + r] * p[1] + vp[8 + r] * p[2] + vp[12 + r] * p[3];
        LG_TEST_CHECK(t, c[3] > 0, "%s: corner %d behind the camera", what, k);
        if (!(c[3] > 0))
            continue;
        for (int a = 0; a < 3; a++) {
            float ndc = c[a] / c[3];
            LG_TEST_CHECK(t, ndc >= -1 && ndc <= 1, "%s: corner %d: ndc[%d] = %g outside [-1, 1]",
                          what, k, a, (double)ndc);
            if (a < 2 && fabsf(ndc) > maxabs)
                maxabs = fabsf(ndc);
        }
    }
    /* the fit is not wasteful either: the scene fills a good part of the image */
    LG_TEST_CHECK(t, maxabs > 0.3f, "%s: the scene spans only %g of the half image", what,
                  (double)maxabs);
}

static void case_orbit(lg_test *t)
{
    static const struct {
        double az, el, fov;
        int w, h;
    } v[] = {
        { 0, 20, 45, 64, 32 },    { 135, -30, 45, 32, 96 }, { 45, 90, 60, 64, 64 },
        { -60, -90, 30, 50, 50 }, { 300, 5, 120, 200, 20 }, { 10, 89.99, 45, 40, 30 },
    };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        char g[1024], what[128], size[32];
        snprintf(what, sizeof what, "orbit az %g el %g fov %g %dx%d", v[i].az, v[i].el, v[i].fov,
                 v[i].w, v[i].h);
        snprintf(
            g, sizeof g,
            "lightgraph 1\n"
            "cube = test_cube { instances = 3, half_size = [1, 2, 0.5], center = [5, -1, 2] }\n"
            "cam = camera { scene = cube, mode = orbit, azimuth_deg = %.17g,\n"
            "               elevation_deg = %.17g, fov_deg = %.17g }\n"
            "probe = test_scene_probe { scene = cam }\n"
            "output probe \"probe.exr\"\n",
            v[i].az, v[i].el, v[i].fov);
        snprintf(size, sizeof size, "%dx%d", v[i].w, v[i].h);
        const char *args[] = { "--size", size, NULL };
        lg_image img;
        if (!run_probe(t, g, args, &img))
            continue;
        lg_vec3 lo = px3(&img, 8), hi = px3(&img, 9);
        lg_vec3 c = lg_v3_scale(lg_v3_add(lo, hi), 0.5f);
        float r = 0.5f * lg_v3_length(lg_v3_sub(hi, lo));
        LG_TEST_CHECK(t, near3(px3(&img, 1), c, 1e-5f), "%s: target is not the bounds' centre",
                      what);
        /* the documented distance: 1.1 r / sin(min(half fov y, half fov x)) */
        double a = (double)v[i].w / v[i].h, hy = 0.5 * v[i].fov * DEG, hx = atan(tan(hy) * a);
        double want = 1.1 * r / sin(hx < hy ? hx : hy);
        lg_vec3 off = lg_v3_sub(px3(&img, 0), c);
        double got = lg_v3_length(off);
        LG_TEST_CHECK(t, fabs(got - want) < 1e-4 * want, "%s: distance %g, want %g", what, got,
                      want);
        double az = v[i].az * DEG, el = v[i].el * DEG;
        lg_vec3 dir = lg_v3((float)(cos(el) * sin(az)), (float)sin(el), (float)(cos(el) * cos(az)));
        LG_TEST_CHECK(t, near3(lg_v3_scale(off, 1.0f / (float)got), dir, 1e-5f),
                      "%s: the camera is not at the azimuth and elevation", what);
        check_up(t, what, &img);
        check_framed(t, what, &img, (float)a);
        check_clip(t, what, &img);
        lg_image_free(&img);
    }

    /* the pole keeps the orientation of its neighbourhood: up at 90 is the limit of 89.99 */
    lg_image a, b;
    const char *ga = "lightgraph 1\ncube = test_cube {}\n"
                     "cam = camera { scene = cube, azimuth_deg = 30, elevation_deg = 90 }\n"
                     "probe = test_scene_probe { scene = cam }\noutput probe \"probe.exr\"\n";
    const char *gb = "lightgraph 1\ncube = test_cube {}\n"
                     "cam = camera { scene = cube, azimuth_deg = 30, elevation_deg = 89.99 }\n"
                     "probe = test_scene_probe { scene = cam }\noutput probe \"probe.exr\"\n";
    if (run_probe(t, ga, NULL, &a)) {
        if (run_probe(t, gb, NULL, &b)) {
            LG_TEST_CHECK(t, near3(px3(&a, 2), px3(&b, 2), 1e-3f), "up at the pole jumps");
            lg_image_free(&b);
        }
        lg_image_free(&a);
    }

    /* an explicit distance is in bounding radii (default elevation 20, azimuth 0) */
    const char *g = "lightgraph 1\ncube = test_cube { half_size = [1, 2, 2] }\n"
                    "cam = camera { scene = cube, mode = orbit, distance = 3 }\n"
                    "probe = test_scene_probe { scene = cam }\noutput probe \"probe.exr\"\n";
    lg_image img;
    if (run_probe(t, g, NULL, &img)) {
        lg_vec3 e = px3(&img, 0);
        LG_TEST_CHECK(t,
                      near3(e, lg_v3(0, 9 * (float)sin(20 * DEG), 9 * (float)cos(20 * DEG)), 1e-5f),
                      "distance 3 x radius 3: eye [%g, %g, %g]", (double)e.x, (double)e.y,
                      (double)e.z);
        check_clip(t, "distance 3", &img);
        lg_image_free(&img);
    }
}

static void check_light(lg_test *t, const lg_image *img, uint32_t i, int type, lg_vec3 dir,
                        lg_vec3 color, float intensity, lg_vec3 pos, float range)
{
    uint32_t x = 10 + 4 * i;
    LG_TEST_CHECK(t, px(img, x)[3] == (float)type, "light %u: type %g, want %d", i,
                  (double)px(img, x)[3], type);
    LG_TEST_CHECK(t, near3(px3(img, x), dir, 1e-6f), "light %u: direction [%g, %g, %g]", i,
                  (double)px(img, x)[0], (double)px(img, x)[1], (double)px(img, x)[2]);
    LG_TEST_CHECK(t, near3(px3(img, x + 1), color, 0) && px(img, x + 1)[3] == intensity,
                  "light %u: colour or intensity", i);
    LG_TEST_CHECK(t, near3(px3(img, x + 2), pos, 0) && px(img, x + 2)[3] == range,
                  "light %u: position or range", i);
}

static void case_lights(lg_test *t)
{
    const char *g =
        "lightgraph 1\n"
        "cube = test_cube {}\n"
        "l1 = light { scene = cube, direction = [3, -4, 0], color = [1, 0.5, 0.25], intensity = 3 }\n"
        "l2 = light { scene = l1, type = point, position = [0, 4, 1], range = 10, intensity = 50 }\n"
        "l3 = light { scene = l2, direction = [0, 0, -2] }\n"
        "probe = test_scene_probe { scene = l3 }\n"
        "output probe \"probe.exr\"\n";
    lg_image img;
    if (run_probe(t, g, NULL, &img)) {
        LG_TEST_CHECK(t, px(&img, 3)[0] == 3 && img.width == 10 + 12, "3 lights: %g",
                      (double)px(&img, 3)[0]);
        LG_TEST_CHECK(t, px(&img, 6)[3] == 2 && px(&img, 7)[3] == 1, "features: %g dir, %g point",
                      (double)px(&img, 6)[3], (double)px(&img, 7)[3]);
        lg_vec3 z = lg_v3(0, 0, 0), w = lg_v3(1, 1, 1);
        check_light(t, &img, 0, 0, lg_v3(0.6f, -0.8f, 0), lg_v3(1, 0.5f, 0.25f), 3, z, 0);
        check_light(t, &img, 1, 1, z, w, 50, lg_v3(0, 4, 1), 10);
        check_light(t, &img, 2, 0, lg_v3(0, 0, -1), w, 1, z, 0);
        lg_image_free(&img);
    }
    const char *g2 =
        "lightgraph 1\n"
        "cube = test_cube {}\n"
        "l1 = light { scene = cube }\n"
        "l2 = light { scene = l1, direction = [1, 0, 0] }\n"
        "l3 = light { scene = l2, mode = replace, direction = [0, 0, 5], color = [2, 2, 2] }\n"
        "probe = test_scene_probe { scene = l3 }\n"
        "output probe \"probe.exr\"\n";
    if (run_probe(t, g2, NULL, &img)) {
        LG_TEST_CHECK(t, px(&img, 3)[0] == 1 && img.width == 14, "replace leaves %g lights",
                      (double)px(&img, 3)[0]);
        check_light(t, &img, 0, 0, lg_v3(0, 0, 1), lg_v3(2, 2, 2), 1, lg_v3(0, 0, 0), 0);
        lg_image_free(&img);
    }
}

/* Spot lights: type 2, position, range, the direction given or aimed at a target
 * (normalised), cones turned into radians; --explain counts them among "other" lights. */
static void case_spot(lg_test *t)
{
    const char *g =
        "lightgraph 1\n"
        "cube = test_cube {}\n"
        "s1 = light { scene = cube, type = spot, position = [1, 4, 2], direction = [0, -3, 4],\n"
        "             inner_cone_deg = 10, outer_cone_deg = 30, intensity = 200, range = 12 }\n"
        "s2 = light { scene = s1, type = spot, position = [0, 2, 0], aim = target,\n"
        "             target = [2, 2, 0], color = [0.5, 1, 1] }\n"
        "probe = test_scene_probe { scene = s2 }\n"
        "output probe \"probe.exr\"\n";
    lg_image img;
    if (run_probe(t, g, NULL, &img)) {
        LG_TEST_CHECK(t, px(&img, 3)[0] == 2 && img.width == 10 + 8, "2 lights: %g",
                      (double)px(&img, 3)[0]);
        /* glTF's default cones (0, 45 degrees) for s2 */
        const float deg = (float)(LG_PI / 180.0);
        check_light(t, &img, 0, 2, lg_v3(0, -0.6f, 0.8f), lg_v3(1, 1, 1), 200, lg_v3(1, 4, 2), 12);
        check_light(t, &img, 1, 2, lg_v3(1, 0, 0), lg_v3(0.5f, 1, 1), 1, lg_v3(0, 2, 0), 0);
        const float *c0 = px(&img, 10 + 3), *c1 = px(&img, 10 + 4 + 3);
        LG_TEST_CHECK(t, fabsf(c0[0] - 10 * deg) < 1e-6f && fabsf(c0[1] - 30 * deg) < 1e-6f,
                      "s1 cones %g, %g rad", (double)c0[0], (double)c0[1]);
        LG_TEST_CHECK(t, c1[0] == 0 && fabsf(c1[1] - 45 * deg) < 1e-6f, "s2 cones %g, %g rad",
                      (double)c1[0], (double)c1[1]);
        lg_image_free(&img);
    }
    char *out = NULL;
    static const char *const explain[] = { "--explain", NULL };
    render_text(t, g, explain, &out);
    const char *o = out ? out : "";
    LG_TEST_CHECK(t, features_say(o, "s2", "lights: 0 directional, 0 point, 2 other"),
                  "s2 features: %s", o);
    free(out);

    /* issue 25 brought spot lights to volumetric_froxel (froxel.h 4.): a scene whose only
     * light is a spot keeps it (it gated it, "no directional light", before) */
    const char *gv = "lightgraph 1\n"
                     "cube = test_cube {}\n"
                     "sp = light { scene = cube, type = spot, position = [0, 3, 0] }\n"
                     "fog = medium { scene = sp, density = 0.5 }\n"
                     "lit = phong { scene = fog }\n"
                     "vol = volumetric_froxel { scene = fog, base = lit, width = 8, height = 8, "
                     "depth = 4 }\n"
                     "output vol \"vol.exr\"\n";
    out = NULL;
    int rc = render_text(t, gv, explain, &out);
    o = out ? out : "";
    LG_TEST_CHECK(t, rc == 0 && !strcmp(state_of(o, "vol"), "kept"),
                  "volumetric_froxel on a spot-lit scene: exit %d, state '%s': %s", rc,
                  state_of(o, "vol"), o);
    free(out);
}

static void case_medium(lg_test *t)
{
    const char *g = "lightgraph 1\n"
                    "cube = test_cube {}\n"
                    "m = medium { scene = cube, density = 0.5, scattering = [0.1, 0.2, 0.3],\n"
                    "             absorption = [0.01, 0.02, 0.03], g = 0.4 }\n"
                    "probe = test_scene_probe { scene = m }\n"
                    "output probe \"probe.exr\"\n";
    lg_image img;
    if (run_probe(t, g, NULL, &img)) {
        const float *m = px(&img, 5);
        LG_TEST_CHECK(t, m[0] == 1 && m[1] == 0.5f && m[2] == 0.4f && m[3] == 1,
                      "medium present %g density %g g %g feature %g", (double)m[0], (double)m[1],
                      (double)m[2], (double)m[3]);
        LG_TEST_CHECK(t, near3(px3(&img, 6), lg_v3(0.1f, 0.2f, 0.3f), 0), "scattering");
        LG_TEST_CHECK(t, near3(px3(&img, 7), lg_v3(0.01f, 0.02f, 0.03f), 0), "absorption");
        lg_image_free(&img);
    }
    /* defaults, then replaced by a second node */
    const char *g2 = "lightgraph 1\n"
                     "cube = test_cube {}\n"
                     "m = medium { scene = cube }\n"
                     "m2 = medium { scene = m, density = 2, g = -0.5 }\n"
                     "probe = test_scene_probe { scene = m }\n"
                     "probe2 = test_scene_probe { scene = m2 }\n"
                     "output probe \"probe.exr\"\n"
                     "output probe2 \"probe2.exr\"\n";
    if (run_probe(t, g2, NULL, &img)) {
        const float *m = px(&img, 5);
        LG_TEST_CHECK(t, m[0] == 1 && m[1] == 1 && m[2] == 0, "default medium: %g %g %g",
                      (double)m[0], (double)m[1], (double)m[2]);
        LG_TEST_CHECK(t, near3(px3(&img, 6), lg_v3(0.1f, 0.1f, 0.1f), 0), "default scattering");
        lg_image_free(&img);
        if (lg_test_read(t, "probe2.exr", &img, NULL)) {
            LG_TEST_CHECK(t, px(&img, 5)[1] == 2 && px(&img, 5)[2] == -0.5f, "replaced medium");
            lg_image_free(&img);
        }
    }
}

static void case_sharing(lg_test *t)
{
    const char *g = "lightgraph 1\n"
                    "cube = test_cube { instances = 4 }\n"
                    "cam = camera { scene = cube }\n"
                    "sun = light { scene = cam }\n"
                    "fog = medium { scene = sun }\n"
                    "probe = test_scene_probe { scene = fog, source = cube }\n"
                    "self = test_scene_probe { scene = cube, source = cube }\n"
                    "output probe \"probe.exr\"\n"
                    "output self \"self.exr\"\n";
    lg_image img;
    if (run_probe(t, g, NULL, &img)) {
        const float *s = px(&img, 4);
        LG_TEST_CHECK(t, s[0] == 1,
                      "the third derived scene's geometry is not the source's resource");
        LG_TEST_CHECK(t, s[1] == 1, "meshes, instances or materials were copied");
        LG_TEST_CHECK(t, s[3] == 4 && px(&img, 8)[3] == 48 && px(&img, 9)[3] == 0,
                      "instances %g, triangles %g, geometry NULL %g", (double)s[3],
                      (double)px(&img, 8)[3], (double)px(&img, 9)[3]);
        lg_image_free(&img);
    }
    if (lg_test_read(t, "self.exr", &img, NULL)) {
        LG_TEST_CHECK(t, px(&img, 4)[0] == 0 && px(&img, 9)[3] == 1,
                      "the source owns its geometry (geometry NULL)");
        lg_image_free(&img);
    }
}

static void case_sharing_gl(lg_test *t)
{
    lg_test_require_backend(t, "gl");
    const char *g = "lightgraph 1\n"
                    "cube = test_cube { instances = 2 }\n"
                    "sun = light { scene = cube }\n"
                    "cam = camera { scene = sun }\n"
                    "probe = test_scene_probe { scene = cam, source = cube, gl = true }\n"
                    "output probe \"probe.exr\"\n";
    lg_image img;
    if (run_probe(t, g, NULL, &img)) {
        LG_TEST_CHECK(t, px(&img, 4)[2] == 1, "the GL buffers of mesh 0 differ (%g)",
                      (double)px(&img, 4)[2]);
        lg_image_free(&img);
    }
}

static void case_sharing_cl(lg_test *t)
{
    lg_test_require_backend(t, "cl");
    const char *g = "lightgraph 1\n"
                    "cube = test_cube { instances = 2 }\n"
                    "sun = light { scene = cube }\n"
                    "probe = test_scene_probe { scene = sun, source = cube, cl = true }\n"
                    "output probe \"probe.exr\"\n";
    lg_image img;
    if (run_probe(t, g, NULL, &img)) {
        LG_TEST_CHECK(t, px(&img, 4)[2] == 1,
                      "the CL copies of mesh 0 are not shared or not the mesh's data (%g)",
                      (double)px(&img, 4)[2]);
        lg_image_free(&img);
    }
}

/* Exit status `code`: 1 for a node's error (prepare), 2 for the graph checker's (ranges,
 * enum values); the output holds every string of `msgs`. */
static void expect_error(lg_test *t, const char *what, int code, const char *nodes,
                         const char *const *msgs)
{
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "cube = test_cube {}\n"
             "empty = test_cube { instances = 0 }\n"
             "desc = test_scene {}\n"
             "%s"
             "probe = test_scene_probe { scene = bad }\n"
             "output probe \"probe.exr\"\n",
             nodes);
    char *out = NULL;
    int rc = render_text(t, g, NULL, &out);
    const char *o = out ? out : "";
    LG_TEST_CHECK(t, rc == code, "%s: exit %d, want %d: %s", what, rc, code, o);
    for (int i = 0; msgs[i]; i++)
        LG_TEST_CHECK(t, strstr(o, msgs[i]) != NULL, "%s: the message lacks '%s': %s", what,
                      msgs[i], o);
    free(out);
}

static void case_errors(lg_test *t)
{
    expect_error(t, "zero direction", 1, "bad = light { scene = cube, direction = [0, 0, 0] }\n",
                 (const char *const[]){ "'bad'", "direction = [0, 0, 0] is the zero vector",
                                        NULL });
    expect_error(t, "fov 180", 1, "bad = camera { scene = cube, fov_deg = 180 }\n",
                 (const char *const[]){ "'bad'", "fov_deg = 180", "inside (0, 180)", NULL });
    expect_error(t, "fov 0", 1, "bad = camera { scene = cube, mode = look_at, fov_deg = 0 }\n",
                 (const char *const[]){ "fov_deg = 0", "inside (0, 180)", NULL });
    expect_error(t, "fov 200", 2, "bad = camera { scene = cube, fov_deg = 200 }\n",
                 (const char *const[]){ "fov_deg", "200", "out of range", NULL });
    expect_error(t, "target == position", 1,
                 "bad = camera { scene = cube, mode = look_at, position = [1, 2, 3],"
                 " target = [1, 2, 3] }\n",
                 (const char *const[]){ "'bad'", "is the camera's position", NULL });
    expect_error(t, "up parallel", 1,
                 "bad = camera { scene = cube, mode = look_at, position = [0, 5, 0],"
                 " target = [0, 0, 0] }\n",
                 (const char *const[]){ "'bad'", "parallel to the view direction", NULL });
    expect_error(t, "up zero", 1, "bad = camera { scene = cube, mode = look_at, up = [0, 0, 0] }\n",
                 (const char *const[]){ "up = [0, 0, 0] is the zero vector", NULL });
    expect_error(t, "orbit without geometry", 1, "bad = camera { scene = empty }\n",
                 (const char *const[]){ "'bad'", "empty bounds", "mode = look_at", NULL });
    expect_error(t, "zfar before znear", 1, "bad = camera { scene = cube, znear = 10, zfar = 5 }\n",
                 (const char *const[]){ "zfar = 5 is not beyond znear = 10", NULL });
    expect_error(t, "znear past the scene", 1, "bad = camera { scene = cube, znear = 1000 }\n",
                 (const char *const[]){ "znear = 1000", "set zfar as well", NULL });
    expect_error(t, "g out of range", 2, "bad = medium { scene = cube, g = 0.995 }\n",
                 (const char *const[]){ "g = 0.995", "out of range", NULL });
    expect_error(t, "negative density", 2, "bad = medium { scene = cube, density = -1 }\n",
                 (const char *const[]){ "density", "out of range", NULL });
    expect_error(t, "negative intensity", 2, "bad = light { scene = cube, intensity = -1 }\n",
                 (const char *const[]){ "intensity", "out of range", NULL });
    expect_error(t, "unknown light type", 2, "bad = light { scene = cube, type = area }\n",
                 (const char *const[]){ "area", "directional, point, spot", NULL });
    expect_error(t, "spot inner = outer", 1,
                 "bad = light { scene = cube, type = spot, inner_cone_deg = 30,"
                 " outer_cone_deg = 30 }\n",
                 (const char *const[]){ "'bad'", "inner_cone_deg = 30, outer_cone_deg = 30",
                                        "inner < outer", NULL });
    expect_error(t, "spot inner > outer", 1,
                 "bad = light { scene = cube, type = spot, inner_cone_deg = 50 }\n",
                 (const char *const[]){ "inner_cone_deg = 50, outer_cone_deg = 45", NULL });
    expect_error(t, "spot outer 0", 1,
                 "bad = light { scene = cube, type = spot, outer_cone_deg = 0 }\n",
                 (const char *const[]){ "outer_cone_deg = 0", "inner < outer", NULL });
    expect_error(t, "spot cone past 90", 2,
                 "bad = light { scene = cube, type = spot, outer_cone_deg = 120 }\n",
                 (const char *const[]){ "outer_cone_deg", "120", "out of range", NULL });
    expect_error(t, "spot negative cone", 2,
                 "bad = light { scene = cube, type = spot, inner_cone_deg = -5 }\n",
                 (const char *const[]){ "inner_cone_deg", "out of range", NULL });
    expect_error(t, "spot zero direction", 1,
                 "bad = light { scene = cube, type = spot, direction = [0, 0, 0] }\n",
                 (const char *const[]){ "'bad'", "direction = [0, 0, 0] is the zero vector",
                                        "spot light", NULL });
    expect_error(t, "spot target at its position", 1,
                 "bad = light { scene = cube, type = spot, position = [1, 2, 3], aim = target,"
                 " target = [1, 2, 3] }\n",
                 (const char *const[]){ "'bad'", "target = [1, 2, 3] is the light's own position",
                                        NULL });
    expect_error(t, "a scene without data", 1, "bad = light { scene = desc }\n",
                 (const char *const[]){ "'bad'", "no scene data", NULL });
    expect_error(t, "huge position", 1,
                 "bad = light { scene = cube, type = point, position = [1e39, 0, 0] }\n",
                 (const char *const[]){ "'bad'", "not a finite single-precision number", NULL });
}

/* ---- density fields -------------------------------------------------------------------------- */

/* Pixel (x, y) of an rgba32f image. */
static const float *pxy(const lg_image *img, uint32_t x, uint32_t y)
{
    static const float none[4] = { NAN, NAN, NAN, NAN };
    return x < img->width && y < img->height ? img->pixels + ((size_t)y * img->width + x) * 4
                                             : none;
}

/* Renders `graph` (its probes write the files named in it) and reads `file`. */
static bool run_field(lg_test *t, const char *graph, const char *file, lg_image *img, char **out)
{
    int rc = render_text(t, graph, NULL, out);
    LG_TEST_CHECK(t, rc == 0, "render failed (exit %d): %s", rc, *out ? *out : "");
    return rc == 0 && lg_test_read(t, file, img, NULL);
}

static void case_field(lg_test *t)
{
    /* none: the homogeneous medium, as before; ignored field parameters are warned about */
    const char *g0 = "lightgraph 1\n"
                     "cube = test_cube {}\n"
                     "m = medium { scene = cube, density = 0.5, height_falloff = 1 }\n"
                     "p = test_field_probe { scene = m, lo = [-1, -1, -1], hi = [1, 1, 1],"
                     " n = [3, 3, 3] }\n"
                     "output p \"none.exr\"\n";
    lg_image img;
    char *out = NULL;
    if (run_field(t, g0, "none.exr", &img, &out)) {
        LG_TEST_CHECK(t, pxy(&img, 0, 0)[0] == 0 && pxy(&img, 0, 0)[2] == 0,
                      "field = none: field %g, features.medium_field %g",
                      (double)pxy(&img, 0, 0)[0], (double)pxy(&img, 0, 0)[2]);
        for (uint32_t y = 1; y < img.height; y++)
            for (uint32_t x = 0; x < 3; x++)
                LG_TEST_CHECK(t, pxy(&img, x, y)[0] == 1, "none: m = %g at row %u",
                              (double)pxy(&img, x, y)[0], y);
        lg_image_free(&img);
    }
    LG_TEST_CHECK(t, out && strstr(out, "height_falloff is ignored with field = none"),
                  "no warning about the ignored height fog: %s", out ? out : "");
    free(out);
    out = NULL;

    /* uniform + height fog + box */
    const char *g1 = "lightgraph 1\n"
                     "cube = test_cube {}\n"
                     "m = medium { scene = cube, field = uniform, height_falloff = 0.5,"
                     " height_base = 1, box_min = [-1, -1, -1], box_max = [1, 2, 1] }\n"
                     "p = test_field_probe { scene = m, lo = [-2, -2, 0], hi = [2, 3, 0],"
                     " n = [9, 11, 1] }\n"
                     "output p \"uniform.exr\"\n";
    if (run_field(t, g1, "uniform.exr", &img, &out)) {
        const float *h0 = pxy(&img, 0, 0), *h2 = pxy(&img, 2, 0), *h3 = pxy(&img, 3, 0);
        LG_TEST_CHECK(t, h0[0] == 1 && h0[1] == LG_FIELD_UNIFORM && h0[2] == 1 && h0[3] == 0.5f,
                      "uniform: present %g kind %g feature %g falloff %g", (double)h0[0],
                      (double)h0[1], (double)h0[2], (double)h0[3]);
        LG_TEST_CHECK(t, pxy(&img, 1, 0)[0] == 1, "height_base %g", (double)pxy(&img, 1, 0)[0]);
        LG_TEST_CHECK(t,
                      near3(lg_v3(h2[0], h2[1], h2[2]), lg_v3(-1, -1, -1), 0) &&
                          near3(lg_v3(h3[0], h3[1], h3[2]), lg_v3(1, 2, 1), 0),
                      "bounds [%g %g %g] [%g %g %g]", (double)h2[0], (double)h2[1], (double)h2[2],
                      (double)h3[0], (double)h3[1], (double)h3[2]);
        int inside = 0;
        for (uint32_t x = 0; x < 9; x++)
            for (uint32_t y = 0; y < 11; y++) {
                const float *s = pxy(&img, x, 1 + y);
                bool in = s[1] >= -1 && s[1] <= 1 && s[2] >= -1 && s[2] <= 2;
                double want = in ? exp(-0.5 * ((double)s[2] - 1.0)) : 0.0;
                inside += in;
                LG_TEST_CHECK(t, fabs((double)s[0] - want) <= 1e-6 * want,
                              "uniform at (%g, %g, %g): %g, want %g", (double)s[1], (double)s[2],
                              (double)s[3], (double)s[0], want);
            }
        LG_TEST_CHECK(t, inside > 10 && inside < 99, "%d of 99 samples inside the box", inside);
        lg_image_free(&img);
    }
    free(out);
    out = NULL;

    /* fbm: every parameter reaches the field; another seed, another field */
    const char *g2 = "lightgraph 1\n"
                     "cube = test_cube {}\n"
                     "a = medium { scene = cube, field = fbm, octaves = 3, seed = 7,"
                     " frequency = 2, lacunarity = 2.5, gain = 0.4, offset = 0.1, scale = 2 }\n"
                     "b = medium { scene = a, field = fbm, octaves = 3, seed = 8,"
                     " frequency = 2, lacunarity = 2.5, gain = 0.4, offset = 0.1, scale = 2 }\n"
                     "pa = test_field_probe { scene = a, lo = [-1, -1, -1], hi = [1, 1, 1],"
                     " n = [8, 8, 8] }\n"
                     "pb = test_field_probe { scene = b, lo = [-1, -1, -1], hi = [1, 1, 1],"
                     " n = [8, 8, 8] }\n"
                     "off = medium { scene = a, density = 0, field = fbm }\n"
                     "po = test_field_probe { scene = off }\n"
                     "output pa \"a.exr\"\n"
                     "output pb \"b.exr\"\n"
                     "output po \"off.exr\"\n";
    lg_image b;
    if (run_field(t, g2, "a.exr", &img, &out)) {
        const float *f4 = pxy(&img, 4, 0), *f5 = pxy(&img, 5, 0);
        LG_TEST_CHECK(t, pxy(&img, 0, 0)[1] == LG_FIELD_FBM && pxy(&img, 0, 0)[2] == 1,
                      "fbm kind %g feature %g", (double)pxy(&img, 0, 0)[1],
                      (double)pxy(&img, 0, 0)[2]);
        LG_TEST_CHECK(t, f4[0] == 3 && f4[1] == 7 && f4[2] == 2 && f4[3] == 2.5f,
                      "octaves %g seed %g frequency %g lacunarity %g", (double)f4[0], (double)f4[1],
                      (double)f4[2], (double)f4[3]);
        LG_TEST_CHECK(t, f5[0] == 0.4f && f5[1] == 0.1f && f5[2] == 2 && f5[3] == 1,
                      "gain %g offset %g scale %g heterogeneous %g", (double)f5[0], (double)f5[1],
                      (double)f5[2], (double)f5[3]);
        lg_density_fbm f = { .octaves = 3,
                             .seed = 7,
                             .frequency = 2,
                             .lacunarity = 2.5f,
                             .gain = 0.4f,
                             .offset = 0.1f,
                             .scale = 2 };
        double diff = 0;
        bool read_b = lg_test_read(t, "b.exr", &b, NULL);
        int zeros = 0;
        for (uint32_t y = 1; y < img.height; y++)
            for (uint32_t x = 0; x < 8; x++) {
                const float *s = pxy(&img, x, y);
                double p[3] = { s[1], s[2], s[3] };
                double want = 2.0 * fmax(0.0, lg_fbm3(&f, p) - (double)0.1f);
                zeros += s[0] == 0;
                LG_TEST_CHECK(t, fabs((double)s[0] - want) <= 1e-6,
                              "fbm at (%g, %g, %g): %g, want %g", p[0], p[1], p[2], (double)s[0],
                              want);
                if (read_b)
                    diff += fabs((double)s[0] - (double)pxy(&b, x, y)[0]);
            }
        LG_TEST_CHECK(t, zeros > 0 && zeros < 512, "%d of 512 fBm samples are 0", zeros);
        LG_TEST_CHECK(t, diff / 512 > 0.05, "seeds 7 and 8 differ by %g on average", diff / 512);
        if (read_b)
            lg_image_free(&b);
        lg_image_free(&img);
        if (lg_test_read(t, "off.exr", &img, NULL)) {
            LG_TEST_CHECK(t, pxy(&img, 0, 0)[2] == 0 && pxy(&img, 7, 0)[3] == 0,
                          "density 0: features.medium_field %g, density %g",
                          (double)pxy(&img, 0, 0)[2], (double)pxy(&img, 7, 0)[3]);
            lg_image_free(&img);
        }
    }
    free(out);
}

/* `file` in the fixtures' folder, or NULL without OpenVDB. */
static const char *vdb_fixture(const char *file)
{
    static char path[1024];
    if (!*ST_VDB_DIR)
        return NULL;
    snprintf(path, sizeof path, "%s/%s", ST_VDB_DIR, file);
    return path;
}

static void case_field_errors(lg_test *t)
{
    char node[1536];
    expect_error(t, "flat box", 1,
                 "bad = medium { scene = cube, field = uniform, box_min = [0, 0, 0],"
                 " box_max = [1, 0, 1] }\n",
                 (const char *const[]){ "'bad'", "along y the box is flat", NULL });
    expect_error(t, "inside-out box", 1,
                 "bad = medium { scene = cube, field = fbm, box_min = [2, 0, 0],"
                 " box_max = [1, 1, 1] }\n",
                 (const char *const[]){ "'bad'", "along x the box is inside out", NULL });
    expect_error(t, "frequency 0", 1, "bad = medium { scene = cube, field = fbm, frequency = 0 }\n",
                 (const char *const[]){ "'bad'", "frequency = 0", "> 0", NULL });
    expect_error(t, "gain 1", 1, "bad = medium { scene = cube, field = fbm, gain = 1 }\n",
                 (const char *const[]){ "'bad'", "gain = 1", "inside (0, 1)", NULL });
    expect_error(t, "octaves 17", 2, "bad = medium { scene = cube, field = fbm, octaves = 17 }\n",
                 (const char *const[]){ "octaves", "out of range", NULL });
    expect_error(t, "height fog overflow", 1,
                 "bad = medium { scene = cube, field = uniform, height_falloff = 1000,"
                 " height_base = 10 }\n",
                 (const char *const[]){ "'bad'", "height_falloff = 1000", "y = -1", "over 1e+06",
                                        NULL });
    expect_error(t, "empty vdb path", 1, "bad = medium { scene = cube, field = vdb }\n",
                 (const char *const[]){ "'bad'", "parameter 'vdb' is empty", NULL });
    if (!vdb_fixture("x")) {
        expect_error(t, "no OpenVDB", 1,
                     "bad = medium { scene = cube, field = vdb, vdb = \"cloud.vdb\" }\n",
                     (const char *const[]){ "'bad'", "has no OpenVDB", "libopenvdb-dev", NULL });
        return;
    }
    expect_error(t, "missing file", 1,
                 "bad = medium { scene = cube, field = vdb, vdb = \"no_such.vdb\" }\n",
                 (const char *const[]){ "'bad'", "no_such.vdb", "cannot read it", NULL });
    expect_error(t, "a folder", 1, "bad = medium { scene = cube, field = vdb, vdb = \".\" }\n",
                 (const char *const[]){ "'bad'", "cannot read it", "directory", NULL });
    /* a sparse file one byte over the 1 GiB cap: refused by its size, before a byte is read */
    lg_test_write_text(t, "big.vdb", "");
    int trc = truncate(lg_test_path(t, "big.vdb"), ((off_t)1 << 30) + 1);
    LG_TEST_CHECK(t, trc == 0, "cannot make the sparse file");
    expect_error(t, "over the size cap", 1,
                 "bad = medium { scene = cube, field = vdb, vdb = \"big.vdb\" }\n",
                 (const char *const[]){ "'bad'", "big.vdb", "cannot read it", "limit", NULL });
    static const struct {
        const char *what, *file, *extra, *msg1, *msg2;
    } bad[] = {
        { "vdb_scale 0", "one_voxel.vdb", "vdb_scale = 0", "vdb_scale = 0", "> 0" },
        { "text", "garbage.vdb", "", "garbage.vdb", "not a readable VDB file" },
        { "truncated", "truncated.vdb", "", "not a readable VDB file", "ends before its grids do" },
        { "no float grid", "vec3.vdb", "", "no float grid", "'velocity' (vec3s)" },
        { "unknown grid", "one_voxel.vdb", "grid = \"smoke\"", "no grid named 'smoke'",
          "'density' (float), 'other' (float)" },
        { "not float", "one_voxel.vdb", "grid = \"velocity\"", "grid 'velocity' holds vec3s",
          "not float" },
        { "level set", "levelset.vdb", "", "grid 'surface' is a level set", "fog volume" },
        { "empty grid", "empty.vdb", "", "grid 'density' has no active voxel", "" },
        { "too many voxels", "huge.vdb", "", "1024 x 1024 x 1024", "over the limit of 134217728" },
        { "frustum", "frustum.vdb", "", "not affine", "" },
        { "negative voxel", "negative.vdb", "", "voxel [1, 0, 1]", "holds -1" },
        { "NaN voxel", "nan.vdb", "", "voxel [0, 1, 0]", "holds nan" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(node, sizeof node,
                 "bad = medium { scene = cube, field = vdb, vdb = \"%s\"%s%s }\n",
                 vdb_fixture(bad[i].file), *bad[i].extra ? ", " : "", bad[i].extra);
        expect_error(t, bad[i].what, 1, node,
                     (const char *const[]){ "'bad'", bad[i].msg1, bad[i].msg2, NULL });
    }
}

/* The field at each "x y z value" line of `samples` (make_vdb_cloud's OpenVDB samples)
 * through one probe per point of `medium` (a node line naming its node `m`), within `tol`
 * (relative to max(1, value)). Returns the number of points checked. */
static int check_samples(lg_test *t, const char *medium, const char *samples, double tol)
{
    FILE *f = fopen(vdb_fixture(samples), "r");
    LG_TEST_CHECK(t, f != NULL, "cannot open %s", vdb_fixture(samples));
    if (!f)
        return 0;
    double pts[64][4];
    int n = 0;
    while (n < 64 &&
           fscanf(f, "%lf %lf %lf %lf", &pts[n][0], &pts[n][1], &pts[n][2], &pts[n][3]) == 4)
        n++;
    fclose(f);
    size_t cap = 1 << 16, len = 0;
    char *g = malloc(cap);
    len += (size_t)snprintf(g + len, cap - len, "lightgraph 1\ncube = test_cube {}\n%s", medium);
    for (int i = 0; i < n; i++)
        len += (size_t)snprintf(g + len, cap - len,
                                "p%d = test_field_probe { scene = m, lo = [%.9g, %.9g, %.9g] }\n"
                                "output p%d \"p%d.exr\"\n",
                                i, pts[i][0], pts[i][1], pts[i][2], i, i);
    char *out = NULL;
    int rc = render_text(t, g, NULL, &out);
    LG_TEST_CHECK(t, rc == 0, "%s: exit %d: %s", samples, rc, out ? out : "");
    free(out);
    free(g);
    int nonzero = 0;
    for (int i = 0; i < n && rc == 0; i++) {
        char file[32];
        snprintf(file, sizeof file, "p%d.exr", i);
        lg_image img;
        if (!lg_test_read(t, file, &img, NULL))
            continue;
        double got = pxy(&img, 0, 1)[0], want = pts[i][3];
        nonzero += want > 0;
        LG_TEST_CHECK(t, fabs(got - want) <= tol * fmax(1.0, fabs(want)),
                      "%s: world (%g, %g, %g): field %.7g, OpenVDB's sample %.7g", samples,
                      pts[i][0], pts[i][1], pts[i][2], got, want);
        lg_image_free(&img);
    }
    LG_TEST_CHECK(t, n >= 6 && nonzero >= 3, "%s: %d samples, %d of them > 0", samples, n, nonzero);
    return n;
}

static void case_vdb(lg_test *t)
{
    if (!vdb_fixture("x"))
        lg_test_skip(t, "this build has no OpenVDB (field_errors checks the message)");
    char g[8192];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "cube = test_cube {}\n"
             "m = medium { scene = cube, field = vdb, vdb = \"%s\" }\n"
             "o = medium { scene = cube, field = vdb, vdb = \"%s\", grid = \"other\" }\n"
             "s = medium { scene = cube, field = vdb, vdb = \"%s\", vdb_scale = 2,"
             " vdb_translate = [1, 0, 0] }\n"
             "pm = test_field_probe { scene = m, lo = [2.5, 1, 5.5] }\n"
             "po = test_field_probe { scene = o }\n"
             "ps = test_field_probe { scene = s, lo = [6, 2, 11] }\n"
             "output pm \"m.exr\"\noutput po \"o.exr\"\noutput ps \"s.exr\"\n",
             vdb_fixture("one_voxel.vdb"), vdb_fixture("one_voxel.vdb"),
             vdb_fixture("one_voxel.vdb"));
    lg_image img;
    char *out = NULL;
    if (run_field(t, g, "m.exr", &img, &out)) {
        const float *h0 = pxy(&img, 0, 0), *h1 = pxy(&img, 1, 0), *h2 = pxy(&img, 2, 0),
                    *h3 = pxy(&img, 3, 0), *h6 = pxy(&img, 6, 0), *h7 = pxy(&img, 7, 0);
        LG_TEST_CHECK(t, h0[1] == LG_FIELD_GRID && h0[2] == 1, "kind %g feature %g", (double)h0[1],
                      (double)h0[2]);
        LG_TEST_CHECK(t, h1[1] == 1 && h1[2] == 1 && h1[3] == 1 && h2[3] == 2,
                      "grid %gx%gx%g max %g", (double)h1[1], (double)h1[2], (double)h1[3],
                      (double)h2[3]);
        /* dense voxel 0 is VDB voxel [3, -2, 5]: world 0.5 [3, -2, 5] + [1, 2, 3] */
        LG_TEST_CHECK(t,
                      near3(lg_v3(h6[0], h6[1], h6[2]), lg_v3(2.5f, 1, 5.5f), 1e-6f) &&
                          near3(lg_v3(h7[0], h7[1], h7[2]), lg_v3(0.5f, 0.5f, 0.5f), 1e-6f),
                      "translation [%g %g %g], voxel [%g %g %g]", (double)h6[0], (double)h6[1],
                      (double)h6[2], (double)h7[0], (double)h7[1], (double)h7[2]);
        /* the support: a voxel beyond the centre each way */
        LG_TEST_CHECK(t,
                      near3(lg_v3(h2[0], h2[1], h2[2]), lg_v3(2, 0.5f, 5), 1e-6f) &&
                          near3(lg_v3(h3[0], h3[1], h3[2]), lg_v3(3, 1.5f, 6), 1e-6f),
                      "bounds [%g %g %g] [%g %g %g]", (double)h2[0], (double)h2[1], (double)h2[2],
                      (double)h3[0], (double)h3[1], (double)h3[2]);
        LG_TEST_CHECK(t, fabs(pxy(&img, 0, 1)[0] - 2.0f) < 1e-6f, "value at the centre %g",
                      (double)pxy(&img, 0, 1)[0]);
        LG_TEST_CHECK(t, h6[3] == (float)strlen(vdb_fixture("one_voxel.vdb")) + 8,
                      "source 'FILE:density' has length %g", (double)h6[3]);
        lg_image_free(&img);
        if (lg_test_read(t, "o.exr", &img, NULL)) {
            LG_TEST_CHECK(t, pxy(&img, 2, 0)[3] == 7 && pxy(&img, 0, 1)[0] == 7,
                          "grid = other: max %g, value at the origin %g",
                          (double)pxy(&img, 2, 0)[3], (double)pxy(&img, 0, 1)[0]);
            lg_image_free(&img);
        }
        if (lg_test_read(t, "s.exr", &img, NULL)) {
            LG_TEST_CHECK(t,
                          fabs(pxy(&img, 0, 1)[0] - 2.0f) < 1e-6f &&
                              fabs(pxy(&img, 7, 0)[0] - 1.0f) < 1e-6f,
                          "scaled and moved: value %g at (6, 2, 11), voxel %g",
                          (double)pxy(&img, 0, 1)[0], (double)pxy(&img, 7, 0)[0]);
            lg_image_free(&img);
        }
    }
    free(out);
    char m[1536];
    snprintf(m, sizeof m, "m = medium { scene = cube, field = vdb, vdb = \"%s\" }\n",
             vdb_fixture("one_voxel.vdb"));
    check_samples(t, m, "one_voxel.txt", 1e-5);
    snprintf(m, sizeof m, "m = medium { scene = cube, field = vdb, vdb = \"%s\" }\n",
             vdb_fixture("rotated.vdb"));
    check_samples(t, m, "rotated.txt", 1e-5);
    snprintf(m, sizeof m, "m = medium { scene = cube, field = vdb, vdb = \"%s\" }\n",
             vdb_fixture("cloud16.vdb"));
    check_samples(t, m, "cloud16.txt", 1e-5);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "features", case_features },
        { "gating", case_gating },
        { "environment", case_environment },
        { "look_at", case_look_at },
        { "orbit", case_orbit },
        { "lights", case_lights },
        { "spot", case_spot },
        { "medium", case_medium },
        { "sharing", case_sharing },
        { "sharing_gl", case_sharing_gl },
        { "sharing_cl", case_sharing_cl },
        { "errors", case_errors },
        { "field", case_field },
        { "field_errors", case_field_errors },
        { "vdb", case_vdb },
    };
    lg_test_main_opts o = { .setup = use_test_plugins };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
