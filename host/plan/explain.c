/* --explain (the plan, node by node: kept, culled or gated and why, devices, resources,
 * scene features, declared work) and the estimate of a run's wall time. */
#include "plan/plan.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/kinds.h"
#include "lightgraph/medium.h"
#include "lightgraph/scene.h"

static const char *state_name(lg_node_state s)
{
    return s == LG_STATE_KEPT ? "kept" : s == LG_STATE_CULLED ? "culled" : "gated";
}

static const char *device_name(lg_device d)
{
    return d == LG_DEVICE_GL ? "gl" : d == LG_DEVICE_CL ? "cl" : "cpu";
}

static const char *format_name(lg_format f)
{
    return lg_format_name(f); /* rgba32f, rgba16f, rgba8, rgbe8 */
}

static void describe_resource(lg_str *s, const lg_resource *r)
{
    char sz[32];
    const char *kind = lg_kind_name(r->kind); /* "image", "shadowmap": the SDK's one table */
    switch (r->kind) {
    case LG_KIND_IMAGE:
        lg_format_bytes(sz, sizeof sz, lg_resource_bytes(r));
        if (r->image.flags & LG_IMAGE_DEPTH_ONLY)
            lg_str_addf(s, "%s %ux%u depth32f (%s)", kind, r->image.width, r->image.height, sz);
        else {
            char lev[32] = "";
            if (r->image.levels > 1)
                snprintf(lev, sizeof lev, " x%u levels", r->image.levels);
            lg_str_addf(s, "%s %ux%u%s %s%s%s (%s)", kind, r->image.width, r->image.height,
                        (r->image.flags & LG_IMAGE_CUBE) ? " cube" : "",
                        format_name(r->image.format),
                        (r->image.flags & LG_IMAGE_DEPTH) ? "+depth" : "", lev, sz);
        }
        break;
    case LG_KIND_VOLUME:
        lg_format_bytes(sz, sizeof sz, lg_resource_bytes(r));
        lg_str_addf(s, "%s %ux%ux%u %s (%s)", kind, r->volume.width, r->volume.height,
                    r->volume.depth, format_name(r->volume.format), sz);
        break;
    case LG_KIND_BUFFER:
        lg_format_bytes(sz, sizeof sz, r->buffer.size);
        lg_str_addf(s, "%s %s", kind, sz);
        break;
    case LG_KIND_SCENE: lg_str_add(s, kind); break;
    default:
        if (lg_kind_is_composite(r->kind)) {
            const lg_kind_desc *kd = lg_kind_describe(r->kind);
            lg_str_addf(s, "%s {", kind);
            uint32_t shown = 0;
            for (uint32_t i = 0; !r->neutral && i < r->parts.n; i++) {
                if (!r->parts.list[i])
                    continue;
                lg_str_addf(s, "%s%s: ", shown++ ? ", " : "", kd->parts[i].name);
                describe_resource(s, r->parts.list[i]);
            }
            lg_str_add(s, "}");
        } else {
            lg_str_add(s, "payload");
        }
        break;
    }
    if (r->neutral)
        lg_str_add(s, " [neutral]");
}

/* "shadows <- shadow.shadows" or "image <- shadow.atlas (part of shadow.shadows)" */
static void describe_inputs(lg_exec *ex, lg_str *d, const lg_pnode *n)
{
    for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
        lg_edge e = n->c->inputs[k];
        if (e.node < 0)
            continue;
        const lg_pnode *src = ex->nodes[e.node];
        const char *port = src->schema->outputs[e.port].name;
        lg_str_addf(d, "%s%s <- %s.", d->len ? "; " : "", n->schema->inputs[k].name, src->pub.name);
        if (e.part) {
            const lg_kind_desc *kd = lg_kind_describe(src->schema->outputs[e.port].kind);
            lg_str_addf(d, "%s (part of %s.%s)", kd ? kd->parts[e.part - 1].name : "?",
                        src->pub.name, port);
        } else {
            lg_str_add(d, port);
        }
    }
}

static void print_features(FILE *f, const char *name, const lg_scene_features *sf)
{
    fprintf(f,
            "scene features (%s): triangles %llu, vertices %llu, lights: %u directional, %u "
            "point, %u other; medium %s (density %g); probe %s; specular material %s; "
            "reflective materials %u; textures %u; masked materials %u; animated instances, "
            "lights and cameras %u; medium field %s\n",
            name, (unsigned long long)sf->triangles, (unsigned long long)sf->vertices,
            sf->dir_lights, sf->point_lights, sf->other_lights, sf->medium ? "yes" : "no",
            (double)sf->medium_density, sf->probe ? "yes" : "no", sf->specular ? "yes" : "no",
            sf->reflective_materials, sf->textures, sf->masked_materials, sf->animated,
            sf->medium_field ? "yes" : "no");
}

/* "medium field (fog): fbm 5 octaves, frequency 1, ...; majorant 1.94 over the scene": the
 * density field of a scene that has one (ABI 3.2), read from the producer's lg_scene. */
static void print_field(FILE *f, const char *name, const lg_scene *s)
{
    const lg_density_field *fd = s->medium.field;
    if (!fd)
        return;
    fprintf(f, "medium field (%s): ", name);
    if (fd->kind == LG_FIELD_GRID && fd->grid) {
        const lg_density_grid *g = fd->grid;
        double mib = (double)g->nx * g->ny * g->nz * sizeof(float) / (1 << 20);
        fprintf(f, "grid %ux%ux%u (%.1f MiB) from %s, values up to %g", g->nx, g->ny, g->nz, mib,
                g->source ? g->source : "?", (double)g->max_value);
    } else if (fd->kind == LG_FIELD_FBM) {
        const lg_density_fbm *b = &fd->fbm;
        fprintf(f,
                "fbm %u octaves, seed %u, frequency %g, lacunarity %g, gain %g, offset %g, "
                "scale %g",
                b->octaves, b->seed, (double)b->frequency, (double)b->lacunarity, (double)b->gain,
                (double)b->offset, (double)b->scale);
    } else {
        fprintf(f, "uniform");
    }
    if (fd->height_falloff > 0)
        fprintf(f, "; height fog falloff %g from y = %g", (double)fd->height_falloff,
                (double)fd->height_base);
    if (fd->bounds_min[0] > -FLT_MAX || fd->bounds_max[0] < FLT_MAX)
        fprintf(f, "; box [%g, %g, %g] .. [%g, %g, %g]", (double)fd->bounds_min[0],
                (double)fd->bounds_min[1], (double)fd->bounds_min[2], (double)fd->bounds_max[0],
                (double)fd->bounds_max[1], (double)fd->bounds_max[2]);
    double lo[3], hi[3];
    bool bounded = true;
    for (int c = 0; c < 3; c++) {
        lo[c] = s->bounds_min[c];
        hi[c] = s->bounds_max[c];
        bounded = bounded && lo[c] <= hi[c];
    }
    if (bounded)
        fprintf(f, "; majorant %.4g over the scene's bounds\n",
                lg_medium_field_max(&s->medium, lo, hi));
    else
        fprintf(f, "; majorant %.4g\n",
                lg_medium_field_max(&s->medium, (const double[3]){ -DBL_MAX, -DBL_MAX, -DBL_MAX },
                                    (const double[3]){ DBL_MAX, DBL_MAX, DBL_MAX }));
}

/* How many times lg_execute will run a kept node: once, or on every frame. */
static uint32_t planned_runs(const lg_exec *ex, const lg_pnode *n)
{
    uint32_t frames = ex->opts.frames ? ex->opts.frames : 1;
    return n->run.per_frame || lg_exec_runs_every_frame(ex, n) ? frames : 1;
}

/* "2.7e+08 samples x 4096 coefficients, about 1.4 h" (per run; "x 10 runs" when it runs
 * on several frames) */
static void describe_work(lg_str *d, const lg_exec *ex, const lg_pnode *n)
{
    char t[64];
    uint32_t runs = planned_runs(ex, n);
    lg_format_duration(t, sizeof t, n->plan.work_seconds * runs);
    lg_str_addf(d, "%.3g %s", n->plan.work_units, n->plan.work_what ? n->plan.work_what : "units");
    if (runs > 1)
        lg_str_addf(d, " x %u runs", runs);
    lg_str_addf(d, ", about %s", t);
}

static int cmp_seconds_desc(const void *a, const void *b)
{
    double x = (*(const lg_pnode *const *)a)->plan.work_seconds,
           y = (*(const lg_pnode *const *)b)->plan.work_seconds;
    return x > y ? -1 : x < y;
}

double lg_plan_estimate(const lg_exec *ex, lg_str *top)
{
    double total = 0;
    const lg_pnode **list = lg_xcalloc(ex->n_nodes ? ex->n_nodes : 1, sizeof *list);
    uint32_t n_list = 0;
    for (uint32_t i = 0; i < ex->n_nodes; i++) {
        const lg_pnode *n = ex->nodes[i];
        /* an adopted node (the viewer) does not run again unless it runs per frame */
        if (!n || n->plan.state != LG_STATE_KEPT || !n->plan.work_declared || n->plan.lent)
            continue;
        total += n->plan.work_seconds * planned_runs(ex, n);
        list[n_list++] = n;
    }
    if (top) {
        /* largest first, by the time of one run (what a user changes a parameter of) */
        qsort(list, n_list, sizeof *list, cmp_seconds_desc);
        for (uint32_t k = 0; k < n_list && k < 3; k++) {
            /* only those that matter: a tenth of the total or more */
            if (k > 0 && list[k]->plan.work_seconds * planned_runs(ex, list[k]) < 0.1 * total)
                break;
            lg_str_addf(top, "%s%s (%s): ", k ? "; " : "", list[k]->pub.name,
                        list[k]->schema->name);
            describe_work(top, ex, list[k]);
        }
    }
    free(list);
    return total;
}

void lg_explain_print(lg_exec *ex, FILE *f)
{
    const lg_checked *c = ex->checked;
    fprintf(f, "plan for %s: %u nodes, %u outputs, %u frame%s, render size %ux%u\n",
            ex->opts.graph_path ? ex->opts.graph_path : "graph", c->n_nodes, c->n_outputs,
            ex->opts.frames, ex->opts.frames == 1 ? "" : "s", ex->opts.width, ex->opts.height);
    int wn = 4, wt = 4;
    for (uint32_t i = 0; i < ex->n_nodes; i++) {
        int a = (int)strlen(ex->nodes[i]->pub.name), b = (int)strlen(ex->nodes[i]->schema->name);
        wn = a > wn ? a : wn;
        wt = b > wt ? b : wt;
    }
    fprintf(f, "  %-*s  %-*s  %-6s  %-9s  %-6s  %s\n", wn, "node", wt, "type", "state", "runs",
            "device", "details");
    for (uint32_t t = 0; t < c->n_nodes; t++) {
        lg_pnode *n = ex->nodes[c->topo[t]];
        lg_str d = { 0 };
        if (n->plan.state == LG_STATE_KEPT) {
            describe_inputs(ex, &d, n);
            for (uint32_t o = 0; o < n->schema->n_outputs; o++) {
                if (d.len)
                    lg_str_add(&d, "; ");
                lg_str_addf(&d, "%s: ", n->schema->outputs[o].name);
                if (n->outputs[o])
                    describe_resource(&d, n->outputs[o]);
            }
            lg_str_addf(&d, "%splugin %s", d.len ? "; " : "", n->plugin ? n->plugin->name : "?");
            if (n->plan.work_declared) {
                lg_str_add(&d, "; work: ");
                describe_work(&d, ex, n);
            }
            if (n->run.per_frame_why)
                lg_str_addf(&d, "; per frame: %s", n->run.per_frame_why);
        } else {
            lg_str_add(&d, n->plan.reason ? n->plan.reason : "");
            if (n->plugin)
                lg_str_addf(&d, "; plugin %s not needed by this node", n->plugin->name);
        }
        fprintf(f, "  %-*s  %-*s  %-6s  %-9s  %-6s  %s\n", wn, n->pub.name, wt, n->schema->name,
                state_name(n->plan.state),
                n->plan.state != LG_STATE_KEPT ? "-"
                : n->run.per_frame             ? "per-frame"
                                               : "once",
                n->plan.state != LG_STATE_KEPT ? "-" : device_name(n->run.device), d.s ? d.s : "");
        lg_str_free(&d);
    }
    for (uint32_t i = 0; i < ex->n_nodes; i++) {
        lg_pnode *n = ex->nodes[i];
        for (uint32_t o = 0; n->outputs && o < n->schema->n_outputs; o++) {
            lg_resource *r = n->outputs[o];
            if (r && r->kind == LG_KIND_SCENE && r->has_features && r->producer == n &&
                !r->neutral) {
                print_features(f, n->pub.name, &r->features);
                if (r->features.medium_field && r->payload.data)
                    print_field(f, n->pub.name, r->payload.data);
            }
        }
    }
    lg_str top = { 0 };
    double est = lg_plan_estimate(ex, &top);
    if (top.len) {
        char t[64];
        lg_format_duration(t, sizeof t, est);
        fprintf(f, "estimated time: about %s (from what the nodes declared: %s)\n", t, top.s);
    } else {
        fprintf(f, "estimated time: no node declared its work\n");
    }
    lg_str_free(&top);
    char *loaded = lg_registry_loaded_list(ex->reg);
    fprintf(f, "plugins loaded: %s\n", loaded[0] ? loaded : "(none)");
    free(loaded);
    lg_str notl = { 0 };
    for (uint32_t i = 0; i < ex->reg->n_plugins; i++)
        if (!ex->reg->plugins[i]->handle)
            lg_str_addf(&notl, "%s%s", notl.len ? " " : "", ex->reg->plugins[i]->name);
    fprintf(f, "plugins not loaded: %s\n", notl.s ? notl.s : "(none)");
    lg_str_free(&notl);
    if (ex->dev.gl)
        fprintf(f, "gl device: %s\n", lg_gl_device_description(ex->dev.gl));
    if (ex->dev.cl)
        fprintf(f, "cl device: %s\n", lg_cl_device_description(ex->dev.cl));
}
