#version 450
// volumetric_polygonal, step 2: the light-volume mesh drawn from the camera. Vertex
// pulling: no vertex array; vertex gl_VertexID is indices[gl_VertexID] of the Vertices
// buffer poly_mesh.comp wrote. Whether a ray enters or leaves the lit volume through a
// triangle is decided in poly_volume.frag from gl_FrontFacing: the rasteriser's own
// winding, consistent with the coverage it computes.
layout(std430, binding = 0) readonly buffer Vertices { vec4 verts[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };

#include "poly_view.glsl"

#ifdef POLY_LOCAL
// 1: no mesh, a triangle covering the viewport (a point or spot light without a shadow map:
// every ray is lit over its whole fog segment, poly_volume.frag)
uniform int u_full;
#endif

out vec3 v_world;

void main()
{
#ifdef POLY_LOCAL
    if (u_full != 0) {
        vec2 c = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
        v_world = u_eye;
        gl_Position = vec4(c, 0.0, 1.0);
        return;
    }
#endif
    vec3 p = verts[indices[gl_VertexID]].xyz;
    v_world = p;
    gl_Position = u_view_proj * vec4(p, 1.0);
}
