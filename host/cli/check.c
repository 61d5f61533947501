/* lightgraph check GRAPH [--set ...]: parses and checks a graph against the plugins found;
 * nothing runs. Exit status 0, or 2 for a bad graph (diagnostics on stderr). */
#include "cli/commands.h"

#include <stdio.h>

int lg_cmd_check(int argc, char **argv)
{
    lg_session s;
    int rc = lg_session_open(&s, argc, argv, true);
    if (rc == 0)
        printf("%s: ok (%u nodes, %u outputs)\n", s.a.graph, s.c->n_nodes, s.c->n_outputs);
    return lg_session_close(&s, rc);
}
