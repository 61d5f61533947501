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
#include <stdlib.h>
#include <string.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/vecmath.h"
#include "lightgraph/scene.h"

#include "common/testscene.h"

/* ---- test_mesh_scene ------------------------------------------------------------------- */

static const char *const tm_layouts[] = {
    "quad_fill",    /* a 20 x 20 quad at z = 0 facing +Z: fills the view */
    "cube",         /* the unit cube (edge 1) at the origin, 24 vertices with face normals */
    "cube_rot45",   /* the same rotated 45 degrees about +Y */
    "cube_stretched", /* the rotated cube then scaled (2, 1, 1): S R, normals need R S^-1 */
    "two_depths",   /* quad x in [-2, -0.2] at z = 0, quad x in [0.2, 2] at z = -3 */
    "instanced",    /* one unit quad mesh, instances centred at (-1.5, 0, 0), (1.5, 0.5, 0) */
    "upper_right",  /* a quad x, y in [0.5, 1.5] at z = 0 facing +Z */
    "back_quad",    /* a 2 x 2 quad at z = 0 facing -Z (away from camera 0) */
    "mirrored",     /* a 2 x 2 quad facing +Z through an instance with scale (-1, 1, 1) */
    "far",          /* a 2 x 2 quad at z = -45 (50 from the camera) */
    "empty",        /* no instances, empty bounds */
    "bad_index",    /* a mesh with an index past its vertices */
    "bad_instance", /* an instance of a mesh that does not exist */
    "no_camera",    /* no camera */
    NULL,
};
enum {
    TM_QUAD_FILL, TM_CUBE, TM_CUBE_ROT45, TM_CUBE_STRETCHED, TM_TWO_DEPTHS, TM_INSTANCED, TM_UPPER_RIGHT,
    TM_BACK_QUAD, TM_MIRRORED, TM_FAR, TM_EMPTY, TM_BAD_INDEX, TM_BAD_INSTANCE, TM_NO_CAMERA,
};

#define TM_MAX_MESHES 4
#define TM_MAX_INSTANCES 4
#define TM_MAX_VERTS 64
#define TM_MAX_INDICES 96

typedef struct tm_mesh_data {
    float pos[TM_MAX_VERTS * 3], nrm[TM_MAX_VERTS * 3];
    uint32_t idx[TM_MAX_INDICES];
} tm_mesh_data;

/* One allocation holds the scene and everything it points to. */
typedef struct tm_scene {
    lg_scene s;
    lg_mesh meshes[TM_MAX_MESHES];
    tm_mesh_data data[TM_MAX_MESHES];
    lg_instance instances[TM_MAX_INSTANCES];
    lg_material material;
    lg_camera cameras[2];
} tm_scene;

static void tm_free(void *p)
{
    free(p);
}

/* Appends a quad c +- u +- v whose front (counter-clockwise) side faces u x v. */
static void tm_quad(tm_scene *t, uint32_t mi, lg_vec3 c, lg_vec3 u, lg_vec3 v)
{
    lg_mesh *m = &t->meshes[mi];
    tm_mesh_data *d = &t->data[mi];
    lg_vec3 nrm = lg_v3_normalize_or(lg_v3_cross(u, v), lg_v3(0, 0, 1));
    static const float su[4] = { -1, 1, 1, -1 }, sv[4] = { -1, -1, 1, 1 };
    uint32_t base = m->n_vertices;
    for (int k = 0; k < 4; k++) {
        lg_vec3 p = lg_v3_add(c, lg_v3_add(lg_v3_scale(u, su[k]), lg_v3_scale(v, sv[k])));
        float *pp = d->pos + (base + k) * 3, *nn = d->nrm + (base + k) * 3;
        pp[0] = p.x, pp[1] = p.y, pp[2] = p.z;
        nn[0] = nrm.x, nn[1] = nrm.y, nn[2] = nrm.z;
    }
    static const uint32_t tri[6] = { 0, 1, 2, 0, 2, 3 };
    for (int k = 0; k < 6; k++)
        d->idx[m->n_indices++] = base + tri[k];
    m->n_vertices += 4;
}

static void tm_cube(tm_scene *t, uint32_t mi)
{
    static const float f[6][3][3] = {
        { { 1, 0, 0 }, { 0, 0, -1 }, { 0, 1, 0 } },  { { -1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },
        { { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, -1 } },  { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } },
        { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 } },   { { 0, 0, -1 }, { -1, 0, 0 }, { 0, 1, 0 } },
    };
    for (int i = 0; i < 6; i++)
        tm_quad(t, mi, lg_v3_scale(lg_v3(f[i][0][0], f[i][0][1], f[i][0][2]), 0.5f),
                lg_v3_scale(lg_v3(f[i][1][0], f[i][1][1], f[i][1][2]), 0.5f),
                lg_v3_scale(lg_v3(f[i][2][0], f[i][2][1], f[i][2][2]), 0.5f));
}

static void tm_instance(tm_scene *t, uint32_t mesh, const float model[16])
{
    lg_instance *in = &t->instances[t->s.n_instances++];
    in->mesh = mesh;
    memcpy(in->model, model, sizeof in->model);
    lg_m4_normal_matrix(in->normal_matrix, model);
}

static void tm_translate(float m[16], float x, float y, float z)
{
    lg_m4_identity(m);
    m[12] = x, m[13] = y, m[14] = z;
}

static tm_scene *tm_build(lg_node *n)
{
    tm_scene *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    int layout = lg_param_enum(n, "layout");
    const lg_value *col = lg_param(n, "color");

    t->s.struct_size = sizeof t->s;
    t->s.source = "test_mesh_scene";
    t->s.meshes = t->meshes;
    t->s.instances = t->instances;
    t->s.materials = &t->material;
    t->s.n_materials = 1;
    t->s.cameras = t->cameras;
    t->s.n_cameras = layout == TM_NO_CAMERA ? 0 : 2;
    t->material.name = "test";
    t->material.kd = 1.0f;
    for (int k = 0; k < 3; k++)
        t->material.base_color[k] = t->material.od[k] = col ? (float)col->v[k] : 0.5f;
    t->material.base_color[3] = 1.0f;
    t->material.roughness = 1.0f;
    t->material.double_sided = lg_param_bool(n, "double_sided");

    static const char *const cam_names[2] = { "front", "away" };
    for (int i = 0; i < 2; i++) {
        lg_camera *c = &t->cameras[i];
        c->name = cam_names[i];
        c->position[2] = 5.0f;
        c->target[2] = i == 0 ? 0.0f : 10.0f;
        c->up[1] = 1.0f;
        c->yfov = (float)(lg_param_float(n, "yfov") * LG_PI / 180.0);
        c->znear = (float)lg_param_float(n, "znear");
        c->zfar = (float)lg_param_float(n, "zfar");
        c->aspect = (float)lg_param_float(n, "camera_aspect");
    }

    float m[16];
    lg_m4_identity(m);
    t->s.n_meshes = 1;
    switch (layout) {
    case TM_QUAD_FILL:
        tm_quad(t, 0, lg_v3(0, 0, 0), lg_v3(10, 0, 0), lg_v3(0, 10, 0));
        tm_instance(t, 0, m);
        break;
    case TM_CUBE:
    case TM_CUBE_ROT45:
    case TM_CUBE_STRETCHED: {
        tm_cube(t, 0);
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
        tm_instance(t, 0, m);
        break;
    }
    case TM_TWO_DEPTHS:
        tm_quad(t, 0, lg_v3(-1.1f, 0, 0), lg_v3(0.9f, 0, 0), lg_v3(0, 1, 0));
        tm_quad(t, 0, lg_v3(1.1f, 0, -3), lg_v3(0.9f, 0, 0), lg_v3(0, 1, 0));
        tm_instance(t, 0, m);
        break;
    case TM_INSTANCED:
        tm_quad(t, 0, lg_v3(0, 0, 0), lg_v3(0.5f, 0, 0), lg_v3(0, 0.5f, 0));
        tm_translate(m, -1.5f, 0, 0);
        tm_instance(t, 0, m);
        tm_translate(m, 1.5f, 0.5f, 0);
        tm_instance(t, 0, m);
        break;
    case TM_UPPER_RIGHT:
        tm_quad(t, 0, lg_v3(1, 1, 0), lg_v3(0.5f, 0, 0), lg_v3(0, 0.5f, 0));
        tm_instance(t, 0, m);
        break;
    case TM_BACK_QUAD:
        tm_quad(t, 0, lg_v3(0, 0, 0), lg_v3(-1, 0, 0), lg_v3(0, 1, 0));
        tm_instance(t, 0, m);
        break;
    case TM_MIRRORED:
        tm_quad(t, 0, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        m[0] = -1.0f;
        tm_instance(t, 0, m);
        break;
    case TM_FAR:
        tm_quad(t, 0, lg_v3(0, 0, -45), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        tm_instance(t, 0, m);
        break;
    case TM_EMPTY:
        t->s.n_meshes = 0;
        break;
    case TM_BAD_INDEX:
        tm_quad(t, 0, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        t->data[0].idx[4] = 9; /* the mesh has 4 vertices */
        tm_instance(t, 0, m);
        break;
    case TM_BAD_INSTANCE:
        tm_quad(t, 0, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        tm_instance(t, 0, m);
        t->instances[0].mesh = 3;
        break;
    case TM_NO_CAMERA:
        tm_quad(t, 0, lg_v3(0, 0, 0), lg_v3(1, 0, 0), lg_v3(0, 1, 0));
        tm_instance(t, 0, m);
        break;
    }
    static const char *const mesh_names[TM_MAX_MESHES] = { "test mesh#0", "", "", "" };
    for (uint32_t i = 0; i < t->s.n_meshes; i++) {
        t->meshes[i].name = mesh_names[i];
        t->meshes[i].positions = t->data[i].pos;
        t->meshes[i].normals = t->data[i].nrm;
        t->meshes[i].indices = t->data[i].idx;
    }
    lg_test_scene_bounds(&t->s, t->meshes);
    lg_scene_compute_features(&t->s);
    return t;
}

static int tm_scene_prepare(lg_node *n)
{
    tm_scene *t = tm_build(n);
    if (!t)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    return n->host->declare_payload(n, 0, LG_KIND_SCENE, &t->s.features, &t->s, tm_free);
}

static int tm_nothing(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- test_depth_plane ------------------------------------------------------------------ */

static int dp_prepare(lg_node *n)
{
    lg_resource_info info;
    const lg_resource *in = lg_input(n, 0);
    if (!in || lg_describe(in, &info, n) || info.kind != LG_KIND_IMAGE)
        return lg_error(n, "input 'image' is not an image");
    if (!(info.image.flags & LG_IMAGE_DEPTH))
        return lg_error(n, "input 'image' has no depth plane");
    lg_image_desc d = { .width = info.image.width, .height = info.image.height,
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

/* ---- the descriptor -------------------------------------------------------------------- */

static const lg_param_desc tm_params[] = {
    { .key = "layout", .type = LG_PARAM_ENUM, .def.e = 0, .enum_values = tm_layouts,
      .doc = "which scene (testmeshscene.c lists them)" },
    { .key = "color", .type = LG_PARAM_COLOR, .def.v = { 0.2, 0.5, 0.8 },
      .doc = "base colour of the one material" },
    { .key = "double_sided", .type = LG_PARAM_BOOL, .def.b = false,
      .doc = "the material's double_sided flag" },
    { .key = "yfov", .type = LG_PARAM_FLOAT, .def.f = 60, .min = 1, .max = 170,
      .doc = "the cameras' vertical field of view, degrees" },
    { .key = "znear", .type = LG_PARAM_FLOAT, .def.f = 1, .min = 0, .max = 1e6,
      .doc = "the cameras' znear" },
    { .key = "zfar", .type = LG_PARAM_FLOAT, .def.f = 20, .min = 0, .max = 1e6,
      .doc = "the cameras' zfar; 0 = from the bounds" },
    { .key = "camera_aspect", .type = LG_PARAM_FLOAT, .def.f = 0, .min = 0, .max = 100,
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
