#!/usr/bin/env python3
"""Write assets/meshes/bunny_box_prt.glb, the scene of examples/prt.lgraph.

usage: make_prt_scene.py [GRID] [OUTPUT.glb]
       (defaults: 64, assets/meshes/bunny_box_prt.glb)

The bunny box of assets/meshes/bunny_cornell_box.glb with each of its five walls cut into
a GRID x GRID grid of quads. Precomputed radiance transfer is computed and interpolated per
vertex (TECHNIQUES.md §5, as the seed does), so a wall made of one quad (four vertices, as
in the source file) can show no shadow at all; on a 64 x 64 grid the vertices are about
3 cm apart on a 2 m box, fine enough for the soft shadows of a light probe. Everything else
is kept: nodes and their transforms, materials (with their extensions), the bunny's mesh
(its vertices and normals copied unchanged). Each grid point is the bilinear blend of its
wall's four corners, so the walls stay exactly where they were (the red wall is slightly
skewed in the source; so is its grid); normals are the wall's own.

Pure python, deterministic (the same bytes on every run). Licences: the box is Embree's
Cornell box (Apache-2.0, assets/meshes/LICENSE-Apache-2.0.txt); the bunny is Stanford's
(assets/meshes/LICENSE-Stanford.txt).
"""
import json
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_ibl_scene import accessor, f32, read_glb  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCE = os.path.join(ROOT, 'assets', 'meshes', 'bunny_cornell_box.glb')
DEFAULT_OUT = os.path.join(ROOT, 'assets', 'meshes', 'bunny_box_prt.glb')
BUNNY = 'bunny_5k_meshlab'


def grid(corners, normal, n):
    """(n + 1)^2 vertices of the bilinear patch over corners v0..v3 (s: v0 -> v1, t: v0 ->
    v3), 2 n^2 triangles wound as the source's (v0, v1, v2), (v0, v2, v3)."""
    v0, v1, v2, v3 = corners
    verts = []
    for j in range(n + 1):
        t = j / n
        for i in range(n + 1):
            s = i / n
            verts.append(tuple((1 - t) * ((1 - s) * v0[k] + s * v1[k]) + t * ((1 - s) * v3[k] + s * v2[k])
                               for k in range(3)))
    tris = []
    row = n + 1
    for j in range(n):
        for i in range(n):
            a, b = j * row + i, j * row + i + 1
            c, d = b + row, a + row
            tris += [(a, b, c), (a, c, d)]
    return verts, [normal] * len(verts), tris


def build(n):
    doc, binary = read_glb(SOURCE)
    out = bytearray()
    views, accessors, meshes = [], [], []

    def add_view(data, target):
        while len(out) % 4:
            out.append(0)
        views.append({'buffer': 0, 'byteOffset': len(out), 'byteLength': len(data), 'target': target})
        out.extend(data)
        return len(views) - 1

    for node in doc['nodes']:
        mesh = doc['meshes'][node['mesh']]
        if len(mesh['primitives']) != 1:
            raise SystemExit(f'{SOURCE}: mesh {mesh.get("name")} has several primitives')
        prim = mesh['primitives'][0]
        pos = accessor(doc, binary, prim['attributes']['POSITION'])
        nrm = accessor(doc, binary, prim['attributes']['NORMAL'])
        idx = accessor(doc, binary, prim['indices'])
        if node.get('name') == BUNNY:
            verts, norms = pos, nrm
            tris = [tuple(idx[i:i + 3]) for i in range(0, len(idx), 3)]
        else:
            if len(idx) != 6 or idx[3] != idx[0] or idx[4] != idx[2]:
                raise SystemExit(f'{SOURCE}: wall {node.get("name")} is not one quad (0 1 2, 0 2 3)')
            corners = [pos[idx[0]], pos[idx[1]], pos[idx[2]], pos[idx[5]]]
            verts, norms, tris = grid(corners, nrm[idx[0]], n)
        verts = [tuple(f32(x) for x in v) for v in verts]
        norms = [tuple(f32(x) for x in v) for v in norms]
        big = len(verts) > 65535
        p = add_view(b''.join(struct.pack('<3f', *v) for v in verts), 34962)
        q = add_view(b''.join(struct.pack('<3f', *v) for v in norms), 34962)
        r = add_view(b''.join(struct.pack('<3I' if big else '<3H', *t) for t in tris), 34963)
        lo = [min(v[k] for v in verts) for k in range(3)]
        hi = [max(v[k] for v in verts) for k in range(3)]
        a = len(accessors)
        accessors += [
            {'bufferView': p, 'componentType': 5126, 'count': len(verts), 'type': 'VEC3', 'min': lo, 'max': hi},
            {'bufferView': q, 'componentType': 5126, 'count': len(norms), 'type': 'VEC3'},
            {'bufferView': r, 'componentType': 5125 if big else 5123, 'count': 3 * len(tris), 'type': 'SCALAR'},
        ]
        meshes.append({'name': mesh.get('name', node.get('name')),
                       'primitives': [{'attributes': {'POSITION': a, 'NORMAL': a + 1}, 'indices': a + 2,
                                       'material': prim['material'], 'mode': 4}]})
        node['mesh'] = len(meshes) - 1
    while len(out) % 4:
        out.append(0)
    new = {
        'asset': {'version': '2.0', 'generator': f'lightgraph tools/make_prt_scene.py (grid {n})',
                  'copyright': 'Cornell box: Embree (Apache-2.0); Stanford Bunny: Stanford 3D Scanning '
                               'Repository (see LICENSE-Stanford.txt)'},
        'scene': 0,
        'scenes': [{'name': 'bunny_box_prt', 'nodes': list(range(len(doc['nodes'])))}],
        'nodes': doc['nodes'],
        'meshes': meshes,
        'materials': doc['materials'],
        'accessors': accessors,
        'bufferViews': views,
        'buffers': [{'byteLength': len(out)}],
    }
    if 'extensionsUsed' in doc:
        new['extensionsUsed'] = doc['extensionsUsed']
    text = json.dumps(new, separators=(',', ':'), ensure_ascii=True).encode('ascii')
    text += b' ' * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(out)
    return (struct.pack('<4sII', b'glTF', 2, total) + struct.pack('<II', len(text), 0x4E4F534A) + text +
            struct.pack('<II', len(out), 0x004E4942) + bytes(out))


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 64
    if not 1 <= n <= 1024:
        raise SystemExit(f'grid {n}: expected 1 .. 1024')
    dest = sys.argv[2] if len(sys.argv) > 2 else DEFAULT_OUT
    data = build(n)
    tmp = dest + '.tmp'
    with open(tmp, 'wb') as f:
        f.write(data)
    os.replace(tmp, dest)
    print(f'{dest}: {len(data)} bytes')


if __name__ == '__main__':
    main()
