/* liblightgraph-test: cases, checks, scratch folders, files, running the host (see
 * lightgraph/test.h). Backend comparison and the bench table are in backends.c. */
#include "test_priv.h"

#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <ftw.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

/* The cases whose scratch folder exists now (made by test_new, forgotten when removed or
 * freed), so that any exit of the harness names each folder it leaves behind: a test that
 * ends with 99 or a failed asset otherwise leaves folders nobody can find. */
static lg_test *live_tests;

static void live_add(lg_test *t)
{
    t->next_live = live_tests;
    live_tests = t;
}

static void live_remove(lg_test *t)
{
    for (lg_test **p = &live_tests; *p; p = &(*p)->next_live)
        if (*p == t) {
            *p = t->next_live;
            return;
        }
}

static void name_kept_folders(void)
{
    for (const lg_test *t = live_tests; t; t = t->next_live)
        fprintf(stderr, "lightgraph-test: scratch folder kept: %s\n", t->dir);
}

void lg_test_die_(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lightgraph-test: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    name_kept_folders();
    exit(LG_TEST_ERROR); /* meson: a hard error, not a test failure */
}

/* ---- checks ---------------------------------------------------------------------------------- */

void lg_test_fail_at(lg_test *t, const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s:%d: check failed: ", file, line);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    t->failures++;
}

void lg_test_failf_(lg_test *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lightgraph-test: check failed: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    t->failures++;
}

void lg_test_check_failed_(lg_test *t, const char *file, int line, const char *cond)
{
    fprintf(stderr, "%s:%d: check failed: %s: ", file, line, cond);
    t->failures++;
}

void lg_test_note_(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

int lg_test_failures(const lg_test *t)
{
    return t->failures;
}

/* ---- scratch folders ------------------------------------------------------------------------- */

static int scratch_make(const char *name, char *dir, size_t n)
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
        fprintf(stderr, "lightgraph-test: cannot make %s: %s\n", base, strerror(errno));
        return -1;
    }
    snprintf(dir, n, "%s/%s-XXXXXX", base, name);
    if (!mkdtemp(dir)) {
        fprintf(stderr, "lightgraph-test: cannot make a folder like %s: %s\n", dir,
                strerror(errno));
        return -1;
    }
    return 0;
}

static int remove_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb;
    (void)flag;
    (void)ftw;
    return remove(path);
}

static void scratch_remove(const char *dir)
{
    if (nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS) != 0)
        fprintf(stderr, "lightgraph-test: could not remove all of %s\n", dir);
}

/* ---- cases ----------------------------------------------------------------------------------- */

static lg_test *test_new(const char *name)
{
    lg_test *t = calloc(1, sizeof *t);
    if (!t)
        lg_test_die_("out of memory");
    if (scratch_make(name, t->dir, sizeof t->dir)) {
        name_kept_folders();
        exit(LG_TEST_ERROR);
    }
    live_add(t);
    return t;
}

/* Removes the case's folder and forgets it. */
static void test_remove_dir(lg_test *t)
{
    scratch_remove(t->dir);
    live_remove(t);
}

lg_test *lg_test_begin(const char *name)
{
    return test_new(name);
}

/* 0 or 1; removes the folder unless a check failed. */
static int test_finish(lg_test *t)
{
    if (t->failures) {
        fprintf(stderr, "%d check(s) failed; files kept in %s\n", t->failures, t->dir);
        live_remove(t); /* named once, here */
        return LG_TEST_FAIL;
    }
    test_remove_dir(t);
    return LG_TEST_PASS;
}

int lg_test_end(lg_test **t)
{
    if (!t || !*t)
        return LG_TEST_ERROR;
    int rc = test_finish(*t);
    live_remove(*t);
    free(*t);
    *t = NULL;
    return rc;
}

void lg_test_skip(lg_test *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "skipped: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    if (t && t->can_jump)
        longjmp(t->skip_jump, 1); /* back to run_one(), which cleans up */
    if (t && t->failures) {
        fprintf(stderr, "(but %d check(s) had failed already; files kept in %s)\n", t->failures,
                t->dir);
        live_remove(t);
        name_kept_folders();
        exit(LG_TEST_FAIL);
    }
    if (t)
        test_remove_dir(t);
    name_kept_folders();
    exit(LG_TEST_SKIP);
}

/* Runs one case in its folder; returns 0, 1 or 77. */
static int run_one(const lg_test_case *c, const char *folder, void (*setup)(lg_test *t),
                   char **args, int n_args, uint32_t bench_frames)
{
    lg_test *t = test_new(folder ? folder : c->name);
    t->args = args;
    t->n_args = n_args;
    t->bench_frames = bench_frames;
    t->can_jump = true;
    int rc;
    if (setjmp(t->skip_jump) == 0) {
        if (setup)
            setup(t);
        c->run(t);
        t->can_jump = false;
        rc = test_finish(t);
    } else {
        t->can_jump = false;
        if (t->failures) {
            fprintf(stderr, "(but %d check(s) had failed already)\n", t->failures);
            rc = test_finish(t);
        } else {
            test_remove_dir(t);
            rc = LG_TEST_SKIP;
        }
    }
    live_remove(t);
    free(t);
    return rc;
}

int lg_test_run_case(const char *prog, const char *name, const lg_test_case *cases, size_t n,
                     const char *folder, void (*setup)(lg_test *t))
{
    for (size_t i = 0; i < n; i++)
        if (strcmp(name, cases[i].name) == 0)
            return run_one(&cases[i], folder, setup, NULL, 0, 0);
    fprintf(stderr, "%s: unknown case '%s'\n", prog, name);
    return LG_TEST_ERROR;
}

static const lg_test_case *find_case(const lg_test_case *cases, size_t n, const char *name)
{
    for (size_t i = 0; i < n; i++)
        if (strcmp(name, cases[i].name) == 0)
            return &cases[i];
    return NULL;
}

static int main_usage(const char *prog)
{
    fprintf(stderr,
            "usage: %s CASE [ARG...]        run one case\n"
            "       %s --all                run every case\n"
            "       %s --list               list the cases\n"
            "       %s --bench[=N] [CASE...] time each backend over N frames (default 30)\n",
            prog, prog, prog, prog);
    return LG_TEST_ERROR;
}

int lg_test_main(int argc, char **argv, const lg_test_case *cases, size_t n,
                 const lg_test_main_opts *opts)
{
    const char *prog = argc > 0 ? argv[0] : "test";
    const char *slash = strrchr(prog, '/');
    prog = slash ? slash + 1 : prog;
    const char *prefix = opts ? opts->prefix : NULL;
    void (*setup)(lg_test *) = opts ? opts->setup : NULL;
    if (argc < 2)
        return main_usage(prog);

    char folder[256];
    if (strcmp(argv[1], "--list") == 0) {
        for (size_t i = 0; i < n; i++)
            printf("%s\n", cases[i].name);
        return 0;
    }
    bool all = strcmp(argv[1], "--all") == 0;
    bool bench = strncmp(argv[1], "--bench", 7) == 0 && (argv[1][7] == 0 || argv[1][7] == '=');
    if (all || bench) {
        uint32_t frames = 0;
        if (bench) {
            frames = 30;
            if (argv[1][7] == '=') {
                char *end;
                long v = strtol(argv[1] + 8, &end, 10);
                if (*end || v < 1 || v > 100000)
                    return main_usage(prog);
                frames = (uint32_t)v;
            }
        }
        if (all && argc > 2)
            return main_usage(prog);
        int failed = 0, passed = 0, skipped = 0;
        size_t count = argc > 2 ? (size_t)(argc - 2) : n;
        for (size_t i = 0; i < count; i++) {
            const lg_test_case *c = argc > 2 ? find_case(cases, n, argv[2 + i]) : &cases[i];
            if (!c) {
                fprintf(stderr, "%s: unknown case '%s'\n", prog, argv[2 + i]);
                return LG_TEST_ERROR;
            }
            if (prefix)
                snprintf(folder, sizeof folder, "%s-%s", prefix, c->name);
            fprintf(stderr, "== %s\n", c->name);
            int rc = run_one(c, prefix ? folder : NULL, setup, NULL, 0, frames);
            failed += rc == LG_TEST_FAIL;
            passed += rc == LG_TEST_PASS;
            skipped += rc == LG_TEST_SKIP;
        }
        fprintf(stderr, "%s: %d passed, %d failed, %d skipped\n", prog, passed, failed, skipped);
        return failed ? LG_TEST_FAIL : passed ? LG_TEST_PASS : LG_TEST_SKIP;
    }
    if (argv[1][0] == '-')
        return main_usage(prog);
    const lg_test_case *c = find_case(cases, n, argv[1]);
    if (!c) {
        fprintf(stderr, "%s: unknown case '%s'\n", prog, argv[1]);
        return LG_TEST_ERROR;
    }
    if (prefix)
        snprintf(folder, sizeof folder, "%s-%s", prefix, c->name);
    return run_one(c, prefix ? folder : NULL, setup, argv + 2, argc - 2, 0);
}

const char *lg_test_arg(const lg_test *t, int i)
{
    return i >= 0 && i < t->n_args ? t->args[i] : NULL;
}

uint32_t lg_test_bench_frames(const lg_test *t)
{
    return t->bench_frames;
}

/* ---- files ----------------------------------------------------------------------------------- */

const char *lg_test_dir(const lg_test *t)
{
    return t->dir;
}

const char *lg_test_path(lg_test *t, const char *rel)
{
    /* built aside: `rel` may itself be an earlier string of the ring */
    char tmp[sizeof t->ring[0]];
    snprintf(tmp, sizeof tmp, "%s/%s", t->dir, rel);
    char *p = t->ring[t->next++ % 8];
    memcpy(p, tmp, sizeof tmp);
    return p;
}

void lg_test_write_text(lg_test *t, const char *rel, const char *text)
{
    const char *p = lg_test_path(t, rel);
    FILE *f = fopen(p, "w");
    if (!f || fputs(text, f) < 0 || fclose(f))
        lg_test_die_("cannot write %s: %s", p, strerror(errno));
}

void lg_test_write_exr(lg_test *t, const char *rel, const lg_image *img)
{
    const char *p = lg_test_path(t, rel);
    char err[512];
    lg_image_write_opts o;
    memset(&o, 0, sizeof o);
    o.exr_pixel = LG_EXR_FLOAT;
    o.exr_compression = LG_EXR_NONE;
    if (lg_image_write(p, img, &o, err, sizeof err))
        lg_test_die_("%s", err);
}

bool lg_test_read(lg_test *t, const char *rel, lg_image *img, unsigned *bits)
{
    char err[512];
    lg_image_read_info info;
    memset(&info, 0, sizeof info);
    memset(img, 0, sizeof *img);
    if (lg_image_read(lg_test_path(t, rel), 0, img, &info, err, sizeof err)) {
        lg_test_failf_(t, "%s", err);
        memset(img, 0, sizeof *img);
        return false;
    }
    if (bits)
        *bits = info.bits;
    return true;
}

const char *lg_test_asset(const char *rel)
{
    static char p[4200];
    const char *root = getenv("LG_SOURCE_ROOT");
    /* a repository file is never optional: missing is a failure, never a quieter test */
    if (!root || !*root) {
        fprintf(stderr, "FAIL: asset %s: LG_SOURCE_ROOT is not set (the build sets it)\n", rel);
        name_kept_folders();
        exit(1);
    }
    snprintf(p, sizeof p, "%s/assets/%s", root, rel);
    if (access(p, R_OK) != 0) {
        fprintf(stderr, "FAIL: asset %s is missing or unreadable\n", p);
        name_kept_folders();
        exit(1);
    }
    return p;
}

/* ---- running the host ------------------------------------------------------------------------ */

/* The program installed with this library: <this library's folder>/LG_TEST_EXE_FROM_LIBDIR
 * (../../bin/lightgraph from lib/x86_64-linux-gnu), when the library sits in an installed
 * <libdir> (its folder ends in LG_TEST_LIBDIR) and the program is there. Found from the
 * library's own file, so that a prefix moved or installed with --destdir runs its own host,
 * never another installation's. NULL otherwise (a build tree, a non-relocatable prefix). */
static const char *exe_beside_library(void)
{
    static char path[PATH_MAX + 64];
    static int done;
    if (done)
        return *path ? path : NULL;
    done = 1;
    Dl_info info;
    char lib[PATH_MAX];
    if (!*LG_TEST_EXE_FROM_LIBDIR || !dladdr((void *)&lg_test_exe, &info) || !info.dli_fname ||
        !realpath(info.dli_fname, lib))
        return NULL;
    char *slash = strrchr(lib, '/');
    if (!slash)
        return NULL;
    *slash = 0;
    size_t ll = strlen(lib), dl = strlen(LG_TEST_LIBDIR);
    if (ll < dl + 1 || strcmp(lib + ll - dl, LG_TEST_LIBDIR) || lib[ll - dl - 1] != '/')
        return NULL;
    char rel[sizeof path];
    snprintf(rel, sizeof rel, "%s/%s", lib, LG_TEST_EXE_FROM_LIBDIR);
    /* resolved, so that messages name .../bin/lightgraph, not .../lib/../../bin/lightgraph */
    if (!realpath(rel, path) || access(path, X_OK) != 0) {
        *path = 0;
        return NULL;
    }
    return path;
}

const char *lg_test_exe(void)
{
    const char *exe = getenv("LG_EXE");
    if (exe && *exe)
        return exe;
    const char *beside = exe_beside_library();
    return beside ? beside : LG_TEST_DEFAULT_EXE;
}

/* Where lg_test_exe() came from, for the message when it cannot start. */
static const char *exe_origin(void)
{
    const char *exe = getenv("LG_EXE");
    if (exe && *exe)
        return "$LG_EXE";
    return exe_beside_library() ? "installed beside liblightgraph-test"
                                : "the prefix liblightgraph-test was built for";
}

/* "SIGSEGV" for 11: a CI log should name the signal, not only its number. */
static const char *signal_name(int sig)
{
    static const struct {
        int sig;
        const char *name;
    } names[] = {
        { SIGSEGV, "SIGSEGV" }, { SIGBUS, "SIGBUS" },   { SIGFPE, "SIGFPE" },
        { SIGILL, "SIGILL" },   { SIGABRT, "SIGABRT" }, { SIGKILL, "SIGKILL" },
        { SIGTERM, "SIGTERM" }, { SIGINT, "SIGINT" },   { SIGHUP, "SIGHUP" },
        { SIGPIPE, "SIGPIPE" }, { SIGALRM, "SIGALRM" }, { SIGTRAP, "SIGTRAP" },
        { SIGXCPU, "SIGXCPU" }, { SIGXFSZ, "SIGXFSZ" }, { SIGQUIT, "SIGQUIT" },
        { SIGSYS, "SIGSYS" },
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (names[i].sig == sig)
            return names[i].name;
    return "SIG?";
}

int lg_test_spawn_(const char *const *argv, const char *cwd, char **out)
{
    int fd[2];
    if (pipe(fd))
        lg_test_die_("pipe: %s", strerror(errno));
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fd[1], 1);
    posix_spawn_file_actions_adddup2(&fa, fd[1], 2);
    posix_spawn_file_actions_addclose(&fa, fd[0]);
    posix_spawn_file_actions_addclose(&fa, fd[1]);
    /* the child starts in `cwd`: relative paths of the graph and -o resolve there. (Not
     * thread-safe, as the header says.) */
    char here[4096];
    if (cwd && !getcwd(here, sizeof here))
        lg_test_die_("getcwd: %s", strerror(errno));
    if (cwd && chdir(cwd))
        lg_test_die_("cannot enter %s: %s", cwd, strerror(errno));
    pid_t pid;
    int rc = posix_spawn(&pid, argv[0], &fa, NULL, (char *const *)argv, environ);
    if (cwd && chdir(here))
        lg_test_die_("cannot return to %s: %s", here, strerror(errno));
    posix_spawn_file_actions_destroy(&fa);
    close(fd[1]);
    if (rc) {
        close(fd[0]);
        lg_test_die_("cannot run %s (%s): %s (set LG_EXE to the lightgraph program)", argv[0],
                     strcmp(argv[0], lg_test_exe()) ? "a program" : exe_origin(), strerror(rc));
    }
    size_t len = 0, cap = 4096;
    char *text = malloc(cap);
    if (!text)
        lg_test_die_("out of memory");
    for (;;) {
        if (len + 1024 > cap) {
            char *bigger = realloc(text, cap *= 2);
            if (!bigger)
                lg_test_die_("out of memory");
            text = bigger;
        }
        ssize_t got = read(fd[0], text + len, cap - len - 1);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            break;
        len += (size_t)got;
    }
    text[len] = 0;
    close(fd[0]);
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            lg_test_die_("waitpid: %s", strerror(errno));
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code != 0 || getenv("LG_TEST_VERBOSE")) {
        fprintf(stderr, "$");
        for (int i = 0; argv[i]; i++)
            fprintf(stderr, " %s", argv[i]);
        if (WIFSIGNALED(status))
            fprintf(stderr, "\n-> killed by signal %d (%s: %s)%s\n%s", WTERMSIG(status),
                    signal_name(WTERMSIG(status)), strsignal(WTERMSIG(status)),
                    WCOREDUMP(status) ? ", core dumped" : "", text);
        else
            fprintf(stderr, "\n-> exit %d\n%s", code, text);
    }
    /* 127: the program never ran its main. The dynamic loader (a missing or unloadable
     * shared library) or the shell says why in the output; that is the cause to name, not
     * what the caller would guess from a failed command (a plugin not found, no device). */
    if (WIFEXITED(status) && code == 127) {
        char why[2048]; /* copied, so that nothing is left allocated at the exit */
        snprintf(why, sizeof why, "%s", *text ? text : "no message: is it a lightgraph program?");
        free(text);
        size_t l = strlen(why);
        while (l && why[l - 1] == '\n')
            why[--l] = 0;
        lg_test_die_("%s (%s) could not start (exit 127, it never ran): %s", argv[0],
                     strcmp(argv[0], lg_test_exe()) ? "a program" : exe_origin(), why);
    }
    if (out)
        *out = text;
    else
        free(text);
    return code;
}

int lg_test_render(lg_test *t, const char *graph, const char *const *args, char **out)
{
    const char *argv[72];
    int n = 0;
    argv[n++] = lg_test_exe();
    argv[n++] = "render";
    argv[n++] = lg_test_path(t, graph);
    for (int i = 0; args && args[i]; i++) {
        if (n >= 70)
            lg_test_die_("lg_test_render: more than 67 arguments");
        argv[n++] = args[i];
    }
    argv[n] = NULL;
    return lg_test_spawn_(argv, t->dir, out);
}

bool lg_test_output_says_no_device(const char *out)
{
    /* the host's wording (host/exec/hostapi.c, lightgraph devices) */
    return out && (strstr(out, "no OpenGL 4.5 device") || strstr(out, "no OpenCL device"));
}

void lg_test_require_backend(lg_test *t, const char *backend)
{
    if (strcmp(backend, "cpu") == 0)
        return;
    if (strcmp(backend, "gl") && strcmp(backend, "cl"))
        lg_test_die_("lg_test_require_backend: unknown backend '%s' (cpu, gl or cl)", backend);
    const char *argv[] = { lg_test_exe(), "devices", backend, NULL };
    char *out = NULL;
    int rc = lg_test_spawn_(argv, NULL, &out);
    if (rc == 1) {
        /* "gl: no OpenGL 4.5 device (osmesa): why" */
        size_t len = strlen(out);
        while (len && out[len - 1] == '\n')
            out[--len] = 0;
        char why[1024];
        snprintf(why, sizeof why, "%s", out);
        free(out);
        out = NULL;
        lg_test_skip(t, "%s", why);
    }
    free(out);
    if (rc != 0)
        lg_test_die_("`%s devices %s` exited with %d", argv[0], backend, rc);
}

void lg_test_use_plugins(lg_test *t, const char *path)
{
    if (!path || !*path) /* the build defines the folder: without it the test is misbuilt */
        lg_test_die_("the test plugins' folder is not defined (a build error, never a skip)");
    setenv("LIGHTGRAPH_PLUGIN_PATH", path, 1);
    if (t)
        setenv("LIGHTGRAPH_CACHE_DIR", lg_test_path(t, "cache"), 1);
}
