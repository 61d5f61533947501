/* host/commands.h: commands of the lightgraph program that live outside host.h's scope. */
#ifndef LG_HOST_COMMANDS_H
#define LG_HOST_COMMANDS_H

/* lightgraph diff A B [--heatmap OUT] [--heat-max X] [--json] [--max-rmse X] [--max-abs X]
 * argv[0] is "diff". Returns the exit status. */
int lg_cmd_diff(int argc, char **argv);

#endif
