#!/usr/bin/env python3
"""Compiles every C snippet of a Markdown guide (docs/plugin-guide.md) against the SDK's
headers, so that a snippet that stops compiling fails the suite.

Fenced blocks:
  ```c                  a whole translation unit, compiled alone
  ```c file=NAME        appended (in the page's order) to file NAME; several blocks make one
  ```glsl file=NAME     file. NAME ending in .c is compiled; any other file (a shader, a
                        kernel) is embedded with embed.py into NAME's basename + .h, which the
                        C files may include. GLSL files without #include are also compiled by
                        glslangValidator when it is installed.
  ```meson from=PATH    an excerpt of the file PATH (relative to --root): every non-blank
                        line of the block, stripped, must be a line of that file, so that an
                        excerpt of the template's meson.build cannot drift from it.
Other languages (sh, meson, text...) and plain ``` blocks are prose, not checked. Each C
chunk starts with a #line directive naming the page and line, so the compiler's messages
point into the guide. A C file that defines a plugin (LG_PLUGIN_DEFINE) is also linked as a
shared module against liblightgraph with --no-undefined, and must export lg_plugin_entry
alone.

  check_guide_snippets.py --cc CC --embed EMBED.PY -I DIR... -L LIBDIR [--min N] GUIDE.md
  check_guide_snippets.py ... --expect-fail FILE:LINE GUIDE.md
        (the self-test: passes only when compiling fails with a message at FILE:LINE)
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

FENCE = re.compile(r'^```\s*([A-Za-z0-9_+-]*)\s*(.*?)\s*$')


def parse(path):
    """Returns [(lang, attrs, first_line, text)] of the fenced blocks of `path`."""
    blocks, cur = [], None
    with open(path, encoding='utf-8') as f:
        for no, line in enumerate(f, 1):
            m = FENCE.match(line)
            if cur is None and m:
                attrs = {}
                for word in m.group(2).split():
                    if '=' not in word:
                        sys.exit(f'{path}:{no}: unknown fence attribute {word!r} '
                                 '(file=NAME or from=PATH)')
                    k, v = word.split('=', 1)
                    if k not in ('file', 'from'):
                        sys.exit(f'{path}:{no}: unknown fence attribute {k!r} '
                                 '(file=NAME or from=PATH)')
                    attrs[k] = v
                cur = (m.group(1), attrs, no + 1, [])
            elif cur is not None and line.startswith('```'):
                blocks.append((cur[0], cur[1], cur[2], ''.join(cur[3])))
                cur = None
            elif cur is not None:
                cur[3].append(line)
    if cur is not None:
        sys.exit(f'{path}:{cur[2] - 1}: fenced block not closed')
    return blocks


def run(cmd, cwd):
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return p.returncode, p.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--cc', required=True)
    ap.add_argument('--embed', required=True)
    ap.add_argument('-I', dest='includes', action='append', default=[])
    ap.add_argument('-L', dest='libdir', required=True)
    ap.add_argument('--root', default=None, help='where from=PATH excerpts are read')
    ap.add_argument('--min', type=int, default=1, help='fewest C snippets the page must have')
    ap.add_argument('--expect-fail', default=None)
    ap.add_argument('guide')
    a = ap.parse_args()

    guide = os.path.abspath(a.guide)
    a.embed = os.path.abspath(a.embed)
    a.libdir = os.path.abspath(a.libdir)
    a.includes = [os.path.abspath(d) for d in a.includes]
    files, units, n_snippets = {}, [], 0
    failures = []
    for lang, attrs, line, text in parse(guide):
        if 'from' in attrs:  # an excerpt: every line must be in the file
            src = os.path.join(a.root or '.', attrs['from'])
            try:
                with open(src, encoding='utf-8') as f:
                    have = {l.strip() for l in f}
            except OSError as e:
                failures.append(f'{guide}:{line - 1}: excerpt of {attrs["from"]}: {e}')
                continue
            for k, l in enumerate(text.splitlines()):
                if l.strip() and l.strip() not in have:
                    failures.append(f'{guide}:{line + k}: this line of the excerpt is not in '
                                    f'{attrs["from"]}: {l.strip()}')
            continue
        name = attrs.get('file')
        if lang != 'c' and name is None:
            continue  # prose: a shell session, a meson excerpt, a graph file
        c_like = (name or '.c').endswith('.c')
        chunk = (f'#line {line} "{guide}"\n' if c_like else '') + text
        if lang == 'c' and c_like:
            n_snippets += 1
        if name is None:
            name = f'snippet_{line}.c'
            units.append(name)
        files.setdefault(name, []).append(chunk)

    tmp = tempfile.mkdtemp(prefix='guide-snippets-')
    try:
        gen = os.path.join(tmp, 'gen')
        os.makedirs(gen)
        for name, chunks in files.items():
            path = os.path.join(tmp, name)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, 'w', encoding='utf-8') as f:
                f.write(''.join(chunks))
        # shaders and kernels first: the C files include what embed.py makes of them
        glslang = shutil.which('glslangValidator')
        for name in files:
            if name.endswith('.c'):
                continue
            path = os.path.join(tmp, name)
            rc, out = run([sys.executable, a.embed, path,
                           os.path.join(gen, os.path.basename(name) + '.h')], tmp)
            if rc:
                failures.append(f'{name}: embed.py failed:\n{out}')
            if glslang and name.endswith(('.comp', '.vert', '.frag', '.geom')) and \
                    '#include' not in ''.join(files[name]):
                rc, out = run([glslang, path], tmp)
                if rc:
                    failures.append(f'{name}: glslangValidator:\n{out}')
        cflags = ['-std=c11', '-Wall', '-Wextra', '-Werror', '-Wno-unused-function',
                  '-fPIC', '-fvisibility=hidden', '-I', gen] + \
                 [x for d in a.includes for x in ('-I', d)]
        for name in files:
            if not name.endswith('.c'):
                continue
            src = os.path.join(tmp, name)
            obj = src[:-2] + '.o'
            rc, out = run([a.cc] + cflags + ['-c', src, '-o', obj], tmp)
            if rc:
                failures.append(f'{name} does not compile:\n{out}')
                continue
            if 'LG_PLUGIN_DEFINE' in ''.join(files[name]):
                so = src[:-2] + '.so'
                rc, out = run([a.cc, '-shared', '-o', so, obj, '-L', a.libdir, '-llightgraph',
                               '-lm', '-Wl,--no-undefined'], tmp)
                if rc:
                    failures.append(f'{name} does not link as a plugin:\n{out}')
                    continue
                rc, out = run(['nm', '-D', '--defined-only', so], tmp)
                syms = sorted(l.split()[-1] for l in out.splitlines()
                              if l.split() and l.split()[-2] in ('T', 'D', 'B', 'R', 'i'))
                if syms != ['lg_plugin_entry']:
                    failures.append(f'{name}: the plugin exports {syms}, not lg_plugin_entry '
                                    'alone')
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    if a.expect_fail:
        text = '\n'.join(failures)
        if a.expect_fail in text:
            print(f'ok: a broken snippet fails, at {a.expect_fail}')
            return 0
        print(f'FAIL: expected a failure at {a.expect_fail}; got:\n{text or "none"}')
        return 1
    if n_snippets < a.min:
        print(f'FAIL: {a.guide}: {n_snippets} C snippets, expected at least {a.min}')
        return 1
    for f in failures:
        print(f'FAIL: {f}')
    if failures:
        return 1
    print(f'ok: {n_snippets} C snippets of {a.guide} in {len(files)} files compiled '
          f'({sum(1 for n in files if not n.endswith(".c"))} shaders and kernels embedded)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
