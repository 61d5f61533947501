#!/bin/sh
# abi_check.sh can fail: the base variant of a small library (fixture/abifx.c) against a
# variant with a function removed, one with a function added, one with a public struct
# changed, at stored and current versions that allow or forbid each. The test
# abi_check_catches.
#
#   abi_selftest.sh FIXTURE_HEADERS BASE REMOVED ADDED CHANGED
set -eu
hdr=$1 base=$2 removed=$3 added=$4 changed=$5
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
sh "$root/tools/abi_dump.sh" --print "$base" "$hdr" >"$TMP/base.abi"
: >"$TMP/none.suppr"
failures=0
# expect pass|fail STORED_VERSION LIB CURRENT_VERSION [WORDS the message must hold]
expect() {
  want=$1 sv=$2 lib=$3 cv=$4 words=${5:-}
  echo "$sv" >"$TMP/VERSION"
  set +e
  sh "$here/abi_check.sh" "$TMP/base.abi" "$TMP/VERSION" "$lib" "$cv" "$TMP/none.suppr" "$hdr" >"$TMP/out.txt" 2>&1
  rc=$?
  set -e
  name="$(basename "$lib") stored $sv, built $cv"
  if [ "$want" = pass ] && [ $rc -ne 0 ]; then
    cat "$TMP/out.txt"; echo "FAIL: $name: expected a pass, exit $rc"; failures=$((failures + 1)); return
  fi
  if [ "$want" = fail ] && [ $rc -ne 1 ]; then
    cat "$TMP/out.txt"; echo "FAIL: $name: expected a failure (exit 1), exit $rc"; failures=$((failures + 1)); return
  fi
  if [ -n "$words" ] && ! grep -q "$words" "$TMP/out.txt"; then
    cat "$TMP/out.txt"; echo "FAIL: $name: the message does not say '$words'"; failures=$((failures + 1)); return
  fi
  echo "ok: $name: $want"
}
expect pass 1.0 "$base" 1.0 "matches the stored dump"
expect fail 1.1 "$base" 1.0 "went back"
expect fail 1.0 "$removed" 1.0 "needs a major version"
expect fail 1.0 "$removed" 1.1 "needs a major version"
expect pass 1.0 "$removed" 2.0 "allowed by the bump"
expect fail 1.0 "$added" 1.0 "without a minor bump"
expect pass 1.0 "$added" 1.1 "allowed by the bump"
expect fail 1.0 "$added" 1.0 "tools/abi_dump.sh BUILD"
if readelf -S "$changed" | grep -q '\.debug_info'; then
  expect fail 1.0 "$changed" 1.1 "needs a major version"
  expect pass 1.0 "$changed" 2.0 "allowed by the bump"
else
  echo "note: no debug info in this build: the changed-struct case needs types, not run"
fi
[ $failures -eq 0 ] || { echo "$failures case(s) failed"; exit 1; }
echo "ok: abi_check.sh passes and fails as docs/sdk.md \"ABI\" says"
