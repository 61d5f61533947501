/*
 * lg_bench_scene_load: loads glTF files with the `gltf` node's loader (no host, no
 * plugin loading) and prints, per file, what was loaded, the load time and the process's
 * peak resident memory. tools/bench_scene_load.py runs it once per file (a fresh process
 * each, so that the peak belongs to that file) and writes the table of
 * plugins/scene_gltf/README.md.
 *
 *     lg_bench_scene_load [--repeat N] [--normals auto|smooth|flat] FILE
 *
 * Output, one line: key=value pairs (file, triangles, vertices, meshes, instances,
 * mesh_mb, best_ms, median_ms, rss_before_mb, peak_rss_mb).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "gltf_load.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double peak_rss_mb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_maxrss / 1024.0; /* kilobytes on Linux */
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    int repeat = 1;
    const char *file = NULL;
    lg_gltf_options opt = lg_gltf_default_options();
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--repeat") && i + 1 < argc) {
            repeat = atoi(argv[++i]);
        } else if (!strcmp(argv[i], "--normals") && i + 1 < argc) {
            const char *v = argv[++i];
            opt.normals = !strcmp(v, "flat")     ? LG_GLTF_NORMALS_FLAT
                          : !strcmp(v, "smooth") ? LG_GLTF_NORMALS_SMOOTH
                                                 : LG_GLTF_NORMALS_AUTO;
        } else if (argv[i][0] != '-' && !file) {
            file = argv[i];
        } else {
            file = NULL;
            break;
        }
    }
    if (!file || repeat < 1 || repeat > 1000) {
        fprintf(stderr,
                "usage: lg_bench_scene_load [--repeat N] [--normals auto|smooth|flat] FILE\n");
        return 2;
    }
    double before = peak_rss_mb();
    double *times = calloc((size_t)repeat, sizeof *times);
    if (!times)
        return 1;
    lg_scene *s = NULL;
    for (int r = 0; r < repeat; r++) {
        char err[1024];
        double t0 = now();
        int rc = lg_gltf_load(file, &opt, &s, NULL, err, sizeof err);
        times[r] = now() - t0;
        if (rc) {
            fprintf(stderr, "%s\n", err);
            free(times);
            return 1;
        }
        if (r + 1 < repeat)
            lg_gltf_scene_free(s);
    }
    double mb = 0;
    for (uint32_t i = 0; i < s->n_meshes; i++) {
        const lg_mesh *m = &s->meshes[i];
        mb += (double)m->n_vertices * (m->texcoords ? 32 : 24) + (double)m->n_indices * 4;
    }
    qsort(times, (size_t)repeat, sizeof *times, cmp_double);
    printf("file=%s triangles=%llu vertices=%llu meshes=%u instances=%u mesh_mb=%.1f best_ms=%.1f "
           "median_ms=%.1f rss_before_mb=%.1f peak_rss_mb=%.1f\n",
           file, (unsigned long long)s->features.triangles,
           (unsigned long long)s->features.vertices, s->n_meshes, s->n_instances, mb / 1048576.0,
           times[0] * 1e3, times[repeat / 2] * 1e3, before, peak_rss_mb());
    lg_gltf_scene_free(s);
    free(times);
    return 0;
}
