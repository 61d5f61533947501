#version 450 core
// The phong node's geometry stage (plugins/phong), for the two modes that decide per facet:
//
//   flat  (LG_SHADING 0): seed 1, 1.3.1: one normal and one colour per facet. The facet
//         normal is the triangle's geometric normal (world), turned to agree with the sum
//         of its vertex normals (so mirrored instances and either winding give the outward
//         side); the lighting equation is evaluated once, at the centroid. Shadows stay per
//         pixel.
//   mixed (LG_SHADING 3): seed 1, 1.3.6: a facet is a highlight facet when the angle
//         between V and R is below the threshold for some light at one of seven samples:
//         its vertices, edge midpoints and centroid, each with the normal Phong shading
//         would use there; highlight facets are shaded per pixel (Phong), the others with
//         the vertex colours (Gouraud). Materials without a specular term have no
//         highlight facets.
//
// Double-sided materials: which side of a facet is seen is decided by its winding
// (gl_FrontFacing), in every mode, as glTF's doubleSided prescribes: the back side is lit
// with the normal reversed. The geometry stage cannot see gl_FrontFacing, so it works out
// both sides (flat: both colours; mixed: both highlight flags) and the fragment stage
// picks. Deciding here by the sign of N.V instead disagrees with the winding wherever the
// facet is seen at a grazing angle with an infinite viewer (one V for the whole image):
// a wall in ambient light in every other mode came out fully lit in flat.

#include "phong.glsl"
#include "phong_scene.glsl"

layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

layout(location = 0) in vec3 g_pos[];
layout(location = 1) in vec3 g_nrm[];
layout(location = 2) flat in uint g_id[];

layout(location = 0) out vec3 o_pos;
layout(location = 2) flat out uint o_id;

// texture coordinates and tangent, interpolated in every mode (ABI 3.1)
#define LG_UV_LOC (6 + 2 * LG_SV_ARR)
layout(location = LG_UV_LOC) in vec4 g_uv[];
layout(location = LG_UV_LOC + 1) in vec4 g_tan[];
layout(location = LG_UV_LOC) out vec4 o_uv;
layout(location = LG_UV_LOC + 1) out vec4 o_tan;

#if LG_SHADING == 0
layout(location = 1) flat out vec3 o_nrm;  // the front side's (the vertex normals' side)
layout(location = 4) flat out vec3 o_c0;   // front colour, then the back side's
layout(location = 5) flat out vec3 o_c0b;
layout(location = 6) flat out vec3 o_cs[LG_SV_ARR];
layout(location = 6 + LG_SV_ARR) flat out vec3 o_csb[LG_SV_ARR];
#else
layout(location = 3) in vec2 g_max_cos[];
layout(location = 4) in vec3 g_c0[];
layout(location = 5) in vec3 g_c0b[];
layout(location = 6) in vec3 g_cs[][LG_SV_ARR];
layout(location = 6 + LG_SV_ARR) in vec3 g_csb[][LG_SV_ARR];

layout(location = 1) out vec3 o_nrm;
layout(location = 3) flat out int o_highlight; // bit 0: front side, bit 1: back side
layout(location = 4) out vec3 o_c0;
layout(location = 5) out vec3 o_c0b;
layout(location = 6) out vec3 o_cs[LG_SV_ARR];
layout(location = 6 + LG_SV_ARR) out vec3 o_csb[LG_SV_ARR];

// The largest cos(V, R) over the lights at the seven samples of the facet (P0..P2 with
// their vertex normals g_nrm, C the centroid), on its front side or (back) its back side.
float facet_max_cos(bool back, vec3 C, vec3 Nf)
{
    float best = -2.0;
    for (int i = 0; i < 3; i++)
        best = max(best, back ? g_max_cos[i].y : g_max_cos[i].x);
    if (best <= u_mixed_cos) {
        vec3 n[3];
        for (int i = 0; i < 3; i++)
            n[i] = lg_safe_normalize(g_nrm[i], Nf) * (back ? -1.0 : 1.0);
        vec3 Ns = back ? -Nf : Nf;
        best = lg_max_cos_vr(C, lg_safe_normalize(n[0] + n[1] + n[2], Ns));
        for (int i = 0; i < 3 && best <= u_mixed_cos; i++)
            best = max(best, lg_max_cos_vr(0.5 * (g_pos[i] + g_pos[(i + 1) % 3]),
                                           lg_safe_normalize(n[i] + n[(i + 1) % 3], Ns)));
    }
    return best;
}
#endif

void main()
{
    vec3 P0 = g_pos[0], P1 = g_pos[1], P2 = g_pos[2];
    vec3 C = (P0 + P1 + P2) * (1.0 / 3.0);
    vec3 nsum = lg_safe_normalize(g_nrm[0], vec3(0.0)) + lg_safe_normalize(g_nrm[1], vec3(0.0)) +
                lg_safe_normalize(g_nrm[2], vec3(0.0));
    vec3 Vc = lg_view_vector(C);
    // a degenerate facet (no area) is not rasterised; its normal only has to be finite
    vec3 Nf = lg_safe_normalize(cross(P1 - P0, P2 - P0), lg_safe_normalize(nsum, Vc));
    if (dot(Nf, nsum) < 0.0)
        Nf = -Nf;
    LgPhongMaterial m = lg_material();

#if LG_SHADING == 0
    vec3 c0, cs[LG_SV_ARR], c0b, csb[LG_SV_ARR];
    lg_shade_split(C, Nf, m, c0, cs);
    if (u_double_sided != 0) {
        lg_shade_split(C, -Nf, m, c0b, csb);
    } else {
        c0b = c0;
        csb = cs;
    }
    for (int i = 0; i < 3; i++) {
        gl_Position = gl_in[i].gl_Position;
        o_pos = g_pos[i];
        o_id = g_id[i];
        o_nrm = Nf;
        o_uv = g_uv[i];
        o_tan = g_tan[i];
        o_c0 = c0;
        o_c0b = c0b;
        o_cs = cs;
        o_csb = csb;
        EmitVertex();
    }
#else
    int highlight = 0;
    if (u_ks > 0.0 && any(greaterThan(u_os, vec3(0.0)))) {
        // seven samples with the normal Phong shading would use there (the normalised
        // interpolation of the vertex normals): the vertices (computed once per vertex by
        // the vertex stage), the edge midpoints and the centroid; for each side that can
        // be seen
        if (facet_max_cos(false, C, Nf) > u_mixed_cos)
            highlight |= 1;
        if (u_double_sided != 0 && facet_max_cos(true, C, Nf) > u_mixed_cos)
            highlight |= 2;
    }
    for (int i = 0; i < 3; i++) {
        gl_Position = gl_in[i].gl_Position;
        o_pos = g_pos[i];
        o_nrm = g_nrm[i];
        o_uv = g_uv[i];
        o_tan = g_tan[i];
        o_id = g_id[i];
        o_highlight = highlight;
        o_c0 = g_c0[i];
        o_c0b = g_c0b[i];
        o_cs = g_cs[i];
        o_csb = g_csb[i];
        EmitVertex();
    }
#endif
    EndPrimitive();
}
