/*
 * tests/fuzz/fuzz_driver.c: the plain main() driver of the fuzz targets (fuzz_driver.h).
 * Only the plain builds link it; with -Dfuzzing=true libFuzzer drives the targets.
 */
#include "fuzz_driver.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>

/* Memory bounded as in `make fuzz` (tools/fuzz.py: -rss_limit_mb=2048, -malloc_limit_mb=
 * 1024), so that a finding that was a memory blow-up fails its replay here too rather than
 * taking the machine's memory: under AddressSanitizer (gcc or clang) through its options,
 * a block over 1 GiB or an RSS over 2 GiB being an error; otherwise an address space of
 * 4 GiB, over which allocations fail (and the host's x-allocators abort). */
#if defined(__SANITIZE_ADDRESS__)
#define LG_FUZZ_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LG_FUZZ_ASAN 1
#endif
#endif

#define LG_FUZZ_MAX_BLOCK_MB 1024
#define LG_FUZZ_MAX_RSS_MB 2048
#define LG_FUZZ_MAX_AS_MB 4096

#ifdef LG_FUZZ_ASAN
#define STR_(x) #x
#define STR(x) STR_(x)
/* Read by the ASan runtime at start, before ASAN_OPTIONS (which may override it). */
__attribute__((visibility("default"), used)) const char *__asan_default_options(void);
const char *__asan_default_options(void)
{
    return "max_allocation_size_mb=" STR(LG_FUZZ_MAX_BLOCK_MB) ":hard_rss_limit_mb=" STR(
        LG_FUZZ_MAX_RSS_MB) ":allocator_may_return_null=0";
}
#endif

static void bound_memory(void)
{
#ifndef LG_FUZZ_ASAN
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0) {
        rlim_t want = (rlim_t)LG_FUZZ_MAX_AS_MB << 20;
        if (rl.rlim_max == RLIM_INFINITY || rl.rlim_max > want) {
            rl.rlim_cur = want;
            setrlimit(RLIMIT_AS, &rl);
        }
    }
#endif
}

typedef struct input {
    char *name;
    uint8_t *data;
    size_t size;
} input;

static void *xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p) {
        fprintf(stderr, "fuzz driver: out of memory (%zu bytes)\n", n);
        abort();
    }
    return p;
}

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint64_t rnd(void)
{
    /* xorshift64*: deterministic across runs and machines */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545f4914f6cdd1dull;
}

static size_t rnd_below(size_t n)
{
    return n ? (size_t)(rnd() % n) : 0;
}

/* One to four edits of `in`, into a new buffer of at most twice its size plus 256 bytes. */
static uint8_t *mutate(const lg_fuzz_target *t, const input *in, const input *all, size_t n_all,
                       size_t *out_size)
{
    size_t cap = in->size * 2 + 256;
    uint8_t *b = xmalloc(cap);
    size_t n = in->size;
    memcpy(b, in->data, n);
    int edits = 1; /* one edit half the time: most mutants stay close to a valid input */
    while (edits < 4 && rnd_below(2))
        edits++;
    for (int e = 0; e < edits; e++) {
        size_t span = (t->head && n > t->head && rnd_below(2)) ? t->head : n;
        size_t at = rnd_below(span + 1); /* at <= n */
        /* the last edit, a dictionary token, only where the target has a dictionary */
        switch (rnd_below(t->n_tokens ? 9 : 8)) {
        case 0: /* flip a bit */
            if (span)
                b[rnd_below(span)] ^= (uint8_t)(1u << rnd_below(8));
            break;
        case 1: /* replace a byte */
            if (span)
                b[rnd_below(span)] = (uint8_t)rnd();
            break;
        case 2: { /* a boundary value over 1, 2 or 4 bytes (sizes, offsets, counts) */
            static const uint32_t vals[] = { 0,          1,           0x7f,        0x80,
                                             0xff,       0x7fff,      0x8000,      0xffff,
                                             0x7fffffff, 0x80000000u, 0xffffffffu, 0x10000 };
            uint32_t v = vals[rnd_below(sizeof vals / sizeof *vals)];
            size_t w = (size_t)1 << rnd_below(3);
            if (at + w <= n)
                for (size_t k = 0; k < w; k++)
                    b[at + k] = (uint8_t)(v >> (8 * k));
            break;
        }
        case 3: { /* delete a span */
            size_t len = rnd_below(n - at + 1);
            if (len > 64 && rnd_below(4))
                len = rnd_below(64);
            memmove(b + at, b + at + len, n - at - len);
            n -= len;
            break;
        }
        case 4: { /* copy a span somewhere else */
            if (!n)
                break;
            size_t from = rnd_below(n), len = rnd_below(n - from + 1);
            if (len > 64)
                len = rnd_below(64);
            if (n + len > cap)
                break;
            uint8_t tmp[64];
            memcpy(tmp, b + from, len);
            memmove(b + at + len, b + at, n - at);
            memcpy(b + at, tmp, len);
            n += len;
            break;
        }
        case 5: /* truncate */ n = rnd_below(n + 1); break;
        case 6: { /* splice: our head, another file's tail */
            const input *o = &all[rnd_below(n_all)];
            size_t from = rnd_below(o->size + 1), len = o->size - from;
            if (at + len > cap)
                len = cap - at;
            memcpy(b + at, o->data + from, len);
            n = at + len;
            break;
        }
        case 7: { /* swap two bytes */
            if (n < 2)
                break;
            size_t i = rnd_below(n), j = rnd_below(n);
            uint8_t tmp = b[i];
            b[i] = b[j];
            b[j] = tmp;
            break;
        }
        default: { /* insert a token */
            const lg_fuzz_token *tok = &t->tokens[rnd_below(t->n_tokens)];
            if (n + tok->len > cap)
                break;
            memmove(b + at + tok->len, b + at, n - at);
            memcpy(b + at, tok->bytes, tok->len);
            n += tok->len;
            break;
        }
        }
    }
    *out_size = n;
    return b;
}

/* Reads a whole file; on failure prints why and returns -1. */
static int load_file(const char *who, const char *path, input *in)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "%s: %s: %s\n", who, path, strerror(errno));
        return -1;
    }
    size_t cap = 4096, n = 0;
    uint8_t *data = xmalloc(cap);
    for (;;) {
        n += fread(data + n, 1, cap - n, f);
        if (n < cap)
            break;
        cap *= 2;
        uint8_t *bigger = realloc(data, cap);
        if (!bigger) {
            fprintf(stderr, "%s: %s: out of memory\n", who, path);
            abort();
        }
        data = bigger;
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        fprintf(stderr, "%s: %s: read error\n", who, path);
        free(data);
        return -1;
    }
    size_t len = strlen(path);
    in->name = xmalloc(len + 1);
    memcpy(in->name, path, len + 1);
    in->data = data;
    in->size = n;
    return 0;
}

typedef struct corpus {
    input *in;
    size_t n, cap;
} corpus;

static int add_file(const char *who, const char *path, corpus *c)
{
    if (c->n == c->cap) {
        c->cap = c->cap ? 2 * c->cap : 32;
        input *bigger = realloc(c->in, c->cap * sizeof *c->in);
        if (!bigger) {
            fprintf(stderr, "%s: out of memory\n", who);
            abort();
        }
        c->in = bigger;
    }
    if (load_file(who, path, &c->in[c->n]) != 0)
        return -1;
    c->n++;
    return 0;
}

/* A file, or the regular files of a folder (not its hidden ones or subfolders). */
static int add_path(const char *who, const char *path, corpus *c)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        fprintf(stderr, "%s: %s: %s\n", who, path, strerror(errno));
        return -1;
    }
    if (!S_ISDIR(st.st_mode))
        return add_file(who, path, c);
    DIR *d = opendir(path);
    if (!d) {
        fprintf(stderr, "%s: %s: %s\n", who, path, strerror(errno));
        return -1;
    }
    int rc = 0;
    struct dirent *e;
    while (rc == 0 && (e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        size_t len = strlen(path) + strlen(e->d_name) + 2;
        char *file = xmalloc(len);
        snprintf(file, len, "%s/%s", path, e->d_name);
        if (stat(file, &st) != 0) {
            fprintf(stderr, "%s: %s: %s\n", who, file, strerror(errno));
            rc = -1;
        } else if (S_ISREG(st.st_mode)) {
            rc = add_file(who, file, c);
        }
        free(file);
    }
    closedir(d);
    return rc;
}

static int cmp_input(const void *a, const void *b)
{
    return strcmp(((const input *)a)->name, ((const input *)b)->name);
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

int lg_fuzz_main(int argc, char **argv, const lg_fuzz_target *t)
{
    bound_memory();
    long per_file = t->mutations;
    corpus c = { 0 };
    int rc = 0;
    for (int i = 1; i < argc && rc == 0; i++) {
        if (strcmp(argv[i], "-n") == 0) {
            char *end = NULL;
            per_file = i + 1 < argc ? strtol(argv[++i], &end, 10) : -1;
            if (!end || end == argv[i] || *end || per_file < 0) {
                fprintf(stderr, "%s: -n wants a count of mutations per file\n", t->name);
                rc = 2;
            }
            continue;
        }
        if (add_path(t->name, argv[i], &c) != 0)
            rc = 2;
    }
    if (rc == 0 && c.n == 0) {
        fprintf(stderr, "usage: %s [-n MUTATIONS_PER_FILE] CORPUS_DIR_OR_FILE...\n", t->name);
        rc = 2;
    }
    if (rc == 0) {
        /* readdir order varies: sorted, every run sees the same inputs */
        qsort(c.in, c.n, sizeof *c.in, cmp_input);
        double t0 = now();
        size_t runs = 0;
        for (size_t i = 0; i < c.n; i++, runs++)
            LLVMFuzzerTestOneInput(c.in[i].data, c.in[i].size);
        for (size_t i = 0; i < c.n; i++) {
            for (long m = 0; m < per_file; m++, runs++) {
                size_t size;
                uint8_t *b = mutate(t, &c.in[i], c.in, c.n, &size);
                LLVMFuzzerTestOneInput(b, size);
                free(b);
            }
        }
        printf("%s: %zu inputs (%zu files, %ld mutations each) in %.2f s", t->name, runs, c.n,
               per_file, now() - t0);
        if (t->summary) {
            fputs("; ", stdout);
            t->summary(stdout);
        }
        putchar('\n');
    }
    for (size_t i = 0; i < c.n; i++) {
        free(c.in[i].name);
        free(c.in[i].data);
    }
    free(c.in);
    return rc;
}
