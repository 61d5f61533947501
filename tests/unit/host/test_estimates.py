#!/usr/bin/env python3
"""Long jobs say what they cost before they start (Reliability 3, finding 6), through the
real program: nodes declare their work in prepare (lg_declare_work, ABI 2.7), --explain
shows it, render warns when the estimate passes a minute (and runs anyway), sweep refuses
up front when its outputs do not fit on the disk and makes each run's temporaries only when
the run starts.

No test runs anything long: the absurd renders are stopped (SIGTERM) as soon as their
warning is out, and the disk's free space comes from the LIGHTGRAPH_TEST_FREE_BYTES hook.

usage: test_estimates.py TEST_NAME   (meson runs each test as its own case)

Environment (tests/unit/host/meson.build): LG_EXE, LG_BUILD_ROOT, LG_SOURCE_ROOT,
LG_TEST_PLUGINS.
"""
import os
import re
import signal
import subprocess
import sys
import threading
import time

import lgrun
from lgrun import Fail, check, write

CORE = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
SRC = os.environ.get("LG_SOURCE_ROOT",
                     os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", "..")))
PROBE = os.path.join(SRC, "assets", "probes", "forest_256x128_half_none.exr")
TMP = lgrun.temp_dir("lg-estimates-test-")


def env_for(extra=None):
    return lgrun.env(CORE, os.path.join(TMP, "cache"), extra, drop=["LIGHTGRAPH_TEST_FREE_BYTES"])


def run(args, expect=None, extra_env=None, timeout=120):
    return lgrun.run(args, env_for(extra_env), expect, timeout)


def fresh_dir(name):
    return lgrun.fresh_dir(TMP, name)


def temporaries(d):
    return [n for n in os.listdir(d) if n.startswith(".")]


def sh_graph(d, params):
    return write(os.path.join(d, "sh.lgraph"), """lightgraph 1
sky = probe { file = "%s" }
sh = sh_project { probe = sky, %s }
output sh "sh.txt"
""" % (PROBE, params))


def one_output_graph(d):
    return write(os.path.join(d, "one.lgraph"), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
t = reinhard { image = c, key = 0.18 }
output t "one.exr"
""")


class Running:
    """A process whose stderr is read line by line on a thread, so that the test can wait
    for a line with a deadline and then stop the process."""

    def __init__(self, args, extra_env=None):
        self.p = subprocess.Popen([lgrun.EXE] + args, env=env_for(extra_env),
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.lines = []
        self.t = threading.Thread(target=self._read, daemon=True)
        self.t.start()

    def _read(self):
        for line in self.p.stderr:
            self.lines.append(line)

    def wait_for(self, text, seconds):
        deadline = time.time() + seconds
        while time.time() < deadline:
            if any(text in l for l in self.lines):
                return True
            if self.p.poll() is not None:
                self.t.join(5)
                return any(text in l for l in self.lines)
            time.sleep(0.02)
        return False

    def stop(self):
        if self.p.poll() is None:
            self.p.send_signal(signal.SIGTERM)
        try:
            out, _ = self.p.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            self.p.kill()
            out, _ = self.p.communicate()
        self.t.join(5)
        return out, "".join(self.lines)


# ---- --explain and render ---------------------------------------------------------------

def test_explain_work():
    """--explain prints each node's declared work and the total; a short render does not
    warn. sh_project by quadrature over a 256x128 probe at 3 bands: 256 * 128 * 9 products."""
    d = fresh_dir("explain")
    g = sh_graph(d, "bands = 3")
    p = run(["render", g, "--explain"], expect=0)
    line = next((l for l in p.stdout.splitlines() if l.strip().startswith("sh ")), "")
    check("work: 2.95e+05 texel x coefficient products, about " in line,
          "no work in the sh_project line:\n%s" % p.stdout)
    check(re.search(r"^estimated time: about [0-9.e+-]+ s \(from what the nodes declared: "
                    r"sh \(sh_project\): 2\.95e\+05 ", p.stdout, re.M),
          "no total:\n%s" % p.stdout)
    check("will take about" not in p.stderr, "a short render warned:\n%s" % p.stderr)
    # the samplers count N^2 samples: 64^2 * 4^2
    g = sh_graph(d, "bands = 4, sampler = sobol, samples = 64")
    p = run(["render", g, "--explain"], expect=0)
    check("work: 6.55e+04 sample x coefficient products" in p.stdout, p.stdout)
    # probe_convert: the source's texels and the result's, 256 * 128 + 32 * 16
    g = write(os.path.join(d, "conv.lgraph"), """lightgraph 1
sky = probe { file = "%s" }
conv = probe_convert { probe = sky, layout = latlong, size = 16 }
output conv "conv.hdr"
""" % PROBE)
    p = run(["render", g, "--explain"], expect=0)
    check("work: 3.33e+04 texels resampled (source and result), about " in p.stdout, p.stdout)


def test_render_warns():
    """An absurd sh_project (64 bands from 16384^2 Sobol samples: 1.1e12 products) is
    explained and warned about before it runs, in hours, and runs anyway: it is still running
    when the test stops it."""
    d = fresh_dir("warn")
    g = sh_graph(d, "bands = 64, sampler = sobol, samples = 16384")
    r = Running(["render", g, "--explain"])
    try:
        seen = r.wait_for("this render will take about", 60)
        time.sleep(0.2)
        still = r.p.poll() is None
    finally:
        out, err = r.stop()
    check(seen, "no warning within 60 s:\n%s" % err)
    check(still, "the render did not run on after the warning (exit %s):\n%s" %
          (r.p.returncode, err))
    m = re.search(r"warning: this render will take about ([0-9.]+) (h|days): sh \(sh_project\): "
                  r"1\.1e\+12 sample x coefficient products, about [^;]*; it runs anyway", err)
    check(m, "warning text:\n%s" % err)
    hours = float(m.group(1)) * (24 if m.group(2) == "days" else 1)
    check(0.3 <= hours <= 100, "about %g h: not the order of magnitude measured (hours)" % hours)
    check("work: 1.1e+12 sample x coefficient products, about" in out,
          "--explain before the run:\n%s" % out)
    # -q hides the warning, not the run; the same plan with few samples does not warn
    g = sh_graph(d, "bands = 64, sampler = sobol, samples = 8")
    p = run(["render", g], expect=0)
    check("will take" not in p.stderr, p.stderr)


def test_volumetric():
    """The volumetric nodes declare their work from the image, the lights and their own
    parameters: volumetric_reference width x height x spp x steps x lights occlusion rays
    (32 x 18 x 4 x 16 x 1), volumetric_froxel its grid x lights per run (190 x 90 x 128)."""
    ex = os.path.join(SRC, "examples")
    p = run(["render", os.path.join(ex, "volumetric_reference.lgraph"), "-o",
             os.path.join(fresh_dir("vol"), "vr.png"), "--size", "32x18", "--set",
             "vol.steps=16", "--explain"], expect=0)
    check(re.search(r"^  vol .*; work: 3\.69e\+04 occlusion rays, about ", p.stdout, re.M),
          p.stdout)
    p = run(["render", os.path.join(ex, "volumetric_froxel.lgraph"), "-o",
             os.path.join(TMP, "vol", "fx.png"), "--size", "32x18", "--explain"], expect=0)
    check(re.search(r"^  vol .*; work: 2\.19e\+06 froxel x light visits, about ", p.stdout,
                    re.M), p.stdout)


def test_prt_cache():
    """prt_bake declares vertices x directions (23733 x 8^2 for examples/prt.lgraph with
    samples = 8), and nothing once its result is in the cache (it looks in prepare).
    (samples = 2 to 4 trip an Embree assertion in the bake itself, on main too.)"""
    args = ["render", os.path.join(SRC, "examples", "prt.lgraph"), "-o",
            os.path.join(fresh_dir("prt"), "prt.png"), "--size", "32x18", "--set",
            "bake.samples=8", "--explain"]
    p = run(args, expect=0)
    check(re.search(r"^  bake .*; work: 1\.52e\+06 vertex x direction pairs, about ",
                    p.stdout, re.M), p.stdout)
    p = run(args, expect=0)
    check(re.search(r"^  bake .*; work: 0 vertex x direction pairs \(the result is in the "
                    r"cache\), about 0 s", p.stdout, re.M), p.stdout)


def test_host_rules():
    """What the host makes of declared estimates, with the test plugin testwork (which
    declares its parameters and does nothing): the warning above 60 s and the render still
    runs; -q hides it; a per-frame node counts once per frame; several nodes are listed
    largest first; a negative or NaN estimate fails the node as a plugin bug."""
    d = fresh_dir("rules")
    path = os.environ["LG_TEST_PLUGINS"] + ":" + CORE

    def graph(name, nodes, out):
        return write(os.path.join(d, name), """lightgraph 1
c = constant { color = [1, 1, 1], width = 4, height = 4 }
%s
output %s "%s.exr"
""" % (nodes, out, name))

    def render(g, *extra, expect=0):
        return run(["render", g] + list(extra), expect=expect,
                   extra_env={"LIGHTGRAPH_PLUGIN_PATH": path})

    g = graph("long", "w = test_work { image = c, units = 1e9, seconds = 5400 }", "w")
    p = render(g, "--explain")
    check("work: 1e+09 test units, about 1.5 h" in p.stdout, p.stdout)
    check("warning: this render will take about 1.5 h: w (test_work): 1e+09 test units, "
          "about 1.5 h; it runs anyway" in p.stderr, p.stderr)
    check(os.path.exists(os.path.join(d, "long.exr")), "the render did not run")
    p = render(g, "-q")
    check("will take" not in p.stderr, "-q: " + p.stderr)
    # 30 s: no warning; the same every frame over 4 frames: 2 min
    g = graph("short", "w = test_work { image = c, units = 10, seconds = 30 }", "w")
    check("will take" not in render(g).stderr, "30 s warned")
    g = graph("frames", "w = test_work { image = c, units = 10, seconds = 30, "
                        "per_frame = true }", "w")
    p = render(g, "--frames", "4", "--explain")
    check("work: 10 test units x 4 runs, about 2 min" in p.stdout, p.stdout)
    check("this render will take about 2 min: w (test_work): 10 test units x 4 runs, about "
          "2 min; it runs anyway" in p.stderr, p.stderr)
    # two nodes: the total, the larger first
    g = graph("two", "a = test_work { image = c, units = 1, seconds = 600 }\n"
                     "b = test_work { image = a, units = 2, seconds = 5400 }", "b")
    p = render(g)
    check("this render will take about 1.7 h: b (test_work): 2 test units, about 1.5 h; "
          "a (test_work): 1 test units, about 10 min; it runs anyway" in p.stderr, p.stderr)
    # malformed estimates: the node fails, nothing is written
    for secs, shown in (("-1", "-1"), ("-1e300", "nan")):
        g = graph("bad", "w = test_work { image = c, units = 1e9, seconds = %s }" % secs, "w")
        p = render(g, expect=1)
        check("node 'w' (test_work): declare_work: units = 1e+09, seconds = %s; both must be "
              "finite and >= 0 (a plugin bug)" % shown in p.stderr, p.stderr)
        check(not os.path.exists(os.path.join(d, "bad.exr")), "bad.exr written")


# ---- sweep --------------------------------------------------------------------------------

def test_sweep_space():
    """A sweep whose outputs do not fit on the disk is refused before the reference runs,
    with what it needs and what there is; nothing is written, no temporary left. The same
    sweep fits with more room or a smaller --size."""
    d = fresh_dir("space")
    g = one_output_graph(d)
    out = fresh_dir("space/out")
    args = ["sweep", g, "--vary", "t.key=0.1,0.2,0.3", "--repeat", "1", "-o", out]
    # 3 runs at 640x360: 4 EXR of 3.7 MB and 3 heat maps of 0.9 MB, about 0.017 GiB
    p = run(args, expect=1, extra_env={"LIGHTGRAPH_TEST_FREE_BYTES": "1000000"})
    check(re.search(r"the 3 runs need about 0\.01[0-9]* GiB in '%s' \(4 EXR images of 640x360"
                    % re.escape(out), p.stderr), p.stderr)
    check("has 0.000931 GiB free; nothing was run" in p.stderr, p.stderr)
    check("sweep: reference" not in p.stderr, "the reference ran:\n%s" % p.stderr)
    check(os.listdir(out) == [], "files left: %s" % os.listdir(out))
    # room enough, or the images made small: it runs
    run(args, expect=0, extra_env={"LIGHTGRAPH_TEST_FREE_BYTES": "100000000"})
    check("run-002.exr" in os.listdir(out), os.listdir(out))
    run(args + ["--size", "8x4"], expect=0, extra_env={"LIGHTGRAPH_TEST_FREE_BYTES": "1000000"})
    check(temporaries(out) == [], "temporaries left: %s" % temporaries(out))
    # a malformed hook is reported and ignored (the real free space is used)
    p = run(args + ["--size", "8x4"], expect=0,
            extra_env={"LIGHTGRAPH_TEST_FREE_BYTES": "lots"})
    check("LIGHTGRAPH_TEST_FREE_BYTES='lots' is not a byte count; ignored" in p.stderr,
          p.stderr)


def test_sweep_lazy():
    """While run 1 of 3 repeats (--repeat 1000 keeps it busy), the directory holds the
    temporaries of the reference, the CSV, the script, the plot and run 1, and none of runs 2
    and 3 (which an up-front reservation made); SIGTERM then removes them all."""
    d = fresh_dir("lazy")
    g = one_output_graph(d)
    out = fresh_dir("lazy/out")
    r = Running(["sweep", g, "--vary", "t.key=0.1,0.2,0.3", "--repeat", "1000", "-o", out])
    try:
        started = r.wait_for("sweep: run 1/3", 60)
        time.sleep(0.3)
        tmps = temporaries(out)
        still = r.p.poll() is None and not any("sweep: run 2/3" in l for l in r.lines)
    finally:
        _, err = r.stop()
    check(started, "run 1 did not start:\n%s" % err)
    check(still, "run 1 was over before the directory was read; cannot tell:\n%s" % err)
    names = " ".join(tmps)
    check(".run-000." in names and ".heat-000." in names,
          "run 1's temporaries are not there: %s" % tmps)
    check(".reference." in names and ".sweep." in names, "up-front temporaries: %s" % tmps)
    for later in ("run-001", "run-002", "heat-001", "heat-002"):
        check("." + later + "." not in names,
              "%s's temporary exists before its run: %s" % (later, tmps))
    check(temporaries(out) == [], "SIGTERM left temporaries: %s" % temporaries(out))


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
