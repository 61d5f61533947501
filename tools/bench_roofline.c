/*
 * lg_bench_roofline: how close the reinhard node's kernels come to the memory bandwidth
 * of this machine, measured in one run (tools/bench_reinhard.py prints the table).
 *
 *   lg_bench_roofline IMAGE.exr [--repeat N] [--backends cpu,gl,cl] [--triad-mib M]
 *
 * Prints one JSON object on stdout:
 *   threads     the CPU pool's size (LIGHTGRAPH_THREADS, else the online CPUs)
 *   triad       STREAM's triad a[i] = b[i] + s c[i] over three arrays of doubles, M MiB
 *               each (default 256: far beyond any last-level cache), threaded through the
 *               host's pool with that many threads and first-touched by it; GB/s counts
 *               24 bytes per element (STREAM's convention: no write-allocate traffic),
 *               best of N runs, as STREAM reports
 *   rows        per backend (cpu, cl, gl) and kernel: the bytes the kernel must touch
 *               (reduce: read the image; map: read it and write the output; passes: both,
 *               i.e. the image read twice, which a two-pass operator on an image larger
 *               than the caches cannot avoid) and its time, median of N runs
 *
 * How each backend is timed, with the plugin's own code and launch geometry
 * (plugins/reinhard/reinhard_launch.h):
 *   cpu  wall time of lg_rh_cpu_reduce / lg_rh_cpu_map (reinhard_cpu.c) on the pool;
 *   cl   the kernels' CL profiling events (start to end), reduce = stage 1 + stage 2;
 *   gl   wall time around each pass's dispatches followed by glFinish (llvmpipe's timer
 *        queries do not measure compute dispatches).
 * The input stays on the device; uploads and downloads are not timed (the node's per
 * frame time through the host is the "node" row of bench_reinhard.py).
 *
 * Exit status 0, or 1 with a message on stderr. A backend whose device cannot be made is
 * reported in the JSON ("skipped": reason), not silently left out.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "exec/device.h"
#include "base/pool.h"
#include "bench_triad.h"
#include "base/util.h"

#include "lightgraph/image.h"

#include "reinhard_cpu.h"
#include "reinhard_launch.h"
#include "reinhard.cl.h"
#include "reinhard_map.comp.h"
#include "reinhard_reduce.comp.h"

static lg_pool *pool;

static int pfor(void *pctx, size_t n, size_t grain,
                void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk), void *ctx)
{
    return lg_pool_run(pctx, n, grain, fn, ctx);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static double minimum(const double *v, int n)
{
    double m = v[0];
    for (int i = 1; i < n; i++)
        m = v[i] < m ? v[i] : m;
    return m;
}

/* ---- output ---------------------------------------------------------------------------------- */

static int rows_printed;

/* Times are the median and the best of the runs (ms; `v` is sorted here). */
static void row(const char *backend, const char *kernel, double bytes, double *v, int n)
{
    double best = minimum(v, n), med = median(v, n);
    printf("%s\n    {\"backend\": \"%s\", \"kernel\": \"%s\", \"bytes\": %.0f, \"ms\": %.4f, "
           "\"best_ms\": %.4f}",
           rows_printed++ ? "," : "", backend, kernel, bytes, med, best);
}

static void skipped(const char *backend, const char *why)
{
    printf("%s\n    {\"backend\": \"%s\", \"skipped\": \"", rows_printed++ ? "," : "", backend);
    for (const char *p = why; *p; p++)
        if (*p == '"' || *p == '\\')
            printf("\\%c", *p);
        else if ((unsigned char)*p >= 0x20)
            putchar(*p);
    printf("\"}");
}

/* ---- cpu ------------------------------------------------------------------------------------- */

static const lg_rh_params params = {
    .mode = LG_RH_LUMINANCE, .w = { 0.2126f, 0.7152f, 0.0722f }, .delta = 1e-4, .white = 0.0
};

static int bench_cpu(const lg_image *img, int repeat)
{
    size_t npx = (size_t)img->width * img->height;
    float *out = malloc(npx * 16);
    lg_rh_stats *slots = calloc(lg_rh_cpu_chunks(img->width, img->height), sizeof *slots);
    if (!out || !slots) {
        fprintf(stderr, "lg_bench_roofline: out of memory\n");
        return 1;
    }
    lg_rh_image in = { img->pixels, img->width, img->width, img->height, false };
    double *t_red = calloc((size_t)repeat, sizeof(double)),
           *t_map = calloc((size_t)repeat, sizeof(double));
    double *t_all = calloc((size_t)repeat, sizeof(double));
    lg_rh_stats s;
    lg_rh_cpu_map(&in, out, img->width, 1.0f, &params, pfor, pool); /* first touch */
    for (int r = 0; r < repeat; r++) {
        double t0 = lg_mono_now();
        lg_rh_cpu_reduce(&in, &params, slots, pfor, pool, &s);
        double t1 = lg_mono_now();
        double lavg = 1.0;
        lg_rh_log_average(&s, &lavg);
        lg_rh_cpu_map(&in, out, img->width, (float)(0.18 / lavg), &params, pfor, pool);
        double t2 = lg_mono_now();
        t_red[r] = (t1 - t0) * 1e3;
        t_map[r] = (t2 - t1) * 1e3;
        t_all[r] = (t2 - t0) * 1e3;
    }
    row("cpu", "reduce", 16.0 * npx, t_red, repeat);
    row("cpu", "map", 32.0 * npx, t_map, repeat);
    row("cpu", "passes", 48.0 * npx, t_all, repeat);
    free(t_red);
    free(t_map);
    free(t_all);
    free(slots);
    free(out);
    return 0;
}

/* ---- cl -------------------------------------------------------------------------------------- */

static double ev_ms(cl_event e)
{
    cl_ulong a = 0, b = 0;
    clWaitForEvents(1, &e);
    clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_START, sizeof a, &a, NULL);
    clGetEventProfilingInfo(e, CL_PROFILING_COMMAND_END, sizeof b, &b, NULL);
    clReleaseEvent(e);
    return (double)(b - a) * 1e-6;
}

#define CLCHECK(call, what)                                                                        \
    do {                                                                                           \
        cl_int e_ = (call);                                                                        \
        if (e_) {                                                                                  \
            snprintf(why, sizeof why, "%s failed (%d)", what, e_);                                 \
            goto fail;                                                                             \
        }                                                                                          \
    } while (0)

static void bench_cl(const lg_image *img, int repeat)
{
    char why[1024] = "";
    lg_cl_dev *dev = NULL;
    cl_kernel kr = NULL, kf = NULL, km = NULL;
    cl_mem min = NULL, mout = NULL, mpart = NULL, mres = NULL;
    double *t_red = calloc((size_t)repeat, sizeof(double)),
           *t_map = calloc((size_t)repeat, sizeof(double));
    double *t_all = calloc((size_t)repeat, sizeof(double));
    if (lg_cl_device_create(&dev, why, sizeof why)) {
        skipped("cl", why);
        goto done;
    }
    cl_context ctx = lg_cl_device_context(dev);
    cl_command_queue q = lg_cl_device_queue(dev);
    char opts[160], *log = NULL;
    snprintf(opts, sizeof opts, "-cl-std=CL1.2 -DLG_LOCAL=%u -DLG_MAP_LOCAL=%u -DLG_PPI=%u",
             RH_GROUP, RH_CL_MAP_LOCAL, RH_CL_PPI);
    cl_program prog = lg_cl_device_program(dev, lg_src_reinhard_cl_file, lg_src_reinhard_cl, opts,
                                           &log);
    if (!prog) {
        snprintf(why, sizeof why, "%s", log ? log : "build failed");
        free(log);
        goto fail;
    }
    free(log);
    cl_int err;
    kr = clCreateKernel(prog, "rh_reduce", &err);
    CLCHECK(err, "clCreateKernel(rh_reduce)");
    kf = clCreateKernel(prog, "rh_reduce_final", &err);
    CLCHECK(err, "clCreateKernel(rh_reduce_final)");
    km = clCreateKernel(prog, "rh_map", &err);
    CLCHECK(err, "clCreateKernel(rh_map)");
    cl_uint npx = img->width * img->height;
    min = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)npx * 16,
                         img->pixels, &err);
    CLCHECK(err, "clCreateBuffer(in)");
    mout = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)npx * 16, NULL, &err);
    CLCHECK(err, "clCreateBuffer(out)");
    mpart = clCreateBuffer(ctx, CL_MEM_READ_WRITE, rh_cl_partials(npx) * sizeof(rh_partial), NULL,
                           &err);
    CLCHECK(err, "clCreateBuffer(partials)");
    rh_result zero;
    memset(&zero, 0, sizeof zero);
    mres = clCreateBuffer(ctx, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof zero, &zero, &err);
    CLCHECK(err, "clCreateBuffer(result)");

    cl_uint groups = rh_cl_groups(npx), partials = rh_cl_partials(npx);
    cl_float delta = (cl_float)params.delta, key = 0.18f, k = 0.0f, from = 0.0f, inv_w2 = 0.0f;
    cl_int adapt = 0, reset = 0, mode = 0;
    cl_float4 w = { { params.w[0], params.w[1], params.w[2], 0.0f } };
    CLCHECK(clSetKernelArg(kr, 0, sizeof min, &min), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kr, 1, sizeof npx, &npx), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kr, 2, sizeof delta, &delta), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kr, 3, sizeof w, &w), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kr, 4, sizeof mpart, &mpart), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 0, sizeof mpart, &mpart), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 1, sizeof partials, &partials), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 2, sizeof mres, &mres), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 3, sizeof key, &key), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 4, sizeof adapt, &adapt), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 5, sizeof k, &k), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 6, sizeof from, &from), "clSetKernelArg");
    CLCHECK(clSetKernelArg(kf, 7, sizeof reset, &reset), "clSetKernelArg");
    CLCHECK(clSetKernelArg(km, 0, sizeof min, &min), "clSetKernelArg");
    CLCHECK(clSetKernelArg(km, 1, sizeof mout, &mout), "clSetKernelArg");
    CLCHECK(clSetKernelArg(km, 2, sizeof npx, &npx), "clSetKernelArg");
    CLCHECK(clSetKernelArg(km, 3, sizeof mres, &mres), "clSetKernelArg");
    CLCHECK(clSetKernelArg(km, 4, sizeof inv_w2, &inv_w2), "clSetKernelArg");
    CLCHECK(clSetKernelArg(km, 5, sizeof mode, &mode), "clSetKernelArg");
    CLCHECK(clSetKernelArg(km, 6, sizeof w, &w), "clSetKernelArg");
    size_t l_red = RH_GROUP, g_red = (size_t)groups * RH_GROUP, g_fin = RH_GROUP;
    size_t l_map = RH_CL_MAP_LOCAL, g_map = rh_cl_map_items(npx);
    for (int r = -1; r < repeat;
         r++) { /* r = -1: warm-up (first launch compiles work-group code) */
        cl_event e[3];
        CLCHECK(clEnqueueNDRangeKernel(q, kr, 1, NULL, &g_red, &l_red, 0, NULL, &e[0]),
                "rh_reduce");
        CLCHECK(clEnqueueNDRangeKernel(q, kf, 1, NULL, &g_fin, &l_red, 0, NULL, &e[1]),
                "rh_reduce_final");
        CLCHECK(clEnqueueNDRangeKernel(q, km, 1, NULL, &g_map, &l_map, 0, NULL, &e[2]), "rh_map");
        CLCHECK(clFinish(q), "clFinish");
        double a0 = ev_ms(e[0]), a1 = ev_ms(e[1]), a = a0 + a1, b = ev_ms(e[2]);
        if (getenv("LG_BENCH_VERBOSE"))
            fprintf(stderr, "cl: stage 1 %.3f ms, stage 2 %.3f ms, map %.3f ms\n", a0, a1, b);
        if (r >= 0) {
            t_red[r] = a;
            t_map[r] = b;
            t_all[r] = a + b;
        }
    }
    row("cl", "reduce", 16.0 * npx, t_red, repeat);
    row("cl", "map", 32.0 * npx, t_map, repeat);
    row("cl", "passes", 48.0 * npx, t_all, repeat);
    goto done;
fail:
    skipped("cl", why);
done:
    if (kr)
        clReleaseKernel(kr);
    if (kf)
        clReleaseKernel(kf);
    if (km)
        clReleaseKernel(km);
    if (min)
        clReleaseMemObject(min);
    if (mout)
        clReleaseMemObject(mout);
    if (mpart)
        clReleaseMemObject(mpart);
    if (mres)
        clReleaseMemObject(mres);
    lg_cl_device_destroy(&dev);
    free(t_red);
    free(t_map);
    free(t_all);
}

/* ---- gl -------------------------------------------------------------------------------------- */

/* Compiles one compute shader with `defines` after its #version line. */
static GLuint gl_program(const GladGLContext *gl, const char *src, const char *defines, char *why,
                         size_t whylen)
{
    const char *nl = strchr(src, '\n');
    if (!nl) {
        snprintf(why, whylen, "shader without a #version line");
        return 0;
    }
    int vlen = (int)(nl + 1 - src);
    const char *parts[3] = { src, defines, nl + 1 };
    GLint lens[3] = { vlen, (GLint)strlen(defines), (GLint)strlen(nl + 1) };
    GLuint sh = gl->CreateShader(GL_COMPUTE_SHADER);
    gl->ShaderSource(sh, 3, parts, lens);
    gl->CompileShader(sh);
    GLint ok = 0;
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        gl->GetShaderInfoLog(sh, (GLsizei)whylen, NULL, why);
        gl->DeleteShader(sh);
        return 0;
    }
    GLuint p = gl->CreateProgram();
    gl->AttachShader(p, sh);
    gl->LinkProgram(p);
    gl->DeleteShader(sh);
    gl->GetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        gl->GetProgramInfoLog(p, (GLsizei)whylen, NULL, why);
        gl->DeleteProgram(p);
        return 0;
    }
    return p;
}

static void bench_gl(const lg_image *img, int repeat)
{
    char why[2048] = "";
    lg_gl_device *dev = NULL;
    double *t_red = calloc((size_t)repeat, sizeof(double)),
           *t_map = calloc((size_t)repeat, sizeof(double));
    double *t_all = calloc((size_t)repeat, sizeof(double));
    if (lg_gl_device_create(&dev, "osmesa", why, sizeof why)) {
        skipped("gl", why);
        goto done;
    }
    const GladGLContext *gl = lg_gl_device_table(dev);
    GLuint p1 = gl_program(gl, lg_src_reinhard_reduce_comp,
                           "#define LG_STAGE 1\n#define LG_IN_FORMAT rgba32f\n", why, sizeof why);
    GLuint p2 = p1 ? gl_program(gl, lg_src_reinhard_reduce_comp, "#define LG_STAGE 2\n", why,
                                sizeof why)
                   : 0;
    GLuint pm = p2 ? gl_program(gl, lg_src_reinhard_map_comp, "#define LG_IN_FORMAT rgba32f\n", why,
                                sizeof why)
                   : 0;
    if (!pm) {
        skipped("gl", why);
        goto done;
    }
    uint32_t w = img->width, h = img->height;
    GLuint tex[2], buf[2];
    gl->CreateTextures(GL_TEXTURE_2D, 2, tex);
    gl->TextureStorage2D(tex[0], 1, GL_RGBA32F, (GLsizei)w, (GLsizei)h);
    gl->TextureStorage2D(tex[1], 1, GL_RGBA32F, (GLsizei)w, (GLsizei)h);
    gl->TextureSubImage2D(tex[0], 0, 0, 0, (GLsizei)w, (GLsizei)h, GL_RGBA, GL_FLOAT, img->pixels);
    rh_result zero;
    memset(&zero, 0, sizeof zero);
    gl->CreateBuffers(2, buf);
    gl->NamedBufferData(buf[0], RH_MAX_GROUPS * sizeof(rh_partial), NULL, GL_DYNAMIC_COPY);
    gl->NamedBufferData(buf[1], sizeof zero, &zero, GL_DYNAMIC_COPY);
    uint32_t cols = rh_gl_cols(w), rows = rh_gl_rows(w, h);
    gl->Finish();
    for (int r = -1; r < repeat; r++) {
        double t0 = lg_mono_now();
        /* as rh_execute_gl dispatches them */
        gl->UseProgram(p1);
        gl->BindImageTexture(0, tex[0], 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf[0]);
        gl->Uniform2i(0, (GLint)w, (GLint)h);
        gl->Uniform1f(1, (float)params.delta);
        gl->Uniform3f(2, params.w[0], params.w[1], params.w[2]);
        gl->DispatchCompute(cols, rows, 1);
        gl->MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gl->UseProgram(p2);
        gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buf[1]);
        gl->Uniform1ui(0, cols * rows);
        gl->Uniform1f(1, 0.18f);
        gl->Uniform1i(2, 0);
        gl->Uniform1f(3, 0.0f);
        gl->Uniform1f(4, 0.0f);
        gl->Uniform1i(5, 0);
        gl->DispatchCompute(1, 1, 1);
        gl->MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        gl->Finish();
        double t1 = lg_mono_now();
        gl->UseProgram(pm);
        gl->BindImageTexture(1, tex[1], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        gl->Uniform2i(0, (GLint)w, (GLint)h);
        gl->Uniform1f(2, 0.0f);
        gl->Uniform1i(3, 0);
        gl->Uniform3f(4, params.w[0], params.w[1], params.w[2]);
        gl->DispatchCompute((w + RH_GL_MAP_X - 1) / RH_GL_MAP_X,
                            (h + RH_GL_MAP_Y - 1) / RH_GL_MAP_Y, 1);
        double t_issued = lg_mono_now();
        gl->MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        gl->Finish();
        double t2 = lg_mono_now();
        if (getenv("LG_BENCH_VERBOSE"))
            fprintf(stderr,
                    "gl: reduce %.3f ms; map dispatch returned after %.3f ms, "
                    "finished after %.3f ms\n",
                    (t1 - t0) * 1e3, (t_issued - t1) * 1e3, (t2 - t1) * 1e3);
        if (r >= 0) {
            t_red[r] = (t1 - t0) * 1e3;
            t_map[r] = (t2 - t1) * 1e3;
            t_all[r] = (t2 - t0) * 1e3;
        }
    }
    GLenum e = gl->GetError();
    if (e != GL_NO_ERROR) {
        snprintf(why, sizeof why, "GL error 0x%04x", e);
        skipped("gl", why);
    } else {
        double npx = (double)w * h;
        row("gl", "reduce", 16.0 * npx, t_red, repeat);
        row("gl", "map", 32.0 * npx, t_map, repeat);
        row("gl", "passes", 48.0 * npx, t_all, repeat);
    }
    gl->UseProgram(0);
    gl->DeleteProgram(p1);
    gl->DeleteProgram(p2);
    gl->DeleteProgram(pm);
    gl->DeleteTextures(2, tex);
    gl->DeleteBuffers(2, buf);
done:
    lg_gl_device_destroy(&dev);
    free(t_red);
    free(t_map);
    free(t_all);
}

int main(int argc, char **argv)
{
    const char *path = NULL, *backends = "cpu,cl,gl";
    int repeat = 9;
    size_t triad_mib = 256;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            repeat = atoi(argv[++i]);
        else if (strcmp(argv[i], "--backends") == 0 && i + 1 < argc)
            backends = argv[++i];
        else if (strcmp(argv[i], "--triad-mib") == 0 && i + 1 < argc)
            triad_mib = (size_t)atol(argv[++i]);
        else if (!path && argv[i][0] != '-')
            path = argv[i];
        else {
            fprintf(stderr, "usage: lg_bench_roofline IMAGE.exr [--repeat N] "
                            "[--backends cpu,gl,cl] [--triad-mib M]\n");
            return 2;
        }
    }
    if (!path || repeat < 1 || triad_mib < 1) {
        fprintf(stderr, "usage: lg_bench_roofline IMAGE.exr [--repeat N] [--backends cpu,gl,cl] "
                        "[--triad-mib M]\n");
        return 2;
    }
    char err[1024];
    lg_image img;
    if (lg_image_read(path, LG_READ_RADIANCE, &img, NULL, err, sizeof err)) {
        fprintf(stderr, "lg_bench_roofline: %s\n", err);
        return 1;
    }
    char *warning = NULL;
    pool = lg_pool_new(lg_pool_configured_size(&warning), NULL);
    if (warning) {
        fprintf(stderr, "lg_bench_roofline: %s\n", warning);
        free(warning);
    }
    double gbs, triad_ms;
    if (lg_bench_triad(pool, triad_mib, repeat, "lg_bench_roofline", &gbs, &triad_ms))
        return 1;
    printf("{\n  \"threads\": %u,\n  \"width\": %u, \"height\": %u,\n"
           "  \"triad\": {\"mib_per_array\": %zu, \"ms\": %.4f, \"gbs\": %.3f},\n  \"rows\": [",
           lg_pool_size(pool), img.width, img.height, triad_mib, triad_ms, gbs);
    int rc = 0;
    if (strstr(backends, "cpu"))
        rc |= bench_cpu(&img, repeat);
    if (strstr(backends, "cl"))
        bench_cl(&img, repeat);
    if (strstr(backends, "gl"))
        bench_gl(&img, repeat);
    printf("\n  ]\n}\n");
    lg_pool_free(pool);
    lg_image_free(&img);
    return rc;
}
