/*
 * gltf_image.c: PNG (libpng) and JPEG (libjpeg-turbo) to RGBA8 (gltf_image.h).
 *
 * Both libraries report errors by calling a function that must not return; the ones here
 * longjmp back to the decoder, which frees what it made and returns the message. Locals
 * changed between setjmp and longjmp are volatile (C11 7.13.2.1).
 */
#include "gltf_image.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>

#include <jerror.h> /* the JWRN_ codes; after jpeglib.h, which it needs */
#include <png.h>

static void set_err(char *err, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_err(char *err, size_t size, const char *fmt, ...)
{
    if (!err || !size)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, size, fmt, ap);
    va_end(ap);
}

/* The size check made on the header, before any pixel memory exists. */
static bool size_ok(uint64_t w, uint64_t h, uint64_t max_pixels, char *err, size_t err_size)
{
    if (w == 0 || h == 0) {
        set_err(err, err_size, "%llu x %llu pixels: an empty image", (unsigned long long)w,
                (unsigned long long)h);
        return false;
    }
    if (w > max_pixels || h > max_pixels || w * h > max_pixels) {
        set_err(err, err_size, "%llu x %llu pixels, more than the %llu accepted",
                (unsigned long long)w, (unsigned long long)h, (unsigned long long)max_pixels);
        return false;
    }
    return true;
}

/* ---- PNG ------------------------------------------------------------------------------------- */

typedef struct png_src {
    const uint8_t *bytes;
    size_t size, at;
    char *err;
    size_t err_size;
} png_src;

static void png_read_mem(png_structp png, png_bytep out, size_t n)
{
    png_src *s = png_get_io_ptr(png);
    if (n > s->size - s->at)
        png_error(png, "the data ends early (a truncated file)");
    memcpy(out, s->bytes + s->at, n);
    s->at += n;
}

static void png_fail(png_structp png, png_const_charp msg)
{
    png_src *s = png_get_error_ptr(png);
    set_err(s->err, s->err_size, "PNG: %s", msg);
    png_longjmp(png, 1);
}

/* libpng's warnings (an unknown sRGB profile, an ancillary chunk's CRC) leave the pixels
 * right: they are not worth a message per load. */
static void png_warn(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static int decode_png(const uint8_t *bytes, size_t size, uint64_t max_pixels, uint32_t *width,
                      uint32_t *height, uint8_t **rgba, char *err, size_t err_size)
{
    png_src src = { bytes, size, 0, err, err_size };
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &src, png_fail, png_warn);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_read_struct(png ? &png : NULL, NULL, NULL);
        set_err(err, err_size, "PNG: out of memory");
        return -1;
    }
    uint8_t *volatile pixels = NULL;
    png_bytep *volatile rows = NULL;
    if (setjmp(png_jmpbuf(png))) {
        free(pixels);
        free(rows);
        png_destroy_read_struct(&png, &info, NULL);
        return -1;
    }
    png_set_read_fn(png, &src, png_read_mem);
    png_read_info(png, info);
    uint32_t w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    if (!size_ok(w, h, max_pixels, err, err_size)) {
        png_destroy_read_struct(&png, &info, NULL);
        return -1;
    }
    int type = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
    bool trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
    if (depth == 16)
        png_set_strip_16(png); /* the high byte: the value rounded down to 8 bits */
    if (type == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if (type == PNG_COLOR_TYPE_GRAY && depth < 8)
        png_set_expand_gray_1_2_4_to_8(png);
    if (trns)
        png_set_tRNS_to_alpha(png);
    if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    if (!(type & PNG_COLOR_MASK_ALPHA) && !trns)
        png_set_filler(png, 0xff, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != (size_t)w * 4)
        png_error(png, "unexpected row size after the RGBA conversion");
    pixels = malloc((size_t)w * h * 4);
    rows = malloc((size_t)h * sizeof *rows);
    if (!pixels || !rows)
        png_error(png, "out of memory for the pixels");
    for (uint32_t y = 0; y < h; y++)
        rows[y] = pixels + (size_t)y * w * 4;
    png_read_image(png, rows);
    png_read_end(png, NULL);
    free(rows);
    png_destroy_read_struct(&png, &info, NULL);
    *width = w;
    *height = h;
    *rgba = pixels;
    return 0;
}

/* ---- JPEG ------------------------------------------------------------------------------------ */

typedef struct jpeg_fail_mgr {
    struct jpeg_error_mgr pub;
    jmp_buf jump;
    char *err;
    size_t err_size;
} jpeg_fail_mgr;

static void jpeg_fail(j_common_ptr c)
{
    jpeg_fail_mgr *f = (jpeg_fail_mgr *)c->err;
    char msg[JMSG_LENGTH_MAX];
    c->err->format_message(c, msg);
    set_err(f->err, f->err_size, "JPEG: %s", msg);
    longjmp(f->jump, 1);
}

/* Warnings that mean the data is corrupt or cut short are errors: libjpeg would go on and
 * fill the rest of the image with grey. Other warnings (unknown markers) are ignored. */
static void jpeg_message(j_common_ptr c, int level)
{
    if (level >= 0)
        return; /* trace messages */
    switch (c->err->msg_code) {
    case JWRN_JPEG_EOF:
    case JWRN_HIT_MARKER:
    case JWRN_MUST_RESYNC:
    case JWRN_HUFF_BAD_CODE:
    case JWRN_BOGUS_PROGRESSION:
    case JWRN_NOT_SEQUENTIAL:
    case JWRN_EXTRANEOUS_DATA: jpeg_fail(c); break;
    default: break;
    }
}

static int decode_jpeg(const uint8_t *bytes, size_t size, uint64_t max_pixels, uint32_t *width,
                       uint32_t *height, uint8_t **rgba, char *err, size_t err_size)
{
    struct jpeg_decompress_struct cinfo;
    jpeg_fail_mgr fail;
    memset(&cinfo, 0, sizeof cinfo);
    cinfo.err = jpeg_std_error(&fail.pub);
    fail.pub.error_exit = jpeg_fail;
    fail.pub.emit_message = jpeg_message;
    fail.err = err;
    fail.err_size = err_size;
    uint8_t *volatile pixels = NULL;
    if (setjmp(fail.jump)) {
        free(pixels);
        jpeg_destroy_decompress(&cinfo);
        return -1;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, bytes, (unsigned long)size);
    jpeg_read_header(&cinfo, TRUE);
    uint32_t w = cinfo.image_width, h = cinfo.image_height;
    if (!size_ok(w, h, max_pixels, err, err_size)) {
        jpeg_destroy_decompress(&cinfo);
        return -1;
    }
    if (cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK) {
        set_err(err, err_size,
                "JPEG: a CMYK image (%s), which glTF does not allow (RGB or greyscale only)",
                cinfo.jpeg_color_space == JCS_CMYK ? "CMYK" : "YCCK");
        jpeg_destroy_decompress(&cinfo);
        return -1;
    }
    cinfo.out_color_space = JCS_EXT_RGBA; /* libjpeg-turbo: grey and YCbCr to RGBX, X = 255 */
    jpeg_start_decompress(&cinfo);
    if (cinfo.output_width != w || cinfo.output_height != h || cinfo.output_components != 4) {
        set_err(err, err_size, "JPEG: the decoder gives %u x %u x %d, not %u x %u RGBA",
                cinfo.output_width, cinfo.output_height, cinfo.output_components, w, h);
        jpeg_destroy_decompress(&cinfo);
        return -1;
    }
    pixels = malloc((size_t)w * h * 4);
    if (!pixels) {
        set_err(err, err_size, "JPEG: out of memory for %u x %u pixels", w, h);
        jpeg_destroy_decompress(&cinfo);
        return -1;
    }
    while (cinfo.output_scanline < h) {
        JSAMPROW row = pixels + (size_t)cinfo.output_scanline * w * 4;
        if (jpeg_read_scanlines(&cinfo, &row, 1) != 1) {
            /* the memory source never suspends; a stalled decoder is a broken stream */
            set_err(err, err_size, "JPEG: the decoder stopped at row %u", cinfo.output_scanline);
            free(pixels);
            jpeg_destroy_decompress(&cinfo);
            return -1;
        }
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    *width = w;
    *height = h;
    *rgba = pixels;
    return 0;
}

int lg_gltf_image_decode(const uint8_t *bytes, size_t size, uint64_t max_pixels, uint32_t *width,
                         uint32_t *height, uint8_t **rgba, char *err, size_t err_size)
{
    *rgba = NULL;
    *width = *height = 0;
    static const uint8_t png_sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
    if (size >= 8 && !memcmp(bytes, png_sig, 8))
        return decode_png(bytes, size, max_pixels, width, height, rgba, err, err_size);
    if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff)
        return decode_jpeg(bytes, size, max_pixels, width, height, rgba, err, err_size);
    if (size == 0) {
        set_err(err, err_size, "an empty image (0 bytes)");
        return -1;
    }
    char head[3 * 8 + 1] = "";
    for (size_t i = 0, at = 0; i < size && i < 8; i++)
        at += (size_t)snprintf(head + at, sizeof head - at, "%s%02x", i ? " " : "", bytes[i]);
    set_err(err, err_size, "not a PNG or JPEG image (it starts with %s)", head);
    return -1;
}
