/*
 * Test plugin "testiblscene": scenes with known geometry, materials and camera built in
 * memory for the ibl tests (tests/plugins/ibl/test_ibl.c), so that reflections can be
 * predicted in closed form.
 *
 *   test_ibl_scene  -> scene
 *
 * Layouts:
 *   sphere   a UV sphere of `radius` at the origin, `segments` x segments/2 quads, exact
 *            normals (position / radius)
 *   quad     a square of edge 2 at the origin in the plane through the origin whose
 *            front (counter-clockwise) side faces `quad_normal`; its normals point along
 *            quad_normal, or against it with flip_normals (front faces whose shading
 *            normals face away from the viewer)
 *   spheres  five spheres of radius 0.4 along X (x = -2, -1, 0, 1, 2) with roughness 0,
 *            0.25, 0.5, 0.75 and 1 (materials 0..4)
 *   none     no geometry (a camera only)
 *
 * Materials: reflectivity, roughness and double_sided from the parameters (spheres: the
 * roughness of each sphere's own material). One camera (camera_position, camera_target,
 * camera_up, yfov_deg; znear 0.1, zfar 50).
 */
#include <math.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

enum { TI_SPHERE = 0, TI_QUAD, TI_SPHERES, TI_NONE };

static lg_vec3 ti_vec(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? lg_v3((float)v->v[0], (float)v->v[1], (float)v->v[2]) : lg_v3(0, 0, 0);
}

/* A UV sphere of (seg + 1) x (seg/2 + 1) vertices centred on c, as the next mesh. */
static void ti_sphere(lg_ts_builder *b, uint32_t material, lg_vec3 c, float r, uint32_t seg)
{
    uint32_t rows = seg / 2 < 2 ? 2 : seg / 2, cols = seg < 3 ? 3 : seg;
    uint32_t k = lg_ts_mesh(b, "test mesh", material);
    lg_ts_uv_sphere(b, &c, r, cols, rows);
    lg_ts_instance(b, k, NULL);
}

/* The quad: its front faces nrm, its shading normals too (or, flipped, away). */
static void ti_quad(lg_ts_builder *b, lg_vec3 nrm, bool flip)
{
    lg_vec3 N = lg_v3_normalize_or(nrm, lg_v3(0, 0, 1));
    lg_vec3 a = fabsf(N.y) < 0.9f ? lg_v3(0, 1, 0) : lg_v3(1, 0, 0);
    lg_vec3 u = lg_v3_normalize_or(lg_v3_cross(a, N), lg_v3(1, 0, 0));
    lg_vec3 w = lg_v3_cross(N, u); /* u x w = N: counter-clockwise faces N */
    lg_vec3 sn = flip ? lg_v3_scale(N, -1.0f) : N;
    lg_ts_mesh(b, "test mesh", 0);
    lg_ts_quad(b, NULL, u, w, &sn);
    lg_ts_instance(b, 0, NULL);
}

static int ti_prepare(lg_node *n)
{
    lg_ts_builder *b = lg_ts_begin("test_ibl_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    lg_vec3 refl = ti_vec(n, "reflectivity");
    uint32_t n_materials = layout == TI_SPHERES ? 5 : 1;
    for (uint32_t i = 0; i < n_materials; i++) {
        lg_material *m = lg_ts_material(b, "test");
        m->kd = 1.0f;
        m->od[0] = m->od[1] = m->od[2] = 0.5f;
        m->reflectivity[0] = refl.x, m->reflectivity[1] = refl.y, m->reflectivity[2] = refl.z;
        m->roughness = layout == TI_SPHERES ? 0.25f * (float)i
                                            : (float)lg_param_float(n, "roughness");
        m->double_sided = lg_param_bool(n, "double_sided");
    }
    lg_ts_camera(b, "test", ti_vec(n, "camera_position"), ti_vec(n, "camera_target"),
                 ti_vec(n, "camera_up"), (float)(lg_param_float(n, "yfov_deg") * LG_PI / 180.0),
                 0.1f, 50.0f);

    uint32_t seg = (uint32_t)lg_param_int(n, "segments");
    float radius = (float)lg_param_float(n, "radius");
    if (layout == TI_SPHERE)
        ti_sphere(b, 0, lg_v3(0, 0, 0), radius, seg);
    else if (layout == TI_QUAD)
        ti_quad(b, ti_vec(n, "quad_normal"), lg_param_bool(n, "flip_normals"));
    else if (layout == TI_SPHERES)
        for (int k = 0; k < 5; k++)
            ti_sphere(b, (uint32_t)k, lg_v3((float)(k - 2), 0, 0), 0.4f, seg);
    return lg_ts_publish(n, 0, b);
}

static int ti_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const char *const ti_layouts[] = { "sphere", "quad", "spheres", "none", NULL };

static const lg_param_desc ti_params[] = {
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = ti_layouts,
      .doc = "sphere, quad, spheres or none (testiblscene.c)" },
    { .key = "radius", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0.01, .max = 100, .doc = "" },
    { .key = "segments", .type = LG_PARAM_INT, .def.i = 96, .min = 3, .max = 2048, .doc = "" },
    { .key = "reflectivity",
      .type = LG_PARAM_COLOR,
      .def.v = { 1, 1, 1 },
      .min = 0,
      .max = 100,
      .doc = "" },
    { .key = "roughness", .type = LG_PARAM_FLOAT, .def.f = 0, .min = 0, .max = 1, .doc = "" },
    { .key = "double_sided", .type = LG_PARAM_BOOL, .def.b = false, .doc = "" },
    { .key = "quad_normal", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 1 }, .doc = "" },
    { .key = "flip_normals", .type = LG_PARAM_BOOL, .def.b = false, .doc = "" },
    { .key = "camera_position", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 5 }, .doc = "" },
    { .key = "camera_target", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 0 }, .doc = "" },
    { .key = "camera_up", .type = LG_PARAM_VEC3, .def.v = { 0, 1, 0 }, .doc = "" },
    { .key = "yfov_deg", .type = LG_PARAM_FLOAT, .def.f = 40, .min = 1, .max = 170, .doc = "" },
};
static const lg_port_desc ti_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_ibl_scene",
    .doc = "A small scene built in memory for the ibl tests",
    LG_PARAMS(ti_params),
    LG_OUTPUTS(ti_out),
    .prepare = ti_prepare,
    .execute = ti_execute,
} };

LG_PLUGIN_DEFINE("testiblscene", "1.0.0", "Scenes for the ibl tests", types)
