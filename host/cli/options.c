/* The option tables of render (and check, fmt, dot), sweep and diff (commands.h): one lookup
 * of an argument among a command's options and of the value it takes, in place of a
 * strcmp chain and a "needs a value" check per option. What an option means, and every
 * message, stays the command's. */
#include "cli/commands.h"

#include <string.h>

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
