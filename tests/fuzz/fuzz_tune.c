/*
 * tests/fuzz/fuzz_tune.c: the command line of `lightgraph tune` (host/cli/tune_args.c:
 * lg_tune_parse_args) on arbitrary argument lists, and each --vary range it accepts read
 * against a few schemas (host/cli/tune_knob.c: lg_tune_knob_from_range), as tune.c reads it
 * against the node's.
 *
 * The input is the arguments after "tune", one per line ('\n' ends each; a last line
 * without one counts too). For every input:
 *   - a refusal must return 2 with a one-line reason;
 *   - an acceptance must hold what tune_args.h promises: a graph, a node, a finite target
 *     above 0, at most LG_TUNE_MAX_VARY --vary each PARAM=RANGE with PARAM and RANGE
 *     non-empty and no PARAM twice, every number within its range and written in digits
 *     only (lg_parse_uint), --gl osmesa or egl, --metric one of metric.h's, one --set and
 *     --ref-set entry per option given;
 *   - the result written back as a canonical argument list (every option once, in a fixed
 *     order) parses to the same result;
 *   - each --vary's range, against an int [1, 4096], an int and a float without a range, a
 *     float [0, 1], one [0, 1e30] ("unbounded"), an enum, a bool and a string: a refusal
 *     is 2 with a one-line reason; a grid holds 1 to LG_TUNE_MAX_VALUES values, a numeric
 *     one finite numbers ascending strictly within the schema (an int's whole), from lo to
 *     hi for lo..hi; a category's values are the enum's words or true/false.
 * lg_tune_args_free and lg_tune_knob_free run on all, so that a leak shows under ASan.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_tune) to the plain driver (fuzz_driver.h):
 *
 *     fuzz_tune [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_argv.h"
#include "fuzz_driver.h"
#include "cli/tune_args.h"
#include "cli/tune_knob.h"
#include "base/util.h"

static unsigned long n_runs, n_ok, n_grids;

static void bad(const char *what)
{
    fprintf(stderr, "fuzz_tune: %s (input %lu)\n", what, n_runs - 1);
    abort();
}

/* How many times option `opt` is given (as an option, not as another's value): every
 * option of tune but -q takes the next argument as its value. */
static int count(int argc, char **argv, const char *opt)
{
    int n = 0;
    for (int i = 1; i < argc; i++) {
        n += strcmp(argv[i], opt) == 0;
        if (argv[i][0] == '-' && strcmp(argv[i], "-q") != 0)
            i++;
    }
    return n;
}

static bool digits_only(const char *v)
{
    return v[0] && strspn(v, "0123456789") == strlen(v);
}

static void check(const lg_tune_args *a, int argc, char **argv)
{
    if (!a->graph || a->graph[0] == '-' || !a->node || !a->dir || !isfinite(a->target) ||
        !(a->target > 0))
        bad("an accepted command line without a graph, a node or a target above 0");
    if (a->n_vary < 0 || a->n_vary > LG_TUNE_MAX_VARY)
        bad("more --vary than the limit");
    for (int i = 0; i < a->n_vary; i++) {
        const lg_tune_vary *v = &a->vary[i];
        size_t pl = v->param ? strlen(v->param) : 0;
        if (!pl || !v->range || !v->range[0] || !v->arg || strncmp(v->arg, v->param, pl) != 0 ||
            v->arg[pl] != '=' || v->range != v->arg + pl + 1)
            bad("a --vary that is not PARAM=RANGE with both non-empty");
        for (int k = 0; k < i; k++)
            if (strcmp(a->vary[k].param, v->param) == 0)
                bad("a --vary parameter given twice, accepted");
    }
    if (a->repeat < 1 || a->repeat > 1000 || a->frames < 1 || a->frames > 100000 ||
        a->max_renders < 1 || a->max_renders > 100000 || a->width < 1 || a->width > LG_MAX_SIZE ||
        a->height < 1 || a->height > LG_MAX_SIZE)
        bad("a number out of its range");
    for (int i = 1; i + 1 < argc; i++) {
        if ((strcmp(argv[i], "--repeat") == 0 || strcmp(argv[i], "--frames") == 0 ||
             strcmp(argv[i], "--max-renders") == 0) &&
            !digits_only(argv[i + 1]))
            bad("a --repeat, --frames or --max-renders that is not digits only, accepted");
        if (argv[i][0] == '-' && strcmp(argv[i], "-q") != 0)
            i++;
    }
    if (a->size_given != (count(argc, argv, "--size") > 0))
        bad("size_given without --size, or --size without it");
    if (!a->gl_backend || (strcmp(a->gl_backend, "osmesa") && strcmp(a->gl_backend, "egl")))
        bad("an unknown --gl");
    if ((unsigned)a->metric >= LG_METRIC_COUNT)
        bad("an unknown --metric");
    if (a->n_sets != count(argc, argv, "--set") || a->n_ref_sets != count(argc, argv, "--ref-set"))
        bad("--set or --ref-set entries lost or made up");
    for (int i = 0; i < a->n_sets; i++)
        if (!a->sets[i])
            bad("a NULL --set");
    for (int i = 0; i < a->n_ref_sets; i++)
        if (!a->ref_sets[i])
            bad("a NULL --ref-set");
}

/* The canonical argument list of `a` (strings malloc'd into *owned). */
static int write_back(const lg_tune_args *a, char **out, char **owned, int *n_owned)
{
    int n = 0;
#define ARG(s) (out[n++] = (char *)(s))
#define OWN(s) (out[n++] = owned[(*n_owned)++] = (s))
    ARG("tune");
    ARG(a->graph);
    ARG("--node");
    ARG(a->node);
    ARG("--target-error");
    OWN(lg_xasprintf("%.17g", a->target));
    ARG("--metric");
    ARG(lg_metric_name(a->metric));
    for (int i = 0; i < a->n_vary; i++) {
        ARG("--vary");
        ARG(a->vary[i].arg);
    }
    if (a->reference) {
        ARG("--reference");
        ARG(a->reference);
    }
    for (int i = 0; i < a->n_ref_sets; i++) {
        ARG("--ref-set");
        ARG(a->ref_sets[i]);
    }
    for (int i = 0; i < a->n_sets; i++) {
        ARG("--set");
        ARG(a->sets[i]);
    }
    if (a->size_given) {
        ARG("--size");
        OWN(lg_xasprintf("%ux%u", a->width, a->height));
    }
    ARG("--frames");
    OWN(lg_xasprintf("%u", a->frames));
    ARG("--repeat");
    OWN(lg_xasprintf("%u", a->repeat));
    ARG("--max-renders");
    OWN(lg_xasprintf("%u", a->max_renders));
    ARG("--gl");
    ARG(a->gl_backend);
    ARG("-o");
    ARG(a->dir);
    if (a->quiet)
        ARG("-q");
#undef ARG
#undef OWN
    return n;
}

static bool same_str(const char *x, const char *y)
{
    return x == y || (x && y && strcmp(x, y) == 0);
}

static bool same(const lg_tune_args *x, const lg_tune_args *y)
{
    if (!same_str(x->graph, y->graph) || !same_str(x->node, y->node) ||
        !same_str(x->reference, y->reference) || !same_str(x->dir, y->dir) ||
        x->target != y->target || x->metric != y->metric || x->n_sets != y->n_sets ||
        x->n_ref_sets != y->n_ref_sets || x->n_vary != y->n_vary || x->repeat != y->repeat ||
        x->frames != y->frames || x->max_renders != y->max_renders || x->width != y->width ||
        x->height != y->height || x->size_given != y->size_given ||
        !same_str(x->gl_backend, y->gl_backend) || x->quiet != y->quiet)
        return false;
    for (int i = 0; i < x->n_sets; i++)
        if (!same_str(x->sets[i], y->sets[i]))
            return false;
    for (int i = 0; i < x->n_ref_sets; i++)
        if (!same_str(x->ref_sets[i], y->ref_sets[i]))
            return false;
    for (int i = 0; i < x->n_vary; i++)
        if (!same_str(x->vary[i].param, y->vary[i].param) ||
            !same_str(x->vary[i].range, y->vary[i].range))
            return false;
    return true;
}

/* ---- the ranges against schemas -------------------------------------------------------------- */

static const char *const modes[] = { "coarse", "fine", "flat", NULL };
static const lg_param_desc schemas[] = {
    { .key = "n", .type = LG_PARAM_INT, .min = 1, .max = 4096 },
    { .key = "count", .type = LG_PARAM_INT },
    { .key = "offset", .type = LG_PARAM_FLOAT },
    { .key = "x", .type = LG_PARAM_FLOAT, .min = 0, .max = 1 },
    { .key = "scale", .type = LG_PARAM_FLOAT, .min = 0, .max = 1e30 },
    { .key = "mode", .type = LG_PARAM_ENUM, .enum_values = modes },
    { .key = "on", .type = LG_PARAM_BOOL },
    { .key = "name", .type = LG_PARAM_STRING },
};

/* A number of the grid as tune writes it into --set: strtod's whole text, finite. */
static double grid_number(const char *s)
{
    char *end = NULL;
    double v = strtod(s, &end);
    if (!s[0] || *end || !isfinite(v))
        bad("a grid value that is not a finite number");
    return v;
}

/* lo and hi of RANGE when it is lo..hi[:...] (as the fuzzer reads it, for the ends). */
static bool range_ends(const char *r, double *lo, double *hi)
{
    const char *dots = strstr(r, "..");
    if (!dots)
        return false;
    const char *colon = strchr(dots + 2, ':');
    char *a = lg_xstrndup(r, (size_t)(dots - r));
    char *b = lg_xstrndup(dots + 2, colon ? (size_t)(colon - dots - 2) : strlen(dots + 2));
    *lo = strtod(a, NULL);
    *hi = strtod(b, NULL);
    free(a);
    free(b);
    return true;
}

/* Whether x and y are the same number as %.6g or an integer writes it. */
static bool near(double x, double y)
{
    return fabs(x - y) <= 1e-5 * fmax(fabs(x), fabs(y));
}

static void check_range(const lg_tune_vary *v, const lg_param_desc *pd)
{
    lg_tune_knob k;
    memset(&k, 0, sizeof k);
    char err[512];
    memset(err, 'x', sizeof err);
    int rc = lg_tune_knob_from_range(&k, pd, v, "nd", err, sizeof err);
    if (rc) {
        if (rc != 2 || !memchr(err, '\0', sizeof err) || !err[0] || strchr(err, '\n'))
            bad("a range refused without 2 and a one-line reason");
        lg_tune_knob_free(&k);
        return;
    }
    n_grids++;
    if (k.n < 1 || k.n > LG_TUNE_MAX_VALUES || k.pd != pd || !k.grid)
        bad("an accepted range with no value, too many, or no words for the report");
    bool numeric = pd->type == LG_PARAM_INT || pd->type == LG_PARAM_FLOAT;
    if (k.numeric != numeric)
        bad("a knob numeric for a category, or a category for a number");
    bool ranged = pd->max > pd->min;
    for (int i = 0; i < k.n; i++) {
        if (!k.values[i] || !k.values[i][0])
            bad("an empty grid value");
        if (numeric) {
            double x = grid_number(k.values[i]);
            if (pd->type == LG_PARAM_INT && x != floor(x))
                bad("an int knob's value that is not whole");
            if (ranged &&
                (x < pd->min - 1e-5 * fabs(pd->min) || x > pd->max + 1e-5 * fabs(pd->max)))
                bad("a grid value outside the schema's range");
            if (i > 0 && !(x > grid_number(k.values[i - 1])))
                bad("a numeric grid that does not ascend strictly");
        } else if (pd->type == LG_PARAM_BOOL) {
            if (strcmp(k.values[i], "true") && strcmp(k.values[i], "false"))
                bad("a bool knob's value that is not true or false");
        } else {
            bool found = false;
            for (int j = 0; pd->enum_values[j]; j++)
                found |= strcmp(k.values[i], pd->enum_values[j]) == 0;
            if (!found)
                bad("an enum knob's value that is not one of the enum's");
        }
    }
    double lo, hi;
    if (numeric && range_ends(v->range, &lo, &hi) &&
        (!near(grid_number(k.values[0]), lo) || !near(grid_number(k.values[k.n - 1]), hi)))
        bad("a lo..hi grid that does not run from lo to hi");
    lg_tune_knob_free(&k);
    if (k.values || k.grid || k.n)
        bad("lg_tune_knob_free left the knob filled");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    n_runs++;
    char *text;
    int argc;
    char **argv = lg_fuzz_argv(data, size, "tune", &text, &argc);
    if (!argv)
        return 0; /* an argument never holds a NUL */

    lg_tune_args a;
    char err[512];
    memset(err, 'x', sizeof err);
    int rc = lg_tune_parse_args(argc, argv, &a, err, sizeof err);
    if (rc) {
        if (rc != 2 || !memchr(err, '\0', sizeof err) || !err[0] || strchr(err, '\n'))
            bad("a refusal that is not 2 with a one-line reason");
    } else {
        n_ok++;
        check(&a, argc, argv);
        char *owned[8];
        int n_owned = 0;
        char **wb = malloc(((size_t)argc * 2 + 32) * sizeof *wb);
        if (!wb)
            abort();
        int n = write_back(&a, wb, owned, &n_owned);
        lg_tune_args b;
        if (lg_tune_parse_args(n, wb, &b, err, sizeof err) != 0) {
            fprintf(stderr, "fuzz_tune: written back: %s\n", err);
            bad("the command line written back is refused");
        }
        if (!same(&a, &b))
            bad("the command line written back parses to another result");
        lg_tune_args_free(&b);
        for (int i = 0; i < n_owned; i++)
            free(owned[i]);
        free(wb);
        for (int i = 0; i < a.n_vary; i++)
            for (size_t s = 0; s < sizeof schemas / sizeof schemas[0]; s++)
                check_range(&a.vary[i], &schemas[s]);
    }
    lg_tune_args_free(&a);
    free(argv);
    free(text);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* The options, values at and past their limits, the forms of a range. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("\n--node\n"),
    LG_FUZZ_TOKEN("\n--target-error\n"),
    LG_FUZZ_TOKEN("\n--metric\n"),
    LG_FUZZ_TOKEN("\n--vary\n"),
    LG_FUZZ_TOKEN("\n--reference\n"),
    LG_FUZZ_TOKEN("\n--ref-set\n"),
    LG_FUZZ_TOKEN("\n--set\n"),
    LG_FUZZ_TOKEN("\n--size\n"),
    LG_FUZZ_TOKEN("\n--frames\n"),
    LG_FUZZ_TOKEN("\n--repeat\n"),
    LG_FUZZ_TOKEN("\n--max-renders\n"),
    LG_FUZZ_TOKEN("\n--gl\n"),
    LG_FUZZ_TOKEN("\n-o\n"),
    LG_FUZZ_TOKEN("\n-q"),
    LG_FUZZ_TOKEN("n=1..4096"),
    LG_FUZZ_TOKEN(".."),
    LG_FUZZ_TOKEN(":pow2"),
    LG_FUZZ_TOKEN(":1000"),
    LG_FUZZ_TOKEN(","),
    LG_FUZZ_TOKEN("="),
    LG_FUZZ_TOKEN("coarse,fine"),
    LG_FUZZ_TOKEN("true"),
    LG_FUZZ_TOKEN("1e30"),
    LG_FUZZ_TOKEN("1e-300"),
    LG_FUZZ_TOKEN("-1e300"),
    LG_FUZZ_TOKEN("nan"),
    LG_FUZZ_TOKEN("inf"),
    LG_FUZZ_TOKEN("0.05"),
    LG_FUZZ_TOKEN("100000"),
    LG_FUZZ_TOKEN("9999999999999999999"),
    LG_FUZZ_TOKEN("rel_rmse"),
    LG_FUZZ_TOKEN("dssim"),
    LG_FUZZ_TOKEN(" "),
    LG_FUZZ_TOKEN("-"),
};

static void summary(FILE *out)
{
    fprintf(out, "%lu accepted, %lu ranges read to a grid", n_ok, n_grids);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_tune",
        .mutations = 3000,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
