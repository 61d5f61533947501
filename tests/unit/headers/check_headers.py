#!/usr/bin/env python3
"""The SDK's headers as a plugin author gets them: installed (`meson install --destdir`),
found through the installed lightgraph.pc, and nothing else.

1. Names: no installed SDK header is named like a C standard, POSIX or other system header
   (its path under include/lightgraph/ is not a top-level header of the compiler's system
   include folders, nor in the list below). With the old `-I${includedir}/lightgraph`,
   lightgraph/math.h was <math.h> for every file of a plugin.
2. Includes: an SDK header includes its siblings as "lightgraph/x.h" (or <lightgraph/x.h>),
   never as "x.h": that only works through a -I the .pc does not give.
3. Each header compiles alone, as C11 and as C++17, warning-free (-Wall -Wextra -pedantic
   -Werror), with exactly the installed `pkg-config --cflags lightgraph`: a plugin author
   may include any one of them first.
4. A third-party plugin file that includes <lightgraph/lightgraph.h> and uses <math.h>
   (sqrtf, isfinite) compiles and links with `pkg-config --cflags --libs lightgraph`.

usage: check_headers.py CC CXX BUILD_DIR -- HEADER...   (HEADER: the SDK's public headers)
"""
import glob
import os
import re
import shlex
import subprocess
import sys
import tempfile

# C11 (7.1.2), C++ compatibility headers, and the POSIX / Linux headers a plugin commonly
# includes without a folder. The compiler's own folders are scanned as well (below).
SYSTEM_NAMES = set("""
assert.h complex.h ctype.h errno.h fenv.h float.h inttypes.h iso646.h limits.h locale.h
math.h setjmp.h signal.h stdalign.h stdarg.h stdatomic.h stdbool.h stddef.h stdint.h stdio.h
stdlib.h stdnoreturn.h string.h tgmath.h threads.h time.h uchar.h wchar.h wctype.h
aio.h arpa/inet.h cpio.h dirent.h dlfcn.h fcntl.h fnmatch.h glob.h grp.h iconv.h langinfo.h
libgen.h monetary.h mqueue.h netdb.h nl_types.h poll.h pthread.h pwd.h regex.h sched.h
search.h semaphore.h spawn.h strings.h syslog.h tar.h termios.h ulimit.h unistd.h utime.h
utmpx.h wordexp.h alloca.h malloc.h memory.h endian.h features.h getopt.h link.h elf.h
error.h execinfo.h
""".split())

failed = 0


def fail(msg):
    global failed
    failed += 1
    print("FAIL: " + msg)


def system_include_dirs(cc):
    """The folders `cc` searches for <...> by default (from `cc -E -v`)."""
    p = subprocess.run([cc, "-xc", "-E", "-v", "-"], input="", capture_output=True, text=True)
    dirs, on = [], False
    for line in p.stderr.splitlines():
        if line.startswith("#include <...> search starts here"):
            on = True
        elif line.startswith("End of search list"):
            break
        elif on:
            dirs.append(line.strip())
    return dirs


def main():
    sep = sys.argv.index("--")
    cc, cxx, build = sys.argv[1:sep]
    headers = [os.path.basename(h) for h in sys.argv[sep + 1:]]
    with tempfile.TemporaryDirectory() as tmp:
        root = os.path.join(tmp, "root")
        p = subprocess.run(["meson", "install", "-C", build, "--destdir", root, "--no-rebuild",
                            "--quiet"], capture_output=True, text=True)
        if p.returncode != 0:
            print(p.stdout + p.stderr)
            fail("meson install --destdir")
            return 1
        pcs = glob.glob(os.path.join(root, "**", "lightgraph.pc"), recursive=True)
        incs = glob.glob(os.path.join(root, "**", "include", "lightgraph"), recursive=True)
        if len(pcs) != 1 or len(incs) != 1:
            fail("expected one lightgraph.pc and one include/lightgraph, found %s and %s" % (pcs, incs))
            return 1
        inc = incs[0]
        env = dict(os.environ, PKG_CONFIG_PATH=os.path.dirname(pcs[0]),
                   PKG_CONFIG_SYSROOT_DIR=root)
        env.pop("PKG_CONFIG_LIBDIR", None)
        cflags = shlex.split(subprocess.run(["pkg-config", "--cflags", "lightgraph"], env=env,
                                            capture_output=True, text=True, check=True).stdout)
        libs = shlex.split(subprocess.run(["pkg-config", "--libs", "lightgraph"], env=env,
                                          capture_output=True, text=True, check=True).stdout)
        print("installed Cflags: %s" % " ".join(cflags))
        print("installed Libs:   %s" % " ".join(libs))

        # 1. names
        installed = sorted(os.path.relpath(f, inc) for f in
                           glob.glob(os.path.join(inc, "**", "*.h"), recursive=True))
        sysdirs = system_include_dirs(cc)
        for rel in installed:
            clash = [d for d in sysdirs if os.path.isfile(os.path.join(d, rel))]
            if rel in SYSTEM_NAMES or clash:
                fail("lightgraph/%s is named like the system header <%s>%s: rename it"
                     % (rel, rel, " (in %s)" % ", ".join(clash) if clash else ""))
            else:
                print("ok: lightgraph/%s is named like no system header" % rel)
        for h in headers:
            if h not in installed:
                fail("lightgraph/%s is a public header but is not installed" % h)

        # 2. sibling includes carry the lightgraph/ prefix
        siblings = set(installed) | {os.path.basename(r) for r in installed}
        for rel in installed:
            if rel.startswith("glad/"):
                continue  # generated by glad; tools/gen_glad.py rewrites its one include
            with open(os.path.join(inc, rel), errors="replace") as f:
                for no, line in enumerate(f, 1):
                    m = re.match(r'\s*#\s*include\s*[<"]([^>"]+)[>"]', line)
                    if m and m.group(1) in siblings:
                        fail('lightgraph/%s:%d includes "%s": write "lightgraph/%s"'
                             % (rel, no, m.group(1), m.group(1)))

        # 3. each header alone, with exactly the installed Cflags
        warn = ["-Wall", "-Wextra", "-Werror", "-fsyntax-only"]
        for h in headers:
            name = "lightgraph/" + h
            for lang, comp, std, ext in (("C11", cc, "-std=c11", "c"),
                                         ("C++17", cxx, "-std=c++17", "cpp")):
                src = os.path.join(tmp, "t." + ext)
                with open(src, "w") as f:
                    f.write('#include <%s>\n#include <%s>\nint lg_header_test_symbol;\n' % (name, name))
                extra = ["-pedantic"] if lang == "C11" else ["-Wno-pedantic"]
                p = subprocess.run([comp, std] + warn + extra + cflags + [src],
                                   capture_output=True, text=True)
                if p.returncode != 0:
                    fail("%s as %s with the installed Cflags:\n%s" % (name, lang, p.stderr))
                else:
                    print("ok: %s as %s" % (name, lang))

        # 4. a third-party plugin file using <math.h> next to the SDK
        src = os.path.join(tmp, "third_party.c")
        with open(src, "w") as f:
            f.write("#include <math.h>\n#include <lightgraph/lightgraph.h>\n\n"
                    "LG_EXPORT float third_party_norm(float x, float y);\n"
                    "LG_EXPORT float third_party_norm(float x, float y)\n"
                    "{\n    float r = sqrtf(x * x + y * y) + lg_v3_length(lg_v3(x, y, 0.0f));\n"
                    "    return isfinite(r) && (int)lg_image_format_from_path(\"a.exr\") >= 0 ? r : 0.0f;\n}\n")
        so = os.path.join(tmp, "third_party.so")
        p = subprocess.run([cc, "-std=c11", "-Wall", "-Wextra", "-Werror", "-fPIC", "-shared",
                            "-fvisibility=hidden", src, "-o", so] + cflags + libs + ["-lm"],
                           capture_output=True, text=True)
        if p.returncode != 0:
            fail("a plugin file with <math.h> (sqrtf, isfinite) and <lightgraph/lightgraph.h> "
                 "does not build with the installed pkg-config flags:\n" + p.stderr)
        else:
            print("ok: a plugin file using sqrtf and isfinite builds with the installed flags")
    return 1 if failed else 0


if __name__ == "__main__":
    rc = main()
    if failed:
        print("%d check(s) failed" % failed)
    sys.exit(rc)
