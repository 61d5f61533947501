#!/usr/bin/env python3
"""examples/volumetric_*.lgraph through the real program (issue 11, item 6 and "done when").

  render     each of the four examples (screen, polygonal, froxel, reference) renders at
             96 x 54 (the reference with 16 steps, 1 spp): `--explain` shows `vol` kept; a
             graph including the example writes `vol.inscatter` and `lit`: the in-scatter is
             finite, non-negative and positive somewhere in the fog, and the composited `out`
             differs from `lit`; `--set vol.backend=cl` and `cpu` render the froxel example
  gated      `--set fog.density=0` on every example: `vol` is gated ("no medium") and its
             plugin not loaded; `out` is `lit` unchanged (the same pixels) and `inscatter`
             black; the same with a scene whose only light is a point light ("no
             directional light"), except for the methods that model point lights
             (POINT_LIGHTS: froxel since issue 25), which are kept
  all        one graph holding all four methods (each reading the previous one's `out` as its
             base) with fog: all four run; with `fog.density = 0`: all four gated, none of
             their plugins loaded, and the shadow map still runs for Phong; and a graph where
             only polygonal reads the shadow map culls the shadow map too ("only gated nodes
             read it") and never loads the shadowmap plugin

The examples are copied with the assets they name (symbolic links) into a scratch folder,
so that their `output tone "../out/..."` lands there, never in the source tree.

usage: test_volumetric_example.py TEST_NAME
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import exr_read  # noqa: E402
import lgrun  # noqa: E402
from lgrun import Fail, check  # noqa: E402

SRC = os.environ["LG_SOURCE_ROOT"]
TMP = lgrun.temp_dir("lg-vol-example-")
W, H = 96, 54
SIZE = ["--size", "%dx%d" % (W, H)]
METHODS = ["screen", "polygonal", "froxel", "reference"]
FAST = {"reference": ["--set", "vol.steps=16", "--set", "vol.spp=1"],
        "froxel": ["--set", "vol.width=48", "--set", "vol.height=27", "--set", "vol.depth=32"]}
PLUGIN = {m: "volumetric_" + m for m in METHODS}


def tree():
    """TMP/examples/volumetric_*.lgraph, TMP/assets -> the source's assets, TMP/out."""
    os.makedirs(os.path.join(TMP, "examples"), exist_ok=True)
    os.makedirs(os.path.join(TMP, "out"), exist_ok=True)
    for m in METHODS + ["scene"]:
        shutil.copy(os.path.join(SRC, "examples", "volumetric_%s.lgraph" % m),
                    os.path.join(TMP, "examples"))
    if not os.path.exists(os.path.join(TMP, "assets")):
        os.symlink(os.path.join(SRC, "assets"), os.path.join(TMP, "assets"))
    return os.path.join(TMP, "examples")


def run(args, expect=0, timeout=600):
    return lgrun.run(args, lgrun.env("", os.path.join(TMP, "cache")), expect, timeout)


def row(text, node):
    return next((l for l in text.splitlines() if l.split()[:1] == [node]), "")


def loaded(text):
    line = next((l for l in text.splitlines() if l.startswith("plugins loaded:")), "")
    check(line, "no 'plugins loaded:' line in:\n%s" % text)
    return line.split(":", 1)[1].split()


def including(ex_dir, method, tag):
    """A graph including the example that also writes vol.inscatter and lit (linear)."""
    g = os.path.join(ex_dir, "inc_%s_%s.lgraph" % (method, tag))
    with open(g, "w") as f:
        f.write('lightgraph 1\ninclude "volumetric_%s.lgraph"\n' % method)
        for what, ref in (("inscatter", "vol.inscatter"), ("out", "vol"), ("lit", "lit")):
            f.write('output %s "../out/%s_%s_%s.exr"\n' % (ref, method, tag, what))
    return g


def images(method, tag):
    o = os.path.join(TMP, "out")
    return (exr_read.read_exr(os.path.join(o, "%s_%s_inscatter.exr" % (method, tag))),
            exr_read.read_exr(os.path.join(o, "%s_%s_out.exr" % (method, tag))),
            exr_read.read_exr(os.path.join(o, "%s_%s_lit.exr" % (method, tag))))


def test_render():
    ex = tree()
    for m in METHODS:
        g = including(ex, m, "fog")
        p = run(["render", g, "--explain"] + SIZE + FAST.get(m, []))
        text = p.stdout + p.stderr
        check("kept" in row(text, "vol"), "%s: vol not kept:\n%s" % (m, text))
        check(PLUGIN[m] in loaded(text), "%s: plugin not loaded:\n%s" % (m, text))
        ins, out, lit = images(m, "fog")
        vals = [c for r in ins for px in r for c in px[:3]]
        check(all(v == v and 0.0 <= v < 1e30 for v in vals),
              "%s: in-scatter not finite and >= 0" % m)
        check(max(vals) > 1e-3, "%s: no in-scatter anywhere (max %g)" % (m, max(vals)))
        diff = max(abs(a - b) for ro, rl in zip(out, lit) for po, pl in zip(ro, rl)
                   for a, b in zip(po[:3], pl[:3]))
        check(diff > 1e-3, "%s: out equals lit with fog" % m)
        check(os.path.exists(os.path.join(TMP, "out", "volumetric_%s.png" % m)),
              "%s: the example's own output was not written" % m)
    for b in ("cl", "cpu"):
        run(["render", os.path.join(ex, "volumetric_froxel.lgraph"), "--set", "vol.backend=" + b]
            + SIZE + FAST["froxel"])


# The methods that model point lights since issue 25 (froxel.h 4.): kept, not gated, when
# the only light is a point light.
POINT_LIGHTS = {"froxel"}


def test_gated():
    ex = tree()
    for m in METHODS:
        g = including(ex, m, "nofog")
        p = run(["render", g, "--explain", "--set", "fog.density=0"] + SIZE + FAST.get(m, []))
        text = p.stdout + p.stderr
        r = row(text, "vol")
        check("gated" in r and "medium" in r, "%s: vol not gated for want of a medium:\n%s"
              % (m, text))
        check(PLUGIN[m] not in loaded(text), "%s: its plugin was loaded:\n%s" % (m, text))
        ins, out, lit = images(m, "nofog")
        check(all(v == 0.0 for r_ in ins for px in r_ for v in px[:3]),
              "%s: gated in-scatter is not black" % m)
        check(out == lit, "%s: gated out is not lit unchanged" % m)
        # the only light a point light: no directional light
        p = run(["render", g, "--explain", "--set", "sun.type=point",
                 "--set", "sun.position=[0,1.5,0]"] + SIZE + FAST.get(m, []))
        text = p.stdout + p.stderr
        r = row(text, "vol")
        if m in POINT_LIGHTS:
            check("kept" in r, "%s: vol not kept with a point light:\n%s" % (m, text))
            continue
        check("gated" in r and "directional" in r,
              "%s: vol not gated for want of a directional light:\n%s" % (m, text))
        check(PLUGIN[m] not in loaded(text), "%s: its plugin was loaded:\n%s" % (m, text))


ALL = """lightgraph 1
include "volumetric_scene.lgraph"
s = volumetric_screen { scene = fog, base = lit, samples = 8 }
p = volumetric_polygonal { scene = fog, base = s, shadows = shadow, resolution = 64 }
f = volumetric_froxel { scene = fog, base = p, shadows = shadow, width = 16, height = 9, depth = 16 }
r = volumetric_reference { scene = fog, base = f, steps = 8, spp = 1 }
output r "../out/all.exr"
"""

ONLY_POLY = """lightgraph 1
scene = gltf { file = "../assets/meshes/bunny_cornell_box.glb" }
sun = light { scene = scene, direction = [0.3, -0.35, 1], intensity = 10 }
fog = medium { scene = sun, density = 0 }
shadow = shadowmap { scene = fog, resolution = 256 }
lit = phong { scene = fog }
vol = volumetric_polygonal { scene = fog, base = lit, shadows = shadow }
output vol "../out/only_poly.exr"
"""


def test_all():
    ex = tree()
    g = os.path.join(ex, "all.lgraph")
    with open(g, "w") as f:
        f.write(ALL)
    p = run(["render", g, "--explain"] + SIZE)
    text = p.stdout + p.stderr
    for n in "spfr":
        check("kept" in row(text, n), "%s not kept with fog:\n%s" % (n, text))
    p = run(["render", g, "--explain", "--set", "fog.density=0"] + SIZE)
    text = p.stdout + p.stderr
    for n in "spfr":
        check("gated" in row(text, n), "%s not gated without fog:\n%s" % (n, text))
    for m in METHODS:
        check(PLUGIN[m] not in loaded(text), "%s loaded without fog:\n%s" % (PLUGIN[m], text))
    check("kept" in row(text, "shadow"), "the shadow map Phong reads was culled:\n%s" % text)
    g = os.path.join(ex, "only_poly.lgraph")
    with open(g, "w") as f:
        f.write(ONLY_POLY)
    p = run(["render", g, "--explain"] + SIZE)
    text = p.stdout + p.stderr
    r = row(text, "shadow")
    check("culled" in r and "only gated nodes read it" in r,
          "the shadow map only the gated polygonal node reads is not culled:\n%s" % text)
    check("shadowmap" not in loaded(text), "the shadowmap plugin was loaded:\n%s" % text)


TESTS = {"render": test_render, "gated": test_gated, "all": test_all}

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
