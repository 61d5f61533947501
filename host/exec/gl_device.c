/* The GL device: backend choice, entry-point loading and checks common to the backends,
 * and the GL state contract (docs/devices.md, "The GL state contract"). */
#include "exec/device.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exec/gl_backend.h"
#include "lightgraph/types.h"

struct lg_gl_device {
    GladGLContext gl;
    lg_gl_backend backend;
    char description[256];
};

/* Image units and texture units the contract covers (GL 4.5 guarantees at least 8). */
enum { STATE_UNITS = 8 };

static const char *gl_string(const GladGLContext *gl, GLenum name)
{
    const GLubyte *s = gl->GetString(name);
    return s ? (const char *)s : "?";
}

static int finish(lg_gl_device **out, lg_gl_device *dev, char *err, size_t errlen);

int lg_gl_device_create(lg_gl_device **out, const char *backend, char *err, size_t errlen)
{
    *out = NULL;
    if (!backend)
        backend = "osmesa";
    int (*open_backend)(lg_gl_backend *, char *, size_t);
    if (strcmp(backend, "osmesa") == 0)
        open_backend = lg_gl_osmesa_open;
    else if (strcmp(backend, "egl") == 0)
        open_backend = lg_gl_egl_open;
    else {
        snprintf(err, errlen, "unknown GL backend '%s' (expected osmesa or egl)", backend);
        return LG_ERR_DEVICE;
    }

    lg_gl_device *dev = calloc(1, sizeof *dev);
    if (!dev) {
        snprintf(err, errlen, "out of memory creating the GL device");
        return LG_ERR_DEVICE;
    }
    int rc = open_backend(&dev->backend, err, errlen);
    if (rc) {
        free(dev);
        return rc;
    }
    return finish(out, dev, err, errlen);
}

int lg_gl_device_wrap(lg_gl_device **out, const lg_gl_backend *backend, char *err, size_t errlen)
{
    *out = NULL;
    lg_gl_device *dev = calloc(1, sizeof *dev);
    if (!dev) {
        snprintf(err, errlen, "out of memory creating the GL device");
        return LG_ERR_DEVICE;
    }
    dev->backend = *backend;
    return finish(out, dev, err, errlen);
}

/* Loads the entry points of dev's backend (its context current) and checks them. */
static int finish(lg_gl_device **out, lg_gl_device *dev, char *err, size_t errlen)
{
    const char *label = dev->backend.label;
    int version = gladLoadGLContextUserPtr(&dev->gl, dev->backend.load, dev->backend.state);
    if (!version) {
        snprintf(err, errlen, "%s: could not load GL entry points (glGetString missing)", label);
        goto fail;
    }
    /* glad loads only the entry points of the versions the context reports, so a 4.5
     * check here is also a check that every function of the table is there. */
    int major = GLAD_VERSION_MAJOR(version), minor = GLAD_VERSION_MINOR(version);
    if (major < 4 || (major == 4 && minor < 5)) {
        snprintf(err, errlen, "%s: context is GL %d.%d (%s, %s), need 4.5", label, major, minor,
                 gl_string(&dev->gl, GL_VERSION), gl_string(&dev->gl, GL_RENDERER));
        goto fail;
    }
    GLint profile = 0;
    dev->gl.GetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    if (!(profile & GL_CONTEXT_CORE_PROFILE_BIT)) {
        snprintf(err, errlen, "%s: context is GL %d.%d but not a core profile (mask 0x%x)", label,
                 major, minor, (unsigned)profile);
        goto fail;
    }
    snprintf(dev->description, sizeof dev->description, "%s, %s, %s", label,
             gl_string(&dev->gl, GL_RENDERER), gl_string(&dev->gl, GL_VERSION));
    /* Drain errors the loader's queries may have raised, and start from the contract's
     * state so the first node sees what every later node sees. */
    while (dev->gl.GetError() != GL_NO_ERROR) {
    }
    lg_gl_state_reset(&dev->gl);
    *out = dev;
    return 0;

fail:
    if (dev->backend.destroy)
        dev->backend.destroy(dev->backend.state);
    free(dev);
    return LG_ERR_DEVICE;
}

const GladGLContext *lg_gl_device_table(const lg_gl_device *dev)
{
    return &dev->gl;
}

const char *lg_gl_device_description(const lg_gl_device *dev)
{
    return dev->description;
}

uint32_t lg_gl_device_timer_query(const lg_gl_device *dev)
{
    const GladGLContext *gl = &dev->gl;
    GLuint query = 0;
    gl->GenQueries(1, &query);
    /* the query runs on nothing: its result is the timestamp, read and dropped here */
    GLuint64 ns = 0;
    gl->BeginQuery(GL_TIME_ELAPSED, query);
    gl->EndQuery(GL_TIME_ELAPSED);
    gl->GetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    return query;
}

void lg_gl_device_destroy(lg_gl_device **pdev)
{
    if (!pdev || !*pdev)
        return;
    lg_gl_device *dev = *pdev;
    /* Objects nodes forgot to delete die with the context; the backend releases the
     * context from this thread before destroying it. */
    if (dev->backend.destroy)
        dev->backend.destroy(dev->backend.state);
    free(dev);
    *pdev = NULL;
}

/* ---- the GL state contract ------------------------------------------------------------------- */

/* Buffer targets whose generic binding reset clears. The first five are also checked. */
static const GLenum reset_buffer_targets[] = {
    GL_SHADER_STORAGE_BUFFER,     GL_UNIFORM_BUFFER,      GL_ARRAY_BUFFER,
    GL_PIXEL_PACK_BUFFER,         GL_PIXEL_UNPACK_BUFFER, GL_ATOMIC_COUNTER_BUFFER,
    GL_COPY_READ_BUFFER,          GL_COPY_WRITE_BUFFER,   GL_DISPATCH_INDIRECT_BUFFER,
    GL_DRAW_INDIRECT_BUFFER,      GL_QUERY_BUFFER,        GL_TEXTURE_BUFFER,
    GL_TRANSFORM_FEEDBACK_BUFFER,
};

/* Capabilities reset to their GL defaults (all off). */
static const GLenum reset_disabled[] = {
    GL_BLEND,
    GL_COLOR_LOGIC_OP,
    GL_CULL_FACE,
    GL_DEPTH_CLAMP,
    GL_DEPTH_TEST,
    GL_FRAMEBUFFER_SRGB,
    GL_POLYGON_OFFSET_FILL,
    GL_POLYGON_OFFSET_LINE,
    GL_POLYGON_OFFSET_POINT,
    GL_PRIMITIVE_RESTART,
    GL_PRIMITIVE_RESTART_FIXED_INDEX,
    GL_PROGRAM_POINT_SIZE,
    GL_RASTERIZER_DISCARD,
    GL_SAMPLE_ALPHA_TO_COVERAGE,
    GL_SAMPLE_ALPHA_TO_ONE,
    GL_SAMPLE_COVERAGE,
    GL_SAMPLE_MASK,
    GL_SAMPLE_SHADING,
    GL_SCISSOR_TEST,
    GL_STENCIL_TEST,
    GL_TEXTURE_CUBE_MAP_SEAMLESS,
};

/* Pixel-store parameters and their defaults; the host's own transfers assume them. */
static const struct {
    GLenum name;
    GLint value;
} reset_pixel_store[] = {
    { GL_PACK_SWAP_BYTES, 0 },   { GL_PACK_LSB_FIRST, 0 },     { GL_PACK_ROW_LENGTH, 0 },
    { GL_PACK_IMAGE_HEIGHT, 0 }, { GL_PACK_SKIP_ROWS, 0 },     { GL_PACK_SKIP_PIXELS, 0 },
    { GL_PACK_SKIP_IMAGES, 0 },  { GL_PACK_ALIGNMENT, 4 },     { GL_UNPACK_SWAP_BYTES, 0 },
    { GL_UNPACK_LSB_FIRST, 0 },  { GL_UNPACK_ROW_LENGTH, 0 },  { GL_UNPACK_IMAGE_HEIGHT, 0 },
    { GL_UNPACK_SKIP_ROWS, 0 },  { GL_UNPACK_SKIP_PIXELS, 0 }, { GL_UNPACK_SKIP_IMAGES, 0 },
    { GL_UNPACK_ALIGNMENT, 4 },
};

void lg_gl_state_reset(const GladGLContext *gl)
{
    /* What lg_gl_state_check verifies. */
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl->UseProgram(0);
    gl->BindProgramPipeline(0);
    gl->BindVertexArray(0);
    for (size_t i = 0; i < sizeof reset_buffer_targets / sizeof reset_buffer_targets[0]; i++)
        gl->BindBuffer(reset_buffer_targets[i], 0);
    gl->BindImageTextures(0, STATE_UNITS, NULL);
    gl->ActiveTexture(GL_TEXTURE0);

    /* Further state a node may change and the next one should not inherit. */
    gl->BindTextures(0, STATE_UNITS, NULL);
    gl->BindSamplers(0, STATE_UNITS, NULL);
    gl->BindRenderbuffer(GL_RENDERBUFFER, 0);
    for (size_t i = 0; i < sizeof reset_disabled / sizeof reset_disabled[0]; i++)
        gl->Disable(reset_disabled[i]);
    gl->Enable(GL_DITHER);
    gl->Enable(GL_MULTISAMPLE);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->DepthMask(GL_TRUE);
    gl->StencilMask(~0u);
    gl->DepthFunc(GL_LESS);
    gl->BlendFunc(GL_ONE, GL_ZERO);
    gl->BlendEquation(GL_FUNC_ADD);
    gl->CullFace(GL_BACK);
    gl->FrontFace(GL_CCW);
    gl->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    gl->ClearColor(0.0f, 0.0f, 0.0f, 0.0f);
    gl->ClearDepth(1.0);
    gl->ClearStencil(0);
    for (size_t i = 0; i < sizeof reset_pixel_store / sizeof reset_pixel_store[0]; i++)
        gl->PixelStorei(reset_pixel_store[i].name, reset_pixel_store[i].value);
}

typedef struct state_report {
    char *buf;
    size_t len, cap;
    int deviations;
} state_report;

static void deviation(state_report *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void deviation(state_report *r, const char *fmt, ...)
{
    r->deviations++;
    if (!r->buf || r->cap == 0 || r->len + 1 >= r->cap)
        return;
    if (r->deviations > 1) {
        int n = snprintf(r->buf + r->len, r->cap - r->len, "; ");
        r->len += n > 0 ? (size_t)n : 0;
        if (r->len >= r->cap) {
            r->len = r->cap - 1;
            return;
        }
    }
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(r->buf + r->len, r->cap - r->len, fmt, ap);
    va_end(ap);
    r->len += n > 0 ? (size_t)n : 0;
    if (r->len >= r->cap)
        r->len = r->cap - 1;
}

static void expect_zero(const GladGLContext *gl, state_report *r, GLenum pname, const char *name)
{
    GLint v = 0;
    gl->GetIntegerv(pname, &v);
    if (v != 0)
        deviation(r, "%s = %d (expected 0)", name, v);
}

int lg_gl_state_check(const GladGLContext *gl, char *err, size_t errlen)
{
    static const char prefix[] = "GL state not restored: ";
    state_report r = { err, 0, errlen, 0 };
    if (err && errlen > 0) {
        snprintf(err, errlen, "%s", prefix);
        r.len = strlen(err);
    }
#define EXPECT_ZERO(pname) expect_zero(gl, &r, pname, #pname)
    EXPECT_ZERO(GL_DRAW_FRAMEBUFFER_BINDING);
    EXPECT_ZERO(GL_READ_FRAMEBUFFER_BINDING);
    EXPECT_ZERO(GL_CURRENT_PROGRAM);
    EXPECT_ZERO(GL_VERTEX_ARRAY_BINDING);
    EXPECT_ZERO(GL_SHADER_STORAGE_BUFFER_BINDING);
    EXPECT_ZERO(GL_UNIFORM_BUFFER_BINDING);
    EXPECT_ZERO(GL_ARRAY_BUFFER_BINDING);
    /* A pixel buffer left bound turns the next client-memory transfer's pointer into an
     * offset into that buffer: silent garbage, so it is part of the check. */
    EXPECT_ZERO(GL_PIXEL_PACK_BUFFER_BINDING);
    EXPECT_ZERO(GL_PIXEL_UNPACK_BUFFER_BINDING);
#undef EXPECT_ZERO
    for (GLuint i = 0; i < STATE_UNITS; i++) {
        GLint tex = 0;
        gl->GetIntegeri_v(GL_IMAGE_BINDING_NAME, i, &tex);
        if (tex != 0)
            deviation(&r, "GL_IMAGE_BINDING_NAME[%u] = %d (expected 0)", i, tex);
    }
    GLint active = 0;
    gl->GetIntegerv(GL_ACTIVE_TEXTURE, &active);
    if (active != GL_TEXTURE0)
        deviation(&r, "GL_ACTIVE_TEXTURE = GL_TEXTURE%d (expected GL_TEXTURE0)",
                  active - GL_TEXTURE0);
    if (r.deviations == 0) {
        if (err && errlen > 0)
            err[0] = '\0';
        return 0;
    }
    return -1;
}

const char *lg_gl_strerror(GLenum e)
{
    switch (e) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
    default: return "unknown GL error";
    }
}
