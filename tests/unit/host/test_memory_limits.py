#!/usr/bin/env python3
"""What a graph makes is bounded before anything runs (docs/images.md "Images a graph
makes"), through the real program:

  size_option     render and sweep refuse a --size over the pixel limit (16384x16384 is 2^28
                  pixels, over the 2^27 default; 20x20 over --max-pixels 100) with exit 2,
                  naming the size, its pixels and the limit, and write nothing; 10x10 passes
  declared_image  an image a node declares in prepare (a constant of the render size, which
                  `check` cannot judge) over the pixel limit fails the render (exit 1) with
                  the node, the output, the size and the limit, and no output file
  plan_memory     under an address-space limit (RLIMIT_AS, set in the child only) that each
                  of three 2048x2048 rgba32f images fits alone but their 192 MiB do not, the
                  plan is refused before any node runs, naming the total, the largest
                  resource and the bound; three 1024x1024 images under the same limit render
                  (in a build with AddressSanitizer, which reserves terabytes of address
                  space at start-up and so cannot start under such a limit, only the plan
                  within the machine's memory is checked, and the test says so)

usage: test_memory_limits.py TEST_NAME
"""
import os
import resource
import subprocess
import sys

import lgrun
from lgrun import Fail, check

EXE = lgrun.EXE
TMP = lgrun.temp_dir("lg-memory-limits-test-")


def run(args, expect=None, address_space=None, timeout=60):
    env = lgrun.env("", os.path.join(TMP, "cache"), drop=["LIGHTGRAPH_MAX_PIXELS"])

    def limit():
        if address_space:
            resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))

    return lgrun.run(args, env, expect, timeout, cwd=TMP, preexec_fn=limit)


def sanitized():
    """Whether the program is built with AddressSanitizer (make test-sanitize)."""
    p = subprocess.run(["ldd", EXE], capture_output=True, text=True)
    return "libasan" in p.stdout


def path(name):
    return os.path.join(TMP, name)


def write(name, text):
    return lgrun.write(path(name), text)


def no_output(name):
    check(not os.path.exists(path(name)), "%s was written" % name)


def test_size_option():
    g = write("g.lgraph", 'lightgraph 1\nc = constant { width = 0, height = 0 }\n'
                          'output c "o.exr"\n')
    p = run(["render", g, "--size", "16384x16384"], expect=2)
    check("--size 16384x16384 is 268435456 pixels, over the limit of 134217728 pixels" in p.stderr
          and "--max-pixels" in p.stderr and "LIGHTGRAPH_MAX_PIXELS" in p.stderr, p.stderr)
    no_output("o.exr")
    p = run(["render", g, "--size", "20x20", "--max-pixels", "100"], expect=2)
    check("--size 20x20 is 400 pixels, over the limit of 100 pixels" in p.stderr, p.stderr)
    no_output("o.exr")
    p = run(["sweep", g, "--vary", "c.color=[1,1,1],[2,2,2]", "--size", "16384x16384",
             "-o", path("sw")], expect=2)
    check("lightgraph sweep: --size 16384x16384 is 268435456 pixels" in p.stderr, p.stderr)
    check(not os.path.exists(path("sw")), "sweep made its folder")
    run(["render", g, "--size", "10x10", "--max-pixels", "100"], expect=0)
    check(os.path.exists(path("o.exr")), "10x10 within 100 pixels was not written")


def test_declared_image():
    # width = height = 0: the render size, known only in prepare (check passes it)
    g = write("g.lgraph", 'lightgraph 1\nc = constant { width = 0, height = 0 }\n'
                          'output c "o.exr"\n')
    run(["check", g, "--max-pixels", "100"], expect=0)
    p = run(["render", g, "--max-pixels", "100"], expect=1)
    check("node 'c' (constant): declares output 'out' of 640x360: 230400 pixels (every face "
          "and mip level counted), over the limit of 100 pixels (raise it with --max-pixels N "
          "or LIGHTGRAPH_MAX_PIXELS=N)" in p.stderr, p.stderr)
    no_output("o.exr")


def graph_of_three(side):
    return write("three%d.lgraph" % side,
                 'lightgraph 1\n'
                 'a = constant { width = %d, height = %d, color = [1, 1, 1] }\n'
                 'b = constant { width = %d, height = %d, color = [2, 2, 2] }\n'
                 's = add { a = a, b = b }\n'
                 'output s "o%d.exr"\n' % (side, side, side, side, side))


def test_plan_memory():
    if sanitized():
        print("AddressSanitizer build: RLIMIT_AS cases not run (its shadow memory needs "
              "terabytes of address space); the plan within memory only")
        run(["render", graph_of_three(1024)], expect=0)
        check(os.path.exists(path("o1024.exr")), "the 48 MiB plan was not written")
        return
    limit = 200 << 20  # each 64 MiB image fits what it leaves, the three together do not
    g = graph_of_three(2048)
    p = run(["render", g], expect=1, address_space=limit)
    check("the plan's 3 images, volumes and buffers need 192.0 MiB (201326592 bytes) in all, "
          "more than the" in p.stderr, p.stderr)
    check("of address space that the process's limit (RLIMIT_AS, ulimit -v) leaves; the "
          "largest is output 'out' of node 'a' (64.0 MiB); nothing was run" in p.stderr,
          p.stderr)
    check("out of memory" not in p.stderr, p.stderr)
    no_output("o2048.exr")
    run(["render", graph_of_three(1024)], expect=0, address_space=limit)
    check(os.path.exists(path("o1024.exr")), "the 48 MiB plan was not written")


TESTS = lgrun.tests_of(globals())

if __name__ == "__main__":
    sys.exit(lgrun.main(TESTS, TMP))
