#!/usr/bin/env python3
"""examples/ibl.lgraph through the real program, with every probe of assets/probes/.

  every_probe   `render examples/ibl.lgraph --size 96x54 --set sky.file=P` for each probe
                file P in assets/probes/ (EXR of every compression there, Radiance .hdr;
                lat-long, angular, cube cross and strip: `layout = auto` tells them apart),
                exit 0, and the tone-mapped picture read back:
                  - every pixel finite, none negative;
                  - the background (pixels whose camera ray misses the bounding spheres of
                    the three objects, computed here from the example's camera) is the
                    probe: not black (mean above 0.02, under 5 % of its pixels black);
                  - the mirror and gold spheres' pixels are not black;
                  - the same environment agrees across files: each probe's picture is
                    compared with the one of a lossless reference of its environment (the
                    prefix before the first '_': forest, studio, apartment), of the same
                    size when there is one (mean absolute difference over the background
                    and over the spheres below TOL_SAME), else of another layout or size
                    (below TOL_RESAMPLED).
                The probes present must cover lat-long and angular maps (by their sizes:
                2:1, 1:1; 4:3, 3:4, 6:1, 1:6 are the cube layouts).
  set_errors    --set sky.file= a missing file, or one of a size no layout has, exits 1
                naming the node and the file.

The ibl plugin (reflect, background) must be built: a missing node is a failure.

usage: test_ibl_example.py TEST_NAME
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import exr_read  # noqa: E402
import lgrun  # noqa: E402
from lgrun import Fail, check  # noqa: E402

SRC = os.environ["LG_SOURCE_ROOT"]
TMP = lgrun.temp_dir("lg-ibl-example-")
GRAPH = os.path.join(SRC, "examples", "ibl.lgraph")
PROBES = os.path.join(SRC, "assets", "probes")
W, H = 96, 54

# The example's camera (examples/ibl.lgraph `cam`) and the objects of
# assets/meshes/ibl_spheres.glb (tools/make_ibl_scene.py): unit spheres at x = -2.3 and 0,
# centre height 1; the bunny at x = 2.3, 1.9 tall from y = 0 (its bounding sphere: centre
# (2.3, 0.95, 0), radius 1.6 holds it).
EYE, TARGET, FOV_DEG = (0.0, 1.3, 9.5), (0.0, 0.95, 0.0), 30.0
SPHERES = [((-2.3, 1.0, 0.0), 1.0), ((0.0, 1.0, 0.0), 1.0)]
BUNNY = ((2.3, 0.95, 0.0), 1.6)

# Each probe's picture is compared with the one of a lossless reference of the same
# environment (the file name's prefix before the first '_'): of the same size when there is
# one (then only the file format and compression differ: TOL_SAME), else the environment's
# main one (another layout or resolution: the resampling and the probe's texel size blur
# the picture differently: TOL_RESAMPLED). Measured (mean absolute difference of the
# tone-mapped pictures, background / spheres): B44 0.0016 / 0.0009, DWAA 0.0007 / 0.0004,
# the forest .hdr 0.0003 / 0.0002; angular 1024 0.0231 / 0.0145, cube strip of 128 texel
# faces 0.0277 / 0.0213, cross of 256 0.0121 / 0.0089 (a 256x128 lat-long would be 0.0415).
REFERENCES = ["forest_1024x512_zip.exr", "forest_256x128_half_none.exr", "studio_1024x512_float_dwab.exr",
              "apartment_512x256_half_dwab.exr"]
MAIN_REFERENCE = {"forest": "forest_1024x512_zip.exr", "studio": "studio_1024x512_float_dwab.exr",
                  "apartment": "apartment_512x256_half_dwab.exr"}
# studio_512x256_half_dwab.exr is another studio (@pmndrs/assets, not blender's): no reference
OWN_REFERENCE = {"studio_512x256_half_dwab.exr"}
TOL_SAME = 0.005
TOL_RESAMPLED = 0.04


def run(args, expect=None, timeout=120):
    return lgrun.run(args, lgrun.env("", os.path.join(TMP, "cache")), expect, timeout)


# the EXR reader: exr_read.py (shared with test_prt_example.py)
def read_exr(path):
    try:
        return exr_read.read_exr(path)
    except exr_read.ExrError as e:
        raise Fail(str(e))


# ---- which pixels are background, which are sphere -------------------------------------

def norm(v):
    n = math.sqrt(sum(x * x for x in v))
    return tuple(x / n for x in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def ray_distance(d, centre):
    """Distance from `centre` to the camera ray of unit direction d (inf behind the eye)."""
    oc = tuple(centre[k] - EYE[k] for k in range(3))
    t = sum(oc[k] * d[k] for k in range(3))
    if t <= 0:
        return math.inf
    p = tuple(EYE[k] + t * d[k] - centre[k] for k in range(3))
    return math.sqrt(sum(x * x for x in p))


def masks():
    """(background, spheres): lists of (x, y). Background: the ray misses every bounding
    sphere by a pixel's angle at least; spheres: it passes well inside a sphere."""
    f = norm(tuple(TARGET[k] - EYE[k] for k in range(3)))
    r = norm(cross(f, (0.0, 1.0, 0.0)))
    u = cross(r, f)
    th = math.tan(math.radians(FOV_DEG) / 2)
    aspect = W / H
    pixel = 2 * th / H * 10.0  # a pixel's width, in radians, at 10 units: a margin
    bg, sp = [], []
    for y in range(H):
        for x in range(W):
            a = (2 * (x + 0.5) / W - 1) * th * aspect
            b = (1 - 2 * (y + 0.5) / H) * th
            d = norm(tuple(f[k] + a * r[k] + b * u[k] for k in range(3)))
            dist = [(ray_distance(d, c), rad) for c, rad in SPHERES + [BUNNY]]
            if all(di > rad + 2 * pixel for di, rad in dist):
                bg.append((x, y))
            elif any(di < rad - 0.15 for di, rad in dist[:2]):
                sp.append((x, y))
    return bg, sp


def lum(p):
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]


def probe_size(path):
    out = run(["diff", path, path], expect=0).stdout.splitlines()[0]
    # "A   file (WxH fmt, ...)"
    inner = out[out.rindex("(") + 1:]
    w, h = inner.split()[0].split("x")
    return int(w), int(h)


def layout_of(w, h):
    if w == 2 * h:
        return "latlong"
    if w == h:
        return "angular"
    if 3 * w == 4 * h or 4 * w == 3 * h:
        return "cross"
    if w == 6 * h or h == 6 * w:
        return "strip"
    return "?"


def render(probe, out):
    # a small GGX chain (faces of 16 texels, 32 samples): the glossy path runs with every
    # probe, at a tenth of the default chain's cost (the chain is cached per probe, and each
    # probe here is new)
    return run(["render", GRAPH, "--size", "%dx%d" % (W, H), "--set", "sky.file=" + probe,
                "--set", "refl.prefilter_size=16", "--set", "refl.prefilter_samples=32", "-o", out],
               expect=0, timeout=300)


def mean_abs(a, b, pixels):
    return sum(abs(a[y][x][c] - b[y][x][c]) for x, y in pixels for c in range(3)) / (3 * len(pixels))


def test_every_probe():
    files = sorted(f for f in os.listdir(PROBES)
                   if f.lower().endswith((".exr", ".hdr", ".pic")) and os.path.isfile(os.path.join(PROBES, f)))
    check(len(files) >= 10, "only %d probes in %s" % (len(files), PROBES))
    bg, sp = masks()
    check(len(bg) > W * H // 3 and len(sp) > 200, "masks: %d background, %d sphere pixels" % (len(bg), len(sp)))
    layouts, pictures, report = {}, {}, []
    for f in files:
        path = os.path.join(PROBES, f)
        layout = layout_of(*probe_size(path))
        layouts.setdefault(layout, []).append(f)
        out = os.path.join(TMP, f + ".exr")
        render(path, out)
        img = read_exr(out)
        check(len(img) == H and len(img[0]) == W, "%s: picture %dx%d" % (f, len(img[0]), len(img)))
        bad = [(x, y) for y in range(H) for x in range(W)
               if not all(math.isfinite(v) and v >= 0 for v in img[y][x][:3])]
        check(not bad, "%s: %d pixels not finite or negative, first %s: %s" %
              (f, len(bad), bad[0] if bad else "", img[bad[0][1]][bad[0][0]] if bad else ""))
        bl = [lum(img[y][x]) for x, y in bg]
        black = sum(1 for v in bl if v <= 1e-4)
        check(sum(bl) / len(bl) > 0.02 and black < 0.05 * len(bl),
              "%s: the background is black: mean %.4f, %d of %d pixels black" % (f, sum(bl) / len(bl), black, len(bl)))
        sl = [lum(img[y][x]) for x, y in sp]
        check(sum(sl) / len(sl) > 0.02, "%s: the spheres are black (mean %.4f)" % (f, sum(sl) / len(sl)))
        pictures[f] = img
    sizes = {f: probe_size(os.path.join(PROBES, f)) for f in files}
    for f in files:
        env = f.split("_")[0]
        if f in OWN_REFERENCE:
            continue
        same = [r for r in REFERENCES if r.split("_")[0] == env and r in sizes and sizes[r] == sizes[f]]
        ref = same[0] if same else MAIN_REFERENCE.get(env)
        tol = TOL_SAME if same else TOL_RESAMPLED
        check(ref in pictures, "%s: no reference probe for environment '%s' (%s)" % (f, env, ref))
        e_bg = mean_abs(pictures[f], pictures[ref], bg)
        e_sp = mean_abs(pictures[f], pictures[ref], sp)
        report.append("%-36s %-8s against %-32s background %.4f spheres %.4f (tolerance %g)" %
                      (f, layout_of(*sizes[f]), ref, e_bg, e_sp, tol))
        check(e_bg < tol and e_sp < tol,
              "%s differs from %s: mean abs %.4f over the background, %.4f over the spheres, tolerance %g\n%s" %
              (f, ref, e_bg, e_sp, tol, "\n".join(report)))
    print("\n".join(report))
    print("layouts: " + ", ".join("%s %d" % (k, len(v)) for k, v in sorted(layouts.items())))
    check("?" not in layouts, "probes of no known layout: %s" % layouts.get("?"))
    for need in ("latlong", "angular"):
        check(need in layouts, "no %s probe in %s" % (need, PROBES))


def test_set_errors():
    missing = os.path.join(TMP, "nope.hdr")
    p = run(["render", GRAPH, "--size", "%dx%d" % (W, H), "--set", "sky.file=" + missing,
             "-o", os.path.join(TMP, "x.exr")], expect=1)
    check("'sky'" in p.stderr and "nope.hdr" in p.stderr, "missing probe: %s" % p.stderr)
    # a 3x1 Radiance file (flat RGBE, three pixels of 1.0): no layout has that shape
    odd = os.path.join(TMP, "odd.hdr")
    with open(odd, "wb") as fh:
        fh.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 3\n" + bytes([128, 128, 128, 129]) * 3)
    p = run(["render", GRAPH, "--size", "%dx%d" % (W, H), "--set", "sky.file=" + odd,
             "-o", os.path.join(TMP, "y.exr")], expect=1)
    check("'sky'" in p.stderr and "odd.hdr" in p.stderr and "3x1" in p.stderr.replace(" x ", "x"),
          "a 3x1 probe: %s" % p.stderr)


TESTS = {"every_probe": test_every_probe, "set_errors": test_set_errors}

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
