/*
 * host/graph/graph.h: graph files, the graph layer's interface to the layers above (private
 * to the host). docs/graph-format.md is the spec.
 *
 * Two stages:
 *   lg_graph_parse()    text -> lg_graph: syntax only (version line, nodes, assignments,
 *                       references, outputs, includes). No schema needed.
 *   lg_graph_check()    lg_graph + schema -> resolved nodes: types, parameters (typed,
 *                       ranged, defaults filled), edges (node, port), outputs; cycles.
 * Overrides (--set node.param=value) are applied between the two with lg_graph_set().
 *
 * Every problem becomes an lg_diag with file:line:col, the offending source line and a
 * did-you-mean where one applies; both stages collect as many as they can before failing.
 *
 * Ownership: an lg_graph owns every string and array it points to (lg_graph_free); an
 * lg_checked points into the lg_graph it was made from (free it first) and the schema;
 * lg_diags own copies of everything they hold, so they outlive both.
 */
#ifndef LG_HOST_GRAPH_H
#define LG_HOST_GRAPH_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "lightgraph/plugin.h"

typedef struct lg_srcloc {
    const char *file;   /* owned by the graph (interned path as given / resolved) */
    uint32_t line, col; /* 1-based; line 0 = no location (e.g. command line) */
    uint32_t len;       /* length of the offending text, for the ~~~ underline */
} lg_srcloc;

typedef enum lg_gv_kind {
    LG_GV_BOOL = 1,
    LG_GV_INT, /* integer literal (also acceptable where a float is expected) */
    LG_GV_FLOAT,
    LG_GV_STRING, /* "quoted" */
    LG_GV_LIST,   /* [a, b, c] */
    LG_GV_IDENT,  /* bare name or name.port: a reference, or an enum value */
    LG_GV_RAW,    /* --set text, interpreted by lg_graph_check with the parameter's type:
                   * `text` is the raw text; items[0] (n_items 1) is the text parsed as one
                   * literal when it is one, otherwise `s` says why it is not */
} lg_gv_kind;

/* The items of a list of plain numbers, kept compact (12 bytes an item): a value and a
 * tag each. A tag packs the item's byte offset from the list's '[' (bits 0-23), the length
 * of its literal (bits 24-30, at most LG_GNUM_MAX_TEXT) and whether it is a float (bit 31).
 * Use lg_glist_item() to see an item as an lg_gvalue. */
#define LG_GNUM_MAX_TEXT 64
typedef union lg_gnum {
    int64_t i;
    double f;
} lg_gnum;

typedef struct lg_gnums {
    const char *at; /* the source text at the list's '[' (owned by the graph) */
    uint32_t *tag;
    lg_gnum *val;
} lg_gnums;

typedef struct lg_gvalue {
    lg_gv_kind kind;
    lg_srcloc loc;
    bool b;
    int64_t i;
    double f;
    char *s;                 /* STRING: the unescaped text; IDENT: the node name */
    char *port;              /* IDENT: after the dot, or NULL */
    struct lg_gvalue *items; /* LIST: the items (NULL when `nums` holds them); RAW: below */
    uint32_t n_items;
    const lg_gnums *nums; /* LIST of numbers only: its n_items items, compact; else NULL */
    char *text;           /* the literal as written (for messages); NULL for a compact LIST
                           * (`nums`), whose items have theirs (lg_glist_item) */
    const char *base_dir; /* directory against which a relative path resolves; NULL: the
                           * current directory */
} lg_gvalue;

typedef struct lg_gassign {
    char *key;
    lg_srcloc key_loc;
    lg_gvalue value;
    char **comments; /* comment lines above the entry (and any inside its value) */
    uint32_t n_comments;
    char *eol_comment; /* comment at the end of the entry's line, or NULL */
    bool blank_before; /* a blank line preceded it (fmt keeps one in a multi-line node) */
} lg_gassign;

/* Comments are stored as written from their '#' on, without trailing white space. In a
 * list of comment lines, an empty string stands for blank lines between or after them. */

typedef struct lg_gnode {
    char *name;
    lg_srcloc loc; /* of the name */
    char *type;
    lg_srcloc type_loc;
    lg_gassign *assigns;
    uint32_t n_assigns;
    char **comments; /* comment lines directly above the node, kept by fmt */
    uint32_t n_comments;
    char *eol_comment;   /* after the '{' or the '}' on the same line, or NULL */
    char **end_comments; /* comment lines after the last entry, before the '}' */
    uint32_t n_end_comments;
    bool blank_before; /* a blank line preceded it (fmt keeps one) */
    bool included;     /* it came from an included file (fmt does not print it) */
} lg_gnode;

/* The pixel type of an EXR output: `output NODE "f.exr" half` (or float). */
enum { LG_OUT_EXR_AUTO = 0, LG_OUT_EXR_HALF = 1, LG_OUT_EXR_FLOAT = 2 };

typedef struct lg_goutput {
    lg_gvalue ref; /* IDENT */
    char *path;    /* as written */
    int exr_pixel; /* LG_OUT_EXR_*: AUTO is float for rgba32f, half for rgba16f */
    lg_srcloc path_loc;
    const char *base_dir;
    char **comments;
    uint32_t n_comments;
    char *eol_comment;
    bool blank_before;
    bool included;
} lg_goutput;

typedef struct lg_ginclude {
    char *path; /* as written */
    lg_srcloc loc;
    char **comments;
    uint32_t n_comments;
    char *eol_comment;
} lg_ginclude;

typedef enum lg_diag_level { LG_DIAG_ERROR = 0, LG_DIAG_WARNING, LG_DIAG_NOTE } lg_diag_level;

typedef struct lg_diag {
    lg_diag_level level;
    lg_srcloc loc; /* loc.file is the diagnostic's own copy */
    char *message;
    char *line_text;   /* an excerpt of the source line (at most LG_DIAG_EXCERPT_COLS
                        * characters around the column, "..." where cut, control bytes
                        * and invalid UTF-8 shown as '?'), or NULL */
    uint32_t text_col; /* the caret's byte column (1-based) inside line_text */
    uint32_t text_len; /* the underline's length in bytes inside line_text */
} lg_diag;

/* How much of a source line a diagnostic shows: a line of a 10 MB graph file is not echoed
 * whole, only this many characters around the column (plus "..." marks where cut). */
#define LG_DIAG_EXCERPT_COLS 100
/* A message longer than this many bytes is cut (at a character boundary, "..." added): a
 * message that quotes a name or a path quotes at most this much of it. */
#define LG_DIAG_MAX_MESSAGE 1024

typedef struct lg_diags {
    lg_diag *items;
    uint32_t n, cap;
    uint32_t errors;
} lg_diags;

/* A parsed graph (one file with its includes merged; nodes in file order). */
typedef struct lg_graph {
    int version;
    char *path; /* the top file as given */
    lg_gnode *nodes;
    uint32_t n_nodes;
    lg_goutput *outputs;
    uint32_t n_outputs;
    lg_ginclude *includes; /* the top file's include statements, for fmt */
    uint32_t n_includes;
    char **header_comments; /* comment lines above the version line */
    uint32_t n_header_comments;
    char **trailing_comments;
    uint32_t n_trailing_comments;
    void *pool; /* private: interned strings, file texts */
} lg_graph;

/* Item i of a LIST as an lg_gvalue: &list->items[i], or for a compact list of numbers
 * one made in *tmp (its text in tmp->text; its location computed when `want_loc`, which
 * costs a scan from the '[' to the item). */
typedef struct lg_gitem {
    lg_gvalue v;
    char text[LG_GNUM_MAX_TEXT + 1];
} lg_gitem;
const lg_gvalue *lg_glist_item(const lg_gvalue *list, uint32_t i, lg_gitem *tmp, bool want_loc);

/* Parses `path` (and the files it includes; relative include paths resolve against the
 * including file, absolute paths and '..' are allowed; include cycles are errors; a file
 * included a second time adds nothing; an included file that does not start with the
 * version line is refused with one message). Every file is read by the bounded reader
 * (regular files only, 16 MiB for the graph with its includes); the other limits (tokens,
 * list items, nodes, depth) are in docs/graph-format.md "Limits".
 * Syntax errors, duplicate node names (across files too) and keys set twice in one node
 * are found here. Returns NULL when any error was found; the diagnostics are in `diags`
 * either way. */
lg_graph *lg_graph_parse_file(const char *path, lg_diags *diags);
/* The same from memory (fuzzing, tests); `name` is the file name used in messages and the
 * base for relative paths is `base_dir` (may be NULL: the current directory). */
lg_graph *lg_graph_parse_string(const char *name, const char *text, size_t len,
                                const char *base_dir, lg_diags *diags);
void lg_graph_free(lg_graph *g);

/* The files g was read from: the top file and every file it includes, as absolute paths
 * (the viewer watches them). *out is a malloc'd array of malloc'd strings (free each, then
 * the array); returns their number. */
uint32_t lg_graph_files(const lg_graph *g, char ***out);

/* The index of the node called `name` in g->nodes, or -1. */
int32_t lg_graph_find_node(const lg_graph *g, const char *name);

/* Adds a diagnostic at `loc` (a location inside `g`, from any of its files or --set
 * assignments) with that location's source line. For everyone who reports on a node of
 * a graph: the checker, the planner, the executor. */
void lg_graph_diag(lg_diags *d, const lg_graph *g, lg_diag_level level, lg_srcloc loc,
                   const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;

/* Applies one command-line override "node.param=value" (it replaces an entry with the same
 * key, or adds one). The value text is kept raw (LG_GV_RAW) and
 * interpreted by lg_graph_check with the parameter's type (so `--set src.file=a.exr` is a
 * path, `--set tone.backend=cl` an enum value, `--set tone.key=0.2` a float, `--set
 * tone.image=other` a reference). Relative paths resolve against the current directory.
 * Errors (syntax, unknown node, with did-you-mean) go to diags; returns 0 or -1. Their
 * location is the file "<command line>", line n for the n-th call on this graph, the
 * column inside `assignment`. */
int lg_graph_set(lg_graph *g, const char *assignment, lg_diags *diags);

/* ---- checking against the plugins' schemas --------------------------------------------------- */

/* Where node types come from (the registry). */
typedef struct lg_schema {
    void *ctx;
    /* NULL if no plugin declares the type */
    const lg_node_type *(*lookup)(void *ctx, const char *type_name);
    /* all known type names, for did-you-mean */
    uint32_t n_names;
    const char *const *names;
    /* The pixel limit in force (lg_image_max_pixels()): an image size that parameters
     * marked LG_ROLE_IMAGE_WIDTH / _HEIGHT give beyond it is an error. 0: not checked. */
    uint64_t max_pixels;
} lg_schema;

typedef struct lg_edge {
    int32_t node;  /* source node index in lg_checked.nodes, -1 if unconnected */
    uint32_t port; /* output port index of the source */
    uint32_t part; /* 0: the whole output; k > 0: part k-1 of its composite kind
                    * (a reference NODE.PART, lightgraph/kinds.h) */
} lg_edge;

typedef struct lg_cnode {
    const lg_gnode *g; /* the parsed node */
    const lg_node_type *type;
    lg_value *params; /* type->n_params values, defaults filled; PATH resolved
                       * to absolute paths; strings owned by lg_checked */
    bool *param_set;  /* whether the graph (or --set) gave the value */
    lg_edge *inputs;  /* type->n_inputs */
} lg_cnode;

typedef struct lg_coutput {
    const lg_goutput *g;
    int32_t node;
    uint32_t port;
    uint32_t part; /* as lg_edge.part */
    char *path;    /* resolved (absolute, or as -o gave it) */
} lg_coutput;

typedef struct lg_checked {
    lg_cnode *nodes; /* same order as lg_graph.nodes */
    uint32_t n_nodes;
    lg_coutput *outputs;
    uint32_t n_outputs;
    uint32_t *topo; /* node indices in a topological order (inputs first) */
    void *pool;
} lg_checked;

/* Resolves and checks every node of `g`: unknown types, unknown parameters (did-you-mean
 * over parameters and inputs), renamed parameters (warning), types and ranges (naming the
 * expected type or range), references (did-you-mean over node names; unknown ports with
 * the list of the node's outputs), resource kinds of edges, missing required inputs,
 * a parameter set twice (under its old and new names), output statements, and cycles
 * (naming every node on the cycle). A --set value wins over the file's. Returns NULL if
 * any error was found. */
lg_checked *lg_graph_check(const lg_graph *g, const lg_schema *schema, lg_diags *diags);
void lg_checked_free(lg_checked *c);

/* ---- printing -------------------------------------------------------------------------------- */

/* The canonical text of a parsed graph (lightgraph fmt): formatting it again changes
 * nothing. Comments are kept. Includes are printed as include statements, and the nodes
 * and outputs that came from included files are not printed. Returns a malloc'd string. */
char *lg_graph_format(const lg_graph *g);
/* Graphviz dot text of a checked graph: nodes with their type, edges labelled by port,
 * output files as boxes. With c == NULL (a graph that did not check), edges are drawn
 * from the references that name a node. Returns a malloc'd string. */
char *lg_graph_dot(const lg_graph *g, const lg_checked *c);

/* ---- diagnostics ----------------------------------------------------------------------------- */

/* Adds a diagnostic; `line_text` (NUL-terminated, or NULL) is the whole source line: only
 * a bounded excerpt around loc.col is kept. */
void lg_diags_add(lg_diags *d, lg_diag_level level, lg_srcloc loc, const char *line_text,
                  const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 5, 6)))
#endif
    ;
/* The same with the line given as `n` bytes (no NUL needed, `line` may be NULL): the
 * caller need not copy a long line to report on it. */
void lg_diags_add_line(lg_diags *d, lg_diag_level level, lg_srcloc loc, const char *line, size_t n,
                       const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 6, 7)))
#endif
    ;
/* Prints "file:line:col: error: message", the source line and a caret line, colourless. */
void lg_diags_print(const lg_diags *d, FILE *f);
void lg_diags_free(lg_diags *d);

/* The length (1 to 4) of the well-formed UTF-8 character at s[0, n), or 0 when the bytes
 * there are not one: a stray continuation byte, a truncated sequence, an overlong form, a
 * UTF-16 surrogate (U+D800..U+DFFF) or a code point above U+10FFFF. */
int lg_utf8_char_len(const unsigned char *s, size_t n);

/* The closest of `names` to `word` by edit distance (case-insensitive, allowing one
 * transposition), or NULL if none is close enough to suggest. */
const char *lg_suggest(const char *word, const char *const *names, uint32_t n);

#endif
