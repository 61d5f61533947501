/*
 * The volumetric_screen plugin: screen-space light shafts after Mitchell 2007 (seed 2
 * 3.2.1, eq. 6-8; TECHNIQUES.md §6; GPU Gems 3 ch. 13), one pass over the pixels on GL (a
 * fragment pass, shaders/volumetric_screen/vs_screen.frag) or on the CPU (the host's thread
 * pool, vs_pixel below, the same float arithmetic).
 *
 * For every pixel p and light l whose screen position p_l is known, N samples
 * p_i = p + i (p_l - p) / N (i = 1..N) read the depth of `base`; a sample is visible
 * (V_i = 1) when it lies inside the image and its depth is at or beyond the light's: the
 * sky (depth 1) for a directional light, the light's own window depth z_l for a point or
 * spot light (a surface in front of the light occludes it, one behind it does not). With
 * the weights w_i = decay^i (or decay^(64 i / N) with normalize = true):
 *
 *   model = thesis     L_v = exposure weight L_c F_e sum_i w_i V_i / N     (eq. 6; / sum_i w_i
 *                      with normalize = true); F_e = 1 for a directional light, the light's
 *                      falloff at the camera (lg_light_falloff at the eye: W C / (d^2 + eps^2))
 *                      for a point or spot light
 *   model = physical   L_v = exposure L_c sigma_s A M,  M = sum_i w_i V_i / sum_i w_i
 *                      (Mitchell's occlusion estimate), A the unshadowed in-scattering along
 *                      the view ray up to d (vol_fog_length): p_HG(g, w.(-L)) d seg(sigma_t d)
 *                      for a directional light, the airlight integral lg_point_inscatter
 *                      (VS_AIRLIGHT_NODES Gauss-Legendre nodes, its window, cone and
 *                      extinction) for a point or spot light: the glow centred on the light
 *
 * summed over the lights. out = base + L_v (thesis: no extinction), base e^(-sigma_t d) +
 * L_v (physical). No memory beyond the two outputs.
 *
 * Lights without a screen position: clip = view_proj (-L, 0) (directional) or
 * view_proj (q, 1) (point, spot); w = clip.w <= 0 (behind the camera, or in its plane: a
 * point light at the camera) contributes nothing, as the method has no samples to take:
 * the effect fades out as the light leaves the view (README.md, "A light behind the
 * camera", says why this and not the negative blur). A light whose p_l is further than
 * 2 (N + 1)(W + H) pixels from the image contributes nothing either, which is exact (every
 * p_i then lies outside the image) and keeps inf out of the arithmetic as w -> 0+.
 * README.md gives the ports, parameters, equations and measurements.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/scene.h"

#include "vol_common.h"

#include "vs_fullscreen.vert.h"
#include "vs_screen.frag.h"

enum { VS_THESIS = 0, VS_PHYSICAL };

/* Gauss-Legendre nodes of a point or spot light's airlight integral per pixel (one panel,
 * the GLSL twin's maximum; vs_screen.frag's VS_AIRLIGHT_NODES). Its error against 64 nodes
 * is in README.md ("What is computed"). */
#define VS_AIRLIGHT_NODES 8

typedef struct vs_state {
    int model;
    lg_device backend;
    bool normalize, per_frame;
    uint32_t samples;
    float exposure, decay, weight, z_limit;
    uint32_t width, height;

    /* [0]: directional lights only (the pass as before issue 25), [1]: with point and spot
     * lights (VS_LOCAL_LIGHTS); each made on first use */
    lg_gl_pass *pass[2];
    lg_gl_binding b_params[2], b_base[2], b_depth[2];
    bool reported_nonfinite; /* base's NaN/Inf pixels said (lg_check_input_finite) */
} vs_state;

/* What one frame computes with: per light its screen position and colour, the sums. */
typedef struct vs_frame {
    vol_setup v;
    float pos[VOL_MAX_LIGHTS][4];  /* xy pixels, z 1 = contributes, w the visible depth
                                    * (1 = sky: directional; z_l: point, spot) */
    float lc[VOL_MAX_LIGHTS][4];   /* L_c (x F_e, thesis, point and spot) */
    float to[VOL_MAX_LIGHTS][4];   /* xyz: -L (directional) or the spot's axis; w: the type
                                    * (0 directional, 1 point, 2 spot) */
    float q[VOL_MAX_LIGHTS][4];    /* point, spot: xyz the position, w the range */
    float cone[VOL_MAX_LIGHTS][4]; /* spot: x cos_inner, y cos_outer */
    float k;                       /* log2 of one step's decay */
    float wt[1025];                /* cpu: wt[i] = exp2f(i k), the shader's values */
    float norm;                    /* 1 / N or 1 / sum of weights */
    float scale;                   /* exposure weight (thesis) or exposure (physical) */
    uint32_t active;
} vs_frame;

/* The pass's uniform block VsParams (std140, shaders/volumetric_screen/vs_screen.frag),
 * uploaded with one lg_gl_pass_uniforms per frame. */
typedef struct vs_gpu_params {
    float inv_view_proj[16];
    float light_pos[VOL_MAX_LIGHTS][4];
    float light_c[VOL_MAX_LIGHTS][4];
    float light_to[VOL_MAX_LIGHTS][4];
    float light_q[VOL_MAX_LIGHTS][4];
    float light_cone[VOL_MAX_LIGHTS][4];
    float eye[3];
    float z_limit;
    float forward[3];
    float g;
    float sigma_s[3];
    float k;
    float sigma_t[3];
    float norm;
    int32_t size[2];
    int32_t samples;
    int32_t lights;
    int32_t physical;
    float scale;
    float pad_[2];
} vs_gpu_params;

LG_GL_BLOCK_SIZE(vs_gpu_params, 2720);
LG_GL_BLOCK_OFFSET(vs_gpu_params, light_pos, 64);
LG_GL_BLOCK_OFFSET(vs_gpu_params, light_to, 1088);
LG_GL_BLOCK_OFFSET(vs_gpu_params, light_q, 1600);
LG_GL_BLOCK_OFFSET(vs_gpu_params, light_cone, 2112);
LG_GL_BLOCK_OFFSET(vs_gpu_params, eye, 2624);
LG_GL_BLOCK_OFFSET(vs_gpu_params, g, 2652);
LG_GL_BLOCK_OFFSET(vs_gpu_params, norm, 2684);
LG_GL_BLOCK_OFFSET(vs_gpu_params, size, 2688);
LG_GL_BLOCK_OFFSET(vs_gpu_params, physical, 2704);
LG_GL_BLOCK_OFFSET(vs_gpu_params, scale, 2708);

/* ---- create / prepare ------------------------------------------------------------------------ */

static int vs_create(lg_node *n)
{
    vs_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->backend = lg_param_backend(n);
    st->model = lg_param_enum(n, "model");
    st->normalize = lg_param_bool(n, "normalize");
    st->per_frame = lg_param_bool(n, "per_frame");
    int64_t samples = lg_param_int(n, "samples");
    double exposure = lg_param_float(n, "exposure"), decay = lg_param_float(n, "decay");
    double weight = lg_param_float(n, "weight"), z_limit = lg_param_float(n, "z_limit");
    if (samples < 1 || samples > 1024)
        return lg_error(n, "samples = %lld: give 1 .. 1024 samples per pixel and light",
                        (long long)samples);
    if (!(exposure >= 0.0 && exposure <= 1e6))
        return lg_error(n, "exposure = %g: give a finite value in [0, 1e6]", exposure);
    if (!(decay > 0.0 && decay <= 1.0))
        return lg_error(n, "decay = %g: give a value in (0, 1] (the thesis: 0.94)", decay);
    if (!(weight >= 0.0 && weight <= 1e6))
        return lg_error(n, "weight = %g: give a finite value in [0, 1e6]", weight);
    if (!(z_limit >= 0.0 && z_limit <= 1e30))
        return lg_error(n, "z_limit = %g: give a view depth >= 0 (0 = the camera's zfar)", z_limit);
    st->samples = (uint32_t)samples;
    st->exposure = (float)exposure;
    st->decay = (float)decay;
    st->weight = (float)weight;
    st->z_limit = (float)z_limit;
    return 0;
}

static int vs_prepare(lg_node *n)
{
    vs_state *st = n->user;
    int rc = vol_declare_outputs(n, &st->width, &st->height);
    if (rc)
        return rc;
    if (st->per_frame)
        lg_set_per_frame(n, true);
    return lg_set_device(n, st->backend);
}

/* ---- the frame ------------------------------------------------------------------------------- */

static int vs_frame_make(lg_node *n, const vs_state *st, vs_frame *f)
{
    memset(f, 0, sizeof *f);
    const lg_scene *s = lg_scene_get(n, lg_input(n, VOL_IN_SCENE));
    if (!s)
        return LG_ERR_INVALID;
    int rc = vol_setup_make(n, s, st->width, st->height, st->z_limit, NULL, VOL_ACCEPT_LIGHTS,
                            &f->v);
    if (rc)
        return rc;
    const vol_setup *v = &f->v;
    /* beyond this distance from the image (pixels), p_l leaves every sample outside */
    double far_px = 2.0 * ((double)st->samples + 1.0) * ((double)st->width + st->height);
    double hw = 0.5 * st->width, hh = 0.5 * st->height;
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_light *L = &v->lights[l];
        bool local = L->type != LG_LIGHT_DIRECTIONAL;
        /* the point at infinity towards a directional light, the light itself otherwise */
        double h[4] = { -(double)L->dir[0], -(double)L->dir[1], -(double)L->dir[2], 0.0 };
        if (local)
            h[0] = L->pos[0], h[1] = L->pos[1], h[2] = L->pos[2], h[3] = 1.0;
        double c[4] = { 0, 0, 0, 0 };
        for (int row = 0; row < 4; row++)
            for (int col = 0; col < 4; col++)
                c[row] += (double)v->view.view_proj[col * 4 + row] * h[col];
        /* homogeneous form of |x_pixels - centre| <= far_px: no division until it holds */
        bool on = c[3] > 0.0 && fabs(c[0]) * hw <= far_px * c[3] &&
                  fabs(c[1]) * hh <= far_px * c[3];
        if (on) {
            f->pos[l][0] = (float)((c[0] / c[3] + 1.0) * hw);
            f->pos[l][1] = (float)((c[1] / c[3] + 1.0) * hh);
            f->pos[l][2] = 1.0f;
            f->active++;
        }
        /* the depth a sample must reach to see the light: the sky, or the light's window
         * depth (in front of the near plane: 0, nothing occludes; beyond zfar: the sky) */
        double zl = on && local ? 0.5 * c[2] / c[3] + 0.5 : 1.0;
        f->pos[l][3] = (float)(zl < 0.0 ? 0.0 : zl > 1.0 ? 1.0 : zl);
        double fe = 1.0;
        if (local && st->model == VS_THESIS) {
            /* the thesis's L_c is the light as the camera sees it: its falloff at the eye */
            lg_light sl = s->lights[L->scene_index];
            fe = lg_light_falloff(&sl, v->eye, NULL, NULL);
        }
        for (int ch = 0; ch < 3; ch++) {
            f->lc[l][ch] = (float)(L->l_c[ch] * fe);
            f->to[l][ch] = local ? L->dir[ch] : -L->dir[ch];
            f->q[l][ch] = L->pos[ch];
        }
        f->to[l][3] = L->type == LG_LIGHT_POINT ? 1.0f : L->type == LG_LIGHT_SPOT ? 2.0f : 0.0f;
        f->q[l][3] = L->range;
        f->cone[l][0] = L->cos_inner;
        f->cone[l][1] = L->cos_outer;
    }
    double N = st->samples;
    double step = st->normalize ? 64.0 / N : 1.0; /* decay's exponent per sample */
    f->k = (float)(log2((double)st->decay) * step);
    double wsum = 0.0;
    for (uint32_t i = 1; i <= st->samples; i++) {
        wsum += exp2((double)i * (double)f->k);
        f->wt[i] = exp2f((float)i * f->k);
    }
    f->norm = st->model == VS_THESIS && !st->normalize ? (float)(1.0 / N) : (float)(1.0 / wsum);
    f->scale = st->model == VS_THESIS ? st->exposure * st->weight : st->exposure;
    return 0;
}

/* ---- GL -------------------------------------------------------------------------------------- */

static int vs_gl_pass(lg_node *n, vs_state *st, int local)
{
    if (st->pass[local])
        return 0;
    static const lg_gl_shader_src src[2] = {
        { GL_VERTEX_SHADER, lg_src_vs_fullscreen_vert_file, lg_src_vs_fullscreen_vert },
        { GL_FRAGMENT_SHADER, lg_src_vs_screen_frag_file, lg_src_vs_screen_frag },
    };
    /* out (colour + depth) and inscatter: the outputs themselves, no other image. A scene
     * of directional lights compiles without the point and spot code: llvmpipe runs the
     * shader with it (not taken) at half the speed (README.md, "Cost") */
    lg_gl_pass_desc d = { .name = "volumetric_screen",
                          .stages = src,
                          .n_stages = 2,
                          .defines = local ? "#define VS_LOCAL_LIGHTS 1\n" : NULL,
                          .colors = { GL_RGBA32F, GL_RGBA32F },
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true,
                          /* every pixel is written, depth included (base's): no test
                           * against the old plane */
                          .depth_func = GL_ALWAYS };
    int rc = lg_gl_pass_create(n, &d, &st->pass[local]);
    if (rc)
        return rc;
    lg_gl_pass *p = st->pass[local];
    st->b_params[local] = lg_gl_pass_uniform_block(p, "VsParams");
    st->b_base[local] = lg_gl_pass_texture(p, "u_base");
    st->b_depth[local] = lg_gl_pass_texture(p, "u_base_depth");
    return 0;
}

static int vs_exec_gl(lg_node *n, vs_state *st, const vs_frame *f)
{
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int local = 0;
    for (uint32_t l = 0; l < f->v.n_lights; l++)
        local |= f->v.lights[l].type != LG_LIGHT_DIRECTIONAL;
    int rc = vs_gl_pass(n, st, local);
    if (rc)
        return rc;
    GLuint base = 0, base_depth = 0;
    if ((rc = lg_map_gl(n, lg_input(n, VOL_IN_BASE), LG_READ, &base, &base_depth)))
        return rc;
    if (!base_depth)
        return lg_error(n, "input 'base' has no depth plane on GL");
    lg_gl_target t, ti;
    if ((rc = lg_gl_target_output(n, "out", &t)) || (rc = lg_gl_target_output(n, "inscatter", &ti)))
        return rc;
    t.color[1] = ti.color[0];
    lg_gl_pass *p = st->pass[local];
    if ((rc = lg_gl_pass_begin(p, &t)))
        return rc;
    const vol_setup *v = &f->v;
    vs_gpu_params u = {
        .eye = { (float)v->eye[0], (float)v->eye[1], (float)v->eye[2] },
        .z_limit = v->z_limit,
        .forward = { (float)v->forward[0], (float)v->forward[1], (float)v->forward[2] },
        .g = v->g,
        .k = f->k,
        .norm = f->norm,
        .size = { (int32_t)st->width, (int32_t)st->height },
        .samples = (int32_t)st->samples,
        .lights = (int32_t)v->n_lights,
        .physical = st->model == VS_PHYSICAL,
        .scale = f->scale,
    };
    for (int i = 0; i < 16; i++)
        u.inv_view_proj[i] = (float)v->inv_view_proj[i];
    memcpy(u.light_pos, f->pos, sizeof u.light_pos);
    memcpy(u.light_c, f->lc, sizeof u.light_c);
    memcpy(u.light_to, f->to, sizeof u.light_to);
    memcpy(u.light_q, f->q, sizeof u.light_q);
    memcpy(u.light_cone, f->cone, sizeof u.light_cone);
    memcpy(u.sigma_s, v->sigma_s, sizeof u.sigma_s);
    memcpy(u.sigma_t, v->sigma_t, sizeof u.sigma_t);
    if ((rc = lg_gl_pass_uniforms(p, st->b_params[local], &u, sizeof u)))
        return lg_gl_pass_end(p, rc);
    lg_gl_pass_bind_texture(p, st->b_base[local], base);
    lg_gl_pass_bind_texture(p, st->b_depth[local], base_depth);
    rc = lg_gl_pass_draw(p, GL_TRIANGLES, 3);
    if ((rc = lg_gl_pass_end(p, rc)))
        return rc;
    return lg_gl_check(n, "volumetric_screen: the pass");
}

/* ---- CPU (the twin of vs_screen.frag) -------------------------------------------------------- */

/* A point or spot light's airlight along the view ray over [0, d] (lg_point_inscatter,
 * per unit L_c and sigma_s). A spot's ray is first cut where it crosses the outer cone
 * (the double cone (dot(x - q, s))^2 = cos^2 |x - q|^2, a quadratic in t) and only the
 * pieces inside the forward cone are integrated, each with the transmittance from the eye
 * to its start: a quadrature over the whole ray would straddle the cone's edges (kinks)
 * and a narrow beam could fall between its nodes. vs_screen.frag's vs_airlight is the
 * float twin. */
static double vs_airlight(const double o[3], const double w[3], double d, const double q[3],
                          double range, const double *spot, double g, double sigma_t)
{
    if (!spot)
        return lg_point_inscatter(o, w, 0.0, d, q, range, NULL, g, sigma_t, VS_AIRLIGHT_NODES);
    double ma = 0.0, wa = 0.0, mw = 0.0, mm = 0.0;
    for (int c = 0; c < 3; c++) {
        double m = o[c] - q[c];
        ma += m * spot[c];
        wa += w[c] * spot[c];
        mw += m * w[c];
        mm += m * m;
    }
    double c2 = spot[4] > 0.0 ? spot[4] * spot[4] : 0.0;
    double A = wa * wa - c2, B = 2.0 * (ma * wa - c2 * mw), C = ma * ma - c2 * mm;
    double t[4] = { 0.0, d, d, d };
    int n = 1;
    double r[2];
    int nr = 0;
    if (fabs(A) > 1e-12) {
        double disc = B * B - 4.0 * A * C;
        if (disc >= 0.0) {
            double sq = sqrt(disc);
            r[nr++] = (-B - sq) / (2.0 * A);
            r[nr++] = (-B + sq) / (2.0 * A);
        }
    } else if (fabs(B) > 0.0) {
        r[nr++] = -C / B;
    }
    if (nr == 2 && r[0] > r[1]) {
        double x = r[0];
        r[0] = r[1];
        r[1] = x;
    }
    for (int k = 0; k < nr; k++)
        if (r[k] > t[n - 1] && r[k] < d)
            t[n++] = r[k];
    t[n++] = d;
    double sum = 0.0;
    for (int k = 0; k + 1 < n; k++) {
        if (!(t[k + 1] > t[k]))
            continue;
        /* inside the forward cone at the piece's middle (the cone's test of lg_spot_cone) */
        double mid = 0.5 * (t[k] + t[k + 1]), v[3], len = 0.0, ca = 0.0;
        for (int c = 0; c < 3; c++) {
            v[c] = o[c] + mid * w[c] - q[c];
            len += v[c] * v[c];
            ca += v[c] * spot[c];
        }
        len = sqrt(len);
        if (!(len > 0.0) || !(ca > spot[4] * len))
            continue;
        sum += exp(-sigma_t * t[k]) * lg_point_inscatter(o, w, t[k], t[k + 1], q, range, spot, g,
                                                         sigma_t, VS_AIRLIGHT_NODES);
    }
    return sum;
}

typedef struct vs_job {
    const vs_state *st;
    const vs_frame *f;
    const float *base, *depth;
    float *out, *out_depth, *inscatter;
} vs_job;

static void vs_pixel(const vs_job *j, uint32_t x, uint32_t y)
{
    const vs_state *st = j->st;
    const vs_frame *f = j->f;
    const vol_setup *v = &f->v;
    size_t idx = (size_t)y * st->width + x;
    float depth = j->depth[idx];
    float px = (float)x + 0.5f, py = (float)y + 0.5f;
    float W = (float)st->width, H = (float)st->height, nf = (float)st->samples;
    double w[3];
    float d = 0.0f;
    if (st->model == VS_PHYSICAL) {
        vol_ray(v, px, py, w);
        double dd = vol_fog_length(v, px, py, depth);
        d = isfinite(dd) ? (float)dd : 0.0f;
    }
    float lv[3] = { 0, 0, 0 };
    for (uint32_t l = 0; l < v->n_lights; l++) {
        if (f->pos[l][2] == 0.0f)
            continue;
        float dx = (f->pos[l][0] - px) / nf, dy = (f->pos[l][1] - py) / nf;
        float zl = f->pos[l][3];
        float s = 0.0f;
        for (uint32_t i = 1; i <= st->samples; i++) {
            float qx = px + (float)i * dx, qy = py + (float)i * dy;
            if (qx >= 0.0f && qy >= 0.0f && qx < W && qy < H &&
                j->depth[(size_t)(uint32_t)qy * st->width + (uint32_t)qx] >= zl)
                s += f->wt[i];
        }
        float a = f->scale * f->norm * s;
        if (st->model == VS_PHYSICAL && f->to[l][3] != 0.0f) {
            /* point, spot: the airlight along the ray to d (the shader's float twin) */
            double q[3] = { f->q[l][0], f->q[l][1], f->q[l][2] };
            double spot[5] = { f->to[l][0], f->to[l][1], f->to[l][2], f->cone[l][0],
                               f->cone[l][1] };
            const double *sp = f->to[l][3] == 2.0f ? spot : NULL;
            float air[3];
            for (int ch = 0; ch < 3; ch++)
                air[ch] = ch > 0 && v->sigma_t[ch] == v->sigma_t[ch - 1]
                              ? air[ch - 1]
                              : (float)vs_airlight(v->eye, w, d, q, f->q[l][3], sp, v->g,
                                                   v->sigma_t[ch]);
            for (int ch = 0; ch < 3; ch++)
                lv[ch] += f->lc[l][ch] * a * v->sigma_s[ch] * air[ch];
        } else if (st->model == VS_PHYSICAL) {
            float c = (float)(w[0] * f->to[l][0] + w[1] * f->to[l][1] + w[2] * f->to[l][2]);
            float ph = lg_hg_phasef(v->g, c);
            for (int ch = 0; ch < 3; ch++)
                lv[ch] += f->lc[l][ch] * a * v->sigma_s[ch] * ph * d *
                          lg_medium_segmentf(v->sigma_t[ch] * d);
        } else {
            for (int ch = 0; ch < 3; ch++)
                lv[ch] += f->lc[l][ch] * a;
        }
    }
    const float *b = j->base + 4 * idx;
    for (int ch = 0; ch < 3; ch++) {
        float t = st->model == VS_PHYSICAL ? expf(-v->sigma_t[ch] * d) : 1.0f;
        j->out[4 * idx + ch] = b[ch] * t + lv[ch];
        j->inscatter[4 * idx + ch] = lv[ch];
    }
    j->out[4 * idx + 3] = b[3];
    j->inscatter[4 * idx + 3] = 1.0f;
    j->out_depth[idx] = depth;
}

static void vs_rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const vs_job *j = ctx;
    for (size_t y = begin; y < end; y++)
        for (uint32_t x = 0; x < j->st->width; x++)
            vs_pixel(j, x, (uint32_t)y);
}

static int vs_exec_cpu(lg_node *n, vs_state *st, const vs_frame *f)
{
    lg_cpu_view bv, ov, iv;
    int rc;
    if ((rc = lg_map_cpu(n, lg_input(n, VOL_IN_BASE), LG_READ, &bv)))
        return rc;
    if (!bv.depth)
        return lg_error(n, "input 'base' has no depth plane");
    if ((rc = lg_map_cpu(n, lg_output(n, VOL_OUT_OUT), LG_WRITE, &ov)) ||
        (rc = lg_map_cpu(n, lg_output(n, VOL_OUT_INSCATTER), LG_WRITE, &iv)))
        return rc;
    if (!ov.depth)
        return lg_error(n, "output 'out' has no depth plane");
    vs_job j = { .st = st,
                 .f = f,
                 .base = bv.pixels,
                 .depth = bv.depth,
                 .out = ov.pixels,
                 .out_depth = ov.depth,
                 .inscatter = iv.pixels };
    return lg_parallel_for(n, st->height, 4, vs_rows, &j);
}

/* ---- execute / destroy ----------------------------------------------------------------------- */

static int vs_execute(lg_node *n, const lg_frame *frame)
{
    vs_state *st = n->user;
    /* base passes into `out`: its NaN and Inf are said once, as `image` says a file's */
    int rc = lg_check_input_finite(n, frame, VOL_IN_BASE, "base", NULL, &st->reported_nonfinite);
    if (rc)
        return rc;
    vs_frame *f = malloc(sizeof *f);
    if (!f)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    rc = vs_frame_make(n, st, f);
    if (!rc)
        rc = st->backend == LG_DEVICE_GL ? vs_exec_gl(n, st, f) : vs_exec_cpu(n, st, f);
    if (!rc)
        lg_log(n, LG_LOG_DEBUG,
               "%u of %u lights on screen (the others behind the camera or too far "
               "off-screen: no shafts), %u samples, %s",
               f->active, f->v.n_lights, st->samples,
               st->model == VS_PHYSICAL ? "physical" : "thesis");
    free(f);
    return rc;
}

static void vs_destroy(lg_node *n)
{
    vs_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->pass[0]);
    lg_gl_pass_destroy(&st->pass[1]);
    free(st);
    n->user = NULL;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const char *const vs_models[] = { "thesis", "physical", NULL };

static const lg_param_desc vs_params[] = {
    /* gl (one fragment pass) or cpu (the host's thread pool); they agree */
    LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL, LG_BACKEND_GL),
    { .key = "samples",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 1,
      .max = 1024,
      .doc = "N: samples from each pixel towards each light's screen position (eq. 7)" },
    { .key = "exposure",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 1e6,
      .doc = "scale of L_v (eq. 6); physical: 1 = physical units" },
    { .key = "decay",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.94,
      .min = 0,
      .max = 1,
      .doc = "in (0, 1]: weight decay per sample (eq. 6); with normalize, per 1/64 of the "
             "path from the pixel to the light" },
    { .key = "weight",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.01,
      .min = 0,
      .max = 1e6,
      .doc = "thesis: the weight of a sample (eq. 6); physical: unused" },
    { .key = "normalize",
      .type = LG_PARAM_BOOL,
      .def.b = true,
      .doc = "brightness independent of N: decay^(64 i / N) and the sum divided by the sum "
             "of the weights (false: decay^i and / N, eq. 6 exactly)" },
    { .key = "model",
      .type = LG_PARAM_ENUM,
      .def.e = VS_PHYSICAL,
      .enum_values = vs_models,
      .doc = "thesis: eq. 6 (Mitchell's units; a point or spot light's L_c times its falloff "
             "at the camera), out = base + L_v; physical: the unshadowed in-scattering along "
             "the view ray (directional: L_c sigma_s p d seg(sigma_t d); point, spot: the "
             "airlight integral) times the decay-weighted fraction of visible samples, out = "
             "base e^(-sigma_t d) + L_v" },
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the fog ends (physical model); 0 = the camera's zfar" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "run again on every frame (--frames), for timing; the result is the same" },
};

static const lg_port_desc vs_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene: its lights (1 .. 32: directional, point, spot), its homogeneous "
             "medium and active camera" },
    { .name = "base",
      .kind = LG_KIND_IMAGE,
      .doc = "the lit image with its depth plane (phong's out): depth 1 = sky" },
};
static const lg_port_desc vs_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f + depth: base (x e^(-sigma_t d), physical) + L_v; depth = base's" },
    { .name = "inscatter",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f: L_v alone (physical: in lightgraph/medium.h's units), alpha 1" },
};

static const lg_node_type vs_types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "volumetric_screen",
    .doc = "Screen-space light shafts (Mitchell 2007): samples towards each light's screen "
           "position (directional, point, spot), visibility from depth (cpu, gl)",
    LG_PARAMS(vs_params),
    LG_INPUTS(vs_inputs),
    LG_OUTPUTS(vs_outputs),
    .needs = LG_NEEDS_MEDIUM | LG_NEEDS_LIGHT,
    .neutral = LG_NEUTRAL_PASSTHROUGH_FIRST,
    .neutral_input = VOL_IN_BASE,
    .create = vs_create,
    .prepare = vs_prepare,
    .execute = vs_execute,
    .destroy = vs_destroy,
} };

LG_PLUGIN_DEFINE("volumetric_screen", "1.0.0",
                 "Screen-space volumetric light shafts (Mitchell 2007) on gl and cpu", vs_types)
