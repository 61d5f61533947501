#!/usr/bin/env python3
"""examples/prt.lgraph through the real program (issue 10, item 8 and "done when").

  cache      `render examples/prt.lgraph --size 96x54 -o a.png --profile` twice into one empty
             cache: the first profile's `cache` column says `miss` for the bake, the second
             `hit` (the bake is loaded: the node prints "loaded from the cache" with -v), and
             both pictures are the same bytes; the picture is not black inside the box
  variants   `--set bake.mode=unshadowed --set lit.backend=cl` and `--set lit.backend=cpu`
             render (exit 0); cl and cpu give the picture gl gives (tone-mapped 8-bit values
             within 2), unshadowed is brighter than shadowed inside the box, and
             `--set lit.rotate_deg=[90,0,0]` changes the picture without baking again
  include    a graph that includes the example and adds `output lit "lit.exr"` writes the
             linear image: float RGBA of the render size, finite, covered pixels alpha 1
             and some positive radiance, the background's alpha 0
  gating     the example's nodes on a glTF scene without geometry: `--explain` shows
             `bake` and `lit` gated ("no geometry") and neither prt_bake nor prt loaded;
             the output is the neutral (zero) image

The example bakes 128 x 128 directions per vertex; the tests set `bake.samples = 16` (a
tenth of a second) and a small size. The example is copied with the assets it names
(symbolic links) into a scratch folder, so that its `output tone "../out/prt.png"` lands
there, never in the source tree.

usage: test_prt_example.py TEST_NAME
"""
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import exr_read  # noqa: E402
import lgrun  # noqa: E402
from lgrun import Fail, check  # noqa: E402

SRC = os.environ["LG_SOURCE_ROOT"]
TMP = lgrun.temp_dir("lg-prt-example-")
W, H = 96, 54
FAST = ["--size", "%dx%d" % (W, H), "--set", "bake.samples=16"]


def tree():
    """TMP/examples/prt.lgraph, TMP/assets -> the source's assets, TMP/out."""
    os.makedirs(os.path.join(TMP, "examples"), exist_ok=True)
    os.makedirs(os.path.join(TMP, "out"), exist_ok=True)
    shutil.copy(os.path.join(SRC, "examples", "prt.lgraph"), os.path.join(TMP, "examples"))
    if not os.path.exists(os.path.join(TMP, "assets")):
        os.symlink(os.path.join(SRC, "assets"), os.path.join(TMP, "assets"))
    return os.path.join(TMP, "examples", "prt.lgraph")


def run(args, cache, expect=0, timeout=300):
    return lgrun.run(args, lgrun.env("", cache), expect, timeout)


def profile_cache(text, node):
    """The `cache` column of `node`'s row in a --profile table."""
    for line in text.splitlines():
        f = line.split()
        if len(f) >= 2 and f[0] == node:
            return f[-1]
    raise Fail("no profile row for node '%s' in:\n%s" % (node, text))


def render_png(graph, name, cache, extra=()):
    out = os.path.join(TMP, name)
    p = run(["render", graph, "-o", out, "--profile", "-v"] + FAST + list(extra), cache)
    with open(out, "rb") as f:
        return f.read(), p.stdout + p.stderr


def png_rows(path):
    """8-bit RGB(A) rows of a PNG lightgraph wrote (via the program: diff's heat map would be
    overkill): read with zlib, filters undone."""
    import struct
    import zlib
    with open(path, "rb") as f:
        data = f.read()
    check(data[:8] == b"\x89PNG\r\n\x1a\n", "%s: not a PNG" % path)
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            check(depth == 8 and ctype in (2, 6), "%s: not 8-bit RGB(A)" % path)
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev, p = [], bytearray(stride), 0
    for _ in range(h):
        ft, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], (prev[i - bpp] if i >= bpp else 0)
            if ft == 1:
                line[i] = (line[i] + a) & 255
            elif ft == 2:
                line[i] = (line[i] + b) & 255
            elif ft == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif ft == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(w)])
        prev = line
    return rows


def box_mean(rows):
    """Mean 8-bit value of the middle of the picture: the back wall and the bunny."""
    vals = [sum(rows[y][x]) / 3 for y in range(H // 3, 2 * H // 3) for x in range(W // 3, 2 * W // 3)]
    return sum(vals) / len(vals)


def test_cache():
    graph = tree()
    cache = os.path.join(TMP, "cache")
    a, log_a = render_png(graph, "a.png", cache)
    b, log_b = render_png(graph, "b.png", cache)
    check(profile_cache(log_a, "bake") == "miss", "first render: bake cache column is not 'miss':\n%s" % log_a)
    check(profile_cache(log_b, "bake") == "hit", "second render: bake cache column is not 'hit':\n%s" % log_b)
    check("transfer baked" in log_a and "transfer loaded from the cache" in log_b,
          "the log does not say baked, then loaded:\n%s\n---\n%s" % (log_a, log_b))
    check(a == b, "the render from the cached bake differs from the first")
    m = box_mean(png_rows(os.path.join(TMP, "a.png")))
    print("inside the box: mean 8-bit value %.1f" % m)
    check(m > 20, "the inside of the box is black (mean %.1f)" % m)


def test_variants():
    graph = tree()
    cache = os.path.join(TMP, "cache")
    render_png(graph, "gl.png", cache)
    gl = png_rows(os.path.join(TMP, "gl.png"))
    for backend in ("cl", "cpu"):
        _, log = render_png(graph, backend + ".png", cache, ["--set", "lit.backend=" + backend])
        check(profile_cache(log, "bake") == "hit", "lit.backend=%s baked again:\n%s" % (backend, log))
        rows = png_rows(os.path.join(TMP, backend + ".png"))
        worst = max(abs(p[c] - q[c]) for r1, r2 in zip(rows, gl) for p, q in zip(r1, r2) for c in range(3))
        print("%s against gl: largest 8-bit difference %d" % (backend, worst))
        check(worst <= 2, "lit.backend=%s differs from gl by %d (8-bit)" % (backend, worst))
    _, log = render_png(graph, "rot.png", cache, ["--set", "lit.rotate_deg=[90,0,0]"])
    check(profile_cache(log, "bake") == "hit", "rotate_deg baked again:\n%s" % log)
    rot = png_rows(os.path.join(TMP, "rot.png"))
    check(rot != gl, "rotate_deg = [90, 0, 0] did not change the picture")
    render_png(graph, "un.png", cache, ["--set", "bake.mode=unshadowed", "--set", "lit.backend=cl"])
    un, sh = box_mean(png_rows(os.path.join(TMP, "un.png"))), box_mean(gl)
    print("inside the box: unshadowed %.1f, shadowed %.1f" % (un, sh))
    check(un > sh, "unshadowed (%.1f) is not brighter than shadowed (%.1f)" % (un, sh))


def test_include():
    tree()
    inc = os.path.join(TMP, "inc.lgraph")
    with open(inc, "w") as f:
        f.write('lightgraph 1\ninclude "examples/prt.lgraph"\noutput lit "lit.exr"\n')
    run(["render", inc] + FAST, os.path.join(TMP, "cache"))
    rows = exr_read.read_exr(os.path.join(TMP, "lit.exr"))
    check(len(rows) == H and len(rows[0]) == W, "lit.exr is %dx%d, want %dx%d" %
          (len(rows[0]), len(rows), W, H))
    covered = [p for r in rows for p in r if p[3] == 1.0]
    empty = [p for r in rows for p in r if p[3] == 0.0]
    check(all(all(v == v and abs(v) < 1e30 for v in p) for r in rows for p in r), "a pixel is not finite")
    check(len(covered) + len(empty) == W * H, "alpha is neither 0 nor 1 somewhere")
    check(len(covered) > W * H // 3 and empty, "%d covered, %d empty pixels" % (len(covered), len(empty)))
    check(max(p[1] for p in covered) > 0.01, "no covered pixel has radiance")
    check(os.path.exists(os.path.join(TMP, "out", "prt.png")), "the example's own output was not written")


def test_gating():
    empty = os.path.join(TMP, "empty.gltf")
    with open(empty, "w") as f:
        f.write('{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}]}\n')
    graph = os.path.join(TMP, "gating.lgraph")
    out = os.path.join(TMP, "gated.exr")
    with open(graph, "w") as f:
        f.write('lightgraph 1\n'
                'scene = gltf { file = "empty.gltf" }\n'
                'sky = probe { file = "%s" }\n'
                'light = sh_project { probe = sky }\n'
                'bake = prt_bake { scene = scene }\n'
                'lit = prt { scene = scene, lighting = light, transfer = bake }\n'
                'output lit "%s"\n' % (os.path.join(SRC, "assets", "probes", "forest_256x128_half_none.exr"), out))
    p = run(["render", graph, "--explain", "--size", "32x16"], os.path.join(TMP, "cache"))
    text = p.stdout + p.stderr
    for node in ("bake", "lit"):
        row = next((l for l in text.splitlines() if l.split()[:1] == [node]), "")
        check("gated" in row and "no geometry" in row, "%s is not gated for want of geometry:\n%s" % (node, text))
    loaded = next((l for l in text.splitlines() if l.startswith("plugins loaded:")), "")
    check(loaded and "prt" not in loaded.split(), "prt was loaded:\n%s" % text)
    check("prt_bake" not in loaded.split(), "prt_bake was loaded:\n%s" % text)
    # sh_project takes no scene: only the gated prt reads it, so it is culled, not loaded
    row = next((l for l in text.splitlines() if l.split()[:1] == ["light"]), "")
    check("culled" in row and "only gated nodes read it" in row,
          "light (sh_project) is not culled behind the gated prt:\n%s" % text)
    check("sh_project" not in loaded.split(), "sh_project was loaded:\n%s" % text)
    rows = exr_read.read_exr(out)
    check(all(v == 0.0 for r in rows for px in r for v in px[:3]), "the gated output is not zero")


TESTS = {"cache": test_cache, "variants": test_variants, "include": test_include,
         "gating": test_gating}

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP, keep_on_fail=True))
