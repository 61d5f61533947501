/*
 * test_gltf_host: the `gltf` node through the host, as a user runs it (`lightgraph render
 * --explain`), with the test plugin `test_fog` (tests/plugins/testnodes: needs a medium
 * and a light) downstream.
 *
 *   test_gltf_host CASE
 *
 *   explain        --explain prints the bunny box's scene features; test_fog is gated (no
 *                  medium) and its plugin never loaded
 *   medium         a scene with a medium and a light: test_fog runs and writes its value
 *   reflective     test_reflective (needs a reflective material) on the bunny box, whose
 *                  materials are dielectrics: gated ("no reflective material"), plugin not
 *                  loaded, "reflective materials 0"; on a triangle of a metal: kept, run,
 *                  "reflective materials 1"; with extras.reflectivity 0 on the metal: gated
 *   errors         bad files and parameters: exit status 1, the node and the file named;
 *                  a buffer uri leading to /etc/passwd refused (no bounds from its bytes)
 *   textures       the Duck: --explain prints "textures 1", --profile counts its decoded
 *                  512 x 512 image (1.0 MiB) against the gltf node; the Duck with a corrupt
 *                  DuckCM.png: exit status 1 naming the node, the file and the image
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "lightgraph/test.h"

#ifndef PT_TESTNODES_DIR
#define PT_TESTNODES_DIR ""
#endif

static const char *asset(const char *rel)
{
    const char *p = lg_test_asset(rel);
    if (!p) {
        /* a repository file: missing is a failure, never a skip */
        fprintf(stderr, "FAIL: asset %s is missing\n", rel);
        exit(1);
    }
    return p;
}

/* The line of `s` that starts with `prefix` (after leading spaces: the explain table's
 * rows are indented), or "". */
static void line_of(const char *s, const char *prefix, char *out, size_t size)
{
    out[0] = 0;
    for (const char *l = s; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL)
        if (!strncmp(l + strspn(l, " "), prefix, strlen(prefix))) {
            size_t n = strcspn(l, "\n");
            snprintf(out, size, "%.*s", (int)n, l);
            return;
        }
}

static void case_explain(lg_test *t)
{
    lg_test_use_plugins(NULL, PT_TESTNODES_DIR);
    char *g = NULL;
    if (asprintf(&g,
                 "lightgraph 1\nscene = gltf { file = \"%s\" }\n"
                 "fog = test_fog { scene = scene, value = 0.5 }\noutput fog \"out.exr\"\n",
                 asset("meshes/bunny_cornell_box.glb")) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--explain", "--size", "8x4", NULL };
    char *out = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, &out) == 0, "render failed");
    const char *s = out ? out : "";
    LG_TEST_CHECK(t, strstr(s, "scene features (scene): triangles 5009, vertices "),
                  "no scene features: %s", s);
    LG_TEST_CHECK(
        t,
        strstr(s, "lights: 0 directional, 0 point, 0 other; medium no (density 0); probe no; "
                  "specular material yes"),
        "features: %s", s);
    LG_TEST_CHECK(t, strstr(s, "gated") && strstr(s, "no participating medium"),
                  "fog was not gated: %s", s);
    char loaded[512], not_loaded[512];
    line_of(s, "plugins loaded:", loaded, sizeof loaded);
    line_of(s, "plugins not loaded:", not_loaded, sizeof not_loaded);
    LG_TEST_CHECK(t,
                  strstr(loaded, "scene_gltf") && !strstr(loaded, "testfog") &&
                      strstr(not_loaded, "testfog"),
                  "testfog was loaded although gated, or scene_gltf was not: '%s' / '%s'", loaded,
                  not_loaded);
    free(out);
    /* the neutral result: a black image */
    lg_image img;
    if (lg_test_read(t, "out.exr", &img, NULL)) {
        LG_TEST_CHECK(t, img.width == 8 && img.height == 4 && img.pixels[0] == 0, "neutral output");
        lg_image_free(&img);
    }
    /* --set overrides the file: the Draco variant gives the same features */
    const char *args2[] = { "--explain", "--size", "8x4", "--set", NULL, NULL };
    char *set = NULL;
    if (asprintf(&set, "scene.file=%s", asset("meshes/bunny_cornell_box_draco.glb")) < 0)
        exit(99);
    args2[4] = set;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args2, &out) == 0,
                  "render with the Draco file failed");
    LG_TEST_CHECK(t, out && strstr(out, "scene features (scene): triangles 5009"), "%s",
                  out ? out : "");
    free(out);
    free(set);
}

static void case_medium(lg_test *t)
{
    lg_test_use_plugins(NULL, PT_TESTNODES_DIR);
    /* one triangle, a directional light and a medium on the scene */
    static const char gltf[] =
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"tri.bin\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"meshes\":[{\"primitives\":[{"
        "\"attributes\":{\"POSITION\":0}}]}],\"nodes\":[{\"mesh\":0},{\"extensions\":{"
        "\"KHR_lights_punctual\":{\"light\":0}}}],\"scenes\":[{\"nodes\":[0,1],\"extras\":{\"medium\":"
        "{\"density\":0.25,\"scattering\":[0.1,0.1,0.1],\"absorption\":0.01,\"g\":0.4}}}],"
        "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"directional\",\"intensity\":2}]}}}";
    lg_test_write_text(t, "fog.gltf", gltf);
    static const float tri[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    FILE *f = fopen(lg_test_path(t, "tri.bin"), "wb");
    if (!f || fwrite(tri, 1, sizeof tri, f) != sizeof tri || fclose(f))
        exit(99);
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nscene = gltf { file = \"fog.gltf\" }\n"
                       "fog = test_fog { scene = scene, value = 0.5 }\noutput fog \"out.exr\"\n");
    const char *args[] = { "--explain", "--size", "4x2", NULL };
    char *out = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, &out) == 0, "render failed");
    const char *s = out ? out : "";
    LG_TEST_CHECK(
        t,
        strstr(s,
               "scene features (scene): triangles 1, vertices 3, lights: 1 directional, 0 point, "
               "0 other; medium yes (density 0.25)"),
        "features: %s", s);
    LG_TEST_CHECK(t, !strstr(s, "gated"), "fog was gated: %s", s);
    free(out);
    lg_image img;
    if (lg_test_read(t, "out.exr", &img, NULL)) {
        LG_TEST_CHECK(t, img.pixels[0] == 0.5f, "fog did not run: %g", img.pixels[0]);
        lg_image_free(&img);
    }
}

/* One triangle drawn with material `mat` (JSON of one glTF material). */
static void write_triangle(lg_test *t, const char *name, const char *mat)
{
    char *gltf = NULL;
    if (asprintf(
            &gltf,
            "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"tri.bin\"}],"
            "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
            "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"materials\":[%s],\"meshes\":[{\"primitives\":"
            "[{\"attributes\":{\"POSITION\":0},\"material\":0}]}],\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]}",
            mat) < 0)
        exit(99);
    lg_test_write_text(t, name, gltf);
    free(gltf);
    static const float tri[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    FILE *f = fopen(lg_test_path(t, "tri.bin"), "wb");
    if (!f || fwrite(tri, 1, sizeof tri, f) != sizeof tri || fclose(f))
        exit(99);
}

/* Renders test_reflective on `file`: checks the features line says `features`, the node's
 * state (and reason when gated), testfog loaded or not, and the image it wrote. */
static void reflective_run(lg_test *t, const char *what, const char *file, const char *features,
                           bool kept)
{
    lg_test_use_plugins(NULL, PT_TESTNODES_DIR);
    char *g = NULL;
    if (asprintf(
            &g,
            "lightgraph 1\nscene = gltf { file = \"%s\" }\n"
            "mirror = test_reflective { scene = scene, value = 0.75 }\noutput mirror \"out.exr\"\n",
            file) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--explain", "--size", "8x4", NULL };
    char *out = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, &out) == 0, "%s: render failed: %s", what,
                  out ? out : "");
    const char *s = out ? out : "";
    char line[1024];
    line_of(s, "scene features (scene):", line, sizeof line);
    LG_TEST_CHECK(t, strstr(line, features), "%s: features do not say '%s': %s", what, features, s);
    line_of(s, "mirror ", line, sizeof line);
    if (kept)
        LG_TEST_CHECK(t, strstr(line, "kept") != NULL, "%s: test_reflective not kept: %s", what, s);
    else
        LG_TEST_CHECK(t, strstr(line, "gated") && strstr(line, "no reflective material"),
                      "%s: test_reflective not gated with 'no reflective material': %s", what, s);
    char loaded[512];
    line_of(s, "plugins loaded:", loaded, sizeof loaded);
    LG_TEST_CHECK(t, (strstr(loaded, "testfog") != NULL) == kept, "%s: testfog %s: '%s'", what,
                  kept ? "not loaded though kept" : "loaded though gated", loaded);
    free(out);
    lg_image img;
    if (lg_test_read(t, "out.exr", &img, NULL)) {
        float want = kept ? 0.75f : 0.0f;
        LG_TEST_CHECK(t,
                      img.width == 8 && img.height == 4 && img.pixels[0] == want &&
                          img.pixels[4 * 31 + 1] == want,
                      "%s: image %ux%u value %g, want %g", what, img.width, img.height,
                      (double)img.pixels[0], (double)want);
        lg_image_free(&img);
    }
}

static void case_reflective(lg_test *t)
{
    /* the bunny box: walls with KHR_materials_specular colour 0 and a plain dielectric bunny */
    reflective_run(t, "bunny box", asset("meshes/bunny_cornell_box.glb"),
                   "specular material yes; reflective materials 0", false);
    write_triangle(
        t, "metal.gltf",
        "{\"name\":\"steel\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.6,0.6,0.6,1],"
        "\"metallicFactor\":1,\"roughnessFactor\":0.3}}");
    reflective_run(t, "metal", "metal.gltf", "reflective materials 1", true);
    write_triangle(
        t, "off.gltf",
        "{\"name\":\"steel\",\"pbrMetallicRoughness\":{\"metallicFactor\":1},\"extras\":{\"reflectivity\":0}}");
    reflective_run(t, "metal with extras.reflectivity 0", "off.gltf", "reflective materials 0",
                   false);
    write_triangle(
        t, "painted.gltf",
        "{\"name\":\"paint\",\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"extras\":{\"reflectivity\":"
        "[0,0,0.1]}}");
    reflective_run(t, "dielectric with extras.reflectivity", "painted.gltf",
                   "reflective materials 1", true);
}

static void case_errors(lg_test *t)
{
    static const struct {
        const char *file, *content, *want;
    } cases[] = {
        { "short.glb", "glTF\x02\0\0\0\xff\xff\0\0", "truncated GLB" },
        { "bad.gltf",
          "{\"asset\":{\"version\":\"2.0\"},\"extensionsRequired\":[\"EXT_meshopt_compression\"]}",
          "requires extension 'EXT_meshopt_compression'" },
        { "missing.gltf",
          "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":4,\"uri\":\"nope.bin\"}]}",
          "nope.bin" },
        { "nothing.gltf", NULL, "cannot read it: No such file or directory" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        if (cases[i].content)
            lg_test_write_text(t, cases[i].file, cases[i].content);
        char g[512];
        snprintf(g, sizeof g,
                 "lightgraph 1\nscene = gltf { file = \"%s\" }\n"
                 "fog = test_fog { scene = scene }\noutput fog \"out.exr\"\n",
                 cases[i].file);
        lg_test_write_text(t, "g.lgraph", g);
        char *out = NULL;
        lg_test_use_plugins(NULL, PT_TESTNODES_DIR);
        int rc = lg_test_render(t, "g.lgraph", NULL, &out);
        LG_TEST_CHECK(t, rc == 1, "%s: exit %d, want 1", cases[i].file, rc);
        LG_TEST_CHECK(t,
                      out && strstr(out, cases[i].file) && strstr(out, cases[i].want) &&
                          strstr(out, "scene"),
                      "%s: the message names neither the node, the file nor the reason: %s",
                      cases[i].file, out ? out : "");
        free(out);
    }
    /* a buffer uri leaving the model's folder (issue 8): refused with the uri and where it
     * leads; before, /etc/passwd was read and the error gave world bounds from its bytes */
    struct stat st;
    unsigned long long passwd_size = stat("/etc/passwd", &st) == 0 ? (unsigned long long)st.st_size
                                                                   : 36;
    char up[512] = "";
    int depth = 0;
    for (const char *p = lg_test_path(t, "x"); *p; p++)
        depth += *p == '/';
    for (int i = 0; i < depth && strlen(up) + 16 < sizeof up; i++)
        strcat(up, "../");
    strcat(up, "etc/passwd");
    char gltf[1024], want[600];
    snprintf(gltf, sizeof gltf,
             "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%llu,\"uri\":\"%s\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
             "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"meshes\":[{\"primitives\":[{"
             "\"attributes\":{\"POSITION\":0}}]}],\"nodes\":[{\"mesh\":0}]}",
             passwd_size, up);
    lg_test_write_text(t, "escape.gltf", gltf);
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nscene = gltf { file = \"escape.gltf\" }\n"
                       "fog = test_fog { scene = scene }\noutput fog \"out.exr\"\n");
    char *esc = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, &esc) == 1, "escaping buffer: not exit 1");
    snprintf(want, sizeof want, "buffer 0: cannot read '%s': it leads to '/etc/passwd', outside '",
             up);
    LG_TEST_CHECK(t,
                  esc && strstr(esc, "node 'scene' (gltf): file '") && strstr(esc, want) &&
                      !strstr(esc, "bounds"),
                  "escaping buffer: want '%s' and no bounds: %s", want, esc ? esc : "");
    free(esc);

    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nscene = gltf { }\nfog = test_fog { scene = scene }\n"
                       "output fog \"out.exr\"\n");
    char *out = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, &out) == 1,
                  "empty file parameter accepted");
    LG_TEST_CHECK(t, out && strstr(out, "parameter 'file' is empty"), "%s", out ? out : "");
    free(out);
}

static void case_textures(lg_test *t)
{
    lg_test_use_plugins(NULL, PT_TESTNODES_DIR);
    char *g = NULL;
    if (asprintf(&g,
                 "lightgraph 1\nscene = gltf { file = \"%s\" }\n"
                 "view = preview { scene = scene }\noutput view \"out.png\"\n",
                 asset("meshes/duck/Duck.gltf")) < 0)
        exit(99);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[] = { "--explain", "--profile", "--size", "8x4", NULL };
    char *out = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, &out) == 0, "Duck render failed: %s",
                  out ? out : "");
    const char *s = out ? out : "";
    LG_TEST_CHECK(t,
                  strstr(s, "scene features (scene): triangles 4212") &&
                      strstr(s, "textures 1; masked materials 0"),
                  "Duck features: %s", s);
    /* the profile's row of the gltf node: its plugin memory is the decoded image */
    char row[512] = "", *p = strstr(s, "profile (");
    line_of(p ? p : "", "scene ", row, sizeof row);
    LG_TEST_CHECK(t, strstr(row, "gltf") && strstr(row, "1.0 MiB"),
                  "profile row of the gltf node: '%s'", row);
    free(out);

    /* the same Duck with a corrupt texture: exit status 1, node, file and image named */
    size_t n = 0;
    static const char *const parts[] = { "Duck.gltf", "Duck0.bin", "DuckCM.png" };
    for (int i = 0; i < 3; i++) {
        char rel[64];
        snprintf(rel, sizeof rel, "meshes/duck/%s", parts[i]);
        FILE *f = fopen(asset(rel), "rb");
        char *buf = malloc(1 << 20);
        n = f && buf ? fread(buf, 1, 1 << 20, f) : 0;
        if (f)
            fclose(f);
        if (i == 2 && n > 100)
            memset(buf + n / 2, 0x5a, 32); /* inside the compressed pixels */
        char *dst = NULL;
        if (asprintf(&dst, "%s", lg_test_path(t, parts[i])) < 0)
            exit(99);
        FILE *o = fopen(dst, "wb");
        if (!o || fwrite(buf, 1, n, o) != n || fclose(o))
            exit(99);
        free(dst);
        free(buf);
    }
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nscene = gltf { file = \"Duck.gltf\" }\n"
                       "view = preview { scene = scene }\noutput view \"out.png\"\n");
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, &out) == 1, "corrupt texture: not exit 1");
    LG_TEST_CHECK(t,
                  out && strstr(out, "node 'scene' (gltf): file '") && strstr(out, "Duck.gltf") &&
                      strstr(out, "image 0 ('DuckCM.png'): cannot decode it: PNG"),
                  "corrupt texture: %s", out ? out : "");
    free(out);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "explain", case_explain },       { "medium", case_medium },
        { "reflective", case_reflective }, { "errors", case_errors },
        { "textures", case_textures },
    };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], NULL);
}
