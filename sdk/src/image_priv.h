/*
 * sdk/src/image_priv.h: the codecs' entry points (private, not installed).
 *
 * image.c dispatches to one reader and one writer per format, declared here and defined in
 * hdr.c, png.c, exr.c (and exr_cxx.cpp, which exr.c calls). Readers fill `img` (the
 * caller frees it on success; on failure the reader leaves it empty) and the format-specific
 * fields of `info` (channels, bits, compression); image.c counts nonfinite pixels and applies
 * LG_READ_RADIANCE afterwards. Writers receive an open, empty temporary file (`fd`, whose
 * name is `tmp_path`) and report errors against `path`, the name the user asked for;
 * image.c fsyncs, closes and renames it, or unlinks it on failure.
 *
 * The codecs call down into image_alloc.c only (image_alloc.h: allocation, limits, errors),
 * never into image.c; see image_alloc.h for the layers.
 */
#ifndef LG_IMAGE_PRIV_H
#define LG_IMAGE_PRIV_H

#include <stdio.h>

#include "image_alloc.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Readers read the open, regular file `fd` of `size` bytes (lg_image_read opened it and
 * closes it; a reader may read it from any offset but never closes it), named `path` in
 * messages. */
int lg_hdr_read(int fd, uint64_t size, const char *path, lg_image *img, lg_image_read_info *info,
                char *err, size_t errlen);
int lg_hdr_write(FILE *f, const char *path, const lg_image *img, char *err, size_t errlen);

int lg_png_read(int fd, uint64_t size, const char *path, lg_image *img, lg_image_read_info *info,
                char *err, size_t errlen);
int lg_png_write(FILE *f, const char *path, const lg_image *img, uint32_t channels, char *err,
                 size_t errlen);

int lg_exr_read(int fd, uint64_t size, const char *path, lg_image *img, lg_image_read_info *info,
                char *err, size_t errlen);
int lg_exr_write(int fd, const char *tmp_path, const char *path, const lg_image *img,
                 const lg_image_write_opts *opts, char *err, size_t errlen);

/* The C++ shim (exr_cxx.cpp): OpenEXR's C++ API, for what the C API cannot do. Never
 * throws. lg_exr_cxx_read reads the open file `fd` as the C readers do (through an
 * Imf::IStream on the descriptor, never by name) and fills channels and bits in `info` (and
 * compression). */
int lg_exr_cxx_read(int fd, uint64_t size, const char *path, lg_image *img,
                    lg_image_read_info *info, char *err, size_t errlen);
/* Writes to the open, empty file `fd` (named `path` in messages). half: 1 for half, 0 for
 * float; channels: 3 or 4; compression: an lg_exr_compression value. */
int lg_exr_cxx_write(int fd, const char *path, const lg_image *img, int half, uint32_t channels,
                     int compression, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif
#endif
