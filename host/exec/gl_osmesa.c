/* The OSMesa backend: a GL 4.5 core context on llvmpipe, rendering into a tiny buffer
 * the device owns (nodes render to their own framebuffer objects). */
#include "exec/gl_backend.h"

#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/types.h"

/* osmesa.h includes <GL/gl.h>, which glad's header has already replaced (it defines
 * __gl_h_): we take only the OSMesaContext type and the constants from it. */
#include <GL/osmesa.h>

typedef OSMesaContext (*create_attribs_fn)(const int *attribs, OSMesaContext share);
typedef GLboolean (*make_current_fn)(OSMesaContext ctx, void *buffer, GLenum type, GLsizei width,
                                     GLsizei height);
typedef OSMESAproc (*get_proc_fn)(const char *name);
typedef void (*destroy_context_fn)(OSMesaContext ctx);

enum { BUFFER_SIZE = 16 };

/* The library stays loaded for the life of the process: llvmpipe keeps a process-wide
 * screen with rasterizer threads and atexit handlers, and unloading the code under them
 * crashes at exit. Devices are created from the host's main thread, so no lock. */
static struct {
    void *lib;
    create_attribs_fn create_attribs;
    make_current_fn make_current;
    get_proc_fn get_proc;
    destroy_context_fn destroy_context;
} osm;

typedef struct osmesa_state {
    OSMesaContext ctx;
    unsigned char buffer[BUFFER_SIZE * BUFFER_SIZE * 4];
} osmesa_state;

static int load_library(char *err, size_t errlen)
{
    if (osm.lib)
        return 0;
    static const char *const names[] = { "libOSMesa.so.8", "libOSMesa.so" };
    char first_error[256] = "";
    void *lib = NULL;
    for (size_t i = 0; i < sizeof names / sizeof names[0] && !lib; i++) {
        lib = dlopen(names[i], RTLD_NOW | RTLD_LOCAL);
        if (!lib && i == 0)
            snprintf(first_error, sizeof first_error, "%s", dlerror());
    }
    if (!lib) {
        snprintf(err, errlen, "OSMesa: libOSMesa.so.8 not found (dlopen: %s)", first_error);
        return LG_ERR_DEVICE;
    }
    static const char *const symbols[] = { "OSMesaCreateContextAttribs", "OSMesaMakeCurrent",
                                           "OSMesaGetProcAddress", "OSMesaDestroyContext" };
    void *fn[4];
    for (size_t i = 0; i < 4; i++) {
        fn[i] = dlsym(lib, symbols[i]);
        if (!fn[i]) {
            snprintf(err, errlen, "OSMesa: %s missing from libOSMesa (Mesa older than 12?)",
                     symbols[i]);
            dlclose(lib);
            return LG_ERR_DEVICE;
        }
    }
    /* dlsym returns void *; POSIX guarantees the conversion to a function pointer. */
    memcpy(&osm.create_attribs, &fn[0], sizeof fn[0]);
    memcpy(&osm.make_current, &fn[1], sizeof fn[1]);
    memcpy(&osm.get_proc, &fn[2], sizeof fn[2]);
    memcpy(&osm.destroy_context, &fn[3], sizeof fn[3]);
    osm.lib = lib;
    return 0;
}

static GLADapiproc osmesa_load(void *state, const char *name)
{
    (void)state;
    return (GLADapiproc)osm.get_proc(name);
}

static void osmesa_destroy(void *p)
{
    osmesa_state *s = p;
    if (!s)
        return;
    if (s->ctx) {
        /* Release before destroying: OSMesa keeps the current context in thread-local
         * state that would otherwise point at freed memory. */
        osm.make_current(NULL, NULL, 0, 0, 0);
        osm.destroy_context(s->ctx);
    }
    free(s);
}

int lg_gl_osmesa_open(lg_gl_backend *out, char *err, size_t errlen)
{
    /* Mesa 22.3's OSMesa picks its gallium driver from GALLIUM_DRIVER (else zink first,
     * then llvmpipe); llvmpipe is the only one here with GL 4.5. main() sets that default
     * before any thread starts (lg_env_defaults): setting it here, after PoCL's and the
     * pool's threads exist, raced their getenv() and crashed (issue 20). */
    int rc = load_library(err, errlen);
    if (rc)
        return rc;

    osmesa_state *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "OSMesa: out of memory");
        return LG_ERR_DEVICE;
    }
    const int attribs[] = {
        OSMESA_FORMAT,
        OSMESA_RGBA,
        OSMESA_DEPTH_BITS,
        0,
        OSMESA_STENCIL_BITS,
        0,
        OSMESA_ACCUM_BITS,
        0,
        OSMESA_PROFILE,
        OSMESA_CORE_PROFILE,
        OSMESA_CONTEXT_MAJOR_VERSION,
        4,
        OSMESA_CONTEXT_MINOR_VERSION,
        5,
        0,
    };
    s->ctx = osm.create_attribs(attribs, NULL);
    if (!s->ctx) {
        const char *drv = getenv("GALLIUM_DRIVER");
        snprintf(err, errlen,
                 "OSMesa: OSMesaCreateContextAttribs failed for an OpenGL 4.5 core profile "
                 "context (GALLIUM_DRIVER=%s; llvmpipe is needed for 4.5)",
                 drv ? drv : "unset");
        free(s);
        return LG_ERR_DEVICE;
    }
    if (!osm.make_current(s->ctx, s->buffer, GL_UNSIGNED_BYTE, BUFFER_SIZE, BUFFER_SIZE)) {
        snprintf(err, errlen, "OSMesa: OSMesaMakeCurrent failed on a %dx%d RGBA buffer",
                 BUFFER_SIZE, BUFFER_SIZE);
        osm.destroy_context(s->ctx);
        free(s);
        return LG_ERR_DEVICE;
    }
    out->label = "OSMesa";
    out->load = osmesa_load;
    out->destroy = osmesa_destroy;
    out->state = s;
    return 0;
}
