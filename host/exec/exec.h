/*
 * host/exec/exec.h: the runtime layer: plugin registry, resources, nodes and their
 * execution, the host API table, the cache.
 */
#ifndef LG_HOST_EXEC_EXEC_H
#define LG_HOST_EXEC_EXEC_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "lightgraph/host.h"
#include "lightgraph/image.h"
#include "lightgraph/scene.h"
#include "exec/device.h"
#include "graph/graph.h"
#include "base/util.h"

/* ---- registry (registry.c) ----------------------------------------------------------------------
 * Plugins are scanned in a child process (fork, dlopen, read the descriptor, serialise it
 * through a pipe, exit), as GStreamer's plugin scanner does: the host learns every node
 * type's schema without loading a single plugin into its own process, a plugin that
 * crashes while being scanned cannot take the host down, and only the plugins the plan
 * needs are ever dlopen'ed by the host (lg_registry_load). */

typedef struct lg_plugin {
    char *path; /* absolute path of the shared object */
    char *name, *version, *doc;
    uint16_t abi_major, abi_minor;
    lg_node_type *types; /* host-owned copies of the scanned schema (no callbacks) */
    uint32_t n_types;
    void *handle;               /* dlopen handle once loaded */
    const lg_plugin_desc *live; /* the plugin's own descriptor once loaded */
    int live_refs;              /* resources and instances alive that came from it */
    /* A plugin reloaded by the viewer (lg_registry_rescan): dlopen'ed from a private copy
     * of the file, since dlopen of a path already loaded returns the library loaded
     * before. NULL: loaded from `path`. */
    char *load_path;
    bool poisoned;     /* crashed in create/prepare/execute: never dlclose'd */
    bool builtin;      /* part of this program (lg_registry_add_builtin): `handle`
                        * is not a dlopen handle, never dlclose'd */
    uint64_t dev, ino; /* the file's identity when scanned: one file reached through
                        * two folders of the search path is scanned once */
} lg_plugin;

typedef struct lg_refusal {
    char *path;
    char *reason;
} lg_refusal;

typedef struct lg_registry {
    lg_plugin **plugins; /* each allocated on its own: nodes point at them */
    uint32_t n_plugins;
    lg_refusal *refused;
    uint32_t n_refused;
    const char **names; /* every node type name, for did-you-mean */
    uint32_t n_names;
    char **dirs; /* the directories searched, in order */
    uint32_t n_dirs;
    /* the viewer's reloads: entries replaced (kept until the registry is freed, since
     * nodes, resources and checked graphs may still point at them), and the private
     * directory of reloaded copies */
    lg_plugin **retired;
    uint32_t n_retired;
    char *reload_dir;
    uint32_t reloads;
    /* the viewer: every plugin is loaded from a private copy, so that a build that writes
     * a .so in place (cp, an install step) never changes code the process runs */
    bool private_copies;
} lg_registry;

/* Finds the plugin directories (LIGHTGRAPH_PLUGIN_PATH, then the program's own: the build
 * tree's plugins/ when the program runs from it, else the install directory) and scans
 * every lg_*.so in them and in their immediate subdirectories (not deeper; a file reached
 * twice is scanned once). Names are unique (names.h): a plugin whose name, or one of whose
 * node type names, a plugin found before it already has is refused, naming both files;
 * the shipped plugins of the program's own directory are taken before any other. Refused
 * plugins are recorded with the reason and reported as warnings. Returns 0 (an empty
 * registry is not an error here). */
int lg_registry_scan(lg_registry *r);
/* Scans exactly these files (tests). */
int lg_registry_scan_files(lg_registry *r, char **paths, uint32_t n);
/* Adds a plugin that is part of this program (the synthetic sources of `lightgraph
 * conform`): `d` is validated as a loaded descriptor, its schema copied as a scanned one,
 * and the entry counts as loaded from the start (never dlopen'ed, never dlclose'd). `d`
 * must outlive the registry; `path` names it in messages. Returns 0, or -1 with the
 * problem in err. */
int lg_registry_add_builtin(lg_registry *r, const lg_plugin_desc *d, const char *path, char *err,
                            size_t errlen);
const lg_node_type *lg_registry_lookup(const lg_registry *r, const char *type, lg_plugin **plugin);
/* dlopens the plugin in this process, checks its descriptor again and that it matches the
 * scanned one. Returns 0 or -1 with a message in err. */
int lg_registry_load(lg_registry *r, lg_plugin *p, char *err, size_t errlen);
/* The live type (with callbacks) of a loaded plugin. */
const lg_node_type *lg_plugin_live_type(const lg_plugin *p, const char *type);
void lg_registry_schema(const lg_registry *r, lg_schema *out);
/* Drops the plugins that have no live objects (dlclose) and frees everything. */
void lg_registry_free(lg_registry *r);

/* The viewer's plugin reload. rescan: the file at `path` (absolute) changed on disk; it is
 * copied to the registry's private directory and the copy scanned in a child process.
 * Returns 0 with *fresh (a heap entry not yet in the registry, its `path` the original
 * one, `load_path` the copy) and *old (the entry for `path` now, or NULL for a new file),
 * or -1 with the reason in err (the file does not scan: not a plugin, wrong ABI, crashes
 * while scanned, ...). replace: puts `to` where `from` is (appends `to` when `from` is
 * NULL; removes `from` when `to` is NULL) and keeps `from` among the retired entries
 * (a retired entry put back is taken out of them): rollback is replace(r, fresh, old). */
int lg_registry_rescan(lg_registry *r, const char *path, lg_plugin **fresh, lg_plugin **old,
                       char *err, size_t errlen);
void lg_registry_replace(lg_registry *r, lg_plugin *from, lg_plugin *to);
/* The entry whose file is `path` (absolute), or NULL. */
lg_plugin *lg_registry_find_path(const lg_registry *r, const char *path);
/* The plugins whose shared object is mapped into this process right now, by walking the
 * loaded objects (dl_iterate_phdr): the evidence --explain prints. */
char *lg_registry_loaded_list(const lg_registry *r);

/* Checks a descriptor as the loader does: sizes, ABI, names, parameter tables, defaults
 * within ranges. Returns 0, or -1 with the first problem in err. */
int lg_descriptor_validate(const lg_plugin_desc *d, const char *path, char *err, size_t errlen);

/* The scan result, the bytes the scanning child writes through the pipe after its 'O'
 * status byte: "LGSCAN1\0", then the descriptor's fields and tables, counts and strings
 * length-prefixed (u32, host byte order; UINT32_MAX for NULL). encode appends d's (the
 * child's side). decode reads n untrusted bytes (the child ran the plugin's code) into *p:
 * name, version, doc, ABI and host-owned copies of the types, without callbacks; path,
 * handle and live stay zero. A string's length is checked against the bytes there are and
 * a count against the validator's limits (1024 types, 256 parameters and list items, 64
 * ports) before anything is allocated for it, and the result is validated as
 * lg_descriptor_validate validates a live descriptor (but for its callbacks), so what the
 * host keeps is what a valid plugin can describe. Returns 0, or -1 with "malformed scan
 * result: WHY" in err and nothing left allocated. */
void lg_registry_encode(lg_str *b, const lg_plugin_desc *d);
int lg_registry_decode(const char *buf, size_t n, lg_plugin *p, char *err, size_t errlen);
/* The descriptor a scanned entry describes (its schema, no callbacks): what decode checks
 * again and what encode writes for it. Points into p; nothing is allocated. */
lg_plugin_desc lg_plugin_scanned_desc(const lg_plugin *p);
/* Frees what decode allocated in p (not path, handle or live) and zeroes it. */
void lg_plugin_free_schema(lg_plugin *p);

/* ---- resources (resource.c) ------------------------------------------------------------------ */

struct lg_exec;
struct lg_pnode;

/* A GPU copy of one array of a plugin-owned payload (lg_host_api.payload_gl_buffer). */
typedef struct lg_attached {
    uint32_t slot;
    size_t size;
    uint32_t gl;
    void *cl;
    bool texture; /* gl is a texture (payload_gl_texture), slots apart from the buffers' */
} lg_attached;

/* A resource's copies on the devices, and which are current (resource.c). */
typedef struct lg_resource_copies {
    void *cpu;
    float *cpu_depth;
    bool cpu_valid;
    uint32_t gl_name, gl_depth;
    bool gl_valid;
    void *cl_mem, *cl_depth;
    bool cl_valid;
} lg_resource_copies;

/* A plugin-owned payload (a scene, SH coefficients, ...) and what the host made of it. */
typedef struct lg_resource_payload {
    void *data;
    void (*free)(void *);
    lg_plugin *plugin;     /* kept loaded while the payload lives */
    lg_attached *attached; /* GPU copies of payload arrays, by slot */
    uint32_t n_attached;
    /* a scene with the viewer's camera (ex->viewer.camera): the copy describe() hands out */
    void *view_scene;
    void *view_cameras;
    uint64_t view_gen;
} lg_resource_payload;

/* Composite kinds (lightgraph/kinds.h): one part per entry of the kind's table, in its
 * order; NULL for an optional part the producer left out. Parts are resources of kind
 * image, volume or buffer, owned by the composite (refs 1, freed with it). A neutral
 * composite has parts too (zero images the render size, empty buffers), which only an
 * edge naming a part (NODE.PART) reaches; lg_part() gives NULL for it. */
typedef struct lg_resource_parts {
    struct lg_resource **list; /* a composite: its parts */
    uint32_t n;
    struct lg_resource *parent; /* a part: its composite */
    int32_t index;              /* a part: its index in the kind's table */
    lg_part_type type;          /* a part: its declared type */
} lg_resource_parts;

struct lg_resource {
    lg_resource_kind kind;
    bool neutral;
    lg_image_desc image;
    lg_buffer_desc buffer;
    lg_volume_desc volume;
    lg_scene_features features;
    bool has_features;
    struct lg_pnode *producer;
    int refs;
    lg_resource_copies copies;
    lg_resource_payload payload;
    lg_resource_parts parts;
};

size_t lg_resource_bytes(const lg_resource *r); /* one copy, depth and parts included */
/* The parts of a composite resource of `kind`, made from the producer's specs (declared
 * in prepare) or, with specs NULL, its neutral parts. Returns 0 or reports and returns
 * LG_ERR_INVALID. */
int lg_resource_make_parts(struct lg_exec *ex, struct lg_pnode *n, lg_resource *r,
                           const lg_part_spec *specs, uint32_t n_specs);
/* What an edge delivers: the source's output, or the part an edge NODE.PART names. */
lg_resource *lg_edge_resource(struct lg_exec *ex, lg_edge e);
/* Whether node n may map r: r (or its composite) is one of n's outputs or came to n
 * through an input. */
bool lg_resource_reachable(struct lg_pnode *n, const lg_resource *r);
lg_resource *lg_resource_new(struct lg_pnode *producer, lg_resource_kind kind);
void lg_resource_unref(struct lg_exec *ex, lg_resource *r);
int lg_resource_map_cpu(struct lg_exec *ex, struct lg_pnode *n, lg_resource *r, unsigned access,
                        lg_cpu_view *view);
int lg_resource_map_gl(struct lg_exec *ex, struct lg_pnode *n, lg_resource *r, unsigned access,
                       uint32_t *name, uint32_t *depth);
int lg_resource_map_cl(struct lg_exec *ex, struct lg_pnode *n, lg_resource *r, unsigned access,
                       void **mem, void **depth);
int lg_resource_payload_gl(struct lg_exec *ex, struct lg_pnode *n, lg_resource *r, uint32_t slot,
                           const void *data, size_t size, uint32_t *name);
int lg_resource_payload_cl(struct lg_exec *ex, struct lg_pnode *n, lg_resource *r, uint32_t slot,
                           const void *data, size_t size, void **mem);
/* A GL texture (full mip chain) of an RGBA8 image of a payload (payload_gl_texture). */
int lg_resource_payload_gl_texture(struct lg_exec *ex, struct lg_pnode *n, lg_resource *r,
                                   uint32_t slot, const void *rgba8, uint32_t width,
                                   uint32_t height, uint32_t internal_format, uint32_t *name);
/* RGBA float copy of an image resource (for output files). Caller frees. */
int lg_resource_to_rgba32f(struct lg_exec *ex, lg_resource *r, float **out, char *err,
                           size_t errlen);
/* The image file of a probe resource (lightgraph/probe.h lg_probe_pack). Caller frees. */
int lg_resource_probe_file(struct lg_exec *ex, lg_resource *r, lg_image *out, char *err,
                           size_t errlen);
/* The text file of an SH coefficient resource (docs/graph-format.md "Outputs"): *out
 * (*len bytes, NUL-terminated) is the caller's to free. */
int lg_resource_sh_text(struct lg_exec *ex, lg_resource *r, char **out, size_t *len, char *err,
                        size_t errlen);

/* ---- plan and execution (plan.c, exec.c) ----------------------------------------------------- */

typedef enum lg_node_state {
    LG_STATE_KEPT = 0,
    LG_STATE_CULLED,
    LG_STATE_GATED,
} lg_node_state;

/* What the planner decided about a node (plan/), and what prepare() told it. */
typedef struct lg_pnode_plan {
    lg_node_state state;
    char *reason; /* why culled or gated */
    lg_digest identity;
    lg_digest plan_identity; /* identity before prepare() added content keys: what a
                              * later plan compares to adopt the node (lg_plan) */
    bool lent;               /* adopted by a newer plan that is not committed yet */
    uint32_t prev_index;     /* while lent: its index in the plan it came from */
    bool reads_scene;        /* an input delivers a scene; it makes none itself; not
                              * view independent */
    bool view_independent_set, view_independent; /* lg_set_view_independent in prepare */
    /* lg_declare_work in prepare (ABI 2.7): one run's work in the plugin's own unit and
     * its estimated wall time; work_what is owned (freed with the node) */
    bool work_declared;
    double work_units, work_seconds;
    char *work_what;
    /* the identity without the inputs' (plugin, version, type, parameters, content keys):
     * what names the cache entries of a LG_NODE_CACHE_BY_CONTENT node (cache.c) */
    lg_digest cache_identity;
} lg_pnode_plan;

/* A node's life in the runtime (exec/). */
typedef struct lg_pnode_run {
    bool per_frame;
    /* why it runs per frame when the plan decided it (static text, or NULL): "reads an
     * animated scene" (--explain) */
    const char *per_frame_why;
    bool device_set;
    lg_device device;
    bool prepared, created;
    bool ran;     /* executed at least once */
    bool crashed; /* a callback crashed under the guard: never called again */
    void **cl_events;
    uint32_t n_cl_events, cap_cl_events;
    bool warned_once;
    bool cache_stuck; /* an entry of this node could not be removed (cache.c):
                       * said once by cache_get, bypassed by cache_put */
    /* the node asked for the render size (lg_render_size): the viewer's plan at another
     * size makes it again (plan.c, adoptable) */
    bool read_render_size;
    /* per frame for itself (lg_set_per_frame(true) in prepare), not only for an animation
     * or an input: the viewer runs it in every frame, also when its clock is paused */
    bool per_frame_own;
} lg_pnode_run;

/* What --profile reports about a node (exec/profile.c). */
typedef struct lg_pnode_prof {
    double cpu_ms, gpu_ms;
    double first_cpu_ms; /* the first run: includes one-off set-up (programs, kernels) */
    double min_cpu_ms;   /* the fastest run */
    bool gpu_unmeasured; /* a GL timer query gave no plausible value */
    uint64_t runs;
    /* bytes_alloc: the resources the host made for the node (outputs, device copies,
     * payload buffers); bytes_moved: what it copied between devices for the node */
    uint64_t bytes_alloc, bytes_moved;
    /* memory the plugin counted itself (lg_account_alloc / lg_account_free): live now, and
     * the most live at once; the profile's `allocated` is bytes_alloc + the peak */
    uint64_t bytes_plugin_live, bytes_plugin_peak;
    uint64_t cache_hits, cache_misses;
} lg_pnode_prof;

/* What the viewer keeps about a node between frames (lg_exec_frame). */
typedef struct lg_pnode_viewer {
    double last_cpu_ms, last_gpu_ms; /* its last run */
    uint32_t last_frame;             /* the frame of its last run */
    bool ran_this_frame;
    uint64_t camera_gen;           /* ex->viewer.camera_gen when it last ran */
    double time;                   /* lg_frame.time of its last run */
    bool output_file_noted;        /* the viewer said it does not write the node's files */
    double avg_cpu_ms, avg_gpu_ms; /* the viewer's moving averages */
} lg_pnode_viewer;

typedef struct lg_pnode {
    lg_node pub; /* what the plugin sees; must stay first */
    struct lg_exec *ex;
    uint32_t index;
    const lg_cnode *c;
    const lg_node_type *schema; /* scanned type */
    lg_plugin *plugin;
    lg_resource **outputs; /* schema->n_outputs */
    lg_pnode_plan plan;
    lg_pnode_run run;
    lg_pnode_prof prof;
    lg_pnode_viewer viewer;
} lg_pnode;

typedef struct lg_exec_opts {
    uint32_t width, height; /* render size */
    uint32_t frames;
    double dt;
    const char *gl_backend;      /* "osmesa" (default) or "egl" */
    const char *output_override; /* -o */
    int exr_pixel;               /* render --exr half|float (LG_OUT_EXR_*): every EXR output */
    bool explain, profile;
    /* the on-disk cache neither read nor written (render --no-cache; sweep and tune always:
     * what they time is computed, not loaded) */
    bool no_cache;
    bool every_frame;              /* --every-frame: static nodes run every frame too ... */
    const char *every_frame_nodes; /* ... only these (comma-separated names); NULL: all */
    const char *profile_json;
    const char *graph_path;
    struct lg_outputs *outputs; /* where the output files go (outputs.h); every output
                                 * path is added to it before the run */
} lg_exec_opts;

/* The exit status of render and sweep when a plugin crashed in one of its callbacks
 * (LG_GUARD_EXIT); 0, 1 and 2 are main.c's. */
#define LG_EXIT_CRASH 3

/* What a crash in a plugin callback does (lg_guard_call). */
typedef enum lg_guard_mode {
    LG_GUARD_NONE = 0, /* nothing: a crash stays a crash (false, before ABI 3.0) */
    /* the viewer's reloads (a broken plugin must not take the window down): the call
     * returns, the node fails with the signal and is never called again, its plugin is
     * never dlclose'd; a crash on another thread stays a crash (1: the `true` of the
     * bool this field was before ABI 3.0) */
    LG_GUARD_RECOVER = 1,
    /* render and sweep: the handler writes the message lg_node_call prepared (node, type,
     * plugin and its path, callback, signal) with write(2), removes every temporary of the
     * outputs and the cache (lg_temp_remove_all) and _exit()s with LG_EXIT_CRASH; a crash
     * on any thread during the callback counts, and the calling thread's stack overflow
     * too (the handler runs on a stack of its own) */
    LG_GUARD_EXIT,
} lg_guard_mode;

/* The devices of a run, made on first need (exec/devices.c). */
typedef struct lg_exec_devices {
    lg_gl_device *gl;
    lg_cl_dev *cl;
    char *gl_error, *cl_error; /* why a device could not be made (reported once per node) */
    uint32_t gl_timer_query;
    bool keep; /* lg_exec_free leaves gl, cl and the timer query alone:
                * the caller owns them (the viewer passes them on) */
} lg_exec_devices;

/* The on-disk cache of a run (exec/cache.c). */
typedef struct lg_exec_cache {
    char *dir; /* checked on first use; NULL until then */
    bool off;  /* the directory failed its check: no caching this run */
} lg_exec_cache;

/* What the viewer (host/viewer) asks of a plan and a run. */
typedef struct lg_exec_viewer {
    /* lg_plan adopts the nodes of this earlier plan of the same registry whose identity,
     * plugin entry and input resources are unchanged (their instances, resources and
     * caches are kept, and they do not run again unless they run per frame); see
     * lg_plan_commit and lg_plan_rollback. NULL: every node is made afresh. */
    struct lg_exec *prev;
    /* When set, the outputs the planner keeps what they need of, instead of the graph's
     * output statements (the viewer: the one image it shows). */
    const lg_edge *roots;
    uint32_t n_roots;
    /* When set, every scene an input delivers has this camera as its active camera
     * (api describe; the copy is made again when camera_gen changes), and lg_exec_frame
     * runs again the nodes that read a scene. */
    const lg_camera *camera;
    uint64_t camera_gen;
    /* When set, lg_exec_frame passes `time` as lg_frame.time instead of index * dt: the
     * viewer's animation clock (play, pause, scrub; docs/viewer.md "Animation"). */
    bool has_time;
    double time;
} lg_exec_viewer;

typedef struct lg_exec {
    lg_exec_opts opts;
    lg_registry *reg;
    const lg_graph *graph;
    const lg_checked *checked;
    lg_pnode **nodes; /* n_nodes, each allocated on its own: a node kept across a
                       * reload (lg_plan_reuse) moves with its address */
    uint32_t n_nodes;
    lg_host_api api;
    lg_exec_devices dev;
    lg_exec_cache cache;
    bool failed;
    uint32_t frame;
    double t_plan_ms, t_total_ms; /* the profile's totals */
    lg_exec_viewer viewer;
    /* How plugin callbacks (create, prepare, execute, destroy) of nodes made in this plan
     * meet a crash (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT): see lg_guard_mode. */
    lg_guard_mode guard;
} lg_exec;

/* Runs one frame for the viewer: a kept node runs when it has not run yet, runs per
 * frame, reads a scene whose camera changed since it last ran (but for nodes that make
 * scenes and LG_NODE_VIEW_INDEPENDENT ones), or reads a node that ran in this frame. The
 * frame's time is ex->viewer.time when has_time is set, else index * dt. A node per frame
 * only because it reads an animated scene (run.per_frame_why) runs when the time moved
 * since its last run: the viewer's paused clock holds the pose without re-rendering it.
 * Returns 0, or -1 after reporting. */
int lg_exec_frame(lg_exec *ex, uint32_t index);
/* fn(ctx) under the guard `mode` asks for: 0, or (LG_GUARD_RECOVER) the signal that
 * interrupted fn. With LG_GUARD_EXIT a crash does not return (lg_node_call prepares the
 * message first). */
int lg_guard_call(lg_guard_mode mode, void (*fn)(void *ctx), void *ctx);
/* A plugin callback of node n (`what`: "create", "prepare", "execute", "destroy") under
 * ex->guard: with LG_GUARD_EXIT the handler's message is prepared first; with
 * LG_GUARD_RECOVER a crash marks n crashed and its plugin poisoned and reports it as the
 * node's error. Returns 0, or the signal. */
int lg_node_call(lg_exec *ex, lg_pnode *n, const char *what, void (*fn)(void *ctx), void *ctx);
/* Runs the frames and writes the outputs. */
int lg_execute(lg_exec *ex);
void lg_exec_free(lg_exec *ex);
void lg_profile_print(lg_exec *ex, FILE *f);
/* --every-frame[=NODE,...]: does `n` run again on every frame although nothing it reads
 * changed? */
bool lg_exec_runs_every_frame(const lg_exec *ex, const lg_pnode *n);
int lg_profile_write_json(lg_exec *ex, const char *path);

/* The host API table plugins call (hostapi.c). */
void lg_host_api_init(lg_host_api *api);
/* A node's messages (node_diag.c): "node 'NAME' (TYPE): ..." at a host log level (LG_H*).
 * errorf also marks the run failed. */
void lg_node_vmsg(lg_pnode *n, int level, const char *fmt, va_list ap);
void lg_node_errorf(lg_pnode *n, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void lg_node_warnf(lg_pnode *n, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The run's GL or CL device, made on first need (devices.c): 0, or LG_ERR_DEVICE after
 * reporting why as n's error. */
int lg_exec_need_gl(lg_exec *ex, lg_pnode *n);
int lg_exec_need_cl(lg_exec *ex, lg_pnode *n);

/* cache (cache.c) */
char *lg_cache_dir(void);
int lg_exec_cache_get(lg_exec *ex, lg_pnode *n, const char *key, void **data, size_t *size);
int lg_exec_cache_put(lg_exec *ex, lg_pnode *n, const char *key, const void *data, size_t size);
/* cache_put saying what it did: an lg_cache_store_result, or an LG_ERR_* (< 0) for a bad
 * key or NULL data (lg_host_api.cache_store). lg_exec_cache_put maps it to LG_OK / LG_ERR_IO. */
int lg_exec_cache_put_status(lg_exec *ex, lg_pnode *n, const char *key, const void *data,
                             size_t size);
/* A hit the node found bad (lg_host_api.cache_reject): warned as corrupt, removed, counted
 * as a miss instead of a hit. */
void lg_exec_cache_drop(lg_exec *ex, lg_pnode *n, const char *key, const char *why);
/* One entry's bytes (cache_entry.c, which has the format). encode appends the entry for
 * `identity`, `key` and the payload to b. check reads an entry's bytes (untrusted: read back
 * from disk) as the entry for `identity` and `key`: returns NULL with *payload pointing
 * into buf and *payload_size set, or the reason it cannot be used ("bad header", "truncated
 * or padded", "checksum mismatch", ...). Nothing is allocated; the declared size is only
 * compared with `len`. */
void lg_cache_entry_encode(lg_str *b, const lg_digest *identity, const char *key, const void *data,
                           size_t size);
const char *lg_cache_entry_check(const char *buf, size_t len, const lg_digest *identity,
                                 const char *key, const char **payload, size_t *payload_size);

#endif
