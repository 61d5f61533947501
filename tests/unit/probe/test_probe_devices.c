/*
 * The probe lookups on the CPU (lightgraph/probe.h) against their twins:
 *
 *   test_probe_devices gl   shaders/common/probe.glsl in a compute shader: lat-long and
 *                           angular from a sampler2D (texelFetch), the cube from a
 *                           samplerCube with GL_TEXTURE_CUBE_MAP_SEAMLESS (GL's filter)
 *   test_probe_devices cl   shaders/common/probe.cl in a kernel, images as buffers
 *
 * For every layout at several sizes (1x1 included), nearest and bilinear, on random
 * directions and on the hard cases (axes, poles, seam, angular centre and rim, cube edges
 * and corners, zero, denormal, non-unit, NaN and Inf vectors): the coordinates and the
 * values agree within the tolerances below, and the measured agreement is printed
 * (docs/probes.md quotes it). A missing device is a failure: the CI machines have
 * llvmpipe and PoCL.
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
#include "lightgraph/probe.h"
#include "probe.cl.h"
#include "probe_eval.cl.h"
#include "probe_eval.comp.h"

/* Tolerances (values in [0, 1)): coordinates within TOL_COORD (the maps' float rounding,
 * atan2 and sin/cos differ by a few ulp between libm, llvmpipe and PoCL); bilinear values
 * within TOL_BILINEAR per texel of width (a coordinate error times the value's slope);
 * nearest values equal wherever the CPU's coordinate is more than 1e-3 texel (or
 * 2 TOL_COORD of the image) from a texel border. */
#define TOL_COORD 4e-6
#define TOL_BILINEAR_PER_TEXEL 4e-6
#define TOL_BILINEAR_MIN 2e-6

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static const char *layout_name(lg_probe_layout l)
{
    return l == LG_PROBE_LATLONG ? "latlong" : l == LG_PROBE_ANGULAR ? "angular" : "cube";
}

/* ---- the directions -------------------------------------------------------------------------- */

static void put(float *d, double x, double y, double z)
{
    d[0] = (float)x;
    d[1] = (float)y;
    d[2] = (float)z;
    d[3] = 0;
}

/* Hard cases then random directions; returns the count (at most cap). */
static uint32_t make_dirs(float *d, uint32_t cap, uint32_t n_random)
{
    uint32_t n = 0;
    const float dn = 1e-40f;
    const float hard[][3] = {
        { 1, 0, 0 },
        { -1, 0, 0 },
        { 0, 1, 0 },
        { 0, -1, 0 },
        { 0, 0, 1 },
        { 0, 0, -1 },
        { 0, 0, 0 },
        { -0.0f, -0.0f, -0.0f },
        { dn, dn, -dn },
        { 1e-31f, 0, 0 },
        { NAN, 0, 0 },
        { 0, NAN, 1 },
        { INFINITY, 0, 0 },
        { 1, -INFINITY, 1 },
        { NAN, NAN, NAN },
        { 3e38f, -3e38f, 3e38f },
        { 1e-20f, 2e-20f, -2e-20f },
        { 5, 0, -5 },
        { 0, 7, 1e-3f },
        { 1e-7f, 0, 1 },
        { -1e-7f, 0, 1 },
        { 1e-7f, 0.5f, 1 },
        { -1e-7f, -0.5f, 1 }, /* seam */
        { 1e-6f, 1, 1e-6f },
        { -1e-6f, 1, -1e-6f },
        { 1e-6f, -1, 0 }, /* poles */
        { 1e-8f, -1e-8f, -1 },
        { 1e-4f, 0, -1 },
        { 0, 1e-4f, -1 }, /* angular centre */
        { 1e-3f, 0, 1 },
        { 0, -1e-3f, 1 },
        { 0.01f, 0.01f, 1 }, /* angular rim */
        { 1, 1, 0 },
        { 1, -1, 0 },
        { -1, 0, 1 },
        { 0, 1, -1 },
        { 1, 1, 1 },
        { -1, -1, -1 },
        { 1, -1, 1 },
        { -1, 1, 1 }, /* cube edges and corners */
    };
    for (size_t k = 0; k < sizeof hard / sizeof hard[0] && n < cap; k++, n++) {
        memcpy(d + 4 * n, hard[k], sizeof hard[k]);
        d[4 * n + 3] = 0;
    }
    /* approaching every cube edge from both faces, at a few distances */
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            for (int s = 0; s < 4; s++)
                for (int e = 1; e <= 3; e++)
                    for (int side = 0; side < 2 && n + 1 < cap; side++) {
                        double p[3] = { 0.3, -0.2, 0.45 };
                        p[a] = (s & 1) ? 1 : -1;
                        p[b] = (s & 2) ? 1 : -1;
                        double eps = pow(10.0, -2.0 * e);
                        p[side ? a : b] *= 1 - eps;
                        put(d + 4 * n++, p[0], p[1], p[2]);
                    }
    for (uint32_t k = 0; k < n_random && n < cap; k++, n++) {
        double z = 2 * rnd() - 1, ph = 2 * LG_PI * rnd(), s = sqrt(1 - z * z);
        double scale = (k % 3 == 0) ? 1 : (k % 3 == 1) ? 1e-3 : 1e3; /* non-unit */
        put(d + 4 * n, scale * s * cos(ph), scale * s * sin(ph), scale * z);
    }
    return n;
}

/* ---- comparing ------------------------------------------------------------------------------- */

typedef struct stats {
    double coord, bilinear_ratio, bilinear_abs;
    uint32_t nearest_checked, nearest_skipped, compared;
} stats;

/* Whether a nearest lookup may legitimately pick another texel: the coordinate is within
 * 1e-3 texel of a texel border, or the direction is on a cube face boundary. */
static int ambiguous(lg_probe_layout l, uint32_t w, uint32_t h, const float *rot, const float *dir)
{
    lg_vec3 d = lg_probe_safe_dir(lg_probe_from_world(rot, lg_v3(dir[0], dir[1], dir[2])));
    if (l == LG_PROBE_CUBE) {
        float a[3] = { fabsf(d.x), fabsf(d.y), fabsf(d.z) };
        float m = fmaxf(a[0], fmaxf(a[1], a[2]));
        int close = 0;
        for (int k = 0; k < 3; k++)
            close += a[k] >= m * (1 - 1e-5f);
        if (close > 1)
            return 1;
    }
    lg_probe_coord c = lg_probe_dir_to_coord(l, d);
    double x = c.u * w, y = c.v * h;
    double fx = x - floor(x), fy = y - floor(y);
    /* 1e-3 texel, or twice the coordinate tolerance in texels for big images */
    const double e = fmax(1e-3, 2 * TOL_COORD * (w > h ? w : h));
    if ((fx < e || fx > 1 - e) && w > 1)
        return 1;
    if ((fy < e || fy > 1 - e) && h > 1 && !(c.v <= 0 || c.v >= 1))
        return 1;
    /* lat-long poles: every u is the pole */
    if (l == LG_PROBE_LATLONG && (fabs(d.y) > 1 - 1e-6))
        return 1;
    /* the angular rim, +Z: a point whose neighbourhood covers the rim */
    if (l == LG_PROBE_ANGULAR && d.z > 1 - 1e-5)
        return 1;
    return 0;
}

static void compare(const char *dev, lg_probe_layout l, uint32_t w, uint32_t h, int bilinear,
                    const float *rot, const float *dirs, uint32_t n, const float *res,
                    const float *rgba, stats *st)
{
    lg_probe_image img = { l, w, h, rgba, rot, { 0 } };
    int bad = 0;
    double tol_b = fmax(TOL_BILINEAR_PER_TEXEL * w, TOL_BILINEAR_MIN);
    for (uint32_t k = 0; k < n; k++) {
        const float *d = dirs + 4 * k;
        lg_vec3 v = lg_v3(d[0], d[1], d[2]);
        float want[4];
        lg_probe_lookup(&img, v, bilinear ? LG_PROBE_BILINEAR : LG_PROBE_NEAREST, want);
        lg_probe_coord c = lg_probe_dir_to_coord(l, lg_probe_from_world(rot, v));
        const float *got = res + 8 * k, *gc = res + 8 * k + 4;
        /* coordinates: the face where no tie is possible, u (mod 1 for lat-long), v */
        int amb = ambiguous(l, w, h, rot, d);
        double du = fabs(gc[0] - c.u), dv = fabs(gc[1] - c.v);
        if (l == LG_PROBE_LATLONG)
            du = fmin(du, 1 - du);
        lg_vec3 sd = lg_probe_safe_dir(lg_probe_from_world(rot, v));
        if (l == LG_PROBE_LATLONG && fabsf(sd.y) > 1 - 1e-6f)
            du = 0; /* at a pole u is arbitrary */
        if (l == LG_PROBE_ANGULAR && sd.z > 1 - 1e-5f)
            du = dv = 0; /* the rim: every point of it is +Z */
        int face_ok = l != LG_PROBE_CUBE || (uint32_t)gc[2] == c.face || amb;
        if (face_ok && (uint32_t)gc[2] == c.face)
            st->coord = fmax(st->coord, fmax(du, dv));
        int ok = face_ok && (((uint32_t)gc[2] != c.face) || (du <= TOL_COORD && dv <= TOL_COORD));
        if (!ok && bad++ < 6)
            CHECKF(
                0,
                "%s %s %ux%u: direction (%g, %g, %g): coord face %g (%.9g, %.9g), CPU face %u (%.9g, %.9g)",
                dev, layout_name(l), w, h, d[0], d[1], d[2], gc[2], gc[0], gc[1], c.face, c.u, c.v);
        double e = 0;
        for (int q = 0; q < 4; q++)
            e = fmax(e, fabs((double)got[q] - want[q]));
        if (!isfinite(got[0]) || !isfinite(got[1]) || !isfinite(got[2]) || !isfinite(got[3]))
            e = INFINITY;
        if (bilinear) {
            st->bilinear_abs = fmax(st->bilinear_abs, e);
            st->bilinear_ratio = fmax(st->bilinear_ratio, e / tol_b);
            if (!(e <= tol_b) && bad++ < 6)
                CHECKF(
                    0,
                    "%s %s %ux%u bilinear: direction (%g, %g, %g): (%.9g %.9g %.9g %.9g), CPU (%.9g %.9g %.9g %.9g), |diff| %.3g > %.3g",
                    dev, layout_name(l), w, h, d[0], d[1], d[2], got[0], got[1], got[2], got[3],
                    want[0], want[1], want[2], want[3], e, tol_b);
        } else if (amb) {
            st->nearest_skipped++;
        } else {
            st->nearest_checked++;
            if (!(e == 0) && bad++ < 6)
                CHECKF(
                    0,
                    "%s %s %ux%u nearest: direction (%g, %g, %g) face %u (%.9g, %.9g): %.9g, CPU %.9g",
                    dev, layout_name(l), w, h, d[0], d[1], d[2], c.face, c.u, c.v, got[0], want[0]);
        }
        st->compared++;
    }
    if (bad > 6)
        fprintf(stderr, "%s %s %ux%u %s: %d disagreements in all\n", dev, layout_name(l), w, h,
                bilinear ? "bilinear" : "nearest", bad);
}

/* ---- GL -------------------------------------------------------------------------------------- */

static int run_gl(const lg_gl *gl, GLuint prog, lg_probe_layout l, uint32_t w, uint32_t h,
                  int bilinear, const float *rot, const float *rgba, const float *dirs, uint32_t n,
                  float *res)
{
    GLuint tex = 0, buf[2];
    if (l == LG_PROBE_CUBE) {
        gl->CreateTextures(GL_TEXTURE_CUBE_MAP, 1, &tex);
        gl->TextureStorage2D(tex, 1, GL_RGBA32F, (GLsizei)w, (GLsizei)w);
        for (uint32_t f = 0; f < 6; f++)
            gl->TextureSubImage3D(tex, 0, 0, 0, (GLint)f, (GLsizei)w, (GLsizei)w, 1, GL_RGBA,
                                  GL_FLOAT, rgba + (size_t)f * w * w * 4);
        GLint filter = bilinear ? GL_LINEAR : GL_NEAREST;
        gl->TextureParameteri(tex, GL_TEXTURE_MIN_FILTER, filter);
        gl->TextureParameteri(tex, GL_TEXTURE_MAG_FILTER, filter);
        gl->TextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        gl->TextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        gl->BindTextureUnit(1, tex);
    } else {
        gl->CreateTextures(GL_TEXTURE_2D, 1, &tex);
        gl->TextureStorage2D(tex, 1, GL_RGBA32F, (GLsizei)w, (GLsizei)h);
        gl->TextureSubImage2D(tex, 0, 0, 0, (GLsizei)w, (GLsizei)h, GL_RGBA, GL_FLOAT, rgba);
        gl->TextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        gl->TextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl->BindTextureUnit(0, tex);
    }
    gl->Enable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    gl->CreateBuffers(2, buf);
    gl->NamedBufferData(buf[0], (GLsizeiptr)n * 16, dirs, GL_STATIC_DRAW);
    gl->NamedBufferData(buf[1], (GLsizeiptr)n * 32, NULL, GL_STATIC_READ);
    gl->UseProgram(prog);
    gl->Uniform1ui(0, n);
    gl->Uniform1i(1, (GLint)l);
    gl->Uniform1i(2, bilinear);
    gl->UniformMatrix3fv(3, 1, GL_FALSE, rot);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf[0]);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buf[1]);
    gl->DispatchCompute((n + 63) / 64, 1, 1);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl->GetNamedBufferSubData(buf[1], 0, (GLsizeiptr)n * 32, res);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    gl->UseProgram(0);
    gl->BindTextureUnit(0, 0);
    gl->BindTextureUnit(1, 0);
    gl->Disable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    gl->DeleteBuffers(2, buf);
    gl->DeleteTextures(1, &tex);
    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "GL error %s", lg_gl_strerror(e));
    return e == GL_NO_ERROR ? 0 : -1;
}

/* ---- CL -------------------------------------------------------------------------------------- */

static int run_cl(lg_cl_dev *dev, cl_kernel k, lg_probe_layout l, uint32_t w, uint32_t h,
                  int bilinear, const float *rot, const float *rgba, const float *dirs, uint32_t n,
                  float *res)
{
    cl_context ctx = lg_cl_device_context(dev);
    cl_command_queue q = lg_cl_device_queue(dev);
    cl_int e;
    size_t texels = (size_t)w * h * (l == LG_PROBE_CUBE ? 6 : 1);
    cl_mem mi = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, texels * 16,
                               (void *)rgba, &e);
    cl_mem md = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n * 16,
                               (void *)dirs, &e);
    cl_mem mr = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)n * 32, NULL, &e);
    int rc = -1;
    if (!mi || !md || !mr) {
        CHECKF(0, "clCreateBuffer: %s", lg_cl_strerror(e));
        goto out;
    }
    cl_int lay = (cl_int)l, cw = (cl_int)w, ch = (cl_int)h, cb = bilinear, cn = (cl_int)n;
    clSetKernelArg(k, 0, sizeof mi, &mi);
    clSetKernelArg(k, 1, sizeof lay, &lay);
    clSetKernelArg(k, 2, sizeof cw, &cw);
    clSetKernelArg(k, 3, sizeof ch, &ch);
    clSetKernelArg(k, 4, sizeof cb, &cb);
    clSetKernelArg(k, 5, sizeof md, &md);
    clSetKernelArg(k, 6, sizeof mr, &mr);
    clSetKernelArg(k, 7, sizeof cn, &cn);
    for (int c = 0; c < 3; c++) {
        cl_float4 col = { { rot[3 * c], rot[3 * c + 1], rot[3 * c + 2], 0 } };
        clSetKernelArg(k, 8 + (cl_uint)c, sizeof col, &col);
    }
    size_t global = n;
    e = clEnqueueNDRangeKernel(q, k, 1, NULL, &global, NULL, 0, NULL, NULL);
    CHECKF(e == CL_SUCCESS, "clEnqueueNDRangeKernel: %s", lg_cl_strerror(e));
    if (e == CL_SUCCESS) {
        e = clEnqueueReadBuffer(q, mr, CL_TRUE, 0, (size_t)n * 32, res, 0, NULL, NULL);
        CHECKF(e == CL_SUCCESS, "clEnqueueReadBuffer: %s", lg_cl_strerror(e));
        rc = e == CL_SUCCESS ? 0 : -1;
    }
out:
    if (mi)
        clReleaseMemObject(mi);
    if (md)
        clReleaseMemObject(md);
    if (mr)
        clReleaseMemObject(mr);
    return rc;
}

/* ---- main ------------------------------------------------------------------------------------ */

int main(int argc, char **argv)
{
    if (argc != 2 || (strcmp(argv[1], "gl") && strcmp(argv[1], "cl"))) {
        fprintf(stderr, "usage: test_probe_devices gl|cl\n");
        return 2;
    }
    int use_gl = strcmp(argv[1], "gl") == 0;
    char err[1024] = "", err2[512] = "";
    lg_gl_device *gldev = NULL;
    lg_cl_dev *cldev = NULL;
    const lg_gl *gl = NULL;
    GLuint prog = 0;
    cl_kernel kern = NULL;
    if (use_gl) {
        if (lg_gl_device_create(&gldev, "osmesa", err, sizeof err) &&
            lg_gl_device_create(&gldev, "egl", err2, sizeof err2)) {
            CHECKF(0, "no GL device (a failure: llvmpipe is a dependency): %s; %s", err, err2);
            return check_report("probe_devices_gl");
        }
        gl = lg_gl_device_table(gldev);
        printf("gl: %s\n", lg_gl_device_description(gldev));
        lg_gl_shader_src src = { GL_COMPUTE_SHADER, lg_src_probe_eval_comp_file,
                                 lg_src_probe_eval_comp };
        devtest_clear();
        prog = lg_gl_program(devtest_node(), gl, &src, 1, NULL);
        CHECKF(prog != 0, "probe_eval.comp: %s", devtest_errors);
        if (!prog) {
            lg_gl_device_destroy(&gldev);
            return check_report("probe_devices_gl");
        }
    } else {
        if (lg_cl_device_create(&cldev, err, sizeof err)) {
            CHECKF(0, "no CL device (a failure: PoCL is a dependency): %s", err);
            return check_report("probe_devices_cl");
        }
        printf("cl: %s\n", lg_cl_device_description(cldev));
        /* probe.cl, then the kernel */
        const char *parts[] = { lg_src_probe_cl, lg_src_probe_eval_cl };
        char *src = test_cl_join(parts, 2);
        CHECKF(src != NULL, "out of memory");
        char *log = NULL;
        cl_program p = src ? lg_cl_device_program(cldev, "probe_eval.cl", src, NULL, &log) : NULL;
        free(src);
        CHECKF(p != NULL, "%s", log ? log : "build failed");
        free(log);
        cl_int e = CL_SUCCESS;
        if (p)
            kern = clCreateKernel(p, "probe_eval", &e);
        CHECKF(kern != NULL, "clCreateKernel: %s", lg_cl_strerror(e));
        if (!kern) {
            lg_cl_device_destroy(&cldev);
            return check_report("probe_devices_cl");
        }
    }

    enum { CAP = 8192 };
    float *dirs = malloc(CAP * 16), *res = malloc(CAP * 32);
    uint32_t n = make_dirs(dirs, CAP, 6000);
    struct {
        lg_probe_layout l;
        uint32_t w, h;
    } cases[] = {
        { LG_PROBE_LATLONG, 1, 1 },     { LG_PROBE_LATLONG, 2, 1 },
        { LG_PROBE_LATLONG, 64, 32 },   { LG_PROBE_LATLONG, 33, 17 },
        { LG_PROBE_LATLONG, 512, 256 }, { LG_PROBE_ANGULAR, 1, 1 },
        { LG_PROBE_ANGULAR, 3, 3 },     { LG_PROBE_ANGULAR, 64, 64 },
        { LG_PROBE_ANGULAR, 513, 513 }, { LG_PROBE_CUBE, 1, 1 },
        { LG_PROBE_CUBE, 2, 2 },        { LG_PROBE_CUBE, 16, 16 },
        { LG_PROBE_CUBE, 128, 128 },
    };
    stats total[3][2];
    memset(total, 0, sizeof total);
    const float identity[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    float rotation[9];
    lg_probe_rotation_from_euler(30, -20, 10, rotation);
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        lg_probe_layout l = cases[c].l;
        uint32_t w = cases[c].w, h = cases[c].h;
        size_t texels = (size_t)w * h * (l == LG_PROBE_CUBE ? 6 : 1);
        float *rgba = malloc(texels * 16);
        for (size_t k = 0; k < texels * 4; k++)
            rgba[k] = (float)rnd();
        /* nearest and bilinear with no rotation (the hard cases are probe directions),
         * then bilinear through a rotation (world directions) */
        for (int pass = 0; pass < 3; pass++) {
            int b = pass > 0;
            const float *rot = pass == 2 ? rotation : identity;
            stats st;
            memset(&st, 0, sizeof st);
            double t0 = devtest_now();
            int rc = use_gl ? run_gl(gl, prog, l, w, h, b, rot, rgba, dirs, n, res)
                            : run_cl(cldev, kern, l, w, h, b, rot, rgba, dirs, n, res);
            double t1 = devtest_now();
            if (rc)
                continue;
            compare(argv[1], l, w, h, b, rot, dirs, n, res, rgba, &st);
            if (b)
                printf(
                    "%s %-7s %4ux%-4u bilinear%s: %u directions, coordinates within %.2e, values "
                    "within %.2e (%.2f of the tolerance), %.1f ms\n",
                    argv[1], layout_name(l), w, h, pass == 2 ? " rotated" : "", st.compared,
                    st.coord, st.bilinear_abs, st.bilinear_ratio, (t1 - t0) * 1e3);
            else
                printf("%s %-7s %4ux%-4u nearest : %u directions, coordinates within %.2e, %u "
                       "equal, %u near a texel border or face tie not compared, %.1f ms\n",
                       argv[1], layout_name(l), w, h, st.compared, st.coord, st.nearest_checked,
                       st.nearest_skipped, (t1 - t0) * 1e3);
            stats *t = &total[l - 1][b];
            t->coord = fmax(t->coord, st.coord);
            t->bilinear_abs = fmax(t->bilinear_abs, st.bilinear_abs);
            t->bilinear_ratio = fmax(t->bilinear_ratio, st.bilinear_ratio);
        }
        free(rgba);
    }
    /* constant images read back exactly their constant on the device too (the seed's
     * oracle for every later node: a constant probe gives exactly c) */
    {
        struct {
            lg_probe_layout l;
            uint32_t w, h;
        } cc[] = { { LG_PROBE_LATLONG, 9, 5 },
                   { LG_PROBE_ANGULAR, 9, 9 },
                   { LG_PROBE_CUBE, 5, 5 },
                   { LG_PROBE_CUBE, 1, 1 } };
        const float cs[] = { 0.1f, 12345.678f, 262016.0f };
        for (size_t c = 0; c < sizeof cc / sizeof cc[0]; c++)
            for (size_t q = 0; q < sizeof cs / sizeof cs[0]; q++) {
                size_t texels = (size_t)cc[c].w * cc[c].h * (cc[c].l == LG_PROBE_CUBE ? 6 : 1);
                float *rgba = malloc(texels * 16);
                for (size_t k = 0; k < texels * 4; k++)
                    rgba[k] = cs[q];
                for (int b = 0; b < 2; b++) {
                    int rc = use_gl ? run_gl(gl, prog, cc[c].l, cc[c].w, cc[c].h, b, identity, rgba,
                                             dirs, n, res)
                                    : run_cl(cldev, kern, cc[c].l, cc[c].w, cc[c].h, b, identity,
                                             rgba, dirs, n, res);
                    if (rc)
                        continue;
                    /* llvmpipe's seamless filter averages a cube corner's three texels
                     * in a way that may round by an ulp: the samplerCube is held to 2 ulp,
                     * everything else (our own arithmetic) to exactly c */
                    double tol = use_gl && cc[c].l == LG_PROBE_CUBE && b ? 2.4e-7 * cs[q] : 0;
                    int bad = 0;
                    for (uint32_t k = 0; k < n; k++)
                        for (int ch = 0; ch < 4; ch++)
                            if (!(fabs((double)res[8 * k + ch] - cs[q]) <= tol) && bad++ < 3)
                                CHECKF(0,
                                       "%s %s %ux%u %s: constant %.9g reads %.9g along (%g %g %g)",
                                       argv[1], layout_name(cc[c].l), cc[c].w, cc[c].h,
                                       b ? "bilinear" : "nearest", cs[q], res[8 * k + ch],
                                       dirs[4 * k], dirs[4 * k + 1], dirs[4 * k + 2]);
                }
                free(rgba);
            }
        printf("%s: constant images (0.1, 12345.678, 262016) read back exactly, every layout%s\n",
               argv[1], use_gl ? " (the samplerCube's bilinear within 2 ulp)" : "");
    }
    for (int l = 0; l < 3; l++)
        printf("%s vs CPU, %s: coordinates within %.2e, bilinear values within %.2e "
               "(%.2f of the tolerance)\n",
               argv[1], layout_name((lg_probe_layout)(l + 1)),
               fmax(total[l][0].coord, total[l][1].coord), total[l][1].bilinear_abs,
               total[l][1].bilinear_ratio);
    free(dirs);
    free(res);
    if (use_gl) {
        gl->DeleteProgram(prog);
        lg_gl_device_destroy(&gldev);
    } else {
        clReleaseKernel(kern);
        lg_cl_device_destroy(&cldev);
    }
    return check_report(use_gl ? "probe_devices_gl" : "probe_devices_cl");
}
