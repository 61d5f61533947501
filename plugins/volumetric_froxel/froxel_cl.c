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
    cl_kernel columns, lookup;
    cl_mem s, hist;          /* rgba32f W x H x D each */
    cl_mem lights, shadows;  /* per frame */
    cl_mem slices;           /* per frame: T(k + jitter), t_{k+1} - t_k, T(k + 0.5), T(k) */
    float *slices_host;      /* 4 D + 1 floats */
    bool hist_valid;
} fx_cl;

static int fx_cl_init(lg_node *n, fx_cl *c, const fx_frame *f)
{
    cl_int e;
    const char *parts[] = { lg_src_medium_cl, lg_src_froxel_cl };
    char *src = lg_cl_source_join(parts, 2);
    if (!src)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    cl_program prog = lg_cl_program(n, lg_src_froxel_cl_file, src, "-cl-std=CL1.2");
    free(src);
    if (!prog)
        return LG_ERR_DEVICE;
    c->columns = clCreateKernel(prog, "fx_columns", &e);
    if (!c->columns)
        return lg_cl_fail(n, e, "clCreateKernel(fx_columns)");
    c->lookup = clCreateKernel(prog, "fx_lookup", &e);
    if (!c->lookup)
        return lg_cl_fail(n, e, "clCreateKernel(fx_lookup)");
    size_t bytes = (size_t)f->w * f->h * f->d * 16;
    c->s = clCreateBuffer(lg_cl_context(n), CL_MEM_READ_WRITE, bytes, NULL, &e);
    if (!c->s)
        return lg_cl_fail(n, e, "clCreateBuffer(S)");
    c->hist = clCreateBuffer(lg_cl_context(n), CL_MEM_READ_WRITE, bytes, NULL, &e);
    if (!c->hist)
        return lg_cl_fail(n, e, "clCreateBuffer(S history)");
    lg_account_alloc(n, 2 * (uint64_t)bytes);
    c->slices_host = malloc((4 * (size_t)f->d + 1) * sizeof(float));
    if (!c->slices_host)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    c->w = f->w;
    c->h = f->h;
    c->d = f->d;
    return 0;
}

static int fx_cl_upload(lg_node *n, cl_mem *m, const float *data, size_t floats,
                        const char *what)
{
    if (*m)
        clReleaseMemObject(*m);
    cl_int e;
    *m = clCreateBuffer(lg_cl_context(n), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                        floats * sizeof(float), (void *)data, &e);
    if (!*m)
        return lg_cl_fail(n, e, what);
    return 0;
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
    if (!lg_cl_context(n) || !lg_cl_queue(n))
        return LG_ERR_DEVICE;
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
    if ((rc = fx_cl_upload(n, &c->lights, lt, 8 * (size_t)v->n_lights, "clCreateBuffer(lights)")) ||
        (rc = fx_cl_upload(n, &c->shadows, sh, 20 * (size_t)(n_sh ? n_sh : 1),
                           "clCreateBuffer(shadow records)")))
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
    if ((rc = fx_cl_upload(n, &c->slices, c->slices_host, 4 * (size_t)f->d + 1,
                           "clCreateBuffer(slice tables)")))
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
        (rc = lg_map_cl(n, lg_part(n, lg_output(n, FX_OUT_GRID), "grid"), LG_WRITE, &grid,
                        &gd)))
        return rc;
    /* a depth-only image's plane comes as the depth mapping */
    cl_mem m_atlas = atlas_depth ? atlas_depth : atlas ? atlas : c->shadows;

    cl_int W = (cl_int)f->w, H = (cl_int)f->h, D = (cl_int)f->d;
    float ivpf[16];
    for (int i = 0; i < 16; i++)
        ivpf[i] = (float)v->inv_view_proj[i];
    cl_float16 ivp = m16(ivpf);
    cl_float4 eye = v4(v->eye[0], v->eye[1], v->eye[2], 0);
    cl_float4 fwd = v4(v->forward[0], v->forward[1], v->forward[2], 0);
    cl_float4 img = v4(v->width, v->height, 0, 0);
    cl_int slicing = (cl_int)f->map.slicing, accum = f->accum == FX_ACC_THESIS ? 0 : 1;
    cl_int grey = v->sigma_t[0] == v->sigma_t[1] && v->sigma_t[1] == v->sigma_t[2];
    cl_float4 map = map4(&f->map);
    cl_float g = v->g, history = f->history;
    cl_float4 ss = v4(v->sigma_s[0], v->sigma_s[1], v->sigma_s[2], 0);
    cl_float4 stt = v4(v->sigma_t[0], v->sigma_t[1], v->sigma_t[2], 0);
    cl_int nl = (cl_int)v->n_lights;
    cl_int aw = f->sm ? (cl_int)f->sm->atlas_width : 0, ah = f->sm ? (cl_int)f->sm->atlas_height : 0;
    cl_int res = f->sm ? (cl_int)f->sm->resolution : 0;
    cl_float bias = f->sm ? f->sm->bias_constant : 0;
    cl_int blend = f->history > 0 && f->prev && c->hist_valid;
    float zero16[16] = { 0 };
    cl_float16 pvp = m16(blend ? f->prev->view.view_proj : zero16);
    cl_float4 peye = blend ? v4(f->prev->eye[0], f->prev->eye[1], f->prev->eye[2], 0)
                           : v4(0, 0, 0, 0);
    cl_float4 pfwd = blend ? v4(f->prev->forward[0], f->prev->forward[1], f->prev->forward[2], 0)
                           : v4(0, 0, 1, 0);
    cl_int pslicing = blend ? (cl_int)f->prev_map.slicing : slicing;
    cl_float4 pmap = blend ? map4(&f->prev_map) : map;
    cl_mem m_grid = grid;

    cl_kernel k = c->columns;
    cl_uint a = 0;
    cl_int e = 0;
#define ARG(x) (e |= clSetKernelArg(k, a++, sizeof(x), &(x)))
    ARG(W), ARG(H), ARG(D), ARG(ivp), ARG(eye), ARG(fwd), ARG(img), ARG(c->slices);
    ARG(accum), ARG(grey), ARG(ss), ARG(stt), ARG(g), ARG(nl), ARG(c->lights);
    ARG(c->shadows), ARG(m_atlas), ARG(aw), ARG(ah), ARG(res), ARG(bias), ARG(blend);
    ARG(history), ARG(pvp), ARG(peye), ARG(pfwd), ARG(pslicing), ARG(pmap), ARG(c->hist);
    ARG(c->s), ARG(m_grid);
    if (e)
        return lg_cl_fail(n, e, "clSetKernelArg(fx_columns)");
    cl_command_queue q = lg_cl_queue(n);
    size_t gsz = (size_t)f->w * f->h;
    cl_event ev;
    if ((e = clEnqueueNDRangeKernel(q, k, 1, NULL, &gsz, NULL, 0, NULL, &ev)))
        return lg_cl_fail(n, e, "clEnqueueNDRangeKernel(fx_columns)");
    lg_cl_profile(n, ev);

    k = c->lookup;
    a = 0;
    cl_float zl = v->z_limit;
    cl_mem mb = base, mbd = base_depth, mo = out, mod = out_depth, mi = ins;
    ARG(W), ARG(H), ARG(D), ARG(ivp), ARG(eye), ARG(fwd), ARG(img), ARG(slicing), ARG(map);
    ARG(c->slices), ARG(zl), ARG(accum), ARG(grey), ARG(stt), ARG(m_grid), ARG(c->s), ARG(mb), ARG(mbd), ARG(mo);
    ARG(mod), ARG(mi);
#undef ARG
    if (e)
        return lg_cl_fail(n, e, "clSetKernelArg(fx_lookup)");
    gsz = (size_t)v->width * v->height;
    if ((e = clEnqueueNDRangeKernel(q, k, 1, NULL, &gsz, NULL, 0, NULL, &ev)))
        return lg_cl_fail(n, e, "clEnqueueNDRangeKernel(fx_lookup)");
    lg_cl_profile(n, ev);
    /* this frame's blended S is the next frame's history */
    cl_mem t = c->s;
    c->s = c->hist;
    c->hist = t;
    c->hist_valid = true;
    return 0;
}

void fx_cl_destroy(lg_node *n, void *state)
{
    (void)n;
    fx_cl *c = state;
    if (!c)
        return;
    if (c->columns)
        clReleaseKernel(c->columns);
    if (c->lookup)
        clReleaseKernel(c->lookup);
    cl_mem m[5] = { c->s, c->hist, c->lights, c->shadows, c->slices };
    for (int i = 0; i < 5; i++)
        if (m[i])
            clReleaseMemObject(m[i]);
    free(c->slices_host);
    free(c);
}
