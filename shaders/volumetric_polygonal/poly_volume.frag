#version 450
// volumetric_polygonal, step 2: one crossing of the lit volume's boundary at distance s
// along the pixel's view ray adds sign F(min(s, d)) (eq. 9 with sigma_s):
//
//     F(s) = L_c sigma_s p_HG(g, dot(w, -L)) s segment(sigma_t s)
//          = L_c sigma_s p_HG (1 - e^(-sigma_t s)) / sigma_t
//
// (lightgraph/medium.h), leaving +, entering -. d is the fog's length along the ray
// (plugins/volumetric_common/vol_common.h: min(surface distance, z_limit / dot(w, fwd));
// fragments beyond it are clamped to it, so a lit interval that goes past the surface
// ends there. Blending adds every fragment (no depth test): the sum over the crossings
// is the in-scatter of the lit intervals; a ray starting inside needs no entry (F(0) = 0).
//
// Leaving or entering: the triangles turn counter-clockwise about the lit volume's
// outward normal (in world space once u_flip, the sign of the light's inverse view_proj's
// determinant, is applied); the camera's projection flips Y (row 0 at the top), so a face
// seen from outside (entering) is clockwise in the window: back facing. gl_FrontFacing
// comes from the same window coordinates as the coverage, so every pixel a triangle covers
// gets the sign of its winding there; a sign computed per triangle in world space
// (dot(n, p - eye) in fp32) can disagree with the coverage on triangles seen almost
// edge-on (the dent's walls when the view runs along the light), and one such fragment
// turns a pixel's +F(d) into -F(d) (README, "Entering or leaving").
//
// Compiled with POLY_LOCAL (polygonal.c: only for a frame with a point or spot light; a
// directional scene runs the code above alone), a point or spot light (u_type 1, 2; its
// volume from a perspective map, or the whole view when it has none, u_full) replaces F(s)
// by the airlight integral from the eye,
//
//     F(s) = L_c sigma_s A(0, s),   A = lg_point_inscatter (shaders/common/medium.glsl)
//
// with u_nodes Gauss-Legendre nodes in the angle (exact for g = 0, sigma_t = 0 and no range,
// lightgraph/medium.h). A starts at the eye, so the signed sum of A(0, s) over the crossings
// is the integral over the lit intervals, as with the directional F; a ray starting inside
// the volume (the camera in the cone) needs no entry term, since A(0, 0) = 0.
// With the eye at the light (within LG_LIGHT_EPSILON, u_apex_eye) the faces through the
// light are edge-on and dropped (radial_face): no ray from the light crosses them.
#include "medium.glsl"

in vec3 v_world;

layout(binding = 0) uniform sampler2D u_base_depth; // base's depth plane (window depth)
#include "poly_view.glsl"
// per light, set between the draws of the pass (uniforms, not a block: rewriting a buffer
// that the pass's earlier draws read makes llvmpipe finish them first)
uniform vec3 u_l_c;            // L_c of this light
uniform vec3 u_dir;            // the direction its light travels
uniform float u_flip;          // +1, or -1 when the light's NDC -> world map mirrors
uniform int u_type;            // 0 directional, 1 point, 2 spot (lg_light_type)
uniform vec3 u_pos;            // point, spot: the light's position
uniform float u_range;         // point, spot: 0 = infinite
uniform vec2 u_cone;           // spot: cos_inner, cos_outer
uniform int u_nodes;           // point, spot: the quadrature's nodes (1 .. 8)
uniform int u_full;            // 1: the whole segment [0, d], sign +
uniform int u_apex_eye;        // 1: the eye is at the light (within LG_LIGHT_EPSILON)
uniform ivec2 u_grid;          // the mesh's Ws, Hs (poly_indices' triangle order)

layout(location = 0) out vec4 o_color;

vec3 unproject(vec2 xy, float z)
{
    vec4 p = u_inv_view_proj * vec4(2.0 * xy / u_size - 1.0, z, 1.0);
    return p.xyz / p.w;
}

#ifdef POLY_LOCAL
// Whether triangle p (gl_PrimitiveID, the draw's p-th triangle in poly_indices' order) lies
// in a plane through the light: the dent's walls and the frustum's sides (along rays from
// the light) and the collapsed cap. Seen from the light itself they are edge-on: no ray
// from it crosses them, yet the rasteriser may give a sliver of one a pixel on its line.
bool radial_face(int p)
{
    int W = u_grid.x - 1, H = u_grid.y - 1;
    int q = p - 2 * W * H; // the grid's triangles first
    if (q < 0)
        return false;
    for (int side = 0; side < 4; side++) {
        int n = (side % 2 == 0) ? W : H;
        if (q < 3 * n)
            return q % 3 != 2; // per border edge: two dent walls, one far-frame triangle
        q -= 3 * n;
        if (q < 3)
            return q != 0; // the frame's trapezoid, then the side's two triangles
        q -= 3;
    }
    return true; // the cap at the light
}
#endif

void main()
{
#ifdef POLY_LOCAL
    if (u_apex_eye != 0 && radial_face(gl_PrimitiveID))
        discard;
#endif
    vec2 xy = gl_FragCoord.xy; // the pixel's centre
    vec3 w = normalize(unproject(xy, 0.0) - u_eye);
    float depth = texelFetch(u_base_depth, ivec2(xy), 0).r;
    float d = 3.0e38;
    if (depth < 1.0)
        d = length(unproject(xy, 2.0 * depth - 1.0) - u_eye);
    float c = dot(w, u_forward);
    if (c > 0.0)
        d = min(d, u_z_limit / c);
    float s = min(length(v_world - u_eye), d);
    vec3 f;
#ifdef POLY_LOCAL
    if (u_type == 0) {
#endif
        float phase = lg_hg_phase(u_g, dot(w, -u_dir));
        f = u_l_c * u_sigma_s * (phase * s) * lg_medium_segment3(u_sigma_t * s);
#ifdef POLY_LOCAL
    } else {
        if (u_full != 0)
            s = d;
        bool spot = u_type == 2;
        vec3 a;
        a.r = lg_point_inscatter(u_eye, w, 0.0, s, u_pos, u_range, spot, u_dir, u_cone, u_g,
                                 u_sigma_t.r, u_nodes);
        // the channels share the integral when they share sigma_t (the usual grey fog)
        a.g = u_sigma_t.g == u_sigma_t.r
                  ? a.r
                  : lg_point_inscatter(u_eye, w, 0.0, s, u_pos, u_range, spot, u_dir, u_cone,
                                       u_g, u_sigma_t.g, u_nodes);
        a.b = u_sigma_t.b == u_sigma_t.r
                  ? a.r
                  : (u_sigma_t.b == u_sigma_t.g
                         ? a.g
                         : lg_point_inscatter(u_eye, w, 0.0, s, u_pos, u_range, spot, u_dir,
                                              u_cone, u_g, u_sigma_t.b, u_nodes));
        f = u_l_c * u_sigma_s * a;
    }
#endif
    float sgn = (gl_FrontFacing ? 1.0 : -1.0) * u_flip; // leaving +, entering -
#ifdef POLY_LOCAL
    if (u_full != 0)
        sgn = 1.0;
#endif
    o_color = vec4(sgn * f, 0.0);
}
