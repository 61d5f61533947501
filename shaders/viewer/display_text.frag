#version 450 core
// The viewer's text overlay (host/viewer_display.c): one rectangle covers the text block;
// each pixel finds its character cell, the character in the text grid and the glyph's
// pixel in the font atlas. A lit glyph pixel is the text colour, any other pixel of the
// block the translucent box (blended over what is there).
//
// Coordinates here run from the framebuffer's top-left, y downwards, as the caller gives
// them; gl_FragCoord's y grows upwards and is turned with the framebuffer height.

layout(location = 1) uniform vec2 u_fb_size;   // framebuffer width, height in pixels
layout(location = 2) uniform ivec2 u_origin;   // the block's top-left, from the top-left
layout(location = 3) uniform int u_scale;      // pixels per font pixel
layout(location = 4) uniform ivec2 u_cell;     // the font's cell, font pixels
layout(location = 5) uniform vec3 u_color;     // text colour, display values
layout(location = 6) uniform float u_box_alpha;
layout(location = 7) uniform int u_first;      // the code point of the atlas's glyph 0
layout(location = 8) uniform int u_count;      // glyphs in the atlas
layout(location = 9) uniform ivec2 u_grid;     // columns, lines of the text grid in use

// The text: one texel per character, row = line, 0 past a line's end (the texture may be
// larger than the grid in use: u_grid bounds it).
layout(binding = 0) uniform usampler2D u_text;
// The font: glyph i occupies columns [i * cell.x, (i + 1) * cell.x), row 0 its top row;
// 1 where the glyph is lit.
layout(binding = 1) uniform sampler2D u_font;

layout(location = 0) out vec4 o_color;

void main()
{
    ivec2 p = ivec2(int(gl_FragCoord.x), int(u_fb_size.y) - 1 - int(gl_FragCoord.y)) - u_origin;
    ivec2 cell_px = u_cell * u_scale;
    ivec2 cell = p / cell_px;
    ivec2 in_cell = (p - cell * cell_px) / u_scale;
    o_color = vec4(0.0, 0.0, 0.0, u_box_alpha);
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(cell, u_grid)))
        return;
    int code = int(texelFetch(u_text, cell, 0).r) - u_first;
    if (code < 0 || code >= u_count)
        return;
    float lit = texelFetch(u_font, ivec2(code * u_cell.x + in_cell.x, in_cell.y), 0).r;
    if (lit > 0.5)
        o_color = vec4(u_color, 1.0);
}
