/*
 * The inline wrappers of lightgraph/host.h against hosts of every 2.x age, without a host:
 * an lg_host_api filled here, its struct_size set as an older host's would be.
 *
 *   lg_cache_store (ABI 2.7): a 2.7 host's cache_store answers; an older host (struct_size
 *   ending before cache_store, or the slot NULL) gets cache_put, and LG_OK from it is
 *   LG_CACHE_UNKNOWN (it returns LG_OK whether or not it stored), never LG_CACHE_STORED.
 *   lg_cache_reject (ABI 2.7): a 2.7 host's cache_reject gets the key and the reason; an
 *   older host (or a NULL slot) gets one warning through log, naming both, and nothing else.
 *
 * The plain wrappers (lg_progress, lg_now, lg_render_size, lg_declare_buffer /
 * _volume / _alias / _payload, lg_add_content_key, lg_cache_get / _save / _free,
 * lg_payload_gl_buffer / _cl_buffer): each reaches its own table entry, with every
 * argument as given, and returns what the entry returned (a fake entry per member records
 * its call; the others stay NULL, so a wrapper that reached the wrong one would crash).
 * lg_create_state and lg_output_size_nonempty (the create/prepare openings), and
 * lg_assert_input: silent on a required input of its kind, and in a LG_DEBUG_CHECKS
 * build an abort (in a child process) on an optional, missing or mistyped one.
 */
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/check.h"
#include "lightgraph/lightgraph.h"

static int put_rc, put_calls, store_calls;

static int fake_put(lg_node *n, const char *key, const void *data, size_t size)
{
    (void)n, (void)key, (void)data, (void)size;
    put_calls++;
    return put_rc;
}

static int fake_store(lg_node *n, const char *key, const void *data, size_t size)
{
    (void)n, (void)key, (void)data;
    store_calls++;
    return size == 1 ? LG_CACHE_OFF : LG_CACHE_STORED;
}

static int reject_calls, log_calls;
static char last[256];

static void fake_reject(lg_node *n, const char *key, const char *why)
{
    (void)n;
    reject_calls++;
    snprintf(last, sizeof last, "%s|%s", key, why);
}

static void fake_log(lg_node *n, lg_log_level level, const char *fmt, va_list ap)
{
    (void)n;
    log_calls += level == LG_LOG_WARN;
    vsnprintf(last, sizeof last, fmt, ap);
}

/* ---- the plain wrappers: one fake per member, recording the call ----------------------------- */

static struct {
    const char *member; /* the entry last called */
    lg_node *node;
    uint32_t port, port2, slot;
    const void *ptr, *ptr2;
    size_t size;
    double x;
    const char *str;
    lg_resource_kind kind;
    void (*free_fn)(void *);
} call;

static void record(const char *member, lg_node *n)
{
    memset(&call, 0, sizeof call);
    call.member = member;
    call.node = n;
}

static void fake_progress(lg_node *n, double fraction, const char *what)
{
    record("progress", n);
    call.x = fraction;
    call.str = what;
}
static double fake_now(void)
{
    record("now", NULL);
    return 1234.5;
}
static void fake_render_size(lg_node *n, uint32_t *w, uint32_t *h)
{
    record("render_size", n);
    *w = 640;
    *h = 360;
}
static int fake_declare_buffer(lg_node *n, uint32_t port, const lg_buffer_desc *d)
{
    record("declare_buffer", n);
    call.port = port;
    call.ptr = d;
    return -101;
}
static int fake_declare_volume(lg_node *n, uint32_t port, const lg_volume_desc *d)
{
    record("declare_volume", n);
    call.port = port;
    call.ptr = d;
    return -102;
}
static int fake_declare_alias(lg_node *n, uint32_t out_port, uint32_t in_port)
{
    record("declare_alias", n);
    call.port = out_port;
    call.port2 = in_port;
    return -103;
}
static int fake_declare_payload(lg_node *n, uint32_t port, lg_resource_kind kind,
                                const lg_scene_features *f, void *payload,
                                void (*free_payload)(void *))
{
    record("declare_payload", n);
    call.port = port;
    call.kind = kind;
    call.ptr = f;
    call.ptr2 = payload;
    call.free_fn = free_payload;
    return -104;
}
static void fake_add_content_key(lg_node *n, const void *bytes, size_t size)
{
    record("add_content_key", n);
    call.ptr = bytes;
    call.size = size;
}
static char cached_entry[] = "entry";
static int fake_cache_get(lg_node *n, const char *key, void **data, size_t *size)
{
    record("cache_get", n);
    call.str = key;
    *data = cached_entry;
    *size = sizeof cached_entry;
    return -105;
}
static int fake_cache_put_plain(lg_node *n, const char *key, const void *data, size_t size)
{
    record("cache_put", n);
    call.str = key;
    call.ptr = data;
    call.size = size;
    return -106;
}
static void fake_cache_free(void *data)
{
    record("cache_free", NULL);
    call.ptr = data;
}
static int fake_payload_gl(lg_node *n, const lg_resource *res, uint32_t slot, const void *data,
                           size_t size, uint32_t *buffer)
{
    record("payload_gl_buffer", n);
    call.ptr = res;
    call.slot = slot;
    call.ptr2 = data;
    call.size = size;
    *buffer = 77;
    return -107;
}
static int fake_payload_cl(lg_node *n, const lg_resource *res, uint32_t slot, const void *data,
                           size_t size, void **mem)
{
    record("payload_cl_buffer", n);
    call.ptr = res;
    call.slot = slot;
    call.ptr2 = data;
    call.size = size;
    *mem = cached_entry;
    return -108;
}
static void free_nothing(void *p)
{
    (void)p;
}

#define CALLED(name) (call.member && strcmp(call.member, name) == 0)

static void check_plain_wrappers(void)
{
    lg_host_api api;
    memset(&api, 0, sizeof api); /* every other entry NULL: a wrong one would crash */
    api.struct_size = sizeof api;
    api.progress = fake_progress;
    api.now = fake_now;
    api.render_size = fake_render_size;
    api.declare_buffer = fake_declare_buffer;
    api.declare_volume = fake_declare_volume;
    api.declare_alias = fake_declare_alias;
    api.declare_payload = fake_declare_payload;
    api.add_content_key = fake_add_content_key;
    api.cache_get = fake_cache_get;
    api.cache_put = fake_cache_put_plain;
    api.cache_free = fake_cache_free;
    api.payload_gl_buffer = fake_payload_gl;
    api.payload_cl_buffer = fake_payload_cl;
    lg_node n;
    memset(&n, 0, sizeof n);
    n.host = &api;

    lg_progress(&n, 0.25, "baking");
    CHECK(CALLED("progress") && call.node == &n && call.x == 0.25 &&
          strcmp(call.str, "baking") == 0);
    CHECK(lg_now(&n) == 1234.5 && CALLED("now"));
    uint32_t w = 0, h = 0;
    lg_render_size(&n, &w, &h);
    CHECK(CALLED("render_size") && call.node == &n && w == 640 && h == 360);

    lg_buffer_desc bd = { .size = 16 };
    CHECK(lg_declare_buffer(&n, 2, &bd) == -101 && CALLED("declare_buffer") && call.node == &n &&
          call.port == 2 && call.ptr == &bd);
    lg_volume_desc vd = { .width = 4 };
    CHECK(lg_declare_volume(&n, 3, &vd) == -102 && CALLED("declare_volume") && call.node == &n &&
          call.port == 3 && call.ptr == &vd);
    CHECK(lg_declare_alias(&n, 1, 4) == -103 && CALLED("declare_alias") && call.node == &n &&
          call.port == 1 && call.port2 == 4);
    lg_scene_features f;
    memset(&f, 0, sizeof f);
    int payload = 0;
    CHECK(lg_declare_payload(&n, 5, LG_KIND_SCENE, &f, &payload, free_nothing) == -104 &&
          CALLED("declare_payload") && call.node == &n && call.port == 5 &&
          call.kind == LG_KIND_SCENE && call.ptr == &f && call.ptr2 == &payload &&
          call.free_fn == free_nothing);

    const uint64_t key = 42;
    lg_add_content_key(&n, &key, sizeof key);
    CHECK(CALLED("add_content_key") && call.node == &n && call.ptr == &key &&
          call.size == sizeof key);

    void *data = NULL;
    size_t size = 0;
    CHECK(lg_cache_get(&n, "table", &data, &size) == -105 && CALLED("cache_get") &&
          call.node == &n && strcmp(call.str, "table") == 0 && data == cached_entry &&
          size == sizeof cached_entry);
    const char bytes[3] = { 1, 2, 3 };
    CHECK(lg_cache_put(&n, "table", bytes, sizeof bytes) == -106 && CALLED("cache_put") &&
          call.node == &n && strcmp(call.str, "table") == 0 && call.ptr == bytes &&
          call.size == sizeof bytes);
    lg_cache_free(&n, data);
    CHECK(CALLED("cache_free") && call.ptr == cached_entry);

    const lg_resource *res = (const lg_resource *)&payload; /* opaque: only passed on */
    uint32_t buffer = 0;
    CHECK(lg_payload_gl_buffer(&n, res, 6, bytes, sizeof bytes, &buffer) == -107 &&
          CALLED("payload_gl_buffer") && call.node == &n && call.ptr == res && call.slot == 6 &&
          call.ptr2 == bytes && call.size == sizeof bytes && buffer == 77);
    void *mem = NULL;
    CHECK(lg_payload_cl_buffer(&n, res, 7, bytes, sizeof bytes, &mem) == -108 &&
          CALLED("payload_cl_buffer") && call.node == &n && call.ptr == res && call.slot == 7 &&
          call.ptr2 == bytes && call.size == sizeof bytes && mem == cached_entry);
}

/* ---- the create/prepare openings and lg_assert_input ----------------------------------------- */

static int error_calls;
static char error_text[256];

static void fake_error(lg_node *n, const char *fmt, va_list ap)
{
    (void)n;
    error_calls++;
    vsnprintf(error_text, sizeof error_text, fmt, ap);
}

static lg_value size_params[2];
static uint32_t render_w, render_h;

static int32_t fake_param_index(lg_node *n, const char *key)
{
    (void)n;
    return strcmp(key, "width") == 0 ? 0 : strcmp(key, "height") == 0 ? 1 : -1;
}
static const lg_value *fake_param(lg_node *n, uint32_t i)
{
    (void)n;
    return i < 2 ? &size_params[i] : NULL;
}
static void fake_render_size_var(lg_node *n, uint32_t *w, uint32_t *h)
{
    (void)n;
    *w = render_w;
    *h = render_h;
}

/* the inputs a fake node sees: a scene on 0, nothing on 1, an image on 2 */
static int resource_kinds[3] = { LG_KIND_SCENE, 0, LG_KIND_IMAGE };
static const lg_resource *fake_input(lg_node *n, uint32_t port)
{
    (void)n;
    return port < 3 && resource_kinds[port] ? (const lg_resource *)&resource_kinds[port] : NULL;
}
static int fake_describe(const lg_resource *r, lg_resource_info *info)
{
    memset(info, 0, sizeof *info);
    if (!r)
        return LG_ERR_INVALID;
    info->kind = (lg_resource_kind) * (const int *)r;
    return 0;
}

#ifdef LG_DEBUG_CHECKS
/* Did lg_assert_input(n, port) abort? In a child, so that the test goes on. */
static bool assert_aborts(lg_node *n, uint32_t port)
{
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        lg_assert_input(n, port);
        _exit(0);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid)
        return false;
    return WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT;
}
#endif

static void check_openings(void)
{
    lg_host_api api;
    memset(&api, 0, sizeof api);
    api.struct_size = sizeof api;
    api.error = fake_error;
    api.param_index = fake_param_index;
    api.param = fake_param;
    api.render_size = fake_render_size_var;
    api.input = fake_input;
    api.describe = fake_describe;
    static const lg_port_desc inputs[] = {
        { .name = "scene", .kind = LG_KIND_SCENE },
        { .name = "shadows", .kind = LG_KIND_SHADOWMAP }, /* required, but nothing there */
        { .name = "base", .kind = LG_KIND_SCENE },        /* an image there: the wrong kind */
        { .name = "extra", .kind = LG_KIND_IMAGE, .optional = true },
    };
    static const lg_node_type type = {
        .struct_size = sizeof(lg_node_type), .name = "fake", .inputs = inputs, .n_inputs = 4
    };
    lg_node n;
    memset(&n, 0, sizeof n);
    n.host = &api;
    n.type = &type;

    /* lg_create_state: zeroed, n->user, owned by the caller */
    unsigned char *st = lg_create_state(&n, 64);
    CHECK(st && n.user == st && error_calls == 0);
    bool zero = st != NULL;
    for (int i = 0; st && i < 64; i++)
        zero &= st[i] == 0;
    CHECK(zero);
    free(st);
    n.user = NULL;

    /* lg_output_size_nonempty: 0 takes the render size; an empty size is an error */
    size_params[0] = (lg_value){ .type = LG_PARAM_INT, .i = 0 };
    size_params[1] = (lg_value){ .type = LG_PARAM_INT, .i = 20 };
    render_w = 320, render_h = 180;
    uint32_t w = 0, h = 0;
    CHECK(lg_output_size_nonempty(&n, "width", "height", &w, &h) == 0 && w == 320 && h == 20 &&
          error_calls == 0);
    render_w = 0;
    CHECK(lg_output_size_nonempty(&n, "width", "height", &w, &h) == LG_ERR_INVALID && w == 0 &&
          h == 20 && error_calls == 1 &&
          strcmp(error_text, "output size 0x20: width and height must be > 0") == 0);

    /* lg_assert_input: nothing to say about a required input of its kind */
    lg_assert_input(&n, 0);
    CHECK(error_calls == 1);
#ifdef LG_DEBUG_CHECKS
    CHECK(!assert_aborts(&n, 0));
    CHECK(assert_aborts(&n, 1)); /* required, not connected */
    CHECK(assert_aborts(&n, 2)); /* another kind */
    CHECK(assert_aborts(&n, 3)); /* optional: no guarantee to assert */
    CHECK(assert_aborts(&n, 4)); /* no such input */
#endif
}

int main(void)
{
    lg_host_api api;
    memset(&api, 0, sizeof api);
    api.cache_put = fake_put;
    api.cache_store = fake_store; /* there, but an older host's size does not reach it */
    lg_node n;
    memset(&n, 0, sizeof n);
    n.host = &api;
    const char data[2] = { 1, 2 };

    /* a 2.6 host: the struct ends where cache_store begins */
    api.struct_size = offsetof(lg_host_api, cache_store);
    put_rc = LG_OK;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_UNKNOWN && put_calls == 1 &&
          store_calls == 0);
    put_rc = LG_ERR_IO;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_NOT_STORED);
    put_rc = LG_ERR_INVALID;
    CHECK(lg_cache_store(&n, NULL, data, 2) == LG_ERR_INVALID);

    /* a 2.7 host that left the slot NULL: the same fallback */
    api.struct_size = sizeof api;
    api.cache_store = NULL;
    put_rc = LG_OK;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_UNKNOWN && store_calls == 0);

    /* a 2.7 host: its answer, cache_put not called */
    api.cache_store = fake_store;
    put_calls = 0;
    CHECK(lg_cache_store(&n, "k", data, 2) == LG_CACHE_STORED && store_calls == 1);
    CHECK(lg_cache_store(&n, "k", data, 1) == LG_CACHE_OFF && put_calls == 0);

    /* the slot took a reserved pointer: the struct's size is what 2.6 plugins were built
     * with (set_view_independent, the last 2.6 field, then 24 reserved pointers), and
     * cache_store lies inside it */
    CHECK(sizeof(lg_host_api) == offsetof(lg_host_api, set_view_independent) + 25 * sizeof(void *));
    CHECK(offsetof(lg_host_api, cache_store) < offsetof(lg_host_api, reserved));

    /* lg_cache_reject: a 2.7 host takes it; an older one (or a NULL slot) gets a warning */
    api.log = fake_log;
    api.cache_reject = fake_reject;
    lg_cache_reject(&n, "k", "float 3 = nan is not finite");
    CHECK(reject_calls == 1 && log_calls == 0 && !strcmp(last, "k|float 3 = nan is not finite"));
    api.struct_size = offsetof(lg_host_api, cache_reject);
    lg_cache_reject(&n, "k", "float 3 = nan is not finite");
    CHECK(reject_calls == 1 && log_calls == 1 && strstr(last, "'k'") &&
          strstr(last, "float 3 = nan is not finite"));
    api.struct_size = sizeof api;
    api.cache_reject = NULL;
    lg_cache_reject(&n, "k", "why");
    CHECK(reject_calls == 1 && log_calls == 2);
    CHECK(offsetof(lg_host_api, cache_reject) < offsetof(lg_host_api, reserved));

    check_plain_wrappers();
    check_openings();
    return check_report("sdk_host_wrappers");
}
