/* lightgraph sweep: what accuracy costs. Renders a graph across parameter values, compares
 * every output with a reference, times the node of interest, and writes a CSV, heat maps
 * and a gnuplot plot of error against time.
 *
 *   lightgraph sweep GRAPH --vary NODE.PARAM=v1,v2,... [--vary ...]
 *                    [--reference REF_GRAPH|REF_IMAGE] [--ref-set NODE.PARAM=V]...
 *                    [--set NODE.PARAM=V]... [--time NODE] [--repeat N] [--frames N]
 *                    [--size WxH] [--gl osmesa|egl] [--metric M] [-o DIR]
 *
 * The reference is REF_GRAPH if given, else GRAPH itself with the --set and --ref-set
 * overrides (e.g. the finest tessellation and per-pixel shading), or REF_IMAGE, an image
 * rendered before (a name ending in .exr, .hdr, .pic or .png; its size is the runs' unless
 * --size says otherwise, and must then match). Every run gets the --set
 * overrides, then one combination of the --vary values (their cartesian product). Times
 * are the median over --repeat runs of the --time node's CPU wall time (which includes its
 * GL work, see docs/devices.md), or of all kept nodes when --time is not given. With
 * --frames N (default 1) every run renders N frames (the outputs are the last frame's, so
 * that state carried across frames, a temporal filter's, shows in the error) and a node that
 * ran on several frames is timed per frame in steady state: the mean of its runs after the
 * first (which pays for shader compilation and first uploads).
 *
 * Every run is judged by lg_metrics_compute (metric.h), the metrics diff and tune report:
 * the CSV has today's columns first (readers that index them keep working), then rel_rmse,
 * ssim, dssim, time_max_ms (the slowest of --repeat) and ref_ms (the reference render's own
 * total time, once, or empty for a REF_IMAGE); --metric chooses the error the plot shows.
 *
 * All or nothing (outputs.h): every --vary value is checked against its parameter's type and
 * range, the reference graph is checked, and every file the sweep writes (reference, runs,
 * heat maps, CSV, script, plot) is checked before the first run, as is the free space of
 * DIR's file system against what the outputs need (sweep_bytes); the reference, CSV, script
 * and plot get their temporaries in DIR (default out/sweep, which must exist) then, each
 * run's image and heat map when the run starts; the files are committed together at the
 * end, or none.
 *
 * Under `mpirun -np N` (docs/distributed.md, docs/sweep.md) the runs are spread over the ranks
 * by lg_dist_map (exec/dist.h), one run an item: a rank renders its runs whole (the graph's
 * own lg_shard calls run on that rank alone), judges them against the reference and sends
 * rank 0 what it writes: the run's EXR and heat map as files' bytes, its CSV row and its line.
 * Every rank renders the reference together (its lg_shard calls are spread over the ranks)
 * and rank 0's pixels are broadcast, so that every rank judges against the same bits. Rank 0
 * alone checks DIR, writes and commits; the CSV is the one process's but for the times,
 * measured on the rank that ran the run. */
#include "cli/commands.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>

#include "lightgraph/image.h"
#include "exec/dist.h"
#include "exec/outputs.h"
#include "cli/metric.h"
#include "cli/sweep_args.h"

typedef lg_sweep_vary vary;

/* The reason (sweep_args.c), then the usage. */
static int usage(const char *msg)
{
    fprintf(stderr, "lightgraph sweep: %s\n", msg);
    fprintf(
        stderr,
        "usage: lightgraph sweep GRAPH --vary NODE.PARAM=v1,v2,... [--vary ...]\n"
        "                        [--reference REF_GRAPH|REF_IMAGE] [--ref-set NODE.PARAM=V]...\n"
        "                        [--set NODE.PARAM=V]... [--time NODE] [--repeat N]\n"
        "                        [--frames N] [--size WxH] [--gl osmesa|egl] [--metric M]\n"
        "                        [-o DIR]\n"
        "DIR (default out/sweep) must exist; nothing is written unless every run succeeds\n"
        "M, the error the plot shows (default rmse; the CSV has every one):\n"
        "  %s\n",
        lg_metric_names());
    return 2;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static char *csv_field(const char *s)
{
    if (!strpbrk(s, ",\"\n"))
        return lg_xstrdup(s);
    lg_str b = { 0 };
    lg_str_addc(&b, '"');
    for (; *s; s++) {
        if (*s == '"')
            lg_str_addc(&b, '"');
        lg_str_addc(&b, *s);
    }
    lg_str_addc(&b, '"');
    return lg_str_take(&b);
}

static int read_image(const char *path, lg_image *img)
{
    char err[512];
    if (lg_image_read(path, 0, img, NULL, err, sizeof err)) {
        fprintf(stderr, "lightgraph sweep: %s\n", err);
        return -1;
    }
    return 0;
}

/* The gnuplot script. It names its data and image through the variables `data` and `out`,
 * which default to sweep.csv and sweep.png in its directory: the sweep runs it on the
 * temporaries before they are committed, a user reruns it as it is. */
/* The CSV's columns after the varied parameters (csv_header), and the one of each metric. */
enum {
    COL_TIME,
    COL_TIME_MIN,
    COL_RMSE,
    COL_PSNR,
    COL_MEAN_ABS,
    COL_MAX_ABS,
    COL_REL_MSE,
    COL_NONFINITE,
    COL_REL_RMSE,
    COL_SSIM,
    COL_DSSIM,
    COL_TIME_MAX,
    COL_REF_MS
};
static const int metric_column[LG_METRIC_COUNT] = {
    [LG_METRIC_RMSE] = COL_RMSE,         [LG_METRIC_REL_RMSE] = COL_REL_RMSE,
    [LG_METRIC_MEAN_ABS] = COL_MEAN_ABS, [LG_METRIC_MAX_ABS] = COL_MAX_ABS,
    [LG_METRIC_REL_MSE] = COL_REL_MSE,   [LG_METRIC_DSSIM] = COL_DSSIM,
};
static const char *const metric_label[LG_METRIC_COUNT] = {
    [LG_METRIC_RMSE] = "RMSE",
    [LG_METRIC_REL_RMSE] = "relative RMSE",
    [LG_METRIC_MEAN_ABS] = "mean absolute error",
    [LG_METRIC_MAX_ABS] = "max absolute error",
    [LG_METRIC_REL_MSE] = "relative MSE",
    [LG_METRIC_DSSIM] = "DSSIM (1 - SSIM)",
};

static int write_gnuplot(lg_outputs *outs, const char *gp, const vary *v, int n_vary,
                         lg_metric_id metric, char *err, size_t errlen)
{
    lg_str s = { 0 };
    lg_str_add(&s, "# gnuplot script written by lightgraph sweep: error against time\n");
    lg_str_add(&s, "if (!exists('data')) data = 'sweep.csv'\n");
    lg_str_add(&s, "if (!exists('out')) out = 'sweep.png'\n");
    lg_str_add(&s, "set terminal pngcairo size 900,600 noenhanced\n");
    lg_str_add(&s, "set output out\nset datafile separator ','\n");
    lg_str_add(&s, "set key off\nset grid\nset logscale y\n");
    lg_str_add(&s, "set xlabel 'time (ms, median; bars: fastest to slowest of --repeat)'\n");
    lg_str_addf(&s, "set ylabel '%s against the reference'\n", metric_label[metric]);
    lg_str_add(&s, "set title 'what accuracy costs: ");
    for (int i = 0; i < n_vary; i++)
        lg_str_addf(&s, "%s%s", i ? ", " : "", v[i].key);
    lg_str_add(&s, "'\n");
    /* columns: run, varied params..., then COL_TIME ... (gnuplot counts from 1); an error
     * of 0 (the reference's own settings) is drawn at 1e-12 on the log scale */
    int tcol = 2 + n_vary, ecol = tcol + metric_column[metric];
    int tmin = tcol + COL_TIME_MIN, tmax = tcol + COL_TIME_MAX;
    lg_str_addf(&s,
                "plot data every ::1 using %d:($%d > 0 ? $%d : 1e-12):%d:%d with xerrorbars "
                "pt 7 ps 1.5, \\\n     '' every ::1 using %d:($%d > 0 ? $%d : 1e-12):(",
                tcol, ecol, ecol, tmin, tmax, tcol, ecol, ecol);
    for (int i = 0; i < n_vary; i++)
        lg_str_addf(&s, "%sstrcol(%d)", i ? ".' '." : "", 2 + i);
    lg_str_add(&s, ") with labels offset 1,1 left\n");
    int rc = lg_outputs_write_data(outs, gp, s.s, s.len, err, errlen);
    lg_str_free(&s);
    return rc;
}

/* Bytes a sweep writes into DIR, at most: the reference and every run as an EXR of the
 * render size (--size) in float RGBA, which is what the host writes an rgba32f render as
 * (ZIP compression saves little on noisy renders, so the raw size is the estimate), a heat
 * map per run (PNG, RGBA8 raw), a CSV row per run, the script and the plot (a 900x600
 * PNG of points and labels: tens of KiB, 256 KiB allowed). The
 * temporaries stay until the commit, and a file they replace stays until then too (as a
 * backup), so all of it must fit at once. */
static double sweep_bytes(int total, int n_vary, const lg_exec_opts *opts)
{
    double px = (double)opts->width * opts->height;
    double exr = px * 16 + 4096, heat = px * 4 + 4096;
    double csv = 256.0 + (double)total * (160.0 + 32.0 * n_vary);
    return (total + 1.0) * exr + total * heat + csv + 4096 + 256.0 * 1024;
}

/* Refuses, before the first run, a sweep whose outputs the file system of DIR has no room
 * for (statvfs: the blocks an unprivileged user may use). Returns 0, or 1 after a message.
 * A file system that cannot say is not refused. */
static int check_space(const char *dir, int total, int n_vary, const lg_exec_opts *opts)
{
    double need = sweep_bytes(total, n_vary, opts);
    double have;
    if (lg_test_free_bytes >= 0) {
        have = (double)lg_test_free_bytes;
    } else {
        struct statvfs sv;
        if (statvfs(dir, &sv) != 0) {
            lg_hlog(LG_HWARN, "sweep: cannot tell the free space in '%s' (%s); not checked", dir,
                    strerror(errno));
            return 0;
        }
        have = (double)sv.f_bavail * (double)sv.f_frsize;
    }
    lg_hlog(LG_HINFO, "sweep: the outputs need up to %.3g GiB in '%s', which has %.3g GiB free",
            need / 1073741824.0, dir, have / 1073741824.0);
    if (need <= have)
        return 0;
    fprintf(stderr,
            "lightgraph sweep: the %d runs need about %.3g GiB in '%s' (%d EXR images of %ux%u "
            "at 16 bytes a pixel, %d heat maps, the CSV and the plot), and its file system "
            "has %.3g GiB free; nothing was run (sweep fewer values, render smaller with "
            "--size, or write elsewhere with -o DIR)\n",
            total, need / 1073741824.0, dir, total + 1, opts->width, opts->height, total,
            have / 1073741824.0);
    return 1;
}

/* A sweep under way: its arguments, the render options every run shares, and what it has
 * made so far (freed by sweep_free). */
typedef struct sweep {
    const lg_sweep_args *a;
    lg_exec_opts opts;
    lg_registry reg;
    lg_outputs *outs;
    lg_image ref;   /* the reference, read back from its temporary, or REF_IMAGE */
    bool ref_image; /* --reference names an image, not a graph */
    double ref_ms;  /* the reference render's total time; NaN for REF_IMAGE */
    lg_str csv;
    char **runs, **heats; /* per run: its image and its heat map (a->total each); rank 0 */
    char *ref_out, *csv_path, *gp_path, *png_path;
    /* the runs spread over the ranks (sweep_item): where a rank other than 0 renders (its
     * TMPDIR: DIR may exist on rank 0's machine only), the runs an earlier batch made, the
     * exit status of this rank's failing run, and scratch arrays of n_sets + n_vary and
     * repeat entries */
    const char *scratch;
    uint64_t batch_from;
    int item_rc;
    const char **run_sets;
    double *times;
} sweep;

/* The last error the host logged (lg_hlog_error_hook) while a run rendered: the reason a
 * failed run sends to rank 0, which does not see a rank's stderr. */
static char last_error[400];
static void keep_error(const char *m)
{
    snprintf(last_error, sizeof last_error, "%s", m);
}

/* The reference's overrides: the --set ones unless a reference graph is given, then the
 * --ref-set ones; an array with room for `extra` more (free it), the count in *n. */
static const char **reference_sets(const lg_sweep_args *a, int extra, int *n)
{
    const char **rs = lg_xcalloc((size_t)(a->n_sets + a->n_ref_sets + extra) + 1, sizeof *rs);
    *n = 0;
    if (!a->reference)
        for (int i = 0; i < a->n_sets; i++)
            rs[(*n)++] = a->sets[i];
    for (int i = 0; i < a->n_ref_sets; i++)
        rs[(*n)++] = a->ref_sets[i];
    return rs;
}

/* "NODE.PARAM=VALUE" for the j-th value of a --vary (malloc'd). */
static char *vary_set(const vary *v, int j)
{
    return lg_xasprintf("%s=%s", v->key, v->values[j]);
}

/* REF_IMAGE, read before anything runs (an image has no parameters: --ref-set is refused).
 * Without --size the runs render at its size. Returns 0, or 2 after a message. */
static int read_reference_image(sweep *sw)
{
    const lg_sweep_args *a = sw->a;
    char err[1024];
    if (a->n_ref_sets) {
        fprintf(stderr,
                "lightgraph sweep: --ref-set %s: the reference '%s' is an image, which has no "
                "parameters to set; nothing was run\n",
                a->ref_sets[0], a->reference);
        return 2;
    }
    if (lg_image_read(a->reference, 0, &sw->ref, NULL, err, sizeof err)) {
        fprintf(stderr, "lightgraph sweep: --reference: %s; nothing was run\n", err);
        return 2;
    }
    if (!a->size_given) {
        sw->opts.width = sw->ref.width;
        sw->opts.height = sw->ref.height;
    }
    return 0;
}

/* Checks, before anything runs, the reference (a graph, or REF_IMAGE read) and every --vary
 * value against its parameter's type and range (the graph with --set and that value,
 * checked as `check` does). Returns 0, or 2 after the checker's diagnostics and the sweep's
 * own line. */
static int check_values(sweep *sw)
{
    const lg_sweep_args *a = sw->a;
    const char *ref_graph = a->reference ? a->reference : a->graph;
    int nrs, rc = 0;
    const char **rs = reference_sets(a, 1, &nrs);
    if (sw->ref_image) {
        rc = read_reference_image(sw);
    } else if (lg_check_file(&sw->reg, ref_graph, rs, nrs)) {
        fprintf(stderr,
                "lightgraph sweep: the reference %s is refused (above); nothing "
                "was run\n",
                ref_graph);
        rc = 2;
    }
    for (int i = 0; i < a->n_vary && rc == 0; i++)
        for (int j = 0; j < a->vary[i].n && rc == 0; j++) {
            for (int k = 0; k < a->n_sets; k++)
                rs[k] = a->sets[k];
            char *kv = vary_set(&a->vary[i], j);
            rs[a->n_sets] = kv;
            if (lg_check_file(&sw->reg, a->graph, rs, a->n_sets + 1)) {
                fprintf(stderr,
                        "lightgraph sweep: --vary %s: the value '%s' is refused (above); "
                        "nothing was run\n",
                        a->vary[i].key, a->vary[i].values[j]);
                rc = 2;
            }
            free(kv);
        }
    free(rs);
    return rc;
}

/* Checks every file the sweep writes and reserves the temporaries of the reference, the
 * CSV, the script and the plot, which also proves DIR writable; the runs' images and heat
 * maps are checked now and get their temporaries when their run starts (a sweep that stops
 * early has made only what it reached). Then DIR's free space. Returns 0, or 1 (printed). */
static int reserve_outputs(sweep *sw)
{
    const char *dir = sw->a->dir;
    int total = sw->a->total;
    char err[1024];
    sw->outs = lg_outputs_new();
    sw->ref_out = lg_xasprintf("%s/reference.exr", dir);
    sw->csv_path = lg_xasprintf("%s/sweep.csv", dir);
    sw->gp_path = lg_xasprintf("%s/sweep.gp", dir);
    sw->png_path = lg_xasprintf("%s/sweep.png", dir);
    sw->runs = lg_xcalloc((size_t)total, sizeof *sw->runs);
    sw->heats = lg_xcalloc((size_t)total, sizeof *sw->heats);
    int rc = lg_outputs_add(sw->outs, sw->ref_out, LG_OUTPUT_IMAGE, err, sizeof err);
    for (int k = 0; k < total && rc == 0; k++) {
        sw->runs[k] = lg_xasprintf("%s/run-%03d.exr", dir, k);
        sw->heats[k] = lg_xasprintf("%s/heat-%03d.png", dir, k);
        rc = lg_outputs_check(sw->runs[k], LG_OUTPUT_IMAGE, err, sizeof err);
        if (rc == 0)
            rc = lg_outputs_check(sw->heats[k], LG_OUTPUT_IMAGE, err, sizeof err);
    }
    if (rc == 0)
        rc = lg_outputs_add(sw->outs, sw->csv_path, LG_OUTPUT_FILE, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_add(sw->outs, sw->gp_path, LG_OUTPUT_FILE, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_add(sw->outs, sw->png_path, LG_OUTPUT_IMAGE, err, sizeof err);
    if (rc) {
        fprintf(stderr, "lightgraph sweep: %s; nothing was run\n", err);
        return 1;
    }
    return check_space(dir, total, sw->a->n_vary, &sw->opts) ? 1 : 0;
}

/* Renders the reference into its output's temporary and reads it back from there, timing
 * it (ref_ms); REF_IMAGE, read already, is written there as it is. Returns the exit status. */
static int render_reference(sweep *sw)
{
    const lg_sweep_args *a = sw->a;
    const char *ref_graph = a->reference ? a->reference : a->graph;
    sw->ref_ms = NAN;
    if (sw->ref_image) {
        char err[1024];
        fprintf(stderr, "sweep: reference (image %s, %ux%u)\n", a->reference, sw->ref.width,
                sw->ref.height);
        /* rank 0 alone writes it (the others have no outputs) */
        if (sw->outs &&
            lg_outputs_write_image(sw->outs, sw->ref_out, &sw->ref, NULL, err, sizeof err)) {
            fprintf(stderr, "lightgraph sweep: %s\n", err);
            return 1;
        }
        return 0;
    }
    int nrs;
    const char **rsets = reference_sets(a, 0, &nrs);
    /* Every rank renders it (a node's lg_shard spreads over the ranks only when every rank
     * makes the call), rank 0 into its output's temporary, the others into a temporary of
     * their own that is removed once read. */
    lg_outputs *own = lg_dist_root() ? NULL : lg_outputs_new();
    char *dest = own ? lg_xasprintf("%s/reference.exr", sw->scratch) : NULL;
    char err[1024];
    lg_exec_opts o = sw->opts;
    o.output_override = own ? dest : sw->ref_out;
    o.outputs = own ? own : sw->outs;
    lg_run_result res;
    fprintf(stderr, "sweep: reference (%s)\n", ref_graph);
    int rc = 0;
    if (own && lg_outputs_add(own, dest, LG_OUTPUT_IMAGE, err, sizeof err)) {
        fprintf(stderr, "lightgraph sweep: %s\n", err);
        rc = 1;
    }
    if (rc == 0)
        rc = lg_render_file(&sw->reg, ref_graph, rsets, nrs, &o, NULL, &res);
    free(rsets);
    if (rc == 0)
        sw->ref_ms = res.total_ms;
    if (rc == 0 && read_image(lg_outputs_temp(o.outputs, o.output_override), &sw->ref))
        rc = 1;
    lg_outputs_free(&own);
    free(dest);
    return rc;
}

/* Rank 0's reference (its pixels and ref_ms) on every rank, so that every rank judges its
 * runs against the same bits and writes the same ref_ms: a rank whose render differed (a
 * node that is not deterministic, another GL driver) cannot make the CSV differ from one
 * process's. Collective; after every rank has its reference. Returns 0 or 1. */
static int share_reference(sweep *sw)
{
    struct {
        uint32_t width, height;
        double ref_ms;
    } head = { sw->ref.width, sw->ref.height, sw->ref_ms };
    if (lg_dist_bcast(&head, sizeof head))
        return 1;
    sw->ref_ms = head.ref_ms;
    if (head.width != sw->ref.width || head.height != sw->ref.height) {
        lg_image_free(&sw->ref);
        if (lg_image_alloc(&sw->ref, head.width, head.height)) {
            fprintf(stderr, "lightgraph sweep: no memory for the reference (%ux%u)\n", head.width,
                    head.height);
            return 1;
        }
    }
    return lg_dist_bcast(sw->ref.pixels, (size_t)head.width * head.height * 4 * sizeof(float));
}

/* The CSV's header: run, the varied parameters, then the columns of add_row. */
static void csv_header(sweep *sw)
{
    lg_str_add(&sw->csv, "run");
    for (int i = 0; i < sw->a->n_vary; i++) {
        char *f = csv_field(sw->a->vary[i].key);
        lg_str_addf(&sw->csv, ",%s", f);
        free(f);
    }
    lg_str_add(&sw->csv, ",time_ms,time_min_ms,rmse,psnr_db,mean_abs,max_abs,rel_mse,nonfinite");
    lg_str_add(&sw->csv, ",rel_rmse,ssim,dssim,time_max_ms,ref_ms\n");
}

/* A CSV number, empty when it is not one (ssim without a window, ref_ms of REF_IMAGE). */
static void csv_number(lg_str *csv, const char *fmt, double v)
{
    lg_str_addc(csv, ',');
    if (!isnan(v))
        lg_str_addf(csv, fmt, v);
}

/* Why run k has no SSIM (its ssim is NaN), for the error of --metric dssim. */
static void no_ssim(const lg_image *img, const lg_metric_set *ms, char *why, size_t whylen)
{
    if (img->width < LG_SSIM_WINDOW || img->height < LG_SSIM_WINDOW)
        snprintf(why, whylen,
                 "--metric dssim: the image is %ux%u, smaller than SSIM's %dx%d window, so it "
                 "has no SSIM (choose another --metric)",
                 img->width, img->height, LG_SSIM_WINDOW, LG_SSIM_WINDOW);
    else
        snprintf(why, whylen,
                 "--metric dssim: every one of its %llu SSIM windows holds a pixel with NaN or "
                 "Inf, so it has no SSIM",
                 (unsigned long long)ms->ssim_skipped);
}

/* Compares run k's image with the reference, writes its heat map into `heat_path` of `outs`
 * and makes its CSV row and its line for stdout. `owned` are its NODE.PARAM=VALUE
 * overrides, times its --repeat timings (sorted here). Returns 0, or 1 with the reason in
 * why. */
static int judge_run(sweep *sw, int k, const lg_image *img, char *const *owned, const char *label,
                     double *times, lg_outputs *outs, const char *heat_path, lg_str *row,
                     lg_str *line, char *why, size_t whylen)
{
    const lg_sweep_args *a = sw->a;
    char err[512];
    lg_metric_set ms;
    const lg_image_metrics *m = &ms.base;
    lg_image heat = { 0 };
    int rc = 0;
    if (lg_metrics_compute(img, &sw->ref, &ms, &heat, 0, err, sizeof err)) {
        snprintf(why, whylen, "against the reference: %s", err);
        rc = 1;
    } else if (isnan(lg_metric_value(&ms, a->metric))) {
        no_ssim(img, &ms, why, whylen); /* dssim is the one metric that can be NaN */
        rc = 1;
    } else if (lg_outputs_write_image(outs, heat_path, &heat, NULL, err, sizeof err)) {
        snprintf(why, whylen, "%s", err);
        rc = 1;
    } else {
        qsort(times, a->repeat, sizeof *times, cmp_double);
        lg_str_addf(row, "%d", k);
        for (int i = 0; i < a->n_vary; i++) {
            char *f = csv_field(strchr(owned[i], '=') + 1);
            lg_str_addf(row, ",%s", f);
            free(f);
        }
        lg_str_addf(row, ",%.4f,%.4f,%.9g,%.4f,%.9g,%.9g,%.9g,%llu", times[a->repeat / 2], times[0],
                    m->rmse, m->psnr > 1e300 ? 999.0 : m->psnr, m->mean_abs, m->max_abs, m->rel_mse,
                    (unsigned long long)m->nonfinite);
        lg_str_addf(row, ",%.9g", ms.rel_rmse);
        csv_number(row, "%.9g", ms.ssim);
        csv_number(row, "%.9g", 1.0 - ms.ssim);
        lg_str_addf(row, ",%.4f", times[a->repeat - 1]);
        csv_number(row, "%.4f", sw->ref_ms);
        lg_str_addc(row, '\n');
        char ssim[32] = "n/a";
        if (!isnan(ms.ssim))
            snprintf(ssim, sizeof ssim, "%.4f", ms.ssim);
        lg_str_addf(line,
                    "%-40s time %9.3f ms  rmse %.4g  rel_rmse %.4g  ssim %s  max %.4g  psnr "
                    "%.2f dB\n",
                    label, times[a->repeat / 2], m->rmse, ms.rel_rmse, ssim, m->max_abs, m->psnr);
    }
    lg_image_free(&heat);
    return rc;
}

/* What a run sends to rank 0 (its item's bytes, lg_dist_map): this head, then as many
 * bytes of its image's file (the EXR the render wrote), of its heat map's (PNG), of its CSV
 * row and of its line on stdout. A run of rank 0's wrote its files into their temporaries
 * itself: exr and heat are 0. */
typedef struct run_sent {
    uint64_t exr, heat, row, line;
} run_sent;

/* Appends the bytes of the file at `path` to out; 0, or 1 with the reason in why. */
static int add_file(lg_str *out, const char *path, uint64_t *len, char *why, size_t whylen)
{
    char err[512];
    size_t n = 0;
    char *b = lg_read_file_limit(path, (size_t)1 << 31, &n, err, sizeof err);
    if (!b) {
        snprintf(why, whylen, "%s", err);
        return 1;
    }
    lg_str_addn(out, b, n);
    *len = n;
    free(b);
    return 0;
}

/* The NODE.PARAM=VALUE overrides of run k (owned[i], malloc'd) and its label. Run k is k in
 * the cartesian product of the --vary values, the last --vary varying fastest. */
static void run_values(const lg_sweep_args *a, int k, char **owned, lg_str *label)
{
    int idx = k;
    for (int i = a->n_vary - 1; i >= 0; i--) {
        int j = idx % a->vary[i].n;
        idx /= a->vary[i].n;
        owned[i] = vary_set(&a->vary[i], j);
    }
    for (int i = 0; i < a->n_vary; i++)
        lg_str_addf(label, "%s%s", i ? " " : "", owned[i]);
}

/* Run k, an lg_dist_map item (on whichever rank took it): --repeat renders with the --set
 * overrides and its combination, timed, then judged; its run_sent to out. Rank 0 renders
 * into its outputs' temporaries, the other ranks into temporaries of their own in their
 * scratch folder, read into out and removed. Returns 0, or 1 with the reason in err (the map
 * adds "sweep run K" and the rank) and the exit status in sw->item_rc. */
static int sweep_item(void *ctx, uint64_t item, lg_str *out, char *err, size_t err_size)
{
    sweep *sw = ctx;
    if (item < sw->batch_from)
        return 0; /* an earlier batch's */
    const lg_sweep_args *a = sw->a;
    int k = (int)item, n_vary = a->n_vary, rc = 0, nr = 0;
    for (int i = 0; i < a->n_sets; i++)
        sw->run_sets[nr++] = a->sets[i];
    char **owned = lg_xcalloc((size_t)n_vary, sizeof *owned);
    lg_str label = { 0 }, row = { 0 }, line = { 0 };
    run_values(a, k, owned, &label);
    for (int i = 0; i < n_vary; i++)
        sw->run_sets[nr++] = owned[i];
    fprintf(stderr, "sweep: run %d/%d: %s\n", k + 1, a->total, label.s);
    bool here = lg_dist_root();
    lg_outputs *own = here ? NULL : lg_outputs_new();
    lg_outputs *outs = here ? sw->outs : own;
    char *run = here ? sw->runs[k] : lg_xasprintf("%s/run-%03d.exr", sw->scratch, k);
    char *heat = here ? sw->heats[k] : lg_xasprintf("%s/heat-%03d.png", sw->scratch, k);
    char why[1024] = "";
    /* this run's temporaries, now that it starts (rank 0's checked before the reference) */
    if (lg_outputs_add(outs, run, LG_OUTPUT_IMAGE, why, sizeof why) ||
        lg_outputs_add(outs, heat, LG_OUTPUT_IMAGE, why, sizeof why))
        rc = 1;
    lg_exec_opts o = sw->opts;
    o.output_override = run;
    o.outputs = outs;
    bool found = true;
    last_error[0] = 0;
    lg_hlog_error_hook = keep_error;
    for (uint32_t r = 0; r < a->repeat && rc == 0; r++) {
        lg_run_result res;
        rc = lg_render_file(&sw->reg, a->graph, sw->run_sets, nr, &o, a->time_node, &res);
        sw->times[r] = a->time_node ? res.node_ms : res.total_ms;
        found &= !a->time_node || res.node_found;
    }
    lg_hlog_error_hook = NULL;
    if (rc && !why[0])
        snprintf(why, sizeof why, "the render failed: %s",
                 last_error[0] ? last_error : "see the messages above");
    if (rc == 0 && !found) {
        snprintf(why, sizeof why, "--time %s: no kept node of that name ran", a->time_node);
        rc = 2;
    }
    lg_image img = { 0 };
    if (rc == 0 && lg_image_read(lg_outputs_temp(outs, run), 0, &img, NULL, why, sizeof why))
        rc = 1;
    if (rc == 0)
        rc = judge_run(sw, k, &img, owned, label.s, sw->times, outs, heat, &row, &line, why,
                       sizeof why);
    /* one process: the run's line now, as it finishes (under mpirun rank 0 prints every
     * run's in run order when its batch is in) */
    if (rc == 0 && lg_dist_size() == 1) {
        fwrite(line.s, 1, line.len, stdout);
        fflush(stdout);
        line.len = 0;
    }
    run_sent sent = { .row = row.len, .line = line.len };
    size_t at = out->len;
    lg_str_addn(out, (const char *)&sent, sizeof sent);
    if (rc == 0 && !here)
        rc = add_file(out, lg_outputs_temp(outs, run), &sent.exr, why, sizeof why) ||
             add_file(out, lg_outputs_temp(outs, heat), &sent.heat, why, sizeof why);
    if (rc == 0) {
        memcpy(out->s + at, &sent, sizeof sent);
        lg_str_addn(out, row.s, row.len);
        lg_str_addn(out, line.s, line.len);
    } else {
        sw->item_rc = rc;
        snprintf(err, err_size, "%s", why);
    }
    lg_image_free(&img);
    lg_outputs_free(&own); /* a rank's own temporaries: read, never committed */
    if (!here) {
        free(run);
        free(heat);
    }
    lg_str_free(&label);
    lg_str_free(&row);
    lg_str_free(&line);
    for (int i = 0; i < n_vary; i++)
        free(owned[i]);
    free(owned);
    return rc;
}

/* Rank 0: runs [from, to) of a map's result into its outputs (the files of the runs other
 * ranks made, into their temporaries), the CSV and stdout, in run order. Returns 0, or 1
 * (printed). */
static int take_runs(sweep *sw, const lg_dist_result *res, uint64_t from, uint64_t to)
{
    char err[1024];
    for (uint64_t k = from; k < to; k++) {
        const char *p = res->data + res->off[k];
        run_sent sent;
        if (res->off[k + 1] - res->off[k] < sizeof sent) {
            fprintf(stderr, "lightgraph sweep: run %llu: its result is missing\n",
                    (unsigned long long)k);
            return 1;
        }
        memcpy(&sent, p, sizeof sent);
        p += sizeof sent;
        if (sent.exr &&
            (lg_outputs_add(sw->outs, sw->runs[k], LG_OUTPUT_IMAGE, err, sizeof err) ||
             lg_outputs_write_data(sw->outs, sw->runs[k], p, sent.exr, err, sizeof err) ||
             lg_outputs_add(sw->outs, sw->heats[k], LG_OUTPUT_IMAGE, err, sizeof err) ||
             lg_outputs_write_data(sw->outs, sw->heats[k], p + sent.exr, sent.heat, err,
                                   sizeof err))) {
            fprintf(stderr, "lightgraph sweep: run %llu: %s\n", (unsigned long long)k, err);
            return 1;
        }
        p += sent.exr + sent.heat;
        lg_str_addn(&sw->csv, p, sent.row);
        fwrite(p + sent.row, 1, sent.line, stdout);
    }
    fflush(stdout);
    return 0;
}

/* Runs per lg_dist_map call: all of them in one process (rank 0 writes its runs' files
 * itself), else as many as keep the images gathered on rank 0 at once under 1 GiB (an EXR
 * in float RGBA and a heat map at their raw sizes, ZIP and PNG being less): rank 0 holds a
 * batch's results until it has written them, and one gather moves at most 2 GiB. */
static uint64_t sweep_batch(const sweep *sw)
{
    uint64_t total = (uint64_t)sw->a->total;
    if (lg_dist_size() == 1)
        return total;
    double px = (double)sw->opts.width * sw->opts.height;
    double per_run = px * 20 + 16384;
    double n = floor(1073741824.0 / per_run);
    return n < 1 ? 1 : n >= (double)total ? total : (uint64_t)n;
}

/* Every run, spread over the ranks in batches (sweep_batch), rank 0 writing each batch's
 * results as they come; stops at the first run that fails, with its reason printed on rank
 * 0. Collective. Returns the exit status. */
static int sweep_runs(sweep *sw)
{
    const lg_sweep_args *a = sw->a;
    sw->run_sets = lg_xcalloc((size_t)(a->n_sets + a->n_vary) + 1, sizeof *sw->run_sets);
    sw->times = lg_xcalloc(a->repeat, sizeof *sw->times);
    uint64_t total = (uint64_t)a->total, batch = sweep_batch(sw);
    int rc = 0;
    for (uint64_t from = 0; from < total && rc == 0; from += batch) {
        uint64_t to = total - from > batch ? from + batch : total;
        lg_dist_result res;
        sw->batch_from = from;
        sw->item_rc = 0;
        /* items [0, from) are earlier batches' (sweep_item returns them empty), so that an
         * item's number is its run's, in the failing run's message too */
        if (lg_dist_map("sweep run", to, 1, true, sweep_item, sw, &res)) {
            rc = sw->item_rc ? sw->item_rc : 1;
            break;
        }
        if (lg_dist_root())
            rc = take_runs(sw, &res, from, to);
        lg_dist_result_free(&res);
        if (to < total)
            rc = lg_dist_agree(rc, NULL); /* rank 0 could not write: every rank stops */
    }
    free(sw->run_sets);
    free(sw->times);
    sw->run_sets = NULL;
    sw->times = NULL;
    return rc;
}

/* Writes the CSV and the script, plots (when gnuplot is there) and commits the sweep's
 * files, all or nothing. Returns 0, or 1 (printed); *plotted says whether the plot was
 * made. */
static int sweep_finish(sweep *sw, bool *plotted)
{
    char err[1024];
    *plotted = false;
    if (lg_outputs_write_data(sw->outs, sw->csv_path, sw->csv.s, sw->csv.len, err, sizeof err) ||
        write_gnuplot(sw->outs, sw->gp_path, sw->a->vary, sw->a->n_vary, sw->a->metric, err,
                      sizeof err)) {
        fprintf(stderr, "lightgraph sweep: %s\n", err);
        return 1;
    }
    /* the plot is the one optional output: without gnuplot the rest is still written */
    *plotted = lg_run_gnuplot(sw->a->dir, lg_outputs_temp(sw->outs, sw->gp_path),
                              lg_outputs_temp(sw->outs, sw->csv_path),
                              lg_outputs_temp(sw->outs, sw->png_path)) == 0;
    if (!*plotted)
        lg_outputs_drop(sw->outs, sw->png_path);
    /* all or nothing: the reference, the runs, the heat maps, the CSV and the plot */
    if (lg_outputs_commit(sw->outs, err, sizeof err)) {
        fprintf(stderr, "lightgraph sweep: %s\n", err);
        return 1;
    }
    return 0;
}

static void sweep_free(sweep *sw)
{
    lg_outputs_free(&sw->outs);
    for (int k = 0; sw->runs && k < sw->a->total; k++) {
        free(sw->runs[k]);
        free(sw->heats[k]);
    }
    free(sw->runs);
    free(sw->heats);
    free(sw->ref_out);
    free(sw->csv_path);
    free(sw->gp_path);
    free(sw->png_path);
    lg_str_free(&sw->csv);
    lg_image_free(&sw->ref);
    lg_registry_free(&sw->reg);
}

int lg_cmd_sweep(int argc, char **argv)
{
    lg_sweep_args args;
    char err[1024];
    int rc = lg_sweep_parse_args(argc, argv, &args, err, sizeof err);
    if (rc) {
        usage(err);
        lg_sweep_args_free(&args);
        return rc;
    }
    if (args.size_given && lg_size_over_limit("sweep", args.width, args.height)) {
        lg_sweep_args_free(&args);
        return 2;
    }
    if (args.quiet)
        lg_verbosity = -1;
    sweep sw;
    memset(&sw, 0, sizeof sw);
    sw.a = &args;
    sw.opts = lg_measure_opts(args.width, args.height, args.frames, args.gl_backend);
    sw.ref_image = args.reference && lg_image_format_from_path(args.reference) != LG_FILE_UNKNOWN;
    lg_registry_scan(&sw.reg);

    /* Everything is checked before the first run: every --vary value, the reference graph,
     * and every file the sweep writes; a refusal there has written nothing to say. */
    /* Under mpirun every rank checks (a rank's files are its own) and agrees; rank 0 alone
     * checks DIR and reserves the outputs; a rank other than 0 renders into its TMPDIR. */
    const char *tmp = getenv("TMPDIR");
    sw.scratch = tmp && tmp[0] ? tmp : "/tmp";
    rc = lg_dist_agree(check_values(&sw), NULL);
    if (rc == 0)
        rc = lg_dist_agree(lg_dist_root() ? reserve_outputs(&sw) : 0, NULL);
    if (rc == 0)
        rc = lg_dist_agree(render_reference(&sw), NULL);
    if (rc == 0 && share_reference(&sw))
        rc = 1;
    if (rc == 0) {
        csv_header(&sw);
        bool plotted = false;
        rc = sweep_runs(&sw);
        if (rc == 0 && lg_dist_root())
            rc = sweep_finish(&sw, &plotted);
        if (rc == 0)
            printf("wrote %s, %s/reference.exr, %s/run-*.exr, heat maps %s/heat-*.png, %s%s\n",
                   sw.csv_path, args.dir, args.dir, args.dir, sw.gp_path,
                   plotted ? " and sweep.png" : " (gnuplot not run: install gnuplot-nox)");
        else
            fprintf(stderr, "lightgraph sweep: nothing was written to %s\n", args.dir);
    }
    sweep_free(&sw);
    lg_sweep_args_free(&args);
    return rc;
}
