/*
 * lightgraph/cl.h: OpenCL for plugins, optional.
 *
 * The host owns one context and one in-order queue (profiling enabled) on the first
 * usable platform, created only if a planned node runs on LG_DEVICE_CL. Programs are
 * built once per process and cached by source and options; a failed build reports its log.
 *
 *     cl_command_queue q = lg_cl_queue(node);
 *     cl_program p = lg_cl_program(node, "reinhard.cl", src, "-cl-std=CL1.2");
 *     if (!q || !p) return LG_ERR_DEVICE;
 *     ...
 *     cl_event ev;
 *     err = clEnqueueNDRangeKernel(q, k, 2, NULL, global, NULL, 0, NULL, &ev);
 *     if (err) return lg_cl_fail(node, err, "clEnqueueNDRangeKernel(map)");
 *     lg_cl_profile(node, ev);   // the host takes the event and counts its time
 *
 * Plugins link OpenCL through the ICD loader (ocl-icd), never a vendor library.
 */
#ifndef LIGHTGRAPH_CL_H
#define LIGHTGRAPH_CL_H

#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>

#include "lightgraph/host.h"

#ifdef __cplusplus
extern "C" {
#endif

static inline cl_context lg_cl_context(lg_node *n)
{
    return (cl_context)n->host->cl_context(n);
}
static inline cl_command_queue lg_cl_queue(lg_node *n)
{
    return (cl_command_queue)n->host->cl_queue(n);
}
static inline cl_device_id lg_cl_device(lg_node *n)
{
    return (cl_device_id)n->host->cl_device(n);
}
static inline cl_program lg_cl_program(lg_node *n, const char *name, const char *source,
                                       const char *options)
{
    return (cl_program)n->host->cl_program(n, name, source, options);
}
static inline void lg_cl_profile(lg_node *n, cl_event ev)
{
    n->host->cl_profile(n, (void *)ev);
}

/* OpenCL C has no #include of embedded text, so a kernel that uses shared code
 * (shaders/common/probe.cl, rgbe.cl) is built from the texts one after the other:
 *     const char *parts[] = { lg_src_rgbe_cl, lg_src_reinhard_cl };
 *     char *src = lg_cl_source_join(parts, 2);
 * Returns the parts joined with a newline between them, NUL-terminated, malloc'd: the
 * caller frees it with free(). NULL when out of memory or a part is NULL. */
LG_API char *lg_cl_source_join(const char *const *parts, size_t n_parts);

/* The name of an OpenCL error code ("CL_OUT_OF_RESOURCES"), or "unknown". */
LG_API const char *lg_cl_strerror(cl_int err);

/* Reports "what: CL_NAME (code)" for this node and returns LG_ERR_DEVICE. */
LG_API int lg_cl_fail(lg_node *node, cl_int err, const char *what);

#ifdef __cplusplus
}
#endif
#endif
