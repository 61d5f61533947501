#!/usr/bin/env python3
"""A GLSL compute shader that #includes shaders/common files, compiled offline: the file
through tools/embed.py (which resolves the includes, as the build does), then
glslangValidator as a GLSL 4.50 compute shader with the given -D defines, so that a GLSL
error shows without a GL device. Used for rgbe.glsl (tests/unit/formats) and the reinhard
shaders with each set of defines the plugin uses (tests/plugins/reinhard).

usage: glsl_offline.py EMBED_PY GLSLANG SHADERS_COMMON_DIR FILE.comp [-DNAME[=VALUE]]...
"""
import os
import re
import subprocess
import sys
import tempfile


def main():
    if len(sys.argv) < 5:
        sys.stderr.write(__doc__)
        return 2
    embed_py, glslang, common, src = sys.argv[1:5]
    defines = sys.argv[5:]
    name = os.path.basename(src)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, name + ".h")
        subprocess.run([sys.executable, embed_py, "-I", common, src, out], check=True)
        text = open(out).read()
        body = text[text.index("[] = {", text.index("lg_src_") + 20):]
        data = bytes(int(h, 16) for h in re.findall(r"0x([0-9a-f]{2})", body)).rstrip(b"\0")
        comp = os.path.join(tmp, name)
        with open(comp, "wb") as f:
            f.write(data)
        r = subprocess.run([glslang, "-S", "comp"] + (["-l"] if defines else []) + defines + [comp],
                           capture_output=True,
                           text=True)
        if r.returncode != 0:
            sys.stderr.write("glslangValidator failed on %s %s:\n%s%s" %
                             (name, " ".join(defines), r.stdout, r.stderr))
            return 1
    print("%s %s: compiles" % (name, " ".join(defines)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
