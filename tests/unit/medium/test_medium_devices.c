/*
 * The twins of lightgraph/medium.h on the devices (test_medium_devices gpu):
 * shaders/common/medium.glsl in a GL compute shader and shaders/common/medium.cl in an
 * OpenCL kernel, over one table of inputs, against the C float functions (lg_hg_phasef,
 * lg_medium_segmentf) and the C double slice maps:
 *
 *   phase    g in {0, +-0.4, +-0.9, +-0.99, +-0.999, +-0.999999, +-1} x cos in {-1, -0.99,
 *            -0.5, 0, 0.3, 0.9, 0.999, 1 - 1e-6, 1} (|g| = 1 is clamped to LG_HG_G_MAX)
 *   segment  tau in {0, 1e-30, 1e-8, 1e-4, 0.01, 0.1, 0.2499, 0.25, 0.2501, 0.5, 1, 2, 5,
 *            10, 30, 80} (0.25: the switch from the series to the quotient)
 *   slices   both slicings, depth 1 and 128 (near 0.1, far 100, near_offset 1): t(z) at
 *            every slice boundary and between, z(t) at the same depths, and the round trip
 *            z(t(z)) evaluated on the device
 *
 * Tolerances (relative unless said): phase TOL_PHASE (the same float operations; the
 * devices may contract to fma and round sqrt and division differently), segment
 * TOL_SEGMENT, t(z) and z(t) TOL_SLICE (float pow, log and reciprocals against double;
 * uniform_clip's t(z) at most FLT_EPSILON t / near, the conditioning of 1/t = 1/near +
 * (z/D)(1/far - 1/near) in float, which cancels towards far), round trips TOL_TRIP
 * slices absolute. z(t) errors are in slices divided by the depth. The worst measured values are printed. A missing
 * device is a failure: llvmpipe and PoCL are dependencies.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exec/device.h"
#include "common/cl_join.h"
#include "devtest.h"
#include "lightgraph/cl.h"
#include "lightgraph/gl.h"
#include "lightgraph/medium.h"
#include "medium.cl.h"
#include "medium_eval.cl.h"
#include "medium_eval.comp.h"

#define TOL_PHASE 4e-6
#define TOL_SEGMENT 2e-6
#define TOL_SLICE 1e-5
#define TOL_TRIP 1e-4

enum { OP_PHASE = 0, OP_SEGMENT, OP_TO_DEPTH, OP_TO_SLICE, OP_TRIP };

typedef struct rec {
    int op, slicing;
    float x;
    float map[4];
} rec;

#define CAP 4096
static rec table[CAP];
static uint32_t n_rec;

static void add(int op, int slicing, float x, float m0, float m1, float m2, float m3)
{
    if (n_rec < CAP)
        table[n_rec++] = (rec){ op, slicing, x, { m0, m1, m2, m3 } };
}

static void make_table(void)
{
    static const float gs[] = { 0,      0.4f,    -0.4f,     0.9f,       -0.9f, 0.99f, -0.99f,
                                0.999f, -0.999f, 0.999999f, -0.999999f, 1,     -1 };
    static const float cs[] = { -1, -0.99f, -0.5f, 0, 0.3f, 0.9f, 0.999f, 1 - 1e-6f, 1 };
    for (size_t i = 0; i < sizeof gs / sizeof gs[0]; i++)
        for (size_t j = 0; j < sizeof cs / sizeof cs[0]; j++)
            add(OP_PHASE, 0, cs[j], gs[i], 0, 0, 0);
    static const float taus[] = { 0,       1e-30f, 1e-8f, 1e-4f, 0.01f, 0.1f, 0.2499f, 0.25f,
                                  0.2501f, 0.5f,   1,     2,     5,     10,   30,      80 };
    for (size_t i = 0; i < sizeof taus / sizeof taus[0]; i++)
        add(OP_SEGMENT, 0, taus[i], 0, 0, 0, 0);
    static const int slicings[] = { LG_FROXEL_UNIFORM_CLIP, LG_FROXEL_EXPONENTIAL };
    static const uint32_t depths[] = { 1, 128 };
    for (int s = 0; s < 2; s++)
        for (int d = 0; d < 2; d++) {
            lg_slice_map m;
            lg_slice_map_init(&m, (lg_froxel_slicing)slicings[s], depths[d], 0.1, 100.0, 1.0);
            uint32_t D = depths[d];
            for (uint32_t k = 0; k <= 4 * D; k++) {
                float z = (float)(k * 0.25);
                add(OP_TO_DEPTH, slicings[s], z, 0.1f, 100.0f, 1.0f, (float)D);
                add(OP_TRIP, slicings[s], z, 0.1f, 100.0f, 1.0f, (float)D);
                add(OP_TO_SLICE, slicings[s], (float)lg_slice_to_depth(&m, z), 0.1f, 100.0f, 1.0f,
                    (float)D);
            }
        }
}

/* The C value of a record (float functions where C has them, else double). */
static double cpu_value(const rec *r)
{
    if (r->op == OP_PHASE)
        return lg_hg_phasef(r->map[0], r->x);
    if (r->op == OP_SEGMENT)
        return lg_medium_segmentf(r->x);
    lg_slice_map m;
    lg_slice_map_init(&m, (lg_froxel_slicing)r->slicing, (uint32_t)r->map[3], r->map[0], r->map[1],
                      r->map[2]);
    if (r->op == OP_TO_DEPTH)
        return lg_slice_to_depth(&m, r->x);
    if (r->op == OP_TO_SLICE)
        return lg_depth_to_slice(&m, r->x);
    return r->x; /* the round trip returns where it started */
}

static const char *op_name(int op)
{
    static const char *const names[] = { "phase", "segment", "slice_to_depth", "depth_to_slice",
                                         "round trip" };
    return names[op];
}

/* Compares the device's results; prints the worst error per op. */
static void compare(const char *dev, const float *res)
{
    double worst[5] = { 0 };
    for (uint32_t i = 0; i < n_rec; i++) {
        const rec *r = &table[i];
        double want = cpu_value(r), got = res[i], err;
        double tol = r->op == OP_PHASE     ? TOL_PHASE
                     : r->op == OP_SEGMENT ? TOL_SEGMENT
                     : r->op == OP_TRIP    ? TOL_TRIP
                                           : TOL_SLICE;
        if (r->op == OP_TRIP)
            err = fabs(got - want);
        else if (r->op == OP_TO_SLICE)
            /* z(t) relative to the slice count (z = 0 has no relative error) */
            err = fabs(got - want) / r->map[3];
        else
            err = fabs(got - want) / fabs(want);
        if (r->op == OP_TO_DEPTH && r->slicing == LG_FROXEL_UNIFORM_CLIP)
            /* 1/near + (z/D)(1/far - 1/near) cancels towards the far end: float keeps
             * about 2^-24 (1/near) absolutely, so t = 1 / that keeps 2^-24 t/near
             * relatively (far/near = 1000 here: up to 6e-5). Measured against that. */
            tol = fmax(tol, 1.0 * FLT_EPSILON * want / r->map[0]);
        CHECKF(isfinite(got) && err <= tol,
               "%s %s (slicing %d, depth %g) at %.9g, g %.9g: "
               "%.9g, C %.9g (error %.3g > %.3g)",
               dev, op_name(r->op), r->slicing, (double)r->map[3], (double)r->x, (double)r->map[0],
               got, want, err, tol);
        if (err > worst[r->op])
            worst[r->op] = err;
    }
    printf("%s: %u records; worst: phase %.2g rel, segment %.2g rel, slice_to_depth %.2g "
           "rel, depth_to_slice %.2g slices/depth, round trip %.2g slices\n",
           dev, n_rec, worst[0], worst[1], worst[2], worst[3], worst[4]);
}

static void run_gl(void)
{
    char err[1024] = "", err2[512] = "";
    lg_gl_device *gldev = NULL;
    if (lg_gl_device_create(&gldev, "osmesa", err, sizeof err) &&
        lg_gl_device_create(&gldev, "egl", err2, sizeof err2)) {
        CHECKF(0, "no GL device (a failure: llvmpipe is a dependency): %s; %s", err, err2);
        return;
    }
    const lg_gl *gl = lg_gl_device_table(gldev);
    printf("gl: %s\n", lg_gl_device_description(gldev));
    lg_gl_shader_src src = { GL_COMPUTE_SHADER, lg_src_medium_eval_comp_file,
                             lg_src_medium_eval_comp };
    devtest_clear();
    GLuint prog = lg_gl_program(devtest_node(), gl, &src, 1, NULL);
    CHECKF(prog != 0, "medium_eval.comp: %s", devtest_errors);
    if (prog) {
        float *args = calloc(n_rec, 16), *maps = calloc(n_rec, 16), *res = calloc(n_rec, 4);
        for (uint32_t i = 0; i < n_rec; i++) {
            args[4 * i] = (float)table[i].op;
            args[4 * i + 1] = (float)table[i].slicing;
            args[4 * i + 2] = table[i].x;
            memcpy(maps + 4 * i, table[i].map, 16);
        }
        GLuint buf[3];
        gl->CreateBuffers(3, buf);
        gl->NamedBufferData(buf[0], (GLsizeiptr)n_rec * 16, args, GL_STATIC_DRAW);
        gl->NamedBufferData(buf[1], (GLsizeiptr)n_rec * 16, maps, GL_STATIC_DRAW);
        gl->NamedBufferData(buf[2], (GLsizeiptr)n_rec * 4, NULL, GL_STATIC_READ);
        gl->UseProgram(prog);
        gl->Uniform1ui(0, n_rec);
        for (GLuint b = 0; b < 3; b++)
            gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, buf[b]);
        gl->DispatchCompute((n_rec + 63) / 64, 1, 1);
        gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        gl->GetNamedBufferSubData(buf[2], 0, (GLsizeiptr)n_rec * 4, res);
        for (GLuint b = 0; b < 3; b++)
            gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
        gl->UseProgram(0);
        gl->DeleteBuffers(3, buf);
        gl->DeleteProgram(prog);
        GLenum e = gl->GetError();
        CHECKF(e == GL_NO_ERROR, "GL error %s", lg_gl_strerror(e));
        if (e == GL_NO_ERROR)
            compare("gl", res);
        free(args);
        free(maps);
        free(res);
    }
    lg_gl_device_destroy(&gldev);
}

static void run_cl(void)
{
    char err[1024] = "";
    lg_cl_dev *cldev = NULL;
    if (lg_cl_device_create(&cldev, err, sizeof err)) {
        CHECKF(0, "no CL device (a failure: PoCL is a dependency): %s", err);
        return;
    }
    printf("cl: %s\n", lg_cl_device_description(cldev));
    const char *parts[] = { lg_src_medium_cl, lg_src_medium_eval_cl };
    char *src = test_cl_join(parts, 2);
    CHECKF(src != NULL, "out of memory");
    char *log = NULL;
    cl_program p = src ? lg_cl_device_program(cldev, "medium_eval.cl", src, NULL, &log) : NULL;
    free(src);
    CHECKF(p != NULL, "%s", log ? log : "build failed");
    free(log);
    cl_int e = CL_SUCCESS;
    cl_kernel k = p ? clCreateKernel(p, "medium_eval", &e) : NULL;
    CHECKF(k != NULL, "clCreateKernel: %s", lg_cl_strerror(e));
    if (k) {
        cl_context ctx = lg_cl_device_context(cldev);
        cl_command_queue q = lg_cl_device_queue(cldev);
        float *args = calloc(n_rec, 16), *maps = calloc(n_rec, 16), *res = calloc(n_rec, 4);
        for (uint32_t i = 0; i < n_rec; i++) {
            args[4 * i] = (float)table[i].op;
            args[4 * i + 1] = (float)table[i].slicing;
            args[4 * i + 2] = table[i].x;
            memcpy(maps + 4 * i, table[i].map, 16);
        }
        cl_int e1, e2, e3;
        cl_mem ma = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n_rec * 16,
                                   args, &e1);
        cl_mem mm = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n_rec * 16,
                                   maps, &e2);
        cl_mem mr = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)n_rec * 4, NULL, &e3);
        CHECKF(e1 == CL_SUCCESS && e2 == CL_SUCCESS && e3 == CL_SUCCESS, "clCreateBuffer");
        if (e1 == CL_SUCCESS && e2 == CL_SUCCESS && e3 == CL_SUCCESS) {
            cl_int cn = (cl_int)n_rec;
            clSetKernelArg(k, 0, sizeof ma, &ma);
            clSetKernelArg(k, 1, sizeof mm, &mm);
            clSetKernelArg(k, 2, sizeof mr, &mr);
            clSetKernelArg(k, 3, sizeof cn, &cn);
            size_t global = n_rec;
            e = clEnqueueNDRangeKernel(q, k, 1, NULL, &global, NULL, 0, NULL, NULL);
            CHECKF(e == CL_SUCCESS, "clEnqueueNDRangeKernel: %s", lg_cl_strerror(e));
            if (e == CL_SUCCESS) {
                e = clEnqueueReadBuffer(q, mr, CL_TRUE, 0, (size_t)n_rec * 4, res, 0, NULL, NULL);
                CHECKF(e == CL_SUCCESS, "clEnqueueReadBuffer: %s", lg_cl_strerror(e));
                if (e == CL_SUCCESS)
                    compare("cl", res);
            }
        }
        if (ma)
            clReleaseMemObject(ma);
        if (mm)
            clReleaseMemObject(mm);
        if (mr)
            clReleaseMemObject(mr);
        clReleaseKernel(k);
        free(args);
        free(maps);
        free(res);
    }
    lg_cl_device_destroy(&cldev); /* releases the program, which the device caches */
}

int main(int argc, char **argv)
{
    if (argc != 2 || strcmp(argv[1], "gpu")) {
        fprintf(stderr, "usage: test_medium_devices gpu\n");
        return 2;
    }
    make_table();
    run_gl();
    run_cl();
    return check_report("medium_gpu");
}
