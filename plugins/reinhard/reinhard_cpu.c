/*
 * Reinhard tone mapping on the CPU, fast (reinhard_cpu.h): float, blocks of LG_RH_BLOCK
 * pixels, selects instead of branches, so that GCC and Clang vectorise both passes at
 * -O2 (GCC 12's "very cheap" vectoriser needs the fixed trip counts of the block loops).
 * The double-precision oracle it is tested against is tests/plugins/reinhard/reinhard_oracle.c.
 */
#include "reinhard_cpu.h"

#include <math.h>
#include <string.h>

#include "lightgraph/image.h" /* lg_pixels_to_rgba32f */

/* The two passes are compiled for AVX-512, AVX2 and baseline x86-64, and the loader picks
 * the best the CPU has (GCC's target_clones, an ifunc): 16 or 8 floats per instruction
 * instead of SSE2's 4, which the passes need to keep up with memory. Rounding is the same
 * in every clone (no FMA contraction: -std=c11 turns it off). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__)
#define RH_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define RH_CLONES
#endif

static inline uint32_t rh_bits(float v)
{
    uint32_t b;
    memcpy(&b, &v, sizeof b);
    return b;
}

static inline float rh_float(uint32_t b)
{
    float v;
    memcpy(&v, &b, sizeof v);
    return v;
}

/* Not NaN, not +-Inf: by the bits, as the shaders do. */
static inline int rh_finite(float v)
{
    return (rh_bits(v) & 0x7f800000u) != 0x7f800000u;
}

/* Cephes' logf (S. L. Moshier): x = m 2^e with m in [sqrt(1/2), sqrt(2)), then a degree-9
 * polynomial in m - 1 and e log(2) in two parts. Branch-free: the range reduction is a
 * select. About 1 ulp on normal inputs, which is all the reduction passes it (delta >=
 * 1e-12 keeps delta + L normal). */
__attribute__((always_inline)) static inline float rh_logf(float x)
{
    uint32_t b = rh_bits(x);
    int32_t e = (int32_t)((b >> 23) & 0xffu) - 126; /* x = m 2^e, m in [0.5, 1) */
    float m = rh_float((b & 0x007fffffu) | 0x3f000000u);
    int small = m < 0.70710678118654752f; /* then use 2m in [sqrt(1/2), 1) */
    e -= small;
    m = small ? m + m : m;
    float f = m - 1.0f;
    float z = f * f;
    float y = 7.0376836292e-2f;
    y = y * f - 1.1514610310e-1f;
    y = y * f + 1.1676998740e-1f;
    y = y * f - 1.2420140846e-1f;
    y = y * f + 1.4249322787e-1f;
    y = y * f - 1.6668057665e-1f;
    y = y * f + 2.0000714765e-1f;
    y = y * f - 2.4999993993e-1f;
    y = y * f + 3.3333331174e-1f;
    y = y * f * z;
    float fe = (float)e;
    y += -2.12194440e-4f * fe;
    y += -0.5f * z;
    return f + y + 0.693359375f * fe;
}

float lg_rh_logf(float x)
{
    return rh_logf(x);
}

/* One block: the logs of the valid pixels (0 for the others) and the counts. */
__attribute__((always_inline)) static inline void
rh_reduce_block(const float *px, size_t n, float w0, float w1, float w2, float delta, float *logs,
                uint32_t *valid, uint32_t *nonfinite, uint32_t *negative)
{
    uint32_t v = 0, nf = 0, ng = 0;
    for (size_t j = 0; j < n; j++) {
        float r = px[4 * j], g = px[4 * j + 1], b = px[4 * j + 2];
        float l = w0 * r + w1 * g + w2 * b;
        int fin = rh_finite(r) & rh_finite(g) & rh_finite(b) & rh_finite(l);
        int neg = fin & (l < 0.0f);
        int ok = fin & !neg;
        logs[j] = rh_logf(ok ? delta + l : 1.0f); /* log(1) = 0 for the others */
        v += (uint32_t)ok;
        nf += (uint32_t)!fin;
        ng += (uint32_t)neg;
    }
    *valid += v;
    *nonfinite += nf;
    *negative += ng;
}

RH_CLONES
void lg_rh_reduce(const float *rgba, size_t n, const lg_rh_params *p, lg_rh_stats *st)
{
    const float w0 = p->w[0], w1 = p->w[1], w2 = p->w[2], delta = (float)p->delta;
    double acc[8] = { 0 };
    uint32_t valid = 0, nonfinite = 0, negative = 0;
    uint64_t valid64 = 0, nonfinite64 = 0, negative64 = 0;
    float logs[LG_RH_BLOCK];
    size_t i = 0;
    for (; i + LG_RH_BLOCK <= n; i += LG_RH_BLOCK) {
        rh_reduce_block(rgba + 4 * i, LG_RH_BLOCK, w0, w1, w2, delta, logs, &valid, &nonfinite,
                        &negative);
        float lane[8] = { 0 };
        for (size_t j = 0; j < LG_RH_BLOCK; j += 8)
            for (size_t k = 0; k < 8; k++)
                lane[k] += logs[j + k];
        for (size_t k = 0; k < 8; k++)
            acc[k] += lane[k];
        /* flush the 32-bit counts long before they could wrap */
        if ((i / LG_RH_BLOCK) % 4096 == 4095) {
            valid64 += valid, nonfinite64 += nonfinite, negative64 += negative;
            valid = nonfinite = negative = 0;
        }
    }
    if (i < n) {
        size_t rest = n - i;
        rh_reduce_block(rgba + 4 * i, rest, w0, w1, w2, delta, logs, &valid, &nonfinite, &negative);
        for (size_t j = 0; j < rest; j++)
            acc[j % 8] += logs[j];
    }
    double sum = 0.0;
    for (size_t k = 0; k < 8; k++)
        sum += acc[k];
    st->log_sum += sum;
    st->valid += valid64 + valid;
    st->nonfinite += nonfinite64 + nonfinite;
    st->negative += negative64 + negative;
}

void lg_rh_stats_add(lg_rh_stats *a, const lg_rh_stats *b)
{
    a->log_sum += b->log_sum;
    a->valid += b->valid;
    a->nonfinite += b->nonfinite;
    a->negative += b->negative;
}

bool lg_rh_log_average(const lg_rh_stats *st, double *lavg)
{
    if (st->valid == 0)
        return false;
    *lavg = exp(st->log_sum / (double)st->valid);
    return true;
}

double lg_rh_adapt(double la, double lavg, double rate, double dt)
{
    return la + (lavg - la) * (1.0 - pow(rate, 60.0 * dt));
}

/* x / (1 + x), white point, +Inf -> 1; x >= 0 (never NaN: the channels are sanitised
 * and the scale is positive and finite). */
static inline float rh_curve(float x, float inv_white2)
{
    float g = x / (1.0f + x);
    float t = g * (1.0f + x * inv_white2); /* inv_white2 = 0: t = g <= 1 */
    g = t < 1.0f ? t : 1.0f;
    return x < INFINITY ? g : 1.0f;
}

/* A channel as the map reads it: NaN, negative and +-Inf -> 0 (+Inf is handled apart). */
static inline float rh_clean(float v)
{
    return (rh_finite(v) & (v >= 0.0f)) ? v : 0.0f;
}

static inline int rh_pinf(float v)
{
    return rh_bits(v) == 0x7f800000u;
}

/* always_inline: compiled into each target clone of lg_rh_map */
__attribute__((always_inline)) static inline void rh_map_luminance(const float *restrict in,
                                                                   float *restrict out, size_t n,
                                                                   float scale, float inv_w2,
                                                                   float w0, float w1, float w2)
{
    for (size_t j = 0; j < n; j++) {
        const float *s = in + 4 * j;
        float *d = out + 4 * j;
        float r = s[0], g = s[1], b = s[2], a = s[3];
        int ir = rh_pinf(r), ig = rh_pinf(g), ib = rh_pinf(b);
        int any = ir | ig | ib;
        float cr = rh_clean(r), cg = rh_clean(g), cb = rh_clean(b);
        /* both weight sets sum to at most 1 in float: L <= max(c), never Inf */
        float l = w0 * cr + w1 * cg + w2 * cb;
        float ld = rh_curve(scale * l, inv_w2);
        /* c Ld / L as c (Ld / L): one division per pixel, not three */
        float k = l > 0.0f ? ld / l : 0.0f;
        float orr = cr * k, og = cg * k, ob = cb * k;
        /* a grey pixel maps to Ld itself: c / L is 1, but L's rounding can make c k one ulp
         * above Ld, and a grey brighter than the scale's range (s L = +Inf, Ld = 1) gave
         * 1.0000001 */
        int grey = (cr == cg) & (cg == cb);
        orr = grey ? ld : orr;
        og = grey ? ld : og;
        ob = grey ? ld : ob;
        /* lim c Ld / L as L -> Inf: 1 for the infinite channels, 0 for the others */
        d[0] = any ? (ir ? 1.0f : 0.0f) : orr;
        d[1] = any ? (ig ? 1.0f : 0.0f) : og;
        d[2] = any ? (ib ? 1.0f : 0.0f) : ob;
        d[3] = a;
    }
}

__attribute__((always_inline)) static inline void
rh_map_rgb(const float *restrict in, float *restrict out, size_t n, float scale, float inv_w2)
{
    for (size_t j = 0; j < n; j++) {
        const float *s = in + 4 * j;
        float *d = out + 4 * j;
        float a = s[3];
        for (int k = 0; k < 3; k++)
            d[k] = rh_pinf(s[k]) ? 1.0f : rh_curve(scale * rh_clean(s[k]), inv_w2);
        d[3] = a;
    }
}

RH_CLONES
void lg_rh_map(const float *restrict in, float *restrict out, size_t n, float scale,
               const lg_rh_params *p)
{
    float inv_w2 = p->white > 0.0 ? (float)(1.0 / (p->white * p->white)) : 0.0f;
    size_t i = 0;
    /* blocks of a fixed size for the vectoriser, then the rest */
    if (p->mode == LG_RH_RGB) {
        for (; i + LG_RH_BLOCK <= n; i += LG_RH_BLOCK)
            rh_map_rgb(in + 4 * i, out + 4 * i, LG_RH_BLOCK, scale, inv_w2);
        rh_map_rgb(in + 4 * i, out + 4 * i, n - i, scale, inv_w2);
    } else {
        for (; i + LG_RH_BLOCK <= n; i += LG_RH_BLOCK)
            rh_map_luminance(in + 4 * i, out + 4 * i, LG_RH_BLOCK, scale, inv_w2, p->w[0], p->w[1],
                             p->w[2]);
        rh_map_luminance(in + 4 * i, out + 4 * i, n - i, scale, inv_w2, p->w[0], p->w[1], p->w[2]);
    }
}

/* ---- the passes over a whole image ----------------------------------------------------------- */

/* rgba16f input is widened this many pixels at a time into a stack buffer. */
#define RH_HALF_BLOCK 256u

typedef struct rh_job {
    const lg_rh_image *in;
    const lg_rh_params *p;
    size_t rows_per_chunk;
    lg_rh_stats *slots;
    float *out;
    size_t out_row_pixels;
    float scale;
} rh_job;

size_t lg_rh_cpu_rows_per_chunk(uint32_t width)
{
    return width == 0 || width >= LG_RH_CHUNK_PIXELS ? 1 : LG_RH_CHUNK_PIXELS / width;
}

size_t lg_rh_cpu_chunks(uint32_t width, uint32_t height)
{
    size_t g = lg_rh_cpu_rows_per_chunk(width);
    return height / g + (height % g != 0);
}

/* Calls fn on runs of rgba32f pixels of row y: the row itself, or blocks of it widened
 * from half or decoded from RGBE (lg_pixels_to_rgba32f). */
static void rh_row_runs(const rh_job *j, size_t y,
                        void (*fn)(const rh_job *j, const float *px, size_t x, size_t n, size_t y,
                                   void *arg),
                        void *arg)
{
    const lg_rh_image *in = j->in;
    size_t px_bytes = in->rgbe ? 4 : in->half ? 8 : 16;
    const unsigned char *row = (const unsigned char *)in->pixels + y * in->row_pixels * px_bytes;
    if (!in->half && !in->rgbe) {
        fn(j, (const float *)(const void *)row, 0, in->width, y, arg);
        return;
    }
    float buf[RH_HALF_BLOCK * 4];
    lg_format f = in->rgbe ? LG_FORMAT_RGBE8 : LG_FORMAT_RGBA16F;
    for (size_t x = 0; x < in->width; x += RH_HALF_BLOCK) {
        size_t n = in->width - x < RH_HALF_BLOCK ? in->width - x : RH_HALF_BLOCK;
        lg_pixels_to_rgba32f(f, row + x * px_bytes, n, buf);
        fn(j, buf, x, n, y, arg);
    }
}

static void rh_reduce_run(const rh_job *j, const float *px, size_t x, size_t n, size_t y, void *arg)
{
    lg_rh_reduce(px, n, j->p, arg);
}

static void rh_reduce_chunk(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    rh_job *j = ctx;
    lg_rh_stats *slot = &j->slots[chunk];
    memset(slot, 0, sizeof *slot);
    for (size_t y = begin; y < end; y++)
        rh_row_runs(j, y, rh_reduce_run, slot);
}

int lg_rh_cpu_reduce(const lg_rh_image *in, const lg_rh_params *p, lg_rh_stats *slots,
                     lg_rh_pfor pfor, void *pctx, lg_rh_stats *total)
{
    rh_job j = {
        .in = in, .p = p, .rows_per_chunk = lg_rh_cpu_rows_per_chunk(in->width), .slots = slots
    };
    memset(total, 0, sizeof *total);
    int rc = pfor(pctx, in->height, j.rows_per_chunk, rh_reduce_chunk, &j);
    if (rc)
        return rc;
    size_t chunks = lg_rh_cpu_chunks(in->width, in->height);
    for (size_t c = 0; c < chunks; c++)
        lg_rh_stats_add(total, &slots[c]);
    return 0;
}

static void rh_map_run(const rh_job *j, const float *px, size_t x, size_t n, size_t y, void *arg)
{
    lg_rh_map(px, j->out + (y * j->out_row_pixels + x) * 4, n, j->scale, j->p);
}

static void rh_map_chunk(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    rh_job *j = ctx;
    for (size_t y = begin; y < end; y++)
        rh_row_runs(j, y, rh_map_run, NULL);
}

int lg_rh_cpu_map(const lg_rh_image *in, float *out, size_t out_row_pixels, float scale,
                  const lg_rh_params *p, lg_rh_pfor pfor, void *pctx)
{
    rh_job j = { .in = in,
                 .p = p,
                 .rows_per_chunk = lg_rh_cpu_rows_per_chunk(in->width),
                 .out = out,
                 .out_row_pixels = out_row_pixels,
                 .scale = scale };
    return pfor(pctx, in->height, j.rows_per_chunk, rh_map_chunk, &j);
}
