/*
 * gltf_load.h: a glTF 2.0 file (.gltf or .glb) to an lg_scene (lightgraph/scene.h).
 *
 * The loader of the `gltf` node, callable without the host (the tests and the benchmark
 * do). README.md describes what it reads, the mappings it applies and what it refuses.
 * Errors come back as an LG_ERR_* code and one line of text that names the file and the
 * glTF object (mesh, primitive, accessor, bufferView, node index) and says why; the
 * loader never prints and never aborts, and frees everything it made on failure.
 */
#ifndef LG_GLTF_LOAD_H
#define LG_GLTF_LOAD_H

#include <stddef.h>
#include <stdint.h>

#include "lightgraph/scene.h"

typedef enum lg_gltf_normals {
    LG_GLTF_NORMALS_AUTO = 0, /* the file's normals where it has them, else smooth */
    LG_GLTF_NORMALS_SMOOTH,   /* computed, split at the crease angle */
    LG_GLTF_NORMALS_FLAT,     /* computed, one per facet (vertices unshared) */
} lg_gltf_normals;

typedef struct lg_gltf_options {
    lg_gltf_normals normals;
    double crease_deg; /* smooth normals: facets further apart than this get a crease */
    int64_t scene;     /* the glTF scene; -1: the file's default, else scene 0, else
                        * every root node */
    int64_t camera;    /* index into lg_scene.cameras; -1: the first (the file's first
                        * camera, else the automatic one) */
    int64_t animation; /* the glTF animation played (lg_scene.animation): an index into the
                        * file's animations, 0 by default (none when the file has none);
                        * -1: none (the rest pose) */
    /* Receives each warning (one line, naming the file); may be NULL. */
    void (*warn)(void *user, const char *message);
    void *warn_user;
} lg_gltf_options;

/* The defaults of the node's parameters. */
lg_gltf_options lg_gltf_default_options(void);

/* Loads `path`: a regular file of at most LG_GLTF_MAX_FILE bytes, read through
 * lightgraph/file.h (a FIFO, a device or a larger file is refused before a byte is read).
 * External buffers are read only from the file's folder (the folder of `path` as given,
 * links resolved): README.md, "Files the model may read". On success *out is the scene
 * (free with lg_gltf_scene_free) and *content_hash (if not NULL) a 64-bit FNV-1a hash of
 * the file and every buffer it loaded. Returns 0 or an LG_ERR_* code with the reason in
 * err. */
int lg_gltf_load(const char *path, const lg_gltf_options *opt, lg_scene **out,
                 uint64_t *content_hash, char *err, size_t err_size);

/* The same from bytes in memory: `name` is the file name used in messages; external
 * buffers are read from, and confined to, base_dir (NULL: none can be loaded, and image
 * uris must still not leave the folder lexically). */
int lg_gltf_load_memory(const uint8_t *bytes, size_t size, const char *name, const char *base_dir,
                        const lg_gltf_options *opt, lg_scene **out, uint64_t *content_hash,
                        char *err, size_t err_size);

/* Frees a scene made by the loader (NULL is fine). Matches declare_payload's free_fn. */
void lg_gltf_scene_free(lg_scene *scene);

/* Limits (README.md, "Limits"). */
#define LG_GLTF_MAX_COUNT (1u << 28)     /* elements of one accessor, points of a Draco mesh */
#define LG_GLTF_MAX_DEPTH 256            /* node nesting */
#define LG_GLTF_MAX_INSTANCES (1u << 24) /* mesh primitives placed in the scene */
/* The .gltf or .glb file itself, each external buffer (its byteLength), and all external
 * buffers of one model together. 2 GiB: tinygltf 2.7.0 takes a file's size as an unsigned
 * int and GLB lengths are 32-bit; 2^31 keeps the Draco rewrite's copy below both. */
#define LG_GLTF_MAX_FILE ((uint64_t)1 << 31)
#define LG_GLTF_MAX_BUFFER ((uint64_t)1 << 31)
#define LG_GLTF_MAX_EXTERNAL ((uint64_t)1 << 32)

#endif
