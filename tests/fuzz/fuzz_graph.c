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
 * runs every file of the corpus folders given on the command line, then a fixed number
 * of deterministic mutations of each (bit flips, byte and token insertions, deletions,
 * duplications, truncations, splices with other files), from a fixed-seed PRNG.
 *
 *     fuzz_graph [-n MUTATIONS_PER_FILE] CORPUS_DIR...
 */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fake_schema.h"
#include "graph.h"
#include "util.h"

/* Relative includes resolve here, where nothing exists. */
#define FUZZ_BASE "/nonexistent-lightgraph-fuzz"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

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
        for (uint32_t i = 0; i < a->n_items; i++)
            if (!same_value(&a->items[i], &b->items[i]))
                return false;
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
    lg_diags d = {0};
    lg_graph *g = lg_graph_parse_string("fuzz.lgraph", (const char *)data, size, FUZZ_BASE, &d);
    if (!g && d.errors == 0)
        fail("parse failed without an error", NULL, NULL);
    if (g && d.errors != 0)
        fail("parse succeeded with errors", NULL, NULL);
    if (g) {
        n_parsed++;
        char *f1 = lg_graph_format(g);
        lg_diags d2 = {0};
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
            const char *val = m->n_assigns && m->assigns[0].value.text ? m->assigns[0].value.text
                                                                        : "1";
            char *set = lg_xasprintf("%s.%s=%s", n->name, key, val);
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

typedef struct input {
    char *name;
    uint8_t *data;
    size_t size;
} input;

static uint64_t rng_state = 0x9E3779B97F4A7C15ull;

static uint64_t rnd(void)
{
    /* xorshift64* */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 2685821657736338717ull;
}

static size_t rnd_below(size_t n)
{
    return n ? (size_t)(rnd() % n) : 0;
}

static const char *const tokens[] = {
    "lightgraph 1\n", "lightgraph 2", "include \"x.lgraph\"\n", "output ", " = ", "{", "}",
    "[", "]", ",", "\"", "\\", "#", "\n", "\r\n", " ", "\t", ".", "-", "1", "0.5", "1e999", "-0",
    ".5e-3", "99999999999999999999", "true", "false", "inf", "nan", "src", "tone", "image",
    "reinhard", "blur", "gbuffer", "add", "sink", "scene", "key", "kye", "backend", "gl",
    "image = src", "src.out", "g.depth", "\"out.png\"", "\"a.jpg\"", "[1, 2, 3]", "[[[[", "]]]]",
    "\xC3\xA9", "\xFF", "\0", "tone = reinhard { image = src }\n", "src = image {}\n",
    "# comment\n", ", ", "{\n", "\n}\n", "\"\\n\\t\\\"\"", "output src \"o.exr\"\n",
};

/* One to four edits of `in`, into a new buffer. */
static uint8_t *mutate(const input *in, const input *all, size_t n_all, size_t *out_size)
{
    size_t cap = in->size * 2 + 256;
    uint8_t *b = lg_xmalloc(cap);
    size_t n = in->size;
    memcpy(b, in->data, n);
    int edits = 1; /* one edit half the time: most mutants stay close to a valid graph */
    while (edits < 4 && rnd_below(2))
        edits++;
    for (int e = 0; e < edits; e++) {
        size_t at = rnd_below(n + 1);
        switch (rnd_below(8)) {
        case 0: /* flip a bit */
            if (n)
                b[rnd_below(n)] ^= (uint8_t)(1u << rnd_below(8));
            break;
        case 1: /* replace a byte */
            if (n)
                b[rnd_below(n)] = (uint8_t)rnd();
            break;
        case 2: { /* insert a token */
            const char *t = tokens[rnd_below(sizeof tokens / sizeof *tokens)];
            size_t tl = t[0] ? strlen(t) : 1;
            if (n + tl > cap)
                break;
            memmove(b + at + tl, b + at, n - at);
            memcpy(b + at, t, tl);
            n += tl;
            break;
        }
        case 3: { /* delete a span */
            size_t len = rnd_below(n - (at < n ? at : n) + 1);
            if (len > 32 && rnd_below(4))
                len = rnd_below(32);
            memmove(b + at, b + at + len, n - at - len);
            n -= len;
            break;
        }
        case 4: { /* copy a span somewhere else */
            if (!n)
                break;
            size_t from = rnd_below(n), len = rnd_below(n - from + 1);
            if (len > 64)
                len = rnd_below(64);
            if (n + len > cap)
                break;
            uint8_t tmp[64];
            memcpy(tmp, b + from, len);
            memmove(b + at + len, b + at, n - at);
            memcpy(b + at, tmp, len);
            n += len;
            break;
        }
        case 5: /* truncate */
            n = at;
            break;
        case 6: { /* splice: our head, another file's tail */
            const input *o = &all[rnd_below(n_all)];
            size_t from = rnd_below(o->size + 1), len = o->size - from;
            if (at + len > cap)
                len = cap - at;
            memcpy(b + at, o->data + from, len);
            n = at + len;
            break;
        }
        default: { /* swap two bytes */
            if (n < 2)
                break;
            size_t i = rnd_below(n), j = rnd_below(n);
            uint8_t t = b[i];
            b[i] = b[j];
            b[j] = t;
        }
        }
    }
    *out_size = n;
    return b;
}

static int cmp_input(const void *a, const void *b)
{
    return strcmp(((const input *)a)->name, ((const input *)b)->name);
}

int main(int argc, char **argv)
{
    long per_file = 2000;
    input *in = NULL;
    size_t n_in = 0, cap = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "-n") == 0 && i + 1 < argc) {
            per_file = strtol(argv[++i], NULL, 10);
            continue;
        }
        DIR *dp = opendir(argv[i]);
        if (!dp) {
            perror(argv[i]);
            return 2;
        }
        struct dirent *e;
        while ((e = readdir(dp))) {
            if (e->d_name[0] == '.')
                continue;
            char *path = lg_path_join(argv[i], e->d_name);
            size_t len;
            char *text = lg_read_file(path, &len);
            if (!text) {
                free(path);
                continue;
            }
            if (n_in == cap) {
                cap = cap ? cap * 2 : 32;
                in = lg_xrealloc(in, cap * sizeof *in);
            }
            in[n_in++] = (input){path, (uint8_t *)text, len};
        }
        closedir(dp);
    }
    if (n_in == 0) {
        fprintf(stderr, "usage: %s [-n MUTATIONS_PER_FILE] CORPUS_DIR...\n", argv[0]);
        return 2;
    }
    qsort(in, n_in, sizeof *in, cmp_input);
    double t0 = lg_now();
    for (size_t i = 0; i < n_in; i++)
        LLVMFuzzerTestOneInput(in[i].data, in[i].size);
    size_t runs = n_in;
    for (size_t i = 0; i < n_in; i++) {
        for (long m = 0; m < per_file; m++) {
            size_t size;
            uint8_t *b = mutate(&in[i], in, n_in, &size);
            LLVMFuzzerTestOneInput(b, size);
            free(b);
            runs++;
        }
    }
    printf("fuzz_graph: %zu inputs (%zu files, %ld mutations each) in %.2f s; %zu parsed, "
           "%zu checks passed\n", runs, n_in, per_file, lg_now() - t0, n_parsed, n_checked);
    for (size_t i = 0; i < n_in; i++) {
        free(in[i].name);
        free(in[i].data);
    }
    free(in);
    if (sink)
        fclose(sink);
    return 0;
}

#endif
