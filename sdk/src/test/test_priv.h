/* liblightgraph-test's private state, shared by its .c files. */
#ifndef LG_TEST_PRIV_H
#define LG_TEST_PRIV_H

#include <setjmp.h>

#include "lightgraph/test.h"

#ifndef LG_TEST_DEFAULT_EXE
#error "LG_TEST_DEFAULT_EXE (the installed lightgraph program) must be defined by the build"
#endif
#ifndef LG_TEST_EXE_FROM_LIBDIR
#error                                                                                             \
    "LG_TEST_EXE_FROM_LIBDIR (the program relative to <libdir>; may be \"\") must be defined by the build"
#endif
#ifndef LG_TEST_LIBDIR
#error "LG_TEST_LIBDIR (the libdir option, relative to the prefix) must be defined by the build"
#endif

struct lg_test {
    char dir[4096]; /* the scratch folder */
    int failures;
    char ring[8][4200]; /* lg_test_path's strings */
    int next;
    char **args; /* the case's arguments after its name */
    int n_args;
    uint32_t bench_frames; /* 0, or N under --bench=N */
    bool can_jump;         /* inside run_one: lg_test_skip returns there */
    jmp_buf skip_jump;
    lg_test *next_live; /* test.c's list of cases whose folder exists */
};

/* Prints "lightgraph-test: ..." and exits 99. */
LG_TEST_NORETURN void lg_test_die_(const char *fmt, ...) LG_TEST_PRINTF(1, 2);

/* A failed check found by the harness (no file:line of the caller to give):
 * "lightgraph-test: check failed: ...". */
void lg_test_failf_(lg_test *t, const char *fmt, ...) LG_TEST_PRINTF(2, 3);

/* Runs argv (argv[0] a path) in `cwd` (NULL: here), stdout and stderr into *out (malloc'd,
 * when out is not NULL). Returns the exit status, -1 on a signal; echoes the command and
 * its output when the status is not 0 or LG_TEST_VERBOSE is set. */
int lg_test_spawn_(const char *const *argv, const char *cwd, char **out);

#endif
