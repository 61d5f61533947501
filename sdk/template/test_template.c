/* The template plugin's test, on the SDK's harness (lightgraph/test.h): template_invert on
 * an image with a plain reference, on every backend the node declares (it has no `backend`
 * parameter, so once, as it is), then its parameter's range through the host's checks.
 *
 *     test_template CASE          one case (meson runs each)
 *     test_template --bench=N     the benchmark: N frames, timing table
 *
 * LIGHTGRAPH_PLUGIN_PATH must name the folder of lg_template.so (meson.build sets it). */
#include <stdlib.h>
#include <string.h>

#include "lightgraph/test.h"

/* The reference: out = max(0, white - in) per RGB channel, alpha copied. */
static void invert(const lg_image *in, lg_image *out, float white)
{
    for (size_t i = 0; i < (size_t)in->width * in->height; i++) {
        for (int c = 0; c < 3; c++) {
            float v = white - in->pixels[4 * i + c];
            out->pixels[4 * i + c] = v > 0 ? v : 0;
        }
        out->pixels[4 * i + 3] = in->pixels[4 * i + 3];
    }
}

static void case_invert(lg_test *t)
{
    uint32_t w = lg_test_bench_frames(t) ? 1920 : 37, h = lg_test_bench_frames(t) ? 1080 : 11;
    lg_image in, want;
    if (lg_image_alloc(&in, w, h) || lg_image_alloc(&want, w, h)) {
        LG_TEST_FAILF(t, "cannot allocate %ux%u images", w, h);
        return;
    }
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        in.pixels[i] = (float)(i % 4 == 3 ? 0.5 : (double)(i % 13) / 6.0); /* 0 .. 2 */
    lg_test_write_exr(t, "in.exr", &in);
    invert(&in, &want, 1.5f);
    lg_test_backends_desc d = {
        .graph = "lightgraph 1\n"
                 "src = image { file = \"in.exr\", radiance = false }\n"
                 "inv = template_invert { image = src, white = 1.5 }\n",
        .node = "inv",
        .reference = &want,
        .tol_reference = {.max_abs = 0},   /* one float subtraction: exact */
        .tol_backends = {.max_abs = 0},
    };
    lg_test_backends(t, &d, NULL);
    lg_image_free(&in);
    lg_image_free(&want);
}

static void case_range(lg_test *t)
{
    /* white is declared in [0, 1e6]: the host refuses -1 with exit status 2, naming it */
    lg_test_write_text(t, "g.lgraph",
                       "lightgraph 1\nc = constant { color = [1, 1, 1] }\n"
                       "inv = template_invert { image = c, white = -1 }\noutput inv \"o.exr\"\n");
    char *out = NULL;
    const char *args[] = {"--size", "4x4", NULL};
    int rc = lg_test_render(t, "g.lgraph", args, &out);
    LG_TEST_CHECK(t, rc == 2, "exit %d, want 2", rc);
    LG_TEST_CHECK(t, out && strstr(out, "white"), "the message does not name the parameter: %s",
                  out ? out : "");
    free(out);
}

int main(int argc, char **argv)
{
    static const lg_test_case cases[] = {{"invert", case_invert}, {"range", case_range}};
    lg_test_main_opts o = {.prefix = "template"};
    return lg_test_main(argc, argv, cases, sizeof cases / sizeof cases[0], &o);
}
