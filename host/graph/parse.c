/*
 * host/graph/parse.c: graph files, tokens -> lg_graph (docs/graph-format.md is the spec):
 * the grammar, and the entry points lg_graph_parse_file / _string. The text is split into
 * tokens first (lexer.c); parse_priv.h says which file does what.
 *
 * The parser is a recursive descent with one token of lookahead (two to tell
 * `output x "f"` from a node called `output`); only lists recurse, and their nesting is
 * limited. After an error it skips to the next entry or statement and goes on, so that one
 * run reports many problems, up to MAX_ERRORS.
 *
 * Everything a graph points to lives in one arena (the pool), freed by lg_graph_free.
 */
#include "graph/parse_priv.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/util.h"

/* ---- parser helpers -------------------------------------------------------------------------- */

static tok *peek_at(parser *p, uint32_t k)
{
    return &p->t[p->cur + k < p->nt ? p->cur + k : p->nt - 1];
}

/* Steps over the current token; a lexical error is reported now. */
static void advance(parser *p)
{
    tok *t = peek(p);
    if (t->kind == T_EOF)
        return;
    if (t->kind == T_ERR)
        lg_tok_report(p, t, LG_DIAG_ERROR, "%s", t->s);
    p->cur++;
}

bool lg_skip_nl(parser *p)
{
    bool any = false;
    while (peek(p)->kind == T_NL) {
        p->cur++;
        any = true;
    }
    return any;
}

/* How a token is named in "found ..." */
static const char *describe(const parser *p, const tok *t, char buf[80])
{
    switch (t->kind) {
    case T_EOF: return "the end of the file";
    case T_NL: return "the end of the line";
    case T_STRING: return "a string";
    case T_EQ: return "'='";
    case T_LBRACE: return "'{'";
    case T_RBRACE: return "'}'";
    case T_LBRACK: return "'['";
    case T_RBRACK: return "']'";
    case T_COMMA: return "','";
    case T_IDENT:
        if (t->port)
            snprintf(buf, 80, "'%.30s.%.30s'", t->s, t->port);
        else
            snprintf(buf, 80, "'%.60s'", t->s);
        return buf;
    case T_INT:
    case T_FLOAT:
    case T_NUMS:
        snprintf(buf, 80, "'%.*s'", (int)(t->len < 60 ? t->len : 60), p->src->text + t->off);
        return buf;
    default: return "an invalid token";
    }
}

/* Reports "expected ..., found X" at the current token, unless the token is a lexical
 * error, which speaks for itself. */
static void expected(parser *p, const char *what)
{
    tok *t = peek(p);
    if (t->kind == T_ERR) {
        advance(p);
        return;
    }
    char buf[80];
    lg_tok_report(p, t, LG_DIAG_ERROR, "expected %s, found %s", what, describe(p, t, buf));
}

/* After an error in an entry: skips to the ',' , new line or '}' that ends it (not
 * consumed), stepping over whole lists. */
static void recover_entry(parser *p)
{
    int depth = p->list_depth;
    p->list_depth = 0;
    for (;;) {
        tok *t = peek(p);
        switch (t->kind) {
        case T_EOF:
        case T_RBRACE: return;
        case T_LBRACK: depth++; break;
        case T_RBRACK:
            if (depth > 0)
                depth--;
            break;
        case T_COMMA:
        case T_NL:
            if (depth == 0)
                return;
            break;
        default: break;
        }
        advance(p);
    }
}

/* After an error in an entry: skips it and the ',' that ends it. */
static void skip_entry(parser *p)
{
    recover_entry(p);
    if (peek(p)->kind == T_COMMA)
        advance(p);
}

/* After an error in a statement: skips to the end of its line, or of its braces. */
static void recover_statement(parser *p)
{
    int depth = 0;
    p->list_depth = 0;
    for (;;) {
        tok *t = peek(p);
        if (t->kind == T_EOF)
            return;
        if (t->kind == T_NL && depth <= 0)
            return;
        if (t->kind == T_LBRACE)
            depth++;
        else if (t->kind == T_RBRACE)
            depth--;
        advance(p);
    }
}

static void set_loc(parser *p, lg_srcloc *l, const tok *t)
{
    l->file = p->src->name;
    l->line = t->line;
    l->col = t->col;
    l->len = t->len;
}

/* A growing array of comment strings. */
typedef struct cvec {
    char **v;
    uint32_t n, cap;
} cvec;

static void cvec_push(cvec *c, char *s)
{
    if (c->n == c->cap) {
        c->cap = c->cap ? c->cap * 2 : 4;
        c->v = lg_xrealloc(c->v, c->cap * sizeof *c->v);
    }
    c->v[c->n++] = s;
}

static void cvec_above(parser *p, cvec *c, const tok *t)
{
    for (uint32_t i = 0; i < t->c_n; i++)
        cvec_push(c, p->cm[t->c_first + i]);
}

/* The comments inside tokens [from, to] that have no place of their own: those above every
 * token but the first, and those ending the line of every token but the last. */
static void cvec_inner(parser *p, cvec *c, uint32_t from, uint32_t to)
{
    for (uint32_t i = from; i <= to && i < p->nt; i++) {
        if (i > from)
            cvec_above(p, c, &p->t[i]);
        if (i < to && p->t[i].eol >= 0)
            cvec_push(c, p->cm[p->t[i].eol]);
    }
}

/* Drops the blank-line markers at the end (before a '}' or the end of the file they mean
 * nothing). */
static void cvec_trim(cvec *c)
{
    while (c->n > 0 && c->v[c->n - 1][0] == 0)
        c->n--;
}

static char **cvec_finish(parser *p, cvec *c, uint32_t *n)
{
    *n = c->n;
    char **r = lg_arena_copy(parena(p), c->v, c->n * sizeof *c->v);
    free(c->v);
    memset(c, 0, sizeof *c);
    return r;
}

static char *eol_of(parser *p, uint32_t k)
{
    return p->t[k].eol >= 0 ? p->cm[p->t[k].eol] : NULL;
}

/* The comments of a one-line statement (tokens [first, last], `first` its keyword): those
 * above it and inside it, and the one that ends its line. */
static char **stmt_comments(parser *p, uint32_t first, uint32_t last, uint32_t *n, char **eol)
{
    cvec c = { 0 };
    cvec_above(p, &c, &p->t[first]);
    cvec_inner(p, &c, first, last);
    *eol = eol_of(p, last);
    return cvec_finish(p, &c, n);
}

/* ---- values ---------------------------------------------------------------------------------- */

/* items[n] of a growing array of *cap values (grown as needed; malloc'd). */
static lg_gvalue *grow_items(lg_gvalue **items, uint32_t n, uint32_t *cap)
{
    if (n == *cap) {
        *cap = *cap ? *cap * 2 : 4;
        *items = lg_xrealloc(*items, *cap * sizeof **items);
    }
    return &(*items)[n];
}

static bool parse_list(parser *p, lg_gvalue *v)
{
    tok *open = peek(p);
    if (p->list_depth >= MAX_LIST_DEPTH) {
        lg_tok_report(p, open, LG_DIAG_ERROR, "lists are nested more than %d deep", MAX_LIST_DEPTH);
        return false;
    }
    p->list_depth++;
    advance(p);
    lg_gvalue *items = NULL;
    uint32_t n = 0, cap = 0;
    bool sep = true; /* a separator (or the '[') came since the last item */
    tok *close = NULL;
    /* A list of numbers only (up to its ']') is kept compact: lg_gnums, no lg_gvalue per
     * item; a list that is one T_NUMS run takes that run's arrays as they are. */
    uint32_t total = 0, runs = 0, plain = 0;
    bool compact = true;
    for (uint32_t k = p->cur; compact && k < p->nt; k++) {
        const tok *t = &p->t[k];
        if (t->kind == T_RBRACK)
            break;
        if (t->kind == T_NUMS) {
            total += ((const numrun *)(const void *)t->s)->n;
            runs++;
        } else if (t->kind == T_INT || t->kind == T_FLOAT) {
            if (t->len > LG_GNUM_MAX_TEXT || t->off + t->len > TAG_OFF_MASK)
                compact = false;
            total++;
            plain++;
        } else if (t->kind != T_COMMA && t->kind != T_NL) {
            compact = false;
        }
    }
    compact = compact && total > 0;
    lg_gnums *nums = NULL;
    if (compact) {
        nums = lg_arena_zalloc(parena(p), sizeof *nums);
        nums->at = p->src->text + open->off;
        if (!(runs == 1 && plain == 0)) {
            nums->tag = lg_arena_alloc(parena(p), total * sizeof *nums->tag);
            nums->val = lg_arena_alloc(parena(p), total * sizeof *nums->val);
        }
    }
    for (;;) {
        if (lg_skip_nl(p))
            sep = true;
        tok *t = peek(p);
        if (t->kind == T_RBRACK) {
            close = t;
            advance(p);
            break;
        }
        if (t->kind == T_EOF) {
            lg_tok_report(p, open, LG_DIAG_ERROR, "'[' is never closed");
            goto fail;
        }
        if (t->kind == T_COMMA && sep) {
            expected(p, "a list item or ']'");
            goto fail;
        }
        if (!sep) {
            expected(p, "',' or ']' after a list item");
            goto fail;
        }
        if (compact) {
            if (t->kind == T_NUMS) {
                numrun *run = (numrun *)(void *)t->s;
                if (!nums->tag) { /* the list's only run: its arrays become the list's */
                    nums->tag = run->tag;
                    nums->val = run->val;
                } else {
                    memcpy(nums->val + n, run->val, run->n * sizeof *run->val);
                    memcpy(nums->tag + n, run->tag, run->n * sizeof *run->tag);
                }
                for (uint32_t j = 0; j < run->n; j++) {
                    uint32_t g = nums->tag[n + j];
                    nums->tag[n + j] = make_tag((g & TAG_OFF_MASK) - open->off, (g >> 24) & 0x7F,
                                                (g & TAG_FLOAT) != 0);
                }
                n += run->n;
            } else { /* T_INT or T_FLOAT */
                bool f = t->kind == T_FLOAT;
                nums->tag[n] = make_tag(t->off - open->off, t->len, f);
                if (f)
                    nums->val[n].f = t->f;
                else
                    nums->val[n].i = t->i;
                n++;
            }
            advance(p);
        } else if (t->kind == T_NUMS) {
            /* In a list that is not all numbers: an lg_gvalue for each (on t's line). */
            const numrun *run = (const numrun *)(const void *)t->s;
            for (uint32_t j = 0; j < run->n; j++) {
                lg_gvalue *it = grow_items(&items, n++, &cap);
                memset(it, 0, sizeof *it);
                uint32_t g = run->tag[j], off = g & TAG_OFF_MASK, len = (g >> 24) & 0x7F;
                it->base_dir = p->base_dir;
                it->loc.file = p->src->name;
                it->loc.line = t->line;
                it->loc.col = t->col + (off - t->off);
                it->loc.len = len;
                if (g & TAG_FLOAT) {
                    it->kind = LG_GV_FLOAT;
                    it->f = run->val[j].f;
                } else {
                    it->kind = LG_GV_INT;
                    it->i = run->val[j].i;
                }
                it->text = lg_arena_strndup(parena(p), p->src->text + off, len);
            }
            advance(p);
        } else {
            if (!lg_parse_value(p, grow_items(&items, n, &cap)))
                goto fail;
            n++;
        }
        sep = false;
        if (lg_skip_nl(p))
            sep = true;
        if (peek(p)->kind == T_COMMA) {
            advance(p);
            sep = true;
        }
    }
    p->list_depth--;
    v->kind = LG_GV_LIST;
    if (compact) {
        v->items = NULL;
        v->nums = nums;
    } else {
        v->items = lg_arena_copy(parena(p), items, n * sizeof *items);
    }
    v->n_items = n;
    free(items);
    set_loc(p, &v->loc, open);
    if (close->line == open->line)
        v->loc.len = close->off + 1 - open->off;
    /* A compact list is not copied again as text (lg_gvalue.text) */
    if (!compact)
        v->text = lg_arena_strndup(parena(p), p->src->text + open->off, close->off + 1 - open->off);
    return true;
fail:
    free(items);
    return false;
}

bool lg_parse_value(parser *p, lg_gvalue *v)
{
    tok *t = peek(p);
    memset(v, 0, sizeof *v);
    v->base_dir = p->base_dir;
    set_loc(p, &v->loc, t);
    switch (t->kind) {
    case T_INT:
        v->kind = LG_GV_INT;
        v->i = t->i;
        break;
    case T_FLOAT:
        v->kind = LG_GV_FLOAT;
        v->f = t->f;
        break;
    case T_STRING:
        v->kind = LG_GV_STRING;
        v->s = t->s;
        break;
    case T_IDENT:
        if (!t->port && (strcmp(t->s, "true") == 0 || strcmp(t->s, "false") == 0)) {
            v->kind = LG_GV_BOOL;
            v->b = t->s[0] == 't';
        } else {
            v->kind = LG_GV_IDENT;
            v->s = t->s;
            v->port = t->port;
        }
        break;
    case T_LBRACK: return parse_list(p, v);
    default: expected(p, "a value"); return false;
    }
    v->text = lg_arena_strndup(parena(p), p->src->text + t->off, t->len);
    advance(p);
    return true;
}

/* ---- statements ------------------------------------------------------------------------------ */

static bool expect_eol(parser *p, const char *after)
{
    tok *t = peek(p);
    if (t->kind == T_NL || t->kind == T_EOF)
        return true;
    char what[96];
    snprintf(what, sizeof what, "a new line after %s", after);
    expected(p, what);
    recover_statement(p);
    return false;
}

static const char *const reserved_words[] = { "lightgraph", "include", "output", "true", "false" };

static bool is_reserved(const char *s)
{
    for (size_t i = 0; i < sizeof reserved_words / sizeof *reserved_words; i++)
        if (strcmp(s, reserved_words[i]) == 0)
            return true;
    return false;
}

static void add_node(parser *p, lg_gnode *n)
{
    session *s = p->s;
    uint32_t prev = lg_strmap_find(&s->pl->nodes, n->name);
    if (prev != STRMAP_NONE) {
        const lg_gnode *f = &s->nodes[prev];
        lg_report(s, p->src, LG_DIAG_ERROR, n->loc.line, n->loc.col, n->loc.len,
                  "node '%s' is defined twice", n->name);
        lg_report(s, lg_pool_source(s->pl, f->loc.file), LG_DIAG_NOTE, f->loc.line, f->loc.col,
                  f->loc.len, "'%s' was first defined here", n->name);
        return;
    }
    if (s->n_nodes >= MAX_NODES) {
        lg_report(s, p->src, LG_DIAG_ERROR, n->loc.line, n->loc.col, n->loc.len,
                  "the graph has more than %u nodes (its includes counted); that is the limit",
                  MAX_NODES);
        s->stop = true; /* one message, not one per node */
        return;
    }
    if (s->n_nodes == s->cap_nodes) {
        s->cap_nodes = s->cap_nodes ? s->cap_nodes * 2 : 16;
        s->nodes = lg_xrealloc(s->nodes, s->cap_nodes * sizeof *s->nodes);
    }
    lg_strmap_put(&s->pl->nodes, n->name, s->n_nodes);
    s->nodes[s->n_nodes++] = *n;
}

/* NAME = TYPE { key = value, ... } */
static void parse_node(parser *p)
{
    uint32_t first = p->cur;
    tok *name = peek(p);
    lg_gnode n;
    memset(&n, 0, sizeof n);
    n.name = name->s;
    set_loc(p, &n.loc, name);
    n.blank_before = name->blank_before;
    n.included = p->included;
    cvec above = { 0 }, end = { 0 };
    cvec_above(p, &above, name);

    if (name->port)
        lg_tok_report(p, name, LG_DIAG_ERROR, "a node name cannot contain '.'");
    else if (is_reserved(name->s))
        lg_tok_report(p, name, LG_DIAG_ERROR, "'%s' is a reserved word and cannot name a node",
                      name->s);
    advance(p); /* name */
    advance(p); /* = */
    tok *type = peek(p);
    if (type->kind != T_IDENT || type->port) {
        if (type->kind == T_IDENT)
            lg_tok_report(p, type, LG_DIAG_ERROR, "a node type cannot contain '.'");
        else
            expected(p, "a node type after '='");
        recover_statement(p);
        free(above.v);
        return;
    }
    n.type = type->s;
    set_loc(p, &n.type_loc, type);
    advance(p);
    uint32_t before_nl = p->cur;
    lg_skip_nl(p);
    if (peek(p)->kind != T_LBRACE) {
        /* Complain at the end of the type's line, not on the next statement. */
        p->cur = before_nl;
        char what[96];
        snprintf(what, sizeof what, "'{' after the node type '%.60s'", n.type);
        expected(p, what);
        recover_statement(p);
        free(above.v);
        return;
    }
    uint32_t lbrace = p->cur;
    cvec_inner(p, &above, first, lbrace);
    n.eol_comment = eol_of(p, lbrace);
    advance(p);

    lg_gassign *as = NULL;
    uint32_t na = 0, cap = 0;
    strmap keys = { 0 };
    for (;;) {
        lg_skip_nl(p);
        tok *t = peek(p);
        if (t->kind == T_RBRACE) {
            cvec_above(p, &end, t);
            char *e = eol_of(p, p->cur);
            if (e && !n.eol_comment)
                n.eol_comment = e;
            else if (e)
                cvec_push(&above, e);
            advance(p);
            expect_eol(p, "'}'");
            break;
        }
        if (t->kind == T_EOF) {
            tok *lb = &p->t[lbrace];
            lg_tok_report(p, lb, LG_DIAG_ERROR, "'{' of node '%s' is never closed", n.name);
            cvec_above(p, &end, t);
            break;
        }
        if (p->s->stop)
            break;
        if (t->kind != T_IDENT) {
            char what[120];
            snprintf(what, sizeof what, "a key or '}' in node '%.60s'", n.name);
            expected(p, what);
            skip_entry(p);
            continue;
        }
        /* key = value */
        uint32_t kidx = p->cur;
        lg_gassign a;
        memset(&a, 0, sizeof a);
        a.key = t->s;
        a.blank_before = t->blank_before;
        set_loc(p, &a.key_loc, t);
        bool ok = true;
        if (t->port) {
            lg_tok_report(p, t, LG_DIAG_ERROR, "a key cannot contain '.'");
            ok = false;
        }
        advance(p);
        if (ok && peek(p)->kind != T_EQ) {
            char what[96];
            snprintf(what, sizeof what, "'=' after the key '%.60s'", a.key);
            expected(p, what);
            ok = false;
        }
        if (ok) {
            advance(p);
            lg_skip_nl(p);
            ok = lg_parse_value(p, &a.value);
        }
        if (!ok) {
            skip_entry(p);
            continue;
        }
        /* The entry's own comments: above its key, and at the end of its line (after the
         * value or after the comma that follows it there). Any other comment inside it
         * moves above it. */
        uint32_t last = p->cur - 1; /* the value's last token */
        int32_t late_comma = -1;    /* a comma that starts the next line (comma-first) */
        tok *sep = peek(p);
        if (sep->kind == T_COMMA) {
            last = p->cur;
            advance(p);
        } else if (sep->kind == T_NL) {
            uint32_t save = p->cur;
            lg_skip_nl(p);
            if (peek(p)->kind == T_COMMA) {
                late_comma = (int32_t)p->cur;
                advance(p);
            } else {
                p->cur = save;
            }
        } else if (sep->kind != T_RBRACE) {
            char what[120];
            snprintf(what, sizeof what, "',' or a new line after the value of '%.60s'", a.key);
            expected(p, what);
            skip_entry(p);
        }
        cvec ac = { 0 };
        cvec_above(p, &ac, &p->t[kidx]);
        cvec_inner(p, &ac, kidx, last);
        a.eol_comment = eol_of(p, last);
        if (late_comma >= 0) {
            cvec_above(p, &ac, &p->t[late_comma]);
            if (p->t[late_comma].eol >= 0)
                cvec_push(&ac, p->cm[p->t[late_comma].eol]);
        }
        a.comments = cvec_finish(p, &ac, &a.n_comments);

        uint32_t prev = lg_strmap_find(&keys, a.key);
        if (prev != STRMAP_NONE) {
            lg_tok_report(p, &p->t[kidx], LG_DIAG_ERROR, "key '%s' is set twice in node '%s'",
                          a.key, n.name);
            lg_report(p->s, p->src, LG_DIAG_NOTE, as[prev].key_loc.line, as[prev].key_loc.col,
                      as[prev].key_loc.len, "'%s' was first set here", a.key);
            continue;
        }
        if (na == cap) {
            cap = cap ? cap * 2 : 8;
            as = lg_xrealloc(as, cap * sizeof *as);
        }
        lg_strmap_put(&keys, a.key, na);
        as[na++] = a;
    }
    lg_strmap_free(&keys);
    n.assigns = lg_arena_copy(parena(p), as, na * sizeof *as);
    n.n_assigns = na;
    free(as);
    n.comments = cvec_finish(p, &above, &n.n_comments);
    cvec_trim(&end);
    n.end_comments = cvec_finish(p, &end, &n.n_end_comments);
    add_node(p, &n);
}

/* output REF "path" [half | float] */
static void parse_output(parser *p)
{
    uint32_t first = p->cur;
    tok *kw = peek(p);
    lg_goutput o;
    memset(&o, 0, sizeof o);
    o.blank_before = kw->blank_before;
    o.included = p->included;
    o.base_dir = p->base_dir;
    advance(p);
    tok *r = peek(p);
    if (r->kind != T_IDENT) {
        expected(p, "the node to write after 'output' (output NODE \"file.png\")");
        recover_statement(p);
        return;
    }
    o.ref.kind = LG_GV_IDENT;
    o.ref.s = r->s;
    o.ref.port = r->port;
    o.ref.base_dir = p->base_dir;
    set_loc(p, &o.ref.loc, r);
    o.ref.text = lg_arena_strndup(parena(p), p->src->text + r->off, r->len);
    advance(p);
    tok *f = peek(p);
    if (f->kind != T_STRING) {
        char what[120];
        snprintf(what, sizeof what,
                 "the file name after 'output %.60s' (a string such as "
                 "\"out.png\")",
                 o.ref.text);
        expected(p, what);
        recover_statement(p);
        return;
    }
    uint32_t last = p->cur;
    o.path = f->s;
    set_loc(p, &o.path_loc, f);
    if (!o.path[0])
        lg_tok_report(p, f, LG_DIAG_ERROR, "the output file name is empty");
    advance(p);
    /* optional: the EXR pixel type, half or float */
    tok *x = peek(p);
    if (x->kind == T_IDENT && (!strcmp(x->s, "half") || !strcmp(x->s, "float"))) {
        size_t n = strlen(o.path);
        if (n < 4 || strcasecmp(o.path + n - 4, ".exr") != 0)
            lg_tok_report(p, x, LG_DIAG_ERROR,
                          "'%s' chooses the pixel type of an .exr output; "
                          "'%.60s' is not one",
                          x->s, o.path);
        o.exr_pixel = x->s[0] == 'h' ? LG_OUT_EXR_HALF : LG_OUT_EXR_FLOAT;
        last = p->cur;
        advance(p);
    }
    if (!expect_eol(p, "the output statement"))
        return;
    o.comments = stmt_comments(p, first, last, &o.n_comments, &o.eol_comment);
    session *s = p->s;
    if (s->n_outputs == s->cap_outputs) {
        s->cap_outputs = s->cap_outputs ? s->cap_outputs * 2 : 4;
        s->outputs = lg_xrealloc(s->outputs, s->cap_outputs * sizeof *s->outputs);
    }
    s->outputs[s->n_outputs++] = o;
}

/* include "path" */
static void parse_include(parser *p)
{
    uint32_t first = p->cur;
    advance(p);
    tok *f = peek(p);
    if (f->kind != T_STRING) {
        expected(p, "a file name after 'include' (include \"other.lgraph\")");
        recover_statement(p);
        return;
    }
    uint32_t last = p->cur;
    advance(p);
    if (!expect_eol(p, "the include statement"))
        return;
    if (!f->s[0]) {
        lg_tok_report(p, f, LG_DIAG_ERROR, "the include file name is empty");
        return;
    }
    if (!p->included) {
        session *s = p->s;
        lg_ginclude inc;
        memset(&inc, 0, sizeof inc);
        inc.path = f->s;
        set_loc(p, &inc.loc, f);
        inc.comments = stmt_comments(p, first, last, &inc.n_comments, &inc.eol_comment);
        if (s->n_includes == s->cap_includes) {
            s->cap_includes = s->cap_includes ? s->cap_includes * 2 : 4;
            s->includes = lg_xrealloc(s->includes, s->cap_includes * sizeof *s->includes);
        }
        s->includes[s->n_includes++] = inc;
    }
    /* include.c opens the file; it is parsed here, so that include.c needs nothing of the
     * parser's (the recursion stays in this file) */
    const char *base_dir = NULL;
    source *src = lg_include_open(p, f, &base_dir);
    if (src) {
        lg_parse_source(p->s, src, base_dir, true);
        p->s->depth--;
    }
}

/* A whole file: the version line, then statements. */
static void parse_body(parser *p)
{
    session *s = p->s;
    lg_graph *g = s->g;
    lg_skip_nl(p);
    tok *t = peek(p);
    if (!p->included) {
        cvec hc = { 0 };
        if (t->kind != T_EOF)
            cvec_above(p, &hc, t);
        g->header_comments = cvec_finish(p, &hc, &g->n_header_comments);
    }
    if (t->kind == T_IDENT && !t->port && strcmp(t->s, "lightgraph") == 0 &&
        peek_at(p, 1)->kind != T_EQ) {
        advance(p);
        tok *v = peek(p);
        char buf[80];
        if (v->kind == T_INT && v->i == 1) {
            advance(p);
            if (!p->included && v->eol >= 0) {
                /* The version line's own comment moves above it. */
                char **hc = lg_arena_alloc(parena(p), (g->n_header_comments + 1) * sizeof *hc);
                if (g->n_header_comments)
                    memcpy(hc, g->header_comments, g->n_header_comments * sizeof *hc);
                hc[g->n_header_comments++] = p->cm[v->eol];
                g->header_comments = hc;
            }
            if (!expect_eol(p, "the version line"))
                return;
        } else if (v->kind == T_INT && v->i > 1) {
            lg_tok_report(p, v, LG_DIAG_ERROR,
                          "graph format version %lld is newer than this "
                          "lightgraph reads (version 1)",
                          (long long)v->i);
            return;
        } else if (v->kind == T_INT || v->kind == T_FLOAT) {
            lg_tok_report(p, v, LG_DIAG_ERROR,
                          "unknown graph format version '%.*s' (this "
                          "lightgraph reads version 1)",
                          (int)v->len, p->src->text + v->off);
            return;
        } else {
            if (v->kind == T_ERR)
                advance(p);
            else
                lg_tok_report(p, v, LG_DIAG_ERROR,
                              "expected a version number after 'lightgraph' "
                              "(lightgraph 1), found %s",
                              describe(p, v, buf));
            return;
        }
    } else if (t->kind == T_EOF) {
        lg_tok_report(p, t, LG_DIAG_ERROR,
                      "missing version line: a graph file starts with "
                      "'lightgraph 1' (this file has no statements)");
        return;
    } else {
        char buf[80];
        if (t->kind == T_ERR)
            advance(p);
        else
            lg_tok_report(p, t, LG_DIAG_ERROR,
                          "missing version line: a graph file starts with "
                          "'lightgraph 1', found %s",
                          describe(p, t, buf));
        /* Go on as version 1 to find more problems. */
    }
    g->version = 1;

    while (!s->stop) {
        lg_skip_nl(p);
        t = peek(p);
        if (t->kind == T_EOF) {
            if (!p->included) {
                cvec tc = { 0 };
                cvec_above(p, &tc, t);
                cvec_trim(&tc);
                g->trailing_comments = cvec_finish(p, &tc, &g->n_trailing_comments);
            }
            break;
        }
        if (t->kind == T_IDENT && !t->port && peek_at(p, 1)->kind != T_EQ) {
            if (strcmp(t->s, "output") == 0) {
                parse_output(p);
                continue;
            }
            if (strcmp(t->s, "include") == 0) {
                parse_include(p);
                continue;
            }
            if (strcmp(t->s, "lightgraph") == 0) {
                lg_tok_report(p, t, LG_DIAG_ERROR,
                              "the version line must come first, and only once");
                recover_statement(p);
                continue;
            }
        }
        if (t->kind == T_IDENT && peek_at(p, 1)->kind == T_EQ) {
            parse_node(p);
            continue;
        }
        if (t->kind == T_IDENT) {
            char what[120];
            snprintf(what, sizeof what, "'=' after the node name '%.60s' (NAME = TYPE { ... })",
                     t->s);
            advance(p);
            expected(p, what);
        } else {
            expected(p, "a statement (NAME = TYPE { ... }, output or include)");
        }
        recover_statement(p);
    }
}

/* ---- entry points ---------------------------------------------------------------------------- */

void lg_parse_source(session *s, source *src, const char *base_dir, bool included)
{
    parser p;
    memset(&p, 0, sizeof p);
    p.s = s;
    p.src = src;
    p.base_dir = base_dir;
    p.included = included;
    lg_lex(&p, 0, src->len);
    parse_body(&p);
    free(p.t);
    free(p.cm);
}

static lg_graph *new_graph(void)
{
    lg_graph *g = lg_xcalloc(1, sizeof *g);
    pool *pl = lg_xcalloc(1, sizeof *pl);
    g->pool = pl;
    return g;
}

/* Parses the top source (already in the pool) and everything it includes. */
static lg_graph *parse_root(lg_graph *g, source *src, const char *base_dir, const char *abs,
                            lg_diags *d)
{
    pool *pl = g->pool;
    session s;
    memset(&s, 0, sizeof s);
    s.pl = pl;
    s.g = g;
    s.d = d;
    g->path = (char *)src->name;
    s.n_bytes = src->len;
    s.stack_name[0] = src->name;
    s.stack_abs[0] = abs ? lg_arena_strdup(&pl->a, abs) : NULL;
    s.depth = 1;
    if (abs) {
        s.done = lg_xmalloc(8 * sizeof *s.done);
        s.cap_done = 8;
        s.done[s.n_done++] = s.stack_abs[0];
    }
    lg_parse_source(&s, src, base_dir ? lg_arena_strdup(&pl->a, base_dir) : NULL, false);

    g->nodes = lg_arena_copy(&pl->a, s.nodes, s.n_nodes * sizeof *s.nodes);
    g->n_nodes = s.n_nodes;
    g->outputs = lg_arena_copy(&pl->a, s.outputs, s.n_outputs * sizeof *s.outputs);
    g->n_outputs = s.n_outputs;
    g->includes = lg_arena_copy(&pl->a, s.includes, s.n_includes * sizeof *s.includes);
    g->n_includes = s.n_includes;
    free(s.nodes);
    free(s.outputs);
    free(s.includes);
    free(s.done);
    if (s.errors > 0) {
        lg_graph_free(g);
        return NULL;
    }
    return g;
}

lg_graph *lg_graph_parse_string(const char *name, const char *text, size_t len,
                                const char *base_dir, lg_diags *diags)
{
    lg_graph *g = new_graph();
    pool *pl = g->pool;
    if (!name)
        name = "<string>";
    if (len > MAX_FILE_BYTES) {
        lg_srcloc loc = { name, 0, 0, 0 };
        lg_diags_add(diags, LG_DIAG_ERROR, loc, NULL,
                     "graph text is too large (%zu bytes; the "
                     "limit is %u MiB)",
                     len, MAX_FILE_BYTES >> 20);
        lg_graph_free(g);
        return NULL;
    }
    source *src = lg_source_add(pl, name, text ? text : "", text ? len : 0, 1, false);
    return parse_root(g, src, base_dir, NULL, diags);
}

lg_graph *lg_graph_parse_file(const char *path, lg_diags *diags)
{
    lg_srcloc loc = { path, 0, 0, 0 };
    size_t len = 0;
    char why[256];
    /* bounded: a FIFO, a device or a huge file is refused before a byte is read */
    char *text = lg_read_file_limit(path, MAX_FILE_BYTES, &len, why, sizeof why);
    if (!text) {
        lg_diags_add(diags, LG_DIAG_ERROR, loc, NULL, "cannot read graph file: %s", why);
        return NULL;
    }
    lg_graph *g = new_graph();
    source *src = lg_source_add(g->pool, path, text, len, 1, true);
    char *dir = lg_path_dirname(path);
    char *abs = lg_path_absolute(path);
    g = parse_root(g, src, dir, abs, diags);
    free(dir);
    free(abs);
    return g;
}

const lg_gvalue *lg_glist_item(const lg_gvalue *list, uint32_t i, lg_gitem *tmp, bool want_loc)
{
    if (!list->nums)
        return &list->items[i];
    lg_gvalue *v = &tmp->v;
    memset(v, 0, sizeof *v);
    uint32_t g = list->nums->tag[i], off = g & TAG_OFF_MASK, len = (g >> 24) & 0x7F;
    if (g & TAG_FLOAT) {
        v->kind = LG_GV_FLOAT;
        v->f = list->nums->val[i].f;
    } else {
        v->kind = LG_GV_INT;
        v->i = list->nums->val[i].i;
    }
    memcpy(tmp->text, list->nums->at + off, len);
    tmp->text[len] = 0;
    v->text = tmp->text;
    v->base_dir = list->base_dir;
    v->loc = list->loc;
    v->loc.len = len;
    if (want_loc) {
        const char *at = list->nums->at;
        uint32_t lines = 0, last = 0;
        for (uint32_t k = 0; k < off; k++)
            if (at[k] == '\n') {
                lines++;
                last = k;
            }
        v->loc.line = list->loc.line + lines;
        v->loc.col = lines ? off - last : list->loc.col + off;
    }
    return v;
}
