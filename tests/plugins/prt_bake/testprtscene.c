/*
 * Test plugin "testprtscene": scenes whose transfer is known in closed form, built in
 * memory for the prt_bake tests (tests/plugins/prt_bake/test_prt_bake.c), and a node that
 * shows a transfer resource as an image.
 *
 *   test_prt_scene     -> scene
 *   test_transfer_image  transfer -> image: coefficient k of vertex i is texel
 *                        ((i mod V) n^2 + k, i / V) = (t_R[k], t_G[k], t_B[k], 1), with
 *                        V = max(1, 1024 / n^2) vertices per row (tp_vertices_per_row), so
 *                        a test reads every coefficient from an EXR and does its own dot
 *                        products; texels past the last vertex are 0
 *   test_raw_probe     -> probe: a lat-long probe (width x width / 2) or a cube (faces of
 *                        width), every colour channel `value`, alpha 1, except texel
 *                        (bad_x, bad_y) of face bad_face (cube) whose colour channels are
 *                        `bad`: none (value), zero, nan, inf or neg_inf. Published as made,
 *                        never cleaned (the `probe` node zeroes NaN and Inf in a file's
 *                        texels, so a consumer's own handling cannot be reached through it)
 *
 * Layouts (every mesh's material 0, base colour `base_color`; all of it moved by the
 * instances' model matrix, a translation by `translate`):
 *   cone    one mesh: a pit shaped as a cone of half-angle alpha_deg about +Y with its apex
 *           at the origin, height 1, `segments` sides, its front faces (counter-clockwise)
 *           and normals facing the axis. Vertex 0 is the apex, normal +Y: it sees the sky
 *           through the opening only, sin^2(alpha) of the cosine-weighted hemisphere.
 *   box     an open box [-1, 1]^3 without its top (y = 1): five walls (meshes 0..4: floor
 *           y = -1, x = -1, x = 1, z = -1, z = 1), each a `grid` x grid quad grid with its
 *           own vertices, front faces and normals inward.
 *   quad    mesh 0: a floor y = 0, [-2, 2]^2, `grid` x grid cells, normals +Y; mesh 1: a
 *           square [-quad_size, quad_size]^2 at y = 1, front face and normals +Y (the floor
 *           sees its back) or, with quad_flip, -Y (its front).
 *   plane   mesh 0 alone: the floor of `quad` (nothing occludes it).
 *   masked  the `quad` layout (floor mesh 0, material 0; the square mesh 1 at y = 1 facing +Y)
 *           with the square on material 1, whose alpha comes from `mask`:
 *             none          opaque, no texture (the `quad` layout's occluder)
 *             checker       LG_ALPHA_MASK, cutoff 0.5, a base colour texture of
 *                           mask_cells x mask_cells texels (nearest, clamp to edge): texel
 *                           (tx, ty) has alpha 1 where (tx + ty + mask_phase) is even, else 0,
 *                           RGB texture_rgb (sRGB bytes); the square's texture coordinates
 *                           (u, v) = ((x + a) / 2a, (a - z) / 2a) (a = quad_size), so the
 *                           opaque cells are those with floor(u cells) + floor(v cells) +
 *                           mask_phase even
 *             blend         the same texture under LG_ALPHA_BLEND
 *             no_texcoords  the checker's material on a square without texture coordinates
 *                           (the filter must treat it as opaque)
 *             colour        opaque, the same texture with alpha 1 everywhere and RGB
 *                           texture_rgb on the cells `checker` makes opaque, 0 on the others
 *                           (for the bounces off a textured surface)
 *           quad_flip turns the square to face -Y (the floor then sees its front).
 *           quad_alpha is material 1's base_color[3] (the factor the texture's alpha
 *           multiplies).
 *   sphere  a UV sphere of radius 1: (segments + 1) x (segments / 2 + 1) vertices,
 *           vertex (i, j) (column i, row j, j = 0 at +Y) at index j (segments + 1) + i with
 *           normal (sin th cos ph, cos th, -sin th sin ph), th = pi j / rows, ph = 2 pi i /
 *           segments.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"
#include "lightgraph/scene.h"
#include "lightgraph/transfer.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

enum { TP_CONE = 0, TP_BOX, TP_QUAD, TP_PLANE, TP_SPHERE, TP_MASKED };
enum { TP_MASK_NONE = 0, TP_MASK_CHECKER, TP_MASK_BLEND, TP_MASK_NO_TEXCOORDS, TP_MASK_COLOUR };

/* The next mesh and its one instance, placed by `model`. */
static void tp_mesh(lg_ts_builder *b, const float model[16])
{
    lg_ts_instance(b, lg_ts_mesh(b, "test mesh", 0), model);
}

/* The cone of the `cone` layout, as the next mesh: apex + one ring at height 1. */
static void tp_cone(lg_ts_builder *b, const float model[16], double alpha, uint32_t seg)
{
    tp_mesh(b, model);
    const double apex[3] = { 0, 0, 0 }, up[3] = { 0, 1, 0 };
    lg_ts_vertex_d(b, apex, up);
    double r = tan(alpha);
    for (uint32_t i = 0; i < seg; i++) {
        double ph = 2 * LG_PI * i / seg, c = cos(ph), s = sin(ph);
        /* the wall's normal, toward the axis: (-cos a c, sin a, -cos a s) */
        const double p[3] = { r * c, 1, r * s };
        const double nn[3] = { -cos(alpha) * c, sin(alpha), -cos(alpha) * s };
        lg_ts_vertex_d(b, p, nn);
    }
    /* seen from the axis (inside), apex, ring i + 1, ring i is counter-clockwise */
    for (uint32_t i = 0; i < seg; i++)
        lg_ts_triangle(b, 0, 1 + (i + 1) % seg, 1 + i);
}

/* A g x g grid as the next mesh (lg_ts_grid_span). */
static void tp_grid(lg_ts_builder *b, const float model[16], uint32_t g, const double o[3],
                    const double U[3], const double V[3], const double nn[3], bool flip)
{
    tp_mesh(b, model);
    lg_ts_grid_span(b, g, o, U, V, nn, flip);
}

/* The masked layout's texture and texture coordinates, owned by the scene: its `textures`
 * points at `t`, the first member, so tp_masked_free finds the block from the scene. */
typedef struct tp_masked {
    lg_scene_textures t;
    lg_scene_texture tex;
    lg_scene_image img;
    lg_material_maps maps;
    uint8_t *rgba8;
    float *uv;
} tp_masked;

static void tp_masked_free(void *scene)
{
    lg_scene *s = scene;
    tp_masked *mk = (tp_masked *)s->textures;
    if (mk) {
        free(mk->rgba8);
        free(mk->uv);
        free(mk);
    }
    lg_ts_free(scene);
}

/* Publishes the masked layout: the builder's scene with material 1's maps, the checker
 * texture and mesh 1's texture coordinates attached (testprtscene.c's header). */
static int tp_masked_publish(lg_node *n, lg_ts_builder *b)
{
    int mask = lg_param_enum(n, "mask");
    uint32_t cells = (uint32_t)lg_param_int(n, "mask_cells");
    uint32_t phase = (uint32_t)lg_param_int(n, "mask_phase");
    const lg_value *rgb = lg_param(n, "texture_rgb");
    lg_scene *s = lg_ts_finish(b);
    tp_masked *mk = calloc(1, sizeof *mk);
    if (!s || !mk) {
        free(mk);
        if (s)
            lg_ts_free(s);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory building the masked scene");
    }
    lg_mesh *quad = (lg_mesh *)&s->meshes[1];
    lg_material *m1 = (lg_material *)&s->materials[1];
    mk->rgba8 = malloc((size_t)cells * cells * 4);
    mk->uv = malloc((size_t)quad->n_vertices * 2 * sizeof(float));
    if (!mk->rgba8 || !mk->uv) {
        free(mk->rgba8);
        free(mk->uv);
        free(mk);
        lg_ts_free(s);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory building the masked scene");
    }
    for (uint32_t ty = 0; ty < cells; ty++)
        for (uint32_t tx = 0; tx < cells; tx++) {
            uint8_t *p = mk->rgba8 + 4 * ((size_t)ty * cells + tx);
            bool on = (tx + ty + phase) % 2 == 0;
            for (int c = 0; c < 3; c++)
                p[c] = mask == TP_MASK_COLOUR && !on ? 0 : (uint8_t)lround(255.0 * rgb->v[c]);
            p[3] = on || mask == TP_MASK_COLOUR ? 255 : 0;
        }
    /* the square's vertices are lg_ts_grid_span's (i, j) = (column, row) of a 1 x 1 grid */
    for (uint32_t v = 0; v < quad->n_vertices; v++) {
        mk->uv[2 * v] = (float)(v % 2);
        mk->uv[2 * v + 1] = (float)(v / 2);
    }
    mk->img = (lg_scene_image){
        .name = "test checker", .width = cells, .height = cells, .rgba8 = mk->rgba8
    };
    mk->tex = (lg_scene_texture){ .image = 0,
                                  .mag_filter = LG_TEX_NEAREST,
                                  .min_filter = LG_TEX_NEAREST,
                                  .wrap_s = LG_TEX_CLAMP_TO_EDGE,
                                  .wrap_t = LG_TEX_CLAMP_TO_EDGE };
    mk->t = (lg_scene_textures){ .images = &mk->img,
                                 .n_images = 1,
                                 .textures = &mk->tex,
                                 .n_textures = 1,
                                 .bytes = (uint64_t)cells * cells * 4 };
    mk->maps = *lg_material_maps_default();
    if (mask != TP_MASK_NONE) {
        mk->maps.base_color.texture = 0;
        mk->maps.alpha_mode = mask == TP_MASK_BLEND    ? LG_ALPHA_BLEND
                              : mask == TP_MASK_COLOUR ? LG_ALPHA_OPAQUE
                                                       : LG_ALPHA_MASK;
        mk->maps.alpha_cutoff = 0.5f;
        m1->maps = &mk->maps;
    }
    m1->base_color[3] = (float)lg_param_float(n, "quad_alpha");
    if (mask != TP_MASK_NO_TEXCOORDS)
        quad->texcoords = mk->uv;
    s->textures = &mk->t;
    lg_scene_compute_features(s);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &s->features, s, tp_masked_free);
}

static int tp_prepare(lg_node *n)
{
    lg_ts_builder *b = lg_ts_begin("test_prt_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    uint32_t grid = (uint32_t)lg_param_int(n, "grid"), seg = (uint32_t)lg_param_int(n, "segments");
    const lg_value *bc = lg_param(n, "base_color");
    lg_material *m = lg_ts_material(b, "test");
    m->kd = 1.0f;
    for (int c = 0; c < 3; c++)
        m->base_color[c] = m->od[c] = (float)bc->v[c];
    m->base_color[3] = 1.0f;
    lg_ts_camera(b, "test", lg_v3(0, 0, 5), lg_v3(0, 0, 0), lg_v3(0, 1, 0), 0.8f, 0.1f, 50.0f);
    /* every mesh's one instance: a translation by `translate` */
    const lg_value *tr = lg_param(n, "translate");
    float model[16];
    lg_m4_identity(model);
    for (int k = 0; k < 3; k++)
        model[12 + k] = (float)tr->v[k];

    if (layout == TP_CONE) {
        tp_cone(b, model, lg_param_float(n, "alpha_deg") * LG_PI / 180.0, seg);
    } else if (layout == TP_BOX) {
        /* o, U, V, inward normal; U x V must point inward (else flip) */
        static const double w[5][4][3] = {
            { { -1, -1, -1 }, { 0, 0, 2 }, { 2, 0, 0 }, { 0, 1, 0 } }, /* floor: z x x = +y */
            { { -1, -1, -1 }, { 0, 2, 0 }, { 0, 0, 2 }, { 1, 0, 0 } }, /* x = -1: y x z = +x */
            { { 1, -1, -1 }, { 0, 0, 2 }, { 0, 2, 0 }, { -1, 0, 0 } }, /* x = 1: z x y = -x */
            { { -1, -1, -1 }, { 2, 0, 0 }, { 0, 2, 0 }, { 0, 0, 1 } }, /* z = -1: x x y = +z */
            { { -1, -1, 1 }, { 0, 2, 0 }, { 2, 0, 0 }, { 0, 0, -1 } }, /* z = 1: y x x = -z */
        };
        for (int k = 0; k < 5; k++)
            tp_grid(b, model, grid, w[k][0], w[k][1], w[k][2], w[k][3], false);
    } else if (layout == TP_MASKED) {
        lg_material *m1 = lg_ts_material(b, "test masked");
        m1->kd = 1.0f;
        for (int c = 0; c < 3; c++)
            m1->base_color[c] = m1->od[c] = (float)bc->v[c];
        static const double o[3] = { -2, 0, 2 }, U[3] = { 4, 0, 0 }, V[3] = { 0, 0, -4 },
                            up[3] = { 0, 1, 0 };
        tp_grid(b, model, grid, o, U, V, up, false);
        double a = lg_param_float(n, "quad_size");
        double qo[3] = { -a, 1, a }, qU[3] = { 2 * a, 0, 0 }, qV[3] = { 0, 0, -2 * a };
        bool flip = lg_param_bool(n, "quad_flip");
        double qn[3] = { 0, flip ? -1 : 1, 0 };
        lg_ts_instance(b, lg_ts_mesh(b, "test masked square", 1), model);
        lg_ts_grid_span(b, 1, qo, qU, qV, qn, flip);
        return tp_masked_publish(n, b);
    } else if (layout == TP_QUAD || layout == TP_PLANE) {
        static const double o[3] = { -2, 0, 2 }, U[3] = { 4, 0, 0 }, V[3] = { 0, 0, -4 },
                            up[3] = { 0, 1, 0 };
        tp_grid(b, model, grid, o, U, V, up, false); /* x x -z = +y */
        if (layout == TP_QUAD) {
            double a = lg_param_float(n, "quad_size");
            bool flip = lg_param_bool(n, "quad_flip");
            double qo[3] = { -a, 1, a }, qU[3] = { 2 * a, 0, 0 }, qV[3] = { 0, 0, -2 * a };
            double qn[3] = { 0, flip ? -1 : 1, 0 };
            tp_grid(b, model, 1, qo, qU, qV, qn, flip);
        }
    } else {
        tp_mesh(b, model);
        lg_ts_uv_sphere(b, NULL, 1.0f, seg, seg / 2 < 2 ? 2 : seg / 2);
    }
    return lg_ts_publish(n, 0, b);
}

static int tp_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- test_transfer_image --------------------------------------------------------------------- */

static uint32_t tp_vertices_per_row(uint32_t n2)
{
    return n2 >= 1024 ? 1 : 1024 / n2;
}

static int ti_prepare(lg_node *n)
{
    const lg_resource *in = lg_input(n, 0);
    const lg_resource *part = in ? lg_part(n, in, "transfer") : NULL;
    lg_resource_info info;
    if (!part || lg_describe(part, &info, n) != 0)
        return lg_error(n, "input 'transfer' has no transfer part");
    uint32_t bands = (uint32_t)lg_param_int(n, "bands"), n2 = bands * bands;
    size_t per = (size_t)12 * n2;
    if (info.buffer.size == 0 || info.buffer.size % per)
        return lg_error(n, "the transfer's %zu bytes are not a whole number of %u-band vertices",
                        info.buffer.size, bands);
    size_t nv = info.buffer.size / per, V = tp_vertices_per_row(n2);
    lg_image_desc d = { .width = (uint32_t)(V * n2),
                        .height = (uint32_t)((nv + V - 1) / V),
                        .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int ti_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_transfer tv;
    const lg_transfer *tr = lg_transfer_get(n, lg_input(n, 0), &tv);
    if (!tr)
        return lg_error(n, "input 'transfer' is not a transfer");
    uint32_t bands = (uint32_t)lg_param_int(n, "bands"), n2 = bands * bands;
    if (tr->info.bands != bands)
        return lg_error(n, "the transfer has %u bands, the node was told %u", tr->info.bands,
                        bands);
    lg_cpu_view in, out;
    int rc = lg_map_cpu(n, tr->transfer, LG_READ, &in);
    if (rc)
        return rc;
    rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &out);
    if (rc)
        return rc;
    const float *t = in.pixels;
    float *o = out.pixels;
    uint32_t V = tp_vertices_per_row(n2);
    size_t rows = (tr->info.vertices + V - 1) / V;
    memset(o, 0, rows * V * n2 * 4 * sizeof(float));
    for (uint32_t i = 0; i < tr->info.vertices; i++)
        for (uint32_t k = 0; k < n2; k++) {
            float *p = o + 4 * ((size_t)(i / V) * V * n2 + (size_t)(i % V) * n2 + k);
            for (int c = 0; c < 3; c++)
                p[c] = t[(size_t)i * 3 * n2 + (size_t)c * n2 + k];
            p[3] = 1.0f;
        }
    lg_log(n, LG_LOG_INFO, "transfer: %u vertices, %u bands, mode %d, %u bounces",
           tr->info.vertices, tr->info.bands, (int)tr->info.mode, tr->info.bounces);
    return 0;
}

/* ---- test_raw_probe -------------------------------------------------------------------------- */

static bool rp_cube(lg_node *n)
{
    return lg_param_bool(n, "cube");
}

static int rp_prepare(lg_node *n)
{
    uint32_t w = (uint32_t)lg_param_int(n, "width");
    bool cube = rp_cube(n);
    lg_image_desc d = { .width = w,
                        .height = cube ? w : w / 2,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = cube ? LG_IMAGE_CUBE : 0 };
    if ((uint32_t)lg_param_int(n, "bad_x") >= d.width ||
        (uint32_t)lg_param_int(n, "bad_y") >= d.height)
        return lg_error(n, "bad_x, bad_y = %d, %d: outside the %ux%u image",
                        (int)lg_param_int(n, "bad_x"), (int)lg_param_int(n, "bad_y"), d.width,
                        d.height);
    int rc = lg_probe_declare(n, 0, cube ? LG_PROBE_CUBE : LG_PROBE_LATLONG, &d, false);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int rp_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    bool cube = rp_cube(n);
    const lg_resource *rad = lg_part(n, lg_output(n, 0), "radiance");
    lg_resource_info info;
    lg_cpu_view v;
    int rc;
    if (!rad)
        return lg_error(n, "the probe has no radiance part");
    if ((rc = lg_describe(rad, &info, n)) || (rc = lg_map_cpu(n, rad, LG_WRITE, &v)))
        return rc;
    uint32_t W = info.image.width, H = info.image.height, faces = cube ? 6 : 1;
    float value = (float)lg_param_float(n, "value");
    float *p = v.pixels;
    for (size_t i = 0; i < (size_t)W * H * faces; i++) {
        p[4 * i] = p[4 * i + 1] = p[4 * i + 2] = value;
        p[4 * i + 3] = 1.0f;
    }
    static const float bad_values[] = { 0.0f, 0.0f, NAN, INFINITY, -INFINITY };
    int bad = lg_param_enum(n, "bad");
    if (bad > 0) {
        uint32_t face = cube ? (uint32_t)lg_param_int(n, "bad_face") : 0;
        float *q = p + 4 * ((size_t)face * W * H + (size_t)lg_param_int(n, "bad_y") * W +
                            (size_t)lg_param_int(n, "bad_x"));
        q[0] = q[1] = q[2] = bad_values[bad];
    }
    lg_probe_info pi = { .struct_size = sizeof pi,
                         .layout = cube ? LG_PROBE_CUBE : LG_PROBE_LATLONG,
                         .scale = 1 };
    pi.rotation[0] = pi.rotation[4] = pi.rotation[8] = 1;
    return lg_probe_publish(n, 0, &pi);
}

static const char *const rp_bad[] = { "none", "zero", "nan", "inf", "neg_inf", NULL };

static const lg_param_desc rp_params[] = {
    { .key = "width", .type = LG_PARAM_INT, .def.i = 32, .min = 2, .max = 1024, .doc = "" },
    { .key = "cube", .type = LG_PARAM_BOOL, .def.b = false, .doc = "" },
    { .key = "value", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0, .max = 1e6, .doc = "" },
    { .key = "bad", .type = LG_PARAM_ENUM, .def.e = 0, .enum_values = rp_bad, .doc = "" },
    { .key = "bad_x", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 1023, .doc = "" },
    { .key = "bad_y", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 1023, .doc = "" },
    { .key = "bad_face", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 5, .doc = "" },
};
static const lg_port_desc rp_out[] = { { .name = "probe", .kind = LG_KIND_PROBE } };

static const char *const tp_layouts[] = {
    "cone", "box", "quad", "plane", "sphere", "masked", NULL
};
static const char *const tp_masks[] = {
    "none", "checker", "blend", "no_texcoords", "colour", NULL
};

static const lg_param_desc tp_params[] = {
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = tp_layouts,
      .doc = "cone, box, quad, plane, sphere or masked (testprtscene.c)" },
    { .key = "alpha_deg", .type = LG_PARAM_FLOAT, .def.f = 45, .min = 1, .max = 89, .doc = "" },
    { .key = "segments", .type = LG_PARAM_INT, .def.i = 64, .min = 3, .max = 4096, .doc = "" },
    { .key = "grid", .type = LG_PARAM_INT, .def.i = 4, .min = 1, .max = 256, .doc = "" },
    { .key = "quad_size", .type = LG_PARAM_FLOAT, .def.f = 0.5, .min = 0.01, .max = 10, .doc = "" },
    { .key = "quad_flip", .type = LG_PARAM_BOOL, .def.b = false, .doc = "" },
    { .key = "base_color",
      .type = LG_PARAM_COLOR,
      .def.v = { 1, 1, 1 },
      .min = 0,
      .max = 10,
      .doc = "" },
    { .key = "translate", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 0 }, .doc = "" },
    { .key = "mask", .type = LG_PARAM_ENUM, .def.e = 1, .enum_values = tp_masks, .doc = "" },
    { .key = "mask_cells", .type = LG_PARAM_INT, .def.i = 4, .min = 1, .max = 256, .doc = "" },
    { .key = "mask_phase", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 1, .doc = "" },
    { .key = "texture_rgb",
      .type = LG_PARAM_COLOR,
      .def.v = { 1, 1, 1 },
      .min = 0,
      .max = 1,
      .doc = "" },
    { .key = "quad_alpha", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0, .max = 1, .doc = "" },
};
static const lg_port_desc tp_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };

static const lg_param_desc ti_params[] = {
    { .key = "bands", .type = LG_PARAM_INT, .def.i = 3, .min = 1, .max = 64, .doc = "" },
};
static const lg_port_desc ti_in[] = { { .name = "transfer", .kind = LG_KIND_TRANSFER } };
static const lg_port_desc ti_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_prt_scene",
        .doc = "A small scene built in memory for the prt_bake tests",
        LG_PARAMS(tp_params),
        LG_OUTPUTS(tp_out),
        .prepare = tp_prepare,
        .execute = tp_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_transfer_image",
        .doc = "A transfer's coefficients as an image (bands^2 x vertices)",
        LG_PARAMS(ti_params),
        LG_INPUTS(ti_in),
        LG_OUTPUTS(ti_out),
        .prepare = ti_prepare,
        .execute = ti_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_raw_probe",
        .doc = "A constant probe with one texel set to 0, NaN or an infinity, never cleaned",
        LG_PARAMS(rp_params),
        LG_OUTPUTS(rp_out),
        .prepare = rp_prepare,
        .execute = rp_execute,
    },
};

LG_PLUGIN_DEFINE("testprtscene", "1.0.0", "Scenes and a transfer viewer for the prt_bake tests",
                 types)
