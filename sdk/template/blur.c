/* acme_blur: a separable Gaussian blur, the SDK's template plugin. Copy this folder to
 * start a plugin; README.md says what the node does and how it was measured,
 * docs/plugin-guide.md (in lightgraph's sources) walks through every part.
 *
 * This file is the node: its descriptor (parameters, ports, the backend set), create
 * (the weights), prepare (the output and the device) and destroy. Each backend is a file
 * of its own with its own state: blur_cpu.c (the reference, on the host's thread pool),
 * blur_gl.c (a compute lg_gl_pass) and blur_cl.c (an lg_cl_pass). All three compute
 *
 *     tmp(x, y) = sum_{i=-r..r} w_|i| in(clamp(x + i), y)      horizontal pass
 *     out(x, y) = sum_{j=-r..r} w_|j| tmp(x, clamp(y + j))     vertical pass
 *
 * with w_i = exp(-i^2 / (2 sigma^2)) / sum_{k=-r..r} exp(-k^2 / (2 sigma^2)), in float,
 * the taps in the order i = -r .. r, each channel (alpha too) on its own. */
#include <math.h>
#include <stdlib.h>

#include "blur.h"

static const lg_param_desc params[] = {
    { .key = "sigma",
      .type = LG_PARAM_FLOAT,
      .def.f = 2.0,
      .min = 0,
      .max = 64,
      .doc = "standard deviation of the Gaussian, pixels; 0 copies the image" },
    { .key = "radius",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = ACME_BLUR_MAX_RADIUS,
      .doc = "taps on each side of a pixel; 0 = ceil(3 sigma)" },
    /* The one backend parameter (lightgraph/plugin.h): the backends this node has, in the
     * order cpu, gl, cl, and its default. */
    LG_PARAM_BACKEND(LG_BACKEND_CPU | LG_BACKEND_GL | LG_BACKEND_CL, LG_BACKEND_CPU),
};
static const lg_port_desc inputs[] = {
    { .name = "image", .kind = LG_KIND_IMAGE, .doc = "the image to blur, rgba32f" },
};
static const lg_port_desc outputs[] = {
    { .name = "out", .kind = LG_KIND_IMAGE, .doc = "the blurred image, rgba32f, same size" },
};

static int blur_create(lg_node *n)
{
    acme_blur *st = calloc(1, sizeof *st);
    if (!st)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu bytes of node state)",
                             sizeof *st);
    n->user = st; /* destroy frees it, even when create fails below */
    st->device = lg_param_backend(n);
    double sigma = lg_param_float(n, "sigma");
    int64_t radius = lg_param_int(n, "radius");
    /* sigma 0: a copy (one tap of weight 1), whatever the radius says */
    st->radius = sigma == 0 ? 0 : radius > 0 ? (int)radius : (int)ceil(3 * sigma);
    if (st->radius > ACME_BLUR_MAX_RADIUS) /* ceil(3 * 64) = 192: cannot happen today */
        return lg_error(n, "parameter sigma = %g: a radius of %d taps, more than %d", sigma,
                        st->radius, ACME_BLUR_MAX_RADIUS);
    st->weights = malloc(((size_t)st->radius + 1) * sizeof *st->weights);
    if (!st->weights)
        return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%d weights)", st->radius + 1);
    /* In double, normalised over the 2r + 1 taps so that a constant image stays constant
     * (up to float rounding), then rounded to float once. */
    double w[ACME_BLUR_MAX_RADIUS + 1], sum = 0;
    for (int i = 0; i <= st->radius; i++) {
        w[i] = sigma == 0 ? 1.0 : exp(-(double)i * i / (2 * sigma * sigma));
        sum += i ? 2 * w[i] : w[i];
    }
    for (int i = 0; i <= st->radius; i++)
        st->weights[i] = (float)(w[i] / sum);
    return 0;
}

static int blur_prepare(lg_node *n)
{
    acme_blur *st = n->user;
    lg_resource_info info;
    int rc = lg_describe(lg_input(n, 0), &info, n);
    if (rc)
        return rc;
    if (info.image.format != LG_FORMAT_RGBA32F)
        return lg_error(n, "input 'image' is %s; acme_blur reads rgba32f images only",
                        lg_format_name(info.image.format));
    if (info.image.flags & (LG_IMAGE_CUBE | LG_IMAGE_DEPTH_ONLY))
        return lg_error(n, "input 'image' is a %s; acme_blur blurs 2D colour images",
                        (info.image.flags & LG_IMAGE_CUBE) ? "cube map" : "depth-only image");
    st->width = info.image.width;
    st->height = info.image.height;
    lg_image_desc d = { .width = st->width, .height = st->height, .format = LG_FORMAT_RGBA32F };
    if ((rc = lg_declare_image(n, 0, &d)))
        return rc;
    /* the host moves the input to this device when it is elsewhere (counted as moved) */
    return lg_set_device(n, st->device);
}

static int blur_execute(lg_node *n, const lg_frame *frame)
{
    acme_blur *st = n->user;
    /* The policy for NaN and Inf (README "Bad pixels"), said once per render on every
     * backend. The count reads the input on the CPU: free when the input's CPU copy is
     * current (an image read from a file), a move when it was made on a GPU. */
    int rc = lg_check_input_finite(n, frame, 0, "image", "read as 0 (NaN) and +-3.4e38 (+-Inf)",
                                   &st->reported_nonfinite);
    if (rc)
        return rc;
    switch (st->device) {
    case LG_DEVICE_GL: return acme_blur_gl(n, st);
    case LG_DEVICE_CL: return acme_blur_cl(n, st);
    default: return acme_blur_cpu(n, st);
    }
}

static void blur_destroy(lg_node *n)
{
    acme_blur *st = n->user;
    if (!st)
        return;
    acme_blur_cpu_free(n, st);
    acme_blur_gl_free(n, st);
    acme_blur_cl_free(n, st);
    free(st->weights);
    free(st);
    n->user = NULL;
}

static const lg_node_type types[] = { {
    .struct_size = sizeof(lg_node_type),
    .name = "acme_blur",
    .doc = "separable Gaussian blur, clamp-to-edge (the SDK's template)",
    LG_PARAMS(params),
    LG_INPUTS(inputs),
    LG_OUTPUTS(outputs),
    .create = blur_create,
    .prepare = blur_prepare,
    .execute = blur_execute,
    .destroy = blur_destroy,
    /* how far cpu, gl and cl may differ (lightgraph conform): float sums of up to 2r + 1
     * taps in two passes, measured below 1e-6 relative (README "Accuracy") */
    .tolerance = 1e-5,
} };

/* The naming rule for third-party plugins: plugin VENDOR_NAME, node types VENDOR_...
 * (VENDOR: 2 to 16 of [a-z0-9], not "lg"). The version is part of every cache key. */
LG_PLUGIN_DEFINE("acme_blur", "1.0.0", "Gaussian blur on cpu, gl and cl (the SDK's template)",
                 types)
