/*
 * test_gltf: the `gltf` node's loader (plugins/scene_gltf/gltf_load.c), called directly.
 *
 *   test_gltf CASE
 *
 *   assets          every shipped asset loads with its triangle counts and bounds
 *   draco           Draco and plain variants hold the same geometry within quantisation
 *   instancing      nodes sharing a mesh: one lg_mesh, several instances (x6 dragon too)
 *   normals_cube    flat, smooth (crease 60) and smooth (crease 120) on split and shared cubes
 *   normals_sphere  smooth normals of a UV sphere point along the position
 *   normals_degenerate  zero-area and collinear triangles give no NaN
 *   primitives      strips, fans, non-indexed, index types, byteStride, sparse, normalized,
 *                   external .bin buffers and the content hash that covers them
 *   hierarchy       matrix and TRS transforms flattened; scene choice
 *   cameras         perspective, orthographic (approximated), the automatic camera, choice
 *   lights          KHR_lights_punctual directional, point, spot
 *   materials       PBR to Phong mapping, extensions, extras overrides, default material
 *   reflectivity    lg_material.reflectivity: metals (any roughness) reflect their base
 *                   colour, KHR_materials_specular dielectrics their F0, plain dielectrics 0,
 *                   extras.reflectivity (number, list, 0) overrides, the default material 1;
 *                   invalid values name the material; features.reflective_materials counts
 *                   materials some instance draws (instanced meshes once, unused ones not)
 *   medium          extras.medium of the scene, root and asset; errors
 *   bad_input       malformed files: each a clear error, no crash (suite stability)
 *   confinement     external buffers and images only from the model's folder: ../, absolute
 *                   paths, schemes, links leading out, FIFOs and devices refused with the
 *                   uri and where it leads, never read; links and ".." that stay inside work
 *   limits          the file and its buffers bounded before reading: a byteLength over the
 *                   file, over 2 GiB, 4 GiB of buffers, a sparse file over 2 GiB, a FIFO
 */
#include <fcntl.h>
#include <float.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/check.h"
#include "gltf_test.h"
#include "lightgraph/vecmath.h"

static char err[2048];

static bool near(double a, double b, double tol)
{
    return fabs(a - b) <= tol;
}

/* ---- a small glTF writer: one mesh with one primitive, data-URI buffer ----------------------- */

typedef struct prim {
    const float *pos;
    uint32_t nv;
    const float *nrm, *uv;
    const uint32_t *idx; /* written as UNSIGNED_INT */
    uint32_t ni;
    int mode;
} prim;

/* The JSON of a file with that primitive (mesh 0), `nodes` (default: one node drawing mesh
 * 0), `scenes` (default: "[{nodes: [0]}]", scene 0; "": none) and `extra` appended to the
 * root object (",\"key\": ..." or NULL). */
static char *mesh_json_scenes(const prim *p, const char *nodes, const char *scenes,
                              const char *extra)
{
    gt_blob b = { 0 };
    size_t opos = gt_add(&b, p->pos, (size_t)p->nv * 12);
    size_t onrm = p->nrm ? gt_add(&b, p->nrm, (size_t)p->nv * 12) : 0;
    size_t ouv = p->uv ? gt_add(&b, p->uv, (size_t)p->nv * 8) : 0;
    size_t oidx = p->idx ? gt_add(&b, p->idx, (size_t)p->ni * 4) : 0;
    char *uri = gt_data_uri(b.data, b.size);
    char views[1024] = "", accs[1024] = "", attrs[256] = "", *v = views, *a = accs;
    int nviews = 0;
    v += sprintf(v, "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u}", opos, p->nv * 12);
    a += sprintf(a, "{\"bufferView\":0,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\"}",
                 p->nv);
    sprintf(attrs, "\"POSITION\":0");
    nviews = 1;
    if (p->nrm) {
        v += sprintf(v, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u}", onrm, p->nv * 12);
        a += sprintf(a,
                     ",{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\"}",
                     nviews, p->nv);
        sprintf(attrs + strlen(attrs), ",\"NORMAL\":%d", nviews++);
    }
    if (p->uv) {
        v += sprintf(v, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u}", ouv, p->nv * 8);
        a += sprintf(a,
                     ",{\"bufferView\":%d,\"componentType\":5126,\"count\":%u,\"type\":\"VEC2\"}",
                     nviews, p->nv);
        sprintf(attrs + strlen(attrs), ",\"TEXCOORD_0\":%d", nviews++);
    }
    char indices[64] = "";
    if (p->idx) {
        v += sprintf(v, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u}", oidx, p->ni * 4);
        a += sprintf(a,
                     ",{\"bufferView\":%d,\"componentType\":5125,\"count\":%u,\"type\":\"SCALAR\"}",
                     nviews, p->ni);
        sprintf(indices, ",\"indices\":%d", nviews++);
    }
    char *json =
        gt_fmt("{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
               "\"bufferViews\":[%s],\"accessors\":[%s],"
               "\"meshes\":[{\"name\":\"m\",\"primitives\":[{\"attributes\":{%s}%s,\"mode\":%d}]}],"
               "\"nodes\":%s%s%s}",
               b.size, uri, views, accs, attrs, indices, p->mode, nodes ? nodes : "[{\"mesh\":0}]",
               !scenes ? ",\"scenes\":[{\"nodes\":[0]}],\"scene\":0" : scenes, extra ? extra : "");
    free(uri);
    gt_blob_free(&b);
    return json;
}

static char *mesh_json(const prim *p, const char *nodes, const char *extra)
{
    return mesh_json_scenes(p, nodes, NULL, extra);
}

static lg_scene *load_prim(const char *name, const prim *p, const char *nodes, const char *extra,
                           const lg_gltf_options *opt)
{
    char *json = mesh_json(p, nodes, extra);
    lg_scene *s = gt_load_text(name, json, opt, err, sizeof err, NULL);
    CHECKF(s, "%s: %s", name, err);
    free(json);
    return s;
}

/* ---- assets ---------------------------------------------------------------------------------- */

static lg_scene *load_asset(const char *rel)
{
    lg_scene *s = gt_load_file(gt_asset(rel), NULL, err, sizeof err, NULL);
    CHECKF(s, "%s: %s", rel, err);
    return s;
}

static uint64_t mesh_triangles(const lg_scene *s)
{
    uint64_t t = 0;
    for (uint32_t i = 0; i < s->n_meshes; i++)
        t += s->meshes[i].n_indices / 3;
    return t;
}

/* Every mesh well formed: indices in range, unit normals, finite positions. */
static void check_consistent(const lg_scene *s, const char *what)
{
    CHECKF(s->struct_size == sizeof(lg_scene), "%s", what);
    CHECKF(s->n_materials >= 1 && s->n_cameras >= 1 && s->camera < s->n_cameras, "%s", what);
    for (uint32_t i = 0; i < s->n_meshes; i++) {
        const lg_mesh *m = &s->meshes[i];
        CHECKF(m->material < s->n_materials, "%s mesh %u material %u", what, i, m->material);
        CHECKF(m->n_indices % 3 == 0, "%s mesh %u", what, i);
        uint32_t bad = 0;
        for (uint32_t k = 0; k < m->n_indices; k++)
            bad += m->indices[k] >= m->n_vertices;
        for (uint32_t v = 0; v < m->n_vertices; v++) {
            const float *n = m->normals + 3 * (size_t)v, *p = m->positions + 3 * (size_t)v;
            float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            bad += !(fabsf(l - 1) < 1e-4f) || !isfinite(p[0] + p[1] + p[2]);
        }
        CHECKF(bad == 0, "%s mesh %u: %u bad indices, normals or positions", what, i, bad);
    }
    for (uint32_t i = 0; i < s->n_instances; i++)
        CHECKF(s->instances[i].mesh < s->n_meshes, "%s instance %u", what, i);
}

static void case_assets(void)
{
    static const struct {
        const char *file;
        uint32_t meshes, instances;
        uint64_t tri_min, tri_max;
    } want[] = {
        { "meshes/bunny_cornell_box.glb", 6, 6, 5009, 5009 },
        { "meshes/bunny_cornell_box_draco.glb", 6, 6, 4990,
          5009 }, /* Draco may drop degenerate triangles */
        { "meshes/cornell_box.gltf", 7, 7, 34, 34 },
        { "meshes/cornell_box_draco.gltf", 7, 7, 30, 34 },
        { "meshes/draco-box/Box.glb", 1, 1, 12, 12 },
        { "meshes/draco-box/Box_Draco.glb", 1, 1, 12, 12 },
        { "meshes/draco-box/Box.gltf", 1, 1, 12, 12 }, /* external Box0.bin */
        { "meshes/dragon_vrip_draco.glb", 1, 1, 871000, 871414 },
        { "meshes/dragon_vrip_x6_instanced_draco.glb", 1, 6, 6 * 871000ull, 6 * 871414ull },
        /* 2 spheres of 96 x 48 quads less the poles' 96 degenerate triangles each, and the
         * bunny of the bunny box */
        { "meshes/ibl_spheres.glb", 3, 3, 2 * (2 * 96 * 48 - 2 * 96) + 4999,
          2 * (2 * 96 * 48 - 2 * 96) + 4999 },
    };
    for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
        lg_scene *s = load_asset(want[i].file);
        if (!s)
            continue;
        check_consistent(s, want[i].file);
        CHECKF(s->n_meshes == want[i].meshes && s->n_instances == want[i].instances,
               "%s: %u meshes, %u instances", want[i].file, s->n_meshes, s->n_instances);
        CHECKF(s->features.triangles >= want[i].tri_min && s->features.triangles <= want[i].tri_max,
               "%s: %llu triangles", want[i].file, (unsigned long long)s->features.triangles);
        CHECK(s->features.triangles == (s->n_instances == s->n_meshes
                                            ? mesh_triangles(s)
                                            : s->n_instances * mesh_triangles(s)));
        CHECK(s->n_lights == 0 && s->features.dir_lights == 0 && !s->features.medium &&
              !s->medium.present);
        lg_gltf_scene_free(s);
    }

    /* the bunny box: Y-up, 2 units wide, open on -Z; the bunny's material is the only
     * specular one (the walls say KHR_materials_specular colour 0) */
    lg_scene *s = load_asset("meshes/bunny_cornell_box.glb");
    if (s) {
        CHECKF(near(s->bounds_min[0], -0.98714, 1e-4) && near(s->bounds_max[0], 0.99857, 1e-4) &&
                   near(s->bounds_min[1], 0, 1e-4) && near(s->bounds_max[1], 1.96, 1e-4) &&
                   near(s->bounds_min[2], -0.99857, 1e-4) && near(s->bounds_max[2], 0.99857, 1e-4),
               "bounds %g %g %g .. %g %g %g", s->bounds_min[0], s->bounds_min[1], s->bounds_min[2],
               s->bounds_max[0], s->bounds_max[1], s->bounds_max[2]);
        CHECK(s->n_materials == 4 && s->features.specular);
        for (uint32_t i = 0; i < 3; i++)
            CHECKF(s->materials[i].os[0] == 0 && s->materials[i].os[1] == 0, "material %u os", i);
        CHECK(near(s->materials[3].os[0], 0.04, 1e-6) &&
              near(s->materials[3].shininess, (2 / pow(0.16, 2) - 2) / 4, 1e-3));
        lg_gltf_scene_free(s);
    }
    /* the IBL scene (tools/make_ibl_scene.py): three metals side by side on no ground, each
     * reflective; unit spheres at x = -2.3 and 0 standing on y = 0 with their normals their
     * unit positions; the bunny 1.9 tall at x = 2.3; a camera at (0, 1.3, 9.5) */
    s = load_asset("meshes/ibl_spheres.glb");
    if (s) {
        CHECKF(s->n_materials == 3 && s->features.reflective_materials == 3,
               "%u materials, %u reflective", s->n_materials, s->features.reflective_materials);
        static const char *const names[3] = { "mirror", "gold", "copper" };
        static const double rough[3] = { 0, 0.35, 0.2 };
        for (uint32_t i = 0; i < 3 && i < s->n_materials; i++) {
            const lg_material *m = &s->materials[i];
            CHECKF(!strcmp(m->name, names[i]) && m->metallic == 1 &&
                       near(m->roughness, rough[i], 1e-7) &&
                       m->reflectivity[0] == m->base_color[0] &&
                       m->reflectivity[2] == m->base_color[2],
                   "material %u: %s metallic %g roughness %g reflectivity %g", i, m->name,
                   m->metallic, m->roughness, m->reflectivity[0]);
        }
        CHECKF(near(s->bounds_min[0], -3.3, 1e-5) && near(s->bounds_min[1], 0, 1e-5) &&
                   near(s->bounds_max[1], 2, 1e-5),
               "bounds %g %g %g .. %g %g %g", s->bounds_min[0], s->bounds_min[1], s->bounds_min[2],
               s->bounds_max[0], s->bounds_max[1], s->bounds_max[2]);
        CHECKF(s->n_cameras >= 1 && near(s->cameras[0].position[2], 9.5, 1e-5) &&
                   near(s->cameras[0].yfov, LG_PI / 6, 1e-6) &&
                   near(s->cameras[0].target[1] - s->cameras[0].position[1],
                        -0.35 / 9.5 * (s->cameras[0].position[2] - s->cameras[0].target[2]), 1e-4),
               "%u cameras, position z %g, yfov %g, target %g %g %g", s->n_cameras,
               s->n_cameras ? s->cameras[0].position[2] : 0, s->n_cameras ? s->cameras[0].yfov : 0,
               s->n_cameras ? s->cameras[0].target[0] : 0,
               s->n_cameras ? s->cameras[0].target[1] : 0,
               s->n_cameras ? s->cameras[0].target[2] : 0);
        double worst = 0;
        for (uint32_t i = 0; i < 2 && i < s->n_meshes; i++) {
            const lg_mesh *m = &s->meshes[i];
            double cx = i == 0 ? -2.3 : 0;
            for (uint32_t v = 0; v < m->n_vertices; v++) {
                const float *p = m->positions + 3 * v, *n = m->normals + 3 * v;
                double d[3] = { p[0] - cx, p[1] - 1.0, p[2] };
                for (int k = 0; k < 3; k++)
                    worst = fmax(worst, fabs(d[k] - n[k]));
            }
        }
        CHECKF(worst < 1e-6, "sphere normals differ from the unit positions by %g", worst);
        lg_gltf_scene_free(s);
    }
    /* the dragon's bounds are the file's accessor min/max, within the Draco quantisation */
    s = load_asset("meshes/dragon_vrip_draco.glb");
    if (s) {
        static const double lo[3] = { -0.10842409166523347, 0.05262940567902198,
                                      -0.050514394370998236 };
        static const double hi[3] = { 0.096666293172325, 0.1972636692662704, 0.04127080958021753 };
        for (int k = 0; k < 3; k++)
            CHECKF(near(s->bounds_min[k], lo[k], 5e-4) && near(s->bounds_max[k], hi[k], 5e-4),
                   "axis %d: %g..%g", k, s->bounds_min[k], s->bounds_max[k]);
        lg_gltf_scene_free(s);
    }
}

/* ---- Draco against plain --------------------------------------------------------------------- */

static double world_area(const lg_scene *s, uint32_t inst)
{
    const lg_instance *in = &s->instances[inst];
    const lg_mesh *m = &s->meshes[in->mesh];
    double a = 0;
    for (uint32_t t = 0; t < m->n_indices; t += 3) {
        float p[3][3];
        for (int k = 0; k < 3; k++)
            gt_world(in, m->positions + 3 * (size_t)m->indices[t + k], p[k]);
        lg_vec3 c = lg_v3_cross(lg_v3(p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]),
                                lg_v3(p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]));
        a += 0.5 * lg_v3_length(c);
    }
    return a;
}

/* The largest distance from a vertex of (s, i) to the nearest vertex of (t, j), world space. */
static double vertex_distance(const lg_scene *s, uint32_t i, const lg_scene *t, uint32_t j)
{
    const lg_mesh *a = &s->meshes[s->instances[i].mesh], *b = &t->meshes[t->instances[j].mesh];
    float *wb = malloc((size_t)b->n_vertices * 3 * sizeof *wb + 1);
    for (uint32_t v = 0; v < b->n_vertices; v++)
        gt_world(&t->instances[j], b->positions + 3 * (size_t)v, wb + 3 * (size_t)v);
    double worst = 0;
    for (uint32_t v = 0; v < a->n_vertices; v++) {
        float p[3];
        gt_world(&s->instances[i], a->positions + 3 * (size_t)v, p);
        double best = DBL_MAX;
        for (uint32_t u = 0; u < b->n_vertices; u++) {
            double dx = p[0] - wb[3 * u], dy = p[1] - wb[3 * u + 1], dz = p[2] - wb[3 * u + 2];
            double d = dx * dx + dy * dy + dz * dz;
            if (d < best)
                best = d;
        }
        if (best > worst)
            worst = best;
    }
    free(wb);
    return sqrt(worst);
}

static void compare_draco(const char *plain, const char *draco)
{
    lg_scene *a = load_asset(plain), *b = load_asset(draco);
    if (!a || !b)
        goto done;
    CHECKF(a->n_instances == b->n_instances, "%s: %u instances, %s: %u", plain, a->n_instances,
           draco, b->n_instances);
    for (uint32_t i = 0; i < a->n_instances && i < b->n_instances; i++) {
        const lg_mesh *ma = &a->meshes[a->instances[i].mesh];
        /* quantisation: at least 10 bits over the mesh's extent */
        double ext = 0;
        for (int k = 0; k < 3; k++)
            ext = fmax(ext, (double)ma->bounds_max[k] - ma->bounds_min[k]);
        double scale = 0;
        for (int k = 0; k < 3; k++)
            scale = fmax(scale, fabs((double)a->instances[i].model[k]) +
                                    fabs((double)a->instances[i].model[4 + k]) +
                                    fabs((double)a->instances[i].model[8 + k]));
        double tol = ext * scale / 1024;
        double d1 = vertex_distance(b, i, a, i), d2 = vertex_distance(a, i, b, i);
        CHECKF(d1 <= tol && d2 <= tol, "%s: distances %g and %g > %g", ma->name, d1, d2, tol);
        double aa = world_area(a, i), ab = world_area(b, i);
        CHECKF(near(aa, ab, 0.01 * aa), "%s: area %g vs %g", ma->name, aa, ab);
    }
    for (int k = 0; k < 3; k++) {
        double ext = (double)a->bounds_max[k] - a->bounds_min[k] + 1e-9;
        CHECKF(near(a->bounds_min[k], b->bounds_min[k], ext / 1000) &&
                   near(a->bounds_max[k], b->bounds_max[k], ext / 1000),
               "%s vs %s: bounds axis %d", plain, draco, k);
    }
done:
    lg_gltf_scene_free(a);
    lg_gltf_scene_free(b);
}

static void case_draco(void)
{
    compare_draco("meshes/bunny_cornell_box.glb", "meshes/bunny_cornell_box_draco.glb");
    compare_draco("meshes/cornell_box.gltf", "meshes/cornell_box_draco.gltf");
    compare_draco("meshes/draco-box/Box.glb", "meshes/draco-box/Box_Draco.glb");
}

/* ---- instancing ------------------------------------------------------------------------------ */

static void case_instancing(void)
{
    lg_scene *s = load_asset("meshes/dragon_vrip_x6_instanced_draco.glb");
    if (s) {
        CHECK(s->n_meshes == 1 && s->n_instances == 6);
        CHECK(s->features.triangles == 6ull * (s->meshes[0].n_indices / 3));
        CHECK(s->features.vertices == 6ull * s->meshes[0].n_vertices);
        /* the six placements of the file, one array of vertices */
        static const float tx[6] = { 0, 0.22559942f, 0.45119885f, 0, 0.22559942f, 0.45119885f };
        static const float tz[6] = { 0, 0, 0, 0.11932077f, 0.11932077f, 0.11932077f };
        for (uint32_t i = 0; i < s->n_instances; i++)
            CHECKF(s->instances[i].mesh == 0 && near(s->instances[i].model[12], tx[i], 1e-6) &&
                       near(s->instances[i].model[14], tz[i], 1e-6),
                   "instance %u", i);
        lg_gltf_scene_free(s);
    }
    /* three nodes share one mesh of two primitives: 2 meshes, 6 instances */
    static const float pos[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    static const uint32_t idx[] = { 0, 1, 2 };
    prim p = { pos, 3, NULL, NULL, idx, 3, 4 };
    char *json = mesh_json(&p,
                           "[{\"mesh\":0,\"children\":[1,2]},{\"mesh\":0,\"translation\":[5,0,0]},"
                           "{\"mesh\":0,\"scale\":[2,2,2]}]",
                           NULL);
    /* a second primitive in mesh 0, the same accessors */
    char *two = strstr(json, "\"mode\":4}]");
    CHECK(two != NULL);
    if (two) {
        char *j2 = gt_fmt("%.*s\"mode\":4},{\"attributes\":{\"POSITION\":0},\"indices\":1}]%s",
                          (int)(two - json), json, two + strlen("\"mode\":4}]"));
        lg_scene *t = gt_load_text("inst.gltf", j2, NULL, err, sizeof err, NULL);
        CHECKF(t, "%s", err);
        if (t) {
            CHECKF(t->n_meshes == 2 && t->n_instances == 6, "%u meshes, %u instances", t->n_meshes,
                   t->n_instances);
            CHECK(t->features.triangles == 6);
            for (uint32_t i = 0; i < t->n_instances; i++)
                CHECK(t->instances[i].mesh == i % 2);
            CHECK(near(t->instances[2].model[12], 5, 0) && near(t->instances[4].model[0], 2, 0));
            lg_gltf_scene_free(t);
        }
        free(j2);
    }
    free(json);
}

/* ---- normals --------------------------------------------------------------------------------- */

/* A cube [-1, 1]^3 with outward winding: 24 vertices (4 per face) or 8 shared. */
static void cube(bool shared, float *pos, uint32_t *nv, uint32_t *idx)
{
    uint32_t n = 0, t = 0;
    for (int a = 0; a < 3; a++)
        for (int s = -1; s <= 1; s += 2) {
            float c[4][3];
            static const float uv[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
            for (int k = 0; k < 4; k++) {
                int kk = s > 0 ? k : 3 - k; /* reversed winding on the negative side */
                c[k][a] = (float)s;
                c[k][(a + 1) % 3] = uv[kk][0];
                c[k][(a + 2) % 3] = uv[kk][1];
            }
            uint32_t id[4];
            for (int k = 0; k < 4; k++) {
                if (shared) {
                    id[k] = (c[k][0] > 0) | (c[k][1] > 0) << 1 | (c[k][2] > 0) << 2;
                    for (int j = 0; j < 3; j++)
                        pos[3 * id[k] + j] = c[k][j];
                } else {
                    id[k] = n;
                    memcpy(pos + 3 * n++, c[k], sizeof c[k]);
                }
            }
            uint32_t tri[6] = { id[0], id[1], id[2], id[0], id[2], id[3] };
            memcpy(idx + t, tri, sizeof tri);
            t += 6;
        }
    *nv = shared ? 8 : n;
}

static void case_normals_cube(void)
{
    for (int shared = 0; shared < 2; shared++) {
        float pos[24 * 3];
        uint32_t idx[36], nv;
        cube(shared, pos, &nv, idx);
        prim p = { pos, nv, NULL, NULL, idx, 36, 4 };
        for (int mode = 0; mode < 3; mode++) {
            lg_gltf_options o = lg_gltf_default_options();
            o.normals = mode == 0 ? LG_GLTF_NORMALS_FLAT : LG_GLTF_NORMALS_SMOOTH;
            o.crease_deg = mode == 2 ? 120 : 60;
            lg_scene *s = load_prim("cube.gltf", &p, NULL, NULL, &o);
            if (!s)
                continue;
            check_consistent(s, "cube");
            const lg_mesh *m = &s->meshes[0];
            CHECK(m->n_indices == 36);
            /* flat: 3 vertices per triangle; crease 60: 4 per face; crease 120: one per
             * source vertex */
            uint32_t want_v = mode == 0 ? 36 : mode == 1 ? 24 : nv;
            CHECKF(m->n_vertices == want_v, "shared %d mode %d: %u vertices, want %u", shared, mode,
                   m->n_vertices, want_v);
            uint32_t bad = 0;
            for (uint32_t t = 0; t < 36; t += 3) {
                /* the face's axis: the centroid's largest coordinate */
                float c[3] = { 0, 0, 0 };
                for (int k = 0; k < 3; k++)
                    for (int j = 0; j < 3; j++)
                        c[j] += m->positions[3 * m->indices[t + k] + j] / 3;
                int ax = fabsf(c[0]) > fabsf(c[1]) ? (fabsf(c[0]) > fabsf(c[2]) ? 0 : 2)
                                                   : (fabsf(c[1]) > fabsf(c[2]) ? 1 : 2);
                for (int k = 0; k < 3; k++) {
                    const float *n = m->normals + 3 * m->indices[t + k],
                                *q = m->positions + 3 * m->indices[t + k];
                    if (mode < 2) {
                        for (int j = 0; j < 3; j++)
                            bad += !near(n[j], j == ax ? (c[ax] > 0 ? 1 : -1) : 0, 1e-6);
                    } else {
                        for (int j = 0; j < 3; j++)
                            bad += !near(n[j], q[j] / sqrt(3.0), 1e-6);
                    }
                }
            }
            CHECKF(bad == 0, "shared %d mode %d: %u wrong normal components", shared, mode, bad);
            lg_gltf_scene_free(s);
        }
    }
}

static void case_normals_sphere(void)
{
    enum { R = 16, S = 32 };
    float *pos = malloc((R + 1) * (S + 1) * 3 * sizeof *pos),
          *uv = malloc((R + 1) * (S + 1) * 2 * sizeof *uv);
    uint32_t *idx = malloc(R * S * 6 * sizeof *idx), nv = 0, ni = 0;
    for (int r = 0; r <= R; r++)
        for (int s = 0; s <= S; s++) {
            /* the seam column and the pole rows repeat their positions exactly, as
             * exporters write them (welding compares positions bit for bit) */
            double th = LG_PI * r / R, ph = 2 * LG_PI * (s % S) / S;
            double st = r == 0 || r == R ? 0 : sin(th), ct = r == R ? -1 : cos(th);
            pos[3 * nv] = (float)(st * cos(ph));
            pos[3 * nv + 1] = (float)ct;
            pos[3 * nv + 2] = (float)(st * sin(ph));
            uv[2 * nv] = (float)s / S;
            uv[2 * nv + 1] = (float)r / R;
            nv++;
        }
    for (int r = 0; r < R; r++)
        for (int s = 0; s < S; s++) {
            uint32_t a = r * (S + 1) + s, b = a + S + 1, c = b + 1, d = a + 1;
            uint32_t t[6] = { a, c, b, a, d, c }; /* outward; the pole rows are degenerate */
            memcpy(idx + ni, t, sizeof t);
            ni += 6;
        }
    prim p = { pos, nv, NULL, uv, idx, ni, 4 };
    for (int mode = 0; mode < 2; mode++) {
        lg_gltf_options o = lg_gltf_default_options();
        o.normals = mode ? LG_GLTF_NORMALS_FLAT : LG_GLTF_NORMALS_AUTO; /* auto: none in the file */
        lg_scene *sc = load_prim("sphere.gltf", &p, NULL, NULL, &o);
        if (!sc)
            continue;
        check_consistent(sc, "sphere");
        const lg_mesh *m = &sc->meshes[0];
        CHECK(m->texcoords != NULL);
        double worst = 1;
        for (uint32_t t = 0; t < m->n_indices; t += 3) {
            float c[3] = { 0, 0, 0 };
            for (int k = 0; k < 3; k++)
                for (int j = 0; j < 3; j++)
                    c[j] += m->positions[3 * m->indices[t + k] + j];
            const float *p0 = m->positions + 3 * m->indices[t],
                        *p1 = m->positions + 3 * m->indices[t + 1],
                        *p2 = m->positions + 3 * m->indices[t + 2];
#define SAME(a, b) ((a)[0] == (b)[0] && (a)[1] == (b)[1] && (a)[2] == (b)[2])
            if (SAME(p0, p1) || SAME(p1, p2) || SAME(p0, p2))
                continue; /* the pole rows' zero-area triangles: (0, 0, 1) in flat mode */
            for (int k = 0; k < 3; k++) {
                const float *n = m->normals + 3 * m->indices[t + k],
                            *q = m->positions + 3 * m->indices[t + k];
                const float *ref = mode ? c : q; /* flat: the facet's centroid direction */
                double l = sqrt(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2]);
                double d = (n[0] * ref[0] + n[1] * ref[1] + n[2] * ref[2]) / l;
                if (d < worst)
                    worst = d;
            }
        }
        /* smooth: within 1 degree of the radius (area x angle weights give 0.64 degrees
         * at worst here, next to the pole; area weights alone would give 1.9); flat:
         * within a facet's angular size */
        CHECKF(worst > (mode ? cos(12 * LG_PI / 180) : cos(1 * LG_PI / 180)),
               "mode %d: worst cosine %.6f", mode, worst);
        /* smooth: the seam and the poles are welded for the normals but keep their
         * texture coordinates: one vertex per source vertex used */
        if (!mode)
            CHECKF(m->n_vertices <= nv, "%u vertices from %u", m->n_vertices, nv);
        lg_gltf_scene_free(sc);
    }
    free(pos);
    free(uv);
    free(idx);
}

static void case_normals_degenerate(void)
{
    /* a good triangle, a zero-area one (two equal corners), a collinear one, and a vertex
     * (4) that only degenerate triangles use */
    static const float pos[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 5, 5, 5, 3, 0, 0 };
    static const uint32_t idx[] = { 0, 1, 2, 4, 4, 1, 0, 3, 5, 4, 0, 0 };
    prim p = { pos, 6, NULL, NULL, idx, 12, 4 };
    for (int mode = 0; mode < 3; mode++) {
        lg_gltf_options o = lg_gltf_default_options();
        o.normals = mode == 0 ? LG_GLTF_NORMALS_FLAT : LG_GLTF_NORMALS_SMOOTH;
        o.crease_deg = mode == 2 ? 0 : 60;
        lg_scene *s = load_prim("degenerate.gltf", &p, NULL, NULL, &o);
        if (!s)
            continue;
        check_consistent(s, "degenerate"); /* unit, finite normals */
        const lg_mesh *m = &s->meshes[0];
        CHECK(m->n_indices == 12);
        /* the good triangle's corners face +Z */
        for (int k = 0; k < 3; k++)
            CHECKF(near(m->normals[3 * m->indices[k] + 2], 1, 1e-6), "mode %d corner %d", mode, k);
        lg_gltf_scene_free(s);
    }
}

/* ---- primitives ------------------------------------------------------------------------------ */

/* A file around one hand-written primitive: `views` and `accessors` JSON over the blob. */
static lg_scene *load_custom(const char *name, const gt_blob *b, const char *views,
                             const char *accessors, const char *primitive,
                             const lg_gltf_options *opt, int *rc)
{
    char *uri = gt_data_uri(b->data, b->size);
    char *json =
        gt_fmt("{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%zu,\"uri\":\"%s\"}],"
               "\"bufferViews\":[%s],\"accessors\":[%s],\"meshes\":[{\"primitives\":[%s]}],"
               "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}]}",
               b->size, uri, views, accessors, primitive);
    lg_scene *s = gt_load_text(name, json, opt, err, sizeof err, rc);
    free(uri);
    free(json);
    return s;
}

static void case_primitives(void)
{
    /* a strip and a fan over 5 points in the z = 0 plane, counter-clockwise from +Z */
    static const float pts[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0 };
    gt_blob b = { 0 };
    size_t op = gt_add(&b, pts, sizeof pts);
    static const uint8_t strip8[] = { 0, 1, 2, 3, 4 };
    static const uint16_t fan16[] = { 0, 1, 3, 2, 4 };
    static const uint32_t tri32[] = { 0, 1, 2, 2, 1, 3 };
    size_t o8 = gt_add(&b, strip8, sizeof strip8), o16 = gt_add(&b, fan16, sizeof fan16),
           o32 = gt_add(&b, tri32, sizeof tri32);
    char *views = gt_fmt(
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":60},{\"buffer\":0,\"byteOffset\":%zu,"
        "\"byteLength\":5},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":10},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":24}",
        op, o8, o16, o32);
    const char *accs = "{\"bufferView\":0,\"componentType\":5126,\"count\":5,\"type\":\"VEC3\"},"
                       "{\"bufferView\":1,\"componentType\":5121,\"count\":5,\"type\":\"SCALAR\"},"
                       "{\"bufferView\":2,\"componentType\":5123,\"count\":5,\"type\":\"SCALAR\"},"
                       "{\"bufferView\":3,\"componentType\":5125,\"count\":6,\"type\":\"SCALAR\"}";
    static const struct {
        const char *prim;
        uint32_t triangles;
    } cases[] = {
        { "{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":5}", 3 }, /* strip, ubyte */
        { "{\"attributes\":{\"POSITION\":0},\"indices\":2,\"mode\":6}", 3 }, /* fan, ushort */
        { "{\"attributes\":{\"POSITION\":0},\"indices\":3}", 2 },            /* triangles, uint */
        { "{\"attributes\":{\"POSITION\":0},\"mode\":5}", 3 },               /* non-indexed strip */
        { "{\"attributes\":{\"POSITION\":0},\"mode\":4}", 1 }, /* non-indexed, 5 % 3 left over */
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        lg_gltf_options o = lg_gltf_default_options();
        o.normals = LG_GLTF_NORMALS_FLAT;
        lg_scene *s = load_custom("prim.gltf", &b, views, accs, cases[i].prim, &o, NULL);
        CHECKF(s, "case %zu: %s", i, err);
        if (!s)
            continue;
        check_consistent(s, cases[i].prim);
        CHECKF(s->features.triangles == cases[i].triangles, "case %zu: %llu triangles", i,
               (unsigned long long)s->features.triangles);
        /* strips and fans keep one winding: every facet faces +Z */
        const lg_mesh *m = &s->meshes[0];
        for (uint32_t v = 0; v < m->n_vertices; v++)
            CHECKF(near(m->normals[3 * v + 2], 1, 1e-6), "case %zu vertex %u normal z %g", i, v,
                   m->normals[3 * v + 2]);
        lg_gltf_scene_free(s);
    }
    /* lines and points are refused by name */
    int rc = 0;
    lg_scene *s = load_custom("lines.gltf", &b, views, accs,
                              "{\"attributes\":{\"POSITION\":0},\"mode\":1}", NULL, &rc);
    CHECKF(!s && rc == LG_ERR_UNSUPPORTED && strstr(err, "mesh 0 primitive 0: mode LINES (1)"),
           "%s", err);
    lg_gltf_scene_free(s);
    s = load_custom("points.gltf", &b, views, accs, "{\"attributes\":{\"POSITION\":0},\"mode\":0}",
                    NULL, &rc);
    CHECKF(!s && strstr(err, "mode POINTS (0)"), "%s", err);
    lg_gltf_scene_free(s);
    free(views);
    gt_blob_free(&b);

    /* interleaved position + normalized ushort texcoord (byteStride 16), and a sparse
     * accessor moving vertex 2 */
    gt_blob c = { 0 };
    uint8_t inter[3 * 16];
    static const float q[3][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
    static const uint16_t t[3][2] = { { 0, 0 }, { 65535, 0 }, { 0, 32768 } };
    for (int v = 0; v < 3; v++) {
        memcpy(inter + 16 * v, q[v], 12);
        memcpy(inter + 16 * v + 12, t[v], 4);
    }
    size_t oi = gt_add(&c, inter, sizeof inter);
    static const uint16_t sidx[1] = { 2 };
    static const float sval[3] = { 0, 3, 0 };
    size_t os = gt_add(&c, sidx, sizeof sidx), ov = gt_add(&c, sval, sizeof sval);
    char *v2 = gt_fmt(
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":48,\"byteStride\":16},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":2},{\"buffer\":0,\"byteOffset\":%zu,"
        "\"byteLength\":12}",
        oi, os, ov);
    const char *a2 =
        "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"sparse\":{\"count\":1,"
        "\"indices\":{\"bufferView\":1,\"componentType\":5123},\"values\":{\"bufferView\":2}}},"
        "{\"bufferView\":0,\"byteOffset\":12,\"componentType\":5123,\"normalized\":true,\"count\":3,"
        "\"type\":\"VEC2\"}";
    s = load_custom("interleaved.gltf", &c, v2, a2,
                    "{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1}}", NULL, NULL);
    CHECKF(s, "%s", err);
    if (s) {
        const lg_mesh *m = &s->meshes[0];
        CHECK(m->texcoords && m->n_indices == 3);
        for (uint32_t i = 0; i < 3 && m->texcoords; i++) {
            uint32_t v = m->indices[i];
            const float *p = m->positions + 3 * v, *uv = m->texcoords + 2 * v;
            float want_y = i == 2 ? 3 : q[i][1], want_u = t[i][0] / 65535.0f,
                  want_v = t[i][1] / 65535.0f;
            CHECKF(near(p[0], q[i][0], 0) && near(p[1], want_y, 0) && near(uv[0], want_u, 1e-7) &&
                       near(uv[1], want_v, 1e-7),
                   "corner %u: %g %g uv %g %g", i, p[0], p[1], uv[0], uv[1]);
        }
        lg_gltf_scene_free(s);
    }
    free(v2);
    gt_blob_free(&c);

    /* an external buffer file next to the .gltf */
    static const float tri[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    gt_write("tri.bin", tri, sizeof tri);
    s = gt_load_text(
        "external.gltf",
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"tri.bin\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"meshes\":[{\"primitives\":[{"
        "\"attributes\":{\"POSITION\":0}}]}],\"nodes\":[{\"mesh\":0}]}",
        NULL, err, sizeof err, NULL);
    CHECKF(s && s->features.triangles == 1, "%s", err);
    lg_gltf_scene_free(s);
    /* a byte order mark before the JSON is fine */
    size_t n = 0;
    uint8_t *text = gt_read(gt_path("external.gltf"), &n);
    uint8_t *bom = malloc(n + 3);
    memcpy(bom, "\xEF\xBB\xBF", 3);
    memcpy(bom + 3, text, n);
    gt_write("bom.gltf", bom, n + 3);
    s = gt_load_file(gt_path("bom.gltf"), NULL, err, sizeof err, NULL);
    CHECKF(s && s->features.triangles == 1, "with a BOM: %s", err);
    lg_gltf_scene_free(s);
    free(text);
    free(bom);
    /* the content hash covers the external buffer: same .gltf, other .bin, other hash */
    uint64_t h1 = 0, h2 = 0, h3 = 0;
    lg_gltf_options o = lg_gltf_default_options();
    CHECK(lg_gltf_load(gt_path("external.gltf"), &o, &s, &h1, err, sizeof err) == 0);
    lg_gltf_scene_free(s);
    CHECK(lg_gltf_load(gt_path("external.gltf"), &o, &s, &h2, err, sizeof err) == 0);
    lg_gltf_scene_free(s);
    static const float moved[] = { 0, 0, 0, 2, 0, 0, 0, 1, 0 };
    gt_write("tri.bin", moved, sizeof moved);
    CHECK(lg_gltf_load(gt_path("external.gltf"), &o, &s, &h3, err, sizeof err) == 0);
    lg_gltf_scene_free(s);
    CHECKF(h1 == h2 && h1 != h3, "hashes %llx %llx %llx", (unsigned long long)h1,
           (unsigned long long)h2, (unsigned long long)h3);
}

/* ---- hierarchy ------------------------------------------------------------------------------- */

static void case_hierarchy(void)
{
    static const float pos[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    static const uint32_t idx[] = { 0, 1, 2 };
    prim p = { pos, 3, NULL, NULL, idx, 3, 4 };
    /* node 0: translate (1, 2, 3), child 1: rotate 90 degrees about Z and scale 2,
     * child 2 of 1: matrix translating (0, 0, 10) */
    const char *nodes =
        "[{\"translation\":[1,2,3],\"children\":[1]},"
        "{\"rotation\":[0,0,0.7071067811865476,0.7071067811865476],\"scale\":[2,2,2],"
        "\"mesh\":0,\"children\":[2]},"
        "{\"matrix\":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,10,1],\"mesh\":0},"
        "{\"mesh\":0,\"translation\":[100,0,0]}]";
    char *json = mesh_json_scenes(&p, nodes,
                                  ",\"scenes\":[{\"nodes\":[0]},{\"nodes\":[3]}],\"scene\":0",
                                  NULL);
    lg_scene *s = gt_load_text("tree.gltf", json, NULL, err, sizeof err, NULL);
    CHECKF(s, "%s", err);
    if (s) {
        CHECK(s->n_meshes == 1 && s->n_instances == 2);
        /* vertex (1, 0, 0) of node 1: rotate -> (0, 1, 0), scale -> (0, 2, 0), + (1, 2, 3) */
        float w[3];
        gt_world(&s->instances[0], pos + 3, w);
        CHECKF(near(w[0], 1, 1e-6) && near(w[1], 4, 1e-6) && near(w[2], 3, 1e-6), "%g %g %g", w[0],
               w[1], w[2]);
        /* node 2: (1, 0, 0) + (0, 0, 10) in node 1's frame -> z 3 + 20 */
        gt_world(&s->instances[1], pos + 3, w);
        CHECKF(near(w[0], 1, 1e-5) && near(w[1], 4, 1e-5) && near(w[2], 23, 1e-5), "%g %g %g", w[0],
               w[1], w[2]);
        /* the normal matrix of a uniform scale 2 is the rotation / 2 */
        CHECK(near(s->instances[0].normal_matrix[3], -0.5, 1e-6));
        lg_gltf_scene_free(s);
    }
    lg_gltf_options o = lg_gltf_default_options();
    o.scene = 1;
    s = gt_load_text("tree.gltf", json, &o, err, sizeof err, NULL);
    CHECKF(s && s->n_instances == 1 && near(s->instances[0].model[12], 100, 0), "%s", err);
    lg_gltf_scene_free(s);
    o.scene = 2;
    int rc = 0;
    s = gt_load_text("tree.gltf", json, &o, err, sizeof err, &rc);
    CHECKF(!s && strstr(err, "scene 2 does not exist"), "%s", err);
    free(json);
    /* no scenes at all: every root node (0 and 3) */
    json = mesh_json_scenes(&p, nodes, "", NULL);
    s = gt_load_text("roots.gltf", json, NULL, err, sizeof err, NULL);
    CHECKF(s && s->n_instances == 3, "%s", err);
    lg_gltf_scene_free(s);
    free(json);
}

/* ---- cameras, lights ------------------------------------------------------------------------- */

static const float unit_tri[] = { -1, -1, 0, 1, -1, 0, 0, 1, 0 };
static const uint32_t unit_idx[] = { 0, 1, 2 };

static void case_cameras(void)
{
    prim p = { unit_tri, 3, NULL, NULL, unit_idx, 3, 4 };
    const char *nodes = "[{\"mesh\":0,\"children\":[1,2,3]},{\"camera\":0,\"translation\":[0,1,5]},"
                        "{\"camera\":1,\"rotation\":[0,0.7071067811865476,0,0.7071067811865476],"
                        "\"translation\":[4,0,0]},{\"camera\":2,\"translation\":[0,0,10]}]";
    const char *cams =
        ",\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,\"znear\":0.1,"
        "\"zfar\":100,\"aspectRatio\":2.0}},{\"name\":\"side\",\"type\":\"perspective\","
        "\"perspective\":{\"yfov\":0.5,\"znear\":0.01}},{\"type\":\"orthographic\","
        "\"orthographic\":{\"xmag\":2,\"ymag\":1,\"znear\":0.5,\"zfar\":50}}]";
    lg_scene *s = load_prim("cams.gltf", &p, nodes, cams, NULL);
    if (s) {
        CHECKF(s->n_cameras == 4 && s->camera == 0, "%u cameras", s->n_cameras);
        const lg_camera *c = &s->cameras[0];
        /* position from the node, looking down -Z at the bounds' centre's depth */
        CHECK(near(c->position[0], 0, 1e-6) && near(c->position[1], 1, 1e-6) &&
              near(c->position[2], 5, 1e-6));
        CHECKF(near(c->target[0], 0, 1e-6) && near(c->target[1], 1, 1e-6) &&
                   near(c->target[2], 0, 1e-6),
               "target %g %g %g", c->target[0], c->target[1], c->target[2]);
        CHECK(near(c->up[1], 1, 1e-6) && near(c->yfov, 0.8, 1e-6) && near(c->znear, 0.1, 1e-7) &&
              near(c->zfar, 100, 1e-5) && c->aspect == 0);
        c = &s->cameras[1]; /* turned 90 degrees about Y: looks down -X */
        CHECK(!strcmp(c->name, "side") && c->zfar == 0);
        CHECKF(c->target[0] < c->position[0] && near(c->target[1], 0, 1e-6) &&
                   near(c->target[2], 0, 1e-5),
               "%g %g %g -> %g %g %g", c->position[0], c->position[1], c->position[2], c->target[0],
               c->target[1], c->target[2]);
        c = &s->cameras[2]; /* orthographic ymag 1 seen from 10: yfov 2 atan(1 / 10) */
        CHECKF(near(c->yfov, 2 * atan(0.1), 1e-5) && near(c->znear, 0.5, 1e-6), "ortho yfov %g",
               c->yfov);
        CHECK(!strcmp(s->cameras[3].name, "auto"));
        lg_gltf_scene_free(s);
    }
    lg_gltf_options o = lg_gltf_default_options();
    o.camera = 1;
    s = load_prim("cams.gltf", &p, nodes, cams, &o);
    CHECK(s && s->camera == 1);
    lg_gltf_scene_free(s);
    o.camera = 4;
    char *json = mesh_json(&p, nodes, cams);
    s = gt_load_text("cams.gltf", json, &o, err, sizeof err, NULL);
    CHECKF(!s && strstr(err, "camera 4 does not exist: the scene has 4"), "%s", err);
    free(json);

    /* the automatic camera: a triangle at z = 0 is seen from +Z, framed in 45 degrees */
    s = load_prim("auto.gltf", &p, NULL, NULL, NULL);
    if (s) {
        const lg_camera *c = &s->cameras[s->camera];
        CHECK(s->n_cameras == 1 && !strcmp(c->name, "auto") && c->aspect == 0);
        double d = 1.05 * 1.0 / tan(LG_PI / 8);
        CHECKF(near(c->position[2], d, 1e-4) && near(c->target[2], 0, 1e-6) &&
                   near(c->yfov, LG_PI / 4, 1e-6),
               "auto camera at z %g", c->position[2]);
        lg_gltf_scene_free(s);
    }
    /* the bunny box is a room open on -Z: its automatic camera stands there */
    s = load_asset("meshes/bunny_cornell_box.glb");
    if (s) {
        const lg_camera *c = &s->cameras[s->camera];
        CHECKF(c->position[2] < s->bounds_min[2] && c->target[2] > c->position[2], "camera z %g",
               c->position[2]);
        lg_gltf_scene_free(s);
    }
}

static void case_lights(void)
{
    prim p = { unit_tri, 3, NULL, NULL, unit_idx, 3, 4 };
    const char *nodes =
        "[{\"mesh\":0,\"children\":[1,2,3]},"
        "{\"rotation\":[-0.7071067811865476,0,0,0.7071067811865476],\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}}},"
        "{\"translation\":[10,0,0],\"children\":[4]},"
        "{\"matrix\":[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,3,0,1],\"extensions\":{\"KHR_lights_punctual\":{\"light\":2}}},"
        "{\"translation\":[1,2,3],\"extensions\":{\"KHR_lights_punctual\":{\"light\":1}}}]";
    const char *lights =
        ",\"extensionsUsed\":[\"KHR_lights_punctual\"],\"extensions\":{\"KHR_lights_punctual\":{\"lights\":["
        "{\"name\":\"sun\",\"type\":\"directional\",\"color\":[1,0.5,0.25],\"intensity\":3},"
        "{\"type\":\"point\",\"intensity\":10,\"range\":5},"
        "{\"type\":\"spot\",\"spot\":{\"innerConeAngle\":0.2,\"outerConeAngle\":0.5}}]}}";
    lg_scene *s = load_prim("lights.gltf", &p, nodes, lights, NULL);
    if (!s)
        return;
    CHECKF(s->n_lights == 3, "%u lights", s->n_lights);
    CHECK(s->features.dir_lights == 1 && s->features.point_lights == 1 &&
          s->features.other_lights == 1);
    if (s->n_lights == 3) {
        const lg_light *l = &s->lights[0]; /* tree order: nodes 1, 4 (under 2), 3 */
        CHECK(!strcmp(l->name, "sun") && l->type == LG_LIGHT_DIRECTIONAL && l->intensity == 3);
        CHECK(l->color[0] == 1 && l->color[1] == 0.5f && l->color[2] == 0.25f);
        CHECKF(near(l->direction[0], 0, 1e-6) && near(l->direction[1], -1, 1e-6) &&
                   near(l->direction[2], 0, 1e-6),
               "sun direction %g %g %g", l->direction[0], l->direction[1], l->direction[2]);
        l = &s->lights[2];
        CHECK(l->type == LG_LIGHT_SPOT && near(l->inner_cone, 0.2, 1e-7) &&
              near(l->outer_cone, 0.5, 1e-7) && near(l->position[1], 3, 0) &&
              near(l->direction[2], -1, 1e-6) && l->intensity == 1 && l->color[1] == 1);
        l = &s->lights[1];
        CHECK(l->type == LG_LIGHT_POINT && l->intensity == 10 && l->range == 5);
        CHECKF(near(l->position[0], 11, 1e-6) && near(l->position[1], 2, 1e-6) &&
                   near(l->position[2], 3, 1e-6),
               "point at %g %g %g", l->position[0], l->position[1], l->position[2]);
    }
    lg_gltf_scene_free(s);
    /* a node naming a light that does not exist */
    char *json = mesh_json(&p,
                           "[{\"mesh\":0,\"extensions\":{\"KHR_lights_punctual\":{\"light\":7}}}]",
                           lights);
    s = gt_load_text("badlight.gltf", json, NULL, err, sizeof err, NULL);
    CHECKF(!s && strstr(err, "node 0: KHR_lights_punctual.light"), "%s", err);
    free(json);
}

/* ---- materials, medium ----------------------------------------------------------------------- */

static void case_materials(void)
{
    prim p = { unit_tri, 3, NULL, NULL, unit_idx, 3, 4 };
    const char *mats =
        ",\"materials\":["
        "{\"name\":\"plastic\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.5,0.25,1,1],\"metallicFactor\":0,"
        "\"roughnessFactor\":0.5}},"
        "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.9,0.6,0.3,1],\"metallicFactor\":1,\"roughnessFactor\":0}},"
        "{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.4,0.2,1],\"metallicFactor\":0.5},"
        "\"extensions\":{\"KHR_materials_specular\":{\"specularColorFactor\":[0,0,0]}},\"emissiveFactor\":[1,0.5,0]},"
        "{\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"extras\":{\"ka\":0.3,\"kd\":0.7,\"ks\":0.2,"
        "\"shininess\":42,\"od\":[0.1,0.2,0.3],\"os\":0.5,\"note\":\"other tools' keys are ignored\"}},"
        "{\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"extensions\":{\"KHR_materials_ior\":{\"ior\":1.0}}}]";
    /* five primitives, one per material, and one without a material */
    char *json = mesh_json(&p, NULL, mats);
    char *at = strstr(json, "\"mode\":4}]");
    CHECK(at != NULL);
    if (!at) {
        free(json);
        return;
    }
    char *prims =
        gt_fmt("%.*s\"mode\":4,\"material\":0},{\"attributes\":{\"POSITION\":0},\"material\":1},"
               "{\"attributes\":{\"POSITION\":0},\"material\":2},{\"attributes\":{\"POSITION\":0},"
               "\"material\":3},{\"attributes\":{\"POSITION\":0},\"material\":4},{\"attributes\":"
               "{\"POSITION\":0}}]%s",
               (int)(at - json), json, at + strlen("\"mode\":4}]"));
    lg_scene *s = gt_load_text("mats.gltf", prims, NULL, err, sizeof err, NULL);
    CHECKF(s, "%s", err);
    if (s) {
        CHECKF(s->n_materials == 6, "%u materials", s->n_materials);
        const lg_material *m = &s->materials[0];
        /* od = base colour, kd = 1 - metallic, os = F0 of ior 1.5 (0.04), ka 0.1, ks 1,
         * n = (2 / alpha^2 - 2) / 4 with alpha = roughness^2 = 0.25: 7.5 */
        CHECK(!strcmp(m->name, "plastic") && m->od[0] == 0.5f && m->od[1] == 0.25f &&
              m->od[2] == 1.0f);
        CHECK(near(m->kd, 1, 0) && near(m->ks, 1, 0) && near(m->ka, 0.1, 1e-7) &&
              near(m->os[1], 0.04, 1e-7));
        CHECKF(near(m->shininess, 7.5, 1e-5), "shininess %g", m->shininess);
        m = &s->materials[1]; /* metal, roughness 0: os = base colour, kd 0, n clamped to 10000 */
        CHECK(near(m->os[0], 0.9, 1e-7) && near(m->os[2], 0.3, 1e-7) && m->kd == 0 &&
              m->shininess == 10000);
        m = &s->materials[2]; /* half metal, no dielectric specular: os = base / 2; n = 1 */
        CHECK(near(m->os[0], 0.4, 1e-7) && near(m->os[1], 0.2, 1e-7) && near(m->kd, 0.5, 0) &&
              m->shininess == 1);
        CHECK(m->emissive[0] == 1 && m->emissive[1] == 0.5f);
        m = &s->materials[3]; /* extras override */
        CHECK(near(m->ka, 0.3, 1e-7) && near(m->kd, 0.7, 1e-7) && near(m->ks, 0.2, 1e-7) &&
              m->shininess == 42);
        CHECK(near(m->od[0], 0.1, 1e-7) && near(m->od[2], 0.3, 1e-7) && m->os[0] == 0.5f &&
              m->os[2] == 0.5f);
        m = &s->materials[4]; /* ior 1: no reflection at all */
        CHECK(m->os[0] == 0 && m->os[1] == 0 && m->os[2] == 0);
        m = &s->materials[5]; /* glTF's default material, for the primitive without one */
        CHECK(!strcmp(m->name, "default") && m->metallic == 1 && s->meshes[5].material == 5);
        CHECK(s->features.specular);
        lg_gltf_scene_free(s);
    }
    free(prims);
    free(json);
    /* only materials without a specular term: the feature is off */
    json = mesh_json(&p, NULL,
                     ",\"materials\":[{\"pbrMetallicRoughness\":{\"metallicFactor\":0},"
                     "\"extras\":{\"ks\":0}}]");
    at = strstr(json, "\"mode\":4}");
    char *j2 = at ? gt_fmt("%.*s\"mode\":4,\"material\":0}%s", (int)(at - json), json,
                           at + strlen("\"mode\":4}"))
                  : NULL;
    s = j2 ? gt_load_text("nospec.gltf", j2, NULL, err, sizeof err, NULL) : NULL;
    CHECKF(s && !s->features.specular, "%s", err);
    lg_gltf_scene_free(s);
    free(j2);
    free(json);
    /* a wrongly typed override is an error naming the material and the key */
    json = mesh_json(&p, NULL, ",\"materials\":[{\"name\":\"bad\",\"extras\":{\"kd\":\"much\"}}]");
    s = gt_load_text("badmat.gltf", json, NULL, err, sizeof err, NULL);
    CHECKF(!s && strstr(err, "material 0 ('bad'): extras.kd must be a number"), "%s", err);
    free(json);
}

/* ---- reflectivity ---------------------------------------------------------------------------- */

/* The unit triangle's file with `mats` (",\"materials\":[...]") and `nodes` (NULL: one node
 * drawing mesh 0), mesh 0 holding one primitive per entry of `prim_mats` (-1: no material). */
static char *multi_prim_json(const char *mats, const char *nodes, const char *scenes,
                             const int *prim_mats, int n)
{
    prim p = { unit_tri, 3, NULL, NULL, unit_idx, 3, 4 };
    char *json = mesh_json_scenes(&p, nodes, scenes, mats);
    char *at = strstr(json, "\"mode\":4}]");
    if (!at) {
        free(json);
        return NULL;
    }
    char prims[4096] = "";
    size_t len = 0;
    for (int i = 0; i < n; i++) {
        const char *head = i == 0 ? "\"mode\":4"
                                  : "{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":4";
        if (prim_mats[i] >= 0)
            len += (size_t)snprintf(prims + len, sizeof prims - len, "%s%s,\"material\":%d}",
                                    i ? "," : "", head, prim_mats[i]);
        else
            len += (size_t)snprintf(prims + len, sizeof prims - len, "%s%s}", i ? "," : "", head);
    }
    char *r = gt_fmt("%.*s%s]%s", (int)(at - json), json, prims, at + strlen("\"mode\":4}]"));
    free(json);
    return r;
}

static bool rgb_near(const float *v, double r, double g, double b, double tol)
{
    return near(v[0], r, tol) && near(v[1], g, tol) && near(v[2], b, tol);
}

static void case_reflectivity(void)
{
    /* F0 closed forms: a metal reflects its base colour (glTF Appendix B, metallic 1:
     * F0 = baseColor); a dielectric with KHR_materials_specular F0 = min(0.04 * specular
     * colour, 1) * specularFactor (ior 1.5); half metal 0.5 * 0.04 + 0.5 * base. */
    const char *mats =
        ",\"materials\":["
        "{\"name\":\"mirror\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.95,0.95,0.95,1],\"metallicFactor\":1,"
        "\"roughnessFactor\":0}},"
        "{\"name\":\"rough gold\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,0.78,0.34,1],\"metallicFactor\":1,"
        "\"roughnessFactor\":0.9}},"
        "{\"name\":\"coated\",\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"extensions\":{\"KHR_materials_specular\":"
        "{\"specularFactor\":0.5,\"specularColorFactor\":[1,0.5,0.25]}}},"
        "{\"name\":\"plastic\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.2,0.5,0.9,1],\"metallicFactor\":0,"
        "\"roughnessFactor\":0.1}},"
        "{\"name\":\"painted\",\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"extras\":{\"reflectivity\":0.3}},"
        "{\"name\":\"tinted\",\"pbrMetallicRoughness\":{\"metallicFactor\":1},\"extras\":{\"reflectivity\":[0.1,0.2,0.3]}},"
        "{\"name\":\"matte metal\",\"pbrMetallicRoughness\":{\"metallicFactor\":1},\"extras\":{\"reflectivity\":0}},"
        "{\"name\":\"half\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.4,0.2,1],\"metallicFactor\":0.5}},"
        "{\"name\":\"ior1\",\"pbrMetallicRoughness\":{\"metallicFactor\":0},\"extensions\":{\"KHR_materials_specular\":"
        "{},\"KHR_materials_ior\":{\"ior\":1}}}]";
    static const int used[] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, -1 };
    char *json = multi_prim_json(mats, NULL, NULL, used, 10);
    lg_scene *s = json ? gt_load_text("refl.gltf", json, NULL, err, sizeof err, NULL) : NULL;
    CHECKF(s, "%s", err);
    if (s) {
        CHECKF(s->n_materials == 10, "%u materials", s->n_materials);
        const lg_material *m = s->materials;
        CHECKF(rgb_near(m[0].reflectivity, 0.95, 0.95, 0.95, 1e-7), "mirror %g",
               m[0].reflectivity[0]);
        /* roughness does not change reflectivity (it selects the prefiltered level) */
        CHECKF(rgb_near(m[1].reflectivity, 1, 0.78, 0.34, 1e-7) && near(m[1].roughness, 0.9, 1e-7),
               "rough gold %g %g %g", m[1].reflectivity[0], m[1].reflectivity[1],
               m[1].reflectivity[2]);
        CHECKF(rgb_near(m[2].reflectivity, 0.02, 0.01, 0.005, 1e-8), "coated %g %g %g",
               m[2].reflectivity[0], m[2].reflectivity[1], m[2].reflectivity[2]);
        /* a plain dielectric has a specular term (os 0.04) but mirrors nothing */
        CHECKF(rgb_near(m[3].reflectivity, 0, 0, 0, 0) && near(m[3].os[0], 0.04, 1e-7),
               "plastic %g, os %g", m[3].reflectivity[0], m[3].os[0]);
        CHECKF(rgb_near(m[4].reflectivity, 0.3, 0.3, 0.3, 1e-7), "extras number %g",
               m[4].reflectivity[0]);
        CHECKF(rgb_near(m[5].reflectivity, 0.1, 0.2, 0.3, 1e-7) && near(m[5].os[0], 1, 0),
               "extras list %g %g %g (os %g unchanged)", m[5].reflectivity[0], m[5].reflectivity[1],
               m[5].reflectivity[2], m[5].os[0]);
        CHECKF(rgb_near(m[6].reflectivity, 0, 0, 0, 0), "extras 0 on a metal %g",
               m[6].reflectivity[0]);
        CHECKF(rgb_near(m[7].reflectivity, 0.42, 0.22, 0.12, 1e-7), "half metal %g %g %g",
               m[7].reflectivity[0], m[7].reflectivity[1], m[7].reflectivity[2]);
        /* KHR_materials_specular with ior 1: F0 0, so a reflectivity of 0 */
        CHECKF(rgb_near(m[8].reflectivity, 0, 0, 0, 0), "ior 1 %g", m[8].reflectivity[0]);
        CHECKF(!strcmp(m[9].name, "default") && rgb_near(m[9].reflectivity, 1, 1, 1, 0),
               "default %s %g", m[9].name, m[9].reflectivity[0]);
        /* reflective: mirror, rough gold, coated, painted, tinted, half, default */
        CHECKF(s->features.reflective_materials == 7, "reflective materials %u, want 7",
               s->features.reflective_materials);
        lg_gltf_scene_free(s);
    }
    free(json);

    /* an instanced mesh counts its material once; a material no primitive uses, and one
     * whose mesh no node draws, count nothing. Mesh 0 (plastic) is drawn by three nodes,
     * mesh 1 (gold) by two; mesh 2 (copper) by none; silver is used by no primitive. */
    const char *mats2 =
        ",\"materials\":[{\"name\":\"plastic\",\"pbrMetallicRoughness\":{\"metallicFactor\":0}},"
        "{\"name\":\"gold\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[1,0.78,0.34,1],\"metallicFactor\":1}},"
        "{\"name\":\"copper\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.95,0.64,0.54,1],\"metallicFactor\":1}},"
        "{\"name\":\"silver\",\"pbrMetallicRoughness\":{\"metallicFactor\":1}}]";
    static const int plastic[] = { 0 };
    json = multi_prim_json(
        mats2,
        "[{\"mesh\":0},{\"mesh\":0,\"translation\":[3,0,0]},{\"mesh\":0,\"translation\":[6,0,0]},"
        "{\"mesh\":1,\"translation\":[0,3,0]},{\"mesh\":1,\"translation\":[0,6,0]}]",
        ",\"scenes\":[{\"nodes\":[0,1,2,3,4]}],\"scene\":0", plastic, 1);
    /* meshes 1 and 2: copies of mesh 0 with gold and copper */
    char *at = json ? strstr(json, "\"meshes\":[") : NULL;
    const char *m0 = at ? at + strlen("\"meshes\":[") : NULL;
    const char *end = m0 ? strstr(m0, "],\"nodes\"") : NULL;
    char *j2 = NULL;
    if (end) {
        int m0len = (int)(end - m0);
        char *gold = gt_fmt("%.*s", m0len, m0);
        char *copper = gt_fmt("%.*s", m0len, m0);
        char *g = strstr(gold, "\"material\":0"), *c = strstr(copper, "\"material\":0");
        if (g && c) {
            g[strlen("\"material\":")] = '1';
            c[strlen("\"material\":")] = '2';
            j2 = gt_fmt("%.*s,%s,%s%s", (int)(end - json), json, gold, copper, end);
        }
        free(gold);
        free(copper);
    }
    CHECKF(j2 != NULL, "could not build the instanced file from %s", json ? json : "(null)");
    s = j2 ? gt_load_text("inst_refl.gltf", j2, NULL, err, sizeof err, NULL) : NULL;
    CHECKF(s || !j2, "%s", err);
    if (s) {
        /* the loader keeps the meshes that nodes draw (copper's is not one) and every material */
        CHECKF(s->n_meshes == 2 && s->n_instances == 5 && s->n_materials == 4,
               "%u meshes, %u instances, %u materials", s->n_meshes, s->n_instances,
               s->n_materials);
        CHECK(s->n_meshes == 2 && s->meshes[0].material == 0 && s->meshes[1].material == 1);
        CHECKF(s->materials[2].reflectivity[0] > 0 && s->materials[3].reflectivity[0] > 0,
               "copper and silver reflect (%g, %g) though nothing draws them",
               s->materials[2].reflectivity[0], s->materials[3].reflectivity[0]);
        CHECKF(s->features.reflective_materials == 1, "reflective materials %u, want 1 (gold)",
               s->features.reflective_materials);
        lg_gltf_scene_free(s);
    }
    free(j2);
    free(json);

    /* no reflective material drawn: 0 */
    json = multi_prim_json(mats2, NULL, NULL, plastic, 1);
    s = json ? gt_load_text("plastic.gltf", json, NULL, err, sizeof err, NULL) : NULL;
    CHECKF(s && s->features.reflective_materials == 0 && s->features.specular, "%s: reflective %u",
           err, s ? s->features.reflective_materials : 99);
    lg_gltf_scene_free(s);
    free(json);

    /* invalid values: an error naming the material and the key */
    static const struct {
        const char *value, *want;
    } bad[] = {
        { "1.5", "material 0 ('shiny'): extras.reflectivity must be a number in [0, 1]" },
        { "-0.1", "material 0 ('shiny'): extras.reflectivity must be a number in [0, 1]" },
        { "[0.5,0.5]",
          "material 0 ('shiny'): extras.reflectivity must be [r, g, b] or one number, each in [0, 1]" },
        { "[0.5,0.5,2]", "material 0 ('shiny'): extras.reflectivity must be a number in [0, 1]" },
        { "\"high\"", "material 0 ('shiny'): extras.reflectivity must be [r, g, b] or one number" },
        { "[0.1,\"x\",0.2]",
          "material 0 ('shiny'): extras.reflectivity must be a number in [0, 1]" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char *m = gt_fmt(",\"materials\":[{\"name\":\"shiny\",\"extras\":{\"reflectivity\":%s}}]",
                         bad[i].value);
        json = multi_prim_json(m, NULL, NULL, plastic, 1);
        s = json ? gt_load_text("badrefl.gltf", json, NULL, err, sizeof err, NULL) : NULL;
        CHECKF(!s && strstr(err, bad[i].want) && strstr(err, "badrefl.gltf"), "reflectivity %s: %s",
               bad[i].value, err);
        lg_gltf_scene_free(s);
        free(json);
        free(m);
    }
}

static void case_medium(void)
{
    prim p = { unit_tri, 3, NULL, NULL, unit_idx, 3, 4 };
    /* on the scene: extinction gives absorption = extinction - scattering */
    char *json = mesh_json(&p, NULL, NULL);
    char *at = strstr(json, "\"scenes\":[{\"nodes\":[0]}]");
    char *j2 = gt_fmt(
        "%.*s\"scenes\":[{\"nodes\":[0],\"extras\":{\"medium\":{\"density\":0.5,\"scattering\":"
        "[0.1,0.2,0.3],\"extinction\":0.5,\"g\":0.4}}}]%s",
        (int)(at - json), json, at + strlen("\"scenes\":[{\"nodes\":[0]}]"));
    lg_scene *s = gt_load_text("medium.gltf", j2, NULL, err, sizeof err, NULL);
    CHECKF(s, "%s", err);
    if (s) {
        const lg_medium *m = &s->medium;
        CHECK(m->present && m->density == 0.5f && near(m->g, 0.4, 1e-7));
        CHECK(near(m->scattering[1], 0.2, 1e-7) && near(m->absorption[0], 0.4, 1e-7) &&
              near(m->absorption[2], 0.2, 1e-7));
        CHECK(s->features.medium && s->features.medium_density == 0.5f);
        lg_gltf_scene_free(s);
    }
    free(j2);
    free(json);
    /* on the root, with defaults; density 0: present but no feature */
    s = load_prim("root.gltf", &p, NULL, ",\"extras\":{\"medium\":{\"density\":0}}", NULL);
    CHECK(s && s->medium.present && !s->features.medium && s->medium.scattering[0] == 1 &&
          s->medium.absorption[0] == 0);
    lg_gltf_scene_free(s);
    /* on the asset */
    json = mesh_json(&p, NULL, NULL);
    at = strstr(json, "\"asset\":{\"version\":\"2.0\"}");
    j2 = gt_fmt(
        "{\"asset\":{\"version\":\"2.0\",\"extras\":{\"medium\":{\"absorption\":[0.1,0,0],\"scattering\":2}}}%s",
        at + strlen("\"asset\":{\"version\":\"2.0\"}"));
    s = gt_load_text("asset.gltf", j2, NULL, err, sizeof err, NULL);
    CHECKF(s && s->features.medium && s->medium.scattering[2] == 2 &&
               near(s->medium.absorption[0], 0.1, 1e-7),
           "%s", err);
    lg_gltf_scene_free(s);
    free(j2);
    free(json);
    static const struct {
        const char *medium, *want;
    } bad[] = {
        { "{\"absorption\":1,\"extinction\":2}", "absorption or extinction, not both" },
        { "{\"scattering\":1,\"extinction\":0.5}",
          "extinction[0] = 0.5 is less than scattering[0] = 1" },
        { "{\"g\":1}", "g must be a number in" },
        { "{\"density\":-1}", "density must be a number in" },
        { "{\"scattering\":[1,2]}", "scattering must be [r, g, b]" },
        { "3", "extras.medium must be an object" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char *extra = gt_fmt(",\"extras\":{\"medium\":%s}", bad[i].medium);
        json = mesh_json(&p, NULL, extra);
        s = gt_load_text("badmedium.gltf", json, NULL, err, sizeof err, NULL);
        CHECKF(!s && strstr(err, bad[i].want) && strstr(err, "badmedium.gltf"), "%s: %s",
               bad[i].medium, err);
        lg_gltf_scene_free(s);
        free(json);
        free(extra);
    }
}

/* ---- bad input ------------------------------------------------------------------------------- */

static void expect_fail_file(const char *path, const char *want, const char *what)
{
    int rc = 0;
    lg_scene *s = gt_load_file(path, NULL, err, sizeof err, &rc);
    const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
    CHECKF(!s && rc < 0 && strstr(err, base) && strstr(err, want),
           "%s: rc %d, message '%s' (want '%s')", what, rc, err, want);
    lg_gltf_scene_free(s);
}

static void expect_fail_bytes(const char *name, const void *data, size_t size, const char *want,
                              const char *what)
{
    gt_write(name, data, size);
    expect_fail_file(gt_path(name), want, what);
}

static void expect_fail_json(const char *json, const char *want, const char *what)
{
    expect_fail_bytes("bad.gltf", json, strlen(json), want, what);
}

static void case_bad_input(void)
{
    size_t n;
    uint8_t *glb = gt_read(gt_asset("meshes/bunny_cornell_box.glb"), &n);
    expect_fail_bytes("short.glb", glb, 5000, "truncated GLB", "truncated glb");
    expect_fail_bytes("tiny.glb", glb, 10, "truncated GLB", "header only");
    uint8_t *copy = malloc(n);
    memcpy(copy, glb, n);
    copy[1] = 'X';
    expect_fail_bytes("magic.glb", copy, n, "not a GLB file", "wrong magic");
    memcpy(copy, glb, n);
    uint32_t json_len;
    memcpy(&json_len, glb + 12, 4);
    uint32_t huge = 0x7ffffff0u;
    memcpy(copy + 20 + json_len, &huge, 4); /* the BIN chunk claims 2 GB */
    expect_fail_bytes("binlen.glb", copy, n, "BIN chunk", "BIN chunk length");
    memcpy(copy, glb, n);
    memcpy(copy + 12, &huge, 4); /* the JSON chunk claims 2 GB */
    expect_fail_bytes("jsonlen.glb", copy, n, "JSON chunk", "JSON chunk length");
    memcpy(copy, glb, n);
    memset(copy + 20, ' ', 40); /* corrupt JSON */
    expect_fail_bytes("json.glb", copy, n, "parse error", "corrupt JSON");
    free(copy);
    free(glb);

    /* Draco: a corrupt stream (its "DRACO" magic and the bytes after it) */
    glb = gt_read(gt_asset("meshes/draco-box/Box_Draco.glb"), &n);
    uint8_t *d = memmem(glb, n, "DRACO", 5);
    CHECK(d != NULL);
    if (d) {
        memset(d, 0x5a, 16);
        expect_fail_bytes("draco.glb", glb, n, "Draco", "Draco decode failure");
    }
    free(glb);

    /* a missing external buffer */
    expect_fail_json(
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"missing.bin\"}]}",
        "missing.bin", "missing buffer file");
    expect_fail_file(gt_path("does-not-exist.glb"), "cannot read it: No such file", "missing file");
    expect_fail_bytes("empty.gltf", "", 0, "neither a GLB", "empty file");
    expect_fail_json("garbage", "neither a GLB", "not JSON");

    /* geometry errors, over one 36-byte buffer of three points */
    static const float pts[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    char *uri = gt_data_uri(pts, sizeof pts);
    static const float nan_pts[] = { 0, 0, 0, NAN, 0, 0, 0, 1, 0 };
    static const float inf_pts[] = { 0, 0, 0, 1, 0, 0, 0, INFINITY, 0 };
    static const float huge_pts[] = { 0, 0, 0, 3e38f, 0, 0, 0, 1, 0 };
    char *nan_uri = gt_data_uri(nan_pts, sizeof nan_pts),
         *inf_uri = gt_data_uri(inf_pts, sizeof inf_pts);
    char *huge_uri = gt_data_uri(huge_pts, sizeof huge_pts);
    static const uint16_t bad_idx[] = { 0, 1, 7, 0 };
    char *idx_uri = gt_data_uri(bad_idx, sizeof bad_idx);
    static const struct {
        const char *buffers, *views, *accessors, *primitive, *extra, *want, *what;
    } cases[] = {
        { NULL, "{\"buffer\":0,\"byteLength\":36}",
          "{\"bufferView\":0,\"byteOffset\":24,\"componentType\":5126,"
          "\"count\":3,\"type\":\"VEC3\"}",
          NULL, "",
          "accessor 0 (POSITION of mesh 0 primitive 0): 3 elements of 12 "
          "bytes",
          "accessor past its bufferView" },
        { NULL, "{\"buffer\":0,\"byteOffset\":12,\"byteLength\":36}", NULL, NULL, "",
          "bufferView 0: bytes 12..48 lie "
          "outside buffer 0 (36 bytes)",
          "bufferView past its buffer" },
        { NULL, "{\"buffer\":3,\"byteLength\":36}", NULL, NULL, "", "buffer 3 does not exist",
          "buffer index" },
        { NULL, NULL, "{\"bufferView\":5,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}",
          NULL, "", "bufferView 5 does not exist", "bufferView index" },
        { NULL, NULL,
          "{\"bufferView\":0,\"componentType\":5126,\"count\":4294967295,\"type\":\"VEC3\"}", NULL,
          "", "count 4294967295 is more than", "absurd count" },
        { NULL, NULL, "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"}",
          NULL, "", "2 components per element, want 3", "wrong type" },
        { NULL, NULL, "{\"bufferView\":0,\"componentType\":5125,\"count\":3,\"type\":\"VEC3\"}",
          NULL, "", "componentType 5125 (UNSIGNED_INT) is not supported", "wrong component type" },
        { "nan", NULL, NULL, NULL, "", "element 1 component 0 is NaN", "NaN position" },
        { "inf", NULL, NULL, NULL, "", "element 2 component 1 is infinite", "infinite position" },
        { "huge", NULL, NULL, NULL, "", "world bounds (0 .. 3e+38 on axis 0) go beyond +-1e30",
          "huge position" },
        { NULL, NULL, NULL, NULL,
          ",\"nodes\":[{\"mesh\":0,\"scale\":[1e30,1e30,1e30],\"children\":[1]},"
          "{\"mesh\":0,\"scale\":[1e30,1e30,1e30]}]",
          "node 1: its world transform overflows", "transform overflow" },
        { "idx", "{\"buffer\":0,\"byteLength\":36},{\"buffer\":1,\"byteLength\":8}",
          "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},{\"bufferView\":1,"
          "\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}",
          "{\"attributes\":{\"POSITION\":0},\"indices\":1}", "",
          "index 7 at position 2 is out of range (3 vertices)", "index out of bounds" },
        { NULL, NULL, NULL, "{\"attributes\":{\"POSITION\":9}}", "", "accessor 9 does not exist",
          "accessor index" },
        { NULL, NULL, NULL, "{\"attributes\":{\"NORMAL\":0}}", "",
          "mesh 0 primitive 0: no POSITION", "no positions" },
        { NULL, NULL, NULL, "{\"attributes\":{\"POSITION\":0},\"material\":3}", "",
          "material 3 does not exist", "material index" },
        { NULL, NULL, NULL, NULL, ",\"extensionsRequired\":[\"EXT_meshopt_compression\"]",
          "requires extension 'EXT_meshopt_compression'", "unsupported required extension" },
        { NULL, NULL, NULL, NULL, ",\"nodes\":[{\"mesh\":0,\"children\":[1]},{\"children\":[0]}]",
          "its own ancestor", "cycle" },
        { NULL, NULL, NULL, NULL, ",\"nodes\":[{\"mesh\":0,\"children\":[0]}]", "its own child",
          "self cycle" },
        { NULL, NULL, NULL, NULL,
          ",\"nodes\":[{\"mesh\":0,\"children\":[2]},{\"children\":[2]},{}]",
          "node 2 has two parents (nodes 0 and 1)", "two parents" },
        { NULL, NULL, NULL, NULL, ",\"nodes\":[{\"mesh\":0,\"children\":[5]}]",
          "node 0: child 5 does not exist", "child index" },
        { NULL, NULL, NULL, NULL, ",\"nodes\":[{\"mesh\":4}]", "node 0: mesh 4 does not exist",
          "mesh index" },
        { NULL, NULL, NULL, NULL, ",\"nodes\":[{\"mesh\":0,\"rotation\":[0,0,0]}]",
          "need 16, 3, 4 and 3 numbers", "short rotation" },
        { NULL, NULL, NULL, NULL, ",\"nodes\":[{\"mesh\":0,\"rotation\":[0,0,0,0]}]",
          "quaternion has length 0", "zero quaternion" },
        { NULL, NULL, NULL, NULL,
          ",\"extras\":[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[["
          "]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]",
          "nested more than 64", "deep JSON" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        const char *buf = !cases[i].buffers                   ? uri
                          : !strcmp(cases[i].buffers, "nan")  ? nan_uri
                          : !strcmp(cases[i].buffers, "inf")  ? inf_uri
                          : !strcmp(cases[i].buffers, "huge") ? huge_uri
                                                              : uri;
        char *buffers =
            !cases[i].buffers || strcmp(cases[i].buffers, "idx")
                ? gt_fmt("{\"byteLength\":36,\"uri\":\"%s\"}", buf)
                : gt_fmt("{\"byteLength\":36,\"uri\":\"%s\"},{\"byteLength\":8,\"uri\":\"%s\"}",
                         uri, idx_uri);
        bool own_nodes = strstr(cases[i].extra, "\"nodes\"") != NULL;
        char *json = gt_fmt(
            "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[%s],\"bufferViews\":[%s],\"accessors\":[%s],"
            "\"meshes\":[{\"primitives\":[%s]}]%s%s}",
            buffers, cases[i].views ? cases[i].views : "{\"buffer\":0,\"byteLength\":36}",
            cases[i].accessors
                ? cases[i].accessors
                : "{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}",
            cases[i].primitive ? cases[i].primitive : "{\"attributes\":{\"POSITION\":0}}",
            own_nodes ? "" : ",\"nodes\":[{\"mesh\":0}]", cases[i].extra);
        expect_fail_json(json, cases[i].want, cases[i].what);
        free(json);
        free(buffers);
    }
    /* nodes nested deeper than LG_GLTF_MAX_DEPTH */
    size_t cap = 64 * (LG_GLTF_MAX_DEPTH + 10);
    char *nodes = malloc(cap), *o = nodes;
    o += sprintf(o, "[");
    for (int k = 0; k < LG_GLTF_MAX_DEPTH + 5; k++)
        o += sprintf(o, "%s{\"children\":[%d]}", k ? "," : "", k + 1);
    sprintf(o, ",{\"mesh\":0}]");
    char *json = gt_fmt(
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"%s\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"meshes\":[{\"primitives\":"
        "[{\"attributes\":{\"POSITION\":0}}]}],\"nodes\":%s}",
        uri, nodes);
    expect_fail_json(json, "levels deep (more than 256)", "deep hierarchy");
    /* a buffer claiming more bytes than its data URI holds */
    char *claim = gt_fmt(
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":1000000,\"uri\":\"%s\"}]}",
        uri);
    expect_fail_json(claim, "Failed to decode 'uri'", "buffer longer than its data");
    gt_write("short.bin", pts, 20);
    expect_fail_json(
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":36,\"uri\":\"short.bin\"}]}",
        "buffer 0: cannot read 'short.bin': it has 20 bytes, fewer than its byteLength 36",
        "buffer file shorter than byteLength");
    free(claim);
    free(json);
    free(nodes);
    free(uri);
    free(nan_uri);
    free(inf_uri);
    free(huge_uri);
    free(idx_uri);
}

/* ---- files the model may read (issue 8): confinement and limits ------------------------------ */

/* A one-triangle file whose buffer 0 is `uri` with `byte_length`, and `images` (a JSON array
 * or NULL); malloc'd. */
static char *tri_json(const char *uri, unsigned long long byte_length, const char *images)
{
    return gt_fmt(
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%llu,\"uri\":\"%s\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{\"bufferView\":0,"
        "\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}],\"meshes\":[{\"primitives\":[{"
        "\"attributes\":{\"POSITION\":0}}]}],\"nodes\":[{\"mesh\":0}]%s%s}",
        byte_length, uri, images ? ",\"images\":" : "", images ? images : "");
}

/* Loads `json` as NAME in the scratch folder and expects one triangle. */
static void expect_load(const char *name, const char *json, const char *what)
{
    lg_scene *s = gt_load_text(name, json, NULL, err, sizeof err, NULL);
    CHECKF(s && s->features.triangles == 1, "%s: %s", what, s ? "not one triangle" : err);
    lg_gltf_scene_free(s);
}

/* Loads `json` as NAME and expects a failure whose message holds every string of `want`
 * (NULL-terminated) and none of `never`. */
static void expect_refused(const char *name, const char *json, const char *const *want,
                           const char *what)
{
    int rc = 0;
    lg_scene *s = gt_load_text(name, json, NULL, err, sizeof err, &rc);
    bool ok = !s && rc < 0 && strstr(err, name);
    for (const char *const *w = want; ok && *w; w++)
        ok = strstr(err, *w) != NULL;
    /* what the old loader printed after reading the file it should have refused */
    static const char *const never[] = {
        "bounds", "NaN", "infinite", "element", "File size mismatch", NULL
    };
    for (const char *const *n = never; ok && *n; n++)
        ok = !strstr(err, *n);
    CHECKF(ok, "%s: rc %d, message '%s' (want '%s'%s)", what, rc, err, want[0],
           want[1] ? " ..." : "");
    lg_gltf_scene_free(s);
}

/* "../" enough times to reach / from the scratch folder (at least 6), then `rest`. */
static char *climb(const char *rest)
{
    int depth = 0;
    for (const char *p = gt_path(""); *p; p++)
        depth += *p == '/';
    char *s = malloc(3 * (size_t)(depth + 6) + strlen(rest) + 1);
    s[0] = 0;
    for (int i = 0; i < (depth > 6 ? depth : 6); i++)
        strcat(s, "../");
    strcat(s, rest);
    return s;
}

static void on_alarm(int sig)
{
    (void)sig;
    static const char msg[] = "test_gltf: a load hung (a FIFO was waited on)\n";
    (void)!write(2, msg, sizeof msg - 1);
    _exit(1);
}

static void case_confinement(void)
{
    /* a FIFO must be refused at once: if a load waits on one, fail instead of hanging */
    signal(SIGALRM, on_alarm);
    alarm(20);
    static const float tri[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    gt_write("tri.bin", tri, sizeof tri);
    CHECK(mkdir(gt_path("sub"), 0755) == 0);
    gt_write("sub/a b+c.bin", tri, sizeof tri);
    CHECK(symlink("tri.bin", gt_path("inside.bin")) == 0);
    CHECK(symlink("../tri.bin", gt_path("sub/up.bin")) == 0);
    CHECK(symlink("/etc/passwd", gt_path("outside.bin")) == 0);
    CHECK(symlink("/etc", gt_path("etc")) == 0);
    CHECK(symlink("/dev/zero", gt_path("zero.bin")) == 0);
    CHECK(mkfifo(gt_path("fifo.bin"), 0644) == 0);
    char *json;

    /* allowed: links that stay inside, subfolders, percent-encoding ('+' is a plus), "."
     * and ".." that stay inside, a missing image (images are never read) */
    static const char *const ok[] = { "inside.bin", "sub/up.bin", "sub/a%20b+c.bin",
                                      "./sub/../tri.bin", "sub/../sub/../tri.bin" };
    for (size_t i = 0; i < sizeof ok / sizeof *ok; i++) {
        json = tri_json(ok[i], 36, "[{\"uri\":\"textures/missing.png\"},{\"uri\":\"tri.bin\"}]");
        expect_load("ok.gltf", json, ok[i]);
        free(json);
    }

    /* the README's promise, broken before: ../../../../../../etc/passwd was read and the error
     * reported world bounds computed from its bytes (byteLength = its size, so that the old
     * loader's size check passed) */
    struct stat st;
    unsigned long long passwd_size = stat("/etc/passwd", &st) == 0 ? (unsigned long long)st.st_size
                                                                   : 36;
    char *up = climb("etc/passwd");
    json = tri_json(up, passwd_size, NULL);
    char *want_up = gt_fmt("buffer 0: cannot read '%s': it leads to '/etc/passwd', outside '", up);
    expect_refused("escape.gltf", json, (const char *const[]){ want_up, NULL },
                   "../ to /etc/passwd");
    free(json);
    free(want_up);
    json = tri_json("../../../../../../etc/passwd", passwd_size, NULL);
    expect_refused("escape6.gltf", json,
                   (const char *const[]){
                       "cannot read '../../../../../../etc/passwd': it leads to '/", "outside '",
                       NULL },
                   "six ../");
    free(json);
    /* the same, percent-encoded */
    char *enc = climb("etc/passwd"), *e = malloc(strlen(enc) * 3 + 1), *o = e;
    for (const char *p = enc; *p; p++)
        o += *p == '.' ? sprintf(o, "%%2e") : *p == '/' ? sprintf(o, "%%2F") : sprintf(o, "%c", *p);
    json = tri_json(e, passwd_size, NULL);
    expect_refused("encoded.gltf", json,
                   (const char *const[]){ e, "leads to '/etc/passwd', outside", NULL },
                   "percent-encoded ../");
    free(json);
    free(enc);
    free(e);
    /* an absolute path, a scheme */
    json = tri_json("/etc/passwd", passwd_size, NULL);
    expect_refused("abs.gltf", json,
                   (const char *const[]){
                       "cannot read '/etc/passwd': it leads to '/etc/passwd', outside", NULL },
                   "absolute path");
    free(json);
    json = tri_json("file:///etc/passwd", passwd_size, NULL);
    expect_refused("scheme.gltf", json,
                   (const char *const[]){ "cannot read 'file:///etc/passwd': only relative paths",
                                          NULL },
                   "file: URI");
    free(json);
    /* links that leave the folder: to a file, through a linked folder, to /dev/zero */
    json = tri_json("outside.bin", passwd_size, NULL);
    expect_refused("link.gltf", json,
                   (const char *const[]){ "buffer 0: cannot read 'outside.bin': it leads to "
                                          "'/etc/passwd', outside '",
                                          NULL },
                   "link to /etc/passwd");
    free(json);
    json = tri_json("etc/passwd", passwd_size, NULL);
    expect_refused("dirlink.gltf", json,
                   (const char *const[]){
                       "cannot read 'etc/passwd': it leads to '/etc/passwd', outside", NULL },
                   "linked folder");
    free(json);
    json = tri_json("zero.bin", 36, NULL);
    expect_refused("zero.gltf", json,
                   (const char *const[]){
                       "cannot read 'zero.bin': it leads to '/dev/zero', outside", NULL },
                   "link to /dev/zero");
    free(json);
    /* not a regular file: refused at once (the alarm above fails the test if it waits) */
    json = tri_json("fifo.bin", 36, NULL);
    expect_refused("fifo.gltf", json,
                   (const char *const[]){
                       "cannot read 'fifo.bin': it is a FIFO, not a regular file", NULL },
                   "FIFO buffer");
    free(json);
    json = tri_json("sub", 36, NULL);
    expect_refused("dir.gltf", json,
                   (const char *const[]){ "cannot read 'sub': it is a directory", NULL },
                   "folder buffer");
    free(json);
    /* malformed uris */
    json = tri_json("tri%2.bin", 36, NULL);
    expect_refused("pct.gltf", json,
                   (const char *const[]){ "cannot read 'tri%2.bin': malformed percent-encoding",
                                          NULL },
                   "bad percent-encoding");
    free(json);
    json = tri_json("tri.bin%00../x", 36, NULL);
    expect_refused("nul.gltf", json, (const char *const[]){ "NUL", NULL }, "encoded NUL");
    free(json);

    /* images are never read, but are held to the folder too */
    char *img_up = climb("etc/passwd"),
         *images = gt_fmt("[{\"uri\":\"tri.bin\"},{\"uri\":\"%s\"}]", img_up);
    json = tri_json("tri.bin", 36, images);
    char *want_img = gt_fmt("image 1: cannot read '%s': it leads to '/etc/passwd', outside",
                            img_up);
    expect_refused("image.gltf", json, (const char *const[]){ want_img, NULL }, "image ../");
    free(json);
    free(images);
    free(want_img);
    free(img_up);
    json = tri_json("tri.bin", 36, "[{\"uri\":\"../missing/x.png\"}]");
    expect_refused("image_missing.gltf", json,
                   (const char *const[]){ "image 0: cannot read '../missing/x.png': it leads to '",
                                          "outside", NULL },
                   "missing image outside");
    free(json);
    json = tri_json("tri.bin", 36, "[{\"uri\":\"outside.bin\"}]");
    expect_refused("image_link.gltf", json,
                   (const char *const[]){
                       "image 0: cannot read 'outside.bin': it leads to '/etc/passwd'", NULL },
                   "image link");
    free(json);

    /* from memory there is no folder: external buffers cannot be read at all */
    json = tri_json("tri.bin", 36, NULL);
    lg_scene *s = NULL;
    int rc = lg_gltf_load_memory((const uint8_t *)json, strlen(json), "mem.gltf", NULL, NULL, &s,
                                 NULL, err, sizeof err);
    CHECKF(
        rc < 0 && !s &&
            strstr(
                err,
                "file 'mem.gltf': buffer 0: cannot read 'tri.bin': the model was loaded from memory"),
        "from memory: rc %d, '%s'", rc, err);
    lg_gltf_scene_free(s);
    free(json);

    /* a GLB's external buffer: the same rules */
    json = tri_json("outside.bin", passwd_size, NULL);
    size_t jl = (strlen(json) + 3) & ~(size_t)3, total = 20 + jl;
    uint8_t *glb = calloc(1, total);
    uint32_t hdr[5] = { 0x46546C67u, 2, (uint32_t)total, (uint32_t)jl, 0x4E4F534Au };
    memcpy(glb, hdr, 20);
    memset(glb + 20, ' ', jl);
    memcpy(glb + 20, json, strlen(json));
    gt_write("ext.glb", glb, total);
    s = gt_load_file(gt_path("ext.glb"), NULL, err, sizeof err, &rc);
    CHECKF(!s && strstr(err, "cannot read 'outside.bin': it leads to '/etc/passwd'"), "GLB: %s",
           err);
    lg_gltf_scene_free(s);
    free(glb);
    free(json);
    free(up);
    alarm(0);
}

/* Peak resident memory of this process, KiB. */
static long max_rss_kib(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) == 0 ? ru.ru_maxrss : 0;
}

static void case_limits(void)
{
    signal(SIGALRM, on_alarm);
    alarm(20);
    long rss0 = max_rss_kib();
    static const float tri[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    gt_write("tri.bin", tri, sizeof tri);
    char *json;

    /* a byteLength larger than its file: refused with both numbers, before anything of that
     * size is allocated or read */
    json = tri_json("tri.bin", 1000000000ull, NULL);
    expect_refused("long.gltf", json,
                   (const char *const[]){
                       "buffer 0: cannot read 'tri.bin': it has 36 bytes, fewer than "
                       "its byteLength 1000000000",
                       NULL },
                   "byteLength > file");
    free(json);
    /* a file longer than its byteLength is valid glTF: only byteLength bytes are read */
    static const float tri_and_more[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 7, 7 };
    gt_write("longer.bin", tri_and_more, sizeof tri_and_more);
    json = tri_json("longer.bin", 36, NULL);
    expect_load("longer.gltf", json, "file longer than byteLength");
    free(json);
    /* a byteLength over the 2 GiB a buffer may hold (the file is sparse: no disk used) */
    int fd = open(gt_path("huge.bin"), O_CREAT | O_WRONLY | O_TRUNC, 0644);
    CHECK(fd >= 0 && ftruncate(fd, (off_t)LG_GLTF_MAX_BUFFER + 4096) == 0);
    close(fd);
    json = tri_json("huge.bin", (unsigned long long)LG_GLTF_MAX_BUFFER + 1, NULL);
    expect_refused("huge.gltf", json,
                   (const char *const[]){ "buffer 0: byteLength 2147483649 is more than the 2 GiB",
                                          NULL },
                   "byteLength over the limit");
    free(json);
    /* three 2 GiB buffers: over the 4 GiB of external buffers a model may read */
    char *three = gt_fmt(
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":%llu,\"uri\":\"huge.bin\"},"
        "{\"byteLength\":%llu,\"uri\":\"huge.bin\"},{\"byteLength\":%llu,\"uri\":\"huge.bin\"}]}",
        (unsigned long long)LG_GLTF_MAX_BUFFER, (unsigned long long)LG_GLTF_MAX_BUFFER,
        (unsigned long long)LG_GLTF_MAX_BUFFER);
    expect_refused("three.gltf", three,
                   (const char *const[]){
                       "buffer 2: the external buffers' byteLengths add up to more "
                       "than the 4 GiB",
                       NULL },
                   "external total");
    free(three);

    /* the file itself over LG_GLTF_MAX_FILE (sparse), a FIFO, a device: refused unread */
    fd = open(gt_path("big.gltf"), O_CREAT | O_WRONLY | O_TRUNC, 0644);
    CHECK(fd >= 0 && ftruncate(fd, (off_t)LG_GLTF_MAX_FILE + 1) == 0);
    close(fd);
    expect_fail_file(gt_path("big.gltf"), "cannot read it: it is 2.0 GiB, over the 2.0 GiB limit",
                     "file over the limit");
    CHECK(mkfifo(gt_path("fifo.glb"), 0644) == 0);
    expect_fail_file(gt_path("fifo.glb"), "cannot read it: it is a FIFO, not a regular file",
                     "FIFO file");
    expect_fail_file("/dev/zero", "cannot read it: it is a character device", "device");
    CHECK(symlink("/dev/zero", gt_path("zero.glb")) == 0);
    expect_fail_file(gt_path("zero.glb"), "cannot read it: it is a character device",
                     "link to a device");

    /* none of it was read: the process grew by far less than one such file */
    long grown = max_rss_kib() - rss0;
    CHECKF(grown < 64 * 1024, "peak memory grew by %ld KiB", grown);
    alarm(0);
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*fn)(void);
    } cases[] = {
        { "assets", case_assets },
        { "draco", case_draco },
        { "instancing", case_instancing },
        { "normals_cube", case_normals_cube },
        { "normals_sphere", case_normals_sphere },
        { "normals_degenerate", case_normals_degenerate },
        { "primitives", case_primitives },
        { "hierarchy", case_hierarchy },
        { "cameras", case_cameras },
        { "lights", case_lights },
        { "materials", case_materials },
        { "reflectivity", case_reflectivity },
        { "medium", case_medium },
        { "bad_input", case_bad_input },
        { "confinement", case_confinement },
        { "limits", case_limits },
    };
    if (argc != 2) {
        fprintf(stderr, "usage: test_gltf CASE\n");
        return 2;
    }
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++)
        if (!strcmp(argv[1], cases[i].name)) {
            gt_init(cases[i].name);
            cases[i].fn();
            gt_cleanup(check_failures != 0);
            return check_report(argv[1]);
        }
    fprintf(stderr, "test_gltf: unknown case '%s'\n", argv[1]);
    return 2;
}
