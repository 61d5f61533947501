/*
 * OpenEXR: round trips through every compression, half and float, RGB and RGBA; files with
 * data windows, tiles, mipmaps, luminance and uint channels written here with the C API;
 * and real files. Everything read through the C API path is also read through the C++
 * shim and the two must agree bit for bit (this is what caught the channel swap of
 * OpenEXR 3.1.5's interleaved half decoding).
 */
#include <math.h>
#include <openexr.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "codectest.h"
#include "image_priv.h"
#include "lightgraph/file.h"

static char scratch[4096];

/* The C++ path alone, on a file opened as lg_image_read opens it. */
static int cxx_read(const char *path, lg_image *img, lg_image_read_info *info, char *err,
                    size_t errlen)
{
    uint64_t size = 0;
    memset(img, 0, sizeof *img);
    int fd = lg_file_open(path, UINT64_MAX, &size, err, errlen);
    if (fd < 0)
        return LG_ERR_IO;
    int rc = lg_exr_cxx_read(fd, size, path, img, info, err, errlen);
    close(fd);
    return rc;
}

static const char *comp_names[] = { "zip",   "none", "rle",  "zips", "piz",
                                    "pxr24", "b44",  "b44a", "dwaa", "dwab" };

static void fill_pattern(lg_image *img)
{
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++) {
            float *p = img->pixels + ((size_t)y * img->width + x) * 4;
            p[0] = 0.002f +
                   4.0f * (float)x / (float)img->width * (1.0f + 0.3f * sinf(0.3f * (float)y));
            p[1] = 0.5f * (float)(y + 1) / (float)img->height;
            p[2] = 0.05f + 0.9f * fabsf(sinf(0.11f * (float)x + 0.07f * (float)y));
            p[3] = (float)((x + 2 * y) % 5) / 4.0f;
        }
}

static int same_pixels(const lg_image *a, const lg_image *b)
{
    return a->width == b->width && a->height == b->height &&
           !memcmp(a->pixels, b->pixels, (size_t)a->width * a->height * 16);
}

/* largest |a-b| / (|b| + floor) over the channels of the given count */
static double max_rel_err(const lg_image *a, const lg_image *b, int chans, double floor)
{
    double m = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++)
        for (int c = 0; c < chans; c++) {
            double d = fabs((double)a->pixels[i * 4 + c] - b->pixels[i * 4 + c]) /
                       (fabs((double)b->pixels[i * 4 + c]) + floor);
            if (!(d <= m))
                m = d;
        }
    return m;
}

static void test_roundtrips(void)
{
    lg_image src, expect_half;
    CHECK(lg_image_alloc(&src, 67, 45) == LG_OK); /* not a multiple of any chunk or block */
    fill_pattern(&src);
    CHECK(lg_image_alloc(&expect_half, 67, 45) == LG_OK);
    for (size_t i = 0; i < 67 * 45 * 4; i++)
        expect_half.pixels[i] = lg_float_from_half(lg_half_from_float(src.pixels[i]));

    for (int comp = LG_EXR_ZIP; comp <= LG_EXR_DWAB; comp++) {
        for (int pix = LG_EXR_HALF; pix <= LG_EXR_FLOAT; pix++) {
            for (uint32_t ch = 3; ch <= 4; ch++) {
                char path[4200], err[512];
                snprintf(path, sizeof path, "%s/rt_%s_%s_%u.exr", scratch, comp_names[comp],
                         pix == LG_EXR_HALF ? "half" : "float", ch);
                lg_image_write_opts o = { .exr_pixel = (lg_exr_pixel)pix,
                                          .exr_compression = (lg_exr_compression)comp,
                                          .channels = ch };
                int rc = lg_image_write(path, &src, &o, err, sizeof err);
                CHECKF(rc == LG_OK, "%s: %s", path, err);
                if (rc)
                    continue;
                lg_image a, b;
                lg_image_read_info ia, ib;
                memset(&ib, 0, sizeof ib);
                rc = lg_image_read(path, 0, &a, &ia, err, sizeof err);
                CHECKF(rc == LG_OK, "%s: %s", path, err);
                int rc2 = cxx_read(path, &b, &ib, err, sizeof err);
                CHECKF(rc2 == LG_OK, "%s (C++): %s", path, err);
                if (rc || rc2) {
                    lg_image_free(&a);
                    lg_image_free(&b);
                    continue;
                }
                CHECKF(!strcmp(ia.compression, comp_names[comp]), "%s: compression %s", path,
                       ia.compression);
                CHECKF(ia.channels == ch && ia.bits == (pix == LG_EXR_HALF ? 16u : 32u),
                       "%s: channels %u bits %u", path, ia.channels, ia.bits);
                CHECKF(ib.channels == ch && ib.bits == ia.bits &&
                           !strcmp(ib.compression, ia.compression),
                       "%s: C++ info differs", path);
                CHECKF(same_pixels(&a, &b), "%s: the C and C++ readers disagree", path);

                const lg_image *want = pix == LG_EXR_HALF ? &expect_half : &src;
                int lossy = (comp == LG_EXR_PXR24 && pix == LG_EXR_FLOAT) ||
                            ((comp == LG_EXR_B44 || comp == LG_EXR_B44A) && pix == LG_EXR_HALF) ||
                            comp == LG_EXR_DWAA || comp == LG_EXR_DWAB;
                /* lossy: B44 quantises 4x4 blocks relative to their largest value, so
                 * small values beside large ones get a large relative error: compare
                 * against the value plus 0.1 (the pattern spans 0 .. 5.2) */
                double rel = max_rel_err(&a, want, 3, lossy ? 0.1 : 0.01);
                double tol = !lossy ? 0.0 : comp == LG_EXR_PXR24 ? 1e-4 : 0.08;
                CHECKF(rel <= tol, "%s: colour error %g > %g", path, rel, tol);
                if (lossy && comp != LG_EXR_PXR24) {
                    lg_image_metrics m;
                    CHECK(lg_image_compare(&a, want, &m, NULL, 0, err, sizeof err) == LG_OK);
                    CHECKF(m.rmse < 0.01, "%s: rmse %g", path, m.rmse);
                }
                /* alpha: exact where the compression keeps it, 1 when not written */
                double arel = 0;
                for (size_t i = 0; i < 67 * 45; i++) {
                    double wa = ch == 4 ? want->pixels[i * 4 + 3] : 1.0;
                    double d = fabs(a.pixels[i * 4 + 3] - wa);
                    if (d > arel)
                        arel = d;
                }
                int alpha_lossy = (comp == LG_EXR_B44 || comp == LG_EXR_B44A) && pix == LG_EXR_HALF;
                CHECKF(arel <= (alpha_lossy ? 0.02 : 0.0), "%s: alpha error %g", path, arel);
                lg_image_free(&a);
                lg_image_free(&b);
            }
        }
    }

    /* half: beyond 65504 becomes Inf, as OpenEXR's half does; NaN stays NaN */
    lg_image big;
    CHECK(lg_image_alloc(&big, 4, 1) == LG_OK);
    float vals[4] = { 65504.0f, 70000.0f, -1e6f, NAN };
    for (int i = 0; i < 4; i++)
        big.pixels[i * 4] = big.pixels[i * 4 + 1] = big.pixels[i * 4 + 2] = vals[i];
    for (int comp = LG_EXR_ZIP; comp <= LG_EXR_DWAB; comp += (comp == LG_EXR_NONE ? 8 : 1)) {
        /* ZIP and NONE through the C API, DWAA/DWAB through C++ */
        char path[4200], err[512];
        snprintf(path, sizeof path, "%s/big_%s.exr", scratch, comp_names[comp]);
        lg_image_write_opts o = { .exr_compression = (lg_exr_compression)comp };
        CHECKF(lg_image_write(path, &big, &o, err, sizeof err) == LG_OK, "%s", err);
        lg_image r;
        lg_image_read_info info;
        CHECKF(lg_image_read(path, 0, &r, &info, err, sizeof err) == LG_OK, "%s", err);
        if (!r.pixels)
            continue;
        if (comp <= LG_EXR_NONE) {
            CHECK(r.pixels[0] == 65504.0f);
            CHECK(r.pixels[4] == INFINITY && r.pixels[8] == -INFINITY && isnan(r.pixels[12]));
            CHECK(info.nonfinite == 3);
        }
        lg_image_free(&r);
    }
    lg_image_free(&big);
    lg_image_free(&src);
    lg_image_free(&expect_half);
}

/* ---- files written here with the C API ------------------------------------------------------- */

typedef struct chan_spec {
    const char *name;
    exr_pixel_type_t type;
    const void *data; /* w*h floats, or uint32 for EXR_PIXEL_UINT, data window sized
                       * (divided by the sampling for subsampled channels) */
    int sampling;     /* 0 or 1: full resolution; 2: every other pixel and line */
} chan_spec;

/* Writes a scanline or tiled (optionally mipmapped: every level gets the level-0 data of
 * its top-left corner) single-part file. */
static int write_special(const char *path, exr_attr_box2i_t dw, const chan_spec *ch, int nch,
                         exr_compression_t comp, int tile, int mip, exr_lineorder_t order)
{
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    int part, w = dw.max.x - dw.min.x + 1;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv)
        return rv;
    exr_attr_box2i_t disp;
    exr_attr_v2f_t swc;
    memset(&swc, 0, sizeof swc);
    disp.min.x = disp.min.y = 0;
    disp.max.x = disp.max.y = 99;
    rv = exr_add_part(ctx, NULL, tile ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE, &part);
    if (!rv)
        rv = exr_initialize_required_attr(ctx, part, &disp, &dw, 1.0f, &swc, 1.0f, order, comp);
    for (int c = 0; c < nch && !rv; c++)
        rv = exr_add_channel(ctx, part, ch[c].name, ch[c].type, EXR_PERCEPTUALLY_LOGARITHMIC,
                             ch[c].sampling ? ch[c].sampling : 1,
                             ch[c].sampling ? ch[c].sampling : 1);
    if (!rv && tile)
        rv = exr_set_tile_descriptor(ctx, part, (uint32_t)tile, (uint32_t)(tile / 2),
                                     mip ? EXR_TILE_MIPMAP_LEVELS : EXR_TILE_ONE_LEVEL,
                                     EXR_TILE_ROUND_DOWN);
    if (!rv)
        rv = exr_write_header(ctx);
    exr_encode_pipeline_t enc;
    memset(&enc, 0, sizeof enc);
    int ready = 0;
    int32_t levels = 1, ly;
    if (!rv && tile)
        rv = exr_get_tile_levels(ctx, part, &levels, &ly);
    for (int32_t lv = 0; lv < levels && !rv; lv++) {
        int32_t lw = w, lh = dw.max.y - dw.min.y + 1, step = 1;
        if (tile) {
            rv = exr_get_level_sizes(ctx, part, lv, lv, &lw, &lh);
        } else {
            rv = exr_get_scanlines_per_chunk(ctx, part, &step);
        }
        int tw = tile ? tile : lw, th = tile ? tile / 2 : step;
        for (int32_t y0 = 0; y0 < lh && !rv; y0 += th)
            for (int32_t x0 = 0; x0 < lw && !rv; x0 += tw) {
                exr_chunk_info_t ci;
                rv = tile ? exr_write_tile_chunk_info(ctx, part, x0 / tw, y0 / th, lv, lv, &ci)
                          : exr_write_scanline_chunk_info(ctx, part, dw.min.y + y0, &ci);
                if (rv)
                    break;
                rv = ready ? exr_encoding_update(ctx, part, &ci, &enc)
                           : exr_encoding_initialize(ctx, part, &ci, &enc);
                if (rv)
                    break;
                ready = 1;
                for (int c = 0; c < enc.channel_count; c++) {
                    const chan_spec *s = NULL;
                    for (int k = 0; k < nch; k++)
                        if (!strcmp(ch[k].name, enc.channels[c].channel_name))
                            s = &ch[k];
                    int sm = s->sampling ? s->sampling : 1, sw = w / sm;
                    enc.channels[c].encode_from_ptr =
                        (const uint8_t *)s->data +
                        ((size_t)(y0 / sm) * (size_t)sw + (size_t)(x0 / sm)) * 4;
                    enc.channels[c].user_pixel_stride = 4;
                    enc.channels[c].user_line_stride = 4 * sw;
                    enc.channels[c].user_bytes_per_element = 4;
                    enc.channels[c].user_data_type = s->type == EXR_PIXEL_UINT ? EXR_PIXEL_UINT
                                                                               : EXR_PIXEL_FLOAT;
                }
                rv = exr_encoding_choose_default_routines(ctx, part, &enc);
                if (!rv)
                    rv = exr_encoding_run(ctx, part, &enc);
            }
    }
    if (ready)
        exr_encoding_destroy(ctx, &enc);
    exr_result_t frv = exr_finish(&ctx);
    return rv ? rv : frv;
}

/* Reads `path` both ways and checks the pixels against want (w*h*4 floats). */
static void check_special(const char *what, const char *path, const float *want, uint32_t w,
                          uint32_t h, uint32_t channels)
{
    char err[512];
    lg_image a, b;
    lg_image_read_info ia, ib;
    memset(&ib, 0, sizeof ib);
    int rc = lg_image_read(path, 0, &a, &ia, err, sizeof err);
    CHECKF(rc == LG_OK, "%s: %s", what, err);
    int rc2 = cxx_read(path, &b, &ib, err, sizeof err);
    CHECKF(rc2 == LG_OK, "%s (C++): %s", what, err);
    if (!rc) {
        CHECKF(a.width == w && a.height == h, "%s: %ux%u, want %ux%u", what, a.width, a.height, w,
               h);
        CHECKF(ia.channels == channels, "%s: channels %u, want %u", what, ia.channels, channels);
        if (a.width == w && a.height == h)
            CHECKF(!memcmp(a.pixels, want, (size_t)w * h * 16), "%s: pixels differ", what);
    }
    if (!rc && !rc2) {
        CHECKF(same_pixels(&a, &b), "%s: the C and C++ readers disagree", what);
        CHECKF(ib.channels == channels, "%s: C++ channels %u", what, ib.channels);
    }
    lg_image_free(&a);
    lg_image_free(&b);
}

static void test_special_files(void)
{
    enum { W = 43, H = 27 };
    static float r[W * H], g[W * H], b[W * H], a[W * H], want[W * H * 4];
    static uint32_t u[3][W * H];
    for (int i = 0; i < W * H; i++) {
        /* exactly representable in half, so the expected values are exact */
        r[i] = lg_float_from_half(lg_half_from_float((float)(i % 97) * 0.25f));
        g[i] = lg_float_from_half(lg_half_from_float(-(float)(i % 13) / 8.0f));
        b[i] = lg_float_from_half(lg_half_from_float((float)i * 3.0f));
        a[i] = (float)(i % 3) / 2.0f;
        for (int c = 0; c < 3; c++)
            u[c][i] = (uint32_t)(i * (c + 1) * 1000);
    }
    exr_attr_box2i_t dw;
    dw.min.x = -3;
    dw.min.y = 5;
    dw.max.x = -3 + W - 1;
    dw.max.y = 5 + H - 1;
    char path[4200], err[512];

    /* RGBA half, scanline, offset data window, several compressions. (Decreasing line
     * order is not written here: 3.1.5's C core writes such files in a way its C++
     * library cannot read.) */
    chan_spec rgba[4] = { { "R", EXR_PIXEL_HALF, r },
                          { "G", EXR_PIXEL_HALF, g },
                          { "B", EXR_PIXEL_HALF, b },
                          { "A", EXR_PIXEL_HALF, a } };
    for (int i = 0; i < W * H; i++) {
        want[i * 4] = r[i];
        want[i * 4 + 1] = g[i];
        want[i * 4 + 2] = b[i];
        want[i * 4 + 3] = a[i];
    }
    static const exr_compression_t comps[] = { EXR_COMPRESSION_NONE, EXR_COMPRESSION_RLE,
                                               EXR_COMPRESSION_ZIPS, EXR_COMPRESSION_ZIP,
                                               EXR_COMPRESSION_PIZ,  EXR_COMPRESSION_PXR24 };
    for (size_t k = 0; k < sizeof comps / sizeof *comps; k++) {
        snprintf(path, sizeof path, "%s/dw_%d.exr", scratch, (int)comps[k]);
        int rv = write_special(path, dw, rgba, 4, comps[k], 0, 0, EXR_LINEORDER_INCREASING_Y);
        CHECKF(rv == 0, "writing %s: %d", path, rv);
        check_special(path, path, want, W, H, 4);
    }

    /* tiled (partial edge tiles), float RGB, one level and mipmapped */
    chan_spec rgbf[3] = { { "R", EXR_PIXEL_FLOAT, r },
                          { "G", EXR_PIXEL_FLOAT, g },
                          { "B", EXR_PIXEL_FLOAT, b } };
    for (int i = 0; i < W * H; i++)
        want[i * 4 + 3] = 1.0f;
    for (int mip = 0; mip < 2; mip++) {
        snprintf(path, sizeof path, "%s/tiled_%d.exr", scratch, mip);
        int rv = write_special(path, dw, rgbf, 3, EXR_COMPRESSION_ZIP, 16, mip,
                               EXR_LINEORDER_INCREASING_Y);
        CHECKF(rv == 0, "writing %s: %d", path, rv);
        check_special(mip ? "tiled mipmap" : "tiled", path, want, W, H, 3);
    }

    /* luminance only, then luminance and alpha: grey */
    chan_spec ya[2] = { { "Y", EXR_PIXEL_HALF, r }, { "A", EXR_PIXEL_HALF, a } };
    for (int i = 0; i < W * H; i++) {
        want[i * 4] = want[i * 4 + 1] = want[i * 4 + 2] = r[i];
        want[i * 4 + 3] = 1.0f;
    }
    snprintf(path, sizeof path, "%s/y.exr", scratch);
    CHECK(write_special(path, dw, ya, 1, EXR_COMPRESSION_PIZ, 0, 0, EXR_LINEORDER_INCREASING_Y) ==
          0);
    check_special("Y only", path, want, W, H, 1);
    for (int i = 0; i < W * H; i++)
        want[i * 4 + 3] = a[i];
    snprintf(path, sizeof path, "%s/ya.exr", scratch);
    CHECK(write_special(path, dw, ya, 2, EXR_COMPRESSION_ZIP, 0, 0, EXR_LINEORDER_INCREASING_Y) ==
          0);
    check_special("Y and A", path, want, W, H, 2);

    /* uint channels become floats of the same value */
    chan_spec ui[3] = { { "R", EXR_PIXEL_UINT, u[0] },
                        { "G", EXR_PIXEL_UINT, u[1] },
                        { "B", EXR_PIXEL_UINT, u[2] } };
    for (int i = 0; i < W * H; i++) {
        for (int c = 0; c < 3; c++)
            want[i * 4 + c] = (float)u[c][i];
        want[i * 4 + 3] = 1.0f;
    }
    snprintf(path, sizeof path, "%s/uint.exr", scratch);
    CHECK(write_special(path, dw, ui, 3, EXR_COMPRESSION_ZIP, 0, 0, EXR_LINEORDER_INCREASING_Y) ==
          0);
    check_special("uint", path, want, W, H, 3);

    /* channels we do not read (depth, a misspelt G): 3.1.5's C core crashed when such a
     * channel was skipped, so they are decoded into a scratch plane */
    chan_spec rgbz[5] = { { "R", EXR_PIXEL_HALF, r },
                          { "G", EXR_PIXEL_HALF, g },
                          { "B", EXR_PIXEL_HALF, b },
                          { "Z", EXR_PIXEL_FLOAT, a },
                          { "A", EXR_PIXEL_HALF, a } };
    for (int i = 0; i < W * H; i++) {
        want[i * 4] = r[i];
        want[i * 4 + 1] = g[i];
        want[i * 4 + 2] = b[i];
        want[i * 4 + 3] = 1.0f;
    }
    snprintf(path, sizeof path, "%s/rgbz.exr", scratch);
    CHECK(write_special(path, dw, rgbz, 4, EXR_COMPRESSION_ZIP, 0, 0, EXR_LINEORDER_INCREASING_Y) ==
          0);
    check_special("R G B Z", path, want, W, H, 3);
    for (int i = 0; i < W * H; i++)
        want[i * 4 + 3] = a[i];
    rgbz[3].name = "H"; /* sorts between G and R */
    rgbz[3].type = EXR_PIXEL_HALF;
    snprintf(path, sizeof path, "%s/rgbha.exr", scratch);
    CHECK(write_special(path, dw, rgbz, 5, EXR_COMPRESSION_PIZ, 0, 0, EXR_LINEORDER_INCREASING_Y) ==
          0);
    check_special("A B G H R", path, want, W, H, 4);

    /* luminance-chroma (Y full, RY and BY every other pixel and line): the C++ shim's
     * RgbaInputFile converts it. With constant chroma: R = (RY + 1) Y, B = (BY + 1) Y and
     * G from Y = 0.2126 R + 0.7152 G + 0.0722 B (Rec. 709, the default chromaticities). */
    {
        exr_attr_box2i_t dw2;
        dw2.min.x = dw2.min.y = 0;
        dw2.max.x = 15;
        dw2.max.y = 7;
        static float yv[16 * 8], ry[8 * 4], by[8 * 4];
        for (int i = 0; i < 16 * 8; i++)
            yv[i] = lg_float_from_half(lg_half_from_float(0.25f + (float)i / 64.0f));
        for (int i = 0; i < 8 * 4; i++) {
            ry[i] = 0.5f;
            by[i] = -0.25f;
        }
        chan_spec yc[3] = { { "Y", EXR_PIXEL_HALF, yv, 1 },
                            { "RY", EXR_PIXEL_HALF, ry, 2 },
                            { "BY", EXR_PIXEL_HALF, by, 2 } };
        snprintf(path, sizeof path, "%s/yc.exr", scratch);
        CHECK(write_special(path, dw2, yc, 3, EXR_COMPRESSION_ZIP, 0, 0,
                            EXR_LINEORDER_INCREASING_Y) == 0);
        lg_image ycimg;
        lg_image_read_info ycinfo;
        int yrc = lg_image_read(path, 0, &ycimg, &ycinfo, err, sizeof err);
        CHECKF(yrc == 0, "YC: %s", err);
        if (!yrc) {
            double worst = 0;
            for (int i = 0; i < 16 * 8; i++) {
                double R = 1.5 * yv[i], B = 0.75 * yv[i];
                double G = (yv[i] - 0.2126 * R - 0.0722 * B) / 0.7152;
                double want3[3] = { R, G, B };
                for (int c = 0; c < 3; c++)
                    worst = fmax(worst, fabs(ycimg.pixels[i * 4 + c] - want3[c]) / want3[c]);
            }
            CHECKF(worst < 5e-3 && ycinfo.channels == 3 && ycimg.width == 16,
                   "YC: error %g, %u channels", worst, ycinfo.channels);
        }
        lg_image_free(&ycimg);
    }

    /* no colour channel at all: a clear error naming the channels */
    chan_spec z[1] = { { "Z", EXR_PIXEL_FLOAT, r } };
    snprintf(path, sizeof path, "%s/z.exr", scratch);
    CHECK(write_special(path, dw, z, 1, EXR_COMPRESSION_ZIP, 0, 0, EXR_LINEORDER_INCREASING_Y) ==
          0);
    lg_image img;
    int rc = lg_image_read(path, 0, &img, NULL, err, sizeof err);
    CHECKF(rc == LG_ERR_UNSUPPORTED && strstr(err, "channels: Z") && strstr(err, "z.exr"),
           "rc %d: %s", rc, err);
    CHECK(img.pixels == NULL);
}

/* ---- real files ------------------------------------------------------------------------------ */

static int read_asset(const char *rel, unsigned flags, lg_image *img, lg_image_read_info *info)
{
    char path[4200], err[512];
    asset_path(rel, path, sizeof path);
    int rc = lg_image_read(path, flags, img, info, err, sizeof err);
    CHECKF(rc == LG_OK, "%s: %s", rel, err);
    return rc;
}

static void test_real_files(void)
{
    char path[4200], err[512];
    lg_image a, b;
    lg_image_read_info ia, ib;

    /* the OpenEXR samples (PIZ half, RGB and RGBA): C and C++ paths agree bit for bit */
    const char *samples[] = { "images/GoldenGate.exr", "images/StillLife.exr" };
    for (int i = 0; i < 2; i++) {
        if (read_asset(samples[i], 0, &a, &ia))
            continue;
        memset(&ib, 0, sizeof ib);
        CHECKF(cxx_read(asset_path(samples[i], path, sizeof path), &b, &ib, err, sizeof err) == 0,
               "%s", err);
        CHECKF(!strcmp(ia.compression, "piz") && ia.bits == 16, "%s: %s %u", samples[i],
               ia.compression, ia.bits);
        CHECK(ia.channels == (i ? 4u : 3u) && ib.channels == ia.channels);
        CHECKF(same_pixels(&a, &b), "%s: the C and C++ readers disagree", samples[i]);
        CHECK(ia.nonfinite == 0 && ia.negatives_clamped == 0);
        lg_image_free(&a);
        lg_image_free(&b);
    }

    /* forest: ZIP float (C API) was made from the DWAB float file (C++): identical */
    if (!read_asset("probes/forest_1024x512_zip.exr", 0, &a, &ia) &&
        !read_asset("probes/forest_1024x512_float_dwab.exr", 0, &b, &ib)) {
        CHECK(a.width == 1024 && a.height == 512);
        CHECK(!strcmp(ia.compression, "zip") && ia.bits == 32 && ia.channels == 3);
        CHECK(!strcmp(ib.compression, "dwab") && ib.bits == 32 && ib.channels == 3);
        CHECKF(same_pixels(&a, &b), "forest ZIP and DWAB decode differently");
    }
    lg_image_free(&a);
    lg_image_free(&b);

    /* studio: PIZ half (C API) is the DWAB float file (C++) rounded to half */
    if (!read_asset("probes/studio_1024x512_half_piz.exr", 0, &a, &ia) &&
        !read_asset("probes/studio_1024x512_float_dwab.exr", 0, &b, &ib)) {
        CHECK(!strcmp(ia.compression, "piz") && ia.bits == 16);
        size_t diff = 0;
        for (size_t i = 0; i < (size_t)b.width * b.height * 4; i++)
            diff += a.pixels[i] != lg_float_from_half(lg_half_from_float(b.pixels[i]));
        CHECKF(a.width == b.width && diff == 0, "studio PIZ vs DWAB: %zu values differ", diff);
    }
    lg_image_free(&a);
    lg_image_free(&b);

    /* DWAB half with negative pixels (lossy compression): passed through as stored, or
     * clamped and counted with LG_READ_RADIANCE */
    const char *dwab[] = { "probes/studio_512x256_half_dwab.exr",
                           "probes/apartment_512x256_half_dwab.exr" };
    for (int i = 0; i < 2; i++) {
        if (read_asset(dwab[i], 0, &a, &ia) || read_asset(dwab[i], LG_READ_RADIANCE, &b, &ib))
            continue;
        CHECK(a.width == 512 && a.height == 256 && ia.bits == 16 &&
              !strcmp(ia.compression, "dwab"));
        uint64_t neg = 0;
        size_t changed = 0, bad = 0;
        for (size_t p = 0; p < 512 * 256; p++) {
            int n = 0;
            for (int c = 0; c < 4; c++) {
                float va = a.pixels[p * 4 + c], vb = b.pixels[p * 4 + c];
                if (va < 0) {
                    n = 1;
                    bad += vb != 0.0f;
                } else {
                    bad += va != vb;
                }
                changed += va != vb;
            }
            neg += (uint64_t)n;
        }
        CHECKF(neg > 0, "%s: expected negative pixels (lossy DWAB)", dwab[i]);
        CHECK(ia.negatives_clamped == 0);
        CHECKF(ib.negatives_clamped == neg, "%s: clamped %llu, counted %llu", dwab[i],
               (unsigned long long)ib.negatives_clamped, (unsigned long long)neg);
        CHECK(bad == 0 && changed > 0);
        lg_image_free(&a);
        lg_image_free(&b);
    }
}

int main(void)
{
    snprintf(scratch, sizeof scratch, "%s", make_scratch("codecs-exr"));
    test_roundtrips();
    test_special_files();
    test_real_files();
    return check_report_scratch("exr", scratch);
}
