#version 450 core
// The phong node's fragment stage (plugins/phong), by shading mode (LG_SHADING):
//   0 flat       the facet's colour (held), times each shadowed light's Shadow_L here
//   1 gouraud    the vertex colours interpolated (seed 1, eq. 1-14, 1-15), same shadows
//   2 phong      the lighting equation here, with the interpolated normal (eq. 1-16, 1-17)
//   3 mixed      phong on highlight facets, gouraud on the others (1.3.6)
//   4 phong_half's first pass: only the surface id (the instance, from 1; 0 is the
//                background) and depth at full size; phong_half shades two quarter-size
//                images with mode 2 and phong_half.comp assembles the output.
// Alpha is 1. For a double-sided material a back face (by winding: gl_FrontFacing, in every
// mode) is lit with the normal reversed.
// Textures (ABI 3.1, shaders/common/material.glsl): alpha-masked texels are no surface in
// every mode (ids included). Per pixel (phong, mixed's highlight facets, phong_half): Od
// times the base colour texture, Os times the base colour texture weighted by metallic
// (mix(1, texture, metallic): a metal's specular colour is its base colour), the normal
// texture in N, occlusion on ka (the ambient term), emissive added. Held colours (flat,
// gouraud, mixed's other facets: lit at the vertices or the facet, where no texel is) are
// modulated by the base colour texture at the pixel (fixed-function GL's GL_MODULATE, the
// specular term included), emissive added; their normal is the vertices' (no normal map)
// and occlusion is not applied.

#include "phong.glsl"
#include "phong_scene.glsl"

layout(location = 0) in vec3 f_pos;
layout(location = 2) flat in uint f_id;
#define LG_UV_LOC (6 + 2 * LG_SV_ARR)
layout(location = LG_UV_LOC) in vec4 f_uv;      // TEXCOORD_0, TEXCOORD_1
layout(location = LG_UV_LOC + 1) in vec4 f_tan; // world tangent, w its sign
#if LG_SHADING == 0
layout(location = 1) flat in vec3 f_nrm;
layout(location = 4) flat in vec3 f_c0;
layout(location = 5) flat in vec3 f_c0b;
layout(location = 6) flat in vec3 f_cs[LG_SV_ARR];
layout(location = 6 + LG_SV_ARR) flat in vec3 f_csb[LG_SV_ARR];
#else
layout(location = 1) in vec3 f_nrm;
#endif
#if LG_SHADING == 3
layout(location = 3) flat in int f_highlight; // bit 0: front side, bit 1: back side
#endif
#if LG_SHADING == 1 || LG_SHADING == 3
layout(location = 4) in vec3 f_c0;
layout(location = 5) in vec3 f_c0b;
layout(location = 6) in vec3 f_cs[LG_SV_ARR];
layout(location = 6 + LG_SV_ARR) in vec3 f_csb[LG_SV_ARR];
#endif

#if LG_SHADING == 4
layout(location = 0) out uint o_id;
#else
layout(location = 0) out vec4 o_color;
#endif

// Whether this pixel shows the back side of a double-sided surface (by winding).
bool back_side()
{
    return u_double_sided != 0 && !gl_FrontFacing;
}

// The normal at this pixel: interpolated (or the facet's), unit, reversed on the back side
// of a double-sided surface.
vec3 pixel_normal()
{
    vec3 N = lg_safe_normalize(f_nrm, lg_view_vector(f_pos));
    return back_side() ? -N : N;
}

// The facet's unit normal from the position's screen derivatives, on N's side (the
// geometric normal the shadow test wants); N where the derivatives give none.
vec3 geometric_normal(vec3 N)
{
    vec3 g = lg_safe_normalize(cross(dFdx(f_pos), dFdy(f_pos)), N);
    return dot(g, N) < 0.0 ? -g : g;
}

#if LG_SHADING == 0 || LG_SHADING == 1 || LG_SHADING == 3
// Interpolated (or held) colours with each shadowed light's visibility at this pixel.
vec3 held_colour(vec3 Ng)
{
    bool back = back_side();
    vec3 c = back ? f_c0b : f_c0;
    // the k-th shadowed light in the lights' order (lg_shade_split's numbering)
    for (int i = 0, k = 0; i < u_n_lights && k < LG_SV; i++) {
        int s = lg_lights[i].shadow;
        if (s < 0)
            continue;
        vec3 ck = back ? f_csb[k] : f_cs[k];
        if (any(greaterThan(ck, vec3(0.0))))
            c += ck * lg_shadow(s, f_pos, Ng, lg_light_dir(i, f_pos));
        k++;
    }
    return c;
}
#endif

// The material's textures at this pixel applied to m and N (per-pixel shading).
void textured(vec4 tex, inout LgPhongMaterial m, inout vec3 N)
{
    if (lg_mat.has.x != 0) {
        m.od *= tex.rgb;
        float metal = clamp(lg_mat_metallic_roughness(f_uv.xy, f_uv.zw).x, 0.0, 1.0);
        m.os *= mix(vec3(1.0), tex.rgb, metal);
    }
    if (lg_mat.has.w != 0)
        m.ka *= lg_mat_occlusion(f_uv.xy, f_uv.zw);
    if (lg_mat.has.z != 0)
        N = lg_mat_normal(f_nrm, f_tan, f_uv.xy, f_uv.zw, gl_FrontFacing);
}

void main()
{
    // the base colour texture and the normals first, in uniform control flow (implicit
    // derivatives), then the alpha mask
    vec4 tex = lg_mat.has.x != 0 ? texture(lg_mat_base_tex, lg_mat_uv(0, f_uv.xy, f_uv.zw))
                                 : vec4(1.0);
#if LG_SHADING != 4
    vec3 N = pixel_normal();
    vec3 Ng = geometric_normal(N);
#endif
    if (lg_mat_cut(lg_mat.base_color.a * tex.a))
        discard;
#if LG_SHADING == 4
    o_id = f_id;
#else
    LgPhongMaterial m = lg_material();
    vec3 c;
#if LG_SHADING == 0 || LG_SHADING == 1
    c = held_colour(Ng) * tex.rgb;
#elif LG_SHADING == 2
    textured(tex, m, N);
    c = lg_shade(f_pos, N, Ng, m);
#elif LG_SHADING == 3
    if ((f_highlight & (back_side() ? 2 : 1)) != 0) {
        textured(tex, m, N);
        c = lg_shade(f_pos, N, Ng, m);
    } else {
        c = held_colour(Ng) * tex.rgb;
    }
#endif
    c += lg_mat_emissive(f_uv.xy, f_uv.zw);
    o_color = vec4(c, 1.0);
#endif
}
