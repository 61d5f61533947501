#version 450
// volumetric_polygonal, step 2: the light-volume mesh drawn from the camera. Vertex
// pulling: no vertex array; vertex gl_VertexID is indices[gl_VertexID] of the Vertices
// buffer poly_mesh.comp wrote. Each triangle's outward normal (the index order makes it
// outward in light NDC; u_flip = the sign of the light's inverse view_proj's determinant
// carries it to world space) tells whether the camera's rays enter (-1) or leave (+1) the
// lit volume through it: for a plane the sign of dot(n, p - eye) is the same at every p.
layout(std430, binding = 0) readonly buffer Vertices { vec4 verts[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };

uniform mat4 u_view_proj;   // the camera's, with its far plane at infinity
uniform vec3 u_eye;
uniform float u_flip;

out vec3 v_world;
flat out float v_sign;

void main()
{
    int first = (gl_VertexID / 3) * 3;
    vec3 a = verts[indices[first]].xyz;
    vec3 b = verts[indices[first + 1]].xyz;
    vec3 c = verts[indices[first + 2]].xyz;
    vec3 n = u_flip * cross(b - a, c - a);
    float side = dot(n, a - u_eye);
    v_sign = side > 0.0 ? 1.0 : (side < 0.0 ? -1.0 : 0.0);
    vec3 p = verts[indices[gl_VertexID]].xyz;
    v_world = p;
    gl_Position = u_view_proj * vec4(p, 1.0);
}
