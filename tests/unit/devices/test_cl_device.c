/* The CL device: creation, queue properties, a kernel built through the program cache and
 * run with a profiling event, build failures with their log, cache identity, lg_cl_fail.
 * Exits 77 if no device can be made. */
#include <string.h>

#include "lightgraph/cl.h"
#include "exec/device.h"
#include "devtest.h"

static const char square_cl[] = "kernel void square(global const float *a, global float *b)\n"
                                "{\n"
                                "    size_t i = get_global_id(0);\n"
                                "    b[i] = a[i] * a[i] + OFFSET;\n"
                                "}\n";

static const char bad_cl[] = "kernel void broken(global float *a)\n"
                             "{\n"
                             "    a[0] = undeclared_thing;\n"
                             "}\n";

enum { N = 1024 };

static void test_run(lg_cl_dev *dev, cl_program prog)
{
    cl_context ctx = lg_cl_device_context(dev);
    cl_command_queue q = lg_cl_device_queue(dev);
    cl_int e;
    cl_kernel k = clCreateKernel(prog, "square", &e);
    CHECKF(k != NULL, "clCreateKernel: %s", lg_cl_strerror(e));
    if (!k)
        return;
    static float a[N], b[N];
    for (int i = 0; i < N; i++)
        a[i] = (float)(i - N / 2) * 0.25f;
    cl_mem ma = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof a, a, &e);
    CHECKF(ma != NULL, "clCreateBuffer: %s", lg_cl_strerror(e));
    cl_mem mb = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, sizeof b, NULL, &e);
    CHECKF(mb != NULL, "clCreateBuffer: %s", lg_cl_strerror(e));
    if (!ma || !mb)
        goto out;
    clSetKernelArg(k, 0, sizeof ma, &ma);
    clSetKernelArg(k, 1, sizeof mb, &mb);
    size_t global = N;
    cl_event ev = NULL;
    double t0 = devtest_now();
    e = clEnqueueNDRangeKernel(q, k, 1, NULL, &global, NULL, 0, NULL, &ev);
    CHECKF(e == CL_SUCCESS, "clEnqueueNDRangeKernel: %s", lg_cl_strerror(e));
    e = clEnqueueReadBuffer(q, mb, CL_TRUE, 0, sizeof b, b, 0, NULL, NULL);
    CHECKF(e == CL_SUCCESS, "clEnqueueReadBuffer: %s", lg_cl_strerror(e));
    /* PoCL compiles the kernel for the launch's work-group size at the first enqueue. */
    printf("cl: first launch and read back in %.1f ms\n", (devtest_now() - t0) * 1e3);
    int bad = 0;
    for (int i = 0; i < N; i++) {
        float want = a[i] * a[i] + 0.5f;
        if (b[i] != want && bad++ < 4)
            CHECKF(0, "b[%d] = %g, expected %g", i, b[i], want);
    }
    CHECKF(bad == 0, "%d of %d values wrong", bad, N);
    if (ev) {
        cl_ulong start = 0, end = 0;
        cl_int e1 = clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_START, sizeof start, &start,
                                            NULL);
        cl_int e2 = clGetEventProfilingInfo(ev, CL_PROFILING_COMMAND_END, sizeof end, &end, NULL);
        CHECKF(e1 == CL_SUCCESS && e2 == CL_SUCCESS, "profiling info: %s / %s", lg_cl_strerror(e1),
               lg_cl_strerror(e2));
        CHECKF(end >= start, "profiling: end %llu < start %llu", (unsigned long long)end,
               (unsigned long long)start);
        printf("kernel over %d items: %.3f ms (profiling event)\n", N, (end - start) * 1e-6);
        clReleaseEvent(ev);
    }
out:
    if (ma)
        clReleaseMemObject(ma);
    if (mb)
        clReleaseMemObject(mb);
    clReleaseKernel(k);
}

int main(void)
{
    char err[512] = "";
    lg_cl_dev *dev = NULL;
    double t0 = devtest_now();
    int rc = lg_cl_device_create(&dev, err, sizeof err);
    double t1 = devtest_now();
    if (rc) {
        printf("SKIP: no CL device: %s\n", err);
        CHECKF(dev == NULL && rc == LG_ERR_DEVICE && err[0], "bad failure: rc %d", rc);
        return check_skip("cl_device");
    }
    printf("cl: %s\n", lg_cl_device_description(dev));
    printf("cl: context and queue created in %.1f ms\n", (t1 - t0) * 1e3);
    CHECKF(lg_cl_device_context(dev) && lg_cl_device_queue(dev) && lg_cl_device_id(dev),
           "missing handles");

    cl_command_queue_properties props = 0;
    cl_int e = clGetCommandQueueInfo(lg_cl_device_queue(dev), CL_QUEUE_PROPERTIES, sizeof props,
                                     &props, NULL);
    CHECKF(e == CL_SUCCESS && (props & CL_QUEUE_PROFILING_ENABLE), "queue properties 0x%llx",
           (unsigned long long)props);
    CHECKF(!(props & CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE), "queue is out of order");

    char *log = NULL;
    t0 = devtest_now();
    cl_program prog = lg_cl_device_program(dev, "square.cl", square_cl, "-DOFFSET=0.5f", &log);
    t1 = devtest_now();
    CHECKF(prog != NULL, "build failed: %s", log ? log : "(no log)");
    CHECKF(log == NULL, "log set on success: %s", log);
    free(log);
    log = NULL;
    printf("cl: square.cl built in %.1f ms\n", (t1 - t0) * 1e3);
    if (prog)
        test_run(dev, prog);

    /* The cache: same name, source and options give the same program... */
    t0 = devtest_now();
    cl_program again = lg_cl_device_program(dev, "square.cl", square_cl, "-DOFFSET=0.5f", &log);
    t1 = devtest_now();
    CHECKF(again == prog, "cache miss for the same source: %p vs %p", (void *)again, (void *)prog);
    printf("cl: cached lookup in %.3f ms\n", (t1 - t0) * 1e3);
    /* ...other options another one. */
    cl_program other = lg_cl_device_program(dev, "square.cl", square_cl, "-DOFFSET=1.5f", &log);
    CHECKF(other != NULL && other != prog, "other options: %p vs %p", (void *)other, (void *)prog);
    free(log);
    log = NULL;

    /* A compile error: NULL, and the log names the file and carries the compiler's error. */
    cl_program bad = lg_cl_device_program(dev, "bad.cl", bad_cl, NULL, &log);
    CHECKF(bad == NULL, "a broken kernel built");
    CHECKF(log && strncmp(log, "bad.cl: build failed:\n", 22) == 0, "log: %s",
           log ? log : "(null)");
    CHECKF(log && strstr(log, "undeclared_thing") && strstr(log, "error"), "log: %s",
           log ? log : "(null)");
    /* The compiler's messages name the file and the line in it. */
    CHECKF(log && strstr(log, "bad.cl:3:"), "log does not point at bad.cl:3: %s",
           log ? log : "(null)");
    if (log)
        printf("build failure log:\n%s\n", log);
    free(log);
    log = NULL;
    /* A failure is not cached: the same call fails again the same way. */
    bad = lg_cl_device_program(dev, "bad.cl", bad_cl, NULL, &log);
    CHECKF(bad == NULL && log && strstr(log, "undeclared_thing"), "second failure: %s",
           log ? log : "(null)");
    free(log);
    log = NULL;
    /* No source. */
    bad = lg_cl_device_program(dev, "none.cl", NULL, NULL, &log);
    CHECKF(bad == NULL && log && strstr(log, "none.cl: build failed"), "no source: %s",
           log ? log : "(null)");
    free(log);

    /* lg_cl_fail reports through the node. */
    devtest_clear();
    rc = lg_cl_fail(devtest_node(), CL_OUT_OF_RESOURCES, "clEnqueueNDRangeKernel(map)");
    CHECKF(rc == LG_ERR_DEVICE, "lg_cl_fail returned %d", rc);
    CHECKF(strcmp(devtest_errors, "clEnqueueNDRangeKernel(map): CL_OUT_OF_RESOURCES (-5)") == 0,
           "message: %s", devtest_errors);

    lg_cl_device_destroy(&dev);
    CHECKF(dev == NULL, "destroy did not clear the handle");
    lg_cl_device_destroy(&dev);
    lg_cl_device_destroy(NULL);
    return check_report("cl_device");
}
