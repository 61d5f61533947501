/*
 * Test plugin "testfroxelcheck": the closed form the froxel grid must meet, computed
 * independently of plugins/volumetric_froxel from the same inputs (vol_common.h's view
 * rays and fog length, lightgraph/medium.h's closed form).
 *
 *   froxel_closed_form   scene + base -> image (rgba32f, base's size): per pixel
 *       sum over the directional lights of L_c sigma_s p(g, dot(w, -L)) d seg(sigma_t d)
 *       (mode = energy_conserving) or L_c sigma_s p d (mode = thesis_one_slice: what the
 *       thesis's sum gives for a one-slice grid), d = vol_fog_length, alpha 1; unshadowed.
 *       Point and spot lights (issue 25), unshadowed, homogeneous medium:
 *       mode = point_exact: sum over every light of L_c sigma_s times the airlight
 *         integral along the pixel's ray from the eye to d with the extinction
 *         (lg_point_inscatter with sigma_t, 64 nodes; directional lights as above): the
 *         continuous answer every slicing converges to;
 *       mode = point_slices: froxel.h 1-3 and 4. written out for the pixel's ray (a column
 *         centre when the image is the grid's W x H) over the slice map of input `grid`
 *         (a volumetric_froxel's grid, jitter 0.5), energy_conserving: per slice,
 *         S_k = sigma_s L_c X(p_k) (nodes > 0: lg_point_inscatter(b_k, b_k+1, sigma_t 0,
 *         nodes) / Delta_k; nodes = 0: F(p_k) p_HG at the sample point p_k), accumulated and
 *         looked up as froxel.h says; what the node must give to rounding.
 *       mode = field_exact: a heterogeneous medium (lg_medium.field), unshadowed: the
 *         single-scattering integral along the ray, m(x) sigma_s L_c F p_HG X e^(-int
 *         sigma_t m) by the midpoint rule in `steps` steps, X the transmittance to the
 *         light (to the light, or for a directional light out of the tau box of
 *         vol_tau_build: a bounded field's own box, else the scene's) marched in
 *         `steps` steps too.
 *
 *   froxel_test_field   scene -> scene: the scene with a density field of kind uniform
 *       (bounds_min, bounds_max, height_falloff, height_base; lightgraph/scene.h): the
 *       medium node gains fields on another branch; these tests need one now.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/froxel.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"

#include "vol_common.h"

typedef struct cf_state {
    uint32_t w, h;
} cf_state;

static int cf_prepare(lg_node *n)
{
    cf_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    n->user = st;
    lg_resource_info info;
    const lg_resource *b = lg_input(n, 1);
    if (!b || lg_describe(b, &info, n) != 0 || info.kind != LG_KIND_IMAGE ||
        !(info.image.flags & LG_IMAGE_DEPTH))
        return lg_error(n, "input 'base' is not an image with depth");
    st->w = info.image.width;
    st->h = info.image.height;
    lg_image_desc d = { .width = st->w, .height = st->h, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

enum { CF_ENERGY = 0, CF_THESIS, CF_POINT_EXACT, CF_POINT_SLICES, CF_FIELD_EXACT };

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* lg_point_inscatter's spot argument for light L, or NULL for a point light. */
static const double *spot_of(const vol_light *L, double sp[5])
{
    if (L->type != LG_LIGHT_SPOT)
        return NULL;
    for (int c = 0; c < 3; c++)
        sp[c] = L->dir[c];
    sp[3] = L->cos_inner;
    sp[4] = L->cos_outer;
    return sp;
}

/* Light L's in-scattering per unit L_c and sigma_s along [t0, t1] of the ray (e, w) with
 * extinction sigma_t from t0 and towards the light (a directional light: none towards it). */
static double light_segment(const vol_setup *v, const vol_light *L, const double w[3], double t0,
                            double t1, double sigma_t, int nodes)
{
    if (L->type == LG_LIGHT_DIRECTIONAL) {
        double dl[3] = { -L->dir[0], -L->dir[1], -L->dir[2] };
        double len = t1 - t0;
        return len > 0 ? lg_hg_phase(v->g, dot3(w, dl)) * len * lg_medium_segment(sigma_t * len)
                       : 0.0;
    }
    double q[3] = { L->pos[0], L->pos[1], L->pos[2] }, sp[5];
    return lg_point_inscatter(v->eye, w, t0, t1, q, L->range, spot_of(L, sp), v->g, sigma_t, nodes);
}

/* The tau box of vol_tau_build (vol_common.c): a bounded field's own box on each axis where
 * it is bounded (beyond it m = 0: the march out of it is exact), else the scene's bounds
 * grown by 1 %. */
static void tau_box(const vol_setup *v, double lo[3], double hi[3])
{
    const lg_density_field *f = v->medium.field;
    for (int c = 0; c < 3; c++) {
        double slo = v->scene_min[c], shi = v->scene_max[c];
        double pad = 0.01 * (shi - slo) + 1e-6;
        bool bounded = fabs((double)f->bounds_min[c]) < 1e30 &&
                       fabs((double)f->bounds_max[c]) < 1e30 && f->bounds_max[c] > f->bounds_min[c];
        lo[c] = bounded ? (double)f->bounds_min[c] : slo - pad;
        hi[c] = bounded ? (double)f->bounds_max[c] : shi + pad;
        if (!(hi[c] > lo[c]))
            hi[c] = lo[c] + 1e-6;
    }
}

/* The optical depth (integral of m) from x towards light L: to the light, or out of the tau
 * box for a directional light, in `steps` midpoint steps. */
static double optical_depth(const vol_setup *v, const vol_light *L, const double x[3], int steps)
{
    double d[3], len;
    if (L->type == LG_LIGHT_DIRECTIONAL) {
        double lo[3], hi[3];
        tau_box(v, lo, hi);
        len = INFINITY;
        for (int c = 0; c < 3; c++) {
            d[c] = -L->dir[c];
            if (d[c] > 0)
                len = fmin(len, (hi[c] - x[c]) / d[c]);
            else if (d[c] < 0)
                len = fmin(len, (lo[c] - x[c]) / d[c]);
        }
        if (!(len > 0) || !isfinite(len))
            return 0.0;
    } else {
        for (int c = 0; c < 3; c++)
            d[c] = L->pos[c] - x[c];
        len = sqrt(dot3(d, d));
        for (int c = 0; c < 3; c++)
            d[c] = len > 0 ? d[c] / len : 0.0;
    }
    double h = len / steps, tau = 0.0;
    for (int i = 0; i < steps; i++) {
        double y[3];
        for (int c = 0; c < 3; c++)
            y[c] = x[c] + d[c] * h * (i + 0.5);
        tau += lg_medium_field_at(&v->medium, y) * h;
    }
    return tau;
}

/* F p_HG of light L at x for a view ray w (directional: p_HG). */
static double falloff_phase(const vol_setup *v, const vol_light *L, const double w[3],
                            const double x[3], double *dist)
{
    double tl[3];
    double f = vol_light_falloff(L, x, tl, dist);
    return f * lg_hg_phase(v->g, dot3(w, tl));
}

static int cf_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    cf_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    vol_setup *v = malloc(sizeof *v);
    if (!v)
        return LG_ERR_NOMEM;
    int mode = lg_param_enum(n, "mode");
    int nodes = (int)lg_param_int(n, "nodes"), steps = (int)lg_param_int(n, "steps");
    unsigned accept = mode >= CF_POINT_EXACT ? VOL_ACCEPT_LIGHTS : VOL_ACCEPT_DIRECTIONAL;
    if (mode == CF_FIELD_EXACT)
        accept |= VOL_ACCEPT_FIELD;
    int rc = vol_setup_make(n, s, st->w, st->h, (float)lg_param_float(n, "z_limit"), NULL, accept,
                            v);
    lg_cpu_view bv, ov;
    lg_slice_map map;
    uint32_t D = 0;
    if (!rc && mode == CF_POINT_SLICES) {
        lg_froxel fx;
        const lg_froxel *g = lg_input(n, 2) ? lg_froxel_get(n, lg_input(n, 2), &fx) : NULL;
        if (!g)
            rc = lg_error(n, "mode point_slices needs input 'grid' (a volumetric_froxel's grid)");
        else if (lg_slice_map_from_info(&map, &g->info))
            rc = lg_error(n, "input 'grid': its slice map is refused");
        else
            D = g->info.depth;
    }
    if (!rc)
        rc = lg_map_cpu(n, lg_input(n, 1), LG_READ, &bv);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov);
    if (rc) {
        free(v);
        return rc;
    }
    float *o = ov.pixels;
    for (uint32_t y = 0; y < st->h; y++)
        for (uint32_t x = 0; x < st->w; x++) {
            size_t p = (size_t)y * st->w + x;
            double w[3];
            vol_ray(v, x + 0.5, y + 0.5, w);
            double d = vol_fog_length(v, x + 0.5, y + 0.5, bv.depth[p]);
            double sum[3] = { 0, 0, 0 };
            if (mode == CF_ENERGY || mode == CF_THESIS) {
                for (int c = 0; c < 3; c++)
                    for (uint32_t l = 0; l < v->n_lights; l++) {
                        const vol_light *L = &v->lights[l];
                        double cosv = -(w[0] * L->dir[0] + w[1] * L->dir[1] + w[2] * L->dir[2]);
                        double ph = lg_hg_phase(v->g, cosv);
                        sum[c] += mode == CF_THESIS ? L->l_c[c] * v->sigma_s[c] * ph * d
                                                    : lg_medium_inscatter(L->l_c[c], v->sigma_s[c],
                                                                          v->sigma_t[c], ph, d);
                    }
            } else if (mode == CF_POINT_EXACT) {
                for (int c = 0; c < 3; c++)
                    for (uint32_t l = 0; l < v->n_lights; l++)
                        sum[c] += v->lights[l].l_c[c] * v->sigma_s[c] *
                                  light_segment(v, &v->lights[l], w, 0.0, d, v->sigma_t[c], 64);
            } else if (mode == CF_POINT_SLICES) {
                /* froxel.h 1-3 and 4. for one column, in double */
                double cosv = dot3(w, v->forward), tr[3] = { 1, 1, 1 };
                double t_end = d * cosv, zc = lg_depth_to_slice(&map, t_end);
                zc = zc < 0 ? 0 : zc > D ? D : zc;
                uint32_t kk = (uint32_t)floor(zc);
                if (kk > D - 1)
                    kk = D - 1;
                for (uint32_t k = 0; k <= kk; k++) {
                    double b0 = k == 0 ? 0.0 : lg_slice_to_depth(&map, k) / cosv;
                    double b1 = lg_slice_to_depth(&map, k + 1.0) / cosv, delta = b1 - b0;
                    double ts = lg_slice_to_depth(&map, k + 0.5) / cosv, pk[3];
                    for (int c = 0; c < 3; c++)
                        pk[c] = v->eye[c] + w[c] * ts;
                    double sk[3] = { 0, 0, 0 };
                    for (uint32_t l = 0; l < v->n_lights; l++) {
                        const vol_light *L = &v->lights[l];
                        double dist = INFINITY, a;
                        if (L->type == LG_LIGHT_DIRECTIONAL || nodes == 0)
                            a = falloff_phase(v, L, w, pk, &dist);
                        else {
                            a = light_segment(v, L, w, b0, b1, 0.0, nodes) / delta;
                            falloff_phase(v, L, w, pk, &dist);
                        }
                        for (int c = 0; c < 3; c++)
                            sk[c] += v->sigma_s[c] * L->l_c[c] * a *
                                     vol_light_transmittance(v, L, dist, c);
                    }
                    double tsk = k == 0 ? 0.0 : lg_slice_to_depth(&map, k);
                    double len = k < kk ? delta : t_end > tsk ? (t_end - tsk) / cosv : 0.0;
                    for (int c = 0; c < 3; c++) {
                        double tau = v->sigma_t[c] * len;
                        sum[c] += tr[c] * sk[c] * len * lg_medium_segment(tau);
                        tr[c] *= exp(-tau);
                    }
                }
            } else {
                /* CF_FIELD_EXACT: the midpoint rule along the ray */
                double h = d / steps, path = 0.0;
                for (int i = 0; i < steps; i++) {
                    double xp[3];
                    for (int c = 0; c < 3; c++)
                        xp[c] = v->eye[c] + w[c] * h * (i + 0.5);
                    double m = lg_medium_field_at(&v->medium, xp);
                    double tv = path + 0.5 * m * h; /* optical path from the eye to xp */
                    path += m * h;
                    if (m == 0.0)
                        continue;
                    for (uint32_t l = 0; l < v->n_lights; l++) {
                        const vol_light *L = &v->lights[l];
                        double dist, a = falloff_phase(v, L, w, xp, &dist);
                        double tl = optical_depth(v, L, xp, steps);
                        for (int c = 0; c < 3; c++)
                            sum[c] += m * v->sigma_s[c] * L->l_c[c] * a *
                                      exp(-v->sigma_t[c] * (tl + tv)) * h;
                    }
                }
            }
            for (int c = 0; c < 3; c++)
                o[4 * p + c] = (float)sum[c];
            o[4 * p + 3] = 1.0f;
        }
    free(v);
    return 0;
}

/* ---- froxel_test_field ----------------------------------------------------------------------- */

typedef struct tf_payload {
    lg_scene scene;
    lg_density_field field;
} tf_payload;

static void tf_free(void *p)
{
    free(p);
}

static int tf_prepare(lg_node *n)
{
    const lg_resource *in = lg_input(n, 0);
    lg_resource_info info;
    if (!in || lg_describe(in, &info, n) != 0 || !info.payload)
        return lg_error(n, "input 'scene' has no scene data");
    const lg_scene *src = lg_scene_get(n, in);
    if (!src)
        return LG_ERR_INVALID;
    tf_payload *p = calloc(1, sizeof *p);
    if (!p)
        return LG_ERR_NOMEM;
    size_t have = src->struct_size < sizeof p->scene ? src->struct_size : sizeof p->scene;
    memcpy(&p->scene, src, have);
    p->scene.struct_size = sizeof p->scene;
    p->scene.geometry = src->geometry ? src->geometry : in;
    p->field.kind = LG_FIELD_UNIFORM;
    const lg_value *lo = lg_param(n, "bounds_min"), *hi = lg_param(n, "bounds_max");
    for (int c = 0; c < 3; c++) {
        p->field.bounds_min[c] = (float)lo->v[c];
        p->field.bounds_max[c] = (float)hi->v[c];
    }
    p->field.height_falloff = (float)lg_param_float(n, "height_falloff");
    p->field.height_base = (float)lg_param_float(n, "height_base");
    p->scene.medium.field = &p->field;
    lg_scene_compute_features(&p->scene);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &p->scene.features, p, tf_free);
}

static int tf_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

static void cf_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static const char *const cf_modes[] = { "energy_conserving", "thesis_one_slice", "point_exact",
                                        "point_slices",      "field_exact",      NULL };
static const lg_param_desc cf_params[] = {
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the fog ends; 0 = the camera's zfar" },
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = cf_modes,
      .doc = "energy_conserving: the closed form; thesis_one_slice: without the segment "
             "factor; point_exact, point_slices, field_exact: see the file's header" },
    { .key = "nodes",
      .type = LG_PARAM_INT,
      .def.i = 2,
      .min = 0,
      .max = 8,
      .doc = "point_slices: the froxel node's point_nodes (0: its sample mode)" },
    { .key = "steps",
      .type = LG_PARAM_INT,
      .def.i = 256,
      .min = 1,
      .max = 100000,
      .doc = "field_exact: midpoint steps along the ray and towards each light" },
};
static const lg_port_desc cf_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" },
    { .name = "base", .kind = LG_KIND_IMAGE, .doc = "the lit image with depth" },
    { .name = "grid",
      .kind = LG_KIND_FROXEL,
      .optional = true,
      .doc = "point_slices: the froxel node's grid (its slice map)" },
};
static const lg_port_desc cf_outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "the closed-form in-scatter" },
};
static const lg_param_desc tf_params[] = {
    { .key = "bounds_min",
      .type = LG_PARAM_VEC3,
      .def.v = { -FLT_MAX, -FLT_MAX, -FLT_MAX },
      .doc = "the fog box's low corner" },
    { .key = "bounds_max",
      .type = LG_PARAM_VEC3,
      .def.v = { FLT_MAX, FLT_MAX, FLT_MAX },
      .doc = "the fog box's high corner" },
    { .key = "height_falloff",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e6,
      .doc = "height fog: exp(-falloff (y - base)); 0 = none" },
    { .key = "height_base", .type = LG_PARAM_FLOAT, .def.f = 0, .doc = "height fog's base y" },
};
static const lg_port_desc tf_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" },
};
static const lg_port_desc tf_outputs[] = {
    { .name = "out", .kind = LG_KIND_SCENE, .doc = "the scene with the field" },
};

static const lg_node_type cf_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "froxel_closed_form",
        .doc = "The closed-form in-scatter of an unshadowed homogeneous medium (tests)",
        LG_PARAMS(cf_params),
        LG_INPUTS(cf_inputs),
        LG_OUTPUTS(cf_outputs),
        .prepare = cf_prepare,
        .execute = cf_execute,
        .destroy = cf_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "froxel_test_field",
        .doc = "The scene with a uniform density field: a box and height fog (tests)",
        LG_PARAMS(tf_params),
        LG_INPUTS(tf_inputs),
        LG_OUTPUTS(tf_outputs),
        .prepare = tf_prepare,
        .execute = tf_execute,
    },
};

LG_PLUGIN_DEFINE("testfroxelcheck", "1.0.0", "The closed form the froxel tests compare with",
                 cf_types)
