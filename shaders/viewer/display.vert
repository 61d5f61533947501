#version 450 core
// The viewer's display quad (host/viewer_display.c): a rectangle of the framebuffer given
// in GL window pixels (origin at the bottom-left), drawn as a triangle strip of four
// vertices made from gl_VertexID: no vertex buffer.

layout(location = 0) uniform vec4 u_rect;   // x0, y0, x1, y1 in pixels
layout(location = 1) uniform vec2 u_fb_size; // framebuffer width, height in pixels

void main()
{
    vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1); // (0,0) (1,0) (0,1) (1,1)
    vec2 pixel = mix(u_rect.xy, u_rect.zw, corner);
    gl_Position = vec4(pixel / u_fb_size * 2.0 - 1.0, 0.0, 1.0);
}
