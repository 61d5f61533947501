/*
 * test_anim_host: rigid glTF animation through the host (issue 24, item 2): the loader's
 * animations, the planner's per-frame runs, frame-pattern outputs and the instance matrices
 * the raster nodes draw at each frame's time.
 *
 *   test_anim_host CASE
 *
 *   frames      a quad keyed from x = -1 (t = 0) to x = +1 (t = 1 s), LINEAR, seen by a
 *               camera at z = 5 (yfov 0.8 rad, 64x64): `preview` with --frames 3 --dt 0.5
 *               into "frames/f_%02d.exr" writes f_00, f_01, f_02 whose coverage centroids
 *               are at the hand-computed columns 32 -+ 32 / (5 tan 0.4) = 16.86, 32, 47.14
 *               (within 0.6 px); frame 1 matches a static file with the quad at x = 0
 *               (centroid within 0.01 px); without a pattern only the last frame is written
 *               (its centroid at 47.14); STEP holds x = -1 until the last key
 *   shadow      the sliding quad of `frames` under a sun travelling -z: the shadow map's atlas
 *               (fit = bounds) holds the quad at every frame (more than a quarter of the
 *               tile covered at t = 0, 0.5, 1 s): the fit follows the posed instances, not
 *               the rest pose's bounds (where the quad at x = -1 or +1 lies outside the map)
 *   camera      the quad still, the camera carried by an animated parent node that moves
 *               from x = -1 to x = +1: the quad's centroid moves the other way (47.14, 32,
 *               16.86 at t = 0, 0.5, 1 s), through lg_scene_at in preview
 *   runs        --profile-json: with the animated file and --frames 4, gltf runs once and
 *               preview 4 times; with `animation = -1` (and with a static file) every node
 *               runs once; --explain says preview runs per frame because it "reads an
 *               animated scene"
 *   pattern     frame patterns refused at check time with the position: %s, two
 *               conversions, %n, "%5d" (exit 2, nothing written); a failure at frame 2
 *               (test_work fail_frame) leaves no frame file, not even frames 0 and 1
 *   truck       CesiumMilkTruck (assets/meshes/CesiumMilkTruck) plays with --frames 3 --dt
 *               0.4: its animation turns the two wheel nodes ("animated instances, lights
 *               and cameras 2"), preview runs per frame, and between frame 0 and frame 2
 *               the normals change inside the wheels only (every changed pixel lies in the
 *               bottom half of the picture, where the wheels are; the body is still)
 *   prt_motion  a torus (gen_scene.py torus --level 10) spinning about z, 0 -> 180 degrees
 *               over 2 s, lit by the forest probe in 4 bands, its transfer baked once at
 *               rest (shadowed, 64 samples): the `prt` node's per-vertex radiance at frames
 *               of 0, 45, 90 and 135 degrees matches a bake of the torus placed statically at
 *               that pose, on cpu and gl, within 0.015 absolute (values up to 1.2) and 2e-4
 *               mean. Measured: max 0.0073 (45 deg), 0.0059 (90 deg), 0 at rest; with 32
 *               samples 0.025 and 0.0165: the residual is the bake's sampling of rotated
 *               versus unrotated directions, shrinking with samples. Unturned lighting (the
 *               rest bake against the 90-degree pose) is off by 0.94: the check can fail.
 *   refused     hard cases (stability): key times not increasing, a NaN key value, a
 *               channel to a node that does not exist, an animated matrix node, a skinned
 *               animation (a joint of a skin), a morph-weight animation, an unknown
 *               interpolation: exit 1, the message names the file, the animation (index and
 *               name) and the channel
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "lightgraph/test.h"

#ifndef PT_TESTNODES_DIR
#define PT_TESTNODES_DIR ""
#endif

/* The quad (two triangles, 0.5 wide, in the z = 0 plane) and the key data, one buffer:
 * positions (48 bytes), indices (12), times (3 floats), translations (3 VEC3), a NaN
 * translation set (3 VEC3) and non-increasing times (3 floats). */
static void write_bin(lg_test *t)
{
    float buf[12 + 3 + 3 + 9 + 9 + 3];
    const float pos[12] = {
        -0.25f, -0.25f, 0, 0.25f, -0.25f, 0, 0.25f, 0.25f, 0, -0.25f, 0.25f, 0
    };
    memcpy(buf, pos, sizeof pos);
    uint16_t idx[6] = { 0, 1, 2, 0, 2, 3 };
    memcpy(buf + 12, idx, sizeof idx);
    const float times[3] = { 0, 0.5f, 1 };
    memcpy(buf + 15, times, sizeof times);
    const float tr[9] = { -1, 0, 0, 0, 0, 0, 1, 0, 0 };
    memcpy(buf + 18, tr, sizeof tr);
    float bad[9] = { -1, 0, 0, 0, 0, 0, 1, 0, 0 };
    bad[4] = NAN;
    memcpy(buf + 27, bad, sizeof bad);
    const float back[3] = { 0, 1, 0.5f };
    memcpy(buf + 36, back, sizeof back);
    FILE *f = fopen(lg_test_path(t, "quad.bin"), "wb");
    if (!f || fwrite(buf, 1, sizeof buf, f) != sizeof buf || fclose(f))
        exit(99);
}

/* A glTF of the quad: node 0 (the quad; `node0` adds to it), node 1 the camera at z = 5,
 * `extra_nodes` appended to the node list, `anim` the "animations" array ("" none),
 * `skins` the "skins" member ("" none). Accessors: 0 positions, 1 indices, 2 times, 3
 * translations, 4 NaN translations, 5 non-increasing times. */
static void write_gltf(lg_test *t, const char *name, const char *node0, const char *extra_nodes,
                       const char *anim, const char *skins)
{
    char *g = NULL;
    if (asprintf(&g,
                 "{\"asset\":{\"version\":\"2.0\"},"
                 "\"buffers\":[{\"byteLength\":156,\"uri\":\"quad.bin\"}],"
                 "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
                 "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":12},"
                 "{\"buffer\":0,\"byteOffset\":60,\"byteLength\":12},"
                 "{\"buffer\":0,\"byteOffset\":72,\"byteLength\":36},"
                 "{\"buffer\":0,\"byteOffset\":108,\"byteLength\":36},"
                 "{\"buffer\":0,\"byteOffset\":144,\"byteLength\":12}],"
                 "\"accessors\":["
                 "{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
                 "\"min\":[-0.25,-0.25,0],\"max\":[0.25,0.25,0]},"
                 "{\"bufferView\":1,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"},"
                 "{\"bufferView\":2,\"componentType\":5126,\"count\":3,\"type\":\"SCALAR\","
                 "\"min\":[0],\"max\":[1]},"
                 "{\"bufferView\":3,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
                 "{\"bufferView\":4,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
                 "{\"bufferView\":5,\"componentType\":5126,\"count\":3,\"type\":\"SCALAR\"}],"
                 "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
                 "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,"
                 "\"znear\":1,\"zfar\":10}}],"
                 "\"nodes\":[{\"name\":\"quad\",\"mesh\":0%s},{\"camera\":0,"
                 "\"translation\":[0,0,5]}%s],"
                 "\"scenes\":[{\"nodes\":[0,1]}],\"scene\":0%s%s%s%s}",
                 node0, extra_nodes, anim[0] ? ",\"animations\":" : "", anim,
                 skins[0] ? ",\"skins\":" : "", skins) < 0)
        exit(99);
    lg_test_write_text(t, name, g);
    free(g);
}

/* The animation moving the quad: translation keys (accessor 3) over times (accessor 2). */
static const char MOVE[] = "[{\"name\":\"slide\",\"channels\":[{\"sampler\":0,\"target\":"
                           "{\"node\":0,\"path\":\"translation\"}}],\"samplers\":[{\"input\":2,"
                           "\"output\":3,\"interpolation\":\"LINEAR\"}]}]";

/* The centroid column of the pixels the quad covers (red > 0) in an EXR; -1 if none. */
static double centroid(lg_test *t, const char *rel)
{
    lg_image img;
    if (!lg_test_read(t, rel, &img, NULL)) {
        LG_TEST_CHECK(t, false, "cannot read %s", rel);
        return -1;
    }
    double sx = 0, n = 0;
    for (uint32_t y = 0; y < img.height; y++)
        for (uint32_t x = 0; x < img.width; x++)
            if (img.pixels[4 * ((size_t)y * img.width + x)] > 0)
                sx += x + 0.5, n++;
    lg_image_free(&img);
    return n ? sx / n : -1;
}

static bool exists(lg_test *t, const char *rel)
{
    struct stat st;
    return stat(lg_test_path(t, rel), &st) == 0;
}

static const char GRAPH[] = "lightgraph 1\nscene = gltf { file = \"anim.gltf\" }\n"
                            "v = preview { scene = scene }\n";

static void case_frames(lg_test *t)
{
    write_bin(t);
    write_gltf(t, "anim.gltf", "", "", MOVE, "");
    if (mkdir(lg_test_path(t, "frames"), 0777))
        exit(99);
    char *g = NULL;
    if (asprintf(&g, "%soutput v \"frames/f_%%02d.exr\"\n", GRAPH) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--frames", "3", "--dt", "0.5", "--size", "64x64", NULL };
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    if (lg_test_output_says_no_device(out))
        lg_test_skip(t, "no GL device");
    LG_TEST_CHECK(t, rc == 0, "render failed: %s", out ? out : "");
    free(out);
    /* hand-computed: x_pixel = 32 + 32 x / (5 tan(0.4)) */
    const double k = 32.0 / (5.0 * tan(0.4));
    const double want[3] = { 32 - k, 32, 32 + k };
    double c[3];
    for (int f = 0; f < 3; f++) {
        char name[32];
        snprintf(name, sizeof name, "frames/f_%02d.exr", f);
        c[f] = centroid(t, name);
        LG_TEST_CHECK(t, fabs(c[f] - want[f]) < 0.6, "frame %d: centroid at column %.3f, want %.3f",
                      f, c[f], want[f]);
    }
    LG_TEST_CHECK(t, !exists(t, "frames/f_03.exr"), "a fourth frame file was written");
    printf("centroids: %.3f %.3f %.3f (hand-computed %.3f %.3f %.3f)\n", c[0], c[1], c[2], want[0],
           want[1], want[2]);

    /* frame 1 against the quad placed statically at its pose (x = 0) */
    write_gltf(t, "static.gltf", ",\"translation\":[0,0,0]", "", "", "");
    lg_test_write_text(t, "s.lgraph",
                       "lightgraph 1\nscene = gltf { file = \"static.gltf\" }\n"
                       "v = preview { scene = scene }\noutput v \"static.exr\"\n");
    const char *sargs[] = { "--size", "64x64", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "s.lgraph", sargs, NULL) == 0, "static render failed");
    double cs = centroid(t, "static.exr");
    LG_TEST_CHECK(t, fabs(cs - c[1]) < 0.01, "frame 1 at %.4f, the static pose at %.4f", c[1], cs);

    /* no pattern: only the last frame */
    if (asprintf(&g, "%soutput v \"last.exr\"\n", GRAPH) < 0)
        exit(99);
    lg_test_write_text(t, "l.lgraph", g);
    free(g);
    LG_TEST_CHECK(t, lg_test_render(t, "l.lgraph", args, NULL) == 0, "render failed");
    double cl = centroid(t, "last.exr");
    LG_TEST_CHECK(t, fabs(cl - want[2]) < 0.6, "last.exr: centroid %.3f, want %.3f", cl, want[2]);

    /* STEP: x = -1 until t = 0.5, then 0; at t = 0.49 still -1 */
    static const char STEP[] = "[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,"
                               "\"path\":\"translation\"}}],\"samplers\":[{\"input\":2,"
                               "\"output\":3,\"interpolation\":\"STEP\"}]}]";
    write_gltf(t, "anim.gltf", "", "", STEP, "");
    const char *targs[] = { "--frames", "2", "--dt", "0.49", "--size", "64x64", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "l.lgraph", targs, NULL) == 0, "render failed");
    cl = centroid(t, "last.exr");
    LG_TEST_CHECK(t, fabs(cl - want[0]) < 0.6, "STEP at 0.49 s: centroid %.3f, want %.3f", cl,
                  want[0]);
}

/* The atlas texels nearer than the far plane (R < 0.999) in an EXR, as a fraction. */
static double covered(lg_test *t, const char *rel)
{
    lg_image img;
    if (!lg_test_read(t, rel, &img, NULL)) {
        LG_TEST_CHECK(t, false, "cannot read %s", rel);
        return -1;
    }
    double n = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        n += img.pixels[4 * i] < 0.999f;
    double f = n / ((double)img.width * img.height);
    lg_image_free(&img);
    return f;
}

static void case_shadow(lg_test *t)
{
    write_bin(t);
    write_gltf(t, "anim.gltf", "", "", MOVE, "");
    if (mkdir(lg_test_path(t, "frames"), 0777))
        exit(99);
    lg_test_write_text(
        t, "g.lgraph",
        "lightgraph 1\nscene = gltf { file = \"anim.gltf\" }\n"
        "sun = light { scene = scene, direction = [0, 0, -1], intensity = 1 }\n"
        "sm = shadowmap { scene = sun, resolution = 64, fit = bounds, cull = none }\n"
        "output sm.atlas \"frames/a_%02d.exr\"\n");
    const char *args[] = { "--frames", "3", "--dt", "0.5", "--size", "64x64", NULL };
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    if (lg_test_output_says_no_device(out))
        lg_test_skip(t, "no GL device");
    LG_TEST_CHECK(t, rc == 0, "render failed: %s", out ? out : "");
    free(out);
    for (int f = 0; f < 3; f++) {
        char name[32];
        snprintf(name, sizeof name, "frames/a_%02d.exr", f);
        double c = covered(t, name);
        printf("frame %d: %.3f of the shadow map covered by the quad\n", f, c);
        LG_TEST_CHECK(t, c > 0.25, "frame %d: the quad covers %.3f of its shadow map", f, c);
    }
}

static void case_camera(lg_test *t)
{
    write_bin(t);
    /* node 2 (animated) carries the camera, node 1 */
    static const char CAM[] = "[{\"name\":\"dolly\",\"channels\":[{\"sampler\":0,\"target\":"
                              "{\"node\":2,\"path\":\"translation\"}}],\"samplers\":[{"
                              "\"input\":2,\"output\":3}]}]";
    write_gltf(t, "anim.gltf", "", ",{\"name\":\"rig\",\"children\":[1]}", CAM, "");
    /* the camera is now node 2's child: the scene lists the quad and the rig */
    char *text = NULL;
    FILE *f = fopen(lg_test_path(t, "anim.gltf"), "rb");
    if (!f)
        exit(99);
    static char buf[8192];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    char *roots = strstr(buf, "\"nodes\":[0,1]");
    if (!roots)
        exit(99);
    memcpy(roots, "\"nodes\":[0,2]", 13);
    lg_test_write_text(t, "anim.gltf", buf);
    if (mkdir(lg_test_path(t, "frames"), 0777))
        exit(99);
    char *g = NULL;
    if (asprintf(&g, "%soutput v \"frames/c_%%d.exr\"\n", GRAPH) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--frames", "3", "--dt", "0.5", "--size", "64x64", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    if (lg_test_output_says_no_device(text))
        lg_test_skip(t, "no GL device");
    LG_TEST_CHECK(t, rc == 0, "render failed: %s", text ? text : "");
    free(text);
    const double k = 32.0 / (5.0 * tan(0.4));
    const double want[3] = { 32 + k, 32, 32 - k };
    for (int i = 0; i < 3; i++) {
        char name[32];
        snprintf(name, sizeof name, "frames/c_%d.exr", i);
        double c = centroid(t, name);
        LG_TEST_CHECK(t, fabs(c - want[i]) < 0.6, "frame %d: centroid %.3f, want %.3f", i, c,
                      want[i]);
    }
}

/* "runs" of node `name` in a --profile-json file, or -1. */
static long runs_of(lg_test *t, const char *json, const char *name)
{
    FILE *f = fopen(lg_test_path(t, json), "rb");
    if (!f)
        return -1;
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    char key[96];
    snprintf(key, sizeof key, "\"name\": \"%s\"", name);
    const char *p = strstr(buf, key);
    p = p ? strstr(p, "\"runs\": ") : NULL;
    return p ? strtol(p + 8, NULL, 10) : -1;
}

static void case_runs(lg_test *t)
{
    write_bin(t);
    write_gltf(t, "anim.gltf", "", "", MOVE, "");
    char *g = NULL;
    if (asprintf(&g, "%soutput v \"out.exr\"\n", GRAPH) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--frames", "4", "--size", "16x16", "--profile-json", "p.json", NULL };
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    if (lg_test_output_says_no_device(out))
        lg_test_skip(t, "no GL device");
    LG_TEST_CHECK(t, rc == 0, "render failed: %s", out ? out : "");
    free(out);
    long a = runs_of(t, "p.json", "scene"), b = runs_of(t, "p.json", "v");
    LG_TEST_CHECK(t, a == 1 && b == 4,
                  "animated: gltf ran %ld times (want 1), preview %ld (want 4)", a, b);
    /* the same file with animation = -1: static, every node once */
    const char *args2[] = {
        "--frames",           "4", "--size", "16x16", "--profile-json", "q.json", "--set",
        "scene.animation=-1", NULL
    };
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args2, NULL) == 0, "render failed");
    a = runs_of(t, "q.json", "scene"), b = runs_of(t, "q.json", "v");
    LG_TEST_CHECK(t, a == 1 && b == 1, "animation -1: gltf %ld, preview %ld (want 1, 1)", a, b);
    /* a file without animations */
    write_gltf(t, "anim.gltf", "", "", "", "");
    const char *args3[] = { "--frames", "4", "--size", "16x16", "--profile-json", "r.json", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args3, NULL) == 0, "render failed");
    b = runs_of(t, "r.json", "v");
    LG_TEST_CHECK(t, b == 1, "static file: preview ran %ld times (want 1)", b);
    /* --explain says why */
    write_gltf(t, "anim.gltf", "", "", MOVE, "");
    const char *eargs[] = { "--frames", "4", "--size", "16x16", "--explain", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", eargs, &out) == 0, "explain failed");
    LG_TEST_CHECK(t,
                  out && strstr(out, "per-frame") &&
                      strstr(out, "per frame: reads an animated scene") &&
                      strstr(out, "animated instances, lights and cameras 1"),
                  "explain: %s", out ? out : "");
    free(out);
}

static void case_pattern(lg_test *t)
{
    write_bin(t);
    write_gltf(t, "anim.gltf", "", "", MOVE, "");
    static const struct {
        const char *name, *says;
    } bad[] = {
        { "f_%s.exr", "character 3: '%s' is not a frame number" },
        { "f_%d_%d.exr", "character 6: a second frame number (the first is at character 3)" },
        { "f_%n.exr", "character 3: '%n' is not a frame number" },
        { "f_%5d.exr", "character 3: '%5d' is not a frame number" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char *g = NULL;
        if (asprintf(&g, "%soutput v \"%s\"\n", GRAPH, bad[i].name) < 0)
            exit(99);
        lg_test_write_text(t, "g.lgraph", g);
        free(g);
        const char *args[] = { "--frames", "2", "--size", "16x16", NULL };
        char *out = NULL;
        int rc = lg_test_render(t, "g.lgraph", args, &out);
        LG_TEST_CHECK(t, rc == 2 && out && strstr(out, bad[i].says),
                      "'%s': exit %d, want 2 and \"%s\": %s", bad[i].name, rc, bad[i].says,
                      out ? out : "");
        free(out);
    }
    /* a failure at frame 2 after frames 0 and 1 were written to their temporaries */
    lg_test_use_plugins(NULL, PT_TESTNODES_DIR);
    if (mkdir(lg_test_path(t, "frames"), 0777))
        exit(99);
    char *g = NULL;
    if (asprintf(&g,
                 "%sw = test_work { image = v, per_frame = true, fail_frame = 2 }\n"
                 "output w \"frames/f_%%d.exr\"\n",
                 GRAPH) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--frames", "4", "--size", "16x16", NULL };
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    if (lg_test_output_says_no_device(out))
        lg_test_skip(t, "no GL device");
    LG_TEST_CHECK(t, rc == 1 && out && strstr(out, "failing at frame 2"), "exit %d: %s", rc,
                  out ? out : "");
    free(out);
    for (int f = 0; f < 4; f++) {
        char name[32];
        snprintf(name, sizeof name, "frames/f_%d.exr", f);
        LG_TEST_CHECK(t, !exists(t, name), "%s was left behind by a failed render", name);
    }
    /* and no temporary either: the folder is empty */
    char *cmd = NULL;
    if (asprintf(&cmd, "test -z \"$(ls -A '%s')\"", lg_test_path(t, "frames")) < 0)
        exit(99);
    LG_TEST_CHECK(t, system(cmd) == 0, "frames/ is not empty after the failure");
    free(cmd);
}

static void case_truck(lg_test *t)
{
    const char *truck = lg_test_asset("meshes/CesiumMilkTruck/CesiumMilkTruck.gltf");
    if (!truck) {
        LG_TEST_CHECK(t, false, "asset meshes/CesiumMilkTruck/CesiumMilkTruck.gltf is missing");
        return;
    }
    char *g = NULL;
    if (asprintf(&g,
                 "lightgraph 1\nscene = gltf { file = \"%s\" }\n"
                 "v = preview { scene = scene, mode = \"normals\" }\noutput v \"t_%%d.exr\"\n",
                 truck) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--frames", "3", "--dt", "0.4", "--size", "96x64", "--explain", NULL };
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    if (lg_test_output_says_no_device(out))
        lg_test_skip(t, "no GL device");
    LG_TEST_CHECK(t,
                  rc == 0 && out && strstr(out, "animated instances, lights and cameras 2") &&
                      strstr(out, "per frame: reads an animated scene"),
                  "exit %d: %s", rc, out ? out : "");
    free(out);
    const char *rargs[] = { "--frames", "3", "--dt", "0.4", "--size", "96x64", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", rargs, NULL) == 0, "render failed");
    lg_image a, b;
    if (!lg_test_read(t, "t_0.exr", &a, NULL) || !lg_test_read(t, "t_2.exr", &b, NULL)) {
        LG_TEST_CHECK(t, false, "frame files missing");
        return;
    }
    uint32_t changed = 0, above = 0;
    for (uint32_t y = 0; y < a.height; y++)
        for (uint32_t x = 0; x < a.width; x++) {
            size_t i = 4 * ((size_t)y * a.width + x);
            bool d = false;
            for (int c = 0; c < 3; c++)
                d |= fabsf(a.pixels[i + c] - b.pixels[i + c]) > 1e-3f;
            changed += d;
            above += d && y < a.height / 2;
        }
    printf("truck: %u pixels changed between frames 0 and 2, %u above the wheels\n", changed,
           above);
    LG_TEST_CHECK(t, changed >= 10, "the wheels did not turn: %u pixels changed", changed);
    LG_TEST_CHECK(t, above == 0, "%u changed pixels above the wheels: the body moved", above);
    lg_image_free(&a);
    lg_image_free(&b);
}

/* Max and mean |a - b| over the RGB of the vertices' values (the `vertices` images). */
static void vertex_diff(lg_test *t, const char *a, const char *b, double *max, double *mean)
{
    lg_image x, y;
    *max = *mean = INFINITY;
    if (!lg_test_read(t, a, &x, NULL) || !lg_test_read(t, b, &y, NULL)) {
        LG_TEST_CHECK(t, false, "cannot read %s or %s", a, b);
        return;
    }
    double m = 0, s = 0;
    size_t n = (size_t)x.width * x.height;
    for (size_t i = 0; i < n && x.width == y.width && x.height == y.height; i++)
        for (int c = 0; c < 3; c++) {
            double d = fabs((double)x.pixels[4 * i + c] - y.pixels[4 * i + c]);
            m = fmax(m, d);
            s += d;
        }
    if (x.width == y.width && x.height == y.height)
        *max = m, *mean = s / (3.0 * (double)n);
    lg_image_free(&x);
    lg_image_free(&y);
}

static void gen_torus(lg_test *t, const char *opts, const char *out)
{
    const char *root = getenv("LG_SOURCE_ROOT");
    char *cmd = NULL;
    if (!root || asprintf(&cmd, "python3 '%s/tools/gen_scene.py' torus --level 10 -q %s -o '%s'",
                          root, opts, lg_test_path(t, out)) < 0)
        exit(99);
    if (system(cmd) != 0) {
        fprintf(stderr, "FAIL: %s\n", cmd);
        exit(1);
    }
    free(cmd);
}

static void case_prt_motion(lg_test *t)
{
    const char *sky = lg_test_asset("probes/forest_1024x512.hdr");
    if (!sky) {
        LG_TEST_CHECK(t, false, "asset probes/forest_1024x512.hdr is missing");
        return;
    }
    gen_torus(t, "--anim-rotation '0:0,0,1,0;2:0,0,1,180'", "anim.glb");
    static const int deg[4] = { 0, 45, 90, 135 };
    for (int k = 0; k < 4; k++) {
        char opt[64], name[32];
        snprintf(opt, sizeof opt, "--rotate 0,0,1,%d", deg[k]);
        snprintf(name, sizeof name, "s%d.glb", deg[k]);
        gen_torus(t, opt, name);
    }
    static const char *const backends[] = { "cpu", "gl" };
    for (int b = 0; b < 2; b++) {
        for (int k = -1; k < 4; k++) {
            /* k = -1: the animated file over 4 frames of 0.5 s; else the static pose k */
            char *g = NULL, file[32], out[32];
            if (k < 0)
                snprintf(file, sizeof file, "anim.glb"), snprintf(out, sizeof out, "v_%%d.exr");
            else
                snprintf(file, sizeof file, "s%d.glb", deg[k]),
                    snprintf(out, sizeof out, "s_%d.exr", deg[k]);
            if (asprintf(&g,
                         "lightgraph 1\nscene = gltf { file = \"%s\" }\n"
                         "sky = probe { file = \"%s\" }\n"
                         "light = sh_project { probe = sky, bands = 4 }\n"
                         "bake = prt_bake { scene = scene, mode = shadowed, bands = 4, "
                         "samples = 64 }\n"
                         "p = prt { scene = scene, lighting = light, transfer = bake, "
                         "backend = %s }\noutput p.vertices \"%s\" float\n",
                         file, sky, backends[b], out) < 0)
                exit(99);
            lg_test_write_text(t, "g.lgraph", g);
            free(g);
            const char *args[] = { "--frames", k < 0 ? "4" : "1", "--dt", "0.5",
                                   "--size",   "32x32",           NULL };
            char *text = NULL;
            int rc = lg_test_render(t, "g.lgraph", args, &text);
            if (lg_test_output_says_no_device(text))
                lg_test_skip(t, "no GL device");
            LG_TEST_CHECK(t, rc == 0, "%s, %s: %s", backends[b], file, text ? text : "");
            free(text);
        }
        for (int k = 0; k < 4; k++) {
            char a[32], s[32];
            snprintf(a, sizeof a, "v_%d.exr", k);
            snprintf(s, sizeof s, "s_%d.exr", deg[k]);
            double mx, mean;
            vertex_diff(t, a, s, &mx, &mean);
            printf("%s: frame %d (%d deg) against the bake at that pose: max %.4g, mean %.3g\n",
                   backends[b], k, deg[k], mx, mean);
            LG_TEST_CHECK(t, mx <= 0.015 && mean <= 2e-4,
                          "%s: frame %d (%d deg): max |diff| %g, mean %g (want <= 0.015, 2e-4)",
                          backends[b], k, deg[k], mx, mean);
        }
        double mx, mean;
        vertex_diff(t, "s_0.exr", "s_90.exr", &mx, &mean);
        LG_TEST_CHECK(t, mx > 0.3, "the poses do not differ (%g): the check could not fail", mx);
    }
}

static void refused(lg_test *t, const char *what, const char *node0, const char *extra,
                    const char *anim, const char *skins, const char *says)
{
    write_gltf(t, "bad.gltf", node0, extra, anim, skins);
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nscene = gltf { file = \"bad.gltf\" }\n"
                       "v = preview { scene = scene }\noutput v \"out.exr\"\n");
    const char *args[] = { "--size", "8x8", NULL };
    char *out = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    LG_TEST_CHECK(t, rc == 1 && out && strstr(out, "bad.gltf") && strstr(out, says),
                  "%s: exit %d (want 1), want \"%s\": %s", what, rc, says, out ? out : "");
    LG_TEST_CHECK(t, !exists(t, "out.exr"), "%s: an output was written", what);
    free(out);
}

static void case_refused(lg_test *t)
{
    write_bin(t);
    refused(t, "non-increasing times", "", "",
            "[{\"name\":\"back\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":"
            "\"translation\"}}],\"samplers\":[{\"input\":5,\"output\":3}]}]",
            "",
            "animation 0 ('back'), channel 0: key times must strictly increase, but key 2 (0.5 s) "
            "does not follow key 1 (1 s)");
    refused(t, "NaN key", "", "",
            "[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}}],"
            "\"samplers\":[{\"input\":2,\"output\":4}]}]",
            "",
            "(animation 0 ('animation 0'), channel 0, output (translation values)): element 1 "
            "component 1 is NaN");
    refused(t, "missing node", "", "",
            "[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":7,\"path\":\"translation\"}}],"
            "\"samplers\":[{\"input\":2,\"output\":3}]}]",
            "", "channel 0: target node 7 does not exist (the file has 2)");
    refused(t, "matrix node", ",\"matrix\":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]", "",
            "[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}}],"
            "\"samplers\":[{\"input\":2,\"output\":3}]}]",
            "", "animates node 0, which is given by a matrix");
    refused(t, "skin", "", ",{\"name\":\"joint\"}",
            "[{\"name\":\"walk\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":2,\"path\":"
            "\"translation\"}}],\"samplers\":[{\"input\":2,\"output\":3}]}]",
            "[{\"joints\":[2]}]",
            "animation 0 ('walk'), channel 0: animates node 2, a joint of skin 0: skinned "
            "animation is not supported");
    refused(t, "morph weights", "", "",
            "[{\"name\":\"blink\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":"
            "\"weights\"}}],\"samplers\":[{\"input\":2,\"output\":2}]}]",
            "", "animation 0 ('blink'), channel 0: animates the morph-target weights of node 0");
    refused(t, "interpolation", "", "",
            "[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}}],"
            "\"samplers\":[{\"input\":2,\"output\":3,\"interpolation\":\"BEZIER\"}]}]",
            "", "interpolation 'BEZIER' (supported: LINEAR, STEP, CUBICSPLINE)");
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "frames", case_frames },   { "runs", case_runs },     { "pattern", case_pattern },
        { "refused", case_refused }, { "truck", case_truck },   { "prt_motion", case_prt_motion },
        { "camera", case_camera },   { "shadow", case_shadow },
    };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], NULL);
}
