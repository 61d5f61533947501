#!/usr/bin/env python3
"""The host's layers (docs/architecture.md), checked by reading the tree.

    check_layers.py SOURCE_ROOT

1. host/ holds the layer folders and, at its top level, no source file but main.c.
2. A file of a layer includes host headers only as "LAYER/name.h", and only of its own layer
   or of a layer below it (base < graph < exec < plan < viewer < cli). A plain "name.h" is
   allowed only for a header generated into the build tree (shaders, the font table).
3. No file outside host/ but main.c includes a header of a layer above what a test may
   reach, and no meson.build outside host/ compiles a host source by path: tests, tools and
   fuzz drivers link the layers' libraries.

Each broken rule is printed as FILE:LINE and the reason; the exit status is 1 when any is.
A self-test runs first on a scratch tree with one violation of each kind, so that a check
that finds nothing cannot pass by accident.
"""
import os
import re
import sys

import rulecheck

LAYERS = ["base", "graph", "exec", "plan", "viewer", "cli"]
RANK = {name: i for i, name in enumerate(LAYERS)}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
# a host source named by path in a meson.build: 'host/x.c', '../host/x/y.c', ...
HOST_SOURCE = re.compile(r"""['"](?:[./]*/)?host/[\w/]+\.c['"]""")


def check(root):
    problems = []
    host = os.path.join(root, "host")
    for entry in sorted(os.listdir(host)):
        path = os.path.join(host, entry)
        if os.path.isdir(path):
            if entry not in RANK:
                problems.append(f"host/{entry}: a folder that is not a layer ({', '.join(LAYERS)})")
            continue
        if entry.endswith((".c", ".h", ".cpp")) and entry != "main.c":
            problems.append(f"host/{entry}: a source at host/'s top level (only main.c belongs there)")

    for layer in LAYERS:
        folder = os.path.join(host, layer)
        if not os.path.isdir(folder):
            problems.append(f"host/{layer}: the layer's folder is missing")
            continue
        own = set(os.listdir(folder))
        for name in sorted(own):
            if not name.endswith((".c", ".h", ".cpp")):
                continue
            rel = f"host/{layer}/{name}"
            with open(os.path.join(folder, name), encoding="utf-8") as f:
                for lineno, line in enumerate(f, 1):
                    m = INCLUDE.match(line)
                    if not m:
                        continue
                    inc = m.group(1)
                    if inc.startswith("lightgraph/"):
                        continue
                    if "/" not in inc:
                        if inc in own:
                            problems.append(f'{rel}:{lineno}: "{inc}": name a host header with '
                                            f'its layer ("{layer}/{inc}")')
                        elif not inc.endswith((".vert.h", ".frag.h", ".comp.h", ".cl.h",
                                               ".hex.h")):
                            problems.append(f'{rel}:{lineno}: "{inc}" is neither a layer\'s '
                                            f'header nor a generated one')
                        continue
                    dep = inc.split("/", 1)[0]
                    if dep not in RANK:
                        problems.append(f'{rel}:{lineno}: "{inc}" is not in a layer')
                    elif RANK[dep] > RANK[layer]:
                        problems.append(f'{rel}:{lineno}: "{inc}": {layer} may not include '
                                        f'{dep}, a layer above it')
                    elif not os.path.exists(os.path.join(host, inc)):
                        problems.append(f'{rel}:{lineno}: "{inc}" does not exist')

    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = [d for d in dirnames
                       if not d.startswith((".", "build")) and
                       os.path.join(dirpath, d) != host]
        if "meson.build" not in filenames or os.path.abspath(dirpath) == os.path.abspath(root):
            continue
        path = os.path.join(dirpath, "meson.build")
        with open(path, encoding="utf-8") as f:
            for lineno, line in enumerate(f, 1):
                if line.lstrip().startswith("#"):
                    continue
                if HOST_SOURCE.search(line):
                    problems.append(f"{os.path.relpath(path, root)}:{lineno}: compiles a host "
                                    f"source by path; link the layer's library "
                                    f"(lg_host_<layer>_dep) instead")
    return problems


def self_test():
    files = {f"host/{layer}/{layer}.h": "\n" for layer in LAYERS}
    files.update({
        "host/main.c": '#include "cli/cli.h"\n',
        "host/stray.c": "\n",
        "host/graph/parse.c": '#include "graph/graph.h"\n#include "exec/exec.h"\n',
        "host/exec/cache.c": '#include "exec.h"\n',
        "tests/unit/x/meson.build": "executable('t', '../../../host/exec/cache.c')\n",
    })
    want = ["host/stray.c", "host/graph/parse.c:2", "host/exec/cache.c:1",
            "tests/unit/x/meson.build:1"]
    return rulecheck.expect_findings("check_layers", check, files, want,
                                     lambda p, w: p.startswith(w))


if __name__ == "__main__":
    sys.exit(rulecheck.main(
        "check_layers", check, self_test,
        lambda n: f"{n} layering problem(s); the layers are in docs/architecture.md",
        "host layers: base < graph < exec < plan < viewer < cli, no include upward, "
        "no host source compiled by path outside host/"))
