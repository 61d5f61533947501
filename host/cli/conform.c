/*
 * lightgraph conform PLUGIN.so [--json] [-v]: a plugin's contracts, checked on the host's
 * own machinery (docs/conform.md). GstHarness, gst-validate and the OpenFX validator are
 * the models, for our ABI.
 *
 * The plugin is scanned alone (lg_registry_scan_files: a child process reads its
 * descriptor), with the program's own plugin "conform" beside it (conform_sources.c), whose
 * node types make the synthetic inputs; nothing on LIGHTGRAPH_PLUGIN_PATH and none of the
 * in-tree plugins is loaded. Every run is a graph text (conform source nodes feeding one
 * node of the type under test) parsed, checked, planned and executed as `render` does it,
 * in a forked child: a crash is a reported failure of the case that was running, and the
 * next child carries on with the next case. Devices are made once per child (per backend)
 * and handed from one plan to the next, as the viewer does.
 *
 * The parent keeps what the children send back (status, first error, every output as
 * floats, memory numbers) and judges the checks: descriptor, runs, outputs, finite,
 * backends, hostile, determinism, resize, failed_prepare, memory, gl_state, device_errors,
 * gating. Each result names the node type, the check and the values.
 */
#include "cli/conform.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
/* The sanitizer runtime's own (sanitizer/allocator_interface.h, which GCC does not ship). */
size_t __sanitizer_get_current_allocated_bytes(void);
#define CF_ASAN 1
#endif

#include "cli/commands.h"
#include "exec/names.h"
#include "lightgraph/image.h"
#include "lightgraph/kinds.h"

/* ---- the report ------------------------------------------------------------------------------ */

typedef enum cf_status { CF_PASS = 0, CF_FAIL, CF_SKIP, CF_NOTE } cf_status;
static const char *const status_names[] = { "pass", "FAIL", "skip", "note" };

typedef struct cf_item {
    cf_status status;
    char *node; /* node type, or NULL for the plugin */
    char *check;
    char *message;
} cf_item;

typedef struct cf_report {
    cf_item *items;
    uint32_t n, cap;
    uint32_t counts[4];
} cf_report;

static void report(cf_report *r, cf_status st, const char *node, const char *check, const char *fmt,
                   ...) __attribute__((format(printf, 5, 6)));
static void report(cf_report *r, cf_status st, const char *node, const char *check, const char *fmt,
                   ...)
{
    if (r->n == r->cap) {
        r->cap = r->cap ? r->cap * 2 : 64;
        r->items = lg_xrealloc(r->items, r->cap * sizeof *r->items);
    }
    va_list ap;
    va_start(ap, fmt);
    char *msg = NULL;
    if (vasprintf(&msg, fmt, ap) < 0)
        msg = NULL;
    va_end(ap);
    r->items[r->n++] = (cf_item){ st, node ? lg_xstrdup(node) : NULL, lg_xstrdup(check),
                                  msg ? msg : lg_xstrdup("?") };
    r->counts[st]++;
}

static void report_free(cf_report *r)
{
    for (uint32_t i = 0; i < r->n; i++) {
        free(r->items[i].node);
        free(r->items[i].check);
        free(r->items[i].message);
    }
    free(r->items);
}

/* ---- cases ----------------------------------------------------------------------------------- */

typedef enum cf_mode {
    CF_RUN = 0, /* plan and one frame */
    CF_TWICE,   /* two fresh plans of the same graph: identical outputs */
    CF_RESIZE,  /* a plan, then one at another size that adopts what it can (lg_plan prev) */
    CF_SQUEEZE, /* the node's prepare fails (pixel limit); destroy must cope */
    CF_FRAMES,  /* many frames, every node every frame: memory must not grow */
    CF_GATE,    /* a scene lacking the declared needs: the planner must gate the node */
} cf_mode;

typedef struct cf_case {
    cf_mode mode;
    int backend;   /* index into the type's backend values; -1: no backend parameter */
    uint32_t w, h; /* image inputs and render size */
    int format;    /* lg_conform_formats */
    int pattern;   /* lg_conform_patterns */
    int scene;     /* lg_conform_scenes */
    bool baseline; /* one of the "runs" cases (ramp, full scene) */
} cf_case;

#define CF_MAX_OUT 32
/* The memory check: frames run, the frame after which growth is measured, and the resident
 * growth over the frames measured that is noise (allocator, driver caches), not a leak;
 * --quick runs fewer frames (a leak of 1 MiB a frame still shows) */
static uint32_t cf_frames_n = 20, cf_frames_from = 5;
static uint64_t cf_rss_slack = 8u << 20;

typedef struct cf_out {
    char *name; /* "out", "probe.radiance" */
    lg_resource_kind kind;
    bool written;
    bool values; /* floats were read */
    uint32_t w, h, d;
    float *f;
    size_t nf;
} cf_out;

typedef struct cf_result {
    bool done;   /* the child reported it */
    int crashed; /* the signal that ended the child in this case, or -1 for a
                  * time-out */
    int phase;   /* 0 ok, 1 the graph failed to check, 2 plan (create/prepare)
                  * failed, 3 execute failed */
    bool gated;
    char *error; /* the first error message, or NULL */
    cf_out outs[CF_MAX_OUT];
    uint32_t n_outs;
    /* CF_TWICE: values that differ between the runs, the largest difference */
    uint64_t diff_count;
    double diff_max;
    char *diff_where;
    /* CF_RESIZE: why the second plan's outputs are not at the new size, or NULL */
    char *resize_bad;
    /* CF_FRAMES: resident memory and the plugin's live bytes after frame cf_frames_from
     * and after the last */
    uint64_t rss0, rss1, live0, live1, peak;
    double ms;
} cf_result;

static void result_free(cf_result *r)
{
    free(r->error);
    free(r->diff_where);
    free(r->resize_bad);
    for (uint32_t i = 0; i < r->n_outs; i++) {
        free(r->outs[i].name);
        free(r->outs[i].f);
    }
    memset(r, 0, sizeof *r);
}

/* ---- the context ----------------------------------------------------------------------------- */

typedef struct cf_ctx {
    const char *path;
    lg_registry reg;
    lg_plugin *plugin;
    bool json, verbose;
    double timeout; /* seconds a child may run without reporting */
    cf_report rep;
} cf_ctx;

/* The backend values of a type ("cpu", "gl", "cl" in that order), or none. */
static uint32_t backends_of(const lg_node_type *t, const char *const **values)
{
    for (uint32_t k = 0; k < t->n_params; k++)
        if (strcmp(t->params[k].key, "backend") == 0 && t->params[k].type == LG_PARAM_ENUM) {
            uint32_t n = 0;
            while (t->params[k].enum_values[n])
                n++;
            *values = t->params[k].enum_values;
            return n;
        }
    *values = NULL;
    return 0;
}

static const char *backend_name(const lg_node_type *t, int b)
{
    const char *const *v;
    return b >= 0 && backends_of(t, &v) > (uint32_t)b ? v[b] : "default";
}

static bool has_input(const lg_node_type *t, lg_resource_kind kind)
{
    for (uint32_t k = 0; k < t->n_inputs; k++)
        if (t->inputs[k].kind == kind ||
            (kind == LG_KIND_IMAGE && t->inputs[k].kind == LG_KIND_ANY))
            return true;
    return false;
}

/* An input port conform cannot feed: its kind has no source. */
static const char *unfed_input(const lg_node_type *t)
{
    for (uint32_t k = 0; k < t->n_inputs; k++)
        if (!t->inputs[k].optional && !lg_conform_source_for(t->inputs[k].kind))
            return t->inputs[k].name;
    return NULL;
}

static void case_label(char *buf, size_t n, const lg_node_type *t, const cf_case *k)
{
    static const char *const modes[] = { "run",    "twice", "resize", "failed prepare",
                                         "frames", "gating" };
    snprintf(buf, n, "%s on %s, %ux%u %s, %s, scene %s", modes[k->mode],
             backend_name(t, k->backend), k->w, k->h, lg_conform_formats[k->format],
             lg_conform_patterns[k->pattern], lg_conform_scenes[k->scene]);
}

/* The graph of one case: a source per input port (all image inputs the same size, every
 * input fed that conform can make; optional inputs of other kinds left unconnected), then
 * the node under test, named as its type. */
static char *case_graph(const lg_node_type *t, const cf_case *k, uint32_t w, uint32_t h,
                        bool squeeze)
{
    lg_str g = { 0 };
    lg_str_add(&g, "lightgraph 1\n");
    uint32_t n_images = 0;
    for (uint32_t i = 0; i < t->n_inputs; i++) {
        const char *src = lg_conform_source_for(t->inputs[i].kind);
        n_images += src && strcmp(src, "conform_image") == 0;
    }
    for (uint32_t i = 0; i < t->n_inputs; i++) {
        const lg_port_desc *p = &t->inputs[i];
        const char *src = lg_conform_source_for(p->kind);
        if (!src)
            continue;
        lg_str_addf(&g, "in_%u = %s { ", i, src);
        if (strcmp(src, "conform_image") == 0) {
            lg_str_addf(&g, "width = %u, height = %u, format = %s, pattern = %s", w, h,
                        lg_conform_formats[k->format], lg_conform_patterns[k->pattern]);
            if (squeeze)
                lg_str_addf(&g, ", squeeze = %u", n_images);
        } else if (strcmp(src, "conform_scene") == 0) {
            lg_str_addf(&g, "variant = %s", lg_conform_scenes[k->scene]);
        } else if (strcmp(src, "conform_shadowmap") == 0) {
            /* one map per directional light of the scene it goes with */
            lg_str_addf(&g, "pattern = %s, lights = %d", lg_conform_patterns[k->pattern],
                        k->scene == LG_CONFORM_SCENE_FULL ? 1 : 0);
        } else if (strcmp(src, "conform_transfer") == 0) {
            lg_str_addf(&g, "pattern = %s, empty_scene = %s", lg_conform_patterns[k->pattern],
                        k->scene == LG_CONFORM_SCENE_EMPTY ? "true" : "false");
        } else {
            lg_str_addf(&g, "pattern = %s", lg_conform_patterns[k->pattern]);
        }
        lg_str_add(&g, " }\n");
    }
    lg_str_addf(&g, "%s = %s {", t->name, t->name);
    const char *sep = " ";
    for (uint32_t i = 0; i < t->n_inputs; i++)
        if (lg_conform_source_for(t->inputs[i].kind)) {
            lg_str_addf(&g, "%s%s = in_%u", sep, t->inputs[i].name, i);
            sep = ", ";
        }
    if (k->backend >= 0)
        lg_str_addf(&g, "%sbackend = %s", sep, backend_name(t, k->backend));
    lg_str_add(&g, " }\n");
    return lg_str_take(&g);
}

/* ---- the child: runs cases, writes records --------------------------------------------------- */

static lg_str child_errors;

static void child_error_hook(const char *m)
{
    if (child_errors.len < 4000) {
        if (child_errors.len)
            lg_str_add(&child_errors, " | ");
        lg_str_add(&child_errors, m);
    }
}

static void write_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            _exit(3);
        p += w;
        n -= (size_t)w;
    }
}

/* What the memory check measures: the process's resident memory; under AddressSanitizer the
 * heap's live bytes instead, because ASan keeps freed blocks in its quarantine (256 MiB by
 * default) and its allocator's caches, so resident memory grows while nothing leaks. A
 * plugin that keeps what it allocates every frame grows both. */
#ifdef CF_ASAN
static const char cf_mem_what[] = "the live heap (AddressSanitizer's allocated bytes)";
#else
static const char cf_mem_what[] = "resident memory";
#endif

static uint64_t rss_bytes(void)
{
#ifdef CF_ASAN
    return (uint64_t)__sanitizer_get_current_allocated_bytes();
#else
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long long size = 0, res = 0;
    if (f) {
        if (fscanf(f, "%llu %llu", &size, &res) != 2)
            res = 0;
        fclose(f);
    }
    return (uint64_t)res * (uint64_t)sysconf(_SC_PAGESIZE);
#endif
}

/* Appends output `r` (its parts for a composite) as floats to res. */
static void collect(lg_exec *ex, lg_pnode *n, lg_resource *r, const char *name, cf_result *res)
{
    if (res->n_outs >= CF_MAX_OUT)
        return;
    cf_out *o = &res->outs[res->n_outs++];
    memset(o, 0, sizeof *o);
    o->name = lg_xstrdup(name);
    if (!r)
        return;
    o->kind = r->kind;
    /* an alias (declare_alias) is its input, written upstream; a neutral stand-in is the
     * host's */
    bool own = r->producer == n || (r->parts.parent && r->parts.parent->producer == n);
    /* a composite is written through its parts, judged one by one below */
    o->written = !own || r->neutral || r->copies.cpu_valid || r->copies.gl_valid ||
                 r->copies.cl_valid || lg_kind_is_composite(r->kind);
    char err[512];
    if (r->kind == LG_KIND_IMAGE) {
        o->w = r->image.width;
        o->h = r->image.height;
        o->d = 1;
        if (o->written && lg_resource_to_rgba32f(ex, r, &o->f, err, sizeof err) == 0) {
            o->values = true;
            o->nf = lg_resource_bytes(r)
                        ? (size_t)o->w * o->h * 4 * ((r->image.flags & LG_IMAGE_CUBE) ? 6 : 1)
                        : 0;
            /* mip levels: level 0 is what the checks read */
        }
    } else if (r->kind == LG_KIND_VOLUME) {
        o->w = r->volume.width, o->h = r->volume.height, o->d = r->volume.depth;
        lg_cpu_view v;
        size_t texels = (size_t)o->w * o->h * o->d;
        if (o->written && lg_resource_map_cpu(ex, r->producer, r, LG_READ, &v) == 0) {
            o->f = lg_xmalloc(texels * 16 + 16);
            if (lg_pixels_to_rgba32f(r->volume.format, v.pixels, texels, o->f) == 0) {
                o->nf = texels * 4;
                o->values = true;
            }
        }
    } else if (r->kind == LG_KIND_BUFFER && r->parts.parent && r->parts.type == LG_PART_BUFFER &&
               (r->parts.parent->kind == LG_KIND_SH || r->parts.parent->kind == LG_KIND_TRANSFER ||
                r->parts.parent->kind == LG_KIND_PROBE)) {
        /* the float parts: SH and transfer coefficients, solid angles */
        lg_cpu_view v;
        o->w = (uint32_t)(r->buffer.size / sizeof(float)), o->h = o->d = 1;
        if (o->written && r->buffer.size &&
            lg_resource_map_cpu(ex, r->producer, r, LG_READ, &v) == 0) {
            o->nf = r->buffer.size / sizeof(float);
            o->f = lg_xmalloc(o->nf * sizeof(float) + 1);
            memcpy(o->f, v.pixels, o->nf * sizeof(float));
            o->values = true;
        }
    } else if (r->kind == LG_KIND_SCENE) {
        o->written = true;
    }
    if (r->parts.list) {
        const lg_kind_desc *kd = lg_kind_describe(r->kind);
        for (uint32_t i = 0; i < r->parts.n && kd && i < kd->n_parts; i++) {
            if (!r->parts.list[i] || kd->parts[i].type == LG_PART_META)
                continue;
            char *pn = lg_xasprintf("%s.%s", name, kd->parts[i].name);
            collect(ex, n, r->parts.list[i], pn, res);
            free(pn);
        }
    }
}

typedef struct cf_devs {
    lg_gl_device *gl;
    lg_cl_dev *cl;
    uint32_t timer;
} cf_devs;

typedef struct cf_run {
    lg_graph *g;
    lg_checked *c;
    lg_exec ex;
    lg_edge *roots;
    int32_t node;
} cf_run;

static void run_free(cf_run *r, cf_devs *d)
{
    if (r->ex.nodes || r->ex.dev.gl || r->ex.dev.cl) {
        d->gl = r->ex.dev.gl;
        d->cl = r->ex.dev.cl;
        d->timer = r->ex.dev.gl_timer_query;
        lg_exec_free(&r->ex);
    }
    lg_checked_free(r->c);
    lg_graph_free(r->g);
    free(r->roots);
    memset(r, 0, sizeof *r);
}

/* Parses, checks and plans one graph; returns the phase that failed (0 none). */
static int run_plan(cf_ctx *c, const lg_node_type *t, const char *text, uint32_t w, uint32_t h,
                    cf_devs *d, lg_exec *prev, cf_run *r, bool every_frame)
{
    memset(r, 0, sizeof *r);
    lg_diags diags = { 0 };
    r->g = lg_graph_parse_string("<conform>", text, strlen(text), NULL, &diags);
    if (r->g) {
        lg_schema schema;
        lg_registry_schema(&c->reg, &schema);
        r->c = lg_graph_check(r->g, &schema, &diags);
    }
    if (!r->c) {
        for (uint32_t i = 0; i < diags.n; i++)
            if (diags.items[i].level == LG_DIAG_ERROR)
                child_error_hook(diags.items[i].message);
        lg_diags_free(&diags);
        return 1;
    }
    lg_diags_free(&diags);
    r->node = lg_graph_find_node(r->g, t->name);
    r->roots = lg_xcalloc(t->n_outputs + 1, sizeof *r->roots);
    for (uint32_t o = 0; o < t->n_outputs; o++)
        r->roots[o] = (lg_edge){ r->node, o, 0 };
    lg_exec *ex = &r->ex;
    ex->opts.width = w;
    ex->opts.height = h;
    ex->opts.frames = 1;
    ex->opts.dt = 1.0 / 60.0;
    ex->opts.gl_backend = "osmesa";
    ex->opts.every_frame = every_frame;
    ex->reg = &c->reg;
    ex->graph = r->g;
    ex->checked = r->c;
    ex->viewer.roots = r->roots;
    ex->viewer.n_roots = t->n_outputs;
    ex->dev.keep = true;
    ex->dev.gl = d->gl;
    ex->dev.cl = d->cl;
    ex->dev.gl_timer_query = d->timer;
    ex->viewer.prev = prev;
    int rc = lg_plan(ex);
    if (prev) {
        if (rc)
            lg_plan_rollback(ex);
        else
            lg_plan_commit(ex);
    }
    return rc ? 2 : 0;
}

/* One frame of every kept node, then the GL-state contract of the last one (the node under
 * test runs last: its sources come first in topological order). */
static int run_frame(cf_run *r, uint32_t frame)
{
    lg_exec *ex = &r->ex;
    if (lg_exec_frame(ex, frame) || ex->failed)
        return 3;
    if (ex->dev.gl) {
        char err[1024];
        const GladGLContext *gl = lg_gl_device_table(ex->dev.gl);
        if (lg_gl_state_check(gl, err, sizeof err)) {
            char *m = lg_xasprintf("left GL state behind (see docs/sdk.md, the GL state "
                                   "contract): %s",
                                   err);
            child_error_hook(m);
            free(m);
            return 3;
        }
        GLenum e = gl->GetError();
        if (e != GL_NO_ERROR) {
            char *m = lg_xasprintf("GL error 0x%04x pending after the node ran", (unsigned)e);
            child_error_hook(m);
            free(m);
            return 3;
        }
    }
    return 0;
}

static void collect_outputs(cf_run *r, const lg_node_type *t, cf_result *res)
{
    lg_pnode *n = r->node >= 0 ? r->ex.nodes[r->node] : NULL;
    if (!n)
        return;
    res->gated = n->plan.state == LG_STATE_GATED;
    for (uint32_t o = 0; o < t->n_outputs; o++)
        collect(&r->ex, n, n->outputs[o], t->outputs[o].name, res);
}

static void child_case(cf_ctx *c, const lg_node_type *t, const cf_case *k, cf_devs *d,
                       cf_result *res)
{
    cf_run r1, r2;
    bool squeeze_by_source = has_input(t, LG_KIND_IMAGE);
    char *text = case_graph(t, k, k->w, k->h, k->mode == CF_SQUEEZE && squeeze_by_source);
    uint64_t limit = lg_image_max_pixels();
    lg_conform_squeeze_reset();
    if (k->mode == CF_SQUEEZE && !squeeze_by_source)
        lg_image_set_max_pixels(1);
    double t0 = lg_mono_now();
    res->phase = run_plan(c, t, text, k->w, k->h, d, NULL, &r1, k->mode == CF_FRAMES);
    lg_image_set_max_pixels(limit);
    if (!res->phase && k->mode != CF_GATE) {
        if (k->mode == CF_FRAMES) {
            lg_pnode *n = r1.ex.nodes[r1.node];
            for (uint32_t f = 0; f < cf_frames_n && !res->phase; f++) {
                res->phase = run_frame(&r1, f);
                if (f + 1 == cf_frames_from) {
                    res->rss0 = rss_bytes();
                    res->live0 = n->prof.bytes_plugin_live;
                }
            }
            res->rss1 = rss_bytes();
            res->live1 = n->prof.bytes_plugin_live;
            res->peak = n->prof.bytes_plugin_peak;
        } else {
            res->phase = run_frame(&r1, 0);
        }
    }
    if (!res->phase || k->mode == CF_GATE)
        collect_outputs(&r1, t, res);
    if (k->mode == CF_TWICE && !res->phase) {
        int ph = run_plan(c, t, text, k->w, k->h, d, NULL, &r2, false);
        if (!ph)
            ph = run_frame(&r2, 0);
        cf_result again;
        memset(&again, 0, sizeof again);
        if (!ph)
            collect_outputs(&r2, t, &again);
        res->phase = ph;
        for (uint32_t i = 0; !ph && i < res->n_outs && i < again.n_outs; i++) {
            const cf_out *a = &res->outs[i], *b = &again.outs[i];
            for (size_t j = 0; j < a->nf && j < b->nf; j++) {
                if (memcmp(&a->f[j], &b->f[j], sizeof(float)) == 0)
                    continue;
                double dd = fabs((double)a->f[j] - (double)b->f[j]);
                if (res->diff_count++ == 0 || dd > res->diff_max) {
                    res->diff_max = dd;
                    free(res->diff_where);
                    res->diff_where = lg_xasprintf("output '%s' value %zu (pixel %zu, channel "
                                                   "%zu): %.9g then %.9g",
                                                   a->name, j, j / 4, j % 4, a->f[j], b->f[j]);
                }
            }
            if (a->nf != b->nf && !res->diff_where) {
                res->diff_count++;
                res->diff_where = lg_xasprintf("output '%s' has %zu values, then %zu", a->name,
                                               a->nf, b->nf);
            }
        }
        result_free(&again);
        run_free(&r2, d);
    }
    if (k->mode == CF_RESIZE && !res->phase) {
        /* the same graph at another size, planned with the first as `prev` (the viewer's
         * plan reuse): the node's inputs changed, so it must be made and prepared again */
        uint32_t w2 = k->w + 2, h2 = k->h + 1;
        char *text2 = case_graph(t, k, w2, h2, false);
        int ph = run_plan(c, t, text2, w2, h2, d, &r1.ex, &r2, false);
        free(text2);
        if (!ph)
            ph = run_frame(&r2, 0);
        if (ph) {
            res->phase = ph;
        } else {
            lg_pnode *n1 = r1.ex.nodes[r1.node], *n2 = r2.ex.nodes[r2.node];
            for (uint32_t o = 0; n1 && n2 && o < t->n_outputs; o++) {
                lg_resource *a = n1->outputs[o], *b = n2->outputs[o];
                if (a && b && a->kind == LG_KIND_IMAGE && b->kind == LG_KIND_IMAGE &&
                    a->image.width == k->w && a->image.height == k->h &&
                    (b->image.width != w2 || b->image.height != h2) && !res->resize_bad)
                    res->resize_bad = lg_xasprintf(
                        "output '%s' was %ux%u at %ux%u, and is %ux%u at %ux%u (not prepared "
                        "again?)",
                        t->outputs[o].name, a->image.width, a->image.height, k->w, k->h,
                        b->image.width, b->image.height, w2, h2);
            }
        }
        run_free(&r2, d);
    }
    res->ms = (lg_mono_now() - t0) * 1e3;
    run_free(&r1, d);
    free(text);
    if (child_errors.len)
        res->error = lg_str_take(&child_errors);
}

/* Runs cases[from..n) and writes a record for each: 'B' index before it starts, then 'R'
 * index and the result. */
static void child_main(cf_ctx *c, const lg_node_type *t, const cf_case *cases, uint32_t from,
                       uint32_t n, int fd)
{
    cf_devs d = { 0 };
    lg_hlog_error_hook = child_error_hook;
    for (uint32_t i = from; i < n; i++) {
        lg_str b = { 0 };
        lg_str_addc(&b, 'B');
        lg_wire_put_u64(&b, i);
        write_all(fd, b.s, b.len);
        lg_str_free(&b);
        cf_result res;
        memset(&res, 0, sizeof res);
        child_case(c, t, &cases[i], &d, &res);
        lg_str_addc(&b, 'R');
        lg_wire_put_u64(&b, i);
        lg_wire_put_u64(&b, (uint64_t)res.phase);
        lg_wire_put_u64(&b, res.gated);
        lg_wire_put_text(&b, res.error);
        lg_wire_put_u64(&b, res.diff_count);
        lg_wire_put_f64(&b, res.diff_max);
        lg_wire_put_text(&b, res.diff_where);
        lg_wire_put_text(&b, res.resize_bad);
        lg_wire_put_u64(&b, res.rss0);
        lg_wire_put_u64(&b, res.rss1);
        lg_wire_put_u64(&b, res.live0);
        lg_wire_put_u64(&b, res.live1);
        lg_wire_put_u64(&b, res.peak);
        lg_wire_put_f64(&b, res.ms);
        lg_wire_put_u64(&b, res.n_outs);
        for (uint32_t o = 0; o < res.n_outs; o++) {
            const cf_out *x = &res.outs[o];
            lg_wire_put_text(&b, x->name);
            lg_wire_put_u64(&b, (uint64_t)x->kind);
            lg_wire_put_u64(&b, x->written);
            lg_wire_put_u64(&b, x->values);
            lg_wire_put_u64(&b, x->w);
            lg_wire_put_u64(&b, x->h);
            lg_wire_put_u64(&b, x->d);
            lg_wire_put_u64(&b, x->nf);
            if (x->nf)
                lg_wire_put_raw(&b, x->f, x->nf * sizeof(float));
        }
        write_all(fd, b.s, b.len);
        lg_str_free(&b);
        result_free(&res);
    }
    lg_gl_device_destroy(&d.gl);
    lg_cl_device_destroy(&d.cl);
}

/* ---- the parent: reads records --------------------------------------------------------------- */

/* Parses the records in buf: fills results, returns the index of a case begun and not
 * reported (the one a crash interrupted), or UINT32_MAX. */
static uint32_t read_records(const char *buf, size_t len, cf_result *results, uint32_t n)
{
    lg_wire_reader r = { buf, buf + len, false };
    uint32_t open = UINT32_MAX;
    while (r.p < r.end && !r.bad) {
        char tag = *r.p++;
        uint64_t i = lg_wire_get_u64(&r);
        if (r.bad || i >= n)
            break;
        if (tag == 'B') {
            open = (uint32_t)i;
            continue;
        }
        if (tag != 'R')
            break;
        cf_result *x = &results[i];
        lg_wire_reader save = r;
        x->phase = (int)lg_wire_get_u64(&r);
        x->gated = lg_wire_get_u64(&r) != 0;
        x->error = lg_wire_get_text(&r);
        x->diff_count = lg_wire_get_u64(&r);
        x->diff_max = lg_wire_get_f64(&r);
        x->diff_where = lg_wire_get_text(&r);
        x->resize_bad = lg_wire_get_text(&r);
        x->rss0 = lg_wire_get_u64(&r);
        x->rss1 = lg_wire_get_u64(&r);
        x->live0 = lg_wire_get_u64(&r);
        x->live1 = lg_wire_get_u64(&r);
        x->peak = lg_wire_get_u64(&r);
        x->ms = lg_wire_get_f64(&r);
        uint64_t no = lg_wire_get_u64(&r);
        for (uint64_t o = 0; o < no && o < CF_MAX_OUT && !r.bad; o++) {
            cf_out *y = &x->outs[x->n_outs++];
            y->name = lg_wire_get_text(&r);
            y->kind = (lg_resource_kind)lg_wire_get_u64(&r);
            y->written = lg_wire_get_u64(&r) != 0;
            y->values = lg_wire_get_u64(&r) != 0;
            y->w = (uint32_t)lg_wire_get_u64(&r);
            y->h = (uint32_t)lg_wire_get_u64(&r);
            y->d = (uint32_t)lg_wire_get_u64(&r);
            y->nf = (size_t)lg_wire_get_u64(&r);
            if (y->nf && (size_t)(r.end - r.p) / sizeof(float) >= y->nf) {
                y->f = lg_xmalloc(y->nf * sizeof(float));
                lg_wire_get_raw(&r, y->f, y->nf * sizeof(float));
            } else if (y->nf) {
                r.bad = true;
            }
        }
        if (r.bad) { /* cut short by the child's death: not reported after all */
            result_free(x);
            r = save;
            break;
        }
        x->done = true;
        open = UINT32_MAX;
    }
    return open;
}

/* Runs every case of type t in children: one child runs them in order; when it dies (or
 * stops reporting for c->timeout seconds), the case it was in is marked crashed (the signal)
 * and a new child carries on with the next one. */
static void run_cases(cf_ctx *c, const lg_node_type *t, const cf_case *cases, uint32_t n,
                      cf_result *results)
{
    uint32_t from = 0;
    while (from < n) {
        int fds[2];
        if (pipe(fds)) {
            report(&c->rep, CF_FAIL, t->name, "harness", "pipe: %s", strerror(errno));
            return;
        }
        fflush(stdout);
        fflush(stderr);
        pid_t pid = fork();
        if (pid < 0) {
            report(&c->rep, CF_FAIL, t->name, "harness", "fork: %s", strerror(errno));
            close(fds[0]);
            close(fds[1]);
            return;
        }
        if (pid == 0) {
            close(fds[0]);
            if (!c->verbose) {
                /* the errors travel in the records; the rest (warnings about the hostile
                 * inputs, which are expected) is noise here */
                int nul = open("/dev/null", O_WRONLY);
                if (nul >= 0)
                    dup2(nul, 2);
            }
            child_main(c, t, cases, from, n, fds[1]);
            close(fds[1]);
            fflush(NULL);
            /* exit, not _exit: a leak checker (the sanitizer build) reports on what the
             * destroyed nodes left */
            exit(0);
        }
        close(fds[1]);
        lg_str buf = { 0 };
        char chunk[65536];
        bool timed_out = false;
        for (;;) {
            struct pollfd pf = { fds[0], POLLIN, 0 };
            int pr = poll(&pf, 1, (int)(c->timeout * 1000));
            if (pr < 0 && errno == EINTR)
                continue;
            if (pr == 0) {
                timed_out = true;
                kill(pid, SIGKILL);
                break;
            }
            ssize_t got = read(fds[0], chunk, sizeof chunk);
            if (got < 0 && errno == EINTR)
                continue;
            if (got <= 0)
                break;
            lg_str_addn(&buf, chunk, (size_t)got);
        }
        close(fds[0]);
        int st = 0;
        while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
        }
        uint32_t open = read_records(buf.s, buf.len, results, n);
        lg_str_free(&buf);
        if (open == UINT32_MAX) {
            /* every case begun was reported: a death after the last (at exit: a leak found
             * by the sanitizer, a crash in a library's destructor) belongs to no case */
            uint32_t last = from;
            while (last < n && results[last].done)
                last++;
            if (last < n) { /* died between cases: blame the next one */
                results[last].done = true;
                results[last].crashed = WIFSIGNALED(st) ? WTERMSIG(st) : -2;
                from = last + 1;
                continue;
            }
            if (!WIFEXITED(st) || WEXITSTATUS(st) != 0)
                report(&c->rep, CF_FAIL, t->name, "exit",
                       "the child process that ran the cases ended with %s %d after the last "
                       "one (a leak found by the sanitizer, or a crash at exit)",
                       WIFSIGNALED(st) ? "signal" : "status",
                       WIFSIGNALED(st) ? WTERMSIG(st) : WEXITSTATUS(st));
            break;
        }
        results[open].done = true;
        results[open].crashed = timed_out ? -1 : WIFSIGNALED(st) ? WTERMSIG(st) : -2;
        from = open + 1;
    }
}

/* ---- judging --------------------------------------------------------------------------------- */

static bool device_missing(const cf_result *r)
{
    return r->error &&
           (strstr(r->error, "no OpenGL 4.5 device") || strstr(r->error, "no OpenCL device"));
}

static const char *phase_text(int phase)
{
    return phase == 1   ? "the graph did not check"
           : phase == 2 ? "create/prepare failed"
                        : "execute failed";
}

static char *crash_text(const cf_result *r, double timeout)
{
    if (r->crashed == -1)
        return lg_xasprintf("stopped after %.0f s without finishing (a hang or far too slow "
                            "for its defaults)",
                            timeout);
    if (r->crashed == -2)
        return lg_xstrdup("the process ended in the middle of it");
    return lg_xasprintf("crashed (signal %d, %s)", r->crashed, strsignal(r->crashed));
}

/* Values that are not finite in the outputs: count, and the first as text in where[n]. */
static uint64_t nonfinite(const cf_result *r, char *where, size_t n)
{
    uint64_t count = 0;
    where[0] = 0;
    for (uint32_t o = 0; o < r->n_outs; o++) {
        const cf_out *x = &r->outs[o];
        for (size_t i = 0; i < x->nf; i++)
            if (!isfinite(x->f[i]) && count++ == 0)
                snprintf(where, n, "output '%s' value %zu (pixel %zu, channel %zu) = %g", x->name,
                         i, i / 4, i % 4, x->f[i]);
    }
    return count;
}

/* The error text of a failed case, classified: the check it breaks. */
static const char *error_check(const char *e)
{
    if (!e)
        return "runs";
    if (strstr(e, "left GL state behind"))
        return "gl_state";
    /* the host's GL check after execute ("GL error GL_INVALID_... while executing"), and
     * lg_cl_fail's "clCall: CL_INVALID_... (-NN)" */
    if (strstr(e, "GL error") || strstr(e, ": CL_") || strstr(e, "OpenCL error"))
        return "device_errors";
    return "runs";
}

static bool needs_file(const lg_node_type *t, const char **key)
{
    for (uint32_t k = 0; k < t->n_params; k++) {
        const lg_param_desc *p = &t->params[k];
        if ((p->type == LG_PARAM_PATH || p->type == LG_PARAM_PATH_LIST) &&
            p->role != LG_ROLE_OUTPUT_FILE && (!p->def.s || !p->def.s[0])) {
            *key = p->key;
            return true;
        }
    }
    return false;
}

/* The largest relative difference of b against the reference a, over every output value:
 * max |a - b| / max(1, max |a|), per output; returns the worst output's in *where. */
static double disagreement(const cf_result *a, const cf_result *b, char *where, size_t n)
{
    double worst = 0;
    where[0] = 0;
    for (uint32_t o = 0; o < a->n_outs && o < b->n_outs; o++) {
        const cf_out *x = &a->outs[o], *y = &b->outs[o];
        if (!x->values || !y->values)
            continue;
        if (x->nf != y->nf) {
            snprintf(where, n, "output '%s': %ux%ux%u against %ux%ux%u", x->name, y->w, y->h, y->d,
                     x->w, x->h, x->d);
            return INFINITY;
        }
        double amax = 0, dmax = 0;
        size_t at = 0;
        for (size_t i = 0; i < x->nf; i++) {
            if (!isfinite(x->f[i]) || !isfinite(y->f[i]))
                continue;
            amax = fmax(amax, fabs(x->f[i]));
            double d = fabs((double)x->f[i] - (double)y->f[i]);
            if (d > dmax)
                dmax = d, at = i;
        }
        double rel = dmax / fmax(1.0, amax);
        if (rel > worst) {
            worst = rel;
            snprintf(where, n,
                     "output '%s': max abs diff %.6g at value %zu (pixel %zu, "
                     "channel %zu: %.6g against %.6g) / max(1, %.6g)",
                     x->name, dmax, at, at / 4, at % 4, y->f[at], x->f[at], amax);
        }
    }
    return worst;
}

/* The check a case of this mode proves, named in a report when the case crashed or failed. */
static const char *mode_check(const cf_case *k)
{
    switch (k->mode) {
    case CF_RUN: return k->baseline ? "runs" : "hostile";
    case CF_TWICE: return "determinism";
    case CF_RESIZE: return "resize";
    case CF_SQUEEZE: return "failed_prepare";
    case CF_FRAMES: return "memory";
    case CF_GATE: break;
    }
    return "gating";
}

static const char *error_or_none(const cf_result *r)
{
    return r->error ? r->error : "no message";
}

/* The case was reported, did not crash, and every phase passed. */
static bool ran_clean(const cf_result *r)
{
    return r->done && !r->crashed && !r->phase;
}

/* One node type being judged, case after case. */
typedef struct cf_judge {
    cf_report *rep;
    const lg_node_type *t;
    const char *name;
    const char *fkey; /* the parameter naming a file with no default (needs_file) */
    bool file;
    bool base_ok[8];   /* per backend: its baseline ran */
    bool base_skip[8]; /* per backend: it cannot run here (no device, a file needed):
                        * its other cases are not judged */
    char own[300];     /* how a message of the node's names it: "node 'T' (T)" */
} cf_judge;

/* CF_SQUEEZE: a prepare made to fail must fail with the node named, and destroy cope. */
static void judge_squeeze(cf_judge *j, const cf_result *r, const char *label, int bi)
{
    if (r->phase == 2 && r->error && strstr(r->error, j->own))
        report(j->rep, CF_PASS, j->name, "failed_prepare",
               "%s: prepare failed (%s), destroy ran without a crash", label, error_or_none(r));
    else if (j->base_ok[bi])
        report(j->rep, CF_NOTE, j->name, "failed_prepare",
               "%s: a one-pixel limit did not make its prepare fail (%s); not checked", label,
               r->phase == 0 ? "it declares no image larger than a pixel" : error_or_none(r));
}

/* CF_GATE: a scene lacking the declared needs must get the node gated, not failed. */
static void judge_gate(cf_judge *j, const cf_result *r, const char *label)
{
    if (r->phase)
        report(j->rep, CF_FAIL, j->name, "gating",
               "%s: the plan failed instead of gating "
               "the node (%s): %s",
               label, phase_text(r->phase), error_or_none(r));
    else if (!r->gated)
        report(j->rep, CF_FAIL, j->name, "gating",
               "%s: the node declares needs 0x%x and was "
               "not gated on a scene that lacks them",
               label, j->t->needs);
    else
        report(j->rep, CF_PASS, j->name, "gating", "%s: gated (needs 0x%x)", label, j->t->needs);
}

/* A case whose check, plan or run failed (r->phase): a broken contract, a hostile input
 * refused as it should be, a format not accepted, or a node conform cannot run. */
static void judge_failed(cf_judge *j, const cf_case *k, const cf_result *r, const char *label,
                         int bi, bool first_of_backend)
{
    const char *check = error_check(r->error);
    bool hostile = k->mode == CF_RUN && !k->baseline;
    if (strcmp(check, "runs") != 0) {
        report(j->rep, CF_FAIL, j->name, check, "%s: %s", label, r->error);
    } else if (hostile) {
        if (k->scene == LG_CONFORM_SCENE_UNLIT && j->t->needs == 0 &&
            has_input(j->t, LG_KIND_SCENE))
            /* geometry without lights, medium, probe or specular and reflective
             * terms: what the needs flags describe; a node that cannot work
             * without one of them says so in `needs`, and is gated (an error on
             * the empty scene, with no geometry at all, is a clear error) */
            report(j->rep, CF_FAIL, j->name, "gating",
                   "%s: %s on a scene with geometry and no lights, medium, probe or "
                   "specular or reflective material, and the node declares no needs "
                   "(lg_node_type.needs) for the planner to gate it by: %s",
                   label, phase_text(r->phase), error_or_none(r));
        else if (!r->error)
            report(j->rep, CF_FAIL, j->name, "hostile", "%s: %s without an error message", label,
                   phase_text(r->phase));
        else
            report(j->rep, CF_PASS, j->name, "hostile", "%s: refused with an error: %s", label,
                   r->error);
    } else if (k->mode == CF_RUN && k->format != 0 && r->phase == 2 && r->error) {
        report(j->rep, CF_NOTE, j->name, "runs", "%s: not accepted: %s", label, r->error);
    } else if (j->file && first_of_backend) {
        j->base_skip[bi] = true;
        report(j->rep, CF_SKIP, j->name, "runs",
               "%s: parameter '%s' names a file and has no "
               "default, so conform cannot run it (%s: %s)",
               label, j->fkey, phase_text(r->phase), error_or_none(r));
    } else if (k->mode == CF_RUN || j->base_ok[bi]) {
        report(j->rep, CF_FAIL, j->name, mode_check(k), "%s: %s: %s", label, phase_text(r->phase),
               error_or_none(r));
    }
}

/* The outputs of a case that ran: every one written; finite on finite input, a hostile
 * input's bad pixel not spread. */
static void judge_outputs(cf_judge *j, const cf_case *k, const cf_result *r, const char *label)
{
    char where[512];
    for (uint32_t o = 0; o < r->n_outs; o++)
        if (!r->outs[o].written)
            report(j->rep, CF_FAIL, j->name, "outputs",
                   "%s: output '%s' was declared and "
                   "never written on any device",
                   label, r->outs[o].name);
    uint64_t bad = nonfinite(r, where, sizeof where);
    if (k->mode == CF_RUN && k->baseline) {
        if (bad)
            report(j->rep, CF_FAIL, j->name, "finite",
                   "%s: %llu values not finite on finite "
                   "input; first: %s",
                   label, (unsigned long long)bad, where);
    } else if (k->mode == CF_RUN) {
        bool contained = k->pattern == LG_CONFORM_NAN || k->pattern == LG_CONFORM_INF;
        /* one bad input pixel may stay one bad pixel per output; it must not spread */
        uint64_t allowed = contained ? 4u * r->n_outs : 0;
        if (bad > allowed)
            report(j->rep, CF_FAIL, j->name, "hostile",
                   "%s: %llu values not finite (at most "
                   "%llu allowed: %s); first: %s",
                   label, (unsigned long long)bad, (unsigned long long)allowed,
                   contained ? "the one non-finite input pixel, not spread" : "finite input",
                   where);
        else if (bad)
            report(j->rep, CF_PASS, j->name, "hostile",
                   "%s: %llu non-finite values, where "
                   "the input's bad pixel was",
                   label, (unsigned long long)bad);
        else
            report(j->rep, CF_PASS, j->name, "hostile", "%s: finite output", label);
    }
}

/* CF_FRAMES: neither the plugin's live memory nor the process's may grow over the frames. */
static void judge_memory(cf_judge *j, const cf_result *r, const char *label)
{
    int64_t grow = (int64_t)r->rss1 - (int64_t)r->rss0;
    if (r->live1 > r->live0)
        report(j->rep, CF_FAIL, j->name, "memory",
               "%s: the profile's live plugin memory "
               "(bytes_plugin_live) grew from %llu bytes after frame %u to %llu after "
               "frame %u (peak %llu): lg_account_alloc without lg_account_free",
               label, (unsigned long long)r->live0, cf_frames_from, (unsigned long long)r->live1,
               cf_frames_n, (unsigned long long)r->peak);
    else if (grow > (int64_t)cf_rss_slack)
        report(j->rep, CF_FAIL, j->name, "memory",
               "%s: %s grew by %.1f MiB "
               "from frame %u to frame %u (%.2f MiB a frame; %u MiB allowed in all)",
               label, cf_mem_what, (double)grow / 1048576.0, cf_frames_from, cf_frames_n,
               (double)grow / 1048576.0 / (cf_frames_n - cf_frames_from),
               (unsigned)(cf_rss_slack >> 20));
    else
        report(j->rep, CF_PASS, j->name, "memory",
               "%s: %s %+.2f MiB, plugin live %llu "
               "-> %llu bytes over frames %u..%u",
               label, cf_mem_what, (double)grow / 1048576.0, (unsigned long long)r->live0,
               (unsigned long long)r->live1, cf_frames_from, cf_frames_n);
}

/* A case that ran: its outputs, then what its mode checks. */
static void judge_ran(cf_judge *j, const cf_case *k, const cf_result *r, const char *label)
{
    if (r->gated && k->mode != CF_GATE)
        report(j->rep, CF_NOTE, j->name, "gating",
               "%s: gated by the planner (needs 0x%x), so "
               "not run",
               label, j->t->needs);
    judge_outputs(j, k, r, label);
    if (k->mode == CF_TWICE) {
        if (r->diff_count)
            report(j->rep, CF_FAIL, j->name, "determinism",
                   "%s: two runs differ in %llu "
                   "values, largest difference %.6g at %s",
                   label, (unsigned long long)r->diff_count, r->diff_max,
                   r->diff_where ? r->diff_where : "?");
        else
            report(j->rep, CF_PASS, j->name, "determinism", "%s: identical", label);
    }
    if (k->mode == CF_RESIZE) {
        if (r->resize_bad)
            report(j->rep, CF_FAIL, j->name, "resize", "%s: %s", label, r->resize_bad);
        else
            report(j->rep, CF_PASS, j->name, "resize", "%s: prepared again at the new size", label);
    }
    if (k->mode == CF_FRAMES)
        judge_memory(j, r, label);
}

/* One case: a crash fails the check its mode proves; a backend with no device here is
 * skipped at its first baseline, and its other cases are not judged; then by mode. */
static void judge_case(cf_judge *j, const cf_case *k, const cf_result *r, double timeout)
{
    int bi = k->backend < 0 ? 0 : k->backend;
    char label[200];
    case_label(label, sizeof label, j->t, k);
    if (!r->done) {
        report(j->rep, CF_FAIL, j->name, "harness",
               "%s: no result (the child stopped "
               "reporting)",
               label);
        return;
    }
    bool first_of_backend = k->baseline && k->w == 7 && k->format == 0;
    if (r->crashed) {
        char *ct = crash_text(r, timeout);
        report(j->rep, CF_FAIL, j->name, mode_check(k), "%s: %s", label, ct);
        free(ct);
        return;
    }
    if (j->base_skip[bi])
        return;
    if (r->ms > 2000)
        report(j->rep, CF_NOTE, j->name, "time", "%s took %.1f s", label, r->ms / 1e3);
    if (device_missing(r)) {
        if (first_of_backend) {
            j->base_skip[bi] = true;
            report(j->rep, CF_SKIP, j->name, "runs", "%s: %s", label, r->error);
        }
        return;
    }
    if (first_of_backend && r->phase == 0)
        j->base_ok[bi] = true;
    if (k->mode == CF_SQUEEZE)
        judge_squeeze(j, r, label, bi);
    else if (k->mode == CF_GATE)
        judge_gate(j, r, label);
    else if (r->phase)
        judge_failed(j, k, r, label, bi, first_of_backend);
    else
        judge_ran(j, k, r, label);
}

/* Backends against the reference, cpu (the first one, for a node without cpu), on the same
 * inputs: every baseline of another backend against the reference's of the same size and
 * format, within the type's tolerance. */
static void judge_backends(cf_report *rep, const lg_node_type *t, const cf_case *cases, uint32_t n,
                           const cf_result *res)
{
    double tol = t->tolerance > 0 ? t->tolerance : 1e-3;
    char where[512];
    int ref = 0;
    const char *const *bv;
    uint32_t nb = backends_of(t, &bv);
    for (uint32_t b = 0; b < nb; b++)
        if (strcmp(bv[b], "cpu") == 0)
            ref = (int)b;
    for (uint32_t i = 0; i < n; i++) {
        const cf_case *k = &cases[i];
        if (k->mode != CF_RUN || !k->baseline || k->backend < 0 || k->backend == ref ||
            !ran_clean(&res[i]))
            continue;
        for (uint32_t j = 0; j < n; j++) {
            const cf_case *q = &cases[j];
            if (q->mode != CF_RUN || !q->baseline || q->backend != ref || q->w != k->w ||
                q->h != k->h || q->format != k->format || !ran_clean(&res[j]))
                continue;
            char label[200];
            case_label(label, sizeof label, t, k);
            double d = disagreement(&res[j], &res[i], where, sizeof where);
            if (d > tol)
                report(rep, CF_FAIL, t->name, "backends",
                       "%s against %s: %s = %.6g > "
                       "tolerance %g%s",
                       label, backend_name(t, ref), where, d, tol,
                       t->tolerance > 0 ? "" : " (the default; lg_node_type.tolerance)");
            else
                report(rep, CF_PASS, t->name, "backends", "%s against %s: %.3g <= %g", label,
                       backend_name(t, ref), d, tol);
        }
    }
}

static void judge_type(cf_ctx *c, const lg_node_type *t, const cf_case *cases, uint32_t n,
                       cf_result *res)
{
    cf_judge j;
    memset(&j, 0, sizeof j);
    j.rep = &c->rep;
    j.t = t;
    j.name = t->name;
    j.file = needs_file(t, &j.fkey);
    snprintf(j.own, sizeof j.own, "node '%s' (%s)", t->name, t->name);
    int n_fail_before = (int)c->rep.counts[CF_FAIL];
    for (uint32_t i = 0; i < n; i++)
        judge_case(&j, &cases[i], &res[i], c->timeout);
    judge_backends(&c->rep, t, cases, n, res);
    bool any_skip = false;
    for (int b = 0; b < 8; b++)
        any_skip |= j.base_skip[b];
    if ((int)c->rep.counts[CF_FAIL] == n_fail_before && !any_skip) {
        double ms = 0;
        for (uint32_t i = 0; i < n; i++)
            ms += res[i].ms;
        report(&c->rep, CF_PASS, t->name, "runs", "%u cases, %.0f ms of runs", n, ms);
    }
}

/* The cases of one node type, every backend. */
static uint32_t make_cases(const lg_node_type *t, cf_case **out, bool quick)
{
    const char *const *bv;
    uint32_t nb = backends_of(t, &bv);
    bool img = has_input(t, LG_KIND_IMAGE);
    bool scene = has_input(t, LG_KIND_SCENE);
    bool patterned = false;
    for (uint32_t k = 0; k < t->n_inputs; k++) {
        const char *s = lg_conform_source_for(t->inputs[k].kind);
        patterned |= s && strcmp(s, "conform_scene") != 0;
    }
    static const uint32_t sizes[3][2] = { { 7, 5 }, { 1, 1 }, { 256, 256 } };
    uint32_t cap = 64 * (nb ? nb : 1), n = 0;
    cf_case *c = lg_xcalloc(cap, sizeof *c);
    for (int b = nb ? 0 : -1; b < (int)(nb ? nb : 0); b++) {
        cf_case base = { .mode = CF_RUN, .backend = b, .w = 7, .h = 5, .baseline = true };
        for (int s = 0; s < (quick ? 2 : 3); s++) /* --quick: no 256x256 */
            for (int f = 0; f < (img ? 4 : 1); f++) {
                c[n] = base;
                c[n].w = sizes[s][0], c[n].h = sizes[s][1], c[n].format = f;
                n++;
            }
        if (patterned)
            for (int p = LG_CONFORM_NAN; p <= LG_CONFORM_HUGE; p++) {
                c[n] = base;
                c[n].baseline = false;
                c[n++].pattern = p;
            }
        if (scene)
            for (int s = LG_CONFORM_SCENE_EMPTY; s <= LG_CONFORM_SCENE_UNLIT; s++) {
                c[n] = base;
                c[n].baseline = false;
                c[n++].scene = s;
            }
        static const cf_mode life[] = { CF_TWICE, CF_RESIZE, CF_SQUEEZE, CF_FRAMES };
        for (size_t m = 0; m < sizeof life / sizeof life[0]; m++) {
            c[n] = base;
            c[n].baseline = false;
            c[n++].mode = life[m];
        }
        if (t->needs && b == (nb ? 0 : -1)) {
            c[n] = base;
            c[n].baseline = false;
            c[n].mode = CF_GATE;
            c[n++].scene = LG_CONFORM_SCENE_EMPTY;
        }
    }
    *out = c;
    return n;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static void check_descriptor(cf_ctx *c)
{
    cf_report *rep = &c->rep;
    const lg_plugin *p = c->plugin;
    char why[512];
    report(rep, CF_PASS, NULL, "descriptor",
           "plugin '%s' %s, ABI %u.%u (host %d.%d), %u node "
           "types",
           p->name, p->version, p->abi_major, p->abi_minor, LG_ABI_MAJOR, LG_ABI_MINOR, p->n_types);
    if (!lg_name_rule_ok(p->name, NULL, why, sizeof why))
        report(rep, CF_FAIL, NULL, "naming", "%s", why);
    if (!p->doc || !p->doc[0])
        report(rep, CF_FAIL, NULL, "docs", "plugin '%s' has no doc line", p->name);
    for (uint32_t i = 0; i < p->n_types; i++) {
        const lg_node_type *t = &p->types[i];
        for (uint32_t j = 0; j < i; j++)
            if (strcmp(p->types[j].name, t->name) == 0)
                report(rep, CF_FAIL, t->name, "descriptor",
                       "node type '%s' declared twice "
                       "(types %u and %u)",
                       t->name, j, i);
        if (strncmp(t->name, "conform_", 8) == 0)
            report(rep, CF_FAIL, t->name, "naming",
                   "node type '%s' uses the prefix conform_, "
                   "which the program's own synthetic sources hold",
                   t->name);
        if (!lg_name_rule_ok(p->name, t->name, why, sizeof why))
            report(rep, CF_FAIL, t->name, "naming", "%s", why);
        if (!t->doc || !t->doc[0])
            report(rep, CF_FAIL, t->name, "docs", "node type '%s' has no doc line", t->name);
        if (!(t->tolerance >= 0 && t->tolerance < 1))
            report(rep, CF_FAIL, t->name, "descriptor", "tolerance %g is not in [0, 1)",
                   t->tolerance);
        for (uint32_t k = 0; k < t->n_params; k++) {
            const lg_param_desc *q = &t->params[k];
            if (!q->doc || !q->doc[0])
                report(rep, CF_FAIL, t->name, "docs", "parameter '%s' has no doc", q->key);
            /* the registry's validator (the scan) already refused defaults outside their
             * range or enum values; the aliases are conform's to check */
            for (int a = 0; q->renamed_from && q->renamed_from[a]; a++) {
                const char *al = q->renamed_from[a];
                for (uint32_t m = 0; m < t->n_params; m++) {
                    if (strcmp(t->params[m].key, al) == 0)
                        report(rep, CF_FAIL, t->name, "aliases",
                               "parameter '%s' was renamed "
                               "from '%s', which is the key of parameter %u",
                               q->key, al, m);
                    for (int b = 0; t->params[m].renamed_from && t->params[m].renamed_from[b]; b++)
                        if ((m != k || b != a) && strcmp(t->params[m].renamed_from[b], al) == 0 &&
                            (m > k || (m == k && b > a)))
                            report(rep, CF_FAIL, t->name, "aliases",
                                   "old key '%s' is an alias "
                                   "of both '%s' and '%s'",
                                   al, q->key, t->params[m].key);
                }
                for (uint32_t m = 0; m < t->n_inputs; m++)
                    if (strcmp(t->inputs[m].name, al) == 0)
                        report(rep, CF_FAIL, t->name, "aliases",
                               "parameter '%s' was renamed "
                               "from '%s', which is an input port's name",
                               q->key, al);
            }
            if (strcmp(q->key, "backend") == 0) {
                /* the shared contract (LG_PARAM_BACKEND): an enum of cpu, gl, cl in that
                 * order */
                static const char *const order[] = { "cpu", "gl", "cl" };
                int at = 0;
                bool ok = q->type == LG_PARAM_ENUM && q->enum_values && q->enum_values[0];
                for (int v = 0; ok && q->enum_values[v]; v++) {
                    while (at < 3 && strcmp(order[at], q->enum_values[v]) != 0)
                        at++;
                    ok = at < 3;
                    at++;
                }
                if (!ok)
                    report(rep, CF_FAIL, t->name, "descriptor",
                           "parameter 'backend' is not the "
                           "shared one (LG_PARAM_BACKEND: an enum of cpu, gl, cl in that order)");
            }
        }
        for (uint32_t k = 0; k < t->n_inputs + t->n_outputs; k++) {
            const lg_port_desc *q = k < t->n_inputs ? &t->inputs[k] : &t->outputs[k - t->n_inputs];
            for (uint32_t m = 0; m < k; m++) {
                const lg_port_desc *o = m < t->n_inputs ? &t->inputs[m]
                                                        : &t->outputs[m - t->n_inputs];
                if (strcmp(o->name, q->name) == 0 && (m < t->n_inputs) == (k < t->n_inputs))
                    report(rep, CF_FAIL, t->name, "descriptor", "port '%s' declared twice",
                           q->name);
            }
            if (k < t->n_inputs)
                for (uint32_t m = 0; m < t->n_params; m++)
                    if (strcmp(t->params[m].key, q->name) == 0)
                        report(rep, CF_FAIL, t->name, "descriptor",
                               "input '%s' has the name of "
                               "a parameter",
                               q->name);
        }
    }
}

/* ---- the command ----------------------------------------------------------------------------- */

static void print_text(const cf_ctx *c, FILE *f)
{
    const cf_report *r = &c->rep;
    for (uint32_t i = 0; i < r->n; i++) {
        const cf_item *x = &r->items[i];
        if (x->status == CF_PASS && !c->verbose)
            continue;
        fprintf(f, "%-4s %s%s%s%s: %s\n", status_names[x->status], x->node ? "node type '" : "",
                x->node ? x->node : "plugin", x->node ? "' " : " ", x->check, x->message);
    }
    fprintf(f, "conform %s: %u passed, %u failed, %u skipped, %u notes: %s\n", c->path,
            r->counts[CF_PASS], r->counts[CF_FAIL], r->counts[CF_SKIP], r->counts[CF_NOTE],
            r->counts[CF_FAIL] ? "FAILS its contracts" : "conforms");
}

static void print_json(const cf_ctx *c, FILE *f)
{
    const cf_report *r = &c->rep;
    lg_str s = { 0 };
    lg_str_add(&s, "{\"plugin\": ");
    lg_str_add_json(&s, c->path);
    lg_str_add(&s, ", \"name\": ");
    lg_str_add_json(&s, c->plugin ? c->plugin->name : "");
    lg_str_addf(&s,
                ", \"conforms\": %s, \"passed\": %u, \"failed\": %u, \"skipped\": %u, "
                "\"notes\": %u, \"results\": [",
                r->counts[CF_FAIL] ? "false" : "true", r->counts[CF_PASS], r->counts[CF_FAIL],
                r->counts[CF_SKIP], r->counts[CF_NOTE]);
    static const char *const st[] = { "pass", "fail", "skip", "note" };
    for (uint32_t i = 0; i < r->n; i++) {
        const cf_item *x = &r->items[i];
        lg_str_addf(&s, "%s\n  {\"status\": \"%s\", \"node\": ", i ? "," : "", st[x->status]);
        if (x->node)
            lg_str_add_json(&s, x->node);
        else
            lg_str_add(&s, "null");
        lg_str_add(&s, ", \"check\": ");
        lg_str_add_json(&s, x->check);
        lg_str_add(&s, ", \"message\": ");
        lg_str_add_json(&s, x->message);
        lg_str_add(&s, "}");
    }
    lg_str_add(&s, "\n]}\n");
    fputs(s.s, f);
    lg_str_free(&s);
}

static int usage(const char *msg, const char *what)
{
    if (msg)
        fprintf(stderr, msg, what);
    fprintf(stderr, "usage: lightgraph conform PLUGIN.so [--json] [--quick] [-v]\n"
                    "  checks one plugin's contracts (docs/conform.md); exit 0: it conforms, "
                    "1: it does not, 2: bad usage\n");
    return 2;
}

int lg_cmd_conform(int argc, char **argv)
{
    cf_ctx c;
    memset(&c, 0, sizeof c);
    c.timeout = 120;
    bool quick = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--json") == 0)
            c.json = true;
        else if (strcmp(argv[i], "--quick") == 0)
            quick = true;
        else if (strcmp(argv[i], "-v") == 0)
            c.verbose = true;
        else if (argv[i][0] == '-')
            return usage("lightgraph conform: unknown option '%s'\n", argv[i]);
        else if (!c.path)
            c.path = argv[i];
        else
            return usage("lightgraph conform: one plugin at a time ('%s' is a second)\n", argv[i]);
    }
    if (!c.path)
        return usage("lightgraph conform: no plugin given\n", "");
    if (quick) {
        cf_frames_n = 10;
        cf_frames_from = 4;
        cf_rss_slack = 4u << 20;
    }
    struct stat st;
    errno = 0;
    if (stat(c.path, &st) != 0 || !S_ISREG(st.st_mode)) {
        fprintf(stderr, "lightgraph conform: %s: %s\n", c.path,
                errno ? strerror(errno) : "not a regular file");
        return 2;
    }
    const char *to = getenv("LIGHTGRAPH_CONFORM_TIMEOUT");
    if (to && atof(to) > 0)
        c.timeout = atof(to);
    /* the plugin alone (scanned in a child process, as always), then the program's own
     * sources; nothing from LIGHTGRAPH_PLUGIN_PATH or the build tree */
    int verbosity = lg_verbosity;
    lg_verbosity = -1; /* a refusal is reported below, as a failed check */
    char *paths[1] = { (char *)c.path };
    lg_registry_scan_files(&c.reg, paths, 1);
    lg_verbosity = verbosity;
    if (c.reg.n_plugins == 1)
        c.plugin = c.reg.plugins[0];
    char err[1024];
    if (!c.plugin) {
        report(&c.rep, CF_FAIL, NULL, "descriptor", "the host refuses the plugin: %s",
               c.reg.n_refused ? c.reg.refused[0].reason : "it was not scanned");
    } else if (lg_registry_add_builtin(&c.reg, lg_conform_sources(), "<lightgraph conform>", err,
                                       sizeof err)) {
        report(&c.rep, CF_FAIL, NULL, "harness", "%s", err);
    } else {
        check_descriptor(&c);
        for (uint32_t i = 0; i < c.plugin->n_types; i++) {
            const lg_node_type *t = &c.plugin->types[i];
            if (lg_registry_lookup(&c.reg, t->name, NULL) != t)
                continue; /* a duplicate, reported above */
            const char *unfed = unfed_input(t);
            if (unfed) {
                report(&c.rep, CF_SKIP, t->name, "runs",
                       "input '%s' is of a kind conform "
                       "cannot make; nothing run",
                       unfed);
                continue;
            }
            cf_case *cases;
            uint32_t n = make_cases(t, &cases, quick);
            cf_result *res = lg_xcalloc(n, sizeof *res);
            run_cases(&c, t, cases, n, res);
            judge_type(&c, t, cases, n, res);
            for (uint32_t k = 0; k < n; k++)
                result_free(&res[k]);
            free(res);
            free(cases);
        }
    }
    if (c.json)
        print_json(&c, stdout);
    else
        print_text(&c, c.rep.counts[CF_FAIL] ? stderr : stdout);
    int rc = c.rep.counts[CF_FAIL] ? 1 : 0;
    report_free(&c.rep);
    lg_registry_free(&c.reg);
    return rc;
}
