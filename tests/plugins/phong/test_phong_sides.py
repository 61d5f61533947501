#!/usr/bin/env python3
"""Which side of a double-sided facet is lit is decided by winding (gl_FrontFacing) in
every shading mode, as glTF's doubleSided prescribes: flat shading used to decide by the
sign of N.V with the one view direction of viewer = infinite, and at a grazing angle the
two disagree.

The bunny box from [0, 1.05, -2.8] towards [0.06, 0.68, 0] (fov 42), one directional
light travelling [0.35, -0.55, 0.75], no shadow map, viewer = infinite: the green wall is
seen at a grazing angle with the light on its far side, so it is in ambient light. It is
rendered in flat and in phong mode and, as the reference, with the light's intensity 0
(ambient only); on the green wall (the pixels that are green in the reference) flat and
phong must both equal the reference. Before the fix, flat lit the whole wall.

usage: test_phong_sides.py   (through meson test: LG_EXE, LG_SOURCE_ROOT, LG_BUILD_ROOT)
"""
import os
import struct
import subprocess
import sys
import tempfile
import zlib

W, H = 96, 60


def read_png(path):
    """8-bit RGB or RGBA, non-interlaced (what `lightgraph render -o x.png` writes): rows of
    (r, g, b) tuples."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG" % path)
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    w, h, depth, ctype, _, _, interlace = hdr
    if depth != 8 or ctype not in (2, 6) or interlace:
        raise ValueError("%s: depth %d colour type %d interlace %d not handled" % (path, depth, ctype, interlace))
    bpp = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if ft == 1:
                line[i] = (line[i] + a) & 255
            elif ft == 2:
                line[i] = (line[i] + b) & 255
            elif ft == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(w)])
        prev = line
    return rows


def main():
    exe, src = os.environ["LG_EXE"], os.environ["LG_SOURCE_ROOT"]
    box = os.path.join(src, "assets/meshes/bunny_cornell_box.glb")
    if not os.path.isfile(box):
        print("FAIL: %s is missing (a repository asset)" % box)
        return 1
    with tempfile.TemporaryDirectory(dir=os.environ.get("LG_BUILD_ROOT")) as tmp:
        graph = os.path.join(tmp, "wall.lgraph")
        with open(graph, "w") as f:
            f.write("""lightgraph 1
scene = gltf { file = "%s" }
sun = light { scene = scene, direction = [0.35, -0.55, 0.75], intensity = 2 }
cam = camera { scene = sun, mode = look_at, position = [0, 1.05, -2.8], target = [0.06, 0.68, 0], fov_deg = 42 }
lit = phong { scene = cam, viewer = infinite, ambient = [0.3, 0.3, 0.3] }
output lit "out.png"
""" % box)
        imgs = {}
        for name, sets in (("reference", ["lit.shading=phong", "sun.intensity=0"]),
                           ("flat", ["lit.shading=flat"]), ("phong", ["lit.shading=phong"]),
                           ("mixed", ["lit.shading=mixed"])):
            out = os.path.join(tmp, name + ".png")
            cmd = [exe, "render", graph, "-o", out, "--size", "%dx%d" % (W, H), "-q"]
            for s in sets:
                cmd += ["--set", s]
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode != 0:
                sys.stdout.write(r.stdout + r.stderr)
                if "no OpenGL 4.5 device" in r.stderr:
                    print("SKIP: no GL device")
                    return 77
                print("FAIL: %s" % " ".join(cmd))
                return 1
            imgs[name] = read_png(out)
        ref = imgs["reference"]
        wall = [(x, y) for y in range(H) for x in range(W)
                if ref[y][x][1] >= 8 and ref[y][x][1] > 3 * max(ref[y][x][0], ref[y][x][2])]
        print("green wall: %d of %d pixels" % (len(wall), W * H))
        if len(wall) < W * H // 20:
            print("FAIL: the green wall covers %d pixels; the view does not show it" % len(wall))
            return 1
        failed = 0
        for mode in ("flat", "phong", "mixed"):
            img = imgs[mode]
            # 2/255: rounding; a few pixels on the wall's edges may differ (coverage)
            off = [(x, y) for x, y in wall if max(abs(img[y][x][c] - ref[y][x][c]) for c in range(3)) > 2]
            mean_g = sum(img[y][x][1] for x, y in wall) / len(wall)
            mean_ref = sum(ref[y][x][1] for x, y in wall) / len(wall)
            print("%s: mean green on the wall %.1f (ambient only: %.1f), %d pixel(s) differ" %
                  (mode, mean_g, mean_ref, len(off)))
            if len(off) > len(wall) // 50:
                x, y = off[0]
                print("FAIL: %s shading lights the green wall: %d of %d pixels are not the ambient "
                      "colour (e.g. (%d, %d): %s, ambient only %s)" %
                      (mode, len(off), len(wall), x, y, img[y][x], ref[y][x]))
                failed += 1
        return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
