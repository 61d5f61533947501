/*
 * tests/common/check.h: checks for the test programs, and meson's exit codes.
 *
 *     CHECK(cond);                   on failure: "file:line: check failed: cond"
 *     CHECKF(cond, fmt, ...);        the same, then ": " and the printf-style message
 *
 * on stderr; the failure is counted and the test goes on, so that one run shows every
 * failing check. main() ends with `return check_report("name");` (0 when no check failed,
 * 1 otherwise), or, when the test cannot run here (no GL or CL device, say), with
 * `return check_skip("name");` (CHECK_SKIP, 77, which meson counts as a skip, unless a
 * check has already failed: a skip never hides a failure).
 *
 * The count is per translation unit (a static in this header): a test's checks and its
 * check_report belong in the same .c file.
 */
#ifndef LG_TEST_COMMON_CHECK_H
#define LG_TEST_COMMON_CHECK_H

#include <stdio.h>

#define CHECK_SKIP 77

static int check_failures;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);               \
            check_failures++;                                                                      \
        }                                                                                          \
    } while (0)

#define CHECKF(cond, ...)                                                                          \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond);               \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fputc('\n', stderr);                                                                   \
            check_failures++;                                                                      \
        }                                                                                          \
    } while (0)

/* main()'s exit status: 1 if a check failed, else 0; says which on stderr. */
static inline int check_report(const char *name)
{
    if (check_failures) {
        fprintf(stderr, "%s: %d check(s) failed\n", name, check_failures);
        return 1;
    }
    fprintf(stderr, "%s: all checks passed\n", name);
    return 0;
}

/* main()'s exit status for a test that cannot run here: CHECK_SKIP, or 1 (with
 * check_report's message) if a check has already failed. */
static inline int check_skip(const char *name)
{
    if (check_failures)
        return check_report(name);
    fprintf(stderr, "%s: skipped\n", name);
    return CHECK_SKIP;
}

#endif
