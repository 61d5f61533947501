/*
 * sdk/src/image_priv.h: what the image files of liblightgraph share (private, not installed).
 *
 * image.c dispatches to one reader and one writer per format. Readers fill `img` (the
 * caller frees it on success; on failure the reader leaves it empty) and the format-specific
 * fields of `info` (channels, bits, compression); image.c counts nonfinite pixels and applies
 * LG_READ_RADIANCE afterwards. Writers receive an open, empty temporary file (`fd`, whose
 * name is `tmp_path`) and report errors against `path`, the name the user asked for;
 * image.c fsyncs, closes and renames it, or unlinks it on failure.
 */
#ifndef LG_IMAGE_PRIV_H
#define LG_IMAGE_PRIV_H

#include <stdarg.h>
#include <stdio.h>

#include "lightgraph/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest image the readers accept, in pixels (the limit lg_image_alloc enforces). */
#define LG_IMAGE_MAX_PIXELS (1ull << 28)

/* Writes a formatted message into err (when not NULL) and returns `code`. */
int lg_image_fail(char *err, size_t errlen, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* Reads a whole file into memory (for the formats parsed by hand). *data is malloc'd. */
int lg_image_slurp(const char *path, unsigned char **data, size_t *len, char *err,
                   size_t errlen);

int lg_hdr_read(const char *path, lg_image *img, lg_image_read_info *info, char *err,
                size_t errlen);
int lg_hdr_write(FILE *f, const char *path, const lg_image *img, char *err, size_t errlen);

int lg_png_read(const char *path, lg_image *img, lg_image_read_info *info, char *err,
                size_t errlen);
int lg_png_write(FILE *f, const char *path, const lg_image *img, uint32_t channels, char *err,
                 size_t errlen);

int lg_exr_read(const char *path, lg_image *img, lg_image_read_info *info, char *err,
                size_t errlen);
int lg_exr_write(int fd, const char *tmp_path, const char *path, const lg_image *img,
                 const lg_image_write_opts *opts, char *err, size_t errlen);

/* The C++ shim (exr_cxx.cpp): OpenEXR's C++ API, for what the C API cannot do. Never
 * throws. lg_exr_cxx_read fills channels and bits in `info` (and compression). */
int lg_exr_cxx_read(const char *path, lg_image *img, lg_image_read_info *info, char *err,
                    size_t errlen);
/* Writes to the open, empty file `fd` (named `path` in messages). half: 1 for half, 0 for
 * float; channels: 3 or 4; compression: an lg_exr_compression value. */
int lg_exr_cxx_write(int fd, const char *path, const lg_image *img, int half,
                     uint32_t channels, int compression, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif
#endif
