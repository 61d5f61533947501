/* What the graph commands share (commands.h): the command line of render, check, fmt and
 * dot, and loading a graph with its --set overrides, checked against the scanned plugins
 * (also sweep's, through lg_check_file and lg_render_file). */
#include "cli/commands.h"

#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "exec/outputs.h"

static int usage(const char *cmd, const char *fmt, const char *what)
{
    if (fmt)
        fprintf(stderr, fmt, what);
    fprintf(
        stderr,
        "usage: lightgraph %s GRAPH [-o OUT] [--set NODE.PARAM=VALUE]... [--size WxH]\n"
        "                 [--frames N] [--every-frame[=NODE,...]] [--dt SECONDS] [--gl osmesa|egl]\n"
        "                 [--exr half|float] [--no-cache]\n"
        "                 [--explain] [--profile] [--profile-json FILE] [-v|-q]\n"
        "(see lightgraph help)\n",
        cmd);
    return 2;
}

/* render's options (check, fmt and dot take the same; -i is fmt's), in the order of
 * graph_opt below */
static const lg_option graph_opts[] = {
    { "-o", "--output", LG_OPT_VALUE },
    { "--set", NULL, LG_OPT_VALUE | LG_OPT_JOINED },
    { "--size", NULL, LG_OPT_VALUE },
    { "--frames", NULL, LG_OPT_VALUE },
    { "--dt", NULL, LG_OPT_VALUE },
    { "--gl", NULL, LG_OPT_VALUE },
    { "--exr", NULL, LG_OPT_VALUE },
    { "--explain", NULL, 0 },
    { "--every-frame", NULL, LG_OPT_JOINED },
    { "--profile", NULL, 0 },
    { "--profile-json", NULL, LG_OPT_VALUE },
    { "--no-cache", NULL, 0 },
    { "-v", NULL, 0 },
    { "-q", NULL, 0 },
    { "-i", NULL, 0 },
};
enum graph_opt {
    OPT_OUTPUT,
    OPT_SET,
    OPT_SIZE,
    OPT_FRAMES,
    OPT_DT,
    OPT_GL,
    OPT_EXR,
    OPT_EXPLAIN,
    OPT_EVERY_FRAME,
    OPT_PROFILE,
    OPT_PROFILE_JSON,
    OPT_NO_CACHE,
    OPT_VERBOSE,
    OPT_QUIET,
    OPT_IN_PLACE,
    N_GRAPH_OPTS
};
_Static_assert(sizeof graph_opts / sizeof graph_opts[0] == N_GRAPH_OPTS, "graph_opts");

/* --dt's seconds: a number or a fraction such as 1/60, in (0, 3600]; -1 when it is not. */
static double parse_dt(const char *v)
{
    char *end;
    double d = strtod(v, &end);
    /* a fraction such as 1/60 is the natural way to write a frame time */
    if (*end == '/') {
        char *end2;
        double den = strtod(end + 1, &end2);
        d = (*end2 == 0 && den > 0) ? d / den : -1;
        end = end2;
    }
    return (*end || !(d > 0 && d <= 3600)) ? -1 : d;
}

/* Applies option `k` with value v (NULL for a switch) to *a. Returns 0, or 2 after the
 * message and the usage. `s` is the option as written, for the messages. */
static int graph_option(lg_graph_args *a, int k, const char *s, const char *v)
{
    switch ((enum graph_opt)k) {
    case OPT_OUTPUT: a->out = v; break;
    case OPT_SET: a->sets[a->n_sets++] = v; break;
    case OPT_SIZE:
        if (!lg_parse_size(v, &a->opts.width, &a->opts.height))
            return usage(a->cmd, "lightgraph: --size wants WxH, 1..16384 each (got '%s')\n", v);
        if (lg_size_over_limit(a->cmd, a->opts.width, a->opts.height))
            return 2;
        break;
    case OPT_FRAMES:
        if (!lg_parse_uint(v, &a->opts.frames, 1000000))
            return usage(a->cmd, "lightgraph: --frames wants 1..1000000 (got '%s')\n", v);
        break;
    case OPT_DT:
        a->opts.dt = parse_dt(v);
        if (a->opts.dt < 0)
            return usage(a->cmd, "lightgraph: --dt wants seconds in (0, 3600] (got '%s')\n", v);
        break;
    case OPT_GL:
        if (strcmp(v, "osmesa") && strcmp(v, "egl"))
            return usage(a->cmd, "lightgraph: --gl wants osmesa or egl (got '%s')\n", v);
        a->opts.gl_backend = v;
        break;
    case OPT_EXR:
        if (strcmp(v, "half") && strcmp(v, "float"))
            return usage(a->cmd, "lightgraph: --exr wants half or float (got '%s')\n", v);
        a->opts.exr_pixel = v[0] == 'h' ? LG_OUT_EXR_HALF : LG_OUT_EXR_FLOAT;
        break;
    case OPT_EXPLAIN: a->opts.explain = true; break;
    case OPT_EVERY_FRAME:
        /* --every-frame, or --every-frame=NODE,...; "--every-frame=" names no node */
        if (v && !v[0])
            return usage(a->cmd, "lightgraph: unknown option '%s'\n", s);
        a->opts.every_frame = true;
        if (v)
            a->opts.every_frame_nodes = v;
        break;
    case OPT_PROFILE: a->opts.profile = true; break;
    case OPT_PROFILE_JSON: a->opts.profile_json = v; break;
    case OPT_NO_CACHE: a->opts.no_cache = true; break;
    case OPT_VERBOSE: lg_verbosity++; break;
    case OPT_QUIET: lg_verbosity = -1; break;
    case OPT_IN_PLACE:
        if (strcmp(a->cmd, "fmt") != 0)
            return usage(a->cmd, "lightgraph: unknown option '%s'\n", s);
        a->in_place = true;
        break;
    case N_GRAPH_OPTS: break;
    }
    return 0;
}

int lg_graph_args_parse(int argc, char **argv, lg_graph_args *a)
{
    memset(a, 0, sizeof *a);
    a->cmd = argv[0];
    a->opts.width = 640;
    a->opts.height = 360;
    a->opts.frames = 1;
    a->opts.dt = 1.0 / 60.0;
    a->opts.gl_backend = "osmesa";
    a->sets = lg_xcalloc((size_t)argc + 1, sizeof *a->sets);
    for (int i = 1; i < argc; i++) {
        const char *s = argv[i], *v;
        int k = lg_option_find(graph_opts, N_GRAPH_OPTS, argc, argv, &i, &v);
        if (k == LG_OPT_NO_VALUE)
            return usage(a->cmd, "lightgraph: %s needs a value\n", s);
        if (k >= 0) {
            int rc = graph_option(a, k, s, v);
            if (rc)
                return rc;
        } else if (s[0] == '-' && s[1]) {
            return usage(a->cmd, "lightgraph: unknown option '%s'\n", s);
        } else if (!a->graph) {
            a->graph = s;
        } else {
            return usage(a->cmd, "lightgraph: unexpected argument '%s'\n", s);
        }
    }
    if (!a->graph)
        return usage(a->cmd, "lightgraph %s: no graph file given\n", a->cmd);
    a->opts.graph_path = a->graph;
    return 0;
}

int lg_load_graph(lg_registry *reg, const char *graph, const char *const *sets, int n_sets,
                  lg_graph **g, lg_checked **c)
{
    lg_diags d = { 0 };
    *c = NULL;
    *g = lg_graph_parse_file(graph, &d);
    for (int i = 0; *g && i < n_sets; i++)
        lg_graph_set(*g, sets[i], &d);
    if (*g && !d.errors && reg) {
        lg_schema schema;
        lg_registry_schema(reg, &schema);
        schema.max_pixels = lg_image_max_pixels();
        *c = lg_graph_check(*g, &schema, &d);
        if (!*c)
            for (uint32_t i = 0; i < reg->n_refused; i++)
                fprintf(stderr, "note: plugin %s was refused: %s\n", reg->refused[i].path,
                        reg->refused[i].reason);
    }
    lg_diags_print(&d, stderr);
    int rc = (!*g || d.errors || (reg && !*c)) ? 2 : 0;
    lg_diags_free(&d);
    return rc;
}

int lg_check_file(lg_registry *reg, const char *graph, const char *const *sets, int n_sets)
{
    lg_graph *g;
    lg_checked *c;
    int rc = lg_load_graph(reg, graph, sets, n_sets, &g, &c);
    lg_checked_free(c);
    lg_graph_free(g);
    return rc;
}

int lg_session_open(lg_session *s, int argc, char **argv, bool need_check)
{
    memset(s, 0, sizeof *s);
    int rc = lg_graph_args_parse(argc, argv, &s->a);
    if (rc)
        return rc;
    if (need_check)
        lg_registry_scan(&s->reg);
    return lg_load_graph(need_check ? &s->reg : NULL, s->a.graph, s->a.sets, s->a.n_sets, &s->g,
                         &s->c);
}

int lg_session_close(lg_session *s, int rc)
{
    lg_checked_free(s->c);
    lg_graph_free(s->g);
    lg_registry_free(&s->reg);
    free(s->a.sets);
    return rc;
}
