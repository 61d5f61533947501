#!/usr/bin/env python3
"""No call cycles between source files, read from the object files of static libraries.

    check_cycles.py NM LIB.a [LIB.a ...]

For every member (object file) of the archives: the symbols it defines (nm: T, D, B, R, W)
and those it needs (U). File A depends on file B when A needs a symbol B defines. A cycle
(A needs B and B, directly or through others, needs A) is printed as the chain of files and
the symbols of each step, and fails the check. Each archive is also one node of a second
graph: a library that needs a library that needs it back is a cycle between layers.

Issue 22 found two such circles: the host's resources and cache calling back into the host
API table that calls them, and the SDK's image dispatch calling codecs that call back into
it for allocation and limits. The check runs its self-test first (two small C files that
call each other, compiled with the C compiler in $CC or cc), so it cannot pass by accident.
"""
import collections
import os
import shlex
import shutil
import subprocess
import sys
import tempfile


def member_name(head):
    """The source file of "lib.a:dir/lib.a.p/.._.._sdk_src_image.c.o": "sdk_src_image.c"."""
    base = head.split(":")[-1].rsplit("/", 1)[-1]
    while base.startswith(".._"):
        base = base[3:]
    return base[:-2] if base.endswith(".o") else base


def read_archive(nm, lib):
    """{member: (defined set, needed set)} of one archive."""
    out = subprocess.run([nm, "-A", "--defined-only", lib], capture_output=True, text=True,
                         check=True).stdout
    und = subprocess.run([nm, "-A", "-u", lib], capture_output=True, text=True,
                         check=True).stdout
    members = collections.defaultdict(lambda: (set(), set()))
    for line in out.splitlines():
        # "lib.a:member.o:0000000000000000 T symbol"
        head, _, rest = line.rpartition(":")
        parts = rest.split()
        if len(parts) == 3 and parts[1] in "TDBRWV":
            members[member_name(head)][0].add(parts[2])
    for line in und.splitlines():
        head, _, rest = line.rpartition(":")
        parts = rest.split()
        if len(parts) == 2 and parts[0] == "U":
            members[member_name(head)][1].add(parts[1])
    return members


def find_cycle(edges):
    """One cycle of the directed graph {node: {node: [symbols]}} as a list, or None."""
    state = {}
    stack = []

    def visit(v):
        state[v] = 1
        stack.append(v)
        for w in sorted(edges.get(v, {})):
            if state.get(w) == 1:
                return stack[stack.index(w):] + [w]
            if w not in state:
                c = visit(w)
                if c:
                    return c
        stack.pop()
        state[v] = 2
        return None

    for v in sorted(edges):
        if v not in state:
            c = visit(v)
            if c:
                return c
    return None


def check(nm, libs):
    problems = []
    defs = {}
    files = {}
    for lib in libs:
        name = os.path.basename(lib)
        for member, (d, u) in read_archive(nm, lib).items():
            key = f"{name}:{member}"
            files[key] = u
            for s in d:
                defs[s] = key
    file_edges = collections.defaultdict(lambda: collections.defaultdict(list))
    lib_edges = collections.defaultdict(lambda: collections.defaultdict(list))
    for key, needed in files.items():
        for s in needed:
            to = defs.get(s)
            if to and to != key:
                file_edges[key][to].append(s)
                a, b = key.split(":")[0], to.split(":")[0]
                if a != b:
                    lib_edges[a][b].append(s)
    for what, edges in (("files", file_edges), ("libraries", lib_edges)):
        c = find_cycle(edges)
        if c:
            steps = [f"{a} -> {b} ({', '.join(sorted(edges[a][b])[:3])})"
                     for a, b in zip(c, c[1:])]
            problems.append(f"a call cycle between {what}:\n  " + "\n  ".join(steps))
    return problems


def self_test(nm):
    # $CC may be a command with words of its own ("ccache gcc")
    cc = shlex.split(os.environ.get("CC", "cc")) or ["cc"]
    ar = shutil.which("ar")
    if not shutil.which(cc[0]) or not ar:
        print(f"check_cycles self-test: no C compiler ({cc[0]}) or ar", file=sys.stderr)
        return False
    with tempfile.TemporaryDirectory() as tmp:
        srcs = {"a.c": "int b(int);\nint a(int x) { return x ? b(x - 1) : 0; }\n",
                "b.c": "int a(int);\nint b(int x) { return a(x); }\n",
                "c.c": "int a(int);\nint c(int x) { return a(x); }\n"}
        for n, text in srcs.items():
            with open(os.path.join(tmp, n), "w") as f:
                f.write(text)
            subprocess.run(cc + ["-c", n, "-o", n[0] + ".o"], cwd=tmp, check=True)
        subprocess.run([ar, "rc", "cyc.a", "a.o", "b.o"], cwd=tmp, check=True)
        subprocess.run([ar, "rc", "ok.a", "a.o", "c.o"], cwd=tmp, check=True)
        bad = check(nm, [os.path.join(tmp, "cyc.a")])
        good = check(nm, [os.path.join(tmp, "ok.a")])
        if len(bad) != 1 or "cyc.a:a" not in bad[0] or good:
            print("check_cycles self-test failed:", bad, good, file=sys.stderr)
            return False
    return True


def main():
    if len(sys.argv) < 3:
        print("usage: check_cycles.py NM LIB.a [LIB.a ...]", file=sys.stderr)
        return 2
    nm, libs = sys.argv[1], sys.argv[2:]
    if not self_test(nm):
        return 1
    problems = check(nm, libs)
    for p in problems:
        print(p)
    if problems:
        return 1
    print(f"no call cycle among the files of {len(libs)} libraries, nor between them")
    return 0


if __name__ == "__main__":
    sys.exit(main())
