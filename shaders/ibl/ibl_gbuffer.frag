#version 450 core
// The ibl plugin's G-buffer: the interpolated world normal (not normalised: the shading
// pass normalises, on every backend alike) and the material index + 1 (0 = no geometry).

in vec3 v_normal;
uniform float u_material; // material index + 1

layout(location = 0) out vec4 o_gbuf;

void main()
{
    o_gbuf = vec4(v_normal, u_material);
}
