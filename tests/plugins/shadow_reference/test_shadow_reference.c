/*
 * shadow_reference through the host, on the shadow-map tests' scene made in memory
 * (tests/plugins/shadowmap/shadowprobe.c's test_shadow_scene: a floor of side 8 at y = 0 and a
 * box, one camera), its visibility held against closed forms computed here from the camera
 * alone (not from the node's outputs):
 *
 *   box_dir     a directional light (slanted) over the box: every floor pixel whose
 *               footprint is not cut by the shadow's outline has V = 1 exactly when the ray
 *               from its centre's floor point towards the light misses the box (slab test),
 *               else 0; the node's `position` output is that floor point
 *   box_point   the same with a point light (the finite segment to the light)
 *   penumbra    a directional area light (angular diameter s) straight above a thin plate:
 *               across the plate's edge V(x) = A((x_e - x) / (h tan(s / 2))) with A(c) the
 *               share of a unit disk beyond the chord at c, (acos c - c sqrt(1 - c^2)) / pi;
 *               the penumbra's width is 2 h tan(s / 2)
 *   identity    out = lit bit for bit where V = 1, out = unlit where V = 0; a light of
 *               intensity 0 gives out = unlit everywhere; a scene without a light gates
 *               the node (out = lit)
 *   errors      a light index past the scene's, a negative light size, lit without depth,
 *               unlit of another size: exit 2 or 1 with the reason, no file
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#define W 128
#define H 96

static void setup_case(lg_test *t)
{
    lg_test_require_backend(t, "gl");
    lg_test_use_plugins(t, SR_PROBE_DIR);
}

typedef struct cam {
    double eye[3], right[3], up[3], fwd[3], tan_half;
} cam;

static void normalize(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int c = 0; c < 3; c++)
        v[c] /= l;
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* test_shadow_scene's camera: look-at with up +Y, yfov degrees, aspect W / H */
static cam make_cam(const double eye[3], const double target[3], double yfov_deg)
{
    cam c;
    memcpy(c.eye, eye, sizeof c.eye);
    for (int k = 0; k < 3; k++)
        c.fwd[k] = target[k] - eye[k];
    normalize(c.fwd);
    const double up0[3] = { 0, 1, 0 };
    cross(c.fwd, up0, c.right);
    normalize(c.right);
    cross(c.right, c.fwd, c.up);
    c.tan_half = tan(0.5 * yfov_deg * LG_PI / 180.0);
    return c;
}

/* The floor point (y = 0) seen at image point (px, py) (continuous, row 0 at the top); false
 * when the ray does not go down. */
static bool floor_point(const cam *c, double px, double py, double p[3])
{
    double a = (2.0 * px / W - 1.0) * c->tan_half * ((double)W / H);
    double b = -(2.0 * py / H - 1.0) * c->tan_half;
    double d[3];
    for (int k = 0; k < 3; k++)
        d[k] = c->fwd[k] + a * c->right[k] + b * c->up[k];
    if (!(d[1] < 0.0))
        return false;
    double t = -c->eye[1] / d[1];
    for (int k = 0; k < 3; k++)
        p[k] = c->eye[k] + t * d[k];
    return true;
}

/* Whether the segment o + t d, t in (0, tmax), meets the box [lo, hi] (slab test). */
static bool hits_box(const double o[3], const double d[3], double tmax, const double lo[3],
                     const double hi[3])
{
    double t0 = 1e-9, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        if (fabs(d[k]) < 1e-300) {
            if (o[k] < lo[k] || o[k] > hi[k])
                return false;
            continue;
        }
        double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        if (a > b) {
            double s = a;
            a = b;
            b = s;
        }
        t0 = a > t0 ? a : t0;
        t1 = b < t1 ? b : t1;
        if (t0 > t1)
            return false;
    }
    return true;
}

/* Closed-form V of floor point p: 1 lit, 0 shadowed. `dir_light`: L is the direction towards
 * the light (unit); else `q` the point light. */
static int closed_v(const double p[3], bool dir_light, const double L[3], const double q[3],
                    const double lo[3], const double hi[3])
{
    double d[3], tmax = INFINITY;
    if (dir_light) {
        memcpy(d, L, sizeof d);
    } else {
        for (int k = 0; k < 3; k++)
            d[k] = q[k] - p[k];
        tmax = 1.0;
    }
    return hits_box(p, d, tmax, lo, hi) ? 0 : 1;
}

/* Renders graph text `g`; reads `file` into *img when given. Returns the status. */
static int render(lg_test *t, const char *g, const char *file, lg_image *img, char **text)
{
    static const char *const args[] = { "--size", "128x96", NULL };
    lg_test_write_text(t, "g.lgraph", g);
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0 || !file)
        return rc;
    return lg_test_read(t, file, img, NULL) ? 0 : -2;
}

/* The graph: the scene (`scene` parameters), the light (a `light` node's parameters), phong
 * with and without it, the reference (`params`); outputs o.exr (out), v.exr (visibility),
 * p.exr (position), l.exr (lit), u.exr (unlit). */
static const char *graph(char *g, size_t n, const char *scene, const char *light,
                         const char *params)
{
    snprintf(g, n,
             "lightgraph 1\n"
             "s = test_shadow_scene { %s }\n"
             "lamp = light { scene = s, %s }\n"
             "lit = phong { scene = lamp, ambient = [0.1, 0.1, 0.1] }\n"
             "unlit = phong { scene = s, ambient = [0.1, 0.1, 0.1] }\n"
             "ref = shadow_reference { scene = lamp, lit = lit, unlit = unlit%s }\n"
             "output ref \"o.exr\" float\n"
             "output ref.visibility \"v.exr\" float\n"
             "output ref.position \"p.exr\" float\n"
             "output lit \"l.exr\" float\n"
             "output unlit \"u.exr\" float\n",
             scene, light, params);
    return g;
}

static const double EYE[3] = { 0, 7, 5 }, TARGET[3] = { 0, 0, 0 };
#define SCENE "camera_position = [0, 7, 5], camera_target = [0, 0, 0], yfov = 60"
static const double BOX_LO[3] = { -0.5, 1.0, -0.5 }, BOX_HI[3] = { 0.5, 2.0, 0.5 };

/* Every floor pixel (its centre ray reaches the floor before the box) whose centre and four
 * corners agree in the closed form is checked against V; returns the pixels checked. */
static int check_hard(lg_test *t, bool dir_light, const double L[3], const double q[3],
                      const char *what)
{
    lg_image v = { 0 }, p = { 0 };
    if (!lg_test_read(t, "v.exr", &v, NULL) || !lg_test_read(t, "p.exr", &p, NULL))
        return 0;
    cam c = make_cam(EYE, TARGET, 60.0);
    int checked = 0, wrong = 0, shadowed = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double fp[3];
            if (!floor_point(&c, x + 0.5, y + 0.5, fp) || fabs(fp[0]) > 3.9 || fabs(fp[2]) > 3.9)
                continue;
            double dv[3];
            for (int k = 0; k < 3; k++)
                dv[k] = fp[k] - EYE[k];
            if (hits_box(EYE, dv, 1.0, BOX_LO, BOX_HI))
                continue; /* the box hides the floor here */
            int want = closed_v(fp, dir_light, L, q, BOX_LO, BOX_HI);
            bool edge = false;
            for (int k = 0; k < 4 && !edge; k++) {
                double cp[3];
                if (!floor_point(&c, x + (k & 1), y + (k >> 1), cp))
                    edge = true;
                else
                    edge = closed_v(cp, dir_light, L, q, BOX_LO, BOX_HI) != want;
            }
            if (edge)
                continue;
            const float *vp = v.pixels + ((size_t)y * W + x) * 4;
            const float *pp = p.pixels + ((size_t)y * W + x) * 4;
            checked++;
            shadowed += want == 0;
            if (vp[0] != (float)want) {
                wrong++;
                if (wrong <= 5)
                    printf("%s: pixel (%d, %d) floor (%.3f, %.3f): V %g, closed form %d\n", what, x,
                           y, fp[0], fp[2], (double)vp[0], want);
            }
            double dp = fabs(pp[0] - fp[0]) + fabs(pp[1] - fp[1]) + fabs(pp[2] - fp[2]);
            LG_TEST_CHECK(t, pp[3] == 1.0f && dp < 1e-4,
                          "%s: pixel (%d, %d): position (%g, %g, %g, %g), the floor point "
                          "(%g, %g, %g)",
                          what, x, y, (double)pp[0], (double)pp[1], (double)pp[2], (double)pp[3],
                          fp[0], fp[1], fp[2]);
        }
    LG_TEST_CHECK(t, wrong == 0, "%s: %d of %d floor pixels wrong", what, wrong, checked);
    LG_TEST_CHECK(t, checked > 1000 && shadowed > 50,
                  "%s: only %d pixels checked, %d shadowed (the scene is not what the test "
                  "expects)",
                  what, checked, shadowed);
    printf("%s: %d floor pixels checked, %d in the shadow, %d wrong\n", what, checked, shadowed,
           wrong);
    lg_image_free(&v);
    lg_image_free(&p);
    return checked;
}

static void case_box_dir(lg_test *t)
{
    char g[2048];
    /* the light travels along (0.8, -1, 0.6), its shadow falls towards the camera: towards
     * the light is (-0.8, 1, -0.6) */
    double L[3] = { -0.8, 1.0, -0.6 };
    normalize(L);
    int rc = render(t, graph(g, sizeof g, SCENE, "direction = [0.8, -1, 0.6]", ""), NULL, NULL,
                    NULL);
    LG_TEST_CHECK(t, rc == 0, "render: %d", rc);
    if (rc == 0)
        check_hard(t, true, L, NULL, "directional");
}

static void case_box_point(lg_test *t)
{
    char g[2048];
    static const double q[3] = { 0.6, 3.5, -0.4 };
    int rc = render(t,
                    graph(g, sizeof g, SCENE,
                          "type = point, position = [0.6, 3.5, -0.4], intensity = 10", ""),
                    NULL, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "render: %d", rc);
    if (rc == 0)
        check_hard(t, false, NULL, q, "point");
}

/* the share of the unit disk beyond the chord at c (c in [-1, 1]) */
static double disk_beyond(double c)
{
    if (c <= -1.0)
        return 1.0;
    if (c >= 1.0)
        return 0.0;
    return (acos(c) - c * sqrt(1.0 - c * c)) / LG_PI;
}

static void case_penumbra(lg_test *t)
{
    /* a plate 1 x 0.002 x 1 at height 1.5 (covering x < 0.5 near z = 0), the light straight
     * down with angular diameter 0.2 rad: the penumbra spans 0.5 +- 1.5 tan(0.1) */
    const double s = 0.2, h = 1.5, xe = 0.5, tau = tan(0.5 * s);
    char g[2048];
    const double eye[3] = { 2.5, 4, 0.01 }, target[3] = { 0.5, 0, 0 };
    int rc = render(t,
                    graph(g, sizeof g,
                          "box_center = [0, 1.5, 0], box_size = [1, 0.002, 1], "
                          "camera_position = [2.5, 4, 0.01], camera_target = [0.5, 0, 0], "
                          "yfov = 10",
                          "direction = [0, -1, 0]", ", light_size = 0.2, light_samples = 1024"),
                    NULL, NULL, NULL);
    LG_TEST_CHECK(t, rc == 0, "render: %d", rc);
    lg_image v = { 0 };
    if (rc != 0 || !lg_test_read(t, "v.exr", &v, NULL))
        return;
    cam c = make_cam(eye, target, 10.0);
    int checked = 0;
    double worst = 0.0, lo_x = INFINITY, hi_x = -INFINITY;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double fp[3];
            if (!floor_point(&c, x + 0.5, y + 0.5, fp) || fabs(fp[2]) > 0.2)
                continue;
            double want = disk_beyond((xe - fp[0]) / (h * tau));
            double got = v.pixels[((size_t)y * W + x) * 4];
            /* the plate's 2 mm move the edge by 1 mm: 0.007 of the penumbra's half-width,
             * at most 0.005 in V; the pattern's 1024 rays 0.003 more */
            double err = fabs(got - want);
            worst = err > worst ? err : worst;
            LG_TEST_CHECK(t, err < 0.012, "pixel (%d, %d) x = %.4f: V %.4f, closed form %.4f", x, y,
                          fp[0], got, want);
            checked++;
            if (got > 0.0 && got < 1.0) {
                lo_x = fp[0] < lo_x ? fp[0] : lo_x;
                hi_x = fp[0] > hi_x ? fp[0] : hi_x;
            }
        }
    /* the penumbra's width: where 0 < V < 1, against 2 h tan(s / 2), within the floor's
     * pixel spacing here (about 0.02) on each side */
    double width = hi_x - lo_x, want_w = 2.0 * h * tau;
    LG_TEST_CHECK(t, checked > 100, "only %d pixels near z = 0", checked);
    LG_TEST_CHECK(t, fabs(width - want_w) < 0.045, "penumbra %.4f .. %.4f wide %.4f, want %.4f",
                  lo_x, hi_x, width, want_w);
    printf("penumbra: %d pixels, worst |V - closed form| %.4f; width %.4f (closed form %.4f)\n",
           checked, worst, width, want_w);
    lg_image_free(&v);
}

static void case_identity(lg_test *t)
{
    char g[2048];
    int rc = render(t, graph(g, sizeof g, SCENE, "direction = [0.8, -1, 0.6]", ""), NULL, NULL,
                    NULL);
    LG_TEST_CHECK(t, rc == 0, "render: %d", rc);
    lg_image o = { 0 }, v = { 0 }, l = { 0 }, u = { 0 };
    if (rc == 0 && lg_test_read(t, "o.exr", &o, NULL) && lg_test_read(t, "v.exr", &v, NULL) &&
        lg_test_read(t, "l.exr", &l, NULL) && lg_test_read(t, "u.exr", &u, NULL)) {
        int lit = 0, dark = 0;
        for (size_t i = 0; i < (size_t)W * H; i++) {
            float V = v.pixels[i * 4];
            LG_TEST_CHECK(t, V == 0.0f || V == 1.0f, "pixel %zu: a hard light's V is %g", i,
                          (double)V);
            const float *want = V == 1.0f ? l.pixels + i * 4 : u.pixels + i * 4;
            for (int c = 0; c < 3; c++)
                LG_TEST_CHECK(t, o.pixels[i * 4 + c] == want[c],
                              "pixel %zu channel %d: out %g, %s %g", i, c,
                              (double)o.pixels[i * 4 + c], V == 1.0f ? "lit" : "unlit",
                              (double)want[c]);
            lit += V == 1.0f;
            dark += V == 0.0f;
        }
        LG_TEST_CHECK(t, dark > 50 && lit > 1000, "%d lit, %d shadowed pixels", lit, dark);
    }
    lg_image_free(&o);
    lg_image_free(&v);
    lg_image_free(&l);
    lg_image_free(&u);
    /* no light: out = unlit = lit */
    rc = render(t, graph(g, sizeof g, SCENE, "direction = [0.8, -1, 0.6], intensity = 0", ""),
                "o.exr", &o, NULL);
    LG_TEST_CHECK(t, rc == 0, "render: %d", rc);
    if (rc == 0 && lg_test_read(t, "u.exr", &u, NULL))
        LG_TEST_CHECK(t, memcmp(o.pixels, u.pixels, (size_t)W * H * 16) == 0,
                      "intensity 0: out differs from unlit");
    lg_image_free(&o);
    lg_image_free(&u);
    /* a scene without any light gates the node: out is lit as it is */
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_shadow_scene { " SCENE " }\n"
             "lit = phong { scene = s }\n"
             "ref = shadow_reference { scene = s, lit = lit, unlit = lit }\n"
             "output ref \"o.exr\" float\n"
             "output lit \"l.exr\" float\n");
    rc = render(t, g, "o.exr", &o, NULL);
    LG_TEST_CHECK(t, rc == 0, "render without a light: %d", rc);
    if (rc == 0 && lg_test_read(t, "l.exr", &l, NULL))
        LG_TEST_CHECK(t, memcmp(o.pixels, l.pixels, (size_t)W * H * 16) == 0,
                      "gated: out differs from lit");
    lg_image_free(&o);
    lg_image_free(&l);
}

static void expect_error(lg_test *t, const char *g, const char *want)
{
    char *msg = NULL;
    remove(lg_test_path(t, "o.exr"));
    int rc = render(t, g, NULL, NULL, &msg);
    LG_TEST_CHECK(t, rc == 1 || rc == 2, "status %d for %s", rc, want);
    LG_TEST_CHECK(t, msg && strstr(msg, want), "the message does not say '%s': %s", want,
                  msg ? msg : "");
    FILE *f = fopen(lg_test_path(t, "o.exr"), "rb");
    LG_TEST_CHECK(t, f == NULL, "o.exr written despite the error (%s)", want);
    if (f)
        fclose(f);
    free(msg);
}

static void case_errors(lg_test *t)
{
    char g[2048];
    expect_error(t, graph(g, sizeof g, SCENE, "direction = [0, -1, 0]", ", light = 3"),
                 "light = 3");
    expect_error(t, graph(g, sizeof g, SCENE, "direction = [0, -1, 0]", ", light_size = -1"),
                 "light_size");
    /* unlit of another size */
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_shadow_scene { " SCENE " }\n"
             "lamp = light { scene = s, direction = [0, -1, 0] }\n"
             "lit = phong { scene = lamp }\n"
             "unlit = phong { scene = s, width = 32, height = 24 }\n"
             "ref = shadow_reference { scene = lamp, lit = lit, unlit = unlit }\n"
             "output ref \"o.exr\" float\n");
    expect_error(t, g, "32x24");
    /* lit without depth (a file) */
    lg_image img = { 0 };
    LG_TEST_CHECK(t, lg_image_alloc(&img, W, H) == 0, "alloc");
    lg_test_write_exr(t, "flat.exr", &img);
    lg_image_free(&img);
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_shadow_scene { " SCENE " }\n"
             "lamp = light { scene = s, direction = [0, -1, 0] }\n"
             "flat = image { file = \"flat.exr\" }\n"
             "ref = shadow_reference { scene = lamp, lit = flat, unlit = flat }\n"
             "output ref \"o.exr\" float\n");
    expect_error(t, g, "depth");
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "box_dir", case_box_dir },   { "box_point", case_box_point },
        { "penumbra", case_penumbra }, { "identity", case_identity },
        { "errors", case_errors },
    };
    lg_test_main_opts o = { .setup = setup_case };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
