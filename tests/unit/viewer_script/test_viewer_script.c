/*
 * The viewer's --script parser (host/viewer/script.c): every event with its fields, paths
 * resolved against the script's folder, key names and modifiers, comments and blank lines,
 * and every error with its line: unknown event, bad number, N = 0, negative frames, unknown
 * key, modifier or button, a missing argument, trailing tokens, a wrong screenshot
 * extension, a file over 1 MiB, more than 100000 events, a NUL byte, a file that is not
 * there or not a regular file.
 */
#include <GLFW/glfw3.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/check.h"
#include "viewer/script.h"

static char g_dir[PATH_MAX]; /* the temporary folder, links resolved */
static char g_path[PATH_MAX + 32];

/* Writes n bytes of text to g_dir/script.txt (n = strlen when (size_t)-1). */
static const char *write_script(const char *text, size_t n)
{
    if (n == (size_t)-1)
        n = strlen(text);
    snprintf(g_path, sizeof g_path, "%s/script.txt", g_dir);
    FILE *f = fopen(g_path, "wb");
    if (!f || fwrite(text, 1, n, f) != n || fclose(f) != 0) {
        fprintf(stderr, "cannot write %s\n", g_path);
        exit(1);
    }
    return g_path;
}

/* The script must be refused with an error that starts "PATH:LINE: " and holds `want`. */
#define EXPECT_ERROR(text, line, want) expect_error_at(__LINE__, (text), (size_t)-1, (line), (want))

static void expect_error_at(int at, const char *text, size_t n, unsigned line, const char *want)
{
    const char *path = write_script(text, n);
    lg_script s;
    char err[1024], prefix[PATH_MAX + 64];
    memset(&s, 0x5a, sizeof s);
    int rc = lg_script_load(path, &s, err, sizeof err);
    snprintf(prefix, sizeof prefix, "%s:%u: ", path, line);
    if (rc != -1 || strncmp(err, prefix, strlen(prefix)) != 0 || !strstr(err, want)) {
        fprintf(stderr, "test line %d: expected '%s...%s', got rc %d: %s\n", at, prefix, want, rc,
                rc ? err : "(loaded)");
        check_failures++;
    }
    CHECK(s.ev == NULL && s.n == 0 && s.path == NULL); /* zeroed on failure */
    if (rc == 0)
        lg_script_free(&s);
}

static int load(const char *text, lg_script *s)
{
    char err[1024];
    int rc = lg_script_load(write_script(text, (size_t)-1), s, err, sizeof err);
    if (rc)
        fprintf(stderr, "unexpected error: %s\n", err);
    return rc;
}

static void test_events(void)
{
    const char *text = "# a comment line, then a blank one\n"
                       "\n"
                       "wait_frames 3\n"
                       "key A   # a trailing comment\n"
                       "\tkey ctrl+shift+RIGHT\n"
                       "key f5\n"
                       "hold w 30\n"
                       "drag 120 -40\n"
                       "drag -5.5 2 right from 10 20\n"
                       "drag 1 1 middle\n"
                       "drag 1 1 from 0 0\n"
                       "scroll -1.5\n"
                       "screenshot shots/a.png\n"
                       "screenshot /abs/b.EXR\n"
                       "screenshot_window win.png\n"
                       "set lit.shading = gouraud\n"
                       "set sun.direction=[0.6, -0.5, 1]\n"
                       "wait_reload\n"
                       "wait_reload 2.5\n"
                       "expect_ok\n"
                       "expect_error\n"
                       "expect_error  cannot open 'x.glb'  \n"
                       "shell touch a.txt && echo \"a#b\" > b.txt   # cut here\n"
                       "sleep 0.25\n"
                       "quit\r\n";
    lg_script s;
    if (load(text, &s) != 0) {
        check_failures++;
        return;
    }
    CHECK(strcmp(s.path, g_path) == 0);
    CHECK(strcmp(s.dir, g_dir) == 0);
    CHECKF(s.n == 23, "%u events", s.n);
    if (s.n != 23) {
        lg_script_free(&s);
        return;
    }
    const lg_sevent *e = s.ev;
    CHECK(e[0].kind == LG_SEV_WAIT_FRAMES && e[0].a == 3 && e[0].line == 3 && !e[0].text);
    CHECK(e[1].kind == LG_SEV_KEY && e[1].key == GLFW_KEY_A && e[1].mods == 0 && e[1].line == 4);
    CHECK(e[2].kind == LG_SEV_KEY && e[2].key == GLFW_KEY_RIGHT &&
          e[2].mods == (GLFW_MOD_CONTROL | GLFW_MOD_SHIFT));
    CHECK(e[3].key == GLFW_KEY_F5);
    CHECK(e[4].kind == LG_SEV_HOLD && e[4].key == GLFW_KEY_W && e[4].a == 30);
    CHECK(e[5].kind == LG_SEV_DRAG && e[5].a == 120 && e[5].b == -40 &&
          e[5].button == GLFW_MOUSE_BUTTON_LEFT && !e[5].has_from);
    CHECK(e[6].a == -5.5 && e[6].b == 2 && e[6].button == GLFW_MOUSE_BUTTON_RIGHT &&
          e[6].has_from && e[6].from_x == 10 && e[6].from_y == 20);
    CHECK(e[7].button == GLFW_MOUSE_BUTTON_MIDDLE && !e[7].has_from);
    CHECK(e[8].button == GLFW_MOUSE_BUTTON_LEFT && e[8].has_from && e[8].from_x == 0);
    CHECK(e[9].kind == LG_SEV_SCROLL && e[9].a == -1.5);
    char want[PATH_MAX + 64];
    snprintf(want, sizeof want, "%s/shots/a.png", g_dir);
    CHECKF(e[10].kind == LG_SEV_SCREENSHOT && strcmp(e[10].text, want) == 0, "%s", e[10].text);
    CHECK(e[11].kind == LG_SEV_SCREENSHOT && strcmp(e[11].text, "/abs/b.EXR") == 0);
    snprintf(want, sizeof want, "%s/win.png", g_dir);
    CHECK(e[12].kind == LG_SEV_SCREENSHOT_WINDOW && strcmp(e[12].text, want) == 0);
    CHECKF(e[13].kind == LG_SEV_SET && strcmp(e[13].text, "lit.shading=gouraud") == 0, "%s",
           e[13].text);
    CHECKF(strcmp(e[14].text, "sun.direction=[0.6, -0.5, 1]") == 0, "%s", e[14].text);
    CHECK(e[15].kind == LG_SEV_WAIT_RELOAD && e[15].a == 60.0);
    CHECK(e[16].kind == LG_SEV_WAIT_RELOAD && e[16].a == 2.5);
    CHECK(e[17].kind == LG_SEV_EXPECT_OK);
    CHECK(e[18].kind == LG_SEV_EXPECT_ERROR && e[18].text == NULL);
    CHECKF(e[19].kind == LG_SEV_EXPECT_ERROR && strcmp(e[19].text, "cannot open 'x.glb'") == 0,
           "%s", e[19].text);
    CHECKF(e[20].kind == LG_SEV_SHELL &&
               strcmp(e[20].text, "touch a.txt && echo \"a#b\" > b.txt") == 0,
           "%s", e[20].text);
    CHECK(e[21].kind == LG_SEV_SLEEP && e[21].a == 0.25);
    CHECK(e[22].kind == LG_SEV_QUIT && e[22].line == 25);
    lg_script_free(&s);
    CHECK(s.ev == NULL && s.n == 0 && s.path == NULL && s.dir == NULL);
    lg_script_free(&s); /* twice is harmless */

    /* an empty script, and one of comments only: no events */
    CHECK(load("", &s) == 0 && s.n == 0);
    lg_script_free(&s);
    CHECK(load("# nothing\n   \n\t# more\n", &s) == 0 && s.n == 0);
    lg_script_free(&s);
}

static void test_keys(void)
{
    CHECK(lg_script_key("A") == GLFW_KEY_A && lg_script_key("z") == GLFW_KEY_Z);
    CHECK(lg_script_key("0") == GLFW_KEY_0 && lg_script_key("9") == GLFW_KEY_9);
    CHECK(lg_script_key("F1") == GLFW_KEY_F1 && lg_script_key("f12") == GLFW_KEY_F12);
    CHECK(lg_script_key("F13") == -1 && lg_script_key("F0") == -1 && lg_script_key("F01") == -1);
    CHECK(lg_script_key("page_up") == GLFW_KEY_PAGE_UP);
    CHECK(lg_script_key("Grave_Accent") == GLFW_KEY_GRAVE_ACCENT);
    CHECK(lg_script_key("") == -1 && lg_script_key(NULL) == -1 && lg_script_key("!") == -1);
    CHECK(lg_script_key("KP_0") == -1 && lg_script_key("SHIFT") == -1);
    /* every listed name round-trips through its code */
    const char *names[] = { "TAB",       "ENTER",     "ESCAPE",     "SPACE",        "BACKSPACE",
                            "LEFT",      "RIGHT",     "UP",         "DOWN",         "PAGE_UP",
                            "PAGE_DOWN", "HOME",      "END",        "LEFT_BRACKET", "RIGHT_BRACKET",
                            "MINUS",     "EQUAL",     "COMMA",      "PERIOD",       "SLASH",
                            "BACKSLASH", "SEMICOLON", "APOSTROPHE", "GRAVE_ACCENT", "Q",
                            "7",         "F9",        "F10" };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        int k = lg_script_key(names[i]);
        const char *back = lg_script_key_name(k);
        CHECKF(k >= 0 && back && strcmp(back, names[i]) == 0, "%s -> %d -> %s", names[i], k,
               back ? back : "(null)");
    }
    CHECK(lg_script_key_name(GLFW_KEY_KP_0) == NULL && lg_script_key_name(-1) == NULL);
    CHECK(lg_script_key_name(GLFW_KEY_LEFT_SHIFT) == NULL);

    lg_script s;
    if (load("key alt+super+x\nkey Control+F2\nhold SHIFT+space 2\n", &s) == 0) {
        CHECK(s.n == 3);
        CHECK(s.ev[0].key == GLFW_KEY_X && s.ev[0].mods == (GLFW_MOD_ALT | GLFW_MOD_SUPER));
        CHECK(s.ev[1].key == GLFW_KEY_F2 && s.ev[1].mods == GLFW_MOD_CONTROL);
        CHECK(s.ev[2].kind == LG_SEV_HOLD && s.ev[2].key == GLFW_KEY_SPACE &&
              s.ev[2].mods == GLFW_MOD_SHIFT && s.ev[2].a == 2);
        lg_script_free(&s);
    } else {
        check_failures++;
    }
}

static void test_errors(void)
{
    EXPECT_ERROR("wait_frames 1\nzoom 3\n", 2, "unknown event 'zoom' (expected wait_frames");
    EXPECT_ERROR("wait_frames x\n", 1,
                 "wait_frames: expected N (frames), a whole number from 1 "
                 "to 1000000, found 'x'");
    EXPECT_ERROR("\n\nwait_frames 0\n", 3, "found '0'");
    EXPECT_ERROR("wait_frames 2.5\n", 1, "a whole number");
    EXPECT_ERROR("wait_frames 1e9\n", 1, "found '1e9'");
    EXPECT_ERROR("wait_frames\n", 1,
                 "wait_frames: expected N (frames) after 'wait_frames', found "
                 "the end of the line");
    EXPECT_ERROR("hold W -3\n", 1,
                 "hold: expected FRAMES, a whole number from 1 to 1000000, "
                 "found '-3'");
    EXPECT_ERROR("hold W\n", 1, "hold: expected FRAMES after 'hold'");
    EXPECT_ERROR("key\n", 1, "key: expected a key name");
    EXPECT_ERROR("key A\nkey PAGEUP\n", 2, "key: unknown key 'PAGEUP' (A-Z, 0-9, F1-F12, TAB");
    EXPECT_ERROR("key hyper+A\n", 1, "key: unknown modifier 'hyper'");
    EXPECT_ERROR("key ctrl+\n", 1, "key: expected a key name after the last '+'");
    EXPECT_ERROR("key A B\n", 1, "key: expected the end of the line, found 'B'");
    EXPECT_ERROR("drag 1\n", 1, "drag: expected DY (pixels) after 'drag'");
    EXPECT_ERROR("drag 1 nan\n", 1,
                 "drag: expected DY (pixels), a number from -1e+06 to 1e+06, "
                 "found 'nan'");
    EXPECT_ERROR("drag 1 inf\n", 1, "found 'inf'");
    EXPECT_ERROR("drag 0x10 1\n", 1, "found '0x10'");
    EXPECT_ERROR("drag 1 2 up\n", 1, "drag: unknown button 'up' (left, right or middle)");
    EXPECT_ERROR("drag 1 2 left right\n", 1,
                 "drag: expected 'from X Y' or the end of the line, "
                 "found 'right'");
    EXPECT_ERROR("drag 1 2 from 3\n", 1, "drag ... from: expected Y (window pixels)");
    EXPECT_ERROR("drag 1 2 from -3 4\n", 1, "found '-3'");
    EXPECT_ERROR("drag 1 2 from 3 4 left\n", 1, "drag: expected the end of the line, found 'left'");
    EXPECT_ERROR("scroll\n", 1, "scroll: expected D (wheel clicks)");
    EXPECT_ERROR("scroll 1e5\n", 1, "a number from -1000 to 1000, found '1e5'");
    EXPECT_ERROR("scroll 1 2\n", 1, "scroll: expected the end of the line, found '2'");
    EXPECT_ERROR("screenshot\n", 1,
                 "screenshot: expected a path ending in .png (display) or "
                 ".exr (linear), found the end of the line");
    EXPECT_ERROR("screenshot a.jpg\n", 1, "found 'a.jpg'");
    EXPECT_ERROR("screenshot .png\n", 1, "found '.png'");
    EXPECT_ERROR("screenshot dir/.exr\n", 1, "found 'dir/.exr'");
    EXPECT_ERROR("screenshot a.png b.png\n", 1, "expected the end of the line, found 'b.png'");
    EXPECT_ERROR("screenshot_window a.exr\n", 1,
                 "screenshot_window: expected a path ending in "
                 ".png, found 'a.exr'");
    EXPECT_ERROR("set\n", 1, "set: expected NODE.PARAM=VALUE");
    EXPECT_ERROR("set lit.shading\n", 1, "(no '=')");
    EXPECT_ERROR("set lit=3\n", 1, "set: expected NODE.PARAM before '='");
    EXPECT_ERROR("set 1lit.k=3\n", 1, "found '1lit.k'");
    EXPECT_ERROR("set lit.=3\n", 1, "found 'lit.'");
    EXPECT_ERROR("set lit.k.j=3\n", 1, "found 'lit.k.j'");
    EXPECT_ERROR("set lit.k=\n", 1, "set: expected a value after '='");
    EXPECT_ERROR("wait_reload 0\n", 1, "wait_reload: expected SECONDS > 0, found '0'");
    EXPECT_ERROR("wait_reload -1\n", 1, "a number from 0 to 3600, found '-1'");
    EXPECT_ERROR("wait_reload 1 2\n", 1, "expected the end of the line, found '2'");
    EXPECT_ERROR("expect_ok now\n", 1, "expect_ok: expected the end of the line, found 'now'");
    EXPECT_ERROR("quit 0\n", 1, "quit: expected the end of the line, found '0'");
    EXPECT_ERROR("shell\n", 1, "shell: expected a command");
    EXPECT_ERROR("shell   # only a comment\n", 1, "shell: expected a command");
    EXPECT_ERROR("sleep\n", 1, "sleep: expected SECONDS after 'sleep'");
    EXPECT_ERROR("sleep 5000\n", 1, "a number from 0 to 3600, found '5000'");
    /* case matters for event names: they are keywords */
    EXPECT_ERROR("Quit\n", 1, "unknown event 'Quit'");
    /* a long token is shown cut short */
    EXPECT_ERROR("key AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA\n", 1,
                 "unknown key 'AAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAAA...'");

    /* a NUL byte on line 3 */
    static const char nul[] = "wait_frames 1\nkey A\nkey B\0C\nquit\n";
    expect_error_at(__LINE__, nul, sizeof nul - 1, 3, "the line holds a NUL byte");

    /* over 1 MiB: refused at the line where the limit falls, nothing parsed */
    size_t big = LG_SCRIPT_MAX_BYTES + 100;
    char *text = malloc(big);
    if (text) {
        /* "wait_frames 1\n" is 14 bytes: the limit falls inside line 1048576 / 14 + 1 */
        for (size_t i = 0; i < big; i++)
            text[i] = "wait_frames 1\n"[i % 14];
        expect_error_at(__LINE__, text, big, LG_SCRIPT_MAX_BYTES / 14 + 1,
                        "the script is 1048676 bytes, over the limit of 1048576 bytes (1 MiB)");
        /* exactly 1 MiB of comments loads */
        memset(text, ' ', LG_SCRIPT_MAX_BYTES);
        text[0] = '#';
        text[LG_SCRIPT_MAX_BYTES - 1] = '\n';
        write_script(text, LG_SCRIPT_MAX_BYTES);
        lg_script s;
        char err[512];
        CHECKF(lg_script_load(g_path, &s, err, sizeof err) == 0 && s.n == 0, "%s", err);
        lg_script_free(&s);
        /* 100000 events load, 100001 do not: the error on the line of the one too many */
        size_t n = 0;
        for (unsigned i = 0; i < LG_SCRIPT_MAX_EVENTS + 1; i++)
            n += (size_t)sprintf(text + n, "%s\n", i % 2 ? "key A" : "quit");
        expect_error_at(__LINE__, text, n, LG_SCRIPT_MAX_EVENTS + 1,
                        "more than 100000 events; that is the limit of a script");
        write_script(text, n - 5); /* without the last "quit\n" */
        CHECKF(lg_script_load(g_path, &s, err, sizeof err) == 0 && s.n == LG_SCRIPT_MAX_EVENTS,
               "%s", err);
        lg_script_free(&s);
        free(text);
    }

    /* not there, a folder: "PATH: cannot read the script: why" */
    lg_script s;
    char err[512], missing[PATH_MAX + 32];
    snprintf(missing, sizeof missing, "%s/none.txt", g_dir);
    CHECK(lg_script_load(missing, &s, err, sizeof err) == -1);
    CHECKF(strncmp(err, missing, strlen(missing)) == 0 && strstr(err, ": cannot read the script: "),
           "%s", err);
    CHECK(lg_script_load(g_dir, &s, err, sizeof err) == -1);
    CHECKF(strstr(err, "cannot read the script") != NULL, "%s", err);
}

/* Issue 24's events: the animation clock and the window's size. */
static void test_clock_and_size(void)
{
    lg_script s;
    if (load("play\npause\ntime 1.25\ntime -5\ntime 1e300\nresize 200 120\nresize 0 0\n", &s) !=
        0) {
        check_failures++;
        return;
    }
    CHECKF(s.n == 7, "%u events", s.n);
    if (s.n == 7) {
        const lg_sevent *e = s.ev;
        CHECK(e[0].kind == LG_SEV_PLAY && e[1].kind == LG_SEV_PAUSE);
        CHECK(e[2].kind == LG_SEV_TIME && e[2].a == 1.25);
        /* any finite time parses: the viewer clamps it (a stability case) */
        CHECK(e[3].kind == LG_SEV_TIME && e[3].a == -5);
        CHECK(e[4].kind == LG_SEV_TIME && e[4].a == 1e300);
        CHECK(e[5].kind == LG_SEV_RESIZE && e[5].a == 200 && e[5].b == 120 && e[5].line == 6);
        CHECK(e[6].kind == LG_SEV_RESIZE && e[6].a == 0 && e[6].b == 0);
    }
    lg_script_free(&s);
    EXPECT_ERROR("time\n", 1, "time: expected T (seconds) after 'time'");
    EXPECT_ERROR("time nan\n", 1, "found 'nan'");
    EXPECT_ERROR("time inf\n", 1, "found 'inf'");
    EXPECT_ERROR("time 1e400\n", 1, "found '1e400'");
    EXPECT_ERROR("time 1 2\n", 1, "time: expected the end of the line, found '2'");
    EXPECT_ERROR("play now\n", 1, "play: expected the end of the line, found 'now'");
    EXPECT_ERROR("pause 1\n", 1, "pause: expected the end of the line, found '1'");
    EXPECT_ERROR("resize 200\n", 1, "resize: expected H (window height) after 'resize'");
    EXPECT_ERROR("resize -1 10\n", 1, "a whole number from 0 to 16384, found '-1'");
    EXPECT_ERROR("resize 10 20000\n", 1, "a whole number from 0 to 16384, found '20000'");
    EXPECT_ERROR("resize 10.5 20\n", 1, "found '10.5'");
    EXPECT_ERROR("resize 10 20 30\n", 1, "resize: expected the end of the line, found '30'");
}

int main(void)
{
    char tmpl[] = "/tmp/lg-script-test-XXXXXX";
    if (!mkdtemp(tmpl) || !realpath(tmpl, g_dir)) {
        perror("mkdtemp");
        return 1;
    }
    test_events();
    test_keys();
    test_errors();
    test_clock_and_size();
    unlink(g_path);
    rmdir(g_dir);
    return check_report("viewer_script");
}
