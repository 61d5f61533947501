#!/usr/bin/env python3
"""The layers of the SDK's image files (sdk/src/image_alloc.h), checked by reading the tree.

    check_sdk_image_layers.py SOURCE_ROOT

    2  image.c                                 format dispatch, the atomic write
    1  exr.c exr_cxx.cpp hdr.c png.c compare.c the codecs, and the comparison
    0  image_alloc.c half.c rgbe.c formats.c file.c
                                               images in memory, the limits, encodings, files

1. No file names a function defined (not static) in a file of a higher layer: a codec never
   calls back into image.c, image_alloc.c never calls a codec. Names are read with comments
   and strings left out, so a call, a function pointer or an address all count.
2. The bottom layer includes image_alloc.h, never image_priv.h (the codecs' entry points),
   and image_alloc.h includes no header of the layers above.
3. Every source of lg_image_sources (sdk/src/meson.build) has a layer here, so that a new
   file is placed before it can call anywhere.

Each broken rule is printed as FILE:LINE and the reason; the exit status is 1 when any is.
A self-test runs first on a scratch tree with one violation of each kind, so that a check
that finds nothing cannot pass by accident.
"""
import os
import re
import sys
import tempfile

LAYERS = [
    ["image_alloc.c", "half.c", "rgbe.c", "formats.c", "file.c"],
    ["exr.c", "exr_cxx.cpp", "hdr.c", "png.c", "compare.c"],
    ["image.c"],
]
RANK = {name: rank for rank, names in enumerate(LAYERS) for name in names}
# the headers of the layers above the bottom, which the bottom may not include
UPPER_HEADERS = {"image_priv.h"}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
# a definition at the start of a line: return type, the name, the parameters, the body
DEFINITION = re.compile(r'^(?!static\b)(?:extern\s+"C"\s+)?[A-Za-z_][\w \t*]*?\b(lg_\w+)\s*'
                        r'\([^;{]*\)\s*\{', re.M)
NAME = re.compile(r'\blg_\w+\b')
SOURCES = re.compile(r"lg_image_sources\s*=\s*files\((.*?)\)", re.S)
# a comment, a string or a character literal, whichever starts first
LEXEME = re.compile(r"/\*.*?(?:\*/|\Z)|//[^\n]*|"
                    r"\"(?:\\.|[^\"\\\n])*\"?|'(?:\\.|[^'\\\n])*'?", re.S)


def strip(text):
    """The text with comments, strings and character literals blanked (newlines kept, so
    that offsets still give the right line)."""
    return LEXEME.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def line_of(text, offset):
    return text.count("\n", 0, offset) + 1


def check(root):
    src = os.path.join(root, "sdk", "src")
    problems = []
    texts, defined = {}, {}
    for name in RANK:
        path = os.path.join(src, name)
        if not os.path.exists(path):
            problems.append(f"sdk/src/{name}: listed in a layer but missing")
            continue
        with open(path, encoding="utf-8") as f:
            raw = f.read()
        texts[name] = (raw, strip(raw))
        for m in DEFINITION.finditer(texts[name][1]):
            defined.setdefault(m.group(1), name)

    for name, (raw, text) in sorted(texts.items()):
        own = {fn for fn, where in defined.items() if where == name}
        for m in NAME.finditer(text):
            fn = m.group(0)
            where = defined.get(fn)
            if fn in own or where is None or RANK[where] <= RANK[name]:
                continue
            problems.append(f"sdk/src/{name}:{line_of(text, m.start())}: names {fn} of "
                            f"{where}, a layer above it")
        if RANK[name] == 0:
            for m in INCLUDE.finditer(raw):
                if m.group(1) in UPPER_HEADERS:
                    problems.append(f'sdk/src/{name}:{line_of(raw, m.start())}: includes '
                                    f'"{m.group(1)}" of the layers above; the bottom '
                                    f'includes image_alloc.h')

    alloc_h = os.path.join(src, "image_alloc.h")
    if os.path.exists(alloc_h):
        with open(alloc_h, encoding="utf-8") as f:
            raw = f.read()
        for m in INCLUDE.finditer(raw):
            if m.group(1) in UPPER_HEADERS:
                problems.append(f'sdk/src/image_alloc.h:{line_of(raw, m.start())}: includes '
                                f'"{m.group(1)}" of the layers above')
    else:
        problems.append("sdk/src/image_alloc.h: missing")

    meson = os.path.join(src, "meson.build")
    with open(meson, encoding="utf-8") as f:
        raw = f.read()
    m = SOURCES.search(raw)
    if not m:
        problems.append("sdk/src/meson.build: no lg_image_sources = files(...)")
    else:
        body = m.group(1)
        for s in re.finditer(r"'([^']+\.(?:c|cpp))'", body):
            if s.group(1) not in RANK:
                line = line_of(raw, m.start(1) + s.start())
                problems.append(f"sdk/src/meson.build:{line}: {s.group(1)} in lg_image_sources "
                                f"has no layer in {os.path.basename(__file__)}")
    return problems


def self_test():
    with tempfile.TemporaryDirectory() as tmp:
        def put(rel, text):
            p = os.path.join(tmp, rel)
            os.makedirs(os.path.dirname(p), exist_ok=True)
            with open(p, "w", encoding="utf-8") as f:
                f.write(text)
        for name in RANK:
            put(f"sdk/src/{name}", "/* nothing */\n")
        put("sdk/src/image_alloc.h", '#include "lightgraph/image.h"\n')
        put("sdk/src/image.c",
            "int lg_image_read(const char *p,\n                  int f)\n{\n"
            "    return lg_hdr_read(p) + lg_image_alloc(p);\n}\n")
        # a call upward on line 5; the name in a comment and in a string does not count
        put("sdk/src/hdr.c",
            '#include "image_priv.h"\n/* lg_image_read( */\nint lg_hdr_read(const char *p)\n'
            '{ const char *s = "lg_image_read(";\n'
            '  return lg_image_read(p, 0) + lg_image_alloc(p); }\n')
        put("sdk/src/image_alloc.c",
            '#include "image_priv.h"\nint lg_image_alloc(const char *p)\n{\n'
            '    int (*f)(const char *) = lg_hdr_read;\n    return f(p);\n}\n')
        put("sdk/src/meson.build",
            "lg_image_sources = files(\n  'image_alloc.c',\n  'stray.c', # no layer\n)\n")
        found = check(tmp)
        want = ["sdk/src/hdr.c:5", "sdk/src/image_alloc.c:1", "sdk/src/image_alloc.c:4",
                "sdk/src/meson.build:3"]
        missing = [w for w in want if not any(p.startswith(w + ":") for p in found)]
        if missing or len(found) != len(want):
            print("check_sdk_image_layers self-test failed: expected a problem at each of",
                  want, "got", found, file=sys.stderr)
            return False
    return True


def main():
    if len(sys.argv) != 2:
        print("usage: check_sdk_image_layers.py SOURCE_ROOT", file=sys.stderr)
        return 2
    if not self_test():
        return 1
    problems = check(sys.argv[1])
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} layering problem(s); the layers are in sdk/src/image_alloc.h",
              file=sys.stderr)
        return 1
    print("sdk image files: image.c > codecs (exr, exr_cxx, hdr, png, compare) > image_alloc.c "
          "and the encodings; no call upward")
    return 0


if __name__ == "__main__":
    sys.exit(main())
