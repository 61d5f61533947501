#version 450 core
// The preview's vertex stage (plugins/preview): one instance of one mesh per draw
// instance. The instance's matrices come from a storage buffer, sorted by mesh so that each
// mesh is one instanced draw; u_first is the draw's first entry.

layout(location = 0) in vec3 a_position; // object space
layout(location = 1) in vec3 a_normal;   // object space
layout(location = 2) in vec2 a_uv0;      // TEXCOORD_0 ((0, 0) for a mesh without)
layout(location = 3) in vec2 a_uv1;      // TEXCOORD_1 ((0, 0) for a mesh without)

struct lg_preview_instance {
    mat4 model;  // object to world
    mat4 normal; // inverse transpose of model's 3x3 (in the upper-left 3x3)
};
layout(std430, binding = 0) readonly buffer Instances {
    lg_preview_instance inst[];
};

layout(location = 0) uniform mat4 u_view_proj; // projection (Y flipped) * view
layout(location = 1) uniform mat4 u_view;      // world to view
layout(location = 2) uniform int u_first;

out vec3 v_normal;      // world space, not normalised
out float v_view_depth; // distance along the view axis, > 0 in front of the camera
out vec2 v_uv0, v_uv1;

void main()
{
    lg_preview_instance I = inst[u_first + gl_InstanceID];
    vec4 world = I.model * vec4(a_position, 1.0);
    v_normal = mat3(I.normal) * a_normal;
    v_view_depth = -(u_view * world).z;
    v_uv0 = a_uv0;
    v_uv1 = a_uv1;
    gl_Position = u_view_proj * world;
}
