"""Texture filtering: the preview node's texture filters (nearest, bilinear, trilinear) and
anisotropy levels on a textured plane seen at a grazing angle, against a supersampled
render."""
import base64
import json
import os
import struct
import subprocess

from accuracy.exr import read_exr
from accuracy.png import write_png
from accuracy.study import Study, StudyError

TITLE = "Texture filtering"
ORDER = 35
INTRO = """\
Scene textures are sampled by GL through the scene's sampler (`lg_scene_texture_gl`,
`lg_gl_pass_bind_material`: [docs/sdk.md](sdk.md)); every raster node reads them the same
way (`shaders/common/material.glsl`), so the `preview` node's `filter` and `anisotropy`
knobs stand for all of them ([plugins/preview/README.md](../plugins/preview/README.md)).
Scene: a 100 m ground plane carrying a 64 x 64 checker texture repeated every 2 m, seen
from 1 m above it, looking 3 degrees below the horizon: the texture is magnified at the
bottom of the image and minified ever more (and ever more anisotropically) towards the
horizon, where nearest and bilinear sampling alias into moire. **Reference:** the same
view rendered at 4 x 4 times the pixels with trilinear, 16x anisotropic filtering, averaged
over each 4 x 4 block (a box filter of 16 well-filtered samples per pixel: what a pixel's
footprint holds, to within the box's own blur). Knobs: `filter` (`nearest`, `bilinear`:
level 0 only; `trilinear`: the mip chain, made by glGenerateTextureMipmap) without
anisotropy, then trilinear with `anisotropy` 1..16 (llvmpipe's maximum is 16). Time: the
`preview` node's (`per_frame = true`), median of the repeats (4 frames each, so that the
first frame's shader compilation and texture upload are not what is measured). Metric:
relative RMSE of the linear base colour. On Mesa's llvmpipe (the machine of this page) every
anisotropy above 1 gave the same image (2 and 16 alike: its anisotropic path does not scale
with the limit) at about 17 times trilinear's time: an implementation's property, which a
GPU would not share."""

PATTERN = 64  # texels per side
TILE_M = 2.0  # metres per texture repeat


def _checker_png(path):
    rows = []
    for j in range(PATTERN):
        row = bytearray()
        for i in range(PATTERN):
            light = ((i // 8) + (j // 8)) % 2 == 0
            row += bytes((235, 225, 200) if light else (30, 50, 110))
        rows.append(row)
    write_png(path, PATTERN, PATTERN, 3, rows)


def _plane_gltf(path, png_name):
    """A glTF 2.0 file: the ground plane (x in [-50, 50], z in [-95, 5]) with uv = (x, z) / 2
    m, its checker texture (glTF's default sampler: repeat, trilinear), and a camera 1 m up
    pitched 3 degrees down."""
    x0, x1, z0, z1 = -50.0, 50.0, -95.0, 5.0
    pos = [(x0, 0, z1), (x1, 0, z1), (x1, 0, z0), (x0, 0, z0)]
    uv = [(x / TILE_M, z / TILE_M) for x, _, z in pos]
    data = b"".join(struct.pack("<3f", *p) for p in pos)
    data += b"".join(struct.pack("<3f", 0, 1, 0) for _ in pos)
    data += b"".join(struct.pack("<2f", *t) for t in uv)
    idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0"
    buf = data + idx
    import math
    half = math.radians(-3.0) / 2
    doc = {
        "asset": {"version": "2.0", "generator": "tools/accuracy/sections/textures.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0},
                  {"camera": 0, "translation": [0, 1, 0],
                   "rotation": [math.sin(half), 0, 0, math.cos(half)]}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 200}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1,
                                                   "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                "metallicFactor": 0}}],
        "textures": [{"source": 0}],
        "images": [{"uri": png_name}],
        "buffers": [{"byteLength": len(buf),
                     "uri": "data:application/octet-stream;base64," +
                            base64.b64encode(buf).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [x0, 0, z0], "max": [x1, 0, z1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }
    with open(path, "w") as f:
        json.dump(doc, f)


def _write_exr(path, w, h, chans):
    """An uncompressed scanline OpenEXR of float channels {name: [values]} (what the
    `image` node and `lightgraph sweep --reference` read)."""
    names = sorted(chans)

    def attr(name, typ, value):
        return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(value)) + value

    chl = b"".join(n.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for n in names) + b"\0"
    box = struct.pack("<4i", 0, 0, w - 1, h - 1)
    head = (b"\x76\x2f\x31\x01" + struct.pack("<I", 2) + attr("channels", "chlist", chl) +
            attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box) +
            attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0") +
            attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
            attr("screenWindowCenter", "v2f", struct.pack("<2f", 0, 0)) +
            attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line = 8 + 4 * w * len(names)
    table = b"".join(struct.pack("<Q", len(head) + 8 * h + y * line) for y in range(h))
    body = bytearray()
    for y in range(h):
        body += struct.pack("<ii", y, 4 * w * len(names))
        for n in names:
            body += struct.pack("<%df" % w, *chans[n][y * w:(y + 1) * w])
    with open(path, "wb") as f:
        f.write(head + table + bytes(body))


def _reference(ctx, graph, size, factor):
    """Renders `graph` at `factor` times `size` per side and box-filters it down to `size`:
    the reference image's path."""
    w, h = (int(v) for v in size.split("x"))
    big = os.path.join(ctx.tmp, "reference_big.exr")
    cmd = [ctx.lightgraph, "render", graph, "--size", "%dx%d" % (w * factor, h * factor),
           "--set", "view.filter=trilinear", "--set", "view.anisotropy=16", "-o", big, "-q"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise StudyError("textures: the reference render `%s` failed: %s"
                         % (" ".join(cmd), (r.stderr or r.stdout).strip()))
    bw, bh, ch = read_exr(big)
    out = {}
    n = float(factor * factor)
    for c in ("R", "G", "B", "A"):
        src = ch[c] if c in ch else [1.0] * (bw * bh)
        dst = [0.0] * (w * h)
        for y in range(h):
            for x in range(w):
                s = 0.0
                for dy in range(factor):
                    row = (y * factor + dy) * bw + x * factor
                    s += sum(src[row:row + factor])
                dst[y * w + x] = s / n
        out[c] = dst
    path = os.path.join(ctx.tmp, "reference.exr")
    _write_exr(path, w, h, out)
    return path


def studies(ctx):
    _checker_png(os.path.join(ctx.tmp, "checker.png"))
    _plane_gltf(os.path.join(ctx.tmp, "plane.gltf"), "checker.png")
    graph = ctx.write("textures.lgraph",
                      'lightgraph 1\n'
                      'scene = gltf { file = "plane.gltf" }\n'
                      'view = preview { scene = scene, background = [0.6, 0.7, 0.9], '
                      'per_frame = true }\n'
                      'output view "view.exr"\n')
    size = "96x54" if ctx.quick else "320x180"
    ref = _reference(ctx, graph, size, 4)
    label = ("preview at 4 x 4 times the pixels, trilinear and 16x anisotropic, box-filtered "
             "down")
    common = dict(technique="preview", backend="gl", graph=graph, time_node="view",
                  reference=ref, reference_label=label, size=size, quick_size=size, frames=4,
                  repeat=5, metric="rel_rmse", display="clip")
    return [
        Study(id="textures_filter", title="filter, no anisotropy",
              sets=["view.anisotropy=1"],
              vary=[("view.filter", ["nearest", "bilinear", "trilinear"])],
              quick_vary=[("view.filter", ["nearest", "trilinear"])], **common),
        Study(id="textures_anisotropy", title="trilinear x anisotropy",
              sets=["view.filter=trilinear"],
              vary=[("view.anisotropy", ["1", "2", "4", "8", "16"])],
              quick_vary=[("view.anisotropy", ["1", "16"])], **common),
    ]
