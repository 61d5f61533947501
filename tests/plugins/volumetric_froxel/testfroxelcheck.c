/*
 * Test plugin "testfroxelcheck": the closed form the froxel grid must meet, computed
 * independently of plugins/volumetric_froxel from the same inputs (vol_common.h's view
 * rays and fog length, lightgraph/medium.h's closed form).
 *
 *   froxel_closed_form   scene + base -> image (rgba32f, base's size): per pixel
 *       sum over the directional lights of L_c sigma_s p(g, dot(w, -L)) d seg(sigma_t d)
 *       (mode = energy_conserving) or L_c sigma_s p d (mode = thesis_one_slice: what the
 *       thesis's sum gives for a one-slice grid), d = vol_fog_length, alpha 1; unshadowed.
 */
#include <math.h>
#include <stdlib.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"

#include "vol_common.h"

typedef struct cf_state {
    uint32_t w, h;
} cf_state;

static int cf_prepare(lg_node *n)
{
    cf_state *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    n->user = st;
    lg_resource_info info;
    const lg_resource *b = lg_input(n, 1);
    if (!b || lg_describe(b, &info, n) != 0 || info.kind != LG_KIND_IMAGE ||
        !(info.image.flags & LG_IMAGE_DEPTH))
        return lg_error(n, "input 'base' is not an image with depth");
    st->w = info.image.width;
    st->h = info.image.height;
    lg_image_desc d = { .width = st->w, .height = st->h, .format = LG_FORMAT_RGBA32F };
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

static int cf_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    cf_state *st = n->user;
    const lg_scene *s = lg_scene_get(n, lg_input(n, 0));
    if (!s)
        return LG_ERR_INVALID;
    vol_setup *v = malloc(sizeof *v);
    if (!v)
        return LG_ERR_NOMEM;
    int rc = vol_setup_make(n, s, st->w, st->h, (float)lg_param_float(n, "z_limit"), NULL,
                            VOL_ACCEPT_DIRECTIONAL, v);
    lg_cpu_view bv, ov;
    if (!rc)
        rc = lg_map_cpu(n, lg_input(n, 1), LG_READ, &bv);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov);
    if (rc) {
        free(v);
        return rc;
    }
    bool thesis = lg_param_enum(n, "mode") == 1;
    float *o = ov.pixels;
    for (uint32_t y = 0; y < st->h; y++)
        for (uint32_t x = 0; x < st->w; x++) {
            size_t p = (size_t)y * st->w + x;
            double w[3];
            vol_ray(v, x + 0.5, y + 0.5, w);
            double d = vol_fog_length(v, x + 0.5, y + 0.5, bv.depth[p]);
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                for (uint32_t l = 0; l < v->n_lights; l++) {
                    const vol_light *L = &v->lights[l];
                    double cosv = -(w[0] * L->dir[0] + w[1] * L->dir[1] + w[2] * L->dir[2]);
                    double ph = lg_hg_phase(v->g, cosv);
                    sum += thesis ? L->l_c[c] * v->sigma_s[c] * ph * d
                                  : lg_medium_inscatter(L->l_c[c], v->sigma_s[c], v->sigma_t[c], ph,
                                                        d);
                }
                o[4 * p + c] = (float)sum;
            }
            o[4 * p + 3] = 1.0f;
        }
    free(v);
    return 0;
}

static void cf_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

static const char *const cf_modes[] = { "energy_conserving", "thesis_one_slice", NULL };
static const lg_param_desc cf_params[] = {
    { .key = "z_limit",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "view depth where the fog ends; 0 = the camera's zfar" },
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = cf_modes,
      .doc = "energy_conserving: the closed form; thesis_one_slice: without the segment "
             "factor" },
};
static const lg_port_desc cf_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene" },
    { .name = "base", .kind = LG_KIND_IMAGE, .doc = "the lit image with depth" },
};
static const lg_port_desc cf_outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "the closed-form in-scatter" },
};
static const lg_node_type cf_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "froxel_closed_form",
        .doc = "The closed-form in-scatter of an unshadowed homogeneous medium (tests)",
        LG_PARAMS(cf_params),
        LG_INPUTS(cf_inputs),
        LG_OUTPUTS(cf_outputs),
        .prepare = cf_prepare,
        .execute = cf_execute,
        .destroy = cf_destroy,
    },
};

LG_PLUGIN_DEFINE("testfroxelcheck", "1.0.0", "The closed form the froxel tests compare with",
                 cf_types)
