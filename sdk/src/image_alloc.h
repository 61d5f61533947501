/*
 * sdk/src/image_alloc.h: the bottom of liblightgraph's image files (private, not installed).
 *
 * The image files stack in three layers, each calling only the ones below it:
 *
 *   image.c        format dispatch (lg_image_read/write pick a codec), the atomic write
 *   exr.c, exr_cxx.cpp, hdr.c, png.c   the codecs (image_priv.h declares their entry points)
 *   image_alloc.c  images in memory and the limits (this header, and lightgraph/image.h's
 *                  lg_image_alloc, lg_image_free, lg_image_max_pixels, lg_memory_available...)
 *
 * A codec, or any other SDK file that only needs images in memory (compare.c), includes this
 * header and never calls a function defined in image.c.
 */
#ifndef LG_IMAGE_ALLOC_H
#define LG_IMAGE_ALLOC_H

#include <stdarg.h>
#include <stdint.h>

#include "lightgraph/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest image the readers accept, in pixels (the limit lg_image_alloc enforces). */
#define LG_IMAGE_MAX_PIXELS (1ull << 28)

/* Writes a formatted message into err (when not NULL) and returns `code`. */
int lg_image_fail(char *err, size_t errlen, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* The larger of LG_IMAGE_MAX_PIXELS and lg_image_max_pixels(): what lg_image_alloc accepts. */
uint64_t lg_image_alloc_cap(void);

/* The checks every reader makes once it knows the declared size, before it allocates or
 * decodes: w x h (overflow-checked) against lg_image_max_pixels(), then the memory the decode
 * needs, (16 + codec_per_pixel) bytes per pixel plus codec_fixed, against what the machine
 * can give (lightgraph/image.h). Returns LG_OK, or an error naming the file, the declared
 * size and the limit met (and how to raise the pixel limit). */
int lg_image_check_size(const char *path, uint64_t w, uint64_t h, uint64_t codec_per_pixel,
                        uint64_t codec_fixed, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif
#endif
