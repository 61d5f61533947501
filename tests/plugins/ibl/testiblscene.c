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
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

enum { TI_SPHERE = 0, TI_QUAD, TI_SPHERES, TI_NONE };
#define TI_MAX 5

typedef struct ti_scene {
    lg_scene s;
    lg_mesh meshes[TI_MAX];
    float *pos[TI_MAX], *nrm[TI_MAX];
    uint32_t *idx[TI_MAX];
    lg_instance instances[TI_MAX];
    lg_material materials[TI_MAX];
    lg_camera camera;
} ti_scene;

static void ti_free(void *p)
{
    ti_scene *t = p;
    if (!t)
        return;
    for (int i = 0; i < TI_MAX; i++) {
        free(t->pos[i]);
        free(t->nrm[i]);
        free(t->idx[i]);
    }
    free(t);
}

static void ti_vec(lg_node *n, const char *key, float out[3])
{
    const lg_value *v = lg_param(n, key);
    for (int k = 0; k < 3; k++)
        out[k] = v ? (float)v->v[k] : 0.0f;
}

/* A UV sphere into mesh slot k: (seg + 1) x (seg/2 + 1) vertices. */
static bool ti_sphere(ti_scene *t, int k, lg_vec3 c, float r, uint32_t seg)
{
    uint32_t rows = seg / 2 < 2 ? 2 : seg / 2, cols = seg < 3 ? 3 : seg;
    uint32_t nv = (cols + 1) * (rows + 1), ni = cols * rows * 6;
    t->pos[k] = malloc((size_t)nv * 12);
    t->nrm[k] = malloc((size_t)nv * 12);
    t->idx[k] = malloc((size_t)ni * 4);
    if (!t->pos[k] || !t->nrm[k] || !t->idx[k])
        return false;
    uint32_t v = 0;
    for (uint32_t j = 0; j <= rows; j++)
        for (uint32_t i = 0; i <= cols; i++, v++) {
            double th = LG_PI * j / rows, ph = 2 * LG_PI * i / cols;
            double x = sin(th) * cos(ph), y = cos(th), z = -sin(th) * sin(ph);
            t->nrm[k][3 * v] = (float)x, t->nrm[k][3 * v + 1] = (float)y,
            t->nrm[k][3 * v + 2] = (float)z;
            t->pos[k][3 * v] = c.x + r * (float)x, t->pos[k][3 * v + 1] = c.y + r * (float)y,
            t->pos[k][3 * v + 2] = c.z + r * (float)z;
        }
    uint32_t q = 0;
    for (uint32_t j = 0; j < rows; j++)
        for (uint32_t i = 0; i < cols; i++) {
            uint32_t a = j * (cols + 1) + i, b = a + 1, d = a + cols + 1, e = d + 1;
            /* counter-clockwise seen from outside */
            uint32_t tri[6] = { a, d, e, a, e, b };
            for (int m = 0; m < 6; m++)
                t->idx[k][q++] = tri[m];
        }
    t->meshes[k].n_vertices = nv;
    t->meshes[k].n_indices = ni;
    return true;
}

static bool ti_quad(ti_scene *t, lg_vec3 nrm, bool flip)
{
    lg_vec3 N = lg_v3_normalize_or(nrm, lg_v3(0, 0, 1));
    lg_vec3 a = fabsf(N.y) < 0.9f ? lg_v3(0, 1, 0) : lg_v3(1, 0, 0);
    lg_vec3 u = lg_v3_normalize_or(lg_v3_cross(a, N), lg_v3(1, 0, 0));
    lg_vec3 w = lg_v3_cross(N, u); /* u x w = N: counter-clockwise faces N */
    t->pos[0] = malloc(4 * 12);
    t->nrm[0] = malloc(4 * 12);
    t->idx[0] = malloc(6 * 4);
    if (!t->pos[0] || !t->nrm[0] || !t->idx[0])
        return false;
    static const float s[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    lg_vec3 sn = flip ? lg_v3_scale(N, -1.0f) : N;
    for (int i = 0; i < 4; i++) {
        lg_vec3 p = lg_v3_add(lg_v3_scale(u, s[i][0]), lg_v3_scale(w, s[i][1]));
        t->pos[0][3 * i] = p.x, t->pos[0][3 * i + 1] = p.y, t->pos[0][3 * i + 2] = p.z;
        t->nrm[0][3 * i] = sn.x, t->nrm[0][3 * i + 1] = sn.y, t->nrm[0][3 * i + 2] = sn.z;
    }
    static const uint32_t tri[6] = { 0, 1, 2, 0, 2, 3 };
    memcpy(t->idx[0], tri, sizeof tri);
    t->meshes[0].n_vertices = 4;
    t->meshes[0].n_indices = 6;
    return true;
}

static int ti_prepare(lg_node *n)
{
    ti_scene *t = calloc(1, sizeof *t);
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    t->s.struct_size = sizeof t->s;
    t->s.source = "test_ibl_scene";
    t->s.meshes = t->meshes;
    t->s.instances = t->instances;
    t->s.materials = t->materials;
    t->s.cameras = &t->camera;
    t->s.n_cameras = 1;

    float refl[3];
    ti_vec(n, "reflectivity", refl);
    t->s.n_materials = layout == TI_SPHERES ? 5 : 1;
    for (uint32_t i = 0; i < t->s.n_materials; i++) {
        lg_material *m = &t->materials[i];
        m->name = "test";
        m->kd = 1.0f;
        m->od[0] = m->od[1] = m->od[2] = 0.5f;
        memcpy(m->reflectivity, refl, sizeof refl);
        m->roughness = layout == TI_SPHERES ? 0.25f * (float)i
                                            : (float)lg_param_float(n, "roughness");
        m->double_sided = lg_param_bool(n, "double_sided");
    }

    lg_camera *c = &t->camera;
    c->name = "test";
    ti_vec(n, "camera_position", c->position);
    ti_vec(n, "camera_target", c->target);
    ti_vec(n, "camera_up", c->up);
    c->yfov = (float)(lg_param_float(n, "yfov_deg") * LG_PI / 180.0);
    c->znear = 0.1f;
    c->zfar = 50.0f;

    bool ok = true;
    uint32_t seg = (uint32_t)lg_param_int(n, "segments");
    float radius = (float)lg_param_float(n, "radius");
    if (layout == TI_SPHERE) {
        t->s.n_meshes = 1;
        ok = ti_sphere(t, 0, lg_v3(0, 0, 0), radius, seg);
    } else if (layout == TI_QUAD) {
        float qn[3];
        ti_vec(n, "quad_normal", qn);
        t->s.n_meshes = 1;
        ok = ti_quad(t, lg_v3(qn[0], qn[1], qn[2]), lg_param_bool(n, "flip_normals"));
    } else if (layout == TI_SPHERES) {
        t->s.n_meshes = 5;
        for (int k = 0; k < 5 && ok; k++) {
            ok = ti_sphere(t, k, lg_v3((float)(k - 2), 0, 0), 0.4f, seg);
            t->meshes[k].material = (uint32_t)k;
        }
    }
    if (!ok) {
        ti_free(t);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    for (uint32_t i = 0; i < t->s.n_meshes; i++) {
        t->meshes[i].name = "test mesh";
        t->meshes[i].positions = t->pos[i];
        t->meshes[i].normals = t->nrm[i];
        t->meshes[i].indices = t->idx[i];
        lg_instance *in = &t->instances[t->s.n_instances++];
        in->mesh = i;
        lg_m4_identity(in->model);
        lg_m4_normal_matrix(in->normal_matrix, in->model);
    }
    lg_test_scene_bounds(&t->s, t->meshes);
    lg_scene_compute_features(&t->s);
    return n->host->declare_payload(n, 0, LG_KIND_SCENE, &t->s.features, &t->s, ti_free);
}

static int ti_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const char *const ti_layouts[] = { "sphere", "quad", "spheres", "none", NULL };

static const lg_param_desc ti_params[] = {
    { .key = "layout", .type = LG_PARAM_ENUM, .def.e = 0, .enum_values = ti_layouts,
      .doc = "sphere, quad, spheres or none (testiblscene.c)" },
    { .key = "radius", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0.01, .max = 100, .doc = "" },
    { .key = "segments", .type = LG_PARAM_INT, .def.i = 96, .min = 3, .max = 2048, .doc = "" },
    { .key = "reflectivity", .type = LG_PARAM_COLOR, .def.v = { 1, 1, 1 }, .min = 0, .max = 100,
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
