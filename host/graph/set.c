/*
 * host/graph/set.c: --set NODE.PARAM=VALUE (lg_graph_set; docs/graph-format.md,
 * "Overrides"). Each assignment is a source of its own, "<command line>" line n for the
 * n-th, so that messages about it point into it as into a file. The value stays raw text
 * (LG_GV_RAW): the checker reads it with the parameter's type; it is lexed and parsed as
 * one literal here only to offer that reading.
 */
#include "graph/parse_priv.h"

#include <stdlib.h>
#include <string.h>

#include "base/util.h"

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

/* The end of the name at a[i] (i when none starts there). */
static uint32_t ident_end(const char *a, uint32_t i, size_t alen)
{
    uint32_t i0 = i;
    while (i < alen &&
           (i == i0 ? is_ident_start((unsigned char)a[i]) : is_ident_char((unsigned char)a[i])))
        i++;
    return i;
}

int lg_graph_set(lg_graph *g, const char *assignment, lg_diags *diags)
{
    pool *pl = g->pool;
    uint32_t ordinal = ++pl->n_sets;
    size_t alen = strlen(assignment);
    if (alen > MAX_FILE_BYTES)
        alen = MAX_FILE_BYTES;
    source *src = lg_source_add(pl, "<command line>", assignment, alen, ordinal, false);
    const char *a = src->text;
    session s = { .pl = pl, .g = g, .d = diags };
    const char *form = " (--set NODE.PARAM=VALUE)";

    /* The value may be taken as raw text (a path, a string, an enum), not only lexed: the
     * whole assignment must be UTF-8, as a graph file is. */
    for (uint32_t i = 0; i < alen; i++) {
        unsigned char ch = (unsigned char)a[i];
        if (ch < 0x80)
            continue;
        int u = lg_utf8_char_len((const unsigned char *)a + i, alen - i);
        if (u == 0) {
            lg_report(&s, src, LG_DIAG_ERROR, ordinal, i + 1, 1,
                      "invalid UTF-8: byte 0x%02X at "
                      "byte offset %u%s",
                      ch, i, form);
            return -1;
        }
        i += (uint32_t)u - 1;
    }

    uint32_t i = 0;
    while (i < alen && is_space(a[i]))
        i++;
    uint32_t n0 = i;
    uint32_t n1 = i = ident_end(a, i, alen);
    if (n1 == n0) {
        lg_report(&s, src, LG_DIAG_ERROR, ordinal, n0 + 1, (uint32_t)(alen - n0),
                  "expected a node name%s", form);
        return -1;
    }
    if (i >= alen || a[i] != '.') {
        lg_report(&s, src, LG_DIAG_ERROR, ordinal, i + 1, i < alen ? 1 : 0,
                  "expected '.' and a parameter name after '%.*s'%s", (int)(n1 - n0), a + n0, form);
        return -1;
    }
    i++;
    uint32_t k0 = i;
    uint32_t k1 = i = ident_end(a, i, alen);
    if (k1 == k0) {
        lg_report(&s, src, LG_DIAG_ERROR, ordinal, k0 + 1, k0 < alen ? 1 : 0,
                  "expected a parameter name after '%.*s.'%s", (int)(n1 - n0), a + n0, form);
        return -1;
    }
    while (i < alen && is_space(a[i]))
        i++;
    if (i >= alen || a[i] != '=') {
        lg_report(&s, src, LG_DIAG_ERROR, ordinal, i + 1, i < alen ? 1 : 0,
                  "expected '=' after '%.*s'%s", (int)(k1 - n0), a + n0, form);
        return -1;
    }
    i++;
    while (i < alen && is_space(a[i]))
        i++;
    uint32_t v0 = i, v1 = (uint32_t)alen;
    while (v1 > v0 && is_space(a[v1 - 1]))
        v1--;

    char *node_name = lg_arena_strndup(&pl->a, a + n0, n1 - n0);
    int32_t ni = lg_graph_find_node(g, node_name);
    if (ni < 0) {
        const char **names = lg_xmalloc((g->n_nodes + 1) * sizeof *names);
        for (uint32_t j = 0; j < g->n_nodes; j++)
            names[j] = g->nodes[j].name;
        const char *sug = lg_suggest(node_name, names, g->n_nodes);
        if (sug)
            lg_report(&s, src, LG_DIAG_ERROR, ordinal, n0 + 1, n1 - n0,
                      "unknown node '%s'; did you mean '%s'?", node_name, sug);
        else
            lg_report(&s, src, LG_DIAG_ERROR, ordinal, n0 + 1, n1 - n0, "unknown node '%s'",
                      node_name);
        free(names);
        return -1;
    }

    /* The value stays raw; try it as a literal now, for the types that want one. */
    lg_gvalue v;
    memset(&v, 0, sizeof v);
    v.kind = LG_GV_RAW;
    v.loc = (lg_srcloc){ src->name, ordinal, v0 + 1, v1 - v0 };
    v.text = lg_arena_strndup(&pl->a, a + v0, v1 - v0);
    v.base_dir = NULL;
    {
        lg_diags tmp = { 0 };
        session vs = { .pl = pl, .g = g, .d = &tmp };
        parser vp;
        memset(&vp, 0, sizeof vp);
        vp.s = &vs;
        vp.src = src;
        lg_lex(&vp, v0, v1);
        lg_skip_nl(&vp);
        lg_gvalue item;
        if (peek(&vp)->kind == T_EOF) {
            v.s = lg_arena_strdup(&pl->a, "the value is empty");
        } else if (lg_parse_value(&vp, &item)) {
            lg_skip_nl(&vp);
            tok *t = peek(&vp);
            if (t->kind == T_EOF) {
                v.items = lg_arena_copy(&pl->a, &item, sizeof item);
                v.n_items = 1;
            } else {
                v.s = lg_arena_strdup(&pl->a, "it is more than one value");
            }
        } else {
            v.s = lg_arena_strdup(&pl->a, tmp.n ? tmp.items[0].message : "it is not a value");
        }
        lg_diags_free(&tmp);
        free(vp.t);
        free(vp.cm);
    }

    lg_gnode *n = &g->nodes[ni];
    char *key = lg_arena_strndup(&pl->a, a + k0, k1 - k0);
    lg_srcloc key_loc = { src->name, ordinal, k0 + 1, k1 - k0 };
    for (uint32_t j = 0; j < n->n_assigns; j++) {
        if (strcmp(n->assigns[j].key, key) == 0) {
            n->assigns[j].value = v;
            n->assigns[j].key_loc = key_loc;
            return 0;
        }
    }
    lg_gassign *as = lg_arena_alloc(&pl->a, (n->n_assigns + 1) * sizeof *as);
    if (n->n_assigns)
        memcpy(as, n->assigns, n->n_assigns * sizeof *as);
    memset(&as[n->n_assigns], 0, sizeof *as);
    as[n->n_assigns].key = key;
    as[n->n_assigns].key_loc = key_loc;
    as[n->n_assigns].value = v;
    n->assigns = as;
    n->n_assigns++;
    return 0;
}
