/*
 * Test plugin "shadowprobe": a scene built in memory for the shadow-map tests, and a probe
 * that evaluates Shadow_L(p) on the CPU for given world points from a shadowmap node's
 * payload and atlas, as a consumer would.
 *
 *   test_shadow_scene   -> scene: a floor quad and a box (or a sphere), no lights (add
 *                          them with the scene_tools `light` node), one camera
 *   test_shadow_probe   scene, shadows -> image (layout below)
 *
 * sp_shadow() below is the CPU reference of the shadow test (TECHNIQUES.md §2, eq. 4, with
 * the bias rules of plugins/shadowmap/README.md, "Bias"): later nodes that test shadows on
 * the GPU can be held against it.
 *
 * The probe's image: width max(P + 1, 3) for P points, height (scene lights) + 1.
 *   row l < lights, column j < P: (Shadow_l(p_j), z, D, 1) where z is p_j's light depth
 *       (clamped to [0, 1]) and D the stored depth of its texel; (1, -1, -1, 0) for a light
 *       without a shadow map (no payload); z = D = -1 when p_j falls outside the light's
 *       tile (lit). A spot or point light's maps (perspective, since ABI 3.2), and every
 *       light with `sdk = true`, are tested by the SDK's lg_shadowmap_visibility instead
 *       (with the map's PCF; z = D = -1), after the normal offset (normal_offset x
 *       texel_world, times |p - light| on a perspective map) with the slope bias as its
 *       bias_extra
 *   row l, column P: (tile_x, tile_y, texel_world, depth_range) of the light's first map,
 *       or zeros
 *   last row, column 0: (n_lights of the payload or -1 without one, resolution,
 *       atlas_width, atlas_height)
 *   last row, column 1: (bias_constant, bias_slope, normal_offset, 1 if the atlas resource
 *       is a depth-only image of atlas_width x atlas_height, else 0)
 *   last row, column 2: (the number of payload entries whose `light` is not a light of the
 *       scene or whose projection is not its type's (orthographic for directional lights,
 *       perspective otherwise), perspective records, point-light records, the pcf_radius):
 *       a check of the lights list
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"
#include "lightgraph/shadowmap.h"

#include "common/testscene.h"

/* ---- the CPU reference of the shadow test ---------------------------------------------------- */

/* Shadow_L(p) for light `l` of `sm` (1 lit, 0 shadowed), with `depth` the atlas's CPU depth
 * plane (`row_pixels` texels per row). `nrm` is p's unit geometric normal, or NULL for a
 * point without one (a point in a medium): then neither the normal offset nor the slope
 * bias applies. `dir` is the light's direction of travel (unit). *z and *d receive the
 * point's light depth and the stored depth (-1, -1 outside the tile). */
static float sp_shadow(const lg_shadowmap *sm, const lg_shadow_light *l, lg_vec3 dir,
                       const float *depth, size_t row_pixels, lg_vec3 p, const lg_vec3 *nrm,
                       float *z, float *d)
{
    float tan_t = 0.0f;
    if (nrm) {
        lg_vec3 to_light = lg_v3_scale(dir, -1.0f);
        float c = fabsf(lg_v3_dot(*nrm, to_light));
        c = c < 0.1f ? 0.1f : c > 1.0f ? 1.0f : c;
        tan_t = sqrtf(1.0f - c * c) / c;
        p = lg_v3_add(p, lg_v3_scale(*nrm, sm->normal_offset * l->texel_world));
    }
    /* orthographic: w = 1 */
    lg_vec3 q = lg_m4_point(l->view_proj, p);
    float tx = q.x * 0.5f + 0.5f, ty = q.y * 0.5f + 0.5f;
    if (!(tx >= 0.0f && tx <= 1.0f && ty >= 0.0f && ty <= 1.0f)) {
        *z = *d = -1.0f;
        return 1.0f;
    }
    uint32_t res = sm->resolution;
    uint32_t ix = (uint32_t)(tx * (float)res), iy = (uint32_t)(ty * (float)res);
    if (ix >= res)
        ix = res - 1;
    if (iy >= res)
        iy = res - 1;
    float zz = q.z * 0.5f + 0.5f;
    zz = zz < 0.0f ? 0.0f : zz > 1.0f ? 1.0f : zz;
    float dd = depth[(size_t)(l->tile_y + iy) * row_pixels + l->tile_x + ix];
    float bias = sm->bias_constant + sm->bias_slope * tan_t;
    *z = zz;
    *d = dd;
    return zz > dd + bias ? 0.0f : 1.0f;
}

/* ---- test_shadow_scene ----------------------------------------------------------------------- */

/* The most rings the sphere may have (the parameter's range). */
#define SS_MAX_RINGS 24

/* Vertex (r, k) of the sphere below. */
static lg_vec3 ss_sphere_point(int r, int k, int rings)
{
    double th = LG_PI * r / rings, az = 2 * LG_PI * k / (2 * rings);
    return lg_v3((float)(sin(th) * cos(az)), (float)cos(th), (float)(sin(th) * sin(az)));
}

/* A UV sphere of radius 1 at the origin in the current mesh: vertex (r, s) at polar angle
 * pi r / R from +Y and azimuth 2 pi s / S (S = 2 R), position (sin t cos a, cos t,
 * sin t sin a), normal the same; quad (r, s) is split into triangles (r, s) (r+1, s)
 * (r+1, s+1) and (r, s) (r+1, s+1) (r, s+1), each wound counter-clockwise seen from
 * outside. The tests rebuild the same triangles to put points on the surface. (Not
 * lg_ts_uv_sphere: its azimuth turns the other way, and these tests' numbers are made
 * for this one.) */
static void ss_sphere(lg_ts_builder *b, int rings)
{
    int segs = 2 * rings;
    for (int r = 0; r <= rings; r++)
        for (int k = 0; k <= segs; k++) {
            lg_vec3 p = ss_sphere_point(r, k, rings);
            lg_ts_vertex(b, p, p);
        }
    for (int r = 0; r < rings; r++)
        for (int k = 0; k < segs; k++) {
            uint32_t a = (uint32_t)(r * (segs + 1) + k), b1 = a + (uint32_t)(segs + 1);
            uint32_t tri[2][3] = { { a, b1, b1 + 1 }, { a, b1 + 1, a + 1 } };
            for (int i = 0; i < 2; i++) {
                lg_vec3 p[3];
                for (int v = 0; v < 3; v++)
                    p[v] = ss_sphere_point((int)tri[i][v] / (segs + 1), (int)tri[i][v] % (segs + 1),
                                           rings);
                lg_vec3 e1 = lg_v3(p[1].x - p[0].x, p[1].y - p[0].y, p[1].z - p[0].z);
                lg_vec3 e2 = lg_v3(p[2].x - p[0].x, p[2].y - p[0].y, p[2].z - p[0].z);
                lg_vec3 c = lg_v3(p[0].x + p[1].x + p[2].x, p[0].y + p[1].y + p[2].y,
                                  p[0].z + p[1].z + p[2].z);
                bool flip = lg_v3_dot(lg_v3_cross(e1, e2), c) < 0.0f;
                lg_ts_triangle(b, tri[i][0], tri[i][flip ? 2 : 1], tri[i][flip ? 1 : 2]);
            }
        }
}

static lg_vec3 ss_vec(lg_node *n, const char *key)
{
    const lg_value *v = lg_param(n, key);
    return v ? lg_v3((float)v->v[0], (float)v->v[1], (float)v->v[2]) : lg_v3(0, 0, 0);
}

static int ss_prepare(lg_node *n)
{
    lg_ts_builder *b = lg_ts_begin("test_shadow_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    static const char *const mat_names[2] = { "floor", "box" };
    static const char *const ds_params[2] = { "floor_double_sided", "box_double_sided" };
    for (int i = 0; i < 2; i++) {
        lg_material *m = lg_ts_material(b, mat_names[i]);
        m->kd = 1.0f;
        for (int k = 0; k < 3; k++)
            m->base_color[k] = m->od[k] = 0.8f;
        m->base_color[3] = 1.0f;
        m->roughness = 1.0f;
        m->double_sided = lg_param_bool(n, ds_params[i]);
    }

    /* mesh 0: the floor, facing +Y; mesh 1: the unit cube, faces outwards */
    float half = (float)lg_param_float(n, "floor_size") * 0.5f;
    lg_vec3 fc = lg_v3(0, (float)lg_param_float(n, "floor_y"), 0);
    lg_ts_mesh(b, "floor#0", 0);
    lg_ts_quad(b, &fc, lg_v3(0, 0, half), lg_v3(half, 0, 0), NULL);
    bool sphere = lg_param_enum(n, "shape") == 1;
    lg_ts_mesh(b, "box#0", 1);
    if (sphere)
        ss_sphere(b, (int)lg_param_int(n, "sphere_rings"));
    else
        lg_ts_unit_cube(b, false);

    lg_ts_instance(b, 0, NULL);
    if (lg_param_bool(n, "box")) {
        lg_vec3 c = ss_vec(n, "box_center"), sz = ss_vec(n, "box_size");
        float model[16];
        lg_m4_identity(model);
        /* a mirroring instance: the cube's X flipped (its faces, seen from outside, are
         * then clockwise: a renderer must flip the front face to cull correctly); the
         * sphere (radius 1) is scaled by half the size, so it fits the same box */
        float k = sphere ? 0.5f : 1.0f;
        model[0] = k * sz.x * (lg_param_bool(n, "box_mirror") ? -1.0f : 1.0f);
        model[5] = k * sz.y;
        model[10] = k * sz.z;
        model[12] = c.x, model[13] = c.y, model[14] = c.z;
        lg_ts_instance(b, 1, model);
    }

    lg_ts_camera(b, "test", ss_vec(n, "camera_position"), ss_vec(n, "camera_target"),
                 lg_v3(0, 1, 0), (float)(lg_param_float(n, "yfov") * LG_PI / 180.0), 0.1f, 0.0f);

    if (lg_param_bool(n, "bad_light")) /* direction (0, 0, 0) */
        lg_ts_dir_light(b, "bad", lg_v3(0, 0, 0), lg_v3(0, 0, 0), 1.0f);
    return lg_ts_publish(n, 0, b);
}

static int ss_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- test_shadow_probe ----------------------------------------------------------------------- */

#define SP_MAX_POINTS 4096

typedef struct sp_state {
    lg_vec3 pts[SP_MAX_POINTS], nrm[SP_MAX_POINTS];
    uint32_t n_pts;
    bool has_normals, sdk;
    uint32_t width, height, n_scene_lights;
} sp_state;

/* "x,y,z;x,y,z;..." into out[]; returns the count or -1 after an error. */
static int sp_parse(lg_node *n, const char *key, const char *s, lg_vec3 *out)
{
    int k = 0;
    const char *p = s;
    while (*p) {
        if (k == SP_MAX_POINTS)
            return lg_error(n, "%s: more than %d points", key, SP_MAX_POINTS), -1;
        float v[3];
        for (int i = 0; i < 3; i++) {
            char *e;
            v[i] = strtof(p, &e);
            if (e == p)
                return lg_error(n, "%s: point %d: expected a number at '%.20s'", key, k, p), -1;
            p = e;
            if (i < 2) {
                if (*p != ',')
                    return lg_error(n, "%s: point %d: expected ',' at '%.20s'", key, k, p), -1;
                p++;
            }
        }
        out[k++] = lg_v3(v[0], v[1], v[2]);
        if (*p == ';')
            p++;
        else if (*p)
            return lg_error(n, "%s: point %d: expected ';' at '%.20s'", key, k - 1, p), -1;
    }
    return k;
}

static int sp_create(lg_node *n)
{
    sp_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    n->user = st;
    int np = sp_parse(n, "points", lg_param_string(n, "points"), st->pts);
    if (np < 0)
        return LG_ERR_INVALID;
    st->n_pts = (uint32_t)np;
    st->sdk = lg_param_bool(n, "sdk");
    const char *ns = lg_param_string(n, "normals");
    if (*ns) {
        int nn = sp_parse(n, "normals", ns, st->nrm);
        if (nn < 0)
            return LG_ERR_INVALID;
        if (nn != np)
            return lg_error(n, "%d normals for %d points", nn, np);
        for (int i = 0; i < nn; i++)
            st->nrm[i] = lg_v3_normalize_or(st->nrm[i], lg_v3(0, 1, 0));
        st->has_normals = true;
    }
    return 0;
}

static int sp_prepare(lg_node *n)
{
    sp_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    st->n_scene_lights = s->n_lights;
    st->width = st->n_pts + 1 < 3 ? 3 : st->n_pts + 1;
    st->height = s->n_lights + 1;
    lg_image_desc d = { .width = st->width, .height = st->height, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int sp_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    sp_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    lg_shadowmap smv;
    const lg_shadowmap *sm = lg_shadowmap_get(n, lg_input(n, 1), &smv);
    lg_cpu_view vo;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &vo);
    if (rc)
        return rc;
    float *o = vo.pixels;
#define PX(x, y) (o + ((size_t)(y)*vo.row_pixels + (x)) * 4)
    for (uint32_t l = 0; l < st->n_scene_lights; l++)
        for (uint32_t j = 0; j < st->n_pts; j++) {
            float *p = PX(j, l);
            p[0] = 1.0f, p[1] = -1.0f, p[2] = -1.0f, p[3] = 0.0f;
        }
    float *info = PX(0, st->n_scene_lights);
    info[0] = -1.0f;
    if (!sm)
        return 0;

    info[0] = (float)sm->n_lights;
    info[1] = (float)sm->resolution;
    info[2] = (float)sm->atlas_width;
    info[3] = (float)sm->atlas_height;
    float *bias = PX(1, st->n_scene_lights);
    bias[0] = sm->bias_constant, bias[1] = sm->bias_slope, bias[2] = sm->normal_offset;
    lg_resource_info ai;
    bias[3] = sm->atlas && lg_describe(sm->atlas, &ai, n) == 0 && ai.kind == LG_KIND_IMAGE &&
                      (ai.image.flags & LG_IMAGE_DEPTH_ONLY) && ai.image.width == sm->atlas_width &&
                      ai.image.height == sm->atlas_height
                  ? 1.0f
                  : 0.0f;
    float *chk = PX(2, st->n_scene_lights);
    for (uint32_t i = 0; i < sm->n_lights; i++) {
        const lg_shadow_light *r = &sm->lights[i];
        bool dir = r->light < s->n_lights && s->lights[r->light].type == LG_LIGHT_DIRECTIONAL;
        if (r->light >= s->n_lights || (dir ? r->projection != LG_SHADOW_ORTHOGRAPHIC
                                            : r->projection != LG_SHADOW_PERSPECTIVE))
            chk[0] += 1.0f;
        chk[1] += r->projection == LG_SHADOW_PERSPECTIVE;
        chk[2] += r->light < s->n_lights && s->lights[r->light].type == LG_LIGHT_POINT;
    }
    chk[3] = (float)sm->pcf_radius;
    if (chk[0] != 0.0f || bias[3] == 0.0f || st->n_pts == 0)
        return 0; /* nothing to test (without points: the atlas is not even read back) */

    lg_cpu_view va;
    if ((rc = lg_map_cpu(n, sm->atlas, LG_READ, &va)))
        return rc;
    if (!va.depth)
        return lg_error(n, "the atlas's depth plane is not mapped");
    if (va.row_pixels != sm->atlas_width)
        return lg_error(n, "the atlas's rows are %zu texels apart, not its width %u", va.row_pixels,
                        sm->atlas_width);
    for (uint32_t i = 0; i < sm->n_lights; i++) {
        const lg_shadow_light *l = &sm->lights[i];
        if (lg_shadowmap_find(sm, l->light) != (int32_t)i)
            continue; /* a later map of a light (a cube's face): tested through its first */
        const lg_light *L = &s->lights[l->light];
        lg_vec3 dir = lg_v3_normalize_or(lg_v3(L->direction[0], L->direction[1], L->direction[2]),
                                         lg_v3(0, -1, 0));
        lg_vec3 pos = lg_v3(L->position[0], L->position[1], L->position[2]);
        bool ortho_ref = L->type == LG_LIGHT_DIRECTIONAL && !st->sdk;
        for (uint32_t j = 0; j < st->n_pts; j++) {
            float *p = PX(j, l->light);
            p[3] = 1.0f;
            if (ortho_ref) {
                p[0] = sp_shadow(sm, l, dir, va.depth, va.row_pixels, st->pts[j],
                                 st->has_normals ? &st->nrm[j] : NULL, &p[1], &p[2]);
                continue;
            }
            lg_vec3 q = st->pts[j];
            double extra = 0.0;
            if (st->has_normals) {
                lg_vec3 to_light = L->type == LG_LIGHT_DIRECTIONAL
                                       ? lg_v3_scale(dir, -1.0f)
                                       : lg_v3_normalize_or(lg_v3_sub(pos, q), lg_v3(0, 1, 0));
                float c = fabsf(lg_v3_dot(st->nrm[j], to_light));
                c = c < 0.1f ? 0.1f : c > 1.0f ? 1.0f : c;
                extra = sm->bias_slope * sqrtf(1.0f - c * c) / c;
                double pd[3] = { q.x, q.y, q.z };
                const lg_shadow_light *r = &sm->lights[lg_shadowmap_record_at(sm, (int32_t)i, pd)];
                float scale = r->projection == LG_SHADOW_PERSPECTIVE
                                  ? lg_v3_length(lg_v3_sub(q, pos))
                                  : 1.0f;
                q = lg_v3_add(q,
                              lg_v3_scale(st->nrm[j], sm->normal_offset * r->texel_world * scale));
            }
            double pd[3] = { q.x, q.y, q.z };
            p[0] = lg_shadowmap_visibility(sm, va.depth, l->light, pd, extra);
            p[1] = p[2] = -1.0f;
        }
        float *t = PX(st->n_pts, l->light);
        t[0] = (float)l->tile_x, t[1] = (float)l->tile_y;
        t[2] = l->texel_world, t[3] = l->depth_range;
    }
#undef PX
    return 0;
}

static void sp_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const char *const ss_shapes[] = { "cube", "sphere", NULL };
static const lg_param_desc ss_params[] = {
    { .key = "floor_size",
      .type = LG_PARAM_FLOAT,
      .def.f = 8,
      .min = 0.01,
      .max = 1e4,
      .doc = "edge of the square floor, centred on the origin" },
    { .key = "floor_y",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -1e4,
      .max = 1e4,
      .doc = "height of the floor" },
    { .key = "floor_double_sided",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "the floor material's double_sided" },
    { .key = "box", .type = LG_PARAM_BOOL, .def.b = true, .doc = "whether there is a box" },
    { .key = "shape",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = ss_shapes,
      .doc = "the box's mesh: a cube, or a UV sphere inscribed in it" },
    { .key = "sphere_rings",
      .type = LG_PARAM_INT,
      .def.i = 12,
      .min = 2,
      .max = SS_MAX_RINGS,
      .doc = "the sphere's rings (its segments are twice as many)" },
    { .key = "box_center",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 1.5, 0 },
      .min = -1e4,
      .max = 1e4,
      .doc = "the box's centre" },
    { .key = "box_size",
      .type = LG_PARAM_VEC3,
      .def.v = { 1, 1, 1 },
      .min = 0.001,
      .max = 1e4,
      .doc = "the box's edges" },
    { .key = "box_double_sided",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "the box material's double_sided" },
    { .key = "box_mirror",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "place the box through a mirroring instance (scale x by -1)" },
    { .key = "camera_position",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 4, 8 },
      .min = -1e4,
      .max = 1e4,
      .doc = "the camera's position" },
    { .key = "camera_target",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .min = -1e4,
      .max = 1e4,
      .doc = "the point the camera looks at" },
    { .key = "yfov",
      .type = LG_PARAM_FLOAT,
      .def.f = 45,
      .min = 1,
      .max = 170,
      .doc = "the camera's vertical field of view, degrees" },
    { .key = "bad_light",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "give the scene one directional light with direction (0, 0, 0)" },
};
static const lg_port_desc ss_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };

static const lg_param_desc sp_params[] = {
    { .key = "points",
      .type = LG_PARAM_STRING,
      .def.s = "",
      .doc = "world points \"x,y,z;x,y,z;...\"" },
    { .key = "normals",
      .type = LG_PARAM_STRING,
      .def.s = "",
      .doc = "their unit normals, same form; empty: points without a normal" },
    { .key = "sdk",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "test directional lights with lg_shadowmap_visibility too (with the map's PCF)" },
};
static const lg_port_desc sp_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE },
    { .name = "shadows", .kind = LG_KIND_SHADOWMAP, .optional = true },
};
static const lg_port_desc sp_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_shadow_scene",
        .doc = "A floor and a box built in memory for the shadow-map tests",
        LG_PARAMS(ss_params),
        LG_OUTPUTS(ss_out),
        .prepare = ss_prepare,
        .execute = ss_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_shadow_probe",
        .doc = "Shadow_L(p) per light per point on the CPU from a shadowmap's payload",
        LG_PARAMS(sp_params),
        LG_INPUTS(sp_in),
        LG_OUTPUTS(sp_out),
        .create = sp_create,
        .prepare = sp_prepare,
        .execute = sp_execute,
        .destroy = sp_destroy,
    },
};

LG_PLUGIN_DEFINE("shadowprobe", "1.0.0", "Scene and CPU shadow probe for the shadow-map tests",
                 types)
