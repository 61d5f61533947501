#include "base/util.h"

#include "lightgraph/file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int lg_verbosity = 0;
int64_t lg_test_free_bytes = -1;

static void oom(size_t n)
{
    fprintf(stderr, "lightgraph: out of memory (allocating %zu bytes)\n", n);
    abort();
}

void *lg_xmalloc(size_t n)
{
    void *p = malloc(n ? n : 1);
    if (!p)
        oom(n);
    return p;
}

void *lg_xcalloc(size_t n, size_t size)
{
    void *p = calloc(n ? n : 1, size ? size : 1);
    if (!p)
        oom(n * size);
    return p;
}

void *lg_xrealloc(void *p, size_t n)
{
    p = realloc(p, n ? n : 1);
    if (!p)
        oom(n);
    return p;
}

char *lg_xstrdup(const char *s)
{
    return lg_xstrndup(s, strlen(s));
}

char *lg_xstrndup(const char *s, size_t n)
{
    char *p = lg_xmalloc(n + 1);
    memcpy(p, s, n);
    p[n] = 0;
    return p;
}

char *lg_vformat(const char *fmt, va_list ap)
{
    /* Into a stack buffer first: one pass for nearly every message, and no
     * vsnprintf(NULL, 0, ...), which GCC 12 misreports under -fsanitize=undefined. */
    if (!fmt)
        return lg_xstrdup("");
    char small[256];
    va_list ap2;
    va_copy(ap2, ap);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    if (n < 0)
        n = 0;
    char *p = lg_xmalloc((size_t)n + 1);
    if ((size_t)n < sizeof small)
        memcpy(p, small, (size_t)n + 1);
    else
        vsnprintf(p, (size_t)n + 1, fmt, ap2);
    va_end(ap2);
    return p;
}

char *lg_xasprintf(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *p = lg_vformat(fmt, ap);
    va_end(ap);
    return p;
}

static void str_reserve(lg_str *b, size_t extra)
{
    if (b->len + extra + 1 <= b->cap)
        return;
    size_t cap = b->cap ? b->cap : 64;
    while (cap < b->len + extra + 1)
        cap *= 2;
    b->s = lg_xrealloc(b->s, cap);
    b->cap = cap;
}

void lg_str_addn(lg_str *b, const char *s, size_t n)
{
    str_reserve(b, n);
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = 0;
}

void lg_str_add(lg_str *b, const char *s)
{
    lg_str_addn(b, s, strlen(s));
}

void lg_str_addc(lg_str *b, char c)
{
    lg_str_addn(b, &c, 1);
}

void lg_str_addf(lg_str *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *p = lg_vformat(fmt, ap);
    va_end(ap);
    lg_str_add(b, p);
    free(p);
}

void lg_str_add_json(lg_str *b, const char *s)
{
    lg_str_addc(b, '"');
    for (const unsigned char *p = (const unsigned char *)(s ? s : ""); *p; p++) {
        switch (*p) {
        case '"': lg_str_add(b, "\\\""); break;
        case '\\': lg_str_add(b, "\\\\"); break;
        case '\n': lg_str_add(b, "\\n"); break;
        case '\t': lg_str_add(b, "\\t"); break;
        case '\r': lg_str_add(b, "\\r"); break;
        default:
            if (*p < 0x20)
                lg_str_addf(b, "\\u%04x", *p);
            else
                lg_str_addc(b, (char)*p);
        }
    }
    lg_str_addc(b, '"');
}

char *lg_str_take(lg_str *b)
{
    char *s = b->s ? b->s : lg_xstrdup("");
    b->s = NULL;
    b->len = b->cap = 0;
    return s;
}

void lg_str_free(lg_str *b)
{
    free(b->s);
    b->s = NULL;
    b->len = b->cap = 0;
}

char *lg_path_dirname(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        return lg_xstrdup(".");
    if (slash == path)
        return lg_xstrdup("/");
    return lg_xstrndup(path, (size_t)(slash - path));
}

char *lg_path_join(const char *dir, const char *rel)
{
    if (rel[0] == '/' || !dir || !dir[0])
        return lg_xstrdup(rel);
    size_t n = strlen(dir);
    return lg_xasprintf("%s%s%s", dir, (n && dir[n - 1] == '/') ? "" : "/", rel);
}

/* Normalises "a/./b/../c" lexically. */
static char *normalise(const char *abs)
{
    size_t n = strlen(abs);
    char *out = lg_xmalloc(n + 2);
    size_t o = 0;
    const char *p = abs;
    while (*p) {
        while (*p == '/')
            p++;
        const char *e = p;
        while (*e && *e != '/')
            e++;
        size_t len = (size_t)(e - p);
        if (len == 0)
            break;
        if (len == 1 && p[0] == '.') {
            /* skip */
        } else if (len == 2 && p[0] == '.' && p[1] == '.') {
            while (o > 0 && out[o - 1] != '/')
                o--;
            if (o > 0)
                o--;
        } else {
            out[o++] = '/';
            memcpy(out + o, p, len);
            o += len;
        }
        p = e;
    }
    if (o == 0)
        out[o++] = '/';
    out[o] = 0;
    return out;
}

char *lg_path_absolute(const char *path)
{
    if (path[0] == '/')
        return normalise(path);
    char cwd[PATH_MAX];
    if (!getcwd(cwd, sizeof cwd))
        return lg_xstrdup(path);
    char *j = lg_path_join(cwd, path);
    char *r = normalise(j);
    free(j);
    return r;
}

bool lg_path_exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

char *lg_read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    lg_str b = { 0 };
    char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        lg_str_addn(&b, buf, n);
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        lg_str_free(&b);
        errno = EIO;
        return NULL;
    }
    if (len)
        *len = b.len;
    return lg_str_take(&b);
}

char *lg_read_file_limit(const char *path, size_t limit, size_t *len, char *err, size_t errlen)
{
    return lg_file_read(path, limit, len, err, errlen);
}

int lg_write_file_atomic(const char *path, const void *data, size_t n)
{
    char *tmp = lg_xasprintf("%s.tmp%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    bool ok = f && fwrite(data, 1, n, f) == n;
    int saved = errno;
    if (f && fclose(f) != 0 && ok) {
        ok = false;
        saved = errno;
    }
    if (ok && rename(tmp, path) != 0) {
        ok = false;
        saved = errno;
    }
    if (!ok) {
        remove(tmp);
        errno = saved ? saved : EIO;
    }
    free(tmp);
    return ok ? 0 : -1;
}

void lg_format_shortest(char out[64], double v, double plain_below, bool short_exponent)
{
    double m = v < 0 ? -v : v;
    if (m == 0 || (m >= 1e-4 && m < plain_below)) {
        for (int d = 0; d <= 25; d++) {
            snprintf(out, 64, "%.*f", d, v);
            if (strtod(out, NULL) == v)
                return;
        }
    }
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(out, 64, "%.*g", prec, v);
        if (strtod(out, NULL) == v)
            break;
    }
    char *e = short_exponent ? strchr(out, 'e') : NULL;
    if (e) { /* "1e+06" -> "1e6", "1e-05" -> "1e-5" */
        char *d = e + 1, *q = e + 1;
        if (*q == '+')
            q++;
        else if (*q == '-')
            *d++ = *q++;
        while (*q == '0' && q[1])
            q++;
        memmove(d, q, strlen(q) + 1);
    }
}

bool lg_parse_uint(const char *s, uint32_t *out, uint32_t max)
{
    char *end;
    errno = 0;
    /* strtoul accepts a sign and leading blanks ("-1" wraps round): only digits here */
    if (!s || *s < '0' || *s > '9')
        return false;
    unsigned long v = strtoul(s, &end, 10);
    if (errno || *end || v == 0 || v > max)
        return false;
    *out = (uint32_t)v;
    return true;
}

bool lg_parse_size(const char *s, uint32_t *w, uint32_t *h)
{
    const char *x = s ? strchr(s, 'x') : NULL;
    if (!x || x == s || (size_t)(x - s) > 10)
        return false;
    char wd[12];
    memcpy(wd, s, (size_t)(x - s));
    wd[x - s] = 0;
    uint32_t a, b;
    if (!lg_parse_uint(wd, &a, LG_MAX_SIZE) || !lg_parse_uint(x + 1, &b, LG_MAX_SIZE))
        return false;
    *w = a;
    *h = b;
    return true;
}

void lg_format_bytes(char *out, size_t n, uint64_t b)
{
    if (b >= (1ull << 20))
        snprintf(out, n, "%.1f MiB", (double)b / (1 << 20));
    else if (b >= 1024)
        snprintf(out, n, "%.1f KiB", (double)b / 1024);
    else
        snprintf(out, n, "%llu B", (unsigned long long)b);
}

void lg_format_duration(char *out, size_t n, double s)
{
    static const struct {
        double unit;
        const char *name;
    } units[] = { { 365.25 * 86400, "years" },
                  { 7 * 86400, "weeks" },
                  { 86400, "days" },
                  { 3600, "h" },
                  { 60, "min" },
                  { 1, "s" } };
    if (!(s >= 0) || s > 1e300) {
        snprintf(out, n, "an unbounded time");
        return;
    }
    for (size_t i = 0; i < sizeof units / sizeof units[0]; i++)
        if (s >= 2 * units[i].unit || (units[i].unit == 1 && s >= 0) ||
            (units[i].unit <= 3600 && s >= units[i].unit)) {
            double v = s / units[i].unit;
            snprintf(out, n, v >= 100 ? "%.0f %s" : "%.2g %s", v, units[i].name);
            return;
        }
    snprintf(out, n, "%.2g s", s);
}

void (*lg_hlog_error_hook)(const char *message);

void lg_hlog(int level, const char *fmt, ...)
{
    if (level == LG_HERR && lg_hlog_error_hook) {
        va_list aq;
        va_start(aq, fmt);
        char *m = NULL;
        if (vasprintf(&m, fmt, aq) >= 0) {
            lg_hlog_error_hook(m);
            free(m);
        }
        va_end(aq);
    }
    if (level >= LG_HINFO && lg_verbosity < level - 1)
        return;
    if (level == LG_HWARN && lg_verbosity < 0)
        return;
    static const char *names[] = { "error", "warning", "info", "debug" };
    fprintf(stderr, "lightgraph: %s: ", names[level < 0 ? 0 : level > 3 ? 3 : level]);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

double lg_mono_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

uint64_t lg_hash64(const void *data, size_t n, uint64_t seed)
{
    const unsigned char *p = data;
    uint64_t h = 1469598103934665603ull ^ seed;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

void lg_digest_init(lg_digest *d)
{
    d->h[0] = 1469598103934665603ull;
    d->h[1] = 0x9e3779b97f4a7c15ull;
}

void lg_digest_add(lg_digest *d, const void *data, size_t n)
{
    const unsigned char *p = data;
    uint64_t a = d->h[0], b = d->h[1];
    for (size_t i = 0; i < n; i++) {
        a ^= p[i];
        a *= 1099511628211ull;
        b += p[i] + 1;
        b *= 0xff51afd7ed558ccdull;
        b ^= b >> 29;
    }
    d->h[0] = a;
    d->h[1] = b;
}

void lg_digest_add_str(lg_digest *d, const char *s)
{
    uint64_t n = s ? strlen(s) : UINT64_MAX;
    lg_digest_add(d, &n, sizeof n);
    if (s)
        lg_digest_add(d, s, (size_t)n);
}

void lg_digest_hex(const lg_digest *d, char out[33])
{
    snprintf(out, 33, "%016llx%016llx", (unsigned long long)d->h[0], (unsigned long long)d->h[1]);
}

bool lg_path_has_ext(const char *path, const char *ext)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash + 1 : path, '.');
    return dot && strcasecmp(dot, ext) == 0;
}

/* ---- records through a pipe ------------------------------------------------------------------ */

void lg_wire_put_raw(lg_str *b, const void *p, size_t n)
{
    lg_str_addn(b, p, n);
}
void lg_wire_put_u32(lg_str *b, uint32_t v)
{
    lg_wire_put_raw(b, &v, sizeof v);
}
void lg_wire_put_u64(lg_str *b, uint64_t v)
{
    lg_wire_put_raw(b, &v, sizeof v);
}
void lg_wire_put_f64(lg_str *b, double v)
{
    lg_wire_put_raw(b, &v, sizeof v);
}

void lg_wire_put_text(lg_str *b, const char *s)
{
    if (!s) {
        lg_wire_put_u32(b, UINT32_MAX);
        return;
    }
    uint32_t n = (uint32_t)strnlen(s, 1u << 20);
    lg_wire_put_u32(b, n);
    lg_wire_put_raw(b, s, n);
}

void lg_wire_get_raw(lg_wire_reader *r, void *out, size_t n)
{
    /* once bad, nothing more is read: the position is no longer where the writer was */
    if (r->bad || (size_t)(r->end - r->p) < n) {
        r->bad = true;
        memset(out, 0, n);
        return;
    }
    memcpy(out, r->p, n);
    r->p += n;
}

uint32_t lg_wire_get_u32(lg_wire_reader *r)
{
    uint32_t v;
    lg_wire_get_raw(r, &v, sizeof v);
    return v;
}

uint64_t lg_wire_get_u64(lg_wire_reader *r)
{
    uint64_t v;
    lg_wire_get_raw(r, &v, sizeof v);
    return v;
}

double lg_wire_get_f64(lg_wire_reader *r)
{
    double v;
    lg_wire_get_raw(r, &v, sizeof v);
    return v;
}

char *lg_wire_get_text(lg_wire_reader *r)
{
    uint32_t n = lg_wire_get_u32(r);
    if (n == UINT32_MAX || r->bad)
        return NULL;
    if ((size_t)(r->end - r->p) < n) {
        r->bad = true;
        return NULL;
    }
    char *s = lg_xstrndup(r->p, n);
    r->p += n;
    return s;
}
