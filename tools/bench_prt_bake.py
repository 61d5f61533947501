#!/usr/bin/env python3
"""The prt_bake benchmark (issue 10 item 5, bake bullets); plugins/prt_bake/README.md has the
figures. Runs `lightgraph render` on graphs of the real `prt_bake` node with an empty cache
each time, reads the node's log (-v) and the process's peak memory (/usr/bin/time), and
prints markdown tables:

  1. occlusion throughput on the bunny box: the bake's visibility pass against bare Embree
     queries (rtcOccluded1, rtcOccluded16) on the same rays in the same run (prt_bake
     `bench = true`), and against `visibility = brute`. Brute is measured with samples = 2
     (16 directions: about 8 rays per vertex) and compared per ray: its cost per ray does not
     depend on the direction count, only on the triangle count.
  2. bake time and peak memory against mesh size (bunny box, the 871k-triangle dragon).
  3. bake time and peak memory against bands (1 .. 8) on the bunny box.

    tools/bench_prt_bake.py --build build [--dragon PATH] [--samples N]
    ninja -C build bench-prt-bake
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile


TEST_PLUGINS = ""


def render(exe, graph, threads=None):
    """Renders `graph` (text) with an empty cache; returns (log text, peak RSS MiB)."""
    with tempfile.TemporaryDirectory(prefix="bench-prt-") as d:
        path = os.path.join(d, "g.lgraph")
        with open(path, "w") as f:
            f.write(graph)
        env = dict(os.environ)
        env["LIGHTGRAPH_CACHE_DIR"] = os.path.join(d, "cache")
        if threads:
            env["LIGHTGRAPH_THREADS"] = str(threads)
        env["LIGHTGRAPH_PLUGIN_PATH"] = TEST_PLUGINS
        cmd = ["/usr/bin/time", "-f", "PEAK_KB %M", exe, "render", path, "-v"]
        p = subprocess.run(cmd, cwd=d, env=env, capture_output=True, text=True)
        text = p.stdout + p.stderr
        if p.returncode != 0:
            sys.exit("render failed:\n" + graph + "\n" + text)
        m = re.search(r"PEAK_KB (\d+)", text)
        return text, (int(m.group(1)) / 1024.0 if m else float("nan"))


def graph(mesh, params, bands=3):
    # the transfer reaches an output through the test plugin's test_transfer_image (the
    # `prt` node that would normally consume it is not needed to time the bake)
    return ("lightgraph 1\n"
            f"s = gltf {{ file = \"{mesh}\" }}\n"
            f"b = prt_bake {{ scene = s, bands = {bands}, {params} }}\n"
            f"v = test_transfer_image {{ transfer = b, bands = {bands} }}\n"
            "output v \"t.exr\"\n")


def triangles(text):
    m = re.search(r"(\d+) triangles", text)
    return int(m.group(1)) if m else 0


def baked(text):
    m = re.search(r"transfer baked in ([0-9.]+) s \((\d+) vertices, (\d+) bands, \w+, "
                  r"(\d+) directions, (\w+) visibility, (\d+) rays, ([0-9.e+]+) rays/s in the "
                  r"visibility pass of ([0-9.]+) s, (\d+) threads", text)
    if not m:
        sys.exit("no bake line in:\n" + text)
    return dict(seconds=float(m.group(1)), vertices=int(m.group(2)), bands=int(m.group(3)),
                directions=int(m.group(4)), rays=int(m.group(6)), rate=float(m.group(7)),
                pass_s=float(m.group(8)), threads=int(m.group(9)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build")
    ap.add_argument("--source", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--dragon", default="/work/shared/assets/meshes/derived/dragon_vrip_draco.glb")
    ap.add_argument("--samples", type=int, default=32)
    a = ap.parse_args()
    global TEST_PLUGINS
    TEST_PLUGINS = os.path.abspath(os.path.join(a.build, "tests/plugins/prt_bake"))
    exe = os.path.abspath(os.path.join(a.build, "lightgraph"))
    bunny = os.path.join(a.source, "assets/meshes/bunny_cornell_box.glb")

    print("## Occlusion throughput (bunny box, shadowed, %d^2 directions)\n" % a.samples)
    text, rss = render(exe, graph(bunny, f"samples = {a.samples}, bench = true"))
    b = baked(text)
    m = re.search(r"bench: bake \(rtcOccluded16\) ([0-9.e+]+) rays/s, bare rtcOccluded1 ([0-9.e+]+) rays/s, "
                  r"rtcOccluded16 ([0-9.e+]+) rays/s", text)
    bake_r, raw1, raw16 = (float(x) for x in m.groups())
    text_b, _ = render(exe, graph(bunny, "samples = 4, visibility = brute"))
    br = baked(text_b)
    print("| what | rays/s | ratio |")
    print("|---|---:|---:|")
    print(f"| bake (rtcOccluded16 packets + SH accumulation), {b['threads']} threads | {bake_r:.3g} | 1 |")
    print(f"| bare rtcOccluded1, same rays | {raw1:.3g} | bake at {100 * bake_r / raw1:.0f}% |")
    print(f"| bare rtcOccluded16 packets, same rays | {raw16:.3g} | bake at {100 * bake_r / raw16:.0f}% |")
    print(f"| brute (seed's loop, per-ray rate) | {br['rate']:.3g} | bake {bake_r / br['rate']:.0f}x faster |")
    print(f"\n({b['vertices']} vertices, {triangles(text)} triangles, {b['rays']} rays; "
          f"brute: {br['rays']} rays with 16 directions, rate per ray.)\n")

    print("## Bake time and memory against mesh size (shadowed, 3 bands, %d^2 directions)\n" % a.samples)
    print("| mesh | triangles | vertices | rays | bake s | visibility pass s | rays/s | peak RSS MiB |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    meshes = [("bunny box", bunny)]
    if os.path.exists(a.dragon):
        meshes.append(("dragon 871k", a.dragon))
    for name, path in meshes:
        text, rss = render(exe, graph(path, f"samples = {a.samples}"))
        r = baked(text)
        print(f"| {name} | {triangles(text)} | {r['vertices']} | {r['rays']} | {r['seconds']:.2f} | {r['pass_s']:.2f} "
              f"| {r['rate']:.3g} | {rss:.0f} |")

    print("\n## Bake time and memory against bands (bunny box, shadowed, %d^2 directions)\n" % a.samples)
    print("| bands | coefficients | bake s | visibility pass s | peak RSS MiB |")
    print("|---:|---:|---:|---:|---:|")
    for n in range(1, 9):
        text, rss = render(exe, graph(bunny, f"samples = {a.samples}", bands=n))
        r = baked(text)
        print(f"| {n} | {n * n} | {r['seconds']:.2f} | {r['pass_s']:.2f} | {rss:.0f} |")


if __name__ == "__main__":
    main()
