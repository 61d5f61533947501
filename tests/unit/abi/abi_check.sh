#!/bin/sh
# Compares a library with its stored ABI dump (docs/sdk.md "ABI"); the test abi_liblightgraph.
#
#   abi_check.sh STORED_ABI STORED_VERSION_FILE LIB CURRENT_VERSION SUPPRESSIONS HDR...
#
# The fresh dump is made by tools/abi_dump.sh --print (the stored one's options), then
# abidiff compares them. The rule (docs/sdk.md "ABI"):
#   - a function or variable removed, or changed (its type, or a type it reaches, e.g. a
#     public struct's fields): only with a major bump (CURRENT major > stored major);
#   - only additions: only with a minor (or major) bump (CURRENT > stored);
#   - nothing changed: passes at any version not older than the stored one.
# A library without debug info (a release build) is compared by its exported symbols only,
# and the test says so. Exit 0 pass, 1 fail (saying what changed and what to do), 99 the
# tools failed.
set -eu
[ $# -ge 6 ] || { echo "usage: abi_check.sh STORED_ABI STORED_VERSION_FILE LIB CURRENT_VERSION SUPPR HDR..." >&2; exit 99; }
stored=$1 version_file=$2 lib=$3 current=$4 suppr=$5
shift 5
here=$(cd "$(dirname "$0")/../../.." && pwd)
command -v abidiff >/dev/null || { echo "FAIL: abidiff not found: install abigail-tools (sh tools/deps.sh)"; exit 99; }
[ -f "$stored" ] || { echo "FAIL: no stored dump $stored: run tools/abi_dump.sh BUILD"; exit 1; }
stored_version=$(cat "$version_file")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# "3.0" -> major and minor, and a comparable number
smaj=${stored_version%%.*} smin=${stored_version#*.}
cmaj=${current%%.*} cmin=${current#*.}
case "$smaj.$smin.$cmaj.$cmin" in *[!0-9.]*|*..*|.*|*.) echo "FAIL: bad versions '$stored_version' / '$current'"; exit 99 ;; esac
sval=$((smaj * 100000 + smin)) cval=$((cmaj * 100000 + cmin))
regen="If the change is intended: give it the version docs/sdk.md \"ABI\" asks for (a new changelog entry, unless it belongs to the newest entry, a version not yet released, as 3.0 while its branches merge), rebuild, then run tools/abi_dump.sh BUILD (it rewrites sdk/abi/ from the build) and commit sdk/abi/."
if [ "$cval" -lt "$sval" ]; then
  echo "FAIL: the ABI version went back: $current is older than the stored dump's $stored_version"; exit 1
fi

# Symbols the comparison ignores, as the suppression file does for abidiff: C++ library
# code instantiated into liblightgraph (exr_cxx.cpp's std::string) and sanitizer symbols.
ignored='^(_ZN|_ZS|_ZT|__odr_asan|__asan|__ubsan|__sanitizer|__lsan)'
if readelf -S "$lib" | grep -q '\.debug_info'; then
  mode=types
  sh "$here/tools/abi_dump.sh" --print "$lib" "$@" >"$TMP/new.abi" 2>"$TMP/abidw.err" || {
    cat "$TMP/abidw.err"; echo "FAIL: abidw $lib"; exit 99; }
  set +e
  abidiff --suppressions "$suppr" --no-show-locs "$stored" "$TMP/new.abi" >"$TMP/report.txt" 2>&1
  rc=$?
  set -e
  if [ $((rc & 3)) -ne 0 ]; then
    cat "$TMP/report.txt"; echo "FAIL: abidiff failed (exit $rc)"; exit 99
  fi
  # "Functions changes summary: 1 Removed, 2 Changed (3 filtered out), 4 Added functions",
  # the same for variables, and for symbols without debug info
  count() {  # WHAT
    sed -n "s/.*summary: \(.*\)/\1/p" "$TMP/report.txt" | tr ',' '\n' |
      sed -n "s/^ *\([0-9][0-9]*\) $1.*/\1/p" | awk '{s += $1} END {print s + 0}'
  }
  removed=$(count Removed) changed=$(count Changed) added=$(count Added)
else
  mode=symbols
  sed -n "s/.*<elf-symbol name='\([^']*\)'.*/\1/p" "$stored" | grep -Ev "$ignored" | sort -u >"$TMP/old.syms"
  nm -D --defined-only "$lib" | awk '{print $3}' | grep -Ev "$ignored" | sort -u >"$TMP/new.syms"
  comm -23 "$TMP/old.syms" "$TMP/new.syms" >"$TMP/removed.syms"
  comm -13 "$TMP/old.syms" "$TMP/new.syms" >"$TMP/added.syms"
  removed=$(wc -l <"$TMP/removed.syms") changed=0 added=$(wc -l <"$TMP/added.syms")
  { echo "removed:"; cat "$TMP/removed.syms"; echo "added:"; cat "$TMP/added.syms"; } >"$TMP/report.txt"
  echo "note: $lib has no debug info: exported symbols compared, not types"
fi

what="$removed removed, $changed changed, $added added"
if [ $((removed + changed)) -gt 0 ]; then
  if [ "$cmaj" -le "$smaj" ]; then
    cat "$TMP/report.txt"
    echo "FAIL: ABI $current removes or changes what the stored dump of $stored_version has ($what, $mode): that needs a major version."
    echo "$regen"
    exit 1
  fi
elif [ "$added" -gt 0 ]; then
  if [ "$cval" -le "$sval" ]; then
    cat "$TMP/report.txt"
    echo "FAIL: ABI $current adds to the stored dump of $stored_version ($what, $mode) without a minor bump."
    echo "$regen"
    exit 1
  fi
fi
if [ $((removed + changed + added)) -gt 0 ] || [ "$cval" -ne "$sval" ]; then
  echo "ok: ABI $current against the stored dump of $stored_version: $what ($mode), allowed by the bump; run tools/abi_dump.sh BUILD to store it"
else
  echo "ok: ABI $current matches the stored dump ($mode)"
fi
