/*
 * lightgraph/test.h: the plugin test harness (library liblightgraph-test, pkg-config
 * package `lightgraph-test`). A test program for a plugin, and its benchmark.
 *
 * What it does. A test runs the `lightgraph` program as a user would: it writes input
 * images and a graph into a scratch folder, runs `lightgraph render` on it, reads the
 * output images back and checks them. lg_test_backends() runs one node on each backend
 * its `backend` parameter declares (cpu, gl, cl...), compares the outputs with each other
 * and with a reference image at a stated tolerance (max abs and RMSE, with the worst
 * pixel's place and values), and times them from the host's profile. Run with `--bench`,
 * the same program renders N frames per backend and prints a timing table (as dav1d's
 * checkasm does).
 *
 * Why a separate program rather than in-process. The host is a program, not a library;
 * running it keeps the test on the path users take (parser, planner, resource moves,
 * devices) and keeps host internals out of this installed library. The price is a process
 * start per render (a few ms plus device creation).
 *
 * Which program. $LG_EXE when set (in-tree tests: meson sets it), else the `lightgraph`
 * installed beside this library (<libdir>/../bin, found from the library's own file, so
 * that a prefix installed with --destdir or moved runs its own program), else the one of
 * the prefix it was built for (the pkg-config variable `lightgraph`). Plugins are found
 * by the host as usual: LIGHTGRAPH_PLUGIN_PATH (see lg_test_use_plugins), the build tree,
 * the install directory.
 *
 * Writing a test program:
 *
 *     static void case_basic(lg_test *t)
 *     {
 *         lg_image in, want;
 *         ... fill in, compute want with a plain reference ...
 *         lg_test_write_exr(t, "in.exr", &in);
 *         lg_test_backends_desc d = {
 *             .graph = "lightgraph 1\n"
 *                      "src = image { file = \"in.exr\" }\n"
 *                      "blur = acme_blur { image = src, sigma = 2 }\n",
 *             .node = "blur",
 *             .reference = &want,
 *             .tol_reference = { .max_abs = 1e-6 },
 *             .tol_backends = { .max_abs = 1e-6 },
 *         };
 *         lg_test_backends(t, &d, NULL);
 *     }
 *
 *     int main(int argc, char **argv)
 *     {
 *         static const lg_test_case cases[] = { { "basic", case_basic } };
 *         return lg_test_main(argc, argv, cases, 1, NULL);
 *     }
 *
 * Exit codes (what meson and CTest expect):
 *   0   every check passed                           LG_TEST_PASS
 *   1   a check failed (the scratch folder is kept)  LG_TEST_FAIL
 *   77  skipped: a device the case needs is missing  LG_TEST_SKIP
 *       (never when a check has already failed: a skip does not hide a failure)
 *   99  the harness itself failed (cannot write a file, start the program, bad usage).
 *       A program that cannot start is named with the cause: the exec error, or for exit
 *       127 (the dynamic loader gave up before main) the loader's own message.
 *
 * Scratch folders: $LG_BUILD_ROOT/test-tmp/NAME-XXXXXX, else $TMPDIR or /tmp. Removed when
 * the case passes (or skips), kept when a check failed or the harness failed (exit 99):
 * every kept folder is named on stderr ("files kept in DIR", "scratch folder kept: DIR").
 *
 * Output on stderr; set LG_TEST_VERBOSE=1 to see every command and the host's output
 * (printed anyway when a render fails).
 *
 * Thread-safety: none. One lg_test per case, used from one thread; the harness changes
 * the process's environment (lg_test_use_plugins).
 */
#ifndef LIGHTGRAPH_TEST_H
#define LIGHTGRAPH_TEST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "lightgraph/config.h"
#include "lightgraph/image.h"

#ifdef __cplusplus
extern "C" {
#endif

#ifdef LG_BUILDING_TEST_LIB
#define LG_TEST_API LG_EXPORT
#else
#define LG_TEST_API
#endif

#if defined(__GNUC__) || defined(__clang__)
#define LG_TEST_PRINTF(f, a) __attribute__((format(printf, f, a)))
#define LG_TEST_NORETURN __attribute__((noreturn))
#else
#define LG_TEST_PRINTF(f, a)
#define LG_TEST_NORETURN
#endif

enum {
    LG_TEST_PASS = 0,
    LG_TEST_FAIL = 1,
    LG_TEST_SKIP = 77,
    LG_TEST_ERROR = 99,
};

/* One running case: its scratch folder and its count of failed checks. Made and freed by
 * the harness (lg_test_main, lg_test_run_case, or lg_test_begin / lg_test_end); a case
 * function only borrows it. */
typedef struct lg_test lg_test;

/* ---- checks ---------------------------------------------------------------------------------- */

/* Records a failed check: prints "FILE:LINE: check failed: " and the message on stderr,
 * counts it, and the case goes on (one run shows every failing check). */
LG_TEST_API void lg_test_fail_at(lg_test *t, const char *file, int line, const char *fmt, ...)
    LG_TEST_PRINTF(4, 5);
/* Number of failed checks so far. */
LG_TEST_API int lg_test_failures(const lg_test *t);

/* LG_TEST_CHECK(t, cond, "printf format", ...): a false `cond` is a failed check, printed
 * with the condition's text and the message (the format is required). */
#define LG_TEST_CHECK(t, cond, ...)                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            lg_test_check_failed_((t), __FILE__, __LINE__, #cond);                                 \
            lg_test_note_(__VA_ARGS__);                                                            \
        }                                                                                          \
    } while (0)
/* LG_TEST_FAILF(t, "printf format", ...): an unconditional failed check. */
#define LG_TEST_FAILF(t, ...) lg_test_fail_at((t), __FILE__, __LINE__, __VA_ARGS__)

/* Parts of LG_TEST_CHECK: the first counts the failure and prints its place and condition,
 * the second its message and a newline. */
LG_TEST_API void lg_test_check_failed_(lg_test *t, const char *file, int line, const char *cond);
LG_TEST_API void lg_test_note_(const char *fmt, ...) LG_TEST_PRINTF(1, 2);

/* ---- cases and main -------------------------------------------------------------------------- */

typedef struct lg_test_case {
    const char *name;
    void (*run)(lg_test *t);
} lg_test_case;

typedef struct lg_test_main_opts {
    /* scratch folder name of a case: "<prefix>-<case>" (NULL: the case's name) */
    const char *prefix;
    /* called after the folder is made, before the case (e.g. lg_test_use_plugins) */
    void (*setup)(lg_test *t);
    uint32_t reserved[8];
} lg_test_main_opts;

/* The main() of a test program. Command line:
 *
 *     PROG CASE [ARG...]          runs one case (meson: one test() per case)
 *     PROG --all                  runs every case in turn; exit 1 if one failed, 77 if all
 *                                 skipped, else 0
 *     PROG --list                 prints the case names
 *     PROG --bench[=N] [CASE...]  runs the cases (all when none is named) with N frames
 *                                 (default 30) per backend in lg_test_backends and prints
 *                                 a timing table per comparison
 *
 * ARGs after CASE are left for the case: lg_test_arg(t, 0) is the first.
 * `opts` may be NULL; it need only live until the call returns. Returns the exit code. */
LG_TEST_API int lg_test_main(int argc, char **argv, const lg_test_case *cases, size_t n,
                             const lg_test_main_opts *opts);

/* Runs the case `name` of `cases[0..n)` in a scratch folder called `folder` (NULL: the
 * case's name), with `setup` (may be NULL) first. Returns the case's exit code; an unknown
 * name prints "PROG: unknown case" and returns 99. (lg_test_main without the parsing.) */
LG_TEST_API int lg_test_run_case(const char *prog, const char *name, const lg_test_case *cases,
                                 size_t n, const char *folder, void (*setup)(lg_test *t));

/* For a program without a case table: makes a case and its scratch folder (exits 99 if it
 * cannot) ... */
LG_TEST_API lg_test *lg_test_begin(const char *name);
/* ... and ends it: removes the folder unless a check failed, frees *t, sets it to NULL,
 * and returns the exit code (0 or 1). */
LG_TEST_API int lg_test_end(lg_test **t);

/* The case's extra command-line arguments (after CASE), or NULL past the last. */
LG_TEST_API const char *lg_test_arg(const lg_test *t, int i);
/* Frames per backend in lg_test_backends: 0 in a test run, N under --bench=N. */
LG_TEST_API uint32_t lg_test_bench_frames(const lg_test *t);

/* Skips the case after printing "skipped: <why>": a case run by lg_test_main or
 * lg_test_run_case ends there (status 77, or 1 if a check had already failed: a skip never
 * hides a failure; the scratch folder is removed when nothing failed) and, under --all,
 * the next case runs. Anywhere else (t NULL, or from lg_test_begin) the program exits
 * with that status. Memory the case allocated is not freed: skip before allocating. */
LG_TEST_API LG_TEST_NORETURN void lg_test_skip(lg_test *t, const char *fmt, ...)
    LG_TEST_PRINTF(2, 3);

/* ---- files in the scratch folder ------------------------------------------------------------- */

/* The case's scratch folder (absolute; lives as long as the case). */
LG_TEST_API const char *lg_test_dir(const lg_test *t);
/* "<dir>/<rel>". The string belongs to `t` and lives until the 8th call after this one. */
LG_TEST_API const char *lg_test_path(lg_test *t, const char *rel);
/* Write a text file, or an image as float RGBA EXR, uncompressed (its size then depends
 * only on the image's size). A write that fails ends the program with 99. */
LG_TEST_API void lg_test_write_text(lg_test *t, const char *rel, const char *text);
LG_TEST_API void lg_test_write_exr(lg_test *t, const char *rel, const lg_image *img);
/* Reads dir/rel into `img` (the caller frees it with lg_image_free). On failure: a failed
 * check, `img` zeroed, false. `bits` may be NULL: it receives the file's bits per channel
 * (16 for half EXR, 32 for float). */
LG_TEST_API bool lg_test_read(lg_test *t, const char *rel, lg_image *img, unsigned *bits);

/* ---- running the host ------------------------------------------------------------------------ */

/* The lightgraph program the harness runs ($LG_EXE, else the installed one). */
LG_TEST_API const char *lg_test_exe(void);

/* Runs `lightgraph render <dir/graph> args...` (`args` NULL-terminated, may be NULL) with
 * the scratch folder as working directory, so relative paths in the graph and in -o land
 * there. Returns the exit status (0 success, 1 failure while running, 2 bad graph or
 * usage; -1 if the program died on a signal). `*out`, when `out` is not NULL, receives
 * what the program printed, stdout and stderr together (malloc'd: free() it). The command
 * and its output are echoed when the status is not 0, or always with LG_TEST_VERBOSE; a
 * death by a signal is echoed with its number and name ("killed by signal 11 (SIGSEGV:
 * Segmentation fault)").
 * Not a check: the caller decides what a status means. */
LG_TEST_API int lg_test_render(lg_test *t, const char *graph, const char *const *args, char **out);

/* Exit status 1 of a render that failed only because a device it needed could not be
 * made here: true when `out` holds the host's message for that ("no OpenGL 4.5 device",
 * "no OpenCL device"). */
LG_TEST_API bool lg_test_output_says_no_device(const char *out);

/* Ends the program with a skip (lg_test_skip) when the backend's device cannot be made
 * here, asking `lightgraph devices`: "gl" or "cl"; "cpu" always works. */
LG_TEST_API void lg_test_require_backend(lg_test *t, const char *backend);

/* Points the host at extra plugin folders: sets LIGHTGRAPH_PLUGIN_PATH to `path` (folders
 * joined with ':') and, with `t`, LIGHTGRAPH_CACHE_DIR to a folder in t's scratch folder so
 * that the case starts with an empty cache. Fails (exit 99) when `path` is NULL or empty:
 * the build defines the folder, so that is a build error, never a skip.
 * It writes the test process's environment (for the host it spawns), so call it, as the
 * set-up hook of lg_test_main does, before the test program starts any thread: setenv()
 * while another thread reads the environment is undefined (glibc crashes). */
LG_TEST_API void lg_test_use_plugins(lg_test *t, const char *path);

/* $LG_SOURCE_ROOT/assets/<rel>. A repository asset is never optional: when LG_SOURCE_ROOT is
 * unset or the file is not readable, the test fails at once (exit 1, naming the path), so a
 * lost file can never turn a test into a quieter one. The string lives until the next
 * call. */
LG_TEST_API const char *lg_test_asset(const char *rel);

/* ---- comparing images ------------------------------------------------------------------------ */

/* A tolerance: a comparison passes when the largest absolute difference is at most
 * max_abs + rel * |reference value| at every channel, and the RMSE over every channel
 * at most `rmse` (0: not checked). NaN must meet NaN; +-Inf must meet the same Inf. */
typedef struct lg_test_tol {
    double max_abs;
    double rel;
    double rmse;
    uint32_t reserved[4];
} lg_test_tol;

/* What a comparison found. */
typedef struct lg_test_diff {
    double max_abs;     /* largest |got - want| over finite pairs */
    double rmse;        /* over finite pairs, all four channels */
    uint32_t x, y, c;   /* where the worst difference (in units of the tolerance) is */
    double got, want;   /* the values there */
    uint64_t over;      /* values beyond the tolerance (non-finite mismatches included) */
    uint64_t nonfinite; /* values where NaN/Inf do not match */
    bool size_mismatch;
    uint32_t reserved[4];
} lg_test_diff;

/* Compares `got` with `want` at `tol`; `bits` is got's file precision (16 adds half's
 * rounding, 2^-11 relative, to the tolerance; 0 or 32: none). Fills `d` (may be NULL).
 * Returns true when within tolerance. Not a check: see lg_test_check_image. */
LG_TEST_API bool lg_test_diff_images(const lg_image *got, const lg_image *want, unsigned bits,
                                     const lg_test_tol *tol, lg_test_diff *d);

/* lg_test_diff_images as a check: on failure prints "<what>: N values beyond tolerance:
 * max abs E at (x, y) channel c: got G, want W; rmse R" and counts a failed check. */
LG_TEST_API bool lg_test_check_image(lg_test *t, const lg_image *got, const lg_image *want,
                                     unsigned bits, const lg_test_tol *tol, const char *what);

/* The tolerance a value read from a file of `bits` had to live with: `tol` plus half's
 * rounding when bits == 16. */
LG_TEST_API double lg_test_tol_of(double expected, unsigned bits, double tol);

/* ---- one node on every backend --------------------------------------------------------------- */

#define LG_TEST_MAX_BACKENDS 8

/* What to run. The graph text defines the node under test and its inputs (files written to
 * the scratch folder beforehand, or nodes) and no `output` for it: the harness appends
 * `output NODE "NODE-BACKEND.exr"` and sets the backend with `--set NODE.backend=B`. */
typedef struct lg_test_backends_desc {
    const char *graph; /* graph text (required) */
    const char *node;  /* the node under test (required) */
    const char *type;  /* its type; NULL: read from "NODE = TYPE" in the graph */
    /* backends to run; NULL-terminated; NULL: every value of the type's `backend` enum
     * (`lightgraph inspect TYPE --json`), or just the default when it has none */
    const char *const *backends;
    const char *const *args;   /* extra render arguments (--size ...), NULL-terminated */
    const lg_image *reference; /* the expected output, or NULL; borrowed */
    lg_test_tol tol_reference; /* each backend against `reference` */
    lg_test_tol tol_backends;  /* each backend against the first that ran */
    const char *what;          /* label in messages (NULL: the node's name) */
    /* Bytes the node reads and writes per frame, for the bench table's GB/s (0: pixels
     * of the output x 32, an rgba32f read and write) */
    double bytes_per_frame;
    /* A backend whose device is missing here is left out of the comparison; then, when
     * nothing failed, the case ends as a skip (77) naming it, so that a run in which a
     * device silently disappeared is never a pass. true: left out, and the case goes on. */
    bool allow_missing;
    uint32_t reserved[8];
} lg_test_backends_desc;

typedef enum lg_test_run_status {
    LG_TEST_RUN_OK = 0,
    LG_TEST_RUN_NO_DEVICE, /* the device is missing here: not a failure */
    LG_TEST_RUN_FAILED,    /* the render failed or its output could not be read */
} lg_test_run_status;

/* One backend's run. */
typedef struct lg_test_run {
    char backend[32];
    lg_test_run_status status;
    lg_image image; /* its output (owned: freed by lg_test_backends_free) */
    unsigned bits;
    uint64_t runs;   /* executions of the node (frames under --bench) */
    double first_ms; /* the first execution: includes programs, kernels */
    double min_ms;   /* the fastest execution */
    double mean_ms;  /* mean of the executions after the first (first when one) */
    double gpu_ms;   /* GL timer / CL events total, when measured */
    bool gpu_measured;
    lg_test_diff vs_reference, vs_first;
    uint32_t reserved[8];
} lg_test_run;

typedef struct lg_test_backends_result {
    lg_test_run run[LG_TEST_MAX_BACKENDS];
    size_t n;
    size_t n_ok; /* runs with status LG_TEST_RUN_OK */
} lg_test_backends_result;

/* Runs desc->node on each backend (in a render of its own, under --bench with N frames and
 * --every-frame=NODE), reads its output, compares it with desc->reference and with the first
 * backend that ran, and prints a table (backend, max abs and where, RMSE, times). Every
 * failed render and every comparison beyond tolerance is a failed check. A backend whose
 * device is missing is reported and left out; the case then ends with a skip
 * (lg_test_skip) unless desc->allow_missing (or a check failed), after `res` has been
 * freed. When no backend could run, it skips in any case. `res` may be NULL; else it
 * receives the runs (free with lg_test_backends_free). `desc` need only live until the
 * call returns. Returns the number of backends that ran. */
LG_TEST_API size_t lg_test_backends(lg_test *t, const lg_test_backends_desc *desc,
                                    lg_test_backends_result *res);
/* Frees the images of `res` and zeroes it. Accepts NULL. */
LG_TEST_API void lg_test_backends_free(lg_test_backends_result *res);

#ifdef __cplusplus
}
#endif
#endif
