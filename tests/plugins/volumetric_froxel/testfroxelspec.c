/*
 * Test plugin "testfroxelspec": the inputs and the reference of the gl backend's point and
 * spot lights and heterogeneous media (tests/plugins/volumetric_froxel/
 * test_froxel_gl_lights.c), independent of plugins/volumetric_froxel (it shares
 * vol_common.h, lightgraph/medium.h and lightgraph/shadowmap.h with it, as froxel.h says).
 *
 *   froxel_fbm_field     scene -> scene: the same scene with lg_medium.field set to fBm
 *                        noise (octaves, frequency, offset, scale, seed; noise = false:
 *                        none, LG_FIELD_UNIFORM) with a height fog (height_falloff,
 *                        height_base), unbounded: a heterogeneous medium before the
 *                        `medium` node can make one.
 *   froxel_hand_shadows  scene -> shadowmap: for each point light six cube faces (+x, -x,
 *                        +y, -y, +z, -z, 90 degrees) and for each spot light one perspective
 *                        map fitted to its outer cone, built by hand (lg_shadow_light records)
 *                        as the shadowmap node will make them, each tile the depth of one
 *                        analytic sphere (centre, radius) seen from the light: texel (x, y)
 *                        of a tile holds the window depth of the sphere along the ray through
 *                        its centre, 1 where the ray misses. pcf = the PCF radius. Directional
 *                        lights get no record (unshadowed). Tiles 16 a row.
 *   froxel_spec          scene + base (+ shadows) -> grid (W x (H D), froxel_grid_image's
 *                        layout), inscatter and out (W x H: base must be W x H, so that
 *                        each pixel's centre is a column's): froxel.h 1, 2 (energy_conserving)
 *                        and 4 (sample point, point_nodes 0) in double on the CPU, uniform
 *                        clip slicing from z_near (0: the camera's znear) to z_limit (0: zfar), jitter
 *                        0.5; shadows by lg_shadowmap_visibility, transmittance towards the
 *                        light e^(-sigma_t d) or, with a field, e^(-sigma_t tau_l(p)) from
 *                        vol_tau_build at 64 cells (froxel.c's tau_res) read by
 *                        vol_tau_sample.
 *   froxel_agree         got + want -> a 2 x 1 image of their agreement (below): the
 *                        comparison in memory, not through files.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/shadowmap.h"
#include "lightgraph/vecmath.h"

#include "vol_common.h"

/* ---- froxel_fbm_field ------------------------------------------------------------------------ */

typedef struct ff_payload {
    lg_scene scene;
    lg_density_field field;
} ff_payload;

static void ff_free(void *p)
{
    free(p);
}

static int ff_prepare(lg_node *n)
{
    const lg_resource *in = lg_input(n, 0);
    const lg_scene *src = lg_scene_get(n, in);
    if (!src)
        return lg_error(n, "input 'scene' has no scene data");
    ff_payload *p = calloc(1, sizeof *p);
    if (!p)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    memcpy(&p->scene, src, sizeof p->scene);
    p->scene.geometry = src->geometry ? src->geometry : in;
    lg_density_field *f = &p->field;
    f->kind = lg_param_bool(n, "noise") ? LG_FIELD_FBM : LG_FIELD_UNIFORM;
    f->fbm.octaves = (uint32_t)lg_param_int(n, "octaves");
    f->fbm.seed = (uint32_t)lg_param_int(n, "seed");
    f->fbm.frequency = (float)lg_param_float(n, "frequency");
    f->fbm.lacunarity = 2.0f;
    f->fbm.gain = 0.5f;
    f->fbm.offset = (float)lg_param_float(n, "offset");
    f->fbm.scale = (float)lg_param_float(n, "scale");
    f->height_falloff = (float)lg_param_float(n, "height_falloff");
    f->height_base = (float)lg_param_float(n, "height_base");
    for (int c = 0; c < 3; c++) {
        f->bounds_min[c] = -FLT_MAX;
        f->bounds_max[c] = FLT_MAX;
    }
    p->scene.medium.field = f;
    lg_scene_compute_features(&p->scene);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &p->scene.features, p, ff_free);
}

static int nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- froxel_hand_shadows --------------------------------------------------------------------- */

#define HS_ROW 16

typedef struct hs_state {
    uint32_t n_rec, res;
    lg_shadow_light rec[6 * VOL_MAX_LIGHTS];
    float centre[3], radius; /* the occluding sphere */
} hs_state;

/* Record r looking from q along `dir` with `up`, a square frustum of yfov. */
static void hs_record(lg_shadow_light *r, uint32_t light, uint32_t face, lg_vec3 q, lg_vec3 dir,
                      lg_vec3 up, float yfov, uint32_t index, uint32_t res)
{
    memset(r, 0, sizeof *r);
    lg_m4_look_at(r->view, q, lg_v3_add(q, dir), up);
    lg_m4_perspective(r->proj, yfov, 1.0f, 0.05f, 20.0f);
    lg_m4_mul(r->view_proj, r->proj, r->view);
    r->light = light;
    r->tile_x = index % HS_ROW * res; /* HS_ROW tiles a row (GL's size limits) */
    r->tile_y = index / HS_ROW * res;
    r->texel_world = 2.0f * tanf(0.5f * yfov) / (float)res;
    r->depth_range = 20.0f - 0.05f;
    r->projection = LG_SHADOW_PERSPECTIVE;
    r->face = face;
    r->znear = 0.05f;
}

/* The atlas: HS_ROW tiles a row, as many rows as needed (at least one tile). */
static void hs_atlas_size(const hs_state *st, uint32_t *w, uint32_t *h)
{
    uint32_t n = st->n_rec ? st->n_rec : 1;
    *w = (n < HS_ROW ? n : HS_ROW) * st->res;
    *h = (n + HS_ROW - 1) / HS_ROW * st->res;
}

static int hs_prepare(lg_node *n)
{
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return lg_error(n, "input 'scene' has no scene data");
    hs_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    n->user = st;
    st->res = (uint32_t)lg_param_int(n, "resolution");
    const lg_value *c = lg_param(n, "centre");
    for (int a = 0; a < 3; a++)
        st->centre[a] = (float)c->v[a];
    st->radius = (float)lg_param_float(n, "radius");
    static const float dirs[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                      { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
    static const float ups[6][3] = { { 0, -1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
                                     { 0, 0, -1 }, { 0, -1, 0 }, { 0, -1, 0 } };
    for (uint32_t l = 0; l < s->n_lights; l++) {
        const lg_light *L = &s->lights[l];
        lg_vec3 q = lg_v3(L->position[0], L->position[1], L->position[2]);
        if (L->type == LG_LIGHT_POINT && st->n_rec + 6 <= 6 * VOL_MAX_LIGHTS)
            for (uint32_t f = 0; f < 6; f++, st->n_rec++)
                hs_record(&st->rec[st->n_rec], l, f, q, lg_v3(dirs[f][0], dirs[f][1], dirs[f][2]),
                          lg_v3(ups[f][0], ups[f][1], ups[f][2]), 0.5f * (float)LG_PI, st->n_rec,
                          st->res);
        else if (L->type == LG_LIGHT_SPOT && st->n_rec < 6 * VOL_MAX_LIGHTS) {
            lg_vec3 d = lg_v3(L->direction[0], L->direction[1], L->direction[2]);
            lg_vec3 up = fabsf(d.y) < 0.9f ? lg_v3(0, 1, 0) : lg_v3(1, 0, 0);
            hs_record(&st->rec[st->n_rec], l, 0, q, d, up, 2.0f * L->outer_cone + 0.05f, st->n_rec,
                      st->res);
            st->n_rec++;
        }
    }
    uint32_t w, h;
    hs_atlas_size(st, &w, &h);
    int rc = lg_shadowmap_declare(n, 0, w, h, st->n_rec);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int hs_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    hs_state *st = n->user;
    uint32_t aw, ah, res = st->res;
    hs_atlas_size(st, &aw, &ah);
    lg_cpu_view av;
    int rc = lg_map_cpu(n, lg_part(n, lg_output(n, 0), "atlas"), LG_WRITE, &av);
    if (rc)
        return rc;
    float *atlas = av.depth ? av.depth : av.pixels;
    if (!atlas)
        return lg_error(n, "the atlas has no CPU plane");
    for (size_t i = 0; i < (size_t)aw * ah; i++)
        atlas[i] = 1.0f;
    for (uint32_t r = 0; r < st->n_rec; r++) {
        const lg_shadow_light *L = &st->rec[r];
        float inv[16];
        if (lg_m4_invert(inv, L->view_proj))
            return lg_error(n, "record %u: a singular matrix", r);
        for (uint32_t y = 0; y < res; y++)
            for (uint32_t x = 0; x < res; x++) {
                /* the ray through the texel's centre: from the near plane to the far one */
                double ndc[2] = { 2.0 * (x + 0.5) / res - 1.0, 2.0 * (y + 0.5) / res - 1.0 };
                double a[3], b[3];
                for (int e = 0; e < 2; e++) {
                    double z = e ? 1.0 : -1.0, h[4];
                    for (int row = 0; row < 4; row++)
                        h[row] = inv[row] * ndc[0] + inv[4 + row] * ndc[1] + inv[8 + row] * z +
                                 inv[12 + row];
                    for (int c = 0; c < 3; c++)
                        (e ? b : a)[c] = h[c] / h[3];
                }
                double d[3], oc[3], dd = 0, bq = 0, cq = 0;
                for (int c = 0; c < 3; c++) {
                    d[c] = b[c] - a[c];
                    oc[c] = a[c] - st->centre[c];
                    dd += d[c] * d[c];
                    bq += oc[c] * d[c];
                    cq += oc[c] * oc[c];
                }
                cq -= (double)st->radius * st->radius;
                double disc = bq * bq - dd * cq;
                if (!(disc >= 0))
                    continue;
                double t = (-bq - sqrt(disc)) / dd;
                if (t < 0)
                    t = (-bq + sqrt(disc)) / dd;
                if (!(t >= 0 && t <= 1))
                    continue;
                double p[3], cl[4];
                for (int c = 0; c < 3; c++)
                    p[c] = a[c] + d[c] * t;
                const float *m = L->view_proj;
                for (int row = 0; row < 4; row++)
                    cl[row] = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
                atlas[(size_t)(L->tile_y + y) * aw + L->tile_x + x] =
                    (float)(cl[2] / cl[3] * 0.5 + 0.5);
            }
    }
    lg_shadowmap_info info = { .struct_size = sizeof info,
                               .resolution = res,
                               .n_lights = st->n_rec,
                               .atlas_width = aw,
                               .atlas_height = ah,
                               .bias_constant = (float)lg_param_float(n, "bias") };
    info.pcf_radius = (uint32_t)lg_param_int(n, "pcf");
    return lg_shadowmap_publish(n, 0, &info, st->rec);
}

static void hs_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

/* ---- froxel_spec ----------------------------------------------------------------------------- */

typedef struct fs_state {
    uint32_t w, h, d;
} fs_state;

static int fs_prepare(lg_node *n)
{
    fs_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    n->user = st;
    st->w = (uint32_t)lg_param_int(n, "width");
    st->h = (uint32_t)lg_param_int(n, "height");
    st->d = (uint32_t)lg_param_int(n, "depth");
    lg_resource_info info;
    const lg_resource *b = lg_input(n, 1);
    if (!b || lg_describe(b, &info, n) != 0 || info.kind != LG_KIND_IMAGE ||
        !(info.image.flags & LG_IMAGE_DEPTH))
        return lg_error(n, "input 'base' is not an image with depth");
    if (info.image.width != st->w || info.image.height != st->h)
        return lg_error(n, "base is %ux%u, the grid %ux%u: they must be the same", info.image.width,
                        info.image.height, st->w, st->h);
    lg_image_desc g = { .width = st->w, .height = st->h * st->d, .format = LG_FORMAT_RGBA32F };
    lg_image_desc i = { .width = st->w, .height = st->h, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &g);
    if (!rc)
        rc = lg_declare_image(n, 1, &i);
    if (!rc)
        rc = lg_declare_image(n, 2, &i);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

/* The reference's per-frame data. */
typedef struct fs_run {
    const vol_setup *v;
    const lg_shadowmap *sm;
    const float *atlas;
    vol_tau_volume tau[VOL_MAX_LIGHTS];
    uint32_t n_tau;
} fs_run;

/* S at world point p on ray w (froxel.h 1 and 4, sample point), rgb. */
static void fs_scatter(const fs_run *r, const double w[3], const double p[3], double s[3])
{
    const vol_setup *v = r->v;
    s[0] = s[1] = s[2] = 0;
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_light *L = &v->lights[l];
        double tl[3], dist = 0, f;
        if (L->type == LG_LIGHT_DIRECTIONAL) {
            f = lg_hg_phase(v->g, -(w[0] * L->dir[0] + w[1] * L->dir[1] + w[2] * L->dir[2]));
        } else {
            f = vol_light_falloff(L, p, tl, &dist);
            f *= lg_hg_phase(v->g, w[0] * tl[0] + w[1] * tl[1] + w[2] * tl[2]);
        }
        if (r->sm && L->shadow >= 0)
            f *= lg_shadowmap_visibility(r->sm, r->atlas, L->scene_index, p, 0.0);
        double tau = v->heterogeneous ? vol_tau_sample(&r->tau[l], p) : 0.0;
        for (int c = 0; c < 3; c++) {
            double x = v->heterogeneous                  ? exp(-v->sigma_t[c] * tau)
                       : L->type != LG_LIGHT_DIRECTIONAL ? exp(-v->sigma_t[c] * dist)
                                                         : 1.0;
            s[c] += v->sigma_s[c] * L->l_c[c] * f * x;
        }
    }
}

static int fs_run_frame(lg_node *n, fs_state *st, fs_run *r, const lg_cpu_view *bv, float *grid,
                        float *ins, float *out)
{
    const vol_setup *v = r->v;
    uint32_t W = st->w, H = st->h, D = st->d;
    lg_slice_map map;
    double z_near = lg_param_float(n, "z_near");
    if (lg_slice_map_init(&map, LG_FROXEL_UNIFORM_CLIP, D, z_near > 0 ? z_near : v->view.znear,
                          v->z_limit, 0.0))
        return lg_error(n, "slice map refused");
    double *tk = malloc((D + 1) * sizeof *tk);
    float *sv = malloc((size_t)W * H * D * 4 * sizeof *sv);
    float *path = malloc((size_t)W * H * D * sizeof *path);
    if (!tk || !sv || !path) {
        free(tk);
        free(sv);
        free(path);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    }
    for (uint32_t k = 0; k <= D; k++)
        tk[k] = lg_slice_to_depth(&map, (double)k);
    for (uint32_t j = 0; j < H; j++)
        for (uint32_t i = 0; i < W; i++) {
            double w[3];
            vol_ray(v, (i + 0.5) * (double)v->width / W, (j + 0.5) * (double)v->height / H, w);
            double cs = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
            double A[3] = { 0, 0, 0 }, Tr[3] = { 1, 1, 1 }, P = 0, t0 = 0;
            for (uint32_t k = 0; k < D; k++) {
                double t = lg_slice_to_depth(&map, k + 0.5), t1 = tk[k + 1], p[3], s[3];
                for (int a = 0; a < 3; a++)
                    p[a] = v->eye[a] + w[a] * t / cs;
                fs_scatter(r, w, p, s);
                double rho = v->heterogeneous ? lg_medium_field_at(&v->medium, p) : 1.0;
                double delta = (t1 - t0) / cs;
                size_t cell = i + (size_t)W * (j + (size_t)H * k);
                for (int c = 0; c < 3; c++) {
                    s[c] *= rho;
                    double tau = v->sigma_t[c] * rho * delta;
                    A[c] += Tr[c] * s[c] * delta * lg_medium_segment(tau);
                    Tr[c] *= exp(-tau);
                    sv[4 * cell + c] = (float)s[c];
                }
                sv[4 * cell + 3] = (float)rho;
                P += rho * delta;
                path[cell] = (float)P;
                float *g = grid + 4 * (i + (size_t)W * (k * H + j));
                g[0] = (float)A[0], g[1] = (float)A[1], g[2] = (float)A[2];
                g[3] = (float)((Tr[0] + Tr[1] + Tr[2]) / 3.0);
                t0 = t1;
            }
        }
    /* the lookup at the columns' centres (froxel.h 3 and 4) */
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t px = (size_t)y * W + x;
            double w[3];
            vol_ray(v, x + 0.5, y + 0.5, w);
            double cs = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
            double d = vol_fog_length(v, x + 0.5, y + 0.5, bv->depth[px]);
            double t_end = d * cs, zc = lg_depth_to_slice(&map, t_end);
            zc = zc < 0 ? 0 : zc > D ? D : zc;
            uint32_t k = (uint32_t)floor(zc);
            if (k > D - 1)
                k = D - 1;
            double t_s = k == 0 ? 0.0 : tk[k];
            double delta = t_end > t_s ? (t_end - t_s) / cs : 0.0;
            size_t cell = x + (size_t)W * (y + (size_t)H * k);
            const float *g = k > 0 ? grid + 4 * (x + (size_t)W * ((k - 1) * H + y)) : NULL;
            double P = k > 0 ? path[cell - (size_t)W * H] : 0.0, rho = sv[4 * cell + 3];
            const float *b = (const float *)bv->pixels + 4 * px;
            for (int c = 0; c < 3; c++) {
                double st_ = v->sigma_t[c];
                double L = (g ? g[c] : 0.0) + exp(-st_ * P) * sv[4 * cell + c] * delta *
                                                  lg_medium_segment(st_ * rho * delta);
                ins[4 * px + c] = (float)L;
                out[4 * px + c] = (float)(b[c] * exp(-st_ * (P + rho * delta)) + L);
            }
            ins[4 * px + 3] = 1.0f;
            out[4 * px + 3] = b[3];
        }
    free(tk);
    free(sv);
    free(path);
    return 0;
}

static int fs_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    fs_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    fs_run r = { 0 };
    lg_shadowmap smv;
    const lg_resource *sres = lg_input(n, 2);
    r.sm = sres ? lg_shadowmap_get(n, sres, &smv) : NULL;
    vol_setup *v = malloc(sizeof *v);
    if (!v)
        return LG_ERR_NOMEM;
    int rc = vol_setup_make(n, s, st->w, st->h, (float)lg_param_float(n, "z_limit"), r.sm,
                            VOL_ACCEPT_LIGHTS | VOL_ACCEPT_FIELD, v);
    r.v = v;
    lg_cpu_view bv, av, gv, iv, ov;
    if (!rc && r.sm) {
        rc = lg_map_cpu(n, r.sm->atlas, LG_READ, &av);
        if (!rc)
            r.atlas = av.depth ? av.depth : av.pixels;
    }
    if (!rc)
        rc = lg_map_cpu(n, lg_input(n, 1), LG_READ, &bv);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &gv);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 1), LG_WRITE, &iv);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 2), LG_WRITE, &ov);
    for (uint32_t l = 0; !rc && v->heterogeneous && l < v->n_lights; l++) {
        rc = vol_tau_build(n, v, l, 64, &r.tau[l]);
        if (!rc)
            r.n_tau = l + 1;
    }
    if (!rc)
        rc = fs_run_frame(n, st, &r, &bv, gv.pixels, iv.pixels, ov.pixels);
    for (uint32_t l = 0; l < r.n_tau; l++)
        vol_tau_free(n, &r.tau[l]);
    free(v);
    return rc;
}

static void fs_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

/* ---- froxel_agree ---------------------------------------------------------------------------- */

/* got against want in memory (the images never pass through a file: a 32 x 864 rgba32f EXR
 * came back with one 16-row ZIP block of garbage, see test_froxel_gl_lights.c): a 1 x 1
 * image (worst error, rmse, values beyond tol, values not finite), errors in units of each
 * channel's largest |want| (rgb and alpha apart), plus the largest |want| of r, g, b. */
static int fa_prepare(lg_node *n)
{
    lg_resource_info a, b;
    if (lg_describe(lg_input(n, 0), &a, n) || lg_describe(lg_input(n, 1), &b, n) ||
        a.kind != LG_KIND_IMAGE || b.kind != LG_KIND_IMAGE)
        return lg_error(n, "inputs 'got' and 'want' must be images");
    if (a.image.width != b.image.width || a.image.height != b.image.height)
        return lg_error(n, "got is %ux%u, want %ux%u", a.image.width, a.image.height, b.image.width,
                        b.image.height);
    lg_image_desc d = { .width = 2, .height = 1, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int fa_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    lg_cpu_view gv, wv, ov;
    int rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &gv);
    if (!rc)
        rc = lg_map_cpu(n, lg_input(n, 1), LG_READ, &wv);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov);
    if (rc)
        return rc;
    const float *a = gv.pixels, *b = wv.pixels;
    size_t cnt = (size_t)info.image.width * info.image.height * 4;
    double tol = lg_param_float(n, "tol"), sc[4] = { 0, 0, 0, 0 };
    for (size_t i = 0; i < cnt; i++)
        if (isfinite(b[i]) && fabs(b[i]) > sc[i % 4])
            sc[i % 4] = fabs(b[i]);
    double sq = 0, worst = 0;
    size_t over = 0, bad = 0;
    for (size_t i = 0; i < cnt; i++) {
        if (!isfinite(a[i]) || !isfinite(b[i])) {
            bad++;
            continue;
        }
        double e = fabs((double)a[i] - b[i]) / (sc[i % 4] > 0 ? sc[i % 4] : 1.0);
        sq += e * e;
        over += e > tol;
        worst = e > worst ? e : worst;
    }
    float *o = ov.pixels;
    o[0] = (float)worst;
    o[1] = (float)sqrt(sq / (double)cnt);
    o[2] = (float)over;
    o[3] = (float)bad;
    o[4] = (float)sc[0], o[5] = (float)sc[1], o[6] = (float)sc[2], o[7] = (float)cnt;
    return 0;
}

/* ---- descriptors ----------------------------------------------------------------------------- */

static const lg_param_desc ff_params[] = {
    { .key = "noise",
      .type = LG_PARAM_BOOL,
      .def.b = true,
      .doc = "fBm noise; false: the height fog alone (LG_FIELD_UNIFORM)" },
    { .key = "octaves", .type = LG_PARAM_INT, .def.i = 3, .min = 1, .max = 16, .doc = "octaves" },
    { .key = "seed", .type = LG_PARAM_INT, .def.i = 7, .min = 0, .max = 1000, .doc = "seed" },
    { .key = "frequency",
      .type = LG_PARAM_FLOAT,
      .def.f = 2,
      .min = 1e-3,
      .max = 1e3,
      .doc = "1 / scene unit" },
    { .key = "offset", .type = LG_PARAM_FLOAT, .def.f = -0.3, .min = -10, .max = 10, .doc = "" },
    { .key = "scale", .type = LG_PARAM_FLOAT, .def.f = 2, .min = 0, .max = 100, .doc = "" },
    { .key = "height_falloff",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.5,
      .min = 0,
      .max = 100,
      .doc = "1 / scene unit" },
    { .key = "height_base",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -1e3,
      .max = 1e3,
      .doc = "" },
};
static const lg_port_desc ff_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" },
};
static const lg_port_desc ff_outputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene with an fBm density field" },
};

static const lg_param_desc hs_params[] = {
    { .key = "resolution",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 4,
      .max = 1024,
      .doc = "tile side" },
    { .key = "centre",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0.5, 0 },
      .min = -1e3,
      .max = 1e3,
      .doc = "the occluding sphere's centre" },
    { .key = "radius", .type = LG_PARAM_FLOAT, .def.f = 0.2, .min = 0, .max = 1e3, .doc = "" },
    { .key = "bias", .type = LG_PARAM_FLOAT, .def.f = 1e-4, .min = 0, .max = 1, .doc = "" },
    { .key = "pcf", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 8, .doc = "PCF radius" },
};
static const lg_port_desc hs_outputs[] = {
    { .name = "out", .kind = LG_KIND_SHADOWMAP, .doc = "the hand-made shadow map" },
};

static const lg_param_desc fs_params[] = {
    { .key = "width", .type = LG_PARAM_INT, .def.i = 8, .min = 1, .max = 512, .doc = "W" },
    { .key = "height", .type = LG_PARAM_INT, .def.i = 8, .min = 1, .max = 512, .doc = "H" },
    { .key = "depth", .type = LG_PARAM_INT, .def.i = 8, .min = 1, .max = 512, .doc = "D" },
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the fog ends; 0 = the camera's zfar" },
    { .key = "z_near",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the grid's slicing starts; 0 = the camera's znear" },
};
static const lg_port_desc fs_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" },
    { .name = "base", .kind = LG_KIND_IMAGE, .doc = "the lit image with depth, W x H" },
    { .name = "shadows", .kind = LG_KIND_SHADOWMAP, .optional = true, .doc = "shadow maps" },
};
static const lg_port_desc fs_outputs[] = {
    { .name = "grid", .kind = LG_KIND_IMAGE, .doc = "the grid, W x (H D)" },
    { .name = "inscatter", .kind = LG_KIND_IMAGE, .doc = "L_v" },
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "base T + L_v" },
};

static const lg_param_desc fa_params[] = {
    { .key = "tol",
      .type = LG_PARAM_FLOAT,
      .def.f = 1e-4,
      .min = 0,
      .max = 1,
      .doc = "an error beyond this (of the channel's largest value) counts" },
};
static const lg_port_desc fa_inputs[] = {
    { .name = "got", .kind = LG_KIND_IMAGE, .doc = "the image tested" },
    { .name = "want", .kind = LG_KIND_IMAGE, .doc = "the reference" },
};
static const lg_port_desc fa_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "2 x 1: (worst, rmse, count beyond tol, not finite), (scale r, g, b, values)" },
};

static const lg_node_type fs_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "froxel_fbm_field",
        .doc = "The scene with an fBm density field (tests)",
        LG_PARAMS(ff_params),
        LG_INPUTS(ff_inputs),
        LG_OUTPUTS(ff_outputs),
        .prepare = ff_prepare,
        .execute = nothing,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "froxel_hand_shadows",
        .doc = "Cube and spot shadow maps of a sphere, made by hand (tests)",
        LG_PARAMS(hs_params),
        LG_INPUTS(ff_inputs),
        LG_OUTPUTS(hs_outputs),
        .prepare = hs_prepare,
        .execute = hs_execute,
        .destroy = hs_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "froxel_spec",
        .doc = "froxel.h 1-4 on the CPU in double at the columns' centres (tests)",
        LG_PARAMS(fs_params),
        LG_INPUTS(fs_inputs),
        LG_OUTPUTS(fs_outputs),
        .prepare = fs_prepare,
        .execute = fs_execute,
        .destroy = fs_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "froxel_agree",
        .doc = "Two images compared in memory (tests)",
        LG_PARAMS(fa_params),
        LG_INPUTS(fa_inputs),
        LG_OUTPUTS(fa_outputs),
        .prepare = fa_prepare,
        .execute = fa_execute,
    },
};

LG_PLUGIN_DEFINE("testfroxelspec", "1.0.0",
                 "Point, spot and field inputs of the froxel gl tests, and their reference",
                 fs_types)
