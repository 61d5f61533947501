/* tests/common/testscene.c: see testscene.h. */
#include "testscene.h"

#include <math.h>

#include "lightgraph/vecmath.h"

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
