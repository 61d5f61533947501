/*
 * How the prt plugin runs its dot products: the CPU loop (prt_cpu.c), the GL and CL
 * launch geometry. Shared by prt.c and the roofline benchmark (tools/bench_prt_roofline.c),
 * so that the benchmark times the kernels exactly as the node runs them.
 *
 * Data (lightgraph/transfer.h, shcoeffs.h):
 *   transfer  float[V][3][stride]  stride = the transfer's n^2
 *   lighting  float[3][n]          n = the common prefix's n^2 (n <= stride), rotated
 *   out       float[texels][4]     the `vertices` image: texel i = vertex i, (r, g, b, 1);
 *                                  texels >= V are (0, 0, 0, 0)
 * radiance_c(v) = sum_{i < n} lighting[c][i] transfer[v][c][i].
 */
#ifndef LG_PRT_LAUNCH_H
#define LG_PRT_LAUNCH_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* GL: invocations per work-group (local_size_x of shaders/prt/prt_dot.comp), one per
 * texel; ceil(texels / PRT_GL_GROUP) groups, at most PRT_GL_MAX_X along x, then rows of
 * them (prt_gl_groups). */
#define PRT_GL_GROUP 64u
#define PRT_GL_MAX_X 32768u

/* CL: work-items per group (one per texel); the global size is rounded up to it. */
#define PRT_CL_LOCAL 256u

/* CPU: vertices per lg_parallel_for chunk (about 75 floats each at 5 bands: ~300 KB of
 * transfer per chunk, far above the hand-off cost, and 1M vertices make ~240 chunks). */
#define PRT_CPU_GRAIN 4096u

/* CL: the build options of shaders/prt/prt.cl for n coefficients of a transfer of `stride`
 * (one program per pair, cached by the host). */
#define PRT_RECORD_PAD(s) ((3u * (s) + 3u) / 4u * 4u)
static inline void prt_cl_options(char *buf, size_t size, uint32_t n, uint32_t stride)
{
    snprintf(buf, size, "-cl-std=CL1.2 -DLG_N=%uu -DLG_STRIDE=%uu -DLG_PAD=%uu", n, stride,
             PRT_RECORD_PAD(stride));
}

/* The lighting laid out like a vertex's record (prt.cl's `record`): 3 rows of
 * PRT_RECORD_PAD(stride) floats, row c holding lighting[c][0 .. n) at [c stride, c stride
 * + n) and zero elsewhere. `out` is the caller's. */
static inline void prt_record_lighting(const float *lighting, uint32_t n, uint32_t stride,
                                       float *out)
{
    const uint32_t pad = PRT_RECORD_PAD(stride);
    for (uint32_t c = 0; c < 3; c++)
        for (uint32_t j = 0; j < pad; j++) {
            uint32_t i = j - c * stride; /* wraps for j < c stride: then not used */
            out[c * pad + j] = j >= c * stride && i < n ? lighting[c * n + i] : 0.0f;
        }
}

static inline size_t prt_cl_global(size_t texels)
{
    size_t g = (texels + PRT_CL_LOCAL - 1) / PRT_CL_LOCAL * PRT_CL_LOCAL;
    return g ? g : PRT_CL_LOCAL;
}

/* GL: the defines of shaders/prt/prt_dot.comp for n coefficients of a transfer of
 * `stride`; tbo: read the transfer through an R32F buffer texture (when its float count
 * fits GL_MAX_TEXTURE_BUFFER_SIZE), else as a storage buffer. */
static inline void prt_gl_defines(char *buf, size_t size, uint32_t n, uint32_t stride, int tbo)
{
    snprintf(buf, size, "#define LG_N %uu\n#define LG_STRIDE %uu\n%s", n, stride,
             tbo ? "#define LG_TBO 1\n" : "");
}

/* GL: the defines of shaders/prt/prt_dot.frag (the dot products as a full-screen draw into
 * the `vertices` image, the version the node runs when its transfer fits a buffer
 * texture: prt_gl_frag_fits); r32f: read the records 1 float per fetch through an R32F
 * buffer texture (LG_R32F, the benchmark's comparison), else 3 through an RGB32F one. */
static inline void prt_gl_frag_defines(char *buf, size_t size, uint32_t n, uint32_t stride,
                                       int r32f)
{
    snprintf(buf, size, "#define LG_N %uu\n#define LG_STRIDE %uu\n%s", n, stride,
             r32f ? "#define LG_R32F 1\n" : "");
}

/* Whether prt_dot.frag can read a transfer of `vertices` records of 3 x `stride` floats
 * through its RGB32F buffer texture (vertices x stride texels): max_tbo =
 * GL_MAX_TEXTURE_BUFFER_SIZE. */
static inline int prt_gl_frag_fits(uint32_t vertices, uint32_t stride, int max_tbo)
{
    return (double)vertices * stride <= (double)max_tbo;
}

static inline void prt_gl_groups(size_t texels, uint32_t *gx, uint32_t *gy)
{
    size_t g = (texels + PRT_GL_GROUP - 1) / PRT_GL_GROUP;
    g = g ? g : 1u;
    *gx = g < PRT_GL_MAX_X ? (uint32_t)g : PRT_GL_MAX_X;
    *gy = (uint32_t)((g + *gx - 1) / *gx);
}

/* The CPU loop over texels [begin, end) (prt_cpu.c, built at -O3 so that GCC vectorises
 * it): writes out[4 * begin .. 4 * end). Thread-safe for disjoint ranges. */
typedef struct prt_cpu_job {
    const float *transfer;
    const float *lighting;
    uint32_t n, stride;
    uint32_t vertices;
    float *out;
} prt_cpu_job;

void lg_prt_cpu_range(const prt_cpu_job *job, size_t begin, size_t end);

#endif
