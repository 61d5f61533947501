/* The host's processes (dist.h). Two implementations share this file: with LG_HAVE_MPI
 * (meson option `mpi`) the MPI one, which runs the single-process code whenever the process
 * was not started by mpirun, has one rank or is inside an lg_dist_map item; without it the
 * single-process one alone (one rank: every collective call is the local computation).
 * docs/distributed.md describes the protocol. */
#include "exec/dist.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int dist_depth; /* lg_dist_map items running on this thread (nested calls) */

bool lg_dist_nested(void)
{
    return dist_depth > 0;
}

void lg_dist_result_free(lg_dist_result *res)
{
    free(res->off);
    free(res->data);
    memset(res, 0, sizeof *res);
}

/* ---- one process ----------------------------------------------------------------------------- */

static int local_map(const char *what, uint64_t count, lg_dist_item_fn fn, void *ctx,
                     lg_dist_result *res)
{
    memset(res, 0, sizeof *res);
    res->off = lg_xcalloc(count + 1, sizeof *res->off);
    lg_str all = { 0 };
    char err[512];
    dist_depth++;
    for (uint64_t i = 0; i < count; i++) {
        err[0] = 0;
        if (fn(ctx, i, &all, err, sizeof err)) {
            dist_depth--;
            fprintf(stderr, "lightgraph: %s %llu: %s\n", what ? what : "item",
                    (unsigned long long)i, err[0] ? err : "failed");
            lg_str_free(&all);
            lg_dist_result_free(res);
            return 1;
        }
        res->off[i + 1] = all.len;
    }
    dist_depth--;
    res->n = count;
    res->data = all.s; /* may be NULL when every item is empty */
    return 0;
}

static int local_fixed(uint64_t count, void *out, lg_dist_range_fn range, void *ctx, char *err,
                       size_t err_size)
{
    if (count == 0)
        return 0;
    err[0] = 0;
    dist_depth++; /* a nested job inside range runs alone */
    int rc = range(ctx, 0, count, out, err, err_size) ? 1 : 0;
    dist_depth--;
    return rc;
}

#ifndef LG_HAVE_MPI

int lg_dist_init(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    return 0;
}

int lg_dist_finish(int status)
{
    return status;
}

int lg_dist_rank(void)
{
    return 0;
}

int lg_dist_size(void)
{
    return 1;
}

bool lg_dist_root(void)
{
    return true;
}

int lg_dist_local_size(void)
{
    return 1;
}

int lg_dist_agree(int status, const char *why)
{
    (void)why;
    return status;
}

int lg_dist_bcast(void *data, size_t size)
{
    (void)data;
    (void)size;
    return 0;
}

int lg_dist_same(uint64_t value, char *err, size_t err_size)
{
    (void)value;
    (void)err;
    (void)err_size;
    return 1;
}

int lg_dist_map(const char *what, uint64_t count, uint64_t grain, bool root_only,
                lg_dist_item_fn fn, void *ctx, lg_dist_result *res)
{
    (void)grain;
    (void)root_only;
    return local_map(what, count, fn, ctx, res);
}

int lg_dist_fixed(const char *what, uint64_t count, uint64_t grain, uint64_t item_bytes, void *out,
                  lg_dist_range_fn range, void *ctx, char *err, size_t err_size)
{
    (void)what;
    (void)grain;
    (void)item_bytes;
    return local_fixed(count, out, range, ctx, err, err_size);
}

int lg_dist_fixed_family(const char *what, uint32_t affinity, uint64_t count, uint64_t grain,
                         uint64_t item_bytes, void *out, lg_dist_range_fn range, void *ctx,
                         char *err, size_t err_size)
{
    (void)affinity;
    return lg_dist_fixed(what, count, grain, item_bytes, out, range, ctx, err, err_size);
}

void lg_dist_fixed_placement(uint64_t *own, uint64_t *stolen, uint64_t *fresh)
{
    *own = *stolen = *fresh = 0;
}

#else /* LG_HAVE_MPI */

#include <fcntl.h>
#include <limits.h>
#include <mpi.h>
#include <pthread.h>
#include <unistd.h>

/* ---- the job's state ------------------------------------------------------------------------- */

static bool d_on; /* MPI_Init was called (started by mpirun) */
static int d_rank, d_size = 1, d_local = 1;
static MPI_Comm d_comm;   /* a duplicate of MPI_COMM_WORLD: ours alone */
static MPI_Win d_win;     /* rank 0's chunk counter (dynamic chunks) */
static MPI_Win d_own_win; /* every rank's counter into its list of former chunks (affinity) */
static void families_forget(void);
static FILE *d_capture;    /* a non-root rank's stderr, read back for its reason */
static pthread_t d_thread; /* main()'s: the one that calls MPI */
static bool d_reported;    /* a failure's reasons already reached rank 0 */

/* The kinds of collective call. Every call opens with the same step (dist_step), so that a
 * rank in one call and a rank in another still match their MPI calls and see each other's
 * kind: that is how a rank that failed alone (and went on to lg_dist_finish) ends a job the
 * others are in instead of leaving them waiting. */
enum { K_AGREE = 1, K_BCAST, K_MAP, K_FIXED, K_SAME, K_FINISH };
static const char *kind_name(int k)
{
    switch (k) {
    case K_AGREE: return "an agreement";
    case K_BCAST: return "a broadcast";
    case K_MAP: return "a map of items";
    case K_FIXED: return "a job (lg_shard)";
    case K_SAME: return "a cache lookup";
    case K_FINISH: return "the end (lg_dist_finish)";
    default: return "an unknown call";
    }
}

#define WHY_MAX 480
typedef struct dist_rec {
    int32_t status, kind;
    char why[WHY_MAX];
} dist_rec;
static dist_rec *d_recs; /* every rank's record after a step that failed */
static bool d_step_ok;   /* the last failed step's kinds and signatures agreed */

/* Some word on every step: the worst status, whether every rank is in the same kind of call
 * with the same signature (a job's count and sizes), and, when any of that fails, every
 * rank's record (status, kind, reason) on every rank. A job's failure (lg_dist_fixed,
 * lg_dist_map: K_FIXED, K_MAP) always sends its reason; a rank's own reason (agree,
 * finish) is sent only while no failure has been gathered yet, so that the consequences
 * of a failure (the others' nodes failing with its reason) are not printed again.
 * Returns 0, or the worst status (>= 1). */
static int dist_step(int kind, uint64_t sig, int status, const char *why)
{
    bool job = kind == K_FIXED || kind == K_MAP;
    int64_t s = (int64_t)(sig >> 2);
    int64_t v[5] = { status, kind, -kind, s, -s };
    MPI_Allreduce(MPI_IN_PLACE, v, 5, MPI_INT64_T, MPI_MAX, d_comm);
    d_step_ok = v[1] == -v[2] && v[3] == -v[4];
    if (v[0] == 0 && d_step_ok)
        return 0;
    dist_rec mine = { .status = status, .kind = kind };
    if (status && why && (job || !d_reported))
        snprintf(mine.why, sizeof mine.why, "%s", why);
    MPI_Allgather(&mine, (int)sizeof mine, MPI_BYTE, d_recs, (int)sizeof mine, MPI_BYTE, d_comm);
    d_reported = true;
    return v[0] > 0 ? (int)(v[0] > 255 ? 255 : v[0]) : 1;
}

/* After a failed step: the reason in one line, the same on every rank (the lowest failing
 * rank's, or what was out of step). */
static void step_reason(char *err, size_t err_size)
{
    for (int r = 0; r < d_size; r++)
        if (d_recs[r].status && d_recs[r].why[0]) {
            /* a job's reason names its items and rank already */
            bool job = d_recs[r].kind == K_FIXED || d_recs[r].kind == K_MAP;
            if (job)
                snprintf(err, err_size, "%s", d_recs[r].why);
            else
                snprintf(err, err_size, "rank %d: %s", r, d_recs[r].why);
            return;
        }
    for (int r = 0; r < d_size; r++)
        if (d_recs[r].status) {
            snprintf(err, err_size, "rank %d failed (its reason was reported before)", r);
            return;
        }
    for (int r = 1; r < d_size; r++)
        if (d_recs[r].kind != d_recs[0].kind || !d_step_ok) {
            snprintf(err, err_size,
                     "the ranks are out of step: rank 0 is in %s, rank %d in %s (every rank "
                     "must run the same graph the same way)",
                     kind_name(d_recs[0].kind), r, kind_name(d_recs[r].kind));
            return;
        }
    snprintf(err, err_size, "the ranks disagree about a job's size");
}

/* Rank 0 prints the other ranks' reasons of a failed step (its own it printed itself). */
static void step_print(void)
{
    if (d_rank != 0)
        return;
    bool any = false;
    int same = 0; /* ranks whose reason an earlier rank gave word for word (a bad graph) */
    for (int r = 1; r < d_size; r++) {
        if (!d_recs[r].status || !d_recs[r].why[0])
            continue;
        /* bad usage or a bad graph (status 2) is the same command line and graph on every
         * rank: rank 0 said it already */
        if (d_recs[r].status == 2 && d_recs[0].status == 2)
            continue;
        bool seen = false;
        for (int q = 1; q < r && !seen; q++)
            seen = d_recs[q].status && strcmp(d_recs[q].why, d_recs[r].why) == 0;
        if (seen)
            same++;
        else
            fprintf(stderr, "lightgraph: rank %d: %s\n", r, d_recs[r].why);
        any = true;
    }
    if (same)
        fprintf(stderr, "lightgraph: (%d more rank%s gave the same reason)\n", same,
                same > 1 ? "s" : "");
    bool failed = false;
    for (int r = 0; r < d_size; r++)
        failed = failed || d_recs[r].status;
    /* a rank that failed goes out of step by design; only a step no rank failed is news */
    if (!any && !failed && !d_step_ok) {
        char why[WHY_MAX + 100];
        step_reason(why, sizeof why);
        fprintf(stderr, "lightgraph: %s\n", why);
    }
}

/* A non-root rank's reason: the last line it wrote to stderr (captured, not shown) that
 * is not a warning, without the program's name. */
static void captured_reason(char *why, size_t size)
{
    why[0] = 0;
    if (!d_capture)
        return;
    fflush(stderr);
    int fd = fileno(d_capture);
    off_t end = lseek(fd, 0, SEEK_END);
    if (end <= 0)
        return;
    char buf[4096];
    off_t from = end > (off_t)sizeof buf - 1 ? end - (off_t)sizeof buf + 1 : 0;
    ssize_t n = pread(fd, buf, (size_t)(end - from), from);
    if (n <= 0)
        return;
    buf[n] = 0;
    /* the last error line, else the last line that is not a warning (a graph error's
     * excerpt and caret follow its message) */
    char *line = NULL, *error = NULL;
    for (char *p = strtok(buf, "\n"); p; p = strtok(NULL, "\n")) {
        if (*p && !strstr(p, "warning:"))
            line = p;
        if (strstr(p, "error:"))
            error = p;
    }
    if (error)
        line = error;
    if (!line)
        return;
    if (strncmp(line, "lightgraph: ", 12) == 0)
        line += 12;
    if (strncmp(line, "error: ", 7) == 0)
        line += 7;
    snprintf(why, size, "%s", line);
}

/* ---- start, end, who is who ------------------------------------------------------------------ */

int lg_dist_init(int *argc, char ***argv)
{
    /* Only a process mpirun started joins a job: anything else does not even load MPI's
     * run-time (MPI_Init costs tens of milliseconds and would look for a launcher). */
    if (!getenv("OMPI_COMM_WORLD_SIZE") && !getenv("PMIX_RANK"))
        return 0;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        fprintf(stderr, "lightgraph: started by mpirun, but MPI_Init_thread failed\n");
        return 1;
    }
    d_on = true;
    d_thread = pthread_self();
    MPI_Comm_dup(MPI_COMM_WORLD, &d_comm);
    MPI_Comm_rank(d_comm, &d_rank);
    MPI_Comm_size(d_comm, &d_size);
    MPI_Comm local;
    MPI_Comm_split_type(d_comm, MPI_COMM_TYPE_SHARED, d_rank, MPI_INFO_NULL, &local);
    MPI_Comm_size(local, &d_local);
    MPI_Comm_free(&local);
    d_recs = lg_xcalloc((size_t)d_size, sizeof *d_recs);
    uint64_t *counter = NULL;
    MPI_Win_allocate(d_rank == 0 ? (MPI_Aint)sizeof(uint64_t) : 0, (int)sizeof(uint64_t),
                     MPI_INFO_NULL, d_comm, &counter, &d_win);
    if (d_rank == 0)
        *counter = 0;
    MPI_Win_lock_all(MPI_MODE_NOCHECK, d_win);
    uint64_t *own = NULL;
    MPI_Win_allocate((MPI_Aint)sizeof(uint64_t), (int)sizeof(uint64_t), MPI_INFO_NULL, d_comm, &own,
                     &d_own_win);
    *own = 0;
    MPI_Win_lock_all(MPI_MODE_NOCHECK, d_own_win);
    if (d_rank != 0) {
        /* Quiet: rank 0 prints the report; another rank's output would repeat it. Its
         * stderr goes to an unlinked file whose last line is its reason if it fails. */
        fflush(stdout);
        fflush(stderr);
        int null = open("/dev/null", O_WRONLY);
        if (null >= 0) {
            dup2(null, 1);
            close(null);
        }
        d_capture = tmpfile();
        if (d_capture)
            dup2(fileno(d_capture), 2);
    }
    if (provided < MPI_THREAD_FUNNELED) {
        fprintf(stderr, "lightgraph: MPI gives thread level %d, below FUNNELED\n", provided);
        return 1;
    }
    return 0;
}

int lg_dist_finish(int status)
{
    if (!d_on)
        return status;
    char why[WHY_MAX] = "";
    if (status && d_rank != 0)
        captured_reason(why, sizeof why);
    int worst = status;
    /* Until every rank is here: a rank that ended early meets the others' calls (each
     * returns a failure to its caller, which ends its command and comes here). */
    for (;;) {
        int rc = dist_step(K_FINISH, 0, status, why[0] ? why : "failed");
        if (rc == 0)
            break;
        worst = rc > worst ? rc : worst;
        step_print();
        bool all = true;
        for (int r = 0; r < d_size; r++)
            all = all && d_recs[r].kind == K_FINISH;
        if (all)
            break;
    }
    MPI_Win_unlock_all(d_win);
    MPI_Win_free(&d_win);
    MPI_Win_unlock_all(d_own_win);
    MPI_Win_free(&d_own_win);
    families_forget();
    MPI_Comm_free(&d_comm);
    MPI_Finalize();
    free(d_recs);
    d_recs = NULL;
    d_on = false;
    return worst;
}

int lg_dist_rank(void)
{
    return d_rank;
}

int lg_dist_size(void)
{
    return d_size;
}

bool lg_dist_root(void)
{
    return d_rank == 0;
}

int lg_dist_local_size(void)
{
    return d_local;
}

/* Whether a call runs on this rank alone: no job, one rank, inside an lg_dist_map item, or
 * on a thread other than main()'s (an lg_shard inside a node's lg_parallel_for chunk: MPI
 * is FUNNELED; every rank makes the same nested call, so every rank runs it alone). */
static bool alone(void)
{
    return !d_on || d_size == 1 || dist_depth > 0 || !pthread_equal(pthread_self(), d_thread);
}

int lg_dist_agree(int status, const char *why)
{
    if (alone())
        return status;
    char own[WHY_MAX] = "";
    if (status && !why && d_rank != 0) {
        captured_reason(own, sizeof own);
        why = own[0] ? own : "failed";
    }
    /* rank 0 printed its own reason already */
    int rc = dist_step(K_AGREE, 0, status, d_rank == 0 ? NULL : why);
    if (rc)
        step_print();
    return rc;
}

int lg_dist_bcast(void *data, size_t size)
{
    if (alone())
        return 0;
    if (dist_step(K_BCAST, size, 0, NULL)) {
        step_print();
        return 1;
    }
    for (size_t at = 0; at < size;) {
        int n = size - at > (size_t)INT_MAX ? INT_MAX : (int)(size - at);
        MPI_Bcast((char *)data + at, n, MPI_BYTE, 0, d_comm);
        at += (size_t)n;
    }
    return 0;
}

int lg_dist_same(uint64_t value, char *err, size_t err_size)
{
    if (alone())
        return 1;
    if (dist_step(K_SAME, 0, 0, NULL)) {
        step_reason(err, err_size);
        return -1;
    }
    uint64_t v[2] = { value, ~value };
    MPI_Allreduce(MPI_IN_PLACE, v, 2, MPI_UINT64_T, MPI_MAX, d_comm);
    return v[0] == value && v[1] == ~value ? 1 : 0;
}

/* ---- dynamic chunks -------------------------------------------------------------------------- */

/* Rank 0's counter: the next chunk. A failing rank sets it past any job's end, so that the
 * others stop at their next chunk. */
#define CHUNK_STOP (UINT64_C(1) << 62)

static uint64_t chunk_op(uint64_t v, MPI_Op op)
{
    uint64_t old = 0;
    MPI_Fetch_and_op(&v, &old, MPI_UINT64_T, 0, 0, op, d_win);
    MPI_Win_flush(0, d_win);
    return old;
}

static uint64_t chunk_take(void)
{
    return chunk_op(1, MPI_SUM);
}

/* Rank r's counter into its list of former chunks (a job with affinity): the owner takes
 * from it first, the others steal from it when their own lists are done. A fetch-and-add
 * hands each index to one rank only, so every chunk runs once. */
static uint64_t own_op(int r, uint64_t v, MPI_Op op)
{
    uint64_t old = 0;
    MPI_Fetch_and_op(&v, &old, MPI_UINT64_T, r, 0, op, d_own_win);
    MPI_Win_flush(r, d_own_win);
    return old;
}

/* Stops a job on every rank: rank 0's counter and every list's counter past any end. */
static void chunks_stop(void)
{
    chunk_op(CHUNK_STOP, MPI_REPLACE);
    for (int r = 0; r < d_size; r++)
        own_op(r, CHUNK_STOP, MPI_REPLACE);
}

/* A family's last job (lg_dist_fixed_family): the same on every rank, since every rank
 * makes the same calls and receives the same owner table. A few families at once (a
 * node's passes); the oldest gives way. */
typedef struct dist_family {
    uint32_t key; /* 0: a free slot */
    uint64_t count, grain, chunks, used;
    int *owner; /* chunks entries */
} dist_family;
#define FAMILIES 8
static dist_family d_fams[FAMILIES];
static uint64_t d_fam_clock;
static uint64_t d_last_own, d_last_stolen, d_last_fresh; /* lg_dist_fixed_placement */

static void family_drop(dist_family *f)
{
    free(f->owner);
    memset(f, 0, sizeof *f);
}

static void families_forget(void)
{
    for (int i = 0; i < FAMILIES; i++)
        family_drop(&d_fams[i]);
}

static dist_family *family_find(uint32_t key)
{
    for (int i = 0; key && i < FAMILIES; i++)
        if (d_fams[i].key == key)
            return &d_fams[i];
    return NULL;
}

/* Remembers `owner` (taken) as the family's last job. */
static void family_keep(uint32_t key, uint64_t count, uint64_t grain, uint64_t chunks, int *owner)
{
    dist_family *f = family_find(key);
    for (int i = 0; !f && i < FAMILIES; i++)
        if (!d_fams[i].key)
            f = &d_fams[i];
    for (int i = 0; !f && i < FAMILIES; i++)
        if (!f || d_fams[i].used < f->used)
            f = &d_fams[i];
    family_drop(f);
    *f = (dist_family){ .key = key,
                        .count = count,
                        .grain = grain,
                        .chunks = chunks,
                        .used = ++d_fam_clock,
                        .owner = owner };
}

void lg_dist_fixed_placement(uint64_t *own, uint64_t *stolen, uint64_t *fresh)
{
    *own = d_last_own;
    *stolen = d_last_stolen;
    *fresh = d_last_fresh;
}

/* A job's signature, checked on every rank by its opening step. */
static uint64_t job_sig(uint64_t a, uint64_t b, uint64_t c, uint64_t d)
{
    uint64_t h = 1469598103934665603u;
    uint64_t v[4] = { a, b, c, d };
    for (int i = 0; i < 4; i++)
        h = (h ^ v[i]) * 1099511628211u;
    return h;
}

/* Opens a job: rank 0 resets the counter (no rank takes a chunk before every rank passed
 * the step, rank 0 included), and a rank that failed elsewhere ends it before it starts. */
static int job_open(int kind, uint64_t sig, char *err, size_t err_size)
{
    if (d_rank == 0)
        chunk_op(0, MPI_REPLACE);
    own_op(d_rank, 0, MPI_REPLACE);
    if (dist_step(kind, sig, 0, NULL) == 0)
        return 0;
    static const char head[] = "the job did not start: ";
    snprintf(err, err_size, "%s", head);
    if (err_size > sizeof head)
        step_reason(err + sizeof head - 1, err_size - sizeof head + 1);
    return 1;
}

/* "PREFIX: why" -> "PREFIX on rank R: why" (the items named first, as in one process). */
static void with_rank(char *err, size_t err_size)
{
    char tmp[WHY_MAX];
    const char *colon = strstr(err, ": ");
    if (colon)
        snprintf(tmp, sizeof tmp, "%.*s on rank %d%s", (int)(colon - err), err, d_rank, colon);
    else
        snprintf(tmp, sizeof tmp, "%s on rank %d", err[0] ? err : "failed", d_rank);
    snprintf(err, err_size, "%s", tmp);
}

/* Every chunk's rank, the same on every rank: owner[c] = the rank that computed chunk c. */
static int *chunk_owners(const int *mine, uint64_t chunks)
{
    int *all = lg_xmalloc((size_t)chunks * sizeof *all);
    for (uint64_t at = 0; at < chunks;) {
        int n = chunks - at > (uint64_t)INT_MAX ? INT_MAX : (int)(chunks - at);
        MPI_Allreduce(mine + at, all + at, n, MPI_INT, MPI_MAX, d_comm);
        at += (uint64_t)n;
    }
    return all;
}

/* The chunks of a job with a remembered family: this rank's former chunks first, then the
 * other ranks' lists, from the next rank on (each rank starts its stealing elsewhere). Sets
 * mine[c] for the chunks run; returns non-zero when a chunk failed (the job stopped). */
static int family_run(const dist_family *f, uint64_t count, uint64_t grain, uint64_t item_bytes,
                      void *out, lg_dist_range_fn range, void *ctx, int *mine, char *why,
                      size_t why_size)
{
    /* every rank's list of former chunks, in chunk order: list[start[r] .. start[r + 1]) */
    uint64_t *start = lg_xcalloc((size_t)d_size + 1, sizeof *start);
    uint64_t *list = lg_xmalloc((size_t)f->chunks * sizeof *list);
    for (uint64_t c = 0; c < f->chunks; c++)
        start[f->owner[c] + 1]++;
    for (int r = 0; r < d_size; r++)
        start[r + 1] += start[r];
    uint64_t *fill = lg_xmalloc((size_t)d_size * sizeof *fill);
    memcpy(fill, start, (size_t)d_size * sizeof *fill);
    for (uint64_t c = 0; c < f->chunks; c++)
        list[fill[f->owner[c]]++] = c;
    free(fill);
    int failed = 0;
    bool stop = false;
    for (int k = 0; k < d_size && !stop && !failed; k++) {
        int v = (d_rank + k) % d_size;
        uint64_t n = start[v + 1] - start[v];
        for (;;) {
            uint64_t i = own_op(v, 1, MPI_SUM);
            if (i >= CHUNK_STOP)
                stop = true;
            if (i >= n)
                break;
            uint64_t c = list[start[v] + i];
            uint64_t b = c * grain, e = b + grain < count ? b + grain : count;
            mine[c] = d_rank;
            if (k == 0)
                d_last_own++;
            else
                d_last_stolen++;
            why[0] = 0;
            dist_depth++;
            int bad = range(ctx, b, e, (char *)out + b * item_bytes, why, why_size);
            dist_depth--;
            if (bad) {
                failed = 1;
                chunks_stop();
                break;
            }
        }
    }
    free(start);
    free(list);
    return failed;
}

int lg_dist_fixed(const char *what, uint64_t count, uint64_t grain, uint64_t item_bytes, void *out,
                  lg_dist_range_fn range, void *ctx, char *err, size_t err_size)
{
    return lg_dist_fixed_family(what, 0, count, grain, item_bytes, out, range, ctx, err, err_size);
}

int lg_dist_fixed_family(const char *what, uint32_t affinity, uint64_t count, uint64_t grain,
                         uint64_t item_bytes, void *out, lg_dist_range_fn range, void *ctx,
                         char *err, size_t err_size)
{
    (void)what;
    if (alone())
        return local_fixed(count, out, range, ctx, err, err_size);
    err[0] = 0;
    d_last_own = d_last_stolen = d_last_fresh = 0;
    if (job_open(K_FIXED, job_sig(count, grain, item_bytes, affinity), err, err_size))
        return 1;
    /* A family whose items or chunks changed starts afresh. */
    dist_family *fam = family_find(affinity);
    if (fam && (fam->count != count || fam->grain != grain)) {
        family_drop(fam);
        fam = NULL;
    }
    if (count == 0)
        return 0;
    uint64_t chunks = grain ? (count + grain - 1) / grain : 0;
    /* A job MPI cannot count in ints (items per rank, an item's bytes) runs on every rank
     * alone: the same bits, only slower. So does a job of one chunk. */
    bool local = grain == 0 || chunks <= 1 || count > (uint64_t)INT_MAX ||
                 item_bytes > (uint64_t)INT_MAX;
    char why[WHY_MAX] = "";
    int failed = 0;
    int *mine = NULL;
    if (local) {
        failed = local_fixed(count, out, range, ctx, why, sizeof why);
    } else {
        mine = lg_xmalloc((size_t)chunks * sizeof *mine);
        for (uint64_t c = 0; c < chunks; c++)
            mine[c] = -1;
        if (fam)
            failed = family_run(fam, count, grain, item_bytes, out, range, ctx, mine, why,
                                sizeof why);
        else
            for (;;) {
                uint64_t c = chunk_take();
                if (c >= chunks)
                    break;
                uint64_t b = c * grain, e = b + grain < count ? b + grain : count;
                mine[c] = d_rank;
                d_last_fresh++;
                why[0] = 0;
                dist_depth++;
                int bad = range(ctx, b, e, (char *)out + b * item_bytes, why, sizeof why);
                dist_depth--;
                if (bad) {
                    failed = 1;
                    chunks_stop();
                    break;
                }
            }
    }
    if (failed)
        with_rank(why, sizeof why);
    if (dist_step(K_FIXED, 0, failed, why)) {
        step_reason(err, err_size);
        if (fam)
            family_drop(fam); /* every rank saw the failure: every rank forgets */
        free(mine);
        return 1;
    }
    if (local)
        return 0;
    /* The gather: each rank's chunks packed in chunk order, every rank receives all and
     * puts each chunk at its place. Counts in items (a contiguous type of item_bytes). */
    int *owner = chunk_owners(mine, chunks);
    int *counts = lg_xcalloc((size_t)d_size, sizeof *counts);
    int *displs = lg_xcalloc((size_t)d_size, sizeof *displs);
    for (uint64_t c = 0; c < chunks; c++) {
        uint64_t n = c + 1 < chunks ? grain : count - c * grain;
        counts[owner[c]] += (int)n;
    }
    for (int r = 1; r < d_size; r++)
        displs[r] = displs[r - 1] + counts[r - 1];
    MPI_Datatype item;
    MPI_Type_contiguous((int)item_bytes, MPI_BYTE, &item);
    MPI_Type_commit(&item);
    char *send = lg_xmalloc((size_t)counts[d_rank] * item_bytes + 1);
    char *recv = lg_xmalloc((size_t)(count * item_bytes));
    size_t at = 0;
    for (uint64_t c = 0; c < chunks; c++)
        if (owner[c] == d_rank) {
            uint64_t n = c + 1 < chunks ? grain : count - c * grain;
            memcpy(send + at, (char *)out + c * grain * item_bytes, (size_t)(n * item_bytes));
            at += (size_t)(n * item_bytes);
        }
    MPI_Allgatherv(send, counts[d_rank], item, recv, counts, displs, item, d_comm);
    for (uint64_t c = 0; c < chunks; c++) {
        uint64_t n = c + 1 < chunks ? grain : count - c * grain;
        int r = owner[c];
        if (r != d_rank)
            memcpy((char *)out + c * grain * item_bytes, recv + (size_t)displs[r] * item_bytes,
                   (size_t)(n * item_bytes));
        displs[r] += (int)n;
    }
    MPI_Type_free(&item);
    free(send);
    free(recv);
    free(counts);
    free(displs);
    if (affinity)
        family_keep(affinity, count, grain, chunks, owner); /* takes owner */
    else
        free(owner);
    free(mine);
    return 0;
}

int lg_dist_map(const char *what, uint64_t count, uint64_t grain, bool root_only,
                lg_dist_item_fn fn, void *ctx, lg_dist_result *res)
{
    if (alone())
        return local_map(what, count, fn, ctx, res);
    memset(res, 0, sizeof *res);
    char err[WHY_MAX + 100] = "";
    if (job_open(K_MAP, job_sig(count, grain, root_only, 0), err, sizeof err)) {
        if (d_rank == 0)
            fprintf(stderr, "lightgraph: %s: %s\n", what ? what : "items", err);
        return 1;
    }
    if (grain == 0)
        grain = 1;
    uint64_t chunks = (count + grain - 1) / grain;
    int *mine = lg_xmalloc((size_t)chunks * sizeof *mine + 1);
    uint64_t *len = lg_xcalloc((size_t)count + 1, sizeof *len);
    for (uint64_t c = 0; c < chunks; c++)
        mine[c] = -1;
    lg_str own = { 0 };
    char why[WHY_MAX] = "", item_why[WHY_MAX - 64];
    int failed = 0;
    for (;;) {
        uint64_t c = chunk_take();
        if (c >= chunks)
            break;
        mine[c] = d_rank;
        uint64_t b = c * grain, e = b + grain < count ? b + grain : count;
        for (uint64_t i = b; i < e && !failed; i++) {
            size_t before = own.len;
            item_why[0] = 0;
            dist_depth++;
            failed = fn(ctx, i, &own, item_why, sizeof item_why) ? 1 : 0;
            dist_depth--;
            len[i] = own.len - before;
            if (failed)
                snprintf(why, sizeof why, "%s %llu on rank %d: %s", what ? what : "item",
                         (unsigned long long)i, d_rank, item_why[0] ? item_why : "failed");
        }
        if (failed) {
            chunk_op(CHUNK_STOP, MPI_REPLACE);
            break;
        }
    }
    int rc = dist_step(K_MAP, 0, failed, why);
    if (rc) {
        step_reason(err, sizeof err);
        if (d_rank == 0)
            fprintf(stderr, "lightgraph: %s\n", err);
        free(mine);
        free(len);
        lg_str_free(&own);
        return 1;
    }
    int *owner = chunk_owners(mine, chunks);
    /* every item's length everywhere (the offsets), then the bytes */
    uint64_t *all_len = lg_xcalloc((size_t)count + 1, sizeof *all_len);
    for (uint64_t at = 0; at < count;) {
        int n = count - at > (uint64_t)INT_MAX ? INT_MAX : (int)(count - at);
        MPI_Allreduce(len + at, all_len + at, n, MPI_UINT64_T, MPI_SUM, d_comm);
        at += (uint64_t)n;
    }
    uint64_t *bytes = lg_xcalloc((size_t)d_size, sizeof *bytes);
    uint64_t total = 0;
    for (uint64_t i = 0; i < count; i++) {
        bytes[owner[i / grain]] += all_len[i];
        total += all_len[i];
    }
    int *counts = lg_xcalloc((size_t)d_size, sizeof *counts);
    int *displs = lg_xcalloc((size_t)d_size, sizeof *displs);
    bool fits = total <= (uint64_t)INT_MAX;
    for (int r = 0; fits && r < d_size; r++) {
        counts[r] = (int)bytes[r];
        displs[r] = r ? displs[r - 1] + counts[r - 1] : 0;
    }
    rc = 0;
    if (!fits) {
        if (d_rank == 0)
            fprintf(stderr,
                    "lightgraph: %s: %llu bytes of results are more than one gather "
                    "moves (2 GiB)\n",
                    what ? what : "items", (unsigned long long)total);
        rc = 1;
    } else {
        bool get = !root_only || d_rank == 0;
        char *recv = get ? lg_xmalloc((size_t)total + 1) : NULL;
        if (root_only)
            MPI_Gatherv(own.s ? own.s : "", (int)own.len, MPI_BYTE, recv, counts, displs, MPI_BYTE,
                        0, d_comm);
        else
            MPI_Allgatherv(own.s ? own.s : "", (int)own.len, MPI_BYTE, recv, counts, displs,
                           MPI_BYTE, d_comm);
        if (get) {
            /* items in order: chunk c's items are contiguous in its rank's part */
            res->off = lg_xcalloc((size_t)count + 1, sizeof *res->off);
            res->data = lg_xmalloc((size_t)total + 1);
            for (uint64_t i = 0; i < count; i++)
                res->off[i + 1] = res->off[i] + all_len[i];
            for (uint64_t c = 0; c < chunks; c++) {
                uint64_t b = c * grain, e = b + grain < count ? b + grain : count;
                int r = owner[c];
                size_t n = (size_t)(res->off[e] - res->off[b]);
                memcpy(res->data + res->off[b], recv + displs[r], n);
                displs[r] += (int)n;
            }
            res->n = count;
        }
        free(recv);
    }
    free(counts);
    free(displs);
    free(bytes);
    free(all_len);
    free(owner);
    free(mine);
    free(len);
    lg_str_free(&own);
    return rc;
}

#endif /* LG_HAVE_MPI */
