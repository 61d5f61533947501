/* The on-disk cache for expensive static results.
 *
 * Directory: $LIGHTGRAPH_CACHE_DIR, else $XDG_CACHE_HOME/lightgraph, else
 * ~/.cache/lightgraph, else a private ${TMPDIR:-/tmp}/lightgraph-cache-UID, each checked
 * before use (cache_ready below). One file per entry, named by a digest of the node's identity (plugin,
 * version, type, parameters, content keys, inputs' identities) and the entry key, so a
 * change to any of them looks up another file: stale entries are never found. The file
 * repeats the identity and key and carries the payload size and a checksum; an entry whose
 * header, size or checksum disagrees is corrupt: reported, removed, and treated as a miss.
 * An entry that cannot be removed (a folder with files in it where the entry belongs) is
 * said so, once, and bypassed for the render: computed, not stored (drop_entry).
 * The entry's bytes are written and checked by cache_entry.c (the format is there).
 */
#include "exec/exec.h"
#include "exec/dist.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "exec/outputs.h"

#define CACHE_MAX_KEY 1024u

/* Where the cache lives, and why it can be trusted (issue 8). Whoever can write into the
 * cache directory chooses the results a render reuses, so the directory must be the user's
 * own: $LIGHTGRAPH_CACHE_DIR, else $XDG_CACHE_HOME/lightgraph (an absolute XDG_CACHE_HOME;
 * the XDG spec says to ignore a relative one), else $HOME/.cache/lightgraph, else, with
 * neither HOME nor XDG_CACHE_HOME, a private ${TMPDIR:-/tmp}/lightgraph-cache-UID. Never a
 * shared folder such as /tmp/.cache/lightgraph.
 *
 * Checked once per render, on first use:
 *   - a directory lightgraph creates is made 0700 (missing parents too), then lstat'ed: a
 *     real directory owned by the effective user, writable by no one else;
 *   - the private fallback, when it exists already, must be that too, and 0700 exactly (no
 *     symbolic link, no access for others: /tmp is shared and another user may have made
 *     it first);
 *   - a directory the user named (the first three) that exists is followed if it is a link
 *     and must be a directory owned by the user and not writable by every user (world
 *     write lets anyone plant entries, with or without the sticky bit). Group write is left
 *     to the user (user-private groups make it common).
 * A directory that fails disables the cache for the render with one warning: nothing is
 * reused or written, and the render goes on. */
typedef struct cache_choice {
    char *dir;
    bool private_dir; /* the /tmp fallback: must be 0700 and no link */
    const char *from; /* the variable it came from, for the warning */
} cache_choice;

static cache_choice choose_dir(void)
{
    cache_choice c = { 0 };
    const char *e = getenv("LIGHTGRAPH_CACHE_DIR");
    if (e && *e) {
        c.dir = lg_xstrdup(e);
        c.from = "LIGHTGRAPH_CACHE_DIR";
        return c;
    }
    e = getenv("XDG_CACHE_HOME");
    if (e && e[0] == '/') {
        c.dir = lg_xasprintf("%s/lightgraph", e);
        c.from = "XDG_CACHE_HOME";
        return c;
    }
    e = getenv("HOME");
    if (e && *e) {
        c.dir = lg_xasprintf("%s/.cache/lightgraph", e);
        c.from = "HOME";
        return c;
    }
    e = getenv("TMPDIR");
    c.dir = lg_xasprintf("%s/lightgraph-cache-%u", e && e[0] == '/' ? e : "/tmp",
                         (unsigned)geteuid());
    c.private_dir = true;
    c.from = "neither HOME nor XDG_CACHE_HOME is set";
    return c;
}

/* The directory the cache would use, before its check (malloc'd). */
char *lg_cache_dir(void)
{
    return choose_dir().dir;
}

/* Why a directory with these attributes cannot be the cache, or NULL. `st` comes from
 * lstat for a directory lightgraph made or the private fallback (strict: no link, no
 * group or other write; `private_dir`: no group or other access at all) and from stat for
 * an existing directory the user named. */
static const char *distrust(const struct stat *st, bool strict, bool private_dir, char *buf,
                            size_t n)
{
    if (S_ISLNK(st->st_mode))
        return "it is a symbolic link, not a directory of your own";
    if (!S_ISDIR(st->st_mode))
        return "it is not a directory";
    if (st->st_uid != geteuid()) {
        snprintf(buf, n, "it is owned by uid %u, not by you (uid %u)", (unsigned)st->st_uid,
                 (unsigned)geteuid());
        return buf;
    }
    mode_t m = st->st_mode & 07777;
    if ((private_dir && (m & 077)) || (strict && (m & 022))) {
        snprintf(buf, n, "its mode is %04o; a private cache directory is 0700", (unsigned)m);
        return buf;
    }
    if (m & S_IWOTH) {
        snprintf(buf, n, "it is writable by every user (mode %04o)", (unsigned)m);
        return buf;
    }
    return NULL;
}

static int mkdir_p(const char *dir, mode_t mode)
{
    char *d = lg_xstrdup(dir);
    int rc = 0;
    for (char *p = d + 1;; p++) {
        if (*p == '/' || !*p) {
            char c = *p;
            *p = 0;
            if (mkdir(d, mode) != 0 && errno != EEXIST) {
                rc = -1;
                break;
            }
            *p = c;
            if (!c)
                break;
        }
    }
    free(d);
    return rc;
}

/* Whether `name` is an entry's temporary, "NAME-HEX32.lgc.tmpPID" (put_entry), with its pid. */
static bool temporary_name(const char *name, long *pid)
{
    const char *t = strstr(name, ".lgc.tmp");
    if (!t || t - name < 34 || t[-33] != '-')
        return false;
    for (const char *h = t - 32; h < t; h++)
        if (!isxdigit((unsigned char)*h))
            return false;
    const char *d = t + strlen(".lgc.tmp");
    size_t nd = strspn(d, "0123456789");
    if (nd == 0 || nd > 10 || d[nd])
        return false;
    *pid = strtol(d, NULL, 10);
    return true;
}

/* Removes the entry temporaries that processes killed outright (SIGKILL, a crash, a power
 * cut) left in the cache: those whose pid is no running process. The directory may be
 * shared by concurrent renders, so a live pid's are kept, and only names of exactly the
 * temporary's pattern are touched. Once per render, when the directory is first used. */
static void remove_stale(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *de;
    while ((de = readdir(d))) {
        long pid;
        if (!temporary_name(de->d_name, &pid) || !lg_temp_owner_dead(pid))
            continue;
        char *p = lg_xasprintf("%s/%s", dir, de->d_name);
        if (unlink(p) == 0)
            lg_hlog(LG_HINFO, "cache: removed %s, left by process %ld, which is gone", p, pid);
        free(p);
    }
    closedir(d);
}

/* The checked cache directory, or NULL: not there yet and !create (a miss), or disabled
 * (warned once). */
static const char *cache_ready(lg_exec *ex, bool create)
{
    if (ex->cache.off)
        return NULL;
    if (ex->cache.dir)
        return ex->cache.dir;
    cache_choice c = choose_dir();
    struct stat st;
    char buf[160];
    const char *why = NULL;
    bool made = false;
    int r = c.private_dir ? lstat(c.dir, &st) : stat(c.dir, &st);
    if (r != 0 && errno == ENOENT && !create) {
        free(c.dir);
        return NULL;
    }
    if (r != 0 && errno == ENOENT) {
        /* 0700: new directories, the missing parents too, are the user's alone */
        r = c.private_dir ? mkdir(c.dir, 0700) : mkdir_p(c.dir, 0700);
        if (r == 0 || errno == EEXIST) {
            made = r == 0;
            r = lstat(c.dir, &st);
        }
    }
    if (r != 0) {
        snprintf(buf, sizeof buf, "%s", strerror(errno));
        why = buf;
    } else {
        why = distrust(&st, made || c.private_dir, c.private_dir, buf, sizeof buf);
    }
    if (why) {
        lg_hlog(LG_HWARN,
                "cache disabled for this run: '%s' (%s) cannot be the cache directory: %s; "
                "set LIGHTGRAPH_CACHE_DIR to a directory of your own",
                c.dir, c.from, why);
        free(c.dir);
        ex->cache.off = true;
        return NULL;
    }
    ex->cache.dir = c.dir;
    remove_stale(ex->cache.dir);
    return ex->cache.dir;
}

/* What names the node's entries: its identity, or for a LG_NODE_CACHE_BY_CONTENT node the
 * identity without its inputs' (the node's keys carry what it reads of them). */
static const lg_digest *cache_identity(const lg_pnode *n)
{
    return (n->schema->flags & LG_NODE_CACHE_BY_CONTENT) ? &n->plan.cache_identity
                                                         : &n->plan.identity;
}

static char *entry_path(const char *dir, lg_pnode *n, const char *key)
{
    lg_digest d = *cache_identity(n);
    lg_digest_add_str(&d, key);
    char hex[33];
    lg_digest_hex(&d, hex);
    return lg_xasprintf("%s/%s-%s.lgc", dir, n->schema->name, hex);
}

static bool key_ok(lg_pnode *n, const char *key)
{
    if (!key || strlen(key) > CACHE_MAX_KEY) {
        lg_node_errorf(n, "cache key missing or longer than %u bytes", CACHE_MAX_KEY);
        return false;
    }
    return true;
}

/* Removes an entry that cannot be used, and says what happened. When it cannot be removed
 * (a non-empty folder in its place; a cache folder we may not write to), saying "removing
 * it" would be false and every render would compute again without knowing why: the
 * message says so and why, and the node's entries are bypassed for the render (cache_put
 * stores nothing at a folder, and says nothing more). */
static void drop_entry(lg_pnode *n, const char *path, const char *problem)
{
    if (remove(path) == 0) {
        lg_hlog(LG_HWARN, "node '%s': cache entry %s %s; removing it and recomputing", n->pub.name,
                path, problem);
        return;
    }
    lg_hlog(LG_HWARN,
            "node '%s': cache entry %s %s and cannot be removed (%s): recomputing, "
            "and not cached in this render (remove it yourself to cache it again)",
            n->pub.name, path, problem, strerror(errno));
    n->run.cache_stuck = true;
}

/* The largest entry read back: the largest buffer a resource may hold (16 GiB) plus the
 * header. */
#define CACHE_MAX_ENTRY (((size_t)1 << 34) + 4096)

int lg_exec_cache_get(lg_exec *ex, lg_pnode *n, const char *key, void **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    if (!key_ok(n, key))
        return LG_ERR_INVALID;
    const char *dir = cache_ready(ex, false);
    if (!dir) {
        n->prof.cache_misses++;
        return LG_ERR_NOTFOUND;
    }
    char *path = entry_path(dir, n, key);
    size_t len = 0;
    char why_read[256];
    /* bounded: an entry that is a FIFO, a device (a link to /dev/zero) or larger than any
     * payload can be is refused before it is read, and treated as a corrupt entry */
    char *buf = lg_read_file_limit(path, CACHE_MAX_ENTRY, &len, why_read, sizeof why_read);
    if (!buf) {
        if (errno != ENOENT) {
            char problem[300];
            snprintf(problem, sizeof problem, "cannot be used (%s)", why_read);
            drop_entry(n, path, problem);
        }
        free(path);
        n->prof.cache_misses++;
        return LG_ERR_NOTFOUND;
    }
    const char *payload = NULL;
    size_t psize = 0;
    const char *why = lg_cache_entry_check(buf, len, cache_identity(n), key, &payload, &psize);
    if (why) {
        char problem[300];
        snprintf(problem, sizeof problem, "is corrupt (%s)", why);
        drop_entry(n, path, problem);
        free(buf);
        free(path);
        n->prof.cache_misses++;
        return LG_ERR_NOTFOUND;
    }
    void *out = malloc(psize ? psize : 1);
    if (!out) {
        free(buf);
        free(path);
        return LG_ERR_NOMEM;
    }
    memcpy(out, payload, psize);
    free(buf);
    lg_hlog(LG_HINFO, "node '%s': cache hit %s (%llu bytes)", n->pub.name, path,
            (unsigned long long)psize);
    free(path);
    *data = out;
    *size = psize;
    n->prof.cache_hits++;
    return LG_OK;
}

/* The node's own check found the values of an entry it read impossible (exec.h,
 * cache_reject): the same words, the same removal and the same miss as the checksum's. */
void lg_exec_cache_drop(lg_exec *ex, lg_pnode *n, const char *key, const char *why)
{
    if (!key_ok(n, key))
        return;
    const char *dir = cache_ready(ex, false);
    if (!dir)
        return;
    char *path = entry_path(dir, n, key);
    char *problem = lg_xasprintf("is corrupt (%s)",
                                 why && *why ? why : "its node rejected its values");
    drop_entry(n, path, problem);
    free(problem);
    free(path);
    if (n->prof.cache_hits)
        n->prof.cache_hits--;
    n->prof.cache_misses++;
}

/* A test hook: LIGHTGRAPH_TEST_CACHE_WRITE_PAUSE=S pauses S seconds (at most 60) half way
 * through writing an entry, so that a test can interrupt the write at a known point. */
static void test_pause(void)
{
    const char *e = getenv("LIGHTGRAPH_TEST_CACHE_WRITE_PAUSE");
    double s = e ? strtod(e, NULL) : 0;
    if (!(s > 0))
        return;
    s = s < 60 ? s : 60;
    struct timespec ts = { (time_t)s, (long)((s - (double)(time_t)s) * 1e9) };
    while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

/* Writes the entry through "PATH.tmpPID", renamed into place. The temporary is on the
 * signal handler's list (outputs.h) from before it exists until it is renamed or removed:
 * SIGINT, SIGTERM or SIGHUP in the middle of a large entry leaves no torn file; the pid in
 * its name lets a later run remove one that SIGKILL left (remove_stale). Sets errno on
 * failure. */
static int put_entry(const char *path, const void *data, size_t n)
{
    char *tmp = lg_xasprintf("%s.tmp%ld", path, (long)getpid());
    lg_temp_track(tmp);
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    int rc = fd < 0 ? -1 : 0, saved = fd < 0 ? errno : 0;
    const char *p = data;
    size_t left = n, half = n / 2;
    while (rc == 0 && left > 0) {
        size_t chunk = left > ((size_t)1 << 24) ? (size_t)1 << 24 : left;
        if (n - left < half && n - left + chunk > half)
            chunk = half - (n - left);
        ssize_t w = write(fd, p, chunk);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            rc = -1;
            saved = w < 0 ? errno : EIO;
            break;
        }
        p += w;
        left -= (size_t)w;
        if (n - left == half && half)
            test_pause();
    }
    if (fd >= 0 && close(fd) != 0 && rc == 0) {
        rc = -1;
        saved = errno;
    }
    if (rc == 0 && rename(tmp, path) != 0) {
        rc = -1;
        saved = errno;
    }
    if (rc)
        unlink(tmp);
    lg_temp_untrack(tmp);
    free(tmp);
    errno = saved;
    return rc;
}

int lg_exec_cache_put_status(lg_exec *ex, lg_pnode *n, const char *key, const void *data,
                             size_t size)
{
    if (!key_ok(n, key))
        return LG_ERR_INVALID;
    if (!data && size)
        return lg_node_errorf(n, "cache_put with NULL data"), LG_ERR_INVALID;
    /* under mpirun rank 0 alone writes (every rank computed the same bytes): one writer
     * per entry, and a successful no-op on the others */
    if (!lg_dist_root() && !lg_dist_nested())
        return LG_CACHE_STORED;
    const char *dir = cache_ready(ex, true);
    if (!dir)
        return LG_CACHE_OFF; /* said once: nothing to store, nothing failed */
    char *path = entry_path(dir, n, key);
    struct stat st;
    if (n->run.cache_stuck && lstat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        free(path); /* cache_get said why; a rename onto the folder would fail again */
        return LG_CACHE_NOT_STORED;
    }
    lg_str b = { 0 };
    lg_cache_entry_encode(&b, cache_identity(n), key, data, size);
    int rc = LG_CACHE_STORED;
    if (put_entry(path, b.s, b.len) != 0) {
        lg_hlog(LG_HWARN, "node '%s': cannot write cache entry %s: %s", n->pub.name, path,
                strerror(errno));
        rc = LG_CACHE_NOT_STORED;
    }
    free(path);
    lg_str_free(&b);
    return rc;
}

int lg_exec_cache_put(lg_exec *ex, lg_pnode *n, const char *key, const void *data, size_t size)
{
    int rc = lg_exec_cache_put_status(ex, n, key, data, size);
    return rc < 0 ? rc : rc == LG_CACHE_NOT_STORED ? LG_ERR_IO : LG_OK;
}
