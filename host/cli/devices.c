/*
 * lightgraph devices [gl] [cl] [--gl osmesa|egl]: tries to make each named device (both
 * when none is named) as a render would, and prints one line per device on stdout:
 *
 *     gl: OpenGL 4.5 ... (osmesa)            the device's description
 *     cl: no OpenCL device: <why>            the message a render would fail with
 *
 * Exit status 0 when every named device can be made, 1 when one cannot, 2 on bad usage.
 * Test programs (the SDK's lightgraph-test library) ask this before running a backend, so
 * that "no device here" (a skip) is told apart from "the node failed" (a failure).
 */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "exec/device.h"
#include "cli/commands.h"

static int devices_usage(const char *what)
{
    if (what)
        fprintf(stderr, "lightgraph devices: %s\n", what);
    fprintf(stderr, "usage: lightgraph devices [gl] [cl] [--gl osmesa|egl]\n");
    return 2;
}

int lg_cmd_devices(int argc, char **argv)
{
    bool want_gl = false, want_cl = false;
    const char *backend = "osmesa";
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "gl") == 0) {
            want_gl = true;
        } else if (strcmp(argv[i], "cl") == 0) {
            want_cl = true;
        } else if (strcmp(argv[i], "--gl") == 0 && i + 1 < argc) {
            backend = argv[++i];
            if (strcmp(backend, "osmesa") && strcmp(backend, "egl"))
                return devices_usage("--gl wants osmesa or egl");
        } else {
            fprintf(stderr, "lightgraph devices: unexpected argument '%s'\n", argv[i]);
            return devices_usage(NULL);
        }
    }
    if (!want_gl && !want_cl)
        want_gl = want_cl = true;

    int rc = 0;
    char err[512];
    if (want_gl) {
        lg_gl_device *gl = NULL;
        err[0] = 0;
        if (lg_gl_device_create(&gl, backend, err, sizeof err) == 0) {
            printf("gl: %s\n", lg_gl_device_description(gl));
            lg_gl_device_destroy(&gl);
        } else {
            /* the wording of a render that needs GL (host/exec/hostapi.c) */
            printf("gl: no OpenGL 4.5 device (%s): %s\n", backend, err);
            rc = 1;
        }
    }
    if (want_cl) {
        lg_cl_dev *cl = NULL;
        err[0] = 0;
        if (lg_cl_device_create(&cl, err, sizeof err) == 0) {
            printf("cl: %s\n", lg_cl_device_description(cl));
            lg_cl_device_destroy(&cl);
        } else {
            printf("cl: no OpenCL device: %s\n", err);
            rc = 1;
        }
    }
    return rc;
}
