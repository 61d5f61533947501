"""tests/unit/host/lgrun.py: what the scripts beside it (test_*.py) share to run lightgraph.

    EXE                      the program under test (LG_EXE, set by tests/meson.build)
    Fail, check(cond, msg)   a failed check: raise Fail(msg) unless cond
    temp_dir(prefix)         a fresh temporary folder (the script removes it in main())
    env(plugin_path, cache)  the environment of one run: this process's, with
                             LIGHTGRAPH_PLUGIN_PATH and LIGHTGRAPH_CACHE_DIR set, the
                             variables named in `drop` removed, then `extra` added
    run(args, env, expect)   runs EXE with args, output captured as text; with `expect`,
                             another exit status raises Fail naming the command, the status
                             and both outputs (their last `tail` characters if given)
    write(path, text)        writes a file, returns its path
    fresh_dir(parent, name)  makes parent/name (which must not exist), returns it
    tests_of(namespace)      {name: fn} of the functions test_<name> in a script's globals
    main(tests, tmp)         runs the test named by the one argument: exit 0 ("ok"),
                             1 (a Fail, printed) or 2 (no such test); removes tmp (but
                             after a Fail with keep_on_fail)

Each script keeps its own small run() wrapper for its defaults (plugin folders, cache,
timeout), built on env() and run() here.
"""
import os
import shutil
import subprocess
import sys
import tempfile

EXE = os.environ["LG_EXE"]


class Fail(Exception):
    pass


def check(cond, msg):
    if not cond:
        raise Fail(msg)


def temp_dir(prefix):
    return tempfile.mkdtemp(prefix=prefix)


def env(plugin_path, cache, extra=None, drop=()):
    e = dict(os.environ)
    e["LIGHTGRAPH_PLUGIN_PATH"] = plugin_path
    e["LIGHTGRAPH_CACHE_DIR"] = cache
    for name in drop:
        e.pop(name, None)
    e.update(extra or {})
    return e


def run(args, env, expect=None, timeout=120, tail=None, **popen):
    p = subprocess.run([EXE] + args, env=env, capture_output=True, text=True, timeout=timeout,
                       **popen)
    if expect is not None and p.returncode != expect:
        out, err = (p.stdout, p.stderr) if tail is None else (p.stdout[-tail:], p.stderr[-tail:])
        raise Fail("%s: exit %d, expected %d\nstdout:\n%s\nstderr:\n%s" %
                   (" ".join(args), p.returncode, expect, out, err))
    return p


def write(path, text, mode="w"):
    with open(path, mode) as f:
        f.write(text)
    return path


def fresh_dir(parent, name):
    d = os.path.join(parent, name)
    os.makedirs(d)
    return d


def tests_of(namespace):
    return {name[5:]: fn for name, fn in namespace.items() if name.startswith("test_")}


def main(tests, tmp=None, keep_on_fail=False):
    """The script's entry: sys.exit(lgrun.main(TESTS, TMP)). keep_on_fail: a failed test
    leaves tmp in place and says where (for the scripts whose scratch tells why)."""
    name = sys.argv[1] if len(sys.argv) == 2 else ""
    if name not in tests:
        print("usage: %s {%s}" % (os.path.basename(sys.argv[0]), "|".join(tests)),
              file=sys.stderr)
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)
        return 2
    failed = True
    try:
        tests[name]()
        failed = False
    except Fail as e:
        print("FAIL %s: %s" % (name, e))
        if keep_on_fail and tmp:
            print("(scratch kept: %s)" % tmp)
        return 1
    finally:
        if tmp and not (failed and keep_on_fail):
            shutil.rmtree(tmp, ignore_errors=True)
    print("ok", name)
    return 0
