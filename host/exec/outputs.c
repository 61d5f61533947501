/* All-or-nothing output files. See outputs.h. */
#include "exec/outputs.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/util.h"

typedef struct entry {
    char *path;   /* as the caller gave it */
    char *abs;    /* normalised, to find the same destination again */
    char *tmp;    /* the temporary beside it */
    char *backup; /* during the commit: a hard link to the previous file, if any */
    char *owner;  /* a node's file: "node 'vol' (mesh_file)"; NULL for the run's own */
    bool written; /* something was written into the temporary */
} entry;

struct lg_outputs {
    entry *e;
    size_t n;
    bool elsewhere; /* lg_outputs_new_elsewhere: names only, another process writes */
};

/* ---- signals --------------------------------------------------------------------------------- */

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
static const int g_sigs[] = { SIGINT, SIGTERM, SIGHUP };

/* Async-signal-safe (see outputs.h). */
void lg_temp_remove_all(void)
{
    for (size_t i = 0; getpid() == g_pid && i < g_ntmp; i++)
        unlink(g_tmp[i]);
}

/* Removes every temporary, then dies of `sig` as the process would have without the
 * handler. Async-signal-safe. */
static void clean_up_and_die(int sig)
{
    lg_temp_remove_all();
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

void lg_temp_track(char *tmp)
{
    track(tmp);
}

void lg_temp_untrack(const char *tmp)
{
    untrack(tmp);
}

bool lg_temp_owner_dead(long pid)
{
    /* EPERM: a live process of another user; only ESRCH says nobody has the pid */
    return pid > 0 && pid != (long)getpid() && kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

/* ---- stale temporaries ----------------------------------------------------------------------- */

/* Whether `s` starts with six letters or digits (what mkstemp puts for XXXXXX). */
static bool six_alnum(const char *s)
{
    for (int k = 0; k < 6; k++)
        if (!isalnum((unsigned char)s[k]))
            return false;
    return true;
}

/* The length of "PID-XXXXXX" at `s` (the pid's digits, a dash, mkstemp's six letters and
 * digits), with the pid in *pid, or 0 when `s` does not start so. */
static size_t pid_and_suffix(const char *s, long *pid)
{
    size_t i = 0;
    *pid = 0;
    while (isdigit((unsigned char)s[i]) && i < 10)
        *pid = *pid * 10 + (s[i++] - '0');
    if (i == 0 || s[i] != '-' || !six_alnum(s + i + 1))
        return 0;
    return i + 7;
}

/* Removes what a killed run left beside this destination: its temporaries
 * ("PREFIX" "PID-XXXXXX" "EXT"), their commit backups (the same + ".old") and the image
 * writer's own temporaries inside them ("." the same ".XXXXXX"), whose PID is no running
 * process. A live pid's are kept: the directory may be shared by concurrent renders (a pid
 * reused since keeps them too; they go once that process is gone). Names that do not match
 * exactly, such as the pid-less temporaries of older versions, are never touched. */
static void remove_stale(const char *dir, const char *prefix, const char *ext)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    size_t np = strlen(prefix), ne = strlen(ext);
    struct dirent *de;
    while ((de = readdir(d))) {
        const char *name = de->d_name;
        bool inner = name[0] == '.' && strncmp(name + 1, prefix, np) == 0;
        const char *rest = inner ? name + 1 + np : name + np;
        if (!inner && strncmp(name, prefix, np) != 0)
            continue;
        long pid;
        size_t k = pid_and_suffix(rest, &pid);
        if (!k || strncmp(rest + k, ext, ne) != 0)
            continue;
        const char *tail = rest + k + ne;
        bool ok = inner ? strlen(tail) == 7 && tail[0] == '.' && six_alnum(tail + 1)
                        : tail[0] == 0 || strcmp(tail, ".old") == 0;
        if (!ok || !lg_temp_owner_dead(pid))
            continue;
        char *p = lg_xasprintf("%s/%s", dir, name);
        if (unlink(p) == 0)
            lg_hlog(LG_HINFO, "removed %s, left by process %ld, which is gone", p, pid);
        free(p);
    }
    closedir(d);
}

/* ---- the set --------------------------------------------------------------------------------- */

static mode_t new_file_mode(void)
{
    mode_t m = umask(0);
    umask(m);
    return 0666 & ~m;
}

static const char *file_type(mode_t m)
{
    return S_ISFIFO(m)   ? "a FIFO"
           : S_ISCHR(m)  ? "a character device"
           : S_ISBLK(m)  ? "a block device"
           : S_ISSOCK(m) ? "a socket"
                         : "not a regular file";
}

lg_outputs *lg_outputs_new(void)
{
    return lg_xcalloc(1, sizeof(lg_outputs));
}

lg_outputs *lg_outputs_new_elsewhere(void)
{
    lg_outputs *o = lg_outputs_new();
    o->elsewhere = true;
    return o;
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
            snprintf(err, errlen, "cannot write '%s': cannot use the directory '%s': %s", path, dir,
                     strerror(errno));
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

static int add(lg_outputs *o, const char *path, lg_output_kind kind, const char *owner, char *err,
               size_t errlen)
{
    if (path && path[0]) {
        const entry *have = find(o, path);
        if (have) {
            if ((!have->owner && !owner) || (have->owner && owner && !strcmp(have->owner, owner)))
                return 0;
            /* two writers of one destination: one of them would be lost */
            snprintf(err, errlen, "cannot write '%s' as %s: it is already %s", path,
                     owner ? owner : "an output of the render",
                     have->owner ? have->owner : "an output of the render");
            return -1;
        }
    }
    if (o->elsewhere) {
        o->e = lg_xrealloc(o->e, (o->n + 1) * sizeof *o->e);
        entry *e = &o->e[o->n++];
        memset(e, 0, sizeof *e);
        e->path = lg_xstrdup(path ? path : "");
        e->abs = lg_path_absolute(e->path);
        e->owner = owner ? lg_xstrdup(owner) : NULL;
        return 0;
    }
    if (lg_outputs_check(path, kind, err, errlen))
        return -1;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    char *dir = lg_path_dirname(path);
    int rc = -1;

    /* ".NAME.lgtmp-PID-XXXXXX.EXT" beside the destination: the extension stays last because
     * it chooses the image format; the name is cut so that it stays well within NAME_MAX;
     * the pid tells a later run whether the process that made it is gone (remove_stale) */
    const char *dot = strrchr(base, '.');
    const char *ext = dot && dot != base && strlen(dot) <= 16 ? dot : "";
    size_t stem = strlen(base) - strlen(ext);
    char *prefix = lg_xasprintf(".%.*s.lgtmp-", (int)(stem > 100 ? 100 : stem), base);
    remove_stale(dir, prefix, ext);
    char *tmp = lg_xasprintf("%.*s%s%ld-XXXXXX%s", (int)(base - path), path, prefix, (long)getpid(),
                             ext);
    free(prefix);
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
    e->owner = owner ? lg_xstrdup(owner) : NULL;
    track(tmp);
    rc = 0;
out:
    free(dir);
    return rc;
}

int lg_outputs_add(lg_outputs *o, const char *path, lg_output_kind kind, char *err, size_t errlen)
{
    return add(o, path, kind, NULL, err, errlen);
}

int lg_outputs_add_owned(lg_outputs *o, const char *path, const char *owner, char *err,
                         size_t errlen)
{
    return add(o, path, LG_OUTPUT_FILE, owner, err, errlen);
}

const char *lg_outputs_temp(const lg_outputs *o, const char *path)
{
    entry *e = o ? find(o, path) : NULL;
    return e ? (e->tmp ? e->tmp : "") : NULL;
}

int lg_outputs_write_image(lg_outputs *o, const char *path, const lg_image *img,
                           const lg_image_write_opts *wo, char *err, size_t errlen)
{
    entry *e = find(o, path);
    if (!e) {
        snprintf(err, errlen, "cannot write '%s': not checked as an output", path);
        return -1;
    }
    if (o->elsewhere) {
        e->written = true;
        return 0;
    }
    char why[1024];
    /* busy, so that lg_image_write's own temporary is always renamed or removed */
    busy();
    int rc = lg_image_write(e->tmp, img, wo, why, sizeof why);
    e->written = true;
    not_busy();
    if (rc)
        snprintf(err, errlen, "cannot write '%s': %s", path, why);
    return rc ? -1 : 0;
}

int lg_outputs_write_data(lg_outputs *o, const char *path, const void *data, size_t n, char *err,
                          size_t errlen)
{
    entry *e = find(o, path);
    if (!e) {
        snprintf(err, errlen, "cannot write '%s': not checked as an output", path);
        return -1;
    }
    if (o->elsewhere) {
        e->written = true;
        return 0;
    }
    busy();
    e->written = true;
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
    if (e->tmp) { /* NULL in a set written elsewhere */
        untrack(e->tmp);
        if (unlink_tmp)
            unlink(e->tmp);
    }
    free(e->path);
    free(e->abs);
    free(e->tmp);
    free(e->backup);
    free(e->owner);
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
    if (o->elsewhere) {
        while (o->n)
            remove_entry(o, o->n - 1, false);
        return 0;
    }
    busy();
    if (g_pending) {
        /* a signal arrived while the outputs were written: nothing is committed, not_busy()
         * removes the temporaries and lets it act */
        snprintf(err, errlen, "interrupted; nothing was written");
        not_busy();
        return -1;
    }
    /* a node's file that the node never wrote (it was gated, or did not run): no empty
     * file takes the place of the destination */
    for (size_t i = o->n; i-- > 0;)
        if (o->e[i].owner && !o->e[i].written) {
            lg_hlog(LG_HINFO, "%s: '%s' not written (the node wrote nothing)", o->e[i].owner,
                    o->e[i].path);
            remove_entry(o, i, true);
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

bool lg_size_over_limit(const char *cmd, uint32_t w, uint32_t h)
{
    uint64_t px = (uint64_t)w * h, limit = lg_image_max_pixels();
    if (px <= limit)
        return false;
    fprintf(stderr,
            "lightgraph %s: --size %ux%u is %llu pixels, over the limit of %llu pixels "
            "(raise it with --max-pixels N or LIGHTGRAPH_MAX_PIXELS=N); nothing was run\n",
            cmd, w, h, (unsigned long long)px, (unsigned long long)limit);
    return true;
}
