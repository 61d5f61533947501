/*
 * Test plugin "testvolscene": the scene of the volumetric_reference tests
 * (test_volumetric_reference.c), built in memory so that every distance is known.
 *
 *   test_vol_scene -> scene
 *
 * One square of half-edge `half` (two triangles) in the plane z = 0, facing +Z; one camera
 * at (0, 0, 5) looking at the origin down -Z, up +Y, 40 degrees vertical field of view,
 * znear 0.1, zfar 50, aspect from the image. No light and no medium: the graph adds them
 * with scene_tools' `light` and `medium`.
 */
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

typedef struct tv_scene {
    lg_scene s;
    lg_mesh mesh;
    float pos[12], nrm[12];
    uint32_t idx[6];
    lg_instance instance;
    lg_material material;
    lg_camera camera;
} tv_scene;

static void tv_free(void *p) { free(p); }

static int tv_prepare(lg_node *n)
{
    double h = lg_param_float(n, "half");
    if (!(h > 0.0 && h < 1e6))
        return lg_error(n, "half = %g: must be in (0, 1e6)", h);
    tv_scene *t = calloc(1, sizeof *t);
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    t->s.struct_size = sizeof t->s;
    t->s.source = "test_vol_scene";
    t->s.meshes = &t->mesh;
    t->s.n_meshes = 1;
    t->s.instances = &t->instance;
    t->s.n_instances = 1;
    t->s.materials = &t->material;
    t->s.n_materials = 1;
    t->s.cameras = &t->camera;
    t->s.n_cameras = 1;
    t->material.name = "test";
    t->material.kd = 1.0f;
    t->material.od[0] = t->material.od[1] = t->material.od[2] = 0.5f;
    for (int c = 0; c < 4; c++)
        t->material.base_color[c] = 1.0f;
    lg_camera *c = &t->camera;
    c->name = "test";
    c->position[2] = 5.0f;
    c->up[1] = 1.0f;
    c->yfov = (float)(40.0 * LG_PI / 180.0);
    c->znear = 0.1f;
    c->zfar = 50.0f;
    static const float corner[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    for (int v = 0; v < 4; v++) {
        t->pos[3 * v] = (float)h * corner[v][0];
        t->pos[3 * v + 1] = (float)h * corner[v][1];
        t->pos[3 * v + 2] = 0.0f;
        t->nrm[3 * v + 2] = 1.0f;
    }
    static const uint32_t tri[6] = { 0, 1, 2, 0, 2, 3 };
    memcpy(t->idx, tri, sizeof tri);
    t->mesh.name = "test square";
    t->mesh.positions = t->pos;
    t->mesh.normals = t->nrm;
    t->mesh.indices = t->idx;
    t->mesh.n_vertices = 4;
    t->mesh.n_indices = 6;
    lg_m4_identity(t->instance.model);
    lg_m4_normal_matrix(t->instance.normal_matrix, t->instance.model);
    lg_test_scene_bounds(&t->s, &t->mesh);
    lg_scene_compute_features(&t->s);
    return n->host->declare_payload(n, 0, LG_KIND_SCENE, &t->s.features, &t->s, tv_free);
}

static int tv_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const lg_param_desc tv_params[] = {
    { .key = "half", .type = LG_PARAM_FLOAT, .def.f = 1.0, .min = 0, .max = 1e6,
      .doc = "half the square's edge" },
};
static const lg_port_desc tv_out[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the square and the camera" },
};
static const lg_node_type tv_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_vol_scene",
        .doc = "A square in z = 0 seen from (0, 0, 5) (volumetric_reference tests)",
        LG_PARAMS(tv_params),
        LG_OUTPUTS(tv_out),
        .prepare = tv_prepare,
        .execute = tv_nothing,
    },
};

LG_PLUGIN_DEFINE("testvolscene", "1.0.0", "The volumetric_reference tests' scene", tv_types)
