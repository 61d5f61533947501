/*
 * The preview plugin: the scene rasterised unlit through the GL device, so that what a
 * scene node loaded can be checked by eye and in tests before any lighting exists.
 *
 *   preview   scene -> image (rgba32f + depth): base colour, world normals or linear depth
 *
 * One pass: every instance of every mesh, one instanced draw per mesh (per mesh and
 * handedness when culling), the instances' matrices in a storage buffer. README.md gives
 * the ports, the parameters and the conventions (depth, culling, aspect ratio).
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/math.h"
#include "lightgraph/scene.h"

#include "preview.frag.h"
#include "preview.vert.h"

enum { PV_BASE_COLOR = 0, PV_NORMALS, PV_DEPTH };
enum { PV_CULL_NONE = 0, PV_CULL_MATERIAL };

/* Uniform locations (shaders/preview/preview.vert and .frag). */
enum { U_VIEW_PROJ = 0, U_VIEW, U_FIRST, U_MODE, U_BASE_COLOR, U_NEAR_FAR };

/* One instance in the storage buffer: std430 layout of lg_preview_instance. */
typedef struct pv_gpu_instance {
    float model[16];
    float normal[16]; /* the 3x3 normal matrix in the upper-left, column-major */
} pv_gpu_instance;

typedef struct pv_state {
    int mode, cull;
    int64_t camera;
    float background[3];
    uint32_t width, height;
    GLuint program;
} pv_state;

/* The projection a preview uses, after the rules of README.md ("Camera"). */
typedef struct pv_view {
    float view[16], proj[16], view_proj[16];
    float znear, zfar, yfov;
    uint32_t camera;
} pv_view;

/* ---- create / prepare ------------------------------------------------------------------ */

static int pv_create(lg_node *n)
{
    pv_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    n->user = st;
    st->mode = lg_param_enum(n, "mode");
    st->cull = lg_param_enum(n, "cull");
    st->camera = lg_param_int(n, "camera");
    const lg_value *bg = lg_param(n, "background");
    for (int i = 0; i < 3; i++)
        st->background[i] = bg ? (float)bg->v[i] : 0.0f;
    return 0;
}

static int pv_prepare(lg_node *n)
{
    pv_state *st = n->user;
    uint32_t rw = 0, rh = 0;
    n->host->render_size(n, &rw, &rh);
    int64_t w = lg_param_int(n, "width"), h = lg_param_int(n, "height");
    st->width = w > 0 ? (uint32_t)w : rw;
    st->height = h > 0 ? (uint32_t)h : rh;
    if (st->width == 0 || st->height == 0)
        return lg_error(n, "output size %ux%u: width and height must be > 0", st->width,
                        st->height);

    lg_resource_info info;
    const lg_resource *in = lg_input(n, 0);
    if (!in || lg_describe(in, &info, n) != 0)
        return lg_error(n, "input 'scene' is not connected");
    if (info.kind != LG_KIND_SCENE)
        return lg_error(n, "input 'scene' is not a scene");

    lg_image_desc d = { .width = st->width, .height = st->height, .format = LG_FORMAT_RGBA32F,
                        .flags = LG_IMAGE_DEPTH };
    int rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    return lg_set_device(n, LG_DEVICE_GL);
}

/* ---- camera ------------------------------------------------------------------------------ */

static bool pv_finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

/* The farthest point of the scene's bounds along the view axis (view space depth), or a
 * negative value when the bounds are empty or behind the camera. */
static float pv_bounds_far(const lg_scene *s, const float view[16])
{
    const float *lo = s->bounds_min, *hi = s->bounds_max;
    if (!pv_finite3(lo) || !pv_finite3(hi) || lo[0] > hi[0] || lo[1] > hi[1] || lo[2] > hi[2])
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

static int pv_make_view(lg_node *n, const pv_state *st, const lg_scene *s, pv_view *v)
{
    if (s->n_cameras == 0 || !s->cameras)
        return lg_error(n, "the scene has no camera (a scene node must provide one)");
    uint32_t ci;
    if (st->camera < 0) {
        if (s->camera >= s->n_cameras)
            return lg_error(n, "the scene's active camera %u does not exist (it has %u)",
                            s->camera, s->n_cameras);
        ci = s->camera;
    } else if ((uint64_t)st->camera >= s->n_cameras) {
        return lg_error(n, "camera %" PRId64 " does not exist: the scene has %u camera%s "
                           "(0..%u; -1 = the active one)",
                        st->camera, s->n_cameras, s->n_cameras == 1 ? "" : "s",
                        s->n_cameras - 1);
    } else {
        ci = (uint32_t)st->camera;
    }
    const lg_camera *c = &s->cameras[ci];
    const char *cname = c->name ? c->name : "";
    if (!pv_finite3(c->position) || !pv_finite3(c->target) || !pv_finite3(c->up) ||
        !isfinite(c->yfov) || !isfinite(c->znear) || !isfinite(c->zfar) || !isfinite(c->aspect))
        return lg_error(n, "camera %u '%s' has a value that is not finite", ci, cname);
    if (!(c->yfov > 0.0f && c->yfov < 3.1f))
        return lg_error(n, "camera %u '%s': vertical field of view %g rad is outside (0, 3.1)",
                        ci, cname, (double)c->yfov);
    if (c->znear < 0.0f || c->zfar < 0.0f || (c->zfar > 0.0f && c->zfar <= c->znear))
        return lg_error(n, "camera %u '%s': znear %g and zfar %g do not make a depth range "
                           "(0 <= znear < zfar, or zfar 0 for 'from the bounds')",
                        ci, cname, (double)c->znear, (double)c->zfar);
    lg_vec3 eye = lg_v3(c->position[0], c->position[1], c->position[2]);
    lg_vec3 target = lg_v3(c->target[0], c->target[1], c->target[2]);
    if (lg_v3_length(lg_v3_sub(target, eye)) < 1e-12f)
        return lg_error(n, "camera %u '%s': position and target are the same point", ci, cname);
    lg_m4_look_at(v->view, eye, target, lg_v3(c->up[0], c->up[1], c->up[2]));

    /* aspect: the output's; when the camera has its own and the output is narrower, keep
     * the camera's horizontal field of view so that nothing it frames is cut off */
    float aspect = (float)st->width / (float)st->height;
    float yfov = c->yfov;
    if (c->aspect > 0.0f && aspect < c->aspect)
        yfov = 2.0f * atanf(tanf(0.5f * yfov) * c->aspect / aspect);
    if (yfov > 3.1f)
        yfov = 3.1f;

    float zfar = c->zfar, znear = c->znear;
    if (zfar == 0.0f) {
        float far = pv_bounds_far(s, v->view);
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
    return 0;
}

/* ---- scene checks -------------------------------------------------------------------------- */

static const char *pv_mesh_name(const lg_mesh *m)
{
    return m->name ? m->name : "";
}

/* What the GL pass relies on, checked once per drawn mesh: arrays present, counts a draw
 * call can take, every index in range (an out-of-range index would read outside the GPU
 * buffer). */
static int pv_check_mesh(lg_node *n, const lg_scene *s, uint32_t mi)
{
    const lg_mesh *m = &s->meshes[mi];
    if (!m->positions || !m->indices || !m->normals)
        return lg_error(n, "mesh %u '%s' lacks its %s array", mi, pv_mesh_name(m),
                        !m->positions ? "positions" : !m->indices ? "indices" : "normals");
    if (m->n_indices % 3 != 0)
        return lg_error(n, "mesh %u '%s': %u indices is not a whole number of triangles", mi,
                        pv_mesh_name(m), m->n_indices);
    if (m->n_indices > (uint32_t)INT32_MAX)
        return lg_error_code(n, LG_ERR_UNSUPPORTED,
                             "mesh %u '%s': %u indices is more than one GL draw takes", mi,
                             pv_mesh_name(m), m->n_indices);
    if (m->material >= s->n_materials)
        return lg_error(n, "mesh %u '%s' uses material %u, the scene has %u", mi,
                        pv_mesh_name(m), m->material, s->n_materials);
    for (uint32_t i = 0; i < m->n_indices; i++)
        if (m->indices[i] >= m->n_vertices)
            return lg_error(n, "mesh %u '%s': index %u (entry %u) is out of range: the mesh "
                               "has %u vertices",
                            mi, pv_mesh_name(m), m->indices[i], i, m->n_vertices);
    return 0;
}

static float pv_det3(const float m[16])
{
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

/* An instance as the draw loop sees it. */
typedef struct pv_item {
    uint32_t mesh;
    uint32_t mirrored; /* the model matrix has a negative determinant */
    uint32_t instance;
} pv_item;

static int pv_item_cmp(const void *a, const void *b)
{
    const pv_item *x = a, *y = b;
    if (x->mesh != y->mesh)
        return x->mesh < y->mesh ? -1 : 1;
    if (x->mirrored != y->mirrored)
        return x->mirrored < y->mirrored ? -1 : 1;
    return x->instance < y->instance ? -1 : x->instance > y->instance;
}

/* The instances to draw, sorted by mesh and handedness; meshes without triangles are
 * left out. *count receives how many. */
static int pv_collect(lg_node *n, const lg_scene *s, pv_item **out, uint32_t *count)
{
    *out = NULL;
    *count = 0;
    if (s->n_instances == 0)
        return 0;
    pv_item *items = malloc((size_t)s->n_instances * sizeof *items);
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
            if ((rc = pv_check_mesh(n, s, in->mesh)))
                break;
            checked[in->mesh] = 1;
        }
        for (int j = 0; j < 16; j++)
            if (!isfinite(in->model[j])) {
                rc = lg_error(n, "instance %u (mesh %u '%s'): its matrix is not finite", i,
                              in->mesh, pv_mesh_name(m));
                break;
            }
        items[k].mesh = in->mesh;
        items[k].mirrored = pv_det3(in->model) < 0.0f;
        items[k].instance = i;
        k++;
    }
    free(checked);
    if (rc) {
        free(items);
        return rc;
    }
    qsort(items, k, sizeof *items, pv_item_cmp);
    *out = items;
    *count = k;
    return 0;
}

/* ---- execute --------------------------------------------------------------------------------- */

/* Leaves the bindings as the GL state contract wants them (docs/devices.md). */
static void pv_unbind(const lg_gl *gl)
{
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    gl->UseProgram(0);
    gl->BindVertexArray(0);
    gl->BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
}

typedef struct pv_gl_objects {
    GLuint fbo, vao, instances;
} pv_gl_objects;

static void pv_gl_free(const lg_gl *gl, pv_gl_objects *o)
{
    if (o->fbo)
        gl->DeleteFramebuffers(1, &o->fbo);
    if (o->vao)
        gl->DeleteVertexArrays(1, &o->vao);
    if (o->instances)
        gl->DeleteBuffers(1, &o->instances);
    memset(o, 0, sizeof *o);
}

static int pv_draw(lg_node *n, pv_state *st, const lg_gl *gl, const lg_scene *s,
                   const lg_resource *scene_res, const pv_view *v, const pv_item *items,
                   uint32_t count, pv_gl_objects *o)
{
    int rc;
    /* the instances' matrices, in draw order */
    if (count) {
        size_t bytes = (size_t)count * sizeof(pv_gpu_instance);
        pv_gpu_instance *gi = calloc(count, sizeof *gi);
        if (!gi)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu bytes of instances)",
                                 bytes);
        for (uint32_t i = 0; i < count; i++) {
            const lg_instance *in = &s->instances[items[i].instance];
            memcpy(gi[i].model, in->model, sizeof gi[i].model);
            for (int c = 0; c < 3; c++)
                for (int r = 0; r < 3; r++)
                    gi[i].normal[c * 4 + r] = in->normal_matrix[c * 3 + r];
            gi[i].normal[15] = 1.0f;
        }
        gl->CreateBuffers(1, &o->instances);
        gl->NamedBufferStorage(o->instances, (GLsizeiptr)bytes, gi, 0);
        free(gi);
        if ((rc = lg_gl_check(n, "preview: uploading the instance matrices")))
            return rc;
    }

    gl->CreateVertexArrays(1, &o->vao);
    gl->EnableVertexArrayAttrib(o->vao, 0);
    gl->VertexArrayAttribFormat(o->vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    gl->VertexArrayAttribBinding(o->vao, 0, 0);
    gl->EnableVertexArrayAttrib(o->vao, 1);
    gl->VertexArrayAttribFormat(o->vao, 1, 3, GL_FLOAT, GL_FALSE, 0);
    gl->VertexArrayAttribBinding(o->vao, 1, 1);

    gl->BindFramebuffer(GL_FRAMEBUFFER, o->fbo);
    gl->Viewport(0, 0, (GLsizei)st->width, (GLsizei)st->height);
    gl->ColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->DepthMask(GL_TRUE);
    gl->Disable(GL_BLEND);
    gl->Disable(GL_SCISSOR_TEST);
    const float bg[4] = { st->background[0], st->background[1], st->background[2], 1.0f };
    const float far = 1.0f;
    gl->ClearNamedFramebufferfv(o->fbo, GL_COLOR, 0, bg);
    gl->ClearNamedFramebufferfv(o->fbo, GL_DEPTH, 0, &far);
    gl->Enable(GL_DEPTH_TEST);
    gl->DepthFunc(GL_LESS);
    gl->DepthRangef(0.0f, 1.0f);
    gl->Disable(GL_CULL_FACE);
    gl->CullFace(GL_BACK);

    gl->UseProgram(st->program);
    gl->BindVertexArray(o->vao);
    gl->UniformMatrix4fv(U_VIEW_PROJ, 1, GL_FALSE, v->view_proj);
    gl->UniformMatrix4fv(U_VIEW, 1, GL_FALSE, v->view);
    gl->Uniform1i(U_MODE, st->mode);
    gl->Uniform2f(U_NEAR_FAR, v->znear, v->zfar);

    GLint max_block = 0, align = 0;
    gl->GetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    gl->GetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    if (align < 1)
        align = 1;
    const size_t isz = sizeof(pv_gpu_instance);
    /* instances one storage-buffer binding can hold, leaving room for the alignment */
    size_t per_bind = (size_t)max_block / isz;
    size_t slack = ((size_t)align + isz - 1) / isz;
    per_bind = per_bind > slack + 1 ? per_bind - slack : 1;

    uint32_t bound_mesh = UINT32_MAX;
    for (uint32_t a = 0; a < count;) {
        uint32_t b = a;
        while (b < count && items[b].mesh == items[a].mesh &&
               (st->cull == PV_CULL_NONE || items[b].mirrored == items[a].mirrored))
            b++;
        uint32_t mi = items[a].mesh;
        const lg_mesh *m = &s->meshes[mi];
        if (mi != bound_mesh) {
            lg_mesh_gl mg;
            if ((rc = lg_scene_mesh_gl(n, scene_res, mi, &mg)))
                return rc;
            gl->VertexArrayVertexBuffer(o->vao, 0, mg.positions, 0, 3 * sizeof(float));
            gl->VertexArrayVertexBuffer(o->vao, 1, mg.normals, 0, 3 * sizeof(float));
            gl->VertexArrayElementBuffer(o->vao, mg.indices);
            const lg_material *mat = &s->materials[m->material];
            gl->Uniform3f(U_BASE_COLOR, mat->base_color[0], mat->base_color[1],
                          mat->base_color[2]);
            if (st->cull == PV_CULL_MATERIAL && !mat->double_sided)
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
            gl->BindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, o->instances, (GLintptr)off,
                                (GLsizeiptr)((size_t)e * isz - off));
            gl->Uniform1i(U_FIRST, (GLint)(((size_t)i * isz - off) / isz));
            gl->DrawElementsInstanced(GL_TRIANGLES, (GLsizei)m->n_indices, GL_UNSIGNED_INT,
                                      NULL, (GLsizei)(e - i));
            i = e;
        }
        a = b;
    }
    return lg_gl_check(n, "preview: drawing the scene");
}

static int pv_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    pv_state *st = n->user;
    const lg_resource *scene_res = lg_input(n, 0);
    const lg_scene *s = lg_scene_get(n, scene_res);
    if (!s)
        return LG_ERR_INVALID;
    pv_view v;
    int rc = pv_make_view(n, st, s, &v);
    if (rc)
        return rc;
    pv_item *items = NULL;
    uint32_t count = 0;
    if ((rc = pv_collect(n, s, &items, &count)))
        return rc;

    const lg_gl *gl = lg_gl_get(n);
    if (!gl) {
        free(items);
        return LG_ERR_DEVICE;
    }
    if (!st->program) {
        lg_gl_shader_src src[2] = {
            { GL_VERTEX_SHADER, lg_src_preview_vert_file, lg_src_preview_vert },
            { GL_FRAGMENT_SHADER, lg_src_preview_frag_file, lg_src_preview_frag },
        };
        st->program = lg_gl_program(n, gl, src, 2, NULL);
        if (!st->program) {
            free(items);
            return LG_ERR_DEVICE;
        }
    }

    uint32_t tex = 0, depth = 0;
    if ((rc = lg_map_gl(n, lg_output(n, 0), LG_WRITE, &tex, &depth))) {
        free(items);
        return rc;
    }
    if (!depth) {
        free(items);
        return lg_error_code(n, LG_ERR_DEVICE, "the output has no GL depth texture");
    }

    pv_gl_objects o = { 0 };
    gl->CreateFramebuffers(1, &o.fbo);
    gl->NamedFramebufferTexture(o.fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    gl->NamedFramebufferTexture(o.fbo, GL_DEPTH_ATTACHMENT, depth, 0);
    gl->NamedFramebufferDrawBuffer(o.fbo, GL_COLOR_ATTACHMENT0);
    GLenum status = gl->CheckNamedFramebufferStatus(o.fbo, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        rc = lg_error_code(n, LG_ERR_DEVICE,
                           "preview: the framebuffer (rgba32f colour %ux%u, depth32f) is "
                           "incomplete: status 0x%04x",
                           st->width, st->height, (unsigned)status);
    } else {
        rc = pv_draw(n, st, gl, s, scene_res, &v, items, count, &o);
    }
    pv_unbind(gl);
    pv_gl_free(gl, &o);
    if (!rc) {
        uint64_t tris = 0;
        for (uint32_t i = 0; i < count; i++)
            tris += s->meshes[items[i].mesh].n_indices / 3;
        const lg_camera *c = &s->cameras[v.camera];
        lg_log(n, LG_LOG_INFO,
               "%u instances, %" PRIu64 " triangles, camera %u '%s', vertical fov %.4g deg, "
               "znear %.6g, zfar %.6g",
               count, tris, v.camera, c->name ? c->name : "", (double)v.yfov * (180.0 / 3.14159265358979323846),
               (double)v.znear, (double)v.zfar);
    }
    free(items);
    return rc ? rc : lg_gl_check(n, "preview: cleaning up");
}

static void pv_destroy(lg_node *n)
{
    pv_state *st = n->user;
    if (!st)
        return;
    if (st->program) {
        const lg_gl *gl = lg_gl_get(n);
        if (gl)
            gl->DeleteProgram(st->program);
    }
    free(st);
    n->user = NULL;
}

/* ---- the descriptor ----------------------------------------------------------------------- */

static const char *const pv_modes[] = { "base_color", "normals", "depth", NULL };
static const char *const pv_culls[] = { "none", "material", NULL };

static const lg_param_desc pv_params[] = {
    { .key = "mode", .type = LG_PARAM_ENUM, .def.e = 0, .enum_values = pv_modes,
      .doc = "base_color: the material's base colour, unlit; normals: world normal * 0.5 + "
             "0.5; depth: linear depth from znear (black) to zfar (white)" },
    { .key = "width", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 16384,
      .doc = "output width in pixels; 0 = the render size (--size)" },
    { .key = "height", .type = LG_PARAM_INT, .def.i = 0, .min = 0, .max = 16384,
      .doc = "output height in pixels; 0 = the render size (--size)" },
    { .key = "background", .type = LG_PARAM_COLOR, .def.v = { 0, 0, 0 }, .min = 0, .max = 1e6,
      .doc = "colour where no surface is, linear RGB (alpha is 1 everywhere)" },
    { .key = "camera", .type = LG_PARAM_INT, .def.i = -1, .min = -1, .max = 1e9,
      .doc = "index of the scene's camera to look through; -1 = the scene's active camera" },
    { .key = "cull", .type = LG_PARAM_ENUM, .def.e = 0, .enum_values = pv_culls,
      .doc = "none: draw both sides of every triangle; material: cull back faces unless the "
             "material is double-sided (glTF)" },
};
static const lg_port_desc pv_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene to draw" },
};
static const lg_port_desc pv_outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE,
      .doc = "rgba32f, upright, with a depth plane: GL window depth in [0, 1] (1 = nothing)" },
};

static const lg_node_type pv_types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "preview",
    .doc = "The scene rasterised unlit (base colour, normals or depth) on GL, with depth",
    LG_PARAMS(pv_params),
    LG_INPUTS(pv_inputs),
    LG_OUTPUTS(pv_outputs),
    .create = pv_create,
    .prepare = pv_prepare,
    .execute = pv_execute,
    .destroy = pv_destroy,
} };

LG_PLUGIN_DEFINE("preview", "1.0.0", "Unlit scene preview on GL (base colour, normals, depth)",
                 pv_types)
