/* lightgraph: the host program. Each command lives in host/cmd_*.c. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/pool.h"
#include "cli/commands.h"
#include "exec/dist.h"
#include "lightgraph/image.h"

/* --max-pixels N (or =N), accepted anywhere on the command line and taken out of argv before
 * the command parses its own options: the pixel limit of every image read (render's image
 * nodes, diff, sweep), of check, of --size and of every image a node declares. Returns 0,
 * or 2 after a message. */
static int take_max_pixels(int *argc, char **argv)
{
    for (int i = 1; i < *argc;) {
        const char *a = argv[i], *v = NULL;
        int used = 1;
        if (strcmp(a, "--max-pixels") == 0) {
            v = i + 1 < *argc ? argv[i + 1] : NULL;
            used = 2;
            if (!v) {
                fprintf(stderr, "lightgraph: --max-pixels needs a number of pixels\n");
                return 2;
            }
        } else if (strncmp(a, "--max-pixels=", 13) == 0) {
            v = a + 13;
        } else {
            i++;
            continue;
        }
        char *end = NULL;
        errno = 0;
        unsigned long long n = strtoull(v, &end, 10);
        if (errno || !end || *end || v[0] == '-' || v[0] == 0 || n == 0) {
            fprintf(stderr,
                    "lightgraph: --max-pixels '%s': expected a positive whole number of "
                    "pixels (default %llu)\n",
                    v, LG_IMAGE_MAX_PIXELS_DEFAULT);
            return 2;
        }
        lg_image_set_max_pixels(n);
        memmove(argv + i, argv + i + used, (size_t)(*argc - i - used + 1) * sizeof *argv);
        *argc -= used;
    }
    return 0;
}

static void help(FILE *f)
{
    fprintf(f,
            "lightgraph %s (plugin ABI %d.%d): a plugin-based real-time renderer\n"
            "\n"
            "usage:\n"
            "  lightgraph render GRAPH [-o OUT] [--set NODE.PARAM=VALUE]... [--size WxH]\n"
            "                    [--frames N] [--every-frame[=NODE,...]] [--dt SECONDS]\n"
            "                    [--gl osmesa|egl] [--explain] [--profile]\n"
            "                    [--profile-json FILE] [--no-cache] [-v|-q]\n"
            "                    (--every-frame: nodes whose inputs do not change run every\n"
            "                    frame too (all, or the named ones), to time them; the\n"
            "                    profile's first_cpu_ms and min_cpu_ms then tell set-up from\n"
            "                    steady state; --no-cache: the on-disk cache is neither\n"
            "                    read nor written, as sweep and tune always run)\n"
            "  lightgraph view GRAPH [--set N.P=V]... [--show NODE.PORT] [--size WxH]\n"
            "                  [--script FILE]        the graph in a window: camera, live\n"
            "                  parameters, method switching, hot reload (docs/viewer.md)\n"
            "  lightgraph check GRAPH [--set ...]     check a graph against the plugins\n"
            "  lightgraph fmt GRAPH [-i]              print (or rewrite) it canonically\n"
            "  lightgraph dot GRAPH                   Graphviz text of the graph\n"
            "  lightgraph plugins [--json]            every node type, ports, parameters\n"
            "  lightgraph inspect NODE_TYPE [--json]  one node type\n"
            "  lightgraph diff A B [--heatmap OUT] [--json] [--max-rmse X] [--max-abs X]\n"
            "  lightgraph sweep GRAPH --vary NODE.PARAM=v1,v2,... [--reference REF_GRAPH]\n"
            "                   [--ref-set N.P=V]... [--set N.P=V]... [--time NODE]\n"
            "                   [--repeat N] [--size WxH] [-o DIR]   error against time\n"
            "  lightgraph tune GRAPH --node N --target-error E [--metric M] [--vary P=RANGE]...\n"
            "                  [--reference REF | --ref-set N.P=V ...] [--set N.P=V]...\n"
            "                  [--size WxH] [--frames N] [--repeat N] [--max-renders N] [-o DIR]\n"
            "                  the cheapest settings of node N within error E (docs/tune.md)\n"
            "  lightgraph devices [gl] [cl] [--gl osmesa|egl]  can the devices be made here?\n"
            "                   (exit 0: all named ones (default: both) can; 1: one cannot)\n"
            "  lightgraph conform PLUGIN.so [--json] [--quick] [-v]  check one plugin's\n"
            "                   contracts: descriptor, runs on synthetic inputs on every\n"
            "                   backend, backends agree, hostile input, lifecycle, memory,\n"
            "                   GL state, gating (docs/conform.md; exit 1 names the node,\n"
            "                   the check and the values)\n"
            "  lightgraph --version | help\n"
            "  mpirun -np N lightgraph render|sweep|tune ...  the same command over N MPI\n"
            "                   ranks: the work nodes share through lg_shard is spread,\n"
            "                   rank 0 prints and writes (docs/distributed.md)\n"
            "\n"
            "option of every command: --max-pixels N  the largest image read or made, in\n"
            "  pixels (default %llu; also LIGHTGRAPH_MAX_PIXELS=N; docs/images.md)\n"
            "exit status: 0 success, 1 failure while running, 2 bad usage or bad graph,\n"
            "  3 a plugin crashed in render or sweep (the message names the node, its type,\n"
            "  its plugin's file and the signal; no output file is written)\n"
            "environment: LIGHTGRAPH_PLUGIN_PATH (plugin folders, ':'-separated, searched\n"
            "  before the program's own: in each, the lg_*.so files in it and in its\n"
            "  immediate subfolders, not deeper; a plugin whose name or node type name one\n"
            "  found before it has is refused, lightgraph's own plugins first; docs/sdk.md\n"
            "  \"Names\"), LIGHTGRAPH_CACHE_DIR (the on-disk cache; default\n"
            "  $XDG_CACHE_HOME/lightgraph, ~/.cache/lightgraph, else a private\n"
            "  $TMPDIR/lightgraph-cache-UID made 0700; a folder others can write is refused),\n"
            "  LIGHTGRAPH_MAX_PIXELS=N (largest image read or made; default 134217728, as\n"
            "  --max-pixels N), LIGHTGRAPH_SCAN_TIMEOUT=S (seconds a plugin scan may take;\n"
            "  default 5),\n"
            "  LIGHTGRAPH_NO_DLCLOSE=1 (keep plugins mapped at exit, for leak checkers),\n"
            "  LIGHTGRAPH_THREADS=N (threads of the CPU pool that cpu backends share, 1..256;\n"
            "  default one per online CPU, divided among the ranks mpirun starts on one\n"
            "  machine), LIGHTGRAPH_TEST_FREE_BYTES=N (a test hook: the\n"
            "  free bytes sweep assumes its output directory has)\n"
            "docs: docs/graph-format.md, docs/images.md, docs/sdk.md, docs/conform.md,\n"
            "  docs/fuzzing.md, docs/distributed.md\n",
            LG_VERSION_STRING, LG_ABI_MAJOR, LG_ABI_MINOR, LG_IMAGE_MAX_PIXELS_DEFAULT);
}

/* The process's environment is decided here, before anything else runs, and never written
 * again: once a thread exists (the CPU pool, PoCL's and llvmpipe's workers), setenv() may move
 * `environ` while another thread's getenv() walks it, a crash we had (issue 20). Everything
 * that needs an environment variable set for a library reads it from here.
 * tests/unit/env checks the rule: no other setenv/putenv/unsetenv in host/, sdk/src or
 * plugins/, and a render of the cl-then-GL path under an interposer that aborts on an
 * environment write after the first thread. */
static void env_defaults(void)
{
    /* Mesa 22.3's OSMesa picks its gallium driver from GALLIUM_DRIVER, trying zink first
     * when it is unset; llvmpipe is the one with GL 4.5 here. A user's choice wins. It
     * touches only software rendering: a hardware EGL or GLX driver is chosen by device. */
    if (!getenv("GALLIUM_DRIVER"))
        setenv("GALLIUM_DRIVER", "llvmpipe", 0);
    /* PoCL writes the environment itself whenever its CPU device starts:
     * setenv("HWLOC_PLUGINS_PATH", "/dev/null", 1) before hwloc's topology (so that hwloc's
     * OpenCL plugin does not load PoCL again), by then on a process with the pool's and
     * llvmpipe's threads. A variable that does not exist yet makes glibc grow `environ`
     * (realloc) under their getenv; one that exists only has its entry's pointer replaced,
     * and the old string stays valid. So it is made to exist here, with the value PoCL
     * forces anyway: its later write changes nothing that a reader can trip on. */
    setenv("HWLOC_PLUGINS_PATH", "/dev/null", 1);
}

/* LIGHTGRAPH_TEST_FREE_BYTES: the test hook of util.h (lg_test_free_bytes), read here once
 * while the process has one thread. */
static void take_test_free_bytes(void)
{
    const char *v = getenv("LIGHTGRAPH_TEST_FREE_BYTES");
    if (!v)
        return;
    char *end = NULL;
    errno = 0;
    unsigned long long n = strtoull(v, &end, 10);
    if (errno || !end || *end || v[0] < '0' || v[0] > '9' || n > INT64_MAX) {
        fprintf(stderr,
                "lightgraph: warning: LIGHTGRAPH_TEST_FREE_BYTES='%s' is not a byte "
                "count; ignored\n",
                v);
        return;
    }
    lg_test_free_bytes = (int64_t)n;
}

/* The command named by argv[1]; its exit status. */
static int run_command(int argc, char **argv)
{
    if (take_max_pixels(&argc, argv))
        return 2;
    if (argc < 2) {
        help(stderr);
        return 2;
    }
    const char *cmd = argv[1];
    static const struct {
        const char *name;
        int (*fn)(int, char **);
    } cmds[] = {
        { "render", lg_cmd_render }, { "check", lg_cmd_check },     { "fmt", lg_cmd_fmt },
        { "dot", lg_cmd_dot },       { "plugins", lg_cmd_plugins }, { "inspect", lg_cmd_inspect },
        { "diff", lg_cmd_diff },     { "sweep", lg_cmd_sweep },     { "devices", lg_cmd_devices },
        { "tune", lg_cmd_tune },     { "view", lg_cmd_view },       { "conform", lg_cmd_conform },
    };
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        if (strcmp(cmd, cmds[i].name) == 0)
            return cmds[i].fn(argc - 1, argv + 1);
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("lightgraph %s (plugin ABI %d.%d)\n", LG_VERSION_STRING, LG_ABI_MAJOR, LG_ABI_MINOR);
        return 0;
    }
    if (strcmp(cmd, "help") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
        help(stdout);
        return 0;
    }
    const char *names[] = { "render", "check",   "fmt",  "dot",     "plugins", "inspect", "diff",
                            "sweep",  "devices", "view", "conform", "help",    "tune" };
    const char *s = lg_suggest(cmd, names, 13);
    fprintf(stderr, "lightgraph: unknown command '%s'%s%s%s\n", cmd, s ? "; did you mean '" : "",
            s ? s : "", s ? "'?" : "");
    return 2;
}

int main(int argc, char **argv)
{
    /* The environment first (env_defaults: no write to it once a thread exists), then the
     * MPI job, whose start-up may start threads of its own (PMIx, Open MPI's progress), then
     * everything else. Without mpirun lg_dist_init does nothing at all. */
    env_defaults();
    if (lg_dist_init(&argc, &argv))
        return lg_dist_finish(1);
    /* ranks sharing this machine share its CPUs (LIGHTGRAPH_THREADS still wins) */
    lg_pool_set_ranks_per_machine((uint32_t)lg_dist_local_size());
    take_test_free_bytes();
    /* every rank's status makes the job's: the worst of them, on every rank */
    return lg_dist_finish(run_command(argc, argv));
}
