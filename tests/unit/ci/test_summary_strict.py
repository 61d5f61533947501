#!/usr/bin/env python3
"""tools/test_summary.py on real meson test logs: a tiny meson project whose suite has one
test that passes and one that skips (exit 77), as a GL test does when context creation
breaks. On CI (CI=true) the unexpected skip fails the summary, naming the test; listed in
an expectations file with its reason it is a skip; off CI it is a skip that is pointed out.
Also: a malformed expectations file, a failing test, no test at all, and that the
repository's own tests/expected-skips.txt parses.

usage: test_summary_strict.py TEST_SUMMARY_PY EXPECTED_SKIPS_TXT
"""
import os
import subprocess
import sys
import tempfile

summary, repo_expected = sys.argv[1], sys.argv[2]
failures = 0


def check(cond, msg):
    global failures
    if not cond:
        failures += 1
        print("check failed: " + msg)


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def run_summary(builds, expected, ci):
    env = {k: v for k, v in os.environ.items() if k != "CI"}
    if ci:
        env["CI"] = "true"
    p = subprocess.run([sys.executable, summary, "--expected-skips", expected] + builds,
                       capture_output=True, text=True, env=env)
    lines = p.stdout.strip().splitlines()
    return p.returncode, p.stdout, lines[-1] if lines else ""


def meson_project(tmp, name, tests):
    """A meson project whose tests are python -c snippets; returns its build folder after
    `meson test` (whose own exit status is not the point here)."""
    src = os.path.join(tmp, name)
    os.makedirs(src)
    body = "project('%s', [])\npy = find_program('python3')\n" % name
    for tname, code in tests:
        body += "test('%s', py, args : ['-c', '%s'])\n" % (tname, code)
    write(os.path.join(src, "meson.build"), body)
    build = os.path.join(src, "build")
    env = {k: v for k, v in os.environ.items() if not k.startswith("MESON")}
    subprocess.run(["meson", "setup", build, src], check=True, capture_output=True, env=env)
    subprocess.run(["meson", "test", "-C", build], capture_output=True, env=env)
    return build


with tempfile.TemporaryDirectory() as tmp:
    device_skip = ("import sys; print(\"no OpenGL 4.5 device (osmesa): context creation failed\", "
                   "file=sys.stderr); sys.exit(77)")
    b = meson_project(tmp, "p1", [("codec roundtrip", "pass"), ("gl device", device_skip)])
    empty = os.path.join(tmp, "empty.txt")
    write(empty, "# nothing may skip\n")
    listed = os.path.join(tmp, "listed.txt")
    write(listed, "# a comment\n\ngl device: this runner has no GL  # and a comment\n")
    pattern = os.path.join(tmp, "pattern.txt")
    write(pattern, "gl *: no GL on this runner\n")
    bad = os.path.join(tmp, "bad.txt")
    write(bad, "gl device\n")

    # 1. the forced unexpected skip under CI=true fails the run and is named
    rc, out, last = run_summary([b], empty, ci=True)
    check(rc == 1, "unexpected skip on CI: exit %d\n%s" % (rc, out))
    check(last == "1 passed, 1 failed, 0 skipped", "unexpected skip on CI: last line %r" % last)
    check("FAIL (unexpected skip): gl device: no OpenGL 4.5 device" in out,
          "unexpected skip not named with its reason:\n" + out)
    # the repository's file does not excuse it either
    rc, out, last = run_summary([b], repo_expected, ci=True)
    check(rc == 1 and last == "1 passed, 1 failed, 0 skipped",
          "tests/expected-skips.txt excuses a GL device skip:\n" + out)

    # 2. listed (by name, or by pattern) with a reason: a skip
    for f in (listed, pattern):
        rc, out, last = run_summary([b], f, ci=True)
        check(rc == 0 and last == "1 passed, 0 failed, 1 skipped", "expected skip (%s):\n%s" % (f, out))
        check("skip (expected: " in out, "expected skip not reported:\n" + out)

    # 3. off CI: a skip, pointed out
    rc, out, last = run_summary([b], empty, ci=False)
    check(rc == 0 and last == "1 passed, 0 failed, 1 skipped", "off CI:\n" + out)
    check("a failure on CI): gl device" in out, "off CI the skip is not pointed out:\n" + out)

    # 4. a line without a reason is an error
    rc, out, last = run_summary([b], bad, ci=True)
    check(rc == 1 and "expected 'test name: reason'" in out, "malformed file accepted:\n" + out)

    # 5. an expected skip that passes is noted; a failure fails; several build folders add up
    b2 = meson_project(tmp, "p2", [("gl device", "pass"), ("broken", "print(1); print(\"x.c:9: check failed: a == b\"); print(2); raise SystemExit(1)")])
    rc, out, last = run_summary([b, b2], listed, ci=True)
    check(rc == 1 and last == "2 passed, 1 failed, 1 skipped", "two builds:\n" + out)
    rc, out, last = run_summary([b2], listed, ci=True)
    check("expected to skip but did not: gl device" in out, "stale entry not noted:\n" + out)
    # a failure is named next to the count with the line that says why (CI shows the tail)
    tail = out.strip().splitlines()[-3:]
    check(len(tail) == 3 and tail[0].startswith("FAIL: broken [") and
          tail[1].strip() == "x.c:9: check failed: a == b",
          "failure digest missing before the count:\n" + out)

    # 6. nothing ran: a failure; a build folder without a log: a failure
    b3 = meson_project(tmp, "p3", [("only skip", "raise SystemExit(77)")])
    rc, out, last = run_summary([b3], pattern, ci=True)
    check(rc == 1 and last == "0 passed, 1 failed, 0 skipped", "nothing passed:\n" + out)
    rc, out, last = run_summary([os.path.join(tmp, "nowhere")], empty, ci=True)
    check(rc == 1 and last == "0 passed, 1 failed, 0 skipped", "missing log:\n" + out)

# 7. the repository's expectations file parses (every entry has a reason)
sys.path.insert(0, os.path.dirname(os.path.abspath(summary)))
import test_summary  # noqa: E402
try:
    entries = test_summary.read_expected(repo_expected)
    print("tests/expected-skips.txt: %d entr%s" % (len(entries), "y" if len(entries) == 1 else "ies"))
except ValueError as e:
    check(False, str(e))

if failures:
    print("test_summary_strict: %d check(s) failed" % failures)
    sys.exit(1)
print("test_summary_strict: all checks passed")
