/* host/cli/commands.h: the commands of the lightgraph program (one file each in host/cli/)
 * and the helpers several of them share (session.c, schema_print.c, options.c, gnuplot.c).
 * sweep's and tune's command lines (sweep_args.h, tune_args.h) and conform's synthetic
 * inputs (conform.h) keep private headers: each is one command's alone, and fuzz_sweep runs
 * sweep's without the rest of the layer. */
#ifndef LG_HOST_CLI_COMMANDS_H
#define LG_HOST_CLI_COMMANDS_H

#include "plan/plan.h"

/* ---- one graph, rendered or checked (render.c, session.c; render and sweep use them) --------- */

/* Renders one graph file: parse, apply `sets` (NODE.PARAM=VALUE), check against `reg`
 * (already scanned), plan, run, write the output (opts->output_override replaces the single
 * output's file), print --explain / --profile per opts. Returns the exit status (0, 1, 2);
 * res gets the kept nodes' total CPU wall time and `time_node`'s (if found). Every file is
 * checked before anything runs and written all or nothing (outputs.h): into a set of its
 * own, committed on success, or, when opts->outputs is given, into that set, which the
 * caller commits (sweep). */
typedef struct lg_run_result {
    double total_ms;
    double node_ms;
    bool node_found;
} lg_run_result;
int lg_render_file(lg_registry *reg, const char *graph, const char *const *sets, int n_sets,
                   const lg_exec_opts *opts, const char *time_node, lg_run_result *res);
/* Parses `graph`, applies `sets` and checks it against the scanned plugins, as `check` does
 * (nothing runs). Diagnostics are printed. Returns 0, or 2 for a bad graph or value. */
int lg_check_file(lg_registry *reg, const char *graph, const char *const *sets, int n_sets);

/* ---- the commands (one file each: render.c, check.c, ...) ---------------------------------------
 * argv[0] is the command's name; each returns the exit status: 0 success, 1 failure while
 * running, 2 bad usage or bad graph (render and sweep: 3, LG_EXIT_CRASH, a plugin crashed). */
int lg_cmd_render(int argc, char **argv);
int lg_cmd_check(int argc, char **argv);
int lg_cmd_fmt(int argc, char **argv);
int lg_cmd_dot(int argc, char **argv);
int lg_cmd_plugins(int argc, char **argv);
int lg_cmd_inspect(int argc, char **argv);
int lg_cmd_sweep(int argc, char **argv);
/* lightgraph tune GRAPH --node N --target-error E [...] (tune.c, docs/tune.md): 0 the answer's
 * check render meets E, 1 E is out of reach (the best found is printed) or the check misses
 * it, 2 bad usage, an unknown node, parameter, range or metric (nothing written). */
int lg_cmd_tune(int argc, char **argv);
int lg_cmd_devices(int argc, char **argv);
/* lightgraph diff A B [--heatmap OUT] [--heat-max X] [--json] [--max-rmse X] [--max-abs X] */
int lg_cmd_diff(int argc, char **argv);
/* lightgraph conform PLUGIN.so [--json] [--quick] [-v] (docs/conform.md): 0 every contract
 * holds, 1 one is broken (the report names the node type, the check and the values), 2 bad
 * usage. Its private header, conform.h, is its synthetic inputs' (conform_sources.c). */
int lg_cmd_conform(int argc, char **argv);
/* lightgraph view GRAPH [options] (view.c, docs/viewer.md) */
int lg_cmd_view(int argc, char **argv);

/* Runs gnuplot inside `dir` on the script `gp` with the variables data (the CSV `csv`) and out
 * (the plot `png`), all three in `dir` and named without quotes or slashes (gnuplot.c: sweep's
 * and tune's plots, made on their outputs' temporaries). Returns 0 when the plot was made. */
int lg_run_gnuplot(const char *dir, const char *gp, const char *csv, const char *png);

/* ---- option tables (options.c: render's, sweep's and diff's command lines) ------------------- */

/* One option of a command: its name, another name for it, and how it takes a value. */
typedef struct lg_option {
    const char *name;  /* "--size" */
    const char *alias; /* "--output" for "-o", or NULL */
    unsigned flags;    /* LG_OPT_VALUE and/or LG_OPT_JOINED; 0: a switch */
} lg_option;
enum {
    LG_OPT_VALUE = 1u << 0,  /* "--opt VALUE": the next argument, whatever it is */
    LG_OPT_JOINED = 1u << 1, /* "--opt=VALUE" (alone, without LG_OPT_VALUE: an optional
                              * value, "--opt" or "--opt=VALUE") */
};
enum { LG_OPT_UNKNOWN = -1, LG_OPT_NO_VALUE = -2 };
/* Looks argv[*i] up among opts[0 .. n-1]. Returns the option's index, *val its value (the
 * next argument, consumed by advancing *i, or the text after '='; NULL for a switch);
 * LG_OPT_NO_VALUE when an option that takes a value is the last argument; LG_OPT_UNKNOWN
 * when argv[*i] is none of them (an operand, or an option the caller names unknown). */
int lg_option_find(const lg_option *opts, int n, int argc, char **argv, int *i, const char **val);

/* An argument parser's refusal: the message printf'd into err (errlen bytes). Returns 2, the
 * exit status of bad usage, so that a parser says `return lg_arg_refuse(err, n, ...)`. */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
int lg_arg_refuse(char *err, size_t errlen, const char *fmt, ...);

/* The run options of the measuring commands, sweep and tune: the size, the frames at dt =
 * 1/60, the GL backend, and the on-disk cache off (a repeat must time the work, never a
 * cache load). */
lg_exec_opts lg_measure_opts(uint32_t width, uint32_t height, uint32_t frames,
                             const char *gl_backend);

/* A macro's value as a string literal ("at most " LG_STR(LG_SWEEP_MAX_VARY)). */
#define LG_STR_(x) #x
#define LG_STR(x) LG_STR_(x)

/* ---- the graph commands' session (session.c) ------------------------------------------------- */

/* The command line of render, check, fmt and dot (lightgraph help):
 * GRAPH [-o OUT] [--set NODE.PARAM=VALUE]... [--size WxH] [--frames N] ... [-i] (fmt only).
 * Strings point into argv; `sets` is owned (free it). */
typedef struct lg_graph_args {
    const char *cmd;
    const char *graph;
    const char *out;
    const char **sets;
    int n_sets;
    lg_exec_opts opts;
    bool in_place;
} lg_graph_args;
/* Parses argv[1 .. argc-1] into *a (zeroed first). Returns 0, or 2 after printing the
 * reason and the usage; a->sets is to be freed either way. */
int lg_graph_args_parse(int argc, char **argv, lg_graph_args *a);

/* Parses `graph`, applies `sets`, and (with reg) checks it against the scanned plugins.
 * Diagnostics are printed. Returns 0 or 2; *g and *c are set either way (the caller frees
 * both; *c is NULL without reg or when the check failed). */
int lg_load_graph(lg_registry *reg, const char *graph, const char *const *sets, int n_sets,
                  lg_graph **g, lg_checked **c);

/* What check, fmt and dot hold: their arguments, the parsed graph, the registry and the
 * checked graph (c is NULL without need_check). */
typedef struct lg_session {
    lg_graph_args a;
    lg_graph *g;
    lg_checked *c;
    lg_registry reg;
} lg_session;
/* Parses the arguments and the graph, applies overrides, and (with need_check) scans the
 * plugins and checks the graph against them. Returns 0 or an exit status (diagnostics
 * printed); lg_session_close() in every case. */
int lg_session_open(lg_session *s, int argc, char **argv, bool need_check);
/* Frees what lg_session_open made; returns rc, so that a command ends with
 * `return lg_session_close(&s, rc);`. */
int lg_session_close(lg_session *s, int rc);

/* ---- what the plugins declare, printed (schema_print.c: plugins, inspect) -------------------- */

/* A node type as one JSON object (no newline), with its plugin's name when p is given. */
void lg_print_type_json(lg_str *out, const lg_node_type *t, const lg_plugin *p);
/* A node type as the indented text of `plugins` and `inspect`. */
void lg_print_type_text(FILE *f, const lg_node_type *t, const lg_plugin *p);
/* A parameter value as written in a graph file. */
void lg_print_value(lg_str *out, const lg_value *v, lg_param_type type);
/* The command line `[--json]` (plugins) or `NAME [--json]` (inspect, want_name): sets *json
 * and *name; returns 0, or -1 after printing what is wrong (the command exits 2). */
int lg_json_args(int argc, char **argv, bool *json, const char **name, bool want_name);

#endif
