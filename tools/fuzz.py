#!/usr/bin/env python3
"""Runs every libFuzzer target of a -Dfuzzing=true build for a time (`make fuzz`).

    python3 tools/fuzz.py --build build-fuzz --seconds 60 [TARGET...]

Each target (tests/fuzz/meson.build: graph, image, gltf, cache, registry, probe,
cache_kinds, script, sweep, tune) runs for the given
seconds with its seed corpus tests/fuzz/corpus_NAME read-only and a work corpus in the
build tree (BUILD/tests/fuzz/corpus_NAME_work) that receives the new inputs, with memory
bounded: an input that makes the process's RSS pass RSS_LIMIT_MB, or asks for one block
over MALLOC_LIMIT_MB, is a finding like a crash, a leak, a sanitizer report or an input
that takes over TIMEOUT seconds. A finding is copied into the seed corpus as
finding-SHA1 (the SHA-1 of its bytes, as libFuzzer names it), where the suite's plain
drivers replay it on every run, and this script exits 1 naming every finding and the log
that shows it. docs/fuzzing.md has the limits and why.
"""
import argparse
import hashlib
import os
import shutil
import subprocess
import sys

TARGETS = ["graph", "image", "gltf", "cache", "registry", "probe", "cache_kinds", "script",
           "sweep", "tune"]

# Largest input per target: the graph parser's files are text, and 4 KiB reaches every
# construct (so do a script and a sweep command line in 8 and 4 KiB); the binary formats
# need room for headers plus some data (a probe is an image; the largest cache payload
# seed, a GGX chain, is 2 KiB).
MAX_LEN = {"graph": 4096, "image": 65536, "gltf": 65536, "cache": 4096, "registry": 65536,
           "probe": 65536, "cache_kinds": 8192, "script": 8192, "sweep": 4096,
           "tune": 4096}

# 2048 MiB: libFuzzer's own default, and more than any input of at most 64 KiB should need
# (the largest legitimate case, an image at the fuzz targets' pixel limit of 2^22 pixels,
# is 64 MiB of RGBA floats); well under what the machines running this have, so that a
# blow-up is reported, not swapped.
RSS_LIMIT_MB = 2048
# 1024 MiB in one malloc: an amplification of 16384 times the largest input; the loaders
# check declared sizes before allocating, so a block this large from a small input is a
# missing check (the sizes bug class of issue 8).
MALLOC_LIMIT_MB = 1024
# seconds for one input: the slowest seeds take well under a second in the ASan build
TIMEOUT = 20

# (libFuzzer also writes slow-unit- files, for inputs over 10 s that passed: not findings)
ARTIFACT_PREFIXES = ("crash-", "leak-", "oom-", "timeout-")


def run_target(name, build, src, seconds):
    exe = os.path.join(build, "tests", "fuzz", "fuzz_" + name)
    corpus = os.path.join(src, "tests", "fuzz", "corpus_" + name)
    work = os.path.join(build, "tests", "fuzz", "corpus_" + name + "_work")
    findings = os.path.join(build, "fuzz-findings", name)
    log_path = os.path.join(build, "fuzz-findings", name + ".log")
    if not os.access(exe, os.X_OK):
        print(f"fuzz: {exe} is missing (build it with -Dfuzzing=true)", file=sys.stderr)
        return None, [], log_path
    os.makedirs(work, exist_ok=True)
    shutil.rmtree(findings, ignore_errors=True)
    os.makedirs(findings)
    env = dict(os.environ)
    supp = os.path.join(src, "tests", "lsan.supp")
    env["ASAN_OPTIONS"] = ("detect_leaks=1:abort_on_error=0:allocator_may_return_null=0:"
                           "intercept_tls_get_addr=0")  # as tests/meson.build says why
    env["UBSAN_OPTIONS"] = "print_stacktrace=1:halt_on_error=1"
    env["LSAN_OPTIONS"] = f"suppressions={supp}:print_suppressions=0"
    env["LIGHTGRAPH_PLUGIN_PATH"] = ""
    cmd = [exe, work, corpus,
           f"-max_total_time={seconds}",
           f"-rss_limit_mb={RSS_LIMIT_MB}",
           f"-malloc_limit_mb={MALLOC_LIMIT_MB}",
           f"-timeout={TIMEOUT}",
           f"-max_len={MAX_LEN[name]}",
           f"-artifact_prefix={findings}/",
           "-print_final_stats=1"]
    print(f"fuzz: {name}: {seconds} s  ({' '.join(cmd)})", flush=True)
    with open(log_path, "wb") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, env=env,
                             cwd=findings)
    artifacts = sorted(f for f in os.listdir(findings) if f.startswith(ARTIFACT_PREFIXES))
    stats = {}
    with open(log_path, "rb") as log:
        for line in log.read().decode("utf-8", "replace").splitlines():
            if line.startswith("stat::"):
                k, _, v = line[6:].partition(":")
                stats[k.strip()] = v.strip()
    print(f"fuzz: {name}: exit {rc}, {stats.get('number_of_executed_units', '?')} runs, "
          f"peak RSS {stats.get('peak_rss_mb', '?')} MiB, "
          f"{len(os.listdir(work))} inputs in {work}", flush=True)
    return rc, artifacts, log_path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build-fuzz")
    ap.add_argument("--seconds", type=int, default=60)
    ap.add_argument("targets", nargs="*", default=TARGETS)
    a = ap.parse_args()
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if a.seconds < 1:
        ap.error("--seconds must be at least 1")
    for t in a.targets:
        if t not in TARGETS:
            ap.error(f"unknown target '{t}' (targets: {', '.join(TARGETS)})")
    failed = []
    for name in a.targets:
        rc, artifacts, log_path = run_target(name, os.path.abspath(a.build), src, a.seconds)
        if rc is None:
            failed.append(f"{name}: not built")
            continue
        corpus = os.path.join(src, "tests", "fuzz", "corpus_" + name)
        for art in artifacts:
            path = os.path.join(os.path.dirname(log_path), name, art)
            with open(path, "rb") as f:
                data = f.read()
            dest = os.path.join(corpus, "finding-" + hashlib.sha1(data).hexdigest())
            shutil.copyfile(path, dest)
            kind = art.split("-")[0]
            failed.append(f"{name}: {kind} finding {os.path.relpath(dest, src)} "
                          f"({len(data)} bytes; log {log_path})")
        if rc != 0 and not artifacts:
            failed.append(f"{name}: exit status {rc} without a finding (log {log_path})")
    if failed:
        print("fuzz: FINDINGS (copied into the seed corpora; the suite replays them):",
              file=sys.stderr)
        for f in failed:
            print("  " + f, file=sys.stderr)
        return 1
    print(f"fuzz: {len(a.targets)} targets, {a.seconds} s each: clean")
    return 0


if __name__ == "__main__":
    sys.exit(main())
