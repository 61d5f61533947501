/*
 * tests/fuzz/fuzz_image_file.h: an input written as an image file, for the targets whose
 * loaders read files (fuzz_image, fuzz_probe). Header-only: libFuzzer builds link no
 * fuzz_driver.c.
 *
 * lg_fuzz_image_file(target, data, size) writes the bytes to "in.EXT" in a private folder
 * made once under $TMPDIR (removed at exit) and returns its path (static storage). EXT
 * follows the bytes' magic (EXR, Radiance, PNG), else the first byte, so that every loader
 * sees arbitrary bytes too. Failures abort, as a fuzz target must.
 */
#ifndef LG_FUZZ_IMAGE_FILE_H
#define LG_FUZZ_IMAGE_FILE_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char lg_fuzz_image_dir[4096];

static void lg_fuzz_image_cleanup(void)
{
    static const char *const names[] = { "in.exr", "in.hdr", "in.png" };
    for (int i = 0; i < 3; i++) {
        char p[4200];
        snprintf(p, sizeof p, "%s/%s", lg_fuzz_image_dir, names[i]);
        unlink(p);
    }
    rmdir(lg_fuzz_image_dir);
}

static const char *lg_fuzz_image_file(const char *target, const uint8_t *data, size_t size)
{
    if (!lg_fuzz_image_dir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(lg_fuzz_image_dir, sizeof lg_fuzz_image_dir, "%s/lg-%s.XXXXXX",
                 base && base[0] ? base : "/tmp", target);
        if (!mkdtemp(lg_fuzz_image_dir)) {
            fprintf(stderr, "%s: mkdtemp %s: ", target, lg_fuzz_image_dir);
            perror(NULL);
            abort();
        }
        atexit(lg_fuzz_image_cleanup);
    }
    const char *ext;
    if (size >= 4 && !memcmp(data, "\x76\x2f\x31\x01", 4))
        ext = "exr";
    else if (size >= 2 && data[0] == '#' && data[1] == '?')
        ext = "hdr";
    else if (size >= 8 && !memcmp(data, "\x89PNG", 4))
        ext = "png";
    else
        ext = (const char *[]){ "exr", "hdr", "png" }[size ? data[0] % 3 : 0];
    static char path[4200];
    snprintf(path, sizeof path, "%s/in.%s", lg_fuzz_image_dir, ext);
    unlink(path); /* a new file each time (ext4 flushes files truncated and rewritten in place) */
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        fprintf(stderr, "%s: writing the input %s: ", target, path);
        perror(NULL);
        abort();
    }
    return path;
}

#endif
