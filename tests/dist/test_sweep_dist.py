#!/usr/bin/env python3
"""lightgraph sweep and tune over MPI ranks (issue 26; docs/sweep.md, docs/tune.md): the same
files as one process.

  sweep NP  a 12-run sweep of testtune's tune_law (law.n x law.mode, 16x12, --repeat 2) with
            one process, then under tests/dist/mpirun.sh NP: the same files; reference.exr,
            every run-*.exr and heat-*.png and sweep.gp identical byte for byte; sweep.csv
            identical column by column but for the times (time_ms, time_min_ms,
            time_max_ms, ref_ms: measured on the rank that ran the run); stdout's lines
            identical but for their time
  tune NP   tune of tune_law's n (mode coarse, rel_rmse <= 0.012, n = 1..4096) where the
            answer does not hinge on time (one combination: the smallest n within E is the
            only candidate): the same answer (n = 84), the same renders line and tune.csv
            identical but for the time columns and on_front (a Pareto front of times)
  refimage NP  a sweep against --reference REF_IMAGE (an EXR rendered before): the same
            files as one process (rank 0 alone writes reference.exr)
  fail NP   a sweep whose run 3 fails in execute (test_work fail_frame = 0): exit 1, the
            run's number and its node's reason on stderr (rank 0's), no file in DIR

NP = 1 runs the program alone (no mpirun): the single-process path of the same code.

usage: test_sweep_dist.py MODE NP LIGHTGRAPH MPIRUN_SH
Environment: LG_TEST_PLUGINS (tests/meson.build).
"""
import csv
import os
import re
import shutil
import subprocess
import sys
import tempfile

TIME_COLS = {"time_ms", "time_min_ms", "time_max_ms", "ref_ms"}


class Fail(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Fail(msg)


def graph(d):
    path = os.path.join(d, "g.lgraph")
    with open(path, "w") as f:
        f.write("lightgraph 1\nlaw = tune_law { mode = coarse }\n"
                "w = test_work { image = law }\noutput w \"w.exr\"\n")
    return path


def run(argv, np, env, expect):
    cmd = [EXE] + argv if np == 1 else ["sh", MPIRUN, str(np), EXE] + argv
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    if p.returncode != expect:
        raise Fail("%s: exit %d, expected %d\nstdout:\n%s\nstderr:\n%s" %
                   (" ".join(cmd), p.returncode, expect, p.stdout, p.stderr[-3000:]))
    return p


def read(path):
    with open(path, "rb") as f:
        return f.read()


def rows(path, skip):
    """The CSV as rows of (column, value) without the columns in skip."""
    with open(path) as f:
        r = list(csv.DictReader(f))
    return [[(k, v) for k, v in row.items() if k not in skip] for row in r]


def no_times(text):
    return re.sub(r"time +[0-9.]+ ms", "time T ms", text)


def sweep_args(g, out):
    return ["sweep", g, "--vary", "law.n=1,2,3,5,8,13", "--vary", "law.mode=coarse,fine",
            "--ref-set", "law.exact=true", "--size", "16x12", "--repeat", "2", "-o", out]


def test_sweep(d, np, env):
    g = graph(d)
    one, many = os.path.join(d, "one"), os.path.join(d, "many")
    os.makedirs(one)
    os.makedirs(many)
    p1 = run(sweep_args(g, one), 1, env, 0)
    pn = run(sweep_args(g, many), np, env, 0)
    files = sorted(os.listdir(one))
    check(files == sorted(os.listdir(many)),
          "files differ: %s against %s" % (files, sorted(os.listdir(many))))
    check(len([f for f in files if f.startswith("run-")]) == 12, "not 12 runs: %s" % files)
    for f in files:
        if f.endswith(".exr") or f.startswith("heat-") or f == "sweep.gp":
            check(read(os.path.join(one, f)) == read(os.path.join(many, f)),
                  "%s differs between 1 process and %d ranks" % (f, np))
    a = rows(os.path.join(one, "sweep.csv"), TIME_COLS)
    b = rows(os.path.join(many, "sweep.csv"), TIME_COLS)
    check(len(a) == 12 and a == b, "sweep.csv differs (times aside):\n%s\n%s" % (a, b))
    check(no_times(p1.stdout.split("wrote")[0]) == no_times(pn.stdout.split("wrote")[0]),
          "stdout differs:\n%s\n%s" % (p1.stdout, pn.stdout))


def test_refimage(d, np, env):
    """--reference REF_IMAGE: read by every rank, written by rank 0 alone."""
    g = graph(d)
    ref = os.path.join(d, "ref.exr")
    run(["render", g, "--set", "law.exact=true", "--size", "16x12", "-o", ref], 1, env, 0)
    one, many = os.path.join(d, "one"), os.path.join(d, "many")
    os.makedirs(one)
    os.makedirs(many)
    args = ["sweep", g, "--vary", "law.n=1,2,3,5,8", "--reference", ref, "--repeat", "1"]
    run(args + ["-o", one], 1, env, 0)
    run(args + ["-o", many], np, env, 0)
    files = sorted(os.listdir(one))
    check(files == sorted(os.listdir(many)) and "run-004.exr" in files,
          "files differ: %s against %s" % (files, sorted(os.listdir(many))))
    for f in files:
        if f.endswith(".exr") or f.startswith("heat-"):
            check(read(os.path.join(one, f)) == read(os.path.join(many, f)),
                  "%s differs between 1 process and %d ranks" % (f, np))
    a = rows(os.path.join(one, "sweep.csv"), TIME_COLS)
    check(a == rows(os.path.join(many, "sweep.csv"), TIME_COLS), "sweep.csv differs")


def tune_args(g, out):
    return ["tune", g, "--node", "law", "--target-error", "0.012", "--vary", "n=1..4096",
            "--ref-set", "law.exact=true", "--size", "8x8", "--repeat", "3", "-o", out]


def test_tune(d, np, env):
    g = graph(d)
    one, many = os.path.join(d, "one"), os.path.join(d, "many")
    os.makedirs(one)
    os.makedirs(many)
    p1 = run(tune_args(g, one), 1, env, 0)
    pn = run(tune_args(g, many), np, env, 0)
    for p in (p1, pn):
        check("answer: --set law.n=84\n" in p.stdout, "not n = 84:\n" + p.stdout)
    renders = [re.search(r"^renders: .*$", p.stdout, re.M).group(0) for p in (p1, pn)]
    check(renders[0] == renders[1], "renders differ: %s" % renders)
    skip = {"time_ms", "time_min_ms", "time_max_ms", "on_front"}
    a = rows(os.path.join(one, "tune.csv"), skip)
    b = rows(os.path.join(many, "tune.csv"), skip)
    check(a == b, "tune.csv differs (times aside):\n%s\n%s" % (a, b))


def test_fail(d, np, env):
    g = graph(d)
    out = os.path.join(d, "out")
    os.makedirs(out)
    p = run(["sweep", g, "--vary", "w.fail_frame=-1,-1,-1,0,-1,-1", "--ref-set", "law.exact=true",
             "--size", "16x12", "--repeat", "1", "-o", out], np, env, 1)
    check(re.search(r"sweep run 3( on rank \d+)?: the render failed: node 'w' \(test_work\): "
                    r"test_work: failing at frame 0 as asked", p.stderr), p.stderr)
    check("nothing was written to" in p.stderr, p.stderr)
    check(os.listdir(out) == [], "files left: %s" % os.listdir(out))


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    mode, NP, EXE, MPIRUN = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
    tmp = tempfile.mkdtemp(prefix="lg-sweep-dist-")
    env = dict(os.environ)
    env["LIGHTGRAPH_PLUGIN_PATH"] = os.environ["LG_TEST_PLUGINS"]
    env["LIGHTGRAPH_CACHE_DIR"] = os.path.join(tmp, "cache")
    env["TMPDIR"] = tmp  # the ranks' own temporaries: checked empty at the end
    try:
        {"sweep": test_sweep, "refimage": test_refimage, "tune": test_tune,
         "fail": test_fail}[mode](tmp, NP, env)
        left = [f for f in os.listdir(tmp) if f.startswith(".")]
        check(left == [], "temporaries left in TMPDIR: %s" % left)
    except Fail as e:
        print("FAIL %s %d: %s" % (mode, NP, e))
        sys.exit(1)
    shutil.rmtree(tmp, ignore_errors=True)
    print("ok %s %d" % (mode, NP))
