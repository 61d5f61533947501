/*
 * The host's CPU thread pool (pool.h). Deliberately small: one job at a time, chunks
 * handed out from an atomic counter, workers asleep on a condition variable between
 * jobs. A job of one chunk, a pool of one, or a nested call runs on the calling thread
 * without waking anybody, so that small images pay nothing for the pool.
 */
#include "base/pool.h"

#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

struct lg_pool {
    pthread_mutex_t run_lock; /* one lg_pool_run at a time */
    pthread_mutex_t lock;     /* the fields below */
    pthread_cond_t wake;      /* a new job, or quit */
    pthread_cond_t idle;      /* busy reached 0 */
    pthread_t *threads;
    uint32_t n_workers;  /* threads started (size - 1) */
    uint64_t generation; /* incremented per job */
    bool quit;
    uint32_t busy; /* workers still in the current job */
    /* the current job */
    lg_pool_fn fn;
    void *ctx;
    size_t n, grain;
    uint32_t chunks;
    atomic_uint next; /* next chunk to hand out */
};

/* Set on pool threads, and on a caller while it runs a job: a nested lg_pool_run then
 * runs inline instead of waiting for a job that waits for it. */
static _Thread_local bool in_job;

static void run_chunks(lg_pool *p)
{
    for (;;) {
        uint32_t c = atomic_fetch_add_explicit(&p->next, 1u, memory_order_relaxed);
        if (c >= p->chunks)
            return;
        size_t begin = (size_t)c * p->grain;
        size_t end = p->n - begin > p->grain ? begin + p->grain : p->n;
        p->fn(p->ctx, begin, end, c);
    }
}

static void *worker(void *arg)
{
    lg_pool *p = arg;
    in_job = true;
    uint64_t seen = 0;
    pthread_mutex_lock(&p->lock);
    for (;;) {
        while (!p->quit && p->generation == seen)
            pthread_cond_wait(&p->wake, &p->lock);
        if (p->quit)
            break;
        seen = p->generation;
        pthread_mutex_unlock(&p->lock);
        run_chunks(p);
        pthread_mutex_lock(&p->lock);
        if (--p->busy == 0)
            pthread_cond_signal(&p->idle);
    }
    pthread_mutex_unlock(&p->lock);
    return NULL;
}

static void pool_init_sync(lg_pool *p)
{
    pthread_mutex_init(&p->run_lock, NULL);
    pthread_mutex_init(&p->lock, NULL);
    pthread_cond_init(&p->wake, NULL);
    pthread_cond_init(&p->idle, NULL);
    atomic_init(&p->next, 0u);
}

lg_pool *lg_pool_new(uint32_t size, char **warning)
{
    if (warning)
        *warning = NULL;
    if (size < 1)
        size = 1;
    if (size > LG_POOL_MAX_THREADS)
        size = LG_POOL_MAX_THREADS;
    lg_pool *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    pool_init_sync(p);
    if (size > 1) {
        p->threads = calloc(size - 1, sizeof *p->threads);
        if (!p->threads) {
            lg_pool_free(p);
            return NULL;
        }
    }
    for (uint32_t i = 0; i + 1 < size; i++) {
        int e = pthread_create(&p->threads[i], NULL, worker, p);
        if (e) {
            if (warning && asprintf(warning,
                                    "CPU thread pool: started %u of %u threads "
                                    "(pthread_create: %s); running with %u",
                                    i, size - 1, strerror(e), i + 1) < 0)
                *warning = NULL;
            break;
        }
        p->n_workers++;
    }
    return p;
}

void lg_pool_free(lg_pool *p)
{
    if (!p)
        return;
    pthread_mutex_lock(&p->lock);
    p->quit = true;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->lock);
    for (uint32_t i = 0; i < p->n_workers; i++)
        pthread_join(p->threads[i], NULL);
    free(p->threads);
    pthread_cond_destroy(&p->wake);
    pthread_cond_destroy(&p->idle);
    pthread_mutex_destroy(&p->lock);
    pthread_mutex_destroy(&p->run_lock);
    free(p);
}

uint32_t lg_pool_size(const lg_pool *p)
{
    return p ? p->n_workers + 1 : 1;
}

int lg_pool_run(lg_pool *p, size_t n, size_t grain, lg_pool_fn fn, void *ctx)
{
    if (grain == 0 || !fn)
        return -1;
    if (n == 0)
        return 0;
    size_t chunks = n / grain + (n % grain != 0);
    if (chunks > UINT32_MAX)
        return -1;

    if (!p || p->n_workers == 0 || chunks == 1 || in_job) {
        /* inline, in chunk order */
        for (size_t c = 0; c < chunks; c++) {
            size_t begin = c * grain;
            fn(ctx, begin, n - begin > grain ? begin + grain : n, (uint32_t)c);
        }
        return 0;
    }

    pthread_mutex_lock(&p->run_lock);
    pthread_mutex_lock(&p->lock);
    p->fn = fn;
    p->ctx = ctx;
    p->n = n;
    p->grain = grain;
    p->chunks = (uint32_t)chunks;
    atomic_store_explicit(&p->next, 0u, memory_order_relaxed);
    /* Every worker wakes, even when there are fewer chunks than workers: the ones that
     * find the counter past the end just report back. */
    p->busy = p->n_workers;
    p->generation++;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->lock);

    in_job = true;
    run_chunks(p);
    in_job = false;

    /* Every worker must have left run_chunks before the job's fields change again (and
     * before the caller's ctx goes out of scope). */
    pthread_mutex_lock(&p->lock);
    while (p->busy > 0)
        pthread_cond_wait(&p->idle, &p->lock);
    pthread_mutex_unlock(&p->lock);
    pthread_mutex_unlock(&p->run_lock);
    return 0;
}

/* ---- the process-wide pool ------------------------------------------------------------------- */

static uint32_t ranks_per_machine = 1;

void lg_pool_set_ranks_per_machine(uint32_t ranks)
{
    ranks_per_machine = ranks ? ranks : 1;
}

uint32_t lg_pool_configured_size(char **warning)
{
    if (warning)
        *warning = NULL;
    long cpus = sysconf(_SC_NPROCESSORS_ONLN) / (long)ranks_per_machine;
    uint32_t def = cpus < 1                           ? 1u
                   : cpus > (long)LG_POOL_MAX_THREADS ? LG_POOL_MAX_THREADS
                                                      : (uint32_t)cpus;
    const char *env = getenv("LIGHTGRAPH_THREADS");
    if (!env || !*env)
        return def;
    char *end;
    errno = 0;
    long v = strtol(env, &end, 10);
    if (errno || *end || v < 1 || v > (long)LG_POOL_MAX_THREADS) {
        if (warning && asprintf(warning,
                                "LIGHTGRAPH_THREADS='%s' is not an integer in 1..%u; "
                                "using %u (the online CPUs%s)",
                                env, LG_POOL_MAX_THREADS, def,
                                ranks_per_machine > 1 ? " over this machine's ranks" : "") < 0)
            *warning = NULL;
        return def;
    }
    return (uint32_t)v;
}

static pthread_once_t global_once = PTHREAD_ONCE_INIT;
static lg_pool *global_pool;
static char *global_warning;
static pid_t global_pid;

static void global_free(void)
{
    /* A forked child (the plugin scanner) has no workers to join. */
    if (global_pool && getpid() == global_pid)
        lg_pool_free(global_pool);
    global_pool = NULL;
}

static void global_make(void)
{
    char *w1 = NULL, *w2 = NULL;
    uint32_t size = lg_pool_configured_size(&w1);
    global_pool = lg_pool_new(size, &w2);
    global_pid = getpid();
    if (w1 && w2) {
        if (asprintf(&global_warning, "%s; %s", w1, w2) < 0)
            global_warning = NULL;
        free(w1);
        free(w2);
    } else {
        global_warning = w1 ? w1 : w2;
    }
    if (global_pool)
        atexit(global_free);
}

lg_pool *lg_pool_global(char **warning)
{
    /* Out of memory at start-up: a pool of one (no workers), which lg_pool_run runs
     * inline without touching its locks. */
    static lg_pool fallback;
    pthread_once(&global_once, global_make);
    if (warning) {
        /* handed over once; pthread_once ordered the write before this read */
        static atomic_flag given = ATOMIC_FLAG_INIT;
        *warning = atomic_flag_test_and_set(&given) ? NULL : global_warning;
    }
    return global_pool ? global_pool : &fallback;
}
