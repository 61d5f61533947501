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
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"

#include "common/testscene.h"

enum { TP_CUBE = 0, TP_PLANE, TP_SHADOW };

typedef struct tp_mesh_data {
    float *pos, *nrm;
    uint32_t *idx;
    uint32_t nv, ni, cap_v, cap_i;
} tp_mesh_data;

/* One allocation for the structs; the vertex arrays are separate. */
typedef struct tp_scene {
    lg_scene s;
    lg_mesh meshes[2];
    tp_mesh_data data[2];
    lg_instance instances[2];
    lg_material material;
    lg_camera camera;
} tp_scene;

static void tp_free(void *p)
{
    tp_scene *t = p;
    if (!t)
        return;
    for (int i = 0; i < 2; i++) {
        free(t->data[i].pos);
        free(t->data[i].nrm);
        free(t->data[i].idx);
    }
    free(t);
}

static bool tp_reserve(tp_mesh_data *d, uint32_t nv, uint32_t ni)
{
    d->pos = malloc((size_t)nv * 3 * sizeof(float));
    d->nrm = malloc((size_t)nv * 3 * sizeof(float));
    d->idx = malloc((size_t)ni * sizeof(uint32_t));
    d->cap_v = nv;
    d->cap_i = ni;
    return d->pos && d->nrm && d->idx;
}

/* A grid of s x s quads over c +- u +- v, facing u x v (counter-clockwise front). */
static void tp_grid(tp_mesh_data *d, lg_vec3 c, lg_vec3 u, lg_vec3 v, uint32_t s)
{
    lg_vec3 nrm = lg_v3_normalize_or(lg_v3_cross(u, v), lg_v3(0, 1, 0));
    uint32_t base = d->nv;
    for (uint32_t j = 0; j <= s; j++)
        for (uint32_t i = 0; i <= s; i++) {
            float a = 2.0f * (float)i / (float)s - 1.0f, b = 2.0f * (float)j / (float)s - 1.0f;
            lg_vec3 p = lg_v3_add(c, lg_v3_add(lg_v3_scale(u, a), lg_v3_scale(v, b)));
            float *pp = d->pos + (size_t)d->nv * 3, *nn = d->nrm + (size_t)d->nv * 3;
            pp[0] = p.x, pp[1] = p.y, pp[2] = p.z;
            nn[0] = nrm.x, nn[1] = nrm.y, nn[2] = nrm.z;
            d->nv++;
        }
    for (uint32_t j = 0; j < s; j++)
        for (uint32_t i = 0; i < s; i++) {
            uint32_t a = base + j * (s + 1) + i, b = a + 1, c2 = a + s + 1, e = c2 + 1;
            uint32_t tri[6] = { a, b, e, a, e, c2 };
            for (int k = 0; k < 6; k++)
                d->idx[d->ni++] = tri[k];
        }
}

static void tp_cube(tp_mesh_data *d)
{
    static const float f[6][3][3] = {
        { { 1, 0, 0 }, { 0, 0, -1 }, { 0, 1, 0 } },  { { -1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },
        { { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, -1 } },  { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } },
        { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 } },   { { 0, 0, -1 }, { -1, 0, 0 }, { 0, 1, 0 } },
    };
    for (int i = 0; i < 6; i++)
        tp_grid(d, lg_v3_scale(lg_v3(f[i][0][0], f[i][0][1], f[i][0][2]), 0.5f),
                lg_v3_scale(lg_v3(f[i][1][0], f[i][1][1], f[i][1][2]), 0.5f),
                lg_v3_scale(lg_v3(f[i][2][0], f[i][2][1], f[i][2][2]), 0.5f), 1);
}

static void tp_vec(lg_node *n, const char *key, float out[3])
{
    const lg_value *v = lg_param(n, key);
    for (int k = 0; k < 3; k++)
        out[k] = v ? (float)v->v[k] : 0.0f;
}

static int tp_prepare(lg_node *n)
{
    tp_scene *t = calloc(1, sizeof *t);
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    float size = (float)lg_param_float(n, "size");
    uint32_t segs = (uint32_t)lg_param_int(n, "segments");

    t->s.struct_size = sizeof t->s;
    t->s.source = "test_phong_scene";
    t->s.meshes = t->meshes;
    t->s.instances = t->instances;
    t->s.materials = &t->material;
    t->s.n_materials = 1;
    t->s.cameras = &t->camera;
    t->s.n_cameras = 1;

    lg_material *m = &t->material;
    m->name = "test";
    m->ka = (float)lg_param_float(n, "ka");
    m->kd = (float)lg_param_float(n, "kd");
    m->ks = (float)lg_param_float(n, "ks");
    m->shininess = (float)lg_param_float(n, "shininess");
    tp_vec(n, "od", m->od);
    tp_vec(n, "os", m->os);
    memcpy(m->base_color, m->od, sizeof m->od);
    m->base_color[3] = 1.0f;
    m->double_sided = lg_param_bool(n, "double_sided");

    lg_camera *c = &t->camera;
    c->name = "test";
    tp_vec(n, "camera_position", c->position);
    tp_vec(n, "camera_target", c->target);
    tp_vec(n, "camera_up", c->up);
    c->yfov = (float)(lg_param_float(n, "yfov_deg") * LG_PI / 180.0);
    c->znear = 0.1f;
    c->zfar = 50.0f;

    bool ok;
    float h = 0.5f * size;
    switch (layout) {
    case TP_CUBE:
        t->s.n_meshes = 1;
        ok = tp_reserve(&t->data[0], 24, 36);
        if (ok)
            tp_cube(&t->data[0]);
        break;
    case TP_PLANE:
        t->s.n_meshes = 1;
        ok = tp_reserve(&t->data[0], (segs + 1) * (segs + 1), 6 * segs * segs);
        if (ok)
            tp_grid(&t->data[0], lg_v3(0, 0, 0), lg_v3(h, 0, 0), lg_v3(0, 0, -h), segs);
        break;
    default:
        t->s.n_meshes = 2;
        ok = tp_reserve(&t->data[0], (segs + 1) * (segs + 1), 6 * segs * segs) &&
             tp_reserve(&t->data[1], 4, 6);
        if (ok) {
            tp_grid(&t->data[0], lg_v3(0, 0, 0), lg_v3(h, 0, 0), lg_v3(0, 0, -h), segs);
            tp_grid(&t->data[1], lg_v3(0, 1, 0), lg_v3(0.5f, 0, 0), lg_v3(0, 0, -0.5f), 1);
        }
        break;
    }
    if (!ok) {
        tp_free(t);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    static const char *const names[2] = { "test mesh#0", "occluder#0" };
    for (uint32_t i = 0; i < t->s.n_meshes; i++) {
        t->meshes[i].name = names[i];
        t->meshes[i].n_vertices = t->data[i].nv;
        t->meshes[i].n_indices = t->data[i].ni;
        t->meshes[i].positions = t->data[i].pos;
        t->meshes[i].normals = t->data[i].nrm;
        t->meshes[i].indices = t->data[i].idx;
        lg_instance *in = &t->instances[t->s.n_instances++];
        in->mesh = i;
        lg_m4_identity(in->model);
        lg_m4_normal_matrix(in->normal_matrix, in->model);
    }
    lg_test_scene_bounds(&t->s, t->meshes);
    lg_scene_compute_features(&t->s);
    return n->host->declare_payload(n, 0, LG_KIND_SCENE, &t->s.features, &t->s, tp_free);
}

static int tp_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const char *const tp_layouts[] = { "cube", "plane", "shadow", NULL };

static const lg_param_desc tp_params[] = {
    { .key = "layout", .type = LG_PARAM_ENUM, .def.e = 0, .enum_values = tp_layouts,
      .doc = "cube, plane or shadow (testphongscene.c)" },
    { .key = "size", .type = LG_PARAM_FLOAT, .def.f = 4, .min = 0.01, .max = 1000,
      .doc = "plane edge" },
    { .key = "segments", .type = LG_PARAM_INT, .def.i = 1, .min = 1, .max = 512,
      .doc = "plane subdivisions per side" },
    { .key = "ka", .type = LG_PARAM_FLOAT, .def.f = 0.1, .min = 0, .max = 100, .doc = "" },
    { .key = "kd", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0, .max = 100, .doc = "" },
    { .key = "ks", .type = LG_PARAM_FLOAT, .def.f = 0, .min = 0, .max = 100, .doc = "" },
    { .key = "shininess", .type = LG_PARAM_FLOAT, .def.f = 10, .min = 0, .max = 1e6, .doc = "" },
    { .key = "od", .type = LG_PARAM_COLOR, .def.v = { 0.8, 0.8, 0.8 }, .min = 0, .max = 100,
      .doc = "" },
    { .key = "os", .type = LG_PARAM_COLOR, .def.v = { 1, 1, 1 }, .min = 0, .max = 100,
      .doc = "" },
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
