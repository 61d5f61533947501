#!/usr/bin/env python3
"""Benchmark: lightgraph's reinhard node (cpu, gl, cl): roofline, and against pfstmo_reinhard02.

usage: tools/bench_reinhard.py [--build DIR] [--util EXE] [--roofline EXE] [--exe EXE]
                               [--image FILE] [--width N] [--key A] [--repeat N]
                               [--frames N] [--out DIR] [--no-pfstmo] [--node-only]

One run does everything on the same input, a WIDTH-pixel-wide float EXR resampled
(bilinear) from IMAGE.

First the roofline table: for every backend (cpu, cl, gl) and kernel (the reduction pass,
the map pass, both passes, and the whole node as the host runs it, per frame) the bytes
it must touch, its time (median of --repeat runs), GB/s, and that as a fraction of a
STREAM triad measured in the same run (tools/bench_roofline.c: C, arrays of 256 MiB,
threaded through the host's pool with the same number of threads). Kernel times come from
lg_bench_roofline (cpu: wall time; cl: profiling events; gl: wall time to glFinish); the
node's from `lightgraph render --profile-json` over --frames frames with adapt = true,
adapt_rate = 0 (recomputed every frame, input resident on the device). --node-only
leaves the kernel rows out (for measuring an older build's node with --exe).

Then, unless --no-pfstmo:

  pfstmo_reinhard02 --key A (global operator; its white point is the image's largest
  scaled luminance and its log offset 1e-5), timed two ways:
    operator  pfstmo_reinhard02 alone on a pre-converted pfs stream (reads and writes
              the stream through pipes; no EXR decoding or encoding)
    command   pfsin x.exr | pfstmo_reinhard02 | pfsoutexr --float32 y.exr
  lightgraph render with reinhard { mode = luminance, key = A, delta = 1e-5, white = the
  same white point }, per backend:
    operator  the node's execute time from --profile-json (first frame: shader or
              kernel compilation and the upload of the input included), and its
              steady per-frame time from a --frames run with adapt = true, adapt_rate = 0
              (the same output, recomputed every frame)
    command   the whole `lightgraph render` (EXR decode, devices, node, EXR encode)

and the mean and maximum absolute differences between each backend's output and
pfstmo's (linear RGB, before any display encoding), computed in float inside a graph
(ours - pfstmo's, times 1000, through core's scale and add nodes) so that a half-float
output file cannot hide them. Times are medians of --repeat runs.
Writes the table to stdout and to OUT/results.md.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

GAIN = 1000.0  # differences are amplified by this before they reach an output file
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(cmd, **kw):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kw)
    if r.returncode != 0:
        sys.exit("bench_reinhard: %s failed (exit %d):\n%s" % (
            cmd if isinstance(cmd, str) else " ".join(cmd), r.returncode,
            r.stderr.decode(errors="replace")))
    return r.stdout.decode()


def timed(cmd, repeat, **kw):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        run(cmd, **kw)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def node_steady_ms(exe, graph, backend, frames, repeat, out):
    """The node's time per frame over `frames` frames, recomputed every frame (adapt with
    rate 0 gives the same output), input resident: (t(frames) - t(1)) / (frames - 1)."""
    prof = os.path.join(out, "profile_%s.json" % backend)
    base = [exe, "render", graph, "--set", "tone.backend=" + backend,
            "--set", "tone.adapt=true", "--set", "tone.adapt_rate=0"]
    steady = []
    for _ in range(repeat):
        t = []
        for n in (1, frames):
            run(base + ["--frames", str(n), "--profile-json", prof,
                        "-o", os.path.join(out, "steady_%s.exr" % backend)])
            node = [x for x in json.load(open(prof))["nodes"] if x["name"] == "tone"][0]
            t.append(node["cpu_ms"])
        steady.append((t[1] - t[0]) / (frames - 1))
    return statistics.median(steady)


def roofline(a, exe, roof, src, w, h, out):
    r = json.loads(run([roof, src, "--repeat", str(max(a.repeat, 5))]))
    triad = r["triad"]["gbs"]
    graph = os.path.join(out, "roofline.lgraph")
    with open(graph, "w") as f:
        f.write("lightgraph 1\n# written by tools/bench_reinhard.py\n"
                "src = image { file = \"%s\" }\n"
                "tone = reinhard { image = src, key = %r }\n"
                "output tone \"roofline.exr\"\n" % (os.path.basename(src), a.key))
    npx = w * h
    rows = [] if a.node_only else [x for x in r["rows"] if "skipped" not in x]
    skipped = [x for x in r["rows"] if "skipped" in x]
    for backend in ("cpu", "cl", "gl"):
        if any(x["backend"] == backend for x in skipped):
            continue
        ms = node_steady_ms(exe, graph, backend, a.frames, a.repeat, out)
        rows.append({"backend": backend, "kernel": "node", "bytes": 48 * npx, "ms": ms})
    order = {"cpu": 0, "cl": 1, "gl": 2}
    korder = {"reduce": 0, "map": 1, "passes": 2, "node": 3}
    rows.sort(key=lambda x: (order[x["backend"]], korder[x["kernel"]]))
    load = os.getloadavg()
    lines = ["Roofline: reinhard on %dx%d rgba32f (%.1f MiB in, %.1f MiB out), %d CPUs, "
             "pool of %d threads, load average %.2f at the end." % (
                 w, h, npx * 16 / 2**20, npx * 16 / 2**20, os.cpu_count(), r["threads"], load[0]),
             "STREAM triad (tools/bench_roofline.c, 3 x %d MiB of doubles, %d threads, best "
             "of %d): %.2f GB/s." % (r["triad"]["mib_per_array"], r["threads"],
                                     max(a.repeat, 5), triad),
             "",
             "| backend | kernel | bytes touched | time ms (median) | GB/s | of triad |",
             "|---|---|---|---|---|---|"]
    what = {"reduce": "reduce (read)", "map": "map (read + write)",
            "passes": "both passes", "node": "node per frame (host)"}
    for x in rows:
        gbs = x["bytes"] / (x["ms"] * 1e-3) / 1e9
        lines.append("| %s | %s | %.1f MiB | %.2f | %.2f | %.1f%% |" % (
            x["backend"], what[x["kernel"]], x["bytes"] / 2**20, x["ms"], gbs,
            100.0 * gbs / triad))
    for x in skipped:
        lines.append("| %s | skipped: %s | | | | |" % (x["backend"], x["skipped"]))
    text = "\n".join(lines) + "\n\n"
    sys.stdout.write(text)
    sys.stdout.flush()
    with open(os.path.join(out, "roofline.md"), "w") as f:
        f.write(text)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--util", help="lg_bench_reinhard (default: BUILD/tools/lg_bench_reinhard)")
    ap.add_argument("--image", default=os.path.join(ROOT, "assets/images/GoldenGate.exr"))
    ap.add_argument("--width", type=int, default=2048)
    ap.add_argument("--key", type=float, default=0.18)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--frames", type=int, default=11)
    ap.add_argument("--out", help="work folder (default: BUILD/bench-reinhard)")
    ap.add_argument("--roofline", help="lg_bench_roofline (default: BUILD/tools/lg_bench_roofline)")
    ap.add_argument("--exe", help="the lightgraph program to time (default: BUILD/lightgraph)")
    ap.add_argument("--no-pfstmo", action="store_true", help="the roofline table only")
    ap.add_argument("--node-only", action="store_true",
                    help="roofline: the triad and the node rows, no kernel rows")
    a = ap.parse_args()

    build = os.path.abspath(a.build)
    exe = os.path.abspath(a.exe) if a.exe else os.path.join(build, "lightgraph")
    util = a.util or os.path.join(build, "tools", "lg_bench_reinhard")
    roof = a.roofline or os.path.join(build, "tools", "lg_bench_roofline")
    out = os.path.abspath(a.out or os.path.join(build, "bench-reinhard"))
    for f in (exe, util, roof, a.image):
        if not os.path.exists(f):
            sys.exit("bench_reinhard: %s does not exist" % f)
    os.makedirs(out, exist_ok=True)
    delta = 1e-5  # pfstmo_reinhard02's log offset

    # the input, and the white point pfstmo_reinhard02 will use
    src = os.path.join(out, "input_%d.exr" % a.width)
    info = json.loads(run([util, "prep", a.image, str(a.width), src, repr(a.key), repr(delta)]))
    w, h, white = info["width"], info["height"], info["white"]
    print("input: %s resampled to %dx%d (%.2f Mpixel), Lavg %.6g, Lmax %.6g, Lwhite %.6g"
          % (os.path.relpath(a.image, ROOT), w, h, w * h / 1e6, info["lavg"], info["lmax"], white),
          file=sys.stderr)

    roofline(a, exe, roof, src, w, h, out)
    if a.no_pfstmo:
        return
    missing = [t for t in ("pfsin", "pfsoutexr", "pfstmo_reinhard02") if not shutil.which(t)]
    if missing:
        print("The comparison with pfstmo_reinhard02 is not run: %s not found (Debian package "
              "pfstools; tools/deps.sh installs it)." % ", ".join(missing))
        return

    # pfstmo_reinhard02
    pfs_in = os.path.join(out, "input.pfs")
    pfs_tm = os.path.join(out, "pfstmo.pfs")
    pfs_out = os.path.join(out, "pfstmo.exr")
    run("pfsin '%s' > '%s'" % (src, pfs_in), shell=True)
    op_pfs = timed("pfstmo_reinhard02 --key %r < '%s' > '%s'" % (a.key, pfs_in, pfs_tm),
                   a.repeat, shell=True)
    cmd_pfs = timed("pfsin '%s' | pfstmo_reinhard02 --key %r | pfsoutexr --float32 '%s'"
                    % (src, a.key, pfs_out), a.repeat, shell=True)

    # lightgraph, per backend
    graph = os.path.join(out, "reinhard.lgraph")
    with open(graph, "w") as f:
        f.write("lightgraph 1\n# written by tools/bench_reinhard.py\n"
                "src = image { file = \"%s\" }\n"
                "tone = reinhard { image = src, key = %r, delta = %r, white = %r }\n"
                "output tone \"lightgraph.exr\"\n" % (os.path.basename(src), a.key, delta, white))
    rows = []
    for backend in ("cpu", "gl", "cl"):
        res = os.path.join(out, "lightgraph_%s.exr" % backend)
        prof = os.path.join(out, "profile_%s.json" % backend)
        base = [exe, "render", graph, "-o", res, "--set", "tone.backend=" + backend]
        cmd_lg = timed(base, a.repeat)
        ops = []
        for _ in range(a.repeat):
            run(base + ["--profile-json", prof])
            node = [n for n in json.load(open(prof))["nodes"] if n["name"] == "tone"][0]
            ops.append((node["cpu_ms"], node["gpu_ms"], node["bytes_moved"]))
        op_ms = statistics.median(o[0] for o in ops)
        gpu_ms = statistics.median(o[1] for o in ops)
        moved = ops[0][2]
        # steady state: the node recomputed every frame, nothing else runs again
        steady = []
        adapt = ["--set", "tone.adapt=true", "--set", "tone.adapt_rate=0"]
        for _ in range(a.repeat):
            t = []
            for frames in (1, a.frames):
                run(base + adapt + ["--frames", str(frames), "--profile-json", prof,
                                    "-o", os.path.join(out, "steady_%s.exr" % backend)])
                node = [n for n in json.load(open(prof))["nodes"] if n["name"] == "tone"][0]
                t.append(node["cpu_ms"])
            steady.append((t[1] - t[0]) / (a.frames - 1))
        steady_ms = statistics.median(steady)
        # the difference in float: (ours - pfstmo's) * GAIN inside a graph
        dgraph = os.path.join(out, "diff_%s.lgraph" % backend)
        dfile = os.path.join(out, "diff_%s.exr" % backend)
        with open(dgraph, "w") as f:
            f.write("lightgraph 1\n# written by tools/bench_reinhard.py\n"
                    "src = image { file = \"%s\" }\n"
                    "tone = reinhard { image = src, key = %r, delta = %r, white = %r, backend = %s }\n"
                    "pfs = image { file = \"%s\", radiance = false }\n"
                    "neg = scale { image = pfs, tint = [-1, -1, -1] }\n"
                    "d = add { a = tone, b = neg }\n"
                    "amp = scale { image = d, factor = %r }\n"
                    "output amp \"%s\"\n" % (os.path.basename(src), a.key, delta, white, backend,
                                              os.path.basename(pfs_out), GAIN,
                                              os.path.basename(dfile)))
        run([exe, "render", dgraph])
        d = json.loads(run([util, "absstats", dfile, repr(GAIN)]))
        rows.append((backend, op_ms, gpu_ms, steady_ms, moved, cmd_lg, d))

    lines = []
    load = os.getloadavg()
    lines.append("Machine: %d CPUs, load average %.2f %.2f %.2f at the end of the run "
                 "(other work on the machine inflates every time alike; compare ratios)."
                 % (os.cpu_count(), load[0], load[1], load[2]))
    lines.append("")
    lines.append("Reinhard global operator, %dx%d (%s resampled), key %g, Lwhite %.6g "
                 "(pfstmo's: the largest scaled luminance), log offset %g; median of %d runs."
                 % (w, h, os.path.basename(a.image), a.key, white, delta, a.repeat))
    lines.append("")
    lines.append("| implementation | operator ms (first frame) | per frame ms (steady) | "
                 "x pfstmo operator | command s | x pfstmo command | mean abs diff | max abs diff |")
    lines.append("|---|---|---|---|---|---|---|---|")
    lines.append("| pfstmo_reinhard02 | %.1f | - | 1 | %.3f | 1 | - | - |"
                 % (op_pfs * 1e3, cmd_pfs))
    for backend, op_ms, gpu_ms, steady_ms, moved, cmd_lg, d in rows:
        lines.append("| reinhard %s | %.1f%s | %.1f | %.2f | %.3f | %.2f | %.3g | %.3g |" % (
            backend, op_ms, "" if not moved else " (%.1f MiB moved%s)" % (
                moved / 2**20, ", kernels %.1f" % gpu_ms if gpu_ms > 0 else ""), steady_ms,
            op_ms / (op_pfs * 1e3), cmd_lg, cmd_lg / cmd_pfs, d["mean_abs"], d["max_abs"]))
    text = "\n".join(lines) + "\n"
    sys.stdout.write(text)
    with open(os.path.join(out, "results.md"), "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
