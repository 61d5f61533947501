/* acme_blur, backend cpu: the two passes on the host's thread pool (lg_parallel_for),
 * rows split into chunks. The horizontal pass writes a scratch image the node owns (counted
 * in the profile with lg_account_alloc / lg_account_free); the vertical pass accumulates
 * whole rows of it, which GCC vectorises. This is the reference the gl and cl backends are
 * compared with in tests (and the test compares it with a double-precision 2D sum). */
#include <float.h>
#include <stdlib.h>

#include "blur.h"

struct acme_blur_cpu {
    float *scratch; /* width x height rgba32f: the horizontal pass's result, then one padded
                     * row (width + 2 radius pixels) per chunk of rows */
    size_t bytes;
};

/* The bad-pixel policy (README "Bad pixels"): NaN reads as 0, +-Inf as +-FLT_MAX, and a sum
 * that overflows is FLT_MAX, so the output is finite. Selects, not branches: they
 * vectorise. shaders/common/acme_blur.glsl and acme_blur.cl are the GPU twins. */
static inline float acme_sanitize(float v)
{
    v = v != v ? 0.0f : v;
    v = v > FLT_MAX ? FLT_MAX : v;
    return v < -FLT_MAX ? -FLT_MAX : v;
}

typedef struct blur_job {
    const float *src;        /* the pass's input, rgba32f */
    float *dst;              /* its output */
    size_t src_row, dst_row; /* floats from one row to the next (lg_cpu_view.row_pixels x 4) */
    float *pad;              /* pass_h: one padded row per chunk */
    const float *w;          /* radius + 1 weights */
    int radius;
    uint32_t width, height;
} blur_job;

/* A row at a time: its pixels sanitized and clamped to the edge into the chunk's padded row
 * (r pixels more on each side), then the taps summed over whole rows, which vectorises as
 * pass_v does. The sum's order (i = -r .. r, from 0) is the GPU backends'. */
static void pass_h(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    const blur_job *j = ctx;
    const int r = j->radius, wd = (int)j->width;
    const size_t row = 4 * (size_t)j->width;
    float *restrict pad = j->pad + (size_t)chunk * (row + 8 * (size_t)r);
    for (size_t y = begin; y < end; y++) {
        const float *src = j->src + y * j->src_row;
        float *restrict dst = j->dst + y * j->dst_row;
        for (int x = -r; x < wd + r; x++) {
            int xi = x < 0 ? 0 : x >= wd ? wd - 1 : x; /* clamp to edge */
            for (int c = 0; c < 4; c++)
                pad[4 * (size_t)(x + r) + c] = acme_sanitize(src[4 * xi + c]);
        }
        for (size_t k = 0; k < row; k++)
            dst[k] = 0;
        for (int i = -r; i <= r; i++) {
            const float *restrict p = pad + 4 * (size_t)(i + r);
            float wt = j->w[i < 0 ? -i : i];
            for (size_t k = 0; k < row; k++)
                dst[k] += wt * p[k];
        }
        for (size_t k = 0; k < row; k++)
            dst[k] = acme_sanitize(dst[k]);
    }
}

static void pass_v(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const blur_job *j = ctx;
    const int r = j->radius, ht = (int)j->height;
    const size_t row = 4 * (size_t)j->width;
    for (size_t y = begin; y < end; y++) {
        float *restrict dst = j->dst + y * j->dst_row; /* restrict: no aliasing, vectorise */
        for (size_t k = 0; k < row; k++)
            dst[k] = 0;
        for (int i = -r; i <= r; i++) { /* whole rows: the inner loop vectorises */
            int yi = (int)y + i < 0 ? 0 : (int)y + i >= ht ? ht - 1 : (int)y + i;
            const float *restrict src = j->src + (size_t)yi * j->src_row;
            float wt = j->w[i < 0 ? -i : i];
            for (size_t k = 0; k < row; k++)
                dst[k] += wt * src[k];
        }
        for (size_t k = 0; k < row; k++)
            dst[k] = acme_sanitize(dst[k]);
    }
}

int acme_blur_cpu(lg_node *n, acme_blur *st)
{
    /* chunks of about 16K pixels (whole rows): worth a hand-off, many per worker */
    size_t grain = st->width >= 16384 ? 1 : 16384 / st->width;
    size_t chunks = lg_parallel_chunks(st->height, grain);
    size_t image = (size_t)st->width * st->height * 4,
           pad = 4 * ((size_t)st->width + 2 * st->radius);
    size_t bytes = (image + chunks * pad) * sizeof(float);
    if (!st->cpu && !(st->cpu = calloc(1, sizeof *st->cpu)))
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (cpu backend state)");
    struct acme_blur_cpu *c = st->cpu;
    if (c->bytes != bytes) { /* first run, or the image size changed: remake it */
        acme_blur_cpu_free(n, st);
        if (!(st->cpu = c = calloc(1, sizeof *c)) || !(c->scratch = malloc(bytes)))
            return lg_error_code(n, LG_ERR_NOMEM,
                                 "out of memory: the scratch image of %ux%u pixels (%zu bytes)",
                                 st->width, st->height, bytes);
        c->bytes = bytes;
        lg_account_alloc(n, bytes);
    }
    lg_cpu_view in, out;
    int rc;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &in)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &out)))
        return rc;
    size_t row = 4 * (size_t)st->width;
    blur_job h = { in.pixels,   c->scratch, 4 * in.row_pixels, row,       c->scratch + image,
                   st->weights, st->radius, st->width,         st->height };
    if ((rc = lg_parallel_for(n, st->height, grain, pass_h, &h)))
        return rc;
    blur_job v = { c->scratch,  out.pixels, row,       4 * out.row_pixels, NULL,
                   st->weights, st->radius, st->width, st->height };
    return lg_parallel_for(n, st->height, grain, pass_v, &v);
}

void acme_blur_cpu_free(lg_node *n, acme_blur *st)
{
    if (!st->cpu)
        return;
    if (st->cpu->scratch)
        lg_account_free(n, st->cpu->bytes);
    free(st->cpu->scratch);
    free(st->cpu);
    st->cpu = NULL;
}
