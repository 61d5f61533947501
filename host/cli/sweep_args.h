/*
 * host/cli/sweep_args.h: the command line of `lightgraph sweep` (sweep.c has the command and
 * its usage), parsed apart from the command so that tests/fuzz/fuzz_sweep.c runs it on
 * arbitrary argument lists (docs/fuzzing.md).
 */
#ifndef LG_HOST_SWEEP_ARGS_H
#define LG_HOST_SWEEP_ARGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cli/metric.h"

#define LG_SWEEP_MAX_VARY 8
/* at most this many combinations: each writes two files, reserved when its run starts */
#define LG_SWEEP_MAX_RUNS 10000

typedef struct lg_sweep_vary {
    char *key;       /* NODE.PARAM (owned) */
    char **values;   /* n values, each non-blank and without ',' (owned) */
    const char *arg; /* the whole --vary value, for messages (points into argv) */
    int n;
} lg_sweep_vary;

/* What the arguments say. Strings other than the --vary ones point into argv. */
typedef struct lg_sweep_args {
    /* reference: --reference, a graph, or an image when its name ends as one does (.exr,
     * .hdr, .pic, .png: lg_image_format_from_path); dir: -o, default "out/sweep" */
    const char *graph, *reference, *time_node, *dir;
    const char **sets, **ref_sets; /* --set, --ref-set values in order (arrays owned) */
    int n_sets, n_ref_sets;
    lg_sweep_vary vary[LG_SWEEP_MAX_VARY];
    int n_vary;
    int total;              /* runs: the product of the --vary counts */
    uint32_t repeat;        /* --repeat, 1..1000, default 3 */
    uint32_t frames;        /* --frames, 1..100000, default 1 */
    uint32_t width, height; /* --size, default 640x360 */
    bool size_given;        /* --size was given (its pixel limit is the command's) */
    const char *gl_backend; /* --gl: "osmesa" (default) or "egl" */
    bool quiet;             /* -q */
    lg_metric_id metric;    /* --metric, the error the plot shows: default LG_METRIC_RMSE */
} lg_sweep_args;

/* Parses argv[1 .. argc-1] (argv[0] is "sweep"). Returns 0 with *a filled, or 2 (bad usage)
 * with the one-line reason in err ("--repeat wants 1..1000, got 'x'", no newline; the
 * caller prints it and the usage). *a is to be freed with lg_sweep_args_free either way.
 * Checks the form of every argument only: the graph, the parameters and the values are
 * the checker's (lg_check_file), the files the outputs'. */
int lg_sweep_parse_args(int argc, char **argv, lg_sweep_args *a, char *err, size_t errlen);
/* Frees what lg_sweep_parse_args made and zeroes *a. */
void lg_sweep_args_free(lg_sweep_args *a);

#endif
