/*
 * vdb_read.h: the `medium` node's reader of OpenVDB float grids, a C interface to a C++ shim
 * (vdb_read.cpp, built only when meson finds OpenVDB: ST_HAVE_OPENVDB).
 *
 * The node reads the file itself through lightgraph/file.h (regular files only, bounded by
 * a size cap) and hands the bytes here, so OpenVDB never opens a path: the shim parses them
 * from memory (openvdb::io::Stream). Every exception OpenVDB or the C++ library throws is
 * caught and becomes an error message; nothing escapes into C.
 *
 * The dense grid covers the chosen grid's active voxel bounding box (OpenVDB's
 * evalActiveVoxelBoundingBox) and holds every voxel's value in it, active or not (what
 * OpenVDB's samplers read). OpenVDB's voxel (i, j, k) has its centre at index point (i, j,
 * k) (cell-centred), as lightgraph/scene.h's lg_density_grid: dense voxel (a, b, c) is VDB
 * voxel bbox_min + (a, b, c), so index_to_world = the grid's transform x translate(bbox_min).
 */
#ifndef LG_SCENE_TOOLS_VDB_READ_H
#define LG_SCENE_TOOLS_VDB_READ_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct st_vdb_grid {
    uint32_t nx, ny, nz; /* dense voxels along x, y, z, each >= 1 */
    float *values;       /* nx ny nz, x fastest; malloc'd, the caller frees it */
    float max_value;     /* the largest value (>= 0) */
    float background;    /* the grid's background (>= 0): its value outside the active voxels */
    int32_t bbox_min[3]; /* the VDB index of dense voxel (0, 0, 0) */
    /* dense index -> world of the file (before the node's own translation and scale),
     * column-major affine */
    double index_to_world[16];
    char name[128]; /* the grid's name as read (truncated to fit) */
} st_vdb_grid;

/* Reads float grid `grid` (NULL or "": the first float grid in the file) from `len` bytes
 * of a .vdb file and makes it dense. Refused, with the reason in err (no file name: the
 * caller adds it): bytes that are not a VDB file, or a corrupt or truncated one; no grid of
 * that name (the message lists the file's grids and their types); a grid that is not a
 * float grid; a level set (its values are distances, not densities); an empty grid; a
 * transform that is not affine (a frustum) or is singular; more than max_voxels voxels in
 * the active bounding box; a background or a voxel value that is negative or not finite
 * (the message names the grid and the voxel's VDB index). Returns 0, or -1 with *out
 * zeroed. */
int st_vdb_read(const void *bytes, size_t len, const char *grid, uint64_t max_voxels,
                st_vdb_grid *out, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
