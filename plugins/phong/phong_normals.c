/* Vertex normals of phong_model.h: seed 1 eq. 1-13, and the crease split that is the
 * remedy for its false smoothing (fig. 1.27). The lighting functions themselves are
 * static inline in the header, so that C callers and the tests compile the same code. */
#include "phong_model.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* Twice a triangle's area below this fraction of its longest edge squared makes it
 * degenerate: its normal would be the direction of rounding noise. */
#define LG_FACET_MIN_RATIO 1e-6

/* Sums of unit normals shorter than this have cancelled: their direction is noise. */
#define LG_SUM_MIN_LENGTH 1e-4

/* Above this many corners around a vertex the crease split groups corners instead of
 * comparing every pair (quadratic); at most this many groups. */
#define LG_CREASE_MAX_PAIRWISE 128
#define LG_CREASE_MAX_GROUPS 64

static void load(const float *pos, uint32_t v, double p[3])
{
    for (int i = 0; i < 3; i++)
        p[i] = pos[3 * (size_t)v + i];
}

/* The unit normal of triangle (a, b, c), counter-clockwise front, computed in double;
 * false for a degenerate triangle (see LG_FACET_MIN_RATIO) or non-finite positions. */
static bool facet_normal(const float *pos, uint32_t a, uint32_t b, uint32_t c, float n[3])
{
    double p0[3], p1[3], p2[3], e1[3], e2[3], e3[3];
    load(pos, a, p0);
    load(pos, b, p1);
    load(pos, c, p2);
    for (int i = 0; i < 3; i++) {
        e1[i] = p1[i] - p0[i];
        e2[i] = p2[i] - p0[i];
        e3[i] = p2[i] - p1[i];
    }
    double cr[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0] };
    double len = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    double l1 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    double l2 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double l3 = e3[0] * e3[0] + e3[1] * e3[1] + e3[2] * e3[2];
    double lmax = fmax(l1, fmax(l2, l3));
    /* written so that NaN fails the test */
    if (!(isfinite(len) && isfinite(lmax) && len > LG_FACET_MIN_RATIO * lmax))
        return false;
    for (int i = 0; i < 3; i++)
        n[i] = (float)(cr[i] / len);
    return true;
}

/* s / |s| into out; false (out untouched) when |s| < LG_SUM_MIN_LENGTH. */
static bool unit_sum(const double s[3], float out[3])
{
    double len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    if (!(len >= LG_SUM_MIN_LENGTH))
        return false;
    for (int i = 0; i < 3; i++)
        out[i] = (float)(s[i] / len);
    return true;
}

int lg_vertex_normals_eq13(const float *pos, uint32_t nv, const uint32_t *idx, uint32_t ni,
                           float *out_normals)
{
    if ((nv && (!pos || !out_normals)) || (ni && !idx))
        return LG_ERR_INVALID;
    int rc = ni % 3 ? LG_ERR_INVALID : LG_OK;
    uint32_t nt = ni / 3;
    /* Sums accumulate in double so that the cancellation test sees real cancellation, not
     * float rounding on high-valence vertices; without memory for them, in out_normals. */
    double *sum = nv ? calloc((size_t)nv * 3, sizeof *sum) : NULL;
    if (nv)
        memset(out_normals, 0, (size_t)nv * 3 * sizeof(float));
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *tri = idx + 3 * (size_t)t;
        if (tri[0] >= nv || tri[1] >= nv || tri[2] >= nv) {
            rc = LG_ERR_INVALID;
            continue;
        }
        float n[3];
        if (!facet_normal(pos, tri[0], tri[1], tri[2], n))
            continue;
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++) {
                if (sum)
                    sum[3 * (size_t)tri[k] + i] += n[i];
                else
                    out_normals[3 * (size_t)tri[k] + i] += n[i];
            }
    }
    /* Normalise; a vertex whose sum cancelled or that has no usable facet is left at
     * exactly zero (a unit vector never is) for the passes below. */
    bool pending = false;
    for (uint32_t v = 0; v < nv; v++) {
        double s[3];
        float *o = out_normals + 3 * (size_t)v;
        for (int i = 0; i < 3; i++)
            s[i] = sum ? sum[3 * (size_t)v + i] : o[i];
        if (!unit_sum(s, o)) {
            o[0] = o[1] = o[2] = 0.0f;
            pending = true;
        }
    }
    free(sum);
    if (!pending)
        return rc;
    /* Cancelled sums: the first usable facet in index order. */
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *tri = idx + 3 * (size_t)t;
        if (tri[0] >= nv || tri[1] >= nv || tri[2] >= nv)
            continue;
        float *o[3] = { out_normals + 3 * (size_t)tri[0], out_normals + 3 * (size_t)tri[1],
                        out_normals + 3 * (size_t)tri[2] };
        bool want = false;
        for (int k = 0; k < 3; k++)
            want = want || (o[k][0] == 0.0f && o[k][1] == 0.0f && o[k][2] == 0.0f);
        float n[3];
        if (!want || !facet_normal(pos, tri[0], tri[1], tri[2], n))
            continue;
        for (int k = 0; k < 3; k++)
            if (o[k][0] == 0.0f && o[k][1] == 0.0f && o[k][2] == 0.0f)
                memcpy(o[k], n, sizeof n);
    }
    /* No usable facet at all. */
    for (uint32_t v = 0; v < nv; v++) {
        float *o = out_normals + 3 * (size_t)v;
        if (o[0] == 0.0f && o[1] == 0.0f && o[2] == 0.0f) {
            o[0] = LG_PHONG_NORMAL_FALLBACK_X;
            o[1] = LG_PHONG_NORMAL_FALLBACK_Y;
            o[2] = LG_PHONG_NORMAL_FALLBACK_Z;
        }
    }
    return rc;
}

static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The normal of corner `self` around one vertex: the normalised sum of the usable facet
 * normals of `corners` within the crease of the corner's own facet (pairwise), or the first
 * of them when the sum cancels. */
static void corner_pairwise(const uint32_t *corners, uint32_t k, uint32_t self, const float *fn,
                            const bool *usable, float thr, float out[3])
{
    const float *own = fn + 3 * (size_t)(corners[self] / 3);
    double s[3] = { 0, 0, 0 };
    const float *first = NULL;
    for (uint32_t j = 0; j < k; j++) {
        uint32_t t = corners[j] / 3;
        if (!usable[t] || !(dot3(own, fn + 3 * (size_t)t) >= thr))
            continue;
        for (int i = 0; i < 3; i++)
            s[i] += fn[3 * (size_t)t + i];
        if (!first)
            first = fn + 3 * (size_t)t;
    }
    if (!unit_sum(s, out))
        memcpy(out, first ? first : own, 3 * sizeof(float));
}

/* High valence: corners join the first group whose seed (first facet) is within the
 * crease, a new group while there is room, or else the group with the closest seed; each
 * takes its group's normalised sum (the seed when it cancels). */
static void corners_grouped(const uint32_t *corners, uint32_t k, const float *fn,
                            const bool *usable, float thr, float *cn)
{
    const float *seed[LG_CREASE_MAX_GROUPS];
    double sum[LG_CREASE_MAX_GROUPS][3];
    uint32_t ng = 0;
    /* first pass: membership and sums; the group of each corner is kept in cn[.][0] as a
     * small integer until the second pass overwrites it with the normal */
    for (uint32_t j = 0; j < k; j++) {
        uint32_t t = corners[j] / 3;
        if (!usable[t])
            continue;
        const float *f = fn + 3 * (size_t)t;
        uint32_t g = UINT32_MAX, best = 0;
        float best_dot = -INFINITY;
        for (uint32_t q = 0; q < ng; q++) {
            float d = dot3(seed[q], f);
            if (d >= thr) {
                g = q;
                break;
            }
            if (d > best_dot) {
                best_dot = d;
                best = q;
            }
        }
        if (g == UINT32_MAX) {
            if (ng < LG_CREASE_MAX_GROUPS) {
                g = ng++;
                seed[g] = f;
                sum[g][0] = sum[g][1] = sum[g][2] = 0;
            } else {
                g = best;
            }
        }
        for (int i = 0; i < 3; i++)
            sum[g][i] += f[i];
        cn[3 * (size_t)corners[j]] = (float)g;
    }
    float gn[LG_CREASE_MAX_GROUPS][3];
    for (uint32_t q = 0; q < ng; q++)
        if (!unit_sum(sum[q], gn[q]))
            memcpy(gn[q], seed[q], sizeof gn[q]);
    for (uint32_t j = 0; j < k; j++) {
        uint32_t t = corners[j] / 3;
        if (!usable[t])
            continue;
        float *o = cn + 3 * (size_t)corners[j];
        memcpy(o, gn[(uint32_t)o[0]], 3 * sizeof(float));
    }
}

int lg_vertex_normals_crease(const float *pos, uint32_t nv, const uint32_t *idx, uint32_t ni,
                             float crease_angle, uint32_t *out_idx, uint32_t *out_src,
                             float *out_normals, uint32_t *out_nv)
{
    if (!out_nv)
        return LG_ERR_INVALID;
    *out_nv = 0;
    if (ni % 3 || (nv && !pos) || (ni && (!idx || !out_idx || !out_src || !out_normals)))
        return LG_ERR_INVALID;
    for (uint32_t c = 0; c < ni; c++)
        if (idx[c] >= nv)
            return LG_ERR_INVALID;
    if (!ni)
        return LG_OK;
    uint32_t nt = ni / 3;
    /* cos(angle) >= cos(crease) - 1e-6: facets exactly at the crease angle, or coplanar
     * with crease 0, are not split by rounding. */
    float thr;
    if (!(crease_angle > 0.0f))
        thr = 1.0f - 1e-6f;
    else if (crease_angle >= LG_PIF)
        thr = -2.0f; /* every pair: eq. 1-13 */
    else
        thr = cosf(crease_angle) - 1e-6f;

    float *fn = malloc((size_t)nt * 3 * sizeof *fn);
    bool *usable = malloc((size_t)nt * sizeof *usable);
    float *smooth = malloc((size_t)nv * 3 * sizeof *smooth);
    uint32_t *start = malloc(((size_t)nv + 1) * sizeof *start);
    uint32_t *corners = malloc((size_t)ni * sizeof *corners);
    float *cn = malloc((size_t)ni * 3 * sizeof *cn);
    uint32_t *head = malloc((size_t)nv * sizeof *head);
    uint32_t *next = malloc((size_t)ni * sizeof *next);
    int rc = LG_ERR_NOMEM;
    if (!fn || !usable || !smooth || !start || !corners || !cn || !head || !next)
        goto done;

    for (uint32_t t = 0; t < nt; t++)
        usable[t] = facet_normal(pos, idx[3 * t], idx[3 * t + 1], idx[3 * t + 2],
                                 fn + 3 * (size_t)t);
    lg_vertex_normals_eq13(pos, nv, idx, ni, smooth); /* input validated: LG_OK */

    /* corners around each vertex, in corner order (counting sort) */
    memset(start, 0, ((size_t)nv + 1) * sizeof *start);
    for (uint32_t c = 0; c < ni; c++)
        start[idx[c] + 1]++;
    for (uint32_t v = 0; v < nv; v++)
        start[v + 1] += start[v];
    for (uint32_t v = 0; v < nv; v++)
        head[v] = start[v]; /* fill cursor, reset below */
    for (uint32_t c = 0; c < ni; c++)
        corners[head[idx[c]]++] = c;

    for (uint32_t v = 0; v < nv; v++) {
        const uint32_t *cv = corners + start[v];
        uint32_t k = start[v + 1] - start[v];
        if (k > LG_CREASE_MAX_PAIRWISE) {
            corners_grouped(cv, k, fn, usable, thr, cn);
        } else {
            for (uint32_t j = 0; j < k; j++)
                if (usable[cv[j] / 3])
                    corner_pairwise(cv, k, j, fn, usable, thr, cn + 3 * (size_t)cv[j]);
        }
        for (uint32_t j = 0; j < k; j++)
            if (!usable[cv[j] / 3])
                memcpy(cn + 3 * (size_t)cv[j], smooth + 3 * (size_t)v, 3 * sizeof(float));
    }

    /* one output vertex per (input vertex, bit-identical normal) */
    uint32_t n_out = 0;
    for (uint32_t v = 0; v < nv; v++) {
        head[v] = UINT32_MAX;
        for (uint32_t j = start[v]; j < start[v + 1]; j++) {
            uint32_t c = corners[j];
            const float *n = cn + 3 * (size_t)c;
            uint32_t o = head[v];
            while (o != UINT32_MAX && memcmp(out_normals + 3 * (size_t)o, n, 3 * sizeof(float)))
                o = next[o];
            if (o == UINT32_MAX) {
                o = n_out++;
                memcpy(out_normals + 3 * (size_t)o, n, 3 * sizeof(float));
                out_src[o] = v;
                next[o] = head[v];
                head[v] = o;
            }
            out_idx[c] = o;
        }
    }
    *out_nv = n_out;
    rc = LG_OK;
done:
    free(fn);
    free(usable);
    free(smooth);
    free(start);
    free(corners);
    free(cn);
    free(head);
    free(next);
    return rc;
}
