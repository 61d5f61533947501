/* liblightgraph-test: image comparison, one node on each backend, the bench table (see
 * lightgraph/test.h). */
#include "test_priv.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- comparing images ------------------------------------------------------------------------ */

double lg_test_tol_of(double expected, unsigned bits, double tol)
{
    /* half: 10 stored mantissa bits, so rounding to nearest is within 2^-11 relative */
    return tol + (bits == 16 ? fabs(expected) * ldexp(1.0, -11) : 0.0);
}

bool lg_test_diff_images(const lg_image *got, const lg_image *want, unsigned bits,
                         const lg_test_tol *tol, lg_test_diff *out)
{
    lg_test_diff d;
    memset(&d, 0, sizeof d);
    lg_test_tol zero;
    memset(&zero, 0, sizeof zero);
    if (!tol)
        tol = &zero;
    if (got->width != want->width || got->height != want->height || !got->pixels || !want->pixels) {
        d.size_mismatch = true;
        if (out)
            *out = d;
        return false;
    }
    size_t n = (size_t)want->width * want->height * 4;
    double sum = 0, worst = -1;
    size_t finite = 0, at = 0;
    for (size_t i = 0; i < n; i++) {
        double g = got->pixels[i], w = want->pixels[i];
        double ratio;
        if (!isfinite(g) || !isfinite(w)) {
            /* NaN meets NaN, Inf the same Inf */
            bool same = (isnan(g) && isnan(w)) || (isinf(g) && isinf(w) && (g > 0) == (w > 0));
            if (same)
                continue;
            d.nonfinite++;
            d.over++;
            ratio = INFINITY;
        } else {
            double e = fabs(g - w);
            sum += e * e;
            finite++;
            if (e > d.max_abs)
                d.max_abs = e;
            double allowed = lg_test_tol_of(w, bits, tol->max_abs + tol->rel * fabs(w));
            ratio = e <= allowed ? (allowed > 0 ? e / allowed : 0)
                                 : (allowed > 0 ? e / allowed : INFINITY);
            if (e > allowed)
                d.over++;
        }
        if (ratio > worst) {
            worst = ratio;
            at = i;
        }
    }
    d.rmse = finite ? sqrt(sum / (double)finite) : 0;
    d.x = (uint32_t)(at / 4 % want->width);
    d.y = (uint32_t)(at / 4 / want->width);
    d.c = (uint32_t)(at % 4);
    d.got = got->pixels[at];
    d.want = want->pixels[at];
    bool ok = d.over == 0 && !(tol->rmse > 0 && d.rmse > tol->rmse);
    if (out)
        *out = d;
    return ok;
}

static const char CHANNEL[] = "rgba";

/* "max abs 1.2e-07 at (3, 4).g (got 0.5, want 0.5000001), rmse 3e-08" */
static void format_diff(char *buf, size_t cap, const lg_test_diff *d)
{
    if (d->size_mismatch) {
        snprintf(buf, cap, "sizes differ");
        return;
    }
    snprintf(buf, cap, "max abs %.3g at (%u, %u).%c (got %.9g, want %.9g), rmse %.3g", d->max_abs,
             d->x, d->y, CHANNEL[d->c], d->got, d->want, d->rmse);
    if (d->nonfinite) {
        size_t len = strlen(buf);
        snprintf(buf + len, cap - len, ", %llu NaN/Inf mismatches",
                 (unsigned long long)d->nonfinite);
    }
}

bool lg_test_check_image(lg_test *t, const lg_image *got, const lg_image *want, unsigned bits,
                         const lg_test_tol *tol, const char *what)
{
    lg_test_diff d;
    if (lg_test_diff_images(got, want, bits, tol, &d))
        return true;
    char text[512];
    format_diff(text, sizeof text, &d);
    if (d.size_mismatch)
        lg_test_failf_(t, "%s: size %ux%u, want %ux%u", what, got->width, got->height, want->width,
                       want->height);
    else
        lg_test_failf_(t,
                       "%s: %llu values beyond tolerance (max abs %.3g + rel %.3g, rmse %.3g): %s",
                       what, (unsigned long long)d.over, tol ? tol->max_abs : 0, tol ? tol->rel : 0,
                       tol ? tol->rmse : 0, text);
    return false;
}

/* ---- one node on every backend --------------------------------------------------------------- */

/* The type of `node` from a line "node = type {" of the graph. */
static bool type_from_graph(const char *graph, const char *node, char *type, size_t cap)
{
    size_t nl = strlen(node);
    for (const char *p = graph; p && *p; p = strchr(p, '\n'), p = p ? p + 1 : NULL) {
        while (*p == ' ' || *p == '\t')
            p++;
        if (strncmp(p, node, nl) || !(p[nl] == ' ' || p[nl] == '\t' || p[nl] == '='))
            continue;
        const char *q = p + nl;
        while (*q == ' ' || *q == '\t')
            q++;
        if (*q++ != '=')
            continue;
        while (*q == ' ' || *q == '\t')
            q++;
        size_t k = 0;
        while ((isalnum((unsigned char)q[k]) || q[k] == '_') && k + 1 < cap) {
            type[k] = q[k];
            k++;
        }
        type[k] = 0;
        return k > 0;
    }
    return false;
}

/* The values of the `backend` enum of `type`, from `lightgraph inspect TYPE --json`.
 * Returns how many (0 when the type has no backend parameter). */
static size_t declared_backends(const char *type, char names[][32], size_t cap)
{
    const char *argv[] = { lg_test_exe(), "inspect", type, "--json", NULL };
    char *out = NULL;
    int rc = lg_test_spawn_(argv, NULL, &out);
    /* (exit 127, a host that cannot start, was named by lg_test_spawn_ already) */
    if (rc != 0 && strstr(out, "unknown node type"))
        lg_test_die_("`%s inspect %s --json`: the host knows no node type '%s' (exit %d): is "
                     "its plugin in a folder of LIGHTGRAPH_PLUGIN_PATH (lg_test_use_plugins)?",
                     argv[0], type, type, rc);
    if (rc != 0)
        lg_test_die_("`%s inspect %s --json` failed (exit %d; its output is above)", argv[0], type,
                     rc);
    size_t n = 0;
    const char *p = strstr(out, "\"key\": \"backend\"");
    const char *v = p ? strstr(p, "\"values\": [") : NULL;
    const char *end = v ? strchr(v, ']') : NULL;
    if (v && end) {
        for (const char *q = strchr(v, '['); q && q < end && n < cap;) {
            const char *a = strchr(q, '"');
            if (!a || a > end)
                break;
            const char *b = strchr(a + 1, '"');
            if (!b || b > end)
                break;
            snprintf(names[n++], 32, "%.*s", (int)(b - a - 1), a + 1);
            q = b + 1;
        }
    }
    free(out);
    return n;
}

/* A number after "key": on the line of `node` in a --profile-json file. */
static bool profile_field(const char *line, const char *key, double *v)
{
    char k[64];
    snprintf(k, sizeof k, "\"%s\": ", key);
    const char *p = strstr(line, k);
    const char *eol = strchr(line, '\n');
    if (!p || (eol && p > eol))
        return false;
    p += strlen(k);
    if (strncmp(p, "true", 4) == 0 || strncmp(p, "false", 5) == 0) {
        *v = p[0] == 't';
        return true;
    }
    char *end;
    *v = strtod(p, &end);
    return end != p;
}

static bool read_profile(lg_test *t, const char *rel, const char *node, lg_test_run *r)
{
    FILE *f = fopen(lg_test_path(t, rel), "r");
    if (!f)
        return false;
    char *text = NULL;
    size_t len = 0;
    if (fseek(f, 0, SEEK_END) == 0) {
        long l = ftell(f);
        if (l > 0 && fseek(f, 0, SEEK_SET) == 0 && (text = calloc(1, (size_t)l + 1)))
            len = fread(text, 1, (size_t)l, f);
    }
    fclose(f);
    if (!text)
        return false;
    text[len] = 0;
    char key[160];
    snprintf(key, sizeof key, "{\"name\": \"%s\"", node);
    const char *line = strstr(text, key);
    double runs = 0, total = 0, first = 0, min = 0, gpu = 0, measured = 0;
    bool ok = line && profile_field(line, "runs", &runs) && profile_field(line, "cpu_ms", &total);
    if (ok) {
        /* hosts before --every-frame have no first/min: the mean is all there is */
        if (!profile_field(line, "first_cpu_ms", &first))
            first = total / (runs > 0 ? runs : 1);
        if (!profile_field(line, "min_cpu_ms", &min))
            min = first;
        profile_field(line, "gpu_ms", &gpu);
        profile_field(line, "gpu_measured", &measured);
        r->runs = (uint64_t)runs;
        r->first_ms = first;
        r->min_ms = min;
        r->mean_ms = runs > 1 ? (total - first) / (runs - 1) : first;
        r->gpu_ms = gpu;
        r->gpu_measured = measured != 0;
    }
    free(text);
    return ok;
}

static void run_backend(lg_test *t, const lg_test_backends_desc *desc, const char *backend,
                        lg_test_run *r)
{
    memset(r, 0, sizeof *r);
    snprintf(r->backend, sizeof r->backend, "%s", backend);
    char out_rel[200], prof_rel[200], graph_rel[200], set[200], frames[32];
    snprintf(out_rel, sizeof out_rel, "%s-%s.exr", desc->node, backend);
    snprintf(prof_rel, sizeof prof_rel, "%s-%s.json", desc->node, backend);
    snprintf(graph_rel, sizeof graph_rel, "%s-%s.lgraph", desc->node, backend);
    snprintf(set, sizeof set, "%s.backend=%s", desc->node, backend);

    size_t glen = strlen(desc->graph);
    char *graph = malloc(glen + 512);
    if (!graph)
        lg_test_die_("out of memory");
    snprintf(graph, glen + 512, "%s%soutput %s \"%s\"\n", desc->graph,
             glen && desc->graph[glen - 1] != '\n' ? "\n" : "", desc->node, out_rel);
    lg_test_write_text(t, graph_rel, graph);
    free(graph);

    const char *argv[64];
    int n = 0;
    if (strcmp(backend, "default")) {
        argv[n++] = "--set";
        argv[n++] = set;
    }
    argv[n++] = "--profile-json";
    argv[n++] = prof_rel;
    char every[200];
    if (t->bench_frames) {
        /* only the node under test runs again: its inputs stay resident on its device, so
         * the time is the node's own work, not its inputs' re-upload */
        snprintf(frames, sizeof frames, "%u", t->bench_frames);
        snprintf(every, sizeof every, "--every-frame=%s", desc->node);
        argv[n++] = "--frames";
        argv[n++] = frames;
        argv[n++] = every;
    }
    for (int i = 0; desc->args && desc->args[i]; i++) {
        if (n >= 62)
            lg_test_die_("lg_test_backends: too many arguments");
        argv[n++] = desc->args[i];
    }
    argv[n] = NULL;

    char *out = NULL;
    int rc = lg_test_render(t, graph_rel, argv, &out);
    if (rc == 1 && lg_test_output_says_no_device(out)) {
        r->status = LG_TEST_RUN_NO_DEVICE;
    } else if (rc != 0) {
        r->status = LG_TEST_RUN_FAILED;
        lg_test_failf_(t, "%s on %s: render failed (exit %d)", desc->what ? desc->what : desc->node,
                       backend, rc);
    } else if (!lg_test_read(t, out_rel, &r->image, &r->bits)) {
        r->status = LG_TEST_RUN_FAILED;
    } else if (!read_profile(t, prof_rel, desc->node, r)) {
        r->status = LG_TEST_RUN_FAILED;
        lg_test_failf_(t, "%s on %s: no timing for node %s in %s",
                       desc->what ? desc->what : desc->node, backend, desc->node, prof_rel);
    }
    free(out);
}

static void print_table(const lg_test *t, const lg_test_backends_desc *desc,
                        const lg_test_backends_result *res, const char *first)
{
    const char *what = desc->what ? desc->what : desc->node;
    const lg_image *img = NULL;
    for (size_t i = 0; i < res->n && !img; i++)
        if (res->run[i].status == LG_TEST_RUN_OK)
            img = &res->run[i].image;
    fprintf(stderr, "%s: %ux%u, %s\n", what, img ? img->width : 0, img ? img->height : 0,
            t->bench_frames ? "bench (--every-frame=node)" : "test");
    fprintf(stderr, "  %-8s %-8s %-36s %-36s %9s %9s %9s", "backend", "status",
            desc->reference ? "vs reference" : "(no reference)", first ? "vs first backend" : "",
            "first ms", "mean ms", "min ms");
    if (t->bench_frames)
        fprintf(stderr, " %8s %8s %8s", "Mpix/s", "GB/s", "gpu ms");
    fputc('\n', stderr);
    for (size_t i = 0; i < res->n; i++) {
        const lg_test_run *r = &res->run[i];
        if (r->status != LG_TEST_RUN_OK) {
            fprintf(stderr, "  %-8s %s\n", r->backend,
                    r->status == LG_TEST_RUN_NO_DEVICE ? "no device here (left out)" : "FAILED");
            continue;
        }
        char a[64] = "-", b[64] = "-";
        if (desc->reference)
            snprintf(a, sizeof a, "%.2e (%u,%u).%c rmse %.1e", r->vs_reference.max_abs,
                     r->vs_reference.x, r->vs_reference.y, CHANNEL[r->vs_reference.c],
                     r->vs_reference.rmse);
        if (first && strcmp(first, r->backend))
            snprintf(b, sizeof b, "%.2e (%u,%u).%c rmse %.1e", r->vs_first.max_abs, r->vs_first.x,
                     r->vs_first.y, CHANNEL[r->vs_first.c], r->vs_first.rmse);
        bool bad = r->vs_reference.over || r->vs_first.over || r->vs_reference.size_mismatch ||
                   r->vs_first.size_mismatch;
        fprintf(stderr, "  %-8s %-8s %-36s %-36s %9.3f %9.3f %9.3f", r->backend,
                bad ? "OVER" : "ok", a, b, r->first_ms, r->mean_ms, r->min_ms);
        if (t->bench_frames) {
            double px = (double)r->image.width * r->image.height;
            double bytes = desc->bytes_per_frame > 0 ? desc->bytes_per_frame : px * 32.0;
            double s = r->mean_ms * 1e-3;
            char gpu[32] = "n/a";
            if (r->gpu_measured && r->gpu_ms > 0 && r->runs)
                snprintf(gpu, sizeof gpu, "%.3f", r->gpu_ms / (double)r->runs);
            fprintf(stderr, " %8.1f %8.2f %8s", s > 0 ? px / s * 1e-6 : 0,
                    s > 0 ? bytes / s * 1e-9 : 0, gpu);
        }
        fputc('\n', stderr);
    }
    if (t->bench_frames)
        fprintf(stderr, "  (%u frames per backend; mean over the frames after the first)\n",
                t->bench_frames);
}

size_t lg_test_backends(lg_test *t, const lg_test_backends_desc *desc, lg_test_backends_result *res)
{
    if (!desc || !desc->graph || !desc->node)
        lg_test_die_("lg_test_backends: graph and node are required");
    lg_test_backends_result local;
    if (!res)
        res = &local;
    memset(res, 0, sizeof *res);

    char names[LG_TEST_MAX_BACKENDS][32];
    size_t nb = 0;
    if (desc->backends) {
        for (; desc->backends[nb]; nb++) {
            if (nb == LG_TEST_MAX_BACKENDS)
                lg_test_die_("lg_test_backends: more than %d backends", LG_TEST_MAX_BACKENDS);
            snprintf(names[nb], 32, "%s", desc->backends[nb]);
        }
    } else {
        char type[128];
        if (desc->type)
            snprintf(type, sizeof type, "%s", desc->type);
        else if (!type_from_graph(desc->graph, desc->node, type, sizeof type))
            lg_test_die_("lg_test_backends: no line \"%s = TYPE {\" in the graph; set .type",
                         desc->node);
        nb = declared_backends(type, names, LG_TEST_MAX_BACKENDS);
        if (nb == 0)
            snprintf(names[nb++], 32, "default"); /* no backend parameter: run it as it is */
    }

    for (size_t i = 0; i < nb; i++)
        run_backend(t, desc, names[i], &res->run[res->n++]);

    const lg_test_run *first = NULL;
    const char *what = desc->what ? desc->what : desc->node;
    for (size_t i = 0; i < res->n; i++) {
        lg_test_run *r = &res->run[i];
        if (r->status != LG_TEST_RUN_OK)
            continue;
        res->n_ok++;
        char label[256];
        if (desc->reference) {
            snprintf(label, sizeof label, "%s on %s vs reference", what, r->backend);
            lg_test_diff_images(&r->image, desc->reference, r->bits, &desc->tol_reference,
                                &r->vs_reference);
            lg_test_check_image(t, &r->image, desc->reference, r->bits, &desc->tol_reference,
                                label);
        }
        if (!first) {
            first = r;
            continue;
        }
        snprintf(label, sizeof label, "%s on %s vs %s", what, r->backend, first->backend);
        /* both sides went through a file: each may carry its own rounding */
        unsigned bits = r->bits == 16 || first->bits == 16 ? 16 : 32;
        lg_test_tol tol = desc->tol_backends;
        if (bits == 16) {
            tol.max_abs *= 2;
            tol.rel += ldexp(1.0, -11);
        }
        lg_test_diff_images(&r->image, &first->image, bits, &tol, &r->vs_first);
        lg_test_check_image(t, &r->image, &first->image, bits, &tol, label);
    }
    print_table(t, desc, res, first && res->n_ok > 1 ? first->backend : NULL);
    size_t ran = res->n_ok;
    char missing[256] = "";
    for (size_t i = 0; i < res->n; i++) {
        if (res->run[i].status == LG_TEST_RUN_NO_DEVICE) {
            size_t len = strlen(missing);
            snprintf(missing + len, sizeof missing - len, "%s%s", len ? ", " : "",
                     res->run[i].backend);
        }
    }
    bool skip = t->failures == 0 && (ran == 0 || (*missing && !desc->allow_missing));
    if (res == &local || skip)
        lg_test_backends_free(res);
    if (skip && ran == 0)
        lg_test_skip(t, "%s: no backend's device can be made here", what);
    if (skip)
        lg_test_skip(t, "%s: no device here for %s (the %zu other backend(s) passed)", what,
                     missing, ran);
    return ran;
}

void lg_test_backends_free(lg_test_backends_result *res)
{
    if (!res)
        return;
    for (size_t i = 0; i < res->n; i++)
        lg_image_free(&res->run[i].image);
    memset(res, 0, sizeof *res);
}
