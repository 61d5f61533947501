/*
 * The SDK's test harness (liblightgraph-test) tested: the comparison's numbers and the
 * worst pixel's place, a wrong output caught, a missing device told apart from a failure,
 * and the bench mode's timings. Runs the reinhard node (cpu, gl, cl) through the host.
 *
 *   diff        lg_test_diff_images: max abs, where, RMSE, NaN/Inf, sizes, half rounding
 *   catches     a reference off by 1e-3 at one pixel: a failed check, at that pixel
 *   no_device   GL and CL made impossible (GALLIUM_DRIVER=softpipe, no OpenCL ICD): cpu
 *               runs, gl and cl are reported as "no device", nothing fails (allow_missing)
 *   partial     the same without allow_missing: the case ends as a skip (77), checked by
 *               running this program's `partial_inner` case
 *   signal      a host killed by SIGSEGV is reported with the signal's number and name
 *   cannot_start  a host that exits 127 before its main (the dynamic loader's "cannot open
 *               shared object file"): the harness prints that message, not a guess about
 *               the plugin path, exits 99 and names the scratch folder it keeps
 *   bench       (run with --bench=3) three executions per backend, times filled in
 */
#include <ftw.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "lightgraph/test.h"

static lg_image image(uint32_t w, uint32_t h, float v)
{
    lg_image img;
    if (lg_image_alloc(&img, w, h)) {
        fprintf(stderr, "lg_image_alloc failed\n");
        exit(LG_TEST_ERROR);
    }
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        img.pixels[i] = v;
    return img;
}

static void case_diff(lg_test *t)
{
    lg_image a = image(5, 3, 0.5f), b = image(5, 3, 0.5f), c = image(3, 5, 0.5f);
    a.pixels[(2 * 5 + 3) * 4 + 2] = 0.75f; /* (3, 2).b */
    lg_test_diff d;
    lg_test_tol loose = { .max_abs = 0.3 }, tight = { .max_abs = 0.1 },
                rmse = { .max_abs = 1, .rmse = 1e-3 };
    LG_TEST_CHECK(t, lg_test_diff_images(&a, &b, 32, &loose, &d), "0.25 within 0.3");
    LG_TEST_CHECK(t, d.max_abs == 0.25 && d.x == 3 && d.y == 2 && d.c == 2, "max %g at (%u, %u).%u",
                  d.max_abs, d.x, d.y, d.c);
    LG_TEST_CHECK(t, d.got == 0.75 && d.want == 0.5, "got %g want %g", d.got, d.want);
    LG_TEST_CHECK(t, fabs(d.rmse - sqrt(0.0625 / 60)) < 1e-12, "rmse %.17g", d.rmse);
    LG_TEST_CHECK(t, !lg_test_diff_images(&a, &b, 32, &tight, &d) && d.over == 1,
                  "0.25 beyond 0.1");
    LG_TEST_CHECK(t, !lg_test_diff_images(&a, &b, 32, &rmse, &d), "rmse %g beyond 1e-3", d.rmse);
    LG_TEST_CHECK(t, !lg_test_diff_images(&a, &c, 32, &loose, &d) && d.size_mismatch, "5x3 vs 3x5");

    /* NaN meets NaN; NaN against a number, or +Inf against -Inf, is a mismatch at its place */
    lg_image n1 = image(4, 4, 1.0f), n2 = image(4, 4, 1.0f);
    n1.pixels[0] = n2.pixels[0] = NAN;
    n1.pixels[5] = n2.pixels[5] = INFINITY;
    LG_TEST_CHECK(t, lg_test_diff_images(&n1, &n2, 32, &tight, &d), "equal NaN and Inf");
    n1.pixels[9 * 4 + 1] = NAN;
    LG_TEST_CHECK(t,
                  !lg_test_diff_images(&n1, &n2, 32, &loose, &d) && d.nonfinite == 1 && d.x == 1 &&
                      d.y == 2 && d.c == 1,
                  "NaN vs 1: nonfinite %llu at (%u, %u).%u", (unsigned long long)d.nonfinite, d.x,
                  d.y, d.c);
    n1.pixels[9 * 4 + 1] = 1.0f;
    n2.pixels[5] = -INFINITY;
    LG_TEST_CHECK(t, !lg_test_diff_images(&n1, &n2, 32, &loose, &d) && d.nonfinite == 1,
                  "+Inf vs -Inf");

    /* half files round to 11 significant bits: 1000.4 vs 1000 passes at bits 16 only */
    lg_image h1 = image(1, 1, 1000.4f), h2 = image(1, 1, 1000.0f);
    lg_test_tol zero = { 0 };
    LG_TEST_CHECK(t, lg_test_diff_images(&h1, &h2, 16, &zero, NULL), "half rounding allowed");
    LG_TEST_CHECK(t, !lg_test_diff_images(&h1, &h2, 32, &zero, NULL), "float: no rounding");
    lg_test_tol rel = { .rel = 1e-3 };
    LG_TEST_CHECK(t, lg_test_diff_images(&h1, &h2, 32, &rel, NULL), "relative tolerance");
    lg_image *all[] = { &a, &b, &c, &n1, &n2, &h1, &h2 };
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        lg_image_free(all[i]);
}

/* A 16x8 image of one colour through reinhard: the closed form is m / (1 + m). */
static const char *graph_for(lg_test *t)
{
    lg_image in = image(16, 8, 2.0f);
    lg_test_write_exr(t, "in.exr", &in);
    lg_image_free(&in);
    return "lightgraph 1\nsrc = image { file = \"in.exr\" }\ntone = reinhard { image = src }\n";
}

static lg_image closed_form(void)
{
    double l = 2.0, m = 0.18 * l / (l + 1e-4);
    lg_image want = image(16, 8, (float)(m / (1 + m)));
    for (size_t i = 0; i < 16 * 8; i++)
        want.pixels[i * 4 + 3] = 2.0f;
    return want;
}

static int rm_entry(const char *p, const struct stat *s, int f, struct FTW *w)
{
    (void)s, (void)f, (void)w;
    return remove(p);
}

static void case_catches(lg_test *t)
{
    /* in a case of its own, whose failure is the expected result */
    lg_test *inner = lg_test_begin("harness-inner");
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", lg_test_dir(inner));
    lg_image want = closed_form();
    want.pixels[(5 * 16 + 7) * 4 + 1] += 1e-3f; /* (7, 5).g */
    lg_test_backends_desc d = {
        .graph = graph_for(inner),
        .node = "tone",
        .backends = (const char *const[]){ "cpu", NULL },
        .reference = &want,
        .tol_reference = { .max_abs = 1e-5 },
    };
    lg_test_backends_result res;
    size_t ran = lg_test_backends(inner, &d, &res);
    LG_TEST_CHECK(t, ran == 1, "%zu backends ran", ran);
    LG_TEST_CHECK(t, lg_test_failures(inner) == 1, "%d failed checks, want 1",
                  lg_test_failures(inner));
    const lg_test_diff *v = &res.run[0].vs_reference;
    LG_TEST_CHECK(t,
                  v->over == 1 && v->x == 7 && v->y == 5 && v->c == 1 &&
                      fabs(v->max_abs - 1e-3) < 1e-6,
                  "over %llu, max %g at (%u, %u).%u", (unsigned long long)v->over, v->max_abs, v->x,
                  v->y, v->c);
    LG_TEST_CHECK(t, lg_test_end(&inner) == LG_TEST_FAIL && inner == NULL, "the inner case passed");
    nftw(dir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
    lg_test_backends_free(&res);
    lg_image_free(&want);
}

static void case_no_device(lg_test *t)
{
    /* the host, started by the harness, inherits these: llvmpipe is needed for GL 4.5, and
     * an empty ICD list leaves no OpenCL platform */
    setenv("GALLIUM_DRIVER", "softpipe", 1);
    setenv("OCL_ICD_VENDORS", lg_test_path(t, "no-icds"), 1);
    lg_image want = closed_form();
    lg_test_backends_desc d = {
        .graph = graph_for(t),
        .node = "tone",
        .reference = &want,
        .tol_reference = { .max_abs = 1e-6 },
        .tol_backends = { .max_abs = 1e-6 },
        .allow_missing = true,
    };
    lg_test_backends_result res;
    size_t ran = lg_test_backends(t, &d, &res);
    LG_TEST_CHECK(t, ran == 1 && res.n == 3, "%zu of %zu ran, want 1 of 3", ran, res.n);
    for (size_t i = 0; i < res.n; i++) {
        bool cpu = strcmp(res.run[i].backend, "cpu") == 0;
        LG_TEST_CHECK(t, res.run[i].status == (cpu ? LG_TEST_RUN_OK : LG_TEST_RUN_NO_DEVICE),
                      "%s: status %d", res.run[i].backend, (int)res.run[i].status);
    }
    LG_TEST_CHECK(t, lg_test_failures(t) == 0, "a missing device counted as a failure");
    lg_test_backends_free(&res);
    lg_image_free(&want);
}

/* Without allow_missing: gl and cl missing make the case a skip, after cpu passed. */
static void case_partial_inner(lg_test *t)
{
    setenv("GALLIUM_DRIVER", "softpipe", 1);
    setenv("OCL_ICD_VENDORS", lg_test_path(t, "no-icds"), 1);
    /* no reference image: the skip leaves this function, which could not free it */
    lg_test_backends_desc d = { .graph = graph_for(t), .node = "tone" };
    lg_test_backends(t, &d, NULL);
    LG_TEST_FAILF(t, "lg_test_backends returned although gl and cl were missing");
}

/* Runs this program's case `inner` in a child, its stdout and stderr into text; returns its
 * exit status (-1 if it did not exit). */
static int run_inner(lg_test *t, const char *inner, char *text, size_t len)
{
    text[0] = 0;
    char self[4096];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) {
        LG_TEST_FAILF(t, "readlink /proc/self/exe failed");
        return -1;
    }
    self[n] = 0;
    char cmd[9000];
    snprintf(cmd, sizeof cmd, "'%s' %s >'%s' 2>&1", self, inner, lg_test_path(t, "inner.txt"));
    int st = system(cmd);
    FILE *f = fopen(lg_test_path(t, "inner.txt"), "r");
    if (f) {
        size_t got = fread(text, 1, len - 1, f);
        text[got] = 0;
        fclose(f);
    }
    return st != -1 && WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void case_partial(lg_test *t)
{
    char text[8192];
    int code = run_inner(t, "partial_inner", text, sizeof text);
    LG_TEST_CHECK(t, code == LG_TEST_SKIP, "exit %d, want 77: %s", code, text);
    LG_TEST_CHECK(t,
                  strstr(text, "no device here for gl, cl (the 1 other backend(s) passed)") != NULL,
                  "the skip does not name the missing devices: %s", text);
}

/* A host that dies on a signal: the harness names the signal (issue 20: CI's log said only
 * "exit -1 (signal)"). The inner case runs a stand-in for the host that kills itself with
 * SIGSEGV; the outer one reads what the harness printed. */
static void case_signal_inner(lg_test *t)
{
    const char *script = lg_test_path(t, "segv.sh");
    FILE *f = fopen(script, "w");
    if (!f || fputs("#!/bin/sh\nkill -SEGV $$\n", f) < 0 || fclose(f) || chmod(script, 0755)) {
        LG_TEST_FAILF(t, "cannot write %s", script);
        return;
    }
    setenv("LG_EXE", script, 1); /* single-threaded test process: allowed */
    int rc = lg_test_render(t, "none.lgraph", NULL, NULL);
    LG_TEST_CHECK(t, rc == -1, "status %d, want -1 (a signal)", rc);
}

static void case_signal(lg_test *t)
{
    char text[8192];
    int code = run_inner(t, "signal_inner", text, sizeof text);
    LG_TEST_CHECK(t, code == 0, "the inner case exited %d: %s", code, text);
    LG_TEST_CHECK(t, strstr(text, "killed by signal 11 (SIGSEGV") != NULL,
                  "the signal is not named: %s", text);
}

/* A host that cannot start (issue 21: an installed program without its RPATH gave exit 127
 * and the hint "is the plugin on LIGHTGRAPH_PLUGIN_PATH?", and the scratch folder was left
 * unnamed). The stand-in prints what ld.so prints and exits 127, as ld.so does. */
static void case_cannot_start_inner(lg_test *t)
{
    const char *script = lg_test_path(t, "noload.sh");
    FILE *f = fopen(script, "w");
    if (!f ||
        fputs("#!/bin/sh\necho \"$0: error while loading shared libraries: liblightgraph.so.3: "
              "cannot open shared object file: No such file or directory\" >&2\nexit 127\n",
              f) < 0 ||
        fclose(f) || chmod(script, 0755)) {
        LG_TEST_FAILF(t, "cannot write %s", script);
        return;
    }
    setenv("LG_EXE", script, 1); /* single-threaded test process: allowed */
    lg_test_backends_desc d = { .graph = graph_for(t), .node = "tone" };
    lg_test_backends(t, &d, NULL); /* asks `inspect` first: the harness must exit there */
    LG_TEST_FAILF(t, "lg_test_backends returned although the host could not start");
}

static void case_cannot_start(lg_test *t)
{
    char text[8192];
    int code = run_inner(t, "cannot_start_inner", text, sizeof text);
    LG_TEST_CHECK(t, code == LG_TEST_ERROR, "exit %d, want 99: %s", code, text);
    LG_TEST_CHECK(t,
                  strstr(text, "could not start (exit 127") != NULL &&
                      strstr(text, "liblightgraph.so.3: cannot open shared object file") != NULL,
                  "the loader's message is not given as the cause: %s", text);
    LG_TEST_CHECK(t, strstr(text, "LIGHTGRAPH_PLUGIN_PATH") == NULL,
                  "a host that cannot start is blamed on the plugin path: %s", text);
    const char *kept = strstr(text, "scratch folder kept: ");
    char dir[4096] = "";
    if (kept)
        sscanf(kept + strlen("scratch folder kept: "), "%4095[^\n]", dir);
    struct stat st;
    LG_TEST_CHECK(t,
                  *dir && strstr(dir, "harness-cannot_start_inner-") && stat(dir, &st) == 0 &&
                      S_ISDIR(st.st_mode),
                  "the kept scratch folder is not named (or not there): '%s' in %s", dir, text);
    if (*dir && strstr(dir, "harness-cannot_start_inner-"))
        nftw(dir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
}

static void case_bench(lg_test *t)
{
    uint32_t frames = lg_test_bench_frames(t);
    if (!frames) {
        LG_TEST_FAILF(t, "run this case with --bench=N");
        return;
    }
    lg_image want = closed_form();
    lg_test_backends_desc d = {
        .graph = graph_for(t),
        .node = "tone",
        .reference = &want,
        .tol_reference = { .max_abs = 1e-5 },
        .tol_backends = { .max_abs = 1e-5 },
    };
    lg_test_backends_result res;
    lg_test_backends(t, &d, &res);
    for (size_t i = 0; i < res.n; i++) {
        const lg_test_run *r = &res.run[i];
        if (r->status != LG_TEST_RUN_OK)
            continue;
        LG_TEST_CHECK(t, r->runs == frames, "%s: %llu runs, want %u", r->backend,
                      (unsigned long long)r->runs, frames);
        LG_TEST_CHECK(t,
                      r->first_ms > 0 && r->min_ms > 0 && r->mean_ms >= r->min_ms &&
                          r->min_ms <= r->first_ms,
                      "%s: first %g, mean %g, min %g ms", r->backend, r->first_ms, r->mean_ms,
                      r->min_ms);
    }
    lg_test_backends_free(&res);
    lg_image_free(&want);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "diff", case_diff },
        { "catches", case_catches },
        { "no_device", case_no_device },
        { "partial", case_partial },
        { "partial_inner", case_partial_inner },
        { "signal", case_signal },
        { "signal_inner", case_signal_inner },
        { "cannot_start", case_cannot_start },
        { "cannot_start_inner", case_cannot_start_inner },
        { "bench", case_bench },
    };
    lg_test_main_opts o = { .prefix = "harness" };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
