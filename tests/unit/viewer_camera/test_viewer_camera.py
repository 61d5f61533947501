#!/usr/bin/env python3
"""The viewer's camera as a graph node (host/viewer/camera.h, lg_vcam_node_text), through the
real program and the real scene_tools `camera` node.

test_viewer_camera cases prints cameras the controller made (look_at as given, after orbit and
zoom, at the pitch limit, after a pan, after fly look and move with znear/zfar/aspect, at the
zoom floor), each as its pasted node text and as its exact floats. Two graphs on the bunny box:
one with the pasted texts, one with the same cameras written with every digit. Both must check
and render (the camera node's run-time checks: fov inside (0, 180), up not parallel, target not
the eye), and each pasted camera must give the picture of its exact one. A control: the first
camera turned by two degrees must not pass the same comparison, so the comparison can fail.

usage: test_viewer_camera.py PATH_TO_test_viewer_camera
"""
import os
import shutil
import subprocess
import sys
import tempfile

EXE = os.environ["LG_EXE"]
ROOT = os.environ["LG_SOURCE_ROOT"]
TMP = tempfile.mkdtemp(prefix="lg-vcam-test-")
MESH = os.path.join(ROOT, "assets", "meshes", "bunny_cornell_box.glb")
W, H = 64, 48
# RMSE between the 6-digit and the exact camera: measured 0 but at the zoom floor (8e-5);
# the limit lets a few pixels flip across an edge (one pixel changing fully in every channel
# is 1/sqrt(W*H) = 0.018). The control (2 degrees off) measures 0.055.
MAX_RMSE = 0.02


class Fail(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Fail(msg)


def run(args, expect=None, timeout=120):
    env = dict(os.environ)
    env["LIGHTGRAPH_PLUGIN_PATH"] = ""
    env["LIGHTGRAPH_CACHE_DIR"] = os.path.join(TMP, "cache")
    p = subprocess.run(args, env=env, capture_output=True, text=True, timeout=timeout)
    if expect is not None and p.returncode != expect:
        raise Fail("%s: exit %d, expected %d\nstdout:\n%s\nstderr:\n%s" %
                   (" ".join(args), p.returncode, expect, p.stdout, p.stderr))
    return p


def cases(helper):
    """[(name, node text, ref floats)] from the helper's output."""
    out = run([helper, "cases"], expect=0).stdout
    result, name, text, ref = [], None, [], None
    for line in out.splitlines():
        if line.startswith("CASE "):
            name, text, ref = line[5:], [], None
        elif line.startswith("REF "):
            ref = [float(x) for x in line[4:].split()]
        elif line == "END":
            check(name and ref and len(ref) == 13, "malformed case output:\n" + out)
            result.append((name, "\n".join(text) + "\n", ref))
            name = None
        else:
            text.append(line)
    check(len(result) >= 5, "expected at least 5 cases:\n" + out)
    return result


def exact_node(name, ref):
    p, t, u = ref[0:3], ref[3:6], ref[6:9]
    vec = lambda v: "[%s]" % ", ".join("%.9g" % x for x in v)
    s = ("c_%s = camera { scene = scene, mode = look_at, position = %s, target = %s, up = %s,\n"
         "    fov_deg = %.9g, znear = %.9g, zfar = %.9g, aspect = %.9g }\n" %
         (name, vec(p), vec(t), vec(u), ref[9], ref[10], ref[11], ref[12]))
    return s


def graph(file, nodes, names, tag):
    text = "lightgraph 1\nscene = gltf { file = \"%s\" }\n" % MESH
    text += "".join(nodes)
    for n in names:
        text += ("v_%s = preview { scene = c_%s, mode = normals, width = %d, height = %d }\n" %
                 (n, n, W, H))
        text += "output v_%s \"%s\"\n" % (n, os.path.join(TMP, "%s_%s.png" % (tag, n)))
    path = os.path.join(TMP, file)
    with open(path, "w") as f:
        f.write(text)
    return path


def rmse(a, b):
    p = run([EXE, "diff", a, b, "--json"])
    check(p.returncode in (0, 1) and p.stdout.strip().startswith("{"),
          "diff %s %s: %s%s" % (a, b, p.stdout, p.stderr))
    import json
    return json.loads(p.stdout)["rmse"]


def main(helper):
    cs = cases(helper)
    names = [c[0] for c in cs]
    pasted = graph("pasted.lgraph", [c[1] for c in cs], names, "pasted")
    exact = graph("exact.lgraph", [exact_node(c[0], c[2]) for c in cs], names, "exact")
    run([EXE, "check", pasted], expect=0)
    run([EXE, "render", pasted], expect=0)
    run([EXE, "render", exact], expect=0)
    worst = 0.0
    for n in names:
        e = rmse(os.path.join(TMP, "pasted_%s.png" % n), os.path.join(TMP, "exact_%s.png" % n))
        print("%-12s rmse %.4g" % (n, e))
        check(e <= MAX_RMSE, "camera %s: the pasted node renders with RMSE %g against the exact "
              "camera (limit %g)" % (n, e, MAX_RMSE))
        worst = max(worst, e)

    # the control: the first camera turned by 2 degrees about +Y through its target
    import math
    name, _, ref = cs[0]
    a = math.radians(2.0)
    p, t = ref[0:3], ref[3:6]
    ox, oz = p[0] - t[0], p[2] - t[2]
    turned = list(ref)
    turned[0] = t[0] + ox * math.cos(a) + oz * math.sin(a)
    turned[2] = t[2] - ox * math.sin(a) + oz * math.cos(a)
    ctl = graph("control.lgraph", [exact_node(name, turned)], [name], "control")
    run([EXE, "render", ctl], expect=0)
    e = rmse(os.path.join(TMP, "control_%s.png" % name), os.path.join(TMP, "exact_%s.png" % name))
    print("control rmse %.4g (must exceed %g)" % (e, MAX_RMSE))
    check(e > MAX_RMSE, "a camera turned by 2 degrees gives RMSE %g, within the limit %g: the "
          "comparison cannot tell cameras apart" % (e, MAX_RMSE))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    try:
        main(sys.argv[1])
    except Fail as e:
        print("FAIL viewer_camera_node_text: %s" % e, file=sys.stderr)
        sys.exit(1)
    finally:
        if not os.environ.get("LG_KEEP_TMP"):
            shutil.rmtree(TMP, ignore_errors=True)
    print("ok viewer_camera_node_text")
