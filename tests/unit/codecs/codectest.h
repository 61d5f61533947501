/*
 * tests/unit/codecs/codectest.h: what the codec tests share besides the checks
 * (tests/common/check.h): a scratch directory, and paths of the source tree's assets.
 */
#ifndef LG_CODECTEST_H
#define LG_CODECTEST_H

#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "common/check.h"
#include "common/scratch.h"

/* A fresh scratch directory (tests/common/scratch.h). Returns a static buffer; exits 1 if it
 * cannot be made. */
static inline const char *make_scratch(const char *tag)
{
    static char dir[4096];
    if (lg_scratch_make(tag, dir, sizeof dir))
        exit(1);
    return dir;
}

/* The end of main() for a test with a scratch directory: removes the directory and all in
 * it if every check passed (a failed test leaves it to look at), then returns
 * check_report(name). */
static inline int check_report_scratch(const char *name, const char *scratch)
{
    if (!check_failures && lg_scratch_remove(scratch) != 0)
        fprintf(stderr, "could not remove %s\n", scratch);
    return check_report(name);
}

/* Path of a file in the source tree's assets folder. Without LG_SOURCE_ROOT (set by meson
 * test) the test fails: a repository file is never a reason to skip. */
static inline const char *asset_path(const char *rel, char *buf, size_t n)
{
    const char *root = getenv("LG_SOURCE_ROOT");
    if (!root || !root[0]) {
        fprintf(stderr,
                "FAIL: LG_SOURCE_ROOT is not set (run through meson test): "
                "assets/%s cannot be found\n",
                rel);
        exit(1);
    }
    snprintf(buf, n, "%s/assets/%s", root, rel);
    return buf;
}

#endif
