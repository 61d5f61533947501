/*
 * plugins/prt_bake/pb_cache.h: the payload of prt_bake's and prt_reference's cache entries
 * (README.md, "Cache"), apart from the bake so that tests/fuzz/fuzz_cache_kinds.c reads
 * arbitrary bytes with it (docs/fuzzing.md). The host's envelope (host/exec/cache_entry.c) holds
 * this payload: the header below, then `floats` floats, in the machine's byte order.
 */
#ifndef LG_PB_CACHE_H
#define LG_PB_CACHE_H

#include <stddef.h>
#include <stdint.h>

/* Any field that disagrees with what the node asks for, a size that does not add up or a
 * value that is not finite: the entry is not trusted (a warning, then the bake runs
 * again). */
#define PB_CACHE_VERSION 1u
/* The most bounces an interreflected bake computes (its parameter's bound). */
#define PB_CACHE_MAX_BOUNCES 64u
typedef struct pb_cache_header {
    char magic[8];    /* "lgprtb1" (bake) or "lgprtr1" (reference) */
    uint32_t version; /* PB_CACHE_VERSION */
    uint32_t bands;
    uint32_t vertices;
    uint32_t mode;
    uint32_t bounces; /* bounces computed (interreflected) */
    uint32_t samples; /* directions per axis (bake) or cube face size (reference) */
    uint64_t floats;  /* floats after the header */
} pb_cache_header;

/* The header part of pb_cache_read: NULL with *h filled (the payload's floats follow it,
 * h->floats of them, not yet looked at), or why the entry is not used. */
const char *pb_cache_header_check(const void *data, size_t bytes, const pb_cache_header *want,
                                  pb_cache_header *h);

/* Checks the payload `data` (`bytes` bytes, any alignment) against `want` (every field
 * but bounces). Returns NULL with `want->floats` floats copied to `out` and the entry's
 * bounce count in *bounces, or why the entry is not used ("bad magic", ...) with `out` and
 * *bounces untouched. Nothing is allocated. */
const char *pb_cache_read(const void *data, size_t bytes, const pb_cache_header *want, float *out,
                          uint32_t *bounces);

/* The payload of header `h` and its h->floats floats `f`: malloc'd (the caller frees it),
 * *bytes long; NULL when out of memory. */
char *pb_cache_encode(const pb_cache_header *h, const float *f, size_t *bytes);

#endif
