/* acme_blur, backend gl: one compute pass (lg_gl_pass, shaders/blur.comp) run twice per
 * frame, horizontally from the input into a scratch texture, then vertically from it into
 * the output. Every GL object is the SDK's: the pass (program, bindings, its uniform-block
 * buffer), the scratch texture (lg_gl_texture) and the weights (lg_gl_buffer), each counted
 * in the profile and freed by destroy. No GL call of our own: the pass sets and restores the
 * state (docs/devices.md, "The GL state contract"). */
#include <stdlib.h>

#include "blur.h"
#include "lightgraph/gl_pass.h"

#include "blur.comp.h" /* lg_src_blur_comp, lg_src_blur_comp_file (meson.build embeds it) */

struct acme_blur_gl {
    lg_gl_pass *pass;
    lg_gl_binding src, dst, weights, params; /* looked up by name once */
    lg_gl_texture scratch;                   /* the horizontal pass's result */
    lg_gl_buffer weights_buf;                /* radius + 1 floats (std430) */
};

/* The uniform block AcmeBlur of shaders/blur.comp (std140), uploaded whole with
 * lg_gl_pass_uniforms: its C mirror, checked here at compile time, and against the compiled
 * program by the first upload (the size of the block). */
typedef struct acme_blur_params {
    int32_t size[2]; /* ivec2 size: the image, pixels */
    int32_t dir[2];  /* ivec2 dir: (1, 0) horizontal, (0, 1) vertical */
    int32_t radius;  /* int radius */
    int32_t pad[3];  /* int pad0, pad1, pad2: a 32-byte block on every driver */
} acme_blur_params;
LG_GL_BLOCK_SIZE(acme_blur_params, 32);
LG_GL_BLOCK_OFFSET(acme_blur_params, dir, 8);
LG_GL_BLOCK_OFFSET(acme_blur_params, radius, 16);

static int gl_init(lg_node *n, struct acme_blur_gl *g)
{
    static const lg_gl_shader_src cs = { GL_COMPUTE_SHADER, lg_src_blur_comp_file,
                                         lg_src_blur_comp };
    lg_gl_pass_desc d = { .name = "acme_blur", .stages = &cs, .n_stages = 1 };
    int rc = lg_gl_pass_create(n, &d, &g->pass);
    if (rc)
        return rc;
    /* a misspelt name fails the pass: its begin then returns the error (one check) */
    g->src = lg_gl_pass_image(g->pass, "u_src");
    g->dst = lg_gl_pass_image(g->pass, "u_dst");
    g->weights = lg_gl_pass_storage(g->pass, "AcmeWeights");
    g->params = lg_gl_pass_uniform_block(g->pass, "AcmeBlur");
    return 0;
}

/* One direction: src -> dst. */
static int gl_run(struct acme_blur_gl *g, const acme_blur *st, GLuint src, GLuint dst, int dx,
                  int dy)
{
    int rc = lg_gl_pass_begin(g->pass, NULL);
    if (rc)
        return rc;
    acme_blur_params p = { .size = { (int32_t)st->width, (int32_t)st->height },
                           .dir = { dx, dy },
                           .radius = st->radius };
    lg_gl_pass_bind_image(g->pass, g->src, src, GL_READ_ONLY, GL_RGBA32F);
    lg_gl_pass_bind_image(g->pass, g->dst, dst, GL_WRITE_ONLY, GL_RGBA32F);
    lg_gl_pass_bind_buffer(g->pass, g->weights, g->weights_buf.name);
    if (!(rc = lg_gl_pass_uniforms(g->pass, g->params, &p, sizeof p)))
        rc = lg_gl_pass_dispatch(g->pass, st->width, st->height, 1);
    /* end: the barrier that makes dst visible to the next pass, and the state restored */
    return lg_gl_pass_end(g->pass, rc);
}

int acme_blur_gl(lg_node *n, acme_blur *st)
{
    int rc;
    if (!st->gl) {
        if (!(st->gl = calloc(1, sizeof *st->gl)))
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (gl backend state)");
        if ((rc = gl_init(n, st->gl)))
            return rc;
    }
    struct acme_blur_gl *g = st->gl;
    /* The recreate idiom: made on the first frame, kept while the size stays, remade (and
     * the old one released, both counted) when it changes. */
    lg_gl_texture_desc td = {
        .target = GL_TEXTURE_2D, .format = GL_RGBA32F, .width = st->width, .height = st->height
    };
    if ((rc = lg_gl_texture_recreate(n, &g->scratch, &td)) < 0)
        return rc;
    /* the weights: a few hundred bytes, uploaded every frame (cheaper than a check) */
    if ((rc = lg_gl_buffer_recreate(n, &g->weights_buf, ((size_t)st->radius + 1) * sizeof(float), 0,
                                    st->weights)))
        return rc;
    GLuint tin, tout;
    if ((rc = lg_map_gl(n, lg_input(n, 0), LG_READ, &tin, NULL)) ||
        (rc = lg_map_gl(n, lg_output(n, 0), LG_WRITE, &tout, NULL)))
        return rc;
    if ((rc = gl_run(g, st, tin, g->scratch.name, 1, 0)))
        return rc;
    return gl_run(g, st, g->scratch.name, tout, 0, 1);
}

void acme_blur_gl_free(lg_node *n, acme_blur *st)
{
    if (!st->gl)
        return;
    lg_gl_pass_destroy(&st->gl->pass);
    lg_gl_texture_destroy(n, &st->gl->scratch);
    lg_gl_buffer_destroy(n, &st->gl->weights_buf);
    free(st->gl);
    st->gl = NULL;
}
