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
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"

#include "preview.frag.h"
#include "preview.vert.h"

enum { PV_BASE_COLOR = 0, PV_NORMALS, PV_DEPTH };
enum { PV_CULL_NONE = 0, PV_CULL_MATERIAL };

/* Uniform locations (shaders/preview/preview.vert and .frag). */
enum { U_VIEW_PROJ = 0, U_VIEW, U_FIRST, U_MODE, U_BASE_COLOR, U_NEAR_FAR };

typedef struct pv_state {
    int mode, cull;
    int64_t camera;
    float background[3];
    uint32_t width, height;
    GLuint program;
} pv_state;

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
    lg_output_size(n, "width", "height", &st->width, &st->height);
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

typedef struct pv_draw_ctx {
    const lg_gl *gl;
    const lg_scene *s;
} pv_draw_ctx;

/* The material's base colour, before the mesh's first draw. */
static int pv_on_mesh(lg_node *n, void *user, uint32_t mesh, GLuint *normals)
{
    (void)n, (void)normals;
    const pv_draw_ctx *c = user;
    const lg_gl *gl = c->gl;
    const lg_scene *s = c->s;
    const lg_material *mat = &s->materials[s->meshes[mesh].material];
    gl->Uniform3f(U_BASE_COLOR, mat->base_color[0], mat->base_color[1], mat->base_color[2]);
    return 0;
}

static int pv_draw(lg_node *n, pv_state *st, const lg_gl *gl, const lg_scene_view *v,
                   lg_scene_gl *sgl, GLuint fbo)
{
    int rc;
    if ((rc = lg_scene_gl_upload(n, gl, sgl)))
        return rc;

    gl->BindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl->Viewport(0, 0, (GLsizei)st->width, (GLsizei)st->height);
    gl->ColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->DepthMask(GL_TRUE);
    gl->Disable(GL_BLEND);
    gl->Disable(GL_SCISSOR_TEST);
    const float bg[4] = { st->background[0], st->background[1], st->background[2], 1.0f };
    const float far = 1.0f;
    gl->ClearNamedFramebufferfv(fbo, GL_COLOR, 0, bg);
    gl->ClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &far);
    gl->Enable(GL_DEPTH_TEST);
    gl->DepthFunc(GL_LESS);
    gl->DepthRangef(0.0f, 1.0f);
    gl->Disable(GL_CULL_FACE);
    gl->CullFace(GL_BACK);

    gl->UseProgram(st->program);
    gl->UniformMatrix4fv(U_VIEW_PROJ, 1, GL_FALSE, v->view_proj);
    gl->UniformMatrix4fv(U_VIEW, 1, GL_FALSE, v->view);
    gl->Uniform1i(U_MODE, st->mode);
    gl->Uniform2f(U_NEAR_FAR, v->znear, v->zfar);

    pv_draw_ctx ctx = { gl, sgl->scene };
    lg_scene_gl_draw_desc d = { .program = st->program, .first_location = U_FIRST,
                                .cull_material = st->cull == PV_CULL_MATERIAL,
                                .on_mesh = pv_on_mesh, .user = &ctx };
    if ((rc = lg_scene_gl_draw(n, gl, sgl, &d)))
        return rc;
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
    lg_scene_view v;
    int rc = lg_scene_view_make(n, s, st->camera, st->width, st->height, &v);
    if (rc)
        return rc;
    lg_scene_gl *sgl = NULL;
    if ((rc = lg_scene_gl_create(n, scene_res, LG_SCENE_GL_NORMALS, &sgl)))
        return rc;

    const lg_gl *gl = lg_gl_get(n);
    if (!gl) {
        lg_scene_gl_destroy(NULL, sgl);
        return LG_ERR_DEVICE;
    }
    if (!st->program) {
        lg_gl_shader_src src[2] = {
            { GL_VERTEX_SHADER, lg_src_preview_vert_file, lg_src_preview_vert },
            { GL_FRAGMENT_SHADER, lg_src_preview_frag_file, lg_src_preview_frag },
        };
        st->program = lg_gl_program(n, gl, src, 2, NULL);
        if (!st->program) {
            lg_scene_gl_destroy(gl, sgl);
            return LG_ERR_DEVICE;
        }
    }

    uint32_t tex = 0, depth = 0;
    if ((rc = lg_map_gl(n, lg_output(n, 0), LG_WRITE, &tex, &depth))) {
        lg_scene_gl_destroy(gl, sgl);
        return rc;
    }
    if (!depth) {
        lg_scene_gl_destroy(gl, sgl);
        return lg_error_code(n, LG_ERR_DEVICE, "the output has no GL depth texture");
    }

    GLuint fbo = 0;
    gl->CreateFramebuffers(1, &fbo);
    gl->NamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    gl->NamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depth, 0);
    gl->NamedFramebufferDrawBuffer(fbo, GL_COLOR_ATTACHMENT0);
    GLenum status = gl->CheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        rc = lg_error_code(n, LG_ERR_DEVICE,
                           "preview: the framebuffer (rgba32f colour %ux%u, depth32f) is "
                           "incomplete: status 0x%04x",
                           st->width, st->height, (unsigned)status);
    } else {
        rc = pv_draw(n, st, gl, &v, sgl, fbo);
    }
    pv_unbind(gl);
    gl->DeleteFramebuffers(1, &fbo);
    if (!rc) {
        const lg_camera *c = &s->cameras[v.camera];
        lg_log(n, LG_LOG_INFO,
               "%u instances, %" PRIu64 " triangles, camera %u '%s', vertical fov %.4g deg, "
               "znear %.6g, zfar %.6g",
               sgl->count, sgl->triangles, v.camera, c->name ? c->name : "", (double)v.yfov * (180.0 / 3.14159265358979323846),
               (double)v.znear, (double)v.zfar);
    }
    lg_scene_gl_destroy(gl, sgl);
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
