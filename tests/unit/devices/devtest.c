#include "devtest.h"

#include <stdarg.h>
#include <string.h>
#include <time.h>

char devtest_errors[16384];
int devtest_error_count;

double devtest_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

void devtest_log(lg_node *node, lg_log_level level, const char *fmt, va_list ap)
{
    fprintf(stderr, "[%s log %d] ", node->name, (int)level);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}

void devtest_error(lg_node *node, const char *fmt, va_list ap)
{
    size_t len = strlen(devtest_errors);
    if (len + 1 < sizeof devtest_errors) {
        if (len > 0)
            devtest_errors[len++] = '\n';
        vsnprintf(devtest_errors + len, sizeof devtest_errors - len, fmt, ap);
    }
    devtest_error_count++;
    fprintf(stderr, "[%s error] %s\n", node->name, devtest_errors + len);
}

static const lg_host_api test_host = {
    .struct_size = sizeof(lg_host_api),
    .abi_major = LG_ABI_MAJOR,
    .abi_minor = LG_ABI_MINOR,
    .log = devtest_log,
    .error = devtest_error,
};

static lg_node test_node = { .host = &test_host, .name = "test" };

lg_node *devtest_node(void)
{
    return &test_node;
}

void devtest_clear(void)
{
    devtest_errors[0] = '\0';
    devtest_error_count = 0;
}

/* ---- a fake host with GL --------------------------------------------------------------------- */

const lg_gl *devtest_gl;

int devtest_gl_open(int argc, char **argv, lg_gl_device **dev)
{
    const char *backend = argc > 1 ? argv[1] : "osmesa";
    char err[512] = "";
    *dev = NULL;
    if (lg_gl_device_create(dev, backend, err, sizeof err)) {
        printf("SKIP: no GL device '%s': %s\n", backend, err);
        return 1;
    }
    devtest_gl = lg_gl_device_table(*dev);
    return 0;
}

const void *devtest_host_gl(lg_node *n)
{
    (void)n;
    return devtest_gl;
}

int devtest_host_gl_check(lg_node *n, const char *what)
{
    GLenum e = devtest_gl->GetError(), first = e;
    if (e == GL_NO_ERROR)
        return 0;
    while (e != GL_NO_ERROR)
        e = devtest_gl->GetError();
    return lg_error_code(n, LG_ERR_DEVICE, "GL error %s while %s", lg_gl_strerror(first), what);
}
