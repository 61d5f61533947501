/*
 * The volumetric_screen plugin: screen-space light shafts after Mitchell 2007 (seed 2
 * 3.2.1, eq. 6-8; TECHNIQUES.md §6), one pass over the pixels on GL (a fragment pass,
 * shaders/volumetric_screen/vs_screen.frag) or on the CPU (the host's thread pool,
 * vs_pixel below, the same float arithmetic).
 *
 * For every pixel p and directional light l whose screen position p_l is known, N samples
 * p_i = p + i (p_l - p) / N (i = 1..N) read the depth of `base`; a sample is visible
 * (V_i = 1) when it lies inside the image and sees the sky (depth 1). With the weights
 * w_i = decay^i (or decay^(64 i / N) with normalize = true):
 *
 *   model = thesis     L_v = exposure weight L_c sum_i w_i V_i / N        (eq. 6; / sum_i w_i
 *                      with normalize = true)
 *   model = physical   L_v = exposure L_c sigma_s p_HG(g, w.(-L)) d seg(sigma_t d) F,
 *                      F = sum_i w_i V_i / sum_i w_i (Mitchell's occlusion estimate),
 *                      d = the fog's length along the view ray (vol_fog_length)
 *
 * summed over the lights. out = base + L_v (thesis: no extinction), base e^(-sigma_t d) +
 * L_v (physical). No memory beyond the two outputs.
 *
 * Lights without a screen position: clip = view_proj (-L, 0); w = clip.w <= 0 (behind the
 * camera, or in the image plane) contributes nothing, as the method has no samples to take
 * (its shafts point away from the viewer); a light whose p_l is further than
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

typedef struct vs_state {
    int model;
    lg_device backend;
    bool normalize, per_frame;
    uint32_t samples;
    float exposure, decay, weight, z_limit;
    uint32_t width, height;

    lg_gl_pass *pass;
    lg_gl_binding b_params, b_base, b_depth;
    bool reported_nonfinite; /* base's NaN/Inf pixels said (lg_check_input_finite) */
} vs_state;

/* What one frame computes with: per light its screen position and colour, the sums. */
typedef struct vs_frame {
    vol_setup v;
    float pos[VOL_MAX_LIGHTS][4]; /* xy pixels, z 1 = contributes */
    float lc[VOL_MAX_LIGHTS][4];
    float to[VOL_MAX_LIGHTS][4]; /* -L */
    float k;                     /* log2 of one step's decay */
    float wt[1025];              /* cpu: wt[i] = exp2f(i k), the shader's values */
    float norm;                  /* 1 / N or 1 / sum of weights */
    float scale;                 /* exposure weight (thesis) or exposure (physical) */
    uint32_t active;
} vs_frame;

/* The pass's uniform block VsParams (std140, shaders/volumetric_screen/vs_screen.frag),
 * uploaded with one lg_gl_pass_uniforms per frame. */
typedef struct vs_gpu_params {
    float inv_view_proj[16];
    float light_pos[VOL_MAX_LIGHTS][4];
    float light_c[VOL_MAX_LIGHTS][4];
    float light_to[VOL_MAX_LIGHTS][4];
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

LG_GL_BLOCK_SIZE(vs_gpu_params, 1696);
LG_GL_BLOCK_OFFSET(vs_gpu_params, light_pos, 64);
LG_GL_BLOCK_OFFSET(vs_gpu_params, light_to, 1088);
LG_GL_BLOCK_OFFSET(vs_gpu_params, eye, 1600);
LG_GL_BLOCK_OFFSET(vs_gpu_params, g, 1628);
LG_GL_BLOCK_OFFSET(vs_gpu_params, norm, 1660);
LG_GL_BLOCK_OFFSET(vs_gpu_params, size, 1664);
LG_GL_BLOCK_OFFSET(vs_gpu_params, physical, 1680);
LG_GL_BLOCK_OFFSET(vs_gpu_params, scale, 1684);

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
    int rc = vol_setup_make(n, s, st->width, st->height, st->z_limit, NULL, VOL_ACCEPT_DIRECTIONAL,
                            &f->v);
    if (rc)
        return rc;
    const vol_setup *v = &f->v;
    /* beyond this distance from the image (pixels), p_l leaves every sample outside */
    double far_px = 2.0 * ((double)st->samples + 1.0) * ((double)st->width + st->height);
    double hw = 0.5 * st->width, hh = 0.5 * st->height;
    for (uint32_t l = 0; l < v->n_lights; l++) {
        const vol_light *L = &v->lights[l];
        double c[4] = { 0, 0, 0, 0 };
        for (int row = 0; row < 4; row++)
            for (int col = 0; col < 3; col++)
                c[row] += (double)v->view.view_proj[col * 4 + row] * -(double)L->dir[col];
        /* homogeneous form of |x_pixels - centre| <= far_px: no division until it holds */
        bool on = c[3] > 0.0 && fabs(c[0]) * hw <= far_px * c[3] &&
                  fabs(c[1]) * hh <= far_px * c[3];
        if (on) {
            f->pos[l][0] = (float)((c[0] / c[3] + 1.0) * hw);
            f->pos[l][1] = (float)((c[1] / c[3] + 1.0) * hh);
            f->pos[l][2] = 1.0f;
            f->active++;
        }
        for (int ch = 0; ch < 3; ch++) {
            f->lc[l][ch] = L->l_c[ch];
            f->to[l][ch] = -L->dir[ch];
        }
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

static int vs_gl_pass(lg_node *n, vs_state *st)
{
    if (st->pass)
        return 0;
    static const lg_gl_shader_src src[2] = {
        { GL_VERTEX_SHADER, lg_src_vs_fullscreen_vert_file, lg_src_vs_fullscreen_vert },
        { GL_FRAGMENT_SHADER, lg_src_vs_screen_frag_file, lg_src_vs_screen_frag },
    };
    /* out (colour + depth) and inscatter: the outputs themselves, no other image */
    lg_gl_pass_desc d = { .name = "volumetric_screen",
                          .stages = src,
                          .n_stages = 2,
                          .colors = { GL_RGBA32F, GL_RGBA32F },
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true,
                          /* every pixel is written, depth included (base's): no test
                           * against the old plane */
                          .depth_func = GL_ALWAYS };
    int rc = lg_gl_pass_create(n, &d, &st->pass);
    if (rc)
        return rc;
    lg_gl_pass *p = st->pass;
    st->b_params = lg_gl_pass_uniform_block(p, "VsParams");
    st->b_base = lg_gl_pass_texture(p, "u_base");
    st->b_depth = lg_gl_pass_texture(p, "u_base_depth");
    return 0;
}

static int vs_exec_gl(lg_node *n, vs_state *st, const vs_frame *f)
{
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc = vs_gl_pass(n, st);
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
    lg_gl_pass *p = st->pass;
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
    memcpy(u.sigma_s, v->sigma_s, sizeof u.sigma_s);
    memcpy(u.sigma_t, v->sigma_t, sizeof u.sigma_t);
    if ((rc = lg_gl_pass_uniforms(p, st->b_params, &u, sizeof u)))
        return lg_gl_pass_end(p, rc);
    lg_gl_pass_bind_texture(p, st->b_base, base);
    lg_gl_pass_bind_texture(p, st->b_depth, base_depth);
    rc = lg_gl_pass_draw(p, GL_TRIANGLES, 3);
    if ((rc = lg_gl_pass_end(p, rc)))
        return rc;
    return lg_gl_check(n, "volumetric_screen: the pass");
}

/* ---- CPU (the twin of vs_screen.frag) -------------------------------------------------------- */

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
        float s = 0.0f;
        for (uint32_t i = 1; i <= st->samples; i++) {
            float qx = px + (float)i * dx, qy = py + (float)i * dy;
            if (qx >= 0.0f && qy >= 0.0f && qx < W && qy < H &&
                j->depth[(size_t)(uint32_t)qy * st->width + (uint32_t)qx] >= 1.0f)
                s += f->wt[i];
        }
        float a = f->scale * f->norm * s;
        if (st->model == VS_PHYSICAL) {
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
               "%u of %u directional lights on screen (the others behind the "
               "camera or too far off-screen: no shafts), %u samples, %s",
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
    lg_gl_pass_destroy(&st->pass);
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
      .doc = "thesis: eq. 6 (Mitchell's units), out = base + L_v; physical: the unshadowed "
             "closed form L_c sigma_s p d seg(sigma_t d) times the decay-weighted fraction "
             "of visible samples, out = base e^(-sigma_t d) + L_v" },
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
      .doc = "the scene: its directional lights (1 .. 32), medium and active camera" },
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
    .doc = "Screen-space light shafts (Mitchell 2007): samples towards each directional "
           "light's screen position, sky visibility from depth (cpu, gl)",
    LG_PARAMS(vs_params),
    LG_INPUTS(vs_inputs),
    LG_OUTPUTS(vs_outputs),
    .needs = LG_NEEDS_MEDIUM | LG_NEEDS_DIR_LIGHT,
    .neutral = LG_NEUTRAL_PASSTHROUGH_FIRST,
    .neutral_input = VOL_IN_BASE,
    .create = vs_create,
    .prepare = vs_prepare,
    .execute = vs_execute,
    .destroy = vs_destroy,
} };

LG_PLUGIN_DEFINE("volumetric_screen", "1.0.0",
                 "Screen-space volumetric light shafts (Mitchell 2007) on gl and cpu", vs_types)
