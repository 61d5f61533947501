/*
 * The prt plugin: diffuse precomputed radiance transfer at run time (TECHNIQUES.md §5,
 * seed 0 §4.3 eq. 4.10-4.12 and §5.4).
 *
 *   prt   scene + lighting (SH) + transfer [+ reflect] -> out (image), vertices (image)
 *
 * Every frame: the lighting's coefficients, truncated to the bands both inputs have, are
 * rotated on the CPU (lightgraph/sh.h; n^2 x 3 values) by rotate_deg (+ spin x time), then
 * each vertex's exit radiance radiance_c = sum_i lighting_c[i] transfer[v][c][i] is
 * computed on the chosen backend (GL fragment pass, CL kernel, or the host's pool: prt_cpu.c)
 * into the `vertices` image (lightgraph/transfer.h, "Per-vertex values as an image"), and
 * the scene is rasterised on GL with the camera, each vertex fetching its value from that
 * image and the rasteriser interpolating it (Gouraud, as seed 0). `reflect`, when given,
 * is added. The transfer buffer is mapped on the backend's device where the host keeps it
 * (a static input is moved once); only the lighting (a few hundred bytes) is uploaded per
 * frame. README.md gives the ports, parameters, equations and measured cost.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"
#include "lightgraph/sh.h"
#include "lightgraph/shcoeffs.h"
#include "lightgraph/transfer.h"

#include "prt.cl.h"
#include "prt.frag.h"
#include "prt.vert.h"
#include "prt_dot.comp.h"
#include "prt_dot.frag.h"
#include "prt_dot.vert.h"
#include "prt_launch.h"
#include "prt_reflect.frag.h"
#include "prt_reflect.vert.h"

enum { IN_SCENE = 0, IN_LIGHTING, IN_TRANSFER, IN_REFLECT };
enum { OUT_IMAGE = 0, OUT_VERTICES };

/* The largest |angle| in degrees (rotate_deg) and |spin| in degrees per second: beyond
 * them a value is a mistake (and float angles lose their fraction). */
#define PRT_MAX_DEG 36000.0

typedef struct prt_state {
    lg_device backend;
    int64_t camera;
    uint32_t width, height;
    double rotate[3];  /* yaw, pitch, roll (degrees) */
    double spin;       /* degrees of yaw per second */
    uint32_t vertices; /* the scene's vertex count (sum over meshes), from prepare */
    uint32_t tex_w, tex_h;
    bool logged_bands;

    /* the frame's mesh offsets (first vertex of each mesh) */
    uint32_t *offsets;
    uint32_t n_offsets;

    /* GL */
    lg_gl_pass *dot, *raster, *refl;
    uint32_t g_n, g_stride;   /* the dot pass's build (prt_gl_frag_defines, prt_gl_defines) */
    int g_frag;               /* 1: prt_dot.frag, 0: prt_dot.comp over a storage buffer */
    lg_gl_buffer_texture tbo; /* the RGB32F buffer texture over the transfer's GL buffer */
    lg_gl_uniform d_vertices, d_width, d_texels, d_light, d_first, d_end;
    lg_gl_binding d_transfer, d_lighting, d_out;
    lg_gl_uniform r_view_proj, r_offset;
    lg_gl_binding r_vertices, f_reflect;
    lg_gl_buffer light_buf;

    /* CL */
    lg_cl_pass *kernel;
    uint32_t k_n, k_stride; /* the kernel's build (prt_cl_options) */
    lg_cl_buffer cl_light, cl_record;
} prt_state;

/* ---- create / prepare ------------------------------------------------------------------------ */

static int prt_create(lg_node *n)
{
    prt_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->backend = lg_param_backend(n);
    st->camera = lg_param_int(n, "camera");
    const lg_value *r = lg_param(n, "rotate_deg");
    static const char *const names[3] = { "yaw", "pitch", "roll" };
    for (int i = 0; i < 3; i++) {
        double v = r ? r->v[i] : 0.0;
        if (!isfinite(v) || fabs(v) > PRT_MAX_DEG)
            return lg_error(n,
                            "rotate_deg[%d] (%s) = %g: give a finite angle within +-%g "
                            "degrees",
                            i, names[i], v, PRT_MAX_DEG);
        st->rotate[i] = v;
    }
    st->spin = lg_param_float(n, "spin_deg_per_s");
    if (!isfinite(st->spin) || fabs(st->spin) > PRT_MAX_DEG)
        return lg_error(n,
                        "spin_deg_per_s = %g: give a finite rate within +-%g degrees per "
                        "second",
                        st->spin, PRT_MAX_DEG);
    return 0;
}

static int prt_prepare(lg_node *n)
{
    prt_state *st = n->user;
    int rc = lg_output_size_nonempty(n, "width", "height", &st->width, &st->height);
    if (rc)
        return rc;
    lg_resource_info info;
    lg_assert_input(n, IN_SCENE);
    const lg_resource *in = lg_input(n, IN_SCENE);
    /* the vertex count sizes the `vertices` image; the scene's payload exists from its
     * producer's prepare on */
    const lg_scene *s = lg_scene_get(n, in);
    if (!s)
        return LG_ERR_INVALID;
    uint64_t total = 0;
    for (uint32_t m = 0; m < s->n_meshes; m++)
        total += s->meshes[m].n_vertices;
    if (total > UINT32_MAX / 2)
        return lg_error(n,
                        "input 'scene' has %llu vertices: more than the per-vertex image "
                        "can number",
                        (unsigned long long)total);
    st->vertices = (uint32_t)total;
    const lg_resource *sh = lg_input(n, IN_LIGHTING);
    if (!sh || lg_describe(sh, &info, n) != 0 || info.kind != LG_KIND_SH)
        return lg_error(n, "input 'lighting' is not SH coefficients (LG_KIND_SH: sh_project's "
                           "output)");
    const lg_resource *tr = lg_input(n, IN_TRANSFER);
    if (!tr || lg_describe(tr, &info, n) != 0 || info.kind != LG_KIND_TRANSFER)
        return lg_error(n, "input 'transfer' is not per-vertex transfer (LG_KIND_TRANSFER: "
                           "prt_bake's output)");
    const lg_resource *refl = lg_input(n, IN_REFLECT);
    if (refl) {
        if (lg_describe(refl, &info, n) != 0 || info.kind != LG_KIND_IMAGE)
            return lg_error(n, "input 'reflect' is not an image");
        if (!info.neutral && (info.image.format != LG_FORMAT_RGBA32F ||
                              (info.image.flags & (LG_IMAGE_CUBE | LG_IMAGE_DEPTH_ONLY))))
            return lg_error(n, "input 'reflect' must be a 2D rgba32f image; convert it first");
        if (!info.neutral && (info.image.width != st->width || info.image.height != st->height))
            return lg_error(n,
                            "input 'reflect' is %ux%u but the output is %ux%u: give the "
                            "node width and height of the reflect image (or render both "
                            "at the same size)",
                            info.image.width, info.image.height, st->width, st->height);
    }
    lg_image_desc d = { .width = st->width,
                        .height = st->height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = LG_IMAGE_DEPTH };
    rc = lg_declare_image(n, OUT_IMAGE, &d);
    if (rc)
        return rc;
    lg_vertex_image_size(st->vertices, &st->tex_w, &st->tex_h);
    lg_image_desc vd = { .width = st->tex_w, .height = st->tex_h, .format = LG_FORMAT_RGBA32F };
    if ((rc = lg_declare_image(n, OUT_VERTICES, &vd)))
        return rc;
    if (st->spin != 0.0)
        lg_set_per_frame(n, true);
    return lg_set_device(n, st->backend);
}

/* ---- the frame's inputs ---------------------------------------------------------------------- */

typedef struct prt_frame {
    const lg_scene *s;
    const lg_resource *scene_res;
    lg_sh sh_view;
    lg_transfer tr_view;
    const lg_sh *sh;
    const lg_transfer *tr;
    uint32_t bands;             /* the common prefix */
    uint32_t nc;                /* bands^2 */
    float *lighting;            /* float[3][nc], rotated; malloc'd, freed by prt_execute */
    const lg_resource *reflect; /* NULL, or a non-neutral image */
    /* rigid motion (ABI 3.1): the vertices [first, end) the dot products write with
     * `lighting`; 0 and st->vertices unless prt_motion_runs splits them */
    uint32_t first, end;
    double time; /* lg_frame.time: the pose the raster pass draws */
} prt_frame;

/* A run of consecutive meshes whose lighting is turned alike (prt_motion_runs). */
typedef struct prt_run {
    uint32_t first, end; /* vertices */
    double Q[9];         /* the SH rotation, row-major: R_m^T (the node's rotation) */
} prt_run;

/* The rotation of frame `frame`: R = Ry(yaw + spin t) Rx(pitch) Rz(roll) (probe.h's
 * convention), row-major double for lightgraph/sh.h. Rebuilt from the absolute angle
 * every frame, never composed (sh.h, "Rotation"). Returns false for the identity. */
static bool prt_rotation(const prt_state *st, const lg_frame *frame, double R[9])
{
    double yaw = st->rotate[0];
    if (st->spin != 0.0)
        yaw += st->spin * (frame ? frame->time : 0.0);
    /* reduced in double so that a long run keeps its fraction of a degree */
    yaw = fmod(yaw, 360.0);
    if (yaw == 0.0 && st->rotate[1] == 0.0 && st->rotate[2] == 0.0)
        return false;
    float c[9];
    lg_probe_rotation_from_euler((float)yaw, (float)st->rotate[1], (float)st->rotate[2], c);
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            R[3 * r + k] = c[3 * k + r]; /* column-major -> row-major */
    return true;
}

static int prt_frame_in(lg_node *n, prt_state *st, const lg_frame *frame, prt_frame *f)
{
    memset(f, 0, sizeof *f);
    f->end = st->vertices;
    f->time = frame ? frame->time : 0.0;
    f->scene_res = lg_input(n, IN_SCENE);
    f->s = lg_scene_get(n, f->scene_res);
    if (!f->s)
        return LG_ERR_INVALID;
    const lg_scene *s = f->s;
    if (st->n_offsets < s->n_meshes + 1) {
        uint32_t *o = realloc(st->offsets, (s->n_meshes + 1) * sizeof *o);
        if (!o)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u meshes)", s->n_meshes);
        st->offsets = o;
        st->n_offsets = s->n_meshes + 1;
    }
    uint64_t total = 0;
    for (uint32_t m = 0; m < s->n_meshes; m++) {
        st->offsets[m] = (uint32_t)total;
        total += s->meshes[m].n_vertices;
    }
    if (total != st->vertices)
        return lg_error(n,
                        "input 'scene' has %llu vertices now but %u when the node was "
                        "prepared",
                        (unsigned long long)total, st->vertices);

    lg_resource_info info;
    const lg_resource *lr = lg_input(n, IN_LIGHTING), *tres = lg_input(n, IN_TRANSFER);
    f->sh = lg_sh_get(n, lr, &f->sh_view);
    if (!f->sh) {
        if (lr && lg_describe(lr, &info, n) == 0 && info.neutral)
            return lg_error(n, "input 'lighting' is empty (its producer was gated)");
        return LG_ERR_INVALID;
    }
    f->tr = lg_transfer_get(n, tres, &f->tr_view);
    if (!f->tr) {
        if (tres && lg_describe(tres, &info, n) == 0 && info.neutral)
            return lg_error(n, "input 'transfer' is empty (its producer was gated)");
        return LG_ERR_INVALID;
    }
    if (f->tr->info.vertices != st->vertices)
        return lg_error(n,
                        "input 'transfer' has %u vertices but the scene has %u (%u meshes): "
                        "the transfer was baked for another scene",
                        f->tr->info.vertices, st->vertices, s->n_meshes);
    uint32_t lb = f->sh->info.bands, tb = f->tr->info.bands;
    f->bands = lb < tb ? lb : tb;
    f->nc = f->bands * f->bands;
    if (lb != tb && !st->logged_bands) {
        st->logged_bands = true;
        lg_log(n, LG_LOG_DEBUG,
               "lighting has %u bands, transfer %u: using the first %u (SH is hierarchical: "
               "the common prefix is the exact truncation)",
               lb, tb, f->bands);
    }

    /* the lighting truncated to the common prefix, then rotated (the rotation is
     * block-diagonal by band, so truncating first is exact) */
    lg_cpu_view cv;
    int rc = lg_map_cpu(n, f->sh->coeffs, LG_READ, &cv);
    if (rc)
        return rc;
    const float *src = cv.pixels;
    f->lighting = malloc((size_t)3 * f->nc * sizeof(float));
    if (!f->lighting)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u coefficients)", f->nc);
    for (int c = 0; c < 3; c++)
        memcpy(f->lighting + (size_t)c * f->nc, src + (size_t)c * f->sh->n_coeffs,
               f->nc * sizeof(float));
    double R[9];
    if (prt_rotation(st, frame, R)) {
        double *mats = malloc(lg_sh_rotation_size(f->bands) * sizeof(double));
        if (!mats)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (SH rotation, %u bands)",
                                 f->bands);
        if (lg_sh_rotation_build(f->bands, R, mats) != 0) {
            free(mats);
            return lg_error(n,
                            "the rotation of rotate_deg = [%g, %g, %g] (spin %g deg/s) is "
                            "not finite",
                            st->rotate[0], st->rotate[1], st->rotate[2], st->spin);
        }
        lg_sh_rotate_planes_f(f->bands, mats, 3, f->lighting, f->lighting);
        free(mats);
    }
    for (size_t i = 0; i < (size_t)3 * f->nc; i++)
        if (!isfinite(f->lighting[i]))
            return lg_error(n,
                            "input 'lighting': coefficient %zu of channel %zu is %g (not "
                            "finite)",
                            i % f->nc, i / f->nc, (double)f->lighting[i]);
    const lg_resource *b = lg_input(n, IN_REFLECT);
    if (b && lg_describe(b, &info, n) == 0 && !info.neutral)
        f->reflect = b;
    return 0;
}

/* ---- the dot products ------------------------------------------------------------------------ */

typedef struct prt_pool_ctx {
    prt_cpu_job job;
    size_t offset; /* the first texel of the range (rigid motion: one mesh run) */
} prt_pool_ctx;

static void prt_cpu_chunk(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const prt_pool_ctx *c = ctx;
    lg_prt_cpu_range(&c->job, c->offset + begin, c->offset + end);
}

static int prt_dot_cpu(lg_node *n, prt_state *st, const prt_frame *f)
{
    lg_cpu_view tv, ov;
    int rc = lg_map_cpu(n, f->tr->transfer, LG_READ, &tv);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, OUT_VERTICES), LG_WRITE, &ov);
    if (rc)
        return rc;
    prt_pool_ctx c = { .job = { .transfer = tv.pixels,
                                .lighting = f->lighting,
                                .n = f->nc,
                                .stride = f->tr->n_coeffs,
                                .vertices = st->vertices,
                                .out = ov.pixels } };
    if (f->first > 0 || f->end < st->vertices) { /* one run of a moving scene */
        c.offset = f->first;
        return lg_parallel_for(n, f->end - f->first, PRT_CPU_GRAIN, prt_cpu_chunk, &c);
    }
    return lg_parallel_for(n, (size_t)st->tex_w * st->tex_h, PRT_CPU_GRAIN, prt_cpu_chunk, &c);
}

/* A table of this frame's, in a buffer kept while large enough (the write blocks: the
 * data is the frame's). */
static int prt_cl_upload(lg_node *n, lg_cl_buffer *b, const void *data, size_t size)
{
    int rc = lg_cl_buffer_recreate(n, b, size, CL_MEM_READ_ONLY);
    return rc ? rc : lg_cl_buffer_write(n, b, 0, size, data);
}

static int prt_dot_cl(lg_node *n, prt_state *st, const prt_frame *f)
{
    int rc;
    uint32_t stride = f->tr->n_coeffs;
    if (!st->kernel || st->k_n != f->nc || st->k_stride != stride) {
        /* one program per coefficient count: the kernel's loops unroll (prt.cl) */
        char opts[160];
        prt_cl_options(opts, sizeof opts, f->nc, stride);
        static const char *const src[] = { lg_src_prt_cl };
        static const char *const names[] = { lg_src_prt_cl_file };
        lg_cl_pass_desc d = { .name = "prt dot",
                              .sources = src,
                              .source_names = names,
                              .n_sources = 1,
                              .options = opts,
                              .kernel = "prt_dot" };
        lg_cl_pass_destroy(&st->kernel);
        if ((rc = lg_cl_pass_create(n, &d, &st->kernel)))
            return rc;
        st->k_n = f->nc;
        st->k_stride = stride;
    }
    size_t pad = PRT_RECORD_PAD(stride);
    float *rec = malloc(3 * pad * sizeof(float));
    if (!rec)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu floats)", 3 * pad);
    prt_record_lighting(f->lighting, f->nc, stride, rec);
    rc = prt_cl_upload(n, &st->cl_record, rec, 3 * pad * sizeof(float));
    free(rec);
    if (!rc)
        rc = prt_cl_upload(n, &st->cl_light, f->lighting, (size_t)3 * f->nc * sizeof(float));
    if (rc)
        return rc;
    uint32_t texels = st->tex_w * st->tex_h;
    lg_cl_pass *k = st->kernel;
    lg_cl_pass_arg_resource(k, 0, f->tr->transfer, LG_READ);
    lg_cl_pass_arg_mem(k, 1, st->cl_record.mem);
    lg_cl_pass_arg_mem(k, 2, st->cl_light.mem);
    lg_cl_pass_arg_uint(k, 3, st->vertices);
    lg_cl_pass_arg_uint(k, 4, texels);
    lg_cl_pass_arg_resource(k, 5, lg_output(n, OUT_VERTICES), LG_WRITE);
    size_t global = prt_cl_global(texels), local = PRT_CL_LOCAL;
    return lg_cl_pass_run(k, 1, &global, &local);
}

/* The dot products on GL: shaders/prt/prt_dot.frag drawn as a full-screen triangle into the
 * `vertices` image (on llvmpipe 2-3.5x faster than the same work as a compute shader:
 * README.md, Roofline), or, for a transfer past GL_MAX_TEXTURE_BUFFER_SIZE floats,
 * prt_dot.comp reading it as a storage buffer. */
static int prt_dot_gl(lg_node *n, prt_state *st, const prt_frame *f)
{
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc;
    GLint max_tbo = 0;
    gl->GetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &max_tbo);
    int frag = prt_gl_frag_fits(st->vertices, f->tr->n_coeffs, max_tbo);
    if (st->dot && (st->g_n != f->nc || st->g_stride != f->tr->n_coeffs || st->g_frag != frag))
        lg_gl_pass_destroy(&st->dot);
    if (!st->dot) {
        /* one program per coefficient count: its loops unroll (prt_dot.frag, .comp) */
        static const lg_gl_shader_src frag_src[2] = {
            { GL_VERTEX_SHADER, lg_src_prt_dot_vert_file, lg_src_prt_dot_vert },
            { GL_FRAGMENT_SHADER, lg_src_prt_dot_frag_file, lg_src_prt_dot_frag },
        };
        static const lg_gl_shader_src comp_src[1] = {
            { GL_COMPUTE_SHADER, lg_src_prt_dot_comp_file, lg_src_prt_dot_comp },
        };
        char defines[96];
        if (frag)
            prt_gl_frag_defines(defines, sizeof defines, f->nc, f->tr->n_coeffs, 0);
        else
            prt_gl_defines(defines, sizeof defines, f->nc, f->tr->n_coeffs, 0);
        lg_gl_pass_desc d = { .name = "prt (dot products)",
                              .stages = frag ? frag_src : comp_src,
                              .n_stages = frag ? 2 : 1,
                              .defines = defines,
                              .colors = { frag ? GL_RGBA32F : 0 } };
        if ((rc = lg_gl_pass_create(n, &d, &st->dot)))
            return rc;
        st->g_n = f->nc;
        st->g_stride = f->tr->n_coeffs;
        st->g_frag = frag;
        st->d_vertices = lg_gl_pass_uniform(st->dot, "u_vertices");
        st->d_width = lg_gl_pass_uniform(st->dot, "u_width");
        if (frag) {
            st->d_light = lg_gl_pass_uniform(st->dot, "u_lighting[0]");
            st->d_first = lg_gl_pass_uniform(st->dot, "u_first");
            st->d_end = lg_gl_pass_uniform(st->dot, "u_end");
            st->d_transfer = lg_gl_pass_texture(st->dot, "u_transfer");
        } else {
            st->d_texels = lg_gl_pass_uniform(st->dot, "u_texels");
            st->d_transfer = lg_gl_pass_storage(st->dot, "Transfer");
            st->d_lighting = lg_gl_pass_storage(st->dot, "Lighting");
            st->d_out = lg_gl_pass_image(st->dot, "u_out");
        }
    }
    GLuint tbuf = 0, dummy = 0;
    if ((rc = lg_map_gl(n, f->tr->transfer, LG_READ, &tbuf, &dummy)))
        return rc;
    if (frag) {
        lg_gl_target t;
        if ((rc = lg_gl_target_output(n, "vertices", &t)))
            return rc;
        /* remade when the host's buffer object changes */
        if ((rc = lg_gl_buffer_texture_recreate(n, &st->tbo, GL_RGB32F, tbuf)) < 0)
            return rc;
        if ((rc = lg_gl_pass_begin(st->dot, &t)))
            return rc;
        lg_gl_set_uint(st->dot, st->d_vertices, st->vertices);
        lg_gl_set_uint(st->dot, st->d_width, st->tex_w);
        lg_gl_set_uint(st->dot, st->d_first, f->first);
        lg_gl_set_uint(st->dot, st->d_end, f->end);
        lg_gl_set_floatv(st->dot, st->d_light, 3 * f->nc, f->lighting);
        lg_gl_pass_bind_texture(st->dot, st->d_transfer, st->tbo.name);
        return lg_gl_pass_end(st->dot, lg_gl_pass_draw(st->dot, GL_TRIANGLES, 3));
    }
    if ((rc = lg_gl_buffer_recreate(n, &st->light_buf, 3 * (size_t)f->nc * sizeof(float), 0,
                                    f->lighting)))
        return rc;
    GLuint otex = 0;
    if ((rc = lg_map_gl(n, lg_output(n, OUT_VERTICES), LG_WRITE, &otex, &dummy)))
        return rc;
    if ((rc = lg_gl_pass_begin(st->dot, NULL)))
        return rc;
    uint32_t texels = st->tex_w * st->tex_h, gx, gy;
    lg_gl_set_uint(st->dot, st->d_vertices, st->vertices);
    lg_gl_set_uint(st->dot, st->d_width, st->tex_w);
    lg_gl_set_uint(st->dot, st->d_texels, texels);
    lg_gl_pass_bind_buffer(st->dot, st->d_transfer, tbuf);
    lg_gl_pass_bind_buffer(st->dot, st->d_lighting, st->light_buf.name);
    lg_gl_pass_bind_image(st->dot, st->d_out, otex, GL_WRITE_ONLY, GL_RGBA32F);
    prt_gl_groups(texels, &gx, &gy);
    return lg_gl_pass_end(st->dot, lg_gl_pass_dispatch_groups(st->dot, gx, gy, 1));
}

/* ---- the raster pass ------------------------------------------------------------------------- */

typedef struct prt_draw_ctx {
    prt_state *st;
} prt_draw_ctx;

static int prt_on_mesh(lg_node *n, void *user, uint32_t mi, GLuint *normals)
{
    (void)n;
    (void)normals;
    prt_state *st = ((prt_draw_ctx *)user)->st;
    lg_gl_set_int(st->raster, st->r_offset, (int32_t)st->offsets[mi]);
    return 0;
}

static int prt_raster(lg_node *n, prt_state *st, const prt_frame *f)
{
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc;
    if (!st->raster) {
        static const lg_gl_shader_src src[2] = {
            { GL_VERTEX_SHADER, lg_src_prt_vert_file, lg_src_prt_vert },
            { GL_FRAGMENT_SHADER, lg_src_prt_frag_file, lg_src_prt_frag },
        };
        lg_gl_pass_desc d = { .name = "prt (raster)",
                              .stages = src,
                              .n_stages = 2,
                              .colors = { GL_RGBA32F },
                              .depth = true,
                              .depth_test = true,
                              .depth_write = true,
                              .cull = LG_GL_CULL_BACK,
                              .scene = LG_GL_SCENE_POSITIONS };
        if ((rc = lg_gl_pass_create(n, &d, &st->raster)))
            return rc;
        st->r_view_proj = lg_gl_pass_uniform(st->raster, "u_view_proj");
        st->r_offset = lg_gl_pass_uniform(st->raster, "u_offset");
        st->r_vertices = lg_gl_pass_texture(st->raster, "u_vertices");
    }
    lg_scene_view v;
    if ((rc = lg_scene_view_make(n, f->s, st->camera, st->width, st->height, &v)))
        return rc;
    GLuint vtex = 0, dummy = 0;
    /* the values the backend just wrote (moved to GL by the host for cl and cpu) */
    if ((rc = lg_map_gl(n, lg_output(n, OUT_VERTICES), LG_READ, &vtex, &dummy)))
        return rc;
    lg_gl_target t;
    if ((rc = lg_gl_target_output(n, "out", &t)))
        return rc;
    lg_gl_pass_set_time(st->raster, f->time); /* an animated scene's pose (ABI 3.1) */
    if ((rc = lg_gl_pass_begin(st->raster, &t)))
        return rc;
    static const float zero[4] = { 0, 0, 0, 0 };
    lg_gl_pass_clear_color(st->raster, 0, zero);
    lg_gl_pass_clear_depth(st->raster, 1.0f);
    if (f->s->features.triangles > 0) {
        lg_gl_set_mat4(st->raster, st->r_view_proj, v.view_proj);
        lg_gl_pass_bind_texture(st->raster, st->r_vertices, vtex);
        prt_draw_ctx ctx = { st };
        lg_gl_scene_draw d = { .on_mesh = prt_on_mesh, .user = &ctx };
        rc = lg_gl_pass_draw_scene(st->raster, f->scene_res, &d);
    }
    if ((rc = lg_gl_pass_end(st->raster, rc)))
        return rc;
    if (!f->reflect)
        return 0;

    /* reflect: its RGB added texel for texel (alpha and depth stay the raster's) */
    if (!st->refl) {
        static const lg_gl_shader_src src[2] = {
            { GL_VERTEX_SHADER, lg_src_prt_reflect_vert_file, lg_src_prt_reflect_vert },
            { GL_FRAGMENT_SHADER, lg_src_prt_reflect_frag_file, lg_src_prt_reflect_frag },
        };
        lg_gl_pass_desc d = { .name = "prt (reflect)",
                              .stages = src,
                              .n_stages = 2,
                              .colors = { GL_RGBA32F },
                              .depth = true,
                              .blend = LG_GL_BLEND_ADD };
        if ((rc = lg_gl_pass_create(n, &d, &st->refl)))
            return rc;
        st->f_reflect = lg_gl_pass_texture(st->refl, "u_reflect");
    }
    GLuint rtex = 0;
    if ((rc = lg_map_gl(n, f->reflect, LG_READ, &rtex, &dummy)))
        return rc;
    if ((rc = lg_gl_pass_begin(st->refl, &t)))
        return rc;
    lg_gl_pass_bind_texture(st->refl, st->f_reflect, rtex);
    return lg_gl_pass_end(st->refl, lg_gl_pass_draw(st->refl, GL_TRIANGLES, 3));
}

/* ---- execute / destroy ----------------------------------------------------------------------- */

/* ---- rigid motion (ABI 3.1) ------------------------------------------------------------------ */

/* The rotation part of a 3x3 (column-major float, as lg_instance.model's upper left):
 * row-major double, its rows made orthonormal (a uniform scale divides out; a non-uniform
 * one leaves the nearest rotation Gram-Schmidt finds). */
static void prt_rotation_of(const double m[9], double R[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            R[3 * r + c] = m[3 * c + r];
    lg_sh_orthonormalize(R);
}

/* Transfer is baked in each mesh's frame of its first instance at rest (lightgraph/
 * transfer.h): when an animation turns that instance by R_m = rot(model(t) model(rest)^-1),
 * the lighting the mesh sees, in the frame its transfer was baked in, is the world lighting
 * turned by R_m^T: g(w) = f(R_m w). Composed with the node's own rotation Rn (the lighting
 * moved to Rn v), one SH rotation Q = R_m^T Rn per mesh. Consecutive meshes with the same
 * Q form a run: the dot products run once per run. *runs is NULL (and *n_runs 0) when no
 * mesh turns: one pass over every vertex, as without animation. Translation does not
 * change distant lighting; scale is not a rotation (README.md, "Rigid motion"). */
static int prt_motion_runs(lg_node *n, const prt_state *st, const lg_scene *s, double time,
                           const double Rn[9], prt_run **runs, uint32_t *n_runs)
{
    *runs = NULL;
    *n_runs = 0;
    if (!lg_scene_is_animated(s) || s->n_meshes == 0)
        return 0;
    lg_instance *posed = malloc(((size_t)s->n_instances + 1) * sizeof *posed);
    prt_run *r = calloc(s->n_meshes, sizeof *r);
    int32_t *first_inst = malloc(s->n_meshes * sizeof *first_inst);
    if (!posed || !r || !first_inst) {
        free(posed), free(r), free(first_inst);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u instances)", s->n_instances);
    }
    int rc = lg_scene_pose(n, s, time, posed);
    for (uint32_t m = 0; m < s->n_meshes; m++)
        first_inst[m] = -1;
    for (uint32_t i = 0; !rc && i < s->n_instances; i++)
        if (s->instances[i].mesh < s->n_meshes && first_inst[s->instances[i].mesh] < 0)
            first_inst[s->instances[i].mesh] = (int32_t)i;
    uint32_t k = 0;
    bool turned = false;
    for (uint32_t m = 0; !rc && m < s->n_meshes; m++) {
        double Q[9];
        memcpy(Q, Rn, sizeof Q);
        int32_t i = first_inst[m];
        if (i >= 0) {
            double a[9], b[9], Ra[9], Rb[9], Rm[9];
            for (int c = 0; c < 3; c++)
                for (int e = 0; e < 3; e++) {
                    a[3 * c + e] = posed[i].model[4 * c + e];
                    b[3 * c + e] = s->instances[i].model[4 * c + e];
                }
            prt_rotation_of(a, Ra);
            prt_rotation_of(b, Rb);
            /* R_m = Ra Rb^T; Q = R_m^T Rn = Rb Ra^T Rn */
            for (int x = 0; x < 3; x++)
                for (int y = 0; y < 3; y++) {
                    double v = 0;
                    for (int z = 0; z < 3; z++)
                        v += Ra[3 * x + z] * Rb[3 * y + z];
                    Rm[3 * x + y] = v;
                }
            for (int x = 0; x < 3; x++)
                for (int y = 0; y < 3; y++) {
                    double v = 0;
                    for (int z = 0; z < 3; z++)
                        v += Rm[3 * z + x] * Rn[3 * z + y];
                    Q[3 * x + y] = v;
                }
            for (int e = 0; e < 9 && !turned; e++)
                turned = fabs(Q[e] - Rn[e]) > 1e-12;
        }
        uint32_t first = st->offsets[m], end = first + s->meshes[m].n_vertices;
        if (k > 0 && !memcmp(r[k - 1].Q, Q, sizeof Q) && r[k - 1].end == first) {
            r[k - 1].end = end;
            continue;
        }
        r[k].first = first;
        r[k].end = end;
        memcpy(r[k].Q, Q, sizeof Q);
        k++;
    }
    free(posed), free(first_inst);
    if (rc || !turned) {
        free(r);
        return rc;
    }
    *runs = r;
    *n_runs = k;
    return 0;
}

static int prt_dot(lg_node *n, prt_state *st, const prt_frame *f)
{
    if (st->backend == LG_DEVICE_GL)
        return prt_dot_gl(n, st, f);
    if (st->backend == LG_DEVICE_CL)
        return prt_dot_cl(n, st, f);
    return prt_dot_cpu(n, st, f);
}

/* The dot products of a moving scene: per run, the input lighting (before the node's
 * rotation) turned by the run's Q, over the run's vertices. */
static int prt_dot_runs(lg_node *n, prt_state *st, prt_frame *f, const float *unrotated,
                        const prt_run *runs, uint32_t n_runs)
{
    if (st->backend == LG_DEVICE_CL || (st->backend == LG_DEVICE_GL && st->dot && !st->g_frag))
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "the scene's animation turns meshes: the %s dot products cannot "
                             "turn the lighting per mesh yet; use backend gl or cpu",
                             st->backend == LG_DEVICE_CL ? "cl" : "gl compute (large transfer)");
    double *mats = malloc(lg_sh_rotation_size(f->bands) * sizeof(double));
    float *keep = f->lighting;
    if (!mats)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (SH rotation, %u bands)", f->bands);
    int rc = 0;
    for (uint32_t k = 0; k < n_runs && !rc; k++) {
        if (lg_sh_rotation_build(f->bands, runs[k].Q, mats) != 0) {
            rc = lg_error(n, "the animation's rotation of vertices %u..%u is not finite",
                          runs[k].first, runs[k].end);
            break;
        }
        lg_sh_rotate_planes_f(f->bands, mats, 3, unrotated, keep);
        f->first = runs[k].first;
        f->end = runs[k].end;
        rc = prt_dot(n, st, f);
    }
    free(mats);
    f->first = 0;
    f->end = st->vertices;
    return rc;
}

static int prt_execute(lg_node *n, const lg_frame *frame)
{
    prt_state *st = n->user;
    prt_frame f;
    int rc = prt_frame_in(n, st, frame, &f);
    prt_run *runs = NULL;
    uint32_t n_runs = 0;
    float *unrotated = NULL;
    if (!rc && lg_scene_is_animated(f.s)) {
        double Rn[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
        prt_rotation(st, frame, Rn);
        rc = prt_motion_runs(n, st, f.s, frame->time, Rn, &runs, &n_runs);
        if (!rc && n_runs) {
            /* the input lighting again, before the node's rotation (Q includes it) */
            lg_cpu_view cv;
            unrotated = malloc((size_t)3 * f.nc * sizeof(float));
            if (!unrotated)
                rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u coefficients)", f.nc);
            if (!rc && !(rc = lg_map_cpu(n, f.sh->coeffs, LG_READ, &cv)))
                for (int c = 0; c < 3; c++)
                    memcpy(unrotated + (size_t)c * f.nc,
                           (const float *)cv.pixels + (size_t)c * f.sh->n_coeffs,
                           f.nc * sizeof(float));
        }
    }
    if (!rc && n_runs)
        rc = prt_dot_runs(n, st, &f, unrotated, runs, n_runs);
    else if (!rc)
        rc = prt_dot(n, st, &f);
    free(runs);
    free(unrotated);
    if (!rc)
        rc = prt_raster(n, st, &f);
    if (!rc)
        lg_log(n, LG_LOG_INFO, "%u vertices, %u bands (lighting %u, transfer %u), %s%s",
               st->vertices, f.bands, f.sh->info.bands, f.tr->info.bands,
               st->backend == LG_DEVICE_GL   ? "gl"
               : st->backend == LG_DEVICE_CL ? "cl"
                                             : "cpu",
               f.reflect ? ", reflect added" : "");
    free(f.lighting);
    return rc;
}

static void prt_destroy(lg_node *n)
{
    prt_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->dot);
    lg_gl_pass_destroy(&st->raster);
    lg_gl_pass_destroy(&st->refl);
    lg_gl_buffer_destroy(n, &st->light_buf);
    lg_gl_buffer_texture_destroy(n, &st->tbo);
    lg_cl_pass_destroy(&st->kernel);
    lg_cl_buffer_destroy(n, &st->cl_light);
    lg_cl_buffer_destroy(n, &st->cl_record);
    free(st->offsets);
    free(st);
    n->user = NULL;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const lg_param_desc prt_params[] = {
    /* where the dot products run; the scene is rasterised on GL in every case */
    LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL | LG_BACKEND_CL, LG_BACKEND_GL),
    { .key = "rotate_deg",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .min = -PRT_MAX_DEG,
      .max = PRT_MAX_DEG,
      .doc = "[yaw, pitch, roll], degrees: the lighting turned by R = Ry(yaw) Rx(pitch) "
             "Rz(roll), the probe node's rotate_deg convention (a light at v moves to R v)" },
    { .key = "spin_deg_per_s",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -PRT_MAX_DEG,
      .max = PRT_MAX_DEG,
      .doc = "degrees of yaw per second added to rotate_deg's yaw (frame time x rate); "
             "non-zero makes the node run every frame" },
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16384,
      .doc = "output width in pixels; 0 = the render size (--size)",
      .role = LG_ROLE_IMAGE_WIDTH },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16384,
      .doc = "output height in pixels; 0 = the render size (--size)",
      .role = LG_ROLE_IMAGE_HEIGHT },
    { .key = "camera",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "index of the scene's camera to look through; -1 = the scene's active camera" },
};

static const lg_port_desc prt_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene the transfer was baked for (its camera and geometry)" },
    { .name = "lighting", .kind = LG_KIND_SH, .doc = "SH lighting (sh_project)" },
    { .name = "transfer",
      .kind = LG_KIND_TRANSFER,
      .doc = "per-vertex transfer vectors of the scene (prt_bake)" },
    { .name = "reflect",
      .kind = LG_KIND_IMAGE,
      .optional = true,
      .doc = "rgba32f image of the output's size (reflect's output, say): its RGB is added "
             "(the specular part, seed 0 §5.7)" },
};
static const lg_port_desc prt_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "linear HDR radiance, rgba32f, alpha 1 where geometry covers the pixel and 0 "
             "elsewhere (RGB 0 there, plus reflect), with a depth plane (GL window depth, 1 "
             "= nothing)" },
    { .name = "vertices",
      .kind = LG_KIND_IMAGE,
      .doc = "the per-vertex radiance, rgba32f, LG_VERTEX_IMAGE_WIDTH wide: vertex i at (i "
             "mod W, i / W), alpha 1, padding 0 (lightgraph/transfer.h)" },
};

static const lg_node_type prt_types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "prt",
    .doc = "Diffuse PRT: per-vertex radiance = lighting . transfer per channel (gl, cl or "
           "cpu), the lighting rotated at run time, rasterised with the scene's camera",
    LG_PARAMS(prt_params),
    LG_INPUTS(prt_inputs),
    LG_OUTPUTS(prt_outputs),
    .needs = LG_NEEDS_GEOMETRY,
    .create = prt_create,
    .prepare = prt_prepare,
    .execute = prt_execute,
    .destroy = prt_destroy,
} };

LG_PLUGIN_DEFINE("prt", "1.0.0",
                 "Precomputed radiance transfer at run time: per-vertex SH dot products on "
                 "gl, cl and cpu, rotation, rasterised",
                 prt_types)
