/*
 * The preview plugin: the scene rasterised unlit through the GL device, so that what a
 * scene node loaded can be checked by eye and in tests before any lighting exists.
 *
 *   preview   scene -> image (rgba32f + depth): base colour, world normals or linear depth
 *
 * Since ABI 3.1 the base colour is the material's factor times its base colour texture
 * (shaders/common/material.glsl), alpha-masked texels are no surface, and `wireframe`
 * draws the triangles' edges over the shaded surface (a geometry stage).
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
#include "preview_wire.geom.h"

enum { PV_BASE_COLOR = 0, PV_NORMALS, PV_DEPTH };
enum { PV_CULL_NONE = 0, PV_CULL_MATERIAL };

typedef struct pv_state {
    int mode, cull, filter;
    int64_t camera;
    float background[3];
    float anisotropy;
    float wire_width, wire_color[3];
    bool per_frame;
    uint32_t width, height;
    lg_gl_pass *pass; /* made on the first execute */
    lg_gl_uniform u_view_proj, u_view, u_mode, u_near_far, u_viewport, u_wire_width, u_wire_color;
    lg_gl_material_binds mat;
    const lg_resource *scene_res; /* during a draw, for on_mesh */
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
    st->filter = lg_param_enum(n, "filter");
    st->anisotropy = (float)lg_param_float(n, "anisotropy");
    st->wire_width = (float)lg_param_float(n, "wireframe");
    st->per_frame = lg_param_bool(n, "per_frame");
    const lg_value *wc = lg_param(n, "wire_color");
    for (int i = 0; i < 3; i++)
        st->wire_color[i] = wc ? (float)wc->v[i] : 0.0f;
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
    if (st->per_frame)
        lg_set_per_frame(n, true);
    return lg_set_device(n, LG_DEVICE_GL);
}

/* ---- execute --------------------------------------------------------------------------------- */

/* The material (its factors, textures and alpha mode), before the mesh's first draw. */
static int pv_on_mesh(lg_node *n, void *user, uint32_t mesh, GLuint *normals)
{
    (void)n, (void)normals;
    pv_state *st = user;
    const lg_scene *s = lg_gl_pass_scene(st->pass)->scene;
    lg_gl_material_opts o = { .filter = (lg_gl_material_filter)st->filter,
                              .max_anisotropy = st->anisotropy };
    return lg_gl_pass_bind_material(st->pass, &st->mat, st->scene_res, s->meshes[mesh].material,
                                    &o);
}

static int pv_make_pass(lg_node *n, pv_state *st)
{
    static const lg_gl_shader_src src[2] = {
        { GL_VERTEX_SHADER, lg_src_preview_vert_file, lg_src_preview_vert },
        { GL_FRAGMENT_SHADER, lg_src_preview_frag_file, lg_src_preview_frag },
    };
    static const lg_gl_shader_src wire_src[3] = {
        { GL_VERTEX_SHADER, lg_src_preview_vert_file, lg_src_preview_vert },
        { GL_GEOMETRY_SHADER, lg_src_preview_wire_geom_file, lg_src_preview_wire_geom },
        { GL_FRAGMENT_SHADER, lg_src_preview_frag_file, lg_src_preview_frag },
    };
    bool wire = st->wire_width > 0.0f;
    lg_gl_pass_desc d = { .name = "preview",
                          .stages = wire ? wire_src : src,
                          .n_stages = wire ? 3 : 2,
                          .defines = wire ? "#define LG_WIREFRAME 1\n" : NULL,
                          .output = "out",
                          .colors = { GL_RGBA32F },
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true,
                          .cull = st->cull == PV_CULL_MATERIAL ? LG_GL_CULL_BACK : LG_GL_CULL_NONE,
                          .scene = LG_GL_SCENE_POSITIONS | LG_GL_SCENE_NORMALS |
                                   LG_GL_SCENE_TEXCOORDS };
    int rc = lg_gl_pass_create(n, &d, &st->pass);
    if (rc)
        return rc;
    st->u_view_proj = lg_gl_pass_uniform(st->pass, "u_view_proj");
    st->u_view = lg_gl_pass_uniform(st->pass, "u_view");
    st->u_mode = lg_gl_pass_uniform(st->pass, "u_mode");
    st->u_near_far = lg_gl_pass_uniform(st->pass, "u_near_far");
    if (wire) {
        st->u_viewport = lg_gl_pass_uniform(st->pass, "u_viewport");
        st->u_wire_width = lg_gl_pass_uniform(st->pass, "u_wire_width");
        st->u_wire_color = lg_gl_pass_uniform(st->pass, "u_wire_color");
    }
    lg_gl_pass_material_binds(st->pass, &st->mat);
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
    /* an animated camera at this frame's time (ABI 3.1; the instances: set_time below) */
    lg_scene at;
    int rc = lg_scene_at(n, s, frame->time, &at);
    if (rc)
        return rc;
    rc = lg_scene_view_make(n, &at, st->camera, st->width, st->height, &v);
    lg_scene_at_free(s, &at);
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
    if (st->wire_width > 0.0f) {
        lg_gl_set_vec2(st->pass, st->u_viewport, (float)st->width, (float)st->height);
        lg_gl_set_float(st->pass, st->u_wire_width, st->wire_width);
        lg_gl_set_vec3v(st->pass, st->u_wire_color, st->wire_color);
    }
    st->scene_res = scene_res;
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
static const char *const pv_filters[] = { "file", "nearest", "bilinear", "trilinear", NULL };

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
    { .key = "filter",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = pv_filters,
      .doc = "how textures are sampled: file: each texture's glTF sampler (default linear / "
             "trilinear); nearest or bilinear: level 0 only; trilinear: the mip chain. The "
             "file's wrap modes are kept" },
    { .key = "anisotropy",
      .type = LG_PARAM_FLOAT,
      .def.f = 16,
      .min = 1,
      .max = 16,
      .doc = "most anisotropic samples for mip-mapped textures (1 = off), at most the "
             "device's maximum (GL_MAX_TEXTURE_MAX_ANISOTROPY)" },
    { .key = "wireframe",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 64,
      .doc = "0: off; else the triangles' edges drawn over the surface, this many pixels "
             "wide (antialiased over one pixel)" },
    { .key = "wire_color",
      .type = LG_PARAM_COLOR,
      .def.v = { 0, 0, 0 },
      .min = 0,
      .max = 1e6,
      .doc = "colour of the wireframe's lines, linear RGB" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "render again on every frame (--frames), for timing; the result is the same" },
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
