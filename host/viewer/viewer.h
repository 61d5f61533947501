/*
 * host/viewer/viewer.h: the viewer layer (docs/viewer.md): an interactive window on a
 * graph, with live parameters, a camera, a --script and hot reload.
 */
#ifndef LG_HOST_VIEWER_VIEWER_H
#define LG_HOST_VIEWER_VIEWER_H

/* lightgraph view GRAPH [options]; argv[0] is "view". Returns the exit status. */
int lg_cmd_view(int argc, char **argv);

#endif
