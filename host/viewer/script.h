/*
 * host/viewer/script.h: the --script files that drive `lightgraph view` (the tests run the
 * viewer under Xvfb with them; docs/viewer.md carries the grammar).
 *
 * A script is a text file of one event per line. Tokens are separated by spaces or tabs;
 * '#' at the start of a line or of a token begins a comment that runs to the end of the
 * line; blank lines are ignored; a line may end in CR LF. The events:
 *
 *   wait_frames N            N >= 1 frames drawn
 *   key NAME                 press and release; NAME is A-Z, 0-9, F1-F12, TAB, ENTER, ESCAPE,
 *                            SPACE, BACKSPACE, LEFT, RIGHT, UP, DOWN, PAGE_UP, PAGE_DOWN,
 *                            HOME, END, LEFT_BRACKET, RIGHT_BRACKET, MINUS, EQUAL, COMMA,
 *                            PERIOD, SLASH, BACKSLASH, SEMICOLON, APOSTROPHE, GRAVE_ACCENT,
 *                            with modifiers as prefixes (shift+, ctrl+, alt+, super+:
 *                            shift+TAB, ctrl+shift+RIGHT); all case-insensitive
 *   hold NAME FRAMES         NAME (as for key) held down for FRAMES >= 1 frames
 *   drag DX DY [BUTTON] [from X Y]
 *                            the pointer moved by (DX, DY) pixels with BUTTON held (left |
 *                            right | middle; default left), from (X, Y) in window pixels
 *                            (default: the window's centre)
 *   scroll D                 wheel by D clicks (> 0 = away from the user = zoom in)
 *   screenshot PATH          PATH ends in .png (display) or .exr (linear)
 *   screenshot_window PATH   .png: the window's pixels as shown (overlay included)
 *                            (either, not written: reported with its line, and the
 *                            viewer's exit status is 1)
 *   set NODE.PARAM=VALUE     a live parameter change, as --set (VALUE is the rest of the
 *                            line and may hold spaces: set sun.direction=[0, -1, 0])
 *   wait_reload [SECONDS]    until the next reload attempt has finished; default 60
 *   expect_ok                the last change or reload succeeded
 *   expect_error [TEXT]      the last change or reload was rejected, with TEXT (the rest of
 *                            the line) in its message
 *   shell COMMAND...         the rest of the line, run by /bin/sh -c in the script's folder
 *   sleep SECONDS            wall time
 *   quit                     ends the viewer
 *   play, pause              the animation clock runs (by --dt a frame) or stops
 *   time T                   the clock shows T seconds (the viewer clamps it to [0, 10^6];
 *                            any finite number parses: a scrub to -5 or 1e300 is a test)
 *   resize W H               the window's size (0 <= W, H <= 16384): glfwSetWindowSize, or
 *                            with a 0 a minimised window's framebuffer of 0 x 0 (an X
 *                            server without a window manager cannot minimise)
 *
 * Limits, so that an absurd script fails at load and not an hour into a run: N and FRAMES
 * at most 1000000; |DX|, |DY|, X, Y at most 1000000 (X, Y >= 0); |D| at most 1000; SECONDS
 * of sleep in [0, 3600], of wait_reload in (0, 3600]; numbers finite. A PATH is one token
 * (no spaces); relative paths are taken from the script's folder.
 *
 * This module parses only; the viewer runs the events (host/viewer/script_run.c). It
 * includes <GLFW/glfw3.h> for the key, modifier and button constants and calls no GLFW
 * function.
 */
#ifndef LG_HOST_VIEWER_SCRIPT_H
#define LG_HOST_VIEWER_SCRIPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The bounds lg_script_load holds a script to. */
#define LG_SCRIPT_MAX_BYTES (1u << 20)
#define LG_SCRIPT_MAX_EVENTS 100000u

typedef enum lg_sev_kind {
    LG_SEV_WAIT_FRAMES = 1,
    LG_SEV_KEY,
    LG_SEV_HOLD,
    LG_SEV_DRAG,
    LG_SEV_SCROLL,
    LG_SEV_SCREENSHOT,
    LG_SEV_SCREENSHOT_WINDOW,
    LG_SEV_SET,
    LG_SEV_WAIT_RELOAD,
    LG_SEV_EXPECT_OK,
    LG_SEV_EXPECT_ERROR,
    LG_SEV_SHELL,
    LG_SEV_SLEEP,
    LG_SEV_QUIT,
    LG_SEV_PLAY, /* since issue 24: the animation clock */
    LG_SEV_PAUSE,
    LG_SEV_TIME,
    LG_SEV_RESIZE /* the window's size */
} lg_sev_kind;

typedef struct lg_sevent {
    lg_sev_kind kind;
    uint32_t line; /* 1-based line in the script */
    int key, mods; /* key, hold: GLFW_KEY_*, GLFW_MOD_* (a mask); else 0 */
    int button;    /* drag: GLFW_MOUSE_BUTTON_*; else 0 */
    double a, b;   /* wait_frames: a = N; hold: a = FRAMES; drag: a = DX, b = DY;
                              scroll: a = D; wait_reload, sleep: a = SECONDS;
                              time: a = T; resize: a = W, b = H */
    bool has_from; /* drag: `from X Y` given */
    double from_x, from_y;
    char *text; /* screenshot(_window): the path resolved against the script's
                              folder; set: "NODE.PARAM=VALUE"; expect_error: TEXT or NULL;
                              shell: COMMAND; else NULL. Owned by the script. */
} lg_sevent;

typedef struct lg_script {
    char *path;    /* as given to lg_script_load */
    char *dir;     /* the script's folder, absolute (symbolic links resolved) */
    lg_sevent *ev; /* n events in file order */
    uint32_t n;
} lg_script;

/* Reads and parses the whole file first (regular files only, at most LG_SCRIPT_MAX_BYTES,
 * LG_SCRIPT_MAX_EVENTS events), so that every error is found before anything runs. Returns
 * 0 with *out filled (free it with lg_script_free), or -1 with *out zeroed and
 * "FILE:LINE: message" in err, the message naming what was expected and what was found
 * ("FILE: message" when the file cannot be read at all). */
int lg_script_load(const char *path, lg_script *out, char *err, size_t errlen);
/* The parsing of lg_script_load, on text already read (tests/fuzz/fuzz_script.c feeds it
 * arbitrary bytes): `text` is `len` bytes followed by a NUL, the caller's, cut into tokens
 * in place; `path` names the script in messages; `dir` is its folder (relative PATHs are
 * resolved against it). No limit on `len` here (lg_script_load's is LG_SCRIPT_MAX_BYTES);
 * the LG_SCRIPT_MAX_EVENTS limit holds. Returns as lg_script_load, *out owning copies of
 * path and dir. */
int lg_script_parse(const char *path, const char *dir, char *text, size_t len, lg_script *out,
                    char *err, size_t errlen);
/* Frees what lg_script_load made and zeroes *s; s may be zeroed already. */
void lg_script_free(lg_script *s);

/* The GLFW key code of a NAME listed above (case-insensitive, without modifiers), or -1. */
int lg_script_key(const char *name);
/* The NAME of a key code in upper case ("PAGE_UP", "F5", "A"), or NULL for a key not listed
 * above. For the viewer's overlay. */
const char *lg_script_key_name(int key);

#endif
