/*
 * host/graph/include.c: the file an include statement names (docs/graph-format.md,
 * "Includes"): resolved against the including file's folder, read by the one bounded
 * reader within what is left of the graph's size limit, handed back to the parser (parse.c)
 * to parse into the same session (its
 * nodes join the graph's, marked `included`), once however often it is included, and
 * refused when it closes a cycle, nests too deep or is not a graph file.
 */
#include "graph/parse_priv.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/util.h"
#include "lightgraph/file.h"

/* Whether `text` starts like a graph file: after blank lines, comments and a byte order
 * mark, the word 'lightgraph' as the version line's (not a node called so). An included
 * file that does not is not parsed at all, so that including /proc/self/status or a PNG
 * gives one message instead of an echo of its lines. */
static bool looks_like_graph(const char *text, size_t len)
{
    size_t i = len >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
    for (;;) {
        while (i < len && (is_blank((unsigned char)text[i]) || text[i] == '\n'))
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

source *lg_include_open(parser *p, const tok *f, const char **base_dir_out)
{
    source *opened = NULL;
    session *s = p->s;
    pool *pl = s->pl;
    /* "x.lgraph" rather than "./x.lgraph" in messages when the including file is in the
     * current directory. */
    char *full = !p->base_dir || strcmp(p->base_dir, ".") == 0 ? lg_xstrdup(f->s)
                                                               : lg_path_join(p->base_dir, f->s);
    char *abs = lg_path_absolute(full);
    for (uint32_t i = 0; i < s->depth; i++) {
        if (s->stack_abs[i] && strcmp(s->stack_abs[i], abs) == 0) {
            lg_str chain = { 0 };
            for (uint32_t j = i; j < s->depth; j++)
                lg_str_addf(&chain, "%s -> ", s->stack_name[j]);
            lg_str_add(&chain, s->stack_name[i]);
            lg_tok_report(p, f, LG_DIAG_ERROR, "include cycle: %s", chain.s);
            lg_str_free(&chain);
            goto out;
        }
    }
    for (uint32_t i = 0; i < s->n_done; i++)
        if (strcmp(s->done[i], abs) == 0)
            goto out; /* already included once: it adds nothing new */
    if (s->depth >= MAX_INCLUDE_DEPTH) {
        lg_tok_report(p, f, LG_DIAG_ERROR, "includes are nested more than %d deep",
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
        lg_tok_report(p, f, LG_DIAG_ERROR, "cannot read included file '%s': %s", full, why);
        goto out;
    }
    if (s->n_bytes + size > MAX_FILE_BYTES) {
        close(fd);
        lg_tok_report(p, f, LG_DIAG_ERROR,
                      "cannot include '%s' (%llu bytes): a graph file and "
                      "its includes have at most %u MiB in all",
                      full, (unsigned long long)size, MAX_FILE_BYTES >> 20);
        goto out;
    }
    char *text = lg_file_read_fd(fd, size, &len, why, sizeof why);
    close(fd);
    if (!text) {
        lg_tok_report(p, f, LG_DIAG_ERROR, "cannot read included file '%s': %s", full, why);
        goto out;
    }
    if (!looks_like_graph(text, len)) {
        lg_tok_report(p, f, LG_DIAG_ERROR,
                      "included file '%s' is not a graph file: it does not "
                      "start with the version line 'lightgraph 1'",
                      full);
        free(text);
        goto out;
    }
    s->n_bytes += len;
    source *src = lg_source_add(pl, full, text, len, 1, true);
    const char *abs_i = lg_arena_strdup(&pl->a, abs);
    if (s->n_done == s->cap_done) {
        s->cap_done = s->cap_done ? s->cap_done * 2 : 8;
        s->done = lg_xrealloc(s->done, s->cap_done * sizeof *s->done);
    }
    s->done[s->n_done++] = abs_i;
    char *dir = lg_path_dirname(full);
    const char *base_dir = lg_arena_strdup(&pl->a, dir);
    free(dir);
    s->stack_name[s->depth] = src->name;
    s->stack_abs[s->depth] = abs_i;
    s->depth++; /* the caller parses src, then takes it off the stack */
    *base_dir_out = base_dir;
    opened = src;
out:
    free(full);
    free(abs);
    return opened;
}
