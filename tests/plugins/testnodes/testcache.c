/* Test plugin "testcache": a node whose "expensive" result (the mean of its input) goes
 * through the host's on-disk cache; it logs whether it computed or reused the result, so
 * the tests can see hits, misses and recomputation after corruption. */
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"

static const lg_param_desc params[] = {
    { .key = "salt", .type = LG_PARAM_INT, .def.i = 0, .doc = "changes the cache identity" },
};
static const lg_port_desc in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int prepare(lg_node *n)
{
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    lg_image_desc d = { .width = info.image.width,
                        .height = info.image.height,
                        .format = LG_FORMAT_RGBA32F };
    return lg_declare_image(n, 0, &d);
}

static int execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    size_t np = (size_t)info.image.width * info.image.height;
    double mean[4] = { 0, 0, 0, 0 };
    void *data = NULL;
    size_t size = 0;
    if (lg_cache_get(n, "mean", &data, &size) == LG_OK && size == sizeof mean) {
        memcpy(mean, data, sizeof mean);
        lg_log(n, LG_LOG_WARN, "testcache: reused the cached mean");
    } else {
        lg_cpu_view v;
        int rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &v);
        if (rc)
            return rc;
        const float *p = v.pixels;
        for (size_t i = 0; i < np; i++)
            for (int c = 0; c < 4; c++)
                mean[c] += p[4 * i + c] / (double)np;
        lg_cache_put(n, "mean", mean, sizeof mean);
        lg_log(n, LG_LOG_WARN, "testcache: computed the mean");
    }
    lg_cache_free(n, data);
    lg_cpu_view o;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &o);
    if (rc)
        return rc;
    float *q = o.pixels;
    for (size_t i = 0; i < np; i++)
        for (int c = 0; c < 4; c++)
            q[4 * i + c] = (float)mean[c];
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_cached",
    .doc = "The mean of its input, through the on-disk cache (test)",
    LG_PARAMS(params),
    LG_INPUTS(in),
    LG_OUTPUTS(out),
    .prepare = prepare,
    .execute = execute,
} };

LG_PLUGIN_DEFINE("testcache", "1.0.0", "Cache API test node", types)
