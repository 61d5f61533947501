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
    memset(e, 0, sizeof *e);
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
