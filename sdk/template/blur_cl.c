/* acme_blur, backend cl: one kernel (lg_cl_pass, shaders/blur.cl after
 * shaders/common/acme_blur.cl) run twice per frame, horizontally from the input into a
 * scratch buffer, then vertically from it into the output. The scratch image and the weights
 * are lg_cl_buffers (counted in the profile, freed by destroy); every argument is set and
 * checked one at a time, so a failure names the kernel, the argument and the CL error. */
#include <stdlib.h>

#include "blur.h"
#include "lightgraph/cl.h"

#include "acme_blur.cl.h" /* lg_src_acme_blur_cl: the bad-pixel policy, shared text */
#include "blur.cl.h"      /* lg_src_blur_cl: the kernel */

struct acme_blur_cl {
    lg_cl_pass *pass;
    lg_cl_buffer scratch; /* width x height float4: the horizontal pass's result */
    lg_cl_buffer weights; /* radius + 1 floats */
};

static int cl_init(lg_node *n, struct acme_blur_cl *c)
{
    /* OpenCL C has no #include of embedded text: the shared text first, then the kernel */
    static const char *const sources[] = { lg_src_acme_blur_cl, lg_src_blur_cl };
    static const char *const names[] = { lg_src_acme_blur_cl_file, lg_src_blur_cl_file };
    lg_cl_pass_desc d = { .struct_size = sizeof d,
                          .name = "acme_blur",
                          .sources = sources,
                          .source_names = names,
                          .n_sources = 2,
                          .options = "-cl-std=CL1.2",
                          .kernel = "acme_blur_1d" };
    return lg_cl_pass_create(n, &d, &c->pass);
}

/* The arguments after the source and the destination (0 and 1), as shaders/blur.cl
 * declares them, then the run: one direction. */
static int cl_run(struct acme_blur_cl *c, const acme_blur *st, int dx, int dy)
{
    int rc;
    if ((rc = lg_cl_pass_arg_int(c->pass, 2, (int32_t)st->width)) ||
        (rc = lg_cl_pass_arg_int(c->pass, 3, (int32_t)st->height)) ||
        (rc = lg_cl_pass_arg_int(c->pass, 4, dx)) || (rc = lg_cl_pass_arg_int(c->pass, 5, dy)) ||
        (rc = lg_cl_pass_arg_mem(c->pass, 6, c->weights.mem)) ||
        (rc = lg_cl_pass_arg_int(c->pass, 7, st->radius)))
        return rc;
    const size_t global[2] = { st->width, st->height };
    return lg_cl_pass_run(c->pass, 2, global, NULL); /* records the event for the profile */
}

int acme_blur_cl(lg_node *n, acme_blur *st)
{
    int rc;
    if (!st->cl) {
        if (!(st->cl = calloc(1, sizeof *st->cl)))
            return lg_error_code(n, LG_ERR_NOMEM, "out of memory (cl backend state)");
        if ((rc = cl_init(n, st->cl)))
            return rc;
    }
    struct acme_blur_cl *c = st->cl;
    /* The recreate idiom: made on the first frame, kept while large enough. */
    size_t wbytes = ((size_t)st->radius + 1) * sizeof(float);
    bool fresh = c->weights.mem == NULL;
    if ((rc = lg_cl_buffer_recreate(n, &c->scratch,
                                    (size_t)st->width * st->height * 4 * sizeof(float), 0)) ||
        (rc = lg_cl_buffer_recreate(n, &c->weights, wbytes, CL_MEM_READ_ONLY)))
        return rc;
    if (fresh && (rc = lg_cl_buffer_write(n, &c->weights, 0, wbytes, st->weights)))
        return rc; /* the weights do not change for an instance: written once */
    /* horizontal: the input (mapped on CL for reading by the pass) -> scratch */
    if ((rc = lg_cl_pass_arg_resource(c->pass, 0, lg_input(n, 0), LG_READ)) ||
        (rc = lg_cl_pass_arg_mem(c->pass, 1, c->scratch.mem)) || (rc = cl_run(c, st, 1, 0)))
        return rc;
    /* vertical: scratch -> the output (mapped for writing) */
    if ((rc = lg_cl_pass_arg_mem(c->pass, 0, c->scratch.mem)) ||
        (rc = lg_cl_pass_arg_resource(c->pass, 1, lg_output(n, 0), LG_WRITE)))
        return rc;
    return cl_run(c, st, 0, 1);
}

void acme_blur_cl_free(lg_node *n, acme_blur *st)
{
    if (!st->cl)
        return;
    lg_cl_pass_destroy(&st->cl->pass);
    lg_cl_buffer_destroy(n, &st->cl->scratch);
    lg_cl_buffer_destroy(n, &st->cl->weights);
    free(st->cl);
    st->cl = NULL;
}
