/*
 * tests/fuzz/fuzz_script.c: the viewer's --script parser (host/viewer/script.c:
 * lg_script_parse, what lg_script_load runs on the file's text) on arbitrary bytes.
 *
 * For every input, parsed as the script "fuzz.script" in the folder "/fuzz/dir":
 *   - a refusal must say where ("fuzz.script:LINE: ..." or "fuzz.script: ...") and return
 *     no events;
 *   - an acceptance must hold what viewer_script.h promises: known kinds, lines in file
 *     order, numbers finite and within their limits, a key of the listed names with
 *     known modifiers, a button for a drag, text where the kind has text (a screenshot's
 *     path absolute and ending in .png or .exr);
 *   - the events written back as a script (one canonical line each) parse to the same
 *     events: the parser reads what it accepted the same way twice, so the viewer runs
 *     the script the user wrote.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_script) to the plain driver (fuzz_driver.h):
 *
 *     fuzz_script [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "fuzz_driver.h"
#include "base/util.h"
#include "viewer/script.h"

#define PATH "fuzz.script"
#define DIR "/fuzz/dir"

static unsigned long n_runs, n_ok, n_events;

static void bad(const char *what, uint32_t line)
{
    fprintf(stderr, "fuzz_script: %s (event line %u, input %lu)\n", what, line, n_runs - 1);
    abort();
}

static bool in(double v, double lo, double hi)
{
    return isfinite(v) && v >= lo && v <= hi;
}

static bool whole(double v)
{
    return v == floor(v);
}

static void check_event(const lg_sevent *e, uint32_t prev_line)
{
    uint32_t l = e->line;
    if (l <= prev_line)
        bad("events out of line order", l);
    bool key = e->kind == LG_SEV_KEY || e->kind == LG_SEV_HOLD;
    if (key != (e->key != 0) || (key && !lg_script_key_name(e->key)) ||
        (e->mods & ~(GLFW_MOD_SHIFT | GLFW_MOD_CONTROL | GLFW_MOD_ALT | GLFW_MOD_SUPER)) ||
        (!key && e->mods))
        bad("a key or modifier where there is none, or an unknown one", l);
    /* GLFW_MOUSE_BUTTON_LEFT is 0, the value of every other kind */
    if (e->kind == LG_SEV_DRAG
            ? !(e->button == GLFW_MOUSE_BUTTON_LEFT || e->button == GLFW_MOUSE_BUTTON_RIGHT ||
                e->button == GLFW_MOUSE_BUTTON_MIDDLE)
            : e->button != 0)
        bad("an unknown button, or a button on an event that is not a drag", l);
    bool text = e->kind == LG_SEV_SCREENSHOT || e->kind == LG_SEV_SCREENSHOT_WINDOW ||
                e->kind == LG_SEV_SET || e->kind == LG_SEV_SHELL;
    if ((text && (!e->text || !e->text[0])) || (!text && e->kind != LG_SEV_EXPECT_ERROR && e->text))
        bad("text missing, or where the kind has none", l);
    switch (e->kind) {
    case LG_SEV_WAIT_FRAMES:
    case LG_SEV_HOLD:
        if (!in(e->a, 1, 1000000) || !whole(e->a))
            bad("frames out of range or not whole", l);
        break;
    case LG_SEV_KEY: break;
    case LG_SEV_DRAG:
        if (!in(e->a, -1e6, 1e6) || !in(e->b, -1e6, 1e6) ||
            (e->has_from && (!in(e->from_x, 0, 1e6) || !in(e->from_y, 0, 1e6))))
            bad("a drag out of range", l);
        break;
    case LG_SEV_SCROLL:
        if (!in(e->a, -1000, 1000))
            bad("a scroll out of range", l);
        break;
    case LG_SEV_SCREENSHOT:
    case LG_SEV_SCREENSHOT_WINDOW: {
        size_t n = strlen(e->text);
        bool png = n > 4 && strcasecmp(e->text + n - 4, ".png") == 0;
        bool exr = n > 4 && strcasecmp(e->text + n - 4, ".exr") == 0;
        if (e->text[0] != '/' || !(png || (exr && e->kind == LG_SEV_SCREENSHOT)) ||
            strpbrk(e->text, " \t"))
            bad("a screenshot path that is not absolute, one token, .png or .exr", l);
        break;
    }
    case LG_SEV_SET:
        if (!strchr(e->text, '=') || !strchr(e->text, '.'))
            bad("a set without NODE.PARAM=VALUE", l);
        break;
    case LG_SEV_WAIT_RELOAD:
        if (!in(e->a, 0, 3600) || !(e->a > 0))
            bad("wait_reload seconds out of range", l);
        break;
    case LG_SEV_SLEEP:
        if (!in(e->a, 0, 3600))
            bad("sleep seconds out of range", l);
        break;
    case LG_SEV_EXPECT_OK:
    case LG_SEV_EXPECT_ERROR:
    case LG_SEV_SHELL:
    case LG_SEV_QUIT: break;
    default: bad("an unknown kind", l);
    }
}

/* One canonical line per event; CR LF endings, so that text ending in a CR (which the
 * parser keeps, cutting only the line's last one) reads back as it was. */
static void write_back(lg_str *b, const lg_sevent *e)
{
    static const char *const names[] = { NULL,    "wait_frames", "key",        "hold",
                                         "drag",  "scroll",      "screenshot", "screenshot_window",
                                         "set",   "wait_reload", "expect_ok",  "expect_error",
                                         "shell", "sleep",       "quit" };
    lg_str_add(b, names[e->kind]);
    if (e->kind == LG_SEV_KEY || e->kind == LG_SEV_HOLD) {
        lg_str_add(b, " ");
        if (e->mods & GLFW_MOD_SHIFT)
            lg_str_add(b, "shift+");
        if (e->mods & GLFW_MOD_CONTROL)
            lg_str_add(b, "ctrl+");
        if (e->mods & GLFW_MOD_ALT)
            lg_str_add(b, "alt+");
        if (e->mods & GLFW_MOD_SUPER)
            lg_str_add(b, "super+");
        lg_str_add(b, lg_script_key_name(e->key));
    }
    switch (e->kind) {
    case LG_SEV_WAIT_FRAMES:
    case LG_SEV_HOLD:
    case LG_SEV_SCROLL:
    case LG_SEV_WAIT_RELOAD:
    case LG_SEV_SLEEP: lg_str_addf(b, " %.17g", e->a); break;
    case LG_SEV_DRAG:
        lg_str_addf(b, " %.17g %.17g %s", e->a, e->b,
                    e->button == GLFW_MOUSE_BUTTON_RIGHT    ? "right"
                    : e->button == GLFW_MOUSE_BUTTON_MIDDLE ? "middle"
                                                            : "left");
        if (e->has_from)
            lg_str_addf(b, " from %.17g %.17g", e->from_x, e->from_y);
        break;
    default:
        if (e->text)
            lg_str_addf(b, " %s", e->text);
    }
    lg_str_add(b, "\r\n");
}

static bool same_event(const lg_sevent *x, const lg_sevent *y)
{
    return x->kind == y->kind && x->key == y->key && x->mods == y->mods && x->button == y->button &&
           x->a == y->a && x->b == y->b && x->has_from == y->has_from && x->from_x == y->from_x &&
           x->from_y == y->from_y && !x->text == !y->text &&
           (!x->text || strcmp(x->text, y->text) == 0);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    n_runs++;
    char *text = malloc(size + 1);
    if (!text)
        abort();
    memcpy(text, data, size);
    text[size] = '\0';
    lg_script s;
    char err[1024];
    memset(err, 'x', sizeof err);
    int rc = lg_script_parse(PATH, DIR, text, size, &s, err, sizeof err);
    free(text);
    if (rc) {
        if (rc != -1 || s.n || s.ev || s.path || s.dir || !memchr(err, '\0', sizeof err) ||
            strncmp(err, PATH ":", strlen(PATH) + 1) != 0 || strlen(err) < strlen(PATH) + 3)
            bad("a refusal that does not say where, or that returns events", 0);
        return 0;
    }
    n_ok++;
    n_events += s.n;
    if (!s.path || strcmp(s.path, PATH) || !s.dir || strcmp(s.dir, DIR) || (s.n && !s.ev))
        bad("an accepted script without its path, folder or events", 0);
    lg_str back = { 0 };
    for (uint32_t i = 0; i < s.n; i++) {
        check_event(&s.ev[i], i ? s.ev[i - 1].line : 0);
        write_back(&back, &s.ev[i]);
    }
    lg_script again;
    char *t = lg_str_take(&back);
    size_t len = strlen(t);
    if (lg_script_parse(PATH, DIR, t, len, &again, err, sizeof err) != 0) {
        fprintf(stderr, "fuzz_script: written back: %s\n", err);
        bad("the script written back is refused", 0);
    }
    if (again.n != s.n)
        bad("the script written back has another number of events", 0);
    for (uint32_t i = 0; i < s.n; i++)
        if (!same_event(&s.ev[i], &again.ev[i]) || again.ev[i].line != i + 1)
            bad("an event written back reads as another", s.ev[i].line);
    free(t);
    lg_script_free(&again);
    lg_script_free(&s);
    if (s.n || s.ev)
        bad("lg_script_free leaves events", 0);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* The events, key names and modifiers, buttons, numbers at and past the limits. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("wait_frames "),
    LG_FUZZ_TOKEN("key "),
    LG_FUZZ_TOKEN("hold "),
    LG_FUZZ_TOKEN("drag "),
    LG_FUZZ_TOKEN("scroll "),
    LG_FUZZ_TOKEN("screenshot "),
    LG_FUZZ_TOKEN("screenshot_window "),
    LG_FUZZ_TOKEN("set "),
    LG_FUZZ_TOKEN("wait_reload"),
    LG_FUZZ_TOKEN("expect_ok"),
    LG_FUZZ_TOKEN("expect_error "),
    LG_FUZZ_TOKEN("shell "),
    LG_FUZZ_TOKEN("sleep "),
    LG_FUZZ_TOKEN("quit"),
    LG_FUZZ_TOKEN("shift+"),
    LG_FUZZ_TOKEN("ctrl+"),
    LG_FUZZ_TOKEN("super+"),
    LG_FUZZ_TOKEN("PAGE_UP"),
    LG_FUZZ_TOKEN("F12"),
    LG_FUZZ_TOKEN(" from "),
    LG_FUZZ_TOKEN(" middle"),
    LG_FUZZ_TOKEN("1000000"),
    LG_FUZZ_TOKEN("1e6"),
    LG_FUZZ_TOKEN("-1000"),
    LG_FUZZ_TOKEN("3600"),
    LG_FUZZ_TOKEN("0.5e-3"),
    LG_FUZZ_TOKEN("1e999"),
    LG_FUZZ_TOKEN(".png"),
    LG_FUZZ_TOKEN(".exr"),
    LG_FUZZ_TOKEN(" # "),
    LG_FUZZ_TOKEN("\r\n"),
    LG_FUZZ_TOKEN("a.b = "),
    LG_FUZZ_TOKEN("\t"),
};

static void summary(FILE *out)
{
    fprintf(out, "%lu accepted, %lu events", n_ok, n_events);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_script",
        .mutations = 2000,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
