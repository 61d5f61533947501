#!/usr/bin/env python3
"""All-or-nothing outputs and scans that cannot hang (issue 8), through the real program:
render, sweep and diff check every value and destination before any work, write into
temporaries beside the destinations and rename them all only when everything succeeded; a
missing directory is refused, never created; SIGTERM/SIGINT leave no temporary; a plugin
whose constructor blocks, or whose descriptor is huge, is refused within a bounded time and
read, and the other plugins still work.

usage: test_outputs.py TEST_NAME   (meson runs each test as its own case)

Environment (tests/unit/host/meson.build): LG_EXE, LG_BUILD_ROOT, LG_HOSTILE_PLUGINS.
"""
import os
import shutil
import resource
import signal
import stat
import subprocess
import sys
import time

import lgrun
from lgrun import Fail, check, write

EXE = lgrun.EXE
CORE = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
HOSTILE = os.environ["LG_HOSTILE_PLUGINS"]
TMP = lgrun.temp_dir("lg-outputs-test-")


def env_for(plugin_path=CORE, extra=None):
    return lgrun.env(plugin_path, os.path.join(TMP, "cache"), extra,
                     drop=["LIGHTGRAPH_SCAN_TIMEOUT"])


def run(args, expect=None, plugin_path=CORE, extra_env=None, preexec=None, timeout=60):
    return lgrun.run(args, env_for(plugin_path, extra_env), expect, timeout,
                     preexec_fn=preexec)


def fresh_dir(name):
    return lgrun.fresh_dir(TMP, name)


def temporaries(d):
    """The commit's temporaries (".NAME.lgtmp-XXXXXX.EXT") and the image writer's own."""
    return [n for n in os.listdir(d) if n.startswith(".")]


def two_output_graph(d, second_node="c2", second="b.hdr"):
    """a.png: 8x4 (a few hundred bytes); b.hdr from c2: 4x4096, written flat (64 KiB)."""
    return write(os.path.join(d, "two.lgraph"), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
c2 = constant { color = [0.25, 0.5, 1], width = 4, height = 4096 }
t = reinhard { image = c, key = 0.18 }
output t "a.png"
output %s "%s"
""" % (second_node, second))


def one_output_graph(d, out="one.exr", extra="", name="one.lgraph"):
    return write(os.path.join(d, name), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
t = reinhard { image = c, key = 0.18 }
%s
output t "%s"
""" % (extra, out))


# ---- render ---------------------------------------------------------------------------------

def test_two_outputs():
    """The second destination is a directory, then a FIFO: refused before anything runs,
    the first destination's previous file untouched, no temporary left; then both
    written together."""
    d = fresh_dir("two")
    g = two_output_graph(d)
    write(os.path.join(d, "a.png"), "previous a")
    os.mkdir(os.path.join(d, "b.hdr"))
    p = run(["render", g], expect=1)
    check("cannot write '%s': it is a directory; nothing was run" % os.path.join(d, "b.hdr")
          in p.stderr, p.stderr)
    check(open(os.path.join(d, "a.png")).read() == "previous a", "a.png was replaced")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    os.rmdir(os.path.join(d, "b.hdr"))
    os.mkfifo(os.path.join(d, "b.hdr"))
    p = run(["render", g], expect=1, timeout=20)
    check("it is a FIFO, not a regular file" in p.stderr, p.stderr)
    check(open(os.path.join(d, "a.png")).read() == "previous a", "a.png was replaced")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    os.unlink(os.path.join(d, "b.hdr"))
    # a destination with an unknown image format, given by -o: bad usage, as before
    run(["render", one_output_graph(d), "-o", os.path.join(d, "x.bmp")], expect=2)
    # now everything can be written: both files, with the mode of any new file
    run(["render", g], expect=0)
    a = open(os.path.join(d, "a.png"), "rb").read()
    check(a.startswith(b"\x89PNG"), "a.png is a PNG now")
    b = os.path.join(d, "b.hdr")
    check(os.path.getsize(b) > 60000, "b.hdr written flat: %d bytes" % os.path.getsize(b))
    umask = os.umask(0)
    os.umask(umask)
    mode = os.stat(b).st_mode & 0o777
    check(mode == 0o666 & ~umask, "mode %o, expected %o" % (mode, 0o666 & ~umask))
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))


def test_write_failure():
    """A write that fails after every check passed (the file-size limit stops the 64 KiB
    second output, the first fits): exit 1, neither output committed, the previous first
    file unchanged, no temporary left."""
    d = fresh_dir("wfail")
    g = two_output_graph(d)
    write(os.path.join(d, "a.png"), "previous a")

    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (8192, 8192))

    p = run(["render", g], expect=1, preexec=limit,
            extra_env={"LIGHTGRAPH_CACHE_DIR": os.path.join(d, "nocache")})
    check("b.hdr" in p.stderr and "File too large" in p.stderr, p.stderr)
    check(open(os.path.join(d, "a.png")).read() == "previous a", "a.png was replaced")
    check(not os.path.exists(os.path.join(d, "b.hdr")), "b.hdr was written")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    # --profile-json is part of the same commit: its destination checked first too
    os.mkdir(os.path.join(d, "prof.json"))
    g1 = one_output_graph(d)
    p = run(["render", g1, "--profile-json", os.path.join(d, "prof.json")], expect=1)
    check("--profile-json: cannot write" in p.stderr and "it is a directory" in p.stderr,
          p.stderr)
    check(not os.path.exists(os.path.join(d, "one.exr")), "one.exr was written")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))


def test_missing_dir():
    """One policy for every command: a missing directory is refused with its name, never
    created."""
    d = fresh_dir("missing")
    g = one_output_graph(d)
    missing = os.path.join(d, "no", "such")
    msg = "the directory '%s' does not exist (lightgraph does not create directories" % missing
    p = run(["render", g, "-o", os.path.join(missing, "x.png")], expect=1)
    check(msg in p.stderr, p.stderr)
    # an output statement into a missing directory
    g2 = one_output_graph(d, out="no/such/y.exr", name="y.lgraph")
    p = run(["render", g2], expect=1)
    check(msg in p.stderr, p.stderr)
    p = run(["render", g, "--profile-json", os.path.join(missing, "p.json")], expect=1)
    check(msg in p.stderr, p.stderr)
    check(not os.path.exists(os.path.join(d, "one.exr")), "one.exr written")
    # sweep -o DIR
    p = run(["sweep", g, "--vary", "t.key=0.1,0.2", "--repeat", "1", "-o", missing], expect=1)
    check(msg in p.stderr and "nothing was run" in p.stderr, p.stderr)
    check("sweep: reference" not in p.stderr, "the reference ran: " + p.stderr)
    # diff --heatmap
    run(["render", g], expect=0)
    one = os.path.join(d, "one.exr")
    p = run(["diff", one, one, "--heatmap", os.path.join(missing, "h.png")], expect=1)
    check(msg in p.stderr, p.stderr)
    check(not os.path.exists(os.path.join(d, "no")), "a directory was created")
    # a path through a file is no directory either
    p = run(["render", g, "-o", os.path.join(one, "x.png")], expect=1)
    check("'%s' is not a directory" % one in p.stderr or "Not a directory" in p.stderr, p.stderr)


# ---- sweep ----------------------------------------------------------------------------------

def test_sweep_values():
    """Every --vary value is checked against the parameter's type and range before the
    first run: nothing runs, no file is written."""
    d = fresh_dir("sweepv")
    g = one_output_graph(d)
    out = fresh_dir("sweepv/out")
    cases = [("t.key=0.1,abc,0.3", "the value 'abc' is refused"),
             ("t.key=0.1,0.2,-5", "the value '-5' is refused"),
             ("t.key=0.1,11", "the value '11' is refused"),
             ("t.mode=luminance,sepia", "the value 'sepia' is refused")]
    for vary, msg in cases:
        p = run(["sweep", g, "--vary", vary, "--repeat", "1", "-o", out], expect=2)
        check(msg in p.stderr and "nothing was run" in p.stderr, vary + ": " + p.stderr)
        check("sweep: reference" not in p.stderr and "sweep: run" not in p.stderr,
              vary + ": something ran: " + p.stderr)
        check(os.listdir(out) == [], vary + ": files left: %s" % os.listdir(out))
    # -5 names the range
    p = run(["sweep", g, "--vary", "t.key=-5", "-o", out], expect=2)
    check("out of range" in p.stderr, p.stderr)
    # a --ref-set that the reference refuses is caught up front too
    p = run(["sweep", g, "--vary", "t.key=0.1", "--ref-set", "t.key=abc", "-o", out], expect=2)
    check("reference" in p.stderr and "nothing was run" in p.stderr, p.stderr)
    check(os.listdir(out) == [], "files left: %s" % os.listdir(out))


def test_sweep_outputs():
    """A sweep that fails after its first runs (--time names no node) commits nothing and
    leaves the previous sweep's files as they were; a good one commits every file."""
    d = fresh_dir("sweepo")
    g = one_output_graph(d)
    out = fresh_dir("sweepo/out")
    write(os.path.join(out, "sweep.csv"), "previous csv\n")
    p = run(["sweep", g, "--vary", "t.key=0.1,0.3", "--repeat", "1", "--time", "nosuchnode",
             "-o", out], expect=2)
    check("sweep: reference" in p.stderr and "no kept node of that name ran" in p.stderr,
          p.stderr)
    check("nothing was written to" in p.stderr, p.stderr)
    check(sorted(os.listdir(out)) == ["sweep.csv"], "files left: %s" % os.listdir(out))
    check(open(os.path.join(out, "sweep.csv")).read() == "previous csv\n", "csv replaced")
    # the destination of one run is a directory: refused before the reference runs
    os.mkdir(os.path.join(out, "run-001.exr"))
    p = run(["sweep", g, "--vary", "t.key=0.1,0.3", "--repeat", "1", "-o", out], expect=1)
    check("run-001.exr': it is a directory; nothing was run" in p.stderr, p.stderr)
    check("sweep: reference" not in p.stderr, p.stderr)
    check(sorted(os.listdir(out)) == ["run-001.exr", "sweep.csv"], "%s" % os.listdir(out))
    os.rmdir(os.path.join(out, "run-001.exr"))
    # all good: every file at once, no temporary
    p = run(["sweep", g, "--vary", "t.key=0.1,0.3", "--repeat", "1", "-o", out], expect=0)
    names = set(os.listdir(out))
    want = {"reference.exr", "run-000.exr", "run-001.exr", "heat-000.png", "heat-001.png",
            "sweep.csv", "sweep.gp"}
    check(want <= names, "missing: %s" % (want - names))
    check(temporaries(out) == [], "temporaries left: %s" % temporaries(out))
    rows = open(os.path.join(out, "sweep.csv")).read().splitlines()
    check(len(rows) == 3 and rows[0].startswith("run,t.key,"), rows)
    # the script runs as written, outside the sweep (when gnuplot is installed)
    gp = open(os.path.join(out, "sweep.gp")).read()
    check("data = 'sweep.csv'" in gp and "out = 'sweep.png'" in gp, gp)
    if "sweep.png" in names:
        check(open(os.path.join(out, "sweep.png"), "rb").read(4) == b"\x89PNG", "a PNG plot")


def test_diff_heatmap():
    """diff --heatmap checks its destination before reading the images."""
    d = fresh_dir("diffh")
    g = one_output_graph(d)
    run(["render", g], expect=0)
    one = os.path.join(d, "one.exr")
    os.mkdir(os.path.join(d, "h.png"))
    p = run(["diff", one, one, "--heatmap", os.path.join(d, "h.png")], expect=1)
    check("--heatmap: cannot write" in p.stderr and "it is a directory" in p.stderr, p.stderr)
    os.rmdir(os.path.join(d, "h.png"))
    run(["diff", one, one, "--heatmap", os.path.join(d, "h.png")], expect=0)
    check(open(os.path.join(d, "h.png"), "rb").read(4) == b"\x89PNG", "heat map written")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))


# ---- signals --------------------------------------------------------------------------------

def test_signal():
    """SIGTERM, then SIGINT, during a long render: the process dies of the signal, its
    temporaries are gone, the previous output is untouched."""
    d = fresh_dir("sig")
    g = write(os.path.join(d, "slow.lgraph"), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 256, height = 256 }
t = reinhard { image = c, key = 0.18 }
output t "slow.exr"
""")
    write(os.path.join(d, "slow.exr"), "previous")
    for sig in (signal.SIGTERM, signal.SIGINT):
        p = subprocess.Popen([EXE, "render", g, "--every-frame", "--frames", "1000000"],
                             env=env_for(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        deadline = time.time() + 20
        while not temporaries(d) and time.time() < deadline and p.poll() is None:
            time.sleep(0.02)
        check(temporaries(d), "the render reserved its temporary before running")
        time.sleep(0.3)
        check(p.poll() is None, "still rendering")
        p.send_signal(sig)
        try:
            _, err = p.communicate(timeout=20)
        except subprocess.TimeoutExpired:
            p.kill()
            raise Fail("did not stop on %s" % sig)
        check(p.returncode == -sig, "died of %s: exit %s %s" % (sig, p.returncode, err))
        check(temporaries(d) == [], "%s left temporaries: %s" % (sig, temporaries(d)))
        check(open(os.path.join(d, "slow.exr")).read() == "previous", "slow.exr replaced")


# ---- files nodes write (LG_ROLE_OUTPUT_FILE, ABI 2.7) ---------------------------------------

TEST_PLUGINS = os.environ.get("LG_TEST_PLUGINS", "")


def writer_graph(d, extra, name="w.lgraph", out="out.exr"):
    """test_file_writer (tests/plugins/testnodes/testfile.c) between a constant and the
    render's one output."""
    return write(os.path.join(d, name), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
w = test_file_writer { image = c%s }
output w "%s"
""" % (", " + extra if extra else "", out))


def test_node_file():
    """A file a node writes goes through the render's outputs: a FIFO (or a link to one) or a
    destination another output names is refused before anything runs, the FIFO untouched;
    a failure after the node wrote leaves neither the file nor a temporary; success writes
    it with the other outputs."""
    d = fresh_dir("nodefile")
    tp = TEST_PLUGINS + ":" + CORE
    fifo = os.path.join(d, "dump.txt")
    os.mkfifo(fifo)
    p = run(["render", writer_graph(d, 'file = "dump.txt"')], expect=1, plugin_path=tp,
            timeout=20)
    check("node 'w', parameter file: cannot write '%s': it is a FIFO, not a regular file; "
          "nothing was run" % fifo in p.stderr, p.stderr)
    check(stat.S_ISFIFO(os.lstat(fifo).st_mode), "the FIFO was replaced")
    check(not os.path.exists(os.path.join(d, "out.exr")), "out.exr written")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    # a symbolic link to a FIFO is judged by what it points to
    link = os.path.join(d, "link.txt")
    os.symlink(fifo, link)
    p = run(["render", writer_graph(d, 'file = "link.txt"')], expect=1, plugin_path=tp,
            timeout=20)
    check("cannot write '%s': it is a FIFO" % link in p.stderr, p.stderr)
    check(os.path.islink(link) and stat.S_ISFIFO(os.lstat(fifo).st_mode), "link or FIFO changed")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    # the render's own output and the node's file at one destination: one would be lost
    p = run(["render", writer_graph(d, 'file = "out.exr"')], expect=1, plugin_path=tp)
    check("cannot write '%s' as node 'w' (file): it is already an output of the render"
          % os.path.join(d, "out.exr") in p.stderr, p.stderr)
    check(temporaries(d) == [] and not os.path.exists(os.path.join(d, "out.exr")),
          "files left: %s" % os.listdir(d))
    # the node writes, then fails: no file, the previous one untouched, no temporary
    dump = os.path.join(d, "dump2.txt")
    write(dump, "previous\n")
    p = run(["render", writer_graph(d, 'file = "dump2.txt", fail = true')], expect=1,
            plugin_path=tp)
    check("failing as asked" in p.stderr, p.stderr)
    check(open(dump).read() == "previous\n", "dump2.txt replaced by a failed render")
    check(not os.path.exists(os.path.join(d, "out.exr")), "out.exr written")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    # a parameter that is not an output file cannot be written through
    p = run(["render", writer_graph(d, "wrong_key = true")], expect=1, plugin_path=tp)
    check("parameter 'text' is not a file the node writes" in p.stderr, p.stderr)
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    # success: written with the other output, the mode of any new file
    p = run(["render", writer_graph(d, 'file = "dump2.txt", text = "mesh\\n"')], expect=0,
            plugin_path=tp)
    check(open(dump).read() == "mesh\n", "dump2.txt: %r" % open(dump).read())
    check(os.path.exists(os.path.join(d, "out.exr")), "out.exr not written")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    # a node that does not run (no output reaches it) writes nothing, and no empty file
    # takes the place of the previous one
    write(dump, "previous\n")
    g = write(os.path.join(d, "culled.lgraph"), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
w = test_file_writer { image = c, file = "dump2.txt" }
output c "out.exr"
""")
    run(["render", g], expect=0, plugin_path=tp)
    check(open(dump).read() == "previous\n", "dump2.txt replaced by a node that did not run")
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))
    # sweep: checked before the reference runs, then the last run's file with the others
    out = fresh_dir("nodefile/sweep")
    os.unlink(dump)
    os.mkfifo(dump)
    g = writer_graph(d, 'file = "dump2.txt"', name="s.lgraph")
    p = run(["sweep", g, "--vary", "w.text=a,b", "--repeat", "1", "-o", out], expect=1,
            plugin_path=tp, timeout=20)
    check("it is a FIFO" in p.stderr and "nothing was run" in p.stderr, p.stderr)
    check(stat.S_ISFIFO(os.lstat(dump).st_mode), "the FIFO was replaced")
    check(temporaries(d) == [] and temporaries(out) == [], "temporaries left")
    os.unlink(dump)
    run(["sweep", g, "--vary", "w.text=a,b", "--repeat", "1", "-o", out], expect=0,
        plugin_path=tp)
    check(open(dump).read() == "b", "the last run's file: %r" % open(dump).read())
    check(temporaries(d) == [] and temporaries(out) == [], "temporaries left")


# ---- temporaries of killed processes --------------------------------------------------------

def dead_pid():
    """The pid of a process that has exited (and been reaped)."""
    p = subprocess.Popen(["true"])
    p.wait()
    return p.pid


def wait_for(cond, what, timeout=20):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if cond():
            return
        time.sleep(0.02)
    raise Fail("timed out waiting for " + what)


def test_stale_output_temporaries():
    """Temporaries that a dead process left beside an output (named with its pid) are
    removed by the next render that writes there; a live process's, and names that are not
    exactly a temporary's, are kept. A render killed with SIGKILL leaves its temporary, and
    the next render removes it."""
    d = fresh_dir("stale")
    g = one_output_graph(d)
    dead, live = dead_pid(), os.getpid()
    stale = [".one.lgtmp-%d-aB3xYz.exr" % dead, ".one.lgtmp-%d-aB3xYz.exr.old" % dead,
             "..one.lgtmp-%d-aB3xYz.exr.Q1w2E3" % dead]
    kept = [".one.lgtmp-%d-aB3xYz.exr" % live, ".one.lgtmp-aB3xYz.exr",
            ".one.lgtmp-%d-aB3xYz.exr.bak" % dead, ".one.lgtmp-%d-aB3.exr" % dead,
            ".other.lgtmp-%d-aB3xYz.exr" % dead]
    for n in stale + kept:
        write(os.path.join(d, n), "")
    run(["render", g], expect=0)
    left = set(temporaries(d))
    check(not (left & set(stale)), "stale temporaries kept: %s" % (left & set(stale)))
    check(left == set(kept), "kept %s, expected %s" % (left, kept))
    for n in kept:
        os.unlink(os.path.join(d, n))
    # SIGKILL: nothing can clean up, so the temporary stays, named with the pid ...
    slow = write(os.path.join(d, "slow.lgraph"), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 64, height = 64 }
t = reinhard { image = c, key = 0.18 }
output t "one.exr"
""")
    p = subprocess.Popen([EXE, "render", slow, "--every-frame", "--frames", "1000000"],
                         env=env_for(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        wait_for(lambda: temporaries(d), "the render's temporary")
    finally:
        p.kill()
        p.wait()
    left = temporaries(d)
    check(left == [".one.lgtmp-%d-%s" % (p.pid, left[0][-10:])] if left else False,
          "SIGKILL left %s (pid %d)" % (left, p.pid))
    # ... and the next render removes it
    run(["render", g], expect=0)
    check(temporaries(d) == [], "temporaries left: %s" % temporaries(d))


def cached_graph(d, salt):
    return write(os.path.join(d, "cached%d.lgraph" % salt), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 4, height = 4 }
m = test_cached { image = c, salt = %d }
output m "mean.hdr"
""" % salt)


def cache_temporaries(cache):
    return [n for n in os.listdir(cache) if ".lgc.tmp" in n] if os.path.isdir(cache) else []


def test_cache_signal():
    """SIGINT in the middle of writing a cache entry removes the entry's temporary
    (LIGHTGRAPH_TEST_CACHE_WRITE_PAUSE holds the write half way); SIGKILL leaves it, and the
    next render removes it, keeping a live process's."""
    d = fresh_dir("cachesig")
    cache = os.path.join(d, "cache")
    tp = TEST_PLUGINS + ":" + CORE
    env = dict(env_for(tp), LIGHTGRAPH_CACHE_DIR=cache, LIGHTGRAPH_TEST_CACHE_WRITE_PAUSE="30")
    for sig, salt in ((signal.SIGINT, 1), (signal.SIGTERM, 2), (signal.SIGKILL, 3)):
        p = subprocess.Popen([EXE, "render", cached_graph(d, salt)], env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        try:
            wait_for(lambda: any(os.path.getsize(os.path.join(cache, n)) > 0
                                 for n in cache_temporaries(cache)),
                     "the cache entry's temporary, half written")
            check(p.poll() is None, "still writing")
            p.send_signal(sig)
            _, err = p.communicate(timeout=20)
        finally:
            if p.poll() is None:
                p.kill()
                p.wait()
        check(p.returncode == -sig, "died of %s: exit %s %s" % (sig, p.returncode, err))
        left = cache_temporaries(cache)
        if sig != signal.SIGKILL:
            check(left == [], "%s left %s" % (sig, left))
        else:
            check(len(left) == 1 and left[0].endswith(".lgc.tmp%d" % p.pid),
                  "SIGKILL left %s (pid %d)" % (left, p.pid))
        check(not os.path.exists(os.path.join(d, "mean.hdr")), "mean.hdr written")
    # a live process's temporary and names of another pattern are kept; the dead one goes
    live = "test_cached-%s.lgc.tmp%d" % ("0" * 32, os.getpid())
    other = ["test_cached-%s.lgc.tmp%dx" % ("0" * 32, dead_pid()), "notes.lgc.tmp1"]
    for n in [live] + other:
        write(os.path.join(cache, n), "")
    p = run(["render", cached_graph(d, 4)], expect=0, plugin_path=tp,
            extra_env={"LIGHTGRAPH_CACHE_DIR": cache})
    check("testcache: computed" in p.stderr, p.stderr)
    left = sorted(n for n in os.listdir(cache) if ".lgc.tmp" in n)
    check(left == sorted([live] + other), "left %s" % left)


# ---- plugin scanning ------------------------------------------------------------------------

def test_scan_timeout():
    """A plugin whose constructor never returns is refused after LIGHTGRAPH_SCAN_TIMEOUT,
    naming the file and the limit; the other plugins still work. The limit applies to every
    scan, the real plugins' too: 3 s leaves an ASan build on a loaded machine room (a scan
    takes 20-50 ms in a plain build; 0.5 s was too tight under ASan with CI's load)."""
    d = fresh_dir("scan")
    g = one_output_graph(d)
    alone = os.path.join(d, "plugins")
    os.makedirs(alone)
    block = os.path.join(alone, "lg_hostile_block.so")
    shutil.copy(os.path.join(HOSTILE, "lg_hostile_block.so"), block)
    path = alone + ":" + CORE
    t0 = time.time()
    p = run(["check", g], expect=0, plugin_path=path,
            extra_env={"LIGHTGRAPH_SCAN_TIMEOUT": "3"}, timeout=60)
    took = time.time() - t0
    check(took < 20, "check took %.1f s" % took)
    check("refusing plugin %s: its scan did not finish within 3 s" % block in p.stderr,
          p.stderr)
    check(": ok (" in p.stdout, p.stdout)
    # rendering with the other plugins still works
    run(["render", g], expect=0, plugin_path=path, extra_env={"LIGHTGRAPH_SCAN_TIMEOUT": "3"},
        timeout=60)
    check(os.path.exists(os.path.join(d, "one.exr")), "rendered")
    # the refusal is listed like any other
    p = run(["plugins"], plugin_path=path, extra_env={"LIGHTGRAPH_SCAN_TIMEOUT": "3"},
            timeout=60)
    check("lg_hostile_block.so" in p.stdout + p.stderr, p.stdout + p.stderr)
    # malformed values are reported and the default used (checked on core plugins only, so
    # that the default 5 s is not waited for)
    for bad in ["abc", "0", "-1", "inf", "nan", "1e9", "2s"]:
        p = run(["check", g], expect=0, extra_env={"LIGHTGRAPH_SCAN_TIMEOUT": bad})
        check("LIGHTGRAPH_SCAN_TIMEOUT='%s' is not a number of seconds in (0, 3600]; using the "
              "default 5 s" % bad in p.stderr, bad + ": " + p.stderr)


def test_scan_size():
    """A plugin whose serialised descriptor is 8 MiB is refused after a bounded read (alone
    in its folder, with a generous timeout: the size cap is what is tested, not the clock)."""
    d = fresh_dir("scansize")
    g = one_output_graph(d)
    alone = os.path.join(d, "plugins")
    os.makedirs(alone)
    huge = os.path.join(alone, "lg_hostile_huge.so")
    shutil.copy(os.path.join(HOSTILE, "lg_hostile_huge.so"), huge)
    p = run(["check", g], expect=0, plugin_path=alone + ":" + CORE,
            extra_env={"LIGHTGRAPH_SCAN_TIMEOUT": "60"}, timeout=120)
    check("refusing plugin %s: its scan result is larger than the 4 MiB limit" % huge
          in p.stderr, p.stderr)


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
