/*
 * The prt_bake plugin (README.md beside this file; TECHNIQUES.md §5, seed 0 eq. 4.8, 4.9,
 * §4.2.2.3; Sloan, Kautz and Snyder 2002):
 *
 *   prt_bake       scene -> out (LG_KIND_TRANSFER): per-vertex transfer vectors, the albedo
 *                  folded in, unshadowed, shadowed (Embree or brute-force visibility) or
 *                  interreflected, over one global set of sphere directions
 *   prt_reference  scene, probe -> vertices (rgba32f per-vertex image): the exit radiance
 *                  of every vertex by exact quadrature over the probe's texels, with the
 *                  same visibility: the oracle of the accuracy study
 *
 * Both run on the CPU (the host's pool), are static, and keep their result in the host's
 * cache under a header of their own that is checked before anything is trusted.
 */
#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <embree3/rtcore.h>

#include "lg_embree.h"
#include "pb_cache.h"

#include "lightgraph/image.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"
#include "lightgraph/sampling.h"
#include "lightgraph/scene.h"
#include "lightgraph/sh.h"
#include "lightgraph/shcoeffs.h"
#include "lightgraph/transfer.h"
#include "lightgraph/vecmath.h"

enum { PB_UNSHADOWED = 0, PB_SHADOWED, PB_INTERREFLECTED };
enum { PB_EMBREE = 0, PB_BRUTE };

/* Above this many ray-triangle tests the brute-force option warns (about a minute here). */
#define PB_BRUTE_WARN 2e10

/* ---- the scene in world space ---------------------------------------------------------------- */

/* Every instance's triangles in world space (float, as Embree takes them), every vertex's
 * world position and normal (the frame of its mesh's first instance), and the albedo of
 * each vertex. Owned by the node state; freed by pb_world_free. */
typedef struct pb_world {
    uint32_t n_vertices;   /* sum of the meshes' vertex counts */
    uint32_t *mesh_offset; /* n_meshes + 1: mesh m's first vertex */
    double *pos, *nrm;     /* 3 per vertex: world position and unit normal */
    double *in;            /* 3 per vertex: unit tangent toward its own mesh's
                            * triangles at a boundary, else 0 (pb_offset) */
    float *albedo;         /* 3 per vertex */
    /* per instance (Embree geometry id = instance index) */
    uint32_t n_inst;
    const uint32_t *inst_mesh; /* scene->instances[i].mesh, copied */
    uint32_t *inst_mesh_store;
    float **inst_pos;       /* world positions of instance i's mesh */
    float **inst_nrm;       /* world normals of instance i's mesh (unit) */
    uint8_t *inst_masked;   /* per instance: its material has an alpha mask
                             * (lg_embree_mesh_masked): brute force asks the mask */
    uint8_t *mesh_textured; /* per mesh: its material has a base colour texture and the
                             * mesh the coordinates it reads (pb_hit_colour) */
    uint64_t n_triangles;   /* over every instance */
    double extent, max_abs; /* world bounds' largest side; largest |coordinate| */
    const lg_scene *s;
} pb_world;

static void pb_world_free(pb_world *w)
{
    if (w->inst_pos)
        for (uint32_t i = 0; i < w->n_inst; i++)
            free(w->inst_pos[i]);
    if (w->inst_nrm)
        for (uint32_t i = 0; i < w->n_inst; i++)
            free(w->inst_nrm[i]);
    free(w->inst_pos);
    free(w->inst_nrm);
    free(w->inst_mesh_store);
    free(w->inst_masked);
    free(w->mesh_textured);
    free(w->mesh_offset);
    free(w->pos);
    free(w->nrm);
    free(w->in);
    free(w->albedo);
    memset(w, 0, sizeof *w);
}

static void pb_xform_point(const float m[16], const float p[3], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = (double)m[r] * p[0] + (double)m[4 + r] * p[1] + (double)m[8 + r] * p[2] +
                 (double)m[12 + r];
}

static void pb_xform_normal(const float m[9], const float nv[3], double out[3])
{
    double l = 0;
    for (int r = 0; r < 3; r++) {
        out[r] = (double)m[r] * nv[0] + (double)m[3 + r] * nv[1] + (double)m[6 + r] * nv[2];
        l += out[r] * out[r];
    }
    l = sqrt(l);
    for (int r = 0; r < 3; r++)
        out[r] = l > 0 ? out[r] / l : 0.0;
}

/* For every vertex, the direction from it into its own mesh's surface (pb_offset): the sum
 * over its triangles of (centroid - vertex), its normal component removed, normalised when
 * it is not negligible against the sum of the lengths (a vertex inside a symmetric fan
 * gets 0; one on a mesh's boundary points away from the boundary). */
static void pb_world_inward(pb_world *w)
{
    const lg_scene *s = w->s;
    double *len = calloc(w->n_vertices, sizeof(double));
    if (!len)
        return; /* no tangent offset: the normal offset alone still applies */
    for (uint32_t m = 0; m < s->n_meshes; m++) {
        const lg_mesh *me = &s->meshes[m];
        uint32_t off = w->mesh_offset[m];
        for (uint32_t t = 0; t + 2 < me->n_indices; t += 3) {
            const uint32_t *ix = me->indices + t;
            if (ix[0] >= me->n_vertices || ix[1] >= me->n_vertices || ix[2] >= me->n_vertices)
                continue; /* reported when the Embree scene is built */
            double c[3];
            for (int k = 0; k < 3; k++)
                c[k] = (w->pos[3 * (size_t)(off + ix[0]) + k] +
                        w->pos[3 * (size_t)(off + ix[1]) + k] +
                        w->pos[3 * (size_t)(off + ix[2]) + k]) /
                       3.0;
            for (int q = 0; q < 3; q++) {
                size_t v = off + ix[q];
                double d[3], l = 0;
                for (int k = 0; k < 3; k++) {
                    d[k] = c[k] - w->pos[3 * v + k];
                    l += d[k] * d[k];
                    w->in[3 * v + k] += d[k];
                }
                len[v] += sqrt(l);
            }
        }
    }
    for (uint32_t v = 0; v < w->n_vertices; v++) {
        double *d = w->in + 3 * (size_t)v;
        const double *N = w->nrm + 3 * (size_t)v;
        double dn = d[0] * N[0] + d[1] * N[1] + d[2] * N[2], l = 0;
        for (int k = 0; k < 3; k++) {
            d[k] -= dn * N[k];
            l += d[k] * d[k];
        }
        l = sqrt(l);
        for (int k = 0; k < 3; k++)
            d[k] = l > 1e-3 * len[v] && l > 0 ? d[k] / l : 0.0;
    }
    free(len);
}

/* The albedo of mesh m: albedo_param ([r, g, b]) or NULL for its material's base colour
 * (1 without a material). An albedo outside [0, 1] is an error naming mesh and material. */
static int pb_mesh_albedo(lg_node *n, const lg_scene *s, uint32_t m, const double *albedo_param,
                          float rho[3])
{
    const lg_mesh *me = &s->meshes[m];
    const lg_material *mat = me->material < s->n_materials ? &s->materials[me->material] : NULL;
    for (int c = 0; c < 3; c++) {
        double a = albedo_param ? albedo_param[c] : mat ? mat->base_color[c] : 1.0;
        if (!(a >= 0.0 && a <= 1.0)) {
            if (albedo_param)
                return lg_error(n,
                                "albedo [%g, %g, %g]: every channel must be in [0, 1] "
                                "(an albedo above 1 makes energy)",
                                albedo_param[0], albedo_param[1], albedo_param[2]);
            return lg_error(n,
                            "mesh %u '%s': material %u '%s' has base colour [%g, %g, "
                            "%g], outside [0, 1]; give the node an albedo = [r, g, b]",
                            m, me->name ? me->name : "", me->material, mat->name ? mat->name : "",
                            (double)mat->base_color[0], (double)mat->base_color[1],
                            (double)mat->base_color[2]);
        }
        rho[c] = (float)a;
    }
    return 0;
}

/* albedo_param: [r, g, b] or NULL for the materials' base colours. Reports bad input
 * (non-finite positions or normals, an albedo outside [0, 1]) naming mesh and vertex. */
static int pb_world_make(lg_node *n, const lg_scene *s, const double *albedo_param, pb_world *w)
{
    memset(w, 0, sizeof *w);
    w->s = s;
    uint64_t nv = 0;
    for (uint32_t m = 0; m < s->n_meshes; m++)
        nv += s->meshes[m].n_vertices;
    if (nv == 0)
        return lg_error(n, "input 'scene' (%s) has no vertices: nothing to bake",
                        s->source ? s->source : "?");
    if (nv > UINT32_MAX / 2)
        return lg_error(n, "input 'scene' has %llu vertices: more than this node handles",
                        (unsigned long long)nv);
    w->n_vertices = (uint32_t)nv;
    w->mesh_offset = calloc((size_t)s->n_meshes + 1, sizeof *w->mesh_offset);
    w->pos = malloc(nv * 3 * sizeof(double));
    w->nrm = malloc(nv * 3 * sizeof(double));
    w->albedo = malloc(nv * 3 * sizeof(float));
    w->in = calloc(nv * 3, sizeof(double));
    w->n_inst = s->n_instances;
    w->inst_mesh_store = calloc(w->n_inst ? w->n_inst : 1, sizeof(uint32_t));
    w->inst_pos = calloc(w->n_inst ? w->n_inst : 1, sizeof(float *));
    w->inst_nrm = calloc(w->n_inst ? w->n_inst : 1, sizeof(float *));
    w->inst_masked = calloc(w->n_inst ? w->n_inst : 1, 1);
    w->mesh_textured = calloc(s->n_meshes ? s->n_meshes : 1, 1);
    if (!w->mesh_offset || !w->pos || !w->nrm || !w->albedo || !w->in || !w->inst_mesh_store ||
        !w->inst_pos || !w->inst_nrm || !w->inst_masked || !w->mesh_textured)
        goto nomem;
    w->inst_mesh = w->inst_mesh_store;

    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t i = 0; i < s->n_instances; i++) {
        const lg_instance *in = &s->instances[i];
        if (in->mesh >= s->n_meshes)
            return lg_error(n, "instance %u names mesh %u of %u", i, in->mesh, s->n_meshes);
        const lg_mesh *me = &s->meshes[in->mesh];
        if (!me->positions || !me->normals || (!me->indices && me->n_indices))
            return lg_error(n,
                            "mesh %u '%s' has no %s: the bake needs positions, normals "
                            "and indices",
                            in->mesh, me->name ? me->name : "",
                            !me->positions ? "positions"
                            : !me->normals ? "normals"
                                           : "indices");
        w->inst_mesh_store[i] = in->mesh;
        w->inst_masked[i] = lg_embree_mesh_masked(s, me);
        w->inst_pos[i] = malloc((size_t)me->n_vertices * 3 * sizeof(float) + 16);
        w->inst_nrm[i] = malloc((size_t)me->n_vertices * 3 * sizeof(float) + 16);
        if (!w->inst_pos[i] || !w->inst_nrm[i])
            goto nomem;
        for (uint32_t v = 0; v < me->n_vertices; v++) {
            double p[3], q[3];
            pb_xform_point(in->model, me->positions + 3 * (size_t)v, p);
            pb_xform_normal(in->normal_matrix, me->normals + 3 * (size_t)v, q);
            for (int c = 0; c < 3; c++) {
                if (!isfinite(p[c]) || !isfinite(q[c]))
                    return lg_error(n,
                                    "mesh %u '%s' vertex %u (instance %u): its %s is not "
                                    "finite",
                                    in->mesh, me->name ? me->name : "", v, i,
                                    isfinite(p[c]) ? "normal" : "position");
                w->inst_pos[i][3 * (size_t)v + c] = (float)p[c];
                w->inst_nrm[i][3 * (size_t)v + c] = (float)q[c];
                lo[c] = fmin(lo[c], p[c]);
                hi[c] = fmax(hi[c], p[c]);
                w->max_abs = fmax(w->max_abs, fabs(p[c]));
            }
        }
        w->n_triangles += me->n_indices / 3;
    }
    for (int c = 0; c < 3; c++)
        if (hi[c] >= lo[c])
            w->extent = fmax(w->extent, hi[c] - lo[c]);

    /* the vertices, numbered as transfer.h says, in the frame of their mesh's first
     * instance (a mesh without an instance keeps its object frame and occludes nothing) */
    uint32_t off = 0;
    for (uint32_t m = 0; m < s->n_meshes; m++) {
        const lg_mesh *me = &s->meshes[m];
        w->mesh_offset[m] = off;
        const lg_instance *first = NULL;
        for (uint32_t i = 0; i < s->n_instances && !first; i++)
            if (s->instances[i].mesh == m)
                first = &s->instances[i];
        float id[16], idn[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
        lg_m4_identity(id);
        if (me->n_vertices && (!me->positions || !me->normals))
            return lg_error(n, "mesh %u '%s' has no %s: the bake needs positions and normals", m,
                            me->name ? me->name : "", !me->positions ? "positions" : "normals");
        if (!albedo_param && me->material < s->n_materials) {
            const lg_texture_ref *r = &lg_material_maps_of(&s->materials[me->material])->base_color;
            w->mesh_textured[m] = r->texture >= 0 &&
                                  ((r->texcoord == 1 && me->texcoords1) || me->texcoords);
        }
        float rho[3];
        int arc = pb_mesh_albedo(n, s, m, albedo_param, rho);
        if (arc)
            return arc;
        for (uint32_t v = 0; v < me->n_vertices; v++, off++) {
            pb_xform_point(first ? first->model : id, me->positions + 3 * (size_t)v,
                           w->pos + 3 * (size_t)off);
            pb_xform_normal(first ? first->normal_matrix : idn, me->normals + 3 * (size_t)v,
                            w->nrm + 3 * (size_t)off);
            for (int c = 0; c < 3; c++) {
                if (!isfinite(w->pos[3 * (size_t)off + c]) ||
                    !isfinite(w->nrm[3 * (size_t)off + c]))
                    return lg_error(n,
                                    "mesh %u '%s' vertex %u: its position or normal is not "
                                    "finite",
                                    m, me->name ? me->name : "", v);
                w->albedo[3 * (size_t)off + c] = rho[c];
            }
        }
    }
    w->mesh_offset[s->n_meshes] = off;
    pb_world_inward(w);
    return 0;
nomem:
    return lg_error_code(n, LG_ERR_NOMEM, "out of memory (world copy of %llu vertices)",
                         (unsigned long long)nv);
}

/*
 * The self-intersection rule. A ray leaves vertex x along w from the origin
 *     o = x + eps(x) (N + D),   eps(x) = 2^-16 extent + PB_ULPS ulp(max(|x|, |y|, |z|)),
 * with tnear = 0, N the vertex's (shading) normal, D the unit tangent from x into its own
 * mesh's triangles (pb_world_inward: 0 inside a mesh, pointing away from a mesh's boundary)
 * and extent the largest side of the scene's world bounds.
 *   - eps: the first term is scale-free (the same geometry scaled gives the same rays,
 *     scaled); the second covers the rounding of float coordinates, which grows with the
 *     distance from the origin (a scene translated by 10^6 has 0.06-wide float steps):
 *     Embree's intersection error is a few ulps of the coordinates involved, so PB_ULPS
 *     ulps lift the origin clear of the vertex's own (coplanar) triangles on a flat plane
 *     anywhere (tests/plugins/prt_bake `large_coords`).
 *   - N rather than a geometric normal: a vertex has one normal but several triangles;
 *     rays with N.w <= 0 are never cast (their weight is 0).
 *   - D: a vertex where two meshes meet (the foot of a wall on a floor) lies ON the other
 *     mesh, whose triangle a ray leaving it would hit at t = 0 whichever way it goes (a
 *     black seam); moved by eps into its own surface it sees the wall block the directions
 *     into the wall only.
 */
#define PB_ULPS 4.0
static double pb_offset(const pb_world *w, const double *p)
{
    double m = fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2])));
    return ldexp(w->extent, -16) + PB_ULPS * m * (double)FLT_EPSILON;
}

/* ---- visibility ------------------------------------------------------------------------------ */

typedef struct pb_hit {
    uint32_t inst, prim;
    float u, v; /* Embree's barycentrics: p = (1-u-v) v0 + u v1 + v v2 */
    float cosw; /* max(N.w, 0) of the ray from the vertex */
} pb_hit;

typedef struct pb_vis {
    int kind;       /* PB_EMBREE or PB_BRUTE */
    RTCScene scene; /* embree: e.scene */
    lg_embree e;    /* the Embree scene (plugins/embree_common) */
    const pb_world *w;
} pb_vis;

static void pb_vis_free(pb_vis *v)
{
    lg_embree_free(&v->e);
    memset(v, 0, sizeof *v);
}

/* Builds the Embree scene of every instance (lg_embree.h: world space, geometry id =
 * instance index, both faces occlude); brute force needs nothing beyond the world copy,
 * whose float positions are the same bits (the model matrix in double, rounded once). */
static int pb_vis_make(lg_node *n, const pb_world *w, int kind, pb_vis *v)
{
    memset(v, 0, sizeof *v);
    v->kind = kind;
    v->w = w;
    if (kind == PB_BRUTE)
        return 0;
    int rc = lg_embree_make(n, w->s, &v->e);
    if (rc)
        return rc;
    v->scene = v->e.scene;
    lg_log(n, LG_LOG_DEBUG,
           "Embree scene: %u instances, %llu triangles, about %.1f MiB of "
           "geometry buffers plus its BVH",
           w->n_inst, (unsigned long long)w->n_triangles, (double)v->e.bytes / 1048576.0);
    return 0;
}

/* Moller-Trumbore, both faces: the distance t > 0 to the triangle, or -1. */
static double pb_mt(const double o[3], const double d[3], const float *a, const float *b,
                    const float *c, double *bu, double *bv)
{
    double e1[3], e2[3], pv[3], tv[3], qv[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
    }
    pv[0] = d[1] * e2[2] - d[2] * e2[1];
    pv[1] = d[2] * e2[0] - d[0] * e2[2];
    pv[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
    if (det == 0.0)
        return -1;
    double inv = 1.0 / det;
    for (int k = 0; k < 3; k++)
        tv[k] = o[k] - a[k];
    double u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) * inv;
    if (u < 0.0 || u > 1.0)
        return -1;
    qv[0] = tv[1] * e1[2] - tv[2] * e1[1];
    qv[1] = tv[2] * e1[0] - tv[0] * e1[2];
    qv[2] = tv[0] * e1[1] - tv[1] * e1[0];
    double vv = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) * inv;
    if (vv < 0.0 || u + vv > 1.0)
        return -1;
    double t = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) * inv;
    *bu = u;
    *bv = vv;
    return t > 0.0 ? t : -1;
}

/* The first hit along the ray (o, d), or false. With any_hit, stops at the first blocker
 * found (occlusion only; *h untouched). */
static bool pb_trace(const pb_vis *v, const double o[3], const double d[3], bool any_hit, pb_hit *h)
{
    if (v->kind == PB_EMBREE) {
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        if (any_hit) {
            struct RTCRay r = { .org_x = (float)o[0],
                                .org_y = (float)o[1],
                                .org_z = (float)o[2],
                                .tnear = 0.0f,
                                .dir_x = (float)d[0],
                                .dir_y = (float)d[1],
                                .dir_z = (float)d[2],
                                .tfar = INFINITY,
                                .mask = ~0u };
            rtcOccluded1(v->scene, &ctx, &r);
            return r.tfar < 0.0f; /* -inf when occluded */
        }
        struct RTCRayHit rh;
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = (float)o[0], rh.ray.org_y = (float)o[1], rh.ray.org_z = (float)o[2];
        rh.ray.dir_x = (float)d[0], rh.ray.dir_y = (float)d[1], rh.ray.dir_z = (float)d[2];
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = INFINITY;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(v->scene, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
            return false;
        h->inst = rh.hit.geomID;
        h->prim = rh.hit.primID;
        h->u = rh.hit.u;
        h->v = rh.hit.v;
        return true;
    }
    /* the seed's loop: every triangle of every instance (for comparison only) */
    const pb_world *w = v->w;
    double best = INFINITY;
    bool found = false;
    for (uint32_t i = 0; i < w->n_inst; i++) {
        const lg_mesh *me = &w->s->meshes[w->inst_mesh[i]];
        const float *P = w->inst_pos[i];
        for (uint32_t t = 0; t + 2 < me->n_indices; t += 3) {
            double bu, bv;
            double d_ = pb_mt(o, d, P + 3 * (size_t)me->indices[t],
                              P + 3 * (size_t)me->indices[t + 1],
                              P + 3 * (size_t)me->indices[t + 2], &bu, &bv);
            /* an alpha mask's transparent texels let the ray through, as Embree's filter
             * does (lg_embree_covers) */
            if (d_ > 0 && d_ < best &&
                (!w->inst_masked[i] || lg_embree_covers(w->s, me, t / 3, (float)bu, (float)bv))) {
                if (any_hit)
                    return true;
                best = d_;
                found = true;
                h->inst = i;
                h->prim = t / 3;
                h->u = (float)bu;
                h->v = (float)bv;
            }
        }
    }
    return found;
}

/* The world shading normal at a hit (instance's normals interpolated). */
static void pb_hit_normal(const pb_world *w, const pb_hit *h, double out[3])
{
    const lg_mesh *me = &w->s->meshes[w->inst_mesh[h->inst]];
    const uint32_t *ix = me->indices + 3 * (size_t)h->prim;
    const float *N = w->inst_nrm[h->inst];
    double b[3] = { 1.0 - h->u - h->v, h->u, h->v };
    for (int c = 0; c < 3; c++)
        out[c] = b[0] * N[3 * (size_t)ix[0] + c] + b[1] * N[3 * (size_t)ix[1] + c] +
                 b[2] * N[3 * (size_t)ix[2] + c];
}

/* The base colour texture's linear RGB at a hit (lg_scene_texture_sample at the texture
 * coordinates interpolated from the hit triangle's vertices): what a bounce off a textured
 * surface is multiplied by, the factor being in the hit vertices' transfer already. Only
 * for meshes with w->mesh_textured (the caller checks): the others multiply by nothing, so
 * an untextured scene's bounces are the bits they were. */
static void pb_hit_colour(const pb_world *w, const pb_hit *h, double out[3])
{
    const lg_mesh *me = &w->s->meshes[w->inst_mesh[h->inst]];
    const lg_material_maps *mp = lg_material_maps_of(&w->s->materials[me->material]);
    const lg_texture_ref *r = &mp->base_color;
    const float *tc = r->texcoord == 1 && me->texcoords1 ? me->texcoords1 : me->texcoords;
    const uint32_t *ix = me->indices + 3 * (size_t)h->prim;
    float b[3] = { 1.0f - h->u - h->v, h->u, h->v }, uv[2], st[2], c[4];
    for (int k = 0; k < 2; k++)
        uv[k] = b[0] * tc[2 * (size_t)ix[0] + k] + b[1] * tc[2 * (size_t)ix[1] + k] +
                b[2] * tc[2 * (size_t)ix[2] + k];
    lg_texture_ref_uv(r, uv, uv, st);
    lg_scene_texture_sample(w->s, r, st, true, c);
    for (int k = 0; k < 3; k++)
        out[k] = c[k];
}

/* ---- node state ------------------------------------------------------------------------------ */

typedef struct pb_params {
    int mode, sampler, visibility;
    uint32_t bands, samples, bounces, resolution;
    uint64_t seed;
    double threshold;
    bool bench;
    int64_t hit_mib;     /* the parameter: -1 = auto, else MiB */
    double hit_budget;   /* bytes of hits the bake may keep (pb_hit_budget) */
    const char *hit_why; /* how hit_budget was chosen, for the log */
    bool albedo_material;
    double albedo[3];
} pb_params;

typedef struct pb_state {
    pb_params p;
    bool reference;    /* prt_reference */
    uint32_t vertices; /* declared in prepare */
    /* prepare() looks the result up in the cache, so that the work it declares is 0 for a
     * hit: the entry's floats (freed once copied out, or in destroy) and bounces */
    bool cache_probed;
    float *cached;
    uint32_t cached_bounces;
    bool reported_nonfinite; /* reference: the probe's NaN/Inf texels said (pb_ref_clean) */
    uint64_t content;        /* bake: the digest of what it reads of the scene (pb_content) */
} pb_state;

static const char *const pb_modes[] = { "unshadowed", "shadowed", "interreflected", NULL };
static const char *const pb_samplers[] = { "jittered", "hammersley", "sobol", NULL };
static const char *const pb_visibilities[] = { "embree", "brute", NULL };
static const char *const pb_albedo_words[] = { "material", NULL };

/* The memory the system can still give without swapping: /proc/meminfo's MemAvailable
 * (Linux), else sysconf's available pages; 0 when neither says. */
static double pb_mem_available(void)
{
    FILE *f = fopen("/proc/meminfo", "r");
    if (f) {
        char line[256];
        unsigned long long kib = 0;
        bool found = false;
        while (!found && fgets(line, sizeof line, f))
            found = sscanf(line, "MemAvailable: %llu kB", &kib) == 1;
        fclose(f);
        if (found)
            return (double)kib * 1024.0;
    }
#ifdef _SC_AVPHYS_PAGES
    long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    if (pages > 0 && size > 0)
        return (double)pages * (double)size;
#endif
    return 0.0;
}

/* hit_memory_mib = -1 (auto, the default): the interreflected bake keeps the shadowed
 * pass's hits within a quarter of the memory available when it starts (MemAvailable, or
 * what an address-space limit leaves if that is less: lg_memory_available), at least 64
 * MiB. A quarter, because the rest of the bake (two transfers, the direction table, the
 * BVH) and whatever else runs must fit beside it; the hits are a speed-up, never a need
 * (over the budget the bounces cast their rays again, same bits). examples/prt.lgraph
 * interreflected keeps 158 M front-face hits, 3.0 GiB (README "Cost"): auto keeps them
 * where 12 GiB or more are available (this machine: 22 GiB, a budget of 5.6 GiB); the old
 * fixed default, 2048 MiB against a worst-case bound of 3.6 GiB, cast every bounce's 1.9e8
 * rays again. 0 keeps none; N keeps at most N MiB. */
static void pb_hit_budget(pb_params *p)
{
    if (p->hit_mib >= 0) {
        p->hit_budget = (double)p->hit_mib * 1048576.0;
        p->hit_why = "hit_memory_mib";
        return;
    }
    double avail = pb_mem_available(), limit = (double)lg_memory_available(NULL);
    if (!(avail > 0) || avail > limit)
        avail = limit;
    p->hit_budget = fmax(avail / 4.0, 64.0 * 1048576.0);
    p->hit_why = "hit_memory_mib = -1 (auto): a quarter of the memory available";
}

static int pb_read_params(lg_node *n, pb_state *st)
{
    pb_params *p = &st->p;
    p->mode = lg_param_enum(n, "mode");
    const lg_value *a = lg_param(n, "albedo");
    p->albedo_material = a && a->e == 0;
    if (a && !p->albedo_material)
        for (int c = 0; c < 3; c++) {
            p->albedo[c] = a->v[c];
            if (!(a->v[c] >= 0.0 && a->v[c] <= 1.0))
                return lg_error(n,
                                "albedo = [%g, %g, %g]: every channel must be in [0, 1] "
                                "(above 1 a surface makes energy)",
                                a->v[0], a->v[1], a->v[2]);
        }
    if (st->reference) {
        p->resolution = (uint32_t)lg_param_int(n, "resolution");
        if (p->mode == PB_INTERREFLECTED)
            return lg_error(n, "mode = interreflected: prt_reference computes unshadowed and "
                               "shadowed radiance only (an interreflected oracle would be a "
                               "path tracer)");
        return 0;
    }
    p->bands = (uint32_t)lg_param_int(n, "bands");
    p->visibility = lg_param_enum(n, "visibility");
    p->sampler = lg_param_enum(n, "sampler");
    p->samples = (uint32_t)lg_param_int(n, "samples");
    p->seed = (uint64_t)lg_param_int(n, "seed");
    p->bounces = (uint32_t)lg_param_int(n, "bounces");
    p->bench = lg_param_bool(n, "bench");
    p->hit_mib = lg_param_int(n, "hit_memory_mib");
    pb_hit_budget(p);
    p->threshold = lg_param_float(n, "bounce_threshold");
    if (!isfinite(p->threshold) || p->threshold < 0)
        return lg_error(n, "bounce_threshold = %g: must be a finite energy ratio >= 0",
                        p->threshold);
    /* the direction table: T n^2 floats */
    double table = (double)p->samples * p->samples * p->bands * p->bands * sizeof(float);
    if (table > 4.0 * 1073741824.0)
        return lg_error(n,
                        "samples = %u with bands = %u: the table of SH values at the %u^2 "
                        "directions would take %.1f GiB; lower one of them",
                        p->samples, p->bands, p->samples, table / 1073741824.0);
    return 0;
}

static int pb_create(lg_node *n, bool reference)
{
    pb_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->reference = reference;
    return 0;
}
static int pb_create_bake(lg_node *n)
{
    return pb_create(n, false);
}
static int pb_create_ref(lg_node *n)
{
    return pb_create(n, true);
}

static void pb_destroy(lg_node *n)
{
    pb_state *st = n->user;
    if (st)
        free(st->cached);
    free(n->user);
    n->user = NULL;
}

static const lg_scene *pb_scene_in(lg_node *n, const lg_resource **res)
{
    lg_assert_input(n, 0); /* both types' scene is required */
    const lg_resource *in = lg_input(n, 0);
    if (res)
        *res = in;
    return lg_scene_get(n, in);
}

/* The bake's working memory, from its parameters and the vertex count, against what the
 * machine can give (lg_memory_available), before anything runs: the direction table (T
 * directions, 24 bytes and n^2 floats each), the world copy (84 bytes per vertex), with
 * mode = interreflected two more transfers and, when hit_memory_mib lets them be kept, the
 * shadowed pass's hits (20 bytes each, up to T / 2 + 1 per vertex; the bound the bake
 * itself uses to decide). A hit_memory_mib the machine cannot give would otherwise grow
 * the hit lists until the process is killed. Returns 0 or an error naming the parameter,
 * its value, the bytes needed and the bytes available. */
static int pb_check_memory(lg_node *n, const pb_params *p, uint32_t nv)
{
    double T = (double)p->samples * p->samples, n2 = (double)p->bands * p->bands;
    double table = T * (3 * sizeof(double) + n2 * sizeof(float));
    double world = (double)nv * (3 * 3 * sizeof(double) + 3 * sizeof(float));
    double incr = p->mode == PB_INTERREFLECTED ? 2.0 * nv * 3 * n2 * sizeof(float) : 0.0;
    /* the hits kept: at most the budget (the bake stops keeping them beyond it); an
     * explicit hit_memory_mib is the user's to answer for, auto's quarter of what is
     * available is not counted (it never asks for more than the machine has free) */
    double hits = fmin((double)nv * (floor(T / 2) + 1) * sizeof(pb_hit), p->hit_budget);
    bool keep = p->mode == PB_INTERREFLECTED && hits > 0 && p->hit_mib >= 0;
    double need = table + world + incr + (keep ? hits : 0.0);
    const char *bound;
    uint64_t avail = lg_memory_available(&bound);
    if (need <= (double)avail)
        return 0;
    char need_s[32], have_s[32], hits_s[32];
    lg_bytes_text(need_s, sizeof need_s, (uint64_t)need);
    lg_bytes_text(have_s, sizeof have_s, avail);
    lg_bytes_text(hits_s, sizeof hits_s, (uint64_t)hits);
    if (keep && p->hit_mib >= 0)
        return lg_error_code(n, LG_ERR_NOMEM,
                             "hit_memory_mib = %lld keeps the shadowed pass's ray hits for the "
                             "bounces, up to %s (%u vertices x %.0f directions x %zu bytes), "
                             "and the bake then needs %s (%.0f bytes), more than the %s "
                             "(%llu bytes) of %s; lower hit_memory_mib below %.0f, or to 0 "
                             "(every bounce casts its rays again: the same result, slower)",
                             (long long)p->hit_mib, hits_s, nv, floor(T / 2) + 1, sizeof(pb_hit),
                             need_s, need, have_s, (unsigned long long)avail, bound,
                             hits / 1048576.0);
    return lg_error_code(n, LG_ERR_NOMEM,
                         "samples = %u with bands = %u: the bake needs %s (%.0f bytes: the "
                         "table of %.0f directions, %u vertices%s), more than the %s (%llu "
                         "bytes) of %s; lower samples or bands",
                         p->samples, p->bands, need_s, need, T, nv,
                         incr > 0 ? " and two transfers for the bounces" : "", have_s,
                         (unsigned long long)avail, bound);
}

/* ---- what the bake reads of the scene (its cache key) ---------------------------------------- */

/* FNV-1a, 64 bits, over `n` bytes (NULL: a marker, so that "absent" differs from "empty"). */
static uint64_t pb_fnv(uint64_t h, const void *data, size_t n)
{
    if (!data) {
        static const char absent[] = "(absent)";
        data = absent;
        n = sizeof absent;
    }
    const unsigned char *b = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}
#define PB_FNV(h, x) pb_fnv((h), &(x), sizeof(x))

/*
 * The digest of everything the bake reads of its scene, for its cache key: prt_bake is a
 * LG_NODE_CACHE_BY_CONTENT node, so its entries are named by its parameters and this key,
 * not by the scene node's identity (which holds every file the scene came from, its
 * images too). In it: every instance (mesh, model and normal matrices), every mesh
 * (positions, normals, indices, material), every material's base colour factor (the albedo
 * with albedo = material; its alpha, the mask's factor), alpha mode and cutoff and base
 * colour texture reference, and the pixels and sampler of that texture where the bake
 * reads them: for a masked (or blended) material, whose alpha decides what occludes, the
 * alpha channel, with the meshes' texture coordinates; and, for mode = interreflected with
 * albedo = material, every textured material's whole image (a bounce's light is multiplied
 * by the texture at its hit).
 * Not in it: a base colour image of an unmasked material in an unshadowed or shadowed
 * bake (the `prt` node multiplies it per pixel: a texture change needs no re-bake), normal,
 * emissive and other maps, lights, cameras, names.
 */
static uint64_t pb_content(const pb_params *p, const lg_scene *s)
{
    uint64_t h = 0xcbf29ce484222325ull;
    bool bounce_tex = p->mode == PB_INTERREFLECTED && p->albedo_material;
    h = PB_FNV(h, s->n_instances);
    for (uint32_t i = 0; i < s->n_instances; i++) {
        const lg_instance *in = &s->instances[i];
        h = PB_FNV(h, in->mesh);
        h = pb_fnv(h, in->model, sizeof in->model);
        h = pb_fnv(h, in->normal_matrix, sizeof in->normal_matrix);
    }
    const lg_scene_textures *tx = s->textures;
    h = PB_FNV(h, s->n_materials);
    for (uint32_t m = 0; m < s->n_materials; m++) {
        const lg_material *mat = &s->materials[m];
        const lg_material_maps *mp = lg_material_maps_of(mat);
        const lg_texture_ref *r = &mp->base_color;
        h = pb_fnv(h, mat->base_color, sizeof mat->base_color);
        h = PB_FNV(h, mp->alpha_mode);
        h = PB_FNV(h, mp->alpha_cutoff);
        h = PB_FNV(h, r->texture);
        h = PB_FNV(h, r->texcoord);
        h = pb_fnv(h, r->transform, sizeof r->transform);
        bool masked = mp->alpha_mode == LG_ALPHA_MASK || mp->alpha_mode == LG_ALPHA_BLEND;
        if (!(masked || bounce_tex) || r->texture < 0 || !tx ||
            (uint32_t)r->texture >= tx->n_textures)
            continue;
        const lg_scene_texture *t = &tx->textures[r->texture];
        h = PB_FNV(h, t->mag_filter);
        h = PB_FNV(h, t->wrap_s);
        h = PB_FNV(h, t->wrap_t);
        if (t->image >= tx->n_images)
            continue;
        const lg_scene_image *img = &tx->images[t->image];
        h = PB_FNV(h, img->width);
        h = PB_FNV(h, img->height);
        size_t texels = img->rgba8 ? (size_t)img->width * img->height : 0;
        if (bounce_tex) {
            h = pb_fnv(h, img->rgba8, texels * 4);
        } else {
            /* a mask reads the alpha alone: a new colour with the same alpha finds the bake */
            for (size_t k = 0; k < texels; k++)
                h = (h ^ img->rgba8[4 * k + 3]) * 0x100000001b3ull;
        }
    }
    h = PB_FNV(h, s->n_meshes);
    for (uint32_t m = 0; m < s->n_meshes; m++) {
        const lg_mesh *me = &s->meshes[m];
        h = PB_FNV(h, me->n_vertices);
        h = PB_FNV(h, me->n_indices);
        h = PB_FNV(h, me->material);
        h = pb_fnv(h, me->positions, me->positions ? (size_t)me->n_vertices * 12 : 0);
        h = pb_fnv(h, me->normals, me->normals ? (size_t)me->n_vertices * 12 : 0);
        h = pb_fnv(h, me->indices, me->indices ? (size_t)me->n_indices * 4 : 0);
        if (me->material >= s->n_materials)
            continue;
        const lg_material_maps *mp = lg_material_maps_of(&s->materials[me->material]);
        bool masked = mp->alpha_mode == LG_ALPHA_MASK || mp->alpha_mode == LG_ALPHA_BLEND;
        if ((masked || bounce_tex) && mp->base_color.texture >= 0) {
            h = pb_fnv(h, me->texcoords, me->texcoords ? (size_t)me->n_vertices * 8 : 0);
            h = pb_fnv(h, me->texcoords1, me->texcoords1 ? (size_t)me->n_vertices * 8 : 0);
        }
    }
    return h;
}

/* The cache entry of this node: its key and the header it must have. */
static void pb_cache_id(const pb_state *st, pb_cache_header *want, char *key, size_t keylen)
{
    const pb_params *p = &st->p;
    uint32_t nv = st->vertices;
    memset(want, 0, sizeof *want);
    want->version = PB_CACHE_VERSION;
    want->vertices = nv;
    want->mode = (uint32_t)p->mode + 1;
    if (st->reference) {
        memcpy(want->magic, "lgprtr1", 8);
        want->samples = p->resolution;
        want->floats = (uint64_t)nv * 4;
        snprintf(key, keylen, "reference-m%d-r%u-v%u", p->mode, p->resolution, nv);
    } else {
        memcpy(want->magic, "lgprtb1", 8);
        want->bands = p->bands;
        want->samples = p->samples;
        want->floats = (uint64_t)nv * 3 * p->bands * p->bands;
        snprintf(key, keylen, "transfer-m%d-b%u-s%u-v%u-c%016llx", p->mode, p->bands, p->samples,
                 nv, (unsigned long long)st->content);
    }
}

static bool pb_cache_load(lg_node *n, const char *key, const pb_cache_header *want,
                          uint32_t max_bounces, float *out, uint32_t *bounces);

/* The work estimates (lg_declare_work): seconds one thread takes per ray and per product.
 * From the README's "Cost" tables (tools/bench_prt_bake.py): the bake casts 7.8e6 to
 * 1.4e7 rays/s on 2 threads on the bunny box, SH accumulation included, 3.3e6 on an 871k
 * triangle mesh; 2.5e-7 s per ray and thread is the first figure. The accumulation (3 n^2
 * products per unblocked direction) is nearly free at 6 bands (bands 1..6 take 0.06 to
 * 0.07 s there) and matters at high band counts: 3e-10 s per product. Checked on
 * examples/prt.lgraph (23733 vertices, 128^2 directions, 6 bands, shadowed): 2.8e6 rays/s
 * on 2 threads with the machine's load at 4, 69 s, where the estimate says about 27 s for a
 * quiet machine. (An earlier figure, 3.8e-6 s per ray, had been measured with seven builds
 * running and made that bake "about 8 min".) Brute-force visibility tests each triangle,
 * 3e-9 s per test (PB_BRUTE_WARN's "about a minute" at 2e10). */
#define PB_SECONDS_PER_RAY 2.5e-7
#define PB_SECONDS_PER_PRODUCT 3e-10
#define PB_SECONDS_PER_TEST 3e-9

/* Looks the result up in the cache (kept for execute on a hit) and declares the work a
 * miss costs, or none for a hit. */
static void pb_declare_estimate(lg_node *n, pb_state *st, const lg_scene *s)
{
    pb_cache_header want;
    char key[96];
    pb_cache_id(st, &want, key, sizeof key);
    st->cache_probed = true;
    float *buf = malloc(want.floats ? want.floats * sizeof(float) : 1);
    /* the header here; the values in execute, against bounds that need the probe */
    uint32_t max_bounces = !st->reference && st->p.mode == PB_INTERREFLECTED ? st->p.bounces : 0;
    if (buf && pb_cache_load(n, key, &want, max_bounces, buf, &st->cached_bounces))
        st->cached = buf;
    else
        free(buf);
    if (st->cached) {
        lg_declare_work(n, 0, 0, "vertex x direction pairs (the result is in the cache)");
        return;
    }
    const pb_params *p = &st->p;
    uint64_t tris = 0;
    for (uint32_t i = 0; i < s->n_instances; i++)
        if (s->instances[i].mesh < s->n_meshes)
            tris += s->meshes[s->instances[i].mesh].n_indices / 3;
    double dirs = st->reference ? 6.0 * p->resolution * p->resolution
                                : (double)p->samples * p->samples;
    double pairs = (double)st->vertices * dirs;
    double n2 = st->reference ? 1.0 : (double)p->bands * p->bands;
    double per = 0.5 * 3 * n2 * PB_SECONDS_PER_PRODUCT; /* half the sphere is above */
    if (p->mode != PB_UNSHADOWED)
        per += 0.5 * (p->visibility == PB_BRUTE && !st->reference
                          ? (double)tris * PB_SECONDS_PER_TEST
                          : PB_SECONDS_PER_RAY);
    if (!st->reference && p->mode == PB_INTERREFLECTED)
        per += 0.5 * p->bounces * 3 * n2 * PB_SECONDS_PER_PRODUCT;
    lg_declare_work(n, pairs, pairs * per / lg_cpu_workers(n), "vertex x direction pairs");
}

typedef struct pb_bounds pb_bounds;
typedef double (*pb_scale_fn)(const void *ctx, uint32_t bounces);
static bool pb_cache_values_ok(lg_node *n, const char *key, pb_bounds *bounds, pb_scale_fn scale,
                               const void *scale_ctx, const float *f, uint64_t floats,
                               uint32_t bounces);

/* The cache entry prepare() found, copied into `out` (then freed), or a lookup now when
 * prepare did not look; then every value held to `bounds` (pb_cache_values_ok): an entry
 * that fails is rejected (lg_cache_reject) and this returns false. */
static bool pb_cache_take(lg_node *n, pb_state *st, const char *key, const pb_cache_header *want,
                          uint32_t max_bounces, pb_bounds *bounds, pb_scale_fn scale,
                          const void *scale_ctx, float *out, uint32_t *bounces)
{
    bool hit = false;
    if (st->cached) {
        memcpy(out, st->cached, want->floats * sizeof(float));
        *bounces = st->cached_bounces;
        free(st->cached);
        st->cached = NULL;
        hit = true;
    } else if (!st->cache_probed) {
        hit = pb_cache_load(n, key, want, max_bounces, out, bounces);
    }
    return hit && pb_cache_values_ok(n, key, bounds, scale, scale_ctx, out, want->floats, *bounces);
}

static int pb_prepare(lg_node *n)
{
    pb_state *st = n->user;
    int rc = pb_read_params(n, st);
    if (rc)
        return rc;
    const lg_scene *s = pb_scene_in(n, NULL);
    if (!s)
        return LG_ERR_INVALID;
    uint64_t nv = 0;
    for (uint32_t m = 0; m < s->n_meshes; m++)
        nv += s->meshes[m].n_vertices;
    if (nv == 0)
        return lg_error(n, "input 'scene' (%s) has no vertices: nothing to bake",
                        s->source ? s->source : "?");
    if (nv > UINT32_MAX / 2)
        return lg_error(n, "input 'scene' has %llu vertices: too many", (unsigned long long)nv);
    st->vertices = (uint32_t)nv;
    if (!st->reference && (rc = pb_check_memory(n, &st->p, st->vertices)))
        return rc;
    if (!st->reference)
        st->content = pb_content(&st->p, s);
    if (st->reference && lg_scene_is_animated(s))
        lg_log(n, LG_LOG_WARN,
               "the scene is animated (%u instances move): the reference is computed for its "
               "rest pose, once (each mesh in the frame of its first instance at rest, as the "
               "bake's transfer); compare a posed frame with a scene placed statically at that "
               "pose",
               s->features.animated);
    if (st->reference) {
        lg_resource_info info;
        const lg_resource *pr = lg_input(n, 1);
        if (!pr || lg_describe(pr, &info, n) != 0 || info.kind != LG_KIND_PROBE)
            return lg_error(n, "input 'probe' is not a light probe");
        lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
        lg_vertex_image_size(st->vertices, &d.width, &d.height);
        rc = lg_declare_image(n, 0, &d);
    } else {
        rc = lg_transfer_declare(n, 0, st->p.bands, st->vertices);
    }
    if (rc)
        return rc;
    pb_declare_estimate(n, st, s);
    return lg_set_device(n, LG_DEVICE_CPU);
}

/* ---- the bake -------------------------------------------------------------------------------- */

typedef struct pb_bake {
    const pb_params *p;
    const pb_world *w;
    const pb_vis *vis;
    uint32_t n2, T;
    const double *dirs; /* 3 per direction */
    const float *Y;     /* n2 per direction */
    /* interreflection */
    bool keep; /* interreflected: hits kept (else every bounce casts again) */
    /* the hits' bytes so far, against p->hit_budget: the first vertex whose hits would
     * pass it sets `over`, and the hits are dropped after the pass (pb_bake_execute) */
    _Atomic uint64_t hit_bytes;
    atomic_bool over;
    /* per vertex: its front-face hits (malloc'd, NULL when there are none) and their
     * count, PB_NOT_KEPT for a vertex this process did not keep: under MPI ranks a
     * process bakes only the vertices lg_shard hands it, so a bounce may draw a vertex
     * whose hits another process holds, and casts its rays again (the same bits) */
    pb_hit **hits;
    uint32_t *n_hits;
    const float *prev; /* the previous bounce's increment, every vertex */
    /* bench: per chunk of PB_GRAIN vertices, rays and blocked rays (pb_raw_vertices) */
    int *failed;
    uint64_t *rays;
} pb_bake;

#define PB_NOT_KEPT UINT32_MAX

/* Shadowed with Embree: the vertex's rays (N.w > 0) in packets of 16 through
 * rtcOccluded16, which bench = true measured about 1.3x faster than rtcOccluded1 on the
 * same rays (rays from one origin are coherent); the unblocked directions accumulate
 * max(N.w, 0) Y(w) into acc. Returns the rays cast. */
static uint64_t pb_vertex_packets(const pb_bake *b, const double o[3], const double N[3],
                                  double *acc)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    /* zeroed: a packet's unused lanes are masked off, but Embree (Debian's build keeps its
     * assertions) checks every lane for a finite ray, and lanes no packet filled yet (a
     * vertex with fewer than 16 rays: samples 2..4) held garbage and aborted the process */
    struct RTCRay16 r;
    memset(&r, 0, sizeof r);
    int valid[16];
    uint32_t idx[16], k = 0, n2 = b->n2;
    double cws[16];
    uint64_t rays = 0;
    for (uint32_t j = 0; j <= b->T; j++) {
        if (j < b->T) {
            const double *d = b->dirs + 3 * (size_t)j;
            double cw = N[0] * d[0] + N[1] * d[1] + N[2] * d[2];
            if (!(cw > 0.0))
                continue;
            r.org_x[k] = (float)o[0], r.org_y[k] = (float)o[1], r.org_z[k] = (float)o[2];
            r.dir_x[k] = (float)d[0], r.dir_y[k] = (float)d[1], r.dir_z[k] = (float)d[2];
            r.tnear[k] = 0.0f, r.tfar[k] = INFINITY, r.time[k] = 0.0f;
            r.mask[k] = ~0u, r.id[k] = k, r.flags[k] = 0;
            valid[k] = -1;
            idx[k] = j;
            cws[k] = cw;
            if (++k < 16)
                continue;
        }
        if (k == 0)
            break;
        for (uint32_t q = k; q < 16; q++)
            valid[q] = 0;
        rtcOccluded16(valid, b->vis->scene, &ctx, &r);
        rays += k;
        for (uint32_t q = 0; q < k; q++) {
            if (r.tfar[q] < 0.0f) /* -inf: occluded */
                continue;
            const float *y = b->Y + (size_t)idx[q] * n2;
            for (uint32_t c = 0; c < n2; c++)
                acc[c] += cws[q] * y[c];
        }
        k = 0;
    }
    return rays;
}

/* The direct pass (lg_shard's run): vertices [begin, end) into `items`, each vertex's
 * [3][n2] floats. A vertex's floats depend on its index alone (its position, normal and
 * the one global direction set), never on the chunk or the thread: the contract that
 * makes a bake over any number of threads or ranks the same bits. */
static int pb_bake_vertices(void *ctx, uint64_t begin, uint64_t end, void *items, char *err,
                            size_t err_size)
{
    pb_bake *b = ctx;
    const pb_world *w = b->w;
    uint32_t n2 = b->n2, T = b->T;
    double *acc = malloc(n2 * sizeof(double));
    pb_hit *tmp = NULL;
    uint32_t tmp_cap = 0;
    int rc = 0;
    if (!acc) {
        snprintf(err, err_size, "out of memory (%u coefficients of accumulator)", n2);
        return 1;
    }
    for (uint64_t i = begin; i < end; i++) {
        /* the way a vertex is traced depends on the parameters alone, never on whether
         * the budget was passed yet (which depends on the schedule): the packets'
         * rtcOccluded16 and rtcIntersect1 need not agree on a grazing ray */
        bool keep_hits = b->keep;
        const double *x = w->pos + 3 * i, *N = w->nrm + 3 * i, *D = w->in + 3 * i;
        double eps = pb_offset(w, x), o[3];
        for (int c = 0; c < 3; c++)
            o[c] = x[c] + eps * (N[c] + D[c]);
        memset(acc, 0, n2 * sizeof(double));
        uint32_t nh = 0;
        if (b->p->mode != PB_UNSHADOWED && !keep_hits && b->vis->kind == PB_EMBREE) {
            pb_vertex_packets(b, o, N, acc);
            goto store;
        }
        for (uint32_t j = 0; j < T; j++) {
            const double *d = b->dirs + 3 * (size_t)j;
            double cw = N[0] * d[0] + N[1] * d[1] + N[2] * d[2];
            if (!(cw > 0.0))
                continue;
            if (b->p->mode != PB_UNSHADOWED) {
                pb_hit h;
                if (pb_trace(b->vis, o, d, !keep_hits, &h)) {
                    if (keep_hits) {
                        /* a back face has no baked transfer on the side the ray sees: it
                         * blocks and carries nothing */
                        double hn[3];
                        pb_hit_normal(w, &h, hn);
                        if (hn[0] * d[0] + hn[1] * d[1] + hn[2] * d[2] < 0.0) {
                            if (nh == tmp_cap) {
                                uint32_t cap = tmp_cap ? 2 * tmp_cap : 64;
                                pb_hit *g = realloc(tmp, cap * sizeof *g);
                                if (!g)
                                    goto nomem;
                                tmp = g;
                                tmp_cap = cap;
                            }
                            h.cosw = (float)cw;
                            tmp[nh++] = h;
                        }
                    }
                    continue;
                }
            }
            const float *y = b->Y + (size_t)j * n2;
            for (uint32_t k = 0; k < n2; k++)
                acc[k] += cw * y[k];
        }
    store:;
        /* (rho / pi) (4 pi / T) sum = 4 rho / T sum */
        float *t = (float *)items + (i - begin) * 3 * n2;
        for (int c = 0; c < 3; c++) {
            double f = 4.0 * w->albedo[3 * i + c] / T;
            for (uint32_t k = 0; k < n2; k++)
                t[c * n2 + k] = (float)(f * acc[k]);
        }
        if (keep_hits && nh && !atomic_load_explicit(&b->over, memory_order_relaxed)) {
            uint64_t add = (uint64_t)nh * sizeof(pb_hit);
            uint64_t was = atomic_fetch_add_explicit(&b->hit_bytes, add, memory_order_relaxed);
            if ((double)(was + add) > b->p->hit_budget)
                atomic_store_explicit(&b->over, true, memory_order_relaxed);
        }
        if (keep_hits && !atomic_load_explicit(&b->over, memory_order_relaxed)) {
            if (nh) {
                b->hits[i] = malloc(nh * sizeof(pb_hit));
                if (!b->hits[i])
                    goto nomem;
                memcpy(b->hits[i], tmp, nh * sizeof(pb_hit));
            }
            b->n_hits[i] = nh;
        }
        continue;
    nomem:
        snprintf(err, err_size,
                 "out of memory at vertex %llu keeping its ray hits for the bounces, up to "
                 "%.1f MiB per vertex (hit_memory_mib = %lld; 0 keeps none)",
                 (unsigned long long)i, (double)(T / 2 + 1) * sizeof(pb_hit) / 1048576.0,
                 (long long)b->p->hit_mib);
        rc = 1;
        break;
    }
    free(tmp);
    free(acc);
    return rc;
}

/* The rays the direct pass cast (its log's count and rate): one per direction above a
 * vertex's horizon. Counted here rather than by the pass, whose vertices a process sees
 * only in part under MPI ranks; integers, so the chunks' sum is exact in any order. */
typedef struct pb_ray_count {
    const pb_world *w;
    const double *dirs;
    uint32_t T;
    uint64_t *per_chunk;
} pb_ray_count;

static void pb_count_rays(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    pb_ray_count *r = ctx;
    uint64_t rays = 0;
    for (size_t i = begin; i < end; i++) {
        const double *N = r->w->nrm + 3 * i;
        for (uint32_t j = 0; j < r->T; j++) {
            const double *d = r->dirs + 3 * (size_t)j;
            rays += N[0] * d[0] + N[1] * d[1] + N[2] * d[2] > 0.0;
        }
    }
    r->per_chunk[chunk] = rays;
}

/* One bounce (lg_shard's run): next(x) = (rho_x / pi) (4 pi / T) sum over x's front-face
 * hits of max(N.w, 0) prev(hit), prev interpolated at the hit from its triangle's vertices;
 * vertices [begin, end) into `items`, [3][n2] floats each. The hits are those this process
 * kept for the vertex, or else (not kept, or kept by another rank) the same rays cast again
 * in the same order: the same sum, bit for bit. */
static int pb_bounce_vertices(void *ctx, uint64_t begin, uint64_t end, void *items, char *err,
                              size_t err_size)
{
    pb_bake *b = ctx;
    const pb_world *w = b->w;
    uint32_t n2 = b->n2, stride = 3 * n2;
    double acc[3 * 64];
    double *a = stride <= 3 * 64 ? acc : malloc(stride * sizeof(double));
    if (!a) {
        snprintf(err, err_size, "out of memory (%u coefficients of accumulator)", stride);
        return 1;
    }
    for (uint64_t i = begin; i < end; i++) {
        float *t = (float *)items + (i - begin) * stride;
        memset(a, 0, stride * sizeof(double));
        const double *x = w->pos + 3 * i, *N = w->nrm + 3 * i, *D = w->in + 3 * i;
        double eps = pb_offset(w, x), o[3];
        for (int c = 0; c < 3; c++)
            o[c] = x[c] + eps * (N[c] + D[c]);
        /* kept hits, or the same rays cast again: the j loop below */
        bool kept = b->n_hits && b->n_hits[i] != PB_NOT_KEPT;
        uint32_t count = kept ? b->n_hits[i] : b->T;
        for (uint32_t h = 0; h < count; h++) {
            pb_hit again;
            const pb_hit *hh = kept ? &b->hits[i][h] : &again;
            if (!kept) {
                const double *d = b->dirs + 3 * (size_t)h;
                double cw = N[0] * d[0] + N[1] * d[1] + N[2] * d[2], hn[3];
                if (!(cw > 0.0) || !pb_trace(b->vis, o, d, false, &again))
                    continue;
                pb_hit_normal(w, &again, hn);
                if (!(hn[0] * d[0] + hn[1] * d[1] + hn[2] * d[2] < 0.0))
                    continue; /* a back face: carries nothing */
                again.cosw = (float)cw;
            }
            uint32_t m = w->inst_mesh[hh->inst];
            const uint32_t *ix = w->s->meshes[m].indices + 3 * (size_t)hh->prim;
            uint32_t off = w->mesh_offset[m];
            double bw[3] = { 1.0 - hh->u - hh->v, hh->u, hh->v };
            if (w->mesh_textured[m]) {
                /* the light leaving a textured hit: its vertices' transfer (the factor
                 * folded in) times the texture's colour at the hit, channel by channel */
                double tex[3];
                pb_hit_colour(w, hh, tex);
                for (int q = 0; q < 3; q++) {
                    const float *pv = b->prev + (size_t)(off + ix[q]) * stride;
                    for (int c = 0; c < 3; c++) {
                        double f = bw[q] * hh->cosw * tex[c];
                        for (uint32_t k = 0; k < n2; k++)
                            a[c * n2 + k] += f * pv[c * n2 + k];
                    }
                }
                continue;
            }
            for (int q = 0; q < 3; q++) {
                const float *pv = b->prev + (size_t)(off + ix[q]) * stride;
                double f = bw[q] * hh->cosw;
                for (uint32_t k = 0; k < stride; k++)
                    a[k] += f * pv[k];
            }
        }
        for (int c = 0; c < 3; c++) {
            double f = 4.0 * w->albedo[3 * i + c] / b->T;
            for (uint32_t k = 0; k < n2; k++)
                t[c * n2 + k] = (float)(f * a[c * n2 + k]);
        }
    }
    if (a != acc)
        free(a);
    return 0;
}

/* bench = true: the bake's rays again, with nothing but the occlusion query (b->p->mode
 * decides nothing here). rays[chunk] counts the rays, failed[chunk] the blocked ones (kept
 * so that the loop is not optimised away). packet: 16 rays per rtcOccluded16 call. */
static void pb_raw_vertices_impl(pb_bake *b, size_t begin, size_t end, uint32_t chunk, bool packet)
{
    const pb_world *w = b->w;
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    uint64_t rays = 0, blocked = 0;
    struct RTCRay16 r16;
    memset(&r16, 0, sizeof r16); /* as pb_vertex_packets: unused lanes hold a finite ray */
    int valid[16];
    uint32_t k = 0;
    for (size_t i = begin; i < end; i++) {
        const double *x = w->pos + 3 * i, *N = w->nrm + 3 * i, *D = w->in + 3 * i;
        double eps = pb_offset(w, x), o[3];
        for (int c = 0; c < 3; c++)
            o[c] = x[c] + eps * (N[c] + D[c]);
        for (uint32_t j = 0; j < b->T; j++) {
            const double *d = b->dirs + 3 * (size_t)j;
            if (!(N[0] * d[0] + N[1] * d[1] + N[2] * d[2] > 0.0))
                continue;
            rays++;
            if (!packet) {
                struct RTCRay r = { .org_x = (float)o[0],
                                    .org_y = (float)o[1],
                                    .org_z = (float)o[2],
                                    .tnear = 0.0f,
                                    .dir_x = (float)d[0],
                                    .dir_y = (float)d[1],
                                    .dir_z = (float)d[2],
                                    .tfar = INFINITY,
                                    .mask = ~0u };
                rtcOccluded1(b->vis->scene, &ctx, &r);
                blocked += r.tfar < 0.0f;
                continue;
            }
            r16.org_x[k] = (float)o[0], r16.org_y[k] = (float)o[1], r16.org_z[k] = (float)o[2];
            r16.dir_x[k] = (float)d[0], r16.dir_y[k] = (float)d[1], r16.dir_z[k] = (float)d[2];
            r16.tnear[k] = 0.0f, r16.tfar[k] = INFINITY, r16.mask[k] = ~0u, r16.time[k] = 0;
            r16.id[k] = 0, r16.flags[k] = 0;
            valid[k] = -1;
            if (++k == 16) {
                rtcOccluded16(valid, b->vis->scene, &ctx, &r16);
                for (uint32_t q = 0; q < 16; q++)
                    blocked += r16.tfar[q] < 0.0f;
                k = 0;
            }
        }
    }
    if (packet && k) {
        for (uint32_t q = k; q < 16; q++)
            valid[q] = 0;
        rtcOccluded16(valid, b->vis->scene, &ctx, &r16);
        for (uint32_t q = 0; q < k; q++)
            blocked += r16.tfar[q] < 0.0f;
    }
    b->rays[chunk] += rays;
    b->failed[chunk] += (int)(blocked & 1);
}
static void pb_raw1(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    pb_raw_vertices_impl(ctx, begin, end, chunk, false);
}
static void pb_raw16(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    pb_raw_vertices_impl(ctx, begin, end, chunk, true);
}

/* bench = true, and the ray count: runs fn over every vertex on this process's threads
 * (never spread over ranks: the bench times this machine's Embree) in batches so that the
 * progress bar moves between them (the pool's chunks must not call the host). Chunk c of
 * the whole range is [c PB_GRAIN, (c + 1) PB_GRAIN): the slot arrays (failed, rays) have
 * pb_chunks(nv) entries. */
#define PB_GRAIN 16u
static size_t pb_chunks(uint32_t nv)
{
    return lg_parallel_chunks(nv, PB_GRAIN);
}

typedef struct pb_tramp {
    void (*fn)(void *, size_t, size_t, uint32_t);
    void *ctx;
    size_t base;
} pb_tramp;

static void pb_tramp_fn(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    pb_tramp *t = ctx;
    t->fn(t->ctx, t->base + begin, t->base + end, (uint32_t)(t->base / PB_GRAIN) + chunk);
}

static int pb_run(lg_node *n, uint32_t nv, void (*fn)(void *, size_t, size_t, uint32_t), void *ctx,
                  const char *what, double f0, double f1)
{
    size_t per = ((size_t)nv + 31) / 32;
    per = (per + PB_GRAIN - 1) / PB_GRAIN * PB_GRAIN;
    for (size_t b0 = 0; b0 < nv; b0 += per) {
        size_t b1 = b0 + per < nv ? b0 + per : nv;
        pb_tramp t = { fn, ctx, b0 };
        int rc = lg_parallel_for(n, b1 - b0, PB_GRAIN, pb_tramp_fn, &t);
        if (rc)
            return rc;
        lg_progress(n, f0 + (f1 - f0) * (double)b1 / nv, what);
    }
    return 0;
}

/* The passes that make a result (the direct pass, each bounce, the reference) are
 * lg_shard jobs over the vertices, one job per pass (a bounce reads every vertex of the
 * last): in one process they run over the pool, under `mpirun -np N` over every rank's
 * threads, each rank taking chunks as it finishes its last, and every rank gets every
 * vertex. One job rather than batches: a batch would end with every rank waiting for its
 * slowest chunk, and the progress bar (the host's alone to move during a job) moves
 * between passes.
 *
 * The chunk: about PB_CHUNK_DIRS direction tests (rays, or kept hits in a bounce, or cube
 * texels in the reference), some milliseconds of one thread, so that handing a chunk to a
 * rank (a message) is noise, while a pass still has hundreds of chunks per thread to even
 * out the vertices near complex geometry, whose rays cost more. Results do not depend on
 * the grain. */
#define PB_CHUNK_DIRS 65536u
static uint64_t pb_grain(uint64_t dirs_per_vertex)
{
    uint64_t g = PB_CHUNK_DIRS / (dirs_per_vertex ? dirs_per_vertex : 1);
    return g < 1 ? 1 : g > 256 ? 256 : g;
}

/* The interreflected bake's direct pass and bounces: one affinity family (host.h, lg_shard
 * "Affinity") with one grain, so that under MPI each rank's bounce chunks are the vertices
 * whose hits it kept in the direct pass (another rank would cast their rays again). */
#define PB_AFFINITY 0x70626231u /* "pbb1": any non-zero number of this node's */

static int pb_shard(lg_node *n, uint32_t nv, uint64_t dirs_per_vertex, uint64_t item_bytes,
                    void *out, int (*run)(void *, uint64_t, uint64_t, void *, char *, size_t),
                    void *ctx, const char *what, double progress, uint32_t affinity)
{
    lg_shard_job job = { .count = nv,
                         .grain = pb_grain(dirs_per_vertex),
                         .item_bytes = item_bytes,
                         .out = out,
                         .run = run,
                         .ctx = ctx,
                         .what = "vertices",
                         .affinity = affinity };
    int rc = lg_shard(n, &job);
    if (!rc)
        lg_progress(n, progress, what);
    return rc;
}

/* What the node can have written into an entry, value by value (pb_bounds_*): the host's
 * checksum proves only that an entry is whole, and anyone who can write into the cache can
 * recompute it (issue "Reliability 3", finding 7), so each value is held to the bound of
 * the computation that makes it.
 *
 * The bake (t = (rho / pi) (4 pi / T) sum_j Y_k(w_j) V max(N.w_j, 0), README "What is
 * computed"): |Y_k| <= Y_l = sqrt((2l + 1) / (4 pi)) for k in band l (the addition theorem:
 * sum_m Y_lm^2 = (2l + 1) / (4 pi)), V in {0, 1}, so |t| <= rho Y_l W with
 *     W = max over unit N of (4 / T) sum_j max(N.w_j, 0)
 *       = max_N (2 / T) (sum_j |N.w_j| + N.sum_j w_j)
 *      <= (2 / T) (sqrt(T lambda_max(sum_j w_j w_j^T)) + |sum_j w_j|)   (Cauchy-Schwarz),
 * which the direction set gives exactly (about 2 / sqrt(3) = 1.155 for any even set; a
 * true cosine integral would be 1). A bounce adds rho_x (4 / T) sum max(N.w, 0) prev(hit),
 * prev interpolated (a convex combination): |dt_b| <= rho_x W max|dt_{b-1}|, so after B
 * bounces |t| <= rho_x Y_l W sum_{i=0..B} (rho_max W)^i.
 * The reference (r = (rho / pi) sum_t L_t V max(N.w_t, 0) dOmega_t over a cube's texels):
 * 0 <= r <= (rho / pi) L_max (1 / 2) sqrt(4 pi (4 pi / 3)) = rho L_max 2 / sqrt(3) (the
 * same inequality; a cube's texels are symmetric: sum w dOmega = 0, sum w w^T dOmega =
 * (4 pi / 3) I), L_max the probe's largest texel per channel (the resampling averages
 * texels). Both get a relative slack of 1e-3 for float rounding. */
#define PB_BOUND_SLACK 1.001
typedef struct pb_bounds {
    bool reference;   /* prt_reference's rgba per vertex, else the bake's [v][3][n2] */
    uint32_t n2;      /* bake: coefficients per channel */
    const float *rho; /* 3 per vertex: the albedo */
    double scale;     /* bake: W sum (rho_max W)^i; reference: 2 / sqrt(3) */
    double lmax[3];   /* reference: the probe's largest texel per channel */
} pb_bounds;

/* The largest |value| float i can hold (bake: symmetric; reference: [0, hi], alpha 1). */
static double pb_bound(const pb_bounds *b, uint64_t i)
{
    if (b->reference) {
        uint64_t v = i / 4;
        int c = (int)(i % 4);
        return c == 3 ? 1.0 : b->rho[3 * v + c] * b->lmax[c] * b->scale * PB_BOUND_SLACK;
    }
    uint64_t v = i / (3 * (uint64_t)b->n2), r = i % (3 * (uint64_t)b->n2);
    int c = (int)(r / b->n2);
    uint32_t k = (uint32_t)(r % b->n2), l = 0;
    while ((l + 1) * (l + 1) <= k)
        l++;
    double yl = sqrt((2.0 * l + 1.0) / (4.0 * LG_PI));
    return b->rho[3 * v + c] * yl * b->scale * PB_BOUND_SLACK;
}

/* Why float i, f, cannot be the node's (into why), or false when it can. */
static bool pb_value_bad(const pb_bounds *b, uint64_t i, float f, char *why, size_t n)
{
    static const char ch[4] = { 'R', 'G', 'B', 'A' };
    char where[96];
    if (b->reference)
        snprintf(where, sizeof where, "float %llu (vertex %llu, %c)", (unsigned long long)i,
                 (unsigned long long)(i / 4), ch[i % 4]);
    else
        snprintf(where, sizeof where, "float %llu (vertex %llu, %c, coefficient %llu)",
                 (unsigned long long)i, (unsigned long long)(i / (3 * (uint64_t)b->n2)),
                 ch[(i % (3 * (uint64_t)b->n2)) / b->n2], (unsigned long long)(i % b->n2));
    double hi = pb_bound(b, i);
    if (!isfinite(f))
        snprintf(why, n, "%s = %g is not finite", where, (double)f);
    else if (b->reference && i % 4 == 3 && f != 1.0f)
        snprintf(why, n, "%s = %g, where the reference writes alpha 1", where, (double)f);
    else if (b->reference && f < 0.0f)
        snprintf(why, n, "%s = %g, below the 0 a reference can make", where, (double)f);
    else if (fabs((double)f) > hi)
        snprintf(why, n, "%s = %g, beyond the %s%.6g this %s can make", where, (double)f,
                 b->reference ? "" : "+-", hi, b->reference ? "reference" : "bake");
    else
        return false;
    return true;
}

/* The bake's bound (pb_bounds above) for direction set (sampler, samples, seed), albedo
 * rho (3 per vertex) and `bounces` bounces. */
static double pb_bake_scale(const pb_params *p, const float *rho, uint32_t nv, uint32_t bounces)
{
    uint32_t T = p->samples * p->samples;
    double A[3][3] = { { 0 } }, sum[3] = { 0, 0, 0 };
    for (uint32_t j = 0; j < T; j++) {
        double uv[2], d[3];
        lg_sample_square((lg_sampler)p->sampler, p->samples, p->seed, j, uv);
        lg_sample_sphere(uv, d);
        for (int r = 0; r < 3; r++) {
            sum[r] += d[r];
            for (int c = 0; c < 3; c++)
                A[r][c] += d[r] * d[c];
        }
    }
    /* lambda_max <= the largest absolute row sum (Gershgorin) */
    double lam = 0;
    for (int r = 0; r < 3; r++)
        lam = fmax(lam, fabs(A[r][0]) + fabs(A[r][1]) + fabs(A[r][2]));
    double W = 2.0 / T *
               (sqrt(T * lam) + sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]));
    double rmax = 0;
    for (size_t i = 0; i < 3 * (size_t)nv; i++)
        rmax = fmax(rmax, rho[i]);
    double g = 0, term = 1;
    for (uint32_t i = 0; i <= bounces; i++, term *= rmax * W)
        g += term;
    return W * g;
}

/* The albedo of every vertex (3 floats each, malloc'd), numbered as transfer.h says; NULL
 * after an error. */
static float *pb_vertex_albedo(lg_node *n, const lg_scene *s, const pb_params *p, uint32_t nv)
{
    float *rho = malloc(((size_t)nv * 3 + 3) * sizeof(float));
    if (!rho) {
        lg_error_code(n, LG_ERR_NOMEM, "out of memory (albedo of %u vertices)", nv);
        return NULL;
    }
    size_t v = 0;
    for (uint32_t m = 0; m < s->n_meshes; m++) {
        float a[3];
        if (pb_mesh_albedo(n, s, m, p->albedo_material ? NULL : p->albedo, a)) {
            free(rho);
            return NULL;
        }
        for (uint32_t i = 0; i < s->meshes[m].n_vertices && v < nv; i++, v++)
            memcpy(rho + 3 * v, a, sizeof a);
    }
    for (; v < nv; v++) /* cannot happen (prepare counted these meshes): no bound then */
        rho[3 * v] = rho[3 * v + 1] = rho[3 * v + 2] = 0.0f;
    return rho;
}

/* Looks up the node's cache entry; true with `out` (floats) filled and *bounces set when
 * the entry is whole and its header agrees with `want` (pb_cache_header_check: magic,
 * version, bands, vertices, mode, samples, size) with at most max_bounces bounces. Anything
 * else: a warning ("not used (why)"), and false. The values are not looked at here:
 * pb_cache_values_ok holds them to what the node can make, in execute. */
static bool pb_cache_load(lg_node *n, const char *key, const pb_cache_header *want,
                          uint32_t max_bounces, float *out, uint32_t *bounces)
{
    void *data = NULL;
    size_t bytes = 0;
    if (lg_cache_get(n, key, &data, &bytes) != LG_OK)
        return false;
    pb_cache_header h;
    const char *why = pb_cache_header_check(data, bytes, want, &h);
    if (!why && h.bounces > max_bounces)
        why = "an impossible bounce count";
    if (!why) {
        /* copied (the payload need not be aligned for floats) */
        memcpy(out, (const char *)data + sizeof h, h.floats * sizeof(float));
        *bounces = h.bounces;
    }
    lg_cache_free(n, data);
    if (why)
        lg_log(n, LG_LOG_WARN, "cache entry '%s' not used (%s): computing it again", key, why);
    return !why;
}

/* Whether every value f[0 .. floats) of the entry `key` (of `bounces` bounces) is one the
 * node can have made (`bounds`, its scale from scale(scale_ctx, bounces) when given). The
 * first that is not is handed back with lg_cache_reject (one warning naming it, the file
 * removed, as the host does for a corrupt entry): false. */
static bool pb_cache_values_ok(lg_node *n, const char *key, pb_bounds *bounds, pb_scale_fn scale,
                               const void *scale_ctx, const float *f, uint64_t floats,
                               uint32_t bounces)
{
    if (scale)
        bounds->scale = scale(scale_ctx, bounces);
    char bad[256] = "";
    for (uint64_t i = 0; i < floats && !bad[0]; i++)
        pb_value_bad(bounds, i, f[i], bad, sizeof bad);
    if (bad[0])
        lg_cache_reject(n, key, bad);
    return !bad[0];
}

typedef struct pb_bake_scale_ctx {
    const pb_params *p;
    const float *rho;
    uint32_t nv;
} pb_bake_scale_ctx;

static double pb_bake_scale_cb(const void *ctx, uint32_t bounces)
{
    const pb_bake_scale_ctx *c = ctx;
    return pb_bake_scale(c->p, c->rho, c->nv, bounces);
}

/* Stores the entry and returns what happened, in the words of the node's log line: a line
 * that says "cached" when nothing was stored (the cache disabled, a write that failed)
 * sends the user looking for an entry that is not there. Not storing is a lost speed-up,
 * not an error. */
static const char *pb_cache_store(lg_node *n, const char *key, const pb_cache_header *h,
                                  const float *f)
{
    size_t total = 0;
    char *blob = pb_cache_encode(h, f, &total);
    if (!blob)
        return "not cached: no memory for the cache entry";
    int r = lg_cache_store(n, key, blob, total);
    free(blob);
    switch (r) {
    case LG_CACHE_STORED: return "cached";
    case LG_CACHE_OFF:
        return "not cached: the cache is disabled for this render (the warning above says why)";
    case LG_CACHE_NOT_STORED:
        return "not cached: the host could not store it (its warning above says why)";
    case LG_CACHE_UNKNOWN:
        return "handed to the cache (this host does not say whether it stored it)";
    default: return "not cached: the host refused the entry (its error above says why)";
    }
}

static int pb_bake_execute(lg_node *n, pb_state *st)
{
    const pb_params *p = &st->p;
    const lg_scene *s = pb_scene_in(n, NULL);
    if (!s)
        return LG_ERR_INVALID;
    uint32_t n2 = p->bands * p->bands, T = p->samples * p->samples, nv = st->vertices;
    const lg_resource *outr = lg_output(n, 0);
    const lg_resource *part = outr ? lg_part(n, outr, "transfer") : NULL;
    if (!part)
        return lg_error(n, "output 'out' has no transfer part");
    lg_cpu_view view;
    int rc = lg_map_cpu(n, part, LG_WRITE, &view);
    if (rc)
        return rc;
    float *out = view.pixels;
    size_t floats = (size_t)nv * 3 * n2;

    pb_cache_header want = { .magic = "lgprtb1",
                             .version = PB_CACHE_VERSION,
                             .bands = p->bands,
                             .vertices = nv,
                             .mode = (uint32_t)p->mode + 1,
                             .samples = p->samples,
                             .floats = floats };
    char key[96];
    snprintf(key, sizeof key, "transfer-m%d-b%u-s%u-v%u-c%016llx", p->mode, p->bands, p->samples,
             nv, (unsigned long long)st->content);
    lg_transfer_info info = { .struct_size = sizeof info,
                              .bands = p->bands,
                              .vertices = nv,
                              .mode = (lg_transfer_mode)(p->mode + 1) };
    uint32_t bounces = 0;
    float *rho = pb_vertex_albedo(n, s, p, nv);
    if (!rho)
        return LG_ERR_INVALID;
    pb_bounds bounds = { .n2 = n2, .rho = rho };
    pb_bake_scale_ctx sc = { p, rho, nv };
    bool hit = pb_cache_take(n, st, key, &want, p->mode == PB_INTERREFLECTED ? p->bounces : 0,
                             &bounds, pb_bake_scale_cb, &sc, out, &bounces);
    free(rho);
    if (hit) {
        info.bounces = bounces;
        lg_log(n, LG_LOG_INFO, "transfer loaded from the cache (%u vertices, %u bands, %s)", nv,
               p->bands, pb_modes[p->mode]);
        return lg_transfer_publish(n, 0, &info);
    }

    double t0 = lg_now(n);
    pb_world w;
    pb_vis vis;
    memset(&vis, 0, sizeof vis);
    double *dirs = NULL;
    float *Y = NULL, *incr[2] = { NULL, NULL };
    int *failed = NULL;
    uint64_t *rays = NULL;
    pb_bake b;
    memset(&b, 0, sizeof b);
    rc = pb_world_make(n, s, p->albedo_material ? NULL : p->albedo, &w);
    if (rc)
        goto done;
    if (p->mode != PB_UNSHADOWED) {
        rc = pb_vis_make(n, &w, p->visibility, &vis);
        if (rc)
            goto done;
        double tests = (double)w.n_triangles * nv * T * 0.5;
        if (p->visibility == PB_BRUTE && tests > PB_BRUTE_WARN)
            lg_log(n, LG_LOG_WARN,
                   "visibility = brute: about %.2g ray-triangle tests (%u "
                   "vertices, %llu triangles, %u directions); it is there for "
                   "comparison only, use visibility = embree",
                   tests, nv, (unsigned long long)w.n_triangles, T);
    }
    /* one global set of directions and their SH values, tabulated once (seed 0 §5.6) */
    dirs = malloc((size_t)T * 3 * sizeof(double));
    Y = malloc((size_t)T * n2 * sizeof(float));
    size_t nc = pb_chunks(nv);
    failed = calloc(nc, sizeof *failed);
    rays = calloc(nc, sizeof *rays);
    if (!dirs || !Y || !failed || !rays) {
        rc = lg_error_code(n, LG_ERR_NOMEM,
                           "out of memory (the direction table: %u directions x "
                           "%u coefficients, %.1f MiB)",
                           T, n2, (double)T * (n2 * 4 + 24) / 1048576.0);
        goto done;
    }
    {
        double *yd = malloc(n2 * sizeof(double));
        if (!yd) {
            rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory");
            goto done;
        }
        for (uint32_t j = 0; j < T; j++) {
            double uv[2];
            lg_sample_square((lg_sampler)p->sampler, p->samples, p->seed, j, uv);
            lg_sample_sphere(uv, dirs + 3 * (size_t)j);
            lg_sh_eval_d(p->bands, dirs + 3 * (size_t)j, yd);
            for (uint32_t k = 0; k < n2; k++)
                Y[(size_t)j * n2 + k] = (float)yd[k];
        }
        free(yd);
    }
    lg_log(n, LG_LOG_DEBUG, "direction table: %.1f MiB; transfer %.1f MiB",
           (double)T * (n2 * 4 + 24) / 1048576.0, (double)floats * 4 / 1048576.0);
    b = (pb_bake){ .p = p,
                   .w = &w,
                   .vis = &vis,
                   .n2 = n2,
                   .T = T,
                   .dirs = dirs,
                   .Y = Y,
                   .failed = failed,
                   .rays = rays };
    /* interreflected: keep the shadowed pass's hits (20 bytes each) while they fit the
     * budget (pb_hit_budget); past it they are dropped after the pass and every bounce
     * casts its rays again (the same bits) */
    double hit_bound = (double)nv * (T / 2 + 1) * sizeof(pb_hit);
    b.keep = p->mode == PB_INTERREFLECTED && p->hit_budget > 0;
    atomic_init(&b.hit_bytes, 0);
    atomic_init(&b.over, false);
    if (p->mode == PB_INTERREFLECTED)
        lg_log(n, LG_LOG_DEBUG,
               "interreflections: hits %s (at most %.1f MiB if every ray hit; budget %.1f "
               "MiB from %s)",
               b.keep ? "kept for the bounces within the budget" : "cast again every bounce",
               hit_bound / 1048576.0, p->hit_budget / 1048576.0, p->hit_why);
    if (b.keep) {
        b.hits = calloc(nv, sizeof *b.hits);
        b.n_hits = malloc(nv * sizeof *b.n_hits);
        if (b.n_hits)
            for (uint32_t i = 0; i < nv; i++)
                b.n_hits[i] = PB_NOT_KEPT;
        if (!b.hits || !b.n_hits) {
            rc = lg_error_code(n, LG_ERR_NOMEM,
                               "out of memory (hit lists of %u vertices, %.1f "
                               "MiB)",
                               nv, (double)nv * (sizeof *b.hits + sizeof *b.n_hits) / 1048576.0);
            goto done;
        }
    }
    double share = p->mode == PB_INTERREFLECTED ? 0.8 : 1.0;
    double tp = lg_now(n);
    rc = pb_shard(n, nv, p->mode == PB_UNSHADOWED ? 1 : T, (uint64_t)3 * n2 * sizeof(float), out,
                  pb_bake_vertices, &b, pb_modes[p->mode], share,
                  p->mode == PB_INTERREFLECTED ? PB_AFFINITY : 0);
    if (rc)
        goto done;
    double t1 = lg_now(n);
    uint64_t total_rays = 0;
    if (p->mode != PB_UNSHADOWED) {
        pb_ray_count count = { &w, dirs, T, rays };
        rc = lg_parallel_for(n, nv, PB_GRAIN, pb_count_rays, &count);
        if (rc)
            goto done;
        for (size_t c = 0; c < nc; c++)
            total_rays += rays[c];
    }
    if (b.keep && atomic_load(&b.over)) {
        /* over the budget: the hits kept so far go, every bounce casts again */
        lg_log(n, LG_LOG_INFO,
               "interreflections: the hits passed their budget of %.1f MiB (%s) after %.1f "
               "MiB: every bounce casts its rays again (the same result, slower)",
               p->hit_budget / 1048576.0, p->hit_why,
               (double)atomic_load(&b.hit_bytes) / 1048576.0);
        for (uint32_t i = 0; i < nv; i++)
            free(b.hits[i]);
        free(b.hits);
        free(b.n_hits);
        b.hits = NULL;
        b.n_hits = NULL;
        b.keep = false;
    }
    if (p->mode == PB_INTERREFLECTED) {
        uint64_t nh = 0;
        for (uint32_t i = 0; b.keep && i < nv; i++)
            nh += b.n_hits[i] != PB_NOT_KEPT ? b.n_hits[i] : 0;
        if (b.keep)
            lg_log(n, LG_LOG_INFO,
                   "interreflections: kept %llu front-face hits for the bounces: %.1f MiB "
                   "(budget %.1f MiB from %s)",
                   (unsigned long long)nh, (double)nh * sizeof(pb_hit) / 1048576.0,
                   p->hit_budget / 1048576.0, p->hit_why);
        incr[0] = malloc(floats * sizeof(float));
        incr[1] = malloc(floats * sizeof(float));
        if (!incr[0] || !incr[1]) {
            rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory (two transfer copies, %.1f MiB)",
                               (double)floats * 8 / 1048576.0);
            goto done;
        }
        memcpy(incr[0], out, floats * sizeof(float));
        /* energy of a transfer: sum over vertices and channels of |t_0| */
        double e0 = 0;
        for (uint32_t i = 0; i < nv; i++)
            for (int c = 0; c < 3; c++)
                e0 += fabs(out[(size_t)i * 3 * n2 + (size_t)c * n2]);
        const char *why = "the bounce count";
        uint32_t k;
        for (k = 1; k <= p->bounces; k++) {
            b.prev = incr[(k - 1) & 1];
            float *next = incr[k & 1];
            /* a bounce reads every vertex of the last: one job each, after the last */
            /* the direct pass's grain (T), not the bounce's cost (T / 2): one family */
            rc = pb_shard(n, nv, T, (uint64_t)3 * n2 * sizeof(float), next, pb_bounce_vertices, &b,
                          "interreflections", share + (1 - share) * k / p->bounces, PB_AFFINITY);
            if (rc)
                goto done;
            double e = 0;
            for (size_t q = 0; q < floats; q++)
                out[q] += next[q];
            for (uint32_t i = 0; i < nv; i++)
                for (int c = 0; c < 3; c++)
                    e += fabs(next[(size_t)i * 3 * n2 + (size_t)c * n2]);
            double ratio = e0 > 0 ? e / e0 : 0;
            lg_log(n, LG_LOG_DEBUG, "bounce %u: energy %.4g of the direct transfer's", k, ratio);
            if (ratio < p->threshold) {
                why = "the energy threshold";
                break;
            }
        }
        info.bounces = k <= p->bounces ? k : p->bounces;
        lg_log(n, LG_LOG_INFO,
               "interreflections: %u bounces in %.3f s, stopped by %s "
               "(bounce_threshold %g)",
               info.bounces, lg_now(n) - t1, why, p->threshold);
    }
    double secs = lg_now(n) - t0;
    if (p->bench && p->mode != PB_UNSHADOWED && p->visibility == PB_EMBREE) {
        double rate[2];
        for (int q = 0; q < 2; q++) {
            memset(rays, 0, nc * sizeof *rays);
            double tq = lg_now(n);
            rc = pb_run(n, nv, q ? pb_raw16 : pb_raw1, &b, "bench", 0.0, 1.0);
            if (rc)
                goto done;
            uint64_t r = 0;
            for (size_t c = 0; c < nc; c++)
                r += rays[c];
            double dt = lg_now(n) - tq;
            rate[q] = dt > 0 ? r / dt : 0.0;
        }
        double bake_rate = t1 > tp ? total_rays / (t1 - tp) : 0.0;
        lg_log(n, LG_LOG_INFO,
               "bench: bake (rtcOccluded16) %.4g rays/s, bare rtcOccluded1 %.4g rays/s, "
               "rtcOccluded16 %.4g rays/s (same %llu rays, %u threads): the "
               "bake at %.0f%% of rtcOccluded1",
               bake_rate, rate[0], rate[1], (unsigned long long)total_rays, lg_cpu_workers(n),
               rate[0] > 0 ? 100.0 * bake_rate / rate[0] : 0.0);
    }
    want.bounces = info.bounces;
    const char *stored = pb_cache_store(n, key, &want, out);
    lg_log(n, LG_LOG_INFO,
           "transfer baked in %.3f s (%u vertices, %u bands, %s, %u directions, "
           "%s visibility, %llu rays, %.3g rays/s in the visibility pass of %.3f s, "
           "%u threads); %s",
           secs, nv, p->bands, pb_modes[p->mode], T, pb_visibilities[p->visibility],
           (unsigned long long)total_rays, t1 > tp ? total_rays / (t1 - tp) : 0.0, t1 - tp,
           lg_cpu_workers(n), stored);
    rc = lg_transfer_publish(n, 0, &info);
done:
    if (b.hits)
        for (uint32_t i = 0; i < nv; i++)
            free(b.hits[i]);
    free(b.hits);
    free(b.n_hits);
    free(incr[0]);
    free(incr[1]);
    free(failed);
    free(rays);
    free(dirs);
    free(Y);
    pb_vis_free(&vis);
    pb_world_free(&w);
    return rc;
}

/* ---- the reference --------------------------------------------------------------------------- */

typedef struct pb_ref {
    const pb_params *p;
    const pb_world *w;
    const pb_vis *vis;
    uint32_t n_tex;    /* 6 R^2 */
    const float *dirs; /* 3 per texel (world) */
    const float *L;    /* 3 per texel: radiance x solid angle */
} pb_ref;

/* lg_shard's run: vertices [begin, end) into `items`, rgba each (the per-vertex image's
 * pixels: vertex i is pixel i of its 1024-wide rows). */
static int pb_ref_vertices(void *ctx, uint64_t begin, uint64_t end, void *items, char *err,
                           size_t err_size)
{
    (void)err;
    (void)err_size;
    pb_ref *r = ctx;
    const pb_world *w = r->w;
    for (uint64_t i = begin; i < end; i++) {
        float *px = (float *)items + 4 * (i - begin);
        const double *x = w->pos + 3 * i, *N = w->nrm + 3 * i, *D = w->in + 3 * i;
        double eps = pb_offset(w, x), o[3], acc[3] = { 0, 0, 0 };
        for (int c = 0; c < 3; c++)
            o[c] = x[c] + eps * (N[c] + D[c]);
        for (uint32_t t = 0; t < r->n_tex; t++) {
            const float *df = r->dirs + 3 * (size_t)t;
            double d[3] = { df[0], df[1], df[2] };
            double cw = N[0] * d[0] + N[1] * d[1] + N[2] * d[2];
            if (!(cw > 0.0))
                continue;
            pb_hit h;
            if (r->p->mode != PB_UNSHADOWED && pb_trace(r->vis, o, d, true, &h))
                continue;
            for (int c = 0; c < 3; c++)
                acc[c] += cw * r->L[3 * (size_t)t + c];
        }
        for (int c = 0; c < 3; c++)
            px[c] = (float)(w->albedo[3 * i + c] / LG_PI * acc[c]);
        px[3] = 1.0f;
    }
    return 0;
}

/* The probe's level 0 (`texels` RGBA texels, faces in order for a cube) with every NaN or
 * infinite colour channel set to 0, so that a texel that is not radiance adds nothing to
 * the integral instead of turning every vertex that sees it into NaN or Inf (a single texel
 * reaches a whole hemisphere of vertices through the resampling). The channel alone is
 * zeroed, as the `probe` node does for a file's texels; alpha is not read. Returns NULL
 * when every colour channel is finite (the probe is then used as it is, so the quadrature on
 * a finite probe is unchanged bit for bit), else a malloc'd copy the caller frees, and
 * *bad, *first: the texels changed and the index of the first. *nomem is set when the copy
 * could not be made. */
static float *pb_ref_clean(const float *px, size_t texels, uint64_t *bad, size_t *first,
                           bool *nomem)
{
    *bad = 0;
    *nomem = false;
    for (size_t i = 0; i < texels; i++)
        if (!isfinite(px[4 * i]) || !isfinite(px[4 * i + 1]) || !isfinite(px[4 * i + 2])) {
            if (!*bad)
                *first = i;
            ++*bad;
        }
    if (!*bad)
        return NULL;
    float *c = malloc(texels * 4 * sizeof(float));
    if (!c) {
        *nomem = true;
        return NULL;
    }
    memcpy(c, px, texels * 4 * sizeof(float));
    for (size_t i = *first; i < texels; i++)
        for (int k = 0; k < 3; k++)
            if (!isfinite(c[4 * i + k]))
                c[4 * i + k] = 0.0f;
    return c;
}

/* Says the probe's non-finite texels once per node (the words of lg_warn_nonfinite, as
 * `image`, ibl and the volumetric nodes say theirs), with where the first one is. */
static void pb_ref_say_nonfinite(lg_node *n, pb_state *st, const lg_probe *probe, uint64_t bad,
                                 size_t first)
{
    if (!bad || st->reported_nonfinite)
        return;
    const lg_image_desc *rd = &probe->radiance_desc;
    size_t face_texels = (size_t)rd->width * rd->height;
    uint32_t face = (uint32_t)(first / face_texels);
    size_t in_face = first % face_texels;
    char what[96], fate[256];
    snprintf(what, sizeof what, "input 'probe' (%ux%u%s)", rd->width, rd->height,
             probe->info.layout == LG_PROBE_CUBE ? " per cube face" : "");
    if (probe->info.layout == LG_PROBE_CUBE)
        snprintf(fate, sizeof fate,
                 "left out of the integral (those channels count as radiance 0); the first at "
                 "texel (%zu, %zu) of face %u (reported once)",
                 in_face % rd->width, in_face / rd->width, face);
    else
        snprintf(fate, sizeof fate,
                 "left out of the integral (those channels count as radiance 0); the first at "
                 "texel (%zu, %zu) (reported once)",
                 in_face % rd->width, in_face / rd->width);
    lg_warn_nonfinite(n, what, bad, fate);
    st->reported_nonfinite = true;
}

static int pb_ref_execute(lg_node *n, pb_state *st)
{
    const pb_params *p = &st->p;
    const lg_scene *s = pb_scene_in(n, NULL);
    if (!s)
        return LG_ERR_INVALID;
    lg_probe pv;
    const lg_resource *pres = lg_input(n, 1);
    const lg_probe *probe = lg_probe_get(n, pres, &pv);
    if (!probe)
        return lg_error(n, "input 'probe' is empty or not a probe");
    const lg_image_desc *rd = &probe->radiance_desc;
    if (rd->format != LG_FORMAT_RGBA32F || rd->width == 0 || rd->height == 0)
        return lg_error(n, "input 'probe': the radiance image must be a non-empty rgba32f image");
    uint32_t nv = st->vertices, R = p->resolution;
    lg_cpu_view ov;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov);
    if (rc)
        return rc;
    uint32_t W, H;
    lg_vertex_image_size(nv, &W, &H);
    float *out = ov.pixels;
    memset(out, 0, (size_t)W * H * 4 * sizeof(float));

    pb_cache_header want = { .magic = "lgprtr1",
                             .version = PB_CACHE_VERSION,
                             .bands = 0,
                             .vertices = nv,
                             .mode = (uint32_t)p->mode + 1,
                             .samples = R,
                             .floats = (uint64_t)nv * 4 };
    char key[96];
    snprintf(key, sizeof key, "reference-m%d-r%u-v%u", p->mode, R, nv);
    uint32_t unused = 0;
    float *rho = pb_vertex_albedo(n, s, p, nv);
    if (!rho)
        return LG_ERR_INVALID;
    pb_bounds bounds = { .reference = true, .rho = rho, .scale = 2.0 / sqrt(3.0) };
    /* level 0, the one the resampling reads; its non-finite channels zeroed in a copy
     * (pb_ref_clean), said whether or not the cache holds the result */
    lg_cpu_view prv;
    if ((rc = lg_map_cpu(n, probe->radiance, LG_READ, &prv))) {
        free(rho);
        return rc;
    }
    size_t texels = (size_t)rd->width * rd->height *
                    (probe->info.layout == LG_PROBE_CUBE ? 6u : 1u);
    uint64_t bad = 0;
    size_t first = 0;
    bool nomem = false;
    float *clean = pb_ref_clean(prv.pixels, texels, &bad, &first, &nomem);
    if (nomem) {
        free(rho);
        return lg_error_code(n, LG_ERR_NOMEM,
                             "out of memory (a copy of the probe's %zu texels without its NaN "
                             "and Inf)",
                             texels);
    }
    pb_ref_say_nonfinite(n, st, probe, bad, first);
    const float *px = clean ? clean : prv.pixels;
    /* the largest texel per channel (finite, after the cleaning) */
    for (size_t i = 0; i < texels; i++)
        for (int c = 0; c < 3; c++)
            if (px[4 * i + c] > bounds.lmax[c])
                bounds.lmax[c] = px[4 * i + c];
    bool hit = pb_cache_take(n, st, key, &want, 0, &bounds, NULL, NULL, out, &unused);
    free(rho);
    if (hit) {
        free(clean);
        lg_log(n, LG_LOG_INFO, "reference loaded from the cache (%u vertices, %s)", nv,
               pb_modes[p->mode]);
        return 0;
    }
    double t0 = lg_now(n);
    size_t n_tex = (size_t)6 * R * R;
    float *cube = malloc(n_tex * 4 * sizeof(float));
    float *sa = malloc(n_tex * sizeof(float));
    float *dirs = malloc(n_tex * 3 * sizeof(float));
    float *L = malloc(n_tex * 3 * sizeof(float));
    pb_world w;
    memset(&w, 0, sizeof w);
    pb_vis vis;
    memset(&vis, 0, sizeof vis);
    if (!cube || !sa || !dirs || !L) {
        rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory (cube of face %u)", R);
        goto done;
    }
    /* resampled with the probe's rotation baked in: texel directions are world directions */
    lg_probe_image src = lg_probe_image_at(probe->info.layout, rd, px, 0, probe->info.rotation);
    rc = lg_probe_resample_pool(n, &src, LG_PROBE_CUBE, R, R, NULL, NULL, cube, NULL);
    if (rc) {
        rc = lg_error_code(n, rc, "resampling the probe to a cube of face %u failed", R);
        goto done;
    }
    if (lg_probe_solid_angles(LG_PROBE_CUBE, R, R, sa) != 0) {
        rc = lg_error(n, "solid angles of a cube of face %u: failed", R);
        goto done;
    }
    for (uint32_t f = 0, t = 0; f < 6; f++)
        for (uint32_t j = 0; j < R; j++)
            for (uint32_t i = 0; i < R; i++, t++) {
                lg_vec3 d = lg_probe_texel_dir(LG_PROBE_CUBE, R, R, f, i, j);
                double l = sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
                dirs[3 * t] = (float)(d.x / l);
                dirs[3 * t + 1] = (float)(d.y / l);
                dirs[3 * t + 2] = (float)(d.z / l);
                for (int c = 0; c < 3; c++)
                    L[3 * t + c] = cube[4 * (size_t)t + c] * sa[t];
            }
    rc = pb_world_make(n, s, p->albedo_material ? NULL : p->albedo, &w);
    if (rc)
        goto done;
    if (p->mode != PB_UNSHADOWED) {
        rc = pb_vis_make(n, &w, PB_EMBREE, &vis);
        if (rc)
            goto done;
    }
    pb_ref r = { .p = p, .w = &w, .vis = &vis, .n_tex = (uint32_t)n_tex, .dirs = dirs, .L = L };
    rc = pb_shard(n, nv, n_tex, 4 * sizeof(float), out, pb_ref_vertices, &r, "reference", 1.0, 0);
    if (rc)
        goto done;
    double secs_ref = lg_now(n) - t0;
    const char *stored = pb_cache_store(n, key, &want, out);
    lg_log(n, LG_LOG_INFO,
           "reference computed in %.3f s (%u vertices, %s, cube %u: %zu "
           "texels); %s",
           secs_ref, nv, pb_modes[p->mode], R, n_tex, stored);
done:
    free(clean);
    free(cube);
    free(sa);
    free(dirs);
    free(L);
    pb_vis_free(&vis);
    pb_world_free(&w);
    return rc;
}

static int pb_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    /* static: the host runs it again only when the scene (or probe) changed, and then the
     * cache is looked up under the new identity */
    pb_state *st = n->user;
    return st->reference ? pb_ref_execute(n, st) : pb_bake_execute(n, st);
}

/* ---- the node types -------------------------------------------------------------------------- */

#define PB_ALBEDO_PARAM                                                                            \
    {                                                                                              \
        .key = "albedo", .type = LG_PARAM_COLOR, .def.e = 0, .min = 0, .max = 1,                   \
        .enum_values = pb_albedo_words,                                                            \
        .doc = "material (the glTF base colour's RGB of each mesh's material) or [r, g, b] "       \
               "in [0, 1] for every surface: folded into the result"                               \
    }

static const lg_param_desc pb_bake_params[] = {
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = PB_SHADOWED,
      .enum_values = pb_modes,
      .doc = "unshadowed (cosine only), shadowed (visibility by rays), interreflected "
             "(shadowed plus bounces)" },
    { .key = "bands",
      .type = LG_PARAM_INT,
      .def.i = 3,
      .min = 1,
      .max = LG_SH_MAX_BANDS,
      .doc = "SH bands n (n^2 coefficients per channel); the bake's cost is rays + "
             "T n^2 multiply-adds per vertex, its memory 12 n^2 bytes per vertex" },
    { .key = "sampler",
      .type = LG_PARAM_ENUM,
      .def.e = LG_SAMPLER_SOBOL,
      .enum_values = pb_samplers,
      .doc = "how the directions are drawn (lightgraph/sampling.h)" },
    { .key = "samples",
      .type = LG_PARAM_INT,
      .def.i = 32,
      .min = 1,
      .max = 2048,
      .doc = "N: N^2 directions over the sphere (about half of them cast rays)" },
    { .key = "seed",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 0x7fffffff,
      .doc = "the point set's seed (jittered: the jitter; hammersley, sobol: a digital shift)" },
    PB_ALBEDO_PARAM,
    { .key = "visibility",
      .type = LG_PARAM_ENUM,
      .def.e = PB_EMBREE,
      .enum_values = pb_visibilities,
      .doc = "embree (BVH occlusion rays) or brute (the seed's test of every triangle for "
             "every ray: for comparison only, it warns above about 2e10 tests)" },
    { .key = "bounces",
      .type = LG_PARAM_INT,
      .def.i = 3,
      .min = 1,
      .max = 64,
      .doc = "interreflected: at most this many bounces" },
    { .key = "hit_memory_mib",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1 << 20,
      .doc = "interreflected: the shadowed pass's front-face ray hits (20 bytes each) are "
             "kept for the bounces while they take at most this many MiB; -1 (auto): a "
             "quarter of the memory available (MemAvailable), at least 64 MiB; over it, or "
             "with 0, every bounce casts its rays again (same result, slower)" },
    { .key = "bench",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "after the bake, time bare Embree occlusion queries on the same rays "
             "(rtcOccluded1, and rtcOccluded16 packets) and log rays/s; for "
             "tools/bench_prt_bake.py" },
    { .key = "bounce_threshold",
      .type = LG_PARAM_FLOAT,
      .def.f = 1e-3,
      .min = 0,
      .max = 1,
      .doc = "interreflected: stop once a bounce adds less than this fraction of the direct "
             "transfer's energy (sum over vertices and channels of |t_0|)" },
};

static const char *const pb_ref_modes[] = { "unshadowed", "shadowed", "interreflected", NULL };

static const lg_param_desc pb_ref_params[] = {
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = PB_SHADOWED,
      .enum_values = pb_ref_modes,
      .doc = "unshadowed or shadowed (interreflected is refused)" },
    { .key = "resolution",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 4,
      .max = 512,
      .doc = "face size of the cube the probe is resampled to (integral-preserving): "
             "6 R^2 directions per vertex" },
    PB_ALBEDO_PARAM,
};

static const lg_port_desc pb_bake_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene (every instance occludes)" },
};
static const lg_port_desc pb_bake_out[] = {
    { .name = "out",
      .kind = LG_KIND_TRANSFER,
      .doc = "per-vertex transfer (lightgraph/transfer.h), the albedo folded in" },
};
static const lg_port_desc pb_ref_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" },
    { .name = "probe", .kind = LG_KIND_PROBE, .doc = "the lighting (any layout)" },
};
static const lg_port_desc pb_ref_out[] = {
    { .name = "vertices",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f per-vertex image (transfer.h): each vertex's exit radiance, alpha 1" },
};

static const lg_node_type pb_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "prt_bake",
        .doc = "Per-vertex PRT transfer vectors (unshadowed, shadowed, interreflected) with "
               "Embree visibility, cached on disk",
        LG_PARAMS(pb_bake_params),
        LG_INPUTS(pb_bake_in),
        LG_OUTPUTS(pb_bake_out),
        .needs = LG_NEEDS_GEOMETRY,
        /* per vertex: the camera plays no part; cached by what it reads of the scene
         * (pb_content), not by the scene's identity; in each mesh's frame of its first
         * instance at rest: an animation that moves it does not re-bake (prt turns the
         * lighting instead, plugins/prt/README.md "Rigid motion") */
        .flags = LG_NODE_VIEW_INDEPENDENT | LG_NODE_CACHE_BY_CONTENT | LG_NODE_POSE_INDEPENDENT,
        .create = pb_create_bake,
        .prepare = pb_prepare,
        .execute = pb_execute,
        .destroy = pb_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "prt_reference",
        .doc = "Per-vertex exit radiance under a probe by exact quadrature over its texels "
               "with Embree visibility: the oracle of the PRT accuracy study",
        LG_PARAMS(pb_ref_params),
        LG_INPUTS(pb_ref_in),
        LG_OUTPUTS(pb_ref_out),
        .needs = LG_NEEDS_GEOMETRY,
        /* the rest pose, like the bake it checks: an animation does not re-run it (it says
         * so when the scene is animated) */
        .flags = LG_NODE_VIEW_INDEPENDENT | LG_NODE_POSE_INDEPENDENT,
        .create = pb_create_ref,
        .prepare = pb_prepare,
        .execute = pb_execute,
        .destroy = pb_destroy,
    },
};

LG_PLUGIN_DEFINE("prt_bake", "1.0.0",
                 "Precomputed radiance transfer: the per-vertex bake (Embree visibility, "
                 "interreflections, cached) and its quadrature reference",
                 pb_types)
