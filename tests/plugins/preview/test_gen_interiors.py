#!/usr/bin/env python3
"""tools/gen_scene.py's spot lights and interiors (classroom, courtyard), read back here.

Reuses test_gen_scene.py's independent reader (container, accessors, bounds, normals) and
checks what the interiors promise:
  - spot lights: KHR_lights_punctual type spot, cones in radians, the node's -Z along the
    direction, defaults (0 and 45 degrees); bad cones and zero directions refused;
  - classroom: TEXCOORD_0 on every primitive; two PNG textures (decoded here: signature,
    CRCs, zlib, filters) used by the wood and floor materials; 3 x --slats slat nodes,
    tilted by --slat-tilt about their long axis, --slat-thickness thick, inside the window
    openings; the window wall has holes where the windows are (no wall triangle covers
    an opening's centre) and covers the piers; rows of desks and chairs; the sun, a spot
    light and a medium;
  - courtyard (--detail 0.01 and 0.02): TEXCOORD_0 everywhere; the leaf material alpha
    MASK with alphaCutoff 0.5, double-sided, its RGBA texture's alpha only 0 or 255 with
    both present; the triangle count (over instances) grows with --detail;
  - both loaded by the program: the gltf node's --explain counts the triangles this file
    counts, and the classroom's lights (a directional and a spot: "1 other");
  - determinism (same bytes twice) and bad arguments (exit 2 naming the option).
Exit 0 when every check passes, 1 otherwise.
"""
import math
import os
import re
import struct
import subprocess
import sys
import tempfile
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_gen_scene as T  # noqa: E402

check = T.check


def png_decode(data):
    """(width, height, channels, rows) of an 8-bit RGB/RGBA PNG, every chunk's CRC checked."""
    if not check(data[:8] == b"\x89PNG\r\n\x1a\n", "PNG signature"):
        return None
    off, idat, ihdr = 8, b"", None
    while off < len(data):
        n, tag = struct.unpack_from(">I4s", data, off)
        body = data[off + 8:off + 8 + n]
        crc, = struct.unpack_from(">I", data, off + 8 + n)
        check(zlib.crc32(tag + body) & 0xFFFFFFFF == crc, "PNG chunk %s CRC" % tag)
        if tag == b"IHDR":
            ihdr = struct.unpack(">IIBBBBB", body)
        elif tag == b"IDAT":
            idat += body
        off += 12 + n
    w, h, depth, ctype = ihdr[0], ihdr[1], ihdr[2], ihdr[3]
    check(depth == 8 and ctype in (2, 6), "PNG depth %d colour type %d" % (depth, ctype))
    ch = 3 if ctype == 2 else 4
    raw = zlib.decompress(idat)
    stride = w * ch
    check(len(raw) == h * (stride + 1), "PNG data length")
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b, c = prev[i], prev[i - ch] if i >= ch else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, ch, rows


def image_bytes(g, b, i):
    v = g["bufferViews"][g["images"][i]["bufferView"]]
    return b[v.get("byteOffset", 0):v.get("byteOffset", 0) + v["byteLength"]]


def every_prim_has_uv(name, g, b):
    for mi, m in enumerate(g["meshes"]):
        for p in m["primitives"]:
            a = p["attributes"]
            if check("TEXCOORD_0" in a, "%s: mesh %s without TEXCOORD_0" % (name, m["name"])):
                ta, _ = T.accessor(g, b, a["TEXCOORD_0"])
                pa, _ = T.accessor(g, b, a["POSITION"])
                check(ta["count"] == pa["count"] and ta["type"] == "VEC2",
                      "%s: mesh %s TEXCOORD_0 count" % (name, m["name"]))


def triangles(g):
    """Triangles drawn: each node's mesh, over every node (the interiors have no hierarchy)."""
    per_mesh = [sum(g["accessors"][p["indices"]]["count"] // 3 for p in m["primitives"])
                for m in g["meshes"]]
    return sum(per_mesh[n["mesh"]] for n in g["nodes"] if "mesh" in n)


def explain(path):
    """The scene's features line printed by the program for the gltf node, or None."""
    exe = os.environ.get("LG_EXE")
    if not exe:
        return None
    graph = os.path.join(os.path.dirname(path), "g.lgraph")
    with open(graph, "w") as f:
        f.write('lightgraph 1\nscene = gltf { file = "%s" }\nview = preview { scene = scene }\n'
                'output view "v.png"\n' % os.path.basename(path))
    p = subprocess.run([exe, "render", graph, "--size", "32x24", "--explain"],
                       capture_output=True, text=True)
    check(p.returncode == 0, "%s: render failed: %s" % (path, p.stderr[-2000:]))
    m = re.search(r"scene features \(scene\): (.*)", p.stdout + p.stderr)
    return m.group(1) if m else None


def spot_node_dir(g, light):
    for n in g["nodes"]:
        if n.get("extensions", {}).get("KHR_lights_punctual", {}).get("light") == light:
            return n, T.quat_rotate(n["rotation"], (0, 0, -1))
    return None, None


def main():
    with tempfile.TemporaryDirectory() as tmp:
        # ---- spot lights on a cube
        p, _ = T.gen(tmp, "spot.glb", "cube", "--spot-light", "1,2,3,0,-2,1,40,10,30,1,0.5,0.5",
                     "--spot-light", "0,3,0,0,-1,0")
        g, b = T.read_glb(p)
        T.check_doc("spot", g, b)
        lights = g["extensions"]["KHR_lights_punctual"]["lights"]
        check([l["type"] for l in lights] == ["spot", "spot"], "spot types %s" % lights)
        s0, s1 = lights
        check(abs(s0["spot"]["innerConeAngle"] - math.radians(10)) < 1e-12 and
              abs(s0["spot"]["outerConeAngle"] - math.radians(30)) < 1e-12, "spot 0 cones")
        check(s0["intensity"] == 40 and s0["color"] == [1, 0.5, 0.5], "spot 0 intensity, colour")
        check(s1["spot"]["innerConeAngle"] == 0 and
              abs(s1["spot"]["outerConeAngle"] - math.pi / 4) < 1e-12 and s1["intensity"] == 10,
              "spot 1 defaults %s" % s1)
        n, d = spot_node_dir(g, 0)
        check(n is not None and n["translation"] == [1, 2, 3], "spot 0 position")
        check(d is not None and T.dot(d, T.unit((0, -2, 1))) > 1 - 1e-9, "spot 0 direction %s" % (d,))

        # ---- classroom
        p, out = T.gen(tmp, "classroom.glb", "classroom", "--slats", "10", "--slat-tilt", "45",
                       "--slat-thickness", "0.01")
        g, b = T.read_glb(p)
        T.check_doc("classroom", g, b)
        every_prim_has_uv("classroom", g, b)
        check(len(g.get("images", [])) == 2 and len(g.get("textures", [])) == 2, "two textures")
        for i, im in enumerate(g.get("images", [])):
            check(im.get("mimeType") == "image/png", "image %d mime type" % i)
            dec = png_decode(image_bytes(g, b, i))
            check(dec is not None and dec[0] == dec[1] == 64 and dec[2] == 3, "image %d size" % i)
        mats = {m["name"]: m for m in g["materials"]}
        for name in ("wood", "floor"):
            check("baseColorTexture" in mats[name]["pbrMetallicRoughness"], name + " textured")
        slats = [n for n in g["nodes"] if n.get("name", "").startswith("slat_")]
        check(len(slats) == 3 * 10, "%d slats, want 30" % len(slats))
        for n in slats:
            axis = T.quat_rotate(n["rotation"], (1, 0, 0))
            check(abs(math.degrees(math.atan2(axis[1], axis[0])) - 45) < 1e-9 and
                  abs(n["scale"][1] - 0.01) < 1e-12, "slat %s tilt or thickness" % n["name"])
            check(0.9 < n["translation"][1] < 2.6, "slat %s outside the window" % n["name"])
        # the window wall (x = 0): its triangles cover the piers, not the openings
        room = next(i for i, m in enumerate(g["meshes"]) if m["name"] == "room")
        wall_tris = []
        for pr in g["meshes"][room]["primitives"]:
            _, pos = T.accessor(g, b, pr["attributes"]["POSITION"])
            _, idx = T.accessor(g, b, pr["indices"])
            idx = [i[0] for i in idx]
            for k in range(0, len(idx), 3):
                t = [pos[idx[k + j]] for j in range(3)]
                if all(abs(v[0]) < 1e-9 for v in t):
                    wall_tris.append([(v[2], v[1]) for v in t])

        def covered(z, y):
            for t in wall_tris:
                (ax, ay), (bx, by), (cx, cy) = t
                d1 = (bx - ax) * (y - ay) - (by - ay) * (z - ax)
                d2 = (cx - bx) * (y - by) - (cy - by) * (z - bx)
                d3 = (ax - cx) * (y - cy) - (ay - cy) * (z - cx)
                if (d1 >= 0 and d2 >= 0 and d3 >= 0) or (d1 <= 0 and d2 <= 0 and d3 <= 0):
                    return True
            return False
        for zc in (2.5, 5.0, 7.5):
            check(not covered(zc, 1.75), "the window at z = %g is walled up" % zc)
        for z, y in ((1.0, 1.75), (3.75, 1.75), (6.25, 1.75), (9.0, 1.75), (5.0, 0.5), (5.0, 3.0)):
            check(covered(z, y), "the window wall has a hole at z = %g, y = %g" % (z, y))
        names = [n.get("name", "") for n in g["nodes"]]
        check(sum(1 for x in names if x.endswith("_top") and x.startswith("desk_")) == 12,
              "12 desks in rows")
        check(sum(1 for x in names if x.startswith("chair_") and x.endswith("_seat")) == 24,
              "24 chairs")
        lights = g["extensions"]["KHR_lights_punctual"]["lights"]
        check(sorted(l["type"] for l in lights) == ["directional", "spot"], "classroom lights")
        check(g["scenes"][0]["extras"]["medium"]["density"] > 0, "classroom medium")
        n_cls = triangles(g)
        f = explain(p)
        if f is not None:
            check(("triangles %d," % n_cls) in f, "classroom: the program counts %s, the file %d"
                  % (f, n_cls))
            check("1 directional, 0 point, 1 other" in f, "classroom lights: %s" % f)
        a = open(p, "rb").read()
        check(a == open(T.gen(tmp, "classroom2.glb", "classroom", "--slats", "10", "--slat-tilt",
                              "45", "--slat-thickness", "0.01")[0], "rb").read(),
              "classroom: two runs differ")

        # ---- courtyard, small
        counts = []
        for det in ("0.01", "0.02"):
            p, _ = T.gen(tmp, "court%s.glb" % det, "courtyard", "--detail", det)
            g, b = T.read_glb(p)
            T.check_doc("courtyard", g, b)
            every_prim_has_uv("courtyard", g, b)
            counts.append(triangles(g))
        leaf = next(m for m in g["materials"] if m["name"] == "leaves")
        check(leaf.get("alphaMode") == "MASK" and leaf.get("alphaCutoff") == 0.5 and
              leaf.get("doubleSided") is True, "leaf material %s" % leaf)
        tex = g["textures"][leaf["pbrMetallicRoughness"]["baseColorTexture"]["index"]]
        dec = png_decode(image_bytes(g, b, tex["source"]))
        if check(dec is not None and dec[2] == 4, "the leaf texture is RGBA"):
            alpha = [row[k] for row in dec[3] for k in range(3, len(row), 4)]
            check(set(alpha) == {0, 255}, "leaf alpha values %s" % sorted(set(alpha))[:8])
            cover = alpha.count(255) / len(alpha)
            check(0.1 < cover < 0.9, "leaves cover %.2f of the card" % cover)
        check(counts[1] > 1.5 * counts[0], "courtyard triangles %s do not grow with --detail"
              % counts)
        f = explain(p)
        if f is not None:
            check(("triangles %d," % counts[1]) in f, "courtyard: the program counts %s, the file "
                  "%d" % (f, counts[1]))
        a = open(p, "rb").read()
        check(a == open(T.gen(tmp, "court_again.glb", "courtyard", "--detail", "0.02")[0],
                        "rb").read(), "courtyard: two runs differ")

        # ---- bad arguments
        for args, word in ((["classroom", "--slats", "0"], "--slats"),
                           (["classroom", "--slat-tilt", "95"], "--slat-tilt"),
                           (["classroom", "--slat-thickness", "0"], "--slat-thickness"),
                           (["courtyard", "--detail", "0"], "--detail"),
                           (["courtyard", "--detail", "5"], "--detail"),
                           (["courtyard", "--slats", "5"], "--slats"),
                           (["classroom", "--detail", "1"], "--detail"),
                           (["cube", "--spot-light", "0,0,0,0,-1,0,1,30,30"], "inner"),
                           (["cube", "--spot-light", "0,0,0,0,-1,0,1,10,95"], "outer"),
                           (["cube", "--spot-light", "0,0,0,0,0,0"], "zero vector"),
                           (["cube", "--spot-light", "0,0,0,0,-1"], "--spot-light")):
            _, proc = T.gen(tmp, "bad.glb", *args, expect=2)
            check(word in proc.stderr, "%s: message lacks %s: %s" % (args, word, proc.stderr))
    return 1 if T.failures else 0


if __name__ == "__main__":
    sys.exit(main())
