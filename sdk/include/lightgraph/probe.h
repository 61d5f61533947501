/*
 * lightgraph/probe.h: the light-probe resource (LG_KIND_PROBE), since ABI 2.0.
 *
 * An HDR environment (radiance arriving from every direction, linear, in the scene's
 * units) with its layout, a world rotation and an intensity scale. Its parts
 * (lightgraph/kinds.h):
 *
 *   radiance     image: 2D for LG_PROBE_LATLONG and LG_PROBE_ANGULAR, a cube
 *                (LG_IMAGE_CUBE, OpenGL's face order and orientation) for LG_PROBE_CUBE;
 *                level 0 is the environment, further levels (if any) a prefiltered chain
 *                whose meaning lg_probe_info.filter states
 *   solid_angle  optional buffer: float steradians per texel of level 0 (every face), in
 *                the radiance image's texel order; sums over the sphere to 4 pi
 *   info         meta: lg_probe_info
 *
 * Directions are world directions with +Y up. A texel's direction in the probe's own
 * frame, d_probe, maps to the world as d_world = rotation * d_probe.
 *
 *   lat-long: texel (i, j) of W x H, row 0 at the top, u = (i + 0.5)/W, v = (j + 0.5)/H,
 *     phi = 2 pi (u - 0.5), theta = pi v measured from +Y,
 *     d = (sin theta sin phi, cos theta, -sin theta cos phi): the centre looks along -Z,
 *     u = 0.75 along +X, the top row is +Y.
 *   angular (Debevec): the centre looks along -Z, up is +Y, radius r = theta / pi with
 *     theta the angle from -Z.
 *   cube: OpenGL's cube-map convention (major axis, then s/t per face as the GL
 *     specification's table 8.19 gives).
 */
#ifndef LIGHTGRAPH_PROBE_H
#define LIGHTGRAPH_PROBE_H

#include <stdbool.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lg_probe_layout {
    LG_PROBE_LATLONG = 1,
    LG_PROBE_ANGULAR,
    LG_PROBE_CUBE,
} lg_probe_layout;

/* What the levels above 0 hold. */
typedef enum lg_probe_filter {
    LG_PROBE_FILTER_NONE = 0,  /* a plain box-filtered mip chain (or no chain) */
    LG_PROBE_FILTER_GLOSSY,    /* level l prefiltered for a Phong lobe (lg_probe_info) */
} lg_probe_filter;

/* The `info` part. */
typedef struct lg_probe_info {
    uint32_t struct_size;      /* sizeof(lg_probe_info) */
    lg_probe_layout layout;
    float rotation[9];         /* probe -> world, column-major 3x3, orthonormal */
    float scale;               /* radiance multiplier already applied to the texels: 1 */
    lg_probe_filter filter;
    float exponent0;           /* LG_PROBE_FILTER_GLOSSY: Phong exponent of level 1 */
    float exponent_ratio;      /* ... each further level divides the exponent by this */
    uint32_t reserved[8];
} lg_probe_info;

/* What a consumer sees (lg_probe_get). */
typedef struct lg_probe {
    lg_probe_info info;
    const lg_resource *radiance;     /* map it on the device of choice */
    const lg_resource *solid_angle;  /* NULL when the producer made none */
    lg_image_desc radiance_desc;     /* its size, format, levels, cube flag */
    void *reserved[4];
} lg_probe;

/* Producer, prepare(): declares output `port` with a radiance image of description
 * `radiance` (a cube, LG_IMAGE_CUBE, for LG_PROBE_CUBE; 2D otherwise) and, if
 * with_solid_angle, the solid-angle table of its level 0. */
LG_API int lg_probe_declare(lg_node *node, uint32_t port, lg_probe_layout layout,
                            const lg_image_desc *radiance, bool with_solid_angle);
/* Producer, execute(): writes the info part. The radiance (and solid angles) are the
 * caller's to write through lg_part(). */
LG_API int lg_probe_publish(lg_node *node, uint32_t port, const lg_probe_info *info);
/* Consumer: fills *out and returns it; NULL without an error for NULL or neutral, NULL
 * after lg_error for another kind or inconsistent parts. */
LG_API const lg_probe *lg_probe_get(lg_node *node, const lg_resource *res, lg_probe *out);

#ifdef __cplusplus
}
#endif
#endif
