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
    fprintf(stderr,
            "usage: lightgraph %s GRAPH [-o OUT] [--set NODE.PARAM=VALUE]... [--size WxH]\n"
            "                 [--frames N] [--every-frame[=NODE,...]] [--dt SECONDS] [--gl osmesa|egl]\n"
            "                 [--exr half|float]\n"
            "                 [--explain] [--profile] [--profile-json FILE] [-v|-q]\n"
            "(see lightgraph help)\n",
            cmd);
    return 2;
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
        const char *s = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
#define NEEDV()                                                                            \
    do {                                                                                   \
        if (!v)                                                                            \
            return usage(a->cmd, "lightgraph: %s needs a value\n", s);                     \
        i++;                                                                               \
    } while (0)
        if (strcmp(s, "-o") == 0 || strcmp(s, "--output") == 0) {
            NEEDV();
            a->out = v;
        } else if (strcmp(s, "--set") == 0) {
            NEEDV();
            a->sets[a->n_sets++] = v;
        } else if (strncmp(s, "--set=", 6) == 0) {
            a->sets[a->n_sets++] = s + 6;
        } else if (strcmp(s, "--size") == 0) {
            NEEDV();
            if (!lg_parse_size(v, &a->opts.width, &a->opts.height))
                return usage(a->cmd, "lightgraph: --size wants WxH, 1..16384 each (got '%s')\n",
                             v);
            if (lg_size_over_limit(a->cmd, a->opts.width, a->opts.height))
                return 2;
        } else if (strcmp(s, "--frames") == 0) {
            NEEDV();
            if (!lg_parse_uint(v, &a->opts.frames, 1000000))
                return usage(a->cmd, "lightgraph: --frames wants 1..1000000 (got '%s')\n", v);
        } else if (strcmp(s, "--dt") == 0) {
            NEEDV();
            char *end;
            double d = strtod(v, &end);
            /* a fraction such as 1/60 is the natural way to write a frame time */
            if (*end == '/') {
                char *end2;
                double den = strtod(end + 1, &end2);
                d = (*end2 == 0 && den > 0) ? d / den : -1;
                end = end2;
            }
            if (*end || !(d > 0 && d <= 3600))
                return usage(a->cmd, "lightgraph: --dt wants seconds in (0, 3600] (got '%s')\n",
                             v);
            a->opts.dt = d;
        } else if (strcmp(s, "--gl") == 0) {
            NEEDV();
            if (strcmp(v, "osmesa") && strcmp(v, "egl"))
                return usage(a->cmd, "lightgraph: --gl wants osmesa or egl (got '%s')\n", v);
            a->opts.gl_backend = v;
        } else if (strcmp(s, "--exr") == 0) {
            NEEDV();
            if (strcmp(v, "half") && strcmp(v, "float"))
                return usage(a->cmd, "lightgraph: --exr wants half or float (got '%s')\n", v);
            a->opts.exr_pixel = v[0] == 'h' ? LG_OUT_EXR_HALF : LG_OUT_EXR_FLOAT;
        } else if (strcmp(s, "--explain") == 0) {
            a->opts.explain = true;
        } else if (strcmp(s, "--every-frame") == 0) {
            a->opts.every_frame = true;
        } else if (strncmp(s, "--every-frame=", 14) == 0 && s[14]) {
            a->opts.every_frame = true;
            a->opts.every_frame_nodes = s + 14;
        } else if (strcmp(s, "--profile") == 0) {
            a->opts.profile = true;
        } else if (strcmp(s, "--profile-json") == 0) {
            NEEDV();
            a->opts.profile_json = v;
        } else if (strcmp(s, "-v") == 0) {
            lg_verbosity++;
        } else if (strcmp(s, "-q") == 0) {
            lg_verbosity = -1;
        } else if (strcmp(s, "-i") == 0 && strcmp(a->cmd, "fmt") == 0) {
            a->in_place = true;
        } else if (s[0] == '-' && s[1]) {
            return usage(a->cmd, "lightgraph: unknown option '%s'\n", s);
        } else if (!a->graph) {
            a->graph = s;
        } else {
            return usage(a->cmd, "lightgraph: unexpected argument '%s'\n", s);
        }
#undef NEEDV
    }
    if (!a->graph)
        return usage(a->cmd, "lightgraph %s: no graph file given\n", a->cmd);
    a->opts.graph_path = a->graph;
    return 0;
}

int lg_load_graph(lg_registry *reg, const char *graph, const char *const *sets, int n_sets,
                  lg_graph **g, lg_checked **c)
{
    lg_diags d = {0};
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
