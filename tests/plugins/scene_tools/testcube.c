/*
 * Test plugin "testcube", for the scene_tools tests (built into this folder's build
 * directory, seen only through LIGHTGRAPH_PLUGIN_PATH):
 *
 *   test_cube         a real lg_scene made in memory: one box mesh (24 vertices, 12
 *                     triangles), `instances` instances side by side along +X, one
 *                     material (reflectivity from the parameter), one camera (or none),
 *                     no light, no medium
 *   test_scene_probe  writes what a scene holds as pixels of a 1-row rgba32f image (layout
 *                     below), so a test reads the derived scene through an EXR; with a
 *                     `source` scene it reports whether the geometry is shared, and with
 *                     gl = true whether the GL copies of mesh 0 are the same buffers
 *
 * Probe pixels (x: r, g, b, a):
 *   0  active camera position, yfov
 *   1  active camera target, znear
 *   2  active camera up, zfar
 *   3  n_lights, n_cameras, camera index, camera aspect
 *   4  geometry is the source's resource (1/0; -1 without source), meshes, instances and
 *      materials pointers equal the source's (1/0/-1), GL buffers of mesh 0 shared
 *      (1/0; -1 when not asked), n_instances
 *   5  medium present, density, g, features.medium
 *   6  medium scattering, features.dir_lights
 *   7  medium absorption, features.point_lights
 *   8  bounds_min, features.triangles
 *   9  bounds_max, geometry pointer is NULL (1/0)
 *   10 + 4i .. 13 + 4i  light i: (direction, type), (color, intensity), (position, range),
 *                       (inner_cone, outer_cone, 0, 0)
 */
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/lightgraph.h"

#include "common/testscene.h"

/* ---- test_cube ------------------------------------------------------------------------------- */

static int cube_prepare(lg_node *n)
{
    const lg_value *hv = lg_param(n, "half_size"), *cv = lg_param(n, "center");
    int64_t count = lg_param_int(n, "instances");
    lg_ts_builder *b = lg_ts_begin("test_cube");
    if (!b)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    lg_vec3 h = lg_v3((float)hv->v[0], (float)hv->v[1], (float)hv->v[2]);
    lg_vec3 ctr = lg_v3((float)cv->v[0], (float)cv->v[1], (float)cv->v[2]);
    lg_ts_mesh(b, "cube#0", 0);
    lg_ts_box(b, h);

    lg_material *m = lg_ts_material(b, "grey");
    m->ka = 0.1f;
    m->kd = 0.8f;
    m->ks = lg_param_bool(n, "specular") ? 0.5f : 0.0f;
    m->shininess = 32;
    for (int i = 0; i < 3; i++)
        m->od[i] = m->os[i] = m->base_color[i] = 0.8f;
    for (int i = 0; i < 3; i++)
        m->reflectivity[i] = (float)lg_param_float(n, "reflectivity");
    m->base_color[3] = 1;
    m->roughness = 1;

    if (lg_param_bool(n, "camera"))
        lg_ts_camera(b, "default", lg_v3(ctr.x, ctr.y, ctr.z + 5), ctr, lg_v3(0, 1, 0), 0.8f, 0.1f,
                     0.0f);

    for (int64_t i = 0; i < count; i++) {
        float model[16];
        lg_m4_identity(model);
        model[12] = ctr.x + 3.0f * h.x * (float)i;
        model[13] = ctr.y;
        model[14] = ctr.z;
        lg_ts_instance(b, 0, model);
    }
    return lg_ts_publish(n, 0, b);
}

static int cube_execute(lg_node *n, const lg_frame *frame)
{
    (void)n;
    (void)frame;
    return 0;
}

/* ---- test_scene_probe ------------------------------------------------------------------------ */

enum { PROBE_FIXED = 10, PROBE_PER_LIGHT = 4 };

static int probe_prepare(lg_node *n)
{
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    if (lg_input(n, 1) && !lg_scene_get(n, lg_input(n, 1)))
        return LG_ERR_INVALID;
    lg_image_desc d = { .width = PROBE_FIXED + PROBE_PER_LIGHT * s->n_lights,
                        .height = 1,
                        .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    return lg_set_device(n, lg_param_bool(n, "cl")   ? LG_DEVICE_CL
                            : lg_param_bool(n, "gl") ? LG_DEVICE_GL
                                                     : LG_DEVICE_CPU);
}

static void put(float *px, int x, float r, float g, float b, float a)
{
    px[x * 4 + 0] = r;
    px[x * 4 + 1] = g;
    px[x * 4 + 2] = b;
    px[x * 4 + 3] = a;
}

static int probe_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    const lg_resource *res = lg_input(n, 0), *src_res = lg_input(n, 1);
    const lg_scene *s = lg_scene_get(n, res), *src = src_res ? lg_scene_get(n, src_res) : NULL;
    if (!s || (src_res && !src))
        return LG_ERR_INVALID;
    float gl_shared = -1;
    if (lg_param_bool(n, "gl")) {
        if (!src)
            return lg_error(n, "gl = true needs the 'source' input");
        lg_mesh_gl a, b;
        int rc = lg_scene_mesh_gl(n, res, 0, &a);
        if (!rc)
            rc = lg_scene_mesh_gl(n, src_res, 0, &b);
        if (rc)
            return rc;
        gl_shared = a.positions && a.positions == b.positions && a.normals == b.normals &&
                    a.indices == b.indices;
    }
    if (lg_param_bool(n, "cl")) {
        /* the CL copies: shared with the source, and holding the mesh's own numbers */
        if (!src)
            return lg_error(n, "cl = true needs the 'source' input");
        lg_mesh_cl a, b;
        int rc = lg_scene_mesh_cl(n, res, 0, &a);
        if (!rc)
            rc = lg_scene_mesh_cl(n, src_res, 0, &b);
        if (rc)
            return rc;
        const lg_mesh *m = &s->meshes[0];
        size_t np = (size_t)m->n_vertices * 3, ni = m->n_indices;
        float *pos = malloc(np * sizeof(float));
        uint32_t *idx = malloc(ni * sizeof(uint32_t));
        cl_int e = pos && idx ? CL_SUCCESS : CL_OUT_OF_HOST_MEMORY;
        if (e == CL_SUCCESS)
            e = clEnqueueReadBuffer(lg_cl_queue(n), (cl_mem)a.positions, CL_TRUE, 0,
                                    np * sizeof(float), pos, 0, NULL, NULL);
        if (e == CL_SUCCESS)
            e = clEnqueueReadBuffer(lg_cl_queue(n), (cl_mem)a.indices, CL_TRUE, 0,
                                    ni * sizeof(uint32_t), idx, 0, NULL, NULL);
        bool same = e == CL_SUCCESS && memcmp(pos, m->positions, np * sizeof(float)) == 0 &&
                    memcmp(idx, m->indices, ni * sizeof(uint32_t)) == 0;
        free(pos);
        free(idx);
        if (e != CL_SUCCESS)
            return lg_cl_fail(n, e, "reading the mesh back from CL");
        gl_shared = a.positions && a.positions == b.positions && a.normals == b.normals &&
                    a.indices == b.indices && same;
    }
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    float *px = v.pixels;
    lg_camera cam;
    memset(&cam, 0, sizeof cam);
    if (s->camera < s->n_cameras)
        cam = s->cameras[s->camera];
    put(px, 0, cam.position[0], cam.position[1], cam.position[2], cam.yfov);
    put(px, 1, cam.target[0], cam.target[1], cam.target[2], cam.znear);
    put(px, 2, cam.up[0], cam.up[1], cam.up[2], cam.zfar);
    put(px, 3, (float)s->n_lights, (float)s->n_cameras, (float)s->camera, cam.aspect);
    float geo = -1, same = -1;
    if (src) {
        geo = s->geometry == src_res;
        same = s->meshes == src->meshes && s->instances == src->instances &&
               s->materials == src->materials;
    }
    put(px, 4, geo, same, gl_shared, (float)s->n_instances);
    put(px, 5, s->medium.present, s->medium.density, s->medium.g, s->features.medium);
    put(px, 6, s->medium.scattering[0], s->medium.scattering[1], s->medium.scattering[2],
        (float)s->features.dir_lights);
    put(px, 7, s->medium.absorption[0], s->medium.absorption[1], s->medium.absorption[2],
        (float)s->features.point_lights);
    put(px, 8, s->bounds_min[0], s->bounds_min[1], s->bounds_min[2], (float)s->features.triangles);
    put(px, 9, s->bounds_max[0], s->bounds_max[1], s->bounds_max[2], s->geometry == NULL);
    for (uint32_t i = 0; i < s->n_lights; i++) {
        const lg_light *l = &s->lights[i];
        int x = PROBE_FIXED + PROBE_PER_LIGHT * (int)i;
        put(px, x, l->direction[0], l->direction[1], l->direction[2], (float)l->type);
        put(px, x + 1, l->color[0], l->color[1], l->color[2], l->intensity);
        put(px, x + 2, l->position[0], l->position[1], l->position[2], l->range);
        put(px, x + 3, l->inner_cone, l->outer_cone, 0, 0);
    }
    return 0;
}

/* ---- descriptors ----------------------------------------------------------------------------- */

static const lg_param_desc cube_params[] = {
    { .key = "half_size",
      .type = LG_PARAM_VEC3,
      .def.v = { 1, 1, 1 },
      .min = 1e-3,
      .max = 1e3,
      .doc = "half the box's extent along x, y, z" },
    { .key = "center",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .min = -1e3,
      .max = 1e3,
      .doc = "centre of the first instance" },
    { .key = "instances",
      .type = LG_PARAM_INT,
      .def.i = 1,
      .min = 0,
      .max = 64,
      .doc = "copies side by side along +X, 3 half sizes apart (0: an empty scene)" },
    { .key = "specular", .type = LG_PARAM_BOOL, .def.b = false, .doc = "material ks 0.5" },
    { .key = "reflectivity",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1,
      .doc = "the material's reflectivity (all three channels): > 0 makes it reflective" },
    { .key = "camera",
      .type = LG_PARAM_BOOL,
      .def.b = true,
      .doc = "the scene has a camera (false: none, which scene.h forbids a loader)" },
};
static const lg_port_desc cube_out[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the cube scene" },
};

static const lg_param_desc probe_params[] = {
    { .key = "gl",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "compare the GL copies of mesh 0 of scene and source" },
    { .key = "cl",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "compare the CL copies of mesh 0 of scene and source, and with the CPU data" },
};
static const lg_port_desc probe_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene to report" },
    { .name = "source",
      .kind = LG_KIND_SCENE,
      .optional = true,
      .doc = "the scene whose geometry `scene` should share" },
};
static const lg_port_desc probe_out[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "rgba32f, 1 row, layout in testcube.c" },
};

static const lg_node_type types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_cube",
        .doc = "A cube scene made in memory (test)",
        LG_PARAMS(cube_params),
        LG_OUTPUTS(cube_out),
        .prepare = cube_prepare,
        .execute = cube_execute,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_scene_probe",
        .doc = "Writes a scene's camera, lights, medium and sharing as pixels (test)",
        LG_PARAMS(probe_params),
        LG_INPUTS(probe_in),
        LG_OUTPUTS(probe_out),
        .prepare = probe_prepare,
        .execute = probe_execute,
    },
};

LG_PLUGIN_DEFINE("testcube", "1.0.0", "A cube scene and a scene probe for scene_tools tests", types)
