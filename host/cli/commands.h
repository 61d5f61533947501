/* host/cli/commands.h: the commands of the lightgraph program (one file each in host/cli/)
 * and the helpers they share. */
#ifndef LG_HOST_CLI_COMMANDS_H
#define LG_HOST_CLI_COMMANDS_H

#include "plan/plan.h"

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

/* commands (cmd_*.c); argv[0] is the command's name; return the exit status */
int lg_cmd_render(int argc, char **argv);
int lg_cmd_check(int argc, char **argv);
int lg_cmd_fmt(int argc, char **argv);
int lg_cmd_dot(int argc, char **argv);
int lg_cmd_plugins(int argc, char **argv);
int lg_cmd_inspect(int argc, char **argv);
int lg_cmd_sweep(int argc, char **argv);
int lg_cmd_devices(int argc, char **argv);
int lg_cmd_view(int argc, char **argv);


/* ---- JSON and text introspection (cmd_info.c) ---------------------------------------- */
void lg_print_type_json(lg_str *out, const lg_node_type *t, const lg_plugin *p);
void lg_print_value(lg_str *out, const lg_value *v, lg_param_type type);


/* lightgraph diff A B [--heatmap OUT] [--heat-max X] [--json] [--max-rmse X] [--max-abs X]
 * argv[0] is "diff". Returns the exit status. */
int lg_cmd_diff(int argc, char **argv);

/* lightgraph conform PLUGIN.so [--json] [--quick] [-v] (cmd_conform.c, docs/conform.md);
 * argv[0] is "conform". Returns the exit status: 0 every contract holds, 1 one is broken
 * (the report names the node type, the check and the values), 2 bad usage. */
int lg_cmd_conform(int argc, char **argv);

#endif
