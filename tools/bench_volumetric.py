#!/usr/bin/env python3
"""bench_volumetric.py: the volumetric thesis's experiments, reported as they came out (issue 11,
item 3; issue 24, item 5; seed 2, chapter 4). docs/volumetric.md ("The thesis's experiments")
has the figures.

usage: tools/bench_volumetric.py [--build DIR] [--out DIR] [--size WxH] [--frames N]
                                 [--repeat R] [--experiments crossover,table6,lights,gating]
                                 [--scenes bunny,dragon,dragons,classroom,courtyard]
                                 [--crossover-scenes bunny,dragon] [--sizes W1xH1,...]
                                 [--lights 1,2,4,8,16,32]
                                 [--light-types directional,point,spot]
                                 [--methods screen,polygonal,...]
                                 [--shadow-resolution R] [--max-seconds S] [--quick]
       tools/bench_volumetric.py --self-test

Every run is `lightgraph render -v` of a generated graph: a scene, a camera, N directional
lights (`light` nodes), the thesis's fog (density 1, C_s = 0.1, g = 0.4), shadow maps
(1024^2 per light), Phong, and one volumetric node with `per_frame = true` over --frames
frames (default 2: the steady time is the second frame's); method "disabled" is the same
graph without the volumetric node. From --profile-json: the node's steady time per frame
(CPU wall time, GL work included: the GL nodes finish their work inside execute), the mean
over frames 2..N; the shadow maps' and
Phong's time (they run once: the scene is static); every node's peak memory
(`bytes_allocated`: its outputs plus the most its plugin held at once, split into
`resource_bytes` and `plugin_bytes_peak`). From --explain: the scene's triangle count as
the loader built it (`scene features`), never typed in. From the polygonal node's log line
(`volume pass: ...`, GL query objects around its light-volume draws): the triangles it draws,
the fragments they make, per pixel.

Each configuration runs --repeat times (default 3), the configurations of one repeat in
turn (so that a slow spell of this shared machine hits every method alike); a table cell is
the median with the min-max in brackets. The frame time is shadow maps + Phong + the
method's node, as the thesis's Table 6 counts it (a "disabled" frame: shadow maps + Phong).

Experiments:
  crossover  time against output size (--sizes, default 6 from 256x175 to 1920x1313) for
             every method and "disabled" on --crossover-scenes; where the ranking flips
             (log-log interpolation between the sizes that bracket a change of sign);
             crossover_<scene>.png (gnuplot, log-log), crossover.csv
  table6     the thesis's Table 6 per scene at --size: triangles (measured), frame time per
             method and "disabled"; the polygonal node's counters per scene (triangles drawn,
             fragments per pixel) beside the scene's triangles and the shadow maps' time;
             table6.csv, polygonal.csv
  lights     the bunny box with --lights lights (default 1, 2, 4, 8, 16, 32) of each of
             --light-types (default directional, point, spot; issue 25): time and peak
             memory per method, with the split of memory into outputs and own allocations;
             point lights on a ring in the box around the bunny, spots on a ring under the
             ceiling shining down (light_places); a method whose `needs` (lightgraph inspect)
             do not cover a light type is "n/a" there (it would be gated, not timed). The
             directional rows are printed beside docs/volumetric.md's table of the same
             experiment ("Memory against the number of lights"): a homogeneous-fog
             directional scene must cost what it cost before issue 25 (same size and load
             assumed: the page's run says its own); lights.csv, lights_time.png,
             lights_memory.png. --max-seconds S: once a method's run of one light type took
             longer than S seconds (wall time, both frames and the setup), its larger light
             counts are not run ("-" in the tables, the run that went over named below them):
             on this shared machine polygonal's 32 point lights (192 meshes of 2 M triangles)
             would take most of an hour
  gating     a frame of the bunny box without fog, by a graph holding all four methods and
             by the same graph without them (planning and frame time, plugins loaded)

Scenes classroom and courtyard are tools/gen_scene.py's interiors (`make scenes` writes them
to out/scenes/; made there on first use), with their own camera and sun and the fog of their
examples (examples/classroom.lgraph, courtyard.lgraph).

--quick: 256x175 and 534x365 crossover, --size 534x365, 2 frames, 1 repeat, lights 1, 4
and 32: a smoke run. Writes --out (default out/bench_volumetric): bench_volumetric.md (the tables,
with the machine, its load before and after, the date and the commit), the CSVs and PNGs.
--self-test checks the parsers, the statistics, the crossover search and the table writer
on canned inputs (meson test `bench_volumetric_selftest`, suite tools).
"""
import argparse
import datetime
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# name: (file relative to ROOT, or gen:KIND for tools/gen_scene.py's interiors; the camera
# line, None for the file's own; z_limit or None; for the interiors the fog of their example,
# examples/classroom.lgraph and courtyard.lgraph, and the file's own sun)
SCENES = {
    "bunny": ("assets/meshes/bunny_cornell_box.glb",
              "cam = camera { scene = scene, mode = look_at, position = [0.55, 1.45, 0.95], "
              "target = [-0.05, 0.55, -1.5], fov_deg = 70 }", 17.6),
    "dragon": ("assets/meshes/dragon_vrip_draco.glb",
               "cam = camera { scene = scene, mode = orbit, azimuth_deg = 30, "
               "elevation_deg = 20 }", None),
    "dragons": ("assets/meshes/dragon_vrip_x6_instanced_draco.glb",
                "cam = camera { scene = scene, mode = orbit, azimuth_deg = 30, "
                "elevation_deg = 25 }", None),
    "classroom": ("gen:classroom", None, 12),
    "courtyard": ("gen:courtyard", None, 40),
}
INTERIOR_FOG = {
    "classroom": "density = 1, scattering = [0.08, 0.08, 0.08], absorption = [0.01, 0.01, "
                 "0.01], g = 0.5",
    "courtyard": "density = 1, scattering = [0.04, 0.04, 0.04], absorption = [0.004, 0.004, "
                 "0.004], g = 0.5",
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
DISABLED = "disabled"

# the thesis's aspect (2134 x 1459), from a quarter of its width to nearly its full width
DEFAULT_SIZES = "256x175,384x262,534x365,800x547,1067x730,1920x1313"


class BenchError(Exception):
    pass


def die(msg):
    sys.stderr.write("bench_volumetric: %s\n" % msg)
    sys.exit(1)


# ---- parsing ---------------------------------------------------------------------------------

POLY_RE = re.compile(r"volume pass: (\d+) lights?, (\d+) triangles drawn, (\d+) primitives "
                     r"generated, (\d+) fragments, ([0-9.]+) per pixel \((\d+)x(\d+)\)")
FEATURES_RE = re.compile(r"scene features \(([^)]*)\): triangles (\d+), vertices (\d+)")
SIZE_RE = re.compile(r"^([1-9][0-9]*)x([1-9][0-9]*)$")


def parse_size(s):
    m = SIZE_RE.match(s)
    if not m:
        raise BenchError("size '%s': give WxH, e.g. 1067x730" % s)
    return int(m.group(1)), int(m.group(2))


def parse_poly_line(text):
    """The polygonal node's first `volume pass:` line in a render's output, as a dict, or
    None when there is none. A line that starts so but does not parse is an error (the node
    and this parser disagree)."""
    for line in text.splitlines():
        if "volume pass:" not in line:
            continue
        m = POLY_RE.search(line)
        if not m:
            raise BenchError("cannot read the polygonal node's counters from: %s" % line)
        lights, drawn, prims, frags = (int(m.group(i)) for i in range(1, 5))
        w, h = int(m.group(6)), int(m.group(7))
        return {"lights": lights, "triangles_drawn": drawn, "primitives": prims,
                "fragments": frags, "per_pixel": frags / float(w * h), "width": w, "height": h}
    return None


def parse_features(text, node="scene"):
    """Triangles and vertices of `node`'s scene from --explain's `scene features (...)`
    line (the first naming `node`, else the first of all)."""
    first = None
    for line in text.splitlines():
        m = FEATURES_RE.search(line)
        if not m:
            continue
        r = {"node": m.group(1), "triangles": int(m.group(2)), "vertices": int(m.group(3))}
        if r["node"] == node:
            return r
        first = first or r
    if first is None:
        raise BenchError("no 'scene features' line in --explain's output")
    return first


def parse_profile(p, node="vol"):
    """What a run measured, from --profile-json's parsed object: the node's steady time per
    frame (mean over frames 2..N; the only run when it ran once) and its minimum, the shadow
    maps' and Phong's time (once), every node's peak memory."""
    nodes = {n["name"]: n for n in p["nodes"]}
    out = {"nodes": {}}
    for name, n in nodes.items():
        out["nodes"][name] = {"bytes": n.get("bytes_allocated", 0),
                              "resource_bytes": n.get("resource_bytes", 0),
                              "plugin_peak": n.get("plugin_bytes_peak", 0)}
    if node is not None:
        v = nodes.get(node)
        if v is None:
            raise BenchError("the profile has no node '%s'" % node)
        if v.get("state") != "kept":
            raise BenchError("node '%s' was not run (%s)" % (node, v.get("reason")))
        runs = v["runs"]
        out["ms"] = (v["cpu_ms"] - v["first_cpu_ms"]) / (runs - 1) if runs > 1 else v["cpu_ms"]
        out["min_ms"] = v["min_cpu_ms"]
        out["bytes"] = v.get("bytes_allocated", 0)
        out["resource_bytes"] = v.get("resource_bytes", 0)
        out["plugin_peak"] = v.get("plugin_bytes_peak", 0)
    else:
        out.update(ms=0.0, min_ms=0.0, bytes=0, resource_bytes=0, plugin_peak=0)
    for k in ("shadow", "lit"):
        # a gated node has no time (the shadow map of a scene without a light it models)
        n = nodes.get(k)
        out[k + "_ms"] = n["cpu_ms"] / max(1, n["runs"]) if n and "cpu_ms" in n else 0.0
    out["frame_ms"] = out["shadow_ms"] + out["lit_ms"] + out["ms"]
    return out


# ---- statistics and tables -------------------------------------------------------------------

def median(xs):
    s = sorted(xs)
    if not s:
        raise BenchError("median of nothing")
    k = len(s) // 2
    return s[k] if len(s) % 2 else 0.5 * (s[k - 1] + s[k])


def summary(xs):
    """(median, min, max)."""
    return (median(xs), min(xs), max(xs))


def cell(st, digits=1):
    """A table cell: the median, the min-max in brackets when there is a spread."""
    med, lo, hi = st
    f = "%%.%df" % digits
    if lo == hi:
        return f % med
    return (f + " (" + f + "-" + f + ")") % (med, lo, hi)


def md_table(header, rows, align=None):
    """A markdown table; align: a string of 'l'/'r' per column (default: first l, others r)."""
    if align is None:
        align = "l" + "r" * (len(header) - 1)
    if len(align) != len(header) or any(len(r) != len(header) for r in rows):
        raise BenchError("table: %d columns in the header, rows of %s" %
                         (len(header), sorted(set(len(r) for r in rows))))
    out = ["| " + " | ".join(header) + " |",
           "|" + "|".join("---:" if a == "r" else "---" for a in align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return out


def crossovers(pixels, series):
    """Where the ranking of two methods flips as the output grows. pixels: increasing pixel
    counts; series: method -> times at those sizes (None where not measured). For every pair
    whose difference changes sign between two neighbouring sizes, the crossing pixel count
    interpolated linearly in log(pixels) against log(ta / tb). Returns (a, b, pixels, faster
    above) tuples, sorted by pixels."""
    out = []
    names = list(series)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            for k in range(len(pixels) - 1):
                ta0, ta1 = series[a][k], series[a][k + 1]
                tb0, tb1 = series[b][k], series[b][k + 1]
                if None in (ta0, ta1, tb0, tb1) or min(ta0, ta1, tb0, tb1) <= 0:
                    continue
                d0, d1 = math.log(ta0 / tb0), math.log(ta1 / tb1)
                if d0 == 0 or d0 * d1 >= 0:
                    continue
                l0, l1 = math.log(pixels[k]), math.log(pixels[k + 1])
                lx = l0 + (l1 - l0) * d0 / (d0 - d1)
                out.append((a, b, math.exp(lx), a if d1 < 0 else b))
    out.sort(key=lambda x: x[2])
    return out


def fastest(series, k, among=None):
    names = [m for m in series if (among is None or m in among) and series[m][k] is not None]
    return min(names, key=lambda m: series[m][k]) if names else None


def fit(pts):
    """Least squares time = a + b x: (a, b, R^2)."""
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


def mib(b):
    return b / (1024.0 * 1024.0)


# ---- the machine and the moment (as tools/accuracy/accuracy.py) -----------------------------

# cpu_model() and loadavg(): the accuracy atlas's own, so both pages say the machine alike
sys.path.insert(0, os.path.join(ROOT, "tools"))
from accuracy.accuracy import cpu_model, loadavg  # noqa: E402


def git_commit():
    r = subprocess.run(["git", "-C", ROOT, "describe", "--always", "--dirty"],
                       capture_output=True, text=True)
    return r.stdout.strip() or "unknown"


# ---- graphs and runs -------------------------------------------------------------------------

def light_dirs(n):
    """n sun directions (the direction the light travels) on a cone of 30 degrees around the
    bunny box's sun, spread in azimuth: every light shines in through the open side."""
    base = (0.3, -0.35, 1.0)
    bl = math.sqrt(sum(c * c for c in base))
    b = [c / bl for c in base]
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


LIGHT_TYPES = ("directional", "point", "spot")
# the need (lightgraph inspect --json) that covers each type besides `light` (any type)
TYPE_NEEDS = {"directional": "directional_light", "point": "point_light", "spot": None}


def light_places(n, ltype):
    """n point or spot lights in the bunny box (x -1 .. 1, y 0 .. 2, z -3 .. -1): positions
    on a ring of radius 0.5 around (0, y, -1.6) spread in azimuth, points at heights 1.0 ..
    1.4 (around the bunny's ears), spots at 1.8 under the ceiling shining down, tilted 15
    degrees towards the ring's axis. Returns [(position, direction)]."""
    out = []
    for k in range(n):
        a = 2 * math.pi * k / n
        x, z = 0.5 * math.cos(a), -1.6 + 0.5 * math.sin(a)
        if ltype == "point":
            out.append(([x, 1.0 + 0.4 * (k % 3) / 2.0, z], [0.0, -1.0, 0.0]))
        else:
            t = math.tan(math.radians(15))
            d = [-math.cos(a) * t, -1.0, -math.sin(a) * t]
            dl = math.sqrt(sum(c * c for c in d))
            out.append(([x, 1.8, z], [c / dl for c in d]))
    return out


def light_nodes(n_lights, ltype):
    """The `light` nodes l0 .. l(n-1), chained from `cam` (the first replaces the scene's
    lights): the suns of light_dirs (10 lux in all), or light_places's points (20 cd in all)
    or spots (60 cd in all, cones 20 and 35 degrees)."""
    g, prev = [], "cam"
    for k in range(n_lights):
        mode = ", mode = replace" if k == 0 else ""
        if ltype == "directional":
            d = light_dirs(n_lights)[k]
            g.append("l%d = light { scene = %s%s, direction = [%.6f, %.6f, %.6f], intensity = %g }"
                     % (k, prev, mode, d[0], d[1], d[2], 10.0 / n_lights))
        elif ltype in ("point", "spot"):
            p, d = light_places(n_lights, ltype)[k]
            extra = (", direction = [%.6f, %.6f, %.6f], inner_cone_deg = 20, outer_cone_deg = 35"
                     % tuple(d) if ltype == "spot" else "")
            g.append("l%d = light { scene = %s%s, type = %s, position = [%.6f, %.6f, %.6f]%s, "
                     "intensity = %g }" % (k, prev, mode, ltype, p[0], p[1], p[2], extra,
                                           (20.0 if ltype == "point" else 60.0) / n_lights))
        else:
            raise BenchError("unknown light type %s (known: %s)" % (ltype, ", ".join(LIGHT_TYPES)))
        prev = "l%d" % k
    return g, prev


def graph(scene_file, scene, method, n_lights, shadow_res, ltype="directional"):
    _, cam, z_limit = SCENES[scene]
    g = ["lightgraph 1", 'scene = gltf { file = "%s" }' % scene_file]
    if cam is None:
        # an interior: its own camera and sun, its example's fog
        if n_lights != 1:
            raise BenchError("scene %s: its own sun only (1 light)" % scene)
        g.append("fog = medium { scene = scene, %s }" % INTERIOR_FOG[scene])
    else:
        g.append(cam)
        lights, prev = light_nodes(n_lights, ltype)
        g += lights
        g.append("fog = medium { scene = %s, density = 1, scattering = [0.1, 0.1, 0.1], "
                 "g = 0.4 }" % prev)
    g.append("shadow = shadowmap { scene = fog, resolution = %d }" % shadow_res)
    g.append("lit = phong { scene = fog, shadows = shadow, background = [0.6, 0.7, 0.9] }")
    if method == DISABLED:
        return "\n".join(g) + '\noutput lit "vol.exr"\n'
    node, params, uses_shadows = METHODS[method]
    zl = ", z_limit = %g" % z_limit if z_limit else ""
    sh = ", shadows = shadow" if uses_shadows else ""
    g.append("vol = %s { scene = fog, base = lit%s, %s%s, per_frame = true }"
             % (node, sh, params, zl))
    return "\n".join(g) + '\noutput vol "vol.exr"\n'


def max_pixels(n_lights, shadow_res, ltype):
    """render's --max-pixels for a run: the default limit (2^27) unless the shadow atlas is
    larger. The atlas is square, ceil(sqrt(records))^2 tiles of shadow_res^2 (a point light
    has six records): 32 point lights at 1024^2 make a 14336^2 atlas, 205 M texels."""
    records = n_lights * (6 if ltype == "point" else 1)
    side = math.ceil(math.sqrt(records))
    return max(1 << 27, 2 * side * side * shadow_res * shadow_res)


class Runner:
    def __init__(self, exe, frames, shadow_res, out, tmp):
        self.exe, self.frames, self.shadow_res, self.out, self.tmp = (exe, frames, shadow_res,
                                                                      out, tmp)
        self.files = {}
        self.triangles = {}
        self.done = {}  # config -> results already measured (an experiment reuses another's)
        self.skipped = {}  # (method, light type) -> (lights, wall s) of the run over budget

    def scene_file(self, scene):
        if scene in self.files:
            return self.files[scene]
        path = SCENES[scene][0]
        if path.startswith("gen:"):
            kind = path[4:]
            gen = os.path.join(ROOT, "tools", "gen_scene.py")
            r = subprocess.run([sys.executable, gen, "--help"], capture_output=True, text=True)
            if kind not in r.stdout:
                raise BenchError("scene %s: tools/gen_scene.py has no kind '%s' here (it comes "
                                 "with branch `scenes`)" % (scene, kind))
            path = os.path.join(ROOT, "out", "scenes", "%s.glb" % kind)  # as `make scenes`
            os.makedirs(os.path.dirname(path), exist_ok=True)
            if not os.path.exists(path):
                r = subprocess.run([sys.executable, gen, kind, "-q", "-o", path],
                                   capture_output=True, text=True)
                if r.returncode != 0:
                    raise BenchError("gen_scene.py %s failed:\n%s" % (kind, r.stderr))
        else:
            path = os.path.join(ROOT, path)
        self.files[scene] = path
        return path

    def run(self, scene, method, n_lights, size, ltype="directional"):
        text = graph(self.scene_file(scene), scene, method, n_lights, self.shadow_res, ltype)
        gpath = os.path.join(self.tmp, "g.lgraph")
        with open(gpath, "w") as f:
            f.write(text)
        prof = os.path.join(self.tmp, "p.json")
        cmd = [self.exe, "render", gpath, "--size", size, "--frames", str(self.frames),
               "--profile-json", prof, "--explain", "--no-cache", "-v",
               "--max-pixels", str(max_pixels(n_lights, self.shadow_res, ltype))]
        t0 = time.monotonic()
        r = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.monotonic() - t0
        if r.returncode != 0:
            raise BenchError("%s failed (exit %d):\n%s\n%s%s" % (
                " ".join(cmd), r.returncode, text, r.stdout[-4000:], r.stderr[-4000:]))
        with open(prof) as f:
            res = parse_profile(json.load(f), None if method == DISABLED else "vol")
        res["wall_s"] = wall
        res["poly"] = parse_poly_line(r.stdout + r.stderr) if method == "polygonal" else None
        if method == "polygonal" and res["poly"] is None:
            raise BenchError("the polygonal node said no 'volume pass:' line (-v):\n%s" %
                             r.stderr[-2000:])
        feats = parse_features(r.stdout + r.stderr)
        self.triangles[scene] = feats["triangles"]
        return res


def repeated(runner, configs, repeat, label, budget=None):
    """Runs every (scene, method, lights, size) of configs `repeat` times, the configs of one
    repeat in turn; returns config -> list of results. budget (seconds, the lights
    experiment's --max-seconds): once a run of a method and light type took longer than
    that in wall time, its larger light counts are not run (their lists stay empty and
    runner.skipped[(method, type)] says (lights, seconds) of the run that went over)."""
    res = {c: list(runner.done.get(c, []))[:repeat] for c in configs}
    for k in range(repeat):
        for c in configs:
            if len(res[c]) > k:
                continue
            key = (c[1], c[4] if len(c) > 4 else "directional")
            over = runner.skipped.get(key)
            if budget is not None and over is not None and c[2] > over[0]:
                continue
            r = runner.run(*c)
            # over the budget: noted only where a larger count of the method and type is
            # left to skip (the largest count going over skips nothing)
            larger = any(d[1] == c[1] and (d[4] if len(d) > 4 else "directional") == key[1]
                         and d[2] > c[2] for d in configs)
            if budget is not None and r["wall_s"] > budget and larger:
                if over is None or c[2] < over[0]:
                    runner.skipped[key] = (c[2], r["wall_s"])
            res[c].append(r)
            runner.done[c] = res[c]
            sys.stderr.write("%s %d/%d %s %s %dL%s %s: %.1f ms (frame %.1f)\n" %
                             (label, k + 1, repeat, c[0], c[1], c[2],
                              " " + c[4] if len(c) > 4 else "", c[3], r["ms"], r["frame_ms"]))
    return res


# ---- experiments -----------------------------------------------------------------------------

def exp_crossover(runner, a, methods, md):
    sizes = [parse_size(s) for s in a.sizes.split(",")]
    names = [s for s in a.sizes.split(",")]
    pixels = [w * h for w, h in sizes]
    if pixels != sorted(pixels):
        raise BenchError("--sizes: give them in increasing order")
    all_m = methods + [DISABLED]
    configs = [(s, m, 1, z) for s in a.crossover_scenes.split(",") for z in names for m in all_m]
    if a.crossover_csv:
        res = load_crossover(a.crossover_csv, configs)
        for s in a.crossover_scenes.split(","):
            runner.run(s, DISABLED, 1, names[0])  # the triangle count, measured
    else:
        res = repeated(runner, configs, a.repeat, "crossover")
    rows = []
    md += ["## Crossover: time against output size (one light)", "",
           "The method's node per frame, median of %d runs (min-max); a frame (shadow maps + "
           "Phong + the node) in the second table. Log-log plots: crossover_<scene>.png."
           % a.repeat, ""]
    for s in a.crossover_scenes.split(","):
        node = {m: [median([r["ms"] for r in res[(s, m, 1, z)]]) for z in names] for m in methods}
        table = []
        for k, z in enumerate(names):
            table.append([z, "%d" % pixels[k]] +
                         [cell(summary([r["ms"] for r in res[(s, m, 1, z)]])) for m in methods] +
                         [cell(summary([r["frame_ms"] for r in res[(s, DISABLED, 1, z)]]))] +
                         [fastest(node, k)])
        md += ["### %s (%s triangles): node ms" % (s, "{:,}".format(runner.triangles[s])), ""]
        md += md_table(["size", "pixels"] + methods + ["disabled frame", "fastest"], table,
                       "ll" + "r" * (len(methods) + 1) + "l")
        frames = [[z] + [cell(summary([r["frame_ms"] for r in res[(s, m, 1, z)]]))
                         for m in all_m] for z in names]
        md += ["", "%s: frame ms (shadow maps + Phong + node)" % s, ""]
        md += md_table(["size"] + all_m, frames)
        flips = crossovers(pixels, node)
        md += [""]
        if flips:
            md += ["Ranking flips (%s, node time): " % s + "; ".join(
                "%s and %s cross at %.0f pixels (~%dx%d), %s faster above" %
                (x, y, px, round(math.sqrt(px * 2134 / 1459)), round(math.sqrt(px * 1459 / 2134)),
                 f) for x, y, px, f in flips) + ".", ""]
        else:
            md += ["Ranking flips (%s): none between %s and %s." % (s, names[0], names[-1]), ""]
        for k, z in enumerate(names):
            for m in all_m:
                for i, r in enumerate(res[(s, m, 1, z)]):
                    rows.append((s, m, z, pixels[k], i, r["ms"], r["frame_ms"], r["bytes"]))
        plot_crossover(a.out, s, names, pixels, all_m, res)
    with open(os.path.join(a.out, "crossover.csv"), "w") as f:
        f.write("scene,method,size,pixels,repeat,node_ms,frame_ms,bytes\n")
        for r in rows:
            f.write("%s,%s,%s,%d,%d,%.4f,%.4f,%d\n" % r)


def load_crossover(path, configs):
    """The results of an earlier run's crossover.csv (--crossover-csv: tables and plots made
    again without measuring), as config -> results with ms and frame_ms."""
    res = {c: [] for c in configs}
    with open(path) as f:
        head = f.readline().strip().split(",")
        for line in f:
            r = dict(zip(head, line.strip().split(",")))
            c = (r["scene"], r["method"], 1, r["size"])
            if c in res:
                res[c].append({"ms": float(r["node_ms"]), "frame_ms": float(r["frame_ms"]),
                               "bytes": int(r["bytes"])})
    missing = [c for c, v in res.items() if not v]
    if missing:
        raise BenchError("%s has no rows for %s" % (path, ", ".join("%s %s %s" % (c[0], c[1], c[3])
                                                                   for c in missing[:4])))
    return res


def plot_crossover(out, scene, names, pixels, methods, res):
    if not shutil.which("gnuplot"):
        sys.stderr.write("bench_volumetric: gnuplot not found: no plots\n")
        return
    dat = []
    for m in methods:
        p = os.path.join(out, "crossover_%s_%s.dat" % (scene, m))
        dat.append((m, p))
        with open(p, "w") as f:
            for k, z in enumerate(names):
                rs = res[(scene, m, 1, z)]
                key = "frame_ms" if m == DISABLED else "ms"
                med, lo, hi = summary([r[key] for r in rs])
                f.write("%d %.4f %.4f %.4f\n" % (pixels[k], med, lo, hi))
    gp = os.path.join(out, "crossover_%s.gp" % scene)
    with open(gp, "w") as f:
        f.write("set terminal pngcairo size 900,600 noenhanced\n")
        f.write("set output '%s'\n" % os.path.join(out, "crossover_%s.png" % scene))
        f.write("set grid\nset key left top\nset logscale xy\n")
        f.write("set xlabel 'output pixels'\nset ylabel 'time per frame (ms): median, min-max'\n")
        f.write("set title '%s: node time per frame against output size; disabled: the whole "
                "frame without one'\n" % scene)
        f.write("plot " + ", \\\n     ".join(
            "'%s' using 1:2:3:4 with yerrorlines title '%s'" % (p, m) for m, p in dat) + "\n")
    subprocess.run(["gnuplot", gp], check=False)


def exp_table6(runner, a, methods, md):
    scenes = a.scenes.split(",")
    all_m = methods + [DISABLED]
    configs = [(s, m, 1, a.size) for s in scenes for m in all_m]
    res = repeated(runner, configs, a.repeat, "table6")
    rows, poly_rows = [], []
    md += ["## The thesis's Table 6: frame time per scene (one light, %s)" % a.size, "",
           "Frame ms = shadow maps + Phong + the method's node (the thesis counts the whole "
           "frame), median of %d runs (min-max); triangles as the loader built the scene "
           "(--explain's scene features)." % a.repeat, ""]
    table = []
    for s in scenes:
        table.append([s, "{:,}".format(runner.triangles[s])] +
                     [cell(summary([r["frame_ms"] for r in res[(s, m, 1, a.size)]]))
                      for m in all_m] +
                     [cell(summary([r["shadow_ms"] for m in all_m
                                    for r in res[(s, m, 1, a.size)]]))])
    md += md_table(["scene", "triangles"] + all_m + ["of which shadow maps"], table)
    # the thesis's Table 6 is frames per second; its overheads (1000/fps - 1000/fps
    # disabled) are what "grows with scene complexity" refers to
    md += ["", "As the thesis's Table 6 has it: frames per second (1000 / median frame ms) and "
           "each method's overhead over \"disabled\" (difference of the medians, ms):", ""]
    ft = []
    for s in scenes:
        dis = median([r["frame_ms"] for r in res[(s, DISABLED, 1, a.size)]])
        row = [s, "%.2f" % (1000.0 / dis)]
        for m in methods:
            fm = median([r["frame_ms"] for r in res[(s, m, 1, a.size)]])
            row.append("%.2f fps, +%.1f ms" % (1000.0 / fm, fm - dis))
        ft.append(row)
    md += md_table(["scene", "disabled fps"] + methods, ft)
    md += ["", "The methods' nodes alone (ms per frame):", ""]
    md += md_table(["scene"] + methods,
                   [[s] + [cell(summary([r["ms"] for r in res[(s, m, 1, a.size)]]))
                           for m in methods] for s in scenes])
    if "polygonal" in methods:
        md += ["", "### Polygonal: what the light volumes cost (GL query objects in its "
               "volume pass)", ""]
        pt = []
        for s in scenes:
            p = res[(s, "polygonal", 1, a.size)][0]["poly"]
            pt.append([s, "{:,}".format(runner.triangles[s]), "{:,}".format(p["triangles_drawn"]),
                       "{:,}".format(p["fragments"]), "%.3f" % p["per_pixel"],
                       cell(summary([r["ms"] for r in res[(s, "polygonal", 1, a.size)]])),
                       cell(summary([r["shadow_ms"] for r in res[(s, "polygonal", 1, a.size)]]))])
            poly_rows.append((s, runner.triangles[s], p["triangles_drawn"], p["primitives"],
                              p["fragments"], p["per_pixel"]))
        md += md_table(["scene", "scene triangles", "volume triangles drawn", "fragments",
                        "fragments per pixel", "polygonal ms", "shadow maps ms"], pt)
        with open(os.path.join(a.out, "polygonal.csv"), "w") as f:
            f.write("scene,scene_triangles,volume_triangles,primitives,fragments,per_pixel\n")
            for r in poly_rows:
                f.write("%s,%d,%d,%d,%d,%.6f\n" % r)
    md += [""]
    with open(os.path.join(a.out, "table6.csv"), "w") as f:
        f.write("scene,triangles,method,repeat,node_ms,frame_ms,shadow_ms,lit_ms\n")
        for s in scenes:
            for m in all_m:
                for i, r in enumerate(res[(s, m, 1, a.size)]):
                    f.write("%s,%d,%s,%d,%.4f,%.4f,%.4f,%.4f\n" % (
                        s, runner.triangles[s], m, i, r["ms"], r["frame_ms"], r["shadow_ms"],
                        r["lit_ms"]))


def covers(needs, ltype):
    """Whether a node with these needs runs on a scene whose lights are all of type ltype."""
    return "light" in needs or (TYPE_NEEDS[ltype] is not None and TYPE_NEEDS[ltype] in needs)


def node_needs(exe, node):
    r = subprocess.run([exe, "inspect", node, "--json"], capture_output=True, text=True)
    if r.returncode != 0:
        raise BenchError("lightgraph inspect %s failed: %s" % (node, r.stderr.strip()))
    return json.loads(r.stdout)["needs"]


def lights_config(m, n, size, ltype):
    """The config of the lights experiment: the directional one is table6's and crossover's
    (a 4-tuple, so that their runs are reused)."""
    return ("bunny", m, n, size) if ltype == "directional" else ("bunny", m, n, size, ltype)


LIGHTS_DOC_HEADING = "### Memory against the number of lights"


def parse_doc_lights(text):
    """docs/volumetric.md's table of the lights experiment (the first table after
    LIGHTS_DOC_HEADING): {lights: {column: value}} with the `... ms` and `... MiB` columns
    as floats (thousands separators and bold marks removed), or {} when there is none."""
    i = text.find(LIGHTS_DOC_HEADING)
    if i < 0:
        return {}
    rows, head = {}, None
    for line in text[i:].split("\n")[1:]:
        if line.startswith("#"):
            break
        if not line.startswith("|"):
            if head is not None and rows:
                break
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if head is None:
            head = cells
            continue
        if set(cells[0]) <= set("-:"):
            continue
        try:
            n = int(cells[0])
            vals = {h: float(c.replace(",", "").replace("*", "")) for h, c in
                    zip(head[1:], cells[1:])}
        except ValueError:
            raise BenchError("docs/volumetric.md: the lights table's row %r does not parse"
                             % line)
        rows[n] = vals
    return rows


def exp_lights(runner, a, methods, md):
    lights = [int(x) for x in a.lights.split(",")]
    if any(n < 1 or n > 32 for n in lights):
        raise BenchError("--lights: 1 .. 32 each")
    types = a.light_types.split(",")
    for t in types:
        if t not in LIGHT_TYPES:
            raise BenchError("--light-types: unknown %s (known: %s)" % (t, ", ".join(LIGHT_TYPES)))
    needs = {m: node_needs(runner.exe, METHODS[m][0]) for m in methods}
    ok = {(m, t): covers(needs[m], t) for m in methods for t in types}
    configs = [lights_config(m, n, a.size, t) for t in types for n in lights for m in methods
               if ok[(m, t)]]
    if a.lights_csv:
        res = load_lights(a.lights_csv, configs, runner)
    else:
        res = repeated(runner, configs, a.repeat, "lights", a.max_seconds)

    def rs(m, n, t):
        return res[lights_config(m, n, a.size, t)]

    def ran(m, n, t):
        return bool(rs(m, n, t))

    def skipped_note(m, t):
        over = runner.skipped.get((m, t))
        if not over:
            return None
        return ("%s %s: %d lights took %.0f s%s, more not run" % (
            m, t, over[0], over[1],
            " (--max-seconds %g)" % a.max_seconds if a.max_seconds is not None else ""))

    md += ["## Time and peak memory against the number of lights (bunny box, %s)" % a.size, "",
           "Time: the node per frame, median of %d runs (min-max). Memory: the node's peak "
           "(`bytes_allocated`: its outputs plus the most its plugin held at once), the same "
           "in every run; then split into outputs (`resource_bytes`) and own allocations "
           "(`plugin_bytes_peak`). Light types (issue 25): directional (suns on a cone around "
           "the box's sun, 10 lux in all), point (a ring around the bunny, 20 cd in all), "
           "spot (a ring under the ceiling shining down, 60 cd in all, cones 20 and 35 "
           "degrees); n/a: the method does not model the type (its needs: the node would be "
           "gated)." % a.repeat, ""]
    for t in types:
        ms = [m for m in methods if ok[(m, t)]]
        na = [m for m in methods if not ok[(m, t)]]
        md += ["### %s lights" % t, ""]
        if na:
            md += ["n/a: %s (needs %s)." % (", ".join(na), "; ".join(
                "%s: %s" % (m, ", ".join(needs[m])) for m in na)), ""]
        if not ms:
            continue
        tab = []
        for n in lights:
            done = [m for m in ms if ran(m, n, t)]
            tab.append(["%d" % n] +
                       [cell(summary([r["ms"] for r in rs(m, n, t)])) if m in done else "-"
                        for m in ms] +
                       ["%.1f" % mib(rs(m, n, t)[0]["bytes"]) if m in done else "-"
                        for m in ms] +
                       ["%.1f" % mib(rs(done[0], n, t)[0]["nodes"]["shadow"]["bytes"])
                        if done else "-"])
        md += md_table(["lights"] + ["%s ms" % m for m in ms] + ["%s MiB" % m for m in ms] +
                       ["shadow maps MiB"], tab)
        notes = [x for x in (skipped_note(m, t) for m in ms) if x]
        if notes:
            md += ["", "-: not run (the time budget): " + "; ".join(notes) + "."]
        md += ["", "Peak memory split, MiB (outputs + own allocations):", ""]
        md += md_table(["lights"] + ms, [
            ["%d" % n] + ["%.1f + %.1f" % (mib(rs(m, n, t)[0]["resource_bytes"]),
                                           mib(rs(m, n, t)[0]["plugin_peak"]))
                          if ran(m, n, t) else "-" for m in ms]
            for n in lights])
        fits = []
        for m in ms:
            pts = [(n, median([r["ms"] for r in rs(m, n, t)])) for n in lights if ran(m, n, t)]
            if len(pts) > 1:
                fits.append("%s a %.1f b %.2f R^2 %.3f (%d-%d lights)"
                            % ((m,) + fit(pts) + (pts[0][0], pts[-1][0])))
        if fits:
            md += ["", "Linear fits, time = a + b x lights (ms, medians): " + "; ".join(fits)
                   + "."]
        md += [""]
    if "directional" in types:
        lights_against_doc(a, methods, lights, ok, rs, md)
    with open(os.path.join(a.out, "lights.csv"), "w") as f:
        f.write("light_type,lights,method,repeat,ms,min_ms,bytes,resource_bytes,plugin_peak,"
                "shadow_bytes,wall_s\n")
        for t in types:
            for n in lights:
                for m in methods:
                    if not ok[(m, t)]:
                        continue
                    for i, r in enumerate(rs(m, n, t)):
                        f.write("%s,%d,%s,%d,%.4f,%.4f,%d,%d,%d,%d,%.2f\n" % (
                            t, n, m, i, r["ms"], r["min_ms"], r["bytes"], r["resource_bytes"],
                            r["plugin_peak"], r["nodes"]["shadow"]["bytes"], r["wall_s"]))
    plot_lights(a.out, [(m, t) for t in types for m in methods if ok[(m, t)]], lights, rs)


def load_lights(path, configs, runner):
    """The results of an earlier run's lights.csv (--lights-csv: the tables and plots made
    again without measuring), as config -> results; a config the CSV has no row for was not
    run (the time budget), and the budget's note is remade from the CSV's wall times
    (the smallest count past which the method and type have no rows)."""
    res = {c: [] for c in configs}
    with open(path) as f:
        head = f.readline().strip().split(",")
        for line in f:
            r = dict(zip(head, line.strip().split(",")))
            c = lights_config(r["method"], int(r["lights"]), configs[0][3], r["light_type"])
            if c not in res:
                continue
            b = int(r["shadow_bytes"])
            res[c].append({"ms": float(r["ms"]), "min_ms": float(r["min_ms"]),
                           "bytes": int(r["bytes"]), "resource_bytes": int(r["resource_bytes"]),
                           "plugin_peak": int(r["plugin_peak"]), "nodes": {"shadow": {"bytes": b}},
                           "wall_s": float(r.get("wall_s") or 0)})
    if not any(res.values()):
        raise BenchError("%s has no rows for this run's configurations" % path)
    for c, v in res.items():
        key = (c[1], c[4] if len(c) > 4 else "directional")
        if not v and key not in runner.skipped:
            done = [d for d, w in res.items() if w and d[1] == c[1] and
                    (d[4] if len(d) > 4 else "directional") == key[1] and d[2] < c[2]]
            if done:
                last = max(done, key=lambda d: d[2])
                runner.skipped[key] = (last[2], res[last][0]["wall_s"])
    return res


def lights_against_doc(a, methods, lights, ok, rs, md):
    """The directional rows of this run beside docs/volumetric.md's (issue 25: a
    homogeneous-fog directional scene costs what it cost before)."""
    path = os.path.join(ROOT, "docs", "volumetric.md")
    doc = parse_doc_lights(open(path).read()) if os.path.exists(path) else {}
    md += ["### Directional lights against docs/volumetric.md", ""]
    if not doc:
        md += ["docs/volumetric.md has no table under \"%s\": nothing to compare."
               % LIGHTS_DOC_HEADING[4:], ""]
        return
    md += ["This run's directional rows beside the page's table (its own run, size and load: "
           "the page says them; the page's is at 1067x730%s). Time ms this run / the page's "
           "(ratio); memory MiB this run / the page's." %
           ("" if a.size == "1067x730" else ", this run at %s: the times are not comparable, "
            "the memory of the outputs scales with the pixels" % a.size), ""]
    rows = []
    for n in lights:
        if n not in doc:
            continue
        for m in methods:
            if not ok[(m, "directional")] or not rs(m, n, "directional"):
                continue
            t = median([r["ms"] for r in rs(m, n, "directional")])
            b = mib(rs(m, n, "directional")[0]["bytes"])
            dt, db = doc[n].get("%s ms" % m), doc[n].get("%s MiB" % m)
            rows.append(["%d" % n, m,
                         "%.1f / %s" % (t, "%.0f (%.2f)" % (dt, t / dt) if dt else "-"),
                         "%.1f / %s" % (b, "%.1f" % db if db is not None else "-")])
    md += md_table(["lights", "method", "time ms (ratio)", "memory MiB"], rows) if rows else \
        ["No light count of this run is in the page's table (%s)." %
         ", ".join(str(n) for n in sorted(doc))]
    md += [""]


def plot_lights(out, series, lights, rs):
    if not shutil.which("gnuplot"):
        return
    # a method and type with no run (none measured, or not read back) has no line
    series = [(m, t) for m, t in series if any(rs(m, n, t) for n in lights)]
    for m, t in series:
        with open(os.path.join(out, "lights_%s_%s.dat" % (m, t)), "w") as f:
            for n in lights:
                r = rs(m, n, t)
                if not r:  # not run (the time budget)
                    continue
                med, lo, hi = summary([x["ms"] for x in r])
                f.write("%d %.4f %.4f %.4f %.4f\n" % (n, med, lo, hi, mib(r[0]["bytes"])))
    types = [t for t in LIGHT_TYPES if any(st == t for _, st in series)]
    methods = []
    for m, _ in series:
        if m not in methods:
            methods.append(m)
    for what, using, label in (("time", "1:2:3:4 with yerrorlines", "time per frame (ms)"),
                               ("memory", "1:5 with linespoints", "node peak memory (MiB)")):
        gp = os.path.join(out, "lights_%s.gp" % what)
        with open(gp, "w") as f:
            # one panel per light type, the same colour for a method in every panel
            f.write("set terminal pngcairo size %d,520 noenhanced\n" % (460 * len(types)))
            f.write("set output '%s'\n" % os.path.join(out, "lights_%s.png" % what))
            f.write("set multiplot layout 1,%d title 'volumetric methods against the number "
                    "of lights of each type (bunny box): %s'\n" % (len(types), label))
            f.write("set grid\nset key left top\nset logscale xy\n")
            f.write("set xtics (%s)\n" % ", ".join(str(n) for n in lights))
            f.write("set xrange [0.8:%g]\n" % (max(lights) * 1.25))
            f.write("set xlabel 'lights'\nset ylabel '%s'\n" % label)
            for t in types:
                f.write("set title '%s'\n" % t)
                f.write("plot " + ", \\\n     ".join(
                    "'%s' using %s lc %d title '%s'" % (
                        os.path.join(out, "lights_%s_%s.dat" % (m, t)), using,
                        methods.index(m) + 1, m)
                    for m, st in series if st == t) + "\n")
            f.write("unset multiplot\n")
        subprocess.run(["gnuplot", gp], check=False)


def exp_gating(runner, a, md):
    """A frame of the bunny box without fog, by a graph that holds all three methods (and
    the reference) and by the same graph without them: planning and execution time (medians
    of --repeat x 2 runs each, alternated), plugins loaded."""
    exe, tmp = runner.exe, runner.tmp
    base = graph(runner.scene_file("bunny"), "bunny", DISABLED, 1, a.shadow_resolution)
    base = [l for l in base.split("\n") if l and not l.startswith("output")]
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
    for k in range(2 * a.repeat):
        for name, text in (("without", without), ("with", with_)):
            gpath = os.path.join(tmp, "gate_%s.lgraph" % name)
            with open(gpath, "w") as f:
                f.write(text)
            prof = os.path.join(tmp, "gate.json")
            r = subprocess.run([exe, "render", gpath, "--size", a.size, "--frames", str(a.frames),
                                "--profile-json", prof, "--explain", "--no-cache"],
                               capture_output=True, text=True)
            if r.returncode != 0:
                raise BenchError("gating run failed:\n%s\n%s%s" % (text, r.stdout, r.stderr))
            with open(prof) as f:
                p = json.load(f)
            res[name].append((p["planning_ms"], p["execution_ms"]))
            loaded[name] = next((l for l in r.stdout.splitlines()
                                 if l.startswith("plugins loaded:")), "")
    st = {n: (summary([x for x, _ in v]), summary([y for _, y in v])) for n, v in res.items()}
    md += ["## No fog: the graph with every method costs what the graph without them costs", ""]
    md += md_table(["graph", "planning ms", "frames ms (%d frames)" % a.frames, "plugins loaded"], [
        ["without the volumetric nodes", cell(st["without"][0]), cell(st["without"][1]),
         loaded["without"].split(":", 1)[-1].strip()],
        ["with screen, polygonal, froxel and reference, fog density 0", cell(st["with"][0]),
         cell(st["with"][1]), loaded["with"].split(":", 1)[-1].strip()]], "lrrl")
    md += ["", "Ratio of medians with / without: planning %.3f, frames %.3f (%d alternated runs "
           "each)." % (st["with"][0][0] / st["without"][0][0],
                       st["with"][1][0] / st["without"][1][0], 2 * a.repeat), ""]


# ---- self-test -------------------------------------------------------------------------------

def self_test():
    """The parsers, the statistics, the crossover search and the table writer on canned
    inputs; each check also feeds what must be refused."""
    fails = []

    def check(cond, what):
        if not cond:
            fails.append(what)

    out = ("node 'vol': grid ...\nnode 'vol': volume pass: 2 lights, 4208140 triangles drawn, "
           "4208140 primitives generated, 3345 fragments, 1.0889 per pixel (64x48)\n")
    p = parse_poly_line(out)
    check(p and p["lights"] == 2 and p["triangles_drawn"] == 4208140 and p["fragments"] == 3345
          and abs(p["per_pixel"] - 3345 / 3072.0) < 1e-12 and p["width"] == 64,
          "poly line: %r" % (p,))
    check(parse_poly_line("node 'vol': grid 1x1x1\n") is None, "poly line where there is none")
    one = parse_poly_line("volume pass: 1 light, 12 triangles drawn, 12 primitives generated, "
                          "7 fragments, 7.0000 per pixel (1x1)")
    check(one and one["lights"] == 1 and one["fragments"] == 7, "poly line, one light")
    try:
        parse_poly_line("volume pass: lots of triangles")
        check(False, "a malformed volume-pass line was accepted")
    except BenchError:
        pass
    ex = ("plan:\n  scene features (other): triangles 12, vertices 8, lights: ...\n"
          "  scene features (scene): triangles 5009, vertices 2600, lights: 1 directional\n")
    f = parse_features(ex)
    check(f["triangles"] == 5009 and f["vertices"] == 2600, "features: %r" % (f,))
    check(parse_features(ex, "none")["triangles"] == 12, "features: first line as fallback")
    try:
        parse_features("no plan here")
        check(False, "features without a line were accepted")
    except BenchError:
        pass
    prof = {"nodes": [
        {"name": "vol", "state": "kept", "runs": 3, "cpu_ms": 30.0, "first_cpu_ms": 10.0,
         "min_cpu_ms": 9.0, "bytes_allocated": 300, "resource_bytes": 100,
         "plugin_bytes_peak": 200},
        {"name": "shadow", "runs": 1, "cpu_ms": 5.0, "bytes_allocated": 7},
        {"name": "lit", "runs": 1, "cpu_ms": 4.0, "bytes_allocated": 1}]}
    r = parse_profile(prof)
    check(r["ms"] == 10.0 and r["min_ms"] == 9.0 and r["frame_ms"] == 19.0 and
          r["plugin_peak"] == 200 and r["nodes"]["shadow"]["bytes"] == 7, "profile: %r" % (r,))
    d = parse_profile(prof, None)
    check(d["ms"] == 0.0 and d["frame_ms"] == 9.0, "profile, disabled: %r" % (d,))
    gated_shadow = {"nodes": [dict(prof["nodes"][0]), {"name": "shadow", "state": "gated"},
                              prof["nodes"][2]]}
    g = parse_profile(gated_shadow)
    check(g["shadow_ms"] == 0.0 and g["frame_ms"] == 14.0 and g["nodes"]["shadow"]["bytes"] == 0,
          "profile, a gated shadow map: %r" % (g,))
    prof["nodes"][0]["state"] = "gated"
    try:
        parse_profile(prof)
        check(False, "a gated node's profile was accepted")
    except BenchError:
        pass
    check(median([3, 1, 2]) == 2 and median([4, 1, 3, 2]) == 2.5, "median")
    check(summary([5, 1, 9]) == (5, 1, 9), "summary")
    check(cell((5.0, 1.0, 9.0)) == "5.0 (1.0-9.0)" and cell((2.0, 2.0, 2.0)) == "2.0", "cell")
    t = md_table(["a", "b"], [["x", 1]])
    check(t == ["| a | b |", "|---|---:|", "| x | 1 |"], "table: %r" % (t,))
    try:
        md_table(["a", "b"], [["x"]])
        check(False, "a short row was accepted")
    except BenchError:
        pass
    # a fixed cost (100) against one growing with pixels (t = px / 1000): they cross at
    # exactly 100,000 pixels, the growing one faster below
    px = [10000, 40000, 160000, 640000]
    series = {"froxel": [100.0] * 4, "screen": [x / 1000.0 for x in px], "none": [None] * 4}
    c = crossovers(px, series)
    check(len(c) == 1 and c[0][0] == "froxel" and c[0][1] == "screen" and
          abs(c[0][2] - 100000.0) < 1e-6 and c[0][3] == "froxel", "crossover: %r" % (c,))
    check(fastest(series, 0) == "screen" and fastest(series, 3) == "froxel", "fastest")
    check(crossovers(px, {"a": [1, 2, 3, 4], "b": [2, 3, 4, 5]}) == [], "no crossing")
    a0, b, r2 = fit([(1, 3.0), (2, 5.0), (4, 9.0)])
    check(abs(a0 - 1) < 1e-12 and abs(b - 2) < 1e-12 and abs(r2 - 1) < 1e-12, "fit")
    check(parse_size("256x175") == (256, 175), "size")
    for bad in ("256", "0x5", "x5", "12x-3"):
        try:
            parse_size(bad)
            check(False, "size '%s' accepted" % bad)
        except BenchError:
            pass
    g = graph("/x.glb", "bunny", DISABLED, 2, 64)
    check("vol =" not in g and 'output lit' in g and g.count("= light {") == 2, "disabled graph")
    g = graph("/x.glb", "bunny", "polygonal", 1, 64)
    check("volumetric_polygonal" in g and "z_limit = 17.6" in g and "shadows = shadow" in g,
          "polygonal graph")
    g = graph("/c.glb", "classroom", "froxel_cl", 1, 64)
    check("camera" not in g and "light {" not in g and "z_limit = 12" in g and
          "scene = scene, density = 1" in g, "interior graph: %s" % g)
    try:
        graph("/c.glb", "classroom", "screen", 2, 64)
        check(False, "an interior with 2 lights was accepted")
    except BenchError:
        pass
    # issue 25: light types
    g = graph("/x.glb", "bunny", "screen", 3, 64, "point")
    check(g.count("type = point") == 3 and "mode = replace" in g and "scene = l2" in g,
          "point graph: %s" % g)
    g = graph("/x.glb", "bunny", "screen", 2, 64, "spot")
    check(g.count("type = spot") == 2 and g.count("outer_cone_deg = 35") == 2, "spot graph")
    for pos, d in light_places(32, "point") + light_places(32, "spot"):
        check(-1 < pos[0] < 1 and 0 < pos[1] < 2 and -3 < pos[2] < -1 and
              abs(sum(c * c for c in d) - 1) < 1e-9, "a light outside the box: %r" % (pos,))
    try:
        graph("/x.glb", "bunny", "screen", 1, 64, "area")
        check(False, "an unknown light type was accepted")
    except BenchError:
        pass
    check(covers(["light", "medium"], "spot") and covers(["point_light"], "point") and
          not covers(["directional_light", "medium"], "point") and
          not covers(["directional_light"], "spot"), "covers")
    doc = parse_doc_lights("# x\n%s\n\ntext\n\n| lights | screen ms | screen MiB |\n"
                           "|---:|---:|---:|\n| 1 | 2,352 | **96.6** |\n| 4 | 6,082 | 56.5 |\n"
                           "\n| lights | screen |\n|---:|---:|\n| 1 | 56.5 + 0 |\n"
                           % LIGHTS_DOC_HEADING)
    check(doc == {1: {"screen ms": 2352.0, "screen MiB": 96.6},
                  4: {"screen ms": 6082.0, "screen MiB": 56.5}}, "doc lights table: %r" % doc)
    check(parse_doc_lights("no such table") == {}, "doc without the table")
    try:
        parse_doc_lights("%s\n| lights | a ms |\n|---|---|\n| 1 | fast |\n" % LIGHTS_DOC_HEADING)
        check(False, "a doc table with words accepted")
    except BenchError:
        pass
    # --max-seconds: a method and type over budget at n lights runs no larger count; the
    # others, and the smaller counts, all run
    class FakeRunner:
        def __init__(self):
            self.done, self.skipped, self.calls = {}, {}, []

        def run(self, scene, m, n, size, t="directional"):
            self.calls.append((m, n, t))
            return {"ms": 1.0, "frame_ms": 1.0, "wall_s": 10.0 * n if m == "slow" else 1.0}

    fr = FakeRunner()
    cfgs = [("bunny", m, n, "1x1", t) for t in ("point", "spot") for n in (1, 2, 4, 8)
            for m in ("slow", "fast")]
    res = repeated(fr, cfgs, 1, "self-test", budget=15.0)
    check([c for c in fr.calls if c[0] == "slow"] ==
          [("slow", 1, "point"), ("slow", 2, "point"), ("slow", 1, "spot"), ("slow", 2, "spot")]
          and len([c for c in fr.calls if c[0] == "fast"]) == 8 and
          fr.skipped == {("slow", "point"): (2, 20.0), ("slow", "spot"): (2, 20.0)} and
          res[("bunny", "slow", 4, "1x1", "point")] == [], "budget: %r %r" % (fr.calls,
                                                                              fr.skipped))
    # --lights-csv: an earlier run's rows back, the budget's note remade from them
    tmpd = tempfile.mkdtemp(prefix="bench-vol-selftest-")
    try:
        csvp = os.path.join(tmpd, "lights.csv")
        with open(csvp, "w") as f:
            f.write("light_type,lights,method,repeat,ms,min_ms,bytes,resource_bytes,"
                    "plugin_peak,shadow_bytes,wall_s\n"
                    "point,1,slow,0,5.0,5.0,100,60,40,7,10.0\n"
                    "point,2,slow,0,9.0,9.0,200,60,140,14,20.0\n"
                    "point,1,fast,0,1.0,1.0,10,10,0,7,1.0\n")
        fr = FakeRunner()
        cf = [("bunny", m, n, "1x1", "point") for n in (1, 2, 4) for m in ("slow", "fast")]
        got = load_lights(csvp, cf, fr)
        check(got[("bunny", "slow", 2, "1x1", "point")][0]["plugin_peak"] == 140 and
              got[("bunny", "slow", 4, "1x1", "point")] == [] and not fr.calls and
              fr.skipped.get(("slow", "point")) == (2, 20.0) and
              fr.skipped.get(("fast", "point")) == (1, 1.0),
              "lights csv: %r %r" % (got, fr.skipped))
    finally:
        shutil.rmtree(tmpd, ignore_errors=True)
    fr = FakeRunner()
    repeated(fr, cfgs, 1, "self-test")
    check(len(fr.calls) == 16 and not fr.skipped, "no budget: every config runs")
    real = os.path.join(ROOT, "docs", "volumetric.md")
    if os.path.exists(real):
        rows = parse_doc_lights(open(real).read())
        check(rows and all("screen ms" in r for r in rows.values()),
              "docs/volumetric.md's lights table: %r" % rows)
    if fails:
        for x in fails:
            sys.stderr.write("bench_volumetric self-test: FAILED %s\n" % x)
        return 1
    print("bench_volumetric self-test: all checks passed")
    return 0


# ---- main ------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench_volumetric"))
    ap.add_argument("--size", default="1067x730")
    ap.add_argument("--sizes", default=DEFAULT_SIZES)
    ap.add_argument("--frames", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--experiments", default="crossover,table6,lights,gating")
    ap.add_argument("--scenes", default="bunny,dragon,dragons,classroom,courtyard")
    ap.add_argument("--crossover-scenes", default="bunny,dragon")
    ap.add_argument("--lights", default="1,2,4,8,16,32")
    ap.add_argument("--light-types", default=",".join(LIGHT_TYPES))
    ap.add_argument("--methods", default=",".join(METHODS))
    ap.add_argument("--shadow-resolution", type=int, default=1024)
    ap.add_argument("--max-seconds", type=float, default=None,
                    help="lights experiment: a method and light type whose run took longer "
                    "than this (wall time) runs no larger light count")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--crossover-csv", help="make the crossover's tables and plots from this "
                    "crossover.csv of an earlier run instead of measuring")
    ap.add_argument("--lights-csv", help="make the lights experiment's tables and plots "
                    "from this lights.csv of an earlier run instead of measuring")
    ap.add_argument("--self-test", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        sys.exit(self_test())
    if a.quick:
        a.size, a.sizes, a.frames, a.repeat, a.lights = ("534x365", "256x175,534x365", 2, 1,
                                                         "1,4,32")
    if a.frames < 1 or a.repeat < 1:
        die("--frames and --repeat: 1 or more")
    exe = os.path.join(a.build, "lightgraph")
    if not os.path.exists(exe):
        die("%s does not exist: build first (meson setup build && ninja -C build)" % exe)
    methods = a.methods.split(",")
    for m in methods:
        if m not in METHODS:
            die("unknown method %s (known: %s)" % (m, ", ".join(METHODS)))
    for s in a.scenes.split(",") + a.crossover_scenes.split(","):
        if s not in SCENES:
            die("unknown scene %s (known: %s)" % (s, ", ".join(SCENES)))
    exps = a.experiments.split(",")
    for e in exps:
        if e not in ("crossover", "table6", "lights", "gating"):
            die("unknown experiment %s" % e)
    try:
        parse_size(a.size)
    except BenchError as e:
        die(str(e))
    os.makedirs(a.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="bench-vol-")
    load0, t0 = loadavg(), datetime.datetime.now(datetime.timezone.utc)
    md = []
    try:
        runner = Runner(exe, a.frames, a.shadow_resolution, a.out, tmp)
        if "crossover" in exps:
            exp_crossover(runner, a, methods, md)
        if "table6" in exps:
            exp_table6(runner, a, methods, md)
        if "lights" in exps:
            exp_lights(runner, a, methods, md)
        if "gating" in exps:
            exp_gating(runner, a, md)
    except BenchError as e:
        die(str(e))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    t1 = datetime.datetime.now(datetime.timezone.utc)
    head = ["# Volumetric lighting: the thesis's experiments (tools/bench_volumetric.py)", "",
            "Run %s to %s on %s (%d cores, shared), load average %s before and %s after, "
            "commit %s. %d frames per run, %d runs per configuration (medians, min-max in "
            "brackets), shadow maps %d^2, froxel grid 190 x 90 x 128, screen-space 64 samples, "
            "polygonal one vertex per shadow-map texel."
            % (t0.strftime("%Y-%m-%d %H:%M"), t1.strftime("%H:%M UTC"), cpu_model(),
               os.cpu_count() or 0, load0, loadavg(), git_commit(), a.frames, a.repeat,
               a.shadow_resolution), ""]
    md = head + md
    with open(os.path.join(a.out, "bench_volumetric.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md))
    print("written: %s" % a.out)


if __name__ == "__main__":
    main()
