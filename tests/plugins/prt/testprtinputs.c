/*
 * Test plugin "testprtinputs": a scene, SH lighting and per-vertex transfer with known
 * values, built in memory for the prt tests (tests/plugins/prt/test_prt.c).
 *
 *   test_prt_inputs_scene -> scene
 *   test_prt_sh        -> lighting (LG_KIND_SH)
 *   test_prt_transfer  -> transfer (LG_KIND_TRANSFER)
 *
 * Scenes (layout):
 *   mixed  mesh 0: a 9 x 9 grid of vertices over the square [-2, 2]^2 in z = -1 facing +Z;
 *          mesh 1: a UV sphere of radius 0.6, 12 x 6 quads (13 x 7 vertices), drawn twice
 *          (instances at x = -1 and x = +1): 81 + 91 = 172 vertices, three instances
 *   quad   one square of edge 2 (4 vertices) in z = 0 facing +Z
 * One camera at (0, 0, 5) looking at the origin, 40 degrees vertical field of view.
 *
 * Lighting (mode): random (prt_testdata.h, `seed`), or delta: a unit delta light along
 * `dir` of colour `color`, coefficient i = color_c Y_i(dir) (lightgraph/sh.h).
 * Transfer (mode): random (per vertex, `seed`), constant (every vertex the vector of
 * vertex 0 of random), or normal: the unshadowed diffuse transfer of a white (albedo 0.8)
 * surface, (0.8 / pi) A_l Y_lm(n) with n the vertex normal of the optional input `scene`
 * (for pictures). `vertices` 0 = the scene's count (mixed: 172); another value makes
 * a transfer for another scene.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/sh.h"
#include "lightgraph/shcoeffs.h"
#include "lightgraph/transfer.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"
#include "prt_testdata.h"

enum { TP_MIXED = 0, TP_QUAD };
enum { TP_GRID_N = 9, TP_SEG = 12 };
/* the mixed scene's vertex count: the grid, then the sphere */
#define TP_MIXED_VERTICES (TP_GRID_N * TP_GRID_N + (TP_SEG + 1) * (TP_SEG / 2 + 1))

typedef struct tp_scene {
    lg_scene s;
    lg_mesh meshes[2];
    float *pos[2], *nrm[2];
    uint32_t *idx[2];
    lg_instance instances[3];
    lg_material material;
    lg_camera camera;
} tp_scene;

static void tp_free(void *p)
{
    tp_scene *t = p;
    if (!t)
        return;
    for (int i = 0; i < 2; i++) {
        free(t->pos[i]);
        free(t->nrm[i]);
        free(t->idx[i]);
    }
    free(t);
}

static bool tp_alloc(tp_scene *t, int k, uint32_t nv, uint32_t ni)
{
    t->pos[k] = malloc((size_t)nv * 12);
    t->nrm[k] = malloc((size_t)nv * 12);
    t->idx[k] = malloc((size_t)ni * 4);
    t->meshes[k].n_vertices = nv;
    t->meshes[k].n_indices = ni;
    return t->pos[k] && t->nrm[k] && t->idx[k];
}

/* An n x n grid over [-h, h]^2 at z, facing +Z (counter-clockwise seen from +Z). */
static bool tp_grid(tp_scene *t, int k, uint32_t n, float h, float z)
{
    if (!tp_alloc(t, k, n * n, (n - 1) * (n - 1) * 6))
        return false;
    for (uint32_t j = 0, v = 0; j < n; j++)
        for (uint32_t i = 0; i < n; i++, v++) {
            t->pos[k][3 * v] = -h + 2 * h * (float)i / (float)(n - 1);
            t->pos[k][3 * v + 1] = -h + 2 * h * (float)j / (float)(n - 1);
            t->pos[k][3 * v + 2] = z;
            t->nrm[k][3 * v] = 0, t->nrm[k][3 * v + 1] = 0, t->nrm[k][3 * v + 2] = 1;
        }
    uint32_t q = 0;
    for (uint32_t j = 0; j + 1 < n; j++)
        for (uint32_t i = 0; i + 1 < n; i++) {
            uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            uint32_t tri[6] = { a, b, d, a, d, c };
            for (int m = 0; m < 6; m++)
                t->idx[k][q++] = tri[m];
        }
    return true;
}

/* A UV sphere of radius r at the origin: (seg + 1) x (seg/2 + 1) vertices. */
static bool tp_sphere(tp_scene *t, int k, float r, uint32_t seg)
{
    uint32_t rows = seg / 2, cols = seg;
    if (!tp_alloc(t, k, (cols + 1) * (rows + 1), cols * rows * 6))
        return false;
    uint32_t v = 0;
    for (uint32_t j = 0; j <= rows; j++)
        for (uint32_t i = 0; i <= cols; i++, v++) {
            double th = LG_PI * j / rows, ph = 2 * LG_PI * i / cols;
            double x = sin(th) * cos(ph), y = cos(th), z = -sin(th) * sin(ph);
            t->nrm[k][3 * v] = (float)x, t->nrm[k][3 * v + 1] = (float)y,
            t->nrm[k][3 * v + 2] = (float)z;
            t->pos[k][3 * v] = r * (float)x, t->pos[k][3 * v + 1] = r * (float)y,
            t->pos[k][3 * v + 2] = r * (float)z;
        }
    uint32_t q = 0;
    for (uint32_t j = 0; j < rows; j++)
        for (uint32_t i = 0; i < cols; i++) {
            uint32_t a = j * (cols + 1) + i, b = a + 1, d = a + cols + 1, e = d + 1;
            uint32_t tri[6] = { a, d, e, a, e, b };
            for (int m = 0; m < 6; m++)
                t->idx[k][q++] = tri[m];
        }
    return true;
}

static int tp_scene_prepare(lg_node *n)
{
    tp_scene *t = calloc(1, sizeof *t);
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    t->s.struct_size = sizeof t->s;
    t->s.source = "test_prt_inputs_scene";
    t->s.meshes = t->meshes;
    t->s.instances = t->instances;
    t->s.materials = &t->material;
    t->s.n_materials = 1;
    t->s.cameras = &t->camera;
    t->s.n_cameras = 1;
    t->material.name = "test";
    t->material.kd = 1.0f;
    t->material.od[0] = t->material.od[1] = t->material.od[2] = 0.5f;
    t->material.base_color[0] = t->material.base_color[1] = t->material.base_color[2] = 1.0f;
    t->material.base_color[3] = 1.0f;
    lg_camera *c = &t->camera;
    c->name = "test";
    c->position[2] = 5.0f;
    c->up[1] = 1.0f;
    c->yfov = (float)(40.0 * LG_PI / 180.0);
    c->znear = 0.1f;
    c->zfar = 50.0f;

    bool ok;
    if (layout == TP_QUAD) {
        t->s.n_meshes = 1;
        ok = tp_grid(t, 0, 2, 1.0f, 0.0f);
    } else {
        t->s.n_meshes = 2;
        ok = tp_grid(t, 0, TP_GRID_N, 2.0f, -1.0f) && tp_sphere(t, 1, 0.6f, TP_SEG);
    }
    if (!ok) {
        tp_free(t);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    for (uint32_t i = 0; i < t->s.n_meshes; i++) {
        t->meshes[i].name = i == 0 ? "test grid" : "test sphere";
        t->meshes[i].positions = t->pos[i];
        t->meshes[i].normals = t->nrm[i];
        t->meshes[i].indices = t->idx[i];
    }
    /* instances: every mesh once; the mixed scene's sphere twice, at x = -1 and +1 */
    uint32_t ni = 0;
    lg_m4_identity(t->instances[ni].model);
    t->instances[ni++].mesh = 0;
    if (layout == TP_MIXED)
        for (int s = -1; s <= 1; s += 2) {
            lg_instance *in = &t->instances[ni++];
            in->mesh = 1;
            lg_m4_identity(in->model);
            in->model[12] = (float)s;
        }
    t->s.n_instances = ni;
    for (uint32_t i = 0; i < ni; i++)
        lg_m4_normal_matrix(t->instances[i].normal_matrix, t->instances[i].model);
    lg_test_scene_bounds(&t->s, t->meshes);
    lg_scene_compute_features(&t->s);
    return n->host->declare_payload(n, 0, LG_KIND_SCENE, &t->s.features, &t->s, tp_free);
}

static int tp_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- lighting ------------------------------------------------------------------------- */

enum { TP_RANDOM = 0, TP_DELTA };

static int tp_sh_prepare(lg_node *n)
{
    return lg_sh_declare(n, 0, (uint32_t)lg_param_int(n, "bands"));
}

static int tp_sh_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    uint32_t bands = (uint32_t)lg_param_int(n, "bands"), nc = bands * bands;
    uint32_t seed = (uint32_t)lg_param_int(n, "seed");
    lg_cpu_view v;
    const lg_resource *p = lg_part(n, lg_output(n, 0), "coeffs");
    if (!p || lg_map_cpu(n, p, LG_WRITE, &v))
        return lg_error(n, "the coefficients cannot be written");
    float *out = v.pixels;
    if (lg_param_enum(n, "mode") == TP_DELTA) {
        const lg_value *d = lg_param(n, "dir"), *col = lg_param(n, "color");
        double dir[3] = { d->v[0], d->v[1], d->v[2] };
        double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        if (!(len > 0))
            return lg_error(n, "dir = [0, 0, 0]");
        for (int k = 0; k < 3; k++)
            dir[k] /= len;
        double *y = malloc(nc * sizeof *y);
        if (!y)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
        lg_sh_eval_d(bands, dir, y);
        for (uint32_t c = 0; c < 3; c++)
            for (uint32_t i = 0; i < nc; i++)
                out[c * nc + i] = (float)(col->v[c] * y[i]);
        free(y);
    } else {
        for (uint32_t c = 0; c < 3; c++)
            for (uint32_t i = 0; i < nc; i++)
                out[c * nc + i] = prt_test_light(seed, c, i);
    }
    lg_sh_info si = { .struct_size = sizeof si, .bands = bands };
    return lg_sh_publish(n, 0, &si);
}

/* ---- transfer ------------------------------------------------------------------------- */

static uint32_t tp_vertices(lg_node *n)
{
    uint32_t v = (uint32_t)lg_param_int(n, "vertices");
    const lg_scene *s = lg_input(n, 0) ? lg_scene_get(n, lg_input(n, 0)) : NULL;
    if (!v && s)
        for (uint32_t m = 0; m < s->n_meshes; m++)
            v += s->meshes[m].n_vertices;
    return v ? v : TP_MIXED_VERTICES;
}

/* mode normal: vertex k's transfer from its normal (tp_tr_execute) */
static void tp_normal_transfer(const lg_scene *s, uint32_t k, uint32_t bands, float *out)
{
    uint32_t m = 0;
    while (m + 1 < s->n_meshes && k >= s->meshes[m].n_vertices)
        k -= s->meshes[m++].n_vertices;
    const float *nf = s->meshes[m].normals + 3 * (size_t)k;
    double d[3] = { nf[0], nf[1], nf[2] }, y[64 * 64];
    lg_sh_eval_d(bands, d, y);
    for (uint32_t l = 0; l < bands; l++)
        for (uint32_t i = l * l; i < (l + 1) * (l + 1); i++)
            for (int c = 0; c < 3; c++)
                out[c * bands * bands + i] =
                    (float)(0.8 / LG_PI * lg_sh_clamped_cosine(l) * y[i]);
}

static int tp_tr_prepare(lg_node *n)
{
    return lg_transfer_declare(n, 0, (uint32_t)lg_param_int(n, "bands"), tp_vertices(n));
}

static int tp_tr_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    uint32_t bands = (uint32_t)lg_param_int(n, "bands"), nc = bands * bands;
    uint32_t seed = (uint32_t)lg_param_int(n, "seed"), nv = tp_vertices(n);
    int mode = lg_param_enum(n, "mode");
    bool constant = mode == 1; /* tp_tr_modes */
    const lg_scene *s = lg_input(n, 0) ? lg_scene_get(n, lg_input(n, 0)) : NULL;
    if (mode == 2 && (!s || bands > 16))
        return lg_error(n, "mode normal needs the input scene and at most 16 bands");
    lg_cpu_view v;
    const lg_resource *p = lg_part(n, lg_output(n, 0), "transfer");
    if (!p || lg_map_cpu(n, p, LG_WRITE, &v))
        return lg_error(n, "the transfer cannot be written");
    float *out = v.pixels;
    for (uint32_t k = 0; k < nv && mode == 2; k++)
        tp_normal_transfer(s, k, bands, out + (size_t)k * 3 * nc);
    for (uint32_t k = 0; k < nv && mode != 2; k++)
        for (uint32_t c = 0; c < 3; c++)
            for (uint32_t i = 0; i < nc; i++)
                out[((size_t)k * 3 + c) * nc + i] = prt_test_transfer(seed, constant ? 0 : k, c, i);
    lg_transfer_info ti = { .struct_size = sizeof ti, .bands = bands, .vertices = nv,
                            .mode = LG_TRANSFER_UNSHADOWED };
    return lg_transfer_publish(n, 0, &ti);
}

/* ---- descriptors ---------------------------------------------------------------------- */

static const char *const tp_layouts[] = { "mixed", "quad", NULL };
static const char *const tp_sh_modes[] = { "random", "delta", NULL };
static const char *const tp_tr_modes[] = { "random", "constant", "normal", NULL };

static const lg_param_desc tp_scene_params[] = {
    { .key = "layout", .type = LG_PARAM_ENUM, .def.e = TP_MIXED, .enum_values = tp_layouts,
      .doc = "mixed or quad (testprtinputs.c)" },
};
static const lg_param_desc tp_sh_params[] = {
    { .key = "bands", .type = LG_PARAM_INT, .def.i = 3, .min = 1, .max = 64, .doc = "" },
    { .key = "seed", .type = LG_PARAM_INT, .def.i = 1, .min = 0, .max = 65535, .doc = "" },
    { .key = "mode", .type = LG_PARAM_ENUM, .def.e = TP_RANDOM, .enum_values = tp_sh_modes,
      .doc = "" },
    { .key = "dir", .type = LG_PARAM_VEC3, .def.v = { 1, 0, 0 }, .doc = "" },
    { .key = "color", .type = LG_PARAM_COLOR, .def.v = { 1, 1, 1 }, .min = 0, .max = 1e6,
      .doc = "" },
};
static const lg_param_desc tp_tr_params[] = {
    { .key = "bands", .type = LG_PARAM_INT, .def.i = 3, .min = 1, .max = 64, .doc = "" },
    { .key = "seed", .type = LG_PARAM_INT, .def.i = 2, .min = 0, .max = 65535, .doc = "" },
    { .key = "mode", .type = LG_PARAM_ENUM, .def.e = TP_RANDOM, .enum_values = tp_tr_modes,
      .doc = "" },
    { .key = "vertices", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 1000000,
      .doc = "0 = the mixed scene's count" },
};
static const lg_port_desc tp_scene_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc tp_sh_out[] = { { .name = "lighting", .kind = LG_KIND_SH } };
static const lg_port_desc tp_tr_out[] = { { .name = "transfer", .kind = LG_KIND_TRANSFER } };
static const lg_port_desc tp_tr_in[] = { { .name = "scene", .kind = LG_KIND_SCENE,
                                           .optional = true } };

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_prt_inputs_scene",
        .doc = "A small scene built in memory for the prt tests",
        LG_PARAMS(tp_scene_params),
        LG_OUTPUTS(tp_scene_out),
        .prepare = tp_scene_prepare,
        .execute = tp_nothing,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_prt_sh",
        .doc = "SH lighting with known values for the prt tests",
        LG_PARAMS(tp_sh_params),
        LG_OUTPUTS(tp_sh_out),
        .prepare = tp_sh_prepare,
        .execute = tp_sh_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_prt_transfer",
        .doc = "Per-vertex transfer with known values for the prt tests",
        LG_PARAMS(tp_tr_params),
        LG_INPUTS(tp_tr_in),
        LG_OUTPUTS(tp_tr_out),
        .prepare = tp_tr_prepare,
        .execute = tp_tr_execute,
    },
};

LG_PLUGIN_DEFINE("testprtinputs", "1.0.0", "Scenes, lighting and transfer for the prt tests",
                 types)
