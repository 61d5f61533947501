#!/usr/bin/env python3
"""Every public SDK header compiles alone, as C11 and as C++17, warning-free (-Wall -Wextra
-pedantic -Werror): a plugin author may include any one of them first.

usage: check_headers.py CC CXX INCLUDE_DIR... -- HEADER...
"""
import os
import subprocess
import sys
import tempfile

sep = sys.argv.index("--")
cc, cxx = sys.argv[1], sys.argv[2]
incs = sys.argv[3:sep]
headers = sys.argv[sep + 1:]
flags = ["-Wall", "-Wextra", "-Werror", "-fsyntax-only"] + ["-I" + i for i in incs]
failed = 0
with tempfile.TemporaryDirectory() as tmp:
    for h in headers:
        name = "lightgraph/" + os.path.basename(h)
        for lang, comp, std, ext in (("C11", cc, "-std=c11", "c"), ("C++17", cxx, "-std=c++17", "cpp")):
            src = os.path.join(tmp, "t." + ext)
            with open(src, "w") as f:
                f.write('#include "%s"\n#include "%s"\nint lg_header_test_symbol;\n' % (name, name))
            extra = ["-pedantic"] if lang == "C11" else ["-Wno-pedantic"]
            p = subprocess.run([comp, std] + flags + extra + [src], capture_output=True, text=True)
            if p.returncode != 0:
                failed += 1
                print("FAIL: %s as %s:\n%s" % (name, lang, p.stderr))
            else:
                print("ok: %s as %s" % (name, lang))
sys.exit(1 if failed else 0)
