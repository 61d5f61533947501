#!/usr/bin/env python3
"""test_quick.py: the meson test accuracy_quick (suite tools). Makes the accuracy page with
--quick over every section into OUT (a directory under the build directory, emptied first),
then checks it (check_page.py): every section of tools/accuracy/sections/ has its heading,
one plot, one answer line and its studies' tables and CSVs. Asserts no timing.

usage: test_quick.py --build BUILD --out OUT"""
import argparse
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
from accuracy.accuracy import discover  # noqa: E402
from accuracy.check_page import check_page  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, os.path.join(HERE, "accuracy.py"), "--build", a.build,
                        "--out", out, "--quick"])
    secs = time.monotonic() - t0
    if r.returncode != 0:
        print("FAIL: accuracy.py --quick exited %d" % r.returncode)
        return 1
    sections = [(s.name, s.title, None) for s in discover(os.path.join(HERE, "sections"))]
    bad = check_page(out, sections)
    for b in bad:
        print("FAIL: %s" % b)
    if bad:
        return 1
    print("ok: %d sections in %.1f s (%s)" % (len(sections), secs,
                                             ", ".join(n for n, _, _ in sections)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
