#!/usr/bin/env python3
"""volumetric_pictures.py: the pictures of docs/volumetric.md: the four volumetric examples
side by side (tone-mapped), their in-scatter, and each method's error heat map against the
reference (`lightgraph diff --heatmap`).

usage: tools/volumetric_pictures.py [--build DIR] [--out DIR] [--size WxH]
                                    [--ref-steps N] [--ref-spp N]

For each of screen, polygonal, froxel and reference: renders examples/volumetric_<m>.lgraph
into <m>.png (the example's own tone-mapped output), <m>_inscatter.png (L_v alone, tone
mapped with Reinhard's operator, key 0.18) and a temporary <m>_inscatter.exr
(linear L_v); then `lightgraph diff <m>_inscatter.exr reference_inscatter.exr --heatmap heat_<m>.png
--json` for the three methods, and writes pictures.md: a markdown table with the pictures
and the RMSE figures (relative to the reference's RMS).
"""
import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from accuracy.exr import read_exr  # noqa: E402  (width, height, {channel: values})
from volumetric_study import vol_block  # noqa: E402  (the example's own `vol` node)

METHODS = ["screen", "polygonal", "froxel", "reference"]


def die(msg):
    sys.stderr.write("volumetric_pictures: %s\n" % msg)
    sys.exit(1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "images", "volumetric"))
    ap.add_argument("--size", default="480x270")
    ap.add_argument("--ref-steps", type=int, default=512)
    ap.add_argument("--ref-spp", type=int, default=4)
    a = ap.parse_args()
    a.out = os.path.abspath(a.out)  # graphs name their files relative to their own folder
    exe = os.path.abspath(os.path.join(a.build, "lightgraph"))
    os.makedirs(a.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="vol-pictures-")  # the linear in-scatter EXRs stay out of git
    try:
        pictures(exe, a, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def pictures(exe, a, tmp):
    for m in METHODS:
        example = "volumetric_%s.lgraph" % m
        tone = re.search(r"^tone = .*$", open(os.path.join(ROOT, "examples", example)).read(),
                         re.M)
        if not tone:
            die("examples/%s: no `tone = ...` line" % example)
        g = os.path.join(tmp, m + ".lgraph")
        with open(g, "w") as f:
            f.write('lightgraph 1\ninclude "%s"\n%s\n%s\noutput tone "%s"\n'
                    'output vol.inscatter "%s"\n'
                    'tone_lv = reinhard { image = vol.inscatter, key = 0.18 }\n'
                    'output tone_lv "%s"\n'
                    % (os.path.join(ROOT, "examples", "volumetric_scene.lgraph"),
                       vol_block(example), tone.group(0), os.path.join(a.out, m + ".png"),
                       os.path.join(tmp, m + "_inscatter.exr"),
                       os.path.join(a.out, m + "_inscatter.png")))
        cmd = [exe, "render", g, "--size", a.size]
        if m == "reference":
            cmd += ["--set", "vol.steps=%d" % a.ref_steps, "--set", "vol.spp=%d" % a.ref_spp,
                    "--set", "vol.subpixel=centre"]
        sys.stderr.write("volumetric_pictures: %s\n" % " ".join(cmd))
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            die("%s failed:\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
    ref = os.path.join(tmp, "reference_inscatter.exr")
    _, _, ch = read_exr(ref)
    vals = [v for c in ("R", "G", "B") for v in ch[c]]
    ref_rms = math.sqrt(sum(v * v for v in vals) / len(vals))
    md = ["| method | image (tone-mapped `out`) | in-scatter error against the reference | "
          "relative RMSE |", "|---|---|---|---:|"]
    for m in METHODS:
        if m == "reference":
            md.append("| reference (%d steps, %d spp, pixel centres) | ![reference](images/volumetric/"
                      "reference.png) | | |" % (a.ref_steps, a.ref_spp))
            continue
        heat = os.path.join(a.out, "heat_%s.png" % m)
        r = subprocess.run([exe, "diff", os.path.join(tmp, m + "_inscatter.exr"), ref,
                            "--heatmap", heat, "--json"], capture_output=True, text=True)
        if r.returncode not in (0, 1):
            die("diff %s failed:\n%s%s" % (m, r.stdout, r.stderr))
        d = json.loads(r.stdout)
        md.append("| %s | ![%s](images/volumetric/%s.png) | ![heat](images/volumetric/heat_%s.png)"
                  " | %.4f |" % (m, m, m, m, d["rmse"] / ref_rms))
    with open(os.path.join(a.out, "pictures.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
