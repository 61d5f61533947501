/* Computed vertex normals (gltf_normals.h). */
#include "gltf_normals.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/vecmath.h"
#include "lightgraph/types.h"

/* Above this many triangles around one point, the per-corner neighbourhood sums (quadratic
 * in the count) give way to grouping by seed normals (linear in count x groups). Real
 * meshes stay far below it; a pathological fan must not take hours. */
#define LG_NORMALS_MAX_PAIRWISE 1024

void lg_nmesh_free(lg_nmesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->texcoords);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

static lg_vec3 vget(const float *p, uint32_t i)
{
    return lg_v3(p[3 * (size_t)i], p[3 * (size_t)i + 1], p[3 * (size_t)i + 2]);
}

/* The interior angle between edges a and b (radians, [0, pi]); atan2 stays accurate for
 * angles near 0 and pi where acos of a dot product does not. */
static float corner_angle(lg_vec3 a, lg_vec3 b)
{
    float s = lg_v3_length(lg_v3_cross(a, b)), c = lg_v3_dot(a, b);
    float r = atan2f(s, c);
    return isfinite(r) ? r : 0.0f;
}

/* The unit normal of triangle p (counter-clockwise front), or zero when the triangle is
 * degenerate (zero or non-finite area); *twice_area receives |cross product|. */
static lg_vec3 facet(const lg_vec3 p[3], float *twice_area)
{
    lg_vec3 cr = lg_v3_cross(lg_v3_sub(p[1], p[0]), lg_v3_sub(p[2], p[0]));
    float a = lg_v3_length(cr);
    lg_vec3 n = lg_v3_normalize_or(cr, lg_v3(0, 0, 0));
    bool ok = isfinite(a) && a > 0 && lg_v3_dot(n, n) > 0.5f;
    *twice_area = ok ? a : 0;
    return ok ? n : lg_v3(0, 0, 0);
}

/* Facet unit normals (zero for degenerate triangles) and per-corner weights
 * area x angle (zero for degenerate triangles). */
static void facets(const float *pos, const uint32_t *idx, uint32_t n_tris, float *fn, float *cw)
{
    for (uint32_t t = 0; t < n_tris; t++) {
        lg_vec3 p[3] = { vget(pos, idx[3 * t]), vget(pos, idx[3 * t + 1]),
                         vget(pos, idx[3 * t + 2]) };
        float twice_area;
        lg_vec3 n = facet(p, &twice_area);
        bool ok = twice_area > 0;
        fn[3 * t] = n.x;
        fn[3 * t + 1] = n.y;
        fn[3 * t + 2] = n.z;
        for (int k = 0; k < 3; k++) {
            lg_vec3 a = lg_v3_sub(p[(k + 1) % 3], p[k]), b = lg_v3_sub(p[(k + 2) % 3], p[k]);
            cw[3 * t + k] = ok ? 0.5f * twice_area * corner_angle(a, b) : 0.0f;
        }
    }
}

/* ---- welding: one id per distinct position --------------------------------------------------- */

static uint32_t float_key(float f)
{
    uint32_t u;
    if (f == 0.0f)
        f = 0.0f; /* -0 and +0 are one position */
    memcpy(&u, &f, sizeof u);
    return u;
}

static void position_key(const float *pos, uint32_t v, uint32_t k[3])
{
    for (int i = 0; i < 3; i++)
        k[i] = float_key(pos[3 * (size_t)v + i]);
}

/* weld[v] = a dense id shared by all vertices at v's bit-identical position, numbered in
 * order of first appearance (an open-addressing hash table of vertex ids); returns the id
 * count, or UINT32_MAX when out of memory. */
static uint32_t weld_positions(const float *pos, uint32_t nv, uint32_t *weld)
{
    size_t cap = 16;
    while (cap < 2 * (size_t)nv)
        cap *= 2;
    uint32_t *table = malloc(cap * sizeof *table);
    if (!table)
        return UINT32_MAX;
    memset(table, 0xff, cap * sizeof *table);
    uint32_t ids = 0;
    for (uint32_t v = 0; v < nv; v++) {
        uint32_t k[3];
        position_key(pos, v, k);
        uint64_t h = (k[0] * 0x9e3779b97f4a7c15ull) ^ (k[1] * 0xc2b2ae3d27d4eb4full) ^
                     (k[2] * 0x165667b19e3779f9ull);
        size_t at = (size_t)(h ^ (h >> 29)) & (cap - 1);
        for (;; at = (at + 1) & (cap - 1)) {
            uint32_t o = table[at];
            if (o == UINT32_MAX) {
                table[at] = v;
                weld[v] = ids++;
                break;
            }
            uint32_t ko[3];
            position_key(pos, o, ko);
            if (!memcmp(k, ko, sizeof k)) {
                weld[v] = weld[o];
                break;
            }
        }
    }
    free(table);
    return ids;
}

/* ---- output vertices: one per (source vertex, normal) ---------------------------------------- */

typedef struct builder {
    const float *pos, *uv;
    lg_nmesh *m;
    uint32_t cap;   /* vertices the output arrays hold */
    uint32_t first; /* the capacity of the first allocation */
    uint32_t *head; /* per source vertex: first output vertex made from it, or UINT32_MAX */
    uint32_t *next; /* per output vertex: the next one from the same source */
} builder;

/* Room for one more output vertex; false when out of memory. */
static bool reserve(builder *b)
{
    if (b->m->n_vertices < b->cap)
        return true;
    size_t cap = b->cap ? (size_t)b->cap + b->cap / 2 + 1024 : b->first;
    if (cap > UINT32_MAX)
        cap = UINT32_MAX;
    float *p = realloc(b->m->positions, cap * 3 * sizeof(float));
    if (p)
        b->m->positions = p;
    float *n = realloc(b->m->normals, cap * 3 * sizeof(float));
    if (n)
        b->m->normals = n;
    float *t = b->uv ? realloc(b->m->texcoords, cap * 2 * sizeof(float)) : NULL;
    if (t)
        b->m->texcoords = t;
    uint32_t *x = realloc(b->next, cap * sizeof(uint32_t));
    if (x)
        b->next = x;
    if (!p || !n || (b->uv && !t) || !x)
        return false;
    b->cap = (uint32_t)cap;
    return true;
}

/* The output vertex for source vertex v with normal n: an earlier one with the same
 * normal, or a new one; UINT32_MAX when out of memory. */
static uint32_t emit(builder *b, uint32_t v, const float n[3])
{
    for (uint32_t o = b->head[v]; o != UINT32_MAX; o = b->next[o])
        if (memcmp(b->m->normals + 3 * (size_t)o, n, 3 * sizeof(float)) == 0)
            return o;
    if (!reserve(b))
        return UINT32_MAX;
    uint32_t o = b->m->n_vertices++;
    memcpy(b->m->positions + 3 * (size_t)o, b->pos + 3 * (size_t)v, 3 * sizeof(float));
    memcpy(b->m->normals + 3 * (size_t)o, n, 3 * sizeof(float));
    if (b->uv)
        memcpy(b->m->texcoords + 2 * (size_t)o, b->uv + 2 * (size_t)v, 2 * sizeof(float));
    b->next[o] = b->head[v];
    b->head[v] = o;
    return o;
}

static int alloc_out(lg_nmesh *m, uint32_t max_vertices, uint32_t n_indices, bool uv)
{
    memset(m, 0, sizeof *m);
    size_t nv = max_vertices ? max_vertices : 1;
    m->positions = malloc(nv * 3 * sizeof(float));
    m->normals = malloc(nv * 3 * sizeof(float));
    m->texcoords = uv ? malloc(nv * 2 * sizeof(float)) : NULL;
    m->indices = malloc((n_indices ? n_indices : 1) * sizeof(uint32_t));
    m->n_indices = n_indices;
    if (!m->positions || !m->normals || (uv && !m->texcoords) || !m->indices) {
        lg_nmesh_free(m);
        return LG_ERR_NOMEM;
    }
    return 0;
}

static void unit_or(const double s[3], const float *facet, float out[3])
{
    lg_vec3 fallback = lg_v3(0, 0, 1);
    if (facet && (facet[0] != 0 || facet[1] != 0 || facet[2] != 0))
        fallback = lg_v3(facet[0], facet[1], facet[2]);
    lg_vec3 n = lg_v3_normalize_or(lg_v3((float)s[0], (float)s[1], (float)s[2]), fallback);
    out[0] = n.x;
    out[1] = n.y;
    out[2] = n.z;
}

static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The normals of the corners around one welded point: corner ids c[0..d-1], normals into
 * cn[3 i .. 3 i + 2]. */
static int point_normals(const uint32_t *c, uint32_t d, const float *fn, const float *cw,
                         float cos_crease, float cos_half, float *cn)
{
    double all[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < d; i++) {
        const float *n = fn + 3 * (size_t)(c[i] / 3);
        for (int k = 0; k < 3; k++)
            all[k] += (double)cw[c[i]] * n[k];
    }
    /* Every facet within half the crease angle of the mean: every pair is within the
     * crease angle, so every corner's sum is the full sum. */
    float mean[3];
    unit_or(all, NULL, mean);
    bool one = lg_v3_length(lg_v3((float)all[0], (float)all[1], (float)all[2])) > 0;
    for (uint32_t i = 0; one && i < d; i++) {
        const float *n = fn + 3 * (size_t)(c[i] / 3);
        if ((n[0] != 0 || n[1] != 0 || n[2] != 0) && dot3(n, mean) < cos_half)
            one = false;
    }
    if (one) {
        for (uint32_t i = 0; i < d; i++)
            memcpy(cn + 3 * (size_t)i, mean, sizeof mean);
        return 0;
    }
    if (d <= LG_NORMALS_MAX_PAIRWISE) {
        for (uint32_t i = 0; i < d; i++) {
            const float *nf = fn + 3 * (size_t)(c[i] / 3);
            bool degenerate = nf[0] == 0 && nf[1] == 0 && nf[2] == 0;
            double s[3] = { 0, 0, 0 };
            if (degenerate) {
                memcpy(s, all, sizeof s);
            } else {
                for (uint32_t j = 0; j < d; j++) {
                    const float *ng = fn + 3 * (size_t)(c[j] / 3);
                    if (dot3(nf, ng) >= cos_crease)
                        for (int k = 0; k < 3; k++)
                            s[k] += (double)cw[c[j]] * ng[k];
                }
            }
            unit_or(s, nf, cn + 3 * (size_t)i);
        }
        return 0;
    }
    /* Many triangles at one point: group facets by the first seed normal within the
     * crease angle, one normal per group. */
    uint32_t *group = malloc(d * sizeof *group);
    float *seed = malloc((size_t)d * 3 * sizeof *seed);
    double *sum = calloc((size_t)d * 3, sizeof *sum);
    if (!group || !seed || !sum) {
        free(group);
        free(seed);
        free(sum);
        return LG_ERR_NOMEM;
    }
    uint32_t ng = 0;
    for (uint32_t i = 0; i < d; i++) {
        const float *nf = fn + 3 * (size_t)(c[i] / 3);
        if (nf[0] == 0 && nf[1] == 0 && nf[2] == 0) {
            group[i] = UINT32_MAX;
            continue;
        }
        uint32_t g = 0;
        while (g < ng && dot3(nf, seed + 3 * (size_t)g) < cos_crease)
            g++;
        if (g == ng)
            memcpy(seed + 3 * (size_t)ng++, nf, 3 * sizeof(float));
        group[i] = g;
        for (int k = 0; k < 3; k++)
            sum[3 * (size_t)g + k] += (double)cw[c[i]] * nf[k];
    }
    for (uint32_t i = 0; i < d; i++) {
        const float *nf = fn + 3 * (size_t)(c[i] / 3);
        unit_or(group[i] == UINT32_MAX ? all : sum + 3 * (size_t)group[i], nf, cn + 3 * (size_t)i);
    }
    free(group);
    free(seed);
    free(sum);
    return 0;
}

int lg_normals_smooth(const float *pos, const float *uv, uint32_t nv, const uint32_t *idx,
                      uint32_t ni, float crease_deg, lg_nmesh *out)
{
    memset(out, 0, sizeof *out);
    uint32_t nt = ni / 3, nc = nt * 3;
    float *fn = malloc(((size_t)nt + 1) * 3 * sizeof *fn);
    float *cw = malloc(((size_t)nc + 1) * sizeof *cw);
    uint32_t *weld = malloc(((size_t)nv + 1) * sizeof *weld);
    uint32_t *start = NULL, *corners = NULL, *head = NULL;
    float *cn = NULL;
    /* about as many output vertices as source vertices: the arrays start there and grow */
    builder b = { pos, uv, out, 0, nv + nv / 8 + 64, NULL, NULL };
    int rc = LG_ERR_NOMEM;
    if (!fn || !cw || !weld)
        goto done;
    facets(pos, idx, nt, fn, cw);

    uint32_t np = weld_positions(pos, nv, weld);
    if (np == UINT32_MAX)
        goto done;
    /* corners grouped by welded point (counting sort) */
    start = calloc((size_t)np + 1, sizeof *start);
    corners = malloc(((size_t)nc + 1) * sizeof *corners);
    if (!start || !corners)
        goto done;
    for (uint32_t c = 0; c < nc; c++)
        start[weld[idx[c]] + 1]++;
    uint32_t max_d = 0;
    for (uint32_t p = 0; p < np; p++) {
        max_d = start[p + 1] > max_d ? start[p + 1] : max_d;
        start[p + 1] += start[p];
    }
    for (uint32_t c = 0; c < nc; c++)
        corners[start[weld[idx[c]]]++] = c;
    for (uint32_t p = np; p > 0; p--)
        start[p] = start[p - 1];
    start[0] = 0;

    /* per point: its corners' normals, then their output vertices */
    cn = malloc(((size_t)max_d + 1) * 3 * sizeof *cn);
    head = malloc(((size_t)nv + 1) * sizeof *head);
    out->indices = malloc(((size_t)nc + 1) * sizeof *out->indices);
    out->n_indices = nc;
    if (!cn || !head || !out->indices)
        goto done;
    memset(head, 0xff, ((size_t)nv + 1) * sizeof *head);
    b.head = head;
    double rad = (double)crease_deg * (LG_PI / 180.0);
    float cos_crease = (float)cos(rad), cos_half = (float)cos(rad * 0.5);
    for (uint32_t p = 0; p < np; p++) {
        const uint32_t *c = corners + start[p];
        uint32_t d = start[p + 1] - start[p];
        if ((rc = point_normals(c, d, fn, cw, cos_crease, cos_half, cn)))
            goto done;
        rc = LG_ERR_NOMEM;
        for (uint32_t i = 0; i < d; i++)
            if ((out->indices[c[i]] = emit(&b, idx[c[i]], cn + 3 * (size_t)i)) == UINT32_MAX)
                goto done;
    }
    /* give back what the vertex arrays did not use */
    size_t n = out->n_vertices ? out->n_vertices : 1;
    float *q = realloc(out->positions, n * 3 * sizeof(float));
    out->positions = q ? q : out->positions;
    q = realloc(out->normals, n * 3 * sizeof(float));
    out->normals = q ? q : out->normals;
    q = uv ? realloc(out->texcoords, n * 2 * sizeof(float)) : NULL;
    out->texcoords = q ? q : out->texcoords;
    rc = 0;
done:
    if (rc)
        lg_nmesh_free(out);
    free(fn);
    free(cw);
    free(cn);
    free(weld);
    free(start);
    free(corners);
    free(head);
    free(b.next);
    return rc;
}

int lg_normals_flat(const float *pos, const float *uv, uint32_t nv, const uint32_t *idx,
                    uint32_t ni, lg_nmesh *out)
{
    (void)nv;
    uint32_t nt = ni / 3;
    if (alloc_out(out, nt * 3, nt * 3, uv != NULL))
        return LG_ERR_NOMEM;
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *tri = idx + 3 * (size_t)t;
        lg_vec3 p[3] = { vget(pos, tri[0]), vget(pos, tri[1]), vget(pos, tri[2]) };
        float twice_area;
        lg_vec3 n = facet(p, &twice_area);
        float fn[3] = { n.x, n.y, twice_area > 0 ? n.z : 1 }; /* degenerate: (0, 0, 1) */
        for (int k = 0; k < 3; k++) {
            size_t o = 3 * (size_t)t + k, v = idx[o];
            memcpy(out->positions + 3 * o, pos + 3 * v, 3 * sizeof(float));
            memcpy(out->normals + 3 * o, fn, sizeof fn);
            if (uv)
                memcpy(out->texcoords + 2 * o, uv + 2 * v, 2 * sizeof(float));
            out->indices[o] = (uint32_t)o;
        }
    }
    out->n_vertices = nt * 3;
    return 0;
}
