/* lightgraph tune: the cheapest settings of one node's knobs whose error against a reference
 * stays within a target, found by a search rather than a grid (docs/tune.md).
 *
 *   lightgraph tune GRAPH --node N --target-error E [--metric M] [--vary P=RANGE]...
 *                   [--reference REF | --ref-set N.P=V ...] [--set N.P=V]... [--size WxH]
 *                   [--frames N] [--repeat N] [--max-renders N] [--gl osmesa|egl] [-o DIR]
 *
 * The knobs are node N's numeric (int, float), enum and bool parameters (or the --vary ones),
 * each with a grid of values (tune_knob.c). Numeric knobs are assumed monotone: a larger
 * value costs no less and errs no more (sizes, sample counts). The
 * search (search_combo): every combination of the enum and bool knobs; in each, the
 * cheapest setting first (it may already meet E), a combination whose cheapest setting is
 * slower than the best answer so far is pruned, then the most accurate setting (a
 * combination that misses E there cannot meet it), then each numeric knob bisected down to
 * its cheapest value within E, one coordinate at a time until none moves. Every point is
 * rendered once (cached by its grid indices); the points near the front get --repeat
 * timings; the chosen one is rendered once more (the check). Renders go through
 * lg_render_file, as sweep's, into a temporary in DIR that is removed after it is read;
 * the CSV, the script and the plot are committed together at the end, or none.
 *
 * Under `mpirun -np N` (docs/tune.md, docs/distributed.md) every rank runs the same search,
 * and every render of a point is an lg_dist_map item whose result (status, time, metrics,
 * messages) reaches every rank: so every rank holds the same points and takes the same
 * decisions, and the renders that do not depend on each other (a point's --repeat timings,
 * every repeat of a round near the front, the two points a pruning test times) run at once
 * on as many ranks. The search's own steps (a bisection's next point) are sequential: one
 * rank renders while the others wait. Every rank renders the reference together and rank
 * 0's is broadcast; rank 0 alone writes. */
#include "cli/commands.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "exec/dist.h"
#include "exec/outputs.h"
#include "cli/metric.h"
#include "cli/tune_args.h"
#include "cli/tune_knob.h"

/* Points within this fraction of the cheapest feasible time get --repeat timings. */
#define TUNE_NEAR_FRONT 0.2
/* A monotonicity violation: this many grid values below the answer are scanned. */
#define TUNE_SCAN_WINDOW 16

static int usage(const char *msg)
{
    fprintf(stderr, "lightgraph tune: %s\n", msg);
    fprintf(stderr,
            "usage: lightgraph tune GRAPH --node N --target-error E [--metric M]\n"
            "                       [--vary P=lo..hi|lo..hi:pow2|lo..hi:N|a,b,c]...\n"
            "                       [--reference REF_GRAPH | --ref-set N.P=V ...]\n"
            "                       [--set N.P=V]... [--size WxH] [--frames N] [--repeat N]\n"
            "                       [--max-renders N] [--gl osmesa|egl] [-q] [-o DIR]\n"
            "metrics: %s (default rel_rmse); DIR (default out/tune) must exist\n",
            lg_metric_names());
    return 2;
}

/* ---- the tune under way ---------------------------------------------------------------------- */

/* One evaluated setting: its grid index per knob, its timings, its error. */
typedef struct point {
    int *idx;      /* n_knobs (owned) */
    double *times; /* n_times of the node's time, ms (owned) */
    int n_times;
    lg_metric_set m;
    double err; /* the chosen metric; +Inf when the render failed */
    bool failed, on_front, chosen;
} point;

typedef struct tune {
    const lg_tune_args *a;
    lg_exec_opts opts;
    lg_registry reg;
    const lg_node_type *type;
    lg_tune_knob *k;
    int n_knobs;
    point *pts;
    int n_pts;
    lg_image ref;
    double ref_ms;
    bool ref_node_found;
    int renders, repeats;
    double grid_size;
    bool budget_hit;
    lg_outputs *outs;
    char *render_out, *csv_path, *gp_path, *png_path;
    /* the check render of the chosen point (check_render): run when checked, its status
     * (render_point's), time, metrics and whether the render failed */
    bool checked, check_failed;
    int check_rc;
    double check_ms;
    lg_metric_set check_m;
} tune;

static bool feasible(const tune *t, const point *p)
{
    return !p->failed && p->err <= t->a->target;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* median of a point's timings (sorted in place) */
static double median_ms(point *p)
{
    if (p->n_times == 0)
        return INFINITY;
    qsort(p->times, (size_t)p->n_times, sizeof *p->times, cmp_double);
    int n = p->n_times;
    return n % 2 ? p->times[n / 2] : 0.5 * (p->times[n / 2 - 1] + p->times[n / 2]);
}

/* "--set N.P=V --set ..." of a point (malloc'd) */
static char *set_line(const tune *t, const int *idx)
{
    lg_str s = { 0 };
    for (int i = 0; i < t->n_knobs; i++)
        lg_str_addf(&s, "%s--set %s.%s=%s", i ? " " : "", t->a->node, t->k[i].pd->key,
                    t->k[i].values[idx[i]]);
    return lg_str_take(&s);
}

/* The overrides of one render of GRAPH: --set, then the knobs at idx (free the array and
 * the last n_knobs strings). */
static const char **point_sets(const tune *t, const int *idx, int *n)
{
    const lg_tune_args *a = t->a;
    const char **s = lg_xcalloc((size_t)(a->n_sets + t->n_knobs) + 1, sizeof *s);
    *n = 0;
    for (int i = 0; i < a->n_sets; i++)
        s[(*n)++] = a->sets[i];
    for (int i = 0; i < t->n_knobs; i++)
        s[(*n)++] = lg_xasprintf("%s.%s=%s", a->node, t->k[i].pd->key, t->k[i].values[idx[i]]);
    return s;
}

static void free_sets(const tune *t, const char **s, int n)
{
    for (int i = n - t->n_knobs; i < n; i++)
        free((char *)s[i]);
    free(s);
}

/* Renders GRAPH (or the reference) once into a temporary in DIR that is read back and
 * removed: nothing of it is kept but *img and the time. Returns the exit status. */
static int render_once(tune *t, const char *graph, const char *const *sets, int n_sets,
                       lg_image *img, lg_run_result *res)
{
    char err[1024];
    lg_outputs *outs = lg_outputs_new();
    lg_exec_opts o = t->opts;
    o.output_override = t->render_out;
    o.outputs = outs;
    int rc = lg_render_file(&t->reg, graph, sets, n_sets, &o, t->a->node, res);
    if (rc == 0 &&
        lg_image_read(lg_outputs_temp(outs, t->render_out), 0, img, NULL, err, sizeof err)) {
        fprintf(stderr, "lightgraph tune: %s\n", err);
        rc = 1;
    }
    lg_outputs_free(&outs); /* removes the temporary: it was never meant to be kept */
    return rc;
}

/* The last error the host logged (lg_hlog_error_hook) while a point rendered: a failed
 * render's reason for rank 0, which does not see another rank's stderr. */
static char last_error[400];
static void keep_error(const char *m)
{
    snprintf(last_error, sizeof last_error, "%s", m);
}

/* Renders the point idx once and judges it. Its messages go to msg (msglen bytes), which
 * the caller prints. Returns 0 (a failed render is a point that failed, not the end of the
 * tune: a backend missing here), or the exit status of a bad graph or a node that did not
 * run. */
static int render_point(tune *t, const int *idx, double *ms, lg_metric_set *m, bool *failed,
                        char *msg, size_t msglen)
{
    int n;
    const char **sets = point_sets(t, idx, &n);
    lg_image img = { 0 };
    lg_run_result res;
    char err[512];
    last_error[0] = 0;
    lg_hlog_error_hook = keep_error;
    int rc = render_once(t, t->a->graph, sets, n, &img, &res);
    lg_hlog_error_hook = NULL;
    *failed = rc == 1;
    msg[0] = 0;
    if (rc == 0 && !res.node_found) {
        snprintf(msg, msglen,
                 "lightgraph tune: --node %s: no kept node of that name ran (is it gated, or "
                 "unused by the output?)\n",
                 t->a->node);
        rc = 2;
    } else if (rc == 0 && lg_metrics_compute(&img, &t->ref, m, NULL, 0, err, sizeof err)) {
        snprintf(msg, msglen, "lightgraph tune: against the reference: %s\n", err);
        rc = 2;
    }
    if (*failed) {
        /* "(above)" where the render's messages are: on rank 0's stderr */
        char *line = set_line(t, idx);
        if (lg_dist_root() || !last_error[0])
            snprintf(msg, msglen, "tune: the render with %s failed (above): counted as missing E\n",
                     line);
        else
            snprintf(msg, msglen,
                     "tune: the render with %s failed on rank %d (%s): counted as missing E\n",
                     line, lg_dist_rank(), last_error);
        free(line);
        rc = 0;
    }
    *ms = res.node_ms;
    lg_image_free(&img);
    free_sets(t, sets, n);
    return rc;
}

/* One render of a point as it reaches every rank (an lg_dist_map item's bytes). */
typedef struct point_sent {
    int32_t rc, failed; /* render_point's status and *failed */
    double ms;
    lg_metric_set m;
    char msg[640]; /* render_point's messages, printed on every rank in item order */
} point_sent;

typedef struct point_batch {
    tune *t;
    const int *const *idx;
} point_batch;

static int point_item(void *ctx, uint64_t item, lg_str *out, char *err, size_t err_size)
{
    (void)err;
    (void)err_size;
    point_batch *b = ctx;
    point_sent s;
    memset(&s, 0, sizeof s);
    bool failed = false;
    s.rc = render_point(b->t, b->idx[item], &s.ms, &s.m, &failed, s.msg, sizeof s.msg);
    s.failed = failed;
    lg_str_addn(out, (const char *)&s, sizeof s);
    return 0;
}

/* Renders the points idx[0..n) once each, spread over the ranks (independent renders: the
 * same answers in any order), every result on every rank in sent[], their messages printed.
 * A render's failure is data (sent[i].rc), the same on every rank, never the map's. Returns
 * 0, or 1 when the ranks could not work together (printed). */
static int render_points(tune *t, const int *const *idx, int n, point_sent *sent)
{
    point_batch b = { t, idx };
    lg_dist_result res;
    if (lg_dist_map("tune render", (uint64_t)n, 1, false, point_item, &b, &res))
        return 1;
    for (int i = 0; i < n; i++) {
        memcpy(&sent[i], res.data + res.off[i], sizeof *sent);
        sent[i].msg[sizeof sent[i].msg - 1] = 0;
        fputs(sent[i].msg, stderr);
    }
    lg_dist_result_free(&res);
    return 0;
}

/* Renders that give points their --repeat timings, made at once (tfill_add, tfill_run). */
typedef struct timing_fill {
    int *who; /* the point of each render */
    const int **idx;
    int n;
} timing_fill;

/* Point p's missing timings into f. */
static void tfill_add(tune *t, timing_fill *f, int p)
{
    int need = (int)t->a->repeat - t->pts[p].n_times;
    for (int i = 0; i < need; i++) {
        f->who = lg_xrealloc(f->who, (size_t)(f->n + 1) * sizeof *f->who);
        f->idx = lg_xrealloc(f->idx, (size_t)(f->n + 1) * sizeof *f->idx);
        f->who[f->n] = p;
        f->idx[f->n++] = t->pts[p].idx;
    }
}

/* Renders f's points and takes their times in item order, as timing one point after the
 * other would: the first render that fails ends it (the renders after it are not counted).
 * Frees f. Returns 0 or an exit status. */
static int tfill_run(tune *t, timing_fill *f)
{
    int rc = 0;
    point_sent *sent = lg_xcalloc((size_t)f->n + 1, sizeof *sent);
    if (f->n && render_points(t, f->idx, f->n, sent))
        rc = 1;
    for (int i = 0; i < f->n && rc == 0; i++) {
        point *q = &t->pts[f->who[i]];
        t->repeats++;
        rc = sent[i].rc;
        if (rc == 0 && sent[i].failed)
            rc = 1; /* it rendered before: a failure now is the machine's */
        if (rc == 0)
            q->times[q->n_times++] = sent[i].ms;
    }
    free(sent);
    free(f->who);
    free(f->idx);
    memset(f, 0, sizeof *f);
    return rc;
}

static int find_point(const tune *t, const int *idx)
{
    for (int p = 0; p < t->n_pts; p++)
        if (memcmp(t->pts[p].idx, idx, (size_t)t->n_knobs * sizeof *idx) == 0)
            return p;
    return -1;
}

/* The point idx: from the cache, or rendered now (once). *out is its index, or -1 when the
 * render budget is spent. Returns 0 or an exit status. */
static int eval(tune *t, const int *idx, int *out)
{
    *out = find_point(t, idx);
    if (*out >= 0)
        return 0;
    if ((uint32_t)(t->renders + t->repeats) >= t->a->max_renders) {
        t->budget_hit = true;
        return 0;
    }
    point p = { 0 };
    t->renders++;
    point_sent sent;
    if (render_points(t, &idx, 1, &sent))
        return 1;
    int rc = sent.rc;
    double ms = sent.ms;
    p.m = sent.m;
    p.failed = sent.failed;
    if (rc)
        return rc;
    p.idx = lg_xmalloc((size_t)t->n_knobs * sizeof *idx);
    memcpy(p.idx, idx, (size_t)t->n_knobs * sizeof *idx);
    p.err = p.failed ? INFINITY : lg_metric_value(&p.m, t->a->metric);
    if (isnan(p.err))
        p.err = INFINITY; /* cannot say (render_reference refuses a metric that never can) */
    if (!p.failed) {
        p.times = lg_xmalloc(t->a->repeat * sizeof *p.times);
        p.times[p.n_times++] = ms;
    }
    t->pts = lg_xrealloc(t->pts, (size_t)(t->n_pts + 1) * sizeof *t->pts);
    t->pts[t->n_pts] = p;
    *out = t->n_pts++;
    char *line = set_line(t, idx);
    if (lg_verbosity >= 0) /* -q: the answer only */
        fprintf(stderr, "tune: render %d: %s: %s %.4g, %.3f ms%s\n", t->renders, line,
                lg_metric_name(t->a->metric), p.err, ms,
                p.failed          ? " (failed)"
                : feasible(t, &p) ? " (within E)"
                                  : "");
    free(line);
    return 0;
}

/* ---- the search ------------------------------------------------------------------------------ */

/* Whether the points evaluated on knob k's line through idx (every other knob as in idx)
 * err less at a smaller value than at a larger one that misses E: the knob is not monotone
 * where it matters, and the bisection may have stopped above a value that meets E. (Wiggles
 * among values that all meet E, a noisy reference's, cannot move the answer: not counted.) */
static bool violates(const tune *t, const int *idx, int k, char *msg, size_t msglen)
{
    const point *va = NULL, *vb = NULL;
    for (int p = 0; p < t->n_pts; p++)
        for (int q = 0; q < t->n_pts; q++) {
            const point *a = &t->pts[p], *b = &t->pts[q];
            if (a->failed || b->failed || a->idx[k] >= b->idx[k])
                continue;
            bool line = true;
            for (int i = 0; i < t->n_knobs && line; i++)
                line = i == k || (a->idx[i] == idx[i] && b->idx[i] == idx[i]);
            /* errors of one render setting are deterministic for most nodes; the margin
             * keeps a float's last bits from counting. The pair named is the closest one
             * (the largest smaller value, then the smallest larger one): the telling one. */
            if (line && b->err > t->a->target && a->err < b->err * (1 - 1e-6) &&
                (!va || a->idx[k] > va->idx[k] ||
                 (a->idx[k] == va->idx[k] && b->idx[k] < vb->idx[k]))) {
                va = a;
                vb = b;
            }
        }
    if (va)
        snprintf(msg, msglen, "%s=%s errs %.4g, less than %s=%s's %.4g", t->k[k].pd->key,
                 t->k[k].values[va->idx[k]], va->err, t->k[k].pd->key, t->k[k].values[vb->idx[k]],
                 vb->err);
    return va != NULL;
}

/* Bisects knob k of x (feasible) down to the smallest grid index that still meets E,
 * assuming monotonicity, then checks it; a violation scans the TUNE_SCAN_WINDOW grid values
 * below the answer and takes the smallest that meets E. Returns 0 or an exit status. */
static int bisect(tune *t, int *x, int k, bool *scanned)
{
    int lo = 0, hi = x[k], p, rc = 0;
    int *y = lg_xmalloc((size_t)t->n_knobs * sizeof *y);
    memcpy(y, x, (size_t)t->n_knobs * sizeof *y);
    while (lo < hi && rc == 0) {
        y[k] = lo + (hi - lo) / 2;
        rc = eval(t, y, &p);
        if (rc || p < 0)
            break;
        if (feasible(t, &t->pts[p]))
            hi = y[k];
        else
            lo = y[k] + 1;
    }
    char msg[512];
    if (rc == 0 && !*scanned && violates(t, x, k, msg, sizeof msg)) {
        *scanned = true;
        int from = hi - TUNE_SCAN_WINDOW > 0 ? hi - TUNE_SCAN_WINDOW : 0;
        if (lg_verbosity >= 0) /* the progress' words; stdout's note says it anyway */
            fprintf(stderr,
                    "tune: %s is not monotone here (%s): scanning its grid from %s to %s "
                    "instead of trusting the bisection\n",
                    t->k[k].pd->key, msg, t->k[k].values[from], t->k[k].values[hi]);
        printf("note: %s is not monotone (%s); its grid was scanned from %s to %s\n",
               t->k[k].pd->key, msg, t->k[k].values[from], t->k[k].values[hi]);
        for (int j = hi - 1; j >= from && rc == 0; j--) {
            y[k] = j;
            rc = eval(t, y, &p);
            if (rc == 0 && p >= 0 && feasible(t, &t->pts[p]))
                hi = j;
        }
    }
    x[k] = hi;
    free(y);
    return rc;
}

/* Whether another point of q's combination of the categorical knobs meets E with no
 * numeric knob higher: by the monotonicity assumed, it costs no more, so q is no candidate
 * (timing noise between a setting and a strictly cheaper one is not left to decide). */
static bool dominated_in_combo(const tune *t, const point *q)
{
    for (int p = 0; p < t->n_pts; p++) {
        const point *r = &t->pts[p];
        if (r == q || !feasible(t, r))
            continue;
        bool below = true, same = true;
        for (int i = 0; i < t->n_knobs && below; i++) {
            if (t->k[i].numeric)
                below = r->idx[i] <= q->idx[i];
            else
                below = r->idx[i] == q->idx[i];
            same &= r->idx[i] == q->idx[i];
        }
        if (below && !same)
            return true;
    }
    return false;
}

/* The candidate (feasible, not dominated in its combination) of least median time, or -1. */
static int cheapest(tune *t)
{
    int best = -1;
    double bt = INFINITY;
    for (int p = 0; p < t->n_pts; p++)
        if (feasible(t, &t->pts[p]) && !dominated_in_combo(t, &t->pts[p])) {
            double ms = median_ms(&t->pts[p]);
            if (best < 0 || ms < bt) {
                best = p;
                bt = ms;
            }
        }
    return best;
}

/* The candidates within TUNE_NEAR_FRONT of the cheapest get --repeat timings, until the set
 * of them no longer changes (a repeat may move the cheapest). A round's repeats render at
 * once (whether a point is in the round depends on its own timings only). */
static int repeat_near_front(tune *t)
{
    int rc = 0;
    for (bool more = true; more && rc == 0;) {
        more = false;
        int c = cheapest(t);
        if (c < 0)
            break;
        double limit = median_ms(&t->pts[c]) * (1 + TUNE_NEAR_FRONT);
        timing_fill f = { 0 };
        for (int p = 0; p < t->n_pts; p++) {
            point *q = &t->pts[p];
            if (!feasible(t, q) || dominated_in_combo(t, q) || median_ms(q) > limit ||
                q->n_times >= (int)t->a->repeat)
                continue;
            tfill_add(t, &f, p);
            more = true;
        }
        rc = tfill_run(t, &f);
    }
    return rc;
}

/* Whether the combination whose cheapest setting is point p (which misses E) is dominated:
 * that setting is already slower than the best candidate so far, by more than
 * TUNE_NEAR_FRONT on the median of --repeat timings of both (one sample on a loaded machine
 * can be off by a factor of three). */
static int dominated_combo(tune *t, int p, bool *pruned)
{
    *pruned = false;
    int b = cheapest(t), rc = 0;
    if (b < 0 || t->pts[p].failed || t->pts[p].times[0] <= median_ms(&t->pts[b]))
        return 0;
    timing_fill f = { 0 };
    tfill_add(t, &f, p);
    tfill_add(t, &f, b);
    if ((rc = tfill_run(t, &f)))
        return rc;
    double tp = median_ms(&t->pts[p]), tb = median_ms(&t->pts[b]);
    if (tp > tb * (1 + TUNE_NEAR_FRONT)) {
        char *line = set_line(t, t->pts[p].idx);
        fprintf(stderr,
                "tune: pruned: %s already takes %.3f ms (median), more than the best answer "
                "so far (%.3f ms)\n",
                line, tp, tb);
        free(line);
        *pruned = true;
    }
    return 0;
}

/* The search within one combination of the categorical knobs (x holds them; the numeric
 * ones are set here). Returns 0 or an exit status. */
static int search_combo(tune *t, int *x)
{
    int p, rc;
    bool any_numeric = false;
    for (int i = 0; i < t->n_knobs; i++)
        if (t->k[i].numeric) {
            x[i] = 0;
            any_numeric = true;
        }
    /* the cheapest setting first: within E there, nothing in this combination is cheaper */
    if ((rc = eval(t, x, &p)) || p < 0 || feasible(t, &t->pts[p]) || !any_numeric)
        return rc;
    bool pruned;
    if ((rc = dominated_combo(t, p, &pruned)) || pruned)
        return rc;
    char *line;
    /* the most accurate setting: a combination that misses E there cannot meet it */
    for (int i = 0; i < t->n_knobs; i++)
        if (t->k[i].numeric)
            x[i] = t->k[i].n - 1;
    if ((rc = eval(t, x, &p)) || p < 0)
        return rc;
    if (!feasible(t, &t->pts[p])) {
        line = set_line(t, x);
        fprintf(stderr, "tune: pruned: even %s misses E (%.4g)\n", line, t->pts[p].err);
        free(line);
        return 0;
    }
    /* coordinate by coordinate until no knob moves */
    bool *scanned = lg_xcalloc((size_t)t->n_knobs, sizeof *scanned);
    for (bool moved = true; moved && rc == 0 && !t->budget_hit;) {
        moved = false;
        for (int i = 0; i < t->n_knobs && rc == 0; i++) {
            if (!t->k[i].numeric)
                continue;
            int before = x[i];
            rc = bisect(t, x, i, &scanned[i]);
            moved |= x[i] != before;
        }
    }
    free(scanned);
    return rc;
}

/* Every combination of the categorical knobs in turn (the first knob varies slowest). */
static int search(tune *t)
{
    int *x = lg_xcalloc((size_t)t->n_knobs, sizeof *x);
    int rc = 0;
    for (bool more = true; more && rc == 0 && !t->budget_hit;) {
        rc = search_combo(t, x);
        more = false;
        for (int i = t->n_knobs - 1; i >= 0 && !more; i--) {
            if (t->k[i].numeric)
                continue;
            if (++x[i] < t->k[i].n)
                more = true;
            else
                x[i] = 0;
        }
    }
    free(x);
    return rc;
}

/* Marks the points on the Pareto front of (median time, error). */
static void mark_front(tune *t)
{
    for (int p = 0; p < t->n_pts; p++) {
        point *a = &t->pts[p];
        a->on_front = !a->failed;
        double ta = median_ms(a);
        for (int q = 0; q < t->n_pts && a->on_front; q++) {
            point *b = &t->pts[q];
            double tb = median_ms(b);
            if (q != p && !b->failed && tb <= ta && b->err <= a->err &&
                (tb < ta || b->err < a->err))
                a->on_front = false;
        }
    }
}

/* ---- outputs --------------------------------------------------------------------------------- */

/* One row of tune.csv: point `num`, q's knobs, time, metrics and flags. */
static void csv_row(tune *t, lg_str *s, int num, point *q, bool check)
{
    lg_str_addf(s, "%d", num);
    for (int i = 0; i < t->n_knobs; i++)
        lg_str_addf(s, ",%s", t->k[i].values[q->idx[i]]);
    double med = median_ms(q);
    if (q->failed)
        lg_str_add(s, ",,,,0");
    else
        lg_str_addf(s, ",%.6g,%.6g,%.6g,%d", med, q->times[0], q->times[q->n_times - 1],
                    q->n_times);
    for (int m = 0; m < LG_METRIC_COUNT; m++) {
        double v = q->failed ? NAN : lg_metric_value(&q->m, (lg_metric_id)m);
        if (isfinite(v))
            lg_str_addf(s, ",%.6g", v);
        else
            lg_str_add(s, ",");
    }
    lg_str_addf(s, ",%d,%d,%d,%d\n", feasible(t, q), q->on_front, q->chosen, check);
}

/* The explored points, then the check render (check = 1: the chosen point's setting
 * rendered once more; not on the front nor chosen itself, so that a reader of the points
 * still finds one chosen row). The columns before `check` keep their order. */
static void csv_write(tune *t, lg_str *s)
{
    lg_str_add(s, "point");
    for (int i = 0; i < t->n_knobs; i++)
        lg_str_addf(s, ",%s.%s", t->a->node, t->k[i].pd->key);
    lg_str_add(s, ",time_ms,time_min_ms,time_max_ms,timings");
    for (int m = 0; m < LG_METRIC_COUNT; m++)
        lg_str_addf(s, ",%s", lg_metric_name((lg_metric_id)m));
    lg_str_add(s, ",within_target,on_front,chosen,check\n");
    int chosen = -1;
    for (int p = 0; p < t->n_pts; p++) {
        csv_row(t, s, p + 1, &t->pts[p], false);
        if (t->pts[p].chosen)
            chosen = p;
    }
    if (t->checked && t->check_rc == 0 && chosen >= 0) {
        point c = { .idx = t->pts[chosen].idx,
                    .times = &t->check_ms,
                    .n_times = 1,
                    .m = t->check_m,
                    .failed = t->check_failed };
        c.err = c.failed ? INFINITY : lg_metric_value(&c.m, t->a->metric);
        csv_row(t, s, t->n_pts + 1, &c, true);
    }
}

/* The gnuplot script: every point, the front as a line, the target, the chosen point. The
 * front and the choice are data blocks in the script (sorted by time), the points are read
 * from the CSV through `data` (default tune.csv beside it), the plot goes to `out`. */
static void gp_write(tune *t, lg_str *s)
{
    const lg_tune_args *a = t->a;
    int tcol = 2 + t->n_knobs, ecol = tcol + 4 + (int)a->metric;
    int ccol = tcol + 4 + LG_METRIC_COUNT + 3; /* check: that row is no explored point */
    lg_str_add(s, "# gnuplot script written by lightgraph tune: error against time\n");
    lg_str_add(s, "if (!exists('data')) data = 'tune.csv'\n");
    lg_str_add(s, "if (!exists('out')) out = 'tune.png'\n");
    lg_str_add(s, "$front << EOD\n");
    double *ft = lg_xcalloc((size_t)t->n_pts + 1, 2 * sizeof *ft);
    int nf = 0;
    for (int p = 0; p < t->n_pts; p++)
        if (t->pts[p].on_front) {
            ft[2 * nf] = median_ms(&t->pts[p]);
            ft[2 * nf + 1] = t->pts[p].err;
            nf++;
        }
    /* by time (insertion sort: the front is short) */
    for (int i = 1; i < nf; i++)
        for (int j = i; j > 0 && ft[2 * j] < ft[2 * j - 2]; j--) {
            double x = ft[2 * j], y = ft[2 * j + 1];
            ft[2 * j] = ft[2 * j - 2];
            ft[2 * j + 1] = ft[2 * j - 1];
            ft[2 * j - 2] = x;
            ft[2 * j - 1] = y;
        }
    for (int i = 0; i < nf; i++)
        lg_str_addf(s, "%.6g,%.6g\n", ft[2 * i], ft[2 * i + 1] > 0 ? ft[2 * i + 1] : 1e-12);
    free(ft);
    lg_str_add(s, "EOD\n$chosen << EOD\n");
    for (int p = 0; p < t->n_pts; p++)
        if (t->pts[p].chosen)
            lg_str_addf(s, "%.6g,%.6g\n", median_ms(&t->pts[p]),
                        t->pts[p].err > 0 ? t->pts[p].err : 1e-12);
    lg_str_add(s, "EOD\n");
    lg_str_add(s, "set terminal pngcairo size 900,600 noenhanced\n");
    lg_str_add(s, "set output out\nset datafile separator ','\n");
    lg_str_add(s, "set grid\nset logscale xy\nset key top right\n");
    lg_str_addf(s, "set xlabel 'time of node %s (ms, median; log scale)'\n", a->node);
    lg_str_addf(s, "set ylabel '%s against the reference'\n", lg_metric_name(a->metric));
    lg_str_addf(s, "set title 'lightgraph tune: %s at %s <= %g (the reference: %.4g ms)'\n",
                a->node, lg_metric_name(a->metric), a->target, t->ref_ms);
    /* the target across the whole plot (a function is drawn only where it is sampled) */
    lg_str_addf(s,
                "set arrow from graph 0, first %g to graph 1, first %g nohead dt 2 lc rgb 'red'\n",
                a->target, a->target);
    lg_str_addf(s,
                "plot data every ::1 using %d:($%d == 1 ? NaN : $%d > 0 ? $%d : 1e-12) "
                "with points pt 7 ps 1 "
                "lc rgb 'gray50' title 'explored', \\\n"
                "     $front using 1:2 with linespoints pt 7 ps 1.3 lc rgb 'blue' "
                "title 'Pareto front', \\\n"
                "     NaN with lines dt 2 lc rgb 'red' title 'target %g', \\\n"
                "     $chosen using 1:2 with points pt 6 ps 3 lw 2 lc rgb 'dark-green' "
                "title 'chosen'\n",
                tcol, ccol, ecol, ecol, a->target);
}

/* Reserves tune.csv, tune.gp, tune.png in DIR (proving it writable) and names the render
 * temporary's destination. Returns 0, or 1 (printed). */
static int reserve_outputs(tune *t)
{
    const char *dir = t->a->dir;
    char err[1024];
    t->outs = lg_outputs_new();
    t->render_out = lg_xasprintf("%s/tune-render.exr", dir);
    t->csv_path = lg_xasprintf("%s/tune.csv", dir);
    t->gp_path = lg_xasprintf("%s/tune.gp", dir);
    t->png_path = lg_xasprintf("%s/tune.png", dir);
    int rc = lg_outputs_check(t->render_out, LG_OUTPUT_IMAGE, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_add(t->outs, t->csv_path, LG_OUTPUT_FILE, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_add(t->outs, t->gp_path, LG_OUTPUT_FILE, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_add(t->outs, t->png_path, LG_OUTPUT_IMAGE, err, sizeof err);
    if (rc) {
        fprintf(stderr, "lightgraph tune: %s; nothing was run\n", err);
        return 1;
    }
    return 0;
}

/* Writes the CSV and the script, plots, and commits the three together. Returns 0 or 1. */
static int write_outputs(tune *t, bool *plotted)
{
    char err[1024];
    lg_str csv = { 0 }, gp = { 0 };
    csv_write(t, &csv);
    gp_write(t, &gp);
    int rc = lg_outputs_write_data(t->outs, t->csv_path, csv.s, csv.len, err, sizeof err) ||
             lg_outputs_write_data(t->outs, t->gp_path, gp.s, gp.len, err, sizeof err);
    lg_str_free(&csv);
    lg_str_free(&gp);
    if (rc) {
        fprintf(stderr, "lightgraph tune: %s\n", err);
        return 1;
    }
    *plotted = lg_run_gnuplot(t->a->dir, lg_outputs_temp(t->outs, t->gp_path),
                              lg_outputs_temp(t->outs, t->csv_path),
                              lg_outputs_temp(t->outs, t->png_path)) == 0;
    if (!*plotted)
        lg_outputs_drop(t->outs, t->png_path);
    if (lg_outputs_commit(t->outs, err, sizeof err)) {
        fprintf(stderr, "lightgraph tune: %s\n", err);
        return 1;
    }
    return 0;
}

/* ---- set-up ---------------------------------------------------------------------------------- */

/* Whether --set fixes N.P (then it is not a knob unless --vary names it). */
static bool set_fixes(const lg_tune_args *a, const char *key)
{
    size_t nl = strlen(a->node), kl = strlen(key);
    for (int i = 0; i < a->n_sets; i++)
        if (strncmp(a->sets[i], a->node, nl) == 0 && a->sets[i][nl] == '.' &&
            strncmp(a->sets[i] + nl + 1, key, kl) == 0 && a->sets[i][nl + 1 + kl] == '=')
            return true;
    return false;
}

/* A --vary's parameter: PARAM, or NODE.PARAM of the tuned node. */
static const lg_param_desc *vary_param(const lg_node_type *ty, const char *node, const char *p)
{
    size_t nl = strlen(node);
    if (strncmp(p, node, nl) == 0 && p[nl] == '.')
        p += nl + 1;
    for (uint32_t i = 0; i < ty->n_params; i++)
        if (strcmp(ty->params[i].key, p) == 0)
            return &ty->params[i];
    return NULL;
}

/* Finds node N in the graph (with --set) and makes its knobs. Returns 0 or 2 (printed). */
static int make_knobs(tune *t)
{
    const lg_tune_args *a = t->a;
    lg_graph *g;
    lg_checked *c;
    int rc = lg_load_graph(&t->reg, a->graph, a->sets, a->n_sets, &g, &c);
    const lg_cnode *cn = NULL;
    for (uint32_t i = 0; rc == 0 && i < c->n_nodes; i++)
        if (strcmp(c->nodes[i].g->name, a->node) == 0)
            cn = &c->nodes[i];
    if (rc == 0 && !cn) {
        const char **names = lg_xcalloc(c->n_nodes + 1, sizeof *names);
        for (uint32_t i = 0; i < c->n_nodes; i++)
            names[i] = c->nodes[i].g->name;
        const char *s = lg_suggest(a->node, names, c->n_nodes);
        fprintf(stderr, "lightgraph tune: --node %s: %s has no node of that name%s%s%s\n", a->node,
                a->graph, s ? "; did you mean '" : "", s ? s : "", s ? "'?" : "");
        free(names);
        rc = 2;
    }
    char err[1024];
    if (rc == 0) {
        const lg_node_type *ty = t->type = cn->type;
        t->k = lg_xcalloc(ty->n_params + (size_t)a->n_vary + 1, sizeof *t->k);
        for (int v = 0; v < a->n_vary && rc == 0; v++) {
            const lg_param_desc *pd = vary_param(ty, a->node, a->vary[v].param);
            if (!pd) {
                const char **keys = lg_xcalloc(ty->n_params + 1, sizeof *keys);
                for (uint32_t i = 0; i < ty->n_params; i++)
                    keys[i] = ty->params[i].key;
                const char *s = lg_suggest(a->vary[v].param, keys, ty->n_params);
                fprintf(stderr,
                        "lightgraph tune: --vary %s: node '%s' (%s) has no parameter '%s'%s%s%s\n",
                        a->vary[v].arg, a->node, ty->name, a->vary[v].param,
                        s ? "; did you mean '" : "", s ? s : "", s ? "'?" : "");
                free(keys);
                rc = 2;
            } else if (lg_tune_knob_from_range(&t->k[t->n_knobs++], pd, &a->vary[v], a->node, err,
                                               sizeof err)) {
                fprintf(stderr, "lightgraph tune: %s\n", err);
                rc = 2;
            }
        }
        for (uint32_t i = 0; i < ty->n_params && rc == 0 && a->n_vary == 0; i++) {
            const lg_param_desc *pd = &ty->params[i];
            const char *why = NULL;
            if (pd->role == LG_ROLE_OUTPUT_FILE || set_fixes(a, pd->key))
                continue;
            if (lg_tune_knob_default(&t->k[t->n_knobs], pd, &why))
                t->n_knobs++;
            else if (why && (pd->type == LG_PARAM_INT || pd->type == LG_PARAM_FLOAT))
                fprintf(stderr, "tune: %s.%s is not varied: %s\n", a->node, pd->key, why);
            else
                lg_tune_knob_free(&t->k[t->n_knobs]); /* a default that gave up */
        }
        if (rc == 0 && t->n_knobs == 0) {
            fprintf(stderr, "lightgraph tune: node '%s' (%s) has no knob to vary\n", a->node,
                    ty->name);
            rc = 2;
        }
    }
    lg_checked_free(c);
    lg_graph_free(g);
    return rc;
}

/* Checks, before anything runs, the reference and each knob's extreme values (every value
 * of a categorical knob) as `check` would: values the node refuses in combination, files,
 * references. Returns 0, or 2 after the checker's diagnostics. */
static int check_values(tune *t)
{
    const lg_tune_args *a = t->a;
    const char *ref_graph = a->reference ? a->reference : a->graph;
    const char **rs = lg_xcalloc((size_t)(a->n_sets + a->n_ref_sets) + 2, sizeof *rs);
    int nrs = 0, rc = 0;
    if (!a->reference)
        for (int i = 0; i < a->n_sets; i++)
            rs[nrs++] = a->sets[i];
    for (int i = 0; i < a->n_ref_sets; i++)
        rs[nrs++] = a->ref_sets[i];
    if (lg_check_file(&t->reg, ref_graph, rs, nrs)) {
        fprintf(stderr, "lightgraph tune: the reference %s is refused (above); nothing was run\n",
                ref_graph);
        rc = 2;
    }
    for (int i = 0; i < a->n_sets; i++)
        rs[i] = a->sets[i];
    for (int k = 0; k < t->n_knobs && rc == 0; k++)
        for (int j = 0; j < t->k[k].n && rc == 0; j++) {
            if (t->k[k].numeric && j != 0 && j != t->k[k].n - 1)
                continue;
            char *kv = lg_xasprintf("%s.%s=%s", a->node, t->k[k].pd->key, t->k[k].values[j]);
            rs[a->n_sets] = kv;
            if (lg_check_file(&t->reg, a->graph, rs, a->n_sets + 1)) {
                fprintf(stderr, "lightgraph tune: %s is refused (above); nothing was run\n", kv);
                rc = 2;
            }
            free(kv);
        }
    free(rs);
    return rc;
}

/* Renders the reference once, keeping its image and node N's time (or the total). */
static int render_reference(tune *t)
{
    const lg_tune_args *a = t->a;
    const char *ref_graph = a->reference ? a->reference : a->graph;
    const char **rs = lg_xcalloc((size_t)(a->n_sets + a->n_ref_sets) + 1, sizeof *rs);
    int nrs = 0;
    if (!a->reference)
        for (int i = 0; i < a->n_sets; i++)
            rs[nrs++] = a->sets[i];
    for (int i = 0; i < a->n_ref_sets; i++)
        rs[nrs++] = a->ref_sets[i];
    lg_run_result res;
    if (lg_verbosity >= 0)
        fprintf(stderr, "tune: reference (%s)\n", ref_graph);
    /* every rank renders it (a node's lg_shard spreads over the ranks only when every
     * rank makes the call), then rank 0's pixels and time are every rank's: every rank
     * judges against the same bits */
    int rc = lg_dist_agree(render_once(t, ref_graph, rs, nrs, &t->ref, &res), NULL);
    free(rs);
    if (rc)
        return rc;
    struct {
        uint32_t width, height;
        double ms;
        int32_t found;
    } head = { t->ref.width, t->ref.height, res.node_found ? res.node_ms : res.total_ms,
               res.node_found };
    if (lg_dist_bcast(&head, sizeof head))
        return 1;
    t->ref_node_found = head.found;
    t->ref_ms = head.ms;
    if ((head.width != t->ref.width || head.height != t->ref.height) &&
        (lg_image_free(&t->ref), lg_image_alloc(&t->ref, head.width, head.height))) {
        fprintf(stderr, "lightgraph tune: no memory for the reference (%ux%u)\n", head.width,
                head.height);
        rc = 1;
    }
    if (lg_dist_bcast(t->ref.pixels, (size_t)head.width * head.height * 4 * sizeof(float)))
        rc = 1;
    /* a metric that cannot be computed on these images (dssim below 11 x 11 pixels: no SSIM
     * window) would make every point miss E; said now, as bad usage */
    lg_metric_set m;
    char err[512];
    if (rc == 0 && (lg_metrics_compute(&t->ref, &t->ref, &m, NULL, 0, err, sizeof err) ||
                    isnan(lg_metric_value(&m, a->metric)))) {
        fprintf(stderr,
                "lightgraph tune: --metric %s cannot be computed on %ux%u images (docs/"
                "metrics.md)\n",
                lg_metric_name(a->metric), t->ref.width, t->ref.height);
        rc = 2;
    }
    return rc;
}

static void tune_free(tune *t)
{
    lg_outputs_free(&t->outs);
    for (int i = 0; i < t->n_knobs; i++)
        lg_tune_knob_free(&t->k[i]);
    free(t->k);
    for (int p = 0; p < t->n_pts; p++) {
        free(t->pts[p].idx);
        free(t->pts[p].times);
    }
    free(t->pts);
    free(t->render_out);
    free(t->csv_path);
    free(t->gp_path);
    free(t->png_path);
    lg_image_free(&t->ref);
    lg_registry_free(&t->reg);
}

/* ---- the report ------------------------------------------------------------------------------ */

static void print_knobs(const tune *t)
{
    const lg_tune_args *a = t->a;
    printf("tune: node %s (%s) in %s: %s <= %g against %s\n", a->node, t->type->name, a->graph,
           lg_metric_name(a->metric), a->target,
           a->reference ? a->reference : "the graph with --ref-set");
    for (int i = 0; i < t->n_knobs; i++)
        printf("knob: %s.%s: %s (%d value%s)\n", a->node, t->k[i].pd->key, t->k[i].grid, t->k[i].n,
               t->k[i].n == 1 ? "" : "s");
}

/* The check render: the chosen setting once more, judged again (before the outputs are
 * written, so that tune.csv holds it; report prints it). */
static void check_render(tune *t, int chosen)
{
    if (chosen < 0)
        return;
    point_sent sent;
    const int *idx = t->pts[chosen].idx;
    if (render_points(t, &idx, 1, &sent)) {
        sent.rc = 1;
        sent.failed = 1;
    }
    t->check_rc = sent.rc;
    t->check_ms = sent.ms;
    t->check_m = sent.m;
    t->check_failed = sent.failed;
    t->checked = true;
}

/* The answer, its check render and the counts. Returns the exit status. */
static int report(tune *t, int chosen)
{
    const lg_tune_args *a = t->a;
    const char *mn = lg_metric_name(a->metric);
    int rc = 0;
    if (t->budget_hit)
        printf("note: the search stopped at --max-renders %u: the answer is the best found, "
               "perhaps not the cheapest\n",
               a->max_renders);
    if (chosen < 0) {
        int best = -1;
        for (int p = 0; p < t->n_pts; p++)
            if (!t->pts[p].failed && (best < 0 || t->pts[p].err < t->pts[best].err))
                best = p;
        if (best >= 0) {
            char *line = set_line(t, t->pts[best].idx);
            printf("E is out of reach on this scene: best %s %.4g at %s\n", mn, t->pts[best].err,
                   line);
            free(line);
        } else {
            printf("E is out of reach on this scene: no render succeeded\n");
        }
        rc = 1;
    } else {
        point *c = &t->pts[chosen];
        rc = t->check_rc;
        double check = t->check_failed ? INFINITY : lg_metric_value(&t->check_m, a->metric);
        bool meets = rc == 0 && !t->check_failed && check <= a->target;
        char *line = set_line(t, c->idx);
        double med = median_ms(c);
        printf("answer: %s\n", line);
        printf("error: %s %.4g (target %g)\n", mn, c->err, a->target);
        printf("time: %.3f ms median [%.3f-%.3f] over %d render%s (node %s)\n", med, c->times[0],
               c->times[c->n_times - 1], c->n_times, c->n_times == 1 ? "" : "s", a->node);
        printf("check: %s %.4g, %s\n", mn, check, meets ? "meets the target" : "MISSES the target");
        free(line);
        if (rc == 0 && !meets)
            rc = 1;
    }
    printf("reference: %.3f ms (%s, one render)\n", t->ref_ms,
           t->ref_node_found ? "its node of that name" : "all its nodes");
    int check = chosen >= 0 ? 1 : 0;
    printf("renders: %d (search %d + timing repeats %d + check %d), reference 1; full grid "
           "%.0f\n",
           t->renders + t->repeats + check, t->renders, t->repeats, check, t->grid_size);
    return rc;
}

int lg_cmd_tune(int argc, char **argv)
{
    lg_tune_args args;
    char err[1024];
    int rc = lg_tune_parse_args(argc, argv, &args, err, sizeof err);
    if (rc) {
        usage(err);
        lg_tune_args_free(&args);
        return rc;
    }
    if (args.size_given && lg_size_over_limit("tune", args.width, args.height)) {
        lg_tune_args_free(&args);
        return 2;
    }
    if (args.quiet)
        lg_verbosity = -1;
    tune t;
    memset(&t, 0, sizeof t);
    t.a = &args;
    t.opts = lg_measure_opts(args.width, args.height, args.frames, args.gl_backend);
    lg_registry_scan(&t.reg);

    /* everything is checked before the first render: the node, its knobs, the values, the
     * reference, the files */
    /* Under mpirun every rank checks and agrees; rank 0 alone reserves the outputs in DIR,
     * the others render into their TMPDIR (DIR may be on rank 0's machine only). */
    rc = lg_dist_agree(make_knobs(&t), NULL);
    if (rc == 0)
        rc = lg_dist_agree(check_values(&t), NULL);
    if (rc == 0 && lg_dist_root()) {
        rc = lg_dist_agree(reserve_outputs(&t), NULL);
    } else if (rc == 0) {
        const char *tmp = getenv("TMPDIR");
        t.render_out = lg_xasprintf("%s/tune-render.exr", tmp && tmp[0] ? tmp : "/tmp");
        rc = lg_dist_agree(0, NULL);
    }
    if (rc == 0) {
        t.grid_size = 1;
        for (int i = 0; i < t.n_knobs; i++)
            t.grid_size *= t.k[i].n;
        print_knobs(&t);
        fflush(stdout);
        rc = render_reference(&t);
    }
    if (rc == 0)
        rc = search(&t);
    if (rc == 0)
        rc = repeat_near_front(&t);
    if (rc == 0) {
        int chosen = cheapest(&t);
        if (chosen >= 0)
            t.pts[chosen].chosen = true;
        mark_front(&t);
        check_render(&t, chosen);
        bool plotted = false;
        int out_rc = lg_dist_root() ? write_outputs(&t, &plotted) : 0;
        rc = report(&t, chosen);
        if (out_rc == 0 && lg_dist_root()) /* rank 0 alone writes (and says so) */
            printf("wrote %s, %s%s\n", t.csv_path, t.gp_path,
                   plotted ? " and tune.png" : " (gnuplot not run: install gnuplot-nox)");
        else if (out_rc && rc == 0)
            rc = 1;
    } else if (t.outs) {
        fprintf(stderr, "lightgraph tune: nothing was written to %s\n", args.dir);
    }
    tune_free(&t);
    lg_tune_args_free(&args);
    return rc;
}
