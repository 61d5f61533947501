/*
 * tests/common/testtextures.h: textures on a scene built with testscene.h, for test plugins
 * that need textured materials without a glTF file (the ibl and prt tests). Header-only:
 * each test plugin compiles its own copy.
 *
 *   lg_ts_builder *b = lg_ts_begin("...");  ... meshes, materials ...
 *   lg_tt_scene *ts = lg_tt_wrap(lg_ts_finish(b));        // NULL: out of memory
 *   uint32_t img = lg_tt_image(ts, "two halves", 2, 1, rgba8);   // pixels copied
 *   lg_material_maps *mm = lg_tt_maps(ts, 0);             // material 0's maps (defaults)
 *   mm->base_color.texture = (int32_t)lg_tt_texture(ts, img, LG_TEX_NEAREST, LG_TEX_CLAMP_TO_EDGE);
 *   lg_tt_planar_uv(ts, 0, ...)                           // texcoords for mesh 0
 *   return lg_tt_publish(n, 0, ts);                       // features recomputed
 *
 * Ownership: lg_tt_wrap takes the finished scene (freed with the wrapper); the published
 * payload is the wrapper's own lg_scene, a copy of the builder's whose meshes and materials
 * arrays are the wrapper's (texcoords and maps added), the rest still the builder's.
 */
#ifndef LG_TEST_TEXTURES_H
#define LG_TEST_TEXTURES_H

#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"

#include "common/testscene.h"

#define LG_TT_MAX 8

typedef struct lg_tt_scene {
    lg_scene s; /* first: the payload */
    lg_scene *inner;
    lg_mesh *meshes;
    lg_material *materials;
    lg_material_maps *maps; /* per material */
    float **uv, **tangents; /* per mesh, malloc'd or NULL */
    lg_scene_textures textures;
    lg_scene_image images[LG_TT_MAX];
    lg_scene_texture texs[LG_TT_MAX];
    uint8_t *pixels[LG_TT_MAX];
} lg_tt_scene;

static inline void lg_tt_free(void *p)
{
    lg_tt_scene *t = p;
    if (!t)
        return;
    for (uint32_t i = 0; t->uv && i < t->s.n_meshes; i++)
        free(t->uv[i]);
    for (uint32_t i = 0; t->tangents && i < t->s.n_meshes; i++)
        free(t->tangents[i]);
    free(t->tangents);
    for (uint32_t i = 0; i < LG_TT_MAX; i++)
        free(t->pixels[i]);
    free(t->uv);
    free(t->meshes);
    free(t->materials);
    free(t->maps);
    lg_ts_free(t->inner);
    free(t);
}

static inline lg_tt_scene *lg_tt_wrap(lg_scene *inner)
{
    if (!inner)
        return NULL;
    lg_tt_scene *t = calloc(1, sizeof *t);
    uint32_t nm = inner->n_meshes ? inner->n_meshes : 1;
    uint32_t nt = inner->n_materials ? inner->n_materials : 1;
    if (t) {
        t->inner = inner;
        t->meshes = calloc(nm, sizeof *t->meshes);
        t->uv = calloc(nm, sizeof *t->uv);
        t->tangents = calloc(nm, sizeof *t->tangents);
        t->materials = calloc(nt, sizeof *t->materials);
        t->maps = calloc(nt, sizeof *t->maps);
    }
    if (!t || !t->meshes || !t->uv || !t->tangents || !t->materials || !t->maps) {
        if (t)
            lg_tt_free(t);
        else
            lg_ts_free(inner);
        return NULL;
    }
    t->s = *inner;
    memcpy(t->meshes, inner->meshes, inner->n_meshes * sizeof *t->meshes);
    memcpy(t->materials, inner->materials, inner->n_materials * sizeof *t->materials);
    for (uint32_t i = 0; i < inner->n_materials; i++) {
        t->maps[i] = *lg_material_maps_default();
        t->materials[i].maps = &t->maps[i];
    }
    t->s.meshes = t->meshes;
    t->s.materials = t->materials;
    t->textures.images = t->images;
    t->textures.textures = t->texs;
    t->s.textures = &t->textures;
    return t;
}

/* Image `w` x `h` of RGBA8 `rgba` (rows top to bottom), copied: its index, or UINT32_MAX. */
static inline uint32_t lg_tt_image(lg_tt_scene *t, const char *name, uint32_t w, uint32_t h,
                                   const uint8_t *rgba)
{
    uint32_t i = t->textures.n_images;
    size_t bytes = (size_t)w * h * 4;
    if (i >= LG_TT_MAX || !(t->pixels[i] = malloc(bytes)))
        return UINT32_MAX;
    memcpy(t->pixels[i], rgba, bytes);
    t->images[i] = (lg_scene_image){ .name = name, .width = w, .height = h, .rgba8 = t->pixels[i] };
    t->textures.n_images++;
    t->textures.bytes += bytes;
    return i;
}

/* A texture of image `img` with one filter and one wrap both ways: its index, or -1. */
static inline int32_t lg_tt_texture(lg_tt_scene *t, uint32_t img, uint32_t filter, uint32_t wrap)
{
    uint32_t i = t->textures.n_textures;
    if (i >= LG_TT_MAX)
        return -1;
    t->texs[i] = (lg_scene_texture){
        .image = img, .mag_filter = filter, .min_filter = filter, .wrap_s = wrap, .wrap_t = wrap
    };
    t->textures.n_textures++;
    return (int32_t)i;
}

/* Material `m`'s maps (the defaults until set). */
static inline lg_material_maps *lg_tt_maps(lg_tt_scene *t, uint32_t m)
{
    return &t->maps[m];
}

/* TEXCOORD_0 of mesh `mesh`: u = (p - origin) . du, v = (p - origin) . dv per vertex
 * position p. False when out of memory. */
static inline bool lg_tt_planar_uv(lg_tt_scene *t, uint32_t mesh, const float origin[3],
                                   const float du[3], const float dv[3])
{
    lg_mesh *m = &t->meshes[mesh];
    float *uv = malloc((size_t)m->n_vertices * 2 * sizeof(float) + 1);
    if (!uv)
        return false;
    for (uint32_t v = 0; v < m->n_vertices; v++) {
        const float *p = m->positions + 3 * (size_t)v;
        float d[3] = { p[0] - origin[0], p[1] - origin[1], p[2] - origin[2] };
        uv[2 * v] = d[0] * du[0] + d[1] * du[1] + d[2] * du[2];
        uv[2 * v + 1] = d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2];
    }
    free(t->uv[mesh]);
    t->uv[mesh] = uv;
    m->texcoords = uv;
    return true;
}

/* TANGENT of mesh `mesh`: `tangent` (xyz, w = the bitangent's sign) at every vertex. */
static inline bool lg_tt_tangents(lg_tt_scene *t, uint32_t mesh, const float tangent[4])
{
    lg_mesh *m = &t->meshes[mesh];
    float *tg = malloc((size_t)m->n_vertices * 4 * sizeof(float) + 1);
    if (!tg)
        return false;
    for (uint32_t v = 0; v < m->n_vertices; v++)
        memcpy(tg + 4 * (size_t)v, tangent, 4 * sizeof(float));
    free(t->tangents[mesh]);
    t->tangents[mesh] = tg;
    m->tangents = tg;
    return true;
}

/* Publishes the scene on output `port` (its features recomputed: textures, masks). */
static inline int lg_tt_publish(lg_node *n, uint32_t port, lg_tt_scene *t)
{
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory building the textured test scene");
    lg_scene_compute_features(&t->s);
    return lg_declare_payload(n, port, LG_KIND_SCENE, &t->s.features, &t->s, lg_tt_free);
}

#endif
