#!/usr/bin/env python3
"""How far the tree is from a clang-format configuration: the measurement behind .clang-format.

    python3 tools/format_measure.py [--base FILE] [--set KEY=VALUE ...] [--try 'KEY=V1|V2|...']

Formats every file `tools/format.sh --list` names (in memory; nothing is written) with the
base configuration (default: the root's .clang-format) and prints the lines `diff` prints
between the tree and the result (`diff | wc -l`, the count docs/style.md reports), the
original lines changed, and the files touched. --set overrides a key of the base for every
run (a value may be YAML: `{Enabled: true}`); --try 'KEY=V1|V2' runs once per value, so that
settings can be compared one key at a time. clang-format 14, as tools/format.sh requires.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def load(path):
    # .clang-format is flat `Key: value` lines (nested maps are written inline), so a dict
    # of lines keeps its order and needs no YAML parser.
    keys = {}
    with open(path) as f:
        for line in f:
            s = line.split('#', 1)[0].rstrip()
            if not s or s.startswith('---') or s.startswith('...') or ':' not in s:
                continue
            k, v = s.split(':', 1)
            keys[k.strip()] = v.strip()
    return keys


def measure(cf, style, files, jobs):
    """(diff lines, original lines changed, files changed) of `files` under `style`."""
    with tempfile.TemporaryDirectory(prefix='lg-format-measure.') as tmp:
        cfg = os.path.join(tmp, '.clang-format')
        with open(cfg, 'w') as f:
            f.write(''.join('%s: %s\n' % kv for kv in style.items()))
        copies = []
        for path in files:
            copy = os.path.join(tmp, 'tree', os.path.relpath(path, ROOT))
            os.makedirs(os.path.dirname(copy), exist_ok=True)
            shutil.copyfile(path, copy)
            copies.append(copy)
        # one clang-format per share of the files: a process per file costs more than the
        # formatting itself
        shares = [copies[i::jobs] for i in range(jobs)]
        procs = [subprocess.Popen([cf, '-i', '--style=file:' + cfg] + s,
                                  stderr=subprocess.DEVNULL) for s in shares if s]
        if any([p.wait() for p in procs]):
            # clang-format 14 crashes on some settings (AlignArrayOfStructures: Left)
            return None
        total = changed = touched = 0
        for path, copy in zip(files, copies):
            d = subprocess.run(['diff', path, copy], capture_output=True).stdout
            lines = d.decode('utf-8', 'replace').splitlines()
            total += len(lines)
            changed += sum(1 for x in lines if x.startswith('<'))
            touched += 1 if lines else 0
    return total, changed, touched


def row(label, r):
    if r is None:
        print('%-52s %s' % (label, 'clang-format failed (crashed?)'))
    else:
        print('%-52s %8d %8d %6d' % ((label,) + r))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--base', default=os.path.join(ROOT, '.clang-format'))
    ap.add_argument('--set', action='append', default=[], metavar='KEY=VALUE')
    ap.add_argument('--try', dest='tries', action='append', default=[], metavar='KEY=V1|V2')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--clang-format', default=os.environ.get('CLANG_FORMAT', 'clang-format-14'))
    a = ap.parse_args()
    base = load(a.base)
    for s in a.set:
        k, v = s.split('=', 1)
        base[k] = v
    listed = subprocess.run(['sh', os.path.join(ROOT, 'tools/format.sh'), '--list'],
                            capture_output=True, text=True, check=True).stdout.split()
    files = [os.path.join(ROOT, f) for f in listed]
    print('%d files' % len(files))
    print('%-52s %8s %8s %6s' % ('setting', 'diff', 'changed', 'files'))
    row('base', measure(a.clang_format, base, files, a.jobs))
    sys.stdout.flush()
    for t in a.tries:
        k, vs = t.split('=', 1)
        for v in vs.split('|'):
            style = dict(base)
            style[k] = v
            row('%s: %s' % (k, v), measure(a.clang_format, style, files, a.jobs))
            sys.stdout.flush()
    return 0


if __name__ == '__main__':
    sys.exit(main())
