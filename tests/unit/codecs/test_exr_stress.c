/*
 * EXR round trips under load: tall narrow images (32x864 among them: one 16-scanline ZIP
 * chunk is then only 8 KiB) of random content, through lg_image_write and lg_image_read,
 * in several threads at once as a host with worker threads writes its outputs, over every
 * lossless compression, half and float. Each read must equal the source bit for bit (half:
 * the source rounded to half). A wrong chunk (a race in the chunk encoder, a reused
 * buffer, a wrong stride for narrow images) shows as the first differing row and its
 * 16-row block.
 *
 * Usage: test_exr_stress [ROUNDS [THREADS]] (defaults: 48 rounds in each of 4 threads,
 * about 3 s, most of it fsync); the seed is fixed, LG_STRESS_SEED=N changes it.
 *
 * What it caught: OpenEXR 3.1.5 stores a zlib stream exactly as long as the packed chunk
 * (ZIP, ZIPS, PXR24), which readers take as raw pixels (sdk/src/exr.c,
 * exr_compress_checked). Before the fix about 1 round trip in 9 differed here (282 of
 * 2400), so one run of 192 fails all but certainly; with the fixed seed, always.
 */
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codectest.h"
#include "lightgraph/image.h"

static char scratch[4096];
static atomic_int n_trips, n_bad;
/* check.h's failure count is a plain int: its checks run under this lock */
static pthread_mutex_t check_lock = PTHREAD_MUTEX_INITIALIZER;
#define TCHECKF(cond, ...)                                                                         \
    do {                                                                                           \
        pthread_mutex_lock(&check_lock);                                                           \
        CHECKF(cond, __VA_ARGS__);                                                                 \
        pthread_mutex_unlock(&check_lock);                                                         \
    } while (0)

typedef struct mode {
    lg_exr_compression comp;
    lg_exr_pixel pixel;
} mode;

/* Lossless for the pixel type: PXR24 rounds float to 24 bits, DWAA/DWAB are lossy. */
static const mode modes[] = {
    { LG_EXR_ZIP, LG_EXR_FLOAT },  { LG_EXR_ZIP, LG_EXR_HALF },   { LG_EXR_NONE, LG_EXR_FLOAT },
    { LG_EXR_RLE, LG_EXR_FLOAT },  { LG_EXR_ZIPS, LG_EXR_FLOAT }, { LG_EXR_PIZ, LG_EXR_FLOAT },
    { LG_EXR_PIZ, LG_EXR_HALF },   { LG_EXR_PXR24, LG_EXR_HALF }, { LG_EXR_B44, LG_EXR_FLOAT },
    { LG_EXR_B44A, LG_EXR_FLOAT }, { LG_EXR_RLE, LG_EXR_HALF },   { LG_EXR_ZIPS, LG_EXR_HALF },
    { LG_EXR_ZIP, LG_EXR_FLOAT },  { LG_EXR_NONE, LG_EXR_HALF },
};
static const char *const comp_names[] = { "zip",   "none", "rle",  "zips", "piz",
                                          "pxr24", "b44",  "b44a", "dwaa", "dwab" };
static const uint32_t widths[] = { 32, 32, 32, 1, 2, 3, 7, 16, 31, 33, 64 };
static const uint32_t heights[] = { 864, 864, 17, 31, 33, 100, 255, 256, 257, 1000, 1 };

static uint64_t next(uint64_t *s)
{
    /* splitmix64 */
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* A random finite float: any sign, mantissa and an exponent away from the extremes, with
 * runs of repeated values and smooth stretches so that every compressor has work. */
static float random_value(uint64_t *s, float prev)
{
    uint64_t r = next(s);
    switch (r & 3) {
    case 0: return prev;
    case 1: return prev + 0.001f;
    default: {
        uint32_t bits = (uint32_t)(r >> 32);
        uint32_t exp = 100u + (uint32_t)((r >> 8) % 50u); /* 2^-27 .. 2^22 */
        bits = (bits & 0x807fffffu) | (exp << 23);
        float f;
        memcpy(&f, &bits, sizeof f);
        return f;
    }
    }
}

typedef struct worker {
    int id, rounds;
    uint64_t seed;
} worker;

static void *run(void *arg)
{
    worker *wk = arg;
    uint64_t s = wk->seed;
    char path[4200], err[1024];
    for (int i = 0; i < wk->rounds; i++) {
        const mode *m = &modes[next(&s) % (sizeof modes / sizeof *modes)];
        uint32_t w = widths[next(&s) % (sizeof widths / sizeof *widths)];
        uint32_t h = heights[next(&s) % (sizeof heights / sizeof *heights)];
        lg_image src, back;
        memset(&back, 0, sizeof back);
        if (lg_image_alloc(&src, w, h) != LG_OK) {
            TCHECKF(0, "out of memory for %ux%u", w, h);
            return NULL;
        }
        float prev = 0.5f;
        if (next(&s) & 1) {
            for (size_t k = 0; k < (size_t)w * h * 4; k++)
                src.pixels[k] = prev = random_value(&s, prev);
        } else {
            /* a rendered image's noise: a smooth ramp whose 18 to 24 low mantissa bits are
             * random, which compresses to about its own size (the reported 32x864 ZIP
             * float images were like that) */
            int bits = 18 + (int)(next(&s) % 7);
            for (size_t k = 0; k < (size_t)w * h * 4; k++) {
                float base = 0.25f + 0.5f * (float)((k / 4) % w) / (float)w;
                uint32_t b;
                memcpy(&b, &base, sizeof b);
                b ^= (uint32_t)next(&s) & ((1u << bits) - 1u);
                memcpy(&src.pixels[k], &b, sizeof b);
            }
        }
        snprintf(path, sizeof path, "%s/t%d-%d.exr", scratch, wk->id, i);
        lg_image_write_opts wo;
        memset(&wo, 0, sizeof wo);
        wo.exr_compression = m->comp;
        wo.exr_pixel = m->pixel;
        int rc = lg_image_write(path, &src, &wo, err, sizeof err);
        TCHECKF(rc == LG_OK, "write %ux%u %s %s: %s", w, h, comp_names[m->comp],
                m->pixel == LG_EXR_HALF ? "half" : "float", err);
        lg_image_read_info info;
        if (rc == LG_OK) {
            rc = lg_image_read(path, 0, &back, &info, err, sizeof err);
            TCHECKF(rc == LG_OK, "read %s: %s", path, err);
        }
        if (rc == LG_OK) {
            TCHECKF(back.width == w && back.height == h, "%s: %ux%u read as %ux%u", path, w, h,
                    back.width, back.height);
            if (m->pixel == LG_EXR_HALF)
                for (size_t k = 0; k < (size_t)w * h * 4; k++)
                    src.pixels[k] = lg_float_from_half(lg_half_from_float(src.pixels[k]));
            long first = -1, nbad = 0;
            for (size_t k = 0; back.width == w && back.height == h && k < (size_t)w * h * 4; k++)
                if (memcmp(&src.pixels[k], &back.pixels[k], sizeof(float)) != 0) {
                    if (first < 0)
                        first = (long)k;
                    nbad++;
                }
            atomic_fetch_add(&n_trips, 1);
            if (first >= 0) {
                atomic_fetch_add(&n_bad, 1);
                /* what was expected, beside the file, to read it with other tools */
                char raw[4300];
                snprintf(raw, sizeof raw, "%s.expected.f32", path);
                FILE *f = fopen(raw, "wb");
                if (f) {
                    fwrite(src.pixels, sizeof(float), (size_t)w * h * 4, f);
                    fclose(f);
                }
                long row = first / 4 / (long)w;
                TCHECKF(0,
                        "%s (%ux%u, %s %s, thread %d round %d): %ld values differ, the first "
                        "at row %ld (16-row block %ld, rows %ld-%ld): %.9g read, %.9g written",
                        path, w, h, comp_names[m->comp], m->pixel == LG_EXR_HALF ? "half" : "float",
                        wk->id, i, nbad, row, row / 16, row / 16 * 16, row / 16 * 16 + 15,
                        (double)back.pixels[first], (double)src.pixels[first]);
            } else {
                remove(path);
            }
        }
        lg_image_free(&back);
        lg_image_free(&src);
    }
    return NULL;
}

int main(int argc, char **argv)
{
    int rounds = argc > 1 ? atoi(argv[1]) : 48, threads = argc > 2 ? atoi(argv[2]) : 4;
    if (rounds <= 0 || threads <= 0 || threads > 64) {
        fprintf(stderr, "usage: test_exr_stress [ROUNDS [THREADS (1-64)]]\n");
        return 2;
    }
    const char *seed_env = getenv("LG_STRESS_SEED");
    uint64_t seed = seed_env ? strtoull(seed_env, NULL, 0) : 20261129u;
    snprintf(scratch, sizeof scratch, "%s", make_scratch("exr_stress"));
    worker wk[64];
    pthread_t th[64];
    for (int t = 0; t < threads; t++) {
        wk[t] = (worker){ t, rounds, seed * 1000003u + (uint64_t)t };
        if (pthread_create(&th[t], NULL, run, &wk[t]) != 0) {
            fprintf(stderr, "FAIL: cannot start thread %d\n", t);
            return 1;
        }
    }
    for (int t = 0; t < threads; t++)
        pthread_join(th[t], NULL);
    printf("%d round trips, %d differed (seed %llu)\n", atomic_load(&n_trips), atomic_load(&n_bad),
           (unsigned long long)seed);
    return check_report_scratch("codecs_exr_stress", scratch);
}
