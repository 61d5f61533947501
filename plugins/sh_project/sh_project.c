/*
 * The sh_project plugin: the lighting of a light probe projected onto real spherical
 * harmonics (TECHNIQUES.md §5, seed 0 §5.6).
 *
 *   sh_project  probe -> sh: c_i = integral over the sphere of L(w) Y_i(w) dw, for the
 *               n^2 functions of n bands (lightgraph/sh.h), per colour channel, in world
 *               directions (the probe's rotation applied)
 *
 * Two estimators:
 *   quadrature  every texel t of the probe's level 0 in its own layout, at its centre
 *               direction w_t, weighted by its exact solid angle (the probe's table):
 *               c_i = sum_t L_t Y_i(w_t) dOmega_t. Exact for the piecewise-constant probe
 *               up to the variation of Y_i within a texel.
 *   samplers    T = N x N points of lightgraph/sampling.h (jittered, Hammersley, Sobol)
 *               mapped uniformly to the sphere, L read by the probe's bilinear lookup:
 *               c_i = (4 pi / T) sum_k L(w_k) Y_i(w_k).
 *
 * Accuracy over 10^8 terms: the terms are cut into fixed chunks (a function of the term
 * count and the band count only); each chunk sums every coefficient and channel with
 * lg_sum (double, Neumaier-compensated); the chunks' sums are merged in chunk order on
 * the calling thread. The result is therefore the same bits on any number of threads
 * (LIGHTGRAPH_THREADS), and the error does not grow with the count. Y is evaluated in
 * double (lg_sh_eval_d): the products L Y_i are summed in double, and float Y (5e-6
 * relative at band 16) would be the largest error; on the CPU the double evaluation
 * costs about what the float one does.
 *
 * The node runs once (static) on the CPU, over the host's thread pool. README.md has the
 * ports, parameters, the text format of its output and the measured accuracy and cost.
 */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lightgraph/lightgraph.h"
#include "lightgraph/probe.h"
#include "lightgraph/sampling.h"
#include "lightgraph/sh.h"
#include "lightgraph/shcoeffs.h"

enum { SHP_QUADRATURE = 0, SHP_JITTERED, SHP_HAMMERSLEY, SHP_SOBOL };
enum { SHP_WINDOW_NONE = 0, SHP_WINDOW_HANNING, SHP_WINDOW_LANCZOS, SHP_WINDOW_GAUSSIAN };

/* Terms per chunk: at least SHP_GRAIN (a chunk is worth a thread hand-off), and at most
 * SHP_SLOT_SUMS compensated sums held over all chunks (64 MiB of slots at 64 bands). */
#define SHP_GRAIN 4096u
#define SHP_SLOT_SUMS ((size_t)1 << 22)

typedef struct shp_state {
    uint32_t bands;
    int sampler, window;
    uint32_t side; /* N: N x N samples */
    uint64_t seed;
    double window_width;
} shp_state;

/* What the chunks read (shared, read-only) and write (their slot only). */
typedef struct shp_job {
    uint32_t bands, nc; /* n, n^2 */
    int sampler;
    uint32_t side;
    uint64_t seed;
    lg_probe_image img;    /* level 0, with the probe's rotation */
    const float *solid;    /* quadrature: steradians per texel */
    uint32_t faces;        /* quadrature: 6 for a cube, else 1 */
    lg_sum *slots;         /* [chunks][3][nc] */
    unsigned char *failed; /* [chunks]: out of memory in the chunk */
} shp_job;

static const char *const shp_samplers[] = { "quadrature", "jittered", "hammersley", "sobol", NULL };
static const char *const shp_windows[] = { "none", "hanning", "lanczos", "gaussian", NULL };

static const lg_param_desc shp_params[] = {
    { .key = "bands",
      .type = LG_PARAM_INT,
      .def.i = 3,
      .min = 1,
      .max = LG_SH_MAX_BANDS,
      .doc = "SH bands n (n^2 coefficients per channel)" },
    { .key = "sampler",
      .type = LG_PARAM_ENUM,
      .def.e = SHP_QUADRATURE,
      .enum_values = shp_samplers,
      .doc = "quadrature (every texel, its exact solid angle) or N x N points: jittered, "
             "hammersley, sobol" },
    { .key = "samples",
      .type = LG_PARAM_INT,
      .def.i = 256,
      .min = 1,
      .max = 16384,
      .doc = "N: N x N sample directions (jittered, hammersley, sobol; ignored by "
             "quadrature)" },
    { .key = "seed",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = 4294967295.0,
      .doc = "jitter / digital shift of the samplers (0: Hammersley and Sobol unshifted)" },
    { .key = "window",
      .type = LG_PARAM_ENUM,
      .def.e = SHP_WINDOW_NONE,
      .enum_values = shp_windows,
      .doc = "ringing window on the result (lg_sh_window, Sloan 2008): none, hanning, "
             "lanczos, gaussian" },
    { .key = "window_width",
      .type = LG_PARAM_FLOAT,
      .def.f = 3.0,
      .min = 1e-3,
      .max = 1e3,
      .doc = "the window's width in bands (ignored with window = none)" },
};
static const lg_port_desc shp_inputs[] = {
    { .name = "probe",
      .kind = LG_KIND_PROBE,
      .doc = "the light probe (any layout; its rotation is applied)" },
};
static const lg_port_desc shp_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_SH,
      .doc = "n^2 x RGB coefficients of the radiance in world directions (lightgraph/sh.h); "
             "`output NODE \"x.txt\"` writes them as text" },
};

static double shp_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int shp_create(lg_node *n)
{
    shp_state *st = lg_create_state(n, sizeof *st);
    if (!st)
        return LG_ERR_NOMEM;
    st->bands = (uint32_t)lg_param_int(n, "bands");
    st->sampler = lg_param_enum(n, "sampler");
    st->side = (uint32_t)lg_param_int(n, "samples");
    st->seed = (uint64_t)lg_param_int(n, "seed");
    st->window = lg_param_enum(n, "window");
    st->window_width = lg_param_float(n, "window_width");
    /* the ranges are the host's to enforce; a descriptor that drifts from them is a bug */
    if (st->bands < 1 || st->bands > LG_SH_MAX_BANDS || st->side < 1 || !(st->window_width > 0) ||
        !isfinite(st->window_width))
        return lg_error(n, "bands = %u, samples = %u, window_width = %g: out of range", st->bands,
                        st->side, st->window_width);
    return 0;
}

static void shp_destroy(lg_node *n)
{
    free(n->user);
    n->user = NULL;
}

/* Seconds one thread takes per term x coefficient (a term: one texel or one sample; each
 * evaluates n^2 SH functions in double and adds 3 n^2 compensated sums). Measured here
 * (2-core VM shared with compiles, LIGHTGRAPH_THREADS=1): bands 32 from 512^2 Sobol
 * samples, 2.7e8 products in 8.1 s, 3.0e-8 s each; quadrature of a 1024x512 probe at
 * 16 bands runs at the same rate within a factor 2. The sampler's own cost per term (a
 * bilinear lookup) is small beside n^2 >= 1 products for every band count but 1, so it
 * is folded in. An order of magnitude is what it is for: `render` warns above a minute. */
#define SHP_SECONDS_PER_PRODUCT 3.0e-8

static int shp_prepare(lg_node *n)
{
    shp_state *st = n->user;
    int rc = lg_sh_declare(n, 0, st->bands);
    if (rc)
        return rc;
    /* the estimate: terms x n^2, on the host's threads */
    double terms = (double)st->side * st->side;
    if (st->sampler == SHP_QUADRATURE) {
        const lg_resource *in = lg_input(n, 0);
        const lg_resource *rad = in ? lg_part(n, in, "radiance") : NULL;
        lg_resource_info ri;
        terms = 0;
        if (rad && lg_describe(rad, &ri, n) == 0)
            terms = (double)ri.image.width * ri.image.height *
                    ((ri.image.flags & LG_IMAGE_CUBE) ? 6 : 1);
    }
    double products = terms * st->bands * st->bands;
    lg_declare_work(n, products, products * SHP_SECONDS_PER_PRODUCT / lg_cpu_workers(n),
                    st->sampler == SHP_QUADRATURE ? "texel x coefficient products"
                                                  : "sample x coefficient products");
    return lg_set_device(n, LG_DEVICE_CPU);
}

/* Adds L * Y (one direction's radiance times weight w, rgb) into the chunk's sums. */
static void shp_accumulate(lg_sum *acc, uint32_t nc, const double *y, const double l[3])
{
    for (int ch = 0; ch < 3; ch++) {
        if (l[ch] == 0.0)
            continue; /* adds exactly nothing */
        lg_sum *a = acc + (size_t)ch * nc;
        for (uint32_t i = 0; i < nc; i++)
            lg_sum_add(&a[i], l[ch] * y[i]);
    }
}

/* The direction a quadrature texel stands for: its centre's. An angular probe's rim
 * texel whose centre lies outside the unit disc (direction +Z, lightgraph/probe.h) but
 * whose solid angle is its part inside stands for that part: the point on the centre's
 * ray half-way between the texel's nearest point to the disc's centre and the rim. */
static lg_vec3 shp_texel_dir(const lg_probe_image *img, uint32_t face, uint32_t i, uint32_t j)
{
    lg_vec3 d = lg_probe_texel_dir(img->layout, img->width, img->height, face, i, j);
    if (img->layout != LG_PROBE_ANGULAR)
        return d;
    double w = img->width, h = img->height;
    double a = 2.0 * (i + 0.5) / w - 1.0, b = 1.0 - 2.0 * (j + 0.5) / h;
    double r = sqrt(a * a + b * b);
    if (r < 1.0)
        return d;
    /* nearest point of the texel [a0, a1] x [b0, b1] to the origin */
    double a0 = 2.0 * i / w - 1.0, a1 = 2.0 * (i + 1) / w - 1.0;
    double b0 = 1.0 - 2.0 * (j + 1) / h, b1 = 1.0 - 2.0 * j / h;
    double na = a0 > 0 ? a0 : a1 < 0 ? a1 : 0.0, nb = b0 > 0 ? b0 : b1 < 0 ? b1 : 0.0;
    double rm = 0.5 * (sqrt(na * na + nb * nb) + 1.0);
    lg_probe_coord c;
    c.face = 0;
    c.u = (float)(0.5 * (a / r * rm + 1.0));
    c.v = (float)(0.5 * (1.0 - b / r * rm));
    return lg_probe_coord_to_dir(LG_PROBE_ANGULAR, c);
}

/* One chunk of terms [begin, end): texels (quadrature) or sample indices. */
static void shp_chunk(void *ctx, size_t begin, size_t end, uint32_t chunk)
{
    const shp_job *j = ctx;
    lg_sum *acc = j->slots + (size_t)chunk * 3 * j->nc;
    double *y = malloc((size_t)j->nc * sizeof *y);
    if (!y) {
        j->failed[chunk] = 1;
        return;
    }
    const uint32_t w = j->img.width, h = j->img.height;
    for (size_t k = begin; k < end; k++) {
        double dir[3], l[3];
        float rgba[4];
        if (j->sampler == SHP_QUADRATURE) {
            double sa = j->solid[k];
            if (sa == 0.0)
                continue; /* an angular probe's corner: not part of the sphere */
            uint32_t face = (uint32_t)(k / ((size_t)w * h));
            size_t r = k % ((size_t)w * h);
            uint32_t row = (uint32_t)(r / w), col = (uint32_t)(r % w);
            lg_vec3 d = lg_probe_to_world(j->img.rotation, shp_texel_dir(&j->img, face, col, row));
            const float *t = j->img.rgba + 4 * k;
            dir[0] = d.x, dir[1] = d.y, dir[2] = d.z;
            for (int ch = 0; ch < 3; ch++)
                l[ch] = (double)t[ch] * sa;
        } else {
            double uv[2];
            static const lg_sampler map[] = { LG_SAMPLER_JITTERED, LG_SAMPLER_JITTERED,
                                              LG_SAMPLER_HAMMERSLEY, LG_SAMPLER_SOBOL };
            lg_sample_square(map[j->sampler], j->side, j->seed, k, uv);
            lg_sample_sphere(uv, dir);
            lg_probe_lookup(&j->img, lg_v3((float)dir[0], (float)dir[1], (float)dir[2]),
                            LG_PROBE_BILINEAR, rgba);
            for (int ch = 0; ch < 3; ch++)
                l[ch] = (double)rgba[ch];
        }
        lg_sh_eval_d(j->bands, dir, y);
        shp_accumulate(acc, j->nc, y, l);
    }
    free(y);
}

/* The probe input, checked; NULL after reporting. */
static const lg_probe *shp_probe(lg_node *n, lg_probe *view)
{
    const lg_resource *pres = lg_input(n, 0);
    const lg_probe *p = lg_probe_get(n, pres, view);
    if (!p) {
        lg_resource_info info;
        if (pres && lg_describe(pres, &info, n) == 0 && info.neutral)
            lg_error(n, "input 'probe' is empty (its producer was gated)");
        return NULL;
    }
    const lg_image_desc *rd = &p->radiance_desc;
    if (rd->format != LG_FORMAT_RGBA32F) {
        lg_error(n, "input 'probe': the radiance image is %s, not rgba32f",
                 lg_format_name(rd->format));
        return NULL;
    }
    if (rd->width == 0 || rd->height == 0) {
        lg_error(n, "input 'probe': the radiance image is empty");
        return NULL;
    }
    if (p->info.layout < LG_PROBE_LATLONG || p->info.layout > LG_PROBE_CUBE) {
        lg_error(n, "input 'probe': unknown layout %d", (int)p->info.layout);
        return NULL;
    }
    if ((p->info.layout == LG_PROBE_CUBE) != ((rd->flags & LG_IMAGE_CUBE) != 0) ||
        (p->info.layout == LG_PROBE_CUBE && rd->width != rd->height)) {
        lg_error(n, "input 'probe': the layout and the radiance image disagree (a cube layout "
                    "without a square cube image, or the reverse)");
        return NULL;
    }
    return p;
}

static int shp_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    shp_state *st = n->user;
    double t0 = shp_now();
    lg_probe view;
    const lg_probe *p = shp_probe(n, &view);
    if (!p)
        return LG_ERR_INVALID;
    const lg_image_desc *rd = &p->radiance_desc;

    shp_job j;
    memset(&j, 0, sizeof j);
    j.bands = st->bands;
    j.nc = st->bands * st->bands;
    j.sampler = st->sampler;
    j.side = st->side;
    j.seed = st->seed;
    j.faces = p->info.layout == LG_PROBE_CUBE ? 6u : 1u;

    lg_cpu_view pv;
    int rc = lg_map_cpu(n, p->radiance, LG_READ, &pv);
    if (rc)
        return rc;
    j.img = lg_probe_image_at(p->info.layout, rd, pv.pixels, 0, p->info.rotation);

    /* quadrature: the probe's solid-angle table, or one computed alike; it must cover the
     * sphere (4 pi), else the sum would not be an integral */
    size_t texels = (size_t)j.faces * j.img.width * j.img.height;
    float *own_solid = NULL;
    double solid_sum = 0.0;
    if (st->sampler == SHP_QUADRATURE) {
        if (p->solid_angle) {
            lg_resource_info si;
            lg_cpu_view sv;
            if ((rc = lg_describe(p->solid_angle, &si, n)))
                return rc;
            if (si.buffer.size != texels * sizeof(float))
                return lg_error(n,
                                "input 'probe': its solid-angle table has %zu bytes, not "
                                "%zu (one float per texel of level 0)",
                                si.buffer.size, texels * sizeof(float));
            if ((rc = lg_map_cpu(n, p->solid_angle, LG_READ, &sv)))
                return rc;
            j.solid = sv.pixels;
        } else {
            own_solid = malloc(texels * sizeof(float));
            if (!own_solid)
                return lg_error_code(n, LG_ERR_NOMEM, "out of memory (%zu solid angles)", texels);
            if (lg_probe_solid_angles(p->info.layout, j.img.width, j.img.height, own_solid)) {
                free(own_solid);
                return lg_error(n, "input 'probe': no solid angles for its %ux%u image",
                                j.img.width, j.img.height);
            }
            j.solid = own_solid;
        }
        lg_sum s = { 0, 0 };
        for (size_t t = 0; t < texels; t++)
            lg_sum_add(&s, (double)j.solid[t]);
        solid_sum = lg_sum_value(&s);
        if (!(fabs(solid_sum - 4.0 * LG_PI) <= 1e-5 * 4.0 * LG_PI)) {
            free(own_solid);
            return lg_error(n,
                            "input 'probe': its texels' solid angles sum to %.9g sr, not "
                            "4 pi = %.9g: the quadrature would not integrate over the "
                            "sphere",
                            solid_sum, 4.0 * LG_PI);
        }
    }

    /* chunks: a function of the term count and the band count only (determinism) */
    uint64_t terms = st->sampler == SHP_QUADRATURE ? (uint64_t)texels
                                                   : (uint64_t)st->side * st->side;
    size_t per_slot = (size_t)3 * j.nc;
    size_t max_chunks = SHP_SLOT_SUMS / per_slot;
    if (max_chunks < 1)
        max_chunks = 1;
    uint64_t grain = SHP_GRAIN;
    if (terms / grain + 1 > max_chunks)
        grain = terms / max_chunks + 1;
    size_t chunks = lg_parallel_chunks((size_t)terms, (size_t)grain);
    j.slots = calloc(chunks * per_slot, sizeof *j.slots);
    j.failed = calloc(chunks ? chunks : 1, 1);
    if (!j.slots || !j.failed) {
        free(j.slots);
        free(j.failed);
        free(own_solid);
        return lg_error_code(n, LG_ERR_NOMEM,
                             "out of memory (%zu chunk sums of %u "
                             "coefficients)",
                             chunks, j.nc);
    }
    rc = lg_parallel_for(n, (size_t)terms, (size_t)grain, shp_chunk, &j);
    for (size_t c = 0; rc == 0 && c < chunks; c++)
        if (j.failed[c])
            rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory in chunk %zu", c);

    /* merge in chunk order, then scale */
    double *coef = rc ? NULL : calloc(per_slot, sizeof *coef);
    if (rc == 0 && !coef)
        rc = lg_error_code(n, LG_ERR_NOMEM, "out of memory");
    if (rc == 0) {
        double scale = st->sampler == SHP_QUADRATURE ? 1.0 : 4.0 * LG_PI / (double)terms;
        for (size_t i = 0; i < per_slot; i++) {
            lg_sum s = { 0, 0 };
            for (size_t c = 0; c < chunks; c++)
                lg_sum_merge(&s, &j.slots[c * per_slot + i]);
            coef[i] = lg_sum_value(&s) * scale;
        }
        if (st->window != SHP_WINDOW_NONE) {
            static const lg_sh_window_kind wk[] = { LG_SH_WINDOW_HANNING, LG_SH_WINDOW_HANNING,
                                                    LG_SH_WINDOW_LANCZOS, LG_SH_WINDOW_GAUSSIAN };
            for (int ch = 0; ch < 3; ch++)
                lg_sh_window(j.bands, wk[st->window], st->window_width, coef + ch * j.nc);
        }
    }
    free(j.slots);
    free(j.failed);
    free(own_solid);

    if (rc == 0) {
        for (size_t i = 0; i < per_slot; i++)
            if (!isfinite(coef[i]) || fabs(coef[i]) > 3.4e38) {
                rc = lg_error(n,
                              "coefficient %zu of channel %c is %g: the probe holds values a "
                              "float cannot carry (NaN, infinite or beyond 3.4e38)",
                              i % j.nc, "RGB"[i / j.nc], coef[i]);
                break;
            }
    }
    const lg_resource *out = rc ? NULL : lg_part(n, lg_output(n, 0), "coeffs");
    lg_cpu_view ov;
    if (rc == 0 && !out)
        rc = lg_error(n, "the output has no coeffs part");
    if (rc == 0 && (rc = lg_map_cpu(n, out, LG_WRITE, &ov)) == 0) {
        float *o = ov.pixels;
        for (size_t i = 0; i < per_slot; i++)
            o[i] = (float)coef[i];
        lg_sh_info info;
        memset(&info, 0, sizeof info);
        info.struct_size = sizeof info;
        info.bands = j.bands;
        info.flags = st->window != SHP_WINDOW_NONE ? LG_SH_WINDOWED : 0u;
        rc = lg_sh_publish(n, 0, &info);
    }
    free(coef);
    if (rc)
        return rc;

    double secs = shp_now() - t0;
    if (st->sampler == SHP_QUADRATURE)
        lg_log(n, LG_LOG_DEBUG,
               "%u bands by quadrature over %zu texels (%s %ux%u%s; solid "
               "angles sum to 4 pi %+.2e relative) in %.3f s on %u threads, "
               "%zu chunks",
               j.bands, texels,
               p->info.layout == LG_PROBE_CUBE      ? "cube"
               : p->info.layout == LG_PROBE_ANGULAR ? "angular"
                                                    : "lat-long",
               j.img.width, j.img.height, j.faces == 6 ? " per face" : "",
               solid_sum / (4.0 * LG_PI) - 1.0, secs, lg_cpu_workers(n), chunks);
    else
        lg_log(n, LG_LOG_DEBUG,
               "%u bands from %llu %s samples (%u x %u, seed %llu) in %.3f s "
               "(%.3g samples/s) on %u threads, %zu chunks",
               j.bands, (unsigned long long)terms, shp_samplers[st->sampler], st->side, st->side,
               (unsigned long long)st->seed, secs, secs > 0 ? (double)terms / secs : 0.0,
               lg_cpu_workers(n), chunks);
    return 0;
}

/* ---- sh_background: the lighting the coefficients reconstruct, seen -------------------------- */
/*
 * The seed's figure of the lighting reconstructed with 1, 3, 5 and 7 bands: the radiance
 * L_n(w) = sum over the first n bands of c_i Y_i(w) (the truncated SH series, no window
 * beyond what the input carries), per pixel of a render-size image, at the pixel centre's
 * direction. `view`:
 *   latlong  the whole sphere in the probe layout's lat-long convention
 *            (lightgraph/probe.h: u = 0.5 looks along -Z, the top row is +Y), so the
 *            picture lies beside the probe's own panorama;
 *   camera   through the active camera of the `scene` input (a pinhole: position,
 *            target, up, yfov, aspect or the image's), the background a renderer would
 *            draw from the coefficients.
 * Y is evaluated in double (lg_sh_eval_d) and summed in double; the pixels are floats. The
 * node runs once on the CPU (its result depends on no time and no camera but the scene's).
 */
enum { SHB_LATLONG = 0, SHB_CAMERA };
static const char *const shb_views[] = { "latlong", "camera", NULL };

static const lg_param_desc shb_params[] = {
    { .key = "bands",
      .type = LG_PARAM_INT,
      .def.i = 0,
      .min = 0,
      .max = LG_SH_MAX_BANDS,
      .doc = "the first n bands of the input reconstructed; 0: all it has" },
    { .key = "view",
      .type = LG_PARAM_ENUM,
      .def.e = SHB_LATLONG,
      .enum_values = shb_views,
      .doc = "latlong: the whole sphere (the probes' lat-long layout); camera: through the "
             "scene's active camera" },
};
static const lg_port_desc shb_inputs[] = {
    { .name = "sh", .kind = LG_KIND_SH, .doc = "the coefficients (sh_project's out)" },
    { .name = "scene",
      .kind = LG_KIND_SCENE,
      .optional = true,
      .doc = "view = camera: the scene whose active camera looks" },
};
static const lg_port_desc shb_outputs[] = {
    { .name = "out",
      .kind = LG_KIND_IMAGE,
      .doc = "rgba32f at the render size: the reconstructed radiance (linear; the ringing of "
             "a truncated series may be negative), alpha 1" },
};

static int shb_prepare(lg_node *n)
{
    if (lg_param_enum(n, "view") == SHB_CAMERA && !lg_input(n, 1))
        return lg_error(n, "view = camera needs the input 'scene' (its active camera looks); "
                           "connect one or use view = latlong");
    lg_image_desc d = { .format = LG_FORMAT_RGBA32F };
    lg_render_size(n, &d.width, &d.height);
    int rc = lg_declare_image(n, 0, &d);
    return rc ? rc : lg_set_device(n, LG_DEVICE_CPU);
}

/* The pinhole of camera c for a w x h image: the world direction through pixel (x, y). */
typedef struct shb_pinhole {
    double eye_fwd[3], right[3], up[3]; /* right and up scaled by the half extents */
} shb_pinhole;

static void shb_norm(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        for (int k = 0; k < 3; k++)
            v[k] /= l;
}

static void shb_cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static int shb_pinhole_make(lg_node *n, const lg_camera *c, uint32_t w, uint32_t h, shb_pinhole *p)
{
    double f[3], up[3] = { c->up[0], c->up[1], c->up[2] }, r[3], u[3];
    for (int k = 0; k < 3; k++)
        f[k] = (double)c->target[k] - (double)c->position[k];
    shb_norm(f);
    shb_norm(up);
    shb_cross(f, up, r);
    double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(rl > 1e-9) || !(c->yfov > 0) || !((double)c->yfov < LG_PI))
        return lg_error(n, "the active camera '%s' cannot look: %s", c->name ? c->name : "?",
                        !(rl > 1e-9) ? "its target is at its position or along its up vector"
                                     : "its vertical field of view is not in (0, 180) degrees");
    shb_norm(r);
    shb_cross(r, f, u);
    double ty = tan(0.5 * (double)c->yfov);
    double aspect = c->aspect > 0 ? (double)c->aspect : (double)w / (double)h;
    for (int k = 0; k < 3; k++) {
        p->eye_fwd[k] = f[k];
        p->right[k] = r[k] * ty * aspect;
        p->up[k] = u[k] * ty;
    }
    return 0;
}

static int shb_execute(lg_node *n, const lg_frame *frame)
{
    (void)frame;
    lg_sh shv;
    const lg_sh *sh = lg_sh_get(n, lg_input(n, 0), &shv);
    if (!sh)
        return lg_error(n, "input 'sh' holds no coefficients");
    uint32_t have = sh->info.bands, want = (uint32_t)lg_param_int(n, "bands");
    uint32_t nb = want ? want : have;
    if (nb > have)
        return lg_error(n,
                        "bands = %u, but the input 'sh' holds %u band%s: reconstruct at most "
                        "%u (or 0 for all)",
                        want, have, have == 1 ? "" : "s", have);
    int view = lg_param_enum(n, "view");
    lg_cpu_view cv, ov;
    int rc = lg_map_cpu(n, sh->coeffs, LG_READ, &cv);
    if (rc)
        return rc;
    /* the coefficients used, [3][nb^2], in double: a NaN or infinite one (a broken
     * producer) would spread to every pixel, so it counts as 0, with one warning */
    uint32_t nc = nb * nb, stride = have * have;
    double coef[3 * LG_SH_MAX_BANDS * LG_SH_MAX_BANDS];
    uint64_t bad = 0;
    for (int ch = 0; ch < 3; ch++)
        for (uint32_t k = 0; k < nc; k++) {
            float c = ((const float *)cv.pixels)[ch * stride + k];
            bad += !isfinite(c);
            coef[ch * nc + k] = isfinite(c) ? (double)c : 0.0;
        }
    if (bad)
        lg_log(n, LG_LOG_WARN, "input 'sh': %llu of %u coefficients NaN or infinite, taken as 0",
               (unsigned long long)bad, 3 * nc);
    lg_resource_info info;
    if ((rc = lg_describe(lg_output(n, 0), &info, n)))
        return rc;
    uint32_t w = info.image.width, h = info.image.height;
    shb_pinhole ph;
    if (view == SHB_CAMERA) {
        const lg_scene *s = lg_scene_get(n, lg_input(n, 1));
        if (!s)
            return LG_ERR_INVALID;
        if (s->camera >= s->n_cameras)
            return lg_error(n, "the scene's active camera %u is not one of its %u", s->camera,
                            s->n_cameras);
        if ((rc = shb_pinhole_make(n, &s->cameras[s->camera], w, h, &ph)))
            return rc;
    }
    if ((rc = lg_map_cpu(n, lg_output(n, 0), LG_WRITE, &ov)))
        return rc;
    double y[LG_SH_MAX_BANDS * LG_SH_MAX_BANDS];
    for (uint32_t j = 0; j < h; j++) {
        float *row = (float *)ov.pixels + (size_t)j * ov.row_pixels * 4;
        for (uint32_t i = 0; i < w; i++) {
            double u = (i + 0.5) / w, v = (j + 0.5) / h, d[3];
            if (view == SHB_LATLONG) {
                double phi = 2.0 * LG_PI * (u - 0.5), theta = LG_PI * v;
                d[0] = sin(theta) * sin(phi);
                d[1] = cos(theta);
                d[2] = -sin(theta) * cos(phi);
            } else {
                double a = 2.0 * u - 1.0, b = 1.0 - 2.0 * v;
                for (int k = 0; k < 3; k++)
                    d[k] = ph.eye_fwd[k] + a * ph.right[k] + b * ph.up[k];
                shb_norm(d);
            }
            lg_sh_eval_d(nb, d, y);
            for (int ch = 0; ch < 3; ch++) {
                double sum = 0;
                for (uint32_t k = 0; k < nc; k++)
                    sum += coef[ch * nc + k] * y[k];
                /* float coefficients near FLT_MAX can sum beyond a float: the largest one */
                row[4 * i + ch] = sum > FLT_MAX ? FLT_MAX : sum < -FLT_MAX ? -FLT_MAX : (float)sum;
            }
            row[4 * i + 3] = 1.0f;
        }
    }
    lg_log(n, LG_LOG_DEBUG, "%u of %u bands reconstructed at %ux%u (%s)", nb, have, w, h,
           shb_views[view]);
    return 0;
}

static const lg_node_type shp_types[] = {
    {
        .struct_size = sizeof(lg_node_type),
        .name = "sh_project",
        .doc = "A light probe's radiance projected onto n bands of real spherical harmonics "
               "(world directions, RGB), by per-texel quadrature or N x N samples",
        LG_PARAMS(shp_params),
        LG_INPUTS(shp_inputs),
        LG_OUTPUTS(shp_outputs),
        .create = shp_create,
        .prepare = shp_prepare,
        .execute = shp_execute,
        .destroy = shp_destroy,
    },
    {
        .struct_size = sizeof(lg_node_type),
        .name = "sh_background",
        .doc = "The lighting the SH coefficients reconstruct from their first n bands, as a "
               "lat-long panorama or through the scene's camera (the seed's 1/3/5/7-band "
               "figure)",
        LG_PARAMS(shb_params),
        LG_INPUTS(shb_inputs),
        LG_OUTPUTS(shb_outputs),
        .prepare = shb_prepare,
        .execute = shb_execute,
    },
};

LG_PLUGIN_DEFINE("sh_project", "1.1.0",
                 "Spherical-harmonic projection of a light probe (quadrature, jittered, "
                 "Hammersley, Sobol)",
                 shp_types)
