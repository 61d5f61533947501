/* lightgraph/probe.h: lg_probe_resample, area-weighted resampling between probe layouts.
 *
 * Each destination texel is split into kx x ky sub-rectangles in its own (u, v); each
 * sub-rectangle carries its own solid angle (exact closed forms for lat-long and cube; the
 * angular map's Jacobian at the sub-rectangle's centre times its area, rescaled so that
 * the texel's sub-weights sum to its exact solid angle). kx and ky follow the ratio of the
 * destination texel's extent to the source texel's local extent (both in radians, where
 * the texel lands), so every sub-rectangle is smaller than a source texel by the
 * oversampling factor. A sub-rectangle's solid angle goes to the source texels under the
 * bounding box of its corners' images (box_split), which gives a sparse matrix of
 * overlaps; balancing it (Sinkhorn) to the exact solid angles of both layouts makes every
 * source texel hand out exactly its solid angle. A destination texel's value is the
 * weighted mean of its row: a constant stays that constant. docs/probes.md "Resampling"
 * has the measurements. */
#include "lightgraph/probe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double cube_area(double x, double y)
{
    return atan2(x * y, sqrt(x * x + y * y + 1.0));
}

/* The angular map's Jacobian (steradians per unit area of the (a, b) plane, a and b in
 * [-1, 1]): pi sin(pi r) / r, its limit pi^2 at the centre; 0 outside the disc. */
static double angular_jacobian(double a, double b)
{
    double r = sqrt(a * a + b * b);
    if (r >= 1)
        return 0;
    if (r < 1e-6)
        return LG_PI * LG_PI;
    return LG_PI * sin(LG_PI * r) / r;
}

/* The extents (radians) of a texel of layout l, size w x h, along its u and v axes, at
 * face coordinates (u, v): local, first order. */
static void texel_extent(lg_probe_layout l, uint32_t w, uint32_t h, double u, double v, double *eu,
                         double *ev)
{
    if (l == LG_PROBE_LATLONG) {
        double theta = LG_PI * v;
        *eu = 2 * LG_PI / w * sin(theta);
        *ev = LG_PI / h;
    } else if (l == LG_PROBE_CUBE) {
        /* on the plane at distance 1, a step dx at (x, y) subtends dx sqrt(1 + y^2) /
         * (1 + x^2 + y^2) */
        double x = 2 * u - 1, y = 2 * v - 1, L2 = 1 + x * x + y * y;
        *eu = 2.0 / w * sqrt(1 + y * y) / L2;
        *ev = 2.0 / h * sqrt(1 + x * x) / L2;
    } else {
        /* radially pi per unit of r, tangentially sin(pi r) / r per unit; clamp r to the
         * disc */
        double a = 2 * u - 1, b = 1 - 2 * v, r = sqrt(a * a + b * b);
        double t = r >= 1 ? 0 : r < 1e-6 ? LG_PI : sin(LG_PI * r) / r;
        double cr = r > 0 ? fabs(a) / r : 1, sr = r > 0 ? fabs(b) / r : 0;
        /* a step along u (the a axis) is cr radial and sr tangential */
        *eu = 2.0 / w * sqrt(cr * cr * LG_PI * LG_PI + sr * sr * t * t);
        *ev = 2.0 / h * sqrt(sr * sr * LG_PI * LG_PI + cr * cr * t * t);
    }
}

/* The source's nearest texel for a direction in its own frame: the texel containing the
 * direction (lg_probe_lookup's nearest rule). */
static size_t source_index(const lg_probe_image *src, lg_vec3 d)
{
    lg_probe_coord c = lg_probe_dir_to_coord(src->layout, d);
    int64_t i = (int64_t)floorf(c.u * (float)src->width);
    int64_t j = (int64_t)floorf(c.v * (float)src->height);
    if (src->layout == LG_PROBE_LATLONG) {
        i %= (int64_t)src->width;
        if (i < 0)
            i += src->width;
    } else {
        i = i < 0 ? 0 : i >= (int64_t)src->width ? (int64_t)src->width - 1 : i;
    }
    j = j < 0 ? 0 : j >= (int64_t)src->height ? (int64_t)src->height - 1 : j;
    return ((size_t)c.face * src->height + (size_t)j) * src->width + (size_t)i;
}

static bool valid(lg_probe_layout l, uint32_t w, uint32_t h)
{
    if (w == 0 || h == 0 || w > 65536 || h > 65536)
        return false;
    if (l == LG_PROBE_CUBE)
        return w == h;
    return l == LG_PROBE_LATLONG || l == LG_PROBE_ANGULAR;
}

/* The sparse overlap matrix: for each destination texel (a row), the source texels its
 * sub-rectangles read and the solid angle each received. */
#define LUT_BITS 12
#define LUT_SIZE (1u << LUT_BITS)

typedef struct overlap {
    size_t *row;   /* rows + 1 offsets */
    uint32_t *src; /* source texel per entry */
    double *w;     /* steradians per entry (double: the balancing runs to 1e-9) */
    size_t n, cap;
    /* the current row's source texels -> entries: a small open-addressing table, emptied
     * per row by a generation count (rows near a lat-long pole gather thousands of
     * entries, where a linear search would dominate) */
    uint32_t lut_key[LUT_SIZE], lut_gen[LUT_SIZE];
    size_t lut_val[LUT_SIZE];
    uint32_t gen;
    size_t row_start;
} overlap;

static void overlap_row(overlap *m)
{
    m->row_start = m->n;
    if (++m->gen == 0) {
        memset(m->lut_gen, 0, sizeof m->lut_gen);
        m->gen = 1;
    }
}

static bool overlap_push(overlap *m, uint32_t s, double w)
{
    size_t len = m->n - m->row_start;
    uint32_t h = 0;
    if (len < LUT_SIZE / 2) {
        h = (uint32_t)(s * 2654435761u) >> (32 - LUT_BITS);
        while (m->lut_gen[h] == m->gen) {
            if (m->lut_key[h] == s) {
                m->w[m->lut_val[h]] += w;
                return true;
            }
            h = (h + 1) & (LUT_SIZE - 1);
        }
    } else {
        for (size_t e = m->row_start; e < m->n; e++)
            if (m->src[e] == s) {
                m->w[e] += w;
                return true;
            }
    }
    if (m->n == m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 1024;
        uint32_t *ns = realloc(m->src, cap * sizeof *ns);
        if (!ns)
            return false;
        m->src = ns;
        double *nw = realloc(m->w, cap * sizeof *nw);
        if (!nw)
            return false;
        m->w = nw;
        m->cap = cap;
    }
    if (len < LUT_SIZE / 2) {
        m->lut_gen[h] = m->gen;
        m->lut_key[h] = s;
        m->lut_val[h] = m->n;
    }
    /* past LUT_SIZE / 2 entries the row is searched linearly (which also finds the
     * entries the table holds) */
    m->src[m->n] = s;
    m->w[m->n] = w;
    m->n++;
    return true;
}

/* Relative error of an image's integral when source texel s counts with area[s] instead
 * of omega[s] (largest of R, G, B). */
static double integral_error(const lg_probe_image *src, size_t n, const double *area,
                             const float *omega, double *area_error)
{
    double dev = 0, tot[3] = { 0, 0, 0 }, err[3] = { 0, 0, 0 }, worst = 0;
    for (size_t s = 0; s < n; s++) {
        double e = area[s] - omega[s];
        dev += fabs(e);
        for (int k = 0; k < 3; k++) {
            tot[k] += (double)src->rgba[4 * s + k] * omega[s];
            err[k] += (double)src->rgba[4 * s + k] * e;
        }
    }
    for (int k = 0; k < 3; k++)
        worst = fmax(worst, tot[k] != 0 ? fabs(err[k] / tot[k]) : fabs(err[k]));
    *area_error = dev / (4 * LG_PI);
    return worst;
}

/* Hands a sub-rectangle's solid angle w to the source texels under it. Its footprint in
 * the source's texel coordinates is approximated by the bounding box of its four
 * corners' images (c: the corner grid at the sub-rectangle's top-left corner, `stride`
 * corners per row) and w is split by the box's overlap with each texel: a continuous
 * ramp across a texel boundary instead of the step of a point sample, so that the
 * coverage errors of neighbouring sub-rectangles cancel to second order. Where the
 * corners do not share the centre's cube face, the box straddles a lat-long pole or
 * spans more than 4 texels, the texel under the centre direction d takes all of w. */
static bool box_split(const lg_probe_image *src, const double *c, uint32_t stride,
                      lg_probe_layout layout, lg_probe_coord centre, const float *rotation,
                      double w, overlap *m)
{
    const double *k4[4] = { c, c + 3, c + 3 * stride, c + 3 * stride + 3 };
    uint32_t face = (uint32_t)k4[0][0];
    double W = src->width, H = src->height;
    double xr = k4[0][1]; /* lat-long: unwrap the corners next to the first */
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    bool ok = true;
    for (int k = 0; k < 4; k++) {
        if ((uint32_t)k4[k][0] != face) {
            ok = false;
            break;
        }
        double x = k4[k][1], y = k4[k][2];
        if (src->layout == LG_PROBE_LATLONG) {
            while (x - xr > 0.5 * W)
                x -= W;
            while (xr - x > 0.5 * W)
                x += W;
        }
        x0 = fmin(x0, x);
        x1 = fmax(x1, x);
        y0 = fmin(y0, y);
        y1 = fmax(y1, y);
    }
    if (ok && (x1 - x0 > 4 || y1 - y0 > 4 || y0 < 0 || y1 > H ||
               (src->layout != LG_PROBE_LATLONG && (x0 < 0 || x1 > W))))
        ok = false;
    if (!ok || !(x1 > x0) || !(y1 > y0)) {
        lg_vec3 d = lg_probe_to_world(rotation, lg_probe_coord_to_dir(layout, centre));
        size_t s0 = source_index(src, lg_probe_from_world(src->rotation, d));
        return overlap_push(m, (uint32_t)s0, w);
    }
    double ix = 1 / (x1 - x0), iy = 1 / (y1 - y0);
    for (double cy = floor(y0); cy < y1; cy += 1) {
        double fy = (fmin(y1, cy + 1) - fmax(y0, cy)) * iy;
        uint32_t jj = cy < 0 ? 0 : cy >= H ? (uint32_t)H - 1 : (uint32_t)cy;
        for (double cx = floor(x0); cx < x1; cx += 1) {
            double fx = (fmin(x1, cx + 1) - fmax(x0, cx)) * ix;
            int64_t ii = (int64_t)cx;
            if (src->layout == LG_PROBE_LATLONG) {
                ii %= (int64_t)src->width;
                if (ii < 0)
                    ii += src->width;
            } else {
                ii = ii < 0 ? 0 : ii >= (int64_t)src->width ? (int64_t)src->width - 1 : ii;
            }
            size_t s = ((size_t)face * src->height + jj) * src->width + (size_t)ii;
            double ws = w * fx * fy;
            if (!(ws > 0))
                continue;
            if (!overlap_push(m, (uint32_t)s, ws))
                return false;
        }
    }
    return true;
}

/* Source texels no sub-rectangle read (lat-long slivers at the poles, angular rim
 * slivers, when max_subdiv caps the subdivision): each joins the destination texel that
 * holds its centre's direction with its exact solid angle, so that its energy is kept
 * (the balancing then makes room for it). Rebuilds the matrix with those entries. */
static bool add_unread(const lg_probe_image *src, lg_probe_layout layout, uint32_t width,
                       uint32_t height, const float *rotation, const float *omega, double *area,
                       const double *rows, overlap *m, size_t dst_n)
{
    size_t src_n = (size_t)src->width * src->height * (src->layout == LG_PROBE_CUBE ? 6 : 1);
    size_t *extra = calloc(dst_n + 1, sizeof *extra);
    size_t *dst_of = malloc(src_n * sizeof *dst_of);
    if (!extra || !dst_of) {
        free(extra);
        free(dst_of);
        return false;
    }
    size_t added = 0;
    for (size_t s = 0; s < src_n; s++) {
        dst_of[s] = SIZE_MAX;
        if (!(omega[s] > 0) || area[s] != 0)
            continue;
        uint32_t i = (uint32_t)(s % src->width), j = (uint32_t)(s / src->width % src->height);
        uint32_t f = (uint32_t)(s / ((size_t)src->width * src->height));
        lg_vec3 d = lg_probe_to_world(src->rotation, lg_probe_texel_dir(src->layout, src->width,
                                                                        src->height, f, i, j));
        lg_probe_image di = { layout, width, height, NULL, NULL, { 0 } };
        size_t t = source_index(&di, lg_probe_from_world(rotation, d));
        if (!(rows[t] > 0))
            continue;
        dst_of[s] = t;
        extra[t]++;
        added++;
    }
    size_t n = m->n + added;
    uint32_t *ns = malloc(n * sizeof *ns);
    double *nw = malloc(n * sizeof *nw);
    if (!ns || !nw) {
        free(ns);
        free(nw);
        free(extra);
        free(dst_of);
        return false;
    }
    size_t *nrow = malloc((dst_n + 1) * sizeof *nrow);
    if (!nrow) {
        free(ns);
        free(nw);
        free(extra);
        free(dst_of);
        return false;
    }
    /* each row: its old entries, then its extras */
    size_t at = 0;
    for (size_t t = 0; t < dst_n; t++) {
        size_t len = m->row[t + 1] - m->row[t];
        memcpy(ns + at, m->src + m->row[t], len * sizeof *ns);
        memcpy(nw + at, m->w + m->row[t], len * sizeof *nw);
        nrow[t] = at;
        at += len;
        size_t cnt = extra[t];
        extra[t] = at; /* the cursor of its extras */
        at += cnt;
    }
    nrow[dst_n] = at;
    for (size_t s = 0; s < src_n; s++)
        if (dst_of[s] != SIZE_MAX) {
            size_t e = extra[dst_of[s]]++;
            ns[e] = (uint32_t)s;
            nw[e] = omega[s];
            area[s] += omega[s];
        }
    free(m->src);
    free(m->w);
    free(m->row);
    m->src = ns;
    m->w = nw;
    m->row = nrow;
    m->n = m->cap = n;
    free(extra);
    free(dst_of);
    return true;
}

/* ---- the driver ------------------------------------------------------------------------------ */

/* Runs fn over [0, n) in chunks of `grain` on the pool of node `pool`, or on this thread
 * in chunk order when pool is NULL. The chunks are the same either way, and every chunk
 * writes only what it owns, so the result does not depend on the thread count. */
static int run_chunks(lg_node *pool, size_t n, size_t grain,
                      void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk), void *ctx)
{
    if (pool)
        return lg_parallel_for(pool, n, grain, fn, ctx) ? LG_ERR_INVALID : 0;
    for (size_t c = 0; c * grain < n; c++)
        fn(ctx, c * grain, c * grain + grain < n ? c * grain + grain : n, (uint32_t)c);
    return 0;
}

typedef struct rs_ctx {
    const lg_probe_image *src;
    lg_probe_image rd; /* the source without its rotation (bilinear lookups) */
    const float *src_rot;
    lg_probe_layout layout;
    uint32_t width, height;
    const float *rotation;
    bool box;
    double q;
    uint32_t kmax;
    float *out;
    double *rows;      /* destination texels' solid angles (row sums) */
    size_t *row;       /* the matrix's row offsets (chunk-local until merged) */
    overlap **chunk_m; /* the matrix, per chunk of destination rows */
    uint64_t *chunk_samples;
    uint32_t *chunk_k;
    int *chunk_rc;
    /* balancing and the result */
    overlap *m; /* the merged matrix */
    const double *colsum;
    const double *factor; /* the column step's factor per source texel */
    const float *omega;
    size_t dst_n;
} rs_ctx;

/* One destination texel (t = (f, j, i)): its sub-rectangles into the matrix (box) or its
 * bilinear mean into out. False when out of memory. */
static bool build_texel(rs_ctx *x, overlap *m, double *wu, uint32_t f, uint32_t j, uint32_t i,
                        uint64_t *samples, uint32_t *kseen)
{
    const lg_probe_image *src = x->src;
    lg_probe_layout layout = x->layout;
    uint32_t width = x->width, height = x->height, kmax = x->kmax;
    const float *rotation = x->rotation, *src_rot = x->src_rot;
    bool box = x->box;
    double q = x->q;
    double *corner = wu + 2 * kmax;                         /* (kmax + 1)^2 cube corner areas */
    double *sco = corner + (size_t)(kmax + 1) * (kmax + 1); /* their source coordinates */
    size_t t = ((size_t)f * height + j) * width + i;
    float *o = x->out + 4 * t;
    if (box) {
        x->row[t] = m->n;
        overlap_row(m);
        x->rows[t] = 0;
    }
    o[0] = o[1] = o[2] = o[3] = 0;
    double uc = (i + 0.5) / width, vc = (j + 0.5) / height;
    lg_probe_coord cc = { f, (float)uc, (float)vc };
    if (layout == LG_PROBE_ANGULAR) {
        /* a texel wholly outside the disc: no sphere, value 0 */
        double x0 = 2.0 * i / width - 1, x1 = 2.0 * (i + 1) / width - 1;
        double y1 = 1 - 2.0 * j / height, y0 = 1 - 2.0 * (j + 1) / height;
        double nx = x0 > 0 ? x0 : x1 < 0 ? x1 : 0;
        double ny = y0 > 0 ? y0 : y1 < 0 ? y1 : 0;
        if (nx * nx + ny * ny >= 1)
            return true;
    }
    /* subdivision: destination extent over the source's local extent */
    double deu, dev, seu, sev;
    texel_extent(layout, width, height, uc, vc, &deu, &dev);
    if (layout == LG_PROBE_LATLONG) {
        /* the texel's widest row, not its centre's */
        double t0 = LG_PI * j / height, t1 = LG_PI * (j + 1) / height;
        double smax = (t0 <= LG_PI / 2 && t1 >= LG_PI / 2) ? 1 : fmax(sin(t0), sin(t1));
        deu = 2 * LG_PI / width * smax;
    } else if (layout == LG_PROBE_ANGULAR) {
        deu = dev = 2.0 * LG_PI / (width < height ? width : height);
    }
    lg_vec3 dc = lg_probe_to_world(rotation, lg_probe_coord_to_dir(layout, cc));
    dc = lg_probe_from_world(src_rot, dc);
    lg_probe_coord sc = lg_probe_dir_to_coord(src->layout, dc);
    texel_extent(src->layout, src->width, src->height, sc.u, sc.v, &seu, &sev);
    double smin = fmin(seu, sev);
    if (src->layout == LG_PROBE_LATLONG) {
        /* near a pole the source texels narrow within the destination texel */
        double th = LG_PI * sc.v, half = 0.5 * fmax(deu, dev);
        double s = fmin(sin(fmax(th - half, 0)), sin(fmin(th + half, LG_PI)));
        smin = fmin(smin, 2 * LG_PI / src->width * fmax(s, 0));
    }
    double ku = smin > 0 ? ceil(q * deu / smin) : kmax;
    double kv = smin > 0 ? ceil(q * dev / smin) : kmax;
    uint32_t kx = ku < 1 ? 1 : ku > kmax ? kmax : (uint32_t)ku;
    uint32_t ky = kv < 1 ? 1 : kv > kmax ? kmax : (uint32_t)kv;
    if (kx > *kseen)
        *kseen = kx;
    if (ky > *kseen)
        *kseen = ky;

    /* sub-rectangle weights */
    double scale = 1, cell = 4.0 / ((double)width * height * kx * ky);
    if (layout == LG_PROBE_CUBE) {
        for (uint32_t b = 0; b <= ky; b++) {
            double y = 2.0 * (j + (double)b / ky) / height - 1;
            for (uint32_t a = 0; a <= kx; a++) {
                double xx = 2.0 * (i + (double)a / kx) / width - 1;
                corner[(size_t)b * (kx + 1) + a] = cube_area(xx, y);
            }
        }
    } else if (layout == LG_PROBE_LATLONG) {
        for (uint32_t b = 0; b < ky; b++) {
            double t0 = LG_PI * (j + (double)b / ky) / height;
            double t1 = LG_PI * (j + (double)(b + 1) / ky) / height;
            /* (2 pi / W kx) (cos t0 - cos t1), without cancellation */
            wu[b] = 2 * LG_PI / ((double)width * kx) * 2 * sin(0.5 * (t0 + t1)) *
                    sin(0.5 * (t1 - t0));
        }
    } else {
        double exact = lg_probe_texel_solid_angle(layout, width, height, 0, i, j);
        double sum = 0;
        for (uint32_t b = 0; b < ky; b++)
            for (uint32_t a = 0; a < kx; a++)
                sum += angular_jacobian(2.0 * (i + (a + 0.5) / kx) / width - 1,
                                        1 - 2.0 * (j + (b + 0.5) / ky) / height);
        sum *= cell;
        /* a rim texel whose sub-centres all fall outside the disc: one sample at the
         * disc's point nearest the texel centre carries its sliver */
        scale = sum > 0 ? exact / sum : 0;
        if (!(sum > 0))
            kx = ky = 1;
    }

    if (box)
        /* the source coordinates of the sub-rectangles' corners */
        for (uint32_t b = 0; b <= ky; b++)
            for (uint32_t a = 0; a <= kx; a++) {
                lg_probe_coord c = { f, (float)((i + (double)a / kx) / width),
                                     (float)((j + (double)b / ky) / height) };
                lg_vec3 d = lg_probe_to_world(rotation, lg_probe_coord_to_dir(layout, c));
                lg_probe_coord e = lg_probe_dir_to_coord(src->layout,
                                                         lg_probe_from_world(src_rot, d));
                double *q3 = sco + 3 * ((size_t)b * (kx + 1) + a);
                q3[0] = e.face;
                q3[1] = (double)e.u * src->width;
                q3[2] = (double)e.v * src->height;
            }
    double acc[4] = { 0, 0, 0, 0 }, wsum = 0;
    for (uint32_t b = 0; b < ky; b++)
        for (uint32_t a = 0; a < kx; a++) {
            double w;
            double u = (i + (a + 0.5) / kx) / width, v = (j + (b + 0.5) / ky) / height;
            if (layout == LG_PROBE_CUBE) {
                const double *c0 = corner + (size_t)b * (kx + 1) + a;
                const double *c1 = c0 + (kx + 1);
                w = fabs(c0[0] - c0[1] - c1[0] + c1[1]);
            } else if (layout == LG_PROBE_LATLONG) {
                w = wu[b];
            } else if (scale > 0) {
                w = angular_jacobian(2 * u - 1, 1 - 2 * v) * scale * cell;
                if (!(w > 0))
                    continue;
            } else {
                w = lg_probe_texel_solid_angle(layout, width, height, 0, i, j);
                double xx = 2 * u - 1, y = 1 - 2 * v, r = hypot(xx, y);
                u = 0.5 * (xx / r * 0.999999 + 1);
                v = 0.5 * (1 - y / r * 0.999999);
            }
            if (!(w > 0))
                continue;
            lg_probe_coord c = { f, (float)u, (float)v };
            (*samples)++;
            if (box) {
                x->rows[t] += w;
                if (!box_split(src, sco + 3 * ((size_t)b * (kx + 1) + a), kx + 1, layout, c,
                               rotation, w, m))
                    return false;
                continue;
            }
            lg_vec3 d = lg_probe_to_world(rotation, lg_probe_coord_to_dir(layout, c));
            float val[4];
            lg_probe_lookup(&x->rd, lg_probe_from_world(src_rot, d), LG_PROBE_BILINEAR, val);
            for (int k = 0; k < 4; k++)
                acc[k] += w * val[k];
            wsum += w;
        }
    if (!box)
        for (int k = 0; k < 4; k++)
            o[k] = wsum > 0 ? (float)(acc[k] / wsum) : 0.0f;
    return true;
}

/* A chunk of destination rows (r = f * height + j): its own matrix, row offsets local. */
static void build_chunk(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    rs_ctx *x = ctx;
    uint32_t kmax = x->kmax;
    overlap *m = calloc(1, sizeof *m);
    double *wu = malloc(sizeof(double) * ((size_t)(kmax + 1) * (kmax + 1) * 4 + 2 * kmax));
    x->chunk_m[chunk] = m;
    if (!m || !wu) {
        x->chunk_rc[chunk] = LG_ERR_NOMEM;
        free(wu);
        return;
    }
    uint64_t samples = 0;
    uint32_t kseen = 0;
    for (size_t r = begin; r < end; r++) {
        uint32_t f = (uint32_t)(r / x->height), j = (uint32_t)(r % x->height);
        for (uint32_t i = 0; i < x->width; i++)
            if (!build_texel(x, m, wu, f, j, i, &samples, &kseen)) {
                x->chunk_rc[chunk] = LG_ERR_NOMEM;
                free(wu);
                return;
            }
    }
    x->chunk_samples[chunk] = samples;
    x->chunk_k[chunk] = kseen;
    free(wu);
}

/* f^p for the over-relaxed column step. Near convergence f = 1 + e with e tiny: the
 * binomial series to e^3 (error below 2e-12 for |e| < 1e-3, far below the 1e-9 the
 * balancing aims at), which spares a pow() per source texel and round (it was most of the
 * balancing's time). */
static double relaxed(double f, double p)
{
    double e = f - 1;
    if (fabs(e) < 1e-3)
        return 1 + e * (p + e * (0.5 * p * (p - 1) + e * (p * (p - 1) * (p - 2) / 6)));
    return pow(f, p);
}

/* Balancing, column step: each entry scaled by its source texel's target over its sum. */
static void scale_columns(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    rs_ctx *x = ctx;
    overlap *m = x->m;
    for (size_t e = begin; e < end; e++) {
        uint32_t s = m->src[e];
        double cs = x->colsum[s];
        m->w[e] = cs > 0 ? m->w[e] * x->factor[s] : 0.0;
    }
}

/* Balancing, row step: each destination texel's entries scaled to its solid angle. */
static void scale_rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    rs_ctx *x = ctx;
    overlap *m = x->m;
    for (size_t t = begin; t < end; t++) {
        double r = 0;
        for (size_t e = m->row[t]; e < m->row[t + 1]; e++)
            r += m->w[e];
        double k = r > 0 ? x->rows[t] / r : 0;
        for (size_t e = m->row[t]; e < m->row[t + 1]; e++)
            m->w[e] *= k;
    }
}

/* The result: each destination texel the weighted mean of its row. */
static void write_rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    rs_ctx *x = ctx;
    overlap *m = x->m;
    const float *rgba = x->src->rgba;
    for (size_t t = begin; t < end; t++) {
        double acc[4] = { 0, 0, 0, 0 }, r = 0;
        for (size_t e = m->row[t]; e < m->row[t + 1]; e++) {
            const float *v = rgba + 4 * (size_t)m->src[e];
            for (int k = 0; k < 4; k++)
                acc[k] += (double)m->w[e] * v[k];
            r += m->w[e];
        }
        for (int k = 0; k < 4; k++)
            x->out[4 * t + k] = r > 0 ? (float)(acc[k] / r) : 0.0f;
    }
}

static void column_sums(const overlap *m, double *colsum, size_t src_n)
{
    memset(colsum, 0, src_n * sizeof *colsum);
    for (size_t e = 0; e < m->n; e++)
        colsum[m->src[e]] += m->w[e];
}

uint64_t lg_probe_resample_bytes(uint64_t src_texels, uint64_t dst_texels)
{
    /* area, omega, factor per source texel; rows, row per destination texel; src + w per
     * entry in the chunks and again in the merged matrix (lg_probe_resample_pool below) */
    uint64_t pairs = src_texels > dst_texels ? src_texels : dst_texels;
    double b = (double)src_texels * (sizeof(double) + sizeof(float) + sizeof(double)) +
               (double)dst_texels * (sizeof(double) + sizeof(size_t)) +
               (double)pairs * 2 * (sizeof(uint32_t) + sizeof(double));
    return b >= 1.8e19 ? UINT64_MAX : (uint64_t)b;
}

int lg_probe_resample(const lg_probe_image *src, lg_probe_layout layout, uint32_t width,
                      uint32_t height, const float *rotation, const lg_probe_resample_opts *opts,
                      float *out, lg_probe_resample_stats *stats)
{
    return lg_probe_resample_pool(NULL, src, layout, width, height, rotation, opts, out, stats);
}

int lg_probe_resample_pool(lg_node *pool, const lg_probe_image *src, lg_probe_layout layout,
                           uint32_t width, uint32_t height, const float *rotation,
                           const lg_probe_resample_opts *opts, float *out,
                           lg_probe_resample_stats *stats)
{
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (!src || !src->rgba || !out || !valid(src->layout, src->width, src->height) ||
        !valid(layout, width, height))
        return LG_ERR_INVALID;
    rs_ctx x;
    memset(&x, 0, sizeof x);
    x.src = src;
    x.rd = *src;
    x.rd.rotation = NULL;
    x.src_rot = src->rotation; /* d_src = R_src^T R_dst d_dst */
    x.layout = layout;
    x.width = width;
    x.height = height;
    x.rotation = rotation;
    lg_probe_sampling sampling = opts ? opts->sampling : LG_PROBE_NEAREST;
    x.box = sampling != LG_PROBE_BILINEAR;
    x.q = opts && opts->oversample > 0 ? opts->oversample : 2.0;
    x.kmax = opts && opts->max_subdiv > 0 ? opts->max_subdiv : 64;
    if (x.kmax > 1024)
        x.kmax = 1024;
    x.out = out;
    uint32_t max_iter = opts && opts->no_balance ? 0 : 300;
    const double tol = 1e-9;
    double *factor = NULL;

    uint32_t faces = layout == LG_PROBE_CUBE ? 6 : 1;
    size_t dst_n = (size_t)width * height * faces;
    size_t src_n = (size_t)src->width * src->height * (src->layout == LG_PROBE_CUBE ? 6 : 1);
    if (src_n > UINT32_MAX)
        return LG_ERR_INVALID;
    x.dst_n = dst_n;
    /* destination rows in 64 chunks or so (a function of the size only: the chunks, and
     * so the result, are the same on any number of threads) */
    size_t nrows = (size_t)faces * height;
    size_t grain = (nrows + 63) / 64;
    size_t nchunks = lg_parallel_chunks(nrows, grain);
    int rc = LG_ERR_NOMEM;
    double *area = x.box ? calloc(src_n, sizeof(double)) : NULL;
    x.rows = x.box ? malloc(dst_n * sizeof(double)) : NULL;
    float *omega = x.box ? malloc(src_n * sizeof(float)) : NULL;
    x.row = x.box ? malloc((dst_n + 1) * sizeof(size_t)) : NULL;
    x.chunk_m = calloc(nchunks, sizeof *x.chunk_m);
    x.chunk_samples = calloc(nchunks, sizeof *x.chunk_samples);
    x.chunk_k = calloc(nchunks, sizeof *x.chunk_k);
    x.chunk_rc = calloc(nchunks, sizeof *x.chunk_rc);
    overlap *m = x.box ? calloc(1, sizeof *m) : NULL;
    x.m = m;
    x.omega = omega;
    if (!x.chunk_m || !x.chunk_samples || !x.chunk_k || !x.chunk_rc ||
        (x.box && (!area || !x.rows || !omega || !x.row || !m)))
        goto done;
    if (x.box && lg_probe_solid_angles(src->layout, src->width, src->height, omega) != 0) {
        rc = LG_ERR_INVALID;
        goto done;
    }
    if ((rc = run_chunks(pool, nrows, grain, build_chunk, &x)))
        goto done;
    uint64_t samples = 0;
    uint32_t kseen = 0;
    size_t total_n = 0;
    rc = 0;
    for (size_t c = 0; c < nchunks; c++) {
        if (x.chunk_rc[c] && !rc)
            rc = x.chunk_rc[c];
        samples += x.chunk_samples[c];
        kseen = x.chunk_k[c] > kseen ? x.chunk_k[c] : kseen;
        total_n += x.chunk_m[c] ? x.chunk_m[c]->n : 0;
    }
    if (rc)
        goto done;
    rc = LG_ERR_NOMEM;

    double raw_total = 0, raw_area = 0, total = 0, area_err = 0, resid = 0;
    uint32_t iter = 0;
    uint64_t unread = 0;
    if (x.box) {
        /* the chunks' matrices, one after the other: the same matrix one thread makes */
        m->src = malloc((total_n ? total_n : 1) * sizeof *m->src);
        m->w = malloc((total_n ? total_n : 1) * sizeof *m->w);
        m->row = x.row;
        x.row = NULL;
        if (!m->src || !m->w)
            goto done;
        size_t base = 0;
        for (size_t c = 0; c < nchunks; c++) {
            overlap *cm = x.chunk_m[c];
            memcpy(m->src + base, cm->src, cm->n * sizeof *m->src);
            memcpy(m->w + base, cm->w, cm->n * sizeof *m->w);
            size_t t0 = c * grain * width,
                   t1 = (c * grain + grain < nrows ? c * grain + grain : nrows) * width;
            for (size_t t = t0; t < t1; t++)
                m->row[t] += base;
            base += cm->n;
            free(cm->src);
            free(cm->w);
            cm->src = NULL;
            cm->w = NULL;
        }
        m->n = m->cap = total_n;
        m->row[dst_n] = m->n;
        column_sums(m, area, src_n);
        for (size_t s = 0; s < src_n; s++)
            unread += omega[s] > 0 && area[s] == 0;
        if (unread &&
            !add_unread(src, layout, width, height, rotation, omega, area, x.rows, m, dst_n))
            goto done;
        raw_total = integral_error(src, src_n, area, omega, &raw_area);
        /* Balancing (Sinkhorn): the sub-rectangles resolve the source texels' boundaries
         * only to a fraction of a sub-rectangle, so the solid angle a source texel
         * received (its column sum) misses its exact solid angle by up to ~1e-2 for a
         * single texel; white noise then loses 1e-3 of an octant's integral. Both
         * marginals are known exactly (rows: the destination texels' solid angles;
         * columns: the source texels'), so alternately rescale columns and rows until
         * both hold: every source texel then hands out exactly its solid angle (its
         * energy is kept) and every destination texel's weights still sum to its own
         * (a constant stays constant). Only the split of a texel pair's overlap moves,
         * by about the sub-rectangle resolution. Both steps run on the pool (each entry,
         * each row on its own); the column sums in entry order on this thread. */
        double *colsum = area;
        x.colsum = colsum;
        factor = malloc(src_n * sizeof *factor);
        if (!factor)
            goto done;
        x.factor = factor;
        /* Over-relaxation of the column step (factor^1.8 instead of factor; Thibault et
         * al. 2021, "Overrelaxed Sinkhorn-Knopp algorithm"): on white noise through a cube
         * it reaches 1e-9 in 2 to 3 times fewer rounds. The row step stays plain, so that
         * after each round the rows hold exactly and the column sums are the result's. */
        const double relax = 1.8;
        /* Stagnation: where the sparsity pattern cannot meet both marginals exactly
         * (texel slivers at the lat-long poles and the angular rim) the residual levels
         * off; stop when it has not halved in the last 50 rounds. */
        double hist[100];
        for (iter = 0; iter < max_iter; iter++) {
            /* the L1 distance of the columns from their targets, over 4 pi: it bounds how
             * much solid angle any region can gain or lose */
            resid = 0;
            for (size_t s = 0; s < src_n; s++)
                resid += fabs(colsum[s] - omega[s]);
            resid /= 4 * LG_PI;
            if (resid < tol || (iter >= 100 && resid > 0.9 * hist[iter % 100]))
                break;
            hist[iter % 100] = resid;
            for (size_t s = 0; s < src_n; s++)
                factor[s] = colsum[s] > 0 ? relaxed(omega[s] / colsum[s], relax) : 0.0;
            if ((rc = run_chunks(pool, m->n, 1u << 16, scale_columns, &x)) ||
                (rc = run_chunks(pool, dst_n, 4096, scale_rows, &x)))
                goto done;
            rc = LG_ERR_NOMEM;
            column_sums(m, colsum, src_n);
        }
        total = integral_error(src, src_n, colsum, omega, &area_err);
        if ((rc = run_chunks(pool, dst_n, 4096, write_rows, &x)))
            goto done;
    }
    if (stats) {
        stats->samples = samples;
        stats->max_subdiv = kseen;
        stats->raw_area_error = raw_area;
        stats->raw_total_error = raw_total;
        stats->area_error = area_err;
        stats->total_error = total;
        stats->iterations = iter;
        stats->unread = unread;
        stats->entries = m ? m->n : 0;
    }
    rc = 0;
done:
    for (size_t c = 0; x.chunk_m && c < nchunks; c++)
        if (x.chunk_m[c]) {
            free(x.chunk_m[c]->src);
            free(x.chunk_m[c]->w);
            free(x.chunk_m[c]);
        }
    free(x.chunk_m);
    free(x.chunk_samples);
    free(x.chunk_k);
    free(x.chunk_rc);
    if (m) {
        free(m->row);
        free(m->src);
        free(m->w);
        free(m);
    }
    free(x.row);
    free(factor);
    free(area);
    free(x.rows);
    free(omega);
    return rc;
}
