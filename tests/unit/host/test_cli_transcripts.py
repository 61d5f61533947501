#!/usr/bin/env python3
"""The program's own words, byte for byte: what render, check, fmt, dot, inspect, diff, sweep,
conform and the plugin scan print, and their exit statuses, on the cases that exercise their
messages (bad usage, bad values, refused files, failed contracts) and on one good run each.

Each group's expected transcript is a file in cli_transcripts/ (GROUP.txt). They were
recorded with the program as it was before issue 22 split host/cli/ into one file per
command and broke its long functions (lg_render_file, lg_cmd_sweep, lg_cmd_diff, conform's
judge_type, the registry's scan_file), so that the refactoring is held to "messages, exit
statuses and outputs stay byte-identical". A change of wording is a change of this file.

usage: test_cli_transcripts.py GROUP            compare (meson runs each group as a test)
       test_cli_transcripts.py GROUP --record   write GROUP.txt from the current program

Temporary, build and source paths read $TMP, $BUILD and $SRC; timings, free space and
memory growth read T (they vary from run to run); conform's notes that a case was slow,
which a loaded or sanitized machine adds, are left out.

Environment (tests/meson.build): LG_EXE, LG_BUILD_ROOT, LG_SOURCE_ROOT, LG_BROKEN_PLUGINS.
"""
import difflib
import os
import re
import shutil
import subprocess
import sys
import tempfile

EXE = os.environ["LG_EXE"]
BUILD = os.environ["LG_BUILD_ROOT"]
SRC = os.environ["LG_SOURCE_ROOT"]
CORE = os.path.join(BUILD, "plugins")
HERE = os.path.dirname(os.path.abspath(__file__))

GRAPH = """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
t = reinhard { image = c, key = 0.18 }
output t "%(tmp)s/g.exr"
"""
TWO = """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
output c "%(tmp)s/a.exr"
output c "%(tmp)s/b.exr"
"""
NONE = """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
"""
# a node type of a plugin the scan refuses: check names every refused plugin and why
BROKEN = """lightgraph 1
x = broken_crash_node { }
output x "%(tmp)s/x.exr"
"""

# A case whose words AddressSanitizer changes (a crash: its handler reports it and exits
# with a status instead of the signal): left out of both transcripts in such a build.
CRASHES = {"LG_TRANSCRIPT_CRASHES": "1"}

# what varies from run to run, and what a machine adds: masked, in this order
MASKS = [
    (re.compile(r"[0-9]+\.[0-9]+ ms|took [0-9.]+ s|[0-9.]+ ms of runs|time +[0-9.]+ ms"), "T"),
    (re.compile(r"[+-][0-9.]+ MiB|[0-9.e+-]+ GiB free|live [0-9]+ -> [0-9]+"), "T"),
    (re.compile(r"\"ms\": [0-9.e+-]+"), "\"ms\": T"),
    (re.compile(r"the live heap \(AddressSanitizer's allocated bytes\)|resident memory"), "MEM"),
    (re.compile(r" and sweep\.png| \(gnuplot not run: install gnuplot-nox\)"), " PLOT"),
]
# conform's note that a case took more than 2 s: present on a slow machine only
DROP = re.compile(r"^.*\btime\b.*\btook T\b.*$\n?|^.*\"check\": \"time\".*$\n?", re.M)


def cases(group):
    """(arguments, plugin path, extra environment) per case; paths under $TMP."""
    broken = os.path.join(BUILD, "tests", "conform", "broken")
    if group == "render":
        return [(a, CORE, {}) for a in [
            ["render", "g.lgraph", "-o", "r.exr"],
            ["render", "g.lgraph", "-o", "r.foo"],
            ["render", "g.lgraph", "-o", "r.txt"],
            ["render", "two.lgraph", "-o", "x.exr"],
            ["render", "none.lgraph"],
            ["render", "g.lgraph", "-o", "nodir/x.exr"],
            ["render", "g.lgraph", "--profile-json", "nodir/p.json"],
            ["render", "g.lgraph", "--size", "0x3"],
            ["render", "g.lgraph", "--frames"],
            ["render", "g.lgraph", "--dt", "1/0"],
            ["render", "g.lgraph", "--bogus"],
            ["render"],
            ["render", "g.lgraph", "h.lgraph"],
            ["render", "g.lgraph", "--set", "t.key=abc"],
            ["render", "g.lgraph", "--set", "t.kye=1"],
            ["render", "g.lgraph", "--output", "o.png", "--set=t.key=0.3", "--exr", "half",
             "--every-frame", "--frames", "2", "--dt", "1/30", "-q"],
            ["render", "g.lgraph", "--output=o.png"],
            ["render", "g.lgraph", "--every-frame=", "-o", "o.png"],
            ["render", "g.lgraph", "--every-frame=t", "--frames", "2", "-o", "o2.png", "-v"],
            ["render", "g.lgraph", "--exr", "quarter"],
            ["render", "g.lgraph", "--gl", "glx"],
            ["render", "g.lgraph", "--dt", "0"],
            ["render", "g.lgraph", "--frames", "x"],
            ["render", "g.lgraph", "--profile-json"],
            ["render", "g.lgraph", "--set="],
            ["render", "g.lgraph", "-i"],
            ["render", "-", "--explainx"],
            ["check", "g.lgraph"],
            ["check", "two.lgraph", "--set", "c.width=x"],
            ["check", "missing.lgraph"],
            ["fmt", "g.lgraph"],
            ["fmt", "-i"],
            ["fmt", "-i", "g.lgraph", "-o"],
            ["dot", "g.lgraph"],
            ["dot", "none.lgraph"],
        ]]
    if group == "introspect":
        return [(a, CORE, {}) for a in [
            ["plugins", "extra"],
            ["inspect"],
            ["inspect", "reinhrd"],
            ["inspect", "constant", "--bogus"],
        ]] + [(["check", "broken.lgraph"], os.environ["LG_BROKEN_PLUGINS"], CRASHES)]
    if group == "diff":
        return [(a, CORE, {}) for a in [
            ["render", "g.lgraph", "-o", "d1.exr", "--set", "t.key=0.2"],
            ["render", "g.lgraph", "-o", "d2.exr"],
            ["diff", "d1.exr", "d2.exr"],
            ["diff", "d1.exr", "d2.exr", "--json"],
            ["diff", "d1.exr", "d2.exr", "--max-rmse", "0.0001", "--max-abs=0.001"],
            ["diff", "d1.exr", "d2.exr", "--heatmap", "h.png", "--heat-max", "0.5"],
            ["diff", "d1.exr", "d2.exr", "--heatmap=h.exr", "--json"],
            ["diff", "d1.exr", "d2.exr", "--heatmap", "h.foo"],
            ["diff", "d1.exr", "d2.exr", "--heatmap", "nodir/h.png"],
            ["diff", "d1.exr", "d2.exr", "--heat-max"],
            ["diff", "d1.exr", "d2.exr", "--heat-max", "-1"],
            ["diff", "d1.exr", "d2.exr", "--frob"],
            ["diff", "d1.exr", "d2.exr", "--json=1"],
            ["diff", "d1.exr", "d2.exr", "--max-rmse="],
            ["diff", "d1.exr", "d2.exr", "--=x"],
            ["diff", "-", "d2.exr"],
            ["diff", "-h", "d1.exr"],
            ["diff", "d1.exr", "--", "--json"],
            ["diff", "d1.exr"],
            ["diff", "d1.exr", "d2.exr", "d3.exr"],
            ["diff", "--", "d1.exr", "missing.exr"],
            ["diff", "d1.exr", os.path.join(SRC, "assets", "images", "GoldenGate.exr")],
            ["diff", "d1.exr", "d1.exr"],
            ["diff", "--help"],
        ]]
    if group == "sweep":
        return [(a, CORE, {}) for a in [
            ["sweep", "g.lgraph", "--vary", "t.key=0.09,0.18", "--vary", "t.mode=luminance,rgb",
             "--ref-set", "t.key=0.18", "--time", "t", "--repeat", "1", "-o", "sw"],
            ["sweep", "g.lgraph", "--vary", "t.kye=1"],
            ["sweep", "g.lgraph", "--vary", "t.key=1", "--repeat"],
            ["sweep", "g.lgraph", "--vary", "t.key=1", "--repeat", "0"],
            ["sweep", "g.lgraph", "--vary=t.key=1"],
            ["sweep", "g.lgraph", "--vary", "t.key=1", "--gl", "glx", "-q"],
            ["sweep", "g.lgraph", "h.lgraph", "--vary", "t.key=1"],
            ["sweep", "-", "--vary", "t.key=1", "--size", "2x2", "--reference"],
            ["sweep", "g.lgraph", "--vary", "t.key=abc", "-o", "sw2"],
            ["sweep", "g.lgraph"],
            ["sweep", "g.lgraph", "--vary", "t.key=0.1", "--reference", "none.lgraph",
             "-o", "sw2"],
            ["sweep", "g.lgraph", "--vary", "t.key=0.1", "--reference", "missing.lgraph"],
            ["sweep", "g.lgraph", "--vary", "t.key=0.1", "-o", "nodir"],
            ["sweep", "g.lgraph", "--vary", "t.key=0.1", "--time", "nosuch", "--repeat", "1",
             "-o", "sw2"],
            ["sweep", "g.lgraph", "--vary", "t.key=0.1,0.2", "--time", "t", "--repeat", "2",
             "--frames", "2", "-o", "sw2", "--set", "t.mode=rgb"],
        ]] + [(["sweep", "g.lgraph", "--vary", "t.key=0.1", "-o", "sw2"], CORE,
               {"LIGHTGRAPH_TEST_FREE_BYTES": "10"})]
    if group == "conform":
        out = [(["conform"], CORE, {})]
        # (resize is left out: its 1x1 case reads what an earlier case left, NaN at times)
        for name in ("control", "nan", "crash", "nogate", "leakaccount"):
            so = os.path.join(broken, "lg_cftest_%s.so" % name)
            out.append((["conform", so, "--quick"], CORE, CRASHES if name == "crash" else {}))
        out.append((["conform", os.path.join(broken, "lg_cftest_nan.so"), "--quick", "--json"],
                    CORE, {}))
        return out
    raise SystemExit("unknown group '%s'" % group)


def sanitized():
    """Whether the program is built with AddressSanitizer (as test_memory_limits.py asks)."""
    p = subprocess.run(["ldd", EXE], capture_output=True, text=True)
    return "libasan" in p.stdout


def blocks(text):
    """The transcript's cases, each from its '$ ' line."""
    return re.split(r"(?m)^(?=\$ )", text)


def transcript(group, skip_crashes):
    tmp = tempfile.mkdtemp(prefix="lg-cli-transcript-")
    try:
        for name, text in (("g", GRAPH), ("two", TWO), ("none", NONE), ("broken", BROKEN)):
            with open(os.path.join(tmp, name + ".lgraph"), "w") as f:
                f.write(text % {"tmp": tmp})
        for d in ("sw", "sw2"):
            os.makedirs(os.path.join(tmp, d))
        out = []
        for args, plugin_path, extra in cases(group):
            if skip_crashes and extra is CRASHES:
                continue
            env = dict(os.environ)
            env["LIGHTGRAPH_PLUGIN_PATH"] = plugin_path
            env["LIGHTGRAPH_CACHE_DIR"] = os.path.join(tmp, "cache")
            env.update(extra)
            p = subprocess.run([EXE] + args, env=env, cwd=tmp, capture_output=True, text=True,
                               timeout=120)
            out.append("$ %s%s\nexit %d\n--- stdout\n%s--- stderr\n%s" % (
                "".join("%s=%s " % kv for kv in sorted(extra.items())), " ".join(args),
                p.returncode, p.stdout, p.stderr))
            if args[0] == "sweep" and p.returncode == 0:
                for d in ("sw", "sw2"):
                    csv = os.path.join(tmp, d, "sweep.csv")
                    if os.path.exists(csv) and "-o" in args and args[args.index("-o") + 1] == d:
                        # the timings columns vary (time_ms and time_min_ms after the
                        # varied parameters, time_max_ms and ref_ms last, issue 23); the
                        # rest is the sweep's result
                        rows = [re.sub(r",[0-9.]+,([0-9.]+)?$", ",T,T", re.sub(
                            r"^([^,]*(?:,[^,]*){%d}),[0-9.]+,[0-9.]+," % (
                                args.count("--vary")), r"\1,T,T,", r))
                            for r in open(csv).read().splitlines()]
                        out.append("--- %s/sweep.csv\n%s\n" % (d, "\n".join(rows)))
        text = "".join(out)
        # longest first: the build and source roots may sit inside one another
        for path, name in sorted(((tmp, "$TMP"), (BUILD, "$BUILD"), (SRC, "$SRC")),
                                 key=lambda x: -len(x[0])):
            text = text.replace(path, name)
        for rx, rep in MASKS:
            text = rx.sub(rep, text)
        return DROP.sub("", text)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def main():
    group = sys.argv[1]
    path = os.path.join(HERE, "cli_transcripts", group + ".txt")
    record = sys.argv[2:] == ["--record"]
    skip = not record and sanitized()
    got = transcript(group, skip)
    if record:
        with open(path, "w") as f:
            f.write(got)
        print("wrote", path)
        return 0
    want = open(path).read()
    if skip:
        print("AddressSanitizer build: the cases of a crashing plugin are left out")
        want = "".join(b for b in blocks(want) if "LG_TRANSCRIPT_CRASHES=1 " not in b)
    if got == want:
        print("%s: %d lines as recorded" % (group, got.count("\n")))
        return 0
    sys.stdout.writelines(difflib.unified_diff(want.splitlines(True), got.splitlines(True),
                                               "recorded " + group + ".txt", "now"))
    print("\n%s: the program's output differs from its recorded transcript (above); if the "
          "change is meant, record it again: %s %s --record" % (group, sys.argv[0], group))
    return 1


if __name__ == "__main__":
    sys.exit(main())
