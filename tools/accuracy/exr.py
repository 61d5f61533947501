"""exr.py: an OpenEXR reader for the accuracy atlas (scanline; NONE, ZIPS, ZIP; half, float),
enough for what lightgraph writes. Taken from tools/format_study.py, whose study the atlas
folds in; plain Python."""
import struct
import zlib


def read_exr(path):
    """Returns (width, height, {channel: [values, row-major]})."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("%s: not an OpenEXR file" % path)
    if struct.unpack_from("<I", data, 4)[0] & 0x200:
        raise ValueError("%s: tiled EXR is not read here" % path)
    pos = 8
    attrs = {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        end2 = data.index(b"\0", end + 1)
        typ = data[end + 1:end2].decode()
        size = struct.unpack_from("<i", data, end2 + 1)[0]
        attrs[name] = (typ, data[end2 + 5:end2 + 5 + size])
        pos = end2 + 5 + size
    pos += 1
    chl = attrs["channels"][1]
    chans = []
    p = 0
    while chl[p] != 0:
        e = chl.index(b"\0", p)
        cname = chl[p:e].decode()
        ptype = struct.unpack_from("<i", chl, e + 1)[0]
        chans.append((cname, ptype))
        p = e + 1 + 16
    chans.sort()
    comp = attrs["compression"][1][0]
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    lines = {0: 1, 2: 1, 3: 16}.get(comp)
    if lines is None:
        raise ValueError("%s: compression %d is not read here (NONE, ZIPS, ZIP are)" % (path, comp))
    nblocks = (h + lines - 1) // lines
    offsets = struct.unpack_from("<%dQ" % nblocks, data, pos)
    out = {c: [0.0] * (w * h) for c, _ in chans}
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        raw = data[off + 8:off + 8 + size]
        n_lines = min(lines, y1 + 1 - y)
        expect = n_lines * w * sum(2 if t == 1 else 4 for _, t in chans)
        if comp != 0 and size < expect:
            t = bytearray(zlib.decompress(raw))
            for i in range(1, len(t)):  # predictor
                t[i] = (t[i - 1] + t[i] - 128) & 0xFF
            half = (len(t) + 1) // 2
            raw = bytearray(len(t))
            raw[0::2] = t[:half]
            raw[1::2] = t[half:]
            raw = bytes(raw)
        q = 0
        for ln in range(n_lines):
            row = (y - y0 + ln) * w
            for cname, t in chans:
                fmt, sz = ("<%de" % w, 2) if t == 1 else ("<%df" % w, 4)
                vals = struct.unpack_from(fmt, raw, q)
                out[cname][row:row + w] = vals
                q += sz * w
    return w, h, out

