#!/usr/bin/env python3
"""examples/demo.lgraph, the README's `make demo`, rendered by the suite at a small size:
it runs with every node kept (none culled or gated: the shadow map and the lights are
used), and its image has no NaN or Inf pixel and is not black.

usage: test_demo.py [WxH]   (through meson test: LG_EXE, LG_SOURCE_ROOT, LG_BUILD_ROOT)
"""
import json
import os
import subprocess
import sys
import tempfile

# Mean of the tone-mapped RGB over the image: the demo's is 0.19 at 160x90; an unlit or
# empty render (background 0.02 before tone mapping) stays far below.
MIN_MEAN = 0.05


def main():
    size = sys.argv[1] if len(sys.argv) > 1 else "160x90"
    exe, src = os.environ["LG_EXE"], os.environ["LG_SOURCE_ROOT"]
    demo = os.path.join(src, "examples", "demo.lgraph")
    if not os.path.isfile(demo):
        print("FAIL: %s is missing" % demo)
        return 1
    with tempfile.TemporaryDirectory(dir=os.environ.get("LG_BUILD_ROOT")) as tmp:
        out, prof = os.path.join(tmp, "demo.exr"), os.path.join(tmp, "profile.json")
        r = subprocess.run([exe, "render", demo, "-o", out, "--size", size, "--profile-json", prof,
                            "--explain"], capture_output=True, text=True)
        sys.stdout.write(r.stdout + r.stderr)
        if r.returncode != 0:
            if "no OpenGL 4.5 device" in r.stderr or "no OpenCL device" in r.stderr:
                print("SKIP: the demo needs a device this machine does not have")
                return 77
            print("FAIL: lightgraph render examples/demo.lgraph exited %d" % r.returncode)
            return 1
        failed = 0
        nodes = json.load(open(prof))["nodes"]
        not_run = [n["name"] for n in nodes if n.get("state") != "kept" or n.get("runs", 0) < 1]
        if not_run:
            print("FAIL: nodes of the demo that did not run: %s" % ", ".join(not_run))
            failed += 1
        types = {n["type"] for n in nodes}
        for t in ("gltf", "light", "shadowmap", "phong", "reinhard"):
            if t not in types:
                print("FAIL: the demo has no %s node: %s" % (t, sorted(types)))
                failed += 1
        black_g = os.path.join(tmp, "black.lgraph")
        with open(black_g, "w") as f:
            f.write('lightgraph 1\nc = constant { color = [0, 0, 0] }\noutput c "black.exr"\n')
        black = os.path.join(tmp, "black.exr")
        subprocess.run([exe, "render", black_g, "-o", black, "--size", size, "-q"], check=True)
        d = subprocess.run([exe, "diff", out, black, "--json"], capture_output=True, text=True)
        if d.returncode != 0:
            print("FAIL: lightgraph diff: " + d.stdout + d.stderr)
            return 1
        m = json.loads(d.stdout)
        w, h = (int(v) for v in size.split("x"))
        print("demo %dx%d: mean %.4f, max %.4f, non-finite pixels %d" %
              (m["width"], m["height"], m["mean_abs"], m["max_abs"], m["nonfinite"]))
        if (m["width"], m["height"]) != (w, h):
            print("FAIL: the demo rendered %dx%d, not %s" % (m["width"], m["height"], size))
            failed += 1
        if m["nonfinite"] != 0:
            print("FAIL: %d pixel(s) of the demo are NaN or Inf" % m["nonfinite"])
            failed += 1
        if not m["mean_abs"] >= MIN_MEAN:
            print("FAIL: the demo is black (mean %.4f < %.2f)" % (m["mean_abs"], MIN_MEAN))
            failed += 1
        return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
