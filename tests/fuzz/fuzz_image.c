/*
 * tests/fuzz/fuzz_image.c: the image loaders (EXR through OpenEXR's C and C++ APIs, Radiance
 * .hdr, PNG) on arbitrary bytes.
 *
 * Each input is written to a temporary file named for the format its first bytes suggest
 * (the EXR, "#?" and PNG signatures; otherwise the first byte chooses) and read with
 * lg_image_read, alternately with and without LG_READ_RADIANCE. A read must either fail
 * with a message or return a consistent image; anything else aborts, and the sanitizers
 * catch the rest.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus to the plain driver (fuzz_driver.h) with a dictionary of format tokens,
 * half of the edits in the first 512 bytes:
 *
 *     fuzz_image [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "fuzz_driver.h"
#include "fuzz_image_file.h"
#include "lightgraph/image.h"

static unsigned long n_runs, n_ok;

/* The pixel limit while fuzzing: 2^22 pixels (64 MiB as RGBA floats), well under the
 * default, so that an input just over it is refused before it is decoded rather than
 * allocating gigabytes (`make fuzz` counts a block over 1 GiB as a finding), and a memory
 * blow-up past -rss_limit_mb is a finding, not the limit at work. The oversized
 * declarations of the corpus (16384 x 16384) are refused by it as by the default. */
#define FUZZ_MAX_PIXELS (1ull << 22)

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lg_image_set_max_pixels(FUZZ_MAX_PIXELS);
    const char *path = lg_fuzz_image_file("fuzz-image", data, size);

    lg_image img;
    lg_image_read_info info;
    char err[512];
    memset(err, 0, sizeof err);
    unsigned flags = (n_runs++ & 1) ? LG_READ_RADIANCE : 0;
    int rc = lg_image_read(path, flags, &img, &info, err, sizeof err);
    if (rc != LG_OK) {
        if (!err[0] || img.pixels || img.width || img.height) {
            fprintf(stderr, "fuzz_image: failure %d without a message or with an image\n", rc);
            abort();
        }
        return 0;
    }
    n_ok++;
    if (!img.pixels || !img.width || !img.height ||
        (uint64_t)img.width * img.height > lg_image_max_pixels() ||
        info.format == LG_FILE_UNKNOWN) {
        fprintf(stderr, "fuzz_image: inconsistent image %ux%u\n", img.width, img.height);
        abort();
    }
    /* touch every pixel, so that a short buffer shows under ASan, and check the counts */
    uint64_t nonfinite = 0, negative = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++) {
        const float *p = img.pixels + i * 4;
        nonfinite += !isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || !isfinite(p[3]);
        negative += p[0] < 0 || p[1] < 0 || p[2] < 0 || p[3] < 0;
    }
    if (nonfinite > info.nonfinite || ((flags & LG_READ_RADIANCE) && negative)) {
        fprintf(stderr, "fuzz_image: counts disagree (nonfinite %llu vs %llu, negative %llu)\n",
                (unsigned long long)nonfinite, (unsigned long long)info.nonfinite,
                (unsigned long long)negative);
        abort();
    }
    lg_image_free(&img);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* Pieces of the three formats, for the driver's "insert a token" edit: signatures, EXR
 * attribute names with their types, Radiance header lines and scanline markers, PNG chunk
 * names and lengths. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("\x76\x2f\x31\x01"),
    LG_FUZZ_TOKEN("\x02\x00\x00\x00"),
    LG_FUZZ_TOKEN("\x02\x02\x00\x00"),
    LG_FUZZ_TOKEN("channels\0chlist\0"),
    LG_FUZZ_TOKEN("compression\0compression\0"),
    LG_FUZZ_TOKEN("dataWindow\0box2i\0"),
    LG_FUZZ_TOKEN("displayWindow\0box2i\0"),
    LG_FUZZ_TOKEN("lineOrder\0lineOrder\0"),
    LG_FUZZ_TOKEN("tiles\0tiledesc\0"),
    LG_FUZZ_TOKEN("R\0\x01\0\0\0"),
    LG_FUZZ_TOKEN("A\0\x02\0\0\0"),
    LG_FUZZ_TOKEN("#?RADIANCE\n"),
    LG_FUZZ_TOKEN("#?RGBE\n"),
    LG_FUZZ_TOKEN("FORMAT=32-bit_rle_rgbe\n"),
    LG_FUZZ_TOKEN("FORMAT=32-bit_rle_xyze\n"),
    LG_FUZZ_TOKEN("EXPOSURE=0\n"),
    LG_FUZZ_TOKEN("\n-Y 2 +X 2\n"),
    LG_FUZZ_TOKEN("+Y 65535"),
    LG_FUZZ_TOKEN("\x02\x02\x00\x08"),
    LG_FUZZ_TOKEN("\x01\x01\x01\xff"),
    LG_FUZZ_TOKEN("\x89PNG\r\n\x1a\n"),
    LG_FUZZ_TOKEN("\0\0\0\x0dIHDR"),
    LG_FUZZ_TOKEN("IDAT"),
    LG_FUZZ_TOKEN("PLTE"),
    LG_FUZZ_TOKEN("tRNS"),
    LG_FUZZ_TOKEN("gAMA"),
    LG_FUZZ_TOKEN("\0\0\0\0IEND\xae\x42\x60\x82"),
};

static void summary(FILE *out)
{
    fprintf(out, "%lu read", n_ok);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_image",
        .mutations = 200,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .head = 512, /* image headers hold the sizes and offsets */
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
