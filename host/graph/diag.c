/*
 * host/graph/diag.c: diagnostics (collect, print) and did-you-mean suggestions.
 */
#include "graph/graph.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"

int lg_utf8_char_len(const unsigned char *s, size_t n)
{
    if (n == 0)
        return 0;
    unsigned c = s[0];
    if (c < 0x80)
        return 1;
    int len;
    uint32_t cp, min;
    if (c >= 0xC2 && c <= 0xDF) {
        len = 2, cp = c & 0x1F, min = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
        len = 3, cp = c & 0x0F, min = 0x800;
    } else if (c >= 0xF0 && c <= 0xF4) {
        len = 4, cp = c & 0x07, min = 0x10000;
    } else {
        return 0; /* a continuation byte, C0/C1 (always overlong), F5..FF */
    }
    if ((size_t)len > n)
        return 0;
    for (int i = 1; i < len; i++) {
        if ((s[i] & 0xC0) != 0x80)
            return 0;
        cp = cp << 6 | (s[i] & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF))
        return 0;
    return len;
}

/* One character of a line as shown: itself when it is printable UTF-8 or a tab (kept so
 * the caret lines up in a terminal), '?' for a control byte or a byte that is not UTF-8
 * (an escape sequence in a graph file must not drive the terminal). Returns the number of
 * input bytes it takes. */
static size_t show_char(lg_str *out, const unsigned char *s, size_t n)
{
    int k = lg_utf8_char_len(s, n);
    if (k == 0 || (k == 1 && ((s[0] < 0x20 && s[0] != '\t') || s[0] == 0x7F)) ||
        (k == 2 && s[0] == 0xC2 && s[1] < 0xA0)) { /* C1 controls U+0080..U+009F */
        lg_str_addc(out, '?');
        return k ? (size_t)k : 1;
    }
    lg_str_addn(out, (const char *)s, (size_t)k);
    return (size_t)k;
}

/* Steps back over one character from `i` (at most 3 continuation bytes). */
static size_t char_back(const unsigned char *s, size_t i)
{
    size_t j = i - 1;
    while (j > 0 && i - j < 4 && (s[j] & 0xC0) == 0x80)
        j--;
    return lg_utf8_char_len(s + j, i - j) == (int)(i - j) ? j : i - 1;
}

/* The excerpt of line[0, n) around byte column `col` (1-based) with `len` bytes underlined:
 * at most LG_DIAG_EXCERPT_COLS characters, a third of them before the column, "..." where
 * the line is cut. Sets the caret's column and the underline's length inside the excerpt.
 * Costs O(LG_DIAG_EXCERPT_COLS), whatever the line's length. */
static char *excerpt(const char *line, size_t n, uint32_t col, uint32_t len, uint32_t *ecol,
                     uint32_t *elen)
{
    const unsigned char *s = (const unsigned char *)line;
    size_t at = col > 0 ? col - 1 : 0;
    if (at > n)
        at = n;
    /* The window [a, b): back a third, then forward to the full width; at the end of the
     * line, back again to fill the width. */
    size_t a = at, chars = 0;
    while (a > 0 && chars < LG_DIAG_EXCERPT_COLS / 3) {
        a = char_back(s, a);
        chars++;
    }
    size_t b = a;
    while (b < n && chars < LG_DIAG_EXCERPT_COLS) {
        int k = lg_utf8_char_len(s + b, n - b);
        if (b < at) {
            b += k ? (size_t)k : 1;
            continue; /* already counted */
        }
        b += k ? (size_t)k : 1;
        chars++;
    }
    while (a > 0 && chars < LG_DIAG_EXCERPT_COLS) {
        a = char_back(s, a);
        chars++;
    }
    lg_str out = { 0 };
    if (a > 0)
        lg_str_add(&out, "...");
    size_t cs = SIZE_MAX, ce = SIZE_MAX, end = at + (len > 0 ? len : 0);
    size_t i = a;
    while (i < b) {
        if (cs == SIZE_MAX && i >= at)
            cs = out.len;
        if (ce == SIZE_MAX && i >= end && i > at)
            ce = out.len;
        i += show_char(&out, s + i, b - i);
    }
    if (cs == SIZE_MAX)
        cs = out.len;
    if (ce == SIZE_MAX)
        ce = out.len;
    if (b < n)
        lg_str_add(&out, "...");
    *ecol = (uint32_t)cs + 1;
    *elen = ce > cs ? (uint32_t)(ce - cs) : 0;
    return lg_str_take(&out);
}

static void diags_addv(lg_diags *d, lg_diag_level level, lg_srcloc loc, const char *line, size_t n,
                       const char *fmt, va_list ap)
{
    if (d->n == d->cap) {
        d->cap = d->cap ? d->cap * 2 : 16;
        d->items = lg_xrealloc(d->items, d->cap * sizeof *d->items);
    }
    char *msg = lg_vformat(fmt, ap);
    size_t mlen = strlen(msg);
    if (mlen > LG_DIAG_MAX_MESSAGE) {
        size_t cut = LG_DIAG_MAX_MESSAGE - 3;
        while (cut > 0 && ((unsigned char)msg[cut] & 0xC0) == 0x80)
            cut--; /* not inside a UTF-8 character */
        memcpy(msg + cut, "...", 4);
    }

    lg_diag *g = &d->items[d->n++];
    g->level = level;
    g->loc = loc;
    /* The diagnostics outlive the graph whose pool holds the file name. */
    g->loc.file = loc.file ? lg_xstrdup(loc.file) : NULL;
    g->message = msg;
    g->line_text = NULL;
    g->text_col = g->text_len = 0;
    if (line)
        g->line_text = excerpt(line, n, loc.col, loc.len, &g->text_col, &g->text_len);
    if (level == LG_DIAG_ERROR)
        d->errors++;
}

void lg_diags_add(lg_diags *d, lg_diag_level level, lg_srcloc loc, const char *line_text,
                  const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    diags_addv(d, level, loc, line_text, line_text ? strlen(line_text) : 0, fmt, ap);
    va_end(ap);
}

void lg_diags_add_line(lg_diags *d, lg_diag_level level, lg_srcloc loc, const char *line, size_t n,
                       const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    diags_addv(d, level, loc, line, n, fmt, ap);
    va_end(ap);
}

static const char *level_name(lg_diag_level l)
{
    switch (l) {
    case LG_DIAG_WARNING: return "warning";
    case LG_DIAG_NOTE: return "note";
    default: return "error";
    }
}

/* The caret line: white space under the text before the column (tabs copied so the caret
 * lines up in a terminal; one column per UTF-8 character), then ^~~~ under `len` bytes. */
static void print_caret(FILE *f, const char *line, uint32_t col, uint32_t len)
{
    size_t n = strlen(line);
    size_t start = col > 0 ? col - 1 : 0;
    if (start > n)
        start = n;
    for (size_t i = 0; i < start; i++) {
        unsigned char c = (unsigned char)line[i];
        if ((c & 0xC0) == 0x80)
            continue;
        fputc(c == '\t' ? '\t' : ' ', f);
    }
    fputc('^', f);
    size_t end = start + (len > 0 ? len : 1);
    if (end > n)
        end = n > start ? n : start + 1;
    for (size_t i = start + 1; i < end; i++) {
        if (((unsigned char)line[i] & 0xC0) == 0x80)
            continue;
        fputc('~', f);
    }
    fputc('\n', f);
}

void lg_diags_print(const lg_diags *d, FILE *f)
{
    for (uint32_t i = 0; i < d->n; i++) {
        const lg_diag *g = &d->items[i];
        if (g->loc.file && g->loc.line > 0)
            fprintf(f, "%s:%u:%u: ", g->loc.file, g->loc.line, g->loc.col);
        else if (g->loc.file)
            fprintf(f, "%s: ", g->loc.file);
        fprintf(f, "%s: %s\n", level_name(g->level), g->message);
        if (g->line_text && g->loc.line > 0) {
            fprintf(f, "%s\n", g->line_text);
            print_caret(f, g->line_text, g->text_col, g->text_len);
        }
    }
}

void lg_diags_free(lg_diags *d)
{
    for (uint32_t i = 0; i < d->n; i++) {
        free((char *)d->items[i].loc.file);
        free(d->items[i].message);
        free(d->items[i].line_text);
    }
    free(d->items);
    memset(d, 0, sizeof *d);
}

/* ---- did-you-mean ---------------------------------------------------------------------------- */

/* Words longer than this get no suggestion: nobody mistypes a 65-letter name by a few
 * letters, and the distance is quadratic in the length. */
#define SUGGEST_MAX_LEN 64

/* Optimal string alignment distance (Damerau-Levenshtein where a substring is edited at
 * most once), case-insensitive, stopping early once every cell of a row exceeds `limit`. */
static size_t osa_distance(const char *a, size_t na, const char *b, size_t nb, size_t limit)
{
    size_t rows[3][SUGGEST_MAX_LEN + 1];
    size_t *prev2 = rows[0], *prev = rows[1], *cur = rows[2];
    for (size_t j = 0; j <= nb; j++)
        prev[j] = j;
    for (size_t i = 1; i <= na; i++) {
        cur[0] = i;
        size_t row_min = cur[0];
        int ca = tolower((unsigned char)a[i - 1]);
        for (size_t j = 1; j <= nb; j++) {
            int cb = tolower((unsigned char)b[j - 1]);
            size_t cost = ca == cb ? 0 : 1;
            size_t v = prev[j] + 1;
            if (cur[j - 1] + 1 < v)
                v = cur[j - 1] + 1;
            if (prev[j - 1] + cost < v)
                v = prev[j - 1] + cost;
            if (i > 1 && j > 1 && ca == tolower((unsigned char)b[j - 2]) &&
                tolower((unsigned char)a[i - 2]) == cb && prev2[j - 2] + 1 < v)
                v = prev2[j - 2] + 1;
            cur[j] = v;
            if (v < row_min)
                row_min = v;
        }
        if (row_min > limit)
            return limit + 1;
        size_t *t = prev2;
        prev2 = prev;
        prev = cur;
        cur = t;
    }
    return prev[nb];
}

const char *lg_suggest(const char *word, const char *const *names, uint32_t n)
{
    size_t nw = word ? strlen(word) : 0;
    if (nw == 0 || nw > SUGGEST_MAX_LEN)
        return NULL;
    /* One edit for short words, a third of the letters for longer ones: 'kye' -> 'key',
     * 'reinhardd' -> 'reinhard', while 'foo' is not offered 'key'. */
    size_t limit = nw / 3 > 1 ? nw / 3 : 1;
    const char *best = NULL;
    size_t best_d = limit + 1;
    for (uint32_t i = 0; i < n; i++) {
        if (!names[i])
            continue;
        size_t nn = strlen(names[i]);
        if (nn == 0 || nn > SUGGEST_MAX_LEN)
            continue;
        size_t diff = nn > nw ? nn - nw : nw - nn;
        if (diff >= best_d)
            continue;
        size_t dist = osa_distance(word, nw, names[i], nn, best_d - 1);
        if (dist < best_d) {
            best_d = dist;
            best = names[i];
        }
    }
    /* A word that only differs from itself in case is still worth pointing out, but an
     * exact match is no suggestion at all. */
    if (best && strcmp(best, word) == 0)
        return NULL;
    return best;
}
