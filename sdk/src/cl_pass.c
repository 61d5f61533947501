/* lg_cl_pass and lg_cl_buffer (lightgraph/cl.h): OpenCL kernels and scratch buffers of a
 * node, with every argument checked as it is set and every buffer counted in the profile. */
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/image.h" /* lg_bytes_text */

/* Unset arguments named in one message at most; the rest are counted. */
#define UNSET_NAMED 4

struct lg_cl_pass {
    lg_node *node; /* its errors are reported there */
    char *name;    /* the descriptor's, copied */
    char *kernel_name;
    cl_kernel kernel;
    cl_uint n_args;
    bool *set;       /* [n_args]: set since the pass was made (and not failed since) */
    char **arg_name; /* [n_args] or NULL: the runtime gave no argument info */
    char **arg_type; /* [n_args] or NULL */
    int failed;      /* 0, or the LG_ERR_* of an argument failure not yet returned by run */
};

static char *dup_str(const char *s)
{
    size_t len = strlen(s) + 1;
    char *d = malloc(len);
    if (d)
        memcpy(d, s, len);
    return d;
}

/* An argument's info string (CL_KERNEL_ARG_NAME, _TYPE_NAME), malloc'd, or NULL when the
 * runtime has none (CL_KERNEL_ARG_INFO_NOT_AVAILABLE: a program built without
 * -cl-kernel-arg-info, or one from a binary). */
static char *arg_info(cl_kernel k, cl_uint i, cl_kernel_arg_info what)
{
    size_t len = 0;
    if (clGetKernelArgInfo(k, i, what, 0, NULL, &len) != CL_SUCCESS || len == 0)
        return NULL;
    char *s = malloc(len + 1);
    if (!s)
        return NULL;
    if (clGetKernelArgInfo(k, i, what, len, s, NULL) != CL_SUCCESS) {
        free(s);
        return NULL;
    }
    s[len] = '\0';
    return s;
}

/* "argument 3 'w' (float4)", or "argument 3" without argument info. */
static void arg_label(const lg_cl_pass *p, unsigned i, char *buf, size_t size)
{
    const char *name = p->arg_name && i < p->n_args ? p->arg_name[i] : NULL;
    const char *type = p->arg_type && i < p->n_args ? p->arg_type[i] : NULL;
    if (name && type)
        snprintf(buf, size, "argument %u '%s' (%s)", i, name, type);
    else if (name)
        snprintf(buf, size, "argument %u '%s'", i, name);
    else
        snprintf(buf, size, "argument %u", i);
}

/* Every text preceded by `#line 1 "file"` when its name is known, so that the compiler's
 * messages point into the right file (the host's own #line names only the first). */
static char *join_sources(const lg_cl_pass_desc *d)
{
    size_t total = 1;
    for (unsigned i = 0; i < d->n_sources; i++) {
        total += strlen(d->sources[i]) + 1;
        if (d->source_names)
            total += strlen(d->source_names[i]) + 16;
    }
    char *src = malloc(total), *w = src;
    if (!src)
        return NULL;
    for (unsigned i = 0; i < d->n_sources; i++) {
        if (d->source_names)
            w += sprintf(w, "#line 1 \"%s\"\n", d->source_names[i]);
        size_t len = strlen(d->sources[i]);
        memcpy(w, d->sources[i], len);
        w += len;
        /* a text that does not end its last line would glue the next #line to it */
        if (i + 1 < d->n_sources)
            *w++ = '\n';
    }
    *w = '\0';
    return src;
}

/* The program's name for the host: its files joined by '+', so that passes with the same
 * texts and options share one cached program; the pass's name without file names. */
static char *program_name(const lg_cl_pass_desc *d)
{
    if (!d->source_names)
        return dup_str(d->name);
    size_t total = 1;
    for (unsigned i = 0; i < d->n_sources; i++)
        total += strlen(d->source_names[i]) + 1;
    char *s = malloc(total), *w = s;
    if (!s)
        return NULL;
    for (unsigned i = 0; i < d->n_sources; i++)
        w += sprintf(w, "%s%s", i ? "+" : "", d->source_names[i]);
    return s;
}

/* The kernels a program has ("rh_reduce;rh_map"), for a misspelt kernel name; "" if the
 * runtime cannot say. */
static void kernel_names(cl_program prog, char *buf, size_t size)
{
    buf[0] = '\0';
    size_t len = 0;
    if (clGetProgramInfo(prog, CL_PROGRAM_KERNEL_NAMES, 0, NULL, &len) != CL_SUCCESS || !len)
        return;
    char *s = malloc(len + 1);
    if (!s)
        return;
    if (clGetProgramInfo(prog, CL_PROGRAM_KERNEL_NAMES, len, s, NULL) == CL_SUCCESS) {
        s[len] = '\0';
        for (char *c = s; *c; c++)
            if (*c == ';')
                *c = ' ';
        snprintf(buf, size, "%s", s);
    }
    free(s);
}

static int check_desc(lg_node *n, const lg_cl_pass_desc *d)
{
    if (!d)
        return lg_error(n, "lg_cl_pass_create: no descriptor");
    if (!d->name || !d->name[0])
        return lg_error(n, "lg_cl_pass_create: the descriptor has no name");
    if (d->struct_size && d->struct_size != sizeof *d)
        return lg_error(n, "cl pass '%s': descriptor struct_size %zu, this SDK has %zu", d->name,
                        d->struct_size, sizeof *d);
    for (int i = 0; i < 4; i++)
        if (d->reserved[i])
            return lg_error(n,
                            "cl pass '%s': reserved[%d] is not zero (a descriptor of a "
                            "newer SDK?)",
                            d->name, i);
    if (!d->kernel || !d->kernel[0])
        return lg_error(n, "cl pass '%s': no kernel name", d->name);
    if (!d->sources || d->n_sources == 0)
        return lg_error(n, "cl pass '%s' (kernel %s): no sources", d->name, d->kernel);
    for (unsigned i = 0; i < d->n_sources; i++) {
        if (!d->sources[i])
            return lg_error(n, "cl pass '%s' (kernel %s): sources[%u] is NULL", d->name, d->kernel,
                            i);
        if (d->source_names && (!d->source_names[i] || !d->source_names[i][0] ||
                                strpbrk(d->source_names[i], "\"\\\n")))
            return lg_error(n,
                            "cl pass '%s' (kernel %s): source_names[%u] is %s%s%s (a file "
                            "name without '\"', '\\' or a newline)",
                            d->name, d->kernel, i, d->source_names[i] ? "\"" : "",
                            d->source_names[i] ? d->source_names[i] : "NULL",
                            d->source_names[i] ? "\"" : "");
    }
    return 0;
}

int lg_cl_pass_create(lg_node *n, const lg_cl_pass_desc *d, lg_cl_pass **out)
{
    if (!out)
        return lg_error(n, "lg_cl_pass_create: no place for the pass (out is NULL)");
    *out = NULL;
    int rc = check_desc(n, d);
    if (rc)
        return rc;
    if (!lg_cl_context(n) || !lg_cl_queue(n))
        return LG_ERR_DEVICE; /* the host said why */

    /* -cl-kernel-arg-info: argument names for the messages below; it changes no code */
    const char *opt = d->options ? d->options : "";
    size_t olen = strlen(opt) + sizeof " -cl-kernel-arg-info";
    char *options = malloc(olen);
    char *src = join_sources(d);
    char *pname = program_name(d);
    lg_cl_pass *p = calloc(1, sizeof *p);
    if (!options || !src || !pname || !p) {
        free(options), free(src), free(pname), free(p);
        return lg_error_code(n, LG_ERR_NOMEM, "cl pass '%s': out of memory", d->name);
    }
    snprintf(options, olen, "%s%s-cl-kernel-arg-info", opt, opt[0] ? " " : "");
    cl_program prog = lg_cl_program(n, pname, src, options);
    free(src);
    free(options);
    p->node = n;
    p->name = dup_str(d->name);
    p->kernel_name = dup_str(d->kernel);
    if (!prog) {
        /* the host reported the build log (or the missing device) */
        rc = lg_error_code(n, LG_ERR_DEVICE,
                           "cl pass '%s': kernel %s: the program (%s) did "
                           "not build",
                           d->name, d->kernel, pname);
        goto fail;
    }
    if (!p->name || !p->kernel_name) {
        rc = lg_error_code(n, LG_ERR_NOMEM, "cl pass '%s': out of memory", d->name);
        goto fail;
    }
    cl_int e;
    p->kernel = clCreateKernel(prog, d->kernel, &e);
    if (!p->kernel) {
        /* a misspelt name: say which kernels there are */
        char have[512];
        kernel_names(prog, have, sizeof have);
        rc = lg_error_code(n, LG_ERR_DEVICE,
                           "cl pass '%s': kernel %s: clCreateKernel: %s (%d)"
                           "%s%s%s%s",
                           d->name, d->kernel, lg_cl_strerror(e), (int)e,
                           have[0] ? "; the program " : "", have[0] ? pname : "",
                           have[0] ? " has: " : "", have);
        goto fail;
    }
    e = clGetKernelInfo(p->kernel, CL_KERNEL_NUM_ARGS, sizeof p->n_args, &p->n_args, NULL);
    if (e != CL_SUCCESS) {
        rc = lg_error_code(n, LG_ERR_DEVICE,
                           "cl pass '%s': kernel %s: clGetKernelInfo("
                           "CL_KERNEL_NUM_ARGS): %s (%d)",
                           d->name, d->kernel, lg_cl_strerror(e), (int)e);
        goto fail;
    }
    p->set = calloc(p->n_args ? p->n_args : 1, sizeof *p->set);
    if (!p->set) {
        rc = lg_error_code(n, LG_ERR_NOMEM, "cl pass '%s': out of memory", d->name);
        goto fail;
    }
    /* Names and types when the runtime has them; without, messages give indices only. */
    if (p->n_args) {
        p->arg_name = calloc(p->n_args, sizeof *p->arg_name);
        p->arg_type = calloc(p->n_args, sizeof *p->arg_type);
        bool any = false;
        for (cl_uint i = 0; p->arg_name && p->arg_type && i < p->n_args; i++) {
            p->arg_name[i] = arg_info(p->kernel, i, CL_KERNEL_ARG_NAME);
            p->arg_type[i] = arg_info(p->kernel, i, CL_KERNEL_ARG_TYPE_NAME);
            any = any || p->arg_name[i];
        }
        if (!any) {
            for (cl_uint i = 0; p->arg_name && p->arg_type && i < p->n_args; i++)
                free(p->arg_name[i]), free(p->arg_type[i]);
            free(p->arg_name);
            free(p->arg_type);
            p->arg_name = p->arg_type = NULL;
            lg_log(n, LG_LOG_DEBUG,
                   "cl pass '%s': kernel %s: no argument info from the "
                   "runtime; messages give argument indices only",
                   d->name, d->kernel);
        }
    }
    free(pname);
    *out = p;
    return 0;

fail:
    free(pname);
    lg_cl_pass_destroy(&p);
    return rc;
}

void lg_cl_pass_destroy(lg_cl_pass **pp)
{
    if (!pp || !*pp)
        return;
    lg_cl_pass *p = *pp;
    if (p->kernel)
        clReleaseKernel(p->kernel);
    for (cl_uint i = 0; i < p->n_args; i++) {
        if (p->arg_name)
            free(p->arg_name[i]);
        if (p->arg_type)
            free(p->arg_type[i]);
    }
    free(p->arg_name);
    free(p->arg_type);
    free(p->set);
    free(p->name);
    free(p->kernel_name);
    free(p);
    *pp = NULL;
}

cl_kernel lg_cl_pass_kernel(const lg_cl_pass *p)
{
    return p ? p->kernel : NULL;
}

/* One clSetKernelArg, its own error reported with its own code: OR-ing the codes of
 * several calls named the wrong error (-51 | -38 = -33, CL_INVALID_DEVICE). */
int lg_cl_pass_arg(lg_cl_pass *p, unsigned i, size_t size, const void *value)
{
    if (!p)
        return LG_ERR_INVALID;
    cl_int e = clSetKernelArg(p->kernel, i, size, value);
    if (e == CL_SUCCESS) {
        if (i < p->n_args)
            p->set[i] = true;
        return 0;
    }
    char label[160];
    arg_label(p, i, label, sizeof label);
    char extra[64] = "";
    if (e == CL_INVALID_ARG_INDEX)
        snprintf(extra, sizeof extra, " (the kernel has %u argument%s)", (unsigned)p->n_args,
                 p->n_args == 1 ? "" : "s");
    if (i < p->n_args)
        p->set[i] = false;
    int rc = lg_error_code(p->node, LG_ERR_DEVICE,
                           "cl pass '%s': kernel %s, %s: %zu bytes%s: clSetKernelArg: %s (%d)%s",
                           p->name, p->kernel_name, label, size, value ? "" : " (local)",
                           lg_cl_strerror(e), (int)e, extra);
    if (!p->failed)
        p->failed = rc;
    return rc;
}

int lg_cl_pass_arg_mem(lg_cl_pass *p, unsigned i, cl_mem m)
{
    return lg_cl_pass_arg(p, i, sizeof m, &m);
}

int lg_cl_pass_arg_int(lg_cl_pass *p, unsigned i, int32_t v)
{
    cl_int x = v;
    return lg_cl_pass_arg(p, i, sizeof x, &x);
}

int lg_cl_pass_arg_uint(lg_cl_pass *p, unsigned i, uint32_t v)
{
    cl_uint x = v;
    return lg_cl_pass_arg(p, i, sizeof x, &x);
}

int lg_cl_pass_arg_float(lg_cl_pass *p, unsigned i, float v)
{
    cl_float x = v;
    return lg_cl_pass_arg(p, i, sizeof x, &x);
}

int lg_cl_pass_arg_float4(lg_cl_pass *p, unsigned i, const float v[4])
{
    cl_float4 x = { { v[0], v[1], v[2], v[3] } };
    return lg_cl_pass_arg(p, i, sizeof x, &x);
}

int lg_cl_pass_arg_local(lg_cl_pass *p, unsigned i, size_t bytes)
{
    return lg_cl_pass_arg(p, i, bytes, NULL);
}

int lg_cl_pass_arg_resource(lg_cl_pass *p, unsigned i, const lg_resource *res, unsigned access)
{
    if (!p)
        return LG_ERR_INVALID;
    if (!res)
        return lg_cl_pass_arg_mem(p, i, NULL);
    int rc;
    char label[160];
    if (access != LG_READ && access != LG_WRITE && access != LG_READ_WRITE) {
        arg_label(p, i, label, sizeof label);
        rc = lg_error(p->node,
                      "cl pass '%s': kernel %s, %s: access %u (LG_READ, LG_WRITE or "
                      "LG_READ_WRITE)",
                      p->name, p->kernel_name, label, access);
    } else {
        void *mem = NULL, *depth = NULL;
        rc = lg_map_cl(p->node, res, access, &mem, &depth);
        if (!rc)
            return lg_cl_pass_arg_mem(p, i, (cl_mem)mem);
        /* the host said why; say where */
        arg_label(p, i, label, sizeof label);
        lg_error_code(p->node, rc,
                      "cl pass '%s': kernel %s, %s: the resource could not be "
                      "mapped on CL",
                      p->name, p->kernel_name, label);
    }
    if (i < p->n_args)
        p->set[i] = false;
    if (!p->failed)
        p->failed = rc;
    return rc;
}

static void sizes_text(char *buf, size_t size, unsigned dims, const size_t *v)
{
    size_t used = 0;
    buf[0] = '\0';
    for (unsigned d = 0; d < dims && used < size; d++)
        used += (size_t)snprintf(buf + used, size - used, "%s%zu", d ? "x" : "", v[d]);
}

int lg_cl_pass_run(lg_cl_pass *p, unsigned dims, const size_t *global, const size_t *local)
{
    if (!p)
        return LG_ERR_INVALID;
    if (p->failed) {
        /* reported when the argument failed; the next run starts afresh */
        int rc = p->failed;
        p->failed = 0;
        return rc;
    }
    if (dims < 1 || dims > 3 || !global)
        return lg_error(p->node,
                        "cl pass '%s': kernel %s: run over %u dimensions%s (1 to 3, "
                        "with global sizes)",
                        p->name, p->kernel_name, dims, global ? "" : " without global sizes");
    char gtext[80], ltext[80] = "the runtime's";
    sizes_text(gtext, sizeof gtext, dims, global);
    if (local)
        sizes_text(ltext, sizeof ltext, dims, local);
    for (unsigned d = 0; d < dims; d++)
        if (!global[d] || (local && !local[d]))
            return lg_error(p->node,
                            "cl pass '%s': kernel %s: run over global %s, local %s: a "
                            "size is 0",
                            p->name, p->kernel_name, gtext, ltext);
    /* Arguments never set: the enqueue would say only CL_INVALID_KERNEL_ARGS. */
    unsigned unset = 0;
    char names[4 * 200] = "";
    size_t used = 0;
    for (cl_uint i = 0; i < p->n_args; i++) {
        if (p->set[i])
            continue;
        if (unset < UNSET_NAMED && used < sizeof names) {
            char label[160];
            arg_label(p, i, label, sizeof label);
            used += (size_t)snprintf(names + used, sizeof names - used, "%s%s", unset ? ", " : "",
                                     label);
        }
        unset++;
    }
    if (unset) {
        char more[48] = "";
        if (unset > UNSET_NAMED)
            snprintf(more, sizeof more, " and %u more", unset - UNSET_NAMED);
        return lg_error(p->node,
                        "cl pass '%s': kernel %s: %s%s not set before the run (of %u "
                        "argument%s)",
                        p->name, p->kernel_name, names, more, (unsigned)p->n_args,
                        p->n_args == 1 ? "" : "s");
    }
    cl_command_queue q = lg_cl_queue(p->node);
    if (!q)
        return LG_ERR_DEVICE;
    cl_event ev = NULL;
    cl_int e = clEnqueueNDRangeKernel(q, p->kernel, dims, NULL, global, local, 0, NULL, &ev);
    if (e != CL_SUCCESS)
        return lg_error_code(p->node, LG_ERR_DEVICE,
                             "cl pass '%s': kernel %s: "
                             "clEnqueueNDRangeKernel over global %s, "
                             "local %s: %s (%d)",
                             p->name, p->kernel_name, gtext, ltext, lg_cl_strerror(e), (int)e);
    lg_cl_profile(p->node, ev); /* the host takes the event */
    return 0;
}

/* ---- scratch buffers ------------------------------------------------------------------------- */

static const char *flags_text(cl_mem_flags f, char *buf, size_t size)
{
    static const struct {
        cl_mem_flags bit;
        const char *name;
    } names[] = {
        { CL_MEM_READ_WRITE, "READ_WRITE" },
        { CL_MEM_WRITE_ONLY, "WRITE_ONLY" },
        { CL_MEM_READ_ONLY, "READ_ONLY" },
        { CL_MEM_USE_HOST_PTR, "USE_HOST_PTR" },
        { CL_MEM_ALLOC_HOST_PTR, "ALLOC_HOST_PTR" },
        { CL_MEM_COPY_HOST_PTR, "COPY_HOST_PTR" },
        { CL_MEM_HOST_WRITE_ONLY, "HOST_WRITE_ONLY" },
        { CL_MEM_HOST_READ_ONLY, "HOST_READ_ONLY" },
        { CL_MEM_HOST_NO_ACCESS, "HOST_NO_ACCESS" },
    };
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < sizeof names / sizeof names[0] && used < size; i++)
        if (f & names[i].bit) {
            used += (size_t)snprintf(buf + used, size - used, "%sCL_MEM_%s", used ? "|" : "",
                                     names[i].name);
            f &= ~names[i].bit;
        }
    if (f && used < size)
        snprintf(buf + used, size - used, "%s0x%llx", used ? "|" : "", (unsigned long long)f);
    return buf;
}

static void buffer_release(lg_node *n, lg_cl_buffer *b)
{
    if (b->mem) {
        clReleaseMemObject(b->mem);
        if (n)
            lg_account_free(n, b->size);
    }
    memset(b, 0, sizeof *b);
}

int lg_cl_buffer_recreate(lg_node *n, lg_cl_buffer *b, size_t size, cl_mem_flags flags)
{
    if (!b)
        return lg_error(n, "lg_cl_buffer_recreate: no buffer (NULL)");
    if (!flags)
        flags = CL_MEM_READ_WRITE;
    char ftext[160];
    if (flags & (CL_MEM_USE_HOST_PTR | CL_MEM_COPY_HOST_PTR))
        return lg_error(n,
                        "CL buffer of %zu bytes: flags %s: host pointers are not taken "
                        "(upload with lg_cl_buffer_write)",
                        size, flags_text(flags, ftext, sizeof ftext));
    if (b->mem && b->size >= size && b->flags == flags && size)
        return 0;
    buffer_release(n, b);
    if (!size)
        return lg_error(n, "CL buffer (flags %s): size 0 bytes",
                        flags_text(flags, ftext, sizeof ftext));
    cl_context ctx = lg_cl_context(n);
    if (!ctx)
        return LG_ERR_DEVICE; /* the host said why */
    cl_int e;
    cl_mem m = clCreateBuffer(ctx, flags, size, NULL, &e);
    if (!m) {
        char btext[32];
        lg_bytes_text(btext, sizeof btext, size);
        return lg_error_code(n, e == CL_OUT_OF_HOST_MEMORY ? LG_ERR_NOMEM : LG_ERR_DEVICE,
                             "CL buffer of %zu bytes (%s), flags %s: clCreateBuffer: %s (%d)", size,
                             btext, flags_text(flags, ftext, sizeof ftext), lg_cl_strerror(e),
                             (int)e);
    }
    *b = (lg_cl_buffer){ .mem = m, .size = size, .flags = flags };
    lg_account_alloc(n, size);
    return 0;
}

static int buffer_range(lg_node *n, const lg_cl_buffer *b, size_t offset, size_t size,
                        const void *data, const char *what)
{
    if (!b || !b->mem)
        return lg_error(n,
                        "%s of %zu bytes at %zu: no buffer (make it with "
                        "lg_cl_buffer_recreate)",
                        what, size, offset);
    if (offset > b->size || size > b->size - offset)
        return lg_error(n, "%s of %zu bytes at %zu: beyond the CL buffer's %zu bytes", what, size,
                        offset, b->size);
    if (size && !data)
        return lg_error(n, "%s of %zu bytes at %zu: no host memory (NULL)", what, size, offset);
    return 0;
}

int lg_cl_buffer_write(lg_node *n, lg_cl_buffer *b, size_t offset, size_t size, const void *data)
{
    int rc = buffer_range(n, b, offset, size, data, "lg_cl_buffer_write");
    if (rc || !size)
        return rc;
    cl_command_queue q = lg_cl_queue(n);
    if (!q)
        return LG_ERR_DEVICE;
    cl_int e = clEnqueueWriteBuffer(q, b->mem, CL_TRUE, offset, size, data, 0, NULL, NULL);
    if (e != CL_SUCCESS)
        return lg_error_code(n, LG_ERR_DEVICE,
                             "lg_cl_buffer_write of %zu bytes at %zu into a "
                             "CL buffer of %zu bytes: clEnqueueWriteBuffer: "
                             "%s (%d)",
                             size, offset, b->size, lg_cl_strerror(e), (int)e);
    return 0;
}

int lg_cl_buffer_read(lg_node *n, const lg_cl_buffer *b, size_t offset, size_t size, void *data)
{
    int rc = buffer_range(n, b, offset, size, data, "lg_cl_buffer_read");
    if (rc || !size)
        return rc;
    cl_command_queue q = lg_cl_queue(n);
    if (!q)
        return LG_ERR_DEVICE;
    cl_int e = clEnqueueReadBuffer(q, b->mem, CL_TRUE, offset, size, data, 0, NULL, NULL);
    if (e != CL_SUCCESS)
        return lg_error_code(n, LG_ERR_DEVICE,
                             "lg_cl_buffer_read of %zu bytes at %zu from a "
                             "CL buffer of %zu bytes: clEnqueueReadBuffer: "
                             "%s (%d)",
                             size, offset, b->size, lg_cl_strerror(e), (int)e);
    return 0;
}

void lg_cl_buffer_destroy(lg_node *n, lg_cl_buffer *b)
{
    if (b)
        buffer_release(n, b);
}
