/*
 * OpenEXR through its C API (openexr.h, OpenEXR 3.1).
 *
 * Reading decodes one float plane per channel and interleaves them afterwards: on 3.1.5,
 * decoding a 4-channel half file straight into one interleaved RGBA buffer swaps
 * channels, while planar decoding is right. What the C API cannot decode (DWAA/DWAB,
 * luminance-chroma and subsampled files) goes to the C++ shim in exr_cxx.cpp, and so do
 * DWAA/DWAB writes, which the C API cannot encode. B44/B44A files with float or uint
 * channels go to the shim both ways too: 3.1.5's C core lays those channels out
 * differently from the C++ library (a test writes with one and reads with the other).
 *
 * All I/O goes through our own read/write callbacks on a file descriptor: that keeps the
 * library's error messages (delivered to a callback with the context) attached to our
 * per-call state, and lets image.c own the temporary file of an atomic write.
 */
#include <errno.h>
#include <fcntl.h>
#include <openexr.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "image_priv.h"

typedef struct exr_io {
    int fd;
    uint64_t size; /* reads: the size lg_image_read found when it opened the file */
    char msg[256]; /* the library's first error message */
} exr_io;

static const char *const exr_compression_names[] = {
    "none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab",
};

static const char *exr_compression_name(int c)
{
    return c >= 0 && c < (int)(sizeof exr_compression_names / sizeof *exr_compression_names)
               ? exr_compression_names[c]
               : "unknown";
}

static void exr_error_cb(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    (void)code;
    if (exr_get_user_data(ctxt, &ud) == EXR_ERR_SUCCESS && ud) {
        exr_io *io = ud;
        if (!io->msg[0])
            snprintf(io->msg, sizeof io->msg, "%s", msg ? msg : "unknown error");
    }
}

static int64_t exr_read_cb(exr_const_context_t ctxt, void *ud, void *buffer, uint64_t sz,
                           uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pread(io->fd, (char *)buffer + done, sz - done, (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            error_cb(ctxt, EXR_ERR_READ_IO, "read error at offset %llu: %s",
                     (unsigned long long)(offset + done), strerror(errno));
            return -1;
        }
        if (n == 0)
            break;
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static int64_t exr_size_cb(exr_const_context_t ctxt, void *ud)
{
    exr_io *io = ud;
    (void)ctxt;
    return (int64_t)io->size; /* the size checked at open, not whatever it is now */
}

static int64_t exr_write_cb(exr_const_context_t ctxt, void *ud, const void *buffer, uint64_t sz,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    uint64_t done = 0;
    while (done < sz) {
        ssize_t n = pwrite(io->fd, (const char *)buffer + done, sz - done, (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            error_cb(ctxt, EXR_ERR_WRITE_IO, "write error: %s", strerror(n < 0 ? errno : ENOSPC));
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

static const char *exr_reason(const exr_io *io, exr_result_t rv)
{
    return io->msg[0] ? io->msg : exr_get_default_error_message(rv);
}

/* ---- reading --------------------------------------------------------------------------------- */

enum { PL_R, PL_G, PL_B, PL_A, PL_Y, PL_COUNT };

static int exr_plane_of(const char *name)
{
    static const char *const names[PL_COUNT] = { "R", "G", "B", "A", "Y" };
    for (int i = 0; i < PL_COUNT; i++)
        if (!strcmp(name, names[i]))
            return i;
    return -1;
}

typedef struct exr_reader {
    const char *path;
    exr_context_t ctx;
    exr_io io;
    int32_t w, h;
    /* One plane per channel we use, in the file's own type (2 bytes for half, 4 for float
     * and uint): the library then only copies, which is much faster than its
     * per-sample conversion; we convert while interleaving. */
    void *planes[PL_COUNT];
    int plane_type[PL_COUNT]; /* exr_pixel_type_t of the file's channel */
    void *discard;            /* where channels we do not use are decoded (see below) */
    exr_decode_pipeline_t dec;
    int dec_ready;
} exr_reader;

/* Decodes one chunk whose top-left pixel is (x0, y0) relative to the data window.
 * Returns an EXR result; on failure the message is in r->io.msg (or the default). */
static exr_result_t exr_decode_chunk(exr_reader *r, const exr_chunk_info_t *ci, int32_t x0,
                                     int32_t y0)
{
    r->io.msg[0] = 0; /* messages belong to the call that failed */
    if (x0 < 0 || y0 < 0 || ci->width <= 0 || ci->height <= 0 || x0 + ci->width > r->w ||
        y0 + ci->height > r->h) {
        snprintf(r->io.msg, sizeof r->io.msg,
                 "chunk %d (%dx%d at %d,%d) lies outside the data window", ci->idx, ci->width,
                 ci->height, x0, y0);
        return EXR_ERR_CORRUPT_CHUNK;
    }
    exr_result_t rv = r->dec_ready ? exr_decoding_update(r->ctx, 0, ci, &r->dec)
                                   : exr_decoding_initialize(r->ctx, 0, ci, &r->dec);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    r->dec_ready = 1;
    for (int c = 0; c < r->dec.channel_count; c++) {
        exr_coding_channel_info_t *ch = &r->dec.channels[c];
        int pl = exr_plane_of(ch->channel_name);
        /* Channels we do not use still get a destination: 3.1.5's C core crashes when a
         * channel is skipped with a NULL pointer (e.g. R, G, B, Z). They all share one
         * plane that nothing reads. */
        uint8_t *plane = (pl < 0 || !r->planes[pl]) ? r->discard : r->planes[pl];
        int32_t size = ch->data_type == EXR_PIXEL_HALF ? 2 : 4;
        ch->decode_to_ptr = plane + ((size_t)y0 * (size_t)r->w + (size_t)x0) * (size_t)size;
        ch->user_pixel_stride = size;
        ch->user_line_stride = size * r->w;
        ch->user_bytes_per_element = (int16_t)size;
        ch->user_data_type = ch->data_type;
    }
    rv = exr_decoding_choose_default_routines(r->ctx, 0, &r->dec);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    return exr_decoding_run(r->ctx, 0, &r->dec);
}

/* Writes plane values, converted to float, into channel `c` (and the `count` - 1 channels
 * after it: Y fills R, G and B) of an RGBA image. */
static void exr_plane_to_rgba(const void *plane, int type, size_t n, float *rgba, int c, int count)
{
    for (size_t i = 0; i < n; i++) {
        float v;
        if (type == EXR_PIXEL_HALF) {
            v = lg_float_from_half(((const uint16_t *)plane)[i]);
        } else if (type == EXR_PIXEL_UINT) {
            v = (float)((const uint32_t *)plane)[i];
        } else {
            memcpy(&v, (const uint8_t *)plane + 4 * i, sizeof v);
        }
        for (int k = 0; k < count; k++)
            rgba[4 * i + (size_t)(c + k)] = v;
    }
}

int lg_exr_read(int fd, uint64_t size, const char *path, lg_image *img, lg_image_read_info *info,
                char *err, size_t errlen)
{
    exr_reader rd;
    memset(&rd, 0, sizeof rd);
    exr_reader *r = &rd;
    r->path = path;
    r->io.fd = fd; /* image.c's: read with pread, never closed here */
    r->io.size = size;
    int rc = LG_OK, use_cxx = 0;
    exr_result_t rv;

    {
        /* Check the magic ourselves: the library's message for a non-EXR file is vague. */
        unsigned char magic[4];
        ssize_t n = pread(r->io.fd, magic, 4, 0);
        static const unsigned char exr_magic[4] = { 0x76, 0x2f, 0x31, 0x01 };
        if (n == 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': empty file", path);
            goto done;
        }
        if (n != 4 || memcmp(magic, exr_magic, 4) != 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                               "cannot read '%s': not an OpenEXR file (bad magic number)", path);
            goto done;
        }
    }

    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_error_cb;
    init.user_data = &r->io;
    init.read_fn = exr_read_cb;
    init.size_fn = exr_size_cb;
    /* no size limit of the library's own: lg_image_check_size below applies lightgraph's,
     * with its message, before anything sized by the header is allocated */
    init.max_image_width = 0;
    init.max_image_height = 0;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    rv = exr_start_read(&r->ctx, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                           exr_reason(&r->io, rv));
        goto done;
    }

    r->io.msg[0] = 0; /* the header parser may have complained about something it then
                       * accepted; later messages belong to later calls */
    exr_storage_t storage;
    exr_compression_t comp;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chl;
    if ((rv = exr_get_storage(r->ctx, 0, &storage)) ||
        (rv = exr_get_compression(r->ctx, 0, &comp)) ||
        (rv = exr_get_data_window(r->ctx, 0, &dw)) || (rv = exr_get_channels(r->ctx, 0, &chl))) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                           exr_reason(&r->io, rv));
        goto done;
    }
    snprintf(info->compression, sizeof info->compression, "%s", exr_compression_name((int)comp));
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED) {
        rc = lg_image_fail(err, errlen, LG_ERR_UNSUPPORTED,
                           "cannot read '%s': deep images are not supported", path);
        goto done;
    }
    int64_t w64 = (int64_t)dw.max.x - dw.min.x + 1, h64 = (int64_t)dw.max.y - dw.min.y + 1;
    if (w64 <= 0 || h64 <= 0 || w64 > INT32_MAX || h64 > INT32_MAX) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                           "cannot read '%s': data window %lldx%lld is empty or too wide", path,
                           (long long)w64, (long long)h64);
        goto done;
    }
    /* The declared size, before a chunk table or a pixel plane is allocated: against the
     * pixel limit, and the memory of the decode (a plane of at most 4 bytes per channel
     * used, R G B A or Y, plus the plane of unused channels; the C++ path needs no more),
     * plus the chunk table, which must also fit in the file. */
    {
        int32_t nchunks = 0;
        if ((rv = exr_get_chunk_count(r->ctx, 0, &nchunks)) != EXR_ERR_SUCCESS || nchunks <= 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                               rv ? exr_reason(&r->io, rv) : "no chunks");
            goto done;
        }
        if ((rc = lg_image_check_size(path, (uint64_t)w64, (uint64_t)h64, 4 * 4 + 4,
                                      (uint64_t)nchunks * 8, err, errlen)) != LG_OK)
            goto done;
        if ((uint64_t)nchunks * 8 > size) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                               "cannot read '%s': file truncated: the table of its %d chunks "
                               "cannot fit in %llu bytes",
                               path, nchunks, (unsigned long long)size);
            goto done;
        }
    }
    r->w = (int32_t)w64;
    r->h = (int32_t)h64;

    /* Which channels, and can the C API decode them? */
    int present[PL_COUNT] = { 0 }, bits = 16, chroma = 0, any_full = 0;
    for (int i = 0; i < chl->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[i];
        if (e->pixel_type != EXR_PIXEL_HALF)
            any_full = 1;
        if (!strcmp(e->name.str, "RY") || !strcmp(e->name.str, "BY"))
            chroma = 1;
        int pl = exr_plane_of(e->name.str);
        if (pl < 0)
            continue;
        present[pl] = 1;
        r->plane_type[pl] = e->pixel_type;
        if (e->pixel_type != EXR_PIXEL_HALF)
            bits = 32;
        if (e->x_sampling != 1 || e->y_sampling != 1)
            chroma = 1; /* subsampled: the C++ API handles those */
    }
    int rgb = present[PL_R] || present[PL_G] || present[PL_B];
    if (!rgb && !present[PL_Y]) {
        char names[160] = "";
        size_t o = 0;
        for (int i = 0; i < chl->num_channels && o < sizeof names - 1; i++)
            o += (size_t)snprintf(names + o, sizeof names - o, "%s%s", i ? ", " : "",
                                  chl->entries[i].name.str);
        rc = lg_image_fail(err, errlen, LG_ERR_UNSUPPORTED,
                           "cannot read '%s': no R, G, B or Y channel (channels: %s)", path,
                           chl->num_channels ? names : "none");
        goto done;
    }
    /* B44/B44A store non-half channels differently in 3.1.5's C core and C++ library
     * (each reads only its own files); the C++ library defines the format. */
    int b44_full = (comp == EXR_COMPRESSION_B44 || comp == EXR_COMPRESSION_B44A) && any_full;
    use_cxx = comp == EXR_COMPRESSION_DWAA || comp == EXR_COMPRESSION_DWAB || chroma || b44_full;
    /* channels: 3 or 4 with colour, 1 (Y) or 2 (Y and A) without */
    info->channels = (rgb ? 3u : 1u) + (unsigned)present[PL_A];
    info->bits = (uint32_t)bits;
    if (rgb)
        present[PL_Y] = 0; /* colour wins over luminance */
    /* Every chunk must be in the file (the library checks each chunk's leader against the
     * file size) before anything sized by the header is allocated: a damaged header must
     * not cost gigabytes. The C++ path gets the same check. */
    if (storage == EXR_STORAGE_SCANLINE) {
        int32_t lpc = 0;
        if ((rv = exr_get_scanlines_per_chunk(r->ctx, 0, &lpc)) || lpc <= 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                               rv ? exr_reason(&r->io, rv) : "bad scanlines per chunk");
            goto done;
        }
        for (int64_t y = 0; y < r->h; y += lpc) {
            exr_chunk_info_t ci;
            r->io.msg[0] = 0; /* messages belong to the call that failed */
            if ((rv = exr_read_scanline_chunk_info(r->ctx, 0, (int)(dw.min.y + y), &ci))) {
                rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                                   "cannot read '%s': scanline block at y=%lld: %s", path,
                                   (long long)(dw.min.y + y), exr_reason(&r->io, rv));
                goto done;
            }
        }
    } else {
        uint32_t tw = 0, th = 0;
        exr_tile_level_mode_t lm;
        exr_tile_round_mode_t rm;
        if ((rv = exr_get_tile_descriptor(r->ctx, 0, &tw, &th, &lm, &rm)) || tw == 0 || th == 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                               rv ? exr_reason(&r->io, rv) : "bad tile size");
            goto done;
        }
        int64_t ntx = (r->w + (int64_t)tw - 1) / tw, nty = (r->h + (int64_t)th - 1) / th;
        for (int64_t ty = 0; ty < nty; ty++)
            for (int64_t tx = 0; tx < ntx; tx++) {
                exr_chunk_info_t ci;
                r->io.msg[0] = 0;
                if ((rv = exr_read_tile_chunk_info(r->ctx, 0, (int)tx, (int)ty, 0, 0, &ci))) {
                    rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                                       "cannot read '%s': tile (%lld, %lld): %s", path,
                                       (long long)tx, (long long)ty, exr_reason(&r->io, rv));
                    goto done;
                }
            }
    }
    if (use_cxx)
        goto done;

    for (int pl = 0; pl < PL_COUNT; pl++) {
        if (!present[pl])
            continue;
        r->planes[pl] = calloc((size_t)r->w * (size_t)r->h,
                               r->plane_type[pl] == EXR_PIXEL_HALF ? 2 : 4);
        if (!r->planes[pl]) {
            rc = lg_image_fail(err, errlen, LG_ERR_NOMEM,
                               "cannot read '%s': out of memory for %dx%d", path, r->w, r->h);
            goto done;
        }
    }

    int unused = 0;
    for (int i = 0; i < chl->num_channels; i++) {
        int pl = exr_plane_of(chl->entries[i].name.str);
        unused |= pl < 0 || !present[pl];
    }
    if (unused) {
        r->discard = calloc((size_t)r->w * (size_t)r->h, sizeof(float));
        if (!r->discard) {
            rc = lg_image_fail(err, errlen, LG_ERR_NOMEM,
                               "cannot read '%s': out of memory for %dx%d", path, r->w, r->h);
            goto done;
        }
    }

    if (storage == EXR_STORAGE_SCANLINE) {
        int32_t lpc = 0;
        if ((rv = exr_get_scanlines_per_chunk(r->ctx, 0, &lpc)) || lpc <= 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                               rv ? exr_reason(&r->io, rv) : "bad scanlines per chunk");
            goto done;
        }
        for (int64_t y = 0; y < r->h; y += lpc) {
            exr_chunk_info_t ci;
            r->io.msg[0] = 0;
            rv = exr_read_scanline_chunk_info(r->ctx, 0, (int)(dw.min.y + y), &ci);
            if (rv == EXR_ERR_SUCCESS)
                rv = exr_decode_chunk(r, &ci, ci.start_x - dw.min.x, ci.start_y - dw.min.y);
            if (rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED) {
                use_cxx = 1;
                goto done;
            }
            if (rv != EXR_ERR_SUCCESS) {
                rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                                   "cannot read '%s': scanline block at y=%lld: %s", path,
                                   (long long)(dw.min.y + y), exr_reason(&r->io, rv));
                goto done;
            }
        }
    } else {
        uint32_t tw = 0, th = 0;
        exr_tile_level_mode_t lm;
        exr_tile_round_mode_t rm;
        if ((rv = exr_get_tile_descriptor(r->ctx, 0, &tw, &th, &lm, &rm)) || tw == 0 || th == 0) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                               rv ? exr_reason(&r->io, rv) : "bad tile size");
            goto done;
        }
        int64_t ntx = (r->w + (int64_t)tw - 1) / tw, nty = (r->h + (int64_t)th - 1) / th;
        for (int64_t ty = 0; ty < nty; ty++) {
            for (int64_t tx = 0; tx < ntx; tx++) {
                exr_chunk_info_t ci;
                r->io.msg[0] = 0;
                rv = exr_read_tile_chunk_info(r->ctx, 0, (int)tx, (int)ty, 0, 0, &ci);
                if (rv == EXR_ERR_SUCCESS)
                    rv = exr_decode_chunk(r, &ci, (int32_t)(tx * tw), (int32_t)(ty * th));
                if (rv == EXR_ERR_FEATURE_NOT_IMPLEMENTED) {
                    use_cxx = 1;
                    goto done;
                }
                if (rv != EXR_ERR_SUCCESS) {
                    rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                                       "cannot read '%s': tile (%lld, %lld): %s", path,
                                       (long long)tx, (long long)ty, exr_reason(&r->io, rv));
                    goto done;
                }
            }
        }
    }

    if (lg_image_alloc(img, (uint32_t)r->w, (uint32_t)r->h) != LG_OK) {
        rc = lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot read '%s': out of memory for %dx%d",
                           path, r->w, r->h);
        goto done;
    }
    {
        size_t n = (size_t)r->w * (size_t)r->h;
        float *d = img->pixels;
        if (r->planes[PL_Y])
            exr_plane_to_rgba(r->planes[PL_Y], r->plane_type[PL_Y], n, d, 0, 3);
        for (int c = 0; c < 4; c++) {
            if (r->planes[c])
                exr_plane_to_rgba(r->planes[c], r->plane_type[c], n, d, c, 1);
            else if (c == 3)
                for (size_t i = 0; i < n; i++)
                    d[4 * i + 3] = 1.0f;
        }
    }

done:
    if (r->dec_ready)
        exr_decoding_destroy(r->ctx, &r->dec);
    if (r->ctx)
        exr_finish(&r->ctx);
    for (int pl = 0; pl < PL_COUNT; pl++)
        free(r->planes[pl]);
    free(r->discard);
    if (use_cxx && rc == LG_OK) {
        lg_image_free(img);
        return lg_exr_cxx_read(fd, size, path, img, info, err, errlen);
    }
    if (rc)
        lg_image_free(img);
    return rc;
}

/* ---- writing --------------------------------------------------------------------------------- */

/* The library's own compressor, which exr_compress_checked calls. */
typedef struct exr_compress_wrap {
    exr_result_t (*compress)(exr_encode_pipeline_t *enc);
} exr_compress_wrap;

/* A chunk whose stored size equals its unpacked size is raw: that is how every reader (the
 * C core's and the C++ library's) tells an uncompressed chunk. OpenEXR 3.1.5's ZIP, ZIPS
 * and PXR24 encoders fall back to the raw bytes only when the compressed stream is larger
 * ("compbufsz > packed_bytes", upstream issue #2306), so a zlib stream of exactly the packed
 * size was stored as it is and read back as raw pixels: one chunk of garbage (16 rows with
 * ZIP). It happens to about 1 chunk in 300 of incompressible content (random or noisy
 * float data) and more often for narrow images, whose chunks are small. Here such a chunk
 * is stored raw, as the format says. */
static exr_result_t exr_compress_checked(exr_encode_pipeline_t *enc)
{
    const exr_compress_wrap *wrap = enc->encoding_user_data;
    exr_result_t rv = wrap->compress(enc);
    if (rv == EXR_ERR_SUCCESS && enc->packed_bytes > 0 &&
        enc->compressed_bytes == enc->packed_bytes && enc->compressed_buffer &&
        enc->packed_buffer && enc->compressed_buffer != enc->packed_buffer)
        memcpy(enc->compressed_buffer, enc->packed_buffer, (size_t)enc->packed_bytes);
    return rv;
}

int lg_exr_write(int fd, const char *tmp_path, const char *path, const lg_image *img,
                 const lg_image_write_opts *opts, char *err, size_t errlen)
{
    (void)tmp_path;
    int half = opts->exr_pixel == LG_EXR_HALF;
    uint32_t channels = opts->channels ? opts->channels : 4;
    /* DWAA/DWAB: the C API cannot encode them. B44/B44A with float channels: the C API
     * writes files that the C++ library (the format's reference) misreads. */
    int b44 = opts->exr_compression == LG_EXR_B44 || opts->exr_compression == LG_EXR_B44A;
    if (opts->exr_compression == LG_EXR_DWAA || opts->exr_compression == LG_EXR_DWAB ||
        (b44 && !half))
        return lg_exr_cxx_write(fd, path, img, half, channels, (int)opts->exr_compression, err,
                                errlen);
    if (img->width > INT32_MAX || img->height > INT32_MAX)
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot write '%s': too large", path);

    static const exr_compression_t ctypes[] = {
        [LG_EXR_ZIP] = EXR_COMPRESSION_ZIP, [LG_EXR_NONE] = EXR_COMPRESSION_NONE,
        [LG_EXR_RLE] = EXR_COMPRESSION_RLE, [LG_EXR_ZIPS] = EXR_COMPRESSION_ZIPS,
        [LG_EXR_PIZ] = EXR_COMPRESSION_PIZ, [LG_EXR_PXR24] = EXR_COMPRESSION_PXR24,
        [LG_EXR_B44] = EXR_COMPRESSION_B44, [LG_EXR_B44A] = EXR_COMPRESSION_B44A,
    };
    exr_io io;
    memset(&io, 0, sizeof io);
    io.fd = fd;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_error_cb;
    init.user_data = &io;
    init.write_fn = exr_write_cb;

    exr_context_t ctx = NULL;
    exr_encode_pipeline_t enc;
    memset(&enc, 0, sizeof enc);
    exr_compress_wrap wrap = { NULL };
    int enc_ready = 0, part = 0;
    int32_t w = (int32_t)img->width, h = (int32_t)img->height;
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctx, part, w, h, ctypes[opts->exr_compression]);
    static const char *const names[4] = { "R", "G", "B", "A" };
    for (uint32_t c = 0; c < channels && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(ctx, part, names[c], half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                             EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctx);
    int32_t lpc = 0;
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_scanlines_per_chunk(ctx, part, &lpc);
    if (rv == EXR_ERR_SUCCESS && lpc <= 0)
        rv = EXR_ERR_UNKNOWN;

    for (int32_t y = 0; y < h && rv == EXR_ERR_SUCCESS; y += lpc) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(ctx, part, y, &ci);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = enc_ready ? exr_encoding_update(ctx, part, &ci, &enc)
                       : exr_encoding_initialize(ctx, part, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS)
            break;
        enc_ready = 1;
        for (int c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            int idx = exr_plane_of(ch->channel_name); /* R G B A are 0..3 */
            ch->encode_from_ptr = (const uint8_t *)(img->pixels + (size_t)y * img->width * 4 +
                                                    (size_t)(idx < 0 ? 0 : idx));
            ch->user_pixel_stride = 4 * (int32_t)sizeof(float);
            ch->user_line_stride = 4 * (int32_t)sizeof(float) * w;
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
        }
        rv = exr_encoding_choose_default_routines(ctx, part, &enc);
        if (rv == EXR_ERR_SUCCESS && enc.compress_fn) {
            wrap.compress = enc.compress_fn;
            enc.encoding_user_data = &wrap;
            enc.compress_fn = exr_compress_checked;
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(ctx, part, &enc);
    }
    if (enc_ready)
        exr_encoding_destroy(ctx, &enc);
    exr_result_t frv = ctx ? exr_finish(&ctx) : EXR_ERR_SUCCESS;
    if (rv == EXR_ERR_SUCCESS)
        rv = frv;
    if (rv != EXR_ERR_SUCCESS)
        return lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s' (%s compression): %s", path,
                             exr_compression_name((int)ctypes[opts->exr_compression]),
                             exr_reason(&io, rv));
    return LG_OK;
}
