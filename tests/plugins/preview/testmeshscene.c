/*
 * Test plugin "testmeshscene": small scenes built in memory, with known geometry, colours
 * and cameras, so that the preview node can be tested without a file loader; and a node
 * that turns an image's depth plane into pixels, so that tests can read it from a file.
 *
 *   test_mesh_scene   -> scene (layout chosen by a parameter, see tm_layouts)
 *   test_depth_plane  image -> image: (d, d, d, 1) with d the input's depth plane
 *
 * Every scene has two cameras: camera 0 (the active one) at (0, 0, 5) looking at the
 * origin with +Y up, and camera 1 at the same place looking the other way (at nothing).
 */
#include <math.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"

#include "common/testscene.h"

/* ---- test_mesh_scene ------------------------------------------------------------------------- */

static const char *const tm_layouts[] = {
    "quad_fill",      /* a 20 x 20 quad at z = 0 facing +Z: fills the view */
    "cube",           /* the unit cube (edge 1) at the origin, 24 vertices with face normals */
    "cube_rot45",     /* the same rotated 45 degrees about +Y */
    "cube_stretched", /* the rotated cube then scaled (2, 1, 1): S R, normals need R S^-1 */
    "two_depths",     /* quad x in [-2, -0.2] at z = 0, quad x in [0.2, 2] at z = -3 */
    "instanced",      /* one unit quad mesh, instances centred at (-1.5, 0, 0), (1.5, 0.5, 0) */
    "upper_right",    /* a quad x, y in [0.5, 1.5] at z = 0 facing +Z */
    "back_quad",      /* a 2 x 2 quad at z = 0 facing -Z (away from camera 0) */
    "mirrored",       /* a 2 x 2 quad facing +Z through an instance with scale (-1, 1, 1) */
    "far",            /* a 2 x 2 quad at z = -45 (50 from the camera) */
    "empty",          /* no instances, empty bounds */
    "bad_index",      /* a mesh with an index past its vertices */
    "bad_instance",   /* an instance of a mesh that does not exist */
    "no_camera",      /* no camera */
    NULL,
};
enum {
    TM_QUAD_FILL,
    TM_CUBE,
    TM_CUBE_ROT45,
    TM_CUBE_STRETCHED,
    TM_TWO_DEPTHS,
    TM_INSTANCED,
    TM_UPPER_RIGHT,
    TM_BACK_QUAD,
    TM_MIRRORED,
    TM_FAR,
    TM_EMPTY,
    TM_BAD_INDEX,
    TM_BAD_INSTANCE,
    TM_NO_CAMERA,
};

static void tm_quad(lg_ts_builder *b, lg_vec3 c, lg_vec3 u, lg_vec3 v)
{
    lg_ts_quad(b, &c, u, v, NULL);
}

static void tm_translate(float m[16], float x, float y, float z)
{
    lg_m4_identity(m);
    m[12] = x, m[13] = y, m[14] = z;
}

static int tm_scene_prepare(lg_node *n)
{
    lg_ts_builder *b = lg_ts_begin("test_mesh_scene");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    int layout = lg_param_enum(n, "layout");
    const lg_value *col = lg_param(n, "color");

    lg_material *mat = lg_ts_material(b, "test");
    mat->kd = 1.0f;
    for (int k = 0; k < 3; k++)
        mat->base_color[k] = mat->od[k] = col ? (float)col->v[k] : 0.5f;
    mat->base_color[3] = 1.0f;
    mat->roughness = 1.0f;
    mat->double_sided = lg_param_bool(n, "double_sided");

    static const char *const cam_names[2] = { "front", "away" };
    for (int i = 0; i < 2 && layout != TM_NO_CAMERA; i++) {
        lg_camera *c =
            lg_ts_camera(b, cam_names[i], lg_v3(0, 0, 5), lg_v3(0, 0, i == 0 ? 0.0f : 10.0f),
                         lg_v3(0, 1, 0), (float)(lg_param_float(n, "yfov") * LG_PI / 180.0),
                         (float)lg_param_float(n, "znear"), (float)lg_param_float(n, "zfar"));
        c->aspect = (float)lg_param_float(n, "camera_aspect");
    }

    float m[16];
    lg_m4_identity(m);
    if (layout != TM_EMPTY)
        lg_ts_mesh(b, "test mesh#0", 0);
    switch (layout) {
    case TM_QUAD_FILL:
        tm_quad(b, lg_v3(0, 0, 0), lg_v3(10, 0, 0), lg_v3(0, 10, 0));
        lg_ts_instance(b, 0, m);
        break;
    case TM_CUBE:
    case TM_CUBE_ROT45:
    case TM_CUBE_STRETCHED: {
        lg_ts_unit_cube(b, false);
        if (layout != TM_CUBE) {
            float a = LG_PIF / 4.0f;
            m[0] = cosf(a), m[2] = -sinf(a); /* column 0: R_y x axis */
            m[8] = sinf(a), m[10] = cosf(a); /* column 2: R_y z axis */
        }
        if (layout == TM_CUBE_STRETCHED) {
            float sx[16];
            lg_m4_identity(sx);
            sx[0] = 2.0f;
            lg_m4_mul(m, sx, m);
        }
        lg_ts_instance(b, 0, m);
        break;
    }
    case TM_TWO_DEPTHS:
        tm_quad(b, lg_v3(-1.1f, 0, 0), lg_v3(0.9f, 0, 0), lg_v3(0, 1, 0));
        tm_quad(b, lg_v3(1.1f, 0, -3), lg_v3(0.9f, 0, 0), lg_v3(0, 1, 0));
        lg_ts_instance(b, 0, m);
        break;
    case TM_INSTANCED:
        tm_quad(b, lg_v3(0, 0, 0), lg_v3(0.5f, 0, 0), lg_v3(0, 0.5f, 0));
        tm_translate(m, -1.5f, 0, 0);
        lg_ts_instance(b, 0, m);
        tm_translate(m, 1.5f, 0.5f, 0);
        lg_ts_instance(b, 0, m);
        break;
    case TM_UPPER_RIGHT:
        tm_quad(b, lg_v3(1, 1, 0), lg_v3(0.5f, 0, 0), lg_v3(0, 0.5f, 0));
        lg_ts_instance(b, 0, m);
        break;
    case TM_BACK_QUAD:
        tm_quad(b, lg_v3(0, 0, 0), lg_v3(-1, 0, 0), lg_v3(0, 1, 0));
        lg_ts_instance(b, 0, m);
        break;
    case TM_MIRRORED:
        tm_quad(b, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        m[0] = -1.0f;
        lg_ts_instance(b, 0, m);
        break;
    case TM_FAR:
        tm_quad(b, lg_v3(0, 0, -45), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        lg_ts_instance(b, 0, m);
        break;
    case TM_EMPTY: break;
    case TM_BAD_INDEX:
        tm_quad(b, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        lg_ts_indices(b)[4] = 9; /* the mesh has 4 vertices */
        lg_ts_instance(b, 0, m);
        break;
    case TM_BAD_INSTANCE:
        tm_quad(b, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        lg_ts_instance(b, 3, m); /* there is one mesh */
        break;
    case TM_NO_CAMERA:
        tm_quad(b, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        lg_ts_instance(b, 0, m);
        break;
    }
    return lg_ts_publish(n, 0, b);
}

static int tm_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- test_depth_plane ------------------------------------------------------------------------ */

static int dp_prepare(lg_node *n)
{
    lg_resource_info info;
    const lg_resource *in = lg_input(n, 0);
    if (!in || lg_describe(in, &info, n) || info.kind != LG_KIND_IMAGE)
        return lg_error(n, "input 'image' is not an image");
    if (!(info.image.flags & LG_IMAGE_DEPTH))
        return lg_error(n, "input 'image' has no depth plane");
    lg_image_desc d = { .width = info.image.width,
                        .height = info.image.height,
                        .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int dp_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_resource_info info;
    lg_describe(lg_input(n, 0), &info, n);
    lg_cpu_view vi, vo;
    int rc;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &vi)) ||
        (rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &vo)))
        return rc;
    if (!vi.depth)
        return lg_error(n, "the input's depth plane is not mapped");
    for (uint32_t y = 0; y < info.image.height; y++)
        for (uint32_t x = 0; x < info.image.width; x++) {
            float d = vi.depth[(size_t)y * vi.row_pixels + x];
            float *o = (float *)vo.pixels + ((size_t)y * vo.row_pixels + x) * 4;
            o[0] = o[1] = o[2] = d;
            o[3] = 1.0f;
        }
    return 0;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const lg_param_desc tm_params[] = {
    { .key = "layout",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = tm_layouts,
      .doc = "which scene (testmeshscene.c lists them)" },
    { .key = "color",
      .type = LG_PARAM_COLOR,
      .def.v = { 0.2, 0.5, 0.8 },
      .doc = "base colour of the one material" },
    { .key = "double_sided",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "the material's double_sided flag" },
    { .key = "yfov",
      .type = LG_PARAM_FLOAT,
      .def.f = 60,
      .min = 1,
      .max = 170,
      .doc = "the cameras' vertical field of view, degrees" },
    { .key = "znear",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e6,
      .doc = "the cameras' znear" },
    { .key = "zfar",
      .type = LG_PARAM_FLOAT,
      .def.f = 20,
      .min = 0,
      .max = 1e6,
      .doc = "the cameras' zfar; 0 = from the bounds" },
    { .key = "camera_aspect",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 100,
      .doc = "the cameras' aspect ratio; 0 = the output's" },
};
static const lg_port_desc tm_out[] = { { .name = "scene", .kind = LG_KIND_SCENE } };
static const lg_port_desc dp_in[] = { { .name = "image", .kind = LG_KIND_IMAGE } };
static const lg_port_desc dp_out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_mesh_scene",
        .doc = "A small scene built in memory for the preview tests",
        LG_PARAMS(tm_params),
        LG_OUTPUTS(tm_out),
        .prepare = tm_scene_prepare,
        .execute = tm_nothing,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_depth_plane",
        .doc = "An image's depth plane as grey pixels (d, d, d, 1)",
        LG_INPUTS(dp_in),
        LG_OUTPUTS(dp_out),
        .prepare = dp_prepare,
        .execute = dp_execute,
    },
};

LG_PLUGIN_DEFINE("testmeshscene", "1.0.0", "In-memory scenes for the preview tests", types)
