/*
 * Watching files through inotify (watch.h). One inotify watch per directory, shared by
 * every registration that needs it; events are matched to registrations by path when read,
 * so that replacing a registration is only a matter of lists and a watch re-synchronisation.
 */
#include "viewer/watch.h"

#include "base/util.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

/* IN_MODIFY besides the events watch.h promises: a file written over a long time without
 * closing (a linker, a slow copy) keeps postponing its report instead of being reported
 * half-written when its writer pauses longer than the quiet period between open and close. */
#define WATCH_MASK                                                                                 \
    (IN_CLOSE_WRITE | IN_MODIFY | IN_MOVED_TO | IN_MOVED_FROM | IN_CREATE | IN_DELETE |            \
     IN_ATTRIB | IN_ONLYDIR | IN_EXCL_UNLINK)

/* A file still open for writing is reported once it has been quiet for this many quiet
 * periods even without its close: a writer that keeps it open for good (a log, a database)
 * or a hard link made with link() (created, never closed) must not hide it forever. */
#define WATCH_WRITING_HOLD 10.0

/* How often a vanished directory is looked for again, in seconds of lg_watch_poll's now. */
#define WATCH_RETRY_S 0.25

/* Subdirectory depth followed in a tree: a bound against symlink-free but absurd trees. */
#define WATCH_MAX_DEPTH 32

typedef struct wfile {
    int tag;
    char *path; /* absolute, normalised */
    char *dir;  /* its directory */
} wfile;

typedef struct wtree {
    int tag;
    char *root; /* absolute, normalised, no trailing slash */
    char **suffixes;
    uint32_t n_suffixes;
} wtree;

typedef struct wdir {
    char *path;
    int wd;        /* -1: vanished, looked for again at retry_at */
    bool required; /* a registered file's directory or a tree's root: kept while it is
                    * missing; other (tree) directories are forgotten when they go */
    double retry_at;
} wdir;

typedef struct wpending {
    char *path;
    int tags;
    double last;  /* the now of the poll that read its last event */
    bool writing; /* its last event says a writer has it open (created as a regular
                   * file, or modified) and no close has been seen since */
} wpending;

struct lg_watch {
    int fd;
    wfile *files;
    uint32_t n_files, cap_files;
    wtree *trees;
    uint32_t n_trees, cap_trees;
    wdir *dirs;
    uint32_t n_dirs, cap_dirs;
    wpending *pending;
    uint32_t n_pending, cap_pending;
};

#define GROW(arr, n, cap)                                                                          \
    do {                                                                                           \
        if ((n) == (cap)) {                                                                        \
            (cap) = (cap) ? 2 * (cap) : 8;                                                         \
            (arr) = lg_xrealloc((arr), (size_t)(cap) * sizeof *(arr));                             \
        }                                                                                          \
    } while (0)

/* ---- paths and matching ---------------------------------------------------------------------- */

/* Whether `path` is `dir` or lies below it. */
static bool path_within(const char *path, const char *dir)
{
    size_t n = strlen(dir);
    if (strncmp(path, dir, n) != 0)
        return false;
    if (n == 1 && dir[0] == '/')
        return true;
    return path[n] == '\0' || path[n] == '/';
}

static const char *path_base(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

static bool tree_matches(const wtree *t, const char *path)
{
    if (!path_within(path, t->root) || strcmp(path, t->root) == 0)
        return false;
    if (t->n_suffixes == 0)
        return true;
    const char *base = path_base(path);
    size_t bn = strlen(base);
    for (uint32_t i = 0; i < t->n_suffixes; i++) {
        size_t sn = strlen(t->suffixes[i]);
        if (bn >= sn && strcmp(base + bn - sn, t->suffixes[i]) == 0)
            return true;
    }
    return false;
}

/* The tags a file at `path` is registered with, as a listed file and through trees (the
 * latter only for what is not a directory). */
static int tags_for(const lg_watch *w, const char *path, bool is_dir)
{
    int tags = 0;
    for (uint32_t i = 0; i < w->n_files; i++)
        if (strcmp(w->files[i].path, path) == 0)
            tags |= w->files[i].tag;
    if (!is_dir)
        for (uint32_t i = 0; i < w->n_trees; i++)
            if (tree_matches(&w->trees[i], path))
                tags |= w->trees[i].tag;
    return tags;
}

static bool in_some_tree(const lg_watch *w, const char *dir)
{
    for (uint32_t i = 0; i < w->n_trees; i++)
        if (path_within(dir, w->trees[i].root))
            return true;
    return false;
}

/* Whether an event with `mask` on `path` leaves it open for writing: a linker creates the
 * .so, writes it in bursts that may pause longer than any quiet period on a loaded machine,
 * and only its close says that it is complete. `mask` 0 (not an event: a scan, an
 * overflow) says nothing is known to be writing. */
static bool still_writing(const char *path, uint32_t mask, bool before)
{
    if (mask & (IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_DELETE))
        return false;
    if (mask & IN_MODIFY)
        return true;
    if ((mask & IN_CREATE) && !(mask & IN_ISDIR)) {
        /* open(O_CREAT) makes a regular file and a close follows; a symbolic link (meson's
         * libfoo.so -> libfoo.so.1) is complete when it appears */
        struct stat st;
        return lstat(path, &st) == 0 && S_ISREG(st.st_mode);
    }
    return mask ? before : false; /* IN_ATTRIB: as it was */
}

static void mark(lg_watch *w, const char *path, int tags, uint32_t mask, double now)
{
    if (!tags)
        return;
    for (uint32_t i = 0; i < w->n_pending; i++)
        if (strcmp(w->pending[i].path, path) == 0) {
            w->pending[i].tags |= tags;
            w->pending[i].last = now;
            w->pending[i].writing = still_writing(path, mask, w->pending[i].writing);
            return;
        }
    GROW(w->pending, w->n_pending, w->cap_pending);
    w->pending[w->n_pending++] = (wpending){ lg_xstrdup(path), tags, now,
                                             still_writing(path, mask, false) };
}

/* ---- directory watches ----------------------------------------------------------------------- */

static int dir_find(const lg_watch *w, const char *path)
{
    for (uint32_t i = 0; i < w->n_dirs; i++)
        if (strcmp(w->dirs[i].path, path) == 0)
            return (int)i;
    return -1;
}

static bool wd_shared(const lg_watch *w, int wd, uint32_t except)
{
    for (uint32_t i = 0; i < w->n_dirs; i++)
        if (i != except && w->dirs[i].wd == wd)
            return true;
    return false;
}

/* Drops dirs[i], removing its watch unless another entry shares it (one directory reached
 * by two paths gets one watch descriptor from the kernel). */
static void dir_remove(lg_watch *w, uint32_t i)
{
    if (w->dirs[i].wd >= 0 && !wd_shared(w, w->dirs[i].wd, i))
        inotify_rm_watch(w->fd, w->dirs[i].wd); /* fails harmlessly if already gone */
    free(w->dirs[i].path);
    w->dirs[i] = w->dirs[--w->n_dirs];
}

static void watch_error(char *err, size_t errlen, const char *dir, int e)
{
    if (e == ENOSPC)
        snprintf(err, errlen,
                 "cannot watch %s: the per-user limit of inotify watches is reached "
                 "(raise /proc/sys/fs/inotify/max_user_watches)",
                 dir);
    else if (e == ENOENT)
        snprintf(err, errlen, "cannot watch %s: no such directory", dir);
    else if (e == ENOTDIR)
        snprintf(err, errlen, "cannot watch %s: not a directory", dir);
    else
        snprintf(err, errlen, "cannot watch %s: %s", dir, strerror(e));
}

/* Adds a watch on `path` unless one is there; returns its index, or -1 with errno. */
static int dir_add(lg_watch *w, const char *path, bool required)
{
    int i = dir_find(w, path);
    if (i >= 0) {
        w->dirs[i].required |= required;
        return i;
    }
    int wd = inotify_add_watch(w->fd, path, WATCH_MASK);
    if (wd < 0)
        return -1;
    GROW(w->dirs, w->n_dirs, w->cap_dirs);
    w->dirs[w->n_dirs] = (wdir){ lg_xstrdup(path), wd, required, 0 };
    return (int)w->n_dirs++;
}

/* Watches `dir` and every directory below it. With `report`, every file found that a
 * registration matches is marked changed at `now` (a directory that appeared after the
 * watch started: its files were made before we could see them). Directories that vanish
 * meanwhile are skipped; a failure to watch one that exists is returned (-1, err). */
static int add_subtree(lg_watch *w, const char *dir, bool required, bool report, double now,
                       int depth, char *err, size_t errlen)
{
    if (dir_add(w, dir, required) < 0) {
        if (!required && (errno == ENOENT || errno == ENOTDIR))
            return 0;
        watch_error(err, errlen, dir, errno);
        return -1;
    }
    if (depth >= WATCH_MAX_DEPTH)
        return 0;
    DIR *d = opendir(dir);
    if (!d)
        return 0; /* vanished, or unreadable: its own events still come */
    int rc = 0;
    struct dirent *e;
    while (rc == 0 && (e = readdir(d))) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        char *sub = lg_path_join(dir, e->d_name);
        bool is_dir = e->d_type == DT_DIR;
        if (e->d_type == DT_UNKNOWN) {
            struct stat st;
            is_dir = lstat(sub, &st) == 0 && S_ISDIR(st.st_mode);
        }
        if (is_dir)
            rc = add_subtree(w, sub, false, report, now, depth + 1, err, errlen);
        else if (report)
            mark(w, sub, tags_for(w, sub, false), 0, now);
        free(sub);
    }
    closedir(d);
    return rc;
}

/* Brings the directory watches in line with the registrations: adds what is missing,
 * then drops what nobody needs. On failure (-1, err) the watches added by this call are
 * removed again and nothing else has changed. With `report`, every registered file is
 * marked changed (after a queue overflow). */
static int sync_dirs(lg_watch *w, bool report, double now, char *err, size_t errlen)
{
    uint32_t before = w->n_dirs;
    /* which existing entries are still wanted: rebuilt below */
    bool *keep = lg_xcalloc(before ? before : 1, sizeof *keep);
    int rc = 0;
    for (uint32_t i = 0; rc == 0 && i < w->n_files; i++) {
        int k = dir_find(w, w->files[i].dir);
        if (k >= 0 && w->dirs[k].wd < 0)
            continue; /* vanished: poll looks for it */
        if (dir_add(w, w->files[i].dir, true) < 0) {
            watch_error(err, errlen, w->files[i].dir, errno);
            rc = -1;
        }
        if (report)
            mark(w, w->files[i].path, w->files[i].tag, 0, now);
    }
    for (uint32_t i = 0; rc == 0 && i < w->n_trees; i++) {
        int k = dir_find(w, w->trees[i].root);
        if (k >= 0 && w->dirs[k].wd < 0)
            continue;
        rc = add_subtree(w, w->trees[i].root, true, report, now, 0, err, errlen);
    }
    if (rc < 0) {
        while (w->n_dirs > before)
            dir_remove(w, w->n_dirs - 1);
        free(keep);
        return -1;
    }
    /* Wanted: a registered file's directory, a tree's root (both required), or a directory
     * inside a tree that still exists (found again by add_subtree above, or watched). */
    for (uint32_t i = 0; i < w->n_dirs; i++) {
        wdir *d = &w->dirs[i];
        bool req = false;
        for (uint32_t f = 0; f < w->n_files && !req; f++)
            req = strcmp(w->files[f].dir, d->path) == 0;
        for (uint32_t t = 0; t < w->n_trees && !req; t++)
            req = strcmp(w->trees[t].root, d->path) == 0;
        d->required = req;
        if (i < before)
            keep[i] = req || (in_some_tree(w, d->path) && d->wd >= 0);
    }
    for (uint32_t i = before; i-- > 0;)
        if (!keep[i])
            dir_remove(w, i); /* moves the last entry into i: those are kept ones */
    free(keep);
    return 0;
}

/* ---- registrations --------------------------------------------------------------------------- */

static void free_files(wfile *f, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++) {
        free(f[i].path);
        free(f[i].dir);
    }
}

static void free_tree(wtree *t)
{
    free(t->root);
    for (uint32_t i = 0; i < t->n_suffixes; i++)
        free(t->suffixes[i]);
    free(t->suffixes);
}

/* `dir` must be an existing directory; `file` (NULL for a tree) is what needs it. */
static int check_dir(const char *dir, const char *file, char *err, size_t errlen)
{
    struct stat st;
    int e = stat(dir, &st) != 0 ? errno : S_ISDIR(st.st_mode) ? 0 : ENOTDIR;
    if (!e)
        return 0;
    const char *why = e == ENOENT    ? "no such directory"
                      : e == ENOTDIR ? "not a directory"
                                     : strerror(e);
    if (file)
        snprintf(err, errlen, "cannot watch %s: its directory %s: %s", file, dir, why);
    else
        snprintf(err, errlen, "cannot watch %s: %s", dir, why);
    return -1;
}

int lg_watch_open(lg_watch **out, char *err, size_t errlen)
{
    *out = NULL;
    int fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (fd < 0) {
        if (errno == EMFILE)
            snprintf(err, errlen,
                     "inotify: the per-user limit of instances is reached "
                     "(/proc/sys/fs/inotify/max_user_instances) or too many open files");
        else
            snprintf(err, errlen, "inotify: %s", strerror(errno));
        return -1;
    }
    lg_watch *w = lg_xcalloc(1, sizeof *w);
    w->fd = fd;
    *out = w;
    return 0;
}

void lg_watch_close(lg_watch **wp)
{
    lg_watch *w = wp ? *wp : NULL;
    if (!w)
        return;
    close(w->fd); /* drops every watch */
    free_files(w->files, w->n_files);
    free(w->files);
    for (uint32_t i = 0; i < w->n_trees; i++)
        free_tree(&w->trees[i]);
    free(w->trees);
    for (uint32_t i = 0; i < w->n_dirs; i++)
        free(w->dirs[i].path);
    free(w->dirs);
    for (uint32_t i = 0; i < w->n_pending; i++)
        free(w->pending[i].path);
    free(w->pending);
    free(w);
    *wp = NULL;
}

int lg_watch_files(lg_watch *w, int tag, const char *const *paths, uint32_t n, char *err,
                   size_t errlen)
{
    wfile *add = lg_xcalloc(n ? n : 1, sizeof *add);
    for (uint32_t i = 0; i < n; i++) {
        add[i].tag = tag;
        add[i].path = lg_path_absolute(paths[i]);
        add[i].dir = lg_path_dirname(add[i].path);
        if (check_dir(add[i].dir, add[i].path, err, errlen) < 0) {
            free_files(add, i + 1);
            free(add);
            return -1;
        }
    }
    /* the new list: other tags' files, then these */
    wfile *old = w->files;
    uint32_t n_old = w->n_files, cap_old = w->cap_files;
    wfile *next = lg_xcalloc((size_t)n_old + n + 1, sizeof *next);
    uint32_t m = 0;
    for (uint32_t i = 0; i < n_old; i++)
        if (old[i].tag != tag)
            next[m++] = old[i];
    memcpy(next + m, add, (size_t)n * sizeof *add);
    free(add);
    w->files = next;
    w->n_files = m + n;
    w->cap_files = n_old + n + 1;
    if (sync_dirs(w, false, 0, err, errlen) < 0) {
        free_files(next + m, n);
        free(next);
        w->files = old;
        w->n_files = n_old;
        w->cap_files = cap_old;
        return -1;
    }
    for (uint32_t i = 0; i < n_old; i++)
        if (old[i].tag == tag) {
            free(old[i].path);
            free(old[i].dir);
        }
    free(old);
    return 0;
}

int lg_watch_tree(lg_watch *w, int tag, const char *dir, const char *const *suffixes,
                  uint32_t n_suffixes, bool replace, char *err, size_t errlen)
{
    char *root = lg_path_absolute(dir);
    if (check_dir(root, NULL, err, errlen) < 0) {
        free(root);
        return -1;
    }
    wtree t = { tag, root, lg_xcalloc(n_suffixes ? n_suffixes : 1, sizeof(char *)), n_suffixes };
    for (uint32_t i = 0; i < n_suffixes; i++)
        t.suffixes[i] = lg_xstrdup(suffixes[i]);

    wtree *old = w->trees;
    uint32_t n_old = w->n_trees, cap_old = w->cap_trees;
    wtree *next = lg_xcalloc((size_t)n_old + 1, sizeof *next);
    uint32_t m = 0;
    for (uint32_t i = 0; i < n_old; i++)
        if (!(replace && old[i].tag == tag))
            next[m++] = old[i];
    next[m++] = t;
    w->trees = next;
    w->n_trees = m;
    w->cap_trees = n_old + 1;
    if (sync_dirs(w, false, 0, err, errlen) < 0) {
        free_tree(&next[m - 1]);
        free(next);
        w->trees = old;
        w->n_trees = n_old;
        w->cap_trees = cap_old;
        return -1;
    }
    for (uint32_t i = 0; i < n_old; i++)
        if (replace && old[i].tag == tag)
            free_tree(&old[i]);
    free(old);
    return 0;
}

int lg_watch_fd(const lg_watch *w)
{
    return w->fd;
}

/* ---- events ---------------------------------------------------------------------------------- */

/* A directory inside a tree went away or was moved out: forget its watches (the required
 * ones among them are looked for again). */
static void drop_subtree(lg_watch *w, const char *path, double now)
{
    for (uint32_t i = w->n_dirs; i-- > 0;) {
        wdir *d = &w->dirs[i];
        if (!path_within(d->path, path))
            continue;
        if (d->required) {
            if (d->wd >= 0 && !wd_shared(w, d->wd, i))
                inotify_rm_watch(w->fd, d->wd);
            d->wd = -1;
            d->retry_at = now;
        } else {
            dir_remove(w, i);
        }
    }
}

static void handle_event(lg_watch *w, const struct inotify_event *ev, double now, char *err,
                         size_t errlen)
{
    if (ev->mask & IN_IGNORED) {
        /* the directory is gone (or we removed the watch ourselves: then no entry has it) */
        for (uint32_t i = w->n_dirs; i-- > 0;) {
            if (w->dirs[i].wd != ev->wd)
                continue;
            if (w->dirs[i].required) {
                w->dirs[i].wd = -1;
                w->dirs[i].retry_at = now;
            } else {
                free(w->dirs[i].path);
                w->dirs[i] = w->dirs[--w->n_dirs];
            }
        }
        return;
    }
    if (!ev->len)
        return; /* an event on the directory itself */
    /* The paths of the directories behind this descriptor, copied first: handling the
     * event may add and drop entries. Usually one; two paths to one directory share it. */
    char *paths[4];
    int np = 0;
    for (uint32_t i = 0; i < w->n_dirs && np < 4; i++)
        if (w->dirs[i].wd == ev->wd)
            paths[np++] = lg_path_join(w->dirs[i].path, ev->name);
    bool is_dir = (ev->mask & IN_ISDIR) != 0;
    for (int k = 0; k < np; k++) {
        const char *path = paths[k];
        mark(w, path, tags_for(w, path, is_dir), ev->mask, now);
        if (is_dir && in_some_tree(w, path)) {
            if (ev->mask & (IN_CREATE | IN_MOVED_TO)) {
                /* a failure here (the watch limit) cannot be returned to anybody useful:
                 * the directory's files stay unwatched, and the log says so */
                if (add_subtree(w, path, false, true, now, 1, err, errlen) < 0)
                    lg_hlog(LG_HWARN, "%s", err);
            } else if (ev->mask & (IN_DELETE | IN_MOVED_FROM)) {
                drop_subtree(w, path, now);
            }
        }
    }
    for (int k = 0; k < np; k++)
        free(paths[k]);
}

/* Required directories that vanished: look again, and when one is back report everything
 * registered in it (it all changed: it was gone). */
static void retry_lost(lg_watch *w, double now, char *err, size_t errlen)
{
    for (uint32_t i = 0; i < w->n_dirs; i++) {
        wdir *d = &w->dirs[i];
        if (d->wd >= 0 || now < d->retry_at)
            continue;
        int wd = inotify_add_watch(w->fd, d->path, WATCH_MASK);
        if (wd < 0) {
            d->retry_at = now + WATCH_RETRY_S;
            continue;
        }
        d->wd = wd;
        char *path = lg_xstrdup(d->path);
        for (uint32_t f = 0; f < w->n_files; f++)
            if (strcmp(w->files[f].dir, path) == 0)
                mark(w, w->files[f].path, w->files[f].tag, 0, now);
        if (in_some_tree(w, path) && add_subtree(w, path, true, true, now, 0, err, errlen) < 0)
            lg_hlog(LG_HWARN, "%s", err);
        free(path);
    }
}

static bool is_ready(const wpending *p, double now, double quiet_s)
{
    return now - p->last >= (p->writing ? WATCH_WRITING_HOLD * quiet_s : quiet_s);
}

static int cmp_change(const void *a, const void *b)
{
    return strcmp(((const lg_watch_change *)a)->path, ((const lg_watch_change *)b)->path);
}

int lg_watch_poll(lg_watch *w, double now, double quiet_s, lg_watch_change **out, char *err,
                  size_t errlen)
{
    *out = NULL;
    char buf[65536] __attribute__((aligned(__alignof__(struct inotify_event))));
    bool overflow = false;
    for (;;) {
        ssize_t n = read(w->fd, buf, sizeof buf);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            if (errno == EAGAIN)
                break;
            snprintf(err, errlen, "reading inotify events: %s", strerror(errno));
            return -1;
        }
        if (n == 0)
            break;
        for (char *p = buf; p < buf + n;) {
            const struct inotify_event *ev = (const struct inotify_event *)p;
            if (ev->mask & IN_Q_OVERFLOW)
                overflow = true;
            else
                handle_event(w, ev, now, err, errlen);
            p += sizeof *ev + ev->len;
        }
    }
    if (overflow) {
        /* events were lost, directory creations among them: watch the trees again and
         * call everything changed */
        lg_hlog(LG_HDEBUG, "inotify queue overflow: reporting every watched file");
        if (sync_dirs(w, true, now, err, errlen) < 0)
            lg_hlog(LG_HWARN, "%s", err);
    }
    retry_lost(w, now, err, errlen);

    uint32_t ready = 0;
    for (uint32_t i = 0; i < w->n_pending; i++)
        if (is_ready(&w->pending[i], now, quiet_s))
            ready++;
    if (!ready)
        return 0;
    lg_watch_change *c = lg_xcalloc(ready, sizeof *c);
    int m = 0;
    for (uint32_t i = 0; i < w->n_pending;) {
        wpending *p = &w->pending[i];
        if (!is_ready(p, now, quiet_s)) {
            i++;
            continue;
        }
        /* registrations may have changed since the event: report what is still watched */
        int tags = p->tags & tags_for(w, p->path, false);
        if (tags)
            c[m++] = (lg_watch_change){ tags, p->path };
        else
            free(p->path);
        *p = w->pending[--w->n_pending];
    }
    if (!m) {
        free(c);
        return 0;
    }
    qsort(c, (size_t)m, sizeof *c, cmp_change);
    *out = c;
    return m;
}

void lg_watch_changes_free(lg_watch_change *c, int n)
{
    if (!c)
        return;
    for (int i = 0; i < n; i++)
        free(c[i].path);
    free(c);
}
