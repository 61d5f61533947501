/*
 * The shadowmap plugin: depth maps of a scene's lights, each in its own tile of one depth-only
 * atlas image (TECHNIQUES.md §2; lightgraph/shadowmap.h): one orthographic map per
 * directional light, one perspective map per spot light (a cube of six when its cone is too
 * wide for one), a cube of six perspective maps per point light.
 *
 *   shadowmap   scene -> shadows (a composite shadow map: parts atlas, lights, info)
 *
 * prepare() fits every light's view and projection to the scene (its bounds, or the camera
 * frustum clipped by them) and declares the parts; execute() publishes them with the tile
 * layout and the bias (the lights and info parts) and
 * rasterises every instance of every mesh into each light's tile: per light, one instanced
 * draw per mesh and handedness, the instances' model matrices in one storage buffer.
 * README.md gives the ports, the parameters, the fit, the culling and the bias rules.
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"
#include "lightgraph/shadowmap.h"

#include "shadowmap.frag.h"
#include "shadowmap.vert.h"

enum { SM_FIT_BOUNDS = 0, SM_FIT_FRUSTUM };
enum { SM_CULL_FRONT = 0, SM_CULL_BACK, SM_CULL_NONE };

/* Defaults of the bias parameters (README.md, "Bias", says how they were chosen). */
#define SM_DEF_BIAS_CONSTANT 0.0002
#define SM_DEF_BIAS_SLOPE 0.0005
#define SM_DEF_NORMAL_OFFSET 1.0

typedef struct sm_state {
    uint32_t resolution;
    int fit, cull;
    int64_t camera; /* fit = frustum: the scene's camera, -1 = the active one */
    float aspect;   /* fit = frustum: width / height, 0 = the render size's */
    float bias_constant, bias_slope, normal_offset;
    uint32_t pcf_radius;   /* percentage-closer filtering: (2 r + 1)^2 taps, applied by consumers */
    float pcss_light_size; /* > 0: PCSS, the light's size (README.md, "Filtering") */
    uint32_t cols, rows;   /* the atlas's grid of tiles */
    uint32_t n_dir, n_spot, n_cube; /* lights with an orthographic map, one perspective map, a
                                     * cube */
    lg_shadowmap view;              /* what prepare() computed, as consumers will see it */
    lg_shadow_light *lights;        /* view.lights, owned here */
    const lg_shadowmap *sm;         /* &view once prepared */
    lg_gl_pass *pass;               /* made on the first execute */
    lg_gl_uniform u_view_proj;
    lg_gl_material_binds mat;     /* alpha masks (material.glsl) */
    const lg_resource *scene_res; /* during a draw, for sm_on_mesh */
} sm_state;

/* ---- create ---------------------------------------------------------------------------------- */

static int sm_create(lg_node *n)
{
    sm_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->resolution = (uint32_t)lg_param_int(n, "resolution");
    st->fit = lg_param_enum(n, "fit");
    st->cull = lg_param_enum(n, "cull");
    st->camera = lg_param_int(n, "camera");
    st->aspect = (float)lg_param_float(n, "aspect");
    st->bias_constant = (float)lg_param_float(n, "bias_constant");
    st->bias_slope = (float)lg_param_float(n, "bias_slope");
    st->normal_offset = (float)lg_param_float(n, "normal_offset");
    st->pcf_radius = (uint32_t)lg_param_int(n, "pcf_radius");
    st->pcss_light_size = (float)lg_param_float(n, "pcss_light_size");
    return 0;
}

/* ---- geometry helpers ------------------------------------------------------------------------ */

static bool sm_finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static lg_vec3 sm_corner(const float lo[3], const float hi[3], int k)
{
    return lg_v3(k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
}

/* The scene's world bounds as the fit uses them: the scene's own, or a cube of side 2 at
 * the origin when it has no geometry (nothing is drawn then, so any box will do). */
static int sm_bounds(lg_node *n, const lg_scene *s, float lo[3], float hi[3])
{
    if (!sm_finite3(s->bounds_min) || !sm_finite3(s->bounds_max) ||
        s->bounds_min[0] > s->bounds_max[0] || s->bounds_min[1] > s->bounds_max[1] ||
        s->bounds_min[2] > s->bounds_max[2]) {
        for (int k = 0; k < 3; k++)
            if (isnan(s->bounds_min[k]) || isnan(s->bounds_max[k]))
                return lg_error(n, "the scene's bounds are not numbers ([%g %g %g] .. [%g %g %g])",
                                (double)s->bounds_min[0], (double)s->bounds_min[1],
                                (double)s->bounds_min[2], (double)s->bounds_max[0],
                                (double)s->bounds_max[1], (double)s->bounds_max[2]);
        for (int k = 0; k < 3; k++) {
            lo[k] = -1.0f;
            hi[k] = 1.0f;
        }
        return 0;
    }
    memcpy(lo, s->bounds_min, 3 * sizeof(float));
    memcpy(hi, s->bounds_max, 3 * sizeof(float));
    return 0;
}

/* ---- the camera frustum clipped by the bounds (fit = frustum) -------------------------------- */

/* The view_proj of the camera a consumer looks through (`camera`, -1 = the active one) at
 * aspect `aspect` (0 = the render size's), after the preview's rules (plugins/preview/
 * README.md, "Camera"), without the Y flip (it does not change the frustum). */
static int sm_camera_view_proj(lg_node *n, const sm_state *st, const lg_scene *s, const float lo[3],
                               const float hi[3], float vp[16])
{
    if (s->n_cameras == 0 || !s->cameras)
        return lg_error(n, "fit = frustum: the scene has no camera");
    uint32_t ci;
    if (st->camera < 0) {
        if (s->camera >= s->n_cameras)
            return lg_error(n,
                            "fit = frustum: the scene's active camera %u does not exist (it "
                            "has %u)",
                            s->camera, s->n_cameras);
        ci = s->camera;
    } else if ((uint64_t)st->camera >= s->n_cameras) {
        return lg_error(n,
                        "fit = frustum: camera %" PRId64 " does not exist: the scene has %u "
                        "camera%s (0..%u; -1 = the active one)",
                        st->camera, s->n_cameras, s->n_cameras == 1 ? "" : "s", s->n_cameras - 1);
    } else {
        ci = (uint32_t)st->camera;
    }
    const lg_camera *c = &s->cameras[ci];
    const char *cname = c->name ? c->name : "";
    if (!sm_finite3(c->position) || !sm_finite3(c->target) || !sm_finite3(c->up) ||
        !isfinite(c->yfov) || !isfinite(c->znear) || !isfinite(c->zfar) || !isfinite(c->aspect))
        return lg_error(n, "fit = frustum: camera %u '%s' has a value that is not finite", ci,
                        cname);
    if (!(c->yfov > 0.0f && c->yfov < 3.1f))
        return lg_error(n,
                        "fit = frustum: camera %u '%s': vertical field of view %g rad is "
                        "outside (0, 3.1)",
                        ci, cname, (double)c->yfov);
    if (c->znear < 0.0f || c->zfar < 0.0f || (c->zfar > 0.0f && c->zfar <= c->znear))
        return lg_error(n,
                        "fit = frustum: camera %u '%s': znear %g and zfar %g do not make a "
                        "depth range",
                        ci, cname, (double)c->znear, (double)c->zfar);
    lg_vec3 eye = lg_v3(c->position[0], c->position[1], c->position[2]);
    lg_vec3 target = lg_v3(c->target[0], c->target[1], c->target[2]);
    if (lg_v3_length(lg_v3_sub(target, eye)) < 1e-12f)
        return lg_error(n,
                        "fit = frustum: camera %u '%s': position and target are the same "
                        "point",
                        ci, cname);
    float view[16], proj[16];
    lg_m4_look_at(view, eye, target, lg_v3(c->up[0], c->up[1], c->up[2]));

    uint32_t w = 0, h = 0;
    lg_render_size(n, &w, &h);
    float aspect = st->aspect > 0.0f ? st->aspect : (w && h) ? (float)w / (float)h : 1.0f;
    float yfov = c->yfov;
    if (c->aspect > 0.0f && aspect < c->aspect)
        yfov = 2.0f * atanf(tanf(0.5f * yfov) * c->aspect / aspect);
    if (yfov > 3.1f)
        yfov = 3.1f;
    float zfar = c->zfar, znear = c->znear;
    if (zfar == 0.0f) {
        float far = -1.0f;
        for (int k = 0; k < 8; k++) {
            float d = -lg_m4_point(view, sm_corner(lo, hi, k)).z;
            if (d > far)
                far = d;
        }
        zfar = far > 0.0f ? far * 1.01f + 1e-6f : 0.0f;
        if (znear > 0.0f && zfar < 2.0f * znear)
            zfar = 2.0f * znear;
        if (zfar == 0.0f)
            zfar = 100.0f;
    }
    if (znear == 0.0f)
        znear = zfar * 1e-4f;
    lg_m4_perspective(proj, yfov, aspect, znear, zfar);
    lg_m4_mul(vp, proj, view);
    return 0;
}

/* A plane a.x + b.y + c.z + d >= 0 (inside), normal of unit length. */
typedef struct sm_plane {
    float a, b, c, d;
} sm_plane;

static float sm_plane_eval(sm_plane p, lg_vec3 v)
{
    return p.a * v.x + p.b * v.y + p.c * v.z + p.d;
}

static sm_plane sm_plane_norm(float a, float b, float c, float d)
{
    float l = sqrtf(a * a + b * b + c * c);
    sm_plane p = { a / l, b / l, c / l, d / l };
    return p;
}

typedef struct sm_convex {
    lg_vec3 v[8];  /* corners, index bits: x, y, z */
    sm_plane p[6]; /* faces, inside >= 0 */
} sm_convex;

static bool sm_inside(const sm_convex *c, lg_vec3 v, float tol)
{
    for (int i = 0; i < 6; i++)
        if (sm_plane_eval(c->p[i], v) < -tol)
            return false;
    return true;
}

/* Points of `a`'s edges where they cross `b`'s faces, kept if inside `b` (and `a`, which
 * an edge point is by construction). */
static uint32_t sm_edge_cuts(const sm_convex *a, const sm_convex *b, float tol, lg_vec3 *out)
{
    uint32_t k = 0;
    for (int i = 0; i < 8; i++)
        for (int bit = 1; bit < 8; bit <<= 1) {
            if (i & bit)
                continue;
            lg_vec3 p = a->v[i], q = a->v[i | bit];
            for (int f = 0; f < 6; f++) {
                float fp = sm_plane_eval(b->p[f], p), fq = sm_plane_eval(b->p[f], q);
                if ((fp < 0.0f) == (fq < 0.0f) || fp == fq)
                    continue;
                float t = fp / (fp - fq);
                lg_vec3 x = lg_v3_add(p, lg_v3_scale(lg_v3_sub(q, p), t));
                if (sm_inside(b, x, tol))
                    out[k++] = x;
            }
        }
    return k;
}

#define SM_MAX_CUT_POINTS (8 + 8 + 12 * 6 * 2)

/* The vertices of (camera frustum) ∩ (bounds), or a superset of them lying in both: the
 * intersection of two convex polyhedra is the convex hull of the corners of each inside
 * the other and of the points where the edges of each cross the faces of the other, so
 * the light-space box of these points is exactly the light-space box of the intersection.
 * Returns how many (0: the camera sees none of the bounds). */
static uint32_t sm_frustum_points(const float cam_vp[16], const float lo[3], const float hi[3],
                                  lg_vec3 *out)
{
    sm_convex fr, bx;
    float inv[16];
    if (lg_m4_invert(inv, cam_vp))
        return 0;
    for (int k = 0; k < 8; k++) {
        fr.v[k] = lg_m4_point(inv, lg_v3(k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f,
                                         k & 4 ? 1.0f : -1.0f));
        bx.v[k] = sm_corner(lo, hi, k);
    }
    /* frustum planes from the rows of view_proj: row3 +- row_i >= 0 (Gribb & Hartmann) */
    const float *m = cam_vp;
    for (int i = 0; i < 3; i++) {
        fr.p[2 * i] = sm_plane_norm(m[3] + m[i], m[7] + m[4 + i], m[11] + m[8 + i],
                                    m[15] + m[12 + i]);
        fr.p[2 * i + 1] = sm_plane_norm(m[3] - m[i], m[7] - m[4 + i], m[11] - m[8 + i],
                                        m[15] - m[12 + i]);
        float ax[3] = { 0, 0, 0 };
        ax[i] = 1.0f;
        bx.p[2 * i] = sm_plane_norm(ax[0], ax[1], ax[2], -lo[i]);
        bx.p[2 * i + 1] = sm_plane_norm(-ax[0], -ax[1], -ax[2], hi[i]);
    }
    lg_vec3 c = lg_v3_scale(lg_v3_add(bx.v[0], bx.v[7]), 0.5f);
    float size = lg_v3_length(lg_v3_sub(bx.v[7], bx.v[0])) + lg_v3_length(c);
    float tol = 1e-5f * (size > 0.0f ? size : 1.0f);
    uint32_t k = 0;
    for (int i = 0; i < 8; i++) {
        if (sm_inside(&bx, fr.v[i], tol))
            out[k++] = fr.v[i];
        if (sm_inside(&fr, bx.v[i], tol))
            out[k++] = bx.v[i];
    }
    k += sm_edge_cuts(&fr, &bx, tol, out + k);
    k += sm_edge_cuts(&bx, &fr, tol, out + k);
    return k;
}

/* ---- each light's matrices ------------------------------------------------------------------- */

static float sm_cross2(const float *x, const float *y, int o, int a, int b)
{
    return (x[a] - x[o]) * (y[b] - y[o]) - (y[a] - y[o]) * (x[b] - x[o]);
}

/* The rotation about the light's axis, in (-pi/4, pi/4], that gives the receivers' 2-D
 * points (x, y) the smallest bounding rectangle, or 0 when it saves less than 5 % (the
 * light's view then keeps its up vector). The smallest enclosing rectangle has a side on
 * an edge of the points' convex hull, so it is enough to try the hull's edges. */
static float sm_best_rotation(const float *x, const float *y, uint32_t n)
{
    int idx[SM_MAX_CUT_POINTS], hull[2 * SM_MAX_CUT_POINTS + 2];
    for (uint32_t i = 0; i < n; i++)
        idx[i] = (int)i;
    /* Andrew's monotone chain: sort by x, then y (insertion sort: n <= 160) */
    for (uint32_t i = 1; i < n; i++)
        for (uint32_t j = i; j > 0; j--) {
            int a = idx[j - 1], b = idx[j];
            if (x[a] < x[b] || (x[a] == x[b] && y[a] <= y[b]))
                break;
            idx[j - 1] = b, idx[j] = a;
        }
    int h = 0;
    for (uint32_t i = 0; i < n; i++) {
        while (h >= 2 && sm_cross2(x, y, hull[h - 2], hull[h - 1], idx[i]) <= 0.0f)
            h--;
        hull[h++] = idx[i];
    }
    for (int i = (int)n - 2, lower = h + 1; i >= 0; i--) {
        while (h >= lower && sm_cross2(x, y, hull[h - 2], hull[h - 1], idx[i]) <= 0.0f)
            h--;
        hull[h++] = idx[i];
    }
    float best = 0.0f, best_area = INFINITY, area0 = INFINITY;
    for (int e = -1; e < h - 1; e++) {
        float a = 0.0f; /* e = -1: the view as it is */
        if (e >= 0) {
            float dx = x[hull[e + 1]] - x[hull[e]], dy = y[hull[e + 1]] - y[hull[e]];
            if (dx == 0.0f && dy == 0.0f)
                continue;
            a = atan2f(dy, dx);
            const float q = LG_PIF / 4.0f; /* pi/4: rectangles repeat every quarter turn */
            while (a > q)
                a -= 2.0f * q;
            while (a <= -q)
                a += 2.0f * q;
        }
        float c = cosf(a), sn = sinf(a);
        float x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
        for (int k = 0; k < h; k++) {
            float u = c * x[hull[k]] + sn * y[hull[k]], v = -sn * x[hull[k]] + c * y[hull[k]];
            x0 = fminf(x0, u), x1 = fmaxf(x1, u);
            y0 = fminf(y0, v), y1 = fmaxf(y1, v);
        }
        float area = (x1 - x0) * (y1 - y0);
        if (e < 0)
            area0 = area;
        if (area < best_area)
            best_area = area, best = a;
    }
    return best_area < 0.95f * area0 ? best : 0.0f;
}

/* Fits light `l`'s view and orthographic projection (README.md, "Fit"): x and y to the
 * light-space box of the receivers (`pts`: the bounds' corners, or the points of the
 * camera frustum clipped by the bounds) plus a margin of normal_offset + 1 texels, depth to
 * the bounds' sphere (every caster; the same depth range for every light). */
static void sm_fit_light(const sm_state *st, lg_vec3 dir, const float lo[3], const float hi[3],
                         const lg_vec3 *pts, uint32_t n_pts, lg_shadow_light *l)
{
    lg_vec3 c = lg_v3_scale(lg_v3_add(sm_corner(lo, hi, 0), sm_corner(lo, hi, 7)), 0.5f);
    float r = 0.5f * lg_v3_length(lg_v3_sub(sm_corner(lo, hi, 7), sm_corner(lo, hi, 0)));
    if (!(r > 0.0f))
        r = 1.0f; /* bounds of one point */
    /* up: world +Y unless the light travels (nearly) vertically; then -Z, so that a light
     * from straight above shows the scene's back (-Z) at the top of its tile */
    lg_vec3 up = fabsf(dir.y) < 0.99f ? lg_v3(0, 1, 0) : lg_v3(0, 0, -1);
    lg_vec3 eye = lg_v3_sub(c, lg_v3_scale(dir, 2.0f * r));
    lg_m4_look_at(l->view, eye, c, up);

    /* turn the view about the light's axis so that the receivers' box is smallest */
    float px[SM_MAX_CUT_POINTS], py[SM_MAX_CUT_POINTS];
    for (uint32_t i = 0; i < n_pts; i++) {
        lg_vec3 v = lg_m4_point(l->view, pts[i]);
        px[i] = v.x, py[i] = v.y;
    }
    float a = sm_best_rotation(px, py, n_pts);
    if (a != 0.0f) {
        float rot[16];
        lg_m4_identity(rot);
        rot[0] = cosf(a), rot[4] = sinf(a);
        rot[1] = -sinf(a), rot[5] = cosf(a);
        lg_m4_mul(l->view, rot, l->view);
    }

    float x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (uint32_t i = 0; i < n_pts; i++) {
        lg_vec3 v = lg_m4_point(l->view, pts[i]);
        x0 = fminf(x0, v.x), x1 = fmaxf(x1, v.x);
        y0 = fminf(y0, v.y), y1 = fmaxf(y1, v.y);
    }
    /* a flat scene seen edge-on has no extent along one axis: keep a sliver */
    float min_ext = 1e-4f * r;
    float cx = 0.5f * (x0 + x1), cy = 0.5f * (y0 + y1);
    float hw = fmaxf(0.5f * (x1 - x0), min_ext), hh = fmaxf(0.5f * (y1 - y0), min_ext);
    /* a margin of m = normal_offset + 1 texels on each side (at most a quarter of the
     * tile), so that a receiver moved along its normal, or rounded, stays inside. The texel
     * is the larger side's, and grows with the margin: with W the larger half-extent,
     * texel = 2 (W + m texel) / res, so texel = 2 W / (res - 2 m). */
    float res = (float)st->resolution;
    float m = fminf(st->normal_offset + 1.0f + (float)st->pcf_radius, 0.25f * res);
    float texel = 2.0f * fmaxf(hw, hh) / (res - 2.0f * m);
    hw += m * texel, hh += m * texel;
    /* depth: the bounds' sphere, 0.1 % wider; every caster lies inside it */
    float znear = 2.0f * r - 1.001f * r, zfar = 2.0f * r + 1.001f * r;

    lg_m4_ortho(l->proj, cx - hw, cx + hw, cy - hh, cy + hh, znear, zfar);
    /* texel row 0 is the atlas's top row: flip Y, so that the tile shows the light's view
     * upright and p_tex.y = 0 (clip y = -1) is the tile's top row */
    for (int col = 0; col < 4; col++)
        l->proj[col * 4 + 1] = -l->proj[col * 4 + 1];
    lg_m4_mul(l->view_proj, l->proj, l->view);
    l->texel_world = texel;
    l->depth_range = zfar - znear;
}

/* Spot lights whose outer cone is wider than this get a cube, as point lights do: one
 * perspective map of 2 x 60 degrees already spends a quarter of its texels' area on the
 * edge (1 / cos^2 = 4), and 2 x 90 degrees cannot be one map at all. */
#define SM_SPOT_MAX_CONE (LG_PIF / 3.0f)

/* How many maps (records) light L gets: 1 (directional, spot) or 6 (point, wide spot). */
static uint32_t sm_records_of(const lg_light *L)
{
    if (L->type == LG_LIGHT_DIRECTIONAL)
        return 1;
    if (L->type == LG_LIGHT_SPOT && L->outer_cone <= SM_SPOT_MAX_CONE)
        return 1;
    return 6;
}

/* Fits one perspective record (README.md, "Spot and point lights"): from the light's
 * position q along `axis` with `up`, a square frustum of half-angle atan(tan_half) widened
 * by a margin of normal_offset + 1 + pcf_radius texels (so that a cube face's taps past its
 * 90 degrees still read real depth), near and far fitted to the bounds (and the range). */
static void sm_fit_perspective(const sm_state *st, lg_vec3 q, lg_vec3 axis, lg_vec3 up,
                               float tan_half, float range, const float lo[3], const float hi[3],
                               lg_shadow_light *l)
{
    lg_m4_look_at(l->view, q, lg_v3_add(q, axis), up);
    /* far: the farthest corner of the bounds (a radial distance bounds the view depth);
     * near: the distance from q to the box (nothing is nearer), at least far / 1000 so
     * that float depth keeps its precision (a light inside the bounds) */
    float far = 0.0f, dbox2 = 0.0f;
    for (int k = 0; k < 8; k++)
        far = fmaxf(far, lg_v3_length(lg_v3_sub(sm_corner(lo, hi, k), q)));
    const float qv[3] = { q.x, q.y, q.z };
    for (int k = 0; k < 3; k++) {
        float d = fmaxf(fmaxf(lo[k] - qv[k], qv[k] - hi[k]), 0.0f);
        dbox2 += d * d;
    }
    if (range > 0.0f && range < far)
        far = range; /* no light beyond the range: nothing there needs a shadow */
    far = far * 1.01f + 1e-6f;
    float znear = fmaxf(0.99f * sqrtf(dbox2), 1e-3f * far);
    if (!(znear < far))
        far = 2.0f * znear; /* the bounds lie beyond the range: an empty map */
    float res = (float)st->resolution;
    float m = fminf(st->normal_offset + 1.0f + (float)st->pcf_radius, 0.25f * res);
    float t = tan_half * res / (res - 2.0f * m);
    lg_m4_perspective(l->proj, 2.0f * atanf(t), 1.0f, znear, far);
    for (int col = 0; col < 4; col++) /* the image row rule, as for directional maps */
        l->proj[col * 4 + 1] = -l->proj[col * 4 + 1];
    lg_m4_mul(l->view_proj, l->proj, l->view);
    l->texel_world = 2.0f * t / res; /* at unit view depth */
    l->depth_range = far - znear;
    l->znear = znear;
    l->projection = LG_SHADOW_PERSPECTIVE;
}

/* ---- prepare --------------------------------------------------------------------------------- */

/* Fits every light's maps (st->lights, nl records, allocated) to the scene: a directional
 * light's to its bounds, or what the camera sees of them (fit = frustum), a spot or point
 * light's to the bounds from its position; assigns the atlas tiles, one per record. */
static int sm_fit(lg_node *n, sm_state *st, const lg_scene *s, uint32_t nl)
{
    float lo[3], hi[3];
    int rc = sm_bounds(n, s, lo, hi);
    if (rc)
        return rc;
    lg_vec3 pts[SM_MAX_CUT_POINTS];
    uint32_t n_pts = 0;
    if (st->fit == SM_FIT_FRUSTUM && st->n_dir) {
        float cam_vp[16];
        if ((rc = sm_camera_view_proj(n, st, s, lo, hi, cam_vp)))
            return rc;
        n_pts = sm_frustum_points(cam_vp, lo, hi, pts);
        if (n_pts == 0)
            lg_log(n, LG_LOG_INFO,
                   "fit = frustum: the camera sees none of the scene's bounds; "
                   "fitting to the bounds");
    }
    if (n_pts == 0) {
        for (int k = 0; k < 8; k++)
            pts[k] = sm_corner(lo, hi, k);
        n_pts = 8;
    }
    /* a cube's faces +x, -x, +y, -y, +z, -z (lightgraph/shadowmap.h), with a cube map's
     * up vectors */
    static const float cube_axis[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                           { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
    static const float cube_up[6][3] = { { 0, -1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
                                         { 0, 0, -1 }, { 0, -1, 0 }, { 0, -1, 0 } };
    uint32_t k = 0;
    for (uint32_t i = 0; i < s->n_lights && k < nl; i++) {
        const lg_light *L = &s->lights[i];
        lg_vec3 d = lg_v3_normalize_or(lg_v3(L->direction[0], L->direction[1], L->direction[2]),
                                       lg_v3(0, -1, 0));
        uint32_t nr = sm_records_of(L);
        for (uint32_t f = 0; f < nr && k < nl; f++, k++) {
            lg_shadow_light *l = &st->lights[k];
            memset(l, 0, sizeof *l);
            l->light = i;
            l->face = f;
            if (L->type == LG_LIGHT_DIRECTIONAL) {
                sm_fit_light(st, d, lo, hi, pts, n_pts, l);
            } else {
                lg_vec3 q = lg_v3(L->position[0], L->position[1], L->position[2]);
                if (nr == 1) /* a spot light's one map along its axis */
                    sm_fit_perspective(st, q, d,
                                       fabsf(d.y) < 0.99f ? lg_v3(0, 1, 0) : lg_v3(0, 0, -1),
                                       tanf(fmaxf(L->outer_cone, 1e-3f)), L->range, lo, hi, l);
                else
                    sm_fit_perspective(st, q,
                                       lg_v3(cube_axis[f][0], cube_axis[f][1], cube_axis[f][2]),
                                       lg_v3(cube_up[f][0], cube_up[f][1], cube_up[f][2]), 1.0f,
                                       L->range, lo, hi, l);
            }
            l->tile_x = (k % st->cols) * st->resolution;
            l->tile_y = (k / st->cols) * st->resolution;
        }
    }
    return 0;
}

static int sm_prepare(lg_node *n)
{
    sm_state *st = n->user;
    lg_assert_input(n, 0);
    const lg_resource *in = lg_input(n, 0);
    const lg_scene *s = lg_scene_get(n, in);
    if (!s)
        return LG_ERR_INVALID;

    /* every light, in the scene's order: one record per directional or spot light, six per
     * point light (and per spot light wider than SM_SPOT_MAX_CONE); a light of another type
     * stops the render rather than going unshadowed */
    uint32_t nl = 0, n_dir = 0, n_spot = 0, n_cube = 0;
    for (uint32_t i = 0; i < s->n_lights; i++) {
        const lg_light *L = &s->lights[i];
        const char *name = L->name ? L->name : "";
        if (L->type != LG_LIGHT_DIRECTIONAL && L->type != LG_LIGHT_POINT &&
            L->type != LG_LIGHT_SPOT)
            return lg_error(n, "light %u '%s' has type %d, which has no shadow map", i, name,
                            (int)L->type);
        if (L->type != LG_LIGHT_POINT) {
            lg_vec3 d = lg_v3(L->direction[0], L->direction[1], L->direction[2]);
            lg_vec3 u = lg_v3_normalize_or(d, lg_v3(0, 0, 0));
            if (u.x == 0.0f && u.y == 0.0f && u.z == 0.0f)
                return lg_error(n,
                                "light %u '%s': direction [%g, %g, %g] is not a direction (zero "
                                "or not finite)",
                                i, name, (double)d.x, (double)d.y, (double)d.z);
        }
        if (L->type != LG_LIGHT_DIRECTIONAL) {
            if (!sm_finite3(L->position) || !isfinite(L->range) || L->range < 0.0f)
                return lg_error(n,
                                "light %u '%s': position [%g, %g, %g] or range %g is not "
                                "finite (or the range is negative)",
                                i, name, (double)L->position[0], (double)L->position[1],
                                (double)L->position[2], (double)L->range);
            if (L->type == LG_LIGHT_SPOT && !(L->outer_cone >= 0.0f && L->outer_cone <= LG_PIF))
                return lg_error(n, "spot light %u '%s': outer cone %g rad is outside [0, pi]", i,
                                name, (double)L->outer_cone);
        }
        uint32_t nr = sm_records_of(L);
        nl += nr;
        if (L->type == LG_LIGHT_DIRECTIONAL)
            n_dir++;
        else if (nr == 1)
            n_spot++;
        else
            n_cube++;
    }
    st->n_dir = n_dir, st->n_spot = n_spot, st->n_cube = n_cube;

    /* the atlas: ceil(sqrt(L)) columns, as many rows as needed */
    uint32_t res = st->resolution;
    uint32_t tiles = nl ? nl : 1;
    uint32_t cols = 1;
    while (cols * cols < tiles)
        cols++;
    uint32_t rows = (tiles + cols - 1) / cols;
    uint64_t aw = (uint64_t)cols * res, ah = (uint64_t)rows * res;
    if (aw > 65536 || ah > 65536 || aw * ah > (1ull << 28))
        return lg_error(n,
                        "%u map%s (%u directional, %u spot, %u cube%s of 6) at resolution %u "
                        "need an atlas of %" PRIu64 "x%" PRIu64 " texels (%.1f GiB of depth), "
                        "more than an image may hold (2^28 texels); lower 'resolution'",
                        nl, nl == 1 ? "" : "s", n_dir, n_spot, n_cube, n_cube == 1 ? "" : "s", res,
                        aw, ah, (double)(aw * ah * 4) / (1024.0 * 1024.0 * 1024.0));
    st->cols = cols;
    st->rows = rows;

    free(st->lights);
    st->sm = NULL;
    st->lights = calloc(tiles, sizeof(lg_shadow_light));
    if (!st->lights)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u shadow maps)", nl);
    int rc = sm_fit(n, st, s, nl);
    if (rc)
        return rc;
    /* fitted to the camera's frustum, the maps follow the camera: execute() fits them again
     * and the viewer runs it again when its camera moves */
    lg_set_view_independent(n, st->fit != SM_FIT_FRUSTUM);

    if ((rc = lg_shadowmap_declare(n, 0, (uint32_t)aw, (uint32_t)ah, nl)))
        return rc;
    st->view = (lg_shadowmap){
        .resolution = res,
        .n_lights = nl,
        .lights = st->lights,
        .atlas_width = (uint32_t)aw,
        .atlas_height = (uint32_t)ah,
        .bias_constant = st->bias_constant,
        .bias_slope = st->bias_slope,
        .normal_offset = st->normal_offset,
        .pcf_radius = st->pcf_radius,
        .pcss_light_size = st->pcss_light_size,
        .point_mode = LG_SHADOW_POINT_CUBE,
    };
    st->sm = &st->view;
    return lg_set_device(n, LG_DEVICE_GL);
}

/* ---- execute --------------------------------------------------------------------------------- */

/* The atlas the pass draws into: output 1's depth plane (the one place that knows where the
 * atlas lives; prepare publishes it in one place too). */
/* The atlas part of the output, mapped on GL for writing: depth only, no colour plane. */
static int sm_atlas_target(lg_node *n, const lg_shadowmap *sm, lg_gl_target *t)
{
    memset(t, 0, sizeof *t);
    uint32_t color = 0;
    int rc = lg_map_gl(n, lg_part(n, lg_output(n, 0), "atlas"), LG_WRITE, &color, &t->depth);
    if (rc)
        return rc;
    if (!t->depth)
        return lg_error_code(n, LG_ERR_DEVICE, "the atlas has no GL depth texture");
    t->width = sm->atlas_width;
    t->height = sm->atlas_height;
    return 0;
}

static int sm_make_pass(lg_node *n, sm_state *st)
{
    static const lg_gl_shader_src src[2] = {
        { GL_VERTEX_SHADER, lg_src_shadowmap_vert_file, lg_src_shadowmap_vert },
        { GL_FRAGMENT_SHADER, lg_src_shadowmap_frag_file, lg_src_shadowmap_frag },
    };
    /* casters are inside [near, far] by the fit; depth clamp keeps a rounding error from
     * clipping one away. No polygon offset: the stored depth is unbiased (README.md). A
     * double-sided material's winding says nothing about which side faces out: both sides
     * cast shadows whatever `cull` says (the scene draw leaves them unculled). */
    lg_gl_pass_desc d = { .name = "shadowmap",
                          .stages = src,
                          .n_stages = 2,
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true,
                          .depth_clamp = true,
                          .cull = st->cull == SM_CULL_BACK    ? LG_GL_CULL_BACK
                                  : st->cull == SM_CULL_FRONT ? LG_GL_CULL_FRONT
                                                              : LG_GL_CULL_NONE,
                          .scene = LG_GL_SCENE_POSITIONS | LG_GL_SCENE_TEXCOORDS };
    int rc = lg_gl_pass_create(n, &d, &st->pass);
    if (rc)
        return rc;
    st->u_view_proj = lg_gl_pass_uniform(st->pass, "u_view_proj");
    lg_gl_pass_material_binds(st->pass, &st->mat);
    return 0;
}

/* The mesh's material, for its alpha mask: the depth pass discards where alpha is below
 * the cutoff. The file's filters without anisotropy (a threshold needs no sharper texels). */
static int sm_on_mesh(lg_node *n, void *user, uint32_t mesh, GLuint *normals)
{
    (void)n, (void)normals;
    sm_state *st = user;
    const lg_scene *s = lg_gl_pass_scene(st->pass)->scene;
    lg_gl_material_opts o = { .filter = LG_GL_MATERIAL_FILTER_FILE, .max_anisotropy = 1.0f };
    return lg_gl_pass_bind_material(st->pass, &st->mat, st->scene_res, s->meshes[mesh].material,
                                    &o);
}

/* The world bounds of the scene's instances posed at `time` (lg_scene_pose): the corners of
 * each drawn mesh's object-space bounds through its posed model matrix. An animation moves
 * the casters, and the fit must still hold every one of them. */
static int sm_posed_bounds(lg_node *n, const lg_scene *s, double time, float lo[3], float hi[3])
{
    lg_instance *posed = malloc((s->n_instances ? s->n_instances : 1) * sizeof *posed);
    if (!posed)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u posed instances)", s->n_instances);
    int rc = lg_scene_pose(n, s, time, posed);
    bool any = false;
    for (uint32_t i = 0; !rc && i < s->n_instances; i++) {
        if (posed[i].mesh >= s->n_meshes || s->meshes[posed[i].mesh].n_indices == 0)
            continue;
        const lg_mesh *me = &s->meshes[posed[i].mesh];
        const float *m = posed[i].model;
        for (int c = 0; c < 8; c++) {
            float p[3] = { (c & 1) ? me->bounds_max[0] : me->bounds_min[0],
                           (c & 2) ? me->bounds_max[1] : me->bounds_min[1],
                           (c & 4) ? me->bounds_max[2] : me->bounds_min[2] };
            for (int k = 0; k < 3; k++) {
                float w = m[k] * p[0] + m[4 + k] * p[1] + m[8 + k] * p[2] + m[12 + k];
                if (!any || w < lo[k])
                    lo[k] = w;
                if (!any || w > hi[k])
                    hi[k] = w;
            }
            any = true;
        }
    }
    free(posed);
    if (!rc && !any)
        for (int k = 0; k < 3; k++)
            lo[k] = s->bounds_min[k], hi[k] = s->bounds_max[k];
    return rc;
}

static int sm_execute(lg_node *n, const lg_frame *frame)
{
    sm_state *st = n->user;
    const lg_shadowmap *sm = st->sm;
    const lg_resource *scene_res = lg_input(n, 0);
    const lg_scene *s = lg_scene_get(n, scene_res);
    if (!s || !sm)
        return LG_ERR_INVALID;
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    /* the camera may have moved since prepare (lightgraph view); an animated scene's
     * lights, camera and instances move with the frame's time: fit to the posed scene */
    int rc0 = 0;
    if (lg_scene_is_animated(s)) {
        lg_scene at;
        if ((rc0 = lg_scene_at(n, s, frame->time, &at)))
            return rc0;
        rc0 = sm_posed_bounds(n, s, frame->time, at.bounds_min, at.bounds_max);
        if (!rc0)
            rc0 = sm_fit(n, st, &at, sm->n_lights);
        lg_scene_at_free(s, &at);
    } else if (st->fit == SM_FIT_FRUSTUM) {
        rc0 = sm_fit(n, st, s, sm->n_lights);
    }
    if (rc0)
        return rc0;

    GLint max_tex = 0, max_vp[2] = { 0, 0 };
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
    gl->GetIntegerv(GL_MAX_VIEWPORT_DIMS, max_vp);
    if ((GLint)sm->atlas_width > max_tex || (GLint)sm->atlas_height > max_tex)
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "the atlas (%ux%u: %u maps at resolution %u) is "
                             "larger than this GL device's textures (GL_MAX_TEXTURE_SIZE %d); "
                             "lower 'resolution'",
                             sm->atlas_width, sm->atlas_height, sm->n_lights, sm->resolution,
                             max_tex);
    if ((GLint)sm->resolution > max_vp[0] || (GLint)sm->resolution > max_vp[1])
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "resolution %u is larger than this GL device's viewports "
                             "(GL_MAX_VIEWPORT_DIMS %dx%d)",
                             sm->resolution, max_vp[0], max_vp[1]);

    /* the lights and info parts, on the CPU: consumers get copies where they read */
    lg_shadowmap_info info = {
        .resolution = sm->resolution,
        .n_lights = sm->n_lights,
        .atlas_width = sm->atlas_width,
        .atlas_height = sm->atlas_height,
        .bias_constant = sm->bias_constant,
        .bias_slope = sm->bias_slope,
        .normal_offset = sm->normal_offset,
        .pcf_radius = sm->pcf_radius,
        .pcss_light_size = sm->pcss_light_size,
        .point_mode = sm->point_mode,
    };
    int rc;
    lg_gl_target atlas;
    if ((rc = lg_shadowmap_publish(n, 0, &info, sm->lights)) ||
        (!st->pass && (rc = sm_make_pass(n, st))) || (rc = sm_atlas_target(n, sm, &atlas)) ||
        (rc = lg_gl_pass_begin(st->pass, &atlas)))
        return rc;
    lg_gl_pass_clear_depth(st->pass, 1.0f);
    st->scene_res = scene_res;
    lg_gl_scene_draw draw = { .on_mesh = sm_on_mesh, .user = st };
    lg_gl_pass_set_time(st->pass, frame->time); /* an animated scene's pose (ABI 3.1) */
    for (uint32_t li = 0; li < sm->n_lights && !rc; li++) {
        const lg_shadow_light *l = &sm->lights[li];
        lg_gl_pass_viewport(st->pass, (int32_t)l->tile_x, (int32_t)l->tile_y, sm->resolution,
                            sm->resolution);
        lg_gl_set_mat4(st->pass, st->u_view_proj, l->view_proj);
        rc = lg_gl_pass_draw_scene(st->pass, scene_res, &draw);
    }
    if ((rc = lg_gl_pass_end(st->pass, rc)))
        return rc;
    const lg_scene_gl *sgl = lg_gl_pass_scene(st->pass);
    /* the line starts as it did before ABI 3.2 ("1 directional light, ..."): tools count it */
    lg_log(n, LG_LOG_INFO,
           "%u directional light%s, %u spot, %u point (%u map%s), atlas %ux%u (%ux%u tiles of "
           "%u), pcf radius %u, pcss %g, fit %s, cull %s; %u instances, %" PRIu64
           " triangles per map",
           st->n_dir, st->n_dir == 1 ? "" : "s", st->n_spot, st->n_cube, sm->n_lights,
           sm->n_lights == 1 ? "" : "s", sm->atlas_width, sm->atlas_height, st->cols, st->rows,
           sm->resolution, sm->pcf_radius, (double)sm->pcss_light_size,
           st->fit == SM_FIT_FRUSTUM ? "frustum" : "bounds",
           st->cull == SM_CULL_FRONT  ? "front"
           : st->cull == SM_CULL_BACK ? "back"
                                      : "none",
           sgl ? sgl->count : 0, sgl ? sgl->triangles : 0);
    for (uint32_t i = 0; i < sm->n_lights; i++) {
        const lg_shadow_light *l = &sm->lights[i];
        lg_log(n, LG_LOG_DEBUG,
               "light %u '%s' %s %u: tile at (%u, %u), texel %.6g m%s, depth range %.6g m",
               l->light, s->lights[l->light].name ? s->lights[l->light].name : "",
               l->projection == LG_SHADOW_PERSPECTIVE ? "perspective face" : "orthographic face",
               l->face, l->tile_x, l->tile_y, (double)l->texel_world,
               l->projection == LG_SHADOW_PERSPECTIVE ? " at 1 m" : "", (double)l->depth_range);
    }
    return 0;
}

static void sm_destroy(lg_node *n)
{
    sm_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->pass);
    free(st->lights);
    free(st);
    n->user = NULL;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const char *const sm_fits[] = { "bounds", "frustum", NULL };
static const char *const sm_culls[] = { "front", "back", "none", NULL };

static const lg_param_desc sm_params[] = {
    { .key = "resolution",
      .type = LG_PARAM_INT,
      .def.i = 1024,
      .min = 16,
      .max = 8192,
      .doc = "side of each light's square depth map, texels (the thesis: 1024)" },
    { .key = "fit",
      .type = LG_PARAM_ENUM,
      .def.e = SM_FIT_BOUNDS,
      .enum_values = sm_fits,
      .doc = "bounds: each map covers the scene's bounds; frustum: what the camera sees of "
             "them (the camera's frustum clipped by the bounds)" },
    { .key = "camera",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "fit = frustum: index of the scene's camera; -1 = the scene's active camera" },
    { .key = "aspect",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1000,
      .doc = "fit = frustum: width / height of the consumer's image; 0 = the render size's" },
    { .key = "cull",
      .type = LG_PARAM_ENUM,
      .def.e = SM_CULL_FRONT,
      .enum_values = sm_culls,
      .doc = "faces left out of the maps: front (against acne), back or none; double-sided "
             "materials always draw both sides" },
    { .key = "bias_constant",
      .type = LG_PARAM_FLOAT,
      .def.f = SM_DEF_BIAS_CONSTANT,
      .min = 0,
      .max = 1,
      .doc = "depth units ([0, 1] over each light's depth range), added to the "
             "stored depth in the test; applied by consumers" },
    { .key = "bias_slope",
      .type = LG_PARAM_FLOAT,
      .def.f = SM_DEF_BIAS_SLOPE,
      .min = 0,
      .max = 1,
      .doc = "depth units per unit of tan(angle between N and L), with |N.L| "
             "clamped to >= 0.1 (tan <= 9.95); applied by consumers" },
    { .key = "normal_offset",
      .type = LG_PARAM_FLOAT,
      .def.f = SM_DEF_NORMAL_OFFSET,
      .min = 0,
      .max = 64,
      .doc = "texels: consumers move the tested point along its normal by this "
             "many of the light's texel_world (perspective maps: times the point's distance "
             "from the light)" },
    { .key = "pcf_radius",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 8,
      .doc = "percentage-closer filtering: consumers average the depth test over (2 r + 1)^2 "
             "texels; 0 = one texel (hard edges)" },
    { .key = "pcss_light_size",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 100,
      .doc = "> 0: percentage-closer soft shadows, the light's diameter (metres; directional: "
             "radians); the PCF radius then follows the blocker search; 0 = off" },
};
static const lg_port_desc sm_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene whose lights (directional, spot, point) cast shadows" },
};
static const lg_port_desc sm_outputs[] = {
    { .name = "shadows",
      .kind = LG_KIND_SHADOWMAP,
      .doc = "the depth atlas (part atlas: NODE.atlas is the image) and the lights' matrices, "
             "tiles and bias (lg_shadowmap_get; no parts when gated)" },
};

static const lg_node_type sm_types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "shadowmap",
    .doc = "Depth maps of every light (orthographic, spot perspective, point cube), in tiles of "
           "a depth atlas (GL)",
    LG_PARAMS(sm_params),
    LG_INPUTS(sm_inputs),
    LG_OUTPUTS(sm_outputs),
    .needs = LG_NEEDS_LIGHT,
    /* the light matrices are fitted in prepare(); execute() renders them whatever the
     * camera (fit = frustum follows the camera of the plan, not the viewer's moves) */
    .flags = LG_NODE_VIEW_INDEPENDENT,
    .neutral = LG_NEUTRAL_ZERO,
    .create = sm_create,
    .prepare = sm_prepare,
    .execute = sm_execute,
    .destroy = sm_destroy,
} };

LG_PLUGIN_DEFINE("shadowmap", "2.1.0",
                 "Shadow maps of every light (orthographic, perspective, cube; tiled depth atlas) "
                 "on GL",
                 sm_types)
