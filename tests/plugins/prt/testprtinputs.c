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
 * Textures (`texture`, quad only; TEXCOORD_0 (u, v) over [0, 1]^2 from the top-left corner
 * as the camera sees it, nearest, clamped; testtextures.h): halves, a 2x1 base colour
 * texture (255, 255, 255) left and (255, 128, 32) right; mask, 2x2 white with alpha 0 in
 * the top-left texel, alpha MASK at 0.5.
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
#include "common/testtextures.h"
#include "prt_testdata.h"

enum { TP_MIXED = 0, TP_QUAD };
enum { TP_TEX_NONE = 0, TP_TEX_HALVES, TP_TEX_MASK };
enum { TP_GRID_N = 9, TP_SEG = 12 };
/* the mixed scene's vertex count: the grid, then the sphere */
#define TP_MIXED_VERTICES (TP_GRID_N * TP_GRID_N + (TP_SEG + 1) * (TP_SEG / 2 + 1))

/* An n x n grid of vertices over [-h, h]^2 at z, facing +Z, as the next mesh. */
static void tp_grid(lg_ts_builder *b, uint32_t n, double h, double z)
{
    const double o[3] = { -h, -h, z }, u[3] = { 2 * h, 0, 0 }, v[3] = { 0, 2 * h, 0 };
    const double nz[3] = { 0, 0, 1 };
    lg_ts_mesh(b, "test grid", 0);
    lg_ts_grid_span(b, n - 1, o, u, v, nz, false);
}

static int tp_scene_prepare(lg_node *n)
{
    lg_ts_builder *b = lg_ts_begin("test_prt_inputs_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    lg_material *m = lg_ts_material(b, "test");
    m->kd = 1.0f;
    m->od[0] = m->od[1] = m->od[2] = 0.5f;
    m->base_color[0] = m->base_color[1] = m->base_color[2] = m->base_color[3] = 1.0f;
    lg_ts_camera(b, "test", lg_v3(0, 0, 5), lg_v3(0, 0, 0), lg_v3(0, 1, 0),
                 (float)(40.0 * LG_PI / 180.0), 0.1f, 50.0f);

    if (layout == TP_QUAD) {
        tp_grid(b, 2, 1.0, 0.0);
    } else {
        tp_grid(b, TP_GRID_N, 2.0, -1.0);
        lg_ts_mesh(b, "test sphere", 0);
        lg_ts_uv_sphere(b, NULL, 0.6f, TP_SEG, TP_SEG / 2);
    }
    /* instances: every mesh once; the mixed scene's sphere twice, at x = -1 and +1 */
    lg_ts_instance(b, 0, NULL);
    if (layout == TP_MIXED)
        for (int s = -1; s <= 1; s += 2) {
            float model[16];
            lg_m4_identity(model);
            model[12] = (float)s;
            lg_ts_instance(b, 1, model);
        }
    int texture = lg_param_enum(n, "texture");
    if (texture == TP_TEX_NONE)
        return lg_ts_publish(n, 0, b);
    if (layout != TP_QUAD) {
        lg_ts_abandon(b);
        return lg_error(n, "texture: only the quad layout has textures");
    }
    lg_tt_scene *t = lg_tt_wrap(lg_ts_finish(b));
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    const float origin[3] = { -1, 1, 0 }, du[3] = { 0.5f, 0, 0 }, dv[3] = { 0, -0.5f, 0 };
    static const uint8_t halves[8] = { 255, 255, 255, 255, 255, 128, 32, 255 };
    static const uint8_t mask[16] = { 255, 255, 255, 0,   255, 255, 255, 255,
                                      255, 255, 255, 255, 255, 255, 255, 255 };
    uint32_t img = texture == TP_TEX_HALVES ? lg_tt_image(t, "halves", 2, 1, halves)
                                            : lg_tt_image(t, "mask", 2, 2, mask);
    lg_material_maps *mm = lg_tt_maps(t, 0);
    mm->base_color.texture = lg_tt_texture(t, img, LG_TEX_NEAREST, LG_TEX_CLAMP_TO_EDGE);
    if (texture == TP_TEX_MASK)
        mm->alpha_mode = LG_ALPHA_MASK;
    if (img == UINT32_MAX || !lg_tt_planar_uv(t, 0, origin, du, dv)) {
        lg_tt_free(t);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    return lg_tt_publish(n, 0, t);
}

static int tp_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- lighting -------------------------------------------------------------------------------- */

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

/* ---- transfer -------------------------------------------------------------------------------- */

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
                out[c * bands * bands + i] = (float)(0.8 / LG_PI * lg_sh_clamped_cosine(l) * y[i]);
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
    lg_transfer_info ti = {
        .struct_size = sizeof ti, .bands = bands, .vertices = nv, .mode = LG_TRANSFER_UNSHADOWED
    };
    return lg_transfer_publish(n, 0, &ti);
}

/* ---- descriptors ----------------------------------------------------------------------------- */

static const char *const tp_layouts[] = { "mixed", "quad", NULL };
static const char *const tp_textures[] = { "none", "halves", "mask", NULL };
static const char *const tp_sh_modes[] = { "random", "delta", NULL };
static const char *const tp_tr_modes[] = { "random", "constant", "normal", NULL };

static const lg_param_desc tp_scene_params[] = {
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = TP_MIXED,
      .enum_values = tp_layouts,
      .doc = "mixed or quad (testprtinputs.c)" },
    { .key = "texture",
      .type = LG_PARAM_ENUM,
      .def.e = TP_TEX_NONE,
      .enum_values = tp_textures,
      .doc = "none, halves or mask: the quad's base colour texture (testprtinputs.c)" },
};
static const lg_param_desc tp_sh_params[] = {
    { .key = "bands", .type = LG_PARAM_INT, .def.i = 3, .min = 1, .max = 64, .doc = "" },
    { .key = "seed", .type = LG_PARAM_INT, .def.i = 1, .min = 0, .max = 65535, .doc = "" },
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = TP_RANDOM,
      .enum_values = tp_sh_modes,
      .doc = "" },
    { .key = "dir", .type = LG_PARAM_VEC3, .def.v = { 1, 0, 0 }, .doc = "" },
    { .key = "color",
      .type = LG_PARAM_COLOR,
      .def.v = { 1, 1, 1 },
      .min = 0,
      .max = 1e6,
      .doc = "" },
};
static const lg_param_desc tp_tr_params[] = {
    { .key = "bands", .type = LG_PARAM_INT, .def.i = 3, .min = 1, .max = 64, .doc = "" },
    { .key = "seed", .type = LG_PARAM_INT, .def.i = 2, .min = 0, .max = 65535, .doc = "" },
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = TP_RANDOM,
      .enum_values = tp_tr_modes,
      .doc = "" },
    { .key = "vertices",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1000000,
      .doc = "0 = the mixed scene's count" },
};
static const lg_port_desc tp_scene_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc tp_sh_out[] = { { .name = "lighting", .kind = LG_KIND_SH } };
static const lg_port_desc tp_tr_out[] = { { .name = "transfer", .kind = LG_KIND_TRANSFER } };
static const lg_port_desc tp_tr_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .optional = true }
};

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

LG_PLUGIN_DEFINE("testprtinputs", "1.0.0", "Scenes, lighting and transfer for the prt tests", types)
