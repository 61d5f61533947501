/* lightgraph/gl.h scratch device memory: lg_gl_buffer, lg_gl_texture and lg_gl_buffer_texture
 * in the recreate idiom, every make and every release counted with the node's profile. */
#include "lightgraph/gl.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

/* ---- formats --------------------------------------------------------------------------------- */

typedef struct gl_format {
    GLenum format;
    const char *name;
    uint32_t bytes; /* per texel, nominal (what the profile counts) */
    bool buffer_ok; /* accepted by glTextureBuffer */
} gl_format;

static const gl_format formats[] = {
    { GL_R8, "GL_R8", 1, true },
    { GL_RG8, "GL_RG8", 2, true },
    { GL_RGBA8, "GL_RGBA8", 4, true },
    { GL_SRGB8_ALPHA8, "GL_SRGB8_ALPHA8", 4, false },
    { GL_R16, "GL_R16", 2, true },
    { GL_RG16, "GL_RG16", 4, true },
    { GL_RGBA16, "GL_RGBA16", 8, true },
    { GL_R16F, "GL_R16F", 2, true },
    { GL_RG16F, "GL_RG16F", 4, true },
    { GL_RGBA16F, "GL_RGBA16F", 8, true },
    { GL_R32F, "GL_R32F", 4, true },
    { GL_RG32F, "GL_RG32F", 8, true },
    { GL_RGB32F, "GL_RGB32F", 12, true },
    { GL_RGBA32F, "GL_RGBA32F", 16, true },
    { GL_R8UI, "GL_R8UI", 1, true },
    { GL_R8I, "GL_R8I", 1, true },
    { GL_R16UI, "GL_R16UI", 2, true },
    { GL_R16I, "GL_R16I", 2, true },
    { GL_R32UI, "GL_R32UI", 4, true },
    { GL_R32I, "GL_R32I", 4, true },
    { GL_RG32UI, "GL_RG32UI", 8, true },
    { GL_RG32I, "GL_RG32I", 8, true },
    { GL_RGB32UI, "GL_RGB32UI", 12, true },
    { GL_RGB32I, "GL_RGB32I", 12, true },
    { GL_RGBA8UI, "GL_RGBA8UI", 4, true },
    { GL_RGBA16UI, "GL_RGBA16UI", 8, true },
    { GL_RGBA32UI, "GL_RGBA32UI", 16, true },
    { GL_RGBA32I, "GL_RGBA32I", 16, true },
    { GL_R11F_G11F_B10F, "GL_R11F_G11F_B10F", 4, false },
    { GL_RGB10_A2, "GL_RGB10_A2", 4, false },
    { GL_DEPTH_COMPONENT16, "GL_DEPTH_COMPONENT16", 2, false },
    { GL_DEPTH_COMPONENT24, "GL_DEPTH_COMPONENT24", 4, false },
    { GL_DEPTH_COMPONENT32F, "GL_DEPTH_COMPONENT32F", 4, false },
    { GL_DEPTH24_STENCIL8, "GL_DEPTH24_STENCIL8", 4, false },
    { GL_DEPTH32F_STENCIL8, "GL_DEPTH32F_STENCIL8", 8, false },
};

static const gl_format *find_format(GLenum f)
{
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++)
        if (formats[i].format == f)
            return &formats[i];
    return NULL;
}

static const char *target_name(GLenum t)
{
    switch (t) {
    case GL_TEXTURE_2D: return "GL_TEXTURE_2D";
    case GL_TEXTURE_3D: return "GL_TEXTURE_3D";
    case GL_TEXTURE_2D_ARRAY: return "GL_TEXTURE_2D_ARRAY";
    case GL_TEXTURE_CUBE_MAP: return "GL_TEXTURE_CUBE_MAP";
    default: return NULL;
    }
}

/* Reports a GL error left pending by the node's own earlier calls, so that the allocation
 * that follows is not blamed for it. */
static int pending_error(lg_node *n, const char *fn)
{
    char what[128];
    snprintf(what, sizeof what,
             "running the node's own GL calls before %s (not the "
             "allocation's)",
             fn);
    return lg_gl_check(n, what);
}

/* ---- buffers --------------------------------------------------------------------------------- */

void lg_gl_buffer_destroy(lg_node *n, lg_gl_buffer *b)
{
    if (!b)
        return;
    if (b->name) {
        const lg_gl *gl = lg_gl_get(n);
        if (gl)
            gl->DeleteBuffers(1, &b->name);
        lg_account_free(n, b->size);
    }
    memset(b, 0, sizeof *b);
}

int lg_gl_buffer_recreate(lg_node *n, lg_gl_buffer *b, size_t size, GLbitfield flags,
                          const void *data)
{
    if (!b)
        return lg_error(n, "lg_gl_buffer_recreate: no buffer handle (NULL)");
    if (size == 0)
        return lg_error(n, "lg_gl_buffer_recreate: a buffer of 0 bytes (a GL buffer holds at "
                           "least one byte)");
    if (size > (size_t)PTRDIFF_MAX)
        return lg_error(n, "lg_gl_buffer_recreate: %zu bytes is beyond what GL can address", size);
    if (!flags)
        flags = GL_DYNAMIC_STORAGE_BIT;
    bool keep = b->name && b->size >= size && b->flags == flags &&
                (!data || (flags & GL_DYNAMIC_STORAGE_BIT));
    if (keep && !data)
        return 0; /* the common case, every frame: no GL call at all */
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc = pending_error(n, "lg_gl_buffer_recreate");
    if (rc)
        return rc;
    if (keep) {
        gl->NamedBufferSubData(b->name, 0, (GLsizeiptr)size, data);
        char what[96];
        snprintf(what, sizeof what, "uploading %zu bytes to a %zu-byte GL buffer", size, b->size);
        return lg_gl_check(n, what);
    }
    lg_gl_buffer_destroy(n, b);
    gl->CreateBuffers(1, &b->name);
    gl->NamedBufferStorage(b->name, (GLsizeiptr)size, data, flags);
    char what[128];
    snprintf(what, sizeof what, "making a GL buffer of %zu bytes (storage flags 0x%x)%s", size,
             (unsigned)flags, data ? " with its data" : "");
    if ((rc = lg_gl_check(n, what))) {
        gl->DeleteBuffers(1, &b->name);
        memset(b, 0, sizeof *b);
        return rc;
    }
    b->size = size;
    b->flags = flags;
    lg_account_alloc(n, size);
    return 0;
}

int lg_gl_buffer_upload(lg_node *n, lg_gl_buffer *b, size_t offset, size_t size, const void *data)
{
    if (!b || !b->name)
        return lg_error(n, "lg_gl_buffer_upload: the buffer was not made (call "
                           "lg_gl_buffer_recreate first)");
    if (size == 0)
        return 0;
    if (!data)
        return lg_error(n, "lg_gl_buffer_upload: %zu bytes at offset %zu from no data (NULL)", size,
                        offset);
    if (offset > b->size || size > b->size - offset)
        return lg_error(n,
                        "lg_gl_buffer_upload: %zu bytes at offset %zu overrun the %zu-byte "
                        "buffer",
                        size, offset, b->size);
    if (!(b->flags & GL_DYNAMIC_STORAGE_BIT))
        return lg_error(n,
                        "lg_gl_buffer_upload: the buffer was made without "
                        "GL_DYNAMIC_STORAGE_BIT (flags 0x%x): it cannot be written; "
                        "give the data to lg_gl_buffer_recreate",
                        (unsigned)b->flags);
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc = pending_error(n, "lg_gl_buffer_upload");
    if (rc)
        return rc;
    gl->NamedBufferSubData(b->name, (GLintptr)offset, (GLsizeiptr)size, data);
    char what[96];
    snprintf(what, sizeof what, "uploading %zu bytes at offset %zu to a %zu-byte GL buffer", size,
             offset, b->size);
    return lg_gl_check(n, what);
}

/* ---- textures -------------------------------------------------------------------------------- */

/* d with its defaults filled in (depth and levels 0 -> 1, reserved cleared). */
static lg_gl_texture_desc normalised(const lg_gl_texture_desc *d)
{
    lg_gl_texture_desc o = { .target = d->target,
                             .format = d->format,
                             .width = d->width,
                             .height = d->height,
                             .depth = d->depth ? d->depth : 1,
                             .levels = d->levels ? d->levels : 1 };
    return o;
}

static uint32_t max_levels(const lg_gl_texture_desc *d)
{
    uint32_t m = d->width > d->height ? d->width : d->height;
    if (d->target == GL_TEXTURE_3D && d->depth > m)
        m = d->depth;
    uint32_t l = 1;
    while (m >>= 1)
        l++;
    return l;
}

static uint32_t level_extent(uint32_t e, uint32_t l)
{
    e >>= l;
    return e ? e : 1;
}

static uint64_t desc_bytes(const lg_gl_texture_desc *d, uint32_t texel)
{
    uint64_t sum = 0;
    for (uint32_t l = 0; l < d->levels; l++) {
        uint64_t layers = d->target == GL_TEXTURE_3D         ? level_extent(d->depth, l)
                          : d->target == GL_TEXTURE_CUBE_MAP ? 6
                                                             : d->depth;
        sum += (uint64_t)level_extent(d->width, l) * level_extent(d->height, l) * layers * texel;
    }
    return sum;
}

/* Why `d` (normalised) cannot be made on any device, as a message into err; 0 when it can. */
static int check_shape(const lg_gl_texture_desc *d, const gl_format **fmt, char *err, size_t len)
{
    const char *tn = target_name(d->target);
    if (!tn)
        return snprintf(err, len,
                        "target 0x%04x is not one of GL_TEXTURE_2D, GL_TEXTURE_3D, "
                        "GL_TEXTURE_2D_ARRAY, GL_TEXTURE_CUBE_MAP",
                        (unsigned)d->target),
               LG_ERR_INVALID;
    if (!(*fmt = find_format(d->format)))
        return snprintf(err, len,
                        "format 0x%04x is not a sized internal format this SDK "
                        "knows (GL_RGBA32F, GL_R32UI, GL_DEPTH_COMPONENT32F, ...; "
                        "an unsized GL_RGBA or a pixel type is not one)",
                        (unsigned)d->format),
               LG_ERR_INVALID;
    if (!d->width || !d->height)
        return snprintf(err, len, "a %s of %ux%u has no texels (width and height >= 1)", tn,
                        d->width, d->height),
               LG_ERR_INVALID;
    if ((d->target == GL_TEXTURE_2D || d->target == GL_TEXTURE_CUBE_MAP) && d->depth != 1)
        return snprintf(err, len, "a %s has depth 1, not %u", tn, d->depth), LG_ERR_INVALID;
    if (d->target == GL_TEXTURE_CUBE_MAP && d->width != d->height)
        return snprintf(err, len, "a cube map's faces are square, not %ux%u", d->width, d->height),
               LG_ERR_INVALID;
    if (d->levels > max_levels(d))
        return snprintf(err, len, "%u levels for %ux%ux%u (at most %u)", d->levels, d->width,
                        d->height, d->depth, max_levels(d)),
               LG_ERR_INVALID;
    return 0;
}

uint64_t lg_gl_texture_bytes(const lg_gl_texture_desc *d)
{
    if (!d)
        return 0;
    lg_gl_texture_desc o = normalised(d);
    const gl_format *f = NULL;
    char err[256];
    return check_shape(&o, &f, err, sizeof err) ? 0 : desc_bytes(&o, f->bytes);
}

/* Why `d` (normalised, its shape checked) cannot be made on this device: its limits. */
static int check_limits(const lg_gl *gl, const lg_gl_texture_desc *d, char *err, size_t len)
{
    GLint max_size = 0, max_depth = 0;
    const char *what = "GL_MAX_TEXTURE_SIZE", *dwhat = NULL;
    switch (d->target) {
    case GL_TEXTURE_3D:
        gl->GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max_size);
        max_depth = max_size;
        what = dwhat = "GL_MAX_3D_TEXTURE_SIZE";
        break;
    case GL_TEXTURE_CUBE_MAP:
        gl->GetIntegerv(GL_MAX_CUBE_MAP_TEXTURE_SIZE, &max_size);
        what = "GL_MAX_CUBE_MAP_TEXTURE_SIZE";
        break;
    case GL_TEXTURE_2D_ARRAY:
        gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
        gl->GetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_depth);
        dwhat = "GL_MAX_ARRAY_TEXTURE_LAYERS";
        break;
    default: gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size); break;
    }
    if (max_size > 0 && (d->width > (uint32_t)max_size || d->height > (uint32_t)max_size))
        return snprintf(err, len, "%ux%u is beyond the device's %s, %d", d->width, d->height, what,
                        max_size),
               LG_ERR_INVALID;
    if (dwhat && max_depth > 0 && d->depth > (uint32_t)max_depth)
        return snprintf(err, len, "depth %u is beyond the device's %s, %d", d->depth, dwhat,
                        max_depth),
               LG_ERR_INVALID;
    return 0;
}

void lg_gl_texture_destroy(lg_node *n, lg_gl_texture *t)
{
    if (!t)
        return;
    if (t->name) {
        const lg_gl *gl = lg_gl_get(n);
        if (gl)
            gl->DeleteTextures(1, &t->name);
        lg_account_free(n, t->bytes);
    }
    memset(t, 0, sizeof *t);
}

int lg_gl_texture_recreate(lg_node *n, lg_gl_texture *t, const lg_gl_texture_desc *d)
{
    if (!t || !d)
        return lg_error(n, "lg_gl_texture_recreate: no %s (NULL)",
                        !t ? "texture handle" : "descriptor");
    lg_gl_texture_desc o = normalised(d);
    if (t->name && memcmp(&o, &t->desc, sizeof o) == 0)
        return 0;
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    char err[256];
    const gl_format *f = NULL;
    int rc = check_shape(&o, &f, err, sizeof err);
    if (!rc)
        rc = check_limits(gl, &o, err, sizeof err);
    if (rc)
        return lg_error_code(n, rc, "lg_gl_texture_recreate: %s", err);
    if ((rc = pending_error(n, "lg_gl_texture_recreate")))
        return rc;
    lg_gl_texture_destroy(n, t);
    gl->CreateTextures(o.target, 1, &t->name);
    if (o.target == GL_TEXTURE_3D || o.target == GL_TEXTURE_2D_ARRAY)
        gl->TextureStorage3D(t->name, (GLsizei)o.levels, o.format, (GLsizei)o.width,
                             (GLsizei)o.height, (GLsizei)o.depth);
    else
        gl->TextureStorage2D(t->name, (GLsizei)o.levels, o.format, (GLsizei)o.width,
                             (GLsizei)o.height);
    /* complete as made, whatever the shader samples it with: the default minifying filter
     * wants mip levels a one-level texture does not have, and the host's images clamp */
    gl->TextureParameteri(t->name, GL_TEXTURE_MIN_FILTER,
                          o.levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
    gl->TextureParameteri(t->name, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl->TextureParameteri(t->name, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl->TextureParameteri(t->name, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl->TextureParameteri(t->name, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    uint64_t bytes = desc_bytes(&o, f->bytes);
    char what[160];
    snprintf(what, sizeof what, "making a %s of %ux%ux%u, %u level%s, %s (%llu bytes)",
             target_name(o.target), o.width, o.height, o.depth, o.levels, o.levels == 1 ? "" : "s",
             f->name, (unsigned long long)bytes);
    if ((rc = lg_gl_check(n, what))) {
        gl->DeleteTextures(1, &t->name);
        memset(t, 0, sizeof *t);
        return rc;
    }
    t->desc = o;
    t->bytes = bytes;
    lg_account_alloc(n, bytes);
    return 1;
}

/* ---- buffer textures ------------------------------------------------------------------------- */

void lg_gl_buffer_texture_destroy(lg_node *n, lg_gl_buffer_texture *t)
{
    if (!t)
        return;
    if (t->name) {
        const lg_gl *gl = lg_gl_get(n);
        if (gl)
            gl->DeleteTextures(1, &t->name);
    }
    memset(t, 0, sizeof *t);
}

int lg_gl_buffer_texture_recreate(lg_node *n, lg_gl_buffer_texture *t, GLenum format, GLuint buffer)
{
    if (!t)
        return lg_error(n, "lg_gl_buffer_texture_recreate: no handle (NULL)");
    if (t->name && t->buffer == buffer && t->format == format)
        return 0;
    const gl_format *f = find_format(format);
    if (!f || !f->buffer_ok)
        return lg_error(n,
                        "lg_gl_buffer_texture_recreate: format 0x%04x%s%s is not one a "
                        "buffer texture takes (GL_R32F, GL_RGB32F, GL_RGBA32F, GL_R32UI, "
                        "...)",
                        (unsigned)format, f ? " " : "", f ? f->name : "");
    if (!buffer)
        return lg_error(n, "lg_gl_buffer_texture_recreate: a %s view of no buffer (0)", f->name);
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc = pending_error(n, "lg_gl_buffer_texture_recreate");
    if (rc)
        return rc;
    lg_gl_buffer_texture_destroy(n, t);
    gl->CreateTextures(GL_TEXTURE_BUFFER, 1, &t->name);
    gl->TextureBuffer(t->name, format, buffer);
    char what[96];
    snprintf(what, sizeof what, "making a %s buffer texture over GL buffer %u", f->name,
             (unsigned)buffer);
    if ((rc = lg_gl_check(n, what))) {
        gl->DeleteTextures(1, &t->name);
        memset(t, 0, sizeof *t);
        return rc;
    }
    t->buffer = buffer;
    t->format = format;
    return 1;
}
