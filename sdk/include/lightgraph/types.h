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

/* What flows along an edge of the graph.
 *
 * Image, buffer and volume are host-managed single resources. Scene is a plugin-owned
 * payload (lightgraph/scene.h). Shadow map, probe, SH coefficients, transfer and froxel
 * are composite (since ABI 2.0): made of named parts (images, volumes, buffers and a small
 * metadata struct), each with its own residency on CPU, GL and CL; lightgraph/kinds.h
 * lists every kind's parts and the kind's own header documents them and its accessors. */
typedef enum lg_resource_kind {
    LG_KIND_ANY = 0,   /* inputs only: accepts every kind */
    LG_KIND_IMAGE,     /* 2D or cube, rgba, mip levels, optional depth (lg_image_desc) */
    LG_KIND_BUFFER,    /* bytes */
    LG_KIND_VOLUME,    /* 3D grid of rgba (lg_volume_desc) */
    LG_KIND_SCENE,     /* meshes, materials, lights, cameras, medium, with lg_scene_features */
    LG_KIND_SHADOWMAP, /* composite: depth atlas + per-light matrices (lightgraph/shadowmap.h) */
    LG_KIND_PROBE,     /* composite: environment radiance with its layout (lightgraph/probe.h) */
    LG_KIND_SH,        /* composite: SH coefficients, n bands x RGB (lightgraph/shcoeffs.h) */
    LG_KIND_TRANSFER,  /* composite: per-vertex PRT transfer, n^2 x RGB (lightgraph/transfer.h) */
    LG_KIND_FROXEL,    /* composite: froxel volume with its slice map (lightgraph/froxel.h) */
    LG_KIND_COUNT_
} lg_resource_kind;

/* What a part of a composite resource is (lightgraph/kinds.h). A part is itself a
 * resource of kind image, volume or buffer; META is a buffer of at most LG_META_MAX bytes
 * holding a plain struct (no pointers) that a kind's header defines. */
typedef enum lg_part_type {
    LG_PART_IMAGE = 1,
    LG_PART_VOLUME,
    LG_PART_BUFFER,
    LG_PART_META,
} lg_part_type;
#define LG_META_MAX 65536u

/* Pixel formats of images and volumes. Every format holds four channels, RGBA. */
typedef enum lg_format {
    LG_FORMAT_RGBA32F = 1, /* 4 x float, linear */
    LG_FORMAT_RGBA16F,     /* 4 x IEEE half, linear */
    LG_FORMAT_RGBA8,       /* 4 x unorm8; the encoding (sRGB or linear) is the producer's to say */
    LG_FORMAT_RGBE8,       /* since ABI 2.2: Ward's RGBE (the .hdr pixel): R, G, B mantissas
                            * and a shared exponent in A, 4 x uint8 (lg_rgbe_encode /
                            * lg_rgbe_decode; shaders/common/rgbe.glsl, rgbe.cl); linear
                            * radiance, decoded by its consumers (lightgraph/image.h) */
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
    LG_WRITE = 2, /* the previous content may be discarded */
    LG_READ_WRITE = 3,
};

/* What a scene holds that decides which effects have anything to do. Produced by scene
 * nodes, read by the planner (gating) and printed by --explain. */
typedef struct lg_scene_features {
    uint64_t triangles; /* rendered, instances counted */
    uint64_t vertices;
    uint32_t dir_lights;
    uint32_t point_lights;
    uint32_t other_lights;
    bool medium;   /* a participating medium with density > 0 */
    bool probe;    /* a light probe */
    bool specular; /* a material with a non-zero specular term */
    float medium_density;
    /* since ABI 2.2: materials whose reflectivity (lg_material.reflectivity) is not zero;
     * it takes the place of the first reserved word */
    uint32_t reflective_materials;
    /* since ABI 3.1, in the place of three reserved words (an anonymous union keeps the
     * layout): */
    union {
        uint32_t reserved[7];
        struct {
            uint32_t textures;         /* textures that the drawn materials sample */
            uint32_t masked_materials; /* drawn materials with alpha mode MASK or BLEND */
            uint32_t animated;         /* instances, lights and cameras an animation moves */
            /* since ABI 3.2, in the place of the next reserved word: 1 when the medium
             * (density > 0) has a density field (lg_medium.field: a grid, noise or height
             * fog), 0 for a homogeneous one. point_lights and other_lights (the spot
             * lights: the only other type) count the local lights. */
            uint32_t medium_field;
            uint32_t reserved_3_2[3];
        };
    };
} lg_scene_features;

#ifdef __cplusplus
}
#endif
#endif
