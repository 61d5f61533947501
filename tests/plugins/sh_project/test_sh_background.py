#!/usr/bin/env python3
"""sh_background (plugins/sh_project) against the closed form of the real SH basis.

The test plugin `kindmaker` (tests/plugins/testnodes/testparts.c) publishes known
coefficients: with B bands, coefficient i of the R plane is i, of the G plane i + B^2, of
the B plane i + 2 B^2. sh_background reconstructs sum_i c_i Y_i(d) at each pixel centre's
direction d; this script evaluates the same sum with the closed forms of bands 0..2 from
the SH literature (Sloan, "Stupid SH tricks": Y_00 = 1 / (2 sqrt(pi)), Y_1,-1 =
sqrt(3 / (4 pi)) y, ...; docs/sh.md's convention), never with lg_sh_eval, at directions
computed from the
documented lat-long convention (lightgraph/probe.h) and a pinhole camera. The node has one
backend (CPU): every case runs on it.

  latlong  all pixels of a 24x12 lat-long, bands 0 (all 3), 2 and 1, within 1e-6 of the
           terms' size
  camera   all pixels of a 20x10 view through a look_at camera, bands 3
  bad      bands above the input's, view = camera without a scene: exit 1, the message
           names the node and why, no output file written

usage: test_sh_background.py CASE
"""
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "unit", "host"))
import exr_read  # noqa: E402

EXE = os.environ["LG_EXE"]
SRC = os.environ["LG_SOURCE_ROOT"]
TMP = tempfile.mkdtemp(prefix="lg-shbg-")
ENV = dict(os.environ)
ENV["LIGHTGRAPH_PLUGIN_PATH"] = os.environ["LG_TEST_PLUGINS"] + ":" + os.path.join(
    os.environ["LG_BUILD_ROOT"], "plugins")


class Fail(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Fail(msg)


def y_closed(d):
    """The nine real SH functions of bands 0..2 at unit direction d, index l(l+1)+m."""
    x, y, z = d
    k0 = 0.5 / math.sqrt(math.pi)             # 0.282095
    k1 = math.sqrt(3 / (4 * math.pi))         # 0.488603
    k2 = math.sqrt(15 / (4 * math.pi))        # 1.092548
    k20 = math.sqrt(5 / (16 * math.pi))       # 0.315392
    k22 = math.sqrt(15 / (16 * math.pi))      # 0.546274
    return [k0,
            k1 * y, k1 * z, k1 * x,
            k2 * x * y, k2 * y * z, k20 * (3 * z * z - 1),
            k2 * x * z, k22 * (x * x - y * y)]


def expected(d, bands, have=3):
    """The sum per channel, and the sum of the terms' magnitudes (the scale of its
    rounding error)."""
    ys = y_closed(d)[:bands * bands]
    nc = have * have
    return ([sum((i + ch * nc) * ys[i] for i in range(len(ys))) for ch in range(3)],
            [sum(abs((i + ch * nc) * ys[i]) for i in range(len(ys))) for ch in range(3)])


def latlong_dir(u, v):
    phi, theta = 2 * math.pi * (u - 0.5), math.pi * v
    return (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))


def norm(a):
    n = math.sqrt(sum(c * c for c in a))
    return tuple(c / n for c in a)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def render(graph_text, size, args=(), expect=0, out="o.exr"):
    g = os.path.join(TMP, "g.lgraph")
    with open(g, "w") as f:
        f.write(graph_text)
    path = os.path.join(TMP, out)
    p = subprocess.run([EXE, "render", g, "-o", path, "--size", size] + list(args),
                       capture_output=True, text=True, env=ENV, timeout=120)
    check(p.returncode == expect, "render exited %d, expected %d:\n%s" %
          (p.returncode, expect, p.stderr[-3000:]))
    return path, p.stderr


def compare(path, dir_of, bands, what):
    rows = exr_read.read_exr(path)
    h, w = len(rows), len(rows[0])
    worst = 0.0
    for j in range(h):
        for i in range(w):
            want, scale = expected(dir_of((i + 0.5) / w, (j + 0.5) / h), bands)
            got = rows[j][i][:3]
            for a, b, m in zip(got, want, scale):
                # the node sums in double and stores a float: its error is the float's
                # rounding, 6e-8 of the terms' size; 1e-6 leaves room for the direction's
                # float inputs (the camera's position, target and field of view)
                err = abs(a - b) / max(1.0, m)
                worst = max(worst, err)
                check(err < 1e-6, "%s: pixel (%d, %d) is %s, the closed form %s" %
                      (what, i, j, got, want))
    # a wrong convention (the lat-long turned, a plane's stride, a band more or less) is
    # off by far more than this
    return worst


GRAPH = """lightgraph 1
km = kindmaker { bands = 3 }
bg = sh_background { sh = km.sh, bands = %d %s }
%s
output bg "o.exr"
"""


def t_latlong():
    for bands in (0, 2, 1):
        path, _ = render(GRAPH % (bands, "", ""), "24x12")
        worst = compare(path, latlong_dir, bands or 3, "latlong bands=%d" % bands)
        print("latlong bands=%d: worst relative error %.2e" % (bands, worst))


def t_camera():
    pos, target, fov = (0.3, 0.5, 2.0), (-0.2, 0.4, -1.0), 50.0
    scene = ('scene = gltf { file = "%s" }\n'
             'cam = camera { scene = scene, mode = look_at, position = [%g, %g, %g], '
             'target = [%g, %g, %g], fov_deg = %g }' %
             ((os.path.join(SRC, "assets", "meshes", "bunny_box_prt.glb"),) + pos + target +
              (fov,)))
    path, _ = render(GRAPH % (3, ", view = camera, scene = cam", scene), "20x10")
    f = norm(tuple(t - p for t, p in zip(target, pos)))
    r = norm(cross(f, (0.0, 1.0, 0.0)))
    up = cross(r, f)
    ty = math.tan(math.radians(fov) / 2)
    aspect = 20 / 10

    def cam_dir(u, v):
        a, b = (2 * u - 1) * ty * aspect, (1 - 2 * v) * ty
        return norm(tuple(f[k] + a * r[k] + b * up[k] for k in range(3)))

    worst = compare(path, cam_dir, 3, "camera")
    print("camera: worst relative error %.2e" % worst)


def t_bad():
    path, err = render(GRAPH % (4, "", ""), "8x4", expect=1)
    check("node 'bg' (sh_background): bands = 4, but the input 'sh' holds 3 bands" in err,
          "no clear message for too many bands:\n" + err)
    check(not os.path.exists(path), "an output was written for a failed render")
    path, err = render(GRAPH % (0, ", view = camera", ""), "8x4", expect=1)
    check("view = camera needs the input 'scene'" in err,
          "no clear message for a camera view without a scene:\n" + err)
    check(not os.path.exists(path), "an output was written for a failed render")


def main():
    tests = {k[2:]: v for k, v in globals().items() if k.startswith("t_")}
    name = sys.argv[1] if len(sys.argv) > 1 else ""
    if name not in tests:
        print("usage: test_sh_background.py CASE (%s)" % " ".join(sorted(tests)))
        return 2
    try:
        tests[name]()
    except Fail as e:
        print("FAIL %s: %s" % (name, e))
        return 1
    print("ok %s" % name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
