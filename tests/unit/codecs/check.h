/*
 * tests/unit/codecs/check.h: the few helpers the codec tests share.
 */
#ifndef LG_TEST_CHECK_H
#define LG_TEST_CHECK_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int check_failures;

#define CHECK(cond)                                                                         \
    do {                                                                                    \
        if (!(cond)) {                                                                      \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);       \
            check_failures++;                                                               \
        }                                                                                   \
    } while (0)

#define CHECKF(cond, ...)                                                                   \
    do {                                                                                    \
        if (!(cond)) {                                                                      \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond);       \
            fprintf(stderr, __VA_ARGS__);                                                   \
            fputc('\n', stderr);                                                            \
            check_failures++;                                                               \
        }                                                                                   \
    } while (0)

/* Exit status for meson: 0 pass, 1 fail. */
static inline int check_report(const char *name)
{
    if (check_failures) {
        fprintf(stderr, "%s: %d check(s) failed\n", name, check_failures);
        return 1;
    }
    fprintf(stderr, "%s: all checks passed\n", name);
    return 0;
}

/* A fresh scratch directory under the build tree (or /tmp), removed by the caller with
 * rm_scratch. Returns a static buffer. */
#include <unistd.h>
static inline const char *make_scratch(const char *tag)
{
    static char dir[4096];
    const char *root = getenv("LG_BUILD_ROOT");
    snprintf(dir, sizeof dir, "%s/%s.XXXXXX", root && root[0] ? root : "/tmp", tag);
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        exit(1);
    }
    return dir;
}

/* Path of a file in the source tree's assets folder; exits 77 (skip) without LG_SOURCE_ROOT. */
static inline const char *asset_path(const char *rel, char *buf, size_t n)
{
    const char *root = getenv("LG_SOURCE_ROOT");
    if (!root || !root[0]) {
        fprintf(stderr, "LG_SOURCE_ROOT is not set\n");
        exit(77);
    }
    snprintf(buf, n, "%s/assets/%s", root, rel);
    return buf;
}

#endif
