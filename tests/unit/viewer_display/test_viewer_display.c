/* The viewer's display (host/viewer/display.c) on an OSMesa context, drawing into an RGBA8
 * framebuffer object read back with glReadPixels. argv[1] is the case:
 *   image      float textures (below 0, in (0,1), above 1, NaN, +-Inf) at 1:1 size for two
 *              exposures, and an RGBA8 one: each pixel is png.c's encoding of
 *              value * exposure (+-1 code value), texel row 0 at the top of the picture
 *   letterbox  a 4x2 image in an 8x8 framebuffer: clear rows above and below the band,
 *              2x2 blocks of the texels inside; images shrunk into it by 2 and 4 (each
 *              pixel the mean of the texels it covers); lg_vdisplay_fit's rectangles
 *   text       "A|" at a known spot: the lit pixels are the font file's glyph bits, the
 *              box behind darker than the clear colour; scale 2, '?' for other bytes,
 *              cutting at the framebuffer's edges
 *   errors     bad arguments and a pending GL error: refused with the value named,
 *              nothing drawn
 * After every call the GL state passes lg_gl_state_check. Exits 77 if no context can be
 * made (CI fails an unlisted skip: tests/expected-skips.txt). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "exec/device.h"
#include "lightgraph/image.h"
#include "viewer/display.h"

#include "unifont-ascii.hex.h"

static const GladGLContext *gl;
static lg_vdisplay *disp;

static void check_state(const char *after)
{
    char err[1024];
    int rc = lg_gl_state_check(gl, err, sizeof err);
    CHECKF(rc == 0, "after %s: %s", after, err);
    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "after %s: %s pending", after, lg_gl_strerror(e));
}

/* ---- an RGBA8 target and what it holds ------------------------------------------------------- */

typedef struct target {
    GLuint fbo, tex;
    int w, h;
    unsigned char *px; /* read back: row 0 the TOP row of the picture */
} target;

static target make_target(int w, int h)
{
    target t = { .w = w, .h = h };
    gl->CreateTextures(GL_TEXTURE_2D, 1, &t.tex);
    gl->TextureStorage2D(t.tex, 1, GL_RGBA8, w, h);
    gl->CreateFramebuffers(1, &t.fbo);
    gl->NamedFramebufferTexture(t.fbo, GL_COLOR_ATTACHMENT0, t.tex, 0);
    CHECK(gl->CheckNamedFramebufferStatus(t.fbo, GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE);
    t.px = malloc((size_t)w * h * 4);
    return t;
}

static void free_target(target *t)
{
    gl->DeleteFramebuffers(1, &t->fbo);
    gl->DeleteTextures(1, &t->tex);
    free(t->px);
}

/* glReadPixels gives GL's bottom row first; the picture's top row is its last. */
static void read_target(target *t)
{
    unsigned char *raw = malloc((size_t)t->w * t->h * 4);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, t->fbo);
    gl->ReadPixels(0, 0, t->w, t->h, GL_RGBA, GL_UNSIGNED_BYTE, raw);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    for (int y = 0; y < t->h; y++)
        memcpy(t->px + (size_t)y * t->w * 4, raw + (size_t)(t->h - 1 - y) * t->w * 4,
               (size_t)t->w * 4);
    free(raw);
}

static const unsigned char *at(const target *t, int x, int ytop)
{
    return t->px + ((size_t)ytop * t->w + x) * 4;
}

static void fill_target(target *t, float v)
{
    const GLfloat c[4] = { v, v, v, 1.0f };
    gl->ClearNamedFramebufferfv(t->fbo, GL_COLOR, 0, c);
}

/* png.c's encoding of a linear value (png_unorm8(lg_srgb_encode(v))). */
static int png_code(float v)
{
    float e = lg_srgb_encode(v);
    if (!(e > 0.0f))
        return 0;
    if (e >= 1.0f)
        return 255;
    return (int)lrintf(e * 255.0f);
}

/* What GL writes for a display value (the clear colour, the box). */
static int unorm8(float v)
{
    return (int)lrintf(v * 255.0f);
}

static GLuint make_texture(GLenum fmt, int w, int h, const float *rgba)
{
    GLuint tex;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &tex);
    gl->TextureStorage2D(tex, 1, fmt, w, h);
    /* texel row 0 = the first row of the array = the picture's top row (docs/sdk.md) */
    gl->TextureSubImage2D(tex, 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, rgba);
    return tex;
}

#define CLOSE(got, want) (abs((int)(got) - (int)(want)) <= 1)

/* ---- image ----------------------------------------------------------------------------------- */

static void test_image(void)
{
    enum { W = 8, H = 4 };
    const float values[] = { -1.0f,    0.0f,      0.001f, 0.0031308f, 0.02f,  0.18f, 0.5f,
                             0.73f,    0.999f,    1.0f,   1.7f,       40.0f,  1e30f, NAN,
                             INFINITY, -INFINITY, 0.3f,   0.06f,      2.5e-4f };
    const int nv = (int)(sizeof values / sizeof values[0]);
    float *img = malloc(sizeof(float) * W * H * 4);
    /* each row and channel a different mix: a flipped or mirrored picture cannot pass */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 4; c++)
                img[((size_t)y * W + x) * 4 + c] = values[(y * W + x + c * 7 + y * 3) % nv];
    GLuint tex = make_texture(GL_RGBA32F, W, H, img);
    target t = make_target(W, H);
    const float exposures[] = { 1.0f, 0.37f };
    for (int e = 0; e < 2; e++) {
        int rc = lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, W, H, exposures[e]);
        CHECKF(rc == 0, "%s", lg_vdisplay_error(disp));
        check_state("draw_image");
        read_target(&t);
        int bad = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                for (int c = 0; c < 3; c++) {
                    float v = img[((size_t)y * W + x) * 4 + c] * exposures[e];
                    int want = png_code(v), got = at(&t, x, y)[c];
                    if (!CLOSE(got, want) && bad++ < 8)
                        CHECKF(0, "exposure %g: pixel (%d, %d) channel %d: value %g -> %d, want %d",
                               (double)exposures[e], x, y, c, (double)v, got, want);
                }
        CHECKF(bad == 0, "exposure %g: %d channel values off", (double)exposures[e], bad);
        for (int x = 0; x < W; x++)
            CHECK(at(&t, x, 0)[3] == 255);
    }
    gl->DeleteTextures(1, &tex);

    /* RGBA8 holds values k / 255, linear: encoded as any other */
    for (int i = 0; i < W * H * 4; i++)
        img[i] = (float)((i * 37) % 256) / 255.0f;
    tex = make_texture(GL_RGBA8, W, H, img);
    CHECKF(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, W, H, 1.0f) == 0, "%s",
           lg_vdisplay_error(disp));
    check_state("draw_image rgba8");
    read_target(&t);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                int want = png_code(img[((size_t)y * W + x) * 4 + c]), got = at(&t, x, y)[c];
                CHECKF(CLOSE(got, want), "rgba8 pixel (%d, %d) channel %d: %d, want %d", x, y, c,
                       got, want);
            }
    gl->DeleteTextures(1, &tex);
    free_target(&t);
    free(img);
}

/* ---- letterbox ------------------------------------------------------------------------------- */

static void test_letterbox(void)
{
    enum { W = 4, H = 2, F = 8 };
    float img[W * H * 4];
    for (int i = 0; i < W * H; i++)
        for (int c = 0; c < 4; c++)
            img[i * 4 + c] = c == 3 ? 1.0f : (float)(i + 1) / (W * H) * (c == 1 ? 0.5f : 1.0f);
    GLuint tex = make_texture(GL_RGBA32F, W, H, img);
    target t = make_target(F, F);
    fill_target(&t, 1.0f); /* the display must clear: no white may survive */
    CHECKF(lg_vdisplay_draw_image(disp, t.fbo, F, F, tex, W, H, 1.0f) == 0, "%s",
           lg_vdisplay_error(disp));
    check_state("draw_image letterbox");
    read_target(&t);
    const int grey = unorm8(LG_VDISPLAY_CLEAR);
    /* scale min(8/4, 8/2) = 2: an 8x4 band in rows 2..5 */
    for (int y = 0; y < F; y++)
        for (int x = 0; x < F; x++)
            for (int c = 0; c < 3; c++) {
                int got = at(&t, x, y)[c];
                if (y < 2 || y >= 6) {
                    CHECKF(CLOSE(got, grey), "(%d, %d) channel %d outside the band: %d, want %d", x,
                           y, c, got, grey);
                } else {
                    int want = png_code(img[((y - 2) / 2 * W + x / 2) * 4 + c]);
                    CHECKF(CLOSE(got, want),
                           "(%d, %d) channel %d in the band: %d, want texel "
                           "(%d, %d) = %d",
                           x, y, c, got, x / 2, (y - 2) / 2, want);
                }
            }
    gl->DeleteTextures(1, &tex);

    /* shrunk (scale 0.5, bilinear): a constant image stays that constant, in the band */
    float big[16 * 8 * 4];
    for (int i = 0; i < 16 * 8 * 4; i++)
        big[i] = 0.2f;
    tex = make_texture(GL_RGBA32F, 16, 8, big);
    CHECKF(lg_vdisplay_draw_image(disp, t.fbo, F, F, tex, 16, 8, 2.0f) == 0, "%s",
           lg_vdisplay_error(disp));
    check_state("draw_image shrunk");
    read_target(&t);
    for (int y = 0; y < F; y++) {
        int want = y < 2 || y >= 6 ? grey : png_code(0.4f);
        for (int x = 0; x < F; x++)
            CHECKF(CLOSE(at(&t, x, y)[0], want), "shrunk (%d, %d): %d, want %d", x, y,
                   at(&t, x, y)[0], want);
    }
    gl->DeleteTextures(1, &tex);

    /* shrunk by 4: each pixel the mean of the 4x4 texels it covers (the box filter); the
     * texels are 1 in every fourth column plus 2 in every fourth row, so the mean is
     * 0.25 + 0.5, where one bilinear tap at the pixel's centre would give 0 + 1 */
    enum { BW = 32, BH = 16 };
    float *stripes = malloc(sizeof(float) * BW * BH * 4);
    for (int y = 0; y < BH; y++)
        for (int x = 0; x < BW; x++)
            for (int c = 0; c < 4; c++)
                stripes[(y * BW + x) * 4 + c] = (x % 4 == 0 ? 1.0f : 0.0f) +
                                                (y % 4 == 1 ? 2.0f : 0.0f);
    tex = make_texture(GL_RGBA32F, BW, BH, stripes);
    free(stripes);
    lg_vdisplay_rect r = lg_vdisplay_fit(F, F, BW, BH);
    CHECKF(r.x == 0 && r.y == 2 && r.w == 8 && r.h == 4 && r.scale == 0.25, "fit %d %d %d %d %g",
           r.x, r.y, r.w, r.h, r.scale);
    CHECKF(lg_vdisplay_draw_image(disp, t.fbo, F, F, tex, BW, BH, 1.0f) == 0, "%s",
           lg_vdisplay_error(disp));
    check_state("draw_image shrunk by 4");
    read_target(&t);
    for (int y = 2; y < 6; y++)
        for (int x = 0; x < F; x++)
            CHECKF(CLOSE(at(&t, x, y)[0], png_code(0.75f)), "shrunk by 4 (%d, %d): %d, want %d", x,
                   y, at(&t, x, y)[0], png_code(0.75f));
    gl->DeleteTextures(1, &tex);

    /* the fitted rectangle: centred, rounded; nothing for an empty size */
    r = lg_vdisplay_fit(F, F, W, H);
    CHECK(r.x == 0 && r.y == 2 && r.w == 8 && r.h == 4 && r.scale == 2.0);
    r = lg_vdisplay_fit(800, 600, 1920, 1080);
    CHECKF(r.x == 0 && r.y == 75 && r.w == 800 && r.h == 450, "fit %d %d %d %d", r.x, r.y, r.w,
           r.h);
    r = lg_vdisplay_fit(0, 600, 1920, 1080);
    CHECK(r.w == 0 && r.h == 0 && r.scale == 0.0);
    free_target(&t);
}

/* ---- text ------------------------------------------------------------------------------------ */

/* The font file itself, read here apart from the build's table: 95 glyphs, 16 rows. */
static int read_hex_font(unsigned char glyphs[LG_FONT_COUNT][16])
{
    const char *root = getenv("LG_SOURCE_ROOT");
    char path[4096];
    snprintf(path, sizeof path, "%s/assets/fonts/unifont-ascii.hex", root ? root : ".");
    FILE *f = fopen(path, "r");
    CHECKF(f != NULL, "cannot open %s", path);
    if (!f)
        return -1;
    char line[256];
    int n = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned code;
        char bits[65];
        if (sscanf(line, "%x:%64s", &code, bits) != 2 || strlen(bits) != 32 ||
            code != LG_FONT_FIRST + (unsigned)n || n >= LG_FONT_COUNT) {
            CHECKF(0, "%s:%d: unexpected line %s", path, n + 1, line);
            break;
        }
        for (int r = 0; r < 16; r++) {
            char byte[3] = { bits[2 * r], bits[2 * r + 1], 0 };
            glyphs[n][r] = (unsigned char)strtoul(byte, NULL, 16);
        }
        n++;
    }
    fclose(f);
    CHECKF(n == LG_FONT_COUNT, "%s: %d glyphs", path, n);
    return n == LG_FONT_COUNT ? 0 : -1;
}

static int glyph_lit(unsigned char glyphs[LG_FONT_COUNT][16], char c, int gx, int gy)
{
    return (glyphs[c - LG_FONT_FIRST][gy] >> (7 - gx)) & 1;
}

/* Checks the block of `s` (one line) drawn at (x0, y0) at `scale` against the glyphs; the
 * pixels around it (a margin of 2, `below` rows below it) must be the clear colour. Counts
 * lit pixels. */
static int check_line(const target *t, unsigned char glyphs[LG_FONT_COUNT][16], const char *s,
                      int x0, int y0, int scale, const int want_rgb[3], int box, int grey,
                      int below)
{
    int n = (int)strlen(s), cw = 8 * scale, ch = 16 * scale, lit = 0, bad = 0;
    for (int y = y0 - 2; y < y0 + ch + below; y++)
        for (int x = x0 - 2; x < x0 + n * cw + 2; x++) {
            if (x < 0 || y < 0 || x >= t->w || y >= t->h)
                continue;
            const unsigned char *p = at(t, x, y);
            int inside = x >= x0 && y >= y0 && x < x0 + n * cw && y < y0 + ch;
            int on = inside &&
                     glyph_lit(glyphs, s[(x - x0) / cw], (x - x0) % cw / scale, (y - y0) / scale);
            for (int c = 0; c < 3; c++) {
                int want = on ? want_rgb[c] : inside ? box : grey;
                if (!CLOSE(p[c], want) && bad++ < 6)
                    CHECKF(0,
                           "'%s' at (%d, %d) scale %d: pixel (%d, %d) channel %d = %d, want %d "
                           "(%s)",
                           s, x0, y0, scale, x, y, c, p[c], want,
                           on       ? "glyph"
                           : inside ? "box"
                                    : "outside");
            }
            lit += on;
        }
    CHECKF(bad == 0, "'%s' at (%d, %d) scale %d: %d channel values off", s, x0, y0, scale, bad);
    return lit;
}

static void test_text(void)
{
    unsigned char glyphs[LG_FONT_COUNT][16];
    if (read_hex_font(glyphs))
        return;
    /* the build's table is the file's */
    CHECK(memcmp(glyphs, lg_font_glyphs, sizeof glyphs) == 0);
    int cw = 0, ch = 0;
    lg_vdisplay_cell(disp, &cw, &ch);
    CHECK(cw == 8 && ch == 16);

    enum { FW = 64, FH = 56 };
    target t = make_target(FW, FH);
    const int grey = unorm8(LG_VDISPLAY_CLEAR);
    const int box = unorm8(LG_VDISPLAY_CLEAR * (1.0f - LG_VDISPLAY_BOX_ALPHA));
    CHECK(box < grey);
    const float rgb[3] = { 1.0f, 0.5f, 0.0f };
    const int want_rgb[3] = { 255, 128, 0 };

    fill_target(&t, LG_VDISPLAY_CLEAR);
    CHECKF(lg_vdisplay_draw_text(disp, t.fbo, FW, FH, 5, 7, "A|", rgb, 1) == 0, "%s",
           lg_vdisplay_error(disp));
    check_state("draw_text");
    read_target(&t);
    int lit = check_line(&t, glyphs, "A|", 5, 7, 1, want_rgb, box, grey, 2);
    CHECKF(lit > 20, "only %d lit pixels", lit);
    /* the '|' is one column, font column 4: mirrored it would be column 3 */
    CHECK(at(&t, 5 + 8 + 4, 7 + 8)[0] == 255 && CLOSE(at(&t, 5 + 8 + 3, 7 + 8)[0], box));
    /* and rows 0-1 of '|' are blank, rows 2.. lit: upside down it would be the reverse */
    CHECK(CLOSE(at(&t, 5 + 8 + 4, 7 + 0)[0], box) && at(&t, 5 + 8 + 4, 7 + 15)[0] == 255);

    /* scale 2, two lines, a byte that is not printable ASCII shown as '?', a final '\n' */
    fill_target(&t, LG_VDISPLAY_CLEAR);
    CHECKF(lg_vdisplay_draw_text(disp, t.fbo, FW, FH, 3, 2, "A|\n\x01", rgb, 2) == 0, "%s",
           lg_vdisplay_error(disp));
    check_state("draw_text scale 2");
    read_target(&t);
    check_line(&t, glyphs, "A|", 3, 2, 2, want_rgb, box, grey, 0);
    /* line 2: '?' then the box (the block is as wide as its longest line) */
    for (int y = 34; y < 56; y++)
        for (int x = 3; x < 35; x++) {
            int on = y < 2 + 64 && x < 3 + 16 && glyph_lit(glyphs, '?', (x - 3) / 2, (y - 34) / 2);
            int want = y >= 2 + 64 ? grey : on ? 255 : box;
            CHECKF(CLOSE(at(&t, x, y)[0], want), "line 2 pixel (%d, %d): %d, want %d", x, y,
                   at(&t, x, y)[0], want);
        }

    /* cut at the edges: partly off the left, the top, the right; far off: nothing drawn */
    fill_target(&t, LG_VDISPLAY_CLEAR);
    CHECKF(lg_vdisplay_draw_text(disp, t.fbo, FW, FH, -12, -3, "A|A|A|A|A|A|A|A|A|A", rgb, 1) == 0,
           "%s", lg_vdisplay_error(disp));
    check_state("draw_text cut");
    read_target(&t);
    /* pixel (x, y) shows the glyph pixel (x + 12, y + 3) of the line */
    int bad = 0;
    for (int y = 0; y < 13; y++)
        for (int x = 0; x < FW; x++) {
            int gx = x + 12, gy = y + 3;
            int want = glyph_lit(glyphs, "A|"[gx / 8 % 2], gx % 8, gy) ? 255 : box;
            if (!CLOSE(at(&t, x, y)[0], want) && bad++ < 4)
                CHECKF(0, "cut text pixel (%d, %d): %d, want %d", x, y, at(&t, x, y)[0], want);
        }
    CHECK(bad == 0);
    CHECK(CLOSE(at(&t, 0, 13)[0], grey));
    fill_target(&t, LG_VDISPLAY_CLEAR);
    CHECK(lg_vdisplay_draw_text(disp, t.fbo, FW, FH, -2147483647 - 1, 5, "A|", rgb, 16) == 0);
    CHECK(lg_vdisplay_draw_text(disp, t.fbo, FW, FH, 5, 2147483647, "A|", rgb, 16) == 0);
    CHECK(lg_vdisplay_draw_text(disp, t.fbo, FW, FH, 5, 5, "", rgb, 1) == 0);
    check_state("draw_text off the framebuffer");
    read_target(&t);
    for (int i = 0; i < FW * FH; i++)
        CHECKF(CLOSE(t.px[i * 4], grey), "pixel %d drawn: %d", i, t.px[i * 4]);
    free_target(&t);
}

/* ---- errors ---------------------------------------------------------------------------------- */

static void expect_error(int rc, const char *what, const char *needle, target *t)
{
    const char *msg = lg_vdisplay_error(disp);
    CHECKF(rc == -1, "%s: rc %d", what, rc);
    CHECKF(strstr(msg, needle) != NULL, "%s: message '%s' lacks '%s'", what, msg, needle);
    check_state(what);
    /* nothing drawn: the target keeps its marker */
    read_target(t);
    CHECKF(t->px[0] == 255 && t->px[1] == 255, "%s: the framebuffer was drawn on", what);
}

static void test_errors(void)
{
    enum { W = 4, H = 4 };
    float img[W * H * 4] = { 0 };
    GLuint tex = make_texture(GL_RGBA32F, W, H, img);
    GLuint r32 = make_texture(GL_R32F, W, H, img);
    GLuint empty_fbo;
    gl->CreateFramebuffers(1, &empty_fbo);
    target t = make_target(W, H);
    fill_target(&t, 1.0f);
    const float rgb[3] = { 1, 1, 1 }, bad_rgb[3] = { 1, NAN, 1 };

    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, W, H, NAN), "exposure NaN",
                 "exposure nan", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, W, H, -1.0f), "exposure -1",
                 "exposure -1", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, W, H, INFINITY), "exposure inf",
                 "exposure inf", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, 0, W, H, 1.0f), "texture 0",
                 "0 is not a texture", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, 99999, W, H, 1.0f), "texture 99999",
                 "99999 is not a texture", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, 8, 4, 1.0f), "wrong size",
                 "is 4x4, not the 8x4 stated", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, 0, 4, 1.0f), "size 0",
                 "image size 0x4", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, r32, W, H, 1.0f), "format R32F",
                 "internal format 0x822e", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, 0, H, tex, W, H, 1.0f), "fb width 0",
                 "framebuffer size 0x4", &t);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, -3, tex, W, H, 1.0f), "fb height -3",
                 "framebuffer size 4x-3", &t);
    expect_error(lg_vdisplay_draw_image(disp, 4242, W, H, tex, W, H, 1.0f), "fbo 4242",
                 "4242 is not a framebuffer", &t);
    expect_error(lg_vdisplay_draw_image(disp, empty_fbo, W, H, tex, W, H, 1.0f), "empty fbo",
                 "is not complete", &t);
    expect_error(lg_vdisplay_draw_text(disp, t.fbo, W, H, 0, 0, NULL, rgb, 1), "text NULL",
                 "text is NULL", &t);
    expect_error(lg_vdisplay_draw_text(disp, t.fbo, W, H, 0, 0, "A", rgb, 0), "scale 0",
                 "scale 0 outside 1..16", &t);
    expect_error(lg_vdisplay_draw_text(disp, t.fbo, W, H, 0, 0, "A", rgb, 17), "scale 17",
                 "scale 17 outside", &t);
    expect_error(lg_vdisplay_draw_text(disp, t.fbo, W, H, 0, 0, "A", bad_rgb, 1), "rgb NaN",
                 "colour component 1 is nan", &t);
    /* a GL error raised before the call is not taken for the display's own */
    gl->Enable(0xFFFF);
    expect_error(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, W, H, 1.0f), "pending error",
                 "pending before the call (GL_INVALID_ENUM", &t);
    /* and the display works again afterwards */
    CHECKF(lg_vdisplay_draw_image(disp, t.fbo, W, H, tex, W, H, 1.0f) == 0, "%s",
           lg_vdisplay_error(disp));
    CHECK(lg_vdisplay_error(disp)[0] == '\0');
    check_state("draw_image after errors");

    char err[256];
    lg_vdisplay *none = (lg_vdisplay *)&err;
    CHECK(lg_vdisplay_create(NULL, &none, err, sizeof err) == -1 && none == NULL);
    CHECKF(strstr(err, "no GL context") != NULL, "%s", err);
    lg_vdisplay_destroy(NULL);
    lg_vdisplay_destroy(&none);

    gl->DeleteFramebuffers(1, &empty_fbo);
    gl->DeleteTextures(1, &tex);
    gl->DeleteTextures(1, &r32);
    free_target(&t);
}

int main(int argc, char **argv)
{
    const char *name = argc > 1 ? argv[1] : "";
    char err[1024];
    lg_gl_device *dev = NULL;
    if (lg_gl_device_create(&dev, "osmesa", err, sizeof err)) {
        fprintf(stderr, "no GL device: %s\n", err);
        return check_skip("viewer_display");
    }
    gl = lg_gl_device_table(dev);
    CHECKF(lg_vdisplay_create(gl, &disp, err, sizeof err) == 0, "%s", err);
    check_state("lg_vdisplay_create");
    if (disp) {
        if (strcmp(name, "image") == 0)
            test_image();
        else if (strcmp(name, "letterbox") == 0)
            test_letterbox();
        else if (strcmp(name, "text") == 0)
            test_text();
        else if (strcmp(name, "errors") == 0)
            test_errors();
        else
            CHECKF(0, "unknown case '%s' (image, letterbox, text, errors)", name);
    }
    lg_vdisplay_destroy(&disp);
    CHECK(disp == NULL);
    lg_gl_device_destroy(&dev);
    return check_report("viewer_display");
}
