/* host/viewer/viewer.c: lightgraph view's window (docs/viewer.md): lg_viewer_run opens the
 * window and its GL 4.5 context, wraps it as the GL device every plan of the viewer runs
 * on, loads the graph, hands over to the frame loop (loop.c), and tears everything down
 * in one place whatever step failed.
 *
 * The viewer's state is one `viewer` (state.h, which maps the layer's files), made here
 * and reached from GLFW's callbacks through the window's user pointer, and from lg_hlog's
 * error hook through the context current on the viewer's thread: no globals.
 */
#include "viewer/state.h"

#include <dlfcn.h>
#include <link.h>
#include <stdlib.h>
#include <string.h>

#include "exec/gl_backend.h"

/* lg_hlog's error hook takes no context: the viewer is the user pointer of the window whose
 * context is current on this thread. Only the viewer's own thread has it current, so an
 * error logged on another thread (a plugin's worker) is not taken for the attempt's, and
 * v->last_error is never written from two threads. */
static void error_hook(const char *message)
{
    GLFWwindow *w = glfwGetCurrentContext();
    viewer *v = w ? glfwGetWindowUserPointer(w) : NULL;
    if (!v)
        return;
    /* the first error of an attempt is the one that says why */
    if (!v->last_error)
        v->last_error = lg_xstrdup(message);
}

/* GLFW's last error on this thread, "DESCRIPTION (GLFW error 0xCODE)" in buf, or
 * `fallback` when there is none. */
static const char *glfw_error(char *buf, size_t len, const char *fallback)
{
    const char *desc = NULL;
    int code = glfwGetError(&desc);
    if (code == GLFW_NO_ERROR)
        return fallback;
    snprintf(buf, len, "%s (GLFW error 0x%x)", desc ? desc : "?", (unsigned)code);
    return buf;
}

/* Every shared object mapped now stays mapped until the process ends (RTLD_NODELETE): the
 * GL driver the window's context loaded (libGL, the DRI driver, llvmpipe) keeps threads and
 * exit handlers, as OSMesa does (gl_osmesa.c), and unloading it at glfwTerminate would also
 * hide its allocations from the leak checker behind "unknown module". */
static int pin_object(struct dl_phdr_info *info, size_t size, void *data)
{
    (void)size;
    (void)data;
    if (info->dlpi_name && info->dlpi_name[0]) {
        void *h = dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
        if (h)
            dlclose(h);
    }
    return 0;
}

static GLADapiproc glfw_load(void *state, const char *name)
{
    (void)state;
    return (GLADapiproc)glfwGetProcAddress(name);
}

static viewer *viewer_new(const lg_viewer_opts *o)
{
    viewer *v = lg_xcalloc(1, sizeof *v);
    v->graph = o->graph;
    v->sets = o->sets;
    v->n_sets = o->n_sets;
    v->show = o->show ? lg_xstrdup(o->show) : NULL;
    v->opts.width = o->width;
    v->opts.height = o->height;
    v->opts.frames = 1;
    v->opts.dt = o->dt;
    v->script = o->script;
    v->scripted = o->script != NULL;
    v->overlay = true;
    v->hold_key = -1;
    return v;
}

/* The window first: without a display there is nothing to do. Then its context as the GL
 * device, the display pass and the timer query. Returns 0, or 1 with the reason printed. */
static int open_window(viewer *v)
{
    char buf[512];
    if (!glfwInit()) {
        const char *d = getenv("DISPLAY");
        fprintf(stderr,
                "lightgraph view: no display (%s%s): %s; run it on a desktop or "
                "under xvfb-run\n",
                d && *d ? "DISPLAY=" : "DISPLAY is not set", d && *d ? d : "",
                glfw_error(buf, sizeof buf, "glfwInit failed"));
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_FALSE);
    v->win = glfwCreateWindow((int)v->opts.width, (int)v->opts.height, "lightgraph view", NULL,
                              NULL);
    if (!v->win) {
        fprintf(stderr, "lightgraph view: the display gives no OpenGL 4.5 core context: %s\n",
                glfw_error(buf, sizeof buf, "glfwCreateWindow failed"));
        return 1;
    }
    glfwSetWindowUserPointer(v->win, v);
    glfwMakeContextCurrent(v->win);
    glfwSwapInterval(v->scripted ? 0 : 1);
    dl_iterate_phdr(pin_object, NULL);
    char err[8192];
    lg_gl_backend be = {
        .label = "GLFW window", .load = glfw_load, .destroy = NULL, .state = NULL
    };
    int rc = lg_gl_device_wrap(&v->gl, &be, err, sizeof err);
    if (rc == 0 && lg_vdisplay_create(lg_gl_device_table(v->gl), &v->disp, err, sizeof err))
        rc = LG_ERR_DEVICE;
    if (rc) {
        fprintf(stderr, "lightgraph view: %s\n", err);
        return 1;
    }
    v->timer_query = lg_gl_device_timer_query(v->gl);
    lg_hlog(LG_HINFO, "GL device: %s", lg_gl_device_description(v->gl));
    return 0;
}

/* The plugins, the graph and its first frame. Returns 0, or the exit status with the
 * reason printed. */
static int open_graph(viewer *v)
{
    lg_hlog_error_hook = error_hook;
    v->vp = lg_vparams_new();
    v->reg.private_copies = true;
    lg_registry_scan(&v->reg);
    char err[8192];
    int rc = lg_viewer_load(v, true, true, err, sizeof err);
    if (rc) {
        fprintf(stderr, "lightgraph view: %s\n", err);
        return rc;
    }
    v->ev_auto_pending = true;
    lg_viewer_start_watching(v);
    lg_viewer_input_attach(v);
    glfwGetFramebufferSize(v->win, &v->fb_w, &v->fb_h);
    lg_viewer_status(v, false, "showing %s (%s)", v->cur.shown_name, v->graph);
    v->last_change_ok = true;
    return 0;
}

/* Frees whatever of the viewer was made, in the reverse order; the one teardown. */
static void viewer_free(viewer *v)
{
    lg_hlog_error_hook = NULL;
    lg_rebuild_free(&v->rebuild);
    lg_watch_close(&v->watch);
    lg_viewer_loaded_free(&v->cur);
    if (v->gl) {
        const GladGLContext *gl = lg_gl_device_table(v->gl);
        if (v->cpu_tex)
            gl->DeleteTextures(1, &v->cpu_tex);
        if (v->timer_query)
            gl->DeleteQueries(1, &v->timer_query);
    }
    lg_vdisplay_destroy(&v->disp);
    lg_gl_device_destroy(&v->gl);
    lg_cl_device_destroy(&v->cl);
    if (v->win)
        glfwDestroyWindow(v->win);
    glfwTerminate(); /* nothing when glfwInit failed */
    lg_registry_free(&v->reg);
    lg_vparams_free(v->vp);
    lg_overrides_free(&v->ov);
    for (uint32_t i = 0; i < v->n_pending_plugins; i++)
        free(v->pending_plugins[i]);
    free(v->pending_plugins);
    free(v->show);
    free(v->off.node);
    free(v->off.port);
    for (uint32_t i = 0; i < v->off.n_inputs; i++)
        free(v->off.inputs[i]);
    free(v->off.inputs);
    free(v->status);
    free(v->last_error);
    free(v->cam_scene_ref);
    free(v->dev_build);
    free(v->dev_shaders);
    free(v->window_shot);
    free(v);
}

int lg_viewer_run(const lg_viewer_opts *o)
{
    viewer *v = viewer_new(o);
    int rc = open_window(v);
    if (rc == 0)
        rc = open_graph(v);
    if (rc == 0)
        rc = lg_viewer_loop(v);
    viewer_free(v);
    return rc;
}
