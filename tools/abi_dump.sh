#!/bin/sh
# The stored ABI of liblightgraph (docs/sdk.md "ABI"): a dump of its public interface by
# libabigail's abidw (Debian abigail-tools), compared with every build by the test
# abi_liblightgraph (tests/unit/abi/abi_check.sh).
#
#   tools/abi_dump.sh [BUILD]            rewrite sdk/abi/liblightgraph.abi and sdk/abi/VERSION
#                                        from BUILD (default: build), once an ABI change is
#                                        intended and the changelog says so
#   tools/abi_dump.sh --print LIB HDR... print the dump of LIB (headers in HDR folders)
#
# The options are here only, so that the stored dump and the test's fresh one are made the
# same way: only types declared in the SDK's public headers (--headers-dir with
# --drop-private-types: what the library uses inside does not count), no file paths or
# line numbers (a moved declaration is no ABI change), type ids by hash (a regenerated dump
# differs only where the ABI did). The dump needs DWARF: a build with debug info (the
# default buildtype, debugoptimized, has it).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)

dump() {  # LIB HDR...
  lib=$1; shift
  hd=""
  for d in "$@"; do hd="$hd --headers-dir $d"; done
  # shellcheck disable=SC2086 # $hd is a list of options
  abidw $hd --drop-private-types --no-corpus-path --no-comp-dir-path --no-show-locs \
    --type-id-style hash --no-elf-needed "$lib"
}

if [ "${1:-}" = "--print" ]; then
  shift
  dump "$@"
  exit 0
fi
[ $# -le 1 ] || { echo "usage: tools/abi_dump.sh [BUILD] | --print LIB HDR..." >&2; exit 2; }
build=${1:-build}
command -v abidw >/dev/null || { echo "abi_dump.sh: abidw not found: install abigail-tools (sh tools/deps.sh)" >&2; exit 1; }
lib=$(ls "$build"/sdk/liblightgraph.so.*.*.* 2>/dev/null | head -1)
[ -n "$lib" ] || { echo "abi_dump.sh: no $build/sdk/liblightgraph.so.*: build first (ninja -C $build)" >&2; exit 1; }
readelf -S "$lib" | grep -q '\.debug_info' || {
  echo "abi_dump.sh: $lib has no debug info: the dump needs it (a debug or debugoptimized build)" >&2; exit 1; }
config="$build/sdk/include/lightgraph/config.h"
major=$(sed -n 's/^#define LG_ABI_MAJOR \([0-9]*\)$/\1/p' "$config")
minor=$(sed -n 's/^#define LG_ABI_MINOR \([0-9]*\)$/\1/p' "$config")
[ -n "$major" ] && [ -n "$minor" ] || { echo "abi_dump.sh: no LG_ABI_MAJOR/MINOR in $config" >&2; exit 1; }
out="$here/sdk/abi"
dump "$lib" "$here/sdk/include/lightgraph" "$build/sdk/include/lightgraph" >"$out/liblightgraph.abi.tmp"
mv "$out/liblightgraph.abi.tmp" "$out/liblightgraph.abi"
echo "$major.$minor" >"$out/VERSION"
echo "abi_dump.sh: wrote sdk/abi/liblightgraph.abi and sdk/abi/VERSION ($major.$minor) from $lib"
