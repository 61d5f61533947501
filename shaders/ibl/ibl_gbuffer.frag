#version 450 core
// The ibl plugin's G-buffer: the world normal (the interpolated one, not normalised: the
// shading pass normalises, on every backend alike; with a normal texture the mapped one)
// and the material index + 1 (0 = no geometry); in attachment 1 the pixel's F0 (rgb) and
// perceptual roughness. The material's textures (shaders/common/material.glsl): an alpha
// mask discards (the probe or base shows through), the metallic-roughness texture scales
// the roughness, and for a material whose F0 follows its textures (u_f0_dielectric.w)
// F0 = mix(F0 of the dielectric, metal's F0 x base colour texel, metallic x texel B) per
// pixel (glTF 2.0 Appendix B; plugins/ibl/README.md, "Textures").
#include "material.glsl"

in vec3 v_normal;
in vec2 v_uv0, v_uv1;
in vec4 v_tangent;
uniform float u_material;      // material index + 1
uniform vec4 u_f0_rough;       // the material's F0 and roughness (the shading's table)
uniform vec4 u_f0_dielectric;  // xyz: the dielectric F0; w: 1 = F0 from the textures
uniform vec3 u_f0_metal;       // the metal's F0 (the base colour factor; a pure metal's
                               // reflectivity), times the base colour texel

layout(location = 0) out vec4 o_gbuf;
layout(location = 1) out vec4 o_gbuf2;

void main()
{
    vec4 base = lg_mat_base_color(v_uv0, v_uv1);
    if (lg_mat_cut(base.a))
        discard;
    vec3 n = v_normal;
    if (lg_mat.has.z != 0)
        n = lg_mat_normal(v_normal, v_tangent, v_uv0, v_uv1, gl_FrontFacing);
    vec4 fr = u_f0_rough;
    // the table's roughness holds the factor (0 where the node reads no chain): times G
    if (lg_mat.has.y != 0)
        fr.a *= texture(lg_mat_mr_tex, lg_mat_uv(1, v_uv0, v_uv1)).g;
    if (u_f0_dielectric.w != 0.0) {
        vec3 texel = lg_mat.has.x != 0 ? texture(lg_mat_base_tex, lg_mat_uv(0, v_uv0, v_uv1)).rgb
                                       : vec3(1.0);
        fr.rgb = mix(u_f0_dielectric.rgb, u_f0_metal * texel,
                     lg_mat_metallic_roughness(v_uv0, v_uv1).x);
    }
    o_gbuf = vec4(n, u_material);
    o_gbuf2 = fr;
}
