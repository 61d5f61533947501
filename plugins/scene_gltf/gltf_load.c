/*
 * gltf_load.c: the loader of the `gltf` node (gltf_load.h), everything but the parsing.
 *
 * gltf_shim.cpp hands over the file as plain C data (gltf_doc.h), checked only for JSON
 * syntax and buffer sizes. Here every index and byte range is checked before it is used,
 * the node tree is walked from the chosen scene's roots (flattening transforms), each
 * mesh primitive drawn by some node becomes one lg_mesh (once, however many nodes draw it:
 * instancing), and cameras, lights, materials and the medium are mapped to lg_scene.
 */
#include "gltf_load.h"

#include <errno.h>
#include <float.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "gltf_doc.h"
#include "gltf_image.h"
#include "gltf_normals.h"
#include "gltf_tangents.h"
#include "lightgraph/file.h"
#include "lightgraph/vecmath.h"

/* ---- the scene we build ---------------------------------------------------------------------- */

/* One allocation owns the scene: lg_scene first, so that the lg_scene pointer handed to
 * the host is the store's. */
typedef struct store {
    lg_scene scene;
    lg_mesh *meshes;
    uint32_t n_meshes, cap_meshes;
    lg_instance *instances;
    uint32_t n_instances, cap_instances;
    lg_material *materials;
    lg_light *lights;
    uint32_t n_lights, cap_lights;
    lg_camera *cameras;
    uint32_t n_cameras, cap_cameras;
    char **strings; /* every name and the source, freed with the scene */
    uint32_t n_strings, cap_strings;
    /* textures (make_textures): the images a material uses, decoded, and the textures;
     * scene.textures points at tex when there is any */
    lg_scene_textures tex;
    lg_scene_image *images;
    lg_scene_texture *textures;
    uint32_t n_image_slots; /* images[] entries (rgba8 freed over all of them) */
    lg_material_maps *maps; /* per material slot, NULL before make_textures */
    /* the animation played (lg_scene.animation), NULL-free when the file has none */
    uint32_t *inst_node; /* per instance: the glTF node that places it */
    uint32_t cap_inst_node;
    lg_scene_animation anim;
    lg_anim_node *anim_nodes;
    lg_anim_channel *anim_channels;
    float **anim_arrays; /* every channel's times and values */
    uint32_t n_anim_arrays;
    int32_t *light_node, *camera_node;
} store;

void lg_gltf_scene_free(lg_scene *scene)
{
    store *st = (store *)scene;
    if (!st)
        return;
    for (uint32_t i = 0; i < st->n_meshes; i++) {
        free((void *)st->meshes[i].positions);
        free((void *)st->meshes[i].normals);
        free((void *)st->meshes[i].texcoords);
        free((void *)st->meshes[i].indices);
        free((void *)st->meshes[i].tangents);
        free((void *)st->meshes[i].texcoords1);
    }
    for (uint32_t i = 0; st->images && i < st->n_image_slots; i++)
        free((void *)st->images[i].rgba8);
    free(st->images);
    free(st->textures);
    free(st->maps);
    free(st->meshes);
    free(st->instances);
    free(st->materials);
    free(st->lights);
    free(st->cameras);
    for (uint32_t i = 0; i < st->n_strings; i++)
        free(st->strings[i]);
    free(st->strings);
    free(st->inst_node);
    free(st->anim_nodes);
    free(st->anim_channels);
    for (uint32_t i = 0; i < st->n_anim_arrays; i++)
        free(st->anim_arrays[i]);
    free(st->anim_arrays);
    free(st->light_node);
    free(st->camera_node);
    free(st);
}

/* Grows *arr (elements of `size` bytes) to hold n + 1; returns false when out of memory. */
static bool grow(void **arr, uint32_t *cap, uint32_t n, size_t size)
{
    if (n < *cap)
        return true;
    uint32_t c = *cap ? *cap * 2 : 8;
    void *p = realloc(*arr, (size_t)c * size);
    if (!p)
        return false;
    memset((char *)p + (size_t)*cap * size, 0, (size_t)(c - *cap) * size);
    *arr = p;
    *cap = c;
    return true;
}

/* ---- the loader's state and its messages ----------------------------------------------------- */

typedef struct loader {
    const char *file;
    const lg_gltf *g;
    const lg_gltf_options *opt;
    char *err;
    size_t err_size;
    store *st;
    int64_t **prim_mesh; /* per glTF mesh, per primitive: lg_mesh index, -1 not made yet */
    bool *material_used_default;
    bool warned_targets, warned_skin, warned_ortho;
    uint64_t hash;            /* the content hash so far (file, buffers, then image files) */
    bool *mesh_no_normal_map; /* per lg_mesh (grown with them): its material's normal
                               * texture reads a texture coordinate set it lacks */
    uint32_t cap_no_normal_map;
    int64_t *parent; /* per glTF node, -1 for a root (check_tree) */
    /* cameras and lights met while walking the tree, with their node's world matrix */
    struct placed {
        uint32_t node, index;
        double world[16];
    } * cams, *lits;
    uint32_t n_cams, cap_cams, n_lits, cap_lits;
} loader;

static int fail(loader *l, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int fail(loader *l, int code, const char *fmt, ...)
{
    if (!l->err || !l->err_size)
        return code;
    int n = snprintf(l->err, l->err_size, "file '%s': ", l->file);
    if (n < 0 || (size_t)n >= l->err_size)
        return code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(l->err + n, l->err_size - (size_t)n, fmt, ap);
    va_end(ap);
    return code;
}

static void warn(loader *l, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void warn(loader *l, const char *fmt, ...)
{
    if (!l->opt->warn)
        return;
    char msg[1024];
    int n = snprintf(msg, sizeof msg, "file '%s': ", l->file);
    if (n < 0 || (size_t)n >= sizeof msg)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg + n, sizeof msg - (size_t)n, fmt, ap);
    va_end(ap);
    l->opt->warn(l->opt->warn_user, msg);
}

static const char *keep(loader *l, const char *s)
{
    if (!grow((void **)&l->st->strings, &l->st->cap_strings, l->st->n_strings, sizeof(char *)))
        return NULL;
    char *c = strdup(s ? s : "");
    if (c)
        l->st->strings[l->st->n_strings++] = c;
    return c;
}

/* "mesh 2 ('wall') primitive 0": names in messages, quoted when the file gives one. */
static const char *mesh_label(loader *l, uint32_t mi, uint32_t pi, char *buf, size_t size)
{
    const char *name = l->g->meshes[mi].name;
    if (name && *name)
        snprintf(buf, size, "mesh %u ('%s') primitive %u", mi, name, pi);
    else
        snprintf(buf, size, "mesh %u primitive %u", mi, pi);
    return buf;
}

/* ---- accessors ------------------------------------------------------------------------------- */

enum { CT_BYTE = 5120, CT_UBYTE, CT_SHORT, CT_USHORT, CT_INT, CT_UINT, CT_FLOAT };

static uint32_t component_size(int32_t t)
{
    switch (t) {
    case CT_BYTE:
    case CT_UBYTE: return 1;
    case CT_SHORT:
    case CT_USHORT: return 2;
    case CT_UINT:
    case CT_FLOAT: return 4;
    default: return 0;
    }
}

static const char *component_name(int32_t t)
{
    switch (t) {
    case CT_BYTE: return "BYTE";
    case CT_UBYTE: return "UNSIGNED_BYTE";
    case CT_SHORT: return "SHORT";
    case CT_USHORT: return "UNSIGNED_SHORT";
    case CT_INT: return "INT";
    case CT_UINT: return "UNSIGNED_INT";
    case CT_FLOAT: return "FLOAT";
    default: return "unknown";
    }
}

/* One component as a number; normalized integers map to [0, 1] or [-1, 1] (glTF 2.0,
 * "Animations" and KHR_mesh_quantization: c / max, signed values clamped at -1). */
static double component(const uint8_t *p, int32_t t, bool normalized)
{
    switch (t) {
    case CT_BYTE: {
        int8_t v;
        memcpy(&v, p, 1);
        return normalized ? fmax(v / 127.0, -1.0) : v;
    }
    case CT_UBYTE: return normalized ? p[0] / 255.0 : p[0];
    case CT_SHORT: {
        int16_t v;
        memcpy(&v, p, 2);
        return normalized ? fmax(v / 32767.0, -1.0) : v;
    }
    case CT_USHORT: {
        uint16_t v;
        memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : v;
    }
    case CT_UINT: {
        uint32_t v;
        memcpy(&v, p, 4);
        return normalized ? v / 4294967295.0 : v;
    }
    default: {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    }
}

/* The bytes of bufferView `vi`, checked against its buffer. `what` names the user. */
static int view_bytes(loader *l, int32_t vi, const char *what, const uint8_t **data, uint64_t *len,
                      uint64_t *stride)
{
    const lg_gltf *g = l->g;
    if (vi < 0 || (uint32_t)vi >= g->n_views)
        return fail(l, LG_ERR_INVALID, "%s: bufferView %d does not exist (the file has %u)", what,
                    vi, g->n_views);
    const lg_gltf_view *v = &g->views[vi];
    if (v->buffer < 0 || (uint32_t)v->buffer >= g->n_buffers)
        return fail(l, LG_ERR_INVALID, "bufferView %d: buffer %d does not exist (the file has %u)",
                    vi, v->buffer, g->n_buffers);
    const lg_gltf_buffer *b = &g->buffers[v->buffer];
    if (v->offset > b->size || v->length > b->size - v->offset)
        return fail(l, LG_ERR_INVALID,
                    "bufferView %d: bytes %" PRIu64 "..%" PRIu64
                    " lie outside buffer %d (%zu bytes)",
                    vi, v->offset, v->offset + v->length, v->buffer, b->size);
    *data = b->data + v->offset;
    *len = v->length;
    if (stride)
        *stride = v->stride;
    return 0;
}

typedef enum { OUT_FLOAT, OUT_UINT } out_kind;

/* Reads accessor `ai` into out (count x comps floats or uint32s): dense data with its
 * stride, or zeros, then the sparse substitutions. `types` is a bit mask of allowed
 * component types (1 << (t - 5120)). */
static int read_accessor(loader *l, int32_t ai, const char *what, uint32_t comps, unsigned types,
                         out_kind kind, void **out, uint32_t *count)
{
    const lg_gltf *g = l->g;
    *out = NULL;
    if (ai < 0 || (uint32_t)ai >= g->n_accessors)
        return fail(l, LG_ERR_INVALID, "%s: accessor %d does not exist (the file has %u)", what, ai,
                    g->n_accessors);
    const lg_gltf_accessor *a = &g->accessors[ai];
    if (a->components != comps)
        return fail(l, LG_ERR_INVALID, "accessor %d (%s): %u components per element, want %u", ai,
                    what, a->components, comps);
    uint32_t cs = component_size(a->component_type);
    if (!cs || a->component_type < CT_BYTE || !(types & (1u << (a->component_type - CT_BYTE))))
        return fail(l, LG_ERR_UNSUPPORTED,
                    "accessor %d (%s): componentType %d (%s) is not supported here", ai, what,
                    a->component_type, component_name(a->component_type));
    if (a->count > LG_GLTF_MAX_COUNT)
        return fail(l, LG_ERR_INVALID,
                    "accessor %d (%s): count %" PRIu64 " is more than the %u accepted", ai, what,
                    a->count, LG_GLTF_MAX_COUNT);
    size_t n = (size_t)a->count, esize = (size_t)cs * comps;
    size_t osize = kind == OUT_FLOAT ? sizeof(float) : sizeof(uint32_t);
    void *buf = calloc(n * comps + 1, osize);
    if (!buf)
        return fail(l, LG_ERR_NOMEM, "accessor %d (%s): out of memory for %zu elements", ai, what,
                    n);

    if (a->view >= 0) {
        const uint8_t *data;
        uint64_t len, stride;
        int rc = view_bytes(l, a->view, what, &data, &len, &stride);
        if (rc) {
            free(buf);
            return rc;
        }
        if (stride == 0)
            stride = esize;
        if (stride < esize) {
            free(buf);
            return fail(l, LG_ERR_INVALID,
                        "accessor %d (%s): bufferView %d's byteStride %" PRIu64
                        " is smaller than an element (%zu bytes)",
                        ai, what, a->view, stride, esize);
        }
        if (n && (a->offset > len || (n - 1) * stride + esize > len - a->offset)) {
            free(buf);
            return fail(l, LG_ERR_INVALID,
                        "accessor %d (%s): %zu elements of %zu bytes, %" PRIu64
                        " apart from byte %" PRIu64 ", run past the end of bufferView %d (%" PRIu64
                        " bytes)",
                        ai, what, n, esize, stride, a->offset, a->view, len);
        }
        const uint8_t *p = data + a->offset;
        for (size_t i = 0; i < n; i++, p += stride)
            for (uint32_t k = 0; k < comps; k++) {
                double v = component(p + (size_t)k * cs, a->component_type, a->normalized);
                if (kind == OUT_FLOAT)
                    ((float *)buf)[i * comps + k] = (float)v;
                else
                    ((uint32_t *)buf)[i * comps + k] = (uint32_t)v;
            }
    }

    if (a->sparse) {
        const uint8_t *idx = NULL, *val = NULL;
        uint64_t ilen = 0, vlen = 0;
        uint32_t ics = component_size(a->sparse_index_type);
        int64_t sn = a->sparse_count;
        int rc = 0;
        if (sn < 1 || (uint64_t)sn > n)
            rc = fail(l, LG_ERR_INVALID,
                      "accessor %d (%s): sparse count %" PRId64 " is not in 1..%zu", ai, what, sn,
                      n);
        else if (!ics || a->sparse_index_type == CT_BYTE || a->sparse_index_type == CT_SHORT ||
                 a->sparse_index_type == CT_FLOAT)
            rc = fail(l, LG_ERR_INVALID, "accessor %d (%s): sparse indices of componentType %d", ai,
                      what, a->sparse_index_type);
        if (!rc)
            rc = view_bytes(l, a->sparse_index_view, what, &idx, &ilen, NULL);
        if (!rc)
            rc = view_bytes(l, a->sparse_value_view, what, &val, &vlen, NULL);
        if (!rc && (a->sparse_index_offset < 0 || (uint64_t)a->sparse_index_offset > ilen ||
                    (uint64_t)sn * ics > ilen - (uint64_t)a->sparse_index_offset ||
                    a->sparse_value_offset < 0 || (uint64_t)a->sparse_value_offset > vlen ||
                    (uint64_t)sn * esize > vlen - (uint64_t)a->sparse_value_offset))
            rc = fail(l, LG_ERR_INVALID,
                      "accessor %d (%s): sparse indices or values run past their bufferViews", ai,
                      what);
        for (int64_t s = 0; !rc && s < sn; s++) {
            uint64_t at = (uint64_t)component(idx + a->sparse_index_offset + s * ics,
                                              a->sparse_index_type, false);
            uint64_t prev = s ? (uint64_t)component(idx + a->sparse_index_offset + (s - 1) * ics,
                                                    a->sparse_index_type, false)
                              : 0;
            if (at >= n || (s && at <= prev)) {
                rc = fail(l, LG_ERR_INVALID,
                          "accessor %d (%s): sparse index %" PRIu64 " (entry %" PRId64
                          ") is out of range or not increasing",
                          ai, what, at, s);
                break;
            }
            const uint8_t *p = val + a->sparse_value_offset + (size_t)s * esize;
            for (uint32_t k = 0; k < comps; k++) {
                double v = component(p + (size_t)k * cs, a->component_type, a->normalized);
                if (kind == OUT_FLOAT)
                    ((float *)buf)[at * comps + k] = (float)v;
                else
                    ((uint32_t *)buf)[at * comps + k] = (uint32_t)v;
            }
        }
        if (rc) {
            free(buf);
            return rc;
        }
    }
    if (kind == OUT_FLOAT) {
        const float *f = buf;
        for (size_t i = 0; i < n * comps; i++)
            if (!isfinite(f[i])) {
                const char *kind_of = isnan(f[i]) ? "NaN" : "infinite";
                free(buf);
                return fail(l, LG_ERR_INVALID, "accessor %d (%s): element %zu component %zu is %s",
                            ai, what, i / comps, i % comps, kind_of);
            }
    }
    *out = buf;
    *count = (uint32_t)n;
    return 0;
}

/* ---- primitives to lg_mesh ------------------------------------------------------------------- */

static int32_t ref_texcoord(const lg_gltf_texture_info *ti);

/* Vertex data of one primitive before normals. */
typedef struct prim_data {
    uint32_t nv, ni;
    float *pos, *nrm, *uv;
    uint32_t *idx;
    float *uv1, *tan; /* TEXCOORD_1 (2 per vertex), TANGENT (4 per vertex), or NULL */
} prim_data;

static void prim_free(prim_data *p)
{
    free(p->pos);
    free(p->nrm);
    free(p->uv);
    free(p->idx);
    free(p->uv1);
    free(p->tan);
    memset(p, 0, sizeof *p);
}

#define MASK(t) (1u << ((t)-CT_BYTE))
#define ATTR_TYPES                                                                                 \
    (MASK(CT_FLOAT) | MASK(CT_BYTE) | MASK(CT_UBYTE) | MASK(CT_SHORT) | MASK(CT_USHORT))
#define INDEX_TYPES (MASK(CT_UBYTE) | MASK(CT_USHORT) | MASK(CT_UINT))

/* Reads the KHR_draco_mesh_compression primitive's data. */
static int read_draco(loader *l, const lg_gltf_primitive *p, const lg_json *ext, const char *label,
                      bool want_normals, prim_data *d)
{
    const lg_json *bv = lg_json_get(ext, "bufferView"), *attrs = lg_json_get(ext, "attributes");
    if (!bv || bv->type != LG_JSON_NUMBER || bv->number < 0 || bv->number != floor(bv->number) ||
        bv->number > INT32_MAX || !attrs || attrs->type != LG_JSON_OBJECT)
        return fail(l, LG_ERR_INVALID,
                    "%s: KHR_draco_mesh_compression needs an integer 'bufferView' and an "
                    "'attributes' object",
                    label);
    if (p->mode != 4)
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: a Draco primitive with mode %d (only TRIANGLES, 4, is supported)", label,
                    p->mode);
    int64_t ids[5] = { -1, -1, -1, -1, -1 };
    static const char *const names[5] = { "POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1",
                                          "TANGENT" };
    const int32_t accs[5] = { p->position, p->normal, p->texcoord, p->texcoord1, p->tangent };
    for (int k = 0; k < 5; k++) {
        const lg_json *id = lg_json_get(attrs, names[k]);
        if (!id)
            continue;
        if (id->type != LG_JSON_NUMBER || id->number < 0 || id->number != floor(id->number) ||
            id->number > UINT32_MAX)
            return fail(l, LG_ERR_INVALID,
                        "%s: KHR_draco_mesh_compression attribute %s is not a valid id", label,
                        names[k]);
        if (accs[k] < 0)
            return fail(l, LG_ERR_INVALID,
                        "%s: Draco attribute %s is not among the primitive's attributes", label,
                        names[k]);
        ids[k] = (int64_t)id->number;
    }
    if (ids[0] < 0)
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: the Draco data has no POSITION (uncompressed positions next to "
                    "Draco data are not supported)",
                    label);
    for (int k = 1; k < 5; k++)
        if (ids[k] < 0 && accs[k] >= 0)
            warn(l, "%s: %s is not in the Draco data; ignored", label, names[k]);
    const uint8_t *data;
    uint64_t len;
    char what[300];
    snprintf(what, sizeof what, "%s, KHR_draco_mesh_compression", label);
    int rc = view_bytes(l, (int32_t)bv->number, what, &data, &len, NULL);
    if (rc)
        return rc;
    lg_draco_mesh dm;
    char derr[512];
    if (lg_draco_decode(data, (size_t)len, ids[0], want_normals ? ids[1] : -1, ids[2], ids[3],
                        ids[4], LG_GLTF_MAX_COUNT, LG_GLTF_MAX_COUNT / 3, &dm, derr, sizeof derr))
        return fail(l, LG_ERR_INVALID, "%s (bufferView %d): %s", label, (int)bv->number, derr);
    for (size_t i = 0; i < (size_t)dm.n_points * 3; i++)
        if (!isfinite(dm.positions[i]) || (dm.normals && !isfinite(dm.normals[i]))) {
            lg_draco_mesh_free(&dm);
            return fail(l, LG_ERR_INVALID,
                        "%s: Draco point %zu has a NaN or infinite position or normal", label,
                        i / 3);
        }
    for (size_t i = 0; i < (size_t)dm.n_points * 4; i++)
        if ((dm.texcoords && i < (size_t)dm.n_points * 2 && !isfinite(dm.texcoords[i])) ||
            (dm.texcoords1 && i < (size_t)dm.n_points * 2 && !isfinite(dm.texcoords1[i])) ||
            (dm.tangents && !isfinite(dm.tangents[i]))) {
            lg_draco_mesh_free(&dm);
            return fail(l, LG_ERR_INVALID,
                        "%s: Draco point %zu has a NaN or infinite texture coordinate or "
                        "tangent",
                        label, i / 4);
        }
    d->nv = dm.n_points;
    d->ni = dm.n_faces * 3;
    d->pos = dm.positions;
    d->nrm = dm.normals;
    d->uv = dm.texcoords;
    d->idx = dm.indices;
    d->uv1 = dm.texcoords1;
    d->tan = dm.tangents;
    return 0;
}

/* Triangle list from the primitive's mode; `src` is the index list (NULL: 0..n-1). */
static int triangulate(loader *l, int32_t mode, const uint32_t *src, uint32_t n, const char *label,
                       uint32_t **out, uint32_t *n_out)
{
    uint32_t nt = mode == 4 ? n / 3 : n >= 3 ? n - 2 : 0;
    uint32_t *t = malloc(((size_t)nt * 3 + 1) * sizeof *t);
    if (!t)
        return fail(l, LG_ERR_NOMEM, "%s: out of memory for %u triangles", label, nt);
    if (mode == 4 && n % 3)
        warn(l, "%s: %u vertices/indices is not a multiple of 3; the last %u are ignored", label, n,
             n % 3);
    uint32_t k = 0;
    for (uint32_t i = 0; i < nt; i++) {
        uint32_t a, b, c;
        if (mode == 4) {
            a = 3 * i, b = 3 * i + 1, c = 3 * i + 2;
        } else if (mode == 5) { /* strip: {i, i + 1 + i % 2, i + 2 - i % 2} (glTF 2.0, 3.7.2.1) */
            a = i, b = i + 1 + i % 2, c = i + 2 - i % 2;
        } else { /* fan: {i + 1, i + 2, 0} */
            a = i + 1, b = i + 2, c = 0;
        }
        if (src)
            a = src[a], b = src[b], c = src[c];
        /* strips and fans join pieces with repeated indices: those triangles are dropped */
        if (mode != 4 && (a == b || b == c || a == c))
            continue;
        t[k++] = a;
        t[k++] = b;
        t[k++] = c;
    }
    *out = t;
    *n_out = k;
    return 0;
}

static const char *mode_name(int32_t mode)
{
    static const char *const names[] = { "POINTS",    "LINES",          "LINE_LOOP",   "LINE_STRIP",
                                         "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN" };
    return mode >= 0 && mode <= 6 ? names[mode] : "unknown";
}

/* Reads one primitive's arrays (plain or Draco) as a triangle list. */
/* A vertex attribute besides POSITION (accessor `acc`, `comps` floats per vertex) into *out;
 * it must have as many elements as POSITION (`nv`). */
static int read_attribute(loader *l, int32_t acc, const char *name, uint32_t comps,
                          const char *label, uint32_t nv, void **out)
{
    char what[300];
    uint32_t n = 0;
    snprintf(what, sizeof what, "%s of %s", name, label);
    int rc = read_accessor(l, acc, what, comps, ATTR_TYPES, OUT_FLOAT, out, &n);
    if (!rc && n != nv)
        rc = fail(l, LG_ERR_INVALID, "%s: %s has %u elements, POSITION %u", label, name, n, nv);
    return rc;
}

static int read_primitive(loader *l, uint32_t mi, uint32_t pi, prim_data *d)
{
    const lg_gltf_primitive *p = &l->g->meshes[mi].primitives[pi];
    char label[256];
    mesh_label(l, mi, pi, label, sizeof label);
    memset(d, 0, sizeof *d);
    if (p->mode < 4 || p->mode > 6)
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: mode %s (%d) cannot be drawn as triangles (supported: "
                    "TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN)",
                    label, mode_name(p->mode), p->mode);
    if (p->n_targets && !l->warned_targets) {
        l->warned_targets = true;
        warn(l, "%s: morph targets are not supported; the base shape is drawn", label);
    }
    bool want_normals = l->opt->normals == LG_GLTF_NORMALS_AUTO;
    const lg_json *draco = lg_json_get(p->extensions, "KHR_draco_mesh_compression");
    if (draco)
        return read_draco(l, p, draco, label, want_normals, d);

    if (p->position < 0)
        return fail(l, LG_ERR_INVALID, "%s: no POSITION attribute", label);
    char what[300];
    uint32_t m = 0;
    snprintf(what, sizeof what, "POSITION of %s", label);
    int rc = read_accessor(l, p->position, what, 3, ATTR_TYPES, OUT_FLOAT, (void **)&d->pos,
                           &d->nv);
    if (!rc && want_normals && p->normal >= 0)
        rc = read_attribute(l, p->normal, "NORMAL", 3, label, d->nv, (void **)&d->nrm);
    if (!rc && p->texcoord >= 0)
        rc = read_attribute(l, p->texcoord, "TEXCOORD_0", 2, label, d->nv, (void **)&d->uv);
    if (!rc && p->texcoord1 >= 0)
        rc = read_attribute(l, p->texcoord1, "TEXCOORD_1", 2, label, d->nv, (void **)&d->uv1);
    if (!rc && p->tangent >= 0)
        rc = read_attribute(l, p->tangent, "TANGENT", 4, label, d->nv, (void **)&d->tan);
    uint32_t *src = NULL;
    if (!rc && p->indices >= 0) {
        snprintf(what, sizeof what, "indices of %s", label);
        rc = read_accessor(l, p->indices, what, 1, INDEX_TYPES, OUT_UINT, (void **)&src, &m);
        for (uint32_t i = 0; !rc && i < m; i++)
            if (src[i] >= d->nv)
                rc = fail(l, LG_ERR_INVALID,
                          "accessor %d (%s): index %u at position %u is out of range (%u "
                          "vertices)",
                          p->indices, what, src[i], i, d->nv);
    }
    if (!rc)
        rc = triangulate(l, p->mode, src, src ? m : d->nv, label, &d->idx, &d->ni);
    free(src);
    if (rc)
        prim_free(d);
    return rc;
}

/* Drops the vertices no triangle uses (files keep leftovers: they would count, and
 * stretch the bounds the automatic camera frames), keeping the order of the others. */
static int compact(lg_nmesh *m)
{
    uint32_t *map = malloc(((size_t)m->n_vertices + 1) * sizeof *map);
    if (!map)
        return LG_ERR_NOMEM;
    memset(map, 0xff, ((size_t)m->n_vertices + 1) * sizeof *map);
    for (uint32_t i = 0; i < m->n_indices; i++)
        map[m->indices[i]] = 0;
    uint32_t n = 0;
    for (uint32_t v = 0; v < m->n_vertices; v++) {
        if (map[v] == UINT32_MAX)
            continue;
        map[v] = n;
        if (n != v) {
            memcpy(m->positions + 3 * (size_t)n, m->positions + 3 * (size_t)v, 3 * sizeof(float));
            memcpy(m->normals + 3 * (size_t)n, m->normals + 3 * (size_t)v, 3 * sizeof(float));
            if (m->texcoords)
                memcpy(m->texcoords + 2 * (size_t)n, m->texcoords + 2 * (size_t)v,
                       2 * sizeof(float));
        }
        n++;
    }
    for (uint32_t i = 0; i < m->n_indices; i++)
        m->indices[i] = map[m->indices[i]];
    m->n_vertices = n;
    free(map);
    return 0;
}

/* A per-vertex array of the source primitive carried to the mesh's vertices: corner c of
 * the source index list `src_idx` became vertex out_idx[c] (the normal computation and
 * compact keep the corners in order), so that vertex takes source vertex src_idx[c]'s
 * values. NULL when out of memory. */
static float *follow_corners(const float *src, uint32_t comps, const uint32_t *src_idx,
                             const uint32_t *out_idx, uint32_t ni, uint32_t nv)
{
    float *out = calloc((size_t)nv * comps + 1, sizeof *out);
    if (!out)
        return NULL;
    for (uint32_t c = 0; c < ni; c++)
        memcpy(out + (size_t)out_idx[c] * comps, src + (size_t)src_idx[c] * comps,
               comps * sizeof *out);
    return out;
}

/* The mesh's tangents and TEXCOORD_1 (README.md, "Tangents"): the file's tangents made
 * orthonormal, else, when its material has a normal texture, MikkTSpace's; a mesh without
 * the texture coordinates that normal texture reads is flagged (its material loses the
 * normal map for it: split_materials). */
static int mesh_tangents(loader *l, const lg_gltf_primitive *p, const char *label, lg_nmesh *nm,
                         float **uv1, float **tan, bool *no_normal_map)
{
    *no_normal_map = false;
    if (*tan) {
        lg_tangents_orthonormalize(*tan, nm->normals, nm->n_vertices);
        return 0;
    }
    const lg_gltf_material *gm = p->material >= 0 ? &l->g->materials[p->material] : NULL;
    if (!gm || gm->normal_tex.index < 0)
        return 0;
    int32_t set = ref_texcoord(&gm->normal_tex);
    if (set != 0 && set != 1)
        return 0; /* refused with the material (texture_ref) */
    if (!(set == 0 ? nm->texcoords : *uv1)) {
        warn(l,
             "%s: its material %d has a normal texture that reads TEXCOORD_%d, which the "
             "primitive lacks: the normal map is ignored for it",
             label, p->material, set);
        *no_normal_map = true;
        return 0;
    }
    if (lg_tangents_generate(nm, uv1, set, tan, NULL))
        return fail(l, LG_ERR_NOMEM, "%s: out of memory computing tangents", label);
    return 0;
}

/* Makes lg_mesh number (mi, pi) if it is not made yet; *id receives its index. */
static int make_mesh(loader *l, uint32_t mi, uint32_t pi, uint32_t *id)
{
    if (l->prim_mesh[mi][pi] >= 0) {
        *id = (uint32_t)l->prim_mesh[mi][pi];
        return 0;
    }
    const lg_gltf_primitive *p = &l->g->meshes[mi].primitives[pi];
    char label[256];
    mesh_label(l, mi, pi, label, sizeof label);
    if (p->material < -1 || (p->material >= 0 && (uint32_t)p->material >= l->g->n_materials))
        return fail(l, LG_ERR_INVALID, "%s: material %d does not exist (the file has %u)", label,
                    p->material, l->g->n_materials);
    prim_data d;
    int rc = read_primitive(l, mi, pi, &d);
    if (rc)
        return rc;
    /* TEXCOORD_1 and TANGENT follow the vertices through the normals (follow_corners) */
    float *uv1 = d.uv1, *tan = d.tan;
    uint32_t *corner_src = NULL;
    d.uv1 = d.tan = NULL;
    if (uv1 || tan) {
        corner_src = malloc(((size_t)d.ni + 1) * sizeof *corner_src);
        if (!corner_src) {
            free(uv1);
            free(tan);
            prim_free(&d);
            return fail(l, LG_ERR_NOMEM, "%s: out of memory", label);
        }
        memcpy(corner_src, d.idx, (size_t)d.ni * sizeof *corner_src);
    }

    lg_nmesh nm;
    memset(&nm, 0, sizeof nm);
    if (d.nrm) {
        for (uint32_t v = 0; v < d.nv; v++) {
            lg_vec3 n = lg_v3(d.nrm[3 * v], d.nrm[3 * v + 1], d.nrm[3 * v + 2]);
            n = lg_v3_normalize_or(n, lg_v3(0, 0, 1));
            d.nrm[3 * v] = n.x, d.nrm[3 * v + 1] = n.y, d.nrm[3 * v + 2] = n.z;
        }
        nm = (lg_nmesh){ d.nv, d.ni, d.pos, d.nrm, d.uv, d.idx };
        memset(&d, 0, sizeof d);
        if (compact(&nm)) {
            lg_nmesh_free(&nm);
            free(uv1);
            free(tan);
            free(corner_src);
            return fail(l, LG_ERR_NOMEM, "%s: out of memory", label);
        }
    } else {
        rc = l->opt->normals == LG_GLTF_NORMALS_FLAT
                 ? lg_normals_flat(d.pos, d.uv, d.nv, d.idx, d.ni, &nm)
                 : lg_normals_smooth(d.pos, d.uv, d.nv, d.idx, d.ni, (float)l->opt->crease_deg,
                                     &nm);
        prim_free(&d);
        if (rc) {
            free(uv1);
            free(tan);
            free(corner_src);
            return fail(l, LG_ERR_NOMEM, "%s: out of memory computing normals", label);
        }
    }
    bool no_normal_map = false;
    float *uv1_out =
        uv1 ? follow_corners(uv1, 2, corner_src, nm.indices, nm.n_indices, nm.n_vertices) : NULL;
    float *tan_out =
        tan ? follow_corners(tan, 4, corner_src, nm.indices, nm.n_indices, nm.n_vertices) : NULL;
    bool lost = (uv1 && !uv1_out) || (tan && !tan_out);
    free(uv1);
    free(tan);
    free(corner_src);
    rc = lost ? fail(l, LG_ERR_NOMEM, "%s: out of memory", label)
              : mesh_tangents(l, p, label, &nm, &uv1_out, &tan_out, &no_normal_map);
    if (!rc && !grow((void **)&l->mesh_no_normal_map, &l->cap_no_normal_map, l->st->n_meshes,
                     sizeof *l->mesh_no_normal_map))
        rc = fail(l, LG_ERR_NOMEM, "out of memory");
    if (rc) {
        lg_nmesh_free(&nm);
        free(uv1_out);
        free(tan_out);
        return rc;
    }
    l->mesh_no_normal_map[l->st->n_meshes] = no_normal_map;

    store *st = l->st;
    if (!grow((void **)&st->meshes, &st->cap_meshes, st->n_meshes, sizeof *st->meshes)) {
        lg_nmesh_free(&nm);
        free(uv1_out);
        free(tan_out);
        return fail(l, LG_ERR_NOMEM, "out of memory");
    }
    lg_mesh *m = &st->meshes[st->n_meshes++];
    memset(m, 0, sizeof *m);
    m->n_vertices = nm.n_vertices;
    m->n_indices = nm.n_indices;
    m->positions = nm.positions;
    m->normals = nm.normals;
    m->texcoords = nm.texcoords;
    m->indices = nm.indices;
    m->texcoords1 = uv1_out;
    m->tangents = tan_out;
    m->material = p->material >= 0 ? (uint32_t)p->material : l->g->n_materials; /* default: last */
    if (p->material < 0)
        *l->material_used_default = true;
    char name[300];
    const char *mn = l->g->meshes[mi].name;
    if (mn && *mn)
        snprintf(name, sizeof name, "%s#%u", mn, pi);
    else
        snprintf(name, sizeof name, "mesh %u#%u", mi, pi);
    m->name = keep(l, name);
    for (int k = 0; k < 3; k++) {
        m->bounds_min[k] = nm.n_vertices ? FLT_MAX : 0;
        m->bounds_max[k] = nm.n_vertices ? -FLT_MAX : 0;
    }
    for (size_t i = 0; i < (size_t)nm.n_vertices * 3; i++) {
        m->bounds_min[i % 3] = fminf(m->bounds_min[i % 3], nm.positions[i]);
        m->bounds_max[i % 3] = fmaxf(m->bounds_max[i % 3], nm.positions[i]);
    }
    if (!m->name)
        return fail(l, LG_ERR_NOMEM, "out of memory");
    l->prim_mesh[mi][pi] = st->n_meshes - 1;
    *id = st->n_meshes - 1;
    return 0;
}

/* ---- the node tree --------------------------------------------------------------------------- */

static void m4d_mul(double out[16], const double a[16], const double b[16])
{
    double r[16];
    for (int c = 0; c < 4; c++)
        for (int rr = 0; rr < 4; rr++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    memcpy(out, r, sizeof r);
}

static bool all_finite(const double *v, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return false;
    return true;
}

/* The node's local matrix: `matrix`, or T * R * S (glTF 2.0, 3.5.3). */
static int local_matrix(loader *l, uint32_t ni, double m[16])
{
    const lg_gltf_node *n = &l->g->nodes[ni];
    if ((n->n_matrix && n->n_matrix != 16) || (n->n_translation && n->n_translation != 3) ||
        (n->n_rotation && n->n_rotation != 4) || (n->n_scale && n->n_scale != 3))
        return fail(l, LG_ERR_INVALID,
                    "node %u: matrix, translation, rotation and scale need 16, 3, 4 and 3 "
                    "numbers (got %u, %u, %u, %u)",
                    ni, n->n_matrix, n->n_translation, n->n_rotation, n->n_scale);
    if (!all_finite(n->matrix, n->n_matrix) || !all_finite(n->translation, n->n_translation) ||
        !all_finite(n->rotation, n->n_rotation) || !all_finite(n->scale, n->n_scale))
        return fail(l, LG_ERR_INVALID, "node %u: its transform has a NaN or infinite number", ni);
    if (n->n_matrix) {
        memcpy(m, n->matrix, 16 * sizeof(double));
        return 0;
    }
    double t[3] = { 0, 0, 0 }, q[4] = { 0, 0, 0, 1 }, s[3] = { 1, 1, 1 };
    if (n->n_translation)
        memcpy(t, n->translation, sizeof t);
    if (n->n_rotation)
        memcpy(q, n->rotation, sizeof q);
    if (n->n_scale)
        memcpy(s, n->scale, sizeof s);
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(len > 1e-12))
        return fail(l, LG_ERR_INVALID, "node %u: rotation quaternion has length 0", ni);
    double x = q[0] / len, y = q[1] / len, z = q[2] / len, w = q[3] / len;
    double r[9] = { /* column-major rotation */
                    1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                    2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                    2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)
    };
    memset(m, 0, 16 * sizeof(double));
    for (int c = 0; c < 3; c++)
        for (int rr = 0; rr < 3; rr++)
            m[c * 4 + rr] = r[c * 3 + rr] * s[c];
    m[12] = t[0], m[13] = t[1], m[14] = t[2], m[15] = 1;
    return 0;
}

/* parent[] of every node, checked: children exist, nobody has two parents, no cycles, no
 * nesting deeper than LG_GLTF_MAX_DEPTH. */
static int check_tree(loader *l, int64_t *parent)
{
    const lg_gltf *g = l->g;
    uint32_t nn = g->n_nodes;
    for (uint32_t i = 0; i < nn; i++)
        parent[i] = -1;
    for (uint32_t i = 0; i < nn; i++) {
        const lg_gltf_node *n = &g->nodes[i];
        for (uint32_t k = 0; k < n->n_children; k++) {
            int32_t c = n->children[k];
            if (c < 0 || (uint32_t)c >= nn)
                return fail(l, LG_ERR_INVALID,
                            "node %u: child %d does not exist (the file has %u nodes)", i, c, nn);
            if ((uint32_t)c == i)
                return fail(l, LG_ERR_INVALID, "node %u is its own child (a cycle)", i);
            if (parent[c] >= 0)
                return fail(l, LG_ERR_INVALID,
                            "node %d has two parents (nodes %" PRId64 " and %u); glTF nodes "
                            "form trees",
                            c, parent[c], i);
            parent[c] = i;
        }
    }
    /* walk up from each node; state 1 = on the current path, 2 = depth known */
    uint8_t *state = calloc(nn + 1, 1);
    uint32_t *depth = calloc(nn + 1, sizeof *depth), *path = malloc((nn + 1) * sizeof *path);
    int rc = 0;
    if (!state || !depth || !path)
        rc = fail(l, LG_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; !rc && i < nn; i++) {
        uint32_t np = 0, v = i, d = 0;
        for (;;) {
            if (state[v] == 1) {
                rc = fail(l, LG_ERR_INVALID,
                          "node %u is its own ancestor (a cycle in the node hierarchy)", v);
                break;
            }
            if (state[v] == 2) { /* path[np - 1] is a child of v */
                d = depth[v] + 1;
                break;
            }
            state[v] = 1;
            path[np++] = v;
            if (parent[v] < 0) { /* path[np - 1] is a root */
                d = 0;
                break;
            }
            v = (uint32_t)parent[v];
        }
        for (uint32_t k = np; !rc && k-- > 0; d++) {
            depth[path[k]] = d;
            state[path[k]] = 2;
            if (d > LG_GLTF_MAX_DEPTH)
                rc = fail(l, LG_ERR_INVALID, "node %u is nested %u levels deep (more than %d)",
                          path[k], d, LG_GLTF_MAX_DEPTH);
        }
    }
    free(state);
    free(depth);
    free(path);
    return rc;
}

static int place(loader *l, struct placed **arr, uint32_t *n, uint32_t *cap, uint32_t node,
                 uint32_t index, const double world[16])
{
    if (!grow((void **)arr, cap, *n, sizeof **arr))
        return fail(l, LG_ERR_NOMEM, "out of memory");
    (*arr)[*n].node = node;
    (*arr)[*n].index = index;
    memcpy((*arr)[*n].world, world, 16 * sizeof(double));
    (*n)++;
    return 0;
}

/* What node ni draws and holds, with its world matrix. */
static int visit(loader *l, uint32_t ni, const double world[16])
{
    const lg_gltf *g = l->g;
    const lg_gltf_node *n = &g->nodes[ni];
    int rc;
    if (n->mesh >= 0) {
        if ((uint32_t)n->mesh >= g->n_meshes)
            return fail(l, LG_ERR_INVALID, "node %u: mesh %d does not exist (the file has %u)", ni,
                        n->mesh, g->n_meshes);
        if (n->skin >= 0 && !l->warned_skin) {
            l->warned_skin = true;
            warn(l, "node %u: skinning is not supported; the mesh is drawn in its bind pose", ni);
        }
        float mf[16], nm[9];
        bool finite = all_finite(world, 16);
        for (int i = 0; i < 16; i++) {
            mf[i] = (float)world[i];
            finite = finite && isfinite(mf[i]);
        }
        if (!finite)
            return fail(l, LG_ERR_INVALID,
                        "node %u: its world transform overflows (beyond the float range)", ni);
        if (lg_m4_normal_matrix(nm, mf)) {
            warn(l,
                 "node %u: its world transform is singular (a zero scale?); its mesh is not drawn",
                 ni);
        } else {
            const lg_gltf_mesh *gm = &g->meshes[n->mesh];
            for (uint32_t p = 0; p < gm->n_primitives; p++) {
                uint32_t id = 0;
                if ((rc = make_mesh(l, (uint32_t)n->mesh, p, &id)))
                    return rc;
                store *st = l->st;
                if (st->n_instances >= LG_GLTF_MAX_INSTANCES)
                    return fail(l, LG_ERR_INVALID,
                                "more than %u mesh primitives placed in the scene",
                                LG_GLTF_MAX_INSTANCES);
                if (!grow((void **)&st->instances, &st->cap_instances, st->n_instances,
                          sizeof *st->instances))
                    return fail(l, LG_ERR_NOMEM, "out of memory");
                uint32_t cap_before = st->cap_inst_node;
                if (!grow((void **)&st->inst_node, &st->cap_inst_node, st->n_instances,
                          sizeof *st->inst_node)) {
                    st->cap_inst_node = cap_before;
                    return fail(l, LG_ERR_NOMEM, "out of memory");
                }
                st->inst_node[st->n_instances] = ni;
                lg_instance *in = &st->instances[st->n_instances++];
                memset(in, 0, sizeof *in);
                in->mesh = id;
                memcpy(in->model, mf, sizeof mf);
                memcpy(in->normal_matrix, nm, sizeof nm);
            }
        }
    }
    if (n->camera >= 0) {
        if ((uint32_t)n->camera >= g->n_cameras)
            return fail(l, LG_ERR_INVALID, "node %u: camera %d does not exist (the file has %u)",
                        ni, n->camera, g->n_cameras);
        if ((rc = place(l, &l->cams, &l->n_cams, &l->cap_cams, ni, (uint32_t)n->camera, world)))
            return rc;
    }
    const lg_json *lp = lg_json_get(n->extensions, "KHR_lights_punctual");
    if (lp) {
        const lg_json *li = lg_json_get(lp, "light");
        if (!li || li->type != LG_JSON_NUMBER || li->number < 0 ||
            li->number != floor(li->number) || li->number >= g->n_lights)
            return fail(l, LG_ERR_INVALID,
                        "node %u: KHR_lights_punctual.light is not one of the file's %u "
                        "lights",
                        ni, g->n_lights);
        if ((rc = place(l, &l->lits, &l->n_lits, &l->cap_lits, ni, (uint32_t)li->number, world)))
            return rc;
    }
    return 0;
}

/* Walks the chosen scene's trees depth first (children in file order). */
static int walk(loader *l, const int64_t *parent)
{
    const lg_gltf *g = l->g;
    const lg_gltf_options *o = l->opt;
    uint32_t nn = g->n_nodes;
    const int32_t *roots = NULL;
    uint32_t n_roots = 0;
    int32_t *all = NULL;
    int64_t si = o->scene >= 0 ? o->scene : g->default_scene;
    if (o->scene >= 0 && (uint64_t)o->scene >= g->n_scenes)
        return fail(l, LG_ERR_INVALID, "scene %" PRId64 " does not exist (the file has %u)",
                    o->scene, g->n_scenes);
    if (si >= 0 && (uint64_t)si >= g->n_scenes)
        return fail(l, LG_ERR_INVALID,
                    "the default scene %" PRId64 " does not exist (the file has %u)", si,
                    g->n_scenes);
    if (si < 0 && g->n_scenes)
        si = 0;
    if (si >= 0) {
        roots = g->scenes[si].nodes;
        n_roots = g->scenes[si].n_nodes;
    } else {
        all = malloc((nn + 1) * sizeof *all);
        if (!all)
            return fail(l, LG_ERR_NOMEM, "out of memory");
        for (uint32_t i = 0; i < nn; i++)
            if (parent[i] < 0)
                all[n_roots++] = (int32_t)i;
        roots = all;
    }
    /* an explicit stack: (node, world matrix) */
    struct item {
        uint32_t node;
        double world[16];
    } *stack = malloc((nn + 1) * sizeof *stack);
    bool *seen = calloc(nn + 1, 1);
    int rc = 0;
    if (!stack || !seen)
        rc = fail(l, LG_ERR_NOMEM, "out of memory");
    for (uint32_t r = 0; !rc && r < n_roots; r++) {
        int32_t root = roots[r];
        if (root < 0 || (uint32_t)root >= nn) {
            rc = fail(l, LG_ERR_INVALID,
                      "scene %" PRId64 ": node %d does not exist (the file has %u)", si, root, nn);
            break;
        }
        if (parent[root] >= 0) {
            rc = fail(l, LG_ERR_INVALID,
                      "scene %" PRId64
                      " lists node %d as a root, but it is a child of node %" PRId64,
                      si, root, parent[root]);
            break;
        }
        uint32_t sp = 0;
        stack[sp].node = (uint32_t)root;
        if ((rc = local_matrix(l, (uint32_t)root, stack[sp].world)))
            break;
        sp++;
        while (sp > 0 && !rc) {
            struct item it = stack[--sp];
            if (seen[it.node]) {
                rc = fail(l, LG_ERR_INVALID, "node %u is listed twice among the scene's roots",
                          it.node);
                break;
            }
            seen[it.node] = true;
            if ((rc = visit(l, it.node, it.world)))
                break;
            const lg_gltf_node *n = &g->nodes[it.node];
            /* pushed in reverse, so that children are visited in file order */
            for (uint32_t k = n->n_children; k-- > 0 && !rc;) {
                double local[16];
                uint32_t c = (uint32_t)n->children[k];
                if ((rc = local_matrix(l, c, local)))
                    break;
                stack[sp].node = c;
                m4d_mul(stack[sp].world, it.world, local);
                sp++;
            }
        }
    }
    free(stack);
    free(seen);
    free(all);
    return rc;
}

/* ---- materials ------------------------------------------------------------------------------- */

static uint64_t fnv1a(uint64_t h, const uint8_t *p, size_t n);

static const lg_json *ext_get(const lg_json *extensions, const char *ext, const char *key)
{
    return lg_json_get(lg_json_get(extensions, ext), key);
}

/* A number from JSON in [lo, hi]; absent leaves *v. */
static int json_number(loader *l, const char *where, const char *key, const lg_json *j, double lo,
                       double hi, double *v)
{
    if (!j)
        return 0;
    if (j->type != LG_JSON_NUMBER || !isfinite(j->number) || j->number < lo || j->number > hi)
        return fail(l, LG_ERR_INVALID, "%s: %s must be a number in [%g, %g]", where, key, lo, hi);
    *v = j->number;
    return 0;
}

/* A colour from JSON: [r, g, b] or one number for all three, each in [lo, hi]. */
static int json_rgb(loader *l, const char *where, const char *key, const lg_json *j, double lo,
                    double hi, double v[3])
{
    if (!j)
        return 0;
    if (j->type == LG_JSON_NUMBER) {
        double x = v[0];
        int rc = json_number(l, where, key, j, lo, hi, &x);
        v[0] = v[1] = v[2] = x;
        return rc;
    }
    if (j->type != LG_JSON_ARRAY || j->n != 3)
        return fail(l, LG_ERR_INVALID, "%s: %s must be [r, g, b] or one number, each in [%g, %g]",
                    where, key, lo, hi);
    for (int k = 0; k < 3; k++)
        if (json_number(l, where, key, &j->items[k], lo, hi, &v[k]))
            return LG_ERR_INVALID;
    return 0;
}

/* glTF metallic-roughness to the Phong parameters (README.md, "Materials"). */
static int map_material(loader *l, uint32_t i, lg_material *out)
{
    const lg_gltf_material *gm = &l->g->materials[i];
    char where[300];
    if (gm->name && *gm->name)
        snprintf(where, sizeof where, "material %u ('%s')", i, gm->name);
    else
        snprintf(where, sizeof where, "material %u", i);
    if (gm->n_base_color != 4 || (gm->n_emissive && gm->n_emissive != 3))
        return fail(l, LG_ERR_INVALID, "%s: baseColorFactor needs 4 numbers and emissiveFactor 3",
                    where);
    double base[4], emissive[3] = { 0, 0, 0 };
    for (int k = 0; k < 4; k++) {
        base[k] = gm->base_color[k];
        if (!(base[k] >= 0 && base[k] <= 1))
            return fail(l, LG_ERR_INVALID, "%s: baseColorFactor[%d] = %g is not in [0, 1]", where,
                        k, base[k]);
    }
    for (uint32_t k = 0; k < gm->n_emissive; k++) {
        emissive[k] = gm->emissive[k];
        if (!(emissive[k] >= 0 && emissive[k] <= 1))
            return fail(l, LG_ERR_INVALID, "%s: emissiveFactor[%u] = %g is not in [0, 1]", where, k,
                        emissive[k]);
    }
    double metal = gm->metallic, rough = gm->roughness;
    if (!(metal >= 0 && metal <= 1) || !(rough >= 0 && rough <= 1))
        return fail(l, LG_ERR_INVALID,
                    "%s: metallicFactor %g and roughnessFactor %g must be in [0, 1]", where, metal,
                    rough);
    double strength = 1, ior = 1.5, spec = 1, spec_color[3] = { 1, 1, 1 };
    int rc;
    if ((rc = json_number(l, where, "KHR_materials_emissive_strength.emissiveStrength",
                          ext_get(gm->extensions, "KHR_materials_emissive_strength",
                                  "emissiveStrength"),
                          0, 1e30, &strength)) ||
        (rc = json_number(l, where, "KHR_materials_ior.ior",
                          ext_get(gm->extensions, "KHR_materials_ior", "ior"), 1, 1e30, &ior)) ||
        (rc = json_number(l, where, "KHR_materials_specular.specularFactor",
                          ext_get(gm->extensions, "KHR_materials_specular", "specularFactor"), 0, 1,
                          &spec)) ||
        (rc = json_rgb(l, where, "KHR_materials_specular.specularColorFactor",
                       ext_get(gm->extensions, "KHR_materials_specular", "specularColorFactor"), 0,
                       1e30, spec_color)))
        return rc;

    /* Fresnel reflectance at normal incidence of the dielectric part, from the index of
     * refraction (KHR_materials_ior) and KHR_materials_specular; metals reflect their
     * base colour (glTF 2.0, Appendix B: F0 = mix(dielectric F0, baseColor, metallic)). */
    double f0 = ((ior - 1) / (ior + 1)) * ((ior - 1) / (ior + 1));
    double od[3], os[3];
    for (int k = 0; k < 3; k++) {
        double dielectric = fmin(f0 * spec_color[k], 1.0) * spec;
        od[k] = base[k];
        os[k] = dielectric * (1 - metal) + base[k] * metal;
    }
    /* roughness -> alpha = roughness^2 (Appendix B) -> Blinn-Phong exponent 2 / alpha^2 - 2
     * (Walter et al. 2007: the Phong distribution matching a Beckmann lobe of width alpha)
     * -> Phong exponent a quarter of it (TECHNIQUES.md 1: Blinn's n' ~ 4n matches Phong's n). */
    double alpha = rough * rough, n;
    if (alpha * alpha < 2.0 / (4.0 * 10000.0 + 2.0))
        n = 10000;
    else
        n = (2.0 / (alpha * alpha) - 2.0) / 4.0;
    n = fmin(fmax(n, 1.0), 10000.0);
    double ka = 0.1, kd = 1 - metal, ks = 1, shininess = n;
    /* What image-based lighting mirrors (lg_material.reflectivity): the same F0, for
     * materials that ask for a reflection: metals, and dielectrics that state their
     * specular reflectance with KHR_materials_specular. A plain dielectric (a wall, the
     * default 0.04 of every glTF material) mirrors nothing, so that a scene of them gates
     * reflect and envmap off. */
    double reflectivity[3] = { 0, 0, 0 };
    bool khr_specular = lg_json_get(gm->extensions, "KHR_materials_specular") != NULL;
    if (metal > 0 || khr_specular)
        for (int k = 0; k < 3; k++)
            reflectivity[k] = os[k];

    /* extras override any of them, by lg_material's names */
    const lg_json *x = gm->extras;
    if (x && x->type != LG_JSON_OBJECT)
        x = NULL; /* extras are free-form: a non-object is someone else's */
    if ((rc = json_number(l, where, "extras.ka", lg_json_get(x, "ka"), 0, 1e30, &ka)) ||
        (rc = json_number(l, where, "extras.kd", lg_json_get(x, "kd"), 0, 1e30, &kd)) ||
        (rc = json_number(l, where, "extras.ks", lg_json_get(x, "ks"), 0, 1e30, &ks)) ||
        (rc = json_number(l, where, "extras.shininess", lg_json_get(x, "shininess"), 0, 1e30,
                          &shininess)) ||
        (rc = json_rgb(l, where, "extras.od", lg_json_get(x, "od"), 0, 1e30, od)) ||
        (rc = json_rgb(l, where, "extras.os", lg_json_get(x, "os"), 0, 1e30, os)) ||
        (rc = json_rgb(l, where, "extras.reflectivity", lg_json_get(x, "reflectivity"), 0, 1,
                       reflectivity)))
        return rc;

    memset(out, 0, sizeof *out);
    out->name = keep(l, gm->name && *gm->name ? gm->name : where);
    out->ka = (float)ka;
    out->kd = (float)kd;
    out->ks = (float)ks;
    out->shininess = (float)shininess;
    for (int k = 0; k < 3; k++) {
        out->od[k] = (float)od[k];
        out->os[k] = (float)os[k];
        out->emissive[k] = (float)(emissive[k] * strength);
        out->reflectivity[k] = (float)reflectivity[k];
    }
    for (int k = 0; k < 4; k++)
        out->base_color[k] = (float)base[k];
    out->metallic = (float)metal;
    out->roughness = (float)rough;
    out->double_sided = gm->double_sided;
    return out->name ? 0 : fail(l, LG_ERR_NOMEM, "out of memory");
}

/* glTF's default material (3.9.6: base colour 1, metallic 1, roughness 1), mapped the
 * same way. */
static void default_material(lg_material *m)
{
    memset(m, 0, sizeof *m);
    m->name = "default";
    m->ka = 0.1f;
    m->kd = 0.0f;
    m->ks = 1.0f;
    m->shininess = 1.0f;
    for (int k = 0; k < 3; k++)
        m->od[k] = m->os[k] = m->reflectivity[k] = 1.0f; /* a metal: it reflects */
    for (int k = 0; k < 4; k++)
        m->base_color[k] = 1.0f;
    m->metallic = m->roughness = 1.0f;
}

/* ---- textures -------------------------------------------------------------------------------- */

static const char *const ref_names[5] = { "baseColorTexture", "metallicRoughnessTexture",
                                          "normalTexture", "occlusionTexture", "emissiveTexture" };

/* The textureInfos of material gm, in the order of ref_names (and of lg_material_maps). */
static const lg_gltf_texture_info *material_ref(const lg_gltf_material *gm, int k)
{
    const lg_gltf_texture_info *refs[5] = { &gm->base_color_tex, &gm->metallic_roughness_tex,
                                            &gm->normal_tex, &gm->occlusion_tex,
                                            &gm->emissive_tex };
    return refs[k];
}

/* The texture coordinate set a textureInfo reads: KHR_texture_transform's texCoord when it
 * gives one, else the textureInfo's (checked by texture_ref). */
static int32_t ref_texcoord(const lg_gltf_texture_info *ti)
{
    const lg_json *tc = ext_get(ti->extensions, "KHR_texture_transform", "texCoord");
    if (tc && tc->type == LG_JSON_NUMBER && tc->number >= 0 && tc->number <= 1 &&
        tc->number == floor(tc->number))
        return (int32_t)tc->number;
    return ti->texcoord;
}

/* A JSON array of n finite numbers into v (absent leaves v). */
static int json_numbers(loader *l, const char *where, const char *key, const lg_json *j, uint32_t n,
                        double *v)
{
    if (!j)
        return 0;
    if (j->type != LG_JSON_ARRAY || j->n != n)
        return fail(l, LG_ERR_INVALID, "%s: %s must be an array of %u numbers", where, key, n);
    for (uint32_t k = 0; k < n; k++) {
        if (j->items[k].type != LG_JSON_NUMBER || !isfinite(j->items[k].number) ||
            fabs(j->items[k].number) > 1e30)
            return fail(l, LG_ERR_INVALID, "%s: %s[%u] is not a finite number (within +-1e30)",
                        where, key, k);
        v[k] = j->items[k].number;
    }
    return 0;
}

/* One textureInfo of a material to an lg_texture_ref (README.md, "Textures"). The file's
 * texture index is kept in out->texture; make_textures renumbers it. */
static int texture_ref(loader *l, const char *material, int k, const lg_gltf_texture_info *ti,
                       lg_texture_ref *out)
{
    *out = lg_material_maps_default()->base_color;
    if (ti->index == -1)
        return 0;
    char where[400];
    snprintf(where, sizeof where, "%s: %s", material, ref_names[k]);
    const lg_gltf *g = l->g;
    if (ti->index < 0 || (uint32_t)ti->index >= g->n_textures)
        return fail(l, LG_ERR_INVALID, "%s: texture %d does not exist (the file has %u)", where,
                    ti->index, g->n_textures);
    if (ti->texcoord != 0 && ti->texcoord != 1)
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: texCoord %d is not supported (only 0 and 1: TEXCOORD_0, TEXCOORD_1)",
                    where, ti->texcoord);
    double scale = ti->scale;
    if (k == 2 && !(isfinite(scale) && fabs(scale) <= 1e30))
        return fail(l, LG_ERR_INVALID, "%s: scale %g is not a finite number", where, scale);
    if (k == 3 && !(scale >= 0 && scale <= 1))
        return fail(l, LG_ERR_INVALID, "%s: strength %g is not in [0, 1]", where, scale);
    out->texture = ti->index;
    out->texcoord = (uint32_t)ti->texcoord;
    out->scale = (k == 2 || k == 3) ? (float)scale : 1.0f;
    const lg_json *tt = lg_json_get(ti->extensions, "KHR_texture_transform");
    if (!tt)
        return 0;
    char twhere[440];
    snprintf(twhere, sizeof twhere, "%s: KHR_texture_transform", where);
    if (tt->type != LG_JSON_OBJECT)
        return fail(l, LG_ERR_INVALID, "%s is not an object", twhere);
    double offset[2] = { 0, 0 }, sc[2] = { 1, 1 }, rot = 0, tc = ti->texcoord;
    int rc = json_numbers(l, twhere, "offset", lg_json_get(tt, "offset"), 2, offset);
    if (!rc)
        rc = json_numbers(l, twhere, "scale", lg_json_get(tt, "scale"), 2, sc);
    if (!rc)
        rc = json_number(l, twhere, "rotation", lg_json_get(tt, "rotation"), -1e30, 1e30, &rot);
    if (!rc)
        rc = json_number(l, twhere, "texCoord", lg_json_get(tt, "texCoord"), -1e30, 1e30, &tc);
    if (rc)
        return rc;
    if (tc != 0 && tc != 1)
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: texCoord %g is not supported (only 0 and 1: TEXCOORD_0, TEXCOORD_1)",
                    twhere, tc);
    out->texcoord = (uint32_t)tc;
    /* T * R * S of the extension's GLSL (column-major): uv' = offset + R(rotation) (scale uv)
     * with R = [cos -sin; sin cos] */
    double c = cos(rot), s = sin(rot);
    double t[6] = { c * sc[0], s * sc[0], -s * sc[1], c * sc[1], offset[0], offset[1] };
    for (int i = 0; i < 6; i++) {
        out->transform[i] = (float)t[i];
        if (!isfinite(out->transform[i]))
            return fail(l, LG_ERR_INVALID, "%s: the transform overflows (element %d is %g)", twhere,
                        i, t[i]);
    }
    return 0;
}

/* Material i's textures and alpha mode into *maps; *any when it differs from the defaults. */
static int material_maps(loader *l, uint32_t i, lg_material_maps *maps, bool *any)
{
    const lg_gltf_material *gm = &l->g->materials[i];
    char where[300];
    if (gm->name && *gm->name)
        snprintf(where, sizeof where, "material %u ('%s')", i, gm->name);
    else
        snprintf(where, sizeof where, "material %u", i);
    *maps = *lg_material_maps_default();
    lg_texture_ref *refs[5] = { &maps->base_color, &maps->metallic_roughness, &maps->normal,
                                &maps->occlusion, &maps->emissive };
    *any = false;
    for (int k = 0; k < 5; k++) {
        int rc = texture_ref(l, where, k, material_ref(gm, k), refs[k]);
        if (rc)
            return rc;
        *any |= refs[k]->texture >= 0;
    }
    const char *mode = gm->alpha_mode ? gm->alpha_mode : "OPAQUE";
    if (!strcmp(mode, "OPAQUE"))
        maps->alpha_mode = LG_ALPHA_OPAQUE;
    else if (!strcmp(mode, "MASK"))
        maps->alpha_mode = LG_ALPHA_MASK;
    else if (!strcmp(mode, "BLEND"))
        maps->alpha_mode = LG_ALPHA_BLEND;
    else
        return fail(l, LG_ERR_INVALID, "%s: alphaMode '%s' is not OPAQUE, MASK or BLEND", where,
                    mode);
    if (!(gm->alpha_cutoff >= 0 && gm->alpha_cutoff <= 1e30))
        return fail(l, LG_ERR_INVALID, "%s: alphaCutoff %g is not a finite number >= 0", where,
                    gm->alpha_cutoff);
    maps->alpha_cutoff = (float)gm->alpha_cutoff;
    *any |= maps->alpha_mode != LG_ALPHA_OPAQUE;
    return 0;
}

static const char *image_label(loader *l, uint32_t i, char *buf, size_t size)
{
    const lg_gltf_image *im = &l->g->images[i];
    if (im->view >= 0)
        snprintf(buf, size, "image %u (bufferView %d)", i, im->view);
    else if (im->data_uri)
        snprintf(buf, size, "image %u (a data: URI)", i);
    else
        snprintf(buf, size, "image %u ('%s')", i, im->uri);
    return buf;
}

static bool valid_filter(int32_t f, bool min)
{
    return f == -1 || f == LG_TEX_NEAREST || f == LG_TEX_LINEAR ||
           (min && f >= LG_TEX_NEAREST_MIPMAP_NEAREST && f <= LG_TEX_LINEAR_MIPMAP_LINEAR);
}

static bool valid_wrap(int32_t w)
{
    return w == LG_TEX_CLAMP_TO_EDGE || w == LG_TEX_MIRRORED_REPEAT || w == LG_TEX_REPEAT;
}

/* Reads (when it is a file) and decodes image i into *out. */
static int decode_image(loader *l, uint32_t i, lg_scene_image *out)
{
    const lg_gltf_image *im = &l->g->images[i];
    char label[600], why[512];
    image_label(l, i, label, sizeof label);
    const uint8_t *bytes = NULL;
    uint8_t *file = NULL;
    size_t size = 0;
    if (im->view >= 0) {
        uint64_t len;
        int rc = view_bytes(l, im->view, label, &bytes, &len, NULL);
        if (rc)
            return rc;
        size = (size_t)len;
    } else if (im->data_uri) {
        bytes = im->data;
        size = im->size;
    } else if (!im->uri[0]) {
        return fail(l, LG_ERR_INVALID, "%s: neither a uri nor a bufferView", label);
    } else if (!l->g->base_dir[0]) {
        return fail(l, LG_ERR_INVALID,
                    "%s: cannot read it: the model was loaded from memory, without a folder for "
                    "external files",
                    label);
    } else {
        /* the same rules as buffers: regular, bounded, confined with links resolved on the
         * file opened (lightgraph/file.h); the uri was checked lexically by the parser */
        file = lg_file_read_within(l->g->base_dir, im->path, LG_GLTF_MAX_IMAGE_FILE, &size, why,
                                   sizeof why);
        if (!file)
            return fail(l, errno == ENOMEM ? LG_ERR_NOMEM : LG_ERR_INVALID,
                        "%s: cannot read it: %s", label, why);
        l->hash = fnv1a(l->hash, file, size);
        bytes = file;
    }
    uint32_t w = 0, h = 0;
    uint8_t *rgba = NULL;
    int rc = lg_gltf_image_decode(bytes, size, LG_GLTF_MAX_IMAGE_PIXELS, &w, &h, &rgba, why,
                                  sizeof why);
    free(file);
    if (rc)
        return fail(l, LG_ERR_INVALID, "%s: cannot decode it: %s", label, why);
    memset(out, 0, sizeof *out);
    out->width = w;
    out->height = h;
    out->rgba8 = rgba;
    const char *name = im->uri[0] ? im->uri : im->name[0] ? im->name : NULL;
    char fallback[64];
    snprintf(fallback, sizeof fallback, "image %u", i);
    out->name = keep(l, name ? name : fallback);
    return out->name ? 0 : fail(l, LG_ERR_NOMEM, "out of memory");
}

/* The scene's textures: every texture a material of the file references, renumbered in
 * the order of first use, and their images, decoded. Images and textures no material uses
 * are not read. Runs after the materials' maps are made (material_maps). */
static int make_textures(loader *l, uint32_t n_maps)
{
    const lg_gltf *g = l->g;
    store *st = l->st;
    int32_t *tex_map = malloc(((size_t)g->n_textures + 1) * sizeof *tex_map);
    int32_t *img_map = malloc(((size_t)g->n_images + 1) * sizeof *img_map);
    st->textures = calloc((size_t)g->n_textures + 1, sizeof *st->textures);
    st->images = calloc((size_t)g->n_images + 1, sizeof *st->images);
    st->n_image_slots = st->images ? g->n_images : 0;
    int rc = 0;
    if (!tex_map || !img_map || !st->textures || !st->images) {
        rc = fail(l, LG_ERR_NOMEM, "out of memory");
        goto done;
    }
    memset(tex_map, 0xff, ((size_t)g->n_textures + 1) * sizeof *tex_map);
    memset(img_map, 0xff, ((size_t)g->n_images + 1) * sizeof *img_map);
    uint32_t n_tex = 0, n_img = 0;
    for (uint32_t m = 0; m < n_maps && !rc; m++) {
        lg_texture_ref *refs[5] = { &st->maps[m].base_color, &st->maps[m].metallic_roughness,
                                    &st->maps[m].normal, &st->maps[m].occlusion,
                                    &st->maps[m].emissive };
        for (int k = 0; k < 5 && !rc; k++) {
            int32_t t = refs[k]->texture;
            if (t < 0)
                continue;
            if (tex_map[t] < 0) {
                const lg_gltf_texture *gt = &g->textures[t];
                if (gt->source == -1)
                    rc = fail(l, LG_ERR_UNSUPPORTED,
                              "texture %d has no source image (image extensions such as "
                              "KHR_texture_basisu are not supported)",
                              t);
                else if (gt->source < 0 || (uint32_t)gt->source >= g->n_images)
                    rc = fail(l, LG_ERR_INVALID,
                              "texture %d: image %d does not exist (the file has %u)", t,
                              gt->source, g->n_images);
                else if (gt->sampler < -1 ||
                         (gt->sampler >= 0 && (uint32_t)gt->sampler >= g->n_samplers))
                    rc = fail(l, LG_ERR_INVALID,
                              "texture %d: sampler %d does not exist (the file has %u)", t,
                              gt->sampler, g->n_samplers);
                if (rc)
                    break;
                lg_scene_texture *out = &st->textures[n_tex];
                if (gt->sampler >= 0) {
                    const lg_gltf_sampler *sm = &g->samplers[gt->sampler];
                    if (!valid_filter(sm->mag_filter, false) ||
                        !valid_filter(sm->min_filter, true) || !valid_wrap(sm->wrap_s) ||
                        !valid_wrap(sm->wrap_t)) {
                        rc = fail(l, LG_ERR_INVALID,
                                  "sampler %d: magFilter %d, minFilter %d, wrapS %d, wrapT %d: "
                                  "not all are glTF's values (9728, 9729, 9984..9987; 33071, "
                                  "33648, 10497)",
                                  gt->sampler, sm->mag_filter, sm->min_filter, sm->wrap_s,
                                  sm->wrap_t);
                        break;
                    }
                    out->mag_filter = sm->mag_filter < 0 ? 0 : (uint32_t)sm->mag_filter;
                    out->min_filter = sm->min_filter < 0 ? 0 : (uint32_t)sm->min_filter;
                    out->wrap_s = (uint32_t)sm->wrap_s;
                    out->wrap_t = (uint32_t)sm->wrap_t;
                }
                if (img_map[gt->source] < 0)
                    img_map[gt->source] = (int32_t)n_img++;
                out->image = (uint32_t)img_map[gt->source];
                tex_map[t] = (int32_t)n_tex++;
            }
            refs[k]->texture = tex_map[t];
        }
    }
    /* decode in the order of first use: image i of the file is scene image img_map[i] */
    uint64_t total = 0;
    for (uint32_t i = 0; i < g->n_images && !rc; i++) {
        if (img_map[i] < 0)
            continue;
        lg_scene_image *im = &st->images[img_map[i]];
        if ((rc = decode_image(l, i, im)))
            break;
        total += (uint64_t)im->width * im->height * 4;
        if (total > LG_GLTF_MAX_TEXTURE_BYTES) {
            char label[600];
            rc = fail(l, LG_ERR_INVALID,
                      "%s: the decoded images come to %" PRIu64 " MiB, more than the %" PRIu64
                      " MiB a model may hold",
                      image_label(l, i, label, sizeof label), total >> 20,
                      (uint64_t)LG_GLTF_MAX_TEXTURE_BYTES >> 20);
        }
    }
    if (!rc && n_tex) {
        st->tex.images = st->images;
        st->tex.n_images = n_img;
        st->tex.textures = st->textures;
        st->tex.n_textures = n_tex;
        st->tex.bytes = total;
        st->scene.textures = &st->tex;
    }
done:
    free(tex_map);
    free(img_map);
    return rc;
}

/* ---- lights, cameras, medium ----------------------------------------------------------------- */

static lg_vec3 world_point(const double w[16])
{
    return lg_v3((float)w[12], (float)w[13], (float)w[14]);
}

static lg_vec3 world_dir(const double w[16], double x, double y, double z, lg_vec3 fallback)
{
    return lg_v3_normalize_or(lg_v3((float)(w[0] * x + w[4] * y + w[8] * z),
                                    (float)(w[1] * x + w[5] * y + w[9] * z),
                                    (float)(w[2] * x + w[6] * y + w[10] * z)),
                              fallback);
}

static void set3(float out[3], lg_vec3 v)
{
    out[0] = v.x, out[1] = v.y, out[2] = v.z;
}

static int make_lights(loader *l)
{
    store *st = l->st;
    st->lights = calloc(l->n_lits + 1, sizeof *st->lights);
    if (!st->lights)
        return fail(l, LG_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < l->n_lits; i++) {
        const struct placed *pl = &l->lits[i];
        const lg_gltf_light *gl = &l->g->lights[pl->index];
        lg_light *o = &st->lights[st->n_lights];
        memset(o, 0, sizeof *o);
        char where[64];
        snprintf(where, sizeof where, "light %u (KHR_lights_punctual)", pl->index);
        if (!strcmp(gl->type, "directional"))
            o->type = LG_LIGHT_DIRECTIONAL;
        else if (!strcmp(gl->type, "point"))
            o->type = LG_LIGHT_POINT;
        else if (!strcmp(gl->type, "spot"))
            o->type = LG_LIGHT_SPOT;
        else
            return fail(l, LG_ERR_UNSUPPORTED,
                        "%s: type '%s' (supported: directional, point, spot)", where, gl->type);
        if (gl->n_color != 3 || !all_finite(gl->color, 3) || gl->color[0] < 0 || gl->color[1] < 0 ||
            gl->color[2] < 0)
            return fail(l, LG_ERR_INVALID, "%s: color must be 3 numbers >= 0", where);
        if (!(gl->intensity >= 0) || !isfinite(gl->intensity) || !(gl->range >= 0) ||
            !isfinite(gl->range))
            return fail(l, LG_ERR_INVALID, "%s: intensity %g and range %g must be finite and >= 0",
                        where, gl->intensity, gl->range);
        if (o->type == LG_LIGHT_SPOT && !(gl->inner_cone >= 0 && gl->inner_cone < gl->outer_cone &&
                                          gl->outer_cone <= LG_PI / 2 + 1e-9))
            return fail(l, LG_ERR_INVALID,
                        "%s: spot cone angles need 0 <= inner (%g) < outer (%g) <= pi/2", where,
                        gl->inner_cone, gl->outer_cone);
        char name[64];
        snprintf(name, sizeof name, "light %u", pl->index);
        o->name = keep(l, gl->name && *gl->name ? gl->name : name);
        if (!o->name)
            return fail(l, LG_ERR_NOMEM, "out of memory");
        for (int k = 0; k < 3; k++)
            o->color[k] = (float)gl->color[k];
        o->intensity = (float)gl->intensity;
        o->range = (float)gl->range;
        set3(o->position, world_point(pl->world));
        /* lights shine down their node's -Z (KHR_lights_punctual) */
        set3(o->direction, world_dir(pl->world, 0, 0, -1, lg_v3(0, 0, -1)));
        if (!isfinite(o->position[0] + o->position[1] + o->position[2]))
            return fail(l, LG_ERR_INVALID,
                        "node %u: the light's position overflows (beyond the float range)",
                        pl->node);
        if (o->type == LG_LIGHT_SPOT) {
            o->inner_cone = (float)gl->inner_cone;
            o->outer_cone = (float)gl->outer_cone;
        }
        st->n_lights++;
    }
    return 0;
}

/* World bounds of every instance (exactly, over vertices, unless that is more than 1e8
 * transforms: then over each mesh's transformed bounding box corners). */
static void scene_bounds(store *st)
{
    lg_scene *s = &st->scene;
    uint64_t work = 0;
    for (uint32_t i = 0; i < st->n_instances; i++)
        work += st->meshes[st->instances[i].mesh].n_vertices;
    bool exact = work <= 100000000u;
    float lo[3] = { FLT_MAX, FLT_MAX, FLT_MAX }, hi[3] = { -FLT_MAX, -FLT_MAX, -FLT_MAX };
    bool any = false;
    for (uint32_t i = 0; i < st->n_instances; i++) {
        const lg_instance *in = &st->instances[i];
        const lg_mesh *m = &st->meshes[in->mesh];
        if (!m->n_indices)
            continue;
        uint32_t n = exact ? m->n_vertices : 8;
        for (uint32_t v = 0; v < n; v++) {
            lg_vec3 p = exact ? lg_v3(m->positions[3 * (size_t)v], m->positions[3 * (size_t)v + 1],
                                      m->positions[3 * (size_t)v + 2])
                              : lg_v3(v & 1 ? m->bounds_max[0] : m->bounds_min[0],
                                      v & 2 ? m->bounds_max[1] : m->bounds_min[1],
                                      v & 4 ? m->bounds_max[2] : m->bounds_min[2]);
            p = lg_m4_point(in->model, p);
            float c[3] = { p.x, p.y, p.z };
            for (int k = 0; k < 3; k++) {
                lo[k] = fminf(lo[k], c[k]);
                hi[k] = fmaxf(hi[k], c[k]);
            }
            any = true;
        }
    }
    for (int k = 0; k < 3; k++) {
        s->bounds_min[k] = any ? lo[k] : 0;
        s->bounds_max[k] = any ? hi[k] : 0;
    }
}

/* Fraction of the bounding box's face at z = zface covered by triangles lying in that
 * plane (within 1% of the box's depth): is there a wall on that side? */
static double side_cover(const store *st, float zface)
{
    const lg_scene *s = &st->scene;
    double w = (double)s->bounds_max[0] - s->bounds_min[0],
           h = (double)s->bounds_max[1] - s->bounds_min[1];
    double tol = 0.01 * ((double)s->bounds_max[2] - s->bounds_min[2]);
    if (!(w > 0 && h > 0))
        return 0;
    double area = 0;
    for (uint32_t i = 0; i < st->n_instances; i++) {
        const lg_instance *in = &st->instances[i];
        const lg_mesh *m = &st->meshes[in->mesh];
        if (m->n_indices > 3u * 100000u)
            continue; /* walls are a few triangles; scanned meshes are not walls */
        for (uint32_t t = 0; t + 2 < m->n_indices; t += 3) {
            lg_vec3 p[3];
            bool in_plane = true;
            for (int k = 0; k < 3; k++) {
                uint32_t v = m->indices[t + k];
                p[k] = lg_m4_point(in->model, lg_v3(m->positions[3 * (size_t)v],
                                                    m->positions[3 * (size_t)v + 1],
                                                    m->positions[3 * (size_t)v + 2]));
                in_plane = in_plane && fabs((double)p[k].z - zface) <= tol;
            }
            if (in_plane) {
                lg_vec3 c = lg_v3_cross(lg_v3_sub(p[1], p[0]), lg_v3_sub(p[2], p[0]));
                area += 0.5 * fabs((double)c.z);
            }
        }
    }
    return area / (w * h);
}

/* The automatic camera (README.md, "Cameras"): looks along -Z at the bounds from the +Z
 * side (glTF's front), or from the -Z side when a wall closes +Z and -Z is open (rooms
 * such as the Cornell box), at a distance that fits the near face of the bounding box
 * into a 45-degree vertical field of view (and into as wide a horizontal one), plus 5%. */
static void auto_camera(const store *st, lg_camera *c)
{
    const lg_scene *s = &st->scene;
    memset(c, 0, sizeof *c);
    c->name = "auto";
    c->yfov = (float)(LG_PI / 4);
    c->up[1] = 1;
    float ctr[3], half[3];
    for (int k = 0; k < 3; k++) {
        ctr[k] = 0.5f * (s->bounds_min[k] + s->bounds_max[k]);
        half[k] = 0.5f * (s->bounds_max[k] - s->bounds_min[k]);
    }
    float extent = fmaxf(half[0], fmaxf(half[1], half[2]));
    if (!(extent > 0)) {
        /* nothing to frame: the unit view of the origin */
        c->position[2] = 1;
        c->znear = 0.01f;
        c->zfar = 100;
        return;
    }
    double front = side_cover(st, s->bounds_max[2]), back = side_cover(st, s->bounds_min[2]);
    float dir = (front > 0.5 && back < 0.5) ? -1.0f : 1.0f; /* the side the camera stands on */
    float t = tanf(c->yfov * 0.5f);
    float dist = 1.05f * fmaxf(half[0], half[1]) / t; /* from the near face */
    if (!(dist > 0))
        dist = extent / t;
    for (int k = 0; k < 3; k++)
        c->position[k] = c->target[k] = ctr[k];
    c->position[2] = ctr[2] + dir * (half[2] + dist);
    c->znear = 0.5f * dist;
    c->zfar = (dist + 2 * half[2]) * 1.5f + extent;
}

static int make_cameras(loader *l)
{
    store *st = l->st;
    st->cameras = calloc(l->n_cams + 1, sizeof *st->cameras);
    if (!st->cameras)
        return fail(l, LG_ERR_NOMEM, "out of memory");
    float ctr[3], radius = 0;
    for (int k = 0; k < 3; k++) {
        ctr[k] = 0.5f * (st->scene.bounds_min[k] + st->scene.bounds_max[k]);
        float h = 0.5f * (st->scene.bounds_max[k] - st->scene.bounds_min[k]);
        radius += h * h;
    }
    radius = sqrtf(radius);
    for (uint32_t i = 0; i < l->n_cams; i++) {
        const struct placed *pl = &l->cams[i];
        const lg_gltf_camera *gc = &l->g->cameras[pl->index];
        lg_camera *c = &st->cameras[st->n_cameras];
        memset(c, 0, sizeof *c);
        lg_vec3 pos = world_point(pl->world);
        lg_vec3 fwd = world_dir(pl->world, 0, 0, -1, lg_v3(0, 0, -1)); /* cameras look down -Z */
        lg_vec3 up = world_dir(pl->world, 0, 1, 0, lg_v3(0, 1, 0));
        /* the target: the point in front of the camera nearest the bounds' centre */
        float focus = lg_v3_dot(lg_v3_sub(lg_v3(ctr[0], ctr[1], ctr[2]), pos), fwd);
        if (!(focus > 1e-6f * (radius + 1e-30f)))
            focus = radius > 0 ? radius : 1;
        set3(c->position, pos);
        set3(c->target, lg_v3_add(pos, lg_v3_scale(fwd, focus)));
        set3(c->up, up);
        if (!isfinite(c->position[0] + c->position[1] + c->position[2] + c->target[0] +
                      c->target[1] + c->target[2]))
            return fail(l, LG_ERR_INVALID,
                        "node %u: the camera's position overflows (beyond the float range)",
                        pl->node);
        char name[64];
        snprintf(name, sizeof name, "camera %u", pl->index);
        c->name = keep(l, gc->name && *gc->name ? gc->name : name);
        if (!c->name)
            return fail(l, LG_ERR_NOMEM, "out of memory");
        if (!strcmp(gc->type, "perspective")) {
            if (!(gc->yfov > 0 && gc->yfov < LG_PI) || !(gc->znear > 0) || !isfinite(gc->znear) ||
                !(gc->zfar == 0 || (gc->zfar > gc->znear && isfinite(gc->zfar))))
                return fail(l, LG_ERR_INVALID,
                            "camera %u: yfov %g must be in (0, pi), znear %g > 0 and zfar %g "
                            "0 or > znear",
                            pl->index, gc->yfov, gc->znear, gc->zfar);
            c->yfov = (float)gc->yfov;
            c->znear = (float)gc->znear;
            c->zfar = (float)gc->zfar;
        } else if (!strcmp(gc->type, "orthographic")) {
            /* approximated by a perspective camera showing the same height at the focus */
            if (!(gc->ymag != 0 && isfinite(gc->ymag)) || !(gc->ortho_zfar > gc->ortho_znear) ||
                !(gc->ortho_znear >= 0) || !isfinite(gc->ortho_zfar))
                return fail(l, LG_ERR_INVALID,
                            "camera %u: orthographic ymag %g must be non-zero and 0 <= znear "
                            "%g < zfar %g",
                            pl->index, gc->ymag, gc->ortho_znear, gc->ortho_zfar);
            if (!l->warned_ortho) {
                l->warned_ortho = true;
                warn(
                    l,
                    "camera %u is orthographic: approximated by a perspective camera that shows the same "
                    "height (2 x ymag) at its target",
                    pl->index);
            }
            c->yfov = 2.0f * atanf((float)fabs(gc->ymag) / focus);
            c->znear = gc->ortho_znear > 0 ? (float)gc->ortho_znear : 0.01f * focus;
            c->zfar = (float)gc->ortho_zfar;
        } else {
            return fail(l, LG_ERR_UNSUPPORTED,
                        "camera %u: type '%s' (supported: perspective, orthographic)", pl->index,
                        gc->type);
        }
        c->aspect = 0; /* the output's (README.md, "Cameras") */
        st->n_cameras++;
    }
    auto_camera(st, &st->cameras[st->n_cameras++]);
    return 0;
}

/* extras.medium of the scene, else of the root object, else of the asset. */
static int make_medium(loader *l, int64_t scene)
{
    const lg_gltf *g = l->g;
    const lg_json *x = NULL;
    const char *where = NULL;
    char buf[64];
    if (scene >= 0 && (uint64_t)scene < g->n_scenes &&
        (x = lg_json_get(g->scenes[scene].extras, "medium"))) {
        snprintf(buf, sizeof buf, "scene %" PRId64 " extras.medium", scene);
        where = buf;
    } else if ((x = lg_json_get(g->extras, "medium"))) {
        where = "extras.medium";
    } else if ((x = lg_json_get(g->asset_extras, "medium"))) {
        where = "asset.extras.medium";
    }
    lg_medium *m = &l->st->scene.medium;
    memset(m, 0, sizeof *m);
    if (!x)
        return 0;
    if (x->type != LG_JSON_OBJECT)
        return fail(l, LG_ERR_INVALID,
                    "%s must be an object {density, scattering, absorption or extinction, g}",
                    where);
    static const char *const known[] = { "density", "scattering", "absorption", "extinction", "g" };
    for (uint32_t i = 0; i < x->n; i++) {
        bool ok = false;
        for (size_t k = 0; k < sizeof known / sizeof *known; k++)
            ok |= !strcmp(x->keys[i], known[k]);
        if (!ok)
            warn(
                l,
                "%s: unknown key '%s' ignored (known: density, scattering, absorption, extinction, g)",
                where, x->keys[i]);
    }
    double density = 1, g_ = 0, sc[3] = { 1, 1, 1 }, ab[3] = { 0, 0, 0 }, ex[3] = { 0, 0, 0 };
    const lg_json *jab = lg_json_get(x, "absorption"), *jex = lg_json_get(x, "extinction");
    int rc;
    if (jab && jex)
        return fail(l, LG_ERR_INVALID, "%s: give absorption or extinction, not both", where);
    if ((rc = json_number(l, where, "density", lg_json_get(x, "density"), 0, 1e30, &density)) ||
        (rc = json_number(l, where, "g", lg_json_get(x, "g"), -0.999999, 0.999999, &g_)) ||
        (rc = json_rgb(l, where, "scattering", lg_json_get(x, "scattering"), 0, 1e30, sc)) ||
        (rc = json_rgb(l, where, "absorption", jab, 0, 1e30, ab)) ||
        (rc = json_rgb(l, where, "extinction", jex, 0, 1e30, ex)))
        return rc;
    if (jex)
        for (int k = 0; k < 3; k++) {
            if (ex[k] < sc[k])
                return fail(l, LG_ERR_INVALID,
                            "%s: extinction[%d] = %g is less than scattering[%d] = %g", where, k,
                            ex[k], k, sc[k]);
            ab[k] = ex[k] - sc[k];
        }
    m->present = true;
    m->density = (float)density;
    m->g = (float)g_;
    for (int k = 0; k < 3; k++) {
        m->scattering[k] = (float)sc[k];
        m->absorption[k] = (float)ab[k];
    }
    return 0;
}

/* ---- the whole file -------------------------------------------------------------------------- */

/* ---- animations ------------------------------------------------------------------------------ */

/* The rest pose of node ni as TRS. A node given by a matrix is decomposed (glTF forbids
 * animating it, but it may be the parent of an animated node); a matrix that TRS cannot
 * hold (shear, a projection) is refused only when that node is an ancestor of an animated
 * one (*exact false). */
static void rest_trs(const lg_gltf_node *n, lg_anim_node *o, bool *exact)
{
    *exact = true;
    if (!n->n_matrix) {
        for (int k = 0; k < 3; k++) {
            o->translation[k] = n->n_translation ? (float)n->translation[k] : 0.0f;
            o->scale[k] = n->n_scale ? (float)n->scale[k] : 1.0f;
        }
        double q[4] = { 0, 0, 0, 1 }, len = 0;
        if (n->n_rotation)
            memcpy(q, n->rotation, sizeof q);
        for (int k = 0; k < 4; k++)
            len += q[k] * q[k];
        len = len > 0 ? sqrt(len) : 1;
        for (int k = 0; k < 4; k++)
            o->rotation[k] = (float)(q[k] / len);
        return;
    }
    const double *m = n->matrix;
    double c[3][3], s[3];
    for (int j = 0; j < 3; j++) {
        s[j] =
            sqrt(m[j * 4] * m[j * 4] + m[j * 4 + 1] * m[j * 4 + 1] + m[j * 4 + 2] * m[j * 4 + 2]);
        for (int r = 0; r < 3; r++)
            c[j][r] = s[j] > 0 ? m[j * 4 + r] / s[j] : (r == j);
    }
    /* a mirror: the sign goes into the x scale */
    double det = c[0][0] * (c[1][1] * c[2][2] - c[2][1] * c[1][2]) -
                 c[1][0] * (c[0][1] * c[2][2] - c[2][1] * c[0][2]) +
                 c[2][0] * (c[0][1] * c[1][2] - c[1][1] * c[0][2]);
    if (det < 0) {
        s[0] = -s[0];
        for (int r = 0; r < 3; r++)
            c[0][r] = -c[0][r];
    }
    /* rotation matrix (columns c[j]) to a quaternion (Shepperd's method) */
    double r00 = c[0][0], r11 = c[1][1], r22 = c[2][2], q[4];
    double tr = r00 + r11 + r22;
    if (tr > 0) {
        double k = 2 * sqrt(tr + 1);
        q[3] = 0.25 * k, q[0] = (c[1][2] - c[2][1]) / k, q[1] = (c[2][0] - c[0][2]) / k,
        q[2] = (c[0][1] - c[1][0]) / k;
    } else if (r00 > r11 && r00 > r22) {
        double k = 2 * sqrt(1 + r00 - r11 - r22);
        q[3] = (c[1][2] - c[2][1]) / k, q[0] = 0.25 * k, q[1] = (c[1][0] + c[0][1]) / k,
        q[2] = (c[2][0] + c[0][2]) / k;
    } else if (r11 > r22) {
        double k = 2 * sqrt(1 + r11 - r00 - r22);
        q[3] = (c[2][0] - c[0][2]) / k, q[0] = (c[1][0] + c[0][1]) / k, q[1] = 0.25 * k,
        q[2] = (c[2][1] + c[1][2]) / k;
    } else {
        double k = 2 * sqrt(1 + r22 - r00 - r11);
        q[3] = (c[0][1] - c[1][0]) / k, q[0] = (c[2][0] + c[0][2]) / k,
        q[1] = (c[2][1] + c[1][2]) / k, q[2] = 0.25 * k;
    }
    for (int k = 0; k < 3; k++) {
        o->translation[k] = (float)m[12 + k];
        o->scale[k] = (float)s[k];
    }
    for (int k = 0; k < 4; k++)
        o->rotation[k] = (float)q[k];
    /* does T R S give the matrix back? (shear and projections do not survive) */
    double scale = 1e-30;
    for (int k = 0; k < 16; k++)
        scale = fmax(scale, fabs(m[k]));
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double rm[9] = { 1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                     2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                     2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y) };
    for (int j = 0; j < 3; j++)
        for (int r = 0; r < 3; r++)
            if (fabs(rm[j * 3 + r] * s[j] - m[j * 4 + r]) > 1e-5 * scale)
                *exact = false;
    if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1)
        *exact = false;
}

static const char *interp_name(lg_anim_interp i)
{
    return i == LG_ANIM_STEP ? "STEP" : i == LG_ANIM_CUBICSPLINE ? "CUBICSPLINE" : "LINEAR";
}

/* Keeps a channel's array (times or values) with the scene. */
static int keep_array(loader *l, float *a)
{
    store *st = l->st;
    float **p = realloc(st->anim_arrays, (st->n_anim_arrays + 1) * sizeof *p);
    if (!p) {
        free(a);
        return fail(l, LG_ERR_NOMEM, "out of memory");
    }
    st->anim_arrays = p;
    p[st->n_anim_arrays++] = a;
    return 0;
}

/* Channel c of animation ai: checked (target, path, interpolation, accessor types and
 * counts, key times strictly increasing, finite and >= 0, finite values) and copied into
 * *o. `where` names the animation and the channel. Returns 0, 1 for a channel to skip (no
 * target node: glTF leaves it to an extension), or an error. */
static int read_channel(loader *l, const lg_gltf_animation *ga, uint32_t c, const char *where,
                        lg_anim_channel *o)
{
    const lg_gltf *g = l->g;
    const lg_gltf_anim_channel *ch = &ga->channels[c];
    if (ch->node < 0) {
        warn(l, "%s: no target node; the channel is ignored", where);
        return 1;
    }
    if ((uint32_t)ch->node >= g->n_nodes)
        return fail(l, LG_ERR_INVALID, "%s: target node %d does not exist (the file has %u)", where,
                    ch->node, g->n_nodes);
    const char *path = ch->path ? ch->path : "";
    if (!strcmp(path, "weights"))
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: animates the morph-target weights of node %d; morph targets are not "
                    "supported (only rigid node animation: translation, rotation, scale)",
                    where, ch->node);
    if (!strcmp(path, "translation"))
        o->path = LG_ANIM_TRANSLATION;
    else if (!strcmp(path, "rotation"))
        o->path = LG_ANIM_ROTATION;
    else if (!strcmp(path, "scale"))
        o->path = LG_ANIM_SCALE;
    else
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: target path '%s' (supported: translation, rotation, scale)", where, path);
    for (uint32_t s = 0; s < g->n_skins; s++)
        for (uint32_t j = 0; j < g->skins[s].n_joints; j++)
            if (g->skins[s].joints[j] == ch->node)
                return fail(l, LG_ERR_UNSUPPORTED,
                            "%s: animates node %d, a joint of skin %u: skinned animation is "
                            "not supported (only rigid node animation)",
                            where, ch->node, s);
    if (g->nodes[ch->node].n_matrix)
        return fail(l, LG_ERR_INVALID,
                    "%s: animates node %d, which is given by a matrix (glTF 2.0 forbids "
                    "animating such a node: give it translation, rotation and scale)",
                    where, ch->node);
    if (ch->sampler < 0 || (uint32_t)ch->sampler >= ga->n_samplers)
        return fail(l, LG_ERR_INVALID, "%s: sampler %d does not exist (the animation has %u)",
                    where, ch->sampler, ga->n_samplers);
    const lg_gltf_anim_sampler *sm = &ga->samplers[ch->sampler];
    const char *ip = sm->interpolation ? sm->interpolation : "LINEAR";
    if (!strcmp(ip, "LINEAR") || !*ip)
        o->interpolation = LG_ANIM_LINEAR;
    else if (!strcmp(ip, "STEP"))
        o->interpolation = LG_ANIM_STEP;
    else if (!strcmp(ip, "CUBICSPLINE"))
        o->interpolation = LG_ANIM_CUBICSPLINE;
    else
        return fail(l, LG_ERR_UNSUPPORTED,
                    "%s: interpolation '%s' (supported: LINEAR, STEP, CUBICSPLINE)", where, ip);
    o->node = (uint32_t)ch->node;
    char what[256];
    snprintf(what, sizeof what, "%s, input (key times)", where);
    float *times = NULL, *values = NULL;
    uint32_t n = 0, nv = 0;
    int rc = read_accessor(l, sm->input, what, 1, 1u << (CT_FLOAT - CT_BYTE), OUT_FLOAT,
                           (void **)&times, &n);
    if (rc)
        return rc;
    if ((rc = keep_array(l, times)))
        return rc;
    if (n == 0)
        return fail(l, LG_ERR_INVALID, "%s: the sampler has no keys (input accessor %d)", where,
                    sm->input);
    for (uint32_t k = 0; k < n; k++) {
        if (!isfinite(times[k]) || times[k] < 0)
            return fail(l, LG_ERR_INVALID,
                        "%s: key time %u is %g: key times must be finite and >= 0 seconds", where,
                        k, times[k]);
        if (k > 0 && !(times[k] > times[k - 1]))
            return fail(l, LG_ERR_INVALID,
                        "%s: key times must strictly increase, but key %u (%g s) does not "
                        "follow key %u (%g s)",
                        where, k, times[k], k - 1, times[k - 1]);
    }
    uint32_t comps = o->path == LG_ANIM_ROTATION ? 4 : 3;
    /* rotations may be normalized integers (glTF 2.0, 3.11), the others only floats */
    unsigned types = 1u << (CT_FLOAT - CT_BYTE);
    if (o->path == LG_ANIM_ROTATION) {
        int32_t oa = sm->output;
        bool intnorm = oa >= 0 && (uint32_t)oa < g->n_accessors &&
                       g->accessors[oa].component_type != CT_FLOAT;
        if (intnorm && !g->accessors[oa].normalized)
            return fail(l, LG_ERR_INVALID,
                        "%s: output accessor %d holds rotations as integers that are not "
                        "normalized (glTF 2.0 allows floats or normalized integers)",
                        where, oa);
        types |= 1u << (CT_BYTE - CT_BYTE) | 1u << (CT_UBYTE - CT_BYTE) |
                 1u << (CT_SHORT - CT_BYTE) | 1u << (CT_USHORT - CT_BYTE);
    }
    snprintf(what, sizeof what, "%s, output (%s values)", where, path);
    if ((rc = read_accessor(l, sm->output, what, comps, types, OUT_FLOAT, (void **)&values, &nv)))
        return rc;
    if ((rc = keep_array(l, values)))
        return rc;
    uint32_t per = o->interpolation == LG_ANIM_CUBICSPLINE ? 3 : 1;
    if ((uint64_t)nv != (uint64_t)n * per)
        return fail(l, LG_ERR_INVALID,
                    "%s: %u key times need %" PRIu64 " output values with %s interpolation, "
                    "the output accessor %d has %u",
                    where, n, (uint64_t)n * per, interp_name(o->interpolation), sm->output, nv);
    for (uint64_t k = 0; k < (uint64_t)nv * comps; k++)
        if (!isfinite(values[k]))
            return fail(l, LG_ERR_INVALID,
                        "%s: output value %" PRIu64 " (component %" PRIu64
                        ") is not a finite number",
                        where, k / comps, k % comps);
    o->n_keys = n;
    o->times = times;
    o->values = values;
    return 0;
}

/* lg_scene.animation from the animation the options choose: the node tree (every glTF node,
 * its parent and rest TRS), the channels, and the nodes that place each instance, light
 * and camera. Skins and morph targets are refused when the animation moves them; a file
 * without animations (or animation -1) gives a scene without one. */
static int make_animation(loader *l)
{
    const lg_gltf *g = l->g;
    store *st = l->st;
    int64_t ai = l->opt->animation;
    if (ai < 0 || (ai == 0 && g->n_animations == 0))
        return 0;
    if ((uint64_t)ai >= g->n_animations)
        return fail(l, LG_ERR_INVALID, "animation %" PRId64 " does not exist (the file has %u)", ai,
                    g->n_animations);
    const lg_gltf_animation *ga = &g->animations[ai];
    char label[96];
    snprintf(label, sizeof label, "animation %" PRId64, ai);
    st->anim.name = keep(l, ga->name && *ga->name ? ga->name : label);
    uint32_t nn = g->n_nodes;
    st->anim_nodes = calloc((size_t)nn + 1, sizeof *st->anim_nodes);
    st->anim_channels = calloc((size_t)ga->n_channels + 1, sizeof *st->anim_channels);
    st->light_node = calloc((size_t)st->n_lights + 1, sizeof *st->light_node);
    st->camera_node = calloc((size_t)st->n_cameras + 1, sizeof *st->camera_node);
    if (!st->anim.name || !st->anim_nodes || !st->anim_channels || !st->light_node ||
        !st->camera_node)
        return fail(l, LG_ERR_NOMEM, "out of memory");
    uint32_t nc = 0;
    double duration = 0;
    for (uint32_t c = 0; c < ga->n_channels; c++) {
        char where[160];
        snprintf(where, sizeof where, "animation %" PRId64 " ('%s'), channel %u", ai, st->anim.name,
                 c);
        int rc = read_channel(l, ga, c, where, &st->anim_channels[nc]);
        if (rc < 0 || rc > 1)
            return rc;
        if (rc == 0) {
            const lg_anim_channel *ch = &st->anim_channels[nc++];
            duration = fmax(duration, ch->times[ch->n_keys - 1]);
            st->anim_nodes[ch->node].animated = 1;
        }
    }
    /* rest TRS, and `animated` carried down to descendants (an ancestor's flag) */
    for (uint32_t i = 0; i < nn; i++) {
        lg_anim_node *o = &st->anim_nodes[i];
        o->parent = (int32_t)l->parent[i];
        bool exact;
        rest_trs(&g->nodes[i], o, &exact);
        (void)exact;
    }
    for (uint32_t i = 0; i < nn; i++) {
        if (st->anim_nodes[i].animated != 1)
            continue;
        for (int64_t p = l->parent[i]; p >= 0; p = l->parent[p]) {
            bool exact;
            lg_anim_node tmp;
            rest_trs(&g->nodes[p], &tmp, &exact);
            if (!exact)
                return fail(l, LG_ERR_UNSUPPORTED,
                            "animation %" PRId64 " ('%s') moves node %u, whose ancestor node "
                            "%" PRId64 " has a matrix that translation, rotation and scale "
                            "cannot express (shear or projection)",
                            ai, st->anim.name, i, p);
        }
    }
    for (uint32_t i = 0; i < nn; i++) {
        if (st->anim_nodes[i].animated)
            continue;
        for (int64_t p = l->parent[i]; p >= 0; p = l->parent[p])
            if (st->anim_nodes[p].animated == 1) {
                st->anim_nodes[i].animated = 2;
                break;
            }
    }
    for (uint32_t i = 0; i < nn; i++)
        st->anim_nodes[i].animated = st->anim_nodes[i].animated != 0;
    for (uint32_t i = 0; i < st->n_lights && i < l->n_lits; i++)
        st->light_node[i] = st->anim_nodes[l->lits[i].node].animated ? (int32_t)l->lits[i].node
                                                                     : -1;
    for (uint32_t i = 0; i < st->n_cameras; i++)
        st->camera_node[i] = i < l->n_cams && st->anim_nodes[l->cams[i].node].animated
                                 ? (int32_t)l->cams[i].node
                                 : -1;
    if (nc == 0) { /* every channel skipped: nothing moves */
        free(st->anim_channels);
        st->anim_channels = NULL;
        return 0;
    }
    st->anim.duration = duration;
    st->anim.nodes = st->anim_nodes;
    st->anim.n_nodes = nn;
    st->anim.channels = st->anim_channels;
    st->anim.n_channels = nc;
    st->anim.instance_node = st->inst_node;
    st->anim.light_node = st->light_node;
    st->anim.camera_node = st->camera_node;
    return 0;
}

/* Extensions the loader implements or may ignore without drawing the scene wrongly. */
static const char *const supported_required[] = {
    "KHR_draco_mesh_compression",      "KHR_lights_punctual", "KHR_mesh_quantization",
    "KHR_materials_emissive_strength", "KHR_materials_ior",   "KHR_materials_specular",
    "KHR_texture_transform",
};

static uint64_t fnv1a(uint64_t h, const uint8_t *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

lg_gltf_options lg_gltf_default_options(void)
{
    lg_gltf_options o;
    memset(&o, 0, sizeof o);
    o.normals = LG_GLTF_NORMALS_AUTO;
    o.crease_deg = 60;
    o.scene = -1;
    o.camera = -1;
    o.animation = 0;
    return o;
}

/* Meshes flagged by mesh_tangents (a normal texture reading texture coordinates they lack)
 * get a copy of their material without the normal map, appended after the others (one
 * copy per material; build made the slots); the other meshes keep the original. */
static int split_materials(loader *l, uint32_t *n_materials)
{
    store *st = l->st;
    const uint32_t n_file = l->g->n_materials;
    uint32_t *copy_of = calloc((size_t)n_file + 1, sizeof *copy_of); /* copy + 1, 0 = none */
    if (!copy_of)
        return fail(l, LG_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < st->n_meshes; i++) {
        uint32_t orig = st->meshes[i].material;
        if (!l->mesh_no_normal_map[i] || orig >= n_file)
            continue;
        if (!copy_of[orig]) {
            uint32_t c = (*n_materials)++;
            st->materials[c] = st->materials[orig];
            st->maps[c] = st->maps[orig];
            st->maps[c].normal = lg_material_maps_default()->normal;
            st->materials[c].maps = &st->maps[c];
            copy_of[orig] = c + 1;
        }
        st->meshes[i].material = copy_of[orig] - 1;
    }
    free(copy_of);
    return 0;
}

static int build(loader *l)
{
    const lg_gltf *g = l->g;
    for (uint32_t i = 0; i < g->n_extensions_required; i++) {
        bool ok = false;
        for (size_t k = 0; k < sizeof supported_required / sizeof *supported_required; k++)
            ok |= !strcmp(g->extensions_required[i], supported_required[k]);
        if (!ok)
            return fail(l, LG_ERR_UNSUPPORTED,
                        "requires extension '%s', which this loader does not support",
                        g->extensions_required[i]);
    }
    int64_t *parent = malloc(((size_t)g->n_nodes + 1) * sizeof *parent);
    l->prim_mesh = calloc(g->n_meshes + 1, sizeof *l->prim_mesh);
    if (!parent || !l->prim_mesh) {
        free(parent);
        return fail(l, LG_ERR_NOMEM, "out of memory");
    }
    for (uint32_t i = 0; i < g->n_meshes; i++) {
        l->prim_mesh[i] = malloc(((size_t)g->meshes[i].n_primitives + 1) * sizeof **l->prim_mesh);
        if (!l->prim_mesh[i]) {
            free(parent);
            return fail(l, LG_ERR_NOMEM, "out of memory");
        }
        for (uint32_t p = 0; p < g->meshes[i].n_primitives; p++)
            l->prim_mesh[i][p] = -1;
    }
    l->parent = parent; /* freed by lg_gltf_load_memory */
    int rc = check_tree(l, parent);
    if (!rc)
        rc = walk(l, parent);
    if (rc)
        return rc;

    store *st = l->st;
    lg_scene *s = &st->scene;
    /* materials: the file's, then the default one where a primitive names none, then
     * copies without their normal map for meshes that cannot use it (split_materials) */
    bool need_default = *l->material_used_default || g->n_materials == 0;
    uint32_t n_flagged = 0;
    for (uint32_t i = 0; i < st->n_meshes; i++)
        n_flagged += l->mesh_no_normal_map[i];
    size_t slots = (size_t)g->n_materials + 1 + n_flagged;
    st->materials = calloc(slots, sizeof *st->materials);
    st->maps = calloc(slots, sizeof *st->maps);
    if (!st->materials || !st->maps)
        return fail(l, LG_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < g->n_materials; i++) {
        bool any = false;
        if ((rc = map_material(l, i, &st->materials[i])) ||
            (rc = material_maps(l, i, &st->maps[i], &any)))
            return rc;
        if (any)
            st->materials[i].maps = &st->maps[i];
    }
    if (need_default)
        default_material(&st->materials[g->n_materials]);
    if ((rc = make_textures(l, g->n_materials)))
        return rc;
    uint32_t n_materials = g->n_materials + (need_default ? 1 : 0);
    if ((rc = split_materials(l, &n_materials)))
        return rc;

    scene_bounds(st);
    for (int k = 0; k < 3; k++)
        if (!(fabsf(s->bounds_min[k]) <= 1e30f) || !(fabsf(s->bounds_max[k]) <= 1e30f))
            return fail(l, LG_ERR_INVALID,
                        "the scene's world bounds (%g .. %g on axis %d) go beyond +-1e30: "
                        "positions or node transforms out of any sensible range",
                        s->bounds_min[k], s->bounds_max[k], k);
    int64_t si = l->opt->scene >= 0      ? l->opt->scene
                 : g->default_scene >= 0 ? g->default_scene
                 : g->n_scenes           ? 0
                                         : -1;
    if ((rc = make_lights(l)) || (rc = make_cameras(l)) || (rc = make_medium(l, si)) ||
        (rc = make_animation(l)))
        return rc;
    int64_t cam = l->opt->camera < 0 ? 0 : l->opt->camera;
    if ((uint64_t)cam >= st->n_cameras)
        return fail(l, LG_ERR_INVALID,
                    "camera %" PRId64 " does not exist: the scene has %u (%u from the file, then "
                    "the automatic one)",
                    cam, st->n_cameras, st->n_cameras - 1);

    s->struct_size = sizeof(lg_scene);
    s->meshes = st->meshes;
    s->n_meshes = st->n_meshes;
    s->instances = st->instances;
    s->n_instances = st->n_instances;
    s->materials = st->materials;
    s->n_materials = n_materials;
    s->lights = st->lights;
    s->n_lights = st->n_lights;
    s->cameras = st->cameras;
    s->n_cameras = st->n_cameras;
    s->camera = (uint32_t)cam;
    s->geometry = NULL;
    s->animation = st->anim_channels ? &st->anim : NULL;
    lg_scene_compute_features(s);
    return 0;
}

int lg_gltf_load_memory(const uint8_t *bytes, size_t size, const char *name, const char *base_dir,
                        const lg_gltf_options *opt, lg_scene **out, uint64_t *content_hash,
                        char *err, size_t err_size)
{
    *out = NULL;
    lg_gltf_options defaults = lg_gltf_default_options();
    loader l;
    memset(&l, 0, sizeof l);
    l.file = name;
    l.opt = opt ? opt : &defaults;
    l.err = err;
    l.err_size = err_size;
    if (err && err_size)
        err[0] = 0;
    if (!(l.opt->crease_deg >= 0 && l.opt->crease_deg <= 180))
        return fail(&l, LG_ERR_INVALID, "crease angle %g is not in [0, 180] degrees",
                    l.opt->crease_deg);

    /* what the bytes are: GLB by its magic, else JSON text */
    size_t at = size >= 3 && !memcmp(bytes, "\xEF\xBB\xBF", 3) ? 3
                                                               : 0; /* a UTF-8 byte order mark */
    while (at < size &&
           (bytes[at] == ' ' || bytes[at] == '\t' || bytes[at] == '\r' || bytes[at] == '\n'))
        at++;
    bool glb = size >= 4 && !memcmp(bytes, "glTF", 4);
    size_t nlen = strlen(name);
    bool glb_name = nlen >= 4 && !strcasecmp(name + nlen - 4, ".glb");
    if (!glb && glb_name)
        return fail(&l, LG_ERR_INVALID, "not a GLB file: it starts with %s, not the magic 'glTF'",
                    size >= 4 ? "other bytes" : "fewer than 4 bytes");
    if (!glb && !(at < size && bytes[at] == '{'))
        return fail(&l, LG_ERR_INVALID,
                    "neither a GLB file (magic 'glTF') nor glTF JSON (a '{' first)");

    char perr[1536];
    const lg_gltf *g = NULL;
    lg_gltf_doc *doc = lg_gltf_parse(bytes, size, base_dir, &g, perr, sizeof perr);
    if (!doc)
        return fail(&l, LG_ERR_INVALID, "%s", perr);
    l.g = g;
    if (g->warnings && *g->warnings)
        warn(&l, "tinygltf: %s", g->warnings);

    /* the content hash: the file, its buffers, then (make_textures) every image file read */
    l.hash = fnv1a(0xcbf29ce484222325ull, bytes, size);
    for (uint32_t i = 0; i < g->n_buffers; i++)
        l.hash = fnv1a(l.hash, g->buffers[i].data, g->buffers[i].size);

    bool used_default = false;
    l.material_used_default = &used_default;
    l.st = calloc(1, sizeof *l.st);
    int rc;
    if (!l.st)
        rc = fail(&l, LG_ERR_NOMEM, "out of memory");
    else if (!(l.st->scene.source = keep(&l, name)))
        rc = fail(&l, LG_ERR_NOMEM, "out of memory");
    else
        rc = build(&l);

    if (l.prim_mesh)
        for (uint32_t i = 0; i < g->n_meshes; i++)
            free(l.prim_mesh[i]);
    free(l.prim_mesh);
    free(l.cams);
    free(l.lits);
    free(l.mesh_no_normal_map);
    free(l.parent);
    lg_gltf_doc_free(doc);
    if (rc) {
        lg_gltf_scene_free(l.st ? &l.st->scene : NULL);
        return rc;
    }
    *out = &l.st->scene;
    if (content_hash)
        *content_hash = l.hash;
    return 0;
}

int lg_gltf_load(const char *path, const lg_gltf_options *opt, lg_scene **out,
                 uint64_t *content_hash, char *err, size_t err_size)
{
    *out = NULL;
    /* bounded: a FIFO, a device or a file over the limit is refused before a byte is read */
    char why[256];
    size_t size = 0;
    uint8_t *bytes = lg_file_read(path, LG_GLTF_MAX_FILE, &size, why, sizeof why);
    if (!bytes) {
        int e = errno;
        snprintf(err, err_size, "file '%s': cannot read it: %s", path, why);
        return e == ENOENT   ? LG_ERR_NOTFOUND
               : e == EFBIG  ? LG_ERR_INVALID
               : e == ENOMEM ? LG_ERR_NOMEM
                             : LG_ERR_IO;
    }
    /* External buffers and images resolve against, and must stay inside, the folder of the
     * path as given (a link to the file does not move its folder), links resolved. */
    char *dir = strdup(path), *base = NULL;
    if (dir) {
        char *slash = strrchr(dir, '/');
        if (slash == dir)
            slash[1] = 0; /* "/file.glb": the root */
        else if (slash)
            *slash = 0;
        base = realpath(slash ? dir : ".", NULL);
    }
    int rc;
    if (!base) {
        int e = errno;
        snprintf(err, err_size, "file '%s': its folder cannot be resolved: %s", path,
                 dir ? strerror(e) : "out of memory");
        rc = LG_ERR_IO;
    } else {
        rc = lg_gltf_load_memory(bytes, size, path, base, opt, out, content_hash, err, err_size);
    }
    free(base);
    free(dir);
    free(bytes);
    return rc;
}
