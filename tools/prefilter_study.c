/*
 * tools/prefilter_study.c: what GGX prefiltering costs and how accurate it is (issue 9:
 * "error and prefilter time for 16 .. 4096 samples per texel"). A benchmark, not a test:
 *
 *     make accuracy ONLY=probe      (tools/accuracy/sections/_prefilter.py runs it)
 *     build/tools/lg_prefilter_study --probe assets/probes/forest_1024x512.hdr \
 *         --face 128 --levels 5 --threads 2 --csv out/prefilter_study.csv
 *
 * The probe (lat-long) is box-downsampled by --down (default 4: 256 x 128), resampled
 * once into a cube of face --face (lg_probe_resample) and prefiltered from that cube
 * (plugins/ibl/ggx_prefilter.h; level 0 is then a copy, so the time is the filtering's)
 * into a chain of --levels levels (default 5: roughness 0, 0.25, 0.5, 0.75, 1), with 16, 32, ..., 4096 samples per texel, with and without source-lod
 * filtering (filtered importance sampling), and with the n.l Vis weighting
 * (LG_PROBE_WEIGHT_NOL_VIS, source lod), on a pool of --threads threads (the host's
 * pool, host/base/pool.c). For each run it measures the wall time and the error of the split
 * sum (lg_probe_ggx_split_sum, the formula `reflect` evaluates) against the Monte Carlo
 * oracle (lg_probe_ggx_reference, --oracle samples per direction, on the chain's level
 * 0) at fixed configurations: --dirs normals n (a fixed pseudo-random set), roughness
 * 0.1, 0.25, 0.5, 0.75 and 1, and three views: v = n ("n=v", where the split sum is exact
 * but for sampling), v at 45 degrees and v at 80 degrees from n ("grazing"). The error is
 * the relative RMS over directions and RGB: sqrt(sum (split - oracle)^2 / sum oracle^2).
 * The oracle's own noise (two seeds) is printed, so the floor is known.
 *
 * Output: one CSV row per (mode, samples, roughness, view) and a summary on stdout.
 * The accuracy atlas's probe section runs this as its Custom study
 * (tools/accuracy/sections/_prefilter.py: one row per mode and sample count, the error at
 * n = v over the roughnesses) into docs/accuracy.md#probe.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightgraph/image.h"
#include "lightgraph/probe.h"
#include "ggx_prefilter.h"
#include "base/pool.h"

static lg_pool *g_pool;

static uint32_t pool_workers(lg_node *n)
{
    (void)n;
    return lg_pool_size(g_pool);
}

static int pool_for(lg_node *n, size_t count, size_t grain,
                    void (*fn)(void *ctx, size_t begin, size_t end, uint32_t chunk), void *ctx)
{
    (void)n;
    return lg_pool_run(g_pool, count, grain, fn, ctx) ? LG_ERR_INVALID : 0;
}

static uint64_t rng_state = 0x2545f4914f6cdd1dull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

static lg_vec3 rnd_dir(void)
{
    double z = 2.0 * rnd() - 1.0, p = 2.0 * LG_PI * rnd(), s = sqrt(fmax(0.0, 1.0 - z * z));
    return lg_v3((float)(s * cos(p)), (float)(s * sin(p)), (float)z);
}

/* v at `deg` degrees from n, in a plane through n chosen per direction */
static lg_vec3 view_at(lg_vec3 n, double deg, uint32_t i)
{
    lg_vec3 a = fabsf(n.x) < 0.9f ? lg_v3(1, 0, 0) : lg_v3(0, 1, 0);
    lg_vec3 t = lg_v3_cross(n, a);
    t = lg_v3_scale(t, 1.0f / lg_v3_length(t));
    lg_vec3 b = lg_v3_cross(n, t);
    double ph = 2.0 * LG_PI * (i * 0.618033988749895);
    lg_vec3 tt = lg_v3_add(lg_v3_scale(t, (float)cos(ph)), lg_v3_scale(b, (float)sin(ph)));
    double r = deg * LG_PI / 180.0;
    return lg_v3_add(lg_v3_scale(n, (float)cos(r)), lg_v3_scale(tt, (float)sin(r)));
}

#define NR 5
#define NV 3
static const float roughs[NR] = { 0.1f, 0.25f, 0.5f, 0.75f, 1.0f };
static const double view_deg[NV] = { 0.0, 45.0, 80.0 };
static const char *view_name[NV] = { "n=v", "45deg", "grazing80" };

static void usage(void)
{
    fprintf(stderr, "usage: lg_prefilter_study [--probe FILE.hdr] [--down N] [--face N] "
                    "[--levels N] [--threads N] [--dirs N] [--oracle N] [--max-samples N] "
                    "[--csv FILE]\n");
}

int main(int argc, char **argv)
{
    const char *probe = "assets/probes/forest_1024x512.hdr", *csv_path = NULL;
    uint32_t down = 4, face = 128, levels = 5, threads = 2, ndirs = 32, oracle = 1u << 16;
    uint32_t max_samples = 4096;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (i + 1 >= argc) {
            usage();
            return 2;
        }
        const char *val = argv[++i];
        if (!strcmp(a, "--probe"))
            probe = val;
        else if (!strcmp(a, "--csv"))
            csv_path = val;
        else if (!strcmp(a, "--down"))
            down = (uint32_t)atoi(val);
        else if (!strcmp(a, "--face"))
            face = (uint32_t)atoi(val);
        else if (!strcmp(a, "--levels"))
            levels = (uint32_t)atoi(val);
        else if (!strcmp(a, "--threads"))
            threads = (uint32_t)atoi(val);
        else if (!strcmp(a, "--dirs"))
            ndirs = (uint32_t)atoi(val);
        else if (!strcmp(a, "--oracle"))
            oracle = (uint32_t)atoi(val);
        else if (!strcmp(a, "--max-samples"))
            max_samples = (uint32_t)atoi(val);
        else {
            usage();
            return 2;
        }
    }
    if (!down || !face || levels < 2 || levels > LG_PROBE_FILTER_MAX_LEVELS || !threads || !ndirs ||
        !oracle || max_samples < 16) {
        usage();
        return 2;
    }

    lg_image im;
    char err[256];
    if (lg_image_read(probe, LG_READ_RADIANCE, &im, NULL, err, sizeof err)) {
        fprintf(stderr, "lg_prefilter_study: %s: %s\n", probe, err);
        return 1;
    }
    uint32_t sw = im.width / down, sh = im.height / down;
    if (!sw || !sh) {
        fprintf(stderr, "lg_prefilter_study: %s: %ux%u is too small for --down %u\n", probe,
                im.width, im.height, down);
        return 1;
    }
    float *src = malloc(sizeof(float) * 4 * sw * sh);
    for (uint32_t y = 0; y < sh; y++)
        for (uint32_t x = 0; x < sw; x++)
            for (int c = 0; c < 4; c++) {
                double s = 0;
                for (uint32_t yy = 0; yy < down; yy++)
                    for (uint32_t xx = 0; xx < down; xx++)
                        s +=
                            im.pixels[4 * ((size_t)(y * down + yy) * im.width + x * down + xx) + c];
                src[4 * ((size_t)y * sw + x) + c] = (float)(s / (down * down));
            }
    lg_image_free(&im);
    lg_probe_image simg;
    memset(&simg, 0, sizeof simg);
    simg.layout = LG_PROBE_LATLONG;
    simg.width = sw;
    simg.height = sh;
    simg.rgba = src;

    g_pool = lg_pool_new(threads, NULL);
    lg_host_api api;
    memset(&api, 0, sizeof api);
    api.struct_size = sizeof api;
    api.cpu_workers = pool_workers;
    api.parallel_for = pool_for;
    lg_node node;
    memset(&node, 0, sizeof node);
    node.host = &api;
    node.name = "prefilter_study";

    lg_image_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.width = desc.height = face;
    desc.format = LG_FORMAT_RGBA32F;
    desc.flags = LG_IMAGE_CUBE;
    desc.levels = levels;
    size_t nfl = 4 * lg_image_offset(&desc, levels, 0);
    float *chain = malloc(sizeof(float) * nfl);
    lg_probe_image lv[LG_PROBE_FILTER_MAX_LEVELS];
    for (uint32_t l = 0; l < levels; l++)
        lv[l] = lg_probe_image_at(LG_PROBE_CUBE, &desc, chain, l, NULL);

    /* the oracle on level 0 (any run's level 0: the same resampling) */
    lg_probe_prefilter_opts o;
    memset(&o, 0, sizeof o);
    o.samples = 16;
    if (lg_probe_prefilter_ggx(&node, &simg, LG_PROBE_CUBE, face, face, 1, &o, chain, NULL)) {
        fprintf(stderr, "lg_prefilter_study: prefiltering failed\n");
        return 1;
    }
    /* every run starts from this cube (level 0 is then a copy): the times measure the
     * filtering alone, not the lat-long -> cube resampling */
    float *cube0 = malloc(sizeof(float) * 4 * 6 * (size_t)face * face);
    memcpy(cube0, chain, sizeof(float) * 4 * 6 * (size_t)face * face);
    lg_probe_image cimg;
    memset(&cimg, 0, sizeof cimg);
    cimg.layout = LG_PROBE_CUBE;
    cimg.width = cimg.height = face;
    cimg.rgba = cube0;
    lg_vec3 *n = malloc(sizeof *n * ndirs);
    double *ref = malloc(sizeof(double) * 3 * ndirs * NR * NV);
    double noise[NR][NV];
    for (uint32_t i = 0; i < ndirs; i++)
        n[i] = rnd_dir();
    printf("probe %s %ux%u -> cube face %u, %u levels (roughness step %.3f), %u threads; "
           "oracle %u samples per direction, %u normals\n",
           probe, sw, sh, face, levels, 1.0 / (levels - 1), threads, oracle, ndirs);
    for (int r = 0; r < NR; r++)
        for (int v = 0; v < NV; v++) {
            double num = 0, den = 0;
            for (uint32_t i = 0; i < ndirs; i++) {
                lg_vec3 vv = view_at(n[i], view_deg[v], i);
                double *o1 = ref + 3 * ((size_t)(r * NV + v) * ndirs + i), o2[3];
                lg_probe_ggx_reference(&lv[0], n[i], vv, roughs[r], NULL, oracle, 1, o1);
                lg_probe_ggx_reference(&lv[0], n[i], vv, roughs[r], NULL, oracle, 2, o2);
                for (int c = 0; c < 3; c++) {
                    num += (o1[c] - o2[c]) * (o1[c] - o2[c]);
                    den += o1[c] * o1[c];
                }
            }
            /* two independent estimates differ by sqrt(2) times one's error */
            noise[r][v] = sqrt(num / den) / sqrt(2.0);
        }
    printf("oracle noise (relative RMS of one estimate, from two seeds):\n");
    for (int r = 0; r < NR; r++)
        printf("  roughness %.2f: n=v %.1e, 45deg %.1e, grazing %.1e\n", roughs[r], noise[r][0],
               noise[r][1], noise[r][2]);

    FILE *csv = csv_path ? fopen(csv_path, "w") : NULL;
    if (csv_path && !csv) {
        fprintf(stderr, "lg_prefilter_study: cannot write %s\n", csv_path);
        return 1;
    }
    if (csv)
        fprintf(csv, "mode,samples,seconds,threads,roughness,view,rel_rms_error,oracle_noise\n");
    printf("\n%-14s %7s %9s", "mode", "samples", "seconds");
    for (int r = 0; r < NR; r++)
        printf("   r=%.2f n=v", roughs[r]);
    printf("\n");
    double bias[NR][NV];
    static const char *mode_name[3] = { "source-lod", "no-source-lod", "source-lod-vis" };
    double bias_vis[NR][NV];
    for (int mode = 0; mode < 3; mode++) {
        for (uint32_t s = 16; s <= max_samples; s *= 2) {
            lg_probe_prefilter_stats st;
            memset(&o, 0, sizeof o);
            o.samples = s;
            o.no_source_lod = mode == 1;
            o.weighting = mode == 2 ? LG_PROBE_WEIGHT_NOL_VIS : LG_PROBE_WEIGHT_NOL;
            if (lg_probe_prefilter_ggx(&node, &cimg, LG_PROBE_CUBE, face, face, levels, &o, chain,
                                       &st)) {
                fprintf(stderr, "lg_prefilter_study: prefiltering failed\n");
                return 1;
            }
            printf("%-14s %7u %9.3f", mode_name[mode], s, st.seconds);
            for (int r = 0; r < NR; r++)
                for (int v = 0; v < NV; v++) {
                    double num = 0, den = 0;
                    for (uint32_t i = 0; i < ndirs; i++) {
                        lg_vec3 vv = view_at(n[i], view_deg[v], i);
                        float ss[3];
                        lg_probe_ggx_split_sum(lv, levels, n[i], vv, roughs[r], NULL, ss);
                        const double *o1 = ref + 3 * ((size_t)(r * NV + v) * ndirs + i);
                        for (int c = 0; c < 3; c++) {
                            num += (ss[c] - o1[c]) * (ss[c] - o1[c]);
                            den += o1[c] * o1[c];
                        }
                    }
                    double e = sqrt(num / den);
                    if (v == 0)
                        printf("   %10.3e", e);
                    if (mode == 0 && s == max_samples)
                        bias[r][v] = e;
                    if (mode == 2 && s == max_samples)
                        bias_vis[r][v] = e;
                    if (csv)
                        fprintf(csv, "%s,%u,%.6f,%u,%.2f,%s,%.6e,%.3e\n", mode_name[mode], s,
                                st.seconds, st.threads, roughs[r], view_name[v], e, noise[r][v]);
                }
            printf("\n");
        }
    }
    printf("\nsplit-sum error at %u samples (source lod) by view: the approximation's price\n",
           max_samples);
    printf("%-10s %10s %10s %10s   %10s %10s %10s (n.l Vis weighting)\n", "roughness", "n=v",
           "45deg", "grazing80", "n=v", "45deg", "grazing80");
    for (int r = 0; r < NR; r++)
        printf("%-10.2f %10.3e %10.3e %10.3e   %10.3e %10.3e %10.3e\n", roughs[r], bias[r][0],
               bias[r][1], bias[r][2], bias_vis[r][0], bias_vis[r][1], bias_vis[r][2]);
    if (csv)
        fclose(csv);
    lg_pool_free(g_pool);
    free(n);
    free(ref);
    free(chain);
    free(cube0);
    free(src);
    return 0;
}
