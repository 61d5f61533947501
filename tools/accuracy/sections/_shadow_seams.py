"""The shadowmap section's Custom study `shadow_point_seams`: a point light's cube against exact
visibility, its error split between the seam pixels (the lookup point within r + 1 texels of
its cube face's edge, so that some of the (2 r + 1)^2 PCF taps lie past the face's 90 degrees,
in the margin that holds the neighbouring face's content drawn again) and the rest.

    python3 _shadow_seams.py --lightgraph PROG --graph G --reference R --out DIR [--quick]

G is the section's point-light graph (its `lit` output, nodes `lamp`, `shadow`), R its
reference (`ref = shadow_reference`, one output). The reference is rendered once with its
`position` output (the surface point of each pixel centre), then G at every resolution and
pcf_radius; each row is one region of one run: its relative RMSE is the region's RMSE over
the whole reference image's RMS (the image metric's denominator), its time
the run's whole render (--profile-json: planning and execution). Writes DIR/rows.csv. Plain
Python 3.11 standard library.
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from accuracy.exr import read_exr  # noqa: E402


def die(msg):
    sys.stderr.write("_shadow_seams: %s\n" % msg)
    sys.exit(1)


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        die("`%s` failed (exit %d):\n%s" % (" ".join(cmd), r.returncode, r.stderr[-3000:]))


def render(prog, graph, size, sets, out, tag):
    """Renders `graph` (its outputs where it names them), returns the whole render's ms."""
    prof = os.path.join(out, "profile_%s.json" % tag)
    cmd = [prog, "render", graph, "--size", size, "--no-cache", "--profile-json", prof]
    for s in sets:
        cmd += ["--set", s]
    run(cmd)
    with open(prof) as f:
        pj = json.load(f)
    return pj["planning_ms"] + pj["execution_ms"]


def rgb(path):
    w, h, ch = read_exr(path)
    return w, h, ch["R"], ch["G"], ch["B"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lightgraph", required=True)
    ap.add_argument("--graph", required=True)
    ap.add_argument("--reference", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    size = "96x54" if a.quick else "320x180"
    resolutions = [256] if a.quick else [256, 512, 1024, 2048]
    radii = [0, 2] if a.quick else [0, 1, 2, 4]

    with open(a.graph) as f:
        gtext = f.read()
    with open(a.reference) as f:
        rtext = f.read()
    m = re.search(r"position = \[([^\]]*)\]", gtext)
    if not m:
        die("%s: the light has no position" % a.graph)
    q = [float(v) for v in m.group(1).split(",")]
    # the copies this study renders: the reference with its position output, the graph into
    # this study's folder
    ref_exr, pos_exr = os.path.join(a.out, "reference.exr"), os.path.join(a.out, "position.exr")
    rtext = re.sub(r'output ref "[^"]*"', 'output ref "%s"' % ref_exr, rtext)
    rtext += 'output ref.position "%s"\n' % pos_exr
    rgraph = os.path.join(a.out, "reference.lgraph")
    with open(rgraph, "w") as f:
        f.write(rtext)
    lit_exr = os.path.join(a.out, "lit.exr")
    ggraph = os.path.join(a.out, "graph.lgraph")
    with open(ggraph, "w") as f:
        f.write(re.sub(r'output lit "[^"]*"', 'output lit "%s"' % lit_exr, gtext))

    ref_ms = render(a.lightgraph, rgraph, size, [], a.out, "ref")
    w, h, rr, rg, rb = rgb(ref_exr)
    pw, ph, pch = read_exr(pos_exr)
    if (pw, ph) != (w, h):
        die("position %dx%d, reference %dx%d" % (pw, ph, w, h))
    px, py, pz, pa = pch["R"], pch["G"], pch["B"], pch["A"]
    ref_ms2 = sum(v * v for c in (rr, rg, rb) for v in c) / (3.0 * w * h)
    ref_rms = math.sqrt(ref_ms2)
    # each surface pixel's position on its cube face: the largest of |minor / major|, 1 at
    # the face's edge (90 degrees)
    edge = []
    for i in range(w * h):
        if pa[i] <= 0.0:
            edge.append(None)
            continue
        d = [px[i] - q[0], py[i] - q[1], pz[i] - q[2]]
        ad = [abs(v) for v in d]
        k = max(range(3), key=lambda j: ad[j])
        if ad[k] <= 0.0:
            edge.append(None)
            continue
        edge.append(max(ad[j] / ad[k] for j in range(3) if j != k))

    rows = []
    for res in resolutions:
        for r in radii:
            tag = "%d_%d" % (res, r)
            ms = render(a.lightgraph, ggraph, size,
                        ["shadow.resolution=%d" % res, "shadow.pcf_radius=%d" % r], a.out, tag)
            lw, lh, lr, lg_, lb = rgb(lit_exr)
            if (lw, lh) != (w, h):
                die("lit %dx%d, reference %dx%d" % (lw, lh, w, h))
            # the face's half-width in tangent units grows by the margin of m = normal_offset
            # + 1 + r texels (plugins/shadowmap/README.md, "Spot and point lights"); a texel
            # is 2 t / res of it; taps cross the edge within r + 1 texels of it
            m_tex = 1 + 1 + r
            t = res / float(res - 2 * m_tex)
            band = 1.0 - (r + 1) * 2.0 * t / res
            acc = {"seams": [0.0, 0], "elsewhere": [0.0, 0]}
            for i in range(w * h):
                e = edge[i]
                if e is None:
                    continue
                region = "seams" if e > band else "elsewhere"
                s = ((lr[i] - rr[i]) ** 2 + (lg_[i] - rg[i]) ** 2 + (lb[i] - rb[i]) ** 2)
                acc[region][0] += s
                acc[region][1] += 1
            for region in ("seams", "elsewhere"):
                sq, n = acc[region]
                # the region's RMSE per pixel, over the whole reference's RMS (the image
                # metric's denominator, so that the two regions compare with each other and
                # with the image's rel_rmse)
                rmse = math.sqrt(sq / (3.0 * n)) if n else 0.0
                rel = rmse / ref_rms if ref_rms > 0 else 0.0
                rows.append({"region": region, "shadow.resolution": res,
                             "shadow.pcf_radius": r, "pixels": n, "time_ms": "%.3f" % ms,
                             "time_min_ms": "", "time_max_ms": "", "rmse": "%.6g" % rmse,
                             "rel_rmse": "%.6g" % rel, "ssim": "", "dssim": "",
                             "ref_ms": "%.3f" % ref_ms})
    with open(os.path.join(a.out, "rows.csv"), "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        wr.writerows(rows)


if __name__ == "__main__":
    main()
