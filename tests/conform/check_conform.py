#!/usr/bin/env python3
"""Runs `lightgraph conform --quick --json PLUGIN` and checks the verdict.

usage: check_conform.py LIGHTGRAPH PLUGIN.so EXPECT [KNOWN...]
  EXPECT 'pass': exit status 0 and no failed result, but for the KNOWN ones (NODE:CHECK,
                 a contract an in-tree plugin is known to break, listed in meson.build with
                 the reason); each KNOWN one must still fail (strict: once fixed, the test
                 says to take it off the list);
  EXPECT CHECK:  exit status 1, and a failed result of that check that names the node type
                 (or the plugin, for a refused descriptor) and says why in a message.
The text report (without --json) must name the same check, so both forms are checked.
"""
import json
import subprocess
import sys


def main():
    exe, plugin, expect = sys.argv[1:4]
    known = set(tuple(k.split(':', 1)) for k in sys.argv[4:])
    run = subprocess.run([exe, 'conform', '--quick', '--json', plugin], capture_output=True,
                         text=True, timeout=560)
    sys.stderr.write(run.stderr)
    try:
        rep = json.loads(run.stdout)
    except json.JSONDecodeError as e:
        print(f'FAIL: the --json report does not parse ({e}):\n{run.stdout[:2000]}')
        return 1
    fails = [r for r in rep['results'] if r['status'] == 'fail']
    for r in rep['results']:
        if r['status'] != 'pass':
            print(f"{r['status']:4} {r['node'] or 'plugin'} {r['check']}: {r['message']}")
    if rep['conforms'] != (not fails) or (run.returncode == 0) != (not fails):
        print(f'FAIL: exit status {run.returncode}, conforms {rep["conforms"]}, '
              f'{len(fails)} failed results disagree')
        return 1
    if expect == 'pass':
        unexpected = [r for r in fails if (r['node'] or '', r['check']) not in known]
        fixed = [k for k in known
                 if not any((r['node'] or '', r['check']) == k for r in fails)]
        if unexpected:
            print(f'FAIL: {plugin} should conform; exit status {run.returncode}, failed: '
                  f'{sorted(set((r["node"], r["check"]) for r in unexpected))}')
            return 1
        if fixed:
            print(f'FAIL: known failures no longer fail (take them off the list in '
                  f'tests/conform/meson.build): {sorted(fixed)}')
            return 1
        if known:
            print(f'ok: {plugin} conforms but for the known failures {sorted(known)}')
            return 0
        print(f'ok: {plugin} conforms ({rep["passed"]} passed, {rep["skipped"]} skipped, '
              f'{rep["notes"]} notes)')
        return 0
    if run.returncode != 1:
        print(f'FAIL: {plugin} breaks {expect}; expected exit status 1, got {run.returncode}')
        return 1
    hits = [r for r in fails if r['check'] == expect and r['message']]
    if not hits:
        print(f'FAIL: no failed result of check {expect!r}; failed: '
              f'{sorted(set(r["check"] for r in fails))}')
        return 1
    text = subprocess.run([exe, 'conform', '--quick', plugin], capture_output=True, text=True,
                          timeout=560)
    line = f" {expect}: "
    if text.returncode != 1 or not any(l.startswith('FAIL') and line in l
                                       for l in text.stderr.splitlines()):
        print(f'FAIL: the text report (exit {text.returncode}) has no FAIL line of {expect}:\n'
              f'{text.stderr[-2000:]}')
        return 1
    print(f'ok: {plugin} fails {expect}: {hits[0]["message"]}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
