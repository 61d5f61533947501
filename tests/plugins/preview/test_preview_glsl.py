#!/usr/bin/env python3
"""The preview node's shaders compiled offline, after tools/embed.py has resolved their
#include lines (preview.frag includes shaders/common/material.glsl).

usage: test_preview_glsl.py EMBED_PY GLSLANG SHADER_DIR SHADERS_COMMON_DIR [FILE...]

Stages: preview.vert, preview.frag with and without LG_WIREFRAME (the define the plugin
passes when `wireframe` > 0), preview_wire.geom; or, with FILEs, those of SHADER_DIR
(without defines: tests/plugins/texgl checks shadowmap's stages so).
"""
import os
import re
import subprocess
import sys
import tempfile


def expand(embed_py, common, src, tmp):
    out = os.path.join(tmp, os.path.basename(src) + ".h")
    subprocess.run([sys.executable, embed_py, "-I", common, src, out], check=True)
    text = open(out).read()
    body = text[text.index("[] = {", text.index("lg_src_") + 20):]
    data = bytes(int(h, 16) for h in re.findall(r"0x([0-9a-f]{2})", body))
    return data.rstrip(b"\0").decode()


def main():
    embed_py, glslang, sdir, common = sys.argv[1:5]
    jobs = [("preview.vert", []), ("preview.frag", []), ("preview.frag", ["-DLG_WIREFRAME=1"]),
            ("preview_wire.geom", [])]
    if len(sys.argv) > 5:
        jobs = [(f, []) for f in sys.argv[5:]]
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name, defs in jobs:
            path = os.path.join(tmp, name)
            with open(path, "w") as f:
                f.write(expand(embed_py, common, os.path.join(sdir, name), tmp))
            r = subprocess.run([glslang, "-l"] + defs + [path], capture_output=True, text=True)
            if r.returncode != 0:
                failures += 1
                sys.stderr.write("%s %s: glslangValidator failed:\n%s%s\n" %
                                 (name, " ".join(defs), r.stdout, r.stderr))
    if failures:
        sys.stderr.write("%d compilation(s) failed\n" % failures)
        return 1
    sys.stderr.write("%d compilations passed\n" % len(jobs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
