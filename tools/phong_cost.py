#!/usr/bin/env python3
"""phong_cost.py: what shading accuracy costs (issue 4, item 4; plugins/phong/README.md).

usage: tools/phong_cost.py [--build DIR] [-o DIR] [--size WxH] [--levels 4,8,...]
                           [--frames K] [--repeat R] [--gl osmesa|egl]

Renders, with the phong node, a UV sphere at several tessellations (tools/gen_scene.py
sphere --level L: 4 L (L - 1) triangles) and the bunny box (examples/phong_scene.lgraph)
in every shading mode, and reports for each run

  time_ms      the phong node's time per frame: its CPU wall time including its GL work
               (glFinish; docs/devices.md), from `--profile-json` of a run of K + 1 frames
               minus a run of 1 frame, divided by K, so that shader compilation and
               llvmpipe's first-draw code generation are left out; median of R repeats
  gpu_ms       the same difference of the GL timer query (llvmpipe: rasterisation only; the
               compute pass of phong_half adds nothing there)
  rmse, max    against per-pixel Phong on the most finely tessellated sphere (for the
               bunny and the 16-light sphere: on the same mesh), linear radiance over RGB
               (`lightgraph diff`)
  rmse_same,   against per-pixel Phong on the same mesh: the shading method's own error,
  max_same     without the silhouette's

mixed_threshold_deg is varied on three scenes (mode "mixed@T"). The results go out
as CSV (phong_cost.csv), a gnuplot plot of error against time (phong_cost.png, and the
script phong_cost.gp), and heat maps of the per-pixel error (heat_<scene>_<mode>.png, the
maximum over RGB through a black-to-white ramp saturating at --heat-max) next to the
tone-free renders (img_<scene>_<mode>.png, clipped to [0, 1]).

A level-16 sphere under 16 directional lights shows where per-pixel lighting costs enough
for the cheaper methods to pay. The sphere's material has a pronounced highlight (kd 0.7, Od (0.8, 0.3, 0.2), ks 1, Os 0.8,
n 40) under one directional light, so that the seed's claims show: Gouraud loses the
highlight inside large facets; mixed costs close to Gouraud with quality close to Phong.
"""
import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys

MODES = ["flat", "gouraud", "phong", "mixed", "phong_half"]
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SPHERE_MATERIAL = '{"ka": 0.2, "kd": 0.7, "ks": 1, "od": [0.8, 0.3, 0.2], ' \
                  '"os": [0.8, 0.8, 0.8], "shininess": 40}'


def run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.stderr.write("command failed: %s\n%s%s" % (" ".join(cmd), r.stdout, r.stderr))
        sys.exit(1)
    return r


def sphere_graph(path, glb):
    with open(path, "w") as f:
        f.write('lightgraph 1\n'
                'scene = gltf { file = "%s" }\n'
                'lit = phong { scene = scene, ambient = [0.2, 0.2, 0.2], '
                'background = [0, 0, 0] }\n'
                'output lit "lit.exr"\n' % glb)


def bunny_graph(path):
    with open(path, "w") as f:
        f.write('lightgraph 1\n'
                'include "%s"\n'
                'lit = phong { scene = bulb, shadows = shadow, ambient = [0.3, 0.3, 0.3], '
                'ks_scale = 20, background = [0.02, 0.02, 0.03] }\n'
                'output lit "lit.exr"\n' % os.path.join(ROOT, "examples/phong_scene.lgraph"))


class Runner:
    def __init__(self, a):
        self.exe = os.path.join(a.build, "lightgraph")
        self.a = a
        self.env = dict(os.environ)
        self.env["LIGHTGRAPH_PLUGIN_PATH"] = ""

    def render(self, graph, out, mode, frames, profile=None):
        """mode: a shading mode, or mixed@T: mixed with mixed_threshold_deg = T."""
        cmd = [self.exe, "render", graph, "-o", out, "--size", self.a.size, "--gl", self.a.gl,
               "--frames", str(frames), "--set", "lit.shading=" + mode.split("@")[0],
               "--set", "lit.per_frame=true"]
        if "@" in mode:
            cmd += ["--set", "lit.mixed_threshold_deg=" + mode.split("@")[1]]
        if profile:
            cmd += ["--profile-json", profile]
        run(cmd, env=self.env)
        if profile:
            with open(profile) as f:
                nodes = json.load(f)["nodes"]
            n = [x for x in nodes if x["name"] == "lit"][0]
            return n["cpu_ms"], n["gpu_ms"]
        return None

    def time(self, graph, tmp, mode):
        """Per-frame time of `lit`: (T(K+1) - T(1)) / K, median of R repeats."""
        k = self.a.frames
        cpu, gpu = [], []
        for r in range(self.a.repeat):
            c1, g1 = self.render(graph, os.path.join(tmp, "t.exr"), mode, 1,
                                 os.path.join(tmp, "p1.json"))
            ck, gk = self.render(graph, os.path.join(tmp, "t.exr"), mode, k + 1,
                                 os.path.join(tmp, "pk.json"))
            cpu.append((ck - c1) / k)
            gpu.append((gk - g1) / k)
        return statistics.median(cpu), statistics.median(gpu)

    def diff(self, a, b, heat=None):
        cmd = [self.exe, "diff", a, b, "--json"]
        if heat:
            cmd += ["--heatmap", heat, "--heat-max", str(self.a.heat_max)]
        r = run(cmd, env=self.env)
        return json.loads(r.stdout)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("-o", "--out", default=os.path.join(ROOT, "out", "phong_cost"))
    p.add_argument("--size", default="640x360")
    p.add_argument("--levels", default="4,6,8,12,16,24,32,64,128")
    p.add_argument("--frames", type=int, default=24)
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--heat-max", type=float, default=0.5)
    p.add_argument("--gl", default="osmesa")
    p.add_argument("--thresholds", default="5,10,15,20,45",
                   help="mixed_threshold_deg values (besides the default 30) tried on "
                        "sphere16, sphere16_16lights and the bunny")
    a = p.parse_args()
    levels = [int(x) for x in a.levels.split(",")]
    os.makedirs(a.out, exist_ok=True)
    tmp = os.path.join(a.out, "tmp")
    os.makedirs(tmp, exist_ok=True)
    R = Runner(a)

    scenes = []
    for lv in levels:
        glb = os.path.join(tmp, "sphere_%d.glb" % lv)
        run([sys.executable, os.path.join(ROOT, "tools/gen_scene.py"), "sphere", "--level",
             str(lv), "--material-extras", SPHERE_MATERIAL, "--dir-light=-0.5,-0.6,-0.8,1.5",
             "--camera-pos", "0,0.4,3.2", "--camera-target", "0,0,0", "--yfov", "45", "-q",
             "-o", glb])
        g = os.path.join(tmp, "sphere_%d.lgraph" % lv)
        sphere_graph(g, glb)
        scenes.append(("sphere%d" % lv, g, 4 * lv * (lv - 1)))
    # the same sphere (level 16) under 16 directional lights: where per-pixel lighting is
    # expensive enough for the cheaper methods to pay on llvmpipe
    glb = os.path.join(tmp, "sphere16_16lights.glb")
    lights = []
    for i in range(16):
        t = 0.39 * i
        lights.append("--dir-light=%.4f,-0.5,%.4f,0.2" % (0.6 * math.cos(t),
                                                            0.6 * math.sin(t) - 0.6))
    run([sys.executable, os.path.join(ROOT, "tools/gen_scene.py"), "sphere", "--level", "16",
         "--material-extras", SPHERE_MATERIAL] + lights +
        ["--camera-pos", "0,0.4,3.2", "--camera-target", "0,0,0", "--yfov", "45", "-q",
         "-o", glb])
    g = os.path.join(tmp, "sphere16_16lights.lgraph")
    sphere_graph(g, glb)
    scenes.append(("sphere16_16lights", g, 4 * 16 * 15))
    g = os.path.join(tmp, "bunny.lgraph")
    bunny_graph(g)
    scenes.append(("bunny", g, 5009))

    # references: per-pixel Phong on the finest sphere, and on each mesh
    fine = os.path.join(tmp, "ref_fine.exr")
    R.render(scenes[len(levels) - 1][1], fine, "phong", 1)
    rows = []
    for name, graph, tris in scenes:
        same = os.path.join(tmp, "ref_%s.exr" % name)
        R.render(graph, same, "phong", 1)
        ref = fine if name.startswith("sphere") and "lights" not in name else same
        extra = []
        if name in ("sphere16", "sphere16_16lights", "bunny"):
            extra = ["mixed@" + t for t in a.thresholds.split(",") if t]
        for mode in MODES + extra:
            img = os.path.join(tmp, "%s_%s.exr" % (name, mode))
            R.render(graph, img, mode, 1)
            t_cpu, t_gpu = R.time(graph, tmp, mode)
            heat = os.path.join(a.out, "heat_%s_%s.png" % (name, mode))
            m = R.diff(img, ref, heat)
            ms = R.diff(img, same)
            shutil.copyfile(img, os.path.join(a.out, "img_%s_%s.exr" % (name, mode)))
            row = dict(scene=name, triangles=tris, mode=mode, time_ms=t_cpu, gpu_ms=t_gpu,
                       rmse=m["rmse"], max=m["max_abs"], rmse_same=ms["rmse"],
                       max_same=ms["max_abs"])
            rows.append(row)
            print("%-10s %-10s %8.3f ms (gpu %7.3f)  rmse %.5f max %.4f  same-mesh rmse %.5f "
                  "max %.4f" % (name, mode, t_cpu, t_gpu, row["rmse"], row["max"],
                                row["rmse_same"], row["max_same"]), flush=True)

    csv = os.path.join(a.out, "phong_cost.csv")
    with open(csv, "w") as f:
        f.write("scene,triangles,mode,time_ms,gpu_ms,rmse,max_abs,rmse_same_mesh,"
                "max_abs_same_mesh\n")
        for r in rows:
            f.write("%s,%d,%s,%.4f,%.4f,%.6g,%.6g,%.6g,%.6g\n" %
                    (r["scene"], r["triangles"], r["mode"], r["time_ms"], r["gpu_ms"],
                     r["rmse"], r["max"], r["rmse_same"], r["max_same"]))
    # PNG copies of the renders (clipped to [0, 1] by the PNG writer)
    for r in rows:
        src = os.path.join(a.out, "img_%s_%s.exr" % (r["scene"], r["mode"]))
        g = os.path.join(tmp, "topng.lgraph")
        with open(g, "w") as f:
            f.write('lightgraph 1\nsrc = image { file = "%s" }\noutput src "%s"\n' %
                    (src, src[:-4] + ".png"))
        run([R.exe, "render", g], env=R.env)
        os.remove(src)

    gp = os.path.join(a.out, "phong_cost.gp")
    spheres = [r for r in rows if r["scene"].startswith("sphere") and "lights" not in r["scene"]]
    with open(gp, "w") as f:
        # the spheres' rows per mode, as datablocks: triangles, time, rmse, rmse same mesh
        for mode in MODES:
            f.write("$%s << EOD\n" % mode)
            for r in spheres:
                if r["mode"] == mode:
                    f.write("%d %.6g %.6g %.6g\n" % (r["triangles"], r["time_ms"], r["rmse"],
                                                     r["rmse_same"]))
            f.write("EOD\n")
        f.write('set terminal pngcairo size 1500,440 font ",10" noenhanced\n'
                'set output "phong_cost.png"\n'
                'set multiplot layout 1,3\n'
                'set logscale xy\n'
                'set key top left\n'
                'set grid\n'
                'set title "spheres, 1 light: time per frame"\n'
                'set xlabel "triangles"\n'
                'set ylabel "phong node, ms per frame (llvmpipe, 640x360)"\n')
        f.write("plot " + ", \\\n     ".join(
            '$%s using 1:2 with linespoints lt %d pt %d title "%s"' % (m, i + 1, i + 4, m)
            for i, m in enumerate(MODES)) + "\n")
        f.write('set key top right\n'
                'set title "error against per-pixel Phong on the finest sphere"\n'
                'set xlabel "ms per frame"\n'
                'set ylabel "RMSE (linear radiance)"\n')
        f.write("plot " + ", \\\n     ".join(
            '$%s using 2:($3 > 0 ? $3 : 1/0) with linespoints lt %d pt %d title "%s"' %
            (m, i + 1, i + 4, m)
            for i, m in enumerate(MODES)) + "\n")
        f.write('set title "error against per-pixel Phong on the same mesh"\n'
                'set xlabel "triangles"\n')
        f.write("plot " + ", \\\n     ".join(
            '$%s using 1:4 with linespoints lt %d pt %d title "%s"' % (m, i + 1, i + 4, m)
            for i, m in enumerate(MODES) if m != "phong") + "\n")
        f.write("unset multiplot\n")
    if shutil.which("gnuplot"):
        subprocess.run(["gnuplot", "phong_cost.gp"], cwd=a.out, check=False)
    shutil.rmtree(tmp, ignore_errors=True)
    print("wrote %s, %s, phong_cost.png and heat maps in %s" % (csv, gp, a.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
