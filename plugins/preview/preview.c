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

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"

#include "preview.frag.h"
#include "preview.vert.h"

enum { PV_BASE_COLOR = 0, PV_NORMALS, PV_DEPTH };
enum { PV_CULL_NONE = 0, PV_CULL_MATERIAL };

typedef struct pv_state {
    int mode, cull;
    int64_t camera;
    float background[3];
    uint32_t width, height;
    lg_gl_pass *pass; /* made on the first execute */
    lg_gl_uniform u_view_proj, u_view, u_mode, u_base_color, u_near_far;
} pv_state;

/* ---- create / prepare ------------------------------------------------------------------------ */

static int pv_create(lg_node *n)
{
    pv_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
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
    int rc = lg_output_size_nonempty(n, "width", "height", &st->width, &st->height);
    if (rc)
        return rc;
    lg_assert_input(n, 0);

    lg_image_desc d = { .width = st->width,
                        .height = st->height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = LG_IMAGE_DEPTH };
    rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    return lg_set_device(n, LG_DEVICE_GL);
}

/* ---- execute --------------------------------------------------------------------------------- */

/* The material's base colour, before the mesh's first draw. */
static int pv_on_mesh(lg_node *n, void *user, uint32_t mesh, GLuint *normals)
{
    (void)n, (void)normals;
    pv_state *st = user;
    const lg_scene *s = lg_gl_pass_scene(st->pass)->scene;
    lg_gl_set_vec3v(st->pass, st->u_base_color, s->materials[s->meshes[mesh].material].base_color);
    return 0;
}

static int pv_make_pass(lg_node *n, pv_state *st)
{
    static const lg_gl_shader_src src[2] = {
        { GL_VERTEX_SHADER, lg_src_preview_vert_file, lg_src_preview_vert },
        { GL_FRAGMENT_SHADER, lg_src_preview_frag_file, lg_src_preview_frag },
    };
    lg_gl_pass_desc d = { .name = "preview",
                          .stages = src,
                          .n_stages = 2,
                          .output = "out",
                          .colors = { GL_RGBA32F },
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true,
                          .cull = st->cull == PV_CULL_MATERIAL ? LG_GL_CULL_BACK : LG_GL_CULL_NONE,
                          .scene = LG_GL_SCENE_POSITIONS | LG_GL_SCENE_NORMALS };
    int rc = lg_gl_pass_create(n, &d, &st->pass);
    if (rc)
        return rc;
    st->u_view_proj = lg_gl_pass_uniform(st->pass, "u_view_proj");
    st->u_view = lg_gl_pass_uniform(st->pass, "u_view");
    st->u_mode = lg_gl_pass_uniform(st->pass, "u_mode");
    st->u_base_color = lg_gl_pass_uniform(st->pass, "u_base_color");
    st->u_near_far = lg_gl_pass_uniform(st->pass, "u_near_far");
    return 0;
}

static int pv_execute(lg_node *n, const lg_frame *frame)
{
    pv_state *st = n->user;
    const lg_resource *scene_res = lg_input(n, 0);
    const lg_scene *s = lg_scene_get(n, scene_res);
    if (!s)
        return LG_ERR_INVALID;
    lg_scene_view v;
    int rc = lg_scene_view_make(n, s, st->camera, st->width, st->height, &v);
    if (rc)
        return rc;
    if (!st->pass && (rc = pv_make_pass(n, st)))
        return rc;
    lg_gl_pass_set_time(st->pass, frame->time); /* an animated scene's pose (ABI 3.1) */
    if ((rc = lg_gl_pass_begin(st->pass, NULL)))
        return rc;
    const float bg[4] = { st->background[0], st->background[1], st->background[2], 1.0f };
    lg_gl_pass_clear_color(st->pass, 0, bg);
    lg_gl_pass_clear_depth(st->pass, 1.0f);
    lg_gl_set_mat4(st->pass, st->u_view_proj, v.view_proj);
    lg_gl_set_mat4(st->pass, st->u_view, v.view);
    lg_gl_set_int(st->pass, st->u_mode, st->mode);
    lg_gl_set_vec2(st->pass, st->u_near_far, v.znear, v.zfar);
    lg_gl_scene_draw d = { .on_mesh = pv_on_mesh, .user = st };
    rc = lg_gl_pass_end(st->pass, lg_gl_pass_draw_scene(st->pass, scene_res, &d));
    if (!rc) {
        const lg_scene_gl *sgl = lg_gl_pass_scene(st->pass);
        const lg_camera *c = &s->cameras[v.camera];
        lg_log(n, LG_LOG_INFO,
               "%u instances, %" PRIu64 " triangles, camera %u '%s', vertical fov %.4g deg, "
               "znear %.6g, zfar %.6g",
               sgl->count, sgl->triangles, v.camera, c->name ? c->name : "",
               (double)v.yfov * (180.0 / LG_PI), (double)v.znear, (double)v.zfar);
    }
    return rc;
}

static void pv_destroy(lg_node *n)
{
    pv_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->pass);
    free(st);
    n->user = NULL;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const char *const pv_modes[] = { "base_color", "normals", "depth", NULL };
static const char *const pv_culls[] = { "none", "material", NULL };

static const lg_param_desc pv_params[] = {
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = pv_modes,
      .doc = "base_color: the material's base colour, unlit; normals: world normal * 0.5 + "
             "0.5; depth: linear depth from znear (black) to zfar (white)" },
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
    { .key = "background",
      .type = LG_PARAM_COLOR,
      .def.v = { 0, 0, 0 },
      .min = 0,
      .max = 1e6,
      .doc = "colour where no surface is, linear RGB (alpha is 1 everywhere)" },
    { .key = "camera",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "index of the scene's camera to look through; -1 = the scene's active camera" },
    { .key = "cull",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = pv_culls,
      .doc = "none: draw both sides of every triangle; material: cull back faces unless the "
             "material is double-sided (glTF)" },
};
static const lg_port_desc pv_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene to draw" },
};
static const lg_port_desc pv_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
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
