#version 450 core
// The preview's wireframe stage (plugins/preview, parameter `wireframe`): passes each
// triangle through and gives every fragment its distance in pixels to the triangle's three
// edges (the "single-pass wireframe" of Bærentzen et al.: each vertex's distance to the
// opposite edge, interpolated without perspective, is the fragment's distance to that
// edge), so that the fragment stage draws lines over the shaded surface without a second
// pass. A triangle with a vertex behind the eye (w <= 0) has no window-space edges: it is
// drawn without lines.

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(location = 6) uniform vec2 u_viewport; // output size in pixels

in vec3 v_normal[];
in float v_view_depth[];
in vec2 v_uv0[], v_uv1[];

out vec3 g_normal;
out float g_view_depth;
out vec2 g_uv0, g_uv1;
noperspective out vec3 g_edge; // distances in pixels to the edges opposite vertices 0, 1, 2

void main()
{
    vec2 p[3];
    bool ok = true;
    for (int i = 0; i < 3; i++) {
        vec4 c = gl_in[i].gl_Position;
        ok = ok && c.w > 0.0;
        p[i] = c.xy / max(c.w, 1e-30) * 0.5 * u_viewport;
    }
    // twice the area over each edge's length: the height from the opposite vertex
    float area = abs((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y));
    vec3 h = vec3(area / max(length(p[2] - p[1]), 1e-30), area / max(length(p[2] - p[0]), 1e-30),
                  area / max(length(p[1] - p[0]), 1e-30));
    for (int i = 0; i < 3; i++) {
        g_normal = v_normal[i];
        g_view_depth = v_view_depth[i];
        g_uv0 = v_uv0[i];
        g_uv1 = v_uv1[i];
        vec3 e = vec3(0.0);
        e[i] = h[i];
        g_edge = ok ? e : vec3(1e30);
        gl_Position = gl_in[i].gl_Position;
        EmitVertex();
    }
    EndPrimitive();
}
