#!/usr/bin/env python3
"""The plugin ABI version, read from its one place: the changelog of docs/sdk.md.

usage: abi_version.py SDK_MD            prints "MAJOR.MINOR" of the newest entry
       abi_version.py --check SDK_MD    checks the changelog only (exit 1 with the reason)

The changelog is the list under the heading "Changelog" of the section "## ABI": each entry
is a line "- MAJOR.MINOR ..." (a range "- 2.2-2.4" is not allowed: one entry per version),
newest first. The top-level meson.build runs this script at configure time and generates
lightgraph/config.h (LG_ABI_MAJOR, LG_ABI_MINOR), the pkg-config variables and the
library's soversion from what it prints, so that the version and its changelog cannot
disagree: a new version is a new entry, and nothing else is edited by hand.

Checked (the build fails, naming the line): the section and its list exist; every entry's
version is well formed; versions strictly decrease down the list; a major bump starts at
minor 0 (3.0 after 2.7, never 3.1 after 2.7).
"""
import re
import sys

ENTRY_RE = re.compile(r'^- (\d+)\.(\d+)([^\d.-]|$)')
LOOKS_LIKE_ENTRY_RE = re.compile(r'^- \d')


def entries(path):
    """[(major, minor, line_number)] of the changelog, in file order."""
    with open(path, encoding='utf-8') as f:
        lines = f.read().split('\n')
    in_abi = in_list = False
    found = []
    for i, line in enumerate(lines, 1):
        if line.startswith('## '):
            if in_abi:
                break
            in_abi = line.strip() == '## ABI'
            continue
        if not in_abi:
            continue
        if line.startswith('Changelog'):
            in_list = True
            continue
        if not in_list or not LOOKS_LIKE_ENTRY_RE.match(line):
            continue
        m = ENTRY_RE.match(line)
        if not m:
            raise ValueError(f'{path}:{i}: a changelog entry must start "- MAJOR.MINOR" '
                             f'(one version per entry): {line.strip()!r}')
        found.append((int(m.group(1)), int(m.group(2)), i))
    if not found:
        raise ValueError(f'{path}: no changelog entry ("- MAJOR.MINOR ...") under '
                         '"Changelog" in the section "## ABI"')
    return found


def check(path):
    found = entries(path)
    for (a_maj, a_min, a_line), (b_maj, b_min, b_line) in zip(found, found[1:]):
        if (a_maj, a_min) <= (b_maj, b_min):
            raise ValueError(f'{path}:{a_line}: {a_maj}.{a_min} is listed above '
                             f'{b_maj}.{b_min} (line {b_line}): newest first, one entry '
                             'per version')
        if a_maj != b_maj and a_min != 0:
            raise ValueError(f'{path}:{a_line}: {a_maj}.{a_min} follows {b_maj}.{b_min}: '
                             'a major bump starts at minor 0')
    return found


def main(argv):
    args = argv[1:]
    only_check = bool(args) and args[0] == '--check'
    if only_check:
        args = args[1:]
    if len(args) != 1:
        print(__doc__.split('\n\n')[1], file=sys.stderr)
        return 2
    try:
        found = check(args[0])
    except (OSError, ValueError) as e:
        print(f'abi_version.py: {e}', file=sys.stderr)
        return 1
    if only_check:
        print(f'ok: {len(found)} entries, newest {found[0][0]}.{found[0][1]}')
    else:
        print(f'{found[0][0]}.{found[0][1]}')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
