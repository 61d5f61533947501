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
#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

static int tv_prepare(lg_node *n)
{
    double h = lg_param_float(n, "half");
    if (!(h > 0.0 && h < 1e6))
        return lg_error(n, "half = %g: must be in (0, 1e6)", h);
    lg_ts_builder *b = lg_ts_begin("test_vol_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    lg_material *m = lg_ts_material(b, "test");
    m->kd = 1.0f;
    m->od[0] = m->od[1] = m->od[2] = 0.5f;
    for (int c = 0; c < 4; c++)
        m->base_color[c] = 1.0f;
    lg_ts_camera(b, "test", lg_v3(0, 0, 5), lg_v3(0, 0, 0), lg_v3(0, 1, 0),
                 (float)(40.0 * LG_PI / 180.0), 0.1f, 50.0f);
    /* a zero centre, so that z is +0 */
    const lg_vec3 centre = lg_v3(0, 0, 0), normal = lg_v3(0, 0, 1);
    lg_ts_mesh(b, "test square", 0);
    lg_ts_quad(b, &centre, lg_v3((float)h, 0, 0), lg_v3(0, (float)h, 0), &normal);
    lg_ts_instance(b, 0, NULL);
    return lg_ts_publish(n, 0, b);
}

static int tv_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const lg_param_desc tv_params[] = {
    { .key = "half",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 1e6,
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
