/* The viewer's --script files (viewer_script.h): read, checked and parsed in full before the
 * viewer runs any of it. */
#include "viewer/script.h"

#include <GLFW/glfw3.h>
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "lightgraph/file.h"

/* ---- key names ------------------------------------------------------------------------------- */

typedef struct key_name {
    const char *name;
    int key;
} key_name;

/* The named keys besides A-Z, 0-9 and F1-F12 (which are computed). */
static const key_name kNamedKeys[] = {
    { "TAB", GLFW_KEY_TAB },
    { "ENTER", GLFW_KEY_ENTER },
    { "ESCAPE", GLFW_KEY_ESCAPE },
    { "SPACE", GLFW_KEY_SPACE },
    { "BACKSPACE", GLFW_KEY_BACKSPACE },
    { "LEFT", GLFW_KEY_LEFT },
    { "RIGHT", GLFW_KEY_RIGHT },
    { "UP", GLFW_KEY_UP },
    { "DOWN", GLFW_KEY_DOWN },
    { "PAGE_UP", GLFW_KEY_PAGE_UP },
    { "PAGE_DOWN", GLFW_KEY_PAGE_DOWN },
    { "HOME", GLFW_KEY_HOME },
    { "END", GLFW_KEY_END },
    { "LEFT_BRACKET", GLFW_KEY_LEFT_BRACKET },
    { "RIGHT_BRACKET", GLFW_KEY_RIGHT_BRACKET },
    { "MINUS", GLFW_KEY_MINUS },
    { "EQUAL", GLFW_KEY_EQUAL },
    { "COMMA", GLFW_KEY_COMMA },
    { "PERIOD", GLFW_KEY_PERIOD },
    { "SLASH", GLFW_KEY_SLASH },
    { "BACKSLASH", GLFW_KEY_BACKSLASH },
    { "SEMICOLON", GLFW_KEY_SEMICOLON },
    { "APOSTROPHE", GLFW_KEY_APOSTROPHE },
    { "GRAVE_ACCENT", GLFW_KEY_GRAVE_ACCENT },
};

#define KEY_LIST                                                                                   \
    "A-Z, 0-9, F1-F12, TAB, ENTER, ESCAPE, SPACE, BACKSPACE, LEFT, RIGHT, UP, DOWN, PAGE_UP, "     \
    "PAGE_DOWN, HOME, END, LEFT_BRACKET, RIGHT_BRACKET, MINUS, EQUAL, COMMA, PERIOD, SLASH, "      \
    "BACKSLASH, SEMICOLON, APOSTROPHE, GRAVE_ACCENT"

int lg_script_key(const char *name)
{
    if (!name || !*name)
        return -1;
    size_t n = strlen(name);
    if (n == 1) {
        char c = name[0];
        if (c >= 'a' && c <= 'z')
            return GLFW_KEY_A + (c - 'a');
        if (c >= 'A' && c <= 'Z')
            return GLFW_KEY_A + (c - 'A');
        if (c >= '0' && c <= '9')
            return GLFW_KEY_0 + (c - '0');
        return -1;
    }
    if ((name[0] == 'F' || name[0] == 'f') && n <= 3 && name[1] >= '1' && name[1] <= '9' &&
        (n == 2 || (name[2] >= '0' && name[2] <= '9'))) {
        int f = atoi(name + 1);
        if (f >= 1 && f <= 12 && !(n == 3 && name[1] == '0'))
            return GLFW_KEY_F1 + (f - 1);
        return -1;
    }
    for (size_t i = 0; i < sizeof kNamedKeys / sizeof kNamedKeys[0]; i++)
        if (strcasecmp(name, kNamedKeys[i].name) == 0)
            return kNamedKeys[i].key;
    return -1;
}

const char *lg_script_key_name(int key)
{
    /* static names for the computed ranges: one string per key, so that the pointer stays
     * valid and no buffer is shared between threads */
    static const char *const letters[26] = { "A", "B", "C", "D", "E", "F", "G", "H", "I",
                                             "J", "K", "L", "M", "N", "O", "P", "Q", "R",
                                             "S", "T", "U", "V", "W", "X", "Y", "Z" };
    static const char *const digits[10] = { "0", "1", "2", "3", "4", "5", "6", "7", "8", "9" };
    static const char *const fkeys[12] = { "F1", "F2", "F3", "F4",  "F5",  "F6",
                                           "F7", "F8", "F9", "F10", "F11", "F12" };
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z)
        return letters[key - GLFW_KEY_A];
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9)
        return digits[key - GLFW_KEY_0];
    if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12)
        return fkeys[key - GLFW_KEY_F1];
    for (size_t i = 0; i < sizeof kNamedKeys / sizeof kNamedKeys[0]; i++)
        if (kNamedKeys[i].key == key)
            return kNamedKeys[i].name;
    return NULL;
}

/* ---- parsing --------------------------------------------------------------------------------- */

/* Limits of the numbers (viewer_script.h). */
#define MAX_FRAMES 1000000.0
#define MAX_PIXELS_MOVED 1000000.0
#define MAX_CLICKS 1000.0
#define MAX_SECONDS 3600.0
#define MAX_WINDOW 16384.0

typedef struct parser {
    const char *path; /* for messages */
    const char *dir;
    uint32_t line;
    char *err;
    size_t errlen;
} parser;

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static int
fail(parser *p, const char *fmt, ...)
{
    int k = snprintf(p->err, p->errlen, "%s:%u: ", p->path, p->line);
    if (k >= 0 && (size_t)k < p->errlen) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(p->err + k, p->errlen - (size_t)k, fmt, ap);
        va_end(ap);
    }
    return -1;
}

/* A token as quoted in a message: at most 40 characters, then "...". */
static const char *shown(const char *tok, char buf[48])
{
    size_t n = strlen(tok);
    if (n <= 40)
        return tok;
    memcpy(buf, tok, 37);
    memcpy(buf + 37, "...", 4);
    return buf;
}

static bool is_space(char c)
{
    return c == ' ' || c == '\t';
}

/* The next token of *s (NUL-terminated in place), or NULL at the end of the line. */
static char *next_token(char **s)
{
    char *p = *s;
    while (is_space(*p))
        p++;
    if (!*p) {
        *s = p;
        return NULL;
    }
    char *tok = p;
    while (*p && !is_space(*p))
        p++;
    if (*p)
        *p++ = '\0';
    *s = p;
    return tok;
}

/* The rest of the line, spaces trimmed at both ends (the comment is already cut off). */
static char *rest_of_line(char *s)
{
    while (is_space(*s))
        s++;
    size_t n = strlen(s);
    while (n > 0 && is_space(s[n - 1]))
        s[--n] = '\0';
    return s;
}

/* A finite number in [lo, hi] (whole when `whole`). `what` names it in the message:
 * "wait_frames: expected N, a whole number from 1 to 1000000, found 'x'". */
static int number(parser *p, const char *event, const char *tok, const char *what, double lo,
                  double hi, bool whole, double *out)
{
    char b[48];
    if (!tok)
        return fail(p, "%s: expected %s after '%s', found the end of the line", event, what, event);
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    bool ok = end != tok && *end == '\0' && errno != ERANGE && isfinite(v);
    /* strtod also reads hex and "inf"/"nan": numbers here are decimal */
    for (const char *c = tok; ok && *c; c++)
        if (!((*c >= '0' && *c <= '9') || *c == '.' || *c == '-' || *c == '+' || *c == 'e' ||
              *c == 'E'))
            ok = false;
    if (ok && whole && v != floor(v))
        ok = false;
    if (!ok || v < lo || v > hi) {
        if (whole)
            return fail(p, "%s: expected %s, a whole number from %.0f to %.0f, found '%s'", event,
                        what, lo, hi, shown(tok, b));
        return fail(p, "%s: expected %s, a number from %g to %g, found '%s'", event, what, lo, hi,
                    shown(tok, b));
    }
    *out = v;
    return 0;
}

/* NAME with modifier prefixes: "ctrl+shift+RIGHT". */
static int key_with_mods(parser *p, const char *event, char *tok, int *key, int *mods)
{
    char b[48];
    if (!tok)
        return fail(p,
                    "%s: expected a key name (" KEY_LIST ", with shift+, ctrl+, alt+ or "
                    "super+ before it) after '%s', found the end of the line",
                    event, event);
    *mods = 0;
    char *part = tok;
    for (char *plus; (plus = strchr(part, '+')) != NULL; part = plus + 1) {
        *plus = '\0';
        if (strcasecmp(part, "shift") == 0)
            *mods |= GLFW_MOD_SHIFT;
        else if (strcasecmp(part, "ctrl") == 0 || strcasecmp(part, "control") == 0)
            *mods |= GLFW_MOD_CONTROL;
        else if (strcasecmp(part, "alt") == 0)
            *mods |= GLFW_MOD_ALT;
        else if (strcasecmp(part, "super") == 0)
            *mods |= GLFW_MOD_SUPER;
        else
            return fail(p,
                        "%s: unknown modifier '%s' (shift, ctrl, alt or super, joined to the "
                        "key by '+': ctrl+shift+RIGHT)",
                        event, shown(part, b));
    }
    if (!*part)
        return fail(p, "%s: expected a key name after the last '+', found the end of the token",
                    event);
    *key = lg_script_key(part);
    if (*key < 0)
        return fail(p, "%s: unknown key '%s' (" KEY_LIST ")", event, shown(part, b));
    return 0;
}

static int no_more(parser *p, const char *event, char **s)
{
    char b[48];
    char *extra = next_token(s);
    if (extra)
        return fail(p, "%s: expected the end of the line, found '%s'", event, shown(extra, b));
    return 0;
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

/* PATH resolved against the script's folder, malloc'd into ev->text. */
static int screenshot_path(parser *p, const char *event, char **s, bool exr_ok, lg_sevent *ev)
{
    char b[48];
    char *tok = next_token(s);
    const char *want = exr_ok ? "a path ending in .png (display) or .exr (linear)"
                              : "a path ending in .png";
    if (!tok)
        return fail(p, "%s: expected %s, found the end of the line", event, want);
    size_t n_tok = strlen(tok);
    /* a name before the extension: ".png" or "shots/.png" is no file name */
    if (!(ends_with(tok, ".png") || (exr_ok && ends_with(tok, ".exr"))) || n_tok < 5 ||
        tok[n_tok - 5] == '/')
        return fail(p, "%s: expected %s, found '%s'", event, want, shown(tok, b));
    if (no_more(p, event, s))
        return -1;
    size_t n = strlen(p->dir) + 1 + strlen(tok) + 1;
    ev->text = malloc(n);
    if (!ev->text)
        return fail(p, "out of memory");
    if (tok[0] == '/')
        snprintf(ev->text, n, "%s", tok);
    else
        snprintf(ev->text, n, "%s/%s", p->dir, tok);
    return 0;
}

static bool name_char(char c, bool first)
{
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' ||
           (!first && c >= '0' && c <= '9');
}

/* "NODE.PARAM=VALUE": the key's shape is checked here, the value by the viewer (the --set
 * checker, against the graph as it is then). Spaces around '=' are dropped. */
static int assignment(parser *p, char *rest, lg_sevent *ev)
{
    char b[48];
    const char *want = "NODE.PARAM=VALUE (as --set: set lit.shading=gouraud)";
    if (!*rest)
        return fail(p, "set: expected %s, found the end of the line", want);
    char *eq = strchr(rest, '=');
    if (!eq)
        return fail(p, "set: expected %s, found '%s' (no '=')", want, shown(rest, b));
    char *key_end = eq;
    while (key_end > rest && is_space(key_end[-1]))
        key_end--;
    size_t key_len = (size_t)(key_end - rest);
    /* NAME '.' NAME */
    size_t i = 0;
    bool ok = key_len > 0;
    for (; ok && i < key_len && rest[i] != '.'; i++)
        ok = name_char(rest[i], i == 0);
    ok = ok && i > 0 && i < key_len && rest[i] == '.' && i + 1 < key_len &&
         name_char(rest[i + 1], true);
    for (size_t j = i + 1; ok && j < key_len; j++)
        ok = name_char(rest[j], false);
    if (!ok) {
        char keybuf[48];
        size_t k = key_len < 40 ? key_len : 40;
        memcpy(keybuf, rest, k);
        keybuf[k] = '\0';
        return fail(p,
                    "set: expected NODE.PARAM before '=' (names of letters, digits and '_'), "
                    "found '%s'",
                    keybuf);
    }
    const char *value = eq + 1;
    while (is_space(*value))
        value++;
    if (!*value)
        return fail(p, "set: expected a value after '=', found the end of the line");
    size_t n = key_len + 1 + strlen(value) + 1;
    ev->text = malloc(n);
    if (!ev->text)
        return fail(p, "out of memory");
    snprintf(ev->text, n, "%.*s=%s", (int)key_len, rest, value);
    return 0;
}

static char *dup_text(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d)
        memcpy(d, s, n);
    return d;
}

/* One line (comment cut, NUL-terminated, not blank) into *ev. */
static int parse_event(parser *p, char *s, lg_sevent *ev)
{
    char b[48];
    char *name = next_token(&s);
    memset(ev, 0, sizeof *ev);
    ev->line = p->line;
    double v;
    if (strcmp(name, "wait_frames") == 0) {
        ev->kind = LG_SEV_WAIT_FRAMES;
        if (number(p, name, next_token(&s), "N (frames)", 1, MAX_FRAMES, true, &ev->a))
            return -1;
        return no_more(p, name, &s);
    }
    if (strcmp(name, "key") == 0 || strcmp(name, "hold") == 0) {
        bool hold = name[0] == 'h';
        ev->kind = hold ? LG_SEV_HOLD : LG_SEV_KEY;
        if (key_with_mods(p, name, next_token(&s), &ev->key, &ev->mods))
            return -1;
        if (hold && number(p, name, next_token(&s), "FRAMES", 1, MAX_FRAMES, true, &ev->a))
            return -1;
        return no_more(p, name, &s);
    }
    if (strcmp(name, "drag") == 0) {
        ev->kind = LG_SEV_DRAG;
        ev->button = GLFW_MOUSE_BUTTON_LEFT;
        if (number(p, name, next_token(&s), "DX (pixels)", -MAX_PIXELS_MOVED, MAX_PIXELS_MOVED,
                   false, &ev->a) ||
            number(p, name, next_token(&s), "DY (pixels)", -MAX_PIXELS_MOVED, MAX_PIXELS_MOVED,
                   false, &ev->b))
            return -1;
        bool has_button = false;
        for (char *tok; (tok = next_token(&s)) != NULL;) {
            if (strcmp(tok, "from") == 0 && !ev->has_from) {
                if (number(p, "drag ... from", next_token(&s), "X (window pixels)", 0,
                           MAX_PIXELS_MOVED, false, &ev->from_x) ||
                    number(p, "drag ... from", next_token(&s), "Y (window pixels)", 0,
                           MAX_PIXELS_MOVED, false, &ev->from_y))
                    return -1;
                ev->has_from = true;
            } else if (!has_button && !ev->has_from && strcasecmp(tok, "left") == 0) {
                has_button = true;
            } else if (!has_button && !ev->has_from && strcasecmp(tok, "right") == 0) {
                ev->button = GLFW_MOUSE_BUTTON_RIGHT;
                has_button = true;
            } else if (!has_button && !ev->has_from && strcasecmp(tok, "middle") == 0) {
                ev->button = GLFW_MOUSE_BUTTON_MIDDLE;
                has_button = true;
            } else if (!has_button && !ev->has_from) {
                return fail(p,
                            "drag: unknown button '%s' (left, right or middle), or expected "
                            "'from X Y' or the end of the line",
                            shown(tok, b));
            } else {
                return fail(p, "drag: expected %s, found '%s'",
                            ev->has_from ? "the end of the line"
                                         : "'from X Y' or the end of the line",
                            shown(tok, b));
            }
        }
        return 0;
    }
    if (strcmp(name, "scroll") == 0) {
        ev->kind = LG_SEV_SCROLL;
        if (number(p, name, next_token(&s), "D (wheel clicks)", -MAX_CLICKS, MAX_CLICKS, false,
                   &ev->a))
            return -1;
        return no_more(p, name, &s);
    }
    if (strcmp(name, "screenshot") == 0) {
        ev->kind = LG_SEV_SCREENSHOT;
        return screenshot_path(p, name, &s, true, ev);
    }
    if (strcmp(name, "screenshot_window") == 0) {
        ev->kind = LG_SEV_SCREENSHOT_WINDOW;
        return screenshot_path(p, name, &s, false, ev);
    }
    if (strcmp(name, "set") == 0) {
        ev->kind = LG_SEV_SET;
        return assignment(p, rest_of_line(s), ev);
    }
    if (strcmp(name, "wait_reload") == 0) {
        ev->kind = LG_SEV_WAIT_RELOAD;
        ev->a = 60.0;
        char *tok = next_token(&s);
        if (tok && number(p, name, tok, "SECONDS", 0, MAX_SECONDS, false, &ev->a))
            return -1;
        if (!(ev->a > 0.0))
            return fail(p, "wait_reload: expected SECONDS > 0, found '%s'", tok);
        return no_more(p, name, &s);
    }
    if (strcmp(name, "expect_ok") == 0 || strcmp(name, "quit") == 0) {
        ev->kind = name[0] == 'q' ? LG_SEV_QUIT : LG_SEV_EXPECT_OK;
        return no_more(p, name, &s);
    }
    if (strcmp(name, "expect_error") == 0) {
        ev->kind = LG_SEV_EXPECT_ERROR;
        char *text = rest_of_line(s);
        if (*text && !(ev->text = dup_text(text)))
            return fail(p, "out of memory");
        return 0;
    }
    if (strcmp(name, "shell") == 0) {
        ev->kind = LG_SEV_SHELL;
        char *cmd = rest_of_line(s);
        if (!*cmd)
            return fail(p, "shell: expected a command after 'shell', found the end of the line");
        if (!(ev->text = dup_text(cmd)))
            return fail(p, "out of memory");
        return 0;
    }
    if (strcmp(name, "sleep") == 0) {
        ev->kind = LG_SEV_SLEEP;
        if (number(p, name, next_token(&s), "SECONDS", 0, MAX_SECONDS, false, &v))
            return -1;
        ev->a = v;
        return no_more(p, name, &s);
    }
    if (strcmp(name, "play") == 0 || strcmp(name, "pause") == 0) {
        ev->kind = strcmp(name, "play") == 0 ? LG_SEV_PLAY : LG_SEV_PAUSE;
        return no_more(p, name, &s);
    }
    if (strcmp(name, "time") == 0) {
        ev->kind = LG_SEV_TIME;
        if (number(p, name, next_token(&s), "T (seconds)", -DBL_MAX, DBL_MAX, false, &ev->a))
            return -1;
        return no_more(p, name, &s);
    }
    if (strcmp(name, "resize") == 0) {
        ev->kind = LG_SEV_RESIZE;
        if (number(p, name, next_token(&s), "W (window width)", 0, MAX_WINDOW, true, &ev->a) ||
            number(p, name, next_token(&s), "H (window height)", 0, MAX_WINDOW, true, &ev->b))
            return -1;
        return no_more(p, name, &s);
    }
    return fail(p,
                "unknown event '%s' (expected wait_frames, key, hold, drag, scroll, "
                "screenshot, screenshot_window, set, wait_reload, expect_ok, expect_error, "
                "shell, sleep, quit, play, pause, time or resize)",
                shown(name, b));
}

/* Cuts a comment off the line: '#' at its start or after a space or tab. */
static void cut_comment(char *s)
{
    for (char *c = s; *c; c++)
        if (*c == '#' && (c == s || is_space(c[-1]))) {
            *c = '\0';
            return;
        }
}

/* The file's folder, absolute and with links resolved, malloc'd; NULL with errno set. */
static char *script_dir(const char *path)
{
    char *real = realpath(path, NULL);
    if (!real)
        return NULL;
    char *slash = strrchr(real, '/');
    if (slash == real)
        slash[1] = '\0'; /* a script in / */
    else if (slash)
        *slash = '\0';
    return real;
}

/* The whole file, or NULL with the message in err. A file over the size limit is reported at
 * the line where the limit falls (its first LG_SCRIPT_MAX_BYTES bytes are read to count). */
static char *read_script(const char *path, size_t *len, char *err, size_t errlen)
{
    char why[256];
    uint64_t size = 0;
    int fd = lg_file_open(path, UINT64_MAX, &size, why, sizeof why);
    if (fd < 0) {
        snprintf(err, errlen, "%s: cannot read the script: %s", path, why);
        return NULL;
    }
    if (size > LG_SCRIPT_MAX_BYTES) {
        char *buf = malloc(LG_SCRIPT_MAX_BYTES);
        size_t got = 0;
        while (buf && got < LG_SCRIPT_MAX_BYTES) {
            ssize_t r = read(fd, buf + got, LG_SCRIPT_MAX_BYTES - got);
            if (r <= 0)
                break;
            got += (size_t)r;
        }
        uint32_t line = 1;
        for (size_t i = 0; i < got; i++)
            line += buf[i] == '\n';
        free(buf);
        close(fd);
        snprintf(err, errlen,
                 "%s:%u: the script is %llu bytes, over the limit of %u bytes (1 MiB), which "
                 "falls on this line",
                 path, line, (unsigned long long)size, LG_SCRIPT_MAX_BYTES);
        return NULL;
    }
    char *text = lg_file_read_fd(fd, size, len, why, sizeof why);
    close(fd);
    if (!text)
        snprintf(err, errlen, "%s: cannot read the script: %s", path, why);
    return text;
}

int lg_script_load(const char *path, lg_script *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (errlen)
        err[0] = '\0';
    size_t len = 0;
    char *text = read_script(path, &len, err, errlen);
    if (!text)
        return -1;
    char *dir = script_dir(path);
    if (!dir) {
        snprintf(err, errlen, "%s: cannot find the script's folder: %s", path, strerror(errno));
        free(text);
        return -1;
    }
    int rc = lg_script_parse(path, dir, text, len, out, err, errlen);
    free(dir);
    free(text);
    return rc;
}

int lg_script_parse(const char *path, const char *dir, char *text, size_t len, lg_script *out,
                    char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (errlen)
        err[0] = '\0';
    lg_script s = { 0 };
    s.path = dup_text(path);
    s.dir = dup_text(dir);
    if (!s.path || !s.dir) {
        snprintf(err, errlen, "%s: out of memory", path);
        lg_script_free(&s);
        return -1;
    }
    parser p = { .path = path, .dir = s.dir, .line = 0, .err = err, .errlen = errlen };
    uint32_t cap = 0;
    int rc = 0;
    for (size_t at = 0; at < len && rc == 0;) {
        p.line++;
        char *line = text + at;
        char *nl = memchr(line, '\n', len - at);
        size_t n = nl ? (size_t)(nl - line) : len - at;
        at += n + (nl ? 1 : 0);
        if (memchr(line, '\0', n)) {
            rc = fail(&p, "the line holds a NUL byte (a script is text)");
            break;
        }
        line[n] = '\0'; /* the '\n', or the NUL lg_file_read_fd put after the content */
        if (n > 0 && line[n - 1] == '\r')
            line[n - 1] = '\0';
        cut_comment(line);
        char *probe = line;
        while (is_space(*probe))
            probe++;
        if (!*probe)
            continue;
        if (s.n == LG_SCRIPT_MAX_EVENTS) {
            rc = fail(&p, "more than %u events; that is the limit of a script",
                      LG_SCRIPT_MAX_EVENTS);
            break;
        }
        if (s.n == cap) {
            uint32_t ncap = cap ? cap * 2 : 64;
            if (ncap > LG_SCRIPT_MAX_EVENTS)
                ncap = LG_SCRIPT_MAX_EVENTS;
            lg_sevent *grown = realloc(s.ev, ncap * sizeof *grown);
            if (!grown) {
                rc = fail(&p, "out of memory");
                break;
            }
            s.ev = grown;
            cap = ncap;
        }
        rc = parse_event(&p, probe, &s.ev[s.n]);
        /* a failed event may hold text already: count it so that lg_script_free frees it */
        s.n++;
    }
    if (rc) {
        lg_script_free(&s);
        return -1;
    }
    *out = s;
    return 0;
}

void lg_script_free(lg_script *s)
{
    if (!s)
        return;
    for (uint32_t i = 0; i < s->n; i++)
        free(s->ev[i].text);
    free(s->ev);
    free(s->path);
    free(s->dir);
    memset(s, 0, sizeof *s);
}
