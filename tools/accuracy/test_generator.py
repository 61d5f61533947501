#!/usr/bin/env python3
"""test_generator.py: the meson test accuracy_generator (suite tools). The generator on the
fake sections of selftest/ (Custom studies with known rows, no render): the Pareto front, the
answer line, the page (check_page.py), --only keeping the other sections, --target, all or
nothing (a failing study: exit 1, its id and stderr quoted, nothing written), --keep-going (the
sections that finished written, the failed one kept as the page had it, exit 1); bad usage
exits 2.

usage: test_generator.py --build BUILD --out SCRATCH"""
import argparse
import csv
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from accuracy.accuracy import answer_row, pareto, reference_time  # noqa: E402
from accuracy.check_page import check_page  # noqa: E402
from accuracy.study import Custom, Row  # noqa: E402

FAILS = []


def check(cond, what):
    print("%s: %s" % ("ok" if cond else "FAIL", what))
    if not cond:
        FAILS.append(what)


def gen(build, out, sections, *extra):
    r = subprocess.run([sys.executable, os.path.join(HERE, "accuracy.py"), "--build", build,
                        "--out", out, "--sections", os.path.join(HERE, "selftest", sections)]
                       + list(extra), capture_output=True, text=True)
    return r


def fronts(out, name):
    with open(os.path.join(out, "images/accuracy/data", name + ".csv")) as f:
        return [int(r["front"]) for r in csv.DictReader(f)]


def answer(out, anchor):
    text = open(os.path.join(out, "accuracy.md")).read()
    body = text.split('<a id="%s"></a>' % anchor, 1)[1]
    return next(ln for ln in body.splitlines() if ln.startswith("**Answer:**"))


def unit():
    s = Custom(id="u", title="u", technique="u", backend="cpu", command=["x"], csv="x")

    def row(t, e):
        return Row(s, [("n.p", str(t))], {"time_ms": t, "rel_rmse": e})
    rows = [row(1, 0.5), row(2, 0.05), row(3, 0.06), row(8, 0.004), row(2, 0.05),
            row(9, 0.004), row(5, None)]
    front = pareto(rows)
    check([r.front for r in rows] == [True, True, False, True, True, False, False],
          "pareto: dominated rows off, equal rows both on, a row without error off")
    check([r.time() for r in front] == [1, 2, 2, 8], "pareto: the front sorted by time")
    check(answer_row(rows, 0.01).time() == 8, "answer: the cheapest row within the target")
    check(answer_row(rows, 0.001) is None, "answer: none within a target nobody reaches")
    rows.append(row(0.5, 0.0))
    check(answer_row(rows, 0.01).time() == 8, "answer: a row of error 0 (the reference) is not")
    check(reference_time(rows, s) == "0.5 ms per frame of the node",
          "the reference's time: its own setting's row, timed like the others")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    scratch = os.path.abspath(a.out)
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)
    out = os.path.join(scratch, "docs")
    unit()

    r = gen(a.build, out, "ok")
    check(r.returncode == 0, "the fake sections make a page (exit %d)\n%s" % (r.returncode,
                                                                              r.stderr))
    if r.returncode == 0:
        bad = check_page(out, [("sec_b", "Fake technique b", ["fake_b"]),
                               ("sec_a", "Fake technique a", ["fake_a", "fake_a2"])])
        check(not bad, "the page holds every section's plot, answer and tables: %s" % bad)
        text = open(os.path.join(out, "accuracy.md")).read()
        check(text.index('id="sec_b"') < text.index('id="sec_a"'), "sections in ORDER")
        check(fronts(out, "sec_a-fake_a") == [1, 1, 0, 1] and
              fronts(out, "sec_a-fake_a2") == [0, 0], "the front over the whole section")
        check(fronts(out, "sec_b-fake_b") == [1, 1], "each section its own front")
        ans = answer(out, "sec_a")
        check("for 1% relative RMSE: fakea knob=4, 8 ms on cpu; the reference (the oracle): "
              "4.2 s for its whole render, once" in ans, "the answer of sec_a: %s" % ans)
        for f in ("sec_a-answer.png", "sec_a-heat.png", "sec_a-reference.png"):
            check(os.path.exists(os.path.join(out, "images/accuracy", f)), "image " + f)

        # --only: sec_b again at another target, sec_a kept as it was
        before = answer(out, "sec_a")
        r = gen(a.build, out, "ok", "--only", "sec_b", "--target", "0.1")
        check(r.returncode == 0, "--only sec_b (exit %d) %s" % (r.returncode, r.stderr))
        check(answer(out, "sec_a") == before, "--only keeps the other section's answer")
        check("fakeb knob=x, 2.5 ms" in answer(out, "sec_b"), "--only remade sec_b at 10%%: %s"
              % answer(out, "sec_b"))
        check(os.path.exists(os.path.join(out, "images/accuracy/sec_a.png")),
              "--only keeps the other section's plot")
        check(not check_page(out, [("sec_b", "Fake technique b", ["fake_b"]),
                                   ("sec_a", "Fake technique a", ["fake_a", "fake_a2"])]),
              "--only leaves a whole page")

        r = gen(a.build, out, "ok", "--target", "0.001", "--only", "sec_a")
        check("no setting swept reaches 0.1% relative RMSE: best fakea knob=4" in
              answer(out, "sec_a"), "the answer when nothing reaches: %s" % answer(out, "sec_a"))

    # all or nothing
    keep = os.path.join(scratch, "kept")
    os.makedirs(keep)
    with open(os.path.join(keep, "accuracy.md"), "w") as f:
        f.write("the old page\n")
    r = gen(a.build, keep, "bad")
    check(r.returncode == 1, "a failing study exits 1 (exit %d)" % r.returncode)
    check("fake_broken" in r.stderr and "the oracle melted (quick=False)" in r.stderr,
          "its id and its stderr are quoted: %s" % r.stderr.strip()[-300:])
    check(open(os.path.join(keep, "accuracy.md")).read() == "the old page\n" and
          not os.path.exists(os.path.join(keep, "images")), "nothing was written")
    check(not [d for d in os.listdir(scratch) if d.startswith(".accuracy-")],
          "no temporary directory left")
    r = gen(a.build, keep, "bad", "--quick", "--only", "sec_b")
    check(r.returncode == 1 and "(quick=True)" in r.stderr, "{quick} becomes --quick")

    # --keep-going: all or nothing per section; the failing one keeps what the page had
    kg = os.path.join(scratch, "keepgoing")
    r = gen(a.build, kg, "ok")
    data = os.path.join(kg, "images/accuracy/data")
    old_b = open(os.path.join(data, "sec_b.md")).read() if r.returncode == 0 else None
    before = answer(kg, "sec_a") if r.returncode == 0 else None
    r = gen(a.build, kg, "bad", "--keep-going", "--target", "0.001")
    check(r.returncode == 1, "--keep-going with a failing section exits 1 (exit %d)"
          % r.returncode)
    check("fake_broken" in r.stderr and "the oracle melted" in r.stderr and
          "section sec_b keeps what the page had" in r.stderr,
          "--keep-going names the failed study and section: %s" % r.stderr.strip()[-400:])
    if old_b is not None:
        check(answer(kg, "sec_a") != before and "no setting swept reaches 0.1%" in
              answer(kg, "sec_a"), "--keep-going wrote the section that finished: %s"
              % answer(kg, "sec_a"))
        check(open(os.path.join(data, "sec_b.md")).read() == old_b and
              "fakeb knob=" in answer(kg, "sec_b") and
              os.path.exists(os.path.join(kg, "images/accuracy/sec_b.png")) and
              os.path.exists(os.path.join(data, "sec_b-fake_b.csv")),
              "--keep-going: the failed section keeps its fragment, plot and data")
        check(not check_page(kg, [("sec_b", "Fake technique b", ["fake_b"]),
                                  ("sec_a", "Fake technique a", ["fake_a", "fake_a2"])]),
              "--keep-going leaves a whole page")
    fresh = os.path.join(scratch, "keepgoing_fresh")
    r = gen(a.build, fresh, "bad", "--keep-going")
    text = (open(os.path.join(fresh, "accuracy.md")).read()
            if os.path.exists(os.path.join(fresh, "accuracy.md")) else "")
    check(r.returncode == 1 and 'id="sec_a"' in text and 'id="sec_b"' not in text,
          "--keep-going without an old page: the section that finished alone (exit %d)"
          % r.returncode)
    r = gen(a.build, os.path.join(scratch, "kg_none"), "bad", "--keep-going", "--only", "sec_b")
    check(r.returncode == 1 and not os.path.exists(os.path.join(scratch, "kg_none")),
          "--keep-going when every section run failed writes nothing (exit %d)" % r.returncode)
    check(not [d for d in os.listdir(scratch) if d.startswith(".accuracy-")],
          "no temporary directory left after --keep-going")

    # bad usage
    for extra, what in ((["--only", "nosuch"], "an unknown section"),
                        (["--target", "0"], "a target of 0"), (["--repeat", "0"], "0 repeats")):
        r = gen(a.build, out, "ok", *extra)
        check(r.returncode == 2 and "accuracy:" in r.stderr, "%s exits 2: %s" % (
            what, r.stderr.strip()))
    r = subprocess.run([sys.executable, os.path.join(HERE, "accuracy.py"), "--build",
                        os.path.join(scratch, "nobuild"), "--out", out], capture_output=True,
                       text=True)
    check(r.returncode == 2 and "build first" in r.stderr, "a build without lightgraph exits 2")
    if FAILS:
        print("%d failed" % len(FAILS))
        return 1
    print("all passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
