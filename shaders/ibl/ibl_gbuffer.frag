#version 450 core
// The ibl plugin's G-buffer: the interpolated world normal (not normalised: the shading
// pass normalises, on every backend alike) and the material index + 1 (0 = no geometry);
// in attachment 1 the pixel's F0 (rgb) and perceptual roughness.

in vec3 v_normal;
uniform float u_material; // material index + 1
uniform vec4 u_f0_rough;  // the material's F0 and roughness (the shading's table)

layout(location = 0) out vec4 o_gbuf;
layout(location = 1) out vec4 o_gbuf2;

void main()
{
    o_gbuf = vec4(v_normal, u_material);
    o_gbuf2 = u_f0_rough;
}
