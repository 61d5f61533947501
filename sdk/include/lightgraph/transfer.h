/*
 * lightgraph/transfer.h: per-vertex PRT transfer vectors (LG_KIND_TRANSFER), since ABI
 * 2.0. For every vertex of a scene, n^2 coefficients per colour channel (the albedo folded
 * in) whose dot product with the lighting's coefficients (lightgraph/shcoeffs.h) is the
 * vertex's exit radiance.
 *
 * Parts (lightgraph/kinds.h):
 *
 *   transfer  buffer: float[vertices][3][n^2]: for each vertex, the R plane, then G, B
 *   info      meta: lg_transfer_info
 *
 * Vertices are numbered as the scene's meshes list them, mesh 0 first (mesh m's vertex v
 * is vertex offset(m) + v, offset(m) the sum of the vertex counts of meshes 0 .. m-1);
 * instances share their mesh's vectors (transfer is computed in the mesh's frame of its
 * first instance).
 */
#ifndef LIGHTGRAPH_TRANSFER_H
#define LIGHTGRAPH_TRANSFER_H

#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/host.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lg_transfer_mode {
    LG_TRANSFER_UNSHADOWED = 1,
    LG_TRANSFER_SHADOWED,
    LG_TRANSFER_INTERREFLECTED,
} lg_transfer_mode;

/* The `info` part. */
typedef struct lg_transfer_info {
    uint32_t struct_size; /* sizeof(lg_transfer_info) */
    uint32_t bands;       /* n */
    uint32_t vertices;
    lg_transfer_mode mode;
    uint32_t bounces; /* LG_TRANSFER_INTERREFLECTED: bounces computed */
    uint32_t reserved[11];
} lg_transfer_info;

typedef struct lg_transfer {
    lg_transfer_info info;
    uint32_t n_coeffs;           /* bands^2 */
    const lg_resource *transfer; /* map it on the device of choice */
    void *reserved[4];
} lg_transfer;

/*
 * Per-vertex values as an image (since ABI 2.3). A node that computes one RGB value per
 * vertex (the `prt` node's exit radiance, `prt_reference`'s oracle) publishes it as an
 * ordinary rgba32f image output named `vertices`, so that every device maps it, the host
 * moves it, and `output NODE.vertices "file.exr"` writes it like any image:
 *   vertex i (numbered as above) is texel (i mod LG_VERTEX_IMAGE_WIDTH,
 *   i / LG_VERTEX_IMAGE_WIDTH), RGB its value and alpha 1; texels past the last vertex are
 *   (0, 0, 0, 0). The image is LG_VERTEX_IMAGE_WIDTH wide (lg_vertex_image_size).
 */
#define LG_VERTEX_IMAGE_WIDTH 1024u

/* The size of a per-vertex image holding `vertices` values (at least 1 x 1). */
static inline void lg_vertex_image_size(uint32_t vertices, uint32_t *width, uint32_t *height)
{
    *width = LG_VERTEX_IMAGE_WIDTH;
    *height = vertices ? (vertices + LG_VERTEX_IMAGE_WIDTH - 1u) / LG_VERTEX_IMAGE_WIDTH : 1u;
}

/* Producer, prepare(): declares output `port` for `vertices` vertices of `bands` bands. */
LG_API int lg_transfer_declare(lg_node *node, uint32_t port, uint32_t bands, uint32_t vertices);
/* Producer, execute(): writes the info part (bands and vertices as declared). */
LG_API int lg_transfer_publish(lg_node *node, uint32_t port, const lg_transfer_info *info);
/* Consumer: fills *out and returns it; NULL without an error for NULL or neutral, NULL
 * after lg_error for another kind or inconsistent parts. */
LG_API const lg_transfer *lg_transfer_get(lg_node *node, const lg_resource *res, lg_transfer *out);

#ifdef __cplusplus
}
#endif
#endif
