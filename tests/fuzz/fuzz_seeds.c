/*
 * tests/fuzz/fuzz_seeds.c: writes the seed corpora of fuzz_cache and fuzz_registry, whose
 * inputs are binary formats the host writes itself (docs/fuzzing.md, "Seeds"):
 *
 *     fuzz_seeds cache DIR
 *     fuzz_seeds registry DIR PLUGIN.so...
 *     fuzz_seeds cache_kinds DIR
 *     fuzz_seeds probe DIR
 *
 * cache: an entry for the identity and key of fuzz_seeds.h written by the host's own
 * encoder (lg_cache_entry_encode), an empty one, and broken ones: truncated, padded, wrong
 * magic, another format version, a stale identity, another key, a bad checksum, and a
 * declared payload of 2^63 bytes.
 *
 * registry: each plugin's scan result as the scanning child writes it (lg_registry_encode of
 * its validated descriptor), NAME.scan; then, written by hand here with the same layout, a
 * small valid result and broken ones: truncated, with bytes after it, huge counts and string
 * lengths, an enum default whose name and index disagree, a NULL inside a list, a bool byte
 * that is not 0 or 1, an unknown neutral result.
 *
 * cache_kinds: per kind of plugin cache payload (fuzz_cache_kinds.c) and per config of
 * fuzz_seeds.h, the payload the plugin's own encoder writes, with the kind and config
 * bytes before it; then broken ones: a NaN, an infinity, another magic or version, 65
 * bounces, a float short, a chain's header for another level count.
 *
 * probe: small probe images in every layout (lat-long, angular, horizontal and vertical
 * cross, 6x1 and 1x6 strip) as EXR, HDR and PNG, written by the SDK's own writer; a float
 * EXR of three of them with a negative, a NaN and an infinite texel; and shapes the probe
 * node refuses (10x7, 17x8 near 2:1) or reads in a corner case (1x1).
 *
 * The files are committed; run this again when a format or a plugin's schema changes.
 */
#include <dlfcn.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_seeds.h"
#include "ibl_cache.h"
#include "pb_cache.h"
#include "exec/exec.h"
#include "lightgraph/image.h"

static int write_seed(const char *dir, const char *name, const void *data, size_t n)
{
    char *path = lg_path_join(dir, name);
    FILE *f = fopen(path, "wb");
    int rc = f && fwrite(data, 1, n, f) == n ? 0 : -1;
    if (f && fclose(f) != 0)
        rc = -1;
    if (rc)
        perror(path);
    else
        printf("%s (%zu bytes)\n", path, n);
    free(path);
    return rc;
}

/* ---- cache ----------------------------------------------------------------------------------- */

static int cache_seeds(const char *dir)
{
    const lg_digest id = LG_FUZZ_CACHE_IDENTITY;
    const char *key = LG_FUZZ_CACHE_KEY;
    size_t klen = strlen(key), head = 8 + 4 + 16 + 4 + klen + 8 + 8;
    char payload[96];
    for (size_t i = 0; i < sizeof payload; i++)
        payload[i] = (char)(i * 37 + 11);
    lg_str e = { 0 }, empty = { 0 };
    lg_cache_entry_encode(&e, &id, key, payload, sizeof payload);
    lg_cache_entry_encode(&empty, &id, key, NULL, 0);
    int rc = write_seed(dir, "valid.lgc", e.s, e.len);
    rc |= write_seed(dir, "valid_empty.lgc", empty.s, empty.len);
    rc |= write_seed(dir, "truncated.lgc", e.s, e.len - 17);
    rc |= write_seed(dir, "truncated_header.lgc", e.s, head - 3);
    char *b = lg_xmalloc(e.len + 8);
    memcpy(b, e.s, e.len);
    memcpy(b + e.len, "PADDING!", 8);
    rc |= write_seed(dir, "padded.lgc", b, e.len + 8);
    memcpy(b, e.s, e.len);
    b[3] ^= 0x20; /* "LGcACHE\1" */
    rc |= write_seed(dir, "wrong_magic.lgc", b, e.len);
    memcpy(b, e.s, e.len);
    b[8] = 2; /* format version 2 */
    rc |= write_seed(dir, "other_version.lgc", b, e.len);
    memcpy(b, e.s, e.len);
    b[12] ^= 1; /* the identity */
    rc |= write_seed(dir, "stale_identity.lgc", b, e.len);
    memcpy(b, e.s, e.len);
    b[32] ^= 1; /* the key's first byte */
    rc |= write_seed(dir, "other_key.lgc", b, e.len);
    memcpy(b, e.s, e.len);
    b[e.len - 1] ^= 1; /* the payload's last byte */
    rc |= write_seed(dir, "bad_checksum.lgc", b, e.len);
    memcpy(b, e.s, e.len);
    uint64_t huge = (uint64_t)1 << 63;
    memcpy(b + 32 + klen, &huge, 8); /* declares 8 EiB */
    rc |= write_seed(dir, "huge_size.lgc", b, e.len);
    free(b);
    lg_str_free(&e);
    lg_str_free(&empty);
    return rc;
}

/* ---- registry -------------------------------------------------------------------------------- */

static void u32(lg_str *b, uint32_t v)
{
    lg_str_addn(b, (const char *)&v, 4);
}

static void str(lg_str *b, const char *s)
{
    if (!s) {
        u32(b, UINT32_MAX);
        return;
    }
    u32(b, (uint32_t)strlen(s));
    lg_str_add(b, s);
}

/* What a variant of the small result changes. */
typedef struct mini {
    int32_t enum_index; /* the enum default's index (its name is "b", index 1) */
    bool null_in_list;  /* renamed_from ["old", NULL, "older"] */
    unsigned char bool_byte;
    uint32_t neutral;
    uint32_t n_inputs; /* declared; one is written */
    uint32_t n_params; /* declared; three are written */
} mini;

/* A plugin "mini" with one node type "t": parameters bool `on`, enum `mode` (a, b; default
 * b) and float `gain` in [0, 2], one image input and one image output. */
static void mini_result(lg_str *b, const mini *m)
{
    lg_str_addn(b, "LGSCAN2", 8);
    u32(b, LG_ABI_MAJOR);
    u32(b, LG_ABI_MINOR);
    str(b, "mini");
    str(b, "1.0");
    str(b, NULL);
    u32(b, 1);
    str(b, "t");
    str(b, "a node type");
    u32(b, 0);          /* needs */
    u32(b, 0);          /* flags */
    u32(b, m->neutral); /* neutral */
    u32(b, 0);          /* neutral_input */
    u32(b, m->n_params);
    lg_value v;
    double lo = 0, hi = 2, none = 0;

    str(b, "on");
    u32(b, LG_PARAM_BOOL);
    memset(&v, 0, sizeof v);
    v.type = LG_PARAM_BOOL;
    memcpy(&v.b, &m->bool_byte, 1);
    lg_str_addn(b, (const char *)&v, sizeof v);
    str(b, NULL);
    lg_str_addn(b, (const char *)&none, 8);
    lg_str_addn(b, (const char *)&none, 8);
    u32(b, UINT32_MAX); /* enum_values */
    str(b, "switch");
    if (m->null_in_list) {
        u32(b, 3);
        str(b, "old");
        str(b, NULL);
        str(b, "older");
    } else {
        u32(b, UINT32_MAX);
    }
    u32(b, 0); /* role */

    str(b, "mode");
    u32(b, LG_PARAM_ENUM);
    memset(&v, 0, sizeof v);
    v.type = LG_PARAM_ENUM;
    v.e = m->enum_index;
    lg_str_addn(b, (const char *)&v, sizeof v);
    str(b, "b");
    lg_str_addn(b, (const char *)&none, 8);
    lg_str_addn(b, (const char *)&none, 8);
    u32(b, 2);
    str(b, "a");
    str(b, "b");
    str(b, "how");
    u32(b, UINT32_MAX);
    u32(b, 0); /* role */

    str(b, "gain");
    u32(b, LG_PARAM_FLOAT);
    memset(&v, 0, sizeof v);
    v.type = LG_PARAM_FLOAT;
    v.f = 1;
    lg_str_addn(b, (const char *)&v, sizeof v);
    str(b, NULL);
    lg_str_addn(b, (const char *)&lo, 8);
    lg_str_addn(b, (const char *)&hi, 8);
    u32(b, UINT32_MAX);
    str(b, "linear factor");
    u32(b, UINT32_MAX);
    u32(b, 0); /* role */

    u32(b, m->n_inputs);
    str(b, "image");
    u32(b, LG_KIND_IMAGE);
    u32(b, 0);
    str(b, NULL);
    u32(b, 1);
    str(b, "out");
    u32(b, LG_KIND_IMAGE);
    u32(b, 0);
    str(b, NULL);
}

static int registry_seeds(const char *dir, int n, char **plugins)
{
    int rc = 0;
    lg_str first = { 0 };
    for (int i = 0; i < n; i++) {
        void *h = dlopen(plugins[i], RTLD_NOW | RTLD_LOCAL);
        lg_plugin_entry_fn entry = h ? (lg_plugin_entry_fn)(uintptr_t)dlsym(h, LG_PLUGIN_ENTRY_NAME)
                                     : NULL;
        const lg_plugin_desc *d = entry ? entry() : NULL;
        char err[512];
        if (!d || lg_descriptor_validate(d, plugins[i], err, sizeof err) != 0) {
            fprintf(stderr, "fuzz_seeds: %s: %s\n", plugins[i], d ? err : dlerror());
            rc = -1;
            continue;
        }
        lg_str b = { 0 };
        lg_registry_encode(&b, d);
        char *name = lg_xasprintf("%s.scan", d->name);
        rc |= write_seed(dir, name, b.s, b.len);
        free(name);
        if (!first.len)
            first = b;
        else
            lg_str_free(&b);
    }
    if (!first.len) {
        fprintf(stderr, "fuzz_seeds: no plugin given, or none valid\n");
        return -1;
    }
    rc |= write_seed(dir, "truncated.scan", first.s, first.len / 2);
    lg_str t = { 0 };
    lg_str_addn(&t, first.s, first.len);
    lg_str_addn(&t, "\0\0\0\0", 4);
    rc |= write_seed(dir, "trailing.scan", t.s, t.len);
    lg_str_free(&t);
    lg_str_free(&first);

    const mini ok = { .enum_index = 1, .bool_byte = 1, .neutral = 0, .n_inputs = 1, .n_params = 3 };
    struct {
        const char *name;
        mini m;
    } variants[] = {
        { "mini.scan", ok },
        { "mini_enum_disagrees.scan", ok },
        { "mini_enum_index_huge.scan", ok },
        { "mini_null_in_list.scan", ok },
        { "mini_bool_byte.scan", ok },
        { "mini_neutral.scan", ok },
        { "mini_inputs_declared_more.scan", ok },
        { "mini_params_huge.scan", ok },
    };
    variants[1].m.enum_index = 0;
    variants[2].m.enum_index = INT32_MAX;
    variants[3].m.null_in_list = true;
    variants[4].m.bool_byte = 7;
    variants[5].m.neutral = 7;
    variants[6].m.n_inputs = 2;
    variants[7].m.n_params = 0x7fffffff;
    for (size_t i = 0; i < sizeof variants / sizeof *variants; i++) {
        lg_str b = { 0 };
        mini_result(&b, &variants[i].m);
        rc |= write_seed(dir, variants[i].name, b.s, b.len);
        lg_str_free(&b);
    }

    /* huge counts and lengths right after the header */
    lg_str h = { 0 };
    lg_str_addn(&h, "LGSCAN2", 8);
    u32(&h, LG_ABI_MAJOR);
    u32(&h, LG_ABI_MINOR);
    size_t at = h.len;
    u32(&h, 0xfffffff0u); /* the plugin name's length */
    lg_str_add(&h, "core");
    rc |= write_seed(dir, "huge_string.scan", h.s, h.len);
    h.len = at;
    str(&h, "huge");
    str(&h, "1");
    str(&h, NULL);
    u32(&h, UINT32_MAX - 1); /* node types */
    rc |= write_seed(dir, "huge_types.scan", h.s, h.len);
    h.len -= 4;
    u32(&h, 1024); /* the most types, none there */
    rc |= write_seed(dir, "many_types_missing.scan", h.s, h.len);
    lg_str_free(&h);
    return rc;
}

/* ---- probe ----------------------------------------------------------------------------------- */

/* A small probe image in every layout the probe node knows, in each format: smooth colours
 * (so that a face cut from the wrong cell shows), one texel out of range per EXR (negative,
 * NaN, infinite: the node zeroes them), and shapes the node refuses or must be told about. */
static int probe_seed(const char *dir, const char *name, uint32_t w, uint32_t h, int odd,
                      const lg_image_write_opts *o)
{
    lg_image img;
    if (lg_image_alloc(&img, w, h))
        return -1;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            float *p = img.pixels + 4 * ((size_t)y * w + x);
            p[0] = (float)(x + 1) / (float)w;
            p[1] = (float)(y + 1) / (float)h;
            p[2] = 0.25f + 0.5f * (float)((x + y) & 1);
            p[3] = 1.0f;
        }
    if (odd == 1)
        img.pixels[0] = -2.0f;
    else if (odd == 2)
        img.pixels[1] = NAN;
    else if (odd == 3)
        img.pixels[6] = INFINITY;
    char *path = lg_path_join(dir, name);
    char err[512];
    int rc = lg_image_write(path, &img, o, err, sizeof err);
    if (rc)
        fprintf(stderr, "fuzz_seeds: %s\n", err);
    else
        printf("%s\n", path);
    free(path);
    lg_image_free(&img);
    return rc ? -1 : 0;
}

static int probe_seeds(const char *dir)
{
    static const struct {
        const char *name;
        uint32_t w, h;
    } shapes[] = {
        { "latlong", 16, 8 }, { "angular", 8, 8 }, { "cross", 16, 12 },       { "vcross", 12, 16 },
        { "strip", 24, 4 },   { "vstrip", 4, 24 }, { "near_latlong", 17, 8 }, /* ambiguous */
        { "odd", 10, 7 },     { "one", 1, 1 }, /* no layout; the smallest cube face */
    };
    static const char *const exts[] = { "exr", "hdr", "png" };
    lg_image_write_opts half = { 0 },
                        flt = { .exr_pixel = LG_EXR_FLOAT, .exr_compression = LG_EXR_NONE };
    int rc = 0;
    for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; i++)
        for (int e = 0; e < 3; e++) {
            /* the cross, the strip and the angular map also as float EXR, each with one
             * value a probe cannot hold */
            char name[64];
            snprintf(name, sizeof name, "%s.%s", shapes[i].name, exts[e]);
            rc |= probe_seed(dir, name, shapes[i].w, shapes[i].h, 0, &half);
            if (e == 0 && i < 3) {
                snprintf(name, sizeof name, "%s_float_odd.exr", shapes[i].name);
                rc |= probe_seed(dir, name, shapes[i].w, shapes[i].h, (int)i + 1, &flt);
            }
        }
    return rc;
}

/* ---- cache_kinds ----------------------------------------------------------------------------- */

/* A seed: the kind and config bytes, then the payload. */
static int kind_seed(const char *dir, const char *name, int kind, unsigned config,
                     const char *payload, size_t n)
{
    char *b = lg_xmalloc(n + 2);
    b[0] = (char)kind;
    b[1] = (char)config;
    memcpy(b + 2, payload, n);
    int rc = write_seed(dir, name, b, n + 2);
    free(b);
    return rc;
}

static float *seed_floats(size_t n)
{
    float *f = lg_xcalloc(n ? n : 1, sizeof *f);
    for (size_t i = 0; i < n; i++)
        f[i] = 0.125f * (float)(i % 17) - 0.5f;
    return f;
}

/* Per kind and config an entry written by the plugin's own encoder (pb_cache_encode,
 * ibl_chain_encode); for the first config of each, broken ones: a NaN, an infinity,
 * another magic, another version (the bakes), 65 bounces (the bake), cut by one float,
 * a float more. */
static int cache_kind_seeds(const char *dir)
{
    int rc = 0;
    char name[64];
    for (int kind = LG_FUZZ_KIND_BAKE; kind <= LG_FUZZ_KIND_REFERENCE; kind++) {
        const lg_fuzz_prt_config *cs = kind == LG_FUZZ_KIND_BAKE ? lg_fuzz_bake_configs
                                                                 : lg_fuzz_reference_configs;
        unsigned nc = kind == LG_FUZZ_KIND_BAKE
                          ? sizeof lg_fuzz_bake_configs / sizeof lg_fuzz_bake_configs[0]
                          : sizeof lg_fuzz_reference_configs / sizeof lg_fuzz_reference_configs[0];
        const char *kn = kind == LG_FUZZ_KIND_BAKE ? "bake" : "reference";
        for (unsigned c = 0; c < nc; c++) {
            pb_cache_header h;
            memset(&h, 0, sizeof h);
            memcpy(h.magic, kind == LG_FUZZ_KIND_BAKE ? "lgprtb1" : "lgprtr1", 8);
            h.version = PB_CACHE_VERSION;
            h.bands = cs[c].bands;
            h.vertices = cs[c].vertices;
            h.mode = cs[c].mode;
            h.samples = cs[c].samples;
            h.bounces = cs[c].mode == 3 ? 3 : 0;
            h.floats = kind == LG_FUZZ_KIND_BAKE
                           ? (uint64_t)cs[c].vertices * 3 * cs[c].bands * cs[c].bands
                           : (uint64_t)cs[c].vertices * 4;
            float *f = seed_floats((size_t)h.floats);
            size_t n = 0;
            char *p = pb_cache_encode(&h, f, &n);
            snprintf(name, sizeof name, "%s_%u.bin", kn, c);
            rc |= kind_seed(dir, name, kind, c, p, n);
            free(p);
            if (c == 0) {
                f[0] = NAN;
                p = pb_cache_encode(&h, f, &n);
                snprintf(name, sizeof name, "%s_nan.bin", kn);
                rc |= kind_seed(dir, name, kind, c, p, n);
                free(p);
                f[0] = INFINITY;
                p = pb_cache_encode(&h, f, &n);
                snprintf(name, sizeof name, "%s_inf.bin", kn);
                rc |= kind_seed(dir, name, kind, c, p, n);
                free(p);
                f[0] = 1.0f;
                pb_cache_header o = h;
                o.magic[6] = '9';
                p = pb_cache_encode(&o, f, &n);
                snprintf(name, sizeof name, "%s_magic.bin", kn);
                rc |= kind_seed(dir, name, kind, c, p, n);
                free(p);
                o = h;
                o.version = 2;
                p = pb_cache_encode(&o, f, &n);
                snprintf(name, sizeof name, "%s_version.bin", kn);
                rc |= kind_seed(dir, name, kind, c, p, n);
                free(p);
                o = h;
                o.bounces = 65;
                p = pb_cache_encode(&o, f, &n);
                snprintf(name, sizeof name, "%s_bounces.bin", kn);
                rc |= kind_seed(dir, name, kind, c, p, n);
                snprintf(name, sizeof name, "%s_short.bin", kn);
                rc |= kind_seed(dir, name, kind, c, p, n - 4);
                free(p);
            }
            free(f);
        }
    }
    unsigned nc = sizeof lg_fuzz_chain_configs / sizeof lg_fuzz_chain_configs[0];
    for (unsigned c = 0; c < nc; c++) {
        const lg_fuzz_chain_config *cc = &lg_fuzz_chain_configs[c];
        lg_image_desc d = {
            .width = cc->size, .height = cc->size, .flags = LG_IMAGE_CUBE, .levels = cc->levels
        };
        size_t nf = 4 * lg_image_offset(&d, cc->levels, 0), n = 0;
        float *f = seed_floats(nf);
        char *p = ibl_chain_encode(cc->size, cc->levels, cc->samples, nf, f, &n);
        snprintf(name, sizeof name, "chain_%u.bin", c);
        rc |= kind_seed(dir, name, LG_FUZZ_KIND_CHAIN, c, p, n);
        free(p);
        if (c == 0) {
            f[nf - 1] = NAN;
            p = ibl_chain_encode(cc->size, cc->levels, cc->samples, nf, f, &n);
            rc |= kind_seed(dir, "chain_nan.bin", LG_FUZZ_KIND_CHAIN, c, p, n);
            free(p);
            p = ibl_chain_encode(cc->size, cc->levels + 1, cc->samples, nf, f, &n);
            rc |= kind_seed(dir, "chain_levels.bin", LG_FUZZ_KIND_CHAIN, c, p, n);
            rc |= kind_seed(dir, "chain_short.bin", LG_FUZZ_KIND_CHAIN, c, p, n - 4);
            free(p);
        }
        free(f);
    }
    return rc;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "cache") == 0)
        return cache_seeds(argv[2]) ? 1 : 0;
    if (argc >= 4 && strcmp(argv[1], "registry") == 0)
        return registry_seeds(argv[2], argc - 3, argv + 3) ? 1 : 0;
    if (argc >= 3 && strcmp(argv[1], "cache_kinds") == 0)
        return cache_kind_seeds(argv[2]) ? 1 : 0;
    if (argc >= 3 && strcmp(argv[1], "probe") == 0)
        return probe_seeds(argv[2]) ? 1 : 0;
    fprintf(stderr, "usage: fuzz_seeds cache DIR\n"
                    "       fuzz_seeds registry DIR PLUGIN.so...\n"
                    "       fuzz_seeds cache_kinds DIR\n"
                    "       fuzz_seeds probe DIR\n");
    return 2;
}
