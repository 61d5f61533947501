/*
 * The bounds of image reads (lightgraph/image.h): the declared size is checked against the
 * pixel limit and against the memory the decode needs before anything is allocated, the file
 * against the image file-size limit, and only regular files are read.
 *
 *   - a 260 KB PNG declaring 16384 x 16384 (a real zlib stream of zeros: the decompression
 *     bomb of issue 8, which took 5 GB), an EXR with a 16384 x 16384 data window (scanline
 *     and tiled), an HDR whose resolution line says 16384 x 16384: each refused within a
 *     second with a message naming the file, the declared size, the limit and how to raise
 *     it, in a child whose address space is limited (RLIMIT_AS) and whose peak RSS is
 *     measured;
 *   - the limit raised past them: the memory check refuses (naming RLIMIT_AS, or physical
 *     memory for a 10^6 x 10^6 PNG), still before allocating;
 *   - PNG ancillary bombs (a zTXt and an iCCP that inflate to 64 MiB, an IDAT that inflates
 *     far past the image) read in bounded memory;
 *   - a limit of 100 pixels: 20 x 20 PNG, EXR and HDR refused, accepted at 400; the same
 *     through LIGHTGRAPH_MAX_PIXELS in a fresh process (this program, `test_limits read F`);
 *   - a FIFO, /dev/zero behind an image name and a sparse file over the file-size limit:
 *     refused at once.
 */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <zlib.h>

#include "codectest.h"
#include "lightgraph/image.h"

static char scratch[4096];

static const char *at(const char *name)
{
    static char buf[8][4200];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/%s", scratch, name);
    return buf[k];
}

/* ---- PNG files made by hand ------------------------------------------------------------------ */

static void put32(FILE *f, uint32_t v)
{
    unsigned char b[4] = { (unsigned char)(v >> 24), (unsigned char)(v >> 16),
                           (unsigned char)(v >> 8), (unsigned char)v };
    fwrite(b, 1, 4, f);
}

static void chunk(FILE *f, const char *type, const unsigned char *data, size_t n)
{
    put32(f, (uint32_t)n);
    fwrite(type, 1, 4, f);
    if (n)
        fwrite(data, 1, n, f);
    uLong crc = crc32(0, (const Bytef *)type, 4);
    if (n)
        crc = crc32(crc, data, (uInt)n);
    put32(f, (uint32_t)crc);
}

/* Raw deflate of n zero bytes ending in a full flush: byte-aligned, with no reference to
 * what came before, so copies of it can follow each other. */
static unsigned char *deflate_segment(size_t n, size_t *len)
{
    unsigned char *in = calloc(n ? n : 1, 1);
    size_t cap = n / 500 + 1024;
    unsigned char *out = malloc(cap);
    z_stream z;
    memset(&z, 0, sizeof z);
    deflateInit2(&z, 9, Z_DEFLATED, -15, 9, Z_DEFAULT_STRATEGY);
    z.next_in = in;
    z.avail_in = (uInt)n;
    z.next_out = out;
    z.avail_out = (uInt)cap;
    deflate(&z, Z_FULL_FLUSH);
    *len = cap - z.avail_out;
    deflateEnd(&z);
    free(in);
    return out;
}

/* A zlib stream of `total` zero bytes at deflate's best ratio (about 1030:1), made from
 * copies of one compressed MiB instead of compressing it all (seconds at level 9). */
static unsigned char *deflate_zeros(uint64_t total, size_t *out_len)
{
    const size_t seg = 1u << 20;
    size_t la, lb;
    unsigned char *a = deflate_segment(seg, &la);
    unsigned char *b = deflate_segment((size_t)(total % seg), &lb);
    uint64_t copies = total / seg;
    size_t len = 2 + (size_t)copies * la + lb + 2 + 4;
    unsigned char *out = malloc(len), *o = out;
    *o++ = 0x78;
    *o++ = 0xda;
    for (uint64_t i = 0; i < copies; i++, o += la)
        memcpy(o, a, la);
    memcpy(o, b, lb);
    o += lb;
    *o++ = 0x03; /* the last block: fixed Huffman, empty */
    *o++ = 0x00;
    static unsigned char zeros[1 << 16];
    uLong ad = adler32(0, NULL, 0);
    for (uint64_t left = total; left;) {
        size_t n = left < sizeof zeros ? (size_t)left : sizeof zeros;
        ad = adler32(ad, zeros, (uInt)n);
        left -= n;
    }
    *o++ = (unsigned char)(ad >> 24);
    *o++ = (unsigned char)(ad >> 16);
    *o++ = (unsigned char)(ad >> 8);
    *o++ = (unsigned char)ad;
    free(a);
    free(b);
    *out_len = len;
    return out;
}

/* An 8-bit grey PNG declaring w x h whose IDAT inflates to idat_raw zero bytes; with
 * `ancillary`, a chunk of that type (zTXt or iCCP: a name, NUL, method 0, then a zlib stream
 * of anc_raw zeros) before it. Returns the file size. */
static long write_png(const char *path, uint32_t w, uint32_t h, uint64_t idat_raw,
                      const char *ancillary, uint64_t anc_raw)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    fwrite("\x89PNG\r\n\x1a\n", 1, 8, f);
    unsigned char ihdr[13] = { (unsigned char)(w >> 24),
                               (unsigned char)(w >> 16),
                               (unsigned char)(w >> 8),
                               (unsigned char)w,
                               (unsigned char)(h >> 24),
                               (unsigned char)(h >> 16),
                               (unsigned char)(h >> 8),
                               (unsigned char)h,
                               8,
                               0,
                               0,
                               0,
                               0 };
    chunk(f, "IHDR", ihdr, 13);
    if (ancillary) {
        size_t zl;
        unsigned char *z = deflate_zeros(anc_raw, &zl);
        unsigned char *d = malloc(zl + 8);
        memcpy(d, "bomb\0\0", 6);
        memcpy(d + 6, z, zl);
        chunk(f, ancillary, d, zl + 6);
        free(d);
        free(z);
    }
    size_t zl;
    unsigned char *z = deflate_zeros(idat_raw, &zl);
    chunk(f, "IDAT", z, zl);
    free(z);
    chunk(f, "IEND", NULL, 0);
    long n = ftell(f);
    fclose(f);
    return n;
}

/* ---- a read in a child, with its address space limited --------------------------------------- */

typedef struct child_result {
    int ran; /* the child reported */
    int rc;
    double ms;      /* the read's wall time */
    long maxrss_kb; /* the child's peak resident set */
    char err[600];
} child_result;

static uint64_t vm_size(void)
{
    unsigned long long pages = 0;
    FILE *f = fopen("/proc/self/statm", "re");
    if (f) {
        if (fscanf(f, "%llu", &pages) != 1)
            pages = 0;
        fclose(f);
    }
    return pages * (uint64_t)sysconf(_SC_PAGESIZE);
}

/* Reads path in a child under RLIMIT_AS = what it maps + as_extra bytes (0: no limit), with
 * the pixel limit max_pixels (0: default) and a 20 s alarm against hangs. */
static child_result read_in_child(const char *path, uint64_t as_extra, uint64_t max_pixels)
{
    child_result r;
    memset(&r, 0, sizeof r);
    int fds[2];
    if (pipe(fds) != 0)
        return r;
    pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        alarm(20);
        if (as_extra) {
            struct rlimit rl = { vm_size() + as_extra, RLIM_INFINITY };
            setrlimit(RLIMIT_AS, &rl);
        }
        lg_image_set_max_pixels(max_pixels);
        child_result c;
        memset(&c, 0, sizeof c);
        lg_image img;
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        c.rc = lg_image_read(path, 0, &img, NULL, c.err, sizeof c.err);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        c.ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) / 1e6;
        c.ran = 1;
        lg_image_free(&img);
        if (write(fds[1], &c, sizeof c) != (ssize_t)sizeof c)
            _exit(3);
        _exit(0);
    }
    close(fds[1]);
    ssize_t n = read(fds[0], &r, sizeof r);
    if (n != (ssize_t)sizeof r)
        memset(&r, 0, sizeof r);
    close(fds[0]);
    int status = 0;
    struct rusage ru;
    memset(&ru, 0, sizeof ru);
    wait4(pid, &status, 0, &ru);
    r.maxrss_kb = ru.ru_maxrss;
    if (!WIFEXITED(status))
        snprintf(r.err, sizeof r.err, "child died (signal %d)", WTERMSIG(status));
    return r;
}

/* Peak RSS a bounded read may reach: the process as forked plus the small buffers. */
#define RSS_BOUND_KB (96 * 1024)

static void expect_refused(const char *what, const char *path, uint64_t max_pixels,
                           const char *const *want)
{
    child_result r = read_in_child(path, 256u << 20, max_pixels);
    const char *base = strrchr(path, '/') + 1;
    CHECKF(r.ran && r.rc < 0 && strstr(r.err, base), "%s: rc %d, '%s'", what, r.rc, r.err);
    for (int i = 0; want[i]; i++)
        CHECKF(strstr(r.err, want[i]), "%s: '%s' does not say '%s'", what, r.err, want[i]);
    CHECKF(r.ms < 20000, "%s: %.0f ms to refuse (a hang guard; memory is the bound tested)", what,
           r.ms);
    CHECKF(r.maxrss_kb < RSS_BOUND_KB, "%s: peak RSS %ld KiB", what, r.maxrss_kb);
    printf("%-34s refused in %6.2f ms, peak RSS %5ld KiB: %s\n", what, r.ms, r.maxrss_kb,
           r.err + strlen("cannot read '") + strlen(path) + 3);
}

/* ---- the cases ------------------------------------------------------------------------------- */

static const char *const limit_words[] = { "16384 x 16384", "over the limit of 134217728 pixels",
                                           "LIGHTGRAPH_MAX_PIXELS", "--max-pixels", NULL };

static void test_png_bomb(void)
{
    /* the file: 16384 x 16384 grey, every row present (zeros), about 260 KB */
    long n = write_png(at("bomb16k.png"), 16384, 16384, (uint64_t)16384 * 16385, NULL, 0);
    CHECKF(n > 200000 && n < 300000, "bomb16k.png is %ld bytes", n);
    expect_refused("PNG 16384x16384 (260 KB bomb)", at("bomb16k.png"), 0, limit_words);

    /* limit raised past it: the memory the decode needs (about 5 GiB) is refused, naming the
     * address-space limit of the child */
    const char *as_words[] = { "16384 x 16384", "needs 5.0 GiB", "RLIMIT_AS", NULL };
    expect_refused("PNG 16384x16384, limit 2^40", at("bomb16k.png"), 1ull << 40, as_words);

    /* 10^6 x 10^6 with the limit raised: 16 TB is more than any machine's memory */
    write_png(at("huge1m.png"), 1000000, 1000000, 100, NULL, 0);
    child_result r = read_in_child(at("huge1m.png"), 0, 1ull << 50);
    CHECKF(r.ran && r.rc == LG_ERR_NOMEM && strstr(r.err, "1000000 x 1000000") &&
               strstr(r.err, "physical memory"),
           "10^6 x 10^6: rc %d: %s", r.rc, r.err);

    /* ancillary and IDAT bombs: a zTXt and an iCCP inflating to 64 MiB are skipped, an IDAT
     * that inflates far past its 64 x 64 image stops at the image; bounded either way */
    const struct {
        const char *name, *type;
        uint64_t idat, anc;
    } anc[] = {
        { "ztxt_bomb.png", "zTXt", 64 * 65, 64u << 20 },
        { "iccp_bomb.png", "iCCP", 64 * 65, 64u << 20 },
        { "idat_bomb.png", NULL, 16u << 20, 0 },
    };
    for (size_t i = 0; i < sizeof anc / sizeof *anc; i++) {
        write_png(at(anc[i].name), 64, 64, anc[i].idat, anc[i].type, anc[i].anc);
        r = read_in_child(at(anc[i].name), 256u << 20, 0);
        CHECKF(r.ran, "%s: %s", anc[i].name, r.err);
        if (anc[i].type)
            CHECKF(r.rc == 0, "%s: %s", anc[i].name, r.err);
        CHECKF(r.ms < 20000 && r.maxrss_kb < RSS_BOUND_KB, "%s: %.0f ms, %ld KiB", anc[i].name,
               r.ms, r.maxrss_kb);
        printf("%-34s rc %d in %6.2f ms, peak RSS %5ld KiB %s\n", anc[i].name, r.rc, r.ms,
               r.maxrss_kb, r.err);
    }
}

/* Sets the data window of an EXR file (patched in place: box2i, little-endian). */
static int patch_exr_window(const char *src, const char *dst, int32_t x1, int32_t y1)
{
    FILE *f = fopen(src, "rb");
    if (!f)
        return -1;
    unsigned char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    unsigned char *dw = memmem(buf, n, "dataWindow\0box2i\0", 17);
    if (!dw)
        return -1;
    int32_t box[4] = { 0, 0, x1, y1 };
    memcpy(dw + 17 + 4, box, 16);
    f = fopen(dst, "wb");
    fwrite(buf, 1, n, f);
    fclose(f);
    return 0;
}

static void test_exr_window(void)
{
    lg_image img;
    lg_image_alloc(&img, 8, 8);
    char err[512];
    CHECKF(lg_image_write(at("small.exr"), &img, NULL, err, sizeof err) == 0, "%s", err);
    lg_image_free(&img);
    CHECK(patch_exr_window(at("small.exr"), at("window16k.exr"), 16383, 16383) == 0);
    expect_refused("EXR window 16384x16384 (scanline)", at("window16k.exr"), 0, limit_words);

    char tiled[4300];
    CHECK(patch_exr_window(asset_path("../tests/fuzz/corpus_image/tiled_mipmap_float.exr", tiled,
                                      sizeof tiled),
                           at("tiled16k.exr"), 16383, 16383) == 0);
    expect_refused("EXR window 16384x16384 (tiled)", at("tiled16k.exr"), 0, limit_words);
}

static void test_hdr_resolution(void)
{
    FILE *f = fopen(at("res16k.hdr"), "wb");
    fputs("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 16384 +X 16384\n", f);
    static unsigned char px[16384 * 4];
    memset(px, 0x80, sizeof px);
    fwrite(px, 1, sizeof px, f); /* enough bytes for the old 4-bytes-per-scanline check */
    fclose(f);
    expect_refused("HDR -Y 16384 +X 16384", at("res16k.hdr"), 0, limit_words);
}

static void test_raise_limit(void)
{
    lg_image img;
    lg_image_alloc(&img, 20, 20);
    for (size_t i = 0; i < 20 * 20 * 4; i++)
        img.pixels[i] = 0.25f;
    const char *names[] = { "p20.png", "p20.exr", "p20.hdr" };
    char err[512];
    for (int i = 0; i < 3; i++)
        CHECKF(lg_image_write(at(names[i]), &img, NULL, err, sizeof err) == 0, "%s", err);
    lg_image_free(&img);

    for (int i = 0; i < 3; i++) {
        lg_image_set_max_pixels(100);
        int rc = lg_image_read(at(names[i]), 0, &img, NULL, err, sizeof err);
        CHECKF(rc == LG_ERR_INVALID && strstr(err, names[i]) && strstr(err, "20 x 20") &&
                   strstr(err, "limit of 100 pixels"),
               "%s at 100: rc %d, %s", names[i], rc, err);
        CHECK(img.pixels == NULL);
        lg_image_set_max_pixels(400);
        rc = lg_image_read(at(names[i]), 0, &img, NULL, err, sizeof err);
        CHECKF(rc == 0 && img.width == 20 && img.height == 20, "%s at 400: rc %d, %s", names[i], rc,
               err);
        lg_image_free(&img);
    }
    lg_image_set_max_pixels(0);
    CHECK(lg_image_max_pixels() == LG_IMAGE_MAX_PIXELS_DEFAULT);

    /* the environment, read at first use: a fresh process */
    for (int i = 0; i < 3; i++) {
        for (int raised = 0; raised < 2; raised++) {
            char cmd[9000], out[1024] = "";
            snprintf(cmd, sizeof cmd, "LIGHTGRAPH_MAX_PIXELS=%d /proc/%d/exe read '%s' 2>&1",
                     raised ? 400 : 100, (int)getpid(), at(names[i]));
            FILE *p = popen(cmd, "r");
            size_t n = p ? fread(out, 1, sizeof out - 1, p) : 0;
            out[n] = 0;
            int st = p ? pclose(p) : -1;
            if (raised)
                CHECKF(st == 0 && strstr(out, "20x20"), "%s, env 400: %s", names[i], out);
            else
                CHECKF(st != 0 && strstr(out, "over the limit of 100 pixels"), "%s, env 100: %s",
                       names[i], out);
        }
    }
}

static void test_special_files(void)
{
    char err[512];
    lg_image img;
    /* a FIFO without a writer: refused at once, never a blocked open (alarm in the child) */
    CHECK(mkfifo(at("fifo.exr"), 0600) == 0);
    CHECK(mkfifo(at("fifo.png"), 0600) == 0);
    child_result r = read_in_child(at("fifo.exr"), 0, 0);
    CHECKF(r.ran && r.rc < 0 && strstr(r.err, "fifo.exr") && strstr(r.err, "it is a FIFO"),
           "fifo.exr: %s", r.err);
    r = read_in_child(at("fifo.png"), 0, 0);
    CHECKF(r.ran && r.rc < 0 && strstr(r.err, "it is a FIFO"), "fifo.png: %s", r.err);
    /* /dev/zero behind an image's name */
    CHECK(symlink("/dev/zero", at("zero.hdr")) == 0);
    r = read_in_child(at("zero.hdr"), 256u << 20, 0);
    CHECKF(r.ran && r.rc < 0 && strstr(r.err, "zero.hdr") && strstr(r.err, "character device"),
           "zero.hdr: %s", r.err);
    /* a sparse file over the file-size limit: 64 MiB (the floor) at a 100-pixel limit */
    int fd = open(at("sparse.exr"), O_CREAT | O_WRONLY | O_TRUNC, 0644);
    CHECK(fd >= 0 && ftruncate(fd, (65 << 20)) == 0);
    if (fd >= 0)
        close(fd);
    lg_image_set_max_pixels(100);
    CHECK(lg_image_max_file_bytes() == 64u << 20);
    int rc = lg_image_read(at("sparse.exr"), 0, &img, NULL, err, sizeof err);
    CHECKF(rc < 0 && strstr(err, "sparse.exr") && strstr(err, "over the 64.0 MiB limit") &&
               strstr(err, "--max-pixels"),
           "sparse: %s", err);
    lg_image_set_max_pixels(0);
    CHECK(lg_image_max_file_bytes() == 32 * LG_IMAGE_MAX_PIXELS_DEFAULT);
    /* ... which the default limit (4 GiB) lets through to the decoder */
    rc = lg_image_read(at("sparse.exr"), 0, &img, NULL, err, sizeof err);
    CHECKF(rc < 0 && strstr(err, "not an OpenEXR file"), "sparse at default: %s", err);
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "read")) {
        lg_image img;
        char err[600];
        if (lg_image_read(argv[2], 0, &img, NULL, err, sizeof err)) {
            fprintf(stderr, "%s\n", err);
            return 1;
        }
        printf("%ux%u\n", img.width, img.height);
        lg_image_free(&img);
        return 0;
    }
    signal(SIGPIPE, SIG_IGN);
    snprintf(scratch, sizeof scratch, "%s", make_scratch("codecs-limits"));
    test_png_bomb();
    test_exr_window();
    test_hdr_resolution();
    test_raise_limit();
    test_special_files();
    return check_report_scratch("limits", scratch);
}
