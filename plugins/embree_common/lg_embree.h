/*
 * plugins/embree_common: the Embree 3 scene of an lg_scene, shared by the plugins that
 * cast rays on the CPU (prt_bake, volumetric_reference). A static library linked into
 * each, not part of the SDK (the SDK does not depend on Embree).
 *
 * The scene: every instance's mesh in world space (positions through the instance's model
 * matrix in double, stored as float), one triangle geometry per instance with geometry id
 * = the instance's index (a hit's geomID names the instance), build quality high, robust
 * intersection. Both faces of every triangle occlude: an Embree library built with
 * backface culling is refused (single-sided triangles would let light through from
 * behind). Instances whose mesh has no triangle get no geometry (their id stays unused).
 *
 * Alpha masks (since the scene's ABI 3.1 textures): an instance whose material's alpha mode
 * is LG_ALPHA_MASK, or LG_ALPHA_BLEND (treated as a mask at its alpha_cutoff: a shadow or
 * camera ray either passes or stops, there is no fractional transmittance), gets an
 * intersection and an occlusion filter function that rejects a hit where the surface has
 * no coverage (lg_embree_covers). Every query through the scene (rtcIntersect*,
 * rtcOccluded*) then goes through the mask's transparent texels and stops at its opaque
 * ones. Instances without a mask get no filter and cost what they cost before.
 */
#ifndef LG_EMBREE_COMMON_H
#define LG_EMBREE_COMMON_H

#include <stdbool.h>
#include <stddef.h>

#include <embree3/rtcore.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"

typedef struct lg_embree {
    RTCDevice dev;
    RTCScene scene;    /* committed: trace it from any thread */
    double extent;     /* the largest side of the world bounds of every vertex (0 when
                        * there is none) */
    size_t bytes;      /* the geometry buffers Embree holds (the BVH comes on top:
                        * about 1.5x for a high-quality build, not reported) */
    char error[256];   /* the first error Embree reported (its callback) */
    uint32_t n_masked; /* instances given an alpha-mask filter */
    void *masks;       /* per instance: what its filter reads (owned; lg_embree_free) */
} lg_embree;

/* Builds *e from scene s; the device runs lg_cpu_workers(node) threads. Errors (reported
 * on the node, *e then holds what was made: free it): no device, backface culling, an
 * instance naming a missing mesh, a mesh without positions or indices, an index past its
 * mesh's vertices, a world position that is not finite, an Embree error. Returns 0 or an
 * LG_ERR_*. */
int lg_embree_make(lg_node *node, const lg_scene *s, lg_embree *e);

/* Releases the scene and the device; zeroes *e (a zeroed *e is fine). */
void lg_embree_free(lg_embree *e);

/* Whether mesh `me` of scene `s` has a surface at the point (u, v) of its triangle `prim`
 * (Embree's barycentrics: p = (1-u-v) v0 + u v1 + v v2): true for a material that is
 * opaque, false where a masked (or blended) material's alpha, base_color[3] times the base
 * colour texture's alpha at the point's texture coordinates (interpolated from the
 * triangle's vertices, KHR_texture_transform applied, lg_scene_texture_sample), is below
 * its alpha_cutoff. A mesh whose mask reads a texture coordinate set it does not have
 * (texcoords NULL) counts as opaque; so does a triangle or index out of range (reported
 * when the scene is built). The filter functions call it; a caller that traces without
 * Embree (prt_bake's brute force) calls it on its own hits. Pure: safe from any thread. */
bool lg_embree_covers(const lg_scene *s, const lg_mesh *me, uint32_t prim, float u, float v);

/* Whether mesh `me`'s material makes lg_embree_covers ever answer false (a mask or blend
 * with a texture it can read, or a factor alpha below the cutoff): the meshes that get a
 * filter. */
bool lg_embree_mesh_masked(const lg_scene *s, const lg_mesh *me);

/* lg_embree_make with the instances of an animated scene posed at `time` seconds
 * (lg_scene_pose; a static scene is built as it is). Rebuilt per frame by the caller. */
int lg_embree_make_at(lg_node *node, const lg_scene *s, double time, lg_embree *e);

#endif
