/*
 * host/cli/tune_knob.h: the knobs of `lightgraph tune` (docs/tune.md "Knobs" and "Ranges"):
 * the grid of values one parameter is searched over, from its schema (the default) or from a
 * --vary range. Apart from tune.c's search so that tests/fuzz/fuzz_tune.c reads ranges
 * against a schema without a graph or a plugin.
 */
#ifndef LG_HOST_TUNE_KNOB_H
#define LG_HOST_TUNE_KNOB_H

#include <stdbool.h>
#include <stddef.h>

#include "lightgraph/plugin.h"
#include "cli/tune_args.h"

/* lo..hi on an int knob: at most this many values (else :pow2 or :N) */
#define LG_TUNE_MAX_VALUES 65536
/* The numbers of an int knob's range are whole and within +-2^53 (exact in a double). */
#define LG_TUNE_INT_LIMIT 9007199254740992.0

/* One knob: a parameter of node N and the values the search may give it. A numeric knob's
 * values ascend strictly (index order is the assumed order of accuracy and cost), each within
 * the schema's range when it has one; an enum's or bool's are categories. Zero it before
 * filling it; free it with lg_tune_knob_free whatever the fill returned. */
typedef struct lg_tune_knob {
    const lg_param_desc *pd; /* not owned: the node type's schema */
    bool numeric;
    int n;
    char **values; /* n, as written after NODE.PARAM= (owned) */
    char *grid;    /* the grid in words, for the report (owned) */
} lg_tune_knob;

/* The default grid of parameter pd, or false (with *why when the parameter is a number
 * that is not varied, e.g. no range in its schema). */
bool lg_tune_knob_default(lg_tune_knob *k, const lg_param_desc *pd, const char **why);
/* The grid that --vary v gives parameter pd of node `node` (for messages). Returns 0, or 2
 * with the one-line reason in err: a range that is not of the forms lo..hi, lo..hi:pow2,
 * lo..hi:N (2..1000) or a,b,c, numbers outside the schema, an int's that are not whole,
 * values that are not the enum's or true/false, lo..hi on a category. */
int lg_tune_knob_from_range(lg_tune_knob *k, const lg_param_desc *pd, const lg_tune_vary *v,
                            const char *node, char *err, size_t errlen);
/* Frees what k owns and zeroes it. */
void lg_tune_knob_free(lg_tune_knob *k);

#endif
