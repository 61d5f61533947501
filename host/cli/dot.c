/* lightgraph dot GRAPH: the checked graph as Graphviz dot on stdout. */
#include "cli/commands.h"

#include <stdio.h>
#include <stdlib.h>

int lg_cmd_dot(int argc, char **argv)
{
    lg_session s;
    int rc = lg_session_open(&s, argc, argv, true);
    if (rc == 0) {
        char *text = lg_graph_dot(s.g, s.c);
        fputs(text, stdout);
        free(text);
    }
    return lg_session_close(&s, rc);
}
