/* host/viewer/clock.c: the animation clock (play, pause, scrub: the time every frame passes
 * to the nodes as lg_frame.time) and the window's framebuffer size as GLFW reports it
 * (docs/viewer.md, "Animation" and "Window size"). The keys (input.c), the script's events
 * (script_run.c) and the frame loop (loop.c, which applies a settled size) call these;
 * they call only the status line (load.c).
 */
#include "viewer/state.h"

#include <math.h>

/* ---- the animation clock --------------------------------------------------------------------- */

/* The time is the viewer's, not the frame index's: a paused or scrubbed graph gets the
 * time it shows, and the nodes that depend on it (per frame, as the planner says) see it as
 * lg_frame.time. A time outside [0, LG_VIEWER_MAX_TIME] is clamped: before 0 the graph's
 * time does not exist, and beyond 10^6 s a step of dt would no longer show in a float. */
static double clamp_time(double t)
{
    return t < 0 ? 0 : t > LG_VIEWER_MAX_TIME ? LG_VIEWER_MAX_TIME : t;
}

void lg_viewer_advance_time(viewer *v)
{
    if (!v->paused)
        v->time = clamp_time(v->time + v->opts.dt);
}

void lg_viewer_play(viewer *v, bool play)
{
    v->paused = !play;
    lg_viewer_status(v, false, "%s at %.3f s", play ? "playing" : "paused", v->time);
}

void lg_viewer_set_time(viewer *v, double t)
{
    if (!isfinite(t)) {
        lg_viewer_status(v, true, "time %g refused: not a finite number of seconds", t);
        return;
    }
    v->time = clamp_time(t);
    if (v->time != t)
        lg_viewer_status(v, false, "time %.3f s (%g clamped to [0, %g])", v->time, t,
                         LG_VIEWER_MAX_TIME);
    else
        lg_viewer_status(v, false, "time %.3f s", v->time);
}

void lg_viewer_step_time(viewer *v, int frames)
{
    v->paused = true;
    v->time = clamp_time(v->time + frames * v->opts.dt);
    lg_viewer_status(v, false, "paused at %.3f s (stepped %+d frame%s)", v->time, frames,
                     frames == 1 || frames == -1 ? "" : "s");
}

/* ---- the window's size ----------------------------------------------------------------------- */

void lg_viewer_framebuffer_resized(viewer *v, int w, int h)
{
    v->fb_w = w;
    v->fb_h = h;
    /* minimised (X and Windows report 0 x 0): keep the render, draw nothing */
    v->minimised = w <= 0 || h <= 0;
    v->resize_pending = !v->minimised &&
                        ((uint32_t)w != v->opts.width || (uint32_t)h != v->opts.height);
    v->resize_at = lg_mono_now();
    v->resize_frame = v->frame;
}
