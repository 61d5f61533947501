/*
 * The volumetric_reference plugin (README.md beside this file; TECHNIQUES.md §6, seed 2
 * chapter 3): single scattering in a homogeneous medium lit by directional lights, ray
 * marched on the CPU with exact visibility (Embree occlusion rays). The oracle the four
 * volumetric methods are measured against.
 *
 *   scene, base -> out (base e^(-sigma_t d) + L_v, base's depth), inscatter (L_v)
 *
 * Estimator, per pixel: `spp` sub-pixel rays (stratified: jittered cells of a square grid
 * when spp is a square, else a jittered Latin hypercube), each from the eye along w to its
 * own fog length d = min(first surface (an Embree ray cast), z_limit / dot(w, forward)),
 * cut into `steps` equal segments [a, b]; in each one point x at a jittered place and, per
 * light l,
 *
 *   L_v += L_c sigma_s p_HG(g, dot(w, -L)) V_l(x) e^(-sigma_t a) (b - a) seg(sigma_t (b - a))
 *
 * (lightgraph/medium.h: the transmittance inside the segment is integrated exactly, so
 * only the visibility V_l is sampled). The pixel's L_v is the mean over its rays. Every
 * random number is a hash of (seed, pixel, ray, segment): the same bits for any thread
 * count and any order.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "lg_embree.h"

#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/scene.h"

#include "vol_common.h"

#define VR_MAX_STEPS 65536
#define VR_MAX_SPP 4096
/* Seconds one thread takes per occlusion ray, the march's step around it included.
 * Measured here (2-core VM shared with compiles, LIGHTGRAPH_THREADS=1):
 * examples/volumetric_reference.lgraph at 160x90, spp 4, steps 256, one light: 1.47e7
 * rays in 4.2 s, 2.9e-7 s each (the bunny box: a small BVH; a large scene costs more per
 * ray). What `render` warns with (above a minute) and --explain shows. */
#define VR_SECONDS_PER_RAY 2.9e-7

typedef struct vr_state {
    uint32_t steps, spp;
    uint64_t seed;
    bool centre; /* subpixel = centre: every ray through the pixel centre */
    float z_limit;
    bool per_frame;
    uint32_t width, height;
    bool reported_nonfinite; /* base's NaN/Inf pixels said (lg_check_input_finite) */
} vr_state;

/* ---- random numbers -------------------------------------------------------------------------- */

/* splitmix64's finaliser: a counter-based generator (a pure function of its input). */
static uint64_t vr_mix(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* A uniform double in [0, 1) from the 53 high bits. */
static double vr_unit(uint64_t h)
{
    return (double)(h >> 11) * 0x1.0p-53;
}

/* ---- the march ------------------------------------------------------------------------------- */

typedef struct vr_run {
    const vr_state *st;
    const vol_setup *v;
    const lg_embree *e;
    const float *base, *depth; /* rgba32f and window depth, row_pixels apart */
    size_t base_row;
    float *out, *out_depth, *insc;
    size_t out_row, depth_row, insc_row;
    uint32_t side;      /* spp = side^2, or 0: Latin hypercube */
    double tnear_light; /* occlusion rays start this far from the medium point */
    size_t row0;        /* the batch's first row */
} vr_run;

/* Sub-pixel position k of pixel `pix`: stratified in [0, 1)^2. `perm` (Latin hypercube
 * only): the pixel's permutation of 0 .. spp-1 (vr_perm). */
static void vr_subpixel(const vr_run *r, uint64_t pix, uint32_t k, const uint32_t *perm,
                        double uv[2])
{
    uint64_t h = vr_mix(r->st->seed * 0x2545f4914f6cdd1dull ^ vr_mix(pix * 8192u + k));
    double xi0 = vr_unit(h), xi1 = vr_unit(vr_mix(h));
    if (r->st->centre) {
        uv[0] = uv[1] = 0.5;
        return;
    }
    if (r->side) {
        uv[0] = ((k % r->side) + xi0) / r->side;
        uv[1] = ((k / r->side) + xi1) / r->side;
        return;
    }
    /* a Latin hypercube: u stratified by k, v by the pixel's permutation of k */
    uint32_t spp = r->st->spp;
    uv[0] = (k + xi0) / spp;
    uv[1] = (perm[k] + xi1) / spp;
}

/* A Fisher-Yates shuffle of 0 .. spp-1 seeded by (seed, pixel). */
static void vr_perm(const vr_run *r, uint64_t pix, uint32_t *perm)
{
    uint32_t spp = r->st->spp;
    for (uint32_t i = 0; i < spp; i++)
        perm[i] = i;
    uint64_t s = vr_mix(r->st->seed ^ vr_mix(pix ^ 0x5bd1e995ull));
    for (uint32_t i = spp - 1; i > 0; i--) {
        s = vr_mix(s);
        uint32_t j = (uint32_t)(s % (i + 1));
        uint32_t t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
}

/* One pixel's in-scattered radiance (mean over its rays). */
static void vr_pixel(const vr_run *r, uint32_t x, uint32_t y, double lv[3])
{
    const vol_setup *v = r->v;
    const vr_state *st = r->st;
    uint64_t pix = (uint64_t)y * v->width + x;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    lv[0] = lv[1] = lv[2] = 0.0;
    uint32_t perm[VR_MAX_SPP];
    if (!r->side && !st->centre)
        vr_perm(r, pix, perm);
    for (uint32_t k = 0; k < st->spp; k++) {
        double uv[2], w[3];
        vr_subpixel(r, pix, k, perm, uv);
        vol_ray(v, x + uv[0], y + uv[1], w);
        double cf = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
        if (!(cf > 0.0))
            continue; /* cannot happen for a ray inside the view: no fog behind the eye */
        /* the surface: the first hit past the near plane (what the raster clipped is not
         * there), the fog ends at z_limit */
        double limit = (double)v->z_limit / cf;
        struct RTCRayHit rh;
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = (float)v->eye[0], rh.ray.org_y = (float)v->eye[1];
        rh.ray.org_z = (float)v->eye[2];
        rh.ray.dir_x = (float)w[0], rh.ray.dir_y = (float)w[1], rh.ray.dir_z = (float)w[2];
        rh.ray.tnear = (float)(v->view.znear / cf);
        rh.ray.tfar = (float)limit;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(r->e->scene, &ctx, &rh);
        double d = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? (double)rh.ray.tfar : limit;
        if (!(d > 0.0) || !isfinite(d))
            continue;
        double h = d / st->steps;
        /* per light: L_c sigma_s p; per channel: the segment's own integral (b - a) seg */
        double lit[VOL_MAX_LIGHTS][3], segi[3];
        for (uint32_t l = 0; l < v->n_lights; l++) {
            const float *L = v->lights[l].dir;
            double c = -(w[0] * L[0] + w[1] * L[1] + w[2] * L[2]);
            double p = lg_hg_phase(v->g, c);
            for (int ch = 0; ch < 3; ch++)
                lit[l][ch] = (double)v->lights[l].l_c[ch] * v->sigma_s[ch] * p;
        }
        for (int ch = 0; ch < 3; ch++)
            segi[ch] = h * lg_medium_segment((double)v->sigma_t[ch] * h);
        uint64_t rs = vr_mix(vr_mix(st->seed + 0x632be59bd9b4e019ull) ^ vr_mix(pix * 8192u + k));
        double acc[3] = { 0, 0, 0 };
        for (uint32_t i = 0; i < st->steps; i++) {
            double a = h * i;
            double t = a + h * vr_unit(vr_mix(rs + i));
            double xs[3] = { v->eye[0] + t * w[0], v->eye[1] + t * w[1], v->eye[2] + t * w[2] };
            double vis[3] = { 0, 0, 0 };
            for (uint32_t l = 0; l < v->n_lights; l++) {
                const float *L = v->lights[l].dir;
                struct RTCRay ray = { .org_x = (float)xs[0],
                                      .org_y = (float)xs[1],
                                      .org_z = (float)xs[2],
                                      .tnear = (float)r->tnear_light,
                                      .dir_x = -L[0],
                                      .dir_y = -L[1],
                                      .dir_z = -L[2],
                                      .tfar = INFINITY,
                                      .mask = ~0u };
                rtcOccluded1(r->e->scene, &ctx, &ray);
                if (ray.tfar < 0.0f) /* -inf: occluded */
                    continue;
                for (int ch = 0; ch < 3; ch++)
                    vis[ch] += lit[l][ch];
            }
            for (int ch = 0; ch < 3; ch++)
                if (vis[ch] != 0.0)
                    acc[ch] += vis[ch] * exp(-(double)v->sigma_t[ch] * a);
        }
        for (int ch = 0; ch < 3; ch++)
            lv[ch] += acc[ch] * segi[ch];
    }
    for (int ch = 0; ch < 3; ch++)
        lv[ch] /= st->spp;
}

static void vr_rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const vr_run *r = ctx;
    const vol_setup *v = r->v;
    for (size_t y = r->row0 + begin; y < r->row0 + end; y++)
        for (uint32_t x = 0; x < v->width; x++) {
            double lv[3];
            vr_pixel(r, x, (uint32_t)y, lv);
            const float *b = r->base + (y * r->base_row + x) * 4;
            float dz = r->depth[y * r->base_row + x];
            /* extinction of the surface behind the fog: the pixel-centre ray to the depth
             * the raster stored (what base shows) */
            double d = vol_fog_length(v, x + 0.5, y + 0.5, dz);
            float *o = r->out + (y * r->out_row + x) * 4;
            float *s = r->insc + (y * r->insc_row + x) * 4;
            for (int ch = 0; ch < 3; ch++) {
                double T = isfinite(d) ? exp(-(double)v->sigma_t[ch] * d) : 0.0;
                o[ch] = (float)((double)b[ch] * T + lv[ch]);
                s[ch] = (float)lv[ch];
            }
            o[3] = b[3];
            s[3] = 1.0f;
            r->out_depth[y * r->depth_row + x] = dz;
        }
}

/* ---- the node -------------------------------------------------------------------------------- */

static int vr_create(lg_node *n)
{
    vr_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    return 0;
}

static void vr_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static int vr_prepare(lg_node *n)
{
    vr_state *st = n->user;
    int64_t steps = lg_param_int(n, "steps"), spp = lg_param_int(n, "spp");
    int64_t seed = lg_param_int(n, "seed");
    double z_limit = lg_param_float(n, "z_limit");
    if (steps < 1 || steps > VR_MAX_STEPS)
        return lg_error(n, "steps = %lld: must be in [1, %d]", (long long)steps, VR_MAX_STEPS);
    if (spp < 1 || spp > VR_MAX_SPP)
        return lg_error(n, "spp = %lld: must be in [1, %d]", (long long)spp, VR_MAX_SPP);
    if (seed < 0)
        return lg_error(n, "seed = %lld: must be >= 0", (long long)seed);
    if (!isfinite(z_limit) || z_limit < 0.0 || z_limit > 1e30)
        return lg_error(n, "z_limit = %g: must be a view depth >= 0 (0 = the camera's zfar)",
                        z_limit);
    st->steps = (uint32_t)steps;
    st->spp = (uint32_t)spp;
    st->seed = (uint64_t)seed;
    st->z_limit = (float)z_limit;
    st->centre = lg_param_enum(n, "subpixel") == 1;
    st->per_frame = lg_param_bool(n, "per_frame");
    int rc = vol_declare_outputs(n, &st->width, &st->height);
    if (rc)
        return rc;
    lg_resource_info info;
    if (lg_describe(lg_input(n, VOL_IN_BASE), &info, n) == 0 &&
        info.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n,
                        "input 'base' is not rgba32f (format %d): connect a linear lit "
                        "image (phong's out)",
                        (int)info.image.format);
    if (st->per_frame)
        lg_set_per_frame(n, true);
    /* the estimate: one occlusion ray per pixel, sub-pixel ray, step and light */
    double rays = (double)st->width * st->height * st->spp * st->steps *
                  vol_scene_lights(n, VOL_ACCEPT_DIRECTIONAL);
    lg_declare_work(n, rays, rays * VR_SECONDS_PER_RAY / lg_cpu_workers(n), "occlusion rays");
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int vr_execute(lg_node *n, const lg_frame *frame)
{
    vr_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, VOL_IN_SCENE));
    if (!s)
        return lg_error(n, "input 'scene' holds no scene");
    /* base passes into `out`: its NaN and Inf are said once, as `image` says a file's */
    int rc = lg_check_input_finite(n, frame, VOL_IN_BASE, "base", NULL, &st->reported_nonfinite);
    if (rc)
        return rc;
    vol_setup v;
    rc = vol_setup_make(n, s, st->width, st->height, st->z_limit, NULL, VOL_ACCEPT_DIRECTIONAL, &v);
    if (rc)
        return rc;
    for (int ch = 0; ch < 3; ch++)
        if (!isfinite(v.sigma_s[ch]) || !isfinite(v.sigma_t[ch]) || v.sigma_s[ch] < 0.0f ||
            v.sigma_t[ch] < v.sigma_s[ch])
            return lg_error(n,
                            "the scene's medium has sigma_s %g, sigma_t %g (channel %d): "
                            "need finite 0 <= sigma_s <= sigma_t",
                            (double)v.sigma_s[ch], (double)v.sigma_t[ch], ch);
    if (!isfinite(v.g))
        return lg_error(n, "the scene's medium has g = %g", (double)v.g);
    for (uint32_t l = 0; l < v.n_lights; l++)
        for (int ch = 0; ch < 3; ch++)
            if (!isfinite(v.lights[l].l_c[ch]) || v.lights[l].l_c[ch] < 0.0f)
                return lg_error(n,
                                "light %u: colour x intensity %g (channel %d) is not a "
                                "finite value >= 0",
                                v.lights[l].scene_index, (double)v.lights[l].l_c[ch], ch);

    lg_cpu_view bv, ov, iv;
    if (lg_map_cpu(n, lg_input(n, VOL_IN_BASE), LG_READ, &bv) || !bv.pixels || !bv.depth)
        return lg_error(n, "input 'base' cannot be read on the CPU");
    if (lg_map_cpu(n, lg_output(n, VOL_OUT_OUT), LG_WRITE, &ov) || !ov.pixels || !ov.depth)
        return lg_error(n, "output 'out' cannot be written");
    if (lg_map_cpu(n, lg_output(n, VOL_OUT_INSCATTER), LG_WRITE, &iv) || !iv.pixels)
        return lg_error(n, "output 'inscatter' cannot be written");

    /* every instance in world space, as prt_bake builds it (plugins/embree_common), at
     * this frame's pose when the scene is animated (ABI 3.1) */
    lg_embree e;
    rc = lg_embree_make_at(n, s, frame->time, &e);
    if (rc) {
        lg_embree_free(&e);
        return rc;
    }
    /* buffers + about 1.5x for the BVH; made and released in every execute */
    const uint64_t counted = (uint64_t)e.bytes * 5 / 2;
    lg_account_alloc(n, counted);
    uint32_t side = (uint32_t)lround(sqrt((double)st->spp));
    vr_run r = {
        .st = st,
        .v = &v,
        .e = &e,
        .base = bv.pixels,
        .depth = bv.depth,
        .base_row = bv.row_pixels,
        .out = ov.pixels,
        .out_depth = ov.depth,
        .insc = iv.pixels,
        .out_row = ov.row_pixels,
        .depth_row = ov.row_pixels,
        .insc_row = iv.row_pixels,
        .side = side * side == st->spp ? side : 0,
        /* occlusion rays start in the medium, not on a surface: a small fraction of the
         * scene's size clears float rounding at the origin without skipping geometry */
        .tnear_light = 1e-5 * (e.extent > 0.0 ? e.extent : 1.0),
    };
    /* the rows in about 32 batches, so that the progress bar moves between them (the
     * pool's chunks must not call the host); each row is one chunk: the work of a row is
     * independent of which thread runs it, so the result is the same bits for any count */
    uint32_t H = st->height, per = (H + 31) / 32;
    for (uint32_t y0 = 0; y0 < H && rc == 0; y0 += per) {
        uint32_t y1 = y0 + per < H ? y0 + per : H;
        r.row0 = y0;
        rc = lg_parallel_for(n, y1 - y0, 1, vr_rows, &r);
        lg_progress(n, (double)y1 / H, "ray marching");
    }
    if (rc == 0)
        lg_log(n, LG_LOG_DEBUG, "%ux%u, %u lights, spp %u, steps %u: %.3g occlusion rays",
               st->width, st->height, v.n_lights, st->spp, st->steps,
               (double)st->width * st->height * st->spp * st->steps * v.n_lights);
    lg_embree_free(&e);
    lg_account_free(n, counted);
    return rc;
}

static const char *const vr_subpixels[] = { "jittered", "centre", NULL };

static const lg_param_desc vr_params[] = {
    { .key = "steps",
      .type = LG_PARAM_INT,
      .def.i = 256,
      .min = 1,
      .max = VR_MAX_STEPS,
      .doc = "segments per ray (one jittered visibility sample each; the transmittance "
             "inside a segment is integrated exactly)" },
    { .key = "spp",
      .type = LG_PARAM_INT,
      .def.i = 4,
      .min = 1,
      .max = VR_MAX_SPP,
      .doc = "rays per pixel, stratified within the pixel (a square count: a jittered grid; "
             "any other: a jittered Latin hypercube)" },
    { .key = "seed",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 0x7fffffff,
      .doc = "the jitter's seed (every random number is a hash of seed, pixel, ray, step)" },
    { .key = "subpixel",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = vr_subpixels,
      .doc = "jittered (the rays cover the pixel: antialiased) or centre (every ray through "
             "the pixel centre, as the screen-space methods sample; spp then averages the "
             "visibility samples only)" },
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth (scene units) where the fog ends; 0 = the camera's zfar" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "run again on every frame (--frames), for timing; the result is the same" },
};

static const lg_port_desc vr_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene: its directional lights, medium, active camera; every instance "
             "occludes" },
    { .name = "base",
      .kind = LG_KIND_IMAGE,
      .doc = "the lit image with depth (phong's out), rgba32f" },
};
static const lg_port_desc vr_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f + depth: base e^(-sigma_t d) + inscatter, base's depth" },
    { .name = "inscatter",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: the in-scattered radiance L_v alone, alpha 1" },
};

static const lg_node_type vr_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "volumetric_reference",
        .doc = "Single scattering in the scene's homogeneous medium by ray marching with "
               "Embree visibility (CPU): the oracle of the volumetric methods",
        LG_PARAMS(vr_params),
        LG_INPUTS(vr_inputs),
        LG_OUTPUTS(vr_outputs),
        .needs = LG_NEEDS_MEDIUM | LG_NEEDS_DIR_LIGHT,
        .neutral = LG_NEUTRAL_PASSTHROUGH_FIRST,
        .neutral_input = 1,
        .create = vr_create,
        .prepare = vr_prepare,
        .execute = vr_execute,
        .destroy = vr_destroy,
    },
};

LG_PLUGIN_DEFINE("volumetric_reference", "1.0.0",
                 "Ray-marched single scattering with Embree visibility: the reference of "
                 "the volumetric methods",
                 vr_types)
