#!/usr/bin/env python3
"""What sh_project's samplers cost and how close they come to the quadrature.

For a probe (default assets/probes/forest_1024x512.hdr) and a band count (default 3):
runs `sh_project` by quadrature (the reference: every texel at its exact solid angle), then
each sampler (jittered, hammersley, sobol) at N x N samples for N in --sides, through the
real program (`lightgraph render`, the coefficients read back from the node's .txt output),
and prints per run the relative RMS error over every coefficient and channel (divided by
the RMS of the three c_0), the node's time from `--profile`, and samples per second.
Optionally writes the table as CSV.

    ninja -C build study-sh-project
    tools/sh_project_study.py --build build [--probe FILE] [--bands 3]
        [--sides 16,64,256,1024] [--seed 1] [--csv out.csv]

A command, not a test: the largest sizes take seconds to minutes.
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def read_txt(path):
    rows = [l.split() for l in open(path) if not l.startswith("#")]
    n = len(rows)
    return [[float(r[3 + ch]) for r in rows] for ch in range(3)], n


def run(exe, tmp, probe, sh):
    g = os.path.join(tmp, "g.lgraph")
    with open(g, "w") as f:
        f.write('lightgraph 1\nsky = probe { file = "%s" }\n'
                'light = sh_project { probe = sky, %s }\noutput light "light.txt"\n'
                % (probe, sh))
    env = dict(os.environ)
    env.setdefault("LIGHTGRAPH_PLUGIN_PATH", "")
    t0 = time.monotonic()
    p = subprocess.run([exe, "render", g, "--profile"], capture_output=True, text=True,
                       cwd=tmp, env=env)
    wall = time.monotonic() - t0
    if p.returncode != 0:
        sys.exit("lightgraph failed (%s):\n%s%s" % (sh, p.stdout, p.stderr))
    ms = None
    for line in (p.stdout + p.stderr).splitlines():
        w = line.split()
        # "light  sh_project  cpu  RUNS  CPU_MS ..."
        if len(w) > 4 and w[0] == "light" and w[1] == "sh_project" and \
                re.match(r"^[0-9.]+$", w[4]):
            ms = float(w[4])
    c, _ = read_txt(os.path.join(tmp, "light.txt"))
    return c, ms, wall


def rel_rms(a, b):
    s = sum((x - y) ** 2 for ca, cb in zip(a, b) for x, y in zip(ca, cb))
    n = sum(len(ca) for ca in a)
    n0 = math.sqrt(sum(cb[0] ** 2 for cb in b) / 3)
    return math.sqrt(s / n) / n0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--probe", default=os.path.join(ROOT, "assets/probes/forest_1024x512.hdr"))
    ap.add_argument("--bands", type=int, default=3)
    ap.add_argument("--sides", default="16,64,256,1024")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--csv")
    a = ap.parse_args()
    exe = os.path.join(os.path.abspath(a.build), "lightgraph")
    probe = os.path.abspath(a.probe)
    sides = [int(s) for s in a.sides.split(",")]
    rows = []
    with tempfile.TemporaryDirectory(prefix="lg-sh-study-") as tmp:
        ref, ms, wall = run(exe, tmp, probe, "bands = %d" % a.bands)
        print("probe %s, %d bands; reference: quadrature, node %s ms"
              % (os.path.basename(probe), a.bands, ms))
        rows.append(("quadrature", 0, 0.0, ms))
        print("%-11s %7s %12s %10s %12s" % ("sampler", "N", "samples", "node ms",
                                            "rel. RMS err"))
        for s in ("jittered", "hammersley", "sobol"):
            for n in sides:
                c, ms, wall = run(exe, tmp, probe, "bands = %d, sampler = %s, samples = %d, "
                                  "seed = %d" % (a.bands, s, n, a.seed))
                e = rel_rms(c, ref)
                rows.append((s, n, e, ms))
                rate = n * n / (ms / 1e3) if ms else float("nan")
                print("%-11s %7d %12d %10.1f %12.3e   %.3g samples/s" % (s, n, n * n, ms or 0,
                                                                        e, rate))
    if a.csv:
        with open(a.csv, "w") as f:
            f.write("sampler,side,samples,rel_rms,node_ms\n")
            for s, n, e, ms in rows:
                f.write("%s,%d,%d,%.6e,%s\n" % (s, n, n * n, e, ms))


if __name__ == "__main__":
    main()
