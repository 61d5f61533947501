/*
 * tests/fuzz/fuzz_registry.c: the plugin registry's scan-result decoder (host/exec/registry.c,
 * lg_registry_decode) on arbitrary bytes.
 *
 * The scan result is what the scanning child writes through the pipe after loading a
 * plugin: the plugin's code ran in that process and could have written anything. For every
 * input: decode. A refusal must say "malformed scan result: ..." and leave nothing
 * allocated (the sanitizer build's leak checker sees the rest). A decoded plugin must hold
 * what the validator allows (names, tables within their limits, enum defaults that name
 * their index); it is encoded again as the child would encode it, that must decode, and
 * its encoding must be the same bytes (one normalisation, then a fixed point).
 *
 * Built with -Dfuzzing=true (clang) this is a libFuzzer target. Otherwise main() below
 * hands the corpus (tests/fuzz/corpus_registry: the scan results of the real plugins and
 * broken ones, written by fuzz_seeds.c) to the plain driver (fuzz_driver.h):
 *
 *     fuzz_registry [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_driver.h"
#include "exec/exec.h"

static unsigned long n_runs, n_ok;

static void bad(const char *what, size_t size)
{
    fprintf(stderr, "fuzz_registry: %s (input %lu, %zu bytes)\n", what, n_runs - 1, size);
    abort();
}

static void encode(lg_str *b, const lg_plugin *p)
{
    lg_plugin_desc d = lg_plugin_scanned_desc(p);
    lg_registry_encode(b, &d);
}

/* Nothing owned left in p. */
static bool all_zero(const lg_plugin *p)
{
    return !p->name && !p->version && !p->doc && !p->types && !p->n_types && !p->path &&
           !p->handle && !p->live;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    n_runs++;
    char err[1024];
    err[0] = 0;
    lg_plugin p;
    if (lg_registry_decode((const char *)data, size, &p, err, sizeof err) != 0) {
        if (strncmp(err, "malformed scan result: ", 23) != 0 || !err[23] || !all_zero(&p))
            bad("a refusal without its reason, or with something left in the plugin", size);
        return 0;
    }
    n_ok++;
    if (!p.name || !p.version || !p.types || !p.n_types || p.n_types > 1024 || p.path)
        bad("a decoded plugin without a name, version or types", size);
    for (uint32_t i = 0; i < p.n_types; i++) {
        const lg_node_type *t = &p.types[i];
        if (!t->name || t->execute || t->n_params > 256 || t->n_inputs > 64 || t->n_outputs > 64)
            bad("a decoded node type out of its limits", size);
        for (uint32_t k = 0; k < t->n_params; k++) {
            const lg_param_desc *q = &t->params[k];
            if (q->type == LG_PARAM_ENUM &&
                (!q->def.s || strcmp(q->def.s, q->enum_values[q->def.e]) != 0))
                bad("an enum default that does not name its index", size);
        }
    }
    lg_str a = { 0 }, b = { 0 };
    encode(&a, &p);
    lg_plugin p2;
    if (lg_registry_decode(a.s, a.len, &p2, err, sizeof err) != 0) {
        fprintf(stderr, "fuzz_registry: %s\n", err);
        bad("a decoded plugin, encoded again, does not decode", size);
    }
    encode(&b, &p2);
    if (a.len != b.len || memcmp(a.s, b.s, a.len) != 0)
        bad("encoding is not a fixed point after one decode", size);
    lg_str_free(&a);
    lg_str_free(&b);
    lg_plugin_free_schema(&p2);
    lg_plugin_free_schema(&p);
    if (!all_zero(&p))
        bad("lg_plugin_free_schema left something", size);
    return 0;
}

#ifndef LG_FUZZ_ENGINE

/* Pieces of a scan result: the magic, small and boundary counts, NULL strings. */
static const lg_fuzz_token tokens[] = {
    LG_FUZZ_TOKEN("LGSCAN2\0"),        LG_FUZZ_TOKEN("\0\0\0\0"),    LG_FUZZ_TOKEN("\1\0\0\0"),
    LG_FUZZ_TOKEN("\2\0\0\0"),         LG_FUZZ_TOKEN("\x40\0\0\0"),  LG_FUZZ_TOKEN("\0\1\0\0"),
    LG_FUZZ_TOKEN("\xff\xff\xff\xff"), LG_FUZZ_TOKEN("\x01\0\0\0x"), LG_FUZZ_TOKEN("\x03\0\0\0key"),
};

static void summary(FILE *out)
{
    fprintf(out, "%lu decoded", n_ok);
}

int main(int argc, char **argv)
{
    static const lg_fuzz_target target = {
        .name = "fuzz_registry",
        .mutations = 1000,
        .tokens = tokens,
        .n_tokens = sizeof tokens / sizeof *tokens,
        .summary = summary,
    };
    return lg_fuzz_main(argc, argv, &target);
}

#endif
