/*
 * envguard: an LD_PRELOAD interposer that makes "no environment write once a thread exists"
 * a hard failure. It wraps pthread_create (every thread, the host's pool, PoCL's and
 * llvmpipe's workers, starts through it) and setenv, putenv, unsetenv and clearenv: a write
 * after the first thread started prints what was written and aborts the process (but for
 * setting a variable to the value it has: see same_value).
 *
 * Why: setenv() may reallocate `environ` while another thread's getenv() walks it; glibc
 * makes no promise for that, and the host crashed that way (issue 20: GALLIUM_DRIVER set when
 * the GL device opened after the CL device). The race shows once in a few hundred runs; this
 * makes the write itself fail every run.
 */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE
#endif
#include <dlfcn.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static atomic_int g_threads;

/* the build hides symbols by default; these must interpose */
#define EXPORT __attribute__((visibility("default")))

typedef int (*create_fn)(pthread_t *, const pthread_attr_t *, void *(*)(void *), void *);

EXPORT int pthread_create(pthread_t *t, const pthread_attr_t *attr, void *(*fn)(void *), void *arg)
{
    static create_fn real;
    if (!real) {
        void *p = dlsym(RTLD_NEXT, "pthread_create");
        memcpy(&real, &p, sizeof p);
    }
    atomic_store(&g_threads, 1);
    return real(t, attr, fn, arg);
}

static void say(const char *s)
{
    ssize_t r = write(2, s, strlen(s));
    (void)r;
}

/* A write after the first thread is refused, except setenv of a variable that exists
 * with that very value: glibc then replaces only that entry's pointer (the old string stays
 * valid), never `environ` itself, and PoCL does exactly that for HWLOC_PLUGINS_PATH every
 * time its device starts (host/main.c sets the variable first for that reason). */
static int same_value(const char *name, const char *value)
{
    const char *have = name ? getenv(name) : NULL;
    return have && value && strcmp(have, value) == 0;
}

static void check(const char *call, const char *what)
{
    if (!atomic_load(&g_threads))
        return;
    say("envguard: ");
    say(call);
    say("(");
    say(what ? what : "");
    say(") after a thread was started: the environment may only be written before any "
        "thread exists (host/main.c env_defaults)\n");
    abort();
}

#define REAL(type, name)                                                                           \
    static type real_;                                                                             \
    if (!real_) {                                                                                  \
        void *p_ = dlsym(RTLD_NEXT, name);                                                         \
        memcpy(&real_, &p_, sizeof p_);                                                            \
    }

EXPORT int setenv(const char *name, const char *value, int overwrite)
{
    if (!same_value(name, value))
        check("setenv", name);
    typedef int (*fn_t)(const char *, const char *, int);
    REAL(fn_t, "setenv");
    return real_(name, value, overwrite);
}

EXPORT int unsetenv(const char *name)
{
    check("unsetenv", name);
    typedef int (*fn_t)(const char *);
    REAL(fn_t, "unsetenv");
    return real_(name);
}

EXPORT int putenv(char *string)
{
    check("putenv", string);
    typedef int (*fn_t)(char *);
    REAL(fn_t, "putenv");
    return real_(string);
}

EXPORT int clearenv(void)
{
    check("clearenv", "");
    typedef int (*fn_t)(void);
    REAL(fn_t, "clearenv");
    return real_();
}
