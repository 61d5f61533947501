/* ptest: see ptest.h. */
#include "ptest.h"
#include "scratch.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "device.h"

extern char **environ;

static void pt_die(const char *fmt, const char *a, const char *b)
{
    fprintf(stderr, "ptest: ");
    fprintf(stderr, fmt, a, b);
    fputc('\n', stderr);
    exit(99); /* meson: hard error, not a test failure */
}

void pt_init(ptest *t, const char *name)
{
    memset(t, 0, sizeof *t);
    if (lg_scratch_make(name, t->dir, sizeof t->dir))
        exit(99); /* meson: hard error, not a test failure */
}

int pt_finish(ptest *t)
{
    if (t->failures) {
        fprintf(stderr, "%d check(s) failed; files kept in %s\n", t->failures, t->dir);
        return 1;
    }
    lg_scratch_remove(t->dir);
    return 0;
}

int pt_run_case(const char *prog, const char *name, const pt_case *cases, size_t n,
                const char *folder, void (*setup)(ptest *t))
{
    for (size_t i = 0; i < n; i++) {
        if (strcmp(name, cases[i].name) == 0) {
            ptest t;
            pt_init(&t, folder ? folder : cases[i].name);
            if (setup)
                setup(&t);
            cases[i].run(&t);
            return pt_finish(&t);
        }
    }
    fprintf(stderr, "%s: unknown case '%s'\n", prog, name);
    return 99;
}

const char *pt_path(ptest *t, const char *rel)
{
    static char ring[8][4200];
    static int next;
    char *p = ring[next++ % 8];
    snprintf(p, sizeof ring[0], "%s/%s", t->dir, rel);
    return p;
}

void pt_write_text(ptest *t, const char *rel, const char *text)
{
    const char *p = pt_path(t, rel);
    FILE *f = fopen(p, "w");
    if (!f || fputs(text, f) < 0 || fclose(f))
        pt_die("cannot write %s: %s", p, strerror(errno));
}

void pt_write_exr(ptest *t, const char *rel, const lg_image *img)
{
    const char *p = pt_path(t, rel);
    char err[512];
    lg_image_write_opts o = { .exr_pixel = LG_EXR_FLOAT, .exr_compression = LG_EXR_NONE };
    if (lg_image_write(p, img, &o, err, sizeof err))
        pt_die("%s%s", err, "");
}

bool pt_read(ptest *t, const char *rel, lg_image *img, unsigned *bits)
{
    char err[512];
    lg_image_read_info info;
    memset(&info, 0, sizeof info);
    if (lg_image_read(pt_path(t, rel), 0, img, &info, err, sizeof err)) {
        fprintf(stderr, "ptest: %s\n", err);
        t->failures++;
        return false;
    }
    if (bits)
        *bits = info.bits;
    return true;
}

int pt_render(ptest *t, const char *graph, const char *const *args, char **err)
{
    const char *exe = getenv("LG_EXE");
    if (!exe || !*exe)
        pt_die("LG_EXE is not set (run the test through meson)%s%s", "", "");
    const char *argv[64];
    int n = 0;
    argv[n++] = exe;
    argv[n++] = "render";
    argv[n++] = pt_path(t, graph);
    for (int i = 0; args && args[i] && n < 62; i++)
        argv[n++] = args[i];
    argv[n] = NULL;

    const char *errpath = pt_path(t, "output.txt");
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 2, errpath, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 2, 1);
    /* relative output paths in the graph and -o resolve in the scratch folder */
    char cwd[4096];
    if (!getcwd(cwd, sizeof cwd))
        pt_die("getcwd: %s%s", strerror(errno), "");
    if (chdir(t->dir))
        pt_die("cannot enter %s: %s", t->dir, strerror(errno));
    pid_t pid;
    int rc = posix_spawn(&pid, exe, &fa, NULL, (char *const *)argv, environ);
    if (chdir(cwd))
        pt_die("cannot return to %s: %s", cwd, strerror(errno));
    posix_spawn_file_actions_destroy(&fa);
    if (rc)
        pt_die("cannot run %s: %s", exe, strerror(rc));
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            pt_die("waitpid: %s%s", strerror(errno), "");

    FILE *f = fopen(errpath, "r");
    char *text = NULL;
    if (f) {
        fseek(f, 0, SEEK_END);
        long len = ftell(f);
        fseek(f, 0, SEEK_SET);
        text = calloc(1, (size_t)(len > 0 ? len : 0) + 1);
        if (text && len > 0 && fread(text, 1, (size_t)len, f) != (size_t)len)
            text[0] = 0;
        fclose(f);
    }
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code != 0 || getenv("PTEST_VERBOSE")) {
        fprintf(stderr, "$");
        for (int i = 0; argv[i]; i++)
            fprintf(stderr, " %s", argv[i]);
        fprintf(stderr, "\n-> exit %d%s\n%s", code, WIFSIGNALED(status) ? " (signal)" : "",
                text ? text : "");
    }
    if (err)
        *err = text;
    else
        free(text);
    return code;
}

void pt_use_plugins(ptest *t, const char *path)
{
    if (!path || !*path) {
        /* the build defines the folder: without it the test is misbuilt, not skippable */
        fprintf(stderr, "FAIL: the test plugins' folder is not defined (a build error)\n");
        exit(1);
    }
    setenv("LIGHTGRAPH_PLUGIN_PATH", path, 1);
    if (t)
        setenv("LIGHTGRAPH_CACHE_DIR", pt_path(t, "cache"), 1);
}

void pt_require_backend(const char *backend)
{
    char err[1024];
    if (strcmp(backend, "gl") == 0) {
        lg_gl_device *dev = NULL;
        if (lg_gl_device_create(&dev, "osmesa", err, sizeof err)) {
            fprintf(stderr, "no GL device (%s): skipped\n", err);
            exit(77);
        }
        lg_gl_device_destroy(&dev);
    } else if (strcmp(backend, "cl") == 0) {
        lg_cl_dev *dev = NULL;
        if (lg_cl_device_create(&dev, err, sizeof err)) {
            fprintf(stderr, "no OpenCL device (%s): skipped\n", err);
            exit(77);
        }
        lg_cl_device_destroy(&dev);
    } else if (strcmp(backend, "cpu") != 0) {
        pt_die("unknown backend '%s'%s", backend, "");
    }
}

double pt_tol(double expected, unsigned bits, double tol)
{
    /* half: 10 stored mantissa bits, so rounding to nearest is within 2^-11 relative */
    double q = bits == 16 ? fabs(expected) * ldexp(1.0, -11) : 0.0;
    return tol + q;
}

const char *pt_asset(const char *rel)
{
    static char p[4200];
    const char *root = getenv("LG_SOURCE_ROOT");
    if (!root)
        return NULL;
    snprintf(p, sizeof p, "%s/assets/%s", root, rel);
    return access(p, R_OK) == 0 ? p : NULL;
}
