#!/usr/bin/env python3
"""No raw OpenCL kernel plumbing or buffer management in plugins (ABI 3.0, docs/sdk.md "CL
passes and buffers"): a kernel runs through lg_cl_pass, scratch memory is an lg_cl_buffer.
Scans the C and C++ sources under each folder given (plugins/ and sdk/template/) for

    clCreateKernel clSetKernelArg clEnqueueNDRangeKernel clCreateBuffer clReleaseMemObject
    lg_cl_source_join

outside comments and string literals (a message may name them) and prints each hit as
FILE:LINE: NAME: the line. Exit 1 with hits, 0 without.

Before scanning, it checks itself on a planted file (the names in code are found with
their lines, the same names in comments and strings are not), so that a scanner that
stopped finding anything fails rather than passes.

usage: check_no_raw_cl.py FOLDER...
"""
import os
import re
import sys
import tempfile

NAMES = ["clCreateKernel", "clSetKernelArg", "clEnqueueNDRangeKernel", "clCreateBuffer",
         "clReleaseMemObject", "lg_cl_source_join"]
WORD = re.compile(r'\b(' + "|".join(NAMES) + r')\b')
# comments and literals in one pass, so that a "//" inside a string or a quote inside a
# comment is read as what it is; newlines kept so that line numbers stay
TOKENS = re.compile(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
EXTS = (".c", ".h", ".cpp", ".cc", ".hpp")
HINT = {
    "clCreateKernel": "lg_cl_pass_create",
    "clSetKernelArg": "lg_cl_pass_arg_*",
    "clEnqueueNDRangeKernel": "lg_cl_pass_run",
    "clCreateBuffer": "lg_cl_buffer_recreate",
    "clReleaseMemObject": "lg_cl_buffer_destroy",
    "lg_cl_source_join": "lg_cl_pass_desc.sources",
}


def blank(m):
    """A comment or literal with everything but newlines blanked."""
    return re.sub(r'[^\n]', ' ', m.group(0))


def scan_text(path, text):
    code = TOKENS.sub(blank, text)
    src = text.splitlines()
    hits = []
    for no, line in enumerate(code.splitlines(), 1):
        for m in WORD.finditer(line):
            hits.append((path, no, m.group(1), src[no - 1].strip()))
    return hits


def scan(folder):
    hits = []
    for d, dirs, files in os.walk(folder):
        dirs.sort()
        for f in sorted(files):
            if f.endswith(EXTS):
                path = os.path.join(d, f)
                with open(path, encoding="utf-8", errors="replace") as fh:
                    hits += scan_text(path, fh.read())
    return hits


PLANTED = '''/* clCreateKernel in a comment is fine, over
 * more than one line: clSetKernelArg */
static int f(void)
{
    const char *msg = "clSetKernelArg(x) failed; // clCreateBuffer";   // clReleaseMemObject
    cl_kernel k = clCreateKernel(prog, "k", &e);
    e |= clSetKernelArg(k, 0,
                        sizeof m, &m); char c = '"'; clEnqueueNDRangeKernel(q, k, 1,
        NULL, g, NULL, 0, NULL, NULL);
    m = clCreateBuffer(ctx, 0, 4, NULL, &e); /* clCreateBuffer */ clReleaseMemObject(m);
    char *s = lg_cl_source_join(parts, 2);
    int not_a_call = my_clCreateKernel + clCreateKernelX;
    return 0;
}
'''
PLANTED_HITS = [(6, "clCreateKernel"), (7, "clSetKernelArg"), (8, "clEnqueueNDRangeKernel"),
                (10, "clCreateBuffer"), (10, "clReleaseMemObject"), (11, "lg_cl_source_join")]


def self_check():
    with tempfile.TemporaryDirectory(prefix="rules_cl.") as tmp:
        os.makedirs(os.path.join(tmp, "plugin"))
        with open(os.path.join(tmp, "plugin", "planted.c"), "w") as fh:
            fh.write(PLANTED)
        with open(os.path.join(tmp, "plugin", "notes.txt"), "w") as fh:
            fh.write("clCreateKernel(not a source file)\n")
        got = [(no, name) for _, no, name, _ in scan(tmp)]
    if got != PLANTED_HITS:
        print("FAIL: the scanner's self-check: found %s in the planted file, expected %s"
              % (got, PLANTED_HITS))
        return False
    return True


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip().splitlines()[-1])
        return 2
    if not self_check():
        return 1
    hits = []
    for folder in sys.argv[1:]:
        if not os.path.isdir(folder):
            print("FAIL: %s: no such folder" % folder)
            return 1
        hits += scan(folder)
    for path, no, name, line in hits:
        print("%s:%d: %s (use %s): %s" % (path, no, name, HINT[name], line))
    if hits:
        print("FAIL: %d raw OpenCL call(s) in plugin sources: kernels run through lg_cl_pass, "
              "scratch memory is an lg_cl_buffer (lightgraph/cl.h)" % len(hits))
        return 1
    print("ok: no raw OpenCL kernel or buffer calls in %s" % ", ".join(sys.argv[1:]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
