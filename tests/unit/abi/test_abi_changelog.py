#!/usr/bin/env python3
"""The ABI version's one place (docs/sdk.md "ABI"): the real changelog reads, and
tools/abi_version.py refuses the broken ones, naming the line. The test abi_changelog.

usage: test_abi_changelog.py ABI_VERSION_PY SDK_MD
"""
import os
import subprocess
import sys
import tempfile

HEAD = "# doc\n\n## Something\n- 9.9 not a changelog\n\n## ABI\n\nText.\n\nChangelog (newest first):\n"
TAIL = "\n## After\n- 8.0 not a changelog either\n"


def run(script, path, *opts):
    r = subprocess.run([sys.executable, script, *opts, path], capture_output=True, text=True)
    return r.returncode, (r.stdout + r.stderr).strip()


def main():
    script, sdk_md = sys.argv[1], sys.argv[2]
    failures = 0

    def check(cond, what):
        nonlocal failures
        print(("ok: " if cond else "FAIL: ") + what)
        failures += 0 if cond else 1

    rc, out = run(script, sdk_md)
    check(rc == 0 and out.count(".") == 1, f"docs/sdk.md gives a version ({out!r})")
    rc, out = run(script, sdk_md, "--check")
    check(rc == 0, f"docs/sdk.md's changelog is well formed ({out})")

    cases = [
        ("good", "- 3.1 (issue 9): x\n  - 2.0 nested, ignored\n- 3.0: y\n- 2.7: z\n", 0, "3.1"),
        ("out of order", "- 3.0: y\n- 3.1: x\n", 1, "is listed above"),
        ("repeated", "- 3.0: y\n- 3.0: x\n", 1, "is listed above"),
        ("major not at .0", "- 4.1: y\n- 3.7: x\n", 1, "a major bump starts at minor 0"),
        ("range", "- 2.2-2.4: y\n- 2.1: x\n", 1, "one version per entry"),
        ("empty", "No entries yet.\n", 1, "no changelog entry"),
    ]
    with tempfile.TemporaryDirectory() as d:
        for name, body, want_rc, want in cases:
            path = os.path.join(d, name.replace(" ", "_") + ".md")
            with open(path, "w", encoding="utf-8") as f:
                f.write(HEAD + body + TAIL)
            rc, out = run(script, path)
            check(rc == want_rc and want in out,
                  f"{name}: exit {rc} (want {want_rc}), {out!r} holds {want!r}")
    print(f"{failures} failed" if failures else "ok: abi_version.py reads and refuses as it should")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
