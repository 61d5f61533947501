/*
 * Test plugin "testphongscene": scenes with known geometry, material and camera built in
 * memory, without lights (the tests add them with scene_tools' `light` node), so that the
 * phong node's results can be computed by hand.
 *
 *   test_phong_scene  -> scene
 *
 * Layouts:
 *   cube     the unit cube (edge 1) at the origin: 24 vertices, face normals
 *   plane    a square of edge `size` at y = 0 facing +Y, `segments` x `segments` quads of two
 *            triangles each (segments = 1: one quad, two triangles)
 *   shadow   the plane (edge `size`) and, above it, a 1 x 1 occluder quad at y = 1 facing +Y
 *            (a second mesh), both with the one material
 *
 * One material (ka, kd, ks, shininess, od, os, double_sided from the parameters) and one
 * camera (camera_position, camera_target, camera_up, yfov_deg; znear 0.1, zfar 50).
 */
#include "lightgraph/lightgraph.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"

#include "common/testscene.h"

enum { TP_CUBE = 0, TP_PLANE, TP_SHADOW };

static lg_vec3 tp_vec(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? lg_v3((float)v->v[0], (float)v->v[1], (float)v->v[2]) : lg_v3(0, 0, 0);
}

static int tp_prepare(lg_node *n)
{
    lg_ts_builder *b = lg_ts_begin("test_phong_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    float size = (float)lg_param_float(n, "size");
    uint32_t segs = (uint32_t)lg_param_int(n, "segments");

    lg_material *m = lg_ts_material(b, "test");
    m->ka = (float)lg_param_float(n, "ka");
    m->kd = (float)lg_param_float(n, "kd");
    m->ks = (float)lg_param_float(n, "ks");
    m->shininess = (float)lg_param_float(n, "shininess");
    lg_vec3 od = tp_vec(n, "od"), os = tp_vec(n, "os");
    m->od[0] = m->base_color[0] = od.x, m->od[1] = m->base_color[1] = od.y;
    m->od[2] = m->base_color[2] = od.z;
    m->base_color[3] = 1.0f;
    m->os[0] = os.x, m->os[1] = os.y, m->os[2] = os.z;
    m->double_sided = lg_param_bool(n, "double_sided");

    lg_ts_camera(b, "test", tp_vec(n, "camera_position"), tp_vec(n, "camera_target"),
                 tp_vec(n, "camera_up"), (float)(lg_param_float(n, "yfov_deg") * LG_PI / 180.0),
                 0.1f, 50.0f);

    float h = 0.5f * size;
    lg_ts_mesh(b, "test mesh#0", 0);
    if (layout == TP_CUBE)
        lg_ts_unit_cube(b, true);
    else
        lg_ts_grid(b, lg_v3(0, 0, 0), lg_v3(h, 0, 0), lg_v3(0, 0, -h), segs);
    lg_ts_instance(b, 0, NULL);
    if (layout == TP_SHADOW) {
        lg_ts_mesh(b, "occluder#0", 0);
        lg_ts_grid(b, lg_v3(0, 1, 0), lg_v3(0.5f, 0, 0), lg_v3(0, 0, -0.5f), 1);
        lg_ts_instance(b, 1, NULL);
    }
    return lg_ts_publish(n, 0, b);
}

static int tp_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const char *const tp_layouts[] = { "cube", "plane", "shadow", NULL };

static const lg_param_desc tp_params[] = {
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = tp_layouts,
      .doc = "cube, plane or shadow (testphongscene.c)" },
    { .key = "size",
      .type = LG_PARAM_FLOAT,
      .def.f = 4,
      .min = 0.01,
      .max = 1000,
      .doc = "plane edge" },
    { .key = "segments",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 1,
      .max = 512,
      .doc = "plane subdivisions per side" },
    { .key = "ka", .type = LG_PARAM_FLOAT, .def.f = 0.1, .min = 0, .max = 100, .doc = "" },
    { .key = "kd", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0, .max = 100, .doc = "" },
    { .key = "ks", .type = LG_PARAM_FLOAT, .def.f = 0, .min = 0, .max = 100, .doc = "" },
    { .key = "shininess", .type = LG_PARAM_FLOAT, .def.f = 10, .min = 0, .max = 1e6, .doc = "" },
    { .key = "od",
      .type = LG_PARAM_COLOR,
      .def.v = { 0.8, 0.8, 0.8 },
      .min = 0,
      .max = 100,
      .doc = "" },
    { .key = "os", .type = LG_PARAM_COLOR, .def.v = { 1, 1, 1 }, .min = 0, .max = 100, .doc = "" },
    { .key = "double_sided", .type = LG_PARAM_BOOL, .def.b = false, .doc = "" },
    { .key = "camera_position", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 5 }, .doc = "" },
    { .key = "camera_target", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 0 }, .doc = "" },
    { .key = "camera_up", .type = LG_PARAM_VEC3, .def.v = { 0, 1, 0 }, .doc = "" },
    { .key = "yfov_deg", .type = LG_PARAM_FLOAT, .def.f = 60, .min = 1, .max = 170, .doc = "" },
};
static const lg_port_desc tp_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_phong_scene",
    .doc = "A small lightless scene built in memory for the phong tests",
    LG_PARAMS(tp_params),
    LG_OUTPUTS(tp_out),
    .prepare = tp_prepare,
    .execute = tp_execute,
} };

LG_PLUGIN_DEFINE("testphongscene", "1.0.0", "Scenes for the phong tests", types)
