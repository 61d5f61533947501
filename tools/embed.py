#!/usr/bin/env python3
"""Embed a shader or kernel file as a C string (Mesa's xxd.py idea, simpler).

usage: embed.py [-I DIR]... INPUT OUTPUT_H [DEPFILE]

Installed with the SDK (<datadir>/lightgraph/embed.py; `pkg-config --variable=embed
lightgraph` gives its path), so that a plugin built out of tree embeds its shaders as the
in-tree plugins do; docs/sdk.md has the meson generator to copy.

Writes `static const char lg_src_<name>[]` (name: the file name with every non
alphanumeric character turned into '_') and `static const char lg_src_<name>_file[]`,
the file's name for compiler messages. GLSL sources keep their #version line first;
lg_gl_program() inserts its defines and a `#line 2` after it, so that messages point at
the file's own lines.

GLSL includes. In a GLSL file (.vert .frag .comp .geom .tesc .tese .glsl), a line
`#include "file"` is replaced by the file's text, found relative to the including file's
folder, then in each -I folder in the order given (the lightgraph build passes
shaders/common/), then, for the installed script, the SDK's shader twins installed beside
it (<datadir>/lightgraph/shaders, the pkg-config variable `shadersdir`). Included text is wrapped in GLSL core #line directives:
`#line 1 N` before it (N: the included file's source-string number, 1, 2, ... in order of
first inclusion; the top file is 0) and `#line NEXT P` after it (NEXT: the number of the
line after the #include, P: the includer's number), so that a compiler message "N:L"
means line L of source string N; the generated header lists the numbers in a comment.
Each file is included once per top file (a repeated #include becomes a comment line);
a missing file, an include cycle, or `#include <file>` is an error naming the file and
line. Includes are resolved whatever #if/#ifdef surround them; #include lines inside
/* */ comments are left alone. A file without #include is embedded byte for byte. Other
files (OpenCL .cl) are embedded byte for byte.

DEPFILE, when given, receives a Makefile-style rule "OUTPUT_H: INPUT INCLUDED... embed.py",
so that the build reruns this script when an included file (or the script) changes.
"""
import os
import re
import sys

GLSL_EXTS = {".vert", ".frag", ".comp", ".geom", ".tesc", ".tese", ".glsl"}
INCLUDE_RE = re.compile(r'^[ \t]*#[ \t]*include\b(.*)$')
QUOTED_RE = re.compile(r'^[ \t]+"([^"]+)"[ \t]*(//.*|/\*.*\*/[ \t]*)?\r?$')


class EmbedError(Exception):
    pass


def in_block_comment_after(line, in_block):
    """Whether a /* */ comment is open at the end of `line`, given its state at the start."""
    i = 0
    while i < len(line):
        if in_block:
            j = line.find("*/", i)
            if j < 0:
                return True
            in_block = False
            i = j + 2
        elif line.startswith("//", i):
            return False
        elif line.startswith("/*", i):
            in_block = True
            i += 2
        else:
            i += 1
    return in_block


class Includer:
    def __init__(self, include_dirs):
        self.include_dirs = include_dirs  # -I folders, searched after the includer's own
        self.numbers = {}   # real path -> source-string number
        self.names = []     # number -> path for messages
        self.stack = []     # real paths being expanded, for cycle detection

    def resolve(self, name, including, line_no):
        folders = [os.path.dirname(including) or "."] + self.include_dirs
        for folder in folders:
            path = os.path.join(folder, name)
            if os.path.isfile(path):
                return path
        raise EmbedError('%s:%d: error: #include "%s": not found in %s'
                         % (including, line_no, name, ", ".join(folders)))

    def expand(self, path, text):
        """The text of `path` (already read) with its includes expanded; `path` must already
        have its number."""
        real = os.path.realpath(path)
        number = self.numbers[real]
        self.stack.append(real)
        out = []
        in_block = False
        lines = text.split("\n")
        # text.split leaves a last empty element when the text ends with a newline
        for i, line in enumerate(lines):
            last = i == len(lines) - 1
            m = None if in_block else INCLUDE_RE.match(line)
            if m is None:
                in_block = in_block_comment_after(line, in_block)
                out.append(line if last else line + "\n")
                continue
            q = QUOTED_RE.match(m.group(1))
            if q is None:
                raise EmbedError('%s:%d: error: only #include "file" is supported, not: %s'
                                 % (path, i + 1, line.strip()))
            child = self.resolve(q.group(1), path, i + 1)
            child_real = os.path.realpath(child)
            if child_real in self.stack:
                chain = " -> ".join(os.path.basename(p) for p in self.stack + [child_real])
                raise EmbedError('%s:%d: error: #include "%s" makes a cycle: %s'
                                 % (path, i + 1, q.group(1), chain))
            if child_real in self.numbers:
                out.append('// #include "%s": already included' % q.group(1) + ("" if last else "\n"))
                continue
            self.numbers[child_real] = len(self.names)
            self.names.append(child)
            with open(child, "rb") as f:
                child_text = f.read().decode("latin-1")
            body = self.expand(child, child_text)
            if not body.endswith("\n"):
                body += "\n"
            out.append("#line 1 %d\n" % self.numbers[child_real])
            out.append(body)
            out.append("#line %d %d\n" % (i + 2, number))
            if last:
                # the #include was the last line, without a newline: drop the directive's
                out[-1] = out[-1][:-1]
        self.stack.pop()
        return "".join(out)


def main(argv):
    include_dirs = []
    args = []
    i = 1
    while i < len(argv):
        a = argv[i]
        if a == "-I" and i + 1 < len(argv):
            include_dirs.append(argv[i + 1])
            i += 2
            continue
        if a.startswith("-I") and len(a) > 2:
            include_dirs.append(a[2:])
        elif a.startswith("-") and a != "-":
            sys.stderr.write("embed.py: unknown option %s\n" % a)
            return 2
        else:
            args.append(a)
        i += 1
    if len(args) not in (2, 3):
        sys.stderr.write("usage: embed.py [-I DIR]... INPUT OUTPUT_H [DEPFILE]\n")
        return 2
    for d in include_dirs:
        if not os.path.isdir(d):
            # a typo in the build file must not turn into "not found" at some later #include
            sys.stderr.write("embed.py: -I %s: not a folder\n" % d)
            return 2
    # Installed with the SDK, the script sits in <datadir>/lightgraph beside shaders/, the
    # SDK's GLSL twins (rgbe.glsl, probe.glsl, medium.glsl): searched after every -I folder,
    # so that an out-of-tree shader's `#include "rgbe.glsl"` needs no -I at all. (In the
    # source tree tools/shaders does not exist; the build passes -I shaders/common.)
    installed_twins = os.path.join(os.path.dirname(os.path.abspath(__file__)), "shaders")
    if os.path.isdir(installed_twins) and installed_twins not in include_dirs:
        include_dirs.append(installed_twins)
    src, out = args[0], args[1]
    depfile = args[2] if len(args) == 3 else None
    base = os.path.basename(src)
    name = re.sub(r"[^A-Za-z0-9]", "_", base)
    with open(src, "rb") as f:
        data = f.read()
    inc = Includer(include_dirs)
    if os.path.splitext(src)[1] in GLSL_EXTS:
        inc.numbers[os.path.realpath(src)] = 0
        inc.names.append(src)
        try:
            text = inc.expand(src, data.decode("latin-1"))
        except EmbedError as e:
            sys.stderr.write("embed.py: %s\n" % e)
            return 1
        if len(inc.names) > 1:
            data = text.encode("latin-1")
    lines = []
    for i in range(0, len(data), 16):
        lines.append(", ".join("0x%02x" % b for b in data[i:i + 16]))
    with open(out, "w") as f:
        f.write("/* generated by embed.py from %s; do not edit */\n" % base)
        if len(inc.names) > 1:
            f.write("/* GLSL source strings: %s */\n"
                    % ", ".join("%d %s" % (n, os.path.basename(p)) for n, p in enumerate(inc.names)))
        f.write("static const char lg_src_%s_file[] = \"%s\";\n" % (name, base))
        f.write("static const char lg_src_%s[] = {\n" % name)
        f.write(",\n".join(lines) + (",\n" if lines else ""))
        f.write("0x00 };\n")
    if depfile:
        def esc(p):
            return p.replace("\\", "\\\\").replace(" ", "\\ ").replace("#", "\\#").replace("$", "$$")
        # the script itself too: a change in how includes expand must re-embed
        deps = [src] + inc.names[1:] + [os.path.abspath(__file__)]
        with open(depfile, "w") as f:
            f.write("%s: %s\n" % (esc(out), " ".join(esc(p) for p in deps)))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
