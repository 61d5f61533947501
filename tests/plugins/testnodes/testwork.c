/* Test plugin "testwork": a pass-through node that declares, in prepare, whatever work its
 * parameters say (lg_declare_work, ABI 2.7) and then does none, so that the tests can show
 * what the host makes of an estimate (--explain, render's warning, runs per frame, a
 * malformed estimate) without running anything long. */
#include <math.h>
#include <string.h>

#include "lightgraph/lightgraph.h"

static const lg_param_desc params[] = {
    { .key = "units",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -1e300,
      .max = 1e300,
      .doc = "the units of work declared" },
    { .key = "seconds",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -1e300,
      .max = 1e300,
      .doc = "the seconds declared; 'nan' is given as any value below -1e299" },
    { .key = "per_frame", .type = LG_PARAM_BOOL, .def.b = false, .doc = "run every frame" },
    { .key = "fail_frame",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "fail in execute at this frame index (-1: never): a failure after earlier frames "
             "wrote their frame-pattern files" },
};
static const lg_port_desc in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static int prepare(lg_node *n)
{
    double seconds = lg_param_float(n, "seconds");
    if (seconds < -1e299)
        seconds = NAN; /* a plugin bug the host must refuse */
    lg_declare_work(n, lg_param_float(n, "units"), seconds, "test units");
    if (lg_param_bool(n, "per_frame"))
        lg_set_per_frame(n, true);
    return lg_declare_alias(n, 0, 0);
}

static int execute(lg_node *n, const lg_frame *frame)
{
    if ((int64_t)frame->index == lg_param_int(n, "fail_frame"))
        return lg_error(n, "test_work: failing at frame %u as asked (fail_frame)", frame->index);
    return 0;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_work",
    .doc = "Its input, unchanged, after declaring the work its parameters give (test)",
    LG_PARAMS(params),
    LG_INPUTS(in),
    LG_OUTPUTS(out),
    .prepare = prepare,
    .execute = execute,
} };

LG_PLUGIN_DEFINE("testwork", "1.0.0", "Work estimate test node", types)
