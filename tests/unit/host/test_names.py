#!/usr/bin/env python3
"""Unique names through the real program (host/names.h, docs/sdk.md "Names"): two plugins
with one name, or two node types with one name, are never both loaded; the one found later
is refused with both paths, at the default verbosity; lightgraph's own plugins are taken
before any other; the search goes one folder deep, no deeper; `plugins` names each file.

usage: test_names.py TEST_NAME   (meson runs each test as its own case)

Environment (tests/unit/host/meson.build): LG_EXE, LG_NAMES_<VARIANT> (the folder of each
test plugin of tests/plugins/names), LG_TEST_PLUGINS (tests/plugins/testnodes).
"""
import json
import os
import shutil
import sys

import lgrun
from lgrun import Fail, check

TEST_PLUGINS = os.environ["LG_TEST_PLUGINS"]
TMP = lgrun.temp_dir("lg-names-test-")


def names_dir(variant):
    return os.environ["LG_NAMES_" + variant.upper()]


def names_so(variant):
    d = names_dir(variant)
    so = [f for f in os.listdir(d) if f.startswith("lg_") and f.endswith(".so")]
    assert len(so) == 1, (d, so)
    return os.path.join(d, so[0])


def run(args, plugin_path, expect=None):
    return lgrun.run(args, lgrun.env(plugin_path, os.path.join(TMP, "cache")), expect,
                     tail=3000, cwd=TMP)


def plugins_json(plugin_path):
    p = run(["plugins", "--json"], plugin_path, expect=0)
    doc = json.loads(p.stdout)
    by_name = {pl["name"]: pl for pl in doc["plugins"]}
    refused = {r["path"]: r["reason"] for r in doc["refused"]}
    return by_name, refused, p.stderr


def graph(text, name="g.lgraph"):
    path = os.path.join(TMP, name)
    with open(path, "w") as f:
        f.write("lightgraph 1\n" + text)
    return path


def test_plugin_twice():
    """Two files declaring the plugin names_dup: the first on the path is kept, the second
    refused with both paths, whichever order; a graph that needs the refused one fails with
    a note naming both; `plugins` shows the file of each plugin."""
    a, b = names_so("dup_a"), names_so("dup_b")
    for first, second, kept_type, lost_type in ((a, b, "names_dup_a", "names_dup_b"),
                                                (b, a, "names_dup_b", "names_dup_a")):
        path = os.path.dirname(first) + ":" + os.path.dirname(second)
        by_name, refused, err = plugins_json(path)
        check(by_name["names_dup"]["path"] == first,
              "the first names_dup is not the one kept: %s" % by_name["names_dup"]["path"])
        types = [t["name"] for t in by_name["names_dup"]["node_types"]]
        check(types == [kept_type], "names_dup's types: %s" % types)
        why = refused.get(second, "")
        check("its name 'names_dup' is also the name of the plugin at %s" % first in why,
              "%s not refused for its name, naming %s: %s" % (second, first, refused))
        # the warning is printed at the default verbosity, with both paths
        check("refusing plugin %s: its name 'names_dup'" % second in err and first in err,
              "no warning naming both files:\n" + err)
        g = graph('c = constant { color = [1, 1, 1] }\nd = %s { image = c }\n'
                  'output d "out.exr"\n' % lost_type)
        p = run(["check", g], path, expect=2)
        check("unknown node type '%s'" % lost_type in p.stderr and
              "note: plugin %s was refused" % second in p.stderr and first in p.stderr,
              "check of a graph needing the refused plugin:\n" + p.stderr)
    # the text listing gives each plugin's file on its heading line
    text = run(["plugins"], os.path.dirname(a), expect=0).stdout
    check("names_dup 1.0.0 (ABI " in text and ") %s\n" % a in text,
          "`plugins` does not show the file of names_dup:\n" + text[:2000])


def test_type_clash():
    """names_other declares names_dup_a, a type of the plugin names_dup: the one found
    later is refused, naming the type, the other plugin and both files."""
    a, o = names_so("dup_a"), names_so("other")
    for first, second, first_name in ((a, o, "names_dup"), (o, a, "names_other")):
        path = os.path.dirname(first) + ":" + os.path.dirname(second)
        by_name, refused, err = plugins_json(path)
        check(by_name[first_name]["path"] == first, "the first plugin was not kept")
        why = refused.get(second, "")
        check("its node type 'names_dup_a' is also declared by the plugin '%s' at %s"
              % (first_name, first) in why, "%s not refused for names_dup_a: %s"
              % (second, refused))
        check("refusing plugin %s" % second in err, "no warning:\n" + err)
        kept = [pl for pl in by_name.values() for t in pl["node_types"]
                if t["name"] == "names_dup_a"]
        check(len(kept) == 1, "names_dup_a is declared %d times" % len(kept))


def test_core_first():
    """A plugin on LIGHTGRAPH_PLUGIN_PATH (searched before the program's own folder) that
    declares `scale`: refused, and core's scale stays (it used to replace it silently: a
    graph setting scale.factor then failed with 'unknown parameter')."""
    s = names_so("scale")
    by_name, refused, err = plugins_json(os.path.dirname(s))
    core = by_name.get("core")
    check(core is not None, "core is not loaded")
    check("scale" in [t["name"] for t in core["node_types"]], "core has no scale")
    check("names_scale" not in by_name, "names_scale was loaded beside core")
    why = refused.get(s, "")
    check("its node type 'scale' is also declared by the plugin 'core' at %s, one of "
          "lightgraph's own plugins" % core["path"] in why, "refusal: %s" % refused)
    check("refusing plugin %s" % s in err and core["path"] in err, "no warning:\n" + err)
    g = graph('c = constant { color = [0.25, 0.5, 1] }\ns = scale { image = c, factor = 2 }\n'
              'output s "out.exr"\n')
    p = run(["render", g, "--size", "4x4"], os.path.dirname(s), expect=0)
    check(os.path.exists(os.path.join(TMP, "out.exr")), "no output")
    check("refusing plugin %s" % s in p.stderr, "render does not warn:\n" + p.stderr)
    # core's file reached first through the path (its folder named after names_scale's) is
    # still the program's own, and still comes first
    core_dir = os.path.dirname(core["path"])
    by_name, refused, err = plugins_json(os.path.dirname(s) + ":" + core_dir)
    check(by_name.get("core", {}).get("path") == core["path"] and "names_scale" not in by_name
          and s in refused, "with core's folder on the path, after names_scale's: %s, %s"
          % (sorted(by_name), refused))


def test_type_twice():
    """A plugin that declares one type name twice is refused (malformed descriptor)."""
    t = names_so("twice")
    by_name, refused, err = plugins_json(os.path.dirname(t))
    check("names_twice" not in by_name, "names_twice was loaded")
    check("declares node type 'names_twice' twice (types 0 and 1)" in refused.get(t, ""),
          "refusal: %s" % refused)


def test_search_depth():
    """A folder of LIGHTGRAPH_PLUGIN_PATH and its immediate subfolders are searched; a
    folder two levels down and hidden ones are not; files not named lg_*.so are not."""
    top = os.path.join(TMP, "top")
    for sub in ("", "sub", "sub/deeper", ".hidden"):
        os.makedirs(os.path.join(top, sub), exist_ok=True)
    copies = {"": "lg_testwork.so", "sub": "lg_testfile.so", "sub/deeper": "lg_testcache.so",
              ".hidden": "lg_testfog.so"}
    for sub, name in copies.items():
        shutil.copy(os.path.join(TEST_PLUGINS, name), os.path.join(top, sub, name))
    shutil.copy(os.path.join(TEST_PLUGINS, "lg_testparts.so"),
                os.path.join(top, "testparts.so"))
    by_name, refused, err = plugins_json(top)
    check(by_name.get("testwork", {}).get("path") == os.path.join(top, "lg_testwork.so"),
          "the folder's own plugin was not found")
    check(by_name.get("testfile", {}).get("path") == os.path.join(top, "sub", "lg_testfile.so"),
          "the plugin one folder down was not found")
    check("testcache" not in by_name, "a plugin two folders down was found")
    check("testfog" not in by_name, "a plugin in a hidden folder was found")
    check("testparts" not in by_name, "a file not named lg_*.so was scanned")
    check(not refused, "refusals: %s" % refused)
    text = run(["--help"], "", expect=0).stdout
    check("immediate subfolders" in text and "not deeper" in text,
          "--help does not say how deep the search goes:\n" + text)


def test_same_file():
    """One file reached twice (a folder given twice through a link, a linked file) is one
    plugin, not a clash with itself."""
    real = os.path.join(TMP, "real")
    os.makedirs(real)
    shutil.copy(names_so("dup_a"), os.path.join(real, "lg_names_dup.so"))
    os.symlink(real, os.path.join(TMP, "alias"))
    other = os.path.join(TMP, "linked")
    os.makedirs(other)
    os.symlink(os.path.join(real, "lg_names_dup.so"), os.path.join(other, "lg_names_dup.so"))
    path = ":".join([real, os.path.join(TMP, "alias"), other])
    by_name, refused, err = plugins_json(path)
    check(not refused, "a file reached twice was refused: %s" % refused)
    check(by_name["names_dup"]["path"] == os.path.join(real, "lg_names_dup.so"),
          "the first path is not the one listed: %s" % by_name["names_dup"]["path"])
    check("refusing" not in err, "a warning:\n" + err)


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
