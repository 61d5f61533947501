#!/usr/bin/env python3
"""tools/bench_distributed.py --build BUILD [--reps N]: the MPI layer's costs here
(docs/distributed.md, "Measured costs"), as one Markdown table per measurement.

Runs BUILD/tools/lg_bench_dist as one process and under tests/dist/mpirun.sh with 2 and 3
ranks (3 oversubscribes a 2-core machine), then times:
  - start-up: `lightgraph --version` plain and under mpirun -np 2 and 3 (MPI_Init, the
    job's agreement at lg_dist_finish, MPI_Finalize, mpirun's own launch);
  - the test_shard node (tests/dist/testshard.c: uneven items through lg_shard) rendered
    at 256x128 with cost 2000 as one process and with 2 and 3 ranks, with
    LIGHTGRAPH_THREADS=1 so that ranks, not threads, share the cores.
A benchmark, not a test: the numbers depend on the machine and its load."""
import argparse
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MPIRUN = os.path.join(ROOT, "tests", "dist", "mpirun.sh")


def run(cmd, env=None):
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit("bench_distributed.py: %s failed (%d): %s" % (" ".join(cmd), p.returncode,
                                                              p.stderr[-2000:]))
    return p.stdout


def under(np, cmd):
    return cmd if np == 1 else ["sh", MPIRUN, str(np)] + cmd


def wall(cmd, reps, env=None):
    t = []
    for _ in range(reps):
        t0 = time.monotonic()
        run(cmd, env)
        t.append(time.monotonic() - t0)
    return statistics.median(t)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--reps", type=int, default=21)
    a = ap.parse_args()
    bench = os.path.join(a.build, "tools", "lg_bench_dist")
    lg = os.path.join(a.build, "lightgraph")
    ranks = [1, 2, 3]
    rows = {}
    for np in ranks:
        for line in run(under(np, [bench, str(a.reps)])).splitlines():
            f = line.split()
            if f[0] == "ranks":
                continue
            key = " ".join(f[:-1])
            rows.setdefault(key, {})[np] = float(f[-1])
    print("| measurement (median of %d) | 1 process | 2 ranks | 3 ranks |" % a.reps)
    print("|---|---|---|---|")
    names = {"empty_job_us": "empty job, %s chunks (us)", "gather_ms": "job of %s MiB, 64 chunks (ms)",
             "agree_us": "lg_dist_agree (us)", "map_us": "lg_dist_map of %s 1-byte items (us)"}
    for key, v in rows.items():
        f = key.split()
        label = names[f[0]] % tuple(f[1:]) if len(f) > 1 else names[f[0]]
        print("| %s | %s |" % (label, " | ".join("%.1f" % v.get(np, float("nan")) for np in ranks)))
    print()
    print("| wall time (s, median of 5) | 1 process | 2 ranks | 3 ranks |")
    print("|---|---|---|---|")
    ver = [wall(under(np, [lg, "--version"]), 5) for np in ranks]
    print("| lightgraph --version | %s |" % " | ".join("%.2f" % t for t in ver))
    env = dict(os.environ, LIGHTGRAPH_THREADS="1",
               LIGHTGRAPH_PLUGIN_PATH=os.path.join(a.build, "tests", "dist"))
    out = os.path.join(a.build, "bench-dist.exr")
    graph = os.path.join(ROOT, "tests", "dist", "shard.lgraph")
    cmd = [lg, "render", graph, "--no-cache", "--set", "s.width=256", "--set", "s.height=128",
           "--set", "s.cost=2000", "-o", out]
    shard = [wall(under(np, cmd), 5, env) for np in ranks]
    print("| render test_shard 256x128, cost 2000, 1 thread per rank | %s |"
          % " | ".join("%.2f" % t for t in shard))
    print("| the same minus --version's start-up | %s |"
          % " | ".join("%.2f" % (s - v) for s, v in zip(shard, ver)))
    os.remove(out)


if __name__ == "__main__":
    main()
