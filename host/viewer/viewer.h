/*
 * host/viewer/viewer.h: the viewer layer (docs/viewer.md): an interactive window on a
 * graph, with live parameters, a camera, a --script and hot reload.
 *
 * The command that parses `lightgraph view`'s arguments is cli/view.c; this layer gets
 * what it parsed and checked, and owns everything from the window on.
 */
#ifndef LG_HOST_VIEWER_VIEWER_H
#define LG_HOST_VIEWER_VIEWER_H

#include <stdint.h>

#include "viewer/script.h"

/* What `lightgraph view` parsed. Every pointer stays the caller's and must outlive
 * lg_viewer_run; the viewer copies what it changes (the shown output). */
typedef struct lg_viewer_opts {
    const char *graph;       /* the graph file (required) */
    const char *const *sets; /* --set NODE.PARAM=VALUE, n_sets of them, in order */
    int n_sets;
    const char *show;        /* --show NODE[.PORT], or NULL: the first output */
    uint32_t width, height;  /* --size: the window's and the graph's, already checked */
    double dt;               /* --dt: seconds per frame of the graph's time */
    const lg_script *script; /* --script, loaded and checked; NULL: interactive */
} lg_viewer_opts;

/* Opens the window, loads the graph and runs the frame loop until the window closes, Esc,
 * the script's quit, or its end (the window then stays for the user). Prints its errors
 * ("lightgraph view: ..."). Returns the exit status: 0; 1 no display, no GL 4.5 context,
 * a failed first frame, a failed script expectation or a script left unfinished; 2 a bad
 * graph (parse, check, --set, --show). */
int lg_viewer_run(const lg_viewer_opts *o);

#endif
