/* lg_gl_buffer, lg_gl_texture and lg_gl_buffer_texture (lightgraph/gl.h) on one GL backend
 * (argv[1]: osmesa or egl), against a fake node whose host counts what they account: kept
 * when the request fits and remade when it does not, data uploaded, every make and release
 * counted (live back to zero after destroy), bad requests refused with a message naming
 * what was wrong, an earlier GL error not blamed on the allocation. Exits 77 if no context
 * can be made. */
#include <stdint.h>
#include <string.h>

#include "exec/device.h"
#include "devtest.h"
#include "lightgraph/gl.h"

/* ---- a fake host: devtest.h's errors and GL, the accounting ---------------------------------- */

static uint64_t live, peak, n_alloc, n_free, bytes_alloc, bytes_free;

static void host_account_alloc(lg_node *n, uint64_t bytes)
{
    (void)n;
    live += bytes;
    peak = live > peak ? live : peak;
    n_alloc++;
    bytes_alloc += bytes;
}

static void host_account_free(lg_node *n, uint64_t bytes)
{
    (void)n;
    CHECKF(bytes <= live, "released %llu bytes with %llu live", (unsigned long long)bytes,
           (unsigned long long)live);
    live -= bytes <= live ? bytes : live;
    n_free++;
    bytes_free += bytes;
}

static const lg_host_api host = {
    DEVTEST_GL_HOST,
    .account_alloc = host_account_alloc,
    .account_free = host_account_free,
};

static const lg_node_type type = { .struct_size = sizeof(lg_node_type), .name = "test" };
static lg_node node = { .host = &host, .name = "memnode", .type = &type };

static void reset_counts(void)
{
    live = peak = n_alloc = n_free = bytes_alloc = bytes_free = 0;
}

/* The first `size` bytes of buffer `name` equal `want`. */
static bool buffer_holds(GLuint name, const void *want, size_t size)
{
    unsigned char got[256];
    if (size > sizeof got)
        return false;
    devtest_gl->GetNamedBufferSubData(name, 0, (GLsizeiptr)size, got);
    return memcmp(got, want, size) == 0;
}

/* ---- buffers --------------------------------------------------------------------------------- */

static void test_buffer(void)
{
    const lg_gl *gl = devtest_gl;
    reset_counts();
    devtest_clear();
    lg_gl_buffer b = { 0 };
    float a[16], c[32];
    for (int i = 0; i < 16; i++)
        a[i] = (float)i + 0.5f;
    for (int i = 0; i < 32; i++)
        c[i] = 100.0f - (float)i;

    /* made with its data, default flags */
    CHECKF(lg_gl_buffer_recreate(&node, &b, sizeof a, 0, a) == 0, "make: %s", devtest_errors);
    CHECK(b.name != 0 && b.size == sizeof a && b.flags == GL_DYNAMIC_STORAGE_BIT);
    CHECK(gl->IsBuffer(b.name));
    CHECKF(buffer_holds(b.name, a, sizeof a), "the data was not uploaded at make");
    CHECK(live == sizeof a && n_alloc == 1 && n_free == 0);
    GLuint first = b.name;

    /* the same size again, other data: kept, uploaded */
    CHECKF(lg_gl_buffer_recreate(&node, &b, sizeof a, 0, c) == 0, "keep: %s", devtest_errors);
    CHECK(b.name == first && n_alloc == 1 && n_free == 0);
    CHECKF(buffer_holds(b.name, c, sizeof a), "the data was not uploaded to a kept buffer");

    /* smaller: kept (the larger buffer holds it), its start uploaded, size unchanged */
    CHECKF(lg_gl_buffer_recreate(&node, &b, 8, 0, a) == 0, "smaller: %s", devtest_errors);
    CHECK(b.name == first && b.size == sizeof a && n_alloc == 1 && live == sizeof a);
    float mix[16];
    memcpy(mix, c, sizeof mix);
    memcpy(mix, a, 8);
    CHECKF(buffer_holds(b.name, mix, sizeof mix), "only the first 8 bytes change");

    /* no data, kept: nothing happens */
    CHECK(lg_gl_buffer_recreate(&node, &b, sizeof a, 0, NULL) == 0 && b.name == first);
    CHECKF(buffer_holds(b.name, mix, sizeof mix), "a kept buffer without data keeps its data");

    /* larger: remade, the old one released first (peak = the larger, not the sum) */
    CHECKF(lg_gl_buffer_recreate(&node, &b, sizeof c, 0, c) == 0, "larger: %s", devtest_errors);
    CHECK(b.size == sizeof c && n_alloc == 2 && n_free == 1);
    CHECKF(live == sizeof c && peak == sizeof c, "live %llu peak %llu", (unsigned long long)live,
           (unsigned long long)peak);
    CHECKF(buffer_holds(b.name, c, sizeof c), "the data of a remade buffer");
    CHECK(!gl->IsBuffer(first) || b.name == first); /* GL may hand the name out again */

    /* other flags: remade */
    GLbitfield rf = GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT;
    CHECKF(lg_gl_buffer_recreate(&node, &b, sizeof c, rf, NULL) == 0, "flags: %s", devtest_errors);
    CHECK(b.flags == rf && n_alloc == 3 && n_free == 2 && live == sizeof c);

    /* immutable (no GL_DYNAMIC_STORAGE_BIT): data for a kept one makes it anew */
    CHECKF(lg_gl_buffer_recreate(&node, &b, sizeof a, GL_MAP_READ_BIT, a) == 0, "ro: %s",
           devtest_errors);
    uint64_t allocs = n_alloc;
    CHECKF(lg_gl_buffer_recreate(&node, &b, sizeof a, GL_MAP_READ_BIT, c) == 0, "ro again: %s",
           devtest_errors);
    CHECK(n_alloc == allocs + 1 && buffer_holds(b.name, c, sizeof a));
    CHECK(lg_gl_buffer_recreate(&node, &b, sizeof a, GL_MAP_READ_BIT, NULL) == 0 &&
          n_alloc == allocs + 1); /* without data it is kept */
    devtest_clear();
    CHECK(lg_gl_buffer_upload(&node, &b, 0, 4, a) == LG_ERR_INVALID &&
          strstr(devtest_errors, "GL_DYNAMIC_STORAGE_BIT"));

    /* uploads: at an offset, past the end, from nothing */
    CHECK(lg_gl_buffer_recreate(&node, &b, sizeof c, 0, c) == 0);
    CHECKF(lg_gl_buffer_upload(&node, &b, 16, 8, a) == 0, "upload: %s", devtest_errors);
    float want[32];
    memcpy(want, c, sizeof want);
    memcpy((char *)want + 16, a, 8);
    CHECKF(buffer_holds(b.name, want, sizeof want), "upload at offset 16");
    devtest_clear();
    CHECKF(lg_gl_buffer_upload(&node, &b, sizeof c - 4, 8, a) == LG_ERR_INVALID &&
               strstr(devtest_errors, "overrun the 128-byte buffer"),
           "overrun: %s", devtest_errors);
    devtest_clear();
    CHECK(lg_gl_buffer_upload(&node, &b, SIZE_MAX, 8, a) == LG_ERR_INVALID);
    devtest_clear();
    CHECK(lg_gl_buffer_upload(&node, &b, 0, 8, NULL) == LG_ERR_INVALID &&
          strstr(devtest_errors, "no data"));
    CHECK(lg_gl_buffer_upload(&node, &b, 0, 0, NULL) == 0);
    lg_gl_buffer none = { 0 };
    devtest_clear();
    CHECK(lg_gl_buffer_upload(&node, &none, 0, 4, a) == LG_ERR_INVALID &&
          strstr(devtest_errors, "was not made"));

    /* a zero size: refused, the handle and the counts untouched */
    devtest_clear();
    uint64_t before = live;
    GLuint kept = b.name;
    CHECKF(lg_gl_buffer_recreate(&node, &b, 0, 0, NULL) == LG_ERR_INVALID &&
               strstr(devtest_errors, "0 bytes") && devtest_error_count == 1,
           "zero size: %s", devtest_errors);
    CHECK(b.name == kept && live == before);
    devtest_clear();
    CHECK(lg_gl_buffer_recreate(&node, NULL, 4, 0, NULL) == LG_ERR_INVALID);
    devtest_clear();
    CHECK(lg_gl_buffer_recreate(&node, &b, (size_t)PTRDIFF_MAX + 1, 0, NULL) == LG_ERR_INVALID &&
          strstr(devtest_errors, "beyond"));

    /* a GL error of the allocation itself (here flags GL does not know: GL_INVALID_VALUE;
     * no huge size, which a sanitizer build would abort on): reported with what was asked,
     * nothing counted, the handle empty */
    lg_gl_buffer bad = { 0 };
    devtest_clear();
    uint64_t allocs_before = n_alloc;
    int rc = lg_gl_buffer_recreate(&node, &bad, 16, 0x40000000u | GL_DYNAMIC_STORAGE_BIT, NULL);
    CHECKF(rc == LG_ERR_DEVICE &&
               strstr(devtest_errors, "GL_INVALID_VALUE while making a GL buffer of 16 bytes "
                                      "(storage flags 0x40000100)"),
           "bad flags: rc %d: %s", rc, devtest_errors);
    CHECK(bad.name == 0 && n_alloc == allocs_before && gl->GetError() == GL_NO_ERROR);

    /* destroy: released, zeroed; twice and NULL are fine */
    GLuint name = b.name;
    lg_gl_buffer_destroy(&node, &b);
    CHECK(b.name == 0 && b.size == 0 && b.flags == 0 && !gl->IsBuffer(name));
    lg_gl_buffer_destroy(&node, &b);
    lg_gl_buffer_destroy(&node, NULL);
    CHECKF(live == 0 && n_alloc == n_free && bytes_alloc == bytes_free,
           "accounting after destroy: live %llu, %llu makes, %llu releases",
           (unsigned long long)live, (unsigned long long)n_alloc, (unsigned long long)n_free);
    CHECK(gl->GetError() == GL_NO_ERROR);
}

/* ---- textures -------------------------------------------------------------------------------- */

static GLint level_param(GLuint tex, GLint level, GLenum what)
{
    GLint v = -1;
    devtest_gl->GetTextureLevelParameteriv(tex, level, what, &v);
    return v;
}

static void expect_refused(const lg_gl_texture_desc *d, const char *words, const char *what)
{
    lg_gl_texture t = { 0 };
    uint64_t allocs = n_alloc;
    devtest_clear();
    int rc = lg_gl_texture_recreate(&node, &t, d);
    CHECKF(rc == LG_ERR_INVALID && strstr(devtest_errors, words) && devtest_error_count == 1,
           "%s: rc %d, errors '%s' (want '%s')", what, rc, devtest_errors, words);
    CHECKF(t.name == 0 && n_alloc == allocs, "%s: something was made", what);
    CHECKF(lg_gl_texture_bytes(d) == 0 || strstr(what, "limit"), "%s: bytes of a bad desc", what);
    CHECK(devtest_gl->GetError() == GL_NO_ERROR);
}

static void test_texture(void)
{
    const lg_gl *gl = devtest_gl;
    reset_counts();
    devtest_clear();
    lg_gl_texture t = { 0 };
    lg_gl_texture_desc d = {
        .target = GL_TEXTURE_2D, .format = GL_RGBA32F, .width = 5, .height = 3
    };

    /* made: 1, the size and format asked, counted, complete as made */
    CHECKF(lg_gl_texture_recreate(&node, &t, &d) == 1, "make: %s", devtest_errors);
    CHECK(t.name && gl->IsTexture(t.name));
    CHECK(level_param(t.name, 0, GL_TEXTURE_WIDTH) == 5 &&
          level_param(t.name, 0, GL_TEXTURE_HEIGHT) == 3 &&
          level_param(t.name, 0, GL_TEXTURE_INTERNAL_FORMAT) == GL_RGBA32F);
    CHECK(t.bytes == 5 * 3 * 16 && live == t.bytes && n_alloc == 1);
    CHECK(t.desc.depth == 1 && t.desc.levels == 1);
    GLint minf = 0, wrap = 0;
    gl->GetTextureParameteriv(t.name, GL_TEXTURE_MIN_FILTER, &minf);
    gl->GetTextureParameteriv(t.name, GL_TEXTURE_WRAP_S, &wrap);
    CHECKF(minf == GL_NEAREST && wrap == GL_CLAMP_TO_EDGE, "min filter 0x%x wrap 0x%x", minf, wrap);

    /* the same desc, and one spelling the defaults out: kept (0) */
    GLuint first = t.name;
    CHECK(lg_gl_texture_recreate(&node, &t, &d) == 0 && t.name == first && n_alloc == 1);
    lg_gl_texture_desc d1 = d;
    d1.depth = 1;
    d1.levels = 1;
    CHECK(lg_gl_texture_recreate(&node, &t, &d1) == 0 && t.name == first && n_alloc == 1);

    /* another size: remade; the old one released first */
    lg_gl_texture_desc d2 = d;
    d2.width = 8;
    d2.height = 8;
    CHECKF(lg_gl_texture_recreate(&node, &t, &d2) == 1, "resize: %s", devtest_errors);
    CHECK(level_param(t.name, 0, GL_TEXTURE_WIDTH) == 8);
    CHECKF(live == 8 * 8 * 16 && peak == 8 * 8 * 16 && n_free == 1,
           "after a resize: live %llu peak %llu releases %llu", (unsigned long long)live,
           (unsigned long long)peak, (unsigned long long)n_free);
    /* a smaller one is remade too: a texture is what its desc says */
    CHECK(lg_gl_texture_recreate(&node, &t, &d) == 1 && live == 5 * 3 * 16);
    /* another format: remade */
    lg_gl_texture_desc d3 = d;
    d3.format = GL_R32UI;
    CHECK(lg_gl_texture_recreate(&node, &t, &d3) == 1 && t.bytes == 5 * 3 * 4 && live == t.bytes);
    CHECK(level_param(t.name, 0, GL_TEXTURE_INTERNAL_FORMAT) == GL_R32UI);

    /* the other targets and their bytes: every level, face and layer */
    lg_gl_texture cube = { 0 }, vol = { 0 }, arr = { 0 }, dep = { 0 };
    lg_gl_texture_desc dc = {
        .target = GL_TEXTURE_CUBE_MAP, .format = GL_RGBA16F, .width = 8, .height = 8, .levels = 4
    };
    CHECKF(lg_gl_texture_recreate(&node, &cube, &dc) == 1, "cube: %s", devtest_errors);
    CHECK(cube.bytes == 6ull * (64 + 16 + 4 + 1) * 8 && lg_gl_texture_bytes(&dc) == cube.bytes);
    GLint levels = 0;
    gl->GetTextureParameteriv(cube.name, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
    CHECK(levels == 4);
    gl->GetTextureParameteriv(cube.name, GL_TEXTURE_MIN_FILTER, &minf);
    CHECK(minf == GL_NEAREST_MIPMAP_NEAREST);
    lg_gl_texture_desc dv = { .target = GL_TEXTURE_3D,
                              .format = GL_RGBA32F,
                              .width = 4,
                              .height = 4,
                              .depth = 2,
                              .levels = 3 };
    CHECKF(lg_gl_texture_recreate(&node, &vol, &dv) == 1, "3d: %s", devtest_errors);
    CHECK(vol.bytes == (32ull + 4 + 1) * 16 && level_param(vol.name, 0, GL_TEXTURE_DEPTH) == 2);
    lg_gl_texture_desc da = { .target = GL_TEXTURE_2D_ARRAY,
                              .format = GL_R8,
                              .width = 4,
                              .height = 2,
                              .depth = 5,
                              .levels = 2 };
    CHECKF(lg_gl_texture_recreate(&node, &arr, &da) == 1, "array: %s", devtest_errors);
    CHECK(arr.bytes == (8ull + 2) * 5 && level_param(arr.name, 1, GL_TEXTURE_DEPTH) == 5);
    lg_gl_texture_desc dd = {
        .target = GL_TEXTURE_2D, .format = GL_DEPTH_COMPONENT32F, .width = 7, .height = 5
    };
    CHECKF(lg_gl_texture_recreate(&node, &dep, &dd) == 1, "depth: %s", devtest_errors);
    CHECK(dep.bytes == 7 * 5 * 4);
    CHECK(live == t.bytes + cube.bytes + vol.bytes + arr.bytes + dep.bytes);

    /* what is refused, and why */
    lg_gl_texture_desc bad = d;
    bad.format = GL_RGBA; /* unsized */
    expect_refused(&bad, "format 0x1908 is not a sized internal format", "unsized format");
    bad = d;
    bad.format = GL_FLOAT; /* a pixel type */
    expect_refused(&bad, "format 0x1406", "a type as format");
    bad = d;
    bad.target = GL_TEXTURE_1D;
    expect_refused(&bad, "target 0x0de0 is not one of", "1D target");
    bad = d;
    bad.width = 0;
    expect_refused(&bad, "a GL_TEXTURE_2D of 0x3 has no texels", "zero width");
    bad = d;
    bad.depth = 4;
    expect_refused(&bad, "a GL_TEXTURE_2D has depth 1, not 4", "2D with depth");
    bad = dc;
    bad.height = 4;
    expect_refused(&bad, "a cube map's faces are square, not 8x4", "cube not square");
    bad = dc;
    bad.levels = 5;
    expect_refused(&bad, "5 levels for 8x8x1 (at most 4)", "too many levels");
    GLint max_size = 0;
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    bad = d;
    bad.width = (uint32_t)max_size + 1;
    expect_refused(&bad, "beyond the device's GL_MAX_TEXTURE_SIZE", "size limit");
    bad = dv;
    bad.levels = 1;
    GLint max_3d = 0;
    gl->GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max_3d);
    bad.depth = (uint32_t)max_3d + 1;
    expect_refused(&bad, "GL_MAX_3D_TEXTURE_SIZE", "3D depth limit");
    devtest_clear();
    CHECK(lg_gl_texture_recreate(&node, &t, NULL) == LG_ERR_INVALID &&
          strstr(devtest_errors, "descriptor"));

    /* a refused desc leaves a made texture as it was */
    GLuint name = t.name;
    bad = d3;
    bad.format = GL_RGB; /* unsized */
    devtest_clear();
    CHECK(lg_gl_texture_recreate(&node, &t, &bad) == LG_ERR_INVALID && t.name == name &&
          gl->IsTexture(name));

    /* a GL error the node left pending is named as the node's, and nothing is made */
    lg_gl_texture other = { 0 };
    gl->Enable(0x7fff); /* GL_INVALID_ENUM */
    devtest_clear();
    uint64_t allocs = n_alloc;
    CHECKF(lg_gl_texture_recreate(&node, &other, &d) == LG_ERR_DEVICE &&
               strstr(devtest_errors, "the node's own GL calls before lg_gl_texture_recreate") &&
               strstr(devtest_errors, "GL_INVALID_ENUM"),
           "pending error: %s", devtest_errors);
    CHECK(other.name == 0 && n_alloc == allocs);
    CHECK(lg_gl_texture_recreate(&node, &other, &d) == 1); /* the next call works */

    /* destroy all: back to zero */
    lg_gl_texture *all[] = { &t, &cube, &vol, &arr, &dep, &other };
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
        GLuint nm = all[i]->name;
        lg_gl_texture_destroy(&node, all[i]);
        CHECK(all[i]->name == 0 && all[i]->bytes == 0 && !gl->IsTexture(nm));
    }
    lg_gl_texture_destroy(&node, &t);
    lg_gl_texture_destroy(&node, NULL);
    CHECKF(live == 0 && n_alloc == n_free && bytes_alloc == bytes_free,
           "accounting after destroy: live %llu, %llu makes, %llu releases",
           (unsigned long long)live, (unsigned long long)n_alloc, (unsigned long long)n_free);
    CHECK(gl->GetError() == GL_NO_ERROR);
}

/* ---- buffer textures ------------------------------------------------------------------------- */

static void test_buffer_texture(void)
{
    const lg_gl *gl = devtest_gl;
    reset_counts();
    devtest_clear();
    float data[12] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12 };
    lg_gl_buffer b1 = { 0 }, b2 = { 0 };
    CHECK(lg_gl_buffer_recreate(&node, &b1, sizeof data, 0, data) == 0);
    CHECK(lg_gl_buffer_recreate(&node, &b2, sizeof data, 0, data) == 0);
    uint64_t buffers = live;

    lg_gl_buffer_texture v = { 0 };
    CHECKF(lg_gl_buffer_texture_recreate(&node, &v, GL_RGB32F, b1.name) == 1, "make: %s",
           devtest_errors);
    CHECK(v.name && v.buffer == b1.name && v.format == GL_RGB32F);
    CHECK(level_param(v.name, 0, GL_TEXTURE_BUFFER_DATA_STORE_BINDING) == (GLint)b1.name);
    CHECK(level_param(v.name, 0, GL_TEXTURE_INTERNAL_FORMAT) == GL_RGB32F);
    CHECK(live == buffers); /* a view holds nothing */
    CHECK(lg_gl_buffer_texture_recreate(&node, &v, GL_RGB32F, b1.name) == 0);
    CHECK(lg_gl_buffer_texture_recreate(&node, &v, GL_RGB32F, b2.name) == 1 &&
          level_param(v.name, 0, GL_TEXTURE_BUFFER_DATA_STORE_BINDING) == (GLint)b2.name);
    CHECK(lg_gl_buffer_texture_recreate(&node, &v, GL_R32F, b2.name) == 1);

    devtest_clear();
    lg_gl_buffer_texture w = { 0 };
    CHECKF(lg_gl_buffer_texture_recreate(&node, &w, GL_RGBA, b1.name) == LG_ERR_INVALID &&
               strstr(devtest_errors, "format 0x1908 is not one a buffer texture takes"),
           "unsized: %s", devtest_errors);
    devtest_clear();
    CHECKF(lg_gl_buffer_texture_recreate(&node, &w, GL_DEPTH_COMPONENT32F, b1.name) ==
                   LG_ERR_INVALID &&
               strstr(devtest_errors, "GL_DEPTH_COMPONENT32F is not one"),
           "depth: %s", devtest_errors);
    devtest_clear();
    CHECKF(lg_gl_buffer_texture_recreate(&node, &w, GL_R32F, 0) == LG_ERR_INVALID &&
               strstr(devtest_errors, "no buffer"),
           "buffer 0: %s", devtest_errors);
    CHECK(w.name == 0);

    GLuint name = v.name;
    lg_gl_buffer_texture_destroy(&node, &v);
    CHECK(v.name == 0 && !gl->IsTexture(name) && gl->IsBuffer(b2.name)); /* not its buffer */
    lg_gl_buffer_texture_destroy(&node, &v);
    lg_gl_buffer_texture_destroy(&node, NULL);
    lg_gl_buffer_destroy(&node, &b1);
    lg_gl_buffer_destroy(&node, &b2);
    CHECK(live == 0 && n_alloc == n_free);
    CHECK(gl->GetError() == GL_NO_ERROR);
}

int main(int argc, char **argv)
{
    lg_gl_device *dev;
    if (devtest_gl_open(argc, argv, &dev))
        return check_skip("gl_mem");
    test_buffer();
    test_texture();
    test_buffer_texture();
    lg_gl_device_destroy(&dev);
    return check_report("gl_mem");
}
