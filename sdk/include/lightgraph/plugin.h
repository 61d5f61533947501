/*
 * lightgraph/plugin.h: what a plugin is.
 *
 * A plugin is a shared object that exports exactly one symbol, `lg_plugin_entry`, a
 * function returning a pointer to a constant `lg_plugin_desc`. Everything else a plugin
 * offers is data in that descriptor: its node types, each with its parameters, its
 * input and output ports, the scene features it needs to have any work, and four
 * callbacks (create, prepare, execute, destroy).
 *
 *     static const lg_param_desc params[] = {
 *         { .key = "factor", .type = LG_PARAM_FLOAT, .def.f = 1.0, .min = 0, .max = 1e6,
 *           .doc = "multiplier applied to every channel" },
 *     };
 *     static const lg_port_desc inputs[]  = { { .name = "image", .kind = LG_KIND_IMAGE } };
 *     static const lg_port_desc outputs[] = { { .name = "out",   .kind = LG_KIND_IMAGE } };
 *     static const lg_node_type types[] = { {
 *         .struct_size = sizeof(lg_node_type), .name = "scale", .doc = "...",
 *         LG_PARAMS(params), LG_INPUTS(inputs), LG_OUTPUTS(outputs),
 *         .prepare = scale_prepare, .execute = scale_execute,
 *     } };
 *     LG_PLUGIN_DEFINE("core", "1.0.0", "Basic image nodes", types)
 *
 * Lifetime. The host loads a plugin (dlopen) only after planning, and only if a kept,
 * ungated node of the graph uses one of its types. It keeps the plugin loaded until every
 * instance and every resource the plugin made is gone. The descriptor and all the data it
 * points to must stay valid and unchanged for as long as the plugin is loaded.
 *
 * Versioning. The descriptor starts with its own size and the ABI version the plugin was
 * built against (LG_ABI_MAJOR/LG_ABI_MINOR from lightgraph/config.h). The host refuses a
 * plugin whose major differs from its own or whose minor is newer, naming the file and
 * both versions. Public structs end in reserved fields that must be zero; a later minor
 * version may give them a meaning where zero keeps the old behaviour.
 *
 * Threading. The host calls every callback of every node from one thread, the thread that
 * owns the GL context.
 */
#ifndef LIGHTGRAPH_PLUGIN_H
#define LIGHTGRAPH_PLUGIN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Parameters ------------------------------------------------------------------------------ */

typedef enum lg_param_type {
    LG_PARAM_BOOL = 1,  /* true / false                                        -> v.b    */
    LG_PARAM_INT,       /* 64-bit integer                                      -> v.i    */
    LG_PARAM_FLOAT,     /* double                                              -> v.f    */
    LG_PARAM_VEC2,      /* [x, y]                                              -> v.v[0..1] */
    LG_PARAM_VEC3,      /* [x, y, z]                                           -> v.v[0..2] */
    LG_PARAM_COLOR,     /* [r, g, b], linear (or a keyword, see below)         -> v.v[0..2] */
    LG_PARAM_STRING,    /* "text"                                              -> v.s    */
    LG_PARAM_PATH,      /* "file", resolved against the graph file that set it -> v.s    */
    LG_PARAM_ENUM,      /* one of enum_values; v.e is its index, v.s its name            */
    LG_PARAM_INT3,      /* [i, j, k]                                           -> v.i3   */
    LG_PARAM_PATH_LIST, /* since ABI 2.2: ["file", ...], each resolved like a PATH -> v.s, v.e */
} lg_param_type;

/* A parameter value. The host owns the strings; they live as long as the node.
 * LG_PARAM_PATH_LIST (since ABI 2.2): e is the number of items and s holds them packed,
 * each followed by its NUL ("a\0b\0" for two; "" for none); read them with
 * lg_param_list_count and lg_param_list_item (lightgraph/host.h). Its default is always
 * the empty list (the registry refuses another). */
typedef struct lg_value {
    lg_param_type type;
    int32_t e; /* LG_PARAM_ENUM: index into enum_values; LG_PARAM_PATH_LIST: item count;
                * LG_PARAM_COLOR with keywords: the keyword's index, -1 for a colour */
    union {
        bool b;
        int64_t i;
        double f;
        double v[4];
        int64_t i3[3];
        const char *s; /* STRING, PATH, ENUM */
    };
} lg_value;

/* What a parameter means to the host beyond its type (lg_param_desc.role, since ABI 2.1;
 * zero, the default, says nothing). `lightgraph check` uses it to refuse, before anything
 * runs, what the parameters alone make impossible. */
typedef enum lg_param_role {
    LG_ROLE_NONE = 0,
    /* INT: the width / height in pixels of the images the node makes, 0 meaning the render
     * size (as lg_output_size reads them). A node type that declares one of the pair
     * declares both. With both set above 0, check refuses width x height beyond the pixel
     * limit (lg_image_max_pixels(), LIGHTGRAPH_MAX_PIXELS) naming the node, the two
     * parameters and the limit. */
    LG_ROLE_IMAGE_WIDTH,
    LG_ROLE_IMAGE_HEIGHT,
    /* since ABI 2.7: PATH: a file the node writes (a debug dump, a mesh), "" meaning none.
     * The default must be "" (the registry refuses another): a file is written only when
     * the graph or --set names it. The host checks the destination with the render's other
     * outputs before anything runs (its directory exists; it is not a directory, a FIFO or
     * a device; no other output names it), and the node writes it only through
     * lg_output_file_write (lightgraph/host.h): into a temporary beside it that is renamed
     * with the render's other outputs when everything succeeded, or removed. A plugin never
     * writes files itself. */
    LG_ROLE_OUTPUT_FILE,
} lg_param_role;

/* One parameter of a node type, declared as data. Zero means "no": min == max means no
 * range; a NULL enum_values or renamed_from means none. For vectors and colours the
 * range applies to every component.
 *
 * Colours that also take keywords (since ABI 2.3). An LG_PARAM_COLOR with enum_values
 * accepts either a colour [r, g, b] or one of the keywords, written as a bare word like
 * an enum (`albedo = material`, `--set bake.albedo=material`, `--set bake.albedo=[1,1,1]`).
 * The node reads lg_value.e: the keyword's index into enum_values, or -1 when a colour was
 * given, which is then in v.v[0..2] (range-checked against min and max; v.v is zero when
 * a keyword was given). The default follows the same rule: .def.e is the index of the
 * default keyword, or -1 with the colour in .def.v, e.g.
 *     static const char *const albedo_kw[] = {"material", NULL};
 *     {.key = "albedo", .type = LG_PARAM_COLOR, .def.e = 0, .enum_values = albedo_kw,
 *      .min = 0, .max = 1, .doc = "material | [r, g, b]"}                  default material
 *     {..., .def = {.e = -1, .v = {0.8, 0.8, 0.8}}, .enum_values = albedo_kw, ...}  a grey
 * (.def.s cannot name the keyword: it shares its storage with .def.v.) Without
 * enum_values a colour is a colour and e is 0, as before ABI 2.3. */
typedef struct lg_param_desc {
    const char *key; /* snake_case name used in graph files */
    lg_param_type type;
    lg_value def;                    /* default; .type need not be set */
    double min, max;                 /* inclusive range of numeric values */
    const char *const *enum_values;  /* LG_PARAM_ENUM (and, optionally, LG_PARAM_COLOR
                                      * keywords): a NULL-terminated list */
    const char *doc;                 /* one line: meaning and unit */
    const char *const *renamed_from; /* old keys still accepted, with a warning */
    /* lg_param_role (since ABI 2.1). It takes the place of the first of four reserved
     * pointers, which ABI 2.0 plugins leave zero: the struct's size and the offsets of
     * the other fields are unchanged. */
    uint32_t role;
    void *reserved[3];
} lg_param_desc;

/* ---- Ports ----------------------------------------------------------------------------------- */

/* One input or output. In a graph file an input is set like a parameter whose value is a
 * reference to another node (`image = src` or `image = src.out`). */
typedef struct lg_port_desc {
    const char *name;
    lg_resource_kind kind;
    bool optional; /* inputs only: may be left unconnected (the host passes NULL) */
    const char *doc;
    void *reserved[2];
} lg_port_desc;

/* ---- Node types ------------------------------------------------------------------------------ */

/* Scene features a node needs to have anything to do (all of them). A kept node whose
 * needs the scene upstream of it does not meet is gated: it never runs, its plugin is
 * never loaded, and its outputs are its neutral result (see lg_neutral). */
enum {
    LG_NEEDS_GEOMETRY = 1u << 0,    /* at least one triangle */
    LG_NEEDS_LIGHT = 1u << 1,       /* at least one light of any type */
    LG_NEEDS_DIR_LIGHT = 1u << 2,   /* at least one directional light */
    LG_NEEDS_POINT_LIGHT = 1u << 3, /* at least one point light */
    LG_NEEDS_MEDIUM = 1u << 4,      /* a participating medium with density > 0 */
    LG_NEEDS_PROBE = 1u << 5,       /* a light probe */
    LG_NEEDS_SPECULAR = 1u << 6,    /* a material with a non-zero specular term */
    LG_NEEDS_REFLECTIVE = 1u << 7,  /* since ABI 2.2: a material with a non-zero
                                     * reflectivity (lg_material.reflectivity) */
    LG_NEEDS_TEXTURES = 1u << 8,    /* since ABI 3.1: a drawn material samples a texture
                                     * (lg_scene_features.textures) */
};

/* What stands in for a gated node's outputs. */
typedef enum lg_neutral {
    LG_NEUTRAL_ZERO = 0,          /* images: black, at the size of the first image input, or the
                                   * render size; other kinds: an empty resource */
    LG_NEUTRAL_PASSTHROUGH,       /* every output is the input named by neutral_input */
    LG_NEUTRAL_PASSTHROUGH_FIRST, /* since ABI 2.4: output 0 is the input named by
                                   * neutral_input, the others as LG_NEUTRAL_ZERO (a filter whose
                                   * second output is an effect alone: volumetric `out` passes
                                   * the lit image through, `inscatter` is black) */
} lg_neutral;

/* Node type flags. */
enum {
    /* The node has an effect outside the graph (writes a file, presents a window): it is
     * kept even when no output statement reaches it. */
    LG_NODE_SIDE_EFFECT = 1u << 0,
    /* The node's result depends on the frame (time, state carried between frames): it
     * runs every frame even when its inputs do not change. prepare() may also decide this
     * per instance with lg_set_per_frame(). */
    LG_NODE_PER_FRAME = 1u << 1,
    /* since ABI 2.5: the node's results do not depend on the scene's camera although it
     * reads a scene (a transfer bake, a shadow map fitted to the scene's bounds): when the
     * viewer moves the camera it does not run the node again. Without the flag a node that
     * reads a scene runs again on every camera move (correct, maybe slower). */
    LG_NODE_VIEW_INDEPENDENT = 1u << 2,
    /* since ABI 2.5: the node's image outputs hold display-referred values in [0, 1] (a
     * tone mapper): the viewer shows an image at or downstream of such a node as it is,
     * and any other image with an exposure it chooses (lightgraph view). */
    LG_NODE_DISPLAY_REFERRED = 1u << 3,
    /* since ABI 3.1: the node's results do not depend on where the scene's animation puts
     * its instances (a PRT transfer bake, made in each mesh's own frame): when the scene is
     * animated it still runs once. Without the flag, a node that reads an animated scene
     * runs every frame (lg_scene_pose at lg_frame.time gives the instances' matrices). */
    LG_NODE_POSE_INDEPENDENT = 1u << 4,
    /* since ABI 3.1: the node's cache entries (lg_cache_get, lg_cache_store) are named by
     * its plugin, version, type, parameters, its own content keys and the entry's key, but
     * NOT by its inputs' identities. The node then puts into each key (as a digest) all of
     * its inputs that its result depends on: what it leaves out may change without the
     * entry changing. For a result that depends on a part of an input only (prt_bake's
     * transfer: a scene's geometry, factors and alpha masks, not its base colour images),
     * so that a change to the rest finds the entry instead of computing it again. */
    LG_NODE_CACHE_BY_CONTENT = 1u << 5,
};

typedef struct lg_node lg_node; /* a node instance, as the host shows it (lightgraph/host.h) */
typedef struct lg_frame lg_frame;

/* Callbacks. All return 0 on success or a negative LG_ERR_* code after reporting the
 * reason with lg_error(); the host then stops with exit status 1 and names the node.
 *
 * create:  make the instance state from the (validated) parameters, read with
 *          lg_param_*(). Store it in node->user. Optional (node->user stays NULL).
 * prepare: read the descriptions of the inputs, declare every output (lg_declare_*), say
 *          which device the node runs on (lg_set_device) and whether it runs per frame.
 *          No GPU work here. Called once, after all upstream nodes are prepared.
 * execute: do the frame's work: map inputs for reading and outputs for writing on the
 *          device of choice and fill the outputs. Called once per frame for per-frame
 *          nodes, once in all for the others.
 * destroy: free node->user. Called once, even after a failed create or prepare; may find
 *          node->user NULL. GL and CL objects may be deleted here (the context is
 *          current). */
typedef int (*lg_create_fn)(lg_node *node);
typedef int (*lg_prepare_fn)(lg_node *node);
typedef int (*lg_execute_fn)(lg_node *node, const lg_frame *frame);
typedef void (*lg_destroy_fn)(lg_node *node);

typedef struct lg_node_type {
    size_t struct_size; /* sizeof(lg_node_type) */
    const char *name;   /* unique across all plugins: [a-z][a-z0-9_]* */
    const char *doc;    /* one line */
    const lg_param_desc *params;
    uint32_t n_params;
    const lg_port_desc *inputs;
    uint32_t n_inputs;
    const lg_port_desc *outputs;
    uint32_t n_outputs;
    uint32_t needs;         /* LG_NEEDS_* */
    uint32_t flags;         /* LG_NODE_* */
    lg_neutral neutral;     /* what a gated node yields */
    uint32_t neutral_input; /* LG_NEUTRAL_PASSTHROUGH: index of the input passed through */
    lg_create_fn create;
    lg_prepare_fn prepare;
    lg_execute_fn execute;
    lg_destroy_fn destroy;
    /* since ABI 3.0: how far the outputs of this node's backends may differ on the same
     * input and still agree: the largest absolute difference of any channel divided by
     * max(1, the largest absolute value of the reference (cpu) output), as `lightgraph
     * conform` measures it. 0 means the default, 1e-3. A node with one backend leaves it 0. */
    double tolerance;
    void *reserved[7];
} lg_node_type;

/* ---- The backend parameter (since ABI 3.0) --------------------------------------------------- */

/* A node that runs on more than one device declares the one shared parameter `backend`
 * with this macro, naming the set of backends it has and the default; the choices are
 * always listed in the order cpu, gl, cl:
 *
 *     static const lg_param_desc params[] = {
 *         LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL | LG_BACKEND_CL, LG_BACKEND_GL),
 *         ...
 *     };
 *     lg_device dev = lg_param_backend(node);   // lightgraph/host.h, in create or prepare
 *
 * The default must be one of the set (a compile-time error otherwise). */
enum { LG_BACKEND_CPU = 1u << 0, LG_BACKEND_GL = 1u << 1, LG_BACKEND_CL = 1u << 2 };

/* The NULL-terminated choices of each set, indexed by the set (1..7), in the order cpu, gl,
 * cl. Data of liblightgraph. */
LG_API extern const char *const lg_backend_names[8][4];

#define LG_BACKEND_INDEX_(set_, def_)                                                              \
    ((((def_) > LG_BACKEND_CPU && ((set_)&LG_BACKEND_CPU)) ? 1 : 0) +                              \
     (((def_) > LG_BACKEND_GL && ((set_)&LG_BACKEND_GL)) ? 1 : 0))
#define LG_PARAM_BACKEND(set_, def_)                                                               \
    {                                                                                              \
        .key = "backend", .type = LG_PARAM_ENUM,                                                   \
        .def.e = LG_BACKEND_INDEX_(set_, def_) +                                                   \
                 0 * (int)sizeof(char[(((set_) & (def_)) && ((def_) & ((def_)-1)) == 0 &&          \
                                       (set_) > 0 && (set_) < 8)                                   \
                                          ? 1                                                      \
                                          : -1]),                                                  \
        .enum_values = lg_backend_names[(set_)],                                                   \
        .doc = "the device the node runs on: cpu (the reference), gl (OpenGL compute or "          \
               "raster), cl (OpenCL)",                                                             \
    }

#define LG_PARAMS(a) .params = (a), .n_params = (uint32_t)(sizeof(a) / sizeof((a)[0]))
#define LG_INPUTS(a) .inputs = (a), .n_inputs = (uint32_t)(sizeof(a) / sizeof((a)[0]))
#define LG_OUTPUTS(a) .outputs = (a), .n_outputs = (uint32_t)(sizeof(a) / sizeof((a)[0]))

/* ---- The plugin descriptor ------------------------------------------------------------------- */

typedef struct lg_plugin_desc {
    size_t struct_size;  /* sizeof(lg_plugin_desc) as the plugin was built */
    uint16_t abi_major;  /* LG_ABI_MAJOR */
    uint16_t abi_minor;  /* LG_ABI_MINOR */
    const char *name;    /* [a-z][a-z0-9_]*, the plugin's folder name */
    const char *version; /* the plugin's own version; part of every cache key */
    const char *doc;     /* one line */
    const lg_node_type *types;
    uint32_t n_types;
    void *reserved[8];
} lg_plugin_desc;

/* The one symbol a plugin exports. */
#define LG_PLUGIN_ENTRY_NAME "lg_plugin_entry"
typedef const lg_plugin_desc *(*lg_plugin_entry_fn)(void);

/* Defines the descriptor and the entry symbol. Use once per plugin, at file scope. */
#define LG_PLUGIN_DEFINE(name_, version_, doc_, types_)                                            \
    static const lg_plugin_desc lg_plugin_desc_ = {                                                \
        .struct_size = sizeof(lg_plugin_desc),                                                     \
        .abi_major = LG_ABI_MAJOR,                                                                 \
        .abi_minor = LG_ABI_MINOR,                                                                 \
        .name = (name_),                                                                           \
        .version = (version_),                                                                     \
        .doc = (doc_),                                                                             \
        .types = (types_),                                                                         \
        .n_types = (uint32_t)(sizeof(types_) / sizeof((types_)[0])),                               \
    };                                                                                             \
    LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void);                                  \
    LG_PLUGIN_EXPORT const lg_plugin_desc *lg_plugin_entry(void)                                   \
    {                                                                                              \
        return &lg_plugin_desc_;                                                                   \
    }

#ifdef __cplusplus
}
#endif
#endif
