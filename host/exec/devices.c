/* The devices of a run, made on the first node that needs one: a GL 4.5 context
 * (gl_device.c: OSMesa or EGL) and an OpenCL context and queue (cl_device.c). A device
 * that cannot be made is reported once per node that needs it, with the reason. */
#include "exec/exec.h"

#include <stdlib.h>

int lg_exec_need_gl(lg_exec *ex, lg_pnode *n)
{
    if (ex->dev.gl)
        return 0;
    if (!ex->dev.gl_error) {
        char err[512] = "";
        double t0 = lg_mono_now();
        const char *backend = ex->opts.gl_backend ? ex->opts.gl_backend : "osmesa";
        if (lg_gl_device_create(&ex->dev.gl, backend, err, sizeof err) == 0) {
            lg_hlog(LG_HINFO, "GL device: %s (%.1f ms)", lg_gl_device_description(ex->dev.gl),
                    (lg_mono_now() - t0) * 1e3);
            ex->dev.gl_timer_query = lg_gl_device_timer_query(ex->dev.gl);
            return 0;
        }
        ex->dev.gl_error = lg_xasprintf("no OpenGL 4.5 device (%s): %s", backend, err);
    }
    lg_node_errorf(n, "%s", ex->dev.gl_error);
    return LG_ERR_DEVICE;
}

int lg_exec_need_cl(lg_exec *ex, lg_pnode *n)
{
    if (ex->dev.cl)
        return 0;
    if (!ex->dev.cl_error) {
        char err[512] = "";
        double t0 = lg_mono_now();
        if (lg_cl_device_create(&ex->dev.cl, err, sizeof err) == 0) {
            lg_hlog(LG_HINFO, "CL device: %s (%.1f ms)", lg_cl_device_description(ex->dev.cl),
                    (lg_mono_now() - t0) * 1e3);
            return 0;
        }
        ex->dev.cl_error = lg_xasprintf("no OpenCL device: %s", err);
    }
    lg_node_errorf(n, "%s", ex->dev.cl_error);
    return LG_ERR_DEVICE;
}
