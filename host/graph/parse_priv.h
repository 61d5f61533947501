/*
 * host/graph/parse_priv.h: what the files of the graph parser share (private to
 * host/graph/: only its .c files include it; the layers above see graph/graph.h alone).
 *
 * The parser is cut by job, each file using only what is declared here:
 *
 *   arena.c    the arena every string and array of a graph lives in; a string -> index map
 *   source.c   the pool (an lg_graph's private part): the texts a graph came from, lines
 *              found by position, messages at a position; lg_graph_free, _files, _diag,
 *              _find_node
 *   lexer.c    text -> tokens (comments attached to tokens, numbers on a line of a list
 *              packed into one token, lexical errors carried in T_ERR tokens)
 *   parse.c    tokens -> lg_graph: the grammar (version line, nodes, values, lists,
 *              output and include statements), error recovery, the entry points
 *   include.c  an include statement's file: found, read (bounded), parsed once, no cycles
 *   set.c      --set NODE.PARAM=VALUE (lg_graph_set)
 *
 * Everything a graph points to is allocated in its pool's arena and freed with it
 * (lg_graph_free); the token and comment arrays of one source's parse are the parser's
 * own (malloc'd, freed when the source is parsed).
 */
#ifndef LG_HOST_GRAPH_PARSE_PRIV_H
#define LG_HOST_GRAPH_PARSE_PRIV_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "graph/graph.h"

/* The limits of a graph (docs/graph-format.md, "Limits"); each is tested in
 * tests/unit/parser. They keep the parser's memory linear in its input and small: a token
 * costs 64 bytes while it is parsed; an item of a list that holds more than numbers about
 * 250 (its token, its comma's, an lg_gvalue and its text); an item of a list of numbers 12
 * (the numbers of a line of a list are one token: numrun). */
#define MAX_FILE_BYTES                                                                             \
    (16u << 20)               /* a file and everything it includes, in all; this
                               * also keeps offsets in 32 bits */
#define MAX_TOKENS (1u << 20) /* names, numbers, strings and punctuation, all files */
#define MAX_LIST_ITEMS 65536  /* items of one list (no parameter takes more than 3) */
#define MAX_LIST_DEPTH 32
#define MAX_INCLUDE_DEPTH 32
#define MAX_NODES 100000
#define MAX_NAME_BYTES 256 /* a name, key, type or NODE.PORT reference */
#define MAX_ERRORS 100

/* ---- arena.c: the arena ---------------------------------------------------------------------- */

typedef struct ablock {
    struct ablock *next;
    size_t used, cap;
    max_align_t data[];
} ablock;

/* Blocks of at least 32 KiB, freed all at once (lg_arena_free); nothing is freed alone.
 * Allocations are aligned for any type. An arena starts zeroed ({0}). */
typedef struct arena {
    ablock *head;
} arena;

void *lg_arena_alloc(arena *a, size_t n);
void *lg_arena_zalloc(arena *a, size_t n);
/* s[0, n) and a NUL */
char *lg_arena_strndup(arena *a, const char *s, size_t n);
char *lg_arena_strdup(arena *a, const char *s);
/* A copy of n bytes at p; NULL when n is 0. */
void *lg_arena_copy(arena *a, const void *p, size_t n);
void lg_arena_free(arena *a);

/* ---- arena.c: a string -> index map (open addressing) ---------------------------------------- */

/* The keys are not copied: they must outlive the map (they are the arena's, or a node's
 * entries'). A map starts zeroed ({0}); lg_strmap_free frees its tables. */
typedef struct strmap {
    const char **keys;
    uint32_t *vals;
    uint32_t cap, n;
} strmap;

#define STRMAP_NONE UINT32_MAX

/* The value stored for `key`, or STRMAP_NONE. */
uint32_t lg_strmap_find(const strmap *m, const char *key);
/* Stores `val` for `key` (replacing an older value). */
void lg_strmap_put(strmap *m, const char *key, uint32_t val);
void lg_strmap_free(strmap *m);

/* ---- source.c: sources and the pool ---------------------------------------------------------- */

/* One text the graph came from: a file, a string, or one --set assignment. */
typedef struct source {
    const char *name; /* what messages call it; lg_srcloc.file points here */
    const char *text; /* NUL-terminated copy (may contain NULs, which are errors) */
    uint32_t len;
    uint32_t first_line; /* 1 for files; n for the n-th --set */
    /* The last line looked up (messages come mostly in file order): lines are found by
     * scanning from here, so that a file of 16 million empty lines costs no table. */
    uint32_t seen_line, seen_off;
    char *owned; /* the text when the source took it over (freed with the pool) */
} source;

/* lg_graph.pool */
typedef struct pool {
    arena a;
    source **src;
    uint32_t n_src, cap_src;
    strmap nodes; /* node name -> index in lg_graph.nodes */
    uint32_t n_sets;
} pool;

/* A new source in the pool. `text` is copied, or taken over when `take` (a malloc'd block
 * of len + 1 bytes ending in a NUL, as lg_read_file_limit gives; the pool frees it): a
 * file's text is not held twice. */
source *lg_source_add(pool *pl, const char *name, const char *text, size_t len, uint32_t first_line,
                      bool take);
/* Line `line` of `s` without its line break: *n bytes at the returned pointer (inside the
 * source's text, not copied); NULL if out of range. */
const char *lg_source_line(source *s, uint32_t line, size_t *n);
/* The source whose name is `name` (the same pointer, as an lg_srcloc.file holds), or
 * NULL. */
source *lg_pool_source(const pool *pl, const char *name);

/* ---- parse session (one lg_graph_parse_* call, all files) ------------------------------------ */

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
    uint32_t n_tokens; /* lexed so far, all files (MAX_TOKENS) */
    uint64_t n_bytes;  /* read so far, all files (MAX_FILE_BYTES in all) */
} session;

/* A message at line:col (len bytes underlined) of `src` (NULL: no source line shown).
 * Errors are counted; after MAX_ERRORS a note says so and the session stops reporting. */
void lg_vreport(session *s, source *src, lg_diag_level lvl, uint32_t line, uint32_t col,
                uint32_t len, const char *fmt, va_list ap);
void lg_report(session *s, source *src, lg_diag_level lvl, uint32_t line, uint32_t col,
               uint32_t len, const char *fmt, ...) __attribute__((format(printf, 7, 8)));

/* ---- tokens (lexer.c makes them, parse.c reads them) ----------------------------------------- */

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
    T_NUMS, /* a run of numbers in a list on one line, "1, 2.5, 3": tok.s points to a
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

static inline uint32_t make_tag(uint32_t off, uint32_t len, bool is_float)
{
    return off | len << 24 | (is_float ? TAG_FLOAT : 0);
}

typedef struct tok {
    uint8_t kind;
    bool blank_before; /* a blank line came before it (or before its comments) */
    uint32_t off, len, line, col;
    uint32_t c_first, c_n; /* the comments above it, in parser.cm */
    int32_t eol;           /* the comment that ends its line, or -1 */
    int64_t i;
    double f;
    char *s;    /* IDENT: name; STRING: the unescaped text; ERR: message */
    char *port; /* IDENT: after the '.', or NULL */
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

static inline arena *parena(parser *p)
{
    return &p->s->pl->a;
}

static inline bool is_ident_start(int c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}

static inline bool is_digit(int c)
{
    return c >= '0' && c <= '9';
}

static inline bool is_ident_char(int c)
{
    return is_ident_start(c) || is_digit(c);
}

/* White space inside a line (a line break is a token). */
static inline bool is_blank(int c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/* ---- lexer.c --------------------------------------------------------------------------------- */

/* Splits p->src->text[pos, end) into p->t (ending with a T_EOF) and p->cm. `pos` is 0 for
 * files; for a --set value it is the offset of the value inside the assignment, so that
 * columns point into it. */
void lg_lex(parser *p, uint32_t pos, uint32_t end);

/* ---- parse.c --------------------------------------------------------------------------------- */

static inline tok *peek(parser *p)
{
    return &p->t[p->cur];
}

/* Lexes and parses the whole of `src` into the session (nodes, outputs, includes; the
 * graph's header and trailing comments when it is the top file, not `included`).
 * `base_dir` is the pool's (or NULL). */
void lg_parse_source(session *s, source *src, const char *base_dir, bool included);
/* One value at the current token (a list with what it holds); false after an error. */
bool lg_parse_value(parser *p, lg_gvalue *v);
/* Steps over line breaks; whether there were any. */
bool lg_skip_nl(parser *p);
void lg_tok_report(parser *p, const tok *t, lg_diag_level lvl, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* ---- include.c ------------------------------------------------------------------------------- */

/* The include statement whose file name is the string token `f` (in p's file): resolves
 * it against p->base_dir and reads it. Returns the source to parse (pushed on the session's
 * include stack, with its folder in *base_dir: the caller parses it with lg_parse_source
 * and then pops it, s->depth--), or NULL when there is nothing to parse: already parsed
 * once, or an error reported at `f` (a cycle, too deep a nesting, an unreadable file, one
 * beyond the graph's size, one that is not a graph file). */
source *lg_include_open(parser *p, const tok *f, const char **base_dir);

#endif
