/* The command line of `lightgraph sweep` (sweep_args.h). Apart from sweep.c, which runs
 * the sweep, so that the fuzz target (tests/fuzz/fuzz_sweep.c) runs it alone. */
#include "cli/sweep_args.h"
#include "cli/commands.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"

/* sweep's options, in the order of sweep_opt; every one but -q takes a value */
static const lg_option sweep_opts[] = {
    { "--vary", NULL, LG_OPT_VALUE },
    { "--reference", NULL, LG_OPT_VALUE },
    { "--ref-set", NULL, LG_OPT_VALUE },
    { "--set", NULL, LG_OPT_VALUE },
    { "--time", NULL, LG_OPT_VALUE },
    { "--repeat", NULL, LG_OPT_VALUE },
    { "--frames", NULL, LG_OPT_VALUE },
    { "--size", NULL, LG_OPT_VALUE },
    { "--gl", NULL, LG_OPT_VALUE },
    { "-o", NULL, LG_OPT_VALUE },
    { "-q", NULL, 0 },
    { "--metric", NULL, LG_OPT_VALUE },
};
enum sweep_opt {
    OPT_VARY,
    OPT_REFERENCE,
    OPT_REF_SET,
    OPT_SET,
    OPT_TIME,
    OPT_REPEAT,
    OPT_FRAMES,
    OPT_SIZE,
    OPT_GL,
    OPT_DIR,
    OPT_QUIET,
    OPT_METRIC,
    N_SWEEP_OPTS
};
_Static_assert(sizeof sweep_opts / sizeof sweep_opts[0] == N_SWEEP_OPTS, "sweep_opts");

int lg_sweep_parse_args(int argc, char **argv, lg_sweep_args *a, char *err, size_t errlen)
{
    memset(a, 0, sizeof *a);
    if (errlen)
        err[0] = '\0';
    a->dir = "out/sweep";
    a->sets = lg_xcalloc((size_t)argc + 1, sizeof *a->sets);
    a->ref_sets = lg_xcalloc((size_t)argc + 1, sizeof *a->ref_sets);
    a->repeat = 3;
    a->frames = 1;
    a->width = 640;
    a->height = 360;
    a->gl_backend = "osmesa";
    a->metric = LG_METRIC_RMSE;
    a->total = 1;
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *val;
        int opt = lg_option_find(sweep_opts, N_SWEEP_OPTS, argc, argv, &i, &val);
        if (opt == LG_OPT_NO_VALUE)
            return lg_arg_refuse(err, errlen, "%s needs a value", o);
        if (opt == OPT_VARY) {
            const char *eq = strchr(val, '=');
            if (!eq || eq == val || !eq[1] || a->n_vary == LG_SWEEP_MAX_VARY)
                return lg_arg_refuse(err, errlen,
                                     "--vary wants NODE.PARAM=v1,v2,... (at most " LG_STR(
                                         LG_SWEEP_MAX_VARY) "), got '%s'",
                                     val);
            lg_sweep_vary *v = &a->vary[a->n_vary++];
            v->key = lg_xstrndup(val, (size_t)(eq - val));
            v->arg = val;
            /* One --vary per parameter: a second one used to replace the first's values
             * silently, and the sweep ran once with the last value. */
            for (int k = 0; k < a->n_vary - 1; k++)
                if (strcmp(a->vary[k].key, v->key) == 0)
                    return lg_arg_refuse(err, errlen,
                                         "--vary %s is given twice ('%s' and '%s'): give "
                                         "all its values in one --vary %s=v1,v2,...",
                                         v->key, a->vary[k].arg, val, v->key);
            /* Every item counts, empty ones too: strtok dropped them, so "0.1,,0.2" and
             * "0.1," ran fewer values than written. */
            for (const char *t = eq + 1;;) {
                const char *comma = strchr(t, ',');
                size_t len = comma ? (size_t)(comma - t) : strlen(t);
                if (strspn(t, " \t") >= len)
                    return lg_arg_refuse(err, errlen,
                                         "--vary %s: item %d of '%s' is empty (the values "
                                         "are separated by single commas, none before the first or "
                                         "after the last)",
                                         v->key, v->n + 1, eq + 1);
                v->values = lg_xrealloc(v->values, (size_t)(v->n + 1) * sizeof(char *));
                v->values[v->n++] = lg_xstrndup(t, len);
                if (!comma)
                    break;
                t = comma + 1;
            }
        } else if (opt == OPT_REFERENCE) {
            a->reference = val;
        } else if (opt == OPT_REF_SET) {
            a->ref_sets[a->n_ref_sets++] = val;
        } else if (opt == OPT_SET) {
            a->sets[a->n_sets++] = val;
        } else if (opt == OPT_TIME) {
            a->time_node = val;
        } else if (opt == OPT_REPEAT) {
            /* lg_parse_uint, as every command reads a count: digits only (strtol took
             * ' 3' and '+3', which render's --frames refuses) */
            if (!lg_parse_uint(val, &a->repeat, 1000))
                return lg_arg_refuse(err, errlen, "--repeat wants 1..1000, got '%s'", val);
        } else if (opt == OPT_FRAMES) {
            if (!lg_parse_uint(val, &a->frames, 100000))
                return lg_arg_refuse(err, errlen, "--frames wants 1..100000, got '%s'", val);
        } else if (opt == OPT_SIZE) {
            if (!lg_parse_size(val, &a->width, &a->height))
                return lg_arg_refuse(err, errlen, "--size wants WxH, 1..16384 each (got '%s')",
                                     val);
            a->size_given = true;
        } else if (opt == OPT_GL) {
            if (strcmp(val, "osmesa") && strcmp(val, "egl"))
                return lg_arg_refuse(err, errlen, "--gl wants osmesa or egl, got '%s'", val);
            a->gl_backend = val;
        } else if (opt == OPT_DIR) {
            a->dir = val;
        } else if (opt == OPT_QUIET) {
            a->quiet = true;
        } else if (opt == OPT_METRIC) {
            if (lg_metric_parse(val, &a->metric))
                return lg_arg_refuse(err, errlen, "--metric wants one of %s, got '%s'",
                                     lg_metric_names(), val);
        } else if (o[0] == '-') {
            return lg_arg_refuse(err, errlen, "unknown option '%s'", o);
        } else if (!a->graph) {
            a->graph = o;
        } else {
            return lg_arg_refuse(err, errlen, "unexpected argument '%s'", o);
        }
    }
    if (!a->graph)
        return lg_arg_refuse(err, errlen, "no graph given");
    if (a->n_vary == 0)
        return lg_arg_refuse(err, errlen, "nothing to vary (give --vary NODE.PARAM=v1,v2,...)");
    for (int i = 0; i < a->n_vary; i++) {
        if (a->vary[i].n == 0)
            return lg_arg_refuse(err, errlen, "--vary %s has no values", a->vary[i].key);
        if (a->total > LG_SWEEP_MAX_RUNS / a->vary[i].n)
            return lg_arg_refuse(err, errlen,
                                 "the --vary values make more than " LG_STR(
                                     LG_SWEEP_MAX_RUNS) " runs");
        a->total *= a->vary[i].n;
    }
    return 0;
}

void lg_sweep_args_free(lg_sweep_args *a)
{
    for (int i = 0; i < a->n_vary; i++) {
        free(a->vary[i].key);
        for (int j = 0; j < a->vary[i].n; j++)
            free(a->vary[i].values[j]);
        free(a->vary[i].values);
    }
    free(a->sets);
    free(a->ref_sets);
    memset(a, 0, sizeof *a);
}
