/*
 * plugins/volumetric_common: what the four volumetric plugins share (volumetric_screen,
 * volumetric_polygonal, volumetric_froxel, volumetric_reference; TECHNIQUES.md §6). A
 * static library linked into each, not part of the SDK: the media maths itself is public
 * (lightgraph/medium.h); this is the plumbing around it.
 *
 * Ports, the same on every volumetric node (vol_input_*, vol_output_*):
 *   inputs   0 scene     the scene: its lights, its medium, its active camera
 *            1 base      the lit image with its depth (phong's `out`): rgba + GL window
 *                        depth in [0, 1], 1 where nothing was drawn (sky)
 *            2 shadows   a shadow map of the same lights (methods that use one)
 *   outputs  0 out       rgba32f + depth: base x T + L_v (T = e^(-sigma_t d) where the
 *                        method models extinction, else 1), depth = base's
 *            1 inscatter rgba32f: L_v alone, alpha 1
 * Gated (no medium with density > 0, or no light): `out` is `base` itself,
 * `inscatter` black (LG_NEUTRAL_PASSTHROUGH_FIRST, neutral_input 1).
 *
 * The view ray. Pixel (x, y) of a W x H image (row 0 at the top, as every image here) has
 * its centre at (x + 0.5, y + 0.5); NDC = (2 (x + 0.5) / W - 1, 2 (y + 0.5) / H - 1,
 * 2 depth - 1) unprojected by the inverse of the camera's view_proj (lg_scene_view_make,
 * the camera phong used for the same size). The ray starts at the eye; w = its unit
 * direction. The medium fills the scene and ends at view depth z_limit (planar, along the
 * camera's forward axis): along the ray the fog spans [0, d], d = min(distance to the
 * surface, z_limit / dot(w, forward)); a sky pixel (depth 1) integrates to z_limit.
 */
#ifndef LG_VOL_COMMON_H
#define LG_VOL_COMMON_H

#include <stdbool.h>
#include <stdint.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/scene_gl.h"
#include "lightgraph/shadowmap.h"

#define VOL_MAX_LIGHTS 32

enum { VOL_IN_SCENE = 0, VOL_IN_BASE = 1, VOL_IN_SHADOWS = 2 };
enum { VOL_OUT_OUT = 0, VOL_OUT_INSCATTER = 1 };

/* What a method takes (vol_setup_make's `accept`): the light types it models and whether it
 * takes a heterogeneous medium (lg_medium.field). A light of a type not accepted is left
 * out with a warning; a field not accepted is an error. */
enum {
    VOL_ACCEPT_DIRECTIONAL = 1u << 0,
    VOL_ACCEPT_POINT = 1u << 1,
    VOL_ACCEPT_SPOT = 1u << 2,
    VOL_ACCEPT_FIELD = 1u << 3,
    VOL_ACCEPT_LIGHTS = VOL_ACCEPT_DIRECTIONAL | VOL_ACCEPT_POINT | VOL_ACCEPT_SPOT,
};

typedef struct vol_light {
    float dir[3];         /* unit: the direction the light travels (directional; a spot's
                           * axis; unused for a point light) */
    float l_c[3];         /* colour x intensity */
    uint32_t scene_index; /* in lg_scene.lights */
    int32_t shadow;       /* its first record in the shadow map's lights, or -1 (unshadowed):
                           * lg_shadowmap_record_at picks a point light's face */
    /* since issue 25 */
    lg_light_type type;
    float pos[3];               /* point, spot: world position */
    float range;                /* point, spot: 0 = infinite (lg_light_window) */
    float cos_inner, cos_outer; /* spot: the cone's cosines (lg_spot_cone) */
} vol_light;

typedef struct vol_setup {
    uint32_t width, height;   /* of base (and of both outputs) */
    lg_scene_view view;       /* the camera, as phong drew base */
    double inv_view_proj[16]; /* column-major */
    double eye[3], forward[3];
    float z_limit;                /* view depth where the fog ends (> 0) */
    float sigma_s[3], sigma_t[3]; /* 1 / scene unit; times lg_medium_field_at with a field */
    float g;                      /* Henyey-Greenstein anisotropy */
    uint32_t n_lights;            /* accepted lights, 1 .. VOL_MAX_LIGHTS, in scene order */
    vol_light lights[VOL_MAX_LIGHTS];
    /* since issue 25 */
    lg_medium medium;                 /* the scene's medium (its field pointer lives as long as the
                                       * scene) */
    bool heterogeneous;               /* medium.field != NULL (only with VOL_ACCEPT_FIELD) */
    float scene_min[3], scene_max[3]; /* the scene's bounds */
} vol_setup;

/* Fills *out from the scene (its lights of the accepted types, in scene order; its medium;
 * its active camera for a width x height image) and the shadow map (NULL: every light
 * unshadowed; a light the map lacks is unshadowed, with a warning). z_limit <= 0 means the
 * camera's zfar. Errors (reported on the node): more than VOL_MAX_LIGHTS accepted lights,
 * none, a light whose position, direction, range or cone is not finite, a heterogeneous
 * medium without VOL_ACCEPT_FIELD, a camera lg_scene_view_make refuses, a singular matrix. */
int vol_setup_make(lg_node *node, const lg_scene *scene, uint32_t width, uint32_t height,
                   float z_limit, const lg_shadowmap *shadows, unsigned accept, vol_setup *out);

/* The lights of the accepted types the scene on the node's input 'scene' declares (its
 * features), within 1 .. VOL_MAX_LIGHTS: what the work estimates of prepare() count
 * (vol_setup_make refuses the scenes outside that range when the node runs). */
uint32_t vol_scene_lights(lg_node *node, unsigned accept);

/* Light k's F(p) (lightgraph/medium.h: 1 for directional, W C / (d^2 + eps^2) for point and
 * spot) with the unit direction towards the light and the distance (INFINITY for a
 * directional light). Multiply by l_c, the shadow and, in a medium, the transmittance
 * towards the light (vol_light_transmittance). */
double vol_light_falloff(const vol_light *l, const double p[3], double to_light[3], double *dist);

/* The medium's transmittance from p towards light l, channel c, in a homogeneous medium:
 * e^(-sigma_t d) for a point or spot light at distance d, 1 for a directional light (the
 * medium's boundary towards it is not modelled, lightgraph/medium.h). */
double vol_light_transmittance(const vol_setup *v, const vol_light *l, double dist, int c);

/* The density multiplier at p (lg_medium_field_at; 1 homogeneous). */
double vol_density(const vol_setup *v, const double p[3]);

/* A light's optical-depth volume in a heterogeneous medium: for each cell centre x of an
 * n[0] x n[1] x n[2] grid over the box [lo, hi] (a bounded field's own box, else the scene's,
 * world), tau[x] = integral of m (the density multiplier) along the segment from x towards
 * the light, to the light (point, spot) or out of the box (directional); the transmittance
 * is then e^(-sigma_t tau) per channel. Built on the CPU by marching the field in steps of
 * half a cell with the midpoint rule, made once per scene and light and kept. Sampled
 * trilinearly (vol_tau_sample), clamped to the box (a point outside reads its nearest
 * cell). The froxel node's "per-light extinction volume" (lightgraph issue 25). */
typedef struct vol_tau_volume {
    uint32_t n[3];
    double lo[3], hi[3];
    float *tau; /* n[0] n[1] n[2], x fastest; owned (vol_tau_free) */
} vol_tau_volume;

/* Builds light k's volume at `res` cells along the box's longest side (the others in
 * proportion, at least 2). The memory is counted on the node. 0 or an LG_ERR_*. */
int vol_tau_build(lg_node *node, const vol_setup *v, uint32_t k, uint32_t res, vol_tau_volume *out);
/* The same for one light outside a vol_setup (the phong node's lights: any number, any
 * camera): the box from `medium`'s field and the scene's bounds [scene_min, scene_max]
 * (tau_box's rule above), light l's type, direction (directional: dir, the direction the
 * light travels) or position (point, spot). The cells are marched over the host's threads
 * (lg_parallel_for, a z layer per chunk: the same bits on any number of threads). */
int vol_tau_build_light(lg_node *node, const lg_medium *medium, const float scene_min[3],
                        const float scene_max[3], const vol_light *l, uint32_t res,
                        vol_tau_volume *out);
void vol_tau_free(lg_node *node, vol_tau_volume *t);
double vol_tau_sample(const vol_tau_volume *t, const double p[3]);

/* Unit direction of the view ray through image point (x, y) (continuous image coordinates:
 * pixel centres at i + 0.5). */
void vol_ray(const vol_setup *v, double x, double y, double dir[3]);
/* vol_ray's rays for a device in float: the column-major matrix m (made in double) with
 * m (ndc_x, ndc_y, 0, 1) = (P - eye) r_w, P the point vol_ray unprojects and r_w > 0 its
 * homogeneous w; normalize(r.xyz / r.w) is the ray to float rounding (the float difference
 * P - eye is not: NDC z 0 lies millimetres from the eye, up to 8e-6 rad off). */
void vol_ray_matrix(const vol_setup *v, float m[16]);

/* Distance along the ray through (x, y) to the surface of window depth `depth`; INFINITY
 * for depth >= 1 (sky) or a depth that is not finite. */
double vol_surface_distance(const vol_setup *v, double x, double y, float depth);

/* The fog's extent along the ray through (x, y): min(surface distance, z_limit /
 * dot(w, forward)). */
double vol_fog_length(const vol_setup *v, double x, double y, float depth);

/* Eq. 4 without a slope term, for a point in the medium: the fraction of the map's PCF
 * taps in which world point p is lit by the light whose first record is `rec` (the face
 * that holds p for a point light). `atlas` is the CPU depth plane of the atlas (lg_map_cpu
 * on sm->atlas). Points outside the light's tile or in front of its near plane are lit.
 * lg_shadowmap_visibility's rule. */
float vol_shadow_cpu(const lg_shadowmap *sm, const float *atlas, int32_t rec, const double p[3]);

/* The common parts of prepare(): checks base (an image with depth), reads the scene,
 * declares `out` (rgba32f + depth) and `inscatter` (rgba32f) at base's size. */
int vol_declare_outputs(lg_node *node, uint32_t *width, uint32_t *height);

#endif
