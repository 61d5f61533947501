/*
 * lightgraph/froxel.h: the froxel volume (LG_KIND_FROXEL), since ABI 2.0: a 3D grid
 * aligned with a camera's frustum (x, y over the image, z over depth slices) holding, per
 * cell, in-scattered radiance (rgb) and transmittance (a), accumulated from the camera.
 *
 * Parts (lightgraph/kinds.h):
 *
 *   grid  volume (rgba16f or rgba32f), width x height x depth cells
 *   info  meta: lg_froxel_info: the slice map and the camera it was made for
 *
 * Slice maps (z in [0, depth] <-> view depth t, with exact inverses; TECHNIQUES.md §6):
 *   LG_FROXEL_UNIFORM_CLIP: slices uniform in clip depth, as the thesis does;
 *   LG_FROXEL_EXPONENTIAL:  t = near_offset + (far - near_offset) ^ (z / depth) style
 *                           exponential slices after a near offset, as production
 *                           engines do; lightgraph/medium.h holds the maps.
 */
#ifndef LIGHTGRAPH_FROXEL_H
#define LIGHTGRAPH_FROXEL_H

#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lg_froxel_slicing {
    LG_FROXEL_UNIFORM_CLIP = 1,
    LG_FROXEL_EXPONENTIAL,
} lg_froxel_slicing;

/* The `info` part. */
typedef struct lg_froxel_info {
    uint32_t struct_size; /* sizeof(lg_froxel_info) */
    uint32_t width, height, depth;
    lg_froxel_slicing slicing;
    float near, far;   /* view depths covered by the grid, scene units */
    float near_offset; /* LG_FROXEL_EXPONENTIAL: depth of the first slice's end */
    float view[16];    /* world -> view of the camera, column-major */
    float proj[16];    /* view -> clip */
    uint32_t reserved[8];
} lg_froxel_info;

typedef struct lg_froxel {
    lg_froxel_info info;
    const lg_resource *grid; /* map it on the device of choice */
    void *reserved[4];
} lg_froxel;

/* Producer, prepare(): declares output `port` with a grid of w x h x d cells of `format`
 * (LG_FORMAT_RGBA16F or LG_FORMAT_RGBA32F). */
LG_API int lg_froxel_declare(lg_node *node, uint32_t port, uint32_t width, uint32_t height,
                             uint32_t depth, lg_format format);
/* Producer, execute(): writes the info part (size as declared). */
LG_API int lg_froxel_publish(lg_node *node, uint32_t port, const lg_froxel_info *info);
/* Consumer: fills *out and returns it; NULL without an error for NULL or neutral, NULL
 * after lg_error for another kind or inconsistent parts. */
LG_API const lg_froxel *lg_froxel_get(lg_node *node, const lg_resource *res, lg_froxel *out);

#ifdef __cplusplus
}
#endif
#endif
