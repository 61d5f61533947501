/* Scene helpers of the SDK (lightgraph/scene.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/scene.h"
#include "lightgraph/shadowmap.h"

const lg_scene *lg_scene_get(lg_node *n, const lg_resource *res)
{
    lg_resource_info info;
    if (!res || lg_describe(res, &info, n) != 0) {
        lg_error(n, "no scene: the input is not connected");
        return NULL;
    }
    if (info.kind != LG_KIND_SCENE) {
        lg_error(n, "expects a scene, got a resource of another kind");
        return NULL;
    }
    if (!info.payload) {
        lg_error(n, "the scene on this input has features but no scene data (%s)",
                 info.neutral ? "a gated node's neutral result"
                              : "its producer declared no lg_scene payload");
        return NULL;
    }
    const lg_scene *s = info.payload;
    if (s->struct_size < offsetof(lg_scene, reserved)) {
        lg_error(n,
                 "the scene was made by a plugin built for an incompatible SDK "
                 "(struct_size %zu)",
                 s->struct_size);
        return NULL;
    }
    return s;
}

void lg_scene_compute_features(lg_scene *s)
{
    lg_scene_features f;
    memset(&f, 0, sizeof f);
    for (uint32_t i = 0; i < s->n_instances; i++) {
        uint32_t m = s->instances[i].mesh;
        if (m < s->n_meshes) {
            f.triangles += s->meshes[m].n_indices / 3;
            f.vertices += s->meshes[m].n_vertices;
        }
    }
    for (uint32_t i = 0; i < s->n_lights; i++) {
        if (s->lights[i].type == LG_LIGHT_DIRECTIONAL)
            f.dir_lights++;
        else if (s->lights[i].type == LG_LIGHT_POINT)
            f.point_lights++;
        else
            f.other_lights++;
    }
    f.medium = s->medium.present && s->medium.density > 0;
    f.medium_density = s->medium.present ? s->medium.density : 0.0f;
    f.medium_field = f.medium && s->medium.field != NULL; /* since ABI 3.2 */
    for (uint32_t i = 0; i < s->n_materials; i++)
        if (s->materials[i].ks > 0 &&
            (s->materials[i].os[0] > 0 || s->materials[i].os[1] > 0 || s->materials[i].os[2] > 0))
            f.specular = true;
    /* reflective: materials with a non-zero reflectivity that some instance draws */
    for (uint32_t i = 0; i < s->n_materials; i++) {
        const float *r = s->materials[i].reflectivity;
        if (!(r[0] > 0 || r[1] > 0 || r[2] > 0))
            continue;
        bool used = false;
        for (uint32_t k = 0; k < s->n_instances && !used; k++) {
            uint32_t m = s->instances[k].mesh;
            used = m < s->n_meshes && s->meshes[m].material == i;
        }
        f.reflective_materials += used;
    }
    /* textures, masked materials (over the materials some instance draws) and animated
     * instances, since ABI 3.1 */
    for (uint32_t i = 0; i < s->n_materials; i++) {
        bool used = false;
        for (uint32_t k = 0; k < s->n_instances && !used; k++) {
            uint32_t m = s->instances[k].mesh;
            used = m < s->n_meshes && s->meshes[m].material == i;
        }
        if (!used)
            continue;
        const lg_material_maps *mp = lg_material_maps_of(&s->materials[i]);
        const lg_texture_ref *refs[5] = { &mp->base_color, &mp->metallic_roughness, &mp->normal,
                                          &mp->occlusion, &mp->emissive };
        for (int r = 0; r < 5; r++)
            f.textures += refs[r]->texture >= 0;
        f.masked_materials += mp->alpha_mode != LG_ALPHA_OPAQUE;
    }
    if (lg_scene_is_animated(s)) {
        const lg_scene_animation *a = s->animation;
        for (uint32_t i = 0; i < s->n_instances; i++) {
            uint32_t k = a->instance_node[i];
            f.animated += k < a->n_nodes && a->nodes[k].animated;
        }
        /* a moving light or camera changes the picture as a moving instance does */
        for (uint32_t i = 0; a->light_node && i < s->n_lights; i++)
            f.animated += a->light_node[i] >= 0;
        for (uint32_t i = 0; a->camera_node && i < s->n_cameras; i++)
            f.animated += a->camera_node[i] >= 0;
    }
    f.probe = s->features.probe;
    s->features = f;
}

/* Slots: four arrays per mesh. */
enum { SLOT_POS = 0, SLOT_NRM, SLOT_UV, SLOT_IDX, SLOTS_PER_MESH };

static int mesh_of(lg_node *n, const lg_resource *res, uint32_t mesh, const lg_scene **s,
                   const lg_resource **owner)
{
    *s = lg_scene_get(n, res);
    if (!*s)
        return LG_ERR_INVALID;
    if (mesh >= (*s)->n_meshes)
        return lg_error(n, "mesh %u does not exist (the scene has %u)", mesh, (*s)->n_meshes);
    *owner = (*s)->geometry ? (*s)->geometry : res;
    return 0;
}

/* One GPU copy of one array: payload_gl_buffer or payload_cl_buffer. */
typedef int (*upload_fn)(lg_node *n, const lg_resource *owner, uint32_t slot, const void *data,
                         size_t size, void *out);

static int upload_gl(lg_node *n, const lg_resource *owner, uint32_t slot, const void *data,
                     size_t size, void *out)
{
    return lg_payload_gl_buffer(n, owner, slot, data, size, (uint32_t *)out);
}

static int upload_cl(lg_node *n, const lg_resource *owner, uint32_t slot, const void *data,
                     size_t size, void *out)
{
    return lg_payload_cl_buffer(n, owner, slot, data, size, (void **)out);
}

/* The mesh's arrays through `up`, into the four result slots (texcoords only if any). */
static int upload_mesh(lg_node *n, const lg_resource *res, uint32_t mesh, upload_fn up, void *pos,
                       void *nrm, void *uv, void *idx)
{
    const lg_scene *s;
    const lg_resource *owner = NULL;
    int rc = mesh_of(n, res, mesh, &s, &owner);
    if (rc)
        return rc;
    const lg_mesh *m = &s->meshes[mesh];
    uint32_t base = mesh * SLOTS_PER_MESH;
    size_t nv = m->n_vertices;
    if ((rc = up(n, owner, base + SLOT_POS, m->positions, nv * 3 * sizeof(float), pos)) ||
        (rc = up(n, owner, base + SLOT_NRM, m->normals, nv * 3 * sizeof(float), nrm)) ||
        (rc = up(n, owner, base + SLOT_IDX, m->indices, m->n_indices * sizeof(uint32_t), idx)))
        return rc;
    if (m->texcoords)
        rc = up(n, owner, base + SLOT_UV, m->texcoords, nv * 2 * sizeof(float), uv);
    return rc;
}

/* Since ABI 3.1: tangents and the second texture coordinates, in slots past the four per
 * mesh of the 3.0 arrays (so that a 3.0 plugin's slots keep their meaning). */
#define SLOT_3_1_BASE 0x80000000u
enum { SLOT_TAN = 0, SLOT_UV1, SLOTS_3_1_PER_MESH };

int lg_scene_mesh_gl(lg_node *n, const lg_resource *res, uint32_t mesh, lg_mesh_gl *out)
{
    memset(out, 0, sizeof *out);
    int rc = upload_mesh(n, res, mesh, upload_gl, &out->positions, &out->normals, &out->texcoords,
                         &out->indices);
    if (rc)
        return rc;
    const lg_scene *s;
    const lg_resource *owner = NULL;
    if ((rc = mesh_of(n, res, mesh, &s, &owner)))
        return rc;
    const lg_mesh *m = &s->meshes[mesh];
    if (!m->tangents && !m->texcoords1)
        return 0;
    if (mesh >= (UINT32_MAX - SLOT_3_1_BASE) / SLOTS_3_1_PER_MESH)
        return lg_error(n, "mesh %u: too many meshes for the GL copies of tangents", mesh);
    uint32_t base = SLOT_3_1_BASE + mesh * SLOTS_3_1_PER_MESH;
    size_t nv = m->n_vertices;
    if (m->tangents && (rc = upload_gl(n, owner, base + SLOT_TAN, m->tangents,
                                       nv * 4 * sizeof(float), &out->tangents)))
        return rc;
    if (m->texcoords1)
        rc = upload_gl(n, owner, base + SLOT_UV1, m->texcoords1, nv * 2 * sizeof(float),
                       &out->texcoords1);
    return rc;
}

int lg_scene_mesh_cl(lg_node *n, const lg_resource *res, uint32_t mesh, lg_mesh_cl *out)
{
    memset(out, 0, sizeof *out);
    return upload_mesh(n, res, mesh, upload_cl, &out->positions, &out->normals, &out->texcoords,
                       &out->indices);
}

/* ---- Textures (ABI 3.1) ---------------------------------------------------------------------- */

int lg_scene_texture_gl(lg_node *n, const lg_resource *res, int32_t texture, bool srgb,
                        uint32_t *out)
{
    *out = 0;
    const lg_scene *s = lg_scene_get(n, res);
    if (!s)
        return LG_ERR_INVALID;
    const lg_scene_textures *t = s->textures;
    uint32_t nt = t ? t->n_textures : 0;
    if (texture < 0 || (uint32_t)texture >= nt)
        return lg_error(n, "texture %d does not exist: the scene has %u texture%s", (int)texture,
                        nt, nt == 1 ? "" : "s");
    const lg_scene_texture *tex = &t->textures[texture];
    if (tex->image >= t->n_images)
        return lg_error(n, "texture %d uses image %u, the scene has %u", (int)texture, tex->image,
                        t->n_images);
    const lg_scene_image *img = &t->images[tex->image];
    if (!img->rgba8 || img->width == 0 || img->height == 0)
        return lg_error(n, "texture %d: image %u '%s' has no pixels (%ux%u)", (int)texture,
                        tex->image, img->name ? img->name : "", img->width, img->height);
    /* one GL texture per image and encoding: textures that differ only in their sampler
     * share it (the sampler is the pass's sampler object) */
    if (tex->image > (UINT32_MAX >> 1))
        return lg_error(n, "texture %d: image index %u too large", (int)texture, tex->image);
    const lg_resource *owner = s->geometry ? s->geometry : res;
    return lg_payload_gl_texture(n, owner, tex->image * 2u + (srgb ? 1u : 0u), img->rgba8,
                                 img->width, img->height,
                                 srgb ? 0x8C43u /* GL_SRGB8_ALPHA8 */ : 0x8058u /* GL_RGBA8 */,
                                 out);
}

static const lg_material_maps default_maps = {
    .base_color = { -1, 0, 1.0f, { 1, 0, 0, 1, 0, 0 }, { 0, 0 } },
    .metallic_roughness = { -1, 0, 1.0f, { 1, 0, 0, 1, 0, 0 }, { 0, 0 } },
    .normal = { -1, 0, 1.0f, { 1, 0, 0, 1, 0, 0 }, { 0, 0 } },
    .occlusion = { -1, 0, 1.0f, { 1, 0, 0, 1, 0, 0 }, { 0, 0 } },
    .emissive = { -1, 0, 1.0f, { 1, 0, 0, 1, 0, 0 }, { 0, 0 } },
    .alpha_mode = LG_ALPHA_OPAQUE,
    .alpha_cutoff = 0.5f,
};

const lg_material_maps *lg_material_maps_default(void)
{
    return &default_maps;
}

static float srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}

/* Texel index along one axis for wrap mode `wrap` (glTF's GL enums; 0 = repeat). */
static uint32_t wrap_index(int64_t i, uint32_t size, uint32_t wrap)
{
    int64_t n = (int64_t)size;
    if (wrap == LG_TEX_CLAMP_TO_EDGE)
        return (uint32_t)(i < 0 ? 0 : i >= n ? n - 1 : i);
    if (wrap == LG_TEX_MIRRORED_REPEAT) {
        int64_t p = i % (2 * n);
        if (p < 0)
            p += 2 * n;
        return (uint32_t)(p < n ? p : 2 * n - 1 - p);
    }
    int64_t p = i % n;
    return (uint32_t)(p < 0 ? p + n : p);
}

static void texel(const lg_scene_image *img, uint32_t x, uint32_t y, bool srgb, float out[4])
{
    const uint8_t *p = img->rgba8 + ((size_t)y * img->width + x) * 4;
    for (int c = 0; c < 3; c++)
        out[c] = srgb ? srgb_to_linear(p[c] / 255.0f) : p[c] / 255.0f;
    out[3] = p[3] / 255.0f;
}

void lg_scene_texture_sample(const lg_scene *s, const lg_texture_ref *r, const float uv[2],
                             bool srgb, float out[4])
{
    out[0] = out[1] = out[2] = out[3] = 1.0f;
    const lg_scene_textures *t = s ? s->textures : NULL;
    if (!t || !r || r->texture < 0 || (uint32_t)r->texture >= t->n_textures)
        return;
    const lg_scene_texture *tex = &t->textures[r->texture];
    if (tex->image >= t->n_images)
        return;
    const lg_scene_image *img = &t->images[tex->image];
    if (!img->rgba8 || img->width == 0 || img->height == 0 || !isfinite(uv[0]) || !isfinite(uv[1]))
        return;
    /* texel centres at half-integers, as GL samples */
    double x = (double)uv[0] * img->width - 0.5, y = (double)uv[1] * img->height - 0.5;
    /* keep the integer parts in range of int64 for absurd coordinates */
    if (fabs(x) > 1e15 || fabs(y) > 1e15)
        x = y = 0.0;
    if (tex->mag_filter == LG_TEX_NEAREST) {
        int64_t xi = (int64_t)floor(x + 0.5), yi = (int64_t)floor(y + 0.5);
        texel(img, wrap_index(xi, img->width, tex->wrap_s),
              wrap_index(yi, img->height, tex->wrap_t), srgb, out);
        return;
    }
    double fx = floor(x), fy = floor(y);
    float ax = (float)(x - fx), ay = (float)(y - fy);
    int64_t x0 = (int64_t)fx, y0 = (int64_t)fy;
    uint32_t xs[2] = { wrap_index(x0, img->width, tex->wrap_s),
                       wrap_index(x0 + 1, img->width, tex->wrap_s) };
    uint32_t ys[2] = { wrap_index(y0, img->height, tex->wrap_t),
                       wrap_index(y0 + 1, img->height, tex->wrap_t) };
    float q[4][4];
    texel(img, xs[0], ys[0], srgb, q[0]);
    texel(img, xs[1], ys[0], srgb, q[1]);
    texel(img, xs[0], ys[1], srgb, q[2]);
    texel(img, xs[1], ys[1], srgb, q[3]);
    for (int c = 0; c < 4; c++) {
        float top = q[0][c] + ax * (q[1][c] - q[0][c]);
        float bot = q[2][c] + ax * (q[3][c] - q[2][c]);
        out[c] = top + ay * (bot - top);
    }
}

bool lg_material_covers(const lg_scene *s, uint32_t material, const float *uv0, const float *uv1)
{
    if (!s || material >= s->n_materials)
        return true;
    const lg_material *m = &s->materials[material];
    const lg_material_maps *mp = lg_material_maps_of(m);
    if (mp->alpha_mode != LG_ALPHA_MASK)
        return true;
    float alpha = m->base_color[3];
    if (mp->base_color.texture >= 0 && uv0) {
        float uv[2], c[4];
        lg_texture_ref_uv(&mp->base_color, uv0, uv1, uv);
        lg_scene_texture_sample(s, &mp->base_color, uv, true, c);
        alpha *= c[3];
    }
    return alpha >= mp->alpha_cutoff;
}

/* ---- Rigid animation (ABI 3.1) --------------------------------------------------------------- */

bool lg_scene_is_animated(const lg_scene *s)
{
    return s && s->animation && s->animation->n_channels > 0 && s->animation->instance_node;
}

/* The channel's value at time t (clamped to its keys), `c` components. */
static void channel_value(const lg_anim_channel *ch, double t, uint32_t c, float *out)
{
    uint32_t n = ch->n_keys;
    bool cubic = ch->interpolation == LG_ANIM_CUBICSPLINE;
    /* value k: for CUBICSPLINE the middle of the triple */
#define VAL(k) (ch->values + ((size_t)(k) * (cubic ? 3 : 1) + (cubic ? 1 : 0)) * c)
    if (n == 1 || t <= ch->times[0]) {
        memcpy(out, VAL(0), c * sizeof(float));
        return;
    }
    if (t >= ch->times[n - 1]) {
        memcpy(out, VAL(n - 1), c * sizeof(float));
        return;
    }
    /* the key interval [k, k+1] holding t (binary search: times strictly increase) */
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (ch->times[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    double t0 = ch->times[lo], t1 = ch->times[hi], td = t1 - t0;
    double u = td > 0 ? (t - t0) / td : 0.0;
    const float *a = VAL(lo), *b = VAL(hi);
    if (ch->interpolation == LG_ANIM_STEP) {
        memcpy(out, a, c * sizeof(float));
    } else if (cubic) {
        /* glTF 2.0 Appendix C: p(u) = (2u^3 - 3u^2 + 1) v_k + td (u^3 - 2u^2 + u) b_k
         *                            + (-2u^3 + 3u^2) v_k+1 + td (u^3 - u^2) a_k+1,
         * b_k the out-tangent of key k, a_k+1 the in-tangent of key k+1 */
        const float *bk = ch->values + ((size_t)lo * 3 + 2) * c;
        const float *ak1 = ch->values + ((size_t)hi * 3 + 0) * c;
        double u2 = u * u, u3 = u2 * u;
        double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
               h11 = u3 - u2;
        for (uint32_t i = 0; i < c; i++)
            out[i] = (float)(h00 * a[i] + h10 * td * bk[i] + h01 * b[i] + h11 * td * ak1[i]);
        if (ch->path == LG_ANIM_ROTATION) {
            double l = 0;
            for (uint32_t i = 0; i < 4; i++)
                l += (double)out[i] * out[i];
            l = l > 0 ? 1.0 / sqrt(l) : 0.0;
            for (uint32_t i = 0; i < 4; i++)
                out[i] = (float)(out[i] * l);
        }
    } else if (ch->path == LG_ANIM_ROTATION) {
        /* slerp along the shorter arc */
        double d = 0;
        for (uint32_t i = 0; i < 4; i++)
            d += (double)a[i] * b[i];
        double sb = d < 0 ? -1.0 : 1.0;
        d = fabs(d);
        double wa, wb;
        if (d > 0.9995) {
            wa = 1 - u;
            wb = u;
        } else {
            double th = acos(d), st = sin(th);
            wa = sin((1 - u) * th) / st;
            wb = sin(u * th) / st;
        }
        double l = 0, q[4];
        for (uint32_t i = 0; i < 4; i++) {
            q[i] = wa * a[i] + wb * sb * b[i];
            l += q[i] * q[i];
        }
        l = l > 0 ? 1.0 / sqrt(l) : 0.0;
        for (uint32_t i = 0; i < 4; i++)
            out[i] = (float)(q[i] * l);
    } else {
        for (uint32_t i = 0; i < c; i++)
            out[i] = (float)(a[i] + u * ((double)b[i] - a[i]));
    }
#undef VAL
}

/* Column-major 4x4 of T * R * S, in double. */
static void trs_matrix(const float t[3], const float q[4], const float s[3], double m[16])
{
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double l = x * x + y * y + z * z + w * w;
    if (l > 0) {
        l = 1.0 / sqrt(l);
        x *= l, y *= l, z *= l, w *= l;
    } else {
        x = y = z = 0, w = 1;
    }
    double r[9] = { 1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
                    2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                    2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y) };
    for (int col = 0; col < 3; col++)
        for (int row = 0; row < 3; row++)
            m[col * 4 + row] = r[col * 3 + row] * s[col];
    m[3] = m[7] = m[11] = 0;
    m[12] = t[0], m[13] = t[1], m[14] = t[2], m[15] = 1;
}

static void mul4(const double a[16], const double b[16], double out[16])
{
    double r[16];
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double v = 0;
            for (int k = 0; k < 4; k++)
                v += a[k * 4 + row] * b[col * 4 + k];
            r[col * 4 + row] = v;
        }
    memcpy(out, r, sizeof r);
}

/* The normal matrix (inverse transpose of the 3x3), column-major; zero when singular. */
static void normal_matrix(const double m[16], float out[9])
{
    double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6],
           i = m[10];
    double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    double det = a * A + b * B + c * C;
    if (det == 0 || !isfinite(det)) {
        memset(out, 0, 9 * sizeof(float));
        return;
    }
    double inv = 1.0 / det;
    /* inverse transpose = cofactor matrix / det; cofactor (row r, col c) stored column-major */
    double cof[9] = { A,
                      B,
                      C,
                      -(b * i - c * h),
                      a * i - c * g,
                      -(a * h - b * g),
                      b * f - c * e,
                      -(a * f - c * d),
                      a * e - b * d };
    /* cof is listed row by row; the inverse transpose's element (r, c) is cof[r][c] / det */
    for (int r = 0; r < 3; r++)
        for (int c2 = 0; c2 < 3; c2++)
            out[c2 * 3 + r] = (float)(cof[r * 3 + c2] * inv);
}

/* World matrices of every node of `a` at `time` (rest: the rest pose, channels ignored).
 * Returns the malloc'd array (n_nodes of them), or NULL when out of memory. */
static double (*node_worlds(const lg_scene_animation *a, double time, bool rest))[16]
{
    uint32_t nn = a->n_nodes;
    /* local TRS per node: the rest pose, then the channels */
    float(*trs)[10] = malloc((size_t)(nn ? nn : 1) * sizeof *trs);
    double(*world)[16] = malloc((size_t)(nn ? nn : 1) * sizeof *world);
    uint8_t *done = calloc(nn ? nn : 1, 1);
    if (!trs || !world || !done) {
        free(trs), free(world), free(done);
        return NULL;
    }
    for (uint32_t k = 0; k < nn; k++) {
        memcpy(trs[k], a->nodes[k].translation, 3 * sizeof(float));
        memcpy(trs[k] + 3, a->nodes[k].rotation, 4 * sizeof(float));
        memcpy(trs[k] + 7, a->nodes[k].scale, 3 * sizeof(float));
    }
    for (uint32_t c = 0; !rest && c < a->n_channels; c++) {
        const lg_anim_channel *ch = &a->channels[c];
        if (ch->node >= nn || ch->n_keys == 0)
            continue;
        uint32_t off = ch->path == LG_ANIM_TRANSLATION ? 0 : ch->path == LG_ANIM_ROTATION ? 3 : 7;
        uint32_t comp = ch->path == LG_ANIM_ROTATION ? 4 : 3;
        channel_value(ch, time, comp, trs[ch->node] + off);
    }
    /* world matrices, parents first (iteratively: a parent index may follow its child) */
    for (uint32_t k = 0; k < nn; k++) {
        /* walk up to the first node already done, then down */
        uint32_t chain[256];
        uint32_t depth = 0, cur = k;
        while (!done[cur] && depth < 256) {
            chain[depth++] = cur;
            int32_t p = a->nodes[cur].parent;
            if (p < 0 || (uint32_t)p >= nn)
                break;
            cur = (uint32_t)p;
        }
        while (depth > 0) {
            uint32_t j = chain[--depth];
            double local[16];
            trs_matrix(trs[j], trs[j] + 3, trs[j] + 7, local);
            int32_t p = a->nodes[j].parent;
            if (p >= 0 && (uint32_t)p < nn && done[p])
                mul4(world[p], local, world[j]);
            else
                memcpy(world[j], local, sizeof local);
            done[j] = 1;
        }
    }
    free(trs), free(done);
    return world;
}

int lg_scene_pose(lg_node *node, const lg_scene *s, double time, lg_instance *out)
{
    if (!isfinite(time)) {
        if (node)
            lg_error(node, "cannot pose the scene at time %g: not a finite number", time);
        return LG_ERR_INVALID;
    }
    if (!lg_scene_is_animated(s)) {
        if (s && s->n_instances)
            memcpy(out, s->instances, s->n_instances * sizeof *out);
        return 0;
    }
    const lg_scene_animation *a = s->animation;
    uint32_t nn = a->n_nodes;
    double(*world)[16] = node_worlds(a, time, false);
    if (!world) {
        if (node)
            lg_error(node, "cannot pose the scene: out of memory for %u nodes", nn);
        return LG_ERR_NOMEM;
    }
    for (uint32_t i = 0; i < s->n_instances; i++) {
        out[i] = s->instances[i];
        uint32_t k = a->instance_node[i];
        if (k >= nn || !a->nodes[k].animated)
            continue;
        for (int e = 0; e < 16; e++)
            out[i].model[e] = (float)world[k][e];
        normal_matrix(world[k], out[i].normal_matrix);
    }
    free(world);
    return 0;
}

/* The inverse of an affine column-major 4x4 (false when its 3x3 is singular). */
static bool affine_inverse(const double m[16], double out[16])
{
    double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6],
           i = m[10];
    double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    double det = a * A + b * B + c * C;
    if (det == 0 || !isfinite(det))
        return false;
    double inv = 1.0 / det;
    /* inverse(r, c) = cofactor(c, r) / det */
    double r[9] = { A * inv, -(b * i - c * h) * inv, (b * f - c * e) * inv,
                    B * inv, (a * i - c * g) * inv,  -(a * f - c * d) * inv,
                    C * inv, -(a * h - b * g) * inv, (a * e - b * d) * inv }; /* row-major */
    memset(out, 0, 16 * sizeof(double));
    for (int row = 0; row < 3; row++) {
        for (int col = 0; col < 3; col++)
            out[col * 4 + row] = r[row * 3 + col];
        out[12 + row] = -(r[row * 3] * m[12] + r[row * 3 + 1] * m[13] + r[row * 3 + 2] * m[14]);
    }
    out[15] = 1;
    return true;
}

/* How node k moved from its rest pose to `time`: D = world(t) * world(rest)^-1, so that a
 * point placed at rest (a light's position, a camera's target) maps to D p. */
static bool node_motion(double (*world)[16], double (*rest)[16], uint32_t k, double d[16])
{
    double inv[16];
    if (!affine_inverse(rest[k], inv))
        return false;
    mul4(world[k], inv, d);
    return true;
}

static void move_point(const double d[16], float p[3])
{
    double x = p[0], y = p[1], z = p[2];
    for (int r = 0; r < 3; r++)
        p[r] = (float)(d[r] * x + d[4 + r] * y + d[8 + r] * z + d[12 + r]);
}

static void move_dir(const double d[16], float v[3])
{
    double x = v[0], y = v[1], z = v[2], o[3], l = 0;
    for (int r = 0; r < 3; r++) {
        o[r] = d[r] * x + d[4 + r] * y + d[8 + r] * z;
        l += o[r] * o[r];
    }
    if (!(l > 0))
        return;
    l = 1.0 / sqrt(l);
    for (int r = 0; r < 3; r++)
        v[r] = (float)(o[r] * l);
}

/* The lights or cameras (`lights` picks which) of `s` at `time`, into out. */
static int pose_carried(lg_node *node, const lg_scene *s, double time, bool lights, void *out)
{
    uint32_t n = lights ? s->n_lights : s->n_cameras;
    if (n)
        memcpy(out, lights ? (const void *)s->lights : (const void *)s->cameras,
               n * (lights ? sizeof(lg_light) : sizeof(lg_camera)));
    if (!isfinite(time)) {
        if (node)
            lg_error(node, "cannot pose the scene at time %g: not a finite number", time);
        return LG_ERR_INVALID;
    }
    const lg_scene_animation *a = lg_scene_is_animated(s) ? s->animation : NULL;
    const int32_t *carrier = !a ? NULL : lights ? a->light_node : a->camera_node;
    bool any = false;
    for (uint32_t i = 0; carrier && i < n; i++)
        any |= carrier[i] >= 0 && (uint32_t)carrier[i] < a->n_nodes;
    if (!any)
        return 0;
    double(*world)[16] = node_worlds(a, time, false);
    double(*rest)[16] = node_worlds(a, 0, true);
    if (!world || !rest) {
        free(world), free(rest);
        if (node)
            lg_error(node, "cannot pose the scene: out of memory for %u nodes", a->n_nodes);
        return LG_ERR_NOMEM;
    }
    for (uint32_t i = 0; i < n; i++) {
        double d[16];
        if (carrier[i] < 0 || (uint32_t)carrier[i] >= a->n_nodes ||
            !node_motion(world, rest, (uint32_t)carrier[i], d))
            continue;
        if (lights) {
            lg_light *l = &((lg_light *)out)[i];
            move_point(d, l->position);
            move_dir(d, l->direction);
        } else {
            lg_camera *c = &((lg_camera *)out)[i];
            move_point(d, c->position);
            move_point(d, c->target);
            move_dir(d, c->up);
        }
    }
    free(world), free(rest);
    return 0;
}

int lg_scene_pose_lights(lg_node *node, const lg_scene *s, double time, lg_light *out)
{
    return pose_carried(node, s, time, true, out);
}

int lg_scene_pose_cameras(lg_node *node, const lg_scene *s, double time, lg_camera *out)
{
    return pose_carried(node, s, time, false, out);
}

int lg_scene_at(lg_node *node, const lg_scene *s, double time, lg_scene *out)
{
    *out = *s;
    const lg_scene_animation *a = lg_scene_is_animated(s) ? s->animation : NULL;
    bool lights = false, cams = false;
    for (uint32_t i = 0; a && a->light_node && i < s->n_lights; i++)
        lights |= a->light_node[i] >= 0;
    for (uint32_t i = 0; a && a->camera_node && i < s->n_cameras; i++)
        cams |= a->camera_node[i] >= 0;
    lg_light *l = lights ? malloc(s->n_lights * sizeof *l) : NULL;
    lg_camera *c = cams ? malloc(s->n_cameras * sizeof *c) : NULL;
    if ((lights && !l) || (cams && !c)) {
        free(l), free(c);
        if (node)
            lg_error(node, "cannot pose the scene's lights and cameras: out of memory");
        return LG_ERR_NOMEM;
    }
    int rc = 0;
    if (l && !(rc = lg_scene_pose_lights(node, s, time, l)))
        out->lights = l;
    if (!rc && c && !(rc = lg_scene_pose_cameras(node, s, time, c)))
        out->cameras = c;
    if (rc) {
        free(l), free(c);
        *out = *s;
    }
    return rc;
}

void lg_scene_at_free(const lg_scene *s, lg_scene *out)
{
    if (out->lights != s->lights)
        free((void *)out->lights);
    if (out->cameras != s->cameras)
        free((void *)out->cameras);
    *out = *s;
}
