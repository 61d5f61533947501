/*
 * lightgraph/host.h: the services the host offers a node.
 *
 * Every callback receives an `lg_node *`. Its first field is the host's service table,
 * `lg_host_api`, a versioned struct of function pointers in the spirit of OpenFX suites:
 * a plugin never links against the host. The inline functions below (lg_param_float,
 * lg_input, lg_declare_image, lg_map_cpu, ...) wrap the table and are what plugin code
 * normally calls.
 *
 * Ownership. The host owns every `lg_node`, every resource and every string it hands out;
 * they stay valid until the node is destroyed unless a function says otherwise. Memory a
 * plugin allocates is freed by the plugin (in destroy, or by the free callback it gives).
 *
 * Errors. lg_error() records a message with the node's name and type; the callback then
 * returns a negative LG_ERR_* value. Messages say what failed and why, with the value
 * that was wrong ("backend 'cl': no OpenCL platform found (clGetPlatformIDs: -1001)").
 *
 * Devices. A node says in prepare() which device it runs on (lg_set_device). The GL
 * context and the CL context/queue exist only if some planned node asks for them. An
 * unavailable device is an error for the node that asked, never a silent fallback.
 *
 * Residency. A resource may have a current copy on the CPU, in GL and in CL. Mapping it
 * for reading on a device where it is not current copies it there (through host memory:
 * llvmpipe and PoCL share nothing) and counts the bytes against the node that asked.
 * Mapping for writing makes that device's copy the only current one.
 *
 * GL state. A node that uses GL may change any state it needs; the host resets the state
 * listed in docs/devices.md ("The GL state contract") before each node, and in debug
 * builds checks after each node that the bindings a node must restore (framebuffer 0,
 * program 0, no bound image units) are restored.
 */
#ifndef LIGHTGRAPH_HOST_H
#define LIGHTGRAPH_HOST_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/config.h"
#include "lightgraph/plugin.h"
#include "lightgraph/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lg_resource lg_resource; /* opaque; owned by the host */

typedef enum lg_log_level {
    LG_LOG_ERROR = 0,
    LG_LOG_WARN,
    LG_LOG_INFO,
    LG_LOG_DEBUG,
} lg_log_level;

/* Images: 2D rgba, with an optional float depth plane of the same size.
 * LG_IMAGE_DEPTH_ONLY (since ABI 1.1): only the depth plane exists (shadow maps); the
 * colour mappings give NULL / 0, the depth mappings the plane; `format` is ignored. An
 * output file of such an image shows depth as grey.
 * LG_IMAGE_CUBE (since ABI 2.0): six square faces of width x height (width == height), in
 * OpenGL's order and orientation (+X, -X, +Y, -Y, +Z, -Z); in GL a GL_TEXTURE_CUBE_MAP.
 * `levels` (since ABI 2.0; 0 means 1): a mip chain, level l of size max(1, width >> l) x
 * max(1, height >> l); at most floor(log2(max(width, height))) + 1 levels. Depth planes
 * have one level. The CPU copy and the CL buffer hold every level, faces and rows
 * tightly packed: level 0 first; in a level, face 0 first; in a face, row 0 (the top row)
 * first. lg_image_offset() gives where a level and face start. */
enum { LG_IMAGE_DEPTH = 1u << 0, LG_IMAGE_DEPTH_ONLY = 1u << 1, LG_IMAGE_CUBE = 1u << 2 };
typedef struct lg_image_desc {
    uint32_t width, height;
    lg_format format;
    uint32_t flags;  /* LG_IMAGE_* */
    uint32_t levels; /* mip levels; 0 = 1 */
    uint32_t reserved[3];
} lg_image_desc;

typedef struct lg_buffer_desc {
    size_t size; /* bytes */
    uint32_t reserved[4];
} lg_buffer_desc;

typedef struct lg_volume_desc {
    uint32_t width, height, depth;
    lg_format format;
    uint32_t reserved[4];
} lg_volume_desc;

/* What a resource is. `neutral` is true for the stand-in a gated node yields: consumers
 * may skip work (an `add` with a neutral zero input copies the other); a neutral
 * composite resource has no parts.
 * A part of a composite resource (lg_part()) describes itself as an image, volume or
 * buffer with `part_of` set to the composite's kind and `part_name` to its name. */
typedef struct lg_resource_info {
    lg_resource_kind kind;
    bool neutral;
    lg_image_desc image;            /* kind == LG_KIND_IMAGE */
    lg_buffer_desc buffer;          /* kind == LG_KIND_BUFFER (and META parts) */
    lg_volume_desc volume;          /* kind == LG_KIND_VOLUME */
    const lg_scene_features *scene; /* kind == LG_KIND_SCENE; owned by the resource */
    const void *payload;            /* kinds whose data the producing plugin owns (scene) */
    /* since ABI 2.0 */
    uint32_t n_parts;         /* composite kinds: the parts it has (0 when neutral) */
    lg_resource_kind part_of; /* a part: the composite's kind; else LG_KIND_ANY */
    const char *part_name;    /* a part: its name; else NULL */
    lg_part_type part_type;   /* a part: its type; else 0 */
    uint32_t reserved[8];
} lg_resource_info;

/* One part of a composite output, declared in prepare() (lg_declare_composite). `name`
 * and `type` must be a part the kind declares (lightgraph/kinds.h); the description that
 * matches the type is read, the others ignored. Strings need only live until the call
 * returns. */
typedef struct lg_part_spec {
    const char *name;
    lg_part_type type;
    lg_image_desc image;   /* LG_PART_IMAGE */
    lg_volume_desc volume; /* LG_PART_VOLUME */
    lg_buffer_desc buffer; /* LG_PART_BUFFER and LG_PART_META (size <= LG_META_MAX) */
    uint32_t reserved[8];
} lg_part_spec;

/* A CPU mapping of an image or volume: rows of `width` pixels, `row_pixels` apart. */
typedef struct lg_cpu_view {
    void *pixels;      /* format as declared; NULL on failure */
    float *depth;      /* images with LG_IMAGE_DEPTH, else NULL */
    size_t row_pixels; /* pixels from one row to the next (== width today) */
    uint32_t reserved[4];
} lg_cpu_view;

/* The frame being executed. */
struct lg_frame {
    uint32_t index;         /* 0 .. count-1 */
    uint32_t count;         /* --frames */
    double time;            /* seconds since frame 0 (index * dt) */
    double dt;              /* seconds per frame (--dt, default 1/60) */
    uint32_t width, height; /* render size (--size), for nodes that make images from nothing */
    uint32_t reserved[8];
};

/* A node's work as a range of independent items (since ABI 3.3; lg_shard below says how the
 * host runs it). The caller owns every pointer; the host reads the struct during the call
 * only. */
typedef struct lg_shard_job {
    uint64_t count;      /* items: vertices, pixel rows, tiles; 0 runs nothing */
    uint64_t grain;      /* items per chunk, the unit of work handed out; >= 1 */
    uint64_t item_bytes; /* bytes of one item's result; >= 1 */
    void *out;           /* count * item_bytes bytes: every item's result, in item order */
    /* Computes items [begin, end) into `items`, (end - begin) * item_bytes bytes (on one
     * process that is out + begin * item_bytes; under MPI it may be a buffer of the
     * host's). Returns 0, or non-zero with a one-line reason in err (err_size bytes, NUL
     * terminated; the host adds the node, the items and the rank). */
    int (*run)(void *ctx, uint64_t begin, uint64_t end, void *items, char *err, size_t err_size);
    void *ctx;
    const char *what; /* the items' name, plural ("vertices", "pixel rows"), for messages
                       * and the profile; NULL reads "items" */
    union {
        uint32_t reserved[8];
        struct {
            /* Non-zero: this job is one of a family over the same items (count and grain
             * equal), e.g. a bake's passes; under MPI each rank first reruns the chunks it
             * ran in the family's previous job (see lg_shard, "Affinity"). 0: none. */
            uint32_t affinity;
            uint32_t reserved_3_3[7];
        };
    };
} lg_shard_job;

typedef struct lg_host_api {
    size_t struct_size; /* sizeof(lg_host_api) as the host was built */
    uint16_t abi_major, abi_minor;

    /* -- messages -- */
    void (*log)(lg_node *node, lg_log_level level, const char *fmt, va_list ap);
    void (*error)(lg_node *node, const char *fmt, va_list ap);
    /* fraction in [0,1]; shown on a terminal, silent otherwise */
    void (*progress)(lg_node *node, double fraction, const char *what);
    double (*now)(void); /* monotonic seconds */

    /* -- parameters (validated; indices follow the node type's params array) -- */
    const lg_value *(*param)(lg_node *node, uint32_t index);
    int32_t (*param_index)(lg_node *node, const char *key); /* -1 if not declared */

    /* -- ports -- */
    /* NULL for an unconnected optional input */
    const lg_resource *(*input)(lg_node *node, uint32_t port);
    lg_resource *(*output)(lg_node *node, uint32_t port);
    int (*describe)(const lg_resource *res, lg_resource_info *out);

    /* -- prepare(): declare outputs and how the node runs -- */
    int (*declare_image)(lg_node *node, uint32_t port, const lg_image_desc *desc);
    int (*declare_buffer)(lg_node *node, uint32_t port, const lg_buffer_desc *desc);
    int (*declare_volume)(lg_node *node, uint32_t port, const lg_volume_desc *desc);
    /* The output is the input, unchanged (no copy). */
    int (*declare_alias)(lg_node *node, uint32_t out_port, uint32_t in_port);
    /* Kinds whose data the plugin owns (scene). `payload` is freed by calling
     * free_payload(payload) when the last consumer is done; both live in the plugin.
     * `features` is copied. */
    int (*declare_payload)(lg_node *node, uint32_t port, lg_resource_kind kind,
                           const lg_scene_features *features, void *payload,
                           void (*free_payload)(void *payload));
    int (*set_device)(lg_node *node, lg_device device);
    void (*set_per_frame)(lg_node *node, bool per_frame);
    /* Adds bytes (e.g. a file's content hash) to what identifies this node's result in the
     * cache and in the results of everything downstream. */
    void (*add_content_key)(lg_node *node, const void *bytes, size_t size);

    /* -- execute(): residency-tracked access -- */
    int (*map_cpu)(lg_node *node, const lg_resource *res, unsigned access, lg_cpu_view *view);
    /* GL texture names (GL_TEXTURE_2D for images, GL_TEXTURE_3D for volumes, a buffer
     * object for buffers); *depth receives the GL_DEPTH_COMPONENT32F texture, or 0. */
    int (*map_gl)(lg_node *node, const lg_resource *res, unsigned access, uint32_t *name,
                  uint32_t *depth);
    /* CL buffers (cl_mem, as void *): pixels tightly packed in the declared format;
     * *depth receives a float buffer or NULL. */
    int (*map_cl)(lg_node *node, const lg_resource *res, unsigned access, void **mem, void **depth);

    /* -- devices -- */
    /* The GL 4.5 core function table (a GladGLContext, see lightgraph/gl.h) of the current
     * context, or NULL after reporting why. */
    const void *(*gl)(lg_node *node);
    /* cl_context, cl_command_queue (in order, profiling enabled), cl_device_id, or NULL */
    void *(*cl_context)(lg_node *node);
    void *(*cl_queue)(lg_node *node);
    void *(*cl_device)(lg_node *node);
    /* Builds an OpenCL program once per process (cached by source and options) and returns
     * the cl_program, owned by the host. `name` is the file name used in messages. On a
     * build failure, reports the build log and returns NULL. */
    void *(*cl_program)(lg_node *node, const char *name, const char *source, const char *options);
    /* Counts a finished or queued cl_event's execution time as this node's GPU time. The
     * host retains the event and releases it after reading its profile. */
    void (*cl_profile)(lg_node *node, void *event);
    /* Reports a GL error if glGetError() has one, with `what` as context. Returns 0 or
     * LG_ERR_DEVICE. */
    int (*gl_check)(lg_node *node, const char *what);

    /* -- on-disk cache for expensive static results --
     * Keys are scoped by the node's identity (plugin, version, type, parameters and the
     * identity of every input); `key` distinguishes several entries of one node. Entries
     * are checksummed; a stale or corrupt entry is reported, removed and treated as a
     * miss. cache_get returns LG_OK with a malloc'd copy the caller frees with
     * cache_free, or LG_ERR_NOTFOUND. Call them through lg_cache_get, lg_cache_put (or
     * lg_cache_store) and lg_cache_free. */
    int (*cache_get)(lg_node *node, const char *key, void **data, size_t *size);
    int (*cache_put)(lg_node *node, const char *key, const void *data, size_t size);
    void (*cache_free)(void *data);

    /* The render size (--size WxH, default 640x360), for nodes that make images from
     * nothing; usable from prepare() on. */
    void (*render_size)(lg_node *node, uint32_t *width, uint32_t *height);

    /* -- since ABI 1.1: GPU copies of plugin-owned payload data --
     * A read-only GL buffer object (or cl_mem) holding `size` bytes of `data`, an array of
     * the payload of resource `res` (a scene's vertex array, say), identified by `slot`.
     * Made on the first request, then returned again to every node that asks; owned and
     * freed by the host with the resource; its bytes are counted against the node that
     * made it. The payload is immutable, so data and size must be the same on every call
     * for a slot. Returns 0 or an LG_ERR_* after reporting. */
    int (*payload_gl_buffer)(lg_node *node, const lg_resource *res, uint32_t slot, const void *data,
                             size_t size, uint32_t *buffer);
    int (*payload_cl_buffer)(lg_node *node, const lg_resource *res, uint32_t slot, const void *data,
                             size_t size, void **mem);

    /* -- since ABI 2.0: CPU parallelism --
     * The host's thread pool, for nodes that run on the CPU; see lg_parallel_for below for
     * the contract. */
    uint32_t (*cpu_workers)(lg_node *node); /* threads the pool runs, >= 1 */
    int (*parallel_for)(lg_node *node, size_t n, size_t grain,
                        void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk), void *ctx);

    /* -- since ABI 2.0: composite resources (lightgraph/kinds.h) --
     * declare_composite: in prepare(), declares output `port` (of a composite kind) with
     * its parts; every part the kind requires must be given, each once. The parts are
     * host-managed: allocated where first mapped, moved only when a consumer on another
     * device reads, counted in the profile like any image or buffer.
     * part: the part called `name` of `res`, a resource this node received through an
     * input or declared as an output (else an error naming node and resource). A part is
     * a resource of kind image, volume or buffer: map it with map_cpu / map_gl / map_cl.
     * Returns NULL without an error for a neutral resource (a gated producer) or an
     * optional part the producer did not declare; NULL after reporting for a name the
     * kind does not declare. The handle lives as long as `res`. */
    int (*declare_composite)(lg_node *node, uint32_t port, const lg_part_spec *parts,
                             uint32_t n_parts);
    const lg_resource *(*part)(lg_node *node, const lg_resource *res, const char *name);

    /* -- since ABI 2.4: memory a plugin allocates itself --
     * Adds `bytes` to the memory the node's plugin holds (live), for memory the plugin
     * makes and keeps itself (a GL buffer of per-light geometry, a history volume), so
     * that a node's memory is all counted; account_free (ABI 3.0) takes it off again.
     * --profile's `allocated` is the node's resources plus the most the plugin held at
     * once (its peak), not the sum of every allocation. Call it once per allocation, where
     * the allocation happens, through lg_account_alloc(), which does nothing on an older
     * host. The SDK's device objects (lg_gl_buffer, lg_gl_texture in lightgraph/gl.h)
     * call it and account_free themselves. */
    void (*account_alloc)(lg_node *node, uint64_t bytes);

    /* -- since ABI 2.5: camera dependence, per instance --
     * In prepare(): whether this instance's results depend on the scene's camera, in place
     * of its type's LG_NODE_VIEW_INDEPENDENT flag (a shadow map fitted to the bounds does
     * not, one fitted to the camera's frustum does). The viewer runs a node that reads a
     * scene again when the camera moves unless it is view independent. Call it through
     * lg_set_view_independent(), which does nothing on an older host. */
    void (*set_view_independent)(lg_node *node, bool independent);

    /* -- since ABI 2.7: files a node writes --
     * Writes `size` bytes of `data` as the whole content of the file named by parameter
     * `key`, a PATH parameter the node type marks LG_ROLE_OUTPUT_FILE (lightgraph/plugin.h).
     * The bytes go into the temporary the host made beside the destination before anything
     * ran; the host renames it into place with the render's other outputs once everything
     * succeeded, and removes it on a failure or a signal. Calling it again replaces the
     * content (a node that runs every frame leaves the last frame's). Returns 0, or an
     * LG_ERR_* after reporting the reason (the key is not an output file, the value is "",
     * the write failed). The data is the caller's; the host copies it before returning.
     * `lightgraph view` writes no such file: there the parameter reads "" (the host says so
     * once), so a node that writes only when the value is not "" does nothing.
     * Call it through lg_output_file_write(). */
    int (*output_file_write)(lg_node *node, const char *key, const void *data, size_t size);

    /* -- since ABI 2.7: what a cache store did --
     * Stores like cache_put and says what happened: an lg_cache_store_result (>= 0), or an
     * LG_ERR_* (< 0) after reporting a missing or too long key or NULL data. Call it
     * through lg_cache_store(), which on an older host calls cache_put instead. */
    int (*cache_store)(lg_node *node, const char *key, const void *data, size_t size);

    /* -- since ABI 2.7: what a run will cost, declared before it starts --
     * In prepare(): one execute() of this node will do `units` of its own work (rays,
     * samples x texels, voxels x steps, ...: `what` names the unit, e.g. "occlusion
     * rays"), which should take about `seconds` of wall time here, the host's threads
     * working (the plugin's calibrated cost per unit, divided by lg_cpu_workers()). The
     * host shows it in --explain and warns before a render whose estimates add up to more
     * than a minute. A later call replaces an earlier one; `what` is copied. units and
     * seconds must be finite and >= 0, else the node fails (a plugin bug). Call it
     * through lg_declare_work(), which does nothing on an older host. */
    void (*declare_work)(lg_node *node, double units, double seconds, const char *what);

    /* -- since ABI 2.7: a cache entry whose values the node cannot have made --
     * The host's checksum proves only that an entry was written whole: anyone who can
     * write into the cache can write a well-formed one. A node that reads an entry checks
     * its values against what it can produce (finite, within the bounds of its
     * computation) and, for an entry that fails, calls this with the entry's `key` and
     * `why` (the bad value and where it is): the host warns as for a corrupt entry
     * ("cache entry PATH is corrupt (why); removing it and recomputing"), removes the
     * file and counts a miss in place of the hit; the node then recomputes as on a miss.
     * Call it through lg_cache_reject(), which on an older host only warns (the entry is
     * then replaced by the node's next cache_put). */
    void (*cache_reject)(lg_node *node, const char *key, const char *why);

    /* -- since ABI 3.0: memory a plugin releases --
     * The release matching an account_alloc of the same `bytes`: the profile then shows
     * the node's live device and host memory (allocated minus released, and its peak), so
     * that a buffer remade every frame is not counted once per frame. The SDK's device
     * objects (lg_gl_buffer, lg_gl_texture: lightgraph/gl.h; lg_cl_buffer: lightgraph/cl.h)
     * call both; a plugin that counts host memory itself calls lg_account_free() where it
     * frees. */
    void (*account_free)(lg_node *node, uint64_t bytes);

    /* Since ABI 3.1, in the place of the first reserved pointer (an anonymous union: the
     * struct keeps its 3.0 size and layout; a 3.0 host leaves it NULL): */
    union {
        void *reserved[19];
        struct {
            /* -- since ABI 3.1: GPU textures of plugin-owned payload images --
             * A GL 2D texture of `width` x `height` RGBA8 texels (`rgba8`, rows top to
             * bottom: row 0 at t = 0), an image of the payload of `res` (a scene's
             * texture) identified by `slot` (slots apart from payload_gl_buffer's), in
             * `internal_format` GL_SRGB8_ALPHA8 (colour: the sampler decodes sRGB) or
             * GL_RGBA8 (data), with its full mip chain (glGenerateTextureMipmap: the
             * driver's filter, a 2x2 box on Mesa). Made on the first request, then
             * returned to every node that asks; owned and freed by the host with the
             * resource; all its levels' bytes are counted against the node that made it.
             * Its own parameters are glTF's defaults (trilinear, repeat): sample it
             * through a sampler object. Returns 0 or an LG_ERR_* after reporting (a size
             * beyond GL_MAX_TEXTURE_SIZE: LG_ERR_UNSUPPORTED). Call it through
             * lg_scene_texture_gl (lightgraph/scene.h). */
            int (*payload_gl_texture)(lg_node *node, const lg_resource *res, uint32_t slot,
                                      const void *rgba8, uint32_t width, uint32_t height,
                                      uint32_t internal_format, uint32_t *texture);
            /* Since ABI 3.3, in the place of the first of reserved_3_1 (a 3.2 host leaves
             * it NULL; a 3.3 plugin does not load there): */
            union {
                void *reserved_3_1[18];
                struct {
                    /* -- since ABI 3.3: work shared over processes (MPI ranks) --
                     * Runs `job` (lg_shard_job above): see lg_shard below for the
                     * contract. */
                    int (*shard)(lg_node *node, const lg_shard_job *job);
                    void *reserved_3_3[17];
                };
            };
        };
    };
} lg_host_api;

/* A node as the host shows it to its plugin. The host owns it. */
struct lg_node {
    const lg_host_api *host;
    const char *name; /* the graph's name for this node, e.g. "tone" */
    const lg_node_type *type;
    void *user; /* the plugin's instance state (create .. destroy) */
    void *reserved[4];
};

/* ---- convenience wrappers -------------------------------------------------------------------- */

static inline void lg_log(lg_node *n, lg_log_level level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static inline void lg_log(lg_node *n, lg_log_level level, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    n->host->log(n, level, fmt, ap);
    va_end(ap);
}

/* Reports an error for this node and returns LG_ERR_INVALID, so that
 * `return lg_error(n, "...")` reads naturally. Use lg_error_code for another code. */
static inline int lg_error(lg_node *n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static inline int lg_error(lg_node *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    n->host->error(n, fmt, ap);
    va_end(ap);
    return LG_ERR_INVALID;
}

static inline int lg_error_code(lg_node *n, int code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
static inline int lg_error_code(lg_node *n, int code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    n->host->error(n, fmt, ap);
    va_end(ap);
    return code;
}

/* Parameters by key. The key must be one the node type declares: another key is an
 * error that fails the node (and aborts at once in a build with -Ddebug_abort=true), and
 * the wrappers then return the type's zero value. */
static inline const lg_value *lg_param(lg_node *n, const char *key)
{
    int32_t i = n->host->param_index(n, key);
    return i < 0 ? NULL : n->host->param(n, (uint32_t)i);
}
static inline double lg_param_float(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? v->f : 0.0;
}
static inline int64_t lg_param_int(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? v->i : 0;
}
static inline bool lg_param_bool(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? v->b : false;
}
static inline const char *lg_param_string(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? v->s : "";
}
/* LG_PARAM_ENUM: the index into enum_values. An LG_PARAM_COLOR with keywords (since ABI
 * 2.3, lightgraph/plugin.h): the keyword's index, or -1 when a colour was given (read it
 * from lg_param(n, key)->v). */
static inline int lg_param_enum(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? v->e : 0;
}
/* LG_PARAM_PATH_LIST (since ABI 2.2): the number of items, and item i (absolute paths,
 * host-owned, living as long as the node; NULL past the last). */
static inline uint32_t lg_param_list_count(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v && v->type == LG_PARAM_PATH_LIST && v->e > 0 ? (uint32_t)v->e : 0u;
}
static inline const char *lg_param_list_item(lg_node *n, const char *key, uint32_t i)
{
    const lg_value *v = lg_param(n, key);
    if (!v || v->type != LG_PARAM_PATH_LIST || v->e < 0 || i >= (uint32_t)v->e || !v->s)
        return NULL;
    const char *s = v->s;
    while (i--)
        s += strlen(s) + 1;
    return s;
}

static inline const lg_resource *lg_input(lg_node *n, uint32_t port)
{
    return n->host->input(n, port);
}
static inline lg_resource *lg_output(lg_node *n, uint32_t port)
{
    return n->host->output(n, port);
}
static inline int lg_describe(const lg_resource *r, lg_resource_info *info, lg_node *n)
{
    return n->host->describe(r, info);
}
static inline int lg_declare_image(lg_node *n, uint32_t port, const lg_image_desc *d)
{
    return n->host->declare_image(n, port, d);
}
static inline int lg_set_device(lg_node *n, lg_device d)
{
    return n->host->set_device(n, d);
}
static inline void lg_set_per_frame(lg_node *n, bool per_frame)
{
    n->host->set_per_frame(n, per_frame);
}
static inline int lg_map_cpu(lg_node *n, const lg_resource *r, unsigned access, lg_cpu_view *v)
{
    return n->host->map_cpu(n, r, access, v);
}
static inline int lg_map_gl(lg_node *n, const lg_resource *r, unsigned access, uint32_t *name,
                            uint32_t *depth)
{
    return n->host->map_gl(n, r, access, name, depth);
}
static inline int lg_map_cl(lg_node *n, const lg_resource *r, unsigned access, void **mem,
                            void **depth)
{
    return n->host->map_cl(n, r, access, mem, depth);
}

/* Messages and time. lg_progress: `fraction` of the work in [0, 1] (clamped), `what` the
 * work's name ("ray marching"); shown on a terminal, nothing otherwise. lg_now: the
 * host's monotonic clock in seconds (the clock the profile measures with), for timing a
 * phase of the node's own work; only differences between two readings mean anything. */
static inline void lg_progress(lg_node *n, double fraction, const char *what)
{
    n->host->progress(n, fraction, what);
}
static inline double lg_now(lg_node *n)
{
    return n->host->now();
}

/* The render size (--size WxH, default 640x360), from prepare() on. A node that makes an
 * image from nothing at a size its parameters may give reads lg_output_size instead. */
static inline void lg_render_size(lg_node *n, uint32_t *width, uint32_t *height)
{
    n->host->render_size(n, width, height);
}

/* More ways to declare an output in prepare() (besides lg_declare_image and
 * lg_declare_composite). Each returns 0, or an LG_ERR_* after reporting (a port the type
 * does not declare, a kind that differs from the port's, a call outside prepare()).
 *   lg_declare_buffer, lg_declare_volume: a host-managed buffer or 3D volume.
 *   lg_declare_alias: output `out_port` is input `in_port` itself, unchanged (no copy);
 *   the input must be connected.
 *   lg_declare_payload: an output of a kind whose data the plugin owns (LG_KIND_SCENE):
 *   `features` is copied; `payload` passes to the host, which calls free_payload(payload)
 *   when the last consumer is done, and at once when the call fails. */
static inline int lg_declare_buffer(lg_node *n, uint32_t port, const lg_buffer_desc *d)
{
    return n->host->declare_buffer(n, port, d);
}
static inline int lg_declare_volume(lg_node *n, uint32_t port, const lg_volume_desc *d)
{
    return n->host->declare_volume(n, port, d);
}
static inline int lg_declare_alias(lg_node *n, uint32_t out_port, uint32_t in_port)
{
    return n->host->declare_alias(n, out_port, in_port);
}
static inline int lg_declare_payload(lg_node *n, uint32_t port, lg_resource_kind kind,
                                     const lg_scene_features *features, void *payload,
                                     void (*free_payload)(void *payload))
{
    return n->host->declare_payload(n, port, kind, features, payload, free_payload);
}

/* Adds `size` bytes (a file's content hash, say) to what identifies this node's result in
 * the cache and in the results of every node downstream; the bytes are copied. */
static inline void lg_add_content_key(lg_node *n, const void *bytes, size_t size)
{
    n->host->add_content_key(n, bytes, size);
}

/* The on-disk cache (see cache_get above for keys and checksums).
 *   lg_cache_get: LG_OK with *data a malloc'd copy of entry `key` (*size bytes), which
 *   the caller frees with lg_cache_free; or LG_ERR_NOTFOUND (a miss, the cache off, or a
 *   stale or corrupt entry, reported and removed). A node that checks the values it loaded
 *   and finds them impossible calls lg_cache_reject.
 *   lg_cache_put: stores `size` bytes of `data` under `key` (the host copies them);
 *   LG_OK whether stored or the cache is off, LG_ERR_IO when the entry could not be
 *   written. lg_cache_store (below) is the same store saying which of these happened:
 *   prefer it.
 *   lg_cache_free: frees what lg_cache_get gave (NULL does nothing). */
static inline int lg_cache_get(lg_node *n, const char *key, void **data, size_t *size)
{
    return n->host->cache_get(n, key, data, size);
}
static inline int lg_cache_put(lg_node *n, const char *key, const void *data, size_t size)
{
    return n->host->cache_put(n, key, data, size);
}
static inline void lg_cache_free(lg_node *n, void *data)
{
    n->host->cache_free(data);
}

/* Since ABI 1.1: GPU copies of an array of a payload (see payload_gl_buffer above): a
 * read-only GL buffer object or cl_mem holding `size` bytes of `data`, which lies in the
 * payload of `res`, made once per (res, slot) and owned by the host. Returns 0 or an
 * LG_ERR_* after reporting. lightgraph/scene.h's lg_scene_mesh_gl / _cl call these. */
static inline int lg_payload_gl_buffer(lg_node *n, const lg_resource *res, uint32_t slot,
                                       const void *data, size_t size, uint32_t *buffer)
{
    return n->host->payload_gl_buffer(n, res, slot, data, size, buffer);
}
static inline int lg_payload_cl_buffer(lg_node *n, const lg_resource *res, uint32_t slot,
                                       const void *data, size_t size, void **mem)
{
    return n->host->payload_cl_buffer(n, res, slot, data, size, mem);
}
/* Since ABI 3.1: a GL texture of an RGBA8 image of a payload (payload_gl_texture above);
 * on an older host (no such entry) LG_ERR_UNSUPPORTED after reporting. */
static inline int lg_payload_gl_texture(lg_node *n, const lg_resource *res, uint32_t slot,
                                        const void *rgba8, uint32_t width, uint32_t height,
                                        uint32_t internal_format, uint32_t *texture)
{
    if (!n->host->payload_gl_texture) {
        *texture = 0;
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "this host (ABI 3.0) cannot make GL textures of a payload's "
                             "images: a 3.1 host is needed for textured scenes");
    }
    return n->host->payload_gl_texture(n, res, slot, rgba8, width, height, internal_format,
                                       texture);
}

/* ---- CPU parallelism (since ABI 2.0) ------------------------------------------------------------
 *
 * The host runs one thread pool for every node of the process: a node that parallelises
 * its CPU work through it shares the machine with the others instead of oversubscribing
 * it with threads of its own. Its size is one thread per online CPU, or the environment
 * variable LIGHTGRAPH_THREADS (1 makes every node single-threaded); the pool is made on
 * first use and joined at exit.
 *
 * lg_parallel_for(node, n, grain, fn, ctx) splits the indices [0, n) into chunks of
 * `grain` consecutive indices, the last one shorter:
 *
 *     chunk c = [c * grain, min(n, (c + 1) * grain)),   c = 0 .. ceil(n / grain) - 1
 *
 * and calls fn(ctx, begin, end, c) once per chunk, on the pool's threads and on the
 * calling thread (which works too). It returns when every chunk is done; everything fn
 * wrote is then visible to the caller.
 *
 *   Determinism. The chunks are a function of n and grain only, never of the number of
 *   threads. A reduction that writes chunk c's partial result into slot c of an array
 *   (ceil(n / grain) slots) and then combines the slots in index order on the calling
 *   thread gives bit-identical results whatever LIGHTGRAPH_THREADS says. Which thread
 *   runs a chunk, and in what order chunks run, is not specified.
 *   Thread safety. fn runs concurrently with itself: it may write only what its chunk
 *   owns (its output rows, its slot). It must not call host services (lg_log, lg_error,
 *   lg_map_*, devices, ...) except lg_cpu_workers; record a failure in the chunk's slot
 *   and report it from the calling thread afterwards. fn must not block waiting for
 *   another chunk.
 *   Grain. Pick it so that a chunk is worth a thread hand-off (tens of microseconds of
 *   work: some thousands of pixels) and so that n / grain is several times the worker
 *   count; a grain >= n runs fn once, on the calling thread, and costs nothing extra.
 *   Nesting. A call from inside fn runs all its chunks on the thread that made it, in
 *   chunk order (no deadlock, no extra parallelism). Calls from several threads of a
 *   plugin are serialised.
 *   Errors. Returns 0, or LG_ERR_INVALID after reporting (grain 0, fn NULL, more than
 *   2^32 - 1 chunks); nothing has run then. n == 0 runs nothing and returns 0.
 *   Call it from execute() (prepare() too); the node's profile counts the wall time.
 */
static inline uint32_t lg_cpu_workers(lg_node *n)
{
    return n->host->cpu_workers(n);
}
static inline int lg_parallel_for(lg_node *n, size_t count, size_t grain,
                                  void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk),
                                  void *ctx)
{
    return n->host->parallel_for(n, count, grain, fn, ctx);
}
/* The number of chunks lg_parallel_for makes of `count` indices: the size of a reduction's
 * per-chunk slot array. */
static inline size_t lg_parallel_chunks(size_t count, size_t grain)
{
    return grain ? count / grain + (count % grain != 0) : 0;
}

/* lg_shard (since ABI 3.3): a node's work spread over every process of the job.
 *
 *   A node whose execute() does one big computation that splits into `count` independent
 *   items of a fixed size (a PRT bake's per-vertex transfer, a reference renderer's pixel
 *   rows) hands it to the host as an lg_shard_job and gets back `out` filled. In a plain
 *   run this is lg_parallel_for(count, grain) over the host's threads, writing into `out`
 *   directly, at no extra cost. Under `mpirun -np N lightgraph ...` (a build with MPI,
 *   docs/distributed.md) every rank runs the same graph; at this call the ranks take
 *   chunks of `grain` items in turn as each finishes its last (dynamic chunks: a rank
 *   that draws costly items takes fewer), each runs its chunks on its own threads, and
 *   then every rank receives every item, so `out` is complete on all of them and the
 *   graph goes on identically everywhere. Only rank 0 writes output files and cache
 *   entries.
 *
 *   Determinism, the contract that makes this work. An item's bytes must depend only on
 *   its index and on the node's inputs and parameters: never on the chunk, the thread,
 *   the rank, the time or a shared random stream (seed a generator from the item index).
 *   Then `out` has the same bits for any number of ranks, threads or any schedule, which
 *   the host's tests check with 1, 2 and 3 ranks. A reduction over items (a sum, a
 *   maximum) is done by the node after the call, over `out` in item order.
 *
 *   run. Called concurrently from the host's threads with disjoint ranges, each a whole
 *   number of chunks' worth or the tail; like lg_parallel_for's fn it writes only its own
 *   items and calls no host service (report through err, not lg_error). A nested
 *   lg_parallel_for or lg_shard inside run runs inline on that thread.
 *
 *   Errors. A run that fails stops the job: no chunk starts after it on any rank, and the
 *   call returns LG_ERR_INVALID on every rank after the host reported "items B..E on rank
 *   R: reason" for the node (under MPI rank 0 prints it; the command exits 1 and writes
 *   no output file and no cache entry). Also LG_ERR_INVALID after reporting for a bad
 *   job (grain or item_bytes 0, run or out NULL, count * item_bytes overflowing) and
 *   LG_ERR_NOMEM. `out`'s bytes are unspecified after a failure.
 *
 *   Affinity. A node whose passes run over the same items, each keeping per-item state of
 *   its own between passes (a bake's ray hits from its direct pass, reused by each
 *   bounce), gives every pass's job the same non-zero `affinity` (any number the node
 *   chooses; distinct families of one run need distinct numbers) and the same count and
 *   grain. Under MPI, in every job of the family after the first, each rank first takes
 *   the chunks it computed in the family's previous job, and when those are done steals
 *   the chunks other ranks have not claimed yet, so a rank mostly meets the items whose
 *   state it kept and a slow rank still gets help. A job whose count or grain differs
 *   starts the family afresh (dynamic chunks). Placement stays invisible: `out` has the
 *   same bits as without affinity; a node that keeps per-item state must still compute
 *   an item whose state it lacks. In one process affinity changes nothing.
 *
 *   Every rank must make the same calls in the same order (the same graph does). Call
 *   it from execute(). A job of under a few milliseconds gains nothing from ranks; the
 *   host may run a small job (count * item_bytes under a page, or count <= grain) on
 *   each rank alone, which the contract makes invisible. */
static inline int lg_shard(lg_node *n, const lg_shard_job *job)
{
    return n->host->shard(n, job);
}

/* The size of an image a node makes from two INT parameters (normally "width" and
 * "height", but any keys the node type declares), where 0 (or a negative value, which
 * ranges normally forbid) means the render size (--size). A key the type does not
 * declare is an error (lg_param). */
static inline void lg_output_size(lg_node *n, const char *width_key, const char *height_key,
                                  uint32_t *width, uint32_t *height)
{
    uint32_t rw = 0, rh = 0;
    n->host->render_size(n, &rw, &rh);
    int64_t w = lg_param_int(n, width_key), h = lg_param_int(n, height_key);
    *width = w > 0 ? (uint32_t)w : rw;
    *height = h > 0 ? (uint32_t)h : rh;
}

/* ---- create() and prepare() openings ------------------------------------------------------------
 *
 * lg_create_state(n, size): the node's instance state: `size` bytes, zeroed, stored in
 * n->user and returned; NULL after reporting "out of memory" (create() then returns
 * LG_ERR_NOMEM). The plugin owns it and frees it in destroy(), which the host calls after
 * a failed create() too: create() may fail after this call without freeing anything.
 *
 * lg_output_size_nonempty(n, width_key, height_key, &w, &h): lg_output_size, and an error
 * (LG_ERR_INVALID after reporting "output size WxH: width and height must be > 0") when
 * either is 0; else 0.
 */
static inline void *lg_create_state(lg_node *n, size_t size)
{
    void *st = calloc(1, size);
    if (!st) {
        lg_error_code(n, LG_ERR_NOMEM, "out of memory");
        return NULL;
    }
    n->user = st;
    return st;
}
static inline int lg_output_size_nonempty(lg_node *n, const char *width_key, const char *height_key,
                                          uint32_t *width, uint32_t *height)
{
    lg_output_size(n, width_key, height_key, width, height);
    if (*width == 0 || *height == 0)
        return lg_error(n, "output size %ux%u: width and height must be > 0", *width, *height);
    return 0;
}

/* ---- inputs the checker guarantees --------------------------------------------------------------
 *
 * Before any node runs, the host checks the graph and refuses (exit status 2, naming the
 * node and the input) one that leaves a required input (lg_port_desc.optional false)
 * unconnected or connects it to an output of another kind (LG_KIND_ANY on either side
 * matches any). From prepare() on, lg_input() on a required input therefore gives a
 * resource of the kind the port declares: a node needs no "is not connected" or "is not
 * a scene" check of its own there. The resource may be a gated producer's neutral result
 * (lg_resource_info.neutral: of the kind, but a scene without data, a composite without
 * parts). An optional input is NULL when unconnected: check that one.
 *
 * lg_assert_input(n, port) says where a node relies on this. In a build that defines
 * LG_DEBUG_CHECKS (lightgraph's own, unless -Ddebug_checks=false) it checks it and, if it
 * does not hold (a bug: the port is optional or does not exist, or the host broke its
 * word), reports it and aborts; otherwise it is nothing.
 */
static inline void lg_assert_input(lg_node *n, uint32_t port)
{
#ifdef LG_DEBUG_CHECKS
    const lg_node_type *t = n->type;
    if (!t || port >= t->n_inputs || t->inputs[port].optional) {
        lg_error(n,
                 "lg_assert_input: input #%u of type '%s' is not a required input (a "
                 "plugin bug)",
                 port, t && t->name ? t->name : "?");
        abort();
    }
    const lg_resource *r = n->host->input(n, port);
    lg_resource_info info;
    if (!r || n->host->describe(r, &info) != 0 ||
        (t->inputs[port].kind != LG_KIND_ANY && info.kind != t->inputs[port].kind)) {
        lg_error(n,
                 "lg_assert_input: required input '%s' is %s, which the host's graph "
                 "check rules out (a host bug)",
                 t->inputs[port].name, r ? "of another kind" : "not connected");
        abort();
    }
#else
    (void)n, (void)port;
#endif
}

/* Composite resources (since ABI 2.0). */
static inline int lg_declare_composite(lg_node *n, uint32_t port, const lg_part_spec *parts,
                                       uint32_t n_parts)
{
    return n->host->declare_composite(n, port, parts, n_parts);
}
static inline const lg_resource *lg_part(lg_node *n, const lg_resource *r, const char *name)
{
    return n->host->part(n, r, name);
}

/* Since ABI 2.4: counts memory the plugin allocated itself (see account_alloc). A no-op on
 * an older host. */
static inline void lg_account_alloc(lg_node *n, uint64_t bytes)
{
    if (n->host->struct_size >= offsetof(lg_host_api, account_alloc) + sizeof(void *) &&
        n->host->account_alloc)
        n->host->account_alloc(n, bytes);
}

/* Since ABI 3.0: the release of memory counted with lg_account_alloc (see account_free). */
static inline void lg_account_free(lg_node *n, uint64_t bytes)
{
    if (n->host->account_free)
        n->host->account_free(n, bytes);
}

/* Since ABI 3.0: the device the node's `backend` parameter (LG_PARAM_BACKEND,
 * lightgraph/plugin.h) names: LG_DEVICE_CPU, LG_DEVICE_GL or LG_DEVICE_CL. A node type
 * without the parameter gets LG_DEVICE_CPU. */
static inline lg_device lg_param_backend(lg_node *n)
{
    const lg_value *v = lg_param(n, "backend");
    if (!v || v->type != LG_PARAM_ENUM || !v->s)
        return LG_DEVICE_CPU;
    if (strcmp(v->s, "gl") == 0)
        return LG_DEVICE_GL;
    if (strcmp(v->s, "cl") == 0)
        return LG_DEVICE_CL;
    return LG_DEVICE_CPU;
}

/* Since ABI 2.7: rejects the cache entry `key` that cache_get returned (see cache_reject).
 * On an older host: the same warning from the node, and the file stays until the node's
 * cache_put replaces it. */
static inline void lg_cache_reject(lg_node *n, const char *key, const char *why)
{
    if (n->host->struct_size >= offsetof(lg_host_api, cache_reject) + sizeof(void *) &&
        n->host->cache_reject)
        n->host->cache_reject(n, key, why);
    else
        lg_log(n, LG_LOG_WARN, "cache entry '%s' is corrupt (%s); computing it again", key, why);
}

static inline void lg_set_view_independent(lg_node *n, bool independent)
{
    if (n->host->struct_size >= offsetof(lg_host_api, set_view_independent) + sizeof(void *) &&
        n->host->set_view_independent)
        n->host->set_view_independent(n, independent);
}

/* Since ABI 2.7: writes the file named by output-file parameter `key` (see
 * output_file_write; the only way a plugin writes a file). On an older host, which cannot
 * write it all or nothing, reports that and returns LG_ERR_UNSUPPORTED: nothing is
 * written. */
static inline int lg_output_file_write(lg_node *n, const char *key, const void *data, size_t size)
{
    if (n->host->struct_size >= offsetof(lg_host_api, output_file_write) + sizeof(void *) &&
        n->host->output_file_write)
        return n->host->output_file_write(n, key, data, size);
    return lg_error_code(n, LG_ERR_UNSUPPORTED,
                         "cannot write the file of parameter '%s': this host (ABI %u.%u) has "
                         "no output_file_write; ABI 2.7 or later is needed",
                         key ? key : "", (unsigned)n->host->abi_major,
                         (unsigned)n->host->abi_minor);
}

/* What lg_cache_store did with an entry (since ABI 2.7), for a message that says so: a
 * node that logs "cached" when nothing was stored sends its user looking for a file that
 * is not there. */
typedef enum lg_cache_store_result {
    LG_CACHE_STORED = 0,     /* on disk: a later render with the same identity finds it */
    LG_CACHE_OFF = 1,        /* the cache is disabled for this render (the host warned once
                              * why): nothing stored */
    LG_CACHE_NOT_STORED = 2, /* the entry could not be written (the host warned why) */
    LG_CACHE_UNKNOWN = 3     /* a host older than ABI 2.7 took the entry: whether it stored
                              * it, it does not say */
} lg_cache_store_result;

/* Stores `size` bytes of `data` under `key` (cache_put's contract: the host copies them,
 * the caller keeps ownership) and returns an lg_cache_store_result, or an LG_ERR_* (< 0)
 * for a bad key or NULL data. Not storing is no error: the result is only lost speed. On a
 * host older than ABI 2.7 it calls cache_put: LG_CACHE_UNKNOWN when that returned LG_OK
 * (stored, or the cache was off), LG_CACHE_NOT_STORED for LG_ERR_IO. */
static inline int lg_cache_store(lg_node *n, const char *key, const void *data, size_t size)
{
    if (n->host->struct_size >= offsetof(lg_host_api, cache_store) + sizeof(void *) &&
        n->host->cache_store)
        return n->host->cache_store(n, key, data, size);
    int rc = n->host->cache_put(n, key, data, size);
    return rc == LG_OK ? LG_CACHE_UNKNOWN : rc == LG_ERR_IO ? LG_CACHE_NOT_STORED : rc;
}

/* Since ABI 2.7: the estimated cost of one execute() (see declare_work). A no-op on an
 * older host. */
static inline void lg_declare_work(lg_node *n, double units, double seconds, const char *what)
{
    if (n->host->struct_size >= offsetof(lg_host_api, declare_work) + sizeof(void *) &&
        n->host->declare_work)
        n->host->declare_work(n, units, seconds, what);
}

/* Mip levels of an image description (0 means 1), faces (6 for a cube, else 1), and
 * the size of one level. */
static inline uint32_t lg_image_levels(const lg_image_desc *d)
{
    return d->levels ? d->levels : 1;
}
static inline uint32_t lg_image_faces(const lg_image_desc *d)
{
    return (d->flags & LG_IMAGE_CUBE) ? 6u : 1u;
}
static inline uint32_t lg_image_level_width(const lg_image_desc *d, uint32_t level)
{
    uint32_t w = d->width >> level;
    return w ? w : 1;
}
static inline uint32_t lg_image_level_height(const lg_image_desc *d, uint32_t level)
{
    uint32_t h = d->height >> level;
    return h ? h : 1;
}
/* Pixels from the start of an image's colour data (CPU copy or CL buffer) to the first
 * pixel of `face` of `level`; with level == levels it is the total pixel count. */
static inline size_t lg_image_offset(const lg_image_desc *d, uint32_t level, uint32_t face)
{
    size_t off = 0;
    for (uint32_t l = 0; l < level; l++)
        off += (size_t)lg_image_level_width(d, l) * lg_image_level_height(d, l) * lg_image_faces(d);
    if (level < lg_image_levels(d))
        off += (size_t)face * lg_image_level_width(d, level) * lg_image_level_height(d, level);
    return off;
}

/* Bytes per pixel of a format. */
static inline size_t lg_format_size(lg_format f)
{
    return f == LG_FORMAT_RGBA32F                           ? 16
           : f == LG_FORMAT_RGBA16F                         ? 8
           : (f == LG_FORMAT_RGBA8 || f == LG_FORMAT_RGBE8) ? 4
                                                            : 0;
}

#ifdef __cplusplus
}
#endif
#endif
