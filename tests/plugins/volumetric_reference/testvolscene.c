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
 */
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
    uint32_t slats = (uint32_t)lg_param_int(n, "slats");
    if (slats)
        return tv_blind_publish(n, b, slats);
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
    { .key = "slats",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 64,
      .doc = "0, or the square is a blind of this many alpha-masked bands" },
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
