#!/usr/bin/env python3
"""test_volumetric.py: the meson test accuracy_volumetric (suite tools): what the accuracy
page's volumetric section (sections/volumetric.py) claims beyond "the page was made"
(accuracy_quick checks that):

1. coverage, against the plugins as built (`lightgraph inspect --json`, no render): every
   backend of every volumetric method has a study, at full size and at --quick; every knob
   a study varies or sets is a parameter of its node (or the linked grid), with values in
   its enum's choices; every light or medium feature the volumetric nodes need has its
   entry in LIGHTS or MEDIA (a node that needs `light`, any type, is covered when LIGHTS
   has every light type); the sections volumetric_lights and volumetric_media (the other
   light types and media, with this file's cases) measure, with this one, every case once,
   their knobs checked alike; the point light has froxel's point_integration study and the
   VDB cloud its study;
2. the runner, at quick size: two froxel studies of one case share one reference (rendered
   once, by the first); the linked knob `vol.grid` is applied (its rows differ, the finer
   grid errs less); every row has a finite relative RMSE, the reference's time and its
   image and heat map;
3. a failing sweep (a grid the node refuses) exits 1 naming the study and quoting
   lightgraph's message, and leaves no rows.csv.

usage: test_volumetric.py --build BUILD --out OUT (a scratch directory, emptied first)"""
import argparse
import csv
import importlib.util
import json
import math
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from accuracy.accuracy import Context  # noqa: E402

SECTION = os.path.join(HERE, "sections", "volumetric.py")
# the sections that measure the other light types and media with volumetric.py's cases
OTHERS = ["volumetric_lights", "volumetric_media"]
METHODS = ["volumetric_screen", "volumetric_polygonal", "volumetric_froxel"]

failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL: %s" % what)
    return ok


def load_section(path=SECTION, name="accuracy_section_volumetric"):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def inspect(build, node):
    r = subprocess.run([os.path.join(build, "lightgraph"), "inspect", node, "--json"],
                       capture_output=True, text=True, check=True)
    return json.loads(r.stdout)


def coverage(sec, build, out):
    nodes = {m: inspect(build, m) for m in METHODS + ["volumetric_reference", "shadowmap"]}
    params = {m: {p["key"]: p for p in d["parameters"]} for m, d in nodes.items()}
    others = {n: load_section(os.path.join(HERE, "sections", n + ".py"), "accuracy_section_" + n)
              for n in OTHERS}
    # every case is measured by one section, and the sections' cases are all of them
    split = [c for n in ["volumetric"] + OTHERS for c in sec.cases(n)]
    check(sorted((a.tag, b.tag) for a, b in split) ==
          sorted((a.tag, b.tag) for a, b in sec.cases()),
          "the sections' cases %s are not every case once" % [(a.tag, b.tag) for a, b in split])
    for quick in (False, True):
        ctx = Context(quick, build, os.path.join(out, "coverage_%s" % quick))
        studies = sec.studies(ctx)
        have = {(s.technique, s.backend) for s in studies}
        for m in METHODS:
            b = params[m].get("backend")
            backends = b["values"] if b else ["gl"]
            for be in backends:
                check((m, be) in have, "quick=%s: no study of %s on %s" % (quick, m, be))
        ids = {s.id for s in studies}
        for n, mod in others.items():
            more = mod.studies(Context(quick, build, os.path.join(out, "cov_%s_%s" % (n, quick))))
            check(more and not ids & {s.id for s in more}, "quick=%s: section %s has no studies "
                  "or shares ids with another" % (quick, n))
            ids |= {s.id for s in more}
            studies = studies + more
        for light in sec.LIGHTS:
            if light.light_type == "point":
                check(any(s.id == "froxel_point_cpu_point_hom" for s in studies),
                      "quick=%s: no study of froxel's point_integration on the point light"
                      % quick)
        check(any(s.id == "froxel_cloud_cpu" for s in studies), "quick=%s: no VDB cloud study"
              % quick)
        for s in studies:
            spec = json.load(open(s.command_template[3]))
            node = {"vol": s.technique, "shadow": "shadowmap"}
            pairs = [(k, v) for k, vs in spec["vary"] for v in vs]
            pairs += [tuple(x.split("=", 1)) for x in spec["sets"]]
            for k, v in pairs:
                n, p = k.split(".", 1)
                if k in sec.LINKED:
                    pairs += [tuple(x.split("=", 1)) for x in sec.LINKED[k](v)]
                    continue
                if not check(n in node and p in params[node[n]],
                             "%s: %s is no parameter of %s" % (s.id, k, node.get(n, n))):
                    continue
                par = params[node[n]][p]
                if par["type"] == "enum":
                    check(v in par["values"], "%s: %s=%s is not one of %s"
                          % (s.id, k, v, par["values"]))
    needs = {n for m in METHODS for n in nodes[m]["needs"]}
    # a light need is one type's (`directional_light`, `point_light`) or `light`, any type:
    # the latter is covered by LIGHTS holding every type a node that needs it models
    light_needs = {n for n in needs if n.endswith("_light") or n == "light"}
    have = {c.need for c in sec.LIGHTS}
    types = {c.light_type for c in sec.LIGHTS}
    for n in sorted(light_needs - {"light"}):
        check(n in have, "the volumetric nodes need %s; LIGHTS covers %s" % (n, sorted(have)))
    if "light" in light_needs:
        check(types >= sec.LIGHT_TYPES, "a volumetric node needs `light` (any type); LIGHTS has "
              "the types %s, not every one of %s" % (sorted(types), sorted(sec.LIGHT_TYPES)))
    for c in sec.LIGHTS:
        check(c.need in light_needs or ("light" in light_needs and c.light_type in types),
              "LIGHTS entry %s: need %s is no volumetric node's" % (c.tag, c.need))
    check({c.need for c in sec.MEDIA} <= needs, "MEDIA names a need no volumetric node has")


def rows_of(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def runner(sec, build, out):
    ctx = Context(True, build, os.path.join(out, "run"))
    studies = {s.id: s for s in sec.studies(ctx)}
    ids = [i for i in studies if i.startswith("froxel_grid_")][:2]
    if not check(len(ids) == 2, "quick: fewer than two froxel grid studies: %s" % ids):
        return
    meta = None
    for k, sid in enumerate(ids):
        s = studies[sid]
        d = os.path.join(out, "run", "out_" + sid)
        r = subprocess.run(s.command(ctx, d), capture_output=True, text=True, cwd=ctx.root)
        if not check(r.returncode == 0, "%s: exit %d: %s" % (sid, r.returncode, r.stderr)):
            return
        renders = r.stderr.count("volumetric: the reference:")
        check(renders == (1 if k == 0 else 0),
              "%s rendered the reference %d times (want %d)" % (sid, renders, k == 0))
        spec = json.load(open(s.command_template[3]))
        m = os.path.join(spec["reference"]["dir"], "reference.json")
        if k == 0:
            meta = os.stat(m).st_mtime_ns
        else:
            check(os.stat(m).st_mtime_ns == meta, "the shared reference was written again")
        rows = rows_of(os.path.join(d, s.csv))
        check(len(rows) == 2, "%s: %d rows, want 2" % (sid, len(rows)))
        for row in rows:
            e = float(row["rel_rmse"])
            check(math.isfinite(e) and e > 0, "%s: rel_rmse %r" % (sid, row["rel_rmse"]))
            check(float(row["ref_ms"]) > 0, "%s: ref_ms %r" % (sid, row["ref_ms"]))
            for f in ("image", "heat"):
                check(os.path.exists(os.path.join(d, row[f])), "%s: no %s %s"
                      % (sid, f, row[f]))
        check(os.path.exists(os.path.join(d, s.reference_image)), "%s: no reference image"
              % sid)
        if len(rows) == 2:
            g = [(r["vol.grid"], float(r["rel_rmse"])) for r in rows]
            check(g[0][0] != g[1][0], "%s: both rows have grid %s" % (sid, g[0][0]))
            # the coarser grid (fewer froxels) first in QUICK_GRIDS: it must err more
            check(g[0][1] > g[1][1], "%s: grid %s errs %.4g, finer %s %.4g: the linked knob "
                  "did not reach the node" % (sid, g[0][0], g[0][1], g[1][0], g[1][1]))


def failing(sec, build, out):
    ctx = Context(True, build, os.path.join(out, "fail"))
    s = next(x for x in sec.studies(ctx) if x.id.startswith("froxel_grid_gl"))
    path = s.command_template[3]
    spec = json.load(open(path))
    spec["vary"] = [("vol.grid", ["24x12x8", "2000x12x8"])]  # width 2000: beyond 1024
    with open(path, "w") as f:
        json.dump(spec, f)
    d = os.path.join(out, "fail", "out")
    r = subprocess.run(s.command(ctx, d), capture_output=True, text=True, cwd=ctx.root)
    check(r.returncode == 1, "a refused grid: exit %d, want 1" % r.returncode)
    check(s.id in r.stderr and "width" in r.stderr,
          "a refused grid: the message names neither the study nor the parameter:\n%s"
          % r.stderr)
    check(not os.path.exists(os.path.join(d, s.csv)), "a failed study left %s" % s.csv)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    build, out = os.path.abspath(a.build), os.path.abspath(a.out)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    sec = load_section()
    coverage(sec, build, out)
    runner(sec, build, out)
    failing(sec, build, out)
    if failures:
        print("%d failed" % len(failures))
        return 1
    print("ok: the volumetric section's coverage, shared reference, linked grid and failure")
    return 0


if __name__ == "__main__":
    sys.exit(main())
