#version 450 core
// The ibl plugin's G-buffer pass (plugins/ibl): one instance of one mesh per draw
// instance, matrices from lightgraph/scene_gl.h's storage buffer (u_first + instance).

layout(location = 0) in vec3 a_position; // object space
layout(location = 1) in vec3 a_normal;   // object space

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

void main()
{
    lg_ibl_instance I = inst[u_first + gl_InstanceID];
    vec4 world = I.model * vec4(a_position, 1.0);
    v_normal = mat3(I.normal) * a_normal;
    gl_Position = u_view_proj * world;
}
