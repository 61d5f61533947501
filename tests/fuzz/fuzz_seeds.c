/*
 * tests/fuzz/fuzz_seeds.c: writes the seed corpora of fuzz_cache and fuzz_registry, whose
 * inputs are binary formats the host writes itself (docs/fuzzing.md, "Seeds"):
 *
 *     fuzz_seeds cache DIR
 *     fuzz_seeds registry DIR PLUGIN.so...
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
 * The files are committed; run this again when a format or a plugin's schema changes.
 */
#include <dlfcn.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_seeds.h"
#include "host.h"

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

/* ---- cache ------------------------------------------------------------------------------- */

static int cache_seeds(const char *dir)
{
    const lg_digest id = LG_FUZZ_CACHE_IDENTITY;
    const char *key = LG_FUZZ_CACHE_KEY;
    size_t klen = strlen(key), head = 8 + 4 + 16 + 4 + klen + 8 + 8;
    char payload[96];
    for (size_t i = 0; i < sizeof payload; i++)
        payload[i] = (char)(i * 37 + 11);
    lg_str e = {0}, empty = {0};
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

/* ---- registry ------------------------------------------------------------------------------ */

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
    int32_t enum_index;     /* the enum default's index (its name is "b", index 1) */
    bool null_in_list;      /* renamed_from ["old", NULL, "older"] */
    unsigned char bool_byte;
    uint32_t neutral;
    uint32_t n_inputs;      /* declared; one is written */
    uint32_t n_params;      /* declared; three are written */
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
    lg_str first = {0};
    for (int i = 0; i < n; i++) {
        void *h = dlopen(plugins[i], RTLD_NOW | RTLD_LOCAL);
        lg_plugin_entry_fn entry =
            h ? (lg_plugin_entry_fn)(uintptr_t)dlsym(h, LG_PLUGIN_ENTRY_NAME) : NULL;
        const lg_plugin_desc *d = entry ? entry() : NULL;
        char err[512];
        if (!d || lg_descriptor_validate(d, plugins[i], err, sizeof err) != 0) {
            fprintf(stderr, "fuzz_seeds: %s: %s\n", plugins[i], d ? err : dlerror());
            rc = -1;
            continue;
        }
        lg_str b = {0};
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
    lg_str t = {0};
    lg_str_addn(&t, first.s, first.len);
    lg_str_addn(&t, "\0\0\0\0", 4);
    rc |= write_seed(dir, "trailing.scan", t.s, t.len);
    lg_str_free(&t);
    lg_str_free(&first);

    const mini ok = {.enum_index = 1, .bool_byte = 1, .neutral = 0, .n_inputs = 1, .n_params = 3};
    struct {
        const char *name;
        mini m;
    } variants[] = {
        {"mini.scan", ok},
        {"mini_enum_disagrees.scan", ok},
        {"mini_enum_index_huge.scan", ok},
        {"mini_null_in_list.scan", ok},
        {"mini_bool_byte.scan", ok},
        {"mini_neutral.scan", ok},
        {"mini_inputs_declared_more.scan", ok},
        {"mini_params_huge.scan", ok},
    };
    variants[1].m.enum_index = 0;
    variants[2].m.enum_index = INT32_MAX;
    variants[3].m.null_in_list = true;
    variants[4].m.bool_byte = 7;
    variants[5].m.neutral = 7;
    variants[6].m.n_inputs = 2;
    variants[7].m.n_params = 0x7fffffff;
    for (size_t i = 0; i < sizeof variants / sizeof *variants; i++) {
        lg_str b = {0};
        mini_result(&b, &variants[i].m);
        rc |= write_seed(dir, variants[i].name, b.s, b.len);
        lg_str_free(&b);
    }

    /* huge counts and lengths right after the header */
    lg_str h = {0};
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

int main(int argc, char **argv)
{
    if (argc >= 3 && strcmp(argv[1], "cache") == 0)
        return cache_seeds(argv[2]) ? 1 : 0;
    if (argc >= 4 && strcmp(argv[1], "registry") == 0)
        return registry_seeds(argv[2], argc - 3, argv + 3) ? 1 : 0;
    fprintf(stderr, "usage: fuzz_seeds cache DIR\n"
                    "       fuzz_seeds registry DIR PLUGIN.so...\n");
    return 2;
}
