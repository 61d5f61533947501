/* The host's processes: work spread over MPI ranks (docs/distributed.md).
 *
 * lightgraph started by `mpirun -np N` (in a build with MPI: meson option `mpi`, on where
 * Open MPI is found) runs as N ranks. Every rank parses the same command line and runs the
 * same graph; the work that is worth spreading is spread through the calls below, and rank 0
 * alone prints the report and writes output files and cache entries. Started any other way
 * (or built without MPI) there is one rank, and every call below does what one process
 * does, at no cost: nothing changes without mpirun.
 *
 * Collective calls. lg_dist_map, lg_dist_fixed, lg_dist_agree and lg_dist_bcast must be
 * made by every rank, in the same order, with the same counts (a graph run the same way on
 * every rank makes them so). A rank that failed on its own (a file its node could not read)
 * still reaches the next collective call with its failure (lg_dist_agree), so that no rank
 * waits forever; the failure's message reaches rank 0, which prints it.
 *
 * How the calls match. Every collective call opens with the same step: one MPI_Allreduce
 * of (the rank's status, the kind of call, the job's signature), and, only when a status
 * is not 0 or the kinds or signatures differ, one MPI_Allgather of every rank's (status,
 * kind, reason). So a rank in lg_dist_finish, lg_dist_agree or any other call meets the
 * others' next call whatever it is: every rank sees the failure, the calls other than
 * lg_dist_finish return it (their callers fail and go on to lg_dist_finish), and
 * lg_dist_finish repeats its step until every rank is in lg_dist_finish. A reason is sent
 * once and printed once by rank 0 ("lightgraph: rank R: why"; a failed job's reason comes
 * back in err, which the caller reports). A rank other than 0 is quiet: lg_dist_init
 * sends its stdout to /dev/null and its stderr to a file whose last line that is not a
 * warning is its reason when it fails without giving one.
 *
 * Threads: MPI is called from the thread that called lg_dist_init only. */
#ifndef LG_HOST_EXEC_DIST_H
#define LG_HOST_EXEC_DIST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "base/util.h"

/* main(): joins the job when started by mpirun (MPI_Init_thread, FUNNELED), else nothing.
 * Returns 0, or 1 after a message (MPI refused to start). Before any thread exists. */
int lg_dist_init(int *argc, char ***argv);
/* main(): the exit status every rank returns: the worst of every rank's `status` (so a
 * rank's failure is the job's), then MPI_Finalize. Without MPI returns status. */
int lg_dist_finish(int status);

int lg_dist_rank(void);  /* 0 .. size - 1; 0 without MPI */
int lg_dist_size(void);  /* ranks in the job; 1 without MPI */
bool lg_dist_root(void); /* rank 0: prints, writes files and cache entries */
/* Ranks that share this machine (MPI_COMM_TYPE_SHARED), >= 1: the host's pool takes
 * (online CPUs / local ranks) threads per rank unless LIGHTGRAPH_THREADS says otherwise. */
int lg_dist_local_size(void);
/* Inside an lg_dist_map item (a sweep's point) or an lg_dist_fixed range (a job's chunk):
 * nested calls run on this rank alone, every collective call as the local computation (as
 * in one process); so do calls from a thread other than lg_dist_init's. */
bool lg_dist_nested(void);

/* The worst (largest) of every rank's status: 0 when every rank passed 0. `why` is the
 * calling rank's reason when status != 0 (may be NULL); when any rank failed, rank 0
 * receives every failing rank's reason and prints it ("lightgraph: rank R: why"). */
int lg_dist_agree(int status, const char *why);

/* Whether every rank holds the same `value`: a cache lookup's answer (api_cache_get: the
 * hash of the entry a rank found, 0 for a miss), which must be one answer for the job, or a
 * rank that missed would enter a job alone. Returns 1 when every rank passed the same
 * value, 0 when they differ, -1 when a rank failed or is out of step (err then holds the
 * reason, as lg_dist_fixed's; the caller fails). One rank: 1. */
int lg_dist_same(uint64_t value, char *err, size_t err_size);

/* Copies `size` bytes at `data` from rank 0 to every rank (a reference image a sweep
 * rendered once). */
int lg_dist_bcast(void *data, size_t size);

/* Items of any size, one call per item. fn computes item `item` and appends its bytes to
 * `out` (an lg_str: binary bytes are fine); returns 0 or non-zero with a reason in err.
 * The items are handed out in chunks of `grain` (dynamic: a rank takes the next chunk when
 * its last is done; the calling rank works too). On success every rank's `res` holds all
 * items' bytes in item order: item i is res->data[res->off[i] .. res->off[i + 1]). With
 * `root_only`, only rank 0 receives them (others get res->n = 0): a sweep's images.
 * Results depend on the items only, never on the schedule. Returns 0, or 1 after the
 * failing rank's reason reached rank 0 ("NAME i on rank R: why"); then res is empty on
 * every rank. */
typedef struct lg_dist_result {
    uint64_t n;    /* items */
    uint64_t *off; /* n + 1 offsets into data */
    char *data;    /* owned; lg_dist_result_free */
} lg_dist_result;
typedef int (*lg_dist_item_fn)(void *ctx, uint64_t item, lg_str *out, char *err, size_t err_size);
int lg_dist_map(const char *what, uint64_t count, uint64_t grain, bool root_only,
                lg_dist_item_fn fn, void *ctx, lg_dist_result *res);
void lg_dist_result_free(lg_dist_result *res);

/* Fixed-size items run over the rank's own threads: the engine of lg_shard (host.h).
 * range(ctx, begin, end, items, err, err_size) computes items [begin, end) into `items`
 * and is called from one thread per rank at a time (hostapi.c spreads it over the pool).
 * On success `out` (count * item_bytes) holds every item on every rank. Returns 0, or 1
 * after the failing rank's reason reached rank 0, with `err` (err_size bytes) the reason
 * on every rank ("items B..E on rank R: why"). */
typedef int (*lg_dist_range_fn)(void *ctx, uint64_t begin, uint64_t end, void *items, char *err,
                                size_t err_size);
int lg_dist_fixed(const char *what, uint64_t count, uint64_t grain, uint64_t item_bytes, void *out,
                  lg_dist_range_fn range, void *ctx, char *err, size_t err_size);

/* lg_dist_fixed with chunk affinity (lg_shard_job.affinity, host.h): a non-zero `affinity`
 * names a family of jobs over the same items. The chunks' owners of the family's last job
 * (with this count and grain) are remembered on every rank; in the next job each rank first
 * takes its own former chunks, then steals the others' still unclaimed ones. 0 is
 * lg_dist_fixed. The result is the same; only where the chunks run differs. */
int lg_dist_fixed_family(const char *what, uint32_t affinity, uint64_t count, uint64_t grain,
                         uint64_t item_bytes, void *out, lg_dist_range_fn range, void *ctx,
                         char *err, size_t err_size);
/* This rank's chunks in its last lg_dist_fixed job of several ranks: `own` its former
 * chunks of the job's family, `stolen` another rank's former chunks, `fresh` chunks of a
 * job without a remembered family (dynamic chunks). Zeros after a job run alone. */
void lg_dist_fixed_placement(uint64_t *own, uint64_t *stolen, uint64_t *fresh);

#endif
