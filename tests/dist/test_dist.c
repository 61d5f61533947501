/* tests/dist/test_dist.c: the host's MPI layer (host/exec/dist.h) on its own, run as one
 * process and under tests/dist/mpirun.sh with 2 and 3 ranks (oversubscribed).
 *
 *   test_dist basic   lg_dist_fixed and lg_dist_map give every item, in item order, on
 *                     every rank (root_only: on rank 0), whatever the schedule (items of
 *                     uneven cost); bcast; agree; a job after a job
 *   test_dist fail    an item that fails ends the job on every rank with "on rank R" and
 *                     its reason, and the next job runs as if nothing happened
 *   test_dist alone   rank 1 fails before a job and goes to lg_dist_finish: the others'
 *                     job ends at once (no rank waits) and the job's status is 1
 */
#include "exec/dist.h"
#include "common/check.h"

#include <string.h>
#include <stdlib.h>

/* An item's bytes: a hash of its index alone, so that they are known here. */
static uint64_t mix(uint64_t x)
{
    x += 0x9e3779b97f4a7c15u;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9u;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebu;
    return x ^ (x >> 31);
}

/* Uneven cost: every 16th item spins a while, so that the ranks take different chunks. */
static void spin(uint64_t i)
{
    if (i % 16 != 3)
        return;
    volatile uint64_t h = i;
    for (int k = 0; k < 20000 * (int)(i % 7 + 1); k++)
        h = mix(h);
}

typedef struct fixed_ctx {
    uint64_t fail_at; /* UINT64_MAX: never */
} fixed_ctx;

static int fixed_range(void *ctx, uint64_t b, uint64_t e, void *items, char *err, size_t n)
{
    const fixed_ctx *c = ctx;
    uint64_t *o = items;
    for (uint64_t i = b; i < e; i++) {
        if (i == c->fail_at) {
            snprintf(err, n, "items %llu..%llu: item %llu refused by request",
                     (unsigned long long)b, (unsigned long long)e - 1, (unsigned long long)i);
            return 1;
        }
        spin(i);
        o[(i - b) * 3 + 0] = i;
        o[(i - b) * 3 + 1] = mix(i);
        o[(i - b) * 3 + 2] = mix(mix(i));
    }
    return 0;
}

static int check_fixed(uint64_t count, uint64_t grain)
{
    uint64_t *out = lg_xcalloc((size_t)count * 3 + 1, sizeof *out);
    fixed_ctx c = { UINT64_MAX };
    char err[512] = "";
    int rc = lg_dist_fixed("items", count, grain, 24, out, fixed_range, &c, err, sizeof err);
    CHECKF(rc == 0, "fixed %llu/%llu: %s", (unsigned long long)count, (unsigned long long)grain,
           err);
    int bad = 0;
    for (uint64_t i = 0; i < count; i++)
        bad += out[i * 3] != i || out[i * 3 + 1] != mix(i) || out[i * 3 + 2] != mix(mix(i));
    CHECKF(bad == 0, "fixed %llu/%llu: %d items wrong on rank %d", (unsigned long long)count,
           (unsigned long long)grain, bad, lg_dist_rank());
    free(out);
    return rc;
}

/* A map item: (i % 5) * 3 bytes, item 0 empty. */
static int map_item(void *ctx, uint64_t i, lg_str *out, char *err, size_t n)
{
    const fixed_ctx *c = ctx;
    if (i == c->fail_at) {
        snprintf(err, n, "point refused by request");
        return 1;
    }
    CHECK(lg_dist_nested());
    spin(i);
    for (uint64_t k = 0; k < (i % 5) * 3; k++)
        lg_str_addc(out, (char)('a' + (mix(i) + k) % 26));
    return 0;
}

static void check_map(uint64_t count, uint64_t grain, bool root_only)
{
    fixed_ctx c = { UINT64_MAX };
    lg_dist_result res;
    int rc = lg_dist_map("point", count, grain, root_only, map_item, &c, &res);
    CHECK(rc == 0);
    bool get = !root_only || lg_dist_root();
    CHECKF(res.n == (get ? count : 0), "map: %llu items on rank %d", (unsigned long long)res.n,
           lg_dist_rank());
    for (uint64_t i = 0; get && rc == 0 && i < count; i++) {
        uint64_t len = res.off[i + 1] - res.off[i];
        CHECKF(len == (i % 5) * 3, "map item %llu: %llu bytes", (unsigned long long)i,
               (unsigned long long)len);
        int wrong = 0;
        for (uint64_t k = 0; k < len; k++)
            wrong += res.data[res.off[i] + k] != (char)('a' + (mix(i) + k) % 26);
        CHECKF(wrong == 0, "map item %llu: %d bytes wrong", (unsigned long long)i, wrong);
    }
    lg_dist_result_free(&res);
}

static void basic(void)
{
    check_fixed(1000, 7);
    check_fixed(5, 100); /* one chunk: each rank alone */
    check_fixed(0, 3);
    check_fixed(97, 1);
    check_map(40, 3, false);
    check_map(40, 1, true);
    check_map(0, 1, false);
    char buf[64] = "";
    if (lg_dist_root())
        snprintf(buf, sizeof buf, "from rank 0");
    CHECK(lg_dist_bcast(buf, sizeof buf) == 0);
    CHECKF(strcmp(buf, "from rank 0") == 0, "bcast gave '%s'", buf);
    CHECK(lg_dist_agree(0, NULL) == 0);
    CHECK(lg_dist_rank() >= 0 && lg_dist_rank() < lg_dist_size());
    CHECK(lg_dist_local_size() >= 1 && lg_dist_local_size() <= lg_dist_size());
    CHECK(!lg_dist_nested());
}

static void fail(void)
{
    uint64_t out[300 * 3];
    fixed_ctx c = { 123 };
    char err[512] = "";
    int rc = lg_dist_fixed("items", 300, 4, 24, out, fixed_range, &c, err, sizeof err);
    CHECK(rc == 1);
    CHECKF(strstr(err, "item 123 refused by request") != NULL, "err '%s'", err);
    if (lg_dist_size() > 1)
        CHECKF(strstr(err, "items 120..123 on rank ") != NULL, "err '%s'", err);
    fprintf(stderr, "rank %d: fixed failed: %s\n", lg_dist_rank(), err);
    /* the next job runs whole */
    check_fixed(200, 3);
    lg_dist_result res;
    c.fail_at = 17;
    rc = lg_dist_map("point", 30, 2, false, map_item, &c, &res);
    CHECK(rc == 1);
    CHECK(res.n == 0 && res.data == NULL);
    check_map(30, 2, false);
    /* a failing agreement fails on every rank */
    CHECK(lg_dist_agree(lg_dist_rank() == lg_dist_size() - 1 ? 1 : 0, "the last rank says no") ==
          1);
}

int main(int argc, char **argv)
{
    if (lg_dist_init(&argc, &argv))
        return 1;
    const char *mode = argc > 1 ? argv[1] : "basic";
    if (strcmp(mode, "basic") == 0) {
        basic();
    } else if (strcmp(mode, "fail") == 0) {
        fail();
    } else if (strcmp(mode, "alone") == 0) {
        if (lg_dist_rank() == 1) {
            fprintf(stderr, "lightgraph: rank 1 could not read its scene by request\n");
            return lg_dist_finish(1);
        }
        uint64_t out[64 * 3];
        fixed_ctx c = { UINT64_MAX };
        char err[512] = "";
        int rc = lg_dist_fixed("items", 64, 2, 24, out, fixed_range, &c, err, sizeof err);
        if (lg_dist_size() > 1) {
            CHECK(rc == 1);
            CHECKF(strstr(err, "could not read its scene") != NULL, "err '%s'", err);
            if (lg_dist_root())
                fprintf(stderr, "lightgraph: %s\n", err);
        } else {
            CHECK(rc == 0);
        }
        /* the job's status is the failing rank's: 1 when there is a rank 1 */
        int st = lg_dist_finish(check_failures ? 1 : 0);
        CHECKF(st == (lg_dist_size() > 1 ? 1 : 0) || lg_dist_size() == 1, "status %d", st);
        return check_failures ? 3 : st;
    } else {
        fprintf(stderr, "usage: test_dist basic|fail|alone\n");
        return 2;
    }
    return lg_dist_finish(check_report("test_dist"));
}
