/* tests/common/testscene.{c,h}, the test plugins' scene builder: what each shape makes
 * (counts, the documented positions bit for bit, counter-clockwise outward winding), the
 * grid's triangles with and without flip, growth past the first capacities, bounds and
 * features at the end, a failed builder (no scene, no leak), and lg_ts_publish through a
 * fake host (the payload declared with its free function, or "out of memory" on the node). */
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include "common/check.h"
#include "common/testscene.h"

static lg_vec3 vtx(const lg_mesh *m, uint32_t i)
{
    return lg_v3(m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2]);
}

/* The triangles of m that face away from `inside` (their u x v points away); *inward
 * counts those that face it. */
static uint32_t outward_triangles_in(const lg_mesh *m, lg_vec3 inside, uint32_t *inward)
{
    uint32_t n = 0;
    *inward = 0;
    for (uint32_t t = 0; t + 2 < m->n_indices; t += 3) {
        lg_vec3 a = vtx(m, m->indices[t]), b = vtx(m, m->indices[t + 1]);
        lg_vec3 c = vtx(m, m->indices[t + 2]);
        lg_vec3 nrm = lg_v3_cross(lg_v3_sub(b, a), lg_v3_sub(c, a));
        lg_vec3 mid = lg_v3_scale(lg_v3_add(lg_v3_add(a, b), c), 1.0f / 3.0f);
        float d = lg_v3_dot(nrm, lg_v3_sub(mid, inside));
        n += d > 0.0f;
        *inward += d < 0.0f;
    }
    return n;
}

/* Every triangle of m faces away from `inside`: the count, or 0 if one faces it. */
static uint32_t outward_triangles(const lg_mesh *m, lg_vec3 inside)
{
    uint32_t inward, n = outward_triangles_in(m, inside, &inward);
    return inward ? 0 : n;
}

static bool same_bits(float a, float b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

static void test_quad_and_grid(void)
{
    lg_ts_builder *b = lg_ts_begin("quads");
    CHECK(b != NULL);
    lg_ts_material(b, "m")->kd = 1.0f;
    lg_ts_mesh(b, "q", 0);
    const lg_vec3 u = lg_v3(1, 0, 0), v = lg_v3(0, 2, 0), nz = lg_v3(0, 0, -1);
    lg_ts_quad(b, NULL, u, v, NULL);
    const lg_vec3 zero = lg_v3(0, 0, 0);
    lg_ts_quad(b, &zero, u, v, &nz);
    lg_ts_mesh(b, "g", 0);
    lg_ts_grid(b, lg_v3(0, 1, 0), lg_v3(2, 0, 0), lg_v3(0, 0, -2), 3);
    lg_ts_mesh(b, "flip", 0);
    const double o[3] = { 0, 0, 0 }, su[3] = { 1, 0, 0 }, sv[3] = { 0, 1, 0 }, up[3] = { 0, 0, 1 };
    lg_ts_grid_span(b, 1, o, su, sv, up, false);
    lg_ts_grid_span(b, 1, o, su, sv, up, true);
    lg_ts_instance(b, 0, NULL);
    lg_scene *s = lg_ts_finish(b);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK(s->n_meshes == 3 && s->n_materials == 1 && s->n_instances == 1);
    const lg_mesh *q = &s->meshes[0];
    CHECKF(q->n_vertices == 8 && q->n_indices == 12, "%u %u", q->n_vertices, q->n_indices);
    /* vertex order (-1,-1) (1,-1) (1,1) (-1,1); triangles (0,1,2) (0,2,3) from each base */
    static const uint32_t want_idx[12] = { 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7 };
    CHECK(memcmp(q->indices, want_idx, sizeof want_idx) == 0);
    CHECK(vtx(q, 0).x == -1 && vtx(q, 0).y == -2 && vtx(q, 2).x == 1 && vtx(q, 2).y == 2);
    /* no centre: 0 * -1 + 0 * -1 stays -0; a zero centre makes it +0 */
    CHECKF(same_bits(q->positions[2], -0.0f) && same_bits(q->positions[14], 0.0f),
           "z of vertex 0: %g (centre NULL), %g (centre 0)", q->positions[2], q->positions[14]);
    CHECK(q->normals[2] == 1.0f && q->normals[14] == -1.0f); /* u x v, then as given */
    CHECK(outward_triangles(q, lg_v3(0, 0, -1)) == 4);
    /* the 3 x 3 grid: 16 vertices, 18 triangles facing u x v = +Y, a = 2i/s - 1 */
    const lg_mesh *g = &s->meshes[1];
    CHECK(g->n_vertices == 16 && g->n_indices == 54);
    CHECK(outward_triangles(g, lg_v3(0, 0, 0)) == 18);
    CHECK(vtx(g, 1).x == 2.0f * (2.0f * 1.0f / 3.0f - 1.0f) && vtx(g, 5).y == 1.0f);
    CHECK(g->normals[1] == 1.0f);
    /* grid_span, one cell each way: (a, a+1, a+W+1) (a, a+W+1, a+W), then flipped */
    const lg_mesh *f = &s->meshes[2];
    static const uint32_t want_flip[12] = { 0, 1, 3, 0, 3, 2, 4, 7, 5, 4, 6, 7 };
    CHECK(f->n_vertices == 8 && f->n_indices == 12 &&
          memcmp(f->indices, want_flip, sizeof want_flip) == 0);
    /* bounds: only mesh 0 has an instance */
    CHECK(s->bounds_min[0] == -1 && s->bounds_max[1] == 2 && s->bounds_min[2] == 0);
    CHECK(g->bounds_min[0] == -2 && g->bounds_max[2] == 2);
    CHECK(s->features.triangles == 4);
    lg_ts_free(s);
}

static void test_solids(void)
{
    lg_ts_builder *b = lg_ts_begin("solids");
    lg_ts_material(b, "m");
    lg_ts_mesh(b, "cube quads", 0);
    lg_ts_unit_cube(b, false);
    lg_ts_mesh(b, "cube grids", 0);
    lg_ts_unit_cube(b, true);
    lg_ts_mesh(b, "box", 0);
    lg_ts_box(b, lg_v3(1, 2, 3));
    lg_ts_mesh(b, "sphere", 0);
    const lg_vec3 c = lg_v3(5, 0, 0);
    lg_ts_uv_sphere(b, &c, 2.0f, 12, 6);
    lg_ts_mesh(b, "origin sphere", 0);
    lg_ts_uv_sphere(b, NULL, 1.0f, 8, 4);
    float model[16];
    lg_m4_identity(model);
    model[0] = -1.0f; /* mirrored */
    model[13] = 3.0f;
    for (uint32_t i = 0; i < 5; i++)
        lg_ts_instance(b, i, i == 2 ? model : NULL);
    lg_scene *s = lg_ts_finish(b);
    CHECK(s != NULL);
    if (!s)
        return;
    for (int i = 0; i < 3; i++) {
        const lg_mesh *m = &s->meshes[i];
        CHECKF(m->n_vertices == 24 && m->n_indices == 36 &&
                   outward_triangles(m, lg_v3(0, 0, 0)) == 12,
               "%s: %u vertices, %u indices", m->name, m->n_vertices, m->n_indices);
    }
    /* the two cubes differ in their vertex order only */
    CHECK(memcmp(s->meshes[0].positions, s->meshes[1].positions, 24 * 12) != 0);
    CHECK(s->meshes[0].bounds_min[0] == -0.5f && s->meshes[1].bounds_max[2] == 0.5f);
    const lg_mesh *box = &s->meshes[2];
    CHECK(box->bounds_min[0] == -1 && box->bounds_max[1] == 2 && box->bounds_max[2] == 3);
    const lg_mesh *sp = &s->meshes[3];
    CHECK(sp->n_vertices == 13 * 7 && sp->n_indices == 12 * 6 * 6);
    /* a pole's triangles with two vertices on it are degenerate (at the south pole, nearly:
     * sin(pi) is not 0): none faces in, all 120 others face out */
    uint32_t inward, out = outward_triangles_in(sp, c, &inward);
    CHECKF(inward == 0 && out >= 12 * 6 * 2 - 2 * 12, "%u out, %u in", out, inward);
    CHECK(vtx(sp, 0).x == 5.0f && vtx(sp, 0).y == 2.0f && sp->normals[1] == 1.0f);
    const lg_mesh *o = &s->meshes[4];
    /* vertex (i, j) = (2, 1) of the 8 x 4 sphere: th = pi/4, ph = pi/2, exactly as built */
    double th = LG_PI / 4, ph = 2 * LG_PI * 2 / 8;
    float want_z = (float)(-sin(th) * sin(ph));
    CHECK(same_bits(o->positions[3 * (9 + 2) + 2], 1.0f * want_z));
    /* instance 2: mirrored, moved up; its normal matrix flips x */
    CHECK(s->instances[2].normal_matrix[0] == -1.0f && s->instances[0].normal_matrix[0] == 1.0f);
    CHECK(s->bounds_max[1] == 5.0f); /* the box's top, moved up by 3 */
    CHECK(s->features.triangles == (12 * 3 + 12 * 6 * 2 + 8 * 4 * 2));
    lg_ts_free(s);
}

/* Past every first capacity, records in order; the spoilt index and the unchecked
 * instance stay as given. */
static void test_growth(void)
{
    lg_ts_builder *b = lg_ts_begin("many");
    for (uint32_t i = 0; i < 9; i++) {
        lg_material *m = lg_ts_material(b, "m");
        m->ks = (float)i;
        lg_ts_dir_light(b, "l", lg_v3(0, -1, 0), lg_v3(1, 1, 1), (float)i);
        lg_camera *c = lg_ts_camera(b, "c", lg_v3(0, 0, (float)i), lg_v3(0, 0, 0), lg_v3(0, 1, 0),
                                    1.0f, 0.1f, 0.0f);
        c->aspect = 2.0f;
    }
    for (uint32_t k = 0; k < 7; k++) {
        uint32_t mi = lg_ts_mesh(b, "tri", k);
        CHECK(mi == k);
        for (uint32_t v = 0; v < 1000; v++)
            CHECK(lg_ts_vertex(b, lg_v3((float)v, (float)k, 0), lg_v3(0, 0, 1)) == v);
        for (uint32_t t = 0; t + 2 < 1000; t++)
            lg_ts_triangle(b, t, t + 1, t + 2);
        lg_ts_instance(b, k, NULL);
    }
    lg_ts_indices(b)[0] = 5000;
    lg_ts_instance(b, 99, NULL);
    lg_ts_medium(b, 0.5f, lg_v3(1, 2, 3), lg_v3(0, 0, 0), 0.25f);
    lg_scene *s = lg_ts_finish(b);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK(s->n_materials == 9 && s->n_lights == 9 && s->n_cameras == 9 && s->n_meshes == 7 &&
          s->n_instances == 8);
    for (uint32_t i = 0; i < 9; i++)
        CHECK(s->materials[i].ks == (float)i && s->lights[i].intensity == (float)i &&
              s->cameras[i].position[2] == (float)i && s->cameras[i].aspect == 2.0f &&
              s->lights[i].type == LG_LIGHT_DIRECTIONAL);
    for (uint32_t k = 0; k < 7; k++)
        CHECK(s->meshes[k].n_vertices == 1000 && s->meshes[k].n_indices == 998 * 3 &&
              s->meshes[k].material == k && s->meshes[k].positions[3 * 999] == 999.0f &&
              s->meshes[k].positions[1] == (float)k);
    CHECK(s->meshes[6].indices[0] == 5000 && s->meshes[5].indices[0] == 0);
    CHECK(s->instances[7].mesh == 99);
    CHECK(s->medium.present && s->medium.density == 0.5f && s->medium.scattering[2] == 3.0f &&
          s->medium.g == 0.25f && s->features.medium && s->features.dir_lights == 9);
    lg_ts_free(s);
}

/* A vertex without a mesh fails the builder: every later call does nothing, finish says
 * NULL (and frees it all: the sanitizer build would see a leak). */
static void test_failure(void)
{
    lg_ts_builder *b = lg_ts_begin("failed");
    lg_ts_vertex(b, lg_v3(0, 0, 0), lg_v3(0, 0, 1));
    lg_ts_material(b, "m")->kd = 1.0f; /* a scratch record: no crash */
    lg_ts_mesh(b, "late", 0);
    lg_ts_quad(b, NULL, lg_v3(1, 0, 0), lg_v3(0, 1, 0), NULL);
    lg_ts_indices(b)[0] = 1;
    CHECK(lg_ts_finish(b) == NULL);
    /* a grid with fewer vertices than it needs fails too */
    b = lg_ts_begin("short grid");
    lg_ts_mesh(b, "g", 0);
    lg_ts_vertex(b, lg_v3(0, 0, 0), lg_v3(0, 0, 1));
    lg_ts_grid_triangles(b, 1, 1, false);
    CHECK(lg_ts_finish(b) == NULL);
    lg_ts_abandon(lg_ts_begin("abandoned"));
    lg_ts_abandon(NULL);
    lg_ts_free(NULL);
    CHECK(lg_ts_finish(NULL) == NULL);
}

/* ---- lg_ts_publish through a fake host ------------------------------------------------------- */

static char last_error[512];
static void *declared;
static void (*declared_free)(void *);
static lg_resource_kind declared_kind;

static void host_error(lg_node *n, const char *fmt, va_list ap)
{
    (void)n;
    vsnprintf(last_error, sizeof last_error, fmt, ap);
}

static int host_declare_payload(lg_node *n, uint32_t port, lg_resource_kind kind,
                                const lg_scene_features *features, void *payload,
                                void (*free_payload)(void *))
{
    (void)n, (void)port, (void)features;
    declared_kind = kind;
    declared = payload;
    declared_free = free_payload;
    return 0;
}

static const lg_host_api host = {
    .struct_size = sizeof(lg_host_api),
    .abi_major = LG_ABI_MAJOR,
    .abi_minor = LG_ABI_MINOR,
    .error = host_error,
    .declare_payload = host_declare_payload,
};

static void test_publish(void)
{
    lg_node node = { .host = &host, .name = "scene" };
    lg_ts_builder *b = lg_ts_begin("published");
    lg_ts_mesh(b, "q", 0);
    lg_ts_quad(b, NULL, lg_v3(1, 0, 0), lg_v3(0, 1, 0), NULL);
    lg_ts_instance(b, 0, NULL);
    CHECK(lg_ts_publish(&node, 0, b) == 0);
    const lg_scene *s = declared;
    CHECK(declared_kind == LG_KIND_SCENE && declared_free == lg_ts_free && s &&
          !strcmp(s->source, "published") && s->features.triangles == 2);
    if (declared_free)
        declared_free(declared);
    b = lg_ts_begin("broken");
    lg_ts_triangle(b, 0, 1, 2); /* no mesh */
    declared = NULL;
    CHECK(lg_ts_publish(&node, 0, b) == LG_ERR_NOMEM && declared == NULL);
    CHECKF(strstr(last_error, "out of memory") && strstr(last_error, "'broken'"), "%s", last_error);
    CHECK(lg_ts_publish(&node, 0, NULL) == LG_ERR_NOMEM);
}

int main(void)
{
    test_quad_and_grid();
    test_solids();
    test_growth();
    test_failure();
    test_publish();
    return check_report("testscene_builder");
}
