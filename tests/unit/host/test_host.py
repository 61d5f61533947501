#!/usr/bin/env python3
"""Host tests through the real program: plugin discovery and refusal, introspection,
planning (culling, gating, plugins never loaded), the cache, exit statuses, profiles.

usage: test_host.py TEST_NAME   (meson runs each test as its own case)

Environment (from tests/meson.build): LG_EXE, LG_TEST_PLUGINS (test plugin dir),
LG_BROKEN_PLUGINS (broken plugin dir), LIGHTGRAPH_CACHE_DIR is replaced per test.
"""
import json
import os
import shutil
import struct
import subprocess
import sys
import zlib

import lgrun
from lgrun import Fail, check

EXE = lgrun.EXE
TEST_PLUGINS = os.environ["LG_TEST_PLUGINS"]
BROKEN = os.environ["LG_BROKEN_PLUGINS"]
TMP = lgrun.temp_dir("lg-host-test-")


def run(args, plugin_path=TEST_PLUGINS, cache=None, expect=None):
    return lgrun.run(args, lgrun.env(plugin_path, cache or os.path.join(TMP, "cache")), expect)


def graph(text, name="g.lgraph"):
    return lgrun.write(os.path.join(TMP, name), text)


def read_hdr_pixels(path):
    """Minimal reader for the flat or RLE .hdr files the host writes (enough for tests that
    check a constant value); the codec tests test the codec itself."""
    data = open(path, "rb").read()
    head, _, rest = data.partition(b"\n\n")
    line, _, body = rest.partition(b"\n")
    parts = line.split()
    h, w = int(parts[1]), int(parts[3])
    pixels = []
    pos = 0
    for _ in range(h):
        if body[pos] == 2 and body[pos + 1] == 2:
            pos += 4
            chans = [[], [], [], []]
            for c in range(4):
                while len(chans[c]) < w:
                    n = body[pos]
                    pos += 1
                    if n > 128:
                        chans[c] += [body[pos]] * (n - 128)
                        pos += 1
                    else:
                        chans[c] += list(body[pos:pos + n])
                        pos += n
            row = list(zip(*chans))
        else:
            row = [tuple(body[pos + 4 * i: pos + 4 * i + 4]) for i in range(w)]
            pos += 4 * w
        for r, g, b, e in row:
            if e == 0:
                pixels.append((0.0, 0.0, 0.0))
            else:
                f = 2.0 ** (e - 136)
                pixels.append((r * f, g * f, b * f))
    return w, h, pixels


# ---- tests -----------------------------------------------------------------------------

def test_plugins_json():
    p = run(["plugins", "--json"], expect=0)
    doc = json.loads(p.stdout)
    check(doc["abi"]["major"] >= 1, "abi missing")
    types = {t["name"]: t for pl in doc["plugins"] for t in pl["node_types"]}
    for name in ("test_scene", "test_fog", "test_specular", "test_cached"):
        check(name in types, "node type %s missing from plugins --json" % name)
    fog = types["test_fog"]
    check([q["key"] for q in fog["parameters"]] == ["value"], "test_fog parameters")
    check(fog["parameters"][0]["default"] == 0.5 and fog["parameters"][0]["max"] == 1e6,
          "test_fog default/range")
    check(fog["needs"] == ["light", "medium"], "test_fog needs: %s" % fog["needs"])
    check(fog["inputs"][1]["optional"] is True, "optional input flag")
    scene = types["test_scene"]
    check(len(scene["parameters"]) == 6, "test_scene has 6 parameters")
    # every node type of every plugin (the build tree's too) with complete parameters
    for name, t in types.items():
        for key in ("doc", "inputs", "outputs", "parameters", "needs", "neutral"):
            check(key in t, "%s lacks %s" % (name, key))
        for q in t["parameters"]:
            for key in ("key", "type", "default", "doc"):
                check(key in q, "%s.%s lacks %s" % (name, q.get("key"), key))
            if q["type"] == "enum":
                check(q["default"] in q["values"], "%s.%s default not a value" % (name, q["key"]))
    for name in ("image", "constant", "add", "scale", "reinhard"):
        check(name in types, "the build tree's node type %s is listed" % name)
    text = run(["plugins"], expect=0).stdout
    check("test_fog" in text and "medium_density" in text, "plugins text output")


def test_inspect():
    p = run(["inspect", "test_fog", "--json"], expect=0)
    t = json.loads(p.stdout)
    check(t["name"] == "test_fog" and t["plugin"] == "testfog", "inspect json")
    p = run(["inspect", "test_fgo"], expect=2)
    check("did you mean 'test_fog'" in p.stderr, "inspect did-you-mean: " + p.stderr)
    p = run(["inspect", "test_scene"], expect=0)
    check("medium_density" in p.stdout and "float" in p.stdout, "inspect text")


def test_broken_refused():
    p = run(["plugins", "--json"], plugin_path=BROKEN + ":" + TEST_PLUGINS, expect=0)
    doc = json.loads(p.stdout)
    refused = {os.path.basename(r["path"]): r["reason"] for r in doc["refused"]}
    M, m = doc["abi"]["major"], doc["abi"]["minor"]
    expect = {
        "lg_broken_major.so": "ABI %d.%d, this host has ABI %d.%d" % (M + 1, m, M, m),
        "lg_broken_minor.so": "ABI %d.%d, this host has ABI %d.%d" % (M, m + 1, M, m),
        "lg_broken_abi1.so": "built for plugin ABI 1.1; this host has ABI %d.%d, which no "
                             "longer loads ABI 1 plugins: rebuild it" % (M, m),
        "lg_broken_short.so": "struct_size 8",
        "lg_broken_noname.so": "plugin name missing",
        "lg_broken_noentry.so": "no 'lg_plugin_entry' symbol",
        "lg_broken_crash.so": "crashed while being scanned",
        "lg_broken_baddefault.so": "default 5 outside [0, 1]",
        "lg_broken_badkeyword.so": "parameter 'x': default keyword index 2 out of range (-1 "
                                   "for the colour .def.v, 0 .. 0 for a keyword)",
        "lg_broken_outputdefault.so": "parameter 'x': an output file (LG_ROLE_OUTPUT_FILE) is "
                                      "a PATH parameter whose default is \"\"",
    }
    for f, why in expect.items():
        check(f in refused, "%s was not refused (refused: %s)" % (f, list(refused)))
        check(why in refused[f], "%s: reason %r lacks %r" % (f, refused[f], why))
    names = [pl["name"] for pl in doc["plugins"]]
    check("testfog" in names, "good plugins still load beside broken ones")
    check(not any(n.startswith("broken") for n in names), "a broken plugin was accepted")
    # the warning names the file and both versions
    check("lg_broken_major.so" in p.stderr and ("needs major %d" % M) in p.stderr,
          "refusal warning on stderr: " + p.stderr)


def fog_graph(density, extra=""):
    return graph("""lightgraph 1
scene = test_scene { medium_density = %s, dir_lights = 1 }
fog = test_fog { scene = scene, value = 0.5 }
%s
output fog "%s"
""" % (density, extra, os.path.join(TMP, "fog.hdr")))


def test_gating():
    g = fog_graph("0")
    p = run(["render", g, "--explain", "--size", "8x4"], expect=0)
    lines = {l.split()[0]: l for l in p.stdout.splitlines() if l.startswith("  ")}
    check("gated" in lines["fog"] and "no participating medium" in lines["fog"],
          "fog should be gated: " + p.stdout)
    loaded = [l for l in p.stdout.splitlines() if l.startswith("plugins loaded:")][0]
    notl = [l for l in p.stdout.splitlines() if l.startswith("plugins not loaded:")][0]
    check("testfog" not in loaded and "testfog" in notl,
          "a gated node's plugin must not be loaded:\n" + p.stdout)
    check("testscene" in loaded, "the scene plugin is loaded")
    check("medium no" in p.stdout, "explain prints scene features")
    w, h, px = read_hdr_pixels(os.path.join(TMP, "fog.hdr"))
    check((w, h) == (8, 4) and all(v == (0.0, 0.0, 0.0) for v in px),
          "a gated node yields black at the render size")

    g = fog_graph("1")
    p = run(["render", g, "--explain", "--size", "8x4"], expect=0)
    lines = {l.split()[0]: l for l in p.stdout.splitlines() if l.startswith("  ")}
    check(" kept " in lines["fog"], "with a medium, fog runs: " + p.stdout)
    loaded = [l for l in p.stdout.splitlines() if l.startswith("plugins loaded:")][0]
    check("testfog" in loaded, "testfog loaded when needed")
    w, h, px = read_hdr_pixels(os.path.join(TMP, "fog.hdr"))
    check(all(abs(v[0] - 0.5) < 1e-6 for v in px), "fog value 0.5 written")

    # no light at all: gated for the other need
    g = graph("""lightgraph 1
scene = test_scene { medium_density = 1, dir_lights = 0 }
fog = test_fog { scene = scene }
output fog "%s"
""" % os.path.join(TMP, "fog2.hdr"))
    p = run(["render", g, "--explain"], expect=0)
    check("no light" in p.stdout, "gated for lack of light: " + p.stdout)

    # passthrough neutral: the image goes through unchanged
    g = graph("""lightgraph 1
scene = test_scene { medium_density = 1, specular = false }
fog = test_fog { scene = scene, value = 0.25 }
spec = test_specular { scene = scene, image = fog }
output spec "%s"
""" % os.path.join(TMP, "spec.hdr"))
    p = run(["render", g, "--explain", "--size", "4x4"], expect=0)
    check("no material with a specular term" in p.stdout, p.stdout)
    w, h, px = read_hdr_pixels(os.path.join(TMP, "spec.hdr"))
    check(all(abs(v[0] - 0.25) < 1e-6 for v in px), "passthrough neutral keeps the input")


def test_culling():
    g = fog_graph("1", "dead = test_cached { image = fog }\n")
    p = run(["render", g, "--explain", "--size", "4x4"], expect=0)
    lines = {l.split()[0]: l for l in p.stdout.splitlines() if l.startswith("  ")}
    check("culled" in lines["dead"] and "no output depends on it" in lines["dead"], p.stdout)
    loaded = [l for l in p.stdout.splitlines() if l.startswith("plugins loaded:")][0]
    check("testcache" not in loaded, "a culled node's plugin must not be loaded: " + loaded)


def cache_graph(salt, value):
    return graph("""lightgraph 1
scene = test_scene { medium_density = 1 }
fog = test_fog { scene = scene, value = %s }
mean = test_cached { image = fog, salt = %d }
output mean "%s"
""" % (value, salt, os.path.join(TMP, "mean.hdr")), "cache.lgraph")


def test_cache():
    cache = os.path.join(TMP, "cache-test")

    def once(salt, value):
        p = run(["render", cache_graph(salt, value), "--size", "4x4"], cache=cache, expect=0)
        if "testcache: computed" in p.stderr:
            return "computed", p
        if "testcache: reused" in p.stderr:
            return "reused", p
        raise Fail("no cache message: " + p.stderr)

    check(once(1, 0.5)[0] == "computed", "first run computes")
    check(once(1, 0.5)[0] == "reused", "second run reuses")
    check(once(2, 0.5)[0] == "computed", "a changed parameter misses")
    check(once(1, 0.75)[0] == "computed", "a changed input misses")
    w, h, px = read_hdr_pixels(os.path.join(TMP, "mean.hdr"))
    check(abs(px[0][0] - 0.75) < 1e-6, "the cached node's result is right")
    check(once(1, 0.75)[0] == "reused", "and is reused")
    # corrupt every entry: flip a payload byte, then truncate another
    entries = [os.path.join(cache, f) for f in os.listdir(cache) if f.endswith(".lgc")]
    check(len(entries) == 3, "three entries written: %s" % entries)
    for e in entries:
        data = bytearray(open(e, "rb").read())
        data[-1] ^= 0xFF
        open(e, "wb").write(data)
    what, p = once(1, 0.75)
    check(what == "computed" and "corrupt (checksum mismatch)" in p.stderr,
          "a corrupt entry is detected and recomputed: " + p.stderr)
    w, h, px = read_hdr_pixels(os.path.join(TMP, "mean.hdr"))
    check(abs(px[0][0] - 0.75) < 1e-6, "the recomputed result is right")
    check(once(1, 0.75)[0] == "reused", "the recomputed entry is trusted again")
    for e in [os.path.join(cache, f) for f in os.listdir(cache) if f.endswith(".lgc")]:
        data = open(e, "rb").read()
        open(e, "wb").write(data[:len(data) - 3])
    what, p = once(1, 0.75)
    check(what == "computed" and "truncated" in p.stderr, "a truncated entry: " + p.stderr)
    # entries that are not regular files (issue 8): a link to /dev/zero and a FIFO are
    # refused at once, removed and recomputed; never read without bound, never waited on
    for make, what_is in ((lambda e: os.symlink("/dev/zero", e), "a character device"),
                          (lambda e: os.mkfifo(e), "a FIFO")):
        entries = [os.path.join(cache, f) for f in os.listdir(cache) if f.endswith(".lgc")]
        check(len(entries) == 3, "three entries: %s" % entries)
        for e in entries:
            os.remove(e)
            make(e)
        what, p = once(1, 0.75)
        check(what == "computed" and ("it is %s, not a regular file" % what_is) in p.stderr
              and "removing it and recomputing" in p.stderr, "%s entry: %s" % (what_is, p.stderr))
        real = [e for e in entries if os.path.isfile(e) and not os.path.islink(e)]
        check(len(real) == 1, "the entry this graph reads was replaced by a real one: %s" %
              [(e, os.path.islink(e), os.path.isfile(e)) for e in entries])


def test_no_cache():
    """render --no-cache, sweep and tune neither read nor write the on-disk cache: what they
    time is the work (a repeat timed as a cache load would make the atlas and tune lie)."""
    cache = os.path.join(TMP, "no-cache-test")
    g = cache_graph(7, 0.5)

    def entries():
        return sorted(f for f in os.listdir(cache) if f.endswith(".lgc")) \
            if os.path.isdir(cache) else []
    for _ in range(2):
        p = run(["render", g, "--size", "4x4", "--no-cache"], cache=cache, expect=0)
        check("testcache: computed" in p.stderr, "--no-cache computes: " + p.stderr)
    check(entries() == [], "--no-cache wrote an entry: %s" % entries())
    p = run(["render", g, "--size", "4x4"], cache=cache, expect=0)
    check("testcache: computed" in p.stderr and len(entries()) == 1,
          "without it the entry is written: %s" % entries())
    p = run(["render", g, "--size", "4x4", "--no-cache"], cache=cache, expect=0)
    check("testcache: computed" in p.stderr, "--no-cache does not read the entry: " + p.stderr)
    out = os.path.join(TMP, "sweep-no-cache")
    os.makedirs(out, exist_ok=True)
    p = run(["sweep", g, "--vary", "fog.value=0.25,0.5", "--repeat", "2", "--size", "4x4",
             "-o", out], cache=cache, expect=0)
    check(p.stderr.count("testcache: computed") == 5 and "reused" not in p.stderr,
          "sweep: the reference and 2 x 2 runs all compute: " + p.stderr)
    check(len(entries()) == 1, "sweep wrote an entry: %s" % entries())


def test_frames_and_profile():
    g = fog_graph("1")
    pj = os.path.join(TMP, "profile.json")
    p = run(["render", g, "--frames", "5", "--profile", "--profile-json", pj, "--size", "4x4"],
            expect=0)
    check("profile (5 frames)" in p.stdout and "cpu ms" in p.stdout, p.stdout)
    doc = json.load(open(pj))
    nodes = {n["name"]: n for n in doc["nodes"]}
    check(nodes["fog"]["runs"] == 1 and nodes["fog"]["per_frame"] is False,
          "a static node runs once across frames")
    check(nodes["fog"]["bytes_allocated"] == 4 * 4 * 16, "bytes allocated counted")
    check(nodes["fog"]["first_cpu_ms"] > 0 and nodes["fog"]["min_cpu_ms"] == nodes["fog"]["first_cpu_ms"],
          "one run: min = first: %r" % nodes["fog"])
    # --every-frame: static nodes run every frame; =NODE,...: only those
    run(["render", g, "--frames", "5", "--every-frame", "--profile-json", pj, "--size", "4x4"],
        expect=0)
    nodes = {n["name"]: n for n in json.load(open(pj))["nodes"]}
    check(nodes["fog"]["runs"] == 5 and nodes["scene"]["runs"] == 5, "--every-frame: %r" % nodes)
    f = nodes["fog"]
    check(f["min_cpu_ms"] <= f["first_cpu_ms"] and f["min_cpu_ms"] * 5 <= f["cpu_ms"] + 1e-9,
          "min <= first, 5 runs >= 5 x min: %r" % f)
    run(["render", g, "--frames", "4", "--every-frame=fog", "--profile-json", pj, "--size", "4x4"],
        expect=0)
    nodes = {n["name"]: n for n in json.load(open(pj))["nodes"]}
    check(nodes["fog"]["runs"] == 4 and nodes["scene"]["runs"] == 1,
          "--every-frame=fog runs fog only: %r" % nodes)


def test_plugin_memory():
    """--profile counts a plugin's own memory as the most it held at once (lg_account_alloc
    and lg_account_free, here through lg_gl_buffer and lg_gl_texture), added to the host's
    resources: N frames of a node that keeps its buffer, or remakes it every execute, show
    what one frame shows; a texture whose size changes counts each release."""
    size = 8
    one = size * size * 16
    pj = os.path.join(TMP, "mem.json")

    def profile(mode, frames, table=False):
        g = graph("lightgraph 1\nm = test_mem { mode = %s, size = %d }\noutput m \"%s\"\n"
                  % (mode, size, os.path.join(TMP, "mem.exr")), "mem.lgraph")
        args = ["render", g, "--frames", str(frames), "--size", "4x4", "--profile-json", pj]
        p = run(args + (["--profile"] if table else []), expect=None)
        skip_if_no_device(p)
        check(p.returncode == 0, "%s, %d frames: %s" % (mode, frames, p.stderr))
        m = {n["name"]: n for n in json.load(open(pj))["nodes"]}["m"]
        check(m["runs"] == frames, "%s: %d runs, want %d" % (mode, m["runs"], frames))
        check(m["bytes_allocated"] == m["resource_bytes"] + m["plugin_bytes_peak"],
              "%s: allocated = resources + plugin peak: %r" % (mode, m))
        check(m["resource_bytes"] >= 4 * 4 * 16, "%s: the output counted: %r" % (mode, m))
        return m, p.stdout

    for mode, live in (("keep", one), ("remake", 0)):
        m1, _ = profile(mode, 1)
        m5, _ = profile(mode, 5)
        check(m1["plugin_bytes_peak"] == one and m5["plugin_bytes_peak"] == one,
              "%s: the plugin's peak is one buffer (%d bytes) after 1 and 5 frames: %d, %d"
              % (mode, one, m1["plugin_bytes_peak"], m5["plugin_bytes_peak"]))
        check(m1["plugin_bytes_live"] == live and m5["plugin_bytes_live"] == live,
              "%s: live after the last frame %d: %r %r" % (mode, live, m1, m5))
        check(m5["bytes_allocated"] == m1["bytes_allocated"],
              "%s: 5 frames allocate what 1 frame does: %d vs %d"
              % (mode, m5["bytes_allocated"], m1["bytes_allocated"]))
    # resize: 8x8, 16x8, 8x8: each remake releases the old texture first
    m, _ = profile("resize", 2)
    check(m["plugin_bytes_peak"] == 2 * one and m["plugin_bytes_live"] == 2 * one, "%r" % m)
    m, out = profile("resize", 3, table=True)
    check(m["plugin_bytes_live"] == one and m["plugin_bytes_peak"] == 2 * one,
          "resize over 3 frames: live %d (want %d), peak %d (want %d)"
          % (m["plugin_bytes_live"], one, m["plugin_bytes_peak"], 2 * one))
    # the table: allocated (resources + peak) and the plugin's peak, in their columns
    head = [l for l in out.splitlines() if "allocated" in l and "plugin" in l and "moved" in l]
    row = [l for l in out.splitlines() if l.split()[:2] == ["m", "test_mem"]]
    check(head and row, "profile table: %s" % out)
    cols = head[0].split()
    check(cols.index("allocated") + 1 == cols.index("plugin"), "columns: %s" % head[0])
    check(("%.1f KiB" % ((m["resource_bytes"] + 2 * one) / 1024.0)) in row[0]
          and "2.0 KiB" in row[0], "row: %s (json %r)" % (row[0], m))


def test_devices():
    """`lightgraph devices`: one line per device, exit 0 when all can be made, 1 (with the
    message a render would fail with) when one cannot."""
    p = run(["devices", "--frob"], expect=2)
    p = run(["devices", "gl"], expect=None)
    if p.returncode != 0:
        print("skipped: " + p.stdout)
        sys.exit(77)
    check(p.stdout.startswith("gl: ") and "4.5" in p.stdout, p.stdout)
    env_gl = dict(os.environ, GALLIUM_DRIVER="softpipe")
    q = subprocess.run([EXE, "devices", "gl"], capture_output=True, text=True, env=env_gl)
    check(q.returncode == 1 and q.stdout.startswith("gl: no OpenGL 4.5 device (osmesa): "),
          "softpipe: %d %s" % (q.returncode, q.stdout))
    env_cl = dict(os.environ, OCL_ICD_VENDORS=os.path.join(TMP, "no-icds"))
    q = subprocess.run([EXE, "devices", "cl", "gl"], capture_output=True, text=True, env=env_cl)
    lines = q.stdout.splitlines()
    check(q.returncode == 1 and len(lines) == 2 and lines[0].startswith("gl: ") and
          "no OpenGL" not in lines[0] and lines[1].startswith("cl: no OpenCL device: "),
          "no ICD: %d %s" % (q.returncode, q.stdout))


def test_exit_status():
    # bad usage
    run([], expect=2)
    run(["render"], expect=2)
    run(["frobnicate"], expect=2)
    p = run(["rendr", "x"], expect=2)
    check("did you mean 'render'" in p.stderr, p.stderr)
    run(["render", fog_graph("1"), "--size", "0x4"], expect=2)
    run(["render", fog_graph("1"), "--frames", "-3"], expect=2)
    # missing graph file
    p = run(["render", os.path.join(TMP, "nope.lgraph")], expect=2)
    check("nope.lgraph" in p.stderr, "names the missing file: " + p.stderr)
    # a bad graph: misspelt parameter
    g = graph("lightgraph 1\nscene = test_scene { medum_density = 1 }\n"
              "fog = test_fog { scene = scene }\noutput fog \"x.hdr\"\n", "bad.lgraph")
    p = run(["render", g], expect=2)
    check("bad.lgraph:2:22:" in p.stderr and "did you mean 'medium_density'" in p.stderr,
          "file:line:col and suggestion: " + p.stderr)
    # failure while running: an output that cannot be written; no partial file left
    out = "/proc/lightgraph-cannot-write/x.hdr"
    p = run(["render", fog_graph("1"), "-o", out], expect=1)
    check("cannot" in p.stderr, p.stderr)
    # -o with an unknown format is bad usage
    run(["render", fog_graph("1"), "-o", os.path.join(TMP, "x.bmp")], expect=2)
    # special files are refused at once, never waited on or read without end (issue 8): a
    # FIFO as an image to diff or as a graph, /dev/zero as a graph
    fifo = os.path.join(TMP, "f.exr")
    os.mkfifo(fifo)
    p = run(["diff", fifo, fifo], expect=None)
    check(p.returncode != 0 and "it is a FIFO, not a regular file" in p.stderr,
          "diff of a FIFO: %d %s" % (p.returncode, p.stderr))
    gfifo = os.path.join(TMP, "f.lgraph")
    os.mkfifo(gfifo)
    p = run(["check", gfifo], expect=2)
    check("cannot read graph file: it is a FIFO, not a regular file" in p.stderr, p.stderr)
    p = run(["check", "/dev/zero"], expect=2)
    check("it is a character device, not a regular file" in p.stderr, p.stderr)
    # check command
    p = run(["check", fog_graph("1")], expect=0)
    check(": ok (2 nodes, 1 outputs)" in p.stdout, p.stdout)


def test_size_option():
    """--size is read by one parser in render, sweep and view (host/base/util.c lg_parse_size):
    WxH with each side 1..16384 and nothing else; anything else exits 2 naming the option
    and the value, before any work (view: before it looks for a display)."""
    g = fog_graph("1")
    bad = ["0x4", "4x0", "4x", "x4", "4", "-1x4", "4x-1", "+4x4", " 4x4", "4x 4", "4x4x",
           "16385x4", "4x16385", "4294967297x4", "4X4", "4x4.5", ""]
    for cmd in (["render", g], ["sweep", g, "--vary", "fog.value=0.1,0.2"], ["view", g]):
        for s in bad:
            p = run(cmd + ["--size", s], expect=2)
            check("--size" in p.stderr and ("'%s'" % s) in p.stderr,
                  "%s --size %r: %s" % (cmd[0], s, p.stderr))
    for s, w, h in (("1x1", 1, 1), ("16384x2", 16384, 2), ("7x3", 7, 3)):
        p = run(["render", g, "--explain", "--size", s], expect=0)
        check(("%dx%d" % (w, h)) in p.stdout + p.stderr, "render --size %s: %s" % (s, p.stdout))


def test_residency():
    """A resource is copied only when a consumer on another device asks, and every copy is
    counted against that consumer: CPU -> GL for the gl node's input, GL -> CL for the cl
    node's input (through the CPU: 2 copies), CL -> CPU for the cpu node and the file."""
    g = graph("""lightgraph 1
c = constant { color = [0.5, 1, 2], width = 16, height = 8 }
a = reinhard { image = c, backend = gl }
b = reinhard { image = a, backend = cl }
s = scale { image = b, factor = 1 }
output s "%s"
""" % os.path.join(TMP, "res.exr"))
    pj = os.path.join(TMP, "res.json")
    core = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
    p = run(["render", g, "--profile-json", pj], plugin_path=core, expect=None)
    if p.returncode != 0 and ("no OpenGL" in p.stderr or "no OpenCL" in p.stderr):
        print("skipped: " + p.stderr)
        sys.exit(77)
    check(p.returncode == 0, p.stderr)
    nodes = {n["name"]: n for n in json.load(open(pj))["nodes"]}
    img = 16 * 8 * 16
    check(nodes["c"]["bytes_moved"] == 0, "the producer moves nothing")
    check(nodes["a"]["device"] == "gl" and nodes["a"]["bytes_moved"] == img,
          "gl node uploads its input once: %s" % nodes["a"])
    check(nodes["b"]["device"] == "cl" and nodes["b"]["bytes_moved"] == 2 * img,
          "cl node: GL -> CPU -> CL: %s" % nodes["b"])
    check(nodes["s"]["bytes_moved"] == img, "cpu node downloads from CL: %s" % nodes["s"])
    check(nodes["a"]["bytes_allocated"] >= 2 * img, "gl texture and output counted")


def skip_if_no_device(p):
    if p.returncode != 0 and ("no OpenGL" in p.stderr or "no OpenCL" in p.stderr):
        print("skipped: " + p.stderr)
        sys.exit(77)


def test_composite():
    """Composite resources (ABI 2.0): a cube probe with mip levels, a solid-angle table and
    its info, written on each device and read on each device, part by part; parts move
    only when a consumer on another device reads them, and the moves are counted."""
    side, levels = 8, 4
    texels = sum(6 * max(1, side >> l) ** 2 for l in range(levels))
    rad_bytes = texels * 16
    for w in ("cpu", "gl", "cl"):
        for r in ("cpu", "gl", "cl"):
            pj = os.path.join(TMP, "parts-%s-%s.json" % (w, r))
            g = graph("""lightgraph 1
m = partmaker { device = %s, size = %d, levels = %d }
c = partcheck { probe = m, device = %s }
output c "%s"
""" % (w, side, levels, r, os.path.join(TMP, "parts.exr")), "parts.lgraph")
            p = run(["render", g, "--profile-json", pj])
            skip_if_no_device(p)
            check(p.returncode == 0, "written on %s, read on %s: %s" % (w, r, p.stderr))
            nodes = {n["name"]: n for n in json.load(open(pj))["nodes"]}
            moved = nodes["c"]["bytes_moved"]
            # radiance: nothing when read where written; one copy CPU<->device; two
            # (through the CPU) between GL and CL. The info and solid-angle parts live on
            # the CPU and the reader maps them there: they never move.
            hops = 0 if w == r else 1 if "cpu" in (w, r) else 2
            check(moved == hops * rad_bytes,
                  "%s -> %s: moved %d bytes, expected %d" % (w, r, moved, hops * rad_bytes))
    # --explain shows the parts of the composite output and what the reader receives
    p = run(["render", g, "--explain"], expect=0)
    check("probe: probe {radiance: image 8x8 cube rgba32f x4 levels" in p.stdout, p.stdout)
    check("solid_angle: buffer" in p.stdout and "info: buffer" in p.stdout, p.stdout)
    check("probe <- m.probe" in p.stdout, p.stdout)
    # introspection lists the parts of composite ports
    doc = json.loads(run(["inspect", "partmaker", "--json"], expect=0).stdout)
    parts = doc["outputs"][0]["parts"]
    check([(q["name"], q["type"], q["optional"]) for q in parts] ==
          [("radiance", "image", False), ("solid_angle", "buffer", True),
           ("info", "meta", False)], "inspect --json parts: %s" % parts)
    p = run(["inspect", "partmaker"], expect=0)
    check(".solid_angle" in p.stdout and "optional" in p.stdout, p.stdout)
    # a part that does not exist, in a graph: an error naming the parts
    g = graph("""lightgraph 1
m = partmaker { }
output m.radiant "x.exr"
""", "badpart.lgraph")
    p = run(["check", g], expect=2)
    check("no output or part 'radiant'; did you mean 'radiance'?" in p.stderr, p.stderr)
    check("parts: radiance solid_angle info" in p.stderr, p.stderr)


def test_kinds():
    """The SH, transfer and froxel kinds through their headers' accessors (declare, publish,
    get), --explain showing their parts, and a part given where the whole kind is wanted."""
    g = graph("""lightgraph 1
m = kindmaker { bands = 4, vertices = 7 }
c = kindcheck { sh = m.sh, transfer = m.transfer, froxel = m.froxel, bands = 4, vertices = 7 }
output c "%s"
""" % os.path.join(TMP, "kinds.exr"), "kinds.lgraph")
    p = run(["render", g, "--explain"])
    check(p.returncode == 0, p.stderr)
    check("sh: sh {coeffs: buffer 192 B, info: buffer" in p.stdout, p.stdout)
    check("transfer: transfer {transfer: buffer 1.3 KiB" in p.stdout, p.stdout)
    check("froxel: froxel {grid: volume 4x3x5 rgba32f" in p.stdout, p.stdout)
    # a part where the whole resource is wanted: the kinds differ
    g = graph("""lightgraph 1
m = kindmaker { }
c = kindcheck { sh = m.coeffs }
output c "x.exr"
""", "kinds_bad.lgraph")
    p = run(["check", g], expect=2)
    check("input 'sh' of node 'c' takes SH coefficients, but 'm.coeffs' gives a buffer" in
          p.stderr, p.stderr)


def test_access_check():
    """A node that maps a resource it did not receive through an input is an error naming
    the node and the resource (debug checks, on in every build of the suite)."""
    for what, msg in (("part", "asks for part 'radiance' of a probe made by node 'm', which "
                               "it did not receive through an input"),
                      ("texture", "maps resource 'm.probe', part 'radiance' on the CPU, which "
                                  "it did not receive through an input")):
        g = graph("""lightgraph 1
m = partmaker { }
c = partcheck { probe = m }
s = partsteal { image = c, what = %s }
output s "%s"
""" % (what, os.path.join(TMP, "steal.exr")), "steal.lgraph")
        p = run(["render", g], expect=1)
        check("node 's' (partsteal): " + msg in p.stderr, p.stderr)
        check(not os.path.exists(os.path.join(TMP, "steal.exr")), "no output after a failure")


def test_undeclared_param():
    """Reading a parameter key the node type does not declare fails the node, never a 0."""
    g = graph("""lightgraph 1
b = badparam { }
output b "%s"
""" % os.path.join(TMP, "bad.exr"), "bad.lgraph")
    p = run(["render", g])
    check(p.returncode != 0, "an undeclared key must fail the render")
    check("node 'b' (badparam): asks for parameter 'no_such_key', which its type does not "
          "declare" in p.stderr, p.stderr)


def test_shadow_parts():
    """The shadow map is a composite: phong receives the atlas through the part, which
    --explain and dot show; NODE.atlas names the part in a graph."""
    core = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
    box = os.path.join(os.environ["LG_SOURCE_ROOT"], "assets", "meshes", "bunny_cornell_box.glb")
    g = graph("""lightgraph 1
box = gltf { file = "%s" }
scene = light { scene = box, direction = [0.6, -0.5, 1] }
shadow = shadowmap { scene = scene, resolution = 64 }
lit = phong { scene = scene, shadows = shadow, width = 32, height = 24 }
output lit "%s"
output shadow.atlas "%s"
""" % (box, os.path.join(TMP, "lit.exr"), os.path.join(TMP, "atlas.exr")), "sm.lgraph")
    p = run(["render", g, "--explain"], plugin_path=core)
    skip_if_no_device(p)
    check(p.returncode == 0, p.stderr)
    check("shadows <- shadow.shadows" in p.stdout, p.stdout)
    check("shadows: shadowmap {atlas: image 64x64 depth32f" in p.stdout, p.stdout)
    check("lights: buffer" in p.stdout and "info: buffer" in p.stdout, p.stdout)
    p = run(["dot", g], plugin_path=core, expect=0)
    check("shadows {atlas, lights, info}" in p.stdout, p.stdout)
    check("atlas, part of shadows" in p.stdout, p.stdout)


def test_gl_backends():
    """--gl chooses the context: OSMesa by default, EGL on request; the same GL node gives
    the same image through both."""
    core = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
    outs = {}
    for backend in ("osmesa", "egl"):
        out = os.path.join(TMP, "gl-%s.exr" % backend)
        g = graph("""lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
t = reinhard { image = c, backend = gl }
output t "%s"
""" % out, "gl-%s.lgraph" % backend)
        p = run(["render", g, "--gl", backend, "--explain"], plugin_path=core)
        if p.returncode != 0 and "no OpenGL" in p.stderr:
            print("skipped: " + p.stderr)
            sys.exit(77)
        check(p.returncode == 0, p.stderr)
        want = "gl device: OSMesa" if backend == "osmesa" else "gl device: EGL"
        check(want in p.stdout, "explain names the context: " + p.stdout)
        outs[backend] = out
    d = run(["diff", outs["osmesa"], outs["egl"], "--max-abs", "0"], plugin_path=core)
    check(d.returncode == 0, "osmesa and egl agree: " + d.stdout + d.stderr)


def test_examples_check():
    """Every example graph checks against the build tree's plugins, and is canonical
    except for what fmt would only re-space."""
    src = os.environ["LG_SOURCE_ROOT"]
    ex = sorted(f for f in os.listdir(os.path.join(src, "examples")) if f.endswith(".lgraph"))
    check(len(ex) >= 3, "examples found: %s" % ex)
    # a copy of the folder, so that formatted files sit beside the files they include
    copy = os.path.join(TMP, "examples")
    shutil.copytree(os.path.join(src, "examples"), copy)
    for f in ex:
        path = os.path.join(src, "examples", f)
        p = run(["check", path], plugin_path="")
        check(p.returncode == 0, "%s does not check: %s" % (f, p.stderr))
        once = run(["fmt", path], plugin_path="", expect=0).stdout
        twice_path = os.path.join(copy, "fmt-" + f)
        with open(twice_path, "w") as fh:
            fh.write(once)
        check(run(["fmt", twice_path], plugin_path="", expect=0).stdout == once,
              "fmt is not idempotent on " + f)


def test_sweep():
    """lightgraph sweep: one CSV row per combination, the reference's own settings give
    zero error, other settings a positive one, heat maps and the gnuplot script exist."""
    g = graph("""lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
t = reinhard { image = c, key = 0.18 }
output t "%s"
""" % os.path.join(TMP, "sw.exr"), "sweep.lgraph")
    out = os.path.join(TMP, "sweep")
    os.makedirs(out)  # sweep -o refuses a missing directory (issue 8)
    core = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
    p = run(["sweep", g, "--vary", "t.key=0.09,0.18", "--vary", "t.mode=luminance,rgb",
             "--ref-set", "t.key=0.18", "--time", "t", "--repeat", "1", "-o", out],
            plugin_path=core, expect=0)
    rows = open(os.path.join(out, "sweep.csv")).read().strip().splitlines()
    check(rows[0].startswith("run,t.key,t.mode,time_ms"), rows[0])
    check(len(rows) == 5, "4 runs: %s" % rows)
    cells = [r.split(",") for r in rows[1:]]
    for c in cells:
        rmse = float(c[5])
        if c[1] == "0.18" and c[2] == "luminance":
            check(rmse == 0, "the reference's own settings: rmse 0, got %s" % rmse)
        else:
            check(rmse > 1e-3, "other settings differ: %s" % c)
        check(float(c[3]) > 0, "a time was measured: %s" % c)
    for k in range(4):
        check(os.path.exists(os.path.join(out, "heat-%03d.png" % k)), "heat map %d" % k)
    check(os.path.exists(os.path.join(out, "sweep.gp")), "gnuplot script")
    run(["sweep", g, "--vary", "t.kye=1"], plugin_path=core, expect=2)
    run(["sweep", g], plugin_path=core, expect=2)
    # --frames: every run renders N frames; the last frame's output is compared
    out3 = os.path.join(TMP, "sweep3")
    os.makedirs(out3)
    run(["sweep", g, "--vary", "t.key=0.18", "--ref-set", "t.key=0.18", "--time", "t",
         "--repeat", "1", "--frames", "3", "-o", out3], plugin_path=core, expect=0)
    rows = open(os.path.join(out3, "sweep.csv")).read().strip().splitlines()
    check(len(rows) == 2 and float(rows[1].split(",")[4]) == 0, "--frames 3: %s" % rows)
    for bad in ("0", "x", "-2"):
        run(["sweep", g, "--vary", "t.key=0.18", "--frames", bad, "-o", out3], plugin_path=core,
            expect=2)


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
