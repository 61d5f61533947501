/* plugins/volumetric_common: the view rays, lights, medium and shadow test every
 * volumetric plugin shares (vol_common.h). */
#include "vol_common.h"

#include <math.h>
#include <stdlib.h>
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

static const char *lname(const lg_light *l)
{
    return l->name ? l->name : "";
}

static bool finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static unsigned accept_bit(lg_light_type t)
{
    return t == LG_LIGHT_DIRECTIONAL ? VOL_ACCEPT_DIRECTIONAL
           : t == LG_LIGHT_POINT     ? VOL_ACCEPT_POINT
           : t == LG_LIGHT_SPOT      ? VOL_ACCEPT_SPOT
                                     : 0u;
}

static const char *type_name(lg_light_type t)
{
    return t == LG_LIGHT_DIRECTIONAL ? "directional"
           : t == LG_LIGHT_POINT     ? "point"
           : t == LG_LIGHT_SPOT      ? "spot"
                                     : "unknown";
}

int vol_setup_make(lg_node *n, const lg_scene *s, uint32_t width, uint32_t height, float z_limit,
                   const lg_shadowmap *sm, unsigned accept, vol_setup *out)
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
    out->medium = s->medium;
    out->heterogeneous = lg_medium_is_heterogeneous(&s->medium);
    if (out->heterogeneous && !(accept & VOL_ACCEPT_FIELD))
        return lg_error(n,
                        "the scene's medium has a density field (%s), which this method does "
                        "not model: use volumetric_froxel or volumetric_reference, or a "
                        "homogeneous medium",
                        s->medium.field->kind == LG_FIELD_GRID  ? "a voxel grid"
                        : s->medium.field->kind == LG_FIELD_FBM ? "fBm noise"
                                                                : "height fog or a fog box");
    for (int c = 0; c < 3; c++) {
        out->scene_min[c] = s->bounds_min[c];
        out->scene_max[c] = s->bounds_max[c];
    }
    uint32_t skipped = 0;
    for (uint32_t i = 0; i < s->n_lights; i++) {
        const lg_light *l = &s->lights[i];
        if (!(accept & accept_bit(l->type))) {
            lg_log(n, LG_LOG_WARN, "light %u '%s': this method does not model %s lights: left out",
                   i, lname(l), type_name(l->type));
            skipped++;
            continue;
        }
        if (out->n_lights == VOL_MAX_LIGHTS)
            return lg_error(n, "the scene has more than %d %s (light %u '%s')", VOL_MAX_LIGHTS,
                            (accept & VOL_ACCEPT_LIGHTS) == VOL_ACCEPT_DIRECTIONAL
                                ? "directional lights"
                                : "lights of the types this method models",
                            i, lname(l));
        vol_light *v = &out->lights[out->n_lights++];
        v->type = l->type;
        double d[3] = { l->direction[0], l->direction[1], l->direction[2] };
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (l->type != LG_LIGHT_POINT && (!(len > 0.0) || !isfinite(len)))
            return lg_error(n, "light %u '%s': direction is zero or not finite", i, lname(l));
        for (int c = 0; c < 3; c++)
            v->dir[c] = len > 0.0 && isfinite(len) ? (float)(d[c] / len) : (c == 1 ? -1.0f : 0.0f);
        if (l->type != LG_LIGHT_DIRECTIONAL) {
            if (!finite3(l->position) || !isfinite(l->range) || l->range < 0.0f)
                return lg_error(n,
                                "%s light %u '%s': its position or range is not finite (or the "
                                "range is negative)",
                                type_name(l->type), i, lname(l));
            for (int c = 0; c < 3; c++)
                v->pos[c] = l->position[c];
            v->range = l->range;
        }
        if (l->type == LG_LIGHT_SPOT) {
            if (!isfinite(l->inner_cone) || !isfinite(l->outer_cone) || l->outer_cone < 0.0f)
                return lg_error(n, "spot light %u '%s': its cone angles are not finite", i,
                                lname(l));
            v->cos_inner = (float)cos((double)l->inner_cone);
            v->cos_outer = (float)cos((double)l->outer_cone);
        }
        lg_light_color(l, v->l_c);
        v->scene_index = i;
        v->shadow = -1;
        if (sm) {
            v->shadow = lg_shadowmap_find(sm, i);
            if (v->shadow < 0)
                lg_log(n, LG_LOG_WARN, "light %u '%s' has no shadow map: unshadowed", i, lname(l));
        }
    }
    if (out->n_lights == 0)
        return lg_error(n, skipped ? "the scene has no light of a type this method models"
                                   : "the scene has no light");
    return 0;
}

double vol_light_falloff(const vol_light *l, const double p[3], double to_light[3], double *dist)
{
    lg_light L = { .type = l->type };
    for (int c = 0; c < 3; c++) {
        L.direction[c] = l->dir[c];
        L.position[c] = l->pos[c];
    }
    L.range = l->range;
    double f = lg_light_falloff(&L, p, to_light, dist);
    if (l->type == LG_LIGHT_SPOT) {
        /* the cone from the stored cosines (lg_light_falloff would take the angles) */
        double tl[3], d;
        L.type = LG_LIGHT_POINT;
        f = lg_light_falloff(&L, p, tl, &d);
        double ca = -(tl[0] * l->dir[0] + tl[1] * l->dir[1] + tl[2] * l->dir[2]);
        f *= lg_spot_cone(ca, l->cos_inner, l->cos_outer);
        if (to_light)
            for (int c = 0; c < 3; c++)
                to_light[c] = tl[c];
        if (dist)
            *dist = d;
    }
    return f;
}

double vol_light_transmittance(const vol_setup *v, const vol_light *l, double dist, int c)
{
    if (l->type == LG_LIGHT_DIRECTIONAL || !isfinite(dist))
        return 1.0;
    return exp(-(double)v->sigma_t[c] * dist);
}

double vol_density(const vol_setup *v, const double p[3])
{
    return v->heterogeneous ? lg_medium_field_at(&v->medium, p) : 1.0;
}

/* The box a light's optical-depth volume covers: a bounded field's own box on each axis
 * where it is bounded (a cloud above the scene's geometry lies outside the scene's bounds:
 * clipping it to them clamped the cloud's upper half to the box's top cells, 2.3x too
 * bright against the reference), else the scene's bounds, grown by 1% so that surfaces
 * lie inside. */
static void tau_box(const lg_medium *medium, const float scene_min[3], const float scene_max[3],
                    double lo[3], double hi[3])
{
    const lg_density_field *f = medium->field;
    for (int c = 0; c < 3; c++) {
        double slo = scene_min[c], shi = scene_max[c];
        double pad = 0.01 * (shi - slo) + 1e-6;
        slo -= pad;
        shi += pad;
        bool bounded = f && fabs((double)f->bounds_min[c]) < 1e30 &&
                       fabs((double)f->bounds_max[c]) < 1e30 && f->bounds_max[c] > f->bounds_min[c];
        lo[c] = bounded ? (double)f->bounds_min[c] : slo;
        hi[c] = bounded ? (double)f->bounds_max[c] : shi;
        if (!(hi[c] > lo[c]))
            hi[c] = lo[c] + 1e-6;
    }
}

/* Distance along unit d from p to the exit of box [lo, hi] (p inside), or 0. */
static double box_exit(const double p[3], const double d[3], const double lo[3], const double hi[3])
{
    double t = INFINITY;
    for (int c = 0; c < 3; c++) {
        if (d[c] > 0.0)
            t = fmin(t, (hi[c] - p[c]) / d[c]);
        else if (d[c] < 0.0)
            t = fmin(t, (lo[c] - p[c]) / d[c]);
    }
    return isfinite(t) && t > 0.0 ? t : 0.0;
}

typedef struct tau_job {
    const lg_medium *medium;
    const vol_light *l;
    vol_tau_volume *out;
    double ext[3], step;
} tau_job;

/* One z layer of cells per index: each cell's march depends on its own position only, so
 * the volume has the same bits on any number of threads. */
static void tau_layers(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    (void)chunk;
    const tau_job *j = ctx;
    vol_tau_volume *out = j->out;
    const vol_light *l = j->l;
    for (uint32_t z = (uint32_t)begin; z < (uint32_t)end; z++)
        for (uint32_t y = 0; y < out->n[1]; y++)
            for (uint32_t x = 0; x < out->n[0]; x++) {
                uint32_t idx[3] = { x, y, z };
                double p[3], d[3], len;
                for (int c = 0; c < 3; c++)
                    p[c] = out->lo[c] + j->ext[c] * (double)idx[c] / (double)(out->n[c] - 1);
                if (l->type == LG_LIGHT_DIRECTIONAL) {
                    for (int c = 0; c < 3; c++)
                        d[c] = -(double)l->dir[c];
                    len = box_exit(p, d, out->lo, out->hi);
                } else {
                    double dd = 0.0;
                    for (int c = 0; c < 3; c++) {
                        d[c] = (double)l->pos[c] - p[c];
                        dd += d[c] * d[c];
                    }
                    dd = sqrt(dd);
                    for (int c = 0; c < 3; c++)
                        d[c] = dd > 0.0 ? d[c] / dd : 0.0;
                    len = fmin(dd, box_exit(p, d, out->lo, out->hi));
                }
                uint32_t steps = (uint32_t)ceil(len / j->step);
                double h = steps ? len / steps : 0.0, tau = 0.0;
                for (uint32_t i = 0; i < steps; i++) {
                    double q[3];
                    for (int c = 0; c < 3; c++)
                        q[c] = p[c] + d[c] * h * ((double)i + 0.5);
                    tau += lg_medium_field_at(j->medium, q) * h;
                }
                out->tau[(size_t)x + (size_t)out->n[0] * ((size_t)y + (size_t)out->n[1] * z)] =
                    (float)tau;
            }
}

int vol_tau_build_light(lg_node *n, const lg_medium *medium, const float scene_min[3],
                        const float scene_max[3], const vol_light *l, uint32_t res,
                        vol_tau_volume *out)
{
    memset(out, 0, sizeof *out);
    if (res < 2)
        res = 2;
    tau_box(medium, scene_min, scene_max, out->lo, out->hi);
    tau_job j = { .medium = medium, .l = l, .out = out };
    double longest = 0.0;
    for (int c = 0; c < 3; c++) {
        j.ext[c] = out->hi[c] - out->lo[c];
        longest = fmax(longest, j.ext[c]);
    }
    for (int c = 0; c < 3; c++) {
        double m = ceil((double)res * j.ext[c] / longest);
        out->n[c] = m < 2.0 ? 2u : (uint32_t)m;
    }
    size_t cells = (size_t)out->n[0] * out->n[1] * out->n[2];
    out->tau = malloc(cells * sizeof(float));
    if (!out->tau)
        return lg_error(n, "out of memory for a %ux%ux%u optical-depth volume", out->n[0],
                        out->n[1], out->n[2]);
    lg_account_alloc(n, cells * sizeof(float));
    j.step = 0.5 * longest / (double)res;
    int rc = lg_parallel_for(n, out->n[2], 1, tau_layers, &j);
    if (rc)
        vol_tau_free(n, out);
    return rc;
}

int vol_tau_build(lg_node *n, const vol_setup *v, uint32_t k, uint32_t res, vol_tau_volume *out)
{
    memset(out, 0, sizeof *out);
    if (k >= v->n_lights)
        return lg_error(n, "vol_tau_build: light %u of %u", k, v->n_lights);
    return vol_tau_build_light(n, &v->medium, v->scene_min, v->scene_max, &v->lights[k], res, out);
}

void vol_tau_free(lg_node *n, vol_tau_volume *t)
{
    if (t->tau) {
        lg_account_free(n, (size_t)t->n[0] * t->n[1] * t->n[2] * sizeof(float));
        free(t->tau);
    }
    memset(t, 0, sizeof *t);
}

double vol_tau_sample(const vol_tau_volume *t, const double p[3])
{
    if (!t->tau)
        return 0.0;
    double f[3];
    uint32_t i0[3];
    for (int c = 0; c < 3; c++) {
        double u = (p[c] - t->lo[c]) / (t->hi[c] - t->lo[c]) * (double)(t->n[c] - 1);
        u = u < 0.0 ? 0.0 : u > (double)(t->n[c] - 1) ? (double)(t->n[c] - 1) : u;
        double fl = floor(u);
        i0[c] = (uint32_t)fl;
        if (i0[c] >= t->n[c] - 1)
            i0[c] = t->n[c] - 2;
        f[c] = u - (double)i0[c];
    }
    double sum = 0.0;
    for (int c = 0; c < 8; c++) {
        uint32_t x = i0[0] + (c & 1), y = i0[1] + ((c >> 1) & 1), z = i0[2] + ((c >> 2) & 1);
        double w = ((c & 1) ? f[0] : 1.0 - f[0]) * (((c >> 1) & 1) ? f[1] : 1.0 - f[1]) *
                   (((c >> 2) & 1) ? f[2] : 1.0 - f[2]);
        sum += w * t->tau[(size_t)x + (size_t)t->n[0] * ((size_t)y + (size_t)t->n[1] * z)];
    }
    return sum;
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

void vol_ray_matrix(const vol_setup *v, float m[16])
{
    for (int col = 0; col < 4; col++) {
        const double *c = &v->inv_view_proj[col * 4];
        for (int row = 0; row < 3; row++)
            m[col * 4 + row] = (float)(c[row] - v->eye[row] * c[3]);
        m[col * 4 + 3] = (float)c[3];
    }
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
    return lg_shadowmap_visibility(sm, atlas, sm->lights[rec].light, p, 0.0);
}

uint32_t vol_scene_lights(lg_node *n, unsigned accept)
{
    lg_resource_info info;
    const lg_resource *sc = lg_input(n, VOL_IN_SCENE);
    uint32_t l = 1;
    if (sc && lg_describe(sc, &info, n) == 0 && info.kind == LG_KIND_SCENE && info.scene) {
        const lg_scene_features *f = info.scene;
        l = ((accept & VOL_ACCEPT_DIRECTIONAL) ? f->dir_lights : 0) +
            ((accept & VOL_ACCEPT_POINT) ? f->point_lights : 0) +
            ((accept & VOL_ACCEPT_SPOT) ? f->other_lights : 0);
    }
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
