/*
 * lg_bench_froxel_roofline: how close the volumetric_froxel node comes to the memory
 * bandwidth of this machine, measured in one run (issue 11, task F;
 * plugins/volumetric_froxel/README.md has the figures).
 *
 *   lg_bench_froxel_roofline [--size WxH] [--grid WxHxD] [--frames N]
 *                            [--backends cpu,cl,gl] [--lights 1,8,32] [--temporal]
 *                            [--triad-mib M] [--type directional|point|spot]
 *                            [--integration sample|analytic] [--unshadowed]
 *
 * Defaults: 640x360, the thesis grid 190x90x128, 6 frames, cpu,cl,gl, 1, 8 and 32 lights,
 * no temporal, a 256 MiB triad.
 *
 * The node runs through the host (lg_render_file, in this process) on the bunny box of
 * examples/volumetric_scene.lgraph with `per_frame = true`: with n lights, the sun and n - 1
 * more directional lights (light nodes, fanned around the sun's direction), all shadowed
 * by one shadowmap node (256 x 256 per light). --type point or spot (issue 25: the light
 * pass's floor, plugins/volumetric_froxel/README.md "The light pass's floor"): n point or
 * spot lights instead, spread inside the box (the spots aimed at the bunny), with the
 * node's point_integration (--integration), unshadowed; --unshadowed: no shadow maps for
 * directional lights either. The ns per froxel-light column is ms / (W H D lights). The
 * time is the node's wall time per frame
 * in steady state (the mean of frames 2 .. N, as `lightgraph sweep --time` reports; the
 * host waits for the node's GL or CL work before stopping the clock).
 *
 * Bytes that must be touched per frame (what is counted, nothing else):
 *   S write        W x H x D x 16   (rgba32f: the lookup and the history need it)
 *   grid write     W x H x D x 16   (the node's output)
 *   shadow atlas   per shadowed light, min(res^2, W x H x D) x 4: its tile read once
 *   lookup         per pixel: base rgba32f + depth read (20), out rgba32f + depth and
 *                  inscatter rgba32f written (36), two bilinear taps of S and grid (free:
 *                  those bytes are counted above)
 *   temporal       + W x H x D x 16 (the history read)
 * GB/s = bytes / time; the fraction is against the STREAM triad (tools/bench_triad.h)
 * through the host's pool, measured before the runs.
 *
 * Prints a table on stderr and one JSON object on stdout. Exit status 0, or 1 with a
 * message; a backend whose run fails is reported ("skipped") and the rest go on.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench_triad.h"
#include "cli/commands.h"
#include "base/pool.h"
#include "base/util.h"
#include "lightgraph/vecmath.h"

#ifndef LG_FROXEL_BENCH_EXAMPLES
#error "LG_FROXEL_BENCH_EXAMPLES (the examples folder) must be defined by the build"
#endif

static int usage(void)
{
    fprintf(stderr, "usage: lg_bench_froxel_roofline [--size WxH] [--grid WxHxD] [--frames N]\n"
                    "         [--backends cpu,cl,gl] [--lights 1,8,32] [--temporal]\n"
                    "         [--triad-mib M] [--type directional|point|spot]\n"
                    "         [--integration sample|analytic] [--unshadowed]\n");
    return 2;
}

/* The light set of --type point or spot: `lights` lights on a ring inside the box. */
static void write_local_lights(FILE *f, const char *type, int lights, const char *integration,
                               const char *backend, const uint32_t grid[3], bool temporal)
{
    const char *prev = "fog";
    char name[32], prevbuf[32];
    for (int l = 0; l < lights; l++) {
        double a = 2.0 * LG_PI * l / lights;
        snprintf(name, sizeof name, "p%d", l);
        fprintf(f,
                "%s = light { scene = %s, mode = %s, type = %s, position = [%.4f, 0.9, %.4f], "
                "intensity = 1%s }\n",
                name, prev, l ? "add" : "replace", type, -0.2 + 0.5 * cos(a), -0.6 + 0.5 * sin(a),
                strcmp(type, "spot") == 0
                    ? ", aim = target, target = [-0.2, 0.3, -0.8], outer_cone_deg = 40"
                    : "");
        snprintf(prevbuf, sizeof prevbuf, "%s", name);
        prev = prevbuf;
    }
    fprintf(f,
            "vol = volumetric_froxel { scene = %s, base = lit, backend = %s,\n"
            "    width = %u, height = %u, depth = %u, slicing = exponential, per_frame = true,\n"
            "    temporal = %s, point_integration = %s }\n"
            "output vol \"out.exr\"\n",
            prev, backend, grid[0], grid[1], grid[2], temporal ? "true" : "false", integration);
}

/* Writes the graph for `lights` lights and `backend` into path; 0 or 1. */
static int write_graph(const char *path, const char *backend, int lights, const uint32_t grid[3],
                       bool temporal, const char *type, const char *integration, bool unshadowed)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "lg_bench_froxel_roofline: cannot write %s\n", path);
        return 1;
    }
    fprintf(f, "lightgraph 1\ninclude \"%s/volumetric_scene.lgraph\"\n", LG_FROXEL_BENCH_EXAMPLES);
    if (strcmp(type, "directional") != 0) {
        write_local_lights(f, type, lights, integration, backend, grid, temporal);
        fclose(f);
        return 0;
    }
    const char *prev = "fog";
    char name[32], prevbuf[32];
    for (int l = 1; l < lights; l++) {
        /* fanned around the sun's [0.3, -0.35, 1]: all shine into the box */
        double a = 2.0 * LG_PI * l / (lights - 1);
        snprintf(name, sizeof name, "l%d", l);
        fprintf(f, "%s = light { scene = %s, direction = [%.4f, %.4f, 1], intensity = 1 }\n", name,
                prev, 0.3 + 0.25 * cos(a), -0.35 + 0.2 * sin(a));
        snprintf(prevbuf, sizeof prevbuf, "%s", name);
        prev = prevbuf;
    }
    fprintf(f, "shadows = shadowmap { scene = %s, resolution = 256 }\n", prev);
    fprintf(f,
            "vol = volumetric_froxel { scene = %s, base = lit, %s backend = %s,\n"
            "    width = %u, height = %u, depth = %u, slicing = exponential, per_frame = true,\n"
            "    temporal = %s }\n"
            "output vol \"out.exr\"\n",
            prev, unshadowed ? "" : "shadows = shadows,", backend, grid[0], grid[1], grid[2],
            temporal ? "true" : "false");
    fclose(f);
    return 0;
}

int main(int argc, char **argv)
{
    const char *backends = "cpu,cl,gl", *lights_s = "1,8,32", *type = "directional",
               *integration = "analytic";
    bool unshadowed = false;
    uint32_t size[2] = { 640, 360 }, grid[3] = { 190, 90, 128 };
    long frames = 6, triad_mib = 256;
    bool temporal = false;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--temporal") == 0) {
            temporal = true;
            continue;
        }
        if (strcmp(a, "--unshadowed") == 0) {
            unshadowed = true;
            continue;
        }
        if (!val)
            return usage();
        i++;
        char *end;
        if (strcmp(a, "--backends") == 0)
            backends = val;
        else if (strcmp(a, "--type") == 0) {
            type = val;
            if (strcmp(type, "directional") && strcmp(type, "point") && strcmp(type, "spot"))
                return usage();
        } else if (strcmp(a, "--integration") == 0) {
            integration = val;
            if (strcmp(integration, "sample") && strcmp(integration, "analytic"))
                return usage();
        } else if (strcmp(a, "--lights") == 0)
            lights_s = val;
        else if (strcmp(a, "--size") == 0) {
            if (sscanf(val, "%ux%u", &size[0], &size[1]) != 2 || !size[0] || !size[1] ||
                size[0] > 8192 || size[1] > 8192)
                return usage();
        } else if (strcmp(a, "--grid") == 0) {
            if (sscanf(val, "%ux%ux%u", &grid[0], &grid[1], &grid[2]) != 3)
                return usage();
        } else if (strcmp(a, "--frames") == 0) {
            frames = strtol(val, &end, 10);
            if (*end || frames < 2 || frames > 1000)
                return usage();
        } else if (strcmp(a, "--triad-mib") == 0) {
            triad_mib = strtol(val, &end, 10);
            if (*end || triad_mib < 1 || triad_mib > 4096)
                return usage();
        } else
            return usage();
    }

    char *warning = NULL;
    lg_pool *pool = lg_pool_global(&warning);
    if (warning) {
        fprintf(stderr, "lg_bench_froxel_roofline: %s\n", warning);
        free(warning);
    }
    if (!pool) {
        fprintf(stderr, "lg_bench_froxel_roofline: no thread pool\n");
        return 1;
    }
    double triad_gbs = 0, triad_ms = 0;
    if (lg_bench_triad(pool, (size_t)triad_mib, 5, "lg_bench_froxel_roofline", &triad_gbs,
                       &triad_ms))
        return 1;

    char dir[] = "/tmp/lg_bench_froxel_XXXXXX";
    if (!mkdtemp(dir)) {
        fprintf(stderr, "lg_bench_froxel_roofline: cannot make a temporary folder\n");
        return 1;
    }
    char graph[sizeof dir + 32], out[sizeof dir + 32];
    snprintf(graph, sizeof graph, "%s/bench.lgraph", dir);
    snprintf(out, sizeof out, "%s/out.exr", dir);

    lg_registry reg = { 0 };
    lg_registry_scan(&reg);

    double vox = (double)grid[0] * grid[1] * grid[2];
    double pix = (double)size[0] * size[1];
    fprintf(stderr,
            "triad %.2f GB/s (best of 5, %ld MiB x 3); %ux%u, grid %ux%ux%u (%.2f M "
            "froxels), %s, %ld frames\n",
            triad_gbs, triad_mib, size[0], size[1], grid[0], grid[1], grid[2], vox * 1e-6,
            temporal ? "temporal" : "not temporal", frames);
    bool local = strcmp(type, "directional") != 0;
    fprintf(stderr, "lights: %s%s%s\n", type,
            local        ? (strcmp(integration, "analytic") ? " (sample)" : " (analytic)")
            : unshadowed ? ", unshadowed"
                         : ", shadowed",
            local ? ", unshadowed" : "");
    fprintf(stderr, "%-8s %6s %10s %10s %10s %8s %8s %10s\n", "backend", "lights", "ms/frame",
            "ns/froxel", "ns/fx-lt", "MB", "GB/s", "% triad");
    printf("{\"triad_gbs\": %.3f, \"size\": [%u, %u], \"grid\": [%u, %u, %u], \"temporal\": %s, "
           "\"type\": \"%s\", \"integration\": \"%s\", \"shadowed\": %s, \"rows\": [",
           triad_gbs, size[0], size[1], grid[0], grid[1], grid[2], temporal ? "true" : "false",
           type, integration, local || unshadowed ? "false" : "true");
    int rows = 0, status = 0;
    char *bl = lg_xstrdup(backends);
    for (char *s1 = NULL, *b = strtok_r(bl, ",", &s1); b; b = strtok_r(NULL, ",", &s1)) {
        char *ll = lg_xstrdup(lights_s);
        for (char *s2 = NULL, *lt = strtok_r(ll, ",", &s2); lt; lt = strtok_r(NULL, ",", &s2)) {
            int lights = atoi(lt);
            if (lights < 1 || lights > 32) {
                fprintf(stderr, "lg_bench_froxel_roofline: --lights: %s is not in 1..32\n", lt);
                status = 2;
                continue;
            }
            if (write_graph(graph, b, lights, grid, temporal, type, integration, unshadowed)) {
                status = 1;
                continue;
            }
            lg_exec_opts o = { .width = size[0],
                               .height = size[1],
                               .frames = (uint32_t)frames,
                               .dt = 1.0 / 60.0,
                               .gl_backend = "osmesa",
                               .output_override = out,
                               .graph_path = graph };
            lg_run_result res = { 0 };
            int rc = lg_render_file(&reg, graph, NULL, 0, &o, "vol", &res);
            double bytes = 2.0 * vox * 16 + pix * (20 + 36) + (temporal ? vox * 16 : 0) +
                           (local || unshadowed ? 0 : lights * fmin(256.0 * 256.0, vox) * 4);
            printf("%s{\"backend\": \"%s\", \"lights\": %d", rows++ ? ", " : "", b, lights);
            if (rc || !res.node_found) {
                fprintf(stderr, "%-8s %6d skipped (the render failed, above)\n", b, lights);
                printf(", \"skipped\": \"render failed\"}");
                continue;
            }
            double gbs = bytes / (res.node_ms * 1e-3) * 1e-9;
            fprintf(stderr, "%-8s %6d %10.1f %10.2f %10.2f %8.1f %8.2f %9.1f%%\n", b, lights,
                    res.node_ms, res.node_ms * 1e6 / vox, res.node_ms * 1e6 / (vox * lights),
                    bytes * 1e-6, gbs, 100.0 * gbs / triad_gbs);
            printf(", \"ms\": %.3f, \"bytes\": %.0f, \"gbs\": %.3f, \"triad_fraction\": %.4f}",
                   res.node_ms, bytes, gbs, gbs / triad_gbs);
        }
        free(ll);
    }
    free(bl);
    printf("]}\n");
    unlink(graph);
    unlink(out);
    rmdir(dir);
    lg_registry_free(&reg);
    return status;
}
