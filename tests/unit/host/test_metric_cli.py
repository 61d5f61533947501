#!/usr/bin/env python3
"""The shared error metrics (host/cli/metric.h, issue 23) through diff and sweep:

  diff    --json and the text carry rel_rmse, ssim and dssim; --max-error X checks the error
          --metric names (rel_rmse of an image scaled by 0.9 is 0.1: fails at 0.05, passes at
          0.2; dssim likewise), --metric alone or unknown is bad usage (2), an SSIM that is
          n/a (an image under 11x11) is printed so and fails --metric dssim with the reason
  sweep   the CSV's columns after today's: rel_rmse (exactly 1 - factor for a scaled
          image), ssim (1 at the reference's own settings, falling with the error, the value
          diff gives for the same image), dssim = 1 - ssim, time_max_ms >= time_ms >=
          time_min_ms, ref_ms the same on every row; a reference image (--reference
          REF.exr) gives the same metrics and an empty ref_ms; --metric picks the plotted
          column; --metric dssim on images under 11x11 fails naming the window, nothing
          written

The scene is a textured PNG written here (stdlib zlib), read by core's `image` node and
scaled by core's `scale`: the error of each run is known in closed form.

usage: test_metric_cli.py TEST_NAME   (meson runs each test as its own case)

Environment (tests/unit/host/meson.build): LG_EXE, LG_BUILD_ROOT.
"""
import csv
import json
import math
import os
import struct
import sys
import zlib

import lgrun
from lgrun import check, write

CORE = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
TMP = lgrun.temp_dir("lg-metric-cli-test-")


def run(args, expect=None, cwd=None):
    return lgrun.run(args, lgrun.env(CORE, os.path.join(TMP, "cache")), expect, cwd=cwd)


def png(path, w, h, fn):
    """An 8-bit RGB PNG of w x h whose pixel (x, y) is fn(x, y), three values in 0..255."""
    raw = b"".join(b"\0" + bytes(c for x in range(w) for c in fn(x, y)) for y in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
    return path


def texture(x, y):
    v = 120 + 60 * math.sin(x * 1.3) * math.cos(y * 0.9) + 2 * x
    return (int(v) & 255, int(0.8 * v) & 255, (40 + 3 * y) & 255)


def scene(d, w=32, h=24):
    """A graph: the texture, scaled by s.factor (default 1), into out.exr."""
    tex = png(os.path.join(d, "tex.png"), w, h, texture)
    return write(os.path.join(d, "g.lgraph"), """lightgraph 1
i = image { file = "%s" }
s = scale { image = i, factor = 1 }
output s "%s"
""" % (tex, os.path.join(d, "out.exr")))


def render(g, factor, path):
    run(["render", g, "--set", "s.factor=%s" % factor, "-o", path], expect=0)
    return path


def close(a, b, tol=1e-6):
    return abs(a - b) <= tol


def test_diff():
    d = lgrun.fresh_dir(TMP, "diff")
    g = scene(d)
    ref, a = render(g, 1, os.path.join(d, "ref.exr")), render(g, 0.9, os.path.join(d, "a.exr"))
    j = json.loads(run(["diff", a, ref, "--json"], expect=0).stdout)
    check(close(j["rel_rmse"], 0.1), "rel_rmse of a 0.9 scale: %s" % j)
    check(0.5 < j["ssim"] < 1.0 and close(j["dssim"], 1.0 - j["ssim"], 1e-8), "ssim: %s" % j)
    same = json.loads(run(["diff", ref, ref, "--json"], expect=0).stdout)
    check(same["ssim"] == 1 and same["dssim"] == 0 and same["rel_rmse"] == 0, "%s" % same)
    text = run(["diff", a, ref], expect=0).stdout
    check("rel RMSE   0.1\n" in text and "SSIM       %.6f (DSSIM" % j["ssim"] in text, text)
    # --max-error checks the metric --metric names (rmse without one)
    p = run(["diff", a, ref, "--metric", "rel_rmse", "--max-error", "0.05"], expect=1)
    check("lightgraph diff: rel_rmse 0.1 exceeds --max-error 0.05" in p.stderr, p.stderr)
    run(["diff", a, ref, "--metric=rel_rmse", "--max-error=0.2"], expect=0)
    p = run(["diff", a, ref, "--max-error", "%g" % (j["rmse"] / 2)], expect=1)
    check("rmse %.6g exceeds --max-error" % j["rmse"] in p.stderr, p.stderr)
    run(["diff", a, ref, "--max-error", "%g" % (j["rmse"] * 2)], expect=0)
    run(["diff", a, ref, "--metric", "dssim", "--max-error", "%g" % (j["dssim"] * 2)], expect=0)
    p = run(["diff", a, ref, "--metric", "dssim", "--max-error", "%g" % (j["dssim"] / 2),
             "--json"], expect=1)
    check(json.loads(p.stdout)["pass"] is False and "dssim" in p.stderr, p.stdout + p.stderr)
    # bad usage: --metric alone, an unknown metric
    p = run(["diff", a, ref, "--metric", "dssim"], expect=2)
    check("no --max-error is given" in p.stderr, p.stderr)
    p = run(["diff", a, ref, "--metric", "ssim", "--max-error", "0.1"], expect=2)
    check("--metric wants one of rmse, rel_rmse, mean_abs, max_abs, rel_mse, dssim, got 'ssim'"
          in p.stderr, p.stderr)
    # an SSIM that is n/a: printed as such, and a failure only where it is checked
    g8 = scene(lgrun.fresh_dir(TMP, "small"), 8, 6)
    s1, s2 = render(g8, 1, os.path.join(d, "s1.exr")), render(g8, 0.5, os.path.join(d, "s2.exr"))
    p = run(["diff", s2, s1], expect=0)
    check("SSIM       n/a (the images are smaller than SSIM's 11x11 window)" in p.stdout,
          p.stdout)
    check(json.loads(run(["diff", s2, s1, "--json"], expect=0).stdout)["ssim"] is None, "null")
    p = run(["diff", s2, s1, "--metric", "dssim", "--max-error", "1"], expect=1)
    check("dssim is n/a (the images are smaller than SSIM's 11x11 window), so --max-error 1 "
          "cannot be checked" in p.stderr, p.stderr)


def test_sweep():
    d = lgrun.fresh_dir(TMP, "sweep")
    g = scene(d)
    out = lgrun.fresh_dir(d, "sw")
    p = run(["sweep", g, "--vary", "s.factor=0.5,0.9,1", "--ref-set", "s.factor=1", "--time",
             "s", "--repeat", "3", "-o", out], expect=0)
    rows = list(csv.DictReader(open(os.path.join(out, "sweep.csv"))))
    head = open(os.path.join(out, "sweep.csv")).readline().strip()
    check(head == "run,s.factor,time_ms,time_min_ms,rmse,psnr_db,mean_abs,max_abs,rel_mse,"
          "nonfinite,rel_rmse,ssim,dssim,time_max_ms,ref_ms", head)
    check(len(rows) == 3, "%s" % rows)
    ssim = [float(r["ssim"]) for r in rows]
    for r, f in zip(rows, (0.5, 0.9, 1.0)):
        check(close(float(r["rel_rmse"]), 1 - f), "rel_rmse of factor %s: %s" % (f, r))
        check(close(float(r["dssim"]), 1 - float(r["ssim"]), 1e-8), "dssim: %s" % r)
        check(float(r["time_min_ms"]) <= float(r["time_ms"]) <= float(r["time_max_ms"]),
              "timings: %s" % r)
        check(r["ref_ms"] == rows[0]["ref_ms"] and float(r["ref_ms"]) > 0, "ref_ms: %s" % r)
    check(ssim[2] == 1.0 and ssim[0] < ssim[1] < 1.0, "ssim by factor: %s" % ssim)
    # the same number diff gives for the same image
    j = json.loads(run(["diff", os.path.join(out, "run-001.exr"),
                        os.path.join(out, "reference.exr"), "--json"], expect=0).stdout)
    check(close(j["ssim"], ssim[1], 1e-8) and close(j["rel_rmse"], 0.1), "diff: %s" % j)
    check("rel_rmse 0.1  ssim %.4f" % ssim[1] in p.stdout, p.stdout)
    gp = open(os.path.join(out, "sweep.gp")).read()
    check("set ylabel 'RMSE against the reference'" in gp and "using 3:($5 > 0" in gp, gp)
    # a reference image: the same metrics, no reference time; the plot of --metric dssim
    out2 = lgrun.fresh_dir(d, "sw2")
    run(["sweep", g, "--vary", "s.factor=0.5,0.9,1", "--reference",
         os.path.join(out, "reference.exr"), "--repeat", "1", "--metric", "dssim", "-o", out2],
        expect=0)
    rows2 = list(csv.DictReader(open(os.path.join(out2, "sweep.csv"))))
    check([r["ssim"] for r in rows2] == [r["ssim"] for r in rows], "%s" % rows2)
    check(all(r["ref_ms"] == "" for r in rows2), "ref_ms of an image: %s" % rows2)
    gp = open(os.path.join(out2, "sweep.gp")).read()
    check("set ylabel 'DSSIM (1 - SSIM) against the reference'" in gp and
          "using 3:($13 > 0" in gp, gp)
    p = run(["sweep", g, "--vary", "s.factor=1", "--reference",
             os.path.join(out, "reference.exr"), "--ref-set", "s.factor=1", "-o", out2], expect=2)
    check("is an image, which has no parameters to set; nothing was run" in p.stderr, p.stderr)
    p = run(["sweep", g, "--vary", "s.factor=1", "--metric", "psnr", "-o", out2], expect=2)
    check("--metric wants one of" in p.stderr, p.stderr)
    # --metric dssim where there is no SSIM: an error naming why, nothing written
    g8 = scene(lgrun.fresh_dir(TMP, "small"), 8, 6)
    out3 = lgrun.fresh_dir(d, "sw3")
    p = run(["sweep", g8, "--vary", "s.factor=0.5", "--ref-set", "s.factor=1", "--repeat", "1",
             "--metric", "dssim", "-o", out3], expect=1)
    check("run 0: --metric dssim: the image is 8x6, smaller than SSIM's 11x11 window" in
          p.stderr, p.stderr)
    check(os.listdir(out3) == [], "files left: %s" % os.listdir(out3))
    run(["sweep", g8, "--vary", "s.factor=0.5", "--ref-set", "s.factor=1", "--repeat", "1",
         "-o", out3], expect=0)
    row = list(csv.DictReader(open(os.path.join(out3, "sweep.csv"))))[0]
    check(row["ssim"] == "" and row["dssim"] == "" and close(float(row["rel_rmse"]), 0.5),
          "an image under the window: %s" % row)


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
