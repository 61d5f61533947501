#!/usr/bin/env python3
"""fake_study.py OUT CSV KIND [--quick]: a Custom study's program for the generator's
self-test: writes OUT/CSV with known rows (KIND: 'a' or 'b'), or fails with a message on
stderr (KIND 'fail'). Each row has a tiny PNG as its image and heat map."""
import os
import struct
import sys
import zlib


def png(path, rgb):
    """A 2x2 RGB PNG of one colour."""
    raw = b"".join(b"\0" + bytes(rgb) * 2 for _ in range(2))

    def chunk(t, d):
        c = struct.pack(">I", len(d)) + t + d
        return c + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


# knob, time_ms, rel_rmse. Section sec_a has both: its front is a's 1, 2 and 4 (a's 3 and
# b's x are dominated by a's 2, b's y by a's 4); section sec_b has b alone: x and y
ROWS = {
    "a": [("1", 1.0, 0.5), ("2", 2.0, 0.05), ("3", 3.0, 0.06), ("4", 8.0, 0.004)],
    "b": [("x", 2.5, 0.05), ("y", 20.0, 0.004)],  # x: dominated by a2; y: by a4
}


def main():
    out, name, kind = sys.argv[1], sys.argv[2], sys.argv[3]
    if kind == "fail":
        sys.stderr.write("fake_study: the oracle melted (quick=%s)\n" % ("--quick" in sys.argv))
        return 3
    png(os.path.join(out, "ref.png"), (200, 200, 200))
    with open(os.path.join(out, name), "w") as f:
        f.write("fake.knob,time_ms,time_min_ms,time_max_ms,rmse,rel_rmse,ssim,dssim,ref_ms,"
                "image,heat\n")
        for i, (k, t, e) in enumerate(ROWS[kind]):
            png(os.path.join(out, "img%d.png" % i), (10 * i, 50, 90))
            png(os.path.join(out, "heat%d.png" % i), (255, 0, 0))
            f.write("%s,%g,%g,%g,%g,%g,,,%g,img%d.png,heat%d.png\n"
                    % (k, t, t * 0.9, t * 1.2, e / 2, e, 4200.0, i, i))
    return 0


if __name__ == "__main__":
    sys.exit(main())
