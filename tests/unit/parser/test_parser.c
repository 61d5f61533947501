/*
 * tests/unit/parser/test_parser.c: graph files (docs/graph-format.md) against a fake schema:
 * every diagnostic with its exact place and text, includes, --set, fmt, dot, order, cycles.
 *
 * Usage: test_parser DATA_DIR [EXAMPLES_DIR]
 * Diagnostics are compared by their first lines, "file:line:col: level: message", joined
 * with new lines; the printer's source and caret lines have their own tests.
 */
#include <dirent.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>

#include "fake_schema.h"
#include "graph/graph.h"
#include "base/util.h"
#include "lightgraph/kinds.h"

static int failures;
static int checks;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        checks++;                                                                                  \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);               \
            failures++;                                                                            \
        }                                                                                          \
    } while (0)

static void check_str(const char *file, int line, const char *got, const char *want)
{
    checks++;
    if (!got || strcmp(got, want) != 0) {
        fprintf(stderr, "%s:%d: mismatch\n--- want:\n%s\n--- got:\n%s\n---\n", file, line, want,
                got ? got : "(null)");
        failures++;
    }
}
#define CHECK_STR(got, want) check_str(__FILE__, __LINE__, (got), (want))

/* The first line of every diagnostic, as lg_diags_print writes it. */
static char *headers(const lg_diags *d)
{
    lg_str b = { 0 };
    static const char *lv[] = { "error", "warning", "note" };
    for (uint32_t i = 0; i < d->n; i++) {
        const lg_diag *g = &d->items[i];
        if (i)
            lg_str_addc(&b, '\n');
        if (g->loc.line)
            lg_str_addf(&b, "%s:%u:%u: ", g->loc.file, g->loc.line, g->loc.col);
        else if (g->loc.file)
            lg_str_addf(&b, "%s: ", g->loc.file);
        lg_str_addf(&b, "%s: %s", lv[g->level], g->message);
    }
    return lg_str_take(&b);
}

static char *printed(const lg_diags *d)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    lg_diags_print(d, f);
    fclose(f);
    return buf;
}

typedef struct run {
    lg_graph *g;
    lg_checked *c;
    lg_diags d;
    int set_failed;
} run;

/* Parses `text` as "t.lgraph" in the folder /base, applies the --set assignments
 * (NULL-terminated), and checks it against the fake schema. */
static void run_text(run *r, const char *text, const char *const *sets)
{
    memset(r, 0, sizeof *r);
    r->g = lg_graph_parse_string("t.lgraph", text, strlen(text), "/base", &r->d);
    if (!r->g)
        return;
    for (const char *const *s = sets; s && *s; s++)
        if (lg_graph_set(r->g, *s, &r->d) != 0)
            r->set_failed++;
    if (r->set_failed)
        return;
    r->c = lg_graph_check(r->g, lg_fake_schema(), &r->d);
}

static void run_free(run *r)
{
    lg_checked_free(r->c);
    lg_graph_free(r->g);
    lg_diags_free(&r->d);
}

/* Runs and compares the diagnostics (after the graph is gone: they own their text). */
static void expect_at(const char *file, int line, const char *text, const char *const *sets,
                      const char *want)
{
    run r;
    run_text(&r, text, sets);
    lg_checked_free(r.c);
    lg_graph_free(r.g);
    char *h = headers(&r.d);
    check_str(file, line, h, want);
    free(h);
    lg_diags_free(&r.d);
}
#define EXPECT(text, want) expect_at(__FILE__, __LINE__, (text), NULL, (want))
#define EXPECT_SET(text, sets, want) expect_at(__FILE__, __LINE__, (text), (sets), (want))

#define HDR "lightgraph 1\nsrc = image {}\n"   /* the tested statement is on line 3 */
#define TONE "tone = reinhard { image = src, " /* the next key starts at column 32 */

/* ---- syntax ---------------------------------------------------------------------------------- */

static void test_version(void)
{
    EXPECT("", "t.lgraph:1:1: error: missing version line: a graph file starts with "
               "'lightgraph 1' (this file has no statements)");
    EXPECT("# only a comment\n", "t.lgraph:2:1: error: missing version line: a graph file "
                                 "starts with 'lightgraph 1' (this file has no statements)");
    EXPECT("src = image {}\n", "t.lgraph:1:1: error: missing version line: a graph file starts "
                               "with 'lightgraph 1', found 'src'");
    /* a missing version line does not stop the search for other errors */
    EXPECT("src = image {}\nsrc = image {}\n",
           "t.lgraph:1:1: error: missing version line: a graph file starts with 'lightgraph 1', "
           "found 'src'\n"
           "t.lgraph:2:1: error: node 'src' is defined twice\n"
           "t.lgraph:1:1: note: 'src' was first defined here");
    EXPECT("lightgraph 2\nsrc = image {}\n",
           "t.lgraph:1:12: error: graph format version 2 is newer than this lightgraph reads "
           "(version 1)");
    EXPECT("lightgraph 0\n", "t.lgraph:1:12: error: unknown graph format version '0' (this "
                             "lightgraph reads version 1)");
    EXPECT("lightgraph 1.5\n", "t.lgraph:1:12: error: unknown graph format version '1.5' (this "
                               "lightgraph reads version 1)");
    EXPECT("lightgraph\n", "t.lgraph:1:11: error: expected a version number after 'lightgraph' "
                           "(lightgraph 1), found the end of the line");
    EXPECT("lightgraph 1 2\n", "t.lgraph:1:14: error: expected a new line after the version "
                               "line, found '2'");
    EXPECT(HDR "lightgraph 1\n",
           "t.lgraph:3:1: error: the version line must come first, and only once");
    /* comments and blank lines may come first; a byte order mark is skipped */
    EXPECT("# header\n\n   # more\nlightgraph 1 # v\nsrc = image {}\n", "");
    EXPECT("\xEF\xBB\xBFlightgraph 1\nsrc = image {}\n", "");
}

static void test_syntax_errors(void)
{
    EXPECT(HDR "tone = reinhard { image = src, mode = \"rgb }\n",
           "t.lgraph:3:39: error: string is not closed before the end of the line\n"
           "t.lgraph:3:17: error: '{' of node 'tone' is never closed");
    EXPECT(HDR "b = blur { image = src, label = \"a\\qb\" }\n",
           "t.lgraph:3:35: error: unknown escape '\\q' in a string (use \\\" \\\\ \\n or \\t)");
    EXPECT(HDR "b = blur { image = src, label = \"a\x01\" }\n",
           "t.lgraph:3:35: error: control character 0x01 in a string");
    EXPECT(HDR "src = image {}\n", "t.lgraph:3:1: error: node 'src' is defined twice\n"
                                   "t.lgraph:2:1: note: 'src' was first defined here");
    EXPECT(HDR TONE "key = 1, key = 2 }\n",
           "t.lgraph:3:41: error: key 'key' is set twice in node 'tone'\n"
           "t.lgraph:3:32: note: 'key' was first set here");
    EXPECT(HDR "tone = reinhard\nx = image {}\n",
           "t.lgraph:3:16: error: expected '{' after the node type 'reinhard', found the end of "
           "the line");
    EXPECT(HDR "tone = { image = src }\n",
           "t.lgraph:3:8: error: expected a node type after '=', found '{'");
    EXPECT(HDR "tone = reinhard { image src }\n",
           "t.lgraph:3:25: error: expected '=' after the key 'image', found 'src'");
    EXPECT(HDR "tone = reinhard { image = src key = 1 }\n",
           "t.lgraph:3:31: error: expected ',' or a new line after the value of 'image', found "
           "'key'");
    EXPECT(HDR "tone = reinhard { image = src,, key = 1 }\n",
           "t.lgraph:3:31: error: expected a key or '}' in node 'tone', found ','");
    EXPECT(HDR "tone = reinhard { image = }\n",
           "t.lgraph:3:27: error: expected a value, found '}'");
    EXPECT(HDR "tone = reinhard { image: src }\n",
           "t.lgraph:3:24: error: unexpected ':' (keys are set with '=')");
    EXPECT(HDR "tone = reinhard { image = src; key = 1 }\n",
           "t.lgraph:3:30: error: unexpected ';' (entries are separated by ',' or new lines)");
    EXPECT(HDR "a = image {} b\n", "t.lgraph:3:14: error: expected a new line after '}', found "
                                   "'b'");
    EXPECT(HDR "output = image {}\n",
           "t.lgraph:3:1: error: 'output' is a reserved word and cannot name a node");
    EXPECT(HDR "true = image {}\n",
           "t.lgraph:3:1: error: 'true' is a reserved word and cannot name a node");
    EXPECT(HDR "a.b = image {}\n", "t.lgraph:3:1: error: a node name cannot contain '.'");
    EXPECT(HDR "a = x.y {}\n", "t.lgraph:3:5: error: a node type cannot contain '.'");
    EXPECT(HDR "tone = reinhard { image.x = src }\n",
           "t.lgraph:3:19: error: a key cannot contain '.'");
    EXPECT(HDR "tone = reinhard { image = src.out.x }\n",
           "t.lgraph:3:27: error: 'src.out.x' has more than one '.' (a reference is NODE or "
           "NODE.PORT)");
    EXPECT(HDR "tone = reinhard { image = src. }\n",
           "t.lgraph:3:27: error: expected a port name after 'src.'");
    EXPECT(HDR "src2\n", "t.lgraph:3:5: error: expected '=' after the node name 'src2' (NAME = "
                         "TYPE { ... }), found the end of the line");
    EXPECT(HDR "= image {}\n", "t.lgraph:3:1: error: expected a statement (NAME = TYPE { ... }, "
                               "output or include), found '='");
    EXPECT(HDR "x = image { } @\n", "t.lgraph:3:15: error: unexpected character '@'");
    EXPECT(HDR "x = image { } \xC3\xA9\n", "t.lgraph:3:15: error: unexpected character '\xC3\xA9'");
    EXPECT(HDR "x = image { } \xFF\n", "t.lgraph:3:15: error: unexpected byte 0xFF at byte "
                                       "offset 42 (not UTF-8 text)");
    EXPECT(HDR "tone = reinhard {\n  image = src\n", "t.lgraph:3:17: error: '{' of node 'tone' "
                                                     "is never closed");
    EXPECT(HDR "b = blur { image = src, grid = [1, 2\n",
           "t.lgraph:3:32: error: '[' is never closed\n"
           "t.lgraph:3:10: error: '{' of node 'b' is never closed");
    EXPECT(HDR "b = blur { image = src, grid = [1 2] }\n",
           "t.lgraph:3:35: error: expected ',' or ']' after a list item, found '2'");
    EXPECT(HDR "b = blur { image = src, grid = [, 2] }\n",
           "t.lgraph:3:33: error: expected a list item or ']', found ','");
    /* several errors in one run, in file order, and the good statements in between */
    EXPECT("lightgraph 1\n"
           "a = image { file = 1 2 }\n"
           "b = image {}\n"
           "c = image { file = @ }\n"
           "b = image {}\n",
           "t.lgraph:2:22: error: expected ',' or a new line after the value of 'file', found "
           "'2'\n"
           "t.lgraph:4:20: error: unexpected character '@'\n"
           "t.lgraph:5:1: error: node 'b' is defined twice\n"
           "t.lgraph:3:1: note: 'b' was first defined here");
    /* a NUL byte is never text */
    {
        static const char text[] = "lightgraph 1\nsrc = image {}\0\n";
        lg_diags d = { 0 };
        lg_graph *g = lg_graph_parse_string("t.lgraph", text, sizeof text - 1, NULL, &d);
        CHECK(!g);
        char *h = headers(&d);
        CHECK_STR(h, "t.lgraph:2:15: error: unexpected NUL byte");
        free(h);
        lg_diags_free(&d);
    }
}

static void test_numbers(void)
{
    EXPECT(HDR "b = blur { image = src, radius = 12abc }\n",
           "t.lgraph:3:34: error: invalid number '12abc'");
    EXPECT(HDR "b = blur { image = src, radius = 1.2.3 }\n",
           "t.lgraph:3:34: error: invalid number '1.2.3'");
    EXPECT(HDR "b = blur { image = src, radius = 0x10 }\n",
           "t.lgraph:3:34: error: invalid number '0x10'");
    EXPECT(HDR "b = blur { image = src, radius = 99999999999999999999 }\n",
           "t.lgraph:3:34: error: integer '99999999999999999999' is out of range (integers have "
           "64 bits: -9223372036854775808 to 9223372036854775807)");
    EXPECT(HDR "tone = reinhard { image = src, key = 1e999 }\n",
           "t.lgraph:3:38: error: number '1e999' is too large (the largest float is about "
           "1.8e308)");
    EXPECT(HDR "tone = reinhard { image = src, key = - 1 }\n",
           "t.lgraph:3:38: error: unexpected character '-'");
    /* the accepted forms */
    run r;
    run_text(&r,
             "lightgraph 1\n"
             "src = image {}\n"
             "t = reinhard { image = src, key = .5, white = 2.5e2, exposure = -.25 }\n"
             "u = reinhard { image = src, key = 5., white = 7, exposure = -2E-1 }\n"
             "b = blur { image = src, radius = -0, grid = [512, 1, 007] }\n"
             "c = blur { image = src, radius = 0, offset = [-9223372036854775808, 1] }\n",
             NULL);
    CHECK(r.g && !r.c); /* c's offset is out of range, the rest is fine */
    CHECK(r.d.errors == 1);
    if (r.g) {
        const lg_gnode *t = &r.g->nodes[1];
        CHECK(t->assigns[1].value.kind == LG_GV_FLOAT && t->assigns[1].value.f == 0.5);
        CHECK(t->assigns[2].value.f == 250.0);
        CHECK(t->assigns[3].value.f == -0.25);
        const lg_gnode *u = &r.g->nodes[2];
        CHECK(u->assigns[1].value.kind == LG_GV_FLOAT && u->assigns[1].value.f == 5.0);
        CHECK(u->assigns[2].value.kind == LG_GV_INT && u->assigns[2].value.i == 7);
        CHECK(u->assigns[3].value.f == -0.2);
        const lg_gnode *b = &r.g->nodes[3];
        lg_gitem tmp;
        CHECK(lg_glist_item(&b->assigns[2].value, 2, &tmp, false)->i == 7);
        const lg_gnode *c = &r.g->nodes[4];
        CHECK(lg_glist_item(&c->assigns[2].value, 0, &tmp, false)->i == INT64_MIN);
    }
    char *h = headers(&r.d);
    CHECK_STR(h, "t.lgraph:6:47: error: offset[0] = -9223372036854775808 is out of range [-10, "
                 "10]");
    free(h);
    run_free(&r);
}

static void test_nesting(void)
{
    /* 40 levels: refused at the 33rd, and the parser goes on after the list */
    lg_str b = { 0 };
    lg_str_add(&b, HDR "b = blur { image = src, grid = ");
    for (int i = 0; i < 40; i++)
        lg_str_addc(&b, '[');
    lg_str_addc(&b, '1');
    for (int i = 0; i < 40; i++)
        lg_str_addc(&b, ']');
    lg_str_add(&b, ", radius = @ }\n");
    EXPECT(b.s, "t.lgraph:3:64: error: lists are nested more than 32 deep\n"
                "t.lgraph:3:124: error: unexpected character '@'");
    lg_str_free(&b);

    /* A million brackets: an error, no stack overflow, no quadratic time. */
    lg_str_add(&b, HDR "b = blur { image = src, grid = ");
    for (int i = 0; i < 1000000; i++)
        lg_str_addc(&b, '[');
    lg_str_add(&b, " }\n");
    lg_diags d = { 0 };
    double t0 = lg_mono_now();
    lg_graph *g = lg_graph_parse_string("t.lgraph", b.s, b.len, NULL, &d);
    double t1 = lg_mono_now();
    CHECK(!g && d.errors == 1);
    printf("1e6 nested '[': %.3f s\n", t1 - t0);
    lg_diags_free(&d);
    lg_str_free(&b);
}

static void test_too_many_errors(void)
{
    lg_str b = { 0 };
    lg_str_add(&b, "lightgraph 1\n");
    for (int i = 0; i < 150; i++)
        lg_str_add(&b, "x\n");
    lg_diags d = { 0 };
    lg_graph *g = lg_graph_parse_string("t.lgraph", b.s, b.len, NULL, &d);
    CHECK(!g);
    CHECK(d.errors == 100);
    CHECK(d.n == 101);
    if (d.n == 101)
        CHECK_STR(d.items[100].message, "too many errors (100); stopping here");
    lg_diags_free(&d);
    lg_str_free(&b);
}

static void test_layout_freedom(void)
{
    /* Braces over lines, newline separators, trailing commas, empty braces. */
    run r;
    run_text(&r,
             "lightgraph 1\n"
             "src = image {\n"
             "}\n"
             "tone = reinhard\n"
             "{\n"
             "    image =\n"
             "        src\n"
             "    key = 0.5\n"
             "    , mode = rgb\n"
             "}\n"
             "b = blur { image = tone, grid = [\n"
             "    1\n"
             "    2,\n"
             "    3,\n"
             "], }\n",
             NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        CHECK(r.c->nodes[1].params[0].f == 0.5);
        CHECK(r.c->nodes[1].params[2].e == 0);
        CHECK(r.c->nodes[2].params[3].i3[0] == 1 && r.c->nodes[2].params[3].i3[2] == 3);
    }
    if (r.d.n) {
        char *h = headers(&r.d);
        fprintf(stderr, "unexpected: %s\n", h);
        free(h);
    }
    run_free(&r);
}

/* ---- checking -------------------------------------------------------------------------------- */

static void test_types_and_params(void)
{
    EXPECT(HDR "tone = reinhardd { image = src }\n",
           "t.lgraph:3:8: error: unknown node type 'reinhardd'; did you mean 'reinhard'?");
    EXPECT(HDR "x = frobnicate {}\n",
           "t.lgraph:3:5: error: unknown node type 'frobnicate' (no plugin declares it; "
           "'lightgraph plugins' lists the known types)");
    EXPECT(HDR TONE "kye = 0.2 }\n",
           "t.lgraph:3:32: error: unknown parameter 'kye' for node 'tone' (type reinhard); did "
           "you mean 'key'?");
    EXPECT(HDR "b = blur { image = src, sclae = 2 }\n",
           "t.lgraph:3:25: error: unknown parameter 'sclae' for node 'b' (type blur; parameters: "
           "radius, offset, tint, grid, enabled, label; inputs: image, mask)");
    EXPECT(HDR TONE "foo = 1 }\n",
           "t.lgraph:3:32: error: unknown parameter 'foo' for node 'tone' (type reinhard; "
           "parameters: key, white, mode, backend, exposure; inputs: image)");
    /* suggestions cover the inputs too */
    EXPECT(HDR "tone = reinhard { imag = src }\n",
           "t.lgraph:3:19: error: unknown parameter 'imag' for node 'tone' (type reinhard); did "
           "you mean 'image'?\n"
           "t.lgraph:3:1: error: node 'tone' (reinhard) needs input 'image'");
    /* renamed: a warning, and the value goes to the new name */
    {
        run r;
        run_text(&r, HDR TONE "gain = 2 }\n", NULL);
        char *h = headers(&r.d);
        CHECK_STR(h, "t.lgraph:3:32: warning: parameter 'gain' of reinhard was renamed to "
                     "'exposure'");
        free(h);
        CHECK(r.c && r.c->nodes[1].params[4].f == 2.0 && r.c->nodes[1].param_set[4]);
        run_free(&r);
    }
    EXPECT(HDR TONE "gain = 2, exposure = 3 }\n",
           "t.lgraph:3:32: warning: parameter 'gain' of reinhard was renamed to 'exposure'\n"
           "t.lgraph:3:42: error: 'exposure' of node 'tone' is set twice (as 'gain' and "
           "'exposure')\n"
           "t.lgraph:3:32: note: 'gain' was first set here");
}

static void test_value_types(void)
{
    EXPECT(HDR TONE "key = \"high\" }\n",
           "t.lgraph:3:38: error: expected a float, found a string (parameter 'key' of node "
           "'tone')");
    EXPECT(HDR TONE "key = src }\n", "t.lgraph:3:38: error: expected a float, found a reference "
                                     "'src' (parameter 'key' of node 'tone')");
    EXPECT(HDR TONE "key = inf }\n", "t.lgraph:3:38: error: expected a float, found 'inf' "
                                     "(parameter 'key' of node 'tone'); only finite numbers are "
                                     "allowed");
    EXPECT(HDR TONE "key = nan }\n", "t.lgraph:3:38: error: expected a float, found 'nan' "
                                     "(parameter 'key' of node 'tone'); only finite numbers are "
                                     "allowed");
    EXPECT(HDR TONE "key = [1] }\n", "t.lgraph:3:38: error: expected a float, found a list of 1 "
                                     "item (parameter 'key' of node 'tone')");
    EXPECT(HDR TONE "key = true }\n", "t.lgraph:3:38: error: expected a float, found a boolean "
                                      "(parameter 'key' of node 'tone')");
#define BLUR HDR "b = blur { image = src, " /* the next key starts at column 25 */
    EXPECT(BLUR "radius = 2.0 }\n", "t.lgraph:3:34: error: expected an integer, found a float "
                                    "(parameter 'radius' of node 'b'); write 2 for an integer");
    EXPECT(BLUR "radius = 2.5 }\n", "t.lgraph:3:34: error: expected an integer, found a float "
                                    "(parameter 'radius' of node 'b')");
    EXPECT(BLUR "enabled = 1 }\n", "t.lgraph:3:35: error: expected a boolean (true or false), "
                                   "found an integer (parameter 'enabled' of node 'b')");
    EXPECT(BLUR "label = hello }\n",
           "t.lgraph:3:33: error: expected a string, found a reference 'hello' (parameter "
           "'label' of node 'b'); strings are written in quotes: \"hello\"");
    EXPECT(BLUR "offset = [1, 2, 3] }\n",
           "t.lgraph:3:34: error: expected a list of 2 numbers, found a list of 3 items "
           "(parameter 'offset' of node 'b')");
    EXPECT(BLUR "offset = 1 }\n", "t.lgraph:3:34: error: expected a list of 2 numbers, found an "
                                  "integer (parameter 'offset' of node 'b')");
    EXPECT(BLUR "offset = [\"a\", 1] }\n",
           "t.lgraph:3:35: error: expected a number, found a string (item 0 of parameter "
           "'offset' of node 'b')");
    EXPECT(BLUR "grid = [1, 2.5, 3] }\n",
           "t.lgraph:3:36: error: expected an integer, found a float (item 1 of parameter "
           "'grid' of node 'b')");
    EXPECT(BLUR "tint = [0, 0.5, 2] }\n",
           "t.lgraph:3:41: error: tint[2] = 2 is out of range [0, 1]");
    EXPECT(BLUR "tint = [1, 1] }\n", "t.lgraph:3:32: error: expected a colour (a list of 3 "
                                     "numbers), found a list of 2 items (parameter 'tint' of "
                                     "node 'b')");
    EXPECT(BLUR "grid = [0, 1, 513] }\n",
           "t.lgraph:3:33: error: grid[0] = 0 is out of range [1, 512]\n"
           "t.lgraph:3:39: error: grid[2] = 513 is out of range [1, 512]");
    EXPECT(BLUR "grid = [[1], 1, 1] }\n",
           "t.lgraph:3:33: error: expected an integer, found a list of 1 item (item 0 of "
           "parameter 'grid' of node 'b')");
    /* ranges */
    EXPECT(HDR TONE "key = -1 }\n", "t.lgraph:3:38: error: key = -1 is out of range [0.001, 100]");
    EXPECT(HDR TONE "key = 100.5 }\n",
           "t.lgraph:3:38: error: key = 100.5 is out of range [0.001, 100]");
    EXPECT(BLUR "radius = 65 }\n", "t.lgraph:3:34: error: radius = 65 is out of range [0, 64]");
    /* enums */
    EXPECT(HDR TONE "backend = gll }\n",
           "t.lgraph:3:42: error: 'gll' is not one of cpu, gl, cl (parameter 'backend' of node "
           "'tone'); did you mean 'gl'?");
    EXPECT(HDR TONE "mode = xyz }\n", "t.lgraph:3:39: error: 'xyz' is not one of rgb, luminance "
                                      "(parameter 'mode' of node 'tone')");
    EXPECT(HDR TONE "backend = 3 }\n", "t.lgraph:3:42: error: expected one of cpu, gl, cl, found "
                                       "an integer (parameter 'backend' of node 'tone')");
    EXPECT(HDR TONE "backend = gl.x }\n", "t.lgraph:3:42: error: expected one of cpu, gl, cl, "
                                          "found a reference 'gl.x' (parameter 'backend' of node "
                                          "'tone')");

    /* every type, converted; defaults filled; enum by name or quoted */
    run r;
    run_text(&r,
             HDR TONE "backend = \"cl\", mode = rgb, white = 3 }\n"
                      "b = blur { image = tone, offset = [1, -2.5], tint = [0, 0.5, 1],"
                      " grid = [2, 3, 4], enabled = false, label = \"x\\ty\", radius = 64 }\n",
             NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        const lg_cnode *t = &r.c->nodes[1];
        CHECK(t->params[0].type == LG_PARAM_FLOAT && t->params[0].f == 0.18 && !t->param_set[0]);
        CHECK(t->params[1].f == 3.0 && t->param_set[1]);
        CHECK(t->params[2].e == 0 && strcmp(t->params[2].s, "rgb") == 0);
        CHECK(t->params[3].e == 2 && strcmp(t->params[3].s, "cl") == 0);
        CHECK(t->inputs[0].node == 0 && t->inputs[0].port == 0);
        const lg_cnode *b = &r.c->nodes[2];
        CHECK(b->params[0].i == 64);
        CHECK(b->params[1].v[0] == 1 && b->params[1].v[1] == -2.5);
        CHECK(b->params[2].v[1] == 0.5 && b->params[2].v[2] == 1);
        CHECK(b->params[3].i3[0] == 2 && b->params[3].i3[1] == 3 && b->params[3].i3[2] == 4);
        CHECK(b->params[4].b == false);
        CHECK(strcmp(b->params[5].s, "x\ty") == 0);
        CHECK(b->inputs[1].node == -1); /* optional, unconnected */
    }
    run_free(&r);
    /* defaults of a node with nothing set */
    run_text(&r, HDR TONE "}\nb = blur { image = src }\n", NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        const lg_cnode *t = &r.c->nodes[1];
        CHECK(t->params[2].e == 1 && strcmp(t->params[2].s, "luminance") == 0); /* def.s */
        CHECK(t->params[3].e == 0 && strcmp(t->params[3].s, "cpu") == 0);       /* def.e */
        const lg_cnode *b = &r.c->nodes[2];
        CHECK(b->params[0].i == 4 && b->params[4].b == true);
        CHECK(strcmp(b->params[5].s, "blur") == 0);
        CHECK(b->params[3].i3[1] == 8);
    }
    run_free(&r);
}

static void test_references(void)
{
    EXPECT(HDR "tone = reinhard { image = srcc }\n",
           "t.lgraph:3:27: error: unknown node 'srcc'; did you mean 'src'?");
    EXPECT(HDR "tone = reinhard { image = zebra }\n", "t.lgraph:3:27: error: unknown node 'zebra'");
    EXPECT(HDR "tone = reinhard { image = src.outt }\n",
           "t.lgraph:3:31: error: node 'src' (image) has no output 'outt'; did you mean 'out'? "
           "(outputs: out)");
    EXPECT(HDR "tone = reinhard { image = src.zzz }\n",
           "t.lgraph:3:31: error: node 'src' (image) has no output 'zzz' (outputs: out)");
    EXPECT(HDR "tone = reinhard { image = 1.5 }\n",
           "t.lgraph:3:27: error: expected a reference to a node (NODE or NODE.PORT), found a "
           "float (input 'image' of node 'tone')");
    EXPECT(HDR "tone = reinhard { image = \"src\" }\n",
           "t.lgraph:3:27: error: expected a reference to a node (NODE or NODE.PORT), found a "
           "string (input 'image' of node 'tone')");
    EXPECT(HDR "sc = scene {}\ntone = reinhard { image = sc }\n",
           "t.lgraph:4:27: error: input 'image' of node 'tone' takes an image, but 'sc' gives a "
           "scene");
    EXPECT(HDR "tone = reinhard {}\n", "t.lgraph:3:1: error: node 'tone' (reinhard) needs input "
                                       "'image'");
    EXPECT(HDR "s = sink {}\ntone = reinhard { image = s }\n",
           "t.lgraph:4:27: error: node 's' (sink) has no outputs");
    /* references to a node of an unknown type: only the type is reported */
    EXPECT(HDR "x = mystery {}\ntone = reinhard { image = x.what }\n",
           "t.lgraph:3:5: error: unknown node type 'mystery' (no plugin declares it; 'lightgraph "
           "plugins' lists the known types)");

    /* ports, ANY, forward references, topological order */
    run r;
    run_text(&r,
             "lightgraph 1\n"
             "b = blur { image = g.depth, mask = sc }\n"
             "g = gbuffer { scene = sc }\n"
             "sc = scene { file = \"s.glb\" }\n"
             "k = sink { image = b }\n",
             NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        CHECK(r.c->nodes[0].inputs[0].node == 1 && r.c->nodes[0].inputs[0].port == 1);
        CHECK(r.c->nodes[0].inputs[1].node == 2 && r.c->nodes[0].inputs[1].port == 0);
        CHECK(r.c->topo[0] == 2 && r.c->topo[1] == 1 && r.c->topo[2] == 0 && r.c->topo[3] == 3);
    }
    run_free(&r);
}

static void test_cycles(void)
{
    EXPECT("lightgraph 1\n"
           "a = add { a = c, b = c }\n"
           "b = add { a = a, b = a }\n"
           "c = add { a = b, b = b }\n",
           "t.lgraph:2:1: error: cycle: a -> b -> c -> a");
    EXPECT("lightgraph 1\ns = reinhard { image = s }\n", "t.lgraph:2:1: error: cycle: s -> s");
    /* two cycles, each once, in file order; a node downstream of one is no cycle */
    EXPECT("lightgraph 1\n"
           "src = image {}\n"
           "down = reinhard { image = y }\n"
           "x = add { a = y, b = src }\n"
           "p = reinhard { image = q }\n"
           "y = add { a = src, b = x }\n"
           "q = reinhard { image = p }\n",
           "t.lgraph:4:1: error: cycle: x -> y -> x\n"
           "t.lgraph:5:1: error: cycle: p -> q -> p");
    /* the shortest cycle through the first node is named */
    EXPECT("lightgraph 1\n"
           "a = add { a = d, b = b }\n"
           "b = add { a = a, b = a }\n"
           "c = add { a = b, b = b }\n"
           "d = add { a = c, b = c }\n",
           "t.lgraph:2:1: error: cycle: a -> b -> a");
}

static void test_outputs(void)
{
    EXPECT(HDR "output srcc \"a.png\"\n",
           "t.lgraph:3:8: error: unknown node 'srcc'; did you mean 'src'?");
    EXPECT(HDR "output src.x \"a.png\"\n",
           "t.lgraph:3:12: error: node 'src' (image) has no output 'x' (outputs: out)");
    EXPECT(HDR "output src \"a.jpg\"\n", "t.lgraph:3:12: error: output file 'a.jpg' has an "
                                         "unsupported extension '.jpg' (use .png, .exr or "
                                         ".hdr; .txt for SH coefficients)");
    EXPECT(HDR "output src \"a\"\n", "t.lgraph:3:12: error: output file 'a' has no extension "
                                     "(use .png, .exr or .hdr)");
    EXPECT(HDR "output src \"dir.v2/a\"\n", "t.lgraph:3:12: error: output file 'dir.v2/a' has no "
                                            "extension (use .png, .exr or .hdr)");
    EXPECT(HDR "output src \"\"\n", "t.lgraph:3:12: error: the output file name is empty");
    EXPECT(HDR "sc = scene {}\noutput sc \"a.png\"\n",
           "t.lgraph:4:8: error: 'sc' gives a scene; only images, probes and SH coefficients "
           "can be written to files");
    /* .txt is for SH coefficients only */
    EXPECT(HDR "output src \"a.txt\"\n",
           "t.lgraph:3:12: error: 'src' gives an image, which cannot be written as text "
           "('a.txt'): only SH coefficients are; use .png, .exr or .hdr");
    EXPECT(HDR "output src \"a.png\"\noutput src \"./a.png\"\n",
           "t.lgraph:4:12: error: file './a.png' is written by two output statements\n"
           "t.lgraph:3:12: note: the first one is here");
    EXPECT(HDR "output \"x.png\"\n", "t.lgraph:3:8: error: expected the node to write after "
                                     "'output' (output NODE \"file.png\"), found a string");
    EXPECT(HDR "output src\n", "t.lgraph:3:11: error: expected the file name after 'output src' "
                               "(a string such as \"out.png\"), found the end of the line");
    EXPECT(HDR "output src \"a.png\" x\n", "t.lgraph:3:20: error: expected a new line after the "
                                           "output statement, found 'x'");
    run r;
    run_text(&r,
             HDR "g = gbuffer { scene = sc }\nsc = scene {}\n"
                 "output src \"out/a.PNG\"\noutput g.depth \"/abs/d.exr\"\n"
                 "output g \"../up.hdr\"\n",
             NULL);
    CHECK(r.c && r.c->n_outputs == 3);
    if (r.c) {
        CHECK_STR(r.c->outputs[0].path, "/base/out/a.PNG");
        CHECK(r.c->outputs[0].node == 0 && r.c->outputs[0].port == 0);
        CHECK_STR(r.c->outputs[1].path, "/abs/d.exr");
        CHECK(r.c->outputs[1].node == 1 && r.c->outputs[1].port == 1);
        CHECK_STR(r.c->outputs[2].path, "/up.hdr");
        CHECK(r.c->outputs[2].port == 0);
    }
    run_free(&r);
}

static void test_paths(void)
{
    run r;
    run_text(&r,
             "lightgraph 1\n"
             "a = image { file = \"tex/a.exr\" }\n"
             "b = image { file = \"/abs/b.exr\" }\n"
             "c = image { file = \"../c.exr\" }\n"
             "d = image {}\n",
             NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        CHECK_STR(r.c->nodes[0].params[0].s, "/base/tex/a.exr");
        CHECK_STR(r.c->nodes[1].params[0].s, "/abs/b.exr");
        CHECK_STR(r.c->nodes[2].params[0].s, "/c.exr");
        CHECK_STR(r.c->nodes[3].params[0].s, ""); /* the default, not a path */
        CHECK(!r.c->nodes[3].param_set[0]);
    }
    run_free(&r);
}

/* ---- --set ----------------------------------------------------------------------------------- */

static void test_set(void)
{
    char cwd[PATH_MAX];
    CHECK(getcwd(cwd, sizeof cwd) != NULL);
    run r;
    const char *sets1[] = { "src.file=x.exr",      "tone.backend=cl",
                            " tone.key = 0.5 ",    "tone.image=other",
                            "b.label=hello world", "b.offset=[1, 2]",
                            "tone.mode=\"rgb\"",   NULL };
    run_text(&r,
             HDR "other = image { file = \"o.exr\" }\n" TONE "key = 0.3 }\n"
                 "b = blur { image = src }\n",
             sets1);
    CHECK(r.c != NULL);
    if (r.c) {
        char *want = lg_xasprintf("%s/x.exr", cwd);
        CHECK_STR(r.c->nodes[0].params[0].s, want);
        free(want);
        CHECK_STR(r.c->nodes[1].params[0].s, "/base/o.exr");
        const lg_cnode *t = &r.c->nodes[2];
        CHECK(t->params[3].e == 2);
        CHECK(t->params[0].f == 0.5);
        CHECK(t->params[2].e == 0);
        CHECK(t->inputs[0].node == 1);
        CHECK_STR(r.c->nodes[3].params[5].s, "hello world");
        CHECK(r.c->nodes[3].params[1].v[1] == 2.0);
        /* the override replaced the entry in place; new keys come last */
        CHECK(strcmp(r.g->nodes[2].assigns[1].key, "key") == 0);
        CHECK(r.g->nodes[2].assigns[1].value.kind == LG_GV_RAW);
        CHECK(r.g->nodes[2].n_assigns == 4);
    }
    run_free(&r);

    const char *s_unknown[] = { "tne.key=1", NULL };
    EXPECT_SET(HDR TONE "}\n", s_unknown,
               "<command line>:1:1: error: unknown node 'tne'; did you mean 'tone'?");
    const char *s_unknown2[] = { "zzz.key=1", NULL };
    EXPECT_SET(HDR TONE "}\n", s_unknown2, "<command line>:1:1: error: unknown node 'zzz'");
    const char *s_key[] = { "tone.key=0.5", "tone.kye=1", NULL };
    EXPECT_SET(HDR TONE "}\n", s_key,
               "<command line>:2:6: error: unknown parameter 'kye' for node 'tone' (type "
               "reinhard); did you mean 'key'?");
    const char *s_range[] = { "tone.key=0.5", "tone.key=-3", NULL };
    EXPECT_SET(HDR TONE "}\n", s_range,
               "<command line>:2:10: error: key = -3 is out of range [0.001, 100]");
    const char *s_word[] = { "tone.key=abc", NULL };
    EXPECT_SET(HDR TONE "}\n", s_word,
               "<command line>:1:10: error: expected a float, found a reference 'abc' "
               "(parameter 'key' of node 'tone')");
    const char *s_big[] = { "tone.key=1e999", NULL };
    EXPECT_SET(HDR TONE "}\n", s_big,
               "<command line>:1:10: error: expected a float, found '1e999' (parameter 'key' of "
               "node 'tone': number '1e999' is too large (the largest float is about 1.8e308))");
    const char *s_two[] = { "tone.key=1 2", NULL };
    EXPECT_SET(HDR TONE "}\n", s_two,
               "<command line>:1:10: error: expected a float, found '1 2' (parameter 'key' of "
               "node 'tone': it is more than one value)");
    const char *s_empty[] = { "tone.key=", NULL };
    EXPECT_SET(HDR TONE "}\n", s_empty,
               "<command line>:1:10: error: expected a float, found '' (parameter 'key' of node "
               "'tone': the value is empty)");
    const char *s_enum[] = { "tone.backend=gll", NULL };
    EXPECT_SET(HDR TONE "}\n", s_enum,
               "<command line>:1:14: error: 'gll' is not one of cpu, gl, cl (parameter 'backend' "
               "of node 'tone'); did you mean 'gl'?");
    const char *s_port[] = { "tone.image=src.outt", NULL };
    EXPECT_SET(HDR TONE "}\n", s_port,
               "<command line>:1:16: error: node 'src' (image) has no output 'outt'; did you mean "
               "'out'? (outputs: out)");
    const char *s_lit[] = { "tone.image=3", NULL };
    EXPECT_SET(HDR TONE "}\n", s_lit,
               "<command line>:1:12: error: expected a reference to a node (NODE or NODE.PORT), "
               "found an integer (input 'image' of node 'tone')");
    const char *s_quote[] = { "b.label=\"abc", NULL };
    EXPECT_SET(HDR "b = blur { image = src }\n", s_quote,
               "<command line>:1:9: error: expected a string, found '\"abc' (parameter 'label' of "
               "node 'b': string is not closed before the end of the line)");
    const char *s_syntax1[] = { "tone", NULL };
    EXPECT_SET(HDR TONE "}\n", s_syntax1,
               "<command line>:1:5: error: expected '.' and a parameter name after 'tone' (--set "
               "NODE.PARAM=VALUE)");
    const char *s_syntax2[] = { "tone.key", NULL };
    EXPECT_SET(HDR TONE "}\n", s_syntax2,
               "<command line>:1:9: error: expected '=' after 'tone.key' (--set "
               "NODE.PARAM=VALUE)");
    const char *s_syntax3[] = { "=3", NULL };
    EXPECT_SET(HDR TONE "}\n", s_syntax3,
               "<command line>:1:1: error: expected a node name (--set NODE.PARAM=VALUE)");
    const char *s_syntax4[] = { "tone.=3", NULL };
    EXPECT_SET(HDR TONE "}\n", s_syntax4,
               "<command line>:1:6: error: expected a parameter name after 'tone.' (--set "
               "NODE.PARAM=VALUE)");
    /* a --set on the new name wins over the file's old name (and the old name still warns) */
    const char *s_renamed[] = { "tone.exposure=4", NULL };
    run_text(&r, HDR TONE "gain = 2 }\n", s_renamed);
    CHECK(r.c && r.c->nodes[1].params[4].f == 4.0);
    char *h = headers(&r.d);
    CHECK_STR(h, "t.lgraph:3:32: warning: parameter 'gain' of reinhard was renamed to "
                 "'exposure'");
    free(h);
    run_free(&r);
    /* the printed form points into the assignment */
    run_text(&r, HDR TONE "}\n", s_unknown);
    char *p = printed(&r.d);
    CHECK_STR(p, "<command line>:1:1: error: unknown node 'tne'; did you mean 'tone'?\n"
                 "tne.key=1\n"
                 "^~~\n");
    free(p);
    CHECK(r.set_failed == 1);
    run_free(&r);
}

/* ---- printing diagnostics -------------------------------------------------------------------- */

static void test_print(void)
{
    run r;
    run_text(&r, HDR TONE "kye = 0.2 }\n", NULL);
    char *p = printed(&r.d);
    CHECK_STR(p, "t.lgraph:3:32: error: unknown parameter 'kye' for node 'tone' (type reinhard); "
                 "did you mean 'key'?\n"
                 "tone = reinhard { image = src, kye = 0.2 }\n"
                 "                               ^~~\n");
    free(p);
    run_free(&r);
    /* tabs are copied so the caret lines up; UTF-8 counts one column per character */
    run_text(&r, HDR "\tb = blur { label = \"\xC3\xA9t\xC3\xA9\", image = src, radius = -1 }\n",
             NULL);
    p = printed(&r.d);
    /* '-' is byte 52 and character 50 of the line: a tab and 48 spaces before the caret */
    CHECK_STR(p, "t.lgraph:3:52: error: radius = -1 is out of range [0, 64]\n"
                 "\tb = blur { label = \"\xC3\xA9t\xC3\xA9\", image = src, radius = -1 }\n"
                 "\t                                                ^~\n");
    free(p);
    run_free(&r);
    /* a warning and a note, and a message without a line */
    lg_diags d = { 0 };
    lg_srcloc none = { "x.lgraph", 0, 0, 0 };
    lg_diags_add(&d, LG_DIAG_WARNING, none, NULL, "careful %d", 1);
    lg_srcloc at = { "x.lgraph", 2, 5, 0 };
    lg_diags_add(&d, LG_DIAG_NOTE, at, "abc", "here");
    p = printed(&d);
    CHECK_STR(p, "x.lgraph: warning: careful 1\nx.lgraph:2:5: note: here\nabc\n   ^\n");
    CHECK(d.errors == 0);
    free(p);
    lg_diags_free(&d);
    /* the error at the end of a file */
    run_text(&r, "lightgraph 1\nsrc = image {", NULL);
    p = printed(&r.d);
    CHECK_STR(p, "t.lgraph:2:13: error: '{' of node 'src' is never closed\n"
                 "src = image {\n"
                 "            ^\n");
    free(p);
    run_free(&r);
}

static void test_suggest(void)
{
    const char *params[] = { "key", "white", "mode", "backend", "scale", "image" };
    const char *types[] = { "image", "reinhard", "add", "blur" };
    CHECK_STR(lg_suggest("kye", params, 6), "key");
    CHECK_STR(lg_suggest("sclae", params, 6), "scale");
    CHECK_STR(lg_suggest("KEY", params, 6), "key");
    CHECK_STR(lg_suggest("whte", params, 6), "white");
    CHECK_STR(lg_suggest("backedn", params, 6), "backend");
    CHECK_STR(lg_suggest("reinhardd", types, 4), "reinhard");
    CHECK_STR(lg_suggest("rienhard", types, 4), "reinhard");
    CHECK_STR(lg_suggest("reinhrd", types, 4), "reinhard");
    CHECK(lg_suggest("foo", params, 6) == NULL);
    CHECK(lg_suggest("zebra", types, 4) == NULL);
    CHECK(lg_suggest("key", params, 6) == NULL); /* an exact match is no suggestion */
    CHECK(lg_suggest("", params, 6) == NULL);
    CHECK(lg_suggest("kye", params, 0) == NULL);
    CHECK(lg_suggest("tonemapper", types, 4) == NULL);
}

/* ---- fmt and dot ----------------------------------------------------------------------------- */

static char *slurp(const char *path)
{
    char *s = lg_read_file(path, NULL);
    if (!s)
        fprintf(stderr, "cannot read %s\n", path);
    return s;
}

/* fmt(x) parses, and fmt(fmt(x)) == fmt(x). Returns fmt(x) or NULL. */
static char *fmt_twice(const char *name, const char *text, const char *base_dir)
{
    lg_diags d = { 0 };
    lg_graph *g = lg_graph_parse_string(name, text, strlen(text), base_dir, &d);
    if (!g) {
        fprintf(stderr, "%s does not parse:\n", name);
        lg_diags_print(&d, stderr);
        lg_diags_free(&d);
        failures++;
        return NULL;
    }
    char *f1 = lg_graph_format(g);
    lg_graph_free(g);
    g = lg_graph_parse_string(name, f1, strlen(f1), base_dir, &d);
    CHECK(g != NULL);
    if (!g) {
        fprintf(stderr, "fmt output of %s does not parse:\n%s\n", name, f1);
        lg_diags_print(&d, stderr);
    }
    char *f2 = g ? lg_graph_format(g) : NULL;
    checks++;
    if (!f2 || strcmp(f1, f2) != 0) {
        fprintf(stderr, "fmt is not idempotent on %s:\n--- once:\n%s--- twice:\n%s---\n", name, f1,
                f2 ? f2 : "(none)");
        failures++;
    }
    free(f2);
    lg_graph_free(g);
    lg_diags_free(&d);
    return f1;
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* Every *.lgraph in `dir`: fmt is idempotent. Returns how many files. */
static int fmt_dir(const char *dir)
{
    DIR *dp = opendir(dir);
    if (!dp)
        return 0;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(dp))) {
        if (!ends_with(e->d_name, ".lgraph"))
            continue;
        char *path = lg_path_join(dir, e->d_name);
        char *text = slurp(path);
        lg_diags d = { 0 };
        lg_graph *g = lg_graph_parse_file(path, &d);
        if (g && text) {
            char *dirn = lg_path_dirname(path);
            free(fmt_twice(path, text, dirn));
            free(dirn);
            n++;
        }
        /* files that are meant to fail (cycles, duplicates) have nothing to format */
        lg_graph_free(g);
        lg_diags_free(&d);
        free(text);
        free(path);
    }
    closedir(dp);
    return n;
}

static void test_fmt(const char *examples)
{
    char *in = slurp("fmt_in.lgraph"), *want = slurp("fmt_out.lgraph");
    if (in && want) {
        char *got = fmt_twice("fmt_in.lgraph", in, ".");
        CHECK_STR(got, want);
        free(got);
    }
    free(in);
    free(want);

    /* Comments in every place they can be, and floats that must stay floats. */
    static const char *const texts[] = {
        "lightgraph 1\n",
        "lightgraph 1 # v\n# end\n",
        "lightgraph 1\nsrc = image {}\n\n\n\nb = image {}\n# trailing\n\n# more\n",
        "lightgraph 1\nt = reinhard { # after brace\n  key = 1.0, white = -0.0, exposure = 1e-7 }"
        " # after close\n",
        "lightgraph 1\nt = reinhard {\n  key = [1, [2, [3.25e300]], \"x\"] # c1\n  # c2\n}\n",
        "lightgraph 1\nt = reinhard {\n  key = [1, # inside\n  2]\n  # end 1\n  # end 2\n}\n",
        "lightgraph 1\nt = x {\n  a = 1\n  , b = 2 # after b\n  , c = 3\n}\n",
        "lightgraph 1\nt = x { a = 0.1, b = 0.30000000000000004, c = 123456789012345678.0, "
        "d = 1e-5, e = 5e-324, f = 1.7976931348623157e308 }\n",
        "lightgraph 1\nt = x { s = \"tab\\there \\\"q\\\" back\\\\slash\\nnl\" }\n",
        "lightgraph 1\n# about the include\ninclude \"nope.lgraph\" # eol\n",
        "lightgraph 1\na = x {}\n# before output\noutput a \"a.png\" # eol\n\noutput a.b \"b.exr\"\n",
        "lightgraph 1\nt = x\n# between type and brace\n{ k = v }\n",
        "lightgraph 1\nt = x { k = 1, # on comma\n m = 2 }\n",
        "lightgraph 1\nt = x { k = 1 } # eol\nu = x { # first\n} # second\n",
        /* 101 and 100 columns */
        "lightgraph 1\nt = x { aaaaaaaaaa = 1, bbbbbbbbbbbbbbbbb = 2, cccccccccccccccccccc = 3,"
        " dddddddddddddddddddddd = 4 }\n",
        "lightgraph 1\nt = x { aaaaaaaaaa = 1, bbbbbbbbbbbbbbbbb = 2, cccccccccccccccccccc = 3,"
        " ddddddddddddddddddddd = 4 }\n",
    };
    for (size_t i = 0; i < sizeof texts / sizeof *texts; i++) {
        /* these have includes that do not exist: format only what parses */
        if (strstr(texts[i], "include")) {
            lg_diags d = { 0 };
            lg_graph *g = lg_graph_parse_string("t.lgraph", texts[i], strlen(texts[i]), ".", &d);
            CHECK(!g && d.errors == 1);
            lg_diags_free(&d);
            continue;
        }
        free(fmt_twice("inline", texts[i], "/base"));
    }

    /* exact forms */
    char *f = fmt_twice("t", texts[3], "/base");
    /* two end-of-line comments for one node: the second moves above it */
    CHECK_STR(f, "lightgraph 1\n\n"
                 "# after close\n"
                 "t = reinhard { key = 1.0, white = -0.0, exposure = 1e-07 }  # after brace\n");
    free(f);
    f = fmt_twice("t", texts[7], "/base");
    CHECK_STR(f, "lightgraph 1\n\n"
                 "t = x {\n"
                 "    a = 0.1\n"
                 "    b = 0.30000000000000004\n"
                 "    c = 1.2345678901234568e+17\n"
                 "    d = 1e-05\n"
                 "    e = 5e-324\n"
                 "    f = 1.7976931348623157e+308\n"
                 "}\n");
    free(f);
    f = fmt_twice("t", texts[14], "/base");
    CHECK(f && strstr(f, "t = x {\n    aaaaaaaaaa = 1\n"));
    free(f);
    f = fmt_twice("t", texts[15], "/base");
    CHECK(f && strstr(f, "t = x { aaaaaaaaaa = 1, bbbbbbbbbbbbbbbbb = 2, cccccccccccccccccccc = "
                         "3, ddddddddddddddddddddd = 4 }\n"));
    free(f);
    /* blank lines: between comment blocks and statements, and between entries */
    f = fmt_twice("t",
                  "# licence\n\n\nlightgraph 1\n# file comment\n\n\n# about a\n# more\n"
                  "a = x {}\n# about b\n\nb = x {\n  k = 1 # c\n\n\n  m = 2\n\n  # end\n\n}\n"
                  "# trailing\n\n\n",
                  "/base");
    CHECK_STR(f, "# licence\n\nlightgraph 1\n\n# file comment\n\n# about a\n# more\n"
                 "a = x {}\n# about b\n\nb = x {\n    k = 1  # c\n\n    m = 2\n    # end\n}\n\n"
                 "# trailing\n");
    free(f);
    f = fmt_twice("t", texts[6], "/base");
    CHECK_STR(f, "lightgraph 1\n\nt = x {\n    a = 1\n    b = 2  # after b\n    c = 3\n}\n");
    free(f);

    /* Every data file and every example. */
    int n = fmt_dir(".");
    n += fmt_dir("sub");
    CHECK(n >= 6);
    int ne = examples ? fmt_dir(examples) : 0;
    printf("fmt idempotent on %d data files and %d examples\n", n, ne);

    /* Included nodes are not printed; the include statement is. */
    lg_diags d = { 0 };
    lg_graph *g = lg_graph_parse_file("main.lgraph", &d);
    CHECK(g != NULL);
    if (g) {
        char *m = lg_graph_format(g);
        CHECK_STR(m, "lightgraph 1\n\n"
                     "# the shared source comes from a file one folder down\n"
                     "include \"sub/common.lgraph\"\n\n"
                     "tone = reinhard { image = src, key = 0.2 }\n\n"
                     "output tone \"out/tone.png\"\n");
        free(m);
    }
    lg_graph_free(g);
    lg_diags_free(&d);

    /* CRLF line ends read like LF ones; fmt writes LF */
    f = fmt_twice("t", "# c\r\nlightgraph 1\r\nsrc = image { file = \"a.exr\" } # e \r\n\r\n", ".");
    CHECK_STR(f, "# c\nlightgraph 1\n\nsrc = image { file = \"a.exr\" }  # e\n");
    free(f);
    EXPECT("lightgraph 1\r\nsrc = image { file = \"a.exr }\r\n",
           "t.lgraph:2:22: error: string is not closed before the end of the line\n"
           "t.lgraph:2:13: error: '{' of node 'src' is never closed");

    /* An include in the middle moves to the top, with its comment. */
    f = fmt_twice("t", "lightgraph 1\na = image {}\n# inc\ninclude \"leaf.lgraph\"\nb = image {}\n",
                  ".");
    CHECK_STR(f, "lightgraph 1\n\n# inc\ninclude \"leaf.lgraph\"\n\na = image {}\nb = image {}\n");
    free(f);

    /* A --set value prints as the literal it reads as, or as a string. */
    run r;
    const char *sets[] = { "src.file=a b.exr", "tone.key=0.50", NULL };
    run_text(&r, HDR TONE "}\n", sets);
    if (r.g) {
        char *m = lg_graph_format(r.g);
        CHECK_STR(m, "lightgraph 1\n\nsrc = image { file = \"a b.exr\" }\n"
                     "tone = reinhard { image = src, key = 0.5 }\n");
        free(m);
    }
    run_free(&r);
}

static void test_dot(void)
{
    run r;
    run_text(&r,
             "lightgraph 1\n"
             "sc = scene {}\n"
             "g = gbuffer { scene = sc }\n"
             "tone = reinhard { image = g.depth }\n"
             "both = add { a = tone, b = g }\n"
             "output both \"out \\\"q\\\".png\"\n"
             "output g.depth \"d.exr\"\n",
             NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        char *dot = lg_graph_dot(r.g, r.c);
        CHECK(strncmp(dot, "digraph lightgraph {\n", 21) == 0);
        CHECK(strstr(dot, "  \"tone\" [label=\"tone\\nreinhard\"];\n") != NULL);
        CHECK(strstr(dot, "  \"sc\" -> \"g\" [label=\"scene\"];\n") != NULL);
        CHECK(strstr(dot, "  \"g\" -> \"tone\" [label=\"depth -> image\"];\n") != NULL);
        CHECK(strstr(dot, "  \"tone\" -> \"both\" [label=\"a\"];\n") != NULL);
        CHECK(strstr(dot, "  \"g\" -> \"both\" [label=\"b\"];\n") != NULL);
        CHECK(strstr(dot, "  \"output:0\" [shape=box, label=\"out \\\"q\\\".png\"];\n") != NULL);
        CHECK(strstr(dot, "  \"both\" -> \"output:0\";\n") != NULL);
        CHECK(strstr(dot, "  \"g\" -> \"output:1\" [label=\"depth\"];\n") != NULL);
        CHECK(ends_with(dot, "}\n"));
        /* without a check: from the references */
        char *dot2 = lg_graph_dot(r.g, NULL);
        CHECK(strstr(dot2, "  \"g\" -> \"tone\" [label=\"depth -> image\"];\n") != NULL);
        CHECK(strstr(dot2, "  \"g\" -> \"output:1\" [label=\"depth\"];\n") != NULL);
        free(dot);
        free(dot2);
    }
    run_free(&r);
}

/* ---- includes (run in the data folder) ------------------------------------------------------- */

static void expect_file(const char *file, int line, const char *path, const char *want)
{
    lg_diags d = { 0 };
    lg_graph *g = lg_graph_parse_file(path, &d);
    lg_graph_free(g);
    char *h = headers(&d);
    check_str(file, line, h, want);
    free(h);
    lg_diags_free(&d);
}
#define EXPECT_FILE(path, want) expect_file(__FILE__, __LINE__, (path), (want))

static void test_includes(const char *data)
{
    lg_diags d = { 0 };
    lg_graph *g = lg_graph_parse_file("main.lgraph", &d);
    CHECK(g != NULL);
    lg_checked *c = g ? lg_graph_check(g, lg_fake_schema(), &d) : NULL;
    CHECK(c != NULL);
    if (c) {
        CHECK(g->n_nodes == 3 && g->n_outputs == 2 && g->n_includes == 1);
        CHECK(strcmp(g->nodes[0].name, "leaf") == 0 && g->nodes[0].included);
        CHECK(strcmp(g->nodes[1].name, "src") == 0 && g->nodes[1].included);
        CHECK(strcmp(g->nodes[2].name, "tone") == 0 && !g->nodes[2].included);
        CHECK_STR(g->nodes[1].loc.file, "sub/common.lgraph");
        CHECK_STR(g->nodes[0].loc.file, "sub/../leaf.lgraph");
        char *want = lg_xasprintf("%s/leaf.png", data);
        CHECK_STR(c->nodes[0].params[0].s, want);
        free(want);
        want = lg_xasprintf("%s/sub/textures/a.exr", data);
        CHECK_STR(c->nodes[1].params[0].s, want);
        free(want);
        want = lg_xasprintf("%s/sub/leaf_copy.exr", data);
        CHECK_STR(c->outputs[0].path, want);
        free(want);
        want = lg_xasprintf("%s/out/tone.png", data);
        CHECK_STR(c->outputs[1].path, want);
        free(want);
        CHECK(c->nodes[2].inputs[0].node == 1);
        CHECK(lg_graph_find_node(g, "tone") == 2 && lg_graph_find_node(g, "nope") == -1);
    }
    CHECK(d.n == 0);
    lg_checked_free(c);
    lg_graph_free(g);
    lg_diags_free(&d);

    /* The same file by an absolute path gives the same result. */
    char *abs = lg_xasprintf("%s/main.lgraph", data);
    g = lg_graph_parse_file(abs, &d);
    CHECK(g && g->n_nodes == 3);
    if (g) {
        char *want = lg_xasprintf("%s/sub/common.lgraph", data);
        CHECK_STR(g->nodes[1].loc.file, want);
        free(want);
    }
    lg_graph_free(g);
    lg_diags_free(&d);
    free(abs);

    EXPECT_FILE("cycle_a.lgraph", "cycle_b.lgraph:3:9: error: include cycle: cycle_a.lgraph -> "
                                  "cycle_b.lgraph -> cycle_a.lgraph");
    EXPECT_FILE("dup_a.lgraph", "dup_a.lgraph:3:1: error: node 'src' is defined twice\n"
                                "dup_b.lgraph:3:1: note: 'src' was first defined here");
    EXPECT_FILE("missing.lgraph", "missing.lgraph:2:9: error: cannot read included file "
                                  "'nope/none.lgraph': No such file or directory");
    EXPECT_FILE("nonexistent.lgraph",
                "nonexistent.lgraph: error: cannot read graph file: No such file or directory");
    EXPECT_FILE("sub", "sub: error: cannot read graph file: it is a directory, not a regular "
                       "file");
    /* Bounded reads (issue 8): special files are refused at once, never read or waited on,
     * and a file over the limit is refused before a byte of it is read. */
    EXPECT_FILE("/dev/zero", "/dev/zero: error: cannot read graph file: it is a character "
                             "device, not a regular file");
    {
        char fifo[] = "/tmp/lg-parser-fifo-XXXXXX";
        char big[] = "/tmp/lg-parser-big-XXXXXX";
        int fd = mkstemp(fifo);
        CHECK(fd >= 0);
        if (fd >= 0) {
            close(fd);
            unlink(fifo);
            CHECK(mkfifo(fifo, 0600) == 0); /* no writer: a plain fopen would block */
            char *want = lg_xasprintf("%s: error: cannot read graph file: it is a FIFO, not a "
                                      "regular file",
                                      fifo);
            EXPECT_FILE(fifo, want);
            free(want);
            unlink(fifo);
        }
        fd = mkstemp(big);
        CHECK(fd >= 0);
        if (fd >= 0) {
            /* 500 MB, sparse: refused from its size, without growing the process */
            CHECK(ftruncate(fd, 500000000) == 0);
            close(fd);
            char *want = lg_xasprintf("%s: error: cannot read graph file: it is 476.8 MiB, "
                                      "over the 16.0 MiB limit",
                                      big);
            EXPECT_FILE(big, want);
            free(want);
            unlink(big);
        }
    }

    /* A file included twice (a diamond) is read once. */
    g = lg_graph_parse_file("diamond.lgraph", &d);
    CHECK(g && g->n_nodes == 4);
    c = g ? lg_graph_check(g, lg_fake_schema(), &d) : NULL;
    CHECK(c != NULL);
    if (c) {
        CHECK(strcmp(g->nodes[0].name, "leaf") == 0 && strcmp(g->nodes[3].name, "both") == 0);
        CHECK(c->topo[0] == 0 && c->topo[3] == 3);
    }
    lg_checked_free(c);
    lg_graph_free(g);
    lg_diags_free(&d);

    /* From a string: relative to its base folder. */
    static const char inc[] = "lightgraph 1\ninclude \"leaf.lgraph\"\ninclude \"sub\"\n";
    g = lg_graph_parse_string("s.lgraph", inc, sizeof inc - 1, ".", &d);
    CHECK(!g);
    char *h = headers(&d);
    CHECK_STR(h, "s.lgraph:3:9: error: cannot read included file 'sub': it is a directory, not "
                 "a regular file");
    free(h);
    lg_diags_free(&d);
    static const char inc2[] = "lightgraph 1\ninclude \"\"\n";
    g = lg_graph_parse_string("s.lgraph", inc2, sizeof inc2 - 1, ".", &d);
    h = headers(&d);
    CHECK_STR(h, "s.lgraph:2:9: error: the include file name is empty");
    free(h);
    lg_diags_free(&d);
    /* an error inside an included file names that file */
    static const char inc3[] = "lightgraph 1\ninclude \"fmt_in.lgraph\"\nx = image {}\n"
                               "tone = image {}\n";
    g = lg_graph_parse_string("s.lgraph", inc3, sizeof inc3 - 1, ".", &d);
    h = headers(&d);
    CHECK_STR(h, "s.lgraph:4:1: error: node 'tone' is defined twice\n"
                 "fmt_in.lgraph:6:1: note: 'tone' was first defined here");
    free(h);
    lg_diags_free(&d);
}

/* ---- size ------------------------------------------------------------------------------------ */

static void test_large(void)
{
    /* A chain of 50k nodes, written last-first: parse, check, order, fmt. */
    const int n = 50000;
    lg_str b = { 0 };
    lg_str_add(&b, "lightgraph 1\n");
    for (int i = n - 1; i >= 1; i--)
        lg_str_addf(&b, "n%d = reinhard { image = n%d, key = 0.5 }\n", i, i - 1);
    lg_str_add(&b, "n0 = image { file = \"a.exr\" }\n");
    lg_str_addf(&b, "output n%d \"out.png\"\n", n - 1);
    lg_diags d = { 0 };
    double t0 = lg_mono_now();
    lg_graph *g = lg_graph_parse_string("big.lgraph", b.s, b.len, "/base", &d);
    double t1 = lg_mono_now();
    lg_checked *c = g ? lg_graph_check(g, lg_fake_schema(), &d) : NULL;
    double t2 = lg_mono_now();
    char *f = g ? lg_graph_format(g) : NULL;
    double t3 = lg_mono_now();
    CHECK(g && c && f);
    if (c) {
        bool ordered = true;
        uint32_t *pos = lg_xmalloc(n * sizeof *pos);
        for (int i = 0; i < n; i++)
            pos[c->topo[i]] = (uint32_t)i;
        for (int i = 0; i < n; i++)
            for (uint32_t j = 0; c->nodes[i].type && j < c->nodes[i].type->n_inputs; j++)
                if (c->nodes[i].inputs[j].node >= 0 && pos[c->nodes[i].inputs[j].node] >= pos[i])
                    ordered = false;
        CHECK(ordered);
        CHECK(c->topo[0] == (uint32_t)n - 1); /* n0 is last in the file */
        free(pos);
    }
    printf("%d-node chain (%zu bytes): parse %.3f s, check %.3f s, fmt %.3f s\n", n, b.len, t1 - t0,
           t2 - t1, t3 - t2);
    free(f);
    lg_checked_free(c);
    lg_graph_free(g);
    lg_diags_free(&d);

    /* The same chain closed into a cycle: one error naming all nodes, no recursion. */
    lg_str_free(&b);
    lg_str_add(&b, "lightgraph 1\n");
    for (int i = 0; i < n; i++)
        lg_str_addf(&b, "n%d = reinhard { image = n%d }\n", i, (i + 1) % n);
    g = lg_graph_parse_string("ring.lgraph", b.s, b.len, NULL, &d);
    t0 = lg_mono_now();
    c = g ? lg_graph_check(g, lg_fake_schema(), &d) : NULL;
    t1 = lg_mono_now();
    CHECK(g && !c && d.errors == 1);
    if (d.n == 1) {
        CHECK_STR(d.items[0].message,
                  "cycle: n0 -> n49999 -> n49998 -> n49997 -> n49996 -> "
                  "n49995 -> n49994 -> n49993 -> ... (49986 more) -> n6 -> n5 -> n4 -> n3 -> n2 "
                  "-> n1 -> n0");
    }
    printf("%d-node ring: check %.3f s\n", n, t1 - t0);
    lg_graph_free(g);
    lg_diags_free(&d);
    lg_str_free(&b);

    /* Every reference unknown: 100 errors reported, and no suggestion search beyond them. */
    lg_str_add(&b, "lightgraph 1\n");
    for (int i = 0; i < n; i++)
        lg_str_addf(&b, "n%d = reinhard { image = m%d }\n", i, i);
    g = lg_graph_parse_string("typos.lgraph", b.s, b.len, NULL, &d);
    t0 = lg_mono_now();
    c = g ? lg_graph_check(g, lg_fake_schema(), &d) : NULL;
    t1 = lg_mono_now();
    CHECK(g && !c && d.errors == 100 && d.n == 101);
    if (d.n == 101) {
        CHECK_STR(d.items[0].message, "unknown node 'm0'; did you mean 'n0'?");
        CHECK_STR(d.items[100].message, "too many errors (100); stopping here");
    }
    printf("%d unknown references: check %.3f s\n", n, t1 - t0);
    lg_graph_free(g);
    lg_diags_free(&d);
    lg_str_free(&b);
}

/* ---- limits (docs/graph-format.md "Limits") -------------------------------------------------- */

/* A text of `n` copies of `unit` between `head` and `tail`. */
static char *repeat(const char *head, const char *unit, size_t n, const char *tail, size_t *len)
{
    size_t hu = strlen(head), uu = strlen(unit), tu = strlen(tail);
    char *t = lg_xmalloc(hu + uu * n + tu + 1);
    memcpy(t, head, hu);
    for (size_t i = 0; i < n; i++)
        memcpy(t + hu + i * uu, unit, uu);
    memcpy(t + hu + uu * n, tail, tu + 1);
    *len = hu + uu * n + tu;
    return t;
}

static char *parse_headers(const char *text, size_t len, bool *ok)
{
    lg_diags d = { 0 };
    lg_graph *g = lg_graph_parse_string("t.lgraph", text, len, "/base", &d);
    *ok = g != NULL;
    lg_graph_free(g);
    char *h = headers(&d);
    lg_diags_free(&d);
    return h;
}

/* The source line shown under a message is an excerpt: at most LG_DIAG_EXCERPT_COLS
 * characters around the column, "..." where cut, control bytes as '?'. */
static void test_excerpt(void)
{
    size_t len;
    /* an error at column 10023 of a 20 kB line: 33 characters before it, 66 after */
    char *t = repeat("lightgraph 1\nx = image { file = \"", "x", 10000, "\" @ } # ", &len);
    char *big = lg_xmalloc(len + 10001);
    memcpy(big, t, len);
    memset(big + len, 'y', 10000);
    big[len + 10000] = 0;
    run r;
    run_text(&r, big, NULL);
    char *p = printed(&r.d);
    CHECK_STR(p, "t.lgraph:2:10023: error: unexpected character '@'\n"
                 "...xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx\" @ } # yyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyyy"
                 "yyyyyyyyyyyyyyyyyyyyyyy...\n"
                 "                                    ^\n");
    free(p);
    run_free(&r);
    free(big);
    free(t);
    /* near the end of a long line: the window fills up backwards */
    t = repeat("lightgraph 1\nx = image { file = \"", "x", 300, "\" @ }", &len);
    run_text(&r, t, NULL);
    p = printed(&r.d);
    /* "..." and 95 x, the quote and a space: the caret in column 101 */
    size_t wl;
    char *w1 = repeat("t.lgraph:2:323: error: unexpected character '@'\n...", "x", 95, "\" @ }\n",
                      &wl);
    char *w2 = repeat(w1, " ", 100, "^\n", &wl);
    CHECK_STR(p, w2);
    free(w1);
    free(w2);
    free(p);
    run_free(&r);
    free(t);
    /* an escape sequence in the file does not reach the terminal; the underline stays
     * under the string */
    run_text(&r, "lightgraph 1\nx = image { file = \"\x1b[31mred\" }\n", NULL);
    p = printed(&r.d);
    CHECK_STR(p, "t.lgraph:2:21: error: control character 0x1B in a string\n"
                 "x = image { file = \"?[31mred\" }\n"
                 "                    ^\n");
    free(p);
    run_free(&r);
    /* lg_diags_add with a long line from any caller keeps an excerpt, not the line */
    lg_diags d = { 0 };
    char *line = lg_xmalloc(1000001);
    memset(line, 'a', 1000000);
    line[1000000] = 0;
    lg_srcloc at = { "x.lgraph", 7, 500000, 3 };
    lg_diags_add(&d, LG_DIAG_ERROR, at, line, "here");
    CHECK(d.items[0].line_text && strlen(d.items[0].line_text) <= LG_DIAG_EXCERPT_COLS + 6);
    CHECK(d.items[0].text_col == 37 && d.items[0].text_len == 3);
    free(line);
    lg_diags_free(&d);
}

/* Graph text is UTF-8: strings and comments with bytes that are not are refused with the
 * byte offset; overlong forms, surrogates and code points past U+10FFFF included. */
static void test_utf8(void)
{
    static const struct {
        const char *bytes;
        int len;
    } cases[] = {
        { "a", 1 },
        { "\xC3\xA9", 2 },
        { "\xE2\x82\xAC", 3 },
        { "\xF0\x9F\x98\x80", 4 },
        { "\xF4\x8F\xBF\xBF", 4 }, /* U+10FFFF */
        { "\xC0\x80", 0 },
        { "\xC1\xBF", 0 }, /* overlong 2-byte */
        { "\xE0\x80\xAF", 0 },
        { "\xF0\x80\x80\xAF", 0 }, /* overlong 3- and 4-byte */
        { "\xED\xA0\x80", 0 },
        { "\xED\xBF\xBF", 0 }, /* surrogates */
        { "\xF4\x90\x80\x80", 0 },
        { "\xF5\x80\x80\x80", 0 }, /* past U+10FFFF */
        { "\x80", 0 },
        { "\xE2\x82", 0 },
        { "\xFF", 0 }, /* stray, truncated, never UTF-8 */
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++)
        CHECK(lg_utf8_char_len((const unsigned char *)cases[i].bytes, strlen(cases[i].bytes)) ==
              cases[i].len);

    EXPECT("lightgraph 1\nx = image { file = \"caf\xC3\xA9 \xF0\x9F\x98\x80\" }\n", "");
    EXPECT("lightgraph 1\nx = image { file = \"a\xC0\x80\" }\n",
           "t.lgraph:2:22: error: invalid UTF-8 in a string: byte 0xC0 at byte offset 34 "
           "(strings are UTF-8 text)");
    EXPECT("lightgraph 1\nx = image { file = \"\xED\xA0\x80\" }\n",
           "t.lgraph:2:21: error: invalid UTF-8 in a string: byte 0xED at byte offset 33 "
           "(strings are UTF-8 text)");
    EXPECT("lightgraph 1\nx = image { file = \"\xF4\x90\x80\x80\" }\n",
           "t.lgraph:2:21: error: invalid UTF-8 in a string: byte 0xF4 at byte offset 33 "
           "(strings are UTF-8 text)");
    EXPECT("lightgraph 1\nx = image { file = \"ab\xE2\x82\" }\n",
           "t.lgraph:2:23: error: invalid UTF-8 in a string: byte 0xE2 at byte offset 35 "
           "(strings are UTF-8 text)");
    /* comments too: fmt writes them back */
    EXPECT("lightgraph 1\n# caf\xC3\xA9 ok\n# bad \xFF here\nx = image {}\n",
           "t.lgraph:3:7: error: invalid UTF-8 in a comment: byte 0xFF at byte offset 30 (a "
           "graph file is UTF-8 text)");
    EXPECT("lightgraph 1\nx = image {} # \xED\xB0\x80\n",
           "t.lgraph:2:16: error: invalid UTF-8 in a comment: byte 0xED at byte offset 28 (a "
           "graph file is UTF-8 text)");
    /* --set values are graph text too */
    static const char *const sets[] = { "x.file=\"\xC3\x28\"", NULL };
    EXPECT_SET("lightgraph 1\nx = image {}\n", sets,
               "<command line>:1:9: error: invalid UTF-8: byte 0xC3 at byte offset 8 (--set "
               "NODE.PARAM=VALUE)");
    /* unquoted, where the text would be taken as it is */
    static const char *const sets2[] = { "x.file=caf\xE9.exr", NULL };
    EXPECT_SET("lightgraph 1\nx = image {}\n", sets2,
               "<command line>:1:11: error: invalid UTF-8: byte 0xE9 at byte offset 10 (--set "
               "NODE.PARAM=VALUE)");
    static const char *const sets3[] = { "x.file=caf\xC3\xA9.exr", NULL };
    EXPECT_SET("lightgraph 1\nx = image {}\n", sets3, "");
}

/* Lists of plain numbers are kept compact (lg_gnums): their items still read, print, check
 * and report at their places as before. */
static void test_compact_lists(void)
{
    /* runs across lines and a comment: one compact list */
    const char *text = BLUR "tint = [0.5, 2, # two\n  -3e0\n], offset = [ 11 , -0.25 ] }\n";
    run r;
    run_text(&r, text, NULL);
    CHECK(r.g != NULL);
    if (r.g) {
        const lg_gvalue *v = &r.g->nodes[1].assigns[1].value;
        CHECK(v->kind == LG_GV_LIST && v->n_items == 3 && v->nums && !v->items);
        lg_gitem tmp;
        const lg_gvalue *it = lg_glist_item(v, 2, &tmp, true);
        CHECK(it->kind == LG_GV_FLOAT && it->f == -3.0 && strcmp(it->text, "-3e0") == 0);
        CHECK(it->loc.line == 4 && it->loc.col == 3 && it->loc.len == 4);
        it = lg_glist_item(v, 1, &tmp, true);
        CHECK(it->kind == LG_GV_INT && it->i == 2 && it->loc.line == 3 && it->loc.col == 38);
        char *f = lg_graph_format(r.g);
        CHECK_STR(f, "lightgraph 1\n\nsrc = image {}\nb = blur {\n    image = src\n    # two\n"
                     "    tint = [0.5, 2, -3.0]\n    offset = [11, -0.25]\n}\n");
        free(f);
    }
    char *h = headers(&r.d);
    CHECK_STR(h, "t.lgraph:5:15: error: offset[0] = 11 is out of range [-10, 10]\n"
                 "t.lgraph:3:38: error: tint[1] = 2 is out of range [0, 1]\n"
                 "t.lgraph:4:3: error: tint[2] = -3e0 is out of range [0, 1]");
    free(h);
    run_free(&r);
    /* a list that is not all numbers keeps an lg_gvalue per item, runs included */
    EXPECT(BLUR "tint = [1, 2, x] }\n",
           "t.lgraph:3:36: error: tint[1] = 2 is out of range [0, 1]\n"
           "t.lgraph:3:39: error: expected a number, found a reference 'x' (item 2 of parameter "
           "'tint' of node 'b')");
    EXPECT(BLUR "offset = [1, 20] }\n",
           "t.lgraph:3:38: error: offset[1] = 20 is out of range [-10, 10]");
    /* a run stops before what it cannot hold; the parser's messages are the same */
    EXPECT(BLUR "tint = [1, 2,, 3] }\n",
           "t.lgraph:3:38: error: expected a list item or ']', found ','");
    EXPECT(BLUR "tint = [1, 2 3] }\n",
           "t.lgraph:3:38: error: expected ',' or ']' after a list item, found '3'");
    EXPECT(BLUR "tint = [1, 2, 3x] }\n", "t.lgraph:3:39: error: invalid number '3x'");
    /* a list where no value goes: its lines are statements, as before */
    EXPECT("lightgraph 1\n[1,\n2]\n",
           "t.lgraph:2:1: error: expected a statement (NAME = TYPE { ... }, output or include), "
           "found '['\n"
           "t.lgraph:3:1: error: expected a statement (NAME = TYPE { ... }, output or include), "
           "found '2'");
    /* a --set list: compact too, its items placed on the command line */
    static const char *const sets[] = { "b.tint=[0, 0.5,\n 7]", NULL };
    EXPECT_SET(BLUR "radius = 1 }\n", sets,
               "<command line>:2:2: error: tint[2] = 7 is out of range [0, 1]");
}

/* A list at the cap (65536 numbers, about 500 kB) costs a few bytes an item: parsed in a
 * child, whose peak RSS grows less than 4 MB over what it was before the parse (before:
 * about 340 bytes an item, 22 MB). Run first, while this process's heap is small: the
 * child could otherwise reuse freed pages it inherited and hide its growth. */
static void test_list_memory(void)
{
    size_t len;
    char *t = repeat("lightgraph 1\nx = blur { tint = [", "123456, 0.1234, ", 32767,
                     "123456, 0.1234] }\n", &len);
    int fd[2];
    if (pipe(fd) != 0) {
        CHECK(!"pipe");
        free(t);
        return;
    }
#if defined(__GLIBC__)
    malloc_trim(0);
#endif
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        struct rusage ru0, ru1;
        getrusage(RUSAGE_SELF, &ru0);
        struct timespec a, b;
        clock_gettime(CLOCK_MONOTONIC, &a);
        lg_diags d = { 0 };
        lg_graph *g = lg_graph_parse_string("t.lgraph", t, len, "/base", &d);
        clock_gettime(CLOCK_MONOTONIC, &b);
        getrusage(RUSAGE_SELF, &ru1);
        long r[3] = { ru1.ru_maxrss - ru0.ru_maxrss,
                      g ? (long)g->nodes[0].assigns[0].value.n_items : -1,
                      (long)((b.tv_sec - a.tv_sec) * 1000000 + (b.tv_nsec - a.tv_nsec) / 1000) };
        ssize_t w = write(fd[1], r, sizeof r);
        _exit(w == (ssize_t)sizeof r ? 0 : 1);
    }
    close(fd[1]);
    long r[3] = { -1, -1, -1 };
    ssize_t got = pid > 0 ? read(fd[0], r, sizeof r) : -1;
    close(fd[0]);
    int status = 0;
    if (pid > 0)
        waitpid(pid, &status, 0);
    CHECK(got == (ssize_t)sizeof r && WIFEXITED(status) && WEXITSTATUS(status) == 0);
    CHECK(r[1] == 65536);
    CHECK(r[0] >= 0 && r[0] < 4096);
    printf("65536-item list (%zu bytes): parsed in %.1f ms, peak RSS +%ld KiB (%.1f bytes an "
           "item)\n",
           len, r[2] / 1000.0, r[0], r[0] * 1024.0 / 65536);
    free(t);
}

static void test_limits(void)
{
    size_t len;
    bool ok;
    /* lists: 65536 items parse; one more is refused where it starts, and the rest of the
     * list is skipped (no token made for it) */
    char *t = repeat("lightgraph 1\nx = blur { tint = [", "1,", 65535, "1] }\n", &len);
    char *h = parse_headers(t, len, &ok);
    CHECK(ok);
    CHECK_STR(h, "");
    free(h);
    free(t);
    t = repeat("lightgraph 1\nx = blur { tint = [", "1,", 100000, "1], radius = x }\ny = z\n",
               &len);
    h = parse_headers(t, len, &ok);
    CHECK(!ok);
    CHECK_STR(h, "t.lgraph:2:131092: error: this list has more than 65536 items; that is the "
                 "limit\n"
                 "t.lgraph:3:6: error: expected '{' after the node type 'z', found the end of the "
                 "line");
    free(h);
    free(t);
    /* items separated by new lines count as well (fmt would write them with commas) */
    t = repeat("lightgraph 1\nx = blur { tint = [", "1\n", 65536, "1] }\n", &len);
    h = parse_headers(t, len, &ok);
    CHECK_STR(h, "t.lgraph:65538:1: error: this list has more than 65536 items; that is the "
                 "limit");
    free(h);
    free(t);
    /* the skipped tail may span lines, hold nested lists, strings with ']' and comments */
    t = repeat("lightgraph 1\nx = blur { tint = [", "1,", 65536,
               "[2, [3]], \"]\" # ]\n 4, 5\n], radius = 1 }\nlightgraph 1\n", &len);
    h = parse_headers(t, len, &ok);
    CHECK_STR(h, "t.lgraph:2:131092: error: this list has more than 65536 items; that is the "
                 "limit\n"
                 "t.lgraph:5:1: error: the version line must come first, and only once");
    free(h);
    free(t);
    /* tokens: 2^20 in all (here 26 a line: the 21st of line 40331 is one too many); the
     * rest of the file is not lexed */
    lg_str b = { 0 };
    lg_str_add(&b, "lightgraph 1\n");
    for (int i = 0; i < 50000; i++)
        lg_str_addf(&b, "n%05d = blur { radius = 1, offset = [1, 2], grid = [1, 2, 3] }\n", i);
    h = parse_headers(b.s, b.len, &ok);
    CHECK(!ok);
    CHECK_STR(h, "t.lgraph:40331:55: error: the graph has more than 1048576 tokens (names, "
                 "numbers, strings and punctuation, its includes counted); that is the limit\n"
                 "t.lgraph:40331:15: error: '{' of node 'n40329' is never closed");
    free(h);
    lg_str_free(&b);
    /* names: 256 characters, NODE.PORT counted whole */
    char name[300];
    memset(name, 'k', sizeof name);
    name[256] = 0;
    lg_str nb = { 0 };
    lg_str_addf(&nb, "lightgraph 1\nx = image { %s = 1 }\n", name);
    h = parse_headers(nb.s, nb.len, &ok);
    CHECK(ok);
    CHECK_STR(h, "");
    free(h);
    lg_str_free(&nb);
    name[256] = 'k';
    name[257] = 0;
    lg_str_addf(&nb, "lightgraph 1\nx = image { %s = 1, y = a.%s }\n", name, name + 2);
    h = parse_headers(nb.s, nb.len, &ok);
    CHECK(!ok);
    CHECK_STR(h, "t.lgraph:2:13: error: this name is 257 characters long; names have at most "
                 "256\n"
                 "t.lgraph:2:280: error: this name is 257 characters long; names have at most "
                 "256");
    free(h);
    lg_str_free(&nb);
    /* a message that quotes something long is cut at LG_DIAG_MAX_MESSAGE bytes */
    lg_str_add(&nb, "lightgraph 1\ninclude \"");
    for (int i = 0; i < 3000; i++)
        lg_str_add(&nb, "\xC3\xA9");
    lg_str_add(&nb, "\"\n");
    lg_diags dd = { 0 };
    lg_graph *gg = lg_graph_parse_string("t.lgraph", nb.s, nb.len, "/nonexistent", &dd);
    CHECK(!gg && dd.n == 1);
    if (dd.n == 1) {
        const char *m = dd.items[0].message;
        size_t ml = strlen(m);
        CHECK(ml <= LG_DIAG_MAX_MESSAGE && ml >= LG_DIAG_MAX_MESSAGE - 4);
        CHECK(strncmp(m, "cannot read included file '/nonexistent/\xC3\xA9", 42) == 0);
        CHECK(strcmp(m + ml - 5, "\xC3\xA9...") == 0); /* cut between characters */
    }
    lg_diags_free(&dd);
    lg_str_free(&nb);
    /* nodes: 100000 */
    lg_str_add(&b, "lightgraph 1\n");
    for (int i = 0; i <= 100000; i++)
        lg_str_addf(&b, "n%d = image {}\n", i);
    h = parse_headers(b.s, b.len, &ok);
    CHECK(!ok);
    CHECK_STR(h, "t.lgraph:100002:1: error: the graph has more than 100000 nodes (its includes "
                 "counted); that is the limit");
    free(h);
    lg_str_free(&b);
}

/* Includes: depth, the bytes of a graph in all, files that are not graphs, and the path
 * rule (relative to the including file; absolute paths and '..' allowed). */
static void test_include_limits(void)
{
    char dir[] = "/tmp/lg-parser-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp");
        return;
    }
    char path[PATH_MAX];
    /* a chain of 34 files: the 33rd include is one too deep */
    for (int i = 0; i < 34; i++) {
        snprintf(path, sizeof path, "%s/c%d.lgraph", dir, i);
        FILE *f = fopen(path, "w");
        fprintf(f, "lightgraph 1\nn%d = image {}\n", i);
        if (i < 33)
            fprintf(f, "include \"c%d.lgraph\"\n", i + 1);
        fclose(f);
    }
    lg_diags d = { 0 };
    snprintf(path, sizeof path, "%s/c0.lgraph", dir);
    lg_graph *g = lg_graph_parse_file(path, &d);
    CHECK(!g && d.errors == 1);
    char want[PATH_MAX + 200];
    snprintf(want, sizeof want,
             "%s/c31.lgraph:3:9: error: includes are nested more than 32 "
             "deep",
             dir);
    char *h = headers(&d);
    CHECK_STR(h, want);
    free(h);
    lg_diags_free(&d);
    /* 32 files deep (the top one and 31 nested includes) is fine */
    snprintf(path, sizeof path, "%s/c2.lgraph", dir);
    g = lg_graph_parse_file(path, &d);
    CHECK(g && g->n_nodes == 32 && d.n == 0);
    lg_graph_free(g);
    lg_diags_free(&d);

    /* 16 MiB for a graph with its includes: a sparse file of 16 MiB less 10 bytes passes
     * the per-file check but not the total (refused before a byte of it is read) */
    snprintf(path, sizeof path, "%s/huge.lgraph", dir);
    FILE *f = fopen(path, "w");
    CHECK(f && ftruncate(fileno(f), (16 << 20) - 10) == 0);
    fclose(f);
    static const char top[] = "lightgraph 1\ninclude \"huge.lgraph\"\n";
    g = lg_graph_parse_string("t.lgraph", top, sizeof top - 1, dir, &d);
    CHECK(!g);
    snprintf(want, sizeof want,
             "t.lgraph:2:9: error: cannot include '%s/huge.lgraph' (16777206 "
             "bytes): a graph file and its includes have at most 16 MiB in all",
             dir);
    h = headers(&d);
    CHECK_STR(h, want);
    free(h);
    lg_diags_free(&d);

    /* not a graph file: one message, none of its lines */
    snprintf(path, sizeof path, "%s/notes.txt", dir);
    f = fopen(path, "w");
    fprintf(f, "Name:\tx\nState:\tR (running)\n= { [ \"\n");
    fclose(f);
    snprintf(path, sizeof path, "%s/empty.lgraph", dir);
    f = fopen(path, "w");
    fprintf(f, "# only a comment\n\n");
    fclose(f);
    snprintf(path, sizeof path, "%s/named.lgraph", dir);
    f = fopen(path, "w");
    fprintf(f, "lightgraph = image {}\n");
    fclose(f);
    static const char inc[] = "lightgraph 1\ninclude \"notes.txt\"\ninclude \"empty.lgraph\"\n"
                              "include \"named.lgraph\"\n";
    g = lg_graph_parse_string("t.lgraph", inc, sizeof inc - 1, dir, &d);
    CHECK(!g && d.errors == 3);
    h = headers(&d);
    snprintf(want, sizeof want,
             "t.lgraph:2:9: error: included file '%s/notes.txt' is not a graph file: it does not "
             "start with the version line 'lightgraph 1'\n"
             "t.lgraph:3:9: error: included file '%s/empty.lgraph' is not a graph file: it does "
             "not start with the version line 'lightgraph 1'\n"
             "t.lgraph:4:9: error: included file '%s/named.lgraph' is not a graph file: it does "
             "not start with the version line 'lightgraph 1'",
             dir, dir, dir);
    CHECK_STR(h, want);
    free(h);
    lg_diags_free(&d);
    /* a special file goes through the bounded reader too: one message, no hang */
    static const char proc[] = "lightgraph 1\ninclude \"/proc/self/status\"\n"
                               "include \"/dev/zero\"\n";
    g = lg_graph_parse_string("t.lgraph", proc, sizeof proc - 1, dir, &d);
    CHECK(!g && d.errors == 2);
    h = headers(&d);
    CHECK(strstr(h, "t.lgraph:2:9: error: cannot read included file '/proc/self/status'") ||
          strstr(h, "t.lgraph:2:9: error: included file '/proc/self/status' is not a graph"));
    CHECK(strstr(h, "t.lgraph:3:9: error: cannot read included file '/dev/zero': it is a "
                    "character device, not a regular file") != NULL);
    CHECK(!strstr(h, "Pid") && !strstr(h, "VmRSS"));
    free(h);
    lg_diags_free(&d);

    /* paths: relative to the including file, '..' and absolute paths allowed */
    snprintf(path, sizeof path, "%s/sub", dir);
    CHECK(mkdir(path, 0700) == 0);
    snprintf(path, sizeof path, "%s/sub/up.lgraph", dir);
    f = fopen(path, "w");
    fprintf(f, "lightgraph 1\ninclude \"../c33.lgraph\"\n");
    fclose(f);
    char abs_inc[PATH_MAX + 64];
    int n = snprintf(abs_inc, sizeof abs_inc,
                     "lightgraph 1\ninclude \"sub/up.lgraph\"\n"
                     "include \"%s/c32.lgraph\"\n",
                     dir);
    g = lg_graph_parse_string("t.lgraph", abs_inc, (size_t)n, dir, &d);
    CHECK(g && g->n_nodes == 2 && d.n == 0);
    if (g && g->n_nodes == 2)
        CHECK(strcmp(g->nodes[0].name, "n33") == 0 && strcmp(g->nodes[1].name, "n32") == 0);
    lg_graph_free(g);
    lg_diags_free(&d);

    char cmd[PATH_MAX + 16];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK(system(cmd) == 0);
}

/* check refuses what the parameters alone make impossible: an image size (parameters with
 * the LG_ROLE_IMAGE_WIDTH / _HEIGHT role) over the schema's pixel limit. */
static void test_image_size(void)
{
    EXPECT("lightgraph 1\ns = solid { w = 65536, h = 65536 }\n",
           "t.lgraph:2:28: error: node 's' (solid) makes a 65536x65536 image (w x h): "
           "4294967296 pixels, over the limit of 134217728 (LIGHTGRAPH_MAX_PIXELS raises it)");
    EXPECT("lightgraph 1\ns = solid { h = 1048576, w = 1048576 }\n",
           "t.lgraph:2:30: error: node 's' (solid) makes a 1048576x1048576 image (w x h): "
           "1099511627776 pixels, over the limit of 134217728 (LIGHTGRAPH_MAX_PIXELS raises "
           "it)");
    EXPECT("lightgraph 1\ns = solid { w = 4096, h = 4096 }\n", "");
    EXPECT("lightgraph 1\ns = solid { w = 16384, h = 8192 }\n", ""); /* 2^27 exactly */
    EXPECT("lightgraph 1\ns = solid { w = 16385, h = 8192 }\n",
           "t.lgraph:2:28: error: node 's' (solid) makes a 16385x8192 image (w x h): "
           "134225920 pixels, over the limit of 134217728 (LIGHTGRAPH_MAX_PIXELS raises it)");
    /* 0 is the render size, which check does not know */
    EXPECT("lightgraph 1\ns = solid { w = 0, h = 1048576 }\n", "");
    /* a --set value is judged as well, at its place on the command line */
    static const char *const sets[] = { "s.w=100000", NULL };
    EXPECT_SET("lightgraph 1\ns = solid { w = 10, h = 100000 }\n", sets,
               "<command line>:1:5: error: node 's' (solid) makes a 100000x100000 image (w x h): "
               "10000000000 pixels, over the limit of 134217728 (LIGHTGRAPH_MAX_PIXELS raises "
               "it)");
}

/* A colour that also takes keywords (ABI 2.3): a word sets e to its index (v zero), a
 * colour sets e = -1; the default is a keyword (def.e >= 0) or a colour (def.e = -1);
 * errors name both forms; --set takes either. */
static void test_keyword_colour(void)
{
#define BAKE "lightgraph 1\nk = bake { " /* the next key starts at column 12 */
    run r;
    run_text(&r, BAKE "albedo = material, tint = [0.5, 0, 1] }\n", NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        const lg_value *a = &r.c->nodes[0].params[0], *t = &r.c->nodes[0].params[1];
        CHECK(a->type == LG_PARAM_COLOR && a->e == 0 && a->v[0] == 0 && a->v[2] == 0);
        CHECK(t->e == -1 && t->v[0] == 0.5 && t->v[1] == 0 && t->v[2] == 1);
    }
    run_free(&r);
    /* defaults: albedo the keyword 'vertex', tint the colour */
    run_text(&r, BAKE "}\n", NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        const lg_value *a = &r.c->nodes[0].params[0], *t = &r.c->nodes[0].params[1];
        CHECK(a->e == 1 && a->v[0] == 0 && a->v[1] == 0 && a->v[2] == 0);
        CHECK(t->e == -1 && t->v[0] == 0.25 && t->v[1] == 0.5 && t->v[2] == 1);
    }
    run_free(&r);
    /* quoted like an enum; and a colour replacing a keyword default */
    run_text(&r, BAKE "albedo = [1, 1, 1], tint = \"vertex\" }\n", NULL);
    CHECK(r.c != NULL);
    if (r.c) {
        CHECK(r.c->nodes[0].params[0].e == -1 && r.c->nodes[0].params[0].v[1] == 1);
        CHECK(r.c->nodes[0].params[1].e == 1);
    }
    run_free(&r);
    /* --set either way */
    static const char *const s_word[] = { "k.tint=material", "k.albedo=[0.5,0.5,0.5]", NULL };
    run_text(&r, BAKE "}\n", s_word);
    CHECK(r.c != NULL);
    if (r.c) {
        CHECK(r.c->nodes[0].params[1].e == 0);
        CHECK(r.c->nodes[0].params[0].e == -1 && r.c->nodes[0].params[0].v[2] == 0.5);
    }
    run_free(&r);
    /* errors */
    EXPECT(BAKE "albedo = materal }\n",
           "t.lgraph:2:21: error: 'materal' is not a colour [r, g, b] or one of: material, "
           "vertex (parameter 'albedo' of node 'k'); did you mean 'material'?");
    EXPECT(BAKE "albedo = 0.5 }\n",
           "t.lgraph:2:21: error: expected a colour [r, g, b] or one of: material, vertex, "
           "found a float (parameter 'albedo' of node 'k')");
    EXPECT(BAKE "albedo = [1, 1] }\n",
           "t.lgraph:2:21: error: expected a colour [r, g, b] or one of: material, vertex, "
           "found a list of 2 items (parameter 'albedo' of node 'k')");
    EXPECT(BAKE "albedo = [1, 1, 2] }\n",
           "t.lgraph:2:28: error: albedo[2] = 2 is out of range [0, 1]");
    EXPECT(BAKE "albedo = material.x }\n",
           "t.lgraph:2:21: error: expected a colour [r, g, b] or one of: material, vertex, "
           "found a reference 'material.x' (parameter 'albedo' of node 'k')");
    static const char *const s_bad[] = { "k.albedo=[0.5,nan,0.5]", NULL };
    EXPECT_SET(BAKE "}\n", s_bad,
               "<command line>:1:15: error: expected a number, found 'nan' (item 1 of "
               "parameter 'albedo' of node 'k'); only finite numbers are allowed");
    static const char *const s_miss[] = { "k.albedo=plastic", NULL };
    EXPECT_SET(BAKE "}\n", s_miss,
               "<command line>:1:10: error: 'plastic' is not a colour [r, g, b] or one of: "
               "material, vertex (parameter 'albedo' of node 'k')");
    /* a colour without keywords is unchanged: e stays 0, a word is an error */
    EXPECT(BLUR "tint = material }\n",
           "t.lgraph:3:32: error: expected a colour (a list of 3 numbers), found a reference "
           "'material' (parameter 'tint' of node 'b')");
#undef BAKE
}

/* The checker names kinds in its messages with lg_kind_phrase (lightgraph/kinds.h), the
 * words the SDK keeps beside its table of kinds: each kind of the table has its own, worded
 * as the messages always were, and a value outside the enum has one too. */
static void test_kind_phrases(void)
{
    static const char *const want[LG_KIND_COUNT_] = {
        [LG_KIND_ANY] = "any resource",
        [LG_KIND_IMAGE] = "an image",
        [LG_KIND_BUFFER] = "a buffer",
        [LG_KIND_VOLUME] = "a volume",
        [LG_KIND_SCENE] = "a scene",
        [LG_KIND_SHADOWMAP] = "a shadow map",
        [LG_KIND_PROBE] = "a light probe",
        [LG_KIND_SH] = "SH coefficients",
        [LG_KIND_TRANSFER] = "transfer vectors",
        [LG_KIND_FROXEL] = "a froxel volume",
    };
    for (int k = 0; k < LG_KIND_COUNT_; k++) {
        CHECK(lg_kind_describe((lg_resource_kind)k) != NULL);
        CHECK(want[k] != NULL); /* a kind added to the enum gets its words here too */
        if (want[k])
            CHECK_STR(lg_kind_phrase((lg_resource_kind)k), want[k]);
        for (int j = 0; j < k; j++)
            CHECK(strcmp(lg_kind_phrase((lg_resource_kind)j),
                         lg_kind_phrase((lg_resource_kind)k)) != 0);
    }
    CHECK(lg_kind_describe(LG_KIND_COUNT_) == NULL);
    CHECK_STR(lg_kind_phrase(LG_KIND_COUNT_), "an unknown kind of resource");
    CHECK_STR(lg_kind_phrase((lg_resource_kind)-1), "an unknown kind of resource");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s DATA_DIR [EXAMPLES_DIR]\n", argv[0]);
        return 2;
    }
    const char *data = argv[1];
    char *examples = argc > 2 ? lg_path_absolute(argv[2]) : NULL;
    if (chdir(data) != 0) {
        perror(data);
        return 2;
    }
    char *data_abs = lg_path_absolute(".");

    test_list_memory(); /* first: see there */
    test_version();
    test_syntax_errors();
    test_numbers();
    test_nesting();
    test_too_many_errors();
    test_layout_freedom();
    test_types_and_params();
    test_value_types();
    test_references();
    test_cycles();
    test_outputs();
    test_paths();
    test_set();
    test_print();
    test_suggest();
    test_fmt(examples);
    test_dot();
    test_includes(data_abs);
    test_large();
    test_excerpt();
    test_utf8();
    test_limits();
    test_compact_lists();
    test_include_limits();
    test_image_size();
    test_keyword_colour();
    test_kind_phrases();

    free(examples);
    free(data_abs);
    printf("%d checks, %d failed\n", checks, failures);
    return failures ? 1 : 0;
}
