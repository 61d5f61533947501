#!/usr/bin/env python3
"""Load time and peak memory of the `gltf` node's loader (plugins/scene_gltf).

Runs lg_bench_scene_load (tools/bench_scene_load.c) once per file, in a fresh process each
so that the peak resident memory is that file's, and prints a Markdown table for
plugins/scene_gltf/README.md. The loader runs without the host: the figures are the
node's prepare() cost (read, parse, Draco decode, normals, bounds), nothing else.

    tools/bench_scene_load.py --build build [--repeat 5] [FILE...]
"""
import argparse
import os
import platform
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_FILES = [
    "assets/meshes/bunny_cornell_box.glb",
    "assets/meshes/bunny_cornell_box_draco.glb",
    "assets/meshes/dragon_vrip_draco.glb",
    "assets/meshes/dragon_vrip_x6_instanced_draco.glb",
]


def run(util, path, repeat):
    out = subprocess.run([util, "--repeat", str(repeat), path], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"bench_scene_load: {path}: {out.stderr.strip()}")
    return dict(kv.split("=", 1) for kv in out.stdout.split())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--util", help="lg_bench_scene_load (default: BUILD/tools/lg_bench_scene_load)")
    ap.add_argument("--repeat", type=int, default=5, help="loads per file; the best and median are shown")
    ap.add_argument("files", nargs="*")
    a = ap.parse_args()
    util = a.util or os.path.join(a.build, "tools", "lg_bench_scene_load")
    files = a.files or [os.path.join(ROOT, f) for f in DEFAULT_FILES]
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    print(f"lg_bench_scene_load, {a.repeat} loads per file, {cpu}, {os.cpu_count()} cores\n")
    print("| file | triangles (rendered) | vertices | meshes | instances | mesh arrays MB "
          "| load ms (best / median) | peak RSS MB (before load) |")
    print("|---|---|---|---|---|---|---|---|")
    for path in files:
        r = run(util, path, a.repeat)
        print(f"| `{os.path.basename(path)}` | {int(r['triangles']):,} | {int(r['vertices']):,} "
              f"| {r['meshes']} | {r['instances']} | {r['mesh_mb']} "
              f"| {r['best_ms']} / {r['median_ms']} | {r['peak_rss_mb']} ({r['rss_before_mb']}) |")


if __name__ == "__main__":
    main()
