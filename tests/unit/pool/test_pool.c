/*
 * host/base/pool.c: the thread pool behind lg_host_api.parallel_for.
 *
 *   chunks        every index of [0, n) visited exactly once, chunk c = [c g, min(n, (c+1) g))
 *                 for pools of 1, 2, 7 and many sizes of n and grain
 *   edges         n = 0 (nothing runs), n < grain and a huge grain (one chunk, inline),
 *                 grain 0 refused, a chunk count above 2^32 - 1 refused
 *   determinism   a float reduction into per-chunk slots combined in chunk order gives
 *                 the same bits for pools of 1, 2 and 7
 *   parallel      a pool of 4 runs chunks on more than one thread
 *   nesting       a call from inside fn runs inline, in order, and completes
 *   env           LIGHTGRAPH_THREADS: valid values taken, invalid ones warned about
 */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/check.h"
#include "base/pool.h"

/* ---- chunks ---------------------------------------------------------------------------------- */

typedef struct visit_ctx {
    atomic_uint *hits; /* per index */
    size_t n, grain;
    atomic_uint bad; /* chunks whose bounds are not the documented ones */
    atomic_uint calls;
} visit_ctx;

static void visit(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    visit_ctx *v = arg;
    size_t want_end = (size_t)chunk * v->grain + v->grain;
    if (want_end > v->n)
        want_end = v->n;
    if (begin != (size_t)chunk * v->grain || end != want_end || begin >= end)
        atomic_fetch_add(&v->bad, 1u);
    for (size_t i = begin; i < end; i++)
        atomic_fetch_add(&v->hits[i], 1u);
    atomic_fetch_add(&v->calls, 1u);
}

static void test_chunks(lg_pool *p)
{
    static const size_t ns[] = { 1, 2, 3, 7, 64, 100, 1000, 4097, 100003 };
    static const size_t grains[] = { 1, 3, 64, 1000, 5000 };
    for (size_t a = 0; a < sizeof ns / sizeof ns[0]; a++) {
        for (size_t b = 0; b < sizeof grains / sizeof grains[0]; b++) {
            size_t n = ns[a], g = grains[b];
            if (n / g > 20000)
                continue; /* keep the test quick */
            visit_ctx v = { .n = n, .grain = g };
            v.hits = calloc(n, sizeof *v.hits);
            CHECK(lg_pool_run(p, n, g, visit, &v) == 0);
            size_t wrong = 0;
            for (size_t i = 0; i < n; i++)
                wrong += atomic_load(&v.hits[i]) != 1;
            CHECKF(wrong == 0, "pool %u, n %zu grain %zu: %zu indices not visited exactly once",
                   lg_pool_size(p), n, g, wrong);
            CHECKF(atomic_load(&v.bad) == 0, "pool %u, n %zu grain %zu: wrong chunk bounds",
                   lg_pool_size(p), n, g);
            CHECKF(atomic_load(&v.calls) == (n + g - 1) / g, "pool %u, n %zu grain %zu: %u calls",
                   lg_pool_size(p), n, g, atomic_load(&v.calls));
            free(v.hits);
        }
    }
}

/* ---- edges ----------------------------------------------------------------------------------- */

static void count_calls(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    visit_ctx *v = arg;
    atomic_fetch_add(&v->calls, 1u);
    if (chunk != 0 || begin != 0 || end != v->n)
        atomic_fetch_add(&v->bad, 1u);
}

static void test_edges(lg_pool *p)
{
    visit_ctx v = { .n = 0 };
    CHECK(lg_pool_run(p, 0, 16, count_calls, &v) == 0);
    CHECKF(atomic_load(&v.calls) == 0, "n = 0 ran %u chunks", atomic_load(&v.calls));

    v = (visit_ctx){ .n = 5 };
    CHECK(lg_pool_run(p, 5, 16, count_calls, &v) == 0);
    CHECKF(atomic_load(&v.calls) == 1 && atomic_load(&v.bad) == 0, "n < grain: one chunk [0, 5)");

    v = (visit_ctx){ .n = 123456 };
    CHECK(lg_pool_run(p, 123456, SIZE_MAX, count_calls, &v) == 0);
    CHECKF(atomic_load(&v.calls) == 1 && atomic_load(&v.bad) == 0, "huge grain: one chunk");

    v = (visit_ctx){ .n = 10 };
    CHECK(lg_pool_run(p, 10, 0, count_calls, &v) == -1);
    CHECK(lg_pool_run(p, SIZE_MAX, 1, count_calls, &v) == -1);
    CHECK(lg_pool_run(p, 10, 1, NULL, &v) == -1);
    CHECKF(atomic_load(&v.calls) == 0, "a refused call ran %u chunks", atomic_load(&v.calls));
}

/* ---- determinism ----------------------------------------------------------------------------- */

typedef struct sum_ctx {
    const float *x;
    float *slots;
} sum_ctx;

static void sum_chunk(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    sum_ctx *s = arg;
    float acc = 0.0f;
    for (size_t i = begin; i < end; i++)
        acc += s->x[i];
    s->slots[chunk] = acc;
    if (chunk % 7 == 3)
        usleep(50); /* shuffle which thread takes what */
}

static float reduce(lg_pool *p, const float *x, size_t n, size_t grain)
{
    size_t chunks = (n + grain - 1) / grain;
    sum_ctx s = { x, calloc(chunks, sizeof(float)) };
    CHECK(lg_pool_run(p, n, grain, sum_chunk, &s) == 0);
    float total = 0.0f;
    for (size_t c = 0; c < chunks; c++)
        total += s.slots[c];
    free(s.slots);
    return total;
}

static void test_determinism(void)
{
    const size_t n = 1000003, grain = 4099;
    float *x = malloc(n * sizeof *x);
    uint32_t seed = 12345;
    for (size_t i = 0; i < n; i++) {
        seed = seed * 1664525u + 1013904223u;
        /* wide dynamic range and both signs: float addition order shows */
        x[i] = (float)ldexp((double)(seed >> 8) / 16777216.0 - 0.5, (int)(seed % 40) - 20);
    }
    /* the plain loop over chunks, no pool */
    float want = 0.0f;
    for (size_t b = 0; b < n; b += grain) {
        float acc = 0.0f;
        for (size_t i = b; i < n && i < b + grain; i++)
            acc += x[i];
        want += acc;
    }
    static const uint32_t sizes[] = { 1, 2, 7 };
    for (size_t k = 0; k < 3; k++) {
        lg_pool *p = lg_pool_new(sizes[k], NULL);
        for (int rep = 0; rep < 5; rep++) {
            float got = reduce(p, x, n, grain);
            CHECKF(memcmp(&got, &want, sizeof got) == 0,
                   "pool of %u, run %d: sum %.9g, the serial chunked sum is %.9g", sizes[k], rep,
                   got, want);
        }
        lg_pool_free(p);
    }
    free(x);
}

/* ---- parallel -------------------------------------------------------------------------------- */

typedef struct who_ctx {
    pthread_t ids[64];
} who_ctx;

static void who(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    who_ctx *w = arg;
    w->ids[chunk] = pthread_self();
    usleep(2000);
}

static void test_parallel(void)
{
    lg_pool *p = lg_pool_new(4, NULL);
    CHECK(lg_pool_size(p) == 4);
    who_ctx w;
    memset(&w, 0, sizeof w);
    CHECK(lg_pool_run(p, 64, 1, who, &w) == 0);
    int distinct = 0;
    for (int i = 0; i < 64; i++) {
        int seen = 0;
        for (int j = 0; j < i; j++)
            seen |= pthread_equal(w.ids[i], w.ids[j]);
        distinct += !seen;
    }
    CHECKF(distinct > 1, "64 chunks of 2 ms ran on %d thread(s) of a pool of 4", distinct);
    lg_pool_free(p);
}

/* ---- nesting --------------------------------------------------------------------------------- */

typedef struct nest_ctx {
    lg_pool *p;
    atomic_uint inner_total;
    atomic_uint order_bad;
} nest_ctx;

typedef struct inner_ctx {
    nest_ctx *outer;
    uint32_t expect;
} inner_ctx;

static void inner(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    inner_ctx *in = arg;
    if (chunk != in->expect++) /* inline: chunks in order on this thread */
        atomic_fetch_add(&in->outer->order_bad, 1u);
    atomic_fetch_add(&in->outer->inner_total, (unsigned)(end - begin));
}

static void outer(void *arg, size_t begin, size_t end, uint32_t chunk)
{
    nest_ctx *o = arg;
    inner_ctx in = { o, 0 };
    CHECK(lg_pool_run(o->p, 100, 7, inner, &in) == 0);
}

static void test_nesting(void)
{
    lg_pool *p = lg_pool_new(3, NULL);
    nest_ctx o = { .p = p };
    CHECK(lg_pool_run(p, 12, 1, outer, &o) == 0);
    CHECKF(atomic_load(&o.inner_total) == 1200, "nested: %u of 1200 indices",
           atomic_load(&o.inner_total));
    CHECKF(atomic_load(&o.order_bad) == 0, "nested chunks out of order");
    lg_pool_free(p);
}

/* ---- env ------------------------------------------------------------------------------------- */

static void test_env(void)
{
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    char *w = NULL;
    setenv("LIGHTGRAPH_THREADS", "3", 1);
    CHECK(lg_pool_configured_size(&w) == 3 && !w);
    static const char *const bad[] = { "0", "-2", "abc", "4x", "100000" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        setenv("LIGHTGRAPH_THREADS", bad[i], 1);
        uint32_t s = lg_pool_configured_size(&w);
        CHECKF(s == (uint32_t)(cpus < 1 ? 1 : cpus), "'%s' gave %u threads", bad[i], s);
        CHECKF(w && strstr(w, "LIGHTGRAPH_THREADS") && strstr(w, bad[i]), "'%s': warning %s",
               bad[i], w ? w : "(none)");
        free(w);
    }
    unsetenv("LIGHTGRAPH_THREADS");
    CHECK(lg_pool_configured_size(&w) == (uint32_t)(cpus < 1 ? 1 : cpus) && !w);

    /* the ranks of one MPI job on this machine share its CPUs; the variable still wins */
    lg_pool_set_ranks_per_machine(2);
    long half = cpus / 2;
    CHECK(lg_pool_configured_size(&w) == (uint32_t)(half < 1 ? 1 : half) && !w);
    lg_pool_set_ranks_per_machine((uint32_t)cpus + 5);
    CHECK(lg_pool_configured_size(&w) == 1 && !w);
    setenv("LIGHTGRAPH_THREADS", "3", 1);
    CHECK(lg_pool_configured_size(&w) == 3 && !w);
    unsetenv("LIGHTGRAPH_THREADS");
    lg_pool_set_ranks_per_machine(0); /* the whole machine again */
    CHECK(lg_pool_configured_size(&w) == (uint32_t)(cpus < 1 ? 1 : cpus) && !w);

    /* the process-wide pool follows the variable, is made once and is never NULL */
    setenv("LIGHTGRAPH_THREADS", "2", 1);
    lg_pool *g = lg_pool_global(NULL);
    CHECK(g && lg_pool_size(g) == 2 && lg_pool_global(NULL) == g);
    test_chunks(g);
}

int main(void)
{
    static const uint32_t sizes[] = { 1, 2, 7 };
    for (size_t k = 0; k < 3; k++) {
        lg_pool *p = lg_pool_new(sizes[k], NULL);
        CHECKF(lg_pool_size(p) == sizes[k], "pool of %u has size %u", sizes[k], lg_pool_size(p));
        test_chunks(p);
        test_edges(p);
        lg_pool_free(p);
    }
    test_chunks(NULL); /* a NULL pool runs inline */
    test_determinism();
    test_parallel();
    test_nesting();
    test_env();
    return check_report("pool");
}
