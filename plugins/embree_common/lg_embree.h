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
 */
#ifndef LG_EMBREE_COMMON_H
#define LG_EMBREE_COMMON_H

#include <stddef.h>

#include <embree3/rtcore.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"

typedef struct lg_embree {
    RTCDevice dev;
    RTCScene scene;  /* committed: trace it from any thread */
    double extent;   /* the largest side of the world bounds of every vertex (0 when
                      * there is none) */
    size_t bytes;    /* the geometry buffers Embree holds (the BVH comes on top:
                      * about 1.5x for a high-quality build, not reported) */
    char error[256]; /* the first error Embree reported (its callback) */
} lg_embree;

/* Builds *e from scene s; the device runs lg_cpu_workers(node) threads. Errors (reported
 * on the node, *e then holds what was made: free it): no device, backface culling, an
 * instance naming a missing mesh, a mesh without positions or indices, an index past its
 * mesh's vertices, a world position that is not finite, an Embree error. Returns 0 or an
 * LG_ERR_*. */
int lg_embree_make(lg_node *node, const lg_scene *s, lg_embree *e);

/* Releases the scene and the device; zeroes *e (a zeroed *e is fine). */
void lg_embree_free(lg_embree *e);

/* lg_embree_make with the instances of an animated scene posed at `time` seconds
 * (lg_scene_pose; a static scene is built as it is). Rebuilt per frame by the caller. */
int lg_embree_make_at(lg_node *node, const lg_scene *s, double time, lg_embree *e);

#endif
