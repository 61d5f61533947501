/*
 * host/viewer/display.h: what the viewer's window shows (private to the host): one image
 * of the graph fitted into the window and encoded for display, and a text overlay.
 *
 * The caller (viewer.c, loop.c) owns the GL context and the window; this module only draws,
 * through the same function table plugins use (lightgraph/glad/gl.h), into a framebuffer it is
 * given: 0 for the window's, or any complete framebuffer object (the tests draw into an
 * RGBA8 one on an OSMesa context). It makes no window-system call.
 *
 *     lg_vdisplay *d;
 *     if (lg_vdisplay_create(gl, &d, err, sizeof err)) { report err; }
 *     // every frame, context current:
 *     if (lg_vdisplay_draw_image(d, 0, fb_w, fb_h, tex, w, h, exposure) ||
 *         lg_vdisplay_draw_text(d, 0, fb_w, fb_h, 8, 8, "phong  2.1 ms", white, 1))
 *         report lg_vdisplay_error(d);
 *     lg_vdisplay_destroy(&d);
 *
 * Display encoding. Framebuffer values are what the screen shows: draw_image writes
 * lg_srgb_encode(clamp(value * exposure, 0, 1)) per channel with NaN -> 0, +Inf -> 1,
 * -Inf -> 0, exactly what the PNG writer (sdk/src/png.c) puts in a file, so that a
 * screenshot of the window and `lightgraph render -o x.png` agree to a code value.
 * GL_FRAMEBUFFER_SRGB stays disabled: the encoding is the shader's. Alpha is written 1.
 *
 * Orientation. Texel row 0 of a lightgraph image is the top row of the picture (docs/sdk.md,
 * "Row order"); framebuffer coordinates here are GL's, row 0 at the bottom, which on a
 * window is the bottom of the screen. draw_image therefore puts texel row 0 at the top of
 * the fitted rectangle. Text positions are given from the framebuffer's top-left.
 *
 * Layout. The image is fitted into the framebuffer keeping its aspect ratio: the scale is
 * min(fb_w / w, fb_h / h) (images smaller than the window are magnified too), the fitted
 * size is rounded to whole pixels and centred (lg_vdisplay_fit), and the rest is the clear
 * colour (LG_VDISPLAY_CLEAR, a dark grey). When the scale is a whole number (1:1 included)
 * the image is sampled nearest, each texel a block of pixels; magnified by another factor,
 * bilinearly; shrunk, each pixel is the mean of n x n bilinear taps spread over its
 * footprint, n = ceil(1 / scale) up to LG_VDISPLAY_MAX_TAPS (a box filter, exact for
 * shrinking by a whole factor up to 8). All filtering is on linear values, before the
 * exposure and the encoding; a NaN or Inf texel under a filter makes the pixel's mean NaN
 * (shown 0) or Inf (shown 1).
 *
 * GL state. Each draw sets what it needs (framebuffer, viewport, program, vertex array,
 * textures and samplers on units 0 and 1, blending, colour mask; scissor, depth and
 * stencil tests, culling, dithering and GL_FRAMEBUFFER_SRGB off) and leaves the state the
 * host's contract wants after a node (host/device.h, lg_gl_state_check): framebuffer 0,
 * program 0, vertex array 0, no buffer on the generic binding points, texture units 0 and
 * 1 and their samplers unbound, active texture unit 0, image units untouched; blending
 * disabled with glBlendFunc(GL_ONE, GL_ZERO), dithering enabled (lg_gl_state_reset's
 * values). The viewport is left as the draw set it (the whole framebuffer). This holds
 * after a failed call too.
 *
 * Errors. Every int function returns 0, or -1 with the reason kept for lg_vdisplay_error()
 * (create: in err). Bad arguments (a size of 0 or beyond GL_MAX_TEXTURE_SIZE, a texture
 * name that is not a 2D texture of the stated size and an accepted format, an incomplete
 * framebuffer, an exposure that is NaN, infinite or negative, a scale outside 1..
 * LG_VDISPLAY_MAX_SCALE, text NULL) are refused before anything is drawn, with the value
 * in the message. A GL error pending when a draw starts is reported as such (and cleared):
 * it was raised by an earlier call, not by the display.
 *
 * Threads. One lg_vdisplay belongs to one GL context, used from the thread where it is
 * current.
 */
#ifndef LG_HOST_VIEWER_DISPLAY_H
#define LG_HOST_VIEWER_DISPLAY_H

#include <stddef.h>
#include <stdint.h>

#include "lightgraph/glad/gl.h"

/* The clear colour (letterbox bars, the background): a display value, written as it is
 * (R = G = B). 0.12 is code value 31. */
#define LG_VDISPLAY_CLEAR 0.12f
/* Opacity of the box behind text: the box darkens what is under it to (1 - alpha). */
#define LG_VDISPLAY_BOX_ALPHA 0.6f
/* The largest text scale accepted. */
#define LG_VDISPLAY_MAX_SCALE 16
/* The most taps per axis when an image is shrunk (a box filter of up to 8 x 8 texels). */
#define LG_VDISPLAY_MAX_TAPS 8

typedef struct lg_vdisplay lg_vdisplay;

/* Where an image of w x h texels shows in a framebuffer of fb_w x fb_h pixels: the rectangle
 * x, y (its top-left, counted from the framebuffer's top-left, y down), w, h in pixels, and
 * the scale (framebuffer pixels per texel, before rounding). Texel (u, v) of the image
 * (v = 0 the top row) covers pixels x + u * scale .. from the top-left. All zero when a
 * size is 0 or negative. For mapping the mouse to image pixels, and what draw_image uses. */
typedef struct lg_vdisplay_rect {
    int x, y, w, h;
    double scale;
} lg_vdisplay_rect;
lg_vdisplay_rect lg_vdisplay_fit(int fb_w, int fb_h, uint32_t w, uint32_t h);

/* Compiles the display's programs (shaders/viewer/: display.vert with display_image.frag
 * and display_text.frag, embedded at build time by tools/embed.py) and uploads the font
 * (assets/fonts/unifont-ascii.hex, GNU Unifont's printable ASCII, 8x16 cells, turned into
 * a table at build time by tools/font_hex.py). The context must be current and GL 4.5
 * core. Returns 0 with *out set, or -1 with *out NULL and the reason in err (a GLSL
 * compiler's log names the file: "display_text.frag: fragment shader compile failed:
 * ..."). The caller owns *out (lg_vdisplay_destroy). */
int lg_vdisplay_create(const GladGLContext *gl, lg_vdisplay **out, char *err, size_t errlen);

/* Deletes the programs, textures, samplers and vertex array (the context that created them
 * must be current) and frees the display. Accepts NULL and *d NULL; clears *d. */
void lg_vdisplay_destroy(lg_vdisplay **d);

/* Draws `tex` (GL_TEXTURE_2D, level 0 of w x h texels, internal format GL_RGBA32F,
 * GL_RGBA16F or GL_RGBA8, holding linear values) into framebuffer `fbo` (0: the window's)
 * of fb_w x fb_h pixels: clears it to LG_VDISPLAY_CLEAR, fits the image (see "Layout"),
 * multiplies by `exposure` (>= 0, finite; 1 shows the values as they are) and encodes for
 * display (see "Display encoding"). The texture's own filtering and mip levels are not
 * used (the display binds its own samplers) and are left unchanged. An RGBE image
 * (lightgraph's rgbe8 format, an RGBA8 texture on GL) is not decoded: convert it first. */
int lg_vdisplay_draw_image(lg_vdisplay *d, uint32_t fbo, int fb_w, int fb_h, uint32_t tex,
                           uint32_t w, uint32_t h, float exposure);

/* Draws `text` over framebuffer `fbo` of fb_w x fb_h pixels, what is there kept: the top-left
 * of its first character cell at pixel (x, y) counted from the framebuffer's top-left
 * (x right, y down; may be negative or beyond the framebuffer: what falls outside is cut).
 * '\n' starts a new line; printable ASCII (0x20..0x7E) shows its glyph; every other byte
 * shows as '?'. Each font pixel becomes scale x scale pixels (scale 1..LG_VDISPLAY_MAX_SCALE).
 * Behind the block (as wide as its longest line, as tall as its lines, in whole cells) a
 * black box of opacity LG_VDISPLAY_BOX_ALPHA darkens what is under it; lit glyph pixels
 * are `rgb` (display values in [0,1], written as they are). An empty text draws nothing. */
int lg_vdisplay_draw_text(lg_vdisplay *d, uint32_t fbo, int fb_w, int fb_h, int x, int y,
                          const char *text, const float rgb[3], int scale);

/* The font's cell in pixels at scale 1 (8 x 16), for layout: a line of n characters at
 * scale s is n * cw * s pixels wide and ch * s pixels tall. */
void lg_vdisplay_cell(const lg_vdisplay *d, int *cw, int *ch);

/* The reason the last failed call on `d` failed ("" before any failure); valid until the
 * next call on `d`. */
const char *lg_vdisplay_error(const lg_vdisplay *d);

#endif
