/* lightgraph sweep: what accuracy costs. Renders a graph across parameter values, compares
 * every output with a reference, times the node of interest, and writes a CSV, heat maps
 * and a gnuplot plot of error against time.
 *
 *   lightgraph sweep GRAPH --vary NODE.PARAM=v1,v2,... [--vary ...]
 *                    [--reference REF_GRAPH] [--ref-set NODE.PARAM=V]...
 *                    [--set NODE.PARAM=V]... [--time NODE] [--repeat N] [--frames N]
 *                    [--size WxH] [--gl osmesa|egl] [-o DIR]
 *
 * The reference is REF_GRAPH if given, else GRAPH itself with the --set and --ref-set
 * overrides (e.g. the finest tessellation and per-pixel shading). Every run gets the --set
 * overrides, then one combination of the --vary values (their cartesian product). Times
 * are the median over --repeat runs of the --time node's CPU wall time (which includes its
 * GL work, see docs/devices.md), or of all kept nodes when --time is not given. With
 * --frames N (default 1) every run renders N frames (the outputs are the last frame's, so
 * that state carried across frames, a temporal filter's, shows in the error) and a node that
 * ran on several frames is timed per frame in steady state: the mean of its runs after the
 * first (which pays for shader compilation and first uploads).
 *
 * All or nothing (outputs.h): every --vary value is checked against its parameter's type and
 * range, the reference graph is checked, and every file the sweep writes (reference, runs,
 * heat maps, CSV, script, plot) is checked before the first run, as is the free space of
 * DIR's file system against what the outputs need (sweep_bytes); the reference, CSV, script
 * and plot get their temporaries in DIR (default out/sweep, which must exist) then, each
 * run's image and heat map when the run starts; the files are committed together at the
 * end, or none. */
#include "cli/commands.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lightgraph/image.h"
#include "exec/outputs.h"
#include "cli/sweep_args.h"

typedef lg_sweep_vary vary;

/* The reason (sweep_args.c), then the usage. */
static int usage(const char *msg)
{
    fprintf(stderr, "lightgraph sweep: %s\n", msg);
    fprintf(stderr,
            "usage: lightgraph sweep GRAPH --vary NODE.PARAM=v1,v2,... [--vary ...]\n"
            "                        [--reference REF_GRAPH] [--ref-set NODE.PARAM=V]...\n"
            "                        [--set NODE.PARAM=V]... [--time NODE] [--repeat N]\n"
            "                        [--frames N] [--size WxH] [--gl osmesa|egl] [-o DIR]\n"
            "DIR (default out/sweep) must exist; nothing is written unless every run succeeds\n");
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
    lg_str b = {0};
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
static int write_gnuplot(lg_outputs *outs, const char *gp, const vary *v, int n_vary, char *err,
                         size_t errlen)
{
    lg_str s = {0};
    lg_str_add(&s, "# gnuplot script written by lightgraph sweep: error against time\n");
    lg_str_add(&s, "if (!exists('data')) data = 'sweep.csv'\n");
    lg_str_add(&s, "if (!exists('out')) out = 'sweep.png'\n");
    lg_str_add(&s, "set terminal pngcairo size 900,600 noenhanced\n");
    lg_str_add(&s, "set output out\nset datafile separator ','\n");
    lg_str_add(&s, "set key off\nset grid\nset logscale y\n");
    lg_str_add(&s, "set xlabel 'time (ms, median)'\nset ylabel 'RMSE against the reference'\n");
    lg_str_add(&s, "set title 'what accuracy costs: ");
    for (int i = 0; i < n_vary; i++)
        lg_str_addf(&s, "%s%s", i ? ", " : "", v[i].key);
    lg_str_add(&s, "'\n");
    /* columns: run, varied params..., time_ms, time_min_ms, rmse, ... */
    int tcol = 2 + n_vary, ecol = tcol + 2;
    lg_str_addf(&s,
                "plot data every ::1 using %d:($%d > 0 ? $%d : 1e-12) with points pt 7 "
                "ps 1.5, \\\n     '' every ::1 using %d:($%d > 0 ? $%d : 1e-12):(",
                tcol, ecol, ecol, tcol, ecol, ecol);
    for (int i = 0; i < n_vary; i++)
        lg_str_addf(&s, "%sstrcol(%d)", i ? ".' '." : "", 2 + i);
    lg_str_add(&s, ") with labels offset 1,1 left\n");
    int rc = lg_outputs_write_data(outs, gp, s.s, s.len, err, errlen);
    lg_str_free(&s);
    return rc;
}

static const char *base_name(const char *p)
{
    const char *slash = strrchr(p, '/');
    return slash ? slash + 1 : p;
}

/* Runs gnuplot inside `dir` on the script's temporary, reading the CSV's and writing the
 * plot's (all three sit in `dir`, named without quotes or slashes); 0 when the plot was
 * made. */
static int run_gnuplot(const char *dir, const char *gp, const char *csv, const char *png)
{
    char *vars = lg_xasprintf("data='%s'; out='%s'", base_name(csv), base_name(png));
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        free(vars);
        return -1;
    }
    if (pid == 0) {
        if (chdir(dir) != 0)
            _exit(127);
        execlp("gnuplot", "gnuplot", "-e", vars, base_name(gp), (char *)NULL);
        _exit(127);
    }
    free(vars);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
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
    double csv = 256.0 + (double)total * (96.0 + 32.0 * n_vary);
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
            lg_hlog(LG_HWARN, "sweep: cannot tell the free space in '%s' (%s); not checked",
                    dir, strerror(errno));
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
    const char *graph = args.graph, *reference = args.reference, *time_node = args.time_node;
    const char *dir = args.dir;
    const char **sets = args.sets, **ref_sets = args.ref_sets;
    int n_sets = args.n_sets, n_ref_sets = args.n_ref_sets, n_vary = args.n_vary;
    const vary *v = args.vary;
    uint32_t repeat = args.repeat;
    int total = args.total;
    lg_exec_opts opts;
    memset(&opts, 0, sizeof opts);
    opts.width = args.width;
    opts.height = args.height;
    opts.frames = args.frames;
    opts.dt = 1.0 / 60.0;
    opts.gl_backend = args.gl_backend;

    lg_registry reg = {0};
    lg_outputs *outs = NULL;
    lg_image ref = {0};
    lg_str csv = {0};
    char **runs = NULL, **heats = NULL;
    char *ref_out = NULL, *csv_path = NULL, *gp_path = NULL, *png_path = NULL;
    lg_registry_scan(&reg);

    /* Everything is checked before the first run: every --vary value against the
     * parameter's type and range (the graph with --set and that value, checked as `check`
     * does), the reference graph, and every file the sweep writes. */
    const char **rs = lg_xcalloc((size_t)(n_sets + n_ref_sets) + 2, sizeof *rs);
    {
        int nrs = 0;
        if (!reference)
            for (int i = 0; i < n_sets; i++)
                rs[nrs++] = sets[i];
        for (int i = 0; i < n_ref_sets; i++)
            rs[nrs++] = ref_sets[i];
        if (lg_check_file(&reg, reference ? reference : graph, rs, nrs)) {
            fprintf(stderr, "lightgraph sweep: the reference %s is refused (above); nothing "
                            "was run\n", reference ? reference : graph);
            rc = 2;
        }
        for (int i = 0; i < n_vary && rc == 0; i++)
            for (int j = 0; j < v[i].n && rc == 0; j++) {
                for (int k = 0; k < n_sets; k++)
                    rs[k] = sets[k];
                char *kv = lg_xasprintf("%s=%s", v[i].key, v[i].values[j]);
                rs[n_sets] = kv;
                if (lg_check_file(&reg, graph, rs, n_sets + 1)) {
                    fprintf(stderr,
                            "lightgraph sweep: --vary %s: the value '%s' is refused (above); "
                            "nothing was run\n",
                            v[i].key, v[i].values[j]);
                    rc = 2;
                }
                free(kv);
            }
        free(rs);
        if (rc)
            goto done;
    }
    outs = lg_outputs_new();
    ref_out = lg_xasprintf("%s/reference.exr", dir);
    csv_path = lg_xasprintf("%s/sweep.csv", dir);
    gp_path = lg_xasprintf("%s/sweep.gp", dir);
    png_path = lg_xasprintf("%s/sweep.png", dir);
    runs = lg_xcalloc((size_t)total, sizeof *runs);
    heats = lg_xcalloc((size_t)total, sizeof *heats);
    /* the runs' images and heat maps are checked now and get their temporaries when their
     * run starts (a sweep that stops early has made only what it reached); the reference,
     * the CSV, the script and the plot get theirs now, which also proves DIR writable */
    rc = lg_outputs_add(outs, ref_out, LG_OUTPUT_IMAGE, err, sizeof err);
    for (int k = 0; k < total && rc == 0; k++) {
        runs[k] = lg_xasprintf("%s/run-%03d.exr", dir, k);
        heats[k] = lg_xasprintf("%s/heat-%03d.png", dir, k);
        rc = lg_outputs_check(runs[k], LG_OUTPUT_IMAGE, err, sizeof err);
        if (rc == 0)
            rc = lg_outputs_check(heats[k], LG_OUTPUT_IMAGE, err, sizeof err);
    }
    if (rc == 0)
        rc = lg_outputs_add(outs, csv_path, LG_OUTPUT_FILE, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_add(outs, gp_path, LG_OUTPUT_FILE, err, sizeof err);
    if (rc == 0)
        rc = lg_outputs_add(outs, png_path, LG_OUTPUT_IMAGE, err, sizeof err);
    if (rc) {
        fprintf(stderr, "lightgraph sweep: %s; nothing was run\n", err);
        rc = 1;
        goto done;
    }
    if (check_space(dir, total, n_vary, &opts)) {
        rc = 1;
        goto done;
    }

    /* the reference; each image goes to its output's temporary, read back from there */
    {
        const char **rsets = lg_xcalloc((size_t)(n_sets + n_ref_sets) + 1, sizeof *rsets);
        int nrs = 0;
        if (!reference) {
            for (int i = 0; i < n_sets; i++)
                rsets[nrs++] = sets[i];
        }
        for (int i = 0; i < n_ref_sets; i++)
            rsets[nrs++] = ref_sets[i];
        lg_exec_opts o = opts;
        o.output_override = ref_out;
        o.outputs = outs;
        lg_run_result res;
        fprintf(stderr, "sweep: reference (%s)\n", reference ? reference : graph);
        rc = lg_render_file(&reg, reference ? reference : graph, rsets, nrs, &o, NULL, &res);
        free(rsets);
    }
    if (rc == 0 && read_image(lg_outputs_temp(outs, ref_out), &ref))
        rc = 1;
    if (rc)
        goto done;

    lg_str_add(&csv, "run");
    for (int i = 0; i < n_vary; i++) {
        char *f = csv_field(v[i].key);
        lg_str_addf(&csv, ",%s", f);
        free(f);
    }
    lg_str_add(&csv, ",time_ms,time_min_ms,rmse,psnr_db,mean_abs,max_abs,rel_mse,nonfinite\n");

    const char **run_sets = lg_xcalloc((size_t)(n_sets + n_vary) + 1, sizeof *run_sets);
    double *times = lg_xcalloc(repeat, sizeof *times);
    for (int k = 0; k < total && rc == 0; k++) {
        int nr = 0;
        for (int i = 0; i < n_sets; i++)
            run_sets[nr++] = sets[i];
        char **owned = lg_xcalloc((size_t)n_vary, sizeof *owned);
        int idx = k;
        lg_str label = {0};
        for (int i = n_vary - 1; i >= 0; i--) {
            int j = idx % v[i].n;
            idx /= v[i].n;
            owned[i] = lg_xasprintf("%s=%s", v[i].key, v[i].values[j]);
        }
        for (int i = 0; i < n_vary; i++) {
            run_sets[nr++] = owned[i];
            lg_str_addf(&label, "%s%s", i ? " " : "", owned[i]);
        }
        lg_exec_opts o = opts;
        o.output_override = runs[k];
        o.outputs = outs;
        fprintf(stderr, "sweep: run %d/%d: %s\n", k + 1, total, label.s);
        /* this run's temporaries, now that it starts (checked before the reference) */
        if (lg_outputs_add(outs, runs[k], LG_OUTPUT_IMAGE, err, sizeof err) ||
            lg_outputs_add(outs, heats[k], LG_OUTPUT_IMAGE, err, sizeof err)) {
            fprintf(stderr, "lightgraph sweep: run %d: %s\n", k, err);
            rc = 1;
        }
        bool found = true;
        for (uint32_t r = 0; r < repeat && rc == 0; r++) {
            lg_run_result res;
            rc = lg_render_file(&reg, graph, run_sets, nr, &o, time_node, &res);
            times[r] = time_node ? res.node_ms : res.total_ms;
            found &= !time_node || res.node_found;
        }
        if (rc == 0 && !found) {
            fprintf(stderr, "lightgraph sweep: --time %s: no kept node of that name ran\n",
                    time_node);
            rc = 2;
        }
        lg_image img = {0};
        if (rc == 0 && read_image(lg_outputs_temp(outs, runs[k]), &img))
            rc = 1;
        if (rc == 0) {
            lg_image_metrics m;
            lg_image heat = {0};
            if (lg_image_compare(&img, &ref, &m, &heat, 0, err, sizeof err)) {
                fprintf(stderr, "lightgraph sweep: run %d against the reference: %s\n", k, err);
                rc = 1;
            } else if (lg_outputs_write_image(outs, heats[k], &heat, NULL, err, sizeof err)) {
                fprintf(stderr, "lightgraph sweep: %s\n", err);
                rc = 1;
            } else {
                qsort(times, repeat, sizeof *times, cmp_double);
                lg_str_addf(&csv, "%d", k);
                for (int i = 0; i < n_vary; i++) {
                    char *f = csv_field(strchr(owned[i], '=') + 1);
                    lg_str_addf(&csv, ",%s", f);
                    free(f);
                }
                lg_str_addf(&csv, ",%.4f,%.4f,%.9g,%.4f,%.9g,%.9g,%.9g,%llu\n",
                            times[repeat / 2], times[0], m.rmse, m.psnr > 1e300 ? 999.0 : m.psnr,
                            m.mean_abs, m.max_abs, m.rel_mse, (unsigned long long)m.nonfinite);
                printf("%-40s time %9.3f ms  rmse %.4g  max %.4g  psnr %.2f dB\n", label.s,
                       times[repeat / 2], m.rmse, m.max_abs, m.psnr);
                fflush(stdout);
            }
            lg_image_free(&heat);
        }
        lg_image_free(&img);
        lg_str_free(&label);
        for (int i = 0; i < n_vary; i++)
            free(owned[i]);
        free(owned);
    }
    free(run_sets);
    free(times);
    bool plotted = false;
    if (rc == 0 && (lg_outputs_write_data(outs, csv_path, csv.s, csv.len, err, sizeof err) ||
                    write_gnuplot(outs, gp_path, v, n_vary, err, sizeof err))) {
        fprintf(stderr, "lightgraph sweep: %s\n", err);
        rc = 1;
    }
    if (rc == 0) {
        /* the plot is the one optional output: without gnuplot the rest is still written */
        plotted = run_gnuplot(dir, lg_outputs_temp(outs, gp_path), lg_outputs_temp(outs, csv_path),
                              lg_outputs_temp(outs, png_path)) == 0;
        if (!plotted)
            lg_outputs_drop(outs, png_path);
    }
    /* all or nothing: the reference, the runs, the heat maps, the CSV and the plot */
    if (rc == 0 && lg_outputs_commit(outs, err, sizeof err)) {
        fprintf(stderr, "lightgraph sweep: %s\n", err);
        rc = 1;
    }
    if (rc == 0)
        printf("wrote %s, %s/reference.exr, %s/run-*.exr, heat maps %s/heat-*.png, %s%s\n",
               csv_path, dir, dir, dir, gp_path,
               plotted ? " and sweep.png" : " (gnuplot not run: install gnuplot-nox)");
    else
        fprintf(stderr, "lightgraph sweep: nothing was written to %s\n", dir);
done:
    lg_outputs_free(&outs);
    for (int k = 0; runs && k < total; k++) {
        free(runs[k]);
        free(heats[k]);
    }
    free(runs);
    free(heats);
    free(ref_out);
    free(csv_path);
    free(gp_path);
    free(png_path);
    lg_str_free(&csv);
    lg_image_free(&ref);
    lg_registry_free(&reg);
    lg_sweep_args_free(&args);
    return rc;
}
