#version 450 core
// The prt node's raster pass (plugins/prt): each vertex carries its radiance, read from
// the `vertices` image at index u_offset + gl_VertexID (u_offset = the first vertex of the
// mesh being drawn, set per mesh; every instance of a mesh shares its values), and the
// rasteriser interpolates it across the triangle (Gouraud, as seed 0 does).

layout(location = 0) in vec3 a_position; // object space

struct lg_prt_instance {
    mat4 model;  // object to world
    mat4 normal; // inverse transpose of model's 3x3 (upper-left)
};
layout(std430, binding = 0) readonly buffer Instances {
    lg_prt_instance inst[];
};

uniform mat4 u_view_proj; // projection (Y flipped) * view
uniform int u_first;
uniform int u_offset;     // the mesh's first vertex in the vertices image
uniform sampler2D u_vertices;

out vec3 v_radiance;

void main()
{
    mat4 model = inst[u_first + gl_InstanceID].model;
    int w = textureSize(u_vertices, 0).x;
    int i = u_offset + gl_VertexID;
    v_radiance = texelFetch(u_vertices, ivec2(i % w, i / w), 0).rgb;
    gl_Position = u_view_proj * (model * vec4(a_position, 1.0));
}
