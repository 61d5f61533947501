/*
 * Bad input and failing output: missing, empty, truncated, bit-flipped and absurd files in
 * every format give an error that names the file, never a crash (run it under ASan);
 * writes are atomic (a failed write leaves neither a partial file nor a temporary one and
 * keeps the previous file); all of it from several threads at once.
 */
#include <dirent.h>
#include <errno.h>
#include <malloc.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <zlib.h>

#include "codectest.h"
#include "lightgraph/image.h"

static char scratch[4096];

static unsigned char *load(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *d = malloc((size_t)len + 1);
    *n = fread(d, 1, (size_t)len, f);
    fclose(f);
    return d;
}

static void store(const char *path, const void *d, size_t n)
{
    /* a new file each time: ext4 flushes a file truncated and rewritten in place when it
     * is closed (auto_da_alloc), which costs milliseconds per damaged copy */
    unlink(path);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(d, 1, n, f) != n)
        fprintf(stderr, "cannot write %s\n", path);
    if (f)
        fclose(f);
}

static int count_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d)
        closedir(d);
    return n;
}

static void pattern(lg_image *img, uint32_t w, uint32_t h)
{
    lg_image_alloc(img, w, h);
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        img->pixels[i] = (float)((i * 2654435761u) % 1000) / 250.0f;
}

/* A read that must fail: an error code, a message naming the file, an empty image. */
static void expect_fail(const char *path, const char *what)
{
    lg_image img;
    char err[512] = "";
    int rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
    const char *base = strrchr(path, '/');
    CHECKF(rc < 0 && strstr(err, base ? base + 1 : path), "%s: rc %d, '%s'", what, rc, err);
    CHECKF(img.pixels == NULL && img.width == 0 && img.height == 0, "%s: image not empty", what);
    lg_image_free(&img);
}

/* ---- inputs ---------------------------------------------------------------------------------- */

typedef struct sample {
    const char *name;
    lg_image_write_opts opts;
} sample;

static const sample samples[] = {
    { "zip_half.exr", { .exr_compression = LG_EXR_ZIP } },
    { "piz_rgba.exr", { .exr_compression = LG_EXR_PIZ, .channels = 4 } },
    { "rle_float.exr", { .exr_compression = LG_EXR_RLE, .exr_pixel = LG_EXR_FLOAT } },
    { "pxr24.exr", { .exr_compression = LG_EXR_PXR24, .exr_pixel = LG_EXR_FLOAT } },
    { "b44_half.exr", { .exr_compression = LG_EXR_B44 } },
    { "b44_float.exr", { .exr_compression = LG_EXR_B44, .exr_pixel = LG_EXR_FLOAT } }, /* C++ */
    { "dwab.exr", { .exr_compression = LG_EXR_DWAB } },                                /* C++ */
    { "dwaa_float.exr", { .exr_compression = LG_EXR_DWAA, .exr_pixel = LG_EXR_FLOAT } },
    { "rle.hdr", { 0 } },
    { "flat.hdr", { 0 } }, /* 5 pixels wide: flat */
    { "rgb.png", { .channels = 3 } },
    { "rgba.png", { 0 } },
};

static void test_bad_inputs(void)
{
    char path[4300], err[512];
    lg_image img;

    /* missing file, directory, unknown extension, NULL arguments */
    snprintf(path, sizeof path, "%s/nope.exr", scratch);
    int rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
    CHECKF(rc == LG_ERR_NOTFOUND && strstr(err, "nope.exr") && strstr(err, "No such file"), "%s",
           err);
    snprintf(path, sizeof path, "%s/nope.png", scratch);
    CHECK(lg_image_read(path, 0, &img, NULL, err, sizeof err) == LG_ERR_NOTFOUND);
    snprintf(path, sizeof path, "%s/nope.hdr", scratch);
    CHECK(lg_image_read(path, 0, &img, NULL, err, sizeof err) == LG_ERR_NOTFOUND);
    snprintf(path, sizeof path, "%s/dir.exr", scratch);
    mkdir(path, 0755);
    expect_fail(path, "directory .exr");
    snprintf(path, sizeof path, "%s/dir.hdr", scratch);
    mkdir(path, 0755);
    expect_fail(path, "directory .hdr");
    snprintf(path, sizeof path, "%s/picture.jpg", scratch);
    store(path, "x", 1);
    rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
    CHECKF(rc == LG_ERR_UNSUPPORTED && strstr(err, "picture.jpg") && strstr(err, "extension"), "%s",
           err);
    CHECK(lg_image_read(path, 0x100, &img, NULL, err, sizeof err) == LG_ERR_INVALID);
    CHECK(lg_image_read(NULL, 0, &img, NULL, err, sizeof err) == LG_ERR_INVALID);
    CHECK(lg_image_read(path, 0, NULL, NULL, NULL, 0) == LG_ERR_INVALID);

    /* empty files and wrong magic */
    const char *empties[] = { "empty.exr", "empty.hdr", "empty.png" };
    for (int i = 0; i < 3; i++) {
        snprintf(path, sizeof path, "%s/%s", scratch, empties[i]);
        store(path, "", 0);
        expect_fail(path, empties[i]);
        rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
        CHECKF(strstr(err, "empty file"), "%s", err);
    }
    snprintf(path, sizeof path, "%s/png_named.exr", scratch);
    store(path, "\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
    expect_fail(path, "PNG named .exr");
    rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
    CHECKF(strstr(err, "not an OpenEXR file"), "%s", err);
    snprintf(path, sizeof path, "%s/exr_named.png", scratch);
    store(path, "v/1\x01\x02\0\0\0channels", 16);
    expect_fail(path, "EXR named .png");
    rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
    CHECKF(strstr(err, "not a PNG file"), "%s", err);

    /* samples: valid files of each kind, then truncated and bit-flipped copies */
    lg_image src, small;
    pattern(&src, 64, 48);
    pattern(&small, 5, 9);
    uint32_t seed = 2024;
    for (size_t s = 0; s < sizeof samples / sizeof *samples; s++) {
        snprintf(path, sizeof path, "%s/%s", scratch, samples[s].name);
        rc = lg_image_write(path, strstr(samples[s].name, "flat") ? &small : &src, &samples[s].opts,
                            err, sizeof err);
        CHECKF(rc == 0, "%s", err);
        size_t len;
        unsigned char *data = load(path, &len);
        if (rc || !data)
            continue;
        rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
        CHECKF(rc == 0, "%s: %s", samples[s].name, err);
        lg_image_free(&img);

        char bad[4400];
        const char *dot = strrchr(samples[s].name, '.');
        snprintf(bad, sizeof bad, "%s/bad_%.*s%s", scratch, (int)(dot - samples[s].name),
                 samples[s].name, dot);
        size_t cuts[] = { 1,           2,         3,        4,       7,       8,
                          20,          50,        100,      300,     len / 4, len / 2,
                          3 * len / 4, len - 100, len - 10, len - 2, len - 1 };
        for (size_t k = 0; k < sizeof cuts / sizeof *cuts; k++) {
            if (cuts[k] >= len || cuts[k] == 0)
                continue;
            store(bad, data, cuts[k]);
            char what[128];
            snprintf(what, sizeof what, "%s cut at %zu of %zu", samples[s].name, cuts[k], len);
            expect_fail(bad, what);
        }
        /* bit flips: either a clean error or an image; ASan/UBSan watch the rest */
        unsigned char *copy = malloc(len);
        for (int it = 0; it < 300; it++) {
            memcpy(copy, data, len);
            int flips = 1 + it % 4;
            for (int f = 0; f < flips; f++) {
                seed = seed * 1664525u + 1013904223u;
                /* headers are where parsers go wrong: favour the first 400 bytes */
                size_t at = (it % 2 ? (seed >> 8) % len : (seed >> 8) % (len < 400 ? len : 400));
                copy[at] ^= (unsigned char)(1u << (seed % 8));
            }
            store(bad, copy, len);
            memset(err, 0, sizeof err);
            rc = lg_image_read(bad, 0, &img, NULL, err, sizeof err);
            if (rc == 0)
                CHECK(img.pixels && img.width > 0 && img.height > 0);
            else
                CHECKF(err[0] && img.pixels == NULL, "%s flip %d: rc %d without message",
                       samples[s].name, it, rc);
            lg_image_free(&img);
        }
        free(copy);
        free(data);
    }

    /* absurd dimensions in otherwise valid headers */
    size_t len;
    snprintf(path, sizeof path, "%s/zip_half.exr", scratch);
    unsigned char *exr = load(path, &len);
    unsigned char *dwp = exr ? memmem(exr, len, "dataWindow\0box2i\0", 17) : NULL;
    CHECK(dwp != NULL);
    if (dwp) {
        int32_t boxes[3][4] = { { 0, 0, 2000000000, 2000000000 },
                                { 0, 0, 1 << 20, 1 << 20 },
                                { 10, 10, 5, 5 } };
        for (int b = 0; b < 3; b++) {
            memcpy(dwp + 17 + 4, boxes[b], 16); /* little-endian, as EXR is */
            snprintf(path, sizeof path, "%s/huge_%d.exr", scratch, b);
            store(path, exr, len);
            expect_fail(path, "absurd EXR data window");
        }
    }
    free(exr);
    snprintf(path, sizeof path, "%s/rgb.png", scratch);
    unsigned char *png = load(path, &len);
    if (png && len > 33 && !memcmp(png + 12, "IHDR", 4)) {
        const uint32_t dims[2][2] = { { 100000, 100000 }, { 0x7fffffff, 1 } };
        for (int b = 0; b < 2; b++) {
            for (int i = 0; i < 2; i++) {
                png[16 + 4 * i] = (unsigned char)(dims[b][i] >> 24);
                png[17 + 4 * i] = (unsigned char)(dims[b][i] >> 16);
                png[18 + 4 * i] = (unsigned char)(dims[b][i] >> 8);
                png[19 + 4 * i] = (unsigned char)dims[b][i];
            }
            uint32_t crc = (uint32_t)crc32(0, png + 12,
                                           17); /* a valid chunk: only the size is absurd */
            png[29] = (unsigned char)(crc >> 24);
            png[30] = (unsigned char)(crc >> 16);
            png[31] = (unsigned char)(crc >> 8);
            png[32] = (unsigned char)crc;
            snprintf(path, sizeof path, "%s/huge_%d.png", scratch, b);
            store(path, png, len);
            expect_fail(path, "absurd PNG size");
        }
    } else {
        CHECK(!"rgb.png has no IHDR where expected");
    }
    free(png);

    lg_image_free(&src);
    lg_image_free(&small);
}

/* ---- outputs --------------------------------------------------------------------------------- */

static void test_atomic_writes(void)
{
    char dir[4300], path[4400], err[512];
    lg_image img, got;
    pattern(&img, 256, 256);
    lg_image_write_opts dwab = { .exr_compression = LG_EXR_DWAB };
    lg_image_write_opts b44f = { .exr_compression = LG_EXR_B44, .exr_pixel = LG_EXR_FLOAT };
    struct {
        const char *name;
        const lg_image_write_opts *opts;
    } outs[] = { { "out.png", NULL },
                 { "out.hdr", NULL },
                 { "out.exr", NULL },
                 { "dwab.exr", &dwab },
                 { "b44f.exr", &b44f } };

    /* into a directory that does not exist: a clean error naming the path */
    snprintf(path, sizeof path, "%s/no/such/dir/out.png", scratch);
    int rc = lg_image_write(path, &img, NULL, err, sizeof err);
    CHECKF(rc == LG_ERR_NOTFOUND && strstr(err, path), "rc %d: %s", rc, err);

    /* bad requests */
    snprintf(path, sizeof path, "%s/x.exr", scratch);
    lg_image_write_opts bad1 = { .channels = 2 },
                        bad2 = { .exr_compression = (lg_exr_compression)42 };
    CHECK(lg_image_write(path, &img, &bad1, err, sizeof err) == LG_ERR_INVALID &&
          strstr(err, "channels"));
    CHECK(lg_image_write(path, &img, &bad2, err, sizeof err) == LG_ERR_INVALID);
    lg_image none = { 0 };
    CHECK(lg_image_write(path, &none, NULL, err, sizeof err) == LG_ERR_INVALID);
    snprintf(path, sizeof path, "%s/x.tiff", scratch);
    CHECK(lg_image_write(path, &img, NULL, err, sizeof err) == LG_ERR_UNSUPPORTED &&
          strstr(err, "x.tiff"));
    snprintf(path, sizeof path, "%s/", scratch);
    CHECK(lg_image_write(path, &img, NULL, err, sizeof err) != LG_OK);

    /* a fresh directory for the atomicity checks */
    snprintf(dir, sizeof dir, "%s/atomic", scratch);
    CHECK(mkdir(dir, 0755) == 0);

    /* the target is a directory: the rename fails, the temporary file goes */
    snprintf(path, sizeof path, "%s/isdir.png", dir);
    mkdir(path, 0755);
    rc = lg_image_write(path, &img, NULL, err, sizeof err);
    CHECKF(rc == LG_ERR_IO && strstr(err, "isdir.png"), "%s", err);
    CHECK(count_entries(dir) == 1);
    rmdir(path);

    /* success: replaces an existing file, with the mode a new file gets */
    mode_t old_mask = umask(022);
    for (size_t i = 0; i < sizeof outs / sizeof *outs; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, outs[i].name);
        store(path, "old content", 11);
        chmod(path, 0600);
        CHECKF(lg_image_write(path, &img, outs[i].opts, err, sizeof err) == 0, "%s", err);
        struct stat st;
        CHECK(stat(path, &st) == 0 && (st.st_mode & 0777) == 0644 && st.st_size > 11);
        CHECKF(lg_image_read(path, 0, &got, NULL, err, sizeof err) == 0, "%s", err);
        lg_image_free(&got);
    }
    umask(old_mask);
    CHECK(count_entries(dir) == (int)(sizeof outs / sizeof *outs));

    /* a write that fails half way (file size limit, like a full disk): the old file stays,
     * no temporary file is left */
    for (size_t i = 0; i < sizeof outs / sizeof *outs; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, outs[i].name);
        store(path, "old content", 11);
    }
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit old_lim, lim;
    getrlimit(RLIMIT_FSIZE, &old_lim);
    lim = old_lim;
    lim.rlim_cur = 2000;
    CHECK(setrlimit(RLIMIT_FSIZE, &lim) == 0);
    int failed[8] = { 0 };
    char errs[8][512];
    for (size_t i = 0; i < sizeof outs / sizeof *outs; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, outs[i].name);
        failed[i] = lg_image_write(path, &img, outs[i].opts, errs[i], sizeof errs[i]);
    }
    setrlimit(RLIMIT_FSIZE, &old_lim);
    for (size_t i = 0; i < sizeof outs / sizeof *outs; i++) {
        CHECKF(failed[i] == LG_ERR_IO && strstr(errs[i], outs[i].name), "%s: rc %d: %s",
               outs[i].name, failed[i], errs[i]);
        snprintf(path, sizeof path, "%s/%s", dir, outs[i].name);
        size_t n;
        unsigned char *d = load(path, &n);
        CHECKF(d && n == 11 && !memcmp(d, "old content", 11), "%s was changed", outs[i].name);
        free(d);
    }
    CHECKF(count_entries(dir) == (int)(sizeof outs / sizeof *outs),
           "temporary files left: %d entries", count_entries(dir));
    lg_image_free(&img);
}

/* ---- threads --------------------------------------------------------------------------------- */

static void *worker(void *arg)
{
    intptr_t id = (intptr_t)arg;
    const char *names[] = { "t.exr", "t.hdr", "t.png", "t_dwab.exr", "t_b44f.exr" };
    lg_image_write_opts opts[] = { { 0 },
                                   { 0 },
                                   { 0 },
                                   { .exr_compression = LG_EXR_DWAB },
                                   { .exr_compression = LG_EXR_B44, .exr_pixel = LG_EXR_FLOAT } };
    lg_image img, got;
    pattern(&img, 40 + (uint32_t)id, 30);
    intptr_t bad = 0;
    for (int it = 0; it < 3; it++) { /* each write fsyncs: keep the count small */
        for (int k = 0; k < 5; k++) {
            char path[4400], err[512];
            snprintf(path, sizeof path, "%s/th%d_%s", scratch, (int)id, names[k]);
            if (lg_image_write(path, &img, &opts[k], err, sizeof err) ||
                lg_image_read(path, 0, &got, NULL, err, sizeof err)) {
                fprintf(stderr, "thread %d: %s\n", (int)id, err);
                bad++;
                continue;
            }
            bad += got.width != img.width || got.height != img.height;
            lg_image_free(&got);
        }
    }
    lg_image_free(&img);
    return (void *)bad;
}

static void test_threads(void)
{
    pthread_t t[4];
    for (intptr_t i = 0; i < 4; i++)
        pthread_create(&t[i], NULL, worker, (void *)i);
    for (int i = 0; i < 4; i++) {
        void *r;
        pthread_join(t[i], &r);
        CHECKF(r == NULL, "thread %d: %ld failures", i, (long)(intptr_t)r);
    }
}

int main(void)
{
    /* meson sets MALLOC_PERTURB_; damaged attribute sizes make OpenEXR's C++ library
     * allocate up to 2 GB before it notices the file is short, and perturbation would
     * fill every such page (seconds per file) */
    mallopt(M_PERTURB, 0);
    snprintf(scratch, sizeof scratch, "%s", make_scratch("codecs-safety"));

    /* the small API */
    lg_image img;
    CHECK(lg_image_alloc(&img, 0, 5) == LG_ERR_INVALID && img.pixels == NULL);
    CHECK(lg_image_alloc(&img, 1u << 15, (1u << 13) + 1) == LG_ERR_INVALID);
    CHECK(lg_image_alloc(NULL, 1, 1) == LG_ERR_INVALID);
    CHECK(lg_image_alloc(&img, 3, 2) == LG_OK && img.pixels && img.pixels[23] == 0.0f);
    lg_image_free(&img);
    lg_image_free(&img);
    lg_image_free(NULL);
    CHECK(lg_image_format_from_path("a/b.EXR") == LG_FILE_EXR);
    CHECK(lg_image_format_from_path("x.Hdr") == LG_FILE_HDR);
    CHECK(lg_image_format_from_path("x.pic") == LG_FILE_HDR);
    CHECK(lg_image_format_from_path("x.png") == LG_FILE_PNG);
    CHECK(lg_image_format_from_path("x.exr.gz") == LG_FILE_UNKNOWN);
    CHECK(lg_image_format_from_path("dir.png/x") == LG_FILE_UNKNOWN);
    CHECK(lg_image_format_from_path(".png") == LG_FILE_UNKNOWN);
    CHECK(lg_image_format_from_path("exr") == LG_FILE_UNKNOWN);
    CHECK(lg_image_format_from_path(NULL) == LG_FILE_UNKNOWN);

    test_bad_inputs();
    test_atomic_writes();
    test_threads();
    return check_report_scratch("io_safety", scratch);
}
