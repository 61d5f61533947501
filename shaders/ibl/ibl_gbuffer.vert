#version 450 core
// The ibl plugin's G-buffer pass (plugins/ibl): one instance of one mesh per draw
// instance, matrices from lightgraph/scene_gl.h's storage buffer (u_first + instance);
// texture coordinates and the tangent for the material's textures (LG_SCENE_GL_TEXCOORDS:
// constants for a mesh without them).

layout(location = 0) in vec3 a_position; // object space
layout(location = 1) in vec3 a_normal;   // object space
layout(location = 2) in vec2 a_uv0;      // TEXCOORD_0
layout(location = 3) in vec2 a_uv1;      // TEXCOORD_1
layout(location = 4) in vec4 a_tangent;  // object space xyz, w the bitangent's sign

struct lg_ibl_instance {
    mat4 model;  // object to world
    mat4 normal; // inverse transpose of model's 3x3 (upper-left)
};
layout(std430, binding = 0) readonly buffer Instances {
    lg_ibl_instance inst[];
};

uniform mat4 u_view_proj; // projection (Y flipped) * view
uniform int u_first;

out vec3 v_normal; // world space, not normalised
out vec2 v_uv0, v_uv1;
out vec4 v_tangent; // world space xyz (not normalised), w the sign

void main()
{
    lg_ibl_instance I = inst[u_first + gl_InstanceID];
    vec4 world = I.model * vec4(a_position, 1.0);
    v_normal = mat3(I.normal) * a_normal;
    v_uv0 = a_uv0;
    v_uv1 = a_uv1;
    // a mirroring model matrix flips the bitangent, as it flips the winding
    mat3 m = mat3(I.model);
    v_tangent = vec4(m * a_tangent.xyz, determinant(m) < 0.0 ? -a_tangent.w : a_tangent.w);
    gl_Position = u_view_proj * world;
}
