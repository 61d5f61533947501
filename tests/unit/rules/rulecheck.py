"""What the source-rule checks of tests/unit/rules share: the command line, the self-test
first, one line per problem, and the exit status (0 kept, 1 broken, 2 bad usage)."""
import os
import sys
import tempfile


def scratch_tree(tmp, files):
    """Writes {relative path: text} under tmp (a self-test's tree)."""
    for rel, text in files.items():
        path = os.path.join(tmp, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)


def expect_findings(name, check, files, want, match):
    """Self-test: check() over a scratch tree of `files` must report exactly one problem
    per entry of `want`, matched by match(problem, wanted). Prints why when not."""
    with tempfile.TemporaryDirectory() as tmp:
        scratch_tree(tmp, files)
        found = check(tmp)
    missing = [w for w in want if not any(match(p, w) for p in found)]
    if missing or len(found) != len(want):
        print(f"{name} self-test failed: expected a problem at each of {want}, got {found}",
              file=sys.stderr)
        return False
    return True


def main(name, check, self_test, failed, passed):
    """`NAME.py SOURCE_ROOT`: the self-test, then check(SOURCE_ROOT)'s problems, one a line.
    failed(count) is the closing line on stderr when any is found, passed the line when
    none is."""
    if len(sys.argv) != 2:
        print(f"usage: {name}.py SOURCE_ROOT", file=sys.stderr)
        return 2
    if not self_test():
        return 1
    problems = check(sys.argv[1])
    for p in problems:
        print(p)
    if problems:
        print(failed(len(problems)), file=sys.stderr)
        return 1
    print(passed)
    return 0
