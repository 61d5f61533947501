/*
 * host/graph_parse.c: graph files, text -> lg_graph (docs/graph-format.md is the spec).
 *
 * A file is read whole and split into tokens first. Comments are not tokens: each one is
 * attached to the token it stands above, or to the token whose line it ends, so that fmt
 * can put it back. Lexical errors travel inside T_ERR tokens and are reported when the
 * parser steps over them, so that messages come out in file order. The parser is a
 * recursive descent with one token of lookahead (two to tell `output x "f"` from a node
 * called `output`); only lists recurse, and their nesting is limited. After an error it
 * skips to the next entry or statement and goes on, so that one run reports many
 * problems, up to MAX_ERRORS.
 *
 * Everything a graph points to lives in one arena (the pool), freed by lg_graph_free.
 *
 * Lists of numbers are kept compact (lg_gnums in graph.h): the lexer makes one T_NUMS token
 * of the numbers that follow each other on a line in a list, and a list of numbers only
 * keeps a value and a tag for each item, no lg_gvalue (lg_glist_item makes one on demand).
 *
 * Numbers are read with strtoll/strtod: the host never calls setlocale(), so the decimal
 * separator is always '.'.
 */
#include "graph/graph.h"

#include <errno.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "lightgraph/file.h"
#include "base/util.h"

/* The limits of a graph (docs/graph-format.md, "Limits"); each is tested in
 * tests/unit/parser. They keep the parser's memory linear in its input and small: a token
 * costs 64 bytes while it is parsed; an item of a list that holds more than numbers about
 * 250 (its token, its comma's, an lg_gvalue and its text); an item of a list of numbers 12
 * (the numbers of a line of a list are one token: numrun). */
#define MAX_FILE_BYTES (16u << 20)  /* a file and everything it includes, in all; this
                                     * also keeps offsets in 32 bits */
#define MAX_TOKENS (1u << 20)       /* names, numbers, strings and punctuation, all files */
#define MAX_LIST_ITEMS 65536        /* items of one list (no parameter takes more than 3) */
#define MAX_LIST_DEPTH 32
#define MAX_INCLUDE_DEPTH 32
#define MAX_NODES 100000
#define MAX_NAME_BYTES 256          /* a name, key, type or NODE.PORT reference */
#define MAX_ERRORS 100

/* ---- arena ---------------------------------------------------------------------------- */

typedef struct ablock {
    struct ablock *next;
    size_t used, cap;
    max_align_t data[];
} ablock;

typedef struct arena {
    ablock *head;
} arena;

static void *arena_alloc(arena *a, size_t n)
{
    const size_t align = _Alignof(max_align_t);
    n = (n + align - 1) & ~(align - 1);
    if (!a->head || a->head->cap - a->head->used < n) {
        size_t cap = n > 32768 ? n : 32768;
        ablock *b = lg_xmalloc(sizeof *b + cap);
        b->used = 0;
        b->cap = cap;
        b->next = a->head;
        a->head = b;
    }
    void *p = (char *)a->head->data + a->head->used;
    a->head->used += n;
    return p;
}

static void *arena_zalloc(arena *a, size_t n)
{
    void *p = arena_alloc(a, n);
    memset(p, 0, n);
    return p;
}

static char *arena_strndup(arena *a, const char *s, size_t n)
{
    char *p = arena_alloc(a, n + 1);
    memcpy(p, s, n);
    p[n] = 0;
    return p;
}

static char *arena_strdup(arena *a, const char *s)
{
    return arena_strndup(a, s, strlen(s));
}

static void *arena_copy(arena *a, const void *p, size_t n)
{
    if (n == 0)
        return NULL;
    void *q = arena_alloc(a, n);
    memcpy(q, p, n);
    return q;
}

static void arena_free(arena *a)
{
    for (ablock *b = a->head, *next; b; b = next) {
        next = b->next;
        free(b);
    }
    a->head = NULL;
}

/* ---- a string -> index map (open addressing) ------------------------------------------ */

typedef struct strmap {
    const char **keys;
    uint32_t *vals;
    uint32_t cap, n;
} strmap;

#define STRMAP_NONE UINT32_MAX

static uint32_t strmap_find(const strmap *m, const char *key)
{
    if (m->cap == 0)
        return STRMAP_NONE;
    uint32_t i = (uint32_t)lg_hash64(key, strlen(key), 0) & (m->cap - 1);
    while (m->keys[i]) {
        if (strcmp(m->keys[i], key) == 0)
            return m->vals[i];
        i = (i + 1) & (m->cap - 1);
    }
    return STRMAP_NONE;
}

static void strmap_put(strmap *m, const char *key, uint32_t val)
{
    if ((m->n + 1) * 2 > m->cap) {
        strmap old = *m;
        m->cap = old.cap ? old.cap * 2 : 16;
        m->keys = lg_xcalloc(m->cap, sizeof *m->keys);
        m->vals = lg_xcalloc(m->cap, sizeof *m->vals);
        m->n = 0;
        for (uint32_t i = 0; i < old.cap; i++)
            if (old.keys[i])
                strmap_put(m, old.keys[i], old.vals[i]);
        free(old.keys);
        free(old.vals);
    }
    uint32_t i = (uint32_t)lg_hash64(key, strlen(key), 0) & (m->cap - 1);
    while (m->keys[i]) {
        if (strcmp(m->keys[i], key) == 0) {
            m->vals[i] = val;
            return;
        }
        i = (i + 1) & (m->cap - 1);
    }
    m->keys[i] = key;
    m->vals[i] = val;
    m->n++;
}

static void strmap_free(strmap *m)
{
    free(m->keys);
    free(m->vals);
    memset(m, 0, sizeof *m);
}

/* ---- sources and the pool --------------------------------------------------------------- */

/* One text the graph came from: a file, a string, or one --set assignment. */
typedef struct source {
    const char *name;     /* what messages call it; lg_srcloc.file points here */
    const char *text;     /* NUL-terminated copy (may contain NULs, which are errors) */
    uint32_t len;
    uint32_t first_line;  /* 1 for files; n for the n-th --set */
    /* The last line looked up (messages come mostly in file order): lines are found by
     * scanning from here, so that a file of 16 million empty lines costs no table. */
    uint32_t seen_line, seen_off;
    char *owned;          /* the text when the source took it over (freed with the pool) */
} source;

typedef struct pool {
    arena a;
    source **src;
    uint32_t n_src, cap_src;
    strmap nodes; /* node name -> index in lg_graph.nodes */
    uint32_t n_sets;
} pool;

/* `text` is copied, or taken over when `take` (a malloc'd block of len + 1 bytes ending in
 * a NUL, as lg_read_file_limit gives): a file's text is not held twice. */
static source *add_source_ex(pool *pl, const char *name, const char *text, size_t len,
                             uint32_t first_line, bool take)
{
    source *s = arena_zalloc(&pl->a, sizeof *s);
    s->name = arena_strdup(&pl->a, name);
    if (take)
        s->text = s->owned = (char *)text;
    else
        s->text = arena_strndup(&pl->a, text, len);
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

static source *add_source(pool *pl, const char *name, const char *text, size_t len,
                          uint32_t first_line)
{
    return add_source_ex(pl, name, text, len, first_line, false);
}

/* Line `line` of `s` without its line break: *n bytes at the returned pointer (inside the
 * source's text, not copied); NULL if out of range. */
static const char *source_line(source *s, uint32_t line, size_t *n)
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

/* ---- parse session (one lg_graph_parse_* call, all files) ----------------------------- */

typedef struct session {
    pool *pl;
    lg_graph *g;
    lg_diags *d;
    uint32_t errors;
    bool stop;
    /* nodes and outputs of all files, in order */
    lg_gnode *nodes;
    uint32_t n_nodes, cap_nodes;
    lg_goutput *outputs;
    uint32_t n_outputs, cap_outputs;
    lg_ginclude *includes;
    uint32_t n_includes, cap_includes;
    /* the files being parsed (for cycles) and those already parsed (included once) */
    const char *stack_name[MAX_INCLUDE_DEPTH + 1];
    const char *stack_abs[MAX_INCLUDE_DEPTH + 1];
    uint32_t depth;
    const char **done;
    uint32_t n_done, cap_done;
    uint32_t n_tokens;    /* lexed so far, all files (MAX_TOKENS) */
    uint64_t n_bytes;     /* read so far, all files (MAX_FILE_BYTES in all) */
} session;

static void vreport(session *s, source *src, lg_diag_level lvl, uint32_t line,
                    uint32_t col, uint32_t len, const char *fmt, va_list ap)
{
    if (s->stop)
        return;
    char *msg = lg_vformat(fmt, ap);
    size_t n = 0;
    const char *text = src ? source_line(src, line, &n) : NULL;
    lg_srcloc loc = {src ? src->name : NULL, line, col, len};
    lg_diags_add_line(s->d, lvl, loc, text, n, "%s", msg);
    free(msg);
    if (lvl == LG_DIAG_ERROR && ++s->errors >= MAX_ERRORS) {
        lg_srcloc none = {src ? src->name : NULL, 0, 0, 0};
        lg_diags_add(s->d, LG_DIAG_NOTE, none, NULL, "too many errors (%u); stopping here",
                     s->errors);
        s->stop = true;
    }
}

static void report(session *s, source *src, lg_diag_level lvl, uint32_t line,
                   uint32_t col, uint32_t len, const char *fmt, ...)
    __attribute__((format(printf, 7, 8)));
static void report(session *s, source *src, lg_diag_level lvl, uint32_t line,
                   uint32_t col, uint32_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vreport(s, src, lvl, line, col, len, fmt, ap);
    va_end(ap);
}

/* ---- tokens ------------------------------------------------------------------------------ */

enum {
    T_EOF,
    T_NL,
    T_IDENT,
    T_INT,
    T_FLOAT,
    T_STRING,
    T_EQ,
    T_LBRACE,
    T_RBRACE,
    T_LBRACK,
    T_RBRACK,
    T_COMMA,
    T_ERR,
    T_NUMS,   /* a run of numbers in a list on one line, "1, 2.5, 3": tok.s points to a
               * numrun; off, len, line and col are those of its first number */
};

/* The numbers of a T_NUMS token: tags as in lg_gnums, but with offsets into the source
 * text (made relative to the '[' when a list takes them). A run holds only numbers that
 * lex cleanly, at most LG_GNUM_MAX_TEXT long, ending before offset 2^24, each separated
 * from the one before by one ',' and blanks: a list item then costs 12 bytes, not a token
 * for it and one for its comma. */
typedef struct numrun {
    uint32_t n;
    uint32_t *tag;
    lg_gnum *val;
} numrun;

#define TAG_OFF_MASK 0xFFFFFFu
#define TAG_FLOAT 0x80000000u

static uint32_t make_tag(uint32_t off, uint32_t len, bool is_float)
{
    return off | len << 24 | (is_float ? TAG_FLOAT : 0);
}

typedef struct tok {
    uint8_t kind;
    bool blank_before;        /* a blank line came before it (or before its comments) */
    uint32_t off, len, line, col;
    uint32_t c_first, c_n;    /* the comments above it, in parser.cm */
    int32_t eol;              /* the comment that ends its line, or -1 */
    int64_t i;
    double f;
    char *s;                  /* IDENT: name; STRING: the unescaped text; ERR: message */
    char *port;               /* IDENT: after the '.', or NULL */
} tok;

/* One file's (or one --set value's) parse. */
typedef struct parser {
    session *s;
    source *src;
    const char *base_dir;
    bool included;
    tok *t;
    uint32_t nt, cap_t, cur;
    char **cm;
    uint32_t ncm, cap_cm;
    int list_depth;
} parser;

static arena *parena(parser *p)
{
    return &p->s->pl->a;
}

static uint32_t push_tok(parser *p)
{
    if (p->nt == p->cap_t) {
        p->cap_t = p->cap_t ? p->cap_t * 2 : 256;
        p->t = lg_xrealloc(p->t, p->cap_t * sizeof *p->t);
    }
    tok *t = &p->t[p->nt];
    memset(t, 0, sizeof *t);
    t->eol = -1;
    return p->nt++;
}

static uint32_t push_comment(parser *p, char *text)
{
    if (p->ncm == p->cap_cm) {
        p->cap_cm = p->cap_cm ? p->cap_cm * 2 : 32;
        p->cm = lg_xrealloc(p->cm, p->cap_cm * sizeof *p->cm);
    }
    p->cm[p->ncm] = text;
    return p->ncm++;
}

static bool is_ident_start(int c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

static bool is_ident_char(int c)
{
    return is_ident_start(c) || (c >= '0' && c <= '9');
}

static bool is_digit(int c)
{
    return c >= '0' && c <= '9';
}

static void set_err(parser *p, tok *t, uint32_t col, uint32_t len, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static void set_err(parser *p, tok *t, uint32_t col, uint32_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *m = lg_vformat(fmt, ap);
    va_end(ap);
    t->kind = T_ERR;
    t->s = arena_strdup(parena(p), m);
    free(m);
    t->col = col;
    t->len = len;
}

/* Past the items of a list beyond MAX_LIST_ITEMS: up to the ']' that closes it (not
 * consumed), a brace or the end, making no tokens, so that the rest of a list costs
 * nothing however long it is. Strings and comments are stepped over whole (a ']' in them
 * does not count); line breaks are counted. */
static uint32_t skip_list_tail(const char *s, uint32_t pos, uint32_t end, uint32_t *line,
                               uint32_t *line_start)
{
    int depth = 0;
    while (pos < end) {
        char c = s[pos];
        if (c == '\n') {
            (*line)++;
            *line_start = pos + 1;
        } else if (c == '#') {
            while (pos + 1 < end && s[pos + 1] != '\n')
                pos++;
        } else if (c == '"') {
            pos++;
            while (pos < end && s[pos] != '"' && s[pos] != '\n')
                pos += s[pos] == '\\' && pos + 1 < end && s[pos + 1] != '\n' ? 2 : 1;
            if (pos >= end)
                return end;
            if (s[pos] == '\n')
                continue; /* counted above */
        } else if (c == '[') {
            depth++;
        } else if (c == ']') {
            if (depth == 0)
                return pos;
            depth--;
        } else if (c == '{' || c == '}') {
            return pos;
        }
        pos++;
    }
    return end;
}

/* Where a number starting at s[pos] ends (pos when none starts there): digits with an
 * optional '-', fraction and exponent; *is_float_out when it has a fraction or an exponent.
 * What follows it (a letter or a '.', which make it an error) is the caller's to judge. */
static uint32_t number_end(const char *s, uint32_t pos, uint32_t end, bool *is_float_out)
{
    unsigned char c = (unsigned char)s[pos];
    bool num = is_digit(c);
    if (!num && (c == '-' || c == '.') && pos + 1 < end) {
        unsigned char c1 = (unsigned char)s[pos + 1];
        num = is_digit(c1) ||
              (c == '-' && c1 == '.' && pos + 2 < end && is_digit((unsigned char)s[pos + 2]));
    }
    if (!num)
        return pos;
    uint32_t e = pos;
    bool is_float = false;
    if (s[e] == '-')
        e++;
    while (e < end && is_digit((unsigned char)s[e]))
        e++;
    if (e < end && s[e] == '.') {
        is_float = true;
        e++;
        while (e < end && is_digit((unsigned char)s[e]))
            e++;
    }
    if (e < end && (s[e] == 'e' || s[e] == 'E')) {
        uint32_t x = e + 1;
        if (x < end && (s[x] == '+' || s[x] == '-'))
            x++;
        if (x < end && is_digit((unsigned char)s[x])) {
            is_float = true;
            e = x;
            while (e < end && is_digit((unsigned char)s[e]))
                e++;
        }
    }
    *is_float_out = is_float;
    return e;
}

/* Whether a number that lexes cleanly starts at s[pos] (what lex() makes a T_INT or
 * T_FLOAT of, with no error): its end, kind and value. The same rules as lex(). */
static bool clean_number(const char *s, uint32_t pos, uint32_t end, uint32_t *e_out,
                         bool *is_float_out, lg_gnum *val)
{
    if (pos >= end)
        return false;
    bool is_float = false;
    uint32_t e = number_end(s, pos, end, &is_float);
    if (e == pos)
        return false;
    if (e < end && (is_ident_char((unsigned char)s[e]) || s[e] == '.'))
        return false;
    char *endp;
    errno = 0;
    if (is_float) {
        double f = strtod(s + pos, &endp);
        if (f > 1.7976931348623157e308 || f < -1.7976931348623157e308)
            return false;
        val->f = f;
    } else {
        long long v = strtoll(s + pos, &endp, 10);
        if (errno == ERANGE)
            return false;
        val->i = v;
    }
    if (endp != s + e)
        return false;
    *e_out = e;
    *is_float_out = is_float;
    return true;
}

/* After a clean number that ends at `pos`: the start of the next number of the same run
 * (past one ',' and blanks, on the same line), or UINT32_MAX. */
static uint32_t run_next(const char *s, uint32_t pos, uint32_t end)
{
    while (pos < end && (s[pos] == ' ' || s[pos] == '\t' || s[pos] == '\r' || s[pos] == '\f' ||
                         s[pos] == '\v'))
        pos++;
    if (pos >= end || s[pos] != ',')
        return UINT32_MAX;
    pos++;
    while (pos < end && (s[pos] == ' ' || s[pos] == '\t' || s[pos] == '\r' || s[pos] == '\f' ||
                         s[pos] == '\v'))
        pos++;
    return pos;
}

/* Splits text[pos, end) into tokens. `pos` is 0 for files; for a --set value it is the
 * offset of the value inside the assignment, so that columns point into it. */
static void lex(parser *p, uint32_t pos, uint32_t end)
{
    const char *s = p->src->text;
    uint32_t line = p->src->first_line, line_start = 0;
    uint32_t pend_first = 0, pend_n = 0;
    bool pend_blank = false, saw_blank = false, line_has_content = false;
    int32_t last_on_line = -1;
    /* The lists open here: their items are counted (MAX_LIST_ITEMS); `want` is whether an
     * item may start (after '[', ',' or a new line). Nesting beyond MAX_LIST_DEPTH counts at the last
     * level; the parser refuses it. */
    uint32_t ldepth = 0, litems[MAX_LIST_DEPTH + 1];
    bool lwant[MAX_LIST_DEPTH + 1];

    if (pos == 0 && end >= 3 && memcmp(s, "\xEF\xBB\xBF", 3) == 0)
        pos = 3; /* a UTF-8 byte order mark */

    while (pos < end) {
        unsigned char c = (unsigned char)s[pos];
        if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
            pos++;
            continue;
        }
        if (c == '\n') {
            if (ldepth > 0) /* a new line separates list items as a comma does */
                lwant[ldepth < MAX_LIST_DEPTH ? ldepth : MAX_LIST_DEPTH] = true;
            if (!line_has_content) {
                saw_blank = true;
                /* A blank line inside or after a run of comments is kept in the run, so
                 * that fmt does not glue a detached comment block to what follows. */
                if (pend_n > 0 && p->cm[pend_first + pend_n - 1][0] != 0) {
                    push_comment(p, arena_strdup(parena(p), ""));
                    pend_n++;
                }
            }
            if (p->nt == 0 || p->t[p->nt - 1].kind != T_NL) {
                uint32_t k = push_tok(p);
                tok *t = &p->t[k];
                t->kind = T_NL;
                t->off = pos;
                t->len = 1;
                t->line = line;
                t->col = pos - line_start + 1;
            }
            pos++;
            line++;
            line_start = pos;
            line_has_content = false;
            last_on_line = -1;
            continue;
        }
        if (c == '#') {
            uint32_t e = pos + 1;
            while (e < end && s[e] != '\n')
                e++;
            /* A NUL is not allowed anywhere (the comment would be cut at it), nor bytes
             * that are not UTF-8: fmt writes comments back, and a graph file is text. */
            uint32_t bad = UINT32_MAX;
            for (uint32_t i = pos + 1; i < e; i++) {
                unsigned char ch = (unsigned char)s[i];
                if (ch == 0) {
                    bad = i;
                    break;
                }
                if (ch >= 0x80) {
                    int k = lg_utf8_char_len((const unsigned char *)s + i, e - i);
                    if (k == 0) {
                        bad = i;
                        break;
                    }
                    i += (uint32_t)k - 1;
                }
            }
            if (bad != UINT32_MAX) {
                uint32_t k = push_tok(p);
                tok *t = &p->t[k];
                t->off = bad;
                t->line = line;
                if (s[bad] == 0)
                    set_err(p, t, bad - line_start + 1, 1, "unexpected NUL byte in a comment");
                else
                    set_err(p, t, bad - line_start + 1, 1, "invalid UTF-8 in a comment: byte "
                            "0x%02X at byte offset %u (a graph file is UTF-8 text)",
                            (unsigned char)s[bad], bad);
                last_on_line = (int32_t)k;
            }
            uint32_t te = e;
            while (te > pos + 1 && (s[te - 1] == ' ' || s[te - 1] == '\t' || s[te - 1] == '\r' ||
                                    s[te - 1] == '\f' || s[te - 1] == '\v'))
                te--;
            uint32_t idx = push_comment(p, arena_strndup(parena(p), s + pos, te - pos));
            if (last_on_line >= 0 && p->t[last_on_line].eol < 0) {
                p->t[last_on_line].eol = (int32_t)idx;
            } else {
                if (pend_n == 0) {
                    pend_first = idx;
                    pend_blank = saw_blank;
                }
                pend_n++;
                saw_blank = false;
            }
            line_has_content = true;
            pos = e;
            continue;
        }

        uint32_t k = push_tok(p);
        tok *t = &p->t[k];
        t->off = pos;
        t->line = line;
        t->col = pos - line_start + 1;
        if (++p->s->n_tokens > MAX_TOKENS) {
            /* One error, then the end: the rest of the file is not read. */
            t->len = 1;
            set_err(p, t, t->col, 1, "the graph has more than %u tokens (names, numbers, "
                    "strings and punctuation, its includes counted); that is the limit",
                    MAX_TOKENS);
            pos = end;
            break;
        }
        bool item_start = false; /* this token starts an item of a list */
        uint32_t item_ld = 0;
        {
            uint32_t ld = ldepth < MAX_LIST_DEPTH ? ldepth : MAX_LIST_DEPTH;
            if (ldepth > 0 && lwant[ld] && c != ',' && c != ']' && c != '{' && c != '}') {
                lwant[ld] = false;
                item_start = ldepth < MAX_LIST_DEPTH;
                item_ld = ld;
                if (++litems[ld] > MAX_LIST_ITEMS) {
                    t->len = 1;
                    set_err(p, t, t->col, 1, "this list has more than %u items; that is the "
                            "limit", MAX_LIST_ITEMS);
                    last_on_line = (int32_t)k;
                    line_has_content = true;
                    pend_n = 0;
                    lwant[ld] = true; /* the next item is not counted again */
                    litems[ld] = 0;
                    uint32_t l0 = line;
                    pos = skip_list_tail(s, pos, end, &line, &line_start);
                    if (line != l0) {
                        line_has_content = false;
                        last_on_line = -1;
                    }
                    continue;
                }
            }
            if (c == ',' && ldepth > 0) {
                lwant[ld] = true;
            } else if (c == '[') {
                ldepth++;
                ld = ldepth < MAX_LIST_DEPTH ? ldepth : MAX_LIST_DEPTH;
                litems[ld] = 0;
                lwant[ld] = true;
            } else if (c == ']' && ldepth > 0) {
                ldepth--;
            } else if (c == '{' || c == '}') {
                ldepth = 0;
            }
        }
        t->c_first = pend_first;
        t->c_n = pend_n;
        t->blank_before = pend_n ? pend_blank : saw_blank;
        pend_n = 0;
        saw_blank = false;
        line_has_content = true;
        last_on_line = (int32_t)k;

        if (is_ident_start(c)) {
            uint32_t e = pos + 1;
            while (e < end && is_ident_char((unsigned char)s[e]))
                e++;
            t->kind = T_IDENT;
            t->s = arena_strndup(parena(p), s + pos, e - pos);
            if (e < end && s[e] == '.') {
                if (e + 1 < end && is_ident_start((unsigned char)s[e + 1])) {
                    uint32_t f = e + 2;
                    while (f < end && is_ident_char((unsigned char)s[f]))
                        f++;
                    t->port = arena_strndup(parena(p), s + e + 1, f - e - 1);
                    e = f;
                    if (e < end && s[e] == '.') {
                        while (e < end && (is_ident_char((unsigned char)s[e]) || s[e] == '.'))
                            e++;
                        set_err(p, t, t->col, e - pos,
                                "'%.*s' has more than one '.' (a reference is NODE or NODE.PORT)",
                                (int)(e - pos), s + pos);
                    }
                } else {
                    e++;
                    set_err(p, t, t->col, e - pos, "expected a port name after '%.*s'",
                            (int)(e - pos), s + pos);
                }
            }
            if (e - pos > MAX_NAME_BYTES)
                set_err(p, t, t->col, e - pos, "this name is %u characters long; names have at "
                        "most %u", e - pos, MAX_NAME_BYTES);
            t->len = e - pos;
            pos = e;
            continue;
        }

        bool is_float = false;
        uint32_t num_end = number_end(s, pos, end, &is_float);
        if (num_end != pos) {
            uint32_t e = num_end;
            if (e < end && (is_ident_char((unsigned char)s[e]) || s[e] == '.')) {
                while (e < end && (is_ident_char((unsigned char)s[e]) || s[e] == '.'))
                    e++;
                t->len = e - pos;
                set_err(p, t, t->col, e - pos, "invalid number '%.*s'", (int)(e - pos), s + pos);
                pos = e;
                continue;
            }
            t->len = e - pos;
            /* The text ends in a character strtoll/strtod cannot take (or the final NUL). */
            char *endp;
            errno = 0;
            if (is_float) {
                t->kind = T_FLOAT;
                t->f = strtod(s + pos, &endp);
                if (t->f > 1.7976931348623157e308 || t->f < -1.7976931348623157e308)
                    set_err(p, t, t->col, t->len,
                            "number '%.*s' is too large (the largest float is about 1.8e308)",
                            (int)t->len, s + pos);
            } else {
                t->kind = T_INT;
                long long v = strtoll(s + pos, &endp, 10);
                t->i = v;
                if (errno == ERANGE)
                    set_err(p, t, t->col, t->len,
                            "integer '%.*s' is out of range (integers have 64 bits: "
                            "-9223372036854775808 to 9223372036854775807)",
                            (int)t->len, s + pos);
            }
            if (t->kind != T_ERR && endp != s + e)
                set_err(p, t, t->col, t->len, "invalid number '%.*s'", (int)t->len, s + pos);
            if (t->kind != T_ERR && item_start && t->len <= LG_GNUM_MAX_TEXT &&
                e <= TAG_OFF_MASK) {
                /* More numbers after this one on its line: one T_NUMS token for them all.
                 * They count as the tokens and list items they would have been. */
                uint32_t q = e, n = 1, ntok = p->s->n_tokens, nitems = litems[item_ld];
                for (;;) {
                    uint32_t r = run_next(s, q, end), ne;
                    bool f;
                    lg_gnum val;
                    if (r == UINT32_MAX || !clean_number(s, r, end, &ne, &f, &val) ||
                        ne - r > LG_GNUM_MAX_TEXT || ne > TAG_OFF_MASK ||
                        ntok + 2 > MAX_TOKENS || nitems + 1 > MAX_LIST_ITEMS)
                        break;
                    ntok += 2;
                    nitems++;
                    n++;
                    q = ne;
                }
                if (n > 1) {
                    numrun *run = arena_alloc(parena(p), sizeof *run);
                    run->n = n;
                    run->tag = arena_alloc(parena(p), n * sizeof *run->tag);
                    run->val = arena_alloc(parena(p), n * sizeof *run->val);
                    bool f = t->kind == T_FLOAT;
                    run->tag[0] = make_tag(pos, t->len, f);
                    if (f)
                        run->val[0].f = t->f;
                    else
                        run->val[0].i = t->i;
                    uint32_t r = e;
                    for (uint32_t j = 1; j < n; j++) {
                        uint32_t b = run_next(s, r, end);
                        clean_number(s, b, end, &r, &f, &run->val[j]);
                        run->tag[j] = make_tag(b, r - b, f);
                    }
                    t->kind = T_NUMS;
                    t->s = (char *)run;
                    p->s->n_tokens = ntok;
                    litems[item_ld] = nitems;
                    e = q;
                }
            }
            pos = e;
            continue;
        }

        if (c == '"') {
            lg_str b = {0};
            uint32_t e = pos + 1;
            char *msg = NULL;
            uint32_t mcol = 0, mlen = 0;
            bool closed = false;
            while (e < end && s[e] != '\n') {
                unsigned char ch = (unsigned char)s[e];
                if (ch == '"') {
                    closed = true;
                    e++;
                    break;
                }
                if (ch == '\\') {
                    char esc = e + 1 < end ? s[e + 1] : '\n';
                    const char *rep = esc == '"' ? "\"" : esc == '\\' ? "\\" : esc == 'n' ? "\n"
                                    : esc == 't' ? "\t" : NULL;
                    if (rep) {
                        lg_str_add(&b, rep);
                        e += 2;
                        continue;
                    }
                    if (esc == '\n' || esc == '\r') {
                        e++;
                        continue; /* reported as an unclosed string */
                    }
                    if (!msg) {
                        mcol = e - line_start + 1;
                        mlen = 2;
                        if ((unsigned char)esc >= 0x20 && (unsigned char)esc < 0x7f)
                            msg = lg_xasprintf("unknown escape '\\%c' in a string (use \\\" \\\\ "
                                               "\\n or \\t)", esc);
                        else
                            msg = lg_xasprintf("unknown escape in a string (use \\\" \\\\ \\n or "
                                               "\\t)");
                    }
                    e += 2;
                    continue;
                }
                if (ch < 0x20 && ch != '\t' && ch != '\r') {
                    if (!msg) {
                        mcol = e - line_start + 1;
                        mlen = 1;
                        msg = lg_xasprintf("control character 0x%02X in a string", ch);
                    }
                    e++;
                    continue;
                }
                if (ch == '\r') {
                    /* A CR is kept only when a LF does not follow (CRLF ends the line). */
                    if (e + 1 < end && s[e + 1] == '\n') {
                        e++;
                        continue;
                    }
                    if (!msg) {
                        mcol = e - line_start + 1;
                        mlen = 1;
                        msg = lg_xasprintf("control character 0x0D in a string");
                    }
                    e++;
                    continue;
                }
                if (ch >= 0x80) {
                    int u = lg_utf8_char_len((const unsigned char *)s + e, end - e);
                    if (u == 0) {
                        if (!msg) {
                            mcol = e - line_start + 1;
                            mlen = 1;
                            msg = lg_xasprintf("invalid UTF-8 in a string: byte 0x%02X at byte "
                                               "offset %u (strings are UTF-8 text)", ch, e);
                        }
                        e++;
                        continue;
                    }
                    lg_str_addn(&b, s + e, (size_t)u);
                    e += (uint32_t)u;
                    continue;
                }
                lg_str_addc(&b, (char)ch);
                e++;
            }
            t->len = e - pos;
            if (!closed) {
                uint32_t l = e - pos;
                while (l > 1 && s[pos + l - 1] == '\r')
                    l--;
                set_err(p, t, t->col, l, "string is not closed before the end of the line");
            } else if (msg) {
                set_err(p, t, mcol, mlen, "%s", msg);
            } else {
                t->kind = T_STRING;
                t->s = arena_strndup(parena(p), b.s ? b.s : "", b.len);
            }
            free(msg);
            lg_str_free(&b);
            pos = e;
            continue;
        }

        t->len = 1;
        switch (c) {
        case '=': t->kind = T_EQ; break;
        case '{': t->kind = T_LBRACE; break;
        case '}': t->kind = T_RBRACE; break;
        case '[': t->kind = T_LBRACK; break;
        case ']': t->kind = T_RBRACK; break;
        case ',': t->kind = T_COMMA; break;
        case 0: set_err(p, t, t->col, 1, "unexpected NUL byte"); break;
        case ':': set_err(p, t, t->col, 1, "unexpected ':' (keys are set with '=')"); break;
        case ';':
            set_err(p, t, t->col, 1, "unexpected ';' (entries are separated by ',' or new lines)");
            break;
        default:
            if (c >= 0x80) {
                /* Show a whole UTF-8 character. */
                int u = lg_utf8_char_len((const unsigned char *)s + pos, end - pos);
                t->len = u > 0 ? (uint32_t)u : 1;
                if (u > 0)
                    set_err(p, t, t->col, t->len, "unexpected character '%.*s'", u, s + pos);
                else
                    set_err(p, t, t->col, t->len, "unexpected byte 0x%02X at byte offset %u "
                            "(not UTF-8 text)", c, pos);
            } else if (c < 0x20 || c == 0x7f) {
                set_err(p, t, t->col, 1, "unexpected control character 0x%02X", c);
            } else {
                set_err(p, t, t->col, 1, "unexpected character '%c'", c);
            }
        }
        pos += t->len;
    }

    uint32_t k = push_tok(p);
    tok *t = &p->t[k];
    t->kind = T_EOF;
    t->off = end;
    t->line = line;
    t->col = end - line_start + 1;
    t->c_first = pend_first;
    t->c_n = pend_n;
    t->blank_before = pend_n ? pend_blank : saw_blank;
}

/* ---- parser helpers ---------------------------------------------------------------------- */

static tok *peek(parser *p)
{
    return &p->t[p->cur];
}

static tok *peek_at(parser *p, uint32_t k)
{
    return &p->t[p->cur + k < p->nt ? p->cur + k : p->nt - 1];
}

static void tok_report(parser *p, const tok *t, lg_diag_level lvl, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void tok_report(parser *p, const tok *t, lg_diag_level lvl, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vreport(p->s, p->src, lvl, t->line, t->col, t->len, fmt, ap);
    va_end(ap);
}

/* Steps over the current token; a lexical error is reported now. */
static void advance(parser *p)
{
    tok *t = peek(p);
    if (t->kind == T_EOF)
        return;
    if (t->kind == T_ERR)
        tok_report(p, t, LG_DIAG_ERROR, "%s", t->s);
    p->cur++;
}

static bool skip_nl(parser *p)
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
    default:
        return "an invalid token";
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
    tok_report(p, t, LG_DIAG_ERROR, "expected %s, found %s", what, describe(p, t, buf));
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
        case T_RBRACE:
            return;
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
    char **r = arena_copy(parena(p), c->v, c->n * sizeof *c->v);
    free(c->v);
    memset(c, 0, sizeof *c);
    return r;
}

static char *eol_of(parser *p, uint32_t k)
{
    return p->t[k].eol >= 0 ? p->cm[p->t[k].eol] : NULL;
}

/* ---- values ------------------------------------------------------------------------------- */

static bool parse_value(parser *p, lg_gvalue *v);

static bool parse_list(parser *p, lg_gvalue *v)
{
    tok *open = peek(p);
    if (p->list_depth >= MAX_LIST_DEPTH) {
        tok_report(p, open, LG_DIAG_ERROR, "lists are nested more than %d deep", MAX_LIST_DEPTH);
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
        nums = arena_zalloc(parena(p), sizeof *nums);
        nums->at = p->src->text + open->off;
        if (!(runs == 1 && plain == 0)) {
            nums->tag = arena_alloc(parena(p), total * sizeof *nums->tag);
            nums->val = arena_alloc(parena(p), total * sizeof *nums->val);
        }
    }
    for (;;) {
        if (skip_nl(p))
            sep = true;
        tok *t = peek(p);
        if (t->kind == T_RBRACK) {
            close = t;
            advance(p);
            break;
        }
        if (t->kind == T_EOF) {
            tok_report(p, open, LG_DIAG_ERROR, "'[' is never closed");
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
                    nums->tag[n + j] = make_tag((g & TAG_OFF_MASK) - open->off,
                                                (g >> 24) & 0x7F, (g & TAG_FLOAT) != 0);
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
                if (n == cap) {
                    cap = cap ? cap * 2 : 4;
                    items = lg_xrealloc(items, cap * sizeof *items);
                }
                lg_gvalue *it = &items[n++];
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
                it->text = arena_strndup(parena(p), p->src->text + off, len);
            }
            advance(p);
        } else {
            if (n == cap) {
                cap = cap ? cap * 2 : 4;
                items = lg_xrealloc(items, cap * sizeof *items);
            }
            if (!parse_value(p, &items[n]))
                goto fail;
            n++;
        }
        sep = false;
        if (skip_nl(p))
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
        v->items = arena_copy(parena(p), items, n * sizeof *items);
    }
    v->n_items = n;
    free(items);
    set_loc(p, &v->loc, open);
    if (close->line == open->line)
        v->loc.len = close->off + 1 - open->off;
    /* A compact list is not copied again as text (lg_gvalue.text) */
    if (!compact)
        v->text = arena_strndup(parena(p), p->src->text + open->off, close->off + 1 - open->off);
    return true;
fail:
    free(items);
    return false;
}

static bool parse_value(parser *p, lg_gvalue *v)
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
    case T_LBRACK:
        return parse_list(p, v);
    default:
        expected(p, "a value");
        return false;
    }
    v->text = arena_strndup(parena(p), p->src->text + t->off, t->len);
    advance(p);
    return true;
}

/* ---- statements --------------------------------------------------------------------------- */

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

static const char *const reserved_words[] = {"lightgraph", "include", "output", "true", "false"};

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
    uint32_t prev = strmap_find(&s->pl->nodes, n->name);
    if (prev != STRMAP_NONE) {
        const lg_gnode *f = &s->nodes[prev];
        report(s, p->src, LG_DIAG_ERROR, n->loc.line, n->loc.col, n->loc.len,
               "node '%s' is defined twice", n->name);
        source *fs = NULL;
        for (uint32_t i = 0; i < s->pl->n_src; i++)
            if (s->pl->src[i]->name == f->loc.file)
                fs = s->pl->src[i];
        report(s, fs, LG_DIAG_NOTE, f->loc.line, f->loc.col, f->loc.len,
               "'%s' was first defined here", n->name);
        return;
    }
    if (s->n_nodes >= MAX_NODES) {
        report(s, p->src, LG_DIAG_ERROR, n->loc.line, n->loc.col, n->loc.len,
               "the graph has more than %u nodes (its includes counted); that is the limit",
               MAX_NODES);
        s->stop = true; /* one message, not one per node */
        return;
    }
    if (s->n_nodes == s->cap_nodes) {
        s->cap_nodes = s->cap_nodes ? s->cap_nodes * 2 : 16;
        s->nodes = lg_xrealloc(s->nodes, s->cap_nodes * sizeof *s->nodes);
    }
    strmap_put(&s->pl->nodes, n->name, s->n_nodes);
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
    cvec above = {0}, end = {0};
    cvec_above(p, &above, name);

    if (name->port)
        tok_report(p, name, LG_DIAG_ERROR, "a node name cannot contain '.'");
    else if (is_reserved(name->s))
        tok_report(p, name, LG_DIAG_ERROR, "'%s' is a reserved word and cannot name a node",
                   name->s);
    advance(p); /* name */
    advance(p); /* = */
    tok *type = peek(p);
    if (type->kind != T_IDENT || type->port) {
        if (type->kind == T_IDENT)
            tok_report(p, type, LG_DIAG_ERROR, "a node type cannot contain '.'");
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
    skip_nl(p);
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
    strmap keys = {0};
    for (;;) {
        skip_nl(p);
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
            tok_report(p, lb, LG_DIAG_ERROR, "'{' of node '%s' is never closed", n.name);
            cvec_above(p, &end, t);
            break;
        }
        if (p->s->stop)
            break;
        if (t->kind != T_IDENT) {
            char what[120];
            snprintf(what, sizeof what, "a key or '}' in node '%.60s'", n.name);
            expected(p, what);
            recover_entry(p);
            if (peek(p)->kind == T_COMMA)
                advance(p);
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
            tok_report(p, t, LG_DIAG_ERROR, "a key cannot contain '.'");
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
            skip_nl(p);
            ok = parse_value(p, &a.value);
        }
        if (!ok) {
            recover_entry(p);
            if (peek(p)->kind == T_COMMA)
                advance(p);
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
            skip_nl(p);
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
            recover_entry(p);
            if (peek(p)->kind == T_COMMA)
                advance(p);
        }
        cvec ac = {0};
        cvec_above(p, &ac, &p->t[kidx]);
        cvec_inner(p, &ac, kidx, last);
        a.eol_comment = eol_of(p, last);
        if (late_comma >= 0) {
            cvec_above(p, &ac, &p->t[late_comma]);
            if (p->t[late_comma].eol >= 0)
                cvec_push(&ac, p->cm[p->t[late_comma].eol]);
        }
        a.comments = cvec_finish(p, &ac, &a.n_comments);

        uint32_t prev = strmap_find(&keys, a.key);
        if (prev != STRMAP_NONE) {
            tok_report(p, &p->t[kidx], LG_DIAG_ERROR, "key '%s' is set twice in node '%s'", a.key,
                       n.name);
            report(p->s, p->src, LG_DIAG_NOTE, as[prev].key_loc.line, as[prev].key_loc.col,
                   as[prev].key_loc.len, "'%s' was first set here", a.key);
            continue;
        }
        if (na == cap) {
            cap = cap ? cap * 2 : 8;
            as = lg_xrealloc(as, cap * sizeof *as);
        }
        strmap_put(&keys, a.key, na);
        as[na++] = a;
    }
    strmap_free(&keys);
    n.assigns = arena_copy(parena(p), as, na * sizeof *as);
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
    o.ref.text = arena_strndup(parena(p), p->src->text + r->off, r->len);
    advance(p);
    tok *f = peek(p);
    if (f->kind != T_STRING) {
        char what[120];
        snprintf(what, sizeof what, "the file name after 'output %.60s' (a string such as "
                 "\"out.png\")", o.ref.text);
        expected(p, what);
        recover_statement(p);
        return;
    }
    uint32_t last = p->cur;
    o.path = f->s;
    set_loc(p, &o.path_loc, f);
    if (!o.path[0])
        tok_report(p, f, LG_DIAG_ERROR, "the output file name is empty");
    advance(p);
    /* optional: the EXR pixel type, half or float */
    tok *x = peek(p);
    if (x->kind == T_IDENT && (!strcmp(x->s, "half") || !strcmp(x->s, "float"))) {
        size_t n = strlen(o.path);
        if (n < 4 || strcasecmp(o.path + n - 4, ".exr") != 0)
            tok_report(p, x, LG_DIAG_ERROR, "'%s' chooses the pixel type of an .exr output; "
                       "'%.60s' is not one", x->s, o.path);
        o.exr_pixel = x->s[0] == 'h' ? LG_OUT_EXR_HALF : LG_OUT_EXR_FLOAT;
        last = p->cur;
        advance(p);
    }
    if (!expect_eol(p, "the output statement"))
        return;
    cvec c = {0};
    cvec_above(p, &c, kw);
    cvec_inner(p, &c, first, last);
    o.eol_comment = eol_of(p, last);
    o.comments = cvec_finish(p, &c, &o.n_comments);
    session *s = p->s;
    if (s->n_outputs == s->cap_outputs) {
        s->cap_outputs = s->cap_outputs ? s->cap_outputs * 2 : 4;
        s->outputs = lg_xrealloc(s->outputs, s->cap_outputs * sizeof *s->outputs);
    }
    s->outputs[s->n_outputs++] = o;
}

static void parse_body(parser *p);

/* Whether `text` starts like a graph file: after blank lines, comments and a byte order
 * mark, the word 'lightgraph' as the version line's (not a node called so). An included
 * file that does not is not parsed at all, so that including /proc/self/status or a PNG
 * gives one message instead of an echo of its lines. */
static bool looks_like_graph(const char *text, size_t len)
{
    size_t i = len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    for (;;) {
        while (i < len && (text[i] == ' ' || text[i] == '\t' || text[i] == '\r' ||
                           text[i] == '\n' || text[i] == '\f' || text[i] == '\v'))
            i++;
        if (i < len && text[i] == '#') {
            while (i < len && text[i] != '\n')
                i++;
            continue;
        }
        break;
    }
    static const char word[] = "lightgraph";
    size_t n = sizeof word - 1;
    if (len - i < n || memcmp(text + i, word, n) != 0)
        return false;
    i += n;
    if (i < len && (is_ident_char((unsigned char)text[i]) || text[i] == '.'))
        return false;
    while (i < len && (text[i] == ' ' || text[i] == '\t'))
        i++;
    return !(i < len && text[i] == '=');
}

static void do_include(parser *p, const tok *f)
{
    session *s = p->s;
    pool *pl = s->pl;
    /* "x.lgraph" rather than "./x.lgraph" in messages when the including file is in the
     * current directory. */
    char *full = !p->base_dir || strcmp(p->base_dir, ".") == 0 ? lg_xstrdup(f->s)
                                                                : lg_path_join(p->base_dir, f->s);
    char *abs = lg_path_absolute(full);
    for (uint32_t i = 0; i < s->depth; i++) {
        if (s->stack_abs[i] && strcmp(s->stack_abs[i], abs) == 0) {
            lg_str chain = {0};
            for (uint32_t j = i; j < s->depth; j++)
                lg_str_addf(&chain, "%s -> ", s->stack_name[j]);
            lg_str_add(&chain, s->stack_name[i]);
            tok_report(p, f, LG_DIAG_ERROR, "include cycle: %s", chain.s);
            lg_str_free(&chain);
            goto out;
        }
    }
    for (uint32_t i = 0; i < s->n_done; i++)
        if (strcmp(s->done[i], abs) == 0)
            goto out; /* already included once: it adds nothing new */
    if (s->depth >= MAX_INCLUDE_DEPTH) {
        tok_report(p, f, LG_DIAG_ERROR, "includes are nested more than %d deep",
                   MAX_INCLUDE_DEPTH);
        goto out;
    }
    size_t len = 0;
    char why[256];
    /* The one bounded reader: regular files only (a FIFO, a device or a directory is
     * refused without blocking), the size checked against what is left of the graph's
     * MAX_FILE_BYTES before a byte is read. */
    uint64_t size = 0;
    int fd = lg_file_open(full, MAX_FILE_BYTES, &size, why, sizeof why);
    if (fd < 0) {
        tok_report(p, f, LG_DIAG_ERROR, "cannot read included file '%s': %s", full, why);
        goto out;
    }
    if (s->n_bytes + size > MAX_FILE_BYTES) {
        close(fd);
        tok_report(p, f, LG_DIAG_ERROR, "cannot include '%s' (%llu bytes): a graph file and "
                   "its includes have at most %u MiB in all", full, (unsigned long long)size,
                   MAX_FILE_BYTES >> 20);
        goto out;
    }
    char *text = lg_file_read_fd(fd, size, &len, why, sizeof why);
    close(fd);
    if (!text) {
        tok_report(p, f, LG_DIAG_ERROR, "cannot read included file '%s': %s", full, why);
        goto out;
    }
    if (!looks_like_graph(text, len)) {
        tok_report(p, f, LG_DIAG_ERROR, "included file '%s' is not a graph file: it does not "
                   "start with the version line 'lightgraph 1'", full);
        free(text);
        goto out;
    }
    s->n_bytes += len;
    source *src = add_source_ex(pl, full, text, len, 1, true);
    const char *abs_i = arena_strdup(&pl->a, abs);
    if (s->n_done == s->cap_done) {
        s->cap_done = s->cap_done ? s->cap_done * 2 : 8;
        s->done = lg_xrealloc(s->done, s->cap_done * sizeof *s->done);
    }
    s->done[s->n_done++] = abs_i;
    char *dir = lg_path_dirname(full);
    parser sub;
    memset(&sub, 0, sizeof sub);
    sub.s = s;
    sub.src = src;
    sub.base_dir = arena_strdup(&pl->a, dir);
    sub.included = true;
    free(dir);
    s->stack_name[s->depth] = src->name;
    s->stack_abs[s->depth] = abs_i;
    s->depth++;
    lex(&sub, 0, src->len);
    parse_body(&sub);
    s->depth--;
    free(sub.t);
    free(sub.cm);
out:
    free(full);
    free(abs);
}

/* include "path" */
static void parse_include(parser *p)
{
    uint32_t first = p->cur;
    tok *kw = peek(p);
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
        tok_report(p, f, LG_DIAG_ERROR, "the include file name is empty");
        return;
    }
    if (!p->included) {
        session *s = p->s;
        lg_ginclude inc;
        memset(&inc, 0, sizeof inc);
        inc.path = f->s;
        set_loc(p, &inc.loc, f);
        cvec c = {0};
        cvec_above(p, &c, kw);
        cvec_inner(p, &c, first, last);
        inc.eol_comment = eol_of(p, last);
        inc.comments = cvec_finish(p, &c, &inc.n_comments);
        if (s->n_includes == s->cap_includes) {
            s->cap_includes = s->cap_includes ? s->cap_includes * 2 : 4;
            s->includes = lg_xrealloc(s->includes, s->cap_includes * sizeof *s->includes);
        }
        s->includes[s->n_includes++] = inc;
    }
    do_include(p, f);
}

/* A whole file: the version line, then statements. */
static void parse_body(parser *p)
{
    session *s = p->s;
    lg_graph *g = s->g;
    skip_nl(p);
    tok *t = peek(p);
    if (!p->included) {
        cvec hc = {0};
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
                char **hc = arena_alloc(parena(p), (g->n_header_comments + 1) * sizeof *hc);
                if (g->n_header_comments)
                    memcpy(hc, g->header_comments, g->n_header_comments * sizeof *hc);
                hc[g->n_header_comments++] = p->cm[v->eol];
                g->header_comments = hc;
            }
            if (!expect_eol(p, "the version line"))
                return;
        } else if (v->kind == T_INT && v->i > 1) {
            tok_report(p, v, LG_DIAG_ERROR, "graph format version %lld is newer than this "
                       "lightgraph reads (version 1)", (long long)v->i);
            return;
        } else if (v->kind == T_INT || v->kind == T_FLOAT) {
            tok_report(p, v, LG_DIAG_ERROR, "unknown graph format version '%.*s' (this "
                       "lightgraph reads version 1)", (int)v->len, p->src->text + v->off);
            return;
        } else {
            if (v->kind == T_ERR)
                advance(p);
            else
                tok_report(p, v, LG_DIAG_ERROR, "expected a version number after 'lightgraph' "
                           "(lightgraph 1), found %s", describe(p, v, buf));
            return;
        }
    } else if (t->kind == T_EOF) {
        tok_report(p, t, LG_DIAG_ERROR, "missing version line: a graph file starts with "
                   "'lightgraph 1' (this file has no statements)");
        return;
    } else {
        char buf[80];
        if (t->kind == T_ERR)
            advance(p);
        else
            tok_report(p, t, LG_DIAG_ERROR, "missing version line: a graph file starts with "
                       "'lightgraph 1', found %s", describe(p, t, buf));
        /* Go on as version 1 to find more problems. */
    }
    g->version = 1;

    while (!s->stop) {
        skip_nl(p);
        t = peek(p);
        if (t->kind == T_EOF) {
            if (!p->included) {
                cvec tc = {0};
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
                tok_report(p, t, LG_DIAG_ERROR, "the version line must come first, and only once");
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

/* ---- entry points ----------------------------------------------------------------------- */

static lg_graph *new_graph(void)
{
    lg_graph *g = lg_xcalloc(1, sizeof *g);
    pool *pl = lg_xcalloc(1, sizeof *pl);
    g->pool = pl;
    return g;
}

void lg_graph_free(lg_graph *g)
{
    if (!g)
        return;
    pool *pl = g->pool;
    if (pl) {
        for (uint32_t i = 0; i < pl->n_src; i++)
            free(pl->src[i]->owned);
        arena_free(&pl->a);
        free(pl->src);
        strmap_free(&pl->nodes);
        free(pl);
    }
    free(g);
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
    s.stack_abs[0] = abs ? arena_strdup(&pl->a, abs) : NULL;
    s.depth = 1;
    if (abs) {
        s.done = lg_xmalloc(8 * sizeof *s.done);
        s.cap_done = 8;
        s.done[s.n_done++] = s.stack_abs[0];
    }
    parser p;
    memset(&p, 0, sizeof p);
    p.s = &s;
    p.src = src;
    p.base_dir = base_dir ? arena_strdup(&pl->a, base_dir) : NULL;
    lex(&p, 0, src->len);
    parse_body(&p);
    free(p.t);
    free(p.cm);

    g->nodes = arena_copy(&pl->a, s.nodes, s.n_nodes * sizeof *s.nodes);
    g->n_nodes = s.n_nodes;
    g->outputs = arena_copy(&pl->a, s.outputs, s.n_outputs * sizeof *s.outputs);
    g->n_outputs = s.n_outputs;
    g->includes = arena_copy(&pl->a, s.includes, s.n_includes * sizeof *s.includes);
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
        lg_srcloc loc = {name, 0, 0, 0};
        lg_diags_add(diags, LG_DIAG_ERROR, loc, NULL, "graph text is too large (%zu bytes; the "
                     "limit is %u MiB)", len, MAX_FILE_BYTES >> 20);
        lg_graph_free(g);
        return NULL;
    }
    source *src = add_source(pl, name, text ? text : "", text ? len : 0, 1);
    return parse_root(g, src, base_dir, NULL, diags);
}

lg_graph *lg_graph_parse_file(const char *path, lg_diags *diags)
{
    lg_srcloc loc = {path, 0, 0, 0};
    size_t len = 0;
    char why[256];
    /* bounded: a FIFO, a device or a huge file is refused before a byte is read */
    char *text = lg_read_file_limit(path, MAX_FILE_BYTES, &len, why, sizeof why);
    if (!text) {
        lg_diags_add(diags, LG_DIAG_ERROR, loc, NULL, "cannot read graph file: %s", why);
        return NULL;
    }
    lg_graph *g = new_graph();
    source *src = add_source_ex(g->pool, path, text, len, 1, true);
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

int32_t lg_graph_find_node(const lg_graph *g, const char *name)
{
    pool *pl = g->pool;
    if (pl) {
        uint32_t i = strmap_find(&pl->nodes, name);
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
    for (uint32_t i = 0; pl && i < pl->n_src; i++)
        if (pl->src[i]->name == loc.file) {
            text = source_line(pl->src[i], loc.line, &n);
            break;
        }
    va_list ap;
    va_start(ap, fmt);
    char *msg = lg_vformat(fmt, ap);
    va_end(ap);
    lg_diags_add_line(d, level, loc, text, n, "%s", msg);
    free(msg);
}

/* ---- --set ------------------------------------------------------------------------------ */

static bool is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
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

int lg_graph_set(lg_graph *g, const char *assignment, lg_diags *diags)
{
    pool *pl = g->pool;
    uint32_t ordinal = ++pl->n_sets;
    size_t alen = strlen(assignment);
    if (alen > MAX_FILE_BYTES)
        alen = MAX_FILE_BYTES;
    source *src = add_source(pl, "<command line>", assignment, alen, ordinal);
    const char *a = src->text;
    session s;
    memset(&s, 0, sizeof s);
    s.pl = pl;
    s.g = g;
    s.d = diags;
    const char *form = " (--set NODE.PARAM=VALUE)";

    /* The value may be taken as raw text (a path, a string, an enum), not only lexed: the
     * whole assignment must be UTF-8, as a graph file is. */
    for (uint32_t i = 0; i < alen; i++) {
        unsigned char ch = (unsigned char)a[i];
        if (ch < 0x80)
            continue;
        int u = lg_utf8_char_len((const unsigned char *)a + i, alen - i);
        if (u == 0) {
            report(&s, src, LG_DIAG_ERROR, ordinal, i + 1, 1, "invalid UTF-8: byte 0x%02X at "
                   "byte offset %u%s", ch, i, form);
            return -1;
        }
        i += (uint32_t)u - 1;
    }

    uint32_t i = 0;
    while (i < alen && is_space(a[i]))
        i++;
    uint32_t n0 = i;
    while (i < alen && (i == n0 ? is_ident_start((unsigned char)a[i])
                                : is_ident_char((unsigned char)a[i])))
        i++;
    uint32_t n1 = i;
    if (n1 == n0) {
        report(&s, src, LG_DIAG_ERROR, ordinal, n0 + 1, (uint32_t)(alen - n0),
               "expected a node name%s", form);
        return -1;
    }
    if (i >= alen || a[i] != '.') {
        report(&s, src, LG_DIAG_ERROR, ordinal, i + 1, i < alen ? 1 : 0,
               "expected '.' and a parameter name after '%.*s'%s", (int)(n1 - n0), a + n0, form);
        return -1;
    }
    i++;
    uint32_t k0 = i;
    while (i < alen && (i == k0 ? is_ident_start((unsigned char)a[i])
                                : is_ident_char((unsigned char)a[i])))
        i++;
    uint32_t k1 = i;
    if (k1 == k0) {
        report(&s, src, LG_DIAG_ERROR, ordinal, k0 + 1, k0 < alen ? 1 : 0,
               "expected a parameter name after '%.*s.'%s", (int)(n1 - n0), a + n0, form);
        return -1;
    }
    while (i < alen && is_space(a[i]))
        i++;
    if (i >= alen || a[i] != '=') {
        report(&s, src, LG_DIAG_ERROR, ordinal, i + 1, i < alen ? 1 : 0,
               "expected '=' after '%.*s'%s", (int)(k1 - n0), a + n0, form);
        return -1;
    }
    i++;
    while (i < alen && is_space(a[i]))
        i++;
    uint32_t v0 = i, v1 = (uint32_t)alen;
    while (v1 > v0 && is_space(a[v1 - 1]))
        v1--;

    char *node_name = arena_strndup(&pl->a, a + n0, n1 - n0);
    int32_t ni = lg_graph_find_node(g, node_name);
    if (ni < 0) {
        const char **names = lg_xmalloc((g->n_nodes + 1) * sizeof *names);
        for (uint32_t j = 0; j < g->n_nodes; j++)
            names[j] = g->nodes[j].name;
        const char *sug = lg_suggest(node_name, names, g->n_nodes);
        if (sug)
            report(&s, src, LG_DIAG_ERROR, ordinal, n0 + 1, n1 - n0,
                   "unknown node '%s'; did you mean '%s'?", node_name, sug);
        else
            report(&s, src, LG_DIAG_ERROR, ordinal, n0 + 1, n1 - n0, "unknown node '%s'",
                   node_name);
        free(names);
        return -1;
    }

    /* The value stays raw; try it as a literal now, for the types that want one. */
    lg_gvalue v;
    memset(&v, 0, sizeof v);
    v.kind = LG_GV_RAW;
    v.loc = (lg_srcloc){src->name, ordinal, v0 + 1, v1 - v0};
    v.text = arena_strndup(&pl->a, a + v0, v1 - v0);
    v.base_dir = NULL;
    {
        lg_diags tmp = {0};
        session vs;
        memset(&vs, 0, sizeof vs);
        vs.pl = pl;
        vs.g = g;
        vs.d = &tmp;
        parser vp;
        memset(&vp, 0, sizeof vp);
        vp.s = &vs;
        vp.src = src;
        lex(&vp, v0, v1);
        skip_nl(&vp);
        lg_gvalue item;
        if (peek(&vp)->kind == T_EOF) {
            v.s = arena_strdup(&pl->a, "the value is empty");
        } else if (parse_value(&vp, &item)) {
            skip_nl(&vp);
            tok *t = peek(&vp);
            if (t->kind == T_EOF) {
                v.items = arena_copy(&pl->a, &item, sizeof item);
                v.n_items = 1;
            } else {
                v.s = arena_strdup(&pl->a, "it is more than one value");
            }
        } else {
            v.s = arena_strdup(&pl->a, tmp.n ? tmp.items[0].message : "it is not a value");
        }
        lg_diags_free(&tmp);
        free(vp.t);
        free(vp.cm);
    }

    lg_gnode *n = &g->nodes[ni];
    char *key = arena_strndup(&pl->a, a + k0, k1 - k0);
    lg_srcloc key_loc = {src->name, ordinal, k0 + 1, k1 - k0};
    for (uint32_t j = 0; j < n->n_assigns; j++) {
        if (strcmp(n->assigns[j].key, key) == 0) {
            n->assigns[j].value = v;
            n->assigns[j].key_loc = key_loc;
            return 0;
        }
    }
    lg_gassign *as = arena_alloc(&pl->a, (n->n_assigns + 1) * sizeof *as);
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
