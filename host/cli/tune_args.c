/* The command line of `lightgraph tune` (tune_args.h), apart from tune.c's search. */
#include "cli/tune_args.h"
#include "cli/commands.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"

/* tune's options, in the order of tune_opt; every one but -q takes a value */
static const lg_option tune_opts[] = {
    { "--node", NULL, LG_OPT_VALUE },
    { "--target-error", NULL, LG_OPT_VALUE },
    { "--metric", NULL, LG_OPT_VALUE },
    { "--vary", NULL, LG_OPT_VALUE },
    { "--reference", NULL, LG_OPT_VALUE },
    { "--ref-set", NULL, LG_OPT_VALUE },
    { "--set", NULL, LG_OPT_VALUE },
    { "--size", NULL, LG_OPT_VALUE },
    { "--frames", NULL, LG_OPT_VALUE },
    { "--repeat", NULL, LG_OPT_VALUE },
    { "--max-renders", NULL, LG_OPT_VALUE },
    { "--gl", NULL, LG_OPT_VALUE },
    { "-o", NULL, LG_OPT_VALUE },
    { "-q", NULL, 0 },
};
enum tune_opt {
    OPT_NODE,
    OPT_TARGET,
    OPT_METRIC,
    OPT_VARY,
    OPT_REFERENCE,
    OPT_REF_SET,
    OPT_SET,
    OPT_SIZE,
    OPT_FRAMES,
    OPT_REPEAT,
    OPT_MAX_RENDERS,
    OPT_GL,
    OPT_DIR,
    OPT_QUIET,
    N_TUNE_OPTS
};
_Static_assert(sizeof tune_opts / sizeof tune_opts[0] == N_TUNE_OPTS, "tune_opts");

/* --target-error: a finite number above 0 (strtod's whole text) */
static bool parse_target(const char *s, double *out)
{
    char *end = NULL;
    double v = strtod(s, &end);
    if (!s[0] || !end || *end || !isfinite(v) || !(v > 0))
        return false;
    *out = v;
    return true;
}

/* One --vary PARAM=RANGE into a->vary: its form only (tune.c reads the range against the
 * parameter's schema). Returns 0 or 2 (err). */
static int add_vary(lg_tune_args *a, const char *val, char *err, size_t errlen)
{
    const char *eq = strchr(val, '=');
    if (!eq || eq == val || !eq[1] || a->n_vary == LG_TUNE_MAX_VARY)
        return lg_arg_refuse(err, errlen,
                             "--vary wants PARAM=lo..hi, PARAM=lo..hi:pow2, PARAM=lo..hi:N or "
                             "PARAM=a,b,c (at most " LG_STR(LG_TUNE_MAX_VARY) "), got '%s'",
                             val);
    lg_tune_vary *v = &a->vary[a->n_vary++];
    v->arg = val;
    v->param = lg_xstrndup(val, (size_t)(eq - val));
    v->range = eq + 1;
    return 0;
}

int lg_tune_parse_args(int argc, char **argv, lg_tune_args *a, char *err, size_t errlen)
{
    memset(a, 0, sizeof *a);
    if (errlen)
        err[0] = '\0';
    a->dir = "out/tune";
    a->metric = LG_METRIC_REL_RMSE;
    a->sets = lg_xcalloc((size_t)argc + 1, sizeof *a->sets);
    a->ref_sets = lg_xcalloc((size_t)argc + 1, sizeof *a->ref_sets);
    a->repeat = 3;
    a->frames = 1;
    a->max_renders = 400;
    a->width = 640;
    a->height = 360;
    a->gl_backend = "osmesa";
    a->target = NAN;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *val;
        int opt = lg_option_find(tune_opts, N_TUNE_OPTS, argc, argv, &i, &val);
        if (opt == LG_OPT_NO_VALUE)
            return lg_arg_refuse(err, errlen, "%s needs a value", o);
        switch (opt) {
        case OPT_NODE: a->node = val; break;
        case OPT_TARGET:
            if (!parse_target(val, &a->target))
                return lg_arg_refuse(err, errlen,
                                     "--target-error wants a finite number above 0 (the largest "
                                     "error accepted, in the metric's unit), got '%s'",
                                     val);
            break;
        case OPT_METRIC:
            if (lg_metric_parse(val, &a->metric))
                return lg_arg_refuse(err, errlen, "--metric: unknown metric '%s' (known: %s)", val,
                                     lg_metric_names());
            break;
        case OPT_VARY:
            if (add_vary(a, val, err, errlen))
                return 2;
            break;
        case OPT_REFERENCE: a->reference = val; break;
        case OPT_REF_SET: a->ref_sets[a->n_ref_sets++] = val; break;
        case OPT_SET: a->sets[a->n_sets++] = val; break;
        case OPT_SIZE:
            if (!lg_parse_size(val, &a->width, &a->height))
                return lg_arg_refuse(err, errlen, "--size wants WxH, 1..16384 each (got '%s')",
                                     val);
            a->size_given = true;
            break;
        case OPT_FRAMES:
            if (!lg_parse_uint(val, &a->frames, 100000))
                return lg_arg_refuse(err, errlen, "--frames wants 1..100000, got '%s'", val);
            break;
        case OPT_REPEAT:
            if (!lg_parse_uint(val, &a->repeat, 1000))
                return lg_arg_refuse(err, errlen, "--repeat wants 1..1000, got '%s'", val);
            break;
        case OPT_MAX_RENDERS:
            if (!lg_parse_uint(val, &a->max_renders, 100000))
                return lg_arg_refuse(err, errlen, "--max-renders wants 1..100000, got '%s'", val);
            break;
        case OPT_GL:
            if (strcmp(val, "osmesa") && strcmp(val, "egl"))
                return lg_arg_refuse(err, errlen, "--gl wants osmesa or egl, got '%s'", val);
            a->gl_backend = val;
            break;
        case OPT_DIR: a->dir = val; break;
        case OPT_QUIET: a->quiet = true; break;
        default:
            if (o[0] == '-')
                return lg_arg_refuse(err, errlen, "unknown option '%s'", o);
            if (a->graph)
                return lg_arg_refuse(err, errlen, "unexpected argument '%s'", o);
            a->graph = o;
        }
    }
    if (!a->graph)
        return lg_arg_refuse(err, errlen, "no graph given");
    if (!a->node)
        return lg_arg_refuse(err, errlen,
                             "no node given (--node NAME: the node whose knobs are tuned)");
    if (isnan(a->target))
        return lg_arg_refuse(err, errlen, "no target given (--target-error E, e.g. 0.05)");
    for (int i = 0; i < a->n_vary; i++)
        for (int k = 0; k < i; k++)
            if (strcmp(a->vary[k].param, a->vary[i].param) == 0)
                return lg_arg_refuse(err, errlen, "--vary %s is given twice ('%s' and '%s')",
                                     a->vary[i].param, a->vary[k].arg, a->vary[i].arg);
    return 0;
}

void lg_tune_args_free(lg_tune_args *a)
{
    for (int i = 0; i < a->n_vary; i++)
        free(a->vary[i].param);
    free(a->sets);
    free(a->ref_sets);
    memset(a, 0, sizeof *a);
}
