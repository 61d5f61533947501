#!/usr/bin/env python3
"""The volumetric_polygonal node's shaders compiled offline.

usage: test_polygonal_glsl.py EMBED_PY GLSLANG SHADER_DIR SHADERS_COMMON_DIR

Each stage goes through tools/embed.py (which resolves #include "medium.glsl"), is decoded
back to text and given to glslangValidator; the program pairs the plugin links (the volume
pass, the composite) are linked (-l), so that an interface mismatch between stages fails
here, not at run time on the first frame.
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
    programs = [["poly_mesh.comp"],
                ["poly_volume.vert", "poly_volume.frag"],
                ["poly_fullscreen.vert", "poly_composite.frag"]]
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for prog in programs:
            files = []
            for name in prog:
                text = expand(embed_py, common, os.path.join(sdir, name), tmp)
                path = os.path.join(tmp, name)
                with open(path, "w") as f:
                    f.write(text)
                files.append(path)
            r = subprocess.run([glslang, "-l"] + files,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            if r.returncode != 0:
                failures += 1
                print("FAIL %s:\n%s" % (" + ".join(prog), r.stdout))
            else:
                print("ok   %s" % " + ".join(prog))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
