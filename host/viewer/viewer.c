/* lightgraph view: the graph in a GLFW window (docs/viewer.md).
 *
 * One thread, one loop; each turn of it is a frame:
 *
 *   1. events: the window's (GLFW callbacks), or the --script's next lines, which call the
 *      same handlers;
 *   2. reloads: the watcher's changes (graph files, plugin .so files, shaders in a
 *      development build, which run the build first) are applied between frames, never
 *      while one is in flight;
 *   3. the frame: lg_exec_frame runs what must run (per-frame nodes, nodes never run, nodes
 *      that read the scene when the camera moved, and what reads them);
 *   4. the picture: the shown image through lg_vdisplay (exposure, sRGB as the PNG writer
 *      encodes), the overlay (timings, plan, selection, status), swap.
 *
 * Every change (a parameter key, a method switch, an edit of the graph, a rebuilt plugin)
 * is a new plan made with the previous one as ex->prev: the planner adopts the nodes whose
 * identity, plugin and inputs are unchanged, with their resources, caches and state. The
 * new plan replaces the old only once its first frame ran; otherwise it is rolled back and
 * the old plan goes on showing the last good frame, with the error on screen.
 */
#include "plan/plan.h"
#include "viewer/viewer.h"

#include <dlfcn.h>
#include <errno.h>
#include <link.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/wait.h>
#include <unistd.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "exec/gl_backend.h"
#include "lightgraph/image.h"
#include "lightgraph/kinds.h"
#include "exec/outputs.h"
#include "viewer/rebuild.h"
#include "viewer/camera.h"
#include "viewer/display.h"
#include "viewer/params.h"
#include "viewer/script.h"
#include "viewer/watch.h"

/* ---- state ----------------------------------------------------------------------------- */

/* One loaded graph: parsed, checked, planned, and what the window shows of it. */
typedef struct loaded {
    lg_graph *g;
    lg_checked *c;
    lg_exec *ex;
    lg_edge shown;              /* the image shown (node, port, part) */
    char *shown_name;           /* "tone.out" */
    bool display_referred;      /* a tone mapper is at or upstream of the shown image */
    char **files;               /* the graph file and its includes, absolute */
    uint32_t n_files;
} loaded;

typedef struct pointer_anim {  /* a scripted drag, one step a frame */
    bool active;
    int button, mods;
    double x0, y0, dx, dy;
    int step, steps;
} pointer_anim;

typedef struct viewer {
    /* arguments */
    const char *graph;
    const char **sets;
    int n_sets;
    char *show;                 /* --show NODE[.PORT], or a method switch's choice */
    lg_exec_opts opts;
    const char *script_path;

    lg_registry reg;
    GLFWwindow *win;
    lg_gl_device *gl;
    lg_cl_dev *cl;
    uint32_t timer_query;
    lg_vdisplay *disp;
    uint32_t cpu_tex;           /* the shown image when it is not a GL texture already */
    uint32_t cpu_tex_w, cpu_tex_h;

    loaded cur;                 /* the last good graph */
    uint32_t frame;
    bool frame_failed;          /* the current plan failed a frame: shown as it was */
    bool frame_done;            /* a (re)load ran this frame already */

    /* live changes */
    lg_overrides ov;
    lg_vparams *vp;

    /* camera */
    lg_vcam vcam;
    bool cam_on;                /* the viewer's camera overrides the graph's */
    lg_camera cam_out;
    uint64_t cam_gen;
    char *cam_scene_ref;        /* the node whose scene the camera node would read */
    float cam_bmin[3], cam_bmax[3]; /* that scene's bounds: the moved camera's clip planes */
    bool fly_speed_fast;

    /* display */
    float ev;                   /* exposure, stops */
    bool ev_auto_pending;
    bool overlay;
    double fps, last_t;

    /* status line: the last change and its outcome */
    char *status;
    bool status_error;
    uint64_t changes, changes_failed; /* counts of attempts (wait_reload, expect_*) */
    bool last_change_ok;
    char *last_error;           /* errors lg_hlog printed during the attempt */

    /* reloads */
    lg_watch *watch;
    char *dev_build, *dev_shaders;
    bool can_rebuild;
    lg_rebuild *rebuild;
    bool rebuild_again;
    char **pending_plugins;
    uint32_t n_pending_plugins;
    bool pending_graph;

    /* input */
    bool held[GLFW_KEY_LAST + 1];
    bool buttons[8];
    double mx, my;
    int mods;
    pointer_anim anim;

    /* script */
    lg_script script;
    bool scripted;
    uint32_t pc;
    uint32_t wait_until;        /* frame number */
    bool wait_reload;
    uint64_t wait_reload_from;
    double wait_deadline;
    int hold_key;
    uint32_t hold_until;
    char *window_shot;          /* screenshot_window pending */
    const lg_sevent *window_shot_ev; /* its script event (for the failure's line) */
    bool expect_failed;
    bool quit;
    int exit_status;
} viewer;

static viewer *g_viewer; /* for the GLFW callbacks and the error hook */

static void set_status(viewer *v, bool error, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_status(viewer *v, bool error, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *m = NULL;
    if (vasprintf(&m, fmt, ap) < 0)
        m = NULL;
    va_end(ap);
    free(v->status);
    v->status = m;
    v->status_error = error;
    if (m)
        fprintf(error ? stderr : stdout, "lightgraph view: %s\n", m);
    fflush(stdout);
}

static void error_hook(const char *message)
{
    viewer *v = g_viewer;
    if (!v)
        return;
    /* the first error of an attempt is the one that says why */
    if (!v->last_error)
        v->last_error = lg_xstrdup(message);
}

/* ---- loading a graph ----------------------------------------------------------------- */

static void loaded_free(loaded *l)
{
    if (l->ex) {
        lg_exec_free(l->ex);
        free(l->ex);
    }
    lg_checked_free(l->c);
    lg_graph_free(l->g);
    free(l->shown_name);
    for (uint32_t i = 0; i < l->n_files; i++)
        free(l->files[i]);
    free(l->files);
    memset(l, 0, sizeof *l);
}

static char *diags_text(const lg_diags *d)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f)
        return lg_xstrdup("(diagnostics could not be formatted)");
    lg_diags_print(d, f);
    fclose(f);
    while (len > 0 && buf[len - 1] == '\n')
        buf[--len] = 0;
    return buf;
}

/* Resolves what to show: --show NODE[.PORT] (or a method switch's), else the first output
 * statement. Returns 0, or -1 with err. */
static int resolve_shown(viewer *v, loaded *l, char *err, size_t errlen)
{
    const lg_checked *c = l->c;
    if (v->show) {
        const char *dot = strchr(v->show, '.');
        char *name = dot ? lg_xstrndup(v->show, (size_t)(dot - v->show)) : lg_xstrdup(v->show);
        int32_t ni = lg_graph_find_node(l->g, name);
        if (ni < 0) {
            snprintf(err, errlen, "--show %s: the graph has no node '%s'", v->show, name);
            free(name);
            return -1;
        }
        free(name);
        const lg_node_type *t = c->nodes[ni].type;
        uint32_t port = 0, part = 0;
        if (dot) {
            port = t->n_outputs;
            for (uint32_t o = 0; o < t->n_outputs; o++)
                if (strcmp(t->outputs[o].name, dot + 1) == 0)
                    port = o;
            /* NODE.PART, as in a graph: the part of the first output of a kind that has it
             * (shadow.atlas) */
            for (uint32_t o = 0; o < t->n_outputs && port == t->n_outputs; o++) {
                int32_t pi = lg_kind_part_index(t->outputs[o].kind, dot + 1);
                if (pi >= 0) {
                    port = o;
                    part = (uint32_t)pi + 1;
                }
            }
            if (port == t->n_outputs) {
                snprintf(err, errlen, "--show %s: node '%.*s' (%s) has no output or part '%s'",
                         v->show, (int)(dot - v->show), v->show, t->name, dot + 1);
                return -1;
            }
        } else if (t->n_outputs == 0) {
            snprintf(err, errlen, "--show %s: node '%s' has no output", v->show, v->show);
            return -1;
        }
        l->shown = (lg_edge){ni, port, part};
    } else {
        if (c->n_outputs == 0) {
            snprintf(err, errlen, "%s has no output statement: name the image to show with "
                     "--show NODE.PORT", v->graph);
            return -1;
        }
        l->shown = (lg_edge){c->outputs[0].node, c->outputs[0].port, c->outputs[0].part};
    }
    const lg_node_type *t = c->nodes[l->shown.node].type;
    lg_resource_kind k = t->outputs[l->shown.port].kind;
    if (l->shown.part) {
        const lg_kind_desc *kd = lg_kind_describe(k);
        if (kd->parts[l->shown.part - 1].type != LG_PART_IMAGE) {
            snprintf(err, errlen, "--show %s: the part '%s' of a %s is not an image", v->show,
                     kd->parts[l->shown.part - 1].name, kd->name);
            return -1;
        }
    } else if (k != LG_KIND_IMAGE && k != LG_KIND_PROBE && k != LG_KIND_ANY) {
        const lg_kind_desc *kd = lg_kind_describe(k);
        snprintf(err, errlen, "'%s.%s' gives %s: the viewer shows images and probes (name an "
                 "image with --show NODE.PORT)", l->g->nodes[l->shown.node].name,
                 t->outputs[l->shown.port].name, kd ? kd->name : "no image");
        return -1;
    }
    l->shown_name = lg_xasprintf("%s.%s", l->g->nodes[l->shown.node].name,
                                 l->shown.part ? lg_kind_describe(k)->parts[l->shown.part - 1].name
                                               : t->outputs[l->shown.port].name);
    return 0;
}

/* Is a node flagged display-referred at or upstream of node i (through kept nodes)? */
static bool upstream_display_referred(const lg_exec *ex, int32_t i, bool *seen)
{
    if (i < 0 || seen[i])
        return false;
    seen[i] = true;
    const lg_pnode *n = ex->nodes[i];
    if (!n || n->state == LG_STATE_CULLED)
        return false;
    if (n->state == LG_STATE_KEPT && (n->schema->flags & LG_NODE_DISPLAY_REFERRED))
        return true;
    for (uint32_t k = 0; k < n->schema->n_inputs; k++)
        if (upstream_display_referred(ex, n->c->inputs[k].node, seen))
            return true;
    return false;
}

/* The resource shown, and the node that may map it (its producer). */
static lg_resource *shown_resource(const loaded *l, lg_pnode **mapper)
{
    lg_resource *r = lg_edge_resource(l->ex, l->shown);
    if (mapper)
        *mapper = r ? (r->parent ? r->parent->producer : r->producer) : NULL;
    return r;
}

/* Makes the texture the display draws from: the shown image's own GL texture when it is
 * one the display can sample, else a CPU copy uploaded into the viewer's texture. */
static int shown_texture(viewer *v, uint32_t *tex, uint32_t *w, uint32_t *h, char *err,
                         size_t errlen)
{
    lg_pnode *mapper;
    lg_resource *r = shown_resource(&v->cur, &mapper);
    if (!r || !mapper) {
        snprintf(err, errlen, "the shown output '%s' has no resource", v->cur.shown_name);
        return -1;
    }
    const GladGLContext *gl = lg_gl_device_table(v->gl);
    if (r->kind == LG_KIND_IMAGE && !(r->image.flags & (LG_IMAGE_CUBE | LG_IMAGE_DEPTH_ONLY)) &&
        (r->image.format == LG_FORMAT_RGBA32F || r->image.format == LG_FORMAT_RGBA16F ||
         r->image.format == LG_FORMAT_RGBA8)) {
        uint32_t name = 0;
        if (lg_resource_map_gl(v->cur.ex, mapper, r, LG_READ, &name, NULL) != 0 || !name) {
            snprintf(err, errlen, "the shown output '%s' cannot be mapped on GL",
                     v->cur.shown_name);
            return -1;
        }
        *tex = name;
        *w = r->image.width;
        *h = r->image.height;
        return 0;
    }
    /* other formats and kinds: through the CPU, as the output files are written; only when
     * the producer ran (the texture keeps the last copy) */
    if (!v->cpu_tex || mapper->ran_this_frame) {
        float *px = NULL;
        lg_image img = {0, 0, NULL};
        if (r->kind == LG_KIND_PROBE) {
            if (lg_resource_probe_file(v->cur.ex, r, &img, err, errlen))
                return -1;
        } else {
            if (lg_resource_to_rgba32f(v->cur.ex, r, &px, err, errlen))
                return -1;
            img = (lg_image){r->image.width, r->image.height, px};
        }
        if (!v->cpu_tex)
            gl->GenTextures(1, &v->cpu_tex);
        gl->BindTexture(GL_TEXTURE_2D, v->cpu_tex);
        gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, (GLsizei)img.width, (GLsizei)img.height, 0,
                       GL_RGBA, GL_FLOAT, img.pixels);
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl->BindTexture(GL_TEXTURE_2D, 0);
        v->cpu_tex_w = img.width;
        v->cpu_tex_h = img.height;
        if (r->kind == LG_KIND_PROBE)
            lg_image_free(&img);
        free(px);
    }
    *tex = v->cpu_tex;
    *w = v->cpu_tex_w;
    *h = v->cpu_tex_h;
    return 0;
}

/* Auto exposure for an image that is not display-referred: the stops that put its
 * log-average luminance at 0.18 (Reinhard's key), from a CPU copy. */
static void auto_exposure(viewer *v)
{
    v->ev_auto_pending = false;
    if (v->cur.display_referred) {
        v->ev = 0;
        return;
    }
    lg_resource *r = shown_resource(&v->cur, NULL);
    float *px = NULL;
    char err[512];
    if (!r || r->kind != LG_KIND_IMAGE || lg_resource_to_rgba32f(v->cur.ex, r, &px, err, sizeof err))
        return;
    double sum = 0;
    size_t n = (size_t)r->image.width * r->image.height, used = 0;
    for (size_t i = 0; i < n; i++) {
        double y = 0.2126 * px[4 * i] + 0.7152 * px[4 * i + 1] + 0.0722 * px[4 * i + 2];
        if (isfinite(y) && y >= 0) {
            sum += log(1e-4 + y);
            used++;
        }
    }
    free(px);
    if (used) {
        double avg = exp(sum / (double)used);
        double ev = log2(0.18 / avg);
        v->ev = (float)(isfinite(ev) ? fmax(-20, fmin(20, ev)) : 0);
    }
}

static void watch_graph_files(viewer *v);
static void update_averages(viewer *v);

/* Parses, checks, plans and runs one frame of the graph with every override; on success it
 * becomes the current graph (adopting the unchanged nodes of the old), else nothing changes
 * and err says why. Returns 0 or -1 (bad graph: 2 when `initial`). */
static int try_load(viewer *v, bool initial, bool full, char *err, size_t errlen)
{
    free(v->last_error);
    v->last_error = NULL;
    loaded l;
    memset(&l, 0, sizeof l);
    lg_diags d = {0};
    l.g = lg_graph_parse_file(v->graph, &d);
    for (int i = 0; l.g && i < v->n_sets; i++)
        lg_graph_set(l.g, v->sets[i], &d);
    for (uint32_t i = 0; l.g && i < v->ov.n; i++)
        lg_graph_set(l.g, v->ov.items[i], &d);
    if (l.g && !d.errors) {
        lg_schema schema;
        lg_registry_schema(&v->reg, &schema);
        schema.max_pixels = lg_image_max_pixels();
        l.c = lg_graph_check(l.g, &schema, &d);
    }
    if (!l.g || d.errors || !l.c) {
        char *t = diags_text(&d);
        snprintf(err, errlen, "%s", t);
        free(t);
        lg_diags_free(&d);
        loaded_free(&l);
        return initial ? 2 : -1;
    }
    if (d.n) {
        lg_diags_print(&d, stderr); /* warnings */
    }
    lg_diags_free(&d);
    if (resolve_shown(v, &l, err, errlen)) {
        loaded_free(&l);
        return initial ? 2 : -1;
    }
    l.n_files = lg_graph_files(l.g, &l.files);

    lg_exec *ex = lg_xcalloc(1, sizeof *ex);
    ex->opts = v->opts;
    ex->opts.graph_path = v->graph;
    ex->reg = &v->reg;
    ex->graph = l.g;
    ex->checked = l.c;
    ex->prev = full ? NULL : v->cur.ex;
    ex->roots = &l.shown;
    ex->n_roots = 1;
    ex->keep_devices = true;
    ex->gl = v->gl;
    ex->gl_timer_query = v->timer_query;
    ex->cl = v->cl;
    ex->camera = v->cam_on ? &v->cam_out : NULL;
    ex->camera_gen = v->cam_gen;
    ex->guard = LG_GUARD_RECOVER;
    l.ex = ex;
    int rc = lg_plan(ex);
    if (rc == 0)
        rc = lg_exec_frame(ex, v->frame);
    if (rc == 0 && ex->failed)
        rc = -1;
    if (ex->cl && !v->cl)
        v->cl = ex->cl; /* made by this plan: the viewer keeps it for every later one */
    if (rc != 0) {
        snprintf(err, errlen, "%s", v->last_error ? v->last_error : "the graph failed to run");
        lg_plan_rollback(ex);
        loaded_free(&l);
        return initial ? 1 : -1;
    }
    lg_plan_commit(ex);
    loaded old = v->cur;
    v->cur = l;
    loaded_free(&old);
    bool *seen = lg_xcalloc(l.c->n_nodes + 1, sizeof *seen);
    v->cur.display_referred = upstream_display_referred(ex, l.shown.node, seen);
    free(seen);
    bool *offer = lg_xcalloc(l.c->n_nodes + 1, sizeof *offer);
    for (uint32_t i = 0; i < l.c->n_nodes; i++)
        offer[i] = ex->nodes[i] && ex->nodes[i]->state == LG_STATE_KEPT;
    lg_vparams_sync(v->vp, v->cur.g, v->cur.c, offer);
    free(offer);
    v->frame_failed = false;
    v->frame_done = true;
    update_averages(v);
    watch_graph_files(v);
    return 0;
}

/* A change that could not even be tried (a step past a range's end, no alternative, a
 * build that failed): counted as a failed change, the reason on screen. */
static void refuse_change(viewer *v, const char *why)
{
    v->changes++;
    v->changes_failed++;
    v->last_change_ok = false;
    set_status(v, true, "%s", why);
}

/* An attempt at a change (a parameter, a switch, a reload): its outcome is the status. */
static bool attempt_ex(viewer *v, const char *what, bool full)
{
    char err[8192];
    v->changes++;
    double t0 = lg_now();
    if (try_load(v, false, full, err, sizeof err) == 0) {
        v->last_change_ok = true;
        uint32_t kept = 0, made = 0;
        for (uint32_t i = 0; i < v->cur.ex->n_nodes; i++) {
            const lg_pnode *n = v->cur.ex->nodes[i];
            if (n && n->state == LG_STATE_KEPT)
                n->runs > 1 || (n->ran && !n->ran_this_frame) ? kept++ : made++;
        }
        set_status(v, false, "%s (%.0f ms: %u node%s made, %u kept)", what,
                   (lg_now() - t0) * 1e3, made, made == 1 ? "" : "s", kept);
        return true;
    }
    v->changes_failed++;
    v->last_change_ok = false;
    set_status(v, true, "%s: rejected, keeping the last good frame:\n%s", what, err);
    return false;
}

static bool attempt(viewer *v, const char *what)
{
    return attempt_ex(v, what, false);
}

/* ---- the camera -------------------------------------------------------------------- */

/* The scene the renderers of the shown image read: the first kept node upstream of the
 * shown one (itself included) that reads a scene. */
static const lg_scene *graph_scene(viewer *v, const char **scene_node)
{
    const loaded *l = &v->cur;
    const lg_checked *c = l->c;
    for (uint32_t t = c->n_nodes; t-- > 0;) {
        const lg_pnode *n = l->ex->nodes[c->topo[t]];
        if (!n || n->state != LG_STATE_KEPT)
            continue;
        for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
            lg_edge e = n->c->inputs[k];
            lg_resource *r = e.node >= 0 ? lg_edge_resource(l->ex, e) : NULL;
            if (r && r->kind == LG_KIND_SCENE && r->payload && !r->neutral) {
                if (scene_node)
                    *scene_node = l->g->nodes[e.node].name;
                return r->payload;
            }
        }
    }
    return NULL;
}

static void camera_changed(viewer *v)
{
    if (v->cam_on)
        lg_vcam_fit_clip(&v->vcam, v->cam_bmin, v->cam_bmax);
    lg_vcam_to_camera(&v->vcam, &v->cam_out);
    v->cam_gen++;
    if (v->cur.ex) {
        v->cur.ex->camera = v->cam_on ? &v->cam_out : NULL;
        v->cur.ex->camera_gen = v->cam_gen;
    }
}

/* The viewer's camera, taking over from the graph's on first use. false: no scene. */
static bool camera_take(viewer *v)
{
    if (v->cam_on)
        return true;
    const char *node = NULL;
    const lg_scene *s = graph_scene(v, &node);
    if (!s) {
        set_status(v, true, "the shown image has no scene upstream: no camera to move");
        return false;
    }
    lg_camera cam;
    memset(&cam, 0, sizeof cam);
    if (s->n_cameras && s->cameras)
        cam = s->cameras[s->camera < s->n_cameras ? s->camera : 0];
    lg_vcam_init(&v->vcam, &cam, s->bounds_min, s->bounds_max);
    memcpy(v->cam_bmin, s->bounds_min, sizeof v->cam_bmin);
    memcpy(v->cam_bmax, s->bounds_max, sizeof v->cam_bmax);
    free(v->cam_scene_ref);
    v->cam_scene_ref = lg_xstrdup(node ? node : "scene");
    v->cam_on = true;
    return true;
}

static void camera_reset(viewer *v)
{
    v->cam_on = false;
    camera_changed(v);
    set_status(v, false, "camera: the graph's");
}

static void camera_print(viewer *v)
{
    if (!camera_take(v))
        return;
    char *t = lg_vcam_node_text(&v->vcam, "cam", v->cam_scene_ref);
    printf("%s\n", t);
    fflush(stdout);
    free(t);
    set_status(v, false, "camera printed on stdout as a camera node");
}

/* ---- live parameters ----------------------------------------------------------------- */

/* The selection on stdout too: a terminal beside the window keeps the history. */
static void print_selection(viewer *v)
{
    lg_str d = {0};
    lg_vparams_describe(v->vp, v->cur.c, &d);
    printf("lightgraph view: select: %s\n", d.s ? d.s : "(nothing to select)");
    fflush(stdout);
    lg_str_free(&d);
}

static void apply_assignment(viewer *v, const char *a)
{
    lg_overrides_set(&v->ov, a);
    if (!attempt(v, a))
        lg_overrides_remove_last(&v->ov);
}

static void step_selected(viewer *v, int dir)
{
    double scale = (v->mods & GLFW_MOD_SHIFT) ? 10 : (v->mods & GLFW_MOD_CONTROL) ? 0.1 : 1;
    char err[512];
    char *a = lg_vparams_step(v->vp, v->cur.g, v->cur.c, dir, scale, err, sizeof err);
    if (!a) {
        refuse_change(v, err);
        return;
    }
    apply_assignment(v, a);
    free(a);
}

static void switch_method(viewer *v, int dir)
{
    char **as = NULL;
    uint32_t n = 0;
    int32_t from = -1, to = -1, new_shown = -1;
    char err[1024];
    if (!lg_vparams_switch_method(v->cur.g, v->cur.c, v->cur.shown.node, dir, &as, &n, &from,
                                  &to, &new_shown, err, sizeof err)) {
        refuse_change(v, err);
        return;
    }
    for (uint32_t i = 0; i < n; i++)
        lg_overrides_set(&v->ov, as[i]);
    char *old_show = v->show ? lg_xstrdup(v->show) : NULL;
    if (new_shown >= 0) {
        /* the output of the same name (alternatives share it) */
        const lg_node_type *tx = v->cur.c->nodes[v->cur.shown.node].type;
        free(v->show);
        v->show = lg_xasprintf("%s.%s", v->cur.g->nodes[new_shown].name,
                               tx->outputs[v->cur.shown.port].name);
    }
    char *what = lg_xasprintf("method: %s -> %s (%s)", v->cur.g->nodes[from].name,
                              v->cur.g->nodes[to].name, v->cur.c->nodes[to].type->name);
    if (!attempt(v, what)) {
        /* undo exactly the sets made here */
        for (uint32_t i = 0; i < n && v->ov.n > 0; i++)
            lg_overrides_remove_last(&v->ov);
        free(v->show);
        v->show = old_show;
        old_show = NULL;
    }
    free(old_show);
    free(what);
    for (uint32_t i = 0; i < n; i++)
        free(as[i]);
    free(as);
}

static void print_overrides(viewer *v)
{
    char *a = lg_overrides_args(&v->ov);
    printf("%s\n", a && a[0] ? a : "(no overrides)");
    fflush(stdout);
    free(a);
    set_status(v, false, "overrides printed on stdout as --set arguments");
}

/* ---- screenshots ------------------------------------------------------------------------ */

/* Writes the shown image: .png as displayed (exposure, sRGB), .exr linear (float). */
static int screenshot(viewer *v, const char *path, char *err, size_t errlen)
{
    lg_resource *r = shown_resource(&v->cur, NULL);
    if (!r) {
        snprintf(err, errlen, "nothing is shown");
        return -1;
    }
    lg_image img = {0, 0, NULL};
    float *px = NULL;
    if (r->kind == LG_KIND_PROBE) {
        if (lg_resource_probe_file(v->cur.ex, r, &img, err, errlen))
            return -1;
    } else {
        if (lg_resource_to_rgba32f(v->cur.ex, r, &px, err, errlen))
            return -1;
        img = (lg_image){r->image.width, r->image.height, px};
    }
    lg_file_format fmt = lg_image_format_from_path(path);
    if (fmt == LG_FILE_PNG) {
        float k = exp2f(v->ev);
        size_t n = (size_t)img.width * img.height * 4;
        for (size_t i = 0; i < n; i++)
            if (i % 4 != 3)
                img.pixels[i] *= k;
    }
    lg_image_write_opts wo;
    memset(&wo, 0, sizeof wo);
    wo.exr_pixel = LG_EXR_FLOAT;
    lg_outputs *o = lg_outputs_new();
    int rc = lg_outputs_add(o, path, LG_OUTPUT_IMAGE, err, errlen);
    if (rc == 0)
        rc = lg_outputs_write_image(o, path, &img, &wo, err, errlen);
    if (rc == 0)
        rc = lg_outputs_commit(o, err, errlen);
    lg_outputs_free(&o);
    if (r->kind == LG_KIND_PROBE)
        lg_image_free(&img);
    free(px);
    return rc;
}

/* The window's pixels as shown, read back after drawing and before the swap. */
static int window_screenshot(viewer *v, const char *path, char *err, size_t errlen)
{
    const GladGLContext *gl = lg_gl_device_table(v->gl);
    int w, h;
    glfwGetFramebufferSize(v->win, &w, &h);
    unsigned char *rgba = lg_xmalloc((size_t)w * h * 4);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    gl->ReadBuffer(GL_BACK);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl->ReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    lg_image img = {(uint32_t)w, (uint32_t)h, lg_xmalloc((size_t)w * h * 4 * sizeof(float))};
    /* bottom-up to top-down; the PNG writer encodes linear values: decode what is shown */
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w * 4; x++) {
            unsigned char b = rgba[(size_t)(h - 1 - y) * w * 4 + x];
            img.pixels[(size_t)y * w * 4 + x] = x % 4 == 3 ? 1.0f : lg_srgb_decode(b / 255.0f);
        }
    free(rgba);
    lg_image_write_opts wo;
    memset(&wo, 0, sizeof wo);
    lg_outputs *o = lg_outputs_new();
    int rc = lg_outputs_add(o, path, LG_OUTPUT_IMAGE, err, errlen);
    if (rc == 0)
        rc = lg_outputs_write_image(o, path, &img, &wo, err, errlen);
    if (rc == 0)
        rc = lg_outputs_commit(o, err, errlen);
    lg_outputs_free(&o);
    free(img.pixels);
    return rc;
}

/* The screenshot key: PNG and EXR next to the graph, named with the time. */
static void screenshot_key(viewer *v)
{
    char *dir = lg_xstrdup(v->graph);
    char *slash = strrchr(dir, '/');
    char *stem = lg_xstrdup(slash ? slash + 1 : dir);
    char *dotp = strrchr(stem, '.');
    if (dotp && dotp != stem)
        *dotp = 0;
    if (slash)
        *slash = 0;
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    struct tm tm;
    localtime_r(&ts.tv_sec, &tm);
    char stamp[64];
    strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    char err[1024];
    for (int k = 0; k < 2; k++) {
        char *path = lg_xasprintf("%s/%s-%s-%03ld.%s", slash ? (dir[0] ? dir : "/") : ".",
                                  stem, stamp, ts.tv_nsec / 1000000, k ? "exr" : "png");
        if (screenshot(v, path, err, sizeof err))
            set_status(v, true, "screenshot: %s", err);
        else
            set_status(v, false, "screenshot: %s", path);
        free(path);
    }
    free(stem);
    free(dir);
}

/* ---- reloads ------------------------------------------------------------------------------ */

static void watch_graph_files(viewer *v)
{
    if (!v->watch)
        return;
    char err[1024];
    if (lg_watch_files(v->watch, LG_WATCH_GRAPH, (const char *const *)v->cur.files,
                       v->cur.n_files, err, sizeof err))
        lg_hlog(LG_HWARN, "cannot watch the graph's files: %s", err);
}

static void start_watching(viewer *v)
{
    char err[1024];
    if (lg_watch_open(&v->watch, err, sizeof err)) {
        lg_hlog(LG_HWARN, "no hot reload: %s", err);
        return;
    }
    watch_graph_files(v);
    static const char *const so[] = {".so"};
    for (uint32_t i = 0; i < v->reg.n_dirs; i++)
        if (lg_watch_tree(v->watch, LG_WATCH_PLUGIN, v->reg.dirs[i], so, 1, false, err,
                          sizeof err))
            lg_hlog(LG_HDEBUG, "not watching plugin directory %s: %s", v->reg.dirs[i], err);
    /* shaders: the development build's source tree, or LIGHTGRAPH_SHADER_DIR (an out-of-tree
     * plugin's shaders, rebuilt by LIGHTGRAPH_REBUILD) */
    v->dev_build = lg_rebuild_dev_build_dir();
    const char *env = getenv("LIGHTGRAPH_SHADER_DIR");
    if (env && *env)
        v->dev_shaders = lg_path_absolute(env);
    else
        v->dev_shaders = v->dev_build ? lg_rebuild_dev_shader_dir() : NULL;
    const char *cmd = getenv("LIGHTGRAPH_REBUILD");
    v->can_rebuild = v->dev_build || (cmd && *cmd);
    if (v->dev_shaders && v->can_rebuild) {
        static const char *const sh[] = {".glsl", ".comp", ".vert", ".frag", ".geom", ".cl"};
        if (lg_watch_tree(v->watch, LG_WATCH_SHADER, v->dev_shaders, sh, 6, true, err,
                          sizeof err))
            lg_hlog(LG_HWARN, "not watching the shaders: %s", err);
        else
            lg_hlog(LG_HINFO, "watching the shaders in %s (a change runs %s)", v->dev_shaders,
                    cmd && *cmd ? cmd : "ninja");
    }
}

static bool is_plugin_file(const char *path)
{
    const char *b = strrchr(path, '/');
    b = b ? b + 1 : path;
    size_t n = strlen(b);
    return strncmp(b, "lg_", 3) == 0 && n > 3 && strcmp(b + n - 3, ".so") == 0;
}

/* Reloads the changed plugins (all or none) and replans; a failure at any step puts
 * every replaced entry back. */
static void reload_plugins(viewer *v)
{
    uint32_t n = v->n_pending_plugins;
    char **paths = v->pending_plugins;
    v->pending_plugins = NULL;
    v->n_pending_plugins = 0;
    lg_plugin **fresh = lg_xcalloc(n + 1, sizeof *fresh), **old = lg_xcalloc(n + 1, sizeof *old);
    uint32_t done = 0;
    lg_str names = {0};
    char err[2048] = "";
    bool ok = true;
    for (uint32_t i = 0; i < n && ok; i++) {
        if (lg_registry_rescan(&v->reg, paths[i], &fresh[done], &old[done], err, sizeof err)) {
            ok = false;
            break;
        }
        lg_registry_replace(&v->reg, old[done], fresh[done]);
        lg_str_addf(&names, "%s%s", names.len ? ", " : "", fresh[done]->name);
        done++;
    }
    if (!ok) {
        v->changes++;
        v->changes_failed++;
        v->last_change_ok = false;
    } else {
        /* nodes of a reloaded plugin are made again with the parameters they had (the
         * graph's and the overrides); the others are adopted as they are */
        char *what = lg_xasprintf("plugin%s %s reloaded", done == 1 ? "" : "s",
                                  names.s ? names.s : "");
        ok = attempt(v, what);
        free(what);
        if (!ok)
            snprintf(err, sizeof err, "%s", v->status ? v->status : "the reload failed");
    }
    if (!ok) {
        for (uint32_t i = done; i-- > 0;)
            lg_registry_replace(&v->reg, fresh[i], old[i]);
        set_status(v, true, "plugin reload failed, rolled back to the previous version:\n%s",
                   err);
    }
    lg_str_free(&names);
    free(fresh);
    free(old);
    for (uint32_t i = 0; i < n; i++)
        free(paths[i]);
    free(paths);
}

static void poll_reloads(viewer *v)
{
    if (!v->watch)
        return;
    lg_watch_change *ch = NULL;
    char err[1024];
    int n = lg_watch_poll(v->watch, lg_now(), 0.15, &ch, err, sizeof err);
    if (n < 0) {
        lg_hlog(LG_HWARN, "watching files: %s", err);
        n = 0;
    }
    bool shaders = false;
    for (int i = 0; i < n; i++) {
        if (ch[i].tag == LG_WATCH_GRAPH) {
            v->pending_graph = true;
        } else if (ch[i].tag == LG_WATCH_SHADER) {
            shaders = true;
        } else if (ch[i].tag == LG_WATCH_PLUGIN && is_plugin_file(ch[i].path) &&
                   access(ch[i].path, R_OK) == 0) {
            bool dup = false;
            for (uint32_t k = 0; k < v->n_pending_plugins; k++)
                dup |= strcmp(v->pending_plugins[k], ch[i].path) == 0;
            if (!dup) {
                v->pending_plugins = lg_xrealloc(v->pending_plugins,
                                                 (v->n_pending_plugins + 1) * sizeof(char *));
                v->pending_plugins[v->n_pending_plugins++] = lg_xstrdup(ch[i].path);
            }
        }
    }
    lg_watch_changes_free(ch, n);
    if (shaders && v->can_rebuild) {
        if (v->rebuild) {
            v->rebuild_again = true;
        } else if (lg_rebuild_start(&v->rebuild, v->dev_build, err, sizeof err)) {
            set_status(v, true, "shaders changed, but the rebuild cannot start: %s", err);
        } else {
            set_status(v, false, "shaders changed: rebuilding (%s)",
                       getenv("LIGHTGRAPH_REBUILD") ? getenv("LIGHTGRAPH_REBUILD") : "ninja");
        }
    }
    if (v->rebuild) {
        int status = 0;
        const char *log = NULL;
        int r = lg_rebuild_poll(v->rebuild, &status, &log);
        if (r == 0)
            return; /* plugins relinked by the build are reloaded together once it ends */
        if (r < 0) {
            refuse_change(v, "the rebuild's process could not be followed; the plugins are "
                             "as they were");
        } else if (status != 0) {
            v->changes++;
            v->changes_failed++;
            v->last_change_ok = false;
            size_t len = log ? strlen(log) : 0;
            const char *tail = len > 2000 ? log + len - 2000 : log ? log : "";
            set_status(v, true, "the rebuild failed (status %d); the plugins are as they "
                       "were:\n%s", status, tail);
        }
        lg_rebuild_free(&v->rebuild);
        if (v->rebuild_again) {
            v->rebuild_again = false;
            if (lg_rebuild_start(&v->rebuild, v->dev_build, err, sizeof err) == 0)
                return;
        }
        /* the relinked .so files settle a moment after the build: the next polls
         * collect them */
    }
    if (v->n_pending_plugins)
        reload_plugins(v);
    else if (v->pending_graph) {
        v->pending_graph = false;
        attempt(v, "graph reloaded");
    }
}

/* ---- input ---------------------------------------------------------------------------- */

static void on_key(viewer *v, int key, int mods, int action)
{
    if (key < 0 || key > GLFW_KEY_LAST)
        return;
    v->mods = mods;
    if (action == GLFW_RELEASE) {
        v->held[key] = false;
        return;
    }
    if (action == GLFW_PRESS)
        v->held[key] = true;
    bool shift = mods & GLFW_MOD_SHIFT;
    switch (key) {
    case GLFW_KEY_ESCAPE:
        v->quit = true;
        break;
    case GLFW_KEY_TAB:
        lg_vparams_next_node(v->vp, shift ? -1 : 1);
        print_selection(v);
        break;
    case GLFW_KEY_UP:
        lg_vparams_next_entry(v->vp, -1);
        print_selection(v);
        break;
    case GLFW_KEY_DOWN:
        lg_vparams_next_entry(v->vp, 1);
        print_selection(v);
        break;
    case GLFW_KEY_HOME:
        lg_vparams_first_entry(v->vp);
        print_selection(v);
        break;
    case GLFW_KEY_LEFT:
        step_selected(v, -1);
        break;
    case GLFW_KEY_RIGHT:
        step_selected(v, 1);
        break;
    case GLFW_KEY_M:
        switch_method(v, shift ? -1 : 1);
        break;
    case GLFW_KEY_O:
        print_overrides(v);
        break;
    case GLFW_KEY_C:
        camera_print(v);
        break;
    case GLFW_KEY_R:
        camera_reset(v);
        break;
    case GLFW_KEY_F:
        if (camera_take(v)) {
            v->vcam.mode = v->vcam.mode == LG_VCAM_FLY ? LG_VCAM_ORBIT : LG_VCAM_FLY;
            set_status(v, false, "camera: %s", v->vcam.mode == LG_VCAM_FLY
                                                   ? "fly (WASD, Q/E down/up, drag to look)"
                                                   : "orbit (drag, right-drag pans, wheel)");
        }
        break;
    case GLFW_KEY_H:
    case GLFW_KEY_F1:
        v->overlay = !v->overlay;
        break;
    case GLFW_KEY_LEFT_BRACKET:
        v->ev -= shift ? 2.0f : 0.5f;
        break;
    case GLFW_KEY_RIGHT_BRACKET:
        v->ev += shift ? 2.0f : 0.5f;
        break;
    case GLFW_KEY_BACKSLASH:
        auto_exposure(v);
        break;
    case GLFW_KEY_F5:
        /* everything made again: also the files the graph's nodes read (an edited mesh) */
        attempt_ex(v, "everything reloaded (F5)", true);
        break;
    case GLFW_KEY_F12:
    case GLFW_KEY_P:
        screenshot_key(v);
        break;
    default:
        break;
    }
}

static void on_button(viewer *v, int button, int action, int mods)
{
    v->mods = mods;
    if (button >= 0 && button < 8)
        v->buttons[button] = action == GLFW_PRESS;
}

static void on_cursor(viewer *v, double x, double y)
{
    double dx = x - v->mx, dy = y - v->my;
    v->mx = x;
    v->my = y;
    bool left = v->buttons[GLFW_MOUSE_BUTTON_LEFT], right = v->buttons[GLFW_MOUSE_BUTTON_RIGHT],
         middle = v->buttons[GLFW_MOUSE_BUTTON_MIDDLE];
    if (!(left || right || middle) || (dx == 0 && dy == 0))
        return;
    if (!camera_take(v))
        return;
    int h = (int)v->opts.height;
    if (v->vcam.mode == LG_VCAM_FLY)
        lg_vcam_look(&v->vcam, dx, dy, h);
    else if (right || middle || (v->mods & GLFW_MOD_SHIFT))
        lg_vcam_pan(&v->vcam, dx, dy, h);
    else
        lg_vcam_orbit(&v->vcam, dx, dy, h);
    camera_changed(v);
}

static void on_scroll(viewer *v, double d)
{
    if (d == 0 || !camera_take(v))
        return;
    if (v->vcam.mode == LG_VCAM_FLY) {
        float f[3] = {0, 0, (float)d};
        lg_vcam_move(&v->vcam, f, 0.1, 1.0);
    } else {
        lg_vcam_zoom(&v->vcam, d);
    }
    camera_changed(v);
}

/* Fly: the held movement keys move the camera by this frame's time. */
static void fly_step(viewer *v, double dt)
{
    if (!v->cam_on || v->vcam.mode != LG_VCAM_FLY)
        return;
    float m[3] = {(float)(v->held[GLFW_KEY_D] - v->held[GLFW_KEY_A]),
                  (float)(v->held[GLFW_KEY_E] - v->held[GLFW_KEY_Q]),
                  (float)(v->held[GLFW_KEY_W] - v->held[GLFW_KEY_S])};
    if (m[0] == 0 && m[1] == 0 && m[2] == 0)
        return;
    bool fast = v->held[GLFW_KEY_LEFT_SHIFT] || v->held[GLFW_KEY_RIGHT_SHIFT];
    lg_vcam_move(&v->vcam, m, dt, fast ? 2.0 : 0.5);
    camera_changed(v);
}

static void cb_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)w;
    (void)scancode;
    if (g_viewer && !g_viewer->scripted)
        on_key(g_viewer, key, mods, action);
}

static void cb_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)w;
    if (g_viewer && !g_viewer->scripted)
        on_button(g_viewer, button, action, mods);
}

static void cb_cursor(GLFWwindow *w, double x, double y)
{
    (void)w;
    if (g_viewer && !g_viewer->scripted)
        on_cursor(g_viewer, x, y);
}

static void cb_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)w;
    (void)dx;
    if (g_viewer && !g_viewer->scripted)
        on_scroll(g_viewer, dy);
}

/* ---- the script ------------------------------------------------------------------------ */

static void script_fail(viewer *v, const lg_sevent *e, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void script_fail(viewer *v, const lg_sevent *e, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lightgraph view: %s:%u: ", v->script.path, e->line);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    v->expect_failed = true;
    v->exit_status = 1;
}

/* Runs script events until one has to wait for frames; called once per frame. */
static void script_step(viewer *v)
{
    if (v->anim.active) {
        pointer_anim *a = &v->anim;
        a->step++;
        double x = a->x0 + a->dx * a->step / a->steps, y = a->y0 + a->dy * a->step / a->steps;
        on_cursor(v, x, y);
        if (a->step >= a->steps) {
            on_button(v, a->button, GLFW_RELEASE, a->mods);
            a->active = false;
        }
        return;
    }
    if (v->hold_key >= 0) {
        if (v->frame < v->hold_until)
            return;
        on_key(v, v->hold_key, 0, GLFW_RELEASE);
        v->hold_key = -1;
    }
    if (v->frame < v->wait_until)
        return;
    if (v->wait_reload) {
        if (v->changes == v->wait_reload_from && lg_now() < v->wait_deadline)
            return;
        if (v->changes == v->wait_reload_from) {
            script_fail(v, &v->script.ev[v->pc - 1], "wait_reload: no reload within the time "
                        "given");
            v->quit = true;
            return;
        }
        v->wait_reload = false;
    }
    while (v->pc < v->script.n && !v->quit) {
        const lg_sevent *e = &v->script.ev[v->pc++];
        char err[2048];
        switch (e->kind) {
        case LG_SEV_WAIT_FRAMES:
            v->wait_until = v->frame + (uint32_t)e->a;
            return;
        case LG_SEV_KEY:
            on_key(v, e->key, e->mods, GLFW_PRESS);
            on_key(v, e->key, e->mods, GLFW_RELEASE);
            v->wait_until = v->frame + 1;
            return;
        case LG_SEV_HOLD:
            on_key(v, e->key, e->mods, GLFW_PRESS);
            v->hold_key = e->key;
            v->hold_until = v->frame + (uint32_t)e->b;
            return;
        case LG_SEV_DRAG: {
            int w, h;
            glfwGetWindowSize(v->win, &w, &h);
            pointer_anim *a = &v->anim;
            a->active = true;
            a->button = e->button;
            a->mods = e->mods;
            a->x0 = e->has_from ? e->from_x : w / 2.0;
            a->y0 = e->has_from ? e->from_y : h / 2.0;
            a->dx = e->a;
            a->dy = e->b;
            a->step = 0;
            a->steps = 4;
            v->mx = a->x0;
            v->my = a->y0;
            on_button(v, a->button, GLFW_PRESS, a->mods);
            return;
        }
        case LG_SEV_SCROLL:
            on_scroll(v, e->a);
            v->wait_until = v->frame + 1;
            return;
        case LG_SEV_SCREENSHOT:
            if (screenshot(v, e->text, err, sizeof err))
                script_fail(v, e, "screenshot %s: %s", e->text, err);
            else
                printf("lightgraph view: wrote %s\n", e->text);
            break;
        case LG_SEV_SCREENSHOT_WINDOW:
            free(v->window_shot);
            v->window_shot = lg_xstrdup(e->text);
            v->window_shot_ev = e;
            v->wait_until = v->frame + 1;
            return;
        case LG_SEV_SET:
            apply_assignment(v, e->text);
            v->wait_until = v->frame + 1;
            return;
        case LG_SEV_WAIT_RELOAD:
            v->wait_reload = true;
            v->wait_reload_from = v->changes;
            v->wait_deadline = lg_now() + (e->a > 0 ? e->a : 60);
            return;
        case LG_SEV_EXPECT_OK:
            if (!v->last_change_ok)
                script_fail(v, e, "expect_ok: the last change failed: %s",
                            v->status ? v->status : "?");
            break;
        case LG_SEV_EXPECT_ERROR:
            if (v->last_change_ok)
                script_fail(v, e, "expect_error: the last change succeeded (%s)",
                            v->status ? v->status : "?");
            else if (e->text && e->text[0] && (!v->status || !strstr(v->status, e->text)))
                script_fail(v, e, "expect_error: the error does not mention '%s': %s", e->text,
                            v->status ? v->status : "?");
            break;
        case LG_SEV_SHELL: {
            char *cmd = lg_xasprintf("cd '%s' && %s", v->script.dir, e->text);
            fflush(NULL);
            int st = system(cmd);
            free(cmd);
            if (st != 0) {
                script_fail(v, e, "shell: '%s' exited with status %d", e->text,
                            WIFEXITED(st) ? WEXITSTATUS(st) : -1);
                v->quit = true;
                return;
            }
            break;
        }
        case LG_SEV_SLEEP:
            usleep((useconds_t)(e->a * 1e6));
            break;
        case LG_SEV_QUIT:
            v->quit = true;
            return;
        }
    }
    if (v->pc >= v->script.n && !v->quit) {
        /* a script that ends without quit: the window stays for the user */
    }
}

/* ---- the overlay ----------------------------------------------------------------------- */

static void overlay_text(viewer *v, lg_str *s)
{
    const loaded *l = &v->cur;
    lg_str_addf(s, "%s  %ux%u  shown: %s  %.1f fps  frame %u\n", v->graph, v->opts.width,
                v->opts.height, l->shown_name ? l->shown_name : "-", v->fps, v->frame);
    int wn = 4, wt = 4;
    for (uint32_t i = 0; i < l->c->n_nodes; i++) {
        int a = (int)strlen(l->g->nodes[i].name), b = (int)strlen(l->c->nodes[i].type->name);
        wn = a > wn ? a : wn;
        wt = b > wt ? b : wt;
    }
    if (wn > 18)
        wn = 18;
    if (wt > 20)
        wt = 20;
    lg_str_addf(s, "%-*.*s %-*.*s %-9s %9s %9s %9s %9s\n", wn, wn, "node", wt, wt, "type",
                "runs", "last ms", "avg ms", "gpu last", "gpu avg");
    lg_str culled = {0}, gated = {0};
    for (uint32_t t = 0; t < l->c->n_nodes; t++) {
        const lg_pnode *n = l->ex->nodes[l->c->topo[t]];
        if (!n)
            continue;
        if (n->state == LG_STATE_CULLED) {
            lg_str_addf(&culled, "%s%s", culled.len ? ", " : "", n->pub.name);
            continue;
        }
        if (n->state == LG_STATE_GATED) {
            lg_str_addf(&gated, "%s%s (%s)", gated.len ? ", " : "", n->pub.name,
                        n->reason ? n->reason : "");
            continue;
        }
        /* GL timer queries read 0 for llvmpipe's compute work: "n/a", as --profile says */
        char gpu[32] = "-", gpu_avg[32] = "-";
        if (n->device == LG_DEVICE_GL || n->device == LG_DEVICE_CL) {
            bool na = n->gpu_unmeasured && n->last_gpu_ms == 0;
            snprintf(gpu, sizeof gpu, na ? "n/a" : "%.2f", n->last_gpu_ms);
            snprintf(gpu_avg, sizeof gpu_avg, na ? "n/a" : "%.2f", n->avg_gpu_ms);
        }
        lg_str_addf(s, "%-*.*s %-*.*s %-9s %9.2f %9.2f %9s %9s%s\n", wn, wn, n->pub.name, wt,
                    wt, n->schema->name, n->per_frame ? "per-frame" : "once", n->last_cpu_ms,
                    n->avg_cpu_ms, gpu, gpu_avg,
                    n->ran_this_frame ? "" : (n->per_frame ? "" : "  (cached)"));
    }
    if (culled.len)
        lg_str_addf(s, "culled: %s\n", culled.s);
    if (gated.len)
        lg_str_addf(s, "gated: %s\n", gated.s);
    lg_str_free(&culled);
    lg_str_free(&gated);
    lg_str d = {0};
    lg_vparams_describe(v->vp, l->c, &d);
    lg_str_addf(s, "select: %s   [Tab node, Up/Down entry, Left/Right value, M method]\n",
                d.s ? d.s : "-");
    lg_str_free(&d);
    lg_str_addf(s, "camera: %s   exposure %+.1f EV%s\n",
                !v->cam_on ? "the graph's" : v->vcam.mode == LG_VCAM_FLY ? "fly" : "orbit",
                (double)v->ev, l->display_referred ? " (display-referred)" : "");
}

static void update_title(viewer *v)
{
    char title[512];
    const char *st = v->status ? v->status : "";
    const char *nl = strchr(st, '\n');
    snprintf(title, sizeof title, "lightgraph view: %s | %.1f fps | %s%.*s", v->graph, v->fps,
             v->status_error ? "error: " : "", (int)(nl ? nl - st : (long)strlen(st)), st);
    glfwSetWindowTitle(v->win, title);
}

/* ---- the loop ---------------------------------------------------------------------------- */

static void present(viewer *v)
{
    const GladGLContext *gl = lg_gl_device_table(v->gl);
    int fw, fh;
    glfwGetFramebufferSize(v->win, &fw, &fh);
    uint32_t tex = 0, w = 0, h = 0;
    char err[1024];
    lg_gl_state_reset(gl);
    if (shown_texture(v, &tex, &w, &h, err, sizeof err) == 0) {
        if (lg_vdisplay_draw_image(v->disp, 0, fw, fh, tex, w, h, exp2f(v->ev)))
            lg_hlog(LG_HWARN, "drawing the image failed");
    } else {
        set_status(v, true, "%s", err);
        v->frame_failed = true;
    }
    if (v->overlay) {
        lg_str s = {0};
        overlay_text(v, &s);
        static const float white[3] = {0.92f, 0.92f, 0.92f}, red[3] = {1.0f, 0.45f, 0.4f},
                           green[3] = {0.6f, 1.0f, 0.6f};
        int cw, ch;
        lg_vdisplay_cell(v->disp, &cw, &ch);
        lg_vdisplay_draw_text(v->disp, 0, fw, fh, 4, 4, s.s ? s.s : "", white, 1);
        int lines = 0;
        for (const char *p = s.s; p && *p; p++)
            lines += *p == '\n';
        if (v->status)
            lg_vdisplay_draw_text(v->disp, 0, fw, fh, 4, 8 + (lines + 1) * ch, v->status,
                                  v->status_error ? red : green, 1);
        lg_str_free(&s);
    }
    if (v->window_shot) {
        /* taken here, after drawing: a failure fails the script as screenshot's does (it
         * used to be printed while the script went on to exit 0) */
        if (window_screenshot(v, v->window_shot, err, sizeof err))
            script_fail(v, v->window_shot_ev, "screenshot_window %s: %s", v->window_shot, err);
        else
            printf("lightgraph view: wrote %s\n", v->window_shot);
        free(v->window_shot);
        v->window_shot = NULL;
    }
    lg_gl_state_reset(gl);
    glfwSwapBuffers(v->win);
}

/* The moving averages of the nodes that ran in this frame. */
static void update_averages(viewer *v)
{
    for (uint32_t i = 0; i < v->cur.ex->n_nodes; i++) {
        lg_pnode *n = v->cur.ex->nodes[i];
        if (n && n->ran_this_frame) {
            n->avg_cpu_ms = n->runs <= 1 ? n->last_cpu_ms
                                         : 0.9 * n->avg_cpu_ms + 0.1 * n->last_cpu_ms;
            n->avg_gpu_ms = n->runs <= 1 ? n->last_gpu_ms
                                         : 0.9 * n->avg_gpu_ms + 0.1 * n->last_gpu_ms;
        }
    }
}

static void run_frame(viewer *v)
{
    if (v->frame_failed)
        return;
    free(v->last_error);
    v->last_error = NULL;
    if (lg_exec_frame(v->cur.ex, v->frame) != 0 || v->cur.ex->failed) {
        v->frame_failed = true;
        set_status(v, true, "a frame failed (fix the graph or the plugin; it is reloaded on "
                   "save):\n%s", v->last_error ? v->last_error : "?");
        return;
    }
    update_averages(v);
}

static int usage(const char *fmt, const char *what)
{
    if (fmt)
        fprintf(stderr, fmt, what);
    fprintf(stderr,
            "usage: lightgraph view GRAPH [--set NODE.PARAM=VALUE]... [--show NODE.PORT]\n"
            "                 [--size WxH] [--script FILE] [--dt SECONDS] [-v|-q]\n"
            "(keys and the script language: docs/viewer.md)\n");
    return 2;
}

static const char *glfw_error_text;
static char glfw_error_buf[512];
static void cb_glfw_error(int code, const char *desc)
{
    snprintf(glfw_error_buf, sizeof glfw_error_buf, "%s (GLFW error 0x%x)", desc ? desc : "?",
             (unsigned)code);
    glfw_error_text = glfw_error_buf;
}

/* Every shared object mapped now stays mapped until the process ends (RTLD_NODELETE): the
 * GL driver the window's context loaded (libGL, the DRI driver, llvmpipe) keeps threads and
 * exit handlers, as OSMesa does (gl_osmesa.c), and unloading it at glfwTerminate would also
 * hide its allocations from the leak checker behind "unknown module". */
static int pin_object(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size;
    (void)data;
    if (info->dlpi_name && info->dlpi_name[0]) {
        void *h = dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
        if (h)
            dlclose(h);
    }
    return 0;
}

static GLADapiproc glfw_load(void *state, const char *name)
{
    (void)state;
    return (GLADapiproc)glfwGetProcAddress(name);
}

int lg_cmd_view(int argc, char **argv)
{
    viewer *v = lg_xcalloc(1, sizeof *v);
    v->opts.width = 640;
    v->opts.height = 360;
    v->opts.frames = 1;
    v->opts.dt = 1.0 / 60.0;
    v->overlay = true;
    v->hold_key = -1;
    v->sets = lg_xcalloc((size_t)argc + 1, sizeof *v->sets);
    int rc = 0;
    for (int i = 1; i < argc && rc == 0; i++) {
        const char *s = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(s, "--set") == 0 && val) {
            v->sets[v->n_sets++] = val;
            i++;
        } else if (strncmp(s, "--set=", 6) == 0) {
            v->sets[v->n_sets++] = s + 6;
        } else if (strcmp(s, "--show") == 0 && val) {
            free(v->show);
            v->show = lg_xstrdup(val);
            i++;
        } else if (strcmp(s, "--size") == 0 && val) {
            if (!lg_parse_size(val, &v->opts.width, &v->opts.height))
                rc = usage("lightgraph view: --size wants WxH, 1..16384 each (got '%s')\n", val);
            else if (lg_size_over_limit("view", v->opts.width, v->opts.height))
                rc = 2;
            i++;
        } else if (strcmp(s, "--script") == 0 && val) {
            v->script_path = val;
            i++;
        } else if (strcmp(s, "--dt") == 0 && val) {
            char *end;
            double d = strtod(val, &end);
            if (*end || !(d > 0 && d <= 3600))
                rc = usage("lightgraph view: --dt wants seconds in (0, 3600] (got '%s')\n", val);
            v->opts.dt = d;
            i++;
        } else if (strcmp(s, "-v") == 0) {
            lg_verbosity++;
        } else if (strcmp(s, "-q") == 0) {
            lg_verbosity = -1;
        } else if (s[0] == '-' && s[1]) {
            rc = usage(val || strncmp(s, "--", 2) ? "lightgraph view: unknown option '%s'\n"
                                                  : "lightgraph view: %s needs a value\n", s);
        } else if (!v->graph) {
            v->graph = s;
        } else {
            rc = usage("lightgraph view: unexpected argument '%s'\n", s);
        }
    }
    if (rc == 0 && !v->graph)
        rc = usage("lightgraph view: no graph file given%s\n", "");
    char err[8192];
    if (rc == 0 && v->script_path && lg_script_load(v->script_path, &v->script, err, sizeof err)) {
        fprintf(stderr, "lightgraph view: %s\n", err);
        rc = 2;
    }
    v->scripted = v->script_path != NULL;
    if (rc) {
        free(v->sets);
        free(v->show);
        lg_script_free(&v->script);
        free(v);
        return rc;
    }

    /* the window first: without a display there is nothing to do */
    glfwSetErrorCallback(cb_glfw_error);
    if (!glfwInit()) {
        const char *d = getenv("DISPLAY");
        fprintf(stderr, "lightgraph view: no display (%s%s): %s; run it on a desktop or "
                "under xvfb-run\n", d && *d ? "DISPLAY=" : "DISPLAY is not set",
                d && *d ? d : "", glfw_error_text ? glfw_error_text : "glfwInit failed");
        free(v->sets);
        free(v->show);
        lg_script_free(&v->script);
        free(v);
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_FALSE);
    v->win = glfwCreateWindow((int)v->opts.width, (int)v->opts.height, "lightgraph view", NULL,
                              NULL);
    if (!v->win) {
        fprintf(stderr, "lightgraph view: the display gives no OpenGL 4.5 core context: %s\n",
                glfw_error_text ? glfw_error_text : "glfwCreateWindow failed");
        glfwTerminate();
        free(v->sets);
        free(v->show);
        lg_script_free(&v->script);
        free(v);
        return 1;
    }
    glfwMakeContextCurrent(v->win);
    glfwSwapInterval(v->scripted ? 0 : 1);
    dl_iterate_phdr(pin_object, NULL);
    lg_gl_backend be = {.label = "GLFW window", .load = glfw_load, .destroy = NULL, .state = NULL};
    rc = lg_gl_device_wrap(&v->gl, &be, err, sizeof err);
    if (rc == 0 && lg_vdisplay_create(lg_gl_device_table(v->gl), &v->disp, err, sizeof err))
        rc = LG_ERR_DEVICE;
    if (rc) {
        fprintf(stderr, "lightgraph view: %s\n", err);
        rc = 1;
        goto out;
    }
    v->timer_query = lg_gl_device_timer_query(v->gl);
    lg_hlog(LG_HINFO, "GL device: %s", lg_gl_device_description(v->gl));
    g_viewer = v;
    lg_hlog_error_hook = error_hook;
    v->vp = lg_vparams_new();
    v->reg.private_copies = true;
    lg_registry_scan(&v->reg);
    rc = try_load(v, true, true, err, sizeof err);
    if (rc) {
        fprintf(stderr, "lightgraph view: %s\n", err);
        goto out;
    }
    v->ev_auto_pending = true;
    start_watching(v);
    glfwSetKeyCallback(v->win, cb_key);
    glfwSetMouseButtonCallback(v->win, cb_button);
    glfwSetCursorPosCallback(v->win, cb_cursor);
    glfwSetScrollCallback(v->win, cb_scroll);
    set_status(v, false, "showing %s (%s)", v->cur.shown_name, v->graph);
    v->last_change_ok = true;
    v->last_t = lg_now();
    /* frame 0 ran in try_load */
    for (;;) {
        glfwPollEvents();
        if (glfwWindowShouldClose(v->win))
            break;
        if (v->scripted)
            script_step(v);
        if (v->quit)
            break;
        poll_reloads(v);
        double now = lg_now();
        double dt = v->scripted ? 1.0 / 30.0 : now - v->last_t;
        fly_step(v, dt);
        if (!v->frame_done)
            run_frame(v);
        v->frame_done = false;
        if (v->ev_auto_pending)
            auto_exposure(v);
        present(v);
        double ft = now - v->last_t;
        v->last_t = now;
        if (ft > 0)
            v->fps = v->fps == 0 ? 1.0 / ft : 0.9 * v->fps + 0.1 / ft;
        if (v->frame % 15 == 0)
            update_title(v);
        v->frame++;
        /* nothing to run, nothing moving: wait for an event rather than spin */
        bool busy = v->scripted || v->anim.active || v->rebuild;
        for (uint32_t i = 0; !busy && i < v->cur.ex->n_nodes; i++)
            busy = v->cur.ex->nodes[i] && v->cur.ex->nodes[i]->per_frame &&
                   v->cur.ex->nodes[i]->state == LG_STATE_KEPT;
        for (int k = 0; !busy && k <= GLFW_KEY_LAST; k++)
            busy = v->held[k];
        if (!busy)
            glfwWaitEventsTimeout(0.1);
    }
    rc = v->expect_failed ? 1 : v->exit_status;
    if (v->scripted && v->pc < v->script.n && !v->expect_failed && !v->quit)
        rc = 1;

out:
    lg_hlog_error_hook = NULL;
    g_viewer = NULL;
    lg_rebuild_free(&v->rebuild);
    lg_watch_close(&v->watch);
    loaded_free(&v->cur);
    if (v->gl) {
        const GladGLContext *gl = lg_gl_device_table(v->gl);
        if (v->cpu_tex)
            gl->DeleteTextures(1, &v->cpu_tex);
        if (v->timer_query)
            gl->DeleteQueries(1, &v->timer_query);
    }
    lg_vdisplay_destroy(&v->disp);
    lg_gl_device_destroy(&v->gl);
    lg_cl_device_destroy(&v->cl);
    if (v->win)
        glfwDestroyWindow(v->win);
    glfwTerminate();
    lg_registry_free(&v->reg);
    lg_vparams_free(v->vp);
    lg_overrides_free(&v->ov);
    lg_script_free(&v->script);
    for (uint32_t i = 0; i < v->n_pending_plugins; i++)
        free(v->pending_plugins[i]);
    free(v->pending_plugins);
    free(v->sets);
    free(v->show);
    free(v->status);
    free(v->last_error);
    free(v->cam_scene_ref);
    free(v->dev_build);
    free(v->dev_shaders);
    free(v->window_shot);
    free(v);
    return rc;
}
