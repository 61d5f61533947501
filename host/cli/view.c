/* host/cli/view.c: `lightgraph view GRAPH [options]` (docs/viewer.md): the command line,
 * checked whole (sizes, --dt, the --script file parsed) before the viewer layer opens a
 * window (viewer/viewer.h). */
#include "cli/commands.h"

#include <stdlib.h>
#include <string.h>

#include "exec/outputs.h"
#include "viewer/script.h"
#include "viewer/viewer.h"

static int usage(const char *fmt, const char *what)
{
    if (fmt)
        fprintf(stderr, fmt, what);
    fprintf(stderr, "usage: lightgraph view GRAPH [--set NODE.PARAM=VALUE]... [--show NODE.PORT]\n"
                    "                 [--size WxH] [--script FILE] [--dt SECONDS] [-v|-q]\n"
                    "(keys and the script language: docs/viewer.md)\n");
    return 2;
}

/* Parses argv into o (o->sets is the caller's array of argc entries; every string is
 * argv's). Returns 0, or 2 with the usage printed. */
static int parse_args(int argc, char **argv, lg_viewer_opts *o, const char **sets,
                      const char **script_path)
{
    int rc = 0;
    for (int i = 1; i < argc && rc == 0; i++) {
        const char *s = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(s, "--set") == 0 && val) {
            sets[o->n_sets++] = val;
            i++;
        } else if (strncmp(s, "--set=", 6) == 0) {
            sets[o->n_sets++] = s + 6;
        } else if (strcmp(s, "--show") == 0 && val) {
            o->show = val;
            i++;
        } else if (strcmp(s, "--size") == 0 && val) {
            if (!lg_parse_size(val, &o->width, &o->height))
                rc = usage("lightgraph view: --size wants WxH, 1..16384 each (got '%s')\n", val);
            else if (lg_size_over_limit("view", o->width, o->height))
                rc = 2;
            i++;
        } else if (strcmp(s, "--script") == 0 && val) {
            *script_path = val;
            i++;
        } else if (strcmp(s, "--dt") == 0 && val) {
            char *end;
            double d = strtod(val, &end);
            if (*end || !(d > 0 && d <= 3600))
                rc = usage("lightgraph view: --dt wants seconds in (0, 3600] (got '%s')\n", val);
            o->dt = d;
            i++;
        } else if (strcmp(s, "-v") == 0) {
            lg_verbosity++;
        } else if (strcmp(s, "-q") == 0) {
            lg_verbosity = -1;
        } else if (s[0] == '-' && s[1]) {
            rc = usage(val || strncmp(s, "--", 2) ? "lightgraph view: unknown option '%s'\n"
                                                  : "lightgraph view: %s needs a value\n",
                       s);
        } else if (!o->graph) {
            o->graph = s;
        } else {
            rc = usage("lightgraph view: unexpected argument '%s'\n", s);
        }
    }
    if (rc == 0 && !o->graph)
        rc = usage("lightgraph view: no graph file given%s\n", "");
    return rc;
}

int lg_cmd_view(int argc, char **argv)
{
    lg_viewer_opts o = { .width = 640, .height = 360, .dt = 1.0 / 60.0 };
    const char **sets = lg_xcalloc((size_t)argc + 1, sizeof *sets);
    o.sets = sets;
    const char *script_path = NULL;
    lg_script script = { 0 };
    int rc = parse_args(argc, argv, &o, sets, &script_path);
    char err[8192];
    if (rc == 0 && script_path && lg_script_load(script_path, &script, err, sizeof err)) {
        fprintf(stderr, "lightgraph view: %s\n", err);
        rc = 2;
    }
    if (rc == 0) {
        o.script = script_path ? &script : NULL;
        rc = lg_viewer_run(&o);
    }
    lg_script_free(&script);
    free(sets);
    return rc;
}
