/*
 * gltf_tangents.c: tangents for normal mapping (gltf_tangents.h).
 *
 * Written from the description in Mikkelsen's thesis (2008) and the glTF specification,
 * not from the reference implementation: the per-triangle frame from the texture
 * coordinate derivatives, its projection into each corner's normal plane, angle weighting,
 * grouping of corners per welded vertex and handedness, and the split of vertices whose
 * corners disagree in handedness. Mikkelsen's code further separates groups of one vertex
 * that are not connected through shared edges; here all corners of one welded vertex and
 * one handedness share the tangent, which is the same on every closed manifold and differs
 * only where a vertex joins separate sheets (README.md, "Tangents", has the measured angle
 * against a file's exported MikkTSpace tangents).
 */
#include "gltf_tangents.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/plugin.h" /* LG_ERR_NOMEM */
#include "lightgraph/vecmath.h"

static lg_vec3 get3(const float *a, uint32_t i)
{
    return lg_v3(a[3 * (size_t)i], a[3 * (size_t)i + 1], a[3 * (size_t)i + 2]);
}

/* A unit vector orthogonal to unit n (the axis least aligned with n, made orthogonal). */
static lg_vec3 any_orthogonal(lg_vec3 n)
{
    lg_vec3 a = fabsf(n.x) < 0.57f   ? lg_v3(1, 0, 0)
                : fabsf(n.y) < 0.57f ? lg_v3(0, 1, 0)
                                     : lg_v3(0, 0, 1);
    lg_vec3 t = lg_v3_sub(a, lg_v3_scale(n, lg_v3_dot(n, a)));
    return lg_v3_normalize_or(t, lg_v3(1, 0, 0));
}

/* v made orthogonal to unit n and unit; `fallback` when nothing is left of it. */
static lg_vec3 orthonormal(lg_vec3 v, lg_vec3 n)
{
    lg_vec3 t = lg_v3_sub(v, lg_v3_scale(n, lg_v3_dot(n, v)));
    float len = lg_v3_length(t);
    return len > 1e-20f && isfinite(len) ? lg_v3_scale(t, 1.0f / len) : any_orthogonal(n);
}

void lg_tangents_orthonormalize(float *tan, const float *normals, uint32_t nv)
{
    for (uint32_t v = 0; v < nv; v++) {
        float *t = tan + 4 * (size_t)v;
        lg_vec3 n = get3(normals, v);
        lg_vec3 o = orthonormal(lg_v3(t[0], t[1], t[2]), n);
        t[0] = o.x, t[1] = o.y, t[2] = o.z;
        t[3] = t[3] < 0 ? -1.0f : 1.0f;
    }
}

/* ---- welding: vertices equal in position, normal and texture coordinates --------------------- */

static uint64_t hash_bytes(const void *p, size_t n)
{
    const uint8_t *b = p;
    uint64_t h = 0xcbf29ce484222325ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h ^ (h >> 29);
}

/* weld[v] = the first vertex with v's key (8 floats, compared bit for bit). */
static bool weld_vertices(const float *pos, const float *nrm, const float *uv, uint32_t nv,
                          uint32_t *weld)
{
    size_t cap = 16;
    while (cap < (size_t)nv * 2)
        cap *= 2;
    uint32_t *table = malloc(cap * sizeof *table);
    if (!table)
        return false;
    memset(table, 0xff, cap * sizeof *table);
    for (uint32_t v = 0; v < nv; v++) {
        float key[8];
        memcpy(key, pos + 3 * (size_t)v, 3 * sizeof(float));
        memcpy(key + 3, nrm + 3 * (size_t)v, 3 * sizeof(float));
        memcpy(key + 6, uv + 2 * (size_t)v, 2 * sizeof(float));
        size_t at = hash_bytes(key, sizeof key) & (cap - 1);
        for (;;) {
            uint32_t o = table[at];
            if (o == UINT32_MAX) {
                table[at] = v;
                weld[v] = v;
                break;
            }
            if (!memcmp(pos + 3 * (size_t)o, key, 3 * sizeof(float)) &&
                !memcmp(nrm + 3 * (size_t)o, key + 3, 3 * sizeof(float)) &&
                !memcmp(uv + 2 * (size_t)o, key + 6, 2 * sizeof(float))) {
                weld[v] = o;
                break;
            }
            at = (at + 1) & (cap - 1);
        }
    }
    free(table);
    return true;
}

/* ---- generation ------------------------------------------------------------------------------ */

static bool grow_floats(float **a, size_t n)
{
    float *p = realloc(*a, (n ? n : 1) * sizeof(float));
    if (!p)
        return false;
    *a = p;
    return true;
}

int lg_tangents_generate(lg_nmesh *m, float **texcoords1, int uv_set, float **tangents,
                         uint32_t *n_split)
{
    *tangents = NULL;
    if (n_split)
        *n_split = 0;
    const float *uv = uv_set == 1 ? *texcoords1 : m->texcoords;
    uint32_t nv = m->n_vertices, nc = m->n_indices, nt = nc / 3;
    const float *pos = m->positions, *nrm = m->normals;
    const uint32_t *idx = m->indices;
    int rc = LG_ERR_NOMEM;
    uint32_t *weld = malloc(((size_t)nv + 1) * sizeof *weld);
    float *frame = malloc(((size_t)nt + 1) * 6 * sizeof *frame); /* per triangle T, B */
    int8_t *side = malloc((size_t)nc + 1);                       /* per corner: +1, -1, 0 */
    double *acc = calloc(((size_t)nv + 1) * 6, sizeof *acc);     /* per welded vertex x side */
    uint8_t *sides = calloc((size_t)nv + 1, 1);                  /* per vertex: bit 0 +, 1 - */
    uint32_t *second = malloc(((size_t)nv + 1) * sizeof *second);
    float *tan = NULL;
    if (!weld || !frame || !side || !acc || !sides || !second ||
        !weld_vertices(pos, nrm, uv, nv, weld))
        goto done;

    /* the triangles' frames: T along +u, B along +v, from the uv derivatives */
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *c = idx + 3 * (size_t)t;
        lg_vec3 e1 = lg_v3_sub(get3(pos, c[1]), get3(pos, c[0]));
        lg_vec3 e2 = lg_v3_sub(get3(pos, c[2]), get3(pos, c[0]));
        float du1 = uv[2 * c[1]] - uv[2 * c[0]], dv1 = uv[2 * c[1] + 1] - uv[2 * c[0] + 1];
        float du2 = uv[2 * c[2]] - uv[2 * c[0]], dv2 = uv[2 * c[2] + 1] - uv[2 * c[0] + 1];
        float det = du1 * dv2 - du2 * dv1;
        /* (dp/du, dp/dv) = ((dv2 e1 - dv1 e2), (du1 e2 - du2 e1)) / det: only the
         * directions matter, so the division becomes det's sign */
        lg_vec3 T = lg_v3_sub(lg_v3_scale(e1, dv2), lg_v3_scale(e2, dv1));
        lg_vec3 B = lg_v3_sub(lg_v3_scale(e2, du1), lg_v3_scale(e1, du2));
        float s = det > 0 ? 1.0f : -1.0f;
        bool ok = det != 0 && isfinite(det) && lg_v3_length(T) > 0 && lg_v3_length(B) > 0;
        T = ok ? lg_v3_normalize_or(lg_v3_scale(T, s), lg_v3(0, 0, 0)) : lg_v3(0, 0, 0);
        B = ok ? lg_v3_normalize_or(lg_v3_scale(B, s), lg_v3(0, 0, 0)) : lg_v3(0, 0, 0);
        float *f = frame + 6 * (size_t)t;
        f[0] = T.x, f[1] = T.y, f[2] = T.z, f[3] = B.x, f[4] = B.y, f[5] = B.z;
        /* each corner's handedness: which side of N x T the bitangent lies on, with the
         * corner's own normal (robust to windings that disagree with the normals). glTF's
         * bitangent points up in the image, +Y of its normal textures: along decreasing v
         * (v grows downwards), so against B = dp/dv */
        for (int k = 0; k < 3; k++) {
            lg_vec3 n = get3(nrm, c[k]);
            float d = -lg_v3_dot(lg_v3_cross(n, T), B);
            side[3 * (size_t)t + k] = !ok || d == 0 ? 0 : d > 0 ? 1 : -1;
            if (side[3 * (size_t)t + k])
                sides[weld[c[k]]] |= side[3 * (size_t)t + k] > 0 ? 1 : 2;
        }
    }
    /* degenerate corners join their welded vertex's handedness (+ when it has both) */
    for (uint32_t c = 0; c < nc; c++)
        if (!side[c])
            side[c] = (sides[weld[idx[c]]] & 1) || !sides[weld[idx[c]]] ? 1 : -1;
    memset(sides, 0, (size_t)nv + 1);
    for (uint32_t c = 0; c < nc; c++)
        sides[idx[c]] |= side[c] > 0 ? 1 : 2;

    /* angle-weighted sums of the projected triangle tangents, per welded vertex and side */
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *c = idx + 3 * (size_t)t;
        const float *f = frame + 6 * (size_t)t;
        lg_vec3 T = lg_v3(f[0], f[1], f[2]);
        if (lg_v3_dot(T, T) == 0)
            continue;
        for (int k = 0; k < 3; k++) {
            lg_vec3 n = get3(nrm, c[k]), p = get3(pos, c[k]);
            /* the corner's angle, between its two edges projected into its normal plane */
            lg_vec3 a = lg_v3_sub(get3(pos, c[(k + 1) % 3]), p);
            lg_vec3 b = lg_v3_sub(get3(pos, c[(k + 2) % 3]), p);
            a = lg_v3_sub(a, lg_v3_scale(n, lg_v3_dot(n, a)));
            b = lg_v3_sub(b, lg_v3_scale(n, lg_v3_dot(n, b)));
            float la = lg_v3_length(a), lb = lg_v3_length(b);
            if (!(la > 0 && lb > 0))
                continue;
            float cosa = lg_v3_dot(a, b) / (la * lb);
            float angle = acosf(cosa < -1 ? -1 : cosa > 1 ? 1 : cosa);
            lg_vec3 tp = lg_v3_sub(T, lg_v3_scale(n, lg_v3_dot(n, T)));
            float lt = lg_v3_length(tp);
            if (!(lt > 0) || !isfinite(angle))
                continue;
            tp = lg_v3_scale(tp, angle / lt);
            double *s = acc + 6 * (size_t)weld[c[k]] + (side[3 * (size_t)t + k] > 0 ? 0 : 3);
            s[0] += tp.x, s[1] += tp.y, s[2] += tp.z;
        }
    }

    /* vertices with corners of both sides get a second vertex for the - side */
    uint32_t n_new = nv;
    for (uint32_t v = 0; v < nv; v++)
        second[v] = sides[v] == 3 ? n_new++ : v;
    if (n_new != nv) {
        if (!grow_floats(&m->positions, (size_t)n_new * 3) ||
            !grow_floats(&m->normals, (size_t)n_new * 3) ||
            (m->texcoords && !grow_floats(&m->texcoords, (size_t)n_new * 2)) ||
            (*texcoords1 && !grow_floats(texcoords1, (size_t)n_new * 2)))
            goto done; /* the arrays that grew keep their first nv vertices: unchanged */
        pos = m->positions, nrm = m->normals;
        for (uint32_t v = 0; v < nv; v++) {
            uint32_t o = second[v];
            if (o == v)
                continue;
            memcpy(m->positions + 3 * (size_t)o, m->positions + 3 * (size_t)v, 3 * sizeof(float));
            memcpy(m->normals + 3 * (size_t)o, m->normals + 3 * (size_t)v, 3 * sizeof(float));
            if (m->texcoords)
                memcpy(m->texcoords + 2 * (size_t)o, m->texcoords + 2 * (size_t)v,
                       2 * sizeof(float));
            if (*texcoords1)
                memcpy(*texcoords1 + 2 * (size_t)o, *texcoords1 + 2 * (size_t)v, 2 * sizeof(float));
        }
    }
    tan = malloc(((size_t)n_new + 1) * 4 * sizeof *tan);
    if (!tan)
        goto done;
    /* each vertex (and its copy) takes its welded vertex's sum for its side */
    for (uint32_t v = 0; v < nv; v++) {
        for (int s = 0; s < 2; s++) {
            if (!(sides[v] & (1 << s)) && !(s == 0 && !sides[v]))
                continue;
            uint32_t o = s == 1 && sides[v] == 3 ? second[v] : v;
            const double *a = acc + 6 * (size_t)weld[v] + 3 * s;
            lg_vec3 n = get3(nrm, v);
            lg_vec3 t = orthonormal(lg_v3((float)a[0], (float)a[1], (float)a[2]), n);
            float *out = tan + 4 * (size_t)o;
            out[0] = t.x, out[1] = t.y, out[2] = t.z;
            out[3] = s == 0 ? 1.0f : -1.0f;
        }
    }
    if (n_new != nv)
        for (uint32_t c = 0; c < nc; c++)
            if (side[c] < 0)
                m->indices[c] = second[m->indices[c]];
    m->n_vertices = n_new;
    *tangents = tan;
    tan = NULL;
    if (n_split)
        *n_split = n_new - nv;
    rc = 0;
done:
    free(tan);
    free(weld);
    free(frame);
    free(side);
    free(acc);
    free(sides);
    free(second);
    return rc;
}
