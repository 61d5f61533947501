/*
 * Scene textures on GL (lg_scene_texture_gl, lg_gl_pass_bind_material, material.glsl)
 * through the preview node, on the textured quads of texscene.h (a quad filling a square
 * output: pixel (x, y)'s centre has uv = (x + 0.5) / W, (y + 0.5) / W in layouts with uv
 * 0..1). The test builds the same scene in memory and samples it on the CPU with
 * lg_scene_texture_sample, the reference. `test_texgl CASE`:
 *
 *   texel      checker, nearest (the texture's glTF NEAREST filters): every pixel encoded
 *              back to sRGB bytes is its texel's bytes exactly (the "texel read
 *              back exactly"), each of the 64 texels is seen, and the linear values agree
 *              with lg_scene_texture_sample within 2e-3 (llvmpipe decodes sRGB with an
 *              approximation: 1.2e-3 measured)
 *   bilinear   random, filter = bilinear, 64x64: GL's bilinear level 0 agrees with the
 *              CPU sampler at each pixel centre within 4e-3 (GL filters with 8-bit
 *              fixed-point weights); a shift of the CPU's coordinates by a quarter texel
 *              disagrees (the comparison can fail)
 *   wrap       uv -1..2 through REPEAT, CLAMP_TO_EDGE and MIRRORED_REPEAT (NEAREST): each
 *              equals the CPU's wrap within 2e-3 (the sRGB decode, as in texel; a wrong
 *              texel is off by far more), and the three pictures differ
 *   mip        a one-texel checker minified 4x: trilinear (and the file's default) gives
 *              the mean 0.5 within 0.05 everywhere; nearest gives 0 or 1 in every pixel
 *   mask       alpha MASK 0.5 on a checker whose odd texels have alpha 0: those pixels
 *              show the background, the others their texel, in base_color and normals
 *              modes alike; BLEND with alpha 0.3 / 0.7 is drawn as a mask at 0.5
 *   shadow     shadowmap's atlas under a light along -Z: the opaque checker quad casts a
 *              full square; its masked twin casts half of it, on one parity of the 8 x 8
 *              cells only (the shadow has holes where the texels are transparent)
 *   phong_texel  the checker through phong (kd 1, Od 1, ks 0, a light along -Z): every
 *              pixel is its texel's sRGB bytes in all five shading modes; the masked
 *              checker has its holes
 *   phong_normal a constant tilted normal texel shades as the tilted normal (phong), lit
 *              from straight ahead and from 45 degrees (the tilt's sign); gouraud lights
 *              the vertex normals (no normal map)
 *   degenerate a texture index past the scene's reads as no texture; a normal texture over
 *              tangents without a direction leaves the interpolated normal (stability)
 *   blinds_agree  the masked quad's shafts: volumetric_froxel (shadow map) and
 *              volumetric_reference (Embree's mask filter) agree; the opaque quad does not
 *   froxel     a masked quad's shadow reaches volumetric_froxel through the shadow map:
 *              fog lit from behind the quad shows shafts through its transparent texels
 *              (and none behind the opaque quad)
 *   profile    texture memory counts in --profile against the node: every mip level's bytes
 *   assets DIR the Duck and the milk truck (DIR: assets/meshes) through preview and phong:
 *              the Duck's pixels are its texture's yellow, the truck shows its logo
 *   wireframe  wireframe = 3 in green: pixels on the quad's diagonal turn green, pixels
 *              8 or more pixels from every edge keep their texel exactly
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/test.h"

#include "texscene.h"

#ifndef TX_TEST_PLUGIN_DIR
#define TX_TEST_PLUGIN_DIR ""
#endif

static const float BG[3] = { 1.0f, 0.0f, 1.0f };

/* Renders preview of test_tex_scene { scene } with { view } at size x size into img. */
static bool render(lg_test *t, const char *scene, const char *view, uint32_t size, lg_image *img)
{
    char g[2048], sz[32];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_tex_scene { %s }\n"
             "view = preview { scene = s, background = [1, 0, 1]%s%s }\n"
             "output view \"out.exr\"\n",
             scene, *view ? ", " : "", view);
    lg_test_write_text(t, "g.lgraph", g);
    snprintf(sz, sizeof sz, "%ux%u", size, size);
    const char *args[] = { "--size", sz, NULL };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "render of {%s} {%s} failed (%d)", scene, view, rc);
    if (rc)
        return false;
    bool ok = lg_test_read(t, "out.exr", img, NULL);
    LG_TEST_CHECK(t, ok, "out.exr unreadable");
    return ok && img->width == size && img->height == size;
}

static const float *px(const lg_image *img, uint32_t x, uint32_t y)
{
    return img->pixels + ((size_t)y * img->width + x) * 4;
}

/* The CPU's colour at pixel (x, y) of a size x size render of scene t (uv u0..u1), the
 * coordinates shifted by `shift` texels. */
static void cpu_at(const tx_scene *t, uint32_t x, uint32_t y, uint32_t size, float u0, float u1,
                   float shift, float out[4])
{
    float uv[2] = { u0 + (x + 0.5f) / size * (u1 - u0), u0 + (y + 0.5f) / size * (u1 - u0) };
    uv[0] += shift / (float)t->image.width;
    lg_scene_texture_sample(&t->s, &t->maps.base_color, uv, true, out);
}

/* Largest |GL - CPU| over the image's RGB. */
static double max_diff(const lg_image *img, const tx_scene *t, float u0, float u1, float shift)
{
    double m = 0;
    for (uint32_t y = 0; y < img->height; y++)
        for (uint32_t x = 0; x < img->width; x++) {
            float c[4];
            cpu_at(t, x, y, img->width, u0, u1, shift, c);
            for (int k = 0; k < 3; k++)
                m = fmax(m, fabs(px(img, x, y)[k] - c[k]));
        }
    return m;
}

/* A linear value encoded to sRGB and rounded to 8 bits: the texel byte it decodes from. */
static int srgb_byte(float lin)
{
    double s = lin <= 0.0031308 ? 12.92 * lin : 1.055 * pow(lin, 1 / 2.4) - 0.055;
    return (int)lround(fmin(fmax(s, 0.0), 1.0) * 255.0);
}

static void case_texel(lg_test *t)
{
    lg_image img = { 0 };
    if (!render(t, "layout = checker", "", 64, &img))
        return;
    tx_scene *s = tx_make(TX_CHECKER, 0);
    double d = max_diff(&img, s, 0, 1, 0);
    /* every pixel re-encoded to sRGB is its texel's bytes exactly */
    int wrong = 0, seen = 0;
    for (uint32_t y = 0; y < 64; y++)
        for (uint32_t x = 0; x < 64; x++) {
            const uint8_t *p = s->pixels + ((y / 8) * 8 + x / 8) * 4;
            bool ok = true;
            for (int k = 0; k < 3; k++)
                ok = ok && srgb_byte(px(&img, x, y)[k]) == p[k];
            wrong += !ok;
            seen += ok && x % 8 == 4 && y % 8 == 4;
        }
    fprintf(stderr,
            "checker through preview: %d of 4096 pixels not their texel's bytes; %d of 64 "
            "texels read back; largest difference from the CPU's decode %.3g\n",
            wrong, seen, d);
    LG_TEST_CHECK(t, wrong == 0, "%d pixels are not their texel's sRGB bytes", wrong);
    LG_TEST_CHECK(t, seen == 64, "%d of 64 texels read back", seen);
    /* GL's sRGB decode is the driver's (llvmpipe approximates it): within a third of a step */
    LG_TEST_CHECK(t, d <= 2e-3, "a pixel differs from the CPU's decoded texel by %g", d);
    tx_free(s);
    lg_image_free(&img);
}

static void case_bilinear(lg_test *t)
{
    lg_image img = { 0 };
    if (!render(t, "layout = random", "filter = bilinear", 64, &img))
        return;
    tx_scene *s = tx_make(TX_RANDOM, 0);
    double d = max_diff(&img, s, 0, 1, 0), off = max_diff(&img, s, 0, 1, 0.25f);
    fprintf(stderr, "bilinear: GL vs lg_scene_texture_sample %.3g (a quarter texel off: %.3g)\n", d,
            off);
    LG_TEST_CHECK(t, d <= 4e-3, "GL's bilinear differs from the CPU's by %g", d);
    LG_TEST_CHECK(t, off > 0.02, "a quarter-texel shift is not seen (%g)", off);
    tx_free(s);
    lg_image_free(&img);
}

static void case_wrap(lg_test *t)
{
    lg_image img[3] = { { 0 } };
    for (int w = 0; w < 3; w++) {
        char sp[64];
        snprintf(sp, sizeof sp, "layout = wrap, wrap = %d", w);
        if (!render(t, sp, "", 48, &img[w]))
            return;
        tx_scene *s = tx_make(TX_WRAP, w);
        double d = max_diff(&img[w], s, -1, 2, 0);
        fprintf(stderr, "wrap %d: GL vs CPU %.3g\n", w, d);
        LG_TEST_CHECK(t, d <= 2e-3, "wrap %d: GL differs from the CPU by %g", w, d);
        tx_free(s);
    }
    for (int a = 0; a < 3; a++) {
        int b = (a + 1) % 3;
        size_t diff = 0;
        for (size_t i = 0; i < (size_t)48 * 48 * 4; i++)
            diff += img[a].pixels[i] != img[b].pixels[i];
        LG_TEST_CHECK(t, diff > 100, "wraps %d and %d give the same picture", a, b);
    }
    for (int w = 0; w < 3; w++)
        lg_image_free(&img[w]);
}

static void case_mip(lg_test *t)
{
    static const char *const views[] = { "filter = trilinear", "", "filter = nearest" };
    for (int v = 0; v < 3; v++) {
        lg_image img = { 0 };
        if (!render(t, "layout = mip", views[v], 16, &img))
            return;
        double lo = 1, hi = 0;
        size_t binary = 0;
        for (uint32_t y = 0; y < 16; y++)
            for (uint32_t x = 0; x < 16; x++) {
                float g = px(&img, x, y)[1];
                lo = fmin(lo, g), hi = fmax(hi, g);
                binary += g == 0.0f || g == 1.0f;
            }
        fprintf(stderr, "mip {%s}: green in [%.4f, %.4f], %zu of 256 pixels 0 or 1\n", views[v], lo,
                hi, binary);
        if (v < 2)
            LG_TEST_CHECK(t, lo >= 0.45 && hi <= 0.55, "{%s}: [%g, %g], not the mean 0.5", views[v],
                          lo, hi);
        else
            LG_TEST_CHECK(t, binary == 256, "nearest: %zu of 256 pixels are texels", binary);
        lg_image_free(&img);
    }
}

static void case_mask(lg_test *t)
{
    /* MASK (cutoff 0.5, alpha 0 / 1) in both modes; BLEND (alpha 0.3 / 0.7) drawn as a
     * mask at one half */
    static const char *const runs[3][2] = { { "layout = mask", "" },
                                            { "layout = mask", "mode = normals" },
                                            { "layout = blend", "" } };
    for (int r = 0; r < 3; r++) {
        lg_image img = { 0 };
        if (!render(t, runs[r][0], runs[r][1], 64, &img))
            break;
        int holes = 0, solid = 0;
        for (int j = 0; j < 8; j++)
            for (int i = 0; i < 8; i++) {
                const float *p = px(&img, 8 * i + 4, 8 * j + 4);
                bool bg = p[0] == BG[0] && p[1] == BG[1] && p[2] == BG[2];
                if ((i + j) % 2)
                    holes += bg;
                else
                    solid += !bg;
            }
        fprintf(stderr, "{%s} {%s}: %d of 32 holes, %d of 32 solid texels\n", runs[r][0],
                runs[r][1], holes, solid);
        LG_TEST_CHECK(t, holes == 32 && solid == 32, "{%s} {%s}: %d holes, %d solid (32 each)",
                      runs[r][0], runs[r][1], holes, solid);
        lg_image_free(&img);
    }
}

static void case_wireframe(lg_test *t)
{
    lg_image plain = { 0 }, wire = { 0 };
    if (!render(t, "layout = checker", "", 64, &plain) ||
        !render(t, "layout = checker", "wireframe = 3, wire_color = [0, 1, 0]", 64, &wire))
        return;
    int green = 0, kept = 0, far = 0;
    for (uint32_t y = 0; y < 64; y++)
        for (uint32_t x = 0; x < 64; x++) {
            const float *w = px(&wire, x, y), *p = px(&plain, x, y);
            if (x == y)
                green += w[1] > 0.9f && w[0] < 0.1f && w[2] < 0.1f;
            /* distance to the diagonal and to the quad's border */
            double dd = fabs((double)x - y) / sqrt(2.0);
            double db = fmin(fmin(x + 0.5, 63.5 - x), fmin(y + 0.5, 63.5 - y));
            if (dd >= 8 && db >= 8) {
                far++;
                kept += memcmp(w, p, 4 * sizeof(float)) == 0;
            }
        }
    fprintf(stderr, "wireframe: %d of 64 diagonal pixels green, %d of %d far pixels kept\n", green,
            kept, far);
    LG_TEST_CHECK(t, green >= 60, "%d of 64 diagonal pixels are the line's colour", green);
    LG_TEST_CHECK(t, far > 1000 && kept == far, "%d of %d pixels away from edges changed",
                  far - kept, far);
    lg_image_free(&plain);
    lg_image_free(&wire);
}

/* The shadow map's atlas of the checker quad (mask: odd texels transparent) under a light
 * travelling along -Z, 128 x 128. */
static bool shadow_atlas(lg_test *t, const char *layout, lg_image *a)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_tex_scene { layout = %s }\n"
             "l = light { scene = s, direction = [0, 0, -1] }\n"
             "sh = shadowmap { scene = l, resolution = 128, cull = none }\n"
             "output sh.atlas \"sm.exr\"\n",
             layout);
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "16x16", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "shadow map render of %s failed (%d)", layout, rc);
    bool ok = !rc && lg_test_read(t, "sm.exr", a, NULL);
    LG_TEST_CHECK(t, ok || rc, "sm.exr unreadable");
    return ok && a->width == 128 && a->height == 128;
}

static void case_shadow(lg_test *t)
{
    lg_image full = { 0 }, masked = { 0 };
    if (!shadow_atlas(t, "checker", &full) || !shadow_atlas(t, "mask", &masked))
        return;
    /* the opaque quad's extent in the tile */
    uint32_t x0 = 128, y0 = 128, x1 = 0, y1 = 0, nfull = 0, nmask = 0;
    for (uint32_t y = 0; y < 128; y++)
        for (uint32_t x = 0; x < 128; x++) {
            nmask += px(&masked, x, y)[0] < 1.0f;
            if (px(&full, x, y)[0] < 1.0f) {
                nfull++;
                x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
                y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
            }
        }
    LG_TEST_CHECK(t, nfull > 0 && x1 > x0 + 16 && y1 > y0 + 16, "the opaque quad casts %u texels",
                  nfull);
    if (!(x1 > x0 + 16 && y1 > y0 + 16))
        return;
    /* cell centres of the 8 x 8 texels: drawn on one parity of (i + j) only (which one
     * depends on how the light's view is turned; the checker is the same either way up) */
    int parity[2] = { 0, 0 };
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 8; i++) {
            uint32_t x = x0 + (uint32_t)((i + 0.5) / 8 * (x1 + 1 - x0));
            uint32_t y = y0 + (uint32_t)((j + 0.5) / 8 * (y1 + 1 - y0));
            if (px(&masked, x, y)[0] < 1.0f)
                parity[(i + j) % 2]++;
        }
    fprintf(stderr,
            "shadow: opaque quad %u texels, masked %u (%.3f); cells drawn by parity %d / %d\n",
            nfull, nmask, (double)nmask / nfull, parity[0], parity[1]);
    LG_TEST_CHECK(t, (parity[0] == 32 && parity[1] == 0) || (parity[0] == 0 && parity[1] == 32),
                  "the masked quad's shadow is not a checker: cells %d / %d", parity[0], parity[1]);
    LG_TEST_CHECK(t, fabs((double)nmask / nfull - 0.5) < 0.05,
                  "the masked quad casts %u of %u texels, not half", nmask, nfull);
    lg_image_free(&full);
    lg_image_free(&masked);
}

/* phong { scene = light { test_tex_scene { layout } along `dir` }, ambient 0 } at 64x64. */
static bool render_phong(lg_test *t, const char *layout, const char *dir, const char *opts,
                         lg_image *img)
{
    char g[1024];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_tex_scene { layout = %s }\n"
             "l = light { scene = s, direction = %s }\n"
             "lit = phong { scene = l, ambient = [0, 0, 0], background = [1, 0, 1]%s%s }\n"
             "output lit \"out.exr\"\n",
             layout, dir, *opts ? ", " : "", opts);
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "64x64", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "phong render of %s (%s) failed (%d)", layout, opts, rc);
    bool ok = !rc && lg_test_read(t, "out.exr", img, NULL);
    return ok && img->width == 64 && img->height == 64;
}

/* Through phong (kd 1, Od 1, ks 0, light along -Z: I = Od * texture * N.L with N.L = 1):
 * every pixel is its texel, in every shading mode (flat and Gouraud modulate their held
 * colour by the texture); the masked checker has its holes. */
static void case_phong_texel(lg_test *t)
{
    static const char *const modes[] = { "shading = phong", "shading = gouraud", "shading = flat",
                                         "shading = mixed", "shading = phong_half" };
    tx_scene *s = tx_make(TX_CHECKER, 0);
    for (int k = 0; k < 5; k++) {
        lg_image img = { 0 };
        if (!render_phong(t, "checker", "[0, 0, -1]", modes[k], &img))
            break;
        int wrong = 0;
        /* phong_half shades quarter images: texel centres there, every pixel elsewhere */
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++) {
                if (k == 4 && (x % 8 < 2 || x % 8 > 5 || y % 8 < 2 || y % 8 > 5))
                    continue;
                const uint8_t *p = s->pixels + ((y / 8) * 8 + x / 8) * 4;
                for (int c = 0; c < 3; c++)
                    wrong += srgb_byte(px(&img, x, y)[c]) != p[c];
            }
        fprintf(stderr, "phong {%s}: %d channels not their texel's bytes\n", modes[k], wrong);
        LG_TEST_CHECK(t, wrong == 0, "{%s}: %d channels differ from the texels", modes[k], wrong);
        lg_image_free(&img);
    }
    tx_free(s);
    lg_image img = { 0 };
    if (!render_phong(t, "mask", "[0, 0, -1]", "", &img))
        return;
    int holes = 0, solid = 0;
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 8; i++) {
            const float *p = px(&img, 8 * i + 4, 8 * j + 4);
            bool bg = p[0] == BG[0] && p[1] == BG[1] && p[2] == BG[2];
            if ((i + j) % 2)
                holes += bg;
            else
                solid += !bg;
        }
    fprintf(stderr, "phong mask: %d of 32 holes, %d of 32 solid\n", holes, solid);
    LG_TEST_CHECK(t, holes == 32 && solid == 32, "phong mask: %d holes, %d solid", holes, solid);
    lg_image_free(&img);
}

/* A flat quad whose normal texture holds one tilted texel shades as the tilted normal:
 * N' = normalize(T x + B y + N z) with T = +X, B = +Y, N = +Z; lit along -Z the pixel is
 * N'.z, lit along (-1, 0, -1) / sqrt 2 it is (N'.x + N'.z) / sqrt 2 (a tilt the wrong way
 * round would give (N'.z - N'.x) / sqrt 2). Gouraud lights the vertex normals: flat. */
static void case_phong_normal(lg_test *t)
{
    double n[3], l = 0;
    for (int k = 0; k < 3; k++)
        n[k] = 2.0 * TX_NORMAL_TEXEL[k] / 255.0 - 1.0, l += n[k] * n[k];
    for (int k = 0; k < 3; k++)
        n[k] /= sqrt(l);
    struct {
        const char *dir, *opts;
        double want;
    } runs[] = {
        { "[0, 0, -1]", "shading = phong", n[2] },
        { "[-1, 0, -1]", "shading = phong", (n[0] + n[2]) / sqrt(2.0) },
        { "[-1, 0, -1]", "shading = gouraud", 1.0 / sqrt(2.0) },
    };
    for (int r = 0; r < 3; r++) {
        lg_image img = { 0 };
        if (!render_phong(t, "normal", runs[r].dir, runs[r].opts, &img))
            return;
        double worst = 0;
        for (uint32_t y = 0; y < 64; y++)
            for (uint32_t x = 0; x < 64; x++)
                worst = fmax(worst, fabs(px(&img, x, y)[0] - runs[r].want));
        fprintf(stderr, "normal map, light %s {%s}: want %.5f, largest difference %.3g\n",
                runs[r].dir, runs[r].opts, runs[r].want, worst);
        LG_TEST_CHECK(t, worst <= 2e-3, "light %s {%s}: pixels off %.5f by up to %g", runs[r].dir,
                      runs[r].opts, runs[r].want, worst);
        lg_image_free(&img);
    }
}

/* Hard references: a base colour texture index past the scene's textures reads as no
 * texture (white: the factor alone), and a normal texture over tangents without a
 * direction falls back to the interpolated normal (lit along -Z: exactly 1), in preview
 * and phong, without an error. */
static void case_degenerate(lg_test *t)
{
    lg_image img = { 0 };
    if (!render(t, "layout = degenerate", "", 32, &img))
        return;
    int white = 0;
    for (size_t i = 0; i < (size_t)32 * 32; i++)
        white += img.pixels[4 * i] == 1.0f && img.pixels[4 * i + 1] == 1.0f &&
                 img.pixels[4 * i + 2] == 1.0f;
    lg_image_free(&img);
    if (!render_phong(t, "degenerate", "[0, 0, -1]", "shading = phong", &img))
        return;
    double worst = 0;
    for (size_t i = 0; i < (size_t)64 * 64; i++)
        worst = fmax(worst, fabs(img.pixels[4 * i] - 1.0));
    fprintf(stderr, "degenerate: %d of 1024 preview pixels white; phong off 1 by %.3g\n", white,
            worst);
    LG_TEST_CHECK(t, white == 1024, "%d of 1024 pixels are the factor's white", white);
    LG_TEST_CHECK(t, worst <= 1e-6, "without a tangent direction N is not the normal (%g)", worst);
    lg_image_free(&img);
}

/* The in-scattered light of volumetric_froxel in fog in front of the quad, lit from behind
 * it (a light travelling +Z, towards the camera), through the shadow map: its `inscatter`
 * image at 64x64 (grid 64 x 64 x 32). */
static bool froxel_inscatter(lg_test *t, const char *layout, lg_image *img)
{
    char g[2048];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_tex_scene { layout = %s }\n"
             "sun = light { scene = s, direction = [0, 0, 1], intensity = 10 }\n"
             "fog = medium { scene = sun, density = 1, scattering = [0.2, 0.2, 0.2], "
             "absorption = [0, 0, 0], g = 0 }\n"
             "shadow = shadowmap { scene = fog, resolution = 256, cull = none }\n"
             "lit = phong { scene = fog, shadows = shadow, ambient = [0, 0, 0] }\n"
             "vol = volumetric_froxel { scene = fog, base = lit, shadows = shadow, width = 64, "
             "height = 64, depth = 32, z_near = 0.5, z_limit = 6 }\n"
             "output vol.inscatter \"ins.exr\"\n",
             layout);
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "64x64", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "froxel render of %s failed (%d)", layout, rc);
    bool ok = !rc && lg_test_read(t, "ins.exr", img, NULL);
    return ok && img->width == 64 && img->height == 64;
}

/* A masked blind's shadow reaches the froxel node through the shadow map: behind the
 * opaque quad the fog in front of it is in shadow everywhere (one uniform value: the fog
 * before the grid's first slice, which the node counts unshadowed); through the masked
 * quad, light shafts pass its transparent texels: at the four central texels (whose rays
 * run nearly along the shafts) the holes' fog is lit and the solid texels' is as dark as
 * behind the opaque quad. */
static void case_froxel(lg_test *t)
{
    lg_image op = { 0 }, mk = { 0 };
    if (!froxel_inscatter(t, "checker", &op) || !froxel_inscatter(t, "mask", &mk))
        return;
    double lo = 1e30, hi = -1e30, sum_op = 0, sum_mk = 0;
    for (size_t i = 0; i < (size_t)64 * 64; i++) {
        lo = fmin(lo, op.pixels[4 * i]), hi = fmax(hi, op.pixels[4 * i]);
        sum_op += op.pixels[4 * i], sum_mk += mk.pixels[4 * i];
    }
    double m0 = sum_op / 4096;
    float c[4];
    for (int k = 0; k < 4; k++)
        c[k] = px(&mk, 8 * (3 + k % 2) + 4, 8 * (3 + k / 2) + 4)[0];
    /* texels (3, 3) and (4, 4) are solid, (4, 3) and (3, 4) holes */
    fprintf(stderr,
            "froxel: opaque quad's in-scattering in [%.4f, %.4f]; masked quad's mean %.4f "
            "(opaque %.4f); central solid texels %.4f %.4f, holes %.4f %.4f\n",
            lo, hi, sum_mk / 4096, m0, c[0], c[3], c[1], c[2]);
    LG_TEST_CHECK(t, hi - lo <= 0.05 * hi + 1e-6,
                  "behind the opaque quad the fog is not in shadow "
                  "alike ([%g, %g])",
                  lo, hi);
    LG_TEST_CHECK(t, sum_mk > 3 * sum_op, "the masked quad lets no light through (%g vs %g)",
                  sum_mk / 4096, m0);
    LG_TEST_CHECK(t, fabs(c[0] - m0) <= 0.1 * m0 && fabs(c[3] - m0) <= 0.1 * m0,
                  "solid texels' fog %g %g, not the opaque quad's %g", c[0], c[3], m0);
    LG_TEST_CHECK(t, c[1] > 5 * m0 && c[2] > 5 * m0, "holes' fog %g %g is not lit (opaque %g)",
                  c[1], c[2], m0);
    lg_image_free(&op);
    lg_image_free(&mk);
}

/* Blinds agree: the masked quad's shafts through volumetric_froxel (its shadow map) and
 * through volumetric_reference (Embree's mask filter, exact visibility) on one graph, in
 * fog in front of the quad lit from behind it. Measured: relative RMSE 0.300 (grid 64 x 64 x
 * 32, shadow map 512), and 0.316 at 128 x 128 x 128 or with a 2048 map: not the grid's
 * sampling. Per 8 x 8 block the two agree within a few per cent in two quadrants of the
 * picture and the froxel is up to 50 % low in the other two; the fog the grid starts after
 * (z_near) counts unshadowed (0.033 where the reference has 0). The cause of the quadrant
 * difference is open (docs/volumetric.md, "The thesis's interiors"); the bound holds the
 * measured agreement, and the opaque quad (much further from the masked reference) shows
 * the masks reach both nodes. */
#define FX_REF_RMSE 0.35
static bool blind_pair(lg_test *t, const char *layout, lg_image *fx, lg_image *ref)
{
    char g[2400];
    snprintf(g, sizeof g,
             "lightgraph 1\n"
             "s = test_tex_scene { layout = %s }\n"
             "sun = light { scene = s, direction = [0, 0, 1], intensity = 10 }\n"
             "fog = medium { scene = sun, density = 1, scattering = [0.2, 0.2, 0.2], "
             "absorption = [0, 0, 0], g = 0 }\n"
             "shadow = shadowmap { scene = fog, resolution = 512, cull = none }\n"
             "lit = phong { scene = fog, shadows = shadow, ambient = [0, 0, 0] }\n"
             "vol = volumetric_froxel { scene = fog, base = lit, shadows = shadow, width = 64, "
             "height = 64, depth = 32, z_near = 0.5, z_limit = 6 }\n"
             "ref = volumetric_reference { scene = fog, base = lit, steps = 128, "
             "subpixel = centre, z_limit = 6 }\n"
             "output vol.inscatter \"fx.exr\"\n"
             "output ref.inscatter \"ref.exr\"\n",
             layout);
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "64x64", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "froxel + reference render of %s failed (%d)", layout, rc);
    bool ok = !rc && lg_test_read(t, "fx.exr", fx, NULL) && lg_test_read(t, "ref.exr", ref, NULL);
    return ok && fx->width == 64 && ref->width == 64 && fx->height == 64 && ref->height == 64;
}

static double rel_rmse_rgb(const lg_image *a, const lg_image *ref)
{
    double se = 0, sr = 0;
    for (size_t i = 0; i < (size_t)64 * 64; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)a->pixels[4 * i + c] - ref->pixels[4 * i + c];
            se += d * d;
            sr += (double)ref->pixels[4 * i + c] * ref->pixels[4 * i + c];
        }
    return sr > 0 ? sqrt(se / sr) : INFINITY;
}

static void case_blinds_agree(lg_test *t)
{
    lg_image fx = { 0 }, ref = { 0 }, fx_op = { 0 }, ref_op = { 0 };
    if (blind_pair(t, "mask", &fx, &ref) && blind_pair(t, "checker", &fx_op, &ref_op)) {
        double e = rel_rmse_rgb(&fx, &ref), e_op = rel_rmse_rgb(&fx_op, &ref);
        double e_ref = rel_rmse_rgb(&ref_op, &ref);
        fprintf(stderr,
                "blinds: froxel vs reference on the masked quad: relative RMSE %.4f; the opaque "
                "quad's froxel vs the masked reference %.4f, its reference %.4f\n",
                e, e_op, e_ref);
        LG_TEST_CHECK(t, e <= FX_REF_RMSE, "froxel and reference disagree on the blind: %g > %g", e,
                      FX_REF_RMSE);
        LG_TEST_CHECK(t, e_op > 3 * e && e_ref > 3 * e,
                      "the opaque quad is not told apart from the blind (%g, %g vs %g)", e_op,
                      e_ref, e);
    }
    lg_image_free(&fx);
    lg_image_free(&ref);
    lg_image_free(&fx_op);
    lg_image_free(&ref_op);
}

/* The preview node's bytes_allocated in --profile-json for test_tex_scene { layout }. */
static long long view_bytes(lg_test *t, const char *layout)
{
    char g[512];
    snprintf(g, sizeof g,
             "lightgraph 1\ns = test_tex_scene { layout = %s }\n"
             "view = preview { scene = s }\noutput view \"out.exr\"\n",
             layout);
    lg_test_write_text(t, "g.lgraph", g);
    const char *args[] = { "--size", "16x16", "--profile-json", "prof.json", NULL };
    int rc = lg_test_render(t, "g.lgraph", args, NULL);
    LG_TEST_CHECK(t, rc == 0, "render of %s failed (%d)", layout, rc);
    FILE *f = rc ? NULL : fopen(lg_test_path(t, "prof.json"), "rb");
    if (!f)
        return -1;
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = 0;
    const char *v = strstr(buf, "\"name\": \"view\"");
    const char *b = v ? strstr(v, "\"bytes_allocated\": ") : NULL;
    return b ? atoll(b + strlen("\"bytes_allocated\": ")) : -1;
}

/* Texture memory is counted against the node that asked: the 64 x 64 texture's mip chain
 * (21844 bytes) against the 8 x 8 one's (340), all else equal. */
static void case_profile(lg_test *t)
{
    long long a = view_bytes(t, "checker"), b = view_bytes(t, "mip");
    fprintf(stderr,
            "profile: preview allocates %lld bytes with the 8x8 texture, %lld with the "
            "64x64 one\n",
            a, b);
    LG_TEST_CHECK(t, a > 0 && b - a == 21844 - 340,
                  "the textures' difference is %lld bytes, not their mip chains' 21504", b - a);
}

/* The glTF assets (the second argument: the assets/meshes folder) through preview and phong:
 * the Duck's covered pixels are its texture's yellow (an untextured Duck would be its factor's
 * white: none yellow): 99% through preview, 66% through phong (shaded sides too dark, white
 * highlights); the milk truck shows its logo's blue and green beside its white body. */
static void case_assets(lg_test *t)
{
    const char *dir = lg_test_arg(t, 0);
    if (!dir || !*dir) {
        LG_TEST_CHECK(t, false, "no assets folder given");
        return;
    }
    static const char *const nodes[] = { "preview { scene = scene }",
                                         "phong { scene = l, ambient = [0.4, 0.4, 0.4] }" };
    for (int k = 0; k < 2; k++) {
        for (int a = 0; a < 2; a++) {
            char g[1024];
            snprintf(g, sizeof g,
                     "lightgraph 1\nscene = gltf { file = \"%s/%s\" }\n"
                     "l = light { scene = scene, direction = [-0.5, -1, -0.6] }\n"
                     "view = %s\noutput view \"out.exr\"\n",
                     dir, a ? "milk_truck/CesiumMilkTruck.gltf" : "duck/Duck.gltf", nodes[k]);
            lg_test_write_text(t, "g.lgraph", g);
            const char *args[] = { "--size", "160x120", NULL };
            int rc = lg_test_render(t, "g.lgraph", args, NULL);
            LG_TEST_CHECK(t, rc == 0, "render of %s failed (%d)", g, rc);
            lg_image img = { 0 };
            if (rc || !lg_test_read(t, "out.exr", &img, NULL))
                return;
            int yellow = 0, covered = 0, blue = 0, green = 0;
            for (size_t i = 0; i < (size_t)img.width * img.height; i++) {
                const float *p = img.pixels + 4 * i;
                if (p[0] + p[1] + p[2] <= 0.0f)
                    continue; /* the background */
                covered++;
                yellow += p[0] > 2 * p[2] && p[1] > 2 * p[2] && p[0] > 0.1f;
                blue += p[2] > 1.5f * p[0] && p[2] > p[1] && p[2] > 0.05f;
                green += p[1] > 1.5f * p[0] && p[1] > 1.5f * p[2] && p[1] > 0.02f;
            }
            fprintf(stderr, "%s through %.7s: %d covered, %d yellow, %d blue, %d green\n",
                    a ? "milk truck" : "Duck", nodes[k], covered, yellow, blue, green);
            if (a == 0)
                /* phong: shadowed sides and white highlights are not yellow (66% measured) */
                LG_TEST_CHECK(t, covered > 500 && yellow > (k ? 0.5 : 0.9) * covered,
                              "the Duck: %d of %d covered pixels yellow", yellow, covered);
            else
                LG_TEST_CHECK(t, covered > 2000 && blue > 50 && green > 50,
                              "the milk truck: %d blue and %d green of %d (its logo)", blue, green,
                              covered);
            lg_image_free(&img);
        }
    }
}

static void setup(lg_test *t)
{
    lg_test_require_backend(t, "gl");
}

int main(int argc, char **argv)
{
    setenv("LIGHTGRAPH_PLUGIN_PATH", TX_TEST_PLUGIN_DIR, 1);
    static const lg_test_case cases[] = {
        { "texel", case_texel },
        { "bilinear", case_bilinear },
        { "wrap", case_wrap },
        { "mip", case_mip },
        { "mask", case_mask },
        { "wireframe", case_wireframe },
        { "shadow", case_shadow },
        { "phong_texel", case_phong_texel },
        { "phong_normal", case_phong_normal },
        { "degenerate", case_degenerate },
        { "froxel", case_froxel },
        { "blinds_agree", case_blinds_agree },
        { "profile", case_profile },
        { "assets", case_assets },
    };
    lg_test_main_opts o = { .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
