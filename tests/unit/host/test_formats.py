#!/usr/bin/env python3
"""The HDR precision formats through the real program (lightgraph/image.h "Pixel formats",
docs/images.md), with the test plugin testformats (test_hdr: a known HDR pattern in any
format; test_copy: a byte copy on cpu, gl or cl):

  roundtrip        an rgbe8 image moved cpu -> gl -> cl -> cpu -> cl -> gl -> cpu by byte
                   copies keeps its bytes: its float EXR output equals the producer's bit
                   for bit, its .hdr output reads back the same values (`lightgraph diff
                   --max-abs 0`), its PNG output equals the producer's PNG; --explain and the
                   profile name the format rgbe8
  rgbe_precision   the rgbe8 image written as float EXR is within half a mantissa step of
                   the rgba32f one in every channel (|c - c32| <= max(R, G, B) / 256), and
                   not equal to it (RGBE rounds); an rgbe8 EXR output is float by default
  half_policy      rgba16f: a sun of 1e6 reads 65504 (never Inf) and NaN reads 0; the node
                   reports it once, with the count, over 3 frames
  reinhard         reinhard of the rgbe8 image equals reinhard of the rgba32f one within
                   RGBE's precision (max abs 0.015 on [0, 1]: a channel at a quarter of the
                   pixel's largest carries up to 1.6% error, times c / L; mean below 2e-3),
                   on cpu, gl and cl; and the three backends agree on the rgbe8 input within
                   1e-5
  core             core's add and scale take rgbe8 (decoded) and agree with rgba32f within
                   RGBE's precision; rgba8 is refused, naming the node, input and format
  accuracy_probe   the accuracy atlas's probe section (tools/accuracy/sections/probe.py, which
                   retired tools/format_study.py) with --quick: its page and CSVs are made;
                   against rgba32f, rgba32f has error 0, rgba16f below 1e-3 and rgbe8 below
                   0.7% (half a mantissa step) on the forest probe, and 2^12 brighter rgba16f
                   errs more than rgbe8 (the sun clamped at 65504)
  keyword_colour   a colour parameter that also takes keywords (ABI 2.3; test_fill's
                   `color = checker | [r, g, b]`): inspect (text and --json) shows the
                   keyword default and list, the default renders the checker, a colour from
                   the file or --set renders that colour, [0, 0, 0] after checker is not
                   mistaken for it, a misspelt word and an out-of-range colour are refused

usage: test_formats.py TEST_NAME
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys

import lgrun
from lgrun import Fail, check

TEST_PLUGINS = os.environ["LG_TEST_PLUGINS"]
BUILD = os.environ["LG_BUILD_ROOT"]
SOURCE = os.environ["LG_SOURCE_ROOT"]
TMP = lgrun.temp_dir("lg-formats-test-")
sys.path.insert(0, os.path.join(SOURCE, "tools"))
from accuracy.exr import read_exr  # noqa: E402  (an EXR reader independent of lightgraph's)


def run(args, expect=0):
    env = lgrun.env(TEST_PLUGINS + ":" + os.path.join(BUILD, "plugins"), os.path.join(TMP, "cache"))
    return lgrun.run(args, env, expect, cwd=TMP)


def graph(text, name="g.lgraph"):
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write("lightgraph 1\n" + text)
    return path


def exr(name):
    return read_exr(os.path.join(TMP, name))


def bits_equal(a, b):
    wa, ha, ca = a
    wb, hb, cb = b
    check((wa, ha) == (wb, hb), "sizes differ")
    for c in "RGBA":
        for i, (x, y) in enumerate(zip(ca[c], cb[c])):
            if not (x == y or (math.isnan(x) and math.isnan(y))):
                raise Fail("channel %s pixel %d: %r vs %r" % (c, i, x, y))


HDR = 'hdr = test_hdr { format = %s, width = 37, height = 23, peak = %s, nan = true }\n'


def t_roundtrip():
    g = graph(HDR % ("rgbe8", "1e6") +
              "g1 = test_copy { image = hdr, backend = gl }\n"
              "c1 = test_copy { image = g1, backend = cl }\n"
              "p1 = test_copy { image = c1, backend = cpu }\n"
              "c2 = test_copy { image = p1, backend = cl }\n"
              "g2 = test_copy { image = c2, backend = gl }\n"
              "p2 = test_copy { image = g2, backend = cpu }\n"
              'output hdr "src.exr"\noutput p2 "chain.exr"\noutput p2 "chain.hdr"\n'
              'output hdr "src.png"\noutput p2 "chain.png"\n')
    p = run(["render", g, "--explain", "--profile"])
    check("37x23 rgbe8 (3.3 KiB)" in p.stdout + p.stderr,
          "--explain does not name rgbe8:\n" + p.stdout + p.stderr)
    for dev in ("gl", "cl"):
        check(any(l.split()[:3] == ["g1" if dev == "gl" else "c1", "test_copy", dev]
                  for l in (p.stdout + p.stderr).splitlines()),
              "the copy did not run on %s:\n%s" % (dev, p.stdout + p.stderr))
    src, chain = exr("src.exr"), exr("chain.exr")
    bits_equal(src, chain)
    # the sun is kept (RGBE's range), the NaN is 0, alpha is 1
    check(abs(src[2]["R"][0] - 1e6) <= 1e6 / 256, "sun %r" % src[2]["R"][0])
    check(src[2]["R"][1] == 0 and src[2]["A"][5] == 1.0, "NaN or alpha")
    d = run(["diff", os.path.join(TMP, "chain.hdr"), os.path.join(TMP, "src.exr"),
             "--max-abs", "0"], expect=None)
    check(d.returncode == 0, "chain.hdr differs from src.exr:\n" + d.stdout + d.stderr)
    with open(os.path.join(TMP, "src.png"), "rb") as a, open(os.path.join(TMP, "chain.png"), "rb") as b:
        check(a.read() == b.read(), "the PNG outputs differ")
    print("rgbe8 through gl, cl, cpu, cl, gl, cpu: bytes unchanged (EXR bit for bit, HDR, PNG)")


def t_rgbe_precision():
    g = graph(HDR % ("rgbe8", "0") + 'output hdr "e.exr"\n', "e.lgraph")
    run(["render", g])
    g = graph(HDR % ("rgba32f", "0") + 'output hdr "f.exr"\n', "f.lgraph")
    run(["render", g])
    e, f = exr("e.exr"), exr("f.exr")
    w, h, ce = e
    cf = f[2]
    differ = 0
    for i in range(w * h):
        if i == 1:
            continue  # the NaN pixel
        m = max(cf["R"][i], cf["G"][i], cf["B"][i])
        for c in "RGB":
            err = abs(ce[c][i] - cf[c][i])
            check(err <= m / 256, "pixel %d %s: rgbe8 %r, rgba32f %r (max %r)" %
                  (i, c, ce[c][i], cf[c][i], m))
            differ += err > 0
    check(differ > w * h, "rgbe8 equals rgba32f almost everywhere: RGBE did not round?")
    # float EXR by default for rgbe8 (half would turn its range into Inf): read the type
    with open(os.path.join(TMP, "e.exr"), "rb") as fh:
        data = fh.read()
    k = data.index(b"channels\0chlist\0")
    check(data[k + 16 + 4 + 2:k + 16 + 4 + 6] == b"\x02\x00\x00\x00",
          "rgbe8 output EXR is not float32")
    print("rgbe8 within half a step (max/256) of rgba32f in %d x 3 channels, %d rounded" %
          (w * h - 1, differ))


def t_half_policy():
    g = graph(HDR % ("rgba16f", "1e6") + 'output hdr "h.exr" float\n', "h.lgraph")
    p = run(["render", g, "--frames", "3", "--every-frame"])
    img = exr("h.exr")[2]
    check(img["R"][0] == 65504.0 and img["G"][0] == 65504.0 and img["B"][0] == 65504.0,
          "sun in rgba16f: %r %r %r, want 65504 (never Inf)" %
          (img["R"][0], img["G"][0], img["B"][0]))
    check(img["R"][1] == 0.0, "NaN in rgba16f reads %r, want 0" % img["R"][1])
    check(all(math.isfinite(v) for c in "RGBA" for v in img[c]), "a non-finite value")
    warns = [l for l in p.stderr.splitlines() if "values it cannot hold" in l]
    check(len(warns) == 1, "want one report over 3 frames, got:\n" + p.stderr)
    check("rgba16f output, frame 0: 4 values" in warns[0], "report: " + warns[0])
    print("rgba16f: sun 1e6 -> 65504, NaN -> 0, reported once: " + warns[0].split(": ", 1)[1])


def t_reinhard():
    per_backend = {}
    for be in ("cpu", "gl", "cl"):
        outs = {}
        for fmt in ("rgba32f", "rgbe8"):
            g = graph(HDR % (fmt, "0") + "tone = reinhard { image = hdr, backend = %s }\n"
                      'output tone "t_%s_%s.exr"\n' % (be, be, fmt), "r_%s_%s.lgraph" % (be, fmt))
            run(["render", g])
            outs[fmt] = os.path.join(TMP, "t_%s_%s.exr" % (be, fmt))
        per_backend[be] = outs["rgbe8"]
        d = run(["diff", outs["rgbe8"], outs["rgba32f"], "--json", "--max-abs", "0.015"],
                expect=None)
        check(d.returncode == 0, "reinhard %s: rgbe8 vs rgba32f beyond 0.01:\n%s%s" %
              (be, d.stdout, d.stderr))
        a, b = read_exr(outs["rgbe8"]), read_exr(outs["rgba32f"])
        w, h = a[0], a[1]
        errs = [abs(a[2][c][i] - b[2][c][i]) for i in range(w * h) if i != 1 for c in "RGB"]
        mean = sum(errs) / len(errs)
        check(0 < mean < 2e-3, "reinhard %s: mean abs %g (want 0 < mean < 2e-3)" % (be, mean))
        print("reinhard %s: rgbe8 vs rgba32f input: max abs %.3g, mean abs %.3g" %
              (be, max(errs), mean))
    for be in ("gl", "cl"):
        d = run(["diff", per_backend[be], per_backend["cpu"], "--max-abs", "1e-5"], expect=None)
        check(d.returncode == 0, "reinhard on rgbe8: %s vs cpu beyond 1e-5:\n%s%s" %
              (be, d.stdout, d.stderr))
        print("reinhard on rgbe8: %s vs cpu: %s" % (be, d.stdout.strip().splitlines()[-1]))


def t_core():
    for fmt in ("rgba32f", "rgbe8"):
        g = graph(HDR % (fmt, "0") + "s = scale { image = hdr, factor = 2 }\n"
                  "a = add { a = hdr, b = s }\n" 'output a "core_%s.exr"\n' % fmt,
                  "core_%s.lgraph" % fmt)
        run(["render", g])
    a, b = exr("core_rgbe8.exr"), exr("core_rgba32f.exr")
    w, h = a[0], a[1]
    for i in range(w * h):
        if i == 1:
            continue
        m = max(b[2]["R"][i], b[2]["G"][i], b[2]["B"][i])
        for c in "RGB":
            # output 3x; input error <= max/256 per channel, so output error <= m/256
            check(abs(a[2][c][i] - b[2][c][i]) <= m / 256 * 1.0001,
                  "core add(x, 2x) pixel %d %s: %r vs %r" % (i, c, a[2][c][i], b[2][c][i]))
    # rgba8 is refused with the node, the input and the format named
    g = graph(HDR % ("rgba8", "0") + "s = scale { image = hdr }\n"
              "t = reinhard { image = hdr }\n" 'output s "r8.exr"\noutput t "r8t.exr"\n',
              "r8.lgraph")
    p = run(["render", g], expect=1)
    check("input 'image' is rgba8 (display-encoded)" in p.stderr and "'s'" in p.stderr,
          "scale does not refuse rgba8 clearly:\n" + p.stderr)
    print("core add and scale take rgbe8 within RGBE's precision; rgba8 refused: " +
          [l for l in p.stderr.splitlines() if "rgba8" in l][0])


def t_accuracy_probe():
    out = os.path.join(TMP, "accuracy")
    env = dict(os.environ)
    env["LIGHTGRAPH_PLUGIN_PATH"] = os.path.join(BUILD, "plugins")
    p = subprocess.run([sys.executable, os.path.join(SOURCE, "tools", "accuracy", "accuracy.py"),
                        "--build", BUILD, "--out", out, "--quick", "--only", "probe"],
                       env=env, capture_output=True, text=True, timeout=300)
    check(p.returncode == 0, "accuracy.py --only probe failed:\n" + p.stdout + p.stderr)
    check(os.path.getsize(os.path.join(out, "accuracy.md")) > 0, "no accuracy.md")
    data = os.path.join(out, "images", "accuracy", "data")

    def errors(study):
        path = os.path.join(data, "probe-%s.csv" % study)
        return {r["refl.format"]: float(r["rel_rmse"]) for r in csv.DictReader(open(path))}

    e = errors("probe_format")
    check(set(e) == {"rgba32f", "rgba16f", "rgbe8"}, "rows: %s" % list(e))
    check(e["rgba32f"] == 0, "rgba32f against itself: %g" % e["rgba32f"])
    check(0 < e["rgba16f"] < 1e-3, "rgba16f relative RMSE %g" % e["rgba16f"])
    check(0 < e["rgbe8"] < 0.007, "rgbe8 relative RMSE %g" % e["rgbe8"])
    sun = errors("probe_format_sun")
    check(sun["rgba32f"] == 0 and sun["rgba16f"] > sun["rgbe8"] > 0,
          "2^12 brighter: rgba16f should err most (clamped at 65504): %s" % sun)
    print("probe formats, relative RMSE against rgba32f: %s; 2^12 brighter: %s" % (e, sun))


def t_keyword_colour():
    p = run(["inspect", "test_fill"])
    line = [l for l in p.stdout.splitlines() if l.split()[:1] == ["color"]]
    check(line and "= checker" in line[0] and "or {checker}" in line[0],
          "inspect text:\n" + p.stdout)
    doc = json.loads(run(["inspect", "test_fill", "--json"]).stdout)
    doc = doc[0] if isinstance(doc, list) else doc
    q = [x for x in doc["parameters"] if x["key"] == "color"][0]
    check(q["type"] == "color" and q["default"] == "checker" and q["values"] == ["checker"]
          and q["min"] == 0 and q["max"] == 100, "inspect --json: %r" % q)

    g = graph('f = test_fill { width = 3, height = 2 }\noutput f "f.exr"\n')
    run(["render", g])
    w, h, c = exr("f.exr")
    check((w, h) == (3, 2), "size %dx%d" % (w, h))
    for i in range(6):
        x, y = i % 3, i // 3
        want = 1.0 if (x + y) % 2 == 0 else 0.0
        check(c["R"][i] == want and c["B"][i] == want, "checker pixel %d: %r" % (i, c["R"][i]))
    # black right after the checker, with the same cache: the keyword is part of the identity
    run(["render", g, "--set", "f.color=[0,0,0]"])
    check(max(exr("f.exr")[2]["R"]) == 0, "[0, 0, 0] rendered as the checker")
    g2 = graph('f = test_fill { width = 3, height = 2, color = [0.25, 0.5, 2] }\n'
               'output f "f.exr"\n', "g2.lgraph")
    run(["render", g2])
    c = exr("f.exr")[2]
    check(set(c["R"]) == {0.25} and set(c["G"]) == {0.5} and set(c["B"]) == {2.0},
          "colour fill: %r" % c)
    run(["render", g2, "--set", "f.color=checker"])
    check(exr("f.exr")[2]["R"][0] == 1.0, "--set color=checker")
    p = run(["check", g2, "--set", "f.color=chekcer"], expect=None)
    check(p.returncode != 0 and "'chekcer' is not a colour [r, g, b] or one of: checker "
          "(parameter 'color' of node 'f'); did you mean 'checker'?" in p.stderr,
          "misspelt keyword:\n" + p.stderr)
    p = run(["check", g2, "--set", "f.color=[1,1,1000]"], expect=None)
    check(p.returncode != 0 and "color[2] = 1000 is out of range [0, 100]" in p.stderr,
          "range:\n" + p.stderr)
    p = run(["check", g2, "--set", "f.color=1"], expect=None)
    check(p.returncode != 0 and "expected a colour [r, g, b] or one of: checker, found an "
          "integer" in p.stderr, "wrong kind:\n" + p.stderr)
    print("test_fill: keyword default, colours from the file and --set, errors")


TESTS = {"keyword_colour": t_keyword_colour, "roundtrip": t_roundtrip, "rgbe_precision": t_rgbe_precision,
         "half_policy": t_half_policy, "reinhard": t_reinhard, "core": t_core,
         "accuracy_probe": t_accuracy_probe}

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
