/* The option tables of render (and check, fmt, dot), sweep and diff (commands.h): one lookup
 * of an argument among a command's options and of the value it takes, in place of a
 * strcmp chain and a "needs a value" check per option. What an option means, and every
 * message, stays the command's. */
#include "cli/commands.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

int lg_arg_refuse(char *err, size_t errlen, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
    return 2;
}

lg_exec_opts lg_measure_opts(uint32_t width, uint32_t height, uint32_t frames,
                             const char *gl_backend)
{
    lg_exec_opts o;
    memset(&o, 0, sizeof o);
    o.width = width;
    o.height = height;
    o.frames = frames;
    o.dt = 1.0 / 60.0;
    o.gl_backend = gl_backend;
    o.no_cache = true;
    return o;
}

int lg_option_find(const lg_option *opts, int n, int argc, char **argv, int *i, const char **val)
{
    const char *arg = argv[*i];
    *val = NULL;
    for (int k = 0; k < n; k++) {
        const lg_option *o = &opts[k];
        const char *names[2] = { o->name, o->alias };
        for (int m = 0; m < 2 && names[m]; m++) {
            size_t len = strlen(names[m]);
            if (strncmp(arg, names[m], len) != 0)
                continue;
            if (arg[len] == '\0') {
                if (!(o->flags & LG_OPT_VALUE))
                    return k;
                if (*i + 1 >= argc)
                    return LG_OPT_NO_VALUE;
                *val = argv[++*i];
                return k;
            }
            if (arg[len] == '=' && (o->flags & LG_OPT_JOINED)) {
                *val = arg + len + 1;
                return k;
            }
        }
    }
    return LG_OPT_UNKNOWN;
}
