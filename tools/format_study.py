#!/usr/bin/env python3
"""format_study.py: what HDR precision costs (issue 9, item 3; lightgraph/image.h "Pixel formats").

usage: tools/format_study.py GRAPH NODE [--size WxH] [--repeat N] [--frames K] [--out DIR]
                             [--floor L] [--build DIR] [--set NODE.PARAM=V]...
                             [--formats rgba32f,rgba16f,rgbe8]

Renders GRAPH once per format with NODE.format = rgba32f, rgba16f, rgbe8 (NODE must have a
`format` parameter with those values) and reports, per format:

  node_ms      NODE's CPU wall time per frame (it includes its GL work: docs/devices.md),
               steady state: the run of `--frames K --every-frame` whose time is least
               (min_cpu_ms of --profile-json, which leaves shader compilation and first-use
               set-up out), median over --repeat renders
  frame_ms     the same for the whole frame: the sum over the graph's kept nodes
  bytes_px     bytes per pixel of NODE's output (16, 8, 4)
  mean_rel,    the relative error of NODE's output (written as a float EXR) against the
  max_rel      rgba32f render, |c - c32| / L32 per RGB channel, mean and maximum over the
               pixels whose rgba32f luminance L32 (Rec. 709) is above --floor (default 1e-4
               of the image's mean luminance), so that black pixels do not divide by 0
  clamped      the pixels whose rgba16f value is not within 1% of rgba32f (a clamp above
               65504 shows here)
  psnr_db      for each PNG output of the graph (the tone-mapped image), the PSNR of its
               8-bit sRGB values against the rgba32f render's, peak 255, over RGB

The runs are separate renders (`lightgraph render --set NODE.format=F --profile-json`), of a
copy of GRAPH written beside it (so that its relative paths resolve as before, removed at the
end) whose output statements write into DIR, plus `output NODE "DIR/NODE_F.exr" float`.
Nothing the graph itself names is overwritten.

Writes into DIR (default out/format_study, created): format_study.csv, format_study.md
(a markdown table), format_study.gp and format_study.png (gnuplot: error against time), and
the renders (NODE_F.exr, F_<png name>). EXR (scanline; NONE, ZIPS, ZIP; half or float) and
PNG (8-bit, non-interlaced) are read here in pure Python, independently of lightgraph's
readers.
"""
import argparse
import json
import math
import os
import re
import statistics
import struct
import subprocess
import sys
import tempfile
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FORMATS = ["rgba32f", "rgba16f", "rgbe8"]
BYTES = {"rgba32f": 16, "rgba16f": 8, "rgbe8": 4}


# ---- EXR (scanline; NONE, ZIPS, ZIP; half, float) -------------------------------------------

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


# ---- PNG (8-bit grey, RGB, RGBA; not interlaced): what lightgraph writes ---------------------

def read_png(path):
    """Returns (width, height, channels, bytes of the 8-bit samples, row-major)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("%s: not a PNG file" % path)
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        ln, typ = struct.unpack_from(">I4s", data, pos)
        body = data[pos + 8:pos + 8 + ln]
        if typ == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif typ == b"IDAT":
            idat += body
        pos += 12 + ln
    w, h, depth, ctype, _, _, interlace = hdr
    if depth != 8 or interlace or ctype not in (0, 2, 6):
        raise ValueError("%s: only 8-bit non-interlaced grey, RGB or RGBA is read here" % path)
    ch = {0: 1, 2: 3, 6: 4}[ctype]
    raw = zlib.decompress(idat)
    stride = w * ch
    out = bytearray(h * stride)
    prev = bytearray(stride)
    p = 0
    for y in range(h):
        ft = raw[p]
        line = bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for i in range(stride):
            a = line[i - ch] if i >= ch else 0
            b = prev[i]
            c = prev[i - ch] if i >= ch else 0
            if ft == 1:
                line[i] = (line[i] + a) & 0xFF
            elif ft == 2:
                line[i] = (line[i] + b) & 0xFF
            elif ft == 3:
                line[i] = (line[i] + (a + b) // 2) & 0xFF
            elif ft == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 0xFF
        out[y * stride:(y + 1) * stride] = line
        prev = line
    return w, h, ch, bytes(out)


def psnr_png(a, b):
    wa, ha, ca, da = read_png(a)
    wb, hb, cb, db = read_png(b)
    if (wa, ha, ca) != (wb, hb, cb):
        raise ValueError("%s and %s differ in size or channels" % (a, b))
    se, n = 0, 0
    for i in range(0, len(da), ca):
        for c in range(min(3, ca)):
            d = da[i + c] - db[i + c]
            se += d * d
            n += 1
    mse = se / n
    return math.inf if mse == 0 else 10 * math.log10(255.0 ** 2 / mse)


# ---- errors ----------------------------------------------------------------------------------

def rel_errors(ref, img, floor_rel):
    """Mean and max relative error of img against ref (read_exr results) over the pixels
    whose reference luminance is above floor_rel times the mean luminance; and the count of
    pixels off by more than 1%."""
    w, h, r = ref
    w2, h2, t = img
    if (w, h) != (w2, h2):
        raise ValueError("the renders differ in size")
    lum = [0.2126 * r["R"][i] + 0.7152 * r["G"][i] + 0.0722 * r["B"][i] for i in range(w * h)]
    finite = [v for v in lum if math.isfinite(v)]
    floor = floor_rel * (sum(finite) / len(finite) if finite else 0)
    s, n, mx, off = 0.0, 0, 0.0, 0
    for i in range(w * h):
        L = lum[i]
        if not (L > floor) or not math.isfinite(L):
            continue
        worst = 0.0
        for c in "RGB":
            e = abs(t[c][i] - r[c][i]) / L
            if not math.isfinite(e):
                e = math.inf
            s += e
            n += 1
            worst = max(worst, e)
        mx = max(mx, worst)
        off += worst > 0.01
    return (s / n if n else 0.0), mx, off, n // 3


# ---- running ---------------------------------------------------------------------------------

OUTPUT_RE = re.compile(r'^(\s*output\s+)(\S+)(\s+)"((?:[^"\\]|\\.)*)"(.*)$')


def study_graph(graph, node, outdir, fmt):
    """The graph's text with its output statements writing into outdir (F_<name>), plus
    NODE's output as a float EXR. Returns (text, {png name in outdir: original name})."""
    lines, pngs = [], {}
    with open(graph) as f:
        for line in f:
            m = OUTPUT_RE.match(line.rstrip("\n"))
            if m:
                name = os.path.basename(m.group(4))
                dest = os.path.join(outdir, "%s_%s" % (fmt, name))
                if name.lower().endswith(".png"):
                    pngs[name] = dest
                line = '%s%s%s"%s"%s\n' % (m.group(1), m.group(2), m.group(3), dest, m.group(5))
            lines.append(line)
    if lines and not lines[-1].endswith("\n"):
        lines[-1] += "\n"
    lines.append('output %s "%s" float\n' % (node, os.path.join(outdir, "%s_%s.exr" % (node, fmt))))
    return "".join(lines), pngs


def run_render(exe, graph_copy, args, fmt, prof):
    cmd = [exe, "render", graph_copy, "--set", "%s.format=%s" % (args.node, fmt),
           "--frames", str(args.frames), "--every-frame", "--profile-json", prof]
    if args.size:
        cmd += ["--size", args.size]
    for s in args.set or []:
        cmd += ["--set", s]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write("format_study: %s failed (exit %d):\n%s%s" %
                         (" ".join(cmd), r.returncode, r.stdout, r.stderr))
        sys.exit(1)
    with open(prof) as f:
        p = json.load(f)
    node_ms, frame_ms = None, 0.0
    for n in p["nodes"]:
        if n["state"] != "kept":
            continue
        frame_ms += n["min_cpu_ms"]
        if n["name"] == args.node:
            node_ms = n["min_cpu_ms"]
    if node_ms is None:
        sys.stderr.write("format_study: node '%s' did not run in %s (gated or culled?)\n" %
                         (args.node, args.graph))
        sys.exit(1)
    return node_ms, frame_ms, r.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("graph")
    ap.add_argument("node")
    ap.add_argument("--size", help="WxH, as lightgraph render --size")
    ap.add_argument("--repeat", type=int, default=3, help="renders per format (median time)")
    ap.add_argument("--frames", type=int, default=3,
                    help="frames per render, every node every frame; the least time counts")
    ap.add_argument("--out", default=os.path.join("out", "format_study"))
    ap.add_argument("--floor", type=float, default=1e-4,
                    help="pixels darker than this times the mean luminance are not compared")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--set", action="append", help="NODE.PARAM=V for every render")
    ap.add_argument("--formats", default=",".join(FORMATS),
                    help="the formats, the first being the reference (rgba32f)")
    args = ap.parse_args()
    if args.repeat < 1 or args.frames < 2:
        ap.error("--repeat must be at least 1 and --frames at least 2")
    formats = args.formats.split(",")
    exe = os.path.join(args.build, "lightgraph")
    if not os.access(exe, os.X_OK):
        ap.error("no lightgraph at %s (build first, or --build DIR)" % exe)
    if not os.path.isfile(args.graph):
        ap.error("no graph file %s" % args.graph)
    os.makedirs(args.out, exist_ok=True)
    outdir = os.path.abspath(args.out)
    gdir = os.path.dirname(os.path.abspath(args.graph))

    rows = []
    pngs_of = {}
    for fmt in formats:
        text, pngs = study_graph(args.graph, args.node, outdir, fmt)
        pngs_of[fmt] = pngs
        fd, copy = tempfile.mkstemp(prefix=".format_study_", suffix=".lgraph", dir=gdir)
        try:
            with os.fdopen(fd, "w") as f:
                f.write(text)
            times, frames, warnings = [], [], ""
            for k in range(args.repeat):
                prof = os.path.join(outdir, "profile_%s.json" % fmt)
                t, fr, err = run_render(exe, copy, args, fmt, prof)
                times.append(t)
                frames.append(fr)
                warnings = warnings or err
        finally:
            os.unlink(copy)
        rows.append({"format": fmt, "node_ms": statistics.median(times),
                     "frame_ms": statistics.median(frames), "bytes_px": BYTES.get(fmt, 0),
                     "warning": " ".join(w.strip() for w in warnings.splitlines()
                                         if "warning: node '%s'" % args.node in w)})
        print("%-8s %s: %.3f ms, frame %.3f ms" % (fmt, args.node, rows[-1]["node_ms"],
                                                   rows[-1]["frame_ms"]))

    ref = read_exr(os.path.join(outdir, "%s_%s.exr" % (args.node, formats[0])))
    for row in rows:
        img = read_exr(os.path.join(outdir, "%s_%s.exr" % (args.node, row["format"])))
        row["mean_rel"], row["max_rel"], row["clamped"], row["compared"] = \
            rel_errors(ref, img, args.floor)
        ps = []
        for name, dest in sorted(pngs_of[row["format"]].items()):
            ps.append(psnr_png(pngs_of[formats[0]][name], dest))
        row["psnr_db"] = min(ps) if ps else None

    cols = ["format", "bytes_px", "node_ms", "frame_ms", "mean_rel", "max_rel", "clamped",
            "compared", "psnr_db"]
    with open(os.path.join(outdir, "format_study.csv"), "w") as f:
        f.write(",".join(cols) + "\n")
        for r in rows:
            f.write(",".join("" if r[c] is None else (("%.6g" % r[c]) if isinstance(r[c], float)
                                                       else str(r[c])) for c in cols) + "\n")

    def psnr_text(v):
        return "-" if v is None else ("inf" if math.isinf(v) else "%.1f" % v)

    with open(os.path.join(outdir, "format_study.md"), "w") as f:
        f.write("Format study: `%s`, node `%s`%s; %d render(s) per format, least of %d "
                "frames each; errors against %s over %d pixels (luminance above %g of the "
                "mean).\n\n" % (os.path.basename(args.graph), args.node,
                                 (", " + args.size) if args.size else "", args.repeat,
                                 args.frames, formats[0], rows[0]["compared"], args.floor))
        f.write("| format | bytes/px | %s ms | frame ms | mean rel. error | max rel. error | "
                "pixels off > 1%% | PSNR of the PNG (dB) |\n" % args.node)
        f.write("|---|---:|---:|---:|---:|---:|---:|---:|\n")
        for r in rows:
            f.write("| %s | %d | %.3f | %.3f | %.3g | %.3g | %d | %s |\n" %
                    (r["format"], r["bytes_px"], r["node_ms"], r["frame_ms"], r["mean_rel"],
                     r["max_rel"], r["clamped"], psnr_text(r["psnr_db"])))
        for r in rows:
            if r["warning"]:
                f.write("\n%s: %s\n" % (r["format"], r["warning"]))

    # gnuplot: mean relative error (log) against the node's time; rgba32f has 0 error
    gp = os.path.join(outdir, "format_study.gp")
    dat = os.path.join(outdir, "format_study.dat")
    with open(dat, "w") as f:
        for r in rows:
            f.write("%s %.6g %.6g %.6g\n" % (r["format"], r["node_ms"],
                                             max(r["mean_rel"], 1e-9), max(r["max_rel"], 1e-9)))
    with open(gp, "w") as f:
        f.write('set terminal pngcairo size 720,480\nset output "%s"\n'
                'set title "%s: %s output format, error against time" noenhanced\n'
                'set xlabel "%s ms per frame"\nset ylabel "relative error vs rgba32f (1e-9 = exact)"\n'
                'set logscale y\nset key bottom right\nset offsets graph 0.1, graph 0.1, graph 0.1, graph 0.1\n'
                'plot "%s" using 2:3 with points pt 7 ps 1.5 title "mean", '
                '"" using 2:4 with points pt 5 ps 1.5 title "max", '
                '"" using 2:3:1 with labels offset 1,1 notitle\n' %
                (os.path.join(outdir, "format_study.png"), os.path.basename(args.graph),
                 args.node, args.node, dat))
    r = subprocess.run(["gnuplot", gp], capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write("format_study: gnuplot failed:\n%s" % r.stderr)
        sys.exit(1)
    with open(os.path.join(outdir, "format_study.md")) as f:
        sys.stdout.write(f.read())
    return 0


if __name__ == "__main__":
    sys.exit(main())
