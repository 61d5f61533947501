#!/usr/bin/env python3
"""Pi is spelled LG_PI (lightgraph/vecmath.h) in C and C++, checked by reading the tree.

    check_no_typed_pi.py SOURCE_ROOT

In the .c, .h and .cpp files of sdk/, host/, plugins/, tests/ and tools/, with comments and
strings left out, none of:
  - pi or a kin typed out: 3.14159.., 6.28318.., 1.570796.., 0.318309.., 0.159154..,
    0.0795774.., 0.785398.. (pi/4), 12.56637.. (4 pi);
  - M_PI and its family (M_PI_2, M_1_PI, ...: POSIX's, not C11's <math.h>);
  - a local macro of pi (#define PI, PI_D, ST_PI, FOUR_PI, ...) given a number.
vecmath.h itself, where the constants are defined, is the exception. Shaders and kernels
(.glsl, .cl, ...) cannot include the header and are not read.

Each finding is printed as FILE:LINE and what was found; the exit status is 1 when any is.
A self-test runs first on a scratch tree with one case of each kind, so that a check that
finds nothing cannot pass by accident.
"""
import os
import re
import sys
import tempfile

FOLDERS = ["sdk", "host", "plugins", "tests", "tools"]
EXEMPT = {os.path.join("sdk", "include", "lightgraph", "vecmath.h")}
TYPED = re.compile(r"(?<![\w.])(?:3\.14159|6\.28318|1\.570796|0\.318309|0\.159154|0\.0795774|"
                   r"0\.785398|12\.56637)\d*")
M_PI = re.compile(r"\bM_(?:PI\w*|1_PI|2_PI|2_SQRTPI)\b")
LOCAL = re.compile(r"^\s*#\s*define\s+(\w*PI\w*)\s+\(?[-+]?[\d.]", re.M)
# a comment, a string or a character literal, whichever starts first
LEXEME = re.compile(r"/\*.*?(?:\*/|\Z)|//[^\n]*|"
                    r"\"(?:\\.|[^\"\\\n])*\"?|'(?:\\.|[^'\\\n])*'?", re.S)


def strip(text):
    """The text with comments, strings and character literals blanked (newlines kept, so
    that offsets still give the right line)."""
    return LEXEME.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def check(root):
    problems = []
    for top in FOLDERS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames[:] = sorted(d for d in dirnames if not d.startswith((".", "build")))
            for name in sorted(filenames):
                if not name.endswith((".c", ".h", ".cpp")):
                    continue
                path = os.path.join(dirpath, name)
                rel = os.path.relpath(path, root)
                if rel in EXEMPT:
                    continue
                with open(path, encoding="utf-8", errors="replace") as f:
                    text = strip(f.read())
                found = []
                for m in TYPED.finditer(text):
                    found.append((m.start(), f"{m.group(0)} typed out"))
                for m in M_PI.finditer(text):
                    found.append((m.start(), f"{m.group(0)} (not C11)"))
                for m in LOCAL.finditer(text):
                    if "PI" in m.group(1).split("_"):  # PI, PI_D, ST_PI, not MAX_PIXELS
                        found.append((m.start(1), f"a local macro of pi, {m.group(1)}"))
                for at, what in sorted(found):
                    line = text.count("\n", 0, at) + 1
                    problems.append(f"{rel}:{line}: {what}; use LG_PI and its kin "
                                    f"(lightgraph/vecmath.h)")
    return problems


def self_test():
    with tempfile.TemporaryDirectory() as tmp:
        def put(rel, text):
            p = os.path.join(tmp, rel)
            os.makedirs(os.path.dirname(p), exist_ok=True)
            with open(p, "w", encoding="utf-8") as f:
                f.write(text)
        put("sdk/include/lightgraph/vecmath.h", "#define LG_PI 3.14159265358979323846\n")
        put("plugins/x/x.c", "/* 3.14159 */\nconst char *s = \"M_PI\";\n"
                             "float q = 0.78539816f;\n")
        put("tests/unit/y/y.c", "#define PI_D 3.14159265358979323846\n"
                                "double a = 2 * M_PI;\n")
        put("tools/z.cpp", "double t = 6.283185307179586;\n")
        put("host/ok.c", "#define MAX_PIXELS 4096\ndouble x = 13.14159, y = LG_PI;\n")
        put("shaders/k.cl", "#define K_PI 3.14159265f\n")
        found = check(tmp)
        want = ["plugins/x/x.c:3", "tests/unit/y/y.c:1", "tests/unit/y/y.c:1", "tests/unit/y/y.c:2",
                "tools/z.cpp:1"]
        got = sorted(p.split(": ", 1)[0] for p in found)
        if got != sorted(want):
            print("check_no_typed_pi self-test failed: expected findings at", want, "got", found,
                  file=sys.stderr)
            return False
    return True


def main():
    if len(sys.argv) != 2:
        print("usage: check_no_typed_pi.py SOURCE_ROOT", file=sys.stderr)
        return 2
    if not self_test():
        return 1
    problems = check(sys.argv[1])
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} pi typed out; lightgraph/vecmath.h has LG_PI, LG_TWO_PI, "
              f"LG_HALF_PI, LG_INV_PI, LG_INV_TWO_PI, LG_INV_FOUR_PI, LG_PIF", file=sys.stderr)
        return 1
    print("no pi typed out in the C and C++ of sdk/, host/, plugins/, tests/, tools/")
    return 0


if __name__ == "__main__":
    sys.exit(main())
