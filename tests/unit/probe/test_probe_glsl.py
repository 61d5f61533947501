#!/usr/bin/env python3
"""shaders/common/probe.glsl compiled offline: tests/unit/probe/probe_eval.comp (which
#includes it) through tools/embed.py, then glslangValidator as a GLSL 4.50 compute shader,
so that a GLSL error shows without a GL device.

usage: test_probe_glsl.py EMBED_PY GLSLANG SHADERS_COMMON_DIR PROBE_EVAL_COMP
"""
import os
import re
import subprocess
import sys
import tempfile


def main():
    embed_py, glslang, common, src = sys.argv[1:5]
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "probe_eval.comp.h")
        subprocess.run([sys.executable, embed_py, "-I", common, src, out], check=True)
        text = open(out).read()
        body = text[text.index("[] = {", text.index("lg_src_") + 20):]
        data = bytes(int(h, 16) for h in re.findall(r"0x([0-9a-f]{2})", body)).rstrip(b"\0")
        comp = os.path.join(tmp, "probe_eval.comp")
        with open(comp, "wb") as f:
            f.write(data)
        r = subprocess.run([glslang, "-S", "comp", comp], capture_output=True, text=True)
        if r.returncode != 0:
            sys.stderr.write("glslangValidator failed on probe_eval.comp (probe.glsl):\n%s%s"
                             % (r.stdout, r.stderr))
            return 1
        if re.search(r"^[ \t]*#[ \t]*include", data.decode(), re.M):
            sys.stderr.write("probe_eval.comp: the #include was not expanded\n")
            return 1
    print("probe.glsl: compiles offline (glslangValidator)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
