/*
 * exr_recompress: writes an image again as an EXR of a given compression and pixel type,
 * optionally reduced by an integer box filter, with the SDK's own reader and writer
 * (lg_image_read, lg_image_write: OpenEXRCore for NONE .. B44A, the C++ library for DWAA
 * and DWAB). It made the small probes of assets/probes/ that cover every EXR compression
 * (assets/README.md), so that `--set sky.file=` of examples/ibl.lgraph is tested with each.
 *
 *   exr_recompress IN OUT.exr COMPRESSION half|float [FACTOR]
 *
 * COMPRESSION: none rle zips zip piz pxr24 b44 b44a dwaa dwab. FACTOR (default 1): each
 * output pixel is the mean of FACTOR x FACTOR input pixels (the size must divide). The
 * output has R, G, B (no alpha). Exit 0, or 1 with a message naming the file and why.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"

static const struct {
    const char *name;
    lg_exr_compression c;
} compressions[] = {
    { "none", LG_EXR_NONE }, { "rle", LG_EXR_RLE },   { "zips", LG_EXR_ZIPS },
    { "zip", LG_EXR_ZIP },   { "piz", LG_EXR_PIZ },   { "pxr24", LG_EXR_PXR24 },
    { "b44", LG_EXR_B44 },   { "b44a", LG_EXR_B44A }, { "dwaa", LG_EXR_DWAA },
    { "dwab", LG_EXR_DWAB },
};

int main(int argc, char **argv)
{
    if (argc < 5 || argc > 6) {
        fprintf(stderr,
                "usage: exr_recompress IN OUT.exr none|rle|zips|zip|piz|pxr24|b44|b44a|dwaa|dwab "
                "half|float [FACTOR]\n");
        return 2;
    }
    lg_image_write_opts opts = { .channels = 3 };
    size_t i = 0;
    while (i < sizeof compressions / sizeof *compressions && strcmp(argv[3], compressions[i].name))
        i++;
    if (i == sizeof compressions / sizeof *compressions) {
        fprintf(stderr, "exr_recompress: unknown compression '%s'\n", argv[3]);
        return 2;
    }
    opts.exr_compression = compressions[i].c;
    if (!strcmp(argv[4], "half"))
        opts.exr_pixel = LG_EXR_HALF;
    else if (!strcmp(argv[4], "float"))
        opts.exr_pixel = LG_EXR_FLOAT;
    else {
        fprintf(stderr, "exr_recompress: pixel type '%s' is neither half nor float\n", argv[4]);
        return 2;
    }
    long factor = argc == 6 ? strtol(argv[5], NULL, 10) : 1;
    char err[1024];
    lg_image in;
    if (lg_image_read(argv[1], 0, &in, NULL, err, sizeof err)) {
        fprintf(stderr, "exr_recompress: %s\n", err);
        return 1;
    }
    if (factor < 1 || factor > 64 || in.width % (uint32_t)factor || in.height % (uint32_t)factor) {
        fprintf(stderr, "exr_recompress: '%s' is %ux%u: factor %ld does not divide it (1..64)\n",
                argv[1], in.width, in.height, factor);
        lg_image_free(&in);
        return 1;
    }
    uint32_t f = (uint32_t)factor;
    lg_image out;
    if (lg_image_alloc(&out, in.width / f, in.height / f)) {
        fprintf(stderr, "exr_recompress: out of memory\n");
        lg_image_free(&in);
        return 1;
    }
    /* the mean of each f x f block, in double: radiance averaged over the block's area */
    for (uint32_t y = 0; y < out.height; y++)
        for (uint32_t x = 0; x < out.width; x++)
            for (int c = 0; c < 4; c++) {
                double sum = 0;
                for (uint32_t v = 0; v < f; v++)
                    for (uint32_t u = 0; u < f; u++)
                        sum += in.pixels[((size_t)(y * f + v) * in.width + x * f + u) * 4 + c];
                out.pixels[((size_t)y * out.width + x) * 4 + c] = (float)(sum / (f * f));
            }
    lg_image_free(&in);
    int rc = lg_image_write(argv[2], &out, &opts, err, sizeof err);
    lg_image_free(&out);
    if (rc) {
        fprintf(stderr, "exr_recompress: %s\n", err);
        return 1;
    }
    return 0;
}
