/* plugins/embree_common: the Embree scene of an lg_scene (lg_embree.h). */
#include "lg_embree.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void lg_embree_on_error(void *user, enum RTCError code, const char *str)
{
    lg_embree *e = user;
    if (!e->error[0])
        snprintf(e->error, sizeof e->error, "Embree error %d: %s", (int)code, str ? str : "");
}

void lg_embree_free(lg_embree *e)
{
    if (e->scene)
        rtcReleaseScene(e->scene);
    if (e->dev)
        rtcReleaseDevice(e->dev);
    free(e->masks);
    memset(e, 0, sizeof *e);
}

/* ---- alpha masks ----------------------------------------------------------------------------- */

/* What one masked instance's filter reads (its geometry's user pointer). */
typedef struct lg_embree_mask {
    const lg_scene *s;
    const lg_mesh *mesh;
} lg_embree_mask;

/* The texture coordinates the mask of `mp` reads on mesh `me`: set 1 when the reference
 * names it and the mesh has it, else set 0 (the SDK's rule, lg_texture_ref_uv); NULL when
 * the mesh has neither. */
static const float *mask_texcoords(const lg_mesh *me, const lg_material_maps *mp)
{
    if (mp->base_color.texcoord == 1 && me->texcoords1)
        return me->texcoords1;
    return me->texcoords;
}

bool lg_embree_mesh_masked(const lg_scene *s, const lg_mesh *me)
{
    if (!s || !me || me->material >= s->n_materials)
        return false;
    const lg_material *m = &s->materials[me->material];
    const lg_material_maps *mp = lg_material_maps_of(m);
    if (mp->alpha_mode != LG_ALPHA_MASK && mp->alpha_mode != LG_ALPHA_BLEND)
        return false;
    /* a factor below the cutoff removes the whole surface; a texture can remove parts of
     * it where the mesh has the coordinates it reads (without them: opaque) */
    if (!(m->base_color[3] >= mp->alpha_cutoff))
        return true;
    return mp->base_color.texture >= 0 && mask_texcoords(me, mp) != NULL;
}

bool lg_embree_covers(const lg_scene *s, const lg_mesh *me, uint32_t prim, float u, float v)
{
    if (!s || !me || me->material >= s->n_materials)
        return true;
    const lg_material *m = &s->materials[me->material];
    const lg_material_maps *mp = lg_material_maps_of(m);
    if (mp->alpha_mode != LG_ALPHA_MASK && mp->alpha_mode != LG_ALPHA_BLEND)
        return true;
    float alpha = m->base_color[3];
    const float *tc = mask_texcoords(me, mp);
    if (mp->base_color.texture >= 0) {
        if (!tc)
            return true; /* no coordinates to read the mask with: opaque (the loader warns) */
        if (!me->indices || prim >= me->n_indices / 3)
            return true;
        const uint32_t *ix = me->indices + 3 * (size_t)prim;
        if (ix[0] >= me->n_vertices || ix[1] >= me->n_vertices || ix[2] >= me->n_vertices)
            return true;
        float w0 = 1.0f - u - v, uv[2], st[2], c[4];
        for (int k = 0; k < 2; k++)
            uv[k] = w0 * tc[2 * (size_t)ix[0] + k] + u * tc[2 * (size_t)ix[1] + k] +
                    v * tc[2 * (size_t)ix[2] + k];
        /* uv is already the set the reference reads: pass it as both sets */
        lg_texture_ref_uv(&mp->base_color, uv, uv, st);
        lg_scene_texture_sample(s, &mp->base_color, st, true, c);
        alpha *= c[3];
    }
    return alpha >= mp->alpha_cutoff;
}

/* The intersection and occlusion filter of a masked instance: a hit where the surface has
 * no coverage is rejected (valid = 0), and Embree goes on to the next one along the ray. The
 * ray's tfar is left alone (a rejected hit must not shorten it). */
static void lg_embree_mask_filter(const struct RTCFilterFunctionNArguments *args)
{
    const lg_embree_mask *mk = args->geometryUserPtr;
    unsigned N = args->N;
    /* RTCHitN is N-wide structure of arrays: Ng xyz, u, v, primID, geomID, instID
     * (rtcore_ray.h's RTCHitN_* accessors, which are C++ only) */
    const float *hf = (const float *)args->hit;
    const unsigned *hu = (const unsigned *)args->hit;
    for (unsigned i = 0; i < N; i++) {
        if (args->valid[i] == 0)
            continue;
        if (!lg_embree_covers(mk->s, mk->mesh, hu[5 * N + i], hf[3 * N + i], hf[4 * N + i]))
            args->valid[i] = 0;
    }
}

int lg_embree_make(lg_node *n, const lg_scene *s, lg_embree *e)
{
    memset(e, 0, sizeof *e);
    char cfg[64];
    snprintf(cfg, sizeof cfg, "threads=%u", lg_cpu_workers(n));
    e->dev = rtcNewDevice(cfg);
    if (!e->dev)
        return lg_error(n, "Embree: no device (rtcNewDevice failed: error %d)",
                        (int)rtcGetDeviceError(NULL));
    rtcSetDeviceErrorFunction(e->dev, lg_embree_on_error, e);
    if (rtcGetDeviceProperty(e->dev, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED))
        return lg_error(n, "this Embree library was built with backface culling: single-sided "
                           "triangles would let light through from behind; use an Embree built "
                           "without EMBREE_BACKFACE_CULLING");
    e->scene = rtcNewScene(e->dev);
    rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
    e->masks = calloc(s->n_instances ? s->n_instances : 1, sizeof(lg_embree_mask));
    if (!e->masks)
        return lg_error_code(n, LG_ERR_NOMEM, "Embree: out of memory for %u instances",
                             s->n_instances);
    bool filters = rtcGetDeviceProperty(e->dev, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED);
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t i = 0; i < s->n_instances; i++) {
        const lg_instance *in = &s->instances[i];
        if (in->mesh >= s->n_meshes)
            return lg_error(n, "instance %u names mesh %u of %u", i, in->mesh, s->n_meshes);
        const lg_mesh *me = &s->meshes[in->mesh];
        const char *name = me->name ? me->name : "";
        uint32_t nt = me->n_indices / 3;
        if (nt == 0 || me->n_vertices == 0)
            continue;
        if (!me->positions || !me->indices)
            return lg_error(n, "mesh %u '%s' has no %s", in->mesh, name,
                            me->positions ? "indices" : "positions");
        RTCGeometry g = rtcNewGeometry(e->dev, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                            3 * sizeof(float), me->n_vertices);
        unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                               3 * sizeof(unsigned), nt);
        if (!vb || !ib) {
            rtcReleaseGeometry(g);
            return lg_error_code(n, LG_ERR_NOMEM, "Embree: out of memory for instance %u (%s)", i,
                                 e->error[0] ? e->error : "no buffer");
        }
        /* the model matrix in double, rounded once to float (as the raster's vertices) */
        const float *m = in->model;
        for (uint32_t v = 0; v < me->n_vertices; v++) {
            const float *p = me->positions + 3 * (size_t)v;
            for (int r = 0; r < 3; r++) {
                double w = (double)m[r] * p[0] + (double)m[4 + r] * p[1] + (double)m[8 + r] * p[2] +
                           (double)m[12 + r];
                if (!isfinite(w)) {
                    rtcReleaseGeometry(g);
                    return lg_error(n,
                                    "mesh %u '%s' vertex %u (instance %u): its world "
                                    "position is not finite",
                                    in->mesh, name, v, i);
                }
                vb[3 * (size_t)v + r] = (float)w;
                lo[r] = fmin(lo[r], w);
                hi[r] = fmax(hi[r], w);
            }
        }
        for (uint32_t t = 0; t < nt * 3; t++) {
            if (me->indices[t] >= me->n_vertices) {
                rtcReleaseGeometry(g);
                return lg_error(n,
                                "mesh %u '%s': index %u (triangle %u) is %u, past its %u "
                                "vertices",
                                in->mesh, name, t, t / 3, me->indices[t], me->n_vertices);
            }
            ib[t] = me->indices[t];
        }
        e->bytes += (size_t)me->n_vertices * 12 + (size_t)nt * 12;
        if (lg_embree_mesh_masked(s, me)) {
            if (!filters) {
                rtcReleaseGeometry(g);
                return lg_error(n,
                                "mesh %u '%s' (instance %u) is alpha-masked, and this Embree "
                                "library was built without filter functions "
                                "(EMBREE_FILTER_FUNCTION): its gaps cannot let rays through",
                                in->mesh, name, i);
            }
            lg_embree_mask *mk = (lg_embree_mask *)e->masks + i;
            mk->s = s;
            mk->mesh = me;
            rtcSetGeometryUserData(g, mk);
            rtcSetGeometryIntersectFilterFunction(g, lg_embree_mask_filter);
            rtcSetGeometryOccludedFilterFunction(g, lg_embree_mask_filter);
            e->n_masked++;
        }
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(e->scene, g, i);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(e->scene);
    if (e->error[0])
        return lg_error(n, "building the Embree scene: %s", e->error);
    for (int c = 0; c < 3; c++)
        if (hi[c] >= lo[c])
            e->extent = fmax(e->extent, hi[c] - lo[c]);
    return 0;
}

int lg_embree_make_at(lg_node *n, const lg_scene *s, double time, lg_embree *e)
{
    if (!lg_scene_is_animated(s))
        return lg_embree_make(n, s, e);
    memset(e, 0, sizeof *e);
    lg_instance *posed = malloc(((size_t)s->n_instances + 1) * sizeof *posed);
    if (!posed)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u instances)", s->n_instances);
    int rc = lg_scene_pose(n, s, time, posed);
    if (!rc) {
        lg_scene at = *s; /* a shallow copy: only the instances differ */
        at.instances = posed;
        rc = lg_embree_make(n, &at, e);
    }
    free(posed);
    return rc;
}
