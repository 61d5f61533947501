/*
 * host/graph/lexer.c: a graph file's text -> tokens (docs/graph-format.md is the spec).
 *
 * A file is read whole and split into tokens first. Comments are not tokens: each one is
 * attached to the token it stands above, or to the token whose line it ends, so that fmt
 * can put it back. Lexical errors travel inside T_ERR tokens and are reported when the
 * parser steps over them, so that messages come out in file order.
 *
 * Lists of numbers are kept compact (lg_gnums in graph.h): the lexer makes one T_NUMS token
 * of the numbers that follow each other on a line in a list, and a list of numbers only
 * keeps a value and a tag for each item, no lg_gvalue (lg_glist_item makes one on demand).
 *
 * Numbers are read with strtoll/strtod: the host never calls setlocale(), so the decimal
 * separator is always '.'.
 */
#include "graph/parse_priv.h"

#include <errno.h>
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"

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

static void set_err(parser *p, tok *t, uint32_t col, uint32_t len, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static void set_err(parser *p, tok *t, uint32_t col, uint32_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *m = lg_vformat(fmt, ap);
    va_end(ap);
    t->kind = T_ERR;
    t->s = lg_arena_strdup(parena(p), m);
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

/* Whether s[e] may follow a number: not a letter, digit, '_' or '.' (which would make
 * "1x" or "1.2.3" one invalid number). */
static bool number_ends_at(const char *s, uint32_t e, uint32_t end)
{
    return !(e < end && (is_ident_char((unsigned char)s[e]) || s[e] == '.'));
}

enum { NUM_OK, NUM_RANGE, NUM_INVALID };

/* The value of the number s[pos, e) that number_end found, in *val (as strtod or strtoll
 * give it, even when out of range): NUM_RANGE for a float beyond the largest double or an
 * integer beyond 64 bits, NUM_INVALID when the conversion does not take all of it. The
 * text ends in a character strtoll/strtod cannot take (or the final NUL). */
static int number_value(const char *s, uint32_t pos, uint32_t e, bool is_float, lg_gnum *val)
{
    char *endp;
    errno = 0;
    if (is_float) {
        val->f = strtod(s + pos, &endp);
        if (val->f > DBL_MAX || val->f < -DBL_MAX)
            return NUM_RANGE;
    } else {
        long long v = strtoll(s + pos, &endp, 10);
        val->i = v;
        if (errno == ERANGE)
            return NUM_RANGE;
    }
    return endp != s + e ? NUM_INVALID : NUM_OK;
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
    if (e == pos || !number_ends_at(s, e, end) || number_value(s, pos, e, is_float, val) != NUM_OK)
        return false;
    *e_out = e;
    *is_float_out = is_float;
    return true;
}

/* After a clean number that ends at `pos`: the start of the next number of the same run
 * (past one ',' and blanks, on the same line), or UINT32_MAX. */
static uint32_t run_next(const char *s, uint32_t pos, uint32_t end)
{
    while (pos < end && is_blank((unsigned char)s[pos]))
        pos++;
    if (pos >= end || s[pos] != ',')
        return UINT32_MAX;
    pos++;
    while (pos < end && is_blank((unsigned char)s[pos]))
        pos++;
    return pos;
}

/* The first byte of the comment text s[pos, e) that a graph file may not hold (a NUL,
 * which would cut the comment, or a byte that is not UTF-8: fmt writes comments back, and
 * a graph file is text), or UINT32_MAX. */
static uint32_t comment_bad_byte(const char *s, uint32_t pos, uint32_t e)
{
    for (uint32_t i = pos; i < e; i++) {
        unsigned char ch = (unsigned char)s[i];
        if (ch == 0)
            return i;
        if (ch >= 0x80) {
            int k = lg_utf8_char_len((const unsigned char *)s + i, e - i);
            if (k == 0)
                return i;
            i += (uint32_t)k - 1;
        }
    }
    return UINT32_MAX;
}

/* A name, or NODE.PORT, at s[pos] (an identifier starts there): its end. */
static uint32_t lex_ident(parser *p, tok *t, uint32_t pos, uint32_t end)
{
    const char *s = p->src->text;
    uint32_t e = pos + 1;
    while (e < end && is_ident_char((unsigned char)s[e]))
        e++;
    t->kind = T_IDENT;
    t->s = lg_arena_strndup(parena(p), s + pos, e - pos);
    if (e < end && s[e] == '.') {
        if (e + 1 < end && is_ident_start((unsigned char)s[e + 1])) {
            uint32_t f = e + 2;
            while (f < end && is_ident_char((unsigned char)s[f]))
                f++;
            t->port = lg_arena_strndup(parena(p), s + e + 1, f - e - 1);
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
            set_err(p, t, t->col, e - pos, "expected a port name after '%.*s'", (int)(e - pos),
                    s + pos);
        }
    }
    if (e - pos > MAX_NAME_BYTES)
        set_err(p, t, t->col, e - pos,
                "this name is %u characters long; names have at "
                "most %u",
                e - pos, MAX_NAME_BYTES);
    t->len = e - pos;
    return e;
}

/* The number s[pos, num_end) (number_end found it): its end. When it starts an item of a
 * list (`item_start`, *litems the items of that list so far) and more clean numbers follow
 * it on its line, they all become one T_NUMS token. */
static uint32_t lex_number(parser *p, tok *t, uint32_t pos, uint32_t end, uint32_t num_end,
                           bool is_float, bool item_start, uint32_t *litems)
{
    const char *s = p->src->text;
    uint32_t e = num_end;
    if (!number_ends_at(s, e, end)) {
        while (e < end && (is_ident_char((unsigned char)s[e]) || s[e] == '.'))
            e++;
        t->len = e - pos;
        set_err(p, t, t->col, e - pos, "invalid number '%.*s'", (int)(e - pos), s + pos);
        return e;
    }
    t->len = e - pos;
    lg_gnum val;
    int r = number_value(s, pos, e, is_float, &val);
    if (is_float) {
        t->kind = T_FLOAT;
        t->f = val.f;
        if (r == NUM_RANGE)
            set_err(p, t, t->col, t->len,
                    "number '%.*s' is too large (the largest float is about 1.8e308)", (int)t->len,
                    s + pos);
    } else {
        t->kind = T_INT;
        t->i = val.i;
        if (r == NUM_RANGE)
            set_err(p, t, t->col, t->len,
                    "integer '%.*s' is out of range (integers have 64 bits: "
                    "-9223372036854775808 to 9223372036854775807)",
                    (int)t->len, s + pos);
    }
    if (r == NUM_INVALID)
        set_err(p, t, t->col, t->len, "invalid number '%.*s'", (int)t->len, s + pos);
    if (t->kind == T_ERR || !item_start || t->len > LG_GNUM_MAX_TEXT || e > TAG_OFF_MASK)
        return e;
    /* More numbers after this one on its line: one T_NUMS token for them all.
     * They count as the tokens and list items they would have been. */
    uint32_t q = e, n = 1, ntok = p->s->n_tokens, nitems = *litems;
    for (;;) {
        uint32_t rn = run_next(s, q, end), ne;
        bool f;
        lg_gnum v;
        if (rn == UINT32_MAX || !clean_number(s, rn, end, &ne, &f, &v) ||
            ne - rn > LG_GNUM_MAX_TEXT || ne > TAG_OFF_MASK || ntok + 2 > MAX_TOKENS ||
            nitems + 1 > MAX_LIST_ITEMS)
            break;
        ntok += 2;
        nitems++;
        n++;
        q = ne;
    }
    if (n == 1)
        return e;
    numrun *run = lg_arena_alloc(parena(p), sizeof *run);
    run->n = n;
    run->tag = lg_arena_alloc(parena(p), n * sizeof *run->tag);
    run->val = lg_arena_alloc(parena(p), n * sizeof *run->val);
    run->tag[0] = make_tag(pos, t->len, is_float);
    run->val[0] = val;
    uint32_t b = e;
    for (uint32_t j = 1; j < n; j++) {
        uint32_t a = run_next(s, b, end);
        bool f;
        clean_number(s, a, end, &b, &f, &run->val[j]);
        run->tag[j] = make_tag(a, b - a, f);
    }
    t->kind = T_NUMS;
    t->s = (char *)run;
    p->s->n_tokens = ntok;
    *litems = nitems;
    return q;
}

/* The first problem inside a string (the one reported). */
typedef struct strerr {
    char *msg;
    uint32_t col, len;
} strerr;

static void str_err(strerr *e, uint32_t col, uint32_t len, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void str_err(strerr *e, uint32_t col, uint32_t len, const char *fmt, ...)
{
    if (e->msg)
        return;
    va_list ap;
    va_start(ap, fmt);
    e->msg = lg_vformat(fmt, ap);
    va_end(ap);
    e->col = col;
    e->len = len;
}

/* A string at s[pos] (a '"' there), up to its closing '"' on the same line: its end. */
static uint32_t lex_string(parser *p, tok *t, uint32_t pos, uint32_t end, uint32_t line_start)
{
    const char *s = p->src->text;
    lg_str b = { 0 };
    uint32_t e = pos + 1;
    strerr err = { 0 };
    bool closed = false;
    while (e < end && s[e] != '\n') {
        unsigned char ch = (unsigned char)s[e];
        uint32_t col = e - line_start + 1;
        if (ch == '"') {
            closed = true;
            e++;
            break;
        }
        if (ch == '\\') {
            char esc = e + 1 < end ? s[e + 1] : '\n';
            const char *rep = esc == '"'    ? "\""
                              : esc == '\\' ? "\\"
                              : esc == 'n'  ? "\n"
                              : esc == 't'  ? "\t"
                                            : NULL;
            if (rep) {
                lg_str_add(&b, rep);
                e += 2;
                continue;
            }
            if (esc == '\n' || esc == '\r') {
                e++;
                continue; /* reported as an unclosed string */
            }
            if ((unsigned char)esc >= 0x20 && (unsigned char)esc < 0x7f)
                str_err(&err, col, 2,
                        "unknown escape '\\%c' in a string (use \\\" \\\\ "
                        "\\n or \\t)",
                        esc);
            else
                str_err(&err, col, 2, "unknown escape in a string (use \\\" \\\\ \\n or \\t)");
            e += 2;
            continue;
        }
        if (ch < 0x20 && ch != '\t' && ch != '\r') {
            str_err(&err, col, 1, "control character 0x%02X in a string", ch);
            e++;
            continue;
        }
        if (ch == '\r') {
            /* A CR is kept only when a LF does not follow (CRLF ends the line). */
            if (!(e + 1 < end && s[e + 1] == '\n'))
                str_err(&err, col, 1, "control character 0x0D in a string");
            e++;
            continue;
        }
        if (ch >= 0x80) {
            int u = lg_utf8_char_len((const unsigned char *)s + e, end - e);
            if (u == 0) {
                str_err(&err, col, 1,
                        "invalid UTF-8 in a string: byte 0x%02X at byte "
                        "offset %u (strings are UTF-8 text)",
                        ch, e);
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
    } else if (err.msg) {
        set_err(p, t, err.col, err.len, "%s", err.msg);
    } else {
        t->kind = T_STRING;
        t->s = lg_arena_strndup(parena(p), b.s ? b.s : "", b.len);
    }
    free(err.msg);
    lg_str_free(&b);
    return e;
}

/* Punctuation, or a character that starts no token, at s[pos]: its end. */
static uint32_t lex_other(parser *p, tok *t, uint32_t pos, uint32_t end)
{
    const char *s = p->src->text;
    unsigned char c = (unsigned char)s[pos];
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
                set_err(p, t, t->col, t->len,
                        "unexpected byte 0x%02X at byte offset %u "
                        "(not UTF-8 text)",
                        c, pos);
        } else if (c < 0x20 || c == 0x7f) {
            set_err(p, t, t->col, 1, "unexpected control character 0x%02X", c);
        } else {
            set_err(p, t, t->col, 1, "unexpected character '%c'", c);
        }
    }
    return pos + t->len;
}

void lg_lex(parser *p, uint32_t pos, uint32_t end)
{
    const char *s = p->src->text;
    uint32_t line = p->src->first_line, line_start = 0;
    uint32_t pend_first = 0, pend_n = 0;
    bool pend_blank = false, saw_blank = false, line_has_content = false;
    int32_t last_on_line = -1;
    /* The lists open here: their items are counted (MAX_LIST_ITEMS); `want` is whether an
     * item may start (after '[', ',' or a new line). Nesting beyond MAX_LIST_DEPTH counts at
     * the last level; the parser refuses it. */
    uint32_t ldepth = 0, litems[MAX_LIST_DEPTH + 1];
    bool lwant[MAX_LIST_DEPTH + 1];

    if (pos == 0 && end >= 3 && memcmp(s, "\xEF\xBB\xBF", 3) == 0)
        pos = 3; /* a UTF-8 byte order mark */

    while (pos < end) {
        unsigned char c = (unsigned char)s[pos];
        if (is_blank(c)) {
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
                    push_comment(p, lg_arena_strdup(parena(p), ""));
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
            uint32_t bad = comment_bad_byte(s, pos + 1, e);
            if (bad != UINT32_MAX) {
                uint32_t k = push_tok(p);
                tok *t = &p->t[k];
                t->off = bad;
                t->line = line;
                if (s[bad] == 0)
                    set_err(p, t, bad - line_start + 1, 1, "unexpected NUL byte in a comment");
                else
                    set_err(p, t, bad - line_start + 1, 1,
                            "invalid UTF-8 in a comment: byte "
                            "0x%02X at byte offset %u (a graph file is UTF-8 text)",
                            (unsigned char)s[bad], bad);
                last_on_line = (int32_t)k;
            }
            uint32_t te = e;
            while (te > pos + 1 && is_blank((unsigned char)s[te - 1]))
                te--;
            uint32_t idx = push_comment(p, lg_arena_strndup(parena(p), s + pos, te - pos));
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
            set_err(p, t, t->col, 1,
                    "the graph has more than %u tokens (names, numbers, "
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
                    set_err(p, t, t->col, 1,
                            "this list has more than %u items; that is the "
                            "limit",
                            MAX_LIST_ITEMS);
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

        bool is_float = false;
        uint32_t num_end;
        if (is_ident_start(c))
            pos = lex_ident(p, t, pos, end);
        else if ((num_end = number_end(s, pos, end, &is_float)) != pos)
            pos = lex_number(p, t, pos, end, num_end, is_float, item_start, &litems[item_ld]);
        else if (c == '"')
            pos = lex_string(p, t, pos, end, line_start);
        else
            pos = lex_other(p, t, pos, end);
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
