#!/usr/bin/env python3
"""prt_study.py: what PRT accuracy costs (issue 10, item 6): bands and samples against time.

usage: tools/prt_study.py [--build DIR] [--out DIR] [--grid G] [--probe FILE]
                          [--samplers jittered,hammersley,sobol] [--samples 16,32,...]
                          [--bands 1,2,...] [--mode shadowed|unshadowed]
                          [--reference-resolution R]

The scene is the bunny box with its walls cut into G x G grids (tools/make_prt_scene.py,
default G = 16: 4,053 vertices; the example's G = 64 has 23,733), under a light probe
(default assets/probes/forest_1024x512.hdr). For every sampler, sample count N (N x N
directions per vertex) and band count n:

  bake_ms   the `prt_bake` node's time for that sampler and N, baked once at the largest
            band count into an empty cache (LIGHTGRAPH_CACHE_DIR; the profile must show no
            cache hit). The smaller band counts use the first n^2 coefficients of that
            bake (the `prt` node takes the bands both inputs have, which is exactly the
            n-band bake of the same directions: SH is hierarchical) and load it from the
            cache. The bake's time hardly depends on the band count (the rays dominate:
            plugins/prt_bake/README.md measures 1..8 bands), so the one time stands for all
  project_ms, dot_ms  the `sh_project` (n bands) and `prt` (cpu) nodes' times
  rel_rmse  the error of the PRT radiance per vertex, dot(lighting, transfer) (`prt` on
            cpu; the lighting projected to n bands by `sh_project` with exact per-texel
            quadrature, so that the lighting adds no sampling error), against the project's
            reference `prt_reference`: per vertex, exact quadrature of the probe resampled
            to a cube of R x R faces (default 128: 98,304 directions) with Embree
            visibility, no SH at all. Relative RMSE over the vertices and RGB channels:
            sqrt(sum (x - ref)^2 / sum ref^2)
  max_rel   the largest per-vertex error |x - ref| over the RGB channels, relative to the
            RMS of the reference
  vs_finest the sampling error alone: the relative RMSE against the same sampler's bake
            with the most samples, at the same band count (the truncation cancels)

Two sources of error meet: truncation to n bands (the visibility and the lighting have
detail above band n: the floor each curve reaches) and sampling (N^2 directions per vertex:
falls with N, fastest for the low-discrepancy samplers).

Writes into DIR (default out/prt_study): prt_study.csv, prt_study.md (a markdown table),
prt_study_time.png (error against bake time, one curve per sampler and band count),
prt_study_bands.png (error against bands, one curve per sample count, sobol) and
prt_study_samples.png (the sampling error alone against bake time), the gnuplot
scripts, the graphs and the vertex images. Plain python and gnuplot; EXR read by
tools/format_study.py's independent reader.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from format_study import read_exr  # noqa: E402


def die(msg):
    sys.stderr.write("prt_study: %s\n" % msg)
    sys.exit(1)


def render(exe, graph, sets, prof, cache):
    env = dict(os.environ, LIGHTGRAPH_CACHE_DIR=cache)
    cmd = [exe, "render", graph, "--profile-json", prof]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.time()
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    wall = time.time() - t0
    if r.returncode != 0:
        die("%s failed (exit %d):\n%s%s" % (" ".join(cmd), r.returncode, r.stdout, r.stderr))
    with open(prof) as f:
        p = json.load(f)
    return {n["name"]: n for n in p["nodes"]}, wall


def vertex_values(path):
    """The RGB values of the vertices (texels with alpha 1) of a per-vertex image."""
    w, h, ch = read_exr(path)
    a = ch.get("A")
    if a is None:
        die("%s: no alpha channel" % path)
    idx = [i for i in range(w * h) if a[i] == 1.0]
    return [(ch["R"][i], ch["G"][i], ch["B"][i]) for i in idx]


def errors(x, ref):
    if len(x) != len(ref):
        die("vertex counts differ: %d against the reference's %d" % (len(x), len(ref)))
    num = den = 0.0
    worst = 0.0
    for a, b in zip(x, ref):
        for c in range(3):
            d = a[c] - b[c]
            num += d * d
            den += b[c] * b[c]
            worst = max(worst, abs(d))
    rms_ref = math.sqrt(den / (3 * len(ref)))
    return math.sqrt(num / den), worst / rms_ref


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "prt_study"))
    ap.add_argument("--grid", type=int, default=16)
    ap.add_argument("--probe", default=os.path.join(ROOT, "assets", "probes", "forest_1024x512.hdr"))
    ap.add_argument("--samplers", default="jittered,hammersley,sobol")
    ap.add_argument("--samples", default="16,32,64,128,256,512")
    ap.add_argument("--bands", default="1,2,3,4,5,6,7,8")
    ap.add_argument("--mode", default="shadowed", choices=["shadowed", "unshadowed"])
    ap.add_argument("--reference-resolution", type=int, default=128)
    args = ap.parse_args()

    exe = os.path.join(args.build, "lightgraph")
    if not os.access(exe, os.X_OK):
        die("%s: not built (ninja -C %s)" % (exe, args.build))
    samplers = args.samplers.split(",")
    samples = [int(s) for s in args.samples.split(",")]
    bands = [int(b) for b in args.bands.split(",")]
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    scene = os.path.join(out, "bunny_box_prt_%d.glb" % args.grid)
    subprocess.run([sys.executable, os.path.join(ROOT, "tools", "make_prt_scene.py"), str(args.grid), scene],
                   check=True, capture_output=True)
    probe = os.path.abspath(args.probe)

    ref_graph = os.path.join(out, "reference.lgraph")
    ref_exr = os.path.join(out, "reference.exr")
    with open(ref_graph, "w") as f:
        f.write('lightgraph 1\n'
                'scene = gltf { file = "%s" }\n'
                'sky = probe { file = "%s" }\n'
                'ref = prt_reference { scene = scene, probe = sky, mode = %s, resolution = %d }\n'
                'output ref.vertices "%s"\n' % (scene, probe, args.mode, args.reference_resolution, ref_exr))
    study_graph = os.path.join(out, "study.lgraph")
    lit_exr = os.path.join(out, "lit.exr")
    with open(study_graph, "w") as f:
        f.write('lightgraph 1\n'
                'scene = gltf { file = "%s" }\n'
                'sky = probe { file = "%s" }\n'
                'light = sh_project { probe = sky, sampler = quadrature }\n'
                'bake = prt_bake { scene = scene, mode = %s, albedo = material }\n'
                'lit = prt { scene = scene, lighting = light, transfer = bake, backend = cpu }\n'
                'output lit.vertices "%s"\n' % (scene, probe, args.mode, lit_exr))

    with tempfile.TemporaryDirectory(prefix="prt_study_cache") as tmp:
        cache = os.path.join(tmp, "ref")
        os.makedirs(cache)
        nodes, wall = render(exe, ref_graph, [], os.path.join(out, "profile_reference.json"), cache)
        ref = vertex_values(ref_exr)
        ref_ms = nodes["ref"]["cpu_ms"]
        print("reference: %d vertices, cube %d, %.1f s" % (len(ref), args.reference_resolution, ref_ms / 1e3))
        rows = []
        values = {}
        top = max(bands)
        for sm in samplers:
            for n_s in samples:
                # one bake of `top` bands per sampler and sample count, into an empty cache;
                # the smaller band counts read its first n^2 coefficients (the `prt` node
                # takes the bands both inputs have: SH is hierarchical, so that is exactly
                # the n-band bake of the same directions), loading the bake from the cache
                cache = tempfile.mkdtemp(dir=tmp)
                bake_ms = None
                for nb in sorted(bands, reverse=True):
                    sets = ["bake.sampler=%s" % sm, "bake.samples=%d" % n_s, "bake.bands=%d" % top,
                            "light.bands=%d" % nb]
                    nodes, wall = render(exe, study_graph, sets, os.path.join(out, "profile_run.json"), cache)
                    b = nodes["bake"]
                    if nb == top:
                        if b.get("cache_hits", 0):
                            die("the bake was loaded from the cache: its time would mean nothing")
                        bake_ms = b["cpu_ms"]
                    elif not b.get("cache_hits", 0):
                        die("the %d-band render baked again instead of loading the bake" % nb)
                    vals = vertex_values(lit_exr)
                    rel, worst = errors(vals, ref)
                    values[(sm, n_s, nb)] = vals
                    row = {"sampler": sm, "samples": n_s, "directions": n_s * n_s, "bands": nb,
                           "bake_ms": bake_ms, "project_ms": nodes["light"]["cpu_ms"],
                           "dot_ms": nodes["lit"]["cpu_ms"], "rel_rmse": rel, "max_rel": worst}
                    rows.append(row)
                    print("%-10s %4d^2  bands %d  bake %10.1f ms  rel rmse %.4g  max %.4g" %
                          (sm, n_s, nb, bake_ms, rel, worst), flush=True)
                shutil.rmtree(cache, ignore_errors=True)

    # the sampling error alone: against the same sampler's finest bake, same bands (the
    # truncation to n bands is common to both and cancels)
    finest = max(samples)
    for r in rows:
        r["vs_finest"] = errors(values[(r["sampler"], r["samples"], r["bands"])],
                                values[(r["sampler"], finest, r["bands"])])[0]

    cols = ["sampler", "samples", "directions", "bands", "bake_ms", "project_ms", "dot_ms", "rel_rmse", "max_rel", "vs_finest"]
    with open(os.path.join(out, "prt_study.csv"), "w") as f:
        f.write(",".join(cols) + "\n")
        for r in rows:
            f.write(",".join(("%.6g" % r[c]) if isinstance(r[c], float) else str(r[c]) for c in cols) + "\n")
    with open(os.path.join(out, "prt_study.md"), "w") as f:
        f.write("Scene: bunny box, walls %dx%d (%d vertices); probe %s; mode %s; reference: cube %d "
                "(%.1f s).\n\n" % (args.grid, args.grid, len(ref), os.path.basename(probe), args.mode,
                                    args.reference_resolution, ref_ms / 1e3))
        f.write("| sampler | samples | bake ms | " + " | ".join("%d bands" % b for b in bands) + " |\n")
        f.write("|---|---|---|" + "---|" * len(bands) + "\n")
        for sm in samplers:
            for n_s in samples:
                cells = []
                for nb in bands:
                    r = next(r for r in rows if r["sampler"] == sm and r["samples"] == n_s and r["bands"] == nb)
                    cells.append("%.3g" % r["rel_rmse"])
                bake_ms = next(r["bake_ms"] for r in rows if r["sampler"] == sm and r["samples"] == n_s)
                f.write("| %s | %d^2 | %.0f | %s |\n" % (sm, n_s, bake_ms, " | ".join(cells)))
        f.write("\nEach cell: relative RMSE over the vertices against the reference.\n")

    # error against time: one curve per (sampler, bands) for a few band counts
    dat = os.path.join(out, "prt_study.dat")
    show_bands = [b for b in (2, 3, 5, 8) if b in bands] or bands[-1:]
    blocks = []
    with open(dat, "w") as f:
        for sm in samplers:
            for nb in show_bands:
                blocks.append((sm, nb))
                for n_s in samples:
                    r = next(r for r in rows if r["sampler"] == sm and r["samples"] == n_s and r["bands"] == nb)
                    f.write("%d %.6g %.6g\n" % (n_s, r["bake_ms"], r["rel_rmse"]))
                f.write("\n\n")
    gp = os.path.join(out, "prt_study_time.gp")
    with open(gp, "w") as f:
        f.write('set terminal pngcairo size 900,560\nset output "%s"\n'
                'set title "PRT (%s): error against bake time, %d vertices" noenhanced\n'
                'set xlabel "bake time (ms)"\nset ylabel "relative RMSE over vertices vs reference"\n'
                'set logscale xy\nset key outside right\nset grid\n' %
                (os.path.join(out, "prt_study_time.png"), args.mode, len(ref)))
        styles = {"jittered": 1, "hammersley": 2, "sobol": 3}
        plots = []
        for i, (sm, nb) in enumerate(blocks):
            plots.append('"%s" index %d using 2:3 with linespoints lc %d pt %d title "%s, %d bands"' %
                         (dat, i, show_bands.index(nb) + 1, 4 + 2 * styles.get(sm, 0), sm, nb))
        f.write("plot " + ", \\\n     ".join(plots) + "\n")
    subprocess.run(["gnuplot", gp], check=True)

    dat2 = os.path.join(out, "prt_study_bands.dat")
    sm0 = "sobol" if "sobol" in samplers else samplers[0]
    with open(dat2, "w") as f:
        for n_s in samples:
            for nb in bands:
                r = next(r for r in rows if r["sampler"] == sm0 and r["samples"] == n_s and r["bands"] == nb)
                f.write("%d %.6g\n" % (nb, r["rel_rmse"]))
            f.write("\n\n")
    gp2 = os.path.join(out, "prt_study_bands.gp")
    with open(gp2, "w") as f:
        f.write('set terminal pngcairo size 900,560\nset output "%s"\n'
                'set title "PRT (%s, %s): error against bands" noenhanced\n'
                'set xlabel "bands"\nset ylabel "relative RMSE over vertices vs reference"\n'
                'set logscale y\nset key outside right\nset grid\nset xtics 1\n' %
                (os.path.join(out, "prt_study_bands.png"), args.mode, sm0))
        f.write("plot " + ", \\\n     ".join('"%s" index %d using 1:2 with linespoints title "%d^2 samples"' %
                                            (dat2, i, n_s) for i, n_s in enumerate(samples)) + "\n")
    subprocess.run(["gnuplot", gp2], check=True)
    dat3 = os.path.join(out, "prt_study_samples.dat")
    blocks3 = []
    with open(dat3, "w") as f:
        for sm in samplers:
            for nb in [b for b in (3, 8) if b in bands] or bands[-1:]:
                blocks3.append((sm, nb))
                for n_s in samples:
                    if n_s == finest:
                        continue
                    r = next(r for r in rows if r["sampler"] == sm and r["samples"] == n_s and r["bands"] == nb)
                    f.write("%d %.6g %.6g\n" % (n_s, r["bake_ms"], max(r["vs_finest"], 1e-9)))
                f.write("\n\n")
    gp3 = os.path.join(out, "prt_study_samples.gp")
    with open(gp3, "w") as f:
        f.write('set terminal pngcairo size 900,560\nset output "%s"\n'
                'set title "PRT (%s): sampling error alone (against the %d^2 bake, same bands)" noenhanced\n'
                'set xlabel "bake time (ms)"\nset ylabel "relative RMSE over vertices"\n'
                'set logscale xy\nset key outside right\nset grid\n' %
                (os.path.join(out, "prt_study_samples.png"), args.mode, finest))
        styles = {"jittered": 1, "hammersley": 2, "sobol": 3}
        f.write("plot " + ", \\\n     ".join(
            '"%s" index %d using 2:3 with linespoints lc %d pt %d title "%s, %d bands"' %
            (dat3, i, styles.get(sm, 0), 4 + 2 * (nb == 8), sm, nb) for i, (sm, nb) in enumerate(blocks3)) + "\n")
    subprocess.run(["gnuplot", gp3], check=True)
    with open(os.path.join(out, "prt_study.md"), "a") as f:
        f.write("\nThe sampling error alone (relative RMSE against the same sampler's %d^2 bake, "
                "same bands):\n\n" % finest)
        f.write("| sampler | bands | " + " | ".join("%d^2" % n for n in samples if n != finest) + " |\n")
        f.write("|---|---|" + "---|" * (len(samples) - 1) + "\n")
        for sm in samplers:
            for nb in [b for b in (3, 8) if b in bands] or bands[-1:]:
                cells = ["%.2g" % next(r["vs_finest"] for r in rows if r["sampler"] == sm and
                                        r["samples"] == n and r["bands"] == nb)
                         for n in samples if n != finest]
                f.write("| %s | %d | %s |\n" % (sm, nb, " | ".join(cells)))
    with open(os.path.join(out, "prt_study.md")) as f:
        sys.stdout.write(f.read())


if __name__ == "__main__":
    main()
