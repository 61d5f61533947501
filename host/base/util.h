/*
 * host/base/util.h: small helpers shared by the host's files (private).
 */
#ifndef LG_HOST_UTIL_H
#define LG_HOST_UTIL_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* Allocation that aborts with a message on failure: the host cannot do anything useful
 * without memory, and every caller checking would hide the real logic. Plugins' memory
 * and image buffers sized by input data use plain malloc and report LG_ERR_NOMEM. */
void *lg_xmalloc(size_t n);
void *lg_xcalloc(size_t n, size_t size);
void *lg_xrealloc(void *p, size_t n);
char *lg_xstrdup(const char *s);
char *lg_xstrndup(const char *s, size_t n);
char *lg_xasprintf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* printf into a malloc'd string; never NULL */
char *lg_vformat(const char *fmt, va_list ap) __attribute__((format(printf, 1, 0)));

/* A growing string. */
typedef struct lg_str {
    char *s;
    size_t len, cap;
} lg_str;
void lg_str_add(lg_str *b, const char *s);
void lg_str_addn(lg_str *b, const char *s, size_t n);
void lg_str_addf(lg_str *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void lg_str_addc(lg_str *b, char c);
/* JSON string literal with quotes and escapes */
void lg_str_add_json(lg_str *b, const char *s);
/* Returns the string (owned by the caller) and resets b. Never NULL. */
char *lg_str_take(lg_str *b);
void lg_str_free(lg_str *b);

/* Records passed from a child process to its parent through a pipe (the plugin scanner's
 * descriptor, conform's results): fixed-size values in the machine's own byte order (both
 * ends are this program), and texts as a 32-bit length, UINT32_MAX for NULL, then the bytes
 * (at most 1 MiB: a longer text is cut). */
void lg_wire_put_raw(lg_str *b, const void *p, size_t n);
void lg_wire_put_u32(lg_str *b, uint32_t v);
void lg_wire_put_u64(lg_str *b, uint64_t v);
void lg_wire_put_f64(lg_str *b, double v);
void lg_wire_put_text(lg_str *b, const char *s);

/* Reads what the lg_wire_put_* functions wrote, bounded by `end`. A read past the end makes
 * the reader bad: it then returns zeros and NULL and reads nothing more (the position is no
 * longer where the writer was), so a caller reads a whole record and checks `bad` once. */
typedef struct lg_wire_reader {
    const char *p, *end;
    bool bad;
} lg_wire_reader;
void lg_wire_get_raw(lg_wire_reader *r, void *out, size_t n);
uint32_t lg_wire_get_u32(lg_wire_reader *r);
uint64_t lg_wire_get_u64(lg_wire_reader *r);
double lg_wire_get_f64(lg_wire_reader *r);
/* A text: malloc'd (the caller frees it), or NULL for a NULL text or a bad reader. */
char *lg_wire_get_text(lg_wire_reader *r);

/* Paths. All return malloc'd strings. */
char *lg_path_dirname(const char *path);              /* "." for a bare name */
char *lg_path_join(const char *dir, const char *rel); /* rel if absolute */
char *lg_path_absolute(const char *path);             /* against the cwd, normalised, no
                                                       * symlink resolution */
bool lg_path_exists(const char *path);
/* Whether the file name's last extension is `ext` (".txt"), ignoring case. */
bool lg_path_has_ext(const char *path, const char *ext);
/* Reads a whole file; returns NULL with errno set. *len receives the size. */
char *lg_read_file(const char *path, size_t *len);
/* Reads a whole regular file of at most `limit` bytes, bounded: anything that is not a
 * regular file after following links (a FIFO, a device, a directory, a socket) is refused
 * without blocking, the size is checked before a byte is read, and no more than `limit`
 * bytes are ever read (a file that grows while read is refused). Returns a malloc'd buffer
 * (NUL-terminated, *len bytes) or NULL with errno set and `err` saying why, naming what the
 * path is ("is a FIFO", "is 22 GiB, over the 16 MiB limit"). */
char *lg_read_file_limit(const char *path, size_t limit, size_t *len, char *err, size_t errlen);

/* Writes `n` bytes to `path` through a temporary file in the same directory renamed into
 * place: a failure never leaves a partial file. Returns 0, or -1 with errno set. */
int lg_write_file_atomic(const char *path, const void *data, size_t n);
/* "12 B", "3.4 KiB", "16.6 MiB" */
void lg_format_bytes(char *out, size_t n, uint64_t bytes);
/* A duration for people, two significant figures: "0.5 s", "42 s", "3.5 min", "1.4 h",
 * "2.3 days", "3.1 weeks", "2.1 years". */
void lg_format_duration(char *out, size_t n, double seconds);
/* The shortest text that reads back as the same double: plain decimals ("1000", "0.3")
 * for 1e-4 <= |v| < plain_below and for 0, else the shortest %g form. With short_exponent
 * the exponent is written short ("1e6", "2.5e-7"; %g gives "1e+06", "2.5e-07"). */
void lg_format_shortest(char out[64], double v, double plain_below, bool short_exponent);

/* Command-line numbers. lg_parse_uint: a decimal integer in 1..max, nothing after it.
 * lg_parse_size: "WxH", each in 1..LG_MAX_SIZE (the --size option of every command). */
#define LG_MAX_SIZE 16384u
bool lg_parse_uint(const char *s, uint32_t *out, uint32_t max);
bool lg_parse_size(const char *s, uint32_t *w, uint32_t *h);

/* Host-side logging to stderr, with the level; verbosity from -v/-q. */
extern int lg_verbosity; /* 0 = errors and warnings, 1 = info, 2 = debug; -1 = errors only */
void lg_hlog(int level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Called with every error message lg_hlog prints (the viewer shows them in its window);
 * NULL: none. Single-threaded use only. */
extern void (*lg_hlog_error_hook)(const char *message);
#define LG_HERR 0
#define LG_HWARN 1
#define LG_HINFO 2
#define LG_HDEBUG 3

/* A test hook: the free bytes that `sweep` believes its output directory's file system
 * has, in place of what statvfs says (-1: not set). main() sets it once, before any
 * thread exists, from LIGHTGRAPH_TEST_FREE_BYTES (a decimal byte count), so that a test
 * can show the refusal of a sweep too large for the disk without filling one. */
extern int64_t lg_test_free_bytes;

/* Monotonic seconds. */
double lg_mono_now(void);

/* 64-bit FNV-1a, and a 128-bit-ish digest for cache keys (two independent 64-bit lanes). */
uint64_t lg_hash64(const void *data, size_t n, uint64_t seed);
typedef struct lg_digest {
    uint64_t h[2];
} lg_digest;
void lg_digest_init(lg_digest *d);
void lg_digest_add(lg_digest *d, const void *data, size_t n);
void lg_digest_add_str(lg_digest *d, const char *s); /* length-prefixed */
void lg_digest_hex(const lg_digest *d, char out[33]);

#endif
