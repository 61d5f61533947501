/*
 * plugins/ibl/ibl_cache.h: the payload of the ibl node's cache entry, its GGX chain (a
 * cube's prefiltered mip levels, README.md "Cache"), apart from the node so that
 * tests/fuzz/fuzz_cache_kinds.c reads arbitrary bytes with it (docs/fuzzing.md). The
 * host's envelope (host/exec/cache_entry.c) holds this payload: the header below, then the
 * chain's floats, in the machine's byte order.
 */
#ifndef LG_IBL_CACHE_H
#define LG_IBL_CACHE_H

#include <stddef.h>
#include <stdint.h>

typedef struct ibl_chain_header {
    char magic[8]; /* "lgibl01" */
    uint32_t size, levels, samples, floats;
} ibl_chain_header;

/* Checks the payload `data` (`bytes` bytes, any alignment) against the chain the node
 * wants: cube face `size`, `levels` levels, `samples` samples per texel, `floats` floats.
 * Returns NULL with *chain a malloc'd copy of the floats (the caller's), or why the entry
 * is not used (its header or size disagrees, a value is not finite, out of memory) with
 * *chain NULL. */
const char *ibl_chain_read(const void *data, size_t bytes, uint32_t size, uint32_t levels,
                           uint32_t samples, size_t floats, float **chain);

/* ibl_chain_read without the test of the values: the node holds them to the probe's range
 * itself (ibl.c, ibl_chain_bad), naming the first bad one. */
const char *ibl_chain_read_raw(const void *data, size_t bytes, uint32_t size, uint32_t levels,
                               uint32_t samples, size_t floats, float **chain);

/* The payload for `chain` (the header made from the other arguments): malloc'd (the
 * caller frees it), *bytes long; NULL when out of memory. */
char *ibl_chain_encode(uint32_t size, uint32_t levels, uint32_t samples, size_t floats,
                       const float *chain, size_t *bytes);

#endif
