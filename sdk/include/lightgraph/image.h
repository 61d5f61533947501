/*
 * lightgraph/image.h: images in memory and in files (SDK helper library, liblightgraph).
 *
 * In memory an image is always RGBA float32, row-major, top row first, linear unless
 * said otherwise. Files: OpenEXR (half and float, RGB and RGBA, every compression
 * OpenEXR 3 supports, DWAA/DWAB included), Radiance .hdr (RGBE, flat and RLE) and PNG
 * (8-bit, sRGB-encoded, for display). The format is chosen by the file name's extension
 * (.exr, .hdr or .pic, .png), case-insensitively.
 *
 * What reading accepts, per format:
 *   - EXR: the first part of a file, scanline or tiled (level 0 of mipmaps), any data
 *     window (the image is the data window), channels R, G, B, A (missing colour channels
 *     read as 0), or Y (grey) with optional A, or luminance-chroma (Y, RY, BY); half, float
 *     and uint. Other channels are ignored; deep files are refused.
 *   - HDR: "#?" signature, FORMAT=32-bit_rle_rgbe, flat, old-style and new-style RLE
 *     scanlines, resolution "-Y H +X W" and its mirrored forms (+Y, -X; transposed forms
 *     are refused). EXPOSURE and COLORCORR are divided out, giving the values before the
 *     program that wrote them scaled them.
 *   - PNG: 1 to 16 bits, grey, grey+alpha, RGB, RGBA, palette (with tRNS), interlaced;
 *     colour is decoded as sRGB (gAMA and iCCP are ignored), alpha is linear.
 *
 * Errors. Every function that can fail returns 0 or a negative LG_ERR_* code and writes a
 * message naming the file and the reason into `err` (`errlen` bytes, always terminated)
 * when `err` is not NULL.
 *
 * Writes are atomic: the data goes to a temporary file beside the target, which is
 * renamed into place only when complete. A failure never leaves a partial file.
 *
 * Thread-safety: all functions are reentrant; distinct images may be used from distinct
 * threads.
 */
#ifndef LIGHTGRAPH_IMAGE_H
#define LIGHTGRAPH_IMAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An RGBA float image. `pixels` holds width*height*4 floats and belongs to whoever filled
 * the struct through lg_image_alloc or lg_image_read: free it with lg_image_free. */
typedef struct lg_image {
    uint32_t width, height;
    float *pixels;
} lg_image;

/* Allocates a zeroed image. Returns LG_OK or LG_ERR_NOMEM / LG_ERR_INVALID (zero or
 * absurd sizes: more than 2^28 pixels, or the pixel limit below when it is higher). */
LG_API int lg_image_alloc(lg_image *img, uint32_t width, uint32_t height);
/* Frees the pixels and zeroes the struct. Accepts NULL and an already freed image. */
LG_API void lg_image_free(lg_image *img);

typedef enum lg_file_format {
    LG_FILE_UNKNOWN = 0,
    LG_FILE_EXR,
    LG_FILE_HDR,
    LG_FILE_PNG,
} lg_file_format;

/* The format the extension of `path` names, or LG_FILE_UNKNOWN. */
LG_API lg_file_format lg_image_format_from_path(const char *path);

/* What a read found, besides the pixels. */
typedef struct lg_image_read_info {
    lg_file_format format;
    uint32_t channels;          /* channels in the file: 3 (RGB), 4 (RGBA), 1 (Y),
                                 * 2 (Y and alpha) */
    uint32_t bits;              /* 16 (half), 32 (float or uint), 8 (RGBE), PNG: 1..16 */
    char compression[16];       /* "none", "rle", "zip", "piz", "dwab", ... */
    uint64_t negatives_clamped; /* radiance reads: pixels with a negative channel, set to 0 */
    uint64_t nonfinite;         /* pixels with a NaN or Inf channel, as found */
    uint32_t reserved[8];
} lg_image_read_info;

enum {
    /* The image is radiance (light probes, renders): negative values, which lossy
     * compressions (DWA, B44) produce, are clamped to zero (in all four channels) and the
     * pixels counted in negatives_clamped. Without it, pixels are returned as stored.
     * NaN and Inf are never changed; nonfinite counts them before any clamping. */
    LG_READ_RADIANCE = 1u << 0,
};

/* The pixel limit. Every read checks the size a file declares (width x height, from its
 * header, before a pixel is decoded or a byte of pixel memory allocated) against this limit,
 * and refuses a larger image with an error that names the file, its declared size and the
 * limit. The same limit bounds image sizes known from a graph's parameters (`lightgraph
 * check`). The default, 2^27 = 134,217,728 pixels (16384 x 8192, 2 GiB as rgba32f), holds
 * the largest light probes in use; Pillow's comparable default is about 89 million.
 * LIGHTGRAPH_MAX_PIXELS in the environment (read at first use) or lg_image_set_max_pixels
 * (the host's --max-pixels) raises or lowers it; 0 restores the default. */
#define LG_IMAGE_MAX_PIXELS_DEFAULT 134217728ull
LG_API uint64_t lg_image_max_pixels(void);
LG_API void lg_image_set_max_pixels(uint64_t n);

/* The other two bounds of every read, both checked before anything is decoded:
 *   - File size: at most lg_image_max_file_bytes(), 32 bytes per pixel of the pixel limit
 *     (an uncompressed float RGBA file of that many pixels takes 16, plus room for extra
 *     channels and tables), but never less than 64 MiB: 4 GiB by default. It follows the
 *     pixel limit when that is raised or lowered.
 *   - Memory: the bytes the decode needs (the codec's buffers plus the rgba32f result,
 *     computed without overflow from the declared size) must fit in what the machine can
 *     give: the physical memory (sysconf) and, when one is set, the address-space limit
 *     (RLIMIT_AS) less what the process already maps. The message says which bound it met.
 * The file is opened once (lightgraph/file.h: regular files only, never blocking on a
 * FIFO) and every decoder reads that open file; no decoder opens the path again. */
LG_API uint64_t lg_image_max_file_bytes(void);

/* Since ABI 2.7. The memory this process can still be given, in bytes: the machine's
 * physical memory (sysconf), or, when an address-space limit is set (RLIMIT_AS, `ulimit
 * -v`, `prlimit --as`), that limit less what the process maps already, whichever is less.
 * It is the bound of every image read (above); the host checks each declared image and
 * volume and the sum of a plan's resources against it before anything runs, and a node
 * whose working memory a parameter sets checks it in prepare() (docs/sdk.md "Memory").
 * `what` (may be NULL) receives a static description of the bound met, for messages:
 * "physical memory", or "address space that the process's limit (RLIMIT_AS, ulimit -v)
 * leaves". Reads /proc/self/statm when a limit is set; thread-safe. */
LG_API uint64_t lg_memory_available(const char **what);

/* Since ABI 2.7. `b` bytes as text for messages: "512 bytes", "1.5 KiB", "4.0 GiB" (one
 * decimal, binary units), written into out[n] (always terminated when n > 0). */
LG_API void lg_bytes_text(char *out, size_t n, uint64_t b);

/* A 64-bit hash of an image's size and pixels (FNV-1a over 8-byte words, then a final mix),
 * continuing from `seed` (LG_IMAGE_HASH_SEED to start; pass a previous result to chain
 * several images). For content keys: the same pixels give the same key from any file
 * encoding, and hashing what was decoded needs no second open of the file. Not a
 * cryptographic hash. */
#define LG_IMAGE_HASH_SEED 0xcbf29ce484222325ull
LG_API uint64_t lg_image_hash(const lg_image *img, uint64_t seed);

/* ---- non-finite pixels: one count and one warning for every node --------------------------------
 *
 * A NaN or Inf pixel is reported, never silently passed on: the `image` node says how many
 * a file holds, and every node that passes an image input on into its output (background,
 * the volumetric nodes) says how many it received, with the same words:
 *
 *     <what>: N pixel(s) with a NaN or Inf channel, <fate>
 *
 * lg_pixels_nonfinite: the pixels of a width x height rgba32f image (rows `row_pixels`
 * pixels apart, >= width) with a NaN or Inf in any of the four channels.
 * lg_warn_nonfinite: that warning on node `node` (`what` names the pixels: "file 'a.exr'",
 * "input 'base'"; `fate` says what the node did with them: "kept as found"); nothing when
 * count is 0.
 * lg_check_input_finite: for a node's rgba32f image input `port`, called from execute():
 * counts its pixels through a CPU mapping for reading (an input current only on GL or CL is
 * copied to the host for it, and the copy counted in the profile like any move) and warns
 * "input '<port_name>' (frame F): N pixels with a NaN or Inf channel, <fate> (reported
 * once)" the first time a frame has any (`fate` NULL: "passed on as found"). `*reported` is the node's own flag
 * (false at create): once it is set no later frame is counted, so a clean input costs one
 * count per frame and a dirty one a single warning per render. An unconnected, neutral or
 * non-rgba32f input counts nothing. Returns 0, or the mapping's error (already reported). */
struct lg_node;
struct lg_frame;
LG_API uint64_t lg_pixels_nonfinite(const float *rgba, uint32_t width, uint32_t height,
                                    size_t row_pixels);
LG_API void lg_warn_nonfinite(struct lg_node *node, const char *what, uint64_t count,
                              const char *fate);
LG_API int lg_check_input_finite(struct lg_node *node, const struct lg_frame *frame, uint32_t port,
                                 const char *port_name, const char *fate, bool *reported);

/* Reads a file into `img` (which the call fills; free with lg_image_free). A file without
 * alpha gets alpha 1. PNG is decoded from sRGB to linear. `info` may be NULL. */
LG_API int lg_image_read(const char *path, unsigned flags, lg_image *img, lg_image_read_info *info,
                         char *err, size_t errlen);

typedef enum lg_exr_pixel { LG_EXR_HALF = 0, LG_EXR_FLOAT } lg_exr_pixel;
typedef enum lg_exr_compression {
    LG_EXR_ZIP = 0, /* default: lossless, widely read */
    LG_EXR_NONE,
    LG_EXR_RLE,
    LG_EXR_ZIPS,
    LG_EXR_PIZ,
    LG_EXR_PXR24,
    LG_EXR_B44,
    LG_EXR_B44A,
    LG_EXR_DWAA,
    LG_EXR_DWAB,
} lg_exr_compression;

/* How to write. Zero means the default for every field. */
typedef struct lg_image_write_opts {
    lg_exr_pixel exr_pixel;             /* EXR: half (the zero value) or float; the host
                                         * writes rgba32f renders as float unless an output
                                         * asks for half */
    lg_exr_compression exr_compression; /* EXR: ZIP by default */
    uint32_t channels;                  /* 0 or 4: RGBA; 3: RGB (EXR and PNG) */
    uint32_t reserved[8];
} lg_image_write_opts;

/* Writes `img` to `path` atomically, in the format its extension names. `opts` may be
 * NULL. PNG: colour is clamped to [0,1] and sRGB-encoded, alpha clamped; NaN writes 0.
 * HDR: new-style RLE for widths 8..32767, flat otherwise, alpha dropped; see
 * lg_rgbe_encode for the edge cases. EXR: scanline, increasing Y; half rounds to
 * nearest even, values beyond 65504 become Inf, as OpenEXR's half does. The new file
 * gets the mode any new file would (0666 less the umask). */
LG_API int lg_image_write(const char *path, const lg_image *img, const lg_image_write_opts *opts,
                          char *err, size_t errlen);

/* ---- encodings ------------------------------------------------------------------------------- */

/* IEEE 754 binary16 <-> binary32, round to nearest even, with denormals, Inf and NaN. */
LG_API uint16_t lg_half_from_float(float f);
LG_API float lg_float_from_half(uint16_t h);

/* Ward's RGBE, from frexp: the largest channel's mantissa in [0.5, 1) scaled by 256.
 * Convention: each channel encodes as round(c * 2^(136 - E)) and decodes as
 * m * 2^(E - 136), without Radiance's half-step offset; that keeps the error within half a
 * step, unbiased, and makes powers of two exact. Files from writers that truncate (as
 * Radiance does) read about half a step (~0.2%) low on average.
 * Edge cases, all deliberate:
 *   - a largest channel below FLT_MIN (1.18e-38: zero or a float denormal) encodes as
 *     (0,0,0,0), which decodes to exactly 0 (a GPU flushes denormals: shaders/common/
 *     rgbe.glsl gives the same bytes);
 *   - negative channels encode as 0 (RGBE has no sign);
 *   - NaN channels encode as 0;
 *   - +Inf, and finite values at or above 2^127 (the largest power RGBE's exponent byte
 *     can hold is 2^127, mantissa < 1), saturate to the largest representable value,
 *     (255, 255, 255, 255) scaled per channel, i.e. about 1.7e38 for the largest channel;
 *   - exact powers of two round trip exactly. */
LG_API void lg_rgbe_encode(const float rgb[3], uint8_t rgbe[4]);
LG_API void lg_rgbe_decode(const uint8_t rgbe[4], float rgb[3]);

/* ---- pixel formats (lg_format) ------------------------------------------------------------------
 *
 * The three formats an HDR image node offers for its output (`format = rgba32f | rgba16f |
 * rgbe8`), and what each does to the values a producer computes in float:
 *
 *   rgba32f  16 bytes a pixel; every float kept as it is.
 *   rgba16f   8 bytes; IEEE half: 11 significant bits (relative step 2^-11, 0.05%), largest
 *            65504. A plain half store turns anything above 65504 into +Inf, and real
 *            suns in probes are brighter than that (1e5 .. 1e9); one Inf then poisons
 *            every filter, average and tone map downstream. The policy: producers CLAMP
 *            to +-65504 and turn NaN into 0 before the store, count the values they
 *            changed, and report once per node and frame with the count (lg_log at
 *            LG_LOG_WARN, e.g. "rgba16f output: 12 values above 65504 clamped, NaN set
 *            to 0"). lg_pixels_from_rgba32f below does it on the CPU; lg_half_range in
 *            shaders/common/rgbe.glsl and rgbe.cl is the GPU twin (same values). The
 *            clamp loses the energy above 65504: a sun of 1e6 integrates 15x too dark.
 *   rgbe8     4 bytes; Ward's RGBE (lg_rgbe_encode above): three 8-bit mantissas and a
 *            shared exponent, so the range is 2^-126 .. 1.7e38 but a channel much darker
 *            than the pixel's brightest loses its precision (steps of max/256); the
 *            relative error of the largest channel is at most 2^-8 (0.39%, half a step of the
 *            smallest mantissa, 128), about 0.1% on average. No sign, no
 *            alpha (reads back as 1). On GL the bytes live in an RGBA8 (unorm) texture and
 *            must be decoded by every consumer (lg_rgbe_decode_unorm); the hardware's
 *            filtering and blending of the raw bytes are meaningless, so an rgbe8 image is
 *            read with texelFetch and decoded before any filtering.
 *   rgba8     4 bytes; unorm, a display encoding (sRGB or linear is the producer's to say);
 *            not an HDR format: nodes that add and scale light refuse it.
 *
 * A consumer that cannot decode a format refuses it in prepare with an error naming the
 * node, the input and the format. */

/* "rgba32f", "rgba16f", "rgba8", "rgbe8" (static strings); "unknown" for anything else. */
LG_API const char *lg_format_name(lg_format f);
/* The format named `name` (as lg_format_name spells it) into *out: 0, or LG_ERR_NOTFOUND. */
LG_API int lg_format_from_name(const char *name, lg_format *out);

/* Converts `n` float RGBA pixels `src` into format `f` at `dst` (n * lg_format_size(f)
 * bytes, caller's memory; dst may be src). The policy above:
 *   rgba32f: copied unchanged;
 *   rgba16f: NaN -> 0, values beyond +-65504 (Inf included) -> +-65504, then rounded to
 *            nearest even (lg_half_from_float);
 *   rgba8:   NaN -> 0, clamped to [0, 1], round(v * 255) (no transfer function);
 *   rgbe8:   lg_rgbe_encode of R, G, B; alpha is not stored.
 * Adds to *clamped (when not NULL) the number of channel values replaced rather than
 * rounded: rgba16f NaN and beyond +-65504; rgba8 NaN and outside [0, 1]; rgbe8 NaN,
 * negative, +Inf and 2^127 or more (saturated). Returns 0, or LG_ERR_INVALID for an unknown
 * format. */
LG_API int lg_pixels_from_rgba32f(lg_format f, const float *src, size_t n, void *dst,
                                  uint64_t *clamped);

/* Converts `n` pixels of format `f` at `src` into float RGBA at `dst` (n * 16 bytes; dst
 * may be src when the buffer holds n * 16 bytes). rgba16f: exact (lg_float_from_half);
 * rgba8: byte / 255; rgbe8: lg_rgbe_decode (exact), alpha 1. Returns 0, or LG_ERR_INVALID
 * for an unknown format. */
LG_API int lg_pixels_to_rgba32f(lg_format f, const void *src, size_t n, float *dst);

/* sRGB transfer function (IEC 61966-2-1), per channel; input clamped to [0,1]. */
LG_API float lg_srgb_encode(float linear);
LG_API float lg_srgb_decode(float encoded);

/* ---- comparison ------------------------------------------------------------------------------ */

typedef struct lg_image_metrics {
    double rmse;        /* over RGB channels of all pixels */
    double psnr;        /* dB, with peak 1.0; +Inf for identical images */
    double mean_abs;    /* mean absolute error over RGB */
    double max_abs;     /* maximum absolute error over RGB */
    double rel_mse;     /* mean of (a-b)^2 / (b^2 + 1e-4) */
    uint64_t nonfinite; /* pixels where either image has NaN/Inf (excluded from the above) */
    uint32_t reserved[8];
} lg_image_metrics;

/* Compares two images of the same size. With `heatmap` not NULL, fills it (allocating)
 * with the per-pixel absolute error (max over RGB) mapped through a colour ramp from
 * black (0) to white (>= heat_max; heat_max <= 0 means the image's maximum error). */
LG_API int lg_image_compare(const lg_image *a, const lg_image *b, lg_image_metrics *out,
                            lg_image *heatmap, double heat_max, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif
#endif
