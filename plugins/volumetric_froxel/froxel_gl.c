/*
 * PLACEHOLDER of the gl backend of volumetric_froxel (froxel.h is its spec): helper D
 * replaces this file and shaders/volumetric_froxel/froxel_*.comp.
 */
#include "lightgraph/lightgraph.h"

#include "froxel.h"

int fx_gl_execute(lg_node *node, void **state, const fx_frame *f)
{
    (void)state;
    (void)f;
    return lg_error(node, "backend gl: not built yet");
}

void fx_gl_destroy(lg_node *node, void *state)
{
    (void)node;
    (void)state;
}
