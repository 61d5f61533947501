/* Test plugin "testmem": a GL node that runs every frame and holds scratch GL memory through
 * the SDK (lg_gl_buffer, lg_gl_texture), so that the tests can show what --profile makes of
 * a plugin's memory (host_plugin_memory in tests/unit/host/test_host.py):
 *
 *   mode = keep     a size x size rgba32f-sized buffer asked for every frame: made once
 *   mode = remake   the same buffer made at the start of every execute and destroyed at its
 *                   end (a scratch buffer per execute, as an author's blur did)
 *   mode = resize   a texture of size x size on even frames, 2 size x size on odd ones:
 *                   remade every frame, the old one released first
 *
 * Its output is a render-size image it clears to `value` on GL. */
#include <stdlib.h>

#include "lightgraph/gl.h"
#include "lightgraph/lightgraph.h"

enum { MEM_KEEP, MEM_REMAKE, MEM_RESIZE };
static const char *const modes[] = { "keep", "remake", "resize", NULL };

static const lg_param_desc params[] = {
    { .key = "mode",
      .type = LG_PARAM_ENUM,
      .def.e = MEM_KEEP,
      .enum_values = modes,
      .doc = "how the scratch memory is asked for (keep, remake, resize)" },
    { .key = "size",
      .type = LG_PARAM_INT,
      .def.i = 16,
      .min = 1,
      .max = 4096,
      .doc = "texels per side of the scratch memory (16 bytes a texel)" },
};
static const lg_port_desc out[] = { { .name = "out", .kind = LG_KIND_IMAGE } };

typedef struct mem_state {
    lg_gl_buffer buf;
    lg_gl_texture tex;
} mem_state;

static int mem_create(lg_node *n)
{
    n->user = calloc(1, sizeof(mem_state));
    return n->user ? 0 : lg_error_code(n, LG_ERR_NOMEM, "out of memory");
}

static int mem_prepare(lg_node *n)
{
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    lg_render_size(n, &d.width, &d.height);
    int rc = lg_declare_image(n, 0, &d);
    if (rc)
        return rc;
    lg_set_per_frame(n, true);
    return lg_set_device(n, LG_DEVICE_GL);
}

static int mem_execute(lg_node *n, const lg_frame *frame)
{
    mem_state *st = n->user;
    uint32_t size = (uint32_t)lg_param_int(n, "size");
    int mode = lg_param_enum(n, "mode"), rc = 0;
    if (mode == MEM_RESIZE) {
        lg_gl_texture_desc d = { .target = GL_TEXTURE_2D,
                                 .format = GL_RGBA32F,
                                 .width = size * (1 + frame->index % 2),
                                 .height = size };
        rc = lg_gl_texture_recreate(n, &st->tex, &d);
        if (rc < 0)
            return rc;
    } else if ((rc = lg_gl_buffer_recreate(n, &st->buf, (size_t)size * size * 16, 0, NULL))) {
        return rc;
    }
    uint32_t color = 0, depth = 0;
    if ((rc = lg_map_gl(n, lg_output(n, 0), LG_WRITE, &color, &depth)))
        return rc;
    const lg_gl *gl = lg_gl_get(n);
    if (!gl)
        return LG_ERR_DEVICE;
    static const float zero[4] = { 0, 0, 0, 1 };
    gl->ClearTexImage(color, 0, GL_RGBA, GL_FLOAT, zero);
    if (mode == MEM_REMAKE)
        lg_gl_buffer_destroy(n, &st->buf);
    return lg_gl_check(n, "test_mem: clearing the output");
}

static void mem_destroy(lg_node *n)
{
    mem_state *st = n->user;
    if (!st)
        return;
    lg_gl_buffer_destroy(n, &st->buf);
    lg_gl_texture_destroy(n, &st->tex);
    free(st);
    n->user = NULL;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "test_mem",
    .doc = "Holds scratch GL memory as `mode` says; outputs black (test)",
    LG_PARAMS(params),
    LG_OUTPUTS(out),
    .create = mem_create,
    .prepare = mem_prepare,
    .execute = mem_execute,
    .destroy = mem_destroy,
} };

LG_PLUGIN_DEFINE("testmem", "1.0.0", "Plugin memory in the profile test node", types)
