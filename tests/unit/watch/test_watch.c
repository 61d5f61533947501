/*
 * host/viewer/watch.c: files watched through inotify, reported after a quiet period.
 *
 * Most checks drive lg_watch_poll with a made-up clock (the module only knows the `now` it
 * is given, and inotify queues an event before the system call that caused it returns), so
 * that "not before the quiet period, once after it" is exact on a loaded machine:
 *
 *   in_place      a file written in place
 *   renamed       saved as a temporary renamed over it (the temporary is not reported)
 *   recreated     deleted, then created again later (the quiet period restarts)
 *   created       created after the watch started
 *   steps         written in steps: reported once the steps stop
 *   open_writer   kept open by its writer: held until closed, or for 10 quiet periods;
 *                 a symbolic link is complete when it appears
 *   only_listed   two files in a directory, one registered; several reported sorted, once
 *   tree          a suffix filter, a subdirectory made after the watch started (and one
 *                 made with its files before we could watch it), tags OR'ed
 *   replace       replacing a tag's files or trees drops the old ones; n == 0 drops all
 *   missing       a missing directory is an error naming it; the old registration stays
 *   dir_back      a watched file's directory removed and made again
 *   overflow      an inotify queue overflow reports every registered file
 *   real_clock    the real thing with lg_mono_now(): a 0.1 s quiet period, up to 10 s
 */
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "common/check.h"
#include "base/util.h"
#include "viewer/watch.h"

static char tmp[256];
static double T = 1000.0; /* the made-up clock; each check moves it on */
#define QUIET 0.2

static char *at(const char *rel)
{
    return lg_path_join(tmp, rel);
}

static void write_at(const char *rel, const char *text)
{
    char *p = at(rel);
    int fd = open(p, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    CHECKF(fd >= 0, "%s: %s", p, strerror(errno));
    if (fd >= 0) {
        CHECK(write(fd, text, strlen(text)) == (ssize_t)strlen(text));
        close(fd);
    }
    free(p);
}

static void append_at(const char *rel, const char *text)
{
    char *p = at(rel);
    int fd = open(p, O_WRONLY | O_APPEND);
    CHECKF(fd >= 0, "%s: %s", p, strerror(errno));
    if (fd >= 0) {
        CHECK(write(fd, text, strlen(text)) == (ssize_t)strlen(text));
        close(fd);
    }
    free(p);
}

static void rename_at(const char *from, const char *to)
{
    char *a = at(from), *b = at(to);
    CHECKF(rename(a, b) == 0, "%s -> %s: %s", a, b, strerror(errno));
    free(a);
    free(b);
}

static void unlink_at(const char *rel)
{
    char *p = at(rel);
    CHECKF(unlink(p) == 0, "%s: %s", p, strerror(errno));
    free(p);
}

static void mkdir_at(const char *rel)
{
    char *p = at(rel);
    CHECKF(mkdir(p, 0755) == 0, "%s: %s", p, strerror(errno));
    free(p);
}

/* Polls at T + dt; returns the count, the changes in *c (caller frees). */
static int poll_at(lg_watch *w, double dt, lg_watch_change **c)
{
    char err[512] = "";
    int n = lg_watch_poll(w, T + dt, QUIET, c, err, sizeof err);
    CHECKF(n >= 0, "poll: %s", err);
    CHECK(n > 0 ? *c != NULL : *c == NULL);
    return n;
}

/* Polls at T + dt and expects exactly the files `rels` (sorted) with tags `tags`. */
static void expect_at(lg_watch *w, double dt, const char *what, int n_want, const char *const *rels,
                      const int *tags)
{
    lg_watch_change *c;
    int n = poll_at(w, dt, &c);
    CHECKF(n == n_want, "%s at +%.2f s: %d changes, want %d", what, dt, n, n_want);
    for (int i = 0; i < n && i < n_want; i++) {
        char *want = at(rels[i]);
        CHECKF(strcmp(c[i].path, want) == 0, "%s: change %d is %s, want %s", what, i, c[i].path,
               want);
        CHECKF(c[i].tag == tags[i], "%s: %s has tag %d, want %d", what, c[i].path, c[i].tag,
               tags[i]);
        free(want);
    }
    for (int i = n_want; i < n; i++)
        fprintf(stderr, "%s: unexpected change %s (tag %d)\n", what, c[i].path, c[i].tag);
    lg_watch_changes_free(c, n);
}

static void expect_none(lg_watch *w, double dt, const char *what)
{
    expect_at(w, dt, what, 0, NULL, NULL);
}

/* A poll at the time of the writes just made: their events are read (and stamped) now,
 * nothing is reported yet. */
static void seen(lg_watch *w)
{
    expect_none(w, 0, "read at the write");
}

static void expect_one(lg_watch *w, double dt, const char *what, const char *rel, int tag)
{
    expect_at(w, dt, what, 1, &rel, &tag);
}

static lg_watch *open_watch(void)
{
    char err[512] = "";
    lg_watch *w = NULL;
    CHECKF(lg_watch_open(&w, err, sizeof err) == 0, "open: %s", err);
    CHECK(w == NULL || lg_watch_fd(w) >= 0);
    return w;
}

static void watch_files(lg_watch *w, int tag, uint32_t n, const char *const *rels)
{
    char *abs[8] = { 0 };
    for (uint32_t i = 0; i < n; i++)
        abs[i] = at(rels[i]);
    char err[512] = "";
    CHECKF(lg_watch_files(w, tag, (const char *const *)abs, n, err, sizeof err) == 0,
           "watch files: %s", err);
    for (uint32_t i = 0; i < n; i++)
        free(abs[i]);
}

/* ---- single files ---------------------------------------------------------------------------- */

static void test_single_files(void)
{
    mkdir_at("single");
    write_at("single/a.lgraph", "one");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *files[] = { "single/a.lgraph", "single/later.lgraph" };
    watch_files(w, LG_WATCH_GRAPH, 2, files);
    expect_none(w, 0, "nothing written yet");

    /* in place */
    T += 10;
    write_at("single/a.lgraph", "two");
    expect_none(w, 0, "in_place: at the write");
    expect_none(w, 0.1, "in_place: within the quiet period");
    expect_one(w, 0.25, "in_place: after it", "single/a.lgraph", LG_WATCH_GRAPH);
    expect_none(w, 1.0, "in_place: reported once");

    /* an editor's save: a temporary renamed over the file */
    T += 10;
    write_at("single/a.lgraph.tmp", "three");
    rename_at("single/a.lgraph.tmp", "single/a.lgraph");
    seen(w);
    expect_none(w, 0.1, "renamed: within the quiet period");
    expect_one(w, 0.25, "renamed: after it", "single/a.lgraph", LG_WATCH_GRAPH);
    expect_none(w, 1.0, "renamed: reported once");

    /* deleted, then created again 0.1 s later: the quiet period starts again */
    T += 10;
    unlink_at("single/a.lgraph");
    expect_none(w, 0, "recreated: at the delete");
    write_at("single/a.lgraph", "four");
    expect_none(w, 0.1, "recreated: at the create");
    expect_none(w, 0.25, "recreated: 0.15 s after the create");
    expect_one(w, 0.31, "recreated: after it", "single/a.lgraph", LG_WATCH_GRAPH);
    expect_none(w, 1.0, "recreated: reported once");

    /* a registered file that did not exist when the watch started */
    T += 10;
    write_at("single/later.lgraph", "new");
    seen(w);
    expect_none(w, 0.1, "created: within the quiet period");
    expect_one(w, 0.25, "created: after it", "single/later.lgraph", LG_WATCH_GRAPH);
    expect_none(w, 1.0, "created: reported once");

    /* written in steps 0.15 s apart: nothing until 0.2 s after the last step */
    T += 10;
    write_at("single/a.lgraph", "step 1");
    expect_none(w, 0, "steps: first");
    append_at("single/a.lgraph", " step 2");
    expect_none(w, 0.15, "steps: second");
    append_at("single/a.lgraph", " step 3");
    expect_none(w, 0.30, "steps: third");
    expect_none(w, 0.45, "steps: 0.15 s after the last");
    expect_one(w, 0.51, "steps: after it", "single/a.lgraph", LG_WATCH_GRAPH);

    /* kept open by its writer (a linker between bursts): held until the close, however
     * long the pause ... */
    T += 10;
    char *a = at("single/a.lgraph");
    int fd = open(a, O_WRONLY | O_TRUNC);
    CHECK(fd >= 0 && write(fd, "burst 1", 7) == 7);
    seen(w);
    expect_none(w, 0.25, "open_writer: quiet but open");
    CHECK(fd < 0 || write(fd, "burst 2", 7) == 7);
    expect_none(w, 1.0, "open_writer: second burst");
    expect_none(w, 1.5, "open_writer: quiet but open again");
    if (fd >= 0)
        close(fd);
    expect_none(w, 1.6, "open_writer: closed");
    expect_one(w, 1.85, "open_writer: after its close", "single/a.lgraph", LG_WATCH_GRAPH);
    /* ... or until 10 quiet periods passed without one */
    T += 10;
    fd = open(a, O_WRONLY | O_APPEND);
    CHECK(fd >= 0 && write(fd, "more", 4) == 4);
    seen(w);
    expect_none(w, 1.9, "open_writer: never closed, 1.9 s");
    expect_one(w, 2.05, "open_writer: never closed, 2 s", "single/a.lgraph", LG_WATCH_GRAPH);
    if (fd >= 0)
        close(fd);
    T += 10;
    seen(w);
    expect_one(w, 0.25, "open_writer: the late close", "single/a.lgraph", LG_WATCH_GRAPH);
    free(a);

    /* a symbolic link appearing is complete at once (no close follows) */
    T += 10;
    char *target = at("single/a.lgraph"), *link = at("single/link.lgraph");
    const char *with_link[] = { "single/link.lgraph" };
    watch_files(w, LG_WATCH_PLUGIN, 1, with_link);
    CHECK(symlink(target, link) == 0);
    seen(w);
    expect_one(w, 0.25, "symlink", "single/link.lgraph", LG_WATCH_PLUGIN);
    free(target);
    free(link);

    lg_watch_close(&w);
    CHECK(w == NULL);
    lg_watch_close(&w); /* NULL is fine */
}

/* ---- which files ----------------------------------------------------------------------------- */

static void test_only_listed(void)
{
    mkdir_at("two");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *one[] = { "two/a.txt" };
    watch_files(w, LG_WATCH_GRAPH, 1, one);
    T += 10;
    write_at("two/a.txt", "a");
    write_at("two/b.txt", "b");
    seen(w);
    expect_one(w, 0.25, "only_listed", "two/a.txt", LG_WATCH_GRAPH);

    /* several files, written in reverse order, many events each: sorted, once each */
    const char *three[] = { "two/c.txt", "two/a.txt", "two/b.txt" };
    watch_files(w, LG_WATCH_GRAPH, 3, three);
    T += 10;
    for (int k = 0; k < 3; k++) {
        write_at("two/c.txt", "c");
        append_at("two/c.txt", "c");
        write_at("two/b.txt", "b");
        write_at("two/a.txt", "a");
    }
    const char *want[] = { "two/a.txt", "two/b.txt", "two/c.txt" };
    const int tags[] = { LG_WATCH_GRAPH, LG_WATCH_GRAPH, LG_WATCH_GRAPH };
    seen(w);
    expect_at(w, 0.25, "sorted", 3, want, tags);
    expect_none(w, 1.0, "sorted: once");
    lg_watch_close(&w);
}

static void test_tree(void)
{
    mkdir_at("tree");
    mkdir_at("tree/old");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *suffixes[] = { ".glsl", ".cl" };
    char *root = at("tree");
    char err[512] = "";
    CHECKF(lg_watch_tree(w, LG_WATCH_SHADER, root, suffixes, 2, true, err, sizeof err) == 0,
           "tree: %s", err);

    /* the filter */
    T += 10;
    write_at("tree/x.glsl", "x");
    write_at("tree/x.txt", "not a shader");
    write_at("tree/x.glsl.swp", "an editor's swap file");
    write_at("tree/old/k.cl", "k");
    const char *want1[] = { "tree/old/k.cl", "tree/x.glsl" };
    const int tags1[] = { LG_WATCH_SHADER, LG_WATCH_SHADER };
    seen(w);
    expect_at(w, 0.25, "tree: suffixes", 2, want1, tags1);

    /* a subdirectory made after the watch started, then a file in it */
    T += 10;
    mkdir_at("tree/sub");
    expect_none(w, 0, "tree: the new directory itself");
    write_at("tree/sub/y.glsl", "y");
    seen(w);
    expect_one(w, 0.25, "tree: a file in a new subdirectory", "tree/sub/y.glsl", LG_WATCH_SHADER);
    /* ... and one made with its files before anybody polled: found when it is watched */
    T += 10;
    mkdir_at("tree/fast");
    mkdir_at("tree/fast/deeper");
    write_at("tree/fast/deeper/z.cl", "z");
    expect_none(w, 0, "tree: fast subdirectory, at once");
    expect_one(w, 0.25, "tree: fast subdirectory", "tree/fast/deeper/z.cl", LG_WATCH_SHADER);
    T += 10;
    write_at("tree/fast/deeper/z.cl", "z again");
    seen(w);
    expect_one(w, 0.25, "tree: fast subdirectory, watched", "tree/fast/deeper/z.cl",
               LG_WATCH_SHADER);

    /* a file both listed and in the tree: one change, the tags OR'ed */
    const char *listed[] = { "tree/x.glsl" };
    watch_files(w, LG_WATCH_GRAPH, 1, listed);
    T += 10;
    write_at("tree/x.glsl", "x again");
    seen(w);
    expect_one(w, 0.25, "tree: two tags", "tree/x.glsl", LG_WATCH_GRAPH | LG_WATCH_SHADER);

    /* a second tree added (replace false) under another tag, any name */
    mkdir_at("plugins");
    char *plugins = at("plugins");
    CHECKF(lg_watch_tree(w, LG_WATCH_PLUGIN, plugins, NULL, 0, false, err, sizeof err) == 0,
           "tree: %s", err);
    T += 10;
    write_at("plugins/libfoo.so", "ELF");
    write_at("tree/sub/y.glsl", "y again");
    const char *want2[] = { "plugins/libfoo.so", "tree/sub/y.glsl" };
    const int tags2[] = { LG_WATCH_PLUGIN, LG_WATCH_SHADER };
    seen(w);
    expect_at(w, 0.25, "tree: two trees", 2, want2, tags2);
    free(plugins);
    free(root);
    lg_watch_close(&w);
}

static void test_replace(void)
{
    mkdir_at("rep");
    mkdir_at("rep/d1");
    mkdir_at("rep/d2");
    mkdir_at("rep/t1");
    mkdir_at("rep/t2");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *first[] = { "rep/d1/a", "rep/d1/b" };
    watch_files(w, LG_WATCH_GRAPH, 2, first);
    const char *other[] = { "rep/d2/p.so" };
    watch_files(w, LG_WATCH_PLUGIN, 1, other);
    const char *second[] = { "rep/d2/c" };
    watch_files(w, LG_WATCH_GRAPH, 1, second); /* replaces a and b, keeps the plugin file */
    T += 10;
    write_at("rep/d1/a", "a");
    write_at("rep/d1/b", "b");
    write_at("rep/d2/c", "c");
    write_at("rep/d2/p.so", "p");
    const char *want[] = { "rep/d2/c", "rep/d2/p.so" };
    const int tags[] = { LG_WATCH_GRAPH, LG_WATCH_PLUGIN };
    seen(w);
    expect_at(w, 0.25, "replace: files", 2, want, tags);

    /* dropped while an event was pending: not reported */
    T += 10;
    write_at("rep/d2/c", "c again");
    seen(w);
    watch_files(w, LG_WATCH_GRAPH, 0, NULL);
    expect_none(w, 0.25, "replace: n == 0 drops, pending included");

    char *t1 = at("rep/t1"), *t2 = at("rep/t2");
    char err[512] = "";
    CHECK(lg_watch_tree(w, LG_WATCH_SHADER, t1, NULL, 0, true, err, sizeof err) == 0);
    CHECK(lg_watch_tree(w, LG_WATCH_SHADER, t2, NULL, 0, true, err, sizeof err) == 0);
    T += 10;
    write_at("rep/t1/old.glsl", "old");
    write_at("rep/t2/new.glsl", "new");
    seen(w);
    expect_one(w, 0.25, "replace: trees", "rep/t2/new.glsl", LG_WATCH_SHADER);
    free(t1);
    free(t2);
    lg_watch_close(&w);
}

/* ---- errors and hard cases ------------------------------------------------------------------- */

static void test_missing(void)
{
    mkdir_at("miss");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *good[] = { "miss/f" };
    watch_files(w, LG_WATCH_GRAPH, 1, good);

    char *bad = at("miss/nodir/f.lgraph");
    char *bad_dir = at("miss/nodir");
    const char *paths[] = { bad };
    char err[512] = "";
    CHECK(lg_watch_files(w, LG_WATCH_GRAPH, paths, 1, err, sizeof err) == -1);
    CHECKF(strstr(err, bad_dir) && strstr(err, "no such directory"), "err: %s", err);
    err[0] = 0;
    CHECK(lg_watch_tree(w, LG_WATCH_SHADER, bad_dir, NULL, 0, true, err, sizeof err) == -1);
    CHECKF(strstr(err, bad_dir) && strstr(err, "no such directory"), "err: %s", err);
    write_at("miss/plain", "a file, not a directory");
    char *plain = at("miss/plain");
    err[0] = 0;
    CHECK(lg_watch_tree(w, LG_WATCH_SHADER, plain, NULL, 0, true, err, sizeof err) == -1);
    CHECKF(strstr(err, plain) && strstr(err, "not a directory"), "err: %s", err);

    /* the registration before the failed calls stays */
    T += 10;
    write_at("miss/f", "f");
    seen(w);
    expect_one(w, 0.25, "missing: old registration kept", "miss/f", LG_WATCH_GRAPH);
    free(plain);
    free(bad);
    free(bad_dir);
    lg_watch_close(&w);
}

static void test_dir_back(void)
{
    mkdir_at("gone");
    mkdir_at("gone/d");
    write_at("gone/d/f", "f");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *files[] = { "gone/d/f" };
    watch_files(w, LG_WATCH_GRAPH, 1, files);
    T += 10;
    unlink_at("gone/d/f");
    char *d = at("gone/d");
    CHECK(rmdir(d) == 0);
    expect_none(w, 0, "dir_back: removed");
    mkdir_at("gone/d");
    write_at("gone/d/f", "f again"); /* before the directory is watched again */
    /* found within a few polls 0.3 s apart (it is looked for every 0.25 s) */
    int n = 0;
    lg_watch_change *c = NULL;
    for (int k = 1; k <= 5 && n == 0; k++)
        n = poll_at(w, 0.3 * k, &c);
    CHECKF(n == 1, "dir_back: %d changes", n);
    lg_watch_changes_free(c, n);
    /* and watched again */
    T += 10;
    write_at("gone/d/f", "f once more");
    seen(w);
    expect_one(w, 0.25, "dir_back: watched again", "gone/d/f", LG_WATCH_GRAPH);
    free(d);
    lg_watch_close(&w);
}

static void test_overflow(void)
{
    long queue = 16384;
    FILE *f = fopen("/proc/sys/fs/inotify/max_queued_events", "r");
    if (f) {
        if (fscanf(f, "%ld", &queue) != 1)
            queue = 16384;
        fclose(f);
    }
    if (queue > 200000) {
        fprintf(stderr, "overflow: max_queued_events %ld is too large to overflow here\n", queue);
        return; /* not a skip of the whole test: the other checks stand */
    }
    mkdir_at("flood");
    write_at("flood/keep.txt", "never touched");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *files[] = { "flood/keep.txt" };
    watch_files(w, LG_WATCH_GRAPH, 1, files);
    char *flood = at("flood");
    const char *suffixes[] = { ".glsl" };
    char err[512] = "";
    CHECK(lg_watch_tree(w, LG_WATCH_SHADER, flood, suffixes, 1, true, err, sizeof err) == 0);
    write_at("flood/s.glsl", "s");
    T += 10;
    seen(w);
    expect_one(w, 0.25, "overflow: before", "flood/s.glsl", LG_WATCH_SHADER);
    /* one IN_MODIFY per write, alternating between two files no registration matches (the
     * kernel merges an event only with an identical one just before it) */
    char *pa = at("flood/noise1"), *pb = at("flood/noise2");
    int fa = open(pa, O_WRONLY | O_CREAT, 0644), fb = open(pb, O_WRONLY | O_CREAT, 0644);
    CHECK(fa >= 0 && fb >= 0);
    for (long i = 0; fa >= 0 && fb >= 0 && i < queue / 2 + 100; i++)
        CHECK(write(fa, "x", 1) == 1 && write(fb, "y", 1) == 1);
    close(fa);
    close(fb);
    free(pa);
    free(pb);
    T += 10;
    const char *want[] = { "flood/keep.txt", "flood/s.glsl" };
    const int tags[] = { LG_WATCH_GRAPH, LG_WATCH_SHADER };
    seen(w);
    expect_at(w, 0.25, "overflow: every registered file", 2, want, tags);
    expect_none(w, 1.0, "overflow: once");
    T += 10;
    write_at("flood/s.glsl", "still watched");
    seen(w);
    expect_one(w, 0.25, "overflow: still watching", "flood/s.glsl", LG_WATCH_SHADER);
    free(flood);
    lg_watch_close(&w);
}

static void test_real_clock(void)
{
    mkdir_at("real");
    lg_watch *w = open_watch();
    if (!w)
        return;
    const char *files[] = { "real/g.lgraph" };
    watch_files(w, LG_WATCH_GRAPH, 1, files);
    char err[512] = "";
    lg_watch_change *c = NULL;
    CHECK(lg_watch_poll(w, lg_mono_now(), 0.1, &c, err, sizeof err) == 0);
    write_at("real/g.lgraph.tmp", "saved");
    rename_at("real/g.lgraph.tmp", "real/g.lgraph");
    double t0 = lg_mono_now(), t1 = t0;
    int n = 0;
    while (n == 0 && t1 - t0 < 10) {
        t1 = lg_mono_now();
        n = lg_watch_poll(w, t1, 0.1, &c, err, sizeof err);
        if (n == 0)
            nanosleep(&(struct timespec){ 0, 10 * 1000 * 1000 }, NULL);
    }
    CHECKF(n == 1, "real_clock: %d changes after %.2f s (%s)", n, t1 - t0, err);
    CHECKF(t1 - t0 >= 0.1, "real_clock: reported after %.3f s, before the quiet period", t1 - t0);
    char *want = at("real/g.lgraph");
    CHECK(n < 1 || strcmp(c[0].path, want) == 0);
    free(want);
    lg_watch_changes_free(c, n);
    lg_watch_close(&w);
}

/* rm -r of the temporary directory */
static void remove_tree(const char *dir)
{
    char *cmd = lg_xasprintf("rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    free(cmd);
}

int main(void)
{
    const char *base = getenv("TMPDIR");
    snprintf(tmp, sizeof tmp, "%s/lg-watch-XXXXXX", base && *base ? base : "/tmp");
    if (!mkdtemp(tmp)) {
        fprintf(stderr, "mkdtemp %s: %s\n", tmp, strerror(errno));
        return 1;
    }
    test_single_files();
    test_only_listed();
    test_tree();
    test_replace();
    test_missing();
    test_dir_back();
    test_overflow();
    test_real_clock();
    remove_tree(tmp);
    return check_report("watch");
}
