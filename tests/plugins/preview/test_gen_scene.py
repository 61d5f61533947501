#!/usr/bin/env python3
"""tools/gen_scene.py's output, read back by an independent reader (this file).

For each kind and option, generates a scene into a scratch folder and checks:
  - the GLB container: 12-byte header (magic, version 2, total length = file size), a JSON
    chunk padded with spaces to 4 bytes, a BIN chunk padded with zeros to 4 bytes, nothing
    after it; the .gltf form: one buffer as a base64 data URI holding the same bytes;
  - the document: every accessor inside its buffer view, every view inside the buffer,
    offsets aligned to the component size, POSITION min/max present and equal to the data's
    bounds, indices below the vertex count and never the reserved maximum (65535 for u16),
    index type as asked, NORMAL present or absent as asked, unit-length normals;
  - the geometry: the triangle counts the docstring promises, closed meshes (sphere,
    torus, cube) wound counter-clockwise outwards (positive signed volume close to the
    analytic one) with vertex normals agreeing with the faces; instancing (grid) by nodes
    sharing one mesh, reaching the asked triangle count;
  - camera, lights and medium: the camera's -Z axis points at the target, directional
    lights' -Z along the given direction, scene extras as documented;
  - determinism (same arguments, same bytes) and bad arguments (exit 2, a message).
Exit 0 when every check passes, 1 otherwise.
"""
import base64
import json
import math
import os
import struct
import subprocess
import sys
import tempfile

ROOT = os.environ.get("LG_SOURCE_ROOT") or os.path.join(os.path.dirname(__file__), "..", "..", "..")
GEN = os.path.join(ROOT, "tools", "gen_scene.py")
failures = 0


def check(cond, msg):
    global failures
    if not cond:
        failures += 1
        print("check failed: " + msg, file=sys.stderr)
    return cond


def gen(tmp, name, *args, expect=0):
    out = os.path.join(tmp, name)
    p = subprocess.run([sys.executable, GEN] + list(args) + ["-o", out, "-q"],
                       capture_output=True, text=True)
    check(p.returncode == expect, "%s %s: exit %d, expected %d: %s"
          % (name, " ".join(args), p.returncode, expect, p.stderr))
    return out, p


def read_glb(path):
    data = open(path, "rb").read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    check(magic == 0x46546C67, "%s: magic %08x" % (path, magic))
    check(version == 2, "%s: version %d" % (path, version))
    check(length == len(data), "%s: header length %d, file %d" % (path, length, len(data)))
    jlen, jtype = struct.unpack_from("<II", data, 12)
    check(jtype == 0x4E4F534A, "%s: first chunk type %08x" % (path, jtype))
    check(jlen % 4 == 0, "%s: JSON chunk length %d not a multiple of 4" % (path, jlen))
    js = data[20:20 + jlen]
    text = js.decode("utf-8")
    stripped = text.rstrip(" ")
    check(len(text) - len(stripped) < 4, "%s: more than 3 padding spaces" % path)
    check(stripped.endswith("}"), "%s: JSON chunk padded with something else" % path)
    g = json.loads(stripped)
    off = 20 + jlen
    blen, btype = struct.unpack_from("<II", data, off)
    check(btype == 0x004E4942, "%s: second chunk type %08x" % (path, btype))
    check(blen % 4 == 0, "%s: BIN chunk length %d" % (path, blen))
    bin_ = data[off + 8:off + 8 + blen]
    check(off + 8 + blen == len(data), "%s: bytes after the BIN chunk" % path)
    bl = g["buffers"][0]["byteLength"]
    check(bl <= blen <= bl + 3, "%s: buffer byteLength %d, BIN chunk %d" % (path, bl, blen))
    check(all(b == 0 for b in bin_[bl:]), "%s: BIN padding is not zeros" % path)
    check("uri" not in g["buffers"][0], "%s: a GLB buffer with a uri" % path)
    return g, bin_


def read_gltf(path):
    g = json.load(open(path))
    uri = g["buffers"][0]["uri"]
    prefix = "data:application/octet-stream;base64,"
    check(uri.startswith(prefix), "%s: buffer uri is not a base64 data URI" % path)
    bin_ = base64.b64decode(uri[len(prefix):])
    check(len(bin_) == g["buffers"][0]["byteLength"], "%s: data URI length" % path)
    return g, bin_


COMP = {5126: ("f", 4), 5123: ("H", 2), 5125: ("I", 4)}
NCOMP = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def accessor(g, bin_, i):
    a = g["accessors"][i]
    v = g["bufferViews"][a["bufferView"]]
    fmt, size = COMP[a["componentType"]]
    n = NCOMP[a["type"]]
    vo, vl = v.get("byteOffset", 0), v["byteLength"]
    check(vo + vl <= len(bin_), "bufferView %d outside the buffer" % a["bufferView"])
    ao = a.get("byteOffset", 0)
    check((vo + ao) % size == 0, "accessor %d misaligned" % i)
    check(ao + a["count"] * n * size <= vl, "accessor %d outside its view" % i)
    vals = struct.unpack_from("<%d%s" % (a["count"] * n, fmt), bin_, vo + ao)
    return a, [vals[k:k + n] for k in range(0, len(vals), n)]


def check_doc(name, g, bin_, normals=True, index_type=None):
    """Checks every primitive; returns per mesh (positions, normals, triangles)."""
    check(g["asset"]["version"] == "2.0", name + ": asset.version")
    meshes = []
    for mi, m in enumerate(g["meshes"]):
        prims = []
        for pi, p in enumerate(m["primitives"]):
            where = "%s: mesh %d primitive %d" % (name, mi, pi)
            check(p.get("mode", 4) == 4, where + ": not triangles")
            pa, pos = accessor(g, bin_, p["attributes"]["POSITION"])
            check("min" in pa and "max" in pa, where + ": POSITION without min/max")
            if "min" in pa:
                for k in range(3):
                    lo = min(v[k] for v in pos)
                    hi = max(v[k] for v in pos)
                    check(pa["min"][k] == lo and pa["max"][k] == hi,
                          where + ": POSITION bounds %s %s, data %s %s"
                          % (pa["min"], pa["max"], lo, hi))
            nrm = None
            check(("NORMAL" in p["attributes"]) == normals, where + ": NORMAL presence")
            if "NORMAL" in p["attributes"]:
                na, nrm = accessor(g, bin_, p["attributes"]["NORMAL"])
                check(na["count"] == pa["count"], where + ": NORMAL count")
                bad = [v for v in nrm if abs(math.sqrt(sum(c * c for c in v)) - 1) > 1e-5]
                check(not bad, where + ": %d normals not unit length" % len(bad))
            ia, idx = accessor(g, bin_, p["indices"])
            idx = [i[0] for i in idx]
            if index_type:
                check(ia["componentType"] == {"u16": 5123, "u32": 5125}[index_type],
                      where + ": index type %d" % ia["componentType"])
            check(len(idx) % 3 == 0, where + ": index count not a multiple of 3")
            check(max(idx) < pa["count"], where + ": index past the vertices")
            limit = 65535 if ia["componentType"] == 5123 else 4294967295
            check(limit not in idx, where + ": the reserved index value")
            check(0 <= p["material"] < len(g["materials"]), where + ": material")
            prims.append((pos, nrm, [idx[k:k + 3] for k in range(0, len(idx), 3)]))
        meshes.append(prims)
    return meshes


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def closed_mesh(name, prim, volume, tol):
    """Outward counter-clockwise winding: positive volume near the analytic one; each
    triangle's face normal agrees with its vertex normals."""
    pos, nrm, tris = prim
    vol = sum(dot(pos[a], cross(pos[b], pos[c])) for a, b, c in tris) / 6
    check(abs(vol - volume) < tol * volume, "%s: signed volume %g, expected %g" % (name, vol, volume))
    if nrm:
        bad = 0
        for a, b, c in tris:
            f = cross(sub(pos[b], pos[a]), sub(pos[c], pos[a]))
            if dot(f, f) < 1e-20:
                bad += 1  # degenerate
                continue
            if min(dot(f, nrm[k]) for k in (a, b, c)) <= 0:
                bad += 1
        check(bad == 0, "%s: %d triangles disagree with their vertex normals" % (name, bad))


def quat_rotate(q, v):
    x, y, z, w = q
    u = (x, y, z)
    t = cross(u, v)
    t = (2 * t[0], 2 * t[1], 2 * t[2])
    c = cross(u, t)
    return (v[0] + w * t[0] + c[0], v[1] + w * t[1] + c[1], v[2] + w * t[2] + c[2])


def unit(v):
    n = math.sqrt(dot(v, v))
    return (v[0] / n, v[1] / n, v[2] / n)


def main():
    with tempfile.TemporaryDirectory() as tmp:
        # sphere: 2 S (R - 1) triangles, (R + 1)(S + 1) vertices, closed, outward
        p, _ = gen(tmp, "s.glb", "sphere", "--rings", "12", "--segments", "20")
        g, b = read_glb(p)
        m = check_doc("sphere", g, b, index_type="u16")
        check(len(m[0][0][2]) == 2 * 20 * 11, "sphere triangles %d" % len(m[0][0][2]))
        check(len(m[0][0][0]) == 13 * 21, "sphere vertices %d" % len(m[0][0][0]))
        closed_mesh("sphere", m[0][0], 4 / 3 * math.pi, 0.06)

        p, _ = gen(tmp, "s8.glb", "sphere", "--level", "8")
        g, b = read_glb(p)
        m = check_doc("sphere level 8", g, b)
        check(len(m[0][0][2]) == 2 * 16 * 7, "sphere level 8: %d triangles" % len(m[0][0][2]))

        # torus: 2 R S triangles, volume 2 pi^2 R r^2
        p, _ = gen(tmp, "t.glb", "torus", "--rings", "40", "--segments", "16", "--tube", "0.3")
        g, b = read_glb(p)
        m = check_doc("torus", g, b)
        check(len(m[0][0][2]) == 2 * 40 * 16, "torus triangles %d" % len(m[0][0][2]))
        closed_mesh("torus", m[0][0], 2 * math.pi ** 2 * 0.09, 0.05)

        # cube: 24 vertices with normals; 8 shared without
        p, _ = gen(tmp, "c.glb", "cube")
        g, b = read_glb(p)
        m = check_doc("cube", g, b)
        check(len(m[0][0][0]) == 24 and len(m[0][0][2]) == 12, "cube counts")
        closed_mesh("cube", m[0][0], 1.0, 1e-6)
        p, _ = gen(tmp, "c8.gltf", "cube", "--shared-vertices")
        g, b = read_gltf(p)
        m = check_doc("cube shared", g, b, normals=False)
        check(len(m[0][0][0]) == 8 and len(m[0][0][2]) == 12, "shared cube counts")
        closed_mesh("cube shared", m[0][0], 1.0, 1e-6)

        # plane: 2 S^2 triangles facing +Y
        p, _ = gen(tmp, "p.glb", "plane", "--segments", "3", "--size", "4")
        g, b = read_glb(p)
        m = check_doc("plane", g, b)
        pos, nrm, tris = m[0][0]
        check(len(tris) == 18, "plane triangles %d" % len(tris))
        check(all(cross(sub(pos[t[1]], pos[t[0]]), sub(pos[t[2]], pos[t[0]]))[1] > 0 for t in tris),
              "plane: a triangle not facing +Y")

        # options: no normals, u32 indices, .gltf form; the same buffer as the .glb
        p1, _ = gen(tmp, "n.glb", "sphere", "--level", "6", "--no-normals", "--index-type", "u32")
        p2, _ = gen(tmp, "n.gltf", "sphere", "--level", "6", "--no-normals", "--index-type", "u32")
        g1, b1 = read_glb(p1)
        g2, b2 = read_gltf(p2)
        check_doc("no normals u32", g1, b1, normals=False, index_type="u32")
        check(b1[:g1["buffers"][0]["byteLength"]] == b2, ".glb and .gltf buffers differ")
        del g1["buffers"], g2["buffers"]
        check(g1 == g2, ".glb and .gltf documents differ")
        gen(tmp, "x.glb", "sphere", "--rings", "200", "--segments", "400", "--index-type", "u16",
            expect=2)

        # box_room: five walls, a panel, one box mesh used by two nodes; Cornell colours
        p, _ = gen(tmp, "r.glb", "box_room")
        g, b = read_glb(p)
        m = check_doc("box_room", g, b)
        check(sum(len(pr[2]) for mesh in m for pr in mesh) == 10 + 2 + 12, "box_room triangles")
        users = [n["mesh"] for n in g["nodes"] if "mesh" in n]
        check(len(users) == 4 and len(set(users)) == 3, "box_room: the box is not instanced")
        names = [mat["name"] for mat in g["materials"]]
        check({"white", "red", "green", "light"} <= set(names), "box_room materials %s" % names)
        check(g["extensions"]["KHR_lights_punctual"]["lights"][0]["type"] == "point",
              "box_room default light")

        # grid: instanced spheres reaching the asked count within 1%
        for target in (5000, 600000, 5000000):
            p, _ = gen(tmp, "g.glb", "grid", "--triangles", str(target))
            g, b = read_glb(p)
            m = check_doc("grid", g, b)
            tris = len(m[0][0][2])
            inst = [n for n in g["nodes"] if n.get("mesh") == 0]
            check(len(g["meshes"]) == 1, "grid: more than one mesh")
            total = tris * len(inst)
            check(abs(total - target) <= 0.01 * target,
                  "grid %d: %d instances x %d = %d triangles" % (target, len(inst), tris, total))
            check(len({tuple(n["translation"]) for n in inst}) == len(inst),
                  "grid: two instances at one place")

        # grid with a given tessellation: instances = T / its triangles
        p, _ = gen(tmp, "gt.glb", "grid", "--triangles", "10000", "--level", "10")
        g, b = read_glb(p)
        m = check_doc("grid level 10", g, b)
        inst = [n for n in g["nodes"] if n.get("mesh") == 0]
        check(len(m[0][0][2]) == 2 * 20 * 9 and len(inst) == round(10000 / 360),
              "grid level 10: %d instances x %d" % (len(inst), len(m[0][0][2])))

        # camera looks at the target; lights along their directions; medium in extras
        p, _ = gen(tmp, "l.glb", "torus", "--camera-pos", "3,2,4", "--camera-target", "0,0.5,0",
                   "--dir-light", "0,-1,0", "--dir-light", "1,-1,-1,7,1,0.5,0.25",
                   "--point-light", "0,3,0,25", "--medium", "0.2,0.4,0.1,0.3",
                   "--material-extras", '{"ks": 0.5}', "--color", "0.1,0.2,0.3",
                   "--roughness", "0.25", "--metallic", "1", "--double-sided")
        g, b = read_glb(p)
        check_doc("lights", g, b)
        cam = [n for n in g["nodes"] if "camera" in n]
        check(len(cam) == 1 and g["cameras"][0]["type"] == "perspective", "one camera")
        fwd = quat_rotate(cam[0]["rotation"], (0, 0, -1))
        want = unit(sub((0, 0.5, 0), cam[0]["translation"]))
        check(dot(fwd, want) > 1 - 1e-9, "camera looks along %s, target is along %s" % (fwd, want))
        up = quat_rotate(cam[0]["rotation"], (0, 1, 0))
        check(up[1] > 0 and abs(dot(up, fwd)) < 1e-9, "camera up %s" % (up,))
        lights = g["extensions"]["KHR_lights_punctual"]["lights"]
        check("KHR_lights_punctual" in g.get("extensionsUsed", []), "extensionsUsed")
        check([l["type"] for l in lights] == ["directional", "directional", "point"], "light types")
        check(lights[1]["intensity"] == 7 and lights[1]["color"] == [1, 0.5, 0.25], "light 1")
        check(lights[2]["intensity"] == 25, "point intensity")
        for n in g["nodes"]:
            ext = n.get("extensions", {}).get("KHR_lights_punctual")
            if not ext:
                continue
            l = ext["light"]
            if lights[l]["type"] == "directional":
                d = quat_rotate(n["rotation"], (0, 0, -1))
                want = unit((0, -1, 0)) if l == 0 else unit((1, -1, -1))
                check(dot(d, want) > 1 - 1e-9, "light %d points along %s" % (l, d))
            else:
                check(n["translation"] == [0, 3, 0], "point light position")
        med = g["scenes"][0]["extras"]["medium"]
        check(med == {"density": 0.2, "scattering": [0.4] * 3, "absorption": [0.1] * 3, "g": 0.3},
              "medium %s" % med)
        mat = g["materials"][0]
        check(mat["pbrMetallicRoughness"] == {"baseColorFactor": [0.1, 0.2, 0.3, 1.0],
                                              "metallicFactor": 1.0, "roughnessFactor": 0.25},
              "material %s" % mat)
        check(mat.get("doubleSided") is True and mat.get("extras") == {"ks": 0.5}, "material flags")

        p, _ = gen(tmp, "bare.glb", "cube", "--no-camera", "--no-lights")
        g, b = read_glb(p)
        check("cameras" not in g and "extensions" not in g, "--no-camera --no-lights")

        # determinism
        a = open(gen(tmp, "d1.glb", "box_room", "--medium", "1")[0], "rb").read()
        b = open(gen(tmp, "d2.glb", "box_room", "--medium", "1")[0], "rb").read()
        check(a == b, "two runs differ")

        # bad arguments: exit 2 with a message naming the option
        for args, word in ((["cube", "--color", "1,2,3"], "--color"),
                           (["sphere", "--rings", "1"], "--rings"),
                           (["torus", "--tube", "1.5"], "--tube"),
                           (["sphere", "--shared-vertices"], "--shared-vertices"),
                           (["grid", "--triangles", "0"], "--triangles"),
                           (["cube", "--dir-light", "0,0"], "--dir-light"),
                           (["cube", "--medium", "1,0.5,0.1,1"], "--medium"),
                           (["cube", "--camera-pos", "0,0,nan"], "--camera-pos"),
                           (["cube", "--material-extras", "[1]"], "--material-extras"),
                           (["cube", "--rings", "8"], "--rings"),
                           (["sphere", "--tube", "0.2"], "--tube"),
                           (["sphere", "--level", "3000"], "grid"),
                           (["torus", "--triangles", "10"], "--triangles")):
            _, proc = gen(tmp, "bad.glb", *args, expect=2)
            check(word in proc.stderr, "%s: message lacks %s: %s" % (args, word, proc.stderr))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
