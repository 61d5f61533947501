/*
 * Test plugin "testpolyshadow": shadow maps of a scene's point and spot lights written by
 * hand on the CPU, in lightgraph/shadowmap.h's 3.2 layout, for volumetric_polygonal's tests
 * until the shadowmap node makes perspective maps (and after, as a producer independent of
 * it). Its depths are exact: each texel's ray from the light is intersected here with the
 * occluders of testphongscene's layouts, analytically.
 *
 *   test_poly_shadow { scene } -> shadow
 *
 * Records, in the scene's light order (directional lights get none: unshadowed):
 *   spot    one perspective record (face 0), looking along the spot's axis, its vertical
 *           and horizontal field of view 2 outer_cone + 2 margin_deg, znear, zfar
 *   point   six perspective records of 90 degrees, faces 0 .. 5 along +x, -x, +y, -y, +z,
 *           -z (a cube map's order and up vectors)
 * Tiles of `resolution` side side by side in one row of the atlas (tile_y 0).
 *
 * Occluders (`occluders`): none (an empty map: every texel 1, an unshadowed cone); floor
 * (testphongscene's plane: y = 0, |x|, |z| <= floor_half); shadow (the floor and the 1 x 1
 * quad at y = 1 of testphongscene's `shadow` layout). A texel's depth is the window depth
 * of the nearest hit of the ray through its centre, 1 where it hits nothing before zfar.
 * `defect` makes maps a consumer must refuse: paraboloid (a point light's two
 * dual-paraboloid records, faces 16 and 17), offcentre (every record's frustum centred
 * 0.5 beside the light), short (a point light with one record only).
 *
 *   test_poly_field_scene -> scene
 *
 * A heterogeneous scene: testphongscene's plane (edge 10), one point light at [0, 2, 0]
 * and a medium with a height-fog density field (lg_medium.field), which volumetric_polygonal
 * must refuse.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/shadowmap.h"
#include "lightgraph/vecmath.h"

#include "common/testscene.h"

enum { TPS_NONE = 0, TPS_FLOOR, TPS_SHADOW };
enum { TPS_OK = 0, TPS_PARABOLOID, TPS_OFFCENTRE, TPS_SHORT };

typedef struct tps_state {
    uint32_t n_records;
} tps_state;

/* Records of a point light: six, two (paraboloid) or one (short). */
static uint32_t tps_point_faces(int defect)
{
    return defect == TPS_PARABOLOID ? 2 : defect == TPS_SHORT ? 1 : 6;
}

static uint32_t tps_records(const lg_scene *s, int defect)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->n_lights; i++)
        n += s->lights[i].type == LG_LIGHT_POINT  ? tps_point_faces(defect)
             : s->lights[i].type == LG_LIGHT_SPOT ? 1
                                                  : 0;
    return n;
}

static int tps_create(lg_node *n)
{
    return lg_create_state(n, sizeof(tps_state)) ? 0 : LG_ERR_NOMEM;
}

static int tps_prepare(lg_node *n)
{
    tps_state *st = n->user;
    lg_assert_input(n, 0);
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    uint32_t R = (uint32_t)lg_param_int(n, "resolution");
    st->n_records = tps_records(s, lg_param_enum(n, "defect"));
    uint32_t tiles = st->n_records ? st->n_records : 1;
    int rc = lg_shadowmap_declare(n, 0, R * tiles, R, st->n_records);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

/* Distance along (o, d) to the square y = y0, |x|, |z| <= h, or INFINITY. */
static double tps_square(double y0, double h, const double o[3], const double d[3])
{
    if (d[1] == 0.0)
        return INFINITY;
    double t = (y0 - o[1]) / d[1];
    if (!(t > 0.0))
        return INFINITY;
    double x = o[0] + t * d[0], z = o[2] + t * d[2];
    return fabs(x) <= h && fabs(z) <= h ? t : INFINITY;
}

/* Light NDC -> world through inv, in double. */
static void tps_unproject(const float inv[16], double x, double y, double z, double out[3])
{
    double h[4];
    for (int r = 0; r < 4; r++)
        h[r] = inv[r] * x + inv[4 + r] * y + inv[8 + r] * z + inv[12 + r];
    for (int r = 0; r < 3; r++)
        out[r] = h[r] / h[3];
}

static int tps_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    tps_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    uint32_t R = (uint32_t)lg_param_int(n, "resolution");
    int occ = lg_param_enum(n, "occluders");
    double zn = lg_param_float(n, "znear"), zf = lg_param_float(n, "zfar");
    double margin = lg_param_float(n, "margin_deg") * LG_PI / 180.0;
    double floor_half = lg_param_float(n, "floor_half");
    int defect = lg_param_enum(n, "defect");
    if (!(zf > zn) || !(zn > 0.0))
        return lg_error(n, "znear = %g, zfar = %g: give 0 < znear < zfar", zn, zf);
    uint32_t tiles = st->n_records ? st->n_records : 1, aw = R * tiles;
    const lg_resource *atlas = lg_part(n, lg_output(n, 0), "atlas");
    lg_cpu_view v;
    int rc = atlas ? lg_map_cpu(n, atlas, LG_WRITE, &v) : lg_error(n, "no atlas part");
    if (rc)
        return rc;
    for (size_t i = 0; i < (size_t)aw * R; i++)
        v.depth[i] = 1.0f;
    lg_shadow_light *recs = calloc(tiles, sizeof *recs);
    if (!recs)
        return LG_ERR_NOMEM;
    /* a cube map's view directions and up vectors, faces +x, -x, +y, -y, +z, -z */
    static const float dirs[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                      { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
    static const float ups[6][3] = { { 0, -1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
                                     { 0, 0, -1 }, { 0, -1, 0 }, { 0, -1, 0 } };
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->n_lights; i++) {
        const lg_light *L = &s->lights[i];
        if (L->type != LG_LIGHT_POINT && L->type != LG_LIGHT_SPOT)
            continue;
        uint32_t faces = L->type == LG_LIGHT_POINT ? tps_point_faces(defect) : 1;
        lg_vec3 q = lg_v3(L->position[0], L->position[1], L->position[2]);
        if (defect == TPS_OFFCENTRE)
            q.x += 0.5f;
        for (uint32_t fc = 0; fc < faces; fc++, k++) {
            lg_shadow_light *r = &recs[k];
            lg_vec3 dir, up;
            float fov;
            if (L->type == LG_LIGHT_SPOT) {
                dir = lg_v3_normalize_or(lg_v3(L->direction[0], L->direction[1], L->direction[2]),
                                         lg_v3(0, -1, 0));
                up = fabsf(dir.y) < 0.9f ? lg_v3(0, 1, 0) : lg_v3(1, 0, 0);
                fov = (float)(2.0 * (L->outer_cone + margin));
            } else {
                dir = lg_v3(dirs[fc][0], dirs[fc][1], dirs[fc][2]);
                up = lg_v3(ups[fc][0], ups[fc][1], ups[fc][2]);
                fov = (float)(LG_PI / 2.0);
            }
            lg_m4_look_at(r->view, q, lg_v3_add(q, dir), up);
            lg_m4_perspective(r->proj, fov, 1.0f, (float)zn, (float)zf);
            lg_m4_mul(r->view_proj, r->proj, r->view);
            r->light = i;
            r->tile_x = k * R;
            r->tile_y = 0;
            r->texel_world = (float)(2.0 * tan(fov * 0.5) / R);
            r->depth_range = (float)(zf - zn);
            r->projection = LG_SHADOW_PERSPECTIVE;
            r->face = defect == TPS_PARABOLOID ? LG_SHADOW_FACE_PARABOLOID_FRONT + fc : fc;
            r->znear = (float)zn;
            float inv[16];
            if (occ == TPS_NONE || lg_m4_invert(inv, r->view_proj) != 0)
                continue;
            const double o[3] = { q.x, q.y, q.z };
            for (uint32_t ty = 0; ty < R; ty++)
                for (uint32_t tx = 0; tx < R; tx++) {
                    double x = 2.0 * (tx + 0.5) / R - 1.0, y = 2.0 * (ty + 0.5) / R - 1.0;
                    double pn[3], d[3];
                    tps_unproject(inv, x, y, -1.0, pn);
                    for (int c = 0; c < 3; c++)
                        d[c] = pn[c] - o[c];
                    double t = tps_square(0.0, floor_half, o, d);
                    if (occ == TPS_SHADOW)
                        t = fmin(t, tps_square(1.0, 0.5, o, d));
                    if (!isfinite(t))
                        continue;
                    double p[3], clip[4];
                    for (int c = 0; c < 3; c++)
                        p[c] = o[c] + t * d[c];
                    for (int row = 0; row < 4; row++)
                        clip[row] = r->view_proj[row] * p[0] + r->view_proj[4 + row] * p[1] +
                                    r->view_proj[8 + row] * p[2] + r->view_proj[12 + row];
                    double z = clip[2] / clip[3] * 0.5 + 0.5;
                    if (z >= 0.0 && z < 1.0)
                        v.depth[(size_t)ty * aw + r->tile_x + tx] = (float)z;
                }
        }
    }
    lg_shadowmap_info info = { .struct_size = sizeof info,
                               .resolution = R,
                               .n_lights = st->n_records,
                               .atlas_width = aw,
                               .atlas_height = R,
                               .bias_constant = (float)lg_param_float(n, "bias") };
    rc = lg_shadowmap_publish(n, 0, &info, recs);
    free(recs);
    return rc;
}

static void tps_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static const char *const tps_occluders[] = { "none", "floor", "shadow", NULL };
static const char *const tps_defects[] = { "none", "paraboloid", "offcentre", "short", NULL };
static const lg_param_desc tps_params[] = {
    { .key = "resolution",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 2,
      .max = 1024,
      .doc = "tile side, texels" },
    { .key = "occluders",
      .type = LG_PARAM_ENUM,
      .def.e = TPS_NONE,
      .enum_values = tps_occluders,
      .doc = "none, floor or shadow (testpolyshadow.c)" },
    { .key = "floor_half",
      .type = LG_PARAM_FLOAT,
      .def.f = 5,
      .min = 0,
      .max = 1e6,
      .doc = "the floor's half side (testphongscene's size / 2)" },
    { .key = "znear",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.05,
      .min = 0,
      .max = 1e6,
      .doc = "the maps' near plane" },
    { .key = "zfar",
      .type = LG_PARAM_FLOAT,
      .def.f = 40,
      .min = 0,
      .max = 1e6,
      .doc = "the maps' far plane" },
    { .key = "margin_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 2,
      .min = 0,
      .max = 40,
      .doc = "a spot's frustum beyond its outer cone, degrees" },
    { .key = "defect",
      .type = LG_PARAM_ENUM,
      .def.e = TPS_OK,
      .enum_values = tps_defects,
      .doc = "none, paraboloid, offcentre or short (testpolyshadow.c)" },
    { .key = "bias",
      .type = LG_PARAM_FLOAT,
      .def.f = 1e-5,
      .min = 0,
      .max = 1,
      .doc = "the maps' constant bias, window depth" },
};
static const lg_port_desc tps_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "its point and spot lights" }
};
static const lg_port_desc tps_out[] = {
    { .name = "shadow", .kind = LG_KIND_SHADOWMAP, .doc = "perspective maps, by hand" }
};
/* ---- test_poly_field_scene ------------------------------------------------------------------- */

/* Height fog: m(p) = e^(-0.5 (p.y - 0)) everywhere (a field, so the medium is heterogeneous). */
static const lg_density_field tps_field = {
    .kind = LG_FIELD_UNIFORM,
    .height_falloff = 0.5f,
    .height_base = 0.0f,
    .bounds_min = { -1e30f, -1e30f, -1e30f },
    .bounds_max = { 1e30f, 1e30f, 1e30f },
};

static int tfs_prepare(lg_node *n)
{
    lg_ts_builder *b = lg_ts_begin("test_poly_field_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    lg_material *m = lg_ts_material(b, "test");
    m->kd = 1.0f;
    m->od[0] = m->od[1] = m->od[2] = m->base_color[0] = m->base_color[1] = m->base_color[2] = 0.8f;
    m->base_color[3] = 1.0f;
    lg_ts_camera(b, "test", lg_v3(0, 2, 6), lg_v3(0, 0, 0), lg_v3(0, 1, 0),
                 (float)(40.0 * LG_PI / 180.0), 0.1f, 50.0f);
    lg_ts_mesh(b, "plane#0", 0);
    lg_ts_grid(b, lg_v3(0, 0, 0), lg_v3(5, 0, 0), lg_v3(0, 0, -5), 1);
    lg_ts_instance(b, 0, NULL);
    lg_light *l = lg_ts_light(b, "bulb", LG_LIGHT_POINT);
    if (l) {
        l->position[1] = 2.0f;
        l->color[0] = l->color[1] = l->color[2] = 1.0f;
        l->intensity = 10.0f;
    }
    lg_ts_medium(b, 1.0f, lg_v3(0.1f, 0.1f, 0.1f), lg_v3(0.05f, 0.05f, 0.05f), 0.0f);
    lg_scene *s = lg_ts_finish(b);
    if (!s)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory building the field scene");
    s->medium.field = &tps_field;
    s->features.medium_field = 1;
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &s->features, s, lg_ts_free);
}

static int tfs_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const lg_port_desc tfs_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_poly_shadow",
        .doc = "Perspective shadow maps of point and spot lights written by hand (tests)",
        LG_PARAMS(tps_params),
        LG_INPUTS(tps_in),
        LG_OUTPUTS(tps_out),
        .create = tps_create,
        .prepare = tps_prepare,
        .execute = tps_execute,
        .destroy = tps_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_poly_field_scene",
        .doc = "A plane, a point light and a heterogeneous (height fog) medium (tests)",
        LG_OUTPUTS(tfs_out),
        .prepare = tfs_prepare,
        .execute = tfs_execute,
    }
};

LG_PLUGIN_DEFINE("testpolyshadow", "1.0.0", "Hand-made perspective shadow maps for tests", types)
