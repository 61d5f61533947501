/*
 * host/base/pool.h: the host's CPU thread pool, behind lg_host_api.parallel_for (see
 * sdk/include/lightgraph/host.h, "CPU parallelism", for the contract plugins see).
 *
 * A pool of `size` participants: size - 1 worker threads plus the thread that calls
 * lg_pool_run, which works too. lg_pool_run splits [0, n) into chunks of `grain` indices
 * (the last one shorter): chunk c is [c * grain, min(n, (c + 1) * grain)). The split
 * depends on n and grain only, never on the pool's size, so per-chunk results combined in
 * chunk order are the same whatever the number of threads. Chunks are handed out in
 * increasing order from an atomic counter; which thread runs which chunk is not fixed.
 *
 * One process-wide pool serves the plugins (lg_pool_global): made on first use with
 * LIGHTGRAPH_THREADS threads, or one per online CPU; joined at exit. Tests make their own
 * pools of chosen sizes with lg_pool_new.
 */
#ifndef LG_HOST_POOL_H
#define LG_HOST_POOL_H

#include <stddef.h>
#include <stdint.h>

typedef struct lg_pool lg_pool;

typedef void (*lg_pool_fn)(void *ctx, size_t begin, size_t end, uint32_t chunk);

/* Hard upper bound on a pool's size (LIGHTGRAPH_THREADS above it is refused). */
#define LG_POOL_MAX_THREADS 256u

/* A pool of `size` participants (>= 1; the caller of lg_pool_run counts as one). If a
 * thread cannot be started the pool is smaller, and *warning (if not NULL) receives a
 * malloc'd message saying so (caller frees). NULL only when out of memory. */
lg_pool *lg_pool_new(uint32_t size, char **warning);
/* Stops and joins the workers; pool may be NULL. Not while lg_pool_run runs. */
void lg_pool_free(lg_pool *pool);
/* Participants, >= 1. */
uint32_t lg_pool_size(const lg_pool *pool);

/* Runs fn(ctx, begin, end, chunk) for every chunk of [0, n) and returns when all are done.
 * n == 0 runs nothing. Returns 0, or -1 (nothing run) when grain is 0 or the chunk count
 * exceeds UINT32_MAX. Calls from several threads are serialised; a call from inside fn
 * (nesting) runs its chunks on the calling thread, in order. */
int lg_pool_run(lg_pool *pool, size_t n, size_t grain, lg_pool_fn fn, void *ctx);

/* The size the process-wide pool has or will have: LIGHTGRAPH_THREADS when it is an
 * integer in 1..LG_POOL_MAX_THREADS, else sysconf(_SC_NPROCESSORS_ONLN) divided by the
 * processes sharing this machine (lg_pool_set_ranks_per_machine; at least 1). When the
 * variable is set but invalid, *warning (if not NULL) receives a malloc'd message (caller
 * frees). */
uint32_t lg_pool_configured_size(char **warning);
/* main(), before the pool exists: `ranks` processes of one MPI job share this machine
 * (host/exec/dist.h, lg_dist_local_size), so that each takes its share of the CPUs by
 * default. 0 or 1: the whole machine (the default). */
void lg_pool_set_ranks_per_machine(uint32_t ranks);
/* The process-wide pool, made on the first call (thread-safe) and joined at exit. Never
 * NULL: when memory is short it is a pool of one (the caller). *warning as lg_pool_new's,
 * given to the first caller only. */
lg_pool *lg_pool_global(char **warning);

#endif
