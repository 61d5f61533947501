/* All-or-nothing output files. See outputs.h. */
#include "outputs.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util.h"

typedef struct entry {
    char *path;   /* as the caller gave it */
    char *abs;    /* normalised, to find the same destination again */
    char *tmp;    /* the temporary beside it */
    char *backup; /* during the commit: a hard link to the previous file, if any */
} entry;

struct lg_outputs {
    entry *e;
    size_t n;
};

/* ---- signals ----------------------------------------------------------------------------- */

/* Every temporary of every live set, for the signal handler. The main thread changes the
 * list and writes files only inside busy(): a signal that arrives then (on any thread: the
 * host has worker threads, so masking the main thread alone would not do) is remembered, and
 * acted on when the main thread is done, so that neither the list nor an image writer's own
 * temporary is left half done. */
static char **g_tmp;
static size_t g_ntmp, g_cap;
static bool g_installed;
/* a forked child (a plugin scanner) that inherits the handler removes nothing */
static pid_t g_pid;
static volatile sig_atomic_t g_busy, g_pending;
static const int g_sigs[] = {SIGINT, SIGTERM, SIGHUP};

/* Removes every temporary, then dies of `sig` as the process would have without the
 * handler. Async-signal-safe. */
static void clean_up_and_die(int sig)
{
    for (size_t i = 0; getpid() == g_pid && i < g_ntmp; i++)
        unlink(g_tmp[i]);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = SIG_DFL;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, NULL);
    /* in the handler, SA_NODEFER lets the default action happen at once */
    raise(sig);
    _exit(128 + sig);
}

static void on_signal(int sig)
{
    if (g_busy) {
        g_pending = sig;
        return;
    }
    clean_up_and_die(sig);
}

static void busy(void)
{
    g_busy++;
}

static void not_busy(void)
{
    if (--g_busy == 0 && g_pending)
        clean_up_and_die(g_pending);
}

/* Installs the handler for the signals whose action is still the default: one that is
 * ignored (nohup) stays ignored, and another handler is left alone. */
static void install_handler(void)
{
    if (g_installed)
        return;
    g_installed = true;
    g_pid = getpid();
    for (size_t i = 0; i < sizeof g_sigs / sizeof g_sigs[0]; i++) {
        struct sigaction old;
        if (sigaction(g_sigs[i], NULL, &old) != 0 || old.sa_handler != SIG_DFL ||
            (old.sa_flags & SA_SIGINFO))
            continue;
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sa.sa_flags = SA_NODEFER;
        sigemptyset(&sa.sa_mask);
        sigaction(g_sigs[i], &sa, NULL);
    }
}

static void track(char *tmp)
{
    busy();
    install_handler();
    if (g_ntmp == g_cap) {
        g_cap = g_cap ? 2 * g_cap : 16;
        g_tmp = lg_xrealloc(g_tmp, g_cap * sizeof *g_tmp);
    }
    g_tmp[g_ntmp++] = tmp;
    not_busy();
}

static void untrack(const char *tmp)
{
    busy();
    for (size_t i = 0; i < g_ntmp; i++)
        if (g_tmp[i] == tmp) {
            g_tmp[i] = g_tmp[--g_ntmp];
            break;
        }
    not_busy();
}

/* ---- the set ----------------------------------------------------------------------------- */

static mode_t new_file_mode(void)
{
    mode_t m = umask(0);
    umask(m);
    return 0666 & ~m;
}

static const char *file_type(mode_t m)
{
    return S_ISFIFO(m)  ? "a FIFO"
           : S_ISCHR(m) ? "a character device"
           : S_ISBLK(m) ? "a block device"
           : S_ISSOCK(m) ? "a socket"
                         : "not a regular file";
}

lg_outputs *lg_outputs_new(void)
{
    return lg_xcalloc(1, sizeof(lg_outputs));
}

static entry *find(const lg_outputs *o, const char *path)
{
    char *abs = lg_path_absolute(path);
    entry *found = NULL;
    for (size_t i = 0; i < o->n && !found; i++)
        if (strcmp(o->e[i].abs, abs) == 0)
            found = &o->e[i];
    free(abs);
    return found;
}

int lg_outputs_check(const char *path, lg_output_kind kind, char *err, size_t errlen)
{
    if (!path || !path[0]) {
        snprintf(err, errlen, "an output file name is empty");
        return -1;
    }
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (!base[0] || strcmp(base, ".") == 0 || strcmp(base, "..") == 0) {
        snprintf(err, errlen, "cannot write '%s': it names no file", path);
        return -1;
    }
    if (kind == LG_OUTPUT_IMAGE && lg_image_format_from_path(path) == LG_FILE_UNKNOWN) {
        snprintf(err, errlen, "cannot write '%s': unknown image format (use .png, .exr or .hdr)",
                 path);
        return -1;
    }
    char *dir = lg_path_dirname(path);
    struct stat st;
    int rc = -1;
    if (stat(dir, &st) != 0) {
        if (errno == ENOENT)
            snprintf(err, errlen,
                     "cannot write '%s': the directory '%s' does not exist (lightgraph does not "
                     "create directories; create it first)",
                     path, dir);
        else
            snprintf(err, errlen, "cannot write '%s': cannot use the directory '%s': %s", path,
                     dir, strerror(errno));
        goto out;
    }
    if (!S_ISDIR(st.st_mode)) {
        snprintf(err, errlen, "cannot write '%s': '%s' is not a directory", path, dir);
        goto out;
    }
    if (stat(path, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            snprintf(err, errlen, "cannot write '%s': it is a directory", path);
            goto out;
        }
        if (!S_ISREG(st.st_mode)) {
            snprintf(err, errlen, "cannot write '%s': it is %s, not a regular file", path,
                     file_type(st.st_mode));
            goto out;
        }
    } else if (errno != ENOENT) {
        snprintf(err, errlen, "cannot write '%s': %s", path, strerror(errno));
        goto out;
    }
    rc = 0;
out:
    free(dir);
    return rc;
}

int lg_outputs_add(lg_outputs *o, const char *path, lg_output_kind kind, char *err,
                   size_t errlen)
{
    if (path && path[0] && find(o, path))
        return 0;
    if (lg_outputs_check(path, kind, err, errlen))
        return -1;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    char *dir = lg_path_dirname(path);
    int rc = -1;

    /* ".NAME.lgtmp-XXXXXX.EXT" beside the destination: the extension stays last because it
     * chooses the image format; the name is cut so that it stays well within NAME_MAX */
    const char *dot = strrchr(base, '.');
    const char *ext = dot && dot != base && strlen(dot) <= 16 ? dot : "";
    size_t stem = strlen(base) - strlen(ext);
    char *tmp = lg_xasprintf("%.*s.%.*s.lgtmp-XXXXXX%s", (int)(base - path), path,
                             (int)(stem > 100 ? 100 : stem), base, ext);
    int fd = mkostemps(tmp, (int)strlen(ext), O_CLOEXEC);
    if (fd < 0) {
        snprintf(err, errlen, "cannot write '%s': cannot create a file in the directory '%s': %s",
                 path, dir, strerror(errno));
        free(tmp);
        goto out;
    }
    /* the mode any new file gets (mkstemp makes 0600), kept by writers that truncate it */
    (void)fchmod(fd, new_file_mode());
    close(fd);
    o->e = lg_xrealloc(o->e, (o->n + 1) * sizeof *o->e);
    entry *e = &o->e[o->n++];
    memset(e, 0, sizeof *e);
    e->path = lg_xstrdup(path);
    e->abs = lg_path_absolute(path);
    e->tmp = tmp;
    track(tmp);
    rc = 0;
out:
    free(dir);
    return rc;
}

const char *lg_outputs_temp(const lg_outputs *o, const char *path)
{
    entry *e = o ? find(o, path) : NULL;
    return e ? e->tmp : NULL;
}

int lg_outputs_write_image(lg_outputs *o, const char *path, const lg_image *img,
                           const lg_image_write_opts *wo, char *err, size_t errlen)
{
    entry *e = find(o, path);
    if (!e) {
        snprintf(err, errlen, "cannot write '%s': not checked as an output", path);
        return -1;
    }
    char why[1024];
    /* busy, so that lg_image_write's own temporary is always renamed or removed */
    busy();
    int rc = lg_image_write(e->tmp, img, wo, why, sizeof why);
    not_busy();
    if (rc)
        snprintf(err, errlen, "cannot write '%s': %s", path, why);
    return rc ? -1 : 0;
}

int lg_outputs_write_data(lg_outputs *o, const char *path, const void *data, size_t n,
                          char *err, size_t errlen)
{
    entry *e = find(o, path);
    if (!e) {
        snprintf(err, errlen, "cannot write '%s': not checked as an output", path);
        return -1;
    }
    busy();
    int fd = open(e->tmp, O_WRONLY | O_TRUNC | O_CLOEXEC);
    int rc = fd < 0 ? -1 : 0;
    const char *p = data;
    while (rc == 0 && n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            rc = -1;
            break;
        }
        p += w;
        n -= (size_t)w;
    }
    if (rc == 0 && (fchmod(fd, new_file_mode()) != 0 || fsync(fd) != 0))
        rc = -1;
    int saved = errno;
    if (fd >= 0 && close(fd) != 0 && rc == 0) {
        rc = -1;
        saved = errno;
    }
    not_busy();
    if (rc)
        snprintf(err, errlen, "cannot write '%s': %s", path, strerror(saved ? saved : EIO));
    return rc;
}

static void remove_entry(lg_outputs *o, size_t i, bool unlink_tmp)
{
    entry *e = &o->e[i];
    untrack(e->tmp);
    if (unlink_tmp)
        unlink(e->tmp);
    free(e->path);
    free(e->abs);
    free(e->tmp);
    free(e->backup);
    o->e[i] = o->e[--o->n];
}

void lg_outputs_drop(lg_outputs *o, const char *path)
{
    entry *e = find(o, path);
    if (e)
        remove_entry(o, (size_t)(e - o->e), true);
}

int lg_outputs_commit(lg_outputs *o, char *err, size_t errlen)
{
    busy();
    if (g_pending) {
        /* a signal arrived while the outputs were written: nothing is committed, not_busy()
         * removes the temporaries and lets it act */
        snprintf(err, errlen, "interrupted; nothing was written");
        not_busy();
        return -1;
    }
    /* keep each previous file as a hard link, so that a rename failing part way can put
     * back what the earlier ones replaced */
    for (size_t i = 0; i < o->n; i++) {
        entry *e = &o->e[i];
        struct stat st;
        if (stat(e->path, &st) == 0 && S_ISREG(st.st_mode)) {
            char *b = lg_xasprintf("%s.old", e->tmp);
            if (link(e->path, b) == 0)
                e->backup = b;
            else
                free(b);
        }
    }
    int rc = 0;
    size_t done = 0;
    for (; done < o->n; done++) {
        if (rename(o->e[done].tmp, o->e[done].path) != 0) {
            snprintf(err, errlen, "cannot write '%s': rename from '%s': %s", o->e[done].path,
                     o->e[done].tmp, strerror(errno));
            rc = -1;
            break;
        }
    }
    if (rc) {
        for (size_t i = 0; i < done; i++) {
            entry *e = &o->e[i];
            if (e->backup)
                rename(e->backup, e->path);
            else
                unlink(e->path);
        }
    }
    for (size_t i = 0; i < o->n; i++)
        if (o->e[i].backup)
            unlink(o->e[i].backup);
    /* committed: the temporaries are now the destinations; failed: remove them */
    while (o->n)
        remove_entry(o, o->n - 1, rc != 0);
    not_busy();
    return rc;
}

void lg_outputs_free(lg_outputs **op)
{
    lg_outputs *o = op ? *op : NULL;
    if (!o)
        return;
    while (o->n)
        remove_entry(o, o->n - 1, true);
    free(o->e);
    free(o);
    *op = NULL;
}
