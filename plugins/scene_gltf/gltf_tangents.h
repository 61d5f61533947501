/*
 * gltf_tangents.h: per-vertex tangents for normal mapping (glTF TANGENT, lg_mesh.tangents).
 *
 * A tangent is 4 floats: xyz a unit vector orthogonal to the vertex normal, pointing along
 * increasing u of the texture coordinates, and w = +1 or -1, the side of the bitangent:
 * B = w (N x T) points up in the image, along *decreasing* v (glTF's v grows downwards and
 * its normal textures have +Y up; glTF 2.0 §3.7.2.1 and §3.9.3). README.md, "Tangents",
 * says how that was checked against a file's own tangents.
 */
#ifndef LG_GLTF_TANGENTS_H
#define LG_GLTF_TANGENTS_H

#include <stdint.h>

#include "gltf_normals.h"

/* Makes a file's tangents usable in place: xyz orthogonalised against the vertex normal
 * (Gram-Schmidt) and normalised, w made +1 or -1 (w < 0 gives -1, anything else +1). A
 * tangent that is zero or parallel to its normal is replaced by a unit vector orthogonal
 * to the normal. n_vertices x 4 floats, normals 3 per vertex. */
void lg_tangents_orthonormalize(float *tangents, const float *normals, uint32_t n_vertices);

/* Generates tangents by MikkTSpace's construction (Mikkelsen 2008, "Simulation of wrinkled
 * surfaces revisited"): each triangle's tangent and bitangent from its texture coordinate
 * derivatives, projected into each corner's normal plane and weighted by the corner's angle
 * there, summed over the corners that share a vertex (same position, normal and texture
 * coordinates, bit for bit) and the same handedness; then orthogonalised to the normal.
 * A vertex whose corners disagree in handedness (a mirrored UV seam) is split: the corners
 * of the second handedness get a new vertex (a copy of every attribute) and the index list
 * follows. Triangles with degenerate texture coordinates contribute nothing and take the
 * handedness of their vertices' other corners.
 *
 * m: the mesh (positions, normals, texcoords, indices; texcoords may be NULL when
 * uv_set is 1); *texcoords1 (may point to NULL) its TEXCOORD_1, reallocated with the mesh's
 * arrays when vertices are split; uv_set: the set whose derivatives define the tangents (0
 * or 1, that set must exist). On success *tangents is a malloc'd n_vertices x 4 array and
 * *n_split (may be NULL) the vertices added. Returns 0 or LG_ERR_NOMEM (the mesh is then
 * unchanged). */
int lg_tangents_generate(lg_nmesh *m, float **texcoords1, int uv_set, float **tangents,
                         uint32_t *n_split);

#endif
