/*
 * host/exec/gl_backend.h: what a GL context backend (gl_osmesa.c, gl_egl.c) gives gl_device.c
 * (private to those three files).
 *
 * A backend opens its library with dlopen, creates a GL 4.5 core context and makes it
 * current on the calling thread. gl_device.c then loads the GL entry points through
 * `load`, checks the version and builds the description. Backends never call GL.
 */
#ifndef LG_HOST_GL_BACKEND_H
#define LG_HOST_GL_BACKEND_H

#include <stddef.h>

#include "lightgraph/glad/gl.h"

typedef struct lg_gl_backend {
    /* Prefix of the device description: "OSMesa", "EGL surfaceless", "EGL pbuffer". */
    const char *label;
    /* The context's get-proc-address; `state` is passed as the user pointer. */
    GLADuserptrloadfunc load;
    /* Releases the context current on the calling thread, destroys it and frees state. */
    void (*destroy)(void *state);
    void *state;
} lg_gl_backend;

/* Both return 0 with *out filled and the context current, or LG_ERR_DEVICE with the
 * reason in err (prefixed with "OSMesa: " or "EGL: "). */
int lg_gl_osmesa_open(lg_gl_backend *out, char *err, size_t errlen);
int lg_gl_egl_open(lg_gl_backend *out, char *err, size_t errlen);

#endif
