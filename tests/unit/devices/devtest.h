/*
 * tests/unit/devices/devtest.h: what the device tests share besides the checks
 * (tests/common/check.h): a clock, a minimal host (an lg_node whose lg_host_api has only
 * log and error) for the SDK helpers that report through the node, and the GL part of the
 * fake hosts of test_gl_mem and test_gl_pass.
 */
#ifndef LG_DEVTEST_H
#define LG_DEVTEST_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "common/check.h"
#include "exec/device.h"
#include "lightgraph/gl.h"
#include "lightgraph/host.h"

double devtest_now(void); /* monotonic seconds */

/* A node named "test" whose errors go to devtest_errors (cleared by devtest_clear) and
 * whose log messages go to stderr. */
lg_node *devtest_node(void);
extern char devtest_errors[16384];
extern int devtest_error_count;
void devtest_clear(void);

/* That node's host functions, for a test's own lg_host_api: log to stderr; errors appended
 * to devtest_errors (one a line), counted in devtest_error_count and echoed to stderr. */
void devtest_log(lg_node *n, lg_log_level level, const char *fmt, va_list ap);
void devtest_error(lg_node *n, const char *fmt, va_list ap);

/* ---- a fake host with GL --------------------------------------------------------------------- */

/* The GL table the fake host hands out (lg_host_api.gl); the test sets it once it has made
 * its device (lg_gl_device_table). */
extern const lg_gl *devtest_gl;

/* Makes the GL device named by argv[1] (osmesa or egl; osmesa without one) into *dev and
 * points devtest_gl at its table. Returns 0, or 1 after printing why there is none ("SKIP:
 * no GL device ..."): main() then returns check_skip. */
int devtest_gl_open(int argc, char **argv, lg_gl_device **dev);

/* lg_host_api.gl: devtest_gl. */
const void *devtest_host_gl(lg_node *n);

/* lg_host_api.gl_check, as the host's: drains GL's error queue and, if it held any, reports
 * the first on n as "GL error NAME while WHAT" and returns LG_ERR_DEVICE; else 0. */
int devtest_host_gl_check(lg_node *n, const char *what);

/* The first members of a GL test's fake host: an lg_host_api initialiser starts
 * { DEVTEST_GL_HOST, .account_alloc = ..., ... } and adds what the test needs. */
#define DEVTEST_GL_HOST                                                                            \
    .struct_size = sizeof(lg_host_api), .abi_major = LG_ABI_MAJOR, .abi_minor = LG_ABI_MINOR,      \
    .log = devtest_log, .error = devtest_error, .gl = devtest_host_gl,                             \
    .gl_check = devtest_host_gl_check

#endif
