/* tools/bench_dist.c: the MPI layer's own costs (host/exec/dist.h, docs/distributed.md),
 * run by tools/bench_distributed.py as one process and under mpirun with 2 and 3 ranks.
 *
 *   lg_bench_dist [REPS]
 *
 * prints, on rank 0, one line per measurement (the median of REPS jobs, each timed from
 * before the call to after it on rank 0, with a barrier-like agreement before each):
 *
 *   empty_job_us CHUNKS US      an lg_dist_fixed job of CHUNKS chunks of 8-byte items whose
 *                               run does nothing: the opening step, the hand-out of every
 *                               chunk through rank 0's counter, the closing step and the
 *                               gather
 *   gather_ms MIB MS            a job of MIB MiB in 64 chunks whose run does nothing: the
 *                               merge (pack, MPI_Allgatherv, unpack) dominates
 *   agree_us US                 lg_dist_agree(0): one collective step
 *   map_us ITEMS US             lg_dist_map of ITEMS one-byte items, grain 1
 *
 * Nothing here is a test: the numbers depend on the machine and its load. */
#include "exec/dist.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int nothing(void *ctx, uint64_t b, uint64_t e, void *items, char *err, size_t n)
{
    (void)ctx;
    (void)b;
    (void)e;
    (void)items;
    (void)err;
    (void)n;
    return 0;
}

static int one_byte(void *ctx, uint64_t i, lg_str *out, char *err, size_t n)
{
    (void)ctx;
    (void)err;
    (void)n;
    lg_str_addc(out, (char)i);
    return 0;
}

static double median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, cmp_double);
    return t[n / 2];
}

static double time_fixed(uint64_t count, uint64_t grain, uint64_t item_bytes, int reps)
{
    char *out = calloc(count * item_bytes + 1, 1);
    double *t = calloc((size_t)reps, sizeof *t);
    char err[256];
    for (int r = 0; r < reps; r++) {
        lg_dist_agree(0, NULL);
        double t0 = now();
        if (lg_dist_fixed("items", count, grain, item_bytes, out, nothing, NULL, err, sizeof err))
            fprintf(stderr, "lg_bench_dist: %s\n", err);
        t[r] = now() - t0;
    }
    double m = median(t, reps);
    free(t);
    free(out);
    return m;
}

int main(int argc, char **argv)
{
    if (lg_dist_init(&argc, &argv))
        return 1;
    int reps = argc > 1 ? atoi(argv[1]) : 21;
    if (reps < 1)
        reps = 1;
    bool root = lg_dist_root();
    if (root)
        printf("ranks %d\n", lg_dist_size());
    static const uint64_t chunks[] = { 2, 16, 128, 1024 };
    for (size_t i = 0; i < sizeof chunks / sizeof chunks[0]; i++) {
        double s = time_fixed(chunks[i] * 4, 4, 8, reps);
        if (root)
            printf("empty_job_us %llu %.1f\n", (unsigned long long)chunks[i], s * 1e6);
    }
    static const uint64_t mib[] = { 1, 16, 64 };
    for (size_t i = 0; i < sizeof mib / sizeof mib[0]; i++) {
        uint64_t bytes = mib[i] << 20, item = 4096;
        double s = time_fixed(bytes / item, bytes / item / 64, item, reps < 7 ? reps : 7);
        if (root)
            printf("gather_ms %llu %.2f\n", (unsigned long long)mib[i], s * 1e3);
    }
    double *t = calloc((size_t)reps, sizeof *t);
    for (int r = 0; r < reps; r++) {
        double t0 = now();
        lg_dist_agree(0, NULL);
        t[r] = now() - t0;
    }
    if (root)
        printf("agree_us %.1f\n", median(t, reps) * 1e6);
    for (int r = 0; r < reps; r++) {
        lg_dist_result res;
        lg_dist_agree(0, NULL);
        double t0 = now();
        lg_dist_map("item", 256, 1, false, one_byte, NULL, &res);
        t[r] = now() - t0;
        lg_dist_result_free(&res);
    }
    if (root)
        printf("map_us 256 %.1f\n", median(t, reps) * 1e6);
    free(t);
    fflush(stdout);
    return lg_dist_finish(0);
}
