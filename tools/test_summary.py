#!/usr/bin/env python3
"""Prints 'N passed, N failed, N skipped' (always the last line) from meson's test logs, one
or more build directories; exits 1 if anything failed or no test ran.

usage: test_summary.py [--expected-skips FILE] BUILD_DIR...

Skips. A test skips (exit 77) when this machine lacks what it needs: a GL or CL device. A
regression that breaks context creation looks exactly the same, so on CI (the environment
has CI=true, as GitHub, GitLab and .ci/run set it) a skip is a failure unless the
expectations file (default: tests/expected-skips.txt next to this script's folder) lists
the test with the reason it may skip there, as Mesa's CI does with its skips files.
Each line of that file is

    TEST NAME: reason

where TEST NAME is the name `meson test` shows (without the "project:suite / " prefix)
or a shell-style pattern (fnmatch: `*`, `?`, `[...]`); '#' starts a comment; a line
without a reason is an error. An unexpected skip counts as failed, not as skipped, with a
line "FAIL (unexpected skip): NAME: what it printed last". Off CI, skips count as skipped
and unexpected ones are only pointed out. An expected skip that did not skip is noted,
so that stale entries get removed.
"""
import fnmatch
import json
import os
import sys

DEFAULT_EXPECTED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests",
                                "expected-skips.txt")


def read_expected(path):
    """[(pattern, reason)] from the expectations file; raises ValueError on a bad line."""
    out = []
    with open(path) as f:
        for no, line in enumerate(f, 1):
            text = line.split("#", 1)[0].strip()
            if not text:
                continue
            name, sep, reason = text.partition(": ")
            if not sep or not name.strip() or not reason.strip():
                raise ValueError("%s:%d: expected 'test name: reason', got %r"
                                 % (path, no, line.rstrip("\n")))
            out.append((name.strip(), reason.strip()))
    return out


def short_name(full):
    """'lightgraph:golden / demo graph' -> 'demo graph'."""
    return full.split(" / ", 1)[1] if " / " in full else full


def last_words(r):
    """The last non-empty line a test printed, to say why it skipped."""
    for stream in ("stderr", "stdout"):
        lines = [l.strip() for l in (r.get(stream) or "").splitlines() if l.strip()]
        if lines:
            return lines[-1][:200]
    return "(no output)"


KEY_WORDS = ("check failed", "error", "Sanitizer", "FAIL", "expected", "differ", "Assertion",
             "Traceback", "Error")


def failure_digest(r, limit=6):
    """A few lines that say why a test failed: the lines naming a failed check, an error or a
    sanitizer report, else its last lines. Printed next to the final count so that the tail
    of a CI log says which check failed, not only which test."""
    lines = []
    for stream in ("stdout", "stderr"):
        lines += [l.rstrip() for l in (r.get(stream) or "").splitlines() if l.strip()]
    keyed = [l for l in lines if any(k in l for k in KEY_WORDS)]
    pick = keyed[:limit] if keyed else lines[-limit:]
    return [l[:300] for l in pick] or ["(no output)"]


def main(argv):
    args = argv[1:]
    expected_path = DEFAULT_EXPECTED
    if len(args) >= 2 and args[0] == "--expected-skips":
        expected_path = args[1]
        args = args[2:]
    if not args:
        sys.stderr.write(__doc__.split("\n\n")[1] + "\n")
        return 2
    on_ci = os.environ.get("CI", "").lower() in ("true", "1", "yes")
    passed = failed = skipped = 0
    try:
        expected = read_expected(expected_path) if os.path.exists(expected_path) else []
    except ValueError as e:
        print("FAIL: %s" % e)
        expected = []
        failed += 1
    if on_ci and not os.path.exists(expected_path):
        print("note: no expectations file %s: every skip fails on CI" % expected_path)
    skipped_names = set()
    failures = []
    for build in args:
        try:
            with open(os.path.join(build, "meson-logs", "testlog.json")) as f:
                records = [json.loads(line) for line in f if line.strip()]
        except FileNotFoundError:
            print("FAIL: no test log in %s" % build)
            failed += 1
            continue
        except ValueError as e:
            print("FAIL: %s/meson-logs/testlog.json is not meson's JSON lines: %s" % (build, e))
            failed += 1
            continue
        for r in records:
            res = r.get("result")
            name = short_name(r.get("name", "?"))
            if res in ("OK", "EXPECTEDFAIL"):
                passed += 1
            elif res == "SKIP":
                skipped_names.add(name)
                why = [reason for pat, reason in expected
                       if fnmatch.fnmatchcase(name, pat) or fnmatch.fnmatchcase(r.get("name", ""), pat)]
                if why:
                    skipped += 1
                    print("skip (expected: %s): %s" % (why[0], name))
                elif on_ci:
                    failed += 1
                    print("FAIL (unexpected skip): %s: %s [%s]" % (name, last_words(r), build))
                else:
                    skipped += 1
                    print("skip (not in %s; a failure on CI): %s: %s"
                          % (os.path.relpath(expected_path), name, last_words(r)))
            else:
                failed += 1
                failures.append((name, build, res, failure_digest(r)))
    if on_ci:
        for pat, reason in expected:
            if not any(fnmatch.fnmatchcase(n, pat) for n in skipped_names):
                print("note: expected to skip but did not: %s (%s): remove it from %s"
                      % (pat, reason, os.path.relpath(expected_path)))
    for name, build, res, digest in failures:
        print("FAIL: %s [%s] (%s):" % (name, build, res))
        for l in digest:
            print("    " + l)
    print("%d passed, %d failed, %d skipped" % (passed, failed, skipped))
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
