#!/usr/bin/env python3
"""lightgraph tune through the real program (issue 23, item 3; docs/tune.md).

  law          tests/plugins/testnodes/testtune.c's tune_law (error a/n^p, cost c*n units per
               mode) at rel_rmse <= 0.012: with --vary n=1..4096 and the three modes, the
               answer is the known optimum, fine at n = 10 (coarse needs 84 and costs twice
               as much; flat never gets there and is pruned at its most accurate setting);
               the coarse combination was bisected to exactly 84; fewer renders than the
               grid's 12288; the CSV has one chosen row, the front, every metric and, last,
               the check render's row (check = 1: the chosen setting, the check: line's
               error). With the default knobs (n on its power-of-two grid, the modes): fine at n = 16
  nonmonotone  bump = 96 makes n = 96..99 err 100 times more: the bisection alone stops at
               100; the violation is seen and said, the grid below is scanned, the answer is
               84 again
  prune        modes fine and slow (n = 1..64): slow's cheapest setting already costs 256
               units, more than fine's answer (40): pruned after its first render, its most
               accurate setting never rendered; --max-renders 5 stops the search and says so
  unreachable  mode flat only: exit 1, "E is out of reach on this scene: best rel_rmse 1"
  errors       unknown node, a --vary parameter the node lacks, a range outside its schema,
               an enum value it lacks, E <= 0 or NaN, an unknown metric, dssim on images
               too small for its window, a missing option:
               exit 2 with the reason; a missing -o DIR: exit 1; nothing written in any case
  froxel_5     examples/volumetric_froxel.lgraph at 96x54 (a 48x27 grid), depth 2..128 and
  froxel_2     the two slicings, against examples/volumetric_reference.lgraph (64 steps, 4
               spp, rays through the pixel centres as the froxel grid samples): the check
               render meets 5% (2%) relative RMSE, in fewer renders than the full grid (both
               counts printed). The froxel node runs on gl: a missing device fails here.

usage: test_tune.py TEST_NAME
"""
import csv
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import lgrun  # noqa: E402
from lgrun import Fail, check  # noqa: E402

SRC = os.environ["LG_SOURCE_ROOT"]
TEST_PLUGINS = os.environ["LG_TEST_PLUGINS"]
TMP = lgrun.temp_dir("lg-tune-test-")


def run(args, expect=0, plugin_path=TEST_PLUGINS, timeout=300):
    return lgrun.run(["tune"] + args, lgrun.env(plugin_path, os.path.join(TMP, "cache")),
                     expect, timeout)


def law_graph(mode="coarse"):
    return lgrun.write(os.path.join(TMP, "law.lgraph"),
                       'lightgraph 1\nlaw = tune_law { mode = %s }\noutput law "law.exr"\n' % mode)


def out_dir(name):
    return lgrun.fresh_dir(TMP, name)


LAW = ["--node", "law", "--ref-set", "law.exact=true", "--size", "8x8"]


def answer(p):
    m = re.search(r"^answer: (.*)$", p.stdout, re.M)
    check(m, "no answer line:\n" + p.stdout)
    return dict(re.findall(r"--set law\.(\w+)=(\S+)", m.group(1)))


def counts(p):
    """(renders spent, full grid) from the renders line."""
    m = re.search(r"^renders: (\d+) \(search (\d+) \+ timing repeats (\d+) \+ check (\d+)\), "
                  r"reference 1; full grid (\d+)$", p.stdout, re.M)
    check(m, "no renders line:\n" + p.stdout)
    total, search, repeats, chk, grid = (int(x) for x in m.groups())
    check(total == search + repeats + chk, "the counts do not add up: " + m.group(0))
    return total, grid


def check_line(p, target):
    m = re.search(r"^check: \S+ (\S+), (meets the target|MISSES the target)$", p.stdout, re.M)
    check(m, "no check line:\n" + p.stdout)
    check(m.group(2) == "meets the target" and float(m.group(1)) <= target,
          "the check render misses %g: %s" % (target, m.group(0)))
    return float(m.group(1))


def all_rows(d):
    with open(os.path.join(d, "tune.csv")) as f:
        return list(csv.DictReader(f))


def rows(d):
    """The explored points of tune.csv (not the check render's row)."""
    r = all_rows(d)
    check(all(x["check"] in ("0", "1") for x in r), "a check column that is not 0 or 1")
    return [x for x in r if x["check"] == "0"]


def check_row(p, d, node, metric, target):
    """tune.csv's last row is the check render: the chosen point's setting, neither chosen nor
    on the front, its error the one of the check: line (%.4g there, %.6g in the CSV)."""
    printed = check_line(p, target)
    r = all_rows(d)
    checks = [x for x in r if x["check"] == "1"]
    check(len(checks) == 1 and r[-1] is checks[0], "not one check row, last: %s" % checks)
    c = checks[0]
    chosen = [x for x in r if x["chosen"] == "1"]
    check(len(chosen) == 1, "chosen rows: %s" % chosen)
    knobs = [k for k in c if k.startswith(node + ".")]
    check(knobs and all(c[k] == chosen[0][k] for k in knobs),
          "the check row's setting %s is not the chosen %s"
          % ({k: c[k] for k in knobs}, {k: chosen[0][k] for k in knobs}))
    check(int(c["point"]) == len(r) and c["chosen"] == "0" and c["on_front"] == "0"
          and c["timings"] == "1" and float(c["time_ms"]) > 0,
          "the check row's point, flags or timing: %s" % c)
    err = float(c[metric])
    check(abs(err - printed) <= 5e-4 * max(abs(printed), 1e-12),
          "the check row's %s %g is not the check line's %g" % (metric, err, printed))
    check(c["within_target"] == ("1" if err <= target else "0"), "within_target of the check row")


def test_law():
    g = law_graph()
    d = out_dir("law")
    p = run([g] + LAW + ["--target-error", "0.012", "--vary", "n=1..4096",
                         "--vary", "mode=coarse,fine,flat", "-o", d])
    check(answer(p) == {"n": "10", "mode": "fine"}, "not the known optimum:\n" + p.stdout)
    total, grid = counts(p)
    check(grid == 4096 * 3, "full grid %d, expected 12288" % grid)
    check(total < 100, "%d renders for a bisection over 4096 values in 3 modes" % total)
    check("pruned: even --set law.n=4096 --set law.mode=flat misses E" in p.stderr,
          "flat not pruned at its most accurate setting:\n" + p.stderr[-2000:])
    check_row(p, d, "law", "rel_rmse", 0.012)
    r = rows(d)
    within = lambda mode, n: [x["within_target"] for x in r
                              if x["law.mode"] == mode and x["law.n"] == str(n)]
    # the coarse combination bisected to its exact optimum: 84 meets 0.012, 83 does not
    check(within("coarse", 84) == ["1"] and within("coarse", 83) == ["0"],
          "coarse not bisected to n = 84: %s %s" % (within("coarse", 84), within("coarse", 83)))
    check(within("fine", 10) == ["1"] and within("fine", 9) == ["0"], "fine not bisected to 10")
    chosen = [x for x in r if x["chosen"] == "1"]
    check(len(chosen) == 1 and chosen[0]["law.n"] == "10", "chosen rows: %s" % chosen)
    check(chosen[0]["on_front"] == "1", "the chosen point is not on the front")
    check(int(chosen[0]["timings"]) == 3, "the chosen point was not timed --repeat times")
    # every metric, the chosen one (rel_rmse) equal to 1/n^2 = 0.01 in float
    check(abs(float(chosen[0]["rel_rmse"]) - 0.01) < 1e-6, "rel_rmse of n = 10")
    check(abs(float(chosen[0]["rmse"]) - 0.01) < 1e-6, "rmse of n = 10")
    check(len(set(tuple(sorted(x.items())) for x in r)) == len(r), "a point twice")
    check(os.path.exists(os.path.join(d, "tune.gp")), "no gnuplot script")
    # the default knobs: n on its powers of two (1..4096: 13 values), the modes; exact and
    # bump fixed by --set
    d2 = out_dir("law_default")
    p = run([g] + LAW + ["--target-error", "0.012", "--set", "law.exact=false",
                         "--set", "law.bump=0", "-o", d2])
    check("knob: law.n: 1..4096, powers of two (13 values)" in p.stdout, p.stdout)
    check("knob: law.mode: coarse,fine,flat,slow (4 values)" in p.stdout, p.stdout)
    check("law.exact" not in p.stdout.split("answer:")[0], "--set law.exact still varied")
    check(answer(p) == {"n": "16", "mode": "fine"}, "default grid's optimum:\n" + p.stdout)
    check(counts(p)[1] == 13 * 4, "full grid of the default knobs")


def test_nonmonotone():
    g = law_graph()
    d = out_dir("bump")
    p = run([g] + LAW + ["--target-error", "0.012", "--vary", "n=1..4096", "--set",
                         "law.bump=96", "-o", d])
    check(re.search(r"^note: n is not monotone .*scanned from 84 to 100$", p.stdout, re.M),
          "the violation is not reported:\n" + p.stdout)
    check(answer(p) == {"n": "84"}, "not the optimum below the bump:\n" + p.stdout)
    check_row(p, d, "law", "rel_rmse", 0.012)
    total, grid = counts(p)
    check(total < grid, "%d renders, grid %d" % (total, grid))


def test_prune():
    g = law_graph()
    d = out_dir("prune")
    p = run([g] + LAW + ["--target-error", "0.012", "--vary", "n=1..64",
                         "--vary", "mode=fine,slow", "-o", d])
    check(answer(p) == {"n": "10", "mode": "fine"}, p.stdout)
    check(re.search(r"pruned: --set law.n=1 --set law.mode=slow already takes [0-9.]+ ms "
                    r"\(median\), more than the best answer so far", p.stderr),
          "slow not pruned:\n" + p.stderr[-3000:])
    slow = [x for x in rows(d) if x["law.mode"] == "slow"]
    check([x["law.n"] for x in slow] == ["1"], "slow rendered at %s" % [x["law.n"] for x in slow])
    check(int(slow[0]["timings"]) == 3, "the pruning did not rest on --repeat timings")
    d2 = out_dir("budget")
    p = run([g] + LAW + ["--target-error", "0.012", "--vary", "n=1..4096", "--max-renders", "5",
                         "-o", d2])
    check("note: the search stopped at --max-renders 5" in p.stdout, p.stdout)
    check(answer(p) == {"n": "512"}, "the best of 1, 4096, 2048, 1024, 512:\n" + p.stdout)
    check(len(rows(d2)) == 5, "%d points for a budget of 5" % len(rows(d2)))
    check(len(all_rows(d2)) == 6, "the budget's check render not in tune.csv")


def test_unreachable():
    g = law_graph("flat")
    d = out_dir("flat")
    p = run([g] + LAW + ["--target-error", "0.5", "--vary", "n=1..64", "-o", d], expect=1)
    check(re.search(r"^E is out of reach on this scene: best rel_rmse 1 at --set law.n=\d+$",
                    p.stdout, re.M), p.stdout)
    check("answer:" not in p.stdout, "an answer for an unreachable target")
    check(all_rows(d) and all(x["check"] == "0" for x in all_rows(d)),
          "a check row without an answer")


def test_errors():
    g = law_graph()
    d = out_dir("errors")
    base = [g, "--node", "law", "--ref-set", "law.exact=true", "--size", "8x8", "-o", d]
    cases = [
        (["--node", "lwa", "--target-error", "0.01"], "--node lwa: .* has no node of that name; "
         "did you mean 'law'"),
        (["--target-error", "0.01", "--vary", "m=1..4"], "node 'law' \\(tune_law\\) has no "
         "parameter 'm'"),
        (["--target-error", "0.01", "--vary", "n=0..5000"], "outside law.n's range \\[1, 4096\\]"),
        (["--target-error", "0.01", "--vary", "n=1,2,9999"], "'9999' is not a value of law.n"),
        (["--target-error", "0.01", "--vary", "mode=coarse,exact"], "'exact' is not a value of "
         "law.mode \\(coarse, fine, flat, slow\\)"),
        (["--target-error", "0.01", "--vary", "mode=a..b"], "lo..hi is for numbers"),
        (["--target-error", "0"], "--target-error wants a finite number above 0"),
        (["--target-error", "-0.1"], "--target-error wants a finite number above 0"),
        (["--target-error", "nan"], "--target-error wants a finite number above 0"),
        (["--target-error", "0.01", "--metric", "psnr"], "unknown metric 'psnr' \\(known: rmse, "
         "rel_rmse"),
        ([], "no target given"),
        # SSIM has no 11 x 11 window in an 8 x 8 image: refused, not "out of reach"
        (["--target-error", "0.01", "--metric", "dssim"], "--metric dssim cannot be computed "
         "on 8x8 images"),
    ]
    for extra, want in cases:
        args = base + extra
        if extra[:1] == ["--node"]:
            args = [g] + extra + base[3:]
        p = run(args, expect=2)
        check(re.search(want, p.stderr), "%s: expected /%s/ in:\n%s" % (extra, want, p.stderr))
        check(os.listdir(d) == [], "%s wrote %s" % (extra, os.listdir(d)))
    p = run([g, "--target-error", "0.01"], expect=2)
    check("no node given" in p.stderr, p.stderr)
    p = run([g] + LAW + ["--target-error", "0.01", "-o", os.path.join(TMP, "missing")], expect=1)
    check("does not exist" in p.stderr and "nothing was run" in p.stderr, p.stderr)
    check(not os.path.exists(os.path.join(TMP, "missing")), "the missing DIR was made")


def froxel(target):
    d = out_dir("froxel")
    ex = os.path.join(SRC, "examples")
    p = run([os.path.join(ex, "volumetric_froxel.lgraph"), "--node", "vol",
             "--target-error", str(target),
             "--reference", os.path.join(ex, "volumetric_reference.lgraph"),
             "--ref-set", "vol.steps=64", "--ref-set", "vol.spp=4",
             "--ref-set", "vol.subpixel=centre",
             "--set", "vol.width=48", "--set", "vol.height=27",
             "--vary", "depth=2..128", "--vary", "slicing=uniform_clip,exponential",
             "--size", "96x54", "-o", d], plugin_path="")
    check_row(p, d, "vol", "rel_rmse", target)
    total, grid = counts(p)
    check(grid == 127 * 2, "full grid %d" % grid)
    check(total < grid, "%d renders, not fewer than the grid's %d" % (total, grid))
    check("failed" not in p.stderr, "a render failed (a device missing?):\n" + p.stderr[-3000:])
    r = rows(d)
    chosen = [x for x in r if x["chosen"] == "1"]
    check(len(chosen) == 1 and float(chosen[0]["rel_rmse"]) <= target, "chosen: %s" % chosen)
    check(re.search(r"^reference: [0-9.]+ ms \(its node of that name", p.stdout, re.M),
          "no reference time:\n" + p.stdout)


def test_froxel_5():
    froxel(0.05)


def test_froxel_2():
    froxel(0.02)


if __name__ == "__main__":
    sys.exit(lgrun.main(lgrun.tests_of(globals()), TMP))
