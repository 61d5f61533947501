/*
 * tests/fuzz/fuzz_cache.c: the cache's entry check (host/exec/cache_entry.c) on arbitrary bytes.
 *
 * An entry read back from the cache directory is untrusted: anyone who can write there, a
 * crash mid-write or a full disk can leave any bytes. For every input:
 *   - checked as the entry of a fixed identity under a fixed key (the seeds', fuzz_seeds.c)
 *     and under the empty key: a refusal must give a reason and no payload;
 *     an acceptance must point inside the input, the payload being the bytes after the
 *     header, and re-encoding that payload must give the input back byte for byte (the
 *     format has one encoding per entry, so nothing else can pass);
 *   - encoded as a payload, checked back (accepted, the same bytes), and checked again one
 *     byte short, with a byte added, and under another key (each refused).
 * Nothing is allocated from a declared size: a seed declares 2^63 bytes.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_cache) to the plain driver (fuzz_driver.h):
 *
 *     fuzz_cache [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_driver.h"
#include "fuzz_seeds.h"
#include "exec/exec.h"

static unsigned long n_runs, n_ok;

static void bad(const char *what, size_t size)
{
    fprintf(stderr, "fuzz_cache: %s (input %lu, %zu bytes)\n", what, n_runs - 1, size);
    abort();
}

/* The input under `key`, and the input as the payload of an entry under `key`. */
static void check(const uint8_t *data, size_t size, const char *key, const char *other_key)
{
    const lg_digest id = LG_FUZZ_CACHE_IDENTITY;
    const char *in = (const char *)data;

    const char *payload = (const char *)1;
    size_t psize = 1;
    const char *why = lg_cache_entry_check(in, size, &id, key, &payload, &psize);
    if (why) {
        if (!why[0] || payload || psize)
            bad("a refusal without a reason, or with a payload", size);
    } else {
        n_ok++;
        size_t head = size - psize;
        if (psize > size || payload != in + head || head != 8 + 4 + 16 + 4 + strlen(key) + 8 + 8)
            bad("the payload is not the bytes after the header", size);
        lg_str again = { 0 };
        lg_cache_entry_encode(&again, &id, key, payload, psize);
        if (again.len != size || memcmp(again.s, in, size) != 0)
            bad("an accepted entry that its payload does not encode to", size);
        lg_str_free(&again);
    }

    /* the input as a payload: accepted back whole, refused cut, padded or under another key */
    lg_str e = { 0 };
    lg_cache_entry_encode(&e, &id, key, data, size);
    lg_str_addc(&e, 0); /* the padded variant's extra byte; not counted below until used */
    size_t len = e.len - 1;
    if (lg_cache_entry_check(e.s, len, &id, key, &payload, &psize) || psize != size ||
        (size && memcmp(payload, data, size) != 0))
        bad("an encoded entry is not read back", size);
    if (!lg_cache_entry_check(e.s, len - 1, &id, key, &payload, &psize) ||
        !lg_cache_entry_check(e.s, len + 1, &id, key, &payload, &psize))
        bad("an entry one byte short or long is accepted", size);
    if (!lg_cache_entry_check(e.s, len, &id, other_key, &payload, &psize))
        bad("an entry is accepted under another key", size);
    lg_str_free(&e);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    n_runs++;
    check(data, size, LG_FUZZ_CACHE_KEY, "");
    check(data, size, "", "k");
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* Pieces of an entry: the magic, the version, the key and its length, boundary sizes. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("LGCACHE\1"),
    LG_FUZZ_TOKEN("\1\0\0\0"),
    LG_FUZZ_TOKEN("\2\0\0\0"),
    LG_FUZZ_TOKEN(LG_FUZZ_CACHE_KEY),
    LG_FUZZ_TOKEN("\0\0\0\0"),
    LG_FUZZ_TOKEN("\0\0\0\0\0\0\0\x80"),
    LG_FUZZ_TOKEN("\xff\xff\xff\xff\xff\xff\xff\xff"),
};

static void summary(FILE *out)
{
    fprintf(out, "%lu accepted", n_ok);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_cache",
        .mutations = 2000,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .head = 64, /* the header: magic, version, identity, key length, key, size, sum */
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
