/* Live parameters, overrides and method switching for the viewer. See viewer_params.h. */
#include "viewer/params.h"

#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/kinds.h"

typedef struct vp_node {
    int32_t index; /* in g->nodes and c->nodes */
    char *name;    /* copies: the graph may be gone by the next sync */
    lg_vp_entry *entries;
    char **keys; /* each entry's parameter or input name */
    uint32_t n_entries;
} vp_node;

struct lg_vparams {
    vp_node *nodes;
    uint32_t n_nodes;
    uint32_t sel_node, sel_entry; /* meaningful when n_nodes > 0 */
};

static void set_err(char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void set_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || !errlen)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

/* For messages and ranges: plain decimals for everyday magnitudes ("1000", "0.3"), else the
 * exponent form written short ("1e6", "2.5e-7"). */
static void fmt_short(char out[64], double v)
{
    lg_format_shortest(out, v, 1e5, true);
}

static bool has_range(const lg_param_desc *pd)
{
    return pd->min != pd->max;
}

static uint32_t n_enum(const lg_param_desc *pd)
{
    uint32_t n = 0;
    while (pd->enum_values && pd->enum_values[n])
        n++;
    return n;
}

static uint32_t n_components(lg_param_type t)
{
    switch (t) {
    case LG_PARAM_VEC2: return 2;
    case LG_PARAM_VEC3:
    case LG_PARAM_COLOR:
    case LG_PARAM_INT3: return 3;
    default: return 0;
    }
}

static bool editable(lg_param_type t)
{
    return t == LG_PARAM_BOOL || t == LG_PARAM_INT || t == LG_PARAM_FLOAT || t == LG_PARAM_ENUM ||
           n_components(t) > 0;
}

/* ---- the selectable list --------------------------------------------------------------------- */

static void free_nodes(lg_vparams *p)
{
    for (uint32_t i = 0; i < p->n_nodes; i++) {
        free(p->nodes[i].name);
        for (uint32_t j = 0; j < p->nodes[i].n_entries; j++)
            free(p->nodes[i].keys[j]);
        free(p->nodes[i].keys);
        free(p->nodes[i].entries);
    }
    free(p->nodes);
    p->nodes = NULL;
    p->n_nodes = 0;
}

lg_vparams *lg_vparams_new(void)
{
    return lg_xcalloc(1, sizeof(lg_vparams));
}

void lg_vparams_free(lg_vparams *p)
{
    if (!p)
        return;
    free_nodes(p);
    free(p);
}

static void add_entry(vp_node *n, const lg_node_type *t, lg_vp_kind kind, uint32_t index,
                      int component)
{
    n->entries = lg_xrealloc(n->entries, (n->n_entries + 1) * sizeof *n->entries);
    n->keys = lg_xrealloc(n->keys, (n->n_entries + 1) * sizeof *n->keys);
    n->entries[n->n_entries] =
        (lg_vp_entry){ .kind = kind, .index = index, .component = component };
    n->keys[n->n_entries] = lg_xstrdup(kind == LG_VP_PARAM ? t->params[index].key
                                                           : t->inputs[index].name);
    n->n_entries++;
}

/* The entry of node `n` like `want` (named `key`): the same kind, key and component, else
 * the same key, else `fallback` (clamped to the node's entries). */
static uint32_t find_entry(const vp_node *n, const lg_vp_entry *want, const char *key,
                           uint32_t fallback)
{
    if (key) {
        for (uint32_t i = 0; i < n->n_entries; i++) {
            const lg_vp_entry *e = &n->entries[i];
            if (e->kind == want->kind && e->component == want->component &&
                strcmp(n->keys[i], key) == 0)
                return i;
        }
        for (uint32_t i = 0; i < n->n_entries; i++)
            if (strcmp(n->keys[i], key) == 0)
                return i;
    }
    return fallback < n->n_entries ? fallback : n->n_entries - 1;
}

void lg_vparams_sync(lg_vparams *p, const lg_graph *g, const lg_checked *c, const bool *offer)
{
    (void)g; /* the check points into it: names come from c->nodes[i].g */
    /* where the selection was, to find it again */
    char *old_name = NULL, *old_key = NULL;
    lg_vp_entry old_e = { 0 };
    int32_t old_index = 0;
    uint32_t old_entry = 0;
    if (p->n_nodes) {
        const vp_node *n = &p->nodes[p->sel_node];
        old_name = lg_xstrdup(n->name);
        old_key = lg_xstrdup(n->keys[p->sel_entry]);
        old_e = n->entries[p->sel_entry];
        old_index = n->index;
        old_entry = p->sel_entry;
    }
    free_nodes(p);

    for (uint32_t i = 0; c && i < c->n_nodes; i++) {
        const lg_cnode *cn = &c->nodes[i];
        if ((offer && !offer[i]) || !cn->type)
            continue;
        vp_node n = { .index = (int32_t)i };
        const lg_node_type *t = cn->type;
        for (uint32_t j = 0; j < t->n_params; j++) {
            const lg_param_desc *pd = &t->params[j];
            if (!editable(pd->type))
                continue;
            uint32_t nc = n_components(pd->type);
            /* a keyword colour: its own entry cycles keywords and a colour */
            if (!nc || (pd->type == LG_PARAM_COLOR && pd->enum_values))
                add_entry(&n, t, LG_VP_PARAM, j, -1);
            for (uint32_t k = 0; k < nc; k++)
                add_entry(&n, t, LG_VP_PARAM, j, (int)k);
        }
        for (uint32_t j = 0; j < t->n_inputs; j++)
            if (cn->inputs[j].node >= 0)
                add_entry(&n, t, LG_VP_INPUT, j, -1);
        if (!n.n_entries)
            continue;
        n.name = lg_xstrdup(cn->g->name);
        p->nodes = lg_xrealloc(p->nodes, (p->n_nodes + 1) * sizeof *p->nodes);
        p->nodes[p->n_nodes++] = n;
    }

    p->sel_node = 0;
    p->sel_entry = 0;
    if (p->n_nodes && old_name) {
        /* the same node, else the one nearest to where it was in the file (the earlier on
         * a tie) */
        uint32_t best = 0;
        int64_t best_d = INT64_MAX;
        bool same = false;
        for (uint32_t i = 0; i < p->n_nodes && !same; i++) {
            if (strcmp(p->nodes[i].name, old_name) == 0) {
                best = i;
                same = true;
            } else {
                int64_t d = llabs((int64_t)p->nodes[i].index - old_index);
                if (d < best_d) {
                    best_d = d;
                    best = i;
                }
            }
        }
        p->sel_node = best;
        p->sel_entry = same ? find_entry(&p->nodes[best], &old_e, old_key, old_entry) : 0;
    }
    free(old_name);
    free(old_key);
}

void lg_vparams_next_node(lg_vparams *p, int dir)
{
    if (!p->n_nodes || !dir)
        return;
    const vp_node *from = &p->nodes[p->sel_node];
    const lg_vp_entry want = from->entries[p->sel_entry];
    const char *key = from->keys[p->sel_entry];
    uint32_t n = p->n_nodes;
    p->sel_node = (p->sel_node + (dir < 0 ? n - 1 : 1)) % n;
    /* the same key in the new node when it has one (stepping `exposure` from one tone
     * mapper to the next), else its first entry */
    const vp_node *to = &p->nodes[p->sel_node];
    uint32_t e = find_entry(to, &want, key, 0);
    p->sel_entry = e;
}

void lg_vparams_next_entry(lg_vparams *p, int dir)
{
    if (!p->n_nodes || !dir)
        return;
    uint32_t n = p->nodes[p->sel_node].n_entries;
    p->sel_entry = (p->sel_entry + (dir < 0 ? n - 1 : 1)) % n;
}

void lg_vparams_first_entry(lg_vparams *p)
{
    if (p && p->n_nodes)
        p->sel_entry = 0;
}

const char *lg_vparams_node(const lg_vparams *p)
{
    return p && p->n_nodes ? p->nodes[p->sel_node].name : NULL;
}

bool lg_vparams_selected(const lg_vparams *p, int32_t *node, lg_vp_entry *entry)
{
    if (!p || !p->n_nodes)
        return false;
    const vp_node *n = &p->nodes[p->sel_node];
    if (node)
        *node = n->index;
    if (entry)
        *entry = n->entries[p->sel_entry];
    return true;
}

/* ---- stepping -------------------------------------------------------------------------------- */

/* A float as --set writes it: %.9g reads back close enough for a viewer's step, and
 * %.17g (exact) when the shorter text would fall outside the range the checker holds it
 * to (a bound like 1.9999999999 rounds to 2). Never "-0". */
static void fmt_value(char out[64], double x, const lg_param_desc *pd)
{
    if (x == 0)
        x = 0;
    snprintf(out, 64, "%.9g", x);
    double back = strtod(out, NULL);
    if (has_range(pd) && (back < pd->min || back > pd->max))
        snprintf(out, 64, "%.17g", x);
}

static bool wide_or_open(const lg_param_desc *pd)
{
    return !has_range(pd) || !isfinite(pd->min) || !isfinite(pd->max) || pd->max - pd->min >= 1e4;
}

/* One float step of `v` (see the header); `what` names it in the reason. */
static int step_float(const lg_param_desc *pd, double v, int dir, double scale, double *out,
                      const char *what, char *err, size_t errlen)
{
    char b[64];
    if (!isfinite(v)) {
        set_err(err, errlen, "%s is %g: no step from a value that is not finite", what, v);
        return -1;
    }
    if (has_range(pd) && dir > 0 && v >= pd->max) {
        fmt_short(b, pd->max);
        set_err(err, errlen, "%s is at its maximum %s", what, b);
        return -1;
    }
    if (has_range(pd) && dir < 0 && v <= pd->min) {
        fmt_short(b, pd->min);
        set_err(err, errlen, "%s is at its minimum %s", what, b);
        return -1;
    }
    double step = wide_or_open(pd) ? (v != 0 ? 0.1 * fabs(v) : 0.1) : (pd->max - pd->min) / 100;
    step *= scale;
    double x = v + (dir > 0 ? step : -step);
    if (fabs(x) < 1e-9 * step) /* 2.2 - 10 x 0.22 is 0, not -4.4e-16 */
        x = 0;
    if (has_range(pd))
        x = x > pd->max ? pd->max : x < pd->min ? pd->min : x;
    if (!isfinite(x)) {
        set_err(err, errlen, "%s = %g cannot grow further (the next step overflows)", what, v);
        return -1;
    }
    *out = x;
    return 0;
}

static int64_t to_i64(double x)
{
    if (x <= -9.2233720368547758e18)
        return INT64_MIN;
    if (x >= 9.2233720368547758e18)
        return INT64_MAX;
    return (int64_t)x;
}

/* One integer step of `v`: +-1 x scale (at least 1), clamped to the range. */
static int step_int(const lg_param_desc *pd, int64_t v, int dir, double scale, int64_t *out,
                    const char *what, char *err, size_t errlen)
{
    int64_t lo = INT64_MIN, hi = INT64_MAX;
    if (has_range(pd)) {
        lo = to_i64(ceil(pd->min));
        hi = to_i64(floor(pd->max));
    }
    char b[64];
    if (dir > 0 && v >= hi) {
        fmt_short(b, has_range(pd) ? pd->max : (double)INT64_MAX);
        set_err(err, errlen, "%s is at its maximum %s", what, b);
        return -1;
    }
    if (dir < 0 && v <= lo) {
        fmt_short(b, has_range(pd) ? pd->min : (double)INT64_MIN);
        set_err(err, errlen, "%s is at its minimum %s", what, b);
        return -1;
    }
    int64_t s = scale >= 1 ? to_i64(llround(scale)) : 1;
    int64_t x;
    if (__builtin_add_overflow(v, dir > 0 ? s : -s, &x))
        x = dir > 0 ? INT64_MAX : INT64_MIN;
    *out = x > hi ? hi : x < lo ? lo : x;
    return 0;
}

/* A reference to output `port` (part `part`, 0: the whole) of node `src`, as --set reads
 * it: NODE for the only output, else NODE.PORT (or NODE.PART). */
static void add_ref(lg_str *b, const lg_cnode *src, uint32_t port, uint32_t part)
{
    lg_str_add(b, src->g->name);
    const lg_node_type *t = src->type;
    if (part) {
        const lg_kind_desc *kd = lg_kind_describe(t->outputs[port].kind);
        lg_str_addf(b, ".%s", kd->parts[part - 1].name);
    } else if (t->n_outputs > 1) {
        lg_str_addf(b, ".%s", t->outputs[port].name);
    }
}

/* Marks `from` and every node downstream of it (reading it, directly or not). The check
 * orders the nodes inputs first (c->topo): one pass in that order settles each node after
 * all its sources. */
static bool *downstream(const lg_checked *c, int32_t from)
{
    bool *mark = lg_xcalloc(c->n_nodes ? c->n_nodes : 1, sizeof *mark);
    mark[from] = true;
    for (uint32_t t = 0; t < c->n_nodes; t++) {
        uint32_t w = c->topo[t];
        const lg_cnode *cn = &c->nodes[w];
        for (uint32_t j = 0; cn->type && j < cn->type->n_inputs && !mark[w]; j++)
            if (cn->inputs[j].node >= 0 && mark[cn->inputs[j].node])
                mark[w] = true;
    }
    return mark;
}

static int cmp_ref(int32_t an, uint32_t ap, uint32_t apart, int32_t bn, uint32_t bp, uint32_t bpart)
{
    if (an != bn)
        return an < bn ? -1 : 1;
    if (ap != bp)
        return ap < bp ? -1 : 1;
    return apart < bpart ? -1 : apart > bpart ? 1 : 0;
}

static char *step_input(const lg_checked *c, int32_t ni, uint32_t ii, int dir, char *err,
                        size_t errlen)
{
    const lg_cnode *cn = &c->nodes[ni];
    const lg_port_desc *in = &cn->type->inputs[ii];
    const lg_edge cur = cn->inputs[ii];
    bool *down = downstream(c, ni);
    /* the candidates in file order; the first after (before) the current source wins, the
     * first (last) of all when none is after (before) it */
    int32_t first_n = -1, last_n = -1, pick_n = -1;
    uint32_t first_p = 0, last_p = 0, pick_p = 0;
    for (uint32_t k = 0; k < c->n_nodes; k++) {
        const lg_cnode *s = &c->nodes[k];
        if (down[k] || !s->type)
            continue;
        for (uint32_t o = 0; o < s->type->n_outputs; o++) {
            lg_resource_kind ok = s->type->outputs[o].kind;
            if (in->kind != LG_KIND_ANY && ok != LG_KIND_ANY && ok != in->kind)
                continue;
            int rel = cmp_ref((int32_t)k, o, 0, cur.node, cur.port, cur.part);
            if (first_n < 0) {
                first_n = (int32_t)k;
                first_p = o;
            }
            last_n = (int32_t)k;
            last_p = o;
            if (dir > 0 && rel > 0 && pick_n < 0) {
                pick_n = (int32_t)k;
                pick_p = o;
            }
            if (dir < 0 && rel < 0) {
                pick_n = (int32_t)k;
                pick_p = o;
            }
        }
    }
    free(down);
    if (pick_n < 0) {
        pick_n = dir > 0 ? first_n : last_n;
        pick_p = dir > 0 ? first_p : last_p;
    }
    if (pick_n < 0 || (pick_n == cur.node && pick_p == cur.port && cur.part == 0)) {
        set_err(err, errlen,
                "%s.%s has no other source: no node outside '%s' and what it "
                "feeds has an output of kind %s",
                cn->g->name, in->name, cn->g->name, lg_kind_name(in->kind));
        return NULL;
    }
    lg_str b = { 0 };
    lg_str_addf(&b, "%s.%s=", cn->g->name, in->name);
    add_ref(&b, &c->nodes[pick_n], pick_p, 0);
    return lg_str_take(&b);
}

/* The selected entry, after checking that `c` is the check it was synced with. */
static bool selection(const lg_vparams *p, const lg_graph *g, const lg_checked *c,
                      const lg_cnode **cn, lg_vp_entry *e, char *err, size_t errlen)
{
    if (!p || !p->n_nodes) {
        set_err(err, errlen, "nothing selected: no node of the graph has a value to step");
        return false;
    }
    const vp_node *n = &p->nodes[p->sel_node];
    *e = n->entries[p->sel_entry];
    if (!c || (uint32_t)n->index >= c->n_nodes || !c->nodes[n->index].type ||
        strcmp(c->nodes[n->index].g->name, n->name) != 0 ||
        (g && ((uint32_t)n->index >= g->n_nodes || strcmp(g->nodes[n->index].name, n->name))) ||
        (e->kind == LG_VP_PARAM ? e->index >= c->nodes[n->index].type->n_params
                                : e->index >= c->nodes[n->index].type->n_inputs)) {
        set_err(err, errlen,
                "the graph changed since the selection was made (node '%s'): "
                "sync first",
                n->name);
        return false;
    }
    *cn = &c->nodes[n->index];
    return true;
}

static void add_vector(lg_str *b, const lg_param_desc *pd, const lg_value *v)
{
    uint32_t nc = n_components(pd->type);
    lg_str_addc(b, '[');
    for (uint32_t k = 0; k < nc; k++) {
        char t[64];
        if (pd->type == LG_PARAM_INT3)
            snprintf(t, sizeof t, "%" PRId64, v->i3[k]);
        else
            fmt_value(t, v->v[k], pd);
        lg_str_addf(b, "%s%s", k ? ", " : "", t);
    }
    lg_str_addc(b, ']');
}

/* The colour a keyword colour turns into after its last keyword: its default colour when
 * the default is one, else the middle of its range, else white. */
static void keyword_colour(const lg_param_desc *pd, lg_value *v)
{
    for (int k = 0; k < 3; k++) {
        if (pd->def.e < 0)
            v->v[k] = pd->def.v[k];
        else if (has_range(pd) && isfinite(pd->min) && isfinite(pd->max))
            v->v[k] = 0.5 * (pd->min + pd->max);
        else
            v->v[k] = 1;
        if (has_range(pd))
            v->v[k] = v->v[k] > pd->max ? pd->max : v->v[k] < pd->min ? pd->min : v->v[k];
    }
    v->e = -1;
}

char *lg_vparams_step(const lg_vparams *p, const lg_graph *g, const lg_checked *c, int dir,
                      double scale, char *err, size_t errlen)
{
    const lg_cnode *cn;
    lg_vp_entry e;
    if (!selection(p, g, c, &cn, &e, err, errlen))
        return NULL;
    if (!(scale > 0) || !isfinite(scale)) {
        set_err(err, errlen, "step scale %g is not a positive number", scale);
        return NULL;
    }
    dir = dir < 0 ? -1 : 1;
    const char *node = cn->g->name;
    if (e.kind == LG_VP_INPUT)
        return step_input(c, (int32_t)(cn - c->nodes), e.index, dir, err, errlen);

    const lg_param_desc *pd = &cn->type->params[e.index];
    lg_value v = cn->params[e.index];
    char what[256], t[64];
    if (e.component >= 0)
        snprintf(what, sizeof what, "%s.%s[%d]", node, pd->key, e.component);
    else
        snprintf(what, sizeof what, "%s.%s", node, pd->key);
    lg_str b = { 0 };
    lg_str_addf(&b, "%s.%s=", node, pd->key);

    switch (pd->type) {
    case LG_PARAM_BOOL: lg_str_add(&b, v.b ? "false" : "true"); return lg_str_take(&b);
    case LG_PARAM_INT: {
        int64_t x;
        if (step_int(pd, v.i, dir, scale, &x, what, err, errlen) != 0)
            goto fail;
        lg_str_addf(&b, "%" PRId64, x);
        return lg_str_take(&b);
    }
    case LG_PARAM_FLOAT:
        if (step_float(pd, v.f, dir, scale, &v.f, what, err, errlen) != 0)
            goto fail;
        fmt_value(t, v.f, pd);
        lg_str_add(&b, t);
        return lg_str_take(&b);
    case LG_PARAM_ENUM: {
        uint32_t nv = n_enum(pd);
        if (nv < 2) {
            set_err(err, errlen, "%s has no other value than '%s'", what,
                    nv ? pd->enum_values[0] : "");
            goto fail;
        }
        uint32_t cur = v.e >= 0 && (uint32_t)v.e < nv ? (uint32_t)v.e : 0;
        lg_str_add(&b, pd->enum_values[(cur + (dir > 0 ? 1 : nv - 1)) % nv]);
        return lg_str_take(&b);
    }
    case LG_PARAM_VEC2:
    case LG_PARAM_VEC3:
    case LG_PARAM_COLOR:
    case LG_PARAM_INT3: break;
    default: set_err(err, errlen, "%s is not a value the viewer steps", what); goto fail;
    }

    bool keywords = pd->type == LG_PARAM_COLOR && pd->enum_values;
    uint32_t nv = keywords ? n_enum(pd) : 0;
    if (keywords && e.component < 0) {
        /* keywords 0..nv-1, then a colour (position nv), cyclic */
        uint32_t pos = v.e >= 0 && (uint32_t)v.e < nv ? (uint32_t)v.e : nv;
        uint32_t next = (pos + (dir > 0 ? 1 : nv)) % (nv + 1);
        if (next < nv) {
            lg_str_add(&b, pd->enum_values[next]);
        } else {
            keyword_colour(pd, &v);
            add_vector(&b, pd, &v);
        }
        return lg_str_take(&b);
    }
    if (keywords && v.e >= 0) {
        set_err(err, errlen,
                "%s.%s is the keyword '%s', not a colour: step %s.%s itself to "
                "turn it into one",
                node, pd->key, (uint32_t)v.e < nv ? pd->enum_values[v.e] : "?", node, pd->key);
        goto fail;
    }
    if (e.component < 0 || (uint32_t)e.component >= n_components(pd->type)) {
        set_err(err, errlen, "%s has no component %d", what, e.component);
        goto fail;
    }
    if (pd->type == LG_PARAM_INT3) {
        if (step_int(pd, v.i3[e.component], dir, scale, &v.i3[e.component], what, err, errlen) != 0)
            goto fail;
    } else if (step_float(pd, v.v[e.component], dir, scale, &v.v[e.component], what, err, errlen) !=
               0) {
        goto fail;
    }
    add_vector(&b, pd, &v);
    return lg_str_take(&b);
fail:
    lg_str_free(&b);
    return NULL;
}

/* ---- the overlay line ------------------------------------------------------------------------ */

static void add_range(lg_str *out, const lg_param_desc *pd)
{
    if (!has_range(pd))
        return;
    char lo[64], hi[64];
    fmt_short(lo, pd->min);
    fmt_short(hi, pd->max);
    lg_str_addf(out, "  [%s, %s]", lo, hi);
}

static void add_display(lg_str *out, double x)
{
    lg_str_addf(out, "%.6g", x == 0 ? 0 : x);
}

static void add_display_vector(lg_str *out, const lg_param_desc *pd, const lg_value *v)
{
    lg_str_addc(out, '[');
    for (uint32_t k = 0; k < n_components(pd->type); k++) {
        if (k)
            lg_str_add(out, ", ");
        if (pd->type == LG_PARAM_INT3)
            lg_str_addf(out, "%" PRId64, v->i3[k]);
        else
            add_display(out, v->v[k]);
    }
    lg_str_addc(out, ']');
}

void lg_vparams_describe(const lg_vparams *p, const lg_checked *c, lg_str *out)
{
    const lg_cnode *cn;
    lg_vp_entry e;
    char err[256];
    if (!p || !p->n_nodes) {
        lg_str_add(out, "nothing to edit");
        return;
    }
    if (!selection(p, NULL, c, &cn, &e, err, sizeof err)) {
        lg_str_add(out, err);
        return;
    }
    const vp_node *n = &p->nodes[p->sel_node];
    lg_str_addf(out, "%s (%s) %u/%u  ", n->name, cn->type->name, p->sel_entry + 1, n->n_entries);
    if (e.kind == LG_VP_INPUT) {
        const lg_port_desc *in = &cn->type->inputs[e.index];
        const lg_edge *ed = &cn->inputs[e.index];
        lg_str_addf(out, "%s <- ", in->name);
        if (ed->node >= 0)
            add_ref(out, &c->nodes[ed->node], ed->port, ed->part);
        lg_str_addf(out, "  (%s)", lg_kind_name(in->kind));
        return;
    }
    const lg_param_desc *pd = &cn->type->params[e.index];
    const lg_value *v = &cn->params[e.index];
    const char *dflt = cn->param_set[e.index] ? "" : " (default)";
    bool keywords = pd->type == LG_PARAM_COLOR && pd->enum_values;
    if (e.component >= 0) {
        lg_str_addf(out, "%s[%d] = ", pd->key, e.component);
        if (keywords && v->e >= 0) {
            lg_str_addf(out, "(the keyword %s)%s", pd->enum_values[v->e], dflt);
            return;
        }
        if (pd->type == LG_PARAM_INT3)
            lg_str_addf(out, "%" PRId64, v->i3[e.component]);
        else
            add_display(out, v->v[e.component]);
        lg_str_add(out, " of ");
        add_display_vector(out, pd, v);
        lg_str_add(out, dflt);
        add_range(out, pd);
        return;
    }
    lg_str_addf(out, "%s = ", pd->key);
    switch (pd->type) {
    case LG_PARAM_BOOL:
        lg_str_addf(out, "%s%s  {false true}", v->b ? "true" : "false", dflt);
        return;
    case LG_PARAM_INT:
        lg_str_addf(out, "%" PRId64 "%s", v->i, dflt);
        add_range(out, pd);
        return;
    case LG_PARAM_FLOAT:
        add_display(out, v->f);
        lg_str_add(out, dflt);
        add_range(out, pd);
        return;
    case LG_PARAM_ENUM:
    case LG_PARAM_COLOR: {
        if (pd->type == LG_PARAM_ENUM)
            lg_str_add(out, v->s ? v->s : "?");
        else if (v->e >= 0)
            lg_str_add(out, pd->enum_values[v->e]);
        else
            add_display_vector(out, pd, v);
        lg_str_addf(out, "%s  {", dflt);
        for (uint32_t k = 0; k < n_enum(pd); k++)
            lg_str_addf(out, "%s%s", k ? " " : "", pd->enum_values[k]);
        lg_str_add(out, pd->type == LG_PARAM_COLOR ? " [r, g, b]}" : "}");
        return;
    }
    default: lg_str_add(out, "?");
    }
}

/* ---- method switching ------------------------------------------------------------------------ */

static bool same_value(const lg_param_desc *pd, const lg_value *a, const lg_value *b)
{
    switch (pd->type) {
    case LG_PARAM_BOOL: return a->b == b->b;
    case LG_PARAM_INT: return a->i == b->i;
    case LG_PARAM_FLOAT: return a->f == b->f;
    case LG_PARAM_VEC2:
    case LG_PARAM_VEC3:
    case LG_PARAM_COLOR:
        return a->e == b->e && memcmp(a->v, b->v, n_components(pd->type) * sizeof a->v[0]) == 0;
    case LG_PARAM_INT3: return memcmp(a->i3, b->i3, sizeof a->i3) == 0;
    case LG_PARAM_ENUM: return a->e == b->e;
    case LG_PARAM_STRING:
    case LG_PARAM_PATH: return strcmp(a->s ? a->s : "", b->s ? b->s : "") == 0;
    case LG_PARAM_PATH_LIST: {
        if (a->e != b->e)
            return false;
        const char *x = a->s, *y = b->s;
        for (int32_t k = 0; k < a->e; k++) {
            if (strcmp(x, y) != 0)
                return false;
            x += strlen(x) + 1;
            y += strlen(y) + 1;
        }
        return true;
    }
    default: return false;
    }
}

/* The output of `t` called `name`, or -1. */
static int32_t output_named(const lg_node_type *t, const char *name)
{
    for (uint32_t o = 0; o < t->n_outputs; o++)
        if (strcmp(t->outputs[o].name, name) == 0)
            return (int32_t)o;
    return -1;
}

/* Does node `from` read node `to`, directly or through other nodes? */
static bool reads_node(const lg_checked *c, uint32_t from, uint32_t to, uint32_t depth)
{
    const lg_cnode *n = &c->nodes[from];
    if (!n->type || depth > c->n_nodes)
        return false;
    for (uint32_t j = 0; j < n->type->n_inputs; j++) {
        int32_t s = n->inputs[j].node;
        if (s >= 0 && ((uint32_t)s == to || reads_node(c, (uint32_t)s, to, depth + 1)))
            return true;
    }
    return false;
}

static bool alternatives(const lg_checked *c, uint32_t x, uint32_t y)
{
    const lg_cnode *a = &c->nodes[x], *b = &c->nodes[y];
    if (x == y || !a->type || !b->type || !a->type->n_outputs || !b->type->n_outputs)
        return false;
    /* the same outputs: the first output of each is the other's too, every output both have
     * is of one kind, and every output of x that a node reads, y has (froxel's extra `grid`
     * does not keep it from being the polygonal method's alternative, unless it is read) */
    if (output_named(b->type, a->type->outputs[0].name) < 0 ||
        output_named(a->type, b->type->outputs[0].name) < 0)
        return false;
    for (uint32_t o = 0; o < a->type->n_outputs; o++) {
        int32_t ob = output_named(b->type, a->type->outputs[o].name);
        if (ob >= 0 && b->type->outputs[ob].kind != a->type->outputs[o].kind)
            return false;
        if (ob >= 0)
            continue;
        for (uint32_t k = 0; k < c->n_nodes; k++) {
            const lg_cnode *r = &c->nodes[k];
            for (uint32_t j = 0; r->type && j < r->type->n_inputs; j++)
                if (r->inputs[j].node == (int32_t)x && r->inputs[j].port == o)
                    return false;
        }
    }
    /* the same sources: every input both types have and both connect reads the same edge,
     * and there is at least one (two scene loaders are not alternatives). An input only one
     * of them has is free: the screen-space method reads no shadow maps and is still the
     * froxel method's alternative. */
    uint32_t shared = 0;
    for (uint32_t i = 0; i < a->type->n_inputs; i++) {
        lg_edge ea = a->inputs[i];
        for (uint32_t j = 0; j < b->type->n_inputs; j++) {
            if (strcmp(a->type->inputs[i].name, b->type->inputs[j].name) != 0)
                continue;
            lg_edge eb = b->inputs[j];
            if ((ea.node >= 0) != (eb.node >= 0))
                return false;
            if (ea.node < 0)
                continue;
            if (ea.node != eb.node || ea.port != eb.port || ea.part != eb.part)
                return false;
            shared++;
        }
    }
    /* siblings, not a node and one it is made from (phong's lit image is not an
     * alternative of the fog drawn over it) */
    if (shared == 0 || reads_node(c, x, y, 0) || reads_node(c, y, x, 0))
        return false;
    /* a twin (same type, same values) is the same method, not another */
    bool differ = strcmp(a->type->name, b->type->name) != 0;
    for (uint32_t j = 0; !differ && j < a->type->n_params; j++)
        differ = !same_value(&a->type->params[j], &a->params[j], &b->params[j]);
    return differ;
}

/* The reference to output `port` (part `part`) of `y` that stands where one to X was, or
 * NULL when a part reference would not resolve to that output (NODE.PART names the first
 * output of its kind that has the part). */
static char *switched_ref(const lg_checked *c, int32_t y, uint32_t port, uint32_t part)
{
    const lg_node_type *t = c->nodes[y].type;
    if (part) {
        const lg_kind_desc *kd = lg_kind_describe(t->outputs[port].kind);
        const char *pn = kd->parts[part - 1].name;
        if (output_named(t, pn) >= 0)
            return NULL;
        for (uint32_t o = 0; o < port; o++)
            if (lg_kind_part_index(t->outputs[o].kind, pn) >= 0)
                return NULL;
    }
    lg_str b = { 0 };
    lg_str_add(&b, c->nodes[y].g->name);
    if (part)
        lg_str_addf(&b, ".%s", lg_kind_describe(t->outputs[port].kind)->parts[part - 1].name);
    else if (t->n_outputs > 1)
        lg_str_addf(&b, ".%s", t->outputs[port].name);
    return lg_str_take(&b);
}

int lg_vparams_switch_method(const lg_graph *g, const lg_checked *c, int32_t shown, int dir,
                             char ***assignments, uint32_t *n, int32_t *switched_from,
                             int32_t *switched_to, int32_t *new_shown, char *err, size_t errlen)
{
    (void)g;
    *assignments = NULL;
    *n = 0;
    *switched_from = *switched_to = *new_shown = -1;
    if (!c || shown < 0 || (uint32_t)shown >= c->n_nodes) {
        set_err(err, errlen, "no node is shown (index %d of %u nodes)", (int)shown,
                c ? c->n_nodes : 0);
        return 0;
    }
    /* breadth first upstream of `shown`, itself first, inputs in their order */
    bool *seen = lg_xcalloc(c->n_nodes, sizeof *seen);
    int32_t *queue = lg_xmalloc(c->n_nodes * sizeof *queue);
    uint32_t head = 0, tail = 0, walked = 0;
    int32_t x = -1;
    seen[shown] = true;
    queue[tail++] = shown;
    while (head < tail && x < 0) {
        int32_t u = queue[head++];
        walked++;
        for (uint32_t k = 0; k < c->n_nodes && x < 0; k++)
            if (alternatives(c, (uint32_t)u, k))
                x = u;
        const lg_cnode *cn = &c->nodes[u];
        for (uint32_t j = 0; cn->type && j < cn->type->n_inputs; j++) {
            int32_t s = cn->inputs[j].node;
            if (s >= 0 && !seen[s]) {
                seen[s] = true;
                queue[tail++] = s;
            }
        }
    }
    free(seen);
    free(queue);
    const char *shown_name = c->nodes[shown].g->name;
    if (x < 0) {
        set_err(err, errlen,
                "no node upstream of '%s' has an alternative: none of the %u "
                "node(s) it is made from (itself included) has another node beside it with "
                "the same outputs reading the same sources",
                shown_name, walked);
        return 0;
    }

    /* X and its alternatives in file order; Y is the next (previous) after X, cyclic */
    int32_t y = -1, first = -1, last = -1;
    for (uint32_t k = 0; k < c->n_nodes; k++) {
        if (!alternatives(c, (uint32_t)x, k))
            continue;
        if (first < 0)
            first = (int32_t)k;
        last = (int32_t)k;
        if (dir >= 0 && (int32_t)k > x && y < 0)
            y = (int32_t)k;
        if (dir < 0 && (int32_t)k < x)
            y = (int32_t)k;
    }
    if (y < 0)
        y = dir >= 0 ? first : last;

    const lg_node_type *tx = c->nodes[x].type, *ty = c->nodes[y].type;
    char **out = NULL;
    uint32_t m = 0;
    for (uint32_t k = 0; k < c->n_nodes; k++) {
        const lg_cnode *cn = &c->nodes[k];
        for (uint32_t j = 0; cn->type && j < cn->type->n_inputs; j++) {
            const lg_edge *e = &cn->inputs[j];
            if (e->node != x)
                continue;
            uint32_t py = (uint32_t)output_named(ty, tx->outputs[e->port].name);
            char *ref = switched_ref(c, y, py, e->part);
            if (!ref) {
                set_err(err, errlen,
                        "cannot rewire %s.%s from '%s' to '%s': the part it reads "
                        "has no reference of its own on '%s'",
                        cn->g->name, cn->type->inputs[j].name, c->nodes[x].g->name,
                        c->nodes[y].g->name, c->nodes[y].g->name);
                for (uint32_t q = 0; q < m; q++)
                    free(out[q]);
                free(out);
                return 0;
            }
            out = lg_xrealloc(out, (m + 1) * sizeof *out);
            out[m++] = lg_xasprintf("%s.%s=%s", cn->g->name, cn->type->inputs[j].name, ref);
            free(ref);
        }
    }
    *assignments = out;
    *n = m;
    *switched_from = x;
    *switched_to = y;
    *new_shown = x == shown ? y : -1;
    return 1;
}

int lg_vparams_passthrough(const lg_checked *c, int32_t x, uint32_t port, lg_edge *src)
{
    if (!c || x < 0 || (uint32_t)x >= c->n_nodes || !c->nodes[x].type ||
        port >= c->nodes[x].type->n_outputs)
        return 0;
    const lg_cnode *cx = &c->nodes[x];
    lg_resource_kind kind = cx->type->outputs[port].kind;
    for (uint32_t j = 0; j < cx->type->n_inputs; j++) {
        lg_edge e = cx->inputs[j];
        if (e.node < 0 || e.part || !c->nodes[e.node].type)
            continue;
        if (c->nodes[e.node].type->outputs[e.port].kind == kind) {
            *src = e;
            return 1;
        }
    }
    return 0;
}

char *lg_vparams_edge_ref(const lg_checked *c, lg_edge e)
{
    if (!c || e.node < 0 || (uint32_t)e.node >= c->n_nodes)
        return NULL;
    return switched_ref(c, e.node, e.port, e.part);
}

int32_t lg_vparams_alternative_end(const lg_checked *c, int32_t x, int dir)
{
    int32_t end = x;
    for (uint32_t k = 0; c && x >= 0 && k < c->n_nodes; k++) {
        if ((int32_t)k != x && !alternatives(c, (uint32_t)x, k))
            continue;
        if (dir >= 0 && (int32_t)k < end)
            end = (int32_t)k;
        if (dir < 0 && (int32_t)k > end)
            end = (int32_t)k;
    }
    return end;
}

/* ---- overrides ------------------------------------------------------------------------------- */

struct lg_override_undo {
    uint32_t index; /* the item the set added or replaced */
    char *prev;     /* what it replaced (owned), or NULL when it added the item */
};

/* The key of an assignment: the text before the first '=', spaces around it left out. */
static void key_span(const char *a, const char **k, size_t *len)
{
    while (*a == ' ' || *a == '\t')
        a++;
    const char *eq = strchr(a, '=');
    size_t n = eq ? (size_t)(eq - a) : strlen(a);
    while (n && (a[n - 1] == ' ' || a[n - 1] == '\t'))
        n--;
    *k = a;
    *len = n;
}

void lg_overrides_set(lg_overrides *o, const char *assignment)
{
    const char *k;
    size_t kl;
    key_span(assignment, &k, &kl);
    struct lg_override_undo u = { .index = o->n, .prev = NULL };
    for (uint32_t i = 0; i < o->n; i++) {
        const char *ik;
        size_t il;
        key_span(o->items[i], &ik, &il);
        if (il == kl && memcmp(ik, k, kl) == 0) {
            u.index = i;
            u.prev = o->items[i];
            break;
        }
    }
    if (u.prev) {
        o->items[u.index] = lg_xstrdup(assignment);
    } else {
        if (o->n == o->cap) {
            o->cap = o->cap ? 2 * o->cap : 8;
            o->items = lg_xrealloc(o->items, o->cap * sizeof *o->items);
        }
        o->items[o->n++] = lg_xstrdup(assignment);
    }
    /* the undo history keeps the last LG_OVERRIDES_UNDO sets: the oldest is forgotten */
    if (o->n_undo == LG_OVERRIDES_UNDO) {
        free(o->undo[0].prev);
        memmove(o->undo, o->undo + 1, (o->n_undo - 1) * sizeof *o->undo);
        o->n_undo--;
    }
    if (o->n_undo == o->cap_undo) {
        o->cap_undo = o->cap_undo ? 2 * o->cap_undo : 8;
        o->undo = lg_xrealloc(o->undo, o->cap_undo * sizeof *o->undo);
    }
    o->undo[o->n_undo++] = u;
}

void lg_overrides_remove_last(lg_overrides *o)
{
    if (!o->n_undo)
        return;
    struct lg_override_undo u = o->undo[--o->n_undo];
    if (u.index >= o->n) { /* cannot happen while sets are undone newest first */
        free(u.prev);
        return;
    }
    free(o->items[u.index]);
    if (u.prev) {
        o->items[u.index] = u.prev;
    } else {
        memmove(o->items + u.index, o->items + u.index + 1,
                (o->n - u.index - 1) * sizeof *o->items);
        o->n--;
    }
}

static bool shell_safe(const char *s)
{
    if (!*s)
        return false;
    for (const char *q = s; *q; q++) {
        char ch = *q;
        if (!((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
              strchr("_.,=/:+@%-", ch)))
            return false;
    }
    return true;
}

char *lg_overrides_args(const lg_overrides *o)
{
    lg_str b = { 0 };
    for (uint32_t i = 0; i < o->n; i++) {
        const char *s = o->items[i];
        lg_str_add(&b, i ? " --set " : "--set ");
        if (shell_safe(s)) {
            lg_str_add(&b, s);
            continue;
        }
        /* single quotes keep everything as it is but a single quote: end the quoted
         * part, add an escaped quote, start another */
        lg_str_addc(&b, '\'');
        for (const char *q = s; *q; q++) {
            if (*q == '\'')
                lg_str_add(&b, "'\\''");
            else
                lg_str_addc(&b, *q);
        }
        lg_str_addc(&b, '\'');
    }
    return lg_str_take(&b);
}

void lg_overrides_free(lg_overrides *o)
{
    for (uint32_t i = 0; i < o->n; i++)
        free(o->items[i]);
    for (uint32_t i = 0; i < o->n_undo; i++)
        free(o->undo[i].prev);
    free(o->items);
    free(o->undo);
    memset(o, 0, sizeof *o);
}
