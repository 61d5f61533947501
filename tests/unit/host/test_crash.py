#!/usr/bin/env python3
"""A plugin's crash during `render` and `sweep` (host/exec.c, LG_GUARD_EXIT): the message
names the node, its type, its plugin and its file, the callback and the signal; the exit
status is 3; no output file is made, a previous one is left as it was, and no temporary is
left (the outputs', a node's own file's, --profile-json's).

usage: test_crash.py TEST_NAME   (meson runs each test as its own case)

Environment (tests/unit/host/meson.build): LG_EXE, LG_CRASH_PLUGINS (the folder of
tests/plugins/crash/lg_testcrash.so; core comes from the build tree).
"""
import os
import sys

import lgrun
from lgrun import Fail, check

CRASH = os.environ["LG_CRASH_PLUGINS"]
SO = os.path.join(CRASH, "lg_testcrash.so")
TMP = lgrun.temp_dir("lg-crash-test-")
OLD = b"the previous file\n"
SIGNALS = {"segv": "SIGSEGV", "bus": "SIGBUS", "fpe": "SIGFPE", "ill": "SIGILL",
           "abrt": "SIGABRT", "stack": "SIGSEGV"}


def run(args, cwd, threads=None, timeout=120):
    extra = {"LIGHTGRAPH_THREADS": str(threads)} if threads else None
    return lgrun.run(args, lgrun.env(CRASH, os.path.join(TMP, "cache"), extra), timeout=timeout,
                     cwd=cwd)


def folder(name):
    return lgrun.fresh_dir(TMP, name)


def write_graph(d, params):
    return lgrun.write(os.path.join(d, "g.lgraph"),
                       'lightgraph 1\nc = constant { color = [0.25, 0.5, 1] }\n'
                       'crashy = test_crash { image = c%s }\noutput crashy "out.png"\n'
                       % "".join(", %s = %s" % kv for kv in params.items()))


def expect_crash(p, d, phase, signal, what):
    """Exit 3, one message naming node, type, plugin, file, callback and signal, and in `d`
    only what was there before (g.lgraph, the previous out.png)."""
    err = p.stderr
    check(p.returncode == 3, "%s: exit %d, expected 3\nstderr:\n%s" % (what, p.returncode, err))
    want = ("lightgraph: error: node 'crashy' (test_crash): crashed in %s() (plugin testcrash, "
            "%s; signal " % (phase, SO))
    check(want in err, "%s: the message lacks\n  %s\nstderr:\n%s" % (what, want, err))
    line = err[err.index(want):].split("\n")[0]
    check(", %s, " % SIGNALS[signal] in line and "exit status 3" in line,
          "%s: the message does not name %s and the status: %s" % (what, SIGNALS[signal], line))
    check(err.count("crashed in") == 1, "%s: said more than once:\n%s" % (what, err))
    left = sorted(os.listdir(d))
    check(left == ["g.lgraph", "out.png"], "%s: files left: %s" % (what, left))
    with open(os.path.join(d, "out.png"), "rb") as f:
        check(f.read() == OLD, "%s: the previous out.png was changed" % what)


def crash_case(phase, signal, extra=None, args=(), threads=None):
    what = "%s/%s%s" % (phase, signal, " " + str(extra) if extra else "")
    d = folder("%s-%s-%d" % (phase, signal, len(os.listdir(TMP))))
    params = {"phase": '"%s"' % phase, "signal": '"%s"' % signal}
    params.update(extra or {})
    g = write_graph(d, params)
    with open(os.path.join(d, "out.png"), "wb") as f:
        f.write(OLD)
    p = run(["render", g, "--size", "8x8"] + list(args), d, threads)
    expect_crash(p, d, phase, signal, what)
    return p


# ---- tests -----------------------------------------------------------------------------

def test_none():
    """The same graph without a crash renders: the plugin, the graph and the checks of the
    other tests are sound (a crash test that could not fail would pass here too)."""
    d = folder("none")
    g = write_graph(d, {"file": '"dump.txt"'})
    p = run(["render", g, "--size", "8x8", "--profile-json", "p.json"], d)
    check(p.returncode == 0, "exit %d:\n%s" % (p.returncode, p.stderr))
    check(sorted(os.listdir(d)) == ["dump.txt", "g.lgraph", "out.png", "p.json"],
          "files: %s" % sorted(os.listdir(d)))
    check("crashed" not in p.stderr, p.stderr)


def test_create():
    crash_case("create", "segv")


def test_prepare():
    crash_case("prepare", "bus")


def test_execute():
    """execute, after the node wrote its own file, with --profile-json: neither remains."""
    crash_case("execute", "fpe", {"file": '"dump.txt"'}, ["--profile-json", "p.json"])


def test_destroy():
    """destroy runs after every output was written to its temporary: still none is kept."""
    crash_case("destroy", "ill", {"file": '"dump.txt"'})


def test_abort():
    crash_case("execute", "abrt")


def test_stack():
    """A stack overflow: the handler runs on a stack of its own."""
    crash_case("execute", "stack")


def test_pool():
    """A crash on a thread of the CPU pool (lg_parallel_for) while execute waits for it."""
    crash_case("execute", "segv", {"on_pool": "true"}, threads=2)


def test_sweep():
    """sweep shares render's path: the reference and a first run succeed, the second run
    crashes; nothing the sweep wrote is left in its folder."""
    d = folder("sweep")
    g = write_graph(d, {"phase": '"none"', "signal": '"segv"'})
    out = folder("sweep/out")
    p = run(["sweep", g, "--vary", "crashy.phase=none,execute", "--repeat", "1", "--size",
             "8x8", "-o", out], d)
    check(p.returncode == 3, "exit %d:\n%s" % (p.returncode, p.stderr))
    check("run 2/2" in p.stderr, "the crash was not in the second run:\n" + p.stderr)
    check("crashed in execute() (plugin testcrash, %s; signal " % SO in p.stderr,
          "message:\n" + p.stderr)
    check(os.listdir(out) == [], "files left: %s" % os.listdir(out))


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
