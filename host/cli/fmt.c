/* lightgraph fmt GRAPH [-i]: the graph file in its canonical form, on stdout or (-i) in
 * place, written atomically. Needs no plugin: the graph is parsed, not checked. */
#include "cli/commands.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int lg_cmd_fmt(int argc, char **argv)
{
    lg_session s;
    int rc = lg_session_open(&s, argc, argv, false);
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
    return lg_session_close(&s, rc);
}
