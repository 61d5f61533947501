/*
 * host/viewer/rebuild.c: the background build, run here with LIGHTGRAPH_REBUILD naming scripts in
 * the test's temporary directory.
 *
 *   status        a script that prints (stdout and stderr), sleeps 0.2 s and exits 3: poll
 *                 says 0 while it runs, then 1 with status 3 and the text, on every call
 *   signal        a script that kills itself with SIGKILL: status 128 + 9
 *   tail          over 64 KiB of output: the last 64 KiB kept, ending with the last line
 *   free_running  freed while running: returns within ~3 s, no zombie (waitpid: ECHILD),
 *                 its child process (the same process group) is gone too; also for one that
 *                 ignores SIGTERM (the SIGKILL after 2 s)
 *   not_found     no ninja on PATH, a missing LIGHTGRAPH_REBUILD program: clear errors
 *   dev_dirs      this test runs inside the build tree: the build directory and the source
 *                 tree's shaders/ are found
 */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "common/check.h"
#include "viewer/rebuild.h"
#include "base/util.h"

static char tmp[256];

/* Writes an executable script and returns its path (caller frees). */
static char *script(const char *name, const char *body)
{
    char *p = lg_path_join(tmp, name);
    char *text = lg_xasprintf("#!/bin/sh\n%s\n", body);
    FILE *f = fopen(p, "w");
    CHECKF(f != NULL, "%s: %s", p, strerror(errno));
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    chmod(p, 0755);
    free(text);
    return p;
}

static lg_rebuild *start(const char *command)
{
    setenv("LIGHTGRAPH_REBUILD", command, 1);
    char err[512] = "";
    lg_rebuild *r = NULL;
    CHECKF(lg_rebuild_start(&r, "/nonexistent-build-dir", err, sizeof err) == 0, "start %s: %s",
           command, err);
    return r;
}

/* Polls every 10 ms until done or 10 s; returns poll's last result. */
static int wait_done(lg_rebuild *r, int *status, const char **log, double *elapsed)
{
    double t0 = lg_mono_now();
    int done = 0;
    while (!(done = lg_rebuild_poll(r, status, log)) && lg_mono_now() - t0 < 10)
        nanosleep(&(struct timespec){ 0, 10 * 1000 * 1000 }, NULL);
    if (elapsed)
        *elapsed = lg_mono_now() - t0;
    return done;
}

static void test_status(void)
{
    char *s = script("exit3.sh", "echo 'building: step 1 of 2'\n"
                                 "echo 'warning: on stderr' >&2\n"
                                 "sleep 0.2\n"
                                 "echo 'FAILED: shaders/phong/lit.frag'\n"
                                 "exit 3");
    /* split on spaces: the interpreter and the script */
    char *cmd = lg_xasprintf("/bin/sh %s", s);
    double t0 = lg_mono_now();
    lg_rebuild *r = start(cmd);
    if (r) {
        int status = -1;
        const char *log = NULL;
        int first = lg_rebuild_poll(r, &status, &log);
        CHECKF(first == 0 || lg_mono_now() - t0 >= 0.2, "poll said done at once");
        double elapsed;
        CHECK(wait_done(r, &status, &log, &elapsed) == 1);
        CHECKF(lg_mono_now() - t0 >= 0.2, "done after %.3f s, before the script's sleep",
               lg_mono_now() - t0);
        CHECKF(status == 3, "status %d", status);
        CHECKF(log && strstr(log, "building: step 1 of 2\n") &&
                   strstr(log, "warning: on stderr\n") &&
                   strstr(log, "FAILED: shaders/phong/lit.frag\n"),
               "log: %s", log ? log : "(null)");
        /* and on every later call */
        status = -1;
        CHECK(lg_rebuild_poll(r, &status, NULL) == 1 && status == 3);
        CHECK(lg_rebuild_poll(r, NULL, NULL) == 1);
    }
    lg_rebuild_free(&r);
    CHECK(r == NULL);
    lg_rebuild_free(&r); /* NULL is fine */
    free(cmd);
    free(s);

    /* a succeeding one, found on PATH by name */
    r = start("true");
    int status = -1;
    if (r)
        CHECK(wait_done(r, &status, NULL, NULL) == 1 && status == 0);
    lg_rebuild_free(&r);
}

static void test_signal(void)
{
    char *s = script("killself.sh", "echo before\nkill -9 $$\necho after");
    lg_rebuild *r = start(s);
    int status = -1;
    const char *log = NULL;
    if (r) {
        CHECK(wait_done(r, &status, &log, NULL) == 1);
        CHECKF(status == 128 + SIGKILL, "status %d", status);
        CHECKF(log && strstr(log, "before") && !strstr(log, "after"), "log: %s", log);
    }
    lg_rebuild_free(&r);
    free(s);
}

static void test_tail(void)
{
    /* 10000 lines of 11 bytes (110000), then the last line */
    char *s = script("loud.sh",
                     "i=0\nwhile [ $i -lt 10000 ]; do echo 0123456789; i=$((i+1)); done\n"
                     "echo 'the last line'");
    lg_rebuild *r = start(s);
    int status = -1;
    const char *log = NULL;
    if (r) {
        CHECK(wait_done(r, &status, &log, NULL) == 1 && status == 0);
        size_t len = log ? strlen(log) : 0;
        CHECKF(len == LG_REBUILD_LOG_MAX, "log of %zu bytes", len);
        const char *end = "0123456789\nthe last line\n";
        CHECKF(len >= strlen(end) && strcmp(log + len - strlen(end), end) == 0, "log ends: %s",
               len > 40 ? log + len - 40 : log);
    }
    lg_rebuild_free(&r);
    free(s);
}

/* Whether a process with this pid runs: a zombie does not (in a container nobody may reap
 * the orphans), and neither does a pid taken by another program meanwhile (its name). */
static bool alive(pid_t pid)
{
    char path[64], line[256] = "";
    snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    bool ok = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    const char *close_paren = strrchr(line, ')');
    return ok && strstr(line, "(sleep)") && close_paren && close_paren[1] == ' ' &&
           close_paren[2] != 'Z';
}

static void free_running(const char *name, const char *body, double max_s)
{
    char *pidfile = lg_path_join(tmp, "child.pid");
    unlink(pidfile);
    /* the child process `sleep` writes nothing; its pid goes to a file */
    char *text = lg_xasprintf(body, pidfile);
    char *s = script(name, text);
    lg_rebuild *r = start(s);
    if (!r)
        goto out;
    /* wait until the script has started its child */
    double t0 = lg_mono_now();
    pid_t child = 0;
    while (!child && lg_mono_now() - t0 < 10) {
        FILE *f = fopen(pidfile, "r");
        long v = 0;
        if (f) {
            if (fscanf(f, "%ld", &v) == 1)
                child = (pid_t)v;
            fclose(f);
        }
        if (!child)
            nanosleep(&(struct timespec){ 0, 10 * 1000 * 1000 }, NULL);
    }
    CHECKF(child > 0, "%s: the script did not start its child", name);
    CHECK(lg_rebuild_poll(r, NULL, NULL) == 0);
    double t1 = lg_mono_now();
    lg_rebuild_free(&r);
    double took = lg_mono_now() - t1;
    CHECKF(took < max_s, "%s: lg_rebuild_free took %.2f s", name, took);
    errno = 0;
    CHECKF(waitpid(-1, NULL, WNOHANG) == -1 && errno == ECHILD,
           "%s: a child is left to reap (errno %d)", name, errno);
    /* the grandchild got the signal too (it is reparented, not ours to reap: give init a
     * moment) */
    if (child > 0) {
        double t2 = lg_mono_now();
        while (alive(child) && lg_mono_now() - t2 < 5)
            nanosleep(&(struct timespec){ 0, 10 * 1000 * 1000 }, NULL);
        CHECKF(!alive(child), "%s: the build's child %d still runs", name, (int)child);
    }
out:
    free(s);
    free(text);
    free(pidfile);
}

static void test_free_running(void)
{
    free_running("long.sh", "sleep 30 &\necho $! > %s\nwait\necho never", 3.0);
    /* ignores SIGTERM, its child too (an ignored signal stays ignored across exec) */
    free_running("stubborn.sh", "trap '' TERM\nsleep 30 &\necho $! > %s\nwait\nwait\nwait", 4.0);
}

static void test_not_found(void)
{
    char err[512] = "";
    lg_rebuild *r = NULL;
    unsetenv("LIGHTGRAPH_REBUILD");
    char *old_path = getenv("PATH") ? lg_xstrdup(getenv("PATH")) : NULL;
    setenv("PATH", tmp, 1); /* holds scripts, no ninja */
    CHECK(lg_rebuild_start(&r, "/some/build", err, sizeof err) == -1 && r == NULL);
    CHECKF(strstr(err, "ninja not found on PATH"), "err: %s", err);
    if (old_path)
        setenv("PATH", old_path, 1);
    free(old_path);

    char *missing = lg_path_join(tmp, "no-such-tool");
    setenv("LIGHTGRAPH_REBUILD", missing, 1);
    err[0] = 0;
    CHECK(lg_rebuild_start(&r, "/some/build", err, sizeof err) == -1 && r == NULL);
    CHECKF(strstr(err, missing) && strstr(err, "No such file"), "err: %s", err);
    setenv("LIGHTGRAPH_REBUILD", "no-such-tool-on-path --flag", 1);
    err[0] = 0;
    CHECK(lg_rebuild_start(&r, "/some/build", err, sizeof err) == -1 && r == NULL);
    CHECKF(strstr(err, "no-such-tool-on-path not found on PATH (from LIGHTGRAPH_REBUILD)"),
           "err: %s", err);
    free(missing);
}

static void test_dev_dirs(void)
{
    char want[PATH_MAX], src[PATH_MAX];
    const char *build = getenv("LG_BUILD_ROOT"), *source = getenv("LG_SOURCE_ROOT");
    char *dir = lg_rebuild_dev_build_dir();
    char *shaders = lg_rebuild_dev_shader_dir();
    if (build && realpath(build, want))
        CHECKF(dir && strcmp(dir, want) == 0, "build dir %s, want %s", dir ? dir : "(null)", want);
    else
        CHECKF(build, "LG_BUILD_ROOT is not set (run through meson test)");
    if (source && realpath(source, src)) {
        char *w2 = lg_path_join(src, "shaders");
        CHECKF(shaders && strcmp(shaders, w2) == 0, "shader dir %s, want %s",
               shaders ? shaders : "(null)", w2);
        free(w2);
    } else {
        CHECKF(source, "LG_SOURCE_ROOT is not set (run through meson test)");
    }
    free(dir);
    free(shaders);
}

int main(void)
{
    const char *base = getenv("TMPDIR");
    snprintf(tmp, sizeof tmp, "%s/lg-rebuild-XXXXXX", base && *base ? base : "/tmp");
    if (!mkdtemp(tmp)) {
        fprintf(stderr, "mkdtemp %s: %s\n", tmp, strerror(errno));
        return 1;
    }
    test_status();
    test_signal();
    test_tail();
    test_free_running();
    test_not_found();
    test_dev_dirs();
    char *cmd = lg_xasprintf("rm -rf '%s'", tmp);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", tmp);
    free(cmd);
    return check_report("rebuild");
}
