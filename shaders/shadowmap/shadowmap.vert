#version 450 core
// The shadow map's vertex stage (plugins/shadowmap): one instance of one mesh per draw
// instance, projected by one light's view_proj into that light's tile of the atlas. The
// instances' model matrices come from a storage buffer sorted by mesh (and handedness),
// so that each mesh is one instanced draw per light; u_first is the draw's first entry.

layout(location = 0) in vec3 a_position; // object space
layout(location = 2) in vec2 a_uv0;      // TEXCOORD_0, for alpha masks ((0, 0) without)
layout(location = 3) in vec2 a_uv1;      // TEXCOORD_1

layout(std430, binding = 0) readonly buffer Instances {
    mat4 model[]; // object to world
};

layout(location = 0) uniform mat4 u_view_proj; // the light's proj (Y flipped) * view
layout(location = 1) uniform int u_first;

out vec2 v_uv0, v_uv1;

void main()
{
    v_uv0 = a_uv0;
    v_uv1 = a_uv1;
    gl_Position = u_view_proj * (model[u_first + gl_InstanceID] * vec4(a_position, 1.0));
}
