/*
 * ptest: what the plugin tests share. A test makes a scratch folder, writes input images
 * and a graph file into it, runs `$LG_EXE render` on it as a user would, and reads the
 * output image back. Used by the tests in tests/plugins/ that run the host.
 *
 * Failures of the harness itself (cannot write a file, cannot start the program) abort
 * the test with a message; checks count failures and the test exits 1 if any failed.
 * The scratch folder is removed when the test passes and kept (its path printed) when
 * it fails.
 */
#ifndef LG_TESTS_PTEST_H
#define LG_TESTS_PTEST_H

#include <stdbool.h>
#include <stddef.h>

#include "lightgraph/image.h"

typedef struct ptest {
    char dir[4096];     /* the scratch folder */
    int failures;
} ptest;

#define PT_CHECK(t, cond, ...)                                                             \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond);       \
            fprintf(stderr, __VA_ARGS__);                                                  \
            fputc('\n', stderr);                                                           \
            (t)->failures++;                                                               \
        }                                                                                  \
    } while (0)

/* One case of a test program: main() holds a table of them and runs the one named on its
 * command line with pt_run_case. */
typedef struct pt_case {
    const char *name;
    void (*run)(ptest *t);
} pt_case;

/* Runs the case called `name` among cases[0 .. n): makes its scratch folder (named
 * `folder`, or the case's name when NULL), calls `setup` (may be NULL) and then the case,
 * and returns pt_finish's status. A name not in the table gets "prog: unknown case" on
 * stderr and 99. */
int pt_run_case(const char *prog, const char *name, const pt_case *cases, size_t n,
                const char *folder, void (*setup)(ptest *t));

/* Makes the scratch folder (under $LG_BUILD_ROOT/test-tmp, else $TMPDIR). */
void pt_init(ptest *t, const char *name);
/* Removes the folder if no check failed; returns the exit status (0 or 1). */
int pt_finish(ptest *t);

/* dir/rel; the string lives until the next 8 calls. */
const char *pt_path(ptest *t, const char *rel);
void pt_write_text(ptest *t, const char *rel, const char *text);
/* As float RGBA EXR, uncompressed (the size depends only on the image's size). */
void pt_write_exr(ptest *t, const char *rel, const lg_image *img);
/* Reads dir/rel; returns false (after a message) if it cannot. `bits` may be NULL: it
 * receives the file's bits per channel (16 for half EXR, 32 for float). */
bool pt_read(ptest *t, const char *rel, lg_image *img, unsigned *bits);

/* Runs `$LG_EXE render <dir/graph> args...` (args NULL-terminated) with the scratch folder
 * as the working directory. Returns the exit status (or -1 if it died); *err receives what
 * the program printed, stdout and stderr together (malloc'd, may be NULL). The command and
 * its output are echoed on a failure, or always with PTEST_VERBOSE set. */
int pt_render(ptest *t, const char *graph, const char *const *args, char **err);

/* Points the host at test plugins: sets LIGHTGRAPH_PLUGIN_PATH to `path` (folders joined
 * with ':'), and with `t` also LIGHTGRAPH_CACHE_DIR to a folder of t's scratch folder, so
 * that a case starts with an empty cache. Fails (exit 1) when `path` is empty (the test
 * plugins' folder was not defined by the build). */
void pt_use_plugins(ptest *t, const char *path);

/* Exits 77 (skip) when the backend's device cannot be made here: "gl" or "cl"; "cpu"
 * always works. */
void pt_require_backend(const char *backend);

/* The tolerance a value written to `path` had to live with: the file's precision (a half
 * EXR rounds to 11 significant bits) plus `tol`. */
double pt_tol(double expected, unsigned bits, double tol);

/* An asset from $LG_SOURCE_ROOT/assets, or NULL if it is not there. */
const char *pt_asset(const char *rel);

#endif
