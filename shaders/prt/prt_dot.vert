#version 450 core
// A triangle covering the viewport, from gl_VertexID alone: the prt node's dot-product pass
// (prt_dot.frag) runs once per texel of the `vertices` image, i.e. once per vertex.

void main()
{
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
