/*
 * tests/fuzz/fuzz_sweep.c: the command line of `lightgraph sweep` (host/cli/sweep_args.c:
 * lg_sweep_parse_args) on arbitrary argument lists.
 *
 * The input is the arguments after "sweep", one per line ('\n' ends each; a last line
 * without one counts too). For every input:
 *   - a refusal must return 2 with a one-line reason;
 *   - an acceptance must hold what sweep_args.h promises: a graph, 1 to 8 --vary each with
 *     a key and values that are non-empty and hold no ',', the run count their product and
 *     at most 10000, every number within its range and written in digits only (as
 *     lg_parse_uint reads the numbers of every command: no blank, no sign), --gl osmesa or
 *     egl, --metric one of metric.h's, one --set and --ref-set entry per option given;
 *   - the result written back as a canonical argument list (every option once, in a fixed
 *     order) parses to the same result.
 * lg_sweep_args_free runs on both, so that a leak shows under ASan.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_sweep) to the plain driver (fuzz_driver.h):
 *
 *     fuzz_sweep [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_argv.h"
#include "fuzz_driver.h"
#include "cli/sweep_args.h"
#include "base/util.h"

static unsigned long n_runs, n_ok;

static void bad(const char *what)
{
    fprintf(stderr, "fuzz_sweep: %s (input %lu)\n", what, n_runs - 1);
    abort();
}

/* Whether option `o` takes the next argument as its value (as sweep_args.c). */
static bool takes_value(const char *o)
{
    static const char *const opts[] = { "--vary", "--reference", "--ref-set", "--set",
                                        "--time", "--repeat",    "--size",    "-o",
                                        "--gl",   "--frames",    "--metric" };
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++)
        if (strcmp(o, opts[k]) == 0)
            return true;
    return false;
}

/* How many times option `opt` is given (as an option, not as another's value). */
static int count(int argc, char **argv, const char *opt)
{
    int n = 0;
    for (int i = 1; i < argc; i++) {
        n += strcmp(argv[i], opt) == 0;
        if (takes_value(argv[i]))
            i++;
    }
    return n;
}

static void check(const lg_sweep_args *a, int argc, char **argv)
{
    if (!a->graph || a->graph[0] == '-' || !a->dir || a->n_vary < 1 ||
        a->n_vary > LG_SWEEP_MAX_VARY)
        bad("an accepted command line without a graph or --vary");
    long total = 1;
    for (int i = 0; i < a->n_vary; i++) {
        const lg_sweep_vary *v = &a->vary[i];
        if (!v->key || !v->key[0] || strchr(v->key, '=') || v->n < 1)
            bad("a --vary without a key or values");
        for (int j = 0; j < v->n; j++)
            if (!v->values[j] || !v->values[j][0] || strchr(v->values[j], ','))
                bad("an empty --vary value, or one holding ','");
        total *= v->n;
        if (total > LG_SWEEP_MAX_RUNS)
            bad("more runs than the limit");
    }
    if (total != a->total)
        bad("a run count that is not the product of the --vary counts");
    if (a->repeat < 1 || a->repeat > 1000 || a->frames < 1 || a->frames > 100000 || a->width < 1 ||
        a->width > LG_MAX_SIZE || a->height < 1 || a->height > LG_MAX_SIZE)
        bad("a number out of its range");
    /* numbers as every command reads them (lg_parse_uint): digits only, so that
     * `--frames ' 4'` or `+4` is refused by sweep as by render */
    for (int i = 1; i + 1 < argc; i++) {
        if (strcmp(argv[i], "--repeat") == 0 || strcmp(argv[i], "--frames") == 0) {
            const char *v = argv[i + 1];
            if (!v[0] || strspn(v, "0123456789") != strlen(v))
                bad("a --repeat or --frames that is not digits only, accepted");
        }
        if (takes_value(argv[i]))
            i++;
    }
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
static int write_back(const lg_sweep_args *a, char **out, char **owned, int *n_owned)
{
    int n = 0;
#define ARG(s) (out[n++] = (char *)(s))
#define OWN(s) (out[n++] = owned[(*n_owned)++] = (s))
    ARG("sweep");
    ARG(a->graph);
    for (int i = 0; i < a->n_vary; i++) {
        lg_str b = { 0 };
        lg_str_addf(&b, "%s=", a->vary[i].key);
        for (int j = 0; j < a->vary[i].n; j++)
            lg_str_addf(&b, "%s%s", j ? "," : "", a->vary[i].values[j]);
        ARG("--vary");
        OWN(lg_str_take(&b));
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
    if (a->time_node) {
        ARG("--time");
        ARG(a->time_node);
    }
    ARG("--repeat");
    OWN(lg_xasprintf("%u", a->repeat));
    ARG("--frames");
    OWN(lg_xasprintf("%u", a->frames));
    ARG("--size");
    OWN(lg_xasprintf("%ux%u", a->width, a->height));
    ARG("--gl");
    ARG(a->gl_backend);
    ARG("-o");
    ARG(a->dir);
    ARG("--metric");
    ARG(lg_metric_name(a->metric));
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

static bool same(const lg_sweep_args *x, const lg_sweep_args *y)
{
    if (!same_str(x->graph, y->graph) || !same_str(x->reference, y->reference) ||
        !same_str(x->time_node, y->time_node) || !same_str(x->dir, y->dir) ||
        x->n_sets != y->n_sets || x->n_ref_sets != y->n_ref_sets || x->n_vary != y->n_vary ||
        x->total != y->total || x->repeat != y->repeat || x->frames != y->frames ||
        x->width != y->width || x->height != y->height || !same_str(x->gl_backend, y->gl_backend) ||
        x->quiet != y->quiet || x->metric != y->metric)
        return false;
    for (int i = 0; i < x->n_sets; i++)
        if (!same_str(x->sets[i], y->sets[i]))
            return false;
    for (int i = 0; i < x->n_ref_sets; i++)
        if (!same_str(x->ref_sets[i], y->ref_sets[i]))
            return false;
    for (int i = 0; i < x->n_vary; i++) {
        if (!same_str(x->vary[i].key, y->vary[i].key) || x->vary[i].n != y->vary[i].n)
            return false;
        for (int j = 0; j < x->vary[i].n; j++)
            if (!same_str(x->vary[i].values[j], y->vary[i].values[j]))
                return false;
    }
    return true;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    n_runs++;
    char *text;
    int argc;
    char **argv = lg_fuzz_argv(data, size, "sweep", &text, &argc);
    if (!argv)
        return 0; /* an argument never holds a NUL */

    lg_sweep_args a;
    char err[512];
    memset(err, 'x', sizeof err);
    int rc = lg_sweep_parse_args(argc, argv, &a, err, sizeof err);
    if (rc) {
        if (rc != 2 || !memchr(err, '\0', sizeof err) || !err[0] || strchr(err, '\n'))
            bad("a refusal that is not 2 with a one-line reason");
    } else {
        n_ok++;
        check(&a, argc, argv);
        char *owned[LG_SWEEP_MAX_VARY + 3];
        int n_owned = 0;
        char **wb = malloc(((size_t)argc * 2 + 32) * sizeof *wb);
        if (!wb)
            abort();
        int n = write_back(&a, wb, owned, &n_owned);
        lg_sweep_args b;
        if (lg_sweep_parse_args(n, wb, &b, err, sizeof err) != 0) {
            fprintf(stderr, "fuzz_sweep: written back: %s\n", err);
            bad("the command line written back is refused");
        }
        if (!same(&a, &b))
            bad("the command line written back parses to another result");
        lg_sweep_args_free(&b);
        for (int i = 0; i < n_owned; i++)
            free(owned[i]);
        free(wb);
    }
    lg_sweep_args_free(&a);
    free(argv);
    free(text);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* The options, values at and past their limits, the separators of --vary. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("\n--vary\n"),
    LG_FUZZ_TOKEN("\n--reference\n"),
    LG_FUZZ_TOKEN("\n--ref-set\n"),
    LG_FUZZ_TOKEN("\n--set\n"),
    LG_FUZZ_TOKEN("\n--time\n"),
    LG_FUZZ_TOKEN("\n--repeat\n"),
    LG_FUZZ_TOKEN("\n--frames\n"),
    LG_FUZZ_TOKEN("\n--size\n"),
    LG_FUZZ_TOKEN("\n--gl\n"),
    LG_FUZZ_TOKEN("\n-o\n"),
    LG_FUZZ_TOKEN("\n-q"),
    LG_FUZZ_TOKEN("a.b=1,2,3"),
    LG_FUZZ_TOKEN(",,"),
    LG_FUZZ_TOKEN("="),
    LG_FUZZ_TOKEN("1000"),
    LG_FUZZ_TOKEN("100000"),
    LG_FUZZ_TOKEN("16384x1"),
    LG_FUZZ_TOKEN("egl"),
    LG_FUZZ_TOKEN("osmesa"),
    LG_FUZZ_TOKEN("9999999999999999999"),
    LG_FUZZ_TOKEN(" "),
    LG_FUZZ_TOKEN("-"),
};

static void summary(FILE *out)
{
    fprintf(out, "%lu accepted", n_ok);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_sweep",
        .mutations = 3000,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
