/* ggx_prefilter.c: the ibl plugin's GGX prefiltering of probes (the split-sum chain), the DFG
 * table, the rough lookup, and the Monte Carlo oracle.
 *
 * Prefiltering follows Filament's cmgen (CubemapIBL::roughnessFilter) and Karis 2013: one
 * Hammersley set of GGX half vectors per level, turned into each texel's tangent frame
 * (n = v = r), each sample weighted by n.l and, by default, read from a box-filtered mip
 * of the source chosen from the sample's pdf (filtered importance sampling, Krivanek &
 * Colbert 2008). Work is split by texel rows; every texel is computed from its own inputs
 * only, so a thread pool gives the same bits as one thread. docs/probes.md "Glossy
 * prefiltering" has the measurements. */
#include "ggx_prefilter.h"

#include <math.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lightgraph/vecmath.h"

/* ---- shared maths ---------------------------------------------------------------------------- */

/* Van der Corput radical inverse in base 2 of a 64-bit index, in [0, 1). */
static double radical_inverse(uint64_t k)
{
    k = (k << 32) | (k >> 32);
    k = ((k & 0x0000ffff0000ffffull) << 16) | ((k & 0xffff0000ffff0000ull) >> 16);
    k = ((k & 0x00ff00ff00ff00ffull) << 8) | ((k & 0xff00ff00ff00ff00ull) >> 8);
    k = ((k & 0x0f0f0f0f0f0f0f0full) << 4) | ((k & 0xf0f0f0f0f0f0f0f0ull) >> 4);
    k = ((k & 0x3333333333333333ull) << 2) | ((k & 0xccccccccccccccccull) >> 2);
    k = ((k & 0x5555555555555555ull) << 1) | ((k & 0xaaaaaaaaaaaaaaaaull) >> 1);
    return (double)(k >> 11) * (1.0 / 9007199254740992.0); /* 53 bits */
}

/* A GGX half vector in the tangent frame (z = n) for uniforms (u1, u2) in [0, 1):
 * phi = 2 pi u1, cos theta = sqrt((1 - u2) / (1 + (alpha^2 - 1) u2)), the inverse CDF of
 * D(h)(n.h) (Walter et al. 2007). */
static void ggx_half(double u1, double u2, double a2, double h[3])
{
    double ct2 = (1.0 - u2) / (1.0 + (a2 - 1.0) * u2);
    if (ct2 > 1.0)
        ct2 = 1.0;
    if (ct2 < 0.0)
        ct2 = 0.0;
    double ct = sqrt(ct2), st = sqrt(1.0 - ct2), phi = 2.0 * LG_PI * u1;
    h[0] = st * cos(phi);
    h[1] = st * sin(phi);
    h[2] = ct;
}

/* GGX D(n.h) for alpha^2 = a2 (> 0). */
static double ggx_d(double noh, double a2)
{
    double t = noh * noh * (a2 - 1.0) + 1.0;
    return a2 / (LG_PI * t * t);
}

/* Smith height-correlated visibility G / (4 (n.l)(n.v)) (Heitz 2014; Filament). */
static double smith_vis(double nov, double nol, double a2)
{
    double gv = nol * sqrt(nov * nov * (1.0 - a2) + a2);
    double gl = nov * sqrt(nol * nol * (1.0 - a2) + a2);
    double s = gv + gl;
    return s > 0.0 ? 0.5 / s : 0.0;
}

/* An orthonormal basis (t, b, n) about unit n, branchless and continuous except on
 * n.z = 0's sign change (Duff et al. 2017, "Building an Orthonormal Basis, Revisited"). */
static void onb(const double n[3], double t[3], double b[3])
{
    double sign = n[2] >= 0.0 ? 1.0 : -1.0;
    double a = -1.0 / (sign + n[2]);
    double c = n[0] * n[1] * a;
    t[0] = 1.0 + sign * n[0] * n[0] * a;
    t[1] = sign * c;
    t[2] = -sign * n[0];
    b[0] = c;
    b[1] = sign + n[1] * n[1] * a;
    b[2] = -n[1];
}

static float clamp_roughness(float r)
{
    if (!(r > 0.0f))
        return 0.0f;
    return r > 1.0f ? 1.0f : r;
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- the rough lookup ------------------------------------------------------------------------ */

void lg_probe_lookup_rough(const lg_probe_image *levels, uint32_t n_levels, lg_vec3 dir,
                           float roughness, float out[4])
{
    if (!levels || n_levels == 0) {
        out[0] = out[1] = out[2] = out[3] = 0.0f;
        return;
    }
    float lod = lg_probe_roughness_lod(roughness, n_levels);
    uint32_t lo = (uint32_t)floorf(lod);
    if (lo > n_levels - 1)
        lo = n_levels - 1;
    float f = lod - (float)lo;
    uint32_t hi = lo + 1 < n_levels ? lo + 1 : n_levels - 1;
    lg_probe_lookup(&levels[lo], dir, LG_PROBE_BILINEAR, out);
    if (f == 0.0f || hi == lo)
        return; /* exactly the level: roughness 0 is lg_probe_lookup of level 0 */
    float b[4];
    lg_probe_lookup(&levels[hi], dir, LG_PROBE_BILINEAR, b);
    for (int c = 0; c < 4; c++)
        out[c] = out[c] + (b[c] - out[c]) * f;
}

/* ---- the DFG table --------------------------------------------------------------------------- */

/* A and B at (n.v, perceptual roughness) from `samples` Hammersley GGX samples. */
static void dfg_entry(double nov, double roughness, uint32_t samples, double *a_out, double *b_out)
{
    double alpha = roughness * roughness, a2 = alpha * alpha;
    if (a2 == 0.0) {
        /* the mirror: h = n, l = reflect(-v, n), f (n.l) / pdf = 1, F at v.h = n.v (and
         * its limit at n.v = 0, where no sample has v.h > 0) */
        double fc = pow(1.0 - fmin(fmax(nov, 0.0), 1.0), 5.0);
        *a_out = 1.0 - fc;
        *b_out = fc;
        return;
    }
    double v[3] = { sqrt(fmax(0.0, 1.0 - nov * nov)), 0.0, nov };
    double a = 0.0, b = 0.0;
    for (uint32_t k = 0; k < samples; k++) {
        double h[3];
        ggx_half(((double)k + 0.5) / samples, radical_inverse(k), a2, h);
        double voh = v[0] * h[0] + v[1] * h[1] + v[2] * h[2];
        double nol = 2.0 * voh * h[2] - v[2];
        double noh = h[2];
        if (nol <= 0.0 || voh <= 0.0 || noh <= 0.0)
            continue;
        /* f (n.l) / pdf with pdf(l) = D (n.h) / (4 v.h): D cancels */
        double g = smith_vis(nov, nol, a2) * 4.0 * voh * nol / noh;
        double fc = pow(1.0 - voh, 5.0);
        a += (1.0 - fc) * g;
        b += fc * g;
    }
    *a_out = a / samples;
    *b_out = b / samples;
}

void lg_ggx_dfg_table(uint32_t size, uint32_t samples, float *out)
{
    if (!size || !out)
        return;
    if (!samples)
        samples = 1024;
    for (uint32_t j = 0; j < size; j++) {
        for (uint32_t i = 0; i < size; i++) {
            double a, b;
            dfg_entry(((double)i + 0.5) / size, ((double)j + 0.5) / size, samples, &a, &b);
            out[2 * ((size_t)j * size + i) + 0] = (float)a;
            out[2 * ((size_t)j * size + i) + 1] = (float)b;
        }
    }
}

/* The process's table: state 0 = not made, 1 = being made, 2 = ready. The first caller
 * makes it (about 1 ms of work per 1000 samples x entries: some 20 ms); concurrent
 * first callers yield until it is ready, so every caller reads the same numbers. */
static float g_dfg[2 * LG_GGX_DFG_SIZE * LG_GGX_DFG_SIZE];
static atomic_int g_dfg_state;

const float *lg_ggx_dfg_shared(void)
{
    if (atomic_load_explicit(&g_dfg_state, memory_order_acquire) == 2)
        return g_dfg;
    int expect = 0;
    if (atomic_compare_exchange_strong(&g_dfg_state, &expect, 1)) {
        /* entries on the end points (i / (N - 1)), not on texel centres: see
         * lg_ggx_dfg_shared in the header */
        for (uint32_t j = 0; j < LG_GGX_DFG_SIZE; j++)
            for (uint32_t i = 0; i < LG_GGX_DFG_SIZE; i++) {
                double a, b;
                dfg_entry((double)i / (LG_GGX_DFG_SIZE - 1), (double)j / (LG_GGX_DFG_SIZE - 1),
                          LG_GGX_DFG_SAMPLES, &a, &b);
                g_dfg[2 * (j * LG_GGX_DFG_SIZE + i) + 0] = (float)a;
                g_dfg[2 * (j * LG_GGX_DFG_SIZE + i) + 1] = (float)b;
            }
        atomic_store_explicit(&g_dfg_state, 2, memory_order_release);
        return g_dfg;
    }
    while (atomic_load_explicit(&g_dfg_state, memory_order_acquire) != 2)
        sched_yield();
    return g_dfg;
}

void lg_ggx_dfg(float n_dot_v, float roughness, float out[2])
{
    const float *t = lg_ggx_dfg_shared();
    const float last = (float)(LG_GGX_DFG_SIZE - 1);
    /* entry i at i / (N - 1): x in [0, N - 1] */
    float x = (n_dot_v > 0.0f ? (n_dot_v < 1.0f ? n_dot_v : 1.0f) : 0.0f) * last;
    float y = clamp_roughness(roughness) * last;
    uint32_t i0 = (uint32_t)x, j0 = (uint32_t)y;
    if (i0 > LG_GGX_DFG_SIZE - 2)
        i0 = LG_GGX_DFG_SIZE - 2;
    if (j0 > LG_GGX_DFG_SIZE - 2)
        j0 = LG_GGX_DFG_SIZE - 2;
    uint32_t i1 = i0 + 1, j1 = j0 + 1;
    float fx = x - (float)i0, fy = y - (float)j0;
    for (int c = 0; c < 2; c++) {
        float t00 = t[2 * (j0 * LG_GGX_DFG_SIZE + i0) + c];
        float t10 = t[2 * (j0 * LG_GGX_DFG_SIZE + i1) + c];
        float t01 = t[2 * (j1 * LG_GGX_DFG_SIZE + i0) + c];
        float t11 = t[2 * (j1 * LG_GGX_DFG_SIZE + i1) + c];
        float a = t00 + (t10 - t00) * fx, b = t01 + (t11 - t01) * fx;
        out[c] = a + (b - a) * fy;
    }
}

/* ---- the oracle and the split sum ------------------------------------------------------------ */

/* PCG32 (O'Neill 2014), for the Cranley-Patterson shift of the oracle's point set. */
static uint32_t pcg32(uint64_t *state)
{
    uint64_t old = *state;
    *state = old * 6364136223846793005ull + 1442695040888963407ull;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31u));
}

static double schlick(double f0, double voh)
{
    return f0 + (1.0 - f0) * pow(1.0 - voh, 5.0);
}

int lg_probe_ggx_reference(const lg_probe_image *src, lg_vec3 n_in, lg_vec3 v_in, float roughness,
                           const float f0[3], uint64_t samples, uint32_t seed, double out[3])
{
    if (!out)
        return LG_ERR_INVALID;
    out[0] = out[1] = out[2] = 0.0;
    if (!src || !src->rgba || !src->width || !src->height)
        return LG_ERR_INVALID;
    if (!samples)
        samples = 65536;
    lg_vec3 nf = lg_probe_safe_dir(n_in), vf = lg_probe_safe_dir(v_in);
    double n[3] = { nf.x, nf.y, nf.z }, v[3] = { vf.x, vf.y, vf.z };
    double nov = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    if (!(nov > 0.0))
        return 0; /* the viewer is behind the surface: nothing reflects toward it */
    float r = clamp_roughness(roughness);
    if (r == 0.0f) {
        /* the mirror: F(n.v) L(reflect(-v, n)), one lookup */
        float c[4];
        lg_vec3 rd = lg_v3((float)(2.0 * nov * n[0] - v[0]), (float)(2.0 * nov * n[1] - v[1]),
                           (float)(2.0 * nov * n[2] - v[2]));
        lg_probe_lookup(src, rd, LG_PROBE_BILINEAR, c);
        for (int ch = 0; ch < 3; ch++)
            out[ch] = (f0 ? schlick(f0[ch], nov) : 1.0) * c[ch];
        return 0;
    }
    double alpha = (double)r * r, a2 = alpha * alpha;
    double t[3], b[3];
    onb(n, t, b);
    uint64_t st = (uint64_t)seed * 0x9e3779b97f4a7c15ull + 0x853c49e6748fea9bull;
    pcg32(&st);
    double s1 = pcg32(&st) * (1.0 / 4294967296.0), s2 = pcg32(&st) * (1.0 / 4294967296.0);
    double acc[3] = { 0.0, 0.0, 0.0 };
    for (uint64_t k = 0; k < samples; k++) {
        double u1 = ((double)k + 0.5) / (double)samples + s1;
        double u2 = radical_inverse(k) + s2;
        u1 -= floor(u1);
        u2 -= floor(u2);
        double hl[3];
        ggx_half(u1, u2, a2, hl);
        double h[3];
        for (int c = 0; c < 3; c++)
            h[c] = hl[0] * t[c] + hl[1] * b[c] + hl[2] * n[c];
        double voh = v[0] * h[0] + v[1] * h[1] + v[2] * h[2];
        if (voh <= 0.0)
            continue;
        double l[3];
        for (int c = 0; c < 3; c++)
            l[c] = 2.0 * voh * h[c] - v[c];
        double nol = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
        double noh = hl[2];
        if (nol <= 0.0 || noh <= 0.0)
            continue;
        double g = smith_vis(nov, nol, a2) * 4.0 * voh * nol / noh;
        float c[4];
        lg_probe_lookup(src, lg_v3((float)l[0], (float)l[1], (float)l[2]), LG_PROBE_BILINEAR, c);
        for (int ch = 0; ch < 3; ch++)
            acc[ch] += (f0 ? schlick(f0[ch], voh) : 1.0) * g * c[ch];
    }
    for (int ch = 0; ch < 3; ch++)
        out[ch] = acc[ch] / (double)samples;
    return 0;
}

void lg_probe_ggx_split_sum(const lg_probe_image *levels, uint32_t n_levels, lg_vec3 n, lg_vec3 v,
                            float roughness, const float f0[3], float out[3])
{
    n = lg_probe_safe_dir(n);
    v = lg_probe_safe_dir(v);
    float nov = lg_v3_dot(n, v);
    lg_vec3 r = lg_v3_sub(lg_v3_scale(n, 2.0f * nov), v);
    nov = nov > 0.0f ? (nov < 1.0f ? nov : 1.0f) : 0.0f;
    float ab[2], c[4];
    lg_ggx_dfg(nov, roughness, ab);
    lg_probe_lookup_rough(levels, n_levels, r, roughness, c);
    for (int ch = 0; ch < 3; ch++)
        out[ch] = c[ch] * ((f0 ? f0[ch] : 1.0f) * ab[0] + ab[1]);
}

/* ---- prefiltering ---------------------------------------------------------------------------- */

/* One level's sample set in the tangent frame: directions l (z = n.l > 0), weights n.l,
 * and the source lod each reads. */
typedef struct level_set {
    float *l; /* 3 per sample */
    float *w;
    float *lod;
    uint32_t count;
} level_set;

typedef struct mip {
    lg_probe_image img;
} mip;

typedef struct filter_job {
    lg_probe_layout layout;
    uint32_t width, height, faces, levels;
    lg_image_desc desc; /* the chain's packing */
    float *out;
    const mip *mips; /* the source chain (mips[0] = level 0 of out) */
    uint32_t n_mips;
    level_set sets[LG_PROBE_FILTER_MAX_LEVELS];
    size_t row_start[LG_PROBE_FILTER_MAX_LEVELS + 1]; /* first row index of each level */
} filter_job;

static void read_source(const filter_job *j, lg_vec3 d, float lod, float out[4])
{
    if (j->n_mips <= 1 || !(lod > 0.0f)) {
        lg_probe_lookup(&j->mips[0].img, d, LG_PROBE_BILINEAR, out);
        return;
    }
    float maxl = (float)(j->n_mips - 1);
    if (lod > maxl)
        lod = maxl;
    uint32_t lo = (uint32_t)lod;
    float f = lod - (float)lo;
    lg_probe_lookup(&j->mips[lo].img, d, LG_PROBE_BILINEAR, out);
    if (f == 0.0f || lo + 1 >= j->n_mips)
        return;
    float b[4];
    lg_probe_lookup(&j->mips[lo + 1].img, d, LG_PROBE_BILINEAR, b);
    for (int c = 0; c < 4; c++)
        out[c] = out[c] + (b[c] - out[c]) * f;
}

static void filter_rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const filter_job *j = ctx;
    for (size_t row = begin; row < end; row++) {
        uint32_t level = 1;
        while (row >= j->row_start[level + 1])
            level++;
        uint32_t lw = lg_image_level_width(&j->desc, level);
        uint32_t lh = lg_image_level_height(&j->desc, level);
        size_t r = row - j->row_start[level];
        uint32_t face = (uint32_t)(r / lh), y = (uint32_t)(r % lh);
        float *dst = j->out + 4 * (lg_image_offset(&j->desc, level, face) + (size_t)y * lw);
        const level_set *s = &j->sets[level];
        for (uint32_t x = 0; x < lw; x++) {
            lg_vec3 nd = lg_probe_texel_dir(j->layout, lw, lh, face, x, y);
            double n[3] = { nd.x, nd.y, nd.z }, t[3], b[3];
            onb(n, t, b);
            /* L(l_0) + sum w_k (L(l_k) - L(l_0)) / sum w_k: exactly L for a constant */
            float ref[4] = { 0, 0, 0, 0 };
            double acc[4] = { 0, 0, 0, 0 }, wsum = 0.0;
            for (uint32_t k = 0; k < s->count; k++) {
                const float *l = s->l + 3 * k;
                lg_vec3 d = lg_v3((float)(l[0] * t[0] + l[1] * b[0] + l[2] * n[0]),
                                  (float)(l[0] * t[1] + l[1] * b[1] + l[2] * n[1]),
                                  (float)(l[0] * t[2] + l[1] * b[2] + l[2] * n[2]));
                float c[4];
                read_source(j, d, s->lod[k], c);
                if (k == 0)
                    memcpy(ref, c, sizeof ref);
                double w = s->w[k];
                for (int ch = 0; ch < 4; ch++)
                    acc[ch] += w * ((double)c[ch] - (double)ref[ch]);
                wsum += w;
            }
            for (int ch = 0; ch < 4; ch++)
                dst[4 * x + ch] = wsum > 0.0 ? (float)((double)ref[ch] + acc[ch] / wsum) : ref[ch];
        }
    }
}

/* The box-filtered (solid-angle-weighted) mip chain of level 0, down to 1 x 1. Each
 * parent texel averages the child texels it covers, weighted by their exact solid angles
 * (so the chain keeps the integral), as t0 + sum w (t - t0) / sum w (so a constant stays
 * exact). Returns the number of mips (>= 1), 0 when out of memory; *storage receives the
 * allocation holding mips 1.. (the caller frees). */
static uint32_t build_mips(lg_probe_layout layout, uint32_t w0, uint32_t h0, uint32_t faces,
                           const float *level0, mip *mips, uint32_t max_mips, float **storage)
{
    uint32_t n = 1;
    size_t total = 0;
    for (uint32_t side = w0 > h0 ? w0 : h0; side > 1 && n < max_mips; side >>= 1, n++) {
        uint32_t w = w0 >> n ? w0 >> n : 1, h = h0 >> n ? h0 >> n : 1;
        total += (size_t)w * h * faces;
    }
    memset(mips, 0, sizeof *mips * n);
    mips[0].img.layout = layout;
    mips[0].img.width = w0;
    mips[0].img.height = h0;
    mips[0].img.rgba = level0;
    *storage = NULL;
    if (n == 1)
        return 1;
    float *buf = malloc(total * 4 * sizeof(float));
    float *sa = malloc((size_t)w0 * h0 * faces * sizeof(float));
    if (!buf || !sa) {
        free(buf);
        free(sa);
        return 0;
    }
    float *p = buf;
    for (uint32_t m = 1; m < n; m++) {
        uint32_t cw = mips[m - 1].img.width, ch = mips[m - 1].img.height;
        uint32_t pw = cw >> 1 ? cw >> 1 : 1, ph = ch >> 1 ? ch >> 1 : 1;
        lg_probe_solid_angles(layout, cw, ch, sa); /* the children's weights */
        const float *child = mips[m - 1].img.rgba;
        for (uint32_t f = 0; f < faces; f++) {
            const float *cf = child + 4 * (size_t)f * cw * ch;
            const float *sf = sa + (size_t)f * cw * ch;
            float *pf = p + 4 * (size_t)f * pw * ph;
            for (uint32_t y = 0; y < ph; y++) {
                uint32_t y0 = (uint32_t)((uint64_t)y * ch / ph);
                uint32_t y1 = (uint32_t)((uint64_t)(y + 1) * ch / ph);
                for (uint32_t x = 0; x < pw; x++) {
                    uint32_t x0 = (uint32_t)((uint64_t)x * cw / pw);
                    uint32_t x1 = (uint32_t)((uint64_t)(x + 1) * cw / pw);
                    const float *t0 = cf + 4 * ((size_t)y0 * cw + x0);
                    double acc[4] = { 0, 0, 0, 0 }, wsum = 0, cnt = 0;
                    double accu[4] = { 0, 0, 0, 0 };
                    for (uint32_t yy = y0; yy < y1; yy++) {
                        for (uint32_t xx = x0; xx < x1; xx++) {
                            const float *tx = cf + 4 * ((size_t)yy * cw + xx);
                            double w = sf[(size_t)yy * cw + xx];
                            for (int c = 0; c < 4; c++) {
                                double d = (double)tx[c] - (double)t0[c];
                                acc[c] += w * d;
                                accu[c] += d;
                            }
                            wsum += w;
                            cnt += 1;
                        }
                    }
                    float *o = pf + 4 * ((size_t)y * pw + x);
                    for (int c = 0; c < 4; c++) /* texels outside the angular disc: plain mean */
                        o[c] = (float)((double)t0[c] + (wsum > 0 ? acc[c] / wsum : accu[c] / cnt));
                }
            }
        }
        mips[m].img.layout = layout;
        mips[m].img.width = pw;
        mips[m].img.height = ph;
        mips[m].img.rgba = p;
        p += 4 * (size_t)pw * ph * faces;
    }
    free(sa);
    *storage = buf;
    return n;
}

/* Texels of a resampled angular level 0 outside the disc (solid angle 0, not part of the
 * sphere) are 0 from lg_probe_resample. Bilinear lookups near the rim, and the rim's mips,
 * read them, which would darken the rim: give them the radiance along +Z, the direction
 * lg_probe_coord_to_dir gives every point outside the disc, so the map continues smoothly
 * past its rim and a constant probe stays constant there. Integrals are unchanged. */
static void fill_outside_disc(const lg_probe_image *src, uint32_t w, uint32_t h, float *out)
{
    float rim[4];
    /* +Z of the chain's frame (the source's), as a world direction for the lookup */
    lg_probe_lookup(src, lg_probe_to_world(src->rotation, lg_v3(0.0f, 0.0f, 1.0f)),
                    LG_PROBE_BILINEAR, rim);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            if (lg_probe_texel_solid_angle(LG_PROBE_ANGULAR, w, h, 0, x, y) == 0.0)
                memcpy(out + 4 * ((size_t)y * w + x), rim, sizeof rim);
}

static int valid_layout(lg_probe_layout l)
{
    return l == LG_PROBE_LATLONG || l == LG_PROBE_ANGULAR || l == LG_PROBE_CUBE;
}

int lg_probe_prefilter_ggx(lg_node *pool, const lg_probe_image *src, lg_probe_layout layout,
                           uint32_t width, uint32_t height, uint32_t levels,
                           const lg_probe_prefilter_opts *opts, float *out,
                           lg_probe_prefilter_stats *stats)
{
    double t_start = now_seconds();
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (!src || !src->rgba || !src->width || !src->height || !valid_layout(src->layout) ||
        !valid_layout(layout) || !width || !height || width > 65536 || height > 65536 ||
        (layout == LG_PROBE_CUBE && width != height) ||
        (src->layout == LG_PROBE_CUBE && src->width != src->height) || levels < 1 ||
        levels > LG_PROBE_FILTER_MAX_LEVELS || !out)
        return LG_ERR_INVALID;
    uint32_t samples = opts && opts->samples ? opts->samples : 256;
    int source_lod = !(opts && opts->no_source_lod);
    int vis_weight = opts && opts->weighting == LG_PROBE_WEIGHT_NOL_VIS;
    if (opts && opts->weighting != LG_PROBE_WEIGHT_NOL && !vis_weight)
        return LG_ERR_INVALID;
    uint32_t faces = layout == LG_PROBE_CUBE ? 6u : 1u;

    /* level 0: the source itself (same layout and size) or resampled into the layout, in
     * the source's frame (destination rotation = the source's: no rotation baked in) */
    if (src->layout == layout && src->width == width && src->height == height) {
        memcpy(out, src->rgba, sizeof(float) * 4 * (size_t)width * height * faces);
    } else {
        int rc = lg_probe_resample(src, layout, width, height, src->rotation, NULL, out, NULL);
        if (rc)
            return rc;
        if (layout == LG_PROBE_ANGULAR)
            fill_outside_disc(src, width, height, out);
    }

    filter_job j;
    memset(&j, 0, sizeof j);
    j.layout = layout;
    j.width = width;
    j.height = height;
    j.faces = faces;
    j.levels = levels;
    j.desc.width = width;
    j.desc.height = height;
    j.desc.format = LG_FORMAT_RGBA32F;
    j.desc.flags = layout == LG_PROBE_CUBE ? LG_IMAGE_CUBE : 0;
    j.desc.levels = levels;
    j.out = out;

    int rc = 0;
    float *mip_storage = NULL;
    mip mips[32];
    j.n_mips = build_mips(layout, width, height, faces, out, mips,
                          source_lod && levels > 1 ? 32u : 1u, &mip_storage);
    if (!j.n_mips)
        return LG_ERR_NOMEM;
    j.mips = mips;

    /* omega_p: the mean solid angle of a level-0 texel on the sphere */
    double texels = (double)width * height * faces;
    if (layout == LG_PROBE_ANGULAR)
        texels *= LG_PI / 4.0; /* the disc's share of the square */
    double omega_p = 4.0 * LG_PI / texels;

    for (uint32_t l = 1; l < levels; l++) {
        double r = lg_probe_level_roughness(l, levels), alpha = r * r, a2 = alpha * alpha;
        level_set *s = &j.sets[l];
        s->l = malloc(sizeof(float) * 3 * samples);
        s->w = malloc(sizeof(float) * samples);
        s->lod = malloc(sizeof(float) * samples);
        if (!s->l || !s->w || !s->lod) {
            rc = LG_ERR_NOMEM;
            goto done;
        }
        for (uint32_t k = 0; k < samples; k++) {
            double h[3];
            ggx_half(((double)k + 0.5) / samples, radical_inverse(k), a2, h);
            /* v = n = (0, 0, 1): l = 2 (n.h) h - n */
            double lz = 2.0 * h[2] * h[2] - 1.0;
            if (lz <= 0.0)
                continue;
            uint32_t c = s->count++;
            s->l[3 * c + 0] = (float)(2.0 * h[2] * h[0]);
            s->l[3 * c + 1] = (float)(2.0 * h[2] * h[1]);
            s->l[3 * c + 2] = (float)lz;
            /* n.l (Karis, Filament), or n.l Vis(n.l, n.v = 1): the integrand's own
             * weight for n = v, which makes the split sum exact there */
            s->w[c] = (float)(vis_weight ? lz * smith_vis(1.0, lz, a2) : lz);
            /* pdf(l) = D(n.h) (n.h) / (4 v.h) = D / 4 with v = n; Filament's
             * lod = log4(omega_s) - log4(omega_p) + log4(K), K = 4 */
            double lod = 0.0;
            if (source_lod && a2 > 0.0) {
                double pdf = ggx_d(h[2], a2) / 4.0;
                double omega_s = 1.0 / ((double)samples * pdf);
                lod = 0.5 * log2(omega_s / omega_p) + 1.0;
                if (lod < 0.0)
                    lod = 0.0;
            }
            s->lod[c] = (float)lod;
        }
    }

    j.row_start[1] = 0;
    for (uint32_t l = 1; l < levels; l++)
        j.row_start[l + 1] = j.row_start[l] + (size_t)lg_image_level_height(&j.desc, l) * faces;
    for (uint32_t l = levels + 1; l <= LG_PROBE_FILTER_MAX_LEVELS; l++)
        j.row_start[l] = j.row_start[levels];
    size_t rows = j.row_start[levels];
    if (rows) {
        if (pool)
            rc = lg_parallel_for(pool, rows, 1, filter_rows, &j);
        else
            filter_rows(&j, 0, rows, 0);
    }
    if (stats) {
        uint64_t n = 0;
        for (uint32_t l = 1; l < levels; l++)
            n += (uint64_t)lg_image_level_width(&j.desc, l) * lg_image_level_height(&j.desc, l) *
                 faces * samples;
        stats->samples = n;
        stats->threads = pool ? lg_cpu_workers(pool) : 1u;
    }

done:
    for (uint32_t l = 0; l < LG_PROBE_FILTER_MAX_LEVELS; l++) {
        free(j.sets[l].l);
        free(j.sets[l].w);
        free(j.sets[l].lod);
    }
    free(mip_storage);
    if (stats)
        stats->seconds = now_seconds() - t_start;
    return rc;
}
