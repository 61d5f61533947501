/* lg_cl_pass and lg_cl_buffer (lightgraph/cl.h) against the real CL device, through a host
 * that has only what they call: the device's context, queue and program cache, the profile
 * (events counted), the memory account (live bytes), and map_cl over fake resources.
 *
 *   run        a kernel built from two texts (a shared twin, then its file) computes what
 *              the C below computes; one event reaches the profile per run
 *   arg size   a uint argument given 8 bytes: the message names the pass, the kernel, the
 *              index, the argument's name and type, the size and CL_INVALID_ARG_SIZE (-51),
 *              once; the run returns the error without enqueueing; set right, it runs
 *   unset      an argument never set is named at the run, which enqueues nothing
 *   resources  a resource bound by access maps it with that access; a failed map fails the
 *              pass
 *   kernel     a misspelt kernel name: CL_INVALID_KERNEL_NAME and the kernels there are
 *   build      an error in the second text: the log points into that file ("broken.cl:3:")
 *   buffers    recreate keeps a large enough buffer of the same flags and remakes one too
 *              small or of other flags; write/read; ranges; the account is back at 0 after
 *              destroy, as many frees as allocations
 *   descriptor no name, a NULL source, reserved fields, a file name with a quote
 * Exits 77 if no CL device can be made. */
#include <stdarg.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "exec/device.h"
#include "devtest.h"

static lg_cl_dev *dev;
static int events;   /* cl_profile calls */
static int64_t live; /* account_alloc - account_free */
static int allocs, frees;

/* A fake resource: what map_cl gives, and the access it was last mapped with. */
struct lg_resource {
    cl_mem mem;
    int fail; /* map_cl reports and returns LG_ERR_DEVICE */
    unsigned access;
};

static void *t_cl_context(lg_node *n)
{
    return lg_cl_device_context(dev);
}
static void *t_cl_queue(lg_node *n)
{
    return lg_cl_device_queue(dev);
}
static void *t_cl_device(lg_node *n)
{
    return lg_cl_device_id(dev);
}
static void *t_cl_program(lg_node *n, const char *name, const char *source, const char *options)
{
    char *log = NULL;
    void *p = lg_cl_device_program(dev, name, source, options, &log);
    if (!p)
        lg_error(n, "%s", log ? log : "build failed");
    free(log);
    return p;
}
static void t_cl_profile(lg_node *n, void *ev)
{
    events++;
    clReleaseEvent((cl_event)ev);
}
static void t_account_alloc(lg_node *n, uint64_t bytes)
{
    live += (int64_t)bytes;
    allocs++;
}
static void t_account_free(lg_node *n, uint64_t bytes)
{
    live -= (int64_t)bytes;
    frees++;
}
static int t_map_cl(lg_node *n, const lg_resource *r, unsigned access, void **mem, void **depth)
{
    ((lg_resource *)r)->access = access;
    if (r->fail)
        return lg_error_code(n, LG_ERR_DEVICE, "map_cl: this resource fails");
    *mem = r->mem;
    *depth = NULL;
    return 0;
}

static lg_host_api api;
static lg_node node;

static const char twin_cl[] = /* a shared twin (as rgbe.cl): a function the kernel calls */
    "float twin_f(float x)\n"
    "{\n"
    "    return 2.0f * x + 1.0f;\n"
    "}\n";

static const char kernel_cl[] =
    "kernel void scale_add(global const float *a, global float *b, uint n, float s,\n"
    "                      float4 v)\n"
    "{\n"
    "    uint i = get_global_id(0);\n"
    "    if (i < n)\n"
    "        b[i] = twin_f(a[i]) * s + v.y;\n"
    "}\n";

static const char broken_cl[] = "kernel void broken(global float *a)\n"
                                "{\n"
                                "    a[0] = twin_f(undeclared_thing);\n"
                                "}\n";

static const char *const srcs[] = { twin_cl, kernel_cl };
static const char *const names[] = { "twin.cl", "scale.cl" };

static lg_cl_pass_desc desc(void)
{
    lg_cl_pass_desc d = { .name = "test scale",
                          .sources = srcs,
                          .source_names = names,
                          .n_sources = 2,
                          .options = "-cl-std=CL1.2",
                          .kernel = "scale_add" };
    return d;
}

enum { N = 100 };

static bool has(const char *s)
{
    return strstr(devtest_errors, s) != NULL;
}

static void test_run(void)
{
    lg_cl_pass *p = NULL;
    lg_cl_pass_desc d = desc();
    devtest_clear();
    int rc = lg_cl_pass_create(&node, &d, &p);
    CHECKF(rc == 0 && p, "create: %d: %s", rc, devtest_errors);
    if (!p)
        return;
    CHECK(lg_cl_pass_kernel(p) != NULL);
    lg_cl_buffer a = { 0 }, b = { 0 };
    float in[N], out[N];
    for (int i = 0; i < N; i++)
        in[i] = (float)i * 0.25f - 3.0f;
    CHECK(lg_cl_buffer_recreate(&node, &a, sizeof in, CL_MEM_READ_ONLY) == 0);
    CHECK(lg_cl_buffer_recreate(&node, &b, sizeof out, 0) == 0);
    CHECK(lg_cl_buffer_write(&node, &a, 0, sizeof in, in) == 0);
    const float v[4] = { 9.0f, 0.5f, 9.0f, 9.0f };
    CHECK(lg_cl_pass_arg_mem(p, 0, a.mem) == 0);
    CHECK(lg_cl_pass_arg_mem(p, 1, b.mem) == 0);
    CHECK(lg_cl_pass_arg_uint(p, 2, N) == 0);
    CHECK(lg_cl_pass_arg_float(p, 3, 3.0f) == 0);
    CHECK(lg_cl_pass_arg_float4(p, 4, v) == 0);
    size_t global = 128, local = 64;
    int ev0 = events;
    rc = lg_cl_pass_run(p, 1, &global, &local);
    CHECKF(rc == 0, "run: %d: %s", rc, devtest_errors);
    CHECKF(events == ev0 + 1, "%d events profiled, expected 1", events - ev0);
    CHECK(lg_cl_buffer_read(&node, &b, 0, sizeof out, out) == 0);
    int bad = 0;
    for (int i = 0; i < N; i++) {
        float want = (2.0f * in[i] + 1.0f) * 3.0f + 0.5f;
        if (out[i] != want && bad++ < 3)
            CHECKF(0, "out[%d] = %g, expected %g", i, out[i], want);
    }
    CHECKF(bad == 0, "%d of %d values wrong", bad, N);
    CHECKF(devtest_error_count == 0, "errors on success: %s", devtest_errors);

    /* A uint given 8 bytes: named, with its own error code, once. */
    devtest_clear();
    double wrong = 1.0;
    rc = lg_cl_pass_arg(p, 2, sizeof wrong, &wrong);
    CHECKF(rc == LG_ERR_DEVICE, "wrong size returned %d", rc);
    CHECKF(devtest_error_count == 1, "%d errors: %s", devtest_error_count, devtest_errors);
    CHECKF(has("cl pass 'test scale'") && has("kernel scale_add") && has("argument 2") &&
               has("'n'") && has("(uint)") && has("8 bytes") && has("CL_INVALID_ARG_SIZE (-51)"),
           "message: %s", devtest_errors);
    printf("wrong size: %s\n", devtest_errors);
    /* the other arguments still set: the run fails only for that one, without enqueueing
     * and without saying it again */
    ev0 = events;
    rc = lg_cl_pass_run(p, 1, &global, &local);
    CHECKF(rc == LG_ERR_DEVICE, "run after a failed argument returned %d", rc);
    CHECKF(events == ev0, "a failed pass enqueued (%d events)", events - ev0);
    CHECKF(devtest_error_count == 1, "the failure was reported again: %s", devtest_errors);
    /* the failed argument counts as unset until set right */
    devtest_clear();
    rc = lg_cl_pass_run(p, 1, &global, &local);
    CHECKF(rc == LG_ERR_INVALID && has("argument 2 'n' (uint)") && has("not set"),
           "run after the failure was returned: %d: %s", rc, devtest_errors);
    CHECKF(events == ev0, "enqueued with an unset argument");
    devtest_clear();
    CHECK(lg_cl_pass_arg_uint(p, 2, N) == 0);
    rc = lg_cl_pass_run(p, 1, &global, &local);
    CHECKF(rc == 0 && events == ev0 + 1, "run once set again: %d: %s", rc, devtest_errors);

    /* A bad index: the count of arguments in the message. */
    devtest_clear();
    rc = lg_cl_pass_arg_uint(p, 7, 1);
    CHECKF(rc == LG_ERR_DEVICE && has("argument 7") && has("CL_INVALID_ARG_INDEX") &&
               has("the kernel has 5 arguments"),
           "bad index: %d: %s", rc, devtest_errors);
    lg_cl_pass_run(p, 1, &global, &local); /* returns that failure; the pass starts afresh */

    /* Sizes in the run's error. */
    devtest_clear();
    size_t g2[2] = { 100, 3 }, l2[2] = { 64, 1 };
    ev0 = events;
    rc = lg_cl_pass_run(p, 2, g2, l2);
    CHECKF(rc == LG_ERR_DEVICE && has("kernel scale_add") && has("global 100x3") &&
               has("local 64x1") && has("CL_INVALID_WORK_GROUP_SIZE"),
           "enqueue failure: %d: %s", rc, devtest_errors);
    CHECKF(events == ev0, "a failed enqueue was profiled");
    devtest_clear();
    rc = lg_cl_pass_run(p, 0, g2, NULL);
    CHECKF(rc == LG_ERR_INVALID && has("0 dimensions"), "dims 0: %d: %s", rc, devtest_errors);

    lg_cl_buffer_destroy(&node, &a);
    lg_cl_buffer_destroy(&node, &b);
    lg_cl_pass_destroy(&p);
    CHECK(p == NULL);
    lg_cl_pass_destroy(&p);
    lg_cl_pass_destroy(NULL);
}

static void test_unset_and_resources(void)
{
    lg_cl_pass *p = NULL;
    lg_cl_pass_desc d = desc();
    devtest_clear();
    if (lg_cl_pass_create(&node, &d, &p))
        return;
    lg_cl_buffer a = { 0 }, b = { 0 };
    CHECK(lg_cl_buffer_recreate(&node, &a, N * 4, 0) == 0);
    CHECK(lg_cl_buffer_recreate(&node, &b, N * 4, 0) == 0);
    lg_resource in = { .mem = a.mem }, out = { .mem = b.mem };
    CHECK(lg_cl_pass_arg_resource(p, 0, &in, LG_READ) == 0);
    CHECKF(in.access == LG_READ, "mapped with access %u", in.access);
    /* 1 and 4 not set */
    CHECK(lg_cl_pass_arg_uint(p, 2, N) == 0);
    CHECK(lg_cl_pass_arg_float(p, 3, 1.0f) == 0);
    size_t global = N;
    int ev0 = events;
    devtest_clear();
    int rc = lg_cl_pass_run(p, 1, &global, NULL);
    CHECKF(rc == LG_ERR_INVALID, "run with unset arguments returned %d", rc);
    CHECKF(has("kernel scale_add") && has("argument 1 'b'") && has("argument 4 'v' (float4)") &&
               has("not set") && !has("argument 0") && !has("argument 2"),
           "message: %s", devtest_errors);
    CHECKF(events == ev0, "enqueued with unset arguments");
    printf("unset: %s\n", devtest_errors);

    /* bound by access; a failed map fails the pass */
    CHECK(lg_cl_pass_arg_resource(p, 1, &out, LG_WRITE) == 0);
    CHECKF(out.access == LG_WRITE, "mapped with access %u", out.access);
    const float v[4] = { 0 };
    CHECK(lg_cl_pass_arg_float4(p, 4, v) == 0);
    devtest_clear();
    CHECKF(lg_cl_pass_run(p, 1, &global, NULL) == 0, "run: %s", devtest_errors);
    lg_resource failing = { .fail = 1 };
    devtest_clear();
    rc = lg_cl_pass_arg_resource(p, 0, &failing, LG_READ);
    CHECKF(rc == LG_ERR_DEVICE && has("this resource fails") && has("argument 0 'a'"),
           "failed map: %d: %s", rc, devtest_errors);
    ev0 = events;
    CHECK(lg_cl_pass_run(p, 1, &global, NULL) == LG_ERR_DEVICE);
    CHECK(events == ev0);
    devtest_clear();
    rc = lg_cl_pass_arg_resource(p, 0, &in, 4);
    CHECKF(rc == LG_ERR_INVALID && has("access 4"), "bad access: %d: %s", rc, devtest_errors);
    lg_cl_pass_run(p, 1, &global, NULL);
    /* NULL: an optional input not connected is a NULL pointer */
    CHECK(lg_cl_pass_arg_resource(p, 0, NULL, LG_READ) == 0);
    CHECK(lg_cl_pass_arg_mem(p, 0, NULL) == 0);
    /* a NULL pass: no report (create reported), LG_ERR_INVALID */
    devtest_clear();
    CHECK(lg_cl_pass_arg_uint(NULL, 0, 1) == LG_ERR_INVALID);
    CHECK(lg_cl_pass_run(NULL, 1, &global, NULL) == LG_ERR_INVALID);
    CHECK(lg_cl_pass_kernel(NULL) == NULL);
    CHECK(devtest_error_count == 0);
    lg_cl_pass_destroy(&p);
    lg_cl_buffer_destroy(&node, &a);
    lg_cl_buffer_destroy(&node, &b);
}

static void test_create_errors(void)
{
    lg_cl_pass *p = (lg_cl_pass *)&node; /* create sets it to NULL on failure */
    lg_cl_pass_desc d = desc();
    d.kernel = "scale_ad";
    devtest_clear();
    int rc = lg_cl_pass_create(&node, &d, &p);
    CHECKF(rc == LG_ERR_DEVICE && p == NULL, "misspelt kernel: %d", rc);
    CHECKF(has("cl pass 'test scale'") && has("kernel scale_ad:") &&
               has("CL_INVALID_KERNEL_NAME (-46)") && has("twin.cl+scale.cl has: scale_add"),
           "message: %s", devtest_errors);
    printf("kernel name: %s\n", devtest_errors);

    /* a build error in the second text: the log names that file and the line in it */
    static const char *const bsrc[] = { twin_cl, broken_cl };
    static const char *const bnames[] = { "twin.cl", "broken.cl" };
    d = desc();
    d.sources = bsrc, d.source_names = bnames, d.kernel = "broken", d.name = "test broken";
    devtest_clear();
    rc = lg_cl_pass_create(&node, &d, &p);
    CHECKF(rc == LG_ERR_DEVICE && p == NULL, "build error: %d", rc);
    CHECKF(has("broken.cl:3:") && has("undeclared_thing") &&
               has("cl pass 'test broken': kernel broken: the program (twin.cl+broken.cl) did "
                   "not build"),
           "build log: %s", devtest_errors);
    printf("build error: %s\n", devtest_errors);

    /* descriptors */
    struct {
        const char *what, *expect;
        lg_cl_pass_desc d;
    } bad[] = {
        { "no name", "has no name", desc() },
        { "no kernel", "no kernel name", desc() },
        { "NULL source", "sources[1] is NULL", desc() },
        { "no sources", "no sources", desc() },
        { "reserved", "reserved[2] is not zero", desc() },
        { "struct_size", "struct_size 12", desc() },
        { "quote", "source_names[0] is \"tw\"in.cl\"", desc() },
    };
    static const char *const nullsrc[] = { twin_cl, NULL };
    static const char *const quoted[] = { "tw\"in.cl", "scale.cl" };
    bad[0].d.name = NULL;
    bad[1].d.kernel = "";
    bad[2].d.sources = nullsrc;
    bad[3].d.n_sources = 0;
    bad[4].d.reserved[2] = &node;
    bad[5].d.struct_size = 12;
    bad[6].d.source_names = quoted;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        devtest_clear();
        p = (lg_cl_pass *)&node;
        rc = lg_cl_pass_create(&node, &bad[i].d, &p);
        CHECKF(rc == LG_ERR_INVALID && p == NULL && has(bad[i].expect), "%s: %d: %s", bad[i].what,
               rc, devtest_errors);
    }
}

static void test_buffers(void)
{
    int64_t live0 = live;
    int allocs0 = allocs, frees0 = frees;
    lg_cl_buffer b = { 0 };
    devtest_clear();
    CHECK(lg_cl_buffer_recreate(&node, &b, 1000, 0) == 0);
    CHECKF(b.mem && b.size == 1000 && b.flags == CL_MEM_READ_WRITE, "made: %p %zu 0x%llx",
           (void *)b.mem, b.size, (unsigned long long)b.flags);
    CHECKF(live - live0 == 1000, "live %lld after 1000 bytes", (long long)(live - live0));
    cl_mem first = b.mem;
    /* smaller, same flags (0 and READ_WRITE are one): kept, contents and all */
    unsigned char pat[1000], back[1000];
    for (int i = 0; i < 1000; i++)
        pat[i] = (unsigned char)(i * 7);
    CHECK(lg_cl_buffer_write(&node, &b, 0, sizeof pat, pat) == 0);
    CHECK(lg_cl_buffer_recreate(&node, &b, 500, CL_MEM_READ_WRITE) == 0);
    CHECKF(b.mem == first && b.size == 1000, "a large enough buffer was remade");
    CHECK(lg_cl_buffer_read(&node, &b, 0, sizeof back, back) == 0);
    CHECKF(memcmp(pat, back, sizeof pat) == 0, "contents lost when kept");
    CHECK(lg_cl_buffer_read(&node, &b, 10, 5, back) == 0 && memcmp(back, pat + 10, 5) == 0);
    CHECKF(live - live0 == 1000 && allocs - allocs0 == 1, "kept: live %lld, %d allocations",
           (long long)(live - live0), allocs - allocs0);
    /* larger: remade */
    CHECK(lg_cl_buffer_recreate(&node, &b, 4000, 0) == 0);
    CHECKF(b.size == 4000 && live - live0 == 4000, "grown: size %zu, live %lld", b.size,
           (long long)(live - live0));
    /* other flags: remade */
    CHECK(lg_cl_buffer_recreate(&node, &b, 100, CL_MEM_READ_ONLY) == 0);
    CHECKF(b.size == 100 && b.flags == CL_MEM_READ_ONLY && live - live0 == 100,
           "other flags: size %zu flags 0x%llx live %lld", b.size, (unsigned long long)b.flags,
           (long long)(live - live0));
    /* ranges */
    devtest_clear();
    CHECK(lg_cl_buffer_write(&node, &b, 60, 41, pat) == LG_ERR_INVALID);
    CHECKF(has("41 bytes at 60") && has("beyond the CL buffer's 100 bytes"), "range: %s",
           devtest_errors);
    devtest_clear();
    CHECK(lg_cl_buffer_read(&node, &b, SIZE_MAX, 2, back) == LG_ERR_INVALID);
    CHECK(lg_cl_buffer_write(&node, &b, 0, 4, NULL) == LG_ERR_INVALID);
    CHECK(lg_cl_buffer_write(&node, &b, 100, 0, NULL) == 0);
    /* refused: host pointers, size 0 (the buffer before it is gone, counted as freed) */
    devtest_clear();
    CHECK(lg_cl_buffer_recreate(&node, &b, 64, CL_MEM_COPY_HOST_PTR) == LG_ERR_INVALID);
    CHECKF(has("CL_MEM_COPY_HOST_PTR") && has("lg_cl_buffer_write"), "host ptr: %s",
           devtest_errors);
    devtest_clear();
    CHECK(lg_cl_buffer_recreate(&node, &b, 0, 0) == LG_ERR_INVALID);
    CHECKF(has("size 0"), "size 0: %s", devtest_errors);
    CHECKF(b.mem == NULL && b.size == 0 && live == live0, "after a failed recreate: %p, live %lld",
           (void *)b.mem, (long long)(live - live0));
    devtest_clear();
    CHECK(lg_cl_buffer_read(&node, &b, 0, 1, back) == LG_ERR_INVALID && has("no buffer"));
    /* too large for the device: the CL error, named */
    devtest_clear();
    cl_ulong max_alloc = 0;
    clGetDeviceInfo((cl_device_id)lg_cl_device_id(dev), CL_DEVICE_MAX_MEM_ALLOC_SIZE,
                    sizeof max_alloc, &max_alloc, NULL);
    if (max_alloc && max_alloc < SIZE_MAX / 2) {
        int rc = lg_cl_buffer_recreate(&node, &b, (size_t)max_alloc * 2, 0);
        CHECKF(rc < 0 && has("clCreateBuffer") && has("CL_INVALID_BUFFER_SIZE") && !b.mem,
               "too large: %d: %s", rc, devtest_errors);
    }
    /* remade per frame, destroyed: back at zero */
    for (int f = 0; f < 5; f++)
        CHECK(lg_cl_buffer_recreate(&node, &b, 256u << f, 0) == 0);
    lg_cl_buffer_destroy(&node, &b);
    CHECKF(b.mem == NULL && b.size == 0 && b.flags == 0, "destroy left %p", (void *)b.mem);
    lg_cl_buffer_destroy(&node, &b);
    lg_cl_buffer zero = { 0 };
    lg_cl_buffer_destroy(&node, &zero);
    CHECKF(live == live0, "live %lld bytes after destroy", (long long)(live - live0));
    CHECKF(allocs - allocs0 == frees - frees0, "%d allocations, %d frees", allocs - allocs0,
           frees - frees0);
}

int main(void)
{
    char err[512] = "";
    if (lg_cl_device_create(&dev, err, sizeof err)) {
        printf("SKIP: no CL device: %s\n", err);
        return check_skip("cl_pass");
    }
    printf("cl: %s\n", lg_cl_device_description(dev));
    const lg_host_api *base = devtest_node()->host; /* its log and error */
    api = *base;
    api.cl_context = t_cl_context;
    api.cl_queue = t_cl_queue;
    api.cl_device = t_cl_device;
    api.cl_program = t_cl_program;
    api.cl_profile = t_cl_profile;
    api.map_cl = t_map_cl;
    api.account_alloc = t_account_alloc;
    api.account_free = t_account_free;
    node = (lg_node){ .host = &api, .name = "test" };

    test_run();
    test_unset_and_resources();
    test_create_errors();
    test_buffers();
    CHECKF(live == 0 && allocs == frees,
           "account after every test: live %lld, %d allocations, "
           "%d frees",
           (long long)live, allocs, frees);
    lg_cl_device_destroy(&dev);
    return check_report("cl_pass");
}
