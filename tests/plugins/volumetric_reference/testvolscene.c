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
 *
 * slats = N > 0 makes the square a venetian blind: LG_ALPHA_MASK (cutoff 0.5) with a base
 * colour texture of 1 x N texels (nearest, clamp), row r opaque (alpha 1) when r is even,
 * clear (alpha 0) when odd; texture coordinates (u, v) = ((x + half) / 2 half, (half - y) /
 * 2 half), so the slat at height y is row floor(v N): N horizontal bands from the top, the
 * first opaque.
 *
 * Since issue 25 (the point and spot light, heterogeneous medium and multiple-scattering
 * cases):
 *   cube = c > 0    adds a closed box of half-edge c (12 triangles, both faces occlude)
 *                   centred at cube_centre: a light inside it is fully occluded
 *   medium = true   the scene carries its own medium (density 1, `scattering`,
 *                   `absorption`, `g`), so that a graph without scene_tools' `medium` node
 *                   keeps the density field below (that node replaces the medium)
 *   field           none (homogeneous), uniform (kind UNIFORM, unbounded), box (UNIFORM
 *                   inside [lo, hi]) or height (UNIFORM, unbounded, height fog
 *                   exp(-falloff (y - base_y))): lg_medium.field, owned by the scene
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

/* The blind's texture and texture coordinates, owned by the scene (its `textures` points
 * at the first member; tv_blind_free finds the block from it). */
typedef struct tv_blind {
    lg_scene_textures t;
    lg_scene_texture tex;
    lg_scene_image img;
    lg_material_maps maps;
    uint8_t *rgba8;
    float uv[8];
} tv_blind;

static void tv_blind_free(void *scene)
{
    lg_scene *s = scene;
    tv_blind *bl = (tv_blind *)s->textures;
    if (bl) {
        free(bl->rgba8);
        free(bl);
    }
    lg_ts_free(scene);
}

static int tv_blind_publish(lg_node *n, lg_ts_builder *b, uint32_t slats)
{
    lg_scene *s = lg_ts_finish(b);
    tv_blind *bl = calloc(1, sizeof *bl);
    uint8_t *px = malloc((size_t)slats * 4);
    if (!s || !bl || !px) {
        free(bl);
        free(px);
        if (s)
            lg_ts_free(s);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    for (uint32_t r = 0; r < slats; r++) {
        px[4 * r] = px[4 * r + 1] = px[4 * r + 2] = 200;
        px[4 * r + 3] = r % 2 == 0 ? 255 : 0;
    }
    /* lg_ts_quad's corners: (-h, -h), (h, -h), (h, h), (-h, h) */
    static const float uv[8] = { 0, 1, 1, 1, 1, 0, 0, 0 };
    memcpy(bl->uv, uv, sizeof uv);
    bl->rgba8 = px;
    bl->img = (lg_scene_image){ .name = "test blind", .width = 1, .height = slats, .rgba8 = px };
    bl->tex = (lg_scene_texture){ .mag_filter = LG_TEX_NEAREST,
                                  .min_filter = LG_TEX_NEAREST,
                                  .wrap_s = LG_TEX_CLAMP_TO_EDGE,
                                  .wrap_t = LG_TEX_CLAMP_TO_EDGE };
    bl->t = (lg_scene_textures){ .images = &bl->img,
                                 .n_images = 1,
                                 .textures = &bl->tex,
                                 .n_textures = 1,
                                 .bytes = (uint64_t)slats * 4 };
    bl->maps = *lg_material_maps_default();
    bl->maps.base_color.texture = 0;
    bl->maps.alpha_mode = LG_ALPHA_MASK;
    bl->maps.alpha_cutoff = 0.5f;
    ((lg_material *)&s->materials[0])->maps = &bl->maps;
    ((lg_mesh *)&s->meshes[0])->texcoords = bl->uv;
    s->textures = &bl->t;
    lg_scene_compute_features(s);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &s->features, s, tv_blind_free);
}

/* The scene of lg_ts_finish with a density field owned beside it (tv_field_free). */
static void tv_field_free(void *scene)
{
    lg_scene *s = scene;
    free((void *)s->medium.field);
    lg_ts_free(scene);
}

static int tv_vec3(lg_node *n, const char *key, float out[3])
{
    const lg_value *v = lg_param(n, key);
    for (int c = 0; c < 3; c++) {
        out[c] = (float)v->v[c];
        if (!isfinite(out[c]))
            return lg_error(n, "%s: component %d is not finite", key, c);
    }
    return 0;
}

/* The medium and its field on a finished builder; publishes. */
static int tv_medium_publish(lg_node *n, lg_ts_builder *b)
{
    float sc[3], ab[3];
    int rc;
    if ((rc = tv_vec3(n, "scattering", sc)) || (rc = tv_vec3(n, "absorption", ab))) {
        lg_ts_abandon(b);
        return rc;
    }
    lg_ts_medium(b, 1.0f, lg_v3(sc[0], sc[1], sc[2]), lg_v3(ab[0], ab[1], ab[2]),
                 (float)lg_param_float(n, "g"));
    int kind = lg_param_enum(n, "field");
    if (kind == 0)
        return lg_ts_publish(n, 0, b);
    lg_scene *s = lg_ts_finish(b);
    lg_density_field *f = calloc(1, sizeof *f);
    if (!s || !f) {
        free(f);
        if (s)
            lg_ts_free(s);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    f->kind = LG_FIELD_UNIFORM;
    for (int c = 0; c < 3; c++) {
        f->bounds_min[c] = -FLT_MAX;
        f->bounds_max[c] = FLT_MAX;
    }
    if (kind == 2 &&
        ((rc = tv_vec3(n, "lo", f->bounds_min)) || (rc = tv_vec3(n, "hi", f->bounds_max)))) {
        free(f);
        lg_ts_free(s);
        return rc;
    }
    if (kind == 3) {
        f->height_falloff = (float)lg_param_float(n, "falloff");
        f->height_base = (float)lg_param_float(n, "base_y");
    }
    s->medium.field = f;
    lg_scene_compute_features(s);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &s->features, s, tv_field_free);
}

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
    double cube = lg_param_float(n, "cube");
    if (cube > 0.0) {
        float cc[3];
        int rc = tv_vec3(n, "cube_centre", cc);
        if (rc) {
            lg_ts_abandon(b);
            return rc;
        }
        float model[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, cc[0], cc[1], cc[2], 1 };
        uint32_t me = lg_ts_mesh(b, "test cube", 0);
        lg_ts_box(b, lg_v3((float)cube, (float)cube, (float)cube));
        lg_ts_instance(b, me, model);
    }
    uint32_t slats = (uint32_t)lg_param_int(n, "slats");
    if (slats)
        return tv_blind_publish(n, b, slats);
    if (lg_param_bool(n, "medium"))
        return tv_medium_publish(n, b);
    return lg_ts_publish(n, 0, b);
}

static int tv_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const char *const tv_fields[] = { "none", "uniform", "box", "height", NULL };
static const lg_param_desc tv_params[] = {
    { .key = "half",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 1e6,
      .doc = "half the square's edge" },
    { .key = "slats",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 64,
      .doc = "0, or the square is a blind of this many alpha-masked bands" },
    { .key = "cube",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.0,
      .min = 0,
      .max = 1e6,
      .doc = "0, or the half-edge of a closed box centred at cube_centre" },
    { .key = "cube_centre",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "the box's centre" },
    { .key = "medium",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "the scene carries its own medium (density 1) and the field below" },
    { .key = "scattering", .type = LG_PARAM_VEC3, .def.v = { 0.1, 0.1, 0.1 }, .doc = "1/m" },
    { .key = "absorption", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 0 }, .doc = "1/m" },
    { .key = "g", .type = LG_PARAM_FLOAT, .def.f = 0, .min = -0.99, .max = 0.99, .doc = "HG g" },
    { .key = "field",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = tv_fields,
      .doc = "none, uniform, box (in [lo, hi]) or height (fog falling off above base_y)" },
    { .key = "lo", .type = LG_PARAM_VEC3, .def.v = { -1, -1, -1 }, .doc = "box: lower corner" },
    { .key = "hi", .type = LG_PARAM_VEC3, .def.v = { 1, 1, 1 }, .doc = "box: upper corner" },
    { .key = "falloff",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e3,
      .doc = "height: 1/m" },
    { .key = "base_y",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -1e6,
      .max = 1e6,
      .doc = "height: where the multiplier is 1" },
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
