/* tests/common/testscene.c: see testscene.h. */
#include "testscene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A mesh's arrays while it grows; lg_mesh points into them once the scene is finished. */
typedef struct ts_mesh_data {
    float *pos, *nrm;
    uint32_t *idx;
    uint32_t nv, ni, cap_v, cap_i;
} ts_mesh_data;

/* The builder is the payload: the lg_scene comes first, so the pointer lg_ts_finish hands
 * out is the one lg_ts_free receives back from the host. */
struct lg_ts_builder {
    lg_scene s;
    lg_mesh *meshes;
    ts_mesh_data *data;
    lg_instance *instances;
    lg_material *materials;
    lg_light *lights;
    lg_camera *cameras;
    uint32_t cap_meshes, cap_instances, cap_materials, cap_lights, cap_cameras;
    bool failed;
    /* Where a failed builder's record calls write, so that callers need not test for NULL
     * between calls (lg_ts_publish reports the failure once). */
    union {
        lg_material material;
        lg_light light;
        lg_camera camera;
        uint32_t index;
    } scratch;
};

/* Makes room for `need` elements of `size` bytes in *arr (capacity *cap, doubled). */
static bool ts_reserve(lg_ts_builder *b, void **arr, uint32_t *cap, uint32_t need, size_t size)
{
    if (b->failed)
        return false;
    if (need <= *cap)
        return true;
    uint32_t c = *cap ? *cap : 4;
    while (c < need)
        c *= 2;
    void *p = realloc(*arr, (size_t)c * size);
    if (!p) {
        b->failed = true;
        return false;
    }
    memset((char *)p + (size_t)*cap * size, 0, (size_t)(c - *cap) * size);
    *arr = p;
    *cap = c;
    return true;
}

lg_ts_builder *lg_ts_begin(const char *source)
{
    lg_ts_builder *b = calloc(1, sizeof *b);
    if (!b)
        return NULL;
    b->s.struct_size = sizeof b->s;
    b->s.source = source;
    return b;
}

/* ---- meshes ---------------------------------------------------------------------------------- */

/* The mesh vertex and triangle calls append to, or NULL (failed, or no lg_ts_mesh yet:
 * then the builder fails, since the call has nowhere to go). */
static ts_mesh_data *ts_current(lg_ts_builder *b)
{
    if (!b->failed && b->s.n_meshes == 0)
        b->failed = true;
    return b->failed ? NULL : &b->data[b->s.n_meshes - 1];
}

uint32_t lg_ts_mesh(lg_ts_builder *b, const char *name, uint32_t material)
{
    uint32_t i = b->s.n_meshes, cap = b->cap_meshes;
    if (!ts_reserve(b, (void **)&b->meshes, &cap, i + 1, sizeof *b->meshes) ||
        !ts_reserve(b, (void **)&b->data, &b->cap_meshes, i + 1, sizeof *b->data))
        return 0;
    b->meshes[i].name = name;
    b->meshes[i].material = material;
    b->s.n_meshes = i + 1;
    return i;
}

static uint32_t ts_vertex(lg_ts_builder *b, const float p[3], const float n[3])
{
    ts_mesh_data *d = ts_current(b);
    uint32_t cap_n = d ? d->cap_v : 0;
    if (!d || !ts_reserve(b, (void **)&d->pos, &d->cap_v, d->nv + 1, 3 * sizeof(float)) ||
        !ts_reserve(b, (void **)&d->nrm, &cap_n, d->nv + 1, 3 * sizeof(float)))
        return 0;
    memcpy(d->pos + (size_t)d->nv * 3, p, 3 * sizeof(float));
    memcpy(d->nrm + (size_t)d->nv * 3, n, 3 * sizeof(float));
    return d->nv++;
}

uint32_t lg_ts_vertex(lg_ts_builder *b, lg_vec3 position, lg_vec3 normal)
{
    const float p[3] = { position.x, position.y, position.z };
    const float n[3] = { normal.x, normal.y, normal.z };
    return ts_vertex(b, p, n);
}

uint32_t lg_ts_vertex_d(lg_ts_builder *b, const double position[3], const double normal[3])
{
    const float p[3] = { (float)position[0], (float)position[1], (float)position[2] };
    const float n[3] = { (float)normal[0], (float)normal[1], (float)normal[2] };
    return ts_vertex(b, p, n);
}

void lg_ts_triangle(lg_ts_builder *b, uint32_t i0, uint32_t i1, uint32_t i2)
{
    ts_mesh_data *d = ts_current(b);
    if (!d || !ts_reserve(b, (void **)&d->idx, &d->cap_i, d->ni + 3, sizeof(uint32_t)))
        return;
    d->idx[d->ni++] = i0;
    d->idx[d->ni++] = i1;
    d->idx[d->ni++] = i2;
}

uint32_t *lg_ts_indices(lg_ts_builder *b)
{
    ts_mesh_data *d = ts_current(b);
    return d && d->idx ? d->idx : &b->scratch.index;
}

void lg_ts_grid_triangles(lg_ts_builder *b, uint32_t cols, uint32_t rows, bool flip)
{
    ts_mesh_data *d = ts_current(b);
    uint32_t w = cols + 1, need = w * (rows + 1);
    if (!d || d->nv < need) {
        b->failed = true; /* fewer vertices than the grid: a caller's mistake */
        return;
    }
    uint32_t first = d->nv - need;
    for (uint32_t j = 0; j < rows; j++)
        for (uint32_t i = 0; i < cols; i++) {
            uint32_t a = first + j * w + i;
            if (flip) {
                lg_ts_triangle(b, a, a + w + 1, a + 1);
                lg_ts_triangle(b, a, a + w, a + w + 1);
            } else {
                lg_ts_triangle(b, a, a + 1, a + w + 1);
                lg_ts_triangle(b, a, a + w + 1, a + w);
            }
        }
}

void lg_ts_quad(lg_ts_builder *b, const lg_vec3 *centre, lg_vec3 u, lg_vec3 v,
                const lg_vec3 *normal)
{
    lg_vec3 nrm = normal ? *normal : lg_v3_normalize_or(lg_v3_cross(u, v), lg_v3(0, 0, 1));
    static const float su[4] = { -1, 1, 1, -1 }, sv[4] = { -1, -1, 1, 1 };
    uint32_t base = 0;
    for (int k = 0; k < 4; k++) {
        lg_vec3 p = lg_v3_add(lg_v3_scale(u, su[k]), lg_v3_scale(v, sv[k]));
        if (centre)
            p = lg_v3_add(*centre, p);
        uint32_t i = lg_ts_vertex(b, p, nrm);
        if (k == 0)
            base = i;
    }
    lg_ts_triangle(b, base, base + 1, base + 2);
    lg_ts_triangle(b, base, base + 2, base + 3);
}

void lg_ts_grid(lg_ts_builder *b, lg_vec3 centre, lg_vec3 u, lg_vec3 v, uint32_t s)
{
    lg_vec3 nrm = lg_v3_normalize_or(lg_v3_cross(u, v), lg_v3(0, 0, 1));
    for (uint32_t j = 0; j <= s; j++)
        for (uint32_t i = 0; i <= s; i++) {
            float a = 2.0f * (float)i / (float)s - 1.0f, c = 2.0f * (float)j / (float)s - 1.0f;
            lg_ts_vertex(b, lg_v3_add(centre, lg_v3_add(lg_v3_scale(u, a), lg_v3_scale(v, c))),
                         nrm);
        }
    lg_ts_grid_triangles(b, s, s, false);
}

void lg_ts_grid_span(lg_ts_builder *b, uint32_t g, const double origin[3], const double span_u[3],
                     const double span_v[3], const double normal[3], bool flip)
{
    for (uint32_t j = 0; j <= g; j++)
        for (uint32_t i = 0; i <= g; i++) {
            double s = (double)i / g, r = (double)j / g, p[3];
            for (int k = 0; k < 3; k++)
                p[k] = origin[k] + s * span_u[k] + r * span_v[k];
            lg_ts_vertex_d(b, p, normal);
        }
    lg_ts_grid_triangles(b, g, g, flip);
}

void lg_ts_unit_cube(lg_ts_builder *b, bool grid_faces)
{
    /* per face: centre direction, u, v (u x v = the outward normal), all halved */
    static const float f[6][3][3] = {
        { { 1, 0, 0 }, { 0, 0, -1 }, { 0, 1, 0 } }, { { -1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },
        { { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, -1 } }, { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } },
        { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 } },  { { 0, 0, -1 }, { -1, 0, 0 }, { 0, 1, 0 } },
    };
    for (int i = 0; i < 6; i++) {
        lg_vec3 c = lg_v3_scale(lg_v3(f[i][0][0], f[i][0][1], f[i][0][2]), 0.5f);
        lg_vec3 u = lg_v3_scale(lg_v3(f[i][1][0], f[i][1][1], f[i][1][2]), 0.5f);
        lg_vec3 v = lg_v3_scale(lg_v3(f[i][2][0], f[i][2][1], f[i][2][2]), 0.5f);
        if (grid_faces)
            lg_ts_grid(b, c, u, v, 1);
        else
            lg_ts_quad(b, &c, u, v, NULL);
    }
}

void lg_ts_box(lg_ts_builder *b, lg_vec3 half)
{
    static const int axes[6][3] = { { 0, 1, 2 }, { 0, 1, 2 }, { 1, 2, 0 },
                                    { 1, 2, 0 }, { 2, 0, 1 }, { 2, 0, 1 } };
    static const float uv[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    const float hv[3] = { half.x, half.y, half.z };
    for (int f = 0; f < 6; f++) {
        int a = axes[f][0], bb = axes[f][1], c = axes[f][2];
        float s = f % 2 ? -1.0f : 1.0f;
        uint32_t base = 0;
        for (int k = 0; k < 4; k++) {
            float p[3], n[3] = { 0, 0, 0 };
            p[a] = s * hv[a];
            /* the tangent flipped on the negative face keeps the winding outward */
            p[bb] = s * uv[k][0] * hv[bb];
            p[c] = uv[k][1] * hv[c];
            n[a] = s;
            uint32_t i = ts_vertex(b, p, n);
            if (k == 0)
                base = i;
        }
        lg_ts_triangle(b, base, base + 1, base + 2);
        lg_ts_triangle(b, base, base + 2, base + 3);
    }
}

void lg_ts_uv_sphere(lg_ts_builder *b, const lg_vec3 *centre, float radius, uint32_t cols,
                     uint32_t rows)
{
    uint32_t first = 0;
    for (uint32_t j = 0; j <= rows; j++)
        for (uint32_t i = 0; i <= cols; i++) {
            double th = LG_PI * j / rows, ph = 2 * LG_PI * i / cols;
            lg_vec3 n = lg_v3((float)(sin(th) * cos(ph)), (float)cos(th),
                              (float)(-sin(th) * sin(ph)));
            lg_vec3 p = lg_v3(radius * n.x, radius * n.y, radius * n.z);
            if (centre)
                p = lg_v3(centre->x + p.x, centre->y + p.y, centre->z + p.z);
            uint32_t v = lg_ts_vertex(b, p, n);
            if (i == 0 && j == 0)
                first = v;
        }
    for (uint32_t j = 0; j < rows; j++)
        for (uint32_t i = 0; i < cols; i++) {
            uint32_t a = first + j * (cols + 1) + i, d = a + cols + 1;
            lg_ts_triangle(b, a, d, d + 1);
            lg_ts_triangle(b, a, d + 1, a + 1);
        }
}

/* ---- instances, materials, lights, cameras, medium ------------------------------------------- */

uint32_t lg_ts_instance(lg_ts_builder *b, uint32_t mesh, const float model[16])
{
    uint32_t i = b->s.n_instances;
    if (!ts_reserve(b, (void **)&b->instances, &b->cap_instances, i + 1, sizeof *b->instances))
        return 0;
    lg_instance *in = &b->instances[i];
    in->mesh = mesh;
    if (model)
        memcpy(in->model, model, sizeof in->model);
    else
        lg_m4_identity(in->model);
    lg_m4_normal_matrix(in->normal_matrix, in->model);
    b->s.n_instances = i + 1;
    return i;
}

lg_material *lg_ts_material(lg_ts_builder *b, const char *name)
{
    uint32_t i = b->s.n_materials;
    if (!ts_reserve(b, (void **)&b->materials, &b->cap_materials, i + 1, sizeof *b->materials))
        return &b->scratch.material;
    b->materials[i].name = name;
    b->s.n_materials = i + 1;
    return &b->materials[i];
}

lg_light *lg_ts_light(lg_ts_builder *b, const char *name, lg_light_type type)
{
    uint32_t i = b->s.n_lights;
    if (!ts_reserve(b, (void **)&b->lights, &b->cap_lights, i + 1, sizeof *b->lights))
        return &b->scratch.light;
    b->lights[i].name = name;
    b->lights[i].type = type;
    b->s.n_lights = i + 1;
    return &b->lights[i];
}

lg_light *lg_ts_dir_light(lg_ts_builder *b, const char *name, lg_vec3 direction, lg_vec3 color,
                          float intensity)
{
    lg_light *l = lg_ts_light(b, name, LG_LIGHT_DIRECTIONAL);
    l->direction[0] = direction.x, l->direction[1] = direction.y, l->direction[2] = direction.z;
    l->color[0] = color.x, l->color[1] = color.y, l->color[2] = color.z;
    l->intensity = intensity;
    return l;
}

lg_camera *lg_ts_camera(lg_ts_builder *b, const char *name, lg_vec3 position, lg_vec3 target,
                        lg_vec3 up, float yfov, float znear, float zfar)
{
    uint32_t i = b->s.n_cameras;
    if (!ts_reserve(b, (void **)&b->cameras, &b->cap_cameras, i + 1, sizeof *b->cameras))
        return &b->scratch.camera;
    lg_camera *c = &b->cameras[i];
    c->name = name;
    c->position[0] = position.x, c->position[1] = position.y, c->position[2] = position.z;
    c->target[0] = target.x, c->target[1] = target.y, c->target[2] = target.z;
    c->up[0] = up.x, c->up[1] = up.y, c->up[2] = up.z;
    c->yfov = yfov;
    c->znear = znear;
    c->zfar = zfar;
    b->s.n_cameras = i + 1;
    return c;
}

void lg_ts_medium(lg_ts_builder *b, float density, lg_vec3 scattering, lg_vec3 absorption, float g)
{
    lg_medium *m = &b->s.medium;
    m->present = true;
    m->density = density;
    m->scattering[0] = scattering.x, m->scattering[1] = scattering.y;
    m->scattering[2] = scattering.z;
    m->absorption[0] = absorption.x, m->absorption[1] = absorption.y;
    m->absorption[2] = absorption.z;
    m->g = g;
}

/* ---- the end --------------------------------------------------------------------------------- */

void lg_ts_abandon(lg_ts_builder *b)
{
    if (!b)
        return;
    for (uint32_t i = 0; i < b->s.n_meshes; i++) {
        free(b->data[i].pos);
        free(b->data[i].nrm);
        free(b->data[i].idx);
    }
    free(b->meshes);
    free(b->data);
    free(b->instances);
    free(b->materials);
    free(b->lights);
    free(b->cameras);
    free(b);
}

void lg_ts_free(void *scene)
{
    lg_ts_abandon(scene); /* the scene is the builder's first member */
}

lg_scene *lg_ts_finish(lg_ts_builder *b)
{
    if (!b)
        return NULL;
    if (b->failed) {
        lg_ts_abandon(b);
        return NULL;
    }
    for (uint32_t i = 0; i < b->s.n_meshes; i++) {
        lg_mesh *m = &b->meshes[i];
        const ts_mesh_data *d = &b->data[i];
        m->n_vertices = d->nv;
        m->n_indices = d->ni;
        m->positions = d->pos;
        m->normals = d->nrm;
        m->indices = d->idx;
    }
    b->s.meshes = b->meshes;
    b->s.instances = b->instances;
    b->s.materials = b->materials;
    b->s.lights = b->lights;
    b->s.cameras = b->cameras;
    lg_test_scene_bounds(&b->s, b->meshes);
    lg_scene_compute_features(&b->s);
    return &b->s;
}

int lg_ts_publish(lg_node *n, uint32_t port, lg_ts_builder *b)
{
    const char *source = b ? b->s.source : "?";
    lg_scene *s = lg_ts_finish(b);
    if (!s)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory building the test scene '%s'", source);
    return lg_declare_payload(n, port, LG_KIND_SCENE, &s->features, s, lg_ts_free);
}

void lg_test_scene_bounds(lg_scene *s, lg_mesh *meshes)
{
    for (uint32_t i = 0; i < s->n_meshes; i++) {
        lg_mesh *m = &meshes[i];
        for (int k = 0; k < 3; k++) {
            m->bounds_min[k] = INFINITY;
            m->bounds_max[k] = -INFINITY;
        }
        for (uint32_t v = 0; v < m->n_vertices; v++)
            for (int k = 0; k < 3; k++) {
                m->bounds_min[k] = fminf(m->bounds_min[k], m->positions[v * 3 + k]);
                m->bounds_max[k] = fmaxf(m->bounds_max[k], m->positions[v * 3 + k]);
            }
    }
    for (int k = 0; k < 3; k++) {
        s->bounds_min[k] = INFINITY;
        s->bounds_max[k] = -INFINITY;
    }
    for (uint32_t i = 0; i < s->n_instances; i++) {
        const lg_instance *in = &s->instances[i];
        if (in->mesh >= s->n_meshes)
            continue;
        const lg_mesh *m = &meshes[in->mesh];
        for (int c = 0; c < 8; c++) {
            lg_vec3 p = lg_v3(c & 1 ? m->bounds_max[0] : m->bounds_min[0],
                              c & 2 ? m->bounds_max[1] : m->bounds_min[1],
                              c & 4 ? m->bounds_max[2] : m->bounds_min[2]);
            p = lg_m4_point(in->model, p);
            float w[3] = { p.x, p.y, p.z };
            for (int k = 0; k < 3; k++) {
                s->bounds_min[k] = fminf(s->bounds_min[k], w[k]);
                s->bounds_max[k] = fmaxf(s->bounds_max[k], w[k]);
            }
        }
    }
}
