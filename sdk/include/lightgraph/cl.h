/*
 * lightgraph/cl.h: OpenCL for plugins, optional.
 *
 * The host owns one context and one in-order queue (profiling enabled) on the first
 * usable platform, created only if a planned node runs on LG_DEVICE_CL. Programs are
 * built once per process and cached by source and options; a failed build reports its log.
 *
 * A kernel is run through an lg_cl_pass (since ABI 3.0), the OpenCL twin of lg_gl_pass: a
 * descriptor names the source texts, the build options and the kernel; the pass is made
 * once (the program from the host's cache, the kernel from it), its arguments are set one
 * at a time, each checked at once, and lg_cl_pass_run enqueues it and hands the event to
 * the profile. Scratch memory is an lg_cl_buffer, remade only when too small:
 *
 *     static const char *const src[] = { lg_src_rgbe_cl, lg_src_blur_cl };
 *     static const char *const names[] = { lg_src_rgbe_cl_file, lg_src_blur_cl_file };
 *     if (!st->pass) {                                   // in execute (or prepare)
 *         lg_cl_pass_desc d = { .name = "blur rows", .sources = src, .source_names = names,
 *                               .n_sources = 2, .options = "-cl-std=CL1.2",
 *                               .kernel = "blur_rows" };
 *         if ((rc = lg_cl_pass_create(n, &d, &st->pass))) return rc;
 *     }
 *     if ((rc = lg_cl_buffer_recreate(n, &st->tmp, bytes, 0))) return rc;
 *     lg_cl_pass_arg_resource(st->pass, 0, lg_input(n, 0), LG_READ);
 *     lg_cl_pass_arg_mem(st->pass, 1, st->tmp.mem);
 *     lg_cl_pass_arg_uint(st->pass, 2, width);
 *     size_t global[2] = { width, height };
 *     return lg_cl_pass_run(st->pass, 2, global, NULL);   // the first failure above, or
 *                                                         // the enqueue's
 *
 *     lg_cl_pass_destroy(&st->pass);                     // in destroy
 *     lg_cl_buffer_destroy(n, &st->tmp);
 *
 * Plugins link OpenCL through the ICD loader (ocl-icd), never a vendor library, and call
 * no clCreateKernel, clSetKernelArg, clEnqueueNDRangeKernel, clCreateBuffer or
 * clReleaseMemObject of their own (tests/unit/rules_cl checks plugins/ and sdk/template/).
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

/* The name of an OpenCL error code ("CL_OUT_OF_RESOURCES"), or "unknown". */
LG_API const char *lg_cl_strerror(cl_int err);

/* Reports "what: CL_NAME (code)" for this node and returns LG_ERR_DEVICE. */
LG_API int lg_cl_fail(lg_node *node, cl_int err, const char *what);

/* ---- passes (since ABI 3.0) ------------------------------------------------------------------ */

typedef struct lg_cl_pass lg_cl_pass; /* opaque */

/* What a pass runs. Zero means default; the struct and every string and array it points
 * to need only live until lg_cl_pass_create returns (the pass keeps copies). */
typedef struct lg_cl_pass_desc {
    size_t struct_size; /* 0 or sizeof(lg_cl_pass_desc) */
    const char *name;   /* for messages, e.g. "reinhard map" (required) */
    /* The program's texts, joined in this order: shared twins first (lg_src_rgbe_cl,
     * lg_src_probe_cl, lg_src_medium_cl), the kernel's own file last. OpenCL C has no
     * #include of embedded text: this is how a kernel uses shaders/common/ code. */
    const char *const *sources;
    /* Their file names (the embed.py `_file` strings), one per source; may be NULL. When
     * given, each text is preceded by `#line 1 "name"` so that the build log says
     * "rgbe.cl:12:5: error" for an error in the shared twin and "blur.cl:40:9" for one in
     * the kernel's file. A name must not hold '"', '\\' or a newline. */
    const char *const *source_names;
    unsigned n_sources; /* >= 1 */
    /* Build options, e.g. "-cl-std=CL1.2 -DGROUP=256"; may be NULL. The pass adds
     * -cl-kernel-arg-info so that argument errors can name the argument. */
    const char *options;
    const char *kernel; /* the kernel function (required) */
    void *reserved[4];  /* zero */
} lg_cl_pass_desc;

/* Makes a pass: the program from the host's cache (built on first use with the sources
 * joined as above and the options plus -cl-kernel-arg-info; passes with the same sources
 * and options share one program) and the kernel `kernel` from it, with its argument count
 * and, when the runtime gives them, its argument names and types. Call it in execute (or
 * in prepare, once the node runs on LG_DEVICE_CL); keep the pass until destroy.
 * Returns 0 with *out set, or an LG_ERR_* after reporting, *out NULL: a bad descriptor
 * (LG_ERR_INVALID), no CL device or a build failure (LG_ERR_DEVICE; the host reported the
 * build log first, with the source file names), a kernel the program does not have
 * (LG_ERR_DEVICE, CL_INVALID_KERNEL_NAME, naming the kernels it has).
 * Ownership: the pass belongs to node `n` (its errors are reported there) and owns its
 * cl_kernel; the program is the host's. One pass belongs to one node and one thread. */
LG_API int lg_cl_pass_create(lg_node *n, const lg_cl_pass_desc *d, lg_cl_pass **out);

/* Releases the kernel and frees the pass. NULL-safe (p or *p); sets *p = NULL. */
LG_API void lg_cl_pass_destroy(lg_cl_pass **p);

/* The pass's kernel, for queries (clGetKernelWorkGroupInfo); owned by the pass. Setting
 * its arguments or enqueueing it directly bypasses the pass's checks: don't. */
LG_API cl_kernel lg_cl_pass_kernel(const lg_cl_pass *p);

/* Arguments, set one at a time and checked one at a time (clSetKernelArg). A failure is
 * reported at once, naming the pass, the kernel, the argument's index, its name and type
 * (when the runtime has argument info), the size given and the real CL error, e.g.
 *     cl pass 'blur rows': kernel blur_rows, argument 2 'width' (uint): 8 bytes:
 *     clSetKernelArg: CL_INVALID_ARG_SIZE (-51)
 * and fails the pass: the argument counts as unset, and the next lg_cl_pass_run returns
 * that error without enqueueing (a node may set all its arguments in a row and check only
 * the run). Each returns 0 or that LG_ERR_* (LG_ERR_DEVICE for a CL error, LG_ERR_INVALID
 * for a NULL pass, which reports nothing: create already did).
 * Values are copied by OpenCL at the call; an argument keeps its value for later runs
 * until set again.
 *   _arg:        `size` bytes at `value` (a struct, a cl_float16...); value NULL with a
 *                size is a __local buffer of that size (as lg_cl_pass_arg_local)
 *   _arg_mem:    a buffer; NULL sets a NULL pointer (an optional input the kernel tests)
 *   _arg_int/_uint/_float: 32-bit scalars (int, uint, float in the kernel)
 *   _arg_float4: v[0..3] as a float4
 *   _arg_local:  `bytes` of __local memory */
LG_API int lg_cl_pass_arg(lg_cl_pass *p, unsigned i, size_t size, const void *value);
LG_API int lg_cl_pass_arg_mem(lg_cl_pass *p, unsigned i, cl_mem m);
LG_API int lg_cl_pass_arg_int(lg_cl_pass *p, unsigned i, int32_t v);
LG_API int lg_cl_pass_arg_uint(lg_cl_pass *p, unsigned i, uint32_t v);
LG_API int lg_cl_pass_arg_float(lg_cl_pass *p, unsigned i, float v);
LG_API int lg_cl_pass_arg_float4(lg_cl_pass *p, unsigned i, const float v[4]);
LG_API int lg_cl_pass_arg_local(lg_cl_pass *p, unsigned i, size_t bytes);

/* A resource bound by access: maps `res` on CL (lg_map_cl) for LG_READ, LG_WRITE or
 * LG_READ_WRITE and sets argument i to its buffer (the pixels; map the resource with
 * lg_map_cl yourself for its depth plane). res NULL sets a NULL pointer, as for an
 * optional input that is not connected. A failed map (reported by the host) fails the
 * pass as a failed argument does. */
LG_API int lg_cl_pass_arg_resource(lg_cl_pass *p, unsigned i, const lg_resource *res,
                                   unsigned access);

/* Enqueues the kernel over `dims` (1..3) dimensions, global[d] work-items each (none 0),
 * in work-groups of local[d] (local NULL: the runtime chooses), on the host's queue, and
 * hands the event to the profile (lg_cl_profile: the node's GPU time). Every argument
 * must have been set since the pass was made: an unset one is reported by index and name.
 * After an argument failure, returns that error without enqueueing or reporting again.
 * An enqueue failure names the pass, the kernel, the sizes and the CL error. Returns 0 or
 * an LG_ERR_*. The run is queued, not finished: read results with a blocking read
 * (lg_cl_buffer_read) or let the host's next mapping wait for them. */
LG_API int lg_cl_pass_run(lg_cl_pass *p, unsigned dims, const size_t *global, const size_t *local);

/* ---- scratch buffers (since ABI 3.0) ------------------------------------------------------------
 *
 * Device memory a node keeps for itself (partial sums, uploaded tables, a history), in
 * libplacebo's recreate idiom: the struct is the handle, zero-initialised means "none
 * yet", lg_cl_buffer_recreate makes or keeps it, lg_cl_buffer_destroy frees it. Every
 * buffer made and freed is counted in the node's profile (lg_account_alloc /
 * lg_account_free), so --profile shows what a node holds, and a node that remakes one per
 * frame shows no growth. The node owns the buffer; free it in destroy. Never release
 * b->mem yourself. */
typedef struct lg_cl_buffer {
    cl_mem mem;         /* NULL: none */
    size_t size;        /* bytes it holds */
    cl_mem_flags flags; /* what it was made with */
} lg_cl_buffer;

/* Makes the buffer when absent, smaller than `size` bytes or made with other flags
 * (0 = CL_MEM_READ_WRITE; CL_MEM_USE_HOST_PTR and CL_MEM_COPY_HOST_PTR are refused: upload
 * with lg_cl_buffer_write); else keeps it, contents and all. A buffer made anew holds
 * exactly `size` bytes of undefined contents. `size` 0 is an error. On failure the old
 * buffer is gone, *b is zero and the error (naming the size, the flags and the CL error)
 * reported. Returns 0 or an LG_ERR_*. */
LG_API int lg_cl_buffer_recreate(lg_node *n, lg_cl_buffer *b, size_t size, cl_mem_flags flags);

/* Copies `size` bytes between host memory and the buffer at byte `offset` on the host's
 * queue, blocking: when it returns, `data` may be reused (write) or holds the bytes (read,
 * after every kernel queued before it). A range beyond b->size or no buffer is an error
 * naming both. Returns 0 or an LG_ERR_*. */
LG_API int lg_cl_buffer_write(lg_node *n, lg_cl_buffer *b, size_t offset, size_t size,
                              const void *data);
LG_API int lg_cl_buffer_read(lg_node *n, const lg_cl_buffer *b, size_t offset, size_t size,
                             void *data);

/* Releases the buffer (counted as freed) and zeroes *b. A zero struct is fine. */
LG_API void lg_cl_buffer_destroy(lg_node *n, lg_cl_buffer *b);

#ifdef __cplusplus
}
#endif
#endif
