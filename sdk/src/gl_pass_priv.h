/* What gl_pass.c shares with the SDK's other sources (not installed). */
#ifndef LG_SDK_GL_PASS_PRIV_H
#define LG_SDK_GL_PASS_PRIV_H

#include "lightgraph/gl_pass.h"

/* The node the pass reports on (gl_material.c). */
lg_node *lg_gl_pass_node_(const lg_gl_pass *pass);

#endif
