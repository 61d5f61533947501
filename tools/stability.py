#!/usr/bin/env python3
"""docs/stability.md from the test suite: every hard case, its policy, the backends it is
tested on and its status in the last run.

usage: stability.py --build BUILD [--registry FILE] [--out FILE] [--check] [--no-status]
                    [--testlog FILE]

Reads the registry (default tests/stability.toml: one [[case]] per hard case, see its head),
the tests meson defined (`meson introspect BUILD --tests`: names, suites, arguments) and,
when it exists, the last run's BUILD/meson-logs/testlog.json (each test's result, the run's
date). Fails (exit 1, each problem on its own line) on:

  - an entry naming a test (or a pattern) that no meson test matches;
  - a test of suite 'stability' that no entry names, and an entry's test without that suite;
  - an entry without its technique, case, policy, what or backends, or with a policy other
    than clamp, fallback, refuse, exact, or an unknown technique;
  - an entry whose backends are not exactly the ones its tests run. A test's backends are
    derived, not claimed: a word cpu, gl or cl in its name or arguments (osmesa and egl are
    gl), else the registry's [[in_process]] table (a test that opens several devices in one
    process, with where that is stated), else cpu (host C code).

Without --check it writes the page (--out, default docs/stability.md; --no-status leaves
the last run out). With --check it
writes nothing and compares the committed page with the one it would write, status
columns and the run's date left out, so the page cannot drift from the registry and the
suite (meson test `stability_page`). Exit status: 0 good, 1 a problem found, 2 bad usage.
"""
import argparse
import datetime
import difflib
import fnmatch
import json
import os
import shutil
import subprocess
import sys
import tomllib

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
POLICIES = ("clamp", "fallback", "refuse", "exact")
BACKENDS = ("cpu", "gl", "cl")
WORD_BACKEND = {"cpu": "cpu", "gl": "gl", "cl": "cl", "osmesa": "gl", "egl": "gl"}
SUITE = "stability"
# Lines of the page that depend on the last run, not on the registry: left out by --check.
STATUS_PREFIX = "Last run:"


def load_tests(build):
    """[{name, suites, args}] of every meson test of BUILD. `meson introspect` when meson is
    on PATH (it is under `meson test`), else the file it reads."""
    meson = shutil.which("meson")
    if meson:
        out = subprocess.run([meson, "introspect", build, "--tests"], capture_output=True,
                             text=True)
        if out.returncode != 0:
            raise RuntimeError(f"meson introspect {build} --tests failed: {out.stderr.strip()}")
        raw = json.loads(out.stdout)
    else:
        with open(os.path.join(build, "meson-info", "intro-tests.json"), encoding="utf-8") as f:
            raw = json.load(f)
    tests = []
    for t in raw:
        # Suites come as "project:suite"; the project prefix says nothing here.
        suites = {s.split(":", 1)[-1] for s in t.get("suite", [])}
        tests.append({"name": t["name"], "suites": suites, "args": list(t.get("cmd", [])[1:])})
    return tests


def load_status(path):
    """({test name: ok | fail | skip}, date of the run) from a meson testlog.json, or ({}, None)
    when there was no run."""
    if not os.path.exists(path):
        return {}, None
    status = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if not line:
                continue
            try:
                rec = json.loads(line)
            except json.JSONDecodeError:
                continue  # a run cut short leaves a partial last line
            # meson writes "project:suite+suite / name"; the registry uses the name.
            name = str(rec.get("name", "")).split(" / ", 1)[-1]
            result = str(rec.get("result", "")).upper()
            if result in ("OK", "EXPECTEDFAIL"):
                status[name] = "ok"
            elif result == "SKIP":
                status[name] = "skip"
            else:
                status[name] = "fail"
    when = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc)
    return status, when.strftime("%Y-%m-%d %H:%M UTC")


def words(text):
    """The words of a test name or argument: split on anything but letters, digits, '_'."""
    out, cur = [], []
    for ch in text:
        if ch.isalnum():
            cur.append(ch)
        else:
            if cur:
                out.append("".join(cur))
            cur = []
    if cur:
        out.append("".join(cur))
    # '_' splits too: closed_form_gl names gl, lights32 names nothing.
    return [w for part in out for w in part.split("_") if w]


def test_backends(test, in_process):
    """The backends a test runs, derived as the module docstring says."""
    found = set()
    for text in [test["name"]] + [a for a in test["args"] if not os.path.isabs(a)]:
        for w in words(text):
            if w in WORD_BACKEND:
                found.add(WORD_BACKEND[w])
    if found:
        return found
    for group in in_process:
        if any(fnmatch.fnmatchcase(test["name"], p) for p in group["tests"]):
            return set(group["backends"])
    return {"cpu"}


def check(registry, tests):
    """Problems (strings) and the resolved cases: each case with its tests' names and the
    backends they run."""
    problems = []
    by_name = {t["name"]: t for t in tests}
    techniques = registry.get("technique", {})
    in_process = registry.get("in_process", [])
    for i, group in enumerate(in_process):
        for key in ("tests", "backends", "why"):
            if not group.get(key):
                problems.append(f"[[in_process]] #{i + 1}: no '{key}'")
        for b in group.get("backends", []):
            if b not in BACKENDS:
                problems.append(f"[[in_process]] #{i + 1}: unknown backend '{b}'")
        for p in group.get("tests", []):
            if not any(fnmatch.fnmatchcase(n, p) for n in by_name):
                problems.append(f"[[in_process]] #{i + 1}: no meson test matches '{p}'")
    named = set()
    resolved = []
    for i, case in enumerate(registry.get("case", [])):
        label = f"case #{i + 1} ({case.get('technique', '?')}: {case.get('case', '?')})"
        for key in ("technique", "case", "policy", "what", "backends", "tests"):
            if not case.get(key):
                problems.append(f"{label}: no '{key}'")
        if case.get("technique") and case["technique"] not in techniques:
            problems.append(f"{label}: technique '{case['technique']}' is not in [technique]")
        if case.get("policy") and case["policy"] not in POLICIES:
            problems.append(f"{label}: policy '{case['policy']}' is not one of "
                            + ", ".join(POLICIES))
        names = []
        for p in case.get("tests", []):
            hits = sorted(n for n in by_name if fnmatch.fnmatchcase(n, p))
            if not hits:
                problems.append(f"{label}: no meson test '{p}'")
            names.extend(h for h in hits if h not in names)
        derived = set()
        for n in names:
            named.add(n)
            if SUITE not in by_name[n]["suites"]:
                problems.append(f"{label}: test '{n}' is not in suite '{SUITE}'")
            derived |= test_backends(by_name[n], in_process)
        claimed = set(case.get("backends", []))
        for b in sorted(claimed - set(BACKENDS)):
            problems.append(f"{label}: unknown backend '{b}'")
        if names and claimed and claimed != derived:
            extra = sorted(claimed - derived)
            missing = sorted(derived - claimed)
            if extra:
                problems.append(f"{label}: backends {', '.join(extra)} claimed, but no test of "
                                "the entry runs them")
            if missing:
                problems.append(f"{label}: its tests run {', '.join(missing)}, not listed in "
                                "backends")
        resolved.append(dict(case, names=names,
                             backends=[b for b in BACKENDS if b in derived or b in claimed]))
    for t in tests:
        if SUITE in t["suites"] and t["name"] not in named:
            problems.append(f"test '{t['name']}' is in suite '{SUITE}' but no entry of the "
                            "registry names it")
    return problems, resolved


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def status_of(names, status):
    """The status cell: 'ok', or each test that is not ok with its status."""
    if not status:
        return "not run"
    states = {n: status.get(n, "not run") for n in names}
    if all(s == "ok" for s in states.values()):
        return "ok"
    if all(s == states[names[0]] for s in states.values()):
        return states[names[0]]
    return ", ".join(f"{s}: `{n}`" for n, s in states.items() if s != "ok")


def render(registry, resolved, status, when, registry_rel):
    out = []
    out.append("# Hard cases and what each technique does with them")
    out.append("")
    out.append(f"Generated by `tools/stability.py` from `{registry_rel}` and the test suite: "
               "do not edit by hand. `make stability` regenerates it after `make test`; meson "
               "test `stability_page` (suite `tools`) fails when it is out of date, when a "
               "hard case has no test, or when a test of suite `stability` has no entry.")
    out.append("")
    out.append("Policies: **clamp** (brought into range, the run goes on), **fallback** (a "
               "defined substitute for what cannot be computed), **refuse** (a clear error or "
               "warning naming where and why), **exact** (no special path needed: the true "
               "value or its limit, to a stated tolerance). Backends are those the tests run, "
               "derived from each test (a word cpu, gl or cl in its name or arguments; for a "
               "test that opens several devices itself, the registry's `[[in_process]]` table, "
               "which says where that is stated; otherwise cpu, the host's own C code), and an "
               "entry listing any other fails the generator. Status is each case's tests in "
               "the last `meson test` run of the build directory.")
    out.append("")
    out.append("**Adding a hard case** (later techniques add theirs the same way): write a "
               "small test, give its `test()` call the suite `'stability'` beside its own, add "
               f"one `[[case]]` to `{registry_rel}` (technique, case, policy, what, backends, "
               "tests), then run `meson test -C build stability_page` and `make stability`. "
               "docs/plugin-guide.md says the same for plugin authors.")
    out.append("")
    out.append(STATUS_PREFIX + " " + (when if when else "none (no testlog.json in the build "
                                      "directory)"))
    out.append("")
    techniques = registry.get("technique", {})
    counts = {}
    for c in resolved:
        counts[c["technique"]] = counts.get(c["technique"], 0) + 1
    out.append("| technique | cases | its tests in the last run |")
    out.append("|---|---|---|")
    for key in techniques:
        if key not in counts:
            continue
        names = list(dict.fromkeys(n for c in resolved if c["technique"] == key
                                   for n in c["names"]))
        out.append(f"| [{key}](#{key}) | {counts[key]} | {status_summary(names, status)} |")
    out.append("")
    for key, tech in techniques.items():
        cases = [c for c in resolved if c["technique"] == key]
        if not cases:
            continue
        out.append(f"<a id=\"{key}\"></a>")
        out.append("")
        out.append(f"## {key}")
        out.append("")
        out.append(f"{tech.get('title', key)}; explained, with what it computes and how "
                   f"well: [{tech['doc']}]({os.path.relpath(tech['doc'], 'docs')}).")
        out.append("")
        out.append("| case | policy | what | backends | tests | status |")
        out.append("|---|---|---|---|---|---|")
        for c in cases:
            tests = "<br>".join(f"`{n}`" for n in c["names"])
            out.append(f"| {cell(c['case'])} | {c['policy']} | {cell(c['what'])} | "
                       f"{', '.join(c['backends'])} | {tests} | {status_of(c['names'], status)} |")
        out.append("")
    return "\n".join(out)


def status_summary(names, status):
    if not status:
        return "not run"
    states = [status.get(n, "not run") for n in names]
    parts = [f"{states.count(s)} {s}" for s in ("ok", "fail", "skip", "not run") if s in states]
    return ", ".join(parts)


def without_status(text):
    """The page less what depends on the last run: the 'Last run:' line and each table's last
    column (status)."""
    lines = []
    for line in text.splitlines():
        if line.startswith(STATUS_PREFIX):
            continue
        if line.startswith("|") and line.rstrip().endswith("|"):
            # The status cell is the last one; cells escape their own '|' as '\|'.
            body = line.rstrip()[:-1]
            cut = len(body)
            while True:
                cut = body.rfind("|", 0, cut)
                if cut <= 0 or body[cut - 1] != "\\":
                    break
            line = body[:cut + 1]
        lines.append(line.rstrip())
    return lines


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="the meson build directory")
    ap.add_argument("--registry", default=os.path.join(ROOT, "tests", "stability.toml"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "stability.md"))
    ap.add_argument("--check", action="store_true",
                    help="write nothing; fail if --out differs from the page generated")
    ap.add_argument("--no-status", action="store_true",
                    help="leave the last run out (every status 'not run')")
    ap.add_argument("--testlog", help="the run's log (default BUILD/meson-logs/testlog.json)")
    try:
        args = ap.parse_args(argv)
    except SystemExit as e:
        return 2 if e.code else 0
    if not os.path.isdir(args.build):
        print(f"stability.py: --build {args.build}: not a directory", file=sys.stderr)
        return 2
    try:
        with open(args.registry, "rb") as f:
            registry = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        print(f"stability.py: {args.registry}: {e}", file=sys.stderr)
        return 1
    try:
        tests = load_tests(args.build)
    except (OSError, RuntimeError, json.JSONDecodeError) as e:
        print(f"stability.py: {e}", file=sys.stderr)
        return 1
    problems, resolved = check(registry, tests)
    for p in problems:
        print(f"stability.py: {os.path.relpath(args.registry, ROOT)}: {p}", file=sys.stderr)
    if problems:
        print(f"stability.py: {len(problems)} problem(s); the page was not written",
              file=sys.stderr)
        return 1
    testlog = args.testlog or os.path.join(args.build, "meson-logs", "testlog.json")
    status, when = ({}, None) if args.check or args.no_status else load_status(testlog)
    # The page names the registry by its place in the tree, whichever file was read.
    page = render(registry, resolved, status, when, "tests/stability.toml") + "\n"
    n_tests = len({n for c in resolved for n in c["names"]})
    if args.check:
        try:
            with open(args.out, encoding="utf-8") as f:
                committed = f.read()
        except OSError as e:
            print(f"stability.py: {args.out}: {e}; run `make stability`", file=sys.stderr)
            return 1
        want, have = without_status(page), without_status(committed)
        if want != have:
            diff = list(difflib.unified_diff(have, want, args.out, "generated", lineterm="", n=1))
            print("\n".join(diff[:60]), file=sys.stderr)
            print(f"stability.py: {args.out} differs from the registry and the suite (status "
                  "left out); run `make stability` and commit it", file=sys.stderr)
            return 1
        print(f"stability.py: {len(resolved)} hard cases, {n_tests} tests: registry, suite and "
              f"{os.path.relpath(args.out, ROOT)} agree")
        return 0
    tmp = args.out + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(page)
    os.replace(tmp, args.out)  # never a half-written page
    print(f"stability.py: wrote {args.out}: {len(resolved)} hard cases, {n_tests} tests"
          + (f", status of the run of {when}" if when else ", no run yet"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
