#!/usr/bin/env python3
"""Prints texels of a PNG decoded with Python's zlib alone (no libpng): the independent
values test_gltf_textures.c compares the loader's decoded images with.

    python3 tests/plugins/scene_gltf/png_texels.py FILE.png X,Y [X,Y ...]

prints "WxH colour-type bit-depth" and one "x y r g b a" line per texel, RGBA as the loader
stores it (grey copied to RGB, alpha 255 where the file has none; 8-bit, non-interlaced
files only: the shipped textures)."""
import struct
import sys
import zlib


def decode(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    at, idat, plte, trns = 8, b"", None, None
    while at < len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"PLTE":
            plte = body
        elif kind == b"tRNS":
            trns = body
        at += 12 + n
    assert depth == 8 and interlace == 0, "8-bit non-interlaced only"
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[ctype]
    raw = zlib.decompress(idat)
    stride = w * channels
    rows, prev, pos = [], bytearray(stride), 0
    for _ in range(h):
        f = raw[pos]
        line = bytearray(raw[pos + 1:pos + 1 + stride])
        pos += 1 + stride
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pr = a if pa <= pb and pa <= pc else b if pb <= pc else c
                line[i] = (line[i] + pr) & 255
        rows.append(line)
        prev = line

    def texel(x, y):
        px = rows[y][x * channels:(x + 1) * channels]
        if ctype == 0:
            return (px[0], px[0], px[0], 255)
        if ctype == 4:
            return (px[0], px[0], px[0], px[1])
        if ctype == 2:
            return (px[0], px[1], px[2], 255)
        if ctype == 3:
            i = px[0]
            alpha = trns[i] if trns and i < len(trns) else 255
            return (plte[3 * i], plte[3 * i + 1], plte[3 * i + 2], alpha)
        return tuple(px)

    return w, h, ctype, depth, texel


def main():
    w, h, ctype, depth, texel = decode(sys.argv[1])
    print(f"{w}x{h} {ctype} {depth}")
    for arg in sys.argv[2:]:
        x, y = (int(v) for v in arg.split(","))
        print(x, y, *texel(x, y))


if __name__ == "__main__":
    main()
