/* Execution: frames, timing, output files, teardown. */
#include "exec/exec.h"

#include "lightgraph/kinds.h"

#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "lightgraph/image.h"
#include "exec/outputs.h"
#include "base/pattern.h"

static void read_cl_events(lg_pnode *n)
{
    if (!n->run.n_cl_events)
        return;
    clWaitForEvents(n->run.n_cl_events, (const cl_event *)n->run.cl_events);
    for (uint32_t i = 0; i < n->run.n_cl_events; i++) {
        cl_ulong start = 0, end = 0;
        cl_event ev = (cl_event)n->run.cl_events[i];
        if (clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof start, &start, NULL) ==
                CL_SUCCESS &&
            clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof end, &end, NULL) ==
                CL_SUCCESS &&
            end >= start)
            n->prof.gpu_ms += (double)(end - start) * 1e-6;
        clReleaseEvent(ev);
    }
    n->run.n_cl_events = 0;
}

/* ---- the crash guard (ex->guard) ------------------------------------------------------------- */

static sigjmp_buf guard_jmp;
static volatile sig_atomic_t guard_active, guard_sig, guard_exit;
static pthread_t guard_thread;
static const int guard_signals[] = { SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT };
#define N_GUARD_SIGNALS (sizeof guard_signals / sizeof guard_signals[0])
/* LG_GUARD_EXIT: what the handler writes, prepared before the call (lg_node_call), since
 * nothing but write(2) can be trusted in the handler: the head names the node, its type,
 * its plugin and the callback, the signal's number and name follow, then the tail. */
static char guard_head[PATH_MAX + 2048]; /* a plugin path of up to PATH_MAX, names */
static size_t guard_head_len;
/* the main thread's stack for the handler, so that a plugin that overflowed its stack is
 * reported too (pool threads have none: such a crash there stays a crash) */
static char guard_stack[64 * 1024];

/* The signal's description without strsignal(), which is not async-signal-safe. */
static const char *guard_signal_text(int sig)
{
    switch (sig) {
    case SIGSEGV: return "SIGSEGV, segmentation fault";
    case SIGBUS: return "SIGBUS, bus error";
    case SIGFPE: return "SIGFPE, arithmetic exception";
    case SIGILL: return "SIGILL, illegal instruction";
    case SIGABRT: return "SIGABRT, aborted";
    default: return "?";
    }
}

static void guard_write(const char *s, size_t n)
{
    while (n > 0) {
        ssize_t w = write(2, s, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return;
        s += w;
        n -= (size_t)w;
    }
}

/* LG_GUARD_EXIT: the prepared message, the signal, every temporary removed, and the
 * process ends with LG_EXIT_CRASH. Only async-signal-safe calls (write, unlink, _exit). */
static void guard_die(int sig)
{
    char num[16];
    size_t k = sizeof num;
    unsigned v = (unsigned)sig;
    do
        num[--k] = (char)('0' + v % 10);
    while ((v /= 10) && k > 0);
    static const char tail[] = "); the run is stopped and no output file is written (exit "
                               "status 3)\n";
    _Static_assert(LG_EXIT_CRASH == 3, "the message above names the exit status");
    guard_write(guard_head, guard_head_len);
    guard_write(num + k, sizeof num - k);
    guard_write(", ", 2);
    const char *name = guard_signal_text(sig);
    guard_write(name, strlen(name));
    guard_write(tail, sizeof tail - 1);
    lg_temp_remove_all();
    _exit(LG_EXIT_CRASH);
}

static void guard_handler(int sig)
{
    /* LG_GUARD_EXIT: a crash on any thread while the callback runs is the node's (a pool
     * thread running its lg_parallel_for body, a driver thread it started) */
    if (guard_active && guard_exit)
        guard_die(sig);
    /* LG_GUARD_RECOVER: only the thread that made the call can jump back to it: a crash on
     * a pool thread (lg_parallel_for) stays a crash */
    if (guard_active && pthread_equal(pthread_self(), guard_thread)) {
        guard_active = 0;
        guard_sig = sig;
        siglongjmp(guard_jmp, 1);
    }
    signal(sig, SIG_DFL);
    raise(sig);
}

int lg_guard_call(lg_guard_mode mode, void (*fn)(void *ctx), void *ctx)
{
    if (mode == LG_GUARD_NONE) {
        fn(ctx);
        return 0;
    }
    /* the handlers are installed only around the call: elsewhere a crash stays a crash
     * (and a sanitizer's report stays the sanitizer's) */
    struct sigaction sa, old[N_GUARD_SIGNALS];
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = guard_handler;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_NODEFER;
    stack_t alt, old_alt;
    bool on_alt = false;
    if (mode == LG_GUARD_EXIT) {
        memset(&alt, 0, sizeof alt);
        alt.ss_sp = guard_stack;
        alt.ss_size = sizeof guard_stack;
        on_alt = sigaltstack(&alt, &old_alt) == 0;
        if (on_alt)
            sa.sa_flags |= SA_ONSTACK;
    }
    for (size_t i = 0; i < N_GUARD_SIGNALS; i++)
        sigaction(guard_signals[i], &sa, &old[i]);
    guard_sig = 0;
    guard_exit = mode == LG_GUARD_EXIT;
    guard_thread = pthread_self();
    if (sigsetjmp(guard_jmp, 1) == 0) {
        guard_active = 1;
        fn(ctx);
        guard_active = 0;
    }
    for (size_t i = 0; i < N_GUARD_SIGNALS; i++)
        sigaction(guard_signals[i], &old[i], NULL);
    if (on_alt)
        sigaltstack(&old_alt, NULL);
    return (int)guard_sig;
}

int lg_node_call(lg_exec *ex, lg_pnode *n, const char *what, void (*fn)(void *ctx), void *ctx)
{
    if (ex->guard == LG_GUARD_EXIT) {
        /* the description the handler writes, set before every callback: formatting it in
         * the handler would call what a crashed process cannot trust (malloc, stdio) */
        int len = snprintf(guard_head, sizeof guard_head,
                           "lightgraph: error: node '%s' (%s): crashed in %s() (plugin %s, %s; "
                           "signal ",
                           n->pub.name, n->schema ? n->schema->name : "?", what,
                           n->plugin ? n->plugin->name : "?", n->plugin ? n->plugin->path : "?");
        guard_head_len = len < 0                           ? 0
                         : (size_t)len < sizeof guard_head ? (size_t)len
                                                           : sizeof guard_head - 1;
        /* what this process printed so far comes before the message */
        fflush(stdout);
        fflush(stderr);
    }
    int sig = lg_guard_call(ex->guard, fn, ctx);
    if (sig) {
        n->run.crashed = true;
        n->plugin->poisoned = true;
        lg_node_errorf(n, "crashed in %s() (signal %d, %s); plugin %s", what, sig, strsignal(sig),
                       n->plugin->path);
    }
    return sig;
}

typedef struct exec_call {
    lg_pnode *n;
    const lg_frame *frame;
    int rc;
} exec_call;

static void call_execute(void *p)
{
    exec_call *c = p;
    c->rc = c->n->pub.type->execute(&c->n->pub, c->frame);
}

static int run_node(lg_exec *ex, lg_pnode *n, const lg_frame *frame)
{
    const GladGLContext *gl = ex->dev.gl ? lg_gl_device_table(ex->dev.gl) : NULL;
    bool timed_gl = gl && n->run.device == LG_DEVICE_GL;
    if (gl)
        lg_gl_state_reset(gl);
    if (timed_gl)
        gl->BeginQuery(GL_TIME_ELAPSED, ex->dev.gl_timer_query);
    double t0 = lg_mono_now();
    double gpu0 = n->prof.gpu_ms;
    exec_call call = { n, frame, 0 };
    int sig = lg_node_call(ex, n, "execute", call_execute, &call);
    int rc = call.rc;
    if (sig) {
        if (timed_gl)
            gl->EndQuery(GL_TIME_ELAPSED);
        return -1;
    }
    if (timed_gl) {
        gl->EndQuery(GL_TIME_ELAPSED);
        /* waits for the node's GL work: the wall time then includes it, as a user timing
         * the frame would see */
        gl->Finish();
        GLuint64 ns = 0;
        gl->GetQueryObjectui64v(ex->dev.gl_timer_query, GL_QUERY_RESULT, &ns);
        double q = (double)ns * 1e-6, wall = (lg_mono_now() - t0) * 1e3;
        /* llvmpipe's GL_TIME_ELAPSED counts rasteriser work only (compute dispatches read
         * 0) and may return an absolute timestamp: a value outside (0, wall] is not a
         * measurement, and the profile says n/a rather than print it */
        if (q > 0 && q <= wall)
            n->prof.gpu_ms += q;
        else
            n->prof.gpu_unmeasured = true;
    }
    if (ex->dev.cl && n->run.device == LG_DEVICE_CL)
        clFinish((cl_command_queue)lg_cl_device_queue(ex->dev.cl));
    read_cl_events(n);
    double ms = (lg_mono_now() - t0) * 1e3;
    n->prof.cpu_ms += ms;
    n->viewer.last_cpu_ms = ms;
    n->viewer.last_gpu_ms = n->prof.gpu_ms - gpu0;
    n->viewer.last_frame = frame->index;
    n->viewer.ran_this_frame = true;
    n->viewer.camera_gen = ex->viewer.camera_gen;
    n->viewer.time = frame->time;
    if (n->prof.runs == 0)
        n->prof.first_cpu_ms = n->prof.min_cpu_ms = ms;
    else if (ms < n->prof.min_cpu_ms)
        n->prof.min_cpu_ms = ms;
    n->prof.runs++;
    n->run.ran = true;
    if (rc == 0 && gl)
        rc = ex->api.gl_check(&n->pub, "executing");
#ifdef LG_DEBUG_CHECKS
    if (rc == 0 && gl) {
        char err[1024];
        if (lg_gl_state_check(gl, err, sizeof err)) {
            lg_node_errorf(n, "left GL state behind (see docs/sdk.md, the GL state contract): %s",
                           err);
            rc = LG_ERR_DEVICE;
        }
    }
#endif
    if (rc == 0 && ex->failed)
        rc = LG_ERR_INVALID;
    if (rc != 0 && !ex->failed)
        lg_node_errorf(n, "execute() failed without saying why (code %d)", rc);
    return rc;
}

/* One output into the temporary of `path`. */
static int write_output(lg_exec *ex, const lg_coutput *o, const char *path)
{
    int rc = 0;
    lg_pnode *n = ex->nodes[o->node];
    lg_resource *r = lg_edge_resource(ex, (lg_edge){ o->node, o->port, o->part });
    char err[1024];
    float *px = NULL;
    lg_image img = { 0, 0, NULL };
    /* SH coefficients: a text file, and only they (graph/check.c refuses the other
     * pairings before anything runs; -o and LG_KIND_ANY outputs meet them here) */
    bool sh = r && r->kind == LG_KIND_SH;
    bool txt = lg_path_has_ext(path, ".txt");
    if (sh != txt) {
        lg_hlog(LG_HERR, "output '%s' of node '%s' -> %s: %s", n->schema->outputs[o->port].name,
                n->pub.name, path,
                sh ? "SH coefficients are written as text: name the file .txt"
                   : "only SH coefficients are written as .txt (images and probes: .png, "
                     ".exr or .hdr)");
        return -1;
    }
    if (sh) {
        char *text = NULL;
        size_t len = 0;
        if (lg_resource_sh_text(ex, r, &text, &len, err, sizeof err) ||
            lg_outputs_write_data(ex->opts.outputs, path, text, len, err, sizeof err)) {
            lg_hlog(LG_HERR, "output '%s' of node '%s' -> %s: %s", n->schema->outputs[o->port].name,
                    n->pub.name, path, err);
            rc = -1;
        } else {
            lg_hlog(LG_HDEBUG,
                    "%s (SH coefficients, %zu bytes) written to its temporary "
                    "file",
                    path, len);
        }
        free(text);
        return rc;
    }
    /* a probe: its radiance laid out as a file (lat-long, angular, cross or strip) */
    bool probe = r && r->kind == LG_KIND_PROBE;
    if (probe && lg_image_format_from_path(path) == LG_FILE_PNG) {
        /* `render -o x.png` on a graph whose output is a probe */
        lg_hlog(LG_HERR,
                "output '%s' of node '%s' -> %s: a probe is HDR: write it as "
                ".exr or .hdr",
                n->schema->outputs[o->port].name, n->pub.name, path);
        return -1;
    }
    if (probe ? lg_resource_probe_file(ex, r, &img, err, sizeof err)
              : lg_resource_to_rgba32f(ex, r, &px, err, sizeof err)) {
        lg_hlog(LG_HERR, "output '%s' of node '%s' -> %s: %s", n->schema->outputs[o->port].name,
                n->pub.name, path, err);
        return -1;
    }
    if (!probe)
        img = (lg_image){ r->image.width, r->image.height, px };
    /* EXR: what `render --exr`, else the output statement, asks for; by default what
     * the resource holds: float for rgba32f, and for rgbe8 (whose range, to 1.7e38,
     * half cannot hold: a sun would become Inf), half otherwise */
    lg_image_write_opts wo;
    memset(&wo, 0, sizeof wo);
    int want = ex->opts.exr_pixel ? ex->opts.exr_pixel : o->g ? o->g->exr_pixel : 0;
    wo.exr_pixel = want == LG_OUT_EXR_HALF    ? LG_EXR_HALF
                   : want == LG_OUT_EXR_FLOAT ? LG_EXR_FLOAT
                   : (probe || r->image.format == LG_FORMAT_RGBA32F ||
                      r->image.format == LG_FORMAT_RGBE8)
                       ? LG_EXR_FLOAT
                       : LG_EXR_HALF;
    /* into the output's temporary: lg_render_file commits every output together once
     * all of them are written (outputs.h) */
    if (lg_outputs_write_image(ex->opts.outputs, path, &img, &wo, err, sizeof err)) {
        lg_hlog(LG_HERR, "%s", err);
        rc = -1;
    } else {
        lg_hlog(LG_HDEBUG, "%s (%ux%u) written to its temporary file", path, img.width, img.height);
    }
    if (probe)
        lg_image_free(&img);
    free(px);
    return rc;
}

/* Writes the outputs into their temporaries: after frame `frame` (>= 0) those whose file
 * name is a frame pattern (base/pattern.h), under that frame's name; with frame -1, after
 * the last frame, the others. */
static int write_outputs(lg_exec *ex, int64_t frame)
{
    const lg_checked *c = ex->checked;
    int rc = 0;
    for (uint32_t i = 0; i < c->n_outputs; i++) {
        const lg_coutput *o = &c->outputs[i];
        const char *given = ex->opts.output_override ? ex->opts.output_override : o->path;
        size_t at;
        bool pattern = lg_frame_pattern_scan(given, &at, NULL, 0) == 1;
        if (pattern != (frame >= 0))
            continue;
        char *frame_path = pattern ? lg_frame_pattern_name(given, (uint32_t)frame) : NULL;
        const char *path = pattern ? frame_path : given;
        rc |= write_output(ex, o, path);
        free(frame_path);
    }
    return rc;
}

/* --every-frame[=NODE,...]: does `n` run again although nothing it reads changed? */
bool lg_exec_runs_every_frame(const lg_exec *ex, const lg_pnode *n)
{
    if (!ex->opts.every_frame)
        return false;
    const char *list = ex->opts.every_frame_nodes;
    if (!list)
        return true;
    size_t len = strlen(n->pub.name);
    for (const char *p = list; *p;) {
        size_t k = strcspn(p, ",");
        if (k == len && strncmp(p, n->pub.name, len) == 0)
            return true;
        p += k;
        p += *p == ',';
    }
    return false;
}

int lg_execute(lg_exec *ex)
{
    const lg_checked *c = ex->checked;
    double t0 = lg_mono_now();
    uint32_t frames = ex->opts.frames ? ex->opts.frames : 1;
    for (uint32_t f = 0; f < frames; f++) {
        lg_frame frame;
        memset(&frame, 0, sizeof frame);
        frame.index = f;
        frame.count = frames;
        frame.dt = ex->opts.dt;
        frame.time = f * ex->opts.dt;
        frame.width = ex->opts.width;
        frame.height = ex->opts.height;
        ex->frame = f;
        for (uint32_t t = 0; t < c->n_nodes; t++) {
            lg_pnode *n = ex->nodes[c->topo[t]];
            if (n->plan.state != LG_STATE_KEPT ||
                (n->run.ran && !n->run.per_frame && !lg_exec_runs_every_frame(ex, n)))
                continue;
            if (run_node(ex, n, &frame))
                return -1;
        }
        /* frame-pattern outputs: this frame's file, into its temporary (committed with
         * the others, all or nothing, by lg_render_file) */
        if (write_outputs(ex, f))
            return -1;
    }
    int rc = write_outputs(ex, -1);
    ex->t_total_ms = (lg_mono_now() - t0) * 1e3;
    return rc;
}

int lg_exec_frame(lg_exec *ex, uint32_t index)
{
    const lg_checked *c = ex->checked;
    lg_frame frame;
    memset(&frame, 0, sizeof frame);
    frame.index = index;
    frame.count = UINT32_MAX; /* open-ended: the viewer runs until it is closed */
    frame.dt = ex->opts.dt;
    frame.time = ex->viewer.has_time ? ex->viewer.time : index * ex->opts.dt;
    frame.width = ex->opts.width;
    frame.height = ex->opts.height;
    ex->frame = index;
    for (uint32_t i = 0; i < ex->n_nodes; i++)
        if (ex->nodes[i])
            ex->nodes[i]->viewer.ran_this_frame = false;
    for (uint32_t t = 0; t < c->n_nodes; t++) {
        lg_pnode *n = ex->nodes[c->topo[t]];
        if (!n || n->plan.state != LG_STATE_KEPT)
            continue;
        /* per frame for itself, or for an animation whose time moved; a node per frame
         * only through a per-frame input runs when that input ran (below) */
        bool own = n->run.per_frame_own || (n->schema->flags & LG_NODE_PER_FRAME);
        bool per_frame = n->run.per_frame &&
                         (own || (n->run.per_frame_why && n->viewer.time != frame.time));
        bool run = !n->run.ran || per_frame || lg_exec_runs_every_frame(ex, n) ||
                   (n->plan.reads_scene && n->viewer.camera_gen != ex->viewer.camera_gen);
        for (uint32_t k = 0; k < n->schema->n_inputs && !run; k++) {
            int32_t s = n->c->inputs[k].node;
            run = s >= 0 && ex->nodes[s] && ex->nodes[s]->viewer.ran_this_frame;
        }
        if (run && run_node(ex, n, &frame))
            return -1;
    }
    return 0;
}

static void call_destroy(void *p)
{
    lg_pnode *n = p;
    n->pub.type->destroy(&n->pub);
}

void lg_exec_free(lg_exec *ex)
{
    if (!ex->nodes)
        goto devices;
    /* destroy instances in reverse topological order, then resources, so that a plugin is
     * dlclose'd only after every object it made is gone. A slot is NULL for a node a newer
     * plan took over (lg_plan_commit) or gave back (lg_plan_rollback). A node that crashed
     * is not called again: its state is whatever the crash left. */
    for (uint32_t t = ex->checked->n_nodes; t-- > 0;) {
        lg_pnode *n = ex->nodes[ex->checked->topo[t]];
        if (!n)
            continue;
        if (n->run.created) {
            if (n->pub.type->destroy && !n->run.crashed)
                lg_node_call(ex, n, "destroy", call_destroy, n);
            if (!n->run.crashed)
                n->plugin->live_refs--;
        }
        for (uint32_t i = 0; i < n->run.n_cl_events; i++)
            clReleaseEvent((cl_event)n->run.cl_events[i]);
        free(n->run.cl_events);
    }
    for (uint32_t i = 0; i < ex->n_nodes; i++) {
        lg_pnode *n = ex->nodes[i];
        if (!n)
            continue;
        for (uint32_t o = 0; o < n->schema->n_outputs; o++)
            lg_resource_unref(ex, n->outputs[o]);
        free(n->outputs);
        free(n->plan.reason);
        free(n->plan.work_what);
        free(n);
    }
    free(ex->nodes);
    ex->nodes = NULL;
devices:
    if (!ex->dev.keep) {
        if (ex->dev.gl) {
            const GladGLContext *gl = lg_gl_device_table(ex->dev.gl);
            if (ex->dev.gl_timer_query)
                gl->DeleteQueries(1, &ex->dev.gl_timer_query);
        }
        lg_gl_device_destroy(&ex->dev.gl);
        lg_cl_device_destroy(&ex->dev.cl);
    }
    free(ex->dev.gl_error);
    free(ex->dev.cl_error);
    free(ex->cache.dir);
}
