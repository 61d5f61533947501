/* --profile: per node CPU wall time, GPU time, bytes allocated and moved, on-disk cache
 * hits and misses; as a table and as JSON.
 *
 * A node's memory (`allocated`) is what the host made for it (its resources: bytes_alloc)
 * plus the most memory its plugin held at once (lg_account_alloc minus lg_account_free:
 * bytes_plugin_peak), so that N frames of a node that keeps its buffers show what one
 * frame shows, and a buffer remade every frame is counted once, not N times. */
#include "exec/exec.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "exec/outputs.h"

static const char *dev(const lg_pnode *n)
{
    return n->run.device == LG_DEVICE_GL ? "gl" : n->run.device == LG_DEVICE_CL ? "cl" : "cpu";
}

static uint64_t allocated(const lg_pnode *n)
{
    return n->prof.bytes_alloc + n->prof.bytes_plugin_peak;
}

void lg_profile_print(lg_exec *ex, FILE *f)
{
    const lg_checked *c = ex->checked;
    int wn = 4, wt = 4;
    for (uint32_t i = 0; i < ex->n_nodes; i++) {
        int a = (int)strlen(ex->nodes[i]->pub.name), b = (int)strlen(ex->nodes[i]->schema->name);
        wn = a > wn ? a : wn;
        wt = b > wt ? b : wt;
    }
    fprintf(f, "profile (%u frame%s):\n", ex->opts.frames, ex->opts.frames == 1 ? "" : "s");
    fprintf(f, "  %-*s  %-*s  %-6s  %5s  %10s  %10s  %11s  %11s  %11s  %s\n", wn, "node", wt,
            "type", "device", "runs", "cpu ms", "gpu ms", "allocated", "plugin", "moved", "cache");
    double tc = 0, tg = 0;
    uint64_t ta = 0, tp = 0, tm = 0;
    for (uint32_t t = 0; t < c->n_nodes; t++) {
        const lg_pnode *n = ex->nodes[c->topo[t]];
        if (n->plan.state != LG_STATE_KEPT)
            continue;
        char a[32], pl[32], m[32], g[32];
        lg_format_bytes(a, sizeof a, allocated(n));
        lg_format_bytes(pl, sizeof pl, n->prof.bytes_plugin_peak);
        lg_format_bytes(m, sizeof m, n->prof.bytes_moved);
        if (n->run.device == LG_DEVICE_CPU)
            snprintf(g, sizeof g, "-");
        else if (n->prof.gpu_unmeasured)
            snprintf(g, sizeof g, "n/a");
        else
            snprintf(g, sizeof g, "%.3f", n->prof.gpu_ms);
        /* the on-disk cache (exec.h, lg_exec_cache_get): "hit" when the node's result came from it,
         * "miss" when it was computed and stored, both counts when a node did each */
        char k[64];
        if (!n->prof.cache_hits && !n->prof.cache_misses)
            snprintf(k, sizeof k, "-");
        else if (!n->prof.cache_misses)
            snprintf(k, sizeof k, n->prof.cache_hits == 1 ? "hit" : "%llu hits",
                     (unsigned long long)n->prof.cache_hits);
        else if (!n->prof.cache_hits)
            snprintf(k, sizeof k, n->prof.cache_misses == 1 ? "miss" : "%llu misses",
                     (unsigned long long)n->prof.cache_misses);
        else
            snprintf(k, sizeof k, "%llu hit, %llu miss", (unsigned long long)n->prof.cache_hits,
                     (unsigned long long)n->prof.cache_misses);
        fprintf(f, "  %-*s  %-*s  %-6s  %5llu  %10.3f  %10s  %11s  %11s  %11s  %s\n", wn,
                n->pub.name, wt, n->schema->name, dev(n), (unsigned long long)n->prof.runs,
                n->prof.cpu_ms, g, a, pl, m, k);
        tc += n->prof.cpu_ms;
        tg += n->prof.gpu_ms;
        ta += allocated(n);
        tp += n->prof.bytes_plugin_peak;
        tm += n->prof.bytes_moved;
    }
    char a[32], pl[32], m[32];
    lg_format_bytes(a, sizeof a, ta);
    lg_format_bytes(pl, sizeof pl, tp);
    lg_format_bytes(m, sizeof m, tm);
    fprintf(f, "  %-*s  %-*s  %-6s  %5s  %10.3f  %10.3f  %11s  %11s  %11s\n", wn, "total", wt, "",
            "", "", tc, tg, a, pl, m);
    for (uint32_t t = 0; t < c->n_nodes; t++)
        if (ex->nodes[c->topo[t]]->prof.gpu_unmeasured) {
            fprintf(f, "  n/a: the GL timer query gave no usable value (llvmpipe times only "
                       "rasterisation); the node's cpu ms include its GL work (glFinish)\n");
            break;
        }
    fprintf(f, "  allocated: the node's resources plus the most memory its plugin held at once "
               "(plugin: that peak, lg_account_alloc/free)\n");
    fprintf(f, "  planning %.3f ms (scan, load, create, prepare); frames and outputs %.3f ms\n",
            ex->t_plan_ms, ex->t_total_ms);
}

int lg_profile_write_json(lg_exec *ex, const char *path)
{
    const lg_checked *c = ex->checked;
    lg_str s = { 0 };
    lg_str_add(&s, "{\n  \"graph\": ");
    lg_str_add_json(&s, ex->opts.graph_path ? ex->opts.graph_path : "");
    lg_str_addf(&s, ",\n  \"frames\": %u,\n  \"width\": %u,\n  \"height\": %u,\n", ex->opts.frames,
                ex->opts.width, ex->opts.height);
    lg_str_addf(&s, "  \"planning_ms\": %.6f,\n  \"execution_ms\": %.6f,\n  \"nodes\": [",
                ex->t_plan_ms, ex->t_total_ms);
    bool first = true;
    for (uint32_t t = 0; t < c->n_nodes; t++) {
        const lg_pnode *n = ex->nodes[c->topo[t]];
        lg_str_add(&s, first ? "\n    {" : ",\n    {");
        first = false;
        lg_str_add(&s, "\"name\": ");
        lg_str_add_json(&s, n->pub.name);
        lg_str_add(&s, ", \"type\": ");
        lg_str_add_json(&s, n->schema->name);
        lg_str_addf(&s, ", \"state\": \"%s\"",
                    n->plan.state == LG_STATE_KEPT     ? "kept"
                    : n->plan.state == LG_STATE_CULLED ? "culled"
                                                       : "gated");
        if (n->plan.state == LG_STATE_KEPT)
            lg_str_addf(
                &s,
                ", \"device\": \"%s\", \"per_frame\": %s, \"runs\": %llu, \"cpu_ms\": "
                "%.6f, \"first_cpu_ms\": %.6f, \"min_cpu_ms\": %.6f, \"gpu_ms\": %.6f, "
                "\"gpu_measured\": %s, \"bytes_allocated\": %llu, \"resource_bytes\": %llu, "
                "\"plugin_bytes_live\": %llu, \"plugin_bytes_peak\": %llu, "
                "\"bytes_moved\": %llu, \"cache_hits\": %llu, \"cache_misses\": %llu",
                dev(n), n->run.per_frame ? "true" : "false", (unsigned long long)n->prof.runs,
                n->prof.cpu_ms, n->prof.first_cpu_ms, n->prof.min_cpu_ms, n->prof.gpu_ms,
                n->prof.gpu_unmeasured ? "false" : "true", (unsigned long long)allocated(n),
                (unsigned long long)n->prof.bytes_alloc,
                (unsigned long long)n->prof.bytes_plugin_live,
                (unsigned long long)n->prof.bytes_plugin_peak,
                (unsigned long long)n->prof.bytes_moved, (unsigned long long)n->prof.cache_hits,
                (unsigned long long)n->prof.cache_misses);
        else {
            lg_str_add(&s, ", \"reason\": ");
            lg_str_add_json(&s, n->plan.reason);
        }
        lg_str_add(&s, "}");
    }
    lg_str_add(&s, "\n  ]\n}\n");
    int rc = 0;
    char err[1024];
    if (ex->opts.outputs) {
        /* committed with the images, all or nothing (outputs.h) */
        if (lg_outputs_write_data(ex->opts.outputs, path, s.s, s.len, err, sizeof err) != 0) {
            lg_hlog(LG_HERR, "%s", err);
            rc = -1;
        }
    } else if (lg_write_file_atomic(path, s.s, s.len) != 0) {
        lg_hlog(LG_HERR, "cannot write %s: %s", path, strerror(errno));
        rc = -1;
    }
    lg_str_free(&s);
    return rc;
}
