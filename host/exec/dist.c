/* The host's processes (dist.h). This build's single-process implementation: one rank,
 * every collective call is the local computation. The MPI implementation replaces it where
 * the build has MPI. */
#include "exec/dist.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int dist_depth; /* lg_dist_map items running on this thread (nested calls) */

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

bool lg_dist_nested(void)
{
    return dist_depth > 0;
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

void lg_dist_result_free(lg_dist_result *res)
{
    free(res->off);
    free(res->data);
    memset(res, 0, sizeof *res);
}

int lg_dist_map(const char *what, uint64_t count, uint64_t grain, bool root_only,
                lg_dist_item_fn fn, void *ctx, lg_dist_result *res)
{
    (void)grain;
    (void)root_only;
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

int lg_dist_fixed(const char *what, uint64_t count, uint64_t grain, uint64_t item_bytes, void *out,
                  lg_dist_range_fn range, void *ctx, char *err, size_t err_size)
{
    (void)what;
    (void)grain;
    (void)item_bytes;
    if (count == 0)
        return 0;
    err[0] = 0;
    return range(ctx, 0, count, out, err, err_size) ? 1 : 0;
}
