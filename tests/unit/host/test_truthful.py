#!/usr/bin/env python3
"""Answers that say what happened (Reliability 3, finding 9), through the real program:

  sweep_vary_items   an empty --vary item ("0.1,,0.2", "0.1,", ",0.1") and one parameter
                     given to two --vary are errors naming the item or the parameter (exit
                     2, nothing run, nothing written); they used to be dropped, or the last
                     --vary to win, and the sweep ran fewer values than written
  cache_folder_entry a non-empty folder where a cache entry belongs cannot be removed: the
                     host says so once, with the reason, bypasses the cache for that entry
                     (the node computes, nothing claims a removal, no write is tried) and
                     leaves the folder as it was; an empty folder is removed, and the entry
                     cached again

usage: test_truthful.py TEST_NAME   (meson runs each test as its own case)

Environment (tests/unit/host/meson.build): LG_EXE, LG_BUILD_ROOT, LG_TEST_PLUGINS.
"""
import os
import sys

import lgrun
from lgrun import Fail, check, write

CORE = os.path.join(os.environ["LG_BUILD_ROOT"], "plugins")
TESTNODES = os.environ["LG_TEST_PLUGINS"]
TMP = lgrun.temp_dir("lg-truthful-test-")


def run(args, expect=None, plugin_path=CORE, cache=None, timeout=120):
    return lgrun.run(args, lgrun.env(plugin_path, cache or os.path.join(TMP, "cache")), expect,
                     timeout)


def fresh_dir(name):
    return lgrun.fresh_dir(TMP, name)


def test_sweep_vary_items():
    d = fresh_dir("sweep")
    g = write(os.path.join(d, "g.lgraph"), """lightgraph 1
c = constant { color = [0.5, 1, 2], width = 8, height = 4 }
t = reinhard { image = c, key = 0.18 }
output t "one.exr"
""")
    out = fresh_dir("sweep/out")
    cases = [(["--vary", "t.key=0.1,,0.2"], "--vary t.key: item 2 of '0.1,,0.2' is empty"),
             (["--vary", "t.key=0.1,"], "--vary t.key: item 2 of '0.1,' is empty"),
             (["--vary", "t.key=,0.1"], "--vary t.key: item 1 of ',0.1' is empty"),
             (["--vary", "t.key=0.1, ,0.2"], "--vary t.key: item 2 of '0.1, ,0.2' is empty"),
             (["--vary", "t.mode=rgb", "--vary", "t.key=0.1,0.2,"],
              "--vary t.key: item 3 of '0.1,0.2,' is empty"),
             (["--vary", "t.key=0.1", "--vary", "t.key=0.2"],
              "--vary t.key is given twice ('t.key=0.1' and 't.key=0.2')"),
             (["--vary", "t.key=0.1,0.3", "--vary", "t.mode=rgb", "--vary", "t.key=0.2"],
              "--vary t.key is given twice ('t.key=0.1,0.3' and 't.key=0.2')")]
    for vary, msg in cases:
        p = run(["sweep", g] + vary + ["--repeat", "1", "-o", out], expect=2)
        check(msg in p.stderr, "%s: %s" % (vary, p.stderr))
        check("sweep: reference" not in p.stderr and "sweep: run" not in p.stderr,
              "%s: something ran: %s" % (vary, p.stderr))
        check(os.listdir(out) == [], "%s: files left: %s" % (vary, os.listdir(out)))
    # what is still accepted: several values, two parameters
    p = run(["sweep", g, "--vary", "t.key=0.1,0.2", "--vary", "t.mode=luminance,rgb",
             "--repeat", "1", "-o", out], expect=0)
    rows = open(os.path.join(out, "sweep.csv")).read().splitlines()
    check(len(rows) == 5, "four runs and a header: %s" % rows)


def cache_graph(d):
    return write(os.path.join(d, "cached.lgraph"), """lightgraph 1
c = constant { color = [0.25, 0.5, 0.75], width = 4, height = 4 }
m = test_cached { image = c, salt = 7 }
output m "mean.hdr"
""")


def test_cache_folder_entry():
    d = fresh_dir("cachefolder")
    cache = os.path.join(d, "cache")
    g = cache_graph(d)
    path = TESTNODES + ":" + CORE
    p = run(["render", g], expect=0, plugin_path=path, cache=cache)
    check("testcache: computed" in p.stderr, p.stderr)
    entries = [f for f in os.listdir(cache) if f.endswith(".lgc")]
    check(len(entries) == 1, "one entry: %s" % entries)
    entry = os.path.join(cache, entries[0])
    # a folder in its place, with a file inside: it cannot be removed
    os.remove(entry)
    os.mkdir(entry)
    write(os.path.join(entry, "keep.txt"), "mine\n")
    for attempt in range(2):
        p = run(["render", g], expect=0, plugin_path=path, cache=cache)
        check("testcache: computed" in p.stderr, "computed again: " + p.stderr)
        said = [l for l in p.stderr.splitlines() if "cache entry" in l]
        check(len(said) == 1 and "removing it" not in said[0]
              and said[0].count("removed") == said[0].count("cannot be removed"),
              "claims a removal: %s" % said)
        check(p.stderr.count(entry) == 1, "said once: " + p.stderr)
        check("cache entry %s cannot be used (it is a directory, not a regular file) and "
              "cannot be removed (Directory not empty): recomputing, and not cached" % entry
              in p.stderr and "remove it yourself" in p.stderr, "says so and why: " + p.stderr)
        check(os.path.isdir(entry) and os.listdir(entry) == ["keep.txt"],
              "the folder is as it was")
        # no stray temporary beside the entry (a write was not even tried)
        check(sorted(os.listdir(cache)) == [entries[0]], "cache: %s" % os.listdir(cache))
    # an empty folder is removed (and said so), then the entry is cached again
    os.remove(os.path.join(entry, "keep.txt"))
    p = run(["render", g], expect=0, plugin_path=path, cache=cache)
    check("testcache: computed" in p.stderr, p.stderr)
    check("cannot be used (it is a directory, not a regular file); removing it and "
          "recomputing" in p.stderr, "the removal is said: " + p.stderr)
    check(os.path.isfile(entry), "the entry is a file again")
    p = run(["render", g], expect=0, plugin_path=path, cache=cache)
    check("testcache: reused" in p.stderr, p.stderr)


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
