/* Device paths that need no working device: error names, an unknown GL backend,
 * destroy(NULL), lg_cl_fail without a node, OSMesa with GALLIUM_DRIVER=softpipe, and "no
 * OpenCL platform" (the ICD loader pointed at an empty vendor directory through
 * OCL_ICD_VENDORS before the first CL call). */
#include <string.h>
#include <unistd.h>

#include "lightgraph/cl.h"
#include "exec/device.h"
#include "devtest.h"

int main(void)
{
    static const struct {
        cl_int code;
        const char *name;
    } cl[] = {
        { CL_SUCCESS, "CL_SUCCESS" },
        { CL_DEVICE_NOT_FOUND, "CL_DEVICE_NOT_FOUND" },
        { CL_BUILD_PROGRAM_FAILURE, "CL_BUILD_PROGRAM_FAILURE" },
        { CL_KERNEL_ARG_INFO_NOT_AVAILABLE, "CL_KERNEL_ARG_INFO_NOT_AVAILABLE" },
        { CL_INVALID_VALUE, "CL_INVALID_VALUE" },
        { CL_INVALID_BUILD_OPTIONS, "CL_INVALID_BUILD_OPTIONS" },
        { CL_INVALID_DEVICE_PARTITION_COUNT, "CL_INVALID_DEVICE_PARTITION_COUNT" },
        { -69, "CL_INVALID_PIPE_SIZE" },
        { -70, "CL_INVALID_DEVICE_QUEUE" },
        { -71, "CL_INVALID_SPEC_ID" },
        { -72, "CL_MAX_SIZE_RESTRICTION_EXCEEDED" },
        { -1001, "CL_PLATFORM_NOT_FOUND_KHR" },
        { -20, "unknown" },
        { 1, "unknown" },
        { -73, "unknown" },
    };
    for (size_t i = 0; i < sizeof cl / sizeof cl[0]; i++)
        CHECKF(strcmp(lg_cl_strerror(cl[i].code), cl[i].name) == 0, "%d: '%s', expected '%s'",
               cl[i].code, lg_cl_strerror(cl[i].code), cl[i].name);
    /* Every code from -1 to -19 and -30 to -72 has a name. */
    for (cl_int c = -1; c >= -72; c--)
        if (c > -20 || c <= -30)
            CHECKF(strncmp(lg_cl_strerror(c), "CL_", 3) == 0, "%d has no name", c);

    CHECKF(strcmp(lg_gl_strerror(GL_INVALID_ENUM), "GL_INVALID_ENUM") == 0, "GL_INVALID_ENUM");
    CHECKF(strcmp(lg_gl_strerror(GL_INVALID_FRAMEBUFFER_OPERATION),
                  "GL_INVALID_FRAMEBUFFER_OPERATION") == 0,
           "GL_INVALID_FRAMEBUFFER_OPERATION");
    CHECKF(strcmp(lg_gl_strerror(GL_OUT_OF_MEMORY), "GL_OUT_OF_MEMORY") == 0, "OOM");
    CHECKF(strcmp(lg_gl_strerror(0x1234), "unknown GL error") == 0, "0x1234");

    CHECKF(lg_cl_fail(NULL, CL_INVALID_VALUE, "x") == LG_ERR_DEVICE, "lg_cl_fail(NULL)");
    devtest_clear();
    CHECKF(lg_cl_fail(devtest_node(), -1001, NULL) == LG_ERR_DEVICE &&
               strcmp(devtest_errors, "OpenCL: CL_PLATFORM_NOT_FOUND_KHR (-1001)") == 0,
           "message: %s", devtest_errors);

    char err[512] = "";
    lg_gl_device *gl = (lg_gl_device *)&err; /* must be cleared on failure */
    int rc = lg_gl_device_create(&gl, "vulkan", err, sizeof err);
    CHECKF(rc == LG_ERR_DEVICE && gl == NULL, "unknown backend: rc %d", rc);
    CHECKF(strstr(err, "'vulkan'") && strstr(err, "osmesa"), "message: %s", err);
    lg_gl_device_destroy(&gl);
    lg_gl_device_destroy(NULL);

    /* A user's GALLIUM_DRIVER is kept: softpipe has no GL 4.5 in Mesa 22.3, so OSMesa
     * fails with a reason that names it (or, on a Mesa where it works, the description
     * shows softpipe). */
    setenv("GALLIUM_DRIVER", "softpipe", 1);
    rc = lg_gl_device_create(&gl, "osmesa", err, sizeof err);
    if (rc == 0) {
        const char *desc = lg_gl_device_description(gl);
        CHECKF(strstr(desc, "softpipe") != NULL, "GALLIUM_DRIVER overridden: %s", desc);
        lg_gl_device_destroy(&gl);
    } else {
        CHECKF(rc == LG_ERR_DEVICE && gl == NULL, "softpipe: rc %d", rc);
        CHECKF(strstr(err, "GALLIUM_DRIVER=softpipe") || strstr(err, "not found"), "message: %s",
               err);
        printf("osmesa with GALLIUM_DRIVER=softpipe: %s\n", err);
    }

    /* No platform: OCL_ICD_VENDORS names a directory without .icd files. */
    char dir[] = "/tmp/lg-no-icd-XXXXXX";
    CHECKF(mkdtemp(dir) != NULL, "mkdtemp");
    setenv("OCL_ICD_VENDORS", dir, 1);
    lg_cl_dev *cldev = (lg_cl_dev *)&err;
    rc = lg_cl_device_create(&cldev, err, sizeof err);
    rmdir(dir);
    CHECKF(rc == LG_ERR_DEVICE && cldev == NULL, "no platform: rc %d", rc);
    CHECKF(strcmp(err, "no OpenCL platform (clGetPlatformIDs: CL_PLATFORM_NOT_FOUND_KHR)") == 0,
           "message: %s", err);
    lg_cl_device_destroy(&cldev);
    lg_cl_device_destroy(NULL);
    return check_report("device_errors");
}
