/* lightgraph render | check | fmt | dot. Exit status: 0 success, 1 failure while running,
 * 2 bad usage or bad graph, 3 (LG_EXIT_CRASH) a plugin crashed in a callback. */
#include "cli/commands.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "exec/outputs.h"

typedef struct args {
    const char *cmd;
    const char *graph;
    const char *out;
    const char **sets;
    int n_sets;
    lg_exec_opts opts;
    bool in_place;
} args;


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

static int parse_args(int argc, char **argv, args *a)
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

/* What every graph command holds: its arguments, the parsed graph, the registry and the
 * checked graph. */
typedef struct session {
    args a;
    lg_graph *g;
    lg_checked *c;
    lg_registry reg;
} session;

/* Parses the arguments and the graph, applies overrides, and (with need_check) scans the
 * plugins and checks the graph against them. Returns 0 or an exit status (diagnostics
 * printed); close_session() in every case. */
/* Parses `graph`, applies `sets`, and (with reg) checks it against the scanned plugins.
 * Diagnostics are printed. Returns 0 or 2; *g and *c are set either way (free both). */
static int load_graph(lg_registry *reg, const char *graph, const char *const *sets, int n_sets,
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
    int rc = load_graph(reg, graph, sets, n_sets, &g, &c);
    lg_checked_free(c);
    lg_graph_free(g);
    return rc;
}

static int open_session(session *s, int argc, char **argv, bool need_check)
{
    memset(s, 0, sizeof *s);
    int rc = parse_args(argc, argv, &s->a);
    if (rc)
        return rc;
    if (need_check)
        lg_registry_scan(&s->reg);
    return load_graph(need_check ? &s->reg : NULL, s->a.graph, s->a.sets, s->a.n_sets, &s->g,
                      &s->c);
}

static int close_session(session *s, int rc)
{
    lg_checked_free(s->c);
    lg_graph_free(s->g);
    lg_registry_free(&s->reg);
    free(s->a.sets);
    return rc;
}

/* Adds every file this run writes (the outputs, or -o; --profile-json) to `out`, each
 * checked before any work. Returns 0, or 1 (printed): a destination that cannot be written
 * is a failure to run, as a failed write was, not bad usage. */
static int add_outputs(lg_outputs *out, const lg_checked *c, const lg_exec_opts *opts)
{
    char err[1024];
    for (uint32_t i = 0; i < c->n_outputs; i++) {
        const char *path = opts->output_override ? opts->output_override : c->outputs[i].path;
        /* .txt: SH coefficients as text (checked against the output's kind before) */
        lg_output_kind kind = lg_path_has_ext(path, ".txt") ? LG_OUTPUT_FILE : LG_OUTPUT_IMAGE;
        if (lg_outputs_add(out, path, kind, err, sizeof err)) {
            fprintf(stderr, "lightgraph: %s; nothing was run\n", err);
            return 1;
        }
    }
    if (opts->profile_json && lg_outputs_add(out, opts->profile_json, LG_OUTPUT_FILE, err,
                                             sizeof err)) {
        fprintf(stderr, "lightgraph: --profile-json: %s; nothing was run\n", err);
        return 1;
    }
    /* the files nodes write (LG_ROLE_OUTPUT_FILE, set to a path): checked here with the
     * others, written by the node into the temporary (lg_output_file_write), committed
     * with the others or not at all */
    for (uint32_t i = 0; i < c->n_nodes; i++) {
        const lg_cnode *cn = &c->nodes[i];
        for (uint32_t k = 0; cn->type && k < cn->type->n_params; k++) {
            const lg_param_desc *pd = &cn->type->params[k];
            const char *path = cn->params[k].s;
            if (pd->role != LG_ROLE_OUTPUT_FILE || pd->type != LG_PARAM_PATH || !path ||
                !path[0])
                continue;
            char *owner = lg_xasprintf("node '%s' (%s)", cn->g->name, pd->key);
            int bad = lg_outputs_add_owned(out, path, owner, err, sizeof err);
            if (bad)
                fprintf(stderr, "lightgraph: node '%s', parameter %s: %s; nothing was run\n",
                        cn->g->name, pd->key, err);
            free(owner);
            if (bad)
                return 1;
        }
    }
    return 0;
}

/* Above this many estimated seconds a render says so before it starts (a warning, not a
 * refusal: a long reference render is often what the user wants, and the estimate is
 * only an order of magnitude; -q hides it). */
#define LG_LONG_RUN_SECONDS 60.0

static void warn_long_run(const lg_exec *ex)
{
    lg_str top = {0};
    double est = lg_plan_estimate(ex, &top);
    if (est > LG_LONG_RUN_SECONDS) {
        char t[64];
        lg_format_duration(t, sizeof t, est);
        lg_hlog(LG_HWARN, "this render will take about %s: %s; it runs anyway (the estimates "
                          "are the nodes' own, see --explain; -q hides this)",
                t, top.s);
    }
    lg_str_free(&top);
}

int lg_render_file(lg_registry *reg, const char *graph, const char *const *sets, int n_sets,
                   const lg_exec_opts *opts, const char *time_node, lg_run_result *res)
{
    memset(res, 0, sizeof *res);
    lg_graph *g;
    lg_checked *c;
    int rc = load_graph(reg, graph, sets, n_sets, &g, &c);
    if (rc == 0 && opts->output_override) {
        if (c->n_outputs != 1) {
            fprintf(stderr,
                    "lightgraph: -o replaces the graph's output file, but %s has %u output "
                    "statements; -o needs exactly one\n",
                    graph, c->n_outputs);
            rc = 2;
        } else {
            /* what the graph's one output gives decides the format: SH coefficients .txt,
             * anything else an image format */
            const lg_coutput *o = &c->outputs[0];
            const lg_node_type *ty = o->node >= 0 ? c->nodes[o->node].type : NULL;
            lg_resource_kind kind = ty && o->part == 0 && o->port < ty->n_outputs
                                    ? ty->outputs[o->port].kind : LG_KIND_ANY;
            bool txt = lg_path_has_ext(opts->output_override, ".txt");
            if (kind == LG_KIND_SH && !txt) {
                fprintf(stderr, "lightgraph: -o %s: the graph's output '%s' gives SH "
                        "coefficients, which are written as text: name the file .txt\n",
                        opts->output_override, o->g ? o->g->ref.text : "?");
                rc = 2;
            } else if (txt && kind != LG_KIND_SH && kind != LG_KIND_ANY) {
                fprintf(stderr, "lightgraph: -o %s: only SH coefficients are written as .txt, "
                        "and the graph's output '%s' is not (use .png, .exr or .hdr)\n",
                        opts->output_override, o->g ? o->g->ref.text : "?");
                rc = 2;
            } else if (!txt &&
                       lg_image_format_from_path(opts->output_override) == LG_FILE_UNKNOWN) {
                fprintf(stderr, "lightgraph: -o %s: unknown image format (use .png, .exr or "
                        ".hdr; .txt for SH coefficients)\n", opts->output_override);
                rc = 2;
            }
        }
    }
    if (rc == 0 && c->n_outputs == 0) {
        fprintf(stderr, "lightgraph: %s has no output statement, so nothing would run\n", graph);
        rc = 2;
    }
    /* all or nothing: every destination is checked and given its temporary before any node
     * runs, and the files are renamed into place only once every one was written; a caller
     * that passes its own set (sweep) commits it itself */
    lg_outputs *own = NULL;
    lg_outputs *out = opts->outputs;
    if (rc == 0 && !out)
        out = own = lg_outputs_new();
    if (rc == 0)
        rc = add_outputs(out, c, opts);
    if (rc == 0) {
        lg_exec ex;
        memset(&ex, 0, sizeof ex);
        ex.opts = *opts;
        ex.opts.graph_path = graph;
        ex.opts.outputs = out;
        ex.reg = reg;
        ex.graph = g;
        ex.checked = c;
        /* a plugin that crashes in a callback ends the run with its node named, its
         * temporaries removed and LG_EXIT_CRASH (sweep shares this path) */
        ex.guard = LG_GUARD_EXIT;
        rc = lg_plan(&ex) ? 1 : 0;
        if (opts->explain && ex.nodes) {
            lg_explain_print(&ex, stdout);
            fflush(stdout); /* shown before a long run starts, also through a pipe */
        }
        if (rc == 0)
            warn_long_run(&ex);
        if (rc == 0)
            rc = lg_execute(&ex) ? 1 : 0;
        if (rc == 0 && ex.failed)
            rc = 1;
        if (rc == 0) {
            if (opts->profile)
                lg_profile_print(&ex, stdout);
            if (opts->profile_json && lg_profile_write_json(&ex, opts->profile_json))
                rc = 1;
            for (uint32_t i = 0; i < ex.n_nodes; i++) {
                const lg_pnode *n = ex.nodes[i];
                if (n->plan.state != LG_STATE_KEPT)
                    continue;
                res->total_ms += n->prof.cpu_ms;
                if (time_node && strcmp(time_node, n->pub.name) == 0) {
                    /* per frame in steady state when it ran on several frames (sweep) */
                    res->node_ms = n->prof.runs > 1 ? (n->prof.cpu_ms - n->prof.first_cpu_ms) / (double)(n->prof.runs - 1)
                                               : n->prof.cpu_ms;
                    res->node_found = true;
                }
            }
        }
        fflush(stdout);
        lg_exec_free(&ex);
    }
    if (rc == 0 && own) {
        char err[1024];
        if (lg_outputs_commit(own, err, sizeof err)) {
            fprintf(stderr, "lightgraph: %s\n", err);
            rc = 1;
        } else {
            for (uint32_t i = 0; i < c->n_outputs; i++)
                lg_hlog(LG_HINFO, "wrote %s",
                        opts->output_override ? opts->output_override : c->outputs[i].path);
        }
    }
    lg_outputs_free(&own);
    lg_checked_free(c);
    lg_graph_free(g);
    return rc;
}

int lg_cmd_render(int argc, char **argv)
{
    args a;
    int rc = parse_args(argc, argv, &a);
    if (rc == 0) {
        lg_registry reg = {0};
        lg_registry_scan(&reg);
        a.opts.output_override = a.out;
        lg_run_result res;
        rc = lg_render_file(&reg, a.graph, a.sets, a.n_sets, &a.opts, NULL, &res);
        lg_registry_free(&reg);
    }
    free(a.sets);
    return rc;
}

int lg_cmd_check(int argc, char **argv)
{
    session s;
    int rc = open_session(&s, argc, argv, true);
    if (rc == 0)
        printf("%s: ok (%u nodes, %u outputs)\n", s.a.graph, s.c->n_nodes, s.c->n_outputs);
    return close_session(&s, rc);
}

int lg_cmd_fmt(int argc, char **argv)
{
    session s;
    int rc = open_session(&s, argc, argv, false);
    if (rc == 0) {
        char *text = lg_graph_format(s.g);
        if (!s.a.in_place) {
            fputs(text, stdout);
        } else if (lg_write_file_atomic(s.a.graph, text, strlen(text)) != 0) {
            fprintf(stderr, "lightgraph fmt: cannot write %s: %s\n", s.a.graph, strerror(errno));
            rc = 1;
        }
        free(text);
    }
    return close_session(&s, rc);
}

int lg_cmd_dot(int argc, char **argv)
{
    session s;
    int rc = open_session(&s, argc, argv, true);
    if (rc == 0) {
        char *text = lg_graph_dot(s.g, s.c);
        fputs(text, stdout);
        free(text);
    }
    return close_session(&s, rc);
}
