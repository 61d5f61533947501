/*
 * The phong node through the host, on lightless scenes built in memory by the test plugin
 * testphongscene, lit with scene_tools' `light` node; every expected value is computed here
 * from the equation (TECHNIQUES.md §1) with the scene's numbers. `test_phong CASE`:
 *
 *   flat_cube   a cube (face normals, ks = 0) seen from a corner, one directional light:
 *               each visible face equals ka Ia Od + Ii kd Od (N.L) at several points, in
 *               every shading mode (flat by construction; the others because the normals
 *               are constant per face); a face turned from the light shows ka Ia Od
 *   lights      a plane facing +Y under 1, 2, 8, 32 and 64 directional lights of known
 *               directions, colours and intensities (some from below): the image equals
 *               ka Ia Od + kd Od sum_i Ii max(N.L_i, 0) everywhere, in flat, gouraud and
 *               phong, and its mean grows with the lights' known contributions
 *   shadow      a ground plane and a quad above it, two directional lights and a shadowmap
 *               node: a point in light 1's shadow gets ambient + light 2 only, a point in
 *               light 2's shadow ambient + light 1, a point in neither both, in every mode
 *               (the per-vertex modes keep shadows per pixel)
 *   highlight   seed 1, 1.3.3: a two-triangle quad with a point light at the camera over its
 *               centre: phong shows the highlight (ks Os Ii on top of the diffuse) at the
 *               centre, gouraud does not (its vertices see none), mixed does (a highlight
 *               facet), phong_half does, flat does not
 *   blinn       the same highlight on a fine plane: blinn with x4 peaks where phong does and
 *               covers about as many pixels above half the peak; without the correction it
 *               covers clearly more
 *   depth_cue   eq. 1-12: the light term at the plane's centre, 5 from the camera, is divided
 *               by (5 + K); the ambient is not (flat: r at the facet's centroid; gouraud and
 *               mixed: r at the corners, interpolated)
 *   infinite    lights_at = infinite turns a point light over the plane into a directional
 *               one (the image is uniform); local gives the cosine falloff away from the
 *               centre; viewer = infinite keeps V constant (a highlight moves)
 *   eq13        gouraud on the cube: with the scene's face normals the +Z face's centre is
 *               lit fully; with vertex_normals = eq13 (the 24 vertices welded to 8 corners,
 *               each the normalised sum of its triangles' normals, computed here through
 *               the SDK) it is the mean of its diagonal's corner colours
 *   spot        a spot light aimed at a target over a plane (phong shading, falloff none
 *               and inverse_square): every pixel equals kd Ii (N.L) times glTF's smooth cone
 *               factor clamp((cos a - cos outer) / (cos inner - cos outer), 0, 1)^2, a the
 *               angle from the spot's axis, at the world point under the pixel's centre;
 *               the image holds full, partial and zero cone factors
 *   gating      a scene with a point light only: since ABI 3.2 the shadowmap node is kept
 *               (the light has its cube; it used to be gated), phong renders the point
 *               light's value
 *   shadow_local  (ABI 3.2) the ground and quad of `shadow` under a point light (its cube)
 *               and a spot light (70 degrees: a cube too; 45: one perspective map) 3 above:
 *               ground points in the quad's shadow get the ambient term alone in every
 *               mode, lit ones ambient + kd Od Ii (N.L) in phong and phong_half, seen from
 *               a camera outside and one inside the spot's cone; with pcf_radius 2 the
 *               shadow's edge becomes a ramp (points between 5 % and 95 % of their lit
 *               value), with 0 it has none; PCSS with a light of 0.5 m draws a penumbra at
 *               least half again as wide as with 0.25 m; PCF at radius 2 under a slanted
 *               spot leaves lit ground whole (no acne: each tap's own bias)
 *   errors      shadow maps of another scene (a light index beyond this scene's lights):
 *               exit status 1 naming the input
 *
 * Every render also passes the host's GL state check (debug builds check after each node
 * that the bindings were restored; a violation fails the render).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/vecmath.h"
#include "phong_model.h"
#include "lightgraph/test.h"

#ifndef PH_TEST_PLUGIN_DIR
#define PH_TEST_PLUGIN_DIR ""
#endif

static const char *const MODES[5] = { "flat", "gouraud", "phong", "mixed", "phong_half" };

typedef struct cam {
    lg_vec3 pos, target, up;
    double yfov_deg;
} cam;

/* The pixel (column, row; row 0 at the top) a world point lands in. */
static bool project(const cam *c, lg_vec3 p, uint32_t w, uint32_t h, uint32_t *col, uint32_t *row)
{
    float view[16], proj[16], vp[16];
    lg_m4_look_at(view, c->pos, c->target, c->up);
    lg_m4_perspective(proj, (float)(c->yfov_deg * LG_PI / 180.0), (float)w / (float)h, 0.1f, 50.0f);
    lg_m4_mul(vp, proj, view);
    lg_vec3 q = lg_m4_point(vp, p);
    double x = (q.x * 0.5 + 0.5) * w, y = (0.5 - q.y * 0.5) * h;
    if (x < 0 || y < 0 || x >= w || y >= h)
        return false;
    *col = (uint32_t)x;
    *row = (uint32_t)y;
    return true;
}

static const float *px(const lg_image *img, uint32_t x, uint32_t y)
{
    return img->pixels + ((size_t)y * img->width + x) * 4;
}

static bool near3(const float *p, const double *c, double rel)
{
    for (int k = 0; k < 3; k++)
        if (fabs(p[k] - c[k]) > rel * fabs(c[k]) + 1e-5)
            return false;
    return true;
}

static void cam_params(char *out, size_t n, const cam *c)
{
    snprintf(out, n,
             "camera_position = [%.9g, %.9g, %.9g], camera_target = [%.9g, %.9g, %.9g], "
             "camera_up = [%.9g, %.9g, %.9g], yfov_deg = %.9g",
             c->pos.x, c->pos.y, c->pos.z, c->target.x, c->target.y, c->target.z, c->up.x, c->up.y,
             c->up.z, c->yfov_deg);
}

/* Writes and renders
 *     s = test_phong_scene { scene }   + `lights` (nodes chained from s; the last is `ls`)
 *     [shadow = shadowmap { scene = ls }]   when `shadow`
 *     lit = phong { scene = ls, [shadows = shadow,] phong }
 *     output lit "out.exr"
 * and reads out.exr. `lights` must define a node `ls` (or be "ls = ..." a chain). */
static int run(lg_test *t, const char *scene, const char *lights, bool shadow, const char *phong,
               const char *size, const char *const *extra_args, lg_image *out, char **text)
{
    size_t cap = strlen(scene) + strlen(lights) + strlen(phong) + 1024;
    char *g = malloc(cap);
    if (!g)
        return -3;
    snprintf(g, cap,
             "lightgraph 1\n"
             "s = test_phong_scene { %s }\n"
             "%s\n"
             "%s"
             "lit = phong { scene = ls%s, %s }\n"
             "output lit \"out.exr\"\n",
             scene, lights, shadow ? "shadow = shadowmap { scene = ls }\n" : "",
             shadow ? ", shadows = shadow" : "", phong);
    lg_test_write_text(t, "g.lgraph", g);
    free(g);
    const char *args[16] = { "--size", size ? size : "64x48" };
    int na = 2;
    for (int i = 0; extra_args && extra_args[i] && na < 15; i++)
        args[na++] = extra_args[i];
    args[na] = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0)
        return rc;
    if (out && !lg_test_read(t, "out.exr", out, NULL))
        return -2;
    return 0;
}

#define RUN_OK(t, sc, li, sh, ph, size, img)                                                       \
    do {                                                                                           \
        int rc_ = run(t, sc, li, sh, ph, size, NULL, img, NULL);                                   \
        LG_TEST_CHECK(t, rc_ == 0, "render of {%s} {%s} failed (%d)", sc, ph, rc_);                \
        if (rc_)                                                                                   \
            return;                                                                                \
    } while (0)

/* A chain of directional lights from s, the last named ls. */
typedef struct dlight {
    lg_vec3 dir; /* the direction the light travels */
    double color[3], intensity;
} dlight;

static char *light_chain(const dlight *l, int n)
{
    size_t cap = (size_t)n * 200 + 64;
    char *s = malloc(cap), *p = s;
    if (!s)
        return NULL;
    *s = 0;
    for (int i = 0; i < n; i++) {
        char name[16], from[16];
        snprintf(name, sizeof name, i == n - 1 ? "ls" : "l%d", i);
        snprintf(from, sizeof from, i == 0 ? "s" : "l%d", i - 1);
        p += snprintf(p, cap - (size_t)(p - s),
                      "%s = light { scene = %s, direction = [%.9g, %.9g, %.9g], color = "
                      "[%.9g, %.9g, %.9g], intensity = %.9g }\n",
                      name, from, l[i].dir.x, l[i].dir.y, l[i].dir.z, l[i].color[0], l[i].color[1],
                      l[i].color[2], l[i].intensity);
    }
    return s;
}

/* ka Ia Od + sum_i Ii kd Od max(N.L_i, 0) */
static void lambert(double out[3], lg_vec3 N, const dlight *l, int n, double ka, double kd,
                    const double od[3], const double ia[3])
{
    for (int c = 0; c < 3; c++)
        out[c] = ka * ia[c] * od[c];
    for (int i = 0; i < n; i++) {
        lg_vec3 L = lg_v3_normalize_or(lg_v3_scale(l[i].dir, -1.0f), lg_v3(0, 0, 0));
        double ndl = lg_v3_dot(N, L);
        if (ndl <= 0)
            continue;
        for (int c = 0; c < 3; c++)
            out[c] += l[i].color[c] * l[i].intensity * kd * od[c] * ndl;
    }
}

/* ---- flat_cube ------------------------------------------------------------------------------- */

static void case_flat_cube(lg_test *t)
{
    const cam c = { { 2.2f, 1.7f, 2.6f }, { 0, 0, 0 }, { 0, 1, 0 }, 40 };
    const double od[3] = { 0.9, 0.5, 0.2 }, ia[3] = { 0.2, 0.3, 0.4 }, ka = 0.3, kd = 0.6;
    const dlight l = { { -0.3f, -1.0f, -0.55f }, { 1.0, 0.9, 0.8 }, 2.5 };
    char cp[512], scene[1024], phong[256];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene, "layout = cube, ka = %g, kd = %g, ks = 0, od = [%g, %g, %g], %s",
             ka, kd, od[0], od[1], od[2], cp);
    char *lights = light_chain(&l, 1);
    /* the three faces seen from (+, +, +), and two points on each besides the centre */
    static const float faces[3][3][3] = {
        { { 1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },
        { { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } },
        { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 } },
    };
    for (int mode = 0; mode < 5; mode++) {
        snprintf(phong, sizeof phong, "shading = %s, ambient = [%g, %g, %g]", MODES[mode], ia[0],
                 ia[1], ia[2]);
        lg_image img = { 0 };
        RUN_OK(t, scene, lights, false, phong, "160x120", &img);
        for (int f = 0; f < 3; f++) {
            lg_vec3 N = lg_v3(faces[f][0][0], faces[f][0][1], faces[f][0][2]);
            lg_vec3 u = lg_v3(faces[f][1][0], faces[f][1][1], faces[f][1][2]);
            lg_vec3 v = lg_v3(faces[f][2][0], faces[f][2][1], faces[f][2][2]);
            double want[3];
            lambert(want, N, &l, 1, ka, kd, od, ia);
            static const float off[3][2] = { { 0, 0 }, { 0.3f, 0.25f }, { -0.3f, -0.3f } };
            for (int k = 0; k < 3; k++) {
                lg_vec3 p = lg_v3_add(lg_v3_scale(N, 0.5f), lg_v3_add(lg_v3_scale(u, off[k][0]),
                                                                      lg_v3_scale(v, off[k][1])));
                uint32_t x, y;
                if (!project(&c, p, img.width, img.height, &x, &y)) {
                    LG_TEST_CHECK(t, false, "face %d point %d projects outside the image", f, k);
                    continue;
                }
                const float *q = px(&img, x, y);
                LG_TEST_CHECK(t, near3(q, want, 1e-4) && q[3] == 1.0f,
                              "%s: face %d point %d pixel (%u, %u) = %g %g %g %g, expected "
                              "%g %g %g 1",
                              MODES[mode], f, k, x, y, q[0], q[1], q[2], q[3], want[0], want[1],
                              want[2]);
            }
        }
        lg_image_free(&img);
    }
    /* the light from straight below: the top face gets only the ambient term */
    const dlight below = { { 0, 1, 0 }, { 1, 1, 1 }, 3 };
    char *lb = light_chain(&below, 1);
    lg_image img = { 0 };
    snprintf(phong, sizeof phong, "shading = flat, ambient = [%g, %g, %g]", ia[0], ia[1], ia[2]);
    RUN_OK(t, scene, lb, false, phong, "160x120", &img);
    uint32_t x, y;
    if (project(&c, lg_v3(0, 0.5f, 0), img.width, img.height, &x, &y)) {
        double want[3] = { ka * ia[0] * od[0], ka * ia[1] * od[1], ka * ia[2] * od[2] };
        const float *q = px(&img, x, y);
        LG_TEST_CHECK(t, near3(q, want, 1e-4),
                      "top face lit from below: %g %g %g, expected %g %g %g", q[0], q[1], q[2],
                      want[0], want[1], want[2]);
    }
    lg_image_free(&img);
    free(lb);
    free(lights);
}

/* ---- lights ---------------------------------------------------------------------------------- */

/* Light i of the lights case: directions spread over the upper hemisphere, every fifth one
 * from below (it must add nothing), colours and intensities varied. */
static dlight nth_light(int i)
{
    dlight l;
    double th = (5.0 + (i * 37) % 80) * LG_PI / 180.0; /* from -Y */
    double ph = i * 0.7;
    double s = i % 5 == 4 ? 1.0 : -1.0;
    l.dir = lg_v3((float)(sin(th) * cos(ph)), (float)(s * cos(th)), (float)(sin(th) * sin(ph)));
    l.color[0] = 1.0;
    l.color[1] = 0.5 + 0.5 * ((i * 3) % 7) / 6.0;
    l.color[2] = 0.25 + 0.75 * ((i * 5) % 11) / 10.0;
    l.intensity = 0.05 + 0.01 * (i % 9);
    return l;
}

static void case_lights(lg_test *t)
{
    const cam c = { { 0, 4, 0.001f }, { 0, 0, 0 }, { 0, 0, -1 }, 40 };
    const double od[3] = { 0.7, 0.6, 0.5 }, ia[3] = { 0.05, 0.05, 0.05 }, ka = 0.2, kd = 0.9;
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = plane, size = 8, segments = 3, ka = %g, kd = %g, ks = 0, "
             "od = [%g, %g, %g], %s",
             ka, kd, od[0], od[1], od[2], cp);
    dlight all[64];
    for (int i = 0; i < 64; i++)
        all[i] = nth_light(i);
    static const int counts[5] = { 1, 2, 8, 32, 64 };
    double prev_mean = -1.0;
    for (int k = 0; k < 5; k++) {
        int n = counts[k];
        char *lights = light_chain(all, n);
        double want[3];
        lambert(want, lg_v3(0, 1, 0), all, n, ka, kd, od, ia);
        for (int mode = 0; mode < 3; mode++) {
            char phong[256];
            snprintf(phong, sizeof phong, "shading = %s, ambient = [%g, %g, %g]", MODES[mode],
                     ia[0], ia[1], ia[2]);
            lg_image img = { 0 };
            RUN_OK(t, scene, lights, false, phong, "64x48", &img);
            double mean = 0;
            uint32_t bad = 0;
            for (uint32_t y = 0; y < img.height; y++)
                for (uint32_t x = 0; x < img.width; x++) {
                    const float *q = px(&img, x, y);
                    mean += q[0] + q[1] + q[2];
                    if (!near3(q, want, 2e-4)) {
                        if (!bad)
                            fprintf(stderr,
                                    "%d lights, %s: pixel (%u, %u) = %g %g %g, "
                                    "expected %g %g %g\n",
                                    n, MODES[mode], x, y, q[0], q[1], q[2], want[0], want[1],
                                    want[2]);
                        bad++;
                    }
                }
            mean /= 3.0 * img.width * img.height;
            LG_TEST_CHECK(t, bad == 0, "%d lights, %s: %u pixels differ from the sum", n,
                          MODES[mode], bad);
            if (mode == 2) {
                LG_TEST_CHECK(t, mean > prev_mean, "%d lights: mean %g is not above %g", n, mean,
                              prev_mean);
                prev_mean = mean;
            }
            lg_image_free(&img);
        }
        free(lights);
    }
}

/* ---- shadow ---------------------------------------------------------------------------------- */

static void case_shadow(lg_test *t)
{
    /* occluder: x, z in [-0.5, 0.5] at y = 1, double-sided (the shadow maps cull front
     * faces, and a single-sided quad facing the light would cast nothing). Light 1 travels (0.5, -1, 0): its shadow is
     * x in [0, 1], z in [-0.5, 0.5]; light 2 travels (0, -1, 0.6): z in [0.1, 1.1],
     * x in [-0.5, 0.5]. The camera on the +X side sees both shadows past the occluder. */
    const cam c = { { 3.5f, 4.0f, 0.3f }, { 0, 0, 0 }, { 0, 1, 0 }, 50 };
    const double od[3] = { 0.8, 0.7, 0.6 }, ia[3] = { 0.3, 0.3, 0.3 }, ka = 0.5, kd = 0.8;
    const dlight l[2] = { { { 0.5f, -1, 0 }, { 1, 1, 1 }, 1.0 },
                          { { 0, -1, 0.6f }, { 1, 0.8, 0.6 }, 0.7 } };
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = shadow, size = 5, segments = 1, ka = %g, kd = %g, ks = 0, "
             "od = [%g, %g, %g], double_sided = true, %s",
             ka, kd, od[0], od[1], od[2], cp);
    char *lights = light_chain(l, 2);
    double both[3], only1[3], only2[3];
    lambert(both, lg_v3(0, 1, 0), l, 2, ka, kd, od, ia);
    lambert(only1, lg_v3(0, 1, 0), &l[0], 1, ka, kd, od, ia);
    lambert(only2, lg_v3(0, 1, 0), &l[1], 1, ka, kd, od, ia);
    struct {
        lg_vec3 p;
        const double *want;
        const char *what;
    } pts[4] = {
        { { 0.65f, 0, -0.2f }, only2, "in light 1's shadow" },
        { { -0.2f, 0, 0.75f }, only1, "in light 2's shadow" },
        { { 1.6f, 0, -1.4f }, both, "lit by both" },
        { { -1.5f, 0, -1.6f }, both, "lit by both (far corner)" },
    };
    for (int mode = 0; mode < 5; mode++) {
        char phong[256];
        snprintf(phong, sizeof phong, "shading = %s, ambient = [%g, %g, %g]", MODES[mode], ia[0],
                 ia[1], ia[2]);
        lg_image img = { 0 };
        RUN_OK(t, scene, lights, true, phong, "160x120", &img);
        for (int k = 0; k < 4; k++) {
            uint32_t x, y;
            if (!project(&c, pts[k].p, img.width, img.height, &x, &y)) {
                LG_TEST_CHECK(t, false, "point %d projects outside the image", k);
                continue;
            }
            const float *q = px(&img, x, y);
            LG_TEST_CHECK(
                t, near3(q, pts[k].want, 1e-4),
                "%s: ground point %d (%s) at pixel (%u, %u) = %g %g %g, expected %g %g %g",
                MODES[mode], k, pts[k].what, x, y, q[0], q[1], q[2], pts[k].want[0], pts[k].want[1],
                pts[k].want[2]);
        }
        lg_image_free(&img);
    }
    free(lights);
}

/* ---- highlight ------------------------------------------------------------------------------- */

/* A quad of edge 4 (two triangles), ks = 1, Os = 1, n = 40, a point light at the camera 3
 * above the centre: at the centre R = V (the highlight: ks Os Ii), at the corners
 * R.V = 1/17 (none). */
static void case_highlight(lg_test *t)
{
    const cam c = { { 0, 3, 0 }, { 0, 0, 0 }, { 0, 0, -1 }, 60 };
    const double kd = 0.3, od = 0.5, ii = 1.0;
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = plane, size = 4, segments = 1, ka = 0, kd = %g, ks = 1, shininess = 40, "
             "od = [%g, %g, %g], os = [1, 1, 1], %s",
             kd, od, od, od, cp);
    const char *lights = "ls = light { scene = s, type = point, position = [0, 3, 0], "
                         "intensity = 1 }";
    double diffuse = ii * kd * od; /* N.L = 1 at the centre */
    double peak = diffuse + ii * 1.0;
    double got[5];
    for (int mode = 0; mode < 5; mode++) {
        char phong[128];
        snprintf(phong, sizeof phong, "shading = %s, ambient = [0, 0, 0]", MODES[mode]);
        lg_image img = { 0 };
        RUN_OK(t, scene, lights, false, phong, "96x96", &img);
        /* the centre of the image is a corner of four pixels: take their maximum */
        got[mode] = 0;
        for (uint32_t y = 47; y <= 48; y++)
            for (uint32_t x = 47; x <= 48; x++)
                got[mode] = fmax(got[mode], px(&img, x, y)[0]);
        lg_image_free(&img);
    }
    LG_TEST_CHECK(t, fabs(got[2] - peak) < 0.02 * peak,
                  "phong: centre %g, expected the highlight %g", got[2], peak);
    LG_TEST_CHECK(t, got[1] < diffuse + 0.05, "gouraud: centre %g shows a highlight (diffuse %g)",
                  got[1], diffuse);
    LG_TEST_CHECK(t, fabs(got[3] - got[2]) < 1e-4 * peak, "mixed: centre %g, phong %g", got[3],
                  got[2]);
    LG_TEST_CHECK(t, fabs(got[4] - peak) < 0.05 * peak, "phong_half: centre %g, expected %g",
                  got[4], peak);
    LG_TEST_CHECK(t, got[0] < 0.5 * peak, "flat: centre %g shows the full highlight %g", got[0],
                  peak);
}

/* ---- blinn ----------------------------------------------------------------------------------- */

static void case_blinn(lg_test *t)
{
    const cam c = { { 0, 3, 0 }, { 0, 0, 0 }, { 0, 0, -1 }, 60 };
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = plane, size = 4, segments = 8, ka = 0, kd = 0, ks = 1, shininess = 30, "
             "od = [0, 0, 0], os = [1, 1, 1], %s",
             cp);
    /* the light off to one side, so that the highlight is not where L = V */
    const char *lights = "ls = light { scene = s, type = point, position = [1.5, 3, 0], "
                         "intensity = 1 }";
    static const char *const variants[3] = {
        "specular = phong",
        "specular = blinn, blinn_correction = x4",
        "specular = blinn, blinn_correction = none",
    };
    double peak[3];
    uint32_t area[3], peak_x[3];
    for (int v = 0; v < 3; v++) {
        char phong[160];
        snprintf(phong, sizeof phong, "shading = phong, ambient = [0, 0, 0], %s", variants[v]);
        lg_image img = { 0 };
        RUN_OK(t, scene, lights, false, phong, "128x128", &img);
        peak[v] = 0;
        peak_x[v] = 0;
        for (uint32_t y = 0; y < img.height; y++)
            for (uint32_t x = 0; x < img.width; x++)
                if (px(&img, x, y)[0] > peak[v]) {
                    peak[v] = px(&img, x, y)[0];
                    peak_x[v] = x;
                }
        area[v] = 0;
        for (uint32_t y = 0; y < img.height; y++)
            for (uint32_t x = 0; x < img.width; x++)
                area[v] += px(&img, x, y)[0] > 0.5 * peak[v];
        lg_image_free(&img);
    }
    fprintf(stderr, "highlight pixels above half the peak: phong %u, blinn x4 %u, blinn %u\n",
            area[0], area[1], area[2]);
    LG_TEST_CHECK(t, peak[0] > 0.95 && peak[1] > 0.95, "peaks %g (phong) %g (blinn x4) are not ~1",
                  peak[0], peak[1]);
    LG_TEST_CHECK(t, abs((int)peak_x[0] - (int)peak_x[1]) <= 1, "peaks at columns %u and %u",
                  peak_x[0], peak_x[1]);
    LG_TEST_CHECK(t, area[1] > 0.7 * area[0] && area[1] < 1.3 * area[0],
                  "blinn x4 covers %u pixels, phong %u", area[1], area[0]);
    LG_TEST_CHECK(t, area[2] > 2.5 * area[0], "uncorrected blinn covers %u pixels, phong %u",
                  area[2], area[0]);
}

/* ---- depth_cue ------------------------------------------------------------------------------- */

static void case_depth_cue(lg_test *t)
{
    const cam c = { { 0, 5, 0 }, { 0, 0, 0 }, { 0, 0, -1 }, 40 };
    const double kd = 0.8, od = 0.5, ia = 0.4, ka = 0.25, K = 2.5;
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = plane, size = 4, ka = %g, kd = %g, ks = 0, od = [%g, %g, %g], %s", ka, kd,
             od, od, od, cp);
    const char *lights = "ls = light { scene = s, direction = [0, -1, 0], intensity = 2 }";
    for (int mode = 0; mode < 5; mode++) {
        char phong[200];
        snprintf(phong, sizeof phong,
                 "shading = %s, ambient = [%g, %g, %g], depth_cue = true, k = %g", MODES[mode], ia,
                 ia, ia, K);
        lg_image img = { 0 };
        RUN_OK(t, scene, lights, false, phong, "64x64", &img);
        double r = 5.0;
        /* flat evaluates at the facet's centroid; gouraud (and mixed, without a specular
         * term) at the vertices: the centre lies on the diagonal between two corners */
        if (mode == 0)
            r = sqrt(25.0 + 2.0 * (2.0 / 3.0) * (2.0 / 3.0));
        else if (mode == 1 || mode == 3)
            r = sqrt(25.0 + 8.0);
        double want = ka * ia * od + 2.0 * kd * od / (r + K);
        const float *q = px(&img, 31, 31);
        double w3[3] = { want, want, want };
        /* the pixel next to the centre is 5.002 away */
        LG_TEST_CHECK(t, near3(q, w3, mode == 0 ? 1e-4 : 2e-4), "%s: %g, expected %g", MODES[mode],
                      q[0], want);
        lg_image_free(&img);
    }
}

/* ---- infinite -------------------------------------------------------------------------------- */

static void case_infinite(lg_test *t)
{
    const cam c = { { 0, 3, 0 }, { 0, 0, 0 }, { 0, 0, -1 }, 60 };
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = plane, size = 4, segments = 4, ka = 0, kd = 1, ks = 0, od = [1, 1, 1], %s",
             cp);
    const char *lights = "ls = light { scene = s, type = point, position = [0, 2, 0], "
                         "intensity = 1 }";
    lg_image img = { 0 };
    /* infinite: the light sits straight above the scene's centre: L = +Y everywhere */
    RUN_OK(t, scene, lights, false, "shading = phong, ambient = [0, 0, 0], lights_at = infinite",
           "64x64", &img);
    double lo = 1e9, hi = -1e9;
    for (uint32_t y = 4; y < 60; y++)
        for (uint32_t x = 4; x < 60; x++) {
            lo = fmin(lo, px(&img, x, y)[0]);
            hi = fmax(hi, px(&img, x, y)[0]);
        }
    LG_TEST_CHECK(t, fabs(lo - 1.0) < 1e-5 && fabs(hi - 1.0) < 1e-5,
                  "lights_at = infinite: values in [%g, %g], expected 1 everywhere", lo, hi);
    lg_image_free(&img);
    /* local: at the plane point (1, 0, 0): N.L = 2 / sqrt(5) */
    RUN_OK(t, scene, lights, false, "shading = phong, ambient = [0, 0, 0], lights_at = local",
           "64x64", &img);
    uint32_t x, y;
    if (project(&c, lg_v3(1, 0, 0), 64, 64, &x, &y)) {
        double want = 2.0 / sqrt(5.0), got = px(&img, x, y)[0];
        /* the pixel's centre is within half a pixel (~0.05) of (1, 0, 0) */
        LG_TEST_CHECK(t, fabs(got - want) < 0.02, "lights_at = local: %g at (1, 0, 0), expected %g",
                      got, want);
    }
    lg_image_free(&img);

    /* viewer = infinite: V = +Y everywhere, so with the light off to the side at (2, 3, 0)
     * and lights_at = infinite (L towards (2, 3, 0) from the centre), R.V is one value over
     * the plane: a uniform image; a local viewer makes it vary */
    snprintf(scene, sizeof scene,
             "layout = plane, size = 4, segments = 4, ka = 0, kd = 0, ks = 1, shininess = 5, "
             "od = [0, 0, 0], os = [1, 1, 1], %s",
             cp);
    const char *side = "ls = light { scene = s, type = point, position = [1, 3, 0], "
                       "intensity = 1 }";
    for (int v = 0; v < 2; v++) {
        char phong[160];
        snprintf(phong, sizeof phong,
                 "shading = phong, ambient = [0, 0, 0], lights_at = infinite, viewer = %s",
                 v ? "local" : "infinite");
        RUN_OK(t, scene, side, false, phong, "64x64", &img);
        lo = 1e9, hi = -1e9;
        for (uint32_t yy = 4; yy < 60; yy++)
            for (uint32_t xx = 4; xx < 60; xx++) {
                lo = fmin(lo, px(&img, xx, yy)[0]);
                hi = fmax(hi, px(&img, xx, yy)[0]);
            }
        /* L = (1, 3, 0)/sqrt(10), R = (-1, 3, 0)/sqrt(10), V = +Y: R.V = 3/sqrt(10) */
        double want = pow(3.0 / sqrt(10.0), 5.0);
        if (v == 0)
            LG_TEST_CHECK(t, fabs(lo - want) < 1e-5 && fabs(hi - want) < 1e-5,
                          "viewer = infinite: values in [%g, %g], expected %g everywhere", lo, hi,
                          want);
        else
            LG_TEST_CHECK(t, hi - lo > 0.1, "viewer = local: values in [%g, %g] hardly vary", lo,
                          hi);
        lg_image_free(&img);
    }
}

/* ---- spot ------------------------------------------------------------------------------------ */

static void case_spot(lg_test *t)
{
    /* straight down at the plane y = 0; image right is +X, image up is -Z */
    const cam c = { { 0, 3, 0 }, { 0, 0, 0 }, { 0, 0, -1 }, 60 };
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = plane, size = 4, segments = 4, ka = 0, kd = 1, ks = 0, od = [1, 1, 1], %s",
             cp);
    const lg_vec3 sp = lg_v3(0.3f, 2, -0.2f), tg = lg_v3(-0.4f, 0, 0.1f);
    const double inner = 15, outer = 35, ii = 2;
    char lights[512];
    snprintf(lights, sizeof lights,
             "ls = light { scene = s, type = spot, position = [%.9g, %.9g, %.9g], aim = target, "
             "target = [%.9g, %.9g, %.9g], inner_cone_deg = %g, outer_cone_deg = %g, "
             "intensity = %g }",
             sp.x, sp.y, sp.z, tg.x, tg.y, tg.z, inner, outer, ii);
    lg_vec3 axis = lg_v3_normalize_or(lg_v3_sub(tg, sp), lg_v3(0, 0, 0));
    double ci = cos(inner * LG_PI / 180.0), co = cos(outer * LG_PI / 180.0);
    for (int fo = 0; fo < 2; fo++) {
        char phong[128];
        snprintf(phong, sizeof phong, "shading = phong, ambient = [0, 0, 0], falloff = %s",
                 fo ? "inverse_square" : "none");
        lg_image img = { 0 };
        RUN_OK(t, scene, lights, false, phong, "64x64", &img);
        const double half = 3.0 * tan(30.0 * LG_PI / 180.0);
        double worst = 0;
        int full = 0, part = 0, dark = 0;
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++) {
                /* the world point under the pixel's centre */
                double wx = ((x + 0.5) / 32.0 - 1.0) * half, wz = ((y + 0.5) / 32.0 - 1.0) * half;
                double lx = sp.x - wx, ly = sp.y, lz = sp.z - wz;
                double d = sqrt(lx * lx + ly * ly + lz * lz);
                double cosa = -(lx * axis.x + ly * axis.y + lz * axis.z) / d;
                double k = (cosa - co) / (ci - co);
                k = k < 0 ? 0 : k > 1 ? 1 : k;
                double want = ii * (ly / d) * k * k / (fo ? d * d : 1.0);
                double got = px(&img, x, y)[0];
                worst = fmax(worst, fabs(got - want));
                full += k == 1;
                part += k > 0 && k < 1;
                dark += k == 0;
            }
        LG_TEST_CHECK(t, worst < 2e-3,
                      "spot (falloff %s): largest difference from the closed "
                      "form %g",
                      fo ? "inverse_square" : "none", worst);
        LG_TEST_CHECK(t, full > 50 && part > 200 && dark > 200,
                      "spot: the image should hold full (%d), partial (%d) and zero (%d) cone "
                      "factors",
                      full, part, dark);
        lg_image_free(&img);
    }
}

/* ---- eq13 ------------------------------------------------------------------------------------ */

/* The cube of testphongscene (6 faces of 2 triangles, 24 vertices), welded to its 8 corners,
 * through the SDK's eq. 1-13: the normal at corner (sx, sy, sz) * 0.5. */
static lg_vec3 cube_eq13_normal(float sx, float sy, float sz)
{
    static const float f[6][3][3] = {
        { { 1, 0, 0 }, { 0, 0, -1 }, { 0, 1, 0 } }, { { -1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 0 } },
        { { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0, -1 } }, { { 0, -1, 0 }, { 1, 0, 0 }, { 0, 0, 1 } },
        { { 0, 0, 1 }, { 1, 0, 0 }, { 0, 1, 0 } },  { { 0, 0, -1 }, { -1, 0, 0 }, { 0, 1, 0 } },
    };
    float pos[8 * 3];
    uint32_t idx[36], ni = 0;
    for (int k = 0; k < 8; k++) {
        pos[3 * k] = k & 1 ? 0.5f : -0.5f;
        pos[3 * k + 1] = k & 2 ? 0.5f : -0.5f;
        pos[3 * k + 2] = k & 4 ? 0.5f : -0.5f;
    }
    for (int i = 0; i < 6; i++) {
        uint32_t q[4];
        for (int j = 0; j < 4; j++) {
            float a = j & 1 ? 1.0f : -1.0f, b = j & 2 ? 1.0f : -1.0f, p[3];
            for (int k = 0; k < 3; k++)
                p[k] = 0.5f * (f[i][0][k] + a * f[i][1][k] + b * f[i][2][k]);
            q[j] = (p[0] > 0) | (p[1] > 0) << 1 | (p[2] > 0) << 2;
        }
        uint32_t tri[6] = { q[0], q[1], q[3], q[0], q[3], q[2] };
        for (int k = 0; k < 6; k++)
            idx[ni++] = tri[k];
    }
    float nrm[8 * 3];
    lg_vertex_normals_eq13(pos, 8, idx, ni, nrm);
    int k = (sx > 0) | (sy > 0) << 1 | (sz > 0) << 2;
    return lg_v3(nrm[3 * k], nrm[3 * k + 1], nrm[3 * k + 2]);
}

static void case_eq13(lg_test *t)
{
    const cam c = { { 2.2f, 1.7f, 2.6f }, { 0, 0, 0 }, { 0, 1, 0 }, 40 };
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene, "layout = cube, ka = 0, kd = 1, ks = 0, od = [1, 1, 1], %s", cp);
    const char *lights = "ls = light { scene = s, direction = [0, 0, -1], intensity = 1 }";
    lg_image a = { 0 }, b = { 0 };
    RUN_OK(t, scene, lights, false, "shading = gouraud, ambient = [0, 0, 0]", "160x120", &a);
    RUN_OK(t, scene, lights, false, "shading = gouraud, ambient = [0, 0, 0], vertex_normals = eq13",
           "160x120", &b);
    /* the +Z face's centre is the midpoint of its diagonal from corner (-, -, +) to
     * (+, +, +): Gouraud gives the mean of their colours, N.L with L = +Z */
    lg_vec3 n0 = cube_eq13_normal(-1, -1, 1), n1 = cube_eq13_normal(1, 1, 1);
    double want = 0.5 * (fmax(n0.z, 0) + fmax(n1.z, 0));
    uint32_t x, y;
    if (project(&c, lg_v3(0, 0, 0.5f), 160, 120, &x, &y)) {
        double ga = px(&a, x, y)[0], gb = px(&b, x, y)[0];
        LG_TEST_CHECK(t, fabs(ga - 1.0) < 1e-4, "scene normals: +Z face centre %g, expected 1", ga);
        LG_TEST_CHECK(t, fabs(gb - want) < 0.01 && want < 0.9,
                      "eq13 normals: +Z face centre %g, expected %g (corner normals (%g %g %g), "
                      "(%g %g %g))",
                      gb, want, n0.x, n0.y, n0.z, n1.x, n1.y, n1.z);
    }
    lg_image_free(&a);
    lg_image_free(&b);
}

/* ---- gating ---------------------------------------------------------------------------------- */

static void case_gating(lg_test *t)
{
    const cam c = { { 0, 4, 0 }, { 0, 0, 0 }, { 0, 0, -1 }, 40 };
    char cp[512], scene[1024];
    cam_params(cp, sizeof cp, &c);
    snprintf(scene, sizeof scene,
             "layout = plane, size = 8, ka = 0, kd = 1, ks = 0, od = [0.5, 0.5, 0.5], %s", cp);
    const char *lights = "ls = light { scene = s, type = point, position = [0, 1, 0], "
                         "intensity = 2 }";
    const char *args[] = { "--explain", "-v", NULL };
    char *text = NULL;
    lg_image img = { 0 };
    int rc = run(t, scene, lights, true, "shading = phong, ambient = [0, 0, 0]", "64x64", args,
                 &img, &text);
    LG_TEST_CHECK(t, rc == 0, "render failed (%d)", rc);
    if (rc == 0) {
        /* since ABI 3.2 a point light has its cube: the node is kept (it was gated) */
        const char *row = text ? strstr(text, "\n  shadow ") : NULL;
        const char *eol = row ? strchr(row + 1, '\n') : NULL;
        const char *gated = row ? strstr(row, " gated ") : NULL;
        LG_TEST_CHECK(t, row && eol && !(gated && gated < eol),
                      "the shadowmap node is reported gated for a point light:\n%s",
                      text ? text : "");
        /* the centre, under the light: 2 * 1 * 0.5 * N.L = 1 */
        double got = fmax(fmax(px(&img, 31, 31)[0], px(&img, 32, 32)[0]),
                          fmax(px(&img, 31, 32)[0], px(&img, 32, 31)[0]));
        LG_TEST_CHECK(t, fabs(got - 1.0) < 1e-3,
                      "point light under a gated shadow node: %g, expected 1", got);
        lg_image_free(&img);
    }
    free(text);
}

/* ---- shadow_local ---------------------------------------------------------------------------- */

/* The point of the ground (y = 0) under pixel (x, y)'s centre, seen through c. */
static lg_vec3 ground_under(const cam *c, uint32_t x, uint32_t y, uint32_t w, uint32_t h)
{
    float view[16], proj[16], vp[16], inv[16];
    lg_m4_look_at(view, c->pos, c->target, c->up);
    lg_m4_perspective(proj, (float)(c->yfov_deg * LG_PI / 180.0), (float)w / (float)h, 0.1f, 50.0f);
    lg_m4_mul(vp, proj, view);
    lg_m4_invert(inv, vp);
    float nx = (float)((x + 0.5) / w * 2.0 - 1.0), ny = (float)(1.0 - (y + 0.5) / h * 2.0);
    lg_vec3 a = lg_m4_point(inv, lg_v3(nx, ny, -1.0f)), b = lg_m4_point(inv, lg_v3(nx, ny, 1.0f));
    float t = a.y / (a.y - b.y);
    return lg_v3_add(a, lg_v3_scale(lg_v3_sub(b, a), t));
}

static void case_shadow_local(lg_test *t)
{
    const cam cams[2] = { { { 3.5f, 4.0f, 0.3f }, { 0, 0, 0 }, { 0, 1, 0 }, 50 },
                          /* inside the spot's cone (58 degrees off its axis) */
                          { { 1.3f, 2.2f, 0.2f }, { 0.4f, 0, 0.1f }, { 0, 1, 0 }, 70 } };
    const double od[3] = { 0.8, 0.7, 0.6 }, ia = 0.3, ka = 0.5, kd = 0.8, ii = 1.5;
    const lg_vec3 q = lg_v3(0, 3, 0);
    /* the quad (x, z in [-0.5, 0.5] at y = 1) shadows |x|, |z| <= 0.75 on the ground */
    const struct {
        lg_vec3 p;
        bool lit;
    } pts[4] = { { { 0.6f, 0, 0.0f }, false },
                 { { 0.2f, 0, 0.6f }, false },
                 { { 1.2f, 0, -0.9f }, true },
                 { { -0.3f, 0, 1.4f }, true } };
    const char *lights[3] = {
        "type = point",
        "type = spot, direction = [0, -1, 0], inner_cone_deg = 60, outer_cone_deg = 70",
        "type = spot, direction = [0, -1, 0], inner_cone_deg = 35, outer_cone_deg = 45",
    };
    for (int li = 0; li < 3; li++)
        for (int ci = 0; ci < 2; ci++)
            for (int mode = 0; mode < 5; mode++) {
                if (ci == 1 && mode != 2)
                    continue; /* inside the cone: per-pixel phong is enough */
                const cam *c = &cams[ci];
                char cp[512], g[2048];
                cam_params(cp, sizeof cp, c);
                snprintf(g, sizeof g,
                         "lightgraph 1\n"
                         "s = test_phong_scene { layout = shadow, size = 5, segments = 8, "
                         "ka = %g, kd = %g, ks = 0, od = [%g, %g, %g], double_sided = true, %s }\n"
                         "ls = light { scene = s, %s, position = [0, 3, 0], intensity = %g }\n"
                         "shadow = shadowmap { scene = ls, resolution = 512 }\n"
                         "lit = phong { scene = ls, shadows = shadow, shading = %s, "
                         "falloff = none, ambient = [%g, %g, %g] }\n"
                         "output lit \"out.exr\"\n",
                         ka, kd, od[0], od[1], od[2], cp, lights[li], ii, MODES[mode], ia, ia, ia);
                lg_test_write_text(t, "g.lgraph", g);
                const char *args[] = { "--size", "160x120", NULL };
                LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, NULL) == 0,
                              "light {%s} %s: render failed", lights[li], MODES[mode]);
                lg_image img = { 0 };
                if (!lg_test_read(t, "out.exr", &img, NULL))
                    return;
                for (int k = 0; k < 4; k++) {
                    uint32_t x, y;
                    if (!project(c, pts[k].p, img.width, img.height, &x, &y)) {
                        LG_TEST_CHECK(t, false, "camera %d: point %d projects outside", ci, k);
                        continue;
                    }
                    /* the lit value at the ground point under the pixel's centre */
                    lg_vec3 gp = ground_under(c, x, y, img.width, img.height);
                    lg_vec3 d = lg_v3_sub(q, gp);
                    double cosn = d.y / lg_v3_length(d), want[3];
                    for (int ch = 0; ch < 3; ch++)
                        want[ch] = ka * ia * od[ch] + (pts[k].lit ? kd * od[ch] * ii * cosn : 0);
                    const float *v = px(&img, x, y);
                    bool per_pixel = mode == 2 || mode == 4;
                    bool ok = pts[k].lit && !per_pixel ? v[0] > ka * ia * od[0] + 0.1
                                                       : near3(v, want, 1e-4);
                    LG_TEST_CHECK(t, ok,
                                  "light {%s} camera %d %s: ground (%g, %g) %s = %g %g %g, "
                                  "want %g %g %g",
                                  lights[li], ci, MODES[mode], (double)pts[k].p.x,
                                  (double)pts[k].p.z, pts[k].lit ? "lit" : "in the shadow",
                                  (double)v[0], (double)v[1], (double)v[2], want[0], want[1],
                                  want[2]);
                }
                lg_image_free(&img);
            }

    /* PCF: ground points across the point light's shadow edge at x = 0.75 (z = 0.2), seen
     * from camera 0; their share of the lit value */
    /* runs: pcf 0, pcf 2, then PCSS with a light of 0.25 and 0.5 m (a 256 map): the
     * penumbra widens with the light's size */
    static const int pcf_r[4] = { 0, 2, 0, 0 }, res[4] = { 128, 128, 256, 256 };
    static const double pcss[4] = { 0, 0, 0.25, 0.5 };
    int ramps[4] = { 0 };
    for (int run_i = 0; run_i < 4; run_i++) {
        int r = pcf_r[run_i];
        const cam *c = &cams[0];
        char cp[512], g[2048];
        cam_params(cp, sizeof cp, c);
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_phong_scene { layout = shadow, size = 5, segments = 1, ka = %g, "
                 "kd = %g, ks = 0, od = [%g, %g, %g], double_sided = true, %s }\n"
                 "ls = light { scene = s, type = point, position = [0, 3, 0], intensity = %g }\n"
                 "shadow = shadowmap { scene = ls, resolution = %d, pcf_radius = %d, "
                 "pcss_light_size = %g }\n"
                 "lit = phong { scene = ls, shadows = shadow, shading = phong, falloff = none, "
                 "ambient = [%g, %g, %g] }\n"
                 "output lit \"out.exr\"\n",
                 ka, kd, od[0], od[1], od[2], cp, ii, res[run_i], r, pcss[run_i], ia, ia, ia);
        lg_test_write_text(t, "g.lgraph", g);
        const char *args[] = { "--size", "320x240", NULL };
        LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, NULL) == 0, "pcf %d: render failed",
                      r);
        lg_image img = { 0 };
        if (!lg_test_read(t, "out.exr", &img, NULL))
            return;
        int ramp = 0, dark = 0, lit = 0;
        for (int i = 0; i <= 60; i++) {
            lg_vec3 p = lg_v3(0.55f + 0.0075f * (float)i, 0, 0.2f);
            uint32_t x, y;
            if (!project(c, p, img.width, img.height, &x, &y))
                continue;
            lg_vec3 d = lg_v3_sub(q, ground_under(c, x, y, img.width, img.height));
            double amb = ka * ia * od[0], full = kd * od[0] * ii * d.y / lg_v3_length(d);
            double share = (px(&img, x, y)[0] - amb) / full;
            ramp += share > 0.05 && share < 0.95;
            dark += share <= 0.05;
            lit += share >= 0.95;
        }
        printf("pcf %d pcss %g: %d points dark, %d on the ramp, %d lit\n", r, pcss[run_i], dark,
               ramp, lit);
        ramps[run_i] = ramp;
        LG_TEST_CHECK(t, dark > 5 && lit > 5, "pcf %d pcss %g: %d dark, %d lit", r, pcss[run_i],
                      dark, lit);
        LG_TEST_CHECK(t, r || pcss[run_i] > 0 ? ramp >= 3 : ramp <= 1,
                      "pcf %d pcss %g: %d points part-shadowed across the edge", r, pcss[run_i],
                      ramp);
        lg_image_free(&img);
    }
    LG_TEST_CHECK(t, ramps[3] >= ramps[2] * 3 / 2,
                  "PCSS: the penumbra of a 0.5 m light (%d points) is not wider than a 0.25 m "
                  "light's (%d) by half again",
                  ramps[3], ramps[2]);

    /* no acne from the filter: a spot aimed slantwise at the ground (its depth changes
     * across the map's texels), pcf_radius 2 on a coarse map: the lit ground around the
     * cone's axis keeps its whole value (a tap k texels aside reads the ground's own depth
     * k texel tan(a) nearer the light: each tap's bias takes that) */
    {
        const cam *c = &cams[0];
        char cp[512], g[2048];
        cam_params(cp, sizeof cp, c);
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_phong_scene { layout = shadow, size = 6, segments = 8, ka = %g, "
                 "kd = %g, ks = 0, od = [%g, %g, %g], double_sided = true, %s }\n"
                 "ls = light { scene = s, type = spot, position = [0, 3, 0], aim = target, "
                 "target = [2, 0, -0.5], inner_cone_deg = 30, outer_cone_deg = 40, "
                 "intensity = %g }\n"
                 "shadow = shadowmap { scene = ls, resolution = 128, pcf_radius = 2 }\n"
                 "lit = phong { scene = ls, shadows = shadow, shading = phong, falloff = none, "
                 "ambient = [%g, %g, %g] }\n"
                 "output lit \"out.exr\"\n",
                 ka, kd, od[0], od[1], od[2], cp, ii, ia, ia, ia);
        lg_test_write_text(t, "g.lgraph", g);
        const char *args[] = { "--size", "320x240", NULL };
        LG_TEST_CHECK(t, lg_test_render(t, "g.lgraph", args, NULL) == 0, "acne: render failed");
        lg_image img = { 0 };
        if (!lg_test_read(t, "out.exr", &img, NULL))
            return;
        int acne = 0, n_pts = 0;
        for (int i = 0; i < 9; i++)
            for (int j = 0; j < 9; j++) {
                lg_vec3 p = lg_v3(1.4f + 0.15f * (float)i, 0, -1.1f + 0.15f * (float)j);
                uint32_t x, y;
                if (!project(c, p, img.width, img.height, &x, &y))
                    continue;
                lg_vec3 d = lg_v3_sub(q, ground_under(c, x, y, img.width, img.height));
                double amb = ka * ia * od[0], full = kd * od[0] * ii * d.y / lg_v3_length(d);
                acne += (px(&img, x, y)[0] - amb) / full < 0.999;
                n_pts++;
            }
        printf("acne: %d of %d lit ground points darkened\n", acne, n_pts);
        LG_TEST_CHECK(t, acne == 0 && n_pts > 60, "pcf 2: %d of %d lit ground points darkened",
                      acne, n_pts);
        lg_image_free(&img);
    }
}

/* ---- errors ---------------------------------------------------------------------------------- */

static void case_errors(lg_test *t)
{
    const char *g = "lightgraph 1\n"
                    "s = test_phong_scene { layout = shadow }\n"
                    "a = light { scene = s, direction = [0, -1, 0] }\n"
                    "b = light { scene = a, direction = [0.2, -1, 0] }\n"
                    "shadow = shadowmap { scene = b }\n"
                    "lit = phong { scene = a, shadows = shadow }\n"
                    "output lit \"out.exr\"\n";
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "32x32", NULL };
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    LG_TEST_CHECK(t, rc == 1, "shadow maps of another scene: exit status %d, expected 1", rc);
    LG_TEST_CHECK(t,
                  text && strstr(text, "node 'lit' (phong)") && strstr(text, "shadow map 1") &&
                      strstr(text, "light 1"),
                  "the message does not name the node, the map and the light:\n%s",
                  text ? text : "");
    free(text);
}

static void require_gl(lg_test *t)
{
    lg_test_require_backend(t, "gl");
}

int main(int argc, char **argv)
{
    setenv("LIGHTGRAPH_PLUGIN_PATH", PH_TEST_PLUGIN_DIR, 1);
    static const lg_test_case cases[] = {
        { "flat_cube", case_flat_cube }, { "lights", case_lights },
        { "shadow", case_shadow },       { "highlight", case_highlight },
        { "blinn", case_blinn },         { "depth_cue", case_depth_cue },
        { "infinite", case_infinite },   { "eq13", case_eq13 },
        { "gating", case_gating },       { "spot", case_spot },
        { "errors", case_errors },       { "shadow_local", case_shadow_local },
    };
    lg_test_main_opts o = { .setup = require_gl };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
