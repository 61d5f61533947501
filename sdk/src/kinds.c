/* Resource kinds and their parts (lightgraph/kinds.h), and the accessors of the composite
 * kinds (lightgraph/shadowmap.h, probe.h, shcoeffs.h, transfer.h, froxel.h). Everything
 * here goes through the host API: a part is reached with lg_part() and mapped like any
 * image or buffer, so residency and the access check apply to it. */
#include "lightgraph/kinds.h"

#include <stddef.h>
#include <math.h>
#include <string.h>

#include "lightgraph/froxel.h"
#include "lightgraph/host.h"
#include "lightgraph/probe.h"
#include "lightgraph/shadowmap.h"
#include "lightgraph/shcoeffs.h"
#include "lightgraph/transfer.h"

/* The lights part is bound as a std430 array by shaders: its record must have the size
 * and offsets a std430 struct of 3 mat4, 3 uint, 2 float has, padded to 16. */
_Static_assert(sizeof(lg_shadow_light) == 224, "lg_shadow_light must match its std430 layout");
_Static_assert(offsetof(lg_shadow_light, view_proj) == 128, "std430 offset of view_proj");
_Static_assert(offsetof(lg_shadow_light, light) == 192, "std430 offset of light");

static const lg_part_decl shadow_parts[] = {
    { .name = "atlas",
      .type = LG_PART_IMAGE,
      .doc = "depth only: each light's window depth in its tile, 1 where nothing is" },
    { .name = "lights",
      .type = LG_PART_BUFFER,
      .doc = "lg_shadow_light[n_lights]: matrices and tile of each light (std430)" },
    { .name = "info",
      .type = LG_PART_META,
      .doc = "lg_shadowmap_info: tile resolution, light count, atlas size, biases" },
};
static const lg_part_decl probe_parts[] = {
    { .name = "radiance",
      .type = LG_PART_IMAGE,
      .doc = "2D (lat-long, angular) or cube radiance, linear, with an optional mip chain" },
    { .name = "solid_angle",
      .type = LG_PART_BUFFER,
      .optional = true,
      .doc = "float steradians per texel of level 0, in texel order" },
    { .name = "info",
      .type = LG_PART_META,
      .doc = "lg_probe_info: layout, rotation, scale, prefiltering" },
};
static const lg_part_decl sh_parts[] = {
    { .name = "coeffs", .type = LG_PART_BUFFER, .doc = "float[3][n^2]: R, G, B planes" },
    { .name = "info", .type = LG_PART_META, .doc = "lg_sh_info: bands, flags" },
};
static const lg_part_decl transfer_parts[] = {
    { .name = "transfer",
      .type = LG_PART_BUFFER,
      .doc = "float[vertices][3][n^2]: per vertex, R, G, B planes" },
    { .name = "info", .type = LG_PART_META, .doc = "lg_transfer_info: bands, vertices, mode" },
};
static const lg_part_decl froxel_parts[] = {
    { .name = "grid",
      .type = LG_PART_VOLUME,
      .doc = "rgb in-scattered radiance, a transmittance, per froxel" },
    { .name = "info",
      .type = LG_PART_META,
      .doc = "lg_froxel_info: grid size, slice map, camera matrices" },
};

#define PARTS(a) .parts = (a), .n_parts = (uint32_t)(sizeof(a) / sizeof((a)[0]))
static const lg_kind_desc kinds[LG_KIND_COUNT_] = {
    [LG_KIND_ANY] = { LG_KIND_ANY, "any", "inputs only: accepts every kind" },
    [LG_KIND_IMAGE] = { LG_KIND_IMAGE, "image",
                        "2D or cube rgba image with mip levels and "
                        "an optional depth plane" },
    [LG_KIND_BUFFER] = { LG_KIND_BUFFER, "buffer", "bytes" },
    [LG_KIND_VOLUME] = { LG_KIND_VOLUME, "volume", "3D grid of rgba" },
    [LG_KIND_SCENE] = { LG_KIND_SCENE, "scene", "meshes, materials, lights, cameras, medium" },
    [LG_KIND_SHADOWMAP] = { LG_KIND_SHADOWMAP, "shadowmap", "depth atlas and per-light matrices",
                            PARTS(shadow_parts) },
    [LG_KIND_PROBE] = { LG_KIND_PROBE, "probe", "environment radiance with its layout",
                        PARTS(probe_parts) },
    [LG_KIND_SH] = { LG_KIND_SH, "sh", "spherical-harmonic coefficients, n bands x RGB",
                     PARTS(sh_parts) },
    [LG_KIND_TRANSFER] = { LG_KIND_TRANSFER, "transfer",
                           "per-vertex PRT transfer vectors, n^2 x RGB per vertex",
                           PARTS(transfer_parts) },
    [LG_KIND_FROXEL] = { LG_KIND_FROXEL, "froxel", "froxel volume with its slice map",
                         PARTS(froxel_parts) },
};

const lg_kind_desc *lg_kind_describe(lg_resource_kind kind)
{
    return (unsigned)kind < LG_KIND_COUNT_ ? &kinds[kind] : NULL;
}

const char *lg_kind_name(lg_resource_kind kind)
{
    return (unsigned)kind < LG_KIND_COUNT_ ? kinds[kind].name : "?";
}

bool lg_kind_is_composite(lg_resource_kind kind)
{
    return (unsigned)kind < LG_KIND_COUNT_ && kinds[kind].n_parts > 0;
}

int32_t lg_kind_part_index(lg_resource_kind kind, const char *name)
{
    const lg_kind_desc *k = lg_kind_describe(kind);
    for (uint32_t i = 0; k && name && i < k->n_parts; i++)
        if (strcmp(k->parts[i].name, name) == 0)
            return (int32_t)i;
    return -1;
}

/* ---- metadata parts -------------------------------------------------------------------------- */

int lg_meta_write(lg_node *n, const lg_resource *res, const char *part, const void *data,
                  size_t size)
{
    const lg_resource *p = res ? lg_part(n, res, part) : NULL;
    if (!p)
        return lg_error(n, "cannot write metadata part '%s': the output has no such part",
                        part ? part : "");
    lg_resource_info info;
    lg_describe(p, &info, n);
    if (size > info.buffer.size)
        return lg_error(n, "metadata part '%s' holds %zu bytes; %zu were written", part,
                        info.buffer.size, size);
    lg_cpu_view v;
    int rc = lg_map_cpu(n, p, LG_WRITE, &v);
    if (rc)
        return rc;
    memcpy(v.pixels, data, size);
    if (size < info.buffer.size)
        memset((char *)v.pixels + size, 0, info.buffer.size - size);
    return 0;
}

const void *lg_meta_read(lg_node *n, const lg_resource *res, const char *part, size_t size)
{
    const lg_resource *p = lg_part(n, res, part);
    if (!p) {
        lg_error(n, "the input has no metadata part '%s'", part ? part : "");
        return NULL;
    }
    lg_resource_info info;
    lg_describe(p, &info, n);
    lg_cpu_view v;
    if (info.buffer.size < size || lg_map_cpu(n, p, LG_READ, &v) != 0 || !v.pixels) {
        lg_error(n,
                 "metadata part '%s' of the input holds %zu bytes, fewer than the %zu "
                 "this plugin reads",
                 part, info.buffer.size, size);
        return NULL;
    }
    uint32_t struct_size;
    memcpy(&struct_size, v.pixels, sizeof struct_size);
    if (struct_size < size) {
        lg_error(n,
                 "metadata part '%s' of the input says it is %u bytes long, fewer than "
                 "the %zu this plugin reads (made by an older or broken producer)",
                 part, struct_size, size);
        return NULL;
    }
    return v.pixels;
}

/* The composite input `res` of `kind`, or NULL: without an error for NULL or a neutral
 * resource, after lg_error for another kind. */
static bool composite_in(lg_node *n, const lg_resource *res, lg_resource_kind kind,
                         lg_resource_info *info)
{
    if (!res || lg_describe(res, info, n) != 0)
        return false;
    if (info->kind != kind) {
        lg_error(n, "expects %s, got a resource of kind %s", lg_kind_name(kind),
                 lg_kind_name(info->kind));
        return false;
    }
    return !info->neutral && info->n_parts > 0;
}

static const lg_resource *required_part(lg_node *n, const lg_resource *res, const char *name,
                                        lg_part_type type, lg_resource_info *pinfo)
{
    const lg_resource *p = lg_part(n, res, name);
    if (!p || lg_describe(p, pinfo, n) != 0 || pinfo->part_type != type) {
        lg_error(n, "the input's part '%s' is missing or of the wrong type", name);
        return NULL;
    }
    return p;
}

static lg_part_spec meta_spec(size_t size)
{
    return (lg_part_spec){ .name = "info", .type = LG_PART_META, .buffer.size = size };
}

/* Producer: writes a kind's info struct (which starts with uint32_t struct_size, set here)
 * into the `info` part of output `port`. */
static int publish_info(lg_node *n, uint32_t port, const void *info, size_t size)
{
    unsigned char copy[512];
    if (size > sizeof copy || size < sizeof(uint32_t))
        return lg_error(n, "an info struct of %zu bytes", size);
    memcpy(copy, info, size);
    uint32_t ss = (uint32_t)size;
    memcpy(copy, &ss, sizeof ss);
    return lg_meta_write(n, lg_output(n, port), "info", copy, size);
}

/* Consumer: the info struct of `res` (a composite of `kind`) and its main part `name` of
 * `type` with its description; NULL without an error for NULL or neutral, NULL after lg_error
 * otherwise. */
static const lg_resource *consume(lg_node *n, const lg_resource *res, lg_resource_kind kind,
                                  size_t info_size, const void **info, const char *name,
                                  lg_part_type type, lg_resource_info *pinfo)
{
    lg_resource_info whole;
    *info = NULL;
    if (!composite_in(n, res, kind, &whole))
        return NULL;
    *info = lg_meta_read(n, res, "info", info_size);
    return *info ? required_part(n, res, name, type, pinfo) : NULL;
}

/* ---- shadow maps ----------------------------------------------------------------------------- */

int lg_shadowmap_declare(lg_node *n, uint32_t port, uint32_t atlas_width, uint32_t atlas_height,
                         uint32_t n_lights)
{
    lg_part_spec parts[3] = {
        { .name = "atlas",
          .type = LG_PART_IMAGE,
          .image = { .width = atlas_width, .height = atlas_height, .flags = LG_IMAGE_DEPTH_ONLY } },
        { .name = "lights",
          .type = LG_PART_BUFFER,
          .buffer.size = (size_t)(n_lights ? n_lights : 1) * sizeof(lg_shadow_light) },
        meta_spec(sizeof(lg_shadowmap_info)),
    };
    return lg_declare_composite(n, port, parts, 3);
}

int lg_shadowmap_publish(lg_node *n, uint32_t port, const lg_shadowmap_info *info,
                         const lg_shadow_light *lights)
{
    const lg_resource *out = lg_output(n, port);
    const lg_resource *lp = out ? lg_part(n, out, "lights") : NULL;
    if (!lp)
        return lg_error(n, "lg_shadowmap_publish: output #%u is not a declared shadow map", port);
    lg_resource_info li;
    lg_describe(lp, &li, n);
    size_t need = (size_t)info->n_lights * sizeof(lg_shadow_light);
    if (need > li.buffer.size)
        return lg_error(n, "lg_shadowmap_publish: %u lights do not fit the %zu declared bytes",
                        info->n_lights, li.buffer.size);
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lp, LG_WRITE, &v);
    if (rc)
        return rc;
    memset(v.pixels, 0, li.buffer.size);
    if (need)
        memcpy(v.pixels, lights, need);
    return publish_info(n, port, info, sizeof *info);
}

const lg_shadowmap *lg_shadowmap_get(lg_node *n, const lg_resource *res, lg_shadowmap *out)
{
    lg_resource_info ai, li;
    const lg_shadowmap_info *mi;
    memset(out, 0, sizeof *out);
    const lg_resource *atlas = consume(n, res, LG_KIND_SHADOWMAP, sizeof *mi, (const void **)&mi,
                                       "atlas", LG_PART_IMAGE, &ai);
    const lg_resource *lights = atlas ? required_part(n, res, "lights", LG_PART_BUFFER, &li) : NULL;
    if (!lights)
        return NULL;
    if (mi->atlas_width != ai.image.width || mi->atlas_height != ai.image.height ||
        mi->resolution == 0 || (size_t)mi->n_lights * sizeof(lg_shadow_light) > li.buffer.size) {
        lg_error(n,
                 "the shadow maps are inconsistent: info says %u lights at %u in a %ux%u "
                 "atlas; the parts hold a %ux%u atlas and %zu bytes of lights",
                 mi->n_lights, mi->resolution, mi->atlas_width, mi->atlas_height, ai.image.width,
                 ai.image.height, li.buffer.size);
        return NULL;
    }
    lg_cpu_view lv;
    if (mi->n_lights && lg_map_cpu(n, lights, LG_READ, &lv) != 0)
        return NULL;
    /* Dual-paraboloid records are refused here, for every consumer at once (since ABI 3.3):
     * no producer makes them (shadowmap's point_mode is always the cube), phong never read
     * them and the lookups that did (this file's, froxel's gl and cl) were never tested on
     * one, so a third-party producer's paraboloids would have been shaded by untested code,
     * or silently unshadowed. */
    const lg_shadow_light *rec = mi->n_lights ? lv.pixels : NULL;
    for (uint32_t k = 0; k < mi->n_lights; k++)
        if (rec[k].projection == LG_SHADOW_PERSPECTIVE &&
            rec[k].face >= LG_SHADOW_FACE_PARABOLOID_FRONT) {
            lg_error(n,
                     "the shadow maps hold a dual-paraboloid map (record %u, light %u, face "
                     "%u): no consumer reads dual-paraboloid maps (untested; the shadowmap "
                     "node makes a point light's cube); give point lights six cube records",
                     k, rec[k].light, rec[k].face);
            return NULL;
        }
    if (mi->point_mode == LG_SHADOW_POINT_PARABOLOID) {
        lg_error(n, "the shadow maps' point_mode is dual-paraboloid: no consumer reads "
                    "dual-paraboloid maps (untested; the shadowmap node makes a point light's "
                    "cube)");
        return NULL;
    }
    out->resolution = mi->resolution;
    out->n_lights = mi->n_lights;
    out->lights = mi->n_lights ? lv.pixels : NULL;
    out->atlas = atlas;
    out->lights_part = lights;
    out->atlas_width = mi->atlas_width;
    out->atlas_height = mi->atlas_height;
    out->bias_constant = mi->bias_constant;
    out->bias_slope = mi->bias_slope;
    out->normal_offset = mi->normal_offset;
    out->pcf_radius = mi->pcf_radius;
    out->pcss_light_size = mi->pcss_light_size;
    out->point_mode = mi->point_mode;
    return out;
}

int32_t lg_shadowmap_find(const lg_shadowmap *sm, uint32_t light)
{
    if (!sm || !sm->lights)
        return -1;
    for (uint32_t k = 0; k < sm->n_lights; k++)
        if (sm->lights[k].light == light)
            return (int32_t)k;
    return -1;
}

/* world -> view space of record r (column-major view). */
static void sm_view_point(const lg_shadow_light *r, const double p[3], double v[3])
{
    const float *m = r->view;
    for (int row = 0; row < 3; row++)
        v[row] = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
}

int32_t lg_shadowmap_record_at(const lg_shadowmap *sm, int32_t first, const double p[3])
{
    if (!sm || first < 0 || (uint32_t)first >= sm->n_lights)
        return -1;
    const lg_shadow_light *r = &sm->lights[first];
    if (r->projection != LG_SHADOW_PERSPECTIVE)
        return first;
    if (r->face == LG_SHADOW_FACE_PARABOLOID_FRONT) {
        double v[3];
        sm_view_point(r, p, v);
        /* view space looks down -z: the front map holds -z (in front of the light) */
        bool back = v[2] > 0.0 && (uint32_t)first + 1 < sm->n_lights &&
                    sm->lights[first + 1].light == r->light;
        return back ? first + 1 : first;
    }
    bool cube = (uint32_t)first + 5 < sm->n_lights && sm->lights[first + 5].light == r->light &&
                sm->lights[first + 5].face == LG_SHADOW_FACE_NEG_Z;
    if (!cube)
        return first;
    /* the light's position: the view matrix is [R | -R q], so q = -R^T t */
    const float *m = r->view;
    double q[3];
    for (int c = 0; c < 3; c++)
        q[c] = -(m[c * 4 + 0] * m[12] + m[c * 4 + 1] * m[13] + m[c * 4 + 2] * m[14]);
    double d[3] = { p[0] - q[0], p[1] - q[1], p[2] - q[2] };
    int axis = 0;
    for (int c = 1; c < 3; c++)
        if (fabs(d[c]) > fabs(d[axis]))
            axis = c;
    return first + 2 * axis + (d[axis] < 0.0 ? 1 : 0);
}

float lg_shadowmap_visibility(const lg_shadowmap *sm, const float *atlas, uint32_t light,
                              const double p[3], double bias_extra)
{
    int32_t rec = lg_shadowmap_record_at(sm, lg_shadowmap_find(sm, light), p);
    if (rec < 0 || !atlas)
        return 1.0f;
    const lg_shadow_light *L = &sm->lights[rec];
    double ndc[3], wdepth = 0.0; /* wdepth: a perspective record's view depth of p */
    if (L->face >= LG_SHADOW_FACE_PARABOLOID_FRONT) {
        /* dual paraboloid: the view-space direction d (unit) maps to d.xy / (1 + d.z'),
         * z' = -d.z for the front map (it looks down -z), +d.z for the back; depth is the
         * distance over depth_range past znear */
        double v[3];
        sm_view_point(L, p, v);
        double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (!(len > 0.0))
            return 1.0f;
        double zf = L->face == LG_SHADOW_FACE_PARABOLOID_FRONT ? -v[2] / len : v[2] / len;
        ndc[0] = v[0] / len / (1.0 + zf);
        ndc[1] = v[1] / len / (1.0 + zf);
        ndc[2] = 2.0 * (len - L->znear) / L->depth_range - 1.0;
        if (L->face == LG_SHADOW_FACE_PARABOLOID_BACK)
            ndc[0] = -ndc[0];
    } else {
        const float *m = L->view_proj;
        double c[4];
        for (int row = 0; row < 4; row++)
            c[row] = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
        if (!(c[3] > 0.0))
            return 1.0f;
        for (int k = 0; k < 3; k++)
            ndc[k] = c[k] / c[3];
        wdepth = c[3];
    }
    double u = ndc[0] * 0.5 + 0.5, vv = ndc[1] * 0.5 + 0.5, z = ndc[2] * 0.5 + 0.5;
    if (!(u >= 0.0 && u < 1.0 && vv >= 0.0 && vv < 1.0) || !(z >= 0.0))
        return 1.0f;
    if (z > 1.0)
        z = 1.0;
    /* A perspective map's window depth is not linear in distance: a bias of b depth units
     * there would be b d^2 (f - n) / (f n) metres at view depth d (a fifth of the range at
     * the far plane for n = f / 1000), so the test is made on view depth instead, with the
     * bias in the same world units as an orthographic map's: (bias) x depth_range. The
     * stored depth D is linearised as n f / (f - D (f - n)). */
    bool persp = L->projection == LG_SHADOW_PERSPECTIVE &&
                 L->face < LG_SHADOW_FACE_PARABOLOID_FRONT;
    double zn = L->znear, zf = (double)L->znear + (double)L->depth_range;
    double bias_world = ((double)sm->bias_constant + bias_extra) * (double)L->depth_range;
    if (persp && wdepth > zf)
        wdepth = zf;
    int64_t res = sm->resolution, r = sm->pcf_radius;
    int64_t cx = (int64_t)(u * res), cy = (int64_t)(vv * res);
    uint32_t lit = 0, taps = 0;
    for (int64_t dy = -r; dy <= r; dy++)
        for (int64_t dx = -r; dx <= r; dx++) {
            int64_t x = cx + dx, y = cy + dy;
            x = x < 0 ? 0 : x >= res ? res - 1 : x;
            y = y < 0 ? 0 : y >= res ? res - 1 : y;
            uint64_t tx = L->tile_x + (uint64_t)x, ty = L->tile_y + (uint64_t)y;
            taps++;
            if (tx >= sm->atlas_width || ty >= sm->atlas_height) {
                lit++;
                continue;
            }
            float stored = atlas[(size_t)ty * sm->atlas_width + tx];
            if (persp) {
                double lin = zn * zf / (zf - (double)stored * (zf - zn));
                if (!(wdepth > lin + bias_world))
                    lit++;
            } else if (!((float)z > stored + sm->bias_constant + (float)bias_extra)) {
                lit++;
            }
        }
    return (float)lit / (float)taps;
}

/* ---- probes ---------------------------------------------------------------------------------- */

int lg_probe_declare(lg_node *n, uint32_t port, lg_probe_layout layout,
                     const lg_image_desc *radiance, bool with_solid_angle)
{
    if (layout < LG_PROBE_LATLONG || layout > LG_PROBE_CUBE)
        return lg_error(n, "lg_probe_declare: unknown layout %d", (int)layout);
    bool cube = (radiance->flags & LG_IMAGE_CUBE) != 0;
    if (cube != (layout == LG_PROBE_CUBE))
        return lg_error(n, "lg_probe_declare: a %s probe needs a %s radiance image",
                        layout == LG_PROBE_CUBE ? "cube" : "2D",
                        layout == LG_PROBE_CUBE ? "cube" : "2D");
    lg_part_spec parts[3] = {
        { .name = "radiance", .type = LG_PART_IMAGE, .image = *radiance },
        meta_spec(sizeof(lg_probe_info)),
        { .name = "solid_angle",
          .type = LG_PART_BUFFER,
          .buffer.size = (size_t)radiance->width * radiance->height * (cube ? 6 : 1) *
                         sizeof(float) },
    };
    return lg_declare_composite(n, port, parts, with_solid_angle ? 3 : 2);
}

int lg_probe_publish(lg_node *n, uint32_t port, const lg_probe_info *info)
{
    return publish_info(n, port, info, sizeof *info);
}

const lg_probe *lg_probe_get(lg_node *n, const lg_resource *res, lg_probe *out)
{
    lg_resource_info ri;
    const lg_probe_info *mi;
    memset(out, 0, sizeof *out);
    const lg_resource *rad = consume(n, res, LG_KIND_PROBE, sizeof *mi, (const void **)&mi,
                                     "radiance", LG_PART_IMAGE, &ri);
    if (!rad)
        return NULL;
    if ((mi->layout == LG_PROBE_CUBE) != ((ri.image.flags & LG_IMAGE_CUBE) != 0) ||
        mi->layout < LG_PROBE_LATLONG || mi->layout > LG_PROBE_CUBE) {
        lg_error(n, "the probe is inconsistent: layout %d with a %s radiance image",
                 (int)mi->layout, (ri.image.flags & LG_IMAGE_CUBE) ? "cube" : "2D");
        return NULL;
    }
    out->info = *mi;
    out->radiance = rad;
    out->radiance_desc = ri.image;
    out->solid_angle = lg_part(n, res, "solid_angle");
    return out;
}

/* ---- SH coefficients ------------------------------------------------------------------------- */

int lg_sh_declare(lg_node *n, uint32_t port, uint32_t bands)
{
    if (bands < 1 || bands > LG_SH_MAX_BANDS)
        return lg_error(n, "%u SH bands: 1 .. %u are possible", bands, LG_SH_MAX_BANDS);
    lg_part_spec parts[2] = {
        { .name = "coeffs",
          .type = LG_PART_BUFFER,
          .buffer.size = (size_t)3 * bands * bands * sizeof(float) },
        meta_spec(sizeof(lg_sh_info)),
    };
    return lg_declare_composite(n, port, parts, 2);
}

int lg_sh_publish(lg_node *n, uint32_t port, const lg_sh_info *info)
{
    return publish_info(n, port, info, sizeof *info);
}

const lg_sh *lg_sh_get(lg_node *n, const lg_resource *res, lg_sh *out)
{
    lg_resource_info ci;
    const lg_sh_info *mi;
    memset(out, 0, sizeof *out);
    const lg_resource *c = consume(n, res, LG_KIND_SH, sizeof *mi, (const void **)&mi, "coeffs",
                                   LG_PART_BUFFER, &ci);
    if (!c)
        return NULL;
    if (mi->bands < 1 || mi->bands > LG_SH_MAX_BANDS ||
        ci.buffer.size != (size_t)3 * mi->bands * mi->bands * sizeof(float)) {
        lg_error(n, "the SH coefficients are inconsistent: %u bands in %zu bytes", mi->bands,
                 ci.buffer.size);
        return NULL;
    }
    out->info = *mi;
    out->n_coeffs = mi->bands * mi->bands;
    out->coeffs = c;
    return out;
}

/* ---- transfer -------------------------------------------------------------------------------- */

int lg_transfer_declare(lg_node *n, uint32_t port, uint32_t bands, uint32_t vertices)
{
    if (bands < 1 || bands > LG_SH_MAX_BANDS)
        return lg_error(n, "%u SH bands: 1 .. %u are possible", bands, LG_SH_MAX_BANDS);
    uint64_t size = (uint64_t)vertices * 3 * bands * bands * sizeof(float);
    if (vertices == 0 || size > (1ull << 34))
        return lg_error(n, "transfer of %u vertices at %u bands (%.1f GiB) is not possible",
                        vertices, bands, (double)size / (1024.0 * 1024.0 * 1024.0));
    lg_part_spec parts[2] = {
        { .name = "transfer", .type = LG_PART_BUFFER, .buffer.size = (size_t)size },
        meta_spec(sizeof(lg_transfer_info)),
    };
    return lg_declare_composite(n, port, parts, 2);
}

int lg_transfer_publish(lg_node *n, uint32_t port, const lg_transfer_info *info)
{
    return publish_info(n, port, info, sizeof *info);
}

const lg_transfer *lg_transfer_get(lg_node *n, const lg_resource *res, lg_transfer *out)
{
    lg_resource_info ti;
    const lg_transfer_info *mi;
    memset(out, 0, sizeof *out);
    const lg_resource *t = consume(n, res, LG_KIND_TRANSFER, sizeof *mi, (const void **)&mi,
                                   "transfer", LG_PART_BUFFER, &ti);
    if (!t)
        return NULL;
    if (mi->bands < 1 || mi->bands > LG_SH_MAX_BANDS ||
        ti.buffer.size != (size_t)mi->vertices * 3 * mi->bands * mi->bands * sizeof(float)) {
        lg_error(n,
                 "the transfer vectors are inconsistent: %u vertices at %u bands in %zu "
                 "bytes",
                 mi->vertices, mi->bands, ti.buffer.size);
        return NULL;
    }
    out->info = *mi;
    out->n_coeffs = mi->bands * mi->bands;
    out->transfer = t;
    return out;
}

/* ---- froxels --------------------------------------------------------------------------------- */

int lg_froxel_declare(lg_node *n, uint32_t port, uint32_t width, uint32_t height, uint32_t depth,
                      lg_format format)
{
    if (format != LG_FORMAT_RGBA16F && format != LG_FORMAT_RGBA32F)
        return lg_error(n, "a froxel grid is rgba16f or rgba32f");
    lg_part_spec parts[2] = {
        { .name = "grid",
          .type = LG_PART_VOLUME,
          .volume = { .width = width, .height = height, .depth = depth, .format = format } },
        meta_spec(sizeof(lg_froxel_info)),
    };
    return lg_declare_composite(n, port, parts, 2);
}

int lg_froxel_publish(lg_node *n, uint32_t port, const lg_froxel_info *info)
{
    return publish_info(n, port, info, sizeof *info);
}

const lg_froxel *lg_froxel_get(lg_node *n, const lg_resource *res, lg_froxel *out)
{
    lg_resource_info gi;
    const lg_froxel_info *mi;
    memset(out, 0, sizeof *out);
    const lg_resource *g = consume(n, res, LG_KIND_FROXEL, sizeof *mi, (const void **)&mi, "grid",
                                   LG_PART_VOLUME, &gi);
    if (!g)
        return NULL;
    if (mi->width != gi.volume.width || mi->height != gi.volume.height ||
        mi->depth != gi.volume.depth) {
        lg_error(n,
                 "the froxel grid is inconsistent: info says %ux%ux%u, the volume is "
                 "%ux%ux%u",
                 mi->width, mi->height, mi->depth, gi.volume.width, gi.volume.height,
                 gi.volume.depth);
        return NULL;
    }
    out->info = *mi;
    out->grid = g;
    return out;
}
