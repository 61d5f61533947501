/* gltf_test: see gltf_test.h. */
#include "gltf_test.h"
#include "common/scratch.h"

#include <errno.h>
#include <ftw.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "lightgraph/vecmath.h"

static char dir[4096];

static void die(const char *what, const char *arg)
{
    fprintf(stderr, "gltf_test: %s %s: %s\n", what, arg, strerror(errno));
    exit(99);
}

void gt_init(const char *name)
{
    if (lg_scratch_make(name, dir, sizeof dir))
        exit(99);
}

void gt_cleanup(bool keep)
{
    if (keep)
        fprintf(stderr, "files kept in %s\n", dir);
    else
        lg_scratch_remove(dir);
}

const char *gt_path(const char *rel)
{
    static char ring[8][4400];
    static int next;
    char *p = ring[next++ % 8];
    snprintf(p, sizeof ring[0], "%s/%s", dir, rel);
    return p;
}

void gt_write(const char *rel, const void *data, size_t size)
{
    const char *p = gt_path(rel);
    FILE *f = fopen(p, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f))
        die("cannot write", p);
}

const char *gt_asset(const char *rel)
{
    static char ring[4][4400];
    static int next;
    const char *root = getenv("LG_SOURCE_ROOT");
    char *p = ring[next++ % 4];
    snprintf(p, sizeof ring[0], "%s/assets/%s", root && *root ? root : ".", rel);
    struct stat st;
    if (stat(p, &st) != 0) {
        /* a repository file: missing is a failure, never a skip */
        fprintf(stderr, "FAIL: asset %s not found\n", p);
        exit(1);
    }
    return p;
}

uint8_t *gt_read(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        die("cannot read", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t *d = malloc((size_t)n + 1);
    if (!d || fread(d, 1, (size_t)n, f) != (size_t)n)
        die("cannot read", path);
    fclose(f);
    *size = (size_t)n;
    return d;
}

size_t gt_add(gt_blob *b, const void *data, size_t size)
{
    size_t at = (b->size + 3) & ~(size_t)3;
    if (at + size > b->cap) {
        b->cap = (at + size) * 2 + 64;
        b->data = realloc(b->data, b->cap);
        if (!b->data)
            die("out of memory", "");
    }
    memset(b->data + b->size, 0, at - b->size);
    memcpy(b->data + at, data, size);
    b->size = at + size;
    return at;
}

void gt_blob_free(gt_blob *b)
{
    free(b->data);
    memset(b, 0, sizeof *b);
}

char *gt_data_uri(const void *data, size_t size)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    static const char head[] = "data:application/octet-stream;base64,";
    const uint8_t *p = data;
    char *out = malloc(sizeof head + (size + 2) / 3 * 4 + 1);
    if (!out)
        die("out of memory", "");
    strcpy(out, head);
    char *o = out + strlen(head);
    for (size_t i = 0; i < size; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < size ? (uint32_t)p[i + 1] << 8 : 0) |
                     (i + 2 < size ? p[i + 2] : 0);
        *o++ = tab[v >> 18 & 63];
        *o++ = tab[v >> 12 & 63];
        *o++ = i + 1 < size ? tab[v >> 6 & 63] : '=';
        *o++ = i + 2 < size ? tab[v & 63] : '=';
    }
    *o = 0;
    return out;
}

char *gt_fmt(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *s = NULL;
    if (vasprintf(&s, fmt, ap) < 0)
        die("out of memory", "");
    va_end(ap);
    return s;
}

lg_scene *gt_load_file(const char *path, const lg_gltf_options *opt, char *err, size_t err_size,
                       int *rc)
{
    lg_gltf_options o = opt ? *opt : lg_gltf_default_options();
    lg_scene *s = NULL;
    int r = lg_gltf_load(path, &o, &s, NULL, err, err_size);
    if (rc)
        *rc = r;
    return r ? NULL : s;
}

lg_scene *gt_load_text(const char *name, const char *json, const lg_gltf_options *opt, char *err,
                       size_t err_size, int *rc)
{
    gt_write(name, json, strlen(json));
    return gt_load_file(gt_path(name), opt, err, err_size, rc);
}

void gt_world(const lg_instance *in, const float *p, float out[3])
{
    lg_vec3 w = lg_m4_point(in->model, lg_v3(p[0], p[1], p[2]));
    out[0] = w.x, out[1] = w.y, out[2] = w.z;
}
