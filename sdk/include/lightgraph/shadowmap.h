/*
 * lightgraph/shadowmap.h: the shadow-map resource (LG_KIND_SHADOWMAP), composite since
 * ABI 2.0 (lightgraph/kinds.h).
 *
 * A shadow-map node renders depth maps of a scene's lights (TECHNIQUES.md §2; seed 2,
 * 2.1.2-2.1.3) into tiles of one depth-only atlas and publishes, beside it, where each
 * map's tile is and its matrices: one orthographic map per directional light, one
 * perspective map per spot light and six (a cube) or two (dual-paraboloid) per point light
 * since ABI 3.2 (lg_shadow_light.projection, .face). Its parts:
 *
 *   atlas   image, LG_IMAGE_DEPTH_ONLY, atlas_width x atlas_height
 *   lights  buffer, lg_shadow_light[n_lights] (a std430 array: shaders may read it; one
 *           record per map)
 *   info    meta, lg_shadowmap_info
 *
 * The test, for a world point p and light k:
 *
 *     p_clip  = view_proj * p_world            (orthographic: w = 1)
 *     p_ndc   = p_clip.xyz / p_clip.w          (perspective: w > 0 in front of the light;
 *                                               a paraboloid record's view_proj is its view,
 *                                               the projection is the paraboloid's, see
 *                                               plugins/shadowmap/README.md)
 *     p_tex   = p_ndc.xy * 0.5 + 0.5           ([0,1] over the light's tile)
 *     texel   = tile origin + p_tex * resolution
 *     Shadow_L(p) = 0 if p_ndc.z * 0.5 + 0.5 > Depth_L(texel) + bias, else 1     (eq. 4)
 *
 * On a perspective record (not a paraboloid) the same test is made on view depth, since
 * window depth is not linear in distance (a bias in depth units would grow with d^2): with
 * n = znear, f = znear + depth_range, d = p_clip.w (clamped to f) and D = Depth_L(texel),
 *
 *     Shadow_L(p) = 0 if d > n f / (f - D (f - n)) + bias depth_range, else 1
 *
 * so a bias keeps its meaning in world units (bias x depth_range metres) on every map; the
 * normal offset of a perspective record is normal_offset x texel_world x |p - light|.
 *
 * Atlas rows follow the image row rule (lightgraph/host.h): texel row 0 is the atlas's top
 * row; p_tex.y = 0 is the tile's top row. Depth is window depth in [0,1] as GL writes it
 * (glClipControl default, glDepthRange 0..1), 1 where nothing was drawn.
 *
 * A gated shadow-map node (the scene has no light; before ABI 3.2: no directional light)
 * yields a neutral resource without parts: lg_shadowmap_get() returns NULL for it, and
 * consumers light without shadows. A graph reads the atlas alone as `NODE.atlas` (an
 * image).
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
    float texel_world;       /* world-space size of one texel (for normal offsets); for a
                              * perspective map: at unit distance from the light (scale
                              * by the distance) */
    float depth_range;       /* world-space depth covered by [0,1] (orthographic); far -
                              * near (perspective) */
    /* Since ABI 3.2, in the place of the three reserved words (a 3.0/3.1 producer's zeros
     * read as an orthographic map of face 0, which is what it wrote): */
    union {
        uint32_t reserved[3];
        struct {
            uint32_t projection; /* LG_SHADOW_ORTHOGRAPHIC or LG_SHADOW_PERSPECTIVE */
            uint32_t face;       /* LG_SHADOW_FACE_*: which map of the light this is */
            float znear;         /* perspective: the near plane's distance, world */
        };
    };
} lg_shadow_light;

/* lg_shadow_light.projection */
enum { LG_SHADOW_ORTHOGRAPHIC = 0, LG_SHADOW_PERSPECTIVE = 1 };

/* lg_shadow_light.face. A directional light has one orthographic record (face 0); a spot
 * light one perspective record (face 0) whose frustum holds its outer cone; a point light
 * six consecutive perspective records of 90 degrees each, faces 0 .. 5 looking along +x,
 * -x, +y, -y, +z, -z from the light (a cube map's order), or two records
 * LG_SHADOW_FACE_PARABOLOID_FRONT/_BACK when the producer makes dual-paraboloid maps
 * (lg_shadowmap_info.point_mode). The records of one light are consecutive, in face order.
 * Since ABI 3.3 lg_shadowmap_get refuses dual-paraboloid records (and point_mode
 * LG_SHADOW_POINT_PARABOLOID) with an error: no producer makes them and no consumer's
 * lookup of them was tested; the values stay reserved. */
enum {
    LG_SHADOW_FACE_POS_X = 0,
    LG_SHADOW_FACE_NEG_X,
    LG_SHADOW_FACE_POS_Y,
    LG_SHADOW_FACE_NEG_Y,
    LG_SHADOW_FACE_POS_Z,
    LG_SHADOW_FACE_NEG_Z,
    LG_SHADOW_FACE_PARABOLOID_FRONT = 16,
    LG_SHADOW_FACE_PARABOLOID_BACK,
};

/* The `info` part. */
typedef struct lg_shadowmap_info {
    uint32_t struct_size; /* sizeof(lg_shadowmap_info) */
    uint32_t resolution;  /* tile side, texels */
    uint32_t n_lights;    /* records (maps), since 3.2 not lights: a point light has 6 or 2 */
    uint32_t atlas_width, atlas_height;
    float bias_constant; /* depth units, added to the stored depth in the test */
    float bias_slope;    /* multiplied by tan(angle between N and L), depth units */
    float normal_offset; /* texels: the lookup point moves along N by this many */
    /* Since ABI 3.2, in the place of four of eight reserved words: */
    union {
        uint32_t reserved[8];
        struct {
            /* percentage-closer filtering: a consumer averages the depth test over the
             * (2 r + 1)^2 texels centred on the lookup's texel (r = pcf_radius; 0 = one
             * texel, the 3.1 test), each tap clamped to the record's tile */
            uint32_t pcf_radius;
            /* > 0: percentage-closer soft shadows (PCSS): the light's size in world units
             * (directional: its angular diameter in radians); the PCF radius then follows
             * the blocker search (plugins/shadowmap/README.md) */
            float pcss_light_size;
            uint32_t point_mode; /* LG_SHADOW_POINT_CUBE or LG_SHADOW_POINT_PARABOLOID */
            uint32_t reserved_3_2[5];
        };
    };
} lg_shadowmap_info;

enum { LG_SHADOW_POINT_CUBE = 0, LG_SHADOW_POINT_PARABOLOID = 1 };

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
    /* Since ABI 3.2, in the place of reserved pointers (same size): the info's filter
     * settings. n_lights above counts records (a point light has six, or two). */
    union {
        void *reserved[8];
        struct {
            uint32_t pcf_radius;
            float pcss_light_size;
            uint32_t point_mode;
            uint32_t reserved_3_2;
        };
    };
} lg_shadowmap;

/* The first record of scene light `light` in *sm, or -1 when the map has none (the light
 * is then unshadowed). Since ABI 3.2. */
LG_API int32_t lg_shadowmap_find(const lg_shadowmap *sm, uint32_t light);

/* The record of the light whose first record is `first` that a world point p falls in: the
 * record itself for one-record lights; for a point light's cube the face whose axis is
 * the largest component of p - light position (ties to the lower face), for a
 * dual-paraboloid the front (z >= 0 in the first record's view space) or the back. -1 for
 * first < 0. Since ABI 3.2. */
LG_API int32_t lg_shadowmap_record_at(const lg_shadowmap *sm, int32_t first, const double p[3]);

/* Eq. 4 on the CPU with the map's filter: the fraction of the PCF kernel's taps in which p
 * is lit (1 lit, 0 shadowed), for scene light `light` (on a perspective record, on view
 * depth with the bias in world units, as above); `atlas` is the atlas's depth plane
 * (lg_map_cpu). bias_extra is added to the constant bias (a consumer's slope term). A point
 * outside every record, behind a perspective record's near plane or of a light without a
 * record is lit. PCSS is not applied here (plugins/shadowmap's own lookups do). Since ABI
 * 3.2; the reference the GPU lookups are tested against. */
LG_API float lg_shadowmap_visibility(const lg_shadowmap *sm, const float *atlas, uint32_t light,
                                     const double p[3], double bias_extra);

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
 * another kind of resource, inconsistent parts or (since ABI 3.3) a dual-paraboloid
 * record. The pointers in *out live as long as
 * the resource (until the node's execute returns, for safety). */
LG_API const lg_shadowmap *lg_shadowmap_get(lg_node *node, const lg_resource *res,
                                            lg_shadowmap *out);

#ifdef __cplusplus
}
#endif
#endif
