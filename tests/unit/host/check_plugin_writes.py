#!/usr/bin/env python3
"""A plugin writes files only through the host (docs/sdk.md, "Files a node writes"): no
plugin source under plugins/ opens a file for writing, makes a temporary, renames or removes
a file, or writes an image file itself. Each hit is printed as FILE:LINE: the call.

usage: check_plugin_writes.py PLUGINS_DIR
"""
import os
import re
import sys

# calls that create, change or remove files; reading (fopen "r", open O_RDONLY) is fine
PATTERNS = [
    (re.compile(r'\b(f|fd)?open(64)?\s*\([^;]*,\s*"(?=[^"]*[wa+])[rwabxe+]*"\s*\)'),
     "fopen for writing"),
    (re.compile(r'\bfreopen\s*\('), "freopen"),
    (re.compile(r'\bopen(at)?(64)?\s*\([^;]*\bO_(WRONLY|RDWR|CREAT|TRUNC|APPEND)\b'),
     "open for writing"),
    (re.compile(r'\bcreat\s*\('), "creat"),
    (re.compile(r'\bmk(o)?s?temps?\s*\('), "a temporary file of its own"),
    (re.compile(r'\b(tmpfile|mkfifo|mknod|link|symlink)\s*\('), "a file of its own"),
    (re.compile(r'\b(rename|renameat|unlink|remove|truncate)\s*\('), "changes a file"),
    (re.compile(r'\blg_image_write\s*\('), "writes an image file itself"),
]
COMMENT = re.compile(r'/\*.*?\*/|//[^\n]*', re.S)
STRING = re.compile(r'"(\\.|[^"\\])*"')


def strip_comments(text):
    """Comments blanked (newlines kept, so that line numbers stay)."""
    return COMMENT.sub(lambda m: re.sub(r'[^\n]', ' ', m.group(0)), text)


def main():
    root = sys.argv[1]
    hits = []
    for d, _, files in os.walk(root):
        for f in sorted(files):
            if not f.endswith((".c", ".h", ".cpp", ".cc")):
                continue
            path = os.path.join(d, f)
            text = strip_comments(open(path, encoding="utf-8", errors="replace").read())
            for no, line in enumerate(text.splitlines(), 1):
                for rx, what in PATTERNS:
                    # a name inside a string (a message) is not a call, except for the
                    # fopen mode, which the pattern reads from the string itself
                    probe = line if what == "fopen for writing" else STRING.sub('""', line)
                    if rx.search(probe):
                        hits.append("%s:%d: %s: %s" % (path, no, what, line.strip()))
    for h in hits:
        print(h)
    if hits:
        print("FAIL: %d place(s) where a plugin writes a file itself; use an output-file "
              "parameter and lg_output_file_write (docs/sdk.md, \"Files a node writes\")"
              % len(hits))
        return 1
    print("ok: no plugin writes a file itself")
    return 0


if __name__ == "__main__":
    sys.exit(main())
