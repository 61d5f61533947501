/*
 * The reinhard plugin: Reinhard et al. 2002 global tone mapping, as seed 0 (3.5, 5.2)
 * describes it, with the paper's white point, on three backends (cpu, gl, cl).
 *
 * Every backend does the same three steps per execution:
 *   1. reduce: sum log(delta + L) over the valid pixels and count the bad ones;
 *   2. Lavg, the adaptation step, the scale a / Lavg (or a / La);
 *   3. map: the tone curve.
 * cpu: float passes threaded through the host's pool (reinhard_cpu.c), step 2 in double.
 * gl and cl: step 2 runs on the device, in the reduction's second stage, which leaves the
 * scale where the map reads it (reinhard_launch.h): no host round trip between the
 * passes. The 32-byte result block is read back after the map was queued, for the
 * bad-pixel report and the debug log only.
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/color.h"
#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"

#include "reinhard_cpu.h"
#include "reinhard_launch.h"
#include "reinhard.cl.h"
#include "rgbe.cl.h"
#include "reinhard_map.comp.h"
#include "reinhard_reduce.comp.h"

/* The mirrors of the shaders' std430 blocks (reinhard_launch.h), checked at compile time
 * against their GLSL layout (and at run time against the compiled program). */
LG_GL_BLOCK_SIZE(rh_partial, 16);
LG_GL_BLOCK_OFFSET(rh_partial, valid, 4);
LG_GL_BLOCK_OFFSET(rh_partial, nonfinite, 8);
LG_GL_BLOCK_OFFSET(rh_partial, negative, 12);
LG_GL_BLOCK_SIZE(rh_result, 32);
LG_GL_BLOCK_OFFSET(rh_result, lavg, 16);
LG_GL_BLOCK_OFFSET(rh_result, scale, 24);
LG_GL_BLOCK_OFFSET(rh_result, have_la, 28);

typedef struct rh_state {
    lg_rh_params p;
    double key, rate, adapt_from, dt;
    bool adapt;
    lg_device backend;

    uint32_t width, height;
    lg_format in_format;

    bool have_la; /* adaptation state (gl, cl: the device holds La, this says it does) */
    double la;
    bool warned_bad, warned_empty;
    lg_rh_stats *slots; /* cpu backend: the reduction's per-chunk partial sums */
    size_t n_slots;

    /* gl: the three compute passes, their uniforms and bindings (reinhard_reduce.comp stage
     * 1 and 2, reinhard_map.comp), and the reduction's buffers */
    lg_gl_pass *gl_reduce, *gl_final, *gl_map;
    lg_gl_uniform r_size, r_delta, r_w;
    lg_gl_uniform f_count, f_key, f_adapt, f_adapt_k, f_adapt_from, f_reset;
    lg_gl_uniform m_size, m_inv_white2, m_mode, m_w;
    lg_gl_binding r_in, r_partials, f_partials, f_result, m_in, m_out, m_result;
    lg_gl_buffer gl_partials, gl_result;

    /* cl: the same three passes (reinhard.cl after rgbe.cl) and buffers */
    lg_cl_pass *cl_reduce, *cl_final, *cl_map;
    lg_cl_buffer cl_partials, cl_result;
} rh_state;

/* ---- create / prepare ------------------------------------------------------------------------ */

static int rh_create(lg_node *n)
{
    rh_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->key = lg_param_float(n, "key");
    st->p.mode = lg_param_enum(n, "mode") == 1 ? LG_RH_RGB : LG_RH_LUMINANCE;
    st->p.white = lg_param_float(n, "white");
    st->p.delta = lg_param_float(n, "delta");
    lg_luma_coeffs(lg_param_enum(n, "luminance") == 1 ? LG_LUMA_SEED0 : LG_LUMA_REC709, st->p.w);
    st->adapt = lg_param_bool(n, "adapt");
    st->rate = lg_param_float(n, "adapt_rate");
    st->adapt_from = lg_param_float(n, "adapt_from");
    st->dt = lg_param_float(n, "dt");
    st->backend = lg_param_backend(n);
    return 0;
}

static int rh_prepare(lg_node *n)
{
    rh_state *st = n->user;
    const lg_resource *in = lg_input(n, 0);
    lg_resource_info info;
    int rc = lg_describe(in, &info, n);
    if (rc)
        return lg_error_code(n, rc, "input 'image': cannot describe the resource");
    if (info.kind != LG_KIND_IMAGE)
        return lg_error(n, "input 'image' is not an image");
    if (info.image.format != LG_FORMAT_RGBA32F && info.image.format != LG_FORMAT_RGBA16F &&
        info.image.format != LG_FORMAT_RGBE8)
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "input 'image' is %s (display-encoded); reinhard maps linear "
                             "HDR images (rgba32f, rgba16f or rgbe8)",
                             lg_format_name(info.image.format));
    st->width = info.image.width;
    st->height = info.image.height;
    st->in_format = info.image.format;

    lg_image_desc d = { .width = st->width, .height = st->height, .format = LG_FORMAT_RGBA32F };
    rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    rc = lg_set_device(n, st->backend);
    if (rc)
        return rc;
    /* adaptation carries state from frame to frame */
    lg_set_per_frame(n, st->adapt);
    st->have_la = false;
    return 0;
}

/* ---- the scale: Lavg, adaptation, reporting -------------------------------------------------- */

/* The warnings every backend gives, once each: pixels left out, no valid pixel. */
static void rh_warn(lg_node *n, rh_state *st, const lg_rh_stats *s, const lg_frame *frame)
{
    uint64_t bad = s->nonfinite + s->negative;
    if (bad && !st->warned_bad) {
        st->warned_bad = true;
        lg_log(n, LG_LOG_WARN,
               "frame %u: %" PRIu64 " of %" PRIu64 " pixels left out of the log-average "
               "(%" PRIu64 " with NaN or Inf, %" PRIu64 " with negative luminance); they map "
               "to 0, and +Inf channels to 1 (reported once)",
               frame->index, bad, bad + s->valid, s->nonfinite, s->negative);
    }
    if (!s->valid && !st->warned_empty) {
        st->warned_empty = true;
        lg_log(n, LG_LOG_WARN, "frame %u: no valid pixel for the log-average; %s (reported once)",
               frame->index,
               st->adapt && st->have_la ? "keeping the adapted luminance" : "using Lavg = 1");
    }
}

static double rh_scale(lg_node *n, rh_state *st, const lg_rh_stats *s, const lg_frame *frame)
{
    rh_warn(n, st, s, frame);
    double lavg;
    bool ok = lg_rh_log_average(s, &lavg);
    double l = ok ? lavg : 1.0;
    if (st->adapt) {
        if (!st->have_la) {
            st->la = st->adapt_from > 0.0 ? st->adapt_from : l;
            st->have_la = true;
        }
        if (ok) {
            double dt = st->dt > 0.0 ? st->dt : frame->dt;
            st->la = lg_rh_adapt(st->la, lavg, st->rate, dt);
        }
        l = st->la;
    }
    lg_log(n, LG_LOG_DEBUG,
           "frame %u: Lavg %.9g (%" PRIu64 " pixels), luminance used %.9g, scale %.9g",
           frame->index, ok ? lavg : NAN, s->valid, l, st->key / l);
    return st->key / l;
}

/* ---- gl and cl: the scale is computed on the device ------------------------------------------ */

/* What stage 2 needs to compute the scale on the device (reinhard_launch.h). */
typedef struct rh_adapt_args {
    float key;
    int32_t adapt;
    float k;       /* 1 - rate^(60 dt), in double here */
    float from;    /* adapt_from */
    int32_t reset; /* first frame since prepare: forget the adapted luminance */
} rh_adapt_args;

static rh_adapt_args rh_adapt_args_for(const rh_state *st, const lg_frame *frame)
{
    double dt = st->dt > 0.0 ? st->dt : frame->dt;
    rh_adapt_args a = {
        .key = (float)st->key,
        .adapt = st->adapt ? 1 : 0,
        .k = (float)(1.0 - pow(st->rate, 60.0 * dt)),
        .from = (float)st->adapt_from,
        .reset = st->have_la ? 0 : 1,
    };
    return a;
}

/* The bad-pixel report and the debug log, from the result block read back after the map;
 * the same messages as the cpu backend's rh_scale. */
static void rh_report(lg_node *n, rh_state *st, const rh_result *r, const lg_frame *frame)
{
    lg_rh_stats s = {
        .log_sum = r->sum, .valid = r->valid, .nonfinite = r->nonfinite, .negative = r->negative
    };
    rh_warn(n, st, &s, frame);
    if (st->adapt)
        st->have_la = true;
    lg_log(n, LG_LOG_DEBUG,
           "frame %u: Lavg %.9g (%" PRIu64 " pixels), luminance used %.9g, scale %.9g",
           frame->index, s.valid ? r->lavg : NAN, s.valid, st->key / r->scale, r->scale);
}

/* ---- cpu ------------------------------------------------------------------------------------- */

static int rh_pfor(void *node, size_t count, size_t grain,
                   void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk), void *ctx)
{
    return lg_parallel_for(node, count, grain, fn, ctx);
}

static int rh_execute_cpu(lg_node *n, rh_state *st, const lg_frame *frame)
{
    lg_cpu_view vi, vo;
    int rc;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &vi)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &vo)))
        return rc;
    lg_rh_image in = { .pixels = vi.pixels,
                       .row_pixels = vi.row_pixels,
                       .width = st->width,
                       .height = st->height,
                       .half = st->in_format == LG_FORMAT_RGBA16F,
                       .rgbe = st->in_format == LG_FORMAT_RGBE8 };
    size_t chunks = lg_rh_cpu_chunks(st->width, st->height);
    if (chunks > st->n_slots) {
        lg_rh_stats *s = realloc(st->slots, chunks * sizeof *s);
        if (!s)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu reduction slots)", chunks);
        st->slots = s;
        st->n_slots = chunks;
    }
    /* pass 1, then the scale (in double, with adaptation), then pass 2 */
    lg_rh_stats s;
    if ((rc = lg_rh_cpu_reduce(&in, &st->p, st->slots, rh_pfor, n, &s)))
        return rc;
    float scale = (float)rh_scale(n, st, &s, frame);
    return lg_rh_cpu_map(&in, vo.pixels, vo.row_pixels, scale, &st->p, rh_pfor, n);
}

/* ---- gl -------------------------------------------------------------------------------------- */

static int rh_gl_init(lg_node *n, rh_state *st)
{
    /* rgbe8: the bytes of an RGBA8 image, decoded after imageLoad (LG_IN_RGBE) */
    const char *fmt = st->in_format == LG_FORMAT_RGBA16F ? "rgba16f"
                      : st->in_format == LG_FORMAT_RGBE8 ? "rgba8\n#define LG_IN_RGBE 1"
                                                         : "rgba32f";
    char defs[160];
    static const lg_gl_shader_src reduce = { GL_COMPUTE_SHADER, lg_src_reinhard_reduce_comp_file,
                                             lg_src_reinhard_reduce_comp };
    static const lg_gl_shader_src map = { GL_COMPUTE_SHADER, lg_src_reinhard_map_comp_file,
                                          lg_src_reinhard_map_comp };
    int rc;
    /* a failed earlier attempt may have made some of them */
    lg_gl_pass_destroy(&st->gl_reduce);
    lg_gl_pass_destroy(&st->gl_final);
    snprintf(defs, sizeof defs, "#define LG_STAGE 1\n#define LG_IN_FORMAT %s\n", fmt);
    lg_gl_pass_desc d = {
        .name = "reinhard reduce", .stages = &reduce, .n_stages = 1, .defines = defs
    };
    if ((rc = lg_gl_pass_create(n, &d, &st->gl_reduce)))
        return rc;
    d.name = "reinhard reduce (stage 2)";
    d.defines = "#define LG_STAGE 2\n";
    if ((rc = lg_gl_pass_create(n, &d, &st->gl_final)))
        return rc;
    snprintf(defs, sizeof defs, "#define LG_IN_FORMAT %s\n", fmt);
    d.name = "reinhard map";
    d.stages = &map;
    d.defines = defs;
    if ((rc = lg_gl_pass_create(n, &d, &st->gl_map)))
        return rc;
    lg_gl_pass *r = st->gl_reduce, *f = st->gl_final, *m = st->gl_map;
    st->r_size = lg_gl_pass_uniform(r, "u_size");
    st->r_delta = lg_gl_pass_uniform(r, "u_delta");
    st->r_w = lg_gl_pass_uniform(r, "u_w");
    st->r_in = lg_gl_pass_image(r, "u_in");
    st->r_partials = lg_gl_pass_storage(r, "Partials");
    st->f_count = lg_gl_pass_uniform(f, "u_count");
    st->f_key = lg_gl_pass_uniform(f, "u_key");
    st->f_adapt = lg_gl_pass_uniform(f, "u_adapt");
    st->f_adapt_k = lg_gl_pass_uniform(f, "u_adapt_k");
    st->f_adapt_from = lg_gl_pass_uniform(f, "u_adapt_from");
    st->f_reset = lg_gl_pass_uniform(f, "u_reset");
    st->f_partials = lg_gl_pass_storage(f, "Partials");
    st->f_result = lg_gl_pass_storage(f, "Result");
    st->m_size = lg_gl_pass_uniform(m, "u_size");
    st->m_inv_white2 = lg_gl_pass_uniform(m, "u_inv_white2");
    st->m_mode = lg_gl_pass_uniform(m, "u_mode");
    st->m_w = lg_gl_pass_uniform(m, "u_w");
    st->m_in = lg_gl_pass_image(m, "u_in");
    st->m_out = lg_gl_pass_image(m, "u_out");
    st->m_result = lg_gl_pass_storage(m, "Result");
    lg_gl_pass_check_block(r, GL_SHADER_STORAGE_BLOCK, "Partials", sizeof(rh_partial));
    lg_gl_pass_check_block(f, GL_SHADER_STORAGE_BLOCK, "Result", sizeof(rh_result));
    lg_gl_pass_check_block(m, GL_SHADER_STORAGE_BLOCK, "Result", sizeof(rh_result));
    if (st->gl_result.name)
        return 0;
    if ((rc = lg_gl_buffer_recreate(n, &st->gl_partials, RH_MAX_GROUPS * sizeof(rh_partial), 0,
                                    NULL)))
        return rc;
    /* the result block starts zeroed: no adapted luminance yet */
    rh_result zero;
    memset(&zero, 0, sizeof zero);
    return lg_gl_buffer_recreate(n, &st->gl_result, sizeof zero, 0, &zero);
}

static int rh_execute_gl(lg_node *n, rh_state *st, const lg_frame *frame)
{
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc;
    if (!st->gl_map && (rc = rh_gl_init(n, st)))
        return rc;
    uint32_t tin = 0, tout = 0, dummy;
    if ((rc = lg_map_gl(n, lg_input(n, 0), LG_READ, &tin, &dummy)) ||
        (rc = lg_map_gl(n, lg_output(n, 0), LG_WRITE, &tout, &dummy)))
        return rc;
    GLenum in_fmt = st->in_format == LG_FORMAT_RGBA16F ? GL_RGBA16F
                    : st->in_format == LG_FORMAT_RGBE8 ? GL_RGBA8
                                                       : GL_RGBA32F;
    uint32_t cols = rh_gl_cols(st->width), rows = rh_gl_rows(st->width, st->height);
    rh_adapt_args ad = rh_adapt_args_for(st, frame);

    /* stage 1: partial sums of log(delta + L), one per work-group of a 2D grid */
    lg_gl_pass *r = st->gl_reduce;
    if ((rc = lg_gl_pass_begin(r, NULL)))
        return rc;
    lg_gl_pass_bind_image(r, st->r_in, tin, GL_READ_ONLY, in_fmt);
    lg_gl_pass_bind_buffer(r, st->r_partials, st->gl_partials.name);
    lg_gl_set_ivec2(r, st->r_size, (int32_t)st->width, (int32_t)st->height);
    lg_gl_set_float(r, st->r_delta, (float)st->p.delta);
    lg_gl_set_vec3(r, st->r_w, st->p.w[0], st->p.w[1], st->p.w[2]);
    if ((rc = lg_gl_pass_end(r, lg_gl_pass_dispatch_groups(r, cols, rows, 1))))
        return rc;

    /* stage 2: Lavg, the adaptation step and the scale, left on the device in gl_result
     * (no host round trip before the map) */
    lg_gl_pass *f = st->gl_final;
    if ((rc = lg_gl_pass_begin(f, NULL)))
        return rc;
    lg_gl_pass_bind_buffer(f, st->f_partials, st->gl_partials.name);
    lg_gl_pass_bind_buffer(f, st->f_result, st->gl_result.name);
    lg_gl_set_uint(f, st->f_count, cols * rows);
    lg_gl_set_float(f, st->f_key, ad.key);
    lg_gl_set_int(f, st->f_adapt, ad.adapt);
    lg_gl_set_float(f, st->f_adapt_k, ad.k);
    lg_gl_set_float(f, st->f_adapt_from, ad.from);
    lg_gl_set_int(f, st->f_reset, ad.reset);
    if ((rc = lg_gl_pass_end(f, lg_gl_pass_dispatch_groups(f, 1, 1, 1))))
        return rc;

    /* the map reads the scale from gl_result; end makes the output visible to whoever
     * reads it next */
    double inv_w2 = st->p.white > 0.0 ? 1.0 / (st->p.white * st->p.white) : 0.0;
    lg_gl_pass *m = st->gl_map;
    if ((rc = lg_gl_pass_begin(m, NULL)))
        return rc;
    lg_gl_pass_bind_image(m, st->m_in, tin, GL_READ_ONLY, in_fmt);
    lg_gl_pass_bind_image(m, st->m_out, tout, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_pass_bind_buffer(m, st->m_result, st->gl_result.name);
    lg_gl_set_ivec2(m, st->m_size, (int32_t)st->width, (int32_t)st->height);
    lg_gl_set_float(m, st->m_inv_white2, (float)inv_w2);
    lg_gl_set_int(m, st->m_mode, st->p.mode == LG_RH_RGB ? 1 : 0);
    lg_gl_set_vec3(m, st->m_w, st->p.w[0], st->p.w[1], st->p.w[2]);
    if ((rc = lg_gl_pass_end(m, lg_gl_pass_dispatch(m, st->width, st->height, 1))))
        return rc;

    /* for the report only, after the map was submitted */
    rh_result res;
    gl->GetNamedBufferSubData(st->gl_result.name, 0, sizeof res, &res);
    if ((rc = lg_gl_check(n, "reinhard: reading the result block")))
        return rc;
    rh_report(n, st, &res, frame);
    return 0;
}

/* ---- cl -------------------------------------------------------------------------------------- */

static int rh_cl_init(lg_node *n, rh_state *st)
{
    char opts[160];
    snprintf(opts, sizeof opts, "-cl-std=CL1.2 -DLG_LOCAL=%u -DLG_MAP_LOCAL=%u -DLG_PPI=%u%s",
             RH_GROUP, RH_CL_MAP_LOCAL, RH_CL_PPI,
             st->in_format == LG_FORMAT_RGBA16F ? " -DLG_IN_HALF=1"
             : st->in_format == LG_FORMAT_RGBE8 ? " -DLG_IN_RGBE=1"
                                                : "");
    /* shaders/common/rgbe.cl, then the kernels (which use its decoder for rgbe8 input); one
     * program for the three passes (same texts and options) */
    static const char *const src[] = { lg_src_rgbe_cl, lg_src_reinhard_cl };
    static const char *const names[] = { lg_src_rgbe_cl_file, lg_src_reinhard_cl_file };
    lg_cl_pass_desc d = { .sources = src, .source_names = names, .n_sources = 2, .options = opts };
    int rc;
    d.name = "reinhard reduce", d.kernel = "rh_reduce";
    if ((rc = lg_cl_pass_create(n, &d, &st->cl_reduce)))
        return rc;
    d.name = "reinhard reduce final", d.kernel = "rh_reduce_final";
    if ((rc = lg_cl_pass_create(n, &d, &st->cl_final)))
        return rc;
    d.name = "reinhard map", d.kernel = "rh_map";
    if ((rc = lg_cl_pass_create(n, &d, &st->cl_map)))
        return rc;
    size_t wg = 0;
    cl_int err = clGetKernelWorkGroupInfo(lg_cl_pass_kernel(st->cl_reduce), lg_cl_device(n),
                                          CL_KERNEL_WORK_GROUP_SIZE, sizeof wg, &wg, NULL);
    if (err)
        return lg_cl_fail(n, err, "clGetKernelWorkGroupInfo(rh_reduce)");
    if (wg < RH_GROUP || wg < RH_CL_MAP_LOCAL)
        return lg_error_code(n, LG_ERR_DEVICE,
                             "backend 'cl': the device runs at most %zu work-items per group "
                             "for rh_reduce, the kernels need %u",
                             wg, RH_GROUP > RH_CL_MAP_LOCAL ? RH_GROUP : RH_CL_MAP_LOCAL);
    /* the result block starts zeroed: no adapted luminance yet */
    rh_result zero;
    memset(&zero, 0, sizeof zero);
    if ((rc = lg_cl_buffer_recreate(n, &st->cl_result, sizeof zero, 0)) ||
        (rc = lg_cl_buffer_write(n, &st->cl_result, 0, sizeof zero, &zero)))
        return rc;
    return 0;
}

static int rh_execute_cl(lg_node *n, rh_state *st, const lg_frame *frame)
{
    int rc;
    if (!st->cl_map && (rc = rh_cl_init(n, st)))
        return rc;
    const lg_resource *in = lg_input(n, 0), *out = lg_output(n, 0);
    uint32_t npx = (uint32_t)((size_t)st->width * st->height);
    uint32_t groups = rh_cl_groups(npx), partials = rh_cl_partials(npx);
    /* one partial per stage-1 work-item: sized by the image, which prepare may change */
    if ((rc = lg_cl_buffer_recreate(n, &st->cl_partials, (size_t)partials * sizeof(rh_partial), 0)))
        return rc;
    const float w[4] = { st->p.w[0], st->p.w[1], st->p.w[2], 0.0f };
    rh_adapt_args ad = rh_adapt_args_for(st, frame);

    /* stage 1 */
    lg_cl_pass *k = st->cl_reduce;
    lg_cl_pass_arg_resource(k, 0, in, LG_READ);
    lg_cl_pass_arg_uint(k, 1, npx);
    lg_cl_pass_arg_float(k, 2, (float)st->p.delta);
    lg_cl_pass_arg_float4(k, 3, w);
    lg_cl_pass_arg_mem(k, 4, st->cl_partials.mem);
    size_t local = RH_GROUP, global = (size_t)groups * RH_GROUP;
    if ((rc = lg_cl_pass_run(k, 1, &global, &local)))
        return rc;

    /* stage 2: the partials, Lavg, adaptation and the scale, on the device */
    k = st->cl_final;
    lg_cl_pass_arg_mem(k, 0, st->cl_partials.mem);
    lg_cl_pass_arg_uint(k, 1, partials);
    lg_cl_pass_arg_mem(k, 2, st->cl_result.mem);
    lg_cl_pass_arg_float(k, 3, ad.key);
    lg_cl_pass_arg_int(k, 4, ad.adapt);
    lg_cl_pass_arg_float(k, 5, ad.k);
    lg_cl_pass_arg_float(k, 6, ad.from);
    lg_cl_pass_arg_int(k, 7, ad.reset);
    global = RH_GROUP;
    if ((rc = lg_cl_pass_run(k, 1, &global, &local)))
        return rc;

    /* the map reads the scale where stage 2 left it */
    k = st->cl_map;
    lg_cl_pass_arg_resource(k, 0, in, LG_READ);
    lg_cl_pass_arg_resource(k, 1, out, LG_WRITE);
    lg_cl_pass_arg_uint(k, 2, npx);
    lg_cl_pass_arg_mem(k, 3, st->cl_result.mem);
    lg_cl_pass_arg_float(k, 4,
                         st->p.white > 0.0 ? (float)(1.0 / (st->p.white * st->p.white)) : 0.0f);
    lg_cl_pass_arg_int(k, 5, st->p.mode == LG_RH_RGB ? 1 : 0);
    lg_cl_pass_arg_float4(k, 6, w);
    local = RH_CL_MAP_LOCAL;
    global = rh_cl_map_items(npx); /* eight pixels per item */
    if ((rc = lg_cl_pass_run(k, 1, &global, &local)))
        return rc;

    /* for the report only, after the map was queued: the device never waits for the host */
    rh_result r;
    if ((rc = lg_cl_buffer_read(n, &st->cl_result, 0, sizeof r, &r)))
        return rc;
    rh_report(n, st, &r, frame);
    return 0;
}

/* ---- execute / destroy ----------------------------------------------------------------------- */

static int rh_execute(lg_node *n, const lg_frame *frame)
{
    rh_state *st = n->user;
    switch (st->backend) {
    case LG_DEVICE_GL: return rh_execute_gl(n, st, frame);
    case LG_DEVICE_CL: return rh_execute_cl(n, st, frame);
    default: return rh_execute_cpu(n, st, frame);
    }
}

static void rh_destroy(lg_node *n)
{
    rh_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->gl_reduce);
    lg_gl_pass_destroy(&st->gl_final);
    lg_gl_pass_destroy(&st->gl_map);
    lg_gl_buffer_destroy(n, &st->gl_partials);
    lg_gl_buffer_destroy(n, &st->gl_result);
    lg_cl_pass_destroy(&st->cl_reduce);
    lg_cl_pass_destroy(&st->cl_final);
    lg_cl_pass_destroy(&st->cl_map);
    lg_cl_buffer_destroy(n, &st->cl_partials);
    lg_cl_buffer_destroy(n, &st->cl_result);
    free(st->slots);
    free(st);
    n->user = NULL;
}

/* ---- descriptor ------------------------------------------------------------------------------ */

static const char *const rh_modes[] = { "luminance", "rgb", NULL };
static const char *const rh_lumas[] = { "rec709", "seed", NULL };

static const lg_param_desc rh_params[] = {
    { .key = "key",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.18,
      .min = 1e-4,
      .max = 10,
      .doc = "key a: the scene's log-average maps to a (0.18 middle grey; seed code: 0.72)" },
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = rh_modes,
      .doc =
          "luminance: map L and scale colour by Ld/L (Reinhard 2002); rgb: curve per channel (seed 0)" },
    { .key = "white",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc =
          "Lwhite, the smallest scaled luminance that maps to 1 (Reinhard 2002 eq. 4); 0 = off" },
    { .key = "delta",
      .type = LG_PARAM_FLOAT,
      .def.f = 1e-4,
      .min = 1e-12,
      .max = 1,
      .doc = "offset in log(delta + L), so that black pixels count (seed: 0.0001)" },
    { .key = "luminance",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = rh_lumas,
      .doc =
          "luminance weights: rec709 (0.2126, 0.7152, 0.0722) or seed (0.2125, 0.7154, 0.0721)" },
    { .key = "adapt",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "adapt gradually to the frame's Lavg (seed 0, 5.2); the node then runs every frame" },
    { .key = "adapt_rate",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.98,
      .min = 0,
      .max = 1,
      .doc = "La += (Lavg - La) (1 - rate^(60 dt)): the fraction kept per 1/60 s (seed: 0.98)" },
    { .key = "adapt_from",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "adapted luminance before the first frame; 0 = the first frame's Lavg" },
    { .key = "dt",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 3600,
      .doc = "seconds per frame for adaptation; 0 = the render's frame time (--dt)" },
    /* cpu (float, vectorised, on the host's thread pool), gl (compute shaders), cl */
    LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL | LG_BACKEND_CL, LG_BACKEND_CPU),
};
static const lg_port_desc rh_inputs[] = {
    { .name = "image",
      .kind = LG_KIND_IMAGE,
      .doc = "linear HDR image, rgba32f, rgba16f or rgbe8 (decoded as read)" },
};
static const lg_port_desc rh_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f, display-referred linear: Ld in [0,1], saturated channels may exceed 1 "
             "in luminance mode; a PNG output applies sRGB and clips" },
};

static const lg_node_type rh_types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "reinhard",
    .doc = "Reinhard global tone mapping: log-average luminance, key, optional white point",
    LG_PARAMS(rh_params),
    LG_INPUTS(rh_inputs),
    LG_OUTPUTS(rh_outputs),
    .flags = LG_NODE_DISPLAY_REFERRED,
    .create = rh_create,
    .prepare = rh_prepare,
    .execute = rh_execute,
    .destroy = rh_destroy,
} };

LG_PLUGIN_DEFINE("reinhard", "1.0.0", "Reinhard 2002 tone mapping (seed 0, 3.5 and 5.2)", rh_types)
