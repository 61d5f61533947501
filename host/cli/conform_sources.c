/*
 * host/cli/conform_sources.c: the synthetic inputs of `lightgraph conform` (conform.h).
 *
 * A plugin that is part of the program (lg_registry_add_builtin), so that conform feeds the
 * plugin under test through the host's own machinery (graph text, checker, planner,
 * executor, resources) without loading any other plugin. One node type per resource kind a
 * port may declare; each makes a small, known value that its parameters choose:
 *
 *   conform_image     -> image  width x height in any format; `pattern`: ramp (finite,
 *                                 in [0.05, 1]), nan / inf (the ramp with one NaN / +Inf
 *                                 pixel), negative (the ramp negated), huge (every channel
 *                                 65504, the largest value every format holds)
 *   conform_scene     -> scene  full: a cube on a floor, a directional and a point light,
 *                                 a specular, reflective material, a medium, a probe flag;
 *                                 empty: a camera and nothing else; unlit: the geometry
 *                                 without lights, medium, probe or specular/reflective terms
 *   conform_probe     -> probe  a 16 x 8 lat-long probe of the ramp (or the pattern)
 *   conform_sh        -> sh     3 bands, small positive coefficients
 *   conform_transfer  -> transfer 3 bands for the full scene's vertices
 *   conform_froxel    -> froxel  4 x 3 x 5 cells
 *   conform_shadowmap -> shadowmap 16 x 16 atlas at depth 1 (nothing occludes)
 *   conform_buffer    -> buffer 64 floats of the ramp
 *   conform_volume    -> volume 4 x 4 x 4 of the ramp
 *
 * `squeeze` (conform_image): after the last of the node's image sources declared its image,
 * it lowers the pixel limit to one pixel, so that the node's prepare fails as it declares
 * its own image: the
 * lifecycle check's "destroy after a failed prepare", made by the host's own limit rather
 * than by asking the plugin. Only conform's child processes use it.
 */
#include "cli/conform.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/froxel.h"
#include "lightgraph/image.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"
#include "lightgraph/scene.h"
#include "lightgraph/shadowmap.h"
#include "lightgraph/shcoeffs.h"
#include "lightgraph/transfer.h"
#include "lightgraph/vecmath.h"

const char *const lg_conform_formats[] = { "rgba32f", "rgba16f", "rgba8", "rgbe8", NULL };
const char *const lg_conform_patterns[] = { "ramp", "nan", "inf", "negative", "huge", NULL };
const char *const lg_conform_scenes[] = { "full", "empty", "unlit", NULL };

#define HUGE_PIXEL 65504.0f

/* The value of channel c of pixel i of n in `pattern`: a ramp over the pixels, the same in
 * every format (rgba8 and rgbe8 round it), alpha 1. */
static float pattern_value(int pattern, size_t i, size_t n, int c)
{
    float t = n > 1 ? (float)i / (float)(n - 1) : 0.5f;
    float v = c == 3 ? 1.0f : 0.05f + 0.95f * (c == 0 ? t : c == 1 ? 1.0f - t : 0.5f * t + 0.25f);
    switch (pattern) {
    case LG_CONFORM_NAN: return i == n / 2 && c < 3 ? NAN : v;
    case LG_CONFORM_INF: return i == n / 2 && c < 3 ? INFINITY : v;
    case LG_CONFORM_NEGATIVE: return c == 3 ? 1.0f : -v;
    case LG_CONFORM_HUGE: return c == 3 ? 1.0f : HUGE_PIXEL;
    default: return v;
    }
}

static int fill_floats(float *p, size_t texels, int pattern)
{
    for (size_t i = 0; i < texels; i++)
        for (int c = 0; c < 4; c++)
            p[i * 4 + c] = pattern_value(pattern, i, texels, c);
    return 0;
}

static int nothing(lg_node *n, const lg_frame *f)
{
    (void)n;
    (void)f;
    return 0;
}

/* ---- conform_image --------------------------------------------------------------------------- */

static int64_t squeezed; /* image sources prepared with `squeeze` since the last reset */

void lg_conform_squeeze_reset(void)
{
    squeezed = 0;
}

static const lg_param_desc image_params[] = {
    { .key = "width", .type = LG_PARAM_INT, .def.i = 7, .min = 1, .max = 16384, .doc = "pixels" },
    { .key = "height", .type = LG_PARAM_INT, .def.i = 5, .min = 1, .max = 16384, .doc = "pixels" },
    { .key = "format",
      .type = LG_PARAM_ENUM,
      .enum_values = lg_conform_formats,
      .doc = "pixel format" },
    { .key = "pattern",
      .type = LG_PARAM_ENUM,
      .enum_values = lg_conform_patterns,
      .doc = "ramp, or one of the hostile patterns" },
    { .key = "squeeze",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 64,
      .doc = "k > 0: the k-th squeezing source to declare its image lowers the pixel limit to 1 "
             "(the node they feed then fails its prepare)" },
};
static const lg_port_desc image_out[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "the image, with a depth plane" }
};

static int image_prepare(lg_node *n)
{
    static const lg_format fmts[] = { LG_FORMAT_RGBA32F, LG_FORMAT_RGBA16F, LG_FORMAT_RGBA8,
                                      LG_FORMAT_RGBE8 };
    lg_image_desc d = { .width = (uint32_t)lg_param_int(n, "width"),
                        .height = (uint32_t)lg_param_int(n, "height"),
                        .format = fmts[lg_param_enum(n, "format")],
                        .flags = LG_IMAGE_DEPTH };
    int rc = lg_declare_image(n, 0, &d);
    int64_t k = lg_param_int(n, "squeeze");
    /* every image source of the node is given the count; the last one to be prepared
     * squeezes, so that the node under test is the first to meet the limit */
    if (!rc && k > 0 && ++squeezed == k)
        lg_image_set_max_pixels(1);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int image_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    lg_cpu_view v;
    int rc = lg_describe(lg_output(n, 0), &info, n);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    size_t texels = (size_t)info.image.width * info.image.height;
    float *f = malloc(texels * 16 + 16);
    if (!f)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory for %zu pixels", texels);
    fill_floats(f, texels, lg_param_enum(n, "pattern"));
    /* the depth plane: window depth from 0.2 (top left) to 0.9, finite in every pattern */
    for (size_t i = 0; v.depth && i < texels; i++)
        v.depth[i] = 0.2f + 0.7f * (texels > 1 ? (float)i / (float)(texels - 1) : 0.5f);
    rc = lg_pixels_from_rgba32f(info.image.format, f, texels, v.pixels, NULL);
    free(f);
    return rc ? lg_error(n, "cannot convert the pattern to %s", lg_format_name(info.image.format))
              : 0;
}

/* ---- conform_scene --------------------------------------------------------------------------- */

#define SCENE_VERTS 28 /* the cube's 24 and the floor's 4: what conform_transfer matches */

typedef struct cf_scene {
    lg_scene s;
    lg_mesh meshes[2];
    float pos[SCENE_VERTS * 3], nrm[SCENE_VERTS * 3];
    uint32_t idx[42];
    lg_instance inst[2];
    lg_material mat;
    lg_light lights[2];
    lg_camera cam;
} cf_scene;

static void scene_free(void *p)
{
    free(p);
}

/* A quad c +- u +- v facing u x v, appended to mesh m (vertices from *nv, indices *ni). */
static void quad(cf_scene *t, lg_mesh *m, lg_vec3 c, lg_vec3 u, lg_vec3 v, uint32_t *nv,
                 uint32_t *ni)
{
    lg_vec3 nr = lg_v3_normalize_or(lg_v3_cross(u, v), lg_v3(0, 1, 0));
    static const float su[4] = { -1, 1, 1, -1 }, sv[4] = { -1, -1, 1, 1 };
    uint32_t base = *nv;
    for (int k = 0; k < 4; k++) {
        lg_vec3 p = lg_v3_add(c, lg_v3_add(lg_v3_scale(u, su[k]), lg_v3_scale(v, sv[k])));
        float *pp = t->pos + (base + k) * 3, *nn = t->nrm + (base + k) * 3;
        pp[0] = p.x, pp[1] = p.y, pp[2] = p.z;
        nn[0] = nr.x, nn[1] = nr.y, nn[2] = nr.z;
    }
    static const uint32_t tri[6] = { 0, 1, 2, 0, 2, 3 };
    for (int k = 0; k < 6; k++)
        t->idx[(*ni)++] = base + tri[k];
    m->n_vertices += 4;
    m->n_indices += 6;
    *nv += 4;
}

static cf_scene *scene_build(int variant)
{
    cf_scene *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->s.struct_size = sizeof t->s;
    t->s.source = "conform scene";
    t->s.meshes = t->meshes;
    t->s.instances = t->inst;
    t->s.materials = &t->mat;
    t->s.n_materials = 1;
    t->s.lights = t->lights;
    t->s.cameras = &t->cam;
    t->s.n_cameras = 1;
    t->mat.name = "conform";
    t->mat.ka = 0.1f, t->mat.kd = 0.8f;
    t->mat.shininess = 32;
    for (int k = 0; k < 3; k++)
        t->mat.od[k] = t->mat.base_color[k] = 0.6f;
    t->mat.base_color[3] = 1;
    t->mat.roughness = 0.5f;
    t->cam.name = "front";
    t->cam.position[0] = 2, t->cam.position[1] = 2, t->cam.position[2] = 4;
    t->cam.up[1] = 1;
    t->cam.yfov = 0.8f;
    t->cam.znear = 0.1f, t->cam.zfar = 50;
    if (variant != LG_CONFORM_SCENE_EMPTY) {
        /* the unit cube (mesh 0) and a 6 x 6 floor at y = -0.5 (mesh 1) */
        static const float f[6][3][3] = {
            { { 1, 0, 0 }, { 0, 0, -1 }, { 0, 1, 0 } }, { { -1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },
            { { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, -1 } }, { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } },
            { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 } },  { { 0, 0, -1 }, { -1, 0, 0 }, { 0, 1, 0 } },
        };
        uint32_t nv = 0, ni = 0;
        t->meshes[0].positions = t->pos, t->meshes[0].normals = t->nrm;
        t->meshes[0].indices = t->idx;
        t->meshes[0].name = "conform cube#0";
        for (int i = 0; i < 6; i++)
            quad(t, &t->meshes[0], lg_v3_scale(lg_v3(f[i][0][0], f[i][0][1], f[i][0][2]), 0.5f),
                 lg_v3_scale(lg_v3(f[i][1][0], f[i][1][1], f[i][1][2]), 0.5f),
                 lg_v3_scale(lg_v3(f[i][2][0], f[i][2][1], f[i][2][2]), 0.5f), &nv, &ni);
        /* mesh 1 indexes its own vertices from 0: its arrays start where the cube's end */
        uint32_t nv1 = 0, ni1 = 0;
        cf_scene tmp;
        memset(&tmp, 0, sizeof tmp);
        quad(&tmp, &t->meshes[1], lg_v3(0, -0.5f, 0), lg_v3(3, 0, 0), lg_v3(0, 0, -3), &nv1, &ni1);
        memcpy(t->pos + nv * 3, tmp.pos, 4 * 3 * sizeof(float));
        memcpy(t->nrm + nv * 3, tmp.nrm, 4 * 3 * sizeof(float));
        memcpy(t->idx + ni, tmp.idx, 6 * sizeof(uint32_t));
        t->meshes[1].positions = t->pos + nv * 3, t->meshes[1].normals = t->nrm + nv * 3;
        t->meshes[1].indices = t->idx + ni;
        t->meshes[1].name = "conform floor#0";
        t->s.n_meshes = 2;
        for (uint32_t i = 0; i < 2; i++) {
            t->inst[i].mesh = i;
            lg_m4_identity(t->inst[i].model);
            lg_m4_normal_matrix(t->inst[i].normal_matrix, t->inst[i].model);
            for (int k = 0; k < 3; k++) {
                t->meshes[i].bounds_min[k] = i == 0 ? -0.5f : k == 1 ? -0.5f : -3.0f;
                t->meshes[i].bounds_max[k] = i == 0 ? 0.5f : k == 1 ? -0.5f : 3.0f;
            }
        }
        t->s.n_instances = 2;
        for (int k = 0; k < 3; k++) {
            t->s.bounds_min[k] = k == 1 ? -0.5f : -3.0f;
            t->s.bounds_max[k] = k == 1 ? 0.5f : 3.0f;
        }
    } else {
        for (int k = 0; k < 3; k++) {
            t->s.bounds_min[k] = INFINITY;
            t->s.bounds_max[k] = -INFINITY;
        }
    }
    if (variant == LG_CONFORM_SCENE_FULL) {
        t->mat.ks = 0.5f;
        for (int k = 0; k < 3; k++)
            t->mat.os[k] = 1, t->mat.reflectivity[k] = 0.2f;
        t->lights[0] = (lg_light){ .name = "sun",
                                   .type = LG_LIGHT_DIRECTIONAL,
                                   .color = { 1, 1, 1 },
                                   .intensity = 3,
                                   .direction = { -0.4f, -0.8f, -0.45f } };
        t->lights[1] = (lg_light){ .name = "bulb",
                                   .type = LG_LIGHT_POINT,
                                   .color = { 1, 0.9f, 0.8f },
                                   .intensity = 10,
                                   .position = { 1.5f, 2, 1.5f } };
        t->s.n_lights = 2;
        t->s.medium = (lg_medium){ .present = true,
                                   .density = 0.1f,
                                   .scattering = { 0.5f, 0.5f, 0.5f },
                                   .absorption = { 0.05f, 0.05f, 0.05f },
                                   .g = 0.3f };
    }
    lg_scene_compute_features(&t->s);
    /* a probe lights the full scene (as scene_tools' environment records it) */
    t->s.features.probe = variant == LG_CONFORM_SCENE_FULL;
    return t;
}

static const lg_param_desc scene_params[] = {
    { .key = "variant",
      .type = LG_PARAM_ENUM,
      .enum_values = lg_conform_scenes,
      .doc = "full, empty or unlit (conform_sources.c)" },
};
static const lg_port_desc scene_out[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" }
};

static int scene_prepare(lg_node *n)
{
    cf_scene *t = scene_build(lg_param_enum(n, "variant"));
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    return n->host->declare_payload(n, 0, LG_KIND_SCENE, &t->s.features, &t->s, scene_free);
}

/* ---- composites ------------------------------------------------------------------------------ */

static const lg_param_desc pattern_params[] = {
    { .key = "pattern",
      .type = LG_PARAM_ENUM,
      .enum_values = lg_conform_patterns,
      .doc = "ramp, or one of the hostile patterns" },
};

static int write_part(lg_node *n, uint32_t port, const char *name, int pattern)
{
    const lg_resource *p = lg_part(n, lg_output(n, port), name);
    lg_resource_info info;
    lg_cpu_view v;
    int rc;
    if (!p)
        return lg_error(n, "part '%s' is missing", name);
    if ((rc = lg_describe(p, &info, n)) || (rc = lg_map_cpu(n, p, LG_WRITE, &v)))
        return rc;
    size_t floats = info.kind == LG_KIND_VOLUME
                        ? (size_t)info.volume.width * info.volume.height * info.volume.depth * 4
                    : info.kind == LG_KIND_IMAGE ? (size_t)info.image.width * info.image.height * 4
                                                 : info.buffer.size / sizeof(float);
    fill_floats(v.pixels, floats / 4, pattern);
    for (size_t i = floats / 4 * 4; i < floats; i++)
        ((float *)v.pixels)[i] = 0.5f;
    return 0;
}

static const lg_port_desc probe_out[] = {
    { .name = "probe", .kind = LG_KIND_PROBE, .doc = "the probe" }
};

static int probe_prepare(lg_node *n)
{
    lg_image_desc d = { .width = 16, .height = 8, .format = LG_FORMAT_RGBA32F };
    int rc = lg_probe_declare(n, 0, LG_PROBE_LATLONG, &d, false);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int probe_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    lg_probe_info info = { .layout = LG_PROBE_LATLONG, .scale = 1 };
    info.rotation[0] = info.rotation[4] = info.rotation[8] = 1;
    int rc = write_part(n, 0, "radiance", lg_param_enum(n, "pattern"));
    return rc ? rc : lg_probe_publish(n, 0, &info);
}

static const lg_port_desc sh_out[] = {
    { .name = "sh", .kind = LG_KIND_SH, .doc = "the coefficients" }
};

static int sh_prepare(lg_node *n)
{
    int rc = lg_sh_declare(n, 0, 3);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int sh_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    lg_sh_info info = { .bands = 3 };
    int rc = write_part(n, 0, "coeffs", lg_param_enum(n, "pattern"));
    return rc ? rc : lg_sh_publish(n, 0, &info);
}

static const lg_param_desc transfer_params[] = {
    { .key = "pattern",
      .type = LG_PARAM_ENUM,
      .enum_values = lg_conform_patterns,
      .doc = "ramp, or one of the hostile patterns" },
    { .key = "empty_scene",
      .type = LG_PARAM_BOOL,
      .doc = "for the empty scene: one vertex (a transfer holds at least one)" },
};

static const lg_port_desc transfer_out[] = {
    { .name = "transfer", .kind = LG_KIND_TRANSFER, .doc = "the transfer vectors" }
};

static int transfer_prepare(lg_node *n)
{
    int rc = lg_transfer_declare(n, 0, 3, lg_param_bool(n, "empty_scene") ? 1 : SCENE_VERTS);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int transfer_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    lg_transfer_info info = { .bands = 3,
                              .vertices = lg_param_bool(n, "empty_scene") ? 1 : SCENE_VERTS,
                              .mode = LG_TRANSFER_SHADOWED };
    int rc = write_part(n, 0, "transfer", lg_param_enum(n, "pattern"));
    return rc ? rc : lg_transfer_publish(n, 0, &info);
}

static const lg_port_desc froxel_out[] = {
    { .name = "froxel", .kind = LG_KIND_FROXEL, .doc = "the grid" }
};

static int froxel_prepare(lg_node *n)
{
    int rc = lg_froxel_declare(n, 0, 4, 3, 5, LG_FORMAT_RGBA32F);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int froxel_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    lg_froxel_info info = { .width = 4,
                            .height = 3,
                            .depth = 5,
                            .slicing = LG_FROXEL_EXPONENTIAL,
                            .near = 0.1f,
                            .far = 50,
                            .near_offset = 0.5f };
    lg_m4_identity(info.view);
    lg_m4_identity(info.proj);
    int rc = write_part(n, 0, "grid", lg_param_enum(n, "pattern"));
    return rc ? rc : lg_froxel_publish(n, 0, &info);
}

static const lg_param_desc shadow_params[] = {
    { .key = "pattern",
      .type = LG_PARAM_ENUM,
      .enum_values = lg_conform_patterns,
      .doc = "ramp, or one of the hostile patterns" },
    { .key = "lights",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 0,
      .max = 1,
      .doc = "maps: one for the full scene's directional light, none for the others" },
};

static const lg_port_desc shadow_out[] = {
    { .name = "shadow", .kind = LG_KIND_SHADOWMAP, .doc = "the shadow map" }
};

static int shadow_prepare(lg_node *n)
{
    int rc = lg_shadowmap_declare(n, 0, 16, 16, (uint32_t)lg_param_int(n, "lights"));
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int shadow_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    const lg_resource *atlas = lg_part(n, lg_output(n, 0), "atlas");
    lg_cpu_view v;
    int rc = atlas ? lg_map_cpu(n, atlas, LG_WRITE, &v) : lg_error(n, "no atlas part");
    if (rc)
        return rc;
    for (size_t i = 0; i < 16 * 16; i++)
        v.depth[i] = 1.0f; /* nothing drawn: nothing occludes */
    lg_shadow_light l;
    memset(&l, 0, sizeof l);
    lg_m4_identity(l.view);
    lg_m4_identity(l.proj);
    for (int k = 0; k < 3; k++)
        l.proj[k * 5] = 0.25f;
    memcpy(l.view_proj, l.proj, sizeof l.proj);
    l.texel_world = 0.5f;
    l.depth_range = 8;
    lg_shadowmap_info info = { .resolution = 16,
                               .n_lights = (uint32_t)lg_param_int(n, "lights"),
                               .atlas_width = 16,
                               .atlas_height = 16,
                               .bias_constant = 1e-3f };
    return lg_shadowmap_publish(n, 0, &info, &l);
}

static const lg_port_desc buffer_out[] = {
    { .name = "buffer", .kind = LG_KIND_BUFFER, .doc = "64 floats" }
};

static int buffer_prepare(lg_node *n)
{
    lg_buffer_desc d = { .size = 64 * sizeof(float) };
    int rc = n->host->declare_buffer(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int buffer_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    return rc ? rc : fill_floats(v.pixels, 16, lg_param_enum(n, "pattern"));
}

static const lg_port_desc volume_out[] = {
    { .name = "volume", .kind = LG_KIND_VOLUME, .doc = "4x4x4" }
};

static int volume_prepare(lg_node *n)
{
    lg_volume_desc d = { .width = 4, .height = 4, .depth = 4, .format = LG_FORMAT_RGBA32F };
    int rc = n->host->declare_volume(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int volume_execute(lg_node *n, const lg_frame *f)
{
    (void)f;
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    return rc ? rc : fill_floats(v.pixels, 64, lg_param_enum(n, "pattern"));
}

#define CF_TYPE(name_, doc_, params_, outs_, prep_, exec_)                                         \
    {                                                                                              \
        .struct_size = sizeof(lg_node_type), .name = (name_), .doc = (doc_), LG_PARAMS(params_),   \
        LG_OUTPUTS(outs_), .prepare = (prep_), .execute = (exec_),                                 \
    }

static const lg_node_type types[] = {
    CF_TYPE("conform_image", "a synthetic image", image_params, image_out, image_prepare,
            image_execute),
    CF_TYPE("conform_scene", "a small scene built in memory", scene_params, scene_out,
            scene_prepare, nothing),
    CF_TYPE("conform_probe", "a 16 x 8 lat-long probe", pattern_params, probe_out, probe_prepare,
            probe_execute),
    CF_TYPE("conform_sh", "3 bands of SH coefficients", pattern_params, sh_out, sh_prepare,
            sh_execute),
    CF_TYPE("conform_transfer", "transfer vectors for the full scene", transfer_params,
            transfer_out, transfer_prepare, transfer_execute),
    CF_TYPE("conform_froxel", "a 4 x 3 x 5 froxel grid", pattern_params, froxel_out, froxel_prepare,
            froxel_execute),
    CF_TYPE("conform_shadowmap", "a shadow map where nothing occludes", shadow_params, shadow_out,
            shadow_prepare, shadow_execute),
    CF_TYPE("conform_buffer", "64 floats", pattern_params, buffer_out, buffer_prepare,
            buffer_execute),
    CF_TYPE("conform_volume", "a 4 x 4 x 4 volume", pattern_params, volume_out, volume_prepare,
            volume_execute),
};

static const lg_plugin_desc desc = {
    .struct_size = sizeof(lg_plugin_desc),
    .abi_major = LG_ABI_MAJOR,
    .abi_minor = LG_ABI_MINOR,
    .name = "conform",
    .version = "1.0.0",
    .doc = "the synthetic inputs of lightgraph conform (part of the program)",
    .types = types,
    .n_types = sizeof types / sizeof types[0],
};

const lg_plugin_desc *lg_conform_sources(void)
{
    return &desc;
}

const char *lg_conform_source_for(lg_resource_kind kind)
{
    switch (kind) {
    case LG_KIND_ANY:
    case LG_KIND_IMAGE: return "conform_image";
    case LG_KIND_SCENE: return "conform_scene";
    case LG_KIND_PROBE: return "conform_probe";
    case LG_KIND_SH: return "conform_sh";
    case LG_KIND_TRANSFER: return "conform_transfer";
    case LG_KIND_FROXEL: return "conform_froxel";
    case LG_KIND_SHADOWMAP: return "conform_shadowmap";
    case LG_KIND_BUFFER: return "conform_buffer";
    case LG_KIND_VOLUME: return "conform_volume";
    default: return NULL;
    }
}
