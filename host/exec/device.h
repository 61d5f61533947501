/*
 * host/exec/device.h: the host's devices (private to the host).
 *
 * GL: one OpenGL 4.5 core context, headless, made current on the calling thread:
 *   - "osmesa": OSMesa (llvmpipe), host/exec/gl_osmesa.c, the default;
 *   - "egl":    EGL surfaceless (EGL_MESA_platform_surfaceless) or a pbuffer on the
 *               default display, host/exec/gl_egl.c.
 * Both libraries are opened with dlopen and GL entry points are resolved through the
 * context's get-proc-address into a GladGLContext: nothing links GL symbols.
 *
 * CL: one context and one in-order queue with profiling on the first usable platform and
 * device (PoCL here); programs built once per process, cached by (source, options).
 *
 * Devices are created lazily, only when a planned node asks for one.
 */
#ifndef LG_HOST_DEVICE_H
#define LG_HOST_DEVICE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/glad/gl.h"

/* ---- GL -------------------------------------------------------------------------------------- */

typedef struct lg_gl_device lg_gl_device;

/* backend: "osmesa" or "egl". On failure returns LG_ERR_DEVICE with the reason in err
 * ("OSMesa: libOSMesa.so.8 not found (dlopen: ...)", "EGL: no display", "context is GL
 * 3.1, need 4.5", ...). The context is current on return. */
int lg_gl_device_create(lg_gl_device **out, const char *backend, char *err, size_t errlen);
/* A device on a context someone else made and made current (the viewer's GLFW window,
 * host/exec/gl_backend.h): the same loading and checks as create. `backend->destroy` may be
 * NULL (the caller destroys the context, after lg_gl_device_destroy). */
struct lg_gl_backend;
int lg_gl_device_wrap(lg_gl_device **out, const struct lg_gl_backend *backend, char *err,
                      size_t errlen);
/* The function table; valid until destroy. */
const GladGLContext *lg_gl_device_table(const lg_gl_device *dev);
/* "OSMesa, llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6" */
const char *lg_gl_device_description(const lg_gl_device *dev);
/* Destroys the context; accepts NULL; clears *dev. */
void lg_gl_device_destroy(lg_gl_device **dev);
/* Makes the GL_TIME_ELAPSED query object that times the nodes on this device's context
 * (lg_exec.gl_timer_query) and spends its first result: llvmpipe's first timer query in a
 * context returns an absolute timestamp, which would otherwise be the first GL node's GPU
 * time. Returns the query's name; the caller deletes it (DeleteQueries) before the device. */
uint32_t lg_gl_device_timer_query(const lg_gl_device *dev);

/* The GL state contract (docs/devices.md): before each node the host resets the state that
 * nodes may change (lg_gl_state_reset); in debug builds it checks after each node that
 * the node restored what it must (lg_gl_state_check): draw/read framebuffer 0, current
 * program 0, vertex array 0, no buffer bound to GL_SHADER_STORAGE_BUFFER /
 * GL_UNIFORM_BUFFER / GL_ARRAY_BUFFER, image units 0..7 unbound, active texture unit 0.
 * Check returns 0, or -1 with a description of every deviation in err. */
void lg_gl_state_reset(const GladGLContext *gl);
int lg_gl_state_check(const GladGLContext *gl, char *err, size_t errlen);
/* "GL_INVALID_ENUM" etc. */
const char *lg_gl_strerror(GLenum e);

/* ---- CL -------------------------------------------------------------------------------------- */

typedef struct lg_cl_dev lg_cl_dev;

/* On failure returns LG_ERR_DEVICE with the reason in err ("no OpenCL platform
 * (clGetPlatformIDs: CL_PLATFORM_NOT_FOUND_KHR)"). */
int lg_cl_device_create(lg_cl_dev **out, char *err, size_t errlen);
void *lg_cl_device_context(const lg_cl_dev *dev); /* cl_context */
void *lg_cl_device_queue(const lg_cl_dev *dev);   /* cl_command_queue */
void *lg_cl_device_id(const lg_cl_dev *dev);      /* cl_device_id */
/* "Portable Computing Language, pthread-skylake-avx512, OpenCL 3.0 PoCL 3.1" */
const char *lg_cl_device_description(const lg_cl_dev *dev);
/* Builds (or finds in the per-process cache) a program. On failure returns NULL and sets
 * *log to a malloc'd message "name: build failed: <build log>" (caller frees). */
void *lg_cl_device_program(lg_cl_dev *dev, const char *name, const char *source,
                           const char *options, char **log);
void lg_cl_device_destroy(lg_cl_dev **dev);

#endif
