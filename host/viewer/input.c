/* host/viewer/input.c: the window's events and what they do. GLFW's callbacks find the
 * viewer through the window's user pointer and hand the event to the same handlers a
 * --script calls (script_run.c); while a script runs, the window's own events are ignored.
 * Keys (docs/viewer.md): live parameters and the method switch (params.c), the camera
 * (camera.c: orbit, pan, zoom, fly), exposure, the overlay, F5, screenshots.
 */
#include "viewer/state.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lightgraph/kinds.h"

/* ---- the camera ------------------------------------------------------------------------------ */

/* The scene the renderers of the shown image read: the first kept node upstream of the
 * shown one (itself included) that reads a scene. */
static const lg_scene *graph_scene(viewer *v, const char **scene_node)
{
    const loaded *l = &v->cur;
    const lg_checked *c = l->c;
    for (uint32_t t = c->n_nodes; t-- > 0;) {
        const lg_pnode *n = l->ex->nodes[c->topo[t]];
        if (!n || n->plan.state != LG_STATE_KEPT)
            continue;
        for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
            lg_edge e = n->c->inputs[k];
            lg_resource *r = e.node >= 0 ? lg_edge_resource(l->ex, e) : NULL;
            if (r && r->kind == LG_KIND_SCENE && r->payload.data && !r->neutral) {
                if (scene_node)
                    *scene_node = l->g->nodes[e.node].name;
                return r->payload.data;
            }
        }
    }
    return NULL;
}

static void camera_changed(viewer *v)
{
    if (v->cam_on)
        lg_vcam_fit_clip(&v->vcam, v->cam_bmin, v->cam_bmax);
    lg_vcam_to_camera(&v->vcam, &v->cam_out);
    v->cam_gen++;
    if (v->cur.ex) {
        v->cur.ex->viewer.camera = v->cam_on ? &v->cam_out : NULL;
        v->cur.ex->viewer.camera_gen = v->cam_gen;
    }
}

/* The viewer's camera, taking over from the graph's on first use. false: no scene. */
static bool camera_take(viewer *v)
{
    if (v->cam_on)
        return true;
    const char *node = NULL;
    const lg_scene *s = graph_scene(v, &node);
    if (!s) {
        lg_viewer_status(v, true, "the shown image has no scene upstream: no camera to move");
        return false;
    }
    lg_camera cam;
    memset(&cam, 0, sizeof cam);
    if (s->n_cameras && s->cameras)
        cam = s->cameras[s->camera < s->n_cameras ? s->camera : 0];
    lg_vcam_init(&v->vcam, &cam, s->bounds_min, s->bounds_max);
    memcpy(v->cam_bmin, s->bounds_min, sizeof v->cam_bmin);
    memcpy(v->cam_bmax, s->bounds_max, sizeof v->cam_bmax);
    free(v->cam_scene_ref);
    v->cam_scene_ref = lg_xstrdup(node ? node : "scene");
    v->cam_on = true;
    return true;
}

static void camera_reset(viewer *v)
{
    v->cam_on = false;
    camera_changed(v);
    lg_viewer_status(v, false, "camera: the graph's");
}

static void camera_print(viewer *v)
{
    if (!camera_take(v))
        return;
    char *t = lg_vcam_node_text(&v->vcam, "cam", v->cam_scene_ref);
    printf("%s\n", t);
    fflush(stdout);
    free(t);
    lg_viewer_status(v, false, "camera printed on stdout as a camera node");
}

/* ---- live parameters ------------------------------------------------------------------------- */

/* The selection on stdout too: a terminal beside the window keeps the history. */
static void print_selection(viewer *v)
{
    lg_str d = { 0 };
    lg_vparams_describe(v->vp, v->cur.c, &d);
    printf("lightgraph view: select: %s\n", d.s ? d.s : "(nothing to select)");
    fflush(stdout);
    lg_str_free(&d);
}

void lg_viewer_apply_assignment(viewer *v, const char *a)
{
    lg_overrides_set(&v->ov, a);
    if (!lg_viewer_attempt(v, a, false))
        lg_overrides_remove_last(&v->ov);
}

static void step_selected(viewer *v, int dir)
{
    double scale = (v->mods & GLFW_MOD_SHIFT) ? 10 : (v->mods & GLFW_MOD_CONTROL) ? 0.1 : 1;
    char err[512];
    char *a = lg_vparams_step(v->vp, v->cur.g, v->cur.c, dir, scale, err, sizeof err);
    if (!a) {
        lg_viewer_refuse(v, err);
        return;
    }
    lg_viewer_apply_assignment(v, a);
    free(a);
}

static void free_strings(char **a, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        free(a[i]);
    free(a);
}

static void off_clear(viewer *v)
{
    free(v->off.node);
    free(v->off.port);
    free_strings(v->off.inputs, v->off.n_inputs);
    memset(&v->off, 0, sizeof v->off);
}

/* Undoes the last n overrides and gives the shown image back its earlier value (*old_show,
 * which passes to the viewer: *old_show becomes NULL). */
static void undo_sets(viewer *v, uint32_t n, char **old_show)
{
    for (uint32_t i = 0; i < n && v->ov.n > 0; i++)
        lg_overrides_remove_last(&v->ov);
    free(v->show);
    v->show = *old_show;
    *old_show = NULL;
}

/* Sets each "consumer.input" of keys to ref, and the shown image to show (unless NULL), as
 * one change `what`; undone when it fails. Returns whether it took. */
static bool rewire(viewer *v, char **keys, uint32_t n, const char *ref, const char *show,
                   const char *what)
{
    for (uint32_t i = 0; i < n; i++) {
        char *a = lg_xasprintf("%s=%s", keys[i], ref);
        lg_overrides_set(&v->ov, a);
        free(a);
    }
    char *old_show = v->show ? lg_xstrdup(v->show) : NULL;
    if (show) {
        free(v->show);
        v->show = lg_xstrdup(show);
    }
    bool ok = lg_viewer_attempt(v, what, false);
    if (!ok)
        undo_sets(v, n, &old_show);
    free(old_show);
    return ok;
}

/* M past the last alternative (shift+M before the first): the method is switched off, its
 * consumers read the input it draws over (lg_vparams_passthrough). Returns false, changing
 * nothing, when node x has no such input (two phong variants: they cycle as before). */
static bool method_off(viewer *v, int32_t x, char **as, uint32_t n, bool shown)
{
    const lg_checked *c = v->cur.c;
    int32_t port = shown ? (int32_t)v->cur.shown.port : -1;
    for (uint32_t k = 0; k < c->n_nodes; k++)
        for (uint32_t j = 0; c->nodes[k].type && j < c->nodes[k].type->n_inputs; j++) {
            lg_edge e = c->nodes[k].inputs[j];
            if (e.node != x)
                continue;
            if (e.part || (port >= 0 && (uint32_t)port != e.port))
                return false; /* consumers of several ports or parts: no single stand-in */
            port = (int32_t)e.port;
        }
    lg_edge src;
    if (port < 0 || !lg_vparams_passthrough(c, x, (uint32_t)port, &src))
        return false;
    char *ref = lg_vparams_edge_ref(c, src);
    if (!ref)
        return false;
    char **keys = lg_xcalloc(n + 1, sizeof *keys);
    for (uint32_t i = 0; i < n; i++)
        keys[i] = lg_xstrndup(as[i], strcspn(as[i], "="));
    char *what = lg_xasprintf("method: %s -> off (%s passed through)", c->nodes[x].g->name, ref);
    char *xname = lg_xstrdup(c->nodes[x].g->name);
    char *pname = lg_xstrdup(c->nodes[x].type->outputs[port].name);
    if (rewire(v, keys, n, ref, shown ? ref : NULL, what)) {
        off_clear(v);
        v->off = (struct method_off){ .on = true,
                                      .node = xname,
                                      .port = pname,
                                      .inputs = keys,
                                      .n_inputs = n,
                                      .was_shown = shown };
    } else {
        free(xname);
        free(pname);
        free_strings(keys, n);
    }
    free(what);
    free(ref);
    return true;
}

/* M after "off": the first alternative in file order (shift+M: the last) is switched on. */
static void method_on(viewer *v, int dir)
{
    const lg_checked *c = v->cur.c;
    int32_t x = -1;
    for (uint32_t k = 0; k < c->n_nodes && x < 0; k++)
        if (strcmp(c->nodes[k].g->name, v->off.node) == 0)
            x = (int32_t)k;
    if (x < 0) {
        char *why = lg_xasprintf("the method switched off, '%s', is no longer in the graph",
                                 v->off.node);
        off_clear(v);
        lg_viewer_refuse(v, why);
        free(why);
        return;
    }
    int32_t y = lg_vparams_alternative_end(c, x, dir);
    const lg_node_type *ty = c->nodes[y].type;
    uint32_t py = 0;
    while (py < ty->n_outputs && strcmp(ty->outputs[py].name, v->off.port) != 0)
        py++;
    char *ref = py < ty->n_outputs ? lg_vparams_edge_ref(c, (lg_edge){ .node = y, .port = py })
                                   : NULL;
    if (!ref) {
        char *why = lg_xasprintf("'%s' has no output '%s' to switch on", c->nodes[y].g->name,
                                 v->off.port);
        lg_viewer_refuse(v, why);
        free(why);
        return;
    }
    char *show = lg_xasprintf("%s.%s", c->nodes[y].g->name, v->off.port);
    char *what = lg_xasprintf("method: off -> %s (%s)", c->nodes[y].g->name, ty->name);
    if (rewire(v, v->off.inputs, v->off.n_inputs, ref, v->off.was_shown ? show : NULL, what))
        off_clear(v);
    free(what);
    free(show);
    free(ref);
}

static void switch_method(viewer *v, int dir)
{
    if (v->off.on) {
        method_on(v, dir);
        return;
    }
    char **as = NULL;
    uint32_t n = 0;
    int32_t from = -1, to = -1, new_shown = -1;
    char err[1024];
    if (!lg_vparams_switch_method(v->cur.g, v->cur.c, v->cur.shown.node, dir, &as, &n, &from, &to,
                                  &new_shown, err, sizeof err)) {
        lg_viewer_refuse(v, err);
        return;
    }
    /* past the end of the alternatives in file order: "off", where the method has an input
     * to pass through (else the cycle goes round, as before issue 24) */
    bool wraps = dir >= 0 ? to < from : to > from;
    if (wraps && method_off(v, from, as, n, new_shown >= 0)) {
        free_strings(as, n);
        return;
    }
    for (uint32_t i = 0; i < n; i++)
        lg_overrides_set(&v->ov, as[i]);
    char *old_show = v->show ? lg_xstrdup(v->show) : NULL;
    if (new_shown >= 0) {
        /* the output of the same name (alternatives share it) */
        const lg_node_type *tx = v->cur.c->nodes[v->cur.shown.node].type;
        free(v->show);
        v->show = lg_xasprintf("%s.%s", v->cur.g->nodes[new_shown].name,
                               tx->outputs[v->cur.shown.port].name);
    }
    char *what = lg_xasprintf("method: %s -> %s (%s)", v->cur.g->nodes[from].name,
                              v->cur.g->nodes[to].name, v->cur.c->nodes[to].type->name);
    if (!lg_viewer_attempt(v, what, false))
        undo_sets(v, n, &old_show); /* exactly the sets made here */
    free(old_show);
    free(what);
    for (uint32_t i = 0; i < n; i++)
        free(as[i]);
    free(as);
}

static void print_overrides(viewer *v)
{
    char *a = lg_overrides_args(&v->ov);
    printf("%s\n", a && a[0] ? a : "(no overrides)");
    fflush(stdout);
    free(a);
    lg_viewer_status(v, false, "overrides printed on stdout as --set arguments");
}

/* The screenshot key: PNG and EXR next to the graph, named with the time. */
static void screenshot_key(viewer *v)
{
    char *dir = lg_xstrdup(v->graph);
    char *slash = strrchr(dir, '/');
    char *stem = lg_xstrdup(slash ? slash + 1 : dir);
    char *dotp = strrchr(stem, '.');
    if (dotp && dotp != stem)
        *dotp = 0;
    if (slash)
        *slash = 0;
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    struct tm tm;
    localtime_r(&ts.tv_sec, &tm);
    char stamp[64];
    strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    char err[1024];
    for (int k = 0; k < 2; k++) {
        char *path = lg_xasprintf("%s/%s-%s-%03ld.%s", slash ? (dir[0] ? dir : "/") : ".", stem,
                                  stamp, ts.tv_nsec / 1000000, k ? "exr" : "png");
        if (lg_viewer_screenshot(v, path, err, sizeof err))
            lg_viewer_status(v, true, "screenshot: %s", err);
        else
            lg_viewer_status(v, false, "screenshot: %s", path);
        free(path);
    }
    free(stem);
    free(dir);
}

/* ---- input ----------------------------------------------------------------------------------- */

void lg_viewer_key(viewer *v, int key, int mods, int action)
{
    if (key < 0 || key > GLFW_KEY_LAST)
        return;
    v->mods = mods;
    if (action == GLFW_RELEASE) {
        v->held[key] = false;
        return;
    }
    if (action == GLFW_PRESS)
        v->held[key] = true;
    bool shift = mods & GLFW_MOD_SHIFT;
    switch (key) {
    case GLFW_KEY_ESCAPE: v->quit = true; break;
    case GLFW_KEY_TAB:
        lg_vparams_next_node(v->vp, shift ? -1 : 1);
        print_selection(v);
        break;
    case GLFW_KEY_UP:
        lg_vparams_next_entry(v->vp, -1);
        print_selection(v);
        break;
    case GLFW_KEY_DOWN:
        lg_vparams_next_entry(v->vp, 1);
        print_selection(v);
        break;
    case GLFW_KEY_HOME:
        lg_vparams_first_entry(v->vp);
        print_selection(v);
        break;
    case GLFW_KEY_LEFT: step_selected(v, -1); break;
    case GLFW_KEY_RIGHT: step_selected(v, 1); break;
    case GLFW_KEY_M: switch_method(v, shift ? -1 : 1); break;
    case GLFW_KEY_SPACE: lg_viewer_play(v, v->paused); break;
    case GLFW_KEY_COMMA: lg_viewer_step_time(v, shift ? -10 : -1); break;
    case GLFW_KEY_PERIOD: lg_viewer_step_time(v, shift ? 10 : 1); break;
    case GLFW_KEY_O: print_overrides(v); break;
    case GLFW_KEY_C: camera_print(v); break;
    case GLFW_KEY_R: camera_reset(v); break;
    case GLFW_KEY_F:
        if (camera_take(v)) {
            v->vcam.mode = v->vcam.mode == LG_VCAM_FLY ? LG_VCAM_ORBIT : LG_VCAM_FLY;
            lg_viewer_status(v, false, "camera: %s",
                             v->vcam.mode == LG_VCAM_FLY ? "fly (WASD, Q/E down/up, drag to look)"
                                                         : "orbit (drag, right-drag pans, wheel)");
        }
        break;
    case GLFW_KEY_H:
    case GLFW_KEY_F1: v->overlay = !v->overlay; break;
    case GLFW_KEY_LEFT_BRACKET: v->ev -= shift ? 2.0f : 0.5f; break;
    case GLFW_KEY_RIGHT_BRACKET: v->ev += shift ? 2.0f : 0.5f; break;
    case GLFW_KEY_BACKSLASH: lg_viewer_auto_exposure(v); break;
    case GLFW_KEY_F5:
        /* everything made again: also the files the graph's nodes read (an edited mesh) */
        lg_viewer_attempt(v, "everything reloaded (F5)", true);
        break;
    case GLFW_KEY_F12:
    case GLFW_KEY_P: screenshot_key(v); break;
    default: break;
    }
}

void lg_viewer_button(viewer *v, int button, int action, int mods)
{
    v->mods = mods;
    if (button >= 0 && button < 8)
        v->buttons[button] = action == GLFW_PRESS;
}

void lg_viewer_cursor(viewer *v, double x, double y)
{
    double dx = x - v->mx, dy = y - v->my;
    v->mx = x;
    v->my = y;
    bool left = v->buttons[GLFW_MOUSE_BUTTON_LEFT], right = v->buttons[GLFW_MOUSE_BUTTON_RIGHT],
         middle = v->buttons[GLFW_MOUSE_BUTTON_MIDDLE];
    if (!(left || right || middle) || (dx == 0 && dy == 0))
        return;
    if (!camera_take(v))
        return;
    int h = (int)v->opts.height;
    if (v->vcam.mode == LG_VCAM_FLY)
        lg_vcam_look(&v->vcam, dx, dy, h);
    else if (right || middle || (v->mods & GLFW_MOD_SHIFT))
        lg_vcam_pan(&v->vcam, dx, dy, h);
    else
        lg_vcam_orbit(&v->vcam, dx, dy, h);
    camera_changed(v);
}

void lg_viewer_scroll(viewer *v, double d)
{
    if (d == 0 || !camera_take(v))
        return;
    if (v->vcam.mode == LG_VCAM_FLY) {
        float f[3] = { 0, 0, (float)d };
        lg_vcam_move(&v->vcam, f, 0.1, 1.0);
    } else {
        lg_vcam_zoom(&v->vcam, d);
    }
    camera_changed(v);
}

/* Fly: the held movement keys move the camera by this frame's time. */
void lg_viewer_fly_step(viewer *v, double dt)
{
    if (!v->cam_on || v->vcam.mode != LG_VCAM_FLY)
        return;
    float m[3] = { (float)(v->held[GLFW_KEY_D] - v->held[GLFW_KEY_A]),
                   (float)(v->held[GLFW_KEY_E] - v->held[GLFW_KEY_Q]),
                   (float)(v->held[GLFW_KEY_W] - v->held[GLFW_KEY_S]) };
    if (m[0] == 0 && m[1] == 0 && m[2] == 0)
        return;
    bool fast = v->held[GLFW_KEY_LEFT_SHIFT] || v->held[GLFW_KEY_RIGHT_SHIFT];
    lg_vcam_move(&v->vcam, m, dt, fast ? 2.0 : 0.5);
    camera_changed(v);
}

/* The viewer of a window whose events it takes (NULL while a script drives it). */
static viewer *window_viewer(GLFWwindow *w)
{
    viewer *v = glfwGetWindowUserPointer(w);
    return v && !v->scripted ? v : NULL;
}

static void cb_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    viewer *v = window_viewer(w);
    if (v)
        lg_viewer_key(v, key, mods, action);
}

static void cb_button(GLFWwindow *w, int button, int action, int mods)
{
    viewer *v = window_viewer(w);
    if (v)
        lg_viewer_button(v, button, action, mods);
}

static void cb_cursor(GLFWwindow *w, double x, double y)
{
    viewer *v = window_viewer(w);
    if (v)
        lg_viewer_cursor(v, x, y);
}

static void cb_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    viewer *v = window_viewer(w);
    if (v)
        lg_viewer_scroll(v, dy);
}

/* Not a user's input: the window's size, also when a script resized it (script_run.c). */
static void cb_framebuffer(GLFWwindow *w, int width, int height)
{
    viewer *v = glfwGetWindowUserPointer(w);
    if (v)
        lg_viewer_framebuffer_resized(v, width, height);
}

void lg_viewer_input_attach(viewer *v)
{
    glfwSetFramebufferSizeCallback(v->win, cb_framebuffer);
    glfwSetKeyCallback(v->win, cb_key);
    glfwSetMouseButtonCallback(v->win, cb_button);
    glfwSetCursorPosCallback(v->win, cb_cursor);
    glfwSetScrollCallback(v->win, cb_scroll);
}
