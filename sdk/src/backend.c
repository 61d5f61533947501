/* The choices of the shared `backend` parameter (LG_PARAM_BACKEND, lightgraph/plugin.h):
 * one list per set of backends, always in the order cpu, gl, cl. */
#include "lightgraph/plugin.h"

LG_API const char *const lg_backend_names[8][4] = {
    [0] = { NULL },
    [LG_BACKEND_CPU] = { "cpu", NULL },
    [LG_BACKEND_GL] = { "gl", NULL },
    [LG_BACKEND_CPU | LG_BACKEND_GL] = { "cpu", "gl", NULL },
    [LG_BACKEND_CL] = { "cl", NULL },
    [LG_BACKEND_CPU | LG_BACKEND_CL] = { "cpu", "cl", NULL },
    [LG_BACKEND_GL | LG_BACKEND_CL] = { "gl", "cl", NULL },
    [LG_BACKEND_CPU | LG_BACKEND_GL | LG_BACKEND_CL] = { "cpu", "gl", "cl", NULL },
};
