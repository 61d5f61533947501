/*
 * tests/fuzz/fuzz_probe.c: the `probe` node's file reading (plugins/probe/probe_load.c:
 * pr_load_file) on arbitrary bytes, in every layout, through the image loaders (EXR, HDR,
 * PNG; sdk/src/image.c).
 *
 * Each input is written to a temporary file named for the format its first bytes suggest
 * (the EXR, "#?" and PNG signatures; otherwise the first byte chooses), then read as the
 * node reads it with layout = latlong (which takes any size), auto, angular, cross, strip,
 * and faces (the same file six times). For every read:
 *   - a refusal must report one error or more (through the node's host, faked here) and
 *     leave the result empty; an acceptance must report none;
 *   - an accepted probe has a size its layout allows (a square face, a square angular
 *     map), every colour channel finite and >= 0 and alpha 1 (what the node promises), and
 *     the same texels as the file: the lat-long read (the image as it is, sanitized) is
 *     the reference; an angular map is that image, a cross or strip written back with
 *     lg_probe_pack (the writer of `output`) gives that image in its face cells and zeroes
 *     elsewhere, and each of the six faces is that image;
 *   - its exact solid angles (lg_probe_solid_angles) are finite, >= 0, and sum to 4 pi.
 * The layout auto accepts only what one of the explicit layouts accepts, and the same.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_probe) to the plain driver (fuzz_driver.h):
 *
 *     fuzz_probe [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_driver.h"
#include "fuzz_image_file.h"
#include "lightgraph/image.h"
#include "lightgraph/vecmath.h"
#include "probe_load.h"

static unsigned long n_runs, n_ok[6];

/* ---- a host that only takes messages --------------------------------------------------------- */

static unsigned n_errors;
static char last_error[1024];

static void fake_log(lg_node *node, lg_log_level level, const char *fmt, va_list ap)
{
    (void)node;
    (void)level;
    char buf[1024];
    vsnprintf(buf, sizeof buf, fmt, ap); /* formatted, so that a bad argument shows */
}

static void fake_error(lg_node *node, const char *fmt, va_list ap)
{
    (void)node;
    n_errors++;
    vsnprintf(last_error, sizeof last_error, fmt, ap);
}

static lg_host_api fake_host = {
    .struct_size = sizeof(lg_host_api),
    .log = fake_log,
    .error = fake_error,
};
static lg_node fake_node = { .host = &fake_host, .name = "fuzz_probe" };

/* ---- the input as a file --------------------------------------------------------------------- */

static void bad(const char *layout, const char *what)
{
    fprintf(stderr, "fuzz_probe: layout %s: %s (input %lu)\n", layout, what, n_runs - 1);
    abort();
}

/* The pixel limit while fuzzing: 2^20 pixels (16 MiB as RGBA floats), so that a file that
 * declares more is refused before it is decoded; the probe's copies and solid angles are
 * then a few times that at most. */
#define FUZZ_MAX_PIXELS (1ull << 20)

static const char *const layout_names[6] = {
    "auto", "latlong", "angular", "cross", "strip", "faces"
};

/* Reads `path` with `want`; checks what the node promises of any result. 0 when read. */
static int load(int want, const char *path, pr_file *out)
{
    const char *faces[6] = { path, path, path, path, path, path };
    const char *name = layout_names[want];
    n_errors = 0;
    last_error[0] = '\0';
    uint64_t key = 0;
    int rc = want == PR_LAYOUT_FACES ? pr_load_file(&fake_node, want, "", faces, 6, out, &key)
                                     : pr_load_file(&fake_node, want, path, NULL, 0, out, &key);
    if (rc) {
        if (rc > 0 || !n_errors || !last_error[0])
            bad(name, "a refusal without an error message or with a positive code");
        if (out->texels || out->decoded.pixels || out->width || out->height)
            bad(name, "a refusal that leaves a probe");
        return rc;
    }
    if (n_errors)
        bad(name, "an acceptance that reported an error");
    n_ok[want]++;
    if (!out->texels || !out->width || !out->height)
        bad(name, "an empty probe");
    uint32_t faces_n = out->layout == LG_PROBE_CUBE ? 6 : 1;
    if ((out->layout == LG_PROBE_CUBE || out->layout == LG_PROBE_ANGULAR) &&
        out->width != out->height)
        bad(name, "a cube face or angular map that is not square");
    if ((uint64_t)out->width * out->height * faces_n > 6 * FUZZ_MAX_PIXELS)
        bad(name, "more texels than the file can hold");
    size_t texels = (size_t)out->width * out->height * faces_n;
    for (size_t i = 0; i < texels; i++) {
        const float *p = out->texels + 4 * i;
        for (int c = 0; c < 3; c++)
            if (!isfinite(p[c]) || p[c] < 0.0f || (p[c] == 0.0f && signbit(p[c])))
                bad(name, "a colour channel that is not finite and >= +0");
        if (p[3] != 1.0f)
            bad(name, "an alpha other than 1");
    }
    float *sa = malloc(texels * sizeof *sa);
    if (!sa)
        bad(name, "out of memory for the solid angles");
    if (lg_probe_solid_angles(out->layout, out->width, out->height, sa) != 0)
        bad(name, "lg_probe_solid_angles refuses the probe's size");
    double sum = 0;
    for (size_t i = 0; i < texels; i++) {
        if (!isfinite(sa[i]) || sa[i] < 0.0f)
            bad(name, "a solid angle that is not finite and >= 0");
        sum += sa[i];
    }
    free(sa);
    /* float texel angles summed in double: a relative 1e-4 is some thousand float ulps of
     * the largest term, far more than rounding, far less than a missing row or face */
    if (fabs(sum - 4.0 * LG_PI) > 1e-4 * 4.0 * LG_PI)
        bad(name, "solid angles that do not sum to 4 pi");
    return 0;
}

static bool same_texels(const float *a, const float *b, size_t n)
{
    return memcmp(a, b, n * 16) == 0;
}

/* A cube read from a cross or strip, written back as that file: the file's image (the
 * reference `ref`) in the face cells, zero elsewhere. */
static void check_pack(const char *name, const pr_file *cube, const pr_file *ref)
{
    lg_probe_info info;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    info.layout = LG_PROBE_CUBE;
    lg_probe_rotation_from_euler(0, 0, 0, info.rotation);
    info.file_layout = cube->file_layout;
    lg_image img;
    char err[256];
    if (lg_probe_pack(&info, cube->width, cube->height, cube->texels, &img, err, sizeof err))
        bad(name, "lg_probe_pack refuses a cube the node read");
    if (img.width != ref->width || img.height != ref->height)
        bad(name, "the cube written back has another size than its file");
    for (size_t i = 0; i < (size_t)img.width * img.height; i++) {
        const float *p = img.pixels + 4 * i, *q = ref->texels + 4 * i;
        static const float zero[4] = { 0, 0, 0, 0 };
        if (p[3] == 1.0f ? memcmp(p, q, 16) != 0 : memcmp(p, zero, 16) != 0)
            bad(name, "the cube written back differs from its file");
    }
    lg_image_free(&img);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lg_image_set_max_pixels(FUZZ_MAX_PIXELS);
    n_runs++;
    const char *path = lg_fuzz_image_file("fuzz-probe", data, size);

    /* the reference: latlong reads any image the loaders decode, as it is */
    pr_file ref;
    if (load(PR_LAYOUT_LATLONG, path, &ref)) {
        /* then nothing reads it */
        for (int want = PR_LAYOUT_AUTO; want <= PR_LAYOUT_FACES; want++) {
            pr_file p;
            if (want != PR_LAYOUT_LATLONG && load(want, path, &p) == 0)
                bad(layout_names[want], "a file the lat-long read refuses is read");
        }
        return 0;
    }
    if (ref.layout != LG_PROBE_LATLONG)
        bad("latlong", "not a lat-long");
    size_t px = (size_t)ref.width * ref.height;

    pr_file got[6];
    memset(got, 0, sizeof got);
    bool ok[6] = { false };
    for (int want = PR_LAYOUT_ANGULAR; want <= PR_LAYOUT_FACES; want++)
        ok[want] = load(want, path, &got[want]) == 0;
    if (ok[PR_LAYOUT_ANGULAR] && (got[PR_LAYOUT_ANGULAR].layout != LG_PROBE_ANGULAR ||
                                  got[PR_LAYOUT_ANGULAR].width != ref.width ||
                                  !same_texels(got[PR_LAYOUT_ANGULAR].texels, ref.texels, px)))
        bad("angular", "not the file's image");
    for (int want = PR_LAYOUT_CROSS; want <= PR_LAYOUT_STRIP; want++)
        if (ok[want]) {
            if (got[want].layout != LG_PROBE_CUBE)
                bad(layout_names[want], "not a cube");
            check_pack(layout_names[want], &got[want], &ref);
        }
    if (ok[PR_LAYOUT_FACES]) {
        const pr_file *c = &got[PR_LAYOUT_FACES];
        if (c->layout != LG_PROBE_CUBE || c->width != ref.width || ref.width != ref.height)
            bad("faces", "not a cube of the file's size");
        for (int face = 0; face < 6; face++)
            if (!same_texels(c->texels + (size_t)4 * face * px, ref.texels, px))
                bad("faces", "a face that is not the file's image");
    }
    /* auto: what the explicit layout of that shape reads (lat-long only for 2:1) */
    pr_file a;
    if (load(PR_LAYOUT_AUTO, path, &a) == 0) {
        int same = a.layout == LG_PROBE_ANGULAR   ? PR_LAYOUT_ANGULAR
                   : a.layout == LG_PROBE_LATLONG ? PR_LAYOUT_LATLONG
                   : (a.file_layout == LG_PROBE_FILE_STRIP || a.file_layout == LG_PROBE_FILE_VSTRIP)
                       ? PR_LAYOUT_STRIP
                       : PR_LAYOUT_CROSS;
        const pr_file *e = same == PR_LAYOUT_LATLONG ? &ref : &got[same];
        if ((same == PR_LAYOUT_LATLONG ? ref.width != 2 * ref.height : !ok[same]) ||
            a.width != e->width || a.height != e->height || a.file_layout != e->file_layout ||
            !same_texels(a.texels, e->texels,
                         (size_t)a.width * a.height * (a.layout == LG_PROBE_CUBE ? 6 : 1)))
            bad("auto", "not what the explicit layout reads");
        pr_file_clear(&a);
    }
    for (int want = 0; want < 6; want++)
        pr_file_clear(&got[want]);
    pr_file_clear(&ref);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* The image formats' pieces (as fuzz_image.c) and the sizes of each layout. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("\x76\x2f\x31\x01"),     LG_FUZZ_TOKEN("\x02\x00\x00\x00"),
    LG_FUZZ_TOKEN("dataWindow\0box2i\0"),  LG_FUZZ_TOKEN("channels\0chlist\0"),
    LG_FUZZ_TOKEN("#?RADIANCE\n"),         LG_FUZZ_TOKEN("FORMAT=32-bit_rle_rgbe\n"),
    LG_FUZZ_TOKEN("\n-Y 4 +X 8\n"),        LG_FUZZ_TOKEN("\n-Y 8 +X 8\n"),
    LG_FUZZ_TOKEN("\n-Y 6 +X 8\n"),        LG_FUZZ_TOKEN("\n-Y 8 +X 6\n"),
    LG_FUZZ_TOKEN("\n-Y 2 +X 12\n"),       LG_FUZZ_TOKEN("\n-Y 12 +X 2\n"),
    LG_FUZZ_TOKEN("\x02\x02\x00\x08"),     LG_FUZZ_TOKEN("\x89PNG\r\n\x1a\n"),
    LG_FUZZ_TOKEN("\0\0\0\x0dIHDR"),       LG_FUZZ_TOKEN("\0\0\0\x08\0\0\0\x06"),
    LG_FUZZ_TOKEN("\0\0\0\x0c\0\0\0\x02"), LG_FUZZ_TOKEN("IDAT"),
};

static void summary(FILE *out)
{
    fprintf(out, "read as auto %lu, latlong %lu, angular %lu, cross %lu, strip %lu, faces %lu",
            n_ok[0], n_ok[1], n_ok[2], n_ok[3], n_ok[4], n_ok[5]);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_probe",
        .mutations = 100,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .head = 512, /* image headers hold the sizes */
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
