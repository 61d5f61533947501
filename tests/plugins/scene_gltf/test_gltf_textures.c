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
 *              the wrap modes; TEXCOORD_1; alpha modes; unused images not read
 *   bad        hard cases (suite stability): a corrupt PNG, a truncated JPEG, an image uri
 *              leaving the folder, a FIFO image, a huge claimed size, texCoord 2, texture,
 *              image and sampler indices out of range, a non-finite texture transform, a
 *              bad alphaMode, a missing image file: each refused with a message naming the
 *              file, the image or material and why
 *   tangents   the sphere's own TANGENTs against MikkTSpace-style tangents regenerated
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
#include "gltf_test.h"
#include "lightgraph/vecmath.h"

static char err[2048];

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
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*fn)(void);
    } cases[] = {
        { "assets", case_assets },
        { "checker", case_checker },
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
