/*
 * How the reinhard plugin launches its GL and CL kernels: the work-group sizes, the
 * number of stage-1 groups, and the result block that stage 2 leaves on the device for
 * the map. Shared by reinhard.c and the roofline benchmark (tools/bench_roofline.c), so
 * that the benchmark times the kernels exactly as the node runs them.
 *
 * The pipeline, on both devices, has no host round trip between the passes:
 *   stage 1  work-groups of RH_GROUP items sum log(delta + L) over their share of the
 *            pixels (branch-free) and write one rh_partial each;
 *   stage 2  one work-group reduces the partials, then one item computes Lavg, the
 *            adaptation step and the scale a / L into the rh_result block;
 *   map      reads the scale from rh_result; one pixel per item (GL), eight (CL).
 * The host reads rh_result back once, after the map was queued, for the bad-pixel report
 * and the debug log only.
 */
#ifndef LG_REINHARD_LAUNCH_H
#define LG_REINHARD_LAUNCH_H

#include <stddef.h>
#include <stdint.h>

/* Work-group size of the reductions (GL: local_size_x in reinhard_reduce.comp; CL:
 * -DLG_LOCAL, the stride between an item's pixels and stage 2's group), and the most
 * stage-1 groups on GL. */
#define RH_GROUP 256u
#define RH_MAX_GROUPS 256u
/* GL stage 1 gives each invocation at least this many rows before it adds more groups. */
#define RH_MIN_PIXELS_PER_ITEM 16u

/* CL stage 1: pixels per work-item (-DLG_PPI, a multiple of RH_CL_BLOCK), each item
 * writing one partial; the groups are as many as the image needs (rh_cl_groups), and
 * stage 2 loops over the partials (rh_cl_partials). 32: the partials add 0.5 byte per
 * pixel of traffic, and stage 2 takes 0.24 ms on 2048x1396 (0.55 ms with 16, 5-6 ms with
 * 4; stage 1 the same or faster with 32 than with 16, no faster with 64; PoCL 3.1). */
#define RH_CL_PPI 32u
_Static_assert(RH_CL_PPI % 8 == 0, "CL stage 1 reads blocks of 8 pixels");

/* CL: pixels per vector (float8) in both pixel kernels; the map runs one block of this
 * many pixels per work-item (rh_cl_map_items). */
#define RH_CL_BLOCK 8u

/* CL map: work-items per group (PoCL measured the same from 64 to 4096 with one pixel per
 * item; with eight, 256 was as fast as 64 and faster than 1024). */
#define RH_CL_MAP_LOCAL 256u

/* GL: stage 1 is a 2D dispatch: groups of RH_GROUP invocations along x, each invocation
 * walking a column of the image with a stride of rh_gl_rows() groups in y (no integer
 * division per pixel). The map runs 64x1 groups along rows (llvmpipe runs 8 or 16
 * invocations side by side; rows keep their loads and stores contiguous). */
#define RH_GL_MAP_X 64u
#define RH_GL_MAP_Y 1u

/* A partial sum as the shaders and kernels write it (std430 / OpenCL struct layout). */
typedef struct rh_partial {
    float sum;
    uint32_t valid, nonfinite, negative;
} rh_partial;

/* What stage 2 leaves on the device (std430 / OpenCL layout, 32 bytes). `la` and
 * `have_la` persist from frame to frame (the adaptation state); the rest is rewritten. */
typedef struct rh_result {
    float sum; /* sum of log(delta + L) over the valid pixels */
    uint32_t valid, nonfinite, negative;
    float lavg;       /* exp(sum / valid), or 1 when no pixel is valid */
    float la;         /* the adapted luminance */
    float scale;      /* a / Lavg, or a / La with adaptation: what the map uses */
    uint32_t have_la; /* la holds a value */
} rh_result;

_Static_assert(sizeof(rh_partial) == 16, "rh_partial mirrors a std430 / OpenCL struct");
_Static_assert(sizeof(rh_result) == 32 && offsetof(rh_result, scale) == 24,
               "rh_result mirrors a std430 / OpenCL struct");

/* CL stage-1 groups for n pixels ... */
static inline uint32_t rh_cl_groups(size_t n)
{
    size_t per_group = (size_t)RH_GROUP * RH_CL_PPI;
    size_t g = (n + per_group - 1) / per_group;
    return g == 0 ? 1u : (uint32_t)g;
}
/* ... and the partials: one per stage-1 work-item. */
static inline uint32_t rh_cl_partials(size_t n)
{
    return rh_cl_groups(n) * RH_GROUP;
}

/* CL map: the global size for n pixels, one block per item, a multiple of RH_CL_MAP_LOCAL
 * (the items past the image return at once; the last block may be partial). */
static inline size_t rh_cl_map_items(size_t n)
{
    size_t blocks = (n + RH_CL_BLOCK - 1) / RH_CL_BLOCK;
    size_t g = (blocks + RH_CL_MAP_LOCAL - 1) / RH_CL_MAP_LOCAL * RH_CL_MAP_LOCAL;
    return g == 0 ? RH_CL_MAP_LOCAL : g;
}

/* GL stage 1: groups along x, and along y (each covering every rh_gl_rows()-th row);
 * cols * rows <= RH_MAX_GROUPS. */
static inline uint32_t rh_gl_cols(uint32_t width)
{
    return (width + RH_GROUP - 1) / RH_GROUP;
}
static inline uint32_t rh_gl_rows(uint32_t width, uint32_t height)
{
    uint32_t cols = rh_gl_cols(width);
    uint32_t rows = RH_MAX_GROUPS / cols;
    uint32_t want = (height + RH_MIN_PIXELS_PER_ITEM - 1) / RH_MIN_PIXELS_PER_ITEM;
    rows = rows < want ? rows : want;
    return rows == 0 ? 1u : rows;
}

#endif
