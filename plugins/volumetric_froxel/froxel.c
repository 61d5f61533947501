/*
 * The volumetric_froxel plugin: single scattering in a participating medium through a froxel
 * grid (TECHNIQUES.md §6; seed 2, chapter 3, eqs. 10-12), on gl, cl and cpu; directional,
 * point and spot lights, homogeneous or heterogeneous media (issue 25, froxel.h 4.).
 *
 *   volumetric_froxel   scene + base [+ shadows] -> out, inscatter, grid
 *
 * This file is the node: parameters, prepare, the frame's set-up (camera, lights, medium,
 * slice map, jitter) and the temporal state (the previous frame's camera); froxel.h is the
 * spec of what each backend computes (froxel_cpu.c, froxel_cl.c, froxel_gl.c) and the
 * interface between them. README.md gives the ports, parameters, equations and
 * measurements.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/froxel.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"

#include "froxel.h"

enum { FX_SLICE_UNIFORM = 0, FX_SLICE_EXP };
enum { FX_POINT_SAMPLE = 0, FX_POINT_ANALYTIC };

/* Caps: each side, and the grid's bytes (rgba32f, W x H x D x 16 <= 1 GiB; the backends
 * hold two more volumes of the same size, S and its history). */
#define FX_MAX_W 1024
#define FX_MAX_H 1024
#define FX_MAX_BYTES (1ull << 30)

/* The temporal jitter of frame f: the fractional part of 0.5 + f / phi (golden ratio
 * sequence; frame 0 samples the slice centres as without temporal). */
#define FX_GOLDEN 0.61803398875

typedef struct fx_state {
    int slicing;
    lg_device backend;
    uint32_t gw, gh, gd; /* grid */
    float z_near, z_limit, near_offset, history;
    bool temporal, per_frame;
    fx_accum accum;
    uint32_t width, height; /* image */

    /* temporal: the previous frame's camera and slice map */
    bool has_prev;
    vol_setup prev;
    lg_slice_map prev_map;

    void *backend_state; /* the backend's (fx_*_execute makes it) */
    int point_nodes;     /* froxel.h 4.: 0 sample, 1 .. 8 analytic */
    /* heterogeneous media: the frame's density multipliers (W x H x D) and each light's
     * optical-depth volume, kept while the scene (by address), its lights and tau_res stay */
    float *density;
    vol_tau_volume tau[VOL_MAX_LIGHTS];
    uint32_t n_tau, tau_res;
    const lg_scene *tau_scene;
    vol_light tau_lights[VOL_MAX_LIGHTS];
    lg_density_field tau_field; /* the field they were built for (a scene at the same
                                 * address may carry another one: a viewer's edit) */
    fx_slices slices;           /* this frame's slice tables (fx_slice_tables) */
    bool reported_nonfinite;    /* base's NaN/Inf pixels said (lg_check_input_finite) */
} fx_state;

static int fx_create(lg_node *n)
{
    fx_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->backend = lg_param_backend(n);
    st->slicing = lg_param_enum(n, "slicing");
    st->accum = lg_param_enum(n, "accumulation") == 0 ? FX_ACC_THESIS : FX_ACC_ENERGY;
    st->gw = (uint32_t)lg_param_int(n, "width");
    st->gh = (uint32_t)lg_param_int(n, "height");
    st->gd = (uint32_t)lg_param_int(n, "depth");
    st->z_near = (float)lg_param_float(n, "z_near");
    st->z_limit = (float)lg_param_float(n, "z_limit");
    st->near_offset = (float)lg_param_float(n, "near_offset");
    st->history = (float)lg_param_float(n, "history");
    st->temporal = lg_param_bool(n, "temporal");
    st->per_frame = lg_param_bool(n, "per_frame");
    st->tau_res = (uint32_t)lg_param_int(n, "tau_res");
    int nodes = (int)lg_param_int(n, "point_nodes");
    if (nodes < 1 || nodes > 8)
        return lg_error(n,
                        "point_nodes = %d: the analytic point and spot lights take 1 .. 8 "
                        "Gauss-Legendre nodes per slice",
                        nodes);
    /* vol_tau_build marches each cell to the light: res^4 field reads per light (64: 3e7,
     * about 0.3 s; 128: 3e8), hence the cap */
    if (st->tau_res < 2 || st->tau_res > 128)
        return lg_error(n, "tau_res = %u: the optical-depth volumes' side must be in [2, 128]",
                        st->tau_res);
    st->point_nodes = lg_param_enum(n, "point_integration") == FX_POINT_ANALYTIC ? nodes : 0;

    const struct {
        const char *key;
        float v;
        float max;
    } f[] = {
        { "z_near", st->z_near, 1e30f },
        { "z_limit", st->z_limit, 1e30f },
        { "near_offset", st->near_offset, 1e30f },
        { "history", st->history, 0.99f },
    };
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++)
        if (!isfinite(f[i].v) || f[i].v < 0 || f[i].v > f[i].max)
            return lg_error(n, "%s = %g: must be a finite number in [0, %g]", f[i].key,
                            (double)f[i].v, (double)f[i].max);
    if (st->gw < 1 || st->gh < 1 || st->gd < 1 || st->gw > FX_MAX_W || st->gh > FX_MAX_H ||
        st->gd > FX_MAX_D)
        return lg_error(n,
                        "grid %ux%ux%u: width, height and depth must be in [1, %d], "
                        "[1, %d], [1, %d]",
                        st->gw, st->gh, st->gd, FX_MAX_W, FX_MAX_H, FX_MAX_D);
    uint64_t bytes = (uint64_t)st->gw * st->gh * st->gd * 16u;
    if (bytes > FX_MAX_BYTES)
        return lg_error(n, "grid %ux%ux%u: %.2f GiB of rgba32f, more than the 1 GiB cap", st->gw,
                        st->gh, st->gd, (double)bytes / (double)(1ull << 30));
    if (st->z_limit > 0 && st->z_near > 0 && !(st->z_near < st->z_limit))
        return lg_error(n, "z_near = %g, z_limit = %g: the grid needs z_near < z_limit",
                        (double)st->z_near, (double)st->z_limit);
    return 0;
}

#define FX_SECONDS_PER_FROXEL 1.8e-7

static int fx_prepare(lg_node *n)
{
    fx_state *st = n->user;
    int rc = vol_declare_outputs(n, &st->width, &st->height);
    if (rc)
        return rc;
    rc = lg_froxel_declare(n, FX_OUT_GRID, st->gw, st->gh, st->gd, LG_FORMAT_RGBA32F);
    if (rc)
        return rc;
    /* temporal needs one execution per frame; per_frame re-runs for timing */
    if (st->per_frame || (st->temporal && st->history > 0))
        lg_set_per_frame(n, true);
    /* the estimate: the light pass visits every froxel once per light (the lookup, one
     * per pixel, is small beside it at any grid worth the name). Measured here on the cpu
     * backend (2-core VM shared with compiles, LIGHTGRAPH_THREADS=1,
     * examples/volumetric_froxel.lgraph with a 380x180x512 grid, one light): 3.5e7
     * froxels in 6.3 s, 1.8e-7 s each; llvmpipe and PoCL run the gl and cl backends on the
     * same cores, taken as the same cost. */
    unsigned accept = VOL_ACCEPT_LIGHTS | VOL_ACCEPT_FIELD; /* a backend or the cpu's */
    double froxels = (double)st->gw * st->gh * st->gd * vol_scene_lights(n, accept);
    /* a point or spot light's froxel costs more than a directional one's (README.md, "The
     * light pass's floor": about 3x sampled, 11x analytic with 2 nodes, measured on cpu) */
    double local = 0;
    if (accept & (VOL_ACCEPT_POINT | VOL_ACCEPT_SPOT)) {
        uint32_t all = vol_scene_lights(n, accept),
                 dir = vol_scene_lights(n, VOL_ACCEPT_DIRECTIONAL);
        lg_resource_info info;
        const lg_resource *sc = lg_input(n, VOL_IN_SCENE);
        if (sc && lg_describe(sc, &info, n) == 0 && info.scene && info.scene->dir_lights == 0)
            dir = 0; /* vol_scene_lights counts at least one */
        local = all > dir ? all - dir : 0;
    }
    double factor = st->point_nodes ? 3.0 + 4.0 * st->point_nodes : 3.0;
    double cost = froxels + (double)st->gw * st->gh * st->gd * local * (factor - 1.0);
    lg_declare_work(n, froxels, cost * FX_SECONDS_PER_FROXEL / lg_cpu_workers(n),
                    "froxel x light visits");
    return lg_set_device(n, st->backend);
}

typedef struct fx_density_ctx {
    const fx_frame *f;
    float *density;
} fx_density_ctx;

/* Columns [begin, end) of fx_density: each index writes only its own column. */
static void fx_density_columns(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const fx_density_ctx *x = ctx;
    const fx_frame *f = x->f;
    const vol_setup *v = f->v;
    for (size_t col = begin; col < end; col++) {
        uint32_t i = (uint32_t)(col % f->w), j = (uint32_t)(col / f->w);
        double w[3];
        /* the column's ray as every backend makes it (froxel.h: NDC of the column centre) */
        vol_ray(v, (i + 0.5) * (double)v->width / f->w, (j + 0.5) * (double)v->height / f->h, w);
        double c = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
        for (uint32_t k = 0; k < f->d; k++) {
            double t = f->slices->tj[k] / c, p[3];
            for (int a = 0; a < 3; a++)
                p[a] = v->eye[a] + w[a] * t;
            x->density[col + (size_t)f->w * f->h * k] = (float)lg_medium_field_at(&v->medium, p);
        }
    }
}

/* froxel.h 4.: the density multiplier at each light-pass sample point of the frame, on the
 * host's pool (a grid or fBm field costs about as much per froxel as the light pass). */
static int fx_density(lg_node *n, fx_state *st, const fx_frame *f)
{
    size_t cells = (size_t)f->w * f->h * f->d;
    if (!st->density) {
        st->density = malloc(cells * sizeof(float));
        if (!st->density)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory for %zu froxel densities", cells);
        lg_account_alloc(n, cells * sizeof(float));
    }
    fx_density_ctx x = { f, st->density };
    return lg_parallel_for(n, (size_t)f->w * f->h, 16, fx_density_columns, &x);
}

static void fx_tau_free(lg_node *n, fx_state *st)
{
    for (uint32_t l = 0; l < st->n_tau; l++)
        vol_tau_free(n, &st->tau[l]);
    st->n_tau = 0;
    st->tau_scene = NULL;
}

/* froxel.h 4.: each light's optical-depth volume, remade when the scene or a light moves. */
static int fx_tau(lg_node *n, fx_state *st, const lg_scene *s, const vol_setup *v)
{
    if (st->tau_scene == s && st->n_tau == v->n_lights &&
        memcmp(st->tau_lights, v->lights, v->n_lights * sizeof(vol_light)) == 0 &&
        v->medium.field && memcmp(&st->tau_field, v->medium.field, sizeof st->tau_field) == 0)
        return 0;
    fx_tau_free(n, st);
    for (uint32_t l = 0; l < v->n_lights; l++) {
        int rc = vol_tau_build(n, v, l, st->tau_res, &st->tau[l]);
        if (rc)
            return rc;
        st->n_tau = l + 1;
    }
    memcpy(st->tau_lights, v->lights, v->n_lights * sizeof(vol_light));
    if (v->medium.field)
        st->tau_field = *v->medium.field;
    st->tau_scene = s;
    return 0;
}

/* The frame's slice tables from its slice map and jitter (froxel.h, fx_slices). */
static void fx_slice_tables(const fx_frame *f, fx_slices *t)
{
    double t_prev = 0; /* t_0 = 0: slice 0 starts at the eye */
    t->tk[0] = lg_slice_to_depth(&f->map, 0.0);
    for (uint32_t k = 0; k < f->d; k++) {
        double t_next = lg_slice_to_depth(&f->map, k + 1.0);
        t->tj[k] = lg_slice_to_depth(&f->map, k + (double)f->jitter);
        t->tlen[k] = t_next - t_prev;
        t->tq[k] = lg_slice_to_depth(&f->map, k + 0.5);
        t->tk[k + 1] = t_next;
        t_prev = t_next;
    }
}

/* The grid's slice map for this frame's camera: near = z_near (0: the camera's znear), far
 * = the fog's end; exponential near_offset 0 = the end of slice 0 of a geometric series
 * from near to far (near (far / near)^(1 / depth)), so that every slice after the first
 * spans the same ratio of depths as the first spans near..near_offset. */
static int fx_slice_map(lg_node *n, const fx_state *st, const vol_setup *v, lg_slice_map *map)
{
    double near = st->z_near > 0 ? st->z_near : v->view.znear;
    double far = v->z_limit;
    if (!(near > 0) || !(far > near))
        return lg_error(n,
                        "the grid spans view depths %g .. %g (z_near %g, z_limit %g, the "
                        "camera's znear %g and zfar %g): it needs 0 < near < far",
                        near, far, (double)st->z_near, (double)st->z_limit, (double)v->view.znear,
                        (double)v->view.zfar);
    lg_froxel_slicing s = st->slicing == FX_SLICE_EXP ? LG_FROXEL_EXPONENTIAL
                                                      : LG_FROXEL_UNIFORM_CLIP;
    double off = st->near_offset;
    if (s == LG_FROXEL_EXPONENTIAL && off <= 0)
        off = st->gd > 1 ? near * pow(far / near, 1.0 / st->gd) : 0.5 * (near + far);
    if (s == LG_FROXEL_EXPONENTIAL && st->gd > 1 && !(off > near && off < far))
        return lg_error(n,
                        "near_offset = %g: exponential slicing needs it between the grid's "
                        "near %g and far %g",
                        off, near, far);
    if (lg_slice_map_init(map, s, st->gd, near, far, off))
        return lg_error(n, "slice map (near %g, far %g, near_offset %g, depth %u) refused", near,
                        far, off, st->gd);
    return 0;
}

static bool fx_has_local(const vol_setup *v)
{
    for (uint32_t l = 0; l < v->n_lights; l++)
        if (v->lights[l].type != LG_LIGHT_DIRECTIONAL)
            return true;
    return false;
}

static int fx_execute(lg_node *n, const lg_frame *frame)
{
    fx_state *st = n->user;
    /* base passes into `out`: its NaN and Inf are said once, as `image` says a file's */
    int rc0 = lg_check_input_finite(n, frame, VOL_IN_BASE, "base", NULL, &st->reported_nonfinite);
    if (rc0)
        return rc0;
    const lg_scene *s = lg_scene_get(n, lg_input(n, VOL_IN_SCENE));
    if (!s)
        return LG_ERR_INVALID;
    lg_shadowmap smv;
    const lg_shadowmap *sm = NULL;
    const lg_resource *sres = lg_input(n, VOL_IN_SHADOWS);
    if (sres) {
        lg_resource_info info;
        sm = lg_shadowmap_get(n, sres, &smv);
        if (!sm &&
            (lg_describe(sres, &info, n) != 0 || (info.kind != LG_KIND_SHADOWMAP && !info.neutral)))
            return LG_ERR_INVALID;
        if (sm && (!sm->atlas || sm->resolution == 0 || (sm->n_lights && !sm->lights)))
            return lg_error(n, "input 'shadows': the shadow maps have no atlas, no "
                               "resolution or no light list");
    }
    /* large (32 lights): kept off the stack of the pool's callers */
    vol_setup *v = malloc(sizeof *v);
    if (!v)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int rc = vol_setup_make(n, s, st->width, st->height, st->z_limit, sm,
                            VOL_ACCEPT_LIGHTS | VOL_ACCEPT_FIELD, v);
    fx_frame f = { 0 };
    if (!rc)
        rc = fx_slice_map(n, st, v, &f.map);
    if (rc) {
        free(v);
        return rc;
    }
    bool temporal = st->temporal && st->history > 0;
    f.v = v;
    f.w = st->gw;
    f.h = st->gh;
    f.d = st->gd;
    f.accum = st->accum;
    f.frame = frame ? frame->index : 0;
    if (temporal) {
        double j = 0.5 + (double)f.frame * FX_GOLDEN;
        f.jitter = (float)(j - floor(j));
        f.history = st->history;
        if (st->has_prev) {
            f.prev = &st->prev;
            f.prev_map = st->prev_map;
        }
    } else {
        f.jitter = 0.5f;
    }
    f.sm = sm;
    fx_slice_tables(&f, &st->slices);
    f.slices = &st->slices;
    f.point_nodes = st->point_nodes;
    if (v->heterogeneous) {
        rc = fx_density(n, st, &f);
        if (!rc)
            rc = fx_tau(n, st, s, v);
        if (rc) {
            free(v);
            return rc;
        }
        f.density = st->density;
        f.tau = st->tau;
    }
    switch (st->backend) {
    case LG_DEVICE_GL: rc = fx_gl_execute(n, &st->backend_state, &f); break;
    case LG_DEVICE_CL: rc = fx_cl_execute(n, &st->backend_state, &f); break;
    default: rc = fx_cpu_execute(n, &st->backend_state, &f); break;
    }
    if (!rc) {
        lg_froxel_info info = { .struct_size = sizeof info,
                                .width = st->gw,
                                .height = st->gh,
                                .depth = st->gd,
                                .slicing = f.map.slicing,
                                .near = (float)f.map.near,
                                .far = (float)f.map.far,
                                .near_offset = (float)f.map.near_offset };
        memcpy(info.view, v->view.view, sizeof info.view);
        memcpy(info.proj, v->view.proj, sizeof info.proj);
        rc = lg_froxel_publish(n, FX_OUT_GRID, &info);
    }
    if (!rc && temporal) {
        st->prev = *v;
        st->prev_map = f.map;
        st->has_prev = true;
    }
    if (!rc && f.frame == 0)
        lg_log(n, LG_LOG_INFO, "grid %ux%ux%u (%s, %g .. %g), %u light%s, %s, %s%s%s%s", st->gw,
               st->gh, st->gd,
               f.map.slicing == LG_FROXEL_EXPONENTIAL ? "exponential" : "uniform_clip", f.map.near,
               f.map.far, v->n_lights, v->n_lights == 1 ? "" : "s", sm ? "shadowed" : "unshadowed",
               st->accum == FX_ACC_THESIS ? "thesis" : "energy_conserving",
               temporal ? ", temporal" : "",
               !fx_has_local(v)  ? ""
               : st->point_nodes ? ", point and spot lights analytic"
                                 : ", point and spot lights sampled",
               v->heterogeneous ? ", density field" : "");
    free(v);
    return rc;
}

static void fx_destroy(lg_node *n)
{
    fx_state *st = n->user;
    if (!st)
        return;
    fx_tau_free(n, st);
    if (st->density) {
        lg_account_free(n, (size_t)st->gw * st->gh * st->gd * sizeof(float));
        free(st->density);
    }
    if (st->backend_state) {
        if (st->backend == LG_DEVICE_GL)
            fx_gl_destroy(n, st->backend_state);
        else if (st->backend == LG_DEVICE_CL)
            fx_cl_destroy(n, st->backend_state);
        else
            fx_cpu_destroy(n, st->backend_state);
    }
    free(st);
    n->user = NULL;
}

static const char *const fx_slicings[] = { "uniform_clip", "exponential", NULL };
static const char *const fx_accums[] = { "thesis", "energy_conserving", NULL };
static const char *const fx_point_modes[] = { "sample", "analytic", NULL };

static const lg_param_desc fx_params[] = {
    /* the device of the light pass, the accumulation and the lookup */
    LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL | LG_BACKEND_CL, LG_BACKEND_GL),
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 190,
      .min = 1,
      .max = FX_MAX_W,
      .doc = "grid columns across the image (the thesis: 190)" },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 90,
      .min = 1,
      .max = FX_MAX_H,
      .doc = "grid rows (the thesis: 90)" },
    { .key = "depth",
      .type = LG_PARAM_INT,
      .def.i = 128,
      .min = 1,
      .max = FX_MAX_D,
      .doc = "depth slices (the thesis: 128); W x H x D x 16 bytes <= 1 GiB" },
    { .key = "slicing",
      .type = LG_PARAM_ENUM,
      .def.e = FX_SLICE_UNIFORM,
      .enum_values = fx_slicings,
      .doc = "uniform_clip: uniform in clip depth (the thesis, eq. 10); exponential: a "
             "linear first slice to near_offset, exponential after it (lightgraph/medium.h)" },
    { .key = "z_near",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the slice map starts; 0 = the camera's znear (the fog "
             "between the eye and z_near counts in slice 0)" },
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the fog (and the grid) ends; 0 = the camera's zfar" },
    { .key = "near_offset",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "exponential: view depth where slice 0 ends; 0 = near (far / near)^(1 / depth) "
             "(every slice then spans the same ratio of depths)" },
    { .key = "accumulation",
      .type = LG_PARAM_ENUM,
      .def.e = 1,
      .enum_values = fx_accums,
      .doc = "thesis: eq. 12 as the thesis sums it (S x slice length, no extinction); "
             "energy_conserving: each slice integrated with the transmittance from the eye" },
    { .key = "temporal",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "jitter the sample in each slice (frame f: frac(0.5 + 0.61803398875 f)) and "
             "blend with the previous frame's reprojected S (the node then runs every "
             "frame); off when history = 0" },
    { .key = "history",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.9,
      .min = 0,
      .max = 0.99,
      .doc = "temporal: weight of the reprojected history in the blend" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "run every frame (timing) instead of once" },
    { .key = "point_integration",
      .type = LG_PARAM_ENUM,
      .def.e = FX_POINT_ANALYTIC,
      .enum_values = fx_point_modes,
      .doc = "point and spot lights: sample = F and the phase at the froxel's sample point; "
             "analytic = their integral over the slice's segment of the column's ray "
             "(point_nodes Gauss-Legendre nodes in the airlight angle; right next to a light "
             "on a coarse grid)" },
    { .key = "point_nodes",
      .type = LG_PARAM_INT,
      .def.i = 2,
      .min = 1,
      .max = 8,
      .doc = "analytic: Gauss-Legendre nodes per slice and light (exact for an isotropic "
             "point light at any count)" },
    { .key = "tau_res",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 2,
      .max = 128,
      .doc = "heterogeneous medium: cells along the longest side of each light's "
             "optical-depth volume (the medium's shadow on itself)" },
};

static const lg_port_desc fx_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene: its directional, point and spot lights (at most 32), its medium "
             "(homogeneous or with a density field), its active camera" },
    { .name = "base",
      .kind = LG_KIND_IMAGE,
      .doc = "the lit image with its depth plane (phong's out)" },
    { .name = "shadows",
      .kind = LG_KIND_SHADOWMAP,
      .optional = true,
      .doc = "shadow maps of the lights (a point light's cube or paraboloids); "
             "unconnected: unshadowed" },
};
static const lg_port_desc fx_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f + depth: base x e^(-sigma_t d) + L_v (thesis: base + L_v)" },
    { .name = "inscatter", .kind = LG_KIND_IMAGE, .doc = "rgba32f: L_v alone, alpha 1" },
    { .name = "grid",
      .kind = LG_KIND_FROXEL,
      .doc = "rgba32f W x H x D: in-scattered radiance from the eye to each slice's far "
             "boundary (rgb), mean transmittance (a); info: the slice map and camera" },
};

static const lg_node_type fx_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "volumetric_froxel",
        .doc = "Single scattering in a participating medium through a froxel grid (light "
               "pass, front-to-back accumulation, per-pixel lookup; seed 2 ch. 3), on cpu, gl, "
               "cl; point and spot lights and density fields on cpu",
        LG_PARAMS(fx_params),
        LG_INPUTS(fx_inputs),
        LG_OUTPUTS(fx_outputs),
        .needs = LG_NEEDS_MEDIUM | LG_NEEDS_LIGHT,
        .neutral = LG_NEUTRAL_PASSTHROUGH_FIRST,
        .neutral_input = VOL_IN_BASE,
        .create = fx_create,
        .prepare = fx_prepare,
        .execute = fx_execute,
        .destroy = fx_destroy,
    },
};

LG_PLUGIN_DEFINE("volumetric_froxel", "1.0.0",
                 "Froxel-grid volumetric lighting (single scattering; directional, point and "
                 "spot lights; homogeneous or heterogeneous media) on gl, cl and cpu",
                 fx_types)
