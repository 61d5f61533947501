/*
 * plugins/probe/probe_load.h: the `probe` node's file reading, apart from the node so that
 * tests/fuzz/fuzz_probe.c runs it on arbitrary files (docs/fuzzing.md). probe.c reads the
 * parameters and calls pr_load_file; everything about the files (decoding, the layout a
 * size means, the cube's cells, the values a probe cannot hold) is here.
 */
#ifndef LG_PROBE_LOAD_H
#define LG_PROBE_LOAD_H

#include <stdint.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"

/* The `layout` parameter's values, in the enum's order. */
enum {
    PR_LAYOUT_AUTO = 0,
    PR_LAYOUT_LATLONG,
    PR_LAYOUT_ANGULAR,
    PR_LAYOUT_CROSS,
    PR_LAYOUT_STRIP,
    PR_LAYOUT_FACES
};

/* A probe as read from its files, level 0 only. */
typedef struct pr_file {
    lg_probe_layout layout;
    uint32_t width, height;           /* the radiance image's size (a cube's face size) */
    float *texels;                    /* level 0, RGBA, packed as the CPU copy (faces, rows); every
                                       * colour channel finite and >= 0, alpha 1 */
    lg_image decoded;                 /* 2D layouts: the decoded file, whose pixels are `texels`
                                       * (freed by the SDK that allocated them) */
    lg_probe_file_layout file_layout; /* how the cube was stored: an output writes it so */
} pr_file;

/* Reads the probe of `file` (want != PR_LAYOUT_FACES) or of the `n_faces` files of
 * `faces` (want == PR_LAYOUT_FACES, or PR_LAYOUT_AUTO with no file and some faces; faces
 * is read only when n_faces is 6), as the `probe` node's parameters `layout`, `file` and
 * `faces` say. Returns 0 with *out filled (the caller owns it: pr_file_clear) and *key the
 * content key of the pixels and the layout, or an LG_ERR_* after lg_error on `n` naming
 * the file, its size and why, with *out empty. Logs on `n`: a warning per file whose
 * values a probe cannot hold (zeroed), debug and info lines. */
int pr_load_file(lg_node *n, int want, const char *file, const char *const *faces, uint32_t n_faces,
                 pr_file *out, uint64_t *key);

/* Frees what pr_load_file made and empties *f (which may be empty already). */
void pr_file_clear(pr_file *f);

#endif
