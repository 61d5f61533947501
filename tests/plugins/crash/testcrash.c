/* Test plugin "testcrash": a pass-through node that crashes on demand, so that the tests
 * (tests/unit/host/test_crash.py) can show how `render` and `sweep` report a plugin's crash
 * (host/exec/exec.c, LG_GUARD_EXIT): the node, its type, its plugin and the signal named, exit
 * status 3, no output file and no temporary left.
 *
 *   test_crash { image = X, phase = "execute", signal = "segv", on_pool = false,
 *                file = "dump.txt" }
 *
 * phase: the callback that crashes (none, create, prepare, execute, destroy); signal: how
 * (a real fault where the machine has one: a NULL write, a truncated mapping, an integer
 * division by zero, an undefined instruction; abort(); a stack overflow, which is a
 * SIGSEGV the handler can report only from a stack of its own); on_pool: in execute, crash
 * on a thread of the host's CPU pool (lg_parallel_for) rather than the calling thread;
 * file: an output file (LG_ROLE_OUTPUT_FILE) written in execute before the crash, whose
 * temporary must go too. Built with the sanitizers' null and division checks off, so that
 * the sanitizer build crashes as the others do instead of reporting first. */
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include "lightgraph/lightgraph.h"

static const char *const phases[] = { "none", "create", "prepare", "execute", "destroy", NULL };
enum { PHASE_NONE, PHASE_CREATE, PHASE_PREPARE, PHASE_EXECUTE, PHASE_DESTROY };
static const char *const signals[] = { "segv", "bus", "fpe", "ill", "abrt", "stack", NULL };
enum { SIG_SEGV_, SIG_BUS_, SIG_FPE_, SIG_ILL_, SIG_ABRT_, SIG_STACK_ };

static const lg_param_desc params[] = {
    { .key = "phase",
      .type = LG_PARAM_ENUM,
      .def.s = "none",
      .enum_values = phases,
      .doc = "the callback that crashes" },
    { .key = "signal",
      .type = LG_PARAM_ENUM,
      .def.s = "segv",
      .enum_values = signals,
      .doc = "how it crashes" },
    { .key = "on_pool",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "execute: crash on a thread of the host's CPU pool" },
    { .key = "file",
      .type = LG_PARAM_PATH,
      .def.s = "",
      .role = LG_ROLE_OUTPUT_FILE,
      .doc = "written in execute before the crash (\"\": none)" },
    { .key = "x",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1,
      .doc = "does nothing (a parameter for sweep to vary)" },
};
static const lg_port_desc in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static volatile int sink;

/* Not tail-recursive (the array is used after the call), so every level takes stack; the
 * bound (4 TiB of stack) is never reached. */
static int overflow(int depth)
{
    volatile char pad[4096];
    pad[0] = (char)depth;
    if (depth > (1 << 30))
        return pad[0];
    return overflow(depth + 1) + pad[0];
}

static void crash(int how)
{
    switch (how) {
    case SIG_SEGV_: {
        int *volatile p = NULL;
        *p = 1;
        break;
    }
    case SIG_BUS_: {
        /* a read past the end of a mapped file (a memfd, no file on disk) */
        int fd = memfd_create("testcrash", 0);
        if (fd >= 0 && ftruncate(fd, 4096) == 0) {
            volatile char *m = mmap(NULL, 4096, PROT_READ, MAP_SHARED, fd, 0);
            if (m != MAP_FAILED && ftruncate(fd, 0) == 0)
                sink = m[0];
        }
        break;
    }
    case SIG_FPE_: {
        volatile int a = 1, b = 0;
        sink = a / b;
        break;
    }
    case SIG_ILL_:
#if defined(__x86_64__) || defined(__i386__)
        __asm__ volatile("ud2");
#endif
        break;
    case SIG_ABRT_: abort();
    case SIG_STACK_: sink = overflow(0); break;
    }
    /* a machine without that fault (an integer division by zero is 0 on some): the signal
     * itself, so that the test sees what it asked for */
    static const int sigs[] = { SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGSEGV };
    raise(sigs[how]);
}

static bool now(lg_node *n, int phase)
{
    return lg_param_enum(n, "phase") == phase;
}

static int create(lg_node *n)
{
    if (now(n, PHASE_CREATE))
        crash(lg_param_enum(n, "signal"));
    return 0;
}

static int prepare(lg_node *n)
{
    if (now(n, PHASE_PREPARE))
        crash(lg_param_enum(n, "signal"));
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    lg_image_desc d = { .width = info.image.width,
                        .height = info.image.height,
                        .format = LG_FORMAT_RGBA32F };
    return lg_declare_image(n, 0, &d);
}

typedef struct pool_ctx {
    pthread_t caller;
    int how;
} pool_ctx;

static void pool_chunk(void *p, size_t begin, size_t end, uint32_t chunk)
{
    (void)begin;
    (void)end;
    (void)chunk;
    const pool_ctx *c = p;
    if (!pthread_equal(pthread_self(), c->caller))
        crash(c->how);
    usleep(2000); /* the calling thread leaves chunks to the pool's threads */
}

static int execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    int rc;
    if (lg_param_string(n, "file")[0] &&
        (rc = lg_output_file_write(n, "file", "written before the crash\n", 25)))
        return rc;
    if (now(n, PHASE_EXECUTE)) {
        if (lg_param_bool(n, "on_pool")) {
            pool_ctx c = { pthread_self(), lg_param_enum(n, "signal") };
            lg_parallel_for(n, 1000, 1, pool_chunk, &c);
            return lg_error(n, "test_crash: no pool thread ran a chunk (LIGHTGRAPH_THREADS=1?)");
        }
        crash(lg_param_enum(n, "signal"));
    }
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    size_t np = (size_t)info.image.width * info.image.height;
    lg_cpu_view a, b;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &a)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &b)))
        return rc;
    const float *p = a.pixels;
    float *q = b.pixels;
    for (size_t i = 0; i < 4 * np; i++)
        q[i] = info.image.format == LG_FORMAT_RGBA32F ? p[i] : 0.0f;
    return 0;
}

static void destroy(lg_node *n)
{
    if (now(n, PHASE_DESTROY))
        crash(lg_param_enum(n, "signal"));
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_crash",
    .doc = "Passes its image through, or crashes where and how its parameters say (test)",
    LG_PARAMS(params),
    LG_INPUTS(in),
    LG_OUTPUTS(out),
    .create = create,
    .prepare = prepare,
    .execute = execute,
    .destroy = destroy,
} };

LG_PLUGIN_DEFINE("testcrash", "1.0.0", "Crash attribution test node", types)
