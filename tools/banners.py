#!/usr/bin/env python3
"""Section banners of one width: `/* ---- name ---...--- */` ending at column 100.

    python3 tools/banners.py --check [--width N] [FILES]   lists each banner of another width
    python3 tools/banners.py --fix [--width N] [FILES]     pads or trims them in place

The tree's 464 banners end anywhere from column 83 to 107 (most between 92 and 99), because
each was typed by hand. A banner is a line that is only a comment opening with four dashes
and a name: `/* ---- name ---- */`, `// ---- name ----`, or the first line of a block
comment, `/* ---- name ----` (the text follows on the next lines). Its trailing dashes are
padded or trimmed so that the line ends at column --width (default 100, the formatter's
column limit, docs/style.md); a name too long for that keeps three dashes and is reported.
Nothing else is touched: not the text, not the indent, not the `/* -- since ABI 2.0 --`
sub-headings of the SDK's tables. clang-format (ReflowComments: false) leaves banners alone,
so the two can run in either order and neither undoes the other.

Without FILES: the files tools/format.sh --list names. Exit status: 0 every banner has the
width (or was fixed), 1 some has not (--check) or a name is too long, 2 bad usage.
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BANNER = re.compile(r'^(?P<head>[ ]*(?:/\*|//) ---- (?P<name>\S.*?)) -{2,}(?P<close> \*/)?\s*$')


def fixed(line, width):
    """(the line at `width`, or the line itself; True if the name is too long)."""
    m = BANNER.match(line)
    if not m:
        return line, False
    close = m.group('close') or ''
    dashes = width - len(m.group('head')) - 1 - len(close)
    too_long = dashes < 3
    return '%s %s%s' % (m.group('head'), '-' * max(dashes, 3), close), too_long


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument('--check', action='store_true')
    mode.add_argument('--fix', action='store_true')
    ap.add_argument('--width', type=int, default=100)
    ap.add_argument('files', nargs='*')
    a = ap.parse_args()
    if a.width < 20:
        ap.error('--width %d: a banner needs at least 20 columns' % a.width)
    files = a.files
    if not files:
        listed = subprocess.run(['sh', os.path.join(ROOT, 'tools/format.sh'), '--list'],
                                capture_output=True, text=True, check=True).stdout.split()
        files = [os.path.join(ROOT, f) for f in listed]
    status = 0
    banners = off = 0
    for path in files:
        shown = os.path.relpath(path, ROOT) if path.startswith(ROOT + os.sep) else path
        try:
            with open(path, encoding='utf-8', newline='') as f:
                lines = f.read().split('\n')
        except OSError as e:
            print('banners.py: %s: %s' % (shown, e.strerror), file=sys.stderr)
            return 2
        changed = False
        for i, line in enumerate(lines):
            if not BANNER.match(line):
                continue
            banners += 1
            new, too_long = fixed(line, a.width)
            if too_long:
                print('%s:%d: banner name too long for %d columns' % (shown, i + 1, a.width))
                status = 1
            if new != line:
                off += 1
                changed = True
                if a.check:
                    print('%s:%d: banner ends at column %d, not %d'
                          % (shown, i + 1, len(line.rstrip()), a.width))
                    status = 1
                lines[i] = new
        if changed and a.fix:
            with open(path, 'w', encoding='utf-8', newline='') as f:
                f.write('\n'.join(lines))
    verb = 'of another width' if a.check else 'fixed'
    print('banners.py: %d banners, %d %s' % (banners, off, verb), file=sys.stderr)
    return status


if __name__ == '__main__':
    sys.exit(main())
