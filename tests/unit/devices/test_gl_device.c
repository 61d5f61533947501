/* The GL device on one backend (argv[1]: osmesa or egl): creation, version and profile,
 * a compute shader through lg_gl_program, compiler and linker messages, the state
 * contract, a timer query, and destroy/re-create. Exits 77 if no context can be made. */
#include <stdint.h>
#include <string.h>

#include "exec/device.h"
#include "devtest.h"
#include "lightgraph/gl.h"

static const char square_comp[] = "#version 450\n"
                                  "layout(local_size_x = 64) in;\n"
                                  "layout(std430, binding = 0) buffer Out { uint v[]; };\n"
                                  "void main()\n"
                                  "{\n"
                                  "    uint i = gl_GlobalInvocationID.x;\n"
                                  "    v[i] = i * SCALE + OFFSET;\n"
                                  "}\n";

/* The error sits on line 5 of the file; the defines must not shift it. */
static const char bad_comp[] = "#version 450\n"
                               "layout(local_size_x = 1) in;\n"
                               "void main()\n"
                               "{\n"
                               "    this is not glsl;\n"
                               "}\n";

/* #version after a comment header: the error is on line 7. */
static const char bad_late_version_comp[] = "// A shader whose #version is not on line 1.\n"
                                            "\n"
                                            "#version 450\n"
                                            "layout(local_size_x = 1) in;\n"
                                            "void main()\n"
                                            "{\n"
                                            "    this is not glsl;\n"
                                            "}\n";

/* Compiles, but a compute program needs main(). */
static const char nomain_comp[] = "#version 450\n"
                                  "layout(local_size_x = 1) in;\n"
                                  "void helper() {}\n";

enum { N = 256 };

static void test_version(const lg_gl *gl, const lg_gl_device *dev, const char *label)
{
    GLint major = 0, minor = 0, profile = 0;
    gl->GetIntegerv(GL_MAJOR_VERSION, &major);
    gl->GetIntegerv(GL_MINOR_VERSION, &minor);
    gl->GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    CHECKF(major > 4 || (major == 4 && minor >= 5), "GL %d.%d", major, minor);
    CHECKF(profile & GL_CONTEXT_CORE_PROFILE_BIT, "profile mask 0x%x", (unsigned)profile);
    CHECKF(gl->VERSION_4_5, "glad did not load 4.5");
    CHECKF(gl->DispatchCompute && gl->GetNamedBufferSubData && gl->BindImageTextures,
           "4.5 entry points missing");
    const char *desc = lg_gl_device_description(dev);
    CHECKF(strncmp(desc, label, strlen(label)) == 0, "description '%s' should start with '%s'",
           desc, label);
    CHECKF(strstr(desc, (const char *)gl->GetString(GL_RENDERER)) != NULL,
           "description '%s' lacks the renderer", desc);
    CHECKF(strstr(desc, (const char *)gl->GetString(GL_VERSION)) != NULL,
           "description '%s' lacks the version", desc);
}

/* A compute shader through lg_gl_program with defines. */
static GLuint test_compute(const lg_gl *gl)
{
    lg_node *node = devtest_node();
    devtest_clear();
    lg_gl_shader_src src = { GL_COMPUTE_SHADER, "square.comp", square_comp };
    GLuint prog = lg_gl_program(node, gl, &src, 1, "#define SCALE 3u\n#define OFFSET 7u");
    CHECKF(prog != 0, "lg_gl_program failed: %s", devtest_errors);
    CHECKF(devtest_error_count == 0, "errors reported: %s", devtest_errors);
    if (!prog)
        return 0;

    GLuint buf;
    gl->CreateBuffers(1, &buf);
    gl->NamedBufferData(buf, N * sizeof(uint32_t), NULL, GL_DYNAMIC_READ);
    gl->UseProgram(prog);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
    gl->DispatchCompute(N / 64, 1, 1);
    gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    uint32_t out[N];
    memset(out, 0xff, sizeof out);
    gl->GetNamedBufferSubData(buf, 0, sizeof out, out);
    int bad = 0;
    for (uint32_t i = 0; i < N; i++)
        if (out[i] != i * 3u + 7u && bad++ < 4)
            CHECKF(0, "v[%u] = %u, expected %u", i, out[i], i * 3u + 7u);
    CHECKF(bad == 0, "%d of %d values wrong", bad, N);

    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "GL error %s", lg_gl_strerror(e));
    gl->DeleteBuffers(1, &buf);
    /* The program stays bound on purpose: the state test starts from here. */
    return prog;
}

static const char fullscreen_vert[] =
    "#version 450\n"
    "void main()\n"
    "{\n"
    "    vec2 p[3] = vec2[](vec2(-1, -1), vec2(3, -1), vec2(-1, 3));\n"
    "    gl_Position = vec4(p[gl_VertexID], 0, 1);\n"
    "}\n";
static const char busy_frag[] = "#version 450\n"
                                "out vec4 color;\n"
                                "void main()\n"
                                "{\n"
                                "    vec4 a = vec4(0);\n"
                                "    for (int i = 0; i < 64; i++)\n"
                                "        a += sin(gl_FragCoord.xyxy * float(i));\n"
                                "    color = a;\n"
                                "}\n";

/* GL_TIME_ELAPSED around a draw gives a duration: more than zero and no more than the
 * wall time from BeginQuery to the result. (llvmpipe times only rasterizer work: compute
 * dispatches are not counted, so a draw is what is measured here.) */
static void test_timer(const lg_gl *gl)
{
    lg_node *node = devtest_node();
    devtest_clear();
    lg_gl_shader_src src[2] = { { GL_VERTEX_SHADER, "fullscreen.vert", fullscreen_vert },
                                { GL_FRAGMENT_SHADER, "busy.frag", busy_frag } };
    GLuint prog = lg_gl_program(node, gl, src, 2, NULL);
    CHECKF(prog != 0, "draw program: %s", devtest_errors);
    if (!prog)
        return;
    GLuint tex, fbo, vao, query;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &tex);
    gl->TextureStorage2D(tex, 1, GL_RGBA8, 256, 256);
    gl->CreateFramebuffers(1, &fbo);
    gl->NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    gl->CreateVertexArrays(1, &vao);
    gl->GenQueries(1, &query);
    gl->BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl->Viewport(0, 0, 256, 256);
    gl->UseProgram(prog);
    gl->BindVertexArray(vao);
    gl->DrawArrays(GL_TRIANGLES, 0, 3); /* warm-up: shader variants are built at first draw */
    gl->Finish();
    for (int i = 0; i < 3; i++) {
        double t0 = devtest_now();
        gl->BeginQuery(GL_TIME_ELAPSED, query);
        gl->DrawArrays(GL_TRIANGLES, 0, 3);
        gl->EndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        gl->GetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
        double wall = devtest_now() - t0;
        GLint available = 0;
        gl->GetQueryObjectiv(query, GL_QUERY_RESULT_AVAILABLE, &available);
        CHECKF(available, "query result not available after GL_QUERY_RESULT");
        CHECKF(ns > 0 && ns * 1e-9 <= wall, "GL_TIME_ELAPSED = %llu ns, wall %.0f ns",
               (unsigned long long)ns, wall * 1e9);
        printf("draw 256x256: GL_TIME_ELAPSED %.3f ms, wall %.3f ms\n", ns * 1e-6, wall * 1e3);
    }
    lg_gl_state_reset(gl);
    gl->DeleteQueries(1, &query);
    gl->DeleteVertexArrays(1, &vao);
    gl->DeleteFramebuffers(1, &fbo);
    gl->DeleteTextures(1, &tex);
    gl->DeleteProgram(prog);
    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "GL error %s", lg_gl_strerror(e));
}

/* lg_gl_device_timer_query on a context no query ran on yet: a query object already spent
 * once (a name from GenQueries is a query object only once begun: IsQuery says whether the
 * warm-up ran), whose next use reads a duration no longer than the wall time around it, not
 * the absolute timestamp llvmpipe has given a context's first timer query. */
static void test_timer_query(lg_gl_device *dev)
{
    const lg_gl *gl = lg_gl_device_table(dev);
    GLuint query = lg_gl_device_timer_query(dev);
    CHECKF(query != 0 && gl->IsQuery(query), "lg_gl_device_timer_query gave %u, not a query",
           query);
    double t0 = devtest_now();
    gl->BeginQuery(GL_TIME_ELAPSED, query);
    gl->EndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    gl->GetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    double wall = devtest_now() - t0;
    CHECKF(ns * 1e-9 <= wall, "first timed use: GL_TIME_ELAPSED = %llu ns, wall %.0f ns",
           (unsigned long long)ns, wall * 1e9);
    gl->DeleteQueries(1, &query);
    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "GL error %s", lg_gl_strerror(e));
}

static void test_program_errors(const lg_gl *gl)
{
    lg_node *node = devtest_node();

    /* A syntax error: the message names the file, the stage, and the file's line. */
    devtest_clear();
    lg_gl_shader_src bad = { GL_COMPUTE_SHADER, "bad.comp", bad_comp };
    GLuint prog = lg_gl_program(node, gl, &bad, 1, "#define A 1\n#define B 2\n#define C 3\n");
    CHECKF(prog == 0, "a syntax error compiled");
    CHECKF(devtest_error_count == 1, "%d errors reported", devtest_error_count);
    CHECKF(strstr(devtest_errors, "bad.comp: compute shader compile failed") != NULL,
           "message lacks file and stage: %s", devtest_errors);
    CHECKF(strstr(devtest_errors, "0:5(") != NULL, "message does not point at line 5: %s",
           devtest_errors);

    /* The same without defines points at the same line. */
    devtest_clear();
    prog = lg_gl_program(node, gl, &bad, 1, NULL);
    CHECKF(prog == 0 && strstr(devtest_errors, "0:5(") != NULL, "without defines: %s",
           devtest_errors);

    /* Defines after a #version that is not on the first line. */
    devtest_clear();
    lg_gl_shader_src late = { GL_COMPUTE_SHADER, "late.comp", bad_late_version_comp };
    prog = lg_gl_program(node, gl, &late, 1, "#define A 1\n");
    CHECKF(prog == 0 && strstr(devtest_errors, "late.comp: compute shader compile failed") &&
               strstr(devtest_errors, "0:7("),
           "late #version: %s", devtest_errors);

    /* Link failure. */
    devtest_clear();
    lg_gl_shader_src nomain = { GL_COMPUTE_SHADER, "nomain.comp", nomain_comp };
    prog = lg_gl_program(node, gl, &nomain, 1, NULL);
    CHECKF(prog == 0, "a program without main linked");
    CHECKF(strstr(devtest_errors, "nomain.comp: link failed") != NULL, "message: %s",
           devtest_errors);

    /* Defines without a #version line to put them after. */
    devtest_clear();
    lg_gl_shader_src noversion = { GL_COMPUTE_SHADER, "noversion.comp", "void main() {}\n" };
    prog = lg_gl_program(node, gl, &noversion, 1, "#define X 1");
    CHECKF(prog == 0 && strstr(devtest_errors, "noversion.comp: no #version line") != NULL,
           "message: %s", devtest_errors);

    /* Bad arguments. */
    devtest_clear();
    lg_gl_shader_src nosrc = { GL_COMPUTE_SHADER, "nosrc.comp", NULL };
    CHECKF(lg_gl_program(node, gl, &nosrc, 1, NULL) == 0 &&
               strstr(devtest_errors, "nosrc.comp: no source") != NULL,
           "message: %s", devtest_errors);
    devtest_clear();
    lg_gl_shader_src badstage = { GL_TEXTURE_2D, "x.glsl", square_comp };
    CHECKF(lg_gl_program(node, gl, &badstage, 1, NULL) == 0 &&
               strstr(devtest_errors, "unknown shader stage") != NULL,
           "message: %s", devtest_errors);
    devtest_clear();
    CHECKF(lg_gl_program(node, NULL, &bad, 1, NULL) == 0 && devtest_error_count == 1,
           "NULL table accepted");
    CHECKF(lg_gl_program(node, gl, NULL, 0, NULL) == 0 && devtest_error_count == 2,
           "no stages accepted");

    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "lg_gl_program left %s", lg_gl_strerror(e));
}

static void test_state(const lg_gl *gl, GLuint prog)
{
    char err[1024];
    GLint v = 0;

    /* test_compute left its program bound: the check names it. */
    gl->GetIntegerv(GL_CURRENT_PROGRAM, &v);
    CHECKF(v == (GLint)prog, "expected program %u bound, got %d", prog, v);
    CHECKF(lg_gl_state_check(gl, err, sizeof err) == -1, "a bound program passed the check");
    CHECKF(strstr(err, "GL_CURRENT_PROGRAM") != NULL, "message: %s", err);

    lg_gl_state_reset(gl);
    CHECKF(lg_gl_state_check(gl, err, sizeof err) == 0, "after reset: %s", err);
    CHECKF(err[0] == '\0', "message after a passing check: %s", err);

    /* Several deviations at once: every one is named. */
    GLuint tex, fbo;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &tex);
    gl->TextureStorage2D(tex, 1, GL_RGBA32F, 4, 4);
    gl->CreateFramebuffers(1, &fbo);
    gl->NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    gl->BindImageTexture(3, tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    gl->ActiveTexture(GL_TEXTURE2);
    gl->UseProgram(prog);
    CHECKF(lg_gl_state_check(gl, err, sizeof err) == -1, "deviations passed");
    static const char *const expected[] = { "GL_CURRENT_PROGRAM", "GL_IMAGE_BINDING_NAME[3]",
                                            "GL_DRAW_FRAMEBUFFER_BINDING", "GL_ACTIVE_TEXTURE" };
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; i++)
        CHECKF(strstr(err, expected[i]) != NULL, "'%s' not named in: %s", expected[i], err);
    CHECKF(strstr(err, "GL_READ_FRAMEBUFFER_BINDING") == NULL, "read framebuffer named: %s", err);
    printf("state check message: %s\n", err);

    /* A short buffer is truncated, not overrun; the verdict is the same. */
    char small[24];
    memset(small, 'x', sizeof small);
    CHECKF(lg_gl_state_check(gl, small, 16) == -1, "short buffer changed the verdict");
    CHECKF(memchr(small, '\0', 16) != NULL && small[16] == 'x', "short buffer overrun");
    CHECKF(lg_gl_state_check(gl, NULL, 0) == -1, "NULL buffer changed the verdict");

    /* Reset covers more than the check: pixel store and capabilities too. */
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl->PixelStorei(GL_PACK_ROW_LENGTH, 17);
    gl->Enable(GL_BLEND);
    gl->Enable(GL_DEPTH_TEST);
    gl->ColorMask(GL_FALSE, GL_TRUE, GL_TRUE, GL_TRUE);
    GLuint pbo;
    gl->CreateBuffers(1, &pbo);
    gl->BindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo);
    CHECKF(lg_gl_state_check(gl, err, sizeof err) == -1 &&
               strstr(err, "GL_PIXEL_UNPACK_BUFFER_BINDING") != NULL,
           "bound PBO not named: %s", err);
    lg_gl_state_reset(gl);
    CHECKF(lg_gl_state_check(gl, err, sizeof err) == 0, "after reset: %s", err);
    gl->GetIntegerv(GL_UNPACK_ALIGNMENT, &v);
    CHECKF(v == 4, "GL_UNPACK_ALIGNMENT = %d after reset", v);
    gl->GetIntegerv(GL_PACK_ROW_LENGTH, &v);
    CHECKF(v == 0, "GL_PACK_ROW_LENGTH = %d after reset", v);
    CHECKF(!gl->IsEnabled(GL_BLEND) && !gl->IsEnabled(GL_DEPTH_TEST), "capabilities kept");
    GLboolean mask[4];
    gl->GetBooleanv(GL_COLOR_WRITEMASK, mask);
    CHECKF(mask[0] && mask[1] && mask[2] && mask[3], "color mask kept");
    gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &v);
    CHECKF(v == 0, "texture unit 0 keeps texture %d", v);

    gl->DeleteBuffers(1, &pbo);
    gl->DeleteFramebuffers(1, &fbo);
    gl->DeleteTextures(1, &tex);
    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "GL error %s", lg_gl_strerror(e));
}

int main(int argc, char **argv)
{
    const char *backend = argc > 1 ? argv[1] : "osmesa";
    const char *label = strcmp(backend, "egl") == 0 ? "EGL " : "OSMesa, ";
    char err[512] = "";
    lg_gl_device *dev = NULL;

    double t0 = devtest_now();
    int rc = lg_gl_device_create(&dev, backend, err, sizeof err);
    double t1 = devtest_now();
    if (rc) {
        printf("SKIP: no GL device '%s': %s\n", backend, err);
        CHECKF(dev == NULL, "failed create left a device");
        CHECKF(rc == LG_ERR_DEVICE, "rc %d", rc);
        CHECKF(err[0] != '\0', "no reason given");
        return check_skip("gl_device");
    }
    printf("%s: %s\n", backend, lg_gl_device_description(dev));
    printf("%s: first context created in %.1f ms\n", backend, (t1 - t0) * 1e3);

    const lg_gl *gl = lg_gl_device_table(dev);
    test_timer_query(dev); /* first: no timer query has run on this context */
    test_version(gl, dev, label);
    GLuint prog = test_compute(gl);
    test_program_errors(gl);
    if (prog) {
        test_state(gl, prog);
        gl->DeleteProgram(prog);
    }
    test_timer(gl);

    lg_gl_device_destroy(&dev);
    CHECKF(dev == NULL, "destroy did not clear the handle");
    lg_gl_device_destroy(&dev); /* NULL handle: no-op */

    /* A second device after the first is gone (the library stays loaded). */
    t0 = devtest_now();
    rc = lg_gl_device_create(&dev, backend, err, sizeof err);
    t1 = devtest_now();
    CHECKF(rc == 0, "second create: %s", err);
    if (rc == 0) {
        printf("%s: second context created in %.1f ms\n", backend, (t1 - t0) * 1e3);
        gl = lg_gl_device_table(dev);
        char serr[512];
        CHECKF(lg_gl_state_check(gl, serr, sizeof serr) == 0, "fresh device: %s", serr);
        GLuint again = test_compute(gl);
        if (again) {
            lg_gl_state_reset(gl);
            gl->DeleteProgram(again);
        }
        lg_gl_device_destroy(&dev);
    }
    return check_report("gl_device");
}
