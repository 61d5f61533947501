/*
 * host/graph/check.c: lg_graph + node type schemas -> lg_checked (docs/graph-format.md,
 * "Checking").
 *
 * Per node: look the type up; map every entry to a parameter or an input (renamed keys
 * warn; a --set value wins over the file's); then convert the surviving values, so that
 * an overridden entry is never judged. Defaults fill the rest. Edges are resolved after
 * every type is known, so references may point forward. Cycles are found with Tarjan's
 * strongly connected components (iterative: no recursion on user data), and each is
 * reported once, by the shortest cycle through its first node in file order.
 */
#include "graph/graph.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"
#include "base/pattern.h"
#include "lightgraph/kinds.h"

/* After this many errors the checker goes on (to fail) but reports nothing more and stops
 * looking for suggestions, which would otherwise cost (errors x names). */
#define MAX_ERRORS 100

typedef struct checker {
    const lg_graph *g;
    const lg_schema *sc;
    lg_diags *d;
    lg_checked *c;
    uint32_t errors;
    bool stop;
    const char **node_names;
} checker;

static void diag(checker *k, lg_diag_level lvl, lg_srcloc loc, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void diag(checker *k, lg_diag_level lvl, lg_srcloc loc, const char *fmt, ...)
{
    if (lvl == LG_DIAG_ERROR)
        k->errors++;
    if (k->stop)
        return;
    va_list ap;
    va_start(ap, fmt);
    char *msg = lg_vformat(fmt, ap);
    va_end(ap);
    lg_graph_diag(k->d, k->g, lvl, loc, "%s", msg);
    free(msg);
    if (k->errors >= MAX_ERRORS) {
        lg_srcloc none = { loc.file, 0, 0, 0 };
        lg_graph_diag(k->d, k->g, LG_DIAG_NOTE, none, "too many errors (%u); stopping here",
                      k->errors);
        k->stop = true;
    }
}

static void enum_list(lg_str *b, const lg_param_desc *pd)
{
    for (uint32_t i = 0; pd->enum_values && pd->enum_values[i]; i++)
        lg_str_addf(b, "%s%s", i ? ", " : "", pd->enum_values[i]);
}

/* "a float", "one of cpu, gl, cl", ... */
static char *expected_name(const lg_param_desc *pd)
{
    lg_str b = { 0 };
    switch (pd->type) {
    case LG_PARAM_BOOL: lg_str_add(&b, "a boolean (true or false)"); break;
    case LG_PARAM_INT: lg_str_add(&b, "an integer"); break;
    case LG_PARAM_FLOAT: lg_str_add(&b, "a float"); break;
    case LG_PARAM_VEC2: lg_str_add(&b, "a list of 2 numbers"); break;
    case LG_PARAM_VEC3: lg_str_add(&b, "a list of 3 numbers"); break;
    case LG_PARAM_COLOR:
        if (pd->enum_values) { /* keywords (ABI 2.3) */
            lg_str_add(&b, "a colour [r, g, b] or one of: ");
            enum_list(&b, pd);
        } else {
            lg_str_add(&b, "a colour (a list of 3 numbers)");
        }
        break;
    case LG_PARAM_STRING: lg_str_add(&b, "a string"); break;
    case LG_PARAM_PATH: lg_str_add(&b, "a file path (a string)"); break;
    case LG_PARAM_INT3: lg_str_add(&b, "a list of 3 integers"); break;
    case LG_PARAM_PATH_LIST: lg_str_add(&b, "a list of file paths (strings)"); break;
    case LG_PARAM_ENUM:
        lg_str_add(&b, "one of ");
        enum_list(&b, pd);
        break;
    default: lg_str_add(&b, "a value of an unknown type"); break;
    }
    return lg_str_take(&b);
}

/* "a string", "a reference 'src.out'", ... */
static char *found_name(const lg_gvalue *v)
{
    switch (v->kind) {
    case LG_GV_BOOL: return lg_xstrdup("a boolean");
    case LG_GV_INT: return lg_xstrdup("an integer");
    case LG_GV_FLOAT: return lg_xstrdup("a float");
    case LG_GV_STRING: return lg_xstrdup("a string");
    case LG_GV_LIST:
        return lg_xasprintf("a list of %u item%s", v->n_items, v->n_items == 1 ? "" : "s");
    case LG_GV_IDENT:
        return v->port ? lg_xasprintf("a reference '%s.%s'", v->s, v->port)
                       : lg_xasprintf("a reference '%s'", v->s);
    default: return lg_xasprintf("'%s'", v->text ? v->text : "");
    }
}

static bool is_nonfinite_word(const char *s)
{
    static const char *const words[] = { "inf", "infinity", "nan" };
    for (size_t i = 0; i < 3; i++)
        if (strcasecmp(s, words[i]) == 0)
            return true;
    return false;
}

/* A value of the wrong kind: "expected a float, found a string (parameter 'key' of node
 * 'tone')", with a hint where one helps. */
static void type_error(checker *k, const lg_gnode *n, const lg_param_desc *pd, const char *what,
                       const lg_gvalue *v, const char *expect)
{
    char *e = expect ? lg_xstrdup(expect) : expected_name(pd);
    char *f = found_name(v);
    const char *hint = "";
    char hintbuf[160] = "";
    if (v->kind == LG_GV_IDENT && !v->port && is_nonfinite_word(v->s) &&
        (pd->type != LG_PARAM_STRING && pd->type != LG_PARAM_PATH && pd->type != LG_PARAM_ENUM)) {
        free(f);
        f = lg_xasprintf("'%s'", v->s);
        hint = "; only finite numbers are allowed";
    } else if (v->kind == LG_GV_IDENT &&
               (pd->type == LG_PARAM_STRING || pd->type == LG_PARAM_PATH)) {
        snprintf(hintbuf, sizeof hintbuf, "; strings are written in quotes: \"%.60s%s%.60s\"", v->s,
                 v->port ? "." : "", v->port ? v->port : "");
        hint = hintbuf;
    } else if (v->kind == LG_GV_FLOAT && !expect && pd->type == LG_PARAM_INT &&
               v->f == floor(v->f) && fabs(v->f) < 9e15) {
        snprintf(hintbuf, sizeof hintbuf, "; write %.0f for an integer", v->f);
        hint = hintbuf;
    }
    diag(k, LG_DIAG_ERROR, v->loc, "expected %s, found %s (%s of node '%s')%s", e, f, what, n->name,
         hint);
    free(e);
    free(f);
}

static bool as_number(const lg_gvalue *v, double *out)
{
    if (v->kind == LG_GV_INT) {
        *out = (double)v->i;
        return true;
    }
    if (v->kind == LG_GV_FLOAT) {
        *out = v->f;
        return true;
    }
    return false;
}

static bool in_range(const lg_param_desc *pd, double x)
{
    return pd->min == pd->max || (x >= pd->min && x <= pd->max);
}

static void range_error(checker *k, const lg_param_desc *pd, const char *name, const lg_gvalue *v)
{
    char lo[64], hi[64];
    lg_format_shortest(lo, pd->min, 1e15, false);
    lg_format_shortest(hi, pd->max, 1e15, false);
    diag(k, LG_DIAG_ERROR, v->loc, "%s = %s is out of range [%s, %s]", name, v->text, lo, hi);
}

/* A --set value, read the way the parameter's type wants it. `textual` types take the
 * text as it is unless it is quoted. Returns NULL after reporting. */
static const lg_gvalue *resolve_raw(checker *k, const lg_gnode *n, const lg_param_desc *pd,
                                    const char *what, const lg_gvalue *v, bool textual,
                                    lg_gvalue *tmp)
{
    if (v->kind != LG_GV_RAW)
        return v;
    if (v->n_items == 1 && (!textual || v->items[0].kind == LG_GV_STRING))
        return &v->items[0];
    if (textual && v->text[0] != '"') {
        *tmp = *v;
        tmp->kind = LG_GV_STRING;
        tmp->s = v->text;
        tmp->n_items = 0;
        tmp->items = NULL;
        return tmp;
    }
    char *e = pd ? expected_name(pd) : lg_xstrdup("a reference to a node (NODE or NODE.PORT)");
    diag(k, LG_DIAG_ERROR, v->loc, "expected %s, found '%s' (%s of node '%s'%s%s)", e, v->text,
         what, n->name, v->s ? ": " : "", v->s ? v->s : "");
    free(e);
    return NULL;
}

static char *resolve_path(const char *base_dir, const char *s)
{
    if (!s[0])
        return lg_xstrdup("");
    char *j = lg_path_join(base_dir, s);
    char *a = lg_path_absolute(j);
    free(j);
    return a;
}

/* A word for an enum, or for a colour that also takes keywords: its index in out->e (and
 * for an enum its name in out->s); reports and returns false when it is not one of them. */
static bool convert_keyword(checker *k, const lg_gnode *n, const lg_param_desc *pd,
                            const lg_gvalue *v, lg_value *out)
{
    uint32_t nv = 0;
    while (pd->enum_values && pd->enum_values[nv])
        nv++;
    for (uint32_t i = 0; i < nv; i++) {
        if (strcmp(v->s, pd->enum_values[i]) == 0) {
            out->e = (int32_t)i;
            if (pd->type == LG_PARAM_ENUM)
                out->s = lg_xstrdup(pd->enum_values[i]);
            return true;
        }
    }
    lg_str b = { 0 };
    enum_list(&b, pd);
    const char *one_of = pd->type == LG_PARAM_COLOR ? "a colour [r, g, b] or one of: " : "one of ";
    const char *sug = lg_suggest(v->s, (const char *const *)pd->enum_values, nv);
    if (sug)
        diag(k, LG_DIAG_ERROR, v->loc,
             "'%s' is not %s%s (parameter '%s' of node '%s'); "
             "did you mean '%s'?",
             v->s, one_of, b.s ? b.s : "", pd->key, n->name, sug);
    else
        diag(k, LG_DIAG_ERROR, v->loc, "'%s' is not %s%s (parameter '%s' of node '%s')", v->s,
             one_of, b.s ? b.s : "", pd->key, n->name);
    lg_str_free(&b);
    return false;
}

/* Converts one parameter value; reports and returns false when it does not fit. */
static bool convert_param(checker *k, const lg_gnode *n, const lg_param_desc *pd,
                          const lg_gvalue *v0, lg_value *out)
{
    char what[160];
    snprintf(what, sizeof what, "parameter '%s'", pd->key);
    bool textual = pd->type == LG_PARAM_STRING || pd->type == LG_PARAM_PATH ||
                   pd->type == LG_PARAM_ENUM;
    lg_gvalue tmp;
    const lg_gvalue *v = resolve_raw(k, n, pd, what, v0, textual, &tmp);
    if (!v)
        return false;
    memset(out, 0, sizeof *out);
    out->type = pd->type;
    double x;
    switch (pd->type) {
    case LG_PARAM_BOOL:
        if (v->kind != LG_GV_BOOL)
            goto wrong;
        out->b = v->b;
        return true;
    case LG_PARAM_INT:
        if (v->kind != LG_GV_INT)
            goto wrong;
        if (!in_range(pd, (double)v->i)) {
            range_error(k, pd, pd->key, v);
            return false;
        }
        out->i = v->i;
        return true;
    case LG_PARAM_FLOAT:
        if (!as_number(v, &x))
            goto wrong;
        if (!in_range(pd, x)) {
            range_error(k, pd, pd->key, v);
            return false;
        }
        out->f = x;
        return true;
    case LG_PARAM_COLOR:
        if (pd->enum_values) {
            /* a colour that also takes keywords (ABI 2.3): e = -1 for a colour, else the
             * keyword's index with v zero */
            out->e = -1;
            if (v->kind == LG_GV_STRING || (v->kind == LG_GV_IDENT && !v->port))
                return convert_keyword(k, n, pd, v, out);
        }
        /* fall through */
    case LG_PARAM_VEC2:
    case LG_PARAM_VEC3:
    case LG_PARAM_INT3: {
        uint32_t want = pd->type == LG_PARAM_VEC2 ? 2 : 3;
        if (v->kind != LG_GV_LIST || v->n_items != want)
            goto wrong;
        bool ok = true;
        for (uint32_t i = 0; i < want; i++) {
            lg_gitem tmpi;
            const lg_gvalue *it = lg_glist_item(v, i, &tmpi, true);
            char name[160];
            snprintf(name, sizeof name, "%s[%u]", pd->key, i);
            char itwhat[200];
            snprintf(itwhat, sizeof itwhat, "item %u of parameter '%s'", i, pd->key);
            if (pd->type == LG_PARAM_INT3) {
                if (it->kind != LG_GV_INT) {
                    lg_param_desc ip = *pd;
                    ip.type = LG_PARAM_INT;
                    type_error(k, n, &ip, itwhat, it, NULL);
                    ok = false;
                    continue;
                }
                x = (double)it->i;
                out->i3[i] = it->i;
            } else {
                if (!as_number(it, &x)) {
                    type_error(k, n, pd, itwhat, it, "a number");
                    ok = false;
                    continue;
                }
                out->v[i] = x;
            }
            if (!in_range(pd, x)) {
                range_error(k, pd, name, it);
                ok = false;
            }
        }
        return ok;
    }
    case LG_PARAM_STRING:
        if (v->kind != LG_GV_STRING)
            goto wrong;
        out->s = lg_xstrdup(v->s);
        return true;
    case LG_PARAM_PATH:
        if (v->kind != LG_GV_STRING)
            goto wrong;
        out->s = resolve_path(v->base_dir, v->s);
        return true;
    case LG_PARAM_PATH_LIST: {
        /* ["a", "b", ...]: each item a string, resolved like a PATH against the file (or
         * the current directory for --set) that wrote it; packed "a\0b\0" (lg_value) */
        if (v->kind != LG_GV_LIST)
            goto wrong;
        lg_str packed = { 0 };
        bool ok = true;
        for (uint32_t i = 0; i < v->n_items; i++) {
            lg_gitem tmpi;
            const lg_gvalue *it = lg_glist_item(v, i, &tmpi, true);
            if (it->kind != LG_GV_STRING) {
                char itwhat[200];
                snprintf(itwhat, sizeof itwhat, "item %u of parameter '%s'", i, pd->key);
                type_error(k, n, pd, itwhat, it, "a file path (a string)");
                ok = false;
                continue;
            }
            if (!it->s[0]) {
                diag(k, LG_DIAG_ERROR, it->loc,
                     "item %u of parameter '%s' of node '%s' is an "
                     "empty path",
                     i, pd->key, n->name);
                ok = false;
                continue;
            }
            char *path = resolve_path(it->base_dir ? it->base_dir : v->base_dir, it->s);
            lg_str_add(&packed, path);
            lg_str_addn(&packed, "", 1);
            free(path);
        }
        if (!ok) {
            lg_str_free(&packed);
            return false;
        }
        out->e = (int32_t)v->n_items;
        out->s = packed.s ? lg_str_take(&packed) : lg_xstrdup("");
        return true;
    }
    case LG_PARAM_ENUM: {
        if (!(v->kind == LG_GV_STRING || (v->kind == LG_GV_IDENT && !v->port)))
            goto wrong;
        return convert_keyword(k, n, pd, v, out);
    }
    default:
        diag(k, LG_DIAG_ERROR, v->loc,
             "parameter '%s' of node '%s' has an unknown type (%d) in "
             "its plugin's schema",
             pd->key, n->name, (int)pd->type);
        return false;
    }
wrong:
    type_error(k, n, pd, what, v, NULL);
    return false;
}

static void default_param(const lg_param_desc *pd, lg_value *out)
{
    *out = pd->def;
    out->type = pd->type;
    if (pd->type == LG_PARAM_ENUM) {
        uint32_t nv = 0;
        while (pd->enum_values && pd->enum_values[nv])
            nv++;
        int32_t e = pd->def.e;
        if (pd->def.s) {
            for (uint32_t i = 0; i < nv; i++)
                if (strcmp(pd->def.s, pd->enum_values[i]) == 0)
                    e = (int32_t)i;
        }
        if (e < 0 || (uint32_t)e >= nv)
            e = 0;
        out->e = e;
        out->s = lg_xstrdup(nv ? pd->enum_values[e] : "");
    } else if (pd->type == LG_PARAM_STRING || pd->type == LG_PARAM_PATH) {
        out->s = lg_xstrdup(pd->def.s ? pd->def.s : "");
    } else if (pd->type == LG_PARAM_PATH_LIST) {
        out->e = 0; /* the empty list (registry.c refuses another default) */
        out->s = lg_xstrdup("");
    } else if (pd->type == LG_PARAM_COLOR && pd->enum_values) {
        /* def.e: the default keyword's index, or -1 for the colour def.v (registry.c) */
        if (pd->def.e >= 0)
            memset(out->v, 0, sizeof out->v);
    } else if (pd->type == LG_PARAM_COLOR) {
        out->e = 0;
    }
}

static void unknown_node_error(checker *k, const lg_gvalue *v)
{
    lg_srcloc loc = v->loc;
    loc.len = (uint32_t)strlen(v->s);
    const char *sug = k->stop ? NULL : lg_suggest(v->s, k->node_names, k->g->n_nodes);
    if (sug)
        diag(k, LG_DIAG_ERROR, loc, "unknown node '%s'; did you mean '%s'?", v->s, sug);
    else
        diag(k, LG_DIAG_ERROR, loc, "unknown node '%s'", v->s);
}

/* The kind a part of a composite kind delivers along an edge. */
static lg_resource_kind part_kind(lg_resource_kind composite, uint32_t part)
{
    const lg_kind_desc *kd = lg_kind_describe(composite);
    lg_part_type t = kd && part > 0 && part <= kd->n_parts ? kd->parts[part - 1].type : 0;
    return t == LG_PART_IMAGE    ? LG_KIND_IMAGE
           : t == LG_PART_VOLUME ? LG_KIND_VOLUME
                                 : LG_KIND_BUFFER;
}

/* The kind an edge (node, port, part) delivers. */
static lg_resource_kind edge_kind(const lg_node_type *ty, uint32_t port, uint32_t part)
{
    lg_resource_kind k = ty->outputs[port].kind;
    return part ? part_kind(k, part) : k;
}

/* Resolves NODE, NODE.PORT or NODE.PART (a part of the first output of a composite kind
 * that has it, lightgraph/kinds.h) to an output; reports and returns false otherwise.
 * With *node >= 0 and *port == UINT32_MAX the node's type is unknown (already reported). */
static bool resolve_ref(checker *k, const lg_gvalue *v, int32_t *node, uint32_t *port,
                        uint32_t *part)
{
    *part = 0;
    int32_t t = lg_graph_find_node(k->g, v->s);
    if (t < 0) {
        unknown_node_error(k, v);
        return false;
    }
    *node = t;
    const lg_node_type *ty = k->c->nodes[t].type;
    if (!ty) {
        *port = UINT32_MAX;
        return true;
    }
    const lg_gnode *tn = &k->g->nodes[t];
    if (!v->port) {
        if (ty->n_outputs == 0) {
            diag(k, LG_DIAG_ERROR, v->loc, "node '%s' (%s) has no outputs", tn->name, ty->name);
            return false;
        }
        *port = 0;
        return true;
    }
    for (uint32_t i = 0; i < ty->n_outputs; i++) {
        if (strcmp(ty->outputs[i].name, v->port) == 0) {
            *port = i;
            return true;
        }
    }
    for (uint32_t i = 0; i < ty->n_outputs; i++) {
        int32_t pi = lg_kind_part_index(ty->outputs[i].kind, v->port);
        if (pi >= 0) {
            *port = i;
            *part = (uint32_t)pi + 1;
            return true;
        }
    }
    lg_srcloc loc = v->loc;
    loc.col += (uint32_t)strlen(v->s) + 1;
    loc.len = (uint32_t)strlen(v->port);
    lg_str list = { 0 };
    uint32_t n_names = 0;
    const char **names = NULL;
    for (uint32_t i = 0; i < ty->n_outputs; i++) {
        const lg_kind_desc *kd = lg_kind_describe(ty->outputs[i].kind);
        uint32_t np = kd ? kd->n_parts : 0;
        names = lg_xrealloc(names, (n_names + 1 + np) * sizeof *names);
        names[n_names++] = ty->outputs[i].name;
        lg_str_addf(&list, "%s%s", i ? ", " : "", ty->outputs[i].name);
        if (np) {
            lg_str_add(&list, " (parts:");
            for (uint32_t j = 0; j < np; j++) {
                names[n_names++] = kd->parts[j].name;
                lg_str_addf(&list, " %s", kd->parts[j].name);
            }
            lg_str_add(&list, ")");
        }
    }
    const char *sug = lg_suggest(v->port, names, n_names);
    const char *what = n_names > ty->n_outputs ? "output or part" : "output";
    if (ty->n_outputs == 0)
        diag(k, LG_DIAG_ERROR, loc, "node '%s' (%s) has no outputs", tn->name, ty->name);
    else if (sug)
        diag(k, LG_DIAG_ERROR, loc,
             "node '%s' (%s) has no %s '%s'; did you mean '%s'? "
             "(outputs: %s)",
             tn->name, ty->name, what, v->port, sug, list.s);
    else
        diag(k, LG_DIAG_ERROR, loc, "node '%s' (%s) has no %s '%s' (outputs: %s)", tn->name,
             ty->name, what, v->port, list.s);
    free(names);
    lg_str_free(&list);
    return false;
}

static void connect_input(checker *k, uint32_t ni, uint32_t ii, const lg_gvalue *v0)
{
    const lg_gnode *n = &k->g->nodes[ni];
    const lg_node_type *ty = k->c->nodes[ni].type;
    const lg_port_desc *in = &ty->inputs[ii];
    char what[160];
    snprintf(what, sizeof what, "input '%s'", in->name);
    lg_gvalue tmp;
    const lg_gvalue *v = resolve_raw(k, n, NULL, what, v0, false, &tmp);
    if (!v)
        return;
    if (v->kind != LG_GV_IDENT) {
        char *f = found_name(v);
        diag(k, LG_DIAG_ERROR, v->loc,
             "expected a reference to a node (NODE or NODE.PORT), "
             "found %s (input '%s' of node '%s')",
             f, in->name, n->name);
        free(f);
        return;
    }
    int32_t src;
    uint32_t port, part;
    if (!resolve_ref(k, v, &src, &port, &part))
        return;
    lg_edge *e = &k->c->nodes[ni].inputs[ii];
    e->node = src;
    e->port = port == UINT32_MAX ? 0 : port;
    e->part = part;
    if (port == UINT32_MAX)
        return;
    lg_resource_kind out = edge_kind(k->c->nodes[src].type, port, part);
    if (in->kind != LG_KIND_ANY && out != LG_KIND_ANY && in->kind != out)
        diag(k, LG_DIAG_ERROR, v->loc, "input '%s' of node '%s' takes %s, but '%s' gives %s",
             in->name, n->name, lg_kind_phrase(in->kind), v->text, lg_kind_phrase(out));
}

/* Which parameter or input an entry sets: >= 0 a parameter, < 0 -(input + 1). */
enum { SLOT_NONE = INT32_MIN };

static int32_t find_slot(checker *k, const lg_gnode *n, const lg_node_type *ty, const lg_gassign *a)
{
    for (uint32_t i = 0; i < ty->n_params; i++)
        if (strcmp(ty->params[i].key, a->key) == 0)
            return (int32_t)i;
    for (uint32_t i = 0; i < ty->n_params; i++) {
        for (const char *const *r = ty->params[i].renamed_from; r && *r; r++) {
            if (strcmp(*r, a->key) == 0) {
                diag(k, LG_DIAG_WARNING, a->key_loc, "parameter '%s' of %s was renamed to '%s'",
                     a->key, ty->name, ty->params[i].key);
                return (int32_t)i;
            }
        }
    }
    for (uint32_t i = 0; i < ty->n_inputs; i++)
        if (strcmp(ty->inputs[i].name, a->key) == 0)
            return -(int32_t)i - 1;

    const char **names = lg_xmalloc((ty->n_params + ty->n_inputs + 1) * sizeof *names);
    for (uint32_t i = 0; i < ty->n_params; i++)
        names[i] = ty->params[i].key;
    for (uint32_t i = 0; i < ty->n_inputs; i++)
        names[ty->n_params + i] = ty->inputs[i].name;
    const char *sug = lg_suggest(a->key, names, ty->n_params + ty->n_inputs);
    if (sug) {
        diag(k, LG_DIAG_ERROR, a->key_loc,
             "unknown parameter '%s' for node '%s' (type %s); did "
             "you mean '%s'?",
             a->key, n->name, ty->name, sug);
    } else {
        lg_str b = { 0 };
        lg_str_add(&b, "parameters: ");
        for (uint32_t i = 0; i < ty->n_params; i++)
            lg_str_addf(&b, "%s%s", i ? ", " : "", ty->params[i].key);
        if (!ty->n_params)
            lg_str_add(&b, "none");
        lg_str_add(&b, "; inputs: ");
        for (uint32_t i = 0; i < ty->n_inputs; i++)
            lg_str_addf(&b, "%s%s", i ? ", " : "", ty->inputs[i].name);
        if (!ty->n_inputs)
            lg_str_add(&b, "none");
        diag(k, LG_DIAG_ERROR, a->key_loc, "unknown parameter '%s' for node '%s' (type %s; %s)",
             a->key, n->name, ty->name, b.s);
        lg_str_free(&b);
    }
    free(names);
    return SLOT_NONE;
}

/* The parameter role (lightgraph/plugin.h) takes the first of lg_param_desc's four reserved
 * pointers of ABI 2.0 without moving anything else. */
_Static_assert(offsetof(lg_param_desc, role) + 4 * sizeof(void *) == sizeof(lg_param_desc),
               "lg_param_desc.role must fill exactly one reserved slot");

/* An image size that the parameters alone make impossible (LG_ROLE_IMAGE_WIDTH / _HEIGHT):
 * width x height beyond the pixel limit, or bytes beyond what this machine can address
 * (16 bytes a pixel, the widest format). 0 takes the render size, unknown here: the
 * render checks that one. */
static void check_image_size(checker *k, const lg_gnode *n, const lg_node_type *ty,
                             const lg_cnode *cn, const int32_t *winner)
{
    int32_t wi = -1, hi = -1;
    for (uint32_t i = 0; i < ty->n_params; i++) {
        if (ty->params[i].type != LG_PARAM_INT)
            continue;
        if (ty->params[i].role == LG_ROLE_IMAGE_WIDTH && wi < 0)
            wi = (int32_t)i;
        else if (ty->params[i].role == LG_ROLE_IMAGE_HEIGHT && hi < 0)
            hi = (int32_t)i;
    }
    if (wi < 0 || hi < 0)
        return;
    int64_t w = cn->params[wi].i, h = cn->params[hi].i;
    if (w <= 0 || h <= 0)
        return;
    uint64_t px = (uint64_t)w * (uint64_t)h; /* both below 2^63 / 2^31 in practice */
    bool overflow = (uint64_t)w > UINT64_MAX / (uint64_t)h;
    uint64_t limit = k->sc->max_pixels;
    bool too_many = limit && (overflow || px > limit);
    bool too_big = overflow || px > SIZE_MAX / 16;
    if (!too_many && !too_big)
        return;
    /* At a value that was set: one from the command line (--set) first, else the later of
     * the two in the file; at the node when both are defaults. */
    lg_srcloc loc = n->loc;
    int32_t at = winner[hi] >= 0 ? winner[hi] : winner[wi];
    if (winner[wi] >= 0 && winner[hi] >= 0) {
        bool wraw = n->assigns[winner[wi]].value.kind == LG_GV_RAW;
        bool hraw = n->assigns[winner[hi]].value.kind == LG_GV_RAW;
        if (wraw != hraw)
            at = wraw ? winner[wi] : winner[hi];
        else if (winner[wi] > winner[hi])
            at = winner[wi];
    }
    if (at >= 0)
        loc = n->assigns[at].value.loc;
    const char *wk = ty->params[wi].key, *hk = ty->params[hi].key;
    if (too_many)
        diag(k, LG_DIAG_ERROR, loc,
             "node '%s' (%s) makes a %lldx%lld image (%s x %s): "
             "%llu pixels, over the limit of %llu (LIGHTGRAPH_MAX_PIXELS raises it)",
             n->name, ty->name, (long long)w, (long long)h, wk, hk,
             overflow ? 0ull : (unsigned long long)px, (unsigned long long)limit);
    else
        diag(k, LG_DIAG_ERROR, loc,
             "node '%s' (%s) makes a %lldx%lld image (%s x %s): too "
             "large for this machine's memory",
             n->name, ty->name, (long long)w, (long long)h, wk, hk);
}

static void check_node(checker *k, uint32_t ni)
{
    const lg_gnode *n = &k->g->nodes[ni];
    lg_cnode *cn = &k->c->nodes[ni];
    const lg_node_type *ty = cn->type;
    if (!ty)
        return;
    uint32_t nslots = ty->n_params + ty->n_inputs;
    /* winner[s]: the entry that sets slot s, or -1 */
    int32_t *winner = lg_xmalloc((nslots + 1) * sizeof *winner);
    for (uint32_t s = 0; s < nslots; s++)
        winner[s] = -1;
    for (uint32_t ai = 0; ai < n->n_assigns; ai++) {
        const lg_gassign *a = &n->assigns[ai];
        int32_t slot = find_slot(k, n, ty, a);
        if (slot == SLOT_NONE)
            continue;
        uint32_t s = slot >= 0 ? (uint32_t)slot : ty->n_params + (uint32_t)(-slot - 1);
        if (winner[s] >= 0) {
            const lg_gassign *first = &n->assigns[winner[s]];
            if (a->value.kind == LG_GV_RAW) {
                winner[s] = (int32_t)ai; /* the command line wins */
                continue;
            }
            const char *canon = slot >= 0 ? ty->params[slot].key : ty->inputs[-slot - 1].name;
            diag(k, LG_DIAG_ERROR, a->key_loc, "'%s' of node '%s' is set twice (as '%s' and '%s')",
                 canon, n->name, first->key, a->key);
            diag(k, LG_DIAG_NOTE, first->key_loc, "'%s' was first set here", first->key);
            continue;
        }
        winner[s] = (int32_t)ai;
    }

    for (uint32_t i = 0; i < ty->n_params; i++) {
        const lg_param_desc *pd = &ty->params[i];
        if (winner[i] >= 0) {
            cn->param_set[i] = true;
            if (!convert_param(k, n, pd, &n->assigns[winner[i]].value, &cn->params[i]))
                default_param(pd, &cn->params[i]);
        } else {
            default_param(pd, &cn->params[i]);
        }
    }
    check_image_size(k, n, ty, cn, winner);
    for (uint32_t i = 0; i < ty->n_inputs; i++) {
        int32_t w = winner[ty->n_params + i];
        if (w >= 0)
            connect_input(k, ni, i, &n->assigns[w].value);
        else if (!ty->inputs[i].optional)
            diag(k, LG_DIAG_ERROR, n->loc, "node '%s' (%s) needs input '%s'", n->name, ty->name,
                 ty->inputs[i].name);
    }
    free(winner);
}

/* ---- cycles and order ------------------------------------------------------------------------ */

typedef struct graph_adj {
    uint32_t *start; /* n + 1 offsets into dst */
    uint32_t *dst;   /* consumers of each node, in data-flow direction */
} graph_adj;

static void build_adj(const lg_checked *c, graph_adj *a)
{
    uint32_t n = c->n_nodes, m = 0;
    a->start = lg_xcalloc(n + 1, sizeof *a->start);
    for (uint32_t i = 0; i < n; i++) {
        const lg_cnode *cn = &c->nodes[i];
        for (uint32_t j = 0; cn->type && j < cn->type->n_inputs; j++)
            if (cn->inputs[j].node >= 0) {
                a->start[cn->inputs[j].node + 1]++;
                m++;
            }
    }
    for (uint32_t i = 0; i < n; i++)
        a->start[i + 1] += a->start[i];
    a->dst = lg_xmalloc((m + 1) * sizeof *a->dst);
    uint32_t *fill = lg_xmalloc((n + 1) * sizeof *fill);
    memcpy(fill, a->start, n * sizeof *fill);
    for (uint32_t i = 0; i < n; i++) {
        const lg_cnode *cn = &c->nodes[i];
        for (uint32_t j = 0; cn->type && j < cn->type->n_inputs; j++)
            if (cn->inputs[j].node >= 0)
                a->dst[fill[cn->inputs[j].node]++] = i;
    }
    free(fill);
}

/* Reports the shortest cycle through `start` inside the component `comp` (comp[v] == id). */
static void report_cycle(checker *k, const graph_adj *a, const int32_t *comp, int32_t id,
                         uint32_t start)
{
    uint32_t n = k->c->n_nodes;
    int32_t *parent = lg_xmalloc((n + 1) * sizeof *parent);
    uint32_t *queue = lg_xmalloc((n + 1) * sizeof *queue);
    for (uint32_t i = 0; i < n; i++)
        parent[i] = -1;
    uint32_t qh = 0, qt = 0;
    int32_t last = -1;
    queue[qt++] = start;
    while (qh < qt && last < 0) {
        uint32_t v = queue[qh++];
        for (uint32_t e = a->start[v]; e < a->start[v + 1]; e++) {
            uint32_t w = a->dst[e];
            if (comp[w] != id)
                continue;
            if (w == start) {
                last = (int32_t)v;
                break;
            }
            if (parent[w] < 0) {
                parent[w] = (int32_t)v;
                queue[qt++] = w;
            }
        }
    }
    /* path start -> ... -> last -> start */
    uint32_t len = 0;
    for (int32_t v = last; v >= 0 && (uint32_t)v != start; v = parent[v])
        queue[len++] = (uint32_t)v;
    /* The cycle is start, queue[len - 1], ..., queue[0], start: len + 2 names. A long one is
     * shown by its first 8 and last 7, so that the message stays short. */
    uint32_t total = len + 2, head = 8, tail = 7;
    lg_str b = { 0 };
    for (uint32_t j = 0; j < total; j++) {
        if (total > head + tail + 1 && j == head) {
            lg_str_addf(&b, " -> ... (%u more)", total - head - tail);
            j = total - tail - 1;
            continue;
        }
        uint32_t v = j == 0 || j == total - 1 ? start : queue[len - j];
        lg_str_addf(&b, "%s%s", j ? " -> " : "", k->g->nodes[v].name);
    }
    diag(k, LG_DIAG_ERROR, k->g->nodes[start].loc, "cycle: %s", b.s);
    lg_str_free(&b);
    free(parent);
    free(queue);
}

/* Tarjan's SCC over the nodes Kahn's algorithm could not order (iterative). */
static void report_cycles(checker *k, const graph_adj *a, const bool *ordered)
{
    uint32_t n = k->c->n_nodes;
    int32_t *index = lg_xmalloc((n + 1) * sizeof *index);
    uint32_t *low = lg_xmalloc((n + 1) * sizeof *low);
    bool *on = lg_xcalloc(n + 1, sizeof *on);
    uint32_t *stack = lg_xmalloc((n + 1) * sizeof *stack);
    uint32_t *fv = lg_xmalloc((n + 1) * sizeof *fv), *fe = lg_xmalloc((n + 1) * sizeof *fe);
    int32_t *comp = lg_xmalloc((n + 1) * sizeof *comp);
    uint32_t *comp_min = lg_xmalloc((n + 1) * sizeof *comp_min);
    for (uint32_t i = 0; i < n; i++) {
        index[i] = -1;
        comp[i] = -1;
    }
    uint32_t next = 0, sp = 0, ncomp = 0;
    for (uint32_t root = 0; root < n; root++) {
        if (ordered[root] || index[root] >= 0)
            continue;
        uint32_t fp = 0;
        fv[fp] = root;
        fe[fp++] = a->start[root];
        index[root] = (int32_t)next;
        low[root] = next++;
        stack[sp++] = root;
        on[root] = true;
        while (fp > 0) {
            uint32_t v = fv[fp - 1];
            if (fe[fp - 1] < a->start[v + 1]) {
                uint32_t w = a->dst[fe[fp - 1]++];
                if (ordered[w])
                    continue;
                if (index[w] < 0) {
                    index[w] = (int32_t)next;
                    low[w] = next++;
                    stack[sp++] = w;
                    on[w] = true;
                    fv[fp] = w;
                    fe[fp++] = a->start[w];
                } else if (on[w] && (uint32_t)index[w] < low[v]) {
                    low[v] = (uint32_t)index[w];
                }
                continue;
            }
            fp--;
            if (fp > 0 && low[v] < low[fv[fp - 1]])
                low[fv[fp - 1]] = low[v];
            if (low[v] == (uint32_t)index[v]) {
                uint32_t mn = v, size = 0;
                uint32_t w;
                do {
                    w = stack[--sp];
                    on[w] = false;
                    comp[w] = (int32_t)ncomp;
                    if (w < mn)
                        mn = w;
                    size++;
                } while (w != v);
                bool self = false;
                for (uint32_t e = a->start[v]; e < a->start[v + 1]; e++)
                    self |= a->dst[e] == v;
                comp_min[ncomp++] = (size > 1 || self) ? mn : UINT32_MAX;
            }
        }
    }
    /* In file order of each cycle's first node. */
    for (uint32_t v = 0; v < n; v++)
        if (comp[v] >= 0 && comp_min[comp[v]] == v)
            report_cycle(k, a, comp, comp[v], v);
    free(index);
    free(low);
    free(on);
    free(stack);
    free(fv);
    free(fe);
    free(comp);
    free(comp_min);
}

static void order_nodes(checker *k)
{
    lg_checked *c = k->c;
    uint32_t n = c->n_nodes;
    graph_adj a;
    build_adj(c, &a);
    uint32_t *indeg = lg_xcalloc(n + 1, sizeof *indeg);
    for (uint32_t v = 0; v < n; v++)
        for (uint32_t e = a.start[v]; e < a.start[v + 1]; e++)
            indeg[a.dst[e]]++;
    bool *ordered = lg_xcalloc(n + 1, sizeof *ordered);
    c->topo = lg_xmalloc((n + 1) * sizeof *c->topo);
    uint32_t qt = 0;
    for (uint32_t v = 0; v < n; v++)
        if (indeg[v] == 0)
            c->topo[qt++] = v;
    for (uint32_t qh = 0; qh < qt; qh++) {
        uint32_t v = c->topo[qh];
        ordered[v] = true;
        for (uint32_t e = a.start[v]; e < a.start[v + 1]; e++)
            if (--indeg[a.dst[e]] == 0)
                c->topo[qt++] = a.dst[e];
    }
    if (qt < n)
        report_cycles(k, &a, ordered);
    free(indeg);
    free(ordered);
    free(a.start);
    free(a.dst);
}

/* ---- outputs --------------------------------------------------------------------------------- */

static void check_outputs(checker *k)
{
    const lg_graph *g = k->g;
    lg_checked *c = k->c;
    c->outputs = lg_xcalloc(g->n_outputs + 1, sizeof *c->outputs);
    c->n_outputs = g->n_outputs;
    for (uint32_t i = 0; i < g->n_outputs; i++) {
        const lg_goutput *o = &g->outputs[i];
        lg_coutput *co = &c->outputs[i];
        co->g = o;
        co->node = -1;
        co->path = resolve_path(o->base_dir, o->path);
        int32_t node;
        uint32_t port, part;
        if (resolve_ref(k, &o->ref, &node, &port, &part)) {
            co->node = node;
            co->port = port == UINT32_MAX ? 0 : port;
            co->part = part;
            if (port != UINT32_MAX) {
                lg_resource_kind kind = edge_kind(c->nodes[node].type, port, part);
                const char *sl = strrchr(o->path, '/');
                const char *ext = strrchr(sl ? sl + 1 : o->path, '.');
                bool txt = ext && strcasecmp(ext, ".txt") == 0;
                /* a probe is written as an image file in its layout (lg_probe_pack) */
                if (kind == LG_KIND_PROBE && ext && strcasecmp(ext, ".png") == 0)
                    diag(k, LG_DIAG_ERROR, o->path_loc,
                         "'%s' gives a probe, which is HDR: "
                         "write it as .exr or .hdr, not '%s'",
                         o->ref.text, o->path);
                /* SH coefficients are written as text, and only they */
                else if (kind == LG_KIND_SH && !txt)
                    diag(k, LG_DIAG_ERROR, o->path_loc,
                         "'%s' gives SH coefficients, which are "
                         "written as text: name the file .txt, not '%s'",
                         o->ref.text, o->path);
                else if (txt && kind != LG_KIND_SH && kind != LG_KIND_ANY)
                    diag(k, LG_DIAG_ERROR, o->path_loc,
                         "'%s' gives %s, which cannot be written "
                         "as text ('%s'): only SH coefficients are; use .png, .exr or .hdr",
                         o->ref.text, lg_kind_phrase(kind), o->path);
                else if (kind != LG_KIND_IMAGE && kind != LG_KIND_ANY && kind != LG_KIND_PROBE &&
                         kind != LG_KIND_SH)
                    diag(k, LG_DIAG_ERROR, o->ref.loc,
                         "'%s' gives %s; only images, probes and SH "
                         "coefficients can be written to files",
                         o->ref.text, lg_kind_phrase(kind));
            }
        }
        const char *slash = strrchr(o->path, '/');
        const char *dot = strrchr(slash ? slash + 1 : o->path, '.');
        if (!dot || dot[1] == 0) {
            diag(k, LG_DIAG_ERROR, o->path_loc,
                 "output file '%s' has no extension (use .png, "
                 ".exr or .hdr)",
                 o->path);
        } else if (strcasecmp(dot, ".png") && strcasecmp(dot, ".exr") && strcasecmp(dot, ".hdr") &&
                   strcasecmp(dot, ".txt")) {
            diag(k, LG_DIAG_ERROR, o->path_loc,
                 "output file '%s' has an unsupported extension "
                 "'%s' (use .png, .exr or .hdr; .txt for SH coefficients)",
                 o->path, dot);
        }
        /* a frame pattern (base/pattern.h): one %d or %0Nd, else no '%' at all */
        size_t at = 0;
        char why[160];
        if (lg_frame_pattern_scan(o->path, &at, why, sizeof why) < 0)
            diag(k, LG_DIAG_ERROR, o->path_loc, "output file '%s', character %zu: %s", o->path,
                 at + 1, why);
        for (uint32_t j = 0; j < i; j++) {
            if (o->path[0] && strcmp(c->outputs[j].path, co->path) == 0) {
                diag(k, LG_DIAG_ERROR, o->path_loc,
                     "file '%s' is written by two output "
                     "statements",
                     o->path);
                diag(k, LG_DIAG_NOTE, g->outputs[j].path_loc, "the first one is here");
                break;
            }
        }
    }
}

/* ---- entry points ---------------------------------------------------------------------------- */

void lg_checked_free(lg_checked *c)
{
    if (!c)
        return;
    for (uint32_t i = 0; i < c->n_nodes; i++) {
        lg_cnode *cn = &c->nodes[i];
        if (cn->params && cn->type) {
            for (uint32_t j = 0; j < cn->type->n_params; j++) {
                lg_param_type t = cn->type->params[j].type;
                if (t == LG_PARAM_STRING || t == LG_PARAM_PATH || t == LG_PARAM_ENUM ||
                    t == LG_PARAM_PATH_LIST)
                    free((char *)cn->params[j].s);
            }
        }
        free(cn->params);
        free(cn->param_set);
        free(cn->inputs);
    }
    for (uint32_t i = 0; i < c->n_outputs; i++)
        free(c->outputs[i].path);
    free(c->nodes);
    free(c->outputs);
    free(c->topo);
    free(c);
}

lg_checked *lg_graph_check(const lg_graph *g, const lg_schema *schema, lg_diags *diags)
{
    checker k;
    memset(&k, 0, sizeof k);
    k.g = g;
    k.sc = schema;
    k.d = diags;
    lg_checked *c = lg_xcalloc(1, sizeof *c);
    k.c = c;
    c->n_nodes = g->n_nodes;
    c->nodes = lg_xcalloc(g->n_nodes + 1, sizeof *c->nodes);
    k.node_names = lg_xmalloc((g->n_nodes + 1) * sizeof *k.node_names);
    for (uint32_t i = 0; i < g->n_nodes; i++)
        k.node_names[i] = g->nodes[i].name;

    /* Types first, so that references can be checked in any order. */
    for (uint32_t i = 0; i < g->n_nodes; i++) {
        const lg_gnode *n = &g->nodes[i];
        lg_cnode *cn = &c->nodes[i];
        cn->g = n;
        cn->type = schema && schema->lookup ? schema->lookup(schema->ctx, n->type) : NULL;
        if (!cn->type) {
            const char *sug = schema ? lg_suggest(n->type, schema->names, schema->n_names) : NULL;
            if (sug)
                diag(&k, LG_DIAG_ERROR, n->type_loc, "unknown node type '%s'; did you mean '%s'?",
                     n->type, sug);
            else
                diag(&k, LG_DIAG_ERROR, n->type_loc,
                     "unknown node type '%s' (no plugin declares "
                     "it; 'lightgraph plugins' lists the known types)",
                     n->type);
            continue;
        }
        cn->params = lg_xcalloc(cn->type->n_params + 1, sizeof *cn->params);
        cn->param_set = lg_xcalloc(cn->type->n_params + 1, sizeof *cn->param_set);
        cn->inputs = lg_xcalloc(cn->type->n_inputs + 1, sizeof *cn->inputs);
        for (uint32_t j = 0; j < cn->type->n_inputs; j++)
            cn->inputs[j].node = -1;
    }
    for (uint32_t i = 0; i < g->n_nodes; i++)
        check_node(&k, i);
    order_nodes(&k);
    check_outputs(&k);
    free(k.node_names);
    if (k.errors) {
        lg_checked_free(c);
        return NULL;
    }
    return c;
}
