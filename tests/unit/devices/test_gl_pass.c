/* lg_gl_pass (lightgraph/gl_pass.h) on one GL backend (argv[1]: osmesa or egl): a raster pass
 * drawing known triangles into a node's output (depth test, blending, clears), a compute pass
 * with group counts from its local size, a scene's draw data kept across frames and made
 * again when the scene changes, name look-ups and their errors, target checks, and the GL
 * state after end; since ABI 3.0 the depth function, sampler state in texture bindings
 * (filter, wrap, comparison, seamless cube maps), mat3 and array uniforms and whole uniform
 * blocks (lg_gl_pass_uniforms), each proved by pixels or values read back. Exits 77 if no
 * context can be made. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "exec/device.h"
#include "devtest.h"
#include "lightgraph/gl_pass.h"
#include "lightgraph/plugin.h"

/* ---- a minimal host: devtest.h's errors and GL, one output image ----------------------------- */

static GLuint out_color, out_depth; /* what map_gl hands out for output 0 */
enum { W = 8, H = 8 };

static int dummy_resource, scene_resource;
static lg_scene the_scene;

/* The host's GPU copies of the scene's arrays: one buffer per slot, made on first use. */
static GLuint slot_buf[16];
static int host_payload_gl_buffer(lg_node *n, const lg_resource *res, uint32_t slot,
                                  const void *data, size_t size, uint32_t *buffer)
{
    (void)res;
    if (slot >= 16)
        return lg_error(n, "slot %u", slot);
    if (!data) {
        *buffer = 0;
        return 0;
    }
    if (!slot_buf[slot]) {
        devtest_gl->CreateBuffers(1, &slot_buf[slot]);
        devtest_gl->NamedBufferStorage(slot_buf[slot], (GLsizeiptr)size, data, 0);
    }
    *buffer = slot_buf[slot];
    return 0;
}

static lg_resource *host_output(lg_node *n, uint32_t port)
{
    (void)n;
    return port == 0 ? (lg_resource *)&dummy_resource : NULL;
}

static int host_describe(const lg_resource *r, lg_resource_info *info)
{
    memset(info, 0, sizeof *info);
    if (r == (const lg_resource *)&scene_resource) {
        info->kind = LG_KIND_SCENE;
        info->payload = &the_scene;
        return 0;
    }
    if (r != (const lg_resource *)&dummy_resource)
        return LG_ERR_INVALID;
    info->kind = LG_KIND_IMAGE;
    info->image.width = W;
    info->image.height = H;
    info->image.format = LG_FORMAT_RGBA32F;
    return 0;
}

static int host_map_gl(lg_node *n, const lg_resource *r, unsigned access, uint32_t *name,
                       uint32_t *depth)
{
    (void)n, (void)access;
    if (r != (const lg_resource *)&dummy_resource)
        return LG_ERR_INVALID;
    *name = out_color;
    *depth = out_depth;
    return 0;
}

/* The profile's count of what the SDK allocates for the node (uniform-block buffers). */
static int64_t accounted;
static void host_account_alloc(lg_node *n, uint64_t bytes)
{
    (void)n;
    accounted += (int64_t)bytes;
}
static void host_account_free(lg_node *n, uint64_t bytes)
{
    (void)n;
    accounted -= (int64_t)bytes;
}

static const lg_host_api host = {
    DEVTEST_GL_HOST,
    .output = host_output,
    .describe = host_describe,
    .map_gl = host_map_gl,
    .payload_gl_buffer = host_payload_gl_buffer,
    .account_alloc = host_account_alloc,
    .account_free = host_account_free,
};

static const lg_port_desc outputs[] = { { .name = "out", .kind = LG_KIND_IMAGE } };
static const lg_node_type type = { .struct_size = sizeof(lg_node_type),
                                   .name = "test",
                                   LG_OUTPUTS(outputs) };
static lg_node node = { .host = &host, .name = "passnode", .type = &type };

/* ---- shaders --------------------------------------------------------------------------------- */

/* The lower-left triangle of clip space, (-1,-1) (1,-1) (-1,1), at depth u_z: window pixel
 * (x, y) with x + y < W - 1 is inside (its centre is strictly below the diagonal). */
static const char tri_vert[] =
    "#version 450 core\n"
    "uniform float u_z;\n"
    "void main()\n"
    "{\n"
    "    vec2 p = vec2(gl_VertexID == 1 ? 1.0 : -1.0, gl_VertexID == 2 ? 1.0 : -1.0);\n"
    "    gl_Position = vec4(p, u_z, 1.0);\n"
    "}\n";

static const char tri_frag[] =
    "#version 450 core\n"
    "uniform vec4 u_color;\n"
    "layout(binding = 2) uniform sampler2D u_tex;\n"
    "layout(std430, binding = 3) readonly buffer Scale { float scale; };\n"
    "layout(location = 0) out vec4 o_color;\n"
    "void main()\n"
    "{\n"
    "    o_color = u_color * scale + texelFetch(u_tex, ivec2(0), 0);\n"
    "}\n";

/* Each invocation inside the size writes its id into u_out and counts itself. */
static const char count_comp[] =
    "#version 450\n"
    "layout(local_size_x = 8, local_size_y = 4) in;\n"
    "layout(binding = 1, rgba32f) uniform writeonly image2D u_out;\n"
    "layout(std430, binding = 2) buffer Counts { uint invocations; uint groups; };\n"
    "uniform ivec2 u_size;\n"
    "void main()\n"
    "{\n"
    "    ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
    "    if (gl_LocalInvocationIndex == 0u)\n"
    "        atomicAdd(groups, 1u);\n"
    "    if (p.x >= u_size.x || p.y >= u_size.y)\n"
    "        return;\n"
    "    atomicAdd(invocations, 1u);\n"
    "    imageStore(u_out, p, vec4(float(p.x), float(p.y), 7.0, 1.0));\n"
    "}\n";

/* A C mirror of Counts, checked at compile time. */
typedef struct counts {
    uint32_t invocations, groups;
} counts;
LG_GL_BLOCK_SIZE(counts, 8);
LG_GL_BLOCK_OFFSET(counts, groups, 4);

/* ---- helpers --------------------------------------------------------------------------------- */

static GLuint make_tex(const lg_gl *gl, GLenum format, int w, int h)
{
    GLuint t;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &t);
    gl->TextureStorage2D(t, 1, format, w, h);
    return t;
}

static void read_rgba(const lg_gl *gl, GLuint tex, float *px, int w, int h)
{
    gl->GetTextureImage(tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)(w * h * 4 * sizeof(float)), px);
}

/* The bindings and capabilities end promises (besides lg_gl_state_check's list). */
static void check_restored(const lg_gl *gl, const char *when)
{
    char err[1024];
    CHECKF(lg_gl_state_check(gl, err, sizeof err) == 0, "%s: %s", when, err);
    GLint v = -1;
    for (GLuint i = 0; i < 8; i++) {
        gl->GetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, i, &v);
        CHECKF(v == 0, "%s: storage binding %u = %d", when, i, v);
        gl->GetIntegeri_v(GL_IMAGE_BINDING_NAME, i, &v);
        CHECKF(v == 0, "%s: image unit %u = %d", when, i, v);
        gl->ActiveTexture(GL_TEXTURE0 + i);
        gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &v);
        CHECKF(v == 0, "%s: texture unit %u = %d", when, i, v);
    }
    for (GLuint i = 0; i < 8; i++) {
        gl->ActiveTexture(GL_TEXTURE0 + i);
        gl->GetIntegerv(GL_SAMPLER_BINDING, &v);
        CHECKF(v == 0, "%s: sampler object %d left on unit %u", when, v, i);
        gl->GetIntegerv(GL_TEXTURE_BINDING_CUBE_MAP, &v);
        CHECKF(v == 0, "%s: cube map %d left on unit %u", when, v, i);
        gl->GetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, i, &v);
        CHECKF(v == 0, "%s: uniform buffer binding %u = %d", when, i, v);
    }
    gl->ActiveTexture(GL_TEXTURE0);
    CHECKF(!gl->IsEnabled(GL_DEPTH_TEST) && !gl->IsEnabled(GL_BLEND) &&
               !gl->IsEnabled(GL_CULL_FACE) && !gl->IsEnabled(GL_DEPTH_CLAMP),
           "%s: a capability is left enabled", when);
    CHECKF(!gl->IsEnabled(GL_TEXTURE_CUBE_MAP_SEAMLESS), "%s: seamless cube maps left on", when);
    GLboolean mask = GL_FALSE;
    gl->GetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    CHECKF(mask == GL_TRUE, "%s: depth mask left false", when);
    gl->GetIntegerv(GL_DEPTH_FUNC, &v);
    CHECKF(v == GL_LESS, "%s: glDepthFunc left 0x%04x (want GL_LESS)", when, (unsigned)v);
    GLenum e = gl->GetError();
    CHECKF(e == GL_NO_ERROR, "%s: %s pending", when, lg_gl_strerror(e));
}

/* ---- tests ----------------------------------------------------------------------------------- */

static void test_raster(const lg_gl *gl)
{
    devtest_clear();
    out_color = make_tex(gl, GL_RGBA32F, W, H);
    out_depth = make_tex(gl, GL_DEPTH_COMPONENT32F, W, H);
    GLuint white = make_tex(gl, GL_RGBA32F, 1, 1), black = make_tex(gl, GL_RGBA32F, 1, 1);
    const float zero[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    gl->ClearTexImage(black, 0, GL_RGBA, GL_FLOAT, zero);
    const float w4[4] = { 0.25f, 0.25f, 0.25f, 0.0f };
    gl->ClearTexImage(white, 0, GL_RGBA, GL_FLOAT, w4);
    GLuint scale_buf;
    const float two = 2.0f;
    gl->CreateBuffers(1, &scale_buf);
    gl->NamedBufferStorage(scale_buf, sizeof two, &two, 0);

    const lg_gl_shader_src src[2] = { { GL_VERTEX_SHADER, "tri.vert", tri_vert },
                                      { GL_FRAGMENT_SHADER, "tri.frag", tri_frag } };
    lg_gl_pass_desc d = { .name = "triangle",
                          .stages = src,
                          .n_stages = 2,
                          .output = "out",
                          .colors = { GL_RGBA32F },
                          .depth = true,
                          .depth_test = true,
                          .depth_write = true };
    lg_gl_pass *p = NULL;
    int rc = lg_gl_pass_create(&node, &d, &p);
    CHECKF(rc == 0 && p, "create: %s", devtest_errors);
    if (!p)
        return;
    lg_gl_uniform u_z = lg_gl_pass_uniform(p, "u_z");
    lg_gl_uniform u_color = lg_gl_pass_uniform(p, "u_color");
    lg_gl_binding tex = lg_gl_pass_texture(p, "u_tex");
    lg_gl_binding scale = lg_gl_pass_storage(p, "Scale");
    CHECKF(devtest_error_count == 0, "look-ups: %s", devtest_errors);
    CHECKF(tex.index == 2 && scale.index == 3, "bindings %d %d", tex.index, scale.index);

    /* two frames: the second reuses the program and framebuffer */
    for (int frame = 0; frame < 2; frame++) {
        rc = lg_gl_pass_begin(p, NULL);
        CHECKF(rc == 0, "begin (frame %d): %s", frame, devtest_errors);
        if (rc)
            return;
        const lg_gl_target *t = lg_gl_pass_current_target(p);
        CHECKF(t && t->color[0] == out_color && t->depth == out_depth && t->width == W,
               "current target");
        GLint vp[4];
        gl->GetIntegerv(GL_VIEWPORT, vp);
        CHECKF(vp[0] == 0 && vp[1] == 0 && vp[2] == W && vp[3] == H, "viewport %d %d %d %d", vp[0],
               vp[1], vp[2], vp[3]);
        const float bg[4] = { 0.0f, 0.0f, 1.0f, 1.0f };
        lg_gl_pass_clear_color(p, 0, bg);
        lg_gl_pass_clear_depth(p, 1.0f);
        lg_gl_pass_bind_buffer(p, scale, scale_buf);
        lg_gl_pass_bind_texture(p, tex, black);
        /* in front (z 0): red * 2; then behind (z 0.5): green, hidden by the depth test */
        const float red[4] = { 0.5f, 0.0f, 0.0f, 1.0f }, green[4] = { 0.0f, 0.5f, 0.0f, 0.5f };
        lg_gl_set_float(p, u_z, 0.0f);
        lg_gl_set_vec4v(p, u_color, red);
        rc = lg_gl_pass_draw(p, GL_TRIANGLES, 3);
        lg_gl_set_float(p, u_z, 0.5f);
        lg_gl_set_vec4v(p, u_color, green);
        if (!rc)
            rc = lg_gl_pass_draw(p, GL_TRIANGLES, 3);
        rc = lg_gl_pass_end(p, rc);
        CHECKF(rc == 0, "draw/end (frame %d): %s", frame, devtest_errors);
        check_restored(gl, "after a raster pass");
    }
    float px[W * H * 4];
    read_rgba(gl, out_color, px, W, H);
    /* texel row 0 is window row 0 (y = 0 at the bottom in GL's window space) */
    const float *in = &px[(1 * W + 1) * 4], *out = &px[(6 * W + 6) * 4];
    CHECKF(in[0] == 1.0f && in[1] == 0.0f && in[2] == 0.0f && in[3] == 2.0f,
           "inside: %g %g %g %g (want 1 0 0 2)", in[0], in[1], in[2], in[3]);
    CHECKF(out[0] == 0.0f && out[1] == 0.0f && out[2] == 1.0f && out[3] == 1.0f,
           "outside: %g %g %g %g (want the clear colour 0 0 1 1)", out[0], out[1], out[2], out[3]);

    /* blending: ADD on top of the last image, no depth test, an explicit target */
    lg_gl_pass *b = NULL;
    lg_gl_pass_desc db = { .name = "add",
                           .stages = src,
                           .n_stages = 2,
                           .colors = { GL_RGBA32F },
                           .blend = LG_GL_BLEND_ADD };
    CHECKF(lg_gl_pass_create(&node, &db, &b) == 0, "create add: %s", devtest_errors);
    if (b) {
        lg_gl_uniform bz = lg_gl_pass_uniform(b, "u_z"), bc = lg_gl_pass_uniform(b, "u_color");
        lg_gl_binding bt = lg_gl_pass_texture(b, "u_tex"), bs = lg_gl_pass_storage(b, "Scale");
        lg_gl_target tgt = { .color = { out_color }, .width = W, .height = H };
        CHECKF(lg_gl_pass_begin(b, &tgt) == 0, "begin add: %s", devtest_errors);
        lg_gl_pass_bind_buffer(b, bs, scale_buf);
        lg_gl_pass_bind_texture(b, bt, white);
        const float c[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
        lg_gl_set_float(b, bz, 0.9f);
        lg_gl_set_vec4v(b, bc, c);
        CHECKF(lg_gl_pass_end(b, lg_gl_pass_draw(b, GL_TRIANGLES, 3)) == 0, "draw add: %s",
               devtest_errors);
        check_restored(gl, "after a blending pass");
        read_rgba(gl, out_color, px, W, H);
        CHECKF(in[0] == 1.25f && in[1] == 0.25f && in[2] == 0.25f && in[3] == 2.0f,
               "added: %g %g %g %g (want 1.25 0.25 0.25 2)", in[0], in[1], in[2], in[3]);
        CHECKF(out[2] == 1.0f && out[0] == 0.0f, "outside changed by the add pass");
    }
    lg_gl_pass_destroy(&b);

    /* a target of the wrong format is named */
    GLuint half = make_tex(gl, GL_RGBA16F, W, H);
    lg_gl_target wrong = { .color = { half }, .depth = out_depth, .width = W, .height = H };
    devtest_clear();
    CHECKF(lg_gl_pass_begin(p, &wrong) == LG_ERR_DEVICE, "a GL_RGBA16F target was accepted");
    CHECKF(strstr(devtest_errors, "'triangle'") && strstr(devtest_errors, "GL_RGBA16F") &&
               strstr(devtest_errors, "GL_RGBA32F"),
           "format message: %s", devtest_errors);
    /* and a missing depth texture */
    devtest_clear();
    lg_gl_target nodepth = { .color = { out_color }, .width = W, .height = H };
    CHECKF(lg_gl_pass_begin(p, &nodepth) == LG_ERR_DEVICE && strstr(devtest_errors, "no depth"),
           "missing depth: %s", devtest_errors);
    check_restored(gl, "after failed begins");

    lg_gl_pass_destroy(&p);
    GLuint texs[5] = { out_color, out_depth, white, black, half };
    gl->DeleteTextures(5, texs);
    gl->DeleteBuffers(1, &scale_buf);
}

static void test_names(const lg_gl *gl)
{
    devtest_clear();
    const lg_gl_shader_src src[2] = { { GL_VERTEX_SHADER, "tri.vert", tri_vert },
                                      { GL_FRAGMENT_SHADER, "tri.frag", tri_frag } };
    lg_gl_pass_desc d = { .name = "names", .stages = src, .n_stages = 2, .colors = { GL_RGBA32F } };
    lg_gl_pass *p = NULL;
    CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create: %s", devtest_errors);
    if (!p)
        return;
    lg_gl_uniform u = lg_gl_pass_uniform_optional(p, "u_exposure");
    CHECKF(u.location == -1 && devtest_error_count == 0, "optional look-up reported: %s",
           devtest_errors);
    lg_gl_binding ob = lg_gl_pass_binding_optional(p, GL_SHADER_STORAGE_BLOCK, "Nope");
    CHECKF(ob.index == -1 && devtest_error_count == 0, "optional binding reported: %s",
           devtest_errors);
    u = lg_gl_pass_uniform(p, "u_exposure");
    CHECKF(u.location == -1, "absent uniform has location %d", u.location);
    CHECKF(devtest_error_count == 1 && strstr(devtest_errors, "gl pass 'names'") &&
               strstr(devtest_errors, "'u_exposure'"),
           "message: %s", devtest_errors);
    lg_gl_set_float(p, u, 1.0f); /* absent: nothing happens */
    CHECKF(gl->GetError() == GL_NO_ERROR, "setting an absent uniform raised a GL error");
    devtest_clear();
    lg_gl_binding b = lg_gl_pass_storage(p, "Lights");
    CHECKF(b.index == -1 && strstr(devtest_errors, "storage block 'Lights'"), "message: %s",
           devtest_errors);
    /* the pass is failed now: begin refuses without touching GL */
    devtest_clear();
    GLuint color = make_tex(gl, GL_RGBA32F, W, H);
    lg_gl_target t = { .color = { color }, .width = W, .height = H };
    CHECKF(lg_gl_pass_begin(p, &t) == LG_ERR_INVALID, "a failed pass began");
    CHECKF(strstr(devtest_errors, "'names'") != NULL, "message: %s", devtest_errors);
    check_restored(gl, "after a refused begin");
    lg_gl_pass_destroy(&p);
    gl->DeleteTextures(1, &color);

    /* block layouts: Scale is one float; a wrong size is named */
    devtest_clear();
    lg_gl_pass *q = NULL;
    lg_gl_pass_desc dq = {
        .name = "blocks", .stages = src, .n_stages = 2, .colors = { GL_RGBA32F }
    };
    CHECKF(lg_gl_pass_create(&node, &dq, &q) == 0, "create: %s", devtest_errors);
    if (q) {
        CHECKF(lg_gl_pass_check_block(q, GL_SHADER_STORAGE_BLOCK, "Scale", 4) == 0, "%s",
               devtest_errors);
        CHECKF(lg_gl_pass_check_block(q, GL_SHADER_STORAGE_BLOCK, "Scale", 8) == LG_ERR_INVALID &&
                   strstr(devtest_errors, "'blocks'") && strstr(devtest_errors, "'Scale'") &&
                   strstr(devtest_errors, "takes 4 bytes") &&
                   strstr(devtest_errors, "mirrors it 8"),
               "message: %s", devtest_errors);
        lg_gl_pass_destroy(&q);
    }

    /* descriptor errors */
    devtest_clear();
    lg_gl_pass_desc none = { .name = "empty", .stages = src, .n_stages = 2 };
    CHECKF(lg_gl_pass_create(&node, &none, &p) == LG_ERR_INVALID && !p &&
               strstr(devtest_errors, "'empty'"),
           "a raster pass without attachments: %s", devtest_errors);
    devtest_clear();
    lg_gl_shader_src bad = { GL_FRAGMENT_SHADER, "bad.frag", "#version 450\nnot glsl;\n" };
    lg_gl_shader_src two[2] = { src[0], bad };
    lg_gl_pass_desc bd = { .name = "bad", .stages = two, .n_stages = 2, .colors = { GL_RGBA32F } };
    CHECKF(lg_gl_pass_create(&node, &bd, &p) == LG_ERR_DEVICE && !p &&
               strstr(devtest_errors, "bad.frag"),
           "a compile error: %s", devtest_errors);
    check_restored(gl, "after failed creates");
}

/* A block ending in an unsized array of a std430 struct with a vec3 (stride 32, not 28). */
static const char stride_comp[] = "#version 450\n"
                                  "layout(local_size_x = 1) in;\n"
                                  "struct L { vec3 a; float b; vec3 c; };\n"
                                  "layout(std430, binding = 0) buffer Ls { uint n; L l[]; };\n"
                                  "void main() { l[0].b = float(n); l[0].c = l[0].a; }\n";

static void test_stride(void)
{
    devtest_clear();
    const lg_gl_shader_src src = { GL_COMPUTE_SHADER, "stride.comp", stride_comp };
    lg_gl_pass_desc d = { .name = "stride", .stages = &src, .n_stages = 1 };
    lg_gl_pass *p = NULL;
    CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create: %s", devtest_errors);
    if (!p)
        return;
    CHECKF(lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "Ls", 32) == 0, "%s", devtest_errors);
    devtest_clear();
    CHECKF(lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "Ls", 28) == LG_ERR_INVALID &&
               strstr(devtest_errors, "stride 32 bytes"),
           "message: %s", devtest_errors);
    lg_gl_pass_destroy(&p);
}

static void test_compute(const lg_gl *gl)
{
    devtest_clear();
    enum { CW = 13, CH = 7 };
    GLuint img = make_tex(gl, GL_RGBA32F, CW, CH);
    const float zero4[4] = { 0, 0, 0, 0 };
    gl->ClearTexImage(img, 0, GL_RGBA, GL_FLOAT, zero4);
    GLuint buf;
    counts c0 = { 0, 0 };
    gl->CreateBuffers(1, &buf);
    gl->NamedBufferData(buf, sizeof c0, &c0, GL_DYNAMIC_READ);

    const lg_gl_shader_src src = { GL_COMPUTE_SHADER, "count.comp", count_comp };
    lg_gl_pass_desc d = { .name = "count", .stages = &src, .n_stages = 1 };
    lg_gl_pass *p = NULL;
    CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create: %s", devtest_errors);
    if (!p)
        return;
    uint32_t l[3];
    lg_gl_pass_local_size(p, l);
    CHECKF(l[0] == 8 && l[1] == 4 && l[2] == 1, "local size %u %u %u", l[0], l[1], l[2]);
    lg_gl_uniform size = lg_gl_pass_uniform(p, "u_size");
    lg_gl_binding out = lg_gl_pass_image(p, "u_out");
    lg_gl_binding cnt = lg_gl_pass_storage(p, "Counts");
    CHECKF(devtest_error_count == 0 && out.index == 1 && cnt.index == 2, "look-ups: %s",
           devtest_errors);
    CHECKF(lg_gl_pass_check_block(p, GL_SHADER_STORAGE_BLOCK, "Counts", sizeof(counts)) == 0,
           "Counts: %s", devtest_errors);

    CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
    GLint prog = 0;
    gl->GetIntegerv(GL_CURRENT_PROGRAM, &prog);
    CHECKF((GLuint)prog == lg_gl_pass_program(p), "begin did not make the program current");
    lg_gl_pass_bind_image(p, out, img, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_pass_bind_buffer(p, cnt, buf);
    lg_gl_set_ivec2(p, size, CW, CH);
    int rc = lg_gl_pass_dispatch(p, CW, CH, 1);
    CHECKF(lg_gl_pass_end(p, rc) == 0, "dispatch/end: %s", devtest_errors);
    check_restored(gl, "after a compute pass");

    counts c;
    gl->GetNamedBufferSubData(buf, 0, sizeof c, &c);
    CHECKF(c.invocations == CW * CH, "%u invocations inside (want %d)", c.invocations, CW * CH);
    CHECKF(c.groups == 2 * 2, "%u groups (want ceil(13/8) x ceil(7/4) = 4)", c.groups);
    float px[CW * CH * 4];
    read_rgba(gl, img, px, CW, CH);
    int bad = 0;
    for (int y = 0; y < CH; y++)
        for (int x = 0; x < CW; x++) {
            const float *q = &px[(y * CW + x) * 4];
            bad += q[0] != (float)x || q[1] != (float)y || q[2] != 7.0f;
        }
    CHECKF(bad == 0, "%d pixels wrong", bad);

    /* a dispatch outside begin/end, and a zero group count, are errors */
    devtest_clear();
    CHECKF(lg_gl_pass_dispatch_groups(p, 1, 1, 1) == LG_ERR_INVALID, "dispatch outside begin");
    CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
    CHECKF(lg_gl_pass_end(p, lg_gl_pass_dispatch_groups(p, 0, 1, 1)) == LG_ERR_UNSUPPORTED,
           "0 groups accepted");
    check_restored(gl, "after a refused dispatch");

    lg_gl_pass_destroy(&p);
    CHECKF(p == NULL, "destroy did not clear the handle");
    lg_gl_pass_destroy(&p); /* NULL handle: no-op */
    lg_gl_pass_destroy(NULL);
    gl->DeleteTextures(1, &img);
    gl->DeleteBuffers(1, &buf);
}

/* Each invocation writes (x, y, z, tag) into every layer of a 3D image (layered binding). */
static const char volume_comp[] =
    "#version 450\n"
    "layout(local_size_x = 4, local_size_y = 4, local_size_z = 2) in;\n"
    "layout(binding = 0, rgba32f) uniform writeonly image3D u_vol;\n"
    "uniform ivec3 u_size;\n"
    "uniform float u_tag;\n"
    "void main()\n"
    "{\n"
    "    ivec3 p = ivec3(gl_GlobalInvocationID);\n"
    "    if (any(greaterThanEqual(p, u_size)))\n"
    "        return;\n"
    "    imageStore(u_vol, p, vec4(vec3(p), u_tag));\n"
    "}\n";

/* The same through a 2D image: one layer of a 3D texture, or one mip level of a 2D one. */
static const char slice_comp[] = "#version 450\n"
                                 "layout(local_size_x = 4, local_size_y = 4) in;\n"
                                 "layout(binding = 0, rgba32f) uniform writeonly image2D u_img;\n"
                                 "uniform ivec2 u_size;\n"
                                 "uniform float u_tag;\n"
                                 "void main()\n"
                                 "{\n"
                                 "    ivec2 p = ivec2(gl_GlobalInvocationID.xy);\n"
                                 "    if (any(greaterThanEqual(p, u_size)))\n"
                                 "        return;\n"
                                 "    imageStore(u_img, p, vec4(vec2(p), -1.0, u_tag));\n"
                                 "}\n";

/* lg_gl_pass_bind_image_level: a 3D volume bound layered (every layer written), one layer of
 * it bound alone (only that layer written), and a mip level above 0 of a 2D texture. */
static void test_image_levels(const lg_gl *gl)
{
    devtest_clear();
    enum { VW = 5, VH = 3, VD = 6, LAYER = 4 };
    GLuint vol;
    gl->CreateTextures(GL_TEXTURE_3D, 1, &vol);
    gl->TextureStorage3D(vol, 1, GL_RGBA32F, VW, VH, VD);
    const float zero4[4] = { 0, 0, 0, 0 };
    gl->ClearTexImage(vol, 0, GL_RGBA, GL_FLOAT, zero4);

    const lg_gl_shader_src vsrc = { GL_COMPUTE_SHADER, "volume.comp", volume_comp };
    lg_gl_pass_desc vd = { .name = "volume", .stages = &vsrc, .n_stages = 1 };
    const lg_gl_shader_src ssrc = { GL_COMPUTE_SHADER, "slice.comp", slice_comp };
    lg_gl_pass_desc sd = { .name = "slice", .stages = &ssrc, .n_stages = 1 };
    lg_gl_pass *pv = NULL, *ps = NULL;
    CHECKF(lg_gl_pass_create(&node, &vd, &pv) == 0 && lg_gl_pass_create(&node, &sd, &ps) == 0,
           "create: %s", devtest_errors);
    if (!pv || !ps) {
        lg_gl_pass_destroy(&pv);
        lg_gl_pass_destroy(&ps);
        gl->DeleteTextures(1, &vol);
        return;
    }
    lg_gl_binding vb = lg_gl_pass_image(pv, "u_vol"), sb = lg_gl_pass_image(ps, "u_img");
    lg_gl_uniform vsize = lg_gl_pass_uniform(pv, "u_size"), vtag = lg_gl_pass_uniform(pv, "u_tag");
    lg_gl_uniform ssize = lg_gl_pass_uniform(ps, "u_size"), stag = lg_gl_pass_uniform(ps, "u_tag");

    /* every layer at once */
    CHECKF(lg_gl_pass_begin(pv, NULL) == 0, "begin: %s", devtest_errors);
    lg_gl_pass_bind_image_level(pv, vb, vol, 0, LG_GL_ALL_LAYERS, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_set_ivec3(pv, vsize, VW, VH, VD);
    lg_gl_set_float(pv, vtag, 1.0f);
    int rc = lg_gl_pass_dispatch(pv, VW, VH, VD);
    CHECKF(lg_gl_pass_end(pv, rc) == 0, "layered dispatch: %s", devtest_errors);
    check_restored(gl, "after a layered image pass");

    /* then layer LAYER alone, as a 2D image */
    CHECKF(lg_gl_pass_begin(ps, NULL) == 0, "begin: %s", devtest_errors);
    lg_gl_pass_bind_image_level(ps, sb, vol, 0, LAYER, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_set_ivec2(ps, ssize, VW, VH);
    lg_gl_set_float(ps, stag, 2.0f);
    rc = lg_gl_pass_dispatch(ps, VW, VH, 1);
    CHECKF(lg_gl_pass_end(ps, rc) == 0, "layer dispatch: %s", devtest_errors);
    check_restored(gl, "after a one-layer image pass");

    static float vpx[VW * VH * VD * 4];
    gl->GetTextureImage(vol, 0, GL_RGBA, GL_FLOAT, (GLsizei)sizeof vpx, vpx);
    int bad = 0;
    for (int z = 0; z < VD; z++)
        for (int y = 0; y < VH; y++)
            for (int x = 0; x < VW; x++) {
                const float *q = &vpx[((z * VH + y) * VW + x) * 4];
                bool ok = z == LAYER ? q[0] == x && q[1] == y && q[2] == -1 && q[3] == 2
                                     : q[0] == x && q[1] == y && q[2] == z && q[3] == 1;
                bad += !ok;
            }
    CHECKF(bad == 0,
           "%d of %d texels of the volume wrong (layered: every layer; then layer %d "
           "alone)",
           bad, VW * VH * VD, LAYER);

    /* mip level 1 of a 2D texture: level 0 untouched */
    enum { MW = 9, MH = 6 };
    GLuint mip;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &mip);
    gl->TextureStorage2D(mip, 2, GL_RGBA32F, MW, MH);
    gl->ClearTexImage(mip, 0, GL_RGBA, GL_FLOAT, zero4);
    gl->ClearTexImage(mip, 1, GL_RGBA, GL_FLOAT, zero4);
    CHECKF(lg_gl_pass_begin(ps, NULL) == 0, "begin: %s", devtest_errors);
    lg_gl_pass_bind_image_level(ps, sb, mip, 1, 0, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_set_ivec2(ps, ssize, MW / 2, MH / 2);
    lg_gl_set_float(ps, stag, 3.0f);
    rc = lg_gl_pass_dispatch(ps, MW / 2, MH / 2, 1);
    CHECKF(lg_gl_pass_end(ps, rc) == 0, "level dispatch: %s", devtest_errors);
    float l0[MW * MH * 4], l1[(MW / 2) * (MH / 2) * 4];
    gl->GetTextureImage(mip, 0, GL_RGBA, GL_FLOAT, (GLsizei)sizeof l0, l0);
    gl->GetTextureImage(mip, 1, GL_RGBA, GL_FLOAT, (GLsizei)sizeof l1, l1);
    int bad0 = 0, bad1 = 0;
    for (int i = 0; i < MW * MH * 4; i++)
        bad0 += l0[i] != 0.0f;
    for (int y = 0; y < MH / 2; y++)
        for (int x = 0; x < MW / 2; x++) {
            const float *q = &l1[(y * (MW / 2) + x) * 4];
            bad1 += !(q[0] == x && q[1] == y && q[2] == -1 && q[3] == 3);
        }
    CHECKF(bad0 == 0 && bad1 == 0,
           "mip level 1: %d values of level 0 changed, %d texels of "
           "level 1 wrong",
           bad0, bad1);

    lg_gl_pass_destroy(&pv);
    lg_gl_pass_destroy(&ps);
    gl->DeleteTextures(1, &vol);
    gl->DeleteTextures(1, &mip);
}

/* The scene's instances through lightgraph/scene_gl.h's records (mat4 model, binding 0). */
static const char scene_vert[] =
    "#version 450 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "layout(std430, binding = 0) readonly buffer Instances { mat4 model[]; };\n"
    "uniform int u_first;\n"
    "void main()\n"
    "{\n"
    "    gl_Position = model[u_first + gl_InstanceID] * vec4(a_position, 1.0);\n"
    "}\n";

static const char scene_frag[] = "#version 450 core\n"
                                 "layout(location = 0) out vec4 o_color;\n"
                                 "void main() { o_color = vec4(1.0, 0.5, 0.25, 1.0); }\n";

/* One triangle, drawn; moved (its instance's matrix changes: the draw data is made again);
 * drawn again unchanged (kept: the scene's checks do not run again). */
static void test_scene(const lg_gl *gl)
{
    devtest_clear();
    static const float pos[9] = { -1, -1, 0, 1, -1, 0, -1, 1, 0 };
    static const float nrm[9] = { 0, 0, 1, 0, 0, 1, 0, 0, 1 };
    static uint32_t idx[3] = { 0, 1, 2 };
    static lg_mesh mesh;
    static lg_instance inst;
    static lg_material mat;
    mesh = (lg_mesh){ .name = "tri",
                      .n_vertices = 3,
                      .n_indices = 3,
                      .positions = pos,
                      .normals = nrm,
                      .indices = idx };
    memset(&inst, 0, sizeof inst);
    for (int i = 0; i < 4; i++)
        inst.model[i * 5] = 1.0f;
    mat.double_sided = true;
    the_scene = (lg_scene){ .struct_size = sizeof(lg_scene),
                            .meshes = &mesh,
                            .n_meshes = 1,
                            .instances = &inst,
                            .n_instances = 1,
                            .materials = &mat,
                            .n_materials = 1 };
    GLuint color = make_tex(gl, GL_RGBA32F, W, H);
    lg_gl_target t = { .color = { color }, .width = W, .height = H };
    const lg_gl_shader_src src[2] = { { GL_VERTEX_SHADER, "scene.vert", scene_vert },
                                      { GL_FRAGMENT_SHADER, "scene.frag", scene_frag } };
    lg_gl_pass_desc d = { .name = "scene",
                          .stages = src,
                          .n_stages = 2,
                          .colors = { GL_RGBA32F },
                          .scene = LG_GL_SCENE_POSITIONS };
    lg_gl_pass *p = NULL;
    CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create: %s", devtest_errors);
    if (!p)
        return;
    const lg_resource *res = (const lg_resource *)&scene_resource;
    float px[W * H * 4];
    for (int frame = 0; frame < 3; frame++) {
        if (frame == 1) /* moved by (1, 1) in clip space: into the upper-right quadrant */
            inst.model[12] = inst.model[13] = 1.0f;
        if (frame == 2) /* unchanged records, so the draw data is kept and not checked */
            idx[2] = 99;
        const float bg[4] = { 0, 0, 0, 0 };
        CHECKF(lg_gl_pass_begin(p, &t) == 0, "begin: %s", devtest_errors);
        lg_gl_pass_clear_color(p, 0, bg);
        int rc = lg_gl_pass_end(p, lg_gl_pass_draw_scene(p, res, NULL));
        CHECKF(rc == 0, "frame %d: %s", frame, devtest_errors);
        check_restored(gl, "after a scene pass");
        read_rgba(gl, color, px, W, H);
        bool at_origin = px[(1 * W + 1) * 4] == 1.0f, moved = px[(4 * W + 4) * 4] == 1.0f;
        CHECKF(frame == 0 ? at_origin && !moved : !at_origin && moved,
               "frame %d: triangle at the origin %d, moved %d", frame, at_origin, moved);
        const lg_scene_gl *sgl = lg_gl_pass_scene(p);
        CHECKF(sgl && sgl->count == 1 && sgl->triangles == 1, "draw data");
    }
    idx[2] = 2;
    /* a scene the checks refuse: an index out of range, in a new record */
    devtest_clear();
    mesh.n_vertices = 2;
    CHECKF(lg_gl_pass_begin(p, &t) == 0, "begin: %s", devtest_errors);
    CHECKF(lg_gl_pass_end(p, lg_gl_pass_draw_scene(p, res, NULL)) == LG_ERR_INVALID &&
               strstr(devtest_errors, "out of range"),
           "a bad index was drawn: %s", devtest_errors);
    check_restored(gl, "after a refused scene");
    lg_gl_pass_destroy(&p);
    gl->DeleteTextures(1, &color);
    for (int i = 0; i < 16; i++)
        if (slot_buf[i])
            gl->DeleteBuffers(1, &slot_buf[i]);
}

/* ---- ABI 3.0: depth function, sampler state, more uniforms, uniform blocks ------------------- */

/* depth_func: a depth plane cleared to 0 hides everything from GL_LESS; GL_ALWAYS draws
 * behind it and writes the fragment's depth. */
static void test_depth_func(const lg_gl *gl)
{
    devtest_clear();
    out_color = make_tex(gl, GL_RGBA32F, W, H);
    out_depth = make_tex(gl, GL_DEPTH_COMPONENT32F, W, H);
    GLuint black = make_tex(gl, GL_RGBA32F, 1, 1), scale_buf;
    const float zero[4] = { 0, 0, 0, 0 }, one = 1.0f;
    gl->ClearTexImage(black, 0, GL_RGBA, GL_FLOAT, zero);
    gl->CreateBuffers(1, &scale_buf);
    gl->NamedBufferStorage(scale_buf, sizeof one, &one, 0);
    const lg_gl_shader_src src[2] = { { GL_VERTEX_SHADER, "tri.vert", tri_vert },
                                      { GL_FRAGMENT_SHADER, "tri.frag", tri_frag } };
    float px[W * H * 4], dp[W * H];
    for (int always = 0; always < 2; always++) {
        lg_gl_pass_desc d = { .name = always ? "always" : "less",
                              .stages = src,
                              .n_stages = 2,
                              .output = "out",
                              .colors = { GL_RGBA32F },
                              .depth = true,
                              .depth_test = true,
                              .depth_write = true,
                              .depth_func = always ? GL_ALWAYS : 0 };
        lg_gl_pass *p = NULL;
        CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create %s: %s", d.name, devtest_errors);
        if (!p)
            continue;
        lg_gl_uniform u_z = lg_gl_pass_uniform(p, "u_z"), u_c = lg_gl_pass_uniform(p, "u_color");
        lg_gl_binding t = lg_gl_pass_texture(p, "u_tex"), sc = lg_gl_pass_storage(p, "Scale");
        CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin %s: %s", d.name, devtest_errors);
        GLint func = 0;
        gl->GetIntegerv(GL_DEPTH_FUNC, &func);
        CHECKF(func == (always ? GL_ALWAYS : GL_LESS), "%s: begin set glDepthFunc 0x%04x", d.name,
               (unsigned)func);
        lg_gl_pass_clear_color(p, 0, zero);
        lg_gl_pass_clear_depth(p, 0.0f);
        lg_gl_pass_bind_texture(p, t, black);
        lg_gl_pass_bind_buffer(p, sc, scale_buf);
        const float red[4] = { 1, 0, 0, 1 };
        lg_gl_set_float(p, u_z, 0.5f); /* window depth 0.75, behind the plane */
        lg_gl_set_vec4v(p, u_c, red);
        CHECKF(lg_gl_pass_end(p, lg_gl_pass_draw(p, GL_TRIANGLES, 3)) == 0, "draw %s: %s", d.name,
               devtest_errors);
        check_restored(gl, always ? "after a GL_ALWAYS pass" : "after a GL_LESS pass");
        read_rgba(gl, out_color, px, W, H);
        gl->GetTextureImage(out_depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, (GLsizei)sizeof dp, dp);
        const float *in = &px[(1 * W + 1) * 4];
        float din = dp[1 * W + 1];
        if (always)
            CHECKF(in[0] == 1.0f && din == 0.75f,
                   "GL_ALWAYS: pixel %g, depth %g (want 1, 0.75: "
                   "drawn behind the plane)",
                   in[0], din);
        else
            CHECKF(in[0] == 0.0f && din == 0.0f,
                   "GL_LESS: pixel %g, depth %g (want 0, 0: "
                   "hidden)",
                   in[0], din);
        lg_gl_pass_destroy(&p);
    }
    devtest_clear();
    lg_gl_pass *bad = NULL;
    lg_gl_pass_desc bd = { .name = "badfunc",
                           .stages = src,
                           .n_stages = 2,
                           .colors = { GL_RGBA32F },
                           .depth_func = GL_RGBA32F };
    CHECKF(lg_gl_pass_create(&node, &bd, &bad) == LG_ERR_INVALID && !bad &&
               strstr(devtest_errors, "'badfunc'") && strstr(devtest_errors, "depth_func"),
           "a bad depth_func: %s", devtest_errors);
    GLuint texs[3] = { out_color, out_depth, black };
    gl->DeleteTextures(3, texs);
    gl->DeleteBuffers(1, &scale_buf);
}

/* Samples u_tex at (u_u[i], 0.5), level u_lod, into o[i] (also lg_gl_set_floatv). */
static const char sample2d_comp[] =
    "#version 450\n"
    "layout(local_size_x = 8) in;\n"
    "layout(binding = 0) uniform sampler2D u_tex;\n"
    "uniform float u_u[8];\n"
    "uniform float u_lod;\n"
    "layout(std430, binding = 1) writeonly buffer Out { vec4 o[8]; };\n"
    "void main()\n"
    "{\n"
    "    uint i = gl_GlobalInvocationID.x;\n"
    "    o[i] = textureLod(u_tex, vec2(u_u[i], 0.5), u_lod);\n"
    "}\n";

static const char samplecube_comp[] =
    "#version 450\n"
    "layout(local_size_x = 1) in;\n"
    "layout(binding = 3) uniform samplerCube u_cube;\n"
    "uniform vec3 u_dir;\n"
    "layout(std430, binding = 1) writeonly buffer Out { vec4 o[8]; };\n"
    "void main() { o[0] = textureLod(u_cube, u_dir, 0.0); }\n";

static const char shadow_comp[] =
    "#version 450\n"
    "layout(local_size_x = 2) in;\n"
    "layout(binding = 2) uniform sampler2DShadow u_shadow;\n"
    "uniform float u_ref[2];\n"
    "layout(std430, binding = 1) writeonly buffer Out { vec4 o[8]; };\n"
    "void main()\n"
    "{\n"
    "    uint i = gl_GlobalInvocationID.x;\n"
    "    o[i] = vec4(textureLod(u_shadow, vec3(0.5, 0.5, u_ref[i]), 0.0));\n"
    "}\n";

/* Runs `p` (one of the shaders above) once and reads o[0..n) (their red channels) back. */
static int run_sample(const lg_gl *gl, lg_gl_pass *p, GLuint out, uint32_t n, float *r)
{
    lg_gl_binding ob = lg_gl_pass_storage(p, "Out");
    lg_gl_pass_bind_buffer(p, ob, out);
    int rc = lg_gl_pass_end(p, lg_gl_pass_dispatch(p, n, 1, 1));
    float o[8 * 4];
    gl->GetNamedBufferSubData(out, 0, sizeof o, o);
    for (uint32_t i = 0; i < n; i++)
        r[i] = o[i * 4];
    return rc;
}

static void test_samplers(const lg_gl *gl)
{
    devtest_clear();
    GLuint out;
    gl->CreateBuffers(1, &out);
    gl->NamedBufferStorage(out, 8 * 4 * sizeof(float), NULL, GL_DYNAMIC_STORAGE_BIT);
    /* a 4x1 texture of red 0, 1, 2, 3 at level 0 and 10, 30 at level 1; its own
     * parameters say nearest */
    GLuint tex;
    gl->CreateTextures(GL_TEXTURE_2D, 1, &tex);
    gl->TextureStorage2D(tex, 2, GL_RGBA32F, 4, 1);
    const float l0[16] = { 0, 0, 0, 1, 1, 0, 0, 1, 2, 0, 0, 1, 3, 0, 0, 1 };
    const float l1[8] = { 10, 0, 0, 1, 30, 0, 0, 1 };
    gl->TextureSubImage2D(tex, 0, 0, 0, 4, 1, GL_RGBA, GL_FLOAT, l0);
    gl->TextureSubImage2D(tex, 1, 0, 0, 2, 1, GL_RGBA, GL_FLOAT, l1);
    gl->TextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl->TextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

    const lg_gl_shader_src src = { GL_COMPUTE_SHADER, "sample2d.comp", sample2d_comp };
    lg_gl_pass_desc d = { .name = "sample", .stages = &src, .n_stages = 1 };
    lg_gl_pass *p = NULL;
    CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create: %s", devtest_errors);
    if (!p)
        return;
    lg_gl_binding t = lg_gl_pass_texture(p, "u_tex");
    lg_gl_uniform uu = lg_gl_pass_uniform(p, "u_u"), lod = lg_gl_pass_uniform(p, "u_lod");
    CHECKF(devtest_error_count == 0, "look-ups: %s", devtest_errors);

    /* filters at u = 0.4 (between texels 1 and 2; x = 1.6 - 0.5 = 1.1 texels), level 0 */
    const float at[8] = { 0.4f, 1.4f };
    struct {
        const char *what;
        const lg_gl_sampler *s;
        float want;
    } f[] = {
        { "texture's own (nearest)", NULL, 1.0f },
        { "LINEAR", &(lg_gl_sampler){ .filter = LG_GL_FILTER_LINEAR }, 1.1f },
        { "NEAREST", &(lg_gl_sampler){ .filter = LG_GL_FILTER_NEAREST }, 1.0f },
        { "NULL again after a sampler", NULL, 1.0f },
    };
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) {
        float r[1];
        CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
        lg_gl_pass_bind_texture_sampled(p, t, tex, f[i].s);
        if (i == 3) /* a LINEAR sampler first, then the texture's own state on the same unit */
            lg_gl_pass_bind_texture_sampled(p, t, tex, f[1].s),
                lg_gl_pass_bind_texture_sampled(p, t, tex, NULL);
        lg_gl_set_floatv(p, uu, 2, at);
        lg_gl_set_float(p, lod, 0.0f);
        CHECKF(run_sample(gl, p, out, 1, r) == 0, "%s: %s", f[i].what, devtest_errors);
        CHECKF(fabsf(r[0] - f[i].want) < 1e-3f, "%s at u 0.4: %g (want %g)", f[i].what, r[0],
               f[i].want);
        check_restored(gl, f[i].what);
    }
    /* trilinear: level 0.5 blends levels 0 and 1 (level 1 at u 0.4: x = 0.3 texels, 16);
     * LINEAR reads level 0 alone */
    for (int tri = 0; tri < 2; tri++) {
        lg_gl_sampler s = { .filter = tri ? LG_GL_FILTER_LINEAR_MIPMAP : LG_GL_FILTER_LINEAR };
        float r[1];
        CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
        lg_gl_pass_bind_texture_sampled(p, t, tex, &s);
        lg_gl_set_floatv(p, uu, 1, at);
        lg_gl_set_float(p, lod, 0.5f);
        CHECKF(run_sample(gl, p, out, 1, r) == 0, "mip: %s", devtest_errors);
        float want = tri ? 0.5f * 1.1f + 0.5f * 16.0f : 1.1f;
        CHECKF(fabsf(r[0] - want) < 2e-2f, "%s at level 0.5: %g (want %g)",
               tri ? "LINEAR_MIPMAP" : "LINEAR", r[0], want);
    }
    /* wraps at u = 1.4, nearest: clamp gives texel 3, repeat 0.4 -> texel 1, mirror 0.6 ->
     * texel 2, the zero border 0 */
    const float want_wrap[4] = { 3, 1, 2, 0 };
    for (int w = 0; w < 4; w++) {
        lg_gl_sampler s = { .filter = LG_GL_FILTER_NEAREST, .wrap = (lg_gl_wrap)w };
        float r[2];
        CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
        lg_gl_pass_bind_texture_sampled(p, t, tex, &s);
        lg_gl_set_floatv(p, uu, 2, at);
        lg_gl_set_float(p, lod, 0.0f);
        CHECKF(run_sample(gl, p, out, 2, r) == 0, "wrap %d: %s", w, devtest_errors);
        CHECKF(r[1] == want_wrap[w] && r[0] == 1.0f, "wrap %d at u 1.4: %g (want %g)", w, r[1],
               want_wrap[w]);
    }
    check_restored(gl, "after sampled bindings");
    /* an unknown wrap is an error at end, and nothing is bound */
    devtest_clear();
    CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
    lg_gl_sampler bad = { .wrap = (lg_gl_wrap)9 };
    lg_gl_pass_bind_texture_sampled(p, t, tex, &bad);
    CHECKF(lg_gl_pass_end(p, 0) == LG_ERR_INVALID && strstr(devtest_errors, "'sample'") &&
               strstr(devtest_errors, "wrap 9"),
           "a bad sampler: %s", devtest_errors);
    check_restored(gl, "after a bad sampler");
    lg_gl_pass_destroy(&p);

    /* depth comparison: a depth texel of 0.5 passes a reference of 0.4 and fails 0.6 */
    devtest_clear();
    GLuint depth = make_tex(gl, GL_DEPTH_COMPONENT32F, 1, 1);
    const float half = 0.5f;
    gl->ClearTexImage(depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, &half);
    const lg_gl_shader_src ssrc = { GL_COMPUTE_SHADER, "shadow.comp", shadow_comp };
    lg_gl_pass_desc sd = { .name = "shadow", .stages = &ssrc, .n_stages = 1 };
    CHECKF(lg_gl_pass_create(&node, &sd, &p) == 0, "create shadow: %s", devtest_errors);
    if (p) {
        lg_gl_binding sb = lg_gl_pass_texture(p, "u_shadow");
        lg_gl_uniform ref = lg_gl_pass_uniform(p, "u_ref");
        const float refs[2] = { 0.4f, 0.6f };
        lg_gl_sampler s = { .filter = LG_GL_FILTER_NEAREST, .compare_less_equal = true };
        float r[2];
        CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
        lg_gl_pass_bind_texture_sampled(p, sb, depth, &s);
        lg_gl_set_floatv(p, ref, 2, refs);
        CHECKF(run_sample(gl, p, out, 2, r) == 0, "shadow: %s", devtest_errors);
        CHECKF(r[0] == 1.0f && r[1] == 0.0f, "compare: ref 0.4 -> %g, 0.6 -> %g (want 1, 0)", r[0],
               r[1]);
        check_restored(gl, "after a shadow sampler");
        lg_gl_pass_destroy(&p);
    }

    /* seamless cube maps: 2x2 faces, +X red 1, the others 0; a direction next to the edge
     * of +X and +Z: clamped to +X alone (1) or filtered across the edge (about 1/2) */
    devtest_clear();
    GLuint cube;
    gl->CreateTextures(GL_TEXTURE_CUBE_MAP, 1, &cube);
    gl->TextureStorage2D(cube, 1, GL_RGBA32F, 2, 2);
    for (int face = 0; face < 6; face++) {
        float v[16];
        for (int k = 0; k < 4; k++) {
            v[k * 4] = face == 0 ? 1.0f : 0.0f;
            v[k * 4 + 1] = v[k * 4 + 2] = 0.0f;
            v[k * 4 + 3] = 1.0f;
        }
        gl->TextureSubImage3D(cube, 0, 0, 0, face, 2, 2, 1, GL_RGBA, GL_FLOAT, v);
    }
    const lg_gl_shader_src csrc = { GL_COMPUTE_SHADER, "cube.comp", samplecube_comp };
    lg_gl_pass_desc cd = { .name = "cube", .stages = &csrc, .n_stages = 1 };
    CHECKF(lg_gl_pass_create(&node, &cd, &p) == 0, "create cube: %s", devtest_errors);
    if (p) {
        lg_gl_binding cb = lg_gl_pass_texture(p, "u_cube");
        lg_gl_uniform dir = lg_gl_pass_uniform(p, "u_dir");
        for (int seamless = 0; seamless < 2; seamless++) {
            lg_gl_sampler s = { .seamless_cube = seamless };
            float r[1];
            CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
            CHECKF(!gl->IsEnabled(GL_TEXTURE_CUBE_MAP_SEAMLESS), "begin left seamless on");
            lg_gl_pass_bind_texture_sampled(p, cb, cube, &s);
            CHECKF(gl->IsEnabled(GL_TEXTURE_CUBE_MAP_SEAMLESS) == (GLboolean)seamless,
                   "seamless %d: the switch is %d", seamless,
                   gl->IsEnabled(GL_TEXTURE_CUBE_MAP_SEAMLESS));
            lg_gl_set_vec3(p, dir, 1.0f, 0.0f, 0.999f);
            CHECKF(run_sample(gl, p, out, 1, r) == 0, "cube: %s", devtest_errors);
            if (seamless)
                CHECKF(r[0] > 0.4f && r[0] < 0.6f, "seamless at the edge: %g (want about 0.5)",
                       r[0]);
            else
                CHECKF(r[0] == 1.0f, "not seamless at the edge: %g (want +X's 1)", r[0]);
            check_restored(gl, seamless ? "after a seamless cube" : "after a clamped cube");
        }
        lg_gl_pass_destroy(&p);
    }
    gl->DeleteTextures(1, &tex);
    gl->DeleteTextures(1, &depth);
    gl->DeleteTextures(1, &cube);
    gl->DeleteBuffers(1, &out);
}

/* mat3, int/vec3/vec4 arrays and a std140 block, written out for the C side to compare. */
static const char uniforms_comp[] =
    "#version 450\n"
    "layout(local_size_x = 1) in;\n"
    "uniform mat3 u_m;\n"
    "uniform int u_i[3];\n"
    "uniform vec3 u_v3[2];\n"
    "uniform vec4 u_v4[2];\n"
    "layout(std140, binding = 4) uniform Params {\n"
    "    mat4 view_proj;\n"
    "    vec3 dir;\n"
    "    float exposure;\n"
    "    ivec2 size;\n"
    "    float weights[3];\n"
    "} u_p;\n"
    "layout(std430, binding = 1) writeonly buffer Out { vec4 o[16]; };\n"
    "void main()\n"
    "{\n"
    "    o[0] = vec4(u_m * vec3(1.0, 10.0, 100.0), 0.0);\n"
    "    o[1] = vec4(u_i[0], u_i[1], u_i[2], 0.0);\n"
    "    o[2] = vec4(u_v3[0], 0.0);\n"
    "    o[3] = vec4(u_v3[1], 0.0);\n"
    "    o[4] = u_v4[0];\n"
    "    o[5] = u_v4[1];\n"
    "    o[6] = u_p.view_proj * vec4(1.0, 2.0, 3.0, 1.0);\n"
    "    o[7] = vec4(u_p.dir, u_p.exposure);\n"
    "    o[8] = vec4(u_p.size, 0.0, 0.0);\n"
    "    o[9] = vec4(u_p.weights[0], u_p.weights[1], u_p.weights[2], 0.0);\n"
    "}\n";

/* The C mirror of Params: std140 strides a float array by 16 bytes. */
typedef struct params {
    float view_proj[16];
    float dir[3];
    float exposure;
    int32_t size[2];
    float pad_[2];
    float weights[3][4];
} params;
LG_GL_BLOCK_SIZE(params, 144);
LG_GL_BLOCK_OFFSET(params, exposure, 76);
LG_GL_BLOCK_OFFSET(params, size, 80);
LG_GL_BLOCK_OFFSET(params, weights, 96);

static void test_uniforms(const lg_gl *gl)
{
    devtest_clear();
    accounted = 0;
    GLuint out;
    gl->CreateBuffers(1, &out);
    gl->NamedBufferStorage(out, 16 * 4 * sizeof(float), NULL, GL_DYNAMIC_STORAGE_BIT);
    const lg_gl_shader_src src = { GL_COMPUTE_SHADER, "uniforms.comp", uniforms_comp };
    lg_gl_pass_desc d = { .name = "uniforms", .stages = &src, .n_stages = 1 };
    lg_gl_pass *p = NULL;
    CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create: %s", devtest_errors);
    if (!p)
        return;
    lg_gl_uniform um = lg_gl_pass_uniform(p, "u_m"), ui = lg_gl_pass_uniform(p, "u_i");
    lg_gl_uniform uv3 = lg_gl_pass_uniform(p, "u_v3"), uv4 = lg_gl_pass_uniform(p, "u_v4[0]");
    lg_gl_binding blk = lg_gl_pass_uniform_block(p, "Params");
    lg_gl_binding ob = lg_gl_pass_storage(p, "Out");
    CHECKF(devtest_error_count == 0 && blk.index == 4, "look-ups (block at %d): %s", blk.index,
           devtest_errors);

    /* columns (1,2,3), (4,5,6), (7,8,9): m * (1, 10, 100) = (741, 852, 963) */
    const float m[9] = { 1, 2, 3, 4, 5, 6, 7, 8, 9 };
    const int32_t iv[3] = { -7, 0, 2147483647 };
    const float v3[6] = { 1.5f, 2.5f, 3.5f, -1, -2, -3 };
    const float v4[8] = { 0.25f, 0.5f, 0.75f, 1, 5, 6, 7, 8 };
    params u = { .dir = { 0.1f, 0.2f, 0.3f },
                 .exposure = 2.5f,
                 .size = { 640, -360 },
                 .weights = { { 0.125f }, { 0.25f }, { 0.375f } } };
    for (int i = 0; i < 4; i++)
        u.view_proj[i * 5] = (float)(i + 2); /* diag(2, 3, 4, 5) */
    u.view_proj[12] = 100.0f;                /* + 100 in x */
    for (int frame = 0; frame < 2; frame++) {
        if (frame == 1) /* a new value in the same buffer */
            u.exposure = -4.0f;
        CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
        lg_gl_set_mat3(p, um, m);
        lg_gl_set_intv(p, ui, 3, iv);
        lg_gl_set_vec3_array(p, uv3, 2, v3);
        lg_gl_set_vec4_array(p, uv4, 2, v4);
        int rc = lg_gl_pass_uniforms(p, blk, &u, sizeof u);
        CHECKF(rc == 0, "uniforms: %s", devtest_errors);
        GLint bound = 0;
        gl->GetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, 4, &bound);
        CHECKF(bound != 0, "the block's buffer is not bound between begin and end");
        lg_gl_pass_bind_buffer(p, ob, out);
        CHECKF(lg_gl_pass_end(p, lg_gl_pass_dispatch(p, 1, 1, 1)) == 0, "dispatch: %s",
               devtest_errors);
        check_restored(gl, "after a uniform-block pass");
        float o[16 * 4];
        gl->GetNamedBufferSubData(out, 0, sizeof o, o);
        CHECKF(o[0] == 741 && o[1] == 852 && o[2] == 963, "mat3: %g %g %g (want 741 852 963)", o[0],
               o[1], o[2]);
        CHECKF(o[4] == -7 && o[5] == 0 && o[6] == 2147483647.0f, "int array: %g %g %g", o[4], o[5],
               o[6]);
        CHECKF(o[8] == 1.5f && o[10] == 3.5f && o[12] == -1 && o[14] == -3,
               "vec3 array: %g %g / %g %g", o[8], o[10], o[12], o[14]);
        CHECKF(o[16] == 0.25f && o[19] == 1 && o[20] == 5 && o[23] == 8,
               "vec4 array: %g %g / %g %g", o[16], o[19], o[20], o[23]);
        CHECKF(o[24] == 102 && o[25] == 6 && o[26] == 12 && o[27] == 5,
               "block mat4: %g %g %g %g (want 102 6 12 5)", o[24], o[25], o[26], o[27]);
        CHECKF(o[28] == 0.1f && o[30] == 0.3f && o[31] == u.exposure,
               "block vec3 + float: %g %g %g (want 0.1 0.3 %g)", o[28], o[30], o[31], u.exposure);
        CHECKF(o[32] == 640 && o[33] == -360, "block ivec2: %g %g", o[32], o[33]);
        CHECKF(o[36] == 0.125f && o[37] == 0.25f && o[38] == 0.375f, "block float[3]: %g %g %g",
               o[36], o[37], o[38]);
    }
    CHECKF(accounted == (int64_t)sizeof u, "the block's buffer counts %lld bytes (want %zu)",
           (long long)accounted, sizeof u);

    /* outside begin/end; a struct of the wrong size (named, and the pass fails) */
    devtest_clear();
    CHECKF(lg_gl_pass_uniforms(p, blk, &u, sizeof u) == LG_ERR_INVALID &&
               strstr(devtest_errors, "outside begin/end"),
           "outside: %s", devtest_errors);
    devtest_clear();
    CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
    int rc = lg_gl_pass_uniforms(p, blk, &u, sizeof u - 16);
    CHECKF(rc == LG_ERR_INVALID && strstr(devtest_errors, "'uniforms'") &&
               strstr(devtest_errors, "'Params'") && strstr(devtest_errors, "mirrors it 128"),
           "a short struct: %s", devtest_errors);
    lg_gl_pass_end(p, rc);
    check_restored(gl, "after a refused block");
    devtest_clear();
    CHECKF(lg_gl_pass_begin(p, NULL) == LG_ERR_INVALID, "the pass began after a bad block");
    lg_gl_pass_destroy(&p);
    CHECKF(accounted == 0, "%lld bytes still counted after destroy", (long long)accounted);

    /* an absent optional block does nothing; a storage binding is refused */
    devtest_clear();
    CHECKF(lg_gl_pass_create(&node, &d, &p) == 0, "create: %s", devtest_errors);
    if (p) {
        lg_gl_binding none = lg_gl_pass_binding_optional(p, GL_UNIFORM_BLOCK, "Nope");
        CHECKF(lg_gl_pass_begin(p, NULL) == 0, "begin: %s", devtest_errors);
        CHECKF(lg_gl_pass_uniforms(p, none, &u, sizeof u) == 0 && devtest_error_count == 0,
               "absent block: %s", devtest_errors);
        CHECKF(lg_gl_pass_uniforms(p, lg_gl_pass_storage(p, "Out"), &u, sizeof u) ==
                       LG_ERR_INVALID &&
                   strstr(devtest_errors, "storage block"),
               "a storage block taken for uniforms: %s", devtest_errors);
        lg_gl_pass_end(p, 0);
        check_restored(gl, "after an absent block");
        lg_gl_pass_destroy(&p);
    }
    gl->DeleteBuffers(1, &out);
}

int main(int argc, char **argv)
{
    lg_gl_device *dev;
    if (devtest_gl_open(argc, argv, &dev))
        return check_skip("gl_pass");
    lg_gl_state_reset(devtest_gl);
    test_raster(devtest_gl);
    test_names(devtest_gl);
    test_compute(devtest_gl);
    test_image_levels(devtest_gl);
    test_stride();
    test_scene(devtest_gl);
    test_depth_func(devtest_gl);
    test_samplers(devtest_gl);
    test_uniforms(devtest_gl);
    lg_gl_device_destroy(&dev);
    return check_report("gl_pass");
}
