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
 *              modes alike
 *   shadow     shadowmap's atlas under a light along -Z: the opaque checker quad casts a
 *              full square; its masked twin casts half of it, on one parity of the 8 x 8
 *              cells only (the shadow has holes where the texels are transparent)
 *   phong_texel  the checker through phong (kd 1, Od 1, ks 0, a light along -Z): every
 *              pixel is its texel's sRGB bytes in all five shading modes; the masked
 *              checker has its holes
 *   phong_normal a constant tilted normal texel shades as the tilted normal (phong), lit
 *              from straight ahead and from 45 degrees (the tilt's sign); gouraud lights
 *              the vertex normals (no normal map)
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
    tx_scene *s = tx_make(TX_MASK, 0);
    for (int mode = 0; mode < 2; mode++) {
        lg_image img = { 0 };
        if (!render(t, "layout = mask", mode ? "mode = normals" : "", 64, &img))
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
        fprintf(stderr, "mask, mode %d: %d of 32 holes, %d of 32 solid texels\n", mode, holes,
                solid);
        LG_TEST_CHECK(t, holes == 32 && solid == 32, "mode %d: %d holes, %d solid (32 each)", mode,
                      holes, solid);
        lg_image_free(&img);
    }
    tx_free(s);
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
    };
    lg_test_main_opts o = { .setup = setup };
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
