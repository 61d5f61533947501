/*
 * gltf_test.h: what the scene_gltf tests share: a scratch folder, glTF files written from
 * JSON text and binary blobs (data URIs or .bin files), and loading through the plugin's
 * loader (plugins/scene_gltf/gltf_load.h) without the host.
 */
#ifndef LG_TESTS_GLTF_TEST_H
#define LG_TESTS_GLTF_TEST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "gltf_load.h"

/* The scratch folder ($LG_BUILD_ROOT/test-tmp/NAME-XXXXXX); gt_cleanup removes it. */
void gt_init(const char *name);
void gt_cleanup(bool keep);
/* dir/rel, valid until the 8th next call */
const char *gt_path(const char *rel);
void gt_write(const char *rel, const void *data, size_t size);
/* $LG_SOURCE_ROOT/assets/rel, or fails (exit 1) when it is not there: a repository file */
const char *gt_asset(const char *rel);
/* A whole file (malloc'd), or exits 99 */
uint8_t *gt_read(const char *path, size_t *size);

/* A growing binary buffer; gt_add pads to 4 bytes and returns the offset of the data. */
typedef struct gt_blob {
    uint8_t *data;
    size_t size, cap;
} gt_blob;
size_t gt_add(gt_blob *b, const void *data, size_t size);
void gt_blob_free(gt_blob *b);
/* "data:application/octet-stream;base64,..." (malloc'd) */
char *gt_data_uri(const void *data, size_t size);
/* printf into a malloc'd string */
char *gt_fmt(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Writes `json` to dir/name and loads it with `opt` (NULL: defaults). Returns the scene,
 * or NULL with the message in err (and *rc the code, when rc is not NULL). */
lg_scene *gt_load_text(const char *name, const char *json, const lg_gltf_options *opt, char *err,
                       size_t err_size, int *rc);
lg_scene *gt_load_file(const char *path, const lg_gltf_options *opt, char *err, size_t err_size,
                       int *rc);

/* The world position of a mesh vertex under an instance. */
void gt_world(const lg_instance *in, const float *p, float out[3]);

#endif
