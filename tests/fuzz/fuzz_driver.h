/*
 * tests/fuzz/fuzz_driver.h: the plain main() driver shared by the fuzz targets.
 *
 * A fuzz target defines LLVMFuzzerTestOneInput. Built with -Dfuzzing=true (clang) it is
 * linked with libFuzzer, which provides main(), and fuzz_driver.c is not built in. Without
 * it the target's main() calls lg_fuzz_main, which runs every file of the corpus folders
 * (or files) given on the command line in name order, then a fixed number of deterministic
 * mutations of each from a fixed-seed PRNG: bit flips, random bytes, boundary values over
 * 1, 2 or 4 bytes, dictionary tokens, deleted, copied and swapped bytes, truncations, and
 * splices with other corpus files. The same corpus and count give the same inputs on
 * every run and machine. Memory is bounded as in `make fuzz` (fuzz_driver.c): a block over
 * 1 GiB or an RSS over 2 GiB fails a sanitizer build, and an address space over 4 GiB
 * makes allocations fail in the others.
 *
 *     fuzz_NAME [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...
 */
#ifndef LG_FUZZ_DRIVER_H
#define LG_FUZZ_DRIVER_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* The libFuzzer entry point, defined by each target: 0 for a handled input; anything wrong
 * aborts, so that the driver (or libFuzzer) stops with the input that did it. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A dictionary entry: `len` bytes, which may include NULs. */
typedef struct lg_fuzz_token {
    const char *bytes;
    size_t len;
} lg_fuzz_token;

/* An entry from a string literal, without its terminating NUL. */
#define LG_FUZZ_TOKEN(literal)                                                                     \
    {                                                                                              \
        (literal), sizeof(literal) - 1                                                             \
    }

/* What differs between targets. Read during the call only. */
typedef struct lg_fuzz_target {
    const char *name;            /* for messages, e.g. "fuzz_graph" */
    long mutations;              /* mutations per corpus file unless -n says otherwise */
    const lg_fuzz_token *tokens; /* what the "insert a token" edit draws from; may be NULL */
    size_t n_tokens;
    size_t head;                /* if > 0, half of the edits land in the first `head`
                                    bytes (file headers, where parsers go wrong) */
    void (*summary)(FILE *out); /* prints the target's own counts after the driver's
                                    summary line (no newline); may be NULL */
} lg_fuzz_target;

/* Runs the corpus and its mutations through LLVMFuzzerTestOneInput and prints a summary to
 * stdout. Returns main()'s exit status: 0, or 2 for a usage error or an unreadable corpus
 * (with a message on stderr). */
int lg_fuzz_main(int argc, char **argv, const lg_fuzz_target *target);

#endif
