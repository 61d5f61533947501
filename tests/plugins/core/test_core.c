/*
 * The core plugin through the host: `test_core CASE`. Each case writes its inputs and a
 * graph into a scratch folder, runs `lightgraph render` and checks the output file.
 *
 *   image_roundtrip     a float EXR comes out as it went in
 *   image_radiance      negatives clamped (radiance = true) with one warning naming the
 *                       file and the count; kept with radiance = false
 *   image_errors        a missing and a corrupt file: exit 1, the message names the file
 *   image_content_key   a file rewritten with the same size and mtime still invalidates a
 *                       downstream cache entry (the key hashes the content)
 *   constant            explicit size, and width/height 0 = --size
 *   add                 a + b, alpha min(1, a + b); different sizes fail naming both
 *   add_neutral         a gated (neutral) input: the output is the other input
 *   scale               RGB * factor * tint, alpha unchanged
 */
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "lightgraph/test.h"

#ifndef PT_TESTNODES_DIR
#define PT_TESTNODES_DIR ""
#endif

static lg_image make_image(uint32_t w, uint32_t h, float seed)
{
    lg_image img;
    if (lg_image_alloc(&img, w, h)) {
        fprintf(stderr, "lg_image_alloc failed\n");
        exit(99);
    }
    for (uint32_t i = 0; i < w * h; i++) {
        img.pixels[i * 4 + 0] = seed + 0.25f * (float)i;
        img.pixels[i * 4 + 1] = seed * 2.0f + 0.5f;
        img.pixels[i * 4 + 2] = 1000.0f / (float)(i + 1);
        img.pixels[i * 4 + 3] = i % 2 ? 1.0f : 0.5f;
    }
    return img;
}

/* Every channel of `got` equals `want` within the file's precision. */
static void check_same(lg_test *t, const lg_image *got, const lg_image *want, unsigned bits,
                       const char *what)
{
    LG_TEST_CHECK(t, got->width == want->width && got->height == want->height,
                  "%s: size %ux%u, want %ux%u", what, got->width, got->height, want->width,
                  want->height);
    if (got->width != want->width || got->height != want->height)
        return;
    int reported = 0;
    for (size_t i = 0; i < (size_t)want->width * want->height * 4; i++) {
        double e = want->pixels[i], g = got->pixels[i];
        if (!(fabs(g - e) <= lg_test_tol_of(e, bits, 1e-7)) && reported++ < 5)
            LG_TEST_CHECK(t, 0, "%s: pixel %zu channel %zu is %.9g, want %.9g", what, i / 4, i % 4,
                          g, e);
    }
}

static void case_image_roundtrip(lg_test *t)
{
    lg_image in = make_image(7, 5, 0.125f);
    lg_test_write_exr(t, "in.exr", &in);
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nsrc = image { file = \"in.exr\" }\noutput src \"out.exr\"\n");
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, NULL) == 0, "render failed");
    lg_image out;
    unsigned bits = 0;
    if (lg_test_read(t, "out.exr", &out, &bits)) {
        check_same(t, &out, &in, bits, "round trip");
        lg_image_free(&out);
    }
    /* -o and --set src.file= override the graph, as the README's commands do */
    lg_image other = make_image(3, 2, 9.0f);
    lg_test_write_exr(t, "other.exr", &other);
    const char *args[] = { "-o", "o2.exr", "--set", "src.file=other.exr", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, NULL) == 0,
                  "render with overrides failed");
    if (lg_test_read(t, "o2.exr", &out, &bits)) {
        check_same(t, &out, &other, bits, "--set src.file");
        lg_image_free(&out);
    }
    lg_image_free(&in);
    lg_image_free(&other);
}

static void case_image_radiance(lg_test *t)
{
    lg_image in = make_image(4, 4, 1.0f);
    in.pixels[5 * 4 + 1] = -0.5f;
    in.pixels[9 * 4 + 0] = -3.0f;
    lg_test_write_exr(t, "neg.exr", &in);
    lg_test_write_text(
        t, "g.lgraph",
        "lightgraph 1\nsrc = image { file = \"neg.exr\" }\noutput src \"out.exr\"\n");
    char *err = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, &err) == 0, "render failed");
    LG_TEST_CHECK(t, err && strstr(err, "neg.exr") && strstr(err, "2 pixels"),
                  "no warning naming the file and the count 2: %s", err ? err : "");
    free(err);
    lg_image out, want = make_image(4, 4, 1.0f);
    want.pixels[5 * 4 + 1] = 0.0f;
    want.pixels[9 * 4 + 0] = 0.0f;
    unsigned bits;
    if (lg_test_read(t, "out.exr", &out, &bits)) {
        check_same(t, &out, &want, bits, "radiance = true");
        lg_image_free(&out);
    }
    lg_test_write_text(
        t, "g2.lgraph",
        "lightgraph 1\nsrc = image { file = \"neg.exr\", radiance = false }\noutput src \"out2.exr\"\n");
    err = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g2.lgraph", NULL, &err) == 0, "render failed");
    LG_TEST_CHECK(t, err && !strstr(err, "clamped"), "radiance = false warned: %s", err ? err : "");
    free(err);
    if (lg_test_read(t, "out2.exr", &out, &bits)) {
        check_same(t, &out, &in, bits, "radiance = false");
        lg_image_free(&out);
    }
    lg_image_free(&in);
    lg_image_free(&want);
}

static void case_image_errors(lg_test *t)
{
    lg_test_write_text(
        t, "g.lgraph",
        "lightgraph 1\nsrc = image { file = \"nope.exr\" }\noutput src \"out.exr\"\n");
    char *err = NULL;
    int rc = lg_test_render(t, "g.lgraph", NULL, &err);
    LG_TEST_CHECK(t, rc == 1, "missing file: exit %d, want 1", rc);
    LG_TEST_CHECK(t, err && strstr(err, "nope.exr") && strstr(err, "src"),
                  "message names neither the file nor the node: %s", err ? err : "");
    free(err);
    lg_test_write_text(t, "bad.exr", "this is not an EXR file\n");
    lg_test_write_text(
        t, "g2.lgraph",
        "lightgraph 1\nsrc = image { file = \"bad.exr\" }\noutput src \"out.exr\"\n");
    err = NULL;
    rc = lg_test_render(t, "g2.lgraph", NULL, &err);
    LG_TEST_CHECK(t, rc == 1, "corrupt file: exit %d, want 1", rc);
    LG_TEST_CHECK(t, err && strstr(err, "bad.exr"), "message does not name the file: %s",
                  err ? err : "");
    free(err);
}

static void case_image_content_key(lg_test *t)
{
    lg_test_use_plugins(t, PT_TESTNODES_DIR);
    lg_image a = make_image(8, 8, 1.0f), b = make_image(8, 8, 5.0f);
    lg_test_write_exr(t, "in.exr", &a);
    struct stat st0;
    stat(lg_test_path(t, "in.exr"), &st0);
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nsrc = image { file = \"in.exr\" }\n"
                       "m = test_cached { image = src }\noutput m \"out.exr\"\n");
    char *err = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, &err) == 0, "first render failed");
    LG_TEST_CHECK(t, err && strstr(err, "computed"), "first render did not compute: %s",
                  err ? err : "");
    free(err);
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, &err) == 0, "second render failed");
    LG_TEST_CHECK(t, err && strstr(err, "reused"), "same file: the cache was not used: %s",
                  err ? err : "");
    free(err);

    /* same size (uncompressed float), same mtime, other pixels */
    lg_test_write_exr(t, "in.exr", &b);
    struct stat st1;
    stat(lg_test_path(t, "in.exr"), &st1);
    LG_TEST_CHECK(t, st1.st_size == st0.st_size,
                  "sizes differ (%lld, %lld): the test needs equal sizes", (long long)st0.st_size,
                  (long long)st1.st_size);
    struct timespec times[2] = { st0.st_atim, st0.st_mtim };
    utimensat(AT_FDCWD, lg_test_path(t, "in.exr"), times, 0);
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, &err) == 0, "third render failed");
    LG_TEST_CHECK(t, err && strstr(err, "computed"),
                  "changed content, same size and mtime: stale cache: %s", err ? err : "");
    free(err);
    lg_image out;
    unsigned bits;
    if (lg_test_read(t, "out.exr", &out, &bits)) {
        double mean = 0;
        for (int i = 0; i < 64; i++)
            mean += b.pixels[i * 4 + 1] / 64.0;
        LG_TEST_CHECK(t, fabs(out.pixels[1] - mean) <= lg_test_tol_of(mean, bits, 1e-5),
                      "mean %.9g, want %.9g", out.pixels[1], mean);
        lg_image_free(&out);
    }
    lg_image_free(&a);
    lg_image_free(&b);
}

static void check_constant(lg_test *t, const char *file, uint32_t w, uint32_t h, const float px[4])
{
    lg_image out;
    unsigned bits;
    if (!lg_test_read(t, file, &out, &bits))
        return;
    LG_TEST_CHECK(t, out.width == w && out.height == h, "%s: %ux%u, want %ux%u", file, out.width,
                  out.height, w, h);
    int bad = 0;
    for (size_t i = 0; i < (size_t)out.width * out.height * 4; i++)
        bad += !(fabs(out.pixels[i] - px[i % 4]) <= lg_test_tol_of(px[i % 4], bits, 1e-7));
    LG_TEST_CHECK(t, bad == 0, "%s: %d channel values differ from (%g %g %g %g)", file, bad, px[0],
                  px[1], px[2], px[3]);
    lg_image_free(&out);
}

static void case_constant(lg_test *t)
{
    lg_test_write_text(
        t, "g.lgraph",
        "lightgraph 1\nc = constant { color = [0.5, 2, 1000], alpha = 0.25, width = 13, height = 3 }\n"
        "d = constant { }\noutput c \"c.exr\"\noutput d \"d.exr\"\n");
    const char *args[] = { "--size", "21x9", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, NULL) == 0, "render failed");
    check_constant(t, "c.exr", 13, 3, (const float[4]){ 0.5f, 2.0f, 1000.0f, 0.25f });
    check_constant(t, "d.exr", 21, 9, (const float[4]){ 0.18f, 0.18f, 0.18f, 1.0f });
}

static void case_add(lg_test *t)
{
    lg_image a = make_image(6, 4, 1.0f), b = make_image(6, 4, 3.0f), want;
    lg_image_alloc(&want, 6, 4);
    for (size_t i = 0; i < 24 * 4; i++)
        want.pixels[i] = i % 4 == 3 ? fminf(1.0f, a.pixels[i] + b.pixels[i])
                                    : a.pixels[i] + b.pixels[i];
    lg_test_write_exr(t, "a.exr", &a);
    lg_test_write_exr(t, "b.exr", &b);
    lg_test_write_text(
        t, "g.lgraph",
        "lightgraph 1\na = image { file = \"a.exr\" }\nb = image { file = \"b.exr\" }\n"
        "s = add { a = a, b = b }\noutput s \"out.exr\"\n");
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, NULL) == 0, "render failed");
    lg_image out;
    unsigned bits;
    if (lg_test_read(t, "out.exr", &out, &bits)) {
        check_same(t, &out, &want, bits, "a + b");
        lg_image_free(&out);
    }
    /* sizes must match */
    lg_image c = make_image(5, 4, 1.0f);
    lg_test_write_exr(t, "c.exr", &c);
    const char *args[] = { "--set", "b.file=c.exr", NULL };
    char *err = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &err);
    LG_TEST_CHECK(t, rc == 1, "different sizes: exit %d, want 1", rc);
    LG_TEST_CHECK(t, err && strstr(err, "6x4") && strstr(err, "5x4"),
                  "message does not name both sizes: %s", err ? err : "");
    free(err);
    lg_image_free(&a);
    lg_image_free(&b);
    lg_image_free(&c);
    lg_image_free(&want);
}

static void case_add_neutral(lg_test *t)
{
    lg_test_use_plugins(NULL, PT_TESTNODES_DIR);
    lg_image a = make_image(6, 4, 1.0f);
    lg_test_write_exr(t, "a.exr", &a);
    /* test_fog needs a medium and a light: with medium_density 0 it is gated and its
     * output is a neutral black image the size of `a` */
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nscene = test_scene { medium_density = 0 }\n"
                       "a = image { file = \"a.exr\" }\n"
                       "fog = test_fog { scene = scene, image = a, value = 0.5 }\n"
                       "s = add { a = fog, b = a }\ns2 = add { a = a, b = fog }\n"
                       "output s \"out.exr\"\noutput s2 \"out2.exr\"\n");
    const char *explain[] = { "--explain", NULL };
    char *err = NULL;
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", explain, &err) == 0, "render failed");
    LG_TEST_CHECK(t, err && strstr(err, "gated"), "fog was not gated: %s", err ? err : "");
    free(err);
    lg_image out;
    unsigned bits;
    if (lg_test_read(t, "out.exr", &out, &bits)) {
        check_same(t, &out, &a, bits, "neutral a");
        lg_image_free(&out);
    }
    if (lg_test_read(t, "out2.exr", &out, &bits)) {
        check_same(t, &out, &a, bits, "neutral b");
        lg_image_free(&out);
    }
    /* with a medium the fog runs: a + 0.5 */
    const char *args[] = { "--set", "scene.medium_density=1", NULL };
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, NULL) == 0, "render with a medium failed");
    if (lg_test_read(t, "out.exr", &out, &bits)) {
        lg_image want;
        lg_image_alloc(&want, 6, 4);
        for (size_t i = 0; i < 24 * 4; i++)
            want.pixels[i] = i % 4 == 3 ? 1.0f : a.pixels[i] + 0.5f;
        check_same(t, &out, &want, bits, "fog + a");
        lg_image_free(&want);
        lg_image_free(&out);
    }
    lg_image_free(&a);
}

static void case_scale(lg_test *t)
{
    lg_image a = make_image(5, 3, 2.0f), want;
    lg_image_alloc(&want, 5, 3);
    const float m[3] = { 2.5f * 1.0f, 2.5f * 0.5f, 2.5f * 0.25f };
    for (size_t i = 0; i < 15 * 4; i++)
        want.pixels[i] = i % 4 == 3 ? a.pixels[i] : a.pixels[i] * m[i % 4];
    lg_test_write_exr(t, "a.exr", &a);
    lg_test_write_text(
        t, "g.lgraph",
        "lightgraph 1\na = image { file = \"a.exr\" }\n"
        "s = scale { image = a, factor = 2.5, tint = [1, 0.5, 0.25] }\noutput s \"out.exr\"\n");
    LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", NULL, NULL) == 0, "render failed");
    lg_image out;
    unsigned bits;
    if (lg_test_read(t, "out.exr", &out, &bits)) {
        check_same(t, &out, &want, bits, "scale");
        lg_image_free(&out);
    }
    /* the default is the identity */
    lg_test_write_text(
        t, "g2.lgraph",
        "lightgraph 1\na = image { file = \"a.exr\" }\ns = scale { image = a }\noutput s \"out2.exr\"\n");
    LG_TEST_CHECK(t, lg_test_render(t, "g2.lgraph", NULL, NULL) == 0, "render failed");
    if (lg_test_read(t, "out2.exr", &out, &bits)) {
        check_same(t, &out, &a, bits, "scale default");
        lg_image_free(&out);
    }
    lg_image_free(&a);
    lg_image_free(&want);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "image_roundtrip", case_image_roundtrip },
        { "image_radiance", case_image_radiance },
        { "image_errors", case_image_errors },
        { "image_content_key", case_image_content_key },
        { "constant", case_constant },
        { "add", case_add },
        { "add_neutral", case_add_neutral },
        { "scale", case_scale },
    };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], NULL);
}
