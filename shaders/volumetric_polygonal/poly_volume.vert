#version 450
// volumetric_polygonal, step 2: the light-volume mesh drawn from the camera. Vertex
// pulling: no vertex array; vertex gl_VertexID is indices[gl_VertexID] of the Vertices
// buffer poly_mesh.comp wrote. Whether a ray enters or leaves the lit volume through a
// triangle is decided in poly_volume.frag from gl_FrontFacing: the rasteriser's own
// winding, consistent with the coverage it computes.
layout(std430, binding = 0) readonly buffer Vertices { vec4 verts[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };

#include "poly_view.glsl"

out vec3 v_world;

void main()
{
    vec3 p = verts[indices[gl_VertexID]].xyz;
    v_world = p;
    gl_Position = u_view_proj * vec4(p, 1.0);
}
