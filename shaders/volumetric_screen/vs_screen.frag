#version 450 core
// volumetric_screen: Mitchell's screen-space light shafts (seed 2 3.2.1, eq. 6-8), one
// fragment per pixel. The C twin is vs_pixel in plugins/volumetric_screen/screen.c: the
// same float arithmetic in the same order, so that the gl and cpu backends agree.
//
// Per light l with screen position p_l (pixels, computed on the host in double; u_light_pos
// .z = 0 marks a light with no contribution: behind the camera, in the image plane, or so
// far off-screen that every sample falls outside the image):
//   p_i = p + i (p_l - p) / N, i = 1..N                          (eq. 7)
//   V_i = 1 where p_i lies inside the image and depth(p_i) >= z_l (eq. 8: z_l = 1, the sky,
//         for a directional light; the light's window depth for a point or spot light)
//   S   = sum_i 2^(i u_k) V_i    (2^(i u_k) = decay^i, or decay^(64 i / N) normalised)
// thesis:   L_v += u_scale u_norm S L_c                          (eq. 6; L_c times the
//           light's falloff at the camera for point and spot lights, on the host)
// physical: L_v += u_scale u_norm S L_c sigma_s A                (u_norm S is then the
//           decay-weighted fraction of visible samples); A = p_HG(g, w.(-L)) d seg(sigma_t d)
//           for a directional light, the airlight integral lg_point_inscatter over [0, d]
//           with VS_AIRLIGHT_NODES nodes for a point or spot light
#include "medium.glsl"

layout(location = 0) out vec4 o_out;
layout(location = 1) out vec4 o_inscatter;

layout(binding = 0) uniform sampler2D u_base;        // base colour (rgba32f)
layout(binding = 1) uniform sampler2D u_base_depth;  // its depth plane, 1 = sky
// Everything the pass reads but the images, uploaded in one call from the C struct that
// mirrors it (vs_gpu_params in plugins/volumetric_screen/screen.c, std140, 2720 bytes). No
// instance name: the members read as plain uniforms.
layout(std140, binding = 0) uniform VsParams {
    mat4 u_inv_view_proj;
    vec4 u_light_pos[32];  // xy: pixels; z: 1 contributes, 0 not; w: z_l, the visible depth
    vec4 u_light_c[32];    // L_c
    vec4 u_light_to[32];   // xyz: -L (directional) or the spot's axis; w: 0 dir, 1 point, 2 spot
    vec4 u_light_q[32];    // point, spot: xyz the position, w the range (0 infinite)
    vec4 u_light_cone[32]; // spot: x cos_inner, y cos_outer
    vec3 u_eye;
    float u_z_limit;
    vec3 u_forward;
    float u_g;
    vec3 u_sigma_s;
    float u_k;             // log2 of the decay of one sample step
    vec3 u_sigma_t;
    float u_norm;          // 1/N (thesis, not normalised) or 1 / sum of the weights
    ivec2 u_size;
    int u_samples;
    int u_lights;
    int u_physical;
    float u_scale;         // exposure x weight (thesis), exposure (physical)
};

// screen.c's VS_AIRLIGHT_NODES
const int VS_AIRLIGHT_NODES = 8;

#ifdef VS_LOCAL_LIGHTS
// A point or spot light's airlight over [0, d] (screen.c's vs_airlight, in float): a spot's
// ray cut where it crosses the outer cone, only the pieces inside the forward cone
// integrated, each with the transmittance from the eye to its start.
float vs_airlight(vec3 o, vec3 w, float d, vec3 q, float range, bool spot, vec3 axis, vec2 cone,
                  float sigma_t)
{
    if (!spot)
        return lg_point_inscatter(o, w, 0.0, d, q, range, false, axis, cone, u_g, sigma_t,
                                  VS_AIRLIGHT_NODES);
    vec3 m = o - q;
    float ma = dot(m, axis), wa = dot(w, axis), mw = dot(m, w), mm = dot(m, m);
    float c2 = cone.y > 0.0 ? cone.y * cone.y : 0.0;
    float A = wa * wa - c2, B = 2.0 * (ma * wa - c2 * mw), C = ma * ma - c2 * mm;
    float t[4] = float[4](0.0, d, d, d);
    int n = 1;
    float r[2] = float[2](0.0, 0.0);
    int nr = 0;
    if (abs(A) > 1e-12) {
        float disc = B * B - 4.0 * A * C;
        if (disc >= 0.0) {
            float sq = sqrt(disc);
            r[0] = (-B - sq) / (2.0 * A);
            r[1] = (-B + sq) / (2.0 * A);
            nr = 2;
        }
    } else if (abs(B) > 0.0) {
        r[0] = -C / B;
        nr = 1;
    }
    if (nr == 2 && r[0] > r[1]) {
        float x = r[0];
        r[0] = r[1];
        r[1] = x;
    }
    for (int k = 0; k < nr; k++)
        if (r[k] > t[n - 1] && r[k] < d)
            t[n++] = r[k];
    t[n++] = d;
    float sum = 0.0;
    for (int k = 0; k + 1 < n; k++) {
        if (!(t[k + 1] > t[k]))
            continue;
        vec3 v = o + (0.5 * (t[k] + t[k + 1])) * w - q;
        float len = length(v);
        if (!(len > 0.0) || !(dot(v, axis) > cone.y * len))
            continue;
        sum += exp(-sigma_t * t[k]) * lg_point_inscatter(o, w, t[k], t[k + 1], q, range, true,
                                                         axis, cone, u_g, sigma_t,
                                                         VS_AIRLIGHT_NODES);
    }
    return sum;
}
#endif

vec3 unproject(vec2 ndc, float z)
{
    vec4 r = u_inv_view_proj * vec4(ndc, z, 1.0);
    return r.xyz / r.w;
}

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 base = texelFetch(u_base, px, 0);
    float depth = texelFetch(u_base_depth, px, 0).r;
    vec2 p = vec2(px) + 0.5;
    vec2 size = vec2(u_size);

    // the view ray and the fog's extent along it (vol_common.h)
    vec2 ndc = 2.0 * p / size - 1.0;
    vec3 w = normalize(unproject(ndc, 0.0) - u_eye);
    float cw = dot(w, u_forward);
    float d = cw > 0.0 ? u_z_limit / cw : 0.0;
    if (depth < 1.0)
        d = min(d, length(unproject(ndc, 2.0 * depth - 1.0) - u_eye));

    vec3 lv = vec3(0.0);
    float nf = float(u_samples);
    for (int l = 0; l < u_lights; l++) {
        if (u_light_pos[l].z == 0.0)
            continue;
        vec2 dp = (u_light_pos[l].xy - p) / nf;
#ifdef VS_LOCAL_LIGHTS
        float zl = u_light_pos[l].w;
#else
        const float zl = 1.0; // directional lights only: the sky
#endif
        float s = 0.0;
        for (int i = 1; i <= u_samples; i++) {
            vec2 q = p + float(i) * dp;
            if (q.x >= 0.0 && q.y >= 0.0 && q.x < size.x && q.y < size.y &&
                texelFetch(u_base_depth, ivec2(q), 0).r >= zl)
                s += exp2(float(i) * u_k);
        }
        vec3 c = u_light_c[l].rgb * (u_scale * u_norm * s);
#ifdef VS_LOCAL_LIGHTS
        float type = u_light_to[l].w;
        if (u_physical != 0 && type != 0.0) {
            // point, spot: the airlight along the ray to d, per distinct sigma_t
            vec3 q = u_light_q[l].xyz, axis = u_light_to[l].xyz;
            float range = u_light_q[l].w;
            bool spot = type == 2.0;
            vec2 cone = u_light_cone[l].xy;
            vec3 a;
            a.r = vs_airlight(u_eye, w, d, q, range, spot, axis, cone, u_sigma_t.r);
            a.g = u_sigma_t.g == u_sigma_t.r
                      ? a.r
                      : vs_airlight(u_eye, w, d, q, range, spot, axis, cone, u_sigma_t.g);
            a.b = u_sigma_t.b == u_sigma_t.g
                      ? a.g
                      : vs_airlight(u_eye, w, d, q, range, spot, axis, cone, u_sigma_t.b);
            c *= u_sigma_s * a;
        } else
#endif
        if (u_physical != 0) {
            c *= u_sigma_s * lg_hg_phase(u_g, dot(w, u_light_to[l].xyz)) * d *
                 lg_medium_segment3(u_sigma_t * d);
        }
        lv += c;
    }
    vec3 t = u_physical != 0 ? exp(-u_sigma_t * d) : vec3(1.0);
    o_out = vec4(base.rgb * t + lv, base.a);
    o_inscatter = vec4(lv, 1.0);
    gl_FragDepth = depth;
}
