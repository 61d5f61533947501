// The phong node's lights, shadows, view and material (plugins/phong/README.md), on top of
// the lighting equation of shaders/common/phong.glsl (include that first). Shared by every
// stage of every shading mode, so that flat, Gouraud, Phong, mixed and phong_half evaluate
// the same equation and differ only in *where* they evaluate it.
//
// Units: a light's Ii = colour * intensity (scene.h), used as the model's incident intensity;
// the result is the model's reflected intensity in the same units (HDR, linear).

// The material's textures and alpha mode (ABI 3.1): shaders/common/material.glsl (block
// binding 6, units 8..12, apart from this node's own bindings).
#include "material.glsl"

// One light as the node uploads it (std430, 64 bytes).
//   pos.xyz  position (point, spot), world
//   pos.w    type: 0 = at infinity (directional lights, and point/spot lights with
//            lights_at = infinite, whose L and Ii the node computed at the scene's centre)
//            1 = local point light, 2 = local spot light
//   dir.xyz  type 0: L, the unit vector from the surface towards the light;
//            type 2: the unit direction the spot light travels
//   dir.w    range (local lights): no light beyond it; 0 = unlimited
//   radiance Ii = colour * intensity (times the cone and falloff already, for type 0)
//   shadow   index into LgShadows of the light's first map, or -1: no shadow map
//   cone     x: cos(outer cone), y: 1 / (cos(inner) - cos(outer)) (spot); z: 1 = inverse-
//            square falloff with distance (local lights), 0 = none
struct LgLight {
    vec4 pos;
    vec4 dir;
    vec3 radiance;
    int shadow;
    vec4 cone;
};
layout(std430, binding = 1) readonly buffer LgLights {
    LgLight lg_lights[];
};

// One map of a shadow-mapped light (a record of lightgraph/shadowmap.h), std430, 112 bytes.
// A point light's six cube faces are consecutive, +x, -x, +y, -y, +z, -z.
struct LgShadow {
    mat4 view_proj;    // world -> the map's clip space (Y flipped)
    vec2 tile;         // the tile's top-left texel in the atlas
    float texel_world; // world size of one texel (normal offset unit; perspective: at 1 m)
    int light;         // index into LgLights
    vec3 light_pos;    // perspective: the light's position, world
    int projection;    // 0 orthographic, 1 perspective
    float znear;       // perspective: the near plane's distance
    float depth_range; // world depth covered by [0, 1] (perspective: far - near)
    int n_faces;       // maps of this light from this one on: 6 for a cube's first face, else 1
    int pad;
};
layout(std430, binding = 2) readonly buffer LgShadows {
    LgShadow lg_shadows[];
};
layout(binding = 0) uniform sampler2D u_atlas; // the depth-only atlas (read with texelFetch)

// PCSS's largest search and filter radius, texels (its searches take at most 7 x 7 taps)
#define LG_PCSS_MAX_RADIUS 16

// What is the same for the whole pass, uploaded in one call from the C struct that mirrors
// it (ph_gpu_frame in plugins/phong/phong.c, std140, 144 bytes). No instance name: the
// members read as plain uniforms.
layout(std140, binding = 1) uniform PhFrame {
    mat4 u_view_proj;         // projection (Y flipped, the image row rule) * view
    vec3 u_eye;               // the camera's position, world
    int u_n_lights;
    vec3 u_view_dir_inf;      // V for a viewer at infinity: unit, towards the camera
    int u_viewer_local;       // 1: V = normalize(eye - P)
    vec3 u_ambient;           // Ia
    int u_depth_cue;          // 1: light terms divided by (r + K), eq. 1-12
    float u_K;
    int u_spec_model;         // LG_SPEC_PHONG or LG_SPEC_BLINN
    float u_n_scale;          // n' = n * u_n_scale (Blinn's exponent correction: 1 or 4)
    float u_mixed_cos;        // cos(mixed_threshold_deg) (phong.geom)
    int u_shadow_res;         // tile side, texels
    float u_bias_const;       // depth units
    float u_bias_slope;       // depth units per unit of tan(angle(N, L))
    float u_normal_offset;    // texels
    int u_pcf_radius;         // percentage-closer filtering: (2 r + 1)^2 taps
    float u_pcss_light_size;  // > 0: PCSS, the light's diameter (m; directional: rad)
};

// The mesh's material: set per mesh between the draws of one pass (uniforms, not a block:
// rewriting a buffer that the pass's earlier draws read makes llvmpipe finish them first).
uniform float u_ka, u_kd, u_ks, u_shininess;
uniform vec3 u_od, u_os;
uniform int u_double_sided;     // 1: back faces are lit with the normal turned towards V

LgPhongMaterial lg_material()
{
    LgPhongMaterial m;
    m.ka = u_ka;
    m.kd = u_kd;
    m.ks = u_ks;
    m.n = u_shininess;
    m.od = u_od;
    m.os = u_os;
    return m;
}

vec3 lg_view_vector(vec3 P)
{
    return u_viewer_local != 0 ? lg_safe_normalize(u_eye - P, u_view_dir_inf) : u_view_dir_inf;
}

// Eq. 1-12's factor at P: r is the distance from P to the camera, for either viewer model.
float lg_cue(vec3 P)
{
    return u_depth_cue != 0 ? lg_depth_cue(distance(u_eye, P), u_K) : 1.0;
}

#ifdef LG_TAU
// The medium's shadow on surfaces (plugins/phong/README.md, "Shadows of the medium"): only
// in the variant the node compiles for a scene whose medium has a density field (the
// plugin then defines LG_TAU); every other scene runs the code above and below unchanged.
// Each light's optical-depth volume (plugins/volumetric_common vol_tau_build: tau at the
// nodes of an n.x x n.y x n.z lattice over the box [u_tau_lo, u_tau_hi], the integral of
// the density multiplier from the node towards the light, to the light or out of the box),
// the lights' volumes stacked along z in light order, sampled linearly.
layout(binding = 3) uniform sampler3D u_tau;
uniform vec3 u_tau_lo, u_tau_hi;
uniform ivec3 u_tau_n;
uniform vec3 u_sigma_t; // density x (scattering + absorption), 1 / scene unit

// Light i's optical depth at q (inside the box): trilinear between the lattice's nodes, by
// the texture unit's linear filter (the volumes' node centres are its texel centres; x is
// clamped to light i's own layers, so no filter reaches a neighbour's), as vol_tau_sample
// does in double.
float lg_tau_at(int i, vec3 q)
{
    vec3 n1 = vec3(u_tau_n - 1);
    vec3 x = clamp((q - u_tau_lo) / (u_tau_hi - u_tau_lo) * n1, vec3(0.0), n1);
    vec3 uvw = (x + 0.5) / vec3(u_tau_n);
    uvw.z = (x.z + 0.5 + float(i * u_tau_n.z)) / float(u_tau_n.z * u_n_lights);
    return textureLod(u_tau, uvw, 0.0).r;
}

// The transmittance e^(-sigma_t tau) from P towards light i along the unit L, over the
// segment [0, d] (d: the light's distance; infinite for a light at infinity). The density
// is 0 outside the box (a bounded field's own box; an unbounded field counts inside the
// scene's bounds, as the froxel node's volumes do), so the segment's optical depth is the
// volume's value where the segment enters the box: exactly 1 when it misses the box (a
// point outside the medium's shadow is lit as without a medium, bit for bit).
vec3 lg_medium_transmittance(int i, vec3 P, vec3 L, float d)
{
    // the slabs' parameters; a zero component counts as 1e-20 of its sign (no inf - inf)
    vec3 s = vec3(L.x < 0.0 ? -1.0 : 1.0, L.y < 0.0 ? -1.0 : 1.0, L.z < 0.0 ? -1.0 : 1.0);
    vec3 inv = 1.0 / (s * max(abs(L), vec3(1e-20)));
    vec3 t0 = (u_tau_lo - P) * inv, t1 = (u_tau_hi - P) * inv;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    float te = max(max(tn.x, tn.y), max(tn.z, 0.0));
    float tx = min(min(tf.x, tf.y), min(tf.z, d));
    if (!(te < tx))
        return vec3(1.0);
    return exp(-u_sigma_t * lg_tau_at(i, P + L * te));
}
#endif

// The direction towards light i and the intensity arriving at P. False when no light
// arrives (beyond the range, outside the cone). A light exactly at P lights along N. With
// a density field (LG_TAU) Ii carries the medium's transmittance towards the light.
bool lg_light_at(int i, vec3 P, vec3 N, out vec3 L, out vec3 Ii)
{
    LgLight l = lg_lights[i];
    Ii = l.radiance;
    if (l.pos.w < 0.5) {
        L = l.dir.xyz;
#ifdef LG_TAU
        Ii *= lg_medium_transmittance(i, P, L, 3.0e38);
#endif
        return true;
    }
    vec3 d = l.pos.xyz - P;
    float dist = length(d);
    if (l.dir.w > 0.0 && dist > l.dir.w) {
        L = N;
        return false;
    }
    L = lg_safe_normalize(d, N);
    if (l.cone.z > 0.5)
        Ii /= max(dist * dist, 1e-12); // closer than 1 micrometre counts as 1 micrometre
    if (l.pos.w > 1.5) {
        // glTF KHR_lights_punctual's recommended spot falloff
        float t = clamp((dot(-L, l.dir.xyz) - l.cone.x) * l.cone.y, 0.0, 1.0);
        Ii *= t * t;
    }
#ifdef LG_TAU
    Ii *= lg_medium_transmittance(i, P, L, dist);
#endif
    return true;
}

// The depth test of one texel (eq. 4): 1 lit, 0 in shadow. An orthographic map compares
// window depths (d and the stored one) with the bias in depth units; a perspective map view
// depths, the stored window depth linearised, the bias times depth_range (world units: the
// rule of lightgraph/shadowmap.h and lg_shadowmap_visibility).
float lg_shadow_tap(LgShadow sh, ivec2 texel, float d, float bias)
{
    float stored = texelFetch(u_atlas, texel, 0).r;
    if (sh.projection == 0)
        return d > stored + bias ? 0.0 : 1.0;
    float zf = sh.znear + sh.depth_range;
    float lin = sh.znear * zf / (zf - stored * sh.depth_range);
    return d > lin + bias * sh.depth_range ? 0.0 : 1.0;
}

// The stored depth of one texel as a distance from the light along the map's axis (world;
// orthographic: from the map's near plane), for PCSS's blocker search.
float lg_shadow_depth_world(LgShadow sh, ivec2 texel)
{
    float stored = texelFetch(u_atlas, texel, 0).r;
    if (sh.projection == 0)
        return stored * sh.depth_range;
    float zf = sh.znear + sh.depth_range;
    return sh.znear * zf / (zf - stored * sh.depth_range);
}

// Shadow_L(P) of the light whose first map is s (eq. 4 with the bias rules of
// lightgraph/shadowmap.h and plugins/shadowmap/README.md, "Bias"): 1 lit, 0 in shadow, the
// fraction of lit taps with PCF. Ng is the unit geometric normal (the facet's) on the
// viewer's side. A point light's face is the one of the largest component of p - light
// (ties to the lower face: lg_shadowmap_record_at's rule). Points outside the map, or
// behind a perspective map's near plane, are lit; an orthographic depth is clamped to
// [0, 1], a perspective one to the far plane. Taps are clamped to the map's tile.
float lg_shadow(int s, vec3 P, vec3 Ng, vec3 L)
{
    if (s < 0)
        return 1.0;
    LgShadow sh = lg_shadows[s];
    bool persp = sh.projection != 0;
    float scale = persp ? distance(P, sh.light_pos) : 1.0;
    vec3 p = P + Ng * (u_normal_offset * sh.texel_world * scale);
    if (sh.n_faces == 6) {
        vec3 d = p - sh.light_pos, a = abs(d);
        int axis = 0;
        if (a.y > a.x)
            axis = 1;
        if (a.z > a[axis])
            axis = 2;
        sh = lg_shadows[s + 2 * axis + (d[axis] < 0.0 ? 1 : 0)];
    }
    vec4 c = sh.view_proj * vec4(p, 1.0);
    if (persp && !(c.w > 0.0))
        return 1.0;
    vec3 q = c.xyz / c.w;
    vec2 t = q.xy * 0.5 + 0.5;
    if (!(t.x >= 0.0 && t.x < 1.0 && t.y >= 0.0 && t.y < 1.0))
        return 1.0;
    float d;
    if (persp) {
        if (q.z < -1.0)
            return 1.0; // nearer to the light than its near plane
        d = min(c.w, sh.znear + sh.depth_range);
    } else {
        d = clamp(q.z * 0.5 + 0.5, 0.0, 1.0);
    }
    ivec2 tile = ivec2(sh.tile);
    ivec2 ct = min(ivec2(t * float(u_shadow_res)), ivec2(u_shadow_res - 1));
    // tan(angle(N, L)) with cos clamped to >= 0.1 (tan <= 9.95), as the shadowmap node
    // documents, so that grazing light keeps a finite bias
    float cl = clamp(abs(dot(Ng, L)), 0.1, 1.0);
    float tn = sqrt(1.0 - cl * cl) / cl;
    float bias = u_bias_const + u_bias_slope * tn;
    // A tap k texels beside the lookup's reads a planar receiver's own depth k texels away,
    // k texel tan(angle(N, L)) nearer the light (world units): each tap adds that to the bias
    // (in depth units), or PCF would shade slanted surfaces with stripes of acne
    float tap_slope = sh.texel_world * (persp ? d : 1.0) * tn / sh.depth_range;
    int r = u_pcf_radius;
    if (u_pcss_light_size > 0.0) {
        // PCSS (Fernando 2005): the blockers' mean distance db over the light's footprint,
        // then a penumbra of w = size (dr - db) / db (perspective; directional: the angle
        // times dr - db) at the receiver, as a PCF radius in texels (README.md)
        float dr = persp ? d : d * sh.depth_range;
        float texel = sh.texel_world * (persp ? d : 1.0);
        float reach = persp ? u_pcss_light_size * (dr - sh.znear) / dr * (d / sh.znear)
                            : u_pcss_light_size * dr;
        int rs = clamp(int(ceil(0.5 * reach / texel)), 1, LG_PCSS_MAX_RADIUS);
        int step = max(1, rs / 3);
        float sum = 0.0, cnt = 0.0;
        for (int y = -rs; y <= rs; y += step)
            for (int x = -rs; x <= rs; x += step) {
                ivec2 k = clamp(ct + ivec2(x, y), ivec2(0), ivec2(u_shadow_res - 1));
                if (lg_shadow_tap(sh, tile + k, d, bias + tap_slope * length(vec2(x, y))) < 0.5) {
                    sum += lg_shadow_depth_world(sh, tile + k);
                    cnt += 1.0;
                }
            }
        if (cnt == 0.0)
            return 1.0;
        float db = sum / cnt;
        float w = persp ? u_pcss_light_size * (dr - db) / max(db, 1e-6)
                        : u_pcss_light_size * (dr - db);
        r = clamp(int(round(0.5 * w / texel)), 0, LG_PCSS_MAX_RADIUS);
    }
    if (r == 0)
        return lg_shadow_tap(sh, tile + ct, d, bias);
    float lit = 0.0;
    for (int y = -r; y <= r; y++)
        for (int x = -r; x <= r; x++)
            lit += lg_shadow_tap(sh, tile + clamp(ct + ivec2(x, y), ivec2(0),
                                                  ivec2(u_shadow_res - 1)),
                                 d, bias + tap_slope * length(vec2(x, y)));
    float taps = float(2 * r + 1);
    return lit / (taps * taps);
}

// The unit vector from P towards light i (its direction for lights at infinity).
vec3 lg_light_dir(int i, vec3 P)
{
    LgLight l = lg_lights[i];
    return l.pos.w < 0.5 ? l.dir.xyz : lg_safe_normalize(l.pos.xyz - P, l.dir.xyz);
}

// Everything at P, shadows at P: ambient plus the attenuated, shadowed direct terms. N is
// the shading normal, Ng the geometric one (for the shadow test).
vec3 lg_shade(vec3 P, vec3 N, vec3 Ng, LgPhongMaterial m)
{
    vec3 V = lg_view_vector(P);
    float n_eff = m.n * u_n_scale;
    vec3 direct = vec3(0.0);
    for (int i = 0; i < u_n_lights; i++) {
        vec3 L, Ii;
        if (!lg_light_at(i, P, N, L, Ii))
            continue;
        vec3 c = lg_phong_direct(N, V, L, Ii, m, u_spec_model, n_eff);
        if (lg_lights[i].shadow >= 0 && any(greaterThan(c, vec3(0.0))))
            c *= lg_shadow(lg_lights[i].shadow, P, Ng, L);
        direct += c;
    }
    return lg_phong_ambient(u_ambient, m) + lg_cue(P) * direct;
}

// The same equation split for the per-vertex and per-facet modes, whose colours are
// interpolated (or held) across a facet while shadows stay per pixel: c0 holds the ambient
// and every light whose shadow is not tested per pixel, cs[k] the attenuated direct term of
// the k-th shadowed light in the lights' order (k < LG_SV), to be multiplied by that light's
// Shadow_L at the pixel. Shadowed lights beyond the first LG_SV have their shadow tested
// here (with N for the geometric normal, which a vertex does not have).
void lg_shade_split(vec3 P, vec3 N, LgPhongMaterial m, out vec3 c0, out vec3 cs[LG_SV_ARR])
{
    vec3 V = lg_view_vector(P);
    float n_eff = m.n * u_n_scale;
    float att = lg_cue(P);
    for (int k = 0; k < LG_SV_ARR; k++)
        cs[k] = vec3(0.0);
    vec3 direct = vec3(0.0);
    int ks = 0; // shadowed lights so far
    for (int i = 0; i < u_n_lights; i++) {
        int s = lg_lights[i].shadow;
        int k = s >= 0 ? ks++ : -1;
        vec3 L, Ii;
        if (!lg_light_at(i, P, N, L, Ii))
            continue;
        vec3 c = lg_phong_direct(N, V, L, Ii, m, u_spec_model, n_eff);
        if (k >= 0 && k < LG_SV) {
            cs[k] = att * c;
            continue;
        }
        if (s >= 0 && any(greaterThan(c, vec3(0.0))))
            c *= lg_shadow(s, P, N, L);
        direct += c;
    }
    c0 = lg_phong_ambient(u_ambient, m) + att * direct;
}

// The largest cos(angle(V, R)) over the lights at P (for the mixed mode's highlight facets);
// -2 when no light reaches the lit side of P.
float lg_max_cos_vr(vec3 P, vec3 N)
{
    vec3 V = lg_view_vector(P);
    float best = -2.0;
    for (int i = 0; i < u_n_lights; i++) {
        vec3 L, Ii;
        if (!lg_light_at(i, P, N, L, Ii) || dot(N, L) <= 0.0 || all(lessThanEqual(Ii, vec3(0.0))))
            continue;
        best = max(best, dot(reflect(-L, N), V));
    }
    return best;
}
