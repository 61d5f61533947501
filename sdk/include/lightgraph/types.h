/*
 * lightgraph/types.h: the small vocabulary every other header uses: error codes,
 * resource kinds, pixel formats, devices, access modes and scene features.
 */
#ifndef LIGHTGRAPH_TYPES_H
#define LIGHTGRAPH_TYPES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Results: 0 is success, a negative value is a failure whose reason has already been
 * reported (to the log callback, or through lg_error()). */
enum {
    LG_OK = 0,
    LG_ERR_INVALID = -22,     /* bad argument or bad input data */
    LG_ERR_NOMEM = -12,       /* allocation failed */
    LG_ERR_IO = -5,           /* a file could not be read or written */
    LG_ERR_UNSUPPORTED = -95, /* valid input that this build cannot handle */
    LG_ERR_DEVICE = -19,      /* a device (GL, CL) is unavailable or failed */
    LG_ERR_NOTFOUND = -2,     /* a file, key or name does not exist */
};

/* What flows along an edge of the graph. */
typedef enum lg_resource_kind {
    LG_KIND_ANY = 0,     /* inputs only: accepts every kind */
    LG_KIND_IMAGE,       /* 2D, rgba, optional depth plane (lg_image_desc) */
    LG_KIND_BUFFER,      /* bytes */
    LG_KIND_VOLUME,      /* 3D grid of rgba (lg_volume_desc) */
    LG_KIND_SCENE,       /* meshes, materials, lights, cameras, medium, with lg_scene_features */
    LG_KIND_SHADOWMAP,   /* depth maps with light matrices */
    LG_KIND_PROBE,       /* environment radiance with its layout */
    LG_KIND_SH,          /* spherical-harmonic coefficients */
    LG_KIND_VERTEX_ATTR, /* per-vertex attributes (e.g. PRT transfer vectors) */
    LG_KIND_COUNT_
} lg_resource_kind;

/* Pixel formats of images and volumes. Every format holds four channels, RGBA. */
typedef enum lg_format {
    LG_FORMAT_RGBA32F = 1, /* 4 x float, linear */
    LG_FORMAT_RGBA16F,     /* 4 x IEEE half, linear */
    LG_FORMAT_RGBA8,       /* 4 x unorm8; the encoding (sRGB or linear) is the producer's to say */
} lg_format;

/* Devices a node can run on and a resource can live on. */
typedef enum lg_device {
    LG_DEVICE_CPU = 1,
    LG_DEVICE_GL,
    LG_DEVICE_CL,
} lg_device;

/* Access modes for mapping a resource on a device. */
enum {
    LG_READ = 1,
    LG_WRITE = 2,      /* the previous content may be discarded */
    LG_READ_WRITE = 3,
};

/* What a scene holds that decides which effects have anything to do. Produced by scene
 * nodes, read by the planner (gating) and printed by --explain. */
typedef struct lg_scene_features {
    uint64_t triangles;      /* rendered, instances counted */
    uint64_t vertices;
    uint32_t dir_lights;
    uint32_t point_lights;
    uint32_t other_lights;
    bool medium;             /* a participating medium with density > 0 */
    bool probe;              /* a light probe */
    bool specular;           /* a material with a non-zero specular term */
    float medium_density;
    uint32_t reserved[8];
} lg_scene_features;

#ifdef __cplusplus
}
#endif
#endif
