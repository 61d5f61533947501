/* lightgraph/file.h: bounded, confined reads of regular files. */
#include "lightgraph/file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void say(char *err, size_t errlen, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static void say(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || !errlen)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

static void bytes(char *out, size_t n, uint64_t b)
{
    static const char *unit[] = { "bytes", "KiB", "MiB", "GiB", "TiB", "PiB" };
    if (b < 1024) {
        snprintf(out, n, "%llu bytes", (unsigned long long)b);
        return;
    }
    double v = (double)b;
    int u = 0;
    while (v >= 1024.0 && u < 5) {
        v /= 1024.0;
        u++;
    }
    snprintf(out, n, "%.1f %s", v, unit[u]);
}

static const char *kind_of(mode_t m)
{
    return S_ISDIR(m)    ? "a directory"
           : S_ISFIFO(m) ? "a FIFO"
           : S_ISCHR(m)  ? "a character device"
           : S_ISBLK(m)  ? "a block device"
           : S_ISSOCK(m) ? "a socket"
                         : "a special file";
}

/* Checks an open descriptor: regular, within the limit; then makes it blocking. */
static int check_fd(int fd, uint64_t limit, uint64_t *size, char *err, size_t errlen)
{
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        say(err, errlen, "%s", strerror(e));
        errno = e;
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        say(err, errlen, "it is %s, not a regular file", kind_of(st.st_mode));
        errno = S_ISDIR(st.st_mode) ? EISDIR : EINVAL;
        return -1;
    }
    if ((uint64_t)st.st_size > limit) {
        char a[32], b[32];
        bytes(a, sizeof a, (uint64_t)st.st_size);
        bytes(b, sizeof b, limit);
        say(err, errlen, "it is %s, over the %s limit", a, b);
        errno = EFBIG;
        return -1;
    }
    int fl = fcntl(fd, F_GETFL);
    if (fl < 0 || fcntl(fd, F_SETFL, fl & ~O_NONBLOCK) != 0) {
        int e = errno;
        say(err, errlen, "%s", strerror(e));
        errno = e;
        return -1;
    }
    if (size)
        *size = (uint64_t)st.st_size;
    return 0;
}

static int open_nb(const char *path, char *err, size_t errlen)
{
    if (!path || !path[0]) {
        say(err, errlen, "empty path");
        errno = EINVAL;
        return -1;
    }
    /* O_NONBLOCK: opening a FIFO with no writer must not hang; it is refused afterwards */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        say(err, errlen, "%s", strerror(e));
        errno = e;
    }
    return fd;
}

int lg_file_open(const char *path, uint64_t limit, uint64_t *size, char *err, size_t errlen)
{
    int fd = open_nb(path, err, errlen);
    if (fd < 0)
        return -1;
    if (check_fd(fd, limit, size, err, errlen) != 0) {
        int e = errno;
        close(fd);
        errno = e;
        return -1;
    }
    return fd;
}

/* Whether resolved (no links, absolute) is root or below it. */
static int inside(const char *root, const char *resolved)
{
    size_t n = strlen(root);
    if (n == 1 && root[0] == '/')
        return 1;
    return strncmp(resolved, root, n) == 0 && (resolved[n] == '/' || resolved[n] == 0);
}

/* path relative to root unless absolute; malloc'd. */
static char *joined(const char *root, const char *path)
{
    if (path[0] == '/')
        return strdup(path);
    size_t a = strlen(root), b = strlen(path);
    char *j = malloc(a + b + 2);
    if (!j)
        return NULL;
    memcpy(j, root, a);
    j[a] = '/';
    memcpy(j + a + 1, path, b + 1);
    return j;
}

/* The root resolved (into rroot, PATH_MAX bytes) and path joined to it (malloc'd), or NULL
 * with the reason in err. */
static char *resolve_join(const char *root, const char *path, char *rroot, char *err, size_t errlen)
{
    if (!root || !root[0] || !path || !path[0]) {
        say(err, errlen, "empty path");
        errno = EINVAL;
        return NULL;
    }
    if (!realpath(root, rroot)) {
        int e = errno;
        say(err, errlen, "its folder '%s' cannot be resolved: %s", root, strerror(e));
        errno = e;
        return NULL;
    }
    char *j = joined(rroot, path);
    if (!j) {
        say(err, errlen, "out of memory");
        errno = ENOMEM;
    }
    return j;
}

int lg_file_open_within(const char *root, const char *path, uint64_t limit, uint64_t *size,
                        char *err, size_t errlen)
{
    char rroot[PATH_MAX];
    char *j = resolve_join(root, path, rroot, err, errlen);
    if (!j)
        return -1;
    int fd = open_nb(j, err, errlen);
    free(j);
    if (fd < 0)
        return -1;
    /* Where the descriptor actually leads: the kernel's answer, immune to a link swapped
     * after a check. realpath of the joined path is the fallback without /proc. */
    char proc[64], real[PATH_MAX];
    snprintf(proc, sizeof proc, "/proc/self/fd/%d", fd);
    ssize_t r = readlink(proc, real, sizeof real - 1);
    if (r > 0) {
        real[r] = 0;
    } else {
        char *j2 = joined(rroot, path);
        char *ok = j2 ? realpath(j2, real) : NULL;
        free(j2);
        if (!ok) {
            int e = errno;
            say(err, errlen, "cannot be resolved: %s", strerror(e));
            close(fd);
            errno = e;
            return -1;
        }
    }
    if (!inside(rroot, real)) {
        say(err, errlen, "'%s' leads to '%s', outside '%s'", path, real, rroot);
        close(fd);
        errno = EACCES;
        return -1;
    }
    if (check_fd(fd, limit, size, err, errlen) != 0) {
        int e = errno;
        close(fd);
        errno = e;
        return -1;
    }
    return fd;
}

void *lg_file_read_fd(int fd, uint64_t size, size_t *len, char *err, size_t errlen)
{
    if (size >= SIZE_MAX) {
        say(err, errlen, "too large for this machine");
        errno = EFBIG;
        return NULL;
    }
    size_t cap = (size_t)size, n = 0;
    char *buf = malloc(cap + 1);
    if (!buf) {
        char a[32];
        bytes(a, sizeof a, size);
        say(err, errlen, "out of memory for %s", a);
        errno = ENOMEM;
        return NULL;
    }
    for (;;) {
        if (n == cap) {
            /* at the size fstat() gave: one more byte means it grew */
            char extra;
            ssize_t r = read(fd, &extra, 1);
            if (r == 0)
                break;
            if (r < 0 && errno == EINTR)
                continue;
            int e = errno;
            if (r < 0)
                say(err, errlen, "%s", strerror(e));
            else
                say(err, errlen, "it grew while being read");
            free(buf);
            errno = r < 0 ? e : EFBIG;
            return NULL;
        }
        ssize_t r = read(fd, buf + n, cap - n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            int e = errno;
            say(err, errlen, "%s", strerror(e));
            free(buf);
            errno = e;
            return NULL;
        }
        if (r == 0)
            break; /* it shrank: what is there is the file */
        n += (size_t)r;
    }
    buf[n] = 0;
    if (len)
        *len = n;
    return buf;
}

void *lg_file_read(const char *path, uint64_t limit, size_t *len, char *err, size_t errlen)
{
    uint64_t size = 0;
    int fd = lg_file_open(path, limit, &size, err, errlen);
    if (fd < 0)
        return NULL;
    void *b = lg_file_read_fd(fd, size, len, err, errlen);
    int e = errno;
    close(fd);
    errno = e;
    return b;
}

void *lg_file_read_within(const char *root, const char *path, uint64_t limit, size_t *len,
                          char *err, size_t errlen)
{
    uint64_t size = 0;
    int fd = lg_file_open_within(root, path, limit, &size, err, errlen);
    if (fd < 0)
        return NULL;
    void *b = lg_file_read_fd(fd, size, len, err, errlen);
    int e = errno;
    close(fd);
    errno = e;
    return b;
}

int lg_path_within(const char *root, const char *path, char *err, size_t errlen)
{
    char rroot[PATH_MAX], real[PATH_MAX];
    char *j = resolve_join(root, path, rroot, err, errlen);
    if (!j)
        return -1;
    char *ok = realpath(j, real);
    int e = errno;
    free(j);
    if (!ok) {
        say(err, errlen, "%s", strerror(e));
        errno = e;
        return -1;
    }
    if (!inside(rroot, real)) {
        say(err, errlen, "'%s' leads to '%s', outside '%s'", path, real, rroot);
        errno = EACCES;
        return -1;
    }
    return 0;
}
