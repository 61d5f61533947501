/* plugins/volumetric_common: the view rays, lights, medium and shadow test every
 * volumetric plugin shares (vol_common.h). */
#include "vol_common.h"

#include <math.h>
#include <string.h>

/* 4x4 inverse in double (cofactors), column-major; 0 or -1 when singular. */
static int inv4(double out[16], const double m[16])
{
    double inv[16];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] +
             m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] -
             m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] +
             m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] -
              m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] -
             m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] +
             m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] -
             m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] +
              m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] +
             m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] -
             m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] +
              m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] -
              m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] -
             m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] +
             m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] -
              m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] +
              m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (!(fabs(det) > 0.0) || !isfinite(det))
        return -1;
    for (int i = 0; i < 16; i++)
        out[i] = inv[i] / det;
    return 0;
}

int vol_setup_make(lg_node *n, const lg_scene *s, uint32_t width, uint32_t height, float z_limit,
                   const lg_shadowmap *sm, vol_setup *out)
{
    memset(out, 0, sizeof *out);
    out->width = width;
    out->height = height;
    int rc = lg_scene_view_make(n, s, -1, width, height, &out->view);
    if (rc)
        return rc;
    double vp[16];
    for (int i = 0; i < 16; i++)
        vp[i] = out->view.view_proj[i];
    if (inv4(out->inv_view_proj, vp) != 0)
        return lg_error(n, "the camera's view-projection matrix is singular");
    out->eye[0] = out->view.eye.x;
    out->eye[1] = out->view.eye.y;
    out->eye[2] = out->view.eye.z;
    out->forward[0] = out->view.forward.x;
    out->forward[1] = out->view.forward.y;
    out->forward[2] = out->view.forward.z;
    out->z_limit = z_limit > 0.0f ? z_limit : out->view.zfar;
    if (!(out->z_limit > out->view.znear) || !isfinite(out->z_limit))
        return lg_error(n, "z_limit %g must lie beyond the camera's near plane %g",
                        (double)out->z_limit, (double)out->view.znear);
    lg_medium_coeffs(&s->medium, out->sigma_s, out->sigma_t);
    out->g = s->medium.g;
    for (uint32_t i = 0; i < s->n_lights; i++) {
        const lg_light *l = &s->lights[i];
        if (l->type != LG_LIGHT_DIRECTIONAL)
            continue;
        if (out->n_lights == VOL_MAX_LIGHTS)
            return lg_error(n, "the scene has more than %d directional lights (light %u '%s')",
                            VOL_MAX_LIGHTS, i, l->name ? l->name : "");
        vol_light *v = &out->lights[out->n_lights++];
        double d[3] = { l->direction[0], l->direction[1], l->direction[2] };
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(len > 0.0) || !isfinite(len))
            return lg_error(n, "light %u '%s': direction is zero or not finite", i,
                            l->name ? l->name : "");
        for (int c = 0; c < 3; c++)
            v->dir[c] = (float)(d[c] / len);
        lg_light_color(l, v->l_c);
        v->scene_index = i;
        v->shadow = -1;
        if (sm) {
            for (uint32_t k = 0; k < sm->n_lights; k++)
                if (sm->lights[k].light == i)
                    v->shadow = (int32_t)k;
            if (v->shadow < 0)
                lg_log(n, LG_LOG_WARN, "light %u '%s' has no shadow map: unshadowed", i,
                       l->name ? l->name : "");
        }
    }
    if (out->n_lights == 0)
        return lg_error(n, "the scene has no directional light");
    return 0;
}

static void unproject(const vol_setup *v, double x, double y, double z, double p[3])
{
    double ndc[4] = { 2.0 * x / v->width - 1.0, 2.0 * y / v->height - 1.0, z, 1.0 };
    double r[4] = { 0, 0, 0, 0 };
    for (int row = 0; row < 4; row++)
        for (int col = 0; col < 4; col++)
            r[row] += v->inv_view_proj[col * 4 + row] * ndc[col];
    for (int c = 0; c < 3; c++)
        p[c] = r[c] / r[3];
}

void vol_ray(const vol_setup *v, double x, double y, double dir[3])
{
    double p[3];
    unproject(v, x, y, 0.0, p);
    double len = 0.0;
    for (int c = 0; c < 3; c++) {
        dir[c] = p[c] - v->eye[c];
        len += dir[c] * dir[c];
    }
    len = sqrt(len);
    for (int c = 0; c < 3; c++)
        dir[c] /= len;
}

double vol_surface_distance(const vol_setup *v, double x, double y, float depth)
{
    if (!(depth < 1.0f) || !isfinite(depth))
        return INFINITY;
    double p[3], len = 0.0;
    unproject(v, x, y, 2.0 * (double)depth - 1.0, p);
    for (int c = 0; c < 3; c++)
        len += (p[c] - v->eye[c]) * (p[c] - v->eye[c]);
    return sqrt(len);
}

double vol_fog_length(const vol_setup *v, double x, double y, float depth)
{
    double w[3];
    vol_ray(v, x, y, w);
    double cosf_ = w[0] * v->forward[0] + w[1] * v->forward[1] + w[2] * v->forward[2];
    double limit = cosf_ > 0.0 ? (double)v->z_limit / cosf_ : INFINITY;
    double d = vol_surface_distance(v, x, y, depth);
    return d < limit ? d : limit;
}

float vol_shadow_cpu(const lg_shadowmap *sm, const float *atlas, int32_t rec, const double p[3])
{
    if (!sm || !atlas || rec < 0 || (uint32_t)rec >= sm->n_lights)
        return 1.0f;
    const lg_shadow_light *L = &sm->lights[rec];
    const float *m = L->view_proj;
    double c[4];
    for (int row = 0; row < 4; row++)
        c[row] = m[row] * p[0] + m[4 + row] * p[1] + m[8 + row] * p[2] + m[12 + row];
    double u = c[0] / c[3] * 0.5 + 0.5, vv = c[1] / c[3] * 0.5 + 0.5;
    double z = c[2] / c[3] * 0.5 + 0.5;
    if (!(u >= 0.0 && u < 1.0 && vv >= 0.0 && vv < 1.0) || !(z >= 0.0))
        return 1.0f;
    uint32_t res = sm->resolution;
    uint32_t tx = L->tile_x + (uint32_t)(u * res), ty = L->tile_y + (uint32_t)(vv * res);
    if (tx >= sm->atlas_width || ty >= sm->atlas_height)
        return 1.0f;
    float stored = atlas[(size_t)ty * sm->atlas_width + tx];
    return (float)z > stored + sm->bias_constant ? 0.0f : 1.0f;
}

uint32_t vol_scene_lights(lg_node *n)
{
    lg_resource_info info;
    const lg_resource *sc = lg_input(n, VOL_IN_SCENE);
    uint32_t l = 1;
    if (sc && lg_describe(sc, &info, n) == 0 && info.kind == LG_KIND_SCENE && info.scene)
        l = info.scene->dir_lights;
    return l < 1 ? 1 : l > VOL_MAX_LIGHTS ? VOL_MAX_LIGHTS : l;
}

int vol_declare_outputs(lg_node *n, uint32_t *width, uint32_t *height)
{
    lg_resource_info info;
    lg_assert_input(n, VOL_IN_SCENE); /* every volumetric method's scene is required */
    const lg_resource *base = lg_input(n, VOL_IN_BASE);
    if (!base || lg_describe(base, &info, n) != 0 || info.kind != LG_KIND_IMAGE)
        return lg_error(n, "input 'base' is not an image");
    if (!(info.image.flags & LG_IMAGE_DEPTH) || (info.image.flags & LG_IMAGE_CUBE))
        return lg_error(n,
                        "input 'base' (%ux%u) has no depth plane: connect a lit image "
                        "with depth (phong's out)",
                        info.image.width, info.image.height);
    /* the cpu and cl paths read base's pixels as floats as they are (and the NaN/Inf count
     * with them): another format would be read as garbage (found by lightgraph conform,
     * which fed an rgba16f base: 1e25 and NaN on cpu and cl, the right image on gl) */
    if (info.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n,
                        "input 'base' must be an rgba32f image (it is %s): phong's out is; "
                        "convert it first",
                        lg_format_name(info.image.format));
    *width = info.image.width;
    *height = info.image.height;
    lg_image_desc d = {
        .width = *width, .height = *height, .format = LG_FORMAT_RGBA32F, .flags = LG_IMAGE_DEPTH
    };
    int rc = lg_declare_image(n, VOL_OUT_OUT, &d);
    if (rc)
        return rc;
    d.flags = 0;
    return lg_declare_image(n, VOL_OUT_INSCATTER, &d);
}
