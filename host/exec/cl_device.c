/* The CL device: the first platform with a usable device, one context, one in-order
 * queue with profiling, and a per-process program cache. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "lightgraph/cl.h"
#include "exec/device.h"
#include "lightgraph/types.h"
#include "base/util.h"

typedef struct cl_cached_program {
    lg_digest key;
    cl_program program;
} cl_cached_program;

struct lg_cl_dev {
    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue;
    char description[256];
    /* A handful of programs per process: a linear search is the right size. */
    cl_cached_program *programs;
    size_t nprograms, cap;
};

/* Device types in order of preference within a platform. */
static const cl_device_type preferred_types[] = {
    CL_DEVICE_TYPE_GPU,
    CL_DEVICE_TYPE_ACCELERATOR,
    CL_DEVICE_TYPE_CPU,
    CL_DEVICE_TYPE_CUSTOM,
};

static char *platform_string(cl_platform_id p, cl_platform_info what)
{
    size_t n = 0;
    if (clGetPlatformInfo(p, what, 0, NULL, &n) != CL_SUCCESS || n == 0)
        return lg_xstrdup("?");
    char *s = lg_xmalloc(n + 1);
    if (clGetPlatformInfo(p, what, n, s, NULL) != CL_SUCCESS)
        s[0] = '\0';
    s[n] = '\0';
    return s;
}

static char *device_string(cl_device_id d, cl_device_info what)
{
    size_t n = 0;
    if (clGetDeviceInfo(d, what, 0, NULL, &n) != CL_SUCCESS || n == 0)
        return lg_xstrdup("?");
    char *s = lg_xmalloc(n + 1);
    if (clGetDeviceInfo(d, what, n, s, NULL) != CL_SUCCESS)
        s[0] = '\0';
    s[n] = '\0';
    return s;
}

/* Available and able to compile OpenCL C: what the program cache needs. */
static bool device_usable(cl_device_id d)
{
    cl_bool available = CL_FALSE, compiler = CL_FALSE;
    if (clGetDeviceInfo(d, CL_DEVICE_AVAILABLE, sizeof available, &available, NULL) ||
        clGetDeviceInfo(d, CL_DEVICE_COMPILER_AVAILABLE, sizeof compiler, &compiler, NULL))
        return false;
    return available && compiler;
}

/* The platform's best usable device, or NULL. */
static cl_device_id pick_device(cl_platform_id p)
{
    for (size_t t = 0; t < sizeof preferred_types / sizeof preferred_types[0]; t++) {
        cl_uint n = 0;
        if (clGetDeviceIDs(p, preferred_types[t], 0, NULL, &n) != CL_SUCCESS || n == 0)
            continue;
        cl_device_id *ids = lg_xcalloc(n, sizeof *ids);
        cl_device_id found = NULL;
        if (clGetDeviceIDs(p, preferred_types[t], n, ids, NULL) == CL_SUCCESS) {
            for (cl_uint i = 0; i < n && !found; i++)
                if (device_usable(ids[i]))
                    found = ids[i];
        }
        free(ids);
        if (found)
            return found;
    }
    return NULL;
}

/* "OpenCL 3.0 PoCL 3.1+debian": the device version's "OpenCL x.y", its first
 * vendor-specific word and the driver version. */
static void describe(lg_cl_dev *dev)
{
    char *platform = platform_string(dev->platform, CL_PLATFORM_NAME);
    char *name = device_string(dev->device, CL_DEVICE_NAME);
    char *version = device_string(dev->device, CL_DEVICE_VERSION);
    char *driver = device_string(dev->device, CL_DRIVER_VERSION);
    char cl[16] = "", vendor[32] = "";
    sscanf(version, "OpenCL %15s %31s", cl, vendor);
    snprintf(dev->description, sizeof dev->description, "%s, %s, OpenCL %s%s%s %s", platform, name,
             cl[0] ? cl : "?", vendor[0] ? " " : "", vendor, driver);
    free(platform);
    free(name);
    free(version);
    free(driver);
}

/* Asynchronous errors the implementation reports for the context (may run on any thread). */
static void CL_CALLBACK context_notify(const char *errinfo, const void *private_info, size_t cb,
                                       void *user_data)
{
    (void)private_info;
    (void)cb;
    (void)user_data;
    lg_hlog(LG_HWARN, "OpenCL: %s", errinfo);
}

int lg_cl_device_create(lg_cl_dev **out, char *err, size_t errlen)
{
    *out = NULL;
    cl_uint nplatforms = 0;
    cl_int e = clGetPlatformIDs(0, NULL, &nplatforms);
    if (e != CL_SUCCESS || nplatforms == 0) {
        if (e != CL_SUCCESS)
            snprintf(err, errlen, "no OpenCL platform (clGetPlatformIDs: %s)", lg_cl_strerror(e));
        else
            snprintf(err, errlen, "no OpenCL platform (clGetPlatformIDs found none)");
        return LG_ERR_DEVICE;
    }
    cl_platform_id *platforms = lg_xcalloc(nplatforms, sizeof *platforms);
    e = clGetPlatformIDs(nplatforms, platforms, NULL);
    if (e != CL_SUCCESS) {
        snprintf(err, errlen, "no OpenCL platform (clGetPlatformIDs: %s)", lg_cl_strerror(e));
        free(platforms);
        return LG_ERR_DEVICE;
    }
    lg_cl_dev *dev = lg_xcalloc(1, sizeof *dev);
    for (cl_uint i = 0; i < nplatforms && !dev->device; i++) {
        dev->device = pick_device(platforms[i]);
        if (dev->device)
            dev->platform = platforms[i];
    }
    free(platforms);
    if (!dev->device) {
        snprintf(err, errlen,
                 "no usable OpenCL device (%u platform%s, no device both "
                 "available and with a compiler)",
                 nplatforms, nplatforms == 1 ? "" : "s");
        free(dev);
        return LG_ERR_DEVICE;
    }

    const cl_context_properties props[] = {
        CL_CONTEXT_PLATFORM,
        (cl_context_properties)dev->platform,
        0,
    };
    dev->context = clCreateContext(props, 1, &dev->device, context_notify, NULL, &e);
    if (!dev->context) {
        snprintf(err, errlen, "OpenCL: clCreateContext: %s", lg_cl_strerror(e));
        lg_cl_device_destroy(&dev);
        return LG_ERR_DEVICE;
    }
    /* clCreateCommandQueue is the 1.2 call; with CL_TARGET_OPENCL_VERSION 120 it is not
     * deprecated and works on every platform. */
    dev->queue = clCreateCommandQueue(dev->context, dev->device, CL_QUEUE_PROFILING_ENABLE, &e);
    if (!dev->queue) {
        snprintf(err, errlen, "OpenCL: clCreateCommandQueue(profiling): %s", lg_cl_strerror(e));
        lg_cl_device_destroy(&dev);
        return LG_ERR_DEVICE;
    }
    describe(dev);
    *out = dev;
    return 0;
}

void *lg_cl_device_context(const lg_cl_dev *dev)
{
    return dev->context;
}

void *lg_cl_device_queue(const lg_cl_dev *dev)
{
    return dev->queue;
}

void *lg_cl_device_id(const lg_cl_dev *dev)
{
    return dev->device;
}

const char *lg_cl_device_description(const lg_cl_dev *dev)
{
    return dev->description;
}

static char *build_log(cl_program prog, cl_device_id device)
{
    size_t n = 0;
    if (clGetProgramBuildInfo(prog, device, CL_PROGRAM_BUILD_LOG, 0, NULL, &n) != CL_SUCCESS)
        return lg_xstrdup("");
    char *log = lg_xmalloc(n + 1);
    if (clGetProgramBuildInfo(prog, device, CL_PROGRAM_BUILD_LOG, n, log, NULL) != CL_SUCCESS)
        n = 0;
    log[n] = '\0';
    /* Drop trailing blank lines and NULs. */
    size_t len = strlen(log);
    while (len > 0 && (log[len - 1] == '\n' || log[len - 1] == ' ' || log[len - 1] == '\r'))
        log[--len] = '\0';
    return log;
}

void *lg_cl_device_program(lg_cl_dev *dev, const char *name, const char *source,
                           const char *options, char **log)
{
    if (log)
        *log = NULL;
    if (!name)
        name = "<unnamed>";
    if (!options)
        options = "";
    if (!source) {
        if (log)
            *log = lg_xasprintf("%s: build failed: no source", name);
        return NULL;
    }
    lg_digest key;
    lg_digest_init(&key);
    lg_digest_add_str(&key, name);
    lg_digest_add_str(&key, source);
    lg_digest_add_str(&key, options);
    for (size_t i = 0; i < dev->nprograms; i++)
        if (memcmp(&dev->programs[i].key, &key, sizeof key) == 0)
            return dev->programs[i].program;

    /* A #line directive names the file in the compiler's messages (PoCL would otherwise
     * show the path of its temporary copy) without moving the line numbers. */
    char *line = NULL;
    if (!strpbrk(name, "\"\\\n"))
        line = lg_xasprintf("#line 1 \"%s\"\n", name);
    const char *strings[2] = { line ? line : "", source };
    cl_int e;
    cl_program prog = clCreateProgramWithSource(dev->context, 2, strings, NULL, &e);
    free(line);
    if (!prog) {
        if (log)
            *log = lg_xasprintf("%s: build failed: clCreateProgramWithSource: %s (%d)", name,
                                lg_cl_strerror(e), e);
        return NULL;
    }
    e = clBuildProgram(prog, 1, &dev->device, options, NULL, NULL);
    if (e != CL_SUCCESS) {
        char *text = build_log(prog, dev->device);
        if (log) {
            if (e == CL_BUILD_PROGRAM_FAILURE)
                *log = lg_xasprintf("%s: build failed:\n%s", name, text);
            else
                /* Bad options and the like: the log may be empty, the code says why. */
                *log = lg_xasprintf("%s: build failed: clBuildProgram(options \"%s\"): %s "
                                    "(%d)%s%s",
                                    name, options, lg_cl_strerror(e), e, text[0] ? "\n" : "", text);
        }
        free(text);
        clReleaseProgram(prog);
        return NULL;
    }
    char *text = build_log(prog, dev->device);
    if (text[0])
        lg_hlog(LG_HDEBUG, "%s: OpenCL build log:\n%s", name, text);
    free(text);

    if (dev->nprograms == dev->cap) {
        dev->cap = dev->cap ? dev->cap * 2 : 8;
        dev->programs = lg_xrealloc(dev->programs, dev->cap * sizeof *dev->programs);
    }
    dev->programs[dev->nprograms++] = (cl_cached_program){ key, prog };
    return prog;
}

void lg_cl_device_destroy(lg_cl_dev **pdev)
{
    if (!pdev || !*pdev)
        return;
    lg_cl_dev *dev = *pdev;
    if (dev->queue) {
        clFinish(dev->queue);
        clReleaseCommandQueue(dev->queue);
    }
    for (size_t i = 0; i < dev->nprograms; i++)
        clReleaseProgram(dev->programs[i].program);
    free(dev->programs);
    if (dev->context)
        clReleaseContext(dev->context);
    free(dev);
    *pdev = NULL;
}
