/*
 * The textured test scenes of tests/plugins/texgl, shared by the scene plugin
 * (testtexscene.c) and the test (test_texgl.c), which builds the same lg_scene in memory to
 * sample it on the CPU (lg_scene_texture_sample) and compare with what GL drew.
 *
 * Every layout is one quad at z = 0 facing +Z, corners (-H, -H) .. (H, H) with
 * H = 5 tan(30 deg): seen by the camera at (0, 0, 5) looking at the origin with yfov
 * 60 degrees it fills a square output exactly, so that pixel (x, y) of a W x W output has
 * its centre at texture coordinates u0 + (x + 0.5) / W (u1 - u0), v likewise (row 0 at
 * the top: v grows downwards as glTF's does). Layouts:
 *
 *   checker  8 x 8 texels, every texel its own sRGB colour (texel (i, j): R = 16 + 29 i,
 *            G = 16 + 29 j, B = 200 - 20 (i + j) % 9, A 255), uv 0..1, NEAREST filters
 *   random   8 x 8 pseudo-random texels (a fixed LCG), uv 0..1, default filters
 *   wrap     the random image through three textures, REPEAT, CLAMP_TO_EDGE and
 *            MIRRORED_REPEAT on both axes (texture index = the `wrap` parameter), NEAREST
 *            magnification, uv -1..2
 *   mip      64 x 64 texels of a one-texel black and white checker, uv 0..1 (minified
 *            4x on a 16 x 16 output), default filters
 *   mask     the checker's colours with alpha 0 on texels where (i + j) is odd, material
 *            alpha MASK cutoff 0.5, NEAREST filters
 *   normal   no base colour texture; a normal texture of one constant texel TX_NORMAL_TEXEL
 *            (tilted towards +X), scale 1, every vertex's tangent (1, 0, 0, 1)
 */
#ifndef LG_TEST_TEXSCENE_H
#define LG_TEST_TEXSCENE_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/scene.h"
#include "lightgraph/vecmath.h"

enum { TX_CHECKER = 0, TX_RANDOM, TX_WRAP, TX_MIP, TX_MASK, TX_NORMAL };

/* The normal texture's texel (RGB bytes): x = 2 * 200 / 255 - 1, y = 2 * 128 / 255 - 1,
 * z = 2 * 220 / 255 - 1 in tangent space. */
static const uint8_t TX_NORMAL_TEXEL[3] = { 200, 128, 220 };

typedef struct tx_scene {
    lg_scene s;
    lg_mesh mesh;
    lg_instance inst;
    lg_material mat;
    lg_material_maps maps;
    lg_camera cam;
    lg_scene_textures textures;
    lg_scene_image image;
    lg_scene_texture tex[3];
    float pos[12], nrm[12], uv[8], tan[16];
    uint32_t idx[6];
    uint8_t *pixels;
} tx_scene;

static inline void tx_free(void *p)
{
    tx_scene *t = p;
    if (t)
        free(t->pixels);
    free(t);
}

/* The scene of `layout`; texture `wrap` (0..2) for TX_WRAP. NULL when out of memory. */
static inline tx_scene *tx_make(int layout, int wrap)
{
    tx_scene *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    uint32_t w = layout == TX_MIP ? 64 : 8;
    t->pixels = malloc((size_t)w * w * 4);
    if (!t->pixels) {
        free(t);
        return NULL;
    }
    uint32_t state = 12345u;
    for (uint32_t j = 0; j < w; j++)
        for (uint32_t i = 0; i < w; i++) {
            uint8_t *p = t->pixels + ((size_t)j * w + i) * 4;
            if (layout == TX_RANDOM || layout == TX_WRAP) {
                for (int c = 0; c < 4; c++) {
                    state = state * 1664525u + 1013904223u;
                    p[c] = (uint8_t)(state >> 24);
                }
                p[3] = 255;
            } else if (layout == TX_NORMAL) {
                memcpy(p, TX_NORMAL_TEXEL, 3);
                p[3] = 255;
            } else if (layout == TX_MIP) {
                uint8_t v = (i + j) % 2 ? 255 : 0;
                p[0] = p[1] = p[2] = v;
                p[3] = 255;
            } else {
                p[0] = (uint8_t)(16 + 29 * i);
                p[1] = (uint8_t)(16 + 29 * j);
                p[2] = (uint8_t)(200 - 20 * ((i + j) % 9));
                p[3] = layout == TX_MASK && (i + j) % 2 ? 0 : 255;
            }
        }
    const float H = 5.0f * tanf((float)(LG_PI / 6.0));
    const float c[4][2] = { { -H, H }, { H, H }, { H, -H }, { -H, -H } }; /* TL TR BR BL */
    float u0 = layout == TX_WRAP ? -1.0f : 0.0f, u1 = layout == TX_WRAP ? 2.0f : 1.0f;
    const float uv[4][2] = { { u0, u0 }, { u1, u0 }, { u1, u1 }, { u0, u1 } };
    for (int k = 0; k < 4; k++) {
        t->pos[3 * k] = c[k][0], t->pos[3 * k + 1] = c[k][1], t->pos[3 * k + 2] = 0.0f;
        t->nrm[3 * k] = 0.0f, t->nrm[3 * k + 1] = 0.0f, t->nrm[3 * k + 2] = 1.0f;
        t->uv[2 * k] = uv[k][0], t->uv[2 * k + 1] = uv[k][1];
        t->tan[4 * k] = 1.0f, t->tan[4 * k + 1] = 0.0f, t->tan[4 * k + 2] = 0.0f;
        t->tan[4 * k + 3] = 1.0f;
    }
    /* counter-clockwise seen from +Z: TL, BL, BR and TL, BR, TR */
    const uint32_t idx[6] = { 0, 3, 2, 0, 2, 1 };
    memcpy(t->idx, idx, sizeof idx);

    t->image =
        (lg_scene_image){ .name = "test texture", .width = w, .height = w, .rgba8 = t->pixels };
    uint32_t near = layout == TX_CHECKER || layout == TX_MASK ? LG_TEX_NEAREST : 0;
    static const uint32_t wraps[3] = { LG_TEX_REPEAT, LG_TEX_CLAMP_TO_EDGE,
                                       LG_TEX_MIRRORED_REPEAT };
    for (int k = 0; k < 3; k++)
        t->tex[k] = (lg_scene_texture){ .image = 0,
                                        .mag_filter = layout == TX_WRAP ? LG_TEX_NEAREST : near,
                                        .min_filter = near,
                                        .wrap_s = wraps[k],
                                        .wrap_t = wraps[k] };
    t->textures = (lg_scene_textures){ .images = &t->image,
                                       .n_images = 1,
                                       .textures = t->tex,
                                       .n_textures = 3,
                                       .bytes = (uint64_t)w * w * 4 };
    t->maps = *lg_material_maps_default();
    t->maps.base_color.texture = layout == TX_WRAP ? wrap : layout == TX_NORMAL ? -1 : 0;
    if (layout == TX_NORMAL)
        t->maps.normal.texture = 0;
    if (layout == TX_MASK) {
        t->maps.alpha_mode = LG_ALPHA_MASK;
        t->maps.alpha_cutoff = 0.5f;
    }
    t->mat = (lg_material){ .name = "textured",
                            .kd = 1.0f,
                            .od = { 1, 1, 1 },
                            .base_color = { 1, 1, 1, 1 },
                            .roughness = 1.0f };
    t->mat.maps = &t->maps;
    t->mesh = (lg_mesh){ .name = "quad",
                         .n_vertices = 4,
                         .positions = t->pos,
                         .normals = t->nrm,
                         .texcoords = t->uv,
                         .n_indices = 6,
                         .indices = t->idx,
                         .material = 0,
                         .tangents = layout == TX_NORMAL ? t->tan : NULL,
                         .bounds_min = { -H, -H, 0 },
                         .bounds_max = { H, H, 0 } };
    lg_m4_identity(t->inst.model);
    t->inst.normal_matrix[0] = t->inst.normal_matrix[4] = t->inst.normal_matrix[8] = 1.0f;
    t->cam = (lg_camera){ .name = "front",
                          .position = { 0, 0, 5 },
                          .target = { 0, 0, 0 },
                          .up = { 0, 1, 0 },
                          .yfov = (float)(LG_PI / 3.0),
                          .znear = 1.0f,
                          .zfar = 20.0f };
    lg_scene *s = &t->s;
    s->struct_size = sizeof *s;
    s->source = "testtexscene";
    s->meshes = &t->mesh, s->n_meshes = 1;
    s->instances = &t->inst, s->n_instances = 1;
    s->materials = &t->mat, s->n_materials = 1;
    s->cameras = &t->cam, s->n_cameras = 1;
    s->textures = &t->textures;
    for (int k = 0; k < 3; k++)
        s->bounds_min[k] = t->mesh.bounds_min[k], s->bounds_max[k] = t->mesh.bounds_max[k];
    lg_scene_compute_features(s);
    return t;
}

#endif
