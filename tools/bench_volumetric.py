#!/usr/bin/env python3
"""bench_volumetric.py: the volumetric thesis's experiments reproduced (issue 11, item 3; seed 2,
chapter 4). docs/volumetric.md ("The thesis's experiments") has the figures.

usage: tools/bench_volumetric.py [--build DIR] [--out DIR] [--size WxH] [--frames N]
                                 [--scenes bunny,dragon,dragons] [--lights 1,2,4,...]
                                 [--methods screen,polygonal,froxel_gl,froxel_cl,froxel_cpu]
                                 [--shadow-resolution R] [--quick]

Every run is `lightgraph render` of a generated graph: a scene, a camera, N directional
lights (`light` nodes), the thesis's fog (density 1, C_s = 0.1, g = 0.4), shadow maps
(1024^2 per light), Phong, and one volumetric node with `per_frame = true`, over --frames
frames (default 8). The node's time per frame is its steady-state CPU wall time (GL work
included: the GL nodes finish their work inside execute) from --profile-json: the mean over
frames 2..N, and the minimum. Memory: the node's bytes allocated (its outputs, and what it
allocates itself through lg_account_alloc: polygonal's per-light meshes, the froxel
scattering volume and its history), and the shadow node's (its atlas grows with the lights).

Experiment 1 (thesis tables 6-8): one light, the three methods (froxel on gl, cl and cpu) on
the bunny box (assets/meshes/bunny_cornell_box.glb, 4,968 triangles with its walls), the
Stanford dragon (assets/meshes/dragon_vrip_draco.glb, 871k triangles) and six instanced
dragons (assets/meshes/dragon_vrip_x6_instanced_draco.glb, 5.2M triangles drawn).

Experiment 2 (thesis figures 4.x): the bunny box with 1, 2, 4, 8, 16 and 32 lights, every
method and froxel backend: time and memory.

The thesis's parameters are the defaults (TECHNIQUES.md §6): output 2134 x 1459, shadow maps
1024^2, froxel grid 190 x 90 x 128, 64 screen-space samples with exposure 1, decay 0.94 and
weight 0.01, polygonal one mesh vertex per shadow-map texel, z_limit 17.6 on the bunny box.
--quick: 534 x 365, 4 frames, lights 1, 4, 16 (a smoke run).

Ratios are what to read (these machines are shared and noisy): every number of a table
comes from the same run. Writes DIR (default out/bench_volumetric): bench_volumetric.md
(the tables), scenes.csv, lights.csv, lights_time.png and lights_memory.png (gnuplot).
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SCENES = {
    # name: (file, camera lines, triangles as the thesis counts them)
    "bunny": ("assets/meshes/bunny_cornell_box.glb",
              "cam = camera { scene = scene, mode = look_at, position = [0.55, 1.45, 0.95], "
              "target = [-0.05, 0.55, -1.5], fov_deg = 70 }\n", "4,968"),
    "dragon": ("assets/meshes/dragon_vrip_draco.glb",
               "cam = camera { scene = scene, mode = orbit, azimuth_deg = 30, "
               "elevation_deg = 20 }\n", "871,306"),
    "dragons": ("assets/meshes/dragon_vrip_x6_instanced_draco.glb",
                "cam = camera { scene = scene, mode = orbit, azimuth_deg = 30, "
                "elevation_deg = 25 }\n", "5,227,836"),
}

METHODS = {
    "screen": ("volumetric_screen", "backend = gl, samples = 64, exposure = 1, decay = 0.94, "
               "weight = 0.01", False),
    "polygonal": ("volumetric_polygonal", "resolution = 0", True),
    "froxel_gl": ("volumetric_froxel", "backend = gl, width = 190, height = 90, depth = 128", True),
    "froxel_cl": ("volumetric_froxel", "backend = cl, width = 190, height = 90, depth = 128", True),
    "froxel_cpu": ("volumetric_froxel", "backend = cpu, width = 190, height = 90, depth = 128",
                   True),
}


def die(msg):
    sys.stderr.write("bench_volumetric: %s\n" % msg)
    sys.exit(1)


def light_dirs(n):
    """n sun directions (the direction the light travels) on a cone of 30 degrees around the
    bunny box's sun, spread in azimuth: every light shines in through the open side."""
    base = (0.3, -0.35, 1.0)
    bl = math.sqrt(sum(c * c for c in base))
    b = [c / bl for c in base]
    # an orthonormal frame around b
    up = (0.0, 1.0, 0.0)
    t = [b[1] * up[2] - b[2] * up[1], b[2] * up[0] - b[0] * up[2], b[0] * up[1] - b[1] * up[0]]
    tl = math.sqrt(sum(c * c for c in t))
    t = [c / tl for c in t]
    s = [b[1] * t[2] - b[2] * t[1], b[2] * t[0] - b[0] * t[2], b[0] * t[1] - b[1] * t[0]]
    out = []
    for k in range(n):
        if n == 1:
            out.append(b)
            continue
        a = 2 * math.pi * k / n
        r = math.tan(math.radians(30)) * (0.5 + 0.5 * (k % 2))
        d = [b[i] + r * (math.cos(a) * t[i] + math.sin(a) * s[i]) for i in range(3)]
        dl = math.sqrt(sum(c * c for c in d))
        out.append([c / dl for c in d])
    return out


def graph(scene, method, n_lights, shadow_res):
    path, cam, _ = SCENES[scene]
    node, params, uses_shadows = METHODS[method]
    g = ["lightgraph 1", 'scene = gltf { file = "%s" }' % os.path.join(ROOT, path), cam.strip()]
    prev = "cam"
    for k, d in enumerate(light_dirs(n_lights)):
        mode = ", mode = replace" if k == 0 else ""
        g.append("l%d = light { scene = %s%s, direction = [%.6f, %.6f, %.6f], intensity = %g }"
                 % (k, prev, mode, d[0], d[1], d[2], 10.0 / n_lights))
        prev = "l%d" % k
    g.append("fog = medium { scene = %s, density = 1, scattering = [0.1, 0.1, 0.1], g = 0.4 }"
             % prev)
    g.append("shadow = shadowmap { scene = fog, resolution = %d }" % shadow_res)
    g.append("lit = phong { scene = fog, shadows = shadow, background = [0.6, 0.7, 0.9] }")
    zl = ", z_limit = 17.6" if scene == "bunny" else ""
    sh = ", shadows = shadow" if uses_shadows else ""
    g.append("vol = %s { scene = fog, base = lit%s, %s%s, per_frame = true }"
             % (node, sh, params, zl))
    return "\n".join(g) + "\n"


def run(exe, text, size, frames, tmp):
    gpath = os.path.join(tmp, "g.lgraph")
    with open(gpath, "w") as f:
        f.write(text + 'output vol "vol.exr"\n')
    prof = os.path.join(tmp, "p.json")
    cmd = [exe, "render", gpath, "--size", size, "--frames", str(frames),
           "--profile-json", prof]
    env = dict(os.environ, LIGHTGRAPH_CACHE_DIR=os.path.join(tmp, "cache"))
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        die("%s failed (exit %d):\n%s\n%s%s" % (" ".join(cmd), r.returncode, text, r.stdout,
                                                r.stderr))
    with open(prof) as f:
        p = json.load(f)
    nodes = {n["name"]: n for n in p["nodes"]}
    v = nodes["vol"]
    if v.get("state") != "kept":
        die("vol was not run (%s):\n%s" % (v.get("reason"), text))
    runs = v["runs"]
    steady = (v["cpu_ms"] - v["first_cpu_ms"]) / (runs - 1) if runs > 1 else v["cpu_ms"]
    return {"ms": steady, "min_ms": v["min_cpu_ms"], "first_ms": v["first_cpu_ms"],
            "bytes": v["bytes_allocated"], "shadow_bytes": nodes["shadow"]["bytes_allocated"],
            "lit_ms": nodes["lit"]["cpu_ms"] / max(1, nodes["lit"]["runs"]),
            "shadow_ms": nodes["shadow"]["cpu_ms"] / max(1, nodes["shadow"]["runs"])}


def mib(b):
    return b / (1024.0 * 1024.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench_volumetric"))
    ap.add_argument("--size", default="2134x1459")
    ap.add_argument("--frames", type=int, default=8)
    ap.add_argument("--scenes", default="bunny,dragon,dragons")
    ap.add_argument("--lights", default="1,2,4,8,16,32")
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--shadow-resolution", type=int, default=1024)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    if a.quick:
        a.size, a.frames, a.lights = "534x365", 4, "1,4,16"
    exe = os.path.join(a.build, "lightgraph")
    if not os.path.exists(exe):
        die("%s does not exist: build first (meson setup build && ninja -C build)" % exe)
    methods = a.methods.split(",")
    for m in methods:
        if m not in METHODS:
            die("unknown method %s (known: %s)" % (m, ", ".join(METHODS)))
    scenes = a.scenes.split(",")
    for s in scenes:
        if s not in SCENES:
            die("unknown scene %s (known: %s)" % (s, ", ".join(SCENES)))
    lights = [int(x) for x in a.lights.split(",")]
    if any(n < 1 or n > 32 for n in lights):
        die("--lights: 1 .. 32 each")
    os.makedirs(a.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="bench-vol-")
    md = ["# Volumetric lighting: the thesis's experiments (tools/bench_volumetric.py)", "",
          "Output %s, %d frames per run, shadow maps %d^2, froxel grid 190 x 90 x 128, "
          "screen-space 64 samples. Times: the `vol` node's CPU wall time per frame (GL work "
          "included), mean of frames 2..%d (min in brackets). Shadow maps and Phong run once per "
          "run (the scene is static): their time, the triangle count's share, is a column of "
          "its own; polygonal and froxel need the shadow maps, screen-space does not."
          % (a.size, a.frames, a.shadow_resolution, a.frames), ""]
    try:
        # experiment 1
        rows = []
        md += ["## Time per method and scene, one light", "",
               "| scene | triangles | " + " | ".join(methods) +
               " | shadow maps (once) | phong (once) |",
               "|---|---:|" + "---:|" * (len(methods) + 2)]
        for s in scenes:
            cells, lit, shadow_ms = [], None, None
            for m in methods:
                r = run(exe, graph(s, m, 1, a.shadow_resolution), a.size, a.frames, tmp)
                rows.append((s, m, r))
                cells.append("%.1f (%.1f)" % (r["ms"], r["min_ms"]))
                lit, shadow_ms = r["lit_ms"], r["shadow_ms"]
                sys.stderr.write("scene %s %s: %.2f ms\n" % (s, m, r["ms"]))
            md.append("| %s | %s | %s | %.1f | %.1f |" % (s, SCENES[s][2], " | ".join(cells),
                                                          shadow_ms, lit))
        with open(os.path.join(a.out, "scenes.csv"), "w") as f:
            f.write("scene,method,ms,min_ms,first_ms,bytes\n")
            for s, m, r in rows:
                f.write("%s,%s,%.4f,%.4f,%.4f,%d\n" % (s, m, r["ms"], r["min_ms"], r["first_ms"],
                                                      r["bytes"]))
        # ratios within the run
        md += ["", "Ratios (same run): " + "; ".join(
            "%s: %s" % (s, ", ".join("%s %.2fx" % (m, r["ms"] / min(rr["ms"] for ss, mm, rr in rows
                                                                    if ss == s))
                                     for ss, m, r in rows if ss == s)) for s in scenes) +
            " (1.00x = the fastest method on that scene).", ""]
        # experiment 2
        rows2 = []
        md += ["## Time and memory against the number of lights (bunny box)", "",
               "| lights | " + " | ".join("%s ms" % m for m in methods) + " | " +
               " | ".join("%s MiB" % m for m in methods) + " | shadow maps MiB |",
               "|---:|" + "---:|" * (2 * len(methods) + 1)]
        for n in lights:
            res = []
            for m in methods:
                r = run(exe, graph("bunny", m, n, a.shadow_resolution), a.size, a.frames, tmp)
                res.append(r)
                rows2.append((n, m, r))
                sys.stderr.write("lights %d %s: %.2f ms, %.1f MiB\n" % (n, m, r["ms"],
                                                                       mib(r["bytes"])))
            md.append("| %d | %s | %s | %.1f |" % (
                n, " | ".join("%.1f" % r["ms"] for r in res),
                " | ".join("%.1f" % mib(r["bytes"]) for r in res), mib(res[0]["shadow_bytes"])))
        with open(os.path.join(a.out, "lights.csv"), "w") as f:
            f.write("lights,method,ms,min_ms,bytes,shadow_bytes\n")
            for n, m, r in rows2:
                f.write("%d,%s,%.4f,%.4f,%d,%d\n" % (n, m, r["ms"], r["min_ms"], r["bytes"],
                                                    r["shadow_bytes"]))
        # linearity: least-squares slope and intercept per method, and R^2
        md += ["", "Linear fits, time = a + b x lights (ms): " + "; ".join(
            "%s a %.1f b %.2f R^2 %.3f" % ((m,) + fit([(n, r["ms"]) for n, mm, r in rows2
                                                       if mm == m]))
            for m in methods) + ".", ""]
        # experiment 3: the promise "simulate only what the scene calls for"
        md += gating_cost(exe, a, tmp)
        with open(os.path.join(a.out, "bench_volumetric.md"), "w") as f:
            f.write("\n".join(md) + "\n")
        plot(a.out, methods)
        print("\n".join(md))
        print("written: %s" % a.out)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def gating_cost(exe, a, tmp):
    """A frame of the bunny box without fog, by a graph that holds all three methods (and
    the reference) and by the same graph without them: planning and execution time (means of
    5 runs each, alternated), plugins loaded."""
    base = graph("bunny", "froxel_cpu", 1, a.shadow_resolution).split("\n")
    base = [l for l in base if l and not l.startswith("vol =")]
    base = [l.replace("density = 1,", "density = 0,") for l in base]
    base = [l.replace("phong { ", "phong { per_frame = true, ") for l in base]
    without = "\n".join(base) + "\noutput lit \"vol.exr\"\n"
    with_ = "\n".join(base + [
        "s = volumetric_screen { scene = fog, base = lit }",
        "p = volumetric_polygonal { scene = fog, base = s, shadows = shadow }",
        "f = volumetric_froxel { scene = fog, base = p, shadows = shadow }",
        "r = volumetric_reference { scene = fog, base = f }"]) + "\noutput r \"vol.exr\"\n"
    res = {"with": [], "without": []}
    loaded = {}
    for k in range(5):
        for name, text in (("without", without), ("with", with_)):
            gpath = os.path.join(tmp, "gate_%s.lgraph" % name)
            with open(gpath, "w") as f:
                f.write(text)
            prof = os.path.join(tmp, "gate.json")
            r = subprocess.run([exe, "render", gpath, "--size", a.size, "--frames", str(a.frames),
                                "--profile-json", prof, "--explain"], capture_output=True,
                               text=True, env=dict(os.environ,
                                                   LIGHTGRAPH_CACHE_DIR=os.path.join(tmp, "c")))
            if r.returncode != 0:
                die("gating run failed:\n%s\n%s%s" % (text, r.stdout, r.stderr))
            with open(prof) as f:
                p = json.load(f)
            res[name].append((p["planning_ms"], p["execution_ms"]))
            loaded[name] = next((l for l in r.stdout.splitlines()
                                 if l.startswith("plugins loaded:")), "")
    mean = {n: (sum(x for x, _ in v) / len(v), sum(y for _, y in v) / len(v))
            for n, v in res.items()}
    return ["## No fog: the graph with every method costs what the graph without them costs", "",
            "| graph | planning ms | frames ms (%d frames) | %s |" % (a.frames, "plugins loaded"),
            "|---|---:|---:|---|",
            "| without the volumetric nodes | %.1f | %.1f | %s |" % (
                mean["without"] + (loaded["without"].split(":", 1)[-1].strip(),)),
            "| with screen, polygonal, froxel and reference, fog density 0 | %.1f | %.1f | %s |"
            % (mean["with"] + (loaded["with"].split(":", 1)[-1].strip(),)),
            "", "Ratio with / without: planning %.3f, frames %.3f (means of 5 alternated runs)."
            % (mean["with"][0] / mean["without"][0], mean["with"][1] / mean["without"][1]), ""]


def fit(pts):
    n = len(pts)
    if n < 2:
        return (pts[0][1] if pts else 0.0, 0.0, 1.0)
    mx = sum(x for x, _ in pts) / n
    my = sum(y for _, y in pts) / n
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    sxy = sum((x - mx) * (y - my) for x, y in pts)
    b = sxy / sxx if sxx > 0 else 0.0
    a0 = my - b * mx
    ss_tot = sum((y - my) ** 2 for _, y in pts)
    ss_res = sum((y - a0 - b * x) ** 2 for x, y in pts)
    return (a0, b, 1.0 - ss_res / ss_tot if ss_tot > 0 else 1.0)


def plot(out, methods):
    """lights_time.png and lights_memory.png from lights.csv: one line per method (a data file
    each, since gnuplot breaks a line at every filtered-out row), log scale in y."""
    if not shutil.which("gnuplot"):
        sys.stderr.write("bench_volumetric: gnuplot not found: no plots\n")
        return
    rows = [l.strip().split(",") for l in open(os.path.join(out, "lights.csv"))][1:]
    for m in methods:
        with open(os.path.join(out, "lights_%s.dat" % m), "w") as f:
            for r in rows:
                if r[1] == m:
                    f.write("%s %s %s\n" % (r[0], r[2], int(r[4]) / 1048576.0))
    for what, col, label in (("time", 2, "time per frame (ms)"),
                             ("memory", 3, "node memory (MiB)")):
        gp = os.path.join(out, "lights_%s.gp" % what)
        with open(gp, "w") as f:
            f.write("set terminal pngcairo size 900,600 noenhanced\n")
            f.write("set output '%s'\n" % os.path.join(out, "lights_%s.png" % what))
            f.write("set grid\nset key left top\nset logscale xy\nset xtics (1, 2, 4, 8, 16, 32)\n")
            f.write("set xlabel 'directional lights'\nset ylabel '%s'\n" % label)
            f.write("set title 'volumetric methods against the number of lights (bunny box)'\n")
            f.write("plot " + ", \\\n     ".join(
                "'%s' using 1:%d with linespoints title '%s'"
                % (os.path.join(out, "lights_%s.dat" % m), col, m) for m in methods) + "\n")
        subprocess.run(["gnuplot", gp], check=False)


if __name__ == "__main__":
    main()
