/*
 * Images in memory and the limits every reader checks: allocation, freeing and hashing of
 * lg_image; the pixel limit (LIGHTGRAPH_MAX_PIXELS, --max-pixels), the file-size limit and
 * the memory a decode may use; the error-message helper of the image files.
 *
 * The bottom of the image files (image_alloc.h): the codecs (exr.c, exr_cxx.cpp, hdr.c,
 * png.c) and compare.c call down to it, image.c (the format dispatch) calls the codecs and
 * it; nothing here calls up.
 */
#include <errno.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "image_alloc.h"

/* 0 until first use, then the limit in force (never 0 again) */
static _Atomic uint64_t max_pixels;

uint64_t lg_image_max_pixels(void)
{
    uint64_t n = atomic_load(&max_pixels);
    if (n)
        return n;
    n = LG_IMAGE_MAX_PIXELS_DEFAULT;
    const char *e = getenv("LIGHTGRAPH_MAX_PIXELS");
    if (e && *e) {
        char *end = NULL;
        errno = 0;
        unsigned long long v = strtoull(e, &end, 10);
        if (errno == 0 && end && *end == 0 && v > 0 && e[0] != '-')
            n = v;
        else
            fprintf(stderr,
                    "lightgraph: warning: LIGHTGRAPH_MAX_PIXELS='%s' is not a positive "
                    "integer; the limit stays %llu pixels\n",
                    e, (unsigned long long)n);
    }
    uint64_t zero = 0;
    atomic_compare_exchange_strong(&max_pixels, &zero, n);
    return atomic_load(&max_pixels);
}

uint64_t lg_image_hash(const lg_image *img, uint64_t h)
{
    if (!img || !img->pixels)
        return h;
    uint64_t head[2] = { img->width, img->height };
    for (int i = 0; i < 2; i++)
        h = (h ^ head[i]) * 0x100000001b3ull;
    const unsigned char *p = (const unsigned char *)img->pixels;
    size_t n = (size_t)img->width * img->height * 4 * sizeof(float);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        h = (h ^ w) * 0x100000001b3ull;
        h ^= h >> 29;
    }
    for (; i < n; i++)
        h = (h ^ p[i]) * 0x100000001b3ull;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    return h;
}

void lg_image_set_max_pixels(uint64_t n)
{
    atomic_store(&max_pixels, n ? n : LG_IMAGE_MAX_PIXELS_DEFAULT);
}

uint64_t lg_image_max_file_bytes(void)
{
    uint64_t px = lg_image_max_pixels();
    uint64_t b = px > UINT64_MAX / 32 ? UINT64_MAX : px * 32;
    return b < (64ull << 20) ? (64ull << 20) : b;
}

uint64_t lg_image_alloc_cap(void)
{
    uint64_t n = lg_image_max_pixels();
    return n > LG_IMAGE_MAX_PIXELS ? n : LG_IMAGE_MAX_PIXELS;
}

void lg_bytes_text(char *out, size_t n, uint64_t b)
{
    static const char *const unit[] = { "bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB" };
    if (b < 1024) {
        snprintf(out, n, "%llu bytes", (unsigned long long)b);
        return;
    }
    double v = (double)b;
    int u = 0;
    while (v >= 1024.0 && u < 6) {
        v /= 1024.0;
        u++;
    }
    snprintf(out, n, "%.1f %s", v, unit[u]);
}

/* What the machine can give a decode (or a plan, or a node's working memory): physical
 * memory, or less when an address-space limit (RLIMIT_AS, `ulimit -v`) is set, less what
 * the process maps already. */
uint64_t lg_memory_available(const char **what_out)
{
    uint64_t avail = UINT64_MAX;
    const char *unused, **what = what_out ? what_out : &unused;
    *what = "memory";
    long pages = sysconf(_SC_PHYS_PAGES), psize = sysconf(_SC_PAGESIZE);
    if (pages > 0 && psize > 0) {
        avail = (uint64_t)pages * (uint64_t)psize;
        *what = "physical memory";
    }
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
        uint64_t mapped = 0;
        FILE *f = fopen("/proc/self/statm", "re");
        if (f) {
            unsigned long long vm = 0;
            if (fscanf(f, "%llu", &vm) == 1 && psize > 0)
                mapped = vm * (uint64_t)psize;
            fclose(f);
        }
        uint64_t left = (uint64_t)rl.rlim_cur > mapped ? (uint64_t)rl.rlim_cur - mapped : 0;
        if (left < avail) {
            avail = left;
            *what = "address space that the process's limit (RLIMIT_AS, ulimit -v) leaves";
        }
    }
    return avail;
}

int lg_image_check_size(const char *path, uint64_t w, uint64_t h, uint64_t codec_per_pixel,
                        uint64_t codec_fixed, char *err, size_t errlen)
{
    if (w == 0 || h == 0)
        return lg_image_fail(err, errlen, LG_ERR_INVALID,
                             "cannot read '%s': it declares %llu x %llu pixels, an empty image",
                             path, (unsigned long long)w, (unsigned long long)h);
    uint64_t limit = lg_image_max_pixels(), px;
    if (__builtin_mul_overflow(w, h, &px) || px > limit)
        return lg_image_fail(err, errlen, LG_ERR_INVALID,
                             "cannot read '%s': it declares %llu x %llu pixels, over the limit of "
                             "%llu pixels (raise it with LIGHTGRAPH_MAX_PIXELS=N in the "
                             "environment or the option --max-pixels N)",
                             path, (unsigned long long)w, (unsigned long long)h,
                             (unsigned long long)limit);
    /* the rgba32f result, the codec's buffers */
    uint64_t per = 0, need = 0;
    const char *what;
    char a[32], b[32];
    if (__builtin_add_overflow(codec_per_pixel, (uint64_t)(4 * sizeof(float)), &per) ||
        __builtin_mul_overflow(px, per, &need) ||
        __builtin_add_overflow(need, codec_fixed, &need) || need > (uint64_t)SIZE_MAX / 2) {
        lg_bytes_text(b, sizeof b, (uint64_t)SIZE_MAX / 2);
        return lg_image_fail(err, errlen, LG_ERR_NOMEM,
                             "cannot read '%s': decoding its %llu x %llu pixels needs more than "
                             "%s, more than this machine can address",
                             path, (unsigned long long)w, (unsigned long long)h, b);
    }
    uint64_t avail = lg_memory_available(&what);
    if (need > avail) {
        lg_bytes_text(a, sizeof a, need);
        lg_bytes_text(b, sizeof b, avail);
        return lg_image_fail(err, errlen, LG_ERR_NOMEM,
                             "cannot read '%s': decoding its %llu x %llu pixels needs %s, more "
                             "than the %s of %s",
                             path, (unsigned long long)w, (unsigned long long)h, a, b, what);
    }
    return LG_OK;
}

int lg_image_fail(char *err, size_t errlen, int code, const char *fmt, ...)
{
    if (err && errlen) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, errlen, fmt, ap);
        va_end(ap);
    }
    return code;
}

int lg_image_alloc(lg_image *img, uint32_t width, uint32_t height)
{
    if (!img)
        return LG_ERR_INVALID;
    memset(img, 0, sizeof *img);
    if (width == 0 || height == 0 || (uint64_t)width * height > lg_image_alloc_cap())
        return LG_ERR_INVALID;
    img->pixels = calloc((size_t)width * height, 4 * sizeof(float));
    if (!img->pixels)
        return LG_ERR_NOMEM;
    img->width = width;
    img->height = height;
    return LG_OK;
}

void lg_image_free(lg_image *img)
{
    if (!img)
        return;
    free(img->pixels);
    memset(img, 0, sizeof *img);
}
