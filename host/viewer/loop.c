/* host/viewer/loop.c: the frame loop. One thread, one loop; each turn of it is a frame:
 *
 *   1. events: the window's (GLFW callbacks, input.c), or the --script's next lines
 *      (script_run.c), which call the same handlers;
 *   2. reloads: the watcher's changes (reload.c: graph files, plugin .so files, shaders in a
 *      development build, which run the build first) are applied between frames, never
 *      while one is in flight;
 *   3. the frame: lg_exec_frame runs what must run (per-frame nodes, nodes never run, nodes
 *      that read the scene when the camera moved, and what reads them);
 *   4. the picture: the shown image through lg_vdisplay (exposure, sRGB as the PNG writer
 *      encodes), the overlay (timings, plan, selection, status), swap.
 */
#include "viewer/state.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the overlay ----------------------------------------------------------------------------- */

static void overlay_text(viewer *v, lg_str *s)
{
    const loaded *l = &v->cur;
    float sx = 1, sy = 1;
    glfwGetWindowContentScale(v->win, &sx, &sy);
    lg_str_addf(s, "%s  %ux%u  shown: %s  %.1f fps  frame %u\n", v->graph, v->opts.width,
                v->opts.height, l->shown_name ? l->shown_name : "-", v->fps, v->frame);
    lg_str_addf(s, "window: framebuffer %dx%d pixels, content scale %.2gx%.2g%s\n", v->fb_w,
                v->fb_h, (double)sx, (double)sy,
                v->minimised        ? " (minimised: nothing rendered)"
                : v->resize_pending ? " (resizing)"
                                    : "");
    int wn = 4, wt = 4;
    for (uint32_t i = 0; i < l->c->n_nodes; i++) {
        int a = (int)strlen(l->g->nodes[i].name), b = (int)strlen(l->c->nodes[i].type->name);
        wn = a > wn ? a : wn;
        wt = b > wt ? b : wt;
    }
    if (wn > 18)
        wn = 18;
    if (wt > 20)
        wt = 20;
    lg_str_addf(s, "%-*.*s %-*.*s %-9s %9s %9s %9s %9s\n", wn, wn, "node", wt, wt, "type", "runs",
                "last ms", "avg ms", "gpu last", "gpu avg");
    lg_str culled = { 0 }, gated = { 0 };
    for (uint32_t t = 0; t < l->c->n_nodes; t++) {
        const lg_pnode *n = l->ex->nodes[l->c->topo[t]];
        if (!n)
            continue;
        if (n->plan.state == LG_STATE_CULLED) {
            lg_str_addf(&culled, "%s%s", culled.len ? ", " : "", n->pub.name);
            continue;
        }
        if (n->plan.state == LG_STATE_GATED) {
            lg_str_addf(&gated, "%s%s (%s)", gated.len ? ", " : "", n->pub.name,
                        n->plan.reason ? n->plan.reason : "");
            continue;
        }
        /* GL timer queries read 0 for llvmpipe's compute work: "n/a", as --profile says */
        char gpu[32] = "-", gpu_avg[32] = "-";
        if (n->run.device == LG_DEVICE_GL || n->run.device == LG_DEVICE_CL) {
            bool na = n->prof.gpu_unmeasured && n->viewer.last_gpu_ms == 0;
            snprintf(gpu, sizeof gpu, na ? "n/a" : "%.2f", n->viewer.last_gpu_ms);
            snprintf(gpu_avg, sizeof gpu_avg, na ? "n/a" : "%.2f", n->viewer.avg_gpu_ms);
        }
        lg_str_addf(s, "%-*.*s %-*.*s %-9s %9.2f %9.2f %9s %9s%s\n", wn, wn, n->pub.name, wt, wt,
                    n->schema->name, n->run.per_frame ? "per-frame" : "once", n->viewer.last_cpu_ms,
                    n->viewer.avg_cpu_ms, gpu, gpu_avg,
                    n->viewer.ran_this_frame ? "" : (n->run.per_frame ? "" : "  (cached)"));
    }
    if (culled.len)
        lg_str_addf(s, "culled: %s\n", culled.s);
    if (gated.len)
        lg_str_addf(s, "gated: %s\n", gated.s);
    lg_str_free(&culled);
    lg_str_free(&gated);
    lg_str d = { 0 };
    lg_vparams_describe(v->vp, l->c, &d);
    lg_str_addf(s, "select: %s   [Tab node, Up/Down entry, Left/Right value, M method]\n",
                d.s ? d.s : "-");
    lg_str_free(&d);
    lg_str_addf(s, "time: %.3f s %s (dt %g s)   [Space play/pause, , . step, shift x10]\n", v->time,
                v->paused ? "paused" : "playing", v->opts.dt);
    lg_str_addf(s, "camera: %s   exposure %+.1f EV%s\n",
                !v->cam_on                    ? "the graph's"
                : v->vcam.mode == LG_VCAM_FLY ? "fly"
                                              : "orbit",
                (double)v->ev, l->display_referred ? " (display-referred)" : "");
}

static void update_title(viewer *v)
{
    char title[512];
    const char *st = v->status ? v->status : "";
    const char *nl = strchr(st, '\n');
    snprintf(title, sizeof title, "lightgraph view: %s | %.1f fps | %s%.*s", v->graph, v->fps,
             v->status_error ? "error: " : "", (int)(nl ? nl - st : (long)strlen(st)), st);
    glfwSetWindowTitle(v->win, title);
}

/* The overlay's text, then the status line below it, in red for an error. */
static void draw_overlay(viewer *v, int fw, int fh)
{
    lg_str s = { 0 };
    overlay_text(v, &s);
    static const float white[3] = { 0.92f, 0.92f, 0.92f }, red[3] = { 1.0f, 0.45f, 0.4f },
                       green[3] = { 0.6f, 1.0f, 0.6f };
    int cw, ch;
    lg_vdisplay_cell(v->disp, &cw, &ch);
    lg_vdisplay_draw_text(v->disp, 0, fw, fh, 4, 4, s.s ? s.s : "", white, 1);
    int lines = 0;
    for (const char *p = s.s; p && *p; p++)
        lines += *p == '\n';
    if (v->status)
        lg_vdisplay_draw_text(v->disp, 0, fw, fh, 4, 8 + (lines + 1) * ch, v->status,
                              v->status_error ? red : green, 1);
    lg_str_free(&s);
}

/* The script's pending screenshot_window, taken here, after drawing: a failure fails the
 * script as screenshot's does (it used to be printed while the script went on to exit 0). */
static void take_window_shot(viewer *v)
{
    char err[1024];
    if (lg_viewer_window_screenshot(v, v->window_shot, err, sizeof err))
        lg_viewer_script_fail(v, v->window_shot_ev, "screenshot_window %s: %s", v->window_shot,
                              err);
    else
        printf("lightgraph view: wrote %s\n", v->window_shot);
    free(v->window_shot);
    v->window_shot = NULL;
}

/* ---- the window's size ----------------------------------------------------------------------- */

/* The render size the framebuffer asks for: its pixels (on a HiDPI screen the framebuffer
 * is larger than the window's coordinates, and the render matches the pixels), at least
 * LG_VIEWER_MIN_SIZE a side, scaled down (keeping the aspect) to the pixel limit. */
static void render_size_for(int fw, int fh, uint32_t *w, uint32_t *h)
{
    double x = fw < LG_VIEWER_MIN_SIZE ? LG_VIEWER_MIN_SIZE : fw;
    double y = fh < LG_VIEWER_MIN_SIZE ? LG_VIEWER_MIN_SIZE : fh;
    double limit = (double)lg_image_max_pixels();
    if (x * y > limit) {
        double f = sqrt(limit / (x * y));
        x = floor(x * f);
        y = floor(y * f);
    }
    *w = (uint32_t)x;
    *h = (uint32_t)y;
}

/* A framebuffer size that has held long enough (a window's edge being dragged sends one
 * every few milliseconds, and a plan at each would stall the drag): the graph is planned
 * again at that size, adopting what does not depend on it (plan.c, adoptable). A failure
 * keeps the old size and its picture, scaled to the window. */
static void apply_resize(viewer *v)
{
    if (!v->resize_pending || v->minimised)
        return;
    bool settled = v->scripted ? v->frame >= v->resize_frame + LG_VIEWER_RESIZE_DEBOUNCE_FRAMES
                               : lg_mono_now() - v->resize_at >= LG_VIEWER_RESIZE_DEBOUNCE;
    if (!settled)
        return;
    v->resize_pending = false;
    uint32_t w, h, ow = v->opts.width, oh = v->opts.height;
    render_size_for(v->fb_w, v->fb_h, &w, &h);
    if (w == ow && h == oh)
        return;
    v->opts.width = w;
    v->opts.height = h;
    char *what = lg_xasprintf("render size %ux%u (the window's framebuffer is %dx%d)", w, h,
                              v->fb_w, v->fb_h);
    if (!lg_viewer_attempt(v, what, false)) {
        v->opts.width = ow;
        v->opts.height = oh;
    }
    free(what);
}

/* ---- the loop -------------------------------------------------------------------------------- */

static void present(viewer *v)
{
    const GladGLContext *gl = lg_gl_device_table(v->gl);
    int fw, fh;
    glfwGetFramebufferSize(v->win, &fw, &fh);
    uint32_t tex = 0, w = 0, h = 0;
    char err[1024];
    lg_gl_state_reset(gl);
    if (lg_viewer_shown_texture(v, &tex, &w, &h, err, sizeof err) == 0) {
        if (lg_vdisplay_draw_image(v->disp, 0, fw, fh, tex, w, h, exp2f(v->ev)))
            lg_hlog(LG_HWARN, "drawing the image failed");
    } else {
        lg_viewer_status(v, true, "%s", err);
        v->frame_failed = true;
    }
    if (v->overlay)
        draw_overlay(v, fw, fh);
    if (v->window_shot)
        take_window_shot(v);
    lg_gl_state_reset(gl);
    glfwSwapBuffers(v->win);
}

static void run_frame(viewer *v)
{
    if (v->frame_failed)
        return;
    free(v->last_error);
    v->last_error = NULL;
    v->cur.ex->viewer.has_time = true;
    v->cur.ex->viewer.time = v->time;
    if (lg_exec_frame(v->cur.ex, v->frame) != 0 || v->cur.ex->failed) {
        v->frame_failed = true;
        lg_viewer_status(v, true,
                         "a frame failed (fix the graph or the plugin; it is reloaded "
                         "on save):\n%s",
                         v->last_error ? v->last_error : "?");
        return;
    }
    lg_viewer_update_averages(v);
}

/* Nothing to run, nothing moving: the loop may wait for an event rather than spin. */
static bool idle(const viewer *v)
{
    /* minimised, nothing is drawn: wait for the window to come back, not spin */
    if (v->minimised && !v->scripted && !v->rebuild)
        return true;
    bool busy = v->scripted || v->anim.active || v->rebuild || v->resize_pending;
    for (uint32_t i = 0; !busy && i < v->cur.ex->n_nodes; i++)
        busy = v->cur.ex->nodes[i] && v->cur.ex->nodes[i]->run.per_frame &&
               v->cur.ex->nodes[i]->plan.state == LG_STATE_KEPT;
    for (int k = 0; !busy && k <= GLFW_KEY_LAST; k++)
        busy = v->held[k];
    return !busy;
}

int lg_viewer_loop(viewer *v)
{
    v->last_t = lg_mono_now();
    /* frame 0 ran in lg_viewer_load */
    for (;;) {
        glfwPollEvents();
        if (glfwWindowShouldClose(v->win))
            break;
        if (v->scripted)
            lg_viewer_script_step(v);
        if (v->quit)
            break;
        lg_viewer_poll_reloads(v);
        double now = lg_mono_now();
        double dt = v->scripted ? 1.0 / 30.0 : now - v->last_t;
        lg_viewer_fly_step(v, dt);
        apply_resize(v);
        if (!v->frame_done && !v->minimised)
            run_frame(v);
        v->frame_done = false;
        if (v->ev_auto_pending)
            lg_viewer_auto_exposure(v);
        if (!v->minimised)
            present(v);
        double ft = now - v->last_t;
        v->last_t = now;
        if (ft > 0)
            v->fps = v->fps == 0 ? 1.0 / ft : 0.9 * v->fps + 0.1 / ft;
        if (v->frame % 15 == 0)
            update_title(v);
        v->frame++;
        lg_viewer_advance_time(v);
        if (idle(v))
            glfwWaitEventsTimeout(0.1);
    }
    /* a script left unfinished (the window closed first) fails */
    if (v->expect_failed)
        return 1;
    if (v->scripted && v->pc < v->script->n && !v->quit)
        return 1;
    return v->exit_status;
}
