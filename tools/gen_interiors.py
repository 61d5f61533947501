"""gen_interiors.py: the thesis's interiors for tools/gen_scene.py (kinds classroom, courtyard).

Imported by gen_scene.py, which owns the command line, the document (Doc) and the file
format; this module builds the two procedural interiors the volumetric thesis renders
(its Classroom and San Miguel cannot be had here) and the small PNG textures they use.
Python 3 standard library only (zlib for PNG); every random choice comes from a
random.Random with a fixed seed, so the same arguments give the same bytes.

classroom  a room 7 x 10 x 3.2 m: floor (tiled texture), ceiling, four walls, three windows
           along the x = 0 wall with venetian blinds of thin slats (--slats per window,
           --slat-tilt degrees, --slat-thickness metres), rows of desks (wood texture) and
           chairs, a blackboard, the sun shining in through the blinds, a spot light over
           the blackboard and a participating medium (scene extras), so the volumetric nodes
           show the shafts between the slats.
courtyard  a square courtyard 24 m across inside two storeys of arcades (columns, round
           arches, gallery floors and roof, outer walls), stone-textured ground, planters
           with foliage cards and a tree whose crown is cards: quads with an alpha-masked
           leaf texture (alphaMode MASK, alphaCutoff 0.5, double-sided), the sun and a
           medium. --detail D scales the triangle count (cards linearly, the columns'
           tessellation by sqrt(D)): about 3.6 million at D = 1, a few ten thousand at
           D = 0.01 (the tests' variant).
"""
import math
import random
import struct
import zlib

# ---- PNG ----------------------------------------------------------------------------------

def png_encode(width, height, channels, pixels):
    """An 8-bit PNG (colour type 2 RGB or 6 RGBA) of `pixels`, a bytes-like of
    width * height * channels values, rows top first. Filter 0 on every row and zlib level 9:
    deterministic bytes."""
    ctype = {3: 2, 4: 6}[channels]
    stride = width * channels
    raw = bytearray()
    for y in range(height):
        raw.append(0)
        raw += pixels[y * stride:(y + 1) * stride]

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, ctype, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b""))


def clamp8(v):
    return max(0, min(255, int(round(v))))


def tex_wood(size=64):
    """Wood grain: rings along v, wavy, in sRGB browns (stretched along a desk's length)."""
    px = bytearray()
    for y in range(size):
        for x in range(size):
            u, v = x / size, y / size
            ring = math.sin(2 * math.pi * (6 * u + 0.35 * math.sin(2 * math.pi * 2 * v)))
            t = 0.5 + 0.5 * ring
            px += bytes((clamp8(150 + 45 * t), clamp8(98 + 30 * t), clamp8(52 + 18 * t)))
    return png_encode(size, size, 3, px)


def tex_tiles(size=64, a=(200, 196, 184), b=(128, 112, 96), grout=(70, 66, 60)):
    """A 2 x 2 checker of tiles with grout lines (one texture repeat = 2 tiles)."""
    px = bytearray()
    half = size // 2
    for y in range(size):
        for x in range(size):
            if x % half in (0, half - 1) or y % half in (0, half - 1):
                c = grout
            else:
                c = a if (x // half + y // half) % 2 == 0 else b
            px += bytes(c)
    return png_encode(size, size, 3, px)


def tex_stone(size=64, seed=7):
    """Irregular flagstones: a jittered grid of cells, each its own grey-ochre, with joints."""
    rnd = random.Random(seed)
    n = 4
    tone = [[(clamp8(150 + rnd.uniform(-25, 25)), clamp8(138 + rnd.uniform(-25, 20)),
              clamp8(118 + rnd.uniform(-20, 20))) for _ in range(n)] for _ in range(n)]
    px = bytearray()
    cell = size // n
    for y in range(size):
        for x in range(size):
            cx, cy = x // cell, y // cell
            # rows offset by half a stone, like a running bond
            cx = ((x + (cell // 2 if cy % 2 else 0)) // cell) % n
            if y % cell == 0 or (x + (cell // 2 if cy % 2 else 0)) % cell == 0:
                px += bytes((86, 80, 72))
            else:
                px += bytes(tone[cy][cx])
    return png_encode(size, size, 3, px)


def tex_leaves(size=128, seed=11):
    """RGBA leaves on transparency: ellipses with a midrib, alpha 255 inside, 0 outside, so
    alphaMode MASK cuts the card to the leaves' outline."""
    rnd = random.Random(seed)
    leaves = []
    for _ in range(14):
        leaves.append((rnd.uniform(0.18, 0.82), rnd.uniform(0.18, 0.82), rnd.uniform(0.07, 0.13),
                       rnd.uniform(0.025, 0.05), rnd.uniform(0, math.pi),
                       (clamp8(rnd.uniform(40, 90)), clamp8(rnd.uniform(100, 160)),
                        clamp8(rnd.uniform(25, 60)))))
    px = bytearray()
    for y in range(size):
        for x in range(size):
            u, v = (x + 0.5) / size, (y + 0.5) / size
            c = None
            for (cx, cy, a, b, ang, col) in leaves:
                du, dv = u - cx, v - cy
                p = du * math.cos(ang) + dv * math.sin(ang)
                q = -du * math.sin(ang) + dv * math.cos(ang)
                if (p / a) ** 2 + (q / b) ** 2 <= 1.0:
                    c = (col[0], col[1], col[2])
                    if abs(q) < 0.004:  # the midrib, lighter
                        c = (clamp8(col[0] + 40), clamp8(col[1] + 40), clamp8(col[2] + 30))
            px += bytes((c[0], c[1], c[2], 255)) if c else bytes((0, 0, 0, 0))
    return png_encode(size, size, 4, px)


# ---- meshes -------------------------------------------------------------------------------

def make_cylinder(Prim, radius, height, segments, rings, material):
    """An open cylinder around +Y from y = 0 to height, normals outwards, u around, v up
    (the caps are hidden under the capital and on the floor)."""
    pos, nrm, uv, idx = [], [], [], []
    for i in range(rings + 1):
        y = height * i / rings
        for j in range(segments + 1):
            a = 2 * math.pi * (j % segments) / segments
            c, s = math.cos(a), math.sin(a)
            pos += [radius * s, y, radius * c]
            nrm += [s, 0.0, c]
            uv += [j / segments, 1.0 - i / rings * height]
    w = segments + 1
    for i in range(rings):
        for j in range(segments):
            a, b, c, d = i * w + j, i * w + j + 1, (i + 1) * w + j + 1, (i + 1) * w + j
            idx += [a, b, c, a, c, d]
    return Prim(pos, nrm, uv, idx, material)


def make_arch(Prim, span, radius, height, depth, segments, material):
    """A wall piece of width `span`, height `height` and thickness `depth` (along Z, centred)
    with a round arch of `radius` (< span / 2, < height) cut from it, springing at y = 0:
    front and back faces plus the curved soffit. Local x in [-span/2, span/2], y in
    [0, height]; the piece rests on the capitals either side of the opening."""
    r, hw = radius, span / 2
    corner = math.atan2(height, hw)
    angles = sorted(set([math.pi * k / segments for k in range(segments + 1)] +
                        [corner, math.pi - corner]))
    pos, nrm, uv, idx = [], [], [], []

    def outer(a):
        c, s = math.cos(a), math.sin(a)
        t = min(hw / abs(c) if abs(c) > 1e-12 else 1e30, height / s if s > 1e-12 else 1e30)
        return (t * c, t * s)

    for face, z, nz in ((0, depth / 2, 1.0), (1, -depth / 2, -1.0)):
        base = len(pos) // 3
        for a in angles:
            ix, iy = r * math.cos(a), r * math.sin(a)
            ox, oy = outer(a)
            for (x, y) in ((ix, iy), (ox, oy)):
                pos += [x, y, z]
                nrm += [0.0, 0.0, nz]
                uv += [x / span + 0.5, 1.0 - y / span]
        for k in range(len(angles) - 1):
            a, b, c, d = (base + 2 * k, base + 2 * k + 1, base + 2 * k + 3, base + 2 * k + 2)
            # angles grow counter-clockwise seen from +Z: inner k, outer k, outer k+1
            if nz > 0:
                idx += [a, b, c, a, c, d]
            else:
                idx += [a, c, b, a, d, c]
    base = len(pos) // 3
    for a in angles:  # the soffit, facing the arch's centre
        c, s = math.cos(a), math.sin(a)
        for z in (depth / 2, -depth / 2):
            pos += [r * c, r * s, z]
            nrm += [-c, -s, 0.0]
            uv += [a / math.pi, 0.5 - z / depth]
    for k in range(len(angles) - 1):
        a, b, c, d = base + 2 * k, base + 2 * k + 1, base + 2 * k + 3, base + 2 * k + 2
        idx += [a, c, b, a, d, c]
    return Prim(pos, nrm, uv, idx, material)


def make_cards(Prim, rnd, count, center, radii, size, material, up_bias=0.0):
    """`count` square cards of edge `size`, centres uniform in an ellipsoid of the given
    radii around `center` (pushed upwards by up_bias in [0, 1)), random orientations; uv the
    whole texture on each card."""
    pos, nrm, uv, idx = [], [], [], []
    h = size / 2
    for k in range(count):
        while True:
            p = (rnd.uniform(-1, 1), rnd.uniform(-1, 1), rnd.uniform(-1, 1))
            if p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0:
                break
        py = p[1] * (1 - up_bias) + up_bias * abs(p[1])
        c = (center[0] + radii[0] * p[0], center[1] + radii[1] * py, center[2] + radii[2] * p[2])
        # a random unit normal and a tangent frame around it
        z = rnd.uniform(-1, 1)
        phi = rnd.uniform(0, 2 * math.pi)
        s = math.sqrt(max(0.0, 1 - z * z))
        n = (s * math.cos(phi), z, s * math.sin(phi))
        a = (1.0, 0.0, 0.0) if abs(n[0]) < 0.9 else (0.0, 1.0, 0.0)
        u = _normalize(_cross(a, n))
        v = _cross(n, u)
        base = 4 * k
        for su, sv in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            pos += [c[i] + h * (su * u[i] + sv * v[i]) for i in range(3)]
            nrm += list(n)
            uv += [(su + 1) / 2, (1 - sv) / 2]
        idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return Prim(pos, nrm, uv, idx, material)


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _normalize(a):
    n = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    return (a[0] / n, a[1] / n, a[2] / n)


def box_node(d, name, mesh, lo, hi, rotation=None):
    """A node drawing the unit cube `mesh` stretched to the box lo..hi (before `rotation`,
    a quaternion about the box's centre)."""
    node = {"name": name, "mesh": mesh,
            "translation": [(lo[k] + hi[k]) / 2 for k in range(3)],
            "scale": [hi[k] - lo[k] for k in range(3)]}
    if rotation:
        node["rotation"] = rotation
    return d.node(node)


# ---- classroom ----------------------------------------------------------------------------

ROOM = (7.0, 3.2, 10.0)  # x (windows at x = 0), y, z (blackboard at z = 0)
WINDOWS_Z = (2.5, 5.0, 7.5)  # centres along the window wall
WINDOW_W, SILL, LINTEL = 1.8, 0.9, 2.6


def classroom(d, o, g):
    """Builds the classroom into Doc `d`; `g` is gen_scene's helpers (Prim, make_quad,
    make_cube, quat_axis_angle). Returns (bmin, bmax, summary, camera, lights, medium)."""
    Prim, make_quad, make_cube, quat_axis_angle = g
    W, H, D = ROOM
    wood = d.texture(d.image(tex_wood(), "wood"), d.sampler())
    tiles = d.texture(d.image(tex_tiles(), "floor_tiles"), d.sampler())
    m_floor = d.material("floor", (1, 1, 1, 1), 0.8, 0.0, True, base_color_texture=tiles)
    m_wall = d.material("plaster", (0.78, 0.76, 0.7, 1), 0.9, 0.0, True)
    m_ceiling = d.material("ceiling", (0.85, 0.85, 0.85, 1), 0.9, 0.0, True)
    m_wood = d.material("wood", (1, 1, 1, 1), 0.6, 0.0, False, base_color_texture=wood)
    m_metal = d.material("metal", (0.25, 0.26, 0.28, 1), 0.4, 0.0, False)
    m_chair = d.material("chair", (0.55, 0.18, 0.12, 1), 0.6, 0.0, False)
    m_slat = d.material("slat", (0.85, 0.85, 0.82, 1), 0.5, 0.0, True)
    m_board = d.material("blackboard", (0.08, 0.16, 0.1, 1), 0.7, 0.0, False)

    # the floor tiles repeat every 1 m (a texture holds 2 x 2 tiles of 0.5 m)
    floor = make_quad((W / 2, 0, D / 2), (W / 2, 0, 0), (0, 0, -D / 2), m_floor)
    floor.texcoords = [t * s for t, s in zip(floor.texcoords, [W, D] * 4)]
    surfaces = [floor,
                make_quad((W / 2, H, D / 2), (W / 2, 0, 0), (0, 0, D / 2), m_ceiling),
                make_quad((W / 2, H / 2, 0), (W / 2, 0, 0), (0, H / 2, 0), m_wall),   # front
                make_quad((W / 2, H / 2, D), (-W / 2, 0, 0), (0, H / 2, 0), m_wall),  # back
                make_quad((W, H / 2, D / 2), (0, 0, D / 2), (0, H / 2, 0), m_wall)]   # right
    # the window wall (x = 0, facing +X) around the openings
    def wall_rect(z0, z1, y0, y1):
        return make_quad((0, (y0 + y1) / 2, (z0 + z1) / 2), (0, 0, -(z1 - z0) / 2),
                         (0, (y1 - y0) / 2, 0), m_wall)
    surfaces.append(wall_rect(0, D, 0, SILL))
    surfaces.append(wall_rect(0, D, LINTEL, H))
    edges = [0.0]
    for zc in WINDOWS_Z:
        edges += [zc - WINDOW_W / 2, zc + WINDOW_W / 2]
    edges.append(D)
    for k in range(0, len(edges), 2):
        surfaces.append(wall_rect(edges[k], edges[k + 1], SILL, LINTEL))
    room = d.mesh("room", surfaces, o)
    d.node({"name": "room", "mesh": room})
    board = d.mesh("blackboard", [make_quad((W / 2 + 0.5, 1.55, 0.01), (2.0, 0, 0), (0, 0.6, 0),
                                            m_board)], o)
    d.node({"name": "blackboard", "mesh": board})

    # the shell's thickness: slabs of 0.25 m behind the walls and above the ceiling (1 mm
    # outside the visible surfaces), so that the sun reaches the room only through the
    # windows; zero-thickness walls would let a shadow map's bias leak light along them
    t, e = 0.25, 0.001
    cube_wall = d.mesh("wall_box", [make_cube(m_wall)], o)
    shell = [((-t, -e, -t), (W + t, H + e + t, -e)),            # front
             ((-t, -e, D + e), (W + t, H + e + t, D + t)),      # back
             ((W + e, -e, -t), (W + t, H + e + t, D + t)),      # right
             ((-t, H + e, -t), (W + t, H + t, D + t)),          # ceiling
             ((-t, -e, -t), (-e, SILL, D + t)),                 # window wall, below the sills
             ((-t, LINTEL, -t), (-e, H + e + t, D + t))]        # and above the lintels
    for k in range(0, len(edges), 2):
        shell.append(((-t, SILL, edges[k]), (-e, LINTEL, edges[k + 1])))
    for k, (lo, hi) in enumerate(shell):
        box_node(d, "shell_%d" % k, cube_wall, lo, hi)

    cube_wood = d.mesh("wood_box", [make_cube(m_wood)], o)
    cube_metal = d.mesh("metal_box", [make_cube(m_metal)], o)
    cube_chair = d.mesh("chair_box", [make_cube(m_chair)], o)
    cube_slat = d.mesh("slat", [make_cube(m_slat)], o)

    def desk(name, x, z, w=1.2, dz=0.6):
        box_node(d, name + "_top", cube_wood, (x - w / 2, 0.72, z - dz / 2), (x + w / 2, 0.75, z + dz / 2))
        for k, (sx, sz) in enumerate(((-1, -1), (1, -1), (1, 1), (-1, 1))):
            lx, lz = x + sx * (w / 2 - 0.05), z + sz * (dz / 2 - 0.05)
            box_node(d, "%s_leg%d" % (name, k), cube_metal, (lx - 0.02, 0, lz - 0.02), (lx + 0.02, 0.72, lz + 0.02))

    def chair(name, x, z):
        box_node(d, name + "_seat", cube_wood, (x - 0.21, 0.43, z - 0.21), (x + 0.21, 0.46, z + 0.21))
        box_node(d, name + "_back", cube_chair, (x - 0.21, 0.6, z + 0.19), (x + 0.21, 0.9, z + 0.22))
        for k, (sx, sz) in enumerate(((-1, -1), (1, -1), (1, 1), (-1, 1))):
            lx, lz = x + sx * 0.18, z + sz * 0.18
            box_node(d, "%s_leg%d" % (name, k), cube_metal, (lx - 0.015, 0, lz - 0.015), (lx + 0.015, 0.43 if sz < 0 else 0.9, lz + 0.015))

    n_desks = 0
    for r, z in enumerate((3.0, 4.6, 6.2, 7.8)):
        for c, x in enumerate((1.9, 3.6, 5.3)):
            desk("desk_%d_%d" % (r, c), x, z)
            chair("chair_%d_%d_a" % (r, c), x - 0.3, z + 0.6)
            chair("chair_%d_%d_b" % (r, c), x + 0.3, z + 0.6)
            n_desks += 1
    desk("teacher_desk", 4.8, 1.3, 1.6, 0.8)
    chair("teacher_chair", 4.8, 0.55)

    # venetian blinds: slats just inside each opening, tilted about their long axis (z)
    n, tilt, thick = o.slats, math.radians(o.slat_tilt), o.slat_thickness
    spacing = (LINTEL - SILL) / n
    width = 1.2 * spacing
    rot = quat_axis_angle((0, 0, 1), tilt)
    for wi, zc in enumerate(WINDOWS_Z):
        for k in range(n):
            y = SILL + (k + 0.5) * spacing
            x = 0.08
            box_node(d, "slat_%d_%d" % (wi, k), cube_slat,
                     (x - width / 2, y - thick / 2, zc - WINDOW_W / 2 + 0.01),
                     (x + width / 2, y + thick / 2, zc + WINDOW_W / 2 - 0.01), rot)

    camera = ((W - 0.5, 1.75, D - 0.4), (0.8, 1.2, 2.6))
    # the sun comes in through the windows (travelling +X, down, a little towards +Z); a
    # spot light over the blackboard
    lights = {"dir": [[0.78, -0.5, 0.38, 4.0]],
              "spot": [[W / 2 + 0.5, H - 0.05, 0.9, 0.0, -1.0, -0.45, 12.0, 20.0, 40.0]]}
    medium = [1.0, 0.08, 0.01, 0.5]
    summary = "%d desks and %d chairs, %d windows of %d slats (tilt %g deg, %g m thick)" % (
        n_desks + 1, 2 * n_desks + 1, len(WINDOWS_Z), n, o.slat_tilt, thick)
    return [0.0, 0.0, 0.0], [W, H, D], summary, camera, lights, medium


# ---- courtyard ----------------------------------------------------------------------------

HALF = 12.0     # the courtyard spans x, z in [-HALF, HALF]
GALLERY = 3.0   # gallery depth behind the arcade
STOREY = 5.0
BAY = 3.0
COL_R, COL_H = 0.22, 3.0


def courtyard(d, o, g):
    Prim, make_quad, make_cube, quat_axis_angle = g
    det = o.detail
    rnd = random.Random(2024)
    stone = d.texture(d.image(tex_stone(), "stone"), d.sampler())
    leaves = d.texture(d.image(tex_leaves(), "leaves"), d.sampler())
    m_ground = d.material("ground", (1, 1, 1, 1), 0.9, 0.0, True, base_color_texture=stone)
    m_stone = d.material("stone", (0.85, 0.8, 0.72, 1), 0.8, 0.0, True)
    m_plaster = d.material("plaster", (0.9, 0.82, 0.68, 1), 0.9, 0.0, True)
    m_bark = d.material("bark", (0.3, 0.22, 0.15, 1), 0.9, 0.0, False)
    m_leaf = d.material("leaves", (1, 1, 1, 1), 0.7, 0.0, True, base_color_texture=leaves,
                        alpha_mode="MASK", alpha_cutoff=0.5)

    out = HALF + GALLERY
    top = 2 * STOREY
    ground = make_quad((0, 0, 0), (out, 0, 0), (0, 0, -out), m_ground)
    ground.texcoords = [t * 2 * out / 2 for t in ground.texcoords]  # a texture every 2 m
    shell = [ground]
    for n in ((1, 0, 0), (-1, 0, 0), (0, 0, 1), (0, 0, -1)):
        # the outer walls, facing inwards (n): u = Y x n, so that u x Y = n
        u = (n[2], 0, -n[0])
        c = (-n[0] * out, top / 2, -n[2] * out)
        shell.append(make_quad(c, (u[0] * out, 0, u[2] * out), (0, top / 2, 0), m_plaster))
    d.node({"name": "shell", "mesh": d.mesh("shell", shell, o)})

    slab = d.mesh("slab", [make_cube(m_stone)], o)
    # gallery floor (upper storey) and roof: four slabs each, a ring around the courtyard
    for level, y in (("floor1", STOREY), ("roof", top)):
        for k, (lo, hi) in enumerate((((HALF, y - 0.3, -out), (out, y, out)),
                                      ((-out, y - 0.3, -out), (-HALF, y, out)),
                                      ((-HALF, y - 0.3, HALF), (HALF, y, out)),
                                      ((-HALF, y - 0.3, -out), (HALF, y, -HALF)))):
            box_node(d, "%s_%d" % (level, k), slab, lo, hi)

    seg = max(8, round(64 * math.sqrt(det)))
    rings = max(2, round(128 * math.sqrt(det)))
    column = d.mesh("column", [make_cylinder(Prim, COL_R, COL_H, seg, rings, m_stone)], o)
    arch_seg = max(6, round(48 * math.sqrt(det)))
    arch = d.mesh("arch", [make_arch(Prim, BAY, BAY / 2 - 0.25, STOREY - COL_H - 0.3, 0.5,
                                     arch_seg, m_plaster)], o)
    capital = slab  # a stone box
    n_cols = int(round(2 * HALF / BAY))
    n_columns = 0
    for s in range(2):
        y0 = s * STOREY
        for side in range(4):
            for i in range(n_cols):
                t = -HALF + i * BAY  # each side owns its first corner
                # side 0: z = -HALF, x = t; 1: x = HALF, z = t; 2: z = HALF, x = -t; 3: x = -HALF, z = -t
                x, z = ((t, -HALF), (HALF, t), (-t, HALF), (-HALF, -t))[side]
                name = "col_%d_%d_%d" % (s, side, i)
                d.node({"name": name, "mesh": column, "translation": [x, y0, z]})
                box_node(d, name + "_base", capital, (x - 0.3, y0, z - 0.3), (x + 0.3, y0 + 0.15, z + 0.3))
                box_node(d, name + "_cap", capital, (x - 0.3, y0 + COL_H - 0.15, z - 0.3),
                         (x + 0.3, y0 + COL_H, z + 0.3))
                n_columns += 1
                # the arch from this column to the next along the side
                mid = ((t + BAY / 2, -HALF), (HALF, t + BAY / 2), (-t - BAY / 2, HALF),
                       (-HALF, -t - BAY / 2))[side]
                ang = (0.0, -math.pi / 2, math.pi, math.pi / 2)[side]
                d.node({"name": "arch_%d_%d_%d" % (s, side, i), "mesh": arch,
                        "translation": [mid[0], y0 + COL_H, mid[1]],
                        "rotation": quat_axis_angle((0, 1, 0), ang)})

    # foliage: planters with bushes of cards, a tree in the middle
    cards = max(4, round(24000 * det))
    bush = d.mesh("bush", [make_cards(Prim, rnd, cards, (0, 0.9, 0), (0.75, 0.6, 0.75), 0.3,
                                      m_leaf, 0.5)], o)
    planters = []
    for k in range(8):
        for r in (5.0, 9.0):
            a = 2 * math.pi * (k + (0.5 if r > 6 else 0.0)) / 8
            planters.append((r * math.cos(a), r * math.sin(a)))
    for k in range(len(planters), 32):
        # the rest along the arcades' inner edge
        side, i = divmod(k - len(planters), 4)
        t = -7.5 + 5.0 * i
        planters.append(((t, -10.8), (10.8, t), (-t, 10.8), (-10.8, -t))[side])
    for k, (x, z) in enumerate(planters):
        box_node(d, "planter_%d" % k, slab, (x - 0.45, 0, z - 0.45), (x + 0.45, 0.5, z + 0.45))
        d.node({"name": "bush_%d" % k, "mesh": bush, "translation": [x, 0.0, z],
                "rotation": quat_axis_angle((0, 1, 0), rnd.uniform(0, 2 * math.pi))})
    trunk = d.mesh("trunk", [make_cylinder(Prim, 0.3, 5.5, max(8, seg // 2), max(2, rings // 4),
                                           m_bark)], o)
    d.node({"name": "trunk", "mesh": trunk})
    crown_cards = max(8, round(400000 * det))
    parts = max(1, math.ceil(crown_cards * 4 / (1 << 20)))
    crown_prims = []
    for p in range(parts):
        n = crown_cards // parts + (1 if p < crown_cards % parts else 0)
        crown_prims.append(d.mesh("crown_%d" % p, [make_cards(Prim, rnd, n, (0, 7.0, 0),
                                                              (3.6, 2.4, 3.6), 0.7, m_leaf)], o))
    for p, m in enumerate(crown_prims):
        d.node({"name": "crown_%d" % p, "mesh": m})

    camera = ((-HALF + 1.5, 1.7, HALF - 1.5), (3.0, 4.5, -3.0))
    lights = {"dir": [[0.45, -0.8, 0.4, 5.0]], "spot": []}
    medium = [1.0, 0.04, 0.004, 0.5]
    summary = ("%d columns and arches, %d planters of %d leaf cards, a tree of %d cards "
               "(detail %g)" % (n_columns, len(planters), cards, crown_cards, det))
    return [-out, 0.0, -out], [out, top, out], summary, camera, lights, medium
