/* Resources and their residency across CPU, GL and CL. See host.h and lightgraph/host.h.
 *
 * A resource has at most one copy per device and a "current" flag per copy. Reading on a
 * device whose copy is stale copies from a current one; llvmpipe and PoCL share no memory,
 * so GL <-> CL goes through the CPU copy. Every allocation and every copy is counted
 * against the node that caused it. */
#include "exec/exec.h"

#include <stdlib.h>
#include <string.h>

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include "lightgraph/cl.h"
#include "lightgraph/image.h"
#include "lightgraph/kinds.h"
#include "lightgraph/probe.h"
#include "lightgraph/shcoeffs.h"

/* Pixels of the colour data: every level and face of an image. */
static size_t pixel_count(const lg_resource *r)
{
    switch (r->kind) {
    case LG_KIND_IMAGE: return lg_image_offset(&r->image, lg_image_levels(&r->image), 0);
    case LG_KIND_VOLUME: return (size_t)r->volume.width * r->volume.height * r->volume.depth;
    default: return 0;
    }
}

static size_t main_bytes(const lg_resource *r)
{
    switch (r->kind) {
    case LG_KIND_IMAGE:
        if (r->image.flags & LG_IMAGE_DEPTH_ONLY)
            return 0;
        return pixel_count(r) * lg_format_size(r->image.format);
    case LG_KIND_VOLUME: return pixel_count(r) * lg_format_size(r->volume.format);
    case LG_KIND_BUFFER: return r->buffer.size;
    default: return 0;
    }
}

/* The depth plane: level 0 of a 2D image (cube and mip-mapped images have none). */
static size_t depth_bytes(const lg_resource *r)
{
    return (r->kind == LG_KIND_IMAGE && (r->image.flags & (LG_IMAGE_DEPTH | LG_IMAGE_DEPTH_ONLY)))
               ? (size_t)r->image.width * r->image.height * sizeof(float)
               : 0;
}

size_t lg_resource_bytes(const lg_resource *r)
{
    size_t b = main_bytes(r) + depth_bytes(r);
    for (uint32_t i = 0; i < r->parts.n; i++)
        if (r->parts.list[i])
            b += lg_resource_bytes(r->parts.list[i]);
    return b;
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
    for (uint32_t i = 0; i < r->parts.n; i++)
        lg_resource_unref(ex, r->parts.list[i]);
    free(r->parts.list);
    free(r->copies.cpu);
    free(r->copies.cpu_depth);
    free(r->payload.view_scene);
    free(r->payload.view_cameras);
    if (ex->dev.gl && (r->copies.gl_name || r->copies.gl_depth)) {
        const GladGLContext *gl = lg_gl_device_table(ex->dev.gl);
        if (r->kind == LG_KIND_BUFFER) {
            gl->DeleteBuffers(1, &r->copies.gl_name);
        } else {
            gl->DeleteTextures(1, &r->copies.gl_name);
            if (r->copies.gl_depth)
                gl->DeleteTextures(1, &r->copies.gl_depth);
        }
    }
    for (uint32_t i = 0; i < r->payload.n_attached; i++) {
        if (r->payload.attached[i].gl && ex->dev.gl) {
            const GladGLContext *gl = lg_gl_device_table(ex->dev.gl);
            if (r->payload.attached[i].texture)
                gl->DeleteTextures(1, &r->payload.attached[i].gl);
            else
                gl->DeleteBuffers(1, &r->payload.attached[i].gl);
        }
        if (r->payload.attached[i].cl)
            clReleaseMemObject((cl_mem)r->payload.attached[i].cl);
    }
    free(r->payload.attached);
    if (r->copies.cl_mem)
        clReleaseMemObject((cl_mem)r->copies.cl_mem);
    if (r->copies.cl_depth)
        clReleaseMemObject((cl_mem)r->copies.cl_depth);
    if (r->payload.data && r->payload.free)
        r->payload.free(r->payload.data);
    if (r->payload.plugin)
        r->payload.plugin->live_refs--;
    free(r);
}

static bool same_or_part_of(const lg_resource *r, const lg_resource *of)
{
    return of && (r == of || r->parts.parent == of);
}

bool lg_resource_reachable(lg_pnode *n, const lg_resource *r)
{
    lg_exec *ex = n->ex;
    for (uint32_t o = 0; n->outputs && o < n->schema->n_outputs; o++)
        if (same_or_part_of(r, n->outputs[o]))
            return true;
    for (uint32_t k = 0; k < n->schema->n_inputs; k++) {
        lg_edge e = n->c->inputs[k];
        if (e.node < 0)
            continue;
        lg_resource *in = lg_edge_resource(ex, e);
        if (same_or_part_of(r, in))
            return true;
    }
    return false;
}

static const char *resource_label(const lg_resource *r, char *buf, size_t len)
{
    const lg_resource *whole = r->parts.parent ? r->parts.parent : r;
    const lg_pnode *p = whole->producer;
    const char *port = "?";
    for (uint32_t o = 0; p && p->outputs && o < p->schema->n_outputs; o++)
        if (p->outputs[o] == whole)
            port = p->schema->outputs[o].name;
    if (r->parts.parent) {
        const lg_kind_desc *kd = lg_kind_describe(whole->kind);
        snprintf(buf, len, "'%s.%s', part '%s'", p ? p->pub.name : "?", port,
                 kd && r->parts.index >= 0 ? kd->parts[r->parts.index].name : "?");
    } else {
        snprintf(buf, len, "'%s.%s'", p ? p->pub.name : "?", port);
    }
    return buf;
}

static int check_access(lg_pnode *n, lg_resource *r, unsigned access, const char *dev)
{
#ifdef LG_DEBUG_CHECKS
    if (!lg_resource_reachable(n, r)) {
        char buf[256];
        return lg_node_errorf(n,
                              "maps resource %s on %s, which it did not receive through an "
                              "input (a plugin reaches other nodes' resources only through "
                              "its inputs)",
                              resource_label(r, buf, sizeof buf), dev),
               LG_ERR_INVALID;
    }
#endif
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

/* ---- CPU ------------------------------------------------------------------------------------- */

static int ensure_cpu(lg_pnode *n, lg_resource *r)
{
    if (!r->copies.cpu) {
        size_t b = main_bytes(r);
        r->copies.cpu = calloc(1, b ? b : 1);
        if (!r->copies.cpu)
            return lg_node_errorf(n, "out of memory allocating %zu bytes", b), LG_ERR_NOMEM;
        n->prof.bytes_alloc += b;
        if (depth_bytes(r)) {
            r->copies.cpu_depth = calloc(1, depth_bytes(r));
            if (!r->copies.cpu_depth)
                return lg_node_errorf(n, "out of memory allocating depth"), LG_ERR_NOMEM;
            n->prof.bytes_alloc += depth_bytes(r);
        }
        /* a fresh resource nobody wrote anywhere is zero everywhere: the CPU copy is it */
        if (!r->copies.gl_valid && !r->copies.cl_valid)
            r->copies.cpu_valid = true;
    }
    return 0;
}

static const GladGLContext *glt(lg_exec *ex)
{
    return ex->dev.gl ? lg_gl_device_table(ex->dev.gl) : NULL;
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
    case LG_FORMAT_RGBE8: /* an RGBA8 target; shaders encode and decode (rgbe.glsl) */
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
        gl->GetNamedBufferSubData(r->copies.gl_name, 0, (GLsizeiptr)b, r->copies.cpu);
    } else {
        GLenum internal, format, type;
        gl_formats(r->kind == LG_KIND_IMAGE ? r->image.format : r->volume.format, &internal,
                   &format, &type);
        if (r->copies.gl_name && r->kind == LG_KIND_IMAGE) {
            /* every level; a cube level comes back as its six faces in order */
            size_t px = lg_format_size(r->image.format);
            for (uint32_t l = 0; l < lg_image_levels(&r->image); l++) {
                size_t off = lg_image_offset(&r->image, l, 0) * px;
                size_t len = lg_image_offset(&r->image, l + 1, 0) * px - off;
                gl->GetTextureImage(r->copies.gl_name, (GLint)l, format, type, (GLsizei)len,
                                    (char *)r->copies.cpu + off);
            }
        } else if (r->copies.gl_name) {
            gl->GetTextureImage(r->copies.gl_name, 0, format, type, (GLsizei)b, r->copies.cpu);
        }
        if (r->copies.gl_depth && r->copies.cpu_depth)
            gl->GetTextureImage(r->copies.gl_depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                                (GLsizei)depth_bytes(r), r->copies.cpu_depth);
    }
    n->prof.bytes_moved += lg_resource_bytes(r);
    return ex->api.gl_check(&n->pub, "copying a resource from GL to the CPU");
}

static int cl_to_cpu(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    cl_command_queue q = (cl_command_queue)lg_cl_device_queue(ex->dev.cl);
    cl_int e = main_bytes(r) ? clEnqueueReadBuffer(q, (cl_mem)r->copies.cl_mem, CL_TRUE, 0,
                                                   main_bytes(r), r->copies.cpu, 0, NULL, NULL)
                             : CL_SUCCESS;
    if (e == CL_SUCCESS && r->copies.cl_depth && r->copies.cpu_depth)
        e = clEnqueueReadBuffer(q, (cl_mem)r->copies.cl_depth, CL_TRUE, 0, depth_bytes(r),
                                r->copies.cpu_depth, 0, NULL, NULL);
    if (e != CL_SUCCESS)
        return lg_node_errorf(n, "copying a resource from CL to the CPU: %s (%d)",
                              lg_cl_strerror(e), e),
               LG_ERR_DEVICE;
    n->prof.bytes_moved += lg_resource_bytes(r);
    return 0;
}

/* Makes the CPU copy current. */
static int sync_cpu(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    int rc = ensure_cpu(n, r);
    if (rc || r->copies.cpu_valid)
        return rc;
    if (r->copies.gl_valid)
        rc = gl_to_cpu(ex, n, r);
    else if (r->copies.cl_valid)
        rc = cl_to_cpu(ex, n, r);
    if (!rc)
        r->copies.cpu_valid = true;
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
        r->copies.cpu_valid = true;
        r->copies.gl_valid = r->copies.cl_valid = false;
    }
    view->pixels = main_bytes(r) || r->kind == LG_KIND_BUFFER ? r->copies.cpu : NULL;
    view->depth = r->copies.cpu_depth;
    view->row_pixels = r->kind == LG_KIND_IMAGE ? r->image.width : r->volume.width;
    if (r->kind == LG_KIND_BUFFER)
        view->row_pixels = 0;
    return 0;
}

/* ---- GL -------------------------------------------------------------------------------------- */

static int ensure_gl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    if (r->copies.gl_name || r->copies.gl_depth)
        return 0;
    const GladGLContext *gl = glt(ex);
    if (r->kind == LG_KIND_BUFFER) {
        gl->CreateBuffers(1, &r->copies.gl_name);
        gl->NamedBufferData(r->copies.gl_name, (GLsizeiptr)(r->buffer.size ? r->buffer.size : 4),
                            NULL, GL_DYNAMIC_COPY);
    } else {
        GLenum internal, format, type;
        if (r->kind == LG_KIND_IMAGE) {
            gl_formats(r->image.format, &internal, &format, &type);
            if (!(r->image.flags & LG_IMAGE_DEPTH_ONLY)) {
                bool cube = (r->image.flags & LG_IMAGE_CUBE) != 0;
                GLsizei levels = (GLsizei)lg_image_levels(&r->image);
                gl->CreateTextures(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D, 1,
                                   &r->copies.gl_name);
                gl->TextureStorage2D(r->copies.gl_name, levels, internal, (GLsizei)r->image.width,
                                     (GLsizei)r->image.height);
                gl->TextureParameteri(r->copies.gl_name, GL_TEXTURE_MAX_LEVEL, levels - 1);
            }
            if (r->image.flags & (LG_IMAGE_DEPTH | LG_IMAGE_DEPTH_ONLY)) {
                gl->CreateTextures(GL_TEXTURE_2D, 1, &r->copies.gl_depth);
                gl->TextureStorage2D(r->copies.gl_depth, 1, GL_DEPTH_COMPONENT32F,
                                     (GLsizei)r->image.width, (GLsizei)r->image.height);
            }
        } else {
            gl_formats(r->volume.format, &internal, &format, &type);
            gl->CreateTextures(GL_TEXTURE_3D, 1, &r->copies.gl_name);
            gl->TextureStorage3D(r->copies.gl_name, 1, internal, (GLsizei)r->volume.width,
                                 (GLsizei)r->volume.height, (GLsizei)r->volume.depth);
        }
        GLuint texs[2] = { r->copies.gl_name, r->copies.gl_depth };
        for (int i = 0; i < 2; i++) {
            if (!texs[i])
                continue;
            gl->TextureParameteri(texs[i], GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            gl->TextureParameteri(texs[i], GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            gl->TextureParameteri(texs[i], GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            gl->TextureParameteri(texs[i], GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        }
    }
    n->prof.bytes_alloc += lg_resource_bytes(r);
    return ex->api.gl_check(&n->pub, "allocating a GL resource");
}

static int cpu_to_gl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    const GladGLContext *gl = glt(ex);
    gl_pixel_store_defaults(gl);
    if (r->kind == LG_KIND_BUFFER) {
        gl->NamedBufferSubData(r->copies.gl_name, 0, (GLsizeiptr)r->buffer.size, r->copies.cpu);
    } else if (r->kind == LG_KIND_IMAGE) {
        GLenum internal, format, type;
        gl_formats(r->image.format, &internal, &format, &type);
        size_t px = lg_format_size(r->image.format);
        bool cube = (r->image.flags & LG_IMAGE_CUBE) != 0;
        for (uint32_t l = 0; r->copies.gl_name && l < lg_image_levels(&r->image); l++) {
            const char *src = (const char *)r->copies.cpu + lg_image_offset(&r->image, l, 0) * px;
            GLsizei w = (GLsizei)lg_image_level_width(&r->image, l);
            GLsizei h = (GLsizei)lg_image_level_height(&r->image, l);
            if (cube) /* DSA sees a cube map as six layers */
                gl->TextureSubImage3D(r->copies.gl_name, (GLint)l, 0, 0, 0, w, h, 6, format, type,
                                      src);
            else
                gl->TextureSubImage2D(r->copies.gl_name, (GLint)l, 0, 0, w, h, format, type, src);
        }
        if (r->copies.gl_depth)
            gl->TextureSubImage2D(r->copies.gl_depth, 0, 0, 0, (GLsizei)r->image.width,
                                  (GLsizei)r->image.height, GL_DEPTH_COMPONENT, GL_FLOAT,
                                  r->copies.cpu_depth);
    } else {
        GLenum internal, format, type;
        gl_formats(r->volume.format, &internal, &format, &type);
        gl->TextureSubImage3D(r->copies.gl_name, 0, 0, 0, 0, (GLsizei)r->volume.width,
                              (GLsizei)r->volume.height, (GLsizei)r->volume.depth, format, type,
                              r->copies.cpu);
    }
    n->prof.bytes_moved += lg_resource_bytes(r);
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
    if ((access & LG_READ) && !r->copies.gl_valid) {
        if ((rc = sync_cpu(ex, n, r)))
            return rc;
        if ((rc = cpu_to_gl(ex, n, r)))
            return rc;
        r->copies.gl_valid = true;
    }
    if (access & LG_WRITE) {
        r->copies.gl_valid = true;
        r->copies.cpu_valid = r->copies.cl_valid = false;
    }
    if (name)
        *name = r->copies.gl_name;
    if (depth)
        *depth = r->copies.gl_depth;
    return 0;
}

/* ---- CL -------------------------------------------------------------------------------------- */

static int ensure_cl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    if (r->copies.cl_mem)
        return 0;
    cl_context ctx = (cl_context)lg_cl_device_context(ex->dev.cl);
    cl_int e = CL_SUCCESS;
    size_t b = main_bytes(r);
    r->copies.cl_mem = clCreateBuffer(ctx, CL_MEM_READ_WRITE, b ? b : 4, NULL, &e);
    if (e == CL_SUCCESS && depth_bytes(r))
        r->copies.cl_depth = clCreateBuffer(ctx, CL_MEM_READ_WRITE, depth_bytes(r), NULL, &e);
    if (e != CL_SUCCESS)
        return lg_node_errorf(n, "clCreateBuffer(%zu bytes): %s (%d)", b, lg_cl_strerror(e), e),
               LG_ERR_DEVICE;
    n->prof.bytes_alloc += lg_resource_bytes(r);
    return 0;
}

static int cpu_to_cl(lg_exec *ex, lg_pnode *n, lg_resource *r)
{
    cl_command_queue q = (cl_command_queue)lg_cl_device_queue(ex->dev.cl);
    cl_int e = main_bytes(r) ? clEnqueueWriteBuffer(q, (cl_mem)r->copies.cl_mem, CL_TRUE, 0,
                                                    main_bytes(r), r->copies.cpu, 0, NULL, NULL)
                             : CL_SUCCESS;
    if (e == CL_SUCCESS && r->copies.cl_depth)
        e = clEnqueueWriteBuffer(q, (cl_mem)r->copies.cl_depth, CL_TRUE, 0, depth_bytes(r),
                                 r->copies.cpu_depth, 0, NULL, NULL);
    if (e != CL_SUCCESS)
        return lg_node_errorf(n, "copying a resource from the CPU to CL: %s (%d)",
                              lg_cl_strerror(e), e),
               LG_ERR_DEVICE;
    n->prof.bytes_moved += lg_resource_bytes(r);
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
    if ((access & LG_READ) && !r->copies.cl_valid) {
        if ((rc = sync_cpu(ex, n, r)))
            return rc;
        if ((rc = cpu_to_cl(ex, n, r)))
            return rc;
        r->copies.cl_valid = true;
    }
    if (access & LG_WRITE) {
        r->copies.cl_valid = true;
        r->copies.cpu_valid = r->copies.gl_valid = false;
    }
    if (mem)
        *mem = main_bytes(r) || r->kind == LG_KIND_BUFFER ? r->copies.cl_mem : NULL;
    if (depth)
        *depth = r->copies.cl_depth;
    return 0;
}

/* ---- GPU copies of payload arrays ------------------------------------------------------------ */

static lg_attached *attached_slot(lg_pnode *n, lg_resource *r, uint32_t slot, size_t size,
                                  const void *data, bool texture)
{
    if (!r->payload.data || r->kind == LG_KIND_IMAGE || r->kind == LG_KIND_BUFFER ||
        r->kind == LG_KIND_VOLUME) {
        lg_node_errorf(n, "asks for a GPU copy of payload data of a resource without a payload");
        return NULL;
    }
    if (!data || size == 0 || size > (1ull << 34)) {
        lg_node_errorf(n, "asks for a GPU copy of %zu bytes at %p (slot %u)", size, data, slot);
        return NULL;
    }
    for (uint32_t i = 0; i < r->payload.n_attached; i++)
        if (r->payload.attached[i].slot == slot && r->payload.attached[i].texture == texture) {
            if (r->payload.attached[i].size != size) {
                lg_node_errorf(n,
                               "payload slot %u was %zu bytes, now %zu: payloads are "
                               "immutable",
                               slot, r->payload.attached[i].size, size);
                return NULL;
            }
            return &r->payload.attached[i];
        }
    r->payload.attached = lg_xrealloc(r->payload.attached,
                                      (r->payload.n_attached + 1) * sizeof *r->payload.attached);
    lg_attached *a = &r->payload.attached[r->payload.n_attached++];
    memset(a, 0, sizeof *a);
    a->slot = slot;
    a->size = size;
    a->texture = texture;
    return a;
}

int lg_resource_payload_gl(lg_exec *ex, lg_pnode *n, lg_resource *r, uint32_t slot,
                           const void *data, size_t size, uint32_t *name)
{
    *name = 0;
    int rc = lg_exec_need_gl(ex, n);
    if (rc)
        return rc;
    lg_attached *a = attached_slot(n, r, slot, size, data, false);
    if (!a)
        return LG_ERR_INVALID;
    if (!a->gl) {
        const GladGLContext *gl = glt(ex);
        gl->CreateBuffers(1, &a->gl);
        gl->NamedBufferStorage(a->gl, (GLsizeiptr)size, data, 0);
        n->prof.bytes_alloc += size;
        n->prof.bytes_moved += size;
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
    lg_attached *a = attached_slot(n, r, slot, size, data, false);
    if (!a)
        return LG_ERR_INVALID;
    if (!a->cl) {
        cl_int e = CL_SUCCESS;
        a->cl = clCreateBuffer((cl_context)lg_cl_device_context(ex->dev.cl),
                               CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, size, (void *)data, &e);
        if (e != CL_SUCCESS) {
            a->cl = NULL;
            lg_node_errorf(n, "clCreateBuffer(%zu bytes of payload data): %s (%d)", size,
                           lg_cl_strerror(e), e);
            return LG_ERR_DEVICE;
        }
        n->prof.bytes_alloc += size;
        n->prof.bytes_moved += size;
    }
    *mem = a->cl;
    return 0;
}

/* A scene image as a GL texture: immutable storage with the full mip chain (levels down to
 * 1x1), level 0 from `rgba8` (rows top to bottom: row 0 at t = 0, so glTF's (u, v) are the
 * texture's (s, t) as they are), the others made by glGenerateTextureMipmap (the driver's
 * filter: on Mesa a 2x2 box, sRGB texels decoded before averaging). The texture's own
 * parameters are glTF's defaults (trilinear, repeat); nodes sample it through sampler
 * objects (lg_gl_pass_bind_texture_sampled). Every level's bytes count against the node. */
int lg_resource_payload_gl_texture(lg_exec *ex, lg_pnode *n, lg_resource *r, uint32_t slot,
                                   const void *rgba8, uint32_t width, uint32_t height,
                                   uint32_t internal_format, uint32_t *name)
{
    *name = 0;
    int rc = lg_exec_need_gl(ex, n);
    if (rc)
        return rc;
    if (internal_format != GL_SRGB8_ALPHA8 && internal_format != GL_RGBA8) {
        lg_node_errorf(n,
                       "asks for a payload texture of internal format 0x%x (slot %u): "
                       "GL_SRGB8_ALPHA8 or GL_RGBA8 only",
                       internal_format, slot);
        return LG_ERR_INVALID;
    }
    const GladGLContext *gl = glt(ex);
    GLint max_size = 0;
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (width == 0 || height == 0 ||
        (max_size > 0 && (width > (uint32_t)max_size || height > (uint32_t)max_size))) {
        lg_node_errorf(n,
                       "asks for a payload texture of %ux%u texels (slot %u): this GL device "
                       "takes 1..%d per side",
                       width, height, slot, max_size);
        return LG_ERR_UNSUPPORTED;
    }
    size_t size = (size_t)width * height * 4;
    lg_attached *a = attached_slot(n, r, slot, size, rgba8, true);
    if (!a)
        return LG_ERR_INVALID;
    if (!a->gl) {
        GLsizei levels = 1;
        uint64_t bytes = 0;
        for (uint32_t w = width, h = height;; levels++) {
            bytes += (uint64_t)w * h * 4;
            if (w == 1 && h == 1)
                break;
            w = w > 1 ? w / 2 : 1;
            h = h > 1 ? h / 2 : 1;
        }
        gl->CreateTextures(GL_TEXTURE_2D, 1, &a->gl);
        gl->TextureStorage2D(a->gl, levels, internal_format, (GLsizei)width, (GLsizei)height);
        /* rows of RGBA8 are whole multiples of 4 bytes: the default unpack alignment fits */
        gl->TextureSubImage2D(a->gl, 0, 0, 0, (GLsizei)width, (GLsizei)height, GL_RGBA,
                              GL_UNSIGNED_BYTE, rgba8);
        gl->GenerateTextureMipmap(a->gl);
        gl->TextureParameteri(a->gl, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        gl->TextureParameteri(a->gl, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        gl->TextureParameteri(a->gl, GL_TEXTURE_WRAP_S, GL_REPEAT);
        gl->TextureParameteri(a->gl, GL_TEXTURE_WRAP_T, GL_REPEAT);
        n->prof.bytes_alloc += bytes;
        n->prof.bytes_moved += size;
        if ((rc = ex->api.gl_check(&n->pub, "uploading a payload texture")))
            return rc;
    }
    *name = a->gl;
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
    if (!r->copies.cpu && !r->copies.gl_valid && !r->copies.cl_valid) {
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
            f[4 * i] = f[4 * i + 1] = f[4 * i + 2] = r->copies.cpu_depth[i];
            f[4 * i + 3] = 1.0f;
        }
        *out = f;
        return 0;
    }
    switch (r->image.format) {
    case LG_FORMAT_RGBA32F: memcpy(f, r->copies.cpu, np * 16); break;
    case LG_FORMAT_RGBA16F: {
        const uint16_t *h = r->copies.cpu;
        for (size_t i = 0; i < np * 4; i++)
            f[i] = lg_float_from_half(h[i]);
        break;
    }
    case LG_FORMAT_RGBA8: {
        const uint8_t *b = r->copies.cpu;
        for (size_t i = 0; i < np * 4; i++)
            f[i] = (float)b[i] / 255.0f;
        break;
    }
    case LG_FORMAT_RGBE8: {
        const uint8_t *b = r->copies.cpu;
        for (size_t i = 0; i < np; i++) {
            lg_rgbe_decode(b + 4 * i, f + 4 * i);
            f[4 * i + 3] = 1.0f;
        }
        break;
    }
    }
    *out = f;
    return 0;
}

/* The image file of a probe resource (an `output` of a probe): level 0 of its radiance,
 * laid out by lg_probe_pack as its info says (a cube as the cross or strip it was read
 * from or converted to). *out is the caller's (lg_image_free). */
int lg_resource_probe_file(lg_exec *ex, lg_resource *r, lg_image *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    int32_t ri = lg_kind_part_index(LG_KIND_PROBE, "radiance");
    int32_t ii = lg_kind_part_index(LG_KIND_PROBE, "info");
    lg_resource *rad = r->kind == LG_KIND_PROBE && ri >= 0 && (uint32_t)ri < r->parts.n
                           ? r->parts.list[ri]
                           : NULL;
    lg_resource *meta = ii >= 0 && (uint32_t)ii < r->parts.n ? r->parts.list[ii] : NULL;
    if (!rad || !meta || !meta->copies.cpu || !meta->copies.cpu_valid ||
        meta->buffer.size < sizeof(lg_probe_info)) {
        snprintf(err, errlen, "the probe was not written (no radiance or info)");
        return LG_ERR_INVALID;
    }
    lg_probe_info info;
    memcpy(&info, meta->copies.cpu, sizeof info);
    if (info.struct_size < sizeof info) /* an older producer: the rest is zero */
        memset((char *)&info + info.struct_size, 0, sizeof info - info.struct_size);
    float *px = NULL;
    int rc = lg_resource_to_rgba32f(ex, rad, &px, err, errlen);
    if (rc)
        return rc;
    /* level 0 comes first (lg_image_offset), a cube's six faces one after the other */
    rc = lg_probe_pack(&info, rad->image.width, rad->image.height, px, out, err, errlen);
    free(px);
    return rc;
}

/* The text file of an SH coefficient resource (docs/graph-format.md "Outputs"): two
 * comment lines, then one line per coefficient i = l (l + 1) + m, "i l m R G B", each
 * float with %.9g (9 significant digits: every float reads back to the same bits). */
int lg_resource_sh_text(lg_exec *ex, lg_resource *r, char **out, size_t *len, char *err,
                        size_t errlen)
{
    *out = NULL;
    *len = 0;
    int32_t ci = lg_kind_part_index(LG_KIND_SH, "coeffs");
    int32_t ii = lg_kind_part_index(LG_KIND_SH, "info");
    lg_resource *co = r->kind == LG_KIND_SH && ci >= 0 && (uint32_t)ci < r->parts.n
                          ? r->parts.list[ci]
                          : NULL;
    lg_resource *meta = r->kind == LG_KIND_SH && ii >= 0 && (uint32_t)ii < r->parts.n
                            ? r->parts.list[ii]
                            : NULL;
    if (!co || !meta || !meta->copies.cpu || !meta->copies.cpu_valid ||
        meta->buffer.size < sizeof(lg_sh_info)) {
        snprintf(err, errlen, "the SH coefficients were not written (no coeffs or info)");
        return LG_ERR_INVALID;
    }
    lg_sh_info info;
    memcpy(&info, meta->copies.cpu, sizeof info);
    if (info.bands < 1 || info.bands > LG_SH_MAX_BANDS ||
        co->buffer.size != (size_t)3 * info.bands * info.bands * sizeof(float)) {
        snprintf(err, errlen, "the SH coefficients are inconsistent: %u bands in %zu bytes",
                 info.bands, co->buffer.size);
        return LG_ERR_INVALID;
    }
    int rc = sync_cpu(ex, co->producer, co);
    if (rc) {
        snprintf(err, errlen, "could not read the SH coefficients back from their device");
        return rc;
    }
    uint32_t n = info.bands, nc = n * n;
    const float *c = co->copies.cpu;
    lg_str b = { 0 };
    lg_str_addf(&b,
                "# lightgraph SH coefficients: %u band%s, %u per channel, basis "
                "lightgraph/sh.h%s\n",
                n, n == 1 ? "" : "s", nc, (info.flags & LG_SH_WINDOWED) ? ", windowed" : "");
    lg_str_add(&b, "# index l m R G B\n");
    for (uint32_t l = 0, i = 0; l < n; l++)
        for (int m = -(int)l; m <= (int)l; m++, i++)
            lg_str_addf(&b, "%u %u %d %.9g %.9g %.9g\n", i, l, m, (double)c[i], (double)c[nc + i],
                        (double)c[2 * nc + i]);
    *len = b.len;
    *out = lg_str_take(&b);
    return 0;
}

/* ---- composite resources --------------------------------------------------------------------- */

lg_resource *lg_edge_resource(lg_exec *ex, lg_edge e)
{
    if (e.node < 0 || !ex->nodes[e.node]->outputs)
        return NULL;
    lg_resource *r = ex->nodes[e.node]->outputs[e.port];
    if (!r || e.part == 0)
        return r;
    return e.part <= r->parts.n ? r->parts.list[e.part - 1] : NULL;
}

/* A neutral part: what an edge NODE.PART reads from a gated producer. */
static lg_resource *neutral_part(lg_exec *ex, lg_pnode *n, lg_part_type type)
{
    lg_resource *p;
    switch (type) {
    case LG_PART_IMAGE:
        p = lg_resource_new(n, LG_KIND_IMAGE);
        p->image.width = ex->opts.width ? ex->opts.width : 1;
        p->image.height = ex->opts.height ? ex->opts.height : 1;
        p->image.format = LG_FORMAT_RGBA32F;
        break;
    case LG_PART_VOLUME:
        p = lg_resource_new(n, LG_KIND_VOLUME);
        p->volume.width = p->volume.height = p->volume.depth = 1;
        p->volume.format = LG_FORMAT_RGBA32F;
        break;
    default: p = lg_resource_new(n, LG_KIND_BUFFER); break;
    }
    p->neutral = true;
    return p;
}

int lg_resource_make_parts(lg_exec *ex, lg_pnode *n, lg_resource *r, const lg_part_spec *specs,
                           uint32_t n_specs)
{
    const lg_kind_desc *kd = lg_kind_describe(r->kind);
    if (!kd || !kd->n_parts)
        return lg_node_errorf(n, "resources of kind %s have no parts", lg_kind_name(r->kind)),
               LG_ERR_INVALID;
    r->parts.list = lg_xcalloc(kd->n_parts, sizeof *r->parts.list);
    r->parts.n = kd->n_parts;
    for (uint32_t i = 0; i < kd->n_parts; i++) {
        lg_resource *p = NULL;
        if (!specs) {
            p = neutral_part(ex, n, kd->parts[i].type);
        } else {
            const lg_part_spec *sp = NULL;
            for (uint32_t j = 0; j < n_specs; j++)
                if (specs[j].name && strcmp(specs[j].name, kd->parts[i].name) == 0)
                    sp = &specs[j];
            if (!sp)
                continue; /* optional (checked by the caller) */
            switch (sp->type) {
            case LG_PART_IMAGE:
                p = lg_resource_new(n, LG_KIND_IMAGE);
                p->image = sp->image;
                if (p->image.flags & LG_IMAGE_DEPTH_ONLY)
                    p->image.format = LG_FORMAT_RGBA32F; /* unused */
                break;
            case LG_PART_VOLUME:
                p = lg_resource_new(n, LG_KIND_VOLUME);
                p->volume = sp->volume;
                break;
            default:
                p = lg_resource_new(n, LG_KIND_BUFFER);
                p->buffer = sp->buffer;
                break;
            }
        }
        p->parts.parent = r;
        p->parts.index = (int32_t)i;
        p->parts.type = kd->parts[i].type;
        r->parts.list[i] = p;
    }
    return 0;
}
