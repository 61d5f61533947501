/*
 * The background build (rebuild.h): a child process in its own process group, its output
 * drained from a non-blocking pipe into a buffer that keeps the tail.
 */
#include "viewer/rebuild.h"

#include "base/util.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <spawn.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

struct lg_rebuild {
    pid_t pid; /* also the process group's id */
    int fd;    /* read end of the output pipe; -1 once closed */
    bool done;
    int status;
    char *log; /* the output's tail, NUL-terminated */
    size_t len;
};

/* How long lg_rebuild_free waits after SIGTERM before SIGKILL. */
#define REBUILD_TERM_WAIT_S 2.0

/* Looks for `name` on PATH like execvp would (an executable regular file); a name with a
 * '/' is taken as is. Returns a malloc'd path or NULL. */
static char *find_on_path(const char *name)
{
    if (strchr(name, '/'))
        return lg_xstrdup(name);
    const char *path = getenv("PATH");
    if (!path)
        path = "/usr/local/bin:/usr/bin:/bin";
    for (const char *p = path;;) {
        const char *end = strchr(p, ':');
        size_t n = end ? (size_t)(end - p) : strlen(p);
        char *dir = n ? lg_xstrndup(p, n) : lg_xstrdup(".");
        char *cand = lg_path_join(dir, name);
        free(dir);
        struct stat st;
        if (stat(cand, &st) == 0 && S_ISREG(st.st_mode) && access(cand, X_OK) == 0)
            return cand;
        free(cand);
        if (!end)
            return NULL;
        p = end + 1;
    }
}

/* The command line: LIGHTGRAPH_REBUILD's words, or ninja -C build_dir. NULL-terminated,
 * malloc'd strings in a malloc'd array; NULL (err) when it is empty. */
static char **command_line(const char *build_dir, uint32_t *argc)
{
    const char *env = getenv("LIGHTGRAPH_REBUILD");
    char **argv;
    uint32_t n = 0;
    if (env && env[strspn(env, " ")]) {
        argv = lg_xcalloc(strlen(env) / 2 + 2, sizeof *argv);
        for (const char *p = env; *p;) {
            p += strspn(p, " ");
            size_t k = strcspn(p, " ");
            if (k)
                argv[n++] = lg_xstrndup(p, k);
            p += k;
        }
    } else {
        argv = lg_xcalloc(4, sizeof *argv);
        argv[n++] = lg_xstrdup("ninja");
        argv[n++] = lg_xstrdup("-C");
        argv[n++] = lg_xstrdup(build_dir);
    }
    argv[n] = NULL;
    *argc = n;
    return argv;
}

static void free_argv(char **argv)
{
    for (char **a = argv; *a; a++)
        free(*a);
    free(argv);
}

int lg_rebuild_start(lg_rebuild **out, const char *build_dir, char *err, size_t errlen)
{
    *out = NULL;
    uint32_t argc;
    char **argv = command_line(build_dir, &argc);
    char *exe = find_on_path(argv[0]);
    if (!exe) {
        snprintf(err, errlen, "%s not found on PATH%s", argv[0],
                 getenv("LIGHTGRAPH_REBUILD") && strcmp(argv[0], "ninja") != 0
                     ? " (from LIGHTGRAPH_REBUILD)"
                     : "");
        free_argv(argv);
        return -1;
    }
    int pfd[2];
    if (pipe2(pfd, O_CLOEXEC) != 0) {
        snprintf(err, errlen, "cannot run %s: pipe: %s", exe, strerror(errno));
        free(exe);
        free_argv(argv);
        return -1;
    }
    posix_spawn_file_actions_t fa;
    posix_spawnattr_t attr;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    /* dup2 clears close-on-exec on the copies: the child keeps 1 and 2, nothing else */
    posix_spawn_file_actions_adddup2(&fa, pfd[1], 1);
    posix_spawn_file_actions_adddup2(&fa, pfd[1], 2);
    posix_spawnattr_init(&attr);
    /* its own process group, so that lg_rebuild_free stops the compilers too; default
     * signal handlers and an empty mask whatever the viewer set up */
    sigset_t none, all;
    sigemptyset(&none);
    sigfillset(&all);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &all);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK |
                                        POSIX_SPAWN_SETSIGDEF);
    pid_t pid;
    int e = posix_spawn(&pid, exe, &fa, &attr, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    posix_spawnattr_destroy(&attr);
    close(pfd[1]);
    if (e != 0) {
        snprintf(err, errlen, "cannot run %s: %s", exe, strerror(e));
        close(pfd[0]);
        free(exe);
        free_argv(argv);
        return -1;
    }
    fcntl(pfd[0], F_SETFL, fcntl(pfd[0], F_GETFL) | O_NONBLOCK);
    lg_hlog(LG_HINFO, "rebuild: started %s (pid %d)", exe, (int)pid);
    free(exe);
    free_argv(argv);
    lg_rebuild *r = lg_xcalloc(1, sizeof *r);
    r->pid = pid;
    r->fd = pfd[0];
    r->log = lg_xmalloc(2 * LG_REBUILD_LOG_MAX + 1);
    r->log[0] = 0;
    *out = r;
    return 0;
}

/* Reads what the pipe holds into the log, keeping the tail; closes it at end of file. */
static void drain(lg_rebuild *r)
{
    while (r->fd >= 0) {
        /* room for up to LG_REBUILD_LOG_MAX more bytes after the kept tail */
        if (r->len > LG_REBUILD_LOG_MAX) {
            memmove(r->log, r->log + r->len - LG_REBUILD_LOG_MAX, LG_REBUILD_LOG_MAX);
            r->len = LG_REBUILD_LOG_MAX;
        }
        ssize_t n = read(r->fd, r->log + r->len, 2 * LG_REBUILD_LOG_MAX - r->len);
        if (n > 0) {
            r->len += (size_t)n;
            continue;
        }
        if (n < 0 && errno == EINTR)
            continue;
        if (n == 0 || errno != EAGAIN) {
            close(r->fd);
            r->fd = -1;
        }
        break;
    }
    if (r->len > LG_REBUILD_LOG_MAX) {
        memmove(r->log, r->log + r->len - LG_REBUILD_LOG_MAX, LG_REBUILD_LOG_MAX);
        r->len = LG_REBUILD_LOG_MAX;
    }
    r->log[r->len] = 0;
}

static int decode_status(int ws)
{
    if (WIFEXITED(ws))
        return WEXITSTATUS(ws);
    if (WIFSIGNALED(ws))
        return 128 + WTERMSIG(ws);
    return 255;
}

int lg_rebuild_poll(lg_rebuild *r, int *status, const char **log)
{
    if (!r->done) {
        drain(r);
        int ws;
        pid_t p = waitpid(r->pid, &ws, WNOHANG);
        if (p == r->pid || (p < 0 && errno == ECHILD)) {
            /* Ended. What it wrote before exiting is in the pipe already; a process it left
             * behind holding the pipe open is not waited for. */
            drain(r);
            if (r->fd >= 0) {
                close(r->fd);
                r->fd = -1;
            }
            r->done = true;
            /* ECHILD: somebody else reaped it (SIGCHLD ignored); its status is lost */
            r->status = p == r->pid ? decode_status(ws) : 255;
        }
    }
    if (!r->done)
        return 0;
    if (status)
        *status = r->status;
    if (log)
        *log = r->log;
    return 1;
}

void lg_rebuild_free(lg_rebuild **rp)
{
    lg_rebuild *r = rp ? *rp : NULL;
    if (!r)
        return;
    if (!r->done) {
        kill(-r->pid, SIGTERM);
        double t0 = lg_mono_now();
        bool reaped = false;
        while (!reaped && lg_mono_now() - t0 < REBUILD_TERM_WAIT_S) {
            pid_t p = waitpid(r->pid, NULL, WNOHANG);
            if (p == r->pid || (p < 0 && errno != EINTR)) {
                reaped = true;
                break;
            }
            nanosleep(&(struct timespec){ 0, 10 * 1000 * 1000 }, NULL);
        }
        /* the leader may be gone while the group lives on (a compiler that ignores
         * SIGTERM): SIGKILL whatever is left of it, then reap the leader */
        kill(-r->pid, SIGKILL);
        if (!reaped)
            while (waitpid(r->pid, NULL, 0) < 0 && errno == EINTR) {
            }
    }
    if (r->fd >= 0)
        close(r->fd);
    free(r->log);
    free(r);
    *rp = NULL;
}

/* realpath into a malloc'd string, or NULL. */
static char *resolved(const char *path)
{
    char buf[PATH_MAX];
    return realpath(path, buf) ? lg_xstrdup(buf) : NULL;
}

char *lg_rebuild_dev_build_dir(void)
{
    char *root = resolved(LG_BUILD_ROOT);
    if (!root)
        return NULL;
    char *ninja = lg_path_join(root, "build.ninja");
    char *exe = resolved("/proc/self/exe");
    bool ok = lg_path_exists(ninja) && exe && strncmp(exe, root, strlen(root)) == 0 &&
              exe[strlen(root)] == '/';
    free(ninja);
    free(exe);
    if (!ok) {
        free(root);
        return NULL;
    }
    return root;
}

char *lg_rebuild_dev_shader_dir(void)
{
    char *build = lg_rebuild_dev_build_dir();
    if (!build)
        return NULL;
    free(build);
    char *dir = resolved(LG_SOURCE_ROOT "/shaders");
    struct stat st;
    if (dir && (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))) {
        free(dir);
        return NULL;
    }
    return dir;
}
