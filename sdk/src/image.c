/*
 * Format dispatch (lg_image_read and lg_image_write choose a codec by the file's extension)
 * and the atomic write every format goes through. Images in memory and the limits are in
 * image_alloc.c, below the codecs: image.c calls the codecs and image_alloc.c, the codecs
 * call image_alloc.c only.
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "image_priv.h"
#include "lightgraph/file.h"

lg_file_format lg_image_format_from_path(const char *path)
{
    if (!path)
        return LG_FILE_UNKNOWN;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    if (!dot || dot == base)
        return LG_FILE_UNKNOWN; /* no extension, or a hidden file's name */
    if (!strcasecmp(dot, ".exr"))
        return LG_FILE_EXR;
    if (!strcasecmp(dot, ".hdr") || !strcasecmp(dot, ".pic"))
        return LG_FILE_HDR;
    if (!strcasecmp(dot, ".png"))
        return LG_FILE_PNG;
    return LG_FILE_UNKNOWN;
}

/* ---- reading --------------------------------------------------------------------------------- */

int lg_image_read(const char *path, unsigned flags, lg_image *img, lg_image_read_info *info,
                  char *err, size_t errlen)
{
    if (err && errlen)
        err[0] = 0;
    if (!img)
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "lg_image_read: img is NULL");
    memset(img, 0, sizeof *img);
    lg_image_read_info local;
    if (!info)
        info = &local;
    memset(info, 0, sizeof *info);
    if (!path || !path[0])
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "lg_image_read: empty path");
    if (flags & ~(unsigned)LG_READ_RADIANCE)
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot read '%s': unknown flags 0x%x",
                             path, flags & ~(unsigned)LG_READ_RADIANCE);

    info->format = lg_image_format_from_path(path);
    if (info->format == LG_FILE_UNKNOWN)
        return lg_image_fail(
            err, errlen, LG_ERR_UNSUPPORTED,
            "cannot read '%s': unknown extension (expected .exr, .hdr, .pic or .png)", path);

    /* Opened once, here: regular files only (a FIFO would block a decoder, a device such as
     * /dev/zero would feed it without end), the size checked before a byte is read. Every
     * decoder reads this descriptor; none opens the path again, so the file checked is the
     * file decoded. */
    uint64_t size = 0;
    char why[256];
    uint64_t file_limit = lg_image_max_file_bytes();
    int fd = lg_file_open(path, file_limit, &size, why, sizeof why);
    if (fd < 0) {
        int e = errno;
        if (e == EFBIG)
            return lg_image_fail(err, errlen, LG_ERR_INVALID,
                                 "cannot read '%s': %s for images (32 bytes per pixel of the "
                                 "%llu-pixel limit; raise it with LIGHTGRAPH_MAX_PIXELS=N or "
                                 "--max-pixels N)",
                                 path, why, (unsigned long long)lg_image_max_pixels());
        return lg_image_fail(err, errlen, e == ENOENT ? LG_ERR_NOTFOUND : LG_ERR_IO,
                             "cannot read '%s': %s", path, why);
    }

    int rc;
    switch (info->format) {
    case LG_FILE_EXR: rc = lg_exr_read(fd, size, path, img, info, err, errlen); break;
    case LG_FILE_HDR: rc = lg_hdr_read(fd, size, path, img, info, err, errlen); break;
    default: rc = lg_png_read(fd, size, path, img, info, err, errlen); break;
    }
    close(fd);
    if (rc != LG_OK) {
        lg_image_free(img);
        return rc;
    }

    /* Counted as found, before any clamping. */
    size_t n = (size_t)img->width * img->height;
    float *p = img->pixels;
    for (size_t i = 0; i < n; i++, p += 4) {
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]) || !isfinite(p[3]))
            info->nonfinite++;
        if (flags & LG_READ_RADIANCE) {
            int neg = 0;
            for (int c = 0; c < 4; c++)
                if (p[c] < 0.0f) {
                    p[c] = 0.0f;
                    neg = 1;
                }
            info->negatives_clamped += (uint64_t)neg;
        }
    }
    return LG_OK;
}

/* ---- writing --------------------------------------------------------------------------------- */

/* The mode a newly created file would get (0666 & ~umask). umask() itself cannot be read
 * without setting it, which races with other threads; Linux shows it in /proc. */
static mode_t new_file_mode(void)
{
    mode_t mask = 022;
    FILE *f = fopen("/proc/self/status", "re");
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f)) {
            unsigned m;
            if (sscanf(line, "Umask: %o", &m) == 1) {
                mask = (mode_t)m;
                break;
            }
        }
        fclose(f);
    }
    return 0666 & ~mask;
}

static int sync_and_close_file(FILE *f, const char *path, char *err, size_t errlen, int rc)
{
    if (rc == LG_OK && (fflush(f) != 0 || ferror(f)))
        rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    if (rc == LG_OK && fsync(fileno(f)) != 0)
        rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': fsync: %s", path,
                           strerror(errno));
    if (fclose(f) != 0 && rc == LG_OK)
        rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    return rc;
}

int lg_image_write(const char *path, const lg_image *img, const lg_image_write_opts *opts,
                   char *err, size_t errlen)
{
    if (err && errlen)
        err[0] = 0;
    if (!path || !path[0])
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "lg_image_write: empty path");
    if (!img || !img->pixels || img->width == 0 || img->height == 0)
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot write '%s': empty image", path);
    if ((uint64_t)img->width * img->height > lg_image_alloc_cap())
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot write '%s': %ux%u is too large",
                             path, img->width, img->height);
    lg_image_write_opts defaults;
    memset(&defaults, 0, sizeof defaults);
    if (!opts)
        opts = &defaults;
    if (opts->channels != 0 && opts->channels != 3 && opts->channels != 4)
        return lg_image_fail(err, errlen, LG_ERR_INVALID,
                             "cannot write '%s': channels must be 3 or 4, not %u", path,
                             opts->channels);
    if ((unsigned)opts->exr_pixel > LG_EXR_FLOAT)
        return lg_image_fail(err, errlen, LG_ERR_INVALID,
                             "cannot write '%s': bad EXR pixel type %d", path,
                             (int)opts->exr_pixel);
    if ((unsigned)opts->exr_compression > LG_EXR_DWAB)
        return lg_image_fail(err, errlen, LG_ERR_INVALID,
                             "cannot write '%s': bad EXR compression %d", path,
                             (int)opts->exr_compression);

    lg_file_format format = lg_image_format_from_path(path);
    if (format == LG_FILE_UNKNOWN)
        return lg_image_fail(
            err, errlen, LG_ERR_UNSUPPORTED,
            "cannot write '%s': unknown extension (expected .exr, .hdr, .pic or .png)", path);

    /* The temporary file sits in the target's directory so that rename() is atomic. */
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    const char *base = slash ? slash + 1 : path;
    if (!base[0])
        return lg_image_fail(err, errlen, LG_ERR_INVALID, "cannot write '%s': no file name", path);
    size_t tmplen = dirlen + strlen(base) + 16;
    char *tmp = malloc(tmplen);
    if (!tmp)
        return lg_image_fail(err, errlen, LG_ERR_NOMEM, "cannot write '%s': out of memory", path);
    /* ".name.XXXXXX", the name cut short enough to stay within NAME_MAX */
    snprintf(tmp, tmplen, "%.*s.%.200s.XXXXXX", (int)dirlen, path, base);
    int fd = mkostemp(tmp, O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        free(tmp);
        return lg_image_fail(err, errlen, e == ENOENT ? LG_ERR_NOTFOUND : LG_ERR_IO,
                             "cannot write '%s': cannot create a file in its directory: %s", path,
                             strerror(e));
    }
    (void)fchmod(fd, new_file_mode());

    int rc;
    uint32_t channels = opts->channels ? opts->channels : 4;
    if (format == LG_FILE_EXR) {
        rc = lg_exr_write(fd, tmp, path, img, opts, err, errlen);
        if (rc == LG_OK && fsync(fd) != 0)
            rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': fsync: %s", path,
                               strerror(errno));
        if (close(fd) != 0 && rc == LG_OK)
            rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': %s", path,
                               strerror(errno));
    } else {
        FILE *f = fdopen(fd, "wb");
        if (!f) {
            rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': %s", path,
                               strerror(errno));
            close(fd);
        } else {
            if (format == LG_FILE_PNG)
                rc = lg_png_write(f, path, img, channels, err, errlen);
            else
                rc = lg_hdr_write(f, path, img, err, errlen);
            rc = sync_and_close_file(f, path, err, errlen, rc);
        }
    }

    if (rc == LG_OK && rename(tmp, path) != 0)
        rc = lg_image_fail(err, errlen, LG_ERR_IO, "cannot write '%s': rename from '%s': %s", path,
                           tmp, strerror(errno));
    /* The directory is not fsynced: the rename is atomic either way, and a second fsync
     * per image doubles the cost of writing many small files. */
    if (rc != LG_OK)
        unlink(tmp);
    free(tmp);
    return rc;
}
