/* acme_blur: what the node's files share (blur.c: the node; blur_cpu.c, blur_gl.c,
 * blur_cl.c: one backend each, with its own state). Private to the plugin: nothing here is
 * exported (the plugin exports lg_plugin_entry alone). */
#ifndef ACME_BLUR_H
#define ACME_BLUR_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "lightgraph/lightgraph.h"

/* The most taps on each side of a pixel (the `radius` parameter's maximum). */
#define ACME_BLUR_MAX_RADIUS 256

/* One instance. Made by create, freed by destroy. A backend's state (its device objects
 * and its scratch memory) is made on its first execute (the GL context and the CL queue
 * exist only then), kept across frames, remade only when the image size changes, and
 * freed by destroy. */
typedef struct acme_blur {
    lg_device device;        /* the `backend` parameter (lg_param_backend) */
    int radius;              /* taps on each side: ceil(3 sigma), or the `radius` parameter */
    float *weights;          /* radius + 1 normalised weights, [0] the centre (owned) */
    uint32_t width, height;  /* the input's size, from prepare */
    bool reported_nonfinite; /* lg_check_input_finite has warned (once per render) */
    struct acme_blur_cpu *cpu;
    struct acme_blur_gl *gl;
    struct acme_blur_cl *cl;
} acme_blur;

/* One backend's execute, and the release of its state (from destroy; NULL-safe). The
 * executes return 0 or an LG_ERR_* after reporting on the node. */
int acme_blur_cpu(lg_node *n, acme_blur *st);
void acme_blur_cpu_free(lg_node *n, acme_blur *st);
int acme_blur_gl(lg_node *n, acme_blur *st);
void acme_blur_gl_free(lg_node *n, acme_blur *st);
int acme_blur_cl(lg_node *n, acme_blur *st);
void acme_blur_cl_free(lg_node *n, acme_blur *st);

#endif
