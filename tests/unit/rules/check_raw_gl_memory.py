#!/usr/bin/env python3
"""No plugin makes GL device memory by hand (ABI 3.0, docs/sdk.md "Scratch device memory"):
under the folders given (plugins/ and sdk/template/), no C or C++ source calls a GL
function that creates, sizes or deletes a buffer or a texture (glCreateBuffers,
glNamedBufferStorage, glNamedBufferData, glTextureStorage*, glDeleteBuffers,
glDeleteTextures, ..., through the loader's table `gl->Name` or by symbol `glName`). They
go through lg_gl_buffer, lg_gl_texture and lg_gl_buffer_texture (lightgraph/gl.h), which
count every make and release in the profile. Each hit is printed as FILE:LINE: the call.
Comments and string literals are not calls.

usage: check_raw_gl_memory.py DIR...      (runs the self-test first)
       check_raw_gl_memory.py --self-test   (shows that the check finds what it must)
"""
import os
import re
import sys
import tempfile

# GL 4.5 names that make, size or delete buffer and texture storage (the DSA calls the
# plugins used, and the bind-to-edit ones that do the same)
CALLS = [
    "CreateBuffers", "GenBuffers", "NamedBufferStorage", "NamedBufferData", "BufferStorage",
    "BufferData", "DeleteBuffers",
    "CreateTextures", "GenTextures", "TextureStorage1D", "TextureStorage2D",
    "TextureStorage3D", "TextureStorage2DMultisample", "TextureStorage3DMultisample",
    "TexStorage1D", "TexStorage2D", "TexStorage3D", "TexStorage2DMultisample",
    "TexStorage3DMultisample", "TexImage1D", "TexImage2D", "TexImage3D",
    "TexImage2DMultisample", "TexImage3DMultisample", "TextureBuffer", "TexBuffer",
    "TextureBufferRange", "TexBufferRange", "DeleteTextures",
]
# `gl->Name(`, `ctx.Name(`, `glName(`, also a function pointer taken without a call
CALL = re.compile(r'(?:->|\.|\bgl)(%s)\b' % "|".join(CALLS))
COMMENT_OR_STRING = re.compile(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'',
                               re.S)
SOURCES = (".c", ".h", ".cpp", ".cc", ".cxx", ".hpp", ".inl")


def blank(text):
    """Comments and string literals blanked, newlines kept (line numbers stay)."""
    return COMMENT_OR_STRING.sub(lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)


def scan(roots):
    hits = []
    for root in roots:
        for d, dirs, files in os.walk(root):
            dirs.sort()
            for f in sorted(files):
                if not f.endswith(SOURCES):
                    continue
                path = os.path.join(d, f)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    text = blank(fh.read())
                for no, line in enumerate(text.splitlines(), 1):
                    for m in CALL.finditer(line):
                        hits.append("%s:%d: gl%s: %s" % (path, no, m.group(1), line.strip()))
    return hits


def self_test():
    """A made-up plugin with each kind of hit and each kind of non-hit."""
    bad = (
        "static void f(const lg_gl *gl, GLuint *b, GLuint *t)\n"   # 1
        "{\n"                                                        # 2
        "    gl->CreateBuffers(1, b);\n"                             # 3: hit
        "    /* gl->NamedBufferStorage(*b, 16, 0, 0); in a comment */\n"
        "    lg_log(n, LG_LOG_INFO, \"gl->DeleteTextures(1, t)\");\n"
        "    glTextureStorage2D(*t, 1, GL_RGBA32F, 4, 4);\n"         # 6: hit
        "    ctx.DeleteTextures(1, t); // gl->DeleteBuffers\n"       # 7: hit
        "    lg_gl_buffer_recreate(n, &st->buf, 16, 0, NULL);\n"
        "    int TextureStorage2Dx = 0, myBufferData = 0;\n"
        "}\n")
    with tempfile.TemporaryDirectory(prefix="lg-rules-") as d:
        os.makedirs(os.path.join(d, "plug"))
        path = os.path.join(d, "plug", "bad.c")
        with open(path, "w") as fh:
            fh.write(bad)
        with open(os.path.join(d, "plug", "notes.md"), "w") as fh:
            fh.write("gl->CreateBuffers is named in a README\n")
        got = [h.split(": ")[0] + ": " + h.split(": ")[1] for h in scan([d])]
    want = ["%s:3: glCreateBuffers" % path, "%s:6: glTextureStorage2D" % path,
            "%s:7: glDeleteTextures" % path]
    if got != want:
        print("FAIL: self-test: found %s, want %s" % (got, want))
        return 1
    print("ok: the self-test's three raw calls were found by file:line, and nothing else")
    return 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    roots = sys.argv[1:]
    if not roots:
        print(__doc__)
        return 2
    for r in roots:
        if not os.path.isdir(r):
            print("FAIL: %s is not a folder" % r)
            return 2
    if self_test():  # a check that finds nothing here must be able to find something
        return 1
    hits = scan(roots)
    for h in hits:
        print(h)
    if hits:
        print("FAIL: %d raw GL memory call(s); make buffers and textures with "
              "lg_gl_buffer_recreate, lg_gl_texture_recreate or lg_gl_buffer_texture_recreate "
              "(lightgraph/gl.h), which count them in the profile" % len(hits))
        return 1
    print("ok: no raw GL memory call under %s" % ", ".join(roots))
    return 0


if __name__ == "__main__":
    sys.exit(main())
