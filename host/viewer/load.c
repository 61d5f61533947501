/* host/viewer/load.c: a change to what the viewer shows. Every change (a parameter key, a
 * method switch, an edit of the graph, a rebuilt plugin) loads the graph again: parse,
 * --set and the overrides, check, plan with the previous plan as ex->viewer.prev (the planner
 * adopts the nodes whose identity, plugin and inputs are unchanged, with their resources,
 * caches and state), and run one frame. The new plan replaces the old only once that frame
 * ran; otherwise it is rolled back and the old one goes on showing the last good frame,
 * with the error on the status line, which this file also keeps.
 */
#include "viewer/state.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/kinds.h"

/* Watches the current graph's files: the graph and its includes, which a load may change
 * (reload.c watches the rest). */
void lg_viewer_watch_graph_files(viewer *v)
{
    if (!v->watch)
        return;
    char err[1024];
    if (lg_watch_files(v->watch, LG_WATCH_GRAPH, (const char *const *)v->cur.files, v->cur.n_files,
                       err, sizeof err))
        lg_hlog(LG_HWARN, "cannot watch the graph's files: %s", err);
}

/* ---- the status line ------------------------------------------------------------------------- */

void lg_viewer_status(viewer *v, bool error, const char *fmt, ...)
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

/* ---- loading a graph ------------------------------------------------------------------------- */

void lg_viewer_loaded_free(loaded *l)
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
        l->shown = (lg_edge){ ni, port, part };
    } else {
        if (c->n_outputs == 0) {
            snprintf(err, errlen,
                     "%s has no output statement: name the image to show with "
                     "--show NODE.PORT",
                     v->graph);
            return -1;
        }
        l->shown = (lg_edge){ c->outputs[0].node, c->outputs[0].port, c->outputs[0].part };
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
        snprintf(err, errlen,
                 "'%s.%s' gives %s: the viewer shows images and probes (name an "
                 "image with --show NODE.PORT)",
                 l->g->nodes[l->shown.node].name, t->outputs[l->shown.port].name,
                 kd ? kd->name : "no image");
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
    if (!n || n->plan.state == LG_STATE_CULLED)
        return false;
    if (n->plan.state == LG_STATE_KEPT && (n->schema->flags & LG_NODE_DISPLAY_REFERRED))
        return true;
    for (uint32_t k = 0; k < n->schema->n_inputs; k++)
        if (upstream_display_referred(ex, n->c->inputs[k].node, seen))
            return true;
    return false;
}

/* Parses the graph, applies --set and the overrides, checks it and resolves what to show,
 * into l (zeroed by the caller). Returns 0, or -1 with err (l then holds what was made). */
static int parse_and_check(viewer *v, loaded *l, char *err, size_t errlen)
{
    lg_diags d = { 0 };
    l->g = lg_graph_parse_file(v->graph, &d);
    for (int i = 0; l->g && i < v->n_sets; i++)
        lg_graph_set(l->g, v->sets[i], &d);
    for (uint32_t i = 0; l->g && i < v->ov.n; i++)
        lg_graph_set(l->g, v->ov.items[i], &d);
    if (l->g && !d.errors) {
        lg_schema schema;
        lg_registry_schema(&v->reg, &schema);
        schema.max_pixels = lg_image_max_pixels();
        l->c = lg_graph_check(l->g, &schema, &d);
    }
    if (!l->g || d.errors || !l->c) {
        char *t = diags_text(&d);
        snprintf(err, errlen, "%s", t);
        free(t);
        lg_diags_free(&d);
        return -1;
    }
    if (d.n) {
        lg_diags_print(&d, stderr); /* warnings */
    }
    lg_diags_free(&d);
    if (resolve_shown(v, l, err, errlen))
        return -1;
    l->n_files = lg_graph_files(l->g, &l->files);
    return 0;
}

/* The execution of a checked graph on the viewer's devices, with the previous plan to adopt
 * from unless `full`. */
static lg_exec *new_exec(viewer *v, loaded *l, bool full)
{
    lg_exec *ex = lg_xcalloc(1, sizeof *ex);
    ex->opts = v->opts;
    ex->opts.graph_path = v->graph;
    ex->reg = &v->reg;
    ex->graph = l->g;
    ex->checked = l->c;
    ex->viewer.prev = full ? NULL : v->cur.ex;
    ex->viewer.roots = &l->shown;
    ex->viewer.n_roots = 1;
    ex->dev.keep = true;
    ex->dev.gl = v->gl;
    ex->dev.gl_timer_query = v->timer_query;
    ex->dev.cl = v->cl;
    ex->viewer.camera = v->cam_on ? &v->cam_out : NULL;
    ex->viewer.camera_gen = v->cam_gen;
    ex->viewer.has_time = true;
    ex->viewer.time = v->time;
    ex->guard = LG_GUARD_RECOVER;
    return ex;
}

/* l, planned and run, becomes the current graph; the old one is freed. */
static void adopt(viewer *v, loaded *l)
{
    lg_exec *ex = l->ex;
    lg_plan_commit(ex);
    loaded old = v->cur;
    v->cur = *l;
    lg_viewer_loaded_free(&old);
    bool *seen = lg_xcalloc(l->c->n_nodes + 1, sizeof *seen);
    v->cur.display_referred = upstream_display_referred(ex, l->shown.node, seen);
    free(seen);
    bool *offer = lg_xcalloc(l->c->n_nodes + 1, sizeof *offer);
    for (uint32_t i = 0; i < l->c->n_nodes; i++)
        offer[i] = ex->nodes[i] && ex->nodes[i]->plan.state == LG_STATE_KEPT;
    lg_vparams_sync(v->vp, v->cur.g, v->cur.c, offer);
    free(offer);
    v->frame_failed = false;
    v->frame_done = true;
    lg_viewer_update_averages(v);
    lg_viewer_watch_graph_files(v);
}

int lg_viewer_load(viewer *v, bool initial, bool full, char *err, size_t errlen)
{
    free(v->last_error);
    v->last_error = NULL;
    loaded l;
    memset(&l, 0, sizeof l);
    if (parse_and_check(v, &l, err, errlen)) {
        lg_viewer_loaded_free(&l);
        return initial ? 2 : -1;
    }
    lg_exec *ex = new_exec(v, &l, full);
    l.ex = ex;
    int rc = lg_plan(ex);
    if (rc == 0)
        rc = lg_exec_frame(ex, v->frame);
    if (rc == 0 && ex->failed)
        rc = -1;
    if (ex->dev.cl && !v->cl)
        v->cl = ex->dev.cl; /* made by this plan: the viewer keeps it for every later one */
    if (rc != 0) {
        snprintf(err, errlen, "%s", v->last_error ? v->last_error : "the graph failed to run");
        lg_plan_rollback(ex);
        lg_viewer_loaded_free(&l);
        return initial ? 1 : -1;
    }
    adopt(v, &l);
    return 0;
}

void lg_viewer_change_failed(viewer *v)
{
    v->changes++;
    v->changes_failed++;
    v->last_change_ok = false;
}

void lg_viewer_refuse(viewer *v, const char *why)
{
    lg_viewer_change_failed(v);
    lg_viewer_status(v, true, "%s", why);
}

bool lg_viewer_attempt(viewer *v, const char *what, bool full)
{
    char err[8192];
    v->changes++;
    double t0 = lg_mono_now();
    if (lg_viewer_load(v, false, full, err, sizeof err) == 0) {
        v->last_change_ok = true;
        uint32_t kept = 0, made = 0;
        for (uint32_t i = 0; i < v->cur.ex->n_nodes; i++) {
            const lg_pnode *n = v->cur.ex->nodes[i];
            if (n && n->plan.state == LG_STATE_KEPT)
                n->prof.runs > 1 || (n->run.ran && !n->viewer.ran_this_frame) ? kept++ : made++;
        }
        lg_viewer_status(v, false, "%s (%.0f ms: %u node%s made, %u kept)", what,
                         (lg_mono_now() - t0) * 1e3, made, made == 1 ? "" : "s", kept);
        return true;
    }
    v->changes_failed++;
    v->last_change_ok = false;
    lg_viewer_status(v, true, "%s: rejected, keeping the last good frame:\n%s", what, err);
    return false;
}

void lg_viewer_update_averages(viewer *v)
{
    for (uint32_t i = 0; i < v->cur.ex->n_nodes; i++) {
        lg_pnode *n = v->cur.ex->nodes[i];
        if (n && n->viewer.ran_this_frame) {
            n->viewer.avg_cpu_ms = n->prof.runs <= 1
                                       ? n->viewer.last_cpu_ms
                                       : 0.9 * n->viewer.avg_cpu_ms + 0.1 * n->viewer.last_cpu_ms;
            n->viewer.avg_gpu_ms = n->prof.runs <= 1
                                       ? n->viewer.last_gpu_ms
                                       : 0.9 * n->viewer.avg_gpu_ms + 0.1 * n->viewer.last_gpu_ms;
        }
    }
}
