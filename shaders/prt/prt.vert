#version 450 core
// The prt node's raster pass (plugins/prt): each vertex carries its radiance, read from
// the `vertices` image at index u_offset + gl_VertexID (u_offset = the first vertex of the
// mesh being drawn, set per mesh; every instance of a mesh shares its values), and the
// rasteriser interpolates it across the triangle (Gouraud, as seed 0 does). The texture
// coordinates go on to the fragment stage for the base colour texture (LG_SCENE_GL_TEXCOORDS:
// constants for a mesh without them).

layout(location = 0) in vec3 a_position; // object space
layout(location = 2) in vec2 a_uv0;      // TEXCOORD_0
layout(location = 3) in vec2 a_uv1;      // TEXCOORD_1

// lightgraph/scene_gl.h's records without normals: the model matrix only
layout(std430, binding = 0) readonly buffer Instances {
    mat4 inst_model[]; // object to world
};

uniform mat4 u_view_proj; // projection (Y flipped) * view
uniform int u_first;
uniform int u_offset;     // the mesh's first vertex in the vertices image
uniform sampler2D u_vertices;

out vec3 v_radiance;
out vec2 v_uv0, v_uv1;

void main()
{
    mat4 model = inst_model[u_first + gl_InstanceID];
    int w = textureSize(u_vertices, 0).x;
    int i = u_offset + gl_VertexID;
    v_radiance = texelFetch(u_vertices, ivec2(i % w, i / w), 0).rgb;
    v_uv0 = a_uv0;
    v_uv1 = a_uv1;
    gl_Position = u_view_proj * (model * vec4(a_position, 1.0));
}
