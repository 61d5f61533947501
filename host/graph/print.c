/*
 * host/graph/print.c: the canonical text of a graph (lightgraph fmt) and its Graphviz
 * picture (lightgraph dot).
 *
 * fmt must be a fixed point: parsing its output and formatting again gives the same
 * text. So every choice here depends only on what the parser keeps (values, comments and
 * where they were, blank lines before statements), never on the original spacing.
 */
#include "graph/graph.h"

#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"
#include "lightgraph/kinds.h"

#define FMT_WIDTH 100

/* The shortest text that reads back as the same double: plain decimals for magnitudes
 * people write that way (1000, 0.18), the exponent form (%g) beyond; always with a '.' or
 * an exponent, so that 1.0 does not come back as the integer 1. */
static void add_float(lg_str *b, double v)
{
    char buf[64];
    bool found = false;
    double m = v < 0 ? -v : v;
    if (m == 0 || (m >= 1e-4 && m < 1e15)) {
        for (int d = 0; d <= 25 && !found; d++) {
            snprintf(buf, sizeof buf, "%.*f", d, v);
            found = strtod(buf, NULL) == v;
        }
    }
    for (int prec = 1; prec <= 17 && !found; prec++) {
        snprintf(buf, sizeof buf, "%.*g", prec, v);
        found = strtod(buf, NULL) == v;
    }
    lg_str_add(b, buf);
    if (!strpbrk(buf, ".eEn"))
        lg_str_add(b, ".0");
}

static void add_string(lg_str *b, const char *s)
{
    lg_str_addc(b, '"');
    for (const char *p = s; *p; p++) {
        switch (*p) {
        case '"': lg_str_add(b, "\\\""); break;
        case '\\': lg_str_add(b, "\\\\"); break;
        case '\n': lg_str_add(b, "\\n"); break;
        case '\t': lg_str_add(b, "\\t"); break;
        default: lg_str_addc(b, *p);
        }
    }
    lg_str_addc(b, '"');
}

static void add_value(lg_str *b, const lg_gvalue *v)
{
    switch (v->kind) {
    case LG_GV_BOOL: lg_str_add(b, v->b ? "true" : "false"); break;
    case LG_GV_INT: lg_str_addf(b, "%" PRId64, v->i); break;
    case LG_GV_FLOAT: add_float(b, v->f); break;
    case LG_GV_STRING: add_string(b, v->s ? v->s : ""); break;
    case LG_GV_LIST:
        lg_str_addc(b, '[');
        for (uint32_t i = 0; i < v->n_items; i++) {
            if (i)
                lg_str_add(b, ", ");
            if (!v->nums)
                add_value(b, &v->items[i]);
            else if (v->nums->tag[i] & 0x80000000u) /* a float (lg_gnums) */
                add_float(b, v->nums->val[i].f);
            else
                lg_str_addf(b, "%" PRId64, v->nums->val[i].i);
        }
        lg_str_addc(b, ']');
        break;
    case LG_GV_IDENT:
        lg_str_add(b, v->s);
        if (v->port) {
            lg_str_addc(b, '.');
            lg_str_add(b, v->port);
        }
        break;
    case LG_GV_RAW:
        /* A --set value: as the literal it reads as, else as a string of its text. */
        if (v->n_items == 1)
            add_value(b, &v->items[0]);
        else
            add_string(b, v->text ? v->text : "");
        break;
    }
}

/* Comment lines ("" is a blank line). */
static void add_comments(lg_str *b, char *const *c, uint32_t n, const char *indent)
{
    for (uint32_t i = 0; i < n; i++) {
        if (c[i][0])
            lg_str_addf(b, "%s%s", indent, c[i]);
        lg_str_addc(b, '\n');
    }
}

static void add_eol(lg_str *b, const char *eol)
{
    if (eol)
        lg_str_addf(b, "  %s", eol);
    lg_str_addc(b, '\n');
}

static void add_node(lg_str *b, const lg_gnode *n)
{
    add_comments(b, n->comments, n->n_comments, "");
    bool multi = n->n_end_comments > 0;
    for (uint32_t i = 0; i < n->n_assigns && !multi; i++)
        multi = n->assigns[i].n_comments > 0 || n->assigns[i].eol_comment;
    if (!multi) {
        lg_str line = { 0 };
        lg_str_addf(&line, "%s = %s {", n->name, n->type);
        for (uint32_t i = 0; i < n->n_assigns; i++) {
            lg_str_addf(&line, "%s%s = ", i ? ", " : " ", n->assigns[i].key);
            add_value(&line, &n->assigns[i].value);
        }
        lg_str_add(&line, n->n_assigns ? " }" : "}");
        if (line.len <= FMT_WIDTH) {
            lg_str_add(b, line.s);
            add_eol(b, n->eol_comment);
            lg_str_free(&line);
            return;
        }
        lg_str_free(&line);
    }
    lg_str_addf(b, "%s = %s {", n->name, n->type);
    add_eol(b, n->eol_comment);
    for (uint32_t i = 0; i < n->n_assigns; i++) {
        const lg_gassign *a = &n->assigns[i];
        if (i > 0 && a->blank_before)
            lg_str_addc(b, '\n');
        add_comments(b, a->comments, a->n_comments, "    ");
        lg_str_addf(b, "    %s = ", a->key);
        add_value(b, &a->value);
        add_eol(b, a->eol_comment);
    }
    add_comments(b, n->end_comments, n->n_end_comments, "    ");
    lg_str_add(b, "}\n");
}

char *lg_graph_format(const lg_graph *g)
{
    lg_str b = { 0 };
    add_comments(&b, g->header_comments, g->n_header_comments, "");
    lg_str_addf(&b, "lightgraph %d\n", g->version > 0 ? g->version : 1);
    if (g->n_includes)
        lg_str_addc(&b, '\n');
    for (uint32_t i = 0; i < g->n_includes; i++) {
        const lg_ginclude *inc = &g->includes[i];
        add_comments(&b, inc->comments, inc->n_comments, "");
        lg_str_add(&b, "include ");
        add_string(&b, inc->path);
        add_eol(&b, inc->eol_comment);
    }
    bool first = true;
    for (uint32_t i = 0; i < g->n_nodes; i++) {
        const lg_gnode *n = &g->nodes[i];
        if (n->included)
            continue;
        if (first || n->blank_before)
            lg_str_addc(&b, '\n');
        first = false;
        add_node(&b, n);
    }
    first = true;
    for (uint32_t i = 0; i < g->n_outputs; i++) {
        const lg_goutput *o = &g->outputs[i];
        if (o->included)
            continue;
        if (first || o->blank_before)
            lg_str_addc(&b, '\n');
        first = false;
        add_comments(&b, o->comments, o->n_comments, "");
        lg_str_add(&b, "output ");
        add_value(&b, &o->ref);
        lg_str_addc(&b, ' ');
        add_string(&b, o->path);
        if (o->exr_pixel)
            lg_str_add(&b, o->exr_pixel == LG_OUT_EXR_HALF ? " half" : " float");
        add_eol(&b, o->eol_comment);
    }
    if (g->n_trailing_comments) {
        lg_str_addc(&b, '\n');
        add_comments(&b, g->trailing_comments, g->n_trailing_comments, "");
    }
    return lg_str_take(&b);
}

/* ---- dot ------------------------------------------------------------------------------------- */

static void add_dot_string(lg_str *b, const char *s)
{
    lg_str_addc(b, '"');
    for (const char *p = s; *p; p++) {
        if (*p == '"' || *p == '\\')
            lg_str_addc(b, '\\');
        if (*p == '\n')
            lg_str_add(b, "\\n");
        else
            lg_str_addc(b, *p);
    }
    lg_str_addc(b, '"');
}

static void add_edge(lg_str *b, const char *from, const char *to, const char *out_port,
                     const char *in_port)
{
    lg_str label = { 0 };
    if (out_port && in_port)
        lg_str_addf(&label, "%s -> %s", out_port, in_port);
    else if (out_port || in_port)
        lg_str_add(&label, out_port ? out_port : in_port);
    lg_str_addf(b, "  \"%s\" -> ", from);
    add_dot_string(b, to);
    if (label.len) {
        lg_str_add(b, " [label=");
        add_dot_string(b, label.s);
        lg_str_addc(b, ']');
    }
    lg_str_add(b, ";\n");
    lg_str_free(&label);
}

/* The reference a value makes, if any (a --set value counts when it reads as one). */
static const lg_gvalue *ref_of(const lg_gvalue *v)
{
    if (v->kind == LG_GV_RAW && v->n_items == 1)
        v = &v->items[0];
    return v->kind == LG_GV_IDENT ? v : NULL;
}

/* The label at an edge's source: the port when the node has several outputs (or when the
 * resource is composite: "shadows {atlas, lights, info}"), the part an edge NODE.PART
 * reads ("atlas, part of shadows"); NULL for the plain single output. Caller frees. */
static char *edge_label(const lg_node_type *t, uint32_t port, uint32_t part)
{
    lg_resource_kind k = t->outputs[port].kind;
    const lg_kind_desc *kd = lg_kind_describe(k);
    if (part && kd && part <= kd->n_parts)
        return lg_xasprintf("%s, part of %s", kd->parts[part - 1].name, t->outputs[port].name);
    if (!lg_kind_is_composite(k))
        return port ? lg_xstrdup(t->outputs[port].name) : NULL;
    lg_str b = { 0 };
    lg_str_addf(&b, "%s {", t->outputs[port].name);
    for (uint32_t i = 0; i < kd->n_parts; i++)
        lg_str_addf(&b, "%s%s", i ? ", " : "", kd->parts[i].name);
    lg_str_add(&b, "}");
    return lg_str_take(&b);
}

char *lg_graph_dot(const lg_graph *g, const lg_checked *c)
{
    lg_str b = { 0 };
    lg_str_add(&b, "digraph lightgraph {\n  rankdir=LR;\n  node [shape=ellipse];\n");
    for (uint32_t i = 0; i < g->n_nodes; i++) {
        const lg_gnode *n = &g->nodes[i];
        char *label = lg_xasprintf("%s\n%s", n->name, n->type);
        lg_str_addf(&b, "  \"%s\" [label=", n->name);
        add_dot_string(&b, label);
        lg_str_add(&b, "];\n");
        free(label);
    }
    for (uint32_t i = 0; i < g->n_nodes; i++) {
        const lg_gnode *n = &g->nodes[i];
        if (c) {
            const lg_cnode *cn = &c->nodes[i];
            for (uint32_t j = 0; cn->type && j < cn->type->n_inputs; j++) {
                const lg_edge *e = &cn->inputs[j];
                if (e->node < 0)
                    continue;
                const lg_cnode *src = &c->nodes[e->node];
                char *tail = edge_label(src->type, e->port, e->part);
                add_edge(&b, src->g->name, n->name, tail, cn->type->inputs[j].name);
                free(tail);
            }
        } else {
            for (uint32_t j = 0; j < n->n_assigns; j++) {
                const lg_gvalue *r = ref_of(&n->assigns[j].value);
                if (r && lg_graph_find_node(g, r->s) >= 0)
                    add_edge(&b, r->s, n->name, r->port, n->assigns[j].key);
            }
        }
    }
    for (uint32_t i = 0; i < g->n_outputs; i++) {
        const lg_goutput *o = &g->outputs[i];
        lg_str_addf(&b, "  \"output:%u\" [shape=box, label=", i);
        add_dot_string(&b, o->path);
        lg_str_add(&b, "];\n");
        char id[32];
        snprintf(id, sizeof id, "output:%u", i);
        if (c) {
            const lg_coutput *co = &c->outputs[i];
            if (co->node >= 0) {
                const lg_cnode *src = &c->nodes[co->node];
                char *tail = edge_label(src->type, co->port, co->part);
                add_edge(&b, src->g->name, id, tail, NULL);
                free(tail);
            }
        } else if (lg_graph_find_node(g, o->ref.s) >= 0) {
            add_edge(&b, o->ref.s, id, o->ref.port, NULL);
        }
    }
    lg_str_add(&b, "}\n");
    return lg_str_take(&b);
}
