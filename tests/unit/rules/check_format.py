#!/usr/bin/env python3
"""The tree is formatted as .clang-format says (docs/style.md), checked with tools/format.sh.

    check_format.py SOURCE_ROOT

1. clang-format 14 must be there: without it the check fails (it never skips), saying to
   run tools/deps.sh.
2. A self-test first, on scratch files outside the tree, so that a check that finds nothing
   cannot pass by accident: a badly formatted file fails `format.sh --check` and is named
   with a diff hunk; a file written in the house style passes (it pins the style's main
   choices: braces, indent, `T *p`, `{ .key = v }`, case labels, aligned trailing
   comments); `--fix` makes the bad file pass, and a second `--fix` changes nothing. The
   tree's list must hold the host, SDK, plugin and test sources and none of what
   .clang-format-ignore leaves out.
3. `format.sh --check` over the tree: every file it names is printed with its first hunk;
   the exit status is 1 when any is.
"""
import fnmatch
import os
import shutil
import subprocess
import sys
import tempfile

# Not formatted in at least a dozen ways: indent 2, braces, spaces, `char* p`, `{.x=1}`, a
# case label indented, a short if on one line, trailing comments not aligned.
BAD = """\
#include <stdio.h>
struct point { int x; int y; };
static int  sum( const int* v,int n ){
  int s=0;
  for(int i=0;i<n;i++) { s+=v[i]; }
  return s;}
int pick(int k) {
    switch (k) {
        case 0: return 1;
        default:
            if (k > 9) k = 9;
            break;
    }
    if (k) return 2;
    struct point p = {.x=1, .y=2}; /* a point */
    int q = 3;  /* not aligned */
    return p.x+p.y+q;
}
"""

# The same program as the house style writes it (what --fix must produce, and what --check
# must accept).
GOOD = """\
#include <stdio.h>
struct point {
    int x;
    int y;
};
static int sum(const int *v, int n)
{
    int s = 0;
    for (int i = 0; i < n; i++) {
        s += v[i];
    }
    return s;
}
int pick(int k)
{
    switch (k) {
    case 0: return 1;
    default:
        if (k > 9)
            k = 9;
        break;
    }
    if (k)
        return 2;
    struct point p = { .x = 1, .y = 2 }; /* a point */
    int q = 3;                           /* not aligned */
    return p.x + p.y + q;
}
"""


def run(root, *args):
    p = subprocess.run(['sh', os.path.join(root, 'tools', 'format.sh')] + list(args),
                       capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def find_clang_format():
    want = os.environ.get('CLANG_FORMAT')
    for name in ([want] if want else ['clang-format-14', 'clang-format']):
        path = shutil.which(name)
        if path:
            return path
    return None


def self_test(root):
    problems = []
    with tempfile.TemporaryDirectory(prefix='lg-check-format.') as tmp:
        bad = os.path.join(tmp, 'bad.c')
        good = os.path.join(tmp, 'good.c')
        with open(bad, 'w') as f:
            f.write(BAD)
        with open(good, 'w') as f:
            f.write(GOOD)

        rc, out, err = run(root, '--check', bad)
        if rc != 1:
            problems.append(f'--check of a badly formatted file exited {rc}, not 1:\n{out}{err}')
        elif 'not formatted: ' + bad not in out or '@@' not in out:
            problems.append(f'--check did not name the bad file with a diff hunk:\n{out}{err}')

        rc, out, err = run(root, '--check', good)
        if rc != 0:
            problems.append('--check of a file in the house style exited %d, not 0 '
                            '(.clang-format no longer formats as the tree is written):\n%s%s'
                            % (rc, out, err))

        rc, out, err = run(root, '--fix', bad)
        if rc != 0 or 'formatted: ' + bad not in out:
            problems.append(f'--fix of the bad file exited {rc} or did not name it:\n{out}{err}')
        with open(bad) as f:
            fixed = f.read()
        if fixed != GOOD:
            problems.append('--fix of the bad file did not give the house style:\n' + fixed)
        rc, out, err = run(root, '--check', bad)
        if rc != 0:
            problems.append(f'--check after --fix exited {rc}, not 0:\n{out}{err}')
        rc, out, err = run(root, '--fix', bad)
        with open(bad) as f:
            again = f.read()
        if rc != 0 or again != fixed or out.strip():
            problems.append(f'a second --fix changed something (exit {rc}):\n{out}{err}')

    rc, out, err = run(root, '--list')
    listed = out.split()
    if rc != 0:
        problems.append(f'--list exited {rc}:\n{err}')
    for must in ('host/main.c', 'sdk/src/image.c', 'plugins/core/core.c',
                 'tests/unit/parser/test_parser.c', 'sdk/include/lightgraph/plugin.h'):
        if must not in listed:
            problems.append(f'--list does not name {must}: the check would not look at it')
    patterns = []
    with open(os.path.join(root, '.clang-format-ignore')) as f:
        for line in f:
            line = line.split('#', 1)[0].strip()
            if line:
                patterns.append(line)
    if not patterns:
        problems.append('.clang-format-ignore lists nothing')
    for path in listed:
        for pat in patterns:
            if fnmatch.fnmatch(path, pat):
                problems.append(f'--list names {path}, which .clang-format-ignore leaves out ({pat})')
    return problems, len(listed)


def main():
    if len(sys.argv) != 2:
        print('usage: check_format.py SOURCE_ROOT', file=sys.stderr)
        return 2
    root = os.path.abspath(sys.argv[1])
    cf = find_clang_format()
    if not cf:
        print('check_format: clang-format (14) not found: run `sh tools/deps.sh` (as root it '
              'installs Debian\'s clang-format; otherwise it prints the apt-get line)',
              file=sys.stderr)
        return 1

    problems, n = self_test(root)
    if problems:
        print('check_format: the self-test failed, so the check cannot be trusted:',
              file=sys.stderr)
        for p in problems:
            print('  ' + p.replace('\n', '\n    '), file=sys.stderr)
        return 1
    print(f'check_format: self-test passed ({cf}); checking {n} files')
    sys.stdout.flush()

    rc, out, err = run(root, '--check')
    sys.stdout.write(out)
    sys.stderr.write(err)
    if rc == 1:
        print('check_format: files above are not formatted: `sh tools/format.sh --fix` '
              '(or `make format`) formats them', file=sys.stderr)
    return 1 if rc else 0


if __name__ == '__main__':
    sys.exit(main())
