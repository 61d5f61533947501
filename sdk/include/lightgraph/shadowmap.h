/*
 * lightgraph/shadowmap.h: the shadow-map resource (LG_KIND_SHADOWMAP), composite since
 * ABI 2.0 (lightgraph/kinds.h).
 *
 * A shadow-map node renders one depth map per directional light of a scene (TECHNIQUES.md
 * §2; seed 2, 2.1.2-2.1.3) into tiles of one depth-only atlas and publishes, beside it,
 * where each light's tile is and the light's matrices. Its parts:
 *
 *   atlas   image, LG_IMAGE_DEPTH_ONLY, atlas_width x atlas_height
 *   lights  buffer, lg_shadow_light[n_lights] (a std430 array: shaders may read it)
 *   info    meta, lg_shadowmap_info
 *
 * The test, for a world point p and light k:
 *
 *     p_clip  = view_proj * p_world            (orthographic: w = 1)
 *     p_tex   = p_clip.xy * 0.5 + 0.5          ([0,1] over the light's tile)
 *     texel   = tile origin + p_tex * resolution
 *     Shadow_L(p) = 0 if p_clip.z * 0.5 + 0.5 > Depth_L(texel) + bias, else 1     (eq. 4)
 *
 * Atlas rows follow the image row rule (lightgraph/host.h): texel row 0 is the atlas's top
 * row; p_tex.y = 0 is the tile's top row. Depth is window depth in [0,1] as GL writes it
 * (glClipControl default, glDepthRange 0..1), 1 where nothing was drawn.
 *
 * A gated shadow-map node (the scene has no directional light) yields a neutral resource
 * without parts: lg_shadowmap_get() returns NULL for it, and consumers light without
 * shadows. A graph reads the atlas alone as `NODE.atlas` (an image).
 */
#ifndef LIGHTGRAPH_SHADOWMAP_H
#define LIGHTGRAPH_SHADOWMAP_H

#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One light's map. Laid out as a std430 struct (matrices first, 16-byte multiple), so the
 * `lights` part can be bound as a shader storage buffer as it is. */
typedef struct lg_shadow_light {
    float view[16];          /* world -> light view, column-major */
    float proj[16];          /* light view -> clip (orthographic for directional lights) */
    float view_proj[16];     /* proj * view */
    uint32_t light;          /* index into the scene's lights */
    uint32_t tile_x, tile_y; /* the tile's top-left texel in the atlas */
    float texel_world;       /* world-space size of one texel (for normal offsets) */
    float depth_range;       /* world-space depth covered by [0,1] */
    uint32_t reserved[3];
} lg_shadow_light;

/* The `info` part. */
typedef struct lg_shadowmap_info {
    uint32_t struct_size; /* sizeof(lg_shadowmap_info) */
    uint32_t resolution;  /* tile side, texels */
    uint32_t n_lights;
    uint32_t atlas_width, atlas_height;
    float bias_constant; /* depth units, added to the stored depth in the test */
    float bias_slope;    /* multiplied by tan(angle between N and L), depth units */
    float normal_offset; /* texels: the lookup point moves along N by this many */
    uint32_t reserved[8];
} lg_shadowmap_info;

/* What a consumer sees (lg_shadowmap_get): the info, the lights mapped on the CPU, and
 * the atlas and lights parts to map on the device of its choice. */
typedef struct lg_shadowmap {
    uint32_t resolution;
    uint32_t n_lights;
    const lg_shadow_light *lights;  /* CPU copy of the lights part (host-owned) */
    const lg_resource *atlas;       /* the atlas part: lg_map_gl / _cl / _cpu it */
    const lg_resource *lights_part; /* the lights part, for binding on a GPU */
    uint32_t atlas_width, atlas_height;
    float bias_constant;
    float bias_slope;
    float normal_offset;
    void *reserved[8];
} lg_shadowmap;

/* Producer, prepare(): declares output `port` (of kind LG_KIND_SHADOWMAP) with an atlas of
 * atlas_width x atlas_height and room for n_lights lights (at least one record is kept,
 * so n_lights may be 0). */
LG_API int lg_shadowmap_declare(lg_node *node, uint32_t port, uint32_t atlas_width,
                                uint32_t atlas_height, uint32_t n_lights);
/* Producer, execute(): writes the info and lights parts (on the CPU; consumers on other
 * devices get copies on demand). info->n_lights records are read from `lights`. The atlas
 * is the caller's to render: lg_part(node, lg_output(node, port), "atlas"). */
LG_API int lg_shadowmap_publish(lg_node *node, uint32_t port, const lg_shadowmap_info *info,
                                const lg_shadow_light *lights);
/* Consumer, execute(): fills *out from `res` and returns out; NULL without an error for an
 * unconnected input (res NULL) or a gated node's neutral result; NULL after lg_error for
 * another kind of resource or inconsistent parts. The pointers in *out live as long as
 * the resource (until the node's execute returns, for safety). */
LG_API const lg_shadowmap *lg_shadowmap_get(lg_node *node, const lg_resource *res,
                                            lg_shadowmap *out);

#ifdef __cplusplus
}
#endif
#endif
