/*
 * lg_bench_prt_roofline: how close the prt node's dot products come to the memory
 * bandwidth of this machine, measured in one run (issue 10, item 5; plugins/prt/README.md
 * has the figures).
 *
 *   lg_bench_prt_roofline [--vertices N] [--bands B] [--repeat N]
 *                         [--backends cpu,cl,gl,gl-frag1,gl-comp]
 *                         [--triad-mib M] [--json]
 *
 * Defaults: 1,000,000 vertices, 5 bands (25 coefficients), RGB, a random transfer
 * (prt_test_value-like hash, fixed seed), 9 repeats, a 256 MiB triad.
 *
 *   triad   STREAM's a[i] = b[i] + s c[i] over three arrays of doubles, M MiB each, through
 *           the host's pool (first-touched by it), 24 bytes per element, best of N (as
 *           STREAM reports; tools/bench_roofline.c's)
 *   rows    per backend: bytes = transfer read (V x 3 x n^2 x 4) + lighting read
 *           (3 x n^2 x 4) + the vertices image written (texels x 16); the time, median and
 *           best of N; GB/s and the fraction of the triad (median)
 *
 * How each backend is timed, with the plugin's own code and launch geometry
 * (plugins/prt/prt_launch.h, prt_cpu.c, shaders/prt/prt.cl, prt_dot.frag, prt_dot.comp):
 *   cpu  wall time of lg_prt_cpu_range over the pool (chunks of PRT_CPU_GRAIN);
 *   cl   the kernel's CL profiling event (start to end);
 *   gl   wall time around the draw followed by glFinish (prt_dot.frag, the version the
 *        node runs: records read through an RGB32F buffer texture);
 *   gl-frag1  the same through an R32F buffer texture (1 float per fetch), for comparison;
 *   gl-comp   the compute shader prt_dot.comp (the node's version before, and its fallback
 *        for a transfer past GL_MAX_TEXTURE_BUFFER_SIZE, here reading an R32F buffer
 *        texture; LG_PRT_SSBO=1: a storage buffer as the node's fallback does), wall time
 *        around the dispatch and glFinish.
 * gl-frag1 and gl-comp run only when named in --backends.
 * The transfer stays on the device; uploads are not timed (the node maps it once).
 * Prints a table on stderr and one JSON object on stdout. Exit status 0, or 1 with a
 * message. A backend whose device cannot be made is reported ("skipped": reason).
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

#include "lightgraph/transfer.h"

#include "prt.cl.h"
#include "prt_dot.comp.h"
#include "prt_dot.frag.h"
#include "prt_dot.vert.h"
#include "prt_launch.h"

static lg_pool *pool;

typedef struct bench_data {
    uint32_t vertices, n; /* n = coefficients per channel */
    uint32_t texels, tex_w;
    float *transfer, *lighting;
    double bytes;
} bench_data;

typedef struct bench_row {
    const char *backend;
    const char *skipped; /* NULL, or why */
    double ms, best_ms;
} bench_row;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static void summarise(double *v, int n, bench_row *r)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    r->ms = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    r->best_ms = v[0];
}

/* ---- the data -------------------------------------------------------------------------------- */

static float hash_value(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
    return (float)((double)(x >> 40) / (double)(1u << 23) - 1.0);
}

typedef struct fill_ctx {
    float *t;
} fill_ctx;

static void fill_run(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    fill_ctx *f = arg;
    for (size_t i = begin; i < end; i++)
        f->t[i] = hash_value(i);
}

/* The reference value of vertex v, channel c (double), for the spot checks. */
static double reference(const bench_data *d, uint32_t v, uint32_t c)
{
    double s = 0;
    for (uint32_t i = 0; i < d->n; i++)
        s += (double)d->lighting[c * d->n + i] *
             (double)d->transfer[((size_t)v * 3 + c) * d->n + i];
    return s;
}

/* Checks a few vertices and a padding texel of `out` (float4 per texel). */
static const char *verify(const bench_data *d, const float *out)
{
    static char why[256];
    uint32_t probe[4] = { 0, d->vertices / 3, d->vertices / 2 + 7, d->vertices - 1 };
    for (int k = 0; k < 4; k++)
        for (uint32_t c = 0; c < 3; c++) {
            double want = reference(d, probe[k], c), got = out[4 * (size_t)probe[k] + c];
            if (!(fabs(got - want) <= 1e-4 * (1.0 + fabs(want)))) {
                snprintf(why, sizeof why, "wrong result: vertex %u channel %u is %g, not %g",
                         probe[k], c, got, want);
                return why;
            }
        }
    if (d->texels > d->vertices && out[4 * (size_t)d->vertices + 3] != 0.0f) {
        snprintf(why, sizeof why, "the padding texel is not 0");
        return why;
    }
    return NULL;
}

/* ---- cpu ------------------------------------------------------------------------------------- */

static void cpu_chunk(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    lg_prt_cpu_range(ctx, begin, end);
}

static void bench_cpu(const bench_data *d, int repeat, bench_row *row)
{
    float *out = malloc((size_t)d->texels * 16);
    double *ms = calloc((size_t)repeat, sizeof *ms);
    row->backend = "cpu";
    if (!out || !ms) {
        row->skipped = "out of memory";
        free(out);
        free(ms);
        return;
    }
    prt_cpu_job job = { .transfer = d->transfer,
                        .lighting = d->lighting,
                        .n = d->n,
                        .stride = d->n,
                        .vertices = d->vertices,
                        .out = out };
    lg_pool_run(pool, d->texels, PRT_CPU_GRAIN, cpu_chunk, &job); /* first touch */
    for (int r = 0; r < repeat; r++) {
        double t0 = lg_mono_now();
        lg_pool_run(pool, d->texels, PRT_CPU_GRAIN, cpu_chunk, &job);
        ms[r] = (lg_mono_now() - t0) * 1e3;
    }
    row->skipped = verify(d, out);
    summarise(ms, repeat, row);
    free(ms);
    free(out);
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

static char cl_why[1024];

static void bench_cl(const bench_data *d, int repeat, bench_row *row)
{
    row->backend = "cl";
    lg_cl_dev *dev = NULL;
    cl_kernel k = NULL;
    cl_mem mt = NULL, ml = NULL, mr = NULL, mo = NULL;
    float rec[3 * PRT_RECORD_PAD(16 * 16)];
    double *ms = calloc((size_t)repeat, sizeof *ms);
    float *out = malloc((size_t)d->texels * 16);
    cl_int e = 0;
    if (!ms || !out) {
        row->skipped = "out of memory";
        goto done;
    }
    if (lg_cl_device_create(&dev, cl_why, sizeof cl_why)) {
        row->skipped = cl_why;
        goto done;
    }
    cl_context ctx = lg_cl_device_context(dev);
    cl_command_queue q = lg_cl_device_queue(dev);
    char *log = NULL, opts[160];
    prt_cl_options(opts, sizeof opts, d->n, d->n);
    cl_program prog = lg_cl_device_program(dev, lg_src_prt_cl_file, lg_src_prt_cl, opts, &log);
    if (!prog) {
        snprintf(cl_why, sizeof cl_why, "%s", log ? log : "build failed");
        free(log);
        row->skipped = cl_why;
        goto done;
    }
    free(log);
    k = clCreateKernel(prog, "prt_dot", &e);
    size_t tbytes = (size_t)d->vertices * 3 * d->n * sizeof(float);
    if (!e)
        mt = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, tbytes, d->transfer, &e);
    if (!e)
        ml = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                            (size_t)3 * d->n * sizeof(float), d->lighting, &e);
    prt_record_lighting(d->lighting, d->n, d->n, rec);
    if (!e)
        mr = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                            3 * PRT_RECORD_PAD(d->n) * sizeof(float), rec, &e);
    if (!e)
        mo = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)d->texels * 16, NULL, &e);
    cl_uint verts = d->vertices, texels = d->texels;
    if (!e) { /* as prt_dot_cl sets them */
        e |= clSetKernelArg(k, 0, sizeof mt, &mt);
        e |= clSetKernelArg(k, 1, sizeof mr, &mr);
        e |= clSetKernelArg(k, 2, sizeof ml, &ml);
        e |= clSetKernelArg(k, 3, sizeof verts, &verts);
        e |= clSetKernelArg(k, 4, sizeof texels, &texels);
        e |= clSetKernelArg(k, 5, sizeof mo, &mo);
    }
    size_t global = prt_cl_global(texels), local = PRT_CL_LOCAL;
    for (int r = -1; r < repeat && !e; r++) { /* r = -1: warm-up (PoCL compiles then) */
        cl_event ev;
        e = clEnqueueNDRangeKernel(q, k, 1, NULL, &global, &local, 0, NULL, &ev);
        if (!e)
            e = clFinish(q);
        if (!e) {
            double t = ev_ms(ev);
            if (r >= 0)
                ms[r] = t;
        }
    }
    if (!e)
        e = clEnqueueReadBuffer(q, mo, CL_TRUE, 0, (size_t)d->texels * 16, out, 0, NULL, NULL);
    if (e) {
        snprintf(cl_why, sizeof cl_why, "OpenCL error %d", e);
        row->skipped = cl_why;
        goto done;
    }
    row->skipped = verify(d, out);
    summarise(ms, repeat, row);
done:
    if (k)
        clReleaseKernel(k);
    if (mt)
        clReleaseMemObject(mt);
    if (ml)
        clReleaseMemObject(ml);
    if (mr)
        clReleaseMemObject(mr);
    if (mo)
        clReleaseMemObject(mo);
    lg_cl_device_destroy(&dev);
    free(ms);
    free(out);
}

/* ---- gl -------------------------------------------------------------------------------------- */

static char gl_why[2048];

/* Compiles one stage with `defines` after its #version line (as lg_gl_program); 0 and
 * gl_why on failure. */
static GLuint gl_shader(const GladGLContext *gl, GLenum stage, const char *src, const char *defines)
{
    const char *nl = strchr(src, '\n');
    if (!nl) {
        snprintf(gl_why, sizeof gl_why, "shader without a #version line");
        return 0;
    }
    const char *parts[3] = { src, defines, nl + 1 };
    GLint lens[3] = { (GLint)(nl + 1 - src), (GLint)strlen(defines), (GLint)strlen(nl + 1) };
    GLuint sh = gl->CreateShader(stage);
    gl->ShaderSource(sh, 3, parts, lens);
    gl->CompileShader(sh);
    GLint ok = 0;
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        gl->GetShaderInfoLog(sh, (GLsizei)sizeof gl_why, NULL, gl_why);
        gl->DeleteShader(sh);
        return 0;
    }
    return sh;
}

/* Links the stages (a compute shader: fs_src NULL); 0 and gl_why on failure. */
static GLuint gl_program(const GladGLContext *gl, const char *src, const char *fs_src,
                         const char *defines)
{
    GLuint sh[2] = { 0, 0 };
    unsigned ns = fs_src ? 2 : 1;
    sh[0] = gl_shader(gl, fs_src ? GL_VERTEX_SHADER : GL_COMPUTE_SHADER, src, defines);
    if (sh[0] && fs_src)
        sh[1] = gl_shader(gl, GL_FRAGMENT_SHADER, fs_src, defines);
    if (!sh[0] || (fs_src && !sh[1])) {
        if (sh[0])
            gl->DeleteShader(sh[0]);
        return 0;
    }
    GLuint p = gl->CreateProgram();
    for (unsigned i = 0; i < ns; i++) {
        gl->AttachShader(p, sh[i]);
        gl->DeleteShader(sh[i]);
    }
    gl->LinkProgram(p);
    GLint ok = 0;
    gl->GetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        gl->GetProgramInfoLog(p, (GLsizei)sizeof gl_why, NULL, gl_why);
        gl->DeleteProgram(p);
        return 0;
    }
    return p;
}

static void bench_gl_comp(const bench_data *d, int repeat, bench_row *row)
{
    row->backend = "gl-comp";
    lg_gl_device *dev = NULL;
    double *ms = calloc((size_t)repeat, sizeof *ms);
    float *out = malloc((size_t)d->texels * 16);
    if (!ms || !out) {
        row->skipped = "out of memory";
        goto done;
    }
    if (lg_gl_device_create(&dev, "osmesa", gl_why, sizeof gl_why)) {
        row->skipped = gl_why;
        goto done;
    }
    const GladGLContext *gl = lg_gl_device_table(dev);
    char defines[96];
    GLint max_tbo = 0;
    gl->GetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &max_tbo);
    int tbo = (double)d->vertices * 3 * d->n <= (double)max_tbo && !getenv("LG_PRT_SSBO");
    prt_gl_defines(defines, sizeof defines, d->n, d->n, tbo);
    GLuint p = gl_program(gl, lg_src_prt_dot_comp, NULL, defines);
    if (!p) {
        row->skipped = gl_why;
        goto done;
    }
    uint32_t tex_h = d->texels / d->tex_w;
    GLuint tex, buf[2];
    gl->CreateTextures(GL_TEXTURE_2D, 1, &tex);
    gl->TextureStorage2D(tex, 1, GL_RGBA32F, (GLsizei)d->tex_w, (GLsizei)tex_h);
    gl->CreateBuffers(2, buf);
    gl->NamedBufferStorage(buf[0], (GLsizeiptr)((size_t)d->vertices * 3 * d->n * sizeof(float)),
                           d->transfer, 0);
    gl->NamedBufferStorage(buf[1], (GLsizeiptr)(3 * (size_t)d->n * sizeof(float)), d->lighting, 0);
    /* as prt_dot_gl binds and dispatches them */
    gl->UseProgram(p);
    gl->Uniform1ui(gl->GetUniformLocation(p, "u_vertices"), d->vertices);
    gl->Uniform1ui(gl->GetUniformLocation(p, "u_width"), d->tex_w);
    gl->Uniform1ui(gl->GetUniformLocation(p, "u_texels"), d->texels);
    GLuint tb = 0;
    if (tbo) { /* as prt_dot_gl: an R32F buffer texture over the transfer */
        gl->CreateTextures(GL_TEXTURE_BUFFER, 1, &tb);
        gl->TextureBuffer(tb, GL_R32F, buf[0]);
        gl->BindTextureUnit(0, tb);
        gl->Uniform1i(gl->GetUniformLocation(p, "u_transfer"), 0);
    } else {
        gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf[0]);
    }
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buf[1]);
    gl->BindImageTexture(0, tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    uint32_t gx, gy;
    prt_gl_groups(d->texels, &gx, &gy);
    gl->Finish();
    for (int r = -1; r < repeat; r++) {
        double t0 = lg_mono_now();
        gl->DispatchCompute(gx, gy, 1);
        gl->MemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        gl->Finish();
        if (r >= 0)
            ms[r] = (lg_mono_now() - t0) * 1e3;
    }
    gl->GetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)((size_t)d->texels * 16), out);
    GLenum err = gl->GetError();
    if (err != GL_NO_ERROR) {
        snprintf(gl_why, sizeof gl_why, "GL error 0x%04x", err);
        row->skipped = gl_why;
    } else {
        row->skipped = verify(d, out);
        summarise(ms, repeat, row);
    }
    gl->UseProgram(0);
    gl->DeleteProgram(p);
    gl->DeleteTextures(1, &tex);
    if (tb)
        gl->DeleteTextures(1, &tb);
    gl->DeleteBuffers(2, buf);
done:
    lg_gl_device_destroy(&dev);
    free(ms);
    free(out);
}

/* The version the node runs (prt_dot_gl): prt_dot.frag drawn as a full-screen triangle
 * into the `vertices` image, reading the transfer through an RGB32F buffer texture; r32f:
 * through an R32F one (row "gl-frag1"). */
static void bench_gl(const bench_data *d, int repeat, bench_row *row, int r32f)
{
    row->backend = r32f ? "gl-frag1" : "gl";
    lg_gl_device *dev = NULL;
    double *ms = calloc((size_t)repeat, sizeof *ms);
    float *out = malloc((size_t)d->texels * 16);
    if (!ms || !out) {
        row->skipped = "out of memory";
        goto done;
    }
    if (lg_gl_device_create(&dev, "osmesa", gl_why, sizeof gl_why)) {
        row->skipped = gl_why;
        goto done;
    }
    const GladGLContext *gl = lg_gl_device_table(dev);
    GLint max_tbo = 0;
    gl->GetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &max_tbo);
    if (!r32f)
        fprintf(stderr, "gl: GL_MAX_TEXTURE_BUFFER_SIZE %d texels\n", max_tbo);
    if (!prt_gl_frag_fits(d->vertices, r32f ? 3 * d->n : d->n, max_tbo)) {
        snprintf(gl_why, sizeof gl_why, "transfer past GL_MAX_TEXTURE_BUFFER_SIZE (%d)", max_tbo);
        row->skipped = gl_why;
        goto done;
    }
    char defines[96];
    prt_gl_frag_defines(defines, sizeof defines, d->n, d->n, r32f);
    GLuint p = gl_program(gl, lg_src_prt_dot_vert, lg_src_prt_dot_frag, defines);
    if (!p) {
        row->skipped = gl_why;
        goto done;
    }
    uint32_t tex_h = d->texels / d->tex_w;
    GLuint tex, buf, tb, fbo, vao;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &tex);
    gl->TextureStorage2D(tex, 1, GL_RGBA32F, (GLsizei)d->tex_w, (GLsizei)tex_h);
    gl->CreateBuffers(1, &buf);
    gl->NamedBufferStorage(buf, (GLsizeiptr)((size_t)d->vertices * 3 * d->n * sizeof(float)),
                           d->transfer, 0);
    gl->CreateFramebuffers(1, &fbo);
    gl->NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    gl->CreateVertexArrays(1, &vao);
    /* as prt_dot_gl binds and draws them */
    gl->UseProgram(p);
    gl->Uniform1ui(gl->GetUniformLocation(p, "u_vertices"), d->vertices);
    gl->Uniform1ui(gl->GetUniformLocation(p, "u_width"), d->tex_w);
    /* the whole range, as the node draws a static scene (its vertex range since ABI 3.1) */
    gl->Uniform1ui(gl->GetUniformLocation(p, "u_first"), 0);
    gl->Uniform1ui(gl->GetUniformLocation(p, "u_end"), d->vertices);
    gl->Uniform1fv(gl->GetUniformLocation(p, "u_lighting[0]"), (GLsizei)(3 * d->n), d->lighting);
    gl->CreateTextures(GL_TEXTURE_BUFFER, 1, &tb);
    gl->TextureBuffer(tb, r32f ? GL_R32F : GL_RGB32F, buf);
    gl->BindTextureUnit(0, tb); /* the shader's layout(binding = 0) */
    gl->BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl->Viewport(0, 0, (GLsizei)d->tex_w, (GLsizei)tex_h);
    gl->BindVertexArray(vao);
    if (gl->CheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(gl_why, sizeof gl_why, "RGBA32F framebuffer incomplete");
        row->skipped = gl_why;
    }
    gl->Finish();
    for (int r = -1; r < repeat && !row->skipped; r++) {
        double t0 = lg_mono_now();
        gl->DrawArrays(GL_TRIANGLES, 0, 3);
        gl->Finish();
        if (r >= 0)
            ms[r] = (lg_mono_now() - t0) * 1e3;
    }
    gl->GetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)((size_t)d->texels * 16), out);
    GLenum err = gl->GetError();
    if (row->skipped) {
        /* the framebuffer's message */
    } else if (err != GL_NO_ERROR) {
        snprintf(gl_why, sizeof gl_why, "GL error 0x%04x", err);
        row->skipped = gl_why;
    } else {
        row->skipped = verify(d, out);
        summarise(ms, repeat, row);
    }
    gl->BindVertexArray(0);
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl->UseProgram(0);
    gl->DeleteProgram(p);
    gl->DeleteVertexArrays(1, &vao);
    gl->DeleteFramebuffers(1, &fbo);
    gl->DeleteTextures(1, &tex);
    gl->DeleteTextures(1, &tb);
    gl->DeleteBuffers(1, &buf);
done:
    lg_gl_device_destroy(&dev);
    free(ms);
    free(out);
}

/* ---- main ------------------------------------------------------------------------------------ */

/* Whether the comma-separated `list` names `name`. */
static int has_backend(const char *list, const char *name)
{
    size_t len = strlen(name);
    for (const char *p = list; *p;) {
        const char *e = strchr(p, ',');
        size_t l = e ? (size_t)(e - p) : strlen(p);
        if (l == len && strncmp(p, name, len) == 0)
            return 1;
        p += l + (e ? 1 : 0);
    }
    return 0;
}

static int usage(void)
{
    fprintf(stderr, "usage: lg_bench_prt_roofline [--vertices N] [--bands B] [--repeat N] "
                    "[--backends cpu,cl,gl,gl-frag1,gl-comp] [--triad-mib M]\n");
    return 2;
}

int main(int argc, char **argv)
{
    const char *backends = "cpu,cl,gl";
    long vertices = 1000000, bands = 5, repeat = 9, triad_mib = 256;
    for (int i = 1; i < argc; i++) {
        long *dst = NULL;
        if (strcmp(argv[i], "--vertices") == 0)
            dst = &vertices;
        else if (strcmp(argv[i], "--bands") == 0)
            dst = &bands;
        else if (strcmp(argv[i], "--repeat") == 0)
            dst = &repeat;
        else if (strcmp(argv[i], "--triad-mib") == 0)
            dst = &triad_mib;
        else if (strcmp(argv[i], "--backends") == 0 && i + 1 < argc) {
            backends = argv[++i];
            continue;
        } else
            return usage();
        if (i + 1 >= argc)
            return usage();
        char *end;
        *dst = strtol(argv[++i], &end, 10);
        if (*end)
            return usage();
    }
    if (vertices < 1 || vertices > 16000000 || bands < 1 || bands > 16 || repeat < 1 ||
        repeat > 1000 || triad_mib < 1 || triad_mib > 4096) {
        fprintf(stderr, "lg_bench_prt_roofline: vertices 1..16e6, bands 1..16, repeat "
                        "1..1000, triad-mib 1..4096\n");
        return 2;
    }
    char *warning = NULL;
    pool = lg_pool_new(lg_pool_configured_size(&warning), NULL);
    if (warning) {
        fprintf(stderr, "lg_bench_prt_roofline: %s\n", warning);
        free(warning);
    }
    bench_data d = { .vertices = (uint32_t)vertices, .n = (uint32_t)(bands * bands) };
    uint32_t th;
    lg_vertex_image_size(d.vertices, &d.tex_w, &th);
    d.texels = d.tex_w * th;
    size_t nt = (size_t)d.vertices * 3 * d.n;
    d.transfer = malloc(nt * sizeof(float));
    d.lighting = malloc((size_t)3 * d.n * sizeof(float));
    if (!d.transfer || !d.lighting) {
        fprintf(stderr, "lg_bench_prt_roofline: out of memory (%zu MiB of transfer)\n",
                nt * 4 >> 20);
        return 1;
    }
    fill_ctx fc = { d.transfer };
    lg_pool_run(pool, nt, 1u << 16, fill_run, &fc);
    for (uint32_t i = 0; i < 3 * d.n; i++)
        d.lighting[i] = hash_value(0xabcdef00ull + i);
    d.bytes = (double)nt * 4 + 3.0 * d.n * 4 + (double)d.texels * 16;

    double gbs, triad_ms;
    if (lg_bench_triad(pool, (size_t)triad_mib, (int)repeat, "lg_bench_prt_roofline", &gbs,
                       &triad_ms))
        return 1;
    bench_row rows[5];
    int nr = 0;
    memset(rows, 0, sizeof rows);
    if (has_backend(backends, "cpu"))
        bench_cpu(&d, (int)repeat, &rows[nr++]);
    if (has_backend(backends, "cl"))
        bench_cl(&d, (int)repeat, &rows[nr++]);
    if (has_backend(backends, "gl"))
        bench_gl(&d, (int)repeat, &rows[nr++], 0);
    if (has_backend(backends, "gl-frag1"))
        bench_gl(&d, (int)repeat, &rows[nr++], 1);
    if (has_backend(backends, "gl-comp"))
        bench_gl_comp(&d, (int)repeat, &rows[nr++]);

    fprintf(stderr,
            "prt dot products: %u vertices, %u bands (%u coefficients), RGB; %.1f MB "
            "per pass; %u threads\n",
            d.vertices, (uint32_t)bands, d.n, d.bytes / 1e6, lg_pool_size(pool));
    fprintf(stderr, "triad (%ld MiB x 3): %.2f GB/s (best of %ld)\n", triad_mib, gbs, repeat);
    fprintf(stderr, "%-8s %10s %10s %10s %10s\n", "backend", "ms (med)", "ms (best)", "GB/s",
            "of triad");
    printf("{\n  \"threads\": %u, \"vertices\": %u, \"bands\": %ld, \"bytes\": %.0f,\n"
           "  \"triad\": {\"mib_per_array\": %ld, \"ms\": %.4f, \"gbs\": %.3f},\n  \"rows\": [",
           lg_pool_size(pool), d.vertices, bands, d.bytes, triad_mib, triad_ms, gbs);
    int rc = 0;
    for (int i = 0; i < nr; i++) {
        const bench_row *r = &rows[i];
        printf("%s\n    {\"backend\": \"%s\", ", i ? "," : "", r->backend);
        if (r->skipped) {
            rc = 1;
            fprintf(stderr, "%-8s skipped: %s\n", r->backend, r->skipped);
            printf("\"skipped\": \"");
            for (const char *p = r->skipped; *p; p++)
                if (*p == '"' || *p == '\\')
                    printf("\\%c", *p);
                else if ((unsigned char)*p >= 0x20)
                    putchar(*p);
            printf("\"}");
            continue;
        }
        double g = d.bytes / (r->ms * 1e-3) / 1e9;
        fprintf(stderr, "%-8s %10.3f %10.3f %10.2f %9.0f%%\n", r->backend, r->ms, r->best_ms, g,
                100.0 * g / gbs);
        printf("\"ms\": %.4f, \"best_ms\": %.4f, \"gbs\": %.3f, \"of_triad\": %.4f}", r->ms,
               r->best_ms, g, g / gbs);
    }
    printf("\n  ]\n}\n");
    free(d.transfer);
    free(d.lighting);
    lg_pool_free(pool);
    return rc;
}
