/*
 * The scene_tools plugin: nodes that derive one scene from another, so that a graph can
 * frame, light and fill with fog any scene without editing its file.
 *
 *   camera   sets the active camera (look_at, or orbit around the scene's bounds)
 *   light    adds a directional, point or spot light, or replaces all lights with one
 *   medium   sets (replaces) the participating medium
 *   environment  attaches a light probe: the scene feature `probe` becomes true, so nodes
 *            that need a probe (reflection, background, PRT) are planned, not gated
 *
 * Each node reads the input scene in prepare() and publishes a derived lg_scene: a shallow
 * copy of the input's struct with its own array for what it changes (lights or cameras),
 * `geometry` pointing at the resource that owns the meshes (so GPU copies are shared), and
 * features recomputed, so that the planner gates downstream nodes on the derived scene.
 * execute() has nothing to do. README.md describes parameters, formulas and fallbacks.
 */
#include <float.h>
#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/file.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/medium.h"
#include "vdb_read.h"

/* Orbit framing: the bounding sphere's angular radius is at most the smaller half field of
 * view divided by this margin (in sine), see README.md "camera". */
#define ST_ORBIT_MARGIN 1.1

/* ---- derived scenes -------------------------------------------------------------------------- */

/* The payload: the derived lg_scene first (the host hands consumers a pointer to it) and
 * the arrays this node owns. Everything else the scene points to (meshes, instances,
 * materials, and the lights or cameras it did not replace) belongs to the source's
 * payload, which the host keeps alive for as long as this one. */
typedef struct st_payload {
    lg_scene scene;
    lg_light *lights;   /* NULL when the source's array is used */
    lg_camera *cameras; /* NULL when the source's array is used */
    char *source;
    char *name; /* the node's name: names of the lights and cameras made here */
    /* the source's animation carried through (ABI 3.1): its nodes and channels are the
     * source's, the lights' and cameras' carrier nodes this node's own (a light or camera
     * made here stands still: -1) */
    lg_scene_animation anim;
    int32_t *light_node, *camera_node;
    /* the medium node's density field (ABI 3.2), which scene.medium.field points at: the
     * field, its grid and the grid's values (NULL without a grid) and "FILE:GRID" */
    lg_density_field field;
    lg_density_grid grid;
    float *grid_values;
    char *grid_source;
} st_payload;

/* The free function given to the host. Touches only this payload's own allocations, never
 * the source's (its payload may be gone by then). */
static void st_free(void *ptr)
{
    st_payload *p = ptr;
    if (!p)
        return;
    free(p->lights);
    free(p->cameras);
    free(p->source);
    free(p->name);
    free(p->light_node);
    free(p->camera_node);
    free(p->grid_values);
    free(p->grid_source);
    free(p);
}

static char *st_strdup(const char *s)
{
    size_t len = strlen(s) + 1;
    char *d = malloc(len);
    if (d)
        memcpy(d, s, len);
    return d;
}

/* The input scene (port 0, required: a scene), with a message that says what is wrong if
 * it has no data. */
static int st_input(lg_node *n, const lg_resource **res, const lg_scene **scene)
{
    lg_assert_input(n, 0);
    const lg_resource *r = lg_input(n, 0);
    lg_resource_info info;
    lg_describe(r, &info, n);
    /* lg_scene_get would report a description-only scene as "another kind": say what it
     * is, since the planner's test scenes and neutral scenes look like this */
    if (!info.payload)
        return lg_error(n,
                        "input 'scene' has scene features but no scene data (%s): this "
                        "node needs a scene made by a scene node such as gltf",
                        info.neutral ? "the neutral result of a gated node"
                                     : "its node declared no lg_scene payload");
    const lg_scene *s = lg_scene_get(n, r);
    if (!s)
        return LG_ERR_INVALID;
    *res = r;
    *scene = s;
    return 0;
}

/* A new payload holding a shallow copy of `src`. `what` describes the change for the
 * derived scene's `source` text. */
static int st_derive(lg_node *n, const lg_resource *in, const lg_scene *src, const char *what,
                     st_payload **out)
{
    *out = NULL;
    st_payload *p = calloc(1, sizeof *p);
    if (!p)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (derived scene)");
    /* a scene built against an older SDK may be shorter: copy what it has */
    size_t have = src->struct_size < sizeof p->scene ? src->struct_size : sizeof p->scene;
    memcpy(&p->scene, src, have);
    p->scene.struct_size = sizeof p->scene;
    /* the fields still reserved; since ABI 3.1 the textures and the animation are shared
     * with the source like its meshes and materials (clearing the whole union lost them) */
    memset(p->scene.reserved_3_1, 0, sizeof p->scene.reserved_3_1);
    if (have == sizeof p->scene && src->animation) {
        p->anim = *src->animation;
        p->scene.animation = &p->anim; /* carriers: st_carriers, by the node that derives */
    }
    /* a chain of derived scenes points straight at the owner of the geometry */
    p->scene.geometry = src->geometry ? src->geometry : in;

    const char *from = src->source ? src->source : "(unnamed scene)";
    size_t len = strlen(from) + strlen(what) + strlen(n->name) + 16;
    p->source = malloc(len);
    p->name = st_strdup(n->name);
    if (!p->source || !p->name) {
        st_free(p);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (derived scene)");
    }
    snprintf(p->source, len, "%s + %s '%s'", from, what, n->name);
    p->scene.source = p->source;
    *out = p;
    return 0;
}

/* The derived scene's light and camera carriers (ABI 3.1 animation): light i of the new
 * scene is the source's light i for i < kept_lights, else made here; the camera in slot
 * `new_camera` (UINT32_MAX: none) is made here, the others are the source's. */
static int st_carriers(lg_node *n, st_payload *p, const lg_scene *src, uint32_t kept_lights,
                       uint32_t new_camera)
{
    if (!p->scene.animation)
        return 0;
    const lg_scene_animation *a = src->animation;
    p->light_node = malloc(((size_t)p->scene.n_lights + 1) * sizeof *p->light_node);
    p->camera_node = malloc(((size_t)p->scene.n_cameras + 1) * sizeof *p->camera_node);
    if (!p->light_node || !p->camera_node)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (animation carriers)");
    for (uint32_t i = 0; i < p->scene.n_lights; i++)
        p->light_node[i] = i < kept_lights && i < src->n_lights && a->light_node ? a->light_node[i]
                                                                                 : -1;
    for (uint32_t i = 0; i < p->scene.n_cameras; i++)
        p->camera_node[i] = i != new_camera && i < src->n_cameras && a->camera_node
                                ? a->camera_node[i]
                                : -1;
    p->anim.light_node = p->light_node;
    p->anim.camera_node = p->camera_node;
    return 0;
}

/* Recomputes the features and hands the payload to the host (which frees it with st_free,
 * also when declaring fails). */
static int st_publish(lg_node *n, st_payload *p)
{
    lg_scene_compute_features(&p->scene);
    return lg_declare_payload(n, 0, LG_KIND_SCENE, &p->scene.features, p, st_free);
}

/* A vec3 or colour parameter as floats; values a float cannot hold are refused. */
static int st_vec3(lg_node *n, const char *key, lg_vec3 *out)
{
    const lg_value *v = lg_param(n, key);
    if (!v)
        return lg_error(n, "parameter '%s' is not declared by this node type", key);
    for (int i = 0; i < 3; i++)
        if (!isfinite(v->v[i]) || fabs(v->v[i]) > FLT_MAX)
            return lg_error(n,
                            "%s = [%g, %g, %g]: component %d is not a finite "
                            "single-precision number",
                            key, v->v[0], v->v[1], v->v[2], i);
    *out = lg_v3((float)v->v[0], (float)v->v[1], (float)v->v[2]);
    return 0;
}

/* The scene's world bounds as centre, radius (half the diagonal) and corners. False when
 * they are empty (no geometry: min > max) or not finite. */
static bool st_bounds(const lg_scene *s, lg_vec3 *centre, float *radius, lg_vec3 corners[8])
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(s->bounds_min[i]) || !isfinite(s->bounds_max[i]) ||
            s->bounds_min[i] > s->bounds_max[i])
            return false;
    lg_vec3 lo = lg_v3(s->bounds_min[0], s->bounds_min[1], s->bounds_min[2]);
    lg_vec3 hi = lg_v3(s->bounds_max[0], s->bounds_max[1], s->bounds_max[2]);
    *centre = lg_v3_scale(lg_v3_add(lo, hi), 0.5f);
    *radius = 0.5f * lg_v3_length(lg_v3_sub(hi, lo));
    for (int k = 0; k < 8; k++)
        corners[k] = lg_v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    return isfinite(*radius);
}

/* ---- camera ---------------------------------------------------------------------------------- */

enum { CAM_LOOK_AT = 0, CAM_ORBIT };

/* Near and far planes that hold the scene's bounds as seen from `eye` along the unit view
 * direction `f` (README.md "camera": clipping planes). */
static void camera_auto_clip(bool have_bounds, const lg_vec3 corners[8], lg_vec3 centre,
                             float radius, lg_vec3 eye, lg_vec3 target, lg_vec3 f, float *znear,
                             float *zfar)
{
    if (!have_bounds) {
        float d = lg_v3_length(lg_v3_sub(target, eye));
        *znear = d / 100.0f;
        *zfar = d * 100.0f;
        return;
    }
    float dmin = INFINITY, dmax = -INFINITY;
    for (int k = 0; k < 8; k++) {
        float d = lg_v3_dot(lg_v3_sub(corners[k], eye), f);
        dmin = d < dmin ? d : dmin;
        dmax = d > dmax ? d : dmax;
    }
    float far = dmax * 1.01f;
    if (!(far > 0)) /* the whole scene is behind the camera: any far plane past it */
        far = lg_v3_length(lg_v3_sub(centre, eye)) + radius;
    if (!(far > 0)) /* a scene that is one point, at the eye */
        far = 1.0f;
    float near = dmin * 0.99f;
    /* the camera inside the bounds (or a scene behind it): keep depth precision usable */
    if (!(near > far * 1e-3f))
        near = far * 1e-3f;
    *znear = near;
    *zfar = far;
}

static int camera_prepare(lg_node *n)
{
    const lg_resource *in;
    const lg_scene *src;
    int rc = st_input(n, &in, &src);
    if (rc)
        return rc;

    int mode = lg_param_enum(n, "mode");
    double fov_deg = lg_param_float(n, "fov_deg");
    if (!(fov_deg > 0 && fov_deg < 180))
        return lg_error(n,
                        "fov_deg = %g: the vertical field of view must be inside (0, 180) "
                        "degrees, both ends excluded",
                        fov_deg);
    float yfov = (float)(fov_deg * LG_PI / 180.0);
    double aspect = lg_param_float(n, "aspect");

    lg_vec3 centre = lg_v3(0, 0, 0), corners[8];
    float radius = 0;
    bool have_bounds = st_bounds(src, &centre, &radius, corners);
    const lg_vec3 zero = lg_v3(0, 0, 0);

    lg_vec3 eye, target, f, up;
    if (mode == CAM_LOOK_AT) {
        lg_vec3 up_in;
        if ((rc = st_vec3(n, "position", &eye)) || (rc = st_vec3(n, "target", &target)) ||
            (rc = st_vec3(n, "up", &up_in)))
            return rc;
        f = lg_v3_normalize_or(lg_v3_sub(target, eye), zero);
        if (lg_v3_length(f) == 0)
            return lg_error(n,
                            "target [%g, %g, %g] is the camera's position: there is no "
                            "view direction; move position or target",
                            (double)target.x, (double)target.y, (double)target.z);
        lg_vec3 u = lg_v3_normalize_or(up_in, zero);
        if (lg_v3_length(u) == 0)
            return lg_error(n,
                            "up = [%g, %g, %g] is the zero vector: give the direction that "
                            "is up in the image, e.g. [0, 1, 0]",
                            (double)up_in.x, (double)up_in.y, (double)up_in.z);
        lg_vec3 s = lg_v3_cross(f, u);
        /* sin of the angle between up and the view direction: below 1e-4 (0.006 degrees)
         * the roll of the image is not defined by anything a user meant */
        if (lg_v3_length(s) < 1e-4f)
            return lg_error(n,
                            "up = [%g, %g, %g] is parallel to the view direction [%g, %g, "
                            "%g] (from position to target): the image's roll is undefined; "
                            "choose an up that is not along the line of sight",
                            (double)up_in.x, (double)up_in.y, (double)up_in.z, (double)f.x,
                            (double)f.y, (double)f.z);
        s = lg_v3_normalize_or(s, lg_v3(1, 0, 0));
        up = lg_v3_cross(s, f);
    } else {
        if (!have_bounds)
            return lg_error(n,
                            "mode = orbit: the scene (%s) has empty bounds (no geometry), so "
                            "there is nothing to orbit around; use mode = look_at",
                            src->source ? src->source : "unnamed");
        double az = lg_param_float(n, "azimuth_deg") * LG_PI / 180.0;
        double el = lg_param_float(n, "elevation_deg") * LG_PI / 180.0;
        double dist = lg_param_float(n, "distance");
        /* a scene that is a single point: orbit a unit sphere around it (README.md) */
        double r = radius > 0 ? radius : 1.0;
        if (dist == 0) {
            uint32_t w = 0, h = 0;
            lg_render_size(n, &w, &h);
            double a = aspect > 0 ? aspect : (w && h ? (double)w / h : 1.0);
            double half_y = 0.5 * yfov, half_x = atan(tan(half_y) * a);
            double half = half_x < half_y ? half_x : half_y;
            dist = ST_ORBIT_MARGIN / sin(half);
        }
        double d = dist * r;
        if (!(d <= FLT_MAX / 4))
            return lg_error(n, "distance = %g times the bounding radius %g does not fit a float",
                            dist, r);
        /* the direction from the centre to the camera; azimuth 0, elevation 0 looks down -Z
         * like glTF's default camera */
        lg_vec3 out = lg_v3((float)(cos(el) * sin(az)), (float)sin(el), (float)(cos(el) * cos(az)));
        target = centre;
        eye = lg_v3_add(centre, lg_v3_scale(out, (float)d));
        f = lg_v3_scale(out, -1.0f);
        /* the camera's own up (perpendicular to f, unit): continuous through the poles,
         * where world Y would be parallel to the view */
        up = lg_v3((float)(-sin(el) * sin(az)), (float)cos(el), (float)(-sin(el) * cos(az)));
    }

    double zn = lg_param_float(n, "znear"), zf = lg_param_float(n, "zfar");
    if (zn > 0 && zf > 0 && zf <= zn)
        return lg_error(n, "zfar = %g is not beyond znear = %g", zf, zn);
    float auto_near, auto_far;
    camera_auto_clip(have_bounds, corners, centre, radius, eye, target, f, &auto_near, &auto_far);
    float znear = zn > 0 ? (float)zn : auto_near;
    float zfar = zf > 0 ? (float)zf : auto_far;
    if (zn > 0 && zf == 0 && zfar <= znear)
        return lg_error(n,
                        "znear = %g is beyond the scene's far side (%g from the camera): "
                        "set zfar as well",
                        zn, (double)auto_far);
    if (zf > 0 && zn == 0 && znear >= zfar)
        znear = zfar * 1e-3f;

    st_payload *p;
    if ((rc = st_derive(n, in, src, "camera", &p)))
        return rc;
    /* replace the active camera; a scene without one (or with a bad index) gets one */
    uint32_t nc = src->n_cameras, slot = src->camera;
    if (slot >= nc)
        slot = nc++;
    p->cameras = calloc(nc, sizeof *p->cameras);
    if (!p->cameras) {
        st_free(p);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u cameras)", nc);
    }
    if (src->n_cameras)
        memcpy(p->cameras, src->cameras, src->n_cameras * sizeof *p->cameras);
    lg_camera *c = &p->cameras[slot];
    memset(c, 0, sizeof *c);
    c->name = p->name;
    memcpy(c->position, &eye, sizeof c->position);
    memcpy(c->target, &target, sizeof c->target);
    memcpy(c->up, &up, sizeof c->up);
    c->yfov = yfov;
    c->znear = znear;
    c->zfar = zfar;
    c->aspect = (float)aspect;
    p->scene.cameras = p->cameras;
    p->scene.n_cameras = nc;
    p->scene.camera = slot;
    if ((rc = st_carriers(n, p, src, UINT32_MAX, slot))) {
        st_free(p);
        return rc;
    }
    return st_publish(n, p);
}

/* ---- light ----------------------------------------------------------------------------------- */

enum { LIGHT_ADD = 0, LIGHT_REPLACE };
enum { LIGHT_DIRECTIONAL = 0, LIGHT_POINT, LIGHT_SPOT };
enum { AIM_DIRECTION = 0, AIM_TARGET };

/* A light's direction from `direction`, or for a spot light aimed at `target`, from its
 * position to the target; a zero result is an error naming what made it. */
static int light_direction(lg_node *n, int type, lg_vec3 pos, lg_vec3 *out)
{
    int rc;
    lg_vec3 d_in;
    bool aim_target = type == LIGHT_SPOT && lg_param_enum(n, "aim") == AIM_TARGET;
    if (aim_target) {
        lg_vec3 target;
        if ((rc = st_vec3(n, "target", &target)))
            return rc;
        d_in = lg_v3_sub(target, pos);
    } else if ((rc = st_vec3(n, "direction", &d_in))) {
        return rc;
    }
    /* normalised in double: a float difference of two large positions may overflow */
    double len = sqrt((double)d_in.x * d_in.x + (double)d_in.y * d_in.y + (double)d_in.z * d_in.z);
    if (aim_target && !(len > 0.0)) {
        const lg_value *t = lg_param(n, "target");
        return lg_error(n,
                        "aim = target: target = [%g, %g, %g] is the light's own position: "
                        "a spot light needs a point to shine at other than where it stands",
                        t->v[0], t->v[1], t->v[2]);
    }
    if (!(len > 0.0) || !isfinite(len))
        return lg_error(n,
                        "direction = [%g, %g, %g] is the zero vector: a %s light needs the "
                        "direction its light travels (e.g. [0, -1, 0] for light falling "
                        "straight down)",
                        (double)d_in.x, (double)d_in.y, (double)d_in.z,
                        type == LIGHT_SPOT ? "spot" : "directional");
    *out = lg_v3((float)(d_in.x / len), (float)(d_in.y / len), (float)(d_in.z / len));
    return 0;
}

static int light_prepare(lg_node *n)
{
    const lg_resource *in;
    const lg_scene *src;
    int rc = st_input(n, &in, &src);
    if (rc)
        return rc;

    lg_light l;
    memset(&l, 0, sizeof l);
    lg_vec3 color, dir = lg_v3(0, 0, 0), pos = lg_v3(0, 0, 0);
    if ((rc = st_vec3(n, "color", &color)))
        return rc;
    int type = lg_param_enum(n, "type");
    if (type == LIGHT_DIRECTIONAL) {
        l.type = LG_LIGHT_DIRECTIONAL;
        if ((rc = light_direction(n, type, pos, &dir)))
            return rc;
    } else {
        l.type = type == LIGHT_SPOT ? LG_LIGHT_SPOT : LG_LIGHT_POINT;
        if ((rc = st_vec3(n, "position", &pos)))
            return rc;
        l.range = (float)lg_param_float(n, "range");
    }
    if (type == LIGHT_SPOT) {
        if ((rc = light_direction(n, type, pos, &dir)))
            return rc;
        /* KHR_lights_punctual: 0 <= inner < outer <= pi/2 (the schema bounds both to
         * [0, 90]); equal angles would make the smooth falloff a division by zero */
        double inner = lg_param_float(n, "inner_cone_deg");
        double outer = lg_param_float(n, "outer_cone_deg");
        if (!(inner < outer))
            return lg_error(n,
                            "inner_cone_deg = %g, outer_cone_deg = %g: a spot light needs "
                            "inner < outer (glTF KHR_lights_punctual: 0 <= inner < outer <= "
                            "90 degrees; the intensity falls smoothly from full at the inner "
                            "cone to zero at the outer)",
                            inner, outer);
        l.inner_cone = (float)(inner * LG_PI / 180.0);
        l.outer_cone = (float)(outer * LG_PI / 180.0);
    }
    memcpy(l.color, &color, sizeof l.color);
    l.intensity = (float)lg_param_float(n, "intensity");
    memcpy(l.direction, &dir, sizeof l.direction);
    memcpy(l.position, &pos, sizeof l.position);

    bool replace = lg_param_enum(n, "mode") == LIGHT_REPLACE;
    uint32_t keep = replace ? 0 : src->n_lights;
    if (keep == UINT32_MAX)
        return lg_error(n, "the scene already has %u lights", keep);
    st_payload *p;
    if ((rc = st_derive(n, in, src, replace ? "light (replacing all)" : "light", &p)))
        return rc;
    p->lights = calloc((size_t)keep + 1, sizeof *p->lights);
    if (!p->lights) {
        st_free(p);
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%u lights)", keep + 1);
    }
    if (keep)
        memcpy(p->lights, src->lights, keep * sizeof *p->lights);
    l.name = p->name;
    p->lights[keep] = l;
    p->scene.lights = p->lights;
    p->scene.n_lights = keep + 1;
    if ((rc = st_carriers(n, p, src, keep, UINT32_MAX))) {
        st_free(p);
        return rc;
    }
    return st_publish(n, p);
}

/* ---- medium ---------------------------------------------------------------------------------- */

enum { FIELD_NONE = 0, FIELD_UNIFORM, FIELD_FBM, FIELD_VDB };

/* Inputs are bounded (README.md "medium"): a .vdb file of at most ST_VDB_MAX_FILE bytes,
 * whose grid made dense holds at most ST_VDB_MAX_VOXELS voxels (2^27: 512 MiB of floats);
 * a height fog whose multiplier over the scene stays within ST_MAX_MULTIPLIER (beyond it
 * the fog is a wall: a sign of a wrong height_base or falloff, and of float overflow). */
#define ST_VDB_MAX_FILE ((uint64_t)1 << 30)
#define ST_VDB_MAX_VOXELS ((uint64_t)1 << 27)
#define ST_MAX_MULTIPLIER 1e6

/* The grid's host memory counted against the node (lg_account_alloc): it lives in the
 * scene payload, made by each prepare; the count is released at the next prepare and in
 * destroy. n->user holds the count (a malloc'd uint64_t, made on first use), as the gltf
 * node does for its textures. */
static void medium_count(lg_node *n, uint64_t bytes)
{
    uint64_t *counted = n->user;
    if (!counted && bytes) {
        counted = calloc(1, sizeof *counted);
        if (!counted)
            return; /* the profile then misses the bytes; the field itself is fine */
        n->user = counted;
    }
    if (!counted)
        return;
    if (*counted)
        lg_account_free(n, *counted);
    *counted = bytes;
    if (bytes)
        lg_account_alloc(n, bytes);
}

static void medium_destroy(lg_node *n)
{
    medium_count(n, 0);
    free(n->user);
    n->user = NULL;
}

/* Column-major affine inverse (the 3x3 part by cofactors, then the translation); false
 * when singular or not finite. */
static bool affine_inverse(const double m[16], double out[16])
{
    double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6],
           i = m[10];
    double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    if (!(fabs(det) > 1e-300) || !isfinite(det))
        return false;
    double r[9] = { (e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det,
                    (f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det,
                    (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det };
    memset(out, 0, 16 * sizeof *out);
    for (int row = 0; row < 3; row++) {
        for (int col = 0; col < 3; col++)
            out[col * 4 + row] = r[row * 3 + col];
        out[12 + row] = -(r[row * 3] * m[12] + r[row * 3 + 1] * m[13] + r[row * 3 + 2] * m[14]);
    }
    out[15] = 1.0;
    for (int k = 0; k < 16; k++)
        if (!isfinite(out[k]))
            return false;
    return true;
}

/* The world box of the grid's support: index box [-1, n] (the trilinear blend reaches a
 * voxel beyond the outer centres, where it falls to 0, as OpenVDB's BoxSampler does with a
 * background of 0) through index_to_world, the axis-aligned box of its eight corners. */
static void grid_world_box(const lg_density_grid *g, float lo[3], float hi[3])
{
    double n[3] = { g->nx, g->ny, g->nz };
    for (int c = 0; c < 3; c++) {
        lo[c] = FLT_MAX;
        hi[c] = -FLT_MAX;
    }
    const double *m = g->index_to_world;
    for (int k = 0; k < 8; k++) {
        double q[3] = { (k & 1) ? n[0] : -1.0, (k & 2) ? n[1] : -1.0, (k & 4) ? n[2] : -1.0 };
        for (int r = 0; r < 3; r++) {
            double w = m[r] * q[0] + m[4 + r] * q[1] + m[8 + r] * q[2] + m[12 + r];
            lo[r] = fminf(lo[r], (float)w);
            hi[r] = fmaxf(hi[r], (float)w);
        }
    }
}

/* 64-bit FNV-1a of the file's bytes: the grid's content in the result's identity. */
static uint64_t fnv1a(const void *bytes, size_t len)
{
    const unsigned char *b = bytes;
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < len; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* field = vdb: reads the file, makes its grid dense into p (grid, values, source) and
 * sets the field's kind, grid and bounds. */

#ifdef ST_HAVE_OPENVDB
typedef int (*st_vdb_read_fn)(const void *bytes, size_t len, const char *grid, uint64_t max_voxels,
                              st_vdb_grid *out, char *err, size_t errlen);

/* st_vdb_read from scene_tools_vdb.so, the library beside this plugin (meson.build says
 * why it is not linked in), loaded on first use and kept loaded (OpenVDB's registries live
 * as long as the process). NULL with the reason in err. */
static st_vdb_read_fn st_vdb_resolve(char *err, size_t errlen)
{
    static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
    static st_vdb_read_fn fn;
    pthread_mutex_lock(&lock);
    if (!fn) {
        Dl_info info;
        if (!dladdr((void *)st_vdb_resolve, &info) || !info.dli_fname) {
            snprintf(err, errlen, "cannot find where the scene_tools plugin lies (dladdr)");
        } else {
            const char *slash = strrchr(info.dli_fname, '/');
            int dirlen = slash ? (int)(slash - info.dli_fname) : 1;
            char path[4096];
            snprintf(path, sizeof path, "%.*s/scene_tools_vdb.so", dirlen,
                     slash ? info.dli_fname : ".");
            void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
            void *sym = h ? dlsym(h, "st_vdb_read") : NULL;
            if (!h)
                snprintf(err, errlen, "%s", dlerror());
            else if (!sym)
                snprintf(err, errlen, "%s has no st_vdb_read", path);
            else
                memcpy(&fn, &sym, sizeof fn); /* a data pointer to a function pointer */
        }
    }
    st_vdb_read_fn r = fn;
    pthread_mutex_unlock(&lock);
    return r;
}
#endif

static int medium_vdb(lg_node *n, st_payload *p, uint64_t *bytes)
{
    const char *path = lg_param_string(n, "vdb");
    const char *want = lg_param_string(n, "grid");
    if (!path || !*path)
        return lg_error(n, "field = vdb but parameter 'vdb' is empty: name a .vdb file "
                           "(tools/make_vdb_cloud.cpp writes one)");
#ifndef ST_HAVE_OPENVDB
    (void)p;
    (void)bytes;
    (void)want;
    return lg_error(n,
                    "field = vdb, vdb = '%s': this build of lightgraph has no OpenVDB "
                    "(libopenvdb-dev and libboost-dev were not found when it was configured; "
                    "install them with tools/deps.sh and reconfigure), so it cannot read VDB "
                    "grids: use field = fbm or uniform",
                    path);
#else
    double scale = lg_param_float(n, "vdb_scale");
    lg_vec3 tr;
    int rc = st_vec3(n, "vdb_translate", &tr);
    if (rc)
        return rc;
    if (!(scale > 0))
        return lg_error(n, "vdb_scale = %g: the grid's scale must be > 0", scale);
    char why[512];
    size_t len = 0;
    double t0 = lg_now(n);
    void *data = lg_file_read(path, ST_VDB_MAX_FILE, &len, why, sizeof why);
    if (!data)
        return lg_error(n, "vdb = '%s': cannot read it: %s", path, why);
    uint64_t hash = fnv1a(data, len);
    st_vdb_grid g;
    st_vdb_read_fn read_grid = st_vdb_resolve(why, sizeof why);
    if (!read_grid) {
        free(data);
        return lg_error(n, "vdb = '%s': cannot load the OpenVDB reader: %s", path, why);
    }
    rc = read_grid(data, len, want, ST_VDB_MAX_VOXELS, &g, why, sizeof why);
    free(data);
    if (rc)
        return lg_error(n, "vdb = '%s': %s", path, why);
    lg_add_content_key(n, &hash, sizeof hash);
    p->grid_values = g.values;
    size_t srclen = strlen(path) + strlen(g.name) + 2;
    p->grid_source = malloc(srclen);
    if (!p->grid_source)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (grid name)");
    snprintf(p->grid_source, srclen, "%s:%s", path, g.name);
    lg_density_grid *d = &p->grid;
    d->nx = g.nx;
    d->ny = g.ny;
    d->nz = g.nz;
    d->values = g.values;
    d->max_value = g.max_value;
    d->source = p->grid_source;
    /* the node's own placement after the file's: world = scale x file world + translate */
    memcpy(d->index_to_world, g.index_to_world, sizeof d->index_to_world);
    for (int k = 0; k < 16; k++)
        if (k % 4 != 3)
            d->index_to_world[k] *= scale;
    d->index_to_world[12] += tr.x;
    d->index_to_world[13] += tr.y;
    d->index_to_world[14] += tr.z;
    if (!affine_inverse(d->index_to_world, d->world_to_index))
        return lg_error(n, "vdb = '%s', grid '%s': its transform times vdb_scale = %g is singular",
                        path, g.name, scale);
    p->field.kind = LG_FIELD_GRID;
    p->field.grid = d;
    grid_world_box(d, p->field.bounds_min, p->field.bounds_max);
    *bytes = (uint64_t)g.nx * g.ny * g.nz * sizeof(float);
    double vs[3];
    for (int c = 0; c < 3; c++)
        vs[c] = sqrt(d->index_to_world[4 * c] * d->index_to_world[4 * c] +
                     d->index_to_world[4 * c + 1] * d->index_to_world[4 * c + 1] +
                     d->index_to_world[4 * c + 2] * d->index_to_world[4 * c + 2]);
    lg_log(n, LG_LOG_INFO,
           "vdb '%s', grid '%s': %ux%ux%u voxels from VDB index [%d, %d, %d] (%.1f MiB), voxel "
           "%g x %g x %g, values up to %g, read in %.1f ms",
           path, g.name, g.nx, g.ny, g.nz, g.bbox_min[0], g.bbox_min[1], g.bbox_min[2],
           (double)*bytes / (1 << 20), vs[0], vs[1], vs[2], (double)g.max_value,
           (lg_now(n) - t0) * 1e3);
    if (g.background > 0.0f)
        lg_log(n, LG_LOG_WARN,
               "vdb '%s', grid '%s': its background is %g, but outside the active voxels' box "
               "the density is 0 here (a constant fog everywhere is density with field = "
               "none)",
               path, g.name, (double)g.background);
    if (!(g.max_value > 0.0f))
        lg_log(n, LG_LOG_WARN, "vdb '%s', grid '%s': every value is 0: the medium is empty", path,
               g.name);
    return 0;
#endif
}

/* field = fbm: the noise's parameters, checked. */
static int medium_fbm(lg_node *n, lg_density_field *f)
{
    double freq = lg_param_float(n, "frequency"), lac = lg_param_float(n, "lacunarity");
    double gain = lg_param_float(n, "gain"), off = lg_param_float(n, "offset");
    double scale = lg_param_float(n, "scale");
    if (!(freq > 0))
        return lg_error(n,
                        "frequency = %g: the first octave's frequency must be > 0 (1 / scene "
                        "unit)",
                        freq);
    if (!(gain > 0 && gain < 1))
        return lg_error(n, "gain = %g: the amplitude ratio between octaves must be inside (0, 1)",
                        gain);
    f->kind = LG_FIELD_FBM;
    f->fbm.octaves = (uint32_t)lg_param_int(n, "octaves");
    f->fbm.seed = (uint32_t)lg_param_int(n, "seed");
    f->fbm.frequency = (float)freq;
    f->fbm.lacunarity = (float)lac;
    f->fbm.gain = (float)gain;
    f->fbm.offset = (float)off;
    f->fbm.scale = (float)scale;
    return 0;
}

/* A box from box_min, box_max: none (everywhere) when both are equal (the defaults). */
static int medium_box(lg_node *n, lg_density_field *f, bool *have)
{
    lg_vec3 lo, hi;
    int rc;
    if ((rc = st_vec3(n, "box_min", &lo)) || (rc = st_vec3(n, "box_max", &hi)))
        return rc;
    *have = !(lo.x == hi.x && lo.y == hi.y && lo.z == hi.z);
    if (!*have)
        return 0;
    float l[3] = { lo.x, lo.y, lo.z }, h[3] = { hi.x, hi.y, hi.z };
    static const char axis[3] = { 'x', 'y', 'z' };
    for (int c = 0; c < 3; c++) {
        if (!(l[c] < h[c]))
            return lg_error(n,
                            "box_min = [%g, %g, %g], box_max = [%g, %g, %g]: along %c the box "
                            "is %s; give box_min < box_max on every axis (or equal vectors for "
                            "no box)",
                            (double)l[0], (double)l[1], (double)l[2], (double)h[0], (double)h[1],
                            (double)h[2], axis[c],
                            l[c] == h[c] ? "flat (no volume)" : "inside out");
        f->bounds_min[c] = fmaxf(f->bounds_min[c], l[c]);
        f->bounds_max[c] = fminf(f->bounds_max[c], h[c]);
    }
    return 0;
}

static const char *const field_names[] = { "none", "uniform", "fbm", "vdb", NULL };

static int medium_prepare(lg_node *n)
{
    const lg_resource *in;
    const lg_scene *src;
    int rc = st_input(n, &in, &src);
    if (rc)
        return rc;
    medium_count(n, 0);
    lg_medium m;
    memset(&m, 0, sizeof m);
    lg_vec3 sc, ab;
    if ((rc = st_vec3(n, "scattering", &sc)) || (rc = st_vec3(n, "absorption", &ab)))
        return rc;
    double density = lg_param_float(n, "density"), g = lg_param_float(n, "g");
    /* the declared ranges hold these already; checked again because gating and every
     * phase function depend on them */
    if (!(density >= 0))
        return lg_error(n, "density = %g must be >= 0 (0 removes the medium)", density);
    if (!(g > -1 && g < 1))
        return lg_error(n, "g = %g: the Henyey-Greenstein anisotropy must be inside (-1, 1)", g);
    m.present = density > 0;
    m.density = (float)density;
    memcpy(m.scattering, &sc, sizeof m.scattering);
    memcpy(m.absorption, &ab, sizeof m.absorption);
    m.g = (float)g;
    if (m.present && lg_v3_length(sc) == 0 && lg_v3_length(ab) == 0)
        lg_log(n, LG_LOG_WARN,
               "density = %g but scattering and absorption are both 0: the "
               "medium has no effect, yet media nodes will run (density = 0 "
               "removes it)",
               density);
    int kind = lg_param_enum(n, "field");
    double falloff = lg_param_float(n, "height_falloff"), base = lg_param_float(n, "height_base");
    const char *vdb = lg_param_string(n, "vdb");
    if (kind != FIELD_VDB && vdb && *vdb)
        lg_log(n, LG_LOG_WARN, "vdb = '%s' is ignored: field = %s (field = vdb reads it)", vdb,
               field_names[kind]);
    st_payload *p;
    if ((rc = st_derive(n, in, src, m.present ? "medium" : "medium (none)", &p)))
        return rc;
    uint64_t bytes = 0;
    if (kind != FIELD_NONE) {
        lg_density_field *f = &p->field;
        for (int c = 0; c < 3; c++) {
            f->bounds_min[c] = -FLT_MAX;
            f->bounds_max[c] = FLT_MAX;
        }
        f->kind = LG_FIELD_UNIFORM;
        f->height_falloff = (float)falloff;
        f->height_base = (float)base;
        bool have_box = false;
        if (kind == FIELD_VDB)
            rc = medium_vdb(n, p, &bytes);
        else if (kind == FIELD_FBM)
            rc = medium_fbm(n, f);
        if (!rc)
            rc = medium_box(n, f, &have_box);
        if (rc) {
            st_free(p);
            return rc;
        }
        m.field = f;
        if (kind == FIELD_UNIFORM && !have_box && falloff == 0)
            lg_log(n, LG_LOG_INFO,
                   "field = uniform without height fog or box is the homogeneous medium, run "
                   "through the heterogeneous code (field = none is the same fog, cheaper)");
        double mmax = 1.0;
        if (kind == FIELD_FBM) {
            double blo[3], bhi[3];
            for (int c = 0; c < 3; c++) {
                blo[c] = f->bounds_min[c];
                bhi[c] = f->bounds_max[c];
            }
            mmax = lg_medium_field_max(&m, blo, bhi);
            if (!(mmax > 0))
                lg_log(n, LG_LOG_WARN,
                       "offset = %g is at least the fBm's largest sum (%g for %u octaves of "
                       "gain %g): the field is 0 everywhere, the medium empty",
                       (double)f->fbm.offset,
                       (double)f->fbm.offset + mmax / fmax((double)f->fbm.scale, 1e-30),
                       f->fbm.octaves, (double)f->fbm.gain);
        }
        bool empty = false;
        for (int c = 0; c < 3; c++)
            empty = empty || !(f->bounds_min[c] <= f->bounds_max[c]);
        if (empty)
            lg_log(n, LG_LOG_WARN,
                   "the box (box_min, box_max) misses the grid: the medium is "
                   "empty");
        /* height fog: its multiplier over the part of the scene the field covers */
        lg_vec3 centre, corners[8];
        float radius;
        if (falloff > 0 && st_bounds(src, &centre, &radius, corners)) {
            double ylo = fmax((double)src->bounds_min[1], (double)f->bounds_min[1]);
            double hmax = exp(-falloff * (ylo - base));
            if (!(hmax <= ST_MAX_MULTIPLIER)) {
                st_free(p);
                return lg_error(n,
                                "height_falloff = %g, height_base = %g: at the lowest point of "
                                "the scene the fog covers (y = %g) the height fog multiplies "
                                "the density by e^(%g (%g - %g)) = %.3g, over %g: raise "
                                "height_base towards the floor or lower height_falloff",
                                falloff, base, ylo, falloff, base, ylo, hmax, ST_MAX_MULTIPLIER);
            }
        }
    } else {
        const lg_value *lo = lg_param(n, "box_min"), *hi = lg_param(n, "box_max");
        bool box = lo && hi &&
                   (lo->v[0] != hi->v[0] || lo->v[1] != hi->v[1] || lo->v[2] != hi->v[2]);
        if (falloff != 0 || box)
            lg_log(n, LG_LOG_WARN,
                   "%s ignored with field = none (the homogeneous medium): set field = uniform "
                   "for height fog or a box of fog",
                   falloff != 0 && box ? "height_falloff, box_min and box_max are"
                   : box               ? "box_min and box_max are"
                                       : "height_falloff is");
    }
    p->scene.medium = m;
    rc = st_publish(n, p);
    if (rc)
        return rc; /* the host has freed the payload */
    medium_count(n, bytes);
    return 0;
}

/* ---- environment ----------------------------------------------------------------------------- */

/* The derived scene records only that a probe lights it (features.probe): the probe's data
 * reaches the nodes that use it through their own `probe` input, an edge the planner sees,
 * rather than through a pointer hidden in the scene (which the host could not track: the
 * probe is written in execute(), after this node's prepare()). lg_scene therefore needs no
 * new field. A gated (neutral) probe attaches nothing. */
static int environment_prepare(lg_node *n)
{
    const lg_resource *in;
    const lg_scene *src;
    int rc = st_input(n, &in, &src);
    if (rc)
        return rc;
    const lg_resource *pr = lg_input(n, 1);
    lg_resource_info pi;
    lg_assert_input(n, 1);
    lg_describe(pr, &pi, n);
    if (pi.kind != LG_KIND_PROBE)
        return lg_error(n, "input 'probe' is not a probe (a `probe` node makes one)");
    st_payload *p;
    if ((rc = st_derive(n, in, src, pi.neutral ? "environment (none)" : "environment", &p)))
        return rc;
    p->scene.features.probe = !pi.neutral;
    return st_publish(n, p); /* lg_scene_compute_features keeps features.probe */
}

static int st_execute(lg_node *n, const lg_frame *frame)
{
    /* the derived scene was made in prepare(), where the planner needs its features */
    (void)n;
    (void)frame;
    return 0;
}

/* ---- descriptors ----------------------------------------------------------------------------- */

static const lg_port_desc st_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene to derive from (unchanged)" },
};

static const lg_port_desc environment_inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "the scene to derive from (unchanged)" },
    { .name = "probe",
      .kind = LG_KIND_PROBE,
      .doc = "the light probe around the scene (a `probe` node)" },
};

static const char *const camera_modes[] = { "look_at", "orbit", NULL };
static const lg_param_desc camera_params[] = {
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = CAM_ORBIT,
      .enum_values = camera_modes,
      .doc = "look_at: position, target, up; orbit: around the bounds' centre" },
    { .key = "position",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 5 },
      .doc = "look_at: the eye, world metres" },
    { .key = "target",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "look_at: the point looked at, world metres" },
    { .key = "up",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 1, 0 },
      .doc = "look_at: up in the image; not parallel to target - position" },
    { .key = "fov_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 45,
      .min = 0,
      .max = 180,
      .doc = "vertical field of view, degrees, inside (0, 180)" },
    { .key = "azimuth_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -360,
      .max = 360,
      .doc = "orbit: degrees about +Y from +Z (0: camera on +Z looking down -Z)" },
    { .key = "elevation_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 20,
      .min = -90,
      .max = 90,
      .doc = "orbit: degrees above the horizontal plane through the centre" },
    { .key = "distance",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e6,
      .doc = "orbit: eye to centre in bounding-sphere radii; 0 = fit the scene (README)" },
    { .key = "znear",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "near plane, metres; 0 = from the bounds" },
    { .key = "zfar",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "far plane, metres; 0 = from the bounds" },
    { .key = "aspect",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1000,
      .doc = "width / height; 0 = the output image's (orbit fits to the render size)" },
};

static const char *const light_modes[] = { "add", "replace", NULL };
static const char *const light_types[] = { "directional", "point", "spot", NULL };
static const char *const light_aims[] = { "direction", "target", NULL };
static const lg_param_desc light_params[] = {
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = LIGHT_ADD,
      .enum_values = light_modes,
      .doc = "add: keep the scene's lights; replace: this light is the only one" },
    { .key = "type",
      .type = LG_PARAM_ENUM,
      .def.e = LIGHT_DIRECTIONAL,
      .enum_values = light_types,
      .doc = "directional (direction), point (position) or spot (position, direction or "
             "target, cones)" },
    { .key = "direction",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, -1, 0 },
      .doc = "directional, spot: the direction the light travels, world; normalised, not zero" },
    { .key = "position",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "point, spot: world metres" },
    { .key = "aim",
      .type = LG_PARAM_ENUM,
      .def.e = AIM_DIRECTION,
      .enum_values = light_aims,
      .doc = "spot: aimed along `direction`, or from `position` at `target`" },
    { .key = "target",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "spot with aim = target: the point the cone's axis passes through, world" },
    { .key = "inner_cone_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 90,
      .doc = "spot: full intensity inside this angle from the axis, degrees (< outer)" },
    { .key = "outer_cone_deg",
      .type = LG_PARAM_FLOAT,
      .def.f = 45,
      .min = 0,
      .max = 90,
      .doc = "spot: no light beyond this angle from the axis, degrees; glTF's smooth "
             "falloff between" },
    { .key = "color",
      .type = LG_PARAM_COLOR,
      .def.v = { 1, 1, 1 },
      .min = 0,
      .max = 1e6,
      .doc = "linear RGB" },
    { .key = "intensity",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e6,
      .doc = "glTF units: lux (directional), candela (point, spot)" },
    { .key = "range",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e30,
      .doc = "point, spot: metres beyond which the light has no effect; 0 = infinite" },
};

static const lg_param_desc medium_params[] = {
    { .key = "density",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e6,
      .doc = "scales the coefficients; 0 = no medium (media nodes are gated)" },
    { .key = "scattering",
      .type = LG_PARAM_COLOR,
      .def.v = { 0.1, 0.1, 0.1 },
      .min = 0,
      .max = 1e6,
      .doc = "scattering coefficient per unit density, 1/m, linear RGB" },
    { .key = "absorption",
      .type = LG_PARAM_COLOR,
      .def.v = { 0, 0, 0 },
      .min = 0,
      .max = 1e6,
      .doc = "absorption coefficient per unit density, 1/m, linear RGB" },
    { .key = "g",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -0.99,
      .max = 0.99,
      .doc = "Henyey-Greenstein anisotropy (> 0: forward scattering)" },
    /* the density field (ABI 3.2; README.md "medium"): m(p) = inside(p) f(p) h(p) */
    { .key = "field",
      .type = LG_PARAM_ENUM,
      .def.e = FIELD_NONE,
      .enum_values = field_names,
      .doc = "none: homogeneous; uniform: f = 1 (height fog, box); fbm: noise; vdb: a VDB "
             "float grid" },
    { .key = "vdb", .type = LG_PARAM_PATH, .def.s = "", .doc = "field = vdb: the .vdb file" },
    { .key = "grid",
      .type = LG_PARAM_STRING,
      .def.s = "",
      .doc = "field = vdb: the float grid's name; empty = the file's first float grid" },
    { .key = "vdb_scale",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e6,
      .doc = "field = vdb: world = vdb_scale x (the grid's own world) + vdb_translate; > 0" },
    { .key = "vdb_translate",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "field = vdb: added after vdb_scale, world units" },
    { .key = "octaves",
      .type = LG_PARAM_INT,
      .def.i = 5,
      .min = 1,
      .max = 16,
      .doc = "field = fbm: noise octaves summed" },
    { .key = "seed",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 4294967295.0,
      .doc = "field = fbm: the noise's seed (another seed, another cloud)" },
    { .key = "frequency",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e6,
      .doc = "field = fbm: the first octave's frequency, 1 / scene unit, > 0" },
    { .key = "lacunarity",
      .type = LG_PARAM_FLOAT,
      .def.f = 2,
      .min = 1,
      .max = 16,
      .doc = "field = fbm: frequency ratio between octaves" },
    { .key = "gain",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.5,
      .min = 0,
      .max = 1,
      .doc = "field = fbm: amplitude ratio between octaves, inside (0, 1)" },
    { .key = "offset",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -16,
      .max = 16,
      .doc = "field = fbm: subtracted from the sum (> 0 leaves clear holes)" },
    { .key = "scale",
      .type = LG_PARAM_FLOAT,
      .def.f = 1,
      .min = 0,
      .max = 1e6,
      .doc = "field = fbm: multiplies max(0, sum - offset)" },
    { .key = "height_falloff",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = 0,
      .max = 1e3,
      .doc = "any field: height fog exp(-falloff (y - height_base)), 1 / scene unit; 0 = none" },
    { .key = "height_base",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -1e30,
      .max = 1e30,
      .doc = "any field: world y where the height fog's multiplier is 1" },
    { .key = "box_min",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "any field: the fog's box (world); equal to box_max (the default) = no box" },
    { .key = "box_max",
      .type = LG_PARAM_VEC3,
      .def.v = { 0, 0, 0 },
      .doc = "any field: the box's other corner; the density is 0 outside the box" },
};

static const lg_port_desc camera_outputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the input scene with this camera as the active one (geometry shared)" },
};
static const lg_port_desc light_outputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the input scene with this light added, or as its only light (geometry shared)" },
};
static const lg_port_desc medium_outputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the input scene with this medium (geometry shared)" },
};

static const lg_port_desc environment_outputs[] = {
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .doc = "the input scene with feature `probe` set (geometry shared; the probe's data "
             "goes to its consumers through their own `probe` input)" },
};

static const lg_node_type st_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "camera",
        .doc = "sets the scene's active camera: look_at, or orbit around its bounds",
        LG_PARAMS(camera_params),
        LG_INPUTS(st_inputs),
        LG_OUTPUTS(camera_outputs),
        .prepare = camera_prepare,
        .execute = st_execute,
        .flags = LG_NODE_POSE_INDEPENDENT, /* the animation is carried, not applied */
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "light",
        .doc = "adds a directional, point or spot light to the scene, or replaces its lights",
        LG_PARAMS(light_params),
        LG_INPUTS(st_inputs),
        LG_OUTPUTS(light_outputs),
        .prepare = light_prepare,
        .execute = st_execute,
        .flags = LG_NODE_POSE_INDEPENDENT, /* the animation is carried, not applied */
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "medium",
        .doc = "sets the scene's participating medium (density 0: none), homogeneous or with "
               "a density field (noise, height fog, box, a VDB grid)",
        LG_PARAMS(medium_params),
        LG_INPUTS(st_inputs),
        LG_OUTPUTS(medium_outputs),
        .prepare = medium_prepare,
        .execute = st_execute,
        .destroy = medium_destroy,
        .flags = LG_NODE_POSE_INDEPENDENT, /* the animation is carried, not applied */
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "environment",
        .doc = "attaches a light probe to the scene (scene feature `probe`)",
        LG_INPUTS(environment_inputs),
        LG_OUTPUTS(environment_outputs),
        .prepare = environment_prepare,
        .execute = st_execute,
        .flags = LG_NODE_POSE_INDEPENDENT, /* the animation is carried, not applied */
    },
};

LG_PLUGIN_DEFINE("scene_tools", "1.0.0",
                 "Camera, lights, medium and environment probe set from the graph", st_types)
