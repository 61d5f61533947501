/* Planning: simulate only what the outputs need and the scene calls for.
 *
 *   1. cull: keep the nodes on a path to an output statement, and side-effect nodes;
 *   2. prepare the nodes that make scenes, and everything upstream of them;
 *   3. gate: a node whose needs the scene upstream of it does not meet becomes its neutral
 *      result and its plugin is not loaded;
 *   4. cull again: a node that only gated nodes read (other than through the input a gated
 *      node passes on) is not needed either;
 *   5. in topological order, load the plugin of each remaining node (dlopen, only now),
 *      create, prepare (outputs declared, device chosen, once or per frame).
 *
 * A node's identity (for the cache, and for everything downstream) is a digest of its
 * plugin, version, type, parameters, content keys and its inputs' identities. */
#include "plan/plan.h"

#include "lightgraph/kinds.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>

static void digest_params(lg_digest *d, const lg_cnode *c)
{
    for (uint32_t i = 0; i < c->type->n_params; i++) {
        const lg_param_desc *p = &c->type->params[i];
        const lg_value *v = &c->params[i];
        lg_digest_add_str(d, p->key);
        switch (p->type) {
        case LG_PARAM_BOOL: {
            uint8_t b = v->b;
            lg_digest_add(d, &b, 1);
            break;
        }
        case LG_PARAM_INT: lg_digest_add(d, &v->i, sizeof v->i); break;
        case LG_PARAM_FLOAT: lg_digest_add(d, &v->f, sizeof v->f); break;
        case LG_PARAM_VEC2:
        case LG_PARAM_VEC3:
        case LG_PARAM_COLOR:
            lg_digest_add(d, v->v, sizeof v->v);
            if (p->type == LG_PARAM_COLOR && p->enum_values) /* keyword index, or -1 */
                lg_digest_add(d, &v->e, sizeof v->e);
            break;
        case LG_PARAM_INT3: lg_digest_add(d, v->i3, sizeof v->i3); break;
        case LG_PARAM_STRING:
        case LG_PARAM_PATH:
        case LG_PARAM_ENUM: lg_digest_add_str(d, v->s); break;
        case LG_PARAM_PATH_LIST: {
            lg_digest_add(d, &v->e, sizeof v->e);
            const char *s = v->s;
            for (int32_t k = 0; s && k < v->e; k++, s += strlen(s) + 1)
                lg_digest_add_str(d, s);
            break;
        }
        }
    }
}

static const char *needs_text(uint32_t unmet)
{
    if (unmet & LG_NEEDS_MEDIUM)
        return "no participating medium with density > 0";
    if (unmet & LG_NEEDS_DIR_LIGHT)
        return "no directional light";
    if (unmet & LG_NEEDS_POINT_LIGHT)
        return "no point light";
    if (unmet & LG_NEEDS_LIGHT)
        return "no light";
    if (unmet & LG_NEEDS_PROBE)
        return "no light probe";
    if (unmet & LG_NEEDS_SPECULAR)
        return "no material with a specular term";
    if (unmet & LG_NEEDS_REFLECTIVE)
        return "no reflective material";
    if (unmet & LG_NEEDS_TEXTURES)
        return "no textured material";
    if (unmet & LG_NEEDS_GEOMETRY)
        return "no geometry";
    return "unmet needs";
}

/* Union of the features of the scenes node i reads: on each input, the scene delivered
 * there, or, for an input that is not a scene (an image made from one, say), the scenes
 * upstream of it. A scene stands for everything upstream of it: a derived scene (camera,
 * light, medium nodes) replaces its source's lights or medium, so the walk stops there and
 * the source does not count again. */
static bool collect_features(lg_exec *ex, uint32_t i, lg_scene_features *f, bool *seen)
{
    if (seen[i])
        return false;
    seen[i] = true;
    bool any = false;
    lg_pnode *n = ex->nodes[i];
    for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
        lg_edge e = n->c->inputs[k];
        if (e.node < 0)
            continue;
        lg_resource *r = lg_edge_resource(ex, e);
        if (r && r->kind == LG_KIND_SCENE && r->has_features) {
            f->triangles += r->features.triangles;
            f->vertices += r->features.vertices;
            f->dir_lights += r->features.dir_lights;
            f->point_lights += r->features.point_lights;
            f->other_lights += r->features.other_lights;
            f->medium |= r->features.medium;
            f->probe |= r->features.probe;
            f->specular |= r->features.specular;
            f->reflective_materials += r->features.reflective_materials;
            f->textures += r->features.textures;
            f->masked_materials += r->features.masked_materials;
            f->animated += r->features.animated;
            if (r->features.medium_density > f->medium_density)
                f->medium_density = r->features.medium_density;
            any = true;
            continue;
        }
        any |= collect_features(ex, (uint32_t)e.node, f, seen);
    }
    return any;
}

static uint32_t unmet_needs(uint32_t needs, const lg_scene_features *f)
{
    uint32_t unmet = 0;
    if ((needs & LG_NEEDS_GEOMETRY) && f->triangles == 0)
        unmet |= LG_NEEDS_GEOMETRY;
    if ((needs & LG_NEEDS_LIGHT) && f->dir_lights + f->point_lights + f->other_lights == 0)
        unmet |= LG_NEEDS_LIGHT;
    if ((needs & LG_NEEDS_DIR_LIGHT) && f->dir_lights == 0)
        unmet |= LG_NEEDS_DIR_LIGHT;
    if ((needs & LG_NEEDS_POINT_LIGHT) && f->point_lights == 0)
        unmet |= LG_NEEDS_POINT_LIGHT;
    if ((needs & LG_NEEDS_MEDIUM) && !(f->medium && f->medium_density > 0))
        unmet |= LG_NEEDS_MEDIUM;
    if ((needs & LG_NEEDS_PROBE) && !f->probe)
        unmet |= LG_NEEDS_PROBE;
    if ((needs & LG_NEEDS_SPECULAR) && !f->specular)
        unmet |= LG_NEEDS_SPECULAR;
    if ((needs & LG_NEEDS_REFLECTIVE) && f->reflective_materials == 0)
        unmet |= LG_NEEDS_REFLECTIVE;
    if ((needs & LG_NEEDS_TEXTURES) && f->textures == 0)
        unmet |= LG_NEEDS_TEXTURES;
    return unmet;
}

/* A gated node's outputs: its neutral result. */
static void make_neutral(lg_exec *ex, lg_pnode *n)
{
    const lg_node_type *t = n->schema;
    for (uint32_t o = 0; o < t->n_outputs; o++) {
        lg_resource *in = NULL;
        if (t->neutral == LG_NEUTRAL_PASSTHROUGH ||
            (t->neutral == LG_NEUTRAL_PASSTHROUGH_FIRST && o == 0)) {
            in = lg_edge_resource(ex, n->c->inputs[t->neutral_input]);
        }
        if (in && (t->outputs[o].kind == LG_KIND_ANY || t->outputs[o].kind == in->kind)) {
            in->refs++;
            n->outputs[o] = in;
            continue;
        }
        lg_resource_kind kind = t->outputs[o].kind == LG_KIND_ANY ? LG_KIND_IMAGE
                                                                  : t->outputs[o].kind;
        lg_resource *r = lg_resource_new(n, kind);
        r->neutral = true;
        if (kind == LG_KIND_IMAGE) {
            r->image.width = ex->opts.width;
            r->image.height = ex->opts.height;
            r->image.format = LG_FORMAT_RGBA32F;
            for (uint32_t k = 0; k < t->n_inputs; k++) {
                lg_resource *src = lg_edge_resource(ex, n->c->inputs[k]);
                if (src && src->kind == LG_KIND_IMAGE) {
                    r->image.width = src->image.width;
                    r->image.height = src->image.height;
                    break;
                }
            }
        } else if (kind == LG_KIND_VOLUME) {
            r->volume.width = r->volume.height = r->volume.depth = 1;
            r->volume.format = LG_FORMAT_RGBA32F;
        } else if (kind == LG_KIND_SCENE) {
            r->has_features = true;
        } else if (lg_kind_is_composite(kind)) {
            lg_resource_make_parts(ex, n, r, NULL, 0);
        }
        n->outputs[o] = r;
    }
}

/* create() or prepare() of a node, under the crash guard ex->guard asks for. */
typedef struct callback_call {
    lg_pnode *n;
    int (*fn)(lg_node *);
    int rc;
} callback_call;

static void call_callback(void *p)
{
    callback_call *c = p;
    c->rc = c->fn(&c->n->pub);
}

static int guarded(lg_exec *ex, lg_pnode *n, int (*fn)(lg_node *), const char *what)
{
    callback_call call = { n, fn, 0 };
    if (lg_node_call(ex, n, what, call_callback, &call))
        return -1;
    return call.rc;
}

static int prepare_node(lg_exec *ex, lg_pnode *n)
{
    char err[1024];
    if (lg_registry_load(ex->reg, n->plugin, err, sizeof err)) {
        lg_node_errorf(n, "%s", err);
        return -1;
    }
    const lg_node_type *live = lg_plugin_live_type(n->plugin, n->schema->name);
    if (!live) {
        lg_node_errorf(n, "plugin %s no longer declares this type", n->plugin->path);
        return -1;
    }
    n->pub.type = live;
    n->plugin->live_refs++;
    n->run.created = true;
    if (live->create && guarded(ex, n, live->create, "create") != 0) {
        if (!ex->failed)
            lg_node_errorf(n, "create() failed without saying why");
        return -1;
    }
    if (live->prepare && guarded(ex, n, live->prepare, "prepare") != 0) {
        if (!ex->failed)
            lg_node_errorf(n, "prepare() failed without saying why");
        return -1;
    }
    if (ex->failed)
        return -1;
    n->run.prepared = true;
    for (uint32_t o = 0; o < n->schema->n_outputs; o++)
        if (!n->outputs[o]) {
            lg_node_errorf(n, "prepare() did not declare output '%s'", n->schema->outputs[o].name);
            return -1;
        }
    if (!n->run.device_set)
        n->run.device = LG_DEVICE_CPU;
    return 0;
}

/* Points a node at plan `ex`, where it is node `index`. */
static void attach(lg_exec *ex, lg_pnode *n, uint32_t index)
{
    n->ex = ex;
    n->index = index;
    n->c = &ex->checked->nodes[index];
    n->schema = n->c->type;
    n->pub.host = &ex->api;
    n->pub.name = n->c->g->name;
}

/* Node i of ex, about to be prepared: the node of ex->viewer.prev it can be instead, or NULL.
 * Same identity before prepare (plugin, version, type, parameters, inputs' identities: a
 * content key is added in prepare, which an adopted node does not run again; a file the
 * node read is not read again either, see docs/viewer.md),
 * same plugin entry (a reloaded plugin makes its nodes again), the same resources on
 * every input (an input made again means this node's preparation may not hold), and the
 * same render size, unless the node has no image output and never asked for the render
 * size (a loaded scene, a bake, shadow maps fitted to the bounds: the viewer's window
 * resize keeps them; docs/viewer.md "Window size"). */
static bool depends_on_size(const lg_pnode *o)
{
    if (o->run.read_render_size)
        return true;
    for (uint32_t k = 0; k < o->schema->n_outputs; k++)
        if (o->outputs && o->outputs[k] && o->outputs[k]->kind == LG_KIND_IMAGE)
            return true;
    return false;
}

static lg_pnode *adoptable(lg_exec *ex, const lg_pnode *n)
{
    lg_exec *pv = ex->viewer.prev;
    if (!pv)
        return NULL;
    bool resized = pv->opts.width != ex->opts.width || pv->opts.height != ex->opts.height;
    for (uint32_t j = 0; j < pv->n_nodes; j++) {
        lg_pnode *o = pv->nodes[j];
        if (!o || o->plan.lent || o->run.crashed || !o->run.prepared ||
            (resized && depends_on_size(o)) || o->plan.state != LG_STATE_KEPT ||
            o->plugin != n->plugin || o->schema != n->schema ||
            memcmp(&o->plan.plan_identity, &n->plan.plan_identity, sizeof n->plan.identity) != 0)
            continue;
        bool same = true;
        for (uint32_t k = 0; k < n->schema->n_inputs && same; k++) {
            lg_edge en = n->c->inputs[k], eo = o->c->inputs[k];
            if ((en.node < 0) != (eo.node < 0))
                same = false;
            else if (en.node >= 0)
                same = lg_edge_resource(ex, en) == lg_edge_resource(pv, eo);
        }
        if (same)
            return o;
    }
    return NULL;
}

void lg_plan_commit(lg_exec *ex)
{
    for (uint32_t i = 0; ex->viewer.prev && i < ex->n_nodes; i++) {
        lg_pnode *n = ex->nodes[i];
        if (n && n->plan.lent) {
            ex->viewer.prev->nodes[n->plan.prev_index] = NULL;
            n->plan.lent = false;
        }
    }
    ex->viewer.prev = NULL;
}

void lg_plan_rollback(lg_exec *ex)
{
    for (uint32_t i = 0; ex->viewer.prev && i < ex->n_nodes; i++) {
        lg_pnode *n = ex->nodes[i];
        if (n && n->plan.lent) {
            attach(ex->viewer.prev, n, n->plan.prev_index);
            n->plan.lent = false;
            ex->nodes[i] = NULL;
        }
    }
    ex->viewer.prev = NULL;
}

/* Nodes with an output of kind scene, and every node upstream of one: prepared first. */
static void mark_scene_producers(lg_exec *ex, bool *early)
{
    const lg_checked *c = ex->checked;
    for (uint32_t t = c->n_nodes; t-- > 0;) {
        uint32_t i = c->topo[t];
        const lg_node_type *ty = ex->nodes[i]->schema;
        bool scene = early[i];
        for (uint32_t o = 0; o < ty->n_outputs && !scene; o++)
            scene = ty->outputs[o].kind == LG_KIND_SCENE;
        if (!scene)
            continue;
        early[i] = true;
        for (uint32_t k = 0; k < ty->n_inputs; k++)
            if (c->nodes[i].inputs[k].node >= 0)
                early[c->nodes[i].inputs[k].node] = true;
    }
}

/* Gates n (state GATED, with the reason) when the scenes upstream do not meet its needs. */
static void decide_gate(lg_exec *ex, lg_pnode *n, bool *seen)
{
    if (!n->schema->needs || n->plan.state == LG_STATE_GATED)
        return;
    lg_scene_features f;
    memset(&f, 0, sizeof f);
    memset(seen, 0, ex->checked->n_nodes * sizeof *seen);
    bool any = collect_features(ex, n->index, &f, seen);
    uint32_t unmet = any ? unmet_needs(n->schema->needs, &f) : n->schema->needs;
    if (unmet) {
        n->plan.state = LG_STATE_GATED;
        n->plan.reason = any ? lg_xasprintf("the scene upstream has %s", needs_text(unmet))
                             : lg_xstrdup("no scene is upstream of it, so its needs "
                                          "cannot be met");
    }
}

/* Culls what no output needs: walks from the outputs and side-effect nodes through the
 * inputs of the nodes it reaches; into a gated node only through the input its neutral
 * result passes on (a gated node reads nothing else). Nodes not reached are culled with
 * `reason`, but for those already prepared (`early`, may be NULL). Run once before anything
 * is gated (every node is then reached through all its inputs), and again after gating. */
static void cull(lg_exec *ex, const bool *early, const char *reason)
{
    const lg_checked *c = ex->checked;
    bool *keep = lg_xcalloc(c->n_nodes ? c->n_nodes : 1, sizeof *keep);
    uint32_t *stack = lg_xcalloc(c->n_nodes + c->n_outputs + ex->viewer.n_roots + 1, sizeof *stack);
    uint32_t sp = 0;
    uint32_t n_roots = ex->viewer.roots ? ex->viewer.n_roots : c->n_outputs;
    for (uint32_t i = 0; i < n_roots; i++) {
        int32_t r = ex->viewer.roots ? ex->viewer.roots[i].node : c->outputs[i].node;
        if (r >= 0 && !keep[r]) {
            keep[r] = true;
            stack[sp++] = (uint32_t)r;
        }
    }
    for (uint32_t i = 0; i < c->n_nodes; i++)
        if ((c->nodes[i].type->flags & LG_NODE_SIDE_EFFECT) && !keep[i]) {
            keep[i] = true;
            stack[sp++] = i;
        }
    while (sp > 0) {
        uint32_t i = stack[--sp];
        const lg_node_type *t = ex->nodes[i]->schema;
        bool gated = ex->nodes[i]->plan.state == LG_STATE_GATED;
        bool passes = t->neutral == LG_NEUTRAL_PASSTHROUGH ||
                      t->neutral == LG_NEUTRAL_PASSTHROUGH_FIRST;
        for (uint32_t k = 0; k < t->n_inputs; k++) {
            if (gated && !(passes && k == t->neutral_input))
                continue;
            int32_t s = c->nodes[i].inputs[k].node;
            if (s >= 0 && !keep[s]) {
                keep[s] = true;
                stack[sp++] = (uint32_t)s;
            }
        }
    }
    for (uint32_t i = 0; i < c->n_nodes; i++)
        if (!keep[i] && !(early && early[i]) && ex->nodes[i]->plan.state == LG_STATE_KEPT) {
            ex->nodes[i]->plan.state = LG_STATE_CULLED;
            ex->nodes[i]->plan.reason = lg_xstrdup(reason);
        }
    free(keep);
    free(stack);
}

/* Rigid animation (ABI 3.1): a node that reads an animated scene (an input delivers a
 * scene with features.animated > 0; a derived scene carries its source's animation) runs
 * on every frame, at lg_frame.time's pose, unless its type says the pose does not matter
 * to it (LG_NODE_POSE_INDEPENDENT: a transfer bake, a node that derives a scene and
 * carries the animation on). What lies downstream of such a node re-runs with it (the
 * per-frame flag of its inputs, above); a static scene's nodes still run once. */
static void animated_per_frame(lg_exec *ex, lg_pnode *n)
{
    if (n->schema->flags & LG_NODE_POSE_INDEPENDENT)
        return;
    bool animated = false;
    for (uint32_t k = 0; k < n->schema->n_inputs && !animated; k++) {
        lg_edge e = n->c->inputs[k];
        if (e.node < 0)
            continue;
        lg_resource *r = lg_edge_resource(ex, e);
        animated = r && r->kind == LG_KIND_SCENE && r->has_features && r->features.animated > 0;
    }
    if (!animated)
        return;
    if (!n->run.per_frame)
        n->run.per_frame_why = "reads an animated scene";
    n->run.per_frame = true;
}

/* One node: its identity and per-frame flag, then gated (its neutral result) or prepared. */
static int plan_node(lg_exec *ex, lg_pnode *n, bool *seen)
{
    lg_digest_init(&n->plan.identity);
    lg_digest_add_str(&n->plan.identity, n->plugin ? n->plugin->name : "");
    lg_digest_add_str(&n->plan.identity, n->plugin ? n->plugin->version : "");
    lg_digest_add_str(&n->plan.identity, n->schema->name);
    digest_params(&n->plan.identity, n->c);
    n->plan.cache_identity = n->plan.identity;
    for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
        lg_edge e = n->c->inputs[k];
        if (e.node < 0) {
            lg_digest_add_str(&n->plan.identity, NULL);
            continue;
        }
        lg_digest_add(&n->plan.identity, &ex->nodes[e.node]->plan.identity, sizeof(lg_digest));
        lg_digest_add(&n->plan.identity, &e.port, sizeof e.port);
        lg_digest_add(&n->plan.identity, &e.part, sizeof e.part);
    }
    for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
        lg_edge e = n->c->inputs[k];
        if (e.node >= 0 && ex->nodes[e.node]->run.per_frame)
            n->run.per_frame = true;
    }
    if (n->schema->flags & LG_NODE_PER_FRAME)
        n->run.per_frame = true;
    animated_per_frame(ex, n);

    n->plan.plan_identity = n->plan.identity;
    decide_gate(ex, n, seen);
    if (n->plan.state == LG_STATE_GATED) {
        make_neutral(ex, n);
        return 0;
    }
    lg_pnode *o = adoptable(ex, n);
    if (o) {
        /* the earlier plan's node, with its instance, resources and state, takes this
         * node's place; `n` (nothing made yet) is dropped */
        uint32_t i = n->index;
        o->plan.prev_index = o->index;
        o->plan.lent = true;
        attach(ex, o, i);
        o->run.per_frame |= n->run.per_frame;
        free(n->outputs);
        free(n->plan.reason);
        free(n);
        ex->nodes[i] = o;
        lg_hlog(LG_HDEBUG, "node '%s' kept from the previous plan", o->pub.name);
        return 0;
    }
    return prepare_node(ex, n);
}

/* The sum of what the plan's resources will take (each image, volume and buffer a kept
 * node declared, once, however many nodes read it; every part of a composite), against
 * what the machine can give (lg_memory_available, the bound of every image read). Each
 * resource passed that bound alone when it was declared; together they may not, and a
 * render that would run out of memory after minutes of work is refused before it starts.
 * Returns 0, or -1 after reporting the total, the largest resource and the bound. */
static int check_plan_memory(lg_exec *ex)
{
    uint64_t total = 0, largest = 0;
    uint32_t count = 0;
    const lg_pnode *big = NULL;
    const char *big_port = NULL;
    for (uint32_t i = 0; i < ex->n_nodes; i++) {
        const lg_pnode *n = ex->nodes[i];
        if (n->plan.state != LG_STATE_KEPT || !n->outputs)
            continue;
        for (uint32_t o = 0; o < n->schema->n_outputs; o++) {
            const lg_resource *r = n->outputs[o];
            if (!r || r->producer != n) /* an alias is its input, counted at its producer */
                continue;
            uint64_t b = lg_resource_bytes(r);
            if (!b)
                continue;
            total += b;
            count++;
            if (b > largest) {
                largest = b;
                big = n;
                big_port = n->schema->outputs[o].name;
            }
        }
    }
    const char *bound;
    uint64_t avail = lg_memory_available(&bound);
    if (total <= avail)
        return 0;
    char need[32], have[32], most[32];
    lg_bytes_text(need, sizeof need, total);
    lg_bytes_text(have, sizeof have, avail);
    lg_bytes_text(most, sizeof most, largest);
    lg_hlog(LG_HERR,
            "the plan's %u images, volumes and buffers need %s (%llu bytes) in all, "
            "more than the %s (%llu bytes) of %s; the largest is output '%s' of node "
            "'%s' (%s); nothing was run",
            count, need, (unsigned long long)total, have, (unsigned long long)avail, bound,
            big_port ? big_port : "?", big ? big->pub.name : "?", most);
    ex->failed = true;
    return -1;
}

int lg_plan(lg_exec *ex)
{
    const lg_checked *c = ex->checked;
    double t0 = lg_mono_now();
    lg_host_api_init(&ex->api);
    ex->n_nodes = c->n_nodes;
    ex->nodes = lg_xcalloc(c->n_nodes ? c->n_nodes : 1, sizeof *ex->nodes);
    for (uint32_t i = 0; i < c->n_nodes; i++) {
        lg_pnode *n = ex->nodes[i] = lg_xcalloc(1, sizeof *n);
        n->pub.host = &ex->api;
        n->pub.name = c->nodes[i].g->name;
        n->pub.type = c->nodes[i].type;
        n->ex = ex;
        n->index = i;
        n->c = &c->nodes[i];
        n->schema = c->nodes[i].type;
        lg_registry_lookup(ex->reg, n->schema->name, &n->plugin);
        n->outputs = lg_xcalloc(n->schema->n_outputs ? n->schema->n_outputs : 1,
                                sizeof *n->outputs);
    }
    cull(ex, NULL, "no output depends on it");

    /* Gating needs the scenes' features, which exist once the nodes that make scenes are
     * prepared. So: (a) prepare the scene producers and everything upstream of them; (b)
     * decide which other nodes are gated; (c) cull again, this time walking into a gated
     * node only through the input its neutral result passes on, so that a node that only
     * gated nodes read (the shadow map of a gated fog pass, say) is not loaded either; (d)
     * prepare the rest. Each pass goes in topological order. */
    bool *seen = lg_xcalloc(c->n_nodes ? c->n_nodes : 1, sizeof *seen);
    bool *early = lg_xcalloc(c->n_nodes ? c->n_nodes : 1, sizeof *early);
    mark_scene_producers(ex, early);
    int rc = 0;
    for (uint32_t t = 0; t < c->n_nodes && rc == 0; t++) {
        uint32_t i = c->topo[t];
        if (early[i] && ex->nodes[i]->plan.state != LG_STATE_CULLED)
            rc = plan_node(ex, ex->nodes[i], seen);
    }
    if (rc == 0) {
        for (uint32_t t = 0; t < c->n_nodes; t++) {
            lg_pnode *n = ex->nodes[c->topo[t]];
            if (!early[n->index] && n->plan.state != LG_STATE_CULLED)
                decide_gate(ex, n, seen);
        }
        cull(ex, early, "only gated nodes read it");
    }
    for (uint32_t t = 0; t < c->n_nodes && rc == 0; t++) {
        uint32_t i = c->topo[t];
        if (!early[i] && ex->nodes[i]->plan.state != LG_STATE_CULLED)
            rc = plan_node(ex, ex->nodes[i], seen);
    }
    free(early);
    free(seen);
    for (uint32_t i = 0; i < c->n_nodes && rc == 0; i++) {
        lg_pnode *n = ex->nodes[i];
        if (n->plan.state != LG_STATE_KEPT)
            continue;
        bool makes = false, reads = false;
        for (uint32_t o = 0; o < n->schema->n_outputs; o++)
            makes |= n->schema->outputs[o].kind == LG_KIND_SCENE;
        for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
            lg_resource *r = n->c->inputs[k].node >= 0 ? lg_edge_resource(ex, n->c->inputs[k])
                                                       : NULL;
            reads |= r && r->kind == LG_KIND_SCENE;
        }
        bool independent = n->plan.view_independent_set
                               ? n->plan.view_independent
                               : (n->schema->flags & LG_NODE_VIEW_INDEPENDENT) != 0;
        n->plan.reads_scene = reads && !makes && !independent;
    }
    if (rc == 0 && !ex->failed)
        rc = check_plan_memory(ex);
    ex->t_plan_ms = (lg_mono_now() - t0) * 1e3;
    return rc || ex->failed ? -1 : 0;
}
