/*
 * shaders/common/rgbe.glsl and rgbe.cl against the C reference (sdk/src/rgbe.c,
 * lightgraph/image.h):
 *
 *   test_rgbe_devices gl   rgbe.glsl in a compute shader (llvmpipe through OSMesa): the
 *                          encoded bytes as numbers and as stored into an RGBA8 image (the
 *                          way an rgbe8 target is written), the decode of bytes given as
 *                          numbers and as an RGBA8 texel (texelFetch, / 255)
 *   test_rgbe_devices cl   rgbe.cl in a kernel (PoCL): uchar4 in and out
 *
 * Inputs: random colours over 2^-100 .. 2^100 (each channel log-uniform, so one channel is
 * often far below the largest), every power of two of the normal floats, rounding ties
 * (a channel exactly half way between two mantissa steps) on both sides, the mantissa
 * round-up that bumps the exponent (255.5 / 256 of a power of two), 0, -0, negative, NaN,
 * +Inf, -Inf, 1e-38, FLT_MIN, values at and above 2^127, FLT_MAX, one channel at the
 * maximum with zero others. The encoded bytes must equal the C encoder's exactly; the
 * decode of every exponent byte with a spread of mantissas must equal the C decoder's
 * exactly; lg_half_range must give clamp(v, -65504, 65504) (Inf included), 0 for NaN, and
 * lg_half_range_count the count lg_pixels_from_rgba32f gives.
 *
 * Intended difference, measured here: float denormals (below FLT_MIN = 1.18e-38). The C
 * encoder treats a largest channel below FLT_MIN as black (so do the twins), so no input
 * with a normal or zero largest channel depends on denormal support; a denormal channel
 * beside a normal maximum may be flushed to 0 by a GPU (llvmpipe runs with flush-to-zero).
 * Decoded values below FLT_MIN (exponent bytes below 10) may likewise read as 0 on a GPU.
 * Those cases are counted and printed, not failed.
 * A missing device is a failure: the CI machines have llvmpipe and PoCL.
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
#include "lightgraph/image.h"
#include "rgbe.cl.h"
#include "rgbe_eval.cl.h"
#include "rgbe_eval.comp.h"

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static uint32_t n_in;
static float *in; /* rgba per input */

static void add(float r, float g, float b)
{
    in[4 * n_in] = r;
    in[4 * n_in + 1] = g;
    in[4 * n_in + 2] = b;
    in[4 * n_in + 3] = (n_in % 5 == 0) ? 70000.0f : (n_in % 5 == 1) ? NAN : 0.5f * r;
    n_in++;
}

/* Whether an input has a denormal channel (the intended difference). */
static int has_denormal(const float *v)
{
    for (int c = 0; c < 3; c++)
        if (v[c] != 0 && fabsf(v[c]) < FLT_MIN)
            return 1;
    return 0;
}

static void make_inputs(uint32_t cap)
{
    in = malloc((size_t)cap * 16);
    n_in = 0;
    const float inf = INFINITY, nan = NAN;
    const float special[][3] = {
        { 0, 0, 0 },
        { -0.0f, 0, -0.0f },
        { -1, -2, -3 },
        { -1, 0.5f, 2 },
        { nan, 1, 2 },
        { nan, nan, nan },
        { inf, 0, 0 },
        { inf, 1, 2 },
        { inf, inf, inf },
        { -inf, 3, 0 },
        { nan, inf, -inf },
        { 1e-38f, 0, 0 },
        { 1e-38f, 1e-38f, 1e-38f },
        { FLT_MIN, 0, 0 },
        { FLT_MIN, FLT_MIN, 1e-39f },
        { 1.1754942e-38f, 0, 0 }, /* the largest denormal */
        { 0x1p127f, 0, 0 },
        { 0x1p127f, 1, 0x1p126f },
        { 0x1.fep126f, 0, 0 },
        { 0x1.ffp126f, 1, 1 },
        { 3e38f, 1e38f, 0 },
        { FLT_MAX, FLT_MAX, FLT_MAX },
        { FLT_MAX, 0, 1 },
        { 1, 0, 0 },
        { 0, 1, 0 },
        { 0, 0, 1 },
        { 65504, 0, 0 },
        { 0, 0, 1e30f },
        { 0, 7, 0 },
        { 0.5f, 0.25f, 0.125f },
        { 1, 1, 1 },
        { 255.0f / 256, 0, 0 },
        { 255.5f / 256, 0, 0 },
        { 0x1.ffp-1f, 0x1.ffp-1f, 0 },
        { 0x1.fefffep-1f, 0, 0 },
        { 1e10f, 1e-10f, 1 },
        { 0.1f, 0.2f, 0.3f },
    };
    for (size_t k = 0; k < sizeof special / sizeof special[0]; k++)
        add(special[k][0], special[k][1], special[k][2]);
    /* every power of two of the normal floats, in each channel, with smaller others */
    for (int e = -126; e <= 127; e++) {
        float p = ldexpf(1.0f, e);
        add(p, 0, 0);
        add(0.3f * p, p, 0.7f * p);
        add(0, 0.99f * p, p);
    }
    /* ties: the largest channel's mantissa k + 0.5 in units of 2^(e-8), for every k; the
     * rounding of the other channels at exactly half a step; the exponent bump */
    for (int e = -100; e <= 120; e += 11) {
        for (int k = 128; k < 256; k++) {
            float m = ldexpf((float)k + 0.5f, e - 8); /* in [2^(e-1), 2^e): exponent e */
            add(m, ldexpf((float)(k / 3) + 0.5f, e - 8), ldexpf(0.5f, e - 8));
        }
        add(ldexpf(255.5f, e - 8), 0, 0);  /* rounds to 256: bumps the exponent */
        add(ldexpf(255.49f, e - 8), 0, 0); /* stays */
        add(ldexpf(255.75f, e - 8), ldexpf(1.5f, e - 8), 0);
    }
    /* random colours: log-uniform channels over 2^-100 .. 2^100, sometimes grey-ish */
    while (n_in < cap) {
        float v[3];
        double base = ldexp(1.0, (int)(rnd() * 200) - 100);
        for (int c = 0; c < 3; c++) {
            double spread = (n_in % 2) ? 1 : 40;
            v[c] = (float)(base * exp2((rnd() - 0.5) * spread));
        }
        if (n_in % 17 == 0)
            v[n_in % 3] = 0;
        add(v[0], v[1], v[2]);
    }
}

/* Bytes to decode: every exponent byte with mantissas 0, 1, 127, 128, 200, 255 and random
 * ones. */
static void make_bytes(uint8_t *b, uint32_t n)
{
    const uint8_t ms[] = { 0, 1, 127, 128, 200, 255 };
    for (uint32_t k = 0; k < n; k++) {
        uint8_t e = (uint8_t)(k % 256);
        uint32_t j = k / 256;
        b[4 * k + 3] = e;
        for (int c = 0; c < 3; c++)
            b[4 * k + c] = j < 6 ? ms[(j + (uint32_t)c) % 6] : (uint8_t)(rnd() * 256);
    }
}

typedef struct result {
    uint8_t *enc, *enc_image;
    float *dec, *dec_unorm, *half;
} result;

static int same_float(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0 || (a == 0 && b == 0);
}

/* ---- GL -------------------------------------------------------------------------------------- */

static int run_gl(const lg_gl *gl, GLuint prog, const uint8_t *bytes, uint32_t n, result *r)
{
    GLuint buf[5], tex[2];
    uint32_t *bytes_u = malloc((size_t)n * 16), *enc_u = malloc((size_t)n * 16);
    float *dec2 = malloc((size_t)n * 32);
    for (uint32_t k = 0; k < 4 * n; k++)
        bytes_u[k] = bytes[k];
    gl->CreateBuffers(5, buf);
    gl->NamedBufferData(buf[0], (GLsizeiptr)n * 16, in, GL_STATIC_DRAW);
    gl->NamedBufferData(buf[1], (GLsizeiptr)n * 16, bytes_u, GL_STATIC_DRAW);
    gl->NamedBufferData(buf[2], (GLsizeiptr)n * 16, NULL, GL_STATIC_READ);
    gl->NamedBufferData(buf[3], (GLsizeiptr)n * 32, NULL, GL_STATIC_READ);
    gl->NamedBufferData(buf[4], (GLsizeiptr)n * 16, NULL, GL_STATIC_READ);
    gl->CreateTextures(GL_TEXTURE_2D, 2, tex);
    gl->TextureStorage2D(tex[0], 1, GL_RGBA8, (GLsizei)n, 1);
    gl->TextureStorage2D(tex[1], 1, GL_RGBA8, (GLsizei)n, 1);
    gl->TextureSubImage2D(tex[1], 0, 0, 0, (GLsizei)n, 1, GL_RGBA, GL_UNSIGNED_BYTE, bytes);
    gl->TextureParameteri(tex[1], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl->TextureParameteri(tex[1], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl->UseProgram(prog);
    gl->Uniform1ui(0, n);
    for (GLuint k = 0; k < 5; k++)
        gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, k, buf[k]);
    gl->BindImageTexture(0, tex[0], 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    gl->BindTextureUnit(0, tex[1]);
    gl->DispatchCompute((n + 63) / 64, 1, 1);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    gl->GetNamedBufferSubData(buf[2], 0, (GLsizeiptr)n * 16, enc_u);
    gl->GetNamedBufferSubData(buf[3], 0, (GLsizeiptr)n * 32, dec2);
    gl->GetNamedBufferSubData(buf[4], 0, (GLsizeiptr)n * 16, r->half);
    gl->GetTextureImage(tex[0], 0, GL_RGBA, GL_UNSIGNED_BYTE, (GLsizei)n * 4, r->enc_image);
    for (uint32_t k = 0; k < n; k++) {
        for (int c = 0; c < 4; c++) {
            r->enc[4 * k + c] = enc_u[4 * k + c] > 255 ? 0xee : (uint8_t)enc_u[4 * k + c];
            r->dec[4 * k + c] = dec2[8 * k + c];
            r->dec_unorm[4 * k + c] = dec2[8 * k + 4 + c];
        }
    }
    for (GLuint k = 0; k < 5; k++)
        gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, k, 0);
    gl->BindImageTexture(0, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    gl->BindTextureUnit(0, 0);
    gl->UseProgram(0);
    gl->DeleteBuffers(5, buf);
    gl->DeleteTextures(2, tex);
    free(bytes_u);
    free(enc_u);
    free(dec2);
    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "GL error %s", lg_gl_strerror(e));
    return e == GL_NO_ERROR ? 0 : -1;
}

/* ---- CL -------------------------------------------------------------------------------------- */

static int run_cl(lg_cl_dev *dev, cl_kernel k, const uint8_t *bytes, uint32_t n, result *r)
{
    cl_context ctx = lg_cl_device_context(dev);
    cl_command_queue q = lg_cl_device_queue(dev);
    cl_int e = CL_SUCCESS;
    cl_mem m[5];
    m[0] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n * 16, in, &e);
    m[1] = clCreateBuffer(ctx, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, (size_t)n * 4,
                          (void *)bytes, &e);
    m[2] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)n * 4, NULL, &e);
    m[3] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)n * 16, NULL, &e);
    m[4] = clCreateBuffer(ctx, CL_MEM_WRITE_ONLY, (size_t)n * 16, NULL, &e);
    int rc = -1;
    for (int i = 0; i < 5; i++)
        if (!m[i]) {
            CHECKF(0, "clCreateBuffer: %s", lg_cl_strerror(e));
            goto out;
        }
    cl_int cn = (cl_int)n;
    for (cl_uint i = 0; i < 5; i++)
        clSetKernelArg(k, i, sizeof m[i], &m[i]);
    clSetKernelArg(k, 5, sizeof cn, &cn);
    size_t global = n;
    e = clEnqueueNDRangeKernel(q, k, 1, NULL, &global, NULL, 0, NULL, NULL);
    CHECKF(e == CL_SUCCESS, "clEnqueueNDRangeKernel: %s", lg_cl_strerror(e));
    if (e != CL_SUCCESS)
        goto out;
    e = clEnqueueReadBuffer(q, m[2], CL_TRUE, 0, (size_t)n * 4, r->enc, 0, NULL, NULL);
    if (e == CL_SUCCESS)
        e = clEnqueueReadBuffer(q, m[3], CL_TRUE, 0, (size_t)n * 16, r->dec, 0, NULL, NULL);
    if (e == CL_SUCCESS)
        e = clEnqueueReadBuffer(q, m[4], CL_TRUE, 0, (size_t)n * 16, r->half, 0, NULL, NULL);
    CHECKF(e == CL_SUCCESS, "clEnqueueReadBuffer: %s", lg_cl_strerror(e));
    rc = e == CL_SUCCESS ? 0 : -1;
out:
    for (int i = 0; i < 5; i++)
        if (m[i])
            clReleaseMemObject(m[i]);
    return rc;
}

/* ---- comparing ------------------------------------------------------------------------------- */

static void compare_encode(const char *what, const uint8_t *got, uint32_t n, uint32_t *denormal)
{
    int bad = 0;
    uint32_t exact = 0;
    for (uint32_t k = 0; k < n; k++) {
        uint8_t want[4];
        lg_rgbe_encode(in + 4 * k, want);
        if (memcmp(want, got + 4 * k, 4) == 0) {
            exact++;
            continue;
        }
        if (has_denormal(in + 4 * k)) {
            (*denormal)++;
            continue;
        }
        if (bad++ < 8)
            CHECKF(0, "%s: encode (%a, %a, %a) = %u %u %u %u, C %u %u %u %u", what, in[4 * k],
                   in[4 * k + 1], in[4 * k + 2], got[4 * k], got[4 * k + 1], got[4 * k + 2],
                   got[4 * k + 3], want[0], want[1], want[2], want[3]);
    }
    if (bad > 8)
        CHECKF(0, "%s: %d encodings differ in all", what, bad);
    printf("%s: %u of %u inputs encode to the C bytes exactly\n", what, exact, n);
}

static void compare_decode(const char *what, const uint8_t *bytes, const float *got, uint32_t n,
                           uint32_t *flushed)
{
    int bad = 0;
    uint32_t exact = 0;
    for (uint32_t k = 0; k < n; k++) {
        float want[3];
        lg_rgbe_decode(bytes + 4 * k, want);
        int ok = 1, ftz = 0;
        for (int c = 0; c < 3; c++) {
            if (same_float(want[c], got[4 * k + c]))
                continue;
            if (want[c] < FLT_MIN && got[4 * k + c] == 0)
                ftz = 1; /* a denormal result flushed */
            else
                ok = 0;
        }
        if (ok && !ftz)
            exact++;
        else if (ok)
            (*flushed)++;
        else if (bad++ < 8)
            CHECKF(0, "%s: decode %u %u %u %u = (%a, %a, %a), C (%a, %a, %a)", what, bytes[4 * k],
                   bytes[4 * k + 1], bytes[4 * k + 2], bytes[4 * k + 3], got[4 * k], got[4 * k + 1],
                   got[4 * k + 2], want[0], want[1], want[2]);
    }
    if (bad > 8)
        CHECKF(0, "%s: %d decodes differ in all", what, bad);
    printf("%s: %u of %u byte quads decode to the C floats exactly\n", what, exact, n);
}

static void compare_half(const char *what, const float *got, const float *dec, uint32_t n)
{
    int bad = 0;
    /* the count in dec[].w against lg_pixels_from_rgba32f's */
    for (uint32_t k = 0; k < n; k++) {
        uint16_t h[4];
        uint64_t want = 0;
        lg_pixels_from_rgba32f(LG_FORMAT_RGBA16F, in + 4 * k, 1, h, &want);
        if (dec[4 * k + 3] != (float)want && bad++ < 8)
            CHECKF(0, "%s: lg_half_range_count(%a %a %a %a) = %g, C %llu", what, in[4 * k],
                   in[4 * k + 1], in[4 * k + 2], in[4 * k + 3], dec[4 * k + 3],
                   (unsigned long long)want);
    }
    for (uint32_t k = 0; k < n; k++)
        for (int c = 0; c < 4; c++) {
            float v = in[4 * k + c];
            float want = isnan(v) ? 0.0f : fminf(fmaxf(v, -65504.0f), 65504.0f);
            float g = got[4 * k + c];
            int ok = same_float(want, g) || (fabsf(want) < FLT_MIN && g == 0);
            if (!ok && bad++ < 8)
                CHECKF(0, "%s: lg_half_range(%a) = %a, want %a", what, v, g, want);
        }
    printf("%s: lg_half_range is clamp(v, -65504, 65504) with NaN 0 on %u x 4 values, "
           "lg_half_range_count the C count%s\n",
           what, n, bad ? " EXCEPT the above" : "");
}

int main(int argc, char **argv)
{
    if (argc != 2 || (strcmp(argv[1], "gl") && strcmp(argv[1], "cl"))) {
        fprintf(stderr, "usage: test_rgbe_devices gl|cl\n");
        return 2;
    }
    int use_gl = strcmp(argv[1], "gl") == 0;
    const char *name = use_gl ? "rgbe_glsl_vs_c" : "rgbe_cl_vs_c";
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
            return check_report(name);
        }
        gl = lg_gl_device_table(gldev);
        printf("gl: %s\n", lg_gl_device_description(gldev));
        lg_gl_shader_src src = { GL_COMPUTE_SHADER, lg_src_rgbe_eval_comp_file,
                                 lg_src_rgbe_eval_comp };
        devtest_clear();
        prog = lg_gl_program(devtest_node(), gl, &src, 1, NULL);
        CHECKF(prog != 0, "rgbe_eval.comp: %s", devtest_errors);
        if (!prog) {
            lg_gl_device_destroy(&gldev);
            return check_report(name);
        }
    } else {
        if (lg_cl_device_create(&cldev, err, sizeof err)) {
            CHECKF(0, "no CL device (a failure: PoCL is a dependency): %s", err);
            return check_report(name);
        }
        printf("cl: %s\n", lg_cl_device_description(cldev));
        const char *parts[] = { lg_src_rgbe_cl, lg_src_rgbe_eval_cl };
        char *src = test_cl_join(parts, 2);
        CHECKF(src != NULL, "out of memory");
        char *log = NULL;
        cl_program p = src ? lg_cl_device_program(cldev, "rgbe_eval.cl", src, NULL, &log) : NULL;
        free(src);
        CHECKF(p != NULL, "%s", log ? log : "build failed");
        free(log);
        cl_int e = CL_SUCCESS;
        if (p)
            kern = clCreateKernel(p, "rgbe_eval", &e);
        CHECKF(kern != NULL, "clCreateKernel: %s", lg_cl_strerror(e));
        if (!kern) {
            lg_cl_device_destroy(&cldev);
            return check_report(name);
        }
    }

    enum { N = 16384 }; /* at most GL_MAX_TEXTURE_SIZE wide (16384 on llvmpipe) */
    make_inputs(N);
    uint8_t *bytes = malloc((size_t)N * 4);
    make_bytes(bytes, N);
    result r;
    r.enc = malloc((size_t)N * 4);
    r.enc_image = malloc((size_t)N * 4);
    r.dec = malloc((size_t)N * 16);
    r.dec_unorm = malloc((size_t)N * 16);
    r.half = malloc((size_t)N * 16);
    double t0 = devtest_now();
    int rc = use_gl ? run_gl(gl, prog, bytes, N, &r) : run_cl(cldev, kern, bytes, N, &r);
    double t1 = devtest_now();
    if (rc == 0) {
        uint32_t denormal = 0, flushed = 0;
        compare_encode(use_gl ? "gl encode (SSBO)" : "cl encode", r.enc, N, &denormal);
        if (use_gl)
            compare_encode("gl encode (RGBA8 imageStore)", r.enc_image, N, &denormal);
        compare_decode(use_gl ? "gl decode" : "cl decode", bytes, r.dec, N, &flushed);
        if (use_gl)
            compare_decode("gl decode_unorm (RGBA8 texelFetch)", bytes, r.dec_unorm, N, &flushed);
        compare_half(argv[1], r.half, r.dec, N);
        printf("%s: intended differences: %u encodings of inputs with a denormal channel, %u "
               "decodes below FLT_MIN read as 0 (flush to zero); %.1f ms\n",
               argv[1], denormal, flushed, (t1 - t0) * 1e3);
    }
    free(in);
    free(bytes);
    free(r.enc);
    free(r.enc_image);
    free(r.dec);
    free(r.dec_unorm);
    free(r.half);
    if (use_gl) {
        gl->DeleteProgram(prog);
        lg_gl_device_destroy(&gldev);
    } else {
        clReleaseKernel(kern);
        lg_cl_device_destroy(&cldev);
    }
    return check_report(name);
}
