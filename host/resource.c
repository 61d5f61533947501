/* Resources and their residency across CPU, GL and CL. See host.h and lightgraph/host.h.
 *
 * A resource has at most one copy per device and a "current" flag per copy. Reading on a
 * device whose copy is stale copies from a current one; llvmpipe and PoCL share no memory,
 * so GL <-> CL goes through the CPU copy. Every allocation and every copy is counted
 * against the node that caused it. */
#include "host.h"

#include <stdlib.h>
#include <string.h>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "lightgraph/cl.h"
#include "lightgraph/image.h"

static size_t pixel_count(const lg_resource *r)
{
    switch (r->kind) {
    case LG_KIND_IMAGE:
        return (size_t)r->image.width * r->image.height;
    case LG_KIND_VOLUME:
        return (size_t)r->volume.width * r->volume.height * r->volume.depth;
    default:
        return 0;
    }
}

static size_t main_bytes(const lg_resource *r)
{
    switch (r->kind) {
    case LG_KIND_IMAGE:
        if (r->image.flags & LG_IMAGE_DEPTH_ONLY)
            return 0;
        return pixel_count(r) * lg_format_size(r->image.format);
    case LG_KIND_VOLUME:
        return pixel_count(r) * lg_format_size(r->volume.format);
    case LG_KIND_BUFFER:
        return r->buffer.size;
    default:
        return 0;
    }
}

static size_t depth_bytes(const lg_resource *r)
{
    return (r->kind == LG_KIND_IMAGE && (r->image.flags & (LG_IMAGE_DEPTH | LG_IMAGE_DEPTH_ONLY)))
               ? pixel_count(r) * sizeof(float)
               : 0;
}

size_t lg_resource_bytes(const lg_resource *r)
{
    return main_bytes(r) + depth_bytes(r);
}

lg_resource *lg_resource_new(lg_pnode *producer, lg_resource_kind kind)
{
    lg_resource *r = lg_xcalloc(1, sizeof *r);
    r->kind = kind;
    r->producer = producer;
    r->refs = 1;
    return r;
}

static bool mappable(lg_resource_kind k)
{
    return k == LG_KIND_IMAGE || k == LG_KIND_VOLUME || k == LG_KIND_BUFFER;
}

void lg_resource_unref(lg_exec *ex, lg_resource *r)
{
    if (!r || --r->refs > 0)
        return;
    free(r->cpu);
    free(r->cpu_depth);
    if (ex->gl && (r->gl_name || r->gl_depth)) {
        const GladGLContext *gl = lg_gl_device_table(ex->gl);
        if (r->kind == LG_KIND_BUFFER) {
            gl->DeleteBuffers(1, &r->gl_name);
        } else {
            gl->DeleteTextures(1, &r->gl_name);
            if (r->gl_depth)
                gl->DeleteTextures(1, &r->gl_depth);
        }
    }
    for (uint32_t i = 0; i < r->n_attached; i++) {
        if (r->attached[i].gl && ex->gl)
            lg_gl_device_table(ex->gl)->DeleteBuffers(1, &r->attached[i].gl);
        if (r->attached[i].cl)
            clReleaseMemObject((cl_mem)r->attached[i].cl);
    }
    free(r->attached);
    if (r->cl_mem)
        clReleaseMemObject((cl_mem)r->cl_mem);
    if (r->cl_depth)
        clReleaseMemObject((cl_mem)r->cl_depth);
    if (r->payload && r->free_payload)
        r->free_payload(r->payload);
    if (r->payload_plugin)
        r->payload_plugin->live_refs--;
    free(r);
}

static int check_access(lg_pnode *n, lg_resource *r, unsigned access, const char *dev)
{
    if (!mappable(r->kind) || access < LG_READ || access > LG_READ_WRITE)
        return lg_node_errorf(n, "cannot map a resource of this kind on %s (access %u)", dev,
                              access),
               LG_ERR_INVALID;
    if ((access & LG_WRITE) && r->producer != n)
        return lg_node_errorf(n, "maps an input for writing on %s; inputs are read-only", dev),
               LG_ERR_INVALID;
    if (lg_resource_bytes(r) == 0 && r->kind != LG_KIND_BUFFER)
        return lg_node_errorf(n, "maps an empty resource on %s", dev), LG_ERR_INVALID;
    return 0;
}

/* ---- CPU ------------------------------------------------------------------------------- */

static int ensure_cpu(lg_pnode *n, lg_resource *r)
{
    if (!r->cpu) {
        size_t b = main_bytes(r);
        r->cpu = calloc(1, b ? b : 1);
        if (!r->cpu)
            return lg_node_errorf(n, "out of memory allocating %zu bytes", b), LG_ERR_NOMEM;
        n->bytes_alloc += b;
        if (depth_bytes(r)) {
            r->cpu_depth = calloc(1, depth_bytes(r));
            if (!r->cpu_depth)
                return lg_node_errorf(n, "out of memory allocating depth"), LG_ERR_NOMEM;
            n->bytes_alloc += depth_bytes(r);
        }
        /* a fresh resource nobody wrote anywhere is zero everywhere: the CPU copy is it */
        if (!r->gl_valid && !r->cl_valid)
            r->cpu_valid = true;
    }
    return 0;
}

static const GladGLContext *glt(lg_exec *ex)
{
    return ex->gl ? lg_gl_device_table(ex->gl) : NULL;
}

static void gl_formats(lg_format f, GLenum *internal, GLenum *format, GLenum *type)
{
    *format = GL_RGBA;
    switch (f) {
    case LG_FORMAT_RGBA16F:
        *internal = GL_RGBA16F;
        *type = GL_HALF_FLOAT;
        break;
    case LG_FORMAT_RGBA8:
        *internal = GL_RGBA8;
        *type = GL_UNSIGNED_BYTE;
        break;
    default:
        *internal = GL_RGBA32F;
        *type = GL_FLOAT;
        break;
    }
}

static void gl_pixel_store_defaults(const GladGLContext *gl)
{
    gl->BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl->BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    gl->PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl->PixelStorei(GL_PACK_ROW_LENGTH, 0);
    gl->PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
}

static int gl_to_cpu(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    const GladGLContext *gl = glt(ex);
    gl->MemoryBarrier(GL_ALL_BARRIER_BITS);
    gl_pixel_store_defaults(gl);
    size_t b = main_bytes(r);
    if (r->kind == LG_KIND_BUFFER) {
        gl->GetNamedBufferSubData(r->gl_name, 0, (GLsizeiptr)b, r->cpu);
    } else {
        GLenum internal, format, type;
        gl_formats(r->kind == LG_KIND_IMAGE ? r->image.format : r->volume.format, &internal,
                   &format, &type);
        if (r->gl_name)
            gl->GetTextureImage(r->gl_name, 0, format, type, (GLsizei)b, r->cpu);
        if (r->gl_depth && r->cpu_depth)
            gl->GetTextureImage(r->gl_depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                                (GLsizei)depth_bytes(r), r->cpu_depth);
    }
    n->bytes_moved += lg_resource_bytes(r);
    return ex->api.gl_check(&n->pub, "copying a resource from GL to the CPU");
}

static int cl_to_cpu(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    cl_command_queue q = (cl_command_queue)lg_cl_device_queue(ex->cl);
    cl_int e = main_bytes(r) ? clEnqueueReadBuffer(q, (cl_mem)r->cl_mem, CL_TRUE, 0, main_bytes(r),
                                                   r->cpu, 0, NULL, NULL)
                             : CL_SUCCESS;
    if (e == CL_SUCCESS && r->cl_depth && r->cpu_depth)
        e = clEnqueueReadBuffer(q, (cl_mem)r->cl_depth, CL_TRUE, 0, depth_bytes(r), r->cpu_depth,
                                0, NULL, NULL);
    if (e != CL_SUCCESS)
        return lg_node_errorf(n, "copying a resource from CL to the CPU: %s (%d)",
                              lg_cl_strerror(e), e),
               LG_ERR_DEVICE;
    n->bytes_moved += lg_resource_bytes(r);
    return 0;
}

/* Makes the CPU copy current. */
static int sync_cpu(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    int rc = ensure_cpu(n, r);
    if (rc || r->cpu_valid)
        return rc;
    if (r->gl_valid)
        rc = gl_to_cpu(ex, n, r);
    else if (r->cl_valid)
        rc = cl_to_cpu(ex, n, r);
    if (!rc)
        r->cpu_valid = true;
    return rc;
}

int lg_resource_map_cpu(lg_exec *ex, lg_pnode *n, lg_resource *r, unsigned access,
                        lg_cpu_view *view)
{
    memset(view, 0, sizeof *view);
    int rc = check_access(n, r, access, "the CPU");
    if (rc)
        return rc;
    rc = (access & LG_READ) ? sync_cpu(ex, n, r) : ensure_cpu(n, r);
    if (rc)
        return rc;
    if (access & LG_WRITE) {
        r->cpu_valid = true;
        r->gl_valid = r->cl_valid = false;
    }
    view->pixels = main_bytes(r) || r->kind == LG_KIND_BUFFER ? r->cpu : NULL;
    view->depth = r->cpu_depth;
    view->row_pixels = r->kind == LG_KIND_IMAGE ? r->image.width : r->volume.width;
    return 0;
}

/* ---- GL -------------------------------------------------------------------------------- */

static int ensure_gl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    if (r->gl_name || r->gl_depth)
        return 0;
    const GladGLContext *gl = glt(ex);
    if (r->kind == LG_KIND_BUFFER) {
        gl->CreateBuffers(1, &r->gl_name);
        gl->NamedBufferData(r->gl_name, (GLsizeiptr)(r->buffer.size ? r->buffer.size : 4), NULL,
                            GL_DYNAMIC_COPY);
    } else {
        GLenum internal, format, type;
        if (r->kind == LG_KIND_IMAGE) {
            gl_formats(r->image.format, &internal, &format, &type);
            if (!(r->image.flags & LG_IMAGE_DEPTH_ONLY)) {
                gl->CreateTextures(GL_TEXTURE_2D, 1, &r->gl_name);
                gl->TextureStorage2D(r->gl_name, 1, internal, (GLsizei)r->image.width,
                                     (GLsizei)r->image.height);
            }
            if (r->image.flags & (LG_IMAGE_DEPTH | LG_IMAGE_DEPTH_ONLY)) {
                gl->CreateTextures(GL_TEXTURE_2D, 1, &r->gl_depth);
                gl->TextureStorage2D(r->gl_depth, 1, GL_DEPTH_COMPONENT32F,
                                     (GLsizei)r->image.width, (GLsizei)r->image.height);
            }
        } else {
            gl_formats(r->volume.format, &internal, &format, &type);
            gl->CreateTextures(GL_TEXTURE_3D, 1, &r->gl_name);
            gl->TextureStorage3D(r->gl_name, 1, internal, (GLsizei)r->volume.width,
                                 (GLsizei)r->volume.height, (GLsizei)r->volume.depth);
        }
        GLuint texs[2] = {r->gl_name, r->gl_depth};
        for (int i = 0; i < 2; i++) {
            if (!texs[i])
                continue;
            gl->TextureParameteri(texs[i], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            gl->TextureParameteri(texs[i], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            gl->TextureParameteri(texs[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            gl->TextureParameteri(texs[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        }
    }
    n->bytes_alloc += lg_resource_bytes(r);
    return ex->api.gl_check(&n->pub, "allocating a GL resource");
}

static int cpu_to_gl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    const GladGLContext *gl = glt(ex);
    gl_pixel_store_defaults(gl);
    if (r->kind == LG_KIND_BUFFER) {
        gl->NamedBufferSubData(r->gl_name, 0, (GLsizeiptr)r->buffer.size, r->cpu);
    } else if (r->kind == LG_KIND_IMAGE) {
        GLenum internal, format, type;
        gl_formats(r->image.format, &internal, &format, &type);
        if (r->gl_name)
            gl->TextureSubImage2D(r->gl_name, 0, 0, 0, (GLsizei)r->image.width,
                                  (GLsizei)r->image.height, format, type, r->cpu);
        if (r->gl_depth)
            gl->TextureSubImage2D(r->gl_depth, 0, 0, 0, (GLsizei)r->image.width,
                                  (GLsizei)r->image.height, GL_DEPTH_COMPONENT, GL_FLOAT,
                                  r->cpu_depth);
    } else {
        GLenum internal, format, type;
        gl_formats(r->volume.format, &internal, &format, &type);
        gl->TextureSubImage3D(r->gl_name, 0, 0, 0, 0, (GLsizei)r->volume.width,
                              (GLsizei)r->volume.height, (GLsizei)r->volume.depth, format, type,
                              r->cpu);
    }
    n->bytes_moved += lg_resource_bytes(r);
    return ex->api.gl_check(&n->pub, "copying a resource from the CPU to GL");
}

int lg_resource_map_gl(lg_exec *ex, lg_pnode *n, lg_resource *r, unsigned access, uint32_t *name,
                       uint32_t *depth)
{
    if (name)
        *name = 0;
    if (depth)
        *depth = 0;
    int rc = check_access(n, r, access, "GL");
    if (rc)
        return rc;
    if ((rc = lg_exec_need_gl(ex, n)))
        return rc;
    if ((rc = ensure_gl(ex, n, r)))
        return rc;
    if ((access & LG_READ) && !r->gl_valid) {
        if ((rc = sync_cpu(ex, n, r)))
            return rc;
        if ((rc = cpu_to_gl(ex, n, r)))
            return rc;
        r->gl_valid = true;
    }
    if (access & LG_WRITE) {
        r->gl_valid = true;
        r->cpu_valid = r->cl_valid = false;
    }
    if (name)
        *name = r->gl_name;
    if (depth)
        *depth = r->gl_depth;
    return 0;
}

/* ---- CL -------------------------------------------------------------------------------- */

static int ensure_cl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    if (r->cl_mem)
        return 0;
    cl_context ctx = (cl_context)lg_cl_device_context(ex->cl);
    cl_int e = CL_SUCCESS;
    size_t b = main_bytes(r);
    r->cl_mem = clCreateBuffer(ctx, CL_MEM_READ_WRITE, b ? b : 4, NULL, &e);
    if (e == CL_SUCCESS && depth_bytes(r))
        r->cl_depth = clCreateBuffer(ctx, CL_MEM_READ_WRITE, depth_bytes(r), NULL, &e);
    if (e != CL_SUCCESS)
        return lg_node_errorf(n, "clCreateBuffer(%zu bytes): %s (%d)", b, lg_cl_strerror(e), e),
               LG_ERR_DEVICE;
    n->bytes_alloc += lg_resource_bytes(r);
    return 0;
}

static int cpu_to_cl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    cl_command_queue q = (cl_command_queue)lg_cl_device_queue(ex->cl);
    cl_int e = main_bytes(r) ? clEnqueueWriteBuffer(q, (cl_mem)r->cl_mem, CL_TRUE, 0,
                                                    main_bytes(r), r->cpu, 0, NULL, NULL)
                             : CL_SUCCESS;
    if (e == CL_SUCCESS && r->cl_depth)
        e = clEnqueueWriteBuffer(q, (cl_mem)r->cl_depth, CL_TRUE, 0, depth_bytes(r),
                                 r->cpu_depth, 0, NULL, NULL);
    if (e != CL_SUCCESS)
        return lg_node_errorf(n, "copying a resource from the CPU to CL: %s (%d)",
                              lg_cl_strerror(e), e),
               LG_ERR_DEVICE;
    n->bytes_moved += lg_resource_bytes(r);
    return 0;
}

int lg_resource_map_cl(lg_exec *ex, lg_pnode *n, lg_resource *r, unsigned access, void **mem,
                       void **depth)
{
    if (mem)
        *mem = NULL;
    if (depth)
        *depth = NULL;
    int rc = check_access(n, r, access, "CL");
    if (rc)
        return rc;
    if ((rc = lg_exec_need_cl(ex, n)))
        return rc;
    if ((rc = ensure_cl(ex, n, r)))
        return rc;
    if ((access & LG_READ) && !r->cl_valid) {
        if ((rc = sync_cpu(ex, n, r)))
            return rc;
        if ((rc = cpu_to_cl(ex, n, r)))
            return rc;
        r->cl_valid = true;
    }
    if (access & LG_WRITE) {
        r->cl_valid = true;
        r->cpu_valid = r->gl_valid = false;
    }
    if (mem)
        *mem = main_bytes(r) || r->kind == LG_KIND_BUFFER ? r->cl_mem : NULL;
    if (depth)
        *depth = r->cl_depth;
    return 0;
}

/* ---- GPU copies of payload arrays -------------------------------------------------------- */

static lg_attached *attached_slot(lg_pnode *n, lg_resource *r, uint32_t slot, size_t size,
                                  const void *data)
{
    if (!r->payload || r->kind == LG_KIND_IMAGE || r->kind == LG_KIND_BUFFER ||
        r->kind == LG_KIND_VOLUME) {
        lg_node_errorf(n, "asks for a GPU copy of payload data of a resource without a payload");
        return NULL;
    }
    if (!data || size == 0 || size > (1ull << 34)) {
        lg_node_errorf(n, "asks for a GPU copy of %zu bytes at %p (slot %u)", size, data, slot);
        return NULL;
    }
    for (uint32_t i = 0; i < r->n_attached; i++)
        if (r->attached[i].slot == slot) {
            if (r->attached[i].size != size) {
                lg_node_errorf(n, "payload slot %u was %zu bytes, now %zu: payloads are "
                                  "immutable",
                               slot, r->attached[i].size, size);
                return NULL;
            }
            return &r->attached[i];
        }
    r->attached = lg_xrealloc(r->attached, (r->n_attached + 1) * sizeof *r->attached);
    lg_attached *a = &r->attached[r->n_attached++];
    memset(a, 0, sizeof *a);
    a->slot = slot;
    a->size = size;
    return a;
}

int lg_resource_payload_gl(lg_exec *ex, lg_pnode *n, lg_resource *r, uint32_t slot,
                           const void *data, size_t size, uint32_t *name)
{
    *name = 0;
    int rc = lg_exec_need_gl(ex, n);
    if (rc)
        return rc;
    lg_attached *a = attached_slot(n, r, slot, size, data);
    if (!a)
        return LG_ERR_INVALID;
    if (!a->gl) {
        const GladGLContext *gl = glt(ex);
        gl->CreateBuffers(1, &a->gl);
        gl->NamedBufferStorage(a->gl, (GLsizeiptr)size, data, 0);
        n->bytes_alloc += size;
        n->bytes_moved += size;
        if ((rc = ex->api.gl_check(&n->pub, "uploading payload data")))
            return rc;
    }
    *name = a->gl;
    return 0;
}

int lg_resource_payload_cl(lg_exec *ex, lg_pnode *n, lg_resource *r, uint32_t slot,
                           const void *data, size_t size, void **mem)
{
    *mem = NULL;
    int rc = lg_exec_need_cl(ex, n);
    if (rc)
        return rc;
    lg_attached *a = attached_slot(n, r, slot, size, data);
    if (!a)
        return LG_ERR_INVALID;
    if (!a->cl) {
        cl_int e = CL_SUCCESS;
        a->cl = clCreateBuffer((cl_context)lg_cl_device_context(ex->cl),
                               CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, size, (void *)data, &e);
        if (e != CL_SUCCESS) {
            a->cl = NULL;
            lg_node_errorf(n, "clCreateBuffer(%zu bytes of payload data): %s (%d)", size,
                           lg_cl_strerror(e), e);
            return LG_ERR_DEVICE;
        }
        n->bytes_alloc += size;
        n->bytes_moved += size;
    }
    *mem = a->cl;
    return 0;
}

int lg_resource_to_rgba32f(lg_exec *ex, lg_resource *r, float **out, char *err, size_t errlen)
{
    *out = NULL;
    if (r->kind != LG_KIND_IMAGE) {
        snprintf(err, errlen, "only images can be written to files");
        return LG_ERR_INVALID;
    }
    size_t np = pixel_count(r);
    float *f = malloc(np * 4 * sizeof(float) + 1);
    if (!f) {
        snprintf(err, errlen, "out of memory");
        return LG_ERR_NOMEM;
    }
    if (!r->cpu && !r->gl_valid && !r->cl_valid) {
        /* never written anywhere (a neutral zero image): black */
        memset(f, 0, np * 4 * sizeof(float));
        *out = f;
        return 0;
    }
    lg_pnode *who = r->producer;
    int rc = sync_cpu(ex, who, r);
    if (rc) {
        free(f);
        snprintf(err, errlen, "could not read the image back from its device");
        return rc;
    }
    if (r->image.flags & LG_IMAGE_DEPTH_ONLY) {
        /* a depth-only image is written as grey depth, alpha 1 */
        for (size_t i = 0; i < np; i++) {
            f[4 * i] = f[4 * i + 1] = f[4 * i + 2] = r->cpu_depth[i];
            f[4 * i + 3] = 1.0f;
        }
        *out = f;
        return 0;
    }
    switch (r->image.format) {
    case LG_FORMAT_RGBA32F:
        memcpy(f, r->cpu, np * 16);
        break;
    case LG_FORMAT_RGBA16F: {
        const uint16_t *h = r->cpu;
        for (size_t i = 0; i < np * 4; i++)
            f[i] = lg_float_from_half(h[i]);
        break;
    }
    case LG_FORMAT_RGBA8: {
        const uint8_t *b = r->cpu;
        for (size_t i = 0; i < np * 4; i++)
            f[i] = (float)b[i] / 255.0f;
        break;
    }
    }
    *out = f;
    return 0;
}
