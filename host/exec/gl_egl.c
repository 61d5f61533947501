/* The EGL backend: a GL 4.5 core context on the surfaceless platform
 * (EGL_MESA_platform_surfaceless) when the client library offers it, else on the default
 * display; current without a surface (EGL_KHR_surfaceless_context) or on a 1x1 pbuffer. */
#include "exec/gl_backend.h"

#include <dlfcn.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/types.h"

/* Types and constants only: libEGL is opened with dlopen. */
#define EGL_NO_PLATFORM_SPECIFIC_TYPES /* no X11 or Wayland headers */
#include <EGL/egl.h>
#include <EGL/eglext.h>

/* The library stays loaded for the life of the process, for the reason given in
 * gl_osmesa.c (Mesa's llvmpipe threads and atexit handlers), and so does the display
 * (see egl_destroy). */
static struct egl_lib {
    void *lib;
    PFNEGLGETPROCADDRESSPROC GetProcAddress;
    PFNEGLQUERYSTRINGPROC QueryString;
    PFNEGLGETDISPLAYPROC GetDisplay;
    PFNEGLINITIALIZEPROC Initialize;
    PFNEGLBINDAPIPROC BindAPI;
    PFNEGLCHOOSECONFIGPROC ChooseConfig;
    PFNEGLCREATECONTEXTPROC CreateContext;
    PFNEGLDESTROYCONTEXTPROC DestroyContext;
    PFNEGLCREATEPBUFFERSURFACEPROC CreatePbufferSurface;
    PFNEGLDESTROYSURFACEPROC DestroySurface;
    PFNEGLMAKECURRENTPROC MakeCurrent;
    PFNEGLGETERRORPROC GetError;
    PFNEGLRELEASETHREADPROC ReleaseThread;
} egl;

typedef struct egl_state {
    EGLDisplay dpy;
    EGLContext ctx;
    EGLSurface surface; /* EGL_NO_SURFACE when surfaceless */
} egl_state;

static const char *egl_strerror(EGLint e)
{
    switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
    }
}

/* Whole-word search in a space-separated extension string. */
static bool has_extension(const char *list, const char *name)
{
    if (!list)
        return false;
    size_t n = strlen(name);
    for (const char *p = list; (p = strstr(p, name)) != NULL; p += n) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    }
    return false;
}

static int load_library(char *err, size_t errlen)
{
    if (egl.lib)
        return 0;
    void *lib = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        snprintf(err, errlen, "EGL: libEGL.so.1 not found (dlopen: %s)", dlerror());
        return LG_ERR_DEVICE;
    }
    static const struct {
        const char *name;
        size_t offset;
    } symbols[] = {
#define SYM(f) { "egl" #f, offsetof(struct egl_lib, f) }
        SYM(GetProcAddress), SYM(QueryString),    SYM(GetDisplay),
        SYM(Initialize),     SYM(BindAPI),        SYM(ChooseConfig),
        SYM(CreateContext),  SYM(DestroyContext), SYM(CreatePbufferSurface),
        SYM(DestroySurface), SYM(MakeCurrent),    SYM(GetError),
        SYM(ReleaseThread),
#undef SYM
    };
    for (size_t i = 0; i < sizeof symbols / sizeof symbols[0]; i++) {
        void *fn = dlsym(lib, symbols[i].name);
        if (!fn) {
            snprintf(err, errlen, "EGL: %s missing from libEGL.so.1", symbols[i].name);
            dlclose(lib);
            return LG_ERR_DEVICE;
        }
        /* POSIX guarantees that dlsym's void * converts to a function pointer. */
        memcpy((char *)&egl + symbols[i].offset, &fn, sizeof fn);
    }
    egl.lib = lib;
    return 0;
}

static GLADapiproc egl_load(void *state, const char *name)
{
    (void)state;
    return (GLADapiproc)egl.GetProcAddress(name);
}

static void egl_destroy(void *p)
{
    egl_state *s = p;
    if (!s)
        return;
    if (s->dpy != EGL_NO_DISPLAY) {
        egl.MakeCurrent(s->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (s->ctx != EGL_NO_CONTEXT)
            egl.DestroyContext(s->dpy, s->ctx);
        if (s->surface != EGL_NO_SURFACE)
            egl.DestroySurface(s->dpy, s->surface);
        /* No eglTerminate: a display is one per process (every eglGetPlatformDisplay
         * call returns the same handle), so terminating it would pull it from under any
         * other context on it; it stays initialized, like the library stays loaded. */
    }
    egl.ReleaseThread();
    free(s);
}

/* The surfaceless platform's display, or EGL_NO_DISPLAY with the reason in `why`. */
static EGLDisplay surfaceless_display(char *why, size_t whylen)
{
    /* Client extensions: NULL when the library has no EGL_EXT_client_extensions. */
    const char *client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client) {
        egl.GetError(); /* EGL_BAD_DISPLAY by design; do not leave it pending */
        snprintf(why, whylen, "no client extensions");
        return EGL_NO_DISPLAY;
    }
    if (!has_extension(client, "EGL_MESA_platform_surfaceless")) {
        snprintf(why, whylen, "no EGL_MESA_platform_surfaceless");
        return EGL_NO_DISPLAY;
    }
    EGLDisplay dpy = EGL_NO_DISPLAY;
    if (has_extension(client, "EGL_EXT_platform_base")) {
        PFNEGLGETPLATFORMDISPLAYEXTPROC get =
            (PFNEGLGETPLATFORMDISPLAYEXTPROC)egl.GetProcAddress("eglGetPlatformDisplayEXT");
        if (get)
            dpy = get(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    } else {
        /* EGL 1.5 has the same entry point in core. */
        PFNEGLGETPLATFORMDISPLAYPROC get =
            (PFNEGLGETPLATFORMDISPLAYPROC)egl.GetProcAddress("eglGetPlatformDisplay");
        if (get)
            dpy = get(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    }
    if (dpy == EGL_NO_DISPLAY) {
        snprintf(why, whylen, "eglGetPlatformDisplay(SURFACELESS_MESA): %s",
                 egl_strerror(egl.GetError()));
        return EGL_NO_DISPLAY;
    }
    EGLint major, minor;
    if (!egl.Initialize(dpy, &major, &minor)) {
        snprintf(why, whylen, "eglInitialize(surfaceless): %s", egl_strerror(egl.GetError()));
        return EGL_NO_DISPLAY;
    }
    return dpy;
}

int lg_gl_egl_open(lg_gl_backend *out, char *err, size_t errlen)
{
    int rc = load_library(err, errlen);
    if (rc)
        return rc;

    egl_state *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "EGL: out of memory");
        return LG_ERR_DEVICE;
    }
    s->dpy = EGL_NO_DISPLAY;
    s->ctx = EGL_NO_CONTEXT;
    s->surface = EGL_NO_SURFACE;

    char why[256] = "";
    bool surfaceless = true;
    s->dpy = surfaceless_display(why, sizeof why);
    if (s->dpy == EGL_NO_DISPLAY) {
        surfaceless = false;
        EGLDisplay dpy = egl.GetDisplay(EGL_DEFAULT_DISPLAY);
        EGLint major, minor;
        if (dpy == EGL_NO_DISPLAY) {
            snprintf(err, errlen, "EGL: no display (surfaceless: %s; default display: none)", why);
            goto fail;
        }
        if (!egl.Initialize(dpy, &major, &minor)) {
            snprintf(err, errlen,
                     "EGL: no display (surfaceless: %s; default display: "
                     "eglInitialize: %s)",
                     why, egl_strerror(egl.GetError()));
            goto fail;
        }
        s->dpy = dpy;
    }
    const char *version = egl.QueryString(s->dpy, EGL_VERSION);
    const char *exts = egl.QueryString(s->dpy, EGL_EXTENSIONS);
    int vmaj = 0, vmin = 0;
    if (version)
        sscanf(version, "%d.%d", &vmaj, &vmin);
    if (vmaj * 10 + vmin < 15 && !has_extension(exts, "EGL_KHR_create_context")) {
        snprintf(err, errlen,
                 "EGL: version %s without EGL_KHR_create_context cannot ask "
                 "for a 4.5 core context",
                 version ? version : "?");
        goto fail;
    }
    if (!egl.BindAPI(EGL_OPENGL_API)) {
        snprintf(err, errlen, "EGL: eglBindAPI(EGL_OPENGL_API): %s (no desktop GL)",
                 egl_strerror(egl.GetError()));
        goto fail;
    }

    const EGLint config_attribs[] = {
        EGL_RENDERABLE_TYPE,
        EGL_OPENGL_BIT,
        EGL_SURFACE_TYPE,
        EGL_PBUFFER_BIT,
        EGL_RED_SIZE,
        8,
        EGL_GREEN_SIZE,
        8,
        EGL_BLUE_SIZE,
        8,
        EGL_ALPHA_SIZE,
        8,
        EGL_NONE,
    };
    EGLConfig config;
    EGLint nconfig = 0;
    if (!egl.ChooseConfig(s->dpy, config_attribs, &config, 1, &nconfig) || nconfig < 1) {
        snprintf(err, errlen, "EGL: no RGBA8 pbuffer config with OpenGL (%s)",
                 nconfig < 1 ? "none matched" : egl_strerror(egl.GetError()));
        goto fail;
    }
    const EGLint context_attribs[] = {
        EGL_CONTEXT_MAJOR_VERSION,
        4,
        EGL_CONTEXT_MINOR_VERSION,
        5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_NONE,
    };
    s->ctx = egl.CreateContext(s->dpy, config, EGL_NO_CONTEXT, context_attribs);
    if (s->ctx == EGL_NO_CONTEXT) {
        snprintf(err, errlen, "EGL: eglCreateContext(OpenGL 4.5 core): %s",
                 egl_strerror(egl.GetError()));
        goto fail;
    }
    /* On the default display (X11, Wayland, ... whatever Mesa picked) a 1x1 pbuffer is
     * the portable choice; only the surfaceless platform goes without a surface. */
    if (!surfaceless || !has_extension(exts, "EGL_KHR_surfaceless_context")) {
        const EGLint pbuffer_attribs[] = { EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE };
        s->surface = egl.CreatePbufferSurface(s->dpy, config, pbuffer_attribs);
        if (s->surface == EGL_NO_SURFACE) {
            snprintf(err, errlen, "EGL: eglCreatePbufferSurface(1x1): %s",
                     egl_strerror(egl.GetError()));
            goto fail;
        }
    }
    if (!egl.MakeCurrent(s->dpy, s->surface, s->surface, s->ctx)) {
        snprintf(err, errlen, "EGL: eglMakeCurrent: %s", egl_strerror(egl.GetError()));
        goto fail;
    }
    out->label = surfaceless ? "EGL surfaceless" : "EGL pbuffer";
    out->load = egl_load;
    out->destroy = egl_destroy;
    out->state = s;
    return 0;

fail:
    egl_destroy(s);
    return LG_ERR_DEVICE;
}
