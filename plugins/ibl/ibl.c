/*
 * The ibl plugin: image-based lighting from a light probe (TECHNIQUES.md §3, seed 0 ch. 3)
 * on cpu, gl and cl.
 *
 *   reflect     scene + probe [+ base] -> image: reflection mapping, the probe looked up
 *               along R = reflect(V, N), times the material's reflectivity (or Schlick's
 *               Fresnel with it as F0), added to `base`
 *   envmap      the same looked up along N (view-independent)
 *   background  scene + probe [+ base] -> image: the probe seen through the camera where
 *               no geometry (and no depth of `base`) covers the pixel
 *
 * Every node rasterises the scene on GL into a G-buffer (world normal, material index,
 * depth; skipped when the scene has no triangles) and then shades every pixel on the
 * chosen backend: a full-screen fragment pass on GL (shaders/ibl/ibl_shade.frag), a kernel
 * on CL (shaders/ibl/ibl.cl), lg_probe_lookup over the host's thread pool on the CPU
 * (ibl_shade_pixel below). The three compute the same thing with the same arithmetic; the
 * probe lookups are lightgraph/probe.h's and their GPU twins (shaders/common/probe.glsl,
 * probe.cl). README.md gives the ports, parameters, equations and measurements.
 *
 * The G-buffer reaches the CPU and CL backends through host memory (glGetTextureImage, then
 * a CL buffer), as the host's own moves between llvmpipe and PoCL do.
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/gl_pass.h"
#include "lightgraph/image.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"
#include "ggx_prefilter.h"
#include "ibl_cache.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"
#include "lightgraph/vecmath.h"

#include "ibl.cl.h"
#include "ibl_fullscreen.vert.h"
#include "ibl_gbuffer.frag.h"
#include "ibl_gbuffer.vert.h"
#include "ibl_shade.frag.h"
#include "probe.cl.h"
#include "rgbe.cl.h"

enum { IBL_REFLECT = 0, IBL_ENVMAP, IBL_BACKGROUND };
enum { IBL_RGBA32F = 0, IBL_RGBA16F, IBL_RGBE8 };
enum { IBL_BILINEAR = 0, IBL_NEAREST };
enum { IBL_FRESNEL_NONE = 0, IBL_FRESNEL_SCHLICK };
enum { IBL_GLOSSY_AUTO = 0, IBL_GLOSSY_OFF };

/* input ports */
enum { IN_SCENE = 0, IN_PROBE, IN_BASE };

typedef struct ibl_state {
    int mode, format, sampling, fresnel, glossy;
    lg_device backend;
    float reflectivity[3]; /* < 0: the material's */
    int64_t camera;
    uint32_t width, height;
    uint32_t levels_param, size_param, samples, weighting;
    bool warned_clamp;
    bool reported_nonfinite; /* base's NaN/Inf pixels said (lg_check_input_finite) */

    /* the GGX chain (glossy = auto, some reflective material rough): a cube of face
     * chain_size with chain_levels levels, in the probe's frame, made once (or loaded from
     * the host's cache); its GL texture and CL buffer are made on first use */
    float *chain;
    uint32_t chain_size, chain_levels;
    bool chain_tried;
    bool cache_probed;    /* prepare() looked the chain up in the cache (and missed) */
    bool chain_unchecked; /* st->chain came from the cache: its values not yet held to
                           * the probe's range (ibl_chain_bad, in execute) */
    lg_gl_texture chain_tex;
    lg_gl_buffer dfg_buf;
    lg_cl_buffer cl_chain, cl_dfg;

    /* GL: the G-buffer pass and its images, the shading pass */
    lg_gl_pass *gpass, *spass;
    lg_gl_uniform g_view_proj, g_material;
    lg_gl_binding s_params;
    lg_gl_binding s_gbuf, s_gdepth, s_base, s_base_depth, s_probe2d, s_probecube, s_mats, s_clamped,
        s_chain, s_dfg;
    lg_gl_texture gbuf_tex, gdepth_tex;
    lg_gl_buffer mats_buf, clamp_buf;

    /* CL */
    lg_cl_pass *kernel;
    lg_cl_buffer cl_gbuf, cl_gdepth, cl_mats, cl_clamped;

    /* CPU copies of the G-buffer (cpu and cl backends) */
    float *gbuf, *gdepth;
} ibl_state;

/* ---- create / prepare ------------------------------------------------------------------------ */

static int ibl_create(lg_node *n, int mode)
{
    ibl_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->mode = mode;
    st->backend = lg_param_backend(n);
    st->format = lg_param_enum(n, "format");
    st->sampling = lg_param_enum(n, "sampling");
    st->camera = lg_param_int(n, "camera");
    st->reflectivity[0] = st->reflectivity[1] = st->reflectivity[2] = -1.0f;
    if (mode != IBL_BACKGROUND) {
        st->fresnel = lg_param_enum(n, "fresnel");
        st->glossy = lg_param_enum(n, "glossy");
        st->levels_param = (uint32_t)lg_param_int(n, "levels");
        st->size_param = (uint32_t)lg_param_int(n, "prefilter_size");
        st->samples = (uint32_t)lg_param_int(n, "prefilter_samples");
        /* the enum's order is lg_probe_prefilter_weighting's */
        st->weighting = (uint32_t)lg_param_enum(n, "prefilter_weighting");
        const lg_value *r = lg_param(n, "reflectivity");
        bool any_neg = false, all_neg = true;
        for (int i = 0; i < 3; i++) {
            double v = r ? r->v[i] : -1.0;
            if (!isfinite(v))
                return lg_error(n, "reflectivity[%d] = %g is not finite", i, v);
            any_neg |= v < 0;
            all_neg &= v < 0;
            st->reflectivity[i] = (float)v;
        }
        if (any_neg && !all_neg)
            return lg_error(n,
                            "reflectivity = [%g, %g, %g]: give three values >= 0, or "
                            "[-1, -1, -1] for the materials' own",
                            (double)st->reflectivity[0], (double)st->reflectivity[1],
                            (double)st->reflectivity[2]);
    }
    return 0;
}

static int ibl_create_reflect(lg_node *n)
{
    return ibl_create(n, IBL_REFLECT);
}
static int ibl_create_envmap(lg_node *n)
{
    return ibl_create(n, IBL_ENVMAP);
}
static int ibl_create_background(lg_node *n)
{
    return ibl_create(n, IBL_BACKGROUND);
}

static const lg_format ibl_formats[] = { LG_FORMAT_RGBA32F, LG_FORMAT_RGBA16F, LG_FORMAT_RGBE8 };
static const char *const ibl_format_names[] = { "rgba32f", "rgba16f", "rgbe8", NULL };

static int ibl_check_chain(lg_node *n, ibl_state *st, const lg_resource *probe);

static int ibl_prepare(lg_node *n)
{
    ibl_state *st = n->user;
    int rc = lg_output_size_nonempty(n, "width", "height", &st->width, &st->height);
    if (rc)
        return rc;
    lg_resource_info info;
    lg_assert_input(n, IN_SCENE);
    const lg_resource *pr = lg_input(n, IN_PROBE);
    if (!pr || lg_describe(pr, &info, n) != 0 || info.kind != LG_KIND_PROBE)
        return lg_error(n, "input 'probe' is not a light probe");
    const lg_resource *base = lg_input(n, IN_BASE);
    if (base) {
        if (lg_describe(base, &info, n) != 0 || info.kind != LG_KIND_IMAGE)
            return lg_error(n, "input 'base' is not an image");
        if (!info.neutral && (info.image.format != LG_FORMAT_RGBA32F ||
                              (info.image.flags & (LG_IMAGE_CUBE | LG_IMAGE_DEPTH_ONLY))))
            return lg_error(n,
                            "input 'base' must be a 2D rgba32f image (it is %s%s); convert "
                            "it first",
                            info.image.format == LG_FORMAT_RGBA16F ? "rgba16f"
                            : info.image.format == LG_FORMAT_RGBE8 ? "rgbe8"
                            : info.image.format == LG_FORMAT_RGBA8 ? "rgba8"
                                                                   : "rgba32f",
                            info.image.flags & LG_IMAGE_CUBE ? ", a cube" : "");
        if (!info.neutral && (info.image.width != st->width || info.image.height != st->height))
            return lg_error(n,
                            "input 'base' is %ux%u but the output is %ux%u: give the node "
                            "width and height of the base image (or leave both at 0)",
                            info.image.width, info.image.height, st->width, st->height);
    }
    lg_image_desc d = { .width = st->width,
                        .height = st->height,
                        .format = ibl_formats[st->format],
                        .flags = LG_IMAGE_DEPTH };
    rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    if (st->mode != IBL_BACKGROUND && (rc = ibl_check_chain(n, st, pr)))
        return rc;
    return lg_set_device(n, st->backend);
}

/* ---- the frame's inputs ---------------------------------------------------------------------- */

typedef struct ibl_frame {
    const lg_scene *s;
    const lg_resource *scene_res;
    lg_scene_view v;
    float inv_vp[16];
    lg_probe probe_view;
    const lg_probe *probe;
    const lg_resource *base; /* NULL, or a non-neutral base image */
    bool geometry;           /* the scene has triangles: the G-buffer pass runs */
    float *mats;             /* 8 floats per material: F0 rgb, roughness; double-sided */
    uint32_t n_mats;
    uint32_t rough; /* reflective materials with roughness > 0 (glossy = auto) */
    double time;    /* lg_frame.time: the pose the geometry pass draws (ABI 3.1) */
} ibl_frame;

/* The material table every backend reads: F0 (the material's reflectivity or the node's),
 * roughness (0 with glossy = off), double-sided. */
static int ibl_materials(lg_node *n, ibl_state *st, ibl_frame *f)
{
    const lg_scene *s = f->s;
    f->n_mats = s->n_materials ? s->n_materials : 1;
    f->mats = calloc((size_t)f->n_mats * 8, sizeof(float));
    if (!f->mats)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u materials)", f->n_mats);
    f->rough = 0;
    for (uint32_t i = 0; i < s->n_materials; i++) {
        const lg_material *m = &s->materials[i];
        float *o = f->mats + 8 * (size_t)i;
        for (int c = 0; c < 3; c++) {
            float r = st->reflectivity[0] >= 0 ? st->reflectivity[c] : m->reflectivity[c];
            o[c] = isfinite(r) && r > 0 ? r : 0.0f;
        }
        o[3] = 0.0f;
        if (st->mode != IBL_BACKGROUND && st->glossy == IBL_GLOSSY_AUTO && m->roughness > 0 &&
            (o[0] > 0 || o[1] > 0 || o[2] > 0)) {
            /* NaN fails the test above; glTF's range is [0, 1] */
            o[3] = m->roughness < 1.0f ? m->roughness : 1.0f;
            f->rough++;
        }
        o[4] = m->double_sided ? 1.0f : 0.0f;
    }
    return 0;
}

static int ibl_frame_in(lg_node *n, ibl_state *st, ibl_frame *f)
{
    memset(f, 0, sizeof *f);
    f->scene_res = lg_input(n, IN_SCENE);
    f->s = lg_scene_get(n, f->scene_res);
    if (!f->s)
        return LG_ERR_INVALID;
    int rc = lg_scene_view_make(n, f->s, st->camera, st->width, st->height, &f->v);
    if (rc)
        return rc;
    if (lg_m4_invert(f->inv_vp, f->v.view_proj))
        return lg_error(n, "camera %u: its view-projection matrix is singular", f->v.camera);
    const lg_resource *pres = lg_input(n, IN_PROBE);
    f->probe = lg_probe_get(n, pres, &f->probe_view);
    if (!f->probe) {
        lg_resource_info info;
        if (pres && lg_describe(pres, &info, n) == 0 && info.neutral)
            return lg_error(n, "input 'probe' is empty (its producer was gated)");
        return LG_ERR_INVALID;
    }
    const lg_image_desc *rd = &f->probe->radiance_desc;
    if (rd->format != LG_FORMAT_RGBA32F)
        return lg_error(n, "input 'probe': the radiance image is not rgba32f");
    if (rd->width == 0 || rd->height == 0)
        return lg_error(n, "input 'probe': the radiance image is empty");
    if (f->probe->info.layout < LG_PROBE_LATLONG || f->probe->info.layout > LG_PROBE_CUBE)
        return lg_error(n, "input 'probe': unknown layout %d", (int)f->probe->info.layout);
    if ((f->probe->info.layout == LG_PROBE_CUBE) != ((rd->flags & LG_IMAGE_CUBE) != 0))
        return lg_error(n, "input 'probe': the layout and the radiance image disagree (cube "
                           "layout without a cube image, or the reverse)");
    const lg_resource *b = lg_input(n, IN_BASE);
    lg_resource_info bi;
    if (b && lg_describe(b, &bi, n) == 0 && !bi.neutral)
        f->base = b;
    f->geometry = f->s->features.triangles > 0;
    return ibl_materials(n, st, f);
}

/* ---- the GGX chain (glossy reflection) ------------------------------------------------------- */

static size_t ibl_chain_floats(uint32_t size, uint32_t levels)
{
    lg_image_desc d = { .width = size, .height = size, .flags = LG_IMAGE_CUBE, .levels = levels };
    return 4 * lg_image_offset(&d, levels, 0);
}

/* The chain's level `l` as a lookup image (the probe's rotation: the chain is in its
 * frame). */
static lg_probe_image ibl_chain_level(const ibl_state *st, const float *rotation, uint32_t l)
{
    lg_image_desc d = { .width = st->chain_size,
                        .height = st->chain_size,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = LG_IMAGE_CUBE,
                        .levels = st->chain_levels };
    return lg_probe_image_at(LG_PROBE_CUBE, &d, st->chain, l, rotation);
}

/* Why the chain of floats `f` (a cube of `size`, `levels` levels) cannot have been made from
 * the probe `pr` (into why), or false when it can. The checksum of the host's cache proves
 * only that an entry is whole (anyone who can write into the cache can recompute it), so a
 * chain read back is held to what lg_probe_prefilter_ggx can make: every texel of every
 * level is a weighted mean, with weights >= 0, of lookups (bilinear: means too) into the
 * probe resampled by area (means again), so each channel lies within the probe's own
 * [min, max] of that channel; a relative 1e-4 of the range covers the rounding. */
static bool ibl_chain_bad(lg_node *n, const ibl_frame *f, const float *chain, size_t nf,
                          uint32_t size, uint32_t levels, char *why, size_t wn)
{
    const lg_image_desc *rd = &f->probe->radiance_desc;
    lg_cpu_view pv;
    if (lg_map_cpu(n, f->probe->radiance, LG_READ, &pv) || !pv.pixels) {
        snprintf(why, wn, "the probe cannot be read to check it");
        return true;
    }
    size_t texels = (size_t)rd->width * rd->height * (rd->flags & LG_IMAGE_CUBE ? 6u : 1u);
    double lo[4] = { INFINITY, INFINITY, INFINITY, INFINITY };
    double hi[4] = { -INFINITY, -INFINITY, -INFINITY, -INFINITY };
    const float *px = pv.pixels;
    for (size_t i = 0; i < texels; i++)
        for (int c = 0; c < 4; c++) {
            lo[c] = fmin(lo[c], px[4 * i + c]);
            hi[c] = fmax(hi[c], px[4 * i + c]);
        }
    for (int c = 0; c < 4; c++) {
        double slack = 1e-4 * fmax(fabs(lo[c]), fabs(hi[c]));
        lo[c] -= slack;
        hi[c] += slack;
    }
    lg_image_desc cd = { .width = size, .height = size, .flags = LG_IMAGE_CUBE, .levels = levels };
    for (size_t i = 0; i < nf; i++) {
        int c = (int)(i % 4);
        double v = chain[i];
        if (isfinite(chain[i]) && v >= lo[c] && v <= hi[c])
            continue;
        size_t t = i / 4;
        uint32_t l = 0;
        while (l + 1 < levels && t >= lg_image_offset(&cd, l + 1, 0))
            l++;
        uint32_t w = lg_image_level_width(&cd, l);
        size_t r = t - lg_image_offset(&cd, l, 0);
        snprintf(why, wn,
                 "float %zu (level %u, face %zu, texel %zu, %zu, channel %c) = %g, "
                 "outside the probe's range [%g, %g] that a prefiltered chain keeps",
                 i, l, r / ((size_t)w * w), r % w, (r / w) % w, "RGBA"[c], v, lo[c], hi[c]);
        return true;
    }
    return false;
}

/* The chain's face size and levels from the parameters and the probe's radiance image
 * (a cube, or a 2D layout). prefilter_size 0: 128, halved while larger than the probe's
 * face (a cube's face; a 2D probe's width / 4, the face of a cube of the same texel
 * density at the equator), at least 8. A prefilter_size above what the probe can fill
 * (that face rounded up to a power of two, at least 8) is clamped to it: a finer chain
 * only interpolates the probe, at 6 size^2 (samples + 22) floats of work and memory (a
 * 1x1 probe at 4096 took 4.4 GiB and 78 s for nothing); levels beyond what the face
 * allows are clamped too. *note (note_len > 0) receives what was clamped, or "". */
static int ibl_chain_shape(lg_node *n, const ibl_state *st, const lg_image_desc *rd,
                           uint32_t *size_out, uint32_t *levels_out, char *note, size_t note_len)
{
    note[0] = 0;
    uint32_t src = (rd->flags & LG_IMAGE_CUBE) ? rd->width : rd->width / 4;
    uint32_t size = st->size_param;
    if (size == 0) {
        size = 128;
        while (size > 8 && size > src)
            size /= 2;
    } else {
        uint32_t fill = 8;
        while (fill < src && fill < 4096)
            fill *= 2;
        if (size > fill) {
            snprintf(note, note_len,
                     "prefilter_size = %u is finer than the %ux%u%s probe can "
                     "fill: the chain is made at %u per face (set "
                     "prefilter_size to %u or less, or 0, to silence this)",
                     size, rd->width, rd->height, (rd->flags & LG_IMAGE_CUBE) ? " cube" : "", fill,
                     fill);
            size = fill;
        }
    }
    uint32_t max_levels = 1;
    while ((size >> max_levels) > 0 && max_levels < LG_PROBE_FILTER_MAX_LEVELS)
        max_levels++;
    uint32_t levels = st->levels_param ? st->levels_param : 6;
    if (levels > max_levels) {
        if (st->levels_param) {
            size_t len = strlen(note);
            snprintf(note + len, note_len - len,
                     "%slevels = %u: a chain of face %u has %u "
                     "levels, so it has %u",
                     len ? "; " : "", levels, size, max_levels, max_levels);
        }
        levels = max_levels;
    }
    if (levels < 2)
        return lg_error(n,
                        "levels = %u: a GGX chain needs at least 2 levels (roughness 0 and 1); "
                        "prefilter_size %u allows %u",
                        levels, size, max_levels);
    *size_out = size;
    *levels_out = levels;
    return 0;
}

/* Bytes the making of a chain of face `size` and `levels` levels needs at its peak: the
 * chain, its copy for the cache, the box-filtered mips of level 0 (a third of it) and their
 * solid angles, the sample sets, and resampling the probe into level 0 (unless it is a
 * cube of that size already; lg_probe_resample_bytes). *resample receives the last. */
static uint64_t ibl_chain_bytes(const lg_image_desc *rd, uint32_t size, uint32_t levels,
                                uint32_t samples, uint64_t *resample)
{
    bool cube = (rd->flags & LG_IMAGE_CUBE) != 0;
    uint64_t level0 = 6ull * size * size;
    uint64_t src = (uint64_t)rd->width * rd->height * (cube ? 6 : 1);
    *resample = cube && rd->width == size ? 0 : lg_probe_resample_bytes(src, level0);
    double b = 2.0 * ibl_chain_floats(size, levels) * sizeof(float) +
               (double)level0 / 3 * 4 * sizeof(float) + (double)level0 * sizeof(float) +
               (double)levels * samples * 5 * sizeof(float) + (double)*resample;
    return b >= 1.8e19 ? UINT64_MAX : (uint64_t)b;
}

/* Whether the scene has a material that reads the chain (reflective, roughness > 0, glossy
 * = auto): ibl_materials' test. */
static bool ibl_scene_rough(const ibl_state *st, const lg_scene *s)
{
    if (st->mode == IBL_BACKGROUND || st->glossy != IBL_GLOSSY_AUTO || !s)
        return false;
    for (uint32_t i = 0; i < s->n_materials; i++) {
        const lg_material *m = &s->materials[i];
        bool reflects = false;
        for (int c = 0; c < 3; c++) {
            float r = st->reflectivity[0] >= 0 ? st->reflectivity[c] : m->reflectivity[c];
            reflects |= isfinite(r) && r > 0;
        }
        if (reflects && m->roughness > 0)
            return true;
    }
    return false;
}

/* In prepare: the chain this node will make, clamped with a note (a warning, shown at the
 * default verbosity) when its parameters ask for more than the probe can fill, and its
 * memory against what the machine can give, before anything runs. */
static void ibl_chain_key(char *key, size_t len, uint32_t size, uint32_t levels, uint32_t samples,
                          uint32_t weighting)
{
    /* the weighting is in the node's identity already (a parameter); naming it in the key
     * too keeps entries of the two apart should its default change */
    snprintf(key, len, "ggx-cube%u-l%u-s%u-w%u", size, levels, samples, weighting);
}

/* The chain from the host's cache into st->chain: true on a hit. An entry that does not fit
 * (ibl_chain_read: header, size, a value that is not finite) is said, and the chain is
 * prefiltered again and stored over it. */
static bool ibl_chain_from_cache(lg_node *n, ibl_state *st, uint32_t size, uint32_t levels,
                                 uint32_t samples)
{
    size_t nf = ibl_chain_floats(size, levels);
    char key[96];
    ibl_chain_key(key, sizeof key, size, levels, samples, st->weighting);
    void *data = NULL;
    size_t bytes = 0;
    if (lg_cache_get(n, key, &data, &bytes) != LG_OK)
        return false;
    /* header and size here; the values in execute, against the probe (ibl_chain_bad), which
     * names the first bad one */
    const char *why = ibl_chain_read_raw(data, bytes, size, levels, samples, nf, &st->chain);
    lg_cache_free(n, data);
    if (why)
        lg_log(n, LG_LOG_WARN, "cache entry '%s' not used (%s): prefiltering it again", key, why);
    if (!st->chain)
        return false;
    st->chain_unchecked = true;
    st->chain_size = size;
    st->chain_levels = levels;
    lg_log(n, LG_LOG_INFO,
           "GGX chain loaded from the cache (cube %u, %u levels, %u samples per texel)", size,
           levels, samples);
    return true;
}

/* The work estimate (lg_declare_work): the GGX chain's prefiltering, the only part that can
 * run long (the shading is one lookup per pixel). Seconds one thread takes, measured here
 * (2-core VM shared with compiles, LIGHTGRAPH_THREADS=1, examples/ibl.lgraph's 1024x512
 * probe into a 128 cube of 6 levels): the level-0 resampling (lg_probe_resample, area
 * weighted, on the calling thread) 14-18 s for 524288 + 98304 texels, about 3e-5 s per
 * texel; the filter 17 s more for 1024 samples a texel instead of 1, 5e-7 s per sample,
 * on the host's threads. */
#define IBL_SECONDS_PER_RESAMPLED_TEXEL 3e-5
#define IBL_SECONDS_PER_SAMPLE 5e-7

/* In prepare(), when execute will make a GGX chain: its shape (a prefilter_size or levels
 * the probe cannot justify is clamped, with a warning), its memory against the machine's,
 * then the cache (a hit is kept for execute) and the work a miss costs (lg_declare_work). */
static int ibl_check_chain(lg_node *n, ibl_state *st, const lg_resource *probe)
{
    const lg_resource *rad = lg_part(n, probe, "radiance");
    lg_resource_info ri;
    if (!rad || lg_describe(rad, &ri, n) != 0 || !ri.image.width || !ri.image.height)
        return 0; /* a gated or empty probe: execute says so */
    if (!ibl_scene_rough(st, lg_scene_get(n, lg_input(n, IN_SCENE))))
        return 0;
    uint32_t size, levels;
    char note[512];
    int rc = ibl_chain_shape(n, st, &ri.image, &size, &levels, note, sizeof note);
    if (rc)
        return rc;
    if (note[0])
        lg_log(n, LG_LOG_WARN, "%s", note);
    uint32_t samples = st->samples ? st->samples : 256;
    uint64_t resample, need = ibl_chain_bytes(&ri.image, size, levels, samples, &resample);
    const char *bound;
    uint64_t avail = lg_memory_available(&bound);
    if (need <= avail) {
        st->cache_probed = true;
        if (st->chain || ibl_chain_from_cache(n, st, size, levels, samples)) {
            lg_declare_work(n, 0, 0, "GGX prefilter samples (the chain is in the cache)");
            return 0;
        }
        double texels = 0;
        for (uint32_t l = 1; l < levels; l++) {
            double side = size >> l ? size >> l : 1;
            texels += 6 * side * side;
        }
        double src = (double)ri.image.width * ri.image.height *
                     ((ri.image.flags & LG_IMAGE_CUBE) ? 6 : 1);
        double secs = (src + 6.0 * size * size) * IBL_SECONDS_PER_RESAMPLED_TEXEL +
                      texels * samples * IBL_SECONDS_PER_SAMPLE / lg_cpu_workers(n);
        lg_declare_work(n, texels * samples, secs, "GGX prefilter samples");
        return 0;
    }
    char need_s[32], have_s[32], rs_s[32];
    lg_bytes_text(need_s, sizeof need_s, need);
    lg_bytes_text(have_s, sizeof have_s, avail);
    lg_bytes_text(rs_s, sizeof rs_s, resample);
    return lg_error_code(n, LG_ERR_NOMEM,
                         "the GGX chain (prefilter_size = %u: cube %u, %u levels, "
                         "prefilter_samples = %u) from the %ux%u%s probe needs %s (%llu bytes; "
                         "resampling the probe into its first level %s), more than the %s "
                         "(%llu bytes) of %s; use a smaller probe (probe_convert), a smaller "
                         "prefilter_size, or glossy = off",
                         st->size_param, size, levels, samples, ri.image.width, ri.image.height,
                         (ri.image.flags & LG_IMAGE_CUBE) ? " cube" : "", need_s,
                         (unsigned long long)need, rs_s, have_s, (unsigned long long)avail, bound);
}

/* Makes the chain once: from the host's cache, else lg_probe_prefilter_ggx (then cached).
 * The cache key is scoped by the node's identity, which includes the probe's content and
 * this node's parameters. */
static int ibl_chain(lg_node *n, ibl_state *st, const ibl_frame *f)
{
    if (st->chain && !st->chain_unchecked)
        return 0;
    if (!st->chain && st->chain_tried)
        return LG_ERR_INVALID;
    st->chain_tried = true;
    const lg_image_desc *rd = &f->probe->radiance_desc;
    uint32_t size, levels;
    char note[512]; /* said in prepare already */
    int rc = ibl_chain_shape(n, st, rd, &size, &levels, note, sizeof note);
    if (rc)
        return rc;
    uint32_t samples = st->samples ? st->samples : 256;
    size_t nf = ibl_chain_floats(size, levels);
    char key[96];
    ibl_chain_key(key, sizeof key, size, levels, samples, st->weighting);
    /* prepare() looked already (ibl_check_chain): a hit is in st->chain */
    if (!st->chain && !st->cache_probed)
        ibl_chain_from_cache(n, st, size, levels, samples);
    if (st->chain) {
        /* a chain from the cache, held to what prefiltering this probe can make before any
         * lookup: a bad one is said once (naming the value), removed and made again */
        st->chain_unchecked = false;
        char bad[256];
        if (!ibl_chain_bad(n, f, st->chain, nf, size, levels, bad, sizeof bad))
            return 0;
        lg_cache_reject(n, key, bad);
        free(st->chain);
        st->chain = NULL;
    }

    lg_cpu_view pv;
    rc = lg_map_cpu(n, f->probe->radiance, LG_READ, &pv);
    if (rc)
        return rc;
    /* rotation NULL: the chain stays in the probe's frame (ggx_prefilter.h, "Frames") */
    lg_probe_image src = lg_probe_image_at(f->probe->info.layout, rd, pv.pixels, 0, NULL);
    st->chain = malloc(nf * sizeof(float));
    if (!st->chain)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (GGX chain, %zu floats: %zu bytes)",
                             nf, nf * sizeof(float));
    lg_probe_prefilter_opts o = { .samples = samples, .weighting = st->weighting };
    lg_probe_prefilter_stats ps;
    rc = lg_probe_prefilter_ggx(n, &src, LG_PROBE_CUBE, size, size, levels, &o, st->chain, &ps);
    if (rc) {
        free(st->chain);
        st->chain = NULL;
        /* the prefilter reports nothing itself: say why, and how much it was after */
        char why[256] = "";
        if (rc == LG_ERR_NOMEM) {
            uint64_t resample, need = ibl_chain_bytes(rd, size, levels, samples, &resample);
            char a[32], b[32];
            lg_bytes_text(a, sizeof a, need);
            lg_bytes_text(b, sizeof b, resample);
            snprintf(why, sizeof why,
                     ": out of memory (it needs about %s, %s of it to "
                     "resample the %ux%u probe into the chain's first level)",
                     a, b, rd->width, rd->height);
        }
        return lg_error_code(n, rc,
                             "prefiltering the probe (cube %u, %u levels, %u samples) "
                             "failed%s",
                             size, levels, samples, why);
    }
    st->chain_size = size;
    st->chain_levels = levels;
    /* a failed store is only a lost speed-up; the log line says which it was, never
     * "cached" when nothing was stored */
    const char *stored = "not cached: no memory for the cache entry";
    size_t total = 0;
    char *blob = ibl_chain_encode(size, levels, samples, nf, st->chain, &total);
    if (blob) {
        int r = lg_cache_store(n, key, blob, total);
        free(blob);
        stored = r == LG_CACHE_STORED    ? "cached"
                 : r == LG_CACHE_OFF     ? "not cached: the cache is disabled for this render "
                                           "(the warning above says why)"
                 : r == LG_CACHE_UNKNOWN ? "handed to the cache (this host does not say whether "
                                           "it stored it)"
                                         : "not cached: the host could not store it (its "
                                           "message above says why)";
    }
    lg_log(n, LG_LOG_INFO,
           "GGX chain prefiltered in %.3f s (cube %u, %u levels, %u samples per texel, %u "
           "threads); %s",
           ps.seconds, size, levels, samples, ps.threads, stored);
    return 0;
}

/* ---- GL: the G-buffer ------------------------------------------------------------------------ */

typedef struct ibl_draw_ctx {
    ibl_state *st;
    const lg_scene *s;
} ibl_draw_ctx;

static int ibl_on_mesh(lg_node *n, void *user, uint32_t mi, GLuint *normals)
{
    (void)n;
    (void)normals;
    const ibl_draw_ctx *c = user;
    lg_gl_set_float(c->st->gpass, c->st->g_material, (float)c->s->meshes[mi].material + 1.0f);
    return 0;
}

/* The G-buffer at the output's size: made on the first frame, then kept (sampled nearest,
 * as lg_gl_texture makes them). */
static int ibl_gbuffer_images(lg_node *n, ibl_state *st)
{
    const lg_gl_texture_desc c = {
        .target = GL_TEXTURE_2D, .format = GL_RGBA32F, .width = st->width, .height = st->height
    };
    const lg_gl_texture_desc d = { .target = GL_TEXTURE_2D,
                                   .format = GL_DEPTH_COMPONENT32F,
                                   .width = st->width,
                                   .height = st->height };
    int rc;
    if ((rc = lg_gl_texture_recreate(n, &st->gbuf_tex, &c)) < 0 ||
        (rc = lg_gl_texture_recreate(n, &st->gdepth_tex, &d)) < 0)
        return rc;
    return 0;
}

/* Rasterises the scene into the G-buffer (cleared to no geometry, depth 1). */
static int ibl_gbuffer(lg_node *n, ibl_state *st, const lg_gl *gl, const ibl_frame *f)
{
    int rc;
    if (!st->gpass) {
        static const lg_gl_shader_src src[2] = {
            { GL_VERTEX_SHADER, lg_src_ibl_gbuffer_vert_file, lg_src_ibl_gbuffer_vert },
            { GL_FRAGMENT_SHADER, lg_src_ibl_gbuffer_frag_file, lg_src_ibl_gbuffer_frag },
        };
        lg_gl_pass_desc d = { .name = "ibl (G-buffer)",
                              .stages = src,
                              .n_stages = 2,
                              .colors = { GL_RGBA32F },
                              .depth = true,
                              .depth_test = true,
                              .depth_write = true,
                              .cull = LG_GL_CULL_BACK,
                              .scene = LG_GL_SCENE_POSITIONS | LG_GL_SCENE_NORMALS };
        if ((rc = lg_gl_pass_create(n, &d, &st->gpass)))
            return rc;
        st->g_view_proj = lg_gl_pass_uniform(st->gpass, "u_view_proj");
        st->g_material = lg_gl_pass_uniform(st->gpass, "u_material");
    }
    if ((rc = ibl_gbuffer_images(n, st)))
        return rc;
    lg_gl_target t = { .color = { st->gbuf_tex.name },
                       .depth = st->gdepth_tex.name,
                       .width = st->width,
                       .height = st->height };
    lg_gl_pass_set_time(st->gpass, f->time); /* an animated scene's pose */
    if ((rc = lg_gl_pass_begin(st->gpass, &t)))
        return rc;
    static const float zero[4] = { 0, 0, 0, 0 };
    lg_gl_pass_clear_color(st->gpass, 0, zero);
    lg_gl_pass_clear_depth(st->gpass, 1.0f);
    lg_gl_set_mat4(st->gpass, st->g_view_proj, f->v.view_proj);
    ibl_draw_ctx ctx = { st, f->s };
    lg_gl_scene_draw d = { .on_mesh = ibl_on_mesh, .user = &ctx };
    return lg_gl_pass_end(st->gpass, lg_gl_pass_draw_scene(st->gpass, f->scene_res, &d));
}

/* The G-buffer in host memory (cpu and cl backends); NULL arrays when there is no
 * geometry (the shading then sees none). */
static int ibl_gbuffer_cpu(lg_node *n, ibl_state *st, const ibl_frame *f)
{
    if (!f->geometry)
        return 0;
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc = ibl_gbuffer(n, st, gl, f);
    if (rc)
        return rc;
    size_t np = (size_t)st->width * st->height;
    if (!st->gbuf) {
        st->gbuf = malloc(np * 4 * sizeof(float));
        st->gdepth = malloc(np * sizeof(float));
        if (!st->gbuf || !st->gdepth)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (G-buffer %ux%u)", st->width,
                                 st->height);
    }
    gl->GetTextureImage(st->gbuf_tex.name, 0, GL_RGBA, GL_FLOAT, (GLsizei)(np * 16), st->gbuf);
    gl->GetTextureImage(st->gdepth_tex.name, 0, GL_DEPTH_COMPONENT, GL_FLOAT, (GLsizei)(np * 4),
                        st->gdepth);
    return lg_gl_check(n, "ibl: reading the G-buffer back");
}

/* ---- GL shading ------------------------------------------------------------------------------ */

/* The shading pass's uniform block IblShade (std140, shaders/ibl/ibl_shade.frag), uploaded
 * with one lg_gl_pass_uniforms per frame. */
typedef struct ibl_gpu_shade {
    float inv_view_proj[16];
    float rotation[3][4]; /* mat3: three columns of vec4 stride */
    int32_t size[2];
    int32_t mode, layout, bilinear, fresnel, has_base, has_base_depth, format, chain_levels,
        dfg_size;
    int32_t pad_;
} ibl_gpu_shade;

LG_GL_BLOCK_SIZE(ibl_gpu_shade, 160);
LG_GL_BLOCK_OFFSET(ibl_gpu_shade, rotation, 64);
LG_GL_BLOCK_OFFSET(ibl_gpu_shade, size, 112);
LG_GL_BLOCK_OFFSET(ibl_gpu_shade, mode, 120);
LG_GL_BLOCK_OFFSET(ibl_gpu_shade, has_base_depth, 140);
LG_GL_BLOCK_OFFSET(ibl_gpu_shade, dfg_size, 152);

static int ibl_gl_shade_pass(lg_node *n, ibl_state *st, const lg_gl *gl)
{
    if (st->spass)
        return 0;
    static const lg_gl_shader_src src[2] = {
        { GL_VERTEX_SHADER, lg_src_ibl_fullscreen_vert_file, lg_src_ibl_fullscreen_vert },
        { GL_FRAGMENT_SHADER, lg_src_ibl_shade_frag_file, lg_src_ibl_shade_frag },
    };
    static const GLenum internal[3] = { GL_RGBA32F, GL_RGBA16F, GL_RGBA8 };
    /* every pixel is written, depth included: no test against the cleared plane */
    lg_gl_pass_desc d = { .name = "ibl (shading)",
                          .stages = src,
                          .n_stages = 2,
                          .output = "out",
                          .colors = { internal[st->format] },
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true,
                          .depth_func = GL_ALWAYS };
    int rc = lg_gl_pass_create(n, &d, &st->spass);
    if (rc)
        return rc;
    lg_gl_pass *p = st->spass;
    st->s_params = lg_gl_pass_uniform_block(p, "IblShade");
    st->s_gbuf = lg_gl_pass_texture(p, "u_gbuf");
    st->s_gdepth = lg_gl_pass_texture(p, "u_gdepth");
    st->s_base = lg_gl_pass_texture(p, "u_base");
    st->s_base_depth = lg_gl_pass_texture(p, "u_base_depth");
    st->s_probe2d = lg_gl_pass_texture(p, "u_probe2d");
    st->s_probecube = lg_gl_pass_texture(p, "u_probecube");
    st->s_mats = lg_gl_pass_storage(p, "Materials");
    st->s_clamped = lg_gl_pass_storage(p, "Clamped");
    st->s_chain = lg_gl_pass_texture(p, "u_chain");
    st->s_dfg = lg_gl_pass_storage(p, "Dfg");
    return lg_gl_check(n, "ibl: making the shading pass");
}

static int ibl_exec_gl(lg_node *n, ibl_state *st, const ibl_frame *f, uint64_t *clamped)
{
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    int rc;
    if ((rc = ibl_gbuffer_images(n, st)))
        return rc;
    if (f->geometry) {
        if ((rc = ibl_gbuffer(n, st, gl, f)))
            return rc;
    } else {
        /* no triangles: an empty G-buffer */
        static const float zero[4] = { 0, 0, 0, 0 };
        const float one = 1.0f;
        gl->ClearTexImage(st->gbuf_tex.name, 0, GL_RGBA, GL_FLOAT, zero);
        gl->ClearTexImage(st->gdepth_tex.name, 0, GL_DEPTH_COMPONENT, GL_FLOAT, &one);
    }
    if ((rc = ibl_gl_shade_pass(n, st, gl)))
        return rc;
    GLuint probe_tex = 0, pd = 0, base_tex = 0, base_depth = 0;
    const lg_probe *pr = f->probe;
    if ((rc = lg_map_gl(n, pr->radiance, LG_READ, &probe_tex, &pd)))
        return rc;
    if (f->base && (rc = lg_map_gl(n, f->base, LG_READ, &base_tex, &base_depth)))
        return rc;
    const uint32_t zero_u = 0;
    if ((rc = lg_gl_buffer_recreate(n, &st->mats_buf, (size_t)f->n_mats * 8 * sizeof(float), 0,
                                    f->mats)) ||
        (rc = lg_gl_buffer_recreate(n, &st->clamp_buf, sizeof zero_u, 0, &zero_u)))
        return rc;
    if (!st->dfg_buf.name &&
        (rc = lg_gl_buffer_recreate(n, &st->dfg_buf,
                                    2 * LG_GGX_DFG_SIZE * LG_GGX_DFG_SIZE * sizeof(float), 0,
                                    lg_ggx_dfg_shared())))
        return rc;
    /* the chain as a cube texture with one mip level per roughness level, filled when made */
    const lg_gl_texture_desc chain_desc = { .target = GL_TEXTURE_CUBE_MAP,
                                            .format = GL_RGBA32F,
                                            .width = st->chain_size,
                                            .height = st->chain_size,
                                            .levels = st->chain_levels };
    if (st->chain && (rc = lg_gl_texture_recreate(n, &st->chain_tex, &chain_desc)) < 0)
        return rc;
    if (st->chain && rc == 1) {
        lg_image_desc cd = { .width = st->chain_size,
                             .height = st->chain_size,
                             .flags = LG_IMAGE_CUBE,
                             .levels = st->chain_levels };
        for (uint32_t l = 0; l < st->chain_levels; l++) {
            GLsizei w = (GLsizei)lg_image_level_width(&cd, l);
            gl->TextureSubImage3D(st->chain_tex.name, (GLint)l, 0, 0, 0, w, w, 6, GL_RGBA, GL_FLOAT,
                                  st->chain + 4 * lg_image_offset(&cd, l, 0));
        }
    }

    lg_gl_pass *p = st->spass;
    if ((rc = lg_gl_pass_begin(p, NULL)))
        return rc;
    ibl_gpu_shade u = {
        .size = { (int32_t)st->width, (int32_t)st->height },
        .mode = st->mode,
        .layout = (int32_t)pr->info.layout,
        .bilinear = st->sampling == IBL_BILINEAR,
        .fresnel = st->fresnel == IBL_FRESNEL_SCHLICK,
        .has_base = base_tex != 0,
        .has_base_depth = base_depth != 0,
        .format = st->format,
        .chain_levels = st->chain_tex.name ? (int32_t)st->chain_levels : 0,
        .dfg_size = (int32_t)LG_GGX_DFG_SIZE,
    };
    memcpy(u.inv_view_proj, f->inv_vp, sizeof u.inv_view_proj);
    for (int c = 0; c < 3; c++)
        memcpy(u.rotation[c], &pr->info.rotation[3 * c], 3 * sizeof(float));
    if ((rc = lg_gl_pass_uniforms(p, st->s_params, &u, sizeof u)))
        return lg_gl_pass_end(p, rc);
    lg_gl_pass_bind_texture(p, st->s_gbuf, st->gbuf_tex.name);
    lg_gl_pass_bind_texture(p, st->s_gdepth, st->gdepth_tex.name);
    lg_gl_pass_bind_texture(p, st->s_base, base_tex);
    lg_gl_pass_bind_texture(p, st->s_base_depth, base_depth);
    /* the probe's filter: GL's seamless bilinear (the CPU's rule) or nearest; the chain's
     * trilinear, seamless too */
    bool cube = pr->info.layout == LG_PROBE_CUBE;
    const lg_gl_sampler probe_s = { .filter = st->sampling == IBL_BILINEAR ? LG_GL_FILTER_LINEAR
                                                                           : LG_GL_FILTER_NEAREST,
                                    .seamless_cube = cube };
    const lg_gl_sampler chain_s = { .filter = LG_GL_FILTER_LINEAR_MIPMAP, .seamless_cube = true };
    lg_gl_pass_bind_texture_sampled(p, cube ? st->s_probecube : st->s_probe2d, probe_tex, &probe_s);
    lg_gl_pass_bind_buffer(p, st->s_mats, st->mats_buf.name);
    lg_gl_pass_bind_buffer(p, st->s_clamped, st->clamp_buf.name);
    lg_gl_pass_bind_buffer(p, st->s_dfg, st->dfg_buf.name);
    if (st->chain_tex.name)
        lg_gl_pass_bind_texture_sampled(p, st->s_chain, st->chain_tex.name, &chain_s);
    rc = lg_gl_pass_draw(p, GL_TRIANGLES, 3);
    if ((rc = lg_gl_pass_end(p, rc)))
        return rc;
    if (st->format == IBL_RGBA16F) {
        uint32_t c = 0;
        gl->MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        gl->GetNamedBufferSubData(st->clamp_buf.name, 0, sizeof c, &c);
        *clamped = c;
    }
    return lg_gl_check(n, "ibl: shading");
}

/* ---- CPU shading (the C twin of ibl_shade.frag and ibl.cl) ----------------------------------- */

typedef struct ibl_cpu_job {
    const ibl_state *st;
    const ibl_frame *f;
    lg_probe_image img;
    lg_probe_image chain[LG_PROBE_FILTER_MAX_LEVELS];
    uint32_t chain_levels; /* 0: no chain */
    const float *gbuf, *gdepth, *base, *base_depth;
    void *out;
    float *out_depth;
    uint64_t *clamped; /* per chunk */
} ibl_cpu_job;

static lg_vec3 ibl_unproject(const float m[16], float x, float y, float z)
{
    float v[4];
    for (int r = 0; r < 4; r++)
        v[r] = m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r];
    return lg_v3(v[0] / v[3], v[1] / v[3], v[2] / v[3]);
}

static bool ibl_nonfinite(float x)
{
    return !isfinite(x);
}

static lg_vec3 ibl_normal(lg_vec3 n, lg_vec3 V, bool double_sided)
{
    float m = fmaxf(fabsf(n.x), fmaxf(fabsf(n.y), fabsf(n.z)));
    if (!(m > 1e-30f) || ibl_nonfinite(m))
        return lg_v3_scale(V, -1.0f);
    lg_vec3 N = lg_v3_scale(n, 1.0f / m);
    N = lg_v3_scale(N, 1.0f / lg_v3_length(N));
    float d = lg_v3_dot(N, V);
    if (d > 0.0f) {
        if (double_sided)
            return lg_v3_scale(N, -1.0f);
        lg_vec3 t = lg_v3_sub(N, lg_v3_scale(V, d));
        float l = lg_v3_length(t);
        return l > 1e-6f ? lg_v3_scale(t, 1.0f / l) : lg_v3_scale(V, -1.0f);
    }
    return N;
}

static float ibl_clean(float x)
{
    return isnan(x) ? 0.0f : x;
}

/* The radiance along dir for a perceptual roughness (as ibl_radiance in ibl_shade.frag):
 * the probe itself at 0; lg_probe_lookup_rough in the chain from lod 1 on; below lod 1 the
 * probe blended with level 1, so that roughness 0+ continues roughness 0. */
static void ibl_radiance(const ibl_cpu_job *j, lg_vec3 dir, float rough, float out[4])
{
    lg_probe_sampling smp = j->st->sampling == IBL_BILINEAR ? LG_PROBE_BILINEAR : LG_PROBE_NEAREST;
    if (!(rough > 0.0f) || j->chain_levels < 2) {
        lg_probe_lookup(&j->img, dir, smp, out);
        return;
    }
    float lod = lg_probe_roughness_lod(rough, j->chain_levels);
    if (lod < 1.0f) {
        float a[4], b[4];
        lg_probe_lookup(&j->img, dir, smp, a);
        lg_probe_lookup(&j->chain[1], dir, LG_PROBE_BILINEAR, b);
        for (int c = 0; c < 4; c++)
            out[c] = a[c] + (b[c] - a[c]) * lod;
        return;
    }
    lg_probe_lookup_rough(j->chain, j->chain_levels, dir, rough, out);
}

/* One pixel: colour (RGBA, NaN-free, before the format's encoding) and depth. */
static void ibl_shade_pixel(const ibl_cpu_job *j, uint32_t x, uint32_t y, float c[4], float *depth)
{
    const ibl_state *st = j->st;
    const ibl_frame *f = j->f;
    size_t i = (size_t)y * st->width + x;
    float nx = ((float)x + 0.5f) / (float)st->width * 2.0f - 1.0f;
    float ny = ((float)y + 0.5f) / (float)st->height * 2.0f - 1.0f;
    lg_vec3 a = ibl_unproject(f->inv_vp, nx, ny, -1.0f), b = ibl_unproject(f->inv_vp, nx, ny, 1.0f);
    lg_vec3 V = lg_probe_safe_dir(lg_v3_sub(b, a));
    const float zero4[4] = { 0, 0, 0, 0 }, base0[4] = { 0, 0, 0, 1 };
    const float *g = j->gbuf ? j->gbuf + 4 * i : zero4;
    float gd = j->gdepth ? j->gdepth[i] : 1.0f;
    const float *bc = j->base ? j->base + 4 * i : base0;
    float bd = j->base_depth ? j->base_depth[i] : 1.0f;
    int mat = (int)(g[3] + 0.5f) - 1;
    float look[4];
    if (st->mode == IBL_BACKGROUND) {
        bool covered = gd < 1.0f || bd < 1.0f;
        if (covered) {
            memcpy(c, bc, 4 * sizeof(float));
        } else {
            lg_probe_lookup(&j->img, V,
                            st->sampling == IBL_BILINEAR ? LG_PROBE_BILINEAR : LG_PROBE_NEAREST,
                            look);
            c[0] = look[0], c[1] = look[1], c[2] = look[2], c[3] = 1.0f;
        }
        *depth = fminf(gd, bd);
    } else if (mat < 0 || (uint32_t)mat >= f->n_mats) {
        memcpy(c, bc, 4 * sizeof(float));
        *depth = bd;
    } else {
        const float *m = f->mats + 8 * (size_t)mat;
        lg_vec3 N = ibl_normal(lg_v3(g[0], g[1], g[2]), V, m[4] != 0.0f);
        float ndv = lg_v3_dot(N, V);
        float cosv = fminf(fmaxf(-ndv, 0.0f), 1.0f);
        lg_vec3 L = st->mode == IBL_REFLECT ? lg_v3_sub(V, lg_v3_scale(N, 2.0f * ndv)) : N;
        float rough = j->chain_levels >= 2 ? m[3] : 0.0f;
        float F[3] = { m[0], m[1], m[2] };
        if (st->fresnel == IBL_FRESNEL_SCHLICK) {
            if (rough > 0.0f) {
                float ab[2];
                lg_ggx_dfg(cosv, rough, ab);
                for (int ch = 0; ch < 3; ch++)
                    F[ch] = F[ch] * ab[0] + ab[1];
            } else {
                float k = 1.0f - cosv, k2 = k * k;
                for (int ch = 0; ch < 3; ch++)
                    F[ch] = F[ch] + (1.0f - F[ch]) * (k2 * k2 * k);
            }
        }
        ibl_radiance(j, L, rough, look);
        for (int ch = 0; ch < 3; ch++)
            c[ch] = bc[ch] + F[ch] * look[ch];
        c[3] = bc[3];
        *depth = gd;
    }
    for (int ch = 0; ch < 4; ch++)
        c[ch] = ibl_clean(c[ch]);
}

static void ibl_cpu_rows(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    ibl_cpu_job *j = ctx;
    const ibl_state *st = j->st;
    uint64_t clamped = 0;
    for (size_t y = begin; y < end; y++)
        for (uint32_t x = 0; x < st->width; x++) {
            float c[4], d;
            ibl_shade_pixel(j, x, (uint32_t)y, c, &d);
            size_t i = y * st->width + x;
            j->out_depth[i] = d;
            if (st->format == IBL_RGBA16F) {
                uint16_t *o = (uint16_t *)j->out + 4 * i;
                if (c[0] > 65504.0f || c[1] > 65504.0f || c[2] > 65504.0f)
                    clamped++;
                for (int ch = 0; ch < 4; ch++)
                    o[ch] = lg_half_from_float(c[ch] < 65504.0f ? c[ch] : 65504.0f);
            } else if (st->format == IBL_RGBE8) {
                lg_rgbe_encode(c, (uint8_t *)j->out + 4 * i);
            } else {
                memcpy((float *)j->out + 4 * i, c, sizeof c);
            }
        }
    j->clamped[chunk] = clamped;
}

static int ibl_exec_cpu(lg_node *n, ibl_state *st, const ibl_frame *f, uint64_t *clamped)
{
    int rc = ibl_gbuffer_cpu(n, st, f);
    if (rc)
        return rc;
    lg_cpu_view pv, bv = { 0 }, ov;
    if ((rc = lg_map_cpu(n, f->probe->radiance, LG_READ, &pv)))
        return rc;
    if (f->base && (rc = lg_map_cpu(n, f->base, LG_READ, &bv)))
        return rc;
    if ((rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov)))
        return rc;
    if (!ov.depth)
        return lg_error(n, "output 'out' has no depth plane");
    ibl_cpu_job j = { .st = st,
                      .f = f,
                      .gbuf = f->geometry ? st->gbuf : NULL,
                      .gdepth = f->geometry ? st->gdepth : NULL,
                      .base = bv.pixels,
                      .base_depth = bv.depth,
                      .out = ov.pixels,
                      .out_depth = ov.depth };
    j.img = lg_probe_image_at(f->probe->info.layout, &f->probe->radiance_desc, pv.pixels, 0,
                              f->probe->info.rotation);
    if (st->chain) {
        j.chain_levels = st->chain_levels;
        for (uint32_t l = 0; l < st->chain_levels; l++)
            j.chain[l] = ibl_chain_level(st, f->probe->info.rotation, l);
    }
    size_t grain = 8;
    size_t chunks = lg_parallel_chunks(st->height, grain);
    j.clamped = calloc(chunks ? chunks : 1, sizeof *j.clamped);
    if (!j.clamped)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    rc = lg_parallel_for(n, st->height, grain, ibl_cpu_rows, &j);
    for (size_t c = 0; c < chunks; c++)
        *clamped += j.clamped[c];
    free(j.clamped);
    return rc;
}

/* ---- CL shading ------------------------------------------------------------------------------ */

/* A read-only table of the kernel's, kept while large enough and rewritten. */
static int ibl_cl_upload(lg_node *n, lg_cl_buffer *b, size_t bytes, const void *data)
{
    int rc = lg_cl_buffer_recreate(n, b, bytes, CL_MEM_READ_ONLY);
    return rc ? rc : lg_cl_buffer_write(n, b, 0, bytes, data);
}

static int ibl_exec_cl(lg_node *n, ibl_state *st, const ibl_frame *f, uint64_t *clamped)
{
    int rc = ibl_gbuffer_cpu(n, st, f);
    if (rc)
        return rc;
    if (!st->kernel) {
        static const char *const src[] = { lg_src_probe_cl, lg_src_rgbe_cl, lg_src_ibl_cl };
        static const char *const names[] = { lg_src_probe_cl_file, lg_src_rgbe_cl_file,
                                             lg_src_ibl_cl_file };
        lg_cl_pass_desc d = { .name = "ibl shade",
                              .sources = src,
                              .source_names = names,
                              .n_sources = 3,
                              .options = "-cl-std=CL1.2",
                              .kernel = "ibl_shade" };
        if ((rc = lg_cl_pass_create(n, &d, &st->kernel)))
            return rc;
    }
    if (!st->cl_dfg.mem &&
        (rc = ibl_cl_upload(n, &st->cl_dfg, 2 * LG_GGX_DFG_SIZE * LG_GGX_DFG_SIZE * sizeof(float),
                            lg_ggx_dfg_shared())))
        return rc;
    if (st->chain && !st->cl_chain.mem &&
        (rc = ibl_cl_upload(n, &st->cl_chain,
                            ibl_chain_floats(st->chain_size, st->chain_levels) * sizeof(float),
                            st->chain)))
        return rc;
    size_t np = (size_t)st->width * st->height;
    if (f->geometry && ((rc = ibl_cl_upload(n, &st->cl_gbuf, np * 16, st->gbuf)) ||
                        (rc = ibl_cl_upload(n, &st->cl_gdepth, np * 4, st->gdepth))))
        return rc;
    if ((rc = ibl_cl_upload(n, &st->cl_mats, (size_t)f->n_mats * 32, f->mats)))
        return rc;
    /* the depth planes too: mapped here rather than by lg_cl_pass_arg_resource */
    void *probe = NULL, *pd = NULL, *base = NULL, *base_depth = NULL, *out = NULL,
         *out_depth = NULL;
    if ((rc = lg_map_cl(n, f->probe->radiance, LG_READ, &probe, &pd)))
        return rc;
    if (f->base && (rc = lg_map_cl(n, f->base, LG_READ, &base, &base_depth)))
        return rc;
    if ((rc = lg_map_cl(n, lg_output(n, 0), LG_WRITE, &out, &out_depth)))
        return rc;
    const uint32_t zero = 0;
    if ((rc = lg_cl_buffer_recreate(n, &st->cl_clamped, sizeof zero, 0)) ||
        (rc = lg_cl_buffer_write(n, &st->cl_clamped, 0, sizeof zero, &zero)))
        return rc;
    cl_float16 ivp;
    memcpy(ivp.s, f->inv_vp, sizeof ivp.s);
    const float *r = f->probe->info.rotation;
    const float r0[4] = { r[0], r[1], r[2], 0 }, r1[4] = { r[3], r[4], r[5], 0 },
                r2[4] = { r[6], r[7], r[8], 0 };
    lg_cl_pass *k = st->kernel;
    unsigned a = 0;
    lg_cl_pass_arg_int(k, a++, st->mode);
    lg_cl_pass_arg_int(k, a++, (int32_t)st->width);
    lg_cl_pass_arg_int(k, a++, (int32_t)st->height);
    lg_cl_pass_arg(k, a++, sizeof ivp, &ivp);
    lg_cl_pass_arg_mem(k, a++, f->geometry ? st->cl_gbuf.mem : NULL);
    lg_cl_pass_arg_mem(k, a++, f->geometry ? st->cl_gdepth.mem : NULL);
    lg_cl_pass_arg_int(k, a++, base != NULL);
    lg_cl_pass_arg_mem(k, a++, base);
    lg_cl_pass_arg_int(k, a++, base_depth != NULL);
    lg_cl_pass_arg_mem(k, a++, base_depth);
    lg_cl_pass_arg_mem(k, a++, st->cl_mats.mem);
    lg_cl_pass_arg_mem(k, a++, probe);
    lg_cl_pass_arg_int(k, a++, (int32_t)f->probe->info.layout);
    lg_cl_pass_arg_int(k, a++, (int32_t)f->probe->radiance_desc.width);
    lg_cl_pass_arg_int(k, a++, (int32_t)f->probe->radiance_desc.height);
    lg_cl_pass_arg_int(k, a++, st->sampling == IBL_BILINEAR);
    lg_cl_pass_arg_float4(k, a++, r0);
    lg_cl_pass_arg_float4(k, a++, r1);
    lg_cl_pass_arg_float4(k, a++, r2);
    lg_cl_pass_arg_int(k, a++, st->fresnel == IBL_FRESNEL_SCHLICK);
    lg_cl_pass_arg_int(k, a++, st->format);
    lg_cl_pass_arg_mem(k, a++, out);
    lg_cl_pass_arg_mem(k, a++, out_depth);
    lg_cl_pass_arg_mem(k, a++, st->cl_clamped.mem);
    lg_cl_pass_arg_mem(k, a++, st->cl_chain.mem);
    lg_cl_pass_arg_int(k, a++, (int32_t)st->chain_size);
    lg_cl_pass_arg_int(k, a++, st->cl_chain.mem ? (int32_t)st->chain_levels : 0);
    lg_cl_pass_arg_mem(k, a++, st->cl_dfg.mem);
    lg_cl_pass_arg_int(k, a++, (int32_t)LG_GGX_DFG_SIZE);
    size_t global[2] = { st->width, st->height };
    if ((rc = lg_cl_pass_run(k, 2, global, NULL)))
        return rc;
    uint32_t c = 0;
    if ((rc = lg_cl_buffer_read(n, &st->cl_clamped, 0, sizeof c, &c)))
        return rc;
    *clamped = c;
    return 0;
}

/* ---- execute / destroy ----------------------------------------------------------------------- */

static int ibl_execute(lg_node *n, const lg_frame *frame)
{
    ibl_state *st = n->user;
    ibl_frame f;
    int rc = ibl_frame_in(n, st, &f);
    f.time = frame->time;
    uint64_t clamped = 0;
    /* base passes into the output (added to, or drawn over): its NaN and Inf are said once,
     * as `image` says a file's; step 7 of the README writes NaN as 0 */
    if (!rc && f.base)
        rc = lg_check_input_finite(n, frame, IN_BASE, "base", "NaN written as 0, Inf passed on",
                                   &st->reported_nonfinite);
    if (!rc && f.rough)
        rc = ibl_chain(n, st, &f);
    if (!rc) {
        if (st->backend == LG_DEVICE_GL)
            rc = ibl_exec_gl(n, st, &f, &clamped);
        else if (st->backend == LG_DEVICE_CL)
            rc = ibl_exec_cl(n, st, &f, &clamped);
        else
            rc = ibl_exec_cpu(n, st, &f, &clamped);
    }
    if (!rc && clamped && !st->warned_clamp) {
        st->warned_clamp = true;
        lg_log(n, LG_LOG_WARN,
               "format rgba16f: %" PRIu64 " pixel%s above 65504 (the largest half) clamped to "
               "65504 (reported once)",
               clamped, clamped == 1 ? "" : "s");
    }
    if (!rc) {
        const lg_probe_info *pi = &f.probe->info;
        lg_log(n, LG_LOG_INFO, "%s probe %ux%u%s, camera %u, %s",
               pi->layout == LG_PROBE_LATLONG   ? "lat-long"
               : pi->layout == LG_PROBE_ANGULAR ? "angular"
                                                : "cube",
               f.probe->radiance_desc.width, f.probe->radiance_desc.height,
               pi->layout == LG_PROBE_CUBE ? " per face" : "", f.v.camera,
               f.geometry ? "with geometry" : "no geometry");
    }
    free(f.mats);
    return rc;
}

static void ibl_destroy(lg_node *n)
{
    ibl_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->gpass);
    lg_gl_pass_destroy(&st->spass);
    lg_gl_texture_destroy(n, &st->gbuf_tex);
    lg_gl_texture_destroy(n, &st->gdepth_tex);
    lg_gl_buffer_destroy(n, &st->mats_buf);
    lg_gl_buffer_destroy(n, &st->clamp_buf);
    lg_gl_texture_destroy(n, &st->chain_tex);
    lg_gl_buffer_destroy(n, &st->dfg_buf);
    lg_cl_pass_destroy(&st->kernel);
    lg_cl_buffer *m[6] = { &st->cl_gbuf,    &st->cl_gdepth, &st->cl_mats,
                           &st->cl_clamped, &st->cl_chain,  &st->cl_dfg };
    for (int i = 0; i < 6; i++)
        lg_cl_buffer_destroy(n, m[i]);
    free(st->gbuf);
    free(st->gdepth);
    free(st->chain);
    free(st);
    n->user = NULL;
}

/* ---- the descriptors ------------------------------------------------------------------------- */

/* in lg_probe_prefilter_weighting order */
static const char *const ibl_weightings[] = { "nol", "nol_vis", NULL };
static const char *const ibl_samplings[] = { "bilinear", "nearest", NULL };
static const char *const ibl_fresnels[] = { "none", "schlick", NULL };
static const char *const ibl_glossies[] = { "auto", "off", NULL };

#define IBL_COMMON_PARAMS                                                                          \
    /* where the shading runs; the G-buffer is rasterised on GL in every case */                   \
    LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL | LG_BACKEND_CL, LG_BACKEND_GL),               \
        { .key = "format",                                                                         \
          .type = LG_PARAM_ENUM,                                                                   \
          .def.e = IBL_RGBA32F,                                                                    \
          .enum_values = ibl_format_names,                                                         \
          .doc = "output format: rgba32f; rgba16f (values above 65504 clamped to 65504, reported " \
                 "once with a count); rgbe8 (Ward's shared exponent on an RGBA8 image)" },         \
        { .key = "width",                                                                          \
          .type = LG_PARAM_INT,                                                                    \
          .def.i = 0,                                                                              \
          .min = 0,                                                                                \
          .max = 16384,                                                                            \
          .doc = "output width in pixels; 0 = the render size (--size)",                           \
          .role = LG_ROLE_IMAGE_WIDTH },                                                           \
        { .key = "height",                                                                         \
          .type = LG_PARAM_INT,                                                                    \
          .def.i = 0,                                                                              \
          .min = 0,                                                                                \
          .max = 16384,                                                                            \
          .doc = "output height in pixels; 0 = the render size (--size)",                          \
          .role = LG_ROLE_IMAGE_HEIGHT },                                                          \
        { .key = "camera",                                                                         \
          .type = LG_PARAM_INT,                                                                    \
          .def.i = -1,                                                                             \
          .min = -1,                                                                               \
          .max = 1e9,                                                                              \
          .doc = "index of the scene's camera to look through; -1 = the scene's active camera" },  \
    {                                                                                              \
        .key = "sampling", .type = LG_PARAM_ENUM, .def.e = IBL_BILINEAR,                           \
        .enum_values = ibl_samplings,                                                              \
        .doc = "probe lookup: bilinear (seamless across cube edges and the lat-long seam) or "     \
               "nearest (lightgraph/probe.h)"                                                      \
    }

static const lg_param_desc ibl_mirror_params[] = {
    IBL_COMMON_PARAMS,
    { .key = "fresnel",
      .type = LG_PARAM_ENUM,
      .def.e = IBL_FRESNEL_NONE,
      .enum_values = ibl_fresnels,
      .doc = "none: the reflectivity as it is; schlick: F0 + (1 - F0)(1 - cos)^5 with F0 = "
             "the reflectivity and cos = N.V of the pixel" },
    { .key = "reflectivity",
      .type = LG_PARAM_COLOR,
      .def.v = { -1, -1, -1 },
      .min = -1,
      .max = 1e6,
      .doc = "[-1, -1, -1]: each material's reflectivity (glTF metals, "
             "KHR_materials_specular, extras.reflectivity); else this linear RGB for every "
             "material" },
    { .key = "glossy",
      .type = LG_PARAM_ENUM,
      .def.e = IBL_GLOSSY_AUTO,
      .enum_values = ibl_glossies,
      .doc = "auto: a material with roughness > 0 reads the GGX-prefiltered chain at its "
             "roughness (split sum); off: every material is a mirror" },
    { .key = "levels",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16,
      .doc = "levels of the GGX chain (level l of L: roughness l/(L-1)); 0 = 6 (fewer when "
             "the face is too small)" },
    { .key = "prefilter_size",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 4096,
      .doc = "face size of the GGX chain (a cube); 0 = 128, halved while larger than the "
             "probe (a cube's face, a 2D probe's width / 4), at least 8; a size finer than "
             "the probe can fill (that face rounded up to a power of two, at least 8) is "
             "clamped to it, with a warning" },
    { .key = "prefilter_samples",
      .type = LG_PARAM_INT,
      .def.i = 256,
      .min = 1,
      .max = 1048576,
      .doc = "GGX samples per texel of the chain (filtered importance "
             "sampling)" },
    { .key = "prefilter_weighting",
      .type = LG_PARAM_ENUM,
      .def.e = LG_PROBE_WEIGHT_NOL,
      .enum_values = ibl_weightings,
      .doc = "nol: Karis's n.l weights (better for views away from the normal); nol_vis: "
             "n.l Vis, whose split sum converges to the BRDF integral where n = v "
             "(docs/probes.md, Glossy prefiltering)" },
};
static const lg_param_desc ibl_bg_params[] = { IBL_COMMON_PARAMS };

static const lg_port_desc ibl_inputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the scene (its camera; its geometry and materials)" },
    { .name = "probe", .kind = LG_KIND_PROBE, .doc = "the light probe (any layout)" },
    { .name = "base",
      .kind = LG_KIND_IMAGE,
      .optional = true,
      .doc = "rgba32f image of the output's size (phong's output, say): the result is added "
             "to it (reflect, envmap) or drawn under it (background); its depth plane, if "
             "any, passes where no geometry is" },
};
static const lg_port_desc ibl_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "linear HDR radiance (format), alpha 1 (or base's), with a depth plane: GL "
             "window depth in [0, 1] (1 = nothing)" },
};

static const lg_node_type ibl_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "reflect",
        .doc = "Reflection mapping: the probe seen along R = reflect(V, N) on the scene's "
               "reflective materials, added to an optional base image (cpu, gl, cl)",
        LG_PARAMS(ibl_mirror_params),
        LG_INPUTS(ibl_inputs),
        LG_OUTPUTS(ibl_outputs),
        .needs = LG_NEEDS_PROBE | LG_NEEDS_REFLECTIVE,
        .neutral = LG_NEUTRAL_PASSTHROUGH,
        .neutral_input = IN_BASE,
        .create = ibl_create_reflect,
        .prepare = ibl_prepare,
        .execute = ibl_execute,
        .destroy = ibl_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "envmap",
        .doc = "Environment mapping: the probe seen along the normal N on the scene's "
               "reflective materials, added to an optional base image (cpu, gl, cl)",
        LG_PARAMS(ibl_mirror_params),
        LG_INPUTS(ibl_inputs),
        LG_OUTPUTS(ibl_outputs),
        .needs = LG_NEEDS_PROBE | LG_NEEDS_REFLECTIVE,
        .neutral = LG_NEUTRAL_PASSTHROUGH,
        .neutral_input = IN_BASE,
        .create = ibl_create_envmap,
        .prepare = ibl_prepare,
        .execute = ibl_execute,
        .destroy = ibl_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "background",
        .doc = "The probe seen through the camera where no geometry covers the pixel, under "
               "an optional base image (cpu, gl, cl)",
        LG_PARAMS(ibl_bg_params),
        LG_INPUTS(ibl_inputs),
        LG_OUTPUTS(ibl_outputs),
        .needs = LG_NEEDS_PROBE,
        .neutral = LG_NEUTRAL_PASSTHROUGH,
        .neutral_input = IN_BASE,
        .create = ibl_create_background,
        .prepare = ibl_prepare,
        .execute = ibl_execute,
        .destroy = ibl_destroy,
    },
};

LG_PLUGIN_DEFINE("ibl", "1.0.0",
                 "Image-based lighting from a light probe: reflection mapping, environment "
                 "mapping and the background, on cpu, gl and cl",
                 ibl_types)
