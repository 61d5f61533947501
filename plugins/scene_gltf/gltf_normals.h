/*
 * gltf_normals.h: vertex normals for triangle meshes that have none (README.md,
 * "Computed normals", says what they are exactly).
 *
 * smooth: each corner's normal is the sum, over the triangles around the corner's
 *         *position* (vertices with bit-identical positions are one point, so seams in
 *         the file's vertex list do not make creases), of facet normal x facet area x the
 *         triangle's interior angle at that point, taken only over the triangles whose
 *         facet normal is within crease_deg of the corner's own triangle; corners of one
 *         source vertex that end up with different normals become separate vertices.
 * flat:   every triangle gets three vertices of its own with its facet normal.
 *
 * Degenerate (zero-area or non-finite) triangles contribute nothing; a corner whose sum
 * is zero takes its triangle's facet normal, or (0, 0, 1) if that is undefined too. No
 * output is ever NaN.
 */
#ifndef LG_GLTF_NORMALS_H
#define LG_GLTF_NORMALS_H

#include <stdint.h>

/* A mesh with normals. Arrays are malloc'd; texcoords NULL when the input had none. */
typedef struct lg_nmesh {
    uint32_t n_vertices, n_indices;
    float *positions, *normals, *texcoords;
    uint32_t *indices;
} lg_nmesh;

/* Both read n_vertices positions (3 floats) and texcoords (2 floats, or NULL) and
 * n_indices indices (a triangle list, each < n_vertices), and fill *out. They return 0, or
 * LG_ERR_NOMEM (then *out holds nothing). */
int lg_normals_smooth(const float *positions, const float *texcoords, uint32_t n_vertices,
                      const uint32_t *indices, uint32_t n_indices, float crease_deg, lg_nmesh *out);
int lg_normals_flat(const float *positions, const float *texcoords, uint32_t n_vertices,
                    const uint32_t *indices, uint32_t n_indices, lg_nmesh *out);

void lg_nmesh_free(lg_nmesh *m);

#endif
