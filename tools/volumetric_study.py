#!/usr/bin/env python3
"""volumetric_study.py: what volumetric accuracy costs (issue 11, item 4): every method's knobs
swept with `lightgraph sweep` against `volumetric_reference` on the same scene.

usage: tools/volumetric_study.py [--build DIR] [--out DIR] [--size WxH] [--repeat N]
                                 [--ref-steps N] [--ref-spp N] [--quick]

The scene is the examples' bunny box with fog and a sun through its open side
(examples/volumetric_scene.lgraph). Each method's example graph is included with an output
of `vol.inscatter` (L_v alone, linear); the reference is examples/volumetric_reference.lgraph
with --ref-steps (default 1024) steps and --ref-spp (default 4) samples per pixel, every ray
through the pixel centre (`subpixel = centre`, as the methods sample: their error holds no
antialiasing term), rendered once and read by every sweep as an image. Sweeps (one `lightgraph sweep` each, `--time vol`,
`vol.per_frame = true` and --frames 4 so that a GL node's time is its steady per-frame cost,
not its shader compilation):

  screen     vol.samples = 4 .. 256 (model physical)
  polygonal  shadow.resolution = 128 .. 2048 (mesh per texel); vol.resolution = 32 .. 1024
             at shadow maps of 1024^2
  froxel     vol.depth = 16 .. 256 x slicing x accumulation (grid 190 x 90); grid width x
             height (48 x 22 .. 380 x 180, depth 128); shadow.resolution; temporal
             reprojection: vol.temporal = false, true over --frames 16 (its error after 16
             frames of jittered slices and history blending)

Error: relative RMSE of `inscatter` over the image and RGB, sqrt(sum (x - ref)^2 / sum ref^2)
(the sweep's RMSE divided by the reference's RMS). Time: the `vol` node's time per frame.
Writes DIR (default out/volumetric_study): each sweep's directory (CSV, heat maps, gnuplot
plot), volumetric_study.csv (all runs, one table), volumetric_study.md, and
volumetric_study.png (relative RMSE against time, every method). Plain python and gnuplot;
EXR read by tools/accuracy/exr.py's reader.
"""
import argparse
import csv
import math
import os
import re
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from accuracy.exr import read_exr  # noqa: E402  (width, height, {channel: values})


def die(msg):
    sys.stderr.write("volumetric_study: %s\n" % msg)
    sys.exit(1)


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def vol_block(example):
    """The `vol = ... { ... }` node of an example, as its file writes it (so that the study
    measures the example's own settings; the example's `tone` and output are left out, since
    a sweep compares exactly one output)."""
    text = open(os.path.join(ROOT, "examples", example)).read()
    m = re.search(r"^vol = [a-z_]+ \{.*?^\}", text, re.S | re.M)
    if not m:
        die("examples/%s: no `vol = ... { ... }` node" % example)
    return m.group(0)


def graph_for(example, out_dir):
    return ('lightgraph 1\ninclude "%s"\n%s\noutput vol.inscatter "%s"\n'
            % (os.path.join(ROOT, "examples", "volumetric_scene.lgraph"), vol_block(example),
               os.path.join(out_dir, "inscatter.exr")))


def rms_of(path):
    _, _, ch = read_exr(path)
    vals = [v for c in ("R", "G", "B") for v in ch[c]]
    return math.sqrt(sum(v * v for v in vals) / len(vals))


SWEEPS = [
    # (name, method label, example, --vary list, extra --set list, frames)
    ("screen_samples", "screen", "volumetric_screen.lgraph",
     ["vol.samples=4,8,16,32,64,128,256"], [], 4),
    ("polygonal_shadow", "polygonal", "volumetric_polygonal.lgraph",
     ["shadow.resolution=128,256,512,1024,2048"], [], 4),
    ("polygonal_mesh", "polygonal", "volumetric_polygonal.lgraph",
     ["vol.resolution=32,64,128,256,512,1024"], ["shadow.resolution=1024"], 4),
    ("froxel_depth", "froxel", "volumetric_froxel.lgraph",
     ["vol.depth=16,32,64,128,256", "vol.slicing=uniform_clip,exponential",
      "vol.accumulation=thesis,energy_conserving"], [], 4),
    ("froxel_xy", "froxel", "volumetric_froxel.lgraph",
     ["vol.width=48,95,190,380", "vol.height=22,45,90,180"], [], 4),
    ("froxel_shadow", "froxel", "volumetric_froxel.lgraph",
     ["shadow.resolution=256,512,1024,2048"], [], 4),
    ("froxel_temporal", "froxel", "volumetric_froxel.lgraph",
     ["vol.temporal=false,true", "vol.depth=32,64,128"], [], 16),
]

QUICK = {
    "screen_samples": ["vol.samples=8,64"],
    "polygonal_shadow": ["shadow.resolution=256,1024"],
    "polygonal_mesh": ["vol.resolution=64,256"],
    "froxel_depth": ["vol.depth=32,128", "vol.accumulation=thesis,energy_conserving"],
    "froxel_xy": ["vol.width=95,190", "vol.height=45,90"],
    "froxel_shadow": ["shadow.resolution=512,1024"],
    "froxel_temporal": ["vol.temporal=false,true", "vol.depth=32"],
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "volumetric_study"))
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ref-steps", type=int, default=1024)
    ap.add_argument("--ref-spp", type=int, default=4)
    ap.add_argument("--only", default="", help="comma-separated sweep names")
    ap.add_argument("--quick", action="store_true", help="two values per knob, 160x90")
    a = ap.parse_args()
    if a.quick:
        a.size, a.repeat, a.ref_steps, a.ref_spp = "160x90", 1, 256, 1
    a.out = os.path.abspath(a.out)  # graphs name their files relative to their own folder
    exe = os.path.abspath(os.path.join(a.build, "lightgraph"))
    if not os.path.exists(exe):
        die("%s does not exist: build first" % exe)
    os.makedirs(a.out, exist_ok=True)
    gdir = os.path.join(a.out, "graphs")
    os.makedirs(gdir, exist_ok=True)

    # the reference: rendered once here; the sweeps read the image through a graph of one
    # `image` node (rendering it again per sweep would cost minutes each)
    ref = os.path.join(gdir, "reference.lgraph")
    write(ref, graph_for("volumetric_reference.lgraph", gdir).replace("inscatter.exr",
                                                                       "reference.exr"))
    # through pixel centres, as the three methods sample (their error then holds no
    # antialiasing term); spp averages the visibility jitter
    ref_sets = ["vol.steps=%d" % a.ref_steps, "vol.spp=%d" % a.ref_spp, "vol.subpixel=centre"]
    cmd = [exe, "render", ref, "--size", a.size]
    for s in ref_sets:
        cmd += ["--set", s]
    sys.stderr.write("volumetric_study: reference (%s steps, %s spp) at %s\n"
                     % (a.ref_steps, a.ref_spp, a.size))
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        die("%s failed:\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
    ref_rms = rms_of(os.path.join(gdir, "reference.exr"))
    if not ref_rms > 0:
        die("the reference's in-scatter is zero: nothing to measure against")
    ref_img = os.path.join(gdir, "reference_image.lgraph")
    write(ref_img, 'lightgraph 1\nref = image { file = "%s" }\noutput ref "%s"\n'
          % (os.path.join(gdir, "reference.exr"), os.path.join(gdir, "reference_copy.exr")))

    only = set(a.only.split(",")) if a.only else None
    rows = []
    for name, method, example, varies, sets, frames in SWEEPS:
        if only and name not in only:
            continue
        if a.quick:
            varies = QUICK[name]
        g = os.path.join(gdir, name + ".lgraph")
        write(g, graph_for(example, gdir))
        d = os.path.join(a.out, name)
        if os.path.isdir(d):
            shutil.rmtree(d)
        os.makedirs(d)
        cmd = [exe, "sweep", g, "--reference", ref_img, "--time", "vol", "--repeat",
               str(a.repeat), "--frames", str(frames), "--size", a.size, "-o", d,
               "--set", "vol.per_frame=true"]
        for s in sets:
            cmd += ["--set", s]
        for v in varies:
            cmd += ["--vary", v]
        sys.stderr.write("volumetric_study: %s\n" % " ".join(cmd))
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            die("sweep %s failed (exit %d):\n%s%s" % (name, r.returncode, r.stdout, r.stderr))
        with open(os.path.join(d, "sweep.csv")) as f:
            rd = list(csv.reader(f))
        head = rd[0]
        ti, ri = head.index("time_ms"), head.index("rmse")
        for row in rd[1:]:
            knobs = " ".join("%s=%s" % (head[i], row[i]) for i in range(1, ti))
            rows.append((name, method, knobs, float(row[ti]), float(row[ri]) / ref_rms))
    with open(os.path.join(a.out, "volumetric_study.csv"), "w") as f:
        f.write("sweep,method,knobs,time_ms,rel_rmse\n")
        for r in rows:
            f.write('%s,%s,"%s",%.4f,%.6g\n' % r)
    md = ["| sweep | knobs | time (ms) | relative RMSE |", "|---|---|---:|---:|"]
    for r in rows:
        md.append("| %s | %s | %.2f | %.4f |" % (r[0], r[2], r[3], r[4]))
    write(os.path.join(a.out, "volumetric_study.md"),
          "Reference: volumetric_reference, %d steps, %d spp through pixel centres, %s; "
          "in-scatter RMS %.5g.\n\n" % (a.ref_steps, a.ref_spp, a.size, ref_rms) + "\n".join(md) + "\n")
    print("\n".join(md))
    plot(a.out, rows)
    print("written: %s" % a.out)


def plot(out, rows):
    if not shutil.which("gnuplot"):
        sys.stderr.write("volumetric_study: gnuplot not found: no plot\n")
        return
    methods = []
    for r in rows:
        if r[0] not in methods:
            methods.append(r[0])
    data = os.path.join(out, "volumetric_study.csv")
    gp = os.path.join(out, "volumetric_study.gp")
    with open(gp, "w") as f:
        f.write("set terminal pngcairo size 1000,650 noenhanced\n")
        f.write("set output '%s'\n" % os.path.join(out, "volumetric_study.png"))
        f.write("set datafile separator ','\nset grid\nset logscale xy\nset key outside right\n")
        f.write("set xlabel 'time per frame of the volumetric node (ms)'\n")
        f.write("set ylabel 'relative RMSE of in-scatter against the reference'\n")
        f.write("set title 'what volumetric accuracy costs (bunny box)'\n")
        f.write("plot " + ", \\\n     ".join(
            "'%s' every ::1 using 4:(strcol(1) eq '%s' ? $5 : 1/0) with points pt %d ps 1.3 "
            "title '%s'" % (data, m, 5 + i, m) for i, m in enumerate(methods)) + "\n")
    subprocess.run(["gnuplot", gp], check=False)


if __name__ == "__main__":
    main()
