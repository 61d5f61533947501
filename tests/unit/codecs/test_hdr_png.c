/*
 * Radiance .hdr (RLE and flat, header variables, orientations, old-style RLE, errors naming
 * the scanline) and PNG (8/16-bit, grey, palette, alpha, interlaced; sRGB both ways),
 * checked against libpng's own simplified API and against a real file of each kind.
 */
#include <float.h>
#include <math.h>
#include <png.h>
#include <stdint.h>
#include <string.h>
#include <sys/wait.h>

#include "codectest.h"
#include "lightgraph/image.h"

static char scratch[4096];

static void scratch_path(char *buf, size_t n, const char *name)
{
    snprintf(buf, n, "%s/%s", scratch, name);
}

static void write_bytes(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, n, f) != n)
        fprintf(stderr, "cannot write %s\n", path);
    if (f)
        fclose(f);
}

/* ---- HDR ------------------------------------------------------------------------------------- */

static void fill_wide(lg_image *img)
{
    uint32_t s = 99;
    for (size_t i = 0; i < (size_t)img->width * img->height * 4; i++) {
        s = s * 1664525u + 1013904223u;
        img->pixels[i] = ldexpf((float)(s >> 8) / 16777216.0f, (int)(s % 40) - 20);
    }
    /* runs, for the RLE encoder, and the edge cases */
    for (uint32_t x = 0; x < img->width / 2; x++)
        for (int c = 0; c < 3; c++)
            img->pixels[(size_t)x * 4 + (size_t)c] = 0.75f;
    img->pixels[4 * 3] = -2.0f;
    img->pixels[4 * 4 + 1] = NAN;
    img->pixels[4 * 5 + 2] = INFINITY;
    memset(img->pixels + 4 * 6, 0, 16);
}

static void check_hdr_roundtrip(uint32_t w, uint32_t h, const char *want_comp)
{
    char path[4200], err[512];
    snprintf(path, sizeof path, "%s/rt_%ux%u.hdr", scratch, w, h);
    lg_image src, got;
    lg_image_read_info info;
    CHECK(lg_image_alloc(&src, w, h) == LG_OK);
    fill_wide(&src);
    CHECKF(lg_image_write(path, &src, NULL, err, sizeof err) == LG_OK, "%s", err);
    int rc = lg_image_read(path, 0, &got, &info, err, sizeof err);
    CHECKF(rc == LG_OK, "%s", err);
    if (rc == LG_OK) {
        CHECK(got.width == w && got.height == h && info.channels == 3 && info.bits == 8);
        CHECKF(!strcmp(info.compression, want_comp), "%ux%u: %s", w, h, info.compression);
        size_t bad = 0;
        for (size_t i = 0; i < (size_t)w * h; i++) {
            uint8_t e[4];
            float want[3];
            lg_rgbe_encode(src.pixels + i * 4, e);
            lg_rgbe_decode(e, want);
            bad += memcmp(want, got.pixels + i * 4, 12) != 0 || got.pixels[i * 4 + 3] != 1.0f;
        }
        CHECKF(bad == 0, "%ux%u: %zu pixels differ", w, h, bad);
    }
    lg_image_free(&src);
    lg_image_free(&got);
}

/* A hand-made file: header text, then raw bytes. */
static int read_made(const char *name, const char *header, const uint8_t *px, size_t n,
                     lg_image *img, lg_image_read_info *info, char *err, size_t errlen)
{
    char path[4200];
    scratch_path(path, sizeof path, name);
    size_t hl = strlen(header);
    uint8_t *buf = malloc(hl + n + 1);
    memcpy(buf, header, hl);
    if (n)
        memcpy(buf + hl, px, n);
    write_bytes(path, buf, hl + n);
    free(buf);
    return lg_image_read(path, 0, img, info, err, errlen);
}

static void test_hdr(void)
{
    check_hdr_roundtrip(67, 45, "rle");
    check_hdr_roundtrip(8, 3, "rle");      /* smallest RLE width */
    check_hdr_roundtrip(7, 3, "none");     /* too narrow: flat */
    check_hdr_roundtrip(32767, 2, "rle");  /* widest RLE width */
    check_hdr_roundtrip(32768, 2, "none"); /* too wide: flat */

    lg_image img;
    lg_image_read_info info;
    char err[512];
    /* 2x2 flat pixels: (128,0,0,129) = 1.0 red, (0,128,0,130) = 2.0 green, ... */
    const uint8_t px[16] = { 128, 0, 0, 129, 0, 128, 0, 130, 0, 0, 128, 131, 128, 128, 128, 128 };
    const float val[4][3] = { { 1, 0, 0 }, { 0, 2, 0 }, { 0, 0, 4 }, { 0.5f, 0.5f, 0.5f } };

    /* #?RGBE signature, EXPOSURE (values were multiplied by it: divide) and COLORCORR */
    int rc = read_made("exp.hdr",
                       "#?RGBE\n# a comment\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=2\nEXPOSURE=  2\n"
                       "COLORCORR=1 2 0.5\nPRIMARIES=0.64 0.33 0.3 0.6 0.15 0.06 0.3127 0.329\n\n"
                       "-Y 2 +X 2\n",
                       px, 16, &img, &info, err, sizeof err);
    CHECKF(rc == 0, "%s", err);
    if (!rc) {
        CHECK(img.pixels[0] == 0.25f && img.pixels[5] == 0.25f && img.pixels[10] == 2.0f);
        CHECK(img.pixels[12] == 0.125f && img.pixels[13] == 0.0625f && img.pixels[14] == 0.25f);
        CHECK(!strcmp(info.compression, "none"));
    }
    lg_image_free(&img);

    /* a header written with CRLF line ends and trailing blanks */
    rc = read_made("crlf.hdr",
                   "#?RADIANCE\r\nFORMAT=32-bit_rle_rgbe \r\nEXPOSURE=0.5\r\n\r\n-Y 2 +X 2\r\n", px,
                   16, &img, NULL, err, sizeof err);
    CHECKF(rc == 0 && img.pixels[0] == 2.0f, "crlf: %s", err);
    lg_image_free(&img);

    /* orientations: +Y is bottom-up, -X right to left */
    const char *orient[3] = { "+Y 2 +X 2\n", "-Y 2 -X 2\n", "+Y 2 -X 2\n" };
    const int map[3][4] = { { 2, 3, 0, 1 },
                            { 1, 0, 3, 2 },
                            { 3, 2, 1, 0 } }; /* file pixel at each place */
    for (int o = 0; o < 3; o++) {
        char hdr[128];
        snprintf(hdr, sizeof hdr, "#?RADIANCE\n\n%s", orient[o]);
        rc = read_made("orient.hdr", hdr, px, 16, &img, NULL, err, sizeof err);
        CHECKF(rc == 0, "%s", err);
        for (int i = 0; i < 4 && !rc; i++)
            for (int c = 0; c < 3; c++)
                CHECKF(img.pixels[i * 4 + c] == val[map[o][i]][c], "%s pixel %d", orient[o], i);
        lg_image_free(&img);
    }

    /* old-style RLE: (1,1,1,n) repeats the previous pixel n << shift times, the shift
     * growing by 8 with each consecutive code: 1 pixel + 43 + (1 << 8) = 300 */
    {
        enum { W = 300 };
        const uint8_t line[12] = { 128, 64, 32, 129, 1, 1, 1, 43, 1, 1, 1, 1 };
        uint8_t file[24];
        memcpy(file, line, 12);
        memcpy(file + 12, line, 12);
        rc = read_made("old.hdr", "#?RADIANCE\n\n-Y 2 +X 300\n", file, 24, &img, NULL, err,
                       sizeof err);
        CHECKF(rc == 0, "%s", err);
        size_t bad = 0;
        for (size_t i = 0; i < 2 * W && !rc; i++)
            bad += img.pixels[i * 4] != 1.0f || img.pixels[i * 4 + 1] != 0.5f ||
                   img.pixels[i * 4 + 2] != 0.25f;
        CHECKF(bad == 0, "old RLE: %zu wrong pixels", bad);
        lg_image_free(&img);
        /* a repeat before any pixel, and one past the width */
        const uint8_t first[4] = { 1, 1, 1, 5 };
        rc = read_made("old1.hdr", "#?RADIANCE\n\n-Y 1 +X 8\n", first, 4, &img, NULL, err,
                       sizeof err);
        CHECKF(rc == LG_ERR_INVALID && strstr(err, "before any pixel"), "%s", err);
        const uint8_t over[8] = { 128, 64, 32, 129, 1, 1, 1, 8 };
        rc = read_made("old2.hdr", "#?RADIANCE\n\n-Y 1 +X 8\n", over, 8, &img, NULL, err,
                       sizeof err);
        CHECKF(rc == LG_ERR_INVALID && strstr(err, "overruns"), "%s", err);
    }

    /* errors, each naming the file and the reason */
    struct {
        const char *name, *header;
        const uint8_t *px;
        size_t n;
        const char *want;
        int code;
    } bad[] = {
        { "empty.hdr", "", NULL, 0, "empty file", LG_ERR_INVALID },
        { "magic.hdr", "P6\n2 2\n255\n", px, 12, "no '#?' signature", LG_ERR_INVALID },
        { "nores.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", NULL, 0, "header", LG_ERR_INVALID },
        { "xyze.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 2\n", px, 16,
          "32-bit_rle_xyze", LG_ERR_UNSUPPORTED },
        { "transp.hdr", "#?RADIANCE\n\n+X 2 -Y 2\n", px, 16, "transposed", LG_ERR_UNSUPPORTED },
        { "res.hdr", "#?RADIANCE\n\n-Y two +X 2\n", px, 16, "bad resolution line", LG_ERR_INVALID },
        { "zero.hdr", "#?RADIANCE\n\n-Y 0 +X 2\n", px, 16, "bad resolution line", LG_ERR_INVALID },
        { "huge.hdr", "#?RADIANCE\n\n-Y 1000000 +X 1000000\n", px, 16, "over the limit of",
          LG_ERR_INVALID },
        { "short.hdr", "#?RADIANCE\n\n-Y 20000 +X 20\n", px, 16, "truncated", LG_ERR_INVALID },
        { "trunc.hdr", "#?RADIANCE\n\n-Y 2 +X 2\n", px, 13, "scanline 1", LG_ERR_INVALID },
        { "exposure.hdr", "#?RADIANCE\nEXPOSURE=-1\n\n-Y 2 +X 2\n", px, 16, "EXPOSURE",
          LG_ERR_INVALID },
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        rc = read_made(bad[i].name, bad[i].header, bad[i].px, bad[i].n, &img, NULL, err,
                       sizeof err);
        CHECKF(rc == bad[i].code && strstr(err, bad[i].want) && strstr(err, bad[i].name),
               "%s: rc %d: %s", bad[i].name, rc, err);
        CHECK(img.pixels == NULL && img.width == 0);
    }

    /* new-style RLE damage: width mismatch, overrun, zero-length literal, truncation */
    uint8_t rle[64];
    size_t n = 0;
    struct {
        uint8_t bytes[24];
        size_t n;
        const char *want;
    } rl[] = {
        { { 2, 2, 0, 9 }, 4, "RLE width 9" },
        { { 2, 2, 0, 8, 128 + 9, 5 }, 6, "overruns" },
        { { 2, 2, 0, 8, 0 }, 5, "zero-length" },
        { { 2, 2, 0, 8, 4, 1, 2 }, 7, "scanline 0" },
        { { 2, 2, 0, 8, 128 + 8, 1, 128 + 8, 2, 128 + 8, 3, 128 + 8, 4, 2, 2 }, 14, "scanline 1" },
    };
    for (size_t i = 0; i < sizeof rl / sizeof *rl; i++) {
        memcpy(rle, rl[i].bytes, rl[i].n);
        n = rl[i].n;
        rc = read_made("rle.hdr", i < 4 ? "#?RADIANCE\n\n-Y 1 +X 8\n" : "#?RADIANCE\n\n-Y 2 +X 8\n",
                       rle, n, &img, NULL, err, sizeof err);
        CHECKF(rc == LG_ERR_INVALID && strstr(err, rl[i].want) && strstr(err, "rle.hdr"),
               "case %zu: rc %d: %s", i, rc, err);
    }

    /* the real file: forest as RGBE (RLE) against the float EXR it came from, within
     * RGBE's precision (one step of the shared exponent: its writer truncates). Pixels
     * with a negative channel in the EXR are left out: the tool that made the .hdr
     * wrapped those channels around to mantissas near 255 (105 values). */
    char path[4200];
    lg_image hdr, exr;
    lg_image_read_info ih;
    rc = lg_image_read(asset_path("probes/forest_1024x512.hdr", path, sizeof path), 0, &hdr, &ih,
                       err, sizeof err);
    CHECKF(rc == 0, "%s", err);
    int rc2 = lg_image_read(asset_path("probes/forest_1024x512_zip.exr", path, sizeof path), 0,
                            &exr, NULL, err, sizeof err);
    CHECKF(rc2 == 0, "%s", err);
    if (!rc && !rc2) {
        CHECK(hdr.width == 1024 && hdr.height == 512 && !strcmp(ih.compression, "rle"));
        size_t worse = 0;
        double sum_h = 0, sum_e = 0;
        for (size_t i = 0; i < 1024 * 512; i++) {
            const float *pe = exr.pixels + i * 4, *ph = hdr.pixels + i * 4;
            if (pe[0] < 0 || pe[1] < 0 || pe[2] < 0)
                continue;
            float mx = fmaxf(pe[0], fmaxf(pe[1], pe[2]));
            int e2;
            frexpf(mx, &e2);
            double step = mx >= FLT_MIN ? ldexp(1.0, e2 - 8) : 0.0;
            for (int c = 0; c < 3; c++) {
                worse += fabs((double)ph[c] - pe[c]) > step * 1.0001;
                sum_h += ph[c];
                sum_e += pe[c];
            }
        }
        CHECKF(worse == 0, "forest .hdr vs .exr: %zu values off by more than one RGBE step", worse);
        /* the reader keeps the file's mean within RGBE's 1% */
        CHECKF(fabs(sum_h / sum_e - 1.0) < 0.01, "mean ratio %g", sum_h / sum_e);
    }
    lg_image_free(&hdr);
    lg_image_free(&exr);
}

/* pfstools carries its own RGBE reader and writer (rgbeio.cpp): an independent check of
 * ours in both directions, through PFM files. pfstools is a dependency (tools/deps.sh):
 * without it the check fails rather than pass without having run. */
static int run_cmd(const char *cmd)
{
    int rc = system(cmd);
    return rc == -1 ? -1 : WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

static void test_pfstools(void)
{
    if (run_cmd("command -v pfsinrgbe >/dev/null && command -v pfsoutpfm >/dev/null && "
                "command -v pfsinpfm >/dev/null && command -v pfsoutrgbe >/dev/null") != 0) {
        fprintf(stderr, "FAIL: pfstools not found (tools/deps.sh installs it): the cross-check "
                        "with its RGBE code cannot run\n");
        check_failures++;
        return;
    }
    enum { W = 61, H = 23 };
    lg_image src, got;
    char ours[4200], pfm[4200], theirs[4200], cmd[13000], err[512];
    CHECK(lg_image_alloc(&src, W, H) == LG_OK);
    fill_wide(&src);
    for (size_t i = 0; i < W * H * 4; i++) /* keep to what both sides agree on */
        if (!(src.pixels[i] >= 1e-3f) || src.pixels[i] > 1e4f)
            src.pixels[i] = 0.5f;
    scratch_path(ours, sizeof ours, "ours.hdr");
    scratch_path(pfm, sizeof pfm, "pfs.pfm");
    scratch_path(theirs, sizeof theirs, "theirs.hdr");
    CHECKF(lg_image_write(ours, &src, NULL, err, sizeof err) == 0, "%s", err);

    /* ours -> pfsinrgbe -> PFM (bottom row first, RGB float) */
    snprintf(cmd, sizeof cmd, "pfsinrgbe '%s' | pfsoutpfm '%s'", ours, pfm);
    CHECK(run_cmd(cmd) == 0);
    FILE *f = fopen(pfm, "rb");
    int w = 0, h = 0;
    float scale = 0;
    if (f && fscanf(f, "PF %d %d %f", &w, &h, &scale) == 3 && fgetc(f) == '\n' && w == W &&
        h == H) {
        float *v = malloc(sizeof(float) * 3 * W * H);
        CHECK(fread(v, sizeof(float) * 3, W * H, f) == W * H);
        double worst = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                for (int c = 0; c < 3; c++) {
                    uint8_t e[4];
                    float dec[3];
                    lg_rgbe_encode(src.pixels + ((size_t)y * W + x) * 4, e);
                    lg_rgbe_decode(e, dec);
                    double t = v[((size_t)(H - 1 - y) * W + x) * 3 + c];
                    /* relative to the pixel's largest channel: the XYZ round trip
                     * spreads float rounding across channels */
                    double mx = fmax(dec[0], fmax(dec[1], dec[2]));
                    double d = fabs(t - dec[c]) / (mx + 1e-30);
                    if (d > worst)
                        worst = d;
                }
        /* pfstools converts through XYZ in float: a few ulps */
        CHECKF(worst < 1e-4, "pfsinrgbe reads our .hdr differently: relative %g", worst);
        free(v);
    } else {
        CHECKF(0, "cannot parse %s (%dx%d)", pfm, w, h);
    }
    if (f)
        fclose(f);

    /* our values as PFM -> pfsoutrgbe -> read by us: within one RGBE step */
    f = fopen(pfm, "wb");
    fprintf(f, "PF\n%d %d\n-1.0\n", W, H);
    for (int y = H - 1; y >= 0; y--)
        for (int x = 0; x < W; x++)
            fwrite(src.pixels + ((size_t)y * W + x) * 4, sizeof(float), 3, f);
    fclose(f);
    snprintf(cmd, sizeof cmd, "pfsinpfm '%s' | pfsoutrgbe '%s'", pfm, theirs);
    CHECK(run_cmd(cmd) == 0);
    int rc = lg_image_read(theirs, 0, &got, NULL, err, sizeof err);
    CHECKF(rc == 0, "%s", err);
    if (!rc) {
        CHECK(got.width == W && got.height == H);
        size_t bad = 0;
        for (size_t i = 0; i < W * H; i++) {
            const float *p = src.pixels + i * 4;
            float mx = fmaxf(p[0], fmaxf(p[1], p[2]));
            int e2;
            frexpf(mx, &e2);
            double step = ldexp(1.0, e2 - 8) * 1.001;
            for (int c = 0; c < 3; c++)
                bad += fabs((double)got.pixels[i * 4 + c] - p[c]) > step;
        }
        CHECKF(bad == 0, "pfsoutrgbe's .hdr: %zu values beyond one RGBE step", bad);
    }
    lg_image_free(&got);
    lg_image_free(&src);
}

/* ---- PNG ------------------------------------------------------------------------------------- */

static uint8_t code8(float v)
{
    if (!(v > 0))
        return 0;
    if (v >= 1)
        return 255;
    return (uint8_t)lrintf(v * 255.0f);
}

/* Writes a PNG with libpng directly: rows of `bytes_per_row`, any type. */
static void libpng_write(const char *path, uint32_t w, uint32_t h, int depth, int type,
                         int interlace, const uint8_t *data, size_t bytes_per_row,
                         const png_color *pal, int npal, const uint8_t *trns, int ntrns)
{
    FILE *f = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "libpng write failed\n");
        exit(1);
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, w, h, depth, type, interlace, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (pal)
        png_set_PLTE(png, info, pal, npal);
    if (trns)
        png_set_tRNS(png, info, trns, ntrns, NULL);
    png_write_info(png, info);
    png_bytep rows[64];
    for (uint32_t y = 0; y < h; y++)
        rows[y] = (png_bytep)data + y * bytes_per_row;
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(f);
}

static void test_png(void)
{
    char path[4200], err[512];
    lg_image src, got;
    lg_image_read_info info;

    /* our writer, read back by us and by libpng's simplified API */
    CHECK(lg_image_alloc(&src, 37, 11) == LG_OK);
    for (size_t i = 0; i < 37 * 11 * 4; i++)
        src.pixels[i] = (float)((i * 7919) % 1000) / 800.0f - 0.1f; /* -0.1 .. 1.15 */
    src.pixels[0] = NAN;
    src.pixels[7] = NAN; /* alpha */
    for (uint32_t ch = 3; ch <= 4; ch++) {
        snprintf(path, sizeof path, "%s/rt_%u.png", scratch, ch);
        lg_image_write_opts o = { .channels = ch };
        CHECKF(lg_image_write(path, &src, &o, err, sizeof err) == 0, "%s", err);
        int rc = lg_image_read(path, 0, &got, &info, err, sizeof err);
        CHECKF(rc == 0, "%s", err);
        if (rc)
            continue;
        CHECK(info.channels == ch && info.bits == 8 && got.width == 37 && got.height == 11);
        png_image pi;
        memset(&pi, 0, sizeof pi);
        pi.version = PNG_IMAGE_VERSION;
        CHECK(png_image_begin_read_from_file(&pi, path));
        pi.format = PNG_FORMAT_RGBA;
        uint8_t *ref = malloc(PNG_IMAGE_SIZE(pi));
        CHECK(png_image_finish_read(&pi, NULL, ref, 0, NULL));
        size_t bad = 0, badref = 0;
        for (size_t i = 0; i < 37 * 11; i++) {
            for (int c = 0; c < 4; c++) {
                float v = src.pixels[i * 4 + c];
                uint8_t want = c < 3 ? code8(lg_srgb_encode(v)) : ch == 4 ? code8(v) : 255;
                float wantf = c < 3 ? lg_srgb_decode((float)want / 255.0f) : (float)want / 255.0f;
                bad += got.pixels[i * 4 + c] != wantf;
                badref += ref[i * 4 + c] != want;
            }
        }
        CHECKF(bad == 0 && badref == 0,
               "png %u channels: %zu values wrong, %zu bytes differ from libpng", ch, bad, badref);
        free(ref);
        lg_image_free(&got);
    }
    lg_image_free(&src);

    /* every colour type and depth, written by libpng, read by us */
    uint8_t data[8 * 8 * 8];
    float lut[256];
    for (int i = 0; i < 256; i++)
        lut[i] = lg_srgb_decode((float)i / 255.0f);
    for (int i = 0; i < (int)sizeof data; i++)
        data[i] = (uint8_t)(i * 37 + 11);

    struct {
        const char *name;
        int depth, type, interlace;
        size_t bpr;
        uint32_t channels;
    } kinds[] = {
        { "g8", 8, PNG_COLOR_TYPE_GRAY, 0, 8, 1 },
        { "g16", 16, PNG_COLOR_TYPE_GRAY, 0, 16, 1 },
        { "g1", 1, PNG_COLOR_TYPE_GRAY, 0, 1, 1 },
        { "ga8", 8, PNG_COLOR_TYPE_GRAY_ALPHA, 0, 16, 2 },
        { "rgb16", 16, PNG_COLOR_TYPE_RGB, 0, 48, 3 },
        { "rgba16", 16, PNG_COLOR_TYPE_RGB_ALPHA, 0, 64, 4 },
        { "rgb8i", 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_ADAM7, 24, 3 },
        { "pal", 8, PNG_COLOR_TYPE_PALETTE, 0, 8, 4 },
    };
    png_color pal[256];
    uint8_t trns[256];
    for (int i = 0; i < 256; i++) {
        pal[i].red = (uint8_t)i;
        pal[i].green = (uint8_t)(255 - i);
        pal[i].blue = (uint8_t)(i * 3);
        trns[i] = (uint8_t)(i ^ 0x5a);
    }
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++) {
        snprintf(path, sizeof path, "%s/%s.png", scratch, kinds[k].name);
        int is_pal = kinds[k].type == PNG_COLOR_TYPE_PALETTE;
        libpng_write(path, 8, 8, kinds[k].depth, kinds[k].type, kinds[k].interlace, data,
                     kinds[k].bpr, is_pal ? pal : NULL, 256, is_pal ? trns : NULL, 256);
        int rc = lg_image_read(path, 0, &got, &info, err, sizeof err);
        CHECKF(rc == 0, "%s: %s", kinds[k].name, err);
        if (rc)
            continue;
        CHECKF(info.channels == kinds[k].channels && info.bits == (uint32_t)kinds[k].depth,
               "%s: channels %u bits %u", kinds[k].name, info.channels, info.bits);
        size_t bad = 0;
        for (uint32_t y = 0; y < 8; y++)
            for (uint32_t x = 0; x < 8; x++) {
                const uint8_t *row = data + y * kinds[k].bpr;
                float want[4] = { 0, 0, 0, 1 };
                const char *nm = kinds[k].name;
                if (!strcmp(nm, "g8") || !strcmp(nm, "ga8")) {
                    int s = !strcmp(nm, "ga8") ? 2 : 1;
                    want[0] = want[1] = want[2] = lut[row[x * s]];
                    if (s == 2)
                        want[3] = row[x * 2 + 1] / 255.0f;
                } else if (!strcmp(nm, "g16")) {
                    want[0] = want[1] = want[2] =
                        lg_srgb_decode((float)(row[2 * x] << 8 | row[2 * x + 1]) / 65535.0f);
                } else if (!strcmp(nm, "g1")) {
                    want[0] = want[1] = want[2] = (row[0] >> (7 - x)) & 1 ? 1.0f : 0.0f;
                } else if (!strcmp(nm, "rgb16") || !strcmp(nm, "rgba16")) {
                    int s = nm[3] == 'a' ? 4 : 3;
                    for (int c = 0; c < s; c++) {
                        float v = (float)(row[2 * (x * s + c)] << 8 | row[2 * (x * s + c) + 1]) /
                                  65535.0f;
                        want[c] = c < 3 ? lg_srgb_decode(v) : v;
                    }
                } else if (!strcmp(nm, "rgb8i")) {
                    for (int c = 0; c < 3; c++)
                        want[c] = lut[row[x * 3 + c]];
                } else { /* palette with transparency */
                    uint8_t idx = row[x];
                    want[0] = lut[pal[idx].red];
                    want[1] = lut[pal[idx].green];
                    want[2] = lut[pal[idx].blue];
                    want[3] = trns[idx] / 255.0f;
                }
                bad += memcmp(want, got.pixels + (y * 8 + x) * 4, 16) != 0;
            }
        CHECKF(bad == 0, "%s: %zu pixels differ", kinds[k].name, bad);
        lg_image_free(&got);
    }

    /* the real file (Draco's test texture): our decode, re-encoded, is libpng's bytes */
    asset_path("images/draco_sphere_basecolor_256.png", path, sizeof path);
    int rc = lg_image_read(path, 0, &got, &info, err, sizeof err);
    CHECKF(rc == 0, "%s", err);
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    if (!rc && png_image_begin_read_from_file(&pi, path)) {
        pi.format = PNG_FORMAT_RGBA;
        uint8_t *ref = malloc(PNG_IMAGE_SIZE(pi));
        CHECK(png_image_finish_read(&pi, NULL, ref, 0, NULL));
        CHECK(pi.width == got.width && pi.height == got.height && info.channels == 3);
        size_t bad = 0;
        for (size_t i = 0; i < (size_t)got.width * got.height * 4; i++)
            bad += code8(i % 4 == 3 ? got.pixels[i] : lg_srgb_encode(got.pixels[i])) != ref[i];
        CHECKF(bad == 0, "draco png: %zu values differ from libpng", bad);
        free(ref);
    } else {
        CHECKF(0, "libpng cannot read %s", path);
    }
    lg_image_free(&got);
}

int main(void)
{
    snprintf(scratch, sizeof scratch, "%s", make_scratch("codecs-hdrpng"));
    test_hdr();
    test_pfstools();
    test_png();
    return check_report_scratch("hdr_png", scratch);
}
