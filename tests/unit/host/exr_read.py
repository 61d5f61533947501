"""A reader for the EXR files lightgraph writes (scanline; compression none or ZIP; half,
float or uint channels), for the Python tests: independent of lightgraph's own reader."""
import struct
import zlib


class ExrError(Exception):
    pass


def _check(cond, msg):
    if not cond:
        raise ExrError(msg)


def half_to_float(h):
    return struct.unpack("<e", struct.pack("<H", h))[0]


def read_exr(path):
    """Rows of (r, g, b, a) float tuples, top row first."""
    with open(path, "rb") as f:
        data = f.read()
    _check(data[:4] == b"\x76\x2f\x31\x01", "%s: not an EXR file" % path)
    _check(data[5] & 0x02 == 0, "%s: tiled, not scanline" % path)
    pos, attrs = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        tend = data.index(b"\0", end + 1)
        size = struct.unpack_from("<i", data, tend + 1)[0]
        attrs[name] = data[tend + 5:tend + 5 + size]
        pos = tend + 5 + size
    pos += 1
    channels, c = [], attrs["channels"]
    i = 0
    while c[i] != 0:
        end = c.index(b"\0", i)
        ptype = struct.unpack_from("<i", c, end + 1)[0]
        channels.append((c[i:end].decode(), ptype))
        i = end + 17
    comp = attrs["compression"][0]
    _check(comp in (0, 3), "%s: compression %d is not none or zip" % (path, comp))
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    per_block = 16 if comp == 3 else 1
    nblocks = (h + per_block - 1) // per_block
    offsets = struct.unpack_from("<%dQ" % nblocks, data, pos)
    sizes = {0: 4, 1: 2, 2: 4}  # UINT, HALF, FLOAT
    line_bytes = sum(sizes[t] for _, t in channels) * w
    rows = [[[0.0, 0.0, 0.0, 1.0] for _ in range(w)] for _ in range(h)]
    index = {"R": 0, "G": 1, "B": 2, "A": 3}
    for off in offsets:
        y, n = struct.unpack_from("<ii", data, off)
        raw = data[off + 8:off + 8 + n]
        lines = min(per_block, y1 + 1 - y)
        if comp == 3 and n < line_bytes * lines:
            t = bytearray(zlib.decompress(raw))
            for k in range(1, len(t)):  # undo the predictor
                t[k] = (t[k - 1] + t[k] - 128) & 255
            half = (len(t) + 1) // 2  # undo the interleave
            u = bytearray(len(t))
            u[0::2] = t[:half]
            u[1::2] = t[half:]
            raw = bytes(u)
        p = 0
        for yy in range(y - y0, y - y0 + lines):
            for name, ptype in channels:  # channels in the file's (alphabetical) order
                for x in range(w):
                    if ptype == 2:  # FLOAT
                        v = struct.unpack_from("<f", raw, p)[0]
                        p += 4
                    elif ptype == 1:  # HALF
                        v = half_to_float(struct.unpack_from("<H", raw, p)[0])
                        p += 2
                    else:  # UINT
                        v = float(struct.unpack_from("<I", raw, p)[0])
                        p += 4
                    if name in index:
                        rows[yy][x][index[name]] = v
    return rows
