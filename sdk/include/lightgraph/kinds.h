/*
 * lightgraph/kinds.h: what each resource kind is made of (since ABI 2.0).
 *
 * A composite resource (shadow map, probe, SH coefficients, per-vertex transfer, froxel
 * volume) is made of named parts. Each part is an image (2D or cube, with mip levels), a
 * 3D volume, a buffer, or a small metadata struct (a buffer of at most LG_META_MAX bytes
 * holding a plain struct the kind's header defines). Each part has its own residency on
 * CPU, GL and CL, exactly like a single image or buffer: it is allocated on the device
 * where it is first mapped and copied only when a consumer on another device reads it,
 * and both are counted in the profile against the node that caused them.
 *
 * The parts of every kind are declared here, as data, once: the producer declares them
 * (lg_declare_composite, or the kind's own lg_<kind>_declare helper), consumers reach
 * them with lg_part(node, resource, "name") or the kind's accessor, and the host uses the
 * same table to check graph files: a reference `NODE.PART` (for example `shadow.atlas`)
 * reads one part of a node's composite output, so `output shadow.atlas "atlas.exr"` or
 * `image = shadow.atlas` are edges the planner sees, and `--explain` and `dot` show them.
 *
 *   kind       part         type    required  what (the kind's header says more)
 *   shadowmap  atlas        image   yes       depth-only atlas, one tile per light
 *              lights       buffer  yes       lg_shadow_light[n_lights]
 *              info         meta    yes       lg_shadowmap_info
 *   probe      radiance     image   yes       2D (lat-long, angular) or cube, mip chain
 *              solid_angle  buffer  no        float per texel of level 0 (steradians)
 *              info         meta    yes       lg_probe_info: layout, rotation, scale
 *   sh         coeffs       buffer  yes       float[3][n^2]: R, G, B planes
 *              info         meta    yes       lg_sh_info: bands
 *   transfer   transfer     buffer  yes       float[vertices][3][n^2]
 *              info         meta    yes       lg_transfer_info: bands, vertices, mode
 *   froxel     grid         volume  yes       rgb in-scattered radiance, a transmittance
 *              info         meta    yes       lg_froxel_info: slice map, matrices
 *
 * Names are [a-z][a-z0-9_]* and never equal an output port's name of a node that has a
 * port of that kind, so `NODE.NAME` is never ambiguous.
 */
#ifndef LIGHTGRAPH_KINDS_H
#define LIGHTGRAPH_KINDS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/config.h"
#include "lightgraph/types.h"
#include "lightgraph/host.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lg_part_decl {
    const char *name;
    lg_part_type type;
    bool optional;   /* a producer may leave it out */
    const char *doc; /* one line */
    void *reserved[2];
} lg_part_decl;

typedef struct lg_kind_desc {
    lg_resource_kind kind;
    const char *name;          /* as graph files, messages and `lightgraph plugins` name it */
    const char *doc;           /* one line */
    const lg_part_decl *parts; /* NULL and 0 for kinds that are not composite */
    uint32_t n_parts;
    void *reserved[4];
} lg_kind_desc;

/* The description of `kind`, or NULL for a value outside the enum. Static data. */
LG_API const lg_kind_desc *lg_kind_describe(lg_resource_kind kind);
/* Its name ("image", "shadowmap", ...), "?" outside the enum. */
LG_API const char *lg_kind_name(lg_resource_kind kind);
/* How a message names the kind in a sentence, with its article: "an image", "a shadow
 * map", "SH coefficients", "any resource" (for LG_KIND_ANY); "an unknown kind of resource"
 * outside the enum. The graph checker's messages use it ("input 'image' of node 'tone'
 * takes an image, but 'sc' gives a scene"). A header function, not a library symbol (it
 * adds nothing to the ABI); the kinds are those of the table lg_kind_describe reads. */
static inline const char *lg_kind_phrase(lg_resource_kind kind)
{
    switch (kind) {
    case LG_KIND_ANY: return "any resource";
    case LG_KIND_IMAGE: return "an image";
    case LG_KIND_BUFFER: return "a buffer";
    case LG_KIND_VOLUME: return "a volume";
    case LG_KIND_SCENE: return "a scene";
    case LG_KIND_SHADOWMAP: return "a shadow map";
    case LG_KIND_PROBE: return "a light probe";
    case LG_KIND_SH: return "SH coefficients";
    case LG_KIND_TRANSFER: return "transfer vectors";
    case LG_KIND_FROXEL: return "a froxel volume";
    default: return "an unknown kind of resource";
    }
}
/* True for kinds made of parts. */
LG_API bool lg_kind_is_composite(lg_resource_kind kind);
/* Index of the part called `name` in the kind's table, or -1. */
LG_API int32_t lg_kind_part_index(lg_resource_kind kind, const char *name);

/* The metadata struct of a composite resource's META part, read and written on the CPU.
 * The structs the kind headers define all start with a uint32_t struct_size.
 * lg_meta_write (producer, execute()): copies `size` bytes into part `part` of the
 * node's own output `res` (size at most the part's declared size).
 * lg_meta_read (consumer): the part's CPU copy, host-owned and read-only, valid as long
 * as `res`; NULL after lg_error when the part is missing, smaller than `size`, or its
 * struct_size is smaller than `size` (written by an older producer). */
LG_API int lg_meta_write(lg_node *node, const lg_resource *res, const char *part, const void *data,
                         size_t size);
LG_API const void *lg_meta_read(lg_node *node, const lg_resource *res, const char *part,
                                size_t size);

#ifdef __cplusplus
}
#endif
#endif
