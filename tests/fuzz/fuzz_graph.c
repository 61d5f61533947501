/*
 * tests/fuzz/fuzz_graph.c: the graph parser, checker and printers on arbitrary bytes.
 *
 * For every input: parse; print the diagnostics; if it parsed, format it, parse the
 * formatted text again (it must parse), format that (it must be the same text) and
 * compare the two graphs (same nodes, keys, values and number of comments); then check
 * against the fake schema, draw it, and apply a few --set overrides and check again.
 * Any difference aborts, so that libFuzzer (or the test) reports it with the input.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus to the plain driver (fuzz_driver.h) with a dictionary of graph-file
 * tokens:
 *
 *     fuzz_graph [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fake_schema.h"
#include "fuzz_driver.h"
#include "graph/graph.h"
#include "base/util.h"

/* Relative includes resolve here, where nothing exists. */
#define FUZZ_BASE "/nonexistent-lightgraph-fuzz"

static const uint8_t *cur_data;
static size_t cur_size;

static void fail(const char *what, const char *f1, const char *f2)
{
    fprintf(stderr, "fuzz_graph: %s\n--- input (%zu bytes):\n%.*s\n--- fmt:\n%s\n--- again:\n%s\n",
            what, cur_size, (int)cur_size, (const char *)cur_data, f1 ? f1 : "", f2 ? f2 : "");
    abort();
}

static uint32_t count_comments(const lg_graph *g)
{
    uint32_t n = g->n_header_comments + g->n_trailing_comments;
    for (uint32_t i = 0; i < g->n_includes; i++)
        n += g->includes[i].n_comments + (g->includes[i].eol_comment != NULL);
    for (uint32_t i = 0; i < g->n_nodes; i++) {
        const lg_gnode *nd = &g->nodes[i];
        if (nd->included)
            continue;
        n += nd->n_comments + nd->n_end_comments + (nd->eol_comment != NULL);
        for (uint32_t j = 0; j < nd->n_assigns; j++)
            n += nd->assigns[j].n_comments + (nd->assigns[j].eol_comment != NULL);
    }
    for (uint32_t i = 0; i < g->n_outputs; i++)
        if (!g->outputs[i].included)
            n += g->outputs[i].n_comments + (g->outputs[i].eol_comment != NULL);
    return n;
}

static bool same_str(const char *a, const char *b)
{
    return (!a && !b) || (a && b && strcmp(a, b) == 0);
}

static bool same_value(const lg_gvalue *a, const lg_gvalue *b)
{
    if (a->kind != b->kind)
        return false;
    switch (a->kind) {
    case LG_GV_BOOL: return a->b == b->b;
    case LG_GV_INT: return a->i == b->i;
    case LG_GV_FLOAT: return memcmp(&a->f, &b->f, sizeof a->f) == 0;
    case LG_GV_STRING: return same_str(a->s, b->s);
    case LG_GV_IDENT: return same_str(a->s, b->s) && same_str(a->port, b->port);
    case LG_GV_LIST:
        if (a->n_items != b->n_items)
            return false;
        for (uint32_t i = 0; i < a->n_items; i++) {
            lg_gitem ta, tb;
            if (!same_value(lg_glist_item(a, i, &ta, false), lg_glist_item(b, i, &tb, false)))
                return false;
        }
        return true;
    default: return false;
    }
}

/* The graph fmt printed, compared with the one read back. */
static const char *same_graph(const lg_graph *a, const lg_graph *b)
{
    if (count_comments(a) != count_comments(b))
        return "the number of comments changed";
    if (a->n_includes != b->n_includes)
        return "includes changed";
    uint32_t j = 0;
    for (uint32_t i = 0; i < a->n_nodes; i++) {
        const lg_gnode *x = &a->nodes[i];
        if (x->included)
            continue;
        while (j < b->n_nodes && b->nodes[j].included)
            j++;
        if (j >= b->n_nodes)
            return "a node was lost";
        const lg_gnode *y = &b->nodes[j++];
        if (strcmp(x->name, y->name) || strcmp(x->type, y->type) || x->n_assigns != y->n_assigns)
            return "a node changed";
        for (uint32_t k = 0; k < x->n_assigns; k++)
            if (strcmp(x->assigns[k].key, y->assigns[k].key) ||
                !same_value(&x->assigns[k].value, &y->assigns[k].value))
                return "a value changed";
    }
    uint32_t nb = 0, na = 0;
    for (uint32_t i = 0; i < a->n_outputs; i++)
        na += !a->outputs[i].included;
    for (uint32_t i = 0; i < b->n_outputs; i++)
        nb += !b->outputs[i].included;
    if (na != nb)
        return "outputs changed";
    return NULL;
}

static void check_order(const lg_checked *c)
{
    uint32_t *pos = lg_xmalloc((c->n_nodes + 1) * sizeof *pos);
    for (uint32_t i = 0; i < c->n_nodes; i++)
        pos[i] = UINT32_MAX;
    for (uint32_t i = 0; i < c->n_nodes; i++) {
        if (c->topo[i] >= c->n_nodes || pos[c->topo[i]] != UINT32_MAX)
            fail("topo is not a permutation", NULL, NULL);
        pos[c->topo[i]] = i;
    }
    for (uint32_t i = 0; i < c->n_nodes; i++)
        for (uint32_t k = 0; k < c->nodes[i].type->n_inputs; k++) {
            int32_t s = c->nodes[i].inputs[k].node;
            if (s >= 0 && pos[s] >= pos[i])
                fail("topo puts a node before its input", NULL, NULL);
        }
    free(pos);
}

static FILE *sink;
static size_t n_parsed, n_checked; /* how deep the inputs went, for the driver's summary */

static void check_and_draw(lg_graph *g, lg_diags *d)
{
    lg_checked *c = lg_graph_check(g, lg_fake_schema(), d);
    if (c) {
        check_order(c);
        n_checked++;
    }
    char *dot = lg_graph_dot(g, c);
    fputs(dot, sink);
    free(dot);
    lg_checked_free(c);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!sink)
        sink = fopen("/dev/null", "w");
    cur_data = data;
    cur_size = size;
    lg_diags d = { 0 };
    lg_graph *g = lg_graph_parse_string("fuzz.lgraph", (const char *)data, size, FUZZ_BASE, &d);
    if (!g && d.errors == 0)
        fail("parse failed without an error", NULL, NULL);
    if (g && d.errors != 0)
        fail("parse succeeded with errors", NULL, NULL);
    if (g) {
        n_parsed++;
        char *f1 = lg_graph_format(g);
        lg_diags d2 = { 0 };
        lg_graph *g2 = lg_graph_parse_string("fuzz.lgraph", f1, strlen(f1), FUZZ_BASE, &d2);
        if (!g2) {
            lg_diags_print(&d2, stderr);
            fail("fmt output does not parse", f1, NULL);
        }
        char *f2 = lg_graph_format(g2);
        if (strcmp(f1, f2) != 0)
            fail("fmt is not idempotent", f1, f2);
        const char *diff = same_graph(g, g2);
        if (diff)
            fail(diff, f1, f2);
        free(f1);
        free(f2);
        lg_graph_free(g2);
        lg_diags_free(&d2);

        check_and_draw(g, &d);
        /* Overrides built from the graph itself: each node's first key set to the text of
         * the next node's first value, and an unknown key. */
        for (uint32_t i = 0; i < g->n_nodes && i < 4; i++) {
            const lg_gnode *n = &g->nodes[i];
            const lg_gnode *m = &g->nodes[(i + 1) % g->n_nodes];
            const char *key = n->n_assigns ? n->assigns[0].key : "key";
            const lg_gvalue *mv = m->n_assigns ? &m->assigns[0].value : NULL;
            lg_str lt = { 0 };
            if (mv && mv->kind == LG_GV_LIST && mv->nums) { /* compact: no text of its own */
                lg_str_addc(&lt, '[');
                for (uint32_t k = 0; k < mv->n_items; k++) {
                    lg_gitem it;
                    lg_str_addf(&lt, "%s%s", k ? ", " : "", lg_glist_item(mv, k, &it, false)->text);
                }
                lg_str_addc(&lt, ']');
            }
            const char *val = lt.s ? lt.s : mv && mv->text ? mv->text : "1";
            char *set = lg_xasprintf("%s.%s=%s", n->name, key, val);
            lg_str_free(&lt);
            lg_graph_set(g, set, &d);
            free(set);
        }
        lg_graph_set(g, "nosuchnode.x=1", &d);
        check_and_draw(g, &d);
        char *f3 = lg_graph_format(g);
        free(f3);
    }
    lg_diags_print(&d, sink);
    lg_diags_free(&d);
    lg_graph_free(g);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* Pieces of graph files, for the driver's "insert a token" edit. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("lightgraph 1\n"),
    LG_FUZZ_TOKEN("lightgraph 2"),
    LG_FUZZ_TOKEN("include \"x.lgraph\"\n"),
    LG_FUZZ_TOKEN("output "),
    LG_FUZZ_TOKEN(" = "),
    LG_FUZZ_TOKEN("{"),
    LG_FUZZ_TOKEN("}"),
    LG_FUZZ_TOKEN("["),
    LG_FUZZ_TOKEN("]"),
    LG_FUZZ_TOKEN(","),
    LG_FUZZ_TOKEN("\""),
    LG_FUZZ_TOKEN("\\"),
    LG_FUZZ_TOKEN("#"),
    LG_FUZZ_TOKEN("\n"),
    LG_FUZZ_TOKEN("\r\n"),
    LG_FUZZ_TOKEN(" "),
    LG_FUZZ_TOKEN("\t"),
    LG_FUZZ_TOKEN("."),
    LG_FUZZ_TOKEN("-"),
    LG_FUZZ_TOKEN("1"),
    LG_FUZZ_TOKEN("0.5"),
    LG_FUZZ_TOKEN("1e999"),
    LG_FUZZ_TOKEN("-0"),
    LG_FUZZ_TOKEN(".5e-3"),
    LG_FUZZ_TOKEN("99999999999999999999"),
    LG_FUZZ_TOKEN("true"),
    LG_FUZZ_TOKEN("false"),
    LG_FUZZ_TOKEN("inf"),
    LG_FUZZ_TOKEN("nan"),
    LG_FUZZ_TOKEN("src"),
    LG_FUZZ_TOKEN("tone"),
    LG_FUZZ_TOKEN("image"),
    LG_FUZZ_TOKEN("reinhard"),
    LG_FUZZ_TOKEN("blur"),
    LG_FUZZ_TOKEN("gbuffer"),
    LG_FUZZ_TOKEN("add"),
    LG_FUZZ_TOKEN("sink"),
    LG_FUZZ_TOKEN("scene"),
    LG_FUZZ_TOKEN("key"),
    LG_FUZZ_TOKEN("kye"),
    LG_FUZZ_TOKEN("backend"),
    LG_FUZZ_TOKEN("gl"),
    LG_FUZZ_TOKEN("image = src"),
    LG_FUZZ_TOKEN("src.out"),
    LG_FUZZ_TOKEN("g.depth"),
    LG_FUZZ_TOKEN("\"out.png\""),
    LG_FUZZ_TOKEN("\"a.jpg\""),
    LG_FUZZ_TOKEN("[1, 2, 3]"),
    LG_FUZZ_TOKEN("[[[["),
    LG_FUZZ_TOKEN("]]]]"),
    LG_FUZZ_TOKEN("\xC3\xA9"),
    LG_FUZZ_TOKEN("\xFF"),
    LG_FUZZ_TOKEN("\0"),
    LG_FUZZ_TOKEN("tone = reinhard { image = src }\n"),
    LG_FUZZ_TOKEN("src = image {}\n"),
    LG_FUZZ_TOKEN("# comment\n"),
    LG_FUZZ_TOKEN(", "),
    LG_FUZZ_TOKEN("{\n"),
    LG_FUZZ_TOKEN("\n}\n"),
    LG_FUZZ_TOKEN("\"\\n\\t\\\"\""),
    LG_FUZZ_TOKEN("output src \"o.exr\"\n"),
};

static void summary(FILE *out)
{
    fprintf(out, "%zu parsed, %zu checks passed", n_parsed, n_checked);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_graph",
        .mutations = 2000,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .summary = summary,
    };
    int rc = lg_fuzz_main(argc, argv, &target);
    if (sink)
        fclose(sink);
    return rc;
}

#endif
