/* Scene helpers of the SDK (lightgraph/scene.h). */
#include <string.h>

#include "lightgraph/scene.h"
#include "lightgraph/shadowmap.h"

const lg_scene *lg_scene_get(lg_node *n, const lg_resource *res)
{
    lg_resource_info info;
    if (!res || lg_describe(res, &info, n) != 0) {
        lg_error(n, "no scene: the input is not connected");
        return NULL;
    }
    if (info.kind != LG_KIND_SCENE) {
        lg_error(n, "expects a scene, got a resource of another kind");
        return NULL;
    }
    if (!info.payload) {
        lg_error(n, "the scene on this input has features but no scene data (%s)",
                 info.neutral ? "a gated node's neutral result"
                              : "its producer declared no lg_scene payload");
        return NULL;
    }
    const lg_scene *s = info.payload;
    if (s->struct_size < offsetof(lg_scene, reserved)) {
        lg_error(n,
                 "the scene was made by a plugin built for an incompatible SDK "
                 "(struct_size %zu)",
                 s->struct_size);
        return NULL;
    }
    return s;
}

void lg_scene_compute_features(lg_scene *s)
{
    lg_scene_features f;
    memset(&f, 0, sizeof f);
    for (uint32_t i = 0; i < s->n_instances; i++) {
        uint32_t m = s->instances[i].mesh;
        if (m < s->n_meshes) {
            f.triangles += s->meshes[m].n_indices / 3;
            f.vertices += s->meshes[m].n_vertices;
        }
    }
    for (uint32_t i = 0; i < s->n_lights; i++) {
        if (s->lights[i].type == LG_LIGHT_DIRECTIONAL)
            f.dir_lights++;
        else if (s->lights[i].type == LG_LIGHT_POINT)
            f.point_lights++;
        else
            f.other_lights++;
    }
    f.medium = s->medium.present && s->medium.density > 0;
    f.medium_density = s->medium.present ? s->medium.density : 0.0f;
    for (uint32_t i = 0; i < s->n_materials; i++)
        if (s->materials[i].ks > 0 &&
            (s->materials[i].os[0] > 0 || s->materials[i].os[1] > 0 || s->materials[i].os[2] > 0))
            f.specular = true;
    /* reflective: materials with a non-zero reflectivity that some instance draws */
    for (uint32_t i = 0; i < s->n_materials; i++) {
        const float *r = s->materials[i].reflectivity;
        if (!(r[0] > 0 || r[1] > 0 || r[2] > 0))
            continue;
        bool used = false;
        for (uint32_t k = 0; k < s->n_instances && !used; k++) {
            uint32_t m = s->instances[k].mesh;
            used = m < s->n_meshes && s->meshes[m].material == i;
        }
        f.reflective_materials += used;
    }
    f.probe = s->features.probe;
    s->features = f;
}

/* Slots: four arrays per mesh. */
enum { SLOT_POS = 0, SLOT_NRM, SLOT_UV, SLOT_IDX, SLOTS_PER_MESH };

static int mesh_of(lg_node *n, const lg_resource *res, uint32_t mesh, const lg_scene **s,
                   const lg_resource **owner)
{
    *s = lg_scene_get(n, res);
    if (!*s)
        return LG_ERR_INVALID;
    if (mesh >= (*s)->n_meshes)
        return lg_error(n, "mesh %u does not exist (the scene has %u)", mesh, (*s)->n_meshes);
    *owner = (*s)->geometry ? (*s)->geometry : res;
    return 0;
}

/* One GPU copy of one array: payload_gl_buffer or payload_cl_buffer. */
typedef int (*upload_fn)(lg_node *n, const lg_resource *owner, uint32_t slot, const void *data,
                         size_t size, void *out);

static int upload_gl(lg_node *n, const lg_resource *owner, uint32_t slot, const void *data,
                     size_t size, void *out)
{
    return lg_payload_gl_buffer(n, owner, slot, data, size, (uint32_t *)out);
}

static int upload_cl(lg_node *n, const lg_resource *owner, uint32_t slot, const void *data,
                     size_t size, void *out)
{
    return lg_payload_cl_buffer(n, owner, slot, data, size, (void **)out);
}

/* The mesh's arrays through `up`, into the four result slots (texcoords only if any). */
static int upload_mesh(lg_node *n, const lg_resource *res, uint32_t mesh, upload_fn up, void *pos,
                       void *nrm, void *uv, void *idx)
{
    const lg_scene *s;
    const lg_resource *owner = NULL;
    int rc = mesh_of(n, res, mesh, &s, &owner);
    if (rc)
        return rc;
    const lg_mesh *m = &s->meshes[mesh];
    uint32_t base = mesh * SLOTS_PER_MESH;
    size_t nv = m->n_vertices;
    if ((rc = up(n, owner, base + SLOT_POS, m->positions, nv * 3 * sizeof(float), pos)) ||
        (rc = up(n, owner, base + SLOT_NRM, m->normals, nv * 3 * sizeof(float), nrm)) ||
        (rc = up(n, owner, base + SLOT_IDX, m->indices, m->n_indices * sizeof(uint32_t), idx)))
        return rc;
    if (m->texcoords)
        rc = up(n, owner, base + SLOT_UV, m->texcoords, nv * 2 * sizeof(float), uv);
    return rc;
}

int lg_scene_mesh_gl(lg_node *n, const lg_resource *res, uint32_t mesh, lg_mesh_gl *out)
{
    memset(out, 0, sizeof *out);
    return upload_mesh(n, res, mesh, upload_gl, &out->positions, &out->normals, &out->texcoords,
                       &out->indices);
}

int lg_scene_mesh_cl(lg_node *n, const lg_resource *res, uint32_t mesh, lg_mesh_cl *out)
{
    memset(out, 0, sizeof *out);
    return upload_mesh(n, res, mesh, upload_cl, &out->positions, &out->normals, &out->texcoords,
                       &out->indices);
}
