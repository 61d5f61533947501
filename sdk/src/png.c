/*
 * PNG through libpng. Reads 1..16-bit gray, gray+alpha, RGB, RGBA and palette files and
 * decodes sRGB to linear (gAMA and iCCP chunks are ignored: PNG for lightgraph is an sRGB
 * display format). Writes 8-bit RGB or RGBA, sRGB-encoded, with an sRGB chunk.
 *
 * libpng reports errors by longjmp. Everything that must survive the jump lives in a
 * heap-allocated state, never in automatic variables modified after setjmp.
 */
#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "image_priv.h"

typedef struct png_state {
    char msg[200];
    int in_rows;     /* reading pixel rows: say which row failed */
    png_uint_32 row; /* rows completed so far (of the current pass) */
    int pass;
    FILE *file;
    png_structp png;
    png_infop info;
    unsigned char *buf;
    png_bytep *rows;
} png_state;

static void png_error_fn(png_structp png, png_const_charp msg)
{
    png_state *st = png_get_error_ptr(png);
    snprintf(st->msg, sizeof st->msg, "%s", msg ? msg : "libpng error");
    png_longjmp(png, 1);
}

/* fread with messages that say what happened: libpng's own says only "Read Error". */
static void png_read_fn(png_structp png, png_bytep data, size_t length)
{
    png_state *st = png_get_io_ptr(png);
    if (fread(data, 1, length, st->file) != length)
        png_error(png,
                  ferror(st->file) ? strerror(errno) : "file truncated (unexpected end of file)");
}

static void png_row_fn(png_structp png, png_uint_32 row, int pass)
{
    png_state *st = png_get_error_ptr(png);
    st->row = row;
    st->pass = pass;
}

static void png_warning_fn(png_structp png, png_const_charp msg)
{
    /* Library code does not print; warnings (bad CRC in an ancillary chunk, unknown
     * profile) do not stop a read. */
    (void)png;
    (void)msg;
}

/* Ancillary chunks lightgraph does not use, skipped unread: the compressed ones (iCCP,
 * zTXt, iTXt) are where a small file can ask for a large inflate. */
static const png_byte png_skipped_chunks[] = {
    'i', 'C', 'C', 'P', '\0', 'z', 'T', 'X', 't', '\0', 'i', 'T', 'X', 't', '\0',
    't', 'E', 'X', 't', '\0', 's', 'P', 'L', 'T', '\0', 'e', 'X', 'I', 'f', '\0',
};

int lg_png_read(int fd, uint64_t size, const char *path, lg_image *img, lg_image_read_info *info,
                char *err, size_t errlen)
{
    png_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot read '%s': out of memory", path);
    int rc = LG_OK;

    /* The declared size, from IHDR (always the first chunk, at byte 8), checked before
     * libpng is even set up. */
    unsigned char head[33];
    size_t got = 0;
    while (got < sizeof head) {
        ssize_t n = pread(fd, head + got, sizeof head - got, (off_t)got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot read '%s': %s", path,
                               strerror(errno));
            goto done;
        }
        if (n == 0)
            break;
        got += (size_t)n;
    }
    if (got == 0) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': empty file", path);
        goto done;
    }
    if (got < 8 || png_sig_cmp(head, 0, 8)) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                           "cannot read '%s': not a PNG file (bad signature)", path);
        goto done;
    }
    if (got == sizeof head && !memcmp(head + 12, "IHDR", 4)) {
        uint32_t dw = (uint32_t)head[16] << 24 | (uint32_t)head[17] << 16 |
                      (uint32_t)head[18] << 8 | head[19];
        uint32_t dh = (uint32_t)head[20] << 24 | (uint32_t)head[21] << 16 |
                      (uint32_t)head[22] << 8 | head[23];
        /* after expansion at most RGBA (tRNS may add alpha to any type), 8 or 16 bits; and a
         * row pointer and a filter byte per row */
        uint64_t per = head[24] == 16 ? 8 : 4;
        if (dw != 0 && dh != 0 &&
            (rc = lg_image_check_size(path, dw, dh, per, (uint64_t)dh * 9, err, errlen)) != LG_OK)
            goto done;
    }

    int dfd = dup(fd);
    st->file = dfd >= 0 ? fdopen(dfd, "rb") : NULL;
    if (!st->file) {
        rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot read '%s': %s", path, strerror(errno));
        if (dfd >= 0)
            close(dfd);
        goto done;
    }
    if (fseek(st->file, 8, SEEK_SET) != 0) {
        rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot read '%s': %s", path, strerror(errno));
        goto done;
    }

    st->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, st, png_error_fn, png_warning_fn);
    if (st->png)
        st->info = png_create_info_struct(st->png);
    if (!st->png || !st->info) {
        rc = lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot read '%s': out of memory", path);
        goto done;
    }
    if (setjmp(png_jmpbuf(st->png))) {
        if (st->in_rows)
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': row %u%s: %s", path,
                               (unsigned)st->row, st->pass > 0 ? " (interlaced)" : "", st->msg);
        else
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path, st->msg);
        lg_image_free(img);
        goto done;
    }
    png_set_read_fn(st->png, st, png_read_fn);
    png_set_read_status_fn(st->png, png_row_fn);
    png_set_sig_bytes(st->png, 8);
    /* libpng's own bounds, behind ours: each side within the pixel limit (and PNG's 2^31 - 1),
     * at most 8 MiB for any one ancillary chunk (and its inflated text or profile), at most
     * 256 stored ancillary chunks; the ones lightgraph ignores are skipped unread. */
    {
        uint64_t lim = lg_image_max_pixels();
        png_uint_32 side = lim < 0x7fffffffu ? (png_uint_32)lim : 0x7fffffffu;
        png_set_user_limits(st->png, side, side);
        png_set_chunk_malloc_max(st->png, 8u << 20);
        png_set_chunk_cache_max(st->png, 256);
        png_set_keep_unknown_chunks(st->png, PNG_HANDLE_CHUNK_NEVER, png_skipped_chunks,
                                    (int)(sizeof png_skipped_chunks / 5));
    }
    png_read_info(st->png, st->info);

    png_uint_32 w = png_get_image_width(st->png, st->info);
    png_uint_32 h = png_get_image_height(st->png, st->info);
    int depth = png_get_bit_depth(st->png, st->info);
    int type = png_get_color_type(st->png, st->info);
    int trns = png_get_valid(st->png, st->info, PNG_INFO_tRNS) != 0;
    if ((rc = lg_image_check_size(path, w, h, depth == 16 ? 8 : 4, (uint64_t)h * 9, err, errlen)) !=
        LG_OK)
        goto done;
    /* Deflate compresses at most 1032:1: a header promising far more pixel data than the
     * file could hold is damaged. Refuse it before allocating for it. */
    {
        uint64_t raw = ((uint64_t)png_get_rowbytes(st->png, st->info) + 1) * h;
        if (raw > 1100u * size + (1u << 20)) {
            rc = lg_image_fail(
                err, errlen, LG_ERR_INVALID,
                "cannot read '%s': %ux%u needs more data than a %llu-byte file can hold", path,
                (unsigned)w, (unsigned)h, (unsigned long long)size);
            goto done;
        }
    }
    switch (type) {
    case PNG_COLOR_TYPE_GRAY: info->channels = 1u + (unsigned)trns; break;
    case PNG_COLOR_TYPE_GRAY_ALPHA: info->channels = 2; break;
    case PNG_COLOR_TYPE_PALETTE: info->channels = 3u + (unsigned)trns; break;
    case PNG_COLOR_TYPE_RGB: info->channels = 3u + (unsigned)trns; break;
    default: info->channels = 4; break;
    }
    info->bits = (uint32_t)depth;
    snprintf(info->compression, sizeof info->compression, "deflate");

    /* To 8 or 16-bit RGB or RGBA. */
    png_set_expand(st->png);
    png_set_gray_to_rgb(st->png);
    png_set_interlace_handling(st->png);
    png_read_update_info(st->png, st->info);
    int chans = png_get_channels(st->png, st->info);
    int bits = png_get_bit_depth(st->png, st->info);
    size_t rowbytes = png_get_rowbytes(st->png, st->info);
    if ((chans != 3 && chans != 4) || (bits != 8 && bits != 16) ||
        rowbytes < (size_t)w * (size_t)chans * (size_t)(bits / 8)) {
        rc = lg_image_fail(
            err, errlen, LG_ERR_UNSUPPORTED,
            "cannot read '%s': unexpected layout after expansion (%d channels, %d bits)", path,
            chans, bits);
        goto done;
    }
    st->buf = malloc(rowbytes * h);
    st->rows = malloc(sizeof *st->rows * h);
    if (!st->buf || !st->rows || lg_image_alloc(img, w, h) != LG_OK) {
        rc = lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot read '%s': out of memory for %ux%u",
                           path, (unsigned)w, (unsigned)h);
        goto done;
    }
    for (png_uint_32 y = 0; y < h; y++)
        st->rows[y] = st->buf + rowbytes * y;
    st->in_rows = 1;
    png_read_image(st->png, st->rows);
    st->in_rows = 0;
    png_read_end(st->png, NULL);

    float lut[256];
    for (int i = 0; i < 256; i++)
        lut[i] = lg_srgb_decode((float)i / 255.0f);
    for (png_uint_32 y = 0; y < h; y++) {
        const unsigned char *s = st->rows[y];
        float *d = img->pixels + (size_t)y * w * 4;
        for (png_uint_32 x = 0; x < w; x++, d += 4) {
            if (bits == 8) {
                for (int c = 0; c < 3; c++)
                    d[c] = lut[s[c]];
                d[3] = chans == 4 ? (float)s[3] / 255.0f : 1.0f;
                s += chans;
            } else {
                for (int c = 0; c < 3; c++)
                    d[c] = lg_srgb_decode((float)(s[2 * c] << 8 | s[2 * c + 1]) / 65535.0f);
                d[3] = chans == 4 ? (float)(s[6] << 8 | s[7]) / 65535.0f : 1.0f;
                s += 2 * chans;
            }
        }
    }

done:
    if (st->png)
        png_destroy_read_struct(&st->png, st->info ? &st->info : NULL, NULL);
    if (st->file)
        fclose(st->file);
    free(st->buf);
    free(st->rows);
    free(st);
    if (rc)
        lg_image_free(img);
    return rc;
}

static unsigned char png_unorm8(float v)
{
    if (!(v > 0.0f))
        return 0; /* also NaN */
    if (v >= 1.0f)
        return 255;
    return (unsigned char)lrintf(v * 255.0f);
}

int lg_png_write(FILE *f, const char *path, const lg_image *img, uint32_t channels, char *err,
                 size_t errlen)
{
    png_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot write '%s': out of memory", path);
    int rc = LG_OK;
    uint32_t w = img->width, h = img->height;

    st->png = png_create_write_struct(PNG_LIBPNG_VER_STRING, st, png_error_fn, png_warning_fn);
    if (st->png)
        st->info = png_create_info_struct(st->png);
    st->buf = malloc((size_t)w * channels);
    if (!st->png || !st->info || !st->buf) {
        rc = lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot write '%s': out of memory", path);
        goto done;
    }
    if (setjmp(png_jmpbuf(st->png))) {
        rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': %s", path, st->msg);
        goto done;
    }
    png_init_io(st->png, f);
    /* display output is written often (every render, every sweep step): zlib level 3 is
     * several times faster than the default 6 for files a few percent larger */
    png_set_compression_level(st->png, 3);
    png_set_IHDR(st->png, st->info, w, h, 8,
                 channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(st->png, st->info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(st->png, st->info);
    for (uint32_t y = 0; y < h; y++) {
        const float *s = img->pixels + (size_t)y * w * 4;
        unsigned char *d = st->buf;
        for (uint32_t x = 0; x < w; x++, s += 4) {
            for (int c = 0; c < 3; c++)
                *d++ = png_unorm8(lg_srgb_encode(s[c]));
            if (channels == 4)
                *d++ = png_unorm8(s[3]);
        }
        png_write_row(st->png, st->buf);
    }
    png_write_end(st->png, NULL);

done:
    if (st->png)
        png_destroy_write_struct(&st->png, st->info ? &st->info : NULL);
    free(st->buf);
    free(st);
    return rc;
}
