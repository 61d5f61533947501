/*
 * test_gltf_textures: the `gltf` node's textures (plugins/scene_gltf: gltf_load.c,
 * gltf_image.c, gltf_tangents.c), the loader called directly.
 *
 *   test_gltf_textures CASE
 *
 *   assets     the Duck, the milk truck and the Draco sphere load with their images:
 *              sizes and texels against values decoded without libpng (png_texels.py,
 *              Python's zlib), the samplers, the maps, the features, the content hash
 *   checker    generated checkerboards (a PNG writer of its own: stored deflate blocks)
 *              as a file, a data: URI and a GLB bufferView; grey, grey+alpha, palette,
 *              16-bit and interlaced PNGs and a JPEG; nearest sampling through
 *              lg_scene_texture_sample; KHR_texture_transform landing on a known texel;
 *              the wrap modes; TEXCOORD_1; alpha modes; unused images not read; a
 *              percent-encoded uri in a subfolder
 *   bad        hard cases (suite stability): a corrupt PNG, a truncated JPEG, an image uri
 *              leaving the folder, a FIFO image, a huge claimed size, texCoord 2, texture,
 *              image and sampler indices out of range, a non-finite texture transform, a
 *              bad alphaMode, a missing image file: each refused with a message naming the
 *              file, the image or material and why
 *   tangents   TEXCOORD_1 and TANGENT from a Draco stream (libdraco's encoder,
 *              draco_encode.cpp); the sphere's own TANGENTs against MikkTSpace-style tangents regenerated
 *              with them stripped (angle bound measured), handedness splits on a mirrored
 *              UV seam, file tangents orthonormalised, a normal map without TEXCOORD_0
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <jpeglib.h>

#include "common/check.h"
#include "draco_encode.h"
#include "gltf_test.h"
#include "lightgraph/vecmath.h"

static char err[2048];

/* The generated tangents' largest angle to the sphere file's own (measured: README.md,
 * "Tangents") */
#define TANGENT_MAX_DEG 1.0

/* ---- a PNG writer of the test's own (no libpng): stored deflate blocks ----------------------- */

static uint32_t crc32_of(const uint8_t *p, size_t n, uint32_t crc)
{
    crc = ~crc;
    for (size_t i = 0; i < n; i++) {
        crc ^= p[i];
        for (int k = 0; k < 8; k++)
            crc = crc & 1 ? (crc >> 1) ^ 0xedb88320u : crc >> 1;
    }
    return ~crc;
}

/* Appends without gt_add's 4-byte alignment (a PNG has none). */
static void put_bytes(gt_blob *b, const void *p, size_t n)
{
    if (b->size + n > b->cap) {
        b->cap = (b->size + n) * 2 + 64;
        b->data = realloc(b->data, b->cap);
        if (!b->data)
            abort();
    }
    memcpy(b->data + b->size, p, n);
    b->size += n;
}

static void put32(gt_blob *b, uint32_t v)
{
    uint8_t x[4] = { (uint8_t)(v >> 24), (uint8_t)(v >> 16), (uint8_t)(v >> 8), (uint8_t)v };
    put_bytes(b, x, 4);
}

static void chunk(gt_blob *b, const char *type, const uint8_t *data, size_t n)
{
    put32(b, (uint32_t)n);
    size_t at = b->size;
    put_bytes(b, type, 4);
    if (n)
        put_bytes(b, data, n);
    put32(b, crc32_of(b->data + at, n + 4, 0));
}

/* A PNG of `rows` (already filtered: each row starts with its filter byte 0) for colour
 * type `ctype`, bit depth `depth`, interlace 0 or 1 (Adam7: `rows` then holds the passes'
 * filtered scanlines, as the caller built them); `plte`/`trns` optional. */
static uint8_t *png_bytes(uint32_t w, uint32_t h, int ctype, int depth, int interlace,
                          const uint8_t *rows, size_t rows_size, const uint8_t *plte, size_t plte_n,
                          const uint8_t *trns, size_t trns_n, size_t *size)
{
    gt_blob b = { 0 };
    put_bytes(&b, "\x89PNG\r\n\x1a\n", 8);
    uint8_t ihdr[13] = { (uint8_t)(w >> 24),
                         (uint8_t)(w >> 16),
                         (uint8_t)(w >> 8),
                         (uint8_t)w,
                         (uint8_t)(h >> 24),
                         (uint8_t)(h >> 16),
                         (uint8_t)(h >> 8),
                         (uint8_t)h,
                         (uint8_t)depth,
                         (uint8_t)ctype,
                         0,
                         0,
                         (uint8_t)interlace };
    chunk(&b, "IHDR", ihdr, 13);
    if (plte)
        chunk(&b, "PLTE", plte, plte_n);
    if (trns)
        chunk(&b, "tRNS", trns, trns_n);
    /* zlib: header, stored blocks of at most 65535 bytes, adler32 */
    gt_blob z = { 0 };
    put_bytes(&z, "\x78\x01", 2);
    size_t at = 0;
    do {
        size_t n = rows_size - at > 65535 ? 65535 : rows_size - at;
        uint8_t hdr[5] = { (uint8_t)(at + n == rows_size), (uint8_t)n, (uint8_t)(n >> 8),
                           (uint8_t)~n, (uint8_t)(~n >> 8) };
        put_bytes(&z, hdr, 5);
        if (n)
            put_bytes(&z, rows + at, n);
        at += n;
    } while (at < rows_size);
    uint32_t s1 = 1, s2 = 0;
    for (size_t i = 0; i < rows_size; i++) {
        s1 = (s1 + rows[i]) % 65521;
        s2 = (s2 + s1) % 65521;
    }
    put32(&z, s2 << 16 | s1);
    chunk(&b, "IDAT", z.data, z.size);
    chunk(&b, "IEND", NULL, 0);
    gt_blob_free(&z);
    *size = b.size;
    return b.data;
}

/* The checker texel (x, y) of the test images: every texel different. */
static void checker_texel(uint32_t x, uint32_t y, uint8_t out[4])
{
    out[0] = (uint8_t)(10 * x + 1);
    out[1] = (uint8_t)(10 * y + 2);
    out[2] = (x + y) % 2 ? 255 : 0;
    out[3] = (uint8_t)(200 + x + 4 * y);
}

/* An RGBA8 checker PNG of w x h. */
static uint8_t *checker_png(uint32_t w, uint32_t h, size_t *size)
{
    size_t stride = 1 + (size_t)w * 4;
    uint8_t *rows = calloc(stride * h, 1);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            checker_texel(x, y, rows + y * stride + 1 + 4 * x);
    uint8_t *png = png_bytes(w, h, 6, 8, 0, rows, stride * h, NULL, 0, NULL, 0, size);
    free(rows);
    return png;
}

/* ---- scenes ---------------------------------------------------------------------------------- */

/* One triangle with TEXCOORD_0 (and TEXCOORD_1 when uv1) in a .bin-less data URI buffer,
 * material 0 = `material` (JSON object text), and the textures/images/samplers given. */
static char *tri_scene(const char *material, const char *textures, const char *images,
                       const char *samplers, bool uv1, const char *extensions_used)
{
    static const float pos[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    static const float uv[6] = { 0, 0, 1, 0, 0, 1 };
    static const float uv_1[6] = { 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f };
    gt_blob b = { 0 };
    gt_add(&b, pos, sizeof pos);
    gt_add(&b, uv, sizeof uv);
    gt_add(&b, uv_1, sizeof uv_1);
    char *uri = gt_data_uri(b.data, b.size);
    char *json = gt_fmt(
        "{\"asset\":{\"version\":\"2.0\"},%s\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1%s},"
        "\"material\":0}]}],\"materials\":[%s],%s%s%s"
        "\"buffers\":[{\"uri\":\"%s\",\"byteLength\":%zu}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
        "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":24},"
        "{\"buffer\":0,\"byteOffset\":60,\"byteLength\":24}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[1,1,0]},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":3,\"type\":\"VEC2\"}]}",
        extensions_used ? extensions_used : "", uv1 ? ",\"TEXCOORD_1\":2" : "", material,
        textures ? textures : "", images ? images : "", samplers ? samplers : "", uri, b.size);
    free(uri);
    gt_blob_free(&b);
    return json;
}

static lg_scene *load_json(const char *name, const char *json)
{
    int rc = 0;
    lg_scene *s = gt_load_text(name, json, NULL, err, sizeof err, &rc);
    CHECKF(s, "%s: %s", name, err);
    return s;
}

/* Samples texture reference `r` with nearest texels at uv (linear values, no sRGB). */
static void sample(const lg_scene *s, const lg_texture_ref *r, float u, float v, float out[4])
{
    float uv[2] = { u, v };
    lg_scene_texture_sample(s, r, uv, false, out);
}

static bool texel_is(const float got[4], const uint8_t want[4])
{
    for (int k = 0; k < 4; k++)
        if (fabsf(got[k] - want[k] / 255.0f) > 0.5f / 255.0f)
            return false;
    return true;
}

/* ---- assets ---------------------------------------------------------------------------------- */

static void expect_texel(const lg_scene_image *im, uint32_t x, uint32_t y, int r, int g, int b,
                         int a, const char *what)
{
    const uint8_t *p = im->rgba8 + ((size_t)y * im->width + x) * 4;
    CHECKF(p[0] == r && p[1] == g && p[2] == b && p[3] == a,
           "%s texel (%u, %u): %d %d %d %d, want %d %d %d %d", what, x, y, p[0], p[1], p[2], p[3],
           r, g, b, a);
}

static void case_assets(void)
{
    int rc = 0;
    uint64_t hash = 0;
    lg_scene *s = NULL;
    /* the Duck: one material with a base colour texture (DuckCM.png, a 512 x 512 palette
     * PNG), a sampler with linear / linear-mipmap-nearest... as the file says */
    rc = lg_gltf_load(gt_asset("meshes/duck/Duck.gltf"), NULL, &s, &hash, err, sizeof err);
    CHECKF(rc == 0 && s, "Duck: %s", err);
    if (s) {
        const lg_scene_textures *t = s->textures;
        CHECKF(t && t->n_images == 1 && t->n_textures == 1, "Duck: %u images, %u textures",
               t ? t->n_images : 0, t ? t->n_textures : 0);
        if (t && t->n_images == 1) {
            const lg_scene_image *im = &t->images[0];
            CHECKF(im->width == 512 && im->height == 512 && !strcmp(im->name, "DuckCM.png"),
                   "Duck image %ux%u '%s'", im->width, im->height, im->name);
            CHECKF(t->bytes == 512u * 512 * 4, "Duck bytes %llu", (unsigned long long)t->bytes);
            /* python3 tests/plugins/scene_gltf/png_texels.py assets/meshes/duck/DuckCM.png
             * 0,0 100,200 255,511 300,300 */
            expect_texel(im, 0, 0, 225, 191, 0, 255, "DuckCM");
            expect_texel(im, 100, 200, 255, 195, 0, 255, "DuckCM");
            expect_texel(im, 255, 511, 240, 203, 0, 255, "DuckCM");
            expect_texel(im, 300, 300, 255, 190, 0, 255, "DuckCM");
            const lg_scene_texture *tx = &t->textures[0];
            CHECKF(tx->image == 0 && tx->mag_filter == LG_TEX_LINEAR &&
                       tx->min_filter == LG_TEX_NEAREST_MIPMAP_LINEAR &&
                       tx->wrap_s == LG_TEX_REPEAT && tx->wrap_t == LG_TEX_REPEAT,
                   "Duck sampler %u %u %u %u", tx->mag_filter, tx->min_filter, tx->wrap_s,
                   tx->wrap_t);
        }
        const lg_material_maps *mp = lg_material_maps_of(&s->materials[0]);
        CHECKF(s->materials[0].maps && mp->base_color.texture == 0 && mp->normal.texture == -1 &&
                   mp->alpha_mode == LG_ALPHA_OPAQUE && mp->base_color.transform[0] == 1 &&
                   mp->base_color.transform[3] == 1,
               "Duck maps: base %d normal %d mode %d", mp->base_color.texture, mp->normal.texture,
               mp->alpha_mode);
        CHECKF(s->features.textures == 1 && s->features.masked_materials == 0,
               "Duck features: textures %u masked %u", s->features.textures,
               s->features.masked_materials);
        CHECKF(!s->meshes[0].tangents && !s->meshes[0].texcoords1,
               "Duck: no normal map, no tangents");
        lg_gltf_scene_free(s);
    }
    /* the content hash covers the image file: the same model with another DuckCM.png */
    {
        size_t n;
        uint8_t *g = gt_read(gt_asset("meshes/duck/Duck.gltf"), &n);
        gt_write("Duck.gltf", g, n);
        free(g);
        g = gt_read(gt_asset("meshes/duck/Duck0.bin"), &n);
        gt_write("Duck0.bin", g, n);
        free(g);
        g = gt_read(gt_asset("meshes/duck/DuckCM.png"), &n);
        gt_write("DuckCM.png", g, n);
        uint64_t h1 = 0, h2 = 0;
        s = NULL;
        rc = lg_gltf_load(gt_path("Duck.gltf"), NULL, &s, &h1, err, sizeof err);
        CHECKF(rc == 0 && h1 == hash, "Duck copy: rc %d, hash %llx vs %llx", rc,
               (unsigned long long)h1, (unsigned long long)hash);
        lg_gltf_scene_free(s);
        size_t pn;
        uint8_t *png = checker_png(8, 8, &pn);
        gt_write("DuckCM.png", png, pn);
        free(png);
        s = NULL;
        rc = lg_gltf_load(gt_path("Duck.gltf"), NULL, &s, &h2, err, sizeof err);
        CHECKF(rc == 0 && h2 != h1, "Duck with another texture: rc %d, hash unchanged", rc);
        CHECKF(s && s->textures && s->textures->images[0].width == 8, "Duck: new texture read");
        lg_gltf_scene_free(s);
        free(g);
    }
    /* the milk truck: 4 materials, 2 textures of one image (2048 x 2048 palette PNG) */
    s = NULL;
    rc = lg_gltf_load(gt_asset("meshes/milk_truck/CesiumMilkTruck.gltf"), NULL, &s, NULL, err,
                      sizeof err);
    CHECKF(rc == 0 && s, "milk truck: %s", err);
    if (s) {
        const lg_scene_textures *t = s->textures;
        CHECKF(t && t->n_images == 1 && t->n_textures == 2, "truck: %u images, %u textures",
               t ? t->n_images : 0, t ? t->n_textures : 0);
        if (t && t->n_images == 1) {
            const lg_scene_image *im = &t->images[0];
            CHECKF(im->width == 2048 && im->height == 2048, "truck image %ux%u", im->width,
                   im->height);
            /* png_texels.py .../CesiumMilkTruck.png 0,0 512,512 1000,100 */
            expect_texel(im, 0, 0, 255, 255, 255, 255, "truck");
            expect_texel(im, 512, 512, 142, 142, 142, 255, "truck");
            expect_texel(im, 1000, 100, 255, 255, 255, 255, "truck");
            CHECKF(t->textures[0].image == 0 && t->textures[1].image == 0,
                   "truck: both textures use image 0");
        }
        uint32_t with_maps = 0;
        for (uint32_t i = 0; i < s->n_materials; i++)
            with_maps += s->materials[i].maps != NULL;
        CHECKF(with_maps == 2 && lg_material_maps_of(&s->materials[0])->base_color.texture == 0 &&
                   lg_material_maps_of(&s->materials[3])->base_color.texture == 1 &&
                   !s->materials[1].maps,
               "truck: %u materials with maps", with_maps);
        CHECKF(s->features.textures >= 1, "truck: features.textures %u", s->features.textures);
        lg_gltf_scene_free(s);
    }
    /* the Draco test sphere: a normal map and a base colour map, RGB PNGs, file tangents */
    s = NULL;
    rc = lg_gltf_load(gt_asset("meshes/sphere/sphere.gltf"), NULL, &s, NULL, err, sizeof err);
    CHECKF(rc == 0 && s, "sphere: %s", err);
    if (s) {
        const lg_scene_textures *t = s->textures;
        CHECKF(t && t->n_images == 2 && t->n_textures == 2, "sphere: images/textures");
        if (t && t->n_images == 2) {
            /* first use: the base colour (texture 1 of the file) comes first */
            const lg_material_maps *mp = lg_material_maps_of(&s->materials[0]);
            const lg_scene_image *base = &t->images[t->textures[mp->base_color.texture].image];
            const lg_scene_image *nrm = &t->images[t->textures[mp->normal.texture].image];
            CHECKF(strstr(base->name, "BaseColor") && strstr(nrm->name, "Normal"),
                   "sphere: base '%s', normal '%s'", base->name, nrm->name);
            expect_texel(base, 0, 0, 0, 0, 0, 255, "sphere base");
            expect_texel(base, 128, 128, 234, 2, 105, 255, "sphere base");
            expect_texel(nrm, 0, 0, 127, 127, 255, 255, "sphere normal");
        }
        CHECKF(s->meshes[0].tangents != NULL, "sphere: tangents");
        lg_gltf_scene_free(s);
    }
}

static void image_kinds(void);

/* ---- checker --------------------------------------------------------------------------------- */

static void case_checker(void)
{
    size_t pn;
    uint8_t *png = checker_png(4, 4, &pn);
    gt_write("checker.png", png, pn);
    static const char *const nearest =
        "\"samplers\":[{\"magFilter\":9728,\"minFilter\":9728,\"wrapS\":33071,\"wrapT\":33648},"
        "{\"magFilter\":9728,\"minFilter\":9728}],";
    /* texture 0: clamp / mirrored; texture 1: repeat; texture 2 with an unread image */
    static const char *const textures = "\"textures\":[{\"source\":0,\"sampler\":0},"
                                        "{\"source\":0,\"sampler\":1},{\"source\":1}],";
    char *json = tri_scene(
        "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":1,\"extensions\":{"
        "\"KHR_texture_transform\":{\"offset\":[0.25,0.5],\"rotation\":1.5707963267948966,"
        "\"scale\":[0.5,0.5]}}},\"metallicRoughnessTexture\":{\"index\":0}},"
        "\"emissiveTexture\":{\"index\":1,\"texCoord\":1},\"alphaMode\":\"MASK\","
        "\"alphaCutoff\":0.25}",
        textures, "\"images\":[{\"uri\":\"checker.png\"},{\"uri\":\"missing.png\"}],", nearest,
        true, "\"extensionsUsed\":[\"KHR_texture_transform\"],");
    lg_scene *s = load_json("checker.gltf", json);
    free(json);
    if (s) {
        const lg_scene_textures *t = s->textures;
        CHECKF(t && t->n_images == 1 && t->n_textures == 2,
               "checker: the unused texture and its (missing) image are not read");
        const lg_material_maps *mp = lg_material_maps_of(&s->materials[0]);
        CHECKF(mp->alpha_mode == LG_ALPHA_MASK && fabsf(mp->alpha_cutoff - 0.25f) < 1e-7f,
               "checker: alpha mode %d cutoff %g", mp->alpha_mode, mp->alpha_cutoff);
        CHECKF(s->features.masked_materials == 1 && s->features.textures == 3,
               "checker: features masked %u textures %u", s->features.masked_materials,
               s->features.textures);
        CHECKF(s->meshes[0].texcoords1 && s->meshes[0].texcoords1[0] == 0.5f,
               "checker: TEXCOORD_1 kept");
        CHECKF(mp->emissive.texcoord == 1, "checker: emissive texCoord 1");
        /* every texel at its centre, through the clamp texture (no transform) */
        for (uint32_t y = 0; y < 4; y++)
            for (uint32_t x = 0; x < 4; x++) {
                uint8_t want[4];
                checker_texel(x, y, want);
                float got[4];
                sample(s, &mp->metallic_roughness, (x + 0.5f) / 4, (y + 0.5f) / 4, got);
                CHECKF(texel_is(got, want), "checker texel (%u, %u): %g %g %g %g", x, y, got[0],
                       got[1], got[2], got[3]);
            }
        /* wrap modes: clamp in u, mirrored repeat in v; repeat on texture 1 */
        uint8_t want[4];
        float got[4], uvw[2];
        sample(s, &mp->metallic_roughness, 1.3f, 1.2f, got); /* u -> texel 3; v 4.8 -> 3 */
        checker_texel(3, 3, want);
        CHECKF(texel_is(got, want), "clamp/mirror: %g %g", got[0], got[1]);
        sample(s, &mp->metallic_roughness, -0.6f, 1.6f, got); /* u -> 0; v 6.4: 6 -> 1 */
        checker_texel(0, 1, want);
        CHECKF(texel_is(got, want), "clamp/mirror 2: %g %g", got[0], got[1]);
        lg_texture_ref plain = mp->base_color;
        memcpy(plain.transform, (float[6]){ 1, 0, 0, 1, 0, 0 }, sizeof plain.transform);
        sample(s, &plain, 1.3f, -0.1f, got); /* repeat: u 5.2 -> 1; v -0.4 -> 3 */
        checker_texel(1, 3, want);
        CHECKF(texel_is(got, want), "repeat: %g %g", got[0], got[1]);
        /* KHR_texture_transform: uv (0.25, 0.25), scaled by 0.5 to (0.125, 0.125), turned a
         * quarter (cos 0, sin 1: (u, v) -> (-v, u)) to (-0.125, 0.125), offset by (0.25,
         * 0.5) to (0.125, 0.625): texel (0, 2) of the 4 x 4 image */
        const float *tf = mp->base_color.transform;
        CHECKF(fabsf(tf[0]) < 1e-7f && fabsf(tf[1] - 0.5f) < 1e-7f && fabsf(tf[2] + 0.5f) < 1e-7f &&
                   fabsf(tf[3]) < 1e-7f && tf[4] == 0.25f && tf[5] == 0.5f,
               "transform %g %g %g %g %g %g", tf[0], tf[1], tf[2], tf[3], tf[4], tf[5]);
        lg_texture_ref_uv(&mp->base_color, (const float[2]){ 0.25f, 0.25f }, NULL, uvw);
        CHECKF(fabsf(uvw[0] - 0.125f) < 1e-6f && fabsf(uvw[1] - 0.625f) < 1e-6f,
               "transformed uv %g %g", uvw[0], uvw[1]);
        sample(s, &mp->base_color, uvw[0], uvw[1], got);
        checker_texel(0, 2, want);
        CHECKF(texel_is(got, want), "transform lands on texel (0, 2): %g %g", got[0], got[1]);
        /* alpha mask: texel alpha (200 + x + 4y) / 255 >= 0.25 everywhere */
        CHECKF(lg_material_covers(s, 0, (const float[2]){ 0.1f, 0.1f }, NULL),
               "mask covers where alpha is high");
        lg_gltf_scene_free(s);
    }

    /* the same image as a data: URI (image/png) and inside a GLB's BIN chunk */
    char *uri = gt_data_uri(png, pn);
    char *png_uri = gt_fmt("data:image/png;base64,%s", strchr(uri, ',') + 1);
    char *images = gt_fmt("\"images\":[{\"uri\":\"%s\"}],", png_uri);
    json = tri_scene("{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}",
                     "\"textures\":[{\"source\":0,\"sampler\":0}],", images, nearest, false, NULL);
    s = load_json("datauri.gltf", json);
    if (s) {
        CHECKF(s->textures && s->textures->n_images == 1 && s->textures->images[0].width == 4,
               "data: URI image decoded");
        float got[4];
        uint8_t want[4];
        sample(s, &lg_material_maps_of(&s->materials[0])->base_color, 0.6f, 0.9f, got);
        checker_texel(2, 3, want);
        CHECKF(texel_is(got, want), "data: URI texel (2, 3): %g %g", got[0], got[1]);
        lg_gltf_scene_free(s);
    }
    free(json);
    free(images);
    free(png_uri);
    free(uri);

    {
        static const float pos[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
        static const float uv[6] = { 0, 0, 1, 0, 0, 1 };
        gt_blob bin = { 0 };
        size_t o_pos = gt_add(&bin, pos, sizeof pos), o_uv = gt_add(&bin, uv, sizeof uv);
        size_t o_png = gt_add(&bin, png, pn);
        char *js = gt_fmt(
            "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
            "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},"
            "\"material\":0}]}],\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":"
            "{\"index\":0}}}],\"textures\":[{\"source\":0}],"
            "\"images\":[{\"bufferView\":2,\"mimeType\":\"image/png\"}],"
            "\"buffers\":[{\"byteLength\":%zu}],"
            "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":36},"
            "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":24},"
            "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
            "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":"
            "\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5126,"
            "\"count\":3,\"type\":\"VEC2\"}]}",
            bin.size, o_pos, o_uv, o_png, pn);
        size_t jl = (strlen(js) + 3) & ~(size_t)3;
        size_t total = 12 + 8 + jl + 8 + bin.size;
        uint8_t *glb = calloc(total, 1);
        uint32_t hdr[5] = { 0x46546c67u, 2, (uint32_t)total, (uint32_t)jl, 0x4E4F534Au };
        memcpy(glb, hdr, 20);
        memset(glb + 20, ' ', jl);
        memcpy(glb + 20, js, strlen(js));
        uint32_t bh[2] = { (uint32_t)bin.size, 0x004E4942u };
        memcpy(glb + 20 + jl, bh, 8);
        memcpy(glb + 28 + jl, bin.data, bin.size);
        gt_write("image.glb", glb, total);
        int rc = 0;
        s = gt_load_file(gt_path("image.glb"), NULL, err, sizeof err, &rc);
        CHECKF(s, "GLB bufferView image: %s", err);
        if (s) {
            CHECKF(s->textures && s->textures->n_images == 1 &&
                       s->textures->images[0].height == 4 &&
                       !memcmp(s->textures->images[0].rgba8 + 4 * 5, (uint8_t[4]){ 11, 12, 0, 205 },
                               4),
                   "GLB bufferView image: texel (1, 1)");
            lg_gltf_scene_free(s);
        }
        free(glb);
        free(js);
        gt_blob_free(&bin);
    }
    free(png);
    image_kinds();
}

/* A mesh from arrays (data URI buffer): nv positions, normals (may be NULL), texcoords (may
 * be NULL), tangents (may be NULL), ni indices; material 0 has the given JSON; texture 0 is
 * checker.png (which the caller wrote). */
static char *mesh_scene(uint32_t nv, const float *pos, const float *nrm, const float *uv,
                        const float *tan, uint32_t ni, const uint32_t *idx, const char *material)
{
    gt_blob b = { 0 };
    size_t o_pos = gt_add(&b, pos, nv * 12), o_nrm = nrm ? gt_add(&b, nrm, nv * 12) : 0;
    size_t o_uv = uv ? gt_add(&b, uv, nv * 8) : 0, o_tan = tan ? gt_add(&b, tan, nv * 16) : 0;
    size_t o_idx = gt_add(&b, idx, ni * 4);
    char *uri = gt_data_uri(b.data, b.size);
    char attrs[200] = "\"POSITION\":0";
    if (nrm)
        strcat(attrs, ",\"NORMAL\":1");
    if (uv)
        strcat(attrs, ",\"TEXCOORD_0\":2");
    if (tan)
        strcat(attrs, ",\"TANGENT\":3");
    char *json = gt_fmt(
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{%s},\"indices\":4,\"material\":0}]}],"
        "\"materials\":[%s],\"textures\":[{\"source\":0}],\"images\":[{\"uri\":"
        "\"checker.png\"}],\"buffers\":[{\"uri\":\"%s\",\"byteLength\":%zu}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u},"
        "{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%u}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%u,\"type\":"
        "\"VEC3\"},{\"bufferView\":1,\"componentType\":5126,\"count\":%u,\"type\":\"VEC3\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":%u,\"type\":\"VEC2\"},"
        "{\"bufferView\":3,\"componentType\":5126,\"count\":%u,\"type\":\"VEC4\"},"
        "{\"bufferView\":4,\"componentType\":5125,\"count\":%u,\"type\":\"SCALAR\"}]}",
        attrs, material, uri, b.size, o_pos, nv * 12, o_nrm, nv * 12, o_uv, nv * 8, o_tan, nv * 16,
        o_idx, ni * 4, nv, nv, nv, nv, ni);
    free(uri);
    gt_blob_free(&b);
    return json;
}

static int n_warnings;
static char last_warning[1024];

static void on_warning(void *user, const char *message)
{
    (void)user;
    n_warnings++;
    snprintf(last_warning, sizeof last_warning, "%s", message);
}

/* ---- more image kinds: one texture per scene ------------------------------------------------- */

/* A triangle whose base colour texture is image file `file` (written by the caller). */
static lg_scene *load_image_scene(const char *name, const char *file, int *rc)
{
    char *images = gt_fmt("\"images\":[{\"uri\":\"%s\"}],", file);
    char *json = tri_scene("{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}",
                           "\"textures\":[{\"source\":0}],", images, NULL, false, NULL);
    lg_scene *s = gt_load_text(name, json, NULL, err, sizeof err, rc);
    free(json);
    free(images);
    return s;
}

/* The decoded image of a one-texture scene must be w x h with these RGBA texels. */
static void expect_image(const char *what, const char *file, uint32_t w, uint32_t h,
                         const uint8_t *want, int tol)
{
    int rc = 0;
    char name[128];
    snprintf(name, sizeof name, "%s.gltf", what);
    lg_scene *s = load_image_scene(name, file, &rc);
    CHECKF(s, "%s: %s", what, err);
    if (!s)
        return;
    const lg_scene_image *im = s->textures ? &s->textures->images[0] : NULL;
    CHECKF(im && im->width == w && im->height == h, "%s: %ux%u", what, im ? im->width : 0,
           im ? im->height : 0);
    for (size_t i = 0; im && im->width == w && im->height == h && i < (size_t)w * h * 4; i++)
        if (abs(im->rgba8[i] - want[i]) > tol) {
            CHECKF(false, "%s: texel %zu channel %zu: %d, want %d", what, i / 4, i % 4,
                   im->rgba8[i], want[i]);
            break;
        }
    lg_gltf_scene_free(s);
}

/* A JPEG of w x h, every pixel `rgb` (grey: 1 component, CMYK: 4), written by libjpeg's
 * encoder (the decoder under test is another code path). */
static uint8_t *jpeg_bytes(uint32_t w, uint32_t h, int components, const uint8_t *px, size_t *size)
{
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr e;
    c.err = jpeg_std_error(&e);
    jpeg_create_compress(&c);
    unsigned char *out = NULL;
    unsigned long n = 0;
    jpeg_mem_dest(&c, &out, &n);
    c.image_width = w;
    c.image_height = h;
    c.input_components = components;
    c.in_color_space = components == 1 ? JCS_GRAYSCALE : components == 3 ? JCS_RGB : JCS_CMYK;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 95, TRUE);
    jpeg_start_compress(&c, TRUE);
    uint8_t *row = malloc((size_t)w * components);
    for (uint32_t x = 0; x < w; x++)
        memcpy(row + (size_t)x * components, px, (size_t)components);
    while (c.next_scanline < h)
        jpeg_write_scanlines(&c, &row, 1);
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    free(row);
    *size = n;
    return out;
}

static void write_png(const char *rel, uint32_t w, uint32_t h, int ctype, int depth, int interlace,
                      const uint8_t *rows, size_t rows_size, const uint8_t *plte, size_t plte_n,
                      const uint8_t *trns, size_t trns_n)
{
    size_t n;
    uint8_t *png = png_bytes(w, h, ctype, depth, interlace, rows, rows_size, plte, plte_n, trns,
                             trns_n, &n);
    gt_write(rel, png, n);
    free(png);
}

static void image_kinds(void)
{
    /* a percent-encoded uri in a subfolder: "sub dir/a b.png" */
    {
        size_t n;
        uint8_t *png = checker_png(3, 2, &n);
        mkdir(gt_path("sub dir"), 0700);
        gt_write("sub dir/a b.png", png, n);
        free(png);
        int rc = 0;
        lg_scene *s = load_image_scene("encoded.gltf", "sub%20dir/a%20b.png", &rc);
        CHECKF(s && s->textures && s->textures->images[0].width == 3 &&
                   !strcmp(s->textures->images[0].name, "sub%20dir/a%20b.png"),
               "percent-encoded image uri: %s", s ? "wrong image" : err);
        lg_gltf_scene_free(s);
    }
    /* grey 8-bit 2 x 1: RGB = grey, alpha 255 */
    write_png("grey.png", 2, 1, 0, 8, 0, (const uint8_t[]){ 0, 7, 250 }, 3, NULL, 0, NULL, 0);
    expect_image("grey", "grey.png", 2, 1, (const uint8_t[]){ 7, 7, 7, 255, 250, 250, 250, 255 },
                 0);
    /* grey + alpha */
    write_png("grey_alpha.png", 1, 1, 4, 8, 0, (const uint8_t[]){ 0, 90, 33 }, 3, NULL, 0, NULL, 0);
    expect_image("grey_alpha", "grey_alpha.png", 1, 1, (const uint8_t[]){ 90, 90, 90, 33 }, 0);
    /* grey 2-bit: 0..3 scaled to 0, 85, 170, 255 */
    write_png("grey2.png", 4, 1, 0, 2, 0, (const uint8_t[]){ 0, 0x1b }, 2, NULL, 0, NULL, 0);
    expect_image("grey2", "grey2.png", 4, 1,
                 (const uint8_t[]){ 0, 0, 0, 255, 85, 85, 85, 255, 170, 170, 170, 255, 255, 255,
                                    255, 255 },
                 0);
    /* palette 4-bit with a tRNS entry for index 1 */
    write_png("palette.png", 2, 1, 3, 4, 0, (const uint8_t[]){ 0, 0x01 }, 2,
              (const uint8_t[]){ 10, 20, 30, 40, 50, 60 }, 6, (const uint8_t[]){ 255, 77 }, 2);
    expect_image("palette", "palette.png", 2, 1,
                 (const uint8_t[]){ 10, 20, 30, 255, 40, 50, 60, 77 }, 0);
    /* 16-bit RGBA: the high byte of each channel */
    write_png("rgba16.png", 1, 1, 6, 16, 0,
              (const uint8_t[]){ 0, 0xab, 0xcd, 0x12, 0x34, 0x00, 0xff, 0xfe, 0x01 }, 9, NULL, 0,
              NULL, 0);
    expect_image("rgba16", "rgba16.png", 1, 1, (const uint8_t[]){ 0xab, 0x12, 0x00, 0xfe }, 0);
    /* Adam7-interlaced RGB 2 x 2: pass 1 holds (0, 0), pass 6 (1, 0), pass 7 row 1 */
    write_png("interlaced.png", 2, 2, 2, 8, 1,
              (const uint8_t[]){ 0, 1, 2, 3, 0, 4, 5, 6, 0, 7, 8, 9, 10, 11, 12 }, 15, NULL, 0,
              NULL, 0);
    expect_image("interlaced", "interlaced.png", 2, 2,
                 (const uint8_t[]){ 1, 2, 3, 255, 4, 5, 6, 255, 7, 8, 9, 255, 10, 11, 12, 255 }, 0);
    /* JPEG, RGB and grey, 16 x 8 of one colour (within the codec's rounding) */
    size_t n;
    uint8_t *jpg = jpeg_bytes(16, 8, 3, (const uint8_t[]){ 200, 100, 50 }, &n);
    gt_write("rgb.jpg", jpg, n);
    free(jpg);
    uint8_t want[16 * 8 * 4];
    for (int i = 0; i < 16 * 8; i++)
        memcpy(want + 4 * i, (const uint8_t[]){ 200, 100, 50, 255 }, 4);
    expect_image("jpeg_rgb", "rgb.jpg", 16, 8, want, 3);
    jpg = jpeg_bytes(16, 8, 1, (const uint8_t[]){ 123 }, &n);
    gt_write("grey.jpg", jpg, n);
    free(jpg);
    for (int i = 0; i < 16 * 8; i++)
        memcpy(want + 4 * i, (const uint8_t[]){ 123, 123, 123, 255 }, 4);
    expect_image("jpeg_grey", "grey.jpg", 16, 8, want, 1);
}

/* ---- bad ------------------------------------------------------------------------------------- */

static void on_alarm(int sig)
{
    (void)sig;
    static const char msg[] = "test_gltf_textures: an image load blocked (FIFO?)\n";
    if (write(2, msg, sizeof msg - 1) < 0) {
        /* nothing more to do */
    }
    _exit(1);
}

/* Loading `json` fails with a message naming the file and containing every one of want. */
static void expect_refused(const char *what, const char *json, const char *const *want)
{
    int rc = 0;
    char name[128];
    snprintf(name, sizeof name, "%s.gltf", what);
    lg_scene *s = gt_load_text(name, json, NULL, err, sizeof err, &rc);
    bool ok = !s && rc < 0 && strstr(err, name);
    for (size_t i = 0; want[i]; i++)
        ok = ok && strstr(err, want[i]);
    CHECKF(ok, "%s: rc %d, message '%s'", what, rc, err);
    lg_gltf_scene_free(s);
}

/* A one-texture scene with material `material`, texture list `textures` and image uri. */
static void expect_refused_scene(const char *what, const char *material, const char *textures,
                                 const char *image_uri, const char *samplers,
                                 const char *const *want)
{
    char *images = gt_fmt("\"images\":[{\"uri\":\"%s\"}],", image_uri);
    char *json = tri_scene(material, textures, images, samplers, false, NULL);
    expect_refused(what, json, want);
    free(json);
    free(images);
}

static long max_rss_kib(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    long kib = -1;
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "VmHWM:", 6))
            kib = strtol(line + 6, NULL, 10);
    if (f)
        fclose(f);
    return kib;
}

static void case_bad(void)
{
    signal(SIGALRM, on_alarm);
    alarm(60);
    static const char *const base =
        "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}";
    static const char *const tex0 = "\"textures\":[{\"source\":0}],";
    size_t pn;
    uint8_t *png = checker_png(4, 4, &pn);
    gt_write("good.png", png, pn);

    /* a corrupt PNG: one byte of the compressed data flipped (zlib's check fails first) */
    png[pn - 20] ^= 0x55;
    gt_write("corrupt.png", png, pn);
    expect_refused_scene("corrupt_png", base, tex0, "corrupt.png", NULL,
                         (const char *const[]){ "image 0 ('corrupt.png')", "cannot decode it",
                                                "PNG: IDAT", NULL });
    /* a PNG cut short inside its data */
    png[pn - 20] ^= 0x55;
    gt_write("short.png", png, pn / 2);
    expect_refused_scene("short_png", base, tex0, "short.png", NULL,
                         (const char *const[]){ "image 0 ('short.png')", "PNG", NULL });
    free(png);

    /* a truncated JPEG: libjpeg would fill the rest with grey; refused instead */
    size_t jn;
    uint8_t *jpg = jpeg_bytes(64, 64, 3, (const uint8_t[]){ 9, 99, 199 }, &jn);
    gt_write("truncated.jpg", jpg, jn * 2 / 3);
    expect_refused_scene("truncated_jpeg", base, tex0, "truncated.jpg", NULL,
                         (const char *const[]){ "image 0 ('truncated.jpg')", "JPEG",
                                                "Premature end", NULL });
    free(jpg);
    /* CMYK JPEG: refused (glTF allows RGB and grey) */
    jpg = jpeg_bytes(8, 8, 4, (const uint8_t[]){ 1, 2, 3, 4 }, &jn);
    gt_write("cmyk.jpg", jpg, jn);
    expect_refused_scene("cmyk_jpeg", base, tex0, "cmyk.jpg", NULL,
                         (const char *const[]){ "image 0 ('cmyk.jpg')", "CMYK", NULL });
    free(jpg);
    /* not an image at all */
    gt_write("gif.png", "GIF89a\x01\x00\x01\x00", 10);
    expect_refused_scene("not_image", base, tex0, "gif.png", NULL,
                         (const char *const[]){ "image 0 ('gif.png')",
                                                "not a PNG or JPEG image (it starts with 47 49 46",
                                                NULL });
    /* a missing image file */
    expect_refused_scene("missing", base, tex0, "nowhere.png", NULL,
                         (const char *const[]){ "image 0 ('nowhere.png')", "cannot read it",
                                                NULL });
    /* an image uri leaving the folder, lexically and through a link */
    expect_refused_scene("leaves", base, tex0, "../../../../../../etc/passwd", NULL,
                         (const char *const[]){ "image 0", "'../../../../../../etc/passwd'",
                                                "outside", NULL });
    if (symlink("/etc/hostname", gt_path("link.png")) == 0)
        expect_refused_scene("link_out", base, tex0, "link.png", NULL,
                             (const char *const[]){ "image 0", "'link.png'", "outside", NULL });
    /* a FIFO: refused at once, never opened for a blocking read (the alarm fails the test) */
    if (mkfifo(gt_path("fifo.png"), 0600) == 0)
        expect_refused_scene("fifo", base, tex0, "fifo.png", NULL,
                             (const char *const[]){ "image 0 ('fifo.png')", "FIFO", NULL });
    /* a header claiming 100000 x 100000 pixels: refused before any pixel memory exists */
    {
        uint8_t row[5] = { 0, 1, 2, 3, 4 };
        size_t n;
        uint8_t *huge = png_bytes(100000, 100000, 6, 8, 0, row, sizeof row, NULL, 0, NULL, 0, &n);
        gt_write("huge.png", huge, n);
        free(huge);
        long before = max_rss_kib();
        expect_refused_scene("huge", base, tex0, "huge.png", NULL,
                             (const char *const[]){ "image 0 ('huge.png')",
                                                    "100000 x 100000 pixels, more than the "
                                                    "67108864 accepted",
                                                    NULL });
        long grew = max_rss_kib() - before;
        CHECKF(grew < 64 * 1024, "huge: the peak memory grew by %ld KiB", grew);
    }
    /* texCoord 2, directly and through KHR_texture_transform */
    expect_refused_scene(
        "texcoord2",
        "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,\"texCoord\":2}}}", tex0,
        "good.png", NULL,
        (const char *const[]){ "material 0: baseColorTexture: texCoord 2 is not supported", NULL });
    expect_refused_scene("texcoord2_transform",
                         "{\"normalTexture\":{\"index\":0,\"extensions\":{"
                         "\"KHR_texture_transform\":{\"texCoord\":2}}}}",
                         tex0, "good.png", NULL,
                         (const char *const[]){ "normalTexture: KHR_texture_transform",
                                                "texCoord 2 is not supported", NULL });
    /* indices out of range: the material's texture, the texture's image and sampler */
    expect_refused_scene("texture_index", "{\"emissiveTexture\":{\"index\":5}}", tex0, "good.png",
                         NULL,
                         (const char *const[]){
                             "material 0: emissiveTexture: texture 5 does not exist", NULL });
    expect_refused_scene("image_index", base, "\"textures\":[{\"source\":7}],", "good.png", NULL,
                         (const char *const[]){ "texture 0: image 7 does not exist", NULL });
    expect_refused_scene("sampler_index", base, "\"textures\":[{\"source\":0,\"sampler\":3}],",
                         "good.png", "\"samplers\":[{}],",
                         (const char *const[]){ "texture 0: sampler 3 does not exist", NULL });
    expect_refused_scene("sampler_value", base, "\"textures\":[{\"source\":0,\"sampler\":0}],",
                         "good.png", "\"samplers\":[{\"wrapS\":1234}],",
                         (const char *const[]){ "sampler 0", "wrapS 1234", NULL });
    /* non-finite and overflowing texture transforms: JSON has no NaN or infinity, and a
     * number beyond double (1e400) is refused by the parser; numbers beyond 1e30 by the
     * loader, so that the float matrix stays finite */
    expect_refused_scene("transform_inf",
                         "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,"
                         "\"extensions\":{\"KHR_texture_transform\":{\"rotation\":1e400}}}}}",
                         tex0, "good.png", NULL,
                         (const char *const[]){ "number overflow", "1e400", NULL });
    expect_refused_scene("transform_scale",
                         "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,"
                         "\"extensions\":{\"KHR_texture_transform\":{\"scale\":[1e300,1]}}}}}",
                         tex0, "good.png", NULL,
                         (const char *const[]){ "KHR_texture_transform", "scale[0]", NULL });
    expect_refused_scene("transform_type",
                         "{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,"
                         "\"extensions\":{\"KHR_texture_transform\":{\"offset\":\"left\"}}}}}",
                         tex0, "good.png", NULL,
                         (const char *const[]){ "KHR_texture_transform: offset", NULL });
    /* alpha mode and cutoff, occlusion strength */
    expect_refused_scene("alpha_mode", "{\"alphaMode\":\"CUTOUT\"}", tex0, "good.png", NULL,
                         (const char *const[]){ "alphaMode 'CUTOUT'", NULL });
    expect_refused_scene("alpha_cutoff", "{\"alphaMode\":\"MASK\",\"alphaCutoff\":-1}", tex0,
                         "good.png", NULL, (const char *const[]){ "alphaCutoff -1", NULL });
    expect_refused_scene("occlusion_strength",
                         "{\"occlusionTexture\":{\"index\":0,\"strength\":3}}", tex0, "good.png",
                         NULL, (const char *const[]){ "occlusionTexture: strength 3", NULL });
    alarm(0);
}

/* ---- tangents -------------------------------------------------------------------------------- */

/* The angle (degrees) between two tangents' xyz, and whether their w agree. */
static double tangent_angle(const float *a, const float *b)
{
    double d = (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
    return acos(d > 1 ? 1 : d < -1 ? -1 : d) * (180.0 / LG_PI);
}

static bool unit_orthogonal(const lg_mesh *m, uint32_t v, double tol)
{
    const float *t = m->tangents + 4 * (size_t)v, *n = m->normals + 3 * (size_t)v;
    double len = sqrt((double)t[0] * t[0] + (double)t[1] * t[1] + (double)t[2] * t[2]);
    double dot = (double)t[0] * n[0] + (double)t[1] * n[1] + (double)t[2] * n[2];
    return fabs(len - 1) < tol && fabs(dot) < tol && (t[3] == 1.0f || t[3] == -1.0f);
}

/* The vertex of mesh m nearest (position and texture coordinates) to vertex v of mesh r. */
static uint32_t match_vertex(const lg_mesh *m, const lg_mesh *r, uint32_t v)
{
    uint32_t best = 0;
    double bd = INFINITY;
    for (uint32_t i = 0; i < m->n_vertices; i++) {
        double d = 0;
        for (int k = 0; k < 3; k++)
            d += pow(m->positions[3 * i + k] - r->positions[3 * v + k], 2);
        for (int k = 0; k < 2; k++)
            d += pow(m->texcoords[2 * i + k] - r->texcoords[2 * v + k], 2);
        if (d < bd)
            bd = d, best = i;
    }
    return best;
}

/* A Draco primitive whose extension lists TEXCOORD_1 and TANGENT: both decoded (exactly:
 * no quantisation), the tangents made unit with w = -1 from the file's (3, 0, 0, -2). */
static void draco_attributes(void)
{
    static const float pos[18] = { 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0 };
    float nrm[18], uv0[12], uv1[12], tan[24];
    for (int c = 0; c < 6; c++) {
        memcpy(nrm + 3 * c, (const float[3]){ 0, 0, 1 }, sizeof(float[3]));
        uv0[2 * c] = pos[3 * c], uv0[2 * c + 1] = 1 - pos[3 * c + 1];
        uv1[2 * c] = 0.25f + 0.5f * pos[3 * c], uv1[2 * c + 1] = 0.75f * pos[3 * c + 1];
        memcpy(tan + 4 * c, (const float[4]){ 3, 0, 0, -2 }, sizeof(float[4]));
    }
    uint8_t *drc = NULL;
    size_t n = 0;
    int ids[5];
    CHECK(gt_draco_encode(2, pos, nrm, uv0, uv1, tan, &drc, &n, ids) == 0);
    if (!drc)
        return;
    char *uri = gt_data_uri(drc, n);
    char *json = gt_fmt(
        "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"KHR_draco_mesh_compression\"],"
        "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{"
        "\"attributes\":{\"POSITION\":0,\"NORMAL\":1,\"TEXCOORD_0\":2,\"TEXCOORD_1\":3,"
        "\"TANGENT\":4},\"extensions\":{\"KHR_draco_mesh_compression\":{\"bufferView\":0,"
        "\"attributes\":{\"POSITION\":%d,\"NORMAL\":%d,\"TEXCOORD_0\":%d,\"TEXCOORD_1\":%d,"
        "\"TANGENT\":%d}}}}]}],\"buffers\":[{\"uri\":\"%s\",\"byteLength\":%zu}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu}],\"accessors\":["
        "{\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]},"
        "{\"componentType\":5126,\"count\":4,\"type\":\"VEC3\"},"
        "{\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
        "{\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},"
        "{\"componentType\":5126,\"count\":4,\"type\":\"VEC4\"}]}",
        ids[0], ids[1], ids[2], ids[3], ids[4], uri, n, n);
    free(uri);
    free(drc);
    lg_scene *s = load_json("draco_attrs.gltf", json);
    free(json);
    if (!s)
        return;
    const lg_mesh *m = &s->meshes[0];
    CHECKF(m->texcoords1 && m->tangents && m->n_indices == 6, "Draco: texcoords1 %p tangents %p",
           (const void *)m->texcoords1, (const void *)m->tangents);
    for (uint32_t v = 0; m->texcoords1 && m->tangents && v < m->n_vertices; v++) {
        const float *p = m->positions + 3 * v, *u1 = m->texcoords1 + 2 * v;
        const float *t = m->tangents + 4 * v;
        CHECKF(u1[0] == 0.25f + 0.5f * p[0] && u1[1] == 0.75f * p[1],
               "Draco vertex %u (%g, %g): TEXCOORD_1 %g %g", v, p[0], p[1], u1[0], u1[1]);
        CHECKF(t[0] == 1 && t[1] == 0 && t[2] == 0 && t[3] == -1,
               "Draco vertex %u: tangent %g %g %g %g", v, t[0], t[1], t[2], t[3]);
    }
    lg_gltf_scene_free(s);
}

static void case_tangents(void)
{
    draco_attributes();
    /* the sphere as shipped (its exporter's MikkTSpace tangents) and without TANGENT */
    int rc = 0;
    lg_scene *ref = NULL, *gen = NULL;
    rc = lg_gltf_load(gt_asset("meshes/sphere/sphere.gltf"), NULL, &ref, NULL, err, sizeof err);
    CHECKF(rc == 0, "sphere: %s", err);
    size_t n;
    char *json = (char *)gt_read(gt_asset("meshes/sphere/sphere.gltf"), &n);
    char *tan = strstr(json, "\"TANGENT\": 4");
    CHECK(tan != NULL);
    if (tan)
        memcpy(tan, "\"TANGENX\"", 9); /* an attribute the loader does not read */
    gt_write("sphere.gltf", json, n);
    free(json);
    uint8_t *b = gt_read(gt_asset("meshes/sphere/sphere_buffer0.bin"), &n);
    gt_write("sphere_buffer0.bin", b, n);
    free(b);
    b = gt_read(gt_asset("meshes/sphere/sphere_Texture0_Normal.png"), &n);
    gt_write("sphere_Texture0_Normal.png", b, n);
    free(b);
    b = gt_read(gt_asset("meshes/sphere/sphere_Texture1_BaseColor.png"), &n);
    gt_write("sphere_Texture1_BaseColor.png", b, n);
    free(b);
    rc = lg_gltf_load(gt_path("sphere.gltf"), NULL, &gen, NULL, err, sizeof err);
    CHECKF(rc == 0, "stripped sphere: %s", err);
    if (ref && gen) {
        const lg_mesh *r = &ref->meshes[0], *g = &gen->meshes[0];
        CHECKF(r->tangents && g->tangents, "tangents: file %p, generated %p", (void *)r->tangents,
               (void *)g->tangents);
        if (r->tangents && g->tangents) {
            double worst = 0, sum = 0;
            uint32_t w_differ = 0, bad = 0;
            for (uint32_t v = 0; v < r->n_vertices; v++) {
                uint32_t i = match_vertex(g, r, v);
                double a = tangent_angle(r->tangents + 4 * v, g->tangents + 4 * i);
                worst = fmax(worst, a);
                sum += a;
                w_differ += r->tangents[4 * v + 3] != g->tangents[4 * i + 3];
                bad += !unit_orthogonal(r, v, 1e-5) || !unit_orthogonal(g, i, 1e-5);
            }
            printf("sphere: %u vertices (file), %u (generated); tangent angle to the file's: "
                   "max %.3f deg, mean %.3f deg; w differs at %u\n",
                   r->n_vertices, g->n_vertices, worst, sum / r->n_vertices, w_differ);
            CHECKF(bad == 0, "%u tangents not unit, orthogonal, w = +-1", bad);
            CHECKF(w_differ == 0, "handedness differs from the file's at %u vertices", w_differ);
            CHECKF(worst < TANGENT_MAX_DEG, "max angle %.3f deg (bound %g, measured)", worst,
                   TANGENT_MAX_DEG);
        }
    }
    lg_gltf_scene_free(ref);
    lg_gltf_scene_free(gen);

    /* a mirrored UV seam: u = |x| on a 2 x 1 strip, so the left half's tangent is -x and
     * the right half's +x with opposite handedness; the middle column's two vertices are
     * shared by both halves and must be split (6 vertices become 8) */
    size_t pn;
    uint8_t *png = checker_png(4, 4, &pn);
    gt_write("checker.png", png, pn);
    free(png);
    static const float pos[18] = { -1, 0, 0, 0, 0, 0, 1, 0, 0, -1, 1, 0, 0, 1, 0, 1, 1, 0 };
    static const float nrm[18] = { 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1 };
    static const float uv[12] = { 1, 1, 0, 1, 1, 1, 1, 0, 0, 0, 1, 0 };
    static const uint32_t idx[12] = { 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4 };
    static const char *const nmat = "{\"normalTexture\":{\"index\":0,\"scale\":0.5}}";
    json = mesh_scene(6, pos, nrm, uv, NULL, 12, idx, nmat);
    lg_scene *s = NULL;
    s = gt_load_text("mirror.gltf", json, NULL, err, sizeof err, &rc);
    free(json);
    CHECKF(s, "mirror: %s", err);
    if (s) {
        const lg_mesh *m = &s->meshes[0];
        CHECKF(m->n_vertices == 8 && m->tangents, "mirror: %u vertices (want 8: 2 split)",
               m->n_vertices);
        CHECKF(lg_material_maps_of(&s->materials[0])->normal.scale == 0.5f, "normal scale");
        for (uint32_t c = 0; m->tangents && c < m->n_indices; c++) {
            uint32_t v = m->indices[c];
            const float *t = m->tangents + 4 * (size_t)v;
            bool left = c < 6; /* triangles 0 and 1 lie at x <= 0 */
            CHECKF(fabsf(t[0] - (left ? -1.0f : 1.0f)) < 1e-6f && fabsf(t[1]) < 1e-6f &&
                       fabsf(t[2]) < 1e-6f,
                   "mirror corner %u (vertex %u): tangent %g %g %g", c, v, t[0], t[1], t[2]);
            /* B = w (N x T) must point up the image (decreasing v: +y here) */
            lg_vec3 bt = lg_v3_scale(lg_v3_cross(lg_v3(0, 0, 1), lg_v3(t[0], t[1], t[2])), t[3]);
            CHECKF(bt.y > 0.99f, "mirror corner %u: bitangent %g %g %g", c, bt.x, bt.y, bt.z);
            CHECKF(m->positions[3 * v] == pos[3 * idx[c]] &&
                       m->positions[3 * v + 1] == pos[3 * idx[c] + 1],
                   "mirror corner %u keeps its position", c);
        }
        lg_gltf_scene_free(s);
    }

    /* a file's tangent that is neither unit nor orthogonal, with w -0.3: made (1, 0, 0, -1) */
    static const float ftan[12] = { 2, 0, 0.5f, -0.3f, 2, 0, 0.5f, -0.3f, 2, 0, 0.5f, -0.3f };
    static const float tpos[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 }, tuv[6] = { 0, 1, 1, 1, 0, 0 };
    static const uint32_t tidx[3] = { 0, 1, 2 };
    json = mesh_scene(3, tpos, nrm, tuv, ftan, 3, tidx, nmat);
    s = gt_load_text("filetan.gltf", json, NULL, err, sizeof err, &rc);
    free(json);
    CHECKF(s, "file tangents: %s", err);
    if (s) {
        const float *t = s->meshes[0].tangents;
        CHECKF(t && fabsf(t[0] - 1) < 1e-6f && fabsf(t[2]) < 1e-6f && t[3] == -1.0f,
               "file tangent made %g %g %g %g", t ? t[0] : 0, t ? t[1] : 0, t ? t[2] : 0,
               t ? t[3] : 0);
        lg_gltf_scene_free(s);
    }

    /* a normal texture on a mesh without TEXCOORD_0: a warning, and the mesh draws a copy
     * of its material without the normal map (the base colour map stays) */
    lg_gltf_options opt = lg_gltf_default_options();
    opt.warn = on_warning;
    n_warnings = 0;
    json = mesh_scene(3, tpos, nrm, NULL, NULL, 3, tidx,
                      "{\"name\":\"bumpy\",\"normalTexture\":{\"index\":0},"
                      "\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}");
    s = gt_load_text("nouv.gltf", json, &opt, err, sizeof err, &rc);
    free(json);
    CHECKF(s, "no TEXCOORD_0: %s", err);
    if (s) {
        const lg_mesh *m = &s->meshes[0];
        const lg_material_maps *mp = lg_material_maps_of(&s->materials[m->material]);
        CHECKF(!m->tangents && m->material == 1 && s->n_materials == 2 &&
                   mp->normal.texture == -1 && mp->base_color.texture == 0 &&
                   lg_material_maps_of(&s->materials[0])->normal.texture == 0 &&
                   !strcmp(s->materials[1].name, "bumpy"),
               "no TEXCOORD_0: material %u of %u, normal %d, base %d", m->material, s->n_materials,
               mp->normal.texture, mp->base_color.texture);
        CHECKF(n_warnings == 1 && strstr(last_warning, "TEXCOORD_0") &&
                   strstr(last_warning, "normal map is ignored"),
               "no TEXCOORD_0: %d warnings, '%s'", n_warnings, last_warning);
        lg_gltf_scene_free(s);
    }
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*fn)(void);
    } cases[] = {
        { "assets", case_assets },
        { "checker", case_checker },
        { "tangents", case_tangents },
        { "bad", case_bad },
    };
    if (argc != 2) {
        fprintf(stderr, "usage: test_gltf_textures CASE\n");
        return 2;
    }
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++)
        if (!strcmp(argv[1], cases[i].name)) {
            gt_init(cases[i].name);
            cases[i].fn();
            gt_cleanup(check_failures != 0);
            return check_report(argv[1]);
        }
    fprintf(stderr, "test_gltf_textures: unknown case '%s'\n", argv[1]);
    return 2;
}
