#!/usr/bin/env python3
"""gen_scene.py: procedural glTF 2.0 scenes for tests and for the scaling experiment.

Writes one scene as a binary .glb (default) or, when the output name ends in .gltf or with
--format gltf, as a .gltf whose buffer is an embedded base64 data URI. Python 3 standard
library only; the same arguments give the same bytes.

usage: gen_scene.py KIND [options] -o OUT

KIND
  sphere     UV sphere of radius 1; --rings R (latitude bands, >= 2) and --segments S
             (longitude, >= 3), or --level L (R = L, S = 2 L). 2 S (R - 1) triangles,
             (R + 1)(S + 1) vertices (a seam and duplicated poles, for texture coordinates).
  torus      torus in the XZ plane, major radius 1, tube radius --tube (0.35); --rings R
             around the ring (>= 3), --segments S around the tube (>= 3), or --level L
             (R = 2 L, S = L). 2 R S triangles.
  cube       unit cube (edge 1, centred): 24 vertices with face normals, 12 triangles; with
             --shared-vertices, 8 shared vertices and no normals (a loader must compute them).
  plane      square of edge --size (2) in the XZ plane facing +Y, --segments S subdivisions
             per side (at most 1023): 2 S^2 triangles.
  box_room   a closed room with an open front, like a Cornell box: floor, ceiling, back
             wall (white), left wall (red), right wall (green), an emissive panel under the
             ceiling, and a short and a tall box (one box mesh instanced twice). The room
             spans x, z in [-1, 1], y in [0, 2]; the open side faces +Z.
  grid       instanced spheres (one mesh, many nodes) on a square grid in the XZ plane,
             reaching about --triangles T (default 600000): the instance count is
             --instances N, else ceil(T / 5000), and the sphere's tessellation is chosen so
             that N x its triangles is as close to T as possible. With --rings/--segments
             or --level the sphere is as given and N (unless given) is T / its triangles,
             rounded. The real count is printed.

Options that shape one kind (--rings, --segments, --level, --tube, --size, --triangles,
--instances) are an error for the others. One mesh holds at most 1,048,576 vertices
(pure Python): larger counts come from `grid`, which instances one mesh.

Geometry options
  --no-normals           omit NORMAL (the loader computes them)
  --no-texcoords         omit TEXCOORD_0
  --index-type auto|u16|u32
                         index component type; auto (default) takes u16 when every index fits
                         (at most 65535 vertices: 65535 itself is reserved by the spec), else u32
  --shared-vertices      cube: 8 shared vertices, implies --no-normals
  --tube F               torus tube radius (0 < F < 1)
  --size F               plane edge length

Material (every KIND but box_room, whose colours are the Cornell box's)
  --color R,G,B[,A]      baseColorFactor, linear (default 0.8,0.8,0.8,1)
  --roughness F          roughnessFactor (default 0.5)
  --metallic F           metallicFactor (default 0)
  --material-extras JSON material "extras" object, e.g. '{"ks": 0.5, "shininess": 64}'
  --double-sided         material doubleSided = true (default false; box_room walls are
                         always double-sided: they are seen from both sides)

Camera and lights
  --no-camera            no camera node (the loader frames the scene from its bounds)
  --camera-pos X,Y,Z     camera position (default: framing the scene's bounds from the
                         front, slightly above and to the right; box_room: straight on)
  --camera-target X,Y,Z  point looked at (default: the bounds' centre)
  --yfov DEG             vertical field of view in degrees (default 40)
  --dir-light DX,DY,DZ[,INTENSITY[,R,G,B]]
                         a KHR_lights_punctual directional light travelling along DX,DY,DZ
                         (intensity in lux, default 3); repeatable
  --point-light X,Y,Z[,INTENSITY[,R,G,B]]
                         a point light (intensity in candela, default 10); repeatable
  --no-lights            no light at all. Without any light option a scene gets one
                         directional light (box_room: one point light under the panel)

Medium (scene extras)
  --medium DENSITY[,SCATTERING[,ABSORPTION[,G]]]
                         writes scenes[0].extras.medium = {"density": D,
                         "scattering": [s, s, s], "absorption": [a, a, a], "g": g}
                         (defaults: scattering 0.5, absorption 0.05, g 0; units 1/m per
                         unit density, g in (-1, 1))

Animation (sphere, torus, cube, plane: one animation "move" keying the object's node)
  --anim-translation T:X,Y,Z[;T:X,Y,Z...]
                         translation keys: time T (seconds) and position
  --anim-rotation T:AX,AY,AZ,DEG[;...]
                         rotation keys: time and an axis-angle (degrees), as quaternions
  --rotate AX,AY,AZ,DEG  the object node's own (rest) rotation, an axis-angle in degrees
  --anim-interp linear|step|cubicspline
                         the samplers' interpolation (default linear); cubicspline writes
                         zero in- and out-tangents

Output
  -o, --output PATH      the file to write (.glb or .gltf)
  --format glb|gltf      override the format the extension implies
  -q, --quiet            do not print the summary line

The summary line (stdout) reads, for example:
  grid.glb: 120 instances x 5,000 = 600,000 triangles, 2,727 vertices in 1 mesh, 126,500 bytes

Examples (the thesis's scaling experiment, about 5k, 600k and 5M triangles):
  tools/gen_scene.py grid --triangles 5000 -o out/grid_5k.glb
  tools/gen_scene.py grid --triangles 600000 -o out/grid_600k.glb
  tools/gen_scene.py grid --triangles 5000000 -o out/grid_5m.glb
  tools/gen_scene.py sphere --level 16 --no-normals --index-type u32 -o sphere.gltf
  tools/gen_scene.py box_room --medium 0.1,0.5,0.05,0.4 -o room.glb

Exit status: 0, or 2 with a message on stderr for bad arguments (a u16 index type for a
mesh with too many vertices, a non-finite number, an unknown kind, ...).
"""
import argparse
import base64
import json
import math
import struct
import sys

GLB_MAGIC = 0x46546C67  # "glTF"
CHUNK_JSON = 0x4E4F534A  # "JSON"
CHUNK_BIN = 0x004E4942  # "BIN\0"

FLOAT = 5126
U16 = 5123
U32 = 5125
ARRAY_BUFFER = 34962
ELEMENT_ARRAY_BUFFER = 34963


class UsageError(Exception):
    pass


# ---- small vector helpers --------------------------------------------------------------

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def normalize(a):
    n = math.sqrt(dot(a, a))
    if not n > 0:
        raise UsageError("a zero-length direction")
    return (a[0] / n, a[1] / n, a[2] / n)


def quat_from_basis(x, y, z):
    """Unit quaternion [x, y, z, w] of the rotation whose matrix has columns x, y, z."""
    m00, m10, m20 = x
    m01, m11, m21 = y
    m02, m12, m22 = z
    tr = m00 + m11 + m22
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = ((m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s, 0.25 * s)
    elif m00 > m11 and m00 > m22:
        s = math.sqrt(1.0 + m00 - m11 - m22) * 2
        q = (0.25 * s, (m01 + m10) / s, (m02 + m20) / s, (m21 - m12) / s)
    elif m11 > m22:
        s = math.sqrt(1.0 + m11 - m00 - m22) * 2
        q = ((m01 + m10) / s, 0.25 * s, (m12 + m21) / s, (m02 - m20) / s)
    else:
        s = math.sqrt(1.0 + m22 - m00 - m11) * 2
        q = ((m02 + m20) / s, (m12 + m21) / s, 0.25 * s, (m10 - m01) / s)
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


def quat_looking_along(forward, up=(0.0, 1.0, 0.0)):
    """Rotation taking the local -Z axis to `forward` (and +Y towards `up`): how glTF
    orients cameras and directional lights."""
    f = normalize(forward)
    if abs(dot(f, normalize(up))) > 0.999:
        up = (1.0, 0.0, 0.0) if abs(f[0]) < 0.9 else (0.0, 0.0, 1.0)
    s = normalize(cross(f, up))
    u = cross(s, f)
    return quat_from_basis(s, u, (-f[0], -f[1], -f[2]))


def quat_axis_angle(axis, angle):
    a = normalize(axis)
    s = math.sin(angle / 2)
    return [a[0] * s, a[1] * s, a[2] * s, math.cos(angle / 2)]


def quat_rotate(q, v):
    x, y, z, w = q
    u = (x, y, z)
    t = cross(u, v)
    t = (2 * t[0], 2 * t[1], 2 * t[2])
    c = cross(u, t)
    return (v[0] + w * t[0] + c[0], v[1] + w * t[1] + c[1], v[2] + w * t[2] + c[2])


# ---- meshes: lists of (positions, normals, texcoords, indices) ---------------------------

class Prim:
    """One triangle list: flat float lists (3 per vertex, 2 per texcoord), int indices."""

    def __init__(self, positions, normals, texcoords, indices, material):
        self.positions = positions
        self.normals = normals
        self.texcoords = texcoords
        self.indices = indices
        self.material = material

    @property
    def n_vertices(self):
        return len(self.positions) // 3


def make_sphere(rings, segments, material, radius=1.0):
    pos, nrm, uv, idx = [], [], [], []
    for i in range(rings + 1):
        theta = math.pi * i / rings
        # exact poles, so that the pole vertices coincide
        st = 0.0 if i in (0, rings) else math.sin(theta)
        ct = 1.0 if i == 0 else -1.0 if i == rings else math.cos(theta)
        for j in range(segments + 1):
            phi = 2 * math.pi * j / segments
            n = (st * math.sin(phi), ct, st * math.cos(phi))
            if j == segments:  # the seam: exactly the first column's position
                n = (0.0 * st, ct, st)
            pos += [radius * n[0], radius * n[1], radius * n[2]]
            nrm += list(n)
            uv += [j / segments, i / rings]
    w = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = i * w + j, (i + 1) * w + j, (i + 1) * w + j + 1, i * w + j + 1
            # counter-clockwise seen from outside; the pole rows have one triangle per quad
            if i != 0:
                idx += [a, b, d]
            if i != rings - 1:
                idx += [b, c, d]
    return Prim(pos, nrm, uv, idx, material)


def make_torus(rings, segments, tube, material, radius=1.0):
    pos, nrm, uv, idx = [], [], [], []
    for i in range(rings + 1):
        u = 2 * math.pi * (i % rings) / rings
        cu, su = math.cos(u), math.sin(u)
        for j in range(segments + 1):
            v = 2 * math.pi * (j % segments) / segments
            cv, sv = math.cos(v), math.sin(v)
            n = (cv * cu, sv, -cv * su)
            pos += [(radius + tube * cv) * cu, tube * sv, -(radius + tube * cv) * su]
            nrm += list(n)
            uv += [i / rings, j / segments]
    w = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = i * w + j, (i + 1) * w + j, (i + 1) * w + j + 1, i * w + j + 1
            idx += [a, b, c, a, c, d]
    return Prim(pos, nrm, uv, idx, material)


# The six faces of a unit cube: (normal, u axis, v axis), with u x v = normal so that the
# corners c - u - v, c + u - v, c + u + v, c - u + v run counter-clockwise seen from outside.
CUBE_FACES = [
    ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
]


def make_cube(material, shared=False):
    if shared:
        pos = []
        for k in range(8):
            pos += [0.5 if k & 1 else -0.5, 0.5 if k & 2 else -0.5, 0.5 if k & 4 else -0.5]
    pos2, nrm, uv, idx = [], [], [], []
    for f, (n, u, v) in enumerate(CUBE_FACES):
        corners = []
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = tuple(0.5 * n[k] + 0.5 * su * u[k] + 0.5 * sv * v[k] for k in range(3))
            corners.append(p)
            pos2 += list(p)
            nrm += [float(c) for c in n]
            uv += [(su + 1) / 2, (1 - sv) / 2]
        if shared:
            ids = [(1 if p[0] > 0 else 0) | (2 if p[1] > 0 else 0) | (4 if p[2] > 0 else 0)
                   for p in corners]
        else:
            ids = [4 * f + k for k in range(4)]
        idx += [ids[0], ids[1], ids[2], ids[0], ids[2], ids[3]]
    if shared:
        return Prim(pos, None, None, idx, material)
    return Prim(pos2, nrm, uv, idx, material)


def make_quad(center, u, v, material):
    """A rectangle c +- u +- v facing u x v (counter-clockwise seen from that side)."""
    n = normalize(cross(u, v))
    pos, nrm, uv = [], [], []
    for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        pos += [center[k] + su * u[k] + sv * v[k] for k in range(3)]
        nrm += list(n)
        uv += [(su + 1) / 2, (1 - sv) / 2]
    return Prim(pos, nrm, uv, [0, 1, 2, 0, 2, 3], material)


def make_plane(size, segments, material):
    pos, nrm, uv, idx = [], [], [], []
    h = size / 2
    for i in range(segments + 1):
        for j in range(segments + 1):
            x = -h + size * j / segments
            z = -h + size * i / segments
            pos += [x, 0.0, z]
            nrm += [0.0, 1.0, 0.0]
            uv += [j / segments, i / segments]
    w = segments + 1
    for i in range(segments):
        for j in range(segments):
            a, b, c, d = i * w + j, (i + 1) * w + j, (i + 1) * w + j + 1, i * w + j + 1
            idx += [a, b, c, a, c, d]  # seen from +Y: a (x-, z-), b (x-, z+), c (x+, z+)
    return Prim(pos, nrm, uv, idx, material)


def sphere_tris(rings, segments):
    return 2 * segments * (rings - 1)


def grid_tessellation(target):
    """(rings, segments) with 2 S (R - 1) closest to `target`, S near 2 R."""
    best = None
    for rings in range(2, 2049):
        for segments in {max(3, round(target / (2 * (rings - 1)))),
                         max(3, math.floor(target / (2 * (rings - 1))))}:
            if not rings <= segments <= 4 * rings:
                continue
            err = abs(sphere_tris(rings, segments) - target)
            key = (err, abs(segments - 2 * rings), rings)
            if best is None or key < best[0]:
                best = (key, rings, segments)
    if best is None:
        return 2, 3
    return best[1], best[2]


# ---- the document --------------------------------------------------------------------------

class Doc:
    def __init__(self):
        self.bin = bytearray()
        self.g = {
            "asset": {"version": "2.0", "generator": "lightgraph tools/gen_scene.py"},
            "scene": 0,
            "scenes": [{"name": "scene", "nodes": []}],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }

    def view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        off = len(self.bin)
        self.bin += data
        bv = {"buffer": 0, "byteOffset": off, "byteLength": len(data), "target": target}
        if target is None:  # animation data: no target (glTF leaves it out)
            del bv["target"]
        self.g["bufferViews"].append(bv)
        return len(self.g["bufferViews"]) - 1

    def accessor(self, values, comp, typ, target, minmax=False):
        ncomp = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[typ]
        fmt = {FLOAT: "f", U16: "H", U32: "I"}[comp]
        data = struct.pack("<%d%s" % (len(values), fmt), *values)
        acc = {"bufferView": self.view(data, target), "componentType": comp,
               "count": len(values) // ncomp, "type": typ}
        if minmax:
            # the bounds of the values as stored (float32), as the spec asks of POSITION
            stored = struct.unpack("<%d%s" % (len(values), fmt), data)
            acc["min"] = [min(stored[k::ncomp]) for k in range(ncomp)]
            acc["max"] = [max(stored[k::ncomp]) for k in range(ncomp)]
        self.g["accessors"].append(acc)
        return len(self.g["accessors"]) - 1

    def material(self, name, color, roughness, metallic, double_sided=False, emissive=None,
                 extras=None):
        m = {"name": name,
             "pbrMetallicRoughness": {"baseColorFactor": list(color),
                                      "metallicFactor": metallic,
                                      "roughnessFactor": roughness}}
        if emissive:
            m["emissiveFactor"] = list(emissive)
        if double_sided:
            m["doubleSided"] = True
        if extras:
            m["extras"] = extras
        self.g["materials"].append(m)
        return len(self.g["materials"]) - 1

    def mesh(self, name, prims, opts):
        out = []
        for p in prims:
            attrs = {"POSITION": self.accessor(p.positions, FLOAT, "VEC3", ARRAY_BUFFER, True)}
            if p.normals is not None and not opts.no_normals:
                attrs["NORMAL"] = self.accessor(p.normals, FLOAT, "VEC3", ARRAY_BUFFER)
            if p.texcoords is not None and not opts.no_texcoords:
                attrs["TEXCOORD_0"] = self.accessor(p.texcoords, FLOAT, "VEC2", ARRAY_BUFFER)
            itype = opts.index_type
            if itype == "auto":
                itype = "u16" if p.n_vertices <= 65535 else "u32"
            if itype == "u16" and p.n_vertices > 65535:
                raise UsageError("mesh '%s' has %d vertices: u16 indices reach 65534 "
                                 "(65535 is reserved); use --index-type u32 or auto"
                                 % (name, p.n_vertices))
            comp = U16 if itype == "u16" else U32
            prim = {"attributes": attrs,
                    "indices": self.accessor(p.indices, comp, "SCALAR", ELEMENT_ARRAY_BUFFER),
                    "material": p.material, "mode": 4}
            out.append(prim)
        self.g["meshes"].append({"name": name, "primitives": out})
        return len(self.g["meshes"]) - 1

    def node(self, node, root=True):
        self.g["nodes"].append(node)
        i = len(self.g["nodes"]) - 1
        if root:
            self.g["scenes"][0]["nodes"].append(i)
        return i

    def use_extension(self, name):
        used = self.g.setdefault("extensionsUsed", [])
        if name not in used:
            used.append(name)

    def encode(self, fmt):
        while len(self.bin) % 4:
            self.bin.append(0)
        g = dict(self.g)
        if fmt == "gltf":
            uri = "data:application/octet-stream;base64," + base64.b64encode(self.bin).decode()
            g["buffers"] = [{"byteLength": len(self.bin), "uri": uri}]
            return (json.dumps(g, indent=1) + "\n").encode()
        g["buffers"] = [{"byteLength": len(self.bin)}]
        js = json.dumps(g, separators=(",", ":")).encode()
        js += b" " * (-len(js) % 4)
        total = 12 + 8 + len(js) + 8 + len(self.bin)
        return (struct.pack("<III", GLB_MAGIC, 2, total) +
                struct.pack("<II", len(js), CHUNK_JSON) + js +
                struct.pack("<II", len(self.bin), CHUNK_BIN) + bytes(self.bin))


# ---- argument parsing ----------------------------------------------------------------------

def floats(text, what, counts):
    try:
        v = [float(x) for x in text.split(",")]
    except ValueError:
        raise UsageError("%s: '%s' is not a comma-separated list of numbers" % (what, text))
    if len(v) not in counts:
        raise UsageError("%s: '%s' has %d values, expected %s"
                         % (what, text, len(v), " or ".join(str(c) for c in counts)))
    if not all(math.isfinite(x) for x in v):
        raise UsageError("%s: '%s' has a value that is not finite" % (what, text))
    return v


def parse_args(argv):
    ap = argparse.ArgumentParser(
        prog="gen_scene.py", usage="gen_scene.py KIND [options] -o OUT",
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("kind", choices=["sphere", "torus", "cube", "plane", "box_room", "grid"])
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--format", choices=["glb", "gltf"])
    ap.add_argument("-q", "--quiet", action="store_true")
    ap.add_argument("--rings", type=int)
    ap.add_argument("--segments", type=int)
    ap.add_argument("--level", type=int)
    ap.add_argument("--tube", type=float)
    ap.add_argument("--size", type=float)
    ap.add_argument("--triangles", type=int)
    ap.add_argument("--instances", type=int)
    ap.add_argument("--no-normals", action="store_true")
    ap.add_argument("--no-texcoords", action="store_true")
    ap.add_argument("--index-type", choices=["auto", "u16", "u32"], default="auto")
    ap.add_argument("--shared-vertices", action="store_true")
    ap.add_argument("--color", default="0.8,0.8,0.8,1")
    ap.add_argument("--roughness", type=float, default=0.5)
    ap.add_argument("--metallic", type=float, default=0.0)
    ap.add_argument("--material-extras")
    ap.add_argument("--double-sided", action="store_true")
    ap.add_argument("--no-camera", action="store_true")
    ap.add_argument("--camera-pos")
    ap.add_argument("--camera-target")
    ap.add_argument("--yfov", type=float, default=40.0)
    ap.add_argument("--dir-light", action="append", default=[])
    ap.add_argument("--point-light", action="append", default=[])
    ap.add_argument("--no-lights", action="store_true")
    ap.add_argument("--medium")
    ap.add_argument("--anim-translation")
    ap.add_argument("--anim-rotation")
    ap.add_argument("--rotate")
    ap.add_argument("--anim-interp", choices=["linear", "step", "cubicspline"],
                    default="linear")
    o = ap.parse_args(argv)

    # options that shape one kind only are refused elsewhere, not silently ignored
    applies = {"rings": ("sphere", "torus", "grid"), "segments": ("sphere", "torus", "plane", "grid"),
               "level": ("sphere", "torus", "grid"), "tube": ("torus",), "size": ("plane",),
               "triangles": ("grid",), "instances": ("grid",)}
    for name, kinds in applies.items():
        if getattr(o, name) is not None and o.kind not in kinds:
            raise UsageError("--%s does not apply to %s (only to %s)"
                             % (name, o.kind, ", ".join(kinds)))
    o.tube = 0.35 if o.tube is None else o.tube
    o.size = 2.0 if o.size is None else o.size
    o.triangles = 600000 if o.triangles is None else o.triangles

    for name in ("tube", "size", "roughness", "metallic", "yfov"):
        if not math.isfinite(getattr(o, name)):
            raise UsageError("--%s: not a finite number" % name)
    if not 0 < o.tube < 1:
        raise UsageError("--tube %g: the tube radius must be in (0, 1)" % o.tube)
    if not o.size > 0:
        raise UsageError("--size %g: must be > 0" % o.size)
    if not 0 <= o.roughness <= 1 or not 0 <= o.metallic <= 1:
        raise UsageError("--roughness and --metallic must be in [0, 1]")
    if not 0 < o.yfov < 180:
        raise UsageError("--yfov %g: must be in (0, 180) degrees" % o.yfov)
    if o.level is not None and (o.rings is not None or o.segments is not None):
        raise UsageError("--level sets --rings and --segments: give one or the other")
    if o.level is not None and not 2 <= o.level <= 4096:
        raise UsageError("--level %d: must be in [2, 4096]" % o.level)
    if o.rings is not None and not 2 <= o.rings <= 65536:
        raise UsageError("--rings %d: must be in [2, 65536]" % o.rings)
    if o.segments is not None and not 1 <= o.segments <= 65536:
        raise UsageError("--segments %d: must be in [1, 65536]" % o.segments)
    if not 1 <= o.triangles <= 2_000_000_000:
        raise UsageError("--triangles %d: must be in [1, 2e9]" % o.triangles)
    if o.instances is not None and not 1 <= o.instances <= 1_000_000:
        raise UsageError("--instances %d: must be in [1, 1e6]" % o.instances)
    o.color = floats(o.color, "--color", (3, 4))
    if len(o.color) == 3:
        o.color.append(1.0)
    if not all(0 <= c <= 1 for c in o.color):
        raise UsageError("--color: components must be in [0, 1]")
    if o.material_extras is not None:
        try:
            o.material_extras = json.loads(o.material_extras)
        except ValueError as e:
            raise UsageError("--material-extras: not JSON (%s)" % e)
        if not isinstance(o.material_extras, dict):
            raise UsageError("--material-extras: must be a JSON object")
    if o.shared_vertices:
        if o.kind != "cube":
            raise UsageError("--shared-vertices applies to the cube only")
        o.no_normals = True
    o.camera_pos = floats(o.camera_pos, "--camera-pos", (3,)) if o.camera_pos else None
    o.camera_target = floats(o.camera_target, "--camera-target", (3,)) if o.camera_target else None
    o.dir_lights = [floats(t, "--dir-light", (3, 4, 7)) for t in o.dir_light]
    o.point_lights = [floats(t, "--point-light", (3, 4, 7)) for t in o.point_light]
    if o.no_lights and (o.dir_lights or o.point_lights):
        raise UsageError("--no-lights contradicts --dir-light/--point-light")
    if o.medium is not None:
        m = floats(o.medium, "--medium", (1, 2, 3, 4))
        m += [0.5, 0.05, 0.0][len(m) - 1:]
        if m[0] < 0 or m[1] < 0 or m[2] < 0 or not -1 < m[3] < 1:
            raise UsageError("--medium: density, scattering and absorption must be >= 0 and "
                             "g in (-1, 1)")
        o.medium = m
    if o.format is None:
        o.format = "gltf" if o.output.lower().endswith(".gltf") else "glb"
    return o


# ---- scenes --------------------------------------------------------------------------------

MAX_VERTICES = 1 << 20  # per mesh: 2 s and 600 MB of Python lists; beyond, instance instead


def tessellation(o, kind):
    if o.level is not None:
        r, s = (o.level, 2 * o.level) if kind == "sphere" else (2 * o.level, o.level)
    elif kind == "sphere":
        r, s = o.rings or 32, o.segments or 64
        if r < 2 or s < 3:
            raise UsageError("sphere: --rings >= 2 and --segments >= 3")
    else:
        r, s = o.rings or 48, o.segments or 24
        if r < 3 or s < 3:
            raise UsageError("torus: --rings >= 3 and --segments >= 3")
    if (r + 1) * (s + 1) > MAX_VERTICES:
        raise UsageError("%s: %d x %d makes %d vertices, more than %d in one mesh; for large "
                         "triangle counts use `grid`, which instances one mesh"
                         % (kind, r, s, (r + 1) * (s + 1), MAX_VERTICES))
    return r, s


def build(o):
    d = Doc()
    extras = o.material_extras
    bmin, bmax = [-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]
    summary = ""
    view_dir = (0.45, 0.4, 1.0)
    if (o.anim_translation or o.anim_rotation) and o.kind in ("box_room", "grid"):
        raise UsageError("--anim-translation and --anim-rotation animate the object of "
                         "sphere, torus, cube or plane, not %s" % o.kind)
    if o.kind in ("sphere", "torus", "cube", "plane"):
        mat = d.material(o.kind, o.color, o.roughness, o.metallic, o.double_sided, None, extras)
        if o.kind == "sphere":
            r, s = tessellation(o, "sphere")
            prim = make_sphere(r, s, mat)
        elif o.kind == "torus":
            r, s = tessellation(o, "torus")
            prim = make_torus(r, s, o.tube, mat)
            bmin, bmax = [-1 - o.tube, -o.tube, -1 - o.tube], [1 + o.tube, o.tube, 1 + o.tube]
        elif o.kind == "cube":
            prim = make_cube(mat, shared=o.shared_vertices)
            bmin, bmax = [-0.5] * 3, [0.5] * 3
        else:
            seg = o.segments or 1
            if seg > 1023:
                raise UsageError("plane: --segments %d: at most 1023" % seg)
            prim = make_plane(o.size, seg, mat)
            bmin, bmax = [-o.size / 2, 0.0, -o.size / 2], [o.size / 2, 0.0, o.size / 2]
            view_dir = (0.3, 1.0, 0.8)
        m = d.mesh(o.kind, [prim], o)
        node = {"name": o.kind, "mesh": m}
        if o.rotate:
            r = floats(o.rotate, "--rotate", (4,))
            node["rotation"] = list(quat_axis_angle(normalize(r[0:3]), math.radians(r[3])))
        obj = d.node(node)
        add_animation(d, o, obj)
        summary = "%s triangles, %s vertices" % (fmt(len(prim.indices) // 3), fmt(prim.n_vertices))
    elif o.kind == "box_room":
        white = d.material("white", (0.73, 0.73, 0.73, 1), 0.9, 0.0, True)
        red = d.material("red", (0.63, 0.065, 0.05, 1), 0.9, 0.0, True)
        green = d.material("green", (0.14, 0.45, 0.091, 1), 0.9, 0.0, True)
        light = d.material("light", (0.78, 0.78, 0.78, 1), 0.9, 0.0, True, (1.0, 1.0, 1.0))
        boxm = d.material("box", (0.73, 0.73, 0.73, 1), 0.6, 0.0, False, None, extras)
        walls = [make_quad((0, 0, 0), (1, 0, 0), (0, 0, -1), white),    # floor, up
                 make_quad((0, 2, 0), (1, 0, 0), (0, 0, 1), white),     # ceiling, down
                 make_quad((0, 1, -1), (1, 0, 0), (0, 1, 0), white),    # back, towards +Z
                 make_quad((-1, 1, 0), (0, 0, -1), (0, 1, 0), red),     # left, towards +X
                 make_quad((1, 1, 0), (0, 0, 1), (0, 1, 0), green)]     # right, towards -X
        room = d.mesh("room", walls, o)
        panel = d.mesh("light_panel", [make_quad((0, 1.99, 0), (0.25, 0, 0), (0, 0, 0.2),
                                                 light)], o)
        box = d.mesh("box", [make_cube(boxm)], o)
        d.node({"name": "room", "mesh": room})
        d.node({"name": "light_panel", "mesh": panel})
        d.node({"name": "short_box", "mesh": box, "translation": [0.33, 0.3, 0.28],
                "rotation": quat_axis_angle((0, 1, 0), -0.29), "scale": [0.6, 0.6, 0.6]})
        d.node({"name": "tall_box", "mesh": box, "translation": [-0.33, 0.6, -0.3],
                "rotation": quat_axis_angle((0, 1, 0), 0.29), "scale": [0.6, 1.2, 0.6]})
        bmin, bmax = [-1.0, 0.0, -1.0], [1.0, 2.0, 1.0]
        view_dir = (0.0, 0.0, 1.0)
        summary = "36 triangles in 3 meshes (the box mesh twice)"
    else:  # grid
        if o.rings is not None or o.segments is not None or o.level is not None:
            r, s = tessellation(o, "sphere")
            n = o.instances or max(1, round(o.triangles / sphere_tris(r, s)))
        else:
            n = o.instances or max(1, math.ceil(o.triangles / 5000))
            r, s = grid_tessellation(o.triangles / n)
        mat = d.material("spheres", o.color, o.roughness, o.metallic, o.double_sided, None, extras)
        prim = make_sphere(r, s, mat, radius=1.0)
        m = d.mesh("sphere", [prim], o)
        cols = math.ceil(math.sqrt(n))
        rows = math.ceil(n / cols)
        pitch = 2.5
        x0, z0 = -(cols - 1) * pitch / 2, -(rows - 1) * pitch / 2
        for k in range(n):
            x, z = x0 + (k % cols) * pitch, z0 + (k // cols) * pitch
            d.node({"name": "sphere_%d" % k, "mesh": m, "translation": [x, 0.0, z]})
        bmin = [x0 - 1, -1.0, z0 - 1]
        bmax = [-x0 + 1, 1.0, -z0 + 1]
        view_dir = (0.3, 0.8, 1.0)
        tris = len(prim.indices) // 3
        summary = "%s instances x %s = %s triangles, %s vertices in 1 mesh" % (
            fmt(n), fmt(tris), fmt(n * tris), fmt(prim.n_vertices))

    center = [(a + b) / 2 for a, b in zip(bmin, bmax)]
    radius = max(1e-3, 0.5 * math.sqrt(sum((b - a) ** 2 for a, b in zip(bmin, bmax))))

    if not o.no_camera:
        yfov = math.radians(o.yfov)
        target = o.camera_target or center
        if o.camera_pos:
            eye = o.camera_pos
        elif o.kind == "box_room":
            # straight into the open side, the opening just filling the view
            eye = [0.0, 1.0, 1.0 + 1.05 / math.tan(yfov / 2)]
        else:
            dist = radius / math.sin(yfov / 2) * 1.05
            v = normalize(view_dir)
            eye = [center[k] + dist * v[k] for k in range(3)]
        fwd = sub(target, eye)
        if dot(fwd, fwd) == 0:
            raise UsageError("--camera-pos and --camera-target are the same point")
        dist = math.sqrt(dot(fwd, fwd))
        znear = max(1e-3, (dist - radius) * 0.5) if dist > radius else 0.01
        cam = {"name": "camera", "type": "perspective",
               "perspective": {"yfov": yfov, "znear": znear}}
        d.g["cameras"] = [cam]
        d.node({"name": "camera", "camera": 0, "translation": list(eye),
                "rotation": quat_looking_along(fwd)})

    lights = []
    dirs, points = list(o.dir_lights), list(o.point_lights)
    if not o.no_lights and not dirs and not points:
        if o.kind == "box_room":
            points = [[0.0, 1.8, 0.0, 10.0]]
        else:
            dirs = [[-0.4, -1.0, -0.6, 3.0]]
    for k, l in enumerate(dirs):
        color = l[4:7] if len(l) == 7 else [1.0, 1.0, 1.0]
        lights.append({"name": "sun_%d" % k, "type": "directional", "color": color,
                       "intensity": l[3] if len(l) > 3 else 3.0})
        d.node({"name": "sun_%d" % k, "rotation": quat_looking_along(l[0:3]),
                "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}})
    for k, l in enumerate(points):
        color = l[4:7] if len(l) == 7 else [1.0, 1.0, 1.0]
        lights.append({"name": "lamp_%d" % k, "type": "point", "color": color,
                       "intensity": l[3] if len(l) > 3 else 10.0})
        d.node({"name": "lamp_%d" % k, "translation": l[0:3],
                "extensions": {"KHR_lights_punctual": {"light": len(lights) - 1}}})
    if lights:
        d.use_extension("KHR_lights_punctual")
        d.g["extensions"] = {"KHR_lights_punctual": {"lights": lights}}

    if o.medium is not None:
        dens, sc, ab, g = o.medium
        d.g["scenes"][0]["extras"] = {"medium": {"density": dens, "scattering": [sc] * 3,
                                                 "absorption": [ab] * 3, "g": g}}
    return d, summary


def anim_keys(text, what, width):
    """'T:v,v,v;T:v,v,v' -> [(t, [v...])], times strictly increasing."""
    keys = []
    for part in text.split(";"):
        if ":" not in part:
            raise UsageError("%s: '%s' is not T:VALUES" % (what, part))
        t, vals = part.split(":", 1)
        tv = floats(t, what + " time", (1,))[0]
        keys.append((tv, floats(vals, what + " value", (width,))))
    for a, b in zip(keys, keys[1:]):
        if not b[0] > a[0]:
            raise UsageError("%s: times must strictly increase (%g then %g)" % (what, a[0], b[0]))
    return keys


def add_animation(d, o, node):
    """The animation of --anim-translation / --anim-rotation on `node`."""
    chans = []
    if o.anim_translation:
        keys = anim_keys(o.anim_translation, "--anim-translation", 3)
        chans.append(("translation", [k[0] for k in keys], [k[1] for k in keys]))
    if o.anim_rotation:
        keys = anim_keys(o.anim_rotation, "--anim-rotation", 4)
        chans.append(("rotation", [k[0] for k in keys],
                      [list(quat_axis_angle(normalize(k[1][0:3]), math.radians(k[1][3])))
                       for k in keys]))
    if not chans:
        return
    interp = o.anim_interp.upper()
    samplers, channels = [], []
    for path, times, vals in chans:
        width = len(vals[0])
        out = []
        for v in vals:
            if interp == "CUBICSPLINE":
                out += [0.0] * width + list(v) + [0.0] * width
            else:
                out += list(v)
        inp = d.accessor(times, FLOAT, "SCALAR", None)
        d.g["accessors"][inp]["min"] = [min(times)]
        d.g["accessors"][inp]["max"] = [max(times)]
        outp = d.accessor(out, FLOAT, "VEC3" if width == 3 else "VEC4", None)
        samplers.append({"input": inp, "output": outp, "interpolation": interp})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": path}})
    d.g["animations"] = [{"name": "move", "channels": channels, "samplers": samplers}]


def fmt(n):
    return "{:,}".format(n)


def main(argv):
    try:
        o = parse_args(argv)
        d, summary = build(o)
        data = d.encode(o.format)
    except UsageError as e:
        print("gen_scene.py: %s" % e, file=sys.stderr)
        return 2
    try:
        with open(o.output, "wb") as f:
            f.write(data)
    except OSError as e:
        print("gen_scene.py: cannot write %s: %s" % (o.output, e.strerror), file=sys.stderr)
        return 1
    if not o.quiet:
        print("%s: %s, %s bytes" % (o.output, summary, fmt(len(data))))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
