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
 *
 *   test_field_probe  samples the scene's density field (ABI 3.2) with the SDK's
 *                     lg_medium_field_at on an n.x x n.y x n.z lattice of points over
 *                     [lo, hi] (point (i, j, k) = lo + (hi - lo) (i, j, k) / (n - 1); n = 1
 *                     gives lo), into an rgba32f image max(n.x, 8) wide, 1 + n.y n.z high:
 *   row 0: 0  field present (1/0), kind, features.medium_field, height_falloff
 *          1  height_base, grid nx, ny, nz (0 without a grid)
 *          2  bounds_min, grid max_value
 *          3  bounds_max, lg_medium_field_max over [lo, hi]
 *          4  fbm octaves, seed, frequency, lacunarity
 *          5  fbm gain, offset, scale, lg_medium_is_heterogeneous
 *          6  grid index_to_world's translation, grid source's length
 *          7  grid voxel size (index_to_world's column lengths), medium density
 *   row 1 + j + n.y k, pixel i: m(p), p.x, p.y, p.z
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/cl.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"

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

/* ---- test_field_probe ------------------------------------------------------------------------ */

static void field_size(lg_node *n, uint32_t *w, uint32_t *h)
{
    const lg_value *nv = lg_param(n, "n");
    *w = nv->i3[0] > 8 ? (uint32_t)nv->i3[0] : 8u;
    *h = 1u + (uint32_t)(nv->i3[1] * nv->i3[2]);
}

static int field_prepare(lg_node *n)
{
    if (!lg_scene_get(n, lg_input(n, 0)))
        return LG_ERR_INVALID;
    uint32_t w, h;
    field_size(n, &w, &h);
    lg_image_desc d = { .width = w, .height = h, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int field_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    lg_cpu_view v;
    int rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &v);
    if (rc)
        return rc;
    uint32_t w, h;
    field_size(n, &w, &h);
    float *px = v.pixels;
    memset(px, 0, (size_t)w * h * 4 * sizeof(float));
    const lg_value *lo = lg_param(n, "lo"), *hi = lg_param(n, "hi"), *nv = lg_param(n, "n");
    const lg_density_field *f = s->medium.field;
    const lg_density_grid *g = f && f->kind == LG_FIELD_GRID ? f->grid : NULL;
    put(px, 0, f != NULL, f ? (float)f->kind : -1, (float)s->features.medium_field,
        f ? f->height_falloff : 0);
    put(px, 1, f ? f->height_base : 0, g ? (float)g->nx : 0, g ? (float)g->ny : 0,
        g ? (float)g->nz : 0);
    put(px, 2, f ? f->bounds_min[0] : 0, f ? f->bounds_min[1] : 0, f ? f->bounds_min[2] : 0,
        g ? g->max_value : 0);
    double blo[3] = { lo->v[0], lo->v[1], lo->v[2] }, bhi[3] = { hi->v[0], hi->v[1], hi->v[2] };
    put(px, 3, f ? f->bounds_max[0] : 0, f ? f->bounds_max[1] : 0, f ? f->bounds_max[2] : 0,
        (float)lg_medium_field_max(&s->medium, blo, bhi));
    put(px, 4, f ? (float)f->fbm.octaves : 0, f ? (float)f->fbm.seed : 0, f ? f->fbm.frequency : 0,
        f ? f->fbm.lacunarity : 0);
    put(px, 5, f ? f->fbm.gain : 0, f ? f->fbm.offset : 0, f ? f->fbm.scale : 0,
        (float)lg_medium_is_heterogeneous(&s->medium));
    float vs[3] = { 0, 0, 0 };
    for (int c = 0; c < 3 && g; c++)
        vs[c] = (float)sqrt(g->index_to_world[4 * c] * g->index_to_world[4 * c] +
                            g->index_to_world[4 * c + 1] * g->index_to_world[4 * c + 1] +
                            g->index_to_world[4 * c + 2] * g->index_to_world[4 * c + 2]);
    put(px, 6, g ? (float)g->index_to_world[12] : 0, g ? (float)g->index_to_world[13] : 0,
        g ? (float)g->index_to_world[14] : 0, g && g->source ? (float)strlen(g->source) : 0);
    put(px, 7, vs[0], vs[1], vs[2], s->medium.density);
    int64_t nn[3] = { nv->i3[0], nv->i3[1], nv->i3[2] };
    for (int64_t k = 0; k < nn[2]; k++)
        for (int64_t j = 0; j < nn[1]; j++)
            for (int64_t i = 0; i < nn[0]; i++) {
                int64_t ijk[3] = { i, j, k };
                double p[3];
                for (int c = 0; c < 3; c++)
                    p[c] = lo->v[c] +
                           (nn[c] > 1 ? (hi->v[c] - lo->v[c]) * (double)ijk[c] / (double)(nn[c] - 1)
                                      : 0.0);
                size_t row = 1 + (size_t)(j + nn[1] * k);
                put(px + row * w * 4, (int)i, (float)lg_medium_field_at(&s->medium, p), (float)p[0],
                    (float)p[1], (float)p[2]);
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

static const lg_param_desc field_params[] = {
    { .key = "lo",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "the lattice's first point" },
    { .key = "hi", .type = LG_PARAM_VEC3, .def.v = { 0, 0, 0 }, .doc = "its last point" },
    { .key = "n",
      .type = LG_PARAM_INT3,
      .def.i3 = { 1, 1, 1 },
      .min = 1,
      .max = 256,
      .doc = "points along x, y, z" },
};
static const lg_port_desc field_in[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene whose medium to sample" },
};
static const lg_port_desc field_out[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "rgba32f, layout in testcube.c" },
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
    {
        .struct_size = sizeof(lg_node_type),
        .name = "test_field_probe",
        .doc = "Samples a scene's density field on a lattice of points (test)",
        LG_PARAMS(field_params),
        LG_INPUTS(field_in),
        LG_OUTPUTS(field_out),
        .prepare = field_prepare,
        .execute = field_execute,
    },
};

LG_PLUGIN_DEFINE("testcube", "1.0.0", "A cube scene and a scene probe for scene_tools tests", types)
