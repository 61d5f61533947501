/*
 * tests/fuzz/fuzz_gltf.c: the `gltf` node's loader (plugins/scene_gltf: gltf_load.c,
 * gltf_normals.c, and tinygltf and libdraco behind gltf_shim.cpp) on arbitrary bytes.
 *
 * Each input is loaded from memory with lg_gltf_load_memory, named .glb or .gltf and with
 * normals auto, smooth or flat by turns. Every fourth input is given a folder for external
 * files (a scratch folder made once: tri.bin, sub/tri.bin, tex.png and sub/tex.png (a 4 x 4
 * RGBA PNG), a link to tri.bin, a link to /etc/passwd, a link to /dev/zero and a FIFO), so
 * that the uri checks and the confined, bounded reads are fuzzed too; the others have none.
 * A load must either fail with a message naming the file, or return a scene whose every
 * index is in range (textures, images and material maps included) and whose every position
 * and normal is finite (normals unit length, tangents unit with w = +-1, decoded images with
 * their pixels); anything else aborts, and the sanitizers catch the rest (libpng and
 * libjpeg on mutated images too). A load that waits on the FIFO hangs the run (a finding).
 *
 * A failed check prints what failed and aborts; LG_FUZZ_DUMP=FILE also writes the input to
 * FILE, to replay it with `fuzz_gltf FILE`.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_gltf, see its README) to the plain driver
 * (fuzz_driver.h) with a dictionary of glTF tokens:
 *
 *     fuzz_gltf [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fuzz_driver.h"
#include "gltf_load.h"

static unsigned long n_runs, n_ok, n_folder_ok;
static char folder[4096];

static void remove_folder(void)
{
    static const char *const names[] = { "tri.bin",     "sub/tri.bin", "tex.png",
                                         "sub/tex.png", "sub",         "inside.bin",
                                         "outside.bin", "zero.bin",    "fifo.bin" };
    char p[4200];
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        snprintf(p, sizeof p, "%s/%s", folder, names[i]);
        remove(p);
    }
    remove(folder);
}

/* The folder for external files, made on first use (see the top of the file). */
static const char *external_folder(void)
{
    if (folder[0])
        return folder;
    const char *tmp = getenv("TMPDIR");
    snprintf(folder, sizeof folder, "%s/lg-fuzz-gltf-XXXXXX", tmp && tmp[0] == '/' ? tmp : "/tmp");
    if (!mkdtemp(folder)) {
        perror("fuzz_gltf: mkdtemp");
        exit(2);
    }
    atexit(remove_folder);
    static const float tri[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    char p[4200], q[4200];
    snprintf(p, sizeof p, "%s/sub", folder);
    int bad = mkdir(p, 0700);
    for (int k = 0; k < 2 && !bad; k++) {
        snprintf(p, sizeof p, k ? "%s/sub/tri.bin" : "%s/tri.bin", folder);
        FILE *f = fopen(p, "wb");
        bad = !f || fwrite(tri, 1, sizeof tri, f) != sizeof tri || fclose(f);
    }
    /* a 4 x 4 RGBA PNG for the image uris (corpus_gltf/textured_external.gltf) */
    static const uint8_t tex[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
        0x52, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x00, 0x04, 0x08, 0x06, 0x00, 0x00, 0x00, 0xa9,
        0xf1, 0x9e, 0x7e, 0x00, 0x00, 0x00, 0x3a, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x15, 0xca,
        0xb1, 0x11, 0x00, 0x20, 0x08, 0x04, 0xb0, 0x87, 0x16, 0x5a, 0x68, 0x65, 0xff, 0x49, 0x54,
        0x86, 0xc2, 0xb7, 0xcd, 0x05, 0xa2, 0xd8, 0xa6, 0x73, 0x42, 0x71, 0x97, 0x4e, 0x43, 0x7c,
        0xb6, 0x39, 0x4e, 0xf8, 0xdc, 0xe5, 0x20, 0x24, 0x47, 0x72, 0x24, 0x47, 0xfe, 0x51, 0x1c,
        0xc5, 0x51, 0x1c, 0x85, 0x7e, 0xdc, 0x12, 0x16, 0xa1, 0x96, 0x93, 0x57, 0x2e, 0x00, 0x00,
        0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82
    };
    for (int k = 0; k < 2 && !bad; k++) {
        snprintf(p, sizeof p, k ? "%s/sub/tex.png" : "%s/tex.png", folder);
        FILE *f = fopen(p, "wb");
        bad = !f || fwrite(tex, 1, sizeof tex, f) != sizeof tex || fclose(f);
    }
    static const char *const links[][2] = { { "tri.bin", "inside.bin" },
                                            { "/etc/passwd", "outside.bin" },
                                            { "/dev/zero", "zero.bin" } };
    for (size_t i = 0; i < 3 && !bad; i++) {
        snprintf(q, sizeof q, "%s/%s", folder, links[i][1]);
        bad = symlink(links[i][0], q) != 0;
    }
    snprintf(p, sizeof p, "%s/fifo.bin", folder);
    if (bad || mkfifo(p, 0600) != 0) {
        perror("fuzz_gltf: making the external folder");
        exit(2);
    }
    return folder;
}
static const uint8_t *cur_data;
static size_t cur_size;

/* Stops with the input that did it; with LG_FUZZ_DUMP=FILE set, writes the input there. */
static void bad(const char *what)
{
    fprintf(stderr, "fuzz_gltf: %s (input %lu, %zu bytes)\n", what, n_runs - 1, cur_size);
    const char *dump = getenv("LG_FUZZ_DUMP");
    FILE *f = dump && *dump ? fopen(dump, "wb") : NULL;
    if (f) {
        fwrite(cur_data, 1, cur_size, f);
        fclose(f);
        fprintf(stderr, "fuzz_gltf: input written to %s\n", dump);
    }
    abort();
}

/* Every texture reference, texture and image in range; every image has its pixels. */
static void check_textures(const lg_scene *s)
{
    const lg_scene_textures *t = s->textures;
    uint32_t n_tex = t ? t->n_textures : 0;
    for (uint32_t i = 0; i < s->n_materials; i++) {
        const lg_material_maps *mp = lg_material_maps_of(&s->materials[i]);
        const lg_texture_ref *refs[5] = { &mp->base_color, &mp->metallic_roughness, &mp->normal,
                                          &mp->occlusion, &mp->emissive };
        for (int k = 0; k < 5; k++) {
            if (refs[k]->texture >= (int32_t)n_tex || refs[k]->texture < -1 ||
                refs[k]->texcoord > 1)
                bad("texture reference out of range");
            for (int j = 0; j < 6; j++)
                if (!isfinite(refs[k]->transform[j]))
                    bad("non-finite texture transform");
        }
        if (mp->alpha_mode > LG_ALPHA_BLEND || !isfinite(mp->alpha_cutoff))
            bad("alpha mode or cutoff");
    }
    if (!t)
        return;
    uint64_t bytes = 0;
    for (uint32_t i = 0; i < t->n_textures; i++)
        if (t->textures[i].image >= t->n_images)
            bad("texture of an image that does not exist");
    for (uint32_t i = 0; i < t->n_images; i++) {
        const lg_scene_image *im = &t->images[i];
        if (!im->rgba8 || !im->width || !im->height || !im->name)
            bad("image without pixels or name");
        bytes += (uint64_t)im->width * im->height * 4;
        /* touch the first and last texel: the sanitizers see a short buffer */
        volatile uint8_t x = im->rgba8[0] ^ im->rgba8[(size_t)im->width * im->height * 4 - 1];
        (void)x;
    }
    if (bytes != t->bytes)
        bad("lg_scene_textures.bytes disagrees with the images");
}

static void check_scene(const lg_scene *s)
{
    if (s->struct_size != sizeof *s || !s->n_materials || !s->n_cameras ||
        s->camera >= s->n_cameras)
        bad("scene without materials or cameras");
    uint64_t tris = 0;
    for (uint32_t i = 0; i < s->n_instances; i++) {
        if (s->instances[i].mesh >= s->n_meshes)
            bad("instance of a mesh that does not exist");
        tris += s->meshes[s->instances[i].mesh].n_indices / 3;
        for (int k = 0; k < 16; k++)
            if (!isfinite(s->instances[i].model[k]))
                bad("non-finite instance matrix");
    }
    if (tris != s->features.triangles)
        bad("features.triangles disagrees with the instances");
    for (uint32_t i = 0; i < s->n_meshes; i++) {
        const lg_mesh *m = &s->meshes[i];
        if (m->material >= s->n_materials || m->n_indices % 3 || !m->name)
            bad("mesh material, index count or name");
        for (uint32_t k = 0; k < m->n_indices; k++)
            if (m->indices[k] >= m->n_vertices)
                bad("index out of range");
        for (uint32_t v = 0; v < m->n_vertices; v++) {
            const float *p = m->positions + 3 * (size_t)v, *n = m->normals + 3 * (size_t)v;
            float l = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if (!isfinite(p[0] + p[1] + p[2]) || !(fabsf(l - 1) < 1e-3f))
                bad("non-finite position or non-unit normal");
            if (m->texcoords &&
                !isfinite(m->texcoords[2 * (size_t)v] + m->texcoords[2 * (size_t)v + 1]))
                bad("non-finite texture coordinate");
            if (m->texcoords1 &&
                !isfinite(m->texcoords1[2 * (size_t)v] + m->texcoords1[2 * (size_t)v + 1]))
                bad("non-finite TEXCOORD_1");
            if (m->tangents) {
                const float *t = m->tangents + 4 * (size_t)v;
                float tl = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
                if (!(fabsf(tl - 1) < 1e-3f) || (t[3] != 1.0f && t[3] != -1.0f))
                    bad("tangent not unit or w not +-1");
            }
        }
    }
    check_textures(s);
    for (uint32_t i = 0; i < s->n_lights; i++) {
        const lg_light *l = &s->lights[i];
        if (!isfinite(l->direction[0] + l->direction[1] + l->direction[2] + l->position[0] +
                      l->position[1] + l->position[2] + l->intensity))
            bad("non-finite light");
    }
    for (uint32_t i = 0; i < s->n_cameras; i++) {
        const lg_camera *c = &s->cameras[i];
        if (!isfinite(c->position[0] + c->position[1] + c->position[2] + c->target[0] +
                      c->target[1] + c->target[2] + c->yfov))
            bad("non-finite camera");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    unsigned long run = n_runs++;
    cur_data = data;
    cur_size = size;
    lg_gltf_options opt = lg_gltf_default_options();
    opt.normals = (lg_gltf_normals)(run % 3);
    opt.crease_deg = run % 2 ? 60 : 120;
    const char *name = size >= 4 && !memcmp(data, "glTF", 4) ? "in.glb"
                       : run % 5 == 0                        ? "in.glb"
                                                             : "in.gltf";
    char err[1024];
    err[0] = 0;
    lg_scene *s = NULL;
    uint64_t hash = 0;
    const char *base = run % 4 == 3 ? external_folder() : NULL;
    int rc = lg_gltf_load_memory(data, size, name, base, &opt, &s, &hash, err, sizeof err);
    if (rc) {
        if (rc >= 0 || s || strncmp(err, "file 'in.gl", 11) != 0)
            bad("a failure without a message naming the file, or with a scene");
        return 0;
    }
    n_ok++;
    n_folder_ok += base != NULL;
    check_scene(s);
    lg_gltf_scene_free(s);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* Pieces of glTF JSON and GLB for the driver's "insert a token" edit: property names the
 * loader reads, boundary numbers, chunk types. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("\"bufferView\":"),
    LG_FUZZ_TOKEN("\"byteOffset\":"),
    LG_FUZZ_TOKEN("\"byteLength\":"),
    LG_FUZZ_TOKEN("\"byteStride\":"),
    LG_FUZZ_TOKEN("\"count\":"),
    LG_FUZZ_TOKEN("\"componentType\":"),
    LG_FUZZ_TOKEN("\"type\":\"VEC3\""),
    LG_FUZZ_TOKEN("\"type\":\"SCALAR\""),
    LG_FUZZ_TOKEN("\"indices\":"),
    LG_FUZZ_TOKEN("\"mode\":"),
    LG_FUZZ_TOKEN("\"children\":["),
    LG_FUZZ_TOKEN("\"mesh\":"),
    LG_FUZZ_TOKEN("\"matrix\":["),
    LG_FUZZ_TOKEN("\"rotation\":["),
    LG_FUZZ_TOKEN("\"sparse\":{"),
    LG_FUZZ_TOKEN("\"normalized\":true"),
    LG_FUZZ_TOKEN("\"KHR_draco_mesh_compression\""),
    LG_FUZZ_TOKEN("\"KHR_lights_punctual\""),
    LG_FUZZ_TOKEN("\"extensionsRequired\":["),
    LG_FUZZ_TOKEN("\"extras\":{\"medium\":{"),
    LG_FUZZ_TOKEN("\"camera\":"),
    LG_FUZZ_TOKEN("\"scene\":"),
    LG_FUZZ_TOKEN("\"material\":"),
    LG_FUZZ_TOKEN("\"uri\":\"data:application/octet-stream;base64,"),
    LG_FUZZ_TOKEN("\"uri\":\"tri.bin\""),
    LG_FUZZ_TOKEN("\"uri\":\"sub/tri.bin\""),
    LG_FUZZ_TOKEN("../"),
    LG_FUZZ_TOKEN("%2e%2e/"),
    LG_FUZZ_TOKEN("%"),
    LG_FUZZ_TOKEN("inside.bin"),
    LG_FUZZ_TOKEN("outside.bin"),
    LG_FUZZ_TOKEN("zero.bin"),
    LG_FUZZ_TOKEN("fifo.bin"),
    LG_FUZZ_TOKEN("\"images\":[{\"uri\":\""),
    LG_FUZZ_TOKEN("tex.png"),
    LG_FUZZ_TOKEN("\"textures\":[{\"source\":"),
    LG_FUZZ_TOKEN("\"sampler\":"),
    LG_FUZZ_TOKEN("\"baseColorTexture\":{\"index\":"),
    LG_FUZZ_TOKEN("\"normalTexture\":{\"index\":0}"),
    LG_FUZZ_TOKEN("\"texCoord\":"),
    LG_FUZZ_TOKEN("\"KHR_texture_transform\":{\"rotation\":"),
    LG_FUZZ_TOKEN("\"alphaMode\":\"MASK\""),
    LG_FUZZ_TOKEN("\"TANGENT\":"),
    LG_FUZZ_TOKEN("\"TEXCOORD_1\":"),
    LG_FUZZ_TOKEN("IHDR"),
    LG_FUZZ_TOKEN("IDAT"),
    LG_FUZZ_TOKEN("\xff\xd8\xff"),
    LG_FUZZ_TOKEN("file:///"),
    LG_FUZZ_TOKEN("5120"),
    LG_FUZZ_TOKEN("5121"),
    LG_FUZZ_TOKEN("5123"),
    LG_FUZZ_TOKEN("5125"),
    LG_FUZZ_TOKEN("5126"),
    LG_FUZZ_TOKEN("5127"),
    LG_FUZZ_TOKEN("-1"),
    LG_FUZZ_TOKEN("4294967295"),
    LG_FUZZ_TOKEN("2147483647"),
    LG_FUZZ_TOKEN("1e308"),
    LG_FUZZ_TOKEN("[[[[[[[["),
    LG_FUZZ_TOKEN("glTF\x02\0\0\0"),
    LG_FUZZ_TOKEN("JSON"),
    LG_FUZZ_TOKEN("BIN\0"),
    LG_FUZZ_TOKEN("DRACO"),
};

static void summary(FILE *out)
{
    fprintf(out, "%lu loaded (%lu with the external folder)", n_ok, n_folder_ok);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_gltf",
        .mutations = 300,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .head = 0,
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
