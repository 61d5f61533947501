#!/usr/bin/env python3
"""Image inputs and outputs through the real program (docs/images.md):

  max_pixels     --max-pixels N and LIGHTGRAPH_MAX_PIXELS bound every image read: `diff`
                 and a render's image node refuse a 20x20 PNG at 100 pixels, with the
                 message naming the file, its size and the limit, and accept it at 400; the
                 option wins over the environment; a bad value is a usage error
  exr_precision  EXR outputs are float32 by default, half or float per output statement
                 (`output n "f.exr" half`), for every EXR output with `render --exr`; fmt
                 keeps the word; half after a .png name is refused; the files are read back
                 to see their pixel type
  special        an image node or diff argument that is a FIFO or /dev/zero fails at once
  exr_tall_narrow  32x864 float images of noisy content, read by image nodes and written by
                 `output n "f.exr"` (ZIP, float), come back bit for bit (read by exr_read.py,
                 not lightgraph): OpenEXR 3.1.5 stored a zlib chunk exactly as long as its
                 raw pixels, which every reader takes as raw, in about 1 such image in 5

usage: test_images.py TEST_NAME
"""
import os
import struct
import sys
import zlib

import lgrun
from lgrun import Fail, check

TMP = lgrun.temp_dir("lg-images-test-")


def run(args, env_extra=None, expect=None, timeout=60):
    env = lgrun.env("", os.path.join(TMP, "cache"), env_extra, drop=["LIGHTGRAPH_MAX_PIXELS"])
    return lgrun.run(args, env, expect, timeout)


def path(name):
    return os.path.join(TMP, name)


def write(name, text):
    return lgrun.write(path(name), text)


def png(name, w, h):
    """An 8-bit RGB PNG, mid grey."""
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    raw = b"".join(b"\0" + bytes([128] * 3 * w) for _ in range(h))
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    with open(path(name), "wb") as f:
        f.write(data)
    return path(name)


def pixel_bits(file):
    """16 (half) or 32 (float) for an EXR, from diff's description of the file."""
    out = run(["diff", file, file], expect=0).stdout
    first = out.splitlines()[0]
    for bits in ("16-bit", "32-bit"):
        if bits in first:
            return int(bits[:2])
    raise Fail("diff does not say the pixel type: " + first)


def test_max_pixels():
    a = png("a.png", 20, 20)
    # diff: the environment, the option, the option over the environment
    p = run(["diff", a, a], {"LIGHTGRAPH_MAX_PIXELS": "100"}, expect=1)
    check("a.png" in p.stderr and "20 x 20" in p.stderr and "over the limit of 100 pixels" in p.stderr
          and "LIGHTGRAPH_MAX_PIXELS" in p.stderr and "--max-pixels" in p.stderr, p.stderr)
    run(["diff", a, a], {"LIGHTGRAPH_MAX_PIXELS": "400"}, expect=0)
    p = run(["diff", a, a, "--max-pixels", "100"], expect=1)
    check("over the limit of 100 pixels" in p.stderr, p.stderr)
    run(["diff", "--max-pixels=400", a, a], {"LIGHTGRAPH_MAX_PIXELS": "100"}, expect=0)
    run(["--max-pixels", "400", "diff", a, a], {"LIGHTGRAPH_MAX_PIXELS": "100"}, expect=0)
    for bad in ("abc", "0", "-5", ""):
        p = run(["diff", a, a, "--max-pixels", bad], expect=2)
        check("--max-pixels" in p.stderr, p.stderr)
    p = run(["diff", a, a, "--max-pixels"], expect=2)

    # render: the image node reads with the same limit
    g = write("g.lgraph", 'lightgraph 1\nsrc = image { file = "a.png" }\noutput src "o.exr"\n')
    p = run(["render", g, "--max-pixels", "100"], expect=1)
    check("a.png" in p.stderr and "over the limit of 100 pixels" in p.stderr, p.stderr)
    check(not os.path.exists(path("o.exr")), "an output was written")
    p = run(["render", g], {"LIGHTGRAPH_MAX_PIXELS": "100"}, expect=1)
    check("over the limit of 100 pixels" in p.stderr, p.stderr)
    run(["render", g, "--max-pixels", "400"], expect=0)
    check(os.path.exists(path("o.exr")), "no output")


def test_exr_precision():
    png("a.png", 20, 20)
    g = write("g.lgraph",
              'lightgraph 1\nsrc = image { file = "a.png" }\n'
              'output src "default.exr"\noutput src "h.exr" half  # small\n'
              'output src "f.exr" float\n')
    run(["render", g], expect=0)
    check(pixel_bits(path("default.exr")) == 32, "default EXR output is not float32")
    check(pixel_bits(path("h.exr")) == 16, "'half' output is not half")
    check(pixel_bits(path("f.exr")) == 32, "'float' output is not float32")
    # fmt keeps the words (and the comment)
    out = run(["fmt", g], expect=0).stdout
    check('output src "h.exr" half  # small' in out and 'output src "f.exr" float' in out, out)
    fmt2 = write("g2.lgraph", out)
    check(run(["fmt", fmt2], expect=0).stdout == out, "fmt is not a fixed point")

    # render --exr: every EXR output, -o included
    one = write("one.lgraph", 'lightgraph 1\nsrc = image { file = "a.png" }\noutput src "x.exr"\n')
    run(["render", one, "-o", path("o_half.exr"), "--exr", "half"], expect=0)
    check(pixel_bits(path("o_half.exr")) == 16, "-o with --exr half is not half")
    run(["render", g, "--exr", "half"], expect=0)
    check(pixel_bits(path("f.exr")) == 16 and pixel_bits(path("default.exr")) == 16,
          "--exr half did not apply to every output")
    p = run(["render", one, "--exr", "quarter"], expect=2)
    check("--exr wants half or float" in p.stderr, p.stderr)

    # 'half' after another extension, or another word
    bad = write("bad.lgraph", 'lightgraph 1\nsrc = image { file = "a.png" }\n'
                'output src "o.png" half\n')
    p = run(["check", bad], expect=2)
    check("'half' chooses the pixel type of an .exr output; 'o.png' is not one" in p.stderr, p.stderr)
    bad = write("bad2.lgraph", 'lightgraph 1\nsrc = image { file = "a.png" }\n'
                'output src "o.exr" quarter\n')
    p = run(["check", bad], expect=2)
    check("found 'quarter'" in p.stderr, p.stderr)


def test_special():
    os.mkfifo(path("f.exr"))
    os.symlink("/dev/zero", path("z.png"))
    png("a.png", 4, 4)
    for name, what in (("f.exr", "it is a FIFO, not a regular file"),
                       ("z.png", "it is a character device, not a regular file")):
        g = write("s.lgraph", 'lightgraph 1\nsrc = image { file = "%s" }\noutput src "o.exr"\n' % name)
        p = run(["render", g], expect=1, timeout=20)
        check(name in p.stderr and what in p.stderr, p.stderr)
        p = run(["diff", path(name), path("a.png")], expect=1, timeout=20)
        check(name in p.stderr and what in p.stderr, p.stderr)


def exr_none_float(name, w, h, bits):
    """An uncompressed float RGBA EXR of w x h: a ramp across each row whose low mantissa
    bits are noise (what a rendered image's floats look like to zlib). `bits` are the
    file's values as float32 bit patterns, row by row, R G B A per pixel."""
    def attr(n, t, v):
        return n.encode() + b"\0" + t.encode() + b"\0" + struct.pack("<i", len(v)) + v
    chl = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "ABGR") + b"\0"
    box = struct.pack("<4i", 0, 0, w - 1, h - 1)
    head = (b"\x76\x2f\x31\x01" + struct.pack("<I", 2) + attr("channels", "chlist", chl) +
            attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box) +
            attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0") +
            attr("pixelAspectRatio", "float", struct.pack("<f", 1.0)) +
            attr("screenWindowCenter", "v2f", struct.pack("<2f", 0.0, 0.0)) +
            attr("screenWindowWidth", "float", struct.pack("<f", 1.0)) + b"\0")
    line = 8 + 16 * w
    table = b"".join(struct.pack("<Q", len(head) + 8 * h + y * line) for y in range(h))
    body = bytearray()
    for y in range(h):
        body += struct.pack("<ii", y, 16 * w)
        for c in (3, 2, 1, 0):  # A B G R
            body += struct.pack("<%dI" % w, *(bits[(y * w + x) * 4 + c] for x in range(w)))
    with open(path(name), "wb") as f:
        f.write(head + table + bytes(body))
    return path(name)


def test_exr_tall_narrow():
    import random
    import exr_read
    w, h, n = 32, 864, 6
    rnd = random.Random(20261129)
    images, text = [], "lightgraph 1\n"
    for i in range(n):
        noise = (1 << rnd.randint(20, 24)) - 1
        bits = [struct.unpack("<I", struct.pack("<f", 0.25 + 0.5 * (k // 4 % w) / w))[0] ^
                (rnd.getrandbits(32) & noise) for k in range(w * h * 4)]
        images.append(bits)
        exr_none_float("in%d.exr" % i, w, h, bits)
        text += 'src%d = image { file = "in%d.exr" }\noutput src%d "out%d.exr"\n' % (i, i, i, i)
    run(["render", write("tall.lgraph", text)], expect=0)
    bad = []
    for i, bits in enumerate(images):
        rows = exr_read.read_exr(path("out%d.exr" % i))
        got = [struct.unpack("<I", struct.pack("<f", v))[0]
               for row in rows for px in row for v in px]
        diff = [k for k in range(len(bits)) if got[k] != bits[k]]
        if diff:
            bad.append("out%d.exr: %d values differ, rows %d-%d" %
                       (i, len(diff), diff[0] // 4 // w, diff[-1] // 4 // w))
    check(not bad, "; ".join(bad))


TESTS = {"max_pixels": test_max_pixels, "exr_precision": test_exr_precision,
         "special": test_special, "exr_tall_narrow": test_exr_tall_narrow}

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
