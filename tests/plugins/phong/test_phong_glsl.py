#!/usr/bin/env python3
"""The phong node's shaders compiled offline.

usage: test_phong_glsl.py EMBED_PY GLSLANG SHADER_DIR SHADERS_COMMON_DIR

Each stage goes through tools/embed.py (which resolves #include "phong.glsl" and
"phong_scene.glsl"), is decoded back to text and compiled by glslangValidator with the
defines the plugin passes (LG_SHADING 0..4, LG_SV 0 and 3; LG_TAU too, the variant for a
medium with a density field, except for phong_half's id pass, 4): the vertex and fragment
stages for every mode, the geometry stage for flat (0) and mixed (3), and phong_half's
assembly pass (phong_fullscreen.vert, phong_half.frag) once.
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
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        jobs = []
        for mode in range(5):
            for sv in (0, 3):
                stages = ["vert", "frag"] + (["geom"] if mode in (0, 3) else [])
                for st in stages:
                    defs = ["-DLG_SHADING=%d" % mode, "-DLG_SV=%d" % sv,
                            "-DLG_SV_ARR=%d" % max(sv, 1)]
                    jobs.append((st, defs))
                    # the variant for a medium with a density field (its shadow on surfaces)
                    if mode != 4:
                        jobs.append((st, defs + ["-DLG_TAU=1"]))
        jobs.append(("fullscreen.vert", []))
        jobs.append(("half.frag", []))
        sources = {}
        for st, defs in jobs:
            name = ("phong_" + st) if "." in st else "phong." + st
            if name not in sources:
                path = os.path.join(tmp, name)
                with open(path, "w") as f:
                    f.write(expand(embed_py, common, os.path.join(sdir, name), tmp))
                sources[name] = path
            r = subprocess.run([glslang, "-l"] + defs + [sources[name]], capture_output=True,
                               text=True)
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
