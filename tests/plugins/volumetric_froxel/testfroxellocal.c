/*
 * Test plugin "testfroxellocal": what the tests of volumetric_froxel's point and spot lights
 * and heterogeneous media (froxel.h 4.) need that other nodes do not make yet, and the grid
 * froxel.h says they must give, computed independently of plugins/volumetric_froxel from the
 * same inputs (vol_common.h, lightgraph/medium.h, lg_shadowmap_visibility) in double.
 *
 *   test_local_shadows  scene -> shadowmap: one perspective record per spot light (a
 *       frustum around its outer cone) and six (a cube, faces +x, -x, +y, -y, +z, -z) per
 *       point light, each a tile of `resolution`; the depth is written by hand: a checker of
 *       8 x 8 texel blocks whose dark blocks hold a wall at view depth `wall` from the light
 *       (1 elsewhere), so that a froxel behind the wall in a dark block is shadowed.
 *       pcf_radius and bias are the map's.
 *   test_field  scene -> scene: the input with a density field on its medium: fBm noise
 *       (frequency, octaves, scale, offset) times a height fog (height_falloff above
 *       height_base), inside the box [box_min, box_max].
 *   froxel_spec_grid  scene + base + froxel + shadows -> image W x (H D) (testfroxelgrid's
 *       layout): froxel.h's grid (1., 2. energy_conserving, 4. with n = 0: the point sample)
 *       for the froxel volume's own slicing and size, jitter 0.5, no history.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/froxel.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/shadowmap.h"
#include "lightgraph/vecmath.h"

#include "vol_common.h"

/* ---- test_local_shadows ---------------------------------------------------------------------- */

#define LS_COLS 8

/* The records the scene's point (6) and spot (1) lights need. */
static uint32_t ls_records(const lg_scene *s)
{
    uint32_t r = 0;
    for (uint32_t i = 0; i < s->n_lights; i++)
        r += s->lights[i].type == LG_LIGHT_POINT ? 6 : s->lights[i].type == LG_LIGHT_SPOT ? 1 : 0;
    return r;
}

static int ls_prepare(lg_node *n)
{
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return lg_error(n, "input 'scene' has no scene data");
    uint32_t res = (uint32_t)lg_param_int(n, "resolution"), r = ls_records(s);
    uint32_t rows = (r + LS_COLS - 1) / LS_COLS;
    int rc = lg_shadowmap_declare(n, 0, res * LS_COLS, res * (rows ? rows : 1), r);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int ls_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    uint32_t res = (uint32_t)lg_param_int(n, "resolution"), nr = ls_records(s);
    uint32_t rows = (nr + LS_COLS - 1) / LS_COLS;
    uint32_t aw = res * LS_COLS, ah = res * (rows ? rows : 1);
    float wall = (float)lg_param_float(n, "wall"), zn = 0.05f, zf = 20.0f;
    lg_shadow_light *recs = calloc(nr ? nr : 1, sizeof *recs);
    lg_cpu_view av;
    int rc = recs ? lg_map_cpu(n, lg_part(n, lg_output(n, 0), "atlas"), LG_WRITE, &av)
                  : lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    if (rc) {
        free(recs);
        return rc;
    }
    float *atlas = av.depth ? av.depth : av.pixels;
    for (size_t i = 0; i < (size_t)aw * ah; i++)
        atlas[i] = 1.0f;
    /* the wall's window depth: GL's perspective depth of view depth `wall` */
    float ndc = (zf + zn) / (zf - zn) - 2.0f * zf * zn / ((zf - zn) * wall);
    float wall_depth = 0.5f * ndc + 0.5f;
    static const float axes[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                      { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->n_lights; i++) {
        const lg_light *l = &s->lights[i];
        if (l->type != LG_LIGHT_POINT && l->type != LG_LIGHT_SPOT)
            continue;
        int faces = l->type == LG_LIGHT_POINT ? 6 : 1;
        lg_vec3 q = lg_v3(l->position[0], l->position[1], l->position[2]);
        for (int f = 0; f < faces; f++, k++) {
            lg_shadow_light *r = &recs[k];
            lg_vec3 d = l->type == LG_LIGHT_SPOT
                            ? lg_v3(l->direction[0], l->direction[1], l->direction[2])
                            : lg_v3(axes[f][0], axes[f][1], axes[f][2]);
            lg_vec3 up = fabsf(d.y) > 0.9f ? lg_v3(0, 0, 1) : lg_v3(0, 1, 0);
            float proj[16];
            lg_m4_look_at(r->view, q, lg_v3_add(q, d), up);
            float fov = l->type == LG_LIGHT_SPOT ? 2.0f * l->outer_cone + 0.1f : (float)LG_HALF_PI;
            lg_m4_perspective(proj, fov, 1.0f, zn, zf);
            memcpy(r->proj, proj, sizeof proj);
            lg_m4_mul(r->view_proj, proj, r->view);
            r->light = i;
            r->tile_x = res * (k % LS_COLS);
            r->tile_y = res * (k / LS_COLS);
            r->texel_world = 2.0f * tanf(fov / 2.0f) / (float)res;
            r->depth_range = zf - zn;
            r->projection = LG_SHADOW_PERSPECTIVE;
            r->face = l->type == LG_LIGHT_POINT ? (uint32_t)f : 0;
            r->znear = zn;
            for (uint32_t y = 0; y < res; y++)
                for (uint32_t x = 0; x < res; x++)
                    if (((x / 8) + (y / 8)) & 1)
                        atlas[(size_t)(r->tile_y + y) * aw + r->tile_x + x] = wall_depth;
        }
    }
    lg_shadowmap_info info = { .struct_size = sizeof info,
                               .resolution = res,
                               .n_lights = nr,
                               .atlas_width = aw,
                               .atlas_height = ah,
                               .bias_constant = (float)lg_param_float(n, "bias") };
    info.pcf_radius = (uint32_t)lg_param_int(n, "pcf_radius");
    info.point_mode = LG_SHADOW_POINT_CUBE;
    rc = lg_shadowmap_publish(n, 0, &info, recs);
    free(recs);
    return rc;
}

/* ---- test_field ------------------------------------------------------------------------------ */

typedef struct tf_payload {
    lg_scene scene;
    lg_density_field field;
} tf_payload;

static int tf_prepare(lg_node *n)
{
    const lg_resource *in = lg_input(n, 0);
    const lg_scene *src = lg_scene_get(n, in);
    if (!src)
        return lg_error(n, "input 'scene' has no scene data");
    tf_payload *p = calloc(1, sizeof *p);
    if (!p)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    memcpy(&p->scene, src, sizeof p->scene);
    p->scene.geometry = src->geometry ? src->geometry : in;
    lg_density_field *f = &p->field;
    f->kind = LG_FIELD_FBM;
    f->fbm.frequency = (float)lg_param_float(n, "frequency");
    f->fbm.octaves = (uint32_t)lg_param_int(n, "octaves");
    f->fbm.lacunarity = 2.0f;
    f->fbm.gain = 0.5f;
    f->fbm.seed = 7;
    f->fbm.scale = (float)lg_param_float(n, "scale");
    f->fbm.offset = (float)lg_param_float(n, "offset");
    f->height_falloff = (float)lg_param_float(n, "height_falloff");
    f->height_base = (float)lg_param_float(n, "height_base");
    const lg_value *lo = lg_param(n, "box_min"), *hi = lg_param(n, "box_max");
    for (int c = 0; c < 3; c++) {
        f->bounds_min[c] = (float)lo->v[c];
        f->bounds_max[c] = (float)hi->v[c];
    }
    p->scene.medium.field = f;
    lg_scene_compute_features(&p->scene);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &p->scene.features, p, free);
}

/* ---- froxel_spec_grid ------------------------------------------------------------------------ */

static int sg_prepare(lg_node *n)
{
    uint32_t w = (uint32_t)lg_param_int(n, "width"), h = (uint32_t)lg_param_int(n, "height"),
             d = (uint32_t)lg_param_int(n, "depth");
    lg_image_desc desc = { .width = w, .height = h * d, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &desc);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

/* One froxel's S (rgb, per unit length) at sample point p on ray w: froxel.h 1. and 4. */
static void sg_scatter(const vol_setup *v, const lg_shadowmap *sm, const float *atlas,
                       const vol_tau_volume *tau, const double w[3], const double p[3], double s[3])
{
    double rho = vol_density(v, p);
    s[0] = s[1] = s[2] = 0.0;
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_light *L = &v->lights[l];
        double tl[3], dist;
        double f = vol_light_falloff(L, p, tl, &dist);
        double ph = lg_hg_phase(v->g, w[0] * tl[0] + w[1] * tl[1] + w[2] * tl[2]);
        double vis = sm ? lg_shadowmap_visibility(sm, atlas, L->scene_index, p, 0.0) : 1.0;
        for (int c = 0; c < 3; c++) {
            double x = v->heterogeneous ? exp(-(double)v->sigma_t[c] * vol_tau_sample(&tau[l], p))
                                        : vol_light_transmittance(v, L, dist, c);
            s[c] += L->l_c[c] * vis * f * x * ph;
        }
    }
    for (int c = 0; c < 3; c++)
        s[c] *= rho * v->sigma_s[c];
}

static int sg_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    uint32_t W = (uint32_t)lg_param_int(n, "width"), H = (uint32_t)lg_param_int(n, "height"),
             D = (uint32_t)lg_param_int(n, "depth");
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    lg_froxel fv;
    const lg_froxel *fx = lg_froxel_get(n, lg_input(n, 2), &fv);
    if (!s || !fx)
        return lg_error(n, "no scene or no froxel volume");
    if (fx->info.width != W || fx->info.height != H || fx->info.depth != D)
        return lg_error(n, "the grid is %ux%ux%u, the parameters say %ux%ux%u", fx->info.width,
                        fx->info.height, fx->info.depth, W, H, D);
    lg_shadowmap smv;
    const lg_shadowmap *sm = lg_shadowmap_get(n, lg_input(n, 3), &smv);
    lg_resource_info bi;
    int rc = lg_describe(lg_input(n, 1), &bi, n);
    if (rc)
        return rc;
    const float *atlas = NULL;
    lg_cpu_view av, ov;
    if (sm) {
        if ((rc = lg_map_cpu(n, sm->atlas, LG_READ, &av)))
            return rc;
        atlas = av.depth ? av.depth : av.pixels;
    }
    if ((rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov)))
        return rc;
    vol_setup *v = malloc(sizeof *v);
    vol_tau_volume *tau = calloc(VOL_MAX_LIGHTS, sizeof *tau);
    if (!v || !tau) {
        free(v);
        free(tau);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    rc = vol_setup_make(n, s, bi.image.width, bi.image.height, fx->info.far, sm,
                        VOL_ACCEPT_LIGHTS | VOL_ACCEPT_FIELD, v);
    lg_slice_map map;
    if (!rc)
        rc = lg_slice_map_from_info(&map, &fx->info);
    for (uint32_t l = 0; !rc && v->heterogeneous && l < v->n_lights; l++)
        rc = vol_tau_build(n, v, l, 64, &tau[l]); /* froxel.c's resolution */
    for (uint32_t j = 0; !rc && j < H; j++)
        for (uint32_t i = 0; i < W; i++) {
            double w[3];
            vol_ray(v, (i + 0.5) * v->width / W, (j + 0.5) * v->height / H, w);
            double cosv = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
            double acc[3] = { 0, 0, 0 }, tr[3] = { 1, 1, 1 }, t_prev = 0.0;
            for (uint32_t k = 0; k < D; k++) {
                double tj = lg_slice_to_depth(&map, k + 0.5), tn = lg_slice_to_depth(&map, k + 1.0);
                double p[3], sc[3];
                for (int a = 0; a < 3; a++)
                    p[a] = v->eye[a] + w[a] * tj / cosv;
                sg_scatter(v, sm, atlas, tau, w, p, sc);
                double delta = (tn - t_prev) / cosv, rho = vol_density(v, p);
                t_prev = tn;
                for (int c = 0; c < 3; c++) {
                    double t = v->sigma_t[c] * rho * delta;
                    acc[c] += tr[c] * sc[c] * delta * lg_medium_segment(t);
                    tr[c] *= exp(-t);
                }
                float *o = (float *)ov.pixels + 4 * ((size_t)(k * H + j) * ov.row_pixels + i);
                for (int c = 0; c < 3; c++)
                    o[c] = (float)acc[c];
                o[3] = (float)((tr[0] + tr[1] + tr[2]) / 3.0);
            }
        }
    for (uint32_t l = 0; l < VOL_MAX_LIGHTS; l++)
        vol_tau_free(n, &tau[l]);
    free(tau);
    free(v);
    return rc;
}

/* ---- descriptors ----------------------------------------------------------------------------- */

static const lg_param_desc ls_params[] = {
    { .key = "resolution",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 8,
      .max = 1024,
      .doc = "tile side, texels" },
    { .key = "wall",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.5,
      .min = 0.06,
      .max = 19,
      .doc = "view depth of the wall in the checker's dark blocks" },
    { .key = "pcf_radius",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 4096,
      .doc = "the map's PCF radius" },
    { .key = "bias",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.0,
      .min = 0,
      .max = 1,
      .doc = "the map's constant bias" },
};
static const lg_param_desc tf_params[] = {
    { .key = "frequency",
      .type = LG_PARAM_FLOAT,
      .def.f = 2.0,
      .min = 0,
      .max = 1e3,
      .doc = "the noise's base frequency" },
    { .key = "octaves",
      .type = LG_PARAM_INT,
      .def.i = 3,
      .min = 1,
      .max = 8,
      .doc = "fBm octaves" },
    { .key = "scale",
      .type = LG_PARAM_FLOAT,
      .def.f = 2.0,
      .min = 0,
      .max = 1e3,
      .doc = "multiplies the noise after the offset" },
    { .key = "offset",
      .type = LG_PARAM_FLOAT,
      .def.f = -0.5,
      .min = -10,
      .max = 10,
      .doc = "subtracted from the noise" },
    { .key = "height_falloff",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 100,
      .doc = "height fog, 1 / scene unit" },
    { .key = "height_base",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.0,
      .min = -1e3,
      .max = 1e3,
      .doc = "world y of the height fog's 1" },
    { .key = "box_min",
      .type = LG_PARAM_VEC3,
      .def.v = { -1e3, -1e3, -1e3 },
      .doc = "the field's box" },
    { .key = "box_max",
      .type = LG_PARAM_VEC3,
      .def.v = { 1e3, 1e3, 1e3 },
      .doc = "the field's box" },
};
static const lg_param_desc sg_params[] = {
    { .key = "width", .type = LG_PARAM_INT, .def.i = 1, .min = 1, .max = 4096, .doc = "W" },
    { .key = "height", .type = LG_PARAM_INT, .def.i = 1, .min = 1, .max = 4096, .doc = "H" },
    { .key = "depth", .type = LG_PARAM_INT, .def.i = 1, .min = 1, .max = 4096, .doc = "D" },
};
static const lg_port_desc scene_in[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc scene_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc sm_out[] = { { .name = "shadows", .kind = LG_KIND_SHADOWMAP } };
static const lg_port_desc sg_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE },
    { .name = "base", .kind = LG_KIND_IMAGE },
    { .name = "froxel", .kind = LG_KIND_FROXEL },
    { .name = "shadows", .kind = LG_KIND_SHADOWMAP, .optional = true },
};
static const lg_port_desc img_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static const lg_node_type fl_types[] = {
    { .struct_size = sizeof(lg_node_type),
      .name = "test_local_shadows",
      .doc = "perspective shadow records of point and spot lights, depth by hand (test)",
      LG_PARAMS(ls_params),
      LG_INPUTS(scene_in),
      LG_OUTPUTS(sm_out),
      .prepare = ls_prepare,
      .execute = ls_execute },
    { .struct_size = sizeof(lg_node_type),
      .name = "test_field",
      .doc = "the scene with an fBm x height-fog density field on its medium (test)",
      LG_PARAMS(tf_params),
      LG_INPUTS(scene_in),
      LG_OUTPUTS(scene_out),
      .prepare = tf_prepare,
      .execute = nothing },
    { .struct_size = sizeof(lg_node_type),
      .name = "froxel_spec_grid",
      .doc = "froxel.h's grid for point and spot lights and fields, in double (test)",
      LG_PARAMS(sg_params),
      LG_INPUTS(sg_in),
      LG_OUTPUTS(img_out),
      .prepare = sg_prepare,
      .execute = sg_execute },
};

LG_PLUGIN_DEFINE("testfroxellocal", "1.0.0",
                 "Point and spot shadows, density fields and froxel.h's grid (tests)", fl_types)
