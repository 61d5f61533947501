/*
 * tests/fuzz/fuzz_seeds.h: what the cache targets (fuzz_cache.c, fuzz_cache_kinds.c) and
 * the seed writer (fuzz_seeds.c) agree on: the identity and key the seed entries are
 * written for, and the nodes whose cache payloads fuzz_cache_kinds reads.
 */
#ifndef LG_FUZZ_SEEDS_H
#define LG_FUZZ_SEEDS_H

/* An lg_digest (host/base/util.h) initialiser, and a key with the characters real keys use. */
#define LG_FUZZ_CACHE_IDENTITY                                                                     \
    {                                                                                              \
        {                                                                                          \
            0x0123456789abcdefull, 0xfedcba9876543210ull                                           \
        }                                                                                          \
    }
#define LG_FUZZ_CACHE_KEY "bvh/v2 leaf=4"

/* fuzz_cache_kinds: an input is a kind byte, a config byte (each taken modulo its table's
 * length), then the payload. The configs are what a node asks for (prt_bake.c's `want`;
 * ibl.c's chain), small so that a seed is a few hundred bytes. */
enum { LG_FUZZ_KIND_BAKE = 0, LG_FUZZ_KIND_REFERENCE, LG_FUZZ_KIND_CHAIN, LG_FUZZ_KINDS };
typedef struct lg_fuzz_prt_config {
    unsigned bands, vertices, mode, samples; /* mode: 1 unshadowed .. 3 interreflected */
} lg_fuzz_prt_config;
static const lg_fuzz_prt_config lg_fuzz_bake_configs[] = {
    { 1, 1, 1, 4 },
    { 2, 3, 3, 8 },
    { 3, 2, 2, 16 },
};
static const lg_fuzz_prt_config lg_fuzz_reference_configs[] = {
    { 0, 1, 1, 8 },
    { 0, 5, 3, 16 },
};
typedef struct lg_fuzz_chain_config {
    unsigned size, levels, samples;
} lg_fuzz_chain_config;
static const lg_fuzz_chain_config lg_fuzz_chain_configs[] = {
    { 4, 3, 64 },
    { 2, 2, 256 },
};

#endif
