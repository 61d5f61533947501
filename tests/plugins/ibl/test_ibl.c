/*
 * The ibl plugin's nodes (reflect, envmap, background) through the host, on scenes built in
 * memory by the test plugin testiblscene and probes written here, on cpu, gl and cl. Each
 * case has an oracle: a closed form (a constant probe), an independent computation (the
 * analytic sphere and camera, lg_probe_lookup), or the agreement of the three backends at
 * a stated tolerance. A missing device is a failure (llvmpipe and PoCL are dependencies).
 *
 *   constant     constant probe c: reflect and envmap give c x reflectivity on every
 *                covered pixel, background c on every other, for every layout (lat-long,
 *                angular, cube strip, 1x1), backend, format (rgba32f exactly; rgba16f and
 *                rgbe8 within their precision) and roughness 0 .. 1
 *   bright_texel one bright texel of a lat-long probe appears on a mirror sphere where the
 *                analytic sphere and camera predict it (centroid within 1 pixel)
 *   backends     a real probe (forest, lat-long and angular; a smooth cube): cpu, gl and cl
 *                agree within the tolerances stated below, for reflect (fresnel schlick),
 *                envmap and background
 *   axes         the background seen exactly along +-X, +-Y, +-Z (poles, seam, cube edges):
 *                the centre pixel is the probe along the axis, backends agree, no NaN
 *   rotation     the probe's rotation (rotate_deg) applies on every backend
 *   glossy       the split sum against lg_probe_ggx_split_sum and the Monte Carlo oracle;
 *                the chain from the host's cache on a second render; roughness 0 = the probe
 *   glossy_backends  rough spheres on the forest probe: cpu, gl and cl agree
 *   cache_said   the chain's log line says "cached" only when the host stored it: with
 *                a world-writable cache folder (the cache off) it says "not cached" and why
 *   grazing      Schlick on a sphere: every covered pixel finite, within [F0 c, c], and
 *                F(cos) of the analytic sphere where cos > 0.2; no NaN
 *   backface     a double-sided quad seen from behind (envmap along the flipped normal) and
 *                a single-sided quad whose normals face away (reflect: R = V, the
 *                background's value)
 *   half_clamp   a probe of 1e5 into rgba16f: every pixel 65504, one warning with the count
 *   base         the reflection added to a base image; where no geometry, base passes
 *   base_rgbe8   an rgbe8 base (background in rgbe8) gives the rgba32f base's reflection:
 *                bit for bit where RGBE holds the values, within its step otherwise
 *   base_rgbe8_extremes  an rgbe8 base saturated at RGBE's largest value (from FLT_MAX) and
 *                0: every output value finite
 *   tex_roughness  a metallic-roughness texture of two halves: each half the GGX level of
 *                its roughness (the untextured quads' pixels)
 *   tex_metal    a metal's base colour texture: c x the decoded texel per half
 *   tex_mask     an alpha mask's hole shows the probe (background and reflect over it)
 *   tex_normal   a normal texture: envmap along the mapped normal (a tilted quad's value)
 *   tex_bad_index  a texture index out of range: read as no texture, bit for bit
 *   duck         the Duck made a metal: its texture tints the reflection; backends agree
 *   gating       no reflective material, and no probe: reflect and envmap gated, the ibl
 *                plugin not loaded, --explain says why
 *   chain_limits a 1x1 probe with prefilter_size = 4096, levels = 16 (4.4 GiB and 78 s
 *                before): the chain is clamped to 8 per face and 4 levels with a warning
 *                shown at the default verbosity, and the render finishes with the constant;
 *                under an address-space limit of 100 MiB (RLIMIT_AS, set in this process and
 *                so in the host) a 2048x1024 probe's chain (94 MiB, mostly the resampling)
 *                is refused in prepare, naming the chain, the bytes needed and available
 *   forged_chain GGX chains in the host's cache with a valid checksum but values no
 *                prefiltering of the probe can make (NaN, Inf, 3e38, and 10 above a probe
 *                of at most 3) at the first, a middle and the last float: each reported
 *                once ("is corrupt (float N ..."), removed, prefiltered again, and the
 *                image equal bit for bit to a cold run; the remade chain then loads
 *   float_max    probes (lat-long, cube strip) of 0, FLT_MAX and sizes between, made by
 *                exposure = 2 clamping: reflect (mirror and rough), envmap and background
 *                write no non-finite value on any backend
 */
#include <float.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "lightgraph/image.h"
#include "lightgraph/probe.h"
#include "ggx_prefilter.h"
#include "lightgraph/test.h"
#include "lightgraph/vecmath.h"

#include "common/cache_forge.h"

static const char *const BACKENDS[] = { "cpu", "gl", "cl" };
static const char *const FORMATS[] = { "rgba32f", "rgba16f", "rgbe8" };

/* ---- helpers --------------------------------------------------------------------------------- */

static const float *px(const lg_image *img, uint32_t x, uint32_t y)
{
    return img->pixels + 4 * ((size_t)y * img->width + x);
}

static bool all_finite(const lg_image *img, uint32_t *bad_x, uint32_t *bad_y)
{
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++)
            for (int c = 0; c < 4; c++)
                if (!isfinite(px(img, x, y)[c])) {
                    *bad_x = x, *bad_y = y;
                    return false;
                }
    return true;
}

#define CHECK_FINITE(t, img, what)                                                                 \
    do {                                                                                           \
        uint32_t bx_ = 0, by_ = 0;                                                                 \
        LG_TEST_CHECK(t, all_finite(img, &bx_, &by_), "%s: a non-finite value at (%u, %u)", what,  \
                      bx_, by_);                                                                   \
    } while (0)

/* A constant W x H image of rgb (alpha 1). */
static lg_image constant_image(uint32_t w, uint32_t h, const float rgb[3])
{
    lg_image img = { 0 };
    if (lg_image_alloc(&img, w, h))
        return img;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        memcpy(img.pixels + 4 * i, rgb, 3 * sizeof(float));
        img.pixels[4 * i + 3] = 1.0f;
    }
    return img;
}

/* The camera of test_ibl_scene's parameters, as lg_scene_view_make builds it (perspective,
 * the output's aspect, row 0 at the top): the world ray through pixel centre (x, y). */
typedef struct cam {
    lg_vec3 pos, target, up;
    double yfov_deg;
} cam;

static lg_vec3 cam_ray(const cam *c, uint32_t w, uint32_t h, double x, double y)
{
    lg_vec3 f = lg_v3_normalize_or(lg_v3_sub(c->target, c->pos), lg_v3(0, 0, -1));
    lg_vec3 r = lg_v3_normalize_or(lg_v3_cross(f, c->up), lg_v3(1, 0, 0));
    lg_vec3 u = lg_v3_cross(r, f);
    double t = tan(0.5 * c->yfov_deg * LG_PI / 180.0), a = (double)w / h;
    double sx = (2.0 * (x + 0.5) / w - 1.0) * t * a, sy = (1.0 - 2.0 * (y + 0.5) / h) * t;
    return lg_v3_normalize_or(lg_v3_add(f, lg_v3_add(lg_v3_scale(r, (float)sx),
                                                     lg_v3_scale(u, (float)sy))),
                              f);
}

static void cam_params(char *out, size_t n, const cam *c)
{
    snprintf(out, n,
             "camera_position = [%g, %g, %g], camera_target = [%g, %g, %g], "
             "camera_up = [%g, %g, %g], yfov_deg = %g",
             c->pos.x, c->pos.y, c->pos.z, c->target.x, c->target.y, c->target.z, c->up.x, c->up.y,
             c->up.z, c->yfov_deg);
}

/* Where a ray from o along unit d meets the sphere of radius r at the origin (the nearer
 * hit); false when it misses. */
static bool hit_sphere(lg_vec3 o, lg_vec3 d, double r, lg_vec3 *p)
{
    double b = lg_v3_dot(o, d), c = lg_v3_dot(o, o) - r * r, disc = b * b - c;
    if (disc < 0)
        return false;
    double t = -b - sqrt(disc);
    if (t <= 0)
        return false;
    *p = lg_v3_add(o, lg_v3_scale(d, (float)t));
    return true;
}

/* Renders graph `g` (written to g.lgraph) with `args`; reads each of `outs` (file names)
 * into imgs. Returns the exit status (and the text in *text when given). */
static int render(lg_test *t, const char *g, const char *const *args, const char *const *outs,
                  lg_image *imgs, int n_outs, char **text)
{
    lg_test_write_text(t, "g.lgraph", g);
    int rc = lg_test_render(t, "g.lgraph", args, text);
    if (rc != 0)
        return rc;
    for (int i = 0; i < n_outs; i++)
        if (!lg_test_read(t, outs[i], &imgs[i], NULL))
            return -2;
    return 0;
}

/* ---- constant probe -------------------------------------------------------------------------- */

typedef struct probe_file {
    const char *what, *layout;
    uint32_t w, h;
} probe_file;

static void constant_formats(lg_test *t, int f_first, int f_last)
{
    const float c[3] = { 0.7f, 1.3f, 2.5f }, refl[3] = { 0.5f, 0.25f, 1.0f };
    static const probe_file probes[] = {
        { "latlong 32x16", "latlong", 32, 16 },
        { "angular 16x16", "angular", 16, 16 },
        { "cube strip 6x 8x8", "strip", 48, 8 },
        { "latlong 1x1", "latlong", 1, 1 },
    };
    const cam cm = { { 0, 0.5f, 6 }, { 0, 0, 0 }, { 0, 1, 0 }, 30 };
    char cp[512];
    cam_params(cp, sizeof cp, &cm);
    for (size_t p = 0; p < sizeof probes / sizeof probes[0]; p++) {
        lg_image pimg = constant_image(probes[p].w, probes[p].h, c);
        lg_test_write_exr(t, "probe.exr", &pimg);
        lg_image_free(&pimg);
        for (int b = 0; b < 3; b++)
            for (int f = f_first; f <= f_last; f++) {
                char g[4096];
                snprintf(g, sizeof g,
                         "lightgraph 1\n"
                         "s = test_ibl_scene { layout = spheres, segments = 24, "
                         "reflectivity = [%g, %g, %g], %s }\n"
                         "sky = probe { file = \"probe.exr\", layout = %s }\n"
                         "env = environment { scene = s, probe = sky }\n"
                         "r = reflect { scene = env, probe = sky, backend = %s, format = %s }\n"
                         "e = envmap { scene = env, probe = sky, backend = %s, format = %s }\n"
                         "bg = background { scene = env, probe = sky, backend = %s, "
                         "format = %s }\n"
                         "output r \"r.exr\"\noutput e \"e.exr\"\noutput bg \"bg.exr\"\n",
                         (double)refl[0], (double)refl[1], (double)refl[2], cp, probes[p].layout,
                         BACKENDS[b], FORMATS[f], BACKENDS[b], FORMATS[f], BACKENDS[b], FORMATS[f]);
                const char *args[] = { "--size", "96x32", NULL };
                const char *outs[] = { "r.exr", "e.exr", "bg.exr" };
                lg_image img[3] = { { 0 } };
                int rc = render(t, g, args, outs, img, 3, NULL);
                LG_TEST_CHECK(t, rc == 0, "%s %s %s: render failed (%d)", probes[p].what,
                              BACKENDS[b], FORMATS[f], rc);
                if (rc == 0) {
                    /* the format's precision: rgba16f one half ulp (2^-10 relative: the GL cube filter
                     * is within 1e-7 of c, which can round down a step), rgbe8 half a step of
                     * the shared exponent's mantissa (2^-8 of the largest channel) */
                    double rel = f == 0 ? 1e-6 : f == 1 ? 1.0 / 1024 : 0;
                    uint64_t covered = 0, wrong = 0, bad_bg = 0;
                    double worst = 0;
                    for (uint32_t y = 0; y < img[0].height; y++)
                        for (uint32_t x = 0; x < img[0].width; x++) {
                            const float *bg = px(&img[2], x, y);
                            bool is_bg = bg[0] != 0.0f;
                            for (int k = 0; k < 2; k++) {
                                const float *v = px(&img[k], x, y);
                                double mx = 0;
                                for (int ch = 0; ch < 3; ch++)
                                    mx = fmax(mx, (double)(refl[ch] * c[ch]));
                                for (int ch = 0; ch < 3; ch++) {
                                    double want = is_bg ? 0.0 : (double)(refl[ch] * c[ch]);
                                    double tol = f == 2 ? mx / 256.0 + 1e-7
                                                        : rel * fabs(want) + 1e-7;
                                    double d = fabs(v[ch] - want);
                                    worst = fmax(worst, d);
                                    if (!(d <= tol))
                                        wrong++;
                                }
                            }
                            if (is_bg) {
                                for (int ch = 0; ch < 3; ch++) {
                                    double tol = f == 2 ? c[2] / 256.0 : rel * c[ch] + 1e-7;
                                    if (!(fabs(bg[ch] - c[ch]) <= tol))
                                        bad_bg++;
                                }
                            } else {
                                covered++;
                            }
                        }
                    uint64_t np = (uint64_t)img[0].width * img[0].height;
                    LG_TEST_CHECK(t, wrong == 0 && bad_bg == 0,
                                  "%s %s %s: %llu reflect/envmap values and %llu background "
                                  "values off (worst abs error %g)",
                                  probes[p].what, BACKENDS[b], FORMATS[f],
                                  (unsigned long long)wrong, (unsigned long long)bad_bg, worst);
                    /* five spheres of radius 0.4 cover some, not all, of the image */
                    LG_TEST_CHECK(t, covered > np / 20 && covered < np / 2,
                                  "%s %s %s: %llu of %llu pixels covered", probes[p].what,
                                  BACKENDS[b], FORMATS[f], (unsigned long long)covered,
                                  (unsigned long long)np);
                    for (int k = 0; k < 3; k++)
                        CHECK_FINITE(t, &img[k], probes[p].what);
                }
                for (int k = 0; k < 3; k++)
                    lg_image_free(&img[k]);
            }
    }
}

static void case_constant(lg_test *t)
{
    constant_formats(t, 0, 1);
}

/* rgbe8 outputs need the host to accept LG_FORMAT_RGBE8 images (branch `formats`): a case
 * of its own, registered in meson.build once that is merged. */
static void case_constant_rgbe8(lg_test *t)
{
    constant_formats(t, 2, 2);
}

/* ---- one bright texel on a mirror sphere ----------------------------------------------------- */

static void case_bright_texel(lg_test *t)
{
    const uint32_t PW = 64, PH = 32, W = 96, H = 96;
    const uint32_t i0 = 58, j0 = 12; /* towards (0.5, 0.3, 0.8): behind the camera */
    lg_image probe = { 0 };
    lg_image_alloc(&probe, PW, PH);
    for (size_t i = 0; i < (size_t)PW * PH; i++)
        probe.pixels[4 * i + 3] = 1.0f;
    float *tx = probe.pixels + 4 * ((size_t)j0 * PW + i0);
    tx[0] = tx[1] = tx[2] = 1000.0f;
    lg_test_write_exr(t, "probe.exr", &probe);

    /* the prediction: analytic sphere, the same camera, the CPU's nearest lookup */
    const cam cm = { { 0, 0, 5 }, { 0, 0, 0 }, { 0, 1, 0 }, 40 };
    lg_probe_image pi = {
        .layout = LG_PROBE_LATLONG, .width = PW, .height = PH, .rgba = probe.pixels
    };
    double sx = 0, sy = 0, sw = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            lg_vec3 d = cam_ray(&cm, W, H, x, y), p;
            if (!hit_sphere(cm.pos, d, 1.0, &p))
                continue;
            lg_vec3 R = lg_v3_sub(d, lg_v3_scale(p, 2.0f * lg_v3_dot(d, p)));
            float v[4];
            lg_probe_lookup(&pi, R, LG_PROBE_NEAREST, v);
            sx += v[0] * x, sy += v[0] * y, sw += v[0];
        }
    LG_TEST_CHECK(t, sw > 0, "the analytic prediction sees no bright texel");
    if (sw <= 0) {
        lg_image_free(&probe);
        return;
    }
    sx /= sw, sy /= sw;
    char cp[512];
    cam_params(cp, sizeof cp, &cm);
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = sphere, segments = 192, %s }\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "r = reflect { scene = env, probe = sky, backend = %s, sampling = nearest }\n"
                 "output r \"r.exr\"\n",
                 cp, BACKENDS[b]);
        const char *args[] = { "--size", "96x96", NULL };
        const char *outs[] = { "r.exr" };
        lg_image img = { 0 };
        int rc = render(t, g, args, outs, &img, 1, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc)
            continue;
        double gx = 0, gy = 0, gw = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                float v = px(&img, x, y)[0];
                gx += v * x, gy += v * y, gw += v;
            }
        LG_TEST_CHECK(t, gw > 0, "%s: no bright pixel", BACKENDS[b]);
        if (gw > 0) {
            gx /= gw, gy /= gw;
            double dist = hypot(gx - sx, gy - sy);
            fprintf(stderr, "%s: bright spot at (%.2f, %.2f), predicted (%.2f, %.2f): %.3f px\n",
                    BACKENDS[b], gx, gy, sx, sy, dist);
            LG_TEST_CHECK(t, dist < 1.0,
                          "%s: the bright texel's reflection is at (%.2f, %.2f), predicted "
                          "(%.2f, %.2f)",
                          BACKENDS[b], gx, gy, sx, sy);
            /* the energy too: the spot's pixel count matches within 25 % */
            LG_TEST_CHECK(t, fabs(gw / sw - 1.0) < 0.25, "%s: spot weight %g, predicted %g",
                          BACKENDS[b], gw, sw);
        }
        CHECK_FINITE(t, &img, BACKENDS[b]);
        lg_image_free(&img);
    }
    lg_image_free(&probe);
}

/* ---- backends agree on a real probe ---------------------------------------------------------- */

/* A smooth cube strip (6N x N): radiance a function of the texel direction. */
static void write_smooth_strip(lg_test *t, uint32_t n)
{
    lg_image img = { 0 };
    lg_image_alloc(&img, 6 * n, n);
    for (uint32_t f = 0; f < 6; f++)
        for (uint32_t j = 0; j < n; j++)
            for (uint32_t i = 0; i < n; i++) {
                lg_vec3 d = lg_probe_texel_dir(LG_PROBE_CUBE, n, n, f, i, j);
                float *p = img.pixels + 4 * ((size_t)j * 6 * n + f * n + i);
                p[0] = 1.0f + d.x, p[1] = 1.0f + d.y * d.y * 2.0f, p[2] = 1.0f + d.z;
                p[3] = 1.0f;
            }
    lg_test_write_exr(t, "strip.exr", &img);
    lg_image_free(&img);
}

/* Tolerances (stated in README.md "Accuracy"): lat-long and angular lookups are the same
 * arithmetic on every backend (texelFetch on GL), so differences come from float rounding
 * of the direction and of atan2 (docs/probes.md: 4e-6 in texture coordinates) times the
 * probe's gradient, which the forest's leaves against the sky make steep: 1 % relative
 * plus 1e-3 absolute per value, RMSE 2e-4; the cube on GL is llvmpipe's seamless filter,
 * whose weights have 8 bits: 1 % relative on the smooth strip. */
static void case_backends(lg_test *t)
{
    write_smooth_strip(t, 32);
    const cam cm = { { 0.3f, 0.8f, 4 }, { 0, 0, 0 }, { 0, 1, 0 }, 45 };
    char cp[512];
    cam_params(cp, sizeof cp, &cm);
    struct {
        const char *file, *layout;
        lg_test_tol tol;
    } probes[] = {
        { "forest_1024x512.hdr", "latlong", { .max_abs = 1e-3, .rel = 1e-2, .rmse = 2e-4 } },
        { "forest_angular_1024.hdr", "angular", { .max_abs = 1e-3, .rel = 1e-2, .rmse = 2e-4 } },
        { "strip.exr", "strip", { .max_abs = 1e-3, .rel = 1e-2 } },
    };
    const char *nodes[] = { "reflect", "envmap", "background" };
    for (size_t p = 0; p < 3; p++) {
        const char *file = probes[p].file[0] == 's'
                               ? probes[p].file
                               : lg_test_asset(strcmp(probes[p].layout, "latlong")
                                                   ? "probes/forest_angular_1024.hdr"
                                                   : "probes/forest_1024x512.hdr");
        for (int k = 0; k < 3; k++) {
            char g[4096];
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_ibl_scene { layout = sphere, reflectivity = [0.9, 0.8, 0.6], %s }\n"
                     "sky = probe { file = \"%s\", layout = %s }\n"
                     "env = environment { scene = s, probe = sky }\n"
                     "n = %s { scene = env, probe = sky%s }\n",
                     cp, file, probes[p].layout, nodes[k], k == 0 ? ", fresnel = schlick" : "");
            const char *args[] = { "--size", "64x48", NULL };
            const char *bk[] = { "cpu", "gl", "cl", NULL };
            char what[128];
            snprintf(what, sizeof what, "%s on %s", nodes[k], probes[p].layout);
            lg_test_backends_desc d = { .graph = g,
                                        .node = "n",
                                        .backends = bk,
                                        .args = args,
                                        .tol_backends = probes[p].tol,
                                        .what = what };
            lg_test_backends_result res;
            lg_test_backends(t, &d, &res);
            for (size_t r = 0; r < res.n; r++)
                if (res.run[r].status == LG_TEST_RUN_OK)
                    CHECK_FINITE(t, &res.run[r].image, what);
            LG_TEST_CHECK(t, res.n_ok == 3, "%s: %zu of 3 backends ran", what, res.n_ok);
            lg_test_backends_free(&res);
        }
    }
}

/* ---- views along the axes -------------------------------------------------------------------- */

static void case_axes(lg_test *t)
{
    write_smooth_strip(t, 16);
    /* a lat-long probe with a gradient in u and v, so that seam and poles show */
    lg_image ll = { 0 };
    lg_image_alloc(&ll, 64, 32);
    for (uint32_t j = 0; j < 32; j++)
        for (uint32_t i = 0; i < 64; i++) {
            lg_vec3 d = lg_probe_texel_dir(LG_PROBE_LATLONG, 64, 32, 0, i, j);
            float *p = ll.pixels + 4 * ((size_t)j * 64 + i);
            p[0] = 1.0f + d.x, p[1] = 1.0f + d.y, p[2] = 1.0f + d.z, p[3] = 1.0f;
        }
    lg_test_write_exr(t, "ll.exr", &ll);
    lg_image_free(&ll);
    static const float axes[6][3] = { { 1, 0, 0 },  { -1, 0, 0 }, { 0, 1, 0 },
                                      { 0, -1, 0 }, { 0, 0, 1 },  { 0, 0, -1 } };
    const char *files[2] = { "ll.exr", "strip.exr" }, *layouts[2] = { "latlong", "strip" };
    for (int l = 0; l < 2; l++)
        for (int a = 0; a < 6; a++) {
            lg_vec3 up = fabsf(axes[a][1]) > 0.5f ? lg_v3(0, 0, -1) : lg_v3(0, 1, 0);
            /* an even size: the axis passes between the four centre pixels */
            const cam cm = { { 0, 0, 0 }, { axes[a][0], axes[a][1], axes[a][2] }, up, 60 };
            char cp[512], g[2048];
            cam_params(cp, sizeof cp, &cm);
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_ibl_scene { layout = none, %s }\n"
                     "sky = probe { file = \"%s\", layout = %s }\n"
                     "env = environment { scene = s, probe = sky }\n"
                     "n = background { scene = env, probe = sky }\n",
                     cp, files[l], layouts[l]);
            const char *args[] = { "--size", "32x32", NULL };
            const char *bk[] = { "cpu", "gl", "cl", NULL };
            char what[64];
            snprintf(what, sizeof what, "%s along (%g, %g, %g)", layouts[l], (double)axes[a][0],
                     (double)axes[a][1], (double)axes[a][2]);
            lg_test_backends_desc d = { .graph = g,
                                        .node = "n",
                                        .backends = bk,
                                        .args = args,
                                        .tol_backends = { .max_abs = 1e-3, .rel = 1e-2 },
                                        .what = what };
            lg_test_backends_result res;
            lg_test_backends(t, &d, &res);
            for (size_t r = 0; r < res.n; r++) {
                if (res.run[r].status != LG_TEST_RUN_OK)
                    continue;
                const lg_image *img = &res.run[r].image;
                CHECK_FINITE(t, img, what);
                /* the mean of the four centre pixels is the probe along the axis: the
                 * functions are linear in the direction, 1 + d, to first order */
                double m[3] = { 0, 0, 0 };
                for (int k = 0; k < 4; k++)
                    for (int ch = 0; ch < 3; ch++)
                        m[ch] += 0.25 * px(img, 15 + (k & 1), 15 + (k >> 1))[ch];
                double want[3] = { 1 + axes[a][0],
                                   l ? 1 + 2 * axes[a][1] * axes[a][1] : 1 + axes[a][1],
                                   1 + axes[a][2] };
                for (int ch = 0; ch < 3; ch++)
                    LG_TEST_CHECK(t, fabs(m[ch] - want[ch]) < 0.05,
                                  "%s on %s: centre channel %d = %g, want %g", what,
                                  res.run[r].backend, ch, m[ch], want[ch]);
            }
            LG_TEST_CHECK(t, res.n_ok == 3, "%s: %zu of 3 backends ran", what, res.n_ok);
            lg_test_backends_free(&res);
        }
}

/* The probe's rotation (info.rotation, rotate_deg = [90, 0, 0]: yaw 90 turns the probe's
 * centre, -Z, toward -X): looking along world -Z sees the probe's own +X, so the centre
 * of the linear probe 1 + d reads (2, 1, 1) on every backend. */
static void case_rotation(lg_test *t)
{
    lg_image ll = { 0 };
    lg_image_alloc(&ll, 64, 32);
    for (uint32_t j = 0; j < 32; j++)
        for (uint32_t i = 0; i < 64; i++) {
            lg_vec3 d = lg_probe_texel_dir(LG_PROBE_LATLONG, 64, 32, 0, i, j);
            float *p = ll.pixels + 4 * ((size_t)j * 64 + i);
            p[0] = 1.0f + d.x, p[1] = 1.0f + d.y, p[2] = 1.0f + d.z, p[3] = 1.0f;
        }
    lg_test_write_exr(t, "ll.exr", &ll);
    lg_image_free(&ll);
    const char *g = "lightgraph 1\n"
                    "s = test_ibl_scene { layout = none, camera_position = [0, 0, 0], "
                    "camera_target = [0, 0, -1] }\n"
                    "sky = probe { file = \"ll.exr\", layout = latlong, rotate_deg = [90, 0, 0] }\n"
                    "env = environment { scene = s, probe = sky }\n"
                    "n = background { scene = env, probe = sky }\n";
    const char *args[] = { "--size", "32x32", NULL };
    const char *bk[] = { "cpu", "gl", "cl", NULL };
    lg_test_backends_desc d = { .graph = g,
                                .node = "n",
                                .backends = bk,
                                .args = args,
                                .tol_backends = { .max_abs = 1e-3, .rel = 1e-2 },
                                .what = "rotated probe" };
    lg_test_backends_result res;
    lg_test_backends(t, &d, &res);
    for (size_t r = 0; r < res.n; r++) {
        if (res.run[r].status != LG_TEST_RUN_OK)
            continue;
        const lg_image *img = &res.run[r].image;
        double m[3] = { 0, 0, 0 }, want[3] = { 2, 1, 1 };
        for (int k = 0; k < 4; k++)
            for (int ch = 0; ch < 3; ch++)
                m[ch] += 0.25 * px(img, 15 + (k & 1), 15 + (k >> 1))[ch];
        for (int ch = 0; ch < 3; ch++)
            LG_TEST_CHECK(t, fabs(m[ch] - want[ch]) < 0.05,
                          "%s: rotated probe, centre channel %d = %g, want %g", res.run[r].backend,
                          ch, m[ch], want[ch]);
        CHECK_FINITE(t, img, res.run[r].backend);
    }
    LG_TEST_CHECK(t, res.n_ok == 3, "%zu of 3 backends ran", res.n_ok);
    lg_test_backends_free(&res);
}

/* ---- grazing views --------------------------------------------------------------------------- */

static void case_grazing(lg_test *t)
{
    const float c[3] = { 2, 2, 2 };
    lg_image pimg = constant_image(16, 8, c);
    lg_test_write_exr(t, "probe.exr", &pimg);
    lg_image_free(&pimg);
    const cam cm = { { 0, 0, 5 }, { 0, 0, 0 }, { 0, 1, 0 }, 30 };
    char cp[512];
    cam_params(cp, sizeof cp, &cm);
    const uint32_t W = 96, H = 96;
    const double F0 = 0.04;
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = sphere, segments = 128, "
                 "reflectivity = [0.04, 0.04, 0.04], %s }\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "r = reflect { scene = env, probe = sky, backend = %s, fresnel = schlick }\n"
                 "output r \"r.exr\"\n",
                 cp, BACKENDS[b]);
        const char *args[] = { "--size", "96x96", NULL };
        const char *outs[] = { "r.exr" };
        lg_image img = { 0 };
        int rc = render(t, g, args, outs, &img, 1, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc)
            continue;
        CHECK_FINITE(t, &img, BACKENDS[b]);
        uint64_t out_of_range = 0, off = 0, checked = 0;
        double worst = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                float v = px(&img, x, y)[0];
                if (v == 0.0f)
                    continue; /* no geometry */
                if (!(v >= F0 * c[0] * (1 - 1e-5) && v <= c[0] * (1 + 1e-5)))
                    out_of_range++;
                lg_vec3 d = cam_ray(&cm, W, H, x, y), p;
                if (!hit_sphere(cm.pos, d, 1.0, &p))
                    continue;
                double cs = -lg_v3_dot(d, p);
                if (cs < 0.2)
                    continue;
                double k = 1 - cs, want = c[0] * (F0 + (1 - F0) * k * k * k * k * k);
                checked++;
                worst = fmax(worst, fabs(v - want) / want);
                if (fabs(v - want) > 0.02 * want)
                    off++;
            }
        fprintf(stderr, "%s: Schlick vs the analytic sphere on %llu pixels: worst %.4f relative\n",
                BACKENDS[b], (unsigned long long)checked, worst);
        LG_TEST_CHECK(t, out_of_range == 0, "%s: %llu pixels outside [F0 c, c]", BACKENDS[b],
                      (unsigned long long)out_of_range);
        LG_TEST_CHECK(t, off == 0 && checked > 1000,
                      "%s: %llu of %llu pixels off Schlick's F by more than 2 %% (worst %g)",
                      BACKENDS[b], (unsigned long long)off, (unsigned long long)checked, worst);
        lg_image_free(&img);
    }
}

/* ---- back-facing normals --------------------------------------------------------------------- */

/* A probe bright on the +Z half (10), dark on -Z (1): which side a lookup reads shows. */
static void write_halves(lg_test *t)
{
    lg_image img = { 0 };
    lg_image_alloc(&img, 64, 32);
    for (uint32_t j = 0; j < 32; j++)
        for (uint32_t i = 0; i < 64; i++) {
            lg_vec3 d = lg_probe_texel_dir(LG_PROBE_LATLONG, 64, 32, 0, i, j);
            float *p = img.pixels + 4 * ((size_t)j * 64 + i);
            float v = 1.0f + 4.0f * (d.z + 1.0f) + 2.0f * d.x;
            p[0] = p[1] = p[2] = v;
            p[3] = 1.0f;
        }
    lg_test_write_exr(t, "halves.exr", &img);
    lg_image_free(&img);
}

static void case_backface(lg_test *t)
{
    write_halves(t);
    lg_image probe = { 0 };
    LG_TEST_CHECK(t, lg_test_read(t, "halves.exr", &probe, NULL), "halves.exr");
    lg_probe_image pi = {
        .layout = LG_PROBE_LATLONG, .width = 64, .height = 32, .rgba = probe.pixels
    };
    /* the camera on -Z looks at a quad whose front faces +Z: its back side */
    const cam cm = { { 0, 0, -4 }, { 0, 0, 0 }, { 0, 1, 0 }, 20 };
    char cp[512];
    cam_params(cp, sizeof cp, &cm);
    for (int b = 0; b < 3; b++) {
        /* 1. double-sided, seen from behind: envmap reads along -N = -Z */
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = quad, quad_normal = [0, 0, 1], "
                 "double_sided = true, %s }\n"
                 "sky = probe { file = \"halves.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "e = envmap { scene = env, probe = sky, backend = %s }\n"
                 "output e \"e.exr\"\n",
                 cp, BACKENDS[b]);
        const char *args[] = { "--size", "32x32", NULL };
        const char *outs[] = { "e.exr" };
        lg_image img = { 0 };
        int rc = render(t, g, args, outs, &img, 1, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc == 0) {
            float want[4];
            lg_probe_lookup(&pi, lg_v3(0, 0, -1), LG_PROBE_BILINEAR, want);
            float got = px(&img, 16, 16)[0];
            LG_TEST_CHECK(t, fabsf(got - want[0]) < 1e-4f * want[0],
                          "%s: double-sided back side: envmap %g, want the probe along -Z %g",
                          BACKENDS[b], (double)got, (double)want[0]);
            CHECK_FINITE(t, &img, BACKENDS[b]);
            lg_image_free(&img);
        }
        /* 2. single-sided, culled from behind: nothing drawn */
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = quad, quad_normal = [0, 0, 1], %s }\n"
                 "sky = probe { file = \"halves.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "e = envmap { scene = env, probe = sky, backend = %s }\n"
                 "output e \"e.exr\"\n",
                 cp, BACKENDS[b]);
        rc = render(t, g, args, outs, &img, 1, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc == 0) {
            LG_TEST_CHECK(t, px(&img, 16, 16)[0] == 0.0f,
                          "%s: a single-sided quad seen from behind was drawn (%g)", BACKENDS[b],
                          (double)px(&img, 16, 16)[0]);
            lg_image_free(&img);
        }
        /* 3. single-sided, front face toward the camera but normals facing away (tilted
         *    30 degrees about Y): reflect gives R = V, the background's value */
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = quad, quad_normal = [-0.5, 0, -0.8660254], "
                 "flip_normals = true, %s }\n"
                 "sky = probe { file = \"halves.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "r = reflect { scene = env, probe = sky, backend = %s }\n"
                 "output r \"r.exr\"\n",
                 cp, BACKENDS[b]);
        const char *outs_r[] = { "r.exr" };
        lg_image two[1] = { { 0 } };
        rc = render(t, g, args, outs_r, two, 1, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc == 0) {
            /* the probe along the pixel's ray (the analytic camera) */
            uint64_t n = 0, off = 0;
            for (uint32_t y = 8; y < 24; y++)
                for (uint32_t x = 8; x < 24; x++) {
                    float r = px(&two[0], x, y)[0];
                    if (r == 0.0f)
                        continue;
                    float want[4];
                    lg_probe_lookup(&pi, cam_ray(&cm, 32, 32, x, y), LG_PROBE_BILINEAR, want);
                    n++;
                    if (fabsf(r - want[0]) > 1e-3f * want[0])
                        off++;
                }
            LG_TEST_CHECK(t, n > 100 && off == 0,
                          "%s: normals facing away on a single-sided quad: %llu of %llu pixels "
                          "are not the probe along V",
                          BACKENDS[b], (unsigned long long)off, (unsigned long long)n);
            CHECK_FINITE(t, &two[0], BACKENDS[b]);
            lg_image_free(&two[0]);
        }
    }
    lg_image_free(&probe);
}

/* ---- glossy reflection ----------------------------------------------------------------------- */

/* A smooth lat-long probe: radiance a low-order function of the direction. */
static void smooth_latlong(lg_image *img, uint32_t w, uint32_t h)
{
    lg_image_alloc(img, w, h);
    for (uint32_t j = 0; j < h; j++)
        for (uint32_t i = 0; i < w; i++) {
            lg_vec3 d = lg_probe_texel_dir(LG_PROBE_LATLONG, w, h, 0, i, j);
            float *p = img->pixels + 4 * ((size_t)j * w + i);
            float up = d.y > 0 ? d.y : 0.0f;
            p[0] = 1.0f + 0.6f * d.x + 2.0f * up * up;
            p[1] = 1.0f + 0.5f * d.z + 1.0f * up;
            p[2] = 1.5f - 0.5f * d.y + 0.3f * d.x * d.z;
            p[3] = 1.0f;
        }
}

/* Glossy spheres (roughness 0.5, F0 0.9, fresnel schlick) under a smooth probe against the
 * Monte Carlo oracle lg_probe_ggx_reference (4096 samples) at the analytic sphere's normal
 * and view, on every backend; the chain comes from the host's cache on a second render;
 * roughness 0 reads the probe itself (glossy = auto and off give the same image, and no
 * chain is made). Two oracles: lg_probe_ggx_split_sum on a chain made here as the node
 * makes it (the node's formula: within 2 %, measured 0.13 % on every backend), and the
 * Monte Carlo integral of the BRDF, from which the split-sum approximation itself departs
 * as the view leaves the normal (Karis 2013 assumes n = v): within 6 % where n.v > 0.7
 * (measured 5.3 %) and 20 % down to n.v = 0.3 (measured 17 %; rms 4.3 %). */
static void case_glossy(lg_test *t)
{
    const uint32_t W = 48, H = 48;
    lg_image probe = { 0 };
    smooth_latlong(&probe, 128, 64);
    lg_test_write_exr(t, "probe.exr", &probe);
    lg_probe_image pi = {
        .layout = LG_PROBE_LATLONG, .width = 128, .height = 64, .rgba = probe.pixels
    };
    const cam cm = { { 0, 0, 4 }, { 0, 0, 0 }, { 0, 1, 0 }, 35 };
    char cp[512];
    cam_params(cp, sizeof cp, &cm);
    const float f0[3] = { 0.9f, 0.9f, 0.9f };
    /* the oracle on every other pixel of the analytic sphere with n.v > 0.3 */
    double *want = calloc((size_t)W * H * 3, sizeof(double));
    float *ss = calloc((size_t)W * H * 3, sizeof(float)),
          *cosv = calloc((size_t)W * H, sizeof(float));
    bool *use = calloc((size_t)W * H, sizeof(bool));
    /* the split sum itself from a chain made here as the node makes it (auto size: the
     * probe's width / 4 = 32 per face, 6 levels, 256 samples): the node's formula */
    const uint32_t CS = 32, CL = 6;
    lg_image_desc cd = { .width = CS, .height = CS, .flags = LG_IMAGE_CUBE, .levels = CL };
    float *chain = malloc(4 * lg_image_offset(&cd, CL, 0) * sizeof(float));
    lg_probe_image lv[6];
    LG_TEST_CHECK(t,
                  chain && lg_probe_prefilter_ggx(NULL, &pi, LG_PROBE_CUBE, CS, CS, CL, NULL, chain,
                                                  NULL) == 0,
                  "prefiltering the test's chain failed");
    for (uint32_t l = 0; l < CL; l++)
        lv[l] = lg_probe_image_at(LG_PROBE_CUBE, &cd, chain, l, NULL);
    uint32_t n_use = 0;
    for (uint32_t y = 0; y < H && want && use; y += 2)
        for (uint32_t x = 0; x < W; x += 2) {
            lg_vec3 d = cam_ray(&cm, W, H, x, y), p;
            if (!hit_sphere(cm.pos, d, 1.0, &p) || -lg_v3_dot(d, p) < 0.3f)
                continue;
            size_t i = (size_t)y * W + x;
            lg_probe_ggx_reference(&pi, p, lg_v3_scale(d, -1.0f), 0.5f, f0, 4096, 7, want + 3 * i);
            if (chain)
                lg_probe_ggx_split_sum(lv, CL, p, lg_v3_scale(d, -1.0f), 0.5f, f0, ss + 3 * i);
            cosv[i] = -lg_v3_dot(d, p);
            use[i] = true;
            n_use++;
        }
    LG_TEST_CHECK(t, n_use > 100, "only %u oracle pixels", n_use);
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = sphere, segments = 128, roughness = 0.5, "
                 "reflectivity = [0.9, 0.9, 0.9], %s }\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "r = reflect { scene = env, probe = sky, backend = %s, fresnel = schlick }\n"
                 "output r \"r.exr\"\n",
                 cp, BACKENDS[b]);
        const char *args[] = { "--size", "48x48", "-v", NULL };
        const char *outs[] = { "r.exr" };
        for (int run = 0; run < 2; run++) {
            lg_image img = { 0 };
            char *text = NULL;
            int rc = render(t, g, args, outs, &img, 1, &text);
            LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
            if (rc == 0) {
                const char *hit = strstr(text, "GGX chain loaded from the cache");
                const char *made = strstr(text, "GGX chain prefiltered");
                LG_TEST_CHECK(t, run == 0 ? (made && !hit) : (hit && !made),
                              "%s, render %d: the chain was not %s:\n%s", BACKENDS[b], run + 1,
                              run == 0 ? "prefiltered" : "loaded from the cache", text);
                /* against the Monte Carlo oracle (n.v > 0.3, and n.v > 0.7) and against the
                 * split sum of the test's own chain */
                double worst = 0, worst7 = 0, worst_ss = 0, sum2 = 0;
                uint32_t off = 0, off_ss = 0, nn = 0;
                for (size_t i = 0; i < (size_t)W * H; i++) {
                    if (!use[i])
                        continue;
                    for (int c = 0; c < 3; c++) {
                        double got = img.pixels[4 * i + c];
                        double e = fabs(got - want[3 * i + c]) / want[3 * i + c];
                        double es = fabs(got - ss[3 * i + c]) / ss[3 * i + c];
                        worst = fmax(worst, e);
                        if (cosv[i] > 0.7f)
                            worst7 = fmax(worst7, e);
                        worst_ss = fmax(worst_ss, es);
                        sum2 += e * e;
                        nn++;
                        off += !(e < (cosv[i] > 0.7f ? 0.06 : 0.20));
                        off_ss += !(es < 0.02);
                    }
                }
                if (run == 0)
                    fprintf(stderr,
                            "%s: roughness 0.5, %u values: vs the oracle worst %.4f (n.v > 0.7: "
                            "%.4f), rms %.4f relative; vs the split sum of lg_probe_ggx_split_sum "
                            "worst %.4f\n",
                            BACKENDS[b], nn, worst, worst7, sqrt(sum2 / (nn ? nn : 1)), worst_ss);
                LG_TEST_CHECK(t, off == 0 && off_ss == 0,
                              "%s: %u values beyond the oracle's tolerance (6 %% where n.v > 0.7, "
                              "20 %% elsewhere; worst %g, %g) and %u beyond 2 %% of the split "
                              "sum (worst %g)",
                              BACKENDS[b], off, worst7, worst, off_ss, worst_ss);
                CHECK_FINITE(t, &img, BACKENDS[b]);
                lg_image_free(&img);
            }
            free(text);
        }
        /* roughness 0: the probe itself, glossy auto or off alike, no chain */
        lg_image two[2] = { { 0 } };
        for (int k = 0; k < 2; k++) {
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_ibl_scene { layout = sphere, segments = 64, roughness = 0, %s }\n"
                     "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                     "env = environment { scene = s, probe = sky }\n"
                     "r = reflect { scene = env, probe = sky, backend = %s, glossy = %s }\n"
                     "output r \"r.exr\"\n",
                     cp, BACKENDS[b], k ? "off" : "auto");
            char *text = NULL;
            int rc = render(t, g, args, outs, &two[k], 1, &text);
            LG_TEST_CHECK(t, rc == 0 && !strstr(text, "GGX chain"),
                          "%s: roughness 0 (glossy %s): status %d, or a chain was made:\n%s",
                          BACKENDS[b], k ? "off" : "auto", rc, text ? text : "");
            free(text);
        }
        if (two[0].pixels && two[1].pixels)
            LG_TEST_CHECK(t, !memcmp(two[0].pixels, two[1].pixels, (size_t)W * H * 16),
                          "%s: roughness 0 differs between glossy auto and off", BACKENDS[b]);
        lg_image_free(&two[0]);
        lg_image_free(&two[1]);
    }
    free(want);
    free(ss);
    free(cosv);
    free(chain);
    free(use);
    lg_image_free(&probe);
}

/* Glossy spheres of roughness 0 .. 1 on the forest probe: cpu, gl and cl agree (GL reads
 * the chain through a mipmapped cube texture with llvmpipe's 8-bit filter weights: 1 %). */
static void case_glossy_backends(lg_test *t)
{
    const cam cm = { { 0, 0.5f, 6 }, { 0, 0, 0 }, { 0, 1, 0 }, 30 };
    char cp[512], g[2048];
    cam_params(cp, sizeof cp, &cm);
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_ibl_scene { layout = spheres, segments = 48, "
             "reflectivity = [0.9, 0.7, 0.5], %s }\n"
             "sky = probe { file = \"%s\", layout = latlong }\n"
             "env = environment { scene = s, probe = sky }\n"
             "n = reflect { scene = env, probe = sky, fresnel = schlick }\n",
             cp, lg_test_asset("probes/forest_1024x512.hdr"));
    const char *args[] = { "--size", "96x32", NULL };
    const char *bk[] = { "cpu", "gl", "cl", NULL };
    lg_test_backends_desc d = { .graph = g,
                                .node = "n",
                                .backends = bk,
                                .args = args,
                                .tol_backends = { .max_abs = 1e-3, .rel = 1e-2, .rmse = 5e-4 },
                                .what = "glossy spheres" };
    lg_test_backends_result res;
    lg_test_backends(t, &d, &res);
    for (size_t r = 0; r < res.n; r++)
        if (res.run[r].status == LG_TEST_RUN_OK)
            CHECK_FINITE(t, &res.run[r].image, res.run[r].backend);
    LG_TEST_CHECK(t, res.n_ok == 3, "%zu of 3 backends ran", res.n_ok);
    lg_test_backends_free(&res);
}

/* ---- rgba16f clamping ------------------------------------------------------------------------ */

static void case_half_clamp(lg_test *t)
{
    const float c[3] = { 1e5f, 1e5f, 1e5f };
    lg_image pimg = constant_image(8, 4, c);
    lg_test_write_exr(t, "probe.exr", &pimg);
    lg_image_free(&pimg);
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = none }\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "bg = background { scene = env, probe = sky, backend = %s, format = rgba16f }\n"
                 "output bg \"bg.exr\"\n",
                 BACKENDS[b]);
        /* two frames, the node run in both: still one report */
        const char *args[] = { "--size", "20x10", "--frames", "2", "--every-frame", "-v", NULL };
        const char *outs[] = { "bg.exr" };
        lg_image img = { 0 };
        char *text = NULL;
        int rc = render(t, g, args, outs, &img, 1, &text);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc == 0) {
            uint64_t off = 0;
            for (size_t i = 0; i < 200; i++)
                for (int ch = 0; ch < 3; ch++)
                    off += img.pixels[4 * i + ch] != 65504.0f;
            LG_TEST_CHECK(t, off == 0, "%s: %llu values are not 65504", BACKENDS[b],
                          (unsigned long long)off);
            const char *key = "200 pixels above 65504";
            const char *m = text ? strstr(text, key) : NULL;
            LG_TEST_CHECK(t, m && !strstr(m + strlen(key), "above 65504"),
                          "%s: the clamp is not reported once with its count:\n%s", BACKENDS[b],
                          text ? text : "");
            lg_image_free(&img);
        }
        free(text);
    }
}

/* ---- a probe at the float maximum ------------------------------------------------------------ */

/* Probes whose texels, times 2^exposure (exposure = 2), pass the float range: the probe
 * node clamps them to FLT_MAX (and says so), next to texels of 0 and of every size between
 * (a hash of the texel's position picks one): a lat-long map and a cube strip. reflect
 * (mirror and rough, fresnel none and schlick), envmap and background on every backend
 * must stay finite: every value they compute is a weighted mean of texels with weights
 * <= 1, which a float holds. */
static void write_float_max_probes(lg_test *t)
{
    for (int cube = 0; cube < 2; cube++) {
        lg_image img = { 0 };
        const uint32_t W = cube ? 6 * 16 : 64, H = cube ? 16 : 32;
        lg_image_alloc(&img, W, H);
        for (uint32_t j = 0; j < H; j++)
            for (uint32_t i = 0; i < W; i++) {
                float *p = img.pixels + 4 * ((size_t)j * W + i);
                uint32_t h = (i * 73856093u) ^ (j * 19349663u);
                h = (h ^ (h >> 13)) * 0x5bd1e995u;
                for (int c = 0; c < 3; c++) {
                    uint32_t r = (h >> (8 * c)) & 0xff;
                    /* a third 0, a third at 1e38 (FLT_MAX once scaled), a third between */
                    p[c] = r < 85 ? 0.0f : r < 170 ? 1e38f : (float)(r - 170) * (1e38f / 85);
                }
                p[3] = 1;
            }
        lg_test_write_exr(t, cube ? "probe_cube.exr" : "probe_latlong.exr", &img);
        lg_image_free(&img);
    }
}

static void case_float_max(lg_test *t)
{
    write_float_max_probes(t);
    static const char *const probes[] = {
        "file = \"probe_latlong.exr\", layout = latlong",
        "file = \"probe_cube.exr\", layout = strip",
    };
    static const char *const nodes[] = {
        "reflect { scene = env, probe = sky, backend = %s, fresnel = none }",
        "reflect { scene = env, probe = sky, backend = %s, fresnel = schlick }",
        "envmap { scene = env, probe = sky, backend = %s, fresnel = schlick }",
        "background { scene = env, probe = sky, backend = %s }",
    };
    static const char *const rough[] = { "0", "0.5" };
    for (int b = 0; b < 3; b++)
        for (int pr = 0; pr < 2; pr++)
            for (size_t k = 0; k < sizeof nodes / sizeof nodes[0]; k++)
                for (int r = 0; r < 2; r++) {
                    if (r == 1 && k == 3)
                        continue; /* background has no roughness */
                    char node[256], g[2048], what[512];
                    snprintf(node, sizeof node, nodes[k], BACKENDS[b]);
                    snprintf(what, sizeof what, "%s, probe { %s }, roughness %s", node, probes[pr],
                             rough[r]);
                    snprintf(g, sizeof g,
                             "lightgraph 1\n"
                             "s = test_ibl_scene { layout = sphere, segments = 64, "
                             "reflectivity = [1, 0.5, 0.04], roughness = %s }\n"
                             "sky = probe { %s, exposure = 2 }\n"
                             "env = environment { scene = s, probe = sky }\n"
                             "r = %s\n"
                             "output r \"r.exr\"\n",
                             rough[r], probes[pr], node);
                    const char *args[] = { "--size", "64x64", NULL };
                    const char *outs[] = { "r.exr" };
                    lg_image img = { 0 };
                    char *text = NULL;
                    int rc = render(t, g, args, outs, &img, 1, &text);
                    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d):\n%s", what, rc,
                                  text ? text : "");
                    free(text);
                    if (rc)
                        continue;
                    uint64_t bad = 0, at_max = 0;
                    for (size_t i = 0; i < (size_t)img.width * img.height; i++)
                        for (int c = 0; c < 4; c++) {
                            bad += !isfinite(img.pixels[4 * i + c]);
                            at_max += img.pixels[4 * i + c] == FLT_MAX;
                        }
                    LG_TEST_CHECK(t, bad == 0, "%s: %llu non-finite values", what,
                                  (unsigned long long)bad);
                    /* the mirror reads FLT_MAX somewhere (else the case tests nothing) */
                    LG_TEST_CHECK(t, r == 1 || at_max > 0, "%s: no value at FLT_MAX", what);
                    lg_image_free(&img);
                }
}

/* ---- forged cache entries -------------------------------------------------------------------- */

static int occurrences(const char *text, const char *needle)
{
    int k = 0;
    for (const char *p = text ? strstr(text, needle) : NULL; p; p = strstr(p + 1, needle))
        k++;
    return k;
}

static void case_forged_chain(lg_test *t)
{
    lg_image probe = { 0 };
    lg_image_alloc(&probe, 64, 32);
    for (uint32_t j = 0; j < 32; j++)
        for (uint32_t i = 0; i < 64; i++) {
            float *p = probe.pixels + 4 * ((size_t)j * 64 + i);
            p[0] = 1.0f + 2.0f * (float)i / 63; /* 1 .. 3 */
            p[1] = 1.0f + (float)j / 31;
            p[2] = 0.5f;
            p[3] = 1.0f;
        }
    lg_test_write_exr(t, "probe.exr", &probe);
    lg_image_free(&probe);
    const char *g = "lightgraph 1\n"
                    "s = test_ibl_scene { layout = sphere, segments = 48, roughness = 0.5, "
                    "reflectivity = [0.9, 0.9, 0.9] }\n"
                    "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                    "env = environment { scene = s, probe = sky }\n"
                    "r = reflect { scene = env, probe = sky, backend = cpu, "
                    "prefilter_samples = 32 }\n"
                    "output r \"r.exr\"\n";
    const char *args[] = { "--size", "32x32", "-v", NULL };
    const char *outs[] = { "r.exr" };
    lg_image cold = { 0 };
    char *text = NULL;
    int rc = render(t, g, args, outs, &cold, 1, &text);
    LG_TEST_CHECK(t, rc == 0 && text && strstr(text, "GGX chain prefiltered"),
                  "the cold run did not prefilter (%d):\n%s", rc, text ? text : "");
    free(text);
    if (rc)
        return;
    const char *dir = getenv("LIGHTGRAPH_CACHE_DIR");
    char path[1024] = "";
    LG_TEST_CHECK(t, cache_forge_find(dir, "reflect-", path, sizeof path) == 1,
                  "want one reflect entry in %s", dir ? dir : "(unset)");
    long nf = cache_forge_floats(path, 24); /* sizeof(ibl_chain_header) */
    LG_TEST_CHECK(t, nf > 8, "chain of %ld floats", nf);
    if (nf <= 8)
        return;
    static const struct {
        float v;
        const char *what;
    } forged[] = { { NAN, "NaN" }, { INFINITY, "Inf" }, { 3e38f, "3e38" }, { 10.0f, "10" } };
    size_t at[3] = { 0, 4 * (size_t)(nf / 8) + 1, (size_t)nf - 3 }; /* R, G, G */
    for (size_t f = 0; f < sizeof forged / sizeof forged[0]; f++)
        for (int a = 0; a < 3; a++) {
            LG_TEST_CHECK(t, cache_forge_float(path, 24, at[a], forged[f].v) == 0,
                          "cannot forge %s", path);
            lg_image img = { 0 };
            rc = render(t, g, args, outs, &img, 1, &text);
            char want[64];
            snprintf(want, sizeof want, "is corrupt (float %zu ", at[a]);
            LG_TEST_CHECK(t,
                          rc == 0 && occurrences(text, "is corrupt") == 1 && strstr(text, want) &&
                              strstr(text, "GGX chain prefiltered"),
                          "%s at float %zu: not reported once and prefiltered again (%d):\n%s",
                          forged[f].what, at[a], rc, text ? text : "");
            if (rc == 0) {
                CHECK_FINITE(t, &img, forged[f].what);
                LG_TEST_CHECK(t, memcmp(img.pixels, cold.pixels, (size_t)32 * 32 * 16) == 0,
                              "%s at float %zu: the image differs from the cold run",
                              forged[f].what, at[a]);
                lg_image_free(&img);
            }
            free(text);
        }
    lg_image img = { 0 };
    rc = render(t, g, args, outs, &img, 1, &text);
    LG_TEST_CHECK(t,
                  rc == 0 && strstr(text, "GGX chain loaded from the cache") &&
                      !strstr(text, "corrupt"),
                  "the remade chain was not loaded (%d):\n%s", rc, text ? text : "");
    if (rc == 0)
        lg_image_free(&img);
    free(text);
    lg_image_free(&cold);
}

/* ---- base image ------------------------------------------------------------------------------ */

static void case_base(lg_test *t)
{
    const float c[3] = { 1, 2, 3 }, bc[3] = { 0.25f, 0.5f, 0.125f };
    lg_image pimg = constant_image(16, 8, c);
    lg_test_write_exr(t, "probe.exr", &pimg);
    lg_image_free(&pimg);
    lg_image base = constant_image(40, 30, bc);
    lg_test_write_exr(t, "base.exr", &base);
    lg_image_free(&base);
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "s = test_ibl_scene { layout = sphere, segments = 32, "
                 "reflectivity = [0.5, 0.5, 0.5] }\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "env = environment { scene = s, probe = sky }\n"
                 "b = image { file = \"base.exr\" }\n"
                 "r = reflect { scene = env, probe = sky, base = b, backend = %s }\n"
                 "output r \"r.exr\"\n",
                 BACKENDS[b]);
        const char *args[] = { "--size", "40x30", NULL };
        const char *outs[] = { "r.exr" };
        lg_image img = { 0 };
        int rc = render(t, g, args, outs, &img, 1, NULL);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", BACKENDS[b], rc);
        if (rc)
            continue;
        uint64_t n_geo = 0, n_base = 0, other = 0;
        for (size_t i = 0; i < 1200; i++) {
            const float *v = img.pixels + 4 * i;
            bool is_base = v[0] == bc[0] && v[1] == bc[1] && v[2] == bc[2];
            bool is_geo = v[0] == bc[0] + 0.5f * c[0] && v[1] == bc[1] + 0.5f * c[1] &&
                          v[2] == bc[2] + 0.5f * c[2];
            n_base += is_base, n_geo += is_geo, other += !is_base && !is_geo;
        }
        LG_TEST_CHECK(t, other == 0 && n_geo > 50 && n_base > 50,
                      "%s: %llu pixels base + reflection, %llu base, %llu neither", BACKENDS[b],
                      (unsigned long long)n_geo, (unsigned long long)n_base,
                      (unsigned long long)other);
        lg_image_free(&img);
    }
    /* a base of another size is an error naming both sizes */
    const char *g = "lightgraph 1\n"
                    "s = test_ibl_scene { layout = sphere }\n"
                    "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                    "env = environment { scene = s, probe = sky }\n"
                    "b = image { file = \"base.exr\" }\n"
                    "r = reflect { scene = env, probe = sky, base = b, backend = cpu }\n"
                    "output r \"r.exr\"\n";
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "64x48", NULL };
    char *text = NULL;
    int rc = lg_test_render(t, "g.lgraph", args, &text);
    LG_TEST_CHECK(t,
                  rc != 0 && text && strstr(text, "40x30") && strstr(text, "64x48") &&
                      strstr(text, "'base'"),
                  "a base of another size: status %d:\n%s", rc, text ? text : "");
    free(text);
}

/* An rgbe8 base (seed 0 keeps its buffers in RGBE8 through the chain): background in rgbe8
 * and in rgba32f under the same reflect, on every backend. (a) A constant probe of powers of
 * two, which RGBE holds exactly: the two reflections are equal bit for bit (a decode that
 * misreads the bytes, or not at all, changes every pixel). (b) The smooth probe, not exact in
 * RGBE: the rgbe8-based reflection is within half a step of the base's shared exponent of
 * the rgba32f-based one (2^-8 of the pixel's largest channel), and where no geometry is it is
 * the decoded base itself; reflect's own output in rgbe8 too (the chain stays RGBE8). */
static void case_base_rgbe8(lg_test *t)
{
    const float c[3] = { 0.5f, 1.0f, 2.0f };
    lg_image pimg = constant_image(16, 8, c);
    lg_test_write_exr(t, "exact.exr", &pimg);
    lg_image_free(&pimg);
    smooth_latlong(&pimg, 64, 32);
    lg_test_write_exr(t, "smooth.exr", &pimg);
    lg_image_free(&pimg);
    static const char *const probes[] = { "exact.exr", "smooth.exr" };
    for (int p = 0; p < 2; p++)
        for (int b = 0; b < 3; b++) {
            char g[2048];
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_ibl_scene { layout = sphere, segments = 32, "
                     "reflectivity = [0.5, 0.25, 0.5] }\n"
                     "sky = probe { file = \"%s\", layout = latlong }\n"
                     "env = environment { scene = s, probe = sky }\n"
                     "b32 = background { scene = env, probe = sky, backend = %s }\n"
                     "b8 = background { scene = env, probe = sky, backend = %s, format = rgbe8 }\n"
                     "r32 = reflect { scene = env, probe = sky, base = b32, backend = %s, "
                     "fresnel = schlick }\n"
                     "r8 = reflect { scene = env, probe = sky, base = b8, backend = %s, "
                     "fresnel = schlick }\n"
                     "r88 = reflect { scene = env, probe = sky, base = b8, backend = %s, "
                     "fresnel = schlick, format = rgbe8 }\n"
                     "output r32 \"r32.exr\"\noutput r8 \"r8.exr\"\noutput r88 \"r88.exr\"\n"
                     "output b8 \"b8.exr\"\n",
                     probes[p], BACKENDS[b], BACKENDS[b], BACKENDS[b], BACKENDS[b], BACKENDS[b]);
            const char *args[] = { "--size", "40x30", NULL };
            const char *outs[] = { "r32.exr", "r8.exr", "r88.exr", "b8.exr" };
            lg_image img[4] = { { 0 } };
            int rc = render(t, g, args, outs, img, 4, NULL);
            LG_TEST_CHECK(t, rc == 0, "%s %s: render failed (%d)", probes[p], BACKENDS[b], rc);
            if (rc == 0) {
                uint64_t off = 0, off88 = 0, off_bg = 0, covered = 0;
                double worst = 0;
                for (uint32_t y = 0; y < 30; y++)
                    for (uint32_t x = 0; x < 40; x++) {
                        const float *a = px(&img[0], x, y), *v = px(&img[1], x, y);
                        const float *v88 = px(&img[2], x, y), *bg = px(&img[3], x, y);
                        bool geo = bg[0] == 0.0f && bg[1] == 0.0f && bg[2] == 0.0f;
                        covered += geo;
                        double mx = fmax(a[0], fmax(a[1], a[2]));
                        for (int ch = 0; ch < 4; ch++) {
                            double d = fabs((double)v[ch] - a[ch]);
                            worst = fmax(worst, d);
                            /* (a): exact; (b): the base's step, 2^-8 of its largest channel
                             * (at most the sum's) */
                            off += p == 0 ? v[ch] != a[ch] : !(d <= mx / 256.0 + 1e-7);
                            /* the rgbe8 output: one more step of its own */
                            off88 += ch < 3 && !(fabs((double)v88[ch] - v[ch]) <= mx / 128.0);
                            /* no geometry: the decoded base passes as it is */
                            off_bg += !geo && v[ch] != bg[ch];
                        }
                    }
                LG_TEST_CHECK(t, off == 0 && off88 == 0 && off_bg == 0,
                              "%s %s: %llu values of the rgbe8-based reflection off the "
                              "rgba32f-based one (worst %g), %llu of its rgbe8 output, %llu "
                              "background values not the decoded base",
                              probes[p], BACKENDS[b], (unsigned long long)off, worst,
                              (unsigned long long)off88, (unsigned long long)off_bg);
                LG_TEST_CHECK(t, covered > 100 && covered < 1100, "%s %s: %llu pixels covered",
                              probes[p], BACKENDS[b], (unsigned long long)covered);
                for (int k = 0; k < 4; k++)
                    CHECK_FINITE(t, &img[k], probes[p]);
            }
            for (int k = 0; k < 4; k++)
                lg_image_free(&img[k]);
        }
}

/* An rgbe8 base at the ends of RGBE's range: background in rgbe8 of the float_max probe, whose
 * FLT_MAX texels saturate to RGBE's largest value (about 1.7e38) and whose 0 texels encode
 * as exponent 0, under reflect (mirror, and rough) on every backend: no value non-finite,
 * and the saturated base decoded as it is where no geometry covers the pixel. */
static void case_base_rgbe8_extremes(lg_test *t)
{
    write_float_max_probes(t);
    for (int b = 0; b < 3; b++)
        for (int r = 0; r < 2; r++) {
            char g[2048];
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "s = test_ibl_scene { layout = sphere, segments = 32, "
                     "reflectivity = [1, 0.5, 0.04], roughness = %s }\n"
                     "sky = probe { file = \"probe_latlong.exr\", layout = latlong, "
                     "exposure = 2 }\n"
                     "env = environment { scene = s, probe = sky }\n"
                     "b8 = background { scene = env, probe = sky, backend = %s, format = rgbe8 }\n"
                     "r = reflect { scene = env, probe = sky, base = b8, backend = %s, "
                     "fresnel = schlick }\n"
                     "output r \"r.exr\"\n",
                     r ? "0.5" : "0", BACKENDS[b], BACKENDS[b]);
            const char *args[] = { "--size", "32x32", NULL };
            const char *outs[] = { "r.exr" };
            lg_image img = { 0 };
            char *text = NULL;
            int rc = render(t, g, args, outs, &img, 1, &text);
            LG_TEST_CHECK(t, rc == 0, "%s roughness %d: render failed (%d):\n%s", BACKENDS[b], r,
                          rc, text ? text : "");
            free(text);
            if (rc)
                continue;
            uint64_t bad = 0, saturated = 0;
            for (size_t i = 0; i < (size_t)img.width * img.height; i++)
                for (int c = 0; c < 4; c++) {
                    bad += !isfinite(img.pixels[4 * i + c]);
                    saturated += img.pixels[4 * i + c] >= 1.6e38f;
                }
            LG_TEST_CHECK(t, bad == 0 && saturated > 0,
                          "%s roughness %d: %llu non-finite values, %llu at RGBE's largest",
                          BACKENDS[b], r, (unsigned long long)bad, (unsigned long long)saturated);
            lg_image_free(&img);
        }
}

/* ---- textured materials ---------------------------------------------------------------------- */

/* Renders graph g at 48x36 and reads the outputs named in outs; false (after a failed check)
 * when the render fails. */
static bool render_tex(lg_test *t, const char *what, const char *g, const char *const *outs,
                       lg_image *imgs, int n)
{
    const char *args[] = { "--size", "48x36", NULL };
    char *text = NULL;
    int rc = render(t, g, args, outs, imgs, n, &text);
    LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d):\n%s", what, rc, text ? text : "");
    free(text);
    return rc == 0;
}

/* The quad's texture coordinates at pixel (x, y) of a 48x36 image seen by test_ibl_scene's
 * default camera (0, 0, 5) -> origin, 40 degrees: false where the ray misses the quad. */
static bool quad_uv(uint32_t x, uint32_t y, double *u, double *v)
{
    const cam c = { { 0, 0, 5 }, { 0, 0, 0 }, { 0, 1, 0 }, 40 };
    lg_vec3 d = cam_ray(&c, 48, 36, x, y);
    if (!(d.z < 0))
        return false;
    double s = -5.0 / d.z, px = s * d.x, py = s * d.y;
    *u = (px + 1) / 2;
    *v = (1 - py) / 2;
    return *u >= 0 && *u <= 1 && *v >= 0 && *v <= 1;
}

/* A metallic-roughness texture of two halves (G 255 and 64, roughness factor 1): the left
 * half's pixels are those of the quad at roughness 1, the right half's those at roughness
 * 64/255, on every backend (the G-buffer's roughness picks the GGX level per pixel); the
 * two levels differ, so a texture ignored fails. */
static void case_tex_roughness(lg_test *t)
{
    lg_image pimg;
    smooth_latlong(&pimg, 64, 32);
    lg_test_write_exr(t, "smooth.exr", &pimg);
    lg_image_free(&pimg);
    for (int b = 0; b < 3; b++) {
        char g[4096];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "sky = probe { file = \"smooth.exr\", layout = latlong }\n"
                 "tq = test_ibl_scene { layout = quad, texture = roughness_halves, roughness = 1, "
                 "reflectivity = [0.9, 0.9, 0.9] }\n"
                 "q1 = test_ibl_scene { layout = quad, roughness = 1, "
                 "reflectivity = [0.9, 0.9, 0.9] }\n"
                 "q2 = test_ibl_scene { layout = quad, roughness = %.9g, "
                 "reflectivity = [0.9, 0.9, 0.9] }\n"
                 "e0 = environment { scene = tq, probe = sky }\n"
                 "e1 = environment { scene = q1, probe = sky }\n"
                 "e2 = environment { scene = q2, probe = sky }\n"
                 "r0 = reflect { scene = e0, probe = sky, backend = %s, fresnel = schlick }\n"
                 "r1 = reflect { scene = e1, probe = sky, backend = %s, fresnel = schlick }\n"
                 "r2 = reflect { scene = e2, probe = sky, backend = %s, fresnel = schlick }\n"
                 "output r0 \"r0.exr\"\noutput r1 \"r1.exr\"\noutput r2 \"r2.exr\"\n",
                 64.0 / 255.0, BACKENDS[b], BACKENDS[b], BACKENDS[b]);
        const char *outs[] = { "r0.exr", "r1.exr", "r2.exr" };
        lg_image img[3] = { { 0 } };
        if (render_tex(t, BACKENDS[b], g, outs, img, 3)) {
            uint64_t left = 0, right = 0, off = 0;
            double differ = 0, worst = 0;
            for (uint32_t y = 0; y < 36; y++)
                for (uint32_t x = 0; x < 48; x++) {
                    double u, v;
                    if (!quad_uv(x, y, &u, &v) || u < 0.03 || u > 0.97 || v < 0.03 || v > 0.97 ||
                        fabs(u - 0.5) < 0.03)
                        continue;
                    const float *p = px(&img[0], x, y);
                    const float *w = px(&img[u < 0.5 ? 1 : 2], x, y);
                    left += u < 0.5, right += u >= 0.5;
                    for (int c = 0; c < 3; c++) {
                        double d = fabs((double)p[c] - w[c]);
                        worst = fmax(worst, d / (fabs(w[c]) + 1e-6));
                        off += !(d <= 1e-5 * fabs(w[c]) + 1e-6);
                        differ = fmax(differ,
                                      fabs((double)px(&img[1], x, y)[c] - px(&img[2], x, y)[c]));
                    }
                }
            LG_TEST_CHECK(t, off == 0 && left > 100 && right > 100,
                          "%s: %llu values off the untextured roughness's (worst %.3g relative); "
                          "%llu left, %llu right pixels",
                          BACKENDS[b], (unsigned long long)off, worst, (unsigned long long)left,
                          (unsigned long long)right);
            LG_TEST_CHECK(t, differ > 0.01, "%s: roughness 1 and 0.25 give the same image (%g)",
                          BACKENDS[b], differ);
            for (int k = 0; k < 3; k++)
                CHECK_FINITE(t, &img[k], BACKENDS[b]);
        }
        for (int k = 0; k < 3; k++)
            lg_image_free(&img[k]);
    }
}

/* A metal (metallic 1, base colour factor 1, reflectivity 1) with a base colour texture of
 * two halves, sRGB (255, 0, 0) and (0, 188, 255): under a constant probe c with fresnel none
 * each half reflects c x the decoded texel (F0 = mix(F0 dielectric, base colour, metallic)
 * per pixel), on every backend. */
static void case_tex_metal(lg_test *t)
{
    const float c[3] = { 1, 2, 4 };
    lg_image pimg = constant_image(16, 8, c);
    lg_test_write_exr(t, "probe.exr", &pimg);
    lg_image_free(&pimg);
    const double right[3] = { 0, lg_srgb_decode(188.0f / 255.0f), 1 };
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "s = test_ibl_scene { layout = quad, texture = metal_halves, metallic = 1, "
                 "reflectivity = [1, 1, 1] }\n"
                 "e = environment { scene = s, probe = sky }\n"
                 "r = reflect { scene = e, probe = sky, backend = %s }\n"
                 "output r \"r.exr\"\n",
                 BACKENDS[b]);
        const char *outs[] = { "r.exr" };
        lg_image img = { 0 };
        if (render_tex(t, BACKENDS[b], g, outs, &img, 1)) {
            uint64_t n = 0, off = 0;
            for (uint32_t y = 0; y < 36; y++)
                for (uint32_t x = 0; x < 48; x++) {
                    double u, v;
                    if (!quad_uv(x, y, &u, &v) || u < 0.03 || u > 0.97 || v < 0.03 || v > 0.97 ||
                        fabs(u - 0.5) < 0.03)
                        continue;
                    n++;
                    for (int ch = 0; ch < 3; ch++) {
                        double want = c[ch] * (u < 0.5 ? (ch == 0 ? 1.0 : 0.0) : right[ch]);
                        /* llvmpipe's sRGB decode: within 2e-3 of the texel */
                        off += !(fabs(px(&img, x, y)[ch] - want) <= 2e-3 * c[ch] + 1e-6);
                    }
                }
            LG_TEST_CHECK(t, off == 0 && n > 200, "%s: %llu of %llu pixels' values not c x texel",
                          BACKENDS[b], (unsigned long long)off, (unsigned long long)n);
        }
        lg_image_free(&img);
    }
}

/* An alpha-masked quad (MASK at 0.5, the top-left texel alpha 0) of reflectivity 0.5 under
 * a constant probe c: reflect over background shows c (the probe) through the hole and
 * 0.5 c on the quad; background alone shows c through the hole and 0 (its base) on the
 * quad, on every backend. */
static void case_tex_mask(lg_test *t)
{
    const float c[3] = { 1, 2, 4 };
    lg_image pimg = constant_image(16, 8, c);
    lg_test_write_exr(t, "probe.exr", &pimg);
    lg_image_free(&pimg);
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "s = test_ibl_scene { layout = quad, texture = mask_hole, "
                 "reflectivity = [0.5, 0.5, 0.5] }\n"
                 "e = environment { scene = s, probe = sky }\n"
                 "bg = background { scene = e, probe = sky, backend = %s }\n"
                 "r = reflect { scene = e, probe = sky, base = bg, backend = %s }\n"
                 "output r \"r.exr\"\noutput bg \"bg.exr\"\n",
                 BACKENDS[b], BACKENDS[b]);
        const char *outs[] = { "r.exr", "bg.exr" };
        lg_image img[2] = { { 0 } };
        if (render_tex(t, BACKENDS[b], g, outs, img, 2)) {
            uint64_t hole = 0, quad = 0, off = 0;
            for (uint32_t y = 0; y < 36; y++)
                for (uint32_t x = 0; x < 48; x++) {
                    double u, v;
                    if (!quad_uv(x, y, &u, &v) || u < 0.03 || u > 0.97 || v < 0.03 || v > 0.97 ||
                        fabs(u - 0.5) < 0.03 || fabs(v - 0.5) < 0.03)
                        continue;
                    bool in_hole = u < 0.5 && v < 0.5;
                    hole += in_hole, quad += !in_hole;
                    for (int ch = 0; ch < 3; ch++) {
                        double want_r = in_hole ? c[ch] : 0.5 * c[ch];
                        double want_bg = in_hole ? c[ch] : 0.0;
                        off += !(fabs(px(&img[0], x, y)[ch] - want_r) <= 1e-5 * c[ch]);
                        off += !(fabs(px(&img[1], x, y)[ch] - want_bg) <= 1e-5 * c[ch]);
                    }
                }
            LG_TEST_CHECK(t, off == 0 && hole > 50 && quad > 150,
                          "%s: %llu values off (%llu pixels in the hole, %llu on the quad)",
                          BACKENDS[b], (unsigned long long)off, (unsigned long long)hole,
                          (unsigned long long)quad);
        }
        for (int k = 0; k < 2; k++)
            lg_image_free(&img[k]);
    }
}

/* A normal texture on the flat quad facing +Z (tangent +X): envmap (the probe along N) of
 * every covered pixel equals that of an untextured quad whose normal is the texel's decoded
 * normal, normalize(2 texel / 255 - 1), and differs from the flat quad's, on every backend. */
static void case_tex_normal(lg_test *t)
{
    lg_image pimg;
    smooth_latlong(&pimg, 64, 32);
    lg_test_write_exr(t, "smooth.exr", &pimg);
    lg_image_free(&pimg);
    const int texel[3] = { 200, 100, 220 };
    double nrm[3], len = 0;
    for (int k = 0; k < 3; k++) {
        nrm[k] = 2.0 * texel[k] / 255.0 - 1.0;
        len += nrm[k] * nrm[k];
    }
    for (int k = 0; k < 3; k++)
        nrm[k] /= sqrt(len);
    for (int b = 0; b < 3; b++) {
        char g[4096];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "sky = probe { file = \"smooth.exr\", layout = latlong }\n"
                 "tq = test_ibl_scene { layout = quad, texture = normal_tilt, "
                 "normal_texel = [%d, %d, %d] }\n"
                 "tilt = test_ibl_scene { layout = quad, quad_normal = [%.9g, %.9g, %.9g] }\n"
                 "flat = test_ibl_scene { layout = quad }\n"
                 "e0 = environment { scene = tq, probe = sky }\n"
                 "e1 = environment { scene = tilt, probe = sky }\n"
                 "e2 = environment { scene = flat, probe = sky }\n"
                 "m0 = envmap { scene = e0, probe = sky, backend = %s }\n"
                 "m1 = envmap { scene = e1, probe = sky, backend = %s }\n"
                 "m2 = envmap { scene = e2, probe = sky, backend = %s }\n"
                 "output m0 \"m0.exr\"\noutput m1 \"m1.exr\"\noutput m2 \"m2.exr\"\n",
                 texel[0], texel[1], texel[2], nrm[0], nrm[1], nrm[2], BACKENDS[b], BACKENDS[b],
                 BACKENDS[b]);
        const char *outs[] = { "m0.exr", "m1.exr", "m2.exr" };
        lg_image img[3] = { { 0 } };
        if (render_tex(t, BACKENDS[b], g, outs, img, 3)) {
            /* the tilted quad covers other pixels: compare the values, each quad's mean over
             * its covered pixels (constant: one normal) */
            double mean[3][3] = { { 0 } }, dev = 0;
            uint64_t n[3] = { 0 };
            for (int k = 0; k < 3; k++)
                for (size_t i = 0; i < 48 * 36; i++) {
                    const float *p = img[k].pixels + 4 * i;
                    if (p[0] == 0 && p[1] == 0 && p[2] == 0)
                        continue;
                    n[k]++;
                    for (int ch = 0; ch < 3; ch++)
                        mean[k][ch] += p[ch];
                }
            for (int k = 0; k < 3; k++)
                for (int ch = 0; ch < 3; ch++)
                    mean[k][ch] /= n[k] ? (double)n[k] : 1.0;
            for (size_t i = 0; i < 48 * 36; i++) {
                const float *p = img[0].pixels + 4 * i;
                if (p[0] != 0 || p[1] != 0 || p[2] != 0)
                    for (int ch = 0; ch < 3; ch++)
                        dev = fmax(dev, fabs(p[ch] - mean[1][ch]) / mean[1][ch]);
            }
            double flat = 0;
            for (int ch = 0; ch < 3; ch++)
                flat = fmax(flat, fabs(mean[2][ch] - mean[1][ch]) / mean[1][ch]);
            LG_TEST_CHECK(t, n[0] > 200 && n[1] > 100 && dev < 2e-3,
                          "%s: the normal-mapped quad's envmap departs from the tilted quad's by "
                          "%.3g (relative; %llu and %llu pixels)",
                          BACKENDS[b], dev, (unsigned long long)n[0], (unsigned long long)n[1]);
            LG_TEST_CHECK(t, flat > 0.02, "%s: the tilt changes the envmap by only %.3g",
                          BACKENDS[b], flat);
        }
        for (int k = 0; k < 3; k++)
            lg_image_free(&img[k]);
    }
}

/* A base colour texture index out of range (7 of one texture) on a metal: read as no
 * texture, the image equal bit for bit to the untextured metal's, every backend. */
static void case_tex_bad_index(lg_test *t)
{
    const float c[3] = { 1, 2, 4 };
    lg_image pimg = constant_image(16, 8, c);
    lg_test_write_exr(t, "probe.exr", &pimg);
    lg_image_free(&pimg);
    for (int b = 0; b < 3; b++) {
        char g[2048];
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "s0 = test_ibl_scene { layout = quad, texture = bad_index, metallic = 1, "
                 "reflectivity = [1, 0.5, 0.25] }\n"
                 "s1 = test_ibl_scene { layout = quad, metallic = 1, "
                 "reflectivity = [1, 0.5, 0.25] }\n"
                 "e0 = environment { scene = s0, probe = sky }\n"
                 "e1 = environment { scene = s1, probe = sky }\n"
                 "r0 = reflect { scene = e0, probe = sky, backend = %s }\n"
                 "r1 = reflect { scene = e1, probe = sky, backend = %s }\n"
                 "output r0 \"r0.exr\"\noutput r1 \"r1.exr\"\n",
                 BACKENDS[b], BACKENDS[b]);
        const char *outs[] = { "r0.exr", "r1.exr" };
        lg_image img[2] = { { 0 } };
        if (render_tex(t, BACKENDS[b], g, outs, img, 2)) {
            uint64_t off = 0, covered = 0;
            for (size_t i = 0; i < 48 * 36 * 4; i++)
                off += img[0].pixels[i] != img[1].pixels[i];
            for (size_t i = 0; i < 48 * 36; i++)
                covered += img[1].pixels[4 * i] != 0;
            LG_TEST_CHECK(t, off == 0 && covered > 200,
                          "%s: %llu values differ from the untextured metal's (%llu covered)",
                          BACKENDS[b], (unsigned long long)off, (unsigned long long)covered);
            CHECK_FINITE(t, &img[0], BACKENDS[b]);
        }
        for (int k = 0; k < 2; k++)
            lg_image_free(&img[k]);
    }
}

/* Copies repository asset `rel` (under assets/) into the test folder as `name`, with each
 * pair of `edits` (from, to, ..., NULL) applied to its first occurrence (a text file; every
 * `from` must occur). */
static bool copy_asset(lg_test *t, const char *rel, const char *name, const char *const *edits)
{
    FILE *f = fopen(lg_test_asset(rel), "rb");
    if (!f)
        return false;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    bool ok = buf && n >= 0 && fread(buf, 1, (size_t)n, f) == (size_t)n;
    fclose(f);
    size_t len = ok ? (size_t)n : 0;
    for (size_t e = 0; ok && edits && edits[e]; e += 2) {
        buf[len] = 0;
        char *at = strstr(buf, edits[e]);
        size_t lf = strlen(edits[e]), lt = strlen(edits[e + 1]);
        char *nb = at ? malloc(len - lf + lt + 1) : NULL;
        ok = nb != NULL;
        if (ok) {
            size_t pre = (size_t)(at - buf);
            memcpy(nb, buf, pre);
            memcpy(nb + pre, edits[e + 1], lt);
            memcpy(nb + pre + lt, at + lf, len - pre - lf);
            len = len - lf + lt;
            free(buf);
            buf = nb;
        }
    }
    FILE *o = ok ? fopen(lg_test_path(t, name), "wb") : NULL;
    if (o) {
        ok = fwrite(buf, 1, len, o) == len;
        ok = fclose(o) == 0 && ok;
    } else {
        ok = false;
    }
    free(buf);
    return ok;
}

/* The Duck (assets/meshes/duck, its base colour texture DuckCM.png) made a metal (metallic
 * 1, roughness 0: a mirror, in a copy of its .gltf) and reflect (Schlick) over the background under
 * the forest probe, on every backend: the backends agree (1 % + 1e-3 per value, RMSE 2e-3),
 * and the textured metal's reflection is the untextured metal's tinted by the yellow texture
 * (its texture removed in a second copy): over the covered pixels blue keeps under a third of
 * what red keeps. duck_*.png in the test folder are the pictures. */
static void case_duck(lg_test *t)
{
    static const char *const metal[] = { "\"metallicFactor\": 0.0",
                                         "\"metallicFactor\": 1.0, \"roughnessFactor\": 0.0",
                                         NULL };
    /* the same without its texture (a key glTF does not know, which the loader ignores) */
    static const char *const plain[] = { "\"metallicFactor\": 0.0",
                                         "\"metallicFactor\": 1.0, \"roughnessFactor\": 0.0",
                                         "\"baseColorTexture\"", "\"unusedTexture\"", NULL };
    bool ok = copy_asset(t, "meshes/duck/Duck0.bin", "Duck0.bin", NULL) &&
              copy_asset(t, "meshes/duck/DuckCM.png", "DuckCM.png", NULL) &&
              copy_asset(t, "meshes/duck/Duck.gltf", "duck_metal.gltf", metal) &&
              copy_asset(t, "meshes/duck/Duck.gltf", "duck_plain.gltf", plain);
    LG_TEST_CHECK(t, ok, "the Duck's files could not be copied and edited");
    if (!ok)
        return;
    lg_image img[2][3] = { { { 0 } } };
    for (int v = 0; v < 2; v++)
        for (int b = 0; b < 3; b++) {
            char g[2048];
            snprintf(g, sizeof g,
                     "lightgraph 1\n"
                     "scene = gltf { file = \"%s\" }\n"
                     "sky = probe { file = \"%s\" }\n"
                     "env = environment { scene = scene, probe = sky }\n"
                     "bg = background { scene = env, probe = sky, backend = %s }\n"
                     "r = reflect { scene = env, probe = sky, base = bg, backend = %s, "
                     "fresnel = schlick }\n"
                     "tone = reinhard { image = r }\n"
                     "output r \"r.exr\"\noutput tone \"duck_%s_%s.png\"\n",
                     v ? "duck_plain.gltf" : "duck_metal.gltf",
                     lg_test_asset("probes/forest_1024x512.hdr"), BACKENDS[b], BACKENDS[b],
                     v ? "plain" : "textured", BACKENDS[b]);
            const char *args[] = { "--size", "96x72", NULL };
            const char *outs[] = { "r.exr" };
            char *text = NULL;
            int rc = render(t, g, args, outs, &img[v][b], 1, &text);
            LG_TEST_CHECK(t, rc == 0, "duck %d %s: render failed (%d):\n%s", v, BACKENDS[b], rc,
                          text ? text : "");
            free(text);
        }
    for (int v = 0; v < 2; v++)
        for (int b = 1; b < 3; b++) {
            if (!img[v][0].pixels || !img[v][b].pixels)
                continue;
            double worst = 0, se = 0;
            size_t np = (size_t)96 * 72, bad = 0;
            for (size_t i = 0; i < np * 4; i++) {
                double d = fabs((double)img[v][b].pixels[i] - img[v][0].pixels[i]);
                worst = fmax(worst, d);
                se += d * d;
                bad += !(d <= 0.01 * fabs(img[v][0].pixels[i]) + 1e-3);
            }
            double rmse = sqrt(se / (double)(np * 4));
            lg_test_note_("duck %s: %s against cpu: max %.3g, RMSE %.3g", v ? "plain" : "textured",
                          BACKENDS[b], worst, rmse);
            /* llvmpipe's cube filter and sRGB decode: a few texels at edges differ more */
            LG_TEST_CHECK(t, bad < np / 100 && rmse < 2e-3,
                          "duck %s: %s differs from cpu: %zu values beyond 1 %% + 1e-3, RMSE %.3g",
                          v ? "plain" : "textured", BACKENDS[b], bad, rmse);
        }
    for (int b = 0; b < 3; b++) {
        if (!img[0][b].pixels || !img[1][b].pixels)
            continue;
        /* the covered pixels: where the two renders differ from the background; compare the
         * reflections' channels: textured / plain per channel */
        double sum[2][3] = { { 0 } };
        size_t n = 0;
        for (size_t i = 0; i < (size_t)96 * 72; i++) {
            const float *a = img[0][b].pixels + 4 * i, *p = img[1][b].pixels + 4 * i;
            if (a[0] == p[0] && a[1] == p[1] && a[2] == p[2])
                continue; /* the background: the same in both */
            n++;
            for (int c = 0; c < 3; c++)
                sum[0][c] += a[c], sum[1][c] += p[c];
        }
        double kr = sum[0][0] / sum[1][0], kb = sum[0][2] / sum[1][2];
        lg_test_note_("duck %s: %zu covered pixels, textured / plain red %.3f, blue %.3f",
                      BACKENDS[b], n, kr, kb);
        LG_TEST_CHECK(t, n > 200 && kr > 0.3 && kb < kr / 3,
                      "%s: the texture does not tint the reflection (red kept %.3f, blue %.3f, "
                      "%zu pixels)",
                      BACKENDS[b], kr, kb, n);
    }
    for (int v = 0; v < 2; v++)
        for (int b = 0; b < 3; b++)
            lg_image_free(&img[v][b]);
}

/* ---- gating ---------------------------------------------------------------------------------- */

static void case_gating(lg_test *t)
{
    const float c[3] = { 1, 1, 1 };
    lg_image pimg = constant_image(16, 8, c);
    lg_test_write_exr(t, "probe.exr", &pimg);
    lg_image_free(&pimg);
    struct {
        const char *scene, *why;
    } cases[] = {
        { "s = test_ibl_scene { layout = sphere, reflectivity = [0, 0, 0] }\n"
          "env = environment { scene = s, probe = sky }\n",
          "no reflective material" },
        { "s = test_ibl_scene { layout = sphere }\nenv = s\n", "no light probe" },
    };
    for (int k = 0; k < 2; k++) {
        char g[2048];
        /* "env = s" is not a graph statement: the second case names the scene directly */
        const char *scene = cases[k].scene;
        char sc[512];
        snprintf(sc, sizeof sc, "%s", scene);
        char *alias = strstr(sc, "env = s\n");
        if (alias)
            *alias = 0;
        snprintf(g, sizeof g,
                 "lightgraph 1\n"
                 "sky = probe { file = \"probe.exr\", layout = latlong }\n"
                 "%s"
                 "r = reflect { scene = %s, probe = sky }\n"
                 "e = envmap { scene = %s, probe = sky }\n"
                 "output r \"r.exr\"\noutput e \"e.exr\"\n",
                 sc, alias ? "s" : "env", alias ? "s" : "env");
        const char *args[] = { "--size", "16x16", "--explain", "-v", NULL };
        const char *outs[] = { "r.exr", "e.exr" };
        lg_image img[2] = { { 0 } };
        char *text = NULL;
        int rc = render(t, g, args, outs, img, 2, &text);
        LG_TEST_CHECK(t, rc == 0, "%s: render failed (%d)", cases[k].why, rc);
        if (rc == 0) {
            for (int i = 0; i < 2; i++) {
                const char *row = strstr(text, i == 0 ? "\n  r " : "\n  e ");
                const char *eol = row ? strchr(row + 1, '\n') : NULL;
                const char *gated = row ? strstr(row, "gated") : NULL;
                const char *why = row ? strstr(row, cases[k].why) : NULL;
                LG_TEST_CHECK(t, row && eol && gated && gated < eol && why && why < eol,
                              "%s: node %s is not reported gated with the reason:\n%s",
                              cases[k].why, i == 0 ? "r" : "e", text);
                /* neutral: no base, so zero */
                double sum = 0;
                for (size_t p = 0; p < (size_t)img[i].width * img[i].height * 4; p++)
                    sum += fabs(img[i].pixels[p]);
                LG_TEST_CHECK(t, sum == 0, "%s: the gated output is not zero", cases[k].why);
            }
            const char *nl = strstr(text, "plugins not loaded:");
            const char *eol = nl ? strchr(nl, '\n') : NULL;
            const char *ibl = nl ? strstr(nl, "ibl") : NULL;
            LG_TEST_CHECK(t, nl && ibl && (!eol || ibl < eol), "%s: the ibl plugin was loaded:\n%s",
                          cases[k].why, text);
        }
        for (int i = 0; i < 2; i++)
            lg_image_free(&img[i]);
        free(text);
    }
}

/* "; cached" at the end of the chain's line only when the host stored it (ABI 2.7). */
static void case_cache_said(lg_test *t)
{
    lg_image probe = { 0 };
    smooth_latlong(&probe, 32, 16);
    lg_test_write_exr(t, "probe.exr", &probe);
    lg_image_free(&probe);
    const cam cm = { { 0, 0, 4 }, { 0, 0, 0 }, { 0, 1, 0 }, 35 };
    char cp[512], g[2048];
    cam_params(cp, sizeof cp, &cm);
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_ibl_scene { layout = sphere, segments = 16, roughness = 0.5, "
             "reflectivity = [0.9, 0.9, 0.9], %s }\n"
             "sky = probe { file = \"probe.exr\", layout = latlong }\n"
             "env = environment { scene = s, probe = sky }\n"
             "r = reflect { scene = env, probe = sky, backend = cpu, prefilter_size = 8, "
             "prefilter_samples = 8 }\n"
             "output r \"r.exr\"\n",
             cp);
    const char *args[] = { "--size", "16x16", "-v", NULL };
    const char *outs[] = { "r.exr" };
    const char *dir = getenv("LIGHTGRAPH_CACHE_DIR"); /* the case's own (setup) */
    LG_TEST_CHECK(t, dir && mkdir(dir, 0700) == 0 && chmod(dir, 0777) == 0,
                  "cannot make the cache folder %s 0777", dir ? dir : "(unset)");
    for (int k = 0; k < 2; k++) {
        if (k == 1)
            LG_TEST_CHECK(t, chmod(dir, 0700) == 0, "chmod %s", dir);
        lg_image img = { 0 };
        char *text = NULL;
        int rc = render(t, g, args, outs, &img, 1, &text);
        const char *o = text ? text : "";
        LG_TEST_CHECK(t, rc == 0, "render failed (%d):\n%s", rc, o);
        const char *line = strstr(o, "GGX chain prefiltered");
        LG_TEST_CHECK(t, line != NULL, "no chain was made:\n%s", o);
        if (line && k == 0)
            LG_TEST_CHECK(t,
                          strstr(line, "not cached: the cache is disabled for this render") &&
                              !strstr(line, "; cached"),
                          "the cache off:\n%s", o);
        if (line && k == 1)
            LG_TEST_CHECK(t, strstr(line, "; cached") && !strstr(line, "not cached"),
                          "a usable cache:\n%s", o);
        if (img.pixels)
            lg_image_free(&img);
        free(text);
    }
}

/* testiblscene's folder, and an empty cache per case */
static void case_chain_limits(lg_test *t)
{
    const float c[3] = { 0.5f, 1.0f, 2.0f };
    lg_image one = constant_image(1, 1, c);
    lg_test_write_exr(t, "one.exr", &one);
    lg_image_free(&one);
    const char *g = "lightgraph 1\n"
                    "s = test_ibl_scene { layout = sphere, segments = 16, roughness = 0.5, "
                    "reflectivity = [0.5, 0.5, 0.5] }\n"
                    "sky = probe { file = \"%s\", layout = latlong }\n"
                    "env = environment { scene = s, probe = sky }\n"
                    "r = reflect { scene = env, probe = sky, backend = cpu%s }\n"
                    "output r \"r.exr\"\n";
    char text[1024];
    snprintf(text, sizeof text, g, "one.exr", ", prefilter_size = 4096, levels = 16");
    const char *args[] = { "--size", "16x16", NULL };
    const char *outs[] = { "r.exr" };
    lg_image img = { 0 };
    char *out = NULL;
    int rc = render(t, text, args, outs, &img, 1, &out);
    LG_TEST_CHECK(t,
                  rc == 0 && out &&
                      strstr(out, "warning: node 'r' (reflect): prefilter_size = "
                                  "4096 is finer than the 1x1 probe can fill: "
                                  "the chain is made at 8 per face") &&
                      strstr(out, "levels = 16: a chain of face 8 has 4 levels, so it has 4"),
                  "a 4096 chain of a 1x1 probe: exit %d\n%s", rc, out ? out : "");
    free(out);
    /* every pixel: 0 where no geometry, the sphere's 0.5 c where covered (a constant chain
     * at any size: test `constant`) */
    uint32_t bad = 0, covered = 0;
    for (uint32_t y = 0; rc == 0 && y < img.height; y++)
        for (uint32_t x = 0; x < img.width; x++) {
            const float *p = px(&img, x, y);
            bool none = p[0] == 0.0f && p[2] == 0.0f;
            bool sphere = fabsf(p[0] - 0.5f * c[0]) < 1e-4f && fabsf(p[2] - 0.5f * c[2]) < 1e-4f;
            bad += !none && !sphere;
            covered += sphere;
        }
    LG_TEST_CHECK(t, rc == 0 && bad == 0 && covered > 0,
                  "%u pixels neither empty nor the sphere's 0.5 c, %u covered", bad, covered);
    lg_image_free(&img);

#ifdef __SANITIZE_ADDRESS__
    /* AddressSanitizer reserves terabytes of address space for its shadow at start-up: the
     * host cannot start under a 100 MiB RLIMIT_AS. The normal build runs this part. */
    printf("AddressSanitizer build: the RLIMIT_AS part is not run\n");
    return;
#endif
    lg_image big = constant_image(2048, 1024, c);
    lg_test_write_exr(t, "big.exr", &big);
    lg_image_free(&big);
    snprintf(text, sizeof text, g, "big.exr", "");
    lg_test_write_text(t, "g.lgraph", text);
    remove(lg_test_path(t, "r.exr")); /* the first render's */
    struct rlimit rl = { 100u << 20, 100u << 20 };
    LG_TEST_CHECK(t, setrlimit(RLIMIT_AS, &rl) == 0, "setrlimit(RLIMIT_AS, 100 MiB) failed");
    out = NULL;
    rc = lg_test_render(t, "g.lgraph", args, &out);
    LG_TEST_CHECK(t,
                  rc == 1 && out &&
                      strstr(out, "node 'r' (reflect): the GGX chain "
                                  "(prefilter_size = 0: cube 128, 6 levels, "
                                  "prefilter_samples = 256) from the 2048x1024 "
                                  "probe needs 94.4 MiB (98989056 bytes; "
                                  "resampling the probe into its first level "
                                  "89.5 MiB), more than the") &&
                      strstr(out, "of address space that the process's limit (RLIMIT_AS, "
                                  "ulimit -v) leaves"),
                  "a 2048x1024 probe's chain under 100 MiB: exit %d\n%s", rc, out ? out : "");
    free(out);
    struct stat sb;
    LG_TEST_CHECK(t, stat(lg_test_path(t, "r.exr"), &sb) != 0, "r.exr was written");
}

static void setup(lg_test *t)
{
    lg_test_use_plugins(t, IBL_TEST_PLUGIN_DIR);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {
        { "constant", case_constant },
        { "constant_rgbe8", case_constant_rgbe8 },
        { "bright_texel", case_bright_texel },
        { "backends", case_backends },
        { "axes", case_axes },
        { "rotation", case_rotation },
        { "grazing", case_grazing },
        { "backface", case_backface },
        { "half_clamp", case_half_clamp },
        { "base", case_base },
        { "base_rgbe8", case_base_rgbe8 },
        { "base_rgbe8_extremes", case_base_rgbe8_extremes },
        { "tex_roughness", case_tex_roughness },
        { "tex_metal", case_tex_metal },
        { "tex_mask", case_tex_mask },
        { "tex_normal", case_tex_normal },
        { "tex_bad_index", case_tex_bad_index },
        { "duck", case_duck },
        { "glossy", case_glossy },
        { "glossy_backends", case_glossy_backends },
        { "cache_said", case_cache_said },
        { "gating", case_gating },
        { "chain_limits", case_chain_limits },
        { "float_max", case_float_max },
        { "forged_chain", case_forged_chain },
    };
    lg_test_main_opts o = { .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
