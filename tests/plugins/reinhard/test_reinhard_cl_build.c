/*
 * Builds shaders/reinhard/reinhard.cl with the options the plugin uses (rgba32f and
 * rgba16f input) on the first OpenCL platform, and prints the build log on failure: the
 * offline check of the kernel (STYLE.md, practice 8). Exits 77 without an OpenCL device.
 */
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>
#include <stdio.h>
#include <stdlib.h>

#include "reinhard.cl.h"
#include "reinhard_launch.h"

int main(void)
{
    cl_platform_id plat;
    cl_uint np = 0;
    if (clGetPlatformIDs(1, &plat, &np) != CL_SUCCESS || np == 0) {
        fprintf(stderr, "no OpenCL platform: skipped\n");
        return 77;
    }
    cl_device_id dev;
    cl_uint nd = 0;
    if (clGetDeviceIDs(plat, CL_DEVICE_TYPE_ALL, 1, &dev, &nd) != CL_SUCCESS || nd == 0) {
        fprintf(stderr, "no OpenCL device: skipped\n");
        return 77;
    }
    cl_int err;
    cl_context ctx = clCreateContext(NULL, 1, &dev, NULL, NULL, &err);
    if (!ctx) {
        fprintf(stderr, "clCreateContext: %d: skipped\n", err);
        return 77;
    }
    /* as plugins/reinhard/reinhard.c builds it */
    char options[2][160];
    for (int i = 0; i < 2; i++)
        snprintf(options[i], sizeof options[i],
                 "-cl-std=CL1.2 -DLG_LOCAL=%u -DLG_MAP_LOCAL=%u -DLG_PPI=%u%s", RH_GROUP,
                 RH_CL_MAP_LOCAL, RH_CL_PPI, i ? " -DLG_IN_HALF=1" : "");
    static const char *const kernels[] = { "rh_reduce", "rh_reduce_final", "rh_map" };
    int failed = 0;
    for (int i = 0; i < 2; i++) {
        const char *src = lg_src_reinhard_cl;
        cl_program prog = clCreateProgramWithSource(ctx, 1, &src, NULL, &err);
        if (!prog) {
            fprintf(stderr, "clCreateProgramWithSource: %d\n", err);
            return 1;
        }
        err = clBuildProgram(prog, 1, &dev, options[i], NULL, NULL);
        size_t len = 0;
        clGetProgramBuildInfo(prog, dev, CL_PROGRAM_BUILD_LOG, 0, NULL, &len);
        char *log = calloc(1, len + 1);
        if (log)
            clGetProgramBuildInfo(prog, dev, CL_PROGRAM_BUILD_LOG, len, log, NULL);
        if (err != CL_SUCCESS) {
            fprintf(stderr, "%s [%s]: build failed (%d):\n%s\n", lg_src_reinhard_cl_file,
                    options[i], err, log ? log : "");
            failed = 1;
        } else {
            for (int k = 0; k < 3; k++) {
                cl_kernel kern = clCreateKernel(prog, kernels[k], &err);
                if (!kern) {
                    fprintf(stderr, "%s [%s]: no kernel %s (%d)\n", lg_src_reinhard_cl_file,
                            options[i], kernels[k], err);
                    failed = 1;
                } else {
                    clReleaseKernel(kern);
                }
            }
        }
        free(log);
        clReleaseProgram(prog);
    }
    clReleaseContext(ctx);
    return failed;
}
