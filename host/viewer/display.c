/* The viewer's display pass and text overlay (host/viewer/display.h). */
#include "viewer/display.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exec/device.h"
#include "lightgraph/gl.h"

#include "display.vert.h"
#include "display_image.frag.h"
#include "display_text.frag.h"
#include "unifont-ascii.hex.h"

/* Uniform locations (the layout(location) of shaders/viewer/). */
enum {
    U_RECT = 0,
    U_FB_SIZE = 1,
    U_EXPOSURE = 2, /* display_image.frag */
    U_TAPS = 3,
    U_ORIGIN = 2, /* display_text.frag from here on */
    U_SCALE = 3,
    U_CELL = 4,
    U_COLOR = 5,
    U_BOX_ALPHA = 6,
    U_FIRST = 7,
    U_COUNT = 8,
    U_GRID = 9,
};

struct lg_vdisplay {
    const GladGLContext *gl;
    GLuint image_prog, text_prog;
    GLuint vao;             /* empty: the quad comes from gl_VertexID */
    GLuint nearest, linear; /* samplers, clamped to the edge */
    GLuint font;            /* R8 atlas, LG_FONT_COUNT glyphs side by side */
    GLuint text;            /* R8UI grid of characters, grown on demand */
    int text_w, text_h;     /* its allocated size */
    GLint max_texture;      /* GL_MAX_TEXTURE_SIZE */
    GLint max_viewport[2];  /* GL_MAX_VIEWPORT_DIMS */
    lg_node node;           /* for lg_gl_program's messages (see compile_error) */
    char err[1024];
};

static void set_error(lg_vdisplay *d, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void set_error(lg_vdisplay *d, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->err, sizeof d->err, fmt, ap);
    va_end(ap);
}

/* lg_gl_program (the SDK's compiler, which names the file in its messages) reports through
 * a node's host API. The display is not a node: a host API with only the two message
 * functions takes the error into the display's buffer; warnings (a driver's remarks on
 * a program that compiled) are not errors and go nowhere, as library code never prints. */
static void compile_error(lg_node *n, const char *fmt, va_list ap)
{
    lg_vdisplay *d = n->user;
    vsnprintf(d->err, sizeof d->err, fmt, ap);
}

static void compile_log(lg_node *n, lg_log_level level, const char *fmt, va_list ap)
{
    (void)n, (void)level, (void)fmt, (void)ap;
}

static const lg_host_api compile_host = {
    .struct_size = sizeof(lg_host_api),
    .abi_major = LG_ABI_MAJOR,
    .abi_minor = LG_ABI_MINOR,
    .log = compile_log,
    .error = compile_error,
};

/* The state both passes set before drawing. */
static void begin_pass(const GladGLContext *gl, GLuint fbo, int fb_w, int fb_h)
{
    gl->BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl->Viewport(0, 0, fb_w, fb_h);
    gl->Disable(GL_SCISSOR_TEST);
    gl->Disable(GL_DEPTH_TEST);
    gl->Disable(GL_STENCIL_TEST);
    gl->Disable(GL_CULL_FACE);
    gl->Disable(GL_RASTERIZER_DISCARD);
    /* the shader encodes; GL must neither encode again nor dither the 8-bit result */
    gl->Disable(GL_FRAMEBUFFER_SRGB);
    gl->Disable(GL_DITHER);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    gl->BindVertexArray(0);
}

/* What the host's contract wants after a node, plus the reset values of what the passes
 * changed beyond it; run after every draw, failed or not. */
static void end_pass(const GladGLContext *gl)
{
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl->UseProgram(0);
    gl->BindVertexArray(0);
    gl->BindTextureUnit(0, 0);
    gl->BindTextureUnit(1, 0);
    gl->BindSampler(0, 0);
    gl->BindSampler(1, 0);
    gl->Disable(GL_BLEND);
    gl->BlendFunc(GL_ONE, GL_ZERO);
    gl->Enable(GL_DITHER);
}

/* Refuses to start over an error raised before: it is not the display's, and would be
 * taken for one at the end of the draw. */
static int pending_error(lg_vdisplay *d, const char *what)
{
    GLenum e = d->gl->GetError();
    if (e == GL_NO_ERROR)
        return 0;
    while (d->gl->GetError() != GL_NO_ERROR) {
    }
    set_error(d,
              "%s: a GL error was pending before the call (%s, raised by an earlier GL call; "
              "cleared)",
              what, lg_gl_strerror(e));
    return -1;
}

static int check_error(lg_vdisplay *d, const char *what)
{
    GLenum e = d->gl->GetError();
    if (e == GL_NO_ERROR)
        return 0;
    while (d->gl->GetError() != GL_NO_ERROR) {
    }
    set_error(d, "%s: %s", what, lg_gl_strerror(e));
    return -1;
}

/* The framebuffer and its size, common to both draws. */
static int check_target(lg_vdisplay *d, const char *what, uint32_t fbo, int fb_w, int fb_h)
{
    const GladGLContext *gl = d->gl;
    if (fb_w <= 0 || fb_h <= 0 || fb_w > d->max_viewport[0] || fb_h > d->max_viewport[1]) {
        set_error(d, "%s: framebuffer size %dx%d outside 1x1..%dx%d (GL_MAX_VIEWPORT_DIMS)", what,
                  fb_w, fb_h, d->max_viewport[0], d->max_viewport[1]);
        return -1;
    }
    if (fbo != 0 && !gl->IsFramebuffer(fbo)) {
        set_error(d, "%s: %u is not a framebuffer object", what, fbo);
        return -1;
    }
    GLenum status = gl->CheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        set_error(d, "%s: framebuffer %u is not complete (status 0x%04x%s)", what, fbo,
                  (unsigned)status,
                  status == GL_FRAMEBUFFER_UNDEFINED ? ": the context has no default framebuffer"
                                                     : "");
        return -1;
    }
    return 0;
}

/* ---- create / destroy ------------------------------------------------------------------------ */

int lg_vdisplay_create(const GladGLContext *gl, lg_vdisplay **out, char *err, size_t errlen)
{
    if (!out) {
        snprintf(err, errlen, "lg_vdisplay_create: out is NULL");
        return -1;
    }
    *out = NULL;
    if (!gl) {
        snprintf(err, errlen, "lg_vdisplay_create: no GL context");
        return -1;
    }
    lg_vdisplay *d = calloc(1, sizeof *d);
    if (!d) {
        snprintf(err, errlen, "lg_vdisplay_create: out of memory");
        return -1;
    }
    d->gl = gl;
    d->node = (lg_node){ .host = &compile_host, .name = "viewer display", .user = d };
    if (pending_error(d, "lg_vdisplay_create"))
        goto fail;
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &d->max_texture);
    gl->GetIntegerv(GL_MAX_VIEWPORT_DIMS, d->max_viewport);

    const lg_gl_shader_src image_src[] = {
        { GL_VERTEX_SHADER, lg_src_display_vert_file, lg_src_display_vert },
        { GL_FRAGMENT_SHADER, lg_src_display_image_frag_file, lg_src_display_image_frag },
    };
    const lg_gl_shader_src text_src[] = {
        { GL_VERTEX_SHADER, lg_src_display_vert_file, lg_src_display_vert },
        { GL_FRAGMENT_SHADER, lg_src_display_text_frag_file, lg_src_display_text_frag },
    };
    d->image_prog = lg_gl_program(&d->node, gl, image_src, 2, NULL);
    if (!d->image_prog)
        goto fail;
    d->text_prog = lg_gl_program(&d->node, gl, text_src, 2, NULL);
    if (!d->text_prog)
        goto fail;

    gl->CreateVertexArrays(1, &d->vao);
    gl->CreateSamplers(1, &d->nearest);
    gl->CreateSamplers(1, &d->linear);
    const GLuint samplers[2] = { d->nearest, d->linear };
    for (int i = 0; i < 2; i++) {
        GLint filter = i == 0 ? GL_NEAREST : GL_LINEAR;
        gl->SamplerParameteri(samplers[i], GL_TEXTURE_MIN_FILTER, filter);
        gl->SamplerParameteri(samplers[i], GL_TEXTURE_MAG_FILTER, filter);
        gl->SamplerParameteri(samplers[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        gl->SamplerParameteri(samplers[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }

    /* The font atlas: glyph i in columns [i * W, (i + 1) * W), its top row in row 0. */
    enum { AW = LG_FONT_COUNT * LG_FONT_CELL_W, AH = LG_FONT_CELL_H };
    unsigned char *atlas = malloc((size_t)AW * AH);
    if (!atlas) {
        set_error(d, "lg_vdisplay_create: out of memory for the font atlas");
        goto fail;
    }
    for (int g = 0; g < LG_FONT_COUNT; g++)
        for (int y = 0; y < AH; y++)
            for (int x = 0; x < LG_FONT_CELL_W; x++)
                atlas[(size_t)y * AW + (size_t)g * LG_FONT_CELL_W + (size_t)x] =
                    (lg_font_glyphs[g][y] >> (7 - x)) & 1 ? 255 : 0;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &d->font);
    gl->TextureStorage2D(d->font, 1, GL_R8, AW, AH);
    /* texelFetch needs a complete texture, and one level is complete only with a
     * non-mipmap minification filter */
    gl->TextureParameteri(d->font, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl->TextureParameteri(d->font, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl->BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl->TextureSubImage2D(d->font, 0, 0, 0, AW, AH, GL_RED, GL_UNSIGNED_BYTE, atlas);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    free(atlas);
    if (check_error(d, "lg_vdisplay_create: font texture and samplers"))
        goto fail;
    *out = d;
    return 0;

fail:
    snprintf(err, errlen, "%s", d->err);
    lg_vdisplay_destroy(&d);
    return -1;
}

void lg_vdisplay_destroy(lg_vdisplay **pd)
{
    if (!pd || !*pd)
        return;
    lg_vdisplay *d = *pd;
    const GladGLContext *gl = d->gl;
    /* Deleting name 0 is ignored by GL, so a half-made display is destroyed the same way. */
    gl->DeleteProgram(d->image_prog);
    gl->DeleteProgram(d->text_prog);
    gl->DeleteVertexArrays(1, &d->vao);
    gl->DeleteSamplers(1, &d->nearest);
    gl->DeleteSamplers(1, &d->linear);
    gl->DeleteTextures(1, &d->font);
    gl->DeleteTextures(1, &d->text);
    free(d);
    *pd = NULL;
}

const char *lg_vdisplay_error(const lg_vdisplay *d)
{
    return d ? d->err : "no display";
}

void lg_vdisplay_cell(const lg_vdisplay *d, int *cw, int *ch)
{
    (void)d;
    if (cw)
        *cw = LG_FONT_CELL_W;
    if (ch)
        *ch = LG_FONT_CELL_H;
}

/* ---- the image ------------------------------------------------------------------------------- */

lg_vdisplay_rect lg_vdisplay_fit(int fb_w, int fb_h, uint32_t w, uint32_t h)
{
    lg_vdisplay_rect r = { 0, 0, 0, 0, 0.0 };
    if (fb_w <= 0 || fb_h <= 0 || w == 0 || h == 0)
        return r;
    r.scale = fmin((double)fb_w / w, (double)fb_h / h);
    r.w = (int)lround(w * r.scale);
    r.h = (int)lround(h * r.scale);
    r.w = r.w < 1 ? 1 : r.w > fb_w ? fb_w : r.w;
    r.h = r.h < 1 ? 1 : r.h > fb_h ? fb_h : r.h;
    r.x = (fb_w - r.w) / 2;
    r.y = (fb_h - r.h) / 2;
    return r;
}

static const char *format_name(GLint f)
{
    switch (f) {
    case GL_RGBA32F: return "GL_RGBA32F";
    case GL_RGBA16F: return "GL_RGBA16F";
    case GL_RGBA8: return "GL_RGBA8";
    default: return NULL;
    }
}

/* The texture is what the caller says it is. */
static int check_texture(lg_vdisplay *d, uint32_t tex, uint32_t w, uint32_t h)
{
    const GladGLContext *gl = d->gl;
    static const char what[] = "lg_vdisplay_draw_image";
    if (w == 0 || h == 0 || w > (uint32_t)d->max_texture || h > (uint32_t)d->max_texture) {
        set_error(d, "%s: image size %ux%u outside 1x1..%dx%d (GL_MAX_TEXTURE_SIZE)", what, w, h,
                  d->max_texture, d->max_texture);
        return -1;
    }
    if (tex == 0 || !gl->IsTexture(tex)) {
        set_error(d, "%s: %u is not a texture name", what, tex);
        return -1;
    }
    GLint target = 0, tw = 0, th = 0, fmt = 0;
    gl->GetTextureParameteriv(tex, GL_TEXTURE_TARGET, &target);
    if (target != GL_TEXTURE_2D) {
        set_error(d, "%s: texture %u is not a GL_TEXTURE_2D (target 0x%04x)", what, tex,
                  (unsigned)target);
        return -1;
    }
    gl->GetTextureLevelParameteriv(tex, 0, GL_TEXTURE_WIDTH, &tw);
    gl->GetTextureLevelParameteriv(tex, 0, GL_TEXTURE_HEIGHT, &th);
    gl->GetTextureLevelParameteriv(tex, 0, GL_TEXTURE_INTERNAL_FORMAT, &fmt);
    if ((uint32_t)tw != w || (uint32_t)th != h) {
        set_error(d, "%s: texture %u is %dx%d, not the %ux%u stated", what, tex, tw, th, w, h);
        return -1;
    }
    if (!format_name(fmt)) {
        set_error(d,
                  "%s: texture %u has internal format 0x%04x; the display takes GL_RGBA32F, "
                  "GL_RGBA16F or GL_RGBA8",
                  what, tex, (unsigned)fmt);
        return -1;
    }
    return 0;
}

int lg_vdisplay_draw_image(lg_vdisplay *d, uint32_t fbo, int fb_w, int fb_h, uint32_t tex,
                           uint32_t w, uint32_t h, float exposure)
{
    static const char what[] = "lg_vdisplay_draw_image";
    if (!d)
        return -1;
    d->err[0] = '\0';
    const GladGLContext *gl = d->gl;
    if (pending_error(d, what))
        return -1;
    if (!isfinite(exposure) || exposure < 0.0f) {
        set_error(d, "%s: exposure %g is not a finite value >= 0", what, (double)exposure);
        return -1;
    }
    if (check_target(d, what, fbo, fb_w, fb_h) || check_texture(d, tex, w, h))
        return -1;

    lg_vdisplay_rect r = lg_vdisplay_fit(fb_w, fb_h, w, h);
    int ox = r.x, oy = fb_h - r.y - r.h, dw = r.w, dh = r.h; /* GL's y grows upwards */
    /* A whole-number scale samples nearest, texel for pixel block; a shrunk image is
     * box-filtered with taps bilinear taps per axis. */
    bool whole = r.scale >= 1.0 && r.scale == floor(r.scale) &&
                 (uint32_t)dw == w * (uint32_t)r.scale && (uint32_t)dh == h * (uint32_t)r.scale;
    int taps = r.scale >= 1.0 ? 1 : (int)ceil(1.0 / r.scale - 1e-9);
    taps = taps > LG_VDISPLAY_MAX_TAPS ? LG_VDISPLAY_MAX_TAPS : taps;

    begin_pass(gl, fbo, fb_w, fb_h);
    const GLfloat clear[4] = { LG_VDISPLAY_CLEAR, LG_VDISPLAY_CLEAR, LG_VDISPLAY_CLEAR, 1.0f };
    gl->ClearNamedFramebufferfv(fbo, GL_COLOR, 0, clear);
    gl->Disable(GL_BLEND);
    gl->UseProgram(d->image_prog);
    gl->BindVertexArray(d->vao);
    gl->BindTextureUnit(0, tex);
    gl->BindSampler(0, whole ? d->nearest : d->linear);
    gl->Uniform4f(U_RECT, (float)ox, (float)oy, (float)(ox + dw), (float)(oy + dh));
    gl->Uniform2f(U_FB_SIZE, (float)fb_w, (float)fb_h);
    gl->Uniform1f(U_EXPOSURE, exposure);
    gl->Uniform1i(U_TAPS, taps);
    gl->DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    end_pass(gl);
    return check_error(d, what);
}

/* ---- text ------------------------------------------------------------------------------------ */

/* Makes the grid texture at least cols x rows. */
static int text_grid(lg_vdisplay *d, int cols, int rows)
{
    if (d->text && cols <= d->text_w && rows <= d->text_h)
        return 0;
    const GladGLContext *gl = d->gl;
    int nw = d->text_w > cols ? d->text_w : cols, nh = d->text_h > rows ? d->text_h : rows;
    /* some slack, so that a line growing by a character does not remake the texture */
    nw = nw < 64 ? 64 : nw + nw / 2;
    nh = nh < 8 ? 8 : nh + nh / 2;
    nw = nw > d->max_texture ? d->max_texture : nw;
    nh = nh > d->max_texture ? d->max_texture : nh;
    gl->DeleteTextures(1, &d->text);
    d->text = 0;
    d->text_w = d->text_h = 0;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &d->text);
    gl->TextureStorage2D(d->text, 1, GL_R8UI, nw, nh);
    gl->TextureParameteri(d->text, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl->TextureParameteri(d->text, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    if (check_error(d, "lg_vdisplay_draw_text: text grid texture"))
        return -1;
    d->text_w = nw;
    d->text_h = nh;
    return 0;
}

int lg_vdisplay_draw_text(lg_vdisplay *d, uint32_t fbo, int fb_w, int fb_h, int x, int y,
                          const char *text, const float rgb[3], int scale)
{
    static const char what[] = "lg_vdisplay_draw_text";
    if (!d)
        return -1;
    d->err[0] = '\0';
    const GladGLContext *gl = d->gl;
    if (pending_error(d, what))
        return -1;
    if (!text || !rgb) {
        set_error(d, "%s: %s is NULL", what, !text ? "text" : "rgb");
        return -1;
    }
    if (scale < 1 || scale > LG_VDISPLAY_MAX_SCALE) {
        set_error(d, "%s: scale %d outside 1..%d", what, scale, LG_VDISPLAY_MAX_SCALE);
        return -1;
    }
    for (int c = 0; c < 3; c++)
        if (!(rgb[c] >= 0.0f && rgb[c] <= 1.0f)) {
            set_error(d, "%s: colour component %d is %g, not in [0, 1]", what, c, (double)rgb[c]);
            return -1;
        }
    if (check_target(d, what, fbo, fb_w, fb_h))
        return -1;

    /* The block: lines, and the longest line's length (a final '\n' ends the last line). */
    int64_t lines = 0, longest = 0, len = 0;
    for (const char *p = text; *p; p++) {
        if (*p == '\n') {
            lines++;
            longest = len > longest ? len : longest;
            len = 0;
        } else {
            len++;
        }
    }
    if (len > 0) {
        lines++;
        longest = len > longest ? len : longest;
    }
    if (lines == 0)
        return 0;

    /* Only the cells that can show: those left of or above the framebuffer are skipped
     * (the origin moves to the first visible one), those beyond it cut, so that the grid
     * stays within a texture whatever the text and the position. 64-bit: x may be INT_MIN. */
    const int64_t cw = (int64_t)LG_FONT_CELL_W * scale, ch = (int64_t)LG_FONT_CELL_H * scale;
    int64_t col0 = x < 0 ? -(int64_t)x / cw : 0, row0 = y < 0 ? -(int64_t)y / ch : 0;
    int64_t ox = x + col0 * cw, oy = y + row0 * ch;
    if (ox >= fb_w || oy >= fb_h || col0 >= longest || row0 >= lines)
        return 0;
    int64_t cols = (fb_w - ox + cw - 1) / cw, rows = (fb_h - oy + ch - 1) / ch;
    cols = cols < longest - col0 ? cols : longest - col0;
    rows = rows < lines - row0 ? rows : lines - row0;

    unsigned char *grid = calloc((size_t)(cols * rows), 1);
    if (!grid) {
        set_error(d, "%s: out of memory for a %lldx%lld text grid", what, (long long)cols,
                  (long long)rows);
        return -1;
    }
    int64_t line = 0, col = 0;
    for (const unsigned char *p = (const unsigned char *)text; *p && line < row0 + rows; p++) {
        if (*p == '\n') {
            line++;
            col = 0;
            continue;
        }
        if (line >= row0 && col >= col0 && col < col0 + cols) {
            unsigned char c = *p >= LG_FONT_FIRST && *p < LG_FONT_FIRST + LG_FONT_COUNT ? *p : '?';
            grid[(line - row0) * cols + (col - col0)] = c;
        }
        col++;
    }
    if (text_grid(d, (int)cols, (int)rows)) {
        free(grid);
        return -1;
    }
    gl->BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl->TextureSubImage2D(d->text, 0, 0, 0, (GLsizei)cols, (GLsizei)rows, GL_RED_INTEGER,
                          GL_UNSIGNED_BYTE, grid);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    free(grid);

    /* The block's rectangle in GL pixels (origin bottom-left). */
    float x0 = (float)ox, x1 = (float)(ox + cols * cw);
    float y1 = (float)(fb_h - oy), y0 = (float)(fb_h - oy - rows * ch);
    begin_pass(gl, fbo, fb_w, fb_h);
    gl->Enable(GL_BLEND);
    gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    gl->BlendEquation(GL_FUNC_ADD);
    gl->UseProgram(d->text_prog);
    gl->BindVertexArray(d->vao);
    gl->BindTextureUnit(0, d->text);
    gl->BindTextureUnit(1, d->font);
    gl->Uniform4f(U_RECT, x0, y0, x1, y1);
    gl->Uniform2f(U_FB_SIZE, (float)fb_w, (float)fb_h);
    gl->Uniform2i(U_ORIGIN, (GLint)ox, (GLint)oy);
    gl->Uniform1i(U_SCALE, scale);
    gl->Uniform2i(U_CELL, LG_FONT_CELL_W, LG_FONT_CELL_H);
    gl->Uniform3f(U_COLOR, rgb[0], rgb[1], rgb[2]);
    gl->Uniform1f(U_BOX_ALPHA, LG_VDISPLAY_BOX_ALPHA);
    gl->Uniform1i(U_FIRST, LG_FONT_FIRST);
    gl->Uniform1i(U_COUNT, LG_FONT_COUNT);
    gl->Uniform2i(U_GRID, (GLint)cols, (GLint)rows);
    gl->DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    end_pass(gl);
    return check_error(d, what);
}
