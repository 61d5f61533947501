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
 *   lights   (ABI 3.2) lg_light_window at d / range in [0, 1.2] and range 0; lg_spot_cone
 *            over a cone's edge, a hard edge (inner = outer) and a reversed pair;
 *            lg_local_falloff of point and spot lights (ranges 0 and 5) at points near,
 *            far, on the axis and at the light itself; lg_point_inscatter on rays past
 *            the light at h = 1, 0.1, 1e-3 and through it, segments before, across and after
 *            it, g 0 / 0.6 / -0.3, sigma_t 0 / 0.3 / 2, range 0 / 3, point and spot, at
 *            1, 3, 4 and 8 nodes (one panel: the C function's nodes at n <= 8)
 *
 * Tolerances (relative unless said): phase TOL_PHASE (the same float operations; the
 * devices may contract to fma and round sqrt and division differently), segment
 * TOL_SEGMENT, t(z) and z(t) TOL_SLICE (float pow, log and reciprocals against double;
 * uniform_clip's t(z) at most FLT_EPSILON t / near, the conditioning of 1/t = 1/near +
 * (z/D)(1/far - 1/near) in float, which cancels towards far), round trips TOL_TRIP
 * slices absolute. z(t) errors are in slices divided by the depth. The lights: window and cone
 * TOL_UNIT absolute (values in [0, 1]; float cancellation in 1 - r^4 and in the cone's
 * (cos - cos_outer) / span); falloff TOL_FALLOFF relative to the point light's W / (d^2 +
 * eps^2) (the cone's t^2 amplifies the float dot product by 2 / span); the airlight
 * TOL_AIRLIGHT relative to the C value at the same nodes, or to 1e-3 of the segment's
 * plain airlight where the value is tiny: measured 5.7e-4 on llvmpipe, 1.1e-4 on PoCL, on
 * rays within 1e-3 of the light with sigma_t = 2 (the angle near +-pi/2, where a float
 * ulp of xi is 1e-4 of pi/2 - |xi|, through tan; llvmpipe's tan and atan are the coarser).
 * Before the fixes of issue 25's polygonal branch the GLSL and CL twins erred by 1-20 %
 * there (h^2 = |qo|^2 - tc^2 cancelled; the spot clip's roots cancelled near the apex). The worst measured values are printed. A missing
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
#include "lightgraph/vecmath.h"
#include "medium.cl.h"
#include "medium_eval.cl.h"
#include "medium_eval.comp.h"

#define TOL_PHASE 4e-6
#define TOL_SEGMENT 2e-6
#define TOL_SLICE 1e-5
#define TOL_TRIP 1e-4
#define TOL_UNIT 2e-6
#define TOL_FALLOFF 2e-5
#define TOL_AIRLIGHT 1e-3

enum {
    OP_PHASE = 0,
    OP_SEGMENT,
    OP_TO_DEPTH,
    OP_TO_SLICE,
    OP_TRIP,
    OP_WINDOW,
    OP_CONE,
    OP_FALLOFF,
    OP_AIRLIGHT,
    OP_COUNT
};

typedef struct rec {
    int op, slicing;
    float x;
    float map[4];
    float ext[16]; /* four vec4 (medium_eval.comp) */
} rec;

#define CAP 4096
static rec table[CAP];
static uint32_t n_rec;

static void add(int op, int slicing, float x, float m0, float m1, float m2, float m3)
{
    if (n_rec < CAP)
        table[n_rec++] = (rec){ op, slicing, x, { m0, m1, m2, m3 } };
}

/* A record of the light ops with its ext words. */
static void add_ext(int op, float x, const float map[4], const float ext[16])
{
    if (n_rec < CAP) {
        rec *r = &table[n_rec++];
        *r = (rec){ op, 0, x, { map[0], map[1], map[2], map[3] }, { 0 } };
        memcpy(r->ext, ext, sizeof r->ext);
    }
}

static void make_light_table(void)
{
    static const float ranges[] = { 0.0f, 2.0f };
    for (int k = 0; k <= 24; k++)
        for (int r = 0; r < 2; r++)
            add(OP_WINDOW, 0, 0.1f * (float)k, ranges[r], 0, 0, 0);
    static const float cones[][2] = { { 0.95f, 0.8f }, { 0.9f, 0.9f }, { 0.8f, 0.95f } };
    for (int c = 0; c < 3; c++)
        for (int k = 0; k <= 20; k++)
            add(OP_CONE, 0, 0.7f + 0.015f * (float)k, cones[c][0], cones[c][1], 0, 0);
    /* falloff: light at (0.2, 3, -0.1), axis (0.6, -0.8, 0), cone cos 0.95 / 0.8 */
    static const float pts[][3] = { { 0.2f, 3.0f, -0.1f }, { 0.2f, 2.0f, -0.1f },
                                    { 1.4f, 1.4f, -0.1f }, { 0.9f, 2.1f, 0.3f },
                                    { 3.0f, 0.0f, 1.0f },  { -2.0f, 3.5f, 4.0f } };
    for (int sp = 0; sp < 2; sp++)
        for (int r = 0; r < 2; r++)
            for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
                const float ext[16] = { 0.2f,      3.0f,      -0.1f,     r ? 5.0f : 0.0f,
                                        0.6f,      -0.8f,     0.0f,      (float)sp,
                                        pts[k][0], pts[k][1], pts[k][2], 0,
                                        0,         0,         0,         0 };
                const float map[4] = { 0.95f, 0.8f, 0, 0 };
                add_ext(OP_FALLOFF, 0.0f, map, ext);
            }
    /* the airlight: the ray from the origin along +z, the light at (h, 0, 3) */
    static const float hs[] = { 1.0f, 0.1f, 1e-3f, 0.0f };
    static const float segs[][2] = {
        { 0.0f, 1.5f }, { 0.0f, 6.0f }, { 2.5f, 3.5f }, { 3.2f, 9.0f }
    };
    static const float gs[] = { 0.0f, 0.6f, -0.3f }, sts[] = { 0.0f, 0.3f, 2.0f };
    static const int nodes[] = { 1, 3, 4, 8 };
    int k = 0;
    for (int ih = 0; ih < 4; ih++)
        for (int is = 0; is < 4; is++)
            for (int ig = 0; ig < 3; ig++)
                for (int it = 0; it < 3; it++)
                    for (int sp = 0; sp < 2; sp++, k++) {
                        const float ext[16] = { 0,      0, 0,          segs[is][0],
                                                0,      0, 1,          segs[is][1],
                                                hs[ih], 0, 3,          (k % 3 == 0) ? 3.0f : 0.0f,
                                                -0.3f,  0, 0.9539392f, (float)sp };
                        const float map[4] = { 0.95f, 0.8f, gs[ig], sts[it] };
                        add_ext(OP_AIRLIGHT, (float)nodes[k % 4], map, ext);
                    }
    /* a spot seen from outside its cone (volumetric_polygonal's spot_cone scene): rays from
     * (3, 2.5, 5) towards points around the cone, the spot at (-0.5, 3, 0.2) along
     * (0.3, -1, -0.1), cones 15 and 30 degrees */
    static const float aims[][3] = { { 0, 0.8f, 0 },        { 0.5f, 1.5f, 0 }, { -0.3f, 2, 0.2f },
                                     { 0.2f, 0.5f, -0.5f }, { -1, 0, 0 },      { 1, 1, 1 } };
    for (size_t i = 0; i < sizeof aims / sizeof aims[0]; i++)
        for (int n = 0; n < 2; n++) {
            double w[3] = { aims[i][0] - 3.0, aims[i][1] - 2.5, aims[i][2] - 5.0 };
            double a[3] = { 0.3, -1.0, -0.1 };
            double lw = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
            double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            const float ext[16] = { 3,
                                    2.5f,
                                    5,
                                    0,
                                    (float)(w[0] / lw),
                                    (float)(w[1] / lw),
                                    (float)(w[2] / lw),
                                    9.0f,
                                    -0.5f,
                                    3,
                                    0.2f,
                                    0,
                                    (float)(a[0] / la),
                                    (float)(a[1] / la),
                                    (float)(a[2] / la),
                                    1 };
            const float map[4] = { (float)cos(15.0 * LG_PI / 180.0),
                                   (float)cos(30.0 * LG_PI / 180.0), 0.4f, 0.15f };
            add_ext(OP_AIRLIGHT, n ? 8.0f : 4.0f, map, ext);
        }
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
    make_light_table();
}

/* The C value of a record (float functions where C has them, else double). */
static double cpu_value(const rec *r)
{
    if (r->op == OP_PHASE)
        return lg_hg_phasef(r->map[0], r->x);
    if (r->op == OP_SEGMENT)
        return lg_medium_segmentf(r->x);
    const float *e = r->ext;
    if (r->op == OP_WINDOW)
        return lg_light_window(r->x, r->map[0]);
    if (r->op == OP_CONE)
        return lg_spot_cone(r->x, r->map[0], r->map[1]);
    if (r->op == OP_FALLOFF) {
        /* the C function takes angles: the cone's cosines through acos (float inputs) */
        lg_light l = { .type = e[7] != 0.0f ? LG_LIGHT_SPOT : LG_LIGHT_POINT,
                       .position = { e[0], e[1], e[2] },
                       .direction = { e[4], e[5], e[6] },
                       .range = e[3],
                       .inner_cone = (float)acos(r->map[0]),
                       .outer_cone = (float)acos(r->map[1]) };
        const double p[3] = { e[8], e[9], e[10] };
        return lg_light_falloff(&l, p, NULL, NULL);
    }
    if (r->op == OP_AIRLIGHT) {
        const double o[3] = { e[0], e[1], e[2] }, w[3] = { e[4], e[5], e[6] };
        const double q[3] = { e[8], e[9], e[10] };
        const double spot[5] = { e[12], e[13], e[14], r->map[0], r->map[1] };
        return lg_point_inscatter(o, w, e[3], e[7], q, e[11], e[15] != 0.0f ? spot : NULL,
                                  r->map[2], r->map[3], (int)r->x);
    }
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
    static const char *const names[] = { "phase",          "segment",    "slice_to_depth",
                                         "depth_to_slice", "round trip", "window",
                                         "cone",           "falloff",    "airlight" };
    return names[op];
}

/* Compares the device's results; prints the worst error per op. */
static void compare(const char *dev, const float *res)
{
    double worst[OP_COUNT] = { 0 };
    for (uint32_t i = 0; i < n_rec; i++) {
        const rec *r = &table[i];
        double want = cpu_value(r), got = res[i], err;
        double tol = r->op == OP_PHASE     ? TOL_PHASE
                     : r->op == OP_SEGMENT ? TOL_SEGMENT
                     : r->op == OP_TRIP    ? TOL_TRIP
                                           : TOL_SLICE;
        if (r->op == OP_WINDOW || r->op == OP_CONE) {
            tol = TOL_UNIT;
            err = fabs(got - want);
        } else if (r->op == OP_FALLOFF) {
            /* relative to the point light's W / (d^2 + eps^2) at the same point */
            double d2 = 0.0;
            for (int c = 0; c < 3; c++)
                d2 += ((double)r->ext[c] - r->ext[8 + c]) * ((double)r->ext[c] - r->ext[8 + c]);
            double ref = lg_light_window(sqrt(d2), r->ext[3]) /
                         (d2 + LG_LIGHT_EPSILON * LG_LIGHT_EPSILON);
            tol = TOL_FALLOFF;
            err = fabs(got - want) / fmax(ref, 1e-30);
        } else if (r->op == OP_AIRLIGHT) {
            /* relative, or against 1e-3 of the segment's airlight without phase,
             * extinction, range or cone (Sun et al.'s closed form, exact at one node) where
             * those leave almost nothing */
            const float *e = r->ext;
            const double o[3] = { e[0], e[1], e[2] }, w[3] = { e[4], e[5], e[6] };
            const double q[3] = { e[8], e[9], e[10] };
            double scale = lg_point_inscatter(o, w, e[3], e[7], q, 0.0, NULL, 0.0, 0.0, 1);
            tol = TOL_AIRLIGHT;
            err = fabs(got - want) / fmax(fabs(want), 1e-3 * scale);
        } else if (r->op == OP_TRIP)
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
           "rel, depth_to_slice %.2g slices/depth, round trip %.2g slices, window %.2g abs, "
           "cone %.2g abs, falloff %.2g rel, airlight %.2g rel\n",
           dev, n_rec, worst[0], worst[1], worst[2], worst[3], worst[4], worst[5], worst[6],
           worst[7], worst[8]);
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
        float *ext = calloc(n_rec, 64);
        for (uint32_t i = 0; i < n_rec; i++) {
            args[4 * i] = (float)table[i].op;
            args[4 * i + 1] = (float)table[i].slicing;
            args[4 * i + 2] = table[i].x;
            memcpy(maps + 4 * i, table[i].map, 16);
            memcpy(ext + 16 * i, table[i].ext, 64);
        }
        GLuint buf[4];
        gl->CreateBuffers(4, buf);
        gl->NamedBufferData(buf[0], (GLsizeiptr)n_rec * 16, args, GL_STATIC_DRAW);
        gl->NamedBufferData(buf[1], (GLsizeiptr)n_rec * 16, maps, GL_STATIC_DRAW);
        gl->NamedBufferData(buf[2], (GLsizeiptr)n_rec * 4, NULL, GL_STATIC_READ);
        gl->NamedBufferData(buf[3], (GLsizeiptr)n_rec * 64, ext, GL_STATIC_DRAW);
        gl->UseProgram(prog);
        gl->Uniform1ui(0, n_rec);
        for (GLuint b = 0; b < 4; b++)
            gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, buf[b]);
        gl->DispatchCompute((n_rec + 63) / 64, 1, 1);
        gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        gl->GetNamedBufferSubData(buf[2], 0, (GLsizeiptr)n_rec * 4, res);
        for (GLuint b = 0; b < 4; b++)
            gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
        gl->UseProgram(0);
        gl->DeleteBuffers(4, buf);
        free(ext);
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
        float *ext = calloc(n_rec, 64);
        for (uint32_t i = 0; i < n_rec; i++) {
            args[4 * i] = (float)table[i].op;
            args[4 * i + 1] = (float)table[i].slicing;
            args[4 * i + 2] = table[i].x;
            memcpy(maps + 4 * i, table[i].map, 16);
            memcpy(ext + 16 * i, table[i].ext, 64);
        }
        cl_int e1, e2, e3, e4;
        cl_mem mx = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n_rec * 64,
                                   ext, &e4);
        cl_mem ma = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n_rec * 16,
                                   args, &e1);
        cl_mem mm = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n_rec * 16,
                                   maps, &e2);
        cl_mem mr = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)n_rec * 4, NULL, &e3);
        CHECKF(e1 == CL_SUCCESS && e2 == CL_SUCCESS && e3 == CL_SUCCESS && e4 == CL_SUCCESS,
               "clCreateBuffer");
        if (e1 == CL_SUCCESS && e2 == CL_SUCCESS && e3 == CL_SUCCESS && e4 == CL_SUCCESS) {
            cl_int cn = (cl_int)n_rec;
            clSetKernelArg(k, 0, sizeof ma, &ma);
            clSetKernelArg(k, 1, sizeof mm, &mm);
            clSetKernelArg(k, 2, sizeof mr, &mr);
            clSetKernelArg(k, 3, sizeof cn, &cn);
            clSetKernelArg(k, 4, sizeof mx, &mx);
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
        if (mx)
            clReleaseMemObject(mx);
        free(ext);
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
