/*
 * tests/common/scratch.h: scratch folders for tests, header-only.
 *
 * lg_scratch_make() makes a fresh folder $LG_BUILD_ROOT/test-tmp/NAME-XXXXXX (or under
 * $TMPDIR or /tmp outside a build tree); lg_scratch_remove() deletes it with everything in
 * it. Tests keep the folder when a check failed, so that its files can be looked at.
 */
#ifndef LG_TEST_SCRATCH_H
#define LG_TEST_SCRATCH_H

#include <errno.h>
#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Fills `dir` (n bytes) with a new folder's path. Returns 0, or -1 with a message on stderr. */
static inline int lg_scratch_make(const char *name, char *dir, size_t n)
{
    const char *root = getenv("LG_BUILD_ROOT");
    char base[3000];
    if (root && *root) {
        snprintf(base, sizeof base, "%s/test-tmp", root);
    } else {
        const char *tmp = getenv("TMPDIR");
        snprintf(base, sizeof base, "%s", tmp && *tmp ? tmp : "/tmp");
    }
    if (mkdir(base, 0777) && errno != EEXIST) {
        fprintf(stderr, "cannot make %s: %s\n", base, strerror(errno));
        return -1;
    }
    snprintf(dir, n, "%s/%s-XXXXXX", base, name);
    if (!mkdtemp(dir)) {
        fprintf(stderr, "cannot make a folder like %s: %s\n", dir, strerror(errno));
        return -1;
    }
    return 0;
}

static inline int lg_scratch_remove_entry_(const char *path, const struct stat *sb, int flag,
                                           struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

/* Removes `dir` and everything in it. Returns 0, or -1 if something could not be removed. */
static inline int lg_scratch_remove(const char *dir)
{
    return nftw(dir, lg_scratch_remove_entry_, 16, FTW_DEPTH | FTW_PHYS) == 0 ? 0 : -1;
}

#endif
