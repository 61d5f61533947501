/*
 * The viewer's camera controller (host/viewer/camera.c).
 *
 *   test_viewer_camera          the laws: orbit (a full-height drag is 180 degrees about the
 *                               target, distance kept; pitch stops short of the poles after
 *                               1000 drags, nothing NaN), pan (a point at the target's depth
 *                               follows the pointer, projected with the SDK's
 *                               lg_scene_view_make), zoom (0.85 per click, the floor), fly
 *                               (move along the camera's axes by speed * dt * scale; look
 *                               keeps the eye and the distance), init and to_camera, node text
 *   test_viewer_camera cases    prints cameras as node text for test_viewer_camera.py, which
 *                               renders them through the real scene_tools `camera` node
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/check.h"
#include "lightgraph/scene.h"
#include "lightgraph/scene_gl.h"
#include "viewer/camera.h"

static double dist3(const float a[3], const float b[3])
{
    double dx = (double)a[0] - b[0], dy = (double)a[1] - b[1], dz = (double)a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The unit view direction. */
static void fwd(const lg_vcam *v, double f[3])
{
    double d = dist3(v->target, v->position);
    for (int i = 0; i < 3; i++)
        f[i] = ((double)v->target[i] - v->position[i]) / d;
}

/* What every function must leave: finite, target != position, up unit and perpendicular. */
static int valid(const lg_vcam *v)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(v->position[i]) || !isfinite(v->target[i]) || !isfinite(v->up[i]))
            return 0;
    if (!(dist3(v->position, v->target) > 0.0))
        return 0;
    double f[3], u[3] = { v->up[0], v->up[1], v->up[2] };
    fwd(v, f);
    return fabs(sqrt(dot3(u, u)) - 1.0) < 1e-5 && fabs(dot3(u, f)) < 1e-5;
}

/* Elevation of the eye above the target, degrees. */
static double eye_elevation_deg(const lg_vcam *v)
{
    double d = dist3(v->position, v->target);
    return asin(((double)v->position[1] - v->target[1]) / d) * 180.0 / LG_PI;
}

static const float kBmin[3] = { -1, 0, -1 }, kBmax[3] = { 1, 2, 1 };

static lg_vcam make(float px, float py, float pz, float tx, float ty, float tz)
{
    lg_camera c = { 0 };
    c.position[0] = px, c.position[1] = py, c.position[2] = pz;
    c.target[0] = tx, c.target[1] = ty, c.target[2] = tz;
    c.up[1] = 1.0f;
    c.yfov = (float)(50.0 * LG_PI / 180.0);
    lg_vcam v;
    lg_vcam_init(&v, &c, kBmin, kBmax);
    return v;
}

/* ---- init / to_camera ------------------------------------------------------------------------ */

static void test_init(void)
{
    lg_vcam v = make(0, 1, 5, 0, 1, 0);
    CHECK(v.mode == LG_VCAM_ORBIT);
    CHECK(fabs(v.scale - sqrt(3.0)) < 1e-6);
    CHECK(v.position[2] == 5.0f && v.target[1] == 1.0f && v.up[1] == 1.0f);
    CHECK(fabs(v.yfov - 50.0 * LG_PI / 180.0) < 1e-6);
    CHECK(valid(&v));

    /* empty, inverted or NaN bounds: scale 1 */
    lg_camera c = { 0 };
    c.position[2] = 3, c.up[1] = 1, c.yfov = 1;
    float inv_lo[3] = { 1, 1, 1 }, inv_hi[3] = { -1, -1, -1 }, nan3[3] = { NAN, 0, 0 };
    lg_vcam_init(&v, &c, inv_lo, inv_hi);
    CHECK(v.scale == 1.0f);
    lg_vcam_init(&v, &c, nan3, kBmax);
    CHECK(v.scale == 1.0f);
    lg_vcam_init(&v, &c, NULL, NULL);
    CHECK(v.scale == 1.0f && valid(&v));
    lg_vcam_init(&v, &c, kBmin, kBmin); /* a single point */
    CHECK(v.scale == 1.0f);

    /* up parallel to the view: made perpendicular, not NaN */
    c.position[0] = 0, c.position[1] = 4, c.position[2] = 0;
    lg_vcam_init(&v, &c, kBmin, kBmax);
    CHECKF(valid(&v), "up (%g %g %g)", v.up[0], v.up[1], v.up[2]);
    /* a tilted up: kept in the view's plane */
    lg_camera t = { 0 };
    t.position[2] = 5, t.up[0] = 1, t.up[1] = 1, t.up[2] = 3, t.yfov = 1;
    lg_vcam_init(&v, &t, kBmin, kBmax);
    CHECK(valid(&v) && fabs(v.up[0] - (float)sqrt(0.5)) < 1e-6 && v.up[2] == 0.0f);

    /* no camera, or one that cannot be: looks at the bounds' centre, all of it in view */
    lg_vcam_init(&v, NULL, kBmin, kBmax);
    CHECK(valid(&v));
    CHECK(v.target[0] == 0.0f && v.target[1] == 1.0f && v.target[2] == 0.0f);
    CHECK(fabs(eye_elevation_deg(&v) - 20.0) < 1e-3);
    CHECK(dist3(v.position, v.target) * sin(0.5 * v.yfov) >= v.scale * 0.999);
    lg_camera bad = c;
    bad.yfov = NAN;
    lg_vcam_init(&v, &bad, kBmin, kBmax);
    CHECK(valid(&v) && v.target[1] == 1.0f);
    bad = c;
    memcpy(bad.target, bad.position, sizeof bad.target);
    lg_vcam_init(&v, &bad, kBmin, kBmax);
    CHECK(valid(&v) && v.target[1] == 1.0f);

    /* the depth range and aspect: kept when they make one, else 0 */
    c.position[1] = 0, c.position[2] = 5;
    c.znear = 0.1f, c.zfar = 40.0f, c.aspect = 1.5f;
    lg_vcam_init(&v, &c, kBmin, kBmax);
    CHECK(v.znear == 0.1f && v.zfar == 40.0f && v.aspect == 1.5f);
    c.zfar = 0.05f; /* below znear */
    lg_vcam_init(&v, &c, kBmin, kBmax);
    CHECK(v.znear == 0.0f && v.zfar == 0.0f && v.aspect == 1.5f);

    lg_camera out;
    memset(&out, 0xff, sizeof out);
    v = make(1, 2, 3, 0, 0, 0);
    lg_vcam_to_camera(&v, &out);
    CHECK(out.name == NULL);
    CHECK(out.reserved[0] == NULL && out.reserved[3] == NULL);
    CHECK(memcmp(out.position, v.position, sizeof out.position) == 0);
    CHECK(memcmp(out.target, v.target, sizeof out.target) == 0);
    CHECK(memcmp(out.up, v.up, sizeof out.up) == 0);
    CHECK(out.yfov == v.yfov && out.znear == v.znear && out.zfar == v.zfar);
}

/* ---- orbit ----------------------------------------------------------------------------------- */

static void test_orbit(void)
{
    const int h = 600;
    /* eye above the target's plane at 30 degrees: a full-height drag sideways is 180 degrees
     * about +Y through the target */
    lg_vcam v = make(2, 3, 1, 0.5f, 1, -0.5f);
    lg_vcam v0 = v;
    double d0 = dist3(v.position, v.target);
    lg_vcam_orbit(&v, h, 0, h);
    CHECK(valid(&v));
    CHECK(memcmp(v.target, v0.target, sizeof v.target) == 0);
    CHECKF(fabs(dist3(v.position, v.target) - d0) < 1e-5 * d0, "distance %g, was %g",
           dist3(v.position, v.target), d0);
    float want[3] = { 2 * v0.target[0] - v0.position[0], v0.position[1],
                      2 * v0.target[2] - v0.position[2] };
    CHECKF(dist3(v.position, want) < 1e-5 * d0, "eye (%g %g %g), expected (%g %g %g)",
           v.position[0], v.position[1], v.position[2], want[0], want[1], want[2]);
    /* and back by the opposite drag */
    lg_vcam_orbit(&v, -h, 0, h);
    CHECK(dist3(v.position, v0.position) < 1e-5 * d0);

    /* a quarter of the height to the right is 45 degrees, the eye moving left (towards -X
     * from +Z) so that the scene turns with the pointer */
    v = make(0, 1, 5, 0, 1, 0);
    lg_vcam_orbit(&v, h / 4.0, 0, h);
    CHECKF(fabs(v.position[0] + 5 * sin(LG_PI / 4)) < 1e-5 &&
               fabs(v.position[2] - 5 * cos(LG_PI / 4)) < 1e-5,
           "eye (%g %g %g)", v.position[0], v.position[1], v.position[2]);
    /* a full-height drag down is 180 degrees of pitch, stopped short of the top pole; a
     * quarter height down raises the eye by 45 degrees */
    v = make(0, 1, 5, 0, 1, 0);
    lg_vcam_orbit(&v, 0, h / 4.0, h);
    CHECKF(fabs(eye_elevation_deg(&v) - 45.0) < 1e-4, "elevation %g", eye_elevation_deg(&v));
    CHECK(valid(&v) && v.up[1] > 0.0f);

    /* 1000 drags towards each pole: clamped, finite, the frame orthonormal, no flip */
    v = make(0, 1, 5, 0, 1, 0);
    for (int i = 0; i < 1000; i++) {
        lg_vcam_orbit(&v, 7.3, h / 3.0, h);
        if (!valid(&v))
            break;
    }
    CHECK(valid(&v));
    double el = eye_elevation_deg(&v);
    CHECKF(el > 89.0 && el < 89.51, "elevation after 1000 drags up: %g", el);
    CHECKF(fabs(dist3(v.position, v.target) - 5.0) < 1e-3, "distance %g",
           dist3(v.position, v.target));
    for (int i = 0; i < 1000; i++)
        lg_vcam_orbit(&v, -3.1, -h / 3.0, h);
    CHECK(valid(&v));
    el = eye_elevation_deg(&v);
    CHECKF(el < -89.0 && el > -89.51, "elevation after 1000 drags down: %g", el);
    CHECK(v.up[1] > 0.0f); /* not flipped */

    /* starting exactly at a pole (looking straight down, the image's up -Z): the first turn
     * keeps the side the camera faced */
    lg_camera top = { 0 };
    top.position[1] = 5, top.up[2] = -1, top.yfov = 1;
    lg_vcam_init(&v, &top, kBmin, kBmax);
    lg_vcam_orbit(&v, 0, -1, h);
    CHECK(valid(&v));
    CHECKF(v.position[2] > 0.0f && fabs(v.position[0]) < 1e-5, "eye (%g %g %g)", v.position[0],
           v.position[1], v.position[2]);

    /* input that is no drag changes nothing */
    v0 = v = make(0, 1, 5, 0, 1, 0);
    lg_vcam_orbit(&v, NAN, 3, h);
    lg_vcam_orbit(&v, 3, INFINITY, h);
    lg_vcam_orbit(&v, 3, 3, 0);
    lg_vcam_orbit(&v, 3, 3, -10);
    CHECK(memcmp(&v, &v0, sizeof v) == 0);
    lg_vcam_orbit(&v, 1e300, 1e300, 1); /* absurd but finite: still a valid camera */
    CHECK(valid(&v));
}

/* ---- pan: checked with the SDK's own projection ---------------------------------------------- */

/* The pixel (x right, y down, row 0 at the top) where the world point p lands in a w x h view
 * of v, as every scene consumer computes it (lg_scene_view_make). */
static int project(const lg_vcam *v, const float p[3], uint32_t w, uint32_t h, double px[2])
{
    lg_camera cam;
    lg_vcam_to_camera(v, &cam);
    lg_scene s;
    memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    s.cameras = &cam;
    s.n_cameras = 1;
    memcpy(s.bounds_min, kBmin, sizeof s.bounds_min);
    memcpy(s.bounds_max, kBmax, sizeof s.bounds_max);
    lg_scene_view sv;
    if (lg_scene_view_make(NULL, &s, -1, w, h, &sv) != 0)
        return -1;
    const float *m = sv.view_proj;
    double c[4];
    for (int r = 0; r < 4; r++)
        c[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
    px[0] = (c[0] / c[3] + 1.0) * 0.5 * w;
    px[1] = (c[1] / c[3] + 1.0) * 0.5 * h;
    return 0;
}

static void test_pan(void)
{
    const uint32_t w = 320, h = 240;
    lg_vcam cams[2] = { make(0, 1, 5, 0, 1, 0), make(3, 4, -2, 0.5f, 0.5f, 0.2f) };
    lg_vcam_orbit(&cams[1], 40, -25, (int)h); /* tilted: pan must use the camera's own axes */
    for (int k = 0; k < 2; k++) {
        lg_vcam v = cams[k];
        float p[3];
        memcpy(p, v.target, sizeof p);
        double before[2], after[2];
        CHECK(project(&v, p, w, h, before) == 0);
        CHECKF(fabs(before[0] - w / 2.0) < 1e-3 && fabs(before[1] - h / 2.0) < 1e-3,
               "the target at (%g, %g)", before[0], before[1]);
        double dx = 37.0, dy = -21.5;
        lg_vcam_pan(&v, dx, dy, (int)h);
        CHECK(valid(&v));
        CHECK(project(&v, p, w, h, after) == 0);
        CHECKF(fabs(after[0] - before[0] - dx) < 0.01 && fabs(after[1] - before[1] - dy) < 0.01,
               "camera %d: the point moved by (%g, %g) pixels, the pointer by (%g, %g)", k,
               after[0] - before[0], after[1] - before[1], dx, dy);
        /* eye and target moved together: the view direction and distance are the same */
        double f0[3], f1[3];
        fwd(&cams[k], f0);
        fwd(&v, f1);
        CHECK(dot3(f0, f1) > 1.0 - 1e-9);
        CHECK(fabs(dist3(v.position, v.target) - dist3(cams[k].position, cams[k].target)) < 1e-5);
    }
    lg_vcam v = cams[0], v0 = cams[0];
    lg_vcam_pan(&v, NAN, 1, 100);
    lg_vcam_pan(&v, 1, 1, 0);
    CHECK(memcmp(&v, &v0, sizeof v) == 0);
}

/* ---- zoom ------------------------------------------------------------------------------------ */

static void test_zoom(void)
{
    lg_vcam v = make(0, 1, 5, 0, 1, 0), v0 = v;
    lg_vcam_zoom(&v, 2);
    CHECKF(fabs(dist3(v.position, v.target) - 5 * 0.85 * 0.85) < 1e-5, "distance %g",
           dist3(v.position, v.target));
    CHECK(memcmp(v.target, v0.target, sizeof v.target) == 0);
    CHECK(v.position[0] == 0.0f && v.position[1] == 1.0f); /* along the view axis */
    lg_vcam_zoom(&v, -2);
    CHECK(fabs(dist3(v.position, v.target) - 5.0) < 1e-5);
    lg_vcam_zoom(&v, 0.5); /* a touchpad's fraction of a click */
    CHECK(fabs(dist3(v.position, v.target) - 5 * sqrt(0.85)) < 1e-5);

    /* the floor: 1e-4 scale, however far one zooms; still a camera */
    v = v0;
    for (int i = 0; i < 100; i++)
        lg_vcam_zoom(&v, 1000);
    CHECK(valid(&v));
    CHECKF(fabs(dist3(v.position, v.target) - 1e-4 * v.scale) < 1e-7, "distance %g, floor %g",
           dist3(v.position, v.target), 1e-4 * v.scale);
    /* and out: finite */
    for (int i = 0; i < 100; i++)
        lg_vcam_zoom(&v, -1000);
    CHECK(valid(&v) && dist3(v.position, v.target) <= 1.0001e9 * v.scale);
    v = v0;
    lg_vcam_zoom(&v, NAN);
    lg_vcam_zoom(&v, INFINITY);
    CHECK(memcmp(&v, &v0, sizeof v) == 0);
}

/* ---- fly ------------------------------------------------------------------------------------- */

static void test_fly(void)
{
    lg_vcam v = make(2, 3, 1, 0.5f, 1, -0.5f), v0 = v;
    v.mode = LG_VCAM_FLY;
    double f[3];
    fwd(&v, f);
    const float forward_only[3] = { 0, 0, 1 };
    lg_vcam_move(&v, forward_only, 0.5, 2.0); /* 1 scale */
    double moved[3];
    for (int i = 0; i < 3; i++)
        moved[i] = (double)v.position[i] - v0.position[i];
    double want = 0.5 * 2.0 * v.scale;
    CHECKF(fabs(sqrt(dot3(moved, moved)) - want) < 1e-5, "moved %g, expected %g",
           sqrt(dot3(moved, moved)), want);
    CHECK(dot3(moved, f) > want * (1 - 1e-6)); /* along the view direction */
    CHECK(fabs(dist3(v.position, v.target) - dist3(v0.position, v0.target)) < 1e-5);
    CHECK(valid(&v));

    /* right and up along the camera's axes; a diagonal is no faster than one axis */
    v = v0;
    const float right_up[3] = { 1, 1, 0 };
    lg_vcam_move(&v, right_up, 1.0, 1.0);
    for (int i = 0; i < 3; i++)
        moved[i] = (double)v.position[i] - v0.position[i];
    CHECK(fabs(sqrt(dot3(moved, moved)) - v.scale) < 1e-5);
    CHECK(fabs(dot3(moved, f)) < 1e-5);
    double up[3] = { v0.up[0], v0.up[1], v0.up[2] };
    CHECK(fabs(dot3(moved, up) - v.scale * sqrt(0.5)) < 1e-5);
    /* out of range, NaN, dt <= 0: clamped or nothing */
    v = v0;
    const float big[3] = { 0, 0, 50 }, nan3[3] = { NAN, 0, 0 };
    lg_vcam_move(&v, big, 1.0, 1.0);
    CHECK(fabs(dist3(v.position, v0.position) - v.scale) < 1e-5);
    v = v0;
    lg_vcam_move(&v, nan3, 1.0, 1.0);
    lg_vcam_move(&v, forward_only, -1.0, 1.0);
    lg_vcam_move(&v, forward_only, 1.0, NAN);
    lg_vcam_move(&v, NULL, 1.0, 1.0);
    CHECK(memcmp(&v, &v0, sizeof v) == 0);

    /* look: half the height to the right turns the view 90 degrees right; the eye stays, the
     * target at the same distance */
    v = make(0, 1, 5, 0, 1, 0);
    v0 = v;
    lg_vcam_look(&v, 120, 0, 240);
    fwd(&v, f);
    CHECKF(fabs(f[0] - 1.0) < 1e-6 && fabs(f[1]) < 1e-6, "view (%g %g %g)", f[0], f[1], f[2]);
    CHECK(memcmp(v.position, v0.position, sizeof v.position) == 0);
    CHECK(fabs(dist3(v.position, v.target) - 5.0) < 1e-5);
    /* moving down looks down */
    lg_vcam_look(&v, 0, 40, 240);
    fwd(&v, f);
    CHECKF(fabs(f[1] + sin(LG_PI / 6)) < 1e-6, "view (%g %g %g)", f[0], f[1], f[2]);
    /* 1000 looks up: clamped short of the pole, the distance kept */
    for (int i = 0; i < 1000; i++)
        lg_vcam_look(&v, 5, -100, 240);
    fwd(&v, f);
    CHECK(valid(&v));
    CHECKF(f[1] < sin(89.51 * LG_PI / 180) && f[1] > sin(89.0 * LG_PI / 180), "view y %g", f[1]);
    CHECK(fabs(dist3(v.position, v.target) - 5.0) < 1e-4);
    CHECK(memcmp(v.position, v0.position, sizeof v.position) == 0);
}

/* ---- node text ------------------------------------------------------------------------------- */

static void test_node_text(void)
{
    lg_vcam v = make(0, 1, 5, 0, 1, 0);
    char *t = lg_vcam_node_text(&v, "cam2", "scene");
    CHECK(t != NULL);
    if (t) {
        const char *want = "cam2 = camera {\n"
                           "    scene = scene\n"
                           "    mode = look_at\n"
                           "    position = [0, 1, 5]\n"
                           "    target = [0, 1, 0]\n"
                           "    up = [0, 1, 0]\n"
                           "    fov_deg = 50\n"
                           "}\n";
        CHECKF(strcmp(t, want) == 0, "got\n%s", t);
    }
    free(t);
    v.znear = 0.25f, v.aspect = 1.75f;
    v.up[0] = -0.0f; /* printed as 0 */
    t = lg_vcam_node_text(&v, "_c", "s_1");
    CHECK(t && strstr(t, "    znear = 0.25\n") && strstr(t, "    aspect = 1.75\n"));
    CHECK(t && !strstr(t, "zfar") && !strstr(t, "-0"));
    free(t);
    CHECK(lg_vcam_node_text(&v, "1cam", "scene") == NULL);
    CHECK(lg_vcam_node_text(&v, "cam", "sce ne") == NULL);
    CHECK(lg_vcam_node_text(&v, "", "scene") == NULL);
    CHECK(lg_vcam_node_text(&v, NULL, "scene") == NULL);

    /* an eye a millimetre from a far target: six digits would print one point twice */
    lg_vcam far = make(1000.301f, 1, 2000.7f, 1000.3f, 1, 2000.7f);
    t = lg_vcam_node_text(&far, "cam", "scene");
    CHECKF(t && strstr(t, "position = [1000.30103") && strstr(t, "target = [1000.29999"), "got\n%s",
           t ? t : "(null)");
    free(t);
}

/* ---- cases for test_viewer_camera.py --------------------------------------------------------- */

/* Each case: "CASE name", "REF px py pz tx ty tz ux uy uz fov_deg znear zfar aspect" (the
 * camera's floats exactly, %.9g), the node text of a camera called c_NAME on node `scene`,
 * "END". The bounds are the bunny box's. */
static void print_case(const char *name, const lg_vcam *v)
{
    char node[64];
    snprintf(node, sizeof node, "c_%s", name);
    char *t = lg_vcam_node_text(v, node, "scene");
    if (!t) {
        fprintf(stderr, "case %s: no node text\n", name);
        exit(1);
    }
    printf("CASE %s\nREF", name);
    const float *vals[3] = { v->position, v->target, v->up };
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 3; i++)
            printf(" %.9g", (double)vals[k][i]);
    printf(" %.9g %.9g %.9g %.9g\n%sEND\n", (double)v->yfov * 180.0 / LG_PI, (double)v->znear,
           (double)v->zfar, (double)v->aspect, t);
    free(t);
}

static int print_cases(void)
{
    const float lo[3] = { -1, 0, -1 }, hi[3] = { 1, 2, 1 };
    lg_camera c = { 0 };
    c.position[0] = 0.3f, c.position[1] = 1.1f, c.position[2] = 3.7f;
    c.target[0] = 0.05f, c.target[1] = 0.9f, c.target[2] = 0.0f;
    c.up[1] = 1.0f;
    c.yfov = 0.7f;
    lg_vcam v;
    lg_vcam_init(&v, &c, lo, hi);
    print_case("look_at", &v);

    lg_vcam o = v;
    lg_vcam_orbit(&o, 133.7, 91.3, 240); /* to the side and well above */
    lg_vcam_zoom(&o, 1.5);
    print_case("orbit_zoom", &o);

    lg_vcam top = v;
    for (int i = 0; i < 20; i++)
        lg_vcam_orbit(&top, 3.3, 100, 240); /* at the pitch limit: up nearly horizontal */
    print_case("orbit_top", &top);

    lg_vcam p = v;
    lg_vcam_pan(&p, -31, 17, 240);
    print_case("pan", &p);

    lg_vcam fly = v;
    fly.znear = 0.05f, fly.zfar = 30.0f, fly.aspect = 1.5f;
    lg_vcam_look(&fly, 20, -12, 240);
    const float rul[3] = { 0.3f, -0.2f, 0.8f };
    lg_vcam_move(&fly, rul, 0.25, 1.0);
    print_case("fly", &fly);

    lg_vcam near = v;
    for (int i = 0; i < 200; i++)
        lg_vcam_zoom(&near, 100);
    /* at the floor, 1e-4 scale from a target a few units off the origin */
    print_case("zoom_floor", &near);
    return 0;
}

/* The clip planes follow a moved camera: they hold the box from where it stands. */
static void test_fit_clip(void)
{
    const float lo[3] = { -1, -1, -1 }, hi[3] = { 1, 1, 1 };
    lg_vcam v;
    memset(&v, 0, sizeof v);
    v.yfov = 1.0f;
    v.up[1] = 1;
    /* outside, looking at the centre from +Z at 5: near 0.99 x 4, far 1.01 x 6 */
    v.position[2] = 5;
    lg_vcam_fit_clip(&v, lo, hi);
    CHECKF(fabs(v.znear - 3.96) < 1e-5 && fabs(v.zfar - 6.06) < 1e-5, "near %g far %g",
           (double)v.znear, (double)v.zfar);
    /* inside: near is far / 1000 */
    v.position[2] = 0.5f;
    lg_vcam_fit_clip(&v, lo, hi);
    CHECKF(fabs(v.zfar - 1.01 * 1.5) < 1e-5 && fabs(v.znear - v.zfar * 1e-3) < 1e-7,
           "inside: near %g far %g", (double)v.znear, (double)v.zfar);
    /* the box behind the camera: still a valid pair */
    v.position[2] = -5;
    v.target[2] = -10;
    lg_vcam_fit_clip(&v, lo, hi);
    CHECK(v.znear > 0 && v.zfar > v.znear && isfinite(v.zfar));
    /* no bounds: the target's distance / 100 and x 100 */
    lg_vcam_fit_clip(&v, NULL, NULL);
    CHECK(fabs(v.znear - 0.05) < 1e-6 && fabs(v.zfar - 500) < 1e-3);
}

int main(int argc, char **argv)
{
    if (argc == 2 && strcmp(argv[1], "cases") == 0)
        return print_cases();
    test_init();
    test_orbit();
    test_pan();
    test_zoom();
    test_fly();
    test_node_text();
    test_fit_clip();
    return check_report("viewer_camera");
}
