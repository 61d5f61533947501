/* host/commands.h: commands of the lightgraph program that live outside host.h's scope. */
#ifndef LG_HOST_COMMANDS_H
#define LG_HOST_COMMANDS_H

/* lightgraph diff A B [--heatmap OUT] [--heat-max X] [--json] [--max-rmse X] [--max-abs X]
 * argv[0] is "diff". Returns the exit status. */
int lg_cmd_diff(int argc, char **argv);

/* lightgraph conform PLUGIN.so [--json] [--quick] [-v] (cmd_conform.c, docs/conform.md);
 * argv[0] is "conform". Returns the exit status: 0 every contract holds, 1 one is broken
 * (the report names the node type, the check and the values), 2 bad usage. */
int lg_cmd_conform(int argc, char **argv);

#endif
