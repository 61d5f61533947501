/*
 * tests/fuzz/fuzz_cache_kinds.c: the payload readers of every kind of cache entry a plugin
 * writes, on arbitrary bytes: prt_bake's transfer ("lgprtb1") and prt_reference's
 * per-vertex radiance ("lgprtr1"), both plugins/prt_bake/pb_cache.c (pb_cache_read), and
 * the ibl node's GGX prefilter chain ("lgibl01", plugins/ibl/ibl_cache.c:
 * ibl_chain_read). fuzz_cache covers the host's envelope around them (host/exec/cache_entry.c);
 * a payload reaches these readers once the envelope's checksum and key agree, so it is
 * whatever a build or version of the plugin wrote, or anyone who can write the cache.
 *
 * An input is a kind byte, a config byte (fuzz_seeds.h: what the node asks for), then the
 * payload. For every input:
 *   - a refusal must give a reason and leave the node's buffers untouched;
 *   - an acceptance must be exactly the payload the plugin would write for those floats
 *     (header fields as the node asks, the size adding up: re-encoding gives the input
 *     back byte for byte), with every float finite, as the node's consumers assume, and
 *     a bounce count of at most 64.
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_cache_kinds) to the plain driver (fuzz_driver.h):
 *
 *     fuzz_cache_kinds [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_driver.h"
#include "fuzz_seeds.h"
#include "ibl_cache.h"
#include "lightgraph/lightgraph.h"
#include "pb_cache.h"

#define N_OF(a) (sizeof(a) / sizeof((a)[0]))

static unsigned long n_runs, n_ok[LG_FUZZ_KINDS];
static const char *const kind_names[LG_FUZZ_KINDS] = { "bake", "reference", "chain" };

static void bad(int kind, const char *what)
{
    fprintf(stderr, "fuzz_cache_kinds: %s: %s (input %lu)\n", kind_names[kind], what, n_runs - 1);
    abort();
}

static bool all_finite(const float *f, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(f[i]))
            return false;
    return true;
}

/* The floats of a GGX chain: a cube of face `size` with `levels` levels, RGBA (ibl.c). */
static size_t chain_floats(unsigned size, unsigned levels)
{
    lg_image_desc d = { .width = size, .height = size, .flags = LG_IMAGE_CUBE, .levels = levels };
    return 4 * lg_image_offset(&d, levels, 0);
}

static void prt(int kind, const lg_fuzz_prt_config *c, const uint8_t *data, size_t size)
{
    pb_cache_header want;
    memset(&want, 0, sizeof want);
    memcpy(want.magic, kind == LG_FUZZ_KIND_BAKE ? "lgprtb1" : "lgprtr1", 8);
    want.version = PB_CACHE_VERSION;
    want.bands = c->bands;
    want.vertices = c->vertices;
    want.mode = c->mode;
    want.samples = c->samples;
    want.floats = kind == LG_FUZZ_KIND_BAKE ? (uint64_t)c->vertices * 3 * c->bands * c->bands
                                            : (uint64_t)c->vertices * 4;
    /* the node's buffer, one float more to see a write past the entry's floats */
    size_t nf = (size_t)want.floats;
    float *out = malloc((nf + 1) * sizeof *out);
    if (!out)
        abort();
    for (size_t i = 0; i <= nf; i++)
        out[i] = -12345.0f;
    uint32_t bounces = 77777;
    const char *why = pb_cache_read(data, size, &want, out, &bounces);
    if (why) {
        if (!why[0] || bounces != 77777)
            bad(kind, "a refusal without a reason, or that sets the bounces");
        for (size_t i = 0; i <= nf; i++)
            if (out[i] != -12345.0f)
                bad(kind, "a refusal that writes the node's buffer");
        free(out);
        return;
    }
    n_ok[kind]++;
    if (out[nf] != -12345.0f)
        bad(kind, "an acceptance that writes past the node's floats");
    if (!all_finite(out, nf) || bounces > PB_CACHE_MAX_BOUNCES)
        bad(kind, "an accepted value that is not finite, or too many bounces");
    pb_cache_header h = want;
    h.bounces = bounces;
    size_t bytes = 0;
    char *again = pb_cache_encode(&h, out, &bytes);
    if (!again || bytes != size || memcmp(again, data, size) != 0)
        bad(kind, "an accepted payload that its floats do not encode to");
    free(again);
    free(out);
}

static void chain(const lg_fuzz_chain_config *c, const uint8_t *data, size_t size)
{
    const int kind = LG_FUZZ_KIND_CHAIN;
    size_t nf = chain_floats(c->size, c->levels);
    float *got = (float *)1;
    const char *why = ibl_chain_read(data, size, c->size, c->levels, c->samples, nf, &got);
    if (why) {
        if (!why[0] || got)
            bad(kind, "a refusal without a reason, or with a chain");
        return;
    }
    n_ok[kind]++;
    if (!got)
        bad(kind, "an acceptance without a chain");
    if (!all_finite(got, nf))
        bad(kind, "an accepted chain with a value that is not finite");
    size_t bytes = 0;
    char *again = ibl_chain_encode(c->size, c->levels, c->samples, nf, got, &bytes);
    if (!again || bytes != size || memcmp(again, data, size) != 0)
        bad(kind, "an accepted payload that its floats do not encode to");
    free(again);
    free(got);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    n_runs++;
    if (size < 2)
        return 0;
    int kind = data[0] % LG_FUZZ_KINDS;
    unsigned config = data[1];
    /* the payload in a buffer of its own size, so that ASan sees a read past it */
    size_t n = size - 2;
    uint8_t *payload = malloc(n ? n : 1);
    if (!payload)
        abort();
    memcpy(payload, data + 2, n);
    if (kind == LG_FUZZ_KIND_BAKE)
        prt(kind, &lg_fuzz_bake_configs[config % N_OF(lg_fuzz_bake_configs)], payload, n);
    else if (kind == LG_FUZZ_KIND_REFERENCE)
        prt(kind, &lg_fuzz_reference_configs[config % N_OF(lg_fuzz_reference_configs)], payload, n);
    else
        chain(&lg_fuzz_chain_configs[config % N_OF(lg_fuzz_chain_configs)], payload, n);
    free(payload);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* The magics, the format version, boundary counts, float specials. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("lgprtb1\0"),          LG_FUZZ_TOKEN("lgprtr1\0"),
    LG_FUZZ_TOKEN("lgibl01\0"),          LG_FUZZ_TOKEN("\1\0\0\0"),
    LG_FUZZ_TOKEN("\x40\0\0\0"),         LG_FUZZ_TOKEN("\x41\0\0\0"),
    LG_FUZZ_TOKEN("\0\0\xc0\x7f"),       LG_FUZZ_TOKEN("\0\0\x80\x7f"),
    LG_FUZZ_TOKEN("\0\0\x80\xff"),       LG_FUZZ_TOKEN("\xff\xff\xff\xff\xff\xff\xff\xff"),
    LG_FUZZ_TOKEN("\0\0\0\0\0\0\0\x40"),
};

static void summary(FILE *out)
{
    fprintf(out, "accepted: bake %lu, reference %lu, chain %lu", n_ok[0], n_ok[1], n_ok[2]);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_cache_kinds",
        .mutations = 1000,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .head = 64, /* the selector bytes and the header */
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
