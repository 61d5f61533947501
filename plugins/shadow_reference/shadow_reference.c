/*
 * The shadow_reference plugin (README.md beside this file): the exact visibility of one
 * light at the surfaces phong shades, by Embree shadow rays, as the reference the shadow
 * maps' filtering (PCF, PCSS) is measured against (issue 25).
 *
 *   scene, lit, unlit -> out (unlit + V (lit - unlit), lit's depth), visibility (V),
 *                        position (the surface point V was computed at)
 *
 * lit is phong's image of the scene with the light and no shadow map, unlit the same
 * without that light (ambient and any other light): lit - unlit is then exactly the
 * light's unshadowed direct term as phong computes it, whatever phong's shading settings,
 * and out is what phong would show if its shadow test were exact. V is the fraction of the
 * light visible from the surface point seen through the pixel centre (an Embree ray cast
 * through the camera phong used): 0 or 1 for a hard light (one occlusion ray to the
 * point or spot light's position, or along a directional light), the visible fraction of
 * an area light of diameter `light_size` (a disk facing the point; directional: a cone of
 * that angular diameter) sampled by a fixed pattern of `light_samples` rays (a Vogel
 * spiral: uniform in area, the same for every pixel, so the result has no noise, only
 * steps of 1 / light_samples). Why this design and not a second phong on the CPU: the
 * shading then never differs from phong's (textures, specular, falloff, cones, every
 * shading mode), so the error measured against it is the shadow test's alone.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "lg_embree.h"

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"
#include "lightgraph/vecmath.h"

#define SR_MAX_SAMPLES 4096
/* Seconds one thread takes per shadow ray in the bunny box (measured with
 * LIGHTGRAPH_THREADS=1 at 320x180, 256 samples: about 3e-7 s, as volumetric_reference's
 * occlusion rays): what --explain and render's long-run warning show. */
#define SR_SECONDS_PER_RAY 3e-7

typedef struct sr_state {
    int64_t light, camera;
    double light_size;
    uint32_t samples;
    bool per_frame;
    uint32_t width, height;
} sr_state;

/* ---- the rays -------------------------------------------------------------------------------- */

typedef struct sr_run {
    const lg_embree *e;
    double inv_vp[16]; /* clip -> world, column-major (the camera's view_proj inverted) */
    double eye[3], forward[3];
    double znear;
    uint32_t width, height;
    int type;           /* the light's lg_light_type */
    double q[3];        /* point, spot: the light's position */
    double to_light[3]; /* directional: unit, towards the light */
    double radius;      /* the area light's radius (m) or half-angle's tangent; 0: hard */
    uint32_t samples;   /* rays per pixel towards the light (1 when hard) */
    double offset;      /* shadow rays start this far off the surface */
    const float *lit, *unlit, *depth;
    size_t lit_row, unlit_row;
    float *out, *out_depth, *vis, *pos;
    size_t out_row, vis_row, pos_row;
    uint32_t *missed; /* per row: drawn pixels whose centre ray hit nothing */
} sr_run;

/* Inverse of a column-major 4x4 matrix by Gauss-Jordan elimination with partial pivoting, in
 * double (the camera's unprojection); false if singular. */
static bool sr_invert(const float m[16], double out[16])
{
    double a[4][8];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            a[r][c] = m[c * 4 + r];
            a[r][c + 4] = r == c ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; c++) {
        int p = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(a[r][c]) > fabs(a[p][c]))
                p = r;
        if (!(fabs(a[p][c]) > 1e-300))
            return false;
        for (int k = 0; k < 8; k++) {
            double t = a[c][k];
            a[c][k] = a[p][k];
            a[p][k] = t;
        }
        double inv = 1.0 / a[c][c];
        for (int k = 0; k < 8; k++)
            a[c][k] *= inv;
        for (int r = 0; r < 4; r++)
            if (r != c) {
                double f = a[r][c];
                for (int k = 0; k < 8; k++)
                    a[r][k] -= f * a[c][k];
            }
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            out[c * 4 + r] = a[r][c + 4];
    return true;
}

static void sr_unproject(const double m[16], double x, double y, double z, double p[3])
{
    double v[4];
    for (int r = 0; r < 4; r++)
        v[r] = m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r];
    for (int k = 0; k < 3; k++)
        p[k] = v[k] / v[3];
}

static void sr_basis(const double n[3], double e1[3], double e2[3])
{
    /* any unit e1 orthogonal to n (the axis least aligned with n crossed with it) */
    double a[3] = { 0, 0, 0 };
    int k = fabs(n[0]) < fabs(n[1]) ? (fabs(n[0]) < fabs(n[2]) ? 0 : 2)
                                    : (fabs(n[1]) < fabs(n[2]) ? 1 : 2);
    a[k] = 1.0;
    e1[0] = a[1] * n[2] - a[2] * n[1];
    e1[1] = a[2] * n[0] - a[0] * n[2];
    e1[2] = a[0] * n[1] - a[1] * n[0];
    double l = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (int c = 0; c < 3; c++)
        e1[c] /= l;
    e2[0] = n[1] * e1[2] - n[2] * e1[1];
    e2[1] = n[2] * e1[0] - n[0] * e1[2];
    e2[2] = n[0] * e1[1] - n[1] * e1[0];
}

/* Sample k of n on the unit disk: Vogel's spiral, radius sqrt((k + 1/2) / n) at k golden
 * angles (uniform in area and stratified in radius; the same points for every pixel). */
static void sr_disk(uint32_t k, uint32_t n, double *x, double *y)
{
    const double golden = LG_PI * (3.0 - sqrt(5.0));
    double r = sqrt((k + 0.5) / n), a = k * golden;
    *x = r * cos(a);
    *y = r * sin(a);
}

static bool sr_unoccluded(const sr_run *r, struct RTCIntersectContext *ctx, const double o[3],
                          const double d[3], double tfar)
{
    struct RTCRay ray = { .org_x = (float)o[0],
                          .org_y = (float)o[1],
                          .org_z = (float)o[2],
                          .tnear = 0.0f,
                          .dir_x = (float)d[0],
                          .dir_y = (float)d[1],
                          .dir_z = (float)d[2],
                          .tfar = (float)tfar,
                          .mask = ~0u };
    rtcOccluded1(r->e->scene, ctx, &ray);
    return !(ray.tfar < 0.0f); /* -inf: occluded */
}

/* V at the surface point p with geometric normal ng (unit, either side): the fraction of the
 * light's samples that the scene does not hide. */
static double sr_visibility(const sr_run *r, struct RTCIntersectContext *ctx, const double p[3],
                            const double ng[3])
{
    /* the axis towards the light's centre */
    double axis[3], dist = INFINITY;
    if (r->type == LG_LIGHT_DIRECTIONAL) {
        memcpy(axis, r->to_light, sizeof axis);
    } else {
        for (int c = 0; c < 3; c++)
            axis[c] = r->q[c] - p[c];
        dist = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        if (!(dist > 0.0))
            return 1.0; /* the light on the surface: nothing between them */
        for (int c = 0; c < 3; c++)
            axis[c] /= dist;
    }
    /* start off the surface on the light's side of it, so that the ray cannot hit the
     * triangle it leaves (a surface turned away from the light gets no direct term from
     * phong anyway) */
    double s = ng[0] * axis[0] + ng[1] * axis[1] + ng[2] * axis[2] >= 0.0 ? 1.0 : -1.0;
    double o[3];
    for (int c = 0; c < 3; c++)
        o[c] = p[c] + s * r->offset * ng[c];
    double e1[3], e2[3];
    if (r->samples > 1)
        sr_basis(axis, e1, e2);
    uint32_t seen = 0;
    for (uint32_t k = 0; k < r->samples; k++) {
        double target[3], d[3], tfar;
        double u = 0.0, v = 0.0;
        if (r->samples > 1)
            sr_disk(k, r->samples, &u, &v);
        if (r->type == LG_LIGHT_DIRECTIONAL) {
            for (int c = 0; c < 3; c++)
                d[c] = axis[c] + r->radius * (u * e1[c] + v * e2[c]);
            tfar = INFINITY;
        } else {
            for (int c = 0; c < 3; c++) {
                target[c] = r->q[c] + r->radius * (u * e1[c] + v * e2[c]);
                d[c] = target[c] - o[c];
            }
            tfar = 1.0;
        }
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(l > 0.0)) {
            seen++;
            continue;
        }
        for (int c = 0; c < 3; c++)
            d[c] /= l;
        /* a local light's segment ends just short of it: geometry behind the light does
         * not shadow it */
        if (r->type != LG_LIGHT_DIRECTIONAL)
            tfar = l * (1.0 - 1e-6);
        seen += sr_unoccluded(r, ctx, o, d, tfar);
    }
    return (double)seen / r->samples;
}

static void sr_rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const sr_run *r = ctx;
    struct RTCIntersectContext ic;
    rtcInitIntersectContext(&ic);
    for (size_t y = begin; y < end; y++) {
        uint32_t missed = 0;
        for (uint32_t x = 0; x < r->width; x++) {
            const float *li = r->lit + (y * r->lit_row + x) * 4;
            const float *un = r->unlit + (y * r->unlit_row + x) * 4;
            float dz = r->depth[y * r->lit_row + x];
            double V = 1.0, hit[4] = { 0, 0, 0, 0 };
            if (dz < 1.0f) {
                /* the pixel centre's ray, as the raster samples it (row 0 at the top: the
                 * camera's projection flips Y, so ndc y = 2 (y + 1/2) / H - 1) */
                double nx = 2.0 * (x + 0.5) / r->width - 1.0;
                double ny = 2.0 * (y + 0.5) / r->height - 1.0;
                double far_p[3], w[3];
                sr_unproject(r->inv_vp, nx, ny, 1.0, far_p);
                for (int c = 0; c < 3; c++)
                    w[c] = far_p[c] - r->eye[c];
                double wl = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
                for (int c = 0; c < 3; c++)
                    w[c] /= wl;
                double cf = w[0] * r->forward[0] + w[1] * r->forward[1] + w[2] * r->forward[2];
                struct RTCRayHit rh;
                memset(&rh, 0, sizeof rh);
                rh.ray.org_x = (float)r->eye[0], rh.ray.org_y = (float)r->eye[1];
                rh.ray.org_z = (float)r->eye[2];
                rh.ray.dir_x = (float)w[0], rh.ray.dir_y = (float)w[1];
                rh.ray.dir_z = (float)w[2];
                rh.ray.tnear = (float)(cf > 0.0 ? r->znear / cf : 0.0);
                rh.ray.tfar = INFINITY;
                rh.ray.mask = ~0u;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcIntersect1(r->e->scene, &ic, &rh);
                if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                    missed++; /* the raster drew an edge the ray passed: V stays 1 */
                } else {
                    double t = rh.ray.tfar, p[3], ng[3] = { rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z };
                    double nl = sqrt(ng[0] * ng[0] + ng[1] * ng[1] + ng[2] * ng[2]);
                    for (int c = 0; c < 3; c++) {
                        p[c] = r->eye[c] + t * w[c];
                        ng[c] = nl > 0.0 ? ng[c] / nl : 0.0;
                    }
                    V = sr_visibility(r, &ic, p, ng);
                    hit[0] = p[0], hit[1] = p[1], hit[2] = p[2], hit[3] = 1.0;
                }
            }
            float *o = r->out + (y * r->out_row + x) * 4;
            for (int c = 0; c < 3; c++)
                o[c] = (float)((double)un[c] + V * ((double)li[c] - (double)un[c]));
            o[3] = li[3];
            r->out_depth[y * r->out_row + x] = dz;
            float *v = r->vis + (y * r->vis_row + x) * 4;
            v[0] = v[1] = v[2] = (float)V;
            v[3] = 1.0f;
            float *h = r->pos + (y * r->pos_row + x) * 4;
            for (int c = 0; c < 4; c++)
                h[c] = (float)hit[c];
        }
        r->missed[y] = missed;
    }
}

/* ---- the node -------------------------------------------------------------------------------- */

static int sr_create(lg_node *n)
{
    sr_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->light = lg_param_int(n, "light");
    st->camera = lg_param_int(n, "camera");
    st->light_size = lg_param_float(n, "light_size");
    st->samples = (uint32_t)lg_param_int(n, "light_samples");
    st->per_frame = lg_param_bool(n, "per_frame");
    if (!isfinite(st->light_size) || st->light_size < 0.0)
        return lg_error(n, "light_size = %g: must be a finite size >= 0", st->light_size);
    return 0;
}

static void sr_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static int sr_prepare(lg_node *n)
{
    sr_state *st = n->user;
    lg_resource_info li, ui;
    if (lg_describe(lg_input(n, 1), &li, n) != 0 || li.kind != LG_KIND_IMAGE ||
        li.image.format != LG_FORMAT_RGBA32F || !(li.image.flags & LG_IMAGE_DEPTH))
        return lg_error(n, "input 'lit' must be an rgba32f image with depth (phong's out, "
                           "rendered without a shadow map)");
    if (lg_describe(lg_input(n, 2), &ui, n) != 0 || ui.kind != LG_KIND_IMAGE ||
        ui.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n, "input 'unlit' must be an rgba32f image (phong's out without the "
                           "light)");
    if (ui.image.width != li.image.width || ui.image.height != li.image.height)
        return lg_error(n, "input 'unlit' is %ux%u but 'lit' is %ux%u: render both at one size",
                        ui.image.width, ui.image.height, li.image.width, li.image.height);
    st->width = li.image.width;
    st->height = li.image.height;
    lg_image_desc d = { .width = st->width,
                        .height = st->height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = LG_IMAGE_DEPTH };
    int rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    d.flags = 0;
    rc = lg_declare_image(n, 1, &d);
    if (rc)
        return rc;
    rc = lg_declare_image(n, 2, &d);
    if (rc)
        return rc;
    if (st->per_frame)
        lg_set_per_frame(n, true);
    double per = st->light_size > 0.0 ? (double)st->samples : 1.0;
    double rays = (double)st->width * st->height * (1.0 + per);
    lg_declare_work(n, rays, rays * SR_SECONDS_PER_RAY / lg_cpu_workers(n), "rays");
    return lg_set_device(n, LG_DEVICE_CPU);
}

static int sr_execute(lg_node *n, const lg_frame *frame)
{
    sr_state *st = n->user;
    const lg_scene *s0 = lg_scene_get(n, lg_input(n, 0));
    if (!s0)
        return lg_error(n, "input 'scene' holds no scene");
    /* an animated scene's lights and camera at this frame's time, as phong sees them */
    lg_scene posed;
    const lg_scene *s = s0;
    bool animated = lg_scene_is_animated(s0);
    if (animated) {
        int rc = lg_scene_at(n, s0, frame->time, &posed);
        if (rc)
            return rc;
        s = &posed;
    }
    int rc = 0;
    lg_embree e;
    memset(&e, 0, sizeof e);
    uint32_t *missed = NULL;
    sr_run r = { .width = st->width, .height = st->height };
    if (s->n_lights == 0) {
        rc = lg_error(n, "the scene has no light: give the scene with the light whose "
                         "shadow is referenced (and 'unlit' rendered without it)");
        goto done;
    }
    int64_t li = st->light < 0 ? (int64_t)s->n_lights - 1 : st->light;
    if (li >= (int64_t)s->n_lights) {
        rc = lg_error(n, "light = %lld: the scene has %u light%s", (long long)st->light,
                      s->n_lights, s->n_lights == 1 ? "" : "s");
        goto done;
    }
    const lg_light *L = &s->lights[li];
    r.type = (int)L->type;
    if (L->type == LG_LIGHT_DIRECTIONAL) {
        double d[3] = { -L->direction[0], -L->direction[1], -L->direction[2] };
        double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(l > 0.0) || !isfinite(l)) {
            rc = lg_error(n, "light %lld '%s': direction [%g, %g, %g] is not a direction",
                          (long long)li, L->name ? L->name : "", (double)L->direction[0],
                          (double)L->direction[1], (double)L->direction[2]);
            goto done;
        }
        for (int c = 0; c < 3; c++)
            r.to_light[c] = d[c] / l;
        /* the cone of angular diameter light_size: directions through a disk of radius
         * tan(size / 2) at unit distance */
        r.radius = st->light_size > 0.0 ? tan(0.5 * fmin(st->light_size, 3.0)) : 0.0;
    } else if (L->type == LG_LIGHT_POINT || L->type == LG_LIGHT_SPOT) {
        for (int c = 0; c < 3; c++)
            r.q[c] = L->position[c];
        if (!isfinite(r.q[0]) || !isfinite(r.q[1]) || !isfinite(r.q[2])) {
            rc = lg_error(n, "light %lld '%s': its position is not finite", (long long)li,
                          L->name ? L->name : "");
            goto done;
        }
        r.radius = 0.5 * st->light_size;
    } else {
        rc = lg_error(n, "light %lld '%s' has an unknown type %d", (long long)li,
                      L->name ? L->name : "", (int)L->type);
        goto done;
    }
    r.samples = r.radius > 0.0 ? st->samples : 1;

    lg_scene_view view;
    rc = lg_scene_view_make(n, s, st->camera, st->width, st->height, &view);
    if (rc)
        goto done;
    if (!sr_invert(view.view_proj, r.inv_vp)) {
        rc = lg_error(n, "the camera's view-projection matrix is singular");
        goto done;
    }
    r.eye[0] = view.eye.x, r.eye[1] = view.eye.y, r.eye[2] = view.eye.z;
    r.forward[0] = view.forward.x, r.forward[1] = view.forward.y, r.forward[2] = view.forward.z;
    r.znear = view.znear;

    lg_cpu_view lv, uv, ov, vv, pv;
    if (lg_map_cpu(n, lg_input(n, 1), LG_READ, &lv) || !lv.pixels || !lv.depth) {
        rc = lg_error(n, "input 'lit' cannot be read on the CPU with its depth");
        goto done;
    }
    if (lg_map_cpu(n, lg_input(n, 2), LG_READ, &uv) || !uv.pixels) {
        rc = lg_error(n, "input 'unlit' cannot be read on the CPU");
        goto done;
    }
    if (lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov) || !ov.pixels || !ov.depth) {
        rc = lg_error(n, "output 'out' cannot be written");
        goto done;
    }
    if (lg_map_cpu(n, lg_output(n, 1), LG_WRITE, &vv) || !vv.pixels) {
        rc = lg_error(n, "output 'visibility' cannot be written");
        goto done;
    }
    if (lg_map_cpu(n, lg_output(n, 2), LG_WRITE, &pv) || !pv.pixels) {
        rc = lg_error(n, "output 'position' cannot be written");
        goto done;
    }
    r.lit = lv.pixels, r.depth = lv.depth, r.lit_row = lv.row_pixels;
    r.unlit = uv.pixels, r.unlit_row = uv.row_pixels;
    r.out = ov.pixels, r.out_depth = ov.depth, r.out_row = ov.row_pixels;
    r.vis = vv.pixels, r.vis_row = vv.row_pixels;
    r.pos = pv.pixels, r.pos_row = pv.row_pixels;
    missed = calloc(st->height, sizeof *missed);
    if (!missed) {
        rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u rows)", st->height);
        goto done;
    }
    r.missed = missed;

    rc = lg_embree_make_at(n, s0, frame->time, &e);
    if (rc)
        goto done;
    const uint64_t counted = (uint64_t)e.bytes * 5 / 2; /* buffers + about 1.5x for the BVH */
    lg_account_alloc(n, counted);
    r.e = &e;
    /* shadow rays leave the surface by a small fraction of the scene's size: clears the
     * float rounding of the hit point (about 1e-7 of the distance) without skipping a
     * contact (the shadow map's normal offset is a texel, 100 to 1000 times more) */
    r.offset = 1e-5 * (e.extent > 0.0 ? e.extent : 1.0);
    rc = lg_parallel_for(n, st->height, 1, sr_rows, &r);
    lg_account_free(n, counted);
    if (rc == 0) {
        uint64_t total = 0;
        for (uint32_t y = 0; y < st->height; y++)
            total += missed[y];
        lg_log(n, LG_LOG_DEBUG,
               "%ux%u, light %lld (%s), %u ray%s per pixel towards it; %llu drawn pixels "
               "whose centre ray missed (V = 1 there)",
               st->width, st->height, (long long)li,
               r.type == LG_LIGHT_DIRECTIONAL ? "directional"
               : r.type == LG_LIGHT_SPOT      ? "spot"
                                              : "point",
               r.samples, r.samples == 1 ? "" : "s", (unsigned long long)total);
    }
done:
    free(missed);
    lg_embree_free(&e);
    if (animated)
        lg_scene_at_free(s0, &posed);
    return rc;
}

static const lg_param_desc sr_params[] = {
    { .key = "light",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "the scene light whose visibility is exact; -1 = the last (the one a `light` "
             "node added)" },
    { .key = "light_size",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 100,
      .doc = "0: a hard light (one shadow ray); > 0: an area light of this diameter "
             "(metres; directional: its angular diameter, radians), as shadowmap's "
             "pcss_light_size" },
    { .key = "light_samples",
      .type = LG_PARAM_INT,
      .def.i = 256,
      .min = 1,
      .max = SR_MAX_SAMPLES,
      .doc = "light_size > 0: shadow rays per pixel, a fixed Vogel spiral over the light's "
             "disk (V in steps of 1 / light_samples, no noise)" },
    { .key = "camera",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "the scene's camera phong looked through; -1 = the active one" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "run again on every frame (--frames), for timing; the result is the same" },
};

static const lg_port_desc sr_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene phong drew, with the light: its geometry occludes, its camera and "
             "the light are read" },
    { .name = "lit",
      .kind = LG_KIND_IMAGE,
      .doc = "phong's out with the light and no shadow map (rgba32f + depth)" },
    { .name = "unlit",
      .kind = LG_KIND_IMAGE,
      .doc = "phong's out without the light (its upstream scene), same size and settings" },
};
static const lg_port_desc sr_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f + depth: unlit + V (lit - unlit), lit's alpha and depth" },
    { .name = "visibility",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: V, the light's visible fraction at the pixel's surface (1 where "
             "nothing is drawn)" },
    { .name = "position",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: the world point V was computed at (x, y, z, 1); 0 where the pixel "
             "centre's ray hit nothing (for studies by region, e.g. a cube map's seams)" },
};

static const lg_node_type sr_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "shadow_reference",
        .doc = "Phong's lit image with one light's exact visibility (Embree shadow rays; an "
               "area light for PCSS): the reference of the shadow maps (CPU)",
        LG_PARAMS(sr_params),
        LG_INPUTS(sr_inputs),
        LG_OUTPUTS(sr_outputs),
        /* a scene without any light: lit = unlit, so out is lit as it is (the other
         * outputs black) and the plugin is not loaded */
        .needs = LG_NEEDS_LIGHT,
        .neutral = LG_NEUTRAL_PASSTHROUGH_FIRST,
        .neutral_input = 1,
        .create = sr_create,
        .prepare = sr_prepare,
        .execute = sr_execute,
        .destroy = sr_destroy,
    },
};

LG_PLUGIN_DEFINE("shadow_reference", "1.0.0",
                 "Exact visibility of one light by Embree shadow rays: the reference of the "
                 "shadow maps' filtering",
                 sr_types)
