#!/usr/bin/env python3
"""tools/stability.py catches what it promises to (meson test stability_page_catches): each
broken registry or page below must fail with exit 1 and the message naming the problem, and
the good ones must pass. The registries are written here, on the real build's tests.

usage: test_stability_page.py STABILITY_PY BUILD REGISTRY
"""
import os
import subprocess
import sys
import tempfile

tool, build, registry = sys.argv[1:4]
with open(registry, encoding="utf-8") as f:
    GOOD = f.read()
failures = []


def run(reg_text, *extra):
    with tempfile.TemporaryDirectory() as d:
        reg = os.path.join(d, "stability.toml")
        with open(reg, "w", encoding="utf-8") as f:
            f.write(reg_text)
        page = os.path.join(d, "stability.md")
        gen = subprocess.run([sys.executable, tool, "--build", build, "--registry", reg,
                              "--out", page, *extra], capture_output=True, text=True)
        return gen


def expect(what, reg_text, code, needle, *extra):
    r = run(reg_text, *extra)
    ok = r.returncode == code and (needle is None or needle in r.stderr + r.stdout)
    print(f"{'ok  ' if ok else 'FAIL'} {what}: exit {r.returncode}")
    if not ok:
        failures.append(what)
        print(r.stdout + r.stderr)


CASE = """
[[case]]
technique = "phong"
case = "a hard case of this test"
policy = "clamp"
what = "clamped"
backends = ["cpu"]
tests = ["{test}"]
"""

# The registry as committed writes a page (no --check: a temporary page).
expect("the committed registry", GOOD, 0, "hard cases")
# A documented hard case whose test does not exist.
expect("a case without its test", GOOD + CASE.format(test="no_such_test"), 1,
       "no meson test 'no_such_test'")
# A test of suite 'stability' with no entry: drop the entry of phong_hard_rv_negative.
start = GOOD.index('tests = ["phong_hard_rv_negative"]')
expect("a stability test without an entry",
       GOOD[:start] + 'tests = ["phong_hard_back_facing"]' +
       GOOD[start + len('tests = ["phong_hard_rv_negative"]'):], 1,
       "test 'phong_hard_rv_negative' is in suite 'stability' but no entry")
# A test named by an entry but not tagged 'stability' (probe_cost is suite 'unit').
expect("an entry's test outside suite stability", GOOD + CASE.format(test="probe_cost"), 1,
       "test 'probe_cost' is not in suite 'stability'")
# An entry missing its policy, and one missing its backends.
expect("an entry without policy",
       GOOD.replace('policy = "clamp"\nwhat = "the cosine clamps at 0',
                    'what = "the cosine clamps at 0', 1),
       1, "no 'policy'")
expect("an entry without backends",
       GOOD.replace('backends = ["cpu", "gl", "cl"]\ntests = ["reinhard badpixels *"]',
                    'tests = ["reinhard badpixels *"]', 1), 1, "no 'backends'")
# A backend claimed that no test runs, and one run but not listed.
expect("a backend claimed but not tested",
       GOOD.replace('backends = ["cpu"]\ntests = ["reinhard threads cpu"]',
                    'backends = ["cpu", "gl"]\ntests = ["reinhard threads cpu"]', 1), 1,
       "backends gl claimed, but no test of the entry runs them")
expect("a backend tested but not listed",
       GOOD.replace('backends = ["cpu", "gl", "cl"]\ntests = ["reinhard sizes *"]',
                    'backends = ["cpu", "gl"]\ntests = ["reinhard sizes *"]', 1), 1,
       "its tests run cl, not listed in backends")
# A policy outside the four.
expect("an unknown policy", GOOD.replace('policy = "clamp"', 'policy = "ignore"', 1), 1,
       "policy 'ignore' is not one of")

# --check: a page with a case changed by hand drifts; a page whose status differs does not.
with tempfile.TemporaryDirectory() as d:
    reg, page = os.path.join(d, "stability.toml"), os.path.join(d, "stability.md")
    with open(reg, "w", encoding="utf-8") as f:
        f.write(GOOD)
    subprocess.run([sys.executable, tool, "--build", build, "--registry", reg, "--out", page],
                   check=True, capture_output=True)
    with open(page, encoding="utf-8") as f:
        text = f.read()
for what, edit, code in [
        ("--check on the page as generated", lambda s: s, 0),
        ("--check with another status", lambda s: s.replace("| not run |", "| fail |")
         .replace("Last run: none", "Last run: 2026-01-01"), 0),
        ("--check with a case edited", lambda s: s.replace("the cosine clamps at 0",
                                                           "the cosine clamps at 1"), 1),
        ("--check with a case removed", lambda s: "\n".join(
            l for l in s.split("\n") if "phong_hard_rv_negative" not in l), 1)]:
    with tempfile.TemporaryDirectory() as d2:
        p2 = os.path.join(d2, "stability.md")
        with open(p2, "w", encoding="utf-8") as f:
            f.write(edit(text))
        with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as f:
            f.write(GOOD)
        chk = subprocess.run([sys.executable, tool, "--build", build, "--registry", f.name,
                              "--out", p2, "--check"], capture_output=True, text=True)
        os.unlink(f.name)
    ok = chk.returncode == code
    print(f"{'ok  ' if ok else 'FAIL'} {what}: exit {chk.returncode}")
    if not ok:
        failures.append(what)
        print(chk.stdout + chk.stderr)

# The status columns come from the run's log: a failed, a skipped and an unrun test show.
with tempfile.TemporaryDirectory() as d:
    log = os.path.join(d, "testlog.json")
    with open(log, "w", encoding="utf-8") as f:
        for name, result in [("phong_hard_rv_negative", "OK"), ("reinhard sizes cpu", "OK"),
                             ("reinhard sizes gl", "FAIL"), ("reinhard sizes cl", "SKIP"),
                             ("reinhard threads cpu", "TIMEOUT")]:
            f.write('{"name": "lightgraph:plugins+stability / %s", "result": "%s"}\n'
                    % (name, result))
    page = os.path.join(d, "stability.md")
    subprocess.run([sys.executable, tool, "--build", build, "--registry", registry, "--out",
                    page, "--testlog", log], check=True, capture_output=True)
    with open(page, encoding="utf-8") as f:
        rows = f.read().split("\n")
    want = [("`phong_hard_rv_negative` | ok |", "an ok test"),
            ("| skip: `reinhard sizes cl`, fail: `reinhard sizes gl` |",
             "a failed and a skipped test"),
            ("`reinhard threads cpu` | fail |", "a timeout as a failure"),
            ("`phong_hard_back_facing` | not run |", "a test not in the log")]
    for needle, what in want:
        ok = any(needle in r for r in rows)
        print(f"{'ok  ' if ok else 'FAIL'} status: {what}")
        if not ok:
            failures.append("status: " + what)

if failures:
    print(f"{len(failures)} check(s) failed: " + ", ".join(failures))
    sys.exit(1)
print("all checks caught")
