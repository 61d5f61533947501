/*
 * tests/common/cache_forge.h: forged cache entries, header-only (#include "common/cache_forge.h").
 *
 * The host's cache checksums each entry with FNV-1a (host/exec/cache_entry.c), which anyone who
 * can write into the cache directory can recompute: these helpers do what such a writer
 * would, so that a test can show a reader rejects values its node cannot have made even
 * when the entry is well formed.
 *
 *   cache_forge_find(dir, prefix, path, n)    the first file in `dir` whose name starts
 *                                             with `prefix` (the node type's, "prt_bake-");
 *                                             how many there are
 *   cache_forge_float(path, skip, index, v)   sets float `index` of the payload, after
 *                                             `skip` bytes of the node's own header, to v,
 *                                             and writes the checksum again; 0 or -1 with a
 *                                             message on stderr
 *   cache_forge_floats(path, skip)            the number of floats after the node's header
 *
 * The entry format (host/exec/cache_entry.c): "LGCACHE\1" | u32 version | 16 bytes identity |
 * u32 key length | key | u64 payload size | u64 checksum (FNV-1a 64, seed 0) | payload.
 */
#ifndef LG_TEST_CACHE_FORGE_H
#define LG_TEST_CACHE_FORGE_H

#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static inline int cache_forge_find(const char *dir, const char *prefix, char *first, size_t n)
{
    DIR *d = dir ? opendir(dir) : NULL;
    int count = 0;
    if (!d)
        return 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (!strncmp(e->d_name, prefix, strlen(prefix)) && count++ == 0)
            snprintf(first, n, "%s/%s", dir, e->d_name);
    closedir(d);
    return count;
}

/* The entry's bytes (malloc'd) and where its payload starts; NULL after a message. */
static inline unsigned char *cache_forge_read(const char *path, size_t *len, size_t *payload)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "cache_forge: cannot open %s\n", path);
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = size > 0 ? malloc((size_t)size) : NULL;
    if (!b || fread(b, 1, (size_t)size, f) != (size_t)size) {
        fprintf(stderr, "cache_forge: cannot read %s\n", path);
        free(b);
        fclose(f);
        return NULL;
    }
    fclose(f);
    uint32_t kl = 0;
    if (size < 48 || memcmp(b, "LGCACHE\1", 8) != 0) {
        fprintf(stderr, "cache_forge: %s is not a cache entry\n", path);
        free(b);
        return NULL;
    }
    memcpy(&kl, b + 28, 4);
    *payload = 32 + (size_t)kl + 16;
    *len = (size_t)size;
    if (*payload > *len) {
        fprintf(stderr, "cache_forge: %s is truncated\n", path);
        free(b);
        return NULL;
    }
    return b;
}

static inline long cache_forge_floats(const char *path, size_t skip)
{
    size_t len, payload;
    unsigned char *b = cache_forge_read(path, &len, &payload);
    if (!b)
        return -1;
    free(b);
    return len < payload + skip ? -1 : (long)((len - payload - skip) / sizeof(float));
}

static inline int cache_forge_float(const char *path, size_t skip, size_t index, float v)
{
    size_t len, payload;
    unsigned char *b = cache_forge_read(path, &len, &payload);
    if (!b)
        return -1;
    size_t at = payload + skip + index * sizeof(float);
    if (at + sizeof v > len) {
        fprintf(stderr, "cache_forge: float %zu is beyond the payload of %s\n", index, path);
        free(b);
        return -1;
    }
    memcpy(b + at, &v, sizeof v);
    /* what a writer of the cache can do: the checksum again, FNV-1a 64 over the payload */
    uint64_t h = 1469598103934665603ull;
    for (size_t i = payload; i < len; i++) {
        h ^= b[i];
        h *= 1099511628211ull;
    }
    memcpy(b + payload - 8, &h, 8);
    FILE *f = fopen(path, "wb");
    int rc = f && fwrite(b, 1, len, f) == len ? 0 : -1;
    if (f && fclose(f) != 0)
        rc = -1;
    if (rc)
        fprintf(stderr, "cache_forge: cannot write %s\n", path);
    free(b);
    return rc;
}

#endif
