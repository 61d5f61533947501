#!/usr/bin/env python3
"""Where the on-disk cache lives, and when it is refused (issue 8; host/cache.c, docs/sdk.md).

usage: test_cache_dir.py TEST_NAME   (meson runs each test as its own case)

Each test runs the real program on a graph with a cached node (test_cached, from the test
plugins) in a scratch folder, with HOME, XDG_CACHE_HOME, LIGHTGRAPH_CACHE_DIR and TMPDIR
set or removed as the case needs, so that nothing outside the scratch folder is touched.

  private_fallback   no HOME, no XDG_CACHE_HOME: a private TMPDIR/lightgraph-cache-UID made
                     0700 and reused (never /tmp/.cache/lightgraph)
  home_created       $HOME/.cache/lightgraph made 0700 when missing; a relative
                     XDG_CACHE_HOME is ignored
  private_refused    a pre-made fallback that is world-writable, 0755, a symbolic link or
                     another user's: one warning, no caching, the render succeeds
  named_refused      a LIGHTGRAPH_CACHE_DIR that is another user's or world-writable (with or
                     without the sticky bit): the same; one that is the user's (0755, or a
                     link to the user's own folder) is used
"""
import os
import shutil
import stat
import sys

import lgrun
from lgrun import Fail, check

TEST_PLUGINS = os.environ["LG_TEST_PLUGINS"]
TMP = lgrun.temp_dir("lg-cache-dir-test-")
UID = os.geteuid()
NOBODY = 65534


GRAPH = os.path.join(TMP, "cache.lgraph")
with open(GRAPH, "w") as f:
    f.write("""lightgraph 1
scene = test_scene { medium_density = 1 }
fog = test_fog { scene = scene, value = 0.5 }
mean = test_cached { image = fog, salt = 7 }
output mean "%s"
""" % os.path.join(TMP, "mean.hdr"))


def render(home=None, xdg=None, named=None, tmpdir=None):
    """Runs the cached graph; returns ("computed" | "reused", stderr)."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("HOME", "XDG_CACHE_HOME", "LIGHTGRAPH_CACHE_DIR", "TMPDIR")}
    env["LIGHTGRAPH_PLUGIN_PATH"] = TEST_PLUGINS
    for key, value in (("HOME", home), ("XDG_CACHE_HOME", xdg), ("LIGHTGRAPH_CACHE_DIR", named),
                       ("TMPDIR", tmpdir)):
        if value is not None:
            env[key] = value
    p = lgrun.run(["render", GRAPH, "--size", "4x4"], env, expect=0, cwd=TMP)
    if "testcache: computed" in p.stderr:
        return "computed", p.stderr
    if "testcache: reused" in p.stderr:
        return "reused", p.stderr
    raise Fail("no cache message: " + p.stderr)


def mode(path):
    return stat.S_IMODE(os.lstat(path).st_mode)


def entries(folder):
    return [f for f in os.listdir(folder) if f.endswith(".lgc")] if os.path.isdir(folder) else []


def warnings(err):
    return [l for l in err.splitlines() if "cache disabled" in l]


def expect_refused(why, reason, runs=1, **where):
    """`runs` renders: each computes (nothing cached) with one warning holding `reason`."""
    for _ in range(runs):
        what, err = render(**where)
        w = warnings(err)
        check(what == "computed", "%s: the cache was used: %s" % (why, err))
        check(len(w) == 1 and reason in w[0] and "set LIGHTGRAPH_CACHE_DIR" in w[0],
              "%s: want one warning with '%s': %s" % (why, reason, err))


def fresh(name):
    d = os.path.join(TMP, name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    return d


def test_private_fallback():
    tmpdir = fresh("tmp")
    shared = "/tmp/.cache/lightgraph"
    before = sorted(entries(shared))
    what, err = render(tmpdir=tmpdir)
    private = os.path.join(tmpdir, "lightgraph-cache-%d" % UID)
    check(what == "computed" and not warnings(err), "first run computes: " + err)
    check(os.path.isdir(private) and not os.path.islink(private), "no private folder " + private)
    check(mode(private) == 0o700, "private folder mode %04o, want 0700" % mode(private))
    check(os.lstat(private).st_uid == UID, "private folder not ours")
    check(len(entries(private)) == 1, "one entry in the private folder: %s" % entries(private))
    check(sorted(entries(shared)) == before, "an entry was written to the shared " + shared)
    what, err = render(tmpdir=tmpdir)
    check(what == "reused" and not warnings(err), "second run reuses: " + err)


def test_home_created():
    home = fresh("home")
    what, err = render(home=home, xdg="relative/cache")  # a relative XDG_CACHE_HOME is ignored
    check(what == "computed" and not warnings(err), err)
    folder = os.path.join(home, ".cache", "lightgraph")
    check(len(entries(folder)) == 1, "no entry in " + folder)
    check(mode(folder) == 0o700 and mode(os.path.join(home, ".cache")) == 0o700,
          "made %04o / %04o, want 0700" % (mode(folder), mode(os.path.join(home, ".cache"))))
    check(not os.path.exists(os.path.join(TMP, "relative")), "the relative XDG_CACHE_HOME was used")
    check(render(home=home)[0] == "reused", "second run reuses")
    # an absolute XDG_CACHE_HOME comes first
    xdg = fresh("xdg")
    check(render(home=home, xdg=xdg)[0] == "computed", "a new XDG folder starts empty")
    check(len(entries(os.path.join(xdg, "lightgraph"))) == 1, "no entry under XDG_CACHE_HOME")


def test_private_refused():
    tmpdir = fresh("tmp2")
    private = os.path.join(tmpdir, "lightgraph-cache-%d" % UID)

    def remake(m):
        if os.path.islink(private) or os.path.isfile(private):
            os.remove(private)
        shutil.rmtree(private, ignore_errors=True)
        os.mkdir(private)
        os.chmod(private, m)

    remake(0o777)  # another user could have made it so, before us, in a shared /tmp
    expect_refused("world-writable", "its mode is 0777; a private cache directory is 0700", runs=2,
                   tmpdir=tmpdir)
    check(entries(private) == [], "entries written into a refused folder")
    remake(0o755)
    expect_refused("0755", "its mode is 0755", tmpdir=tmpdir)
    remake(0o1777)
    expect_refused("sticky", "its mode is 1777", tmpdir=tmpdir)
    # a link to a folder of our own is still refused: in a shared /tmp, whoever made the
    # link chose where it points
    target = fresh("elsewhere")
    os.chmod(target, 0o700)
    shutil.rmtree(private)
    os.symlink(target, private)
    expect_refused("symbolic link", "it is a symbolic link", tmpdir=tmpdir)
    check(entries(target) == [], "entries written through the link")
    os.remove(private)
    open(private, "w").close()
    expect_refused("a file", "it is not a directory", tmpdir=tmpdir)
    os.remove(private)
    if UID == 0:
        remake(0o700)
        os.chown(private, NOBODY, NOBODY)
        expect_refused("another user's", "it is owned by uid %d, not by you (uid 0)" % NOBODY, tmpdir=tmpdir)
    # and a private folder as it should be is used again
    shutil.rmtree(private)
    check(render(tmpdir=tmpdir)[0] == "computed" and mode(private) == 0o700, "remade")
    check(render(tmpdir=tmpdir)[0] == "reused", "then reused")


def test_named_refused():
    named = fresh("named")
    os.chmod(named, 0o777)
    expect_refused("world-writable", "it is writable by every user (mode 0777)", runs=2, named=named)
    os.chmod(named, 0o1777)  # the sticky bit does not stop another user planting an entry
    expect_refused("sticky world-writable", "it is writable by every user (mode 1777)", named=named)
    check(entries(named) == [], "entries written into a refused folder")
    if UID == 0:
        os.chmod(named, 0o755)
        os.chown(named, NOBODY, NOBODY)
        expect_refused("another user's", "it is owned by uid %d" % NOBODY, named=named)
    else:
        expect_refused("root's", "it is owned by uid 0", named="/")
    # the user's own folder, 0755, and a link to it: used
    own = fresh("own")
    os.chmod(own, 0o755)
    check(render(named=own)[0] == "computed", "own folder")
    check(render(named=own)[0] == "reused", "own folder reused")
    link = os.path.join(TMP, "own-link")
    os.symlink(own, link)
    what, err = render(named=link)
    check(what == "reused" and not warnings(err), "a link to the user's own folder: " + err)


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
