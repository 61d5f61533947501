/*
 * plugins/volumetric_froxel/froxel_gl.c: the gl backend of volumetric_froxel, two compute
 * passes (shaders/volumetric_froxel/froxel_{column,lookup}.comp) that compute what
 * froxel.h specifies:
 *
 *   column  one invocation per column, front to back: the light pass (S = sigma_s sum_l
 *           C_l Shadow_l p_HG, blended with the reprojected history; written to this
 *           frame's S volume) fused with the accumulation (the grid part: A_k, mean Tr_k),
 *           with the column's constants (phase, light-clip line) computed once
 *   lookup  one invocation per pixel: `inscatter` and `out`; out's depth = base's (copied)
 *
 * (Before, the light pass ran one invocation per froxel, each doing the phase and the full
 * shadow projection, and a second pass accumulated: 305 / 902 / 2588 ms at the thesis grid
 * with 1 / 8 / 32 lights against 219 / 371 / 1003 ms fused; README.)
 *
 * State kept across frames (fx_gl): the two passes, the lights buffer, the slice-table
 * buffer (refilled each frame: T(k + jitter), T(k), T(k + 0.5)), and two rgba32f
 * 3D textures of W x H x D that take turns as "this frame's S" and "the history" (the
 * previous frame's blended S), so that no copy is needed between frames. All four are the
 * SDK's lg_gl_buffer / lg_gl_texture: the volumes are made with the grid size, remade when
 * it changes (the old ones released in the profile first), and deleted in fx_gl_destroy.
 *
 * Why 3D textures (image load/store) and not storage buffers: on llvmpipe the earlier three
 * passes with S in two SSBOs ([k][j][i] vec4) ran about 2x slower in the light pass and
 * 3-4x slower in the accumulation (190x90x128 grid, 640x360; README's numbers), as the PRT
 * work found for wide buffer reads in compute shaders there.
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"

#include "froxel.h"
#include "froxel_column.comp.h"
#include "froxel_lookup.comp.h"

/* One light of the FxLights block (froxel_column.comp): the light and its shadow record. */
typedef struct fx_gl_light {
    float view_proj[16]; /* the shadow record's world -> clip (zero when unshadowed) */
    float dir[3];        /* unit, the direction the light travels */
    int32_t shadow;      /* record index, or -1: unshadowed */
    float l_c[3];
    float pad0;
    int32_t tile[2]; /* the record's tile origin in the atlas, texels */
    int32_t pad1[2];
} fx_gl_light;
LG_GL_BLOCK_SIZE(fx_gl_light, 112);
LG_GL_BLOCK_OFFSET(fx_gl_light, dir, 64);
LG_GL_BLOCK_OFFSET(fx_gl_light, shadow, 76);
LG_GL_BLOCK_OFFSET(fx_gl_light, l_c, 80);
LG_GL_BLOCK_OFFSET(fx_gl_light, tile, 96);

/* The slice table FxSlices (froxel_column.comp): T(k + jitter) for k < D, T(k) for k <= D,
 * T(k + 0.5) for k < D; sized for the largest grid depth. */
#define FX_GL_SLICES_MAX (3 * FX_MAX_D + 1)

/* The uniforms of both passes: the grid, this frame's camera, and the slice map (the lookup
 * only: the column pass reads the slice table). */
typedef struct fx_gl_view_u {
    lg_gl_uniform grid, inv_vp, eye, fwd, slicing, map;
} fx_gl_view_u;

typedef struct fx_gl {
    lg_gl_pass *column, *lookup;
    fx_gl_view_u lv, kv;
    struct {
        lg_gl_uniform sigma_s, g, n_lights, shadow_res, bias, history;
        lg_gl_uniform prev_vp, prev_eye, prev_fwd, prev_slicing, prev_map;
        lg_gl_uniform sigma_t, energy;
        lg_gl_binding lights, slices, atlas, s, hist, out;
    } l;
    struct {
        lg_gl_uniform size, z_limit, sigma_t, energy;
        lg_gl_binding slices, base, depth, acc, s, out, inscatter;
    } k;
    lg_gl_buffer lights_buf; /* VOL_MAX_LIGHTS fx_gl_light */
    lg_gl_buffer slices_buf; /* FX_GL_SLICES_MAX floats: the frame's slice table (fx_gl_slices) */
    lg_gl_texture vol[2];    /* S volumes; vol[cur] is written this frame, vol[1 - cur] is
                              * history */
    int cur;
    bool hist_valid; /* vol[1 - cur] holds a frame's S (false after (re)making them) */
} fx_gl;

static const lg_gl_shader_src fx_src_column = { GL_COMPUTE_SHADER, lg_src_froxel_column_comp_file,
                                                lg_src_froxel_column_comp };
static const lg_gl_shader_src fx_src_lookup = { GL_COMPUTE_SHADER, lg_src_froxel_lookup_comp_file,
                                                lg_src_froxel_lookup_comp };

static void fx_gl_view_lookup(lg_gl_pass *p, fx_gl_view_u *u, bool slice_map)
{
    u->grid = lg_gl_pass_uniform(p, "u_grid");
    u->inv_vp = lg_gl_pass_uniform(p, "u_inv_vp");
    u->eye = lg_gl_pass_uniform(p, "u_eye");
    u->fwd = lg_gl_pass_uniform(p, "u_fwd");
    u->slicing.location = u->map.location = -1;
    if (slice_map) {
        u->slicing = lg_gl_pass_uniform(p, "u_slicing");
        u->map = lg_gl_pass_uniform(p, "u_map");
    }
}

/* The passes and the lights buffer, made on the first execute. */
static int fx_gl_make_passes(lg_node *n, fx_gl *st)
{
    int rc;
    lg_gl_pass_desc d = { .name = "volumetric_froxel column",
                          .stages = &fx_src_column,
                          .n_stages = 1 };
    if ((rc = lg_gl_pass_create(n, &d, &st->column)))
        return rc;
    d.name = "volumetric_froxel lookup";
    d.stages = &fx_src_lookup;
    if ((rc = lg_gl_pass_create(n, &d, &st->lookup)))
        return rc;

    lg_gl_pass *p = st->column;
    fx_gl_view_lookup(p, &st->lv, false);
    st->l.sigma_s = lg_gl_pass_uniform(p, "u_sigma_s");
    st->l.g = lg_gl_pass_uniform(p, "u_g");
    st->l.n_lights = lg_gl_pass_uniform(p, "u_n_lights");
    st->l.shadow_res = lg_gl_pass_uniform(p, "u_shadow_res");
    st->l.bias = lg_gl_pass_uniform(p, "u_bias");
    st->l.history = lg_gl_pass_uniform(p, "u_history");
    st->l.prev_vp = lg_gl_pass_uniform(p, "u_prev_vp");
    st->l.prev_eye = lg_gl_pass_uniform(p, "u_prev_eye");
    st->l.prev_fwd = lg_gl_pass_uniform(p, "u_prev_fwd");
    st->l.prev_slicing = lg_gl_pass_uniform(p, "u_prev_slicing");
    st->l.prev_map = lg_gl_pass_uniform(p, "u_prev_map");
    st->l.lights = lg_gl_pass_storage(p, "FxLights");
    st->l.slices = lg_gl_pass_storage(p, "FxSlices");
    st->l.atlas = lg_gl_pass_texture(p, "u_atlas");
    st->l.s = lg_gl_pass_image(p, "u_s");
    st->l.hist = lg_gl_pass_image(p, "u_hist");
    st->l.sigma_t = lg_gl_pass_uniform(p, "u_sigma_t");
    st->l.energy = lg_gl_pass_uniform(p, "u_energy");
    st->l.out = lg_gl_pass_image(p, "u_out");
    lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "FxLights", sizeof(fx_gl_light));

    p = st->lookup;
    fx_gl_view_lookup(p, &st->kv, true);
    st->k.size = lg_gl_pass_uniform(p, "u_size");
    st->k.z_limit = lg_gl_pass_uniform(p, "u_z_limit");
    st->k.sigma_t = lg_gl_pass_uniform(p, "u_sigma_t");
    st->k.energy = lg_gl_pass_uniform(p, "u_energy");
    st->k.slices = lg_gl_pass_storage(p, "FxSlices");
    st->k.base = lg_gl_pass_texture(p, "u_base");
    st->k.depth = lg_gl_pass_texture(p, "u_depth");
    st->k.acc = lg_gl_pass_image(p, "u_acc");
    st->k.s = lg_gl_pass_image(p, "u_s");
    st->k.out = lg_gl_pass_image(p, "u_out");
    st->k.inscatter = lg_gl_pass_image(p, "u_inscatter");
    /* a failed look-up fails the pass: its begin reports LG_ERR_INVALID */

    if ((rc = lg_gl_buffer_recreate(n, &st->lights_buf, VOL_MAX_LIGHTS * sizeof(fx_gl_light), 0,
                                    NULL)))
        return rc;
    return lg_gl_buffer_recreate(n, &st->slices_buf, FX_GL_SLICES_MAX * sizeof(float), 0, NULL);
}

/* The two S volumes at W x H x D, made (cleared to 0) when absent or of another size. */
static int fx_gl_volumes(lg_node *n, const lg_gl *gl, fx_gl *st, const fx_frame *f)
{
    const lg_gl_texture_desc d = {
        .target = GL_TEXTURE_3D, .format = GL_RGBA32F, .width = f->w, .height = f->h, .depth = f->d
    };
    int made0 = lg_gl_texture_recreate(n, &st->vol[0], &d);
    int made1 = made0 < 0 ? made0 : lg_gl_texture_recreate(n, &st->vol[1], &d);
    if (made0 < 0 || made1 < 0) {
        lg_gl_texture_destroy(n, &st->vol[0]);
        lg_gl_texture_destroy(n, &st->vol[1]);
        return lg_error_code(n, made0 < 0 ? made0 : made1,
                             "volumetric_froxel: two %ux%ux%u rgba32f volumes (%.1f MB) could "
                             "not be made",
                             f->w, f->h, f->d, 2.0 * f->w * f->h * f->d * 16 / 1e6);
    }
    if (!made0 && !made1)
        return 0;
    static const float zero[4] = { 0, 0, 0, 0 };
    for (int i = 0; i < 2; i++)
        gl->ClearTexImage(st->vol[i].name, 0, GL_RGBA, GL_FLOAT, zero);
    st->cur = 0;
    st->hist_valid = false;
    return lg_gl_check(n, "volumetric_froxel: clearing the scattering volumes");
}

static void fx_gl_map_vec4(const lg_slice_map *m, float out[4])
{
    out[0] = (float)m->near;
    out[1] = (float)m->far;
    out[2] = (float)m->near_offset;
    out[3] = (float)m->depth;
}

static void fx_gl_set_view(const lg_gl *gl, lg_gl_pass *p, const fx_gl_view_u *u, const fx_frame *f)
{
    const vol_setup *v = f->v;
    float inv[16], map[4];
    for (int i = 0; i < 16; i++)
        inv[i] = (float)v->inv_view_proj[i];
    fx_gl_map_vec4(&f->map, map);
    lg_gl_set_ivec3(p, u->grid, (int32_t)f->w, (int32_t)f->h, (int32_t)f->d);
    lg_gl_set_mat4(p, u->inv_vp, inv);
    lg_gl_set_vec3(p, u->eye, (float)v->eye[0], (float)v->eye[1], (float)v->eye[2]);
    lg_gl_set_vec3(p, u->fwd, (float)v->forward[0], (float)v->forward[1], (float)v->forward[2]);
    lg_gl_set_int(p, u->slicing, (int32_t)f->map.slicing);
    lg_gl_set_vec4v(p, u->map, map);
}

/* Binds level 0 of 3D texture `tex`, every layer (an image3D), to image binding b. */
static void fx_gl_bind_volume(lg_gl_pass *p, lg_gl_binding b, GLuint tex, GLenum access)
{
    lg_gl_pass_bind_image_level(p, b, tex, 0, LG_GL_ALL_LAYERS, access, GL_RGBA32F);
}

/* The FxLights records of this frame: each light with its shadow record (if any). */
static void fx_gl_lights(const fx_frame *f, fx_gl_light *out)
{
    const vol_setup *v = f->v;
    memset(out, 0, VOL_MAX_LIGHTS * sizeof *out);
    for (uint32_t i = 0; i < v->n_lights; i++) {
        const vol_light *l = &v->lights[i];
        fx_gl_light *g = &out[i];
        memcpy(g->dir, l->dir, sizeof g->dir);
        memcpy(g->l_c, l->l_c, sizeof g->l_c);
        g->shadow = -1;
        if (f->sm && l->shadow >= 0 && (uint32_t)l->shadow < f->sm->n_lights) {
            const lg_shadow_light *r = &f->sm->lights[l->shadow];
            memcpy(g->view_proj, r->view_proj, sizeof g->view_proj);
            g->tile[0] = (int32_t)r->tile_x;
            g->tile[1] = (int32_t)r->tile_y;
            g->shadow = l->shadow;
        }
    }
}

/* The frame's slice table in FxSlices' layout (FX_GL_SLICES_MAX floats at most), from
 * froxel.c's tables. */
static uint32_t fx_gl_slices(const fx_frame *f, float *out)
{
    const fx_slices *t = f->slices;
    uint32_t D = f->d;
    for (uint32_t k = 0; k < D; k++) {
        out[k] = (float)t->tj[k];
        out[2 * D + 1 + k] = (float)t->tq[k];
    }
    for (uint32_t k = 0; k <= D; k++)
        out[D + k] = (float)t->tk[k];
    return 3 * D + 1;
}

/* Maps the grid part for writing, after checking it is the rgba32f volume froxel.h wants. */
static int fx_gl_grid(lg_node *n, const fx_frame *f, GLuint *tex)
{
    const lg_resource *grid = lg_part(n, lg_output(n, FX_OUT_GRID), "grid");
    if (!grid)
        return lg_error(n, "volumetric_froxel (gl): output 'grid' has no part 'grid'");
    lg_resource_info info;
    int rc = lg_describe(grid, &info, n);
    if (rc)
        return rc;
    if (info.kind != LG_KIND_VOLUME || info.volume.format != LG_FORMAT_RGBA32F ||
        info.volume.width != f->w || info.volume.height != f->h || info.volume.depth != f->d)
        return lg_error(n,
                        "volumetric_froxel (gl): the grid part is not an rgba32f volume of "
                        "%ux%ux%u (declared %ux%ux%u, format %d)",
                        f->w, f->h, f->d, info.volume.width, info.volume.height, info.volume.depth,
                        (int)info.volume.format);
    uint32_t dummy = 0;
    return lg_map_gl(n, grid, LG_WRITE, tex, &dummy);
}

int fx_gl_execute(lg_node *n, void **state, const fx_frame *f)
{
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    const vol_setup *v = f->v;
    int rc;
    fx_gl *st = *state;
    if (!st) {
        if (!(st = calloc(1, sizeof *st)))
            return lg_error_code(n, LG_ERR_NOMEM, "volumetric_froxel (gl): out of memory");
        *state = st;
    }
    if (!st->lookup || !st->lights_buf.name || !st->slices_buf.name) {
        /* first frame, or an earlier attempt failed part-way: make them all again */
        lg_gl_pass_destroy(&st->column);
        lg_gl_pass_destroy(&st->lookup);
        lg_gl_buffer_destroy(n, &st->lights_buf);
        lg_gl_buffer_destroy(n, &st->slices_buf);
        if ((rc = fx_gl_make_passes(n, st))) {
            lg_gl_pass_destroy(&st->lookup); /* so that the next frame tries again */
            return rc;
        }
    }
    if (v->n_lights < 1 || v->n_lights > VOL_MAX_LIGHTS)
        return lg_error(n, "volumetric_froxel (gl): %u directional lights (1 .. %d)", v->n_lights,
                        VOL_MAX_LIGHTS);
    if (f->d > (FX_GL_SLICES_MAX - 1) / 3)
        return lg_error(n,
                        "volumetric_froxel (gl): grid depth %u, more than the slice table's "
                        "%d",
                        f->d, (FX_GL_SLICES_MAX - 1) / 3);
    if ((rc = fx_gl_volumes(n, gl, st, f)))
        return rc;

    /* inputs and outputs on the GL device */
    uint32_t base_tex = 0, base_depth = 0, out_tex = 0, out_depth = 0, ins_tex = 0, dummy = 0;
    GLuint grid_tex = 0, atlas = 0;
    if ((rc = lg_map_gl(n, lg_input(n, VOL_IN_BASE), LG_READ, &base_tex, &base_depth)) ||
        (rc = lg_map_gl(n, lg_output(n, VOL_OUT_OUT), LG_WRITE, &out_tex, &out_depth)) ||
        (rc = lg_map_gl(n, lg_output(n, VOL_OUT_INSCATTER), LG_WRITE, &ins_tex, &dummy)) ||
        (rc = fx_gl_grid(n, f, &grid_tex)))
        return rc;
    if (!base_depth)
        return lg_error(n, "input 'base': the image has no depth plane on GL (the fog needs "
                           "the surface distance)");
    if (!out_depth)
        return lg_error(n, "volumetric_froxel (gl): output 'out' has no depth plane");

    fx_gl_light lights[VOL_MAX_LIGHTS];
    fx_gl_lights(f, lights);
    bool shadowed = false;
    for (uint32_t i = 0; i < v->n_lights; i++)
        shadowed |= lights[i].shadow >= 0;
    if (shadowed) {
        uint32_t color = 0;
        if ((rc = lg_map_gl(n, f->sm->atlas, LG_READ, &color, &atlas)))
            return rc;
        if (!atlas)
            return lg_error_code(n, LG_ERR_DEVICE,
                                 "input 'shadows': the atlas has no GL depth "
                                 "texture");
    }
    float slices[FX_GL_SLICES_MAX];
    uint32_t n_slices = fx_gl_slices(f, slices);
    if ((rc = lg_gl_buffer_upload(n, &st->lights_buf, 0, v->n_lights * sizeof *lights, lights)) ||
        (rc = lg_gl_buffer_upload(n, &st->slices_buf, 0, n_slices * sizeof(float), slices)))
        return rc;

    /* history: the other volume holds the previous frame's S only if a frame ran into it */
    bool hist = f->history > 0.0f && f->prev && st->hist_valid;
    GLuint s_now = st->vol[st->cur].name, s_prev = st->vol[1 - st->cur].name;

    /* 1. and 2. light pass and accumulation, one invocation per column */
    lg_gl_pass *p = st->column;
    if ((rc = lg_gl_pass_begin(p, NULL)))
        return rc;
    fx_gl_set_view(gl, p, &st->lv, f);
    lg_gl_set_vec3v(p, st->l.sigma_s, v->sigma_s);
    lg_gl_set_float(p, st->l.g, v->g);
    lg_gl_set_int(p, st->l.n_lights, (int32_t)v->n_lights);
    lg_gl_set_int(p, st->l.shadow_res, f->sm ? (int32_t)f->sm->resolution : 1);
    lg_gl_set_float(p, st->l.bias, f->sm ? f->sm->bias_constant : 0.0f);
    lg_gl_set_float(p, st->l.history, hist ? f->history : 0.0f);
    if (hist) {
        const vol_setup *q = f->prev;
        float pmap[4];
        fx_gl_map_vec4(&f->prev_map, pmap);
        lg_gl_set_mat4(p, st->l.prev_vp, q->view.view_proj);
        lg_gl_set_vec3(p, st->l.prev_eye, (float)q->eye[0], (float)q->eye[1], (float)q->eye[2]);
        lg_gl_set_vec3(p, st->l.prev_fwd, (float)q->forward[0], (float)q->forward[1],
                       (float)q->forward[2]);
        lg_gl_set_int(p, st->l.prev_slicing, (int32_t)f->prev_map.slicing);
        lg_gl_set_vec4v(p, st->l.prev_map, pmap);
    }
    lg_gl_pass_bind_buffer(p, st->l.lights, st->lights_buf.name);
    lg_gl_pass_bind_buffer(p, st->l.slices, st->slices_buf.name);
    if (atlas)
        lg_gl_pass_bind_texture(p, st->l.atlas, atlas);
    fx_gl_bind_volume(p, st->l.s, s_now, GL_WRITE_ONLY);
    fx_gl_bind_volume(p, st->l.hist, s_prev, GL_READ_ONLY);
    lg_gl_set_vec3v(p, st->l.sigma_t, v->sigma_t);
    lg_gl_set_int(p, st->l.energy, f->accum == FX_ACC_ENERGY);
    fx_gl_bind_volume(p, st->l.out, grid_tex, GL_WRITE_ONLY);
    if ((rc = lg_gl_pass_end(p, lg_gl_pass_dispatch(p, f->w, f->h, 1))))
        return rc;

    /* 3. lookup and composite, per pixel */
    p = st->lookup;
    if ((rc = lg_gl_pass_begin(p, NULL)))
        return rc;
    fx_gl_set_view(gl, p, &st->kv, f);
    lg_gl_set_ivec2(p, st->k.size, (int32_t)v->width, (int32_t)v->height);
    lg_gl_set_float(p, st->k.z_limit, v->z_limit);
    lg_gl_set_vec3v(p, st->k.sigma_t, v->sigma_t);
    lg_gl_set_int(p, st->k.energy, f->accum == FX_ACC_ENERGY);
    lg_gl_pass_bind_buffer(p, st->k.slices, st->slices_buf.name);
    lg_gl_pass_bind_texture(p, st->k.base, base_tex);
    lg_gl_pass_bind_texture(p, st->k.depth, base_depth);
    fx_gl_bind_volume(p, st->k.acc, grid_tex, GL_READ_ONLY);
    fx_gl_bind_volume(p, st->k.s, s_now, GL_READ_ONLY);
    lg_gl_pass_bind_image(p, st->k.out, out_tex, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_pass_bind_image(p, st->k.inscatter, ins_tex, GL_WRITE_ONLY, GL_RGBA32F);
    if ((rc = lg_gl_pass_end(p, lg_gl_pass_dispatch(p, v->width, v->height, 1))))
        return rc;

    /* out's depth = base's: a depth texture cannot be a compute shader's image, so copy it */
    gl->CopyImageSubData(base_depth, GL_TEXTURE_2D, 0, 0, 0, 0, out_depth, GL_TEXTURE_2D, 0, 0, 0,
                         0, (GLsizei)v->width, (GLsizei)v->height, 1);
    if ((rc = lg_gl_check(n, "volumetric_froxel: copying base's depth to out")))
        return rc;

    /* this frame's S is the next frame's history */
    st->cur = 1 - st->cur;
    st->hist_valid = true;
    return 0;
}

void fx_gl_destroy(lg_node *n, void *state)
{
    fx_gl *st = state;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->column);
    lg_gl_pass_destroy(&st->lookup);
    lg_gl_texture_destroy(n, &st->vol[0]);
    lg_gl_texture_destroy(n, &st->vol[1]);
    lg_gl_buffer_destroy(n, &st->lights_buf);
    lg_gl_buffer_destroy(n, &st->slices_buf);
    free(st);
}
