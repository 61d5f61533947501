#version 450 core
// The prt node's raster pass (plugins/prt): each vertex carries its radiance, read from
// the `vertices` image at index u_offset + gl_VertexID (u_offset = the first vertex of the
// mesh being drawn, set per mesh; every instance of a mesh shares its values), and the
// rasteriser interpolates it across the triangle (Gouraud, as seed 0 does).

layout(location = 0) in vec3 a_position; // object space

// lightgraph/scene_gl.h's records without normals: the model matrix only
layout(std430, binding = 0) readonly buffer Instances {
    mat4 inst_model[]; // object to world
};

uniform mat4 u_view_proj; // projection (Y flipped) * view
uniform int u_first;
uniform int u_offset;     // the mesh's first vertex in the vertices image
uniform sampler2D u_vertices;

out vec3 v_radiance;

void main()
{
    mat4 model = inst_model[u_first + gl_InstanceID];
    int w = textureSize(u_vertices, 0).x;
    int i = u_offset + gl_VertexID;
    v_radiance = texelFetch(u_vertices, ivec2(i % w, i / w), 0).rgb;
    gl_Position = u_view_proj * (model * vec4(a_position, 1.0));
}
