/*
 * The cl backend of volumetric_froxel: froxel.h's passes as two kernels of
 * shaders/volumetric_froxel/froxel.cl (built after shaders/common/medium.cl): fx_columns
 * (light pass and accumulation fused, one work-item per column, as the cpu backend does)
 * and fx_lookup (one work-item per pixel). S and its history are two buffers of this
 * backend, swapped after each frame; base, the shadow atlas and the outputs are the host's
 * CL buffers (lg_map_cl).
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
    lg_cl_buffer s, hist;         /* rgba32f W x H x D each */
    lg_cl_buffer lights, shadows; /* per frame */
    lg_cl_buffer slices;          /* per frame: T(k + jitter), t_{k+1} - t_k, T(k + 0.5), T(k) */
    float *slices_host;           /* 4 D + 1 floats */
    bool hist_valid;
} fx_cl;

static int fx_cl_init(lg_node *n, fx_cl *c, const fx_frame *f)
{
    static const char *const src[] = { lg_src_medium_cl, lg_src_froxel_cl };
    static const char *const names[] = { lg_src_medium_cl_file, lg_src_froxel_cl_file };
    lg_cl_pass_desc d = { .name = "froxel columns",
                          .sources = src,
                          .source_names = names,
                          .n_sources = 2,
                          .options = "-cl-std=CL1.2",
                          .kernel = "fx_columns" };
    int rc;
    if ((rc = lg_cl_pass_create(n, &d, &c->columns)))
        return rc;
    d.name = "froxel lookup", d.kernel = "fx_lookup";
    if ((rc = lg_cl_pass_create(n, &d, &c->lookup)))
        return rc;
    size_t bytes = (size_t)f->w * f->h * f->d * 16;
    if ((rc = lg_cl_buffer_recreate(n, &c->s, bytes, 0)) ||
        (rc = lg_cl_buffer_recreate(n, &c->hist, bytes, 0)))
        return rc;
    c->slices_host = malloc((4 * (size_t)f->d + 1) * sizeof(float));
    if (!c->slices_host)
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

    /* lights and shadow records (froxel.cl's layout) */
    float lt[VOL_MAX_LIGHTS * 8];
    float sh[VOL_MAX_LIGHTS * 20];
    uint32_t n_sh = 0;
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_light *L = &v->lights[l];
        float *o = lt + 8 * l;
        int rec = -1;
        if (f->sm && L->shadow >= 0 && (uint32_t)L->shadow < f->sm->n_lights) {
            const lg_shadow_light *s = &f->sm->lights[L->shadow];
            memcpy(sh + 20 * n_sh, s->view_proj, 16 * sizeof(float));
            sh[20 * n_sh + 16] = (float)s->tile_x;
            sh[20 * n_sh + 17] = (float)s->tile_y;
            sh[20 * n_sh + 18] = sh[20 * n_sh + 19] = 0;
            rec = (int)n_sh++;
        }
        o[0] = L->dir[0], o[1] = L->dir[1], o[2] = L->dir[2], o[3] = (float)rec;
        o[4] = L->l_c[0], o[5] = L->l_c[1], o[6] = L->l_c[2], o[7] = 0;
    }
    if (!n_sh)
        memset(sh, 0, 20 * sizeof(float));
    if ((rc = fx_cl_upload(n, &c->lights, lt, 8 * (size_t)v->n_lights)) ||
        (rc = fx_cl_upload(n, &c->shadows, sh, 20 * (size_t)(n_sh ? n_sh : 1))))
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

    lg_cl_pass *k = c->columns;
    unsigned a = 0;
#define ARG(x) lg_cl_pass_arg(k, a++, sizeof(x), &(x))
    lg_cl_pass_arg_int(k, a++, W), lg_cl_pass_arg_int(k, a++, H), lg_cl_pass_arg_int(k, a++, D);
    ARG(ivp), ARG(eye), ARG(fwd), ARG(img);
    lg_cl_pass_arg_mem(k, a++, c->slices.mem);
    lg_cl_pass_arg_int(k, a++, accum), lg_cl_pass_arg_int(k, a++, grey);
    ARG(ss), ARG(stt);
    lg_cl_pass_arg_float(k, a++, v->g);
    lg_cl_pass_arg_int(k, a++, (int32_t)v->n_lights);
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
    size_t gsz = (size_t)f->w * f->h;
    if ((rc = lg_cl_pass_run(k, 1, &gsz, NULL)))
        return rc;

    k = c->lookup;
    a = 0;
    lg_cl_pass_arg_int(k, a++, W), lg_cl_pass_arg_int(k, a++, H), lg_cl_pass_arg_int(k, a++, D);
    ARG(ivp), ARG(eye), ARG(fwd), ARG(img);
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
    lg_cl_buffer *m[5] = { &c->s, &c->hist, &c->lights, &c->shadows, &c->slices };
    for (int i = 0; i < 5; i++)
        lg_cl_buffer_destroy(n, m[i]);
    free(c->slices_host);
    free(c);
}
