#!/usr/bin/env python3
"""GLSL #include in tools/embed.py: resolution (the including file's folder, then the -I
folders in order; the build passes shaders/common/), #line directives that map compiler messages back to the files, include
once, errors for a missing file, a cycle and <file>, comments left alone, files without
includes embedded byte for byte, and the depfile. With glslangValidator (required), that the
compiler's "string:line" of an error in an included file is that file's line.

usage: test_embed_include.py EMBED_PY SHADERS_COMMON_DIR (passed to embed.py as -I)
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

embed, common = sys.argv[1], sys.argv[2]
failures = 0


def check(cond, msg):
    global failures
    if not cond:
        failures += 1
        print("check failed: " + msg, file=sys.stderr)


def run(src, out, dep=None, incs=None):
    """embed.py with -I shaders/common (as the build's generator) unless incs says otherwise."""
    incs = [common] if incs is None else incs
    args = [sys.executable, embed] + sum((["-I", d] for d in incs), []) + [src, out]
    args += [dep] if dep else []
    return subprocess.run(args, capture_output=True, text=True)


def embedded(path):
    """The bytes of the C array in a generated header, without the final NUL."""
    text = open(path).read()
    body = text[text.index("[] = {", text.index("lg_src_") + 1) + 6:text.rindex("}")]
    data = bytes(int(x, 16) for x in re.findall(r"0x([0-9a-f]{2})", body))
    check(data.endswith(b"\0"), "array does not end with NUL")
    return data[:-1]


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        f.write(text)


with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "out.h")
    dep = os.path.join(tmp, "out.d")

    # 1. no include: byte for byte (CRLF, no final newline, a comment mentioning #include)
    raw = "#version 450\r\n// #include \"nothing.glsl\" is only a comment\r\nvoid main() {}"
    write(os.path.join(tmp, "plain.comp"), raw)
    r = run(os.path.join(tmp, "plain.comp"), out, dep)
    check(r.returncode == 0, "plain: " + r.stderr)
    check(embedded(out) == raw.encode(), "plain file not embedded byte for byte")
    check("source strings" not in open(out).read(), "plain file header lists source strings")
    deps = open(dep).read()
    check(deps.startswith(out + ":") and "plain.comp" in deps and "embed.py" in deps,
          "plain depfile: " + deps)

    # 2. nesting, numbering, #line, include once, folder then shaders/common/
    write(os.path.join(tmp, "sub", "a.glsl"), "// a line 1\n#include \"b.glsl\"\nfloat a() { return b(); }\n")
    write(os.path.join(tmp, "sub", "b.glsl"), "// b line 1\nfloat b() { return 1.0; }\n")
    write(os.path.join(tmp, "sub", "main.frag"),
          "#version 450\n#include \"a.glsl\"\n#include \"b.glsl\"\n  #  include \"phong.glsl\" // common\n"
          "void main() {}\n")
    r = run(os.path.join(tmp, "sub", "main.frag"), out, dep)
    check(r.returncode == 0, "nested: " + r.stderr)
    got = embedded(out).decode()
    phong = open(os.path.join(common, "phong.glsl")).read()
    want = ("#version 450\n"
            "#line 1 1\n"
            "// a line 1\n"
            "#line 1 2\n"
            "// b line 1\nfloat b() { return 1.0; }\n"
            "#line 3 1\n"
            "float a() { return b(); }\n"
            "#line 3 0\n"
            "// #include \"b.glsl\": already included\n"
            "#line 1 3\n" + phong + ("" if phong.endswith("\n") else "\n") +
            "#line 5 0\n"
            "void main() {}\n")
    check(got == want, "nested expansion differs:\n--- got\n%s\n--- want\n%s" % (got[:600], want[:600]))
    check("GLSL source strings: 0 main.frag, 1 a.glsl, 2 b.glsl, 3 phong.glsl" in open(out).read(),
          "source-string list missing")
    deps = open(dep).read()
    for name in ("main.frag", "a.glsl", "b.glsl", os.path.join(common, "phong.glsl")):
        check(name in deps, "depfile lacks %s: %s" % (name, deps))

    # 3. errors: missing, cycle, <file>; no output written
    write(os.path.join(tmp, "missing.comp"), "#version 450\n\n#include \"nope.glsl\"\n")
    out2 = os.path.join(tmp, "never.h")
    r = run(os.path.join(tmp, "missing.comp"), out2)
    check(r.returncode != 0, "missing include accepted")
    check("missing.comp:3" in r.stderr and "nope.glsl" in r.stderr and "not found" in r.stderr,
          "missing include message: " + r.stderr)
    check(not os.path.exists(out2), "output written despite an error")
    write(os.path.join(tmp, "cyc", "x.glsl"), "#include \"y.glsl\"\n")
    write(os.path.join(tmp, "cyc", "y.glsl"), "\n#include \"x.glsl\"\n")
    write(os.path.join(tmp, "cyc", "c.comp"), "#version 450\n#include \"x.glsl\"\n")
    r = run(os.path.join(tmp, "cyc", "c.comp"), out2)
    check(r.returncode != 0, "cycle accepted")
    check("y.glsl:2" in r.stderr and "cycle" in r.stderr and "x.glsl -> y.glsl -> x.glsl" in r.stderr,
          "cycle message: " + r.stderr)
    write(os.path.join(tmp, "angle.comp"), "#version 450\n#include <phong.glsl>\n")
    r = run(os.path.join(tmp, "angle.comp"), out2)
    check(r.returncode != 0 and "angle.comp:2" in r.stderr, "#include <file> accepted: " + r.stderr)

    # 4. inside a block comment: left alone (and then no include at all: byte for byte)
    text = "#version 450\n/* an example:\n#include \"nope.glsl\"\n*/\nvoid main() {}\n"
    write(os.path.join(tmp, "comment.comp"), text)
    r = run(os.path.join(tmp, "comment.comp"), out)
    check(r.returncode == 0 and embedded(out) == text.encode(), "#include in a comment expanded: " + r.stderr)

    # 5. OpenCL: never expanded
    text = "#include \"nope.h\"\nkernel void k() {}\n"
    write(os.path.join(tmp, "k.cl"), text)
    r = run(os.path.join(tmp, "k.cl"), out)
    check(r.returncode == 0 and embedded(out) == text.encode(), ".cl expanded: " + r.stderr)

    # 6. -I: searched after the includer's folder, in the order given; without it nothing
    #    outside the includer's folder is found; a -I that is not a folder is an error
    write(os.path.join(tmp, "i1", "x.glsl"), "// from i1\n")
    write(os.path.join(tmp, "i2", "x.glsl"), "// from i2\n")
    write(os.path.join(tmp, "i2", "y.glsl"), "// y from i2\n")
    write(os.path.join(tmp, "top", "t.frag"), "#version 450\n#include \"x.glsl\"\n#include \"y.glsl\"\n")
    r = run(os.path.join(tmp, "top", "t.frag"), out, incs=[os.path.join(tmp, "i1"), os.path.join(tmp, "i2")])
    got = embedded(out).decode() if r.returncode == 0 else ""
    check(r.returncode == 0 and "// from i1" in got and "// from i2" not in got and "// y from i2" in got,
          "-I order: " + r.stderr + got)
    write(os.path.join(tmp, "top", "x.glsl"), "// from top\n")
    r = run(os.path.join(tmp, "top", "t.frag"), out, incs=[os.path.join(tmp, "i1"), os.path.join(tmp, "i2")])
    got = embedded(out).decode() if r.returncode == 0 else ""
    check(r.returncode == 0 and "// from top" in got and "from i1" not in got,
          "the includer's folder comes before -I: " + r.stderr + got)
    r = run(os.path.join(tmp, "top", "t.frag"), out2, incs=[])
    check(r.returncode != 0 and "y.glsl" in r.stderr and not os.path.exists(out2),
          "found without -I: " + r.stderr)
    r = run(os.path.join(tmp, "top", "t.frag"), out2, incs=[os.path.join(tmp, "no-such-folder")])
    check(r.returncode != 0 and "no-such-folder" in r.stderr and not os.path.exists(out2),
          "a -I that is not a folder accepted: " + r.stderr)

    # 7. the compiler's view: an error on line 2 of an included file and one on line 4 of
    #    the top file (the line after the #include) are reported as 1:2 and 0:4.
    #    glslang-tools is a dependency (tools/deps.sh): without it this test fails.
    glslang = shutil.which("glslangValidator")
    check(glslang is not None, "glslangValidator not found (glslang-tools, tools/deps.sh)")
    if glslang:
        # (glslang stops at the first error: one file each)
        expanded = os.path.join(tmp, "err", "expanded.comp")
        for inc_body, where, ident in (
                ("float ok() { return 1.0; }\nfloat bad() { return undefined_a; }\n", "1:2", "undefined_a"),
                ("float ok() { return 1.0; }\n", "0:4", "undefined_b")):
            write(os.path.join(tmp, "err", "inc.glsl"), inc_body)
            write(os.path.join(tmp, "err", "e.comp"),
                  "#version 450\nlayout(local_size_x = 1) in;\n#include \"inc.glsl\"\n"
                  "void main() { float x = undefined_b; }\n")
            r = run(os.path.join(tmp, "err", "e.comp"), out)
            check(r.returncode == 0, "err: " + r.stderr)
            with open(expanded, "wb") as f:
                f.write(embedded(out))
            g = subprocess.run([glslang, expanded], capture_output=True, text=True)
            msg = g.stdout + g.stderr
            check(re.search(where + r": '?" + ident, msg) is not None,
                  "error on %s not reported at %s:\n%s" % (ident, where, msg))
        # and shaders/common/phong.glsl compiles in a shader
        write(os.path.join(tmp, "ok", "ok.comp"),
              "#version 450\nlayout(local_size_x = 1) in;\n#include \"phong.glsl\"\n"
              "layout(std430, binding = 0) buffer B { vec4 v[]; };\n"
              "void main() { v[0].x = lg_depth_cue(v[1].x, v[1].y); }\n")
        r = run(os.path.join(tmp, "ok", "ok.comp"), out)
        with open(expanded, "wb") as f:
            f.write(embedded(out))
        g = subprocess.run([glslang, expanded], capture_output=True, text=True)
        check(g.returncode == 0, "phong.glsl does not compile:\n" + g.stdout + g.stderr)

if failures:
    print("embed_include: %d check(s) failed" % failures, file=sys.stderr)
    sys.exit(1)
print("embed_include: all checks passed")
