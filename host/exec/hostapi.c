/* The lg_host_api table: what plugins call. Every entry checks its arguments at the
 * boundary and reports misuse with the node's name, since a plugin bug should read as
 * such and not as a host crash. */
#include "exec/exec.h"
#include "exec/outputs.h"
#include "exec/dist.h"
#include "base/pool.h"

#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "lightgraph/kinds.h"

static lg_pnode *P(lg_node *n)
{
    return (lg_pnode *)n;
}

static void api_log(lg_node *n, lg_log_level level, const char *fmt, va_list ap)
{
    int map[] = { LG_HERR, LG_HWARN, LG_HINFO, LG_HDEBUG };
    lg_node_vmsg(P(n), map[level <= LG_LOG_DEBUG ? level : LG_LOG_DEBUG], fmt, ap);
}

static void api_error(lg_node *n, const char *fmt, va_list ap)
{
    lg_node_vmsg(P(n), LG_HERR, fmt, ap);
    P(n)->ex->failed = true;
}

static void api_progress(lg_node *n, double fraction, const char *what)
{
    if (!isatty(2) || lg_verbosity < 0)
        return;
    if (fraction < 0)
        fraction = 0;
    if (fraction > 1)
        fraction = 1;
    fprintf(stderr, "\r%s: %s %5.1f%%%s", n->name, what ? what : "", fraction * 100.0,
            fraction >= 1 ? "\n" : "");
    fflush(stderr);
}

static double api_now(void)
{
    return lg_mono_now();
}

static const lg_value *api_param(lg_node *n, uint32_t index)
{
    lg_pnode *p = P(n);
    if (index >= p->schema->n_params) {
        lg_node_errorf(p, "asks for parameter #%u; its type declares %u", index,
                       p->schema->n_params);
        return NULL;
    }
    const lg_value *v = &p->c->params[index];
    /* without a set of outputs (lightgraph view) no node writes a file: the node reads ""
     * and so writes nothing, rather than rewriting it on every camera move */
    if (p->schema->params[index].role == LG_ROLE_OUTPUT_FILE && !p->ex->opts.outputs && v->s &&
        v->s[0]) {
        static const lg_value none = { .type = LG_PARAM_PATH, .s = "" };
        if (!p->viewer.output_file_noted)
            lg_node_warnf(p,
                          "%s '%s' is not written: the viewer writes no files but its "
                          "screenshots (lightgraph render writes it)",
                          p->schema->params[index].key, v->s);
        p->viewer.output_file_noted = true;
        return &none;
    }
    return v;
}

static int32_t api_param_index(lg_node *n, const char *key)
{
    lg_pnode *p = P(n);
    for (uint32_t i = 0; i < p->schema->n_params; i++)
        if (strcmp(p->schema->params[i].key, key) == 0)
            return (int32_t)i;
    lg_node_errorf(p,
                   "asks for parameter '%s', which its type does not declare (a plugin "
                   "bug: the value would have been a silent 0)",
                   key ? key : "");
#ifdef LG_DEBUG_ABORT
    abort(); /* -Ddebug_abort=true: stop where the bug is, for a debugger or a core dump */
#endif
    return -1;
}

static const lg_resource *api_input(lg_node *n, uint32_t port)
{
    lg_pnode *p = P(n);
    if (port >= p->schema->n_inputs) {
        lg_node_errorf(p, "asks for input #%u; its type declares %u", port, p->schema->n_inputs);
        return NULL;
    }
    return lg_edge_resource(p->ex, p->c->inputs[port]);
}

static lg_resource *api_output(lg_node *n, uint32_t port)
{
    lg_pnode *p = P(n);
    if (port >= p->schema->n_outputs) {
        lg_node_errorf(p, "asks for output #%u; its type declares %u", port, p->schema->n_outputs);
        return NULL;
    }
    return p->outputs[port];
}

/* The scene on r with the viewer's camera as its active camera (ex->viewer.camera), or r's own
 * payload. The copy is shallow (meshes, materials, lights are the producer's) but for the
 * cameras, and is made again when the camera changes. */
static const void *scene_payload(const lg_resource *cr)
{
    lg_resource *r = (lg_resource *)cr; /* the copy is the host's cache on the resource */
    lg_exec *ex = r->producer ? r->producer->ex : NULL;
    const lg_scene *s = r->payload.data;
    if (!ex || !ex->viewer.camera || r->kind != LG_KIND_SCENE || !s ||
        s->struct_size < offsetof(lg_scene, reserved))
        return r->payload.data;
    if (r->payload.view_scene && r->payload.view_gen == ex->viewer.camera_gen)
        return r->payload.view_scene;
    size_t size = s->struct_size > sizeof(lg_scene) ? s->struct_size : sizeof(lg_scene);
    uint32_t nc = s->n_cameras ? s->n_cameras : 1;
    uint32_t active = s->camera < s->n_cameras ? s->camera : 0;
    free(r->payload.view_scene);
    free(r->payload.view_cameras);
    lg_scene *copy = lg_xcalloc(1, size);
    memcpy(copy, s, s->struct_size);
    lg_camera *cams = lg_xcalloc(nc, sizeof *cams);
    if (s->n_cameras && s->cameras)
        memcpy(cams, s->cameras, s->n_cameras * sizeof *cams);
    const char *name = s->n_cameras && s->cameras ? s->cameras[active].name : "viewer";
    cams[active] = *ex->viewer.camera;
    cams[active].name = name;
    copy->cameras = cams;
    copy->n_cameras = nc;
    copy->camera = active;
    r->payload.view_scene = copy;
    r->payload.view_cameras = cams;
    r->payload.view_gen = ex->viewer.camera_gen;
    return copy;
}

static int api_describe(const lg_resource *r, lg_resource_info *out)
{
    memset(out, 0, sizeof *out);
    if (!r)
        return LG_ERR_INVALID;
    out->kind = r->kind;
    out->neutral = r->neutral;
    out->image = r->image;
    out->buffer = r->buffer;
    out->volume = r->volume;
    out->scene = r->has_features ? &r->features : NULL;
    out->payload = scene_payload(r);
    out->n_parts = r->neutral ? 0 : r->parts.n;
    if (r->parts.parent) {
        const lg_kind_desc *kd = lg_kind_describe(r->parts.parent->kind);
        out->part_of = r->parts.parent->kind;
        out->part_name = kd ? kd->parts[r->parts.index].name : NULL;
        out->part_type = r->parts.type;
    }
    return 0;
}

/* Outputs are declared once, in prepare, with the kind the port declares. */
static lg_resource *declare(lg_pnode *p, uint32_t port, lg_resource_kind kind, const char *what)
{
    if (p->run.prepared) {
        lg_node_errorf(p, "declares output #%u outside prepare()", port);
        return NULL;
    }
    if (port >= p->schema->n_outputs) {
        lg_node_errorf(p, "declares %s output #%u; its type declares %u outputs", what, port,
                       p->schema->n_outputs);
        return NULL;
    }
    lg_resource_kind want = p->schema->outputs[port].kind;
    if (want != LG_KIND_ANY && want != kind) {
        lg_node_errorf(p, "declares output '%s' as %s, but its port kind differs",
                       p->schema->outputs[port].name, what);
        return NULL;
    }
    if (p->outputs[port]) {
        lg_resource_unref(p->ex, p->outputs[port]);
        p->outputs[port] = NULL;
    }
    lg_resource *r = lg_resource_new(p, kind);
    p->outputs[port] = r;
    return r;
}

#define MAX_DIM 65536u

/* The bounds every image, volume and buffer a node declares obeys, checked here in
 * prepare() so that a size the parameters, --size or an input make impossible is refused
 * before any node runs (docs/images.md "Images a graph makes"): its texels, every face and
 * mip level counted, at most the pixel limit (--max-pixels, LIGHTGRAPH_MAX_PIXELS; the
 * limit of every read and of `check`), and its bytes within what this machine can give
 * (lg_memory_available, the bound of every read). texels 0: a buffer, bytes only. */
static int check_size_limits(lg_pnode *p, const char *what, const char *dims, uint64_t texels,
                             uint64_t bytes)
{
    uint64_t limit = lg_image_max_pixels();
    if (texels > limit)
        return lg_node_errorf(p,
                              "declares %s of %s: %llu pixels (every face and mip level "
                              "counted), over the limit of %llu pixels (raise it with "
                              "--max-pixels N or LIGHTGRAPH_MAX_PIXELS=N)",
                              what, dims, (unsigned long long)texels, (unsigned long long)limit),
               LG_ERR_INVALID;
    const char *bound;
    uint64_t avail = lg_memory_available(&bound);
    if (bytes > avail) {
        char need[32], have[32];
        lg_bytes_text(need, sizeof need, bytes);
        lg_bytes_text(have, sizeof have, avail);
        return lg_node_errorf(p,
                              "declares %s of %s: it needs %s (%llu bytes), more than the "
                              "%s (%llu bytes) of %s",
                              what, dims, need, (unsigned long long)bytes, have,
                              (unsigned long long)avail, bound),
               LG_ERR_NOMEM;
    }
    return 0;
}

/* Checks an image description; reports with `what` ("output 'out'", "part 'atlas'"). */
static int check_image_desc(lg_pnode *p, const lg_image_desc *d, const char *what)
{
    if (!d || d->width == 0 || d->height == 0 || d->width > MAX_DIM || d->height > MAX_DIM ||
        (uint64_t)d->width * d->height > (1ull << 28))
        return lg_node_errorf(p,
                              "declares %s of %ux%u (each side must be 1..%u, at most 2^28 "
                              "pixels)",
                              what, d ? d->width : 0, d ? d->height : 0, MAX_DIM),
               LG_ERR_INVALID;
    bool depth_only = (d->flags & LG_IMAGE_DEPTH_ONLY) != 0;
    if (!depth_only && (d->format < LG_FORMAT_RGBA32F || d->format > LG_FORMAT_RGBE8))
        return lg_node_errorf(p, "declares %s with unknown format %d", what, (int)d->format),
               LG_ERR_INVALID;
    if (d->flags & ~(uint32_t)(LG_IMAGE_DEPTH | LG_IMAGE_DEPTH_ONLY | LG_IMAGE_CUBE))
        return lg_node_errorf(p, "declares %s with unknown flags 0x%x", what, d->flags),
               LG_ERR_INVALID;
    uint32_t maxlev = 1, m = d->width > d->height ? d->width : d->height;
    while (m >>= 1)
        maxlev++;
    if (d->levels > maxlev)
        return lg_node_errorf(p, "declares %s of %ux%u with %u mip levels; at most %u exist", what,
                              d->width, d->height, d->levels, maxlev),
               LG_ERR_INVALID;
    if ((d->flags & LG_IMAGE_CUBE) && d->width != d->height)
        return lg_node_errorf(p, "declares %s as a cube map with %ux%u faces; faces are square",
                              what, d->width, d->height),
               LG_ERR_INVALID;
    if ((d->flags & (LG_IMAGE_DEPTH | LG_IMAGE_DEPTH_ONLY)) &&
        ((d->flags & LG_IMAGE_CUBE) || d->levels > 1))
        return lg_node_errorf(p,
                              "declares %s with a depth plane and a cube or mip levels; "
                              "depth planes are 2D with one level",
                              what),
               LG_ERR_INVALID;
    uint32_t levels = d->levels ? d->levels : 1;
    bool cube = (d->flags & LG_IMAGE_CUBE) != 0;
    uint64_t texels = depth_only ? (uint64_t)d->width * d->height
                                 : (uint64_t)lg_image_offset(d, levels, 0);
    uint64_t bytes = depth_only ? 0 : texels * lg_format_size(d->format);
    if (d->flags & (LG_IMAGE_DEPTH | LG_IMAGE_DEPTH_ONLY))
        bytes += (uint64_t)d->width * d->height * sizeof(float);
    char dims[96];
    snprintf(dims, sizeof dims, "%ux%u%s%s", d->width, d->height, cube ? " (a cube: 6 faces)" : "",
             depth_only ? " (depth)" : "");
    if (levels > 1) {
        size_t len = strlen(dims);
        snprintf(dims + len, sizeof dims - len, " with %u mip levels", levels);
    }
    return check_size_limits(p, what, dims, texels, bytes);
}

/* "output 'name'" for messages about output `port` (checked against the schema later). */
static const char *output_label(lg_pnode *p, uint32_t port, char *buf, size_t len)
{
    if (port < p->schema->n_outputs)
        snprintf(buf, len, "output '%s'", p->schema->outputs[port].name);
    else
        snprintf(buf, len, "output #%u", port);
    return buf;
}

static int api_declare_image(lg_node *n, uint32_t port, const lg_image_desc *d)
{
    lg_pnode *p = P(n);
    char what[96];
    int rc = check_image_desc(p, d, output_label(p, port, what, sizeof what));
    if (rc)
        return rc;
    lg_resource *r = declare(p, port, LG_KIND_IMAGE, "an image");
    if (!r)
        return LG_ERR_INVALID;
    r->image = *d;
    if (d->flags & LG_IMAGE_DEPTH_ONLY) {
        r->image.flags = LG_IMAGE_DEPTH_ONLY;
        r->image.format = LG_FORMAT_RGBA32F; /* unused; keeps the description valid */
    }
    return 0;
}

static int api_declare_buffer(lg_node *n, uint32_t port, const lg_buffer_desc *d)
{
    lg_pnode *p = P(n);
    if (!d || d->size > (1ull << 34))
        return lg_node_errorf(p, "declares a buffer of absurd size"), LG_ERR_INVALID;
    char what[96], dims[48];
    snprintf(dims, sizeof dims, "%zu bytes", d->size);
    int rc = check_size_limits(p, output_label(p, port, what, sizeof what), dims, 0, d->size);
    if (rc)
        return rc;
    lg_resource *r = declare(p, port, LG_KIND_BUFFER, "a buffer");
    if (!r)
        return LG_ERR_INVALID;
    r->buffer = *d;
    return 0;
}

static int check_volume_desc(lg_pnode *p, const lg_volume_desc *d, const char *what)
{
    if (!d || !d->width || !d->height || !d->depth || d->width > 4096 || d->height > 4096 ||
        d->depth > 4096 || (uint64_t)d->width * d->height * d->depth > (1ull << 28) ||
        d->format < LG_FORMAT_RGBA32F || d->format > LG_FORMAT_RGBE8)
        return lg_node_errorf(p,
                              "declares %s of %ux%ux%u (each side 1..4096, at most 2^28 "
                              "cells, a known format)",
                              what, d ? d->width : 0, d ? d->height : 0, d ? d->depth : 0),
               LG_ERR_INVALID;
    uint64_t cells = (uint64_t)d->width * d->height * d->depth;
    char dims[64];
    snprintf(dims, sizeof dims, "%ux%ux%u", d->width, d->height, d->depth);
    return check_size_limits(p, what, dims, cells, cells * lg_format_size(d->format));
}

static int api_declare_volume(lg_node *n, uint32_t port, const lg_volume_desc *d)
{
    lg_pnode *p = P(n);
    char what[96];
    int rc = check_volume_desc(p, d, output_label(p, port, what, sizeof what));
    if (rc)
        return rc;
    lg_resource *r = declare(p, port, LG_KIND_VOLUME, "a volume");
    if (!r)
        return LG_ERR_INVALID;
    r->volume = *d;
    return 0;
}

static int api_declare_alias(lg_node *n, uint32_t out_port, uint32_t in_port)
{
    lg_pnode *p = P(n);
    if (out_port >= p->schema->n_outputs || in_port >= p->schema->n_inputs)
        return lg_node_errorf(p, "declare_alias(%u, %u): no such ports", out_port, in_port),
               LG_ERR_INVALID;
    lg_resource *in = (lg_resource *)api_input(n, in_port);
    if (!in)
        return lg_node_errorf(p, "declare_alias: input '%s' is not connected",
                              p->schema->inputs[in_port].name),
               LG_ERR_INVALID;
    if (p->outputs[out_port])
        lg_resource_unref(p->ex, p->outputs[out_port]);
    in->refs++;
    p->outputs[out_port] = in;
    return 0;
}

static int api_declare_payload(lg_node *n, uint32_t port, lg_resource_kind kind,
                               const lg_scene_features *features, void *payload,
                               void (*free_payload)(void *))
{
    lg_pnode *p = P(n);
    if (kind == LG_KIND_IMAGE || kind == LG_KIND_BUFFER || kind == LG_KIND_VOLUME ||
        kind <= LG_KIND_ANY || kind >= LG_KIND_COUNT_ || lg_kind_is_composite(kind)) {
        lg_node_errorf(p, "declare_payload: kind %s is host-managed%s", lg_kind_name(kind),
                       lg_kind_is_composite(kind) ? " (composite since ABI 2.0: "
                                                    "declare_composite)"
                                                  : " or unknown");
        if (payload && free_payload)
            free_payload(payload);
        return LG_ERR_INVALID;
    }
    lg_resource *r = declare(p, port, kind, "a payload");
    if (!r) {
        if (payload && free_payload)
            free_payload(payload);
        return LG_ERR_INVALID;
    }
    if (features) {
        r->features = *features;
        r->has_features = true;
    }
    r->payload.data = payload;
    r->payload.free = free_payload;
    if (payload && p->plugin) {
        r->payload.plugin = p->plugin;
        p->plugin->live_refs++;
    }
    return 0;
}

static int api_set_device(lg_node *n, lg_device d)
{
    lg_pnode *p = P(n);
    if (d < LG_DEVICE_CPU || d > LG_DEVICE_CL)
        return lg_node_errorf(p, "set_device: unknown device %d", (int)d), LG_ERR_INVALID;
    p->run.device = d;
    p->run.device_set = true;
    /* Devices are made when a planned node asks: here, so that an unavailable device is
     * reported at planning time with the node's name, before any frame runs. */
    if (d == LG_DEVICE_GL)
        return lg_exec_need_gl(p->ex, p);
    if (d == LG_DEVICE_CL)
        return lg_exec_need_cl(p->ex, p);
    return 0;
}

static void api_set_view_independent(lg_node *n, bool independent)
{
    lg_pnode *p = P(n);
    p->plan.view_independent_set = true;
    p->plan.view_independent = independent;
}

static void api_set_per_frame(lg_node *n, bool per_frame)
{
    if (per_frame)
        P(n)->run.per_frame = P(n)->run.per_frame_own = true;
}

static void api_add_content_key(lg_node *n, const void *bytes, size_t size)
{
    if (bytes && size) {
        lg_digest_add(&P(n)->plan.identity, bytes, size);
        lg_digest_add(&P(n)->plan.cache_identity, bytes, size);
    }
}

static int api_map_cpu(lg_node *n, const lg_resource *r, unsigned access, lg_cpu_view *v)
{
    if (!r || !v)
        return lg_node_errorf(P(n), "map_cpu: NULL resource or view"), LG_ERR_INVALID;
    return lg_resource_map_cpu(P(n)->ex, P(n), (lg_resource *)r, access, v);
}

static int api_map_gl(lg_node *n, const lg_resource *r, unsigned access, uint32_t *name,
                      uint32_t *depth)
{
    if (!r)
        return lg_node_errorf(P(n), "map_gl: NULL resource"), LG_ERR_INVALID;
    return lg_resource_map_gl(P(n)->ex, P(n), (lg_resource *)r, access, name, depth);
}

static int api_map_cl(lg_node *n, const lg_resource *r, unsigned access, void **mem, void **depth)
{
    if (!r)
        return lg_node_errorf(P(n), "map_cl: NULL resource"), LG_ERR_INVALID;
    return lg_resource_map_cl(P(n)->ex, P(n), (lg_resource *)r, access, mem, depth);
}

static const void *api_gl(lg_node *n)
{
    lg_pnode *p = P(n);
    if (lg_exec_need_gl(p->ex, p))
        return NULL;
    return lg_gl_device_table(p->ex->dev.gl);
}

static void *api_cl_context(lg_node *n)
{
    lg_pnode *p = P(n);
    return lg_exec_need_cl(p->ex, p) ? NULL : lg_cl_device_context(p->ex->dev.cl);
}

static void *api_cl_queue(lg_node *n)
{
    lg_pnode *p = P(n);
    return lg_exec_need_cl(p->ex, p) ? NULL : lg_cl_device_queue(p->ex->dev.cl);
}

static void *api_cl_device(lg_node *n)
{
    lg_pnode *p = P(n);
    return lg_exec_need_cl(p->ex, p) ? NULL : lg_cl_device_id(p->ex->dev.cl);
}

static void *api_cl_program(lg_node *n, const char *name, const char *source, const char *options)
{
    lg_pnode *p = P(n);
    if (lg_exec_need_cl(p->ex, p))
        return NULL;
    char *log = NULL;
    void *prog = lg_cl_device_program(p->ex->dev.cl, name ? name : "kernel", source ? source : "",
                                      options, &log);
    if (!prog)
        lg_node_errorf(p, "%s", log ? log : "OpenCL program build failed");
    free(log);
    return prog;
}

static void api_cl_profile(lg_node *n, void *event)
{
    lg_pnode *p = P(n);
    if (!event)
        return;
    if (p->run.n_cl_events == p->run.cap_cl_events) {
        p->run.cap_cl_events = p->run.cap_cl_events ? p->run.cap_cl_events * 2 : 8;
        p->run.cl_events = lg_xrealloc(p->run.cl_events,
                                       p->run.cap_cl_events * sizeof *p->run.cl_events);
    }
    p->run.cl_events[p->run.n_cl_events++] = event; /* the host releases it after reading it */
}

static int api_gl_check(lg_node *n, const char *what)
{
    lg_pnode *p = P(n);
    if (!p->ex->dev.gl)
        return 0;
    const GladGLContext *gl = lg_gl_device_table(p->ex->dev.gl);
    GLenum e, first = GL_NO_ERROR;
    int count = 0;
    while ((e = gl->GetError()) != GL_NO_ERROR && count < 16) {
        if (!count)
            first = e;
        count++;
    }
    if (!count)
        return 0;
    lg_node_errorf(p, "GL error %s (0x%04x)%s while %s", lg_gl_strerror(first), first,
                   count > 1 ? " and more" : "", what ? what : "running");
    return LG_ERR_DEVICE;
}

/* An entry's fingerprint for the ranks' agreement (never 0, which is a miss). */
static uint64_t cache_fingerprint(const void *data, size_t size)
{
    uint64_t h = 1469598103934665603u ^ size;
    const unsigned char *b = data;
    for (size_t i = 0; i < size; i++)
        h = (h ^ b[i]) * 1099511628211u;
    return h ? h : 1;
}

/* Under mpirun a lookup is one answer for the job (dist.h, lg_dist_same): a hit only when
 * every rank found the same entry, else a miss on every rank. A rank that missed while the
 * others hit would otherwise compute alone and enter the node's lg_shard job alone. Each
 * rank then uses its own copy, which the fingerprint proved equal to rank 0's. */
static int api_cache_get(lg_node *n, const char *key, void **data, size_t *size)
{
    lg_pnode *p = P(n);
    int rc = lg_exec_cache_get(p->ex, p, key, data, size);
    if (lg_dist_size() == 1 || lg_dist_nested() || rc == LG_ERR_INVALID)
        return rc;
    char err[600] = "";
    int same = lg_dist_same(rc == LG_OK ? cache_fingerprint(*data, *size) : 0, err, sizeof err);
    if (same == 1)
        return rc;
    if (rc == LG_OK) {
        free(*data);
        *data = NULL;
        *size = 0;
        p->prof.cache_hits--;
        p->prof.cache_misses++;
    }
    if (same < 0)
        return lg_node_errorf(p, "cache lookup: %s", err), LG_ERR_INVALID;
    lg_hlog(LG_HINFO,
            "node '%s': cache entry %s: the ranks' entries differ (some miss): "
            "computed again on every rank",
            p->pub.name, key);
    return LG_ERR_NOTFOUND;
}

static int api_cache_put(lg_node *n, const char *key, const void *data, size_t size)
{
    return lg_exec_cache_put(P(n)->ex, P(n), key, data, size);
}

static int api_cache_store(lg_node *n, const char *key, const void *data, size_t size)
{
    return lg_exec_cache_put_status(P(n)->ex, P(n), key, data, size);
}

static void api_cache_free(void *data)
{
    free(data);
}

static void api_cache_reject(lg_node *n, const char *key, const char *why)
{
    lg_exec_cache_drop(P(n)->ex, P(n), key, why);
}

static void api_render_size(lg_node *n, uint32_t *w, uint32_t *h)
{
    P(n)->run.read_render_size = true;
    if (w)
        *w = P(n)->ex->opts.width;
    if (h)
        *h = P(n)->ex->opts.height;
}

static int api_payload_gl_buffer(lg_node *n, const lg_resource *r, uint32_t slot, const void *data,
                                 size_t size, uint32_t *buffer)
{
    if (!r || !buffer)
        return lg_node_errorf(P(n), "payload_gl_buffer: NULL resource or result"), LG_ERR_INVALID;
    return lg_resource_payload_gl(P(n)->ex, P(n), (lg_resource *)r, slot, data, size, buffer);
}

static int api_payload_gl_texture(lg_node *n, const lg_resource *r, uint32_t slot,
                                  const void *rgba8, uint32_t width, uint32_t height,
                                  uint32_t internal_format, uint32_t *texture)
{
    if (!r || !texture || !rgba8)
        return lg_node_errorf(P(n), "payload_gl_texture: NULL resource, pixels or result"),
               LG_ERR_INVALID;
    return lg_resource_payload_gl_texture(P(n)->ex, P(n), (lg_resource *)r, slot, rgba8, width,
                                          height, internal_format, texture);
}

static int api_payload_cl_buffer(lg_node *n, const lg_resource *r, uint32_t slot, const void *data,
                                 size_t size, void **mem)
{
    if (!r || !mem)
        return lg_node_errorf(P(n), "payload_cl_buffer: NULL resource or result"), LG_ERR_INVALID;
    return lg_resource_payload_cl(P(n)->ex, P(n), (lg_resource *)r, slot, data, size, mem);
}

static int api_declare_composite(lg_node *n, uint32_t port, const lg_part_spec *parts,
                                 uint32_t n_parts)
{
    lg_pnode *p = P(n);
    if (port >= p->schema->n_outputs)
        return lg_node_errorf(p, "declare_composite: output #%u; its type declares %u outputs",
                              port, p->schema->n_outputs),
               LG_ERR_INVALID;
    lg_resource_kind kind = p->schema->outputs[port].kind;
    const lg_kind_desc *kd = lg_kind_describe(kind);
    if (!lg_kind_is_composite(kind))
        return lg_node_errorf(p,
                              "declare_composite: output '%s' is of kind %s, which has no "
                              "parts",
                              p->schema->outputs[port].name, lg_kind_name(kind)),
               LG_ERR_INVALID;
    if (!parts && n_parts)
        return lg_node_errorf(p, "declare_composite: NULL parts"), LG_ERR_INVALID;
    /* every spec names a declared part once, with its type and a valid description */
    for (uint32_t i = 0; i < n_parts; i++) {
        const lg_part_spec *sp = &parts[i];
        int32_t idx = lg_kind_part_index(kind, sp->name);
        if (idx < 0) {
            lg_str list = { 0 };
            for (uint32_t j = 0; j < kd->n_parts; j++)
                lg_str_addf(&list, "%s%s", j ? ", " : "", kd->parts[j].name);
            lg_node_errorf(p, "declare_composite: a %s has no part '%s' (parts: %s)", kd->name,
                           sp->name ? sp->name : "(null)", list.s);
            lg_str_free(&list);
            return LG_ERR_INVALID;
        }
        for (uint32_t j = 0; j < i; j++)
            if (strcmp(parts[j].name, sp->name) == 0)
                return lg_node_errorf(p, "declare_composite: part '%s' given twice", sp->name),
                       LG_ERR_INVALID;
        lg_part_type want = kd->parts[idx].type;
        if (sp->type != want)
            return lg_node_errorf(p,
                                  "declare_composite: part '%s' of a %s is of type %d, "
                                  "declared as %d",
                                  sp->name, kd->name, (int)want, (int)sp->type),
                   LG_ERR_INVALID;
        char what[160];
        snprintf(what, sizeof what, "part '%s' of output '%s'", sp->name,
                 p->schema->outputs[port].name);
        int rc = 0;
        if (want == LG_PART_IMAGE && (rc = check_image_desc(p, &sp->image, what)))
            return rc;
        if (want == LG_PART_VOLUME && (rc = check_volume_desc(p, &sp->volume, what)))
            return rc;
        if (want == LG_PART_BUFFER && sp->buffer.size > (1ull << 34))
            return lg_node_errorf(p, "declares %s of %zu bytes (at most 16 GiB)", what,
                                  sp->buffer.size),
                   LG_ERR_INVALID;
        if (want == LG_PART_BUFFER) {
            char dims[48];
            snprintf(dims, sizeof dims, "%zu bytes", sp->buffer.size);
            if ((rc = check_size_limits(p, what, dims, 0, sp->buffer.size)))
                return rc;
        }
        if (want == LG_PART_META && (sp->buffer.size == 0 || sp->buffer.size > LG_META_MAX))
            return lg_node_errorf(p, "declares metadata %s of %zu bytes (1..%u)", what,
                                  sp->buffer.size, LG_META_MAX),
                   LG_ERR_INVALID;
    }
    for (uint32_t j = 0; j < kd->n_parts; j++) {
        if (kd->parts[j].optional)
            continue;
        bool given = false;
        for (uint32_t i = 0; i < n_parts; i++)
            given |= strcmp(parts[i].name, kd->parts[j].name) == 0;
        if (!given)
            return lg_node_errorf(p, "declare_composite: output '%s' (%s) needs part '%s'",
                                  p->schema->outputs[port].name, kd->name, kd->parts[j].name),
                   LG_ERR_INVALID;
    }
    lg_resource *r = declare(p, port, kind, kd->name);
    if (!r)
        return LG_ERR_INVALID;
    return lg_resource_make_parts(p->ex, p, r, parts, n_parts);
}

static const lg_resource *api_part(lg_node *n, const lg_resource *r, const char *name)
{
    lg_pnode *p = P(n);
    if (!r)
        return lg_node_errorf(p, "part('%s'): NULL resource", name ? name : ""), NULL;
    const lg_kind_desc *kd = lg_kind_describe(r->kind);
    if (!lg_kind_is_composite(r->kind))
        return lg_node_errorf(p, "part('%s'): a resource of kind %s has no parts", name ? name : "",
                              kd ? kd->name : "?"),
               NULL;
    int32_t idx = lg_kind_part_index(r->kind, name);
    if (idx < 0) {
        lg_str list = { 0 };
        for (uint32_t j = 0; j < kd->n_parts; j++)
            lg_str_addf(&list, "%s%s", j ? ", " : "", kd->parts[j].name);
        lg_node_errorf(p, "part('%s'): a %s has no such part (parts: %s)", name ? name : "",
                       kd->name, list.s);
        lg_str_free(&list);
        return NULL;
    }
#ifdef LG_DEBUG_CHECKS
    if (!lg_resource_reachable(p, r)) {
        const lg_pnode *src = r->producer;
        return lg_node_errorf(p,
                              "asks for part '%s' of a %s made by node '%s', which it did "
                              "not receive through an input",
                              name, kd->name, src ? src->pub.name : "?"),
               NULL;
    }
#endif
    if (r->neutral || (uint32_t)idx >= r->parts.n)
        return NULL;
    return r->parts.list[idx];
}

/* The pool is made on the first call of either function; a warning from making it (an
 * invalid LIGHTGRAPH_THREADS, a thread that would not start) is reported once. */
static lg_pool *pool_for(lg_pnode *p)
{
    char *warning = NULL;
    lg_pool *pool = lg_pool_global(&warning);
    if (warning) {
        lg_hlog(LG_HWARN, "%s", warning);
        free(warning);
    }
    (void)p;
    return pool;
}

static uint32_t api_cpu_workers(lg_node *n)
{
    return lg_pool_size(pool_for(P(n)));
}

static int api_parallel_for(lg_node *n, size_t count, size_t grain,
                            void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk),
                            void *ctx)
{
    lg_pnode *p = P(n);
    if (!fn || grain == 0)
        return lg_node_errorf(p, "parallel_for: %s", !fn ? "fn is NULL" : "grain is 0"),
               LG_ERR_INVALID;
    if (count / grain >= UINT32_MAX)
        return lg_node_errorf(p,
                              "parallel_for: %zu indices in chunks of %zu make more than "
                              "2^32 - 1 chunks; use a larger grain",
                              count, grain),
               LG_ERR_INVALID;
    if (lg_pool_run(pool_for(p), count, grain, fn, ctx))
        return lg_node_errorf(p, "parallel_for(%zu, %zu) refused by the pool", count, grain),
               LG_ERR_INVALID;
    return 0;
}

/* lg_shard (host.h): the job's items over the ranks (lg_dist_fixed), and each rank's share
 * over the pool. A failing chunk stops the chunks not yet started; the reason kept is the
 * failing chunk's with the lowest first item, so that the message does not depend on which
 * thread failed first. */
typedef struct shard_run {
    const lg_shard_job *job;
    lg_pool *pool;
    uint64_t grain; /* the job's grain: the pool's chunks */
    uint8_t *items; /* the rank's share being computed, items [base, ...) */
    uint64_t base;
    pthread_mutex_t lock;
    int failed; /* read without the lock as a hint; written under it */
    uint64_t fail_begin, fail_end;
    char why[512];
} shard_run;

static void shard_chunk(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    shard_run *r = ctx;
    if (__atomic_load_n(&r->failed, __ATOMIC_RELAXED))
        return;
    char why[512] = "";
    const lg_shard_job *job = r->job;
    uint64_t b = r->base + begin, e = r->base + end;
    if (job->run(job->ctx, b, e, r->items + (uint64_t)begin * job->item_bytes, why, sizeof why)) {
        pthread_mutex_lock(&r->lock);
        if (!r->failed || b < r->fail_begin) {
            r->fail_begin = b;
            r->fail_end = e;
            why[sizeof why - 1] = 0;
            snprintf(r->why, sizeof r->why, "%s", why[0] ? why : "failed (no reason given)");
        }
        __atomic_store_n(&r->failed, 1, __ATOMIC_RELAXED);
        pthread_mutex_unlock(&r->lock);
    }
}

/* lg_dist_range_fn: items [begin, end) of the job on this rank's threads. */
static int shard_range(void *ctx, uint64_t begin, uint64_t end, void *items, char *err,
                       size_t err_size)
{
    shard_run *r = ctx;
    r->items = items;
    r->base = begin;
    if (lg_pool_run(r->pool, (size_t)(end - begin), (size_t)r->grain, shard_chunk, r)) {
        snprintf(err, err_size, "the thread pool refused %llu items in chunks of %llu",
                 (unsigned long long)(end - begin), (unsigned long long)r->grain);
        return 1;
    }
    if (r->failed) {
        snprintf(err, err_size, "%s %llu..%llu: %s", r->job->what ? r->job->what : "items",
                 (unsigned long long)r->fail_begin, (unsigned long long)r->fail_end - 1, r->why);
        return 1;
    }
    return 0;
}

static int api_shard(lg_node *n, const lg_shard_job *job)
{
    lg_pnode *p = P(n);
    if (!job || !job->run || (!job->out && job->count) || job->grain == 0 || job->item_bytes == 0)
        return lg_node_errorf(p, "shard: %s",
                              !job                   ? "job is NULL"
                              : !job->run            ? "run is NULL"
                              : job->grain == 0      ? "grain is 0"
                              : job->item_bytes == 0 ? "item_bytes is 0"
                                                     : "out is NULL"),
               LG_ERR_INVALID;
    if (job->count > SIZE_MAX / job->item_bytes || job->count / job->grain >= UINT32_MAX)
        return lg_node_errorf(p,
                              "shard: %llu items of %llu bytes in chunks of %llu are more "
                              "than this host can hold or count",
                              (unsigned long long)job->count, (unsigned long long)job->item_bytes,
                              (unsigned long long)job->grain),
               LG_ERR_INVALID;
    if (job->count == 0)
        return 0;
    shard_run r = { .job = job, .pool = pool_for(p), .grain = job->grain };
    pthread_mutex_init(&r.lock, NULL);
    /* A rank's chunk: one grain per thread, so that every thread of the rank has work. */
    uint64_t workers = lg_pool_size(r.pool);
    uint64_t rank_grain = job->grain > UINT64_MAX / workers ? job->grain : job->grain * workers;
    char err[768] = "";
    int rc = lg_dist_fixed_family(job->what ? job->what : "items", job->affinity, job->count,
                                  rank_grain, job->item_bytes, job->out, shard_range, &r, err,
                                  sizeof err);
    pthread_mutex_destroy(&r.lock);
    if (rc)
        return lg_node_errorf(p, "%s", err[0] ? err : "shard: failed"), LG_ERR_INVALID;
    if (lg_dist_size() > 1) {
        /* where this rank's chunks came from (-v -v; tests/dist checks affinity with it) */
        uint64_t own, stolen, fresh;
        lg_dist_fixed_placement(&own, &stolen, &fresh);
        lg_log(n, LG_LOG_DEBUG, "shard: rank %d ran %llu chunks (%llu its own, %llu stolen)",
               lg_dist_rank(), (unsigned long long)(own + stolen + fresh), (unsigned long long)own,
               (unsigned long long)stolen);
    }
    return 0;
}

static int api_output_file_write(lg_node *n, const char *key, const void *data, size_t size)
{
    lg_pnode *p = P(n);
    const lg_param_desc *pd = NULL;
    uint32_t i = 0;
    for (; key && i < p->schema->n_params && !pd; i++)
        if (strcmp(p->schema->params[i].key, key) == 0)
            pd = &p->schema->params[i];
    if (!pd || pd->role != LG_ROLE_OUTPUT_FILE || pd->type != LG_PARAM_PATH)
        return lg_node_errorf(p,
                              "output_file_write: parameter '%s' is not a file the node "
                              "writes (a PATH parameter with .role = LG_ROLE_OUTPUT_FILE)",
                              key ? key : "(null)"),
               LG_ERR_INVALID;
    if (!data && size)
        return lg_node_errorf(p, "output_file_write(%s): data is NULL", key), LG_ERR_INVALID;
    struct lg_outputs *outs = p->ex->opts.outputs;
    if (!outs)
        return 0; /* the viewer: the file is not written (api_param said so) */
    const char *path = p->c->params[i - 1].s;
    if (!path || !path[0])
        return lg_node_errorf(p, "output_file_write: parameter %s names no file", key),
               LG_ERR_INVALID;
    char err[1024];
    if (!lg_outputs_temp(outs, path))
        return lg_node_errorf(p,
                              "%s: '%s' was not checked as an output before the run (a "
                              "host bug)",
                              key, path),
               LG_ERR_INVALID;
    if (lg_outputs_write_data(outs, path, data, size, err, sizeof err))
        return lg_node_errorf(p, "%s: %s", key, err), LG_ERR_IO;
    return 0;
}

static void api_declare_work(lg_node *n, double units, double seconds, const char *what)
{
    lg_pnode *p = P(n);
    /* a NaN or negative estimate is a plugin bug: shown as such rather than summed into a
     * warning that makes no sense */
    if (!(units >= 0) || !(seconds >= 0) || isinf(units) || isinf(seconds)) {
        lg_node_errorf(p,
                       "declare_work: units = %g, seconds = %g; both must be finite and "
                       ">= 0 (a plugin bug)",
                       units, seconds);
        return;
    }
    p->plan.work_declared = true;
    p->plan.work_units = units;
    p->plan.work_seconds = seconds;
    free(p->plan.work_what);
    p->plan.work_what = lg_xstrdup(what && what[0] ? what : "units");
}

/* Plugin memory is kept apart from bytes_alloc (the host's resources for the node): the
 * profile adds its peak, not its sum, so a buffer remade every frame counts once. */
static void api_account_alloc(lg_node *n, uint64_t bytes)
{
    lg_pnode *p = P(n);
    p->prof.bytes_plugin_live += bytes;
    if (p->prof.bytes_plugin_live > p->prof.bytes_plugin_peak)
        p->prof.bytes_plugin_peak = p->prof.bytes_plugin_live;
}

/* A release larger than what is live is a plugin's bookkeeping bug: said once, and the live
 * count clamps at zero rather than wrapping round. */
static void api_account_free(lg_node *n, uint64_t bytes)
{
    lg_pnode *p = P(n);
    if (bytes > p->prof.bytes_plugin_live) {
        lg_log(n, LG_LOG_WARN,
               "account_free: releasing %llu bytes with %llu counted as live (a "
               "plugin bug)",
               (unsigned long long)bytes, (unsigned long long)p->prof.bytes_plugin_live);
        p->prof.bytes_plugin_live = 0;
        return;
    }
    p->prof.bytes_plugin_live -= bytes;
}

void lg_host_api_init(lg_host_api *a)
{
    memset(a, 0, sizeof *a);
    a->struct_size = sizeof *a;
    a->abi_major = LG_ABI_MAJOR;
    a->abi_minor = LG_ABI_MINOR;
    a->log = api_log;
    a->error = api_error;
    a->progress = api_progress;
    a->now = api_now;
    a->param = api_param;
    a->param_index = api_param_index;
    a->input = api_input;
    a->output = api_output;
    a->describe = api_describe;
    a->declare_image = api_declare_image;
    a->declare_buffer = api_declare_buffer;
    a->declare_volume = api_declare_volume;
    a->declare_alias = api_declare_alias;
    a->declare_payload = api_declare_payload;
    a->set_device = api_set_device;
    a->set_per_frame = api_set_per_frame;
    a->set_view_independent = api_set_view_independent;
    a->add_content_key = api_add_content_key;
    a->account_alloc = api_account_alloc;
    a->account_free = api_account_free;
    a->declare_work = api_declare_work;
    a->map_cpu = api_map_cpu;
    a->map_gl = api_map_gl;
    a->map_cl = api_map_cl;
    a->gl = api_gl;
    a->cl_context = api_cl_context;
    a->cl_queue = api_cl_queue;
    a->cl_device = api_cl_device;
    a->cl_program = api_cl_program;
    a->cl_profile = api_cl_profile;
    a->gl_check = api_gl_check;
    a->cache_get = api_cache_get;
    a->cache_put = api_cache_put;
    a->cache_store = api_cache_store;
    a->cache_free = api_cache_free;
    a->cache_reject = api_cache_reject;
    a->render_size = api_render_size;
    a->payload_gl_buffer = api_payload_gl_buffer;
    a->payload_cl_buffer = api_payload_cl_buffer;
    a->payload_gl_texture = api_payload_gl_texture;
    a->declare_composite = api_declare_composite;
    a->part = api_part;
    a->cpu_workers = api_cpu_workers;
    a->parallel_for = api_parallel_for;
    a->shard = api_shard;
    a->output_file_write = api_output_file_write;
}
