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
 * Materials: reflectivity, roughness, metallic and double_sided from the parameters
 * (spheres: the roughness of each sphere's own material).
 *
 * Textures (`texture`, on the quad; its TEXCOORD_0 (u, v) runs over [0, 1]^2 from the
 * top-left corner as the camera sees it, nearest filtering, clamped):
 *   roughness_halves  metallic-roughness 2x1: G = 255 on the left half, 64 on the right
 *                     (roughness factor x 1 and x 64/255), B = 255
 *   metal_halves      base colour 2x1 (sRGB): (255, 0, 0) left, (0, 188, 255) right; the
 *                     material a metal (metallic 1, base colour factor 1)
 *   mask_hole         base colour 2x2, white, alpha 0 in the top-left texel, 255 elsewhere;
 *                     alpha MASK, cutoff 0.5: a hole in the top-left quarter
 *   normal_tilt       normal 1x1 texel `normal_texel` (bytes), tangent +X (w +1)
 *   bad_index         base colour texture index 7 of a scene with one texture (out of
 *                     range: read as no texture) One camera (camera_position, camera_target,
 * camera_up, yfov_deg; znear 0.1, zfar 50).
 */
#include <math.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"
#include "common/testtextures.h"

enum { TI_SPHERE = 0, TI_QUAD, TI_SPHERES, TI_NONE };
enum { TT_NONE = 0, TT_ROUGH_HALVES, TT_METAL_HALVES, TT_MASK_HOLE, TT_NORMAL_TILT, TT_BAD_INDEX };

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

/* The quad's textures (the header says which). */
static int ti_textures(lg_node *n, lg_tt_scene *t, int texture)
{
    /* the quad's corners as the camera on +Z sees them: (u, v) = (0, 0) top-left (the
     * default quad_normal +Z: its u axis is +X, w axis +Y) */
    const float origin[3] = { -1, 1, 0 }, du[3] = { 0.5f, 0, 0 }, dv[3] = { 0, -0.5f, 0 };
    lg_material_maps *mm = lg_tt_maps(t, 0);
    bool ok = lg_tt_planar_uv(t, 0, origin, du, dv);
    uint32_t img = UINT32_MAX;
    if (texture == TT_ROUGH_HALVES) {
        static const uint8_t px[8] = { 0, 255, 255, 255, 0, 64, 255, 255 };
        img = lg_tt_image(t, "roughness halves", 2, 1, px);
        mm->metallic_roughness.texture = lg_tt_texture(t, img, LG_TEX_NEAREST,
                                                       LG_TEX_CLAMP_TO_EDGE);
    } else if (texture == TT_METAL_HALVES) {
        static const uint8_t px[8] = { 255, 0, 0, 255, 0, 188, 255, 255 };
        img = lg_tt_image(t, "metal halves", 2, 1, px);
        mm->base_color.texture = lg_tt_texture(t, img, LG_TEX_NEAREST, LG_TEX_CLAMP_TO_EDGE);
        t->materials[0].metallic = 1.0f;
    } else if (texture == TT_MASK_HOLE) {
        static const uint8_t px[16] = { 255, 255, 255, 0,   255, 255, 255, 255,
                                        255, 255, 255, 255, 255, 255, 255, 255 };
        img = lg_tt_image(t, "mask hole", 2, 2, px);
        mm->base_color.texture = lg_tt_texture(t, img, LG_TEX_NEAREST, LG_TEX_CLAMP_TO_EDGE);
        mm->alpha_mode = LG_ALPHA_MASK;
        mm->alpha_cutoff = 0.5f;
    } else if (texture == TT_NORMAL_TILT) {
        const lg_value *v = lg_param(n, "normal_texel");
        uint8_t px[4] = { 128, 128, 255, 255 };
        for (int c = 0; v && c < 3; c++)
            px[c] = (uint8_t)v->v[c];
        img = lg_tt_image(t, "normal tilt", 1, 1, px);
        mm->normal.texture = lg_tt_texture(t, img, LG_TEX_NEAREST, LG_TEX_CLAMP_TO_EDGE);
        const float tangent[4] = { 1, 0, 0, 1 };
        ok = ok && lg_tt_tangents(t, 0, tangent);
    } else if (texture == TT_BAD_INDEX) {
        static const uint8_t px[4] = { 0, 0, 0, 255 };
        img = lg_tt_image(t, "unused", 1, 1, px);
        lg_tt_texture(t, img, LG_TEX_NEAREST, LG_TEX_CLAMP_TO_EDGE);
        mm->base_color.texture = 7;
        t->materials[0].metallic = 1.0f;
    }
    if (!ok || img == UINT32_MAX) {
        lg_tt_free(t);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    return lg_tt_publish(n, 0, t);
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
        m->metallic = (float)lg_param_float(n, "metallic");
        m->base_color[0] = m->base_color[1] = m->base_color[2] = m->base_color[3] = 1.0f;
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
    int texture = lg_param_enum(n, "texture");
    if (texture == TT_NONE)
        return lg_ts_publish(n, 0, b);
    if (layout != TI_QUAD)
        return lg_error(n, "texture: only the quad layout has textures");
    lg_tt_scene *t = lg_tt_wrap(lg_ts_finish(b));
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    return ti_textures(n, t, texture);
}

static int ti_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const char *const ti_layouts[] = { "sphere", "quad", "spheres", "none", NULL };
static const char *const ti_textures_names[] = { "none",      "roughness_halves", "metal_halves",
                                                 "mask_hole", "normal_tilt",      "bad_index",
                                                 NULL };

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
    { .key = "metallic", .type = LG_PARAM_FLOAT, .def.f = 0, .min = 0, .max = 1, .doc = "" },
    { .key = "texture",
      .type = LG_PARAM_ENUM,
      .def.e = TT_NONE,
      .enum_values = ti_textures_names,
      .doc = "the quad's textures (testiblscene.c)" },
    { .key = "normal_texel",
      .type = LG_PARAM_VEC3,
      .def.v = { 128, 128, 255 },
      .doc = "normal_tilt: the texel's bytes" },
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
