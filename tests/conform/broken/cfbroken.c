/*
 * Deliberately broken plugins for `lightgraph conform` (tests/conform/meson.build): each
 * variant (-DCF_<VARIANT>) breaks exactly one contract of docs/conform.md, and the test
 * checks that conform fails it naming that check. Without a variant the plugin conforms
 * (the control: conform passes it).
 *
 * The node: `image` -> `out`, out = image * 0.5 (alpha kept), on cpu; it declares the
 * shared backend parameter {cpu, gl} where a variant needs two backends, and then runs its
 * "gl" backend on the CPU too (conform compares outputs; where they are computed does not
 * matter to it).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/gl.h"
#include "lightgraph/lightgraph.h"
#include "lightgraph/scene.h"

#if defined(CF_DISAGREE) || defined(CF_GLDIRTY) || defined(CF_GLERROR)
#define CF_TWO_BACKENDS 1
#endif

static const lg_param_desc params[] = {
#ifdef CF_TWO_BACKENDS
    LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL, LG_BACKEND_CPU),
#endif
#ifdef CF_BAD_DEFAULT
    { .key = "gain",
      .type = LG_PARAM_FLOAT,
      .def.f = 5,
      .min = 0,
      .max = 1,
      .doc = "a default outside its range" },
#else
    { .key = "gain",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.5,
      .min = 0,
      .max = 1,
      .doc = "multiplier of R, G and B" },
#endif
#ifdef CF_DUP_PARAM
    { .key = "gain",
      .type = LG_PARAM_FLOAT,
      .def.f = 0.5,
      .min = 0,
      .max = 1,
      .doc = "declared twice" },
#endif
#ifdef CF_NO_DOC
    { .key = "bias", .type = LG_PARAM_FLOAT, .def.f = 0, .min = -1, .max = 1 },
#endif
#ifdef CF_ALIAS
    { .key = "bias",
      .type = LG_PARAM_FLOAT,
      .def.f = 0,
      .min = -1,
      .max = 1,
      .doc = "renamed from a key still in use",
      .renamed_from = (const char *const[]){ "gain", NULL } },
#endif
};

#ifdef CF_NOGATE
static const lg_port_desc inputs[] = {
    { .name = "scene", .kind = LG_KIND_SCENE, .doc = "lit scene" }
};
#else
static const lg_port_desc inputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE, .doc = "rgba32f" }
};
#endif
static const lg_port_desc outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "rgba32f" }
};

#ifdef CF_EXIT_CRASH
/* crashes as the process that ran a node exits (a library destructor gone wrong): no case
 * is running then, so conform blames the exit, not a case */
static volatile int ran;
__attribute__((destructor)) static void at_unload(void)
{
    if (ran) {
        volatile int *p = NULL;
        *p = 1;
    }
}
#endif

typedef struct state {
    int frames;
    void *hoard[64];
} state;

static int create(lg_node *n)
{
    state *s = calloc(1, sizeof *s);
    if (!s)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    n->user = s;
    return 0;
}

static int prepare(lg_node *n)
{
    uint32_t w, h;
#ifdef CF_NOGATE
    n->host->render_size(n, &w, &h);
#else
    lg_resource_info info;
    int rc = lg_describe(lg_input(n, 0), &info, n);
    if (rc)
        return rc;
    if (info.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n, "input 'image' is %s; rgba32f only", lg_format_name(info.image.format));
    w = info.image.width, h = info.image.height;
#endif
#ifdef CF_RESIZE
    /* remembers the first size it saw, as if the instance were made once */
    static uint32_t first_w, first_h;
    if (!first_w)
        first_w = w, first_h = h;
    w = first_w, h = first_h;
#endif
    lg_image_desc d = { .width = w, .height = h, .format = LG_FORMAT_RGBA32F };
    int rc2 = lg_declare_image(n, 0, &d);
    return rc2 ? rc2 : lg_set_device(n, LG_DEVICE_CPU);
}

static int execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    state *s = n->user;
    lg_cpu_view vo;
    lg_resource_info oi;
    int rc = lg_describe(lg_output(n, 0), &oi, n);
    if (!rc)
        rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &vo);
    if (rc)
        return rc;
    float *o = vo.pixels;
    size_t np = (size_t)oi.image.width * oi.image.height;
    float gain = (float)lg_param_float(n, "gain");
#ifdef CF_NOGATE
    const lg_scene *sc = lg_scene_get(n, lg_input(n, 0));
    if (!sc)
        return LG_ERR_INVALID;
    if (sc->n_lights == 0)
        return lg_error(n, "the scene has no light to draw with");
    for (size_t i = 0; i < np * 4; i++)
        o[i] = gain;
#else
    lg_cpu_view vi;
    if ((rc = lg_map_cpu(n, lg_input(n, 0), LG_READ, &vi)))
        return rc;
    const float *in = vi.pixels;
    for (size_t i = 0; i < np; i++) {
        for (int c = 0; c < 3; c++)
            o[i * 4 + c] = in[i * 4 + c] * gain;
        o[i * 4 + 3] = in[i * 4 + 3];
    }
#endif
#ifdef CF_NAN
    o[0] = NAN; /* on every input */
#endif
#ifdef CF_CRASH
    if (isnan(in[(np / 2) * 4])) { /* a NaN pixel: a crash */
        volatile int *p = NULL;
        *p = 1;
    }
#endif
#ifdef CF_DISAGREE
    if (lg_param_backend(n) == LG_DEVICE_GL)
        for (size_t i = 0; i < np; i++)
            o[i * 4] += 0.05f;
#endif
#ifdef CF_NONDET
    static int runs;
    o[0] += (float)(runs++) * 1e-3f;
#endif
#ifdef CF_LEAK_ACCOUNT
    lg_account_alloc(n, 4096); /* counted every frame, never released */
#endif
#ifdef CF_LEAK_RSS
    /* 1 MiB a frame, touched, kept until destroy (a scratch buffer made per execute) */
    if (s->frames < 64) {
        s->hoard[s->frames] = malloc(1u << 20);
        if (s->hoard[s->frames])
            memset(s->hoard[s->frames], 1, 1u << 20);
    }
#endif
#ifdef CF_GLDIRTY
    if (lg_param_backend(n) == LG_DEVICE_GL) {
        const lg_gl *gl = lg_gl_get(n);
        if (!gl)
            return LG_ERR_DEVICE;
        GLuint b = 0;
        gl->CreateBuffers(1, &b);
        gl->BindBuffer(GL_SHADER_STORAGE_BUFFER, b); /* left bound */
    }
#endif
#ifdef CF_GLERROR
    if (lg_param_backend(n) == LG_DEVICE_GL) {
        const lg_gl *gl = lg_gl_get(n);
        if (!gl)
            return LG_ERR_DEVICE;
        gl->BindBuffer(GL_ARRAY_BUFFER, 987654); /* no such buffer: GL_INVALID_OPERATION */
    }
#endif
#ifdef CF_EXIT_CRASH
    ran = 1;
#endif
    s->frames++;
    return 0;
}

static void destroy(lg_node *n)
{
    state *s = n->user;
#ifdef CF_DESTROY_CRASH
    /* assumes prepare ran: after a failed prepare `frames` is 0 ... */
    if (s->frames == 0) {
        volatile int *p = NULL;
        *p = 1;
    }
#endif
    if (s)
        for (int i = 0; i < 64; i++)
            free(s->hoard[i]);
    free(s);
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
#ifdef CF_BAD_NAME
    .name = "halve",
#else
    .name = CF_TYPE_NAME,
#endif
    .doc = "a broken node (tests/conform/broken)",
    LG_PARAMS(params),
    LG_INPUTS(inputs),
    LG_OUTPUTS(outputs),
    .create = create,
    .prepare = prepare,
    .execute = execute,
    .destroy = destroy,
} };

LG_PLUGIN_DEFINE(CF_PLUGIN_NAME, "0.0.1", "a plugin that breaks one contract (conform test)", types)
