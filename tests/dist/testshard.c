/* Test plugin "testshard": a third-party-style node (the SDK alone) whose execute() fills its
 * output image through lg_shard (lightgraph/host.h, ABI 3.3): one item per pixel, 16 bytes
 * (RGBA32F), the bits a hash of the pixel's index only, each item costing a varying amount
 * of work (cost * (1 + hash % 16) rounds), so that the ranks' dynamic chunks differ from run
 * to run while the image must not. Its parameters make it fail at an item, or on one rank
 * only (before the job or inside it), hand the host a bad job, or go through the on-disk
 * cache, so that tests/dist reaches every path of the host's sharding (docs/distributed.md).
 *
 * The rank: read from OMPI_COMM_WORLD_RANK, which mpirun sets (test-only; a real node never
 * knows its rank: its items must not depend on it). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lightgraph/lightgraph.h"

static const char *const fail_modes[] = { "none", "before", "job", NULL };
static const char *const bad_modes[] = { "none",     "grain0",   "bytes0", "run_null",
                                         "out_null", "overflow", NULL };

static const lg_param_desc params[] = {
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 1,
      .max = 4096,
      .doc = "image width" },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 32,
      .min = 1,
      .max = 4096,
      .doc = "image height" },
    { .key = "grain",
      .type = LG_PARAM_INT,
      .def.i = 16,
      .min = 1,
      .max = 1e9,
      .doc = "items (pixels) per chunk" },
    { .key = "cost",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1e6,
      .doc = "hash rounds per item, times 1..16 by the item's hash: uneven work" },
    { .key = "fail_at",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "the item whose run fails (-1: none), on whichever rank computes it" },
    { .key = "fail_rank",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e6,
      .doc = "the rank that fails (-1: none), where fail_where says" },
    { .key = "fail_where",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = fail_modes,
      .doc = "none; before: execute fails on fail_rank before its job; job: every chunk "
             "fail_rank takes fails (the other ranks' items then sleep slow_us each)" },
    { .key = "slow_us",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1e6,
      .doc = "microseconds each item sleeps on the ranks that do not fail (fail_where = job)" },
    { .key = "bad",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = bad_modes,
      .doc = "hand the host a bad job: grain 0, item_bytes 0, no run, no out, or a count "
             "whose bytes overflow" },
    { .key = "passes",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 1,
      .max = 4,
      .doc = "jobs run one after the other over the same pixels (each must give the same "
             "bits; the last is the image)" },
    { .key = "affinity",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1e6,
      .doc = "the passes' lg_shard_job.affinity (0: none)" },
    { .key = "lag_rank",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e6,
      .doc = "the rank whose items sleep lag_us each in the passes after the first (-1: "
             "none): a rank-dependent cost" },
    { .key = "lag_us",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 1e6,
      .doc = "microseconds each item of lag_rank sleeps (passes after the first)" },
    { .key = "hold_us",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 5e6,
      .doc = "microseconds the first item of every rank but 0 sleeps in each pass after the "
             "first: ranks late to a job, so that what rank 0 runs does not hang on the "
             "scheduler (its own chunks first, then the late ranks' others)" },
    { .key = "cached",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "keep the image in the on-disk cache (key \"image\")" },
};
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int my_rank(void)
{
    const char *r = getenv("OMPI_COMM_WORLD_RANK");
    return r ? atoi(r) : 0;
}

static uint64_t mix(uint64_t x)
{
    x += 0x9e3779b97f4a7c15u;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9u;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebu;
    return x ^ (x >> 31);
}

typedef struct job_ctx {
    uint64_t cost;
    int64_t fail_at;
    bool fail_here; /* fail_where = job on this rank */
    uint64_t slow_us;
    uint64_t hold_us; /* this rank's first item of the pass sleeps so long */
    int held;         /* set by the first item of the pass (threads race for it) */
} job_ctx;

static int run(void *ctx, uint64_t begin, uint64_t end, void *items, char *err, size_t err_size)
{
    job_ctx *c = ctx;
    if (c->hold_us && !__atomic_exchange_n(&c->held, 1, __ATOMIC_RELAXED)) {
        struct timespec ts = { (time_t)(c->hold_us / 1000000),
                               (long)(c->hold_us % 1000000 * 1000) };
        nanosleep(&ts, NULL);
    }
    float *px = items;
    if (c->fail_here) {
        snprintf(err, err_size, "testshard: refused on this rank by request (fail_rank)");
        return 1;
    }
    for (uint64_t i = begin; i < end; i++) {
        if ((int64_t)i == c->fail_at) {
            snprintf(err, err_size, "testshard: item %llu refused by request (fail_at)",
                     (unsigned long long)i);
            return 1;
        }
        uint64_t h = mix(i);
        /* uneven work whose result is thrown away: the schedule must not show */
        volatile uint64_t w = h;
        for (uint64_t k = 0; k < c->cost * (1 + h % 16); k++)
            w = mix(w);
        if (c->slow_us) {
            struct timespec ts = { 0, (long)(c->slow_us * 1000) };
            nanosleep(&ts, NULL);
        }
        float *p = px + (i - begin) * 4;
        for (int ch = 0; ch < 4; ch++)
            p[ch] = (float)((h >> (16 * ch)) & 0xffff) / 65536.0f;
    }
    return 0;
}

static int prepare(lg_node *n)
{
    lg_image_desc d = { .width = (uint32_t)lg_param_int(n, "width"),
                        .height = (uint32_t)lg_param_int(n, "height"),
                        .format = LG_FORMAT_RGBA32F };
    return lg_declare_image(n, 0, &d);
}

static int execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    uint64_t w = (uint64_t)lg_param_int(n, "width"), h = (uint64_t)lg_param_int(n, "height");
    uint64_t count = w * h;
    int where = lg_param_enum(n, "fail_where");
    bool this_rank = lg_param_int(n, "fail_rank") == my_rank();
    if (where == 1 && this_rank)
        return lg_error(n, "testshard: failing before the job on rank %d by request (fail_rank)",
                        my_rank());
    lg_cpu_view o;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &o);
    if (rc)
        return rc;
    bool cached = lg_param_bool(n, "cached");
    void *data = NULL;
    size_t size = 0;
    float *img = NULL;
    if (cached && lg_cache_get(n, "image", &data, &size) == LG_OK && size == count * 16) {
        lg_log(n, LG_LOG_WARN, "testshard: reused the cached image");
        img = data;
    } else {
        lg_cache_free(n, data);
        data = NULL;
        img = malloc(count * 16);
        if (!img)
            return lg_error(n, "testshard: out of memory");
        job_ctx c = { .cost = (uint64_t)lg_param_int(n, "cost"),
                      .fail_at = lg_param_int(n, "fail_at"),
                      .fail_here = where == 2 && this_rank,
                      .slow_us = where == 2 && !this_rank ? (uint64_t)lg_param_int(n, "slow_us")
                                                          : 0 };
        lg_shard_job job = { .count = count,
                             .grain = (uint64_t)lg_param_int(n, "grain"),
                             .item_bytes = 16,
                             .out = img,
                             .run = run,
                             .ctx = &c,
                             .what = "pixels",
                             .affinity = (uint32_t)lg_param_int(n, "affinity") };
        switch (lg_param_enum(n, "bad")) {
        case 1: job.grain = 0; break;
        case 2: job.item_bytes = 0; break;
        case 3: job.run = NULL; break;
        case 4: job.out = NULL; break;
        case 5: job.item_bytes = UINT64_MAX / 2; break;
        default: break;
        }
        rc = lg_shard(n, &job);
        if (rc) {
            free(img);
            return rc;
        }
        /* Further passes (one affinity family when `affinity` is set), each into its own
         * buffer, the lagging rank slowed: placement differs, the bits may not. */
        int passes = (int)lg_param_int(n, "passes");
        float *again = passes > 1 ? malloc(count * 16) : NULL;
        if (passes > 1 && !again) {
            free(img);
            return lg_error(n, "testshard: out of memory");
        }
        if (lg_param_int(n, "lag_rank") == my_rank())
            c.slow_us = (uint64_t)lg_param_int(n, "lag_us");
        if (my_rank() > 0)
            c.hold_us = (uint64_t)lg_param_int(n, "hold_us");
        for (int pass = 1; pass < passes; pass++) {
            job.out = again;
            c.held = 0;
            rc = lg_shard(n, &job);
            if (rc == 0 && memcmp(again, img, count * 16) != 0)
                rc = lg_error(n, "testshard: pass %d's pixels differ from pass 1's", pass + 1);
            if (rc) {
                free(again);
                free(img);
                return rc;
            }
        }
        free(again);
        if (cached) {
            lg_cache_put(n, "image", img, count * 16);
            lg_log(n, LG_LOG_WARN, "testshard: computed the image");
        }
    }
    for (uint64_t y = 0; y < h; y++)
        memcpy((float *)o.pixels + y * o.row_pixels * 4, img + y * w * 4, w * 16);
    if (data)
        lg_cache_free(n, data);
    else
        free(img);
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_shard",
    .doc = "An image whose pixels are hashes of their index, made through lg_shard with "
           "uneven work (test)",
    LG_PARAMS(params),
    LG_OUTPUTS(out),
    .prepare = prepare,
    .execute = execute,
} };

LG_PLUGIN_DEFINE("testshard", "1.0.0", "lg_shard test node (tests/dist)", types)
