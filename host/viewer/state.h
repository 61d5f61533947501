/*
 * host/viewer/state.h: the viewer's state (one `viewer` per window, no globals) and the
 * functions its files share. Private to the viewer layer; viewer/viewer.h is its face.
 *
 * Who owns what:
 *   viewer.c      lg_viewer_run: the window, the GL device, start and the one teardown;
 *                 lg_hlog's error hook
 *   load.c        a change: parse, check, plan and run a graph, adopt it or keep the last
 *                 good one (lg_viewer_load, lg_viewer_attempt), and the status line
 *   picture.c     the shown image: its texture, auto exposure, screenshots
 *   input.c       keys, buttons, pointer and wheel (GLFW callbacks), and what they do:
 *                 camera, live parameters, method switch, screenshot key
 *   script_run.c  a --script's events, played through input.c's handlers
 *   reload.c      hot reload: watched graph files, plugin .so files, shaders and the
 *                 rebuild they start
 *   loop.c        the frame loop: events, reloads, the frame, the picture, the overlay
 *   clock.c       the animation clock (lg_frame.time) and the framebuffer's size
 * and, below them: camera.c, display.c, params.c, script.c, watch.c, rebuild.c.
 *
 * GLFW callbacks reach the viewer through glfwGetWindowUserPointer; the viewer sets no
 * signal handler.
 */
#ifndef LG_HOST_VIEWER_STATE_H
#define LG_HOST_VIEWER_STATE_H

#include "plan/plan.h"
#include "viewer/viewer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "viewer/camera.h"
#include "viewer/display.h"
#include "viewer/params.h"
#include "viewer/rebuild.h"
#include "viewer/script.h"
#include "viewer/watch.h"

/* One loaded graph: parsed, checked, planned, and what the window shows of it. */
typedef struct loaded {
    lg_graph *g;
    lg_checked *c;
    lg_exec *ex;
    lg_edge shown;         /* the image shown (node, port, part) */
    char *shown_name;      /* "tone.out" */
    bool display_referred; /* a tone mapper is at or upstream of the shown image */
    char **files;          /* the graph file and its includes, absolute */
    uint32_t n_files;
} loaded;

typedef struct pointer_anim { /* a scripted drag, one step a frame */
    bool active;
    int button, mods;
    double x0, y0, dx, dy;
    int step, steps;
} pointer_anim;

typedef struct viewer {
    /* arguments */
    const char *graph;
    const char *const *sets;
    int n_sets;
    char *show; /* --show NODE[.PORT], or a method switch's choice */
    lg_exec_opts opts;

    lg_registry reg;
    GLFWwindow *win;
    lg_gl_device *gl;
    lg_cl_dev *cl;
    uint32_t timer_query;
    lg_vdisplay *disp;
    uint32_t cpu_tex; /* the shown image when it is not a GL texture already */
    uint32_t cpu_tex_w, cpu_tex_h;

    loaded cur; /* the last good graph */
    uint32_t frame;
    bool frame_failed; /* the current plan failed a frame: shown as it was */
    bool frame_done;   /* a (re)load ran this frame already */

    /* live changes */
    lg_overrides ov;
    lg_vparams *vp;

    /* camera */
    lg_vcam vcam;
    bool cam_on; /* the viewer's camera overrides the graph's */
    lg_camera cam_out;
    uint64_t cam_gen;
    char *cam_scene_ref;            /* the node whose scene the camera node would read */
    float cam_bmin[3], cam_bmax[3]; /* that scene's bounds: the moved camera's clip planes */
    bool fly_speed_fast;

    /* display */
    float ev; /* exposure, stops */
    bool ev_auto_pending;
    bool overlay;
    double fps, last_t;

    /* status line: the last change and its outcome */
    char *status;
    bool status_error;
    uint64_t changes, changes_failed; /* counts of attempts (wait_reload, expect_*) */
    bool last_change_ok;
    char *last_error; /* errors lg_hlog printed during the attempt */

    /* reloads */
    lg_watch *watch;
    char *dev_build, *dev_shaders;
    bool can_rebuild;
    lg_rebuild *rebuild;
    bool rebuild_again;
    char **pending_plugins;
    uint32_t n_pending_plugins;
    bool pending_graph;

    /* input */
    bool held[GLFW_KEY_LAST + 1];
    bool buttons[8];
    double mx, my;
    int mods;
    pointer_anim anim;

    /* animation (docs/viewer.md "Animation"): the time every frame passes to the nodes as
     * lg_frame.time; while playing it advances by opts.dt per drawn frame */
    double time;
    bool paused;

    /* the window's size (docs/viewer.md "Window size"): the render follows the framebuffer,
     * once it has kept one size for a moment (a drag of the window's edge) */
    int fb_w, fb_h;        /* the framebuffer's pixels, as GLFW last said */
    bool resize_pending;   /* fb_w x fb_h differs from the render size */
    double resize_at;      /* when it last changed (lg_mono_now) */
    uint32_t resize_frame; /* ... and in which frame (a script counts frames) */
    bool minimised;        /* a 0 x 0 framebuffer: nothing is drawn or rendered */

    /* the method switched off (M past the last alternative): the consumers' inputs that
     * read the pass-through source instead, to be rewired when M switches a method on */
    struct method_off {
        bool on;
        char *node;    /* the alternative switched from (its name) */
        char *port;    /* the output its consumers read */
        char **inputs; /* "consumer.input", n_inputs of them */
        uint32_t n_inputs;
        bool was_shown; /* the node was the shown image: show its alternative again */
    } off;

    /* script */
    const lg_script *script; /* the caller's (lg_viewer_opts); NULL: interactive */
    bool scripted;
    uint32_t pc;
    uint32_t wait_until; /* frame number */
    bool wait_reload;
    uint64_t wait_reload_from;
    double wait_deadline;
    int hold_key;
    uint32_t hold_until;
    char *window_shot;               /* screenshot_window pending */
    const lg_sevent *window_shot_ev; /* its script event (for the failure's line) */
    bool expect_failed;
    bool quit;
    int exit_status;
} viewer;

/* ---- load.c: changes and the status line ----------------------------------------------------- */

/* The status line (window title, overlay) and stdout or stderr: "lightgraph view: ...". */
void lg_viewer_status(viewer *v, bool error, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Frees what a loaded graph owns and zeroes it; a zeroed one is fine. */
void lg_viewer_loaded_free(loaded *l);
/* Parses, checks, plans and runs one frame of the graph with every override; on success it
 * becomes the current graph (adopting the unchanged nodes of the old unless `full`), else
 * nothing changes and err says why. Returns 0, else -1, or when `initial` the exit status
 * (2 a bad graph, 1 a failed frame). */
int lg_viewer_load(viewer *v, bool initial, bool full, char *err, size_t errlen);
/* An attempt at a change (a parameter, a switch, a reload; `full`: nothing adopted, F5):
 * counted, its outcome on the status line. Returns whether it took. */
bool lg_viewer_attempt(viewer *v, const char *what, bool full);
/* A change that failed before or outside an attempt: counted as failed. */
void lg_viewer_change_failed(viewer *v);
/* A change that could not even be tried (a step past a range's end, no alternative, a
 * build that failed): counted as failed, `why` on the status line. */
void lg_viewer_refuse(viewer *v, const char *why);
/* The moving averages of the nodes that ran in this frame. */
void lg_viewer_update_averages(viewer *v);

/* ---- picture.c: the shown image -------------------------------------------------------------- */

/* The resource shown, and the node that may map it (its producer); mapper may be NULL. */
lg_resource *lg_viewer_shown_resource(const loaded *l, lg_pnode **mapper);
/* The texture the display draws from: the shown image's own GL texture when the display
 * can sample it, else a CPU copy in the viewer's texture. Returns 0 or -1 with err. */
int lg_viewer_shown_texture(viewer *v, uint32_t *tex, uint32_t *w, uint32_t *h, char *err,
                            size_t errlen);
/* Sets v->ev so that a scene-referred image's log-average luminance lands at 0.18. */
void lg_viewer_auto_exposure(viewer *v);
/* Writes the shown image: .png as displayed (exposure, sRGB), .exr linear (float). */
int lg_viewer_screenshot(viewer *v, const char *path, char *err, size_t errlen);
/* Writes the window's pixels as shown; call after drawing, before the swap. */
int lg_viewer_window_screenshot(viewer *v, const char *path, char *err, size_t errlen);

/* ---- input.c: events and what they do -------------------------------------------------------- */

/* The handlers of GLFW's events, which the script calls too (GLFW_PRESS, ...). */
void lg_viewer_key(viewer *v, int key, int mods, int action);
void lg_viewer_button(viewer *v, int button, int action, int mods);
void lg_viewer_cursor(viewer *v, double x, double y);
void lg_viewer_scroll(viewer *v, double d);
/* Fly mode: the held movement keys move the camera by dt seconds. */
void lg_viewer_fly_step(viewer *v, double dt);
/* A live NODE.PARAM=VALUE: kept as an override when the change takes. */
void lg_viewer_apply_assignment(viewer *v, const char *a);
/* Installs the window's callbacks (the window's user pointer is v). */
void lg_viewer_input_attach(viewer *v);

/* ---- script_run.c: the --script -------------------------------------------------------------- */

/* Runs script events until one has to wait for frames; called once per frame. */
void lg_viewer_script_step(viewer *v);
/* "SCRIPT:LINE: message" on stderr; the script fails (exit status 1). */
void lg_viewer_script_fail(viewer *v, const lg_sevent *e, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* ---- reload.c: hot reload -------------------------------------------------------------------- */

/* Opens the watches (graph files, plugin folders, shaders of a development build); without
 * inotify the viewer runs with no hot reload (a warning). */
void lg_viewer_start_watching(viewer *v);
/* Watches the current graph's files (load.c, after each load: its includes may have
 * changed). */
void lg_viewer_watch_graph_files(viewer *v);
/* Collects the watcher's changes, follows a rebuild, and applies what is ready. */
void lg_viewer_poll_reloads(viewer *v);

/* ---- loop.c: the frame loop ------------------------------------------------------------------ */

/* Runs frames until the window closes or the viewer quits; returns the exit status. */
int lg_viewer_loop(viewer *v);
/* ---- clock.c: the animation clock and the framebuffer's size --------------------------------- */

/* The animation clock: play (true) or pause; a time to show (clamped to [0,
 * LG_VIEWER_MAX_TIME], a non-finite one refused); a step of `frames` frames of opts.dt,
 * which pauses. Each says what it did on the status line. */
#define LG_VIEWER_MAX_TIME 1e6
void lg_viewer_play(viewer *v, bool play);
void lg_viewer_set_time(viewer *v, double t);
void lg_viewer_step_time(viewer *v, int frames);
/* After a drawn frame: the clock advances by opts.dt unless paused (clamped). */
void lg_viewer_advance_time(viewer *v);
/* The framebuffer is now w x h pixels (GLFW's callback, or a script's resize): the render
 * follows once the size has held for LG_VIEWER_RESIZE_DEBOUNCE seconds (a script: frames). */
#define LG_VIEWER_RESIZE_DEBOUNCE 0.25
#define LG_VIEWER_RESIZE_DEBOUNCE_FRAMES 3
#define LG_VIEWER_MIN_SIZE 16
void lg_viewer_framebuffer_resized(viewer *v, int w, int h);

#endif
