/*
 * plugins/volumetric_common: what the four volumetric plugins share (volumetric_screen,
 * volumetric_polygonal, volumetric_froxel, volumetric_reference; TECHNIQUES.md §6). A
 * static library linked into each, not part of the SDK: the media maths itself is public
 * (lightgraph/medium.h); this is the plumbing around it.
 *
 * Ports, the same on every volumetric node (vol_input_*, vol_output_*):
 *   inputs   0 scene     the scene: its directional lights, its medium, its active camera
 *            1 base      the lit image with its depth (phong's `out`): rgba + GL window
 *                        depth in [0, 1], 1 where nothing was drawn (sky)
 *            2 shadows   a shadow map of the same lights (methods that use one)
 *   outputs  0 out       rgba32f + depth: base x T + L_v (T = e^(-sigma_t d) where the
 *                        method models extinction, else 1), depth = base's
 *            1 inscatter rgba32f: L_v alone, alpha 1
 * Gated (no medium with density > 0, or no directional light): `out` is `base` itself,
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

typedef struct vol_light {
    float dir[3];         /* unit: the direction the light travels */
    float l_c[3];         /* colour x intensity */
    uint32_t scene_index; /* in lg_scene.lights */
    int32_t shadow;       /* its record in the shadow map's lights, or -1 (unshadowed) */
} vol_light;

typedef struct vol_setup {
    uint32_t width, height;   /* of base (and of both outputs) */
    lg_scene_view view;       /* the camera, as phong drew base */
    double inv_view_proj[16]; /* column-major */
    double eye[3], forward[3];
    float z_limit;                /* view depth where the fog ends (> 0) */
    float sigma_s[3], sigma_t[3]; /* 1 / scene unit */
    float g;                      /* Henyey-Greenstein anisotropy */
    uint32_t n_lights;            /* directional lights, 1 .. VOL_MAX_LIGHTS */
    vol_light lights[VOL_MAX_LIGHTS];
} vol_setup;

/* Fills *out from the scene (its directional lights, in scene order; its medium; its
 * active camera for a width x height image) and the shadow map (NULL: every light
 * unshadowed; a light the map lacks is unshadowed, with a warning). z_limit <= 0 means the
 * camera's zfar. Errors (reported on the node): more than VOL_MAX_LIGHTS directional
 * lights, no directional light, a camera lg_scene_view_make refuses, a singular matrix. */
int vol_setup_make(lg_node *node, const lg_scene *scene, uint32_t width, uint32_t height,
                   float z_limit, const lg_shadowmap *shadows, vol_setup *out);

/* The directional lights the scene on the node's input 'scene' declares (its features),
 * within 1 .. VOL_MAX_LIGHTS: what the work estimates of prepare() count (vol_setup_make
 * refuses the scenes outside that range when the node runs). */
uint32_t vol_scene_lights(lg_node *node);

/* Unit direction of the view ray through image point (x, y) (continuous image coordinates:
 * pixel centres at i + 0.5). */
void vol_ray(const vol_setup *v, double x, double y, double dir[3]);

/* Distance along the ray through (x, y) to the surface of window depth `depth`; INFINITY
 * for depth >= 1 (sky) or a depth that is not finite. */
double vol_surface_distance(const vol_setup *v, double x, double y, float depth);

/* The fog's extent along the ray through (x, y): min(surface distance, z_limit /
 * dot(w, forward)). */
double vol_fog_length(const vol_setup *v, double x, double y, float depth);

/* Eq. 4 without a slope term, for a point in the medium: 1 if world point p is lit by the
 * shadow map's light record `rec`, 0 if shadowed. `atlas` is the CPU depth plane of the
 * atlas (lg_map_cpu on sm->atlas). Points outside the light's tile or in front of its near
 * plane are lit. */
float vol_shadow_cpu(const lg_shadowmap *sm, const float *atlas, int32_t rec, const double p[3]);

/* The common parts of prepare(): checks base (an image with depth), reads the scene,
 * declares `out` (rgba32f + depth) and `inscatter` (rgba32f) at base's size. */
int vol_declare_outputs(lg_node *node, uint32_t *width, uint32_t *height);

#endif
