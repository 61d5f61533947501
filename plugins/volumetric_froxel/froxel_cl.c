/*
 * The cl backend of volumetric_froxel: froxel.h's passes as two kernels of
 * shaders/volumetric_froxel/froxel.cl (built after shaders/common/medium.cl): fx_columns
 * (light pass and accumulation fused, one work-item per column, as the cpu backend does)
 * and fx_lookup (one work-item per pixel). S and its history are two buffers of this
 * backend, swapped after each frame; base, the shadow atlas and the outputs are the host's
 * CL buffers (lg_map_cl).
 *
 * Point and spot lights and heterogeneous media (froxel.h 4.) run in a second build of the
 * same two kernels (-DFX_FULL=1, made on the first frame that needs it): a frame with only
 * directional lights in a homogeneous medium runs the FX_FULL=0 build, whose code is what
 * it was before (the added branches are compiled away). The full build takes, per frame,
 * the point and spot lights (`locals`), every shadow record of theirs (a point light's six
 * cube faces or two paraboloids, chosen per sample), and for a field the density volume
 * rho (W x H x D floats, froxel.c's), each light's optical-depth volume (`tau`, one buffer,
 * and `taud`, where each lies) and the optical path P (W x H x D floats, written by the
 * columns, read by the lookup). All are lg_cl_buffers, counted in the profile.
 */
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/lightgraph.h"

#include "froxel.cl.h"
#include "froxel.h"
#include "medium.cl.h"

typedef struct fx_cl {
    uint32_t w, h, d;
    lg_cl_pass *columns, *lookup;
    lg_cl_pass *columns_full, *lookup_full; /* -DFX_FULL=1: made when first needed */
    lg_cl_buffer s, hist;                   /* rgba32f W x H x D each */
    lg_cl_buffer locals;                    /* per frame: FX_LOCAL floats per point or spot light */
    lg_cl_buffer density, path;             /* heterogeneous: W x H x D floats each */
    lg_cl_buffer tau, taud;       /* heterogeneous: the optical-depth volumes, their places */
    lg_cl_buffer lights, shadows; /* per frame */
    lg_cl_buffer slices;          /* per frame: T(k + jitter), t_{k+1} - t_k, T(k + 0.5), T(k) */
    float *slices_host;           /* 4 D + 1 floats */
    float *sh_host;               /* FX_REC floats per record, six records per light */
    bool hist_valid;
} fx_cl;

/* the full build's work-group size (fx_cl_execute) */
#define FX_CL_FULL_GROUP 64

/* froxel.cl's record and light strides */
#define FX_REC 24
#define FX_LOCAL 20

/* The two passes of one build of froxel.cl (full: -DFX_FULL=1). */
static int fx_cl_passes(lg_node *n, bool full, lg_cl_pass **columns, lg_cl_pass **lookup)
{
    static const char *const src[] = { lg_src_medium_cl, lg_src_froxel_cl };
    static const char *const names[] = { lg_src_medium_cl_file, lg_src_froxel_cl_file };
    lg_cl_pass_desc d = { .name = full ? "froxel columns (local lights, fields)" : "froxel columns",
                          .sources = src,
                          .source_names = names,
                          .n_sources = 2,
                          .options = full ? "-cl-std=CL1.2 -DFX_FULL=1" : "-cl-std=CL1.2",
                          .kernel = "fx_columns" };
    int rc;
    if ((rc = lg_cl_pass_create(n, &d, columns)))
        return rc;
    d.name = full ? "froxel lookup (fields)" : "froxel lookup", d.kernel = "fx_lookup";
    return lg_cl_pass_create(n, &d, lookup);
}

static int fx_cl_init(lg_node *n, fx_cl *c, const fx_frame *f)
{
    int rc;
    if ((rc = fx_cl_passes(n, false, &c->columns, &c->lookup)))
        return rc;
    size_t bytes = (size_t)f->w * f->h * f->d * 16;
    if ((rc = lg_cl_buffer_recreate(n, &c->s, bytes, 0)) ||
        (rc = lg_cl_buffer_recreate(n, &c->hist, bytes, 0)))
        return rc;
    c->slices_host = malloc((4 * (size_t)f->d + 1) * sizeof(float));
    c->sh_host = malloc(VOL_MAX_LIGHTS * 6 * FX_REC * sizeof(float));
    if (!c->slices_host || !c->sh_host)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    c->w = f->w;
    c->h = f->h;
    c->d = f->d;
    return 0;
}

/* A table of this frame's, in a buffer kept while large enough. */
static int fx_cl_upload(lg_node *n, lg_cl_buffer *b, const float *data, size_t floats)
{
    int rc = lg_cl_buffer_recreate(n, b, floats * sizeof(float), CL_MEM_READ_ONLY);
    return rc ? rc : lg_cl_buffer_write(n, b, 0, floats * sizeof(float), data);
}

static cl_float16 m16(const float *m)
{
    cl_float16 r;
    memcpy(r.s, m, sizeof r.s);
    return r;
}

static cl_float4 v4(double a, double b, double c, double d)
{
    cl_float4 r = { { (float)a, (float)b, (float)c, (float)d } };
    return r;
}

static cl_float4 map4(const lg_slice_map *m)
{
    return v4(m->near, m->far, m->near_offset, m->depth);
}

/* How many consecutive records from `first` are one light's maps: six for a cube, two for
 * a dual paraboloid, else one (lg_shadowmap_record_at's rule). */
static uint32_t fx_cl_faces(const lg_shadowmap *sm, uint32_t first)
{
    const lg_shadow_light *r = &sm->lights[first];
    if (r->projection != LG_SHADOW_PERSPECTIVE)
        return 1;
    if (r->face == LG_SHADOW_FACE_PARABOLOID_FRONT)
        return first + 1 < sm->n_lights && sm->lights[first + 1].light == r->light ? 2 : 1;
    bool cube = first + 5 < sm->n_lights && sm->lights[first + 5].light == r->light &&
                sm->lights[first + 5].face == LG_SHADOW_FACE_NEG_Z;
    return cube ? 6 : 1;
}

/* One record in froxel.cl's layout (FX_REC floats): view_proj (a paraboloid's view),
 * tile, face, znear, depth_range. */
static void fx_cl_record(const lg_shadow_light *r, float *o)
{
    memset(o, 0, FX_REC * sizeof(float));
    bool parab = r->projection == LG_SHADOW_PERSPECTIVE &&
                 r->face >= LG_SHADOW_FACE_PARABOLOID_FRONT;
    memcpy(o, parab ? r->view : r->view_proj, 16 * sizeof(float));
    o[16] = (float)r->tile_x;
    o[17] = (float)r->tile_y;
    o[18] = r->projection == LG_SHADOW_PERSPECTIVE ? (float)r->face : 0.0f;
    o[19] = r->znear;
    o[20] = r->depth_range;
}

/* The light's position as its first record's view matrix [R | -R q] gives it, q = -R^T t
 * (lg_shadowmap_record_at picks a cube face around this point). */
static void fx_cl_light_position(const lg_shadow_light *r, float q[3])
{
    const float *m = r->view;
    for (int c = 0; c < 3; c++)
        q[c] = (float)-((double)m[c * 4 + 0] * m[12] + (double)m[c * 4 + 1] * m[13] +
                        (double)m[c * 4 + 2] * m[14]);
}

/* Heterogeneous medium: rho (froxel.c's W x H x D multipliers), every light's optical-depth
 * volume one after the other in `tau` with its box, size and offset in `taud` (12 floats a
 * light, froxel.cl's fx_tau), and room for the optical path. The volumes are uploaded each
 * frame (froxel.c remakes them only when a light or the scene changes; a frame's upload is
 * 4 bytes a cell, 1 MiB a light at the default 64 cells a side). */
static int fx_cl_fields(lg_node *n, fx_cl *c, const fx_frame *f)
{
    const vol_setup *v = f->v;
    size_t vox = (size_t)f->w * f->h * f->d, cells = 0;
    float td[VOL_MAX_LIGHTS * 12];
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_tau_volume *t = &f->tau[l];
        float *o = td + 12 * l;
        memset(o, 0, 12 * sizeof(float));
        for (int a = 0; a < 3; a++) {
            o[a] = (float)t->lo[a];
            o[3 + a] = (float)t->hi[a];
            o[6 + a] = (float)t->n[a];
        }
        if (cells > INT32_MAX)
            return lg_error(n, "the optical-depth volumes hold more than 2^31 cells");
        int32_t off = (int32_t)cells;
        memcpy(o + 9, &off, sizeof off);
        cells += (size_t)t->n[0] * t->n[1] * t->n[2];
    }
    int rc;
    if ((rc = fx_cl_upload(n, &c->density, f->density, vox)) ||
        (rc = lg_cl_buffer_recreate(n, &c->path, vox * sizeof(float), 0)) ||
        (rc = fx_cl_upload(n, &c->taud, td, 12 * (size_t)v->n_lights)) ||
        (rc = lg_cl_buffer_recreate(n, &c->tau, cells * sizeof(float), CL_MEM_READ_ONLY)))
        return rc;
    size_t at = 0;
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_tau_volume *t = &f->tau[l];
        size_t nc = (size_t)t->n[0] * t->n[1] * t->n[2];
        if ((rc = lg_cl_buffer_write(n, &c->tau, at * sizeof(float), nc * sizeof(float), t->tau)))
            return rc;
        at += nc;
    }
    return 0;
}

int fx_cl_execute(lg_node *n, void **state, const fx_frame *f)
{
    fx_cl *c = *state;
    if (c && (c->w != f->w || c->h != f->h || c->d != f->d)) {
        fx_cl_destroy(n, c);
        *state = c = NULL;
    }
    int rc;
    if (!c) {
        c = calloc(1, sizeof *c);
        if (!c)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
        *state = c;
        if ((rc = fx_cl_init(n, c, f))) {
            fx_cl_destroy(n, c);
            *state = NULL;
            return rc;
        }
    }
    const vol_setup *v = f->v;

    /* lights and shadow records (froxel.cl's layout): directional lights in `lights`, point
     * and spot lights in `locals`, the records of both in `shadows` */
    float lt[VOL_MAX_LIGHTS * 8];
    float loc[VOL_MAX_LIGHTS * FX_LOCAL];
    float *sh = c->sh_host; /* at most six records a light */
    uint32_t n_sh = 0, n_dir = 0, n_loc = 0;
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_light *L = &v->lights[l];
        int first = -1;
        uint32_t faces = 0;
        if (f->sm && L->shadow >= 0 && (uint32_t)L->shadow < f->sm->n_lights) {
            faces = fx_cl_faces(f->sm, (uint32_t)L->shadow);
            first = (int)n_sh;
            for (uint32_t r = 0; r < faces; r++)
                fx_cl_record(&f->sm->lights[L->shadow + r], sh + FX_REC * n_sh++);
        }
        if (L->type == LG_LIGHT_DIRECTIONAL) {
            float *o = lt + 8 * n_dir++;
            o[0] = L->dir[0], o[1] = L->dir[1], o[2] = L->dir[2], o[3] = (float)first;
            o[4] = L->l_c[0], o[5] = L->l_c[1], o[6] = L->l_c[2], o[7] = (float)l;
            continue;
        }
        float *o = loc + FX_LOCAL * n_loc++;
        memset(o, 0, FX_LOCAL * sizeof(float));
        o[0] = L->pos[0], o[1] = L->pos[1], o[2] = L->pos[2], o[3] = L->range;
        o[4] = L->dir[0], o[5] = L->dir[1], o[6] = L->dir[2];
        o[7] = L->type == LG_LIGHT_SPOT ? 1.0f : 0.0f;
        o[8] = L->l_c[0], o[9] = L->l_c[1], o[10] = L->l_c[2], o[11] = (float)first;
        o[12] = L->cos_inner, o[13] = L->cos_outer, o[14] = (float)faces, o[15] = (float)l;
        for (int a = 0; a < 3; a++)
            o[16 + a] = L->pos[a];
        if (first >= 0)
            fx_cl_light_position(&f->sm->lights[L->shadow], o + 16);
    }
    if (!n_sh)
        memset(sh, 0, FX_REC * sizeof(float));
    if (!n_dir)
        memset(lt, 0, 8 * sizeof(float));
    if (!n_loc)
        memset(loc, 0, FX_LOCAL * sizeof(float));
    /* a kernel of (2 r + 1)^2 taps per sample: a radius past the tile is a bad map */
    if (f->sm && n_sh && f->sm->pcf_radius > f->sm->resolution)
        return lg_error(n,
                        "the shadow map's pcf_radius %u is larger than its tiles (%u texels): "
                        "refused",
                        f->sm->pcf_radius, f->sm->resolution);
    bool het = f->density && f->tau;
    bool full = n_loc > 0 || het;
    if ((rc = fx_cl_upload(n, &c->lights, lt, 8 * (size_t)(n_dir ? n_dir : 1))) ||
        (rc = fx_cl_upload(n, &c->shadows, sh, FX_REC * (size_t)(n_sh ? n_sh : 1))))
        return rc;
    if (full && !c->columns_full && (rc = fx_cl_passes(n, true, &c->columns_full, &c->lookup_full)))
        return rc;
    if (full && (rc = fx_cl_upload(n, &c->locals, loc, FX_LOCAL * (size_t)(n_loc ? n_loc : 1))))
        return rc;
    if (het && (rc = fx_cl_fields(n, c, f)))
        return rc;

    /* the slice tables (froxel.cl's fx_columns and fx_lookup): T(k + jitter), the steps,
     * T(k + 0.5), T(k) for k <= D */
    const fx_slices *tab = f->slices;
    for (uint32_t k = 0; k < f->d; k++) {
        c->slices_host[k] = (float)tab->tj[k];
        c->slices_host[f->d + k] = (float)tab->tlen[k];
        c->slices_host[2 * f->d + k] = (float)tab->tq[k];
    }
    for (uint32_t k = 0; k <= f->d; k++)
        c->slices_host[3 * f->d + k] = (float)tab->tk[k];
    if ((rc = fx_cl_upload(n, &c->slices, c->slices_host, 4 * (size_t)f->d + 1)))
        return rc;

    void *base, *base_depth, *atlas = NULL, *atlas_depth = NULL, *out, *out_depth, *ins, *insd,
                             *grid, *gd;
    if ((rc = lg_map_cl(n, lg_input(n, VOL_IN_BASE), LG_READ, &base, &base_depth)))
        return rc;
    if (!base_depth)
        return lg_error(n, "input 'base' has no depth plane");
    if (f->sm && n_sh && (rc = lg_map_cl(n, f->sm->atlas, LG_READ, &atlas, &atlas_depth)))
        return rc;
    if ((rc = lg_map_cl(n, lg_output(n, VOL_OUT_OUT), LG_WRITE, &out, &out_depth)) ||
        (rc = lg_map_cl(n, lg_output(n, VOL_OUT_INSCATTER), LG_WRITE, &ins, &insd)) ||
        (rc = lg_map_cl(n, lg_part(n, lg_output(n, FX_OUT_GRID), "grid"), LG_WRITE, &grid, &gd)))
        return rc;
    /* a depth-only image's plane comes as the depth mapping */
    cl_mem m_atlas = atlas_depth ? atlas_depth : atlas ? atlas : c->shadows.mem;

    int32_t W = (int32_t)f->w, H = (int32_t)f->h, D = (int32_t)f->d;
    float ivpf[16];
    for (int i = 0; i < 16; i++)
        ivpf[i] = (float)v->inv_view_proj[i];
    cl_float16 ivp = m16(ivpf);
    vol_ray_matrix(v, ivpf);
    cl_float16 rvp = m16(ivpf);
    cl_float4 eye = v4(v->eye[0], v->eye[1], v->eye[2], 0);
    cl_float4 fwd = v4(v->forward[0], v->forward[1], v->forward[2], 0);
    cl_float4 img = v4(v->width, v->height, 0, 0);
    int32_t slicing = (int32_t)f->map.slicing, accum = f->accum == FX_ACC_THESIS ? 0 : 1;
    int32_t grey = v->sigma_t[0] == v->sigma_t[1] && v->sigma_t[1] == v->sigma_t[2];
    cl_float4 map = map4(&f->map);
    cl_float4 ss = v4(v->sigma_s[0], v->sigma_s[1], v->sigma_s[2], 0);
    cl_float4 stt = v4(v->sigma_t[0], v->sigma_t[1], v->sigma_t[2], 0);
    int32_t blend = f->history > 0 && f->prev && c->hist_valid;
    float zero16[16] = { 0 };
    cl_float16 pvp = m16(blend ? f->prev->view.view_proj : zero16);
    cl_float4 peye = blend ? v4(f->prev->eye[0], f->prev->eye[1], f->prev->eye[2], 0)
                           : v4(0, 0, 0, 0);
    cl_float4 pfwd = blend ? v4(f->prev->forward[0], f->prev->forward[1], f->prev->forward[2], 0)
                           : v4(0, 0, 1, 0);
    cl_float4 pmap = blend ? map4(&f->prev_map) : map;

    lg_cl_pass *k = full ? c->columns_full : c->columns;
    unsigned a = 0;
#define ARG(x) lg_cl_pass_arg(k, a++, sizeof(x), &(x))
    lg_cl_pass_arg_int(k, a++, W), lg_cl_pass_arg_int(k, a++, H), lg_cl_pass_arg_int(k, a++, D);
    ARG(ivp), ARG(rvp), ARG(eye), ARG(fwd), ARG(img);
    lg_cl_pass_arg_mem(k, a++, c->slices.mem);
    lg_cl_pass_arg_int(k, a++, accum), lg_cl_pass_arg_int(k, a++, grey);
    ARG(ss), ARG(stt);
    lg_cl_pass_arg_float(k, a++, v->g);
    lg_cl_pass_arg_int(k, a++, (int32_t)n_dir);
    lg_cl_pass_arg_mem(k, a++, c->lights.mem);
    lg_cl_pass_arg_mem(k, a++, c->shadows.mem);
    lg_cl_pass_arg_mem(k, a++, m_atlas);
    lg_cl_pass_arg_int(k, a++, f->sm ? (int32_t)f->sm->atlas_width : 0);
    lg_cl_pass_arg_int(k, a++, f->sm ? (int32_t)f->sm->atlas_height : 0);
    lg_cl_pass_arg_int(k, a++, f->sm ? (int32_t)f->sm->resolution : 0);
    lg_cl_pass_arg_float(k, a++, f->sm ? f->sm->bias_constant : 0);
    lg_cl_pass_arg_int(k, a++, blend);
    lg_cl_pass_arg_float(k, a++, f->history);
    ARG(pvp), ARG(peye), ARG(pfwd);
    lg_cl_pass_arg_int(k, a++, blend ? (int32_t)f->prev_map.slicing : slicing);
    ARG(pmap);
    lg_cl_pass_arg_mem(k, a++, c->hist.mem);
    lg_cl_pass_arg_mem(k, a++, c->s.mem);
    lg_cl_pass_arg_mem(k, a++, grid);
    /* froxel.h 4. (FX_FULL; the other build ignores them): absent buffers are a stand-in */
    cl_mem none = c->shadows.mem;
    lg_cl_pass_arg_int(k, a++, (int32_t)n_loc);
    lg_cl_pass_arg_mem(k, a++, full ? c->locals.mem : none);
    lg_cl_pass_arg_int(k, a++, f->point_nodes < 0 ? 0 : f->point_nodes > 8 ? 8 : f->point_nodes);
    lg_cl_pass_arg_int(k, a++, f->sm ? (int32_t)f->sm->pcf_radius : 0);
    lg_cl_pass_arg_int(k, a++, het);
    lg_cl_pass_arg_mem(k, a++, het ? c->density.mem : none);
    lg_cl_pass_arg_mem(k, a++, het ? c->tau.mem : none);
    lg_cl_pass_arg_mem(k, a++, het ? c->taud.mem : none);
    lg_cl_pass_arg_mem(k, a++, het ? c->path.mem : none);
    size_t gsz = (size_t)f->w * f->h;
    /* The full build's work-items hold ~2.6 KiB of private arrays (per-light constants of 32
     * lights): with the work-group PoCL picks itself, `lightgraph conform` crashed (SIGSEGV,
     * its default 190 x 90 x 128 grid, a point light) in its forked runs; with 64 columns a
     * group it does not (taken to be the group's private memory on a worker's stack; a
     * plain render of that grid did not crash either way). The kernel skips columns past
     * W H. */
    size_t lsz = FX_CL_FULL_GROUP;
    if (full)
        gsz = (gsz + lsz - 1) / lsz * lsz;
    if ((rc = lg_cl_pass_run(k, 1, &gsz, full ? &lsz : NULL)))
        return rc;

    k = full ? c->lookup_full : c->lookup;
    a = 0;
    lg_cl_pass_arg_int(k, a++, W), lg_cl_pass_arg_int(k, a++, H), lg_cl_pass_arg_int(k, a++, D);
    ARG(ivp), ARG(rvp), ARG(eye), ARG(fwd), ARG(img);
    lg_cl_pass_arg_int(k, a++, slicing);
    ARG(map);
    lg_cl_pass_arg_mem(k, a++, c->slices.mem);
    lg_cl_pass_arg_float(k, a++, v->z_limit);
    lg_cl_pass_arg_int(k, a++, accum), lg_cl_pass_arg_int(k, a++, grey);
    ARG(stt);
    lg_cl_pass_arg_mem(k, a++, grid);
    lg_cl_pass_arg_mem(k, a++, c->s.mem);
    lg_cl_pass_arg_mem(k, a++, base), lg_cl_pass_arg_mem(k, a++, base_depth);
    lg_cl_pass_arg_mem(k, a++, out), lg_cl_pass_arg_mem(k, a++, out_depth);
    lg_cl_pass_arg_mem(k, a++, ins);
    lg_cl_pass_arg_int(k, a++, het);
    lg_cl_pass_arg_mem(k, a++, het ? c->density.mem : none);
    lg_cl_pass_arg_mem(k, a++, het ? c->path.mem : none);
#undef ARG
    gsz = (size_t)v->width * v->height;
    if ((rc = lg_cl_pass_run(k, 1, &gsz, NULL)))
        return rc;
    /* this frame's blended S is the next frame's history */
    lg_cl_buffer t = c->s;
    c->s = c->hist;
    c->hist = t;
    c->hist_valid = true;
    return 0;
}

void fx_cl_destroy(lg_node *n, void *state)
{
    fx_cl *c = state;
    if (!c)
        return;
    lg_cl_pass_destroy(&c->columns);
    lg_cl_pass_destroy(&c->lookup);
    lg_cl_pass_destroy(&c->columns_full);
    lg_cl_pass_destroy(&c->lookup_full);
    lg_cl_buffer *m[10] = { &c->s,      &c->hist,    &c->lights, &c->shadows, &c->slices,
                            &c->locals, &c->density, &c->path,   &c->tau,     &c->taud };
    for (int i = 0; i < 10; i++)
        lg_cl_buffer_destroy(n, m[i]);
    free(c->slices_host);
    free(c->sh_host);
    free(c);
}
