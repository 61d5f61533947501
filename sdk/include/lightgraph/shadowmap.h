/*
 * lightgraph/shadowmap.h: the shadow-map resource (LG_KIND_SHADOWMAP), since ABI 1.1.
 *
 * A shadow-map node renders one depth map per directional light of a scene (TECHNIQUES.md
 * §2; seed 2, 2.1.2-2.1.3) into tiles of one depth-only atlas image (LG_IMAGE_DEPTH_ONLY, a
 * host-managed resource: consumers map it on GL, CL or the CPU like any image), and
 * publishes, as a plugin-owned payload on its first output, where each light's tile is and
 * the light's matrices:
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
 * without a payload: lg_shadowmap_get() returns NULL for it, and consumers light without
 * shadows.
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

typedef struct lg_shadow_light {
    uint32_t light;            /* index into the scene's lights */
    float view[16];            /* world -> light view, column-major */
    float proj[16];            /* light view -> clip (orthographic for directional lights) */
    float view_proj[16];       /* proj * view */
    uint32_t tile_x, tile_y;   /* the tile's top-left texel in the atlas */
    float texel_world;         /* world-space size of one texel (for normal offsets) */
    float depth_range;         /* world-space depth covered by [0,1] */
    void *reserved[4];
} lg_shadow_light;

typedef struct lg_shadowmap {
    size_t struct_size;        /* sizeof(lg_shadowmap) */
    uint32_t resolution;       /* tile side, texels */
    uint32_t n_lights;
    const lg_shadow_light *lights;
    const lg_resource *atlas;  /* the depth-only atlas image (the node's second output) */
    uint32_t atlas_width, atlas_height;
    float bias_constant;       /* depth units, added to the stored depth in the test */
    float bias_slope;          /* multiplied by tan(angle between N and L), depth units */
    float normal_offset;       /* texels: the lookup point moves along N by this many */
    void *reserved[8];
} lg_shadowmap;

/* The shadow maps on `res`; NULL without an error for an unconnected input (res NULL) or
 * a gated node's neutral result, NULL after lg_error for another kind of resource. */
LG_API const lg_shadowmap *lg_shadowmap_get(lg_node *node, const lg_resource *res);

#ifdef __cplusplus
}
#endif
#endif
