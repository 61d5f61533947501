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
 * Point and spot lights, a PCF radius above 0 and a density field (froxel.h 4.) run
 * variants of the two passes compiled from the same sources with #define FX_GENERAL (and
 * FX_HETERO): every light per froxel with its falloff, the map record that holds the
 * sample (cube face, perspective divide, PCF; FxRecords holds the map's records), the
 * transmittance towards the light; with a field, rho (a 3D texture uploaded per frame), the
 * lights' optical-depth volumes stacked along z in one 3D texture read with linear
 * filtering, and the optical path P (r32f volume) for the lookup. The variant is chosen per
 * frame, so a homogeneous medium lit by directional lights runs the plain pass as before.
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
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"

#include "froxel.h"
#include "froxel_column.comp.h"
#include "froxel_lookup.comp.h"

/* One light of the FxLights block (froxel_column.comp): the light and its shadow record.
 * The plain variant reads view_proj .. tile (a directional light's one record); the general
 * one (FX_GENERAL: point and spot lights, PCF, a heterogeneous medium) the rest. */
typedef struct fx_gl_light {
    float view_proj[16]; /* the shadow record's world -> clip (zero when unshadowed) */
    float dir[3];        /* unit, the direction the light travels (a spot's axis) */
    int32_t shadow;      /* record index, or -1: unshadowed */
    float l_c[3];
    int32_t type;    /* lg_light_type */
    int32_t tile[2]; /* the record's tile origin in the atlas, texels */
    int32_t rec;     /* FX_GENERAL: first record in FxRecords (= the map's), or -1 */
    int32_t n_rec;   /* 1, 2 (dual paraboloid) or 6 (cube): lg_shadowmap_record_at's rule */
    float pos[3];
    float range;
    float sq[3]; /* the light's position from its first record's view (the face choice) */
    float cos_inner;
    float cos_outer;
    float pad2, pad3[2];
} fx_gl_light;
LG_GL_BLOCK_SIZE(fx_gl_light, 160);
LG_GL_BLOCK_OFFSET(fx_gl_light, dir, 64);
LG_GL_BLOCK_OFFSET(fx_gl_light, shadow, 76);
LG_GL_BLOCK_OFFSET(fx_gl_light, l_c, 80);
LG_GL_BLOCK_OFFSET(fx_gl_light, tile, 96);
LG_GL_BLOCK_OFFSET(fx_gl_light, pos, 112);
LG_GL_BLOCK_OFFSET(fx_gl_light, sq, 128);
LG_GL_BLOCK_OFFSET(fx_gl_light, cos_outer, 144);

/* One shadow record of FxRecords (froxel_column.comp, FX_GENERAL): the map's records in its
 * order, with what lg_shadowmap_visibility reads of each. */
typedef struct fx_gl_record {
    float m[16]; /* view_proj; a dual-paraboloid record's view */
    int32_t tile[2];
    int32_t face;
    int32_t projection;
    float znear;
    float depth_range;
    float pad[2];
} fx_gl_record;
LG_GL_BLOCK_SIZE(fx_gl_record, 96);
LG_GL_BLOCK_OFFSET(fx_gl_record, tile, 64);
LG_GL_BLOCK_OFFSET(fx_gl_record, znear, 80);

/* The column pass's variants (froxel.h 4.: the added terms are behind per-frame choices,
 * compiled out of the plain pass that a homogeneous medium with directional lights runs). */
enum { FX_GL_PLAIN = 0, FX_GL_LOCAL = 1, FX_GL_HETERO = 2, FX_GL_VARIANTS = 3 };
static const char *const fx_gl_defines[FX_GL_VARIANTS] = {
    NULL, "#define FX_GENERAL 1\n", "#define FX_GENERAL 1\n#define FX_HETERO 1\n"
};

/* The slice table FxSlices (froxel_column.comp): T(k + jitter) for k < D, T(k) for k <= D,
 * T(k + 0.5) for k < D, and the slice lengths tlen (t_{k+1} - t_k, t_0 = 0, made in double
 * by froxel.c as cpu takes them) for k < D; sized for the largest grid depth. */
#define FX_GL_SLICES_MAX (4 * FX_MAX_D + 1)

/* The uniforms of both passes: the grid, this frame's camera, and the slice map (the lookup
 * only: the column pass reads the slice table). */
typedef struct fx_gl_view_u {
    lg_gl_uniform grid, inv_vp, ray_vp, eye, fwd, slicing, map;
} fx_gl_view_u;

/* The column pass of one variant and its bindings. */
typedef struct fx_gl_column {
    lg_gl_pass *pass;
    fx_gl_view_u v;
    lg_gl_uniform sigma_s, g, n_lights, shadow_res, bias, history;
    lg_gl_uniform prev_vp, prev_eye, prev_fwd, prev_slicing, prev_map;
    lg_gl_uniform sigma_t, energy;
    lg_gl_binding lights, slices, atlas, s, hist, out;
    /* FX_GENERAL, FX_HETERO (absent in the others) */
    lg_gl_uniform pcf, point_nodes, tau_lo, tau_hi, tau_n;
    lg_gl_binding records, density, tau, path;
} fx_gl_column;

/* The lookup pass of one variant (plain, or FX_HETERO). */
typedef struct fx_gl_lookup {
    lg_gl_pass *pass;
    fx_gl_view_u v;
    lg_gl_uniform size, z_limit, sigma_t, energy;
    lg_gl_binding slices, base, depth, acc, s, out, inscatter, path;
} fx_gl_lookup;

typedef struct fx_gl {
    fx_gl_column col[FX_GL_VARIANTS]; /* made at the first frame that needs each */
    fx_gl_lookup look[2];             /* [heterogeneous] */
    lg_gl_buffer lights_buf;          /* VOL_MAX_LIGHTS fx_gl_light */
    lg_gl_buffer slices_buf; /* FX_GL_SLICES_MAX floats: the frame's slice table (fx_gl_slices) */
    lg_gl_texture vol[2];    /* S volumes; vol[cur] is written this frame, vol[1 - cur] is
                              * history */
    int cur;
    bool hist_valid; /* vol[1 - cur] holds a frame's S (false after (re)making them) */
    /* FX_GENERAL: the shadow map's records (remade when there are more) */
    lg_gl_buffer records_buf;
    /* heterogeneous media: rho (r32f W x H x D), the lights' tau volumes stacked along z
     * (r32f; both uploaded each frame, remade when their size changes) and the optical
     * path P (r32f W x H x D) */
    lg_gl_texture density, tau, path;
} fx_gl;

static const lg_gl_shader_src fx_src_column = { GL_COMPUTE_SHADER, lg_src_froxel_column_comp_file,
                                                lg_src_froxel_column_comp };
static const lg_gl_shader_src fx_src_lookup = { GL_COMPUTE_SHADER, lg_src_froxel_lookup_comp_file,
                                                lg_src_froxel_lookup_comp };

static void fx_gl_view_lookup(lg_gl_pass *p, fx_gl_view_u *u, bool slice_map)
{
    u->grid = lg_gl_pass_uniform(p, "u_grid");
    /* the lookup also unprojects the surface; the column pass only needs the rays */
    u->inv_vp.location = -1;
    if (slice_map)
        u->inv_vp = lg_gl_pass_uniform(p, "u_inv_vp");
    u->ray_vp = lg_gl_pass_uniform(p, "u_ray_vp");
    u->eye = lg_gl_pass_uniform(p, "u_eye");
    u->fwd = lg_gl_pass_uniform(p, "u_fwd");
    u->slicing.location = u->map.location = -1;
    if (slice_map) {
        u->slicing = lg_gl_pass_uniform(p, "u_slicing");
        u->map = lg_gl_pass_uniform(p, "u_map");
    }
}

/* The column pass of variant `var`, made at its first use. */
static int fx_gl_make_column(lg_node *n, fx_gl_column *c, int var)
{
    char name[64];
    snprintf(name, sizeof name, "volumetric_froxel column%s",
             var == FX_GL_HETERO  ? " (heterogeneous)"
             : var == FX_GL_LOCAL ? " (point, spot, pcf)"
                                  : "");
    lg_gl_pass_desc d = {
        .name = name, .stages = &fx_src_column, .n_stages = 1, .defines = fx_gl_defines[var]
    };
    int rc = lg_gl_pass_create(n, &d, &c->pass);
    if (rc)
        return rc;
    lg_gl_pass *p = c->pass;
    fx_gl_view_lookup(p, &c->v, false);
    c->sigma_s = lg_gl_pass_uniform(p, "u_sigma_s");
    c->g = lg_gl_pass_uniform(p, "u_g");
    c->n_lights = lg_gl_pass_uniform(p, "u_n_lights");
    c->shadow_res = lg_gl_pass_uniform(p, "u_shadow_res");
    c->bias = lg_gl_pass_uniform(p, "u_bias");
    c->history = lg_gl_pass_uniform(p, "u_history");
    c->prev_vp = lg_gl_pass_uniform(p, "u_prev_vp");
    c->prev_eye = lg_gl_pass_uniform(p, "u_prev_eye");
    c->prev_fwd = lg_gl_pass_uniform(p, "u_prev_fwd");
    c->prev_slicing = lg_gl_pass_uniform(p, "u_prev_slicing");
    c->prev_map = lg_gl_pass_uniform(p, "u_prev_map");
    c->lights = lg_gl_pass_storage(p, "FxLights");
    c->slices = lg_gl_pass_storage(p, "FxSlices");
    c->atlas = lg_gl_pass_texture(p, "u_atlas");
    c->s = lg_gl_pass_image(p, "u_s");
    c->hist = lg_gl_pass_image(p, "u_hist");
    c->sigma_t = lg_gl_pass_uniform(p, "u_sigma_t");
    c->energy = lg_gl_pass_uniform(p, "u_energy");
    c->out = lg_gl_pass_image(p, "u_out");
    lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "FxLights", sizeof(fx_gl_light));
    c->pcf.location = c->point_nodes.location = -1;
    c->tau_lo.location = c->tau_hi.location = c->tau_n.location = -1;
    if (var != FX_GL_PLAIN) {
        c->pcf = lg_gl_pass_uniform(p, "u_pcf");
        c->point_nodes = lg_gl_pass_uniform(p, "u_point_nodes");
        c->records = lg_gl_pass_storage(p, "FxRecords");
        lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "FxRecords", sizeof(fx_gl_record));
    }
    if (var == FX_GL_HETERO) {
        c->tau_lo = lg_gl_pass_uniform(p, "u_tau_lo");
        c->tau_hi = lg_gl_pass_uniform(p, "u_tau_hi");
        c->tau_n = lg_gl_pass_uniform(p, "u_tau_n");
        c->density = lg_gl_pass_texture(p, "u_density");
        c->tau = lg_gl_pass_texture(p, "u_tau");
        c->path = lg_gl_pass_image(p, "u_path");
    }
    /* a failed look-up fails the pass: its begin reports LG_ERR_INVALID */
    return 0;
}

/* The lookup pass (heterogeneous or not), made at its first use. */
static int fx_gl_make_lookup(lg_node *n, fx_gl_lookup *k, bool hetero)
{
    lg_gl_pass_desc d = { .name = hetero ? "volumetric_froxel lookup (heterogeneous)"
                                         : "volumetric_froxel lookup",
                          .stages = &fx_src_lookup,
                          .n_stages = 1,
                          .defines = hetero ? fx_gl_defines[FX_GL_HETERO] : NULL };
    int rc = lg_gl_pass_create(n, &d, &k->pass);
    if (rc)
        return rc;
    lg_gl_pass *p = k->pass;
    fx_gl_view_lookup(p, &k->v, true);
    k->size = lg_gl_pass_uniform(p, "u_size");
    k->z_limit = lg_gl_pass_uniform(p, "u_z_limit");
    k->sigma_t = lg_gl_pass_uniform(p, "u_sigma_t");
    k->energy = lg_gl_pass_uniform(p, "u_energy");
    k->slices = lg_gl_pass_storage(p, "FxSlices");
    k->base = lg_gl_pass_texture(p, "u_base");
    k->depth = lg_gl_pass_texture(p, "u_depth");
    k->acc = lg_gl_pass_image(p, "u_acc");
    k->s = lg_gl_pass_image(p, "u_s");
    k->out = lg_gl_pass_image(p, "u_out");
    k->inscatter = lg_gl_pass_image(p, "u_inscatter");
    if (hetero)
        k->path = lg_gl_pass_image(p, "u_path");
    return 0;
}

/* The buffers every variant uses, made on the first execute. */
static int fx_gl_make_buffers(lg_node *n, fx_gl *st)
{
    int rc = lg_gl_buffer_recreate(n, &st->lights_buf, VOL_MAX_LIGHTS * sizeof(fx_gl_light), 0,
                                   NULL);
    if (rc)
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
    float inv[16], ray[16], map[4];
    for (int i = 0; i < 16; i++)
        inv[i] = (float)v->inv_view_proj[i];
    vol_ray_matrix(v, ray);
    fx_gl_map_vec4(&f->map, map);
    lg_gl_set_ivec3(p, u->grid, (int32_t)f->w, (int32_t)f->h, (int32_t)f->d);
    lg_gl_set_mat4(p, u->inv_vp, inv);
    lg_gl_set_mat4(p, u->ray_vp, ray);
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

/* The records of the light whose first record is `first`: 6 for a cube, 2 for a pair of
 * paraboloids, else 1 (lg_shadowmap_record_at's rule). */
static int32_t fx_gl_n_records(const lg_shadowmap *sm, int32_t first)
{
    const lg_shadow_light *r = &sm->lights[first];
    if (r->projection != LG_SHADOW_PERSPECTIVE)
        return 1;
    if (r->face == LG_SHADOW_FACE_PARABOLOID_FRONT)
        return (uint32_t)first + 1 < sm->n_lights && sm->lights[first + 1].light == r->light ? 2
                                                                                             : 1;
    return (uint32_t)first + 5 < sm->n_lights && sm->lights[first + 5].light == r->light &&
                   sm->lights[first + 5].face == LG_SHADOW_FACE_NEG_Z
               ? 6
               : 1;
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
        g->type = (int32_t)l->type;
        memcpy(g->pos, l->pos, sizeof g->pos);
        g->range = l->range;
        g->cos_inner = l->cos_inner;
        g->cos_outer = l->cos_outer;
        g->shadow = g->rec = -1;
        if (f->sm && l->shadow >= 0 && (uint32_t)l->shadow < f->sm->n_lights) {
            const lg_shadow_light *r = &f->sm->lights[l->shadow];
            memcpy(g->view_proj, r->view_proj, sizeof g->view_proj);
            g->tile[0] = (int32_t)r->tile_x;
            g->tile[1] = (int32_t)r->tile_y;
            g->shadow = g->rec = l->shadow;
            g->n_rec = fx_gl_n_records(f->sm, l->shadow);
            /* the light's position as lg_shadowmap_record_at takes it: the view matrix is
             * [R | -R q], so q = -R^T t */
            const float *m = r->view;
            for (int c = 0; c < 3; c++)
                g->sq[c] = (float)-((double)m[c * 4 + 0] * m[12] + (double)m[c * 4 + 1] * m[13] +
                                    (double)m[c * 4 + 2] * m[14]);
        }
    }
}

/* Every record of the shadow map in FxRecords' layout (out: sm->n_lights entries). */
static void fx_gl_records(const lg_shadowmap *sm, fx_gl_record *out)
{
    for (uint32_t i = 0; i < sm->n_lights; i++) {
        const lg_shadow_light *r = &sm->lights[i];
        fx_gl_record *g = &out[i];
        memset(g, 0, sizeof *g);
        bool parab = r->face >= LG_SHADOW_FACE_PARABOLOID_FRONT;
        memcpy(g->m, parab ? r->view : r->view_proj, sizeof g->m);
        g->tile[0] = (int32_t)r->tile_x;
        g->tile[1] = (int32_t)r->tile_y;
        g->face = (int32_t)r->face;
        g->projection = (int32_t)r->projection;
        g->znear = r->znear;
        g->depth_range = r->depth_range;
    }
}

/* Heterogeneous media (froxel.h 4.): rho and the lights' tau volumes (stacked along z)
 * uploaded every frame, and the optical path's volume. */
static int fx_gl_hetero(lg_node *n, const lg_gl *gl, fx_gl *st, const fx_frame *f)
{
    const vol_setup *v = f->v;
    const vol_tau_volume *t0 = &f->tau[0];
    for (uint32_t l = 1; l < v->n_lights; l++)
        if (memcmp(f->tau[l].n, t0->n, sizeof t0->n) != 0)
            return lg_error(n,
                            "volumetric_froxel (gl): light %u's optical-depth volume is "
                            "%ux%ux%u, light 0's %ux%ux%u (the gl backend stacks them: one size)",
                            l, f->tau[l].n[0], f->tau[l].n[1], f->tau[l].n[2], t0->n[0], t0->n[1],
                            t0->n[2]);
    lg_gl_texture_desc d = {
        .target = GL_TEXTURE_3D, .format = GL_R32F, .width = f->w, .height = f->h, .depth = f->d
    };
    int made = lg_gl_texture_recreate(n, &st->density, &d);
    if (made >= 0)
        made = lg_gl_texture_recreate(n, &st->path, &d);
    if (made < 0)
        return made;
    gl->TextureSubImage3D(st->density.name, 0, 0, 0, 0, (GLsizei)f->w, (GLsizei)f->h, (GLsizei)f->d,
                          GL_RED, GL_FLOAT, f->density);
    lg_gl_texture_desc td = { .target = GL_TEXTURE_3D,
                              .format = GL_R32F,
                              .width = t0->n[0],
                              .height = t0->n[1],
                              .depth = t0->n[2] * v->n_lights };
    made = lg_gl_texture_recreate(n, &st->tau, &td);
    if (made < 0)
        return made;
    /* every frame: froxel.c may have remade a volume at the same address (a copy is
     * 4 bytes a cell, ~1 MB a light at tau_res 64, small beside the pass) */
    for (uint32_t l = 0; l < v->n_lights; l++)
        gl->TextureSubImage3D(st->tau.name, 0, 0, 0, (GLint)(l * t0->n[2]), (GLsizei)t0->n[0],
                              (GLsizei)t0->n[1], (GLsizei)t0->n[2], GL_RED, GL_FLOAT,
                              f->tau[l].tau);
    return lg_gl_check(n, "volumetric_froxel: uploading the density and optical-depth volumes");
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
        out[3 * D + 1 + k] = (float)t->tlen[k];
    }
    for (uint32_t k = 0; k <= D; k++)
        out[D + k] = (float)t->tk[k];
    return 4 * D + 1;
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
    if (!st->lights_buf.name || !st->slices_buf.name) {
        /* first frame, or an earlier attempt failed part-way: make them again */
        lg_gl_buffer_destroy(n, &st->lights_buf);
        lg_gl_buffer_destroy(n, &st->slices_buf);
        if ((rc = fx_gl_make_buffers(n, st)))
            return rc;
    }
    if (v->n_lights < 1 || v->n_lights > VOL_MAX_LIGHTS)
        return lg_error(n, "volumetric_froxel (gl): %u lights (1 .. %d)", v->n_lights,
                        VOL_MAX_LIGHTS);
    if (f->d > (FX_GL_SLICES_MAX - 1) / 4)
        return lg_error(n,
                        "volumetric_froxel (gl): grid depth %u, more than the slice table's "
                        "%d",
                        f->d, (FX_GL_SLICES_MAX - 1) / 4);

    fx_gl_light lights[VOL_MAX_LIGHTS];
    fx_gl_lights(f, lights);
    bool shadowed = false, local = false;
    for (uint32_t i = 0; i < v->n_lights; i++) {
        shadowed |= lights[i].shadow >= 0;
        local |= v->lights[i].type != LG_LIGHT_DIRECTIONAL;
    }
    /* the variant: today's pass for a homogeneous medium lit by directional lights with
     * one-texel shadows; the general one for point and spot lights or PCF */
    bool hetero = f->density != NULL;
    int var = hetero                                         ? FX_GL_HETERO
              : local || (shadowed && f->sm->pcf_radius > 0) ? FX_GL_LOCAL
                                                             : FX_GL_PLAIN;
    fx_gl_column *col = &st->col[var];
    fx_gl_lookup *look = &st->look[hetero];
    if (!col->pass && (rc = fx_gl_make_column(n, col, var)))
        return rc;
    if (!look->pass && (rc = fx_gl_make_lookup(n, look, hetero)))
        return rc;
    if ((rc = fx_gl_volumes(n, gl, st, f)))
        return rc;
    if (hetero && (rc = fx_gl_hetero(n, gl, st, f)))
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

    if (shadowed) {
        uint32_t color = 0;
        if ((rc = lg_map_gl(n, f->sm->atlas, LG_READ, &color, &atlas)))
            return rc;
        if (!atlas)
            return lg_error_code(n, LG_ERR_DEVICE,
                                 "input 'shadows': the atlas has no GL depth "
                                 "texture");
    }
    if (var != FX_GL_PLAIN) {
        /* every record of the map (at least one, so the buffer exists unshadowed) */
        uint32_t nr = shadowed ? f->sm->n_lights : 1;
        size_t bytes = nr * sizeof(fx_gl_record);
        if (st->records_buf.size < bytes &&
            (rc = lg_gl_buffer_recreate(n, &st->records_buf, bytes, 0, NULL)))
            return rc;
        fx_gl_record *recs = calloc(nr, sizeof *recs);
        if (!recs)
            return lg_error_code(n, LG_ERR_NOMEM, "volumetric_froxel (gl): out of memory");
        if (shadowed)
            fx_gl_records(f->sm, recs);
        rc = lg_gl_buffer_upload(n, &st->records_buf, 0, bytes, recs);
        free(recs);
        if (rc)
            return rc;
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
    lg_gl_pass *p = col->pass;
    if ((rc = lg_gl_pass_begin(p, NULL)))
        return rc;
    fx_gl_set_view(gl, p, &col->v, f);
    lg_gl_set_vec3v(p, col->sigma_s, v->sigma_s);
    lg_gl_set_float(p, col->g, v->g);
    lg_gl_set_int(p, col->n_lights, (int32_t)v->n_lights);
    lg_gl_set_int(p, col->shadow_res, f->sm ? (int32_t)f->sm->resolution : 1);
    lg_gl_set_float(p, col->bias, f->sm ? f->sm->bias_constant : 0.0f);
    lg_gl_set_float(p, col->history, hist ? f->history : 0.0f);
    if (hist) {
        const vol_setup *q = f->prev;
        float pmap[4];
        fx_gl_map_vec4(&f->prev_map, pmap);
        lg_gl_set_mat4(p, col->prev_vp, q->view.view_proj);
        lg_gl_set_vec3(p, col->prev_eye, (float)q->eye[0], (float)q->eye[1], (float)q->eye[2]);
        lg_gl_set_vec3(p, col->prev_fwd, (float)q->forward[0], (float)q->forward[1],
                       (float)q->forward[2]);
        lg_gl_set_int(p, col->prev_slicing, (int32_t)f->prev_map.slicing);
        lg_gl_set_vec4v(p, col->prev_map, pmap);
    }
    lg_gl_pass_bind_buffer(p, col->lights, st->lights_buf.name);
    lg_gl_pass_bind_buffer(p, col->slices, st->slices_buf.name);
    if (atlas)
        lg_gl_pass_bind_texture(p, col->atlas, atlas);
    fx_gl_bind_volume(p, col->s, s_now, GL_WRITE_ONLY);
    fx_gl_bind_volume(p, col->hist, s_prev, GL_READ_ONLY);
    lg_gl_set_vec3v(p, col->sigma_t, v->sigma_t);
    lg_gl_set_int(p, col->energy, f->accum == FX_ACC_ENERGY);
    fx_gl_bind_volume(p, col->out, grid_tex, GL_WRITE_ONLY);
    if (var != FX_GL_PLAIN) {
        lg_gl_set_int(p, col->pcf, shadowed ? (int32_t)f->sm->pcf_radius : 0);
        lg_gl_set_int(p, col->point_nodes, f->point_nodes);
        lg_gl_pass_bind_buffer(p, col->records, st->records_buf.name);
    }
    if (hetero) {
        const vol_tau_volume *t = &f->tau[0];
        lg_gl_set_vec3(p, col->tau_lo, (float)t->lo[0], (float)t->lo[1], (float)t->lo[2]);
        lg_gl_set_vec3(p, col->tau_hi, (float)t->hi[0], (float)t->hi[1], (float)t->hi[2]);
        lg_gl_set_ivec3(p, col->tau_n, (int32_t)t->n[0], (int32_t)t->n[1], (int32_t)t->n[2]);
        lg_gl_pass_bind_texture(p, col->density, st->density.name);
        /* linear filtering: froxel.h's trilinear tau, the texture unit's own weights */
        const lg_gl_sampler lin = { .filter = LG_GL_FILTER_LINEAR, .wrap = LG_GL_WRAP_CLAMP };
        lg_gl_pass_bind_texture_sampled(p, col->tau, st->tau.name, &lin);
        lg_gl_pass_bind_image_level(p, col->path, st->path.name, 0, LG_GL_ALL_LAYERS, GL_WRITE_ONLY,
                                    GL_R32F);
    }
    if ((rc = lg_gl_pass_end(p, lg_gl_pass_dispatch(p, f->w, f->h, 1))))
        return rc;

    /* 3. lookup and composite, per pixel */
    p = look->pass;
    if ((rc = lg_gl_pass_begin(p, NULL)))
        return rc;
    fx_gl_set_view(gl, p, &look->v, f);
    lg_gl_set_ivec2(p, look->size, (int32_t)v->width, (int32_t)v->height);
    lg_gl_set_float(p, look->z_limit, v->z_limit);
    lg_gl_set_vec3v(p, look->sigma_t, v->sigma_t);
    lg_gl_set_int(p, look->energy, f->accum == FX_ACC_ENERGY);
    lg_gl_pass_bind_buffer(p, look->slices, st->slices_buf.name);
    lg_gl_pass_bind_texture(p, look->base, base_tex);
    lg_gl_pass_bind_texture(p, look->depth, base_depth);
    fx_gl_bind_volume(p, look->acc, grid_tex, GL_READ_ONLY);
    fx_gl_bind_volume(p, look->s, s_now, GL_READ_ONLY);
    lg_gl_pass_bind_image(p, look->out, out_tex, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_pass_bind_image(p, look->inscatter, ins_tex, GL_WRITE_ONLY, GL_RGBA32F);
    if (hetero)
        lg_gl_pass_bind_image_level(p, look->path, st->path.name, 0, LG_GL_ALL_LAYERS, GL_READ_ONLY,
                                    GL_R32F);
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
    for (int i = 0; i < FX_GL_VARIANTS; i++)
        lg_gl_pass_destroy(&st->col[i].pass);
    for (int i = 0; i < 2; i++)
        lg_gl_pass_destroy(&st->look[i].pass);
    lg_gl_texture_destroy(n, &st->vol[0]);
    lg_gl_texture_destroy(n, &st->vol[1]);
    lg_gl_texture_destroy(n, &st->density);
    lg_gl_texture_destroy(n, &st->tau);
    lg_gl_texture_destroy(n, &st->path);
    lg_gl_buffer_destroy(n, &st->lights_buf);
    lg_gl_buffer_destroy(n, &st->slices_buf);
    lg_gl_buffer_destroy(n, &st->records_buf);
    free(st);
}
