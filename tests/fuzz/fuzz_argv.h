/*
 * tests/fuzz/fuzz_argv.h: a fuzz input as a command line, for the targets that drive a
 * command's argument parser (fuzz_sweep.c, fuzz_tune.c). Header-only, so that it serves the
 * libFuzzer build (where fuzz_driver.c is not linked) as well as the plain one.
 */
#ifndef LG_FUZZ_ARGV_H
#define LG_FUZZ_ARGV_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The input's lines as the arguments after argv0: "a\nb" and "a\nb\n" are both the
 * arguments a and b, "" is none. Returns argv (NULL-terminated, *argc entries, argv0
 * first), or NULL for an input holding a NUL (an argument never does). The caller frees
 * the returned array and *text, into which the arguments point. */
static inline char **lg_fuzz_argv(const uint8_t *data, size_t size, char *argv0, char **text,
                                  int *argc)
{
    if (memchr(data, '\0', size))
        return NULL;
    char *t = malloc(size + 1);
    char **argv = malloc((size + 2) * sizeof *argv);
    if (!t || !argv)
        abort();
    memcpy(t, data, size);
    t[size] = '\0';
    int n = 0;
    argv[n++] = argv0;
    for (char *p = t; size > 0;) {
        char *nl = strchr(p, '\n');
        argv[n++] = p;
        if (!nl)
            break;
        *nl = '\0';
        p = nl + 1;
        if (p == t + size)
            break;
    }
    argv[n] = NULL;
    *text = t;
    *argc = n;
    return argv;
}

#endif
