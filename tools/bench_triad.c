/* The STREAM triad of the roofline benchmarks (bench_triad.h). */
#include "bench_triad.h"

#include <stdio.h>
#include <stdlib.h>

#include "base/util.h"

typedef struct triad_ctx {
    double *a, *b, *c;
    double s;
} triad_ctx;

static void triad_init(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    triad_ctx *t = arg;
    for (size_t i = begin; i < end; i++) {
        t->a[i] = 0.0;
        t->b[i] = 1.0;
        t->c[i] = 2.0;
    }
}

static void triad_run(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    triad_ctx *t = arg;
    double *restrict a = t->a;
    const double *restrict b = t->b, *restrict c = t->c;
    const double s = t->s;
    for (size_t i = begin; i < end; i++)
        a[i] = b[i] + s * c[i];
}

int lg_bench_triad(lg_pool *pool, size_t mib, int repeat, const char *prog, double *gbs,
                   double *ms_best)
{
    size_t n = mib * 1024 * 1024 / sizeof(double);
    triad_ctx t = { malloc(n * 8), malloc(n * 8), malloc(n * 8), 3.0 };
    double *ms = calloc((size_t)(repeat > 0 ? repeat : 1), sizeof *ms);
    int rc = 0;
    if (!t.a || !t.b || !t.c || !ms) {
        fprintf(stderr, "%s: cannot allocate 3 x %zu MiB for the triad\n", prog, mib);
        rc = 1;
        goto out;
    }
    const size_t grain = 1u << 16;
    lg_pool_run(pool, n, grain, triad_init, &t); /* first touch by the pool's threads */
    lg_pool_run(pool, n, grain, triad_run, &t);  /* warm-up */
    double best = 0;
    for (int r = 0; r < repeat; r++) {
        double t0 = lg_mono_now();
        lg_pool_run(pool, n, grain, triad_run, &t);
        ms[r] = (lg_mono_now() - t0) * 1e3;
        if (r == 0 || ms[r] < best)
            best = ms[r];
    }
    *ms_best = best;
    *gbs = 24.0 * (double)n / (best * 1e-3) / 1e9;
    /* keep the result alive */
    if (t.a[n / 2] != 1.0 + 3.0 * 2.0)
        fprintf(stderr, "%s: the triad computed %g\n", prog, t.a[n / 2]);
out:
    free(ms);
    free(t.a);
    free(t.b);
    free(t.c);
    return rc;
}
