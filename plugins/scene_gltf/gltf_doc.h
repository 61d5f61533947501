/*
 * gltf_doc.h: a parsed glTF 2.0 file as plain C data, and Draco decoding.
 *
 * The only C++ of the plugin (gltf_shim.cpp) sits behind this header: it runs tinygltf
 * (2.7.0, Debian's libtinygltf-dev, compiled in) on a file held in memory and copies the
 * parts the loader uses into the structs below, and it decodes Draco-compressed
 * primitives with libdraco. Every exception and every tinygltf or Draco failure comes
 * back as a message; nothing here prints or aborts.
 *
 * Nothing in the document is validated beyond what tinygltf checks while parsing (JSON
 * syntax, required properties, buffer sizes against their byteLength): indices between
 * objects, ranges and counts are the loader's to check (gltf_load.c). Numbers are as the
 * file says them (doubles); -1 means "absent" for an index.
 */
#ifndef LG_GLTF_DOC_H
#define LG_GLTF_DOC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A JSON value from `extras` or `extensions`. Objects keep the file's keys (sorted, as
 * tinygltf stores them in a std::map). */
typedef enum lg_json_type {
    LG_JSON_NULL = 0,
    LG_JSON_BOOL,
    LG_JSON_NUMBER,
    LG_JSON_STRING,
    LG_JSON_ARRAY,
    LG_JSON_OBJECT,
} lg_json_type;

typedef struct lg_json {
    lg_json_type type;
    bool boolean;
    double number;
    const char *string;
    uint32_t n;                  /* array items or object members */
    const struct lg_json *items; /* n values */
    const char *const *keys;     /* objects: n keys */
} lg_json;

/* Member `key` of an object, or NULL (also when `obj` is NULL or not an object). */
const lg_json *lg_json_get(const lg_json *obj, const char *key);

typedef struct lg_gltf_buffer {
    const uint8_t *data;
    size_t size;
} lg_gltf_buffer;

typedef struct lg_gltf_view {
    int32_t buffer;
    uint64_t offset, length, stride; /* stride 0: tightly packed */
} lg_gltf_view;

typedef struct lg_gltf_accessor {
    const char *name;
    int32_t view; /* -1: all zeros (then sparse, if any) */
    uint64_t offset;
    int32_t component_type; /* 5120 byte .. 5126 float (GL enums) */
    uint32_t components;    /* 1 SCALAR, 2, 3, 4 VEC, 4 MAT2, 9 MAT3, 16 MAT4; 0 unknown */
    bool normalized;
    uint64_t count;
    bool sparse;
    int64_t sparse_count;
    int32_t sparse_index_view, sparse_index_type, sparse_value_view;
    int64_t sparse_index_offset, sparse_value_offset;
} lg_gltf_accessor;

typedef struct lg_gltf_primitive {
    int32_t mode;                       /* 0 POINTS .. 6 TRIANGLE_FAN (tinygltf's default 4) */
    int32_t indices, material;          /* accessor, material; -1 absent */
    int32_t position, normal, texcoord; /* accessors of POSITION, NORMAL, TEXCOORD_0 */
    uint32_t n_targets;                 /* morph targets (not supported: base shape is used) */
    const lg_json *extensions;          /* object or NULL */
} lg_gltf_primitive;

typedef struct lg_gltf_mesh {
    const char *name;
    const lg_gltf_primitive *primitives;
    uint32_t n_primitives;
} lg_gltf_mesh;

typedef struct lg_gltf_node {
    const char *name;
    int32_t mesh, camera, skin;
    const int32_t *children;
    uint32_t n_children;
    /* as many numbers as the file gave (the loader checks 0 or 16, 0 or 3, 0 or 4) */
    uint32_t n_matrix, n_translation, n_rotation, n_scale;
    double matrix[16], translation[3], rotation[4], scale[3];
    const lg_json *extensions; /* object or NULL */
} lg_gltf_node;

typedef struct lg_gltf_scene {
    const char *name;
    const int32_t *nodes;
    uint32_t n_nodes;
    const lg_json *extras;
} lg_gltf_scene;

typedef struct lg_gltf_camera {
    const char *name;
    const char *type;                 /* "perspective" or "orthographic" (or what the file says) */
    double yfov, aspect, znear, zfar; /* perspective */
    double xmag, ymag, ortho_znear, ortho_zfar;
} lg_gltf_camera;

typedef struct lg_gltf_material {
    const char *name;
    uint32_t n_base_color, n_emissive;
    double base_color[4], emissive[3];
    double metallic, roughness;
    bool double_sided;
    const lg_json *extensions, *extras;
} lg_gltf_material;

typedef struct lg_gltf_light {
    const char *name;
    const char *type; /* "directional", "point", "spot" */
    uint32_t n_color;
    double color[3];
    double intensity, range, inner_cone, outer_cone;
} lg_gltf_light;

/* Animations (glTF 2.0, 3.11): samplers read key times (input) and values (output)
 * accessors; a channel points a sampler at a node's path. */
typedef struct lg_gltf_anim_sampler {
    int32_t input, output;     /* accessors; -1 absent */
    const char *interpolation; /* "LINEAR" (the default, also when absent), "STEP", ... */
} lg_gltf_anim_sampler;

typedef struct lg_gltf_anim_channel {
    int32_t sampler, node; /* node -1: no target node */
    const char *path;      /* "translation", "rotation", "scale", "weights" or the file's */
} lg_gltf_anim_channel;

typedef struct lg_gltf_animation {
    const char *name;
    const lg_gltf_anim_channel *channels;
    uint32_t n_channels;
    const lg_gltf_anim_sampler *samplers;
    uint32_t n_samplers;
} lg_gltf_animation;

/* A skin: only its joints (nodes) are read, so that an animation of them is refused. */
typedef struct lg_gltf_skin {
    const int32_t *joints;
    uint32_t n_joints;
} lg_gltf_skin;

typedef struct lg_gltf {
    const lg_gltf_buffer *buffers;
    const lg_gltf_view *views;
    const lg_gltf_accessor *accessors;
    const lg_gltf_mesh *meshes;
    const lg_gltf_node *nodes;
    const lg_gltf_scene *scenes;
    const lg_gltf_camera *cameras;
    const lg_gltf_material *materials;
    const lg_gltf_light *lights; /* KHR_lights_punctual */
    uint32_t n_buffers, n_views, n_accessors, n_meshes, n_nodes, n_scenes, n_cameras, n_materials,
        n_lights;
    int32_t default_scene; /* "scene", or -1 */
    const char *const *extensions_required;
    uint32_t n_extensions_required;
    const lg_json *extras; /* the root object's */
    const lg_json *asset_extras;
    const char *warnings; /* tinygltf's warnings, "" if none */
    const lg_gltf_animation *animations;
    uint32_t n_animations;
    const lg_gltf_skin *skins;
    uint32_t n_skins;
} lg_gltf;

typedef struct lg_gltf_doc lg_gltf_doc; /* owns everything the lg_gltf points to */

/* Parses a glTF (JSON) or GLB file held in `bytes` (the GLB magic decides). External
 * buffers are read from `base_dir` (absolute) only; images are not read or decoded.
 * Returns the document, or NULL with a message in err (without the file name: the
 * caller adds it). */
lg_gltf_doc *lg_gltf_parse(const uint8_t *bytes, size_t size, const char *base_dir,
                           const lg_gltf **out, char *err, size_t err_size);
void lg_gltf_doc_free(lg_gltf_doc *doc);

/* A decoded KHR_draco_mesh_compression primitive: point arrays (floats, normalized
 * integers mapped to [0, 1] or [-1, 1]) and a triangle list. Arrays are malloc'd;
 * free with lg_draco_mesh_free. */
typedef struct lg_draco_mesh {
    uint32_t n_points, n_faces;
    float *positions;  /* 3 per point */
    float *normals;    /* 3 per point, or NULL when not asked for */
    float *texcoords;  /* 2 per point, or NULL when not asked for */
    uint32_t *indices; /* 3 per face, each < n_points */
} lg_draco_mesh;

/* Decodes a Draco mesh from `size` bytes. The ids are Draco attribute unique ids from the
 * extension's "attributes" (position required; normal and texcoord -1 when absent).
 * `max_points` and `max_faces` bound what the stream may claim. Returns 0, or -1 with a
 * message in err (and *out zeroed). */
int lg_draco_decode(const uint8_t *bytes, size_t size, int64_t position_id, int64_t normal_id,
                    int64_t texcoord_id, uint64_t max_points, uint64_t max_faces,
                    lg_draco_mesh *out, char *err, size_t err_size);
void lg_draco_mesh_free(lg_draco_mesh *m);

#ifdef __cplusplus
}
#endif
#endif
