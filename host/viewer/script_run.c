/* host/viewer/script_run.c: plays a --script (parsed by script.c, docs/viewer.md). Once a
 * frame, the events run in order until one has to wait: a key press and release, a set, a
 * scroll or a window screenshot wait one frame; wait_frames, hold and a drag (four steps, one
 * a frame) wait their frames; wait_reload waits for the next change or its deadline. Input
 * events go through input.c's handlers, as the window's do. A failed expectation, a failed
 * screenshot or shell command is "SCRIPT:LINE: why" on stderr and exit status 1.
 */
#include "viewer/state.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

void lg_viewer_script_fail(viewer *v, const lg_sevent *e, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lightgraph view: %s:%u: ", v->script->path, e->line);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    v->expect_failed = true;
    v->exit_status = 1;
}

/* Steps what an earlier event left running (a drag, a held key, frames to wait, a reload to
 * wait for). Returns true while the script must wait. */
static bool script_waiting(viewer *v)
{
    if (v->anim.active) {
        pointer_anim *a = &v->anim;
        a->step++;
        double x = a->x0 + a->dx * a->step / a->steps, y = a->y0 + a->dy * a->step / a->steps;
        lg_viewer_cursor(v, x, y);
        if (a->step >= a->steps) {
            lg_viewer_button(v, a->button, GLFW_RELEASE, a->mods);
            a->active = false;
        }
        return true;
    }
    if (v->hold_key >= 0) {
        if (v->frame < v->hold_until)
            return true;
        lg_viewer_key(v, v->hold_key, 0, GLFW_RELEASE);
        v->hold_key = -1;
    }
    if (v->frame < v->wait_until)
        return true;
    if (v->wait_reload) {
        if (v->changes == v->wait_reload_from && lg_mono_now() < v->wait_deadline)
            return true;
        if (v->changes == v->wait_reload_from) {
            lg_viewer_script_fail(v, &v->script->ev[v->pc - 1],
                                  "wait_reload: no reload within the time given");
            v->quit = true;
            return true;
        }
        v->wait_reload = false;
    }
    return false;
}

/* The event just run waits for the next frame. */
static bool next_frame(viewer *v)
{
    v->wait_until = v->frame + 1;
    return true;
}

/* A drag: the button pressed at its start (the window's centre unless `from`), the pointer
 * moved in four steps, one a frame, then released (script_waiting). */
static void drag_start(viewer *v, const lg_sevent *e)
{
    int w, h;
    glfwGetWindowSize(v->win, &w, &h);
    pointer_anim *a = &v->anim;
    a->active = true;
    a->button = e->button;
    a->mods = e->mods;
    a->x0 = e->has_from ? e->from_x : w / 2.0;
    a->y0 = e->has_from ? e->from_y : h / 2.0;
    a->dx = e->a;
    a->dy = e->b;
    a->step = 0;
    a->steps = 4;
    v->mx = a->x0;
    v->my = a->y0;
    lg_viewer_button(v, a->button, GLFW_PRESS, a->mods);
}

/* Runs one event. Returns true when the script waits before the next one. */
static bool script_event(viewer *v, const lg_sevent *e)
{
    char err[2048];
    const char *status = v->status ? v->status : "?";
    switch (e->kind) {
    case LG_SEV_WAIT_FRAMES: v->wait_until = v->frame + (uint32_t)e->a; return true;
    case LG_SEV_KEY:
        lg_viewer_key(v, e->key, e->mods, GLFW_PRESS);
        lg_viewer_key(v, e->key, e->mods, GLFW_RELEASE);
        return next_frame(v);
    case LG_SEV_HOLD:
        lg_viewer_key(v, e->key, e->mods, GLFW_PRESS);
        v->hold_key = e->key;
        v->hold_until = v->frame + (uint32_t)e->b;
        return true;
    case LG_SEV_DRAG: drag_start(v, e); return true;
    case LG_SEV_SCROLL: lg_viewer_scroll(v, e->a); return next_frame(v);
    case LG_SEV_SCREENSHOT:
        if (lg_viewer_screenshot(v, e->text, err, sizeof err))
            lg_viewer_script_fail(v, e, "screenshot %s: %s", e->text, err);
        else
            printf("lightgraph view: wrote %s\n", e->text);
        return false;
    case LG_SEV_SCREENSHOT_WINDOW:
        /* taken after the next frame is drawn (loop.c) */
        free(v->window_shot);
        v->window_shot = lg_xstrdup(e->text);
        v->window_shot_ev = e;
        return next_frame(v);
    case LG_SEV_SET: lg_viewer_apply_assignment(v, e->text); return next_frame(v);
    case LG_SEV_WAIT_RELOAD:
        v->wait_reload = true;
        v->wait_reload_from = v->changes;
        v->wait_deadline = lg_mono_now() + (e->a > 0 ? e->a : 60);
        return true;
    case LG_SEV_EXPECT_OK:
        if (!v->last_change_ok)
            lg_viewer_script_fail(v, e, "expect_ok: the last change failed: %s", status);
        return false;
    case LG_SEV_EXPECT_ERROR:
        if (v->last_change_ok)
            lg_viewer_script_fail(v, e, "expect_error: the last change succeeded (%s)", status);
        else if (e->text && e->text[0] && (!v->status || !strstr(v->status, e->text)))
            lg_viewer_script_fail(v, e, "expect_error: the error does not mention '%s': %s",
                                  e->text, status);
        return false;
    case LG_SEV_SHELL: {
        char *cmd = lg_xasprintf("cd '%s' && %s", v->script->dir, e->text);
        fflush(NULL);
        int st = system(cmd);
        free(cmd);
        if (st != 0) {
            lg_viewer_script_fail(v, e, "shell: '%s' exited with status %d", e->text,
                                  WIFEXITED(st) ? WEXITSTATUS(st) : -1);
            v->quit = true;
            return true;
        }
        return false;
    }
    case LG_SEV_SLEEP: usleep((useconds_t)(e->a * 1e6)); return false;
    case LG_SEV_QUIT: v->quit = true; return true;
    case LG_SEV_PLAY:
    case LG_SEV_PAUSE: lg_viewer_play(v, e->kind == LG_SEV_PLAY); return false;
    case LG_SEV_TIME: lg_viewer_set_time(v, e->a); return false;
    case LG_SEV_RESIZE:
        if (e->a == 0 || e->b == 0) {
            lg_viewer_framebuffer_resized(v, 0, 0);
        } else {
            glfwSetWindowSize(v->win, (int)e->a, (int)e->b);
            if (v->minimised) { /* back from a 0 x 0: the callback says the new size */
                int fw, fh;
                glfwGetFramebufferSize(v->win, &fw, &fh);
                lg_viewer_framebuffer_resized(v, fw, fh);
            }
        }
        return next_frame(v);
    }
    return false;
}

void lg_viewer_script_step(viewer *v)
{
    if (script_waiting(v))
        return;
    /* a script that ends without quit leaves the window to the user */
    while (v->pc < v->script->n && !v->quit)
        if (script_event(v, &v->script->ev[v->pc++]))
            return;
}
