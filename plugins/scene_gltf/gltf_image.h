/*
 * gltf_image.h: PNG and JPEG images to RGBA8, for the textures of a glTF model.
 *
 * The decoders take the encoded bytes (a file the loader read, a bufferView, a data: URI)
 * and give the pixels as stored, 4 bytes per pixel, rows top to bottom: no colour or gamma
 * conversion (a colour texture keeps its sRGB values; the sampler decodes them). What is
 * accepted (README.md, "Textures"):
 *   PNG (libpng): grey, grey + alpha, RGB, RGBA, palette (with or without tRNS), 1 to 16
 *       bits per channel (16 bits are cut to their high byte), interlaced or not. Grey is
 *       copied to R, G and B; a missing alpha is 255 (tRNS transparency included).
 *   JPEG (libjpeg-turbo): greyscale, YCbCr and RGB, baseline or progressive; CMYK and YCCK
 *       (Adobe's print JPEGs) are refused: glTF allows only RGB(A) images. Alpha is 255.
 * The format is told by the bytes' signature, not by the mimeType or the file name.
 *
 * Every failure (a corrupt or truncated stream, a CRC error, a size over the limit) comes
 * back as a message; libpng's and libjpeg's errors are caught with setjmp/longjmp and their
 * warnings about corrupt data are errors too (a truncated JPEG would otherwise decode to
 * grey). Nothing prints and nothing exits. The size in the header is checked against
 * `max_pixels` before any pixel memory is allocated.
 */
#ifndef LG_GLTF_IMAGE_H
#define LG_GLTF_IMAGE_H

#include <stddef.h>
#include <stdint.h>

/* Decodes a PNG or JPEG held in bytes[0..size). On success returns 0, *rgba is a malloc'd
 * width * height * 4 bytes (the caller frees it), *width and *height at least 1 with
 * width * height <= max_pixels. Otherwise returns -1, *rgba is NULL and err says why
 * ("not a PNG or JPEG file (it starts with 47 49 46 38)", "PNG: IDAT: CRC error",
 * "JPEG: premature end of data segment", "1000000 x 1000000 pixels, more than the
 * 67108864 accepted"). */
int lg_gltf_image_decode(const uint8_t *bytes, size_t size, uint64_t max_pixels, uint32_t *width,
                         uint32_t *height, uint8_t **rgba, char *err, size_t err_size);

#endif
