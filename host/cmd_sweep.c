/* lightgraph sweep: what accuracy costs. Renders a graph across parameter values, compares
 * every output with a reference, times the node of interest, and writes a CSV, heat maps
 * and a gnuplot plot of error against time.
 *
 *   lightgraph sweep GRAPH --vary NODE.PARAM=v1,v2,... [--vary ...]
 *                    [--reference REF_GRAPH] [--ref-set NODE.PARAM=V]...
 *                    [--set NODE.PARAM=V]... [--time NODE] [--repeat N] [--size WxH]
 *                    [--gl osmesa|egl] [-o DIR]
 *
 * The reference is REF_GRAPH if given, else GRAPH itself with the --set and --ref-set
 * overrides (e.g. the finest tessellation and per-pixel shading). Every run gets the --set
 * overrides, then one combination of the --vary values (their cartesian product). Times
 * are the median over --repeat runs of the --time node's CPU wall time (which includes its
 * GL work, see docs/devices.md), or of all kept nodes when --time is not given. */
#include "host.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lightgraph/image.h"

#define MAX_VARY 8

typedef struct vary {
    char *key;       /* NODE.PARAM */
    char **values;
    int n;
} vary;

static int usage(const char *msg, const char *what)
{
    if (msg)
        fprintf(stderr, msg, what);
    fprintf(stderr,
            "usage: lightgraph sweep GRAPH --vary NODE.PARAM=v1,v2,... [--vary ...]\n"
            "                        [--reference REF_GRAPH] [--ref-set NODE.PARAM=V]...\n"
            "                        [--set NODE.PARAM=V]... [--time NODE] [--repeat N]\n"
            "                        [--size WxH] [--gl osmesa|egl] [-o DIR]\n");
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

static void write_gnuplot(const char *dir, const vary *v, int n_vary)
{
    char *gp = lg_xasprintf("%s/sweep.gp", dir);
    lg_str s = {0};
    lg_str_add(&s, "# gnuplot script written by lightgraph sweep: error against time\n");
    lg_str_add(&s, "set terminal pngcairo size 900,600 noenhanced\n");
    lg_str_add(&s, "set output 'sweep.png'\nset datafile separator ','\n");
    lg_str_add(&s, "set key off\nset grid\nset logscale y\n");
    lg_str_add(&s, "set xlabel 'time (ms, median)'\nset ylabel 'RMSE against the reference'\n");
    lg_str_add(&s, "set title 'what accuracy costs: ");
    for (int i = 0; i < n_vary; i++)
        lg_str_addf(&s, "%s%s", i ? ", " : "", v[i].key);
    lg_str_add(&s, "'\n");
    /* columns: run, varied params..., time_ms, time_min_ms, rmse, ... */
    int tcol = 2 + n_vary, ecol = tcol + 2;
    lg_str_addf(&s,
                "plot 'sweep.csv' every ::1 using %d:($%d > 0 ? $%d : 1e-12) with points pt 7 "
                "ps 1.5, \\\n     '' every ::1 using %d:($%d > 0 ? $%d : 1e-12):(",
                tcol, ecol, ecol, tcol, ecol, ecol);
    for (int i = 0; i < n_vary; i++)
        lg_str_addf(&s, "%sstrcol(%d)", i ? ".' '." : "", 2 + i);
    lg_str_add(&s, ") with labels offset 1,1 left\n");
    if (lg_write_file_atomic(gp, s.s, s.len) != 0)
        fprintf(stderr, "lightgraph sweep: cannot write %s: %s\n", gp, strerror(errno));
    lg_str_free(&s);
    free(gp);
}

/* Runs gnuplot on sweep.gp inside `dir`; 0 when the plot was made. */
static int run_gnuplot(const char *dir)
{
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        if (chdir(dir) != 0)
            _exit(127);
        execlp("gnuplot", "gnuplot", "sweep.gp", (char *)NULL);
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 0 : -1;
}

int lg_cmd_sweep(int argc, char **argv)
{
    const char *graph = NULL, *reference = NULL, *time_node = NULL, *dir = "out/sweep";
    const char **sets = lg_xcalloc((size_t)argc + 1, sizeof *sets);
    const char **ref_sets = lg_xcalloc((size_t)argc + 1, sizeof *ref_sets);
    int n_sets = 0, n_ref_sets = 0, n_vary = 0;
    vary v[MAX_VARY];
    memset(v, 0, sizeof v);
    uint32_t repeat = 3;
    lg_exec_opts opts;
    memset(&opts, 0, sizeof opts);
    opts.width = 640;
    opts.height = 360;
    opts.frames = 1;
    opts.dt = 1.0 / 60.0;
    opts.gl_backend = "osmesa";
    int rc = 0;
    for (int i = 1; i < argc && rc == 0; i++) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        bool takes = strcmp(a, "--vary") == 0 || strcmp(a, "--reference") == 0 ||
                     strcmp(a, "--ref-set") == 0 || strcmp(a, "--set") == 0 ||
                     strcmp(a, "--time") == 0 || strcmp(a, "--repeat") == 0 ||
                     strcmp(a, "--size") == 0 || strcmp(a, "-o") == 0 || strcmp(a, "--gl") == 0;
        if (takes && !val) {
            rc = usage("lightgraph sweep: %s needs a value\n", a);
            break;
        }
        if (takes)
            i++;
        if (strcmp(a, "--vary") == 0) {
            const char *eq = strchr(val, '=');
            if (!eq || eq == val || !eq[1] || n_vary == MAX_VARY) {
                rc = usage("lightgraph sweep: --vary wants NODE.PARAM=v1,v2,... (at most 8), "
                           "got '%s'\n",
                           val);
                break;
            }
            v[n_vary].key = lg_xstrndup(val, (size_t)(eq - val));
            char *list = lg_xstrdup(eq + 1);
            for (char *save = NULL, *t = strtok_r(list, ",", &save); t;
                 t = strtok_r(NULL, ",", &save)) {
                v[n_vary].values =
                    lg_xrealloc(v[n_vary].values, (size_t)(v[n_vary].n + 1) * sizeof(char *));
                v[n_vary].values[v[n_vary].n++] = lg_xstrdup(t);
            }
            free(list);
            n_vary++;
        } else if (strcmp(a, "--reference") == 0) {
            reference = val;
        } else if (strcmp(a, "--ref-set") == 0) {
            ref_sets[n_ref_sets++] = val;
        } else if (strcmp(a, "--set") == 0) {
            sets[n_sets++] = val;
        } else if (strcmp(a, "--time") == 0) {
            time_node = val;
        } else if (strcmp(a, "--repeat") == 0) {
            char *end;
            long r = strtol(val, &end, 10);
            if (*end || r < 1 || r > 1000)
                rc = usage("lightgraph sweep: --repeat wants 1..1000, got '%s'\n", val);
            repeat = (uint32_t)r;
        } else if (strcmp(a, "--size") == 0) {
            unsigned w = 0, h = 0;
            char tail;
            if (sscanf(val, "%ux%u%c", &w, &h, &tail) != 2 || !w || !h || w > 16384 || h > 16384)
                rc = usage("lightgraph sweep: --size wants WxH, got '%s'\n", val);
            opts.width = w;
            opts.height = h;
        } else if (strcmp(a, "--gl") == 0) {
            if (strcmp(val, "osmesa") && strcmp(val, "egl"))
                rc = usage("lightgraph sweep: --gl wants osmesa or egl, got '%s'\n", val);
            opts.gl_backend = val;
        } else if (strcmp(a, "-o") == 0) {
            dir = val;
        } else if (strcmp(a, "-q") == 0) {
            lg_verbosity = -1;
        } else if (a[0] == '-') {
            rc = usage("lightgraph sweep: unknown option '%s'\n", a);
        } else if (!graph) {
            graph = a;
        } else {
            rc = usage("lightgraph sweep: unexpected argument '%s'\n", a);
        }
    }
    if (rc == 0 && !graph)
        rc = usage("lightgraph sweep: no graph given%s\n", "");
    if (rc == 0 && n_vary == 0)
        rc = usage("lightgraph sweep: nothing to vary (give --vary NODE.PARAM=v1,v2,...)%s\n", "");

    lg_registry reg = {0};
    char *csv_path = NULL;
    lg_image ref = {0};
    lg_str csv = {0};
    if (rc)
        goto done;
    {
        char *mk = lg_xasprintf("%s/.", dir);
        char *d = lg_path_dirname(mk);
        /* mkdir -p */
        for (char *p = d + 1;; p++) {
            if (*p == '/' || !*p) {
                char c = *p;
                *p = 0;
                if (mkdir(d, 0777) != 0 && errno != EEXIST) {
                    fprintf(stderr, "lightgraph sweep: cannot create %s: %s\n", d,
                            strerror(errno));
                    rc = 1;
                }
                *p = c;
                if (!c || rc)
                    break;
            }
        }
        free(d);
        free(mk);
        if (rc)
            goto done;
    }
    lg_registry_scan(&reg);

    /* the reference */
    char *ref_out = lg_xasprintf("%s/reference.exr", dir);
    {
        const char **rs = lg_xcalloc((size_t)(n_sets + n_ref_sets) + 1, sizeof *rs);
        int nrs = 0;
        if (!reference) {
            for (int i = 0; i < n_sets; i++)
                rs[nrs++] = sets[i];
        }
        for (int i = 0; i < n_ref_sets; i++)
            rs[nrs++] = ref_sets[i];
        lg_exec_opts o = opts;
        o.output_override = ref_out;
        lg_run_result res;
        fprintf(stderr, "sweep: reference (%s)\n", reference ? reference : graph);
        rc = lg_render_file(&reg, reference ? reference : graph, rs, nrs, &o, NULL, &res);
        free(rs);
    }
    if (rc == 0 && read_image(ref_out, &ref))
        rc = 1;
    free(ref_out);
    if (rc)
        goto done;

    lg_str_add(&csv, "run");
    for (int i = 0; i < n_vary; i++) {
        char *f = csv_field(v[i].key);
        lg_str_addf(&csv, ",%s", f);
        free(f);
    }
    lg_str_add(&csv, ",time_ms,time_min_ms,rmse,psnr_db,mean_abs,max_abs,rel_mse,nonfinite\n");

    int total = 1;
    for (int i = 0; i < n_vary; i++)
        total *= v[i].n;
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
        char *out = lg_xasprintf("%s/run-%03d.exr", dir, k);
        lg_exec_opts o = opts;
        o.output_override = out;
        fprintf(stderr, "sweep: run %d/%d: %s\n", k + 1, total, label.s);
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
        if (rc == 0 && read_image(out, &img))
            rc = 1;
        if (rc == 0) {
            lg_image_metrics m;
            lg_image heat = {0};
            char err[512];
            if (lg_image_compare(&img, &ref, &m, &heat, 0, err, sizeof err)) {
                fprintf(stderr, "lightgraph sweep: run %d against the reference: %s\n", k, err);
                rc = 1;
            } else {
                char *hp = lg_xasprintf("%s/heat-%03d.png", dir, k);
                if (lg_image_write(hp, &heat, NULL, err, sizeof err))
                    fprintf(stderr, "lightgraph sweep: %s\n", err);
                free(hp);
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
        free(out);
        lg_str_free(&label);
        for (int i = 0; i < n_vary; i++)
            free(owned[i]);
        free(owned);
    }
    free(run_sets);
    free(times);
    if (rc == 0) {
        csv_path = lg_xasprintf("%s/sweep.csv", dir);
        if (lg_write_file_atomic(csv_path, csv.s, csv.len) != 0) {
            fprintf(stderr, "lightgraph sweep: cannot write %s: %s\n", csv_path, strerror(errno));
            rc = 1;
        } else {
            write_gnuplot(dir, v, n_vary);
            bool plotted = run_gnuplot(dir) == 0;
            printf("wrote %s, %s/sweep.gp%s, heat maps %s/heat-*.png\n", csv_path, dir,
                   plotted ? " and sweep.png" : " (gnuplot not run: install gnuplot-nox)", dir);
        }
    }
done:
    lg_str_free(&csv);
    free(csv_path);
    lg_image_free(&ref);
    lg_registry_free(&reg);
    for (int i = 0; i < n_vary; i++) {
        free(v[i].key);
        for (int j = 0; j < v[i].n; j++)
            free(v[i].values[j]);
        free(v[i].values);
    }
    free(sets);
    free(ref_sets);
    return rc;
}
