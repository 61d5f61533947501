/*
 * Radiance .hdr / .pic (RGBE): read flat, old-style RLE and new-style RLE scanlines; write
 * new-style RLE when the width allows it (8..32767), flat otherwise.
 *
 * The header is read first and the declared size checked (lg_image_check_size); then the
 * whole file is read into memory so that every access is bounds-checked against a known end
 * (the files are small next to their decoded floats).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "image_priv.h"
#include "lightgraph/file.h"

#define HDR_MAX_HEADER (64 * 1024)

typedef struct hdr_reader {
    const char *path;
    const unsigned char *p, *end;
    char *err;
    size_t errlen;
} hdr_reader;

/* Decodes one scanline of `w` RGBE pixels into `out` (w*4 bytes). On error, writes a message
 * naming the scanline (counted from the top of the file, as stored) and returns nonzero. */
static int hdr_read_scanline(hdr_reader *r, uint32_t w, uint32_t y, unsigned char *out)
{
    const unsigned char *p = r->p, *end = r->end;

    if (w >= 8 && w <= 0x7fff && end - p >= 4 && p[0] == 2 && p[1] == 2 && !(p[2] & 0x80)) {
        uint32_t enc_w = (uint32_t)p[2] << 8 | p[3];
        if (enc_w != w)
            return lg_image_fail(
                r->err, r->errlen, LG_ERR_INVALID,
                "cannot read '%s': scanline %u: RLE width %u differs from the image width %u",
                r->path, y, enc_w, w);
        p += 4;
        /* New-style RLE: the four components one after the other, each as runs
         * (count > 128: count-128 copies of one byte) and literals (count bytes). */
        for (int c = 0; c < 4; c++) {
            uint32_t x = 0;
            while (x < w) {
                if (p >= end)
                    goto truncated;
                unsigned code = *p++;
                if (code > 128) {
                    uint32_t run = code - 128;
                    if (x + run > w)
                        return lg_image_fail(
                            r->err, r->errlen, LG_ERR_INVALID,
                            "cannot read '%s': scanline %u: a run of %u overruns the width %u (component %d, x %u)",
                            r->path, y, run, w, c, x);
                    if (p >= end)
                        goto truncated;
                    unsigned char v = *p++;
                    for (uint32_t i = 0; i < run; i++)
                        out[(x + i) * 4 + (uint32_t)c] = v;
                    x += run;
                } else {
                    if (code == 0)
                        return lg_image_fail(
                            r->err, r->errlen, LG_ERR_INVALID,
                            "cannot read '%s': scanline %u: zero-length RLE literal (component %d, x %u)",
                            r->path, y, c, x);
                    if (x + code > w)
                        return lg_image_fail(
                            r->err, r->errlen, LG_ERR_INVALID,
                            "cannot read '%s': scanline %u: %u literal bytes overrun the width %u (component %d, x %u)",
                            r->path, y, code, w, c, x);
                    if ((size_t)(end - p) < code)
                        goto truncated;
                    for (uint32_t i = 0; i < code; i++)
                        out[(x + i) * 4 + (uint32_t)c] = p[i];
                    p += code;
                    x += code;
                }
            }
        }
        r->p = p;
        return 0;
    }

    /* Flat pixels, possibly with old-style RLE: (1,1,1,n) repeats the previous pixel
     * n << shift times, shift growing by 8 with each consecutive repeat code. */
    uint32_t x = 0;
    unsigned shift = 0;
    while (x < w) {
        if (end - p < 4)
            goto truncated;
        if (p[0] == 1 && p[1] == 1 && p[2] == 1) {
            if (x == 0)
                return lg_image_fail(r->err, r->errlen, LG_ERR_INVALID,
                                     "cannot read '%s': scanline %u: repeat code before any pixel",
                                     r->path, y);
            if (shift > 24)
                return lg_image_fail(
                    r->err, r->errlen, LG_ERR_INVALID,
                    "cannot read '%s': scanline %u: too many consecutive repeat codes", r->path, y);
            uint64_t count = (uint64_t)p[3] << shift;
            if (x + count > w)
                return lg_image_fail(
                    r->err, r->errlen, LG_ERR_INVALID,
                    "cannot read '%s': scanline %u: a repeat of %llu overruns the width %u (x %u)",
                    r->path, y, (unsigned long long)count, w, x);
            for (uint64_t i = 0; i < count; i++, x++)
                memcpy(out + x * 4, out + (x - 1) * 4, 4);
            shift += 8;
        } else {
            memcpy(out + x * 4, p, 4);
            x++;
            shift = 0;
        }
        p += 4;
    }
    r->p = p;
    return 0;

truncated:
    return lg_image_fail(r->err, r->errlen, LG_ERR_INVALID,
                         "cannot read '%s': file truncated in scanline %u of the pixel data",
                         r->path, y);
}

/* Parses "-Y H +X W" and its three mirrored variants. Transposed layouts (X first) are
 * valid Radiance but rare; they are refused with a clear message. */
static int hdr_parse_resolution(const char *line, int *flip_y, int *flip_x, uint32_t *w,
                                uint32_t *h)
{
    char sy, ay, sx, ax;
    long hy, wx;
    int n = 0;
    if (sscanf(line, " %c%c %ld %c%c %ld %n", &sy, &ay, &hy, &sx, &ax, &wx, &n) != 6 || line[n])
        return -1;
    if ((sy != '-' && sy != '+') || (sx != '-' && sx != '+'))
        return -1;
    if (ay == 'X' && ax == 'Y')
        return -2;
    if (ay != 'Y' || ax != 'X')
        return -1;
    if (hy <= 0 || wx <= 0 || hy > 0x7fffffff || wx > 0x7fffffff)
        return -3;
    *flip_y = sy == '+'; /* +Y: the first scanline is the bottom row */
    *flip_x = sx == '-'; /* -X: each scanline runs right to left */
    *h = (uint32_t)hy;
    *w = (uint32_t)wx;
    return 0;
}

int lg_hdr_read(int fd, uint64_t size, const char *path, lg_image *img, lg_image_read_info *info,
                char *err, size_t errlen)
{
    /* First the header and the resolution line alone (at most 64 KiB + 256 bytes), so that
     * the declared size is checked before the file, up to the image file limit, is read
     * into memory; then the whole file. */
    size_t len = 0, head_cap = size < HDR_MAX_HEADER + 512 ? (size_t)size : HDR_MAX_HEADER + 512;
    unsigned char *data = malloc(head_cap + 1);
    if (!data)
        return lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot read '%s': out of memory", path);
    while (len < head_cap) {
        ssize_t n = pread(fd, data + len, head_cap - len, (off_t)len);
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0) {
            int e = errno;
            free(data);
            return lg_image_fail(err, errlen, LG_ERR_IO, "cannot read '%s': %s", path, strerror(e));
        }
        if (n == 0)
            break;
        len += (size_t)n;
    }
    int rc = LG_OK;

    info->channels = 3;
    info->bits = 8;
    snprintf(info->compression, sizeof info->compression, "none");

    const unsigned char *p = data, *end = data + len;
    unsigned char *line = NULL;
    double exposure = 1.0, colorcorr[3] = { 1.0, 1.0, 1.0 };

    if (len == 0) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': empty file", path);
        goto done;
    }
    if (len < 2 || p[0] != '#' || p[1] != '?') {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                           "cannot read '%s': not a Radiance HDR file (no '#?' signature)", path);
        goto done;
    }

    /* Header: lines up to an empty one. */
    char text[1024];
    int lineno = 0, seen_blank = 0;
    while (!seen_blank) {
        const unsigned char *nl = memchr(p, '\n', (size_t)(end - p));
        if (!nl || nl - data > HDR_MAX_HEADER) {
            rc = lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': %s", path,
                               nl || len < size ? "header longer than 64 KiB"
                                                : "file ends inside the header");
            goto done;
        }
        size_t n = (size_t)(nl - p);
        lineno++;
        if (n == 0 || (n == 1 && p[0] == '\r')) {
            seen_blank = 1;
        } else if (lineno > 1 && p[0] != '#') {
            snprintf(text, sizeof text, "%.*s", (int)(n < sizeof text - 1 ? n : sizeof text - 1),
                     p);
            /* trailing blanks and the \r of files written with CRLF */
            for (size_t k = strlen(text);
                 k > 0 && (text[k - 1] == ' ' || text[k - 1] == '\t' || text[k - 1] == '\r'); k--)
                text[k - 1] = 0;
            if (!strncmp(text, "FORMAT=", 7)) {
                if (strcmp(text + 7, "32-bit_rle_rgbe") != 0) {
                    rc = lg_image_fail(
                        err, errlen, LG_ERR_UNSUPPORTED,
                        "cannot read '%s': header line %d: unsupported format '%s' (only 32-bit_rle_rgbe)",
                        path, lineno, text + 7);
                    goto done;
                }
            } else if (!strncmp(text, "EXPOSURE=", 9)) {
                char *e;
                double v = strtod(text + 9, &e);
                if (!(v > 0.0) || !isfinite(v)) {
                    rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                                       "cannot read '%s': header line %d: bad EXPOSURE '%s'", path,
                                       lineno, text + 9);
                    goto done;
                }
                exposure *= v;
            } else if (!strncmp(text, "COLORCORR=", 10)) {
                double v[3];
                if (sscanf(text + 10, "%lf %lf %lf", &v[0], &v[1], &v[2]) != 3 || !(v[0] > 0) ||
                    !(v[1] > 0) || !(v[2] > 0) || !isfinite(v[0] + v[1] + v[2])) {
                    rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                                       "cannot read '%s': header line %d: bad COLORCORR '%s'", path,
                                       lineno, text + 10);
                    goto done;
                }
                for (int i = 0; i < 3; i++)
                    colorcorr[i] *= v[i];
            }
            /* Other variables (PRIMARIES, PIXASPECT, VIEW, SOFTWARE...) do not change
             * the pixel values. */
        }
        p = nl + 1;
    }

    /* Resolution line. */
    const unsigned char *nl = memchr(p, '\n', (size_t)(end - p) < 256 ? (size_t)(end - p) : 256);
    if (!nl) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                           "cannot read '%s': missing resolution line after the header", path);
        goto done;
    }
    snprintf(text, sizeof text, "%.*s", (int)(nl - p), p);
    p = nl + 1;
    int flip_y = 0, flip_x = 0;
    uint32_t w = 0, h = 0;
    int pr = hdr_parse_resolution(text, &flip_y, &flip_x, &w, &h);
    if (pr == -2) {
        rc = lg_image_fail(
            err, errlen, LG_ERR_UNSUPPORTED,
            "cannot read '%s': transposed orientation '%s' is not supported (expected '-Y H +X W')",
            path, text);
        goto done;
    }
    if (pr != 0) {
        rc = lg_image_fail(err, errlen, LG_ERR_INVALID,
                           "cannot read '%s': bad resolution line '%s' (expected '-Y H +X W')",
                           path, text);
        goto done;
    }
    /* the declared size against the pixel limit and the memory: one scanline of RGBE
     * besides the rgba32f result (the file itself is in memory already) */
    if ((rc = lg_image_check_size(path, w, h, 0, (uint64_t)w * 4 + size, err, errlen)) != LG_OK)
        goto done;
    /* Every scanline takes at least 4 bytes: refuse absurd sizes before allocating. */
    size_t offset = (size_t)(p - data);
    if (size - offset < (uint64_t)h * 4) {
        rc =
            lg_image_fail(err, errlen, LG_ERR_INVALID,
                          "cannot read '%s': file truncated: %u scanlines cannot fit in %llu bytes",
                          path, h, (unsigned long long)(size - offset));
        goto done;
    }
    /* Now the whole file (its size was checked against the image file limit at open). */
    {
        char why[200];
        free(data);
        data = lg_file_read_fd(fd, size, &len, why, sizeof why);
        if (!data) {
            rc = lg_image_fail(err, errlen, errno == ENOMEM ? LG_ERR_NOMEM : LG_ERR_IO,
                               "cannot read '%s': %s", path, why);
            goto done;
        }
        if (len < offset) {
            rc = lg_image_fail(err, errlen, LG_ERR_IO,
                               "cannot read '%s': it shrank while being "
                               "read",
                               path);
            goto done;
        }
        p = data + offset;
        end = data + len;
    }

    line = malloc((size_t)w * 4);
    rc = line ? lg_image_alloc(img, w, h) : LG_ERR_NOMEM;
    if (rc) {
        rc = lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot read '%s': out of memory for %ux%u",
                           path, w, h);
        goto done;
    }

    hdr_reader r = { path, p, end, err, errlen };
    int rle_lines = 0;
    float scale[3];
    for (int i = 0; i < 3; i++)
        scale[i] = (float)(1.0 / (exposure * colorcorr[i]));
    for (uint32_t y = 0; y < h; y++) {
        if (r.end - r.p >= 4 && r.p[0] == 2 && r.p[1] == 2 && !(r.p[2] & 0x80) && w >= 8 &&
            w <= 0x7fff)
            rle_lines++;
        if (hdr_read_scanline(&r, w, y, line)) {
            rc = LG_ERR_INVALID;
            goto done;
        }
        uint32_t row = flip_y ? h - 1 - y : y;
        float *dst = img->pixels + (size_t)row * w * 4;
        for (uint32_t x = 0; x < w; x++) {
            uint32_t col = flip_x ? w - 1 - x : x;
            float *px = dst + (size_t)col * 4;
            lg_rgbe_decode(line + (size_t)x * 4, px);
            for (int i = 0; i < 3; i++)
                px[i] *= scale[i];
            px[3] = 1.0f;
        }
    }
    if (rle_lines)
        snprintf(info->compression, sizeof info->compression, "rle");
    rc = LG_OK;

done:
    if (rc)
        lg_image_free(img);
    free(line);
    free(data);
    return rc;
}

/* ---- writing --------------------------------------------------------------------------------- */

/* Appends one component (n bytes, stride 1) as new-style RLE: runs of 4 or more identical
 * bytes as (128 + count, byte), the rest as literals of up to 128 bytes. */
static size_t hdr_rle_component(const unsigned char *d, uint32_t n, unsigned char *out)
{
    size_t o = 0;
    uint32_t i = 0;
    while (i < n) {
        uint32_t run = 1;
        while (i + run < n && run < 127 && d[i + run] == d[i])
            run++;
        if (run >= 4) {
            out[o++] = (unsigned char)(128 + run);
            out[o++] = d[i];
            i += run;
            continue;
        }
        uint32_t j = i;
        while (j < n && j - i < 128) {
            uint32_t r = 1;
            while (j + r < n && r < 4 && d[j + r] == d[j])
                r++;
            if (r >= 4)
                break;
            j++;
        }
        out[o++] = (unsigned char)(j - i);
        memcpy(out + o, d + i, j - i);
        o += j - i;
        i = j;
    }
    return o;
}

int lg_hdr_write(FILE *f, const char *path, const lg_image *img, char *err, size_t errlen)
{
    uint32_t w = img->width, h = img->height;
    int rle = w >= 8 && w <= 0x7fff;
    unsigned char *rgbe = malloc((size_t)w * 4);
    unsigned char *comp = malloc(w);
    /* worst case per component: a count byte per 128 literals */
    unsigned char *out = malloc(4 + 4 * ((size_t)w + w / 128 + 2));
    int rc = LG_OK;
    if (!rgbe || !comp || !out) {
        rc = lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot write '%s': out of memory", path);
        goto done;
    }
    if (fprintf(f, "#?RADIANCE\n# written by lightgraph\nFORMAT=32-bit_rle_rgbe\n\n-Y %u +X %u\n",
                h, w) < 0)
        goto io;
    for (uint32_t y = 0; y < h; y++) {
        const float *src = img->pixels + (size_t)y * w * 4;
        for (uint32_t x = 0; x < w; x++)
            lg_rgbe_encode(src + (size_t)x * 4, rgbe + (size_t)x * 4);
        size_t o = 0;
        if (rle) {
            out[o++] = 2;
            out[o++] = 2;
            out[o++] = (unsigned char)(w >> 8);
            out[o++] = (unsigned char)(w & 0xff);
            for (int c = 0; c < 4; c++) {
                for (uint32_t x = 0; x < w; x++)
                    comp[x] = rgbe[(size_t)x * 4 + (uint32_t)c];
                o += hdr_rle_component(comp, w, out + o);
            }
            if (fwrite(out, 1, o, f) != o)
                goto io;
        } else if (fwrite(rgbe, 4, w, f) != w) {
            goto io;
        }
    }
    goto done;
io:
    rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
done:
    free(rgbe);
    free(comp);
    free(out);
    return rc;
}
