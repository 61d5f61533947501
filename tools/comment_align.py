#!/usr/bin/env python3
"""Re-indents the continuation lines of trailing block comments under their opening.

    clang-format ... FILE | python3 tools/comment_align.py > OUT

clang-format 14 with `ReflowComments: false` (which keeps every comment's words where the
author put them) moves a trailing comment's first line when it aligns the comments of
neighbouring lines, but leaves the comment's other lines where they were:

    lg_gl_pass *pass; /* the raster pass, for ... (phong_half:
                           * per-pixel Phong, ... */

This filter puts each such line's `*` under the opening's `*` again, and changes nothing
else: a comment of its own line, a line that does not start with `*`, and every line of
code pass through as they are. tools/format.sh runs it after clang-format, so --check and
--fix agree and a second --fix changes nothing.
"""
import re
import sys

CONTINUATION = re.compile(r"^[ \t]+(\*.*)$")


def align(lines):
    out = []
    col = None  # the column of the open trailing comment's '*', or None
    for line in lines:
        if col is not None:
            m = CONTINUATION.match(line)
            if m:
                line = " " * col + m.group(1)
                out.append(line)
                if "*/" in line:
                    col = None
                continue
            col = None
        out.append(line)
        start = line.find("/*")
        if start > 0 and line[:start].strip() and "*/" not in line[start + 2:] \
                and not line.rstrip().endswith("\\") and '"' not in line[start:]:
            col = start + 1
    return out


def main():
    text = sys.stdin.read()
    end = "\n" if text.endswith("\n") else ""
    lines = text[:-1].split("\n") if end else text.split("\n")
    sys.stdout.write("\n".join(align(lines)) + end)
    return 0


if __name__ == "__main__":
    sys.exit(main())
