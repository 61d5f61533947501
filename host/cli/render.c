/* lightgraph render GRAPH [-o OUT] ...: runs a graph and writes its outputs, all or nothing;
 * lg_render_file is also sweep's. Exit status: 0 success, 1 failure while running, 2 bad
 * usage or bad graph, 3 (LG_EXIT_CRASH) a plugin crashed in a callback. */
#include "cli/commands.h"

#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "exec/dist.h"
#include "exec/outputs.h"
#include "base/pattern.h"

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
        /* a frame pattern (base/pattern.h): one file per frame, each reserved here */
        size_t at;
        char why[160];
        int pattern = lg_frame_pattern_scan(path, &at, why, sizeof why);
        if (pattern < 0) { /* -o (a graph's outputs were checked with the graph) */
            fprintf(stderr, "lightgraph: output file '%s', character %zu: %s; nothing was run\n",
                    path, at + 1, why);
            return 1;
        }
        uint32_t files = pattern ? (opts->frames ? opts->frames : 1) : 1;
        for (uint32_t f = 0; f < files; f++) {
            char *name = lg_frame_pattern_name(path, f);
            int bad = lg_outputs_add(out, name, kind, err, sizeof err);
            free(name);
            if (bad) {
                fprintf(stderr, "lightgraph: %s; nothing was run\n", err);
                return 1;
            }
        }
    }
    if (opts->profile_json &&
        lg_outputs_add(out, opts->profile_json, LG_OUTPUT_FILE, err, sizeof err)) {
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
            if (pd->role != LG_ROLE_OUTPUT_FILE || pd->type != LG_PARAM_PATH || !path || !path[0])
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
    lg_str top = { 0 };
    double est = lg_plan_estimate(ex, &top);
    if (est > LG_LONG_RUN_SECONDS) {
        char t[64];
        lg_format_duration(t, sizeof t, est);
        lg_hlog(LG_HWARN,
                "this render will take about %s: %s; it runs anyway (the estimates "
                "are the nodes' own, see --explain; -q hides this)",
                t, top.s);
    }
    lg_str_free(&top);
}

/* -o names the file of the graph's one output: refused (2, printed) unless the graph has
 * exactly one output and the name's extension fits what that output gives (SH
 * coefficients as .txt, anything else an image format). */
static int check_output_override(const lg_checked *c, const char *graph, const char *path)
{
    if (c->n_outputs != 1) {
        fprintf(stderr,
                "lightgraph: -o replaces the graph's output file, but %s has %u output "
                "statements; -o needs exactly one\n",
                graph, c->n_outputs);
        return 2;
    }
    /* what the graph's one output gives decides the format: SH coefficients .txt,
     * anything else an image format */
    const lg_coutput *o = &c->outputs[0];
    const lg_node_type *ty = o->node >= 0 ? c->nodes[o->node].type : NULL;
    lg_resource_kind kind = ty && o->part == 0 && o->port < ty->n_outputs
                                ? ty->outputs[o->port].kind
                                : LG_KIND_ANY;
    bool txt = lg_path_has_ext(path, ".txt");
    if (kind == LG_KIND_SH && !txt) {
        fprintf(stderr,
                "lightgraph: -o %s: the graph's output '%s' gives SH "
                "coefficients, which are written as text: name the file .txt\n",
                path, o->g ? o->g->ref.text : "?");
        return 2;
    }
    if (txt && kind != LG_KIND_SH && kind != LG_KIND_ANY) {
        fprintf(stderr,
                "lightgraph: -o %s: only SH coefficients are written as .txt, "
                "and the graph's output '%s' is not (use .png, .exr or .hdr)\n",
                path, o->g ? o->g->ref.text : "?");
        return 2;
    }
    if (!txt && lg_image_format_from_path(path) == LG_FILE_UNKNOWN) {
        fprintf(stderr,
                "lightgraph: -o %s: unknown image format (use .png, .exr or "
                ".hdr; .txt for SH coefficients)\n",
                path);
        return 2;
    }
    return 0;
}

/* The kept nodes' total CPU wall time and `time_node`'s into *res. */
static void collect_times(const lg_exec *ex, const char *time_node, lg_run_result *res)
{
    for (uint32_t i = 0; i < ex->n_nodes; i++) {
        const lg_pnode *n = ex->nodes[i];
        if (n->plan.state != LG_STATE_KEPT)
            continue;
        res->total_ms += n->prof.cpu_ms;
        if (time_node && strcmp(time_node, n->pub.name) == 0) {
            /* per frame in steady state when it ran on several frames (sweep) */
            res->node_ms = n->prof.runs > 1 ? (n->prof.cpu_ms - n->prof.first_cpu_ms) /
                                                  (double)(n->prof.runs - 1)
                                            : n->prof.cpu_ms;
            res->node_found = true;
        }
    }
}

/* Plans and runs the checked graph, its files going into `out`, and prints --explain and
 * --profile. Returns 0, or 1 (printed) when the plan, a frame or the profile's file failed. */
static int run_graph(lg_registry *reg, const char *graph, lg_graph *g, lg_checked *c,
                     const lg_exec_opts *opts, lg_outputs *out, const char *time_node,
                     lg_run_result *res)
{
    lg_exec ex;
    memset(&ex, 0, sizeof ex);
    ex.opts = *opts;
    ex.opts.graph_path = graph;
    ex.opts.outputs = out;
    ex.cache.off = opts->no_cache;
    ex.reg = reg;
    ex.graph = g;
    ex.checked = c;
    /* a plugin that crashes in a callback ends the run with its node named, its
     * temporaries removed and LG_EXIT_CRASH (sweep shares this path) */
    ex.guard = LG_GUARD_EXIT;
    int rc = lg_plan(&ex) ? 1 : 0;
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
        collect_times(&ex, time_node, res);
    }
    fflush(stdout);
    lg_exec_free(&ex);
    return rc;
}

/* Renames a render's own files into place, all of them or none. Returns 0, or 1 (printed). */
static int commit_outputs(lg_outputs *own, const lg_checked *c, const lg_exec_opts *opts)
{
    char err[1024];
    if (lg_outputs_commit(own, err, sizeof err)) {
        fprintf(stderr, "lightgraph: %s\n", err);
        return 1;
    }
    for (uint32_t i = 0; i < c->n_outputs; i++)
        lg_hlog(LG_HINFO, "wrote %s",
                opts->output_override ? opts->output_override : c->outputs[i].path);
    return 0;
}

int lg_render_file(lg_registry *reg, const char *graph, const char *const *sets, int n_sets,
                   const lg_exec_opts *opts, const char *time_node, lg_run_result *res)
{
    memset(res, 0, sizeof *res);
    lg_graph *g;
    lg_checked *c;
    int rc = lg_load_graph(reg, graph, sets, n_sets, &g, &c);
    if (rc == 0 && opts->output_override)
        rc = check_output_override(c, graph, opts->output_override);
    if (rc == 0 && c->n_outputs == 0) {
        fprintf(stderr, "lightgraph: %s has no output statement, so nothing would run\n", graph);
        rc = 2;
    }
    /* all or nothing: every destination is checked and given its temporary before any node
     * runs, and the files are renamed into place only once every one was written; a caller
     * that passes its own set (sweep) commits it itself */
    lg_outputs *own = NULL;
    lg_outputs *out = opts->outputs;
    /* under mpirun rank 0 alone writes the files; the other ranks only name them */
    if (rc == 0 && !out)
        out = own = lg_dist_root() || lg_dist_nested() ? lg_outputs_new()
                                                       : lg_outputs_new_elsewhere();
    if (rc == 0)
        rc = add_outputs(out, c, opts);
    if (rc == 0)
        rc = run_graph(reg, graph, g, c, opts, out, time_node, res);
    /* under mpirun: rank 0 writes only when every rank succeeded (a rank that failed on
     * its own meets the others here at the latest; dist.h), and the status is the job's */
    if (own)
        rc = lg_dist_agree(rc, NULL);
    if (rc == 0 && own)
        rc = commit_outputs(own, c, opts);
    lg_outputs_free(&own);
    lg_checked_free(c);
    lg_graph_free(g);
    return rc;
}

int lg_cmd_render(int argc, char **argv)
{
    lg_graph_args a;
    int rc = lg_graph_args_parse(argc, argv, &a);
    if (rc == 0) {
        lg_registry reg = { 0 };
        lg_registry_scan(&reg);
        a.opts.output_override = a.out;
        lg_run_result res;
        rc = lg_render_file(&reg, a.graph, a.sets, a.n_sets, &a.opts, NULL, &res);
        lg_registry_free(&reg);
    }
    free(a.sets);
    return rc;
}
