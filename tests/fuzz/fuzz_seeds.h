/*
 * tests/fuzz/fuzz_seeds.h: what the cache target (fuzz_cache.c) and the seed writer
 * (fuzz_seeds.c) agree on: the identity and key the seed entries are written for.
 */
#ifndef LG_FUZZ_SEEDS_H
#define LG_FUZZ_SEEDS_H

/* An lg_digest (host/util.h) initialiser, and a key with the characters real keys use. */
#define LG_FUZZ_CACHE_IDENTITY {{0x0123456789abcdefull, 0xfedcba9876543210ull}}
#define LG_FUZZ_CACHE_KEY "bvh/v2 leaf=4"

#endif
