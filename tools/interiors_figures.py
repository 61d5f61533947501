#!/usr/bin/env python3
"""interiors_figures.py: the figures of docs/volumetric.md, "The thesis's interiors": the
generated classroom and courtyard (tools/gen_scene.py) and the thesis's artefact cases, each
as ours | volumetric_reference with the relative error of the in-scatter.

usage: tools/interiors_figures.py [--build DIR] [--out DIR] [--size WxH]
                                  [--ref-steps N] [--ref-spp N] [--quick]

Cases (all in the classroom, examples/classroom.lgraph's nodes; the scene generated into a
scratch folder, so nothing under out/ is needed):
  leak      the blinds closed (--slat-tilt 35: the slats face the sun and overlap), froxel
            at the example's grid: light the reference does not have leaks into the room
            through the thin slats and the window wall, which are thinner than a froxel
  grid      the blinds half open (the default), froxel at 40x23x32, 80x45x64 and 160x90x128:
            the slats' striped shafts are under-sampled by the coarser grids
  screen    the camera turned away from the windows (the sun and the openings off screen),
            volumetric_screen: no sky on screen, so no shafts, where the reference has them
and the two examples' own pictures (classroom.png, courtyard.png: the courtyard from
out/scenes/courtyard.glb, which `make scenes` writes; skipped with a note if it is absent)
with the triangle counts the program prints (--explain's scene features).

Writes PNGs (tone-mapped with Reinhard, key 0.18; in-scatter alone also tone-mapped) and
interiors.md (the tables, numbers included) into --out (default docs/images/interiors).
The relative error is `lightgraph diff`'s rel_rmse of the linear in-scatter (L_v alone)
against the reference's. Python 3.11 standard library; a few minutes (the three references
at 320 x 180, 256 steps, 2 rays per pixel through pixel centres).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# the camera node takes the name `fog` (the medium becomes fog0), so that shadowmap, phong and
# every vol node, which read `fog`, see the scene through it
CAMERA_AWAY = 'fog = camera { scene = fog0, mode = look_at, position = [1.2, 1.7, 1.2], ' \
              'target = [5.5, 1.0, 8.0], fov_deg = 55 }\n'
GRIDS = ["40x23x32", "80x45x64", "160x90x128"]


def die(msg):
    sys.stderr.write("interiors_figures: %s\n" % msg)
    sys.exit(1)


def run(cmd):
    sys.stderr.write("interiors_figures: %s\n" % " ".join(cmd))
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        die("`%s` failed (exit %d):\n%s%s" % (" ".join(cmd), r.returncode, r.stdout, r.stderr))
    return r


def node(text, name):
    m = re.search(r"^%s = [a-z_]+ \{\n.*?^\}" % name, text, re.S | re.M)
    if not m:
        die("no `%s = ... { ... }` block" % name)
    return m.group(0)


def triangles(exe, graph, tmp, sets=()):
    cmd = [exe, "render", graph, "--size", "16x9", "--explain", "-o",
           os.path.join(tmp, "explain.png")]
    for s in sets:
        cmd += ["--set", s]
    r = run(cmd)
    m = re.search(r"scene features \(scene\): triangles (\d+)", r.stdout + r.stderr)
    if not m:
        die("%s: --explain printed no scene features" % graph)
    return int(m.group(1))


class Figures:
    def __init__(self, a, tmp):
        self.a, self.tmp = a, tmp
        self.exe = os.path.abspath(os.path.join(a.build, "lightgraph"))
        self.example = open(os.path.join(ROOT, "examples", "classroom.lgraph")).read()

    def scene(self, tag, gen_args, camera=False):
        """The classroom example's scene nodes (up to vol) on a scene generated with
        gen_args; with camera, `cam` turned away from the windows in place of the file's."""
        glb = os.path.join(self.tmp, tag + ".glb")
        run([sys.executable, os.path.join(ROOT, "tools", "gen_scene.py"), "classroom", "-q",
             "-o", glb] + gen_args)
        text = self.example[:self.example.index(node(self.example, "vol"))]
        text = re.sub(r'file = "[^"]*"', 'file = "%s"' % glb, text)
        if camera:
            fog = node_line(text, "fog")
            text = text.replace(fog, fog.replace("fog = ", "fog0 = ", 1) + "\n" + CAMERA_AWAY)
        path = os.path.join(self.tmp, tag + "_scene.lgraph")
        with open(path, "w") as f:
            f.write(text)
        return path

    def render(self, scene, name, vol, sets=()):
        """Renders `vol` (a node block named vol) on `scene`: name.png (tone-mapped out),
        name_inscatter.png and a linear name_inscatter.exr in tmp; returns the EXR."""
        g = os.path.join(self.tmp, name + ".lgraph")
        exr = os.path.join(self.tmp, name + "_inscatter.exr")
        with open(g, "w") as f:
            f.write('lightgraph 1\ninclude "%s"\n%s\ntone = reinhard { image = vol, key = 0.18 }\n'
                    'tone_lv = reinhard { image = vol.inscatter, key = 0.18 }\n'
                    'output tone "%s"\noutput tone_lv "%s"\noutput vol.inscatter "%s"\n'
                    % (scene, vol, os.path.join(self.a.out, name + ".png"),
                       os.path.join(self.a.out, name + "_inscatter.png"), exr))
        cmd = [self.exe, "render", g, "--size", self.a.size]
        for s in sets:
            cmd += ["--set", s]
        run(cmd)
        return exr

    def reference(self, scene, name):
        z = re.search(r"z_limit = ([0-9.]+)", node(self.example, "vol")).group(1)
        return self.render(scene, name, "vol = volumetric_reference { scene = fog, base = lit, "
                           "z_limit = %s }" % z,
                           ["vol.steps=%d" % self.a.ref_steps, "vol.spp=%d" % self.a.ref_spp,
                            "vol.subpixel=centre"])

    def error(self, exr, ref):
        r = subprocess.run([self.exe, "diff", exr, ref, "--json"], capture_output=True, text=True)
        if r.returncode not in (0, 1):
            die("diff %s %s failed:\n%s" % (exr, ref, r.stderr))
        return json.loads(r.stdout)["rel_rmse"]


def node_line(text, name):
    m = re.search(r"^%s = .*$" % name, text, re.M)
    if not m:
        die("no `%s = ...` line" % name)
    return m.group(0)


def img(name):
    return "![%s](images/interiors/%s.png)" % (name, name)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "images", "interiors"))
    ap.add_argument("--size", default="320x180")
    ap.add_argument("--ref-steps", type=int, default=256)
    ap.add_argument("--ref-spp", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="64x36, 32 steps: a smoke run")
    a = ap.parse_args()
    if a.quick:
        a.size, a.ref_steps, a.ref_spp = "64x36", 32, 1
    a.out = os.path.abspath(a.out)
    os.makedirs(a.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="interiors-")
    try:
        md = figures(a, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    with open(os.path.join(a.out, "interiors.md"), "w") as f:
        f.write(md)
    print(md)


def figures(a, tmp):
    F = Figures(a, tmp)
    froxel = node(F.example, "vol")
    screen = ("vol = volumetric_screen { scene = fog, base = lit, z_limit = %s }"
              % re.search(r"z_limit = ([0-9.]+)", froxel).group(1))
    md = ["Made by `tools/interiors_figures.py` at %s, references with %d steps and %d rays "
          "per pixel through pixel centres. Error: relative RMSE of the linear in-scatter "
          "against the reference's (`lightgraph diff`'s rel_rmse)." % (a.size, a.ref_steps,
                                                                       a.ref_spp), ""]

    # leak: the blinds closed
    s = F.scene("leak", ["--slat-tilt", "35"])
    ref = F.reference(s, "leak_reference")
    e = F.error(F.render(s, "leak_froxel", froxel), ref)
    md += ["**Light leaking through thin gaps** (blinds closed, `--slat-tilt 35`; froxel "
           "160 x 90 x 128 on gl):", "",
           "| froxel | reference | froxel in-scatter | reference in-scatter | relative error |",
           "|---|---|---|---|---:|",
           "| %s | %s | %s | %s | %.3f |" % (img("leak_froxel"), img("leak_reference"),
                                            img("leak_froxel_inscatter"),
                                            img("leak_reference_inscatter"), e), ""]

    # grid: the default blinds under coarse grids
    s = F.scene("grid", [])
    ref = F.reference(s, "grid_reference")
    rows = []
    for gsize in GRIDS:
        w, h, d = gsize.split("x")
        name = "grid_froxel_%s" % gsize
        e = F.error(F.render(s, name, froxel, ["vol.width=" + w, "vol.height=" + h,
                                                "vol.depth=" + d]), ref)
        rows.append("| %s | %s | %s | %.3f |" % (gsize, img(name), img(name + "_inscatter"), e))
    md += ["**Blinds under-sampled by the froxel grid** (blinds half open, the default; froxel "
           "on gl; the reference: %s, in-scatter %s):" % (img("grid_reference"),
                                                          img("grid_reference_inscatter")), "",
           "| grid | froxel | in-scatter | relative error |", "|---|---|---|---:|"] + rows + [""]

    # screen: the openings off screen
    s = F.scene("screen", [], camera=True)
    ref = F.reference(s, "screen_reference")
    e_s = F.error(F.render(s, "screen_screen", screen), ref)
    e_f = F.error(F.render(s, "screen_froxel", froxel), ref)
    md += ["**Screen-space occlusion failure** (the camera turned away from the windows: the sun "
           "and the openings are off screen; volumetric_screen at 64 samples, froxel "
           "160 x 90 x 128 for comparison):", "",
           "| screen-space | froxel | reference | relative error (screen, froxel) |",
           "|---|---|---|---:|",
           "| %s | %s | %s | %.3f, %.3f |" % (img("screen_screen_inscatter"),
                                              img("screen_froxel_inscatter"),
                                              img("screen_reference_inscatter"), e_s, e_f), ""]

    # the examples' own pictures and triangle counts
    for ex in ("classroom", "courtyard"):
        graph = os.path.join(ROOT, "examples", ex + ".lgraph")
        if ex == "classroom":
            graph = os.path.join(tmp, "example_classroom.lgraph")
            with open(graph, "w") as f:
                f.write('lightgraph 1\ninclude "%s"\n' % F.scene("example", []))
                f.write(froxel + "\ntone = reinhard { image = vol, key = 0.18 }\n"
                        'output tone "%s"\n' % os.path.join(a.out, "classroom.png"))
        elif not os.path.exists(os.path.join(ROOT, "out", "scenes", "courtyard.glb")):
            md += ["(courtyard: out/scenes/courtyard.glb is absent; run `make scenes`)", ""]
            continue
        n = triangles(F.exe, graph, tmp)
        size = "960x540" if not a.quick else "64x36"
        run([F.exe, "render", graph, "--size", size, "-o", os.path.join(a.out, ex + ".png")])
        md += ["%s: %s triangles (`--explain`), %s" % (ex, "{:,}".format(n), img(ex)), ""]
    return "\n".join(md)


if __name__ == "__main__":
    main()
