/*
 * The phong plugin: local illumination of a scene on GL (TECHNIQUES.md §1, seed 1): the Phong
 * reflection model (or Blinn's) with depth cueing, many directional, point and spot lights,
 * shadows from a shadow-map input, and five shading methods.
 *
 *   phong   scene [+ shadows] -> image (rgba32f + depth): HDR linear radiance
 *
 * The lighting equation itself lives in shaders/common/phong.glsl (its C twin is
 * phong_model.h); shaders/phong/ say where each shading method evaluates it. One raster
 * pass (vertex, optional geometry, fragment stage); phong_half takes four passes.
 * README.md gives the ports, parameters, units, conventions and measured costs.
 *
 * The camera is lightgraph/scene_gl.h's (as for preview and shadowmap); the passes are
 * lg_gl_pass (lightgraph/gl_pass.h), which keep the programs, framebuffers and the scene's
 * draw data across frames and set and restore the GL state.
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl_pass.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "lightgraph/vecmath.h"
#include "phong_model.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"
#include "lightgraph/shadowmap.h"
#include "vol_common.h"

#include "phong.frag.h"
#include "phong.geom.h"
#include "phong.vert.h"
#include "phong_fullscreen.vert.h"
#include "phong_half.frag.h"

enum { PH_FLAT = 0, PH_GOURAUD, PH_PHONG, PH_MIXED, PH_HALF };
enum { PH_VIEWER_INFINITE = 0, PH_VIEWER_LOCAL };
enum { PH_NORMALS_SCENE = 0, PH_NORMALS_EQ13 };
enum { PH_CULL_NONE = 0, PH_CULL_MATERIAL };

/* Shadowed lights whose colours the per-vertex and per-facet modes carry separately (so that
 * their shadows stay per pixel); further shadowed lights are tested at the vertex. */
#define PH_MAX_SV 8
/* phong_half: neighbours within this relative linear depth count as the same surface */
#define PH_HALF_DEPTH_TOL 0.05f

/* std430 layouts of shaders/phong/phong_scene.glsl (the instances: lightgraph/scene_gl.h) */
typedef struct ph_gpu_light {
    float pos[4];
    float dir[4];
    float radiance[3];
    int32_t shadow;
    float cone[4];
} ph_gpu_light;

typedef struct ph_gpu_shadow {
    float view_proj[16];
    float tile[2];
    float texel_world;
    int32_t light;
    float light_pos[3];
    int32_t projection;
    float znear;
    float depth_range;
    int32_t n_faces;
    int32_t pad;
} ph_gpu_shadow;

LG_GL_BLOCK_SIZE(ph_gpu_light, 64);
LG_GL_BLOCK_OFFSET(ph_gpu_light, dir, 16);
LG_GL_BLOCK_OFFSET(ph_gpu_light, radiance, 32);
LG_GL_BLOCK_OFFSET(ph_gpu_light, shadow, 44);
LG_GL_BLOCK_OFFSET(ph_gpu_light, cone, 48);
LG_GL_BLOCK_SIZE(ph_gpu_shadow, 112);
LG_GL_BLOCK_OFFSET(ph_gpu_shadow, tile, 64);
LG_GL_BLOCK_OFFSET(ph_gpu_shadow, texel_world, 72);
LG_GL_BLOCK_OFFSET(ph_gpu_shadow, light, 76);
LG_GL_BLOCK_OFFSET(ph_gpu_shadow, light_pos, 80);
LG_GL_BLOCK_OFFSET(ph_gpu_shadow, projection, 92);
LG_GL_BLOCK_OFFSET(ph_gpu_shadow, n_faces, 104);

/* The pass's uniform block PhFrame (std140, shaders/phong/phong_scene.glsl): one upload per
 * pass with lg_gl_pass_uniforms. */
typedef struct ph_gpu_frame {
    float view_proj[16];
    float eye[3];
    int32_t n_lights;
    float view_dir_inf[3];
    int32_t viewer_local;
    float ambient[3];
    int32_t depth_cue;
    float K;
    int32_t spec_model;
    float n_scale;
    float mixed_cos;
    int32_t shadow_res;
    float bias_const;
    float bias_slope;
    float normal_offset;
    int32_t pcf_radius;
    float pcss_light_size;
    float pad[2];
} ph_gpu_frame;

LG_GL_BLOCK_SIZE(ph_gpu_frame, 160);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, eye, 64);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, n_lights, 76);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, view_dir_inf, 80);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, viewer_local, 92);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, ambient, 96);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, depth_cue, 108);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, K, 112);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, mixed_cos, 124);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, shadow_res, 128);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, normal_offset, 140);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, pcf_radius, 144);
LG_GL_BLOCK_OFFSET(ph_gpu_frame, pcss_light_size, 148);

/* The uniforms and bindings of a raster pass. Each shading mode compiles its own variant and
 * drops what it does not use, so all but the PhFrame block are optional. */
typedef struct ph_uniforms {
    lg_gl_uniform id_base, ka, kd, ks, shininess, od, os, double_sided;
    lg_gl_binding frame, lights, shadows, atlas;
    lg_gl_material_binds mat; /* the material's textures (shaders/common/material.glsl) */
    /* the medium's shadow (the LG_TAU variant only; absent elsewhere) */
    lg_gl_binding tau;
    lg_gl_uniform tau_lo, tau_hi, tau_n, sigma_t;
} ph_uniforms;

typedef struct ph_state {
    int shading, specular, blinn_x4, viewer, lights_at, normals, falloff, cull;
    bool depth_cue, per_frame;
    float K, ks_scale, ambient[3], background[3], mixed_cos;
    int64_t camera;
    uint32_t width, height;

    lg_gl_pass *pass; /* the raster pass, for program_sv shadowed varyings (phong_half:
                       * per-pixel Phong, drawn into the two quarter images) */
    int program_sv;
    ph_uniforms u;
    /* phong_half: the full-size pass that writes surface ids and depth, the full-screen
     * pass that assembles the output, and their images */
    lg_gl_pass *id_pass, *half_pass;
    ph_uniforms id_u;
    lg_gl_uniform h_size, h_near_far, h_depth_tol, h_background;
    lg_gl_binding h_depth, h_even, h_odd, h_id;
    lg_gl_texture id_tex;                 /* r32ui, full size */
    lg_gl_texture quarter[2];             /* rgba32f, ceil(w/2) x ceil(h/2): the pixels with x, y
                                           * even; odd */
    lg_gl_texture quarter_depth;          /* depth32f of the quarter passes */
    lg_gl_buffer lights_buf, shadows_buf; /* LgLights, LgShadows: filled again every execute */
    lg_gl_buffer *eq13; /* vertex_normals = eq13: one buffer per mesh (name 0 = not
                         * made) */
    uint32_t n_eq13;
    bool warned_shadow;

    /* The medium's shadow on surfaces (README.md, "Shadows of the medium"), only for a
     * scene whose medium has a density field: each light's optical-depth volume
     * (vol_tau_build_light), kept while the scene (by address), its field, its lights as
     * the shaders see them and the resolution stay, and their stack in one 3D texture. */
    bool medium_shadows;
    uint32_t tau_res;
    int program_tau;       /* st->pass compiled with LG_TAU (1) or without (0) */
    vol_tau_volume *tau;   /* n_tau volumes, owned */
    vol_light *tau_lights; /* what they were built for, n_tau */
    uint32_t n_tau;
    const lg_scene *tau_scene;
    lg_density_field tau_field;
    float tau_bounds[6];
    lg_gl_texture tau_tex; /* r32f, n.x x n.y x (n.z n_tau) */
    bool tau_uploaded;     /* tau_tex holds the volumes above */
} ph_state;

/* ---- create / prepare ------------------------------------------------------------------------ */

static int ph_create(lg_node *n)
{
    ph_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->shading = lg_param_enum(n, "shading");
    st->specular = lg_param_enum(n, "specular") == 1 ? LG_SPEC_BLINN : LG_SPEC_PHONG;
    st->blinn_x4 = lg_param_enum(n, "blinn_correction");
    st->viewer = lg_param_enum(n, "viewer");
    st->lights_at = lg_param_enum(n, "lights_at");
    st->normals = lg_param_enum(n, "vertex_normals");
    st->falloff = lg_param_enum(n, "falloff");
    st->cull = lg_param_enum(n, "cull");
    st->depth_cue = lg_param_bool(n, "depth_cue");
    st->per_frame = lg_param_bool(n, "per_frame");
    st->K = (float)lg_param_float(n, "k");
    st->ks_scale = (float)lg_param_float(n, "ks_scale");
    st->mixed_cos = (float)cos(lg_param_float(n, "mixed_threshold_deg") * (LG_PI / 180.0));
    st->camera = lg_param_int(n, "camera");
    st->medium_shadows = lg_param_bool(n, "medium_shadows");
    st->tau_res = (uint32_t)lg_param_int(n, "medium_shadow_res");
    const lg_value *a = lg_param(n, "ambient"), *bg = lg_param(n, "background");
    for (int i = 0; i < 3; i++) {
        st->ambient[i] = a ? (float)a->v[i] : 0.0f;
        st->background[i] = bg ? (float)bg->v[i] : 0.0f;
        if (!isfinite(st->ambient[i]) || !isfinite(st->background[i]))
            return lg_error(n, "%s[%d] = %g does not fit a float",
                            !isfinite(st->ambient[i]) ? "ambient" : "background", i,
                            !isfinite(st->ambient[i]) ? a->v[i] : bg->v[i]);
    }
    if (!isfinite(st->K))
        return lg_error(n, "K = %g does not fit a float", lg_param_float(n, "k"));
    return 0;
}

static int ph_prepare(lg_node *n)
{
    ph_state *st = n->user;
    int rc = lg_output_size_nonempty(n, "width", "height", &st->width, &st->height);
    if (rc)
        return rc;

    lg_resource_info info;
    lg_assert_input(n, 0);
    const lg_resource *sh = lg_input(n, 1);
    if (sh && (lg_describe(sh, &info, n) != 0 || info.kind != LG_KIND_SHADOWMAP))
        return lg_error(n, "input 'shadows' is not a shadow map");

    lg_image_desc d = { .width = st->width,
                        .height = st->height,
                        .format = LG_FORMAT_RGBA32F,
                        .flags = LG_IMAGE_DEPTH };
    rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    if (st->per_frame)
        lg_set_per_frame(n, true);
    return lg_set_device(n, LG_DEVICE_GL);
}

/* ---- camera (as plugins/preview) ------------------------------------------------------------- */

static bool ph_finite3(const float v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static bool ph_bounds_ok(const lg_scene *s)
{
    const float *lo = s->bounds_min, *hi = s->bounds_max;
    return ph_finite3(lo) && ph_finite3(hi) && lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2];
}

static const char *ph_mesh_name(const lg_mesh *m)
{
    return m->name ? m->name : "";
}

/* ---- lights ---------------------------------------------------------------------------------- */

static const char *ph_light_name(const lg_light *l)
{
    return l->name ? l->name : "";
}

/* The scene's lights as the shaders read them (phong_scene.glsl, LgLight), and the shadow
 * maps of every light type (LgShadow: one per map, a point light's six cube faces
 * consecutive); *n_shadow counts the shadowed lights, *n_maps the maps. */
static int ph_build_lights(lg_node *n, ph_state *st, const lg_scene *s, const lg_shadowmap *sm,
                           ph_gpu_light **out_l, ph_gpu_shadow **out_s, uint32_t *n_shadow,
                           uint32_t *n_maps)
{
    *out_l = NULL;
    *out_s = NULL;
    *n_shadow = 0;
    *n_maps = 0;
    uint32_t nl = s->n_lights;
    ph_gpu_light *gl = calloc(nl ? nl : 1, sizeof *gl);
    ph_gpu_shadow *gs = calloc(sm && sm->n_lights ? sm->n_lights : 1, sizeof *gs);
    if (!gl || !gs) {
        free(gl);
        free(gs);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u lights)", nl);
    }
    lg_vec3 centre = lg_v3(0, 0, 0);
    if (ph_bounds_ok(s))
        centre = lg_v3(0.5f * (s->bounds_min[0] + s->bounds_max[0]),
                       0.5f * (s->bounds_min[1] + s->bounds_max[1]),
                       0.5f * (s->bounds_min[2] + s->bounds_max[2]));
    int rc = 0;
    for (uint32_t i = 0; i < nl && !rc; i++) {
        const lg_light *l = &s->lights[i];
        ph_gpu_light *g = &gl[i];
        g->shadow = -1;
        for (int c = 0; c < 3; c++) {
            g->radiance[c] = l->color[c] * l->intensity;
            if (!isfinite(g->radiance[c]) || g->radiance[c] < 0.0f)
                rc = lg_error(n,
                              "light %u '%s': colour * intensity = %g (channel %d) is not a "
                              "finite value >= 0",
                              i, ph_light_name(l), (double)g->radiance[c], c);
        }
        if (rc)
            break;
        if (l->type == LG_LIGHT_DIRECTIONAL) {
            lg_vec3 d = lg_v3(l->direction[0], l->direction[1], l->direction[2]);
            lg_vec3 L = lg_v3_normalize_or(lg_v3_scale(d, -1.0f), lg_v3(0, 0, 0));
            if (lg_v3_dot(L, L) == 0.0f) {
                rc = lg_error(n,
                              "directional light %u '%s': direction [%g, %g, %g] has no "
                              "direction",
                              i, ph_light_name(l), (double)d.x, (double)d.y, (double)d.z);
                break;
            }
            g->dir[0] = L.x, g->dir[1] = L.y, g->dir[2] = L.z;
            continue;
        }
        if (l->type != LG_LIGHT_POINT && l->type != LG_LIGHT_SPOT) {
            rc = lg_error(n, "light %u '%s' has an unknown type %d", i, ph_light_name(l),
                          (int)l->type);
            break;
        }
        if (!ph_finite3(l->position) || !isfinite(l->range) || l->range < 0.0f) {
            rc = lg_error(n,
                          "light %u '%s': its position or range is not finite (or the "
                          "range is negative)",
                          i, ph_light_name(l));
            break;
        }
        float cone_x = -2.0f, cone_y = 1.0f; /* a point light: cos > -2 always */
        lg_vec3 spot_dir = lg_v3(0, -1, 0);
        if (l->type == LG_LIGHT_SPOT) {
            spot_dir = lg_v3_normalize_or(lg_v3(l->direction[0], l->direction[1], l->direction[2]),
                                          lg_v3(0, 0, 0));
            if (lg_v3_dot(spot_dir, spot_dir) == 0.0f || !isfinite(l->inner_cone) ||
                !isfinite(l->outer_cone)) {
                rc = lg_error(n,
                              "spot light %u '%s': its direction or cone angles are not "
                              "usable",
                              i, ph_light_name(l));
                break;
            }
            float co = cosf(l->outer_cone), ci = cosf(l->inner_cone);
            cone_x = co;
            cone_y = 1.0f / fmaxf(ci - co, 1e-6f);
        }
        lg_vec3 pos = lg_v3(l->position[0], l->position[1], l->position[2]);
        if (st->lights_at == PH_VIEWER_INFINITE) {
            /* the model's assumption (seed 1, 1.2.6): the light at infinity in the
             * direction it lies from the scene's centre; its falloff, range and cone are
             * evaluated once, at the centre */
            lg_vec3 d = lg_v3_sub(pos, centre);
            float dist = lg_v3_length(d);
            lg_vec3 L = lg_v3_normalize_or(d, lg_v3(0, 1, 0));
            float f = 1.0f;
            if (st->falloff)
                f = 1.0f / fmaxf(dist * dist, 1e-12f);
            if (l->range > 0.0f && dist > l->range)
                f = 0.0f;
            if (l->type == LG_LIGHT_SPOT) {
                float t = (lg_v3_dot(lg_v3_scale(L, -1.0f), spot_dir) - cone_x) * cone_y;
                t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
                f *= t * t;
            }
            for (int c = 0; c < 3; c++)
                g->radiance[c] *= f;
            g->dir[0] = L.x, g->dir[1] = L.y, g->dir[2] = L.z;
            continue;
        }
        g->pos[0] = pos.x, g->pos[1] = pos.y, g->pos[2] = pos.z;
        g->pos[3] = l->type == LG_LIGHT_SPOT ? 2.0f : 1.0f;
        g->dir[0] = spot_dir.x, g->dir[1] = spot_dir.y, g->dir[2] = spot_dir.z;
        g->dir[3] = l->range;
        g->cone[0] = cone_x;
        g->cone[1] = cone_y;
        g->cone[2] = st->falloff ? 1.0f : 0.0f;
    }

    uint32_t ns = 0, nmaps = 0;
    for (uint32_t k = 0; sm && k < sm->n_lights && !rc; k++) {
        const lg_shadow_light *sl = &sm->lights[k];
        if (sl->light >= nl) {
            rc = lg_error(n,
                          "input 'shadows': shadow map %u is for light %u, but the scene has "
                          "%u light%s (are the phong and shadow nodes given the same scene?)",
                          k, sl->light, nl, nl == 1 ? "" : "s");
            break;
        }
        if (gl[sl->light].shadow >= 0)
            continue; /* a later map of a light already taken (its cube's faces are) */
        /* the light's maps: one, or a cube's six consecutive faces */
        uint32_t nf = 1;
        if (sl->projection == LG_SHADOW_PERSPECTIVE && k + 5 < sm->n_lights &&
            sm->lights[k + 5].light == sl->light && sm->lights[k + 5].face == LG_SHADOW_FACE_NEG_Z)
            nf = 6;
        bool ok = sl->projection == LG_SHADOW_ORTHOGRAPHIC ||
                  (sl->projection == LG_SHADOW_PERSPECTIVE &&
                   sl->face < LG_SHADOW_FACE_PARABOLOID_FRONT);
        if (!ok) {
            if (!st->warned_shadow)
                lg_log(n, LG_LOG_WARN,
                       "input 'shadows': shadow map %u of light %u '%s' is a dual-paraboloid "
                       "map (face %u), which phong does not read: the light is unshadowed",
                       k, sl->light, ph_light_name(&s->lights[sl->light]), sl->face);
            st->warned_shadow = true;
            continue;
        }
        gl[sl->light].shadow = (int32_t)nmaps;
        for (uint32_t f = 0; f < nf; f++) {
            const lg_shadow_light *r = &sm->lights[k + f];
            ph_gpu_shadow *g = &gs[nmaps++];
            memcpy(g->view_proj, r->view_proj, sizeof g->view_proj);
            g->tile[0] = (float)r->tile_x;
            g->tile[1] = (float)r->tile_y;
            g->texel_world = r->texel_world;
            g->light = (int32_t)r->light;
            memcpy(g->light_pos, s->lights[r->light].position, sizeof g->light_pos);
            g->projection = (int32_t)r->projection;
            g->znear = r->znear;
            g->depth_range = r->depth_range;
            g->n_faces = f == 0 ? (int32_t)nf : 1;
        }
        ns++;
    }
    if (rc) {
        free(gl);
        free(gs);
        return rc;
    }
    *out_l = gl;
    *out_s = gs;
    *n_shadow = ns;
    *n_maps = nmaps;
    return 0;
}

/* ---- vertex normals by eq. 1-13 -------------------------------------------------------------- */

typedef struct ph_weld {
    uint32_t key[3];
    uint32_t vertex;
} ph_weld;

static int ph_weld_cmp(const void *a, const void *b)
{
    const ph_weld *x = a, *y = b;
    for (int i = 0; i < 3; i++)
        if (x->key[i] != y->key[i])
            return x->key[i] < y->key[i] ? -1 : 1;
    return x->vertex < y->vertex ? -1 : x->vertex > y->vertex;
}

/* Seed 1 eq. 1-13 over the facets that share a vertex *position*: vertices the file split
 * at one position (seams, poles, hard edges) are welded first, so that each gets the sum
 * over all the facets meeting there, as the seed's vertex A shared by four facets. */
static int ph_eq13_normals(lg_node *n, const lg_mesh *m, float *out)
{
    uint32_t nv = m->n_vertices;
    ph_weld *w = malloc((size_t)nv * sizeof *w);
    uint32_t *canon = malloc((size_t)nv * sizeof *canon);
    uint32_t *idx = malloc((size_t)m->n_indices * sizeof *idx);
    float *upos = malloc((size_t)nv * 3 * sizeof *upos);
    float *unrm = malloc((size_t)nv * 3 * sizeof *unrm);
    int rc = 0;
    if (!w || !canon || !idx || !upos || !unrm) {
        rc = lg_error_code(n, LG_ERR_NOMEM,
                           "out of memory (eq. 1-13 normals of mesh '%s', "
                           "%u vertices)",
                           ph_mesh_name(m), nv);
        goto done;
    }
    for (uint32_t v = 0; v < nv; v++) {
        for (int i = 0; i < 3; i++) {
            float f = m->positions[3 * (size_t)v + i];
            if (f == 0.0f)
                f = 0.0f; /* -0 and +0 are one position */
            memcpy(&w[v].key[i], &f, sizeof f);
        }
        w[v].vertex = v;
    }
    qsort(w, nv, sizeof *w, ph_weld_cmp);
    uint32_t nu = 0;
    for (uint32_t i = 0; i < nv; i++) {
        if (i == 0 || memcmp(w[i].key, w[i - 1].key, sizeof w[i].key) != 0) {
            memcpy(&upos[3 * (size_t)nu], &m->positions[3 * (size_t)w[i].vertex],
                   3 * sizeof(float));
            nu++;
        }
        canon[w[i].vertex] = nu - 1;
    }
    for (uint32_t i = 0; i < m->n_indices; i++)
        idx[i] = canon[m->indices[i]];
    if (lg_vertex_normals_eq13(upos, nu, idx, m->n_indices, unrm) != LG_OK) {
        rc = lg_error(n, "mesh '%s': eq. 1-13 normals could not be computed", ph_mesh_name(m));
        goto done;
    }
    for (uint32_t v = 0; v < nv; v++)
        memcpy(&out[3 * (size_t)v], &unrm[3 * (size_t)canon[v]], 3 * sizeof(float));
done:
    free(w);
    free(canon);
    free(idx);
    free(upos);
    free(unrm);
    return rc;
}

/* The GL buffer of mesh mi's eq. 1-13 normals, made on first use and kept. */
static int ph_eq13_buffer(lg_node *n, ph_state *st, const lg_scene *s, uint32_t mi, GLuint *buf)
{
    if (!st->eq13) {
        st->eq13 = calloc(s->n_meshes ? s->n_meshes : 1, sizeof *st->eq13);
        if (!st->eq13)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
        st->n_eq13 = s->n_meshes;
    }
    if (mi >= st->n_eq13)
        return lg_error(n, "mesh %u: the scene changed its mesh count between frames", mi);
    if (!st->eq13[mi].name) {
        const lg_mesh *m = &s->meshes[mi];
        float *nrm = malloc((size_t)m->n_vertices * 3 * sizeof *nrm);
        if (!nrm)
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
        int rc = ph_eq13_normals(n, m, nrm);
        if (!rc)
            rc = lg_gl_buffer_recreate(n, &st->eq13[mi], (size_t)m->n_vertices * 3 * sizeof(float),
                                       0, nrm);
        free(nrm);
        if (rc)
            return rc;
    }
    *buf = st->eq13[mi].name;
    return 0;
}

/* ---- passes ---------------------------------------------------------------------------------- */

static void ph_locate(lg_gl_pass *p, ph_uniforms *u)
{
    u->frame = lg_gl_pass_uniform_block(p, "PhFrame");
#define OPT(f, name) u->f = lg_gl_pass_uniform_optional(p, name)
    OPT(id_base, "u_id_base");
    OPT(ka, "u_ka");
    OPT(kd, "u_kd");
    OPT(ks, "u_ks");
    OPT(shininess, "u_shininess");
    OPT(od, "u_od");
    OPT(os, "u_os");
    OPT(double_sided, "u_double_sided");
#undef OPT
    u->lights = lg_gl_pass_binding_optional(p, GL_SHADER_STORAGE_BLOCK, "LgLights");
    u->shadows = lg_gl_pass_binding_optional(p, GL_SHADER_STORAGE_BLOCK, "LgShadows");
    u->atlas = lg_gl_pass_binding_optional(p, GL_SAMPLER, "u_atlas");
    u->tau = lg_gl_pass_binding_optional(p, GL_SAMPLER, "u_tau");
    u->tau_lo = lg_gl_pass_uniform_optional(p, "u_tau_lo");
    u->tau_hi = lg_gl_pass_uniform_optional(p, "u_tau_hi");
    u->tau_n = lg_gl_pass_uniform_optional(p, "u_tau_n");
    u->sigma_t = lg_gl_pass_uniform_optional(p, "u_sigma_t");
    /* the C mirrors against the compiled layout (their static checks hold the numbers) */
    if (u->lights.index >= 0)
        lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "LgLights", sizeof(ph_gpu_light));
    if (u->shadows.index >= 0)
        lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "LgShadows", sizeof(ph_gpu_shadow));
    lg_gl_pass_material_binds(p, &u->mat);
}

/* How many shadowed lights the per-vertex modes can carry as separate varyings here: each
 * takes two locations (front and back colour), on top of six and the two of the texture
 * coordinates and tangent (ABI 3.1). */
static int ph_sv_limit(const lg_gl *gl)
{
    GLint a = 0, b = 0, c = 0;
    gl->GetIntegerv(GL_MAX_VERTEX_OUTPUT_COMPONENTS, &a);
    gl->GetIntegerv(GL_MAX_GEOMETRY_OUTPUT_COMPONENTS, &b);
    gl->GetIntegerv(GL_MAX_FRAGMENT_INPUT_COMPONENTS, &c);
    GLint m = a < b ? a : b;
    m = m < c ? m : c;
    int locs = m / 4 - 8; /* with a margin for built-ins */
    int sv = locs > 8 ? (locs - 8) / 2 : 0;
    return sv < PH_MAX_SV ? sv : PH_MAX_SV;
}

/* A raster pass of the scene: the output's rgba32f colour (r32ui surface ids for phong_half's
 * id pass) and depth. */
static int ph_raster_pass(lg_node *n, const ph_state *st, int shading, int sv, bool geom, bool tau,
                          GLenum color, lg_gl_pass **out)
{
    /* LG_TAU only for a scene with a density field: every other scene compiles the same
     * source with the same defines as before the medium's shadow existed */
    char defines[192];
    snprintf(defines, sizeof defines,
             "#define LG_SHADING %d\n#define LG_SV %d\n#define LG_SV_ARR %d\n%s", shading, sv,
             sv > 0 ? sv : 1, tau ? "#define LG_TAU 1\n" : "");
    static const lg_gl_shader_src src[3] = {
        { GL_VERTEX_SHADER, lg_src_phong_vert_file, lg_src_phong_vert },
        { GL_FRAGMENT_SHADER, lg_src_phong_frag_file, lg_src_phong_frag },
        { GL_GEOMETRY_SHADER, lg_src_phong_geom_file, lg_src_phong_geom },
    };
    lg_gl_pass_desc d = { .name = shading == PH_HALF ? "phong (surface ids)" : "phong",
                          .stages = src,
                          .n_stages = geom ? 3 : 2,
                          .defines = defines,
                          .colors = { color },
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true,
                          .cull = st->cull == PH_CULL_MATERIAL ? LG_GL_CULL_BACK : LG_GL_CULL_NONE,
                          .scene = LG_GL_SCENE_POSITIONS | LG_GL_SCENE_NORMALS |
                                   LG_GL_SCENE_TEXCOORDS };
    return lg_gl_pass_create(n, &d, out);
}

static int ph_passes(lg_node *n, ph_state *st, int sv, bool tau)
{
    int rc;
    if (st->pass && (st->program_sv != sv || st->program_tau != (int)tau)) {
        lg_gl_pass_destroy(&st->pass);
    }
    if (!st->pass) {
        /* phong_half shades its two quarter images with the phong mode's program */
        int shading = st->shading == PH_HALF ? PH_PHONG : st->shading;
        if ((rc = ph_raster_pass(n, st, shading, sv, shading == PH_FLAT || shading == PH_MIXED, tau,
                                 GL_RGBA32F, &st->pass)))
            return rc;
        st->program_sv = sv;
        st->program_tau = tau;
        ph_locate(st->pass, &st->u);
    }
    if (st->shading == PH_HALF && (!st->id_pass || !st->half_pass)) {
        lg_gl_pass_destroy(&st->id_pass); /* after a failed attempt */
        if ((rc = ph_raster_pass(n, st, PH_HALF, 0, false, false, GL_R32UI, &st->id_pass)))
            return rc;
        ph_locate(st->id_pass, &st->id_u);
        static const lg_gl_shader_src c[2] = {
            { GL_VERTEX_SHADER, lg_src_phong_fullscreen_vert_file, lg_src_phong_fullscreen_vert },
            { GL_FRAGMENT_SHADER, lg_src_phong_half_frag_file, lg_src_phong_half_frag },
        };
        lg_gl_pass_desc d = { .name = "phong (phong_half assembly)",
                              .stages = c,
                              .n_stages = 2,
                              .colors = { GL_RGBA32F } };
        if ((rc = lg_gl_pass_create(n, &d, &st->half_pass)))
            return rc;
        lg_gl_pass *h = st->half_pass;
        st->h_size = lg_gl_pass_uniform(h, "u_size");
        st->h_near_far = lg_gl_pass_uniform(h, "u_near_far");
        st->h_depth_tol = lg_gl_pass_uniform(h, "u_depth_tol");
        st->h_background = lg_gl_pass_uniform(h, "u_background");
        st->h_depth = lg_gl_pass_texture(h, "u_depth");
        st->h_even = lg_gl_pass_texture(h, "u_even");
        st->h_odd = lg_gl_pass_texture(h, "u_odd");
        st->h_id = lg_gl_pass_texture(h, "u_id");
    }
    return 0;
}

/* ---- execute --------------------------------------------------------------------------------- */

/* Fills *buf (kept while it is large enough) with `bytes` of `data`: at least 16 bytes, so
 * that an empty array still binds. */
static int ph_upload(lg_node *n, lg_gl_buffer *buf, const void *data, size_t bytes)
{
    static const float zero[4];
    return lg_gl_buffer_recreate(n, buf, bytes ? bytes : sizeof zero, 0, bytes ? data : zero);
}

/* The shadow atlas's GL depth texture, read by the raster passes. The one place that knows
 * how the atlas reaches phong (today: the shadow map's `atlas` part, a depth-only image). */
static int phong_shadow_atlas(lg_node *n, const lg_shadowmap *sm, GLuint *tex)
{
    uint32_t color = 0, depth = 0;
    int rc = lg_map_gl(n, sm->atlas, LG_READ, &color, &depth);
    if (rc)
        return rc;
    if (!depth)
        return lg_error_code(n, LG_ERR_DEVICE,
                             "input 'shadows': the atlas has no GL depth "
                             "texture");
    *tex = depth;
    return 0;
}

typedef struct ph_frame_in {
    const lg_scene *s;
    const lg_resource *scene_res;
    const lg_shadowmap *sm;
    lg_shadowmap sm_view; /* what sm points to */
    GLuint atlas;
    const lg_scene_view *v;
    uint32_t n_lights;
    bool tau; /* the medium's shadow: st->tau_tex and these */
    float sigma_t[3];
} ph_frame_in;

static int ph_set_globals(ph_state *st, lg_gl_pass *p, const ph_uniforms *u, const ph_frame_in *f,
                          const float view_proj[16])
{
    const lg_scene_view *v = f->v;
    const lg_shadowmap *sm = f->sm;
    ph_gpu_frame g = {
        .eye = { v->eye.x, v->eye.y, v->eye.z },
        .n_lights = (int32_t)f->n_lights,
        .view_dir_inf = { -v->forward.x, -v->forward.y, -v->forward.z },
        .viewer_local = st->viewer == PH_VIEWER_LOCAL,
        .ambient = { st->ambient[0], st->ambient[1], st->ambient[2] },
        .depth_cue = st->depth_cue,
        .K = st->K,
        .spec_model = st->specular,
        .n_scale = st->specular == LG_SPEC_BLINN && st->blinn_x4 ? LG_BLINN_CORRECTION : 1.0f,
        .mixed_cos = st->mixed_cos,
        .shadow_res = sm ? (int32_t)sm->resolution : 1,
        .bias_const = sm ? sm->bias_constant : 0.0f,
        .bias_slope = sm ? sm->bias_slope : 0.0f,
        .normal_offset = sm ? sm->normal_offset : 0.0f,
        .pcf_radius = sm ? (int32_t)sm->pcf_radius : 0,
        .pcss_light_size = sm ? sm->pcss_light_size : 0.0f,
    };
    memcpy(g.view_proj, view_proj, sizeof g.view_proj);
    return lg_gl_pass_uniforms(p, u->frame, &g, sizeof g);
}

static void ph_set_material(ph_state *st, lg_gl_pass *p, const ph_uniforms *u, const lg_material *m)
{
    lg_gl_set_float(p, u->ka, m->ka);
    lg_gl_set_float(p, u->kd, m->kd);
    lg_gl_set_float(p, u->ks, m->ks * st->ks_scale);
    lg_gl_set_float(p, u->shininess, m->shininess);
    lg_gl_set_vec3v(p, u->od, m->od);
    lg_gl_set_vec3v(p, u->os, m->os);
    lg_gl_set_int(p, u->double_sided, m->double_sided);
}

typedef struct ph_draw_ctx {
    ph_state *st;
    const lg_gl *gl;
    const lg_scene *s;
    lg_gl_pass *pass;
    const ph_uniforms *u;
    const lg_resource *scene_res;
} ph_draw_ctx;

/* Before a mesh's first draw: its normals (vertex_normals = eq13) and material. */
static int ph_on_mesh(lg_node *n, void *user, uint32_t mi, GLuint *normals)
{
    const ph_draw_ctx *c = user;
    int rc;
    if (c->st->normals == PH_NORMALS_EQ13 && (rc = ph_eq13_buffer(n, c->st, c->s, mi, normals)))
        return rc;
    /* with culling off, a single-sided surface seen from behind is lit as it is (its normal
     * facing away: ambient only), as the seed's model would */
    uint32_t mat = c->s->meshes[mi].material;
    ph_set_material(c->st, c->pass, c->u, &c->s->materials[mat]);
    /* its textures and alpha mode: the file's samplers, anisotropy 16 (at most the device's) */
    return lg_gl_pass_bind_material(c->pass, &c->u->mat, c->scene_res, mat, NULL);
}

/* The surface ids of phong_half: instance (first + 1) onwards. */
static void ph_on_batch(void *user, uint32_t first)
{
    const ph_draw_ctx *c = user;
    lg_gl_set_int(c->pass, c->u->id_base, (int32_t)(first + 1));
}

/* One raster pass: every instance through `p` with `view_proj` into `target`, cleared first
 * (colour to `clear`, depth to 1). */
static int ph_pass(lg_node *n, ph_state *st, const lg_gl *gl, const ph_frame_in *f, lg_gl_pass *p,
                   const ph_uniforms *u, const lg_gl_target *target, const float clear[4],
                   const float view_proj[16])
{
    int rc = lg_gl_pass_begin(p, target);
    if (rc)
        return rc;
    lg_gl_pass_clear_color(p, 0, clear);
    lg_gl_pass_clear_depth(p, 1.0f);
    if ((rc = ph_set_globals(st, p, u, f, view_proj)))
        return lg_gl_pass_end(p, rc);
    lg_gl_pass_bind_buffer(p, u->lights, st->lights_buf.name);
    lg_gl_pass_bind_buffer(p, u->shadows, st->shadows_buf.name);
    lg_gl_pass_bind_texture(p, u->atlas, f->atlas);
    if (f->tau) {
        const vol_tau_volume *t = &st->tau[0];
        lg_gl_set_vec3(p, u->tau_lo, (float)t->lo[0], (float)t->lo[1], (float)t->lo[2]);
        lg_gl_set_vec3(p, u->tau_hi, (float)t->hi[0], (float)t->hi[1], (float)t->hi[2]);
        lg_gl_set_ivec3(p, u->tau_n, (int32_t)t->n[0], (int32_t)t->n[1], (int32_t)t->n[2]);
        lg_gl_set_vec3v(p, u->sigma_t, f->sigma_t);
        /* linear filtering: the volume's trilinear tau, the texture unit's own weights */
        const lg_gl_sampler lin = { .filter = LG_GL_FILTER_LINEAR, .wrap = LG_GL_WRAP_CLAMP };
        lg_gl_pass_bind_texture_sampled(p, u->tau, st->tau_tex.name, &lin);
    }
    ph_draw_ctx ctx = { st, gl, f->s, p, u, f->scene_res };
    lg_gl_scene_draw d = { .on_mesh = ph_on_mesh, .on_batch = ph_on_batch, .user = &ctx };
    return lg_gl_pass_end(p, lg_gl_pass_draw_scene(p, f->scene_res, &d));
}

/* ---- the medium's shadow on surfaces --------------------------------------------------------- */

/* Whether the medium shadows surfaces in this scene: medium_shadows on and a medium with a
 * density field and some extinction. Every other scene (no medium, a homogeneous one, a
 * field of no extinction) runs the program and the uploads it ran before (README.md). */
static bool ph_tau_wanted(const ph_state *st, const lg_scene *s, float sigma_t[3])
{
    if (!st->medium_shadows || !s->medium.present || !(s->medium.density > 0.0f) ||
        !s->medium.field)
        return false;
    float sigma_s[3];
    lg_medium_coeffs(&s->medium, sigma_s, sigma_t);
    return sigma_t[0] > 0.0f || sigma_t[1] > 0.0f || sigma_t[2] > 0.0f;
}

static void ph_tau_free(lg_node *n, ph_state *st)
{
    for (uint32_t i = 0; i < st->n_tau; i++)
        vol_tau_free(n, &st->tau[i]);
    free(st->tau);
    free(st->tau_lights);
    st->tau = NULL;
    st->tau_lights = NULL;
    st->n_tau = 0;
    st->tau_scene = NULL;
    st->tau_uploaded = false;
}

/* Each light's optical-depth volume as the shaders see the light (a light at infinity,
 * pos.w 0, marches along its L out of the box; a local one to its position), remade when
 * the scene, its field, a light or the resolution changes, and their stack uploaded into
 * st->tau_tex. `scene` is the scene on the input (the cache's key), `s` its pose. */
static int ph_tau(lg_node *n, ph_state *st, const lg_gl *gl, const lg_scene *scene,
                  const lg_scene *s, const ph_gpu_light *lights, uint32_t nl)
{
    vol_light *want = calloc(nl ? nl : 1, sizeof *want);
    if (!want)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u lights)", nl);
    for (uint32_t i = 0; i < nl; i++) {
        const ph_gpu_light *g = &lights[i];
        vol_light *l = &want[i];
        l->scene_index = i;
        l->shadow = -1;
        if (g->pos[3] < 0.5f) {
            l->type = LG_LIGHT_DIRECTIONAL;
            for (int c = 0; c < 3; c++)
                l->dir[c] = -g->dir[c]; /* vol_light: the direction the light travels */
        } else {
            l->type = LG_LIGHT_POINT; /* a spot's cone does not change the path */
            memcpy(l->pos, g->pos, sizeof l->pos);
        }
    }
    float bounds[6];
    memcpy(bounds, s->bounds_min, sizeof s->bounds_min);
    memcpy(bounds + 3, s->bounds_max, sizeof s->bounds_max);
    if (st->tau && st->tau_scene == scene && st->n_tau == nl &&
        memcmp(st->tau_lights, want, nl * sizeof *want) == 0 &&
        memcmp(&st->tau_field, s->medium.field, sizeof st->tau_field) == 0 &&
        memcmp(st->tau_bounds, bounds, sizeof bounds) == 0 && st->tau[0].tau && st->tau[0].n[0] &&
        st->tau_uploaded) {
        free(want);
        return 0;
    }
    ph_tau_free(n, st);
    st->tau = calloc(nl ? nl : 1, sizeof *st->tau);
    if (!st->tau) {
        free(want);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u lights)", nl);
    }
    st->tau_lights = want;
    int rc = 0;
    for (uint32_t i = 0; i < nl && !rc; i++) {
        rc = vol_tau_build_light(n, &s->medium, s->bounds_min, s->bounds_max, &want[i], st->tau_res,
                                 &st->tau[i]);
        if (!rc)
            st->n_tau = i + 1;
    }
    if (rc) {
        ph_tau_free(n, st);
        return rc;
    }
    const vol_tau_volume *t0 = &st->tau[0];
    GLint max3d = 0;
    gl->GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
    uint64_t depth = (uint64_t)t0->n[2] * nl;
    if (depth > (uint64_t)max3d) {
        ph_tau_free(n, st);
        return lg_error(n,
                        "medium_shadows: %u lights' optical-depth volumes of %u cells in z "
                        "(medium_shadow_res = %u) stack to %llu layers, beyond this device's "
                        "3D texture limit of %d: lower medium_shadow_res or turn "
                        "medium_shadows off",
                        nl, t0->n[2], st->tau_res, (unsigned long long)depth, (int)max3d);
    }
    lg_gl_texture_desc td = { .target = GL_TEXTURE_3D,
                              .format = GL_R32F,
                              .width = t0->n[0],
                              .height = t0->n[1],
                              .depth = (uint32_t)depth };
    int made = lg_gl_texture_recreate(n, &st->tau_tex, &td);
    if (made < 0) {
        ph_tau_free(n, st);
        return made;
    }
    for (uint32_t i = 0; i < nl; i++)
        gl->TextureSubImage3D(st->tau_tex.name, 0, 0, 0, (GLint)(i * t0->n[2]), (GLsizei)t0->n[0],
                              (GLsizei)t0->n[1], (GLsizei)t0->n[2], GL_RED, GL_FLOAT,
                              st->tau[i].tau);
    if ((rc = lg_gl_check(n, "phong: uploading the optical-depth volumes"))) {
        ph_tau_free(n, st);
        return rc;
    }
    st->tau_scene = scene;
    st->tau_field = *s->medium.field;
    memcpy(st->tau_bounds, bounds, sizeof bounds);
    st->tau_uploaded = true;
    lg_log(n, LG_LOG_INFO,
           "the medium's shadow: %u optical-depth volume%s of %ux%ux%u cells over [%.4g, %.4g, "
           "%.4g] .. [%.4g, %.4g, %.4g]",
           nl, nl == 1 ? "" : "s", t0->n[0], t0->n[1], t0->n[2], t0->lo[0], t0->lo[1], t0->lo[2],
           t0->hi[0], t0->hi[1], t0->hi[2]);
    return 0;
}

/* phong_half's images at the output's size (made on the first frame, then kept; sampled
 * nearest, as lg_gl_texture makes them). */
static int ph_half_images(lg_node *n, ph_state *st)
{
    uint32_t qw = (st->width + 1) / 2, qh = (st->height + 1) / 2;
    const lg_gl_texture_desc id = {
        .target = GL_TEXTURE_2D, .format = GL_R32UI, .width = st->width, .height = st->height
    };
    const lg_gl_texture_desc q = {
        .target = GL_TEXTURE_2D, .format = GL_RGBA32F, .width = qw, .height = qh
    };
    const lg_gl_texture_desc qd = {
        .target = GL_TEXTURE_2D, .format = GL_DEPTH_COMPONENT32F, .width = qw, .height = qh
    };
    int rc;
    if ((rc = lg_gl_texture_recreate(n, &st->id_tex, &id)) < 0 ||
        (rc = lg_gl_texture_recreate(n, &st->quarter[0], &q)) < 0 ||
        (rc = lg_gl_texture_recreate(n, &st->quarter[1], &q)) < 0 ||
        (rc = lg_gl_texture_recreate(n, &st->quarter_depth, &qd)) < 0)
        return rc;
    return 0;
}

/* The view_proj that draws the pixels (2 x + p, 2 y + p) of the w x h output, p = 0 or 1,
 * into a ceil(w/2) x ceil(h/2) image: window x maps to (x - p + 1/2) / 2, so pixel centres
 * land on pixel centres. Applied in clip space: x' = a x + b w. */
static void ph_quarter_view_proj(float out[16], const float vp[16], uint32_t w, uint32_t h, int p)
{
    float qw = (float)((w + 1) / 2), qh = (float)((h + 1) / 2);
    float ax = (float)w / (2.0f * qw), bx = (0.5f * (float)w - (float)p + 0.5f) / qw - 1.0f;
    float ay = (float)h / (2.0f * qh), by = (0.5f * (float)h - (float)p + 0.5f) / qh - 1.0f;
    /* rows of the result: x' = ax x + bx w, y' = ay y + by w (row 3 of vp gives w) */
    for (int c = 0; c < 4; c++) {
        out[c * 4 + 0] = ax * vp[c * 4 + 0] + bx * vp[c * 4 + 3];
        out[c * 4 + 1] = ay * vp[c * 4 + 1] + by * vp[c * 4 + 3];
        out[c * 4 + 2] = vp[c * 4 + 2];
        out[c * 4 + 3] = vp[c * 4 + 3];
    }
}

/* phong_half (seed 1, 1.3.6, the second optimisation): the surface ids and depth at full
 * size, per-pixel Phong on the two halves of a checkerboard at quarter size each, and a
 * full-screen pass that puts the evaluated pixels in place and interpolates the others. */
static int ph_half(lg_node *n, ph_state *st, const lg_gl *gl, const ph_frame_in *f,
                   const lg_gl_target *out)
{
    int rc;
    if ((rc = ph_half_images(n, st)))
        return rc;
    const float bg[4] = { st->background[0], st->background[1], st->background[2], 1.0f };
    const float zero[4] = { 0, 0, 0, 0 };

    /* ids and the output's depth */
    lg_gl_target ids = {
        .color = { st->id_tex.name }, .depth = out->depth, .width = st->width, .height = st->height
    };
    if ((rc = ph_pass(n, st, gl, f, st->id_pass, &st->id_u, &ids, zero, f->v->view_proj)))
        return rc;

    /* the checkerboard's two halves */
    uint32_t qw = (st->width + 1) / 2, qh = (st->height + 1) / 2;
    for (int p = 0; p < 2; p++) {
        float vp[16];
        ph_quarter_view_proj(vp, f->v->view_proj, st->width, st->height, p);
        lg_gl_target q = { .color = { st->quarter[p].name },
                           .depth = st->quarter_depth.name,
                           .width = qw,
                           .height = qh };
        if ((rc = ph_pass(n, st, gl, f, st->pass, &st->u, &q, bg, vp)))
            return rc;
    }

    /* assembly: every output pixel, reading the ids, the depth and the quarter images */
    lg_gl_pass *h = st->half_pass;
    lg_gl_target color = { .color = { out->color[0] }, .width = st->width, .height = st->height };
    if ((rc = lg_gl_pass_begin(h, &color)))
        return rc;
    lg_gl_pass_bind_texture(h, st->h_depth, out->depth);
    lg_gl_pass_bind_texture(h, st->h_even, st->quarter[0].name);
    lg_gl_pass_bind_texture(h, st->h_odd, st->quarter[1].name);
    lg_gl_pass_bind_texture(h, st->h_id, st->id_tex.name);
    lg_gl_set_ivec2(h, st->h_size, (int32_t)st->width, (int32_t)st->height);
    lg_gl_set_vec2(h, st->h_near_far, f->v->znear, f->v->zfar);
    lg_gl_set_float(h, st->h_depth_tol, PH_HALF_DEPTH_TOL);
    lg_gl_set_vec3v(h, st->h_background, st->background);
    return lg_gl_pass_end(h, lg_gl_pass_draw(h, GL_TRIANGLES, 3));
}

static int ph_execute(lg_node *n, const lg_frame *frame)
{
    ph_state *st = n->user;
    ph_frame_in f = { 0 };
    f.scene_res = lg_input(n, 0);
    f.s = lg_scene_get(n, f.scene_res);
    if (!f.s)
        return LG_ERR_INVALID;
    const lg_resource *sres = lg_input(n, 1);
    if (sres) {
        lg_resource_info info;
        f.sm = lg_shadowmap_get(n, sres, &f.sm_view);
        if (!f.sm && (lg_describe(sres, &info, n) != 0 || info.kind != LG_KIND_SHADOWMAP))
            return LG_ERR_INVALID;
        if (f.sm && (!f.sm->atlas || f.sm->resolution == 0 || (f.sm->n_lights && !f.sm->lights)))
            return lg_error(n, "input 'shadows': the shadow maps have no atlas, no "
                               "resolution or no light list");
    }
    lg_scene_view v;
    /* animated lights and cameras at this frame's time (ABI 3.1): the lights and the view
     * read the posed copy, materials and meshes are the scene's own */
    lg_scene at;
    int rc = lg_scene_at(n, f.s, frame->time, &at);
    if (rc)
        return rc;
    const lg_scene *scene = f.s;
    f.s = &at;
    rc = lg_scene_view_make(n, f.s, st->camera, st->width, st->height, &v);
    if (rc) {
        lg_scene_at_free(scene, &at);
        return rc;
    }
    f.v = &v;
    ph_gpu_light *lights = NULL;
    ph_gpu_shadow *shadows = NULL;
    uint32_t n_shadow = 0, n_maps = 0;
    if ((rc = ph_build_lights(n, st, f.s, f.sm, &lights, &shadows, &n_shadow, &n_maps))) {
        lg_scene_at_free(scene, &at);
        return rc;
    }
    f.n_lights = f.s->n_lights;

    const lg_gl *gl = lg_gl_get(n);
    lg_gl_target out;
    if (!gl) {
        rc = LG_ERR_DEVICE;
        goto out;
    }
    int sv = (int)n_shadow < ph_sv_limit(gl) ? (int)n_shadow : ph_sv_limit(gl);
    f.tau = f.n_lights > 0 && ph_tau_wanted(st, f.s, f.sigma_t);
    if (f.tau && (rc = ph_tau(n, st, gl, scene, f.s, lights, f.n_lights)))
        goto out;
    if ((rc = ph_passes(n, st, sv, f.tau)) ||
        (n_shadow && (rc = phong_shadow_atlas(n, f.sm, &f.atlas))) ||
        (rc = lg_gl_target_output(n, "out", &out)))
        goto out;
    if ((rc = ph_upload(n, &st->lights_buf, lights, (size_t)f.n_lights * sizeof *lights)) ||
        (rc = ph_upload(n, &st->shadows_buf, shadows, (size_t)n_maps * sizeof *shadows)))
        goto out;
    /* an animated scene: its instances at this frame's time (ABI 3.1) */
    lg_gl_pass_set_time(st->pass, frame->time);
    lg_gl_pass_set_time(st->id_pass, frame->time);
    lg_gl_pass_set_time(st->half_pass, frame->time);
    if (st->shading == PH_HALF) {
        rc = ph_half(n, st, gl, &f, &out);
    } else {
        const float bg[4] = { st->background[0], st->background[1], st->background[2], 1.0f };
        rc = ph_pass(n, st, gl, &f, st->pass, &st->u, &out, bg, v.view_proj);
    }

out:
    if (!rc) {
        const lg_scene_gl *sgl = lg_gl_pass_scene(st->pass);
        const lg_camera *c = &f.s->cameras[v.camera];
        bool per_vertex = st->shading == PH_FLAT || st->shading == PH_GOURAUD ||
                          st->shading == PH_MIXED;
        char split[96] = "";
        if (per_vertex && n_shadow > (uint32_t)st->program_sv)
            snprintf(split, sizeof split, "; the first %d tested per pixel, the others per vertex",
                     st->program_sv);
        lg_log(n, LG_LOG_INFO,
               "%u instances, %" PRIu64 " triangles, %u light%s (%u with shadow maps%s), "
               "camera %u '%s' at (%.4g, %.4g, %.4g) looking along (%.3f, %.3f, %.3f)",
               sgl->count, sgl->triangles, f.n_lights, f.n_lights == 1 ? "" : "s", n_shadow, split,
               v.camera, c->name ? c->name : "", (double)v.eye.x, (double)v.eye.y, (double)v.eye.z,
               (double)v.forward.x, (double)v.forward.y, (double)v.forward.z);
    }
    free(lights);
    free(shadows);
    lg_scene_at_free(scene, &at);
    return rc ? rc : (gl ? lg_gl_check(n, "phong: uploading the lights") : rc);
}

static void ph_destroy(lg_node *n)
{
    ph_state *st = n->user;
    if (!st)
        return;
    lg_gl_pass_destroy(&st->pass);
    lg_gl_pass_destroy(&st->id_pass);
    lg_gl_pass_destroy(&st->half_pass);
    lg_gl_texture_destroy(n, &st->id_tex);
    lg_gl_texture_destroy(n, &st->quarter[0]);
    lg_gl_texture_destroy(n, &st->quarter[1]);
    lg_gl_texture_destroy(n, &st->quarter_depth);
    lg_gl_buffer_destroy(n, &st->lights_buf);
    lg_gl_buffer_destroy(n, &st->shadows_buf);
    lg_gl_texture_destroy(n, &st->tau_tex);
    ph_tau_free(n, st);
    for (uint32_t i = 0; i < st->n_eq13; i++)
        lg_gl_buffer_destroy(n, &st->eq13[i]);
    free(st->eq13);
    free(st);
    n->user = NULL;
}

/* ---- the descriptor -------------------------------------------------------------------------- */

static const char *const ph_shadings[] = {
    "flat", "gouraud", "phong", "mixed", "phong_half", NULL
};
static const char *const ph_speculars[] = { "phong", "blinn", NULL };
static const char *const ph_corrections[] = { "none", "x4", NULL };
static const char *const ph_at[] = { "infinite", "local", NULL };
static const char *const ph_normal_srcs[] = { "scene", "eq13", NULL };
static const char *const ph_falloffs[] = { "none", "inverse_square", NULL };
static const char *const ph_culls[] = { "none", "material", NULL };

static const lg_param_desc ph_params[] = {
    { .key = "shading",
      .type = LG_PARAM_ENUM,
      .def.e = PH_PHONG,
      .enum_values = ph_shadings,
      .doc = "flat: per facet; gouraud: per vertex, colours interpolated; phong: per pixel, "
             "normals interpolated; mixed: phong on highlight facets, gouraud elsewhere; "
             "phong_half: per pixel on half the pixels (a checkerboard), the others the mean "
             "of their neighbours" },
    { .key = "specular",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = ph_speculars,
      .doc = "phong: (R.V)^n; blinn: (N.H)^n' with H = (L+V)/|L+V|" },
    { .key = "blinn_correction",
      .type = LG_PARAM_ENUM,
      .def.e = 1,
      .enum_values = ph_corrections,
      .doc = "blinn's exponent: none: n' = n (a larger highlight); x4: n' = 4n (matches phong)" },
    { .key = "depth_cue",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "divide the light terms (not the ambient) by (r + K), r the distance to the "
             "camera (eq. 1-12; factor capped at 1)" },
    { .key = "k",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 1e30,
      .doc = "K of eq. 1-12 (depth cueing), metres: the light terms are divided by r + K" },
    { .key = "viewer",
      .type = LG_PARAM_ENUM,
      .def.e = PH_VIEWER_LOCAL,
      .enum_values = ph_at,
      .doc = "infinite: one V for the whole image (towards the camera along its axis; seed 1 "
             "1.2.6); local: V from each point to the camera" },
    { .key = "lights_at",
      .type = LG_PARAM_ENUM,
      .def.e = PH_VIEWER_LOCAL,
      .enum_values = ph_at,
      .doc = "infinite: point and spot lights act as directional lights from where they lie "
             "seen from the scene's centre (seed 1 1.2.6); local: L from each point" },
    { .key = "ambient",
      .type = LG_PARAM_COLOR,
      .def.v = { 0.1, 0.1, 0.1 },
      .min = 0,
      .max = 1e6,
      .doc = "Ia, the ambient light (linear RGB, the lights' units)" },
    { .key = "ks_scale",
      .type = LG_PARAM_FLOAT,
      .def.f = 1.0,
      .min = 0,
      .max = 1e6,
      .doc = "multiplies every material's ks (1 = as the scene says; > 1 exaggerates the "
             "highlights of materials that have a specular term; 0 = matte)" },
    { .key = "mixed_threshold_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 30.0,
      .min = 0,
      .max = 180,
      .doc = "mixed: a facet whose angle between V and R is below this (degrees) for some "
             "light, at a vertex, an edge midpoint or its centroid, is a highlight facet "
             "(phong-shaded); the others are gouraud-shaded" },
    { .key = "vertex_normals",
      .type = LG_PARAM_ENUM,
      .def.e = PH_NORMALS_SCENE,
      .enum_values = ph_normal_srcs,
      .doc = "scene: the mesh's normals; eq13: normalised sum of the normals of the facets "
             "meeting at each vertex position (seed 1 eq. 1-13)" },
    { .key = "falloff",
      .type = LG_PARAM_ENUM,
      .def.e = 0,
      .enum_values = ph_falloffs,
      .doc = "point and spot lights: none (the seed's model: Ii at any distance) or "
             "inverse_square (Ii / d^2, glTF's candela)" },
    { .key = "cull",
      .type = LG_PARAM_ENUM,
      .def.e = PH_CULL_MATERIAL,
      .enum_values = ph_culls,
      .doc = "none: draw both sides of every triangle; material: cull back faces unless the "
             "material is double-sided (glTF)" },
    { .key = "width",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16384,
      .doc = "output width in pixels; 0 = the render size (--size)",
      .role = LG_ROLE_IMAGE_WIDTH },
    { .key = "height",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 16384,
      .doc = "output height in pixels; 0 = the render size (--size)",
      .role = LG_ROLE_IMAGE_HEIGHT },
    { .key = "background",
      .type = LG_PARAM_COLOR,
      .def.v = { 0, 0, 0 },
      .min = 0,
      .max = 1e6,
      .doc = "radiance where no surface is, linear RGB (alpha is 1 everywhere)" },
    { .key = "camera",
      .type = LG_PARAM_INT,
      .def.i = -1,
      .min = -1,
      .max = 1e9,
      .doc = "index of the scene's camera to look through; -1 = the scene's active camera" },
    { .key = "per_frame",
      .type = LG_PARAM_BOOL,
      .def.b = false,
      .doc = "render again on every frame (--frames), for timing; the result is the same" },
    { .key = "medium_shadows",
      .type = LG_PARAM_BOOL,
      .def.b = true,
      .doc = "a medium with a density field shadows surfaces: each light times the "
             "transmittance towards it through the field (an optical-depth volume per "
             "light); scenes without a field are unaffected either way" },
    { .key = "medium_shadow_res",
      .type = LG_PARAM_INT,
      .def.i = 64,
      .min = 2,
      .max = 128,
      .doc = "medium_shadows: cells along the longest side of each light's optical-depth "
             "volume (built on the CPU once per scene and light: res^4 field reads)" },
};
static const lg_port_desc ph_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene to light and draw" },
    { .name = "shadows",
      .kind = LG_KIND_SHADOWMAP,
      .optional = true,
      .doc = "shadow maps of the scene's lights, every type (a shadowmap node); unconnected "
             "or gated: no shadows" },
};
static const lg_port_desc ph_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f HDR linear radiance, alpha 1, upright, with a depth plane: GL window "
             "depth in [0, 1] (1 = nothing)" },
};

static const lg_node_type ph_types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "phong",
    .doc = "Phong/Blinn local illumination with depth cueing and shadow maps; flat, Gouraud, "
           "Phong, mixed or half-rate Phong shading (GL)",
    LG_PARAMS(ph_params),
    LG_INPUTS(ph_inputs),
    LG_OUTPUTS(ph_outputs),
    .create = ph_create,
    .prepare = ph_prepare,
    .execute = ph_execute,
    .destroy = ph_destroy,
} };

LG_PLUGIN_DEFINE("phong", "1.0.0",
                 "Local illumination (Phong, Blinn, depth cueing, shadows) with flat, Gouraud, "
                 "Phong, mixed and half-rate shading on GL",
                 ph_types)
