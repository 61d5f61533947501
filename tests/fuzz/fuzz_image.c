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
 * runs every file of the corpus folders given on the command line, then a fixed number of
 * deterministic mutations of each (bit flips, byte replacements with boundary values,
 * truncations, deleted and copied spans, splices with other files), from a fixed-seed PRNG.
 *
 *     fuzz_image [-n MUTATIONS_PER_FILE] CORPUS_DIR...
 */
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "lightgraph/image.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char tmp_dir[4096];
static unsigned long n_runs, n_ok;

static void cleanup(void)
{
    static const char *const names[] = {"in.exr", "in.hdr", "in.png"};
    for (int i = 0; i < 3; i++) {
        char p[4200];
        snprintf(p, sizeof p, "%s/%s", tmp_dir, names[i]);
        unlink(p);
    }
    rmdir(tmp_dir);
}

static void make_tmp_dir(void)
{
    if (tmp_dir[0])
        return;
    const char *base = getenv("TMPDIR");
    snprintf(tmp_dir, sizeof tmp_dir, "%s/lg-fuzz-image.XXXXXX", base && base[0] ? base : "/tmp");
    if (!mkdtemp(tmp_dir)) {
        perror("fuzz_image: mkdtemp");
        abort();
    }
    atexit(cleanup);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    make_tmp_dir();
    const char *ext;
    if (size >= 4 && !memcmp(data, "\x76\x2f\x31\x01", 4))
        ext = "exr";
    else if (size >= 2 && data[0] == '#' && data[1] == '?')
        ext = "hdr";
    else if (size >= 8 && !memcmp(data, "\x89PNG", 4))
        ext = "png";
    else
        ext = (const char *[]){"exr", "hdr", "png"}[size ? data[0] % 3 : 0];

    char path[4200];
    snprintf(path, sizeof path, "%s/in.%s", tmp_dir, ext);
    /* a new file each time (ext4 flushes files truncated and rewritten in place) */
    unlink(path);
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size)) {
        perror("fuzz_image: writing the input");
        abort();
    }
    fclose(f);

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
        (uint64_t)img.width * img.height > (1ull << 28) || info.format == LG_FILE_UNKNOWN) {
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

typedef struct input {
    char *name;
    uint8_t *data;
    size_t size;
} input;

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rnd(void)
{
    /* xorshift64*: deterministic across runs and machines */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545f4914f6cdd1dull;
}

static size_t rnd_below(size_t n)
{
    return n ? (size_t)(rnd() % n) : 0;
}

/* One to four edits of `in`, into a new buffer. Image headers hold sizes and offsets, so
 * besides bit flips a mutation often writes a boundary value over four bytes. */
static uint8_t *mutate(const input *in, const input *all, size_t n_all, size_t *out_size)
{
    size_t cap = in->size * 2 + 256;
    uint8_t *b = malloc(cap);
    if (!b)
        abort();
    size_t n = in->size;
    memcpy(b, in->data, n);
    /* headers are where parsers go wrong: half of the edits land in the first 512 bytes */
    int edits = 1;
    while (edits < 4 && rnd_below(2))
        edits++;
    for (int e = 0; e < edits; e++) {
        size_t span = (rnd_below(2) && n > 512) ? 512 : n;
        size_t at = rnd_below(span + 1);
        switch (rnd_below(7)) {
        case 0: /* flip a bit */
            if (n)
                b[rnd_below(span)] ^= (uint8_t)(1u << rnd_below(8));
            break;
        case 1: { /* a boundary value over 1, 2 or 4 bytes */
            static const uint32_t vals[] = {0, 1, 0x7f, 0x80, 0xff, 0x7fff, 0x8000, 0xffff,
                                            0x7fffffff, 0x80000000u, 0xffffffffu, 0x10000};
            uint32_t v = vals[rnd_below(sizeof vals / sizeof *vals)];
            size_t w = (size_t)1 << rnd_below(3);
            if (at + w <= n)
                for (size_t k = 0; k < w; k++)
                    b[at + k] = (uint8_t)(v >> (8 * k));
            break;
        }
        case 2: { /* delete a span */
            size_t len = rnd_below(n - (at < n ? at : n) + 1);
            if (len > 64 && rnd_below(4))
                len = rnd_below(64);
            if (at < n) {
                memmove(b + at, b + at + len, n - at - len);
                n -= len;
            }
            break;
        }
        case 3: { /* copy a span somewhere else */
            if (!n || at > n)
                break;
            size_t from = rnd_below(n), len = rnd_below(n - from + 1);
            if (len > 64)
                len = rnd_below(64);
            if (n + len > cap)
                break;
            uint8_t tmp[64];
            memcpy(tmp, b + from, len);
            memmove(b + at + len, b + at, n - at);
            memcpy(b + at, tmp, len);
            n += len;
            break;
        }
        case 4: /* truncate */
            n = rnd_below(n + 1);
            break;
        case 5: { /* splice: our head, another file's tail */
            const input *o = &all[rnd_below(n_all)];
            if (at > n)
                at = n;
            size_t from = rnd_below(o->size + 1), len = o->size - from;
            if (at + len > cap)
                len = cap - at;
            memcpy(b + at, o->data + from, len);
            n = at + len;
            break;
        }
        default: /* replace a byte */
            if (n)
                b[rnd_below(span)] = (uint8_t)rnd();
        }
    }
    *out_size = n;
    return b;
}

static int cmp_input(const void *a, const void *b)
{
    return strcmp(((const input *)a)->name, ((const input *)b)->name);
}

static int load_file(const char *path, input *in)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    in->data = malloc(len > 0 ? (size_t)len : 1);
    in->size = len > 0 ? fread(in->data, 1, (size_t)len, f) : 0;
    in->name = strdup(path);
    fclose(f);
    return 0;
}

int main(int argc, char **argv)
{
    long per_file = 200;
    input *in = NULL;
    size_t n_in = 0, cap = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-n") && i + 1 < argc) {
            per_file = atol(argv[++i]);
            continue;
        }
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "fuzz_image: %s: not found\n", argv[i]);
            return 2;
        }
        DIR *d = S_ISDIR(st.st_mode) ? opendir(argv[i]) : NULL;
        struct dirent *e;
        do {
            char path[4200];
            if (d) {
                e = readdir(d);
                if (!e)
                    break;
                if (e->d_name[0] == '.')
                    continue;
                snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
            } else {
                snprintf(path, sizeof path, "%s", argv[i]);
            }
            if (n_in == cap) {
                cap = cap ? 2 * cap : 16;
                in = realloc(in, cap * sizeof *in);
            }
            if (load_file(path, &in[n_in]) == 0)
                n_in++;
        } while (d);
        if (d)
            closedir(d);
    }
    if (!n_in) {
        fprintf(stderr, "usage: fuzz_image [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...\n");
        return 2;
    }
    qsort(in, n_in, sizeof *in, cmp_input); /* readdir order varies: keep runs identical */

    clock_t t0 = clock();
    for (size_t i = 0; i < n_in; i++) {
        LLVMFuzzerTestOneInput(in[i].data, in[i].size);
        for (long k = 0; k < per_file; k++) {
            size_t size;
            uint8_t *b = mutate(&in[i], in, n_in, &size);
            LLVMFuzzerTestOneInput(b, size);
            free(b);
        }
    }
    printf("fuzz_image: %lu inputs (%zu files, %ld mutations each) in %.2f s CPU; %lu read\n",
           n_runs, n_in, per_file, (double)(clock() - t0) / CLOCKS_PER_SEC, n_ok);
    for (size_t i = 0; i < n_in; i++) {
        free(in[i].name);
        free(in[i].data);
    }
    free(in);
    return 0;
}
#endif
