/* The knobs of lightgraph tune (tune_knob.h): a parameter's grid from its schema or --vary. */
#include "cli/tune_knob.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/util.h"
#include "cli/commands.h"

/* A numeric knob's default grid: every integer up to this many values, else powers of two
 * (with both ends); a float's: this many points. */
#define TUNE_INT_STEP_MAX 64
#define TUNE_FLOAT_POINTS 9
/* A float range wider than this (0..1e30: "unbounded") is not varied unless --vary names it. */
#define TUNE_FLOAT_SPAN_MAX 1e6

/* ---- knobs ----------------------------------------------------------------------------------- */

static void knob_add_value(lg_tune_knob *k, char *v)
{
    k->values = lg_xrealloc(k->values, (size_t)(k->n + 1) * sizeof *k->values);
    k->values[k->n++] = v;
}

static void knob_add_number(lg_tune_knob *k, double v)
{
    if (k->pd->type == LG_PARAM_INT)
        knob_add_value(k, lg_xasprintf("%lld", (long long)llround(v)));
    else
        knob_add_value(k, lg_xasprintf("%.6g", v));
}

/* Integers lo..hi: every one, or (pow2) lo, the powers of two between, hi. */
static void grid_int(lg_tune_knob *k, long long lo, long long hi, bool pow2)
{
    knob_add_number(k, (double)lo);
    if (!pow2) {
        for (long long v = lo + 1; v <= hi; v++)
            knob_add_number(k, (double)v);
        return;
    }
    for (long long p = 1; p < hi && p > 0; p *= 2)
        if (p > lo)
            knob_add_number(k, (double)p);
    if (hi > lo)
        knob_add_number(k, (double)hi);
}

/* Floats lo..hi in n points: geometric when lo > 0 (ratios are what sizes and steps scale
 * by), linear otherwise. */
static void grid_float(lg_tune_knob *k, double lo, double hi, int n)
{
    /* in logarithms and weights, not hi / lo or hi - lo, which overflow to infinity on
     * 1e-300..1e30 or -1e300..1e300 (fuzz_tune); the ends are lo and hi exactly */
    for (int i = 0; i < n; i++) {
        double t = n > 1 ? (double)i / (n - 1) : 1.0;
        double v = lo > 0 ? exp(log(lo) + (log(hi) - log(lo)) * t) : lo * (1 - t) + hi * t;
        knob_add_number(k, i == 0 ? lo : i == n - 1 ? hi : v);
    }
}

/* The default grid of a parameter, or false (with *why) when it is not varied by default. */
bool lg_tune_knob_default(lg_tune_knob *k, const lg_param_desc *pd, const char **why)
{
    k->pd = pd;
    switch (pd->type) {
    case LG_PARAM_BOOL:
        knob_add_value(k, lg_xstrdup("false"));
        knob_add_value(k, lg_xstrdup("true"));
        k->grid = lg_xstrdup("false,true");
        return true;
    case LG_PARAM_ENUM: {
        lg_str s = { 0 };
        for (int i = 0; pd->enum_values && pd->enum_values[i]; i++) {
            knob_add_value(k, lg_xstrdup(pd->enum_values[i]));
            lg_str_addf(&s, "%s%s", i ? "," : "", pd->enum_values[i]);
        }
        k->grid = lg_str_take(&s);
        return k->n > 0;
    }
    case LG_PARAM_INT: {
        if (!(pd->max > pd->min)) {
            *why = "no range in its schema";
            return false;
        }
        long long lo = (long long)ceil(pd->min), hi = (long long)floor(pd->max);
        bool pow2 = hi - lo + 1 > TUNE_INT_STEP_MAX;
        k->numeric = true;
        grid_int(k, lo, hi, pow2);
        k->grid = lg_xasprintf("%lld..%lld, %s", lo, hi, pow2 ? "powers of two" : "every integer");
        return true;
    }
    case LG_PARAM_FLOAT: {
        if (!(pd->max > pd->min) || pd->max - pd->min > TUNE_FLOAT_SPAN_MAX) {
            *why = "its schema range is unbounded or too wide to grid (name it with --vary)";
            return false;
        }
        k->numeric = true;
        grid_float(k, pd->min, pd->max, TUNE_FLOAT_POINTS);
        k->grid = lg_xasprintf("%g..%g, %d %s points", pd->min, pd->max, TUNE_FLOAT_POINTS,
                               pd->min > 0 ? "geometric" : "linear");
        return true;
    }
    default: *why = "not a number, an enum or a bool"; return false;
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* A number of a --vary range: strtod's whole text; an int knob's must be whole. */
static bool range_number(const lg_tune_knob *k, const char *s, size_t len, double *out)
{
    char buf[64];
    if (len == 0 || len >= sizeof buf)
        return false;
    memcpy(buf, s, len);
    buf[len] = '\0';
    char *end = NULL;
    *out = strtod(buf, &end);
    if (*end || !isfinite(*out))
        return false;
    /* an int's within +-2^53, where a double holds every integer and the grid's long long
     * conversions are defined (an int without a schema range took 1e300: fuzz_tune) */
    return k->pd->type != LG_PARAM_INT || (*out == floor(*out) && fabs(*out) <= LG_TUNE_INT_LIMIT);
}

static bool in_schema(const lg_param_desc *pd, double v)
{
    return !(pd->max > pd->min) || (v >= pd->min && v <= pd->max);
}

/* Drops the values of a numeric grid written as the one before: an int's geometric steps
 * round to the same integer, and %.6g writes 1 and 1.0000001 (or the ends of 1..1.0000001:pow2)
 * alike (fuzz_tune), so that the grid ascends strictly. */
static void drop_repeats(lg_tune_knob *k)
{
    for (int i = k->n - 1; i > 0; i--)
        if (strcmp(k->values[i], k->values[i - 1]) == 0) {
            free(k->values[i]);
            memmove(k->values + i, k->values + i + 1, (size_t)(k->n - i - 1) * sizeof *k->values);
            k->n--;
        }
}

/* The grid --vary P=RANGE gives (docs/tune.md "Ranges"). Returns 0, or 2 with err. */
int lg_tune_knob_from_range(lg_tune_knob *k, const lg_param_desc *pd, const lg_tune_vary *v,
                            const char *node, char *err, size_t errlen)
{
    k->pd = pd;
    const char *r = v->range, *dots = strstr(r, "..");
    bool numeric = pd->type == LG_PARAM_INT || pd->type == LG_PARAM_FLOAT;
    if (!numeric && pd->type != LG_PARAM_ENUM && pd->type != LG_PARAM_BOOL) {
        snprintf(err, errlen,
                 "--vary %s: %s.%s is not a number, an enum or a bool, so not a knob tune "
                 "can vary",
                 v->arg, node, pd->key);
        return 2;
    }
    k->numeric = numeric;
    k->grid = lg_xstrdup(r);
    if (dots) {
        if (!numeric) {
            snprintf(err, errlen, "--vary %s: lo..hi is for numbers; list the values of %s.%s",
                     v->arg, node, pd->key);
            return 2;
        }
        const char *colon = strchr(dots + 2, ':');
        double lo, hi;
        size_t hl = colon ? (size_t)(colon - dots - 2) : strlen(dots + 2);
        if (!range_number(k, r, (size_t)(dots - r), &lo) || !range_number(k, dots + 2, hl, &hi) ||
            !(hi > lo)) {
            snprintf(err, errlen, "--vary %s: expected lo..hi with lo < hi (%s for %s.%s)", v->arg,
                     pd->type == LG_PARAM_INT ? "integers" : "numbers", node, pd->key);
            return 2;
        }
        if (!in_schema(pd, lo) || !in_schema(pd, hi)) {
            snprintf(err, errlen, "--vary %s: %g..%g is outside %s.%s's range [%g, %g]", v->arg, lo,
                     hi, node, pd->key, pd->min, pd->max);
            return 2;
        }
        uint32_t steps = 0;
        bool pow2 = colon && strcmp(colon + 1, "pow2") == 0;
        if (colon && !pow2 && !lg_parse_uint(colon + 1, &steps, 1000)) {
            snprintf(err, errlen, "--vary %s: after lo..hi: ':pow2' or ':N' (2..1000 steps)",
                     v->arg);
            return 2;
        }
        if (steps == 1) {
            snprintf(err, errlen, "--vary %s: ':N' wants 2 or more steps", v->arg);
            return 2;
        }
        if (pd->type == LG_PARAM_INT && !steps) {
            if (!pow2 && hi - lo + 1 > LG_TUNE_MAX_VALUES) {
                snprintf(err, errlen,
                         "--vary %s: %.0f values; give :pow2 or :N steps (at most %d "
                         "integers)",
                         v->arg, hi - lo + 1, LG_TUNE_MAX_VALUES);
                return 2;
            }
            grid_int(k, (long long)lo, (long long)hi, pow2);
        } else if (pow2) {
            knob_add_number(k, lo);
            for (double p = exp2(ceil(log2(fmax(lo, 1e-300)))); p < hi; p *= 2)
                if (p > lo)
                    knob_add_number(k, p);
            knob_add_number(k, hi);
        } else {
            grid_float(k, lo, hi, steps ? (int)steps : TUNE_FLOAT_POINTS);
        }
        drop_repeats(k);
        return 0;
    }
    /* a,b,c: numbers ascending, or the enum's words / true, false as given */
    double *nums = NULL;
    int nn = 0;
    for (const char *t = r;;) {
        const char *comma = strchr(t, ',');
        size_t len = comma ? (size_t)(comma - t) : strlen(t);
        char *item = lg_xstrndup(t, len);
        bool ok = len > 0;
        if (ok && numeric) {
            double x;
            ok = range_number(k, t, len, &x) && in_schema(pd, x);
            nums = lg_xrealloc(nums, (size_t)(nn + 1) * sizeof *nums);
            nums[nn++] = x;
        } else if (ok && pd->type == LG_PARAM_BOOL) {
            ok = strcmp(item, "true") == 0 || strcmp(item, "false") == 0;
        } else if (ok) {
            ok = false;
            for (int i = 0; pd->enum_values && pd->enum_values[i]; i++)
                ok |= strcmp(item, pd->enum_values[i]) == 0;
        }
        if (!ok) {
            lg_str allowed = { 0 };
            if (numeric) {
                lg_str_add(&allowed, pd->type == LG_PARAM_INT ? "integers" : "numbers");
                /* a schema without a range (min == max) bounds nothing: no "in [0, 0]" */
                if (pd->max > pd->min)
                    lg_str_addf(&allowed, " in [%g, %g]", pd->min, pd->max);
                else if (pd->type == LG_PARAM_INT)
                    lg_str_add(&allowed, " within +-2^53");
            } else if (pd->type == LG_PARAM_BOOL)
                lg_str_add(&allowed, "true, false");
            else
                for (int i = 0; pd->enum_values && pd->enum_values[i]; i++)
                    lg_str_addf(&allowed, "%s%s", i ? ", " : "", pd->enum_values[i]);
            snprintf(err, errlen, "--vary %s: '%s' is not a value of %s.%s (%s)", v->arg, item,
                     node, pd->key, allowed.s ? allowed.s : "none");
            lg_str_free(&allowed);
            free(item);
            free(nums);
            return 2;
        }
        if (!numeric)
            knob_add_value(k, item);
        else
            free(item);
        if (!comma)
            break;
        t = comma + 1;
    }
    if (numeric) {
        qsort(nums, (size_t)nn, sizeof *nums, cmp_double);
        for (int i = 0; i < nn; i++)
            if (i == 0 || nums[i] != nums[i - 1])
                knob_add_number(k, nums[i]);
        drop_repeats(k);
    }
    free(nums);
    return 0;
}

void lg_tune_knob_free(lg_tune_knob *k)
{
    for (int j = 0; j < k->n; j++)
        free(k->values[j]);
    free(k->values);
    free(k->grid);
    memset(k, 0, sizeof *k);
}
