/*
 * tests/common/testscene.h: what the test plugins that build an lg_scene in memory share
 * (testmeshscene, testphongscene, shadowprobe). Linked into those plugins as a static
 * library (lg_test_scene_dep in tests/meson.build).
 */
#ifndef LG_TEST_COMMON_TESTSCENE_H
#define LG_TEST_COMMON_TESTSCENE_H

#include "lightgraph/scene.h"

/* Sets each of meshes[0 .. s->n_meshes) bounds from its positions, then s's world bounds
 * from the eight corners of each instance's mesh bounds through the instance's model
 * matrix. `meshes` is s->meshes, writable. Instances of a mesh that does not exist are
 * passed over; with no instance the world bounds stay empty (+inf, -inf). */
void lg_test_scene_bounds(lg_scene *s, lg_mesh *meshes);

#endif
