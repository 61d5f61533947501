/* lg_scene_view_make, lg_scene_gl_* (lightgraph/scene_gl.h): the scene rasterisation shared
 * by the raster plugins. */
#include "lightgraph/scene_gl.h"

#include <inttypes.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/plugin.h"

/* ---- camera ---------------------------------------------------------------------------------- */

static bool finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* The farthest point of the scene's bounds along the view axis (view space depth), or a
 * negative value when the bounds are empty or behind the camera. */
static float bounds_far(const lg_scene *s, const float view[16])
{
    const float *lo = s->bounds_min, *hi = s->bounds_max;
    if (!finite3(lo) || !finite3(hi) || lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2])
        return -1.0f;
    float far = -1.0f;
    for (int k = 0; k < 8; k++) {
        lg_vec3 c = lg_v3(k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]);
        float d = -lg_m4_point(view, c).z;
        if (d > far)
            far = d;
    }
    return far;
}

int lg_scene_view_make(lg_node *n, const lg_scene *s, int64_t camera, uint32_t width,
                       uint32_t height, lg_scene_view *v)
{
    if (width == 0 || height == 0)
        return lg_error(n, "output size %ux%u: width and height must be > 0", width, height);
    if (s->n_cameras == 0 || !s->cameras)
        return lg_error(n, "the scene has no camera (a scene node must provide one)");
    uint32_t ci;
    if (camera < 0) {
        if (s->camera >= s->n_cameras)
            return lg_error(n, "the scene's active camera %u does not exist (it has %u)", s->camera,
                            s->n_cameras);
        ci = s->camera;
    } else if ((uint64_t)camera >= s->n_cameras) {
        return lg_error(n,
                        "camera %" PRId64 " does not exist: the scene has %u camera%s "
                        "(0..%u; -1 = the active one)",
                        camera, s->n_cameras, s->n_cameras == 1 ? "" : "s", s->n_cameras - 1);
    } else {
        ci = (uint32_t)camera;
    }
    const lg_camera *c = &s->cameras[ci];
    const char *cname = c->name ? c->name : "";
    if (!finite3(c->position) || !finite3(c->target) || !finite3(c->up) || !isfinite(c->yfov) ||
        !isfinite(c->znear) || !isfinite(c->zfar) || !isfinite(c->aspect))
        return lg_error(n, "camera %u '%s' has a value that is not finite", ci, cname);
    if (!(c->yfov > 0.0f && c->yfov < 3.1f))
        return lg_error(n, "camera %u '%s': vertical field of view %g rad is outside (0, 3.1)", ci,
                        cname, (double)c->yfov);
    if (c->znear < 0.0f || c->zfar < 0.0f || (c->zfar > 0.0f && c->zfar <= c->znear))
        return lg_error(n,
                        "camera %u '%s': znear %g and zfar %g do not make a depth range "
                        "(0 <= znear < zfar, or zfar 0 for 'from the bounds')",
                        ci, cname, (double)c->znear, (double)c->zfar);
    lg_vec3 eye = lg_v3(c->position[0], c->position[1], c->position[2]);
    lg_vec3 target = lg_v3(c->target[0], c->target[1], c->target[2]);
    if (lg_v3_length(lg_v3_sub(target, eye)) < 1e-12f)
        return lg_error(n, "camera %u '%s': position and target are the same point", ci, cname);
    memset(v, 0, sizeof *v); /* the reserved fields */
    lg_m4_look_at(v->view, eye, target, lg_v3(c->up[0], c->up[1], c->up[2]));

    /* aspect: the output's; when the camera has its own and the output is narrower, keep
     * the camera's horizontal field of view so that nothing it frames is cut off */
    float aspect = (float)width / (float)height;
    float yfov = c->yfov;
    if (c->aspect > 0.0f && aspect < c->aspect)
        yfov = 2.0f * atanf(tanf(0.5f * yfov) * c->aspect / aspect);
    if (yfov > 3.1f)
        yfov = 3.1f;

    float zfar = c->zfar, znear = c->znear;
    if (zfar == 0.0f) {
        float far = bounds_far(s, v->view);
        /* a margin, so that the farthest corner is not clipped by rounding */
        zfar = far > 0.0f ? far * 1.01f + 1e-6f : 0.0f;
        if (znear > 0.0f && zfar < 2.0f * znear)
            zfar = 2.0f * znear;
        if (zfar == 0.0f)
            zfar = 100.0f; /* nothing in front of the camera: any range will do */
    }
    if (znear == 0.0f)
        znear = zfar * 1e-4f;

    lg_m4_perspective(v->proj, yfov, aspect, znear, zfar);
    /* texel row 0 is the image's top row (docs/sdk.md, "Row order"): flip Y in clip space,
     * which also turns counter-clockwise front faces clockwise in window space */
    for (int col = 0; col < 4; col++)
        v->proj[col * 4 + 1] = -v->proj[col * 4 + 1];
    lg_m4_mul(v->view_proj, v->proj, v->view);
    v->znear = znear;
    v->zfar = zfar;
    v->yfov = yfov;
    v->camera = ci;
    v->eye = eye;
    v->forward = lg_v3_normalize_or(lg_v3_sub(target, eye), lg_v3(0, 0, -1));
    return 0;
}

/* ---- instances ------------------------------------------------------------------------------- */

static const char *mesh_name(const lg_mesh *m)
{
    return m->name ? m->name : "";
}

/* What the GL pass relies on, checked once per drawn mesh: arrays present, counts a draw
 * call can take, every index in range (an out-of-range index would read outside the GPU
 * buffer), a material that exists. */
static int check_mesh(lg_node *n, const lg_scene *s, uint32_t mi, bool normals)
{
    const lg_mesh *m = &s->meshes[mi];
    if (!m->positions || !m->indices || (normals && !m->normals))
        return lg_error(n, "mesh %u '%s' lacks its %s array", mi, mesh_name(m),
                        !m->positions ? "positions"
                        : !m->indices ? "indices"
                                      : "normals");
    if (m->n_indices % 3 != 0)
        return lg_error(n, "mesh %u '%s': %u indices is not a whole number of triangles", mi,
                        mesh_name(m), m->n_indices);
    if (m->n_indices > (uint32_t)INT32_MAX)
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "mesh %u '%s': %u indices is more than one GL draw takes", mi,
                             mesh_name(m), m->n_indices);
    if (m->material >= s->n_materials)
        return lg_error(n, "mesh %u '%s' uses material %u, the scene has %u", mi, mesh_name(m),
                        m->material, s->n_materials);
    for (uint32_t i = 0; i < m->n_indices; i++)
        if (m->indices[i] >= m->n_vertices)
            return lg_error(n,
                            "mesh %u '%s': index %u (entry %u) is out of range: the mesh "
                            "has %u vertices",
                            mi, mesh_name(m), m->indices[i], i, m->n_vertices);
    return 0;
}

static float det3(const float m[16])
{
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

static int item_cmp(const void *a, const void *b)
{
    const lg_scene_gl_item *x = a, *y = b;
    if (x->mesh != y->mesh)
        return x->mesh < y->mesh ? -1 : 1;
    if (x->mirrored != y->mirrored)
        return x->mirrored < y->mirrored ? -1 : 1;
    return x->instance < y->instance ? -1 : x->instance > y->instance;
}

/* The instances to draw, sorted by mesh and handedness; meshes without triangles are
 * left out. */
static int collect(lg_node *n, lg_scene_gl *sgl)
{
    const lg_scene *s = sgl->scene;
    if (s->n_instances == 0)
        return 0;
    lg_scene_gl_item *items = malloc((size_t)s->n_instances * sizeof *items);
    unsigned char *checked = calloc(s->n_meshes ? s->n_meshes : 1, 1);
    if (!items || !checked) {
        free(items);
        free(checked);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u instances)", s->n_instances);
    }
    uint32_t k = 0;
    int rc = 0;
    for (uint32_t i = 0; i < s->n_instances && !rc; i++) {
        const lg_instance *in = &s->instances[i];
        if (in->mesh >= s->n_meshes) {
            rc = lg_error(n, "instance %u refers to mesh %u, the scene has %u", i, in->mesh,
                          s->n_meshes);
            break;
        }
        const lg_mesh *m = &s->meshes[in->mesh];
        if (m->n_indices == 0 || m->n_vertices == 0)
            continue;
        if (!checked[in->mesh]) {
            if ((rc = check_mesh(n, s, in->mesh, sgl->flags & LG_SCENE_GL_NORMALS)))
                break;
            checked[in->mesh] = 1;
        }
        for (int j = 0; j < 16 && !rc; j++)
            if (!isfinite(in->model[j]))
                rc = lg_error(n, "instance %u (mesh %u '%s'): its matrix is not finite", i,
                              in->mesh, mesh_name(m));
        items[k].mesh = in->mesh;
        items[k].mirrored = det3(in->model) < 0.0f;
        items[k].instance = i;
        items[k].reserved = 0;
        k++;
    }
    free(checked);
    if (rc) {
        free(items);
        return rc;
    }
    qsort(items, k, sizeof *items, item_cmp);
    uint64_t tris = 0;
    for (uint32_t i = 0; i < k; i++)
        tris += s->meshes[items[i].mesh].n_indices / 3;
    sgl->items = items;
    sgl->count = k;
    sgl->triangles = tris;
    return 0;
}

int lg_scene_gl_create(lg_node *n, const lg_resource *scene_res, unsigned flags, lg_scene_gl **out)
{
    *out = NULL;
    if (flags & ~(unsigned)LG_SCENE_GL_NORMALS)
        return lg_error(n, "lg_scene_gl_create: unknown flags 0x%x", flags);
    const lg_scene *s = lg_scene_get(n, scene_res);
    if (!s)
        return LG_ERR_INVALID;
    lg_scene_gl *sgl = calloc(1, sizeof *sgl);
    if (!sgl)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    sgl->scene = s;
    sgl->res = scene_res;
    sgl->flags = flags;
    sgl->record_size = (flags & LG_SCENE_GL_NORMALS ? 32 : 16) * sizeof(float);
    int rc = collect(n, sgl);
    if (rc) {
        free(sgl);
        return rc;
    }
    *out = sgl;
    return 0;
}

/* ---- GL -------------------------------------------------------------------------------------- */

/* The storage-buffer records of the drawn items from `insts` (the scene's instances, or
 * their pose at some time); malloc'd, NULL when out of memory. */
static float *make_records(const lg_scene_gl *sgl, const lg_instance *insts)
{
    bool normals = sgl->flags & LG_SCENE_GL_NORMALS;
    const size_t rec = sgl->record_size / sizeof(float);
    float *recs = calloc(sgl->count, sgl->record_size);
    if (!recs)
        return NULL;
    for (uint32_t i = 0; i < sgl->count; i++) {
        const lg_instance *in = &insts[sgl->items[i].instance];
        float *r = recs + (size_t)i * rec;
        memcpy(r, in->model, 16 * sizeof(float));
        if (normals) {
            for (int c = 0; c < 3; c++)
                for (int k = 0; k < 3; k++)
                    r[16 + c * 4 + k] = in->normal_matrix[c * 3 + k];
            r[16 + 15] = 1.0f;
        }
    }
    return recs;
}

int lg_scene_gl_upload(lg_node *n, const lg_gl *gl, lg_scene_gl *sgl)
{
    if (sgl->vao)
        return lg_error(n, "lg_scene_gl_upload: called twice");
    bool normals = sgl->flags & LG_SCENE_GL_NORMALS;
    if (sgl->count) {
        size_t bytes = (size_t)sgl->count * sgl->record_size;
        float *recs = make_records(sgl, sgl->scene->instances);
        if (!recs)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu bytes of instances)", bytes);
        gl->CreateBuffers(1, &sgl->instances);
        /* an animated scene's records are filled again at each pose (lg_scene_gl_pose) */
        gl->NamedBufferStorage(sgl->instances, (GLsizeiptr)bytes, recs,
                               lg_scene_is_animated(sgl->scene) ? GL_DYNAMIC_STORAGE_BIT : 0);
        free(recs);
        int rc = lg_gl_check(n, "uploading the instance matrices");
        if (rc)
            return rc;
    }
    gl->CreateVertexArrays(1, &sgl->vao);
    gl->EnableVertexArrayAttrib(sgl->vao, 0);
    gl->VertexArrayAttribFormat(sgl->vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl->VertexArrayAttribBinding(sgl->vao, 0, 0);
    if (normals) {
        gl->EnableVertexArrayAttrib(sgl->vao, 1);
        gl->VertexArrayAttribFormat(sgl->vao, 1, 3, GL_FLOAT, GL_FALSE, 0);
        gl->VertexArrayAttribBinding(sgl->vao, 1, 1);
    }
    return 0;
}

int lg_scene_gl_pose(lg_node *n, const lg_gl *gl, lg_scene_gl *sgl, double time)
{
    const lg_scene *s = sgl->scene;
    if (!lg_scene_is_animated(s) || !sgl->count)
        return 0;
    if (!sgl->instances)
        return lg_error(n, "lg_scene_gl_pose: lg_scene_gl_upload was not called");
    lg_instance *posed = malloc((size_t)s->n_instances * sizeof *posed);
    if (!posed)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u instances)", s->n_instances);
    int rc = lg_scene_pose(n, s, time, posed);
    for (uint32_t i = 0; !rc && i < sgl->count; i++)
        for (int j = 0; j < 16 && !rc; j++)
            if (!isfinite(posed[sgl->items[i].instance].model[j]))
                rc = lg_error(n, "instance %u at time %g s: its matrix is not finite",
                              sgl->items[i].instance, time);
    float *recs = rc ? NULL : make_records(sgl, posed);
    free(posed);
    if (rc)
        return rc;
    if (!recs)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (instance records)");
    gl->NamedBufferSubData(sgl->instances, 0, (GLsizeiptr)((size_t)sgl->count * sgl->record_size),
                           recs);
    free(recs);
    return lg_gl_check(n, "posing the instance matrices");
}

int lg_scene_gl_draw(lg_node *n, const lg_gl *gl, const lg_scene_gl *sgl,
                     const lg_scene_gl_draw_desc *d)
{
    if (!sgl->vao)
        return lg_error(n, "lg_scene_gl_draw: lg_scene_gl_upload was not called");
    const lg_scene *s = sgl->scene;
    const lg_scene_gl_item *items = sgl->items;
    const uint32_t count = sgl->count;
    int rc;
    gl->BindVertexArray(sgl->vao);

    GLint max_block = 0, align = 0;
    gl->GetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    gl->GetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    if (align < 1)
        align = 1;
    const size_t isz = sgl->record_size;
    /* instances one storage-buffer binding can hold, leaving room for the alignment */
    size_t per_bind = (size_t)max_block / isz;
    size_t slack = ((size_t)align + isz - 1) / isz;
    per_bind = per_bind > slack + 1 ? per_bind - slack : 1;

    uint32_t bound_mesh = UINT32_MAX;
    for (uint32_t a = 0; a < count;) {
        uint32_t b = a;
        while (b < count && items[b].mesh == items[a].mesh &&
               (!d->cull_material || items[b].mirrored == items[a].mirrored))
            b++;
        uint32_t mi = items[a].mesh;
        const lg_mesh *m = &s->meshes[mi];
        if (mi != bound_mesh) {
            lg_mesh_gl mg;
            if ((rc = lg_scene_mesh_gl(n, sgl->res, mi, &mg)))
                return rc;
            GLuint nrm = mg.normals;
            if (d->on_mesh && (rc = d->on_mesh(n, d->user, mi, &nrm)))
                return rc;
            gl->VertexArrayVertexBuffer(sgl->vao, 0, mg.positions, 0, 3 * sizeof(float));
            if (sgl->flags & LG_SCENE_GL_NORMALS)
                gl->VertexArrayVertexBuffer(sgl->vao, 1, nrm, 0, 3 * sizeof(float));
            gl->VertexArrayElementBuffer(sgl->vao, mg.indices);
            /* a double-sided material's winding says nothing about which side faces out */
            if (d->cull_material && !s->materials[m->material].double_sided)
                gl->Enable(GL_CULL_FACE);
            else
                gl->Disable(GL_CULL_FACE);
            bound_mesh = mi;
        }
        /* with Y flipped, a counter-clockwise front face is clockwise on screen; a mirrored
         * instance flips it back (glTF: negative determinant reverses the winding) */
        gl->FrontFace(items[a].mirrored ? GL_CCW : GL_CW);
        for (uint32_t i = a; i < b;) {
            uint32_t e = (uint32_t)((size_t)(b - i) > per_bind ? i + per_bind : b);
            size_t off = (size_t)i * isz / (size_t)align * (size_t)align;
            gl->BindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, sgl->instances, (GLintptr)off,
                                (GLsizeiptr)((size_t)e * isz - off));
            gl->ProgramUniform1i(d->program, d->first_location,
                                 (GLint)(((size_t)i * isz - off) / isz));
            if (d->on_batch)
                d->on_batch(d->user, i);
            gl->DrawElementsInstanced(GL_TRIANGLES, (GLsizei)m->n_indices, GL_UNSIGNED_INT, NULL,
                                      (GLsizei)(e - i));
            i = e;
        }
        a = b;
    }
    return 0;
}

void lg_scene_gl_destroy(const lg_gl *gl, lg_scene_gl *sgl)
{
    if (!sgl)
        return;
    if (gl && sgl->vao)
        gl->DeleteVertexArrays(1, &sgl->vao);
    if (gl && sgl->instances)
        gl->DeleteBuffers(1, &sgl->instances);
    free(sgl->items);
    free(sgl);
}
