/*
 * The preview node through the host, on scenes built in memory by the test plugin
 * testmeshscene (camera 0 at (0, 0, 5) looking at the origin, +Y up, yfov 60 degrees,
 * znear 1, zfar 20 unless a case says otherwise). `test_preview CASE`:
 *
 *   fill       a quad filling the view: its base colour in every pixel, alpha 1
 *   normals    the cube seen along -Z shows (0.5, 0.5, 1) at the centre; rotated 45
 *              degrees about +Y, its two visible faces show their world normals, the
 *              left one on the left (no mirror image); then stretched x2 along X, they
 *              show the inverse transpose's normals, not the model matrix's
 *   depth      two quads at distances 5 and 8: the depth plane is GL's window depth
 *              f (z - n) / (z (f - n)), 1 where nothing is, within [0, 1], larger for the
 *              farther quad; the depth mode's grey is (z - n) / (f - n)
 *   instancing two instances of one quad mesh both appear where the projection puts them,
 *              with the background between them
 *   upright    a quad in the upper right of the view lands in the top rows and right
 *              columns of the output file
 *   cull       cull = none draws a quad facing away; cull = material hides it unless its
 *              material is double-sided, keeps a quad facing the camera, and keeps a quad
 *              seen through a mirroring instance (negative determinant)
 *   size       width/height parameters, and 0 = the render size (--size)
 *   aspect     camera aspect 0: a square stays square on a 2:1 output; a camera aspect of
 *              1 on a 1:2 output keeps the camera's horizontal field of view
 *   far        zfar 0: the range comes from the bounds; a quad 50 away is drawn and its
 *              grey is (50 - n) / (zfar - n) with zfar just past it
 *   camera     camera = 1 (looking away) shows only background; camera = 2 is an error
 *              naming it
 *   empty      a scene without instances: background and depth 1 everywhere
 *   errors     an index out of range, an instance of a missing mesh, a scene without a
 *              camera: exit status 1 and a message naming the object
 *
 * Through the gltf node (plugin scene_gltf), with a file given as the second argument:
 *
 *   example FILE   examples/preview.lgraph on the bunny box (FILE): a Cornell box with a
 *                  bunny: the red wall's pixels on the left, the green wall's on the
 *                  right, about as many of each; the bunny's grey (base colour 0.8) in the
 *                  lower middle; the background around the box's opening
 *   draco FILE     the same with the Draco variant (FILE): under 1% of the pixels differ
 *                  from the plain file's preview (quantisation moves edges by a pixel)
 *   sphere FILE    a sphere from tools/gen_scene.py (FILE: radius 1, colour 0.9 0.3 0.1,
 *                  camera at (0, 3, 6) looking at the origin, yfov 40 degrees): its colour
 *                  in every covered pixel, its area pi r^2 in pixels within 2% for the
 *                  silhouette's projected radius, and the normal at the centre pointing
 *                  at the camera
 *
 * Every render also passes the host's GL state check (debug builds check after each node
 * that the bindings were restored; a violation fails the render).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#ifndef PV_TEST_PLUGIN_DIR
#define PV_TEST_PLUGIN_DIR ""
#endif

static const double N = 1.0, F = 20.0;            /* znear, zfar of the test cameras */
static const double T30 = 0.57735026918962576;    /* tan(30 degrees): half of yfov 60 */
static const float BG[3] = { 1.0f, 0.0f, 1.0f };  /* a background no test colour equals */
static const float COL[3] = { 0.2f, 0.5f, 0.8f }; /* testmeshscene's default colour */

/* Writes g.lgraph with `scene` params and `view` params, outputs the colour image to
 * out.exr and, with depth, the depth plane to depth.exr; renders; reads them back. */
static int run(lg_test *t, const char *scene_params, const char *view_params, bool depth,
               const char *size, lg_image *out, lg_image *dplane, char **text)
{
    char g[4096];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_mesh_scene { %s }\n"
             "view = preview { scene = s, background = [1, 0, 1]%s%s }\n"
             "output view \"out.exr\"\n"
             "%s",
             scene_params, *view_params ? ", " : "", view_params,
             depth ? "d = test_depth_plane { image = view }\noutput d \"depth.exr\"\n" : "");
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", size ? size : "64x48", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0)
        return rc;
    if (out && !lg_test_read(t, "out.exr", out, NULL))
        return -2;
    if (depth && dplane && !lg_test_read(t, "depth.exr", dplane, NULL))
        return -2;
    return 0;
}

static const float *px(const lg_image *img, uint32_t x, uint32_t y)
{
    return img->pixels + ((size_t)y * img->width + x) * 4;
}

static bool near3(const float *p, const float *c, double tol)
{
    return fabs(p[0] - c[0]) <= tol && fabs(p[1] - c[1]) <= tol && fabs(p[2] - c[2]) <= tol;
}

static bool is_bg(const float *p)
{
    return near3(p, BG, 1e-6);
}

/* The pixel a world point lands in with camera 0 (at (0,0,5), looking down -Z) on a
 * w x h output; yfov's tangent t, aspect a. Row 0 is the top. */
static void project(double x, double y, double z, double t, double a, uint32_t w, uint32_t h,
                    uint32_t *col, uint32_t *row)
{
    double d = 5.0 - z;
    double nx = x / (d * t * a), ny = y / (d * t);
    *col = (uint32_t)floor((nx * 0.5 + 0.5) * w);
    *row = (uint32_t)floor((0.5 - ny * 0.5) * h);
}

static double window_depth(double z)
{
    return F * (z - N) / (z * (F - N));
}

#define RUN_OK(t, sp, vp, depth, size, out, dp)                                                    \
    do {                                                                                           \
        int rc_ = run(t, sp, vp, depth, size, out, dp, NULL);                                      \
        LG_TEST_CHECK(t, rc_ == 0, "render of {%s} {%s} failed (%d)", sp, vp, rc_);                \
        if (rc_)                                                                                   \
            return;                                                                                \
    } while (0)

static void case_fill(lg_test *t)
{
    lg_image img = { 0 };
    RUN_OK(t, "layout = quad_fill", "", false, NULL, &img, NULL);
    LG_TEST_CHECK(t, img.width == 64 && img.height == 48, "size %ux%u", img.width, img.height);
    uint32_t bad = 0;
    for (uint32_t y = 0; y < img.height; y++)
        for (uint32_t x = 0; x < img.width; x++) {
            const float *p = px(&img, x, y);
            if (!near3(p, COL, 1e-6) || p[3] != 1.0f) {
                if (!bad)
                    fprintf(stderr, "pixel (%u, %u) = %g %g %g %g\n", x, y, p[0], p[1], p[2], p[3]);
                bad++;
            }
        }
    LG_TEST_CHECK(t, bad == 0, "%u pixels differ from the base colour", bad);
    lg_image_free(&img);
}

static void case_normals(lg_test *t)
{
    lg_image img = { 0 };
    RUN_OK(t, "layout = cube", "mode = normals", false, "64x64", &img, NULL);
    const float front[3] = { 0.5f, 0.5f, 1.0f };
    const float *c = px(&img, 32, 32);
    LG_TEST_CHECK(t, near3(c, front, 1e-5), "cube centre %g %g %g, expected 0.5 0.5 1", c[0], c[1],
                  c[2]);
    LG_TEST_CHECK(t, is_bg(px(&img, 2, 2)) && is_bg(px(&img, 61, 61)),
                  "corners are not background");
    lg_image_free(&img);

    /* rotated 45 degrees about +Y: the object's -X face now faces (-s, 0, s) and its +Z
     * face (s, 0, s), s = sqrt(1/2); the first is on the left */
    RUN_OK(t, "layout = cube_rot45", "mode = normals", false, "64x64", &img, NULL);
    float s = (float)sqrt(0.5);
    const float left[3] = { -s * 0.5f + 0.5f, 0.5f, s * 0.5f + 0.5f };
    const float right[3] = { s * 0.5f + 0.5f, 0.5f, s * 0.5f + 0.5f };
    const float *l = px(&img, 26, 32), *r = px(&img, 38, 32);
    LG_TEST_CHECK(t, near3(l, left, 1e-5), "left face %g %g %g, expected %g %g %g", l[0], l[1],
                  l[2], left[0], left[1], left[2]);
    LG_TEST_CHECK(t, near3(r, right, 1e-5), "right face %g %g %g, expected %g %g %g", r[0], r[1],
                  r[2], right[0], right[1], right[2]);
    lg_image_free(&img);

    /* S R with S = (2, 1, 1): the normal matrix S^-1 R turns (-s, 0, s) into
     * (-s / 2, 0, s), normalised (-1, 0, 2) / sqrt(5) */
    RUN_OK(t, "layout = cube_stretched", "mode = normals", false, "64x64", &img, NULL);
    float a = (float)(1 / sqrt(5.0)), b = (float)(2 / sqrt(5.0));
    const float sl[3] = { -a * 0.5f + 0.5f, 0.5f, b * 0.5f + 0.5f };
    const float sr[3] = { a * 0.5f + 0.5f, 0.5f, b * 0.5f + 0.5f };
    l = px(&img, 24, 32);
    r = px(&img, 40, 32);
    LG_TEST_CHECK(t, near3(l, sl, 1e-5), "stretched left face %g %g %g, expected %g %g %g", l[0],
                  l[1], l[2], sl[0], sl[1], sl[2]);
    LG_TEST_CHECK(t, near3(r, sr, 1e-5), "stretched right face %g %g %g, expected %g %g %g", r[0],
                  r[1], r[2], sr[0], sr[1], sr[2]);
    lg_image_free(&img);
}

static void case_depth(lg_test *t)
{
    lg_image img = { 0 }, dp = { 0 };
    RUN_OK(t, "layout = two_depths", "", true, "64x48", &img, &dp);
    double a = 64.0 / 48.0;
    uint32_t lx, ly, rx, ry;
    project(-1.1, 0, 0, T30, a, 64, 48, &lx, &ly);
    project(1.1, 0, -3, T30, a, 64, 48, &rx, &ry);
    double dl = px(&dp, lx, ly)[0], dr = px(&dp, rx, ry)[0];
    LG_TEST_CHECK(t, fabs(dl - window_depth(5)) < 1e-5, "near quad depth %.7g, expected %.7g", dl,
                  window_depth(5));
    LG_TEST_CHECK(t, fabs(dr - window_depth(8)) < 1e-5, "far quad depth %.7g, expected %.7g", dr,
                  window_depth(8));
    LG_TEST_CHECK(t, dr > dl, "depth does not increase with distance (%g, %g)", dl, dr);
    LG_TEST_CHECK(t, px(&dp, 32, 2)[0] == 1.0f, "background depth %g, expected 1",
                  px(&dp, 32, 2)[0]);
    uint32_t outside = 0;
    for (size_t i = 0; i < (size_t)dp.width * dp.height; i++)
        if (!(dp.pixels[i * 4] >= 0.0f && dp.pixels[i * 4] <= 1.0f))
            outside++;
    LG_TEST_CHECK(t, outside == 0, "%u depth values outside [0, 1]", outside);
    lg_image_free(&img);
    lg_image_free(&dp);

    RUN_OK(t, "layout = two_depths", "mode = depth", false, "64x48", &img, NULL);
    double gl = px(&img, lx, ly)[0], gr = px(&img, rx, ry)[0];
    LG_TEST_CHECK(t, fabs(gl - (5 - N) / (F - N)) < 1e-5, "near grey %.7g, expected %.7g", gl,
                  (5 - N) / (F - N));
    LG_TEST_CHECK(t, fabs(gr - (8 - N) / (F - N)) < 1e-5, "far grey %.7g, expected %.7g", gr,
                  (8 - N) / (F - N));
    LG_TEST_CHECK(t, is_bg(px(&img, 32, 2)), "depth mode: no background above the quads");
    lg_image_free(&img);
}

static void case_instancing(lg_test *t)
{
    lg_image img = { 0 };
    RUN_OK(t, "layout = instanced", "", false, "96x48", &img, NULL);
    double a = 2.0;
    uint32_t x0, y0, x1, y1, xm, ym;
    project(-1.5, 0, 0, T30, a, 96, 48, &x0, &y0);
    project(1.5, 0.5, 0, T30, a, 96, 48, &x1, &y1);
    project(0, 0.25, 0, T30, a, 96, 48, &xm, &ym);
    LG_TEST_CHECK(t, near3(px(&img, x0, y0), COL, 1e-6), "instance 0 missing at (%u, %u)", x0, y0);
    LG_TEST_CHECK(t, near3(px(&img, x1, y1), COL, 1e-6), "instance 1 missing at (%u, %u)", x1, y1);
    LG_TEST_CHECK(t, is_bg(px(&img, xm, ym)), "no background between the instances at (%u, %u)", xm,
                  ym);
    /* instance 1 is 0.5 higher: its centre row is above instance 0's */
    LG_TEST_CHECK(t, y1 < y0, "projection: rows %u %u", y0, y1);
    LG_TEST_CHECK(t, is_bg(px(&img, x1, y0 + 4)), "instance 1 drawn at instance 0's height");
    uint32_t covered = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        covered += !is_bg(img.pixels + i * 4);
    /* each unit quad at distance 5: (1 / (2 * 5 * t30)) of the height squared, in pixels */
    double side = 48.0 / (2 * 5 * T30);
    LG_TEST_CHECK(t, fabs(covered - 2 * side * side) < 4 * side + 4,
                  "%u pixels covered, two instances make about %.0f", covered, 2 * side * side);
    lg_image_free(&img);
}

static void case_upright(lg_test *t)
{
    lg_image img = { 0 };
    RUN_OK(t, "layout = upper_right", "", false, "64x64", &img, NULL);
    uint32_t x, y;
    project(1, 1, 0, T30, 1.0, 64, 64, &x, &y);
    LG_TEST_CHECK(t, y < 32 && x > 32, "projection puts the quad at (%u, %u)", x, y);
    LG_TEST_CHECK(t, near3(px(&img, x, y), COL, 1e-6),
                  "the quad is not in the upper right (%u, %u)", x, y);
    LG_TEST_CHECK(t, is_bg(px(&img, x, 63 - y)), "something in the lower right (mirrored in Y?)");
    LG_TEST_CHECK(t, is_bg(px(&img, 63 - x, y)), "something in the upper left (mirrored in X?)");
    lg_image_free(&img);
}

static void case_cull(lg_test *t)
{
    lg_image img = { 0 };
    RUN_OK(t, "layout = back_quad", "cull = none", false, "32x32", &img, NULL);
    LG_TEST_CHECK(t, near3(px(&img, 16, 16), COL, 1e-6), "cull = none hides a back face");
    lg_image_free(&img);
    RUN_OK(t, "layout = back_quad", "cull = material", false, "32x32", &img, NULL);
    LG_TEST_CHECK(t, is_bg(px(&img, 16, 16)), "cull = material draws a single-sided back face");
    lg_image_free(&img);
    RUN_OK(t, "layout = back_quad, double_sided = true", "cull = material", false, "32x32", &img,
           NULL);
    LG_TEST_CHECK(t, near3(px(&img, 16, 16), COL, 1e-6),
                  "cull = material hides a double-sided face");
    lg_image_free(&img);
    RUN_OK(t, "layout = upper_right", "cull = material", false, "64x64", &img, NULL);
    uint32_t x, y;
    project(1, 1, 0, T30, 1.0, 64, 64, &x, &y);
    LG_TEST_CHECK(t, near3(px(&img, x, y), COL, 1e-6), "cull = material hides a front face");
    lg_image_free(&img);
    RUN_OK(t, "layout = mirrored", "cull = material", false, "32x32", &img, NULL);
    LG_TEST_CHECK(t, near3(px(&img, 16, 16), COL, 1e-6),
                  "cull = material hides a front face seen through a mirroring instance");
    lg_image_free(&img);
    RUN_OK(t, "layout = mirrored", "cull = material, mode = normals", false, "32x32", &img, NULL);
    const float plus_z[3] = { 0.5f, 0.5f, 1.0f };
    LG_TEST_CHECK(t, near3(px(&img, 16, 16), plus_z, 1e-5), "mirrored quad's normal %g %g %g",
                  px(&img, 16, 16)[0], px(&img, 16, 16)[1], px(&img, 16, 16)[2]);
    lg_image_free(&img);
}

static void case_size(lg_test *t)
{
    lg_image img = { 0 };
    RUN_OK(t, "layout = quad_fill", "width = 40, height = 30", false, "64x48", &img, NULL);
    LG_TEST_CHECK(t, img.width == 40 && img.height == 30, "width/height: %ux%u", img.width,
                  img.height);
    lg_image_free(&img);
    RUN_OK(t, "layout = quad_fill", "", false, "50x20", &img, NULL);
    LG_TEST_CHECK(t, img.width == 50 && img.height == 20, "render size: %ux%u", img.width,
                  img.height);
    lg_image_free(&img);
    RUN_OK(t, "layout = quad_fill", "width = 24", false, "50x20", &img, NULL);
    LG_TEST_CHECK(t, img.width == 24 && img.height == 20, "width only: %ux%u", img.width,
                  img.height);
    lg_image_free(&img);
}

/* The covered box's width and height in pixels. */
static void coverage_box(const lg_image *img, int *w, int *h)
{
    int x0 = (int)img->width, x1 = -1, y0 = (int)img->height, y1 = -1;
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++)
            if (!is_bg(px(img, x, y))) {
                x0 = (int)x < x0 ? (int)x : x0;
                x1 = (int)x > x1 ? (int)x : x1;
                y0 = (int)y < y0 ? (int)y : y0;
                y1 = (int)y > y1 ? (int)y : y1;
            }
    *w = x1 - x0 + 1;
    *h = y1 - y0 + 1;
}

static void case_aspect(lg_test *t)
{
    lg_image img = { 0 };
    int w, h;
    /* the 2 x 2 back quad (double-sided) at distance 5: 2 / (2 * 5 * t30) of the height */
    RUN_OK(t, "layout = back_quad", "", false, "160x80", &img, NULL);
    coverage_box(&img, &w, &h);
    double side = 80.0 * 2 / (2 * 5 * T30);
    LG_TEST_CHECK(t, abs(w - h) <= 1 && fabs(h - side) <= 1.5,
                  "aspect 0 on 2:1: %dx%d, expected %.1f "
                  "square",
                  w, h, side);
    lg_image_free(&img);
    /* camera aspect 1 on a 1:2 output: the horizontal field is the camera's, so the quad
     * takes the fraction of the width it takes in a square image */
    RUN_OK(t, "layout = back_quad, camera_aspect = 1", "", false, "80x160", &img, NULL);
    coverage_box(&img, &w, &h);
    side = 80.0 * 2 / (2 * 5 * T30);
    LG_TEST_CHECK(t, abs(w - h) <= 1 && fabs(w - side) <= 1.5,
                  "camera aspect 1 on 1:2: %dx%d, expected %.1f square", w, h, side);
    lg_image_free(&img);
}

static void case_far(lg_test *t)
{
    lg_image img = { 0 }, dp = { 0 };
    RUN_OK(t, "layout = far, zfar = 0", "mode = depth", true, "32x32", &img, &dp);
    const float *p = px(&img, 16, 16);
    double zfar = 50.0 * 1.01;
    LG_TEST_CHECK(t, !is_bg(p), "the quad 50 away is clipped");
    LG_TEST_CHECK(t, fabs(p[0] - (50 - N) / (zfar - N)) < 1e-3, "grey %g, expected %g", p[0],
                  (50 - N) / (zfar - N));
    double d = px(&dp, 16, 16)[0];
    LG_TEST_CHECK(t, d > 0.9 && d < 1.0, "window depth %g", d);
    lg_image_free(&img);
    lg_image_free(&dp);
}

static void case_camera(lg_test *t)
{
    lg_image img = { 0 };
    RUN_OK(t, "layout = quad_fill", "camera = 1", false, "32x32", &img, NULL);
    uint32_t covered = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        covered += !is_bg(img.pixels + i * 4);
    LG_TEST_CHECK(t, covered == 0, "camera 1 looks away, yet %u pixels are covered", covered);
    lg_image_free(&img);
    RUN_OK(t, "layout = quad_fill", "camera = 0", false, "32x32", &img, NULL);
    LG_TEST_CHECK(t, near3(px(&img, 16, 16), COL, 1e-6), "camera 0 does not see the quad");
    lg_image_free(&img);
    char *text = NULL;
    int rc = run(t, "layout = quad_fill", "camera = 2", false, "32x32", NULL, NULL, &text);
    LG_TEST_CHECK(t,
                  rc == 1 && text && strstr(text, "camera 2 does not exist") &&
                      strstr(text, "view"),
                  "camera 2: exit %d, message: %s", rc, text ? text : "");
    free(text);
}

static void case_empty(lg_test *t)
{
    lg_image img = { 0 }, dp = { 0 };
    RUN_OK(t, "layout = empty", "", true, "16x16", &img, &dp);
    uint32_t bad = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
        bad += !is_bg(img.pixels + i * 4) || dp.pixels[i * 4] != 1.0f;
    LG_TEST_CHECK(t, bad == 0, "%u pixels are not background at depth 1", bad);
    lg_image_free(&img);
    lg_image_free(&dp);
}

static void expect_error(lg_test *t, const char *layout, const char *const *needles)
{
    char sp[128], *text = NULL;
    snprintf(sp, sizeof sp, "layout = %s", layout);
    int rc = run(t, sp, "", false, "16x16", NULL, NULL, &text);
    LG_TEST_CHECK(t, rc == 1, "%s: exit %d, expected 1", layout, rc);
    for (int i = 0; needles[i]; i++)
        LG_TEST_CHECK(t, text && strstr(text, needles[i]), "%s: message lacks '%s': %s", layout,
                      needles[i], text ? text : "");
    free(text);
}

static void case_errors(lg_test *t)
{
    expect_error(t, "bad_index",
                 (const char *const[]){ "mesh 0 'test mesh#0'", "index 9", "out of range",
                                        "4 vertices", NULL });
    expect_error(t, "bad_instance",
                 (const char *const[]){ "instance 0 refers to mesh 3", "has 1", NULL });
    expect_error(t, "no_camera", (const char *const[]){ "no camera", NULL });
}

/* ---- through the gltf node ------------------------------------------------------------------- */

static const char *file_arg;

/* Renders `graph_text` (written to g.lgraph) with args; reads out.exr. */
static bool render_graph(lg_test *t, const char *graph_text, const char *const *args, lg_image *img)
{
    lg_test_write_text(t, "g.lgraph", graph_text);
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "render failed (exit %d)", rc);
    return rc == 0 && lg_test_read(t, "out.exr", img, NULL);
}

typedef struct pv_stats {
    double n, sx, sy;
} pv_stats;

static void stats_add(pv_stats *s, uint32_t x, uint32_t y)
{
    s->n++;
    s->sx += x;
    s->sy += y;
}

static void render_example(lg_test *t, const char *file, lg_image *img)
{
    char g[8192];
    const char *root = getenv("LG_SOURCE_ROOT");
    snprintf(g, sizeof g, "lightgraph 1\ninclude \"%s/examples/preview.lgraph\"\n",
             root ? root : ".");
    char set_file[4200];
    snprintf(set_file, sizeof set_file, "scene.file=%s", file);
    const char *args[] = { "-o",    "out.exr", "--size", "640x360",
                           "--set", set_file,  "--set",  "view.background=[1,0,1]",
                           NULL };
    render_graph(t, g, args, img);
}

static void case_example(lg_test *t)
{
    lg_image img = { 0 };
    render_example(t, file_arg, &img);
    if (!img.pixels)
        return;
    LG_TEST_CHECK(t, img.width == 640 && img.height == 360, "size %ux%u", img.width, img.height);
    pv_stats red = { 0 }, green = { 0 }, bunny = { 0 }, bg = { 0 };
    for (uint32_t y = 0; y < img.height; y++)
        for (uint32_t x = 0; x < img.width; x++) {
            const float *p = px(&img, x, y);
            if (is_bg(p))
                stats_add(&bg, x, y);
            else if (p[0] > 0.5f && p[1] < 0.1f && p[2] < 0.1f)
                stats_add(&red, x, y);
            else if (p[1] > 0.5f && p[0] < 0.1f && p[2] < 0.1f)
                stats_add(&green, x, y);
            else if (fabsf(p[0] - 0.8f) < 1e-3f && fabsf(p[1] - 0.8f) < 1e-3f &&
                     fabsf(p[2] - 0.8f) < 1e-3f)
                stats_add(&bunny, x, y);
        }
    double total = (double)img.width * img.height;
    fprintf(stderr,
            "red %.0f px at x %.0f, green %.0f px at x %.0f, bunny %.0f px at (%.0f, "
            "%.0f), background %.0f px\n",
            red.n, red.n ? red.sx / red.n : 0, green.n, green.n ? green.sx / green.n : 0, bunny.n,
            bunny.n ? bunny.sx / bunny.n : 0, bunny.n ? bunny.sy / bunny.n : 0, bg.n);
    LG_TEST_CHECK(t, red.n > 0.02 * total && green.n > 0.02 * total,
                  "walls: red %.0f, green %.0f px", red.n, green.n);
    if (red.n && green.n) {
        LG_TEST_CHECK(t, red.sx / red.n < 0.35 * img.width, "the red wall is not on the left");
        LG_TEST_CHECK(t, green.sx / green.n > 0.65 * img.width,
                      "the green wall is not on the right");
        LG_TEST_CHECK(t, fabs(red.n - green.n) < 0.15 * fmax(red.n, green.n),
                      "the walls are not symmetric: %.0f and %.0f px", red.n, green.n);
    }
    LG_TEST_CHECK(t, bunny.n > 0.01 * total, "the bunny covers %.0f px", bunny.n);
    if (bunny.n) {
        LG_TEST_CHECK(t, bunny.sy / bunny.n > 0.6 * img.height,
                      "the bunny is not on the floor "
                      "(centroid row %.0f of %u)",
                      bunny.sy / bunny.n, img.height);
        LG_TEST_CHECK(t, fabs(bunny.sx / bunny.n - img.width / 2.0) < 0.1 * img.width,
                      "the bunny is not in the middle (centroid column %.0f)", bunny.sx / bunny.n);
    }
    LG_TEST_CHECK(t, bg.n > 0.2 * total && bg.n < 0.7 * total, "background %.0f of %.0f px", bg.n,
                  total);
    lg_image_free(&img);
}

static void case_draco(lg_test *t)
{
    const char *plain = lg_test_asset("meshes/bunny_cornell_box.glb");
    if (!plain) {
        LG_TEST_FAILF(t, "assets/meshes/bunny_cornell_box.glb is missing");
        return;
    }
    lg_image a = { 0 }, b = { 0 };
    char keep[4200];
    snprintf(keep, sizeof keep, "%s", plain);
    render_example(t, keep, &a);
    render_example(t, file_arg, &b);
    if (!a.pixels || !b.pixels || a.width != b.width || a.height != b.height) {
        LG_TEST_CHECK(t, false, "no comparable images");
    } else {
        size_t differ = 0, total = (size_t)a.width * a.height;
        for (size_t i = 0; i < total; i++)
            differ += !near3(a.pixels + i * 4, b.pixels + i * 4, 1e-3);
        fprintf(stderr, "%zu of %zu pixels differ\n", differ, total);
        LG_TEST_CHECK(t, differ < total / 100, "%zu of %zu pixels differ", differ, total);
    }
    lg_image_free(&a);
    lg_image_free(&b);
}

static void case_sphere(lg_test *t)
{
    char g[8192];
    snprintf(g, sizeof g,
             "lightgraph 1\nscene = gltf { file = \"%s\" }\n"
             "view = preview { scene = scene, background = [1, 0, 1], mode = %%s }\n"
             "output view \"out.exr\"\n",
             file_arg);
    char text[8192];
    const char *args[] = { "--size", "320x240", NULL };
    lg_image img = { 0 };
    snprintf(text, sizeof text, g, "base_color");
    if (!render_graph(t, text, args, &img))
        return;
    const float col[3] = { 0.9f, 0.3f, 0.1f };
    double covered = 0;
    size_t wrong = 0;
    for (size_t i = 0; i < (size_t)img.width * img.height; i++) {
        if (is_bg(img.pixels + i * 4))
            continue;
        covered++;
        wrong += !near3(img.pixels + i * 4, col, 1e-6);
    }
    LG_TEST_CHECK(t, wrong == 0, "%zu covered pixels are not the sphere's colour", wrong);
    /* the silhouette: angular radius asin(1 / d), d = |(0, 3, 6)| */
    double d = sqrt(45.0), t20 = tan(20.0 * LG_PI / 180.0);
    double r = tan(asin(1.0 / d)) / t20 * img.height / 2.0;
    double area = LG_PI * r * r;
    fprintf(stderr, "sphere covers %.0f px, a disc of radius %.2f px is %.0f\n", covered, r, area);
    LG_TEST_CHECK(t, fabs(covered - area) < 0.02 * area, "coverage %.0f px, expected %.0f", covered,
                  area);
    lg_image_free(&img);

    snprintf(text, sizeof text, g, "normals");
    if (!render_graph(t, text, args, &img))
        return;
    const float *c = px(&img, img.width / 2, img.height / 2);
    double n[3] = { 0, 3 / d, 6 / d };
    const float want[3] = { (float)(n[0] * 0.5 + 0.5), (float)(n[1] * 0.5 + 0.5),
                            (float)(n[2] * 0.5 + 0.5) };
    LG_TEST_CHECK(t, near3(c, want, 0.01), "normal at the centre %g %g %g, expected %g %g %g", c[0],
                  c[1], c[2], want[0], want[1], want[2]);
    lg_image_free(&img);
}

/* GL is needed by every case; the scene file of the gltf cases follows the case's name */
static void setup(lg_test *t)
{
    file_arg = lg_test_arg(t, 0) ? lg_test_arg(t, 0) : "";
    lg_test_require_backend(t, "gl");
}

int main(int argc, char **argv)
{
    setenv("LIGHTGRAPH_PLUGIN_PATH", PV_TEST_PLUGIN_DIR, 1);
    static const lg_test_case cases[] = {
        { "fill", case_fill },       { "normals", case_normals },
        { "depth", case_depth },     { "instancing", case_instancing },
        { "upright", case_upright }, { "cull", case_cull },
        { "size", case_size },       { "aspect", case_aspect },
        { "far", case_far },         { "camera", case_camera },
        { "empty", case_empty },     { "errors", case_errors },
        { "example", case_example }, { "draco", case_draco },
        { "sphere", case_sphere },
    };
    lg_test_main_opts o = { .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
