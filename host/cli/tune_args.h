/*
 * host/cli/tune_args.h: the command line of `lightgraph tune` (tune.c has the command, its
 * search and its usage; docs/tune.md), parsed apart from the command: the form of every
 * argument only. Whether the node, its parameters and the values exist is the command's to
 * check, against the graph and the node's schema.
 */
#ifndef LG_HOST_TUNE_ARGS_H
#define LG_HOST_TUNE_ARGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "cli/metric.h"

#define LG_TUNE_MAX_VARY 16

/* One --vary PARAM=RANGE, as written (PARAM may also be written NODE.PARAM). */
typedef struct lg_tune_vary {
    const char *arg;   /* the whole value, for messages (points into argv) */
    char *param;       /* PARAM (owned) */
    const char *range; /* the text after '=' (points into argv) */
} lg_tune_vary;

/* What the arguments say. Strings point into argv unless marked owned. */
typedef struct lg_tune_args {
    const char *graph, *node, *reference, *dir; /* dir: -o, default "out/tune" */
    double target;                              /* --target-error E: finite, > 0 */
    lg_metric_id metric;                        /* --metric, default rel_rmse */
    const char **sets, **ref_sets;              /* --set, --ref-set in order (arrays owned) */
    int n_sets, n_ref_sets;
    lg_tune_vary vary[LG_TUNE_MAX_VARY];
    int n_vary;
    uint32_t repeat;        /* --repeat, 1..1000, default 3: timings of a point near the front */
    uint32_t frames;        /* --frames, 1..100000, default 1 */
    uint32_t max_renders;   /* --max-renders, 1..100000, default 400 */
    uint32_t width, height; /* --size, default 640x360 */
    bool size_given;
    const char *gl_backend; /* --gl: "osmesa" (default) or "egl" */
    bool quiet;             /* -q */
} lg_tune_args;

/* Parses argv[1 .. argc-1] (argv[0] is "tune"). Returns 0 with *a filled, or 2 (bad usage)
 * with the one-line reason in err (no newline; the caller prints it and the usage). *a is
 * to be freed with lg_tune_args_free either way. */
int lg_tune_parse_args(int argc, char **argv, lg_tune_args *a, char *err, size_t errlen);
/* Frees what lg_tune_parse_args made and zeroes *a. */
void lg_tune_args_free(lg_tune_args *a);

#endif
