/* Test plugin "testtune": a node whose error and cost follow known laws, so that the tests of
 * `lightgraph tune` (tests/unit/host/test_tune.py, docs/tune.md) know the optimum in advance.
 *
 *   tune_law  every channel of its image (the render size) is 1 + a / n^p, and it first does
 *             c x n units of deterministic busy work, where (a, p, c) are the mode's:
 *
 *               mode    a   p   c     error against 1 (rel_rmse)   cost
 *               coarse  1   1   1     1 / n                        n units
 *               fine    1   2   4     1 / n^2                      4 n units
 *               flat    1   0   1     1 (never below)              n units
 *               slow    1   2   256   1 / n^2                      256 n units
 *
 *             exact = true writes 1 without work: the reference (--ref-set law.exact=true).
 *             bump = B > 0 breaks the monotonicity on purpose: for B <= n < B + 4 the error
 *             is 100 times the law's (a knob whose error is not non-increasing in n).
 *
 * The cost ratios are large enough (fine reaches 1% at n = 10, 40 units; coarse at n = 100,
 * 100 units; slow costs 256 units at n = 1 already, a combination to prune) that timing
 * noise cannot flip the optimum. */
#include <math.h>
#include <string.h>

#include "lightgraph/lightgraph.h"

static const char *const modes[] = { "coarse", "fine", "flat", "slow", NULL };
static const double law_a[] = { 1, 1, 1, 1 }, law_p[] = { 1, 2, 0, 2 }, law_c[] = { 1, 4, 1, 256 };

/* iterations of one unit of work: about 10 to 20 microseconds */
#define TUNE_UNIT 10000

static const lg_param_desc params[] = {
    { .key = "n",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 1,
      .max = 4096,
      .doc = "the sample count: error a / n^p, cost c x n units" },
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.s = "coarse",
      .enum_values = modes,
      .doc = "the law: coarse (1/n, n), fine (1/n^2, 4n), flat (1, n), slow (1/n^2, 256n)" },
    { .key = "exact", .type = LG_PARAM_BOOL, .def.b = false, .doc = "write 1, no work" },
    { .key = "bump",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 4096,
      .doc = "B > 0: the error is 100 times the law's for B <= n < B + 4" },
};
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int prepare(lg_node *n)
{
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    lg_render_size(n, &d.width, &d.height);
    return lg_declare_image(n, 0, &d);
}

/* c x n units of work whose result the compiler cannot drop (volatile sink) */
static void busy(double units)
{
    volatile double sink = 0;
    double x = 1.0;
    long iters = (long)(units * TUNE_UNIT);
    for (long i = 0; i < iters; i++)
        x = x * 1.0000001 + 1e-9;
    sink = x;
    (void)sink;
}

static int execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    int64_t count = lg_param_int(n, "n"), bump = lg_param_int(n, "bump");
    int m = lg_param_enum(n, "mode");
    float val = 1.0f;
    if (!lg_param_bool(n, "exact")) {
        busy(law_c[m] * (double)count);
        double err = law_a[m] / pow((double)count, law_p[m]);
        if (bump > 0 && count >= bump && count < bump + 4)
            err *= 100;
        val = (float)(1.0 + err);
    }
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    lg_resource_info info;
    lg_describe(lg_output(n, 0), &info, n);
    float *p = v.pixels;
    for (size_t i = 0; i < (size_t)info.image.width * info.image.height; i++) {
        p[4 * i + 0] = p[4 * i + 1] = p[4 * i + 2] = val;
        p[4 * i + 3] = 1;
    }
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "tune_law",
    .doc = "An image of known error 1 + a/n^p after c x n units of work, per mode (test)",
    LG_PARAMS(params),
    LG_OUTPUTS(out),
    .prepare = prepare,
    .execute = execute,
} };

LG_PLUGIN_DEFINE("testtune", "1.0.0", "Known error and cost laws for lightgraph tune", types)
