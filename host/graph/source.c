/*
 * host/graph/source.c: the pool behind an lg_graph: the texts it came from (files, strings,
 * --set assignments), their lines found by position, and messages at a position of them.
 */
#include "graph/parse_priv.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"

source *lg_source_add(pool *pl, const char *name, const char *text, size_t len, uint32_t first_line,
                      bool take)
{
    source *s = lg_arena_zalloc(&pl->a, sizeof *s);
    s->name = lg_arena_strdup(&pl->a, name);
    if (take)
        s->text = s->owned = (char *)text;
    else
        s->text = lg_arena_strndup(&pl->a, text, len);
    s->len = (uint32_t)len;
    s->first_line = first_line;
    s->seen_line = first_line;
    s->seen_off = 0;
    if (pl->n_src == pl->cap_src) {
        pl->cap_src = pl->cap_src ? pl->cap_src * 2 : 8;
        pl->src = lg_xrealloc(pl->src, pl->cap_src * sizeof *pl->src);
    }
    pl->src[pl->n_src++] = s;
    return s;
}

const char *lg_source_line(source *s, uint32_t line, size_t *n)
{
    if (line < s->first_line)
        return NULL;
    uint32_t l = s->seen_line, off = s->seen_off;
    if (line < l) {
        l = s->first_line;
        off = 0;
    }
    while (l < line) {
        const char *nl = memchr(s->text + off, '\n', s->len - off);
        if (!nl)
            return NULL;
        off = (uint32_t)(nl - s->text) + 1;
        l++;
    }
    s->seen_line = l;
    s->seen_off = off;
    uint32_t b = off;
    const char *nl = memchr(s->text + off, '\n', s->len - off);
    b = nl ? (uint32_t)(nl - s->text) : s->len;
    while (b > off && s->text[b - 1] == '\r')
        b--;
    *n = b - off;
    return s->text + off;
}

source *lg_pool_source(const pool *pl, const char *name)
{
    for (uint32_t i = 0; i < pl->n_src; i++)
        if (pl->src[i]->name == name)
            return pl->src[i];
    return NULL;
}

void lg_vreport(session *s, source *src, lg_diag_level lvl, uint32_t line, uint32_t col,
                uint32_t len, const char *fmt, va_list ap)
{
    if (s->stop)
        return;
    char *msg = lg_vformat(fmt, ap);
    size_t n = 0;
    const char *text = src ? lg_source_line(src, line, &n) : NULL;
    lg_srcloc loc = { src ? src->name : NULL, line, col, len };
    lg_diags_add_line(s->d, lvl, loc, text, n, "%s", msg);
    free(msg);
    if (lvl == LG_DIAG_ERROR && ++s->errors >= MAX_ERRORS) {
        lg_srcloc none = { src ? src->name : NULL, 0, 0, 0 };
        lg_diags_add(s->d, LG_DIAG_NOTE, none, NULL, "too many errors (%u); stopping here",
                     s->errors);
        s->stop = true;
    }
}

/* A message at token t of the file p is parsing. */
void lg_tok_report(parser *p, const tok *t, lg_diag_level lvl, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    lg_vreport(p->s, p->src, lvl, t->line, t->col, t->len, fmt, ap);
    va_end(ap);
}

void lg_report(session *s, source *src, lg_diag_level lvl, uint32_t line, uint32_t col,
               uint32_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    lg_vreport(s, src, lvl, line, col, len, fmt, ap);
    va_end(ap);
}

void lg_graph_free(lg_graph *g)
{
    if (!g)
        return;
    pool *pl = g->pool;
    if (pl) {
        for (uint32_t i = 0; i < pl->n_src; i++)
            free(pl->src[i]->owned);
        lg_arena_free(&pl->a);
        free(pl->src);
        lg_strmap_free(&pl->nodes);
        free(pl);
    }
    free(g);
}

int32_t lg_graph_find_node(const lg_graph *g, const char *name)
{
    pool *pl = g->pool;
    if (pl) {
        uint32_t i = lg_strmap_find(&pl->nodes, name);
        return i == STRMAP_NONE || i >= g->n_nodes ? -1 : (int32_t)i;
    }
    for (uint32_t i = 0; i < g->n_nodes; i++)
        if (strcmp(g->nodes[i].name, name) == 0)
            return (int32_t)i;
    return -1;
}

void lg_graph_diag(lg_diags *d, const lg_graph *g, lg_diag_level level, lg_srcloc loc,
                   const char *fmt, ...)
{
    const char *text = NULL;
    size_t n = 0;
    const pool *pl = g ? g->pool : NULL;
    source *src = pl ? lg_pool_source(pl, loc.file) : NULL;
    if (src)
        text = lg_source_line(src, loc.line, &n);
    va_list ap;
    va_start(ap, fmt);
    char *msg = lg_vformat(fmt, ap);
    va_end(ap);
    lg_diags_add_line(d, level, loc, text, n, "%s", msg);
    free(msg);
}

uint32_t lg_graph_files(const lg_graph *g, char ***out)
{
    const pool *pl = g->pool;
    char **files = lg_xcalloc(pl->n_src + 1, sizeof *files);
    uint32_t n = 0;
    for (uint32_t i = 0; i < pl->n_src; i++) {
        const source *s = pl->src[i];
        if (s->first_line != 1 || strcmp(s->name, "<command line>") == 0)
            continue;
        files[n++] = lg_path_absolute(s->name);
    }
    *out = files;
    return n;
}
